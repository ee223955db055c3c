#version 300 es
// float-probe shader: mediump refract and reflect of vectors made from texels
// (FLOAT_PROBE_TEXTURE=upload), 64 rows; run with W=10 H=64; see README.md ("mediump builtins").
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
    vec3 i = normalize(vec3(a - 0.5, b - 0.5, -1.0));
    vec3 n = normalize(vec3(b, a, 1.0));
    vec3 r1 = refract(i, n, 1.0 / 1.2);
    vec3 r2 = refract(i * 1.3, n, 1.0 / 1.2);
    const float index = 0.66;
    highp float value;
    if (x == 0) value = r1.x;
    else if (x == 1) value = r1.y;
    else if (x == 2) value = r1.z;
    else if (x == 3) value = r2.x;
    else if (x == 4) value = r2.y;
    else if (x == 5) value = refract(i, n, 1.2).y;
    else if (x == 6) value = refract(i, n, index).x;
    else if (x == 7) value = reflect(i, n).x;
    else if (x == 8) value = i.x;
    else value = n.z;
    uint bits = floatBitsToUint(value);
    color = vec4(float(bits >> 24), float((bits >> 16) & 255u), float((bits >> 8) & 255u), float(bits & 255u)) / 255.0;
}
