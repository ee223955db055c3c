#version 300 es
// float-probe shader: mediump and highp arithmetic, one expression per column (x), inputs
// growing by row (y); each pixel holds the bits of one float (see README.md).
precision mediump float;
precision highp int;
out highp vec4 color;

highp float wide(highp float a, highp float b) { return a * b + 0.1; }

void main() {
    highp vec2 q = floor(gl_FragCoord.xy);
    highp float row = q.y + 1.0;
    mediump float m = row * 1.0001;
    mediump float e = row * 0.00146484375;
    mediump float n = 1.0 / 7.0;
    highp float value;
    int x = int(q.x);
    if (x == 0) value = q.y >= 0.0 ? n : m;
    else if (x == 1) value = m * n;
    else if (x == 2) { mediump float d = fract(m * 0.3); d = fract(3.0 * d); d = fract(3.0 * d); value = fract(3.0 * d); }
    else if (x == 3) value = dot(vec4(m, e, e, 0.0), vec4(1.0));
    else if (x == 4) value = (m + e) + e;
    else if (x == 5) { mediump float p = 146.0 + m; value = floor(p * n * n); }
    else if (x == 6) value = normalize(vec3(m, e, 1.0)).x;
    else if (x == 7) value = length(vec2(m, 0.3));
    else if (x == 8) value = inversesqrt(m + 0.7);
    else if (x == 9) value = mix(m, 0.3, 0.25);
    else if (x == 10) value = pow(m * 0.5, 1.7);
    else if (x == 11) value = sin(m * 1.3);
    else if (x == 12) value = exp2(m * 0.37);
    else if (x == 13) value = clamp(m * 0.37, 0.1, 0.9);
    else if (x == 14) value = row * 1.0001 + m;
    else value = wide(m, n);
    highp uint bits = floatBitsToUint(value);
    color = vec4(float(bits >> 24), float((bits >> 16) & 255u), float((bits >> 8) & 255u), float(bits & 255u)) / 255.0;
}
