#version 300 es
// float-probe shader: highp dot, length and normalize of vectors made from the row by single
// products (no sums a compiler could fuse), 64 rows; run with W=8 H=64; see README.md.
precision highp float;
precision highp int;
out highp vec4 color;
void main() {
    highp vec2 q = floor(gl_FragCoord.xy);
    int x = int(q.x);
    float r = q.y + 1.0;
    vec3 a = vec3(r * 0.0173, (65.0 - r) * 0.0119, -0.37);
    vec4 b = vec4(a, r * 0.0031);
    highp float value;
    if (x == 0) value = normalize(a).x;
    else if (x == 1) value = normalize(a).y;
    else if (x == 2) value = normalize(a).z;
    else if (x == 3) value = dot(a, a);
    else if (x == 4) value = length(a);
    else if (x == 5) value = dot(a, vec3(0.3, -0.7, 0.11));
    else if (x == 6) value = normalize(b).w;
    else value = dot(b, b);
    uint bits = floatBitsToUint(value);
    color = vec4(float(bits >> 24), float((bits >> 16) & 255u), float((bits >> 8) & 255u), float(bits & 255u)) / 255.0;
}
