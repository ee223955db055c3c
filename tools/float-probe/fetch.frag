#version 300 es
// float-probe shader (FLOAT_PROBE_TEXTURE=varied): texelFetch of each texel of level 0 of the
// 8x8 texture, one channel per pixel (column x reads channel x mod 4), through a highp
// sampler: the conversion of a stored byte to float, to the bit.
precision highp float;
precision highp int;
uniform highp sampler2D t;
out highp vec4 color;
void main() {
    ivec2 q = ivec2(gl_FragCoord.xy);
    vec4 s = texelFetch(t, ivec2((q.x / 4) % 8, q.y % 8), 0);
    int c = q.x % 4;
    float value = c == 0 ? s.x : c == 1 ? s.y : c == 2 ? s.z : s.w;
    highp uint bits = floatBitsToUint(value);
    color = vec4(float(bits >> 24), float((bits >> 16) & 255u), float((bits >> 8) & 255u), float(bits & 255u)) / 255.0;
}
