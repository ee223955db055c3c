#version 300 es
// float-probe shader (FLOAT_PROBE_TEXTURE=varied or varied-npot, FLOAT_PROBE_FILTER=linear):
// one filtered channel of the texture per pixel through a highp sampler (no binary16), at
// coordinates that move irregularly with the pixel, inside and outside [0, 1], so that the
// sub-texel positions take many weights; column x reads channel x mod 4.
precision highp float;
precision highp int;
uniform highp sampler2D t;
out highp vec4 color;
void main() {
    vec2 q = floor(gl_FragCoord.xy);
    vec2 st = vec2(q.x * 0.1371 + q.y * 0.0213 - 0.41, q.y * 0.1173 + q.x * 0.0071 - 0.27);
    vec4 s = texture(t, st);
    int c = int(q.x) % 4;
    float value = c == 0 ? s.x : c == 1 ? s.y : c == 2 ? s.z : s.w;
    highp uint bits = floatBitsToUint(value);
    color = vec4(float(bits >> 24), float((bits >> 16) & 255u), float((bits >> 8) & 255u), float(bits & 255u)) / 255.0;
}
