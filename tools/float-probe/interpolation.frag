#version 300 es
// float-probe shader: the varying `v` (float-probe.c's vertex shader: an affine function of the
// position with irregular slopes) as interpolated at each pixel centre; even columns v.x, odd
// columns v.y (see README.md). Run with a triangle inside the window and unequal w.
precision highp float;
precision highp int;
in highp vec2 v;
out highp vec4 color;
void main() {
    int x = int(gl_FragCoord.x);
    highp float value = (x % 2 == 0) ? v.x : v.y;
    uint bits = floatBitsToUint(value);
    color = vec4(float(bits >> 24), float((bits >> 16) & 255u), float((bits >> 8) & 255u), float(bits & 255u)) / 255.0;
}
