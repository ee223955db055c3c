#version 300 es
// float-probe shader: every texel of FLOAT_PROBE_TEXTURE=upload read through a mediump sampler, red in
// columns 0-7, green in 8-15 (8 rows). llvmpipe returns each as binary16 rounded toward zero.
precision mediump float;
precision highp int;
uniform sampler2D t;
out highp vec4 color;
void main() {
    highp vec2 q = floor(gl_FragCoord.xy);
    int x = int(q.x);
    vec4 s = texture(t, (mod(q, 8.0) + 0.5) / 8.0);
    highp float value = x < 8 ? s.x : s.y;
    highp uint bits = floatBitsToUint(value);
    color = vec4(float(bits >> 24), float((bits >> 16) & 255u), float((bits >> 8) & 255u), float(bits & 255u)) / 255.0;
}
