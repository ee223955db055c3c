#version 300 es
// float-probe experiment (see README.md here): mediump refract, reflect, pow and normalize against llvmpipe.
precision mediump float;
precision highp int;
out highp vec4 color;
void main() {
    highp vec2 q = floor(gl_FragCoord.xy);
    highp float row = q.y + 1.0;
    mediump float m = row * 0.1001;
    mediump float e = row * 0.0146484375 + 0.3;
    int x = int(q.x);
    mediump vec3 i = normalize(vec3(m - 0.2, e, -1.0));
    mediump vec3 n = normalize(vec3(e, 1.0 - m, 0.7));
    mediump vec3 r = refract(i, n, 1.2);
    mediump vec3 r2 = refract(i * 1.3, n, 1.0 / 1.2);
    mediump vec3 fl = reflect(i, n);
    highp float value;
    if (x == 0) value = r.x;
    else if (x == 1) value = r.y;
    else if (x == 2) value = r.z;
    else if (x == 3) value = r2.x;
    else if (x == 4) value = r2.y;
    else if (x == 5) value = fl.x;
    else if (x == 6) value = fl.z;
    else if (x == 7) value = pow(max(0.0, dot(fl, i)), 100.0);
    else if (x == 8) value = pow(m, 7.5);
    else if (x == 9) value = i.x;
    else if (x == 10) value = n.y;
    else if (x == 11) value = dot(i, n);
    else value = 0.0;
    uint bits = floatBitsToUint(value);
    color = vec4(float(bits >> 24), float((bits >> 16) & 255u), float((bits >> 8) & 255u), float(bits & 255u)) / 255.0;
}
