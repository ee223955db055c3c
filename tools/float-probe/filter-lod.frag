#version 300 es
// float-probe shader (FLOAT_PROBE_TEXTURE=varied, FLOAT_PROBE_FILTER=linear): textureLod at
// an explicit level of detail varying irregularly with the pixel (trilinear between the given
// levels, weight ⌊256 · fract(λ)⌋), at coordinates as filter.frag's; column x reads
// channel x mod 4.
precision highp float;
precision highp int;
uniform highp sampler2D t;
out highp vec4 color;
void main() {
    vec2 q = floor(gl_FragCoord.xy);
    vec2 st = vec2(q.x * 0.1371 + q.y * 0.0213 - 0.41, q.y * 0.1173 + q.x * 0.0071 - 0.27);
    vec4 s = textureLod(t, st, fract(q.y * 0.4137 + q.x * 0.0291) * 3.2);
    int c = int(q.x) % 4;
    float value = c == 0 ? s.x : c == 1 ? s.y : c == 2 ? s.z : s.w;
    highp uint bits = floatBitsToUint(value);
    color = vec4(float(bits >> 24), float((bits >> 16) & 255u), float((bits >> 8) & 255u), float(bits & 255u)) / 255.0;
}
