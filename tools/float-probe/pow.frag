#version 300 es
// float-probe shader: mediump pow, exp2, log2 and mix of texels (FLOAT_PROBE_TEXTURE=upload), 64 rows;
// run with W=10 H=64; see README.md ("mediump builtins").
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
    if (x == 0) value = pow(a, 30.0);
    else if (x == 1) value = pow(a, b * 4.0);
    else if (x == 2) value = exp2(a * 3.0);
    else if (x == 3) value = log2(a);
    else if (x == 4) value = exp2(b * 7.0 - 3.0);
    else if (x == 5) value = log2(b * 100.0);
    else if (x == 6) value = mix(a, b, 0.3);
    else if (x == 7) value = mix(a, b, 1.0 - a);
    else if (x == 8) value = max(dot(vec3(a, b, 0.3), vec3(0.2, a, b)), 0.0);
    else if (x == 9) value = 1.0 - min(a / b, 1.0);
    else value = 0.0;
    highp uint bits = floatBitsToUint(value);
    color = vec4(float(bits >> 24), float((bits >> 16) & 255u), float((bits >> 8) & 255u), float(bits & 255u)) / 255.0;
}
