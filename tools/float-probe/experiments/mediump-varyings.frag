#version 300 es
// float-probe experiment (see README.md here): single mediump operations on a varying. Run with FLOAT_PROBE_TRIANGLE="-1 -1 0.9 -0.95 -0.97 0.93".
precision mediump float;
precision highp int;
in mediump vec2 v;
uniform mediump float unused;
out highp vec4 color;
void main() {
    int x = int(gl_FragCoord.x);
    highp float value;
    if (x == 0) value = v.x + v.y;
    else if (x == 1) value = v.x * v.y;
    else if (x == 2) value = sqrt(v.y);
    else if (x == 3) value = (v.x + v.y) + v.y;
    else if (x == 4) value = v.x;
    else value = v.x - 0.1;
    uint bits = floatBitsToUint(value);
    color = vec4(float(bits >> 24), float((bits >> 16) & 255u), float((bits >> 8) & 255u), float(bits & 255u)) / 255.0;
}
