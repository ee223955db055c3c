#version 300 es
// float-probe shader: single mediump operations and builtins on texels (FLOAT_PROBE_TEXTURE=upload),
// 64 rows; run with W=16 H=64; see README.md ("mediump builtins").
precision mediump float;
precision highp int;
uniform sampler2D t;
out highp vec4 color;
void main() {
    highp vec2 q = floor(gl_FragCoord.xy);
    int x = int(q.x);
    int r = int(q.y);
    float a = texture(t, (vec2(float(r % 8), float(r / 8)) + 0.5) / 8.0).x;
    float b = texture(t, (vec2(float((r + 3) % 8), float((r / 8 + 5) % 8)) + 0.5) / 8.0).y;
    highp float value;
    if (x == 0) value = a + b;
    else if (x == 1) value = a * b;
    else if (x == 2) value = a - b;
    else if (x == 3) value = a / b;
    else if (x == 4) value = sqrt(a);
    else if (x == 5) value = inversesqrt(a);
    else if (x == 6) value = dot(vec2(a, b), vec2(a, b));
    else if (x == 7) value = dot(vec3(a, b, a), vec3(b, a, b));
    else if (x == 8) value = a * b + a;
    else if (x == 9) value = exp2(a);
    else if (x == 10) value = 1.0 / a;
    else if (x == 11) value = length(vec2(a, b));
    else if (x == 12) value = normalize(vec2(a, b)).x;
    else if (x == 13) value = a * a + b * b;
    else if (x == 14) value = a * 0.7;
    else value = (a + b) * 0.3;
    highp uint bits = floatBitsToUint(value);
    color = vec4(float(bits >> 24), float((bits >> 16) & 255u), float((bits >> 8) & 255u), float(bits & 255u)) / 255.0;
}
