#version 300 es
// float-probe shader: mediump dot products of texels (FLOAT_PROBE_TEXTURE=upload), 64 rows: columns
// 0-6 dots, 7-9 the texels. Run with W=10 H=64; see README.md ("mediump builtins").
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
    float c = texture(t, (vec2(float((r + 5) % 8), float((r / 8 + 2) % 8)) + 0.5) / 8.0).x;
    highp float value;
    if (x == 0) value = dot(vec3(a, b, c), vec3(a, b, c));
    else if (x == 1) value = dot(vec3(a, b, 0.0), vec3(a, b, 0.0));
    else if (x == 2) value = dot(vec3(a, b, c), vec3(1.0));
    else if (x == 3) value = a * a + b * b + c * c;
    else if (x == 4) value = dot(vec4(a, b, c, a), vec4(c, a, b, b));
    else if (x == 5) value = dot(vec2(a, b), vec2(c, a));
    else if (x == 6) value = dot(vec3(a, b, c), vec3(b, c, a));
    else if (x == 7) value = a;
    else if (x == 8) value = b;
    else if (x == 9) value = c;
    else value = 0.0;
    highp uint bits = floatBitsToUint(value);
    color = vec4(float(bits >> 24), float((bits >> 16) & 255u), float((bits >> 8) & 255u), float(bits & 255u)) / 255.0;
}
