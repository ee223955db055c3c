#version 300 es
// float-probe shader (FLOAT_PROBE_TEXTURE=varied, FLOAT_PROBE_FILTER=linear or
// FLOAT_PROBE_MIN=...): texture() with the level of detail from the quad's own derivatives,
// which vary from quad to quad (steps of 0.01 to 0.6 of the texture per pixel, skewed, so
// λ spans about −2.7 to 2.3 on the 8×8 texture) plus a bias that varies from one 4×2 group
// of pixels to the next (llvmpipe takes a quad's first pixel's, tiler a group's); column x
// reads channel x mod 4.
precision highp float;
precision highp int;
uniform highp sampler2D t;
out highp vec4 color;
void main() {
    vec2 q = floor(gl_FragCoord.xy);
    vec2 quad = floor(q * 0.5);
    vec2 o = q - 2.0 * quad;
    float a = fract(quad.x * 0.3719 + quad.y * 0.6183);
    float b = fract(quad.x * 0.1287 + quad.y * 0.4419);
    vec2 dx = vec2(0.01 + a * a * 0.6, b * 0.2 - 0.1);
    vec2 dy = vec2(a * 0.15 - 0.05, 0.012 + b * b * 0.5);
    vec2 st = vec2(quad.x * 0.2371 - 0.3, quad.y * 0.1913 - 0.2) + o.x * dx + o.y * dy;
    float bias = fract(floor(q.x * 0.25) * 0.37 + floor(q.y * 0.5) * 0.23) * 1.5 - 0.5;
    vec4 s = texture(t, st, bias);
    int c = int(q.x) % 4;
    float value = c == 0 ? s.x : c == 1 ? s.y : c == 2 ? s.z : s.w;
    highp uint bits = floatBitsToUint(value);
    color = vec4(float(bits >> 24), float((bits >> 16) & 255u), float((bits >> 8) & 255u), float(bits & 255u)) / 255.0;
}
