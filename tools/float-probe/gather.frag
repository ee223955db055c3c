#version 310 es
// float-probe shader (FLOAT_PROBE_TEXTURE=upload or render): textureGather of the 8×8 texture
// at a coordinate that moves irregularly with the pixel; each output byte is one gathered
// texel's red (30x + y of its texel): x, y, z, w as GL ES 3.1 §8.14.2 orders them.
precision highp float;
uniform highp sampler2D tex;
out highp vec4 color;
void main() {
    vec2 p = floor(gl_FragCoord.xy);
    vec2 st = vec2(p.x * 0.0713 + 0.013, p.y * 0.1917 + 0.031);
    color = textureGather(tex, st);
}
