#version 300 es
// float-probe experiment (see README.md here): which mediump operations llvmpipe keeps in single precision.
precision mediump float;
precision highp int;
out highp vec4 color;
void main() {
    highp vec2 q = floor(gl_FragCoord.xy);
    highp float row = q.y + 1.0;
    int x = int(q.x);
    mediump float m = row * 0.1001;
    mediump float u = row * 0.0123;
    mediump vec2 a = vec2(row * 0.1001, row * 0.0123);
    highp float value;
    if (x == 0) value = m;
    else if (x == 1) value = m - 0.2;
    else if (x == 2) { mediump float k = m - 0.2; value = k; }
    else if (x == 3) value = (m - 0.2) * 3.0;
    else if (x == 4) value = m * u;
    else if (x == 5) value = a.x + a.y;
    else if (x == 6) value = dot(a, vec2(1.0));
    else if (x == 7) value = m + u;
    else if (x == 8) { mediump float k = m - 0.2; value = k * k; }
    else if (x == 9) value = sqrt(m);
    else if (x == 10) value = 1.0 / m;
    else if (x == 11) { mediump float s = m + u; value = s + 0.5; }
    else if (x == 12) value = m * 3.0 + u;
    else if (x == 13) value = max(m - 0.2, u);
    else if (x == 14) value = (m - u) - 0.05;
    else value = 0.0;
    uint bits = floatBitsToUint(value);
    color = vec4(float(bits >> 24), float((bits >> 16) & 255u), float((bits >> 8) & 255u), float(bits & 255u)) / 255.0;
}
