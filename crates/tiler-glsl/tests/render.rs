//! GLSL programs rendered through `tiler::Device`, compared bit for bit with Rust shaders doing
//! the same arithmetic; vertex-stage math checked against Rust f32 directly; compile errors;
//! introspection.
//!
//! The fragment shaders compared with Rust `f32` code declare `highp` floats: a `mediump`
//! operation is computed in binary16 (see `compile::Prec`), which the `mediump_*` tests check.

// The native shaders loop over lanes by index, as the per-lane arithmetic reads best.
#![allow(clippy::needless_range_loop)]

use std::sync::Arc;

use glam::Vec4;
use tiler::{
    Category, ColorAttachment, ColorSpace, Device, DeviceConfig, Draw, F32x8, Format, FragmentShader, Fragments,
    ImageDesc, Interpolation, LaneMask, MipChain, PassReport, Pipeline, PipelineDesc, RenderPass, RenderPassDesc,
    Sampler, ShaderProperties, Texture, VertexFormat, VertexInput, VertexInputState, VertexOutput, VertexShader,
};
use tiler_glsl::{CompiledProgram, Error, Stage, TextureBinding, Type, UniformValues};

const WIDTH: u32 = 40;
const HEIGHT: u32 = 24;

fn desc() -> PipelineDesc {
    PipelineDesc::new("test", VertexInputState::interleaved(&[VertexFormat::Float32x4]))
}

/// Draws a full-screen triangle (GL clip space, attribute 0) with `pipeline`.
fn render(pipeline: &Pipeline) -> (Vec<u8>, PassReport) {
    let mut device = Device::new(DeviceConfig::default()).unwrap();
    let color = device.create_image(ImageDesc::new(WIDTH, HEIGHT, Format::Rgba8Unorm)).unwrap();
    let vertices: [[f32; 4]; 3] = [[-1.0, -1.0, 0.25, 1.0], [3.0, -1.0, 0.25, 1.0], [-1.0, 3.0, 0.25, 1.0]];
    let buffer = device.create_buffer_from(&vertices).unwrap();
    let mut pass = RenderPass::new(RenderPassDesc {
        color: vec![ColorAttachment::clear_store(color, [0.1, 0.2, 0.3, 1.0])],
        depth_stencil: None,
        render_area: None,
    });
    pass.draw(Draw::new(pipeline, buffer, 0, 3));
    let report = device.submit(&pass).unwrap();
    (device.read_rgba8(color).unwrap(), report)
}

/// The GL → tiler clip conversion the GLSL vertex shader applies.
fn gl_to_tiler(p: Vec4) -> Vec4 {
    Vec4::new(p.x, -p.y, (p.z + p.w) * 0.5, p.w)
}

const PASS_VS: &str = "
attribute vec4 position;
varying vec2 uv;
void main() {
    gl_Position = position;
    uv = position.xy * 0.5 + 0.5;
}";

/// The native twin of `PASS_VS`.
struct PassVs;
impl VertexShader for PassVs {
    fn shade(&self, input: &VertexInput, out: &mut VertexOutput) {
        let p = input.attributes[0];
        out.position = gl_to_tiler(p);
        out.varyings[0] = p.x * 0.5 + 0.5;
        out.varyings[1] = p.y * 0.5 + 0.5;
    }
}

fn native_desc() -> PipelineDesc {
    PipelineDesc { varyings: vec![Interpolation::Perspective; 2], ..desc() }
}

fn glsl(vs: &str, fs: &str) -> Arc<CompiledProgram> {
    Arc::new(CompiledProgram::new(vs, fs, &[]).unwrap_or_else(|e| panic!("{e}")))
}

fn glsl_pipeline(
    program: &Arc<CompiledProgram>,
    uniforms: &UniformValues,
    textures: &[Option<TextureBinding>],
) -> Pipeline {
    tiler_glsl::pipeline(program, uniforms, textures, HEIGHT, desc()).unwrap()
}

fn distinct_pixels(image: &[u8]) -> usize {
    let mut pixels: Vec<&[u8]> = image.chunks(4).collect();
    pixels.sort();
    pixels.dedup();
    pixels.len()
}

fn assert_same(glsl: &[u8], native: &[u8], min_distinct: usize) {
    assert_eq!(glsl.len(), native.len());
    let differing = glsl.chunks(4).zip(native.chunks(4)).filter(|(a, b)| a != b).count();
    assert_eq!(differing, 0, "{differing} pixels differ");
    let distinct = distinct_pixels(native);
    assert!(distinct >= min_distinct, "only {distinct} distinct colours: the test would not see a difference");
}

#[test]
fn varying_gradient_matches_native() {
    const FS: &str = "
precision highp float;
varying vec2 uv;
void main() {
    gl_FragColor = vec4(uv, fract(uv.x * 37.0), 1.0);
}";
    struct Native;
    impl FragmentShader for Native {
        fn shade(&self, frag: &mut Fragments<'_>) {
            let [u, v] = frag.smooth_n::<2>(0);
            let f = F32x8::from_array(u.to_array().map(|x| {
                let y = x * 37.0;
                y - y.floor()
            }));
            frag.set_color(0, [u, v, f, F32x8::ONE]);
        }
    }
    let program = glsl(PASS_VS, FS);
    let (a, _) = render(&glsl_pipeline(&program, &program.new_uniform_values(), &[]));
    let (b, _) = render(&Pipeline::new(PassVs, Native, native_desc()).unwrap());
    assert_same(&a, &b, 200);
}

#[test]
fn frag_coord_is_gl_window_coordinates() {
    // Red: x / width; green: GL's y (up) / height; the bottom-left pixel is (0.5, 0.5).
    const FS: &str = "
void main() {
    gl_FragColor = vec4(gl_FragCoord.x / 40.0, gl_FragCoord.y / 24.0, gl_FragCoord.z, gl_FragCoord.w);
}";
    let program = glsl(PASS_VS, FS);
    let (a, _) = render(&glsl_pipeline(&program, &program.new_uniform_values(), &[]));
    let pixel = |x: u32, y: u32| &a[((y * WIDTH + x) * 4) as usize..][..4];
    let unorm = |x: f32| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
    // Top-left pixel (tiler row 0) is GL's top row: y = 24 − 0.5.
    assert_eq!(pixel(0, 0)[0], unorm(0.5 / 40.0));
    assert_eq!(pixel(0, 0)[1], unorm(23.5 / 24.0));
    assert_eq!(pixel(0, HEIGHT - 1)[1], unorm(0.5 / 24.0));
    assert_eq!(pixel(WIDTH - 1, 0)[0], unorm(39.5 / 40.0));
    // z = 0.25 → window depth (0.25 + 1) / 2; w = 1.
    assert_eq!(pixel(3, 3)[2], unorm(0.625));
    assert_eq!(pixel(3, 3)[3], 255);
}

fn checker_texture() -> Arc<Texture> {
    let (w, h) = (16u32, 8u32);
    let mut rgba = Vec::new();
    for y in 0..h {
        for x in 0..w {
            rgba.extend_from_slice(&[(x * 16) as u8, (y * 32) as u8, if (x + y) % 2 == 0 { 255 } else { 0 }, 255]);
        }
    }
    Arc::new(Texture::from_rgba8(w, h, &rgba, ColorSpace::Linear, MipChain::BaseOnly).unwrap())
}

#[test]
fn texture_sample_matches_native_with_the_same_traffic() {
    const FS: &str = "
precision highp float;
uniform highp sampler2D tex; // highp: texels not rounded to binary16, as the native shader's
uniform vec4 tint;
varying vec2 uv;
void main() {
    gl_FragColor = texture2D(tex, uv * 1.5) * tint;
}";
    let texture = checker_texture();
    let sampler = Sampler::BILINEAR_CLAMP;
    let tint = [0.9f32, 0.8, 1.0, 1.0];
    struct Native {
        texture: Arc<Texture>,
        sampler: Sampler,
        tint: [f32; 4],
    }
    impl FragmentShader for Native {
        fn shade(&self, frag: &mut Fragments<'_>) {
            let [u, v] = frag.smooth_n::<2>(0);
            let (s, t) = (u * 1.5, v * 1.5);
            let texel = frag.sample(&self.texture, &self.sampler, [s, F32x8::ONE - t]);
            frag.set_color(0, std::array::from_fn(|c| texel[c] * self.tint[c]));
        }
    }
    let program = glsl(PASS_VS, FS);
    let mut uniforms = program.new_uniform_values();
    program.set_uniform(&mut uniforms, program.uniform_location("tint").unwrap(), &tint).unwrap();
    program.set_uniform(&mut uniforms, program.uniform_location("tex").unwrap(), &[2.0]).unwrap();
    let textures = [None, None, Some(TextureBinding::Core(texture.clone(), sampler))];
    let (a, ra) = render(&glsl_pipeline(&program, &uniforms, &textures));
    let native = Native { texture, sampler, tint };
    let (b, rb) = render(&Pipeline::new(PassVs, native, native_desc()).unwrap());
    assert_same(&a, &b, 20);
    assert_eq!(ra.ledger, rb.ledger, "texture traffic differs");

    // Unit 0 is unbound: opaque black, times the tint.
    program.set_uniform(&mut uniforms, program.uniform_location("tex").unwrap(), &[0.0]).unwrap();
    let (c, _) = render(&glsl_pipeline(&program, &uniforms, &textures));
    assert_eq!(&c[..4], &[0, 0, 0, 255]);
}

#[test]
fn discard_on_a_checker_matches_native() {
    const FS: &str = "
void main() {
    vec2 cell = floor(gl_FragCoord.xy / 4.0);
    if (mod(cell.x + cell.y, 2.0) < 0.5) {
        discard;
    }
    gl_FragColor = vec4(1.0, 0.5, 0.0, 1.0);
}";
    struct Native;
    impl FragmentShader for Native {
        fn properties(&self) -> ShaderProperties {
            ShaderProperties { discards: true, ..ShaderProperties::default() }
        }
        fn shade(&self, frag: &mut Fragments<'_>) {
            let (x, y) = frag.position();
            let mut bits = 0u8;
            for lane in 0..8 {
                let gy = HEIGHT as f32 - y.lane(lane);
                let (cx, cy) = ((x.lane(lane) / 4.0).floor(), (gy / 4.0).floor());
                let s = cx + cy;
                let m = s - 2.0 * (s / 2.0).floor();
                if m < 0.5 {
                    bits |= 1 << lane;
                }
            }
            frag.discard(LaneMask(bits));
            frag.set_color(0, [F32x8::ONE, F32x8::splat(0.5), F32x8::ZERO, F32x8::ONE]);
        }
    }
    let program = glsl(PASS_VS, FS);
    assert!(program.fragment_properties().discards);
    let (a, _) = render(&glsl_pipeline(&program, &program.new_uniform_values(), &[]));
    let (b, _) = render(&Pipeline::new(PassVs, Native, native_desc()).unwrap());
    assert_same(&a, &b, 2);
    // Half the pixels keep the clear colour.
    let cleared = a.chunks(4).filter(|p| p[0] != 255).count();
    assert_eq!(cleared, (WIDTH * HEIGHT / 2) as usize);
}

#[test]
fn loop_with_divergent_break_and_continue_matches_native() {
    const FS: &str = "
varying vec2 uv;
void main() {
    float sum = 0.0;
    int steps = 0;
    for (int i = 0; i < 64; i++) {
        if (float(i) > uv.x * 40.0) break;
        steps++;
        if (mod(float(i), 3.0) == 0.0) continue;
        sum += uv.y * 0.01;
    }
    gl_FragColor = vec4(float(steps) / 64.0, sum, fract(sum * 100.0), 1.0);
}";
    struct Native;
    impl FragmentShader for Native {
        fn shade(&self, frag: &mut Fragments<'_>) {
            let [u, v] = frag.smooth_n::<2>(0);
            let mut out = [[0.0f32; 8]; 3];
            for lane in 0..8 {
                let (mut sum, mut steps) = (0.0f32, 0i32);
                for i in 0..64 {
                    if i as f32 > u.lane(lane) * 40.0 {
                        break;
                    }
                    steps += 1;
                    let f = i as f32;
                    if f - 3.0 * (f / 3.0).floor() == 0.0 {
                        continue;
                    }
                    sum += v.lane(lane) * 0.01;
                }
                let y = sum * 100.0;
                out[0][lane] = steps as f32 / 64.0;
                out[1][lane] = sum;
                out[2][lane] = y - y.floor();
            }
            frag.set_color(
                0,
                [F32x8::from_array(out[0]), F32x8::from_array(out[1]), F32x8::from_array(out[2]), F32x8::ONE],
            );
        }
    }
    let program = glsl(PASS_VS, FS);
    let (a, _) = render(&glsl_pipeline(&program, &program.new_uniform_values(), &[]));
    let (b, _) = render(&Pipeline::new(PassVs, Native, native_desc()).unwrap());
    assert_same(&a, &b, 30);
}

#[test]
fn functions_structs_and_matrices_match_native() {
    const FS: &str = "
precision highp float;
struct Light { vec3 dir; vec3 color; };
uniform Light light;
uniform mat3 rot;
varying vec2 uv;

float lambert(vec3 n, Light l, out float facing) {
    float d = dot(n, normalize(l.dir));
    facing = d > 0.0 ? 1.0 : 0.0;
    if (d < 0.0) return 0.0;
    return d;
}

void main() {
    vec3 n = rot * vec3(uv * 2.0 - 1.0, 1.0);
    n = normalize(n);
    float facing;
    float k = lambert(n, light, facing);
    gl_FragColor = vec4(light.color * k, facing);
}";
    let dir = [0.3f32, -0.5, 0.8];
    let color = [1.0f32, 0.7, 0.4];
    // Column-major rotation-ish matrix.
    let rot = [0.9f32, 0.1, -0.2, -0.1, 0.95, 0.05, 0.2, 0.0, 0.97];
    struct Native {
        dir: [f32; 3],
        color: [f32; 3],
        rot: [f32; 9],
    }
    fn norm(v: [f32; 3]) -> [f32; 3] {
        let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|c| c / len)
    }
    impl FragmentShader for Native {
        fn shade(&self, frag: &mut Fragments<'_>) {
            let [u, v] = frag.smooth_n::<2>(0);
            let mut out = [[0.0f32; 8]; 4];
            for lane in 0..8 {
                let p = [u.lane(lane) * 2.0 - 1.0, v.lane(lane) * 2.0 - 1.0, 1.0];
                let m = &self.rot;
                let n: [f32; 3] = std::array::from_fn(|r| m[r] * p[0] + m[3 + r] * p[1] + m[6 + r] * p[2]);
                let n = norm(n);
                let l = norm(self.dir);
                let d = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
                let facing = if d > 0.0 { 1.0 } else { 0.0 };
                let k = if d < 0.0 { 0.0 } else { d };
                for c in 0..3 {
                    out[c][lane] = self.color[c] * k;
                }
                out[3][lane] = facing;
            }
            frag.set_color(0, out.map(F32x8::from_array));
        }
    }
    let program = glsl(PASS_VS, FS);
    let mut uniforms = program.new_uniform_values();
    program.set_uniform(&mut uniforms, program.uniform_location("light.dir").unwrap(), &dir).unwrap();
    program.set_uniform(&mut uniforms, program.uniform_location("light.color").unwrap(), &color).unwrap();
    program.set_uniform(&mut uniforms, program.uniform_location("rot").unwrap(), &rot).unwrap();
    let (a, _) = render(&glsl_pipeline(&program, &uniforms, &[]));
    let (b, _) = render(&Pipeline::new(PassVs, Native { dir, color, rot }, native_desc()).unwrap());
    assert_same(&a, &b, 50);
}

/// Runs a vertex shader on one vertex and returns its varyings.
fn run_vertex(
    vs: &str,
    fs: &str,
    attribute: [f32; 4],
    set: impl FnOnce(&CompiledProgram, &mut UniformValues),
) -> Vec<f32> {
    let program = glsl(vs, fs);
    let mut uniforms = program.new_uniform_values();
    set(&program, &mut uniforms);
    let (shader, _) = tiler_glsl::shaders(&program, &uniforms, &[], HEIGHT);
    let mut input = VertexInput { attributes: [Vec4::ZERO; tiler::MAX_VERTEX_ATTRIBUTES], vertex_index: 0 };
    input.attributes[0] = Vec4::from_array(attribute);
    let mut out = VertexOutput::default();
    shader.shade(&input, &mut out);
    out.varyings[..program.varying_floats()].to_vec()
}

#[test]
fn vertex_built_ins_match_rust_bit_for_bit() {
    const VS: &str = "
attribute vec4 a;
uniform mat4 m;
uniform float values[3];
varying vec4 r0;
varying vec4 r1;
varying vec4 r2;
varying vec4 r3;
void main() {
    vec4 p = m * a;
    vec3 c = cross(a.xyz, vec3(0.2, 0.7, -0.4));
    vec3 refl = reflect(normalize(a.xyz), vec3(0.0, 1.0, 0.0));
    int idx = int(a.w);
    r0 = p;
    r1 = vec4(c, length(a.xyz));
    r2 = vec4(refl, smoothstep(0.0, 2.0, a.x));
    r3 = vec4(mix(a.x, a.y, 0.3), clamp(a.z, -0.5, 0.5), pow(abs(a.y), 1.5), values[idx]);
    gl_Position = p;
}";
    const FS: &str = "
varying vec4 r0; varying vec4 r1; varying vec4 r2; varying vec4 r3;
void main() { gl_FragColor = r0 + r1 + r2 + r3; }";
    let a = [0.7f32, -1.3, 0.45, 2.0];
    let m: [f32; 16] = std::array::from_fn(|i| (i as f32 * 0.37).sin());
    let values = [3.5f32, -2.25, 9.0];
    let got = run_vertex(VS, FS, a, |p, u| {
        p.set_uniform(u, p.uniform_location("m").unwrap(), &m).unwrap();
        p.set_uniform(u, p.uniform_location("values").unwrap(), &values).unwrap();
    });
    let mut want = Vec::new();
    for r in 0..4 {
        want.push(((m[r] * a[0] + m[4 + r] * a[1]) + m[8 + r] * a[2]) + m[12 + r] * a[3]);
    }
    let b = [0.2f32, 0.7, -0.4];
    want.extend([a[1] * b[2] - b[1] * a[2], a[2] * b[0] - b[2] * a[0], a[0] * b[1] - b[0] * a[1]]);
    let len = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    want.push(len);
    let n = [a[0] / len, a[1] / len, a[2] / len];
    let d = 0.0 * n[0] + 1.0 * n[1] + 0.0 * n[2];
    let d2 = 2.0 * d;
    want.extend([n[0] - d2 * 0.0, n[1] - d2 * 1.0, n[2] - d2 * 0.0]);
    let t = ((a[0] - 0.0) / (2.0 - 0.0)).clamp(0.0, 1.0);
    want.push(t * t * (3.0 - 2.0 * t));
    want.push(a[0] * (1.0 - 0.3) + a[1] * 0.3);
    want.push(a[2].clamp(-0.5, 0.5));
    want.push(a[1].abs().powf(1.5));
    want.push(values[2]);
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&got), bits(&want), "got {got:?}\nwant {want:?}");
}

#[test]
fn dynamic_indices_and_inout_parameters() {
    const VS: &str = "
attribute vec4 a;
varying vec4 r;
void bump(inout float x, float by) { x += by; }
void main() {
    float arr[4];
    for (int i = 0; i < 4; i++) { arr[i] = float(i * i); }
    int k = int(a.x);
    arr[k] = -1.0;
    vec4 v = vec4(10.0, 20.0, 30.0, 40.0);
    v[k] = 7.0;
    float s = arr[0] + arr[1] + arr[2] + arr[3];
    bump(s, 0.5);
    int j = 0;
    do { j += 2; } while (j < 5);
    r = vec4(s, v[1] + v[2], float(j), a.y > 0.0 && !(a.z > 0.0) ? 1.0 : 2.0);
    gl_Position = a;
}";
    const FS: &str = "varying vec4 r; void main() { gl_FragColor = r; }";
    let got = run_vertex(VS, FS, [2.0, 1.0, -1.0, 1.0], |_, _| {});
    // arr = 0, 1, -1, 9 → 9 + 0.5; v = 10, 20, 7, 40; j = 6.
    assert_eq!(got, vec![9.5, 27.0, 6.0, 1.0]);
    let got = run_vertex(VS, FS, [1.0, 1.0, 1.0, 1.0], |_, _| {});
    assert_eq!(got, vec![0.0 + -1.0 + 4.0 + 9.0 + 0.5, 7.0 + 30.0, 6.0, 2.0]);
}

#[test]
fn compile_errors_name_the_shader_and_line() {
    let fs_ok = "void main() { gl_FragColor = vec4(1.0); }";
    let vs_bad = "attribute vec4 p;\nvoid main() {\n  gl_Position = p;\n  float x = undeclared * 2.0;\n}";
    match CompiledProgram::new(vs_bad, fs_ok, &[]) {
        Err(Error::Compile { stage: Stage::Vertex, line: 4, message }) => assert!(message.contains("undeclared")),
        other => panic!("{other:?}"),
    }
    let vs_ok = "attribute vec4 p; void main() { gl_Position = p; }";
    let fs_bad = "precision highp float;\n\nvoid main() {\n  vec3 c = vec2(1.0);\n  gl_FragColor = vec4(c, 1.0);\n}";
    let e = CompiledProgram::new(vs_ok, fs_bad, &[]).unwrap_err();
    assert!(matches!(e, Error::Compile { stage: Stage::Fragment, line: 4, .. }), "{e}");
    assert!(e.to_string().starts_with("fragment shader, line 4:"), "{e}");
    // A syntax error, with a #version line before it.
    let fs_syntax = "#version 100\nvoid main() {\n  gl_FragColor = vec4(1.0) +;\n}";
    let e = CompiledProgram::new(vs_ok, fs_syntax, &[]).unwrap_err();
    assert!(matches!(e, Error::Compile { stage: Stage::Fragment, line: 3, .. }), "{e}");
    // Cube lookups with the wrong sampler or direction are refused clearly.
    let fs_cube = "uniform sampler2D env;\nvoid main() {\n  gl_FragColor = textureCube(env, vec3(1.0));\n}";
    let e = CompiledProgram::new(vs_ok, fs_cube, &[]).unwrap_err();
    assert!(
        matches!(e, Error::Compile { stage: Stage::Fragment, line: 3, .. }) && e.to_string().contains("samplerCube"),
        "{e}"
    );
    let fs_cube = "uniform samplerCube env;\nvoid main() {\n  gl_FragColor = textureCube(env, vec2(1.0));\n}";
    let e = CompiledProgram::new(vs_ok, fs_cube, &[]).unwrap_err();
    assert!(e.to_string().contains("vec3 direction"), "{e}");
    let fs_cube = "uniform samplerCube env;\nvoid main() {\n  gl_FragColor = texture2D(env, vec2(1.0));\n}";
    let e = CompiledProgram::new(vs_ok, fs_cube, &[]).unwrap_err();
    assert!(e.to_string().contains("needs a sampler2D"), "{e}");
    let vs_bias = "attribute vec4 p;\nuniform samplerCube env;\nvarying vec4 c;\n\
                   void main() { c = textureCube(env, p.xyz, 1.0); gl_Position = p; }";
    let e = CompiledProgram::new(vs_bias, fs_ok, &[]).unwrap_err();
    assert!(e.to_string().contains("bias in a vertex shader"), "{e}");
    // GL_ES is predefined.
    let fs_es =
        "#ifdef GL_ES\nprecision highp float;\n#else\n#error not ES\n#endif\nvoid main() { gl_FragColor = vec4(1.0); }";
    CompiledProgram::new(vs_ok, fs_es, &[]).unwrap();
    // Recursion cannot inline forever.
    let fs_rec = "float f(float x) { return f(x); }\nvoid main() { gl_FragColor = vec4(f(1.0)); }";
    let e = CompiledProgram::new(vs_ok, fs_rec, &[]).unwrap_err();
    assert!(e.to_string().contains("recursion"), "{e}");
}

#[test]
fn introspection_and_linking() {
    const VS: &str = "
attribute vec3 normal;
attribute vec4 position;
attribute mat2 twist;
uniform mat4 mvp;
uniform vec3 offsets[4];
struct S { float a; vec2 b[2]; };
uniform S s;
varying vec3 n;
varying float unused_by_fs;
void main() { gl_Position = mvp * position; n = normal + offsets[1] + vec3(twist[0], s.a); unused_by_fs = 1.0; }";
    const FS: &str = "
precision highp float;
uniform sampler2D tex;
uniform vec3 offsets[4];
varying vec3 n;
void main() { gl_FragColor = texture2D(tex, n.xy) + vec4(offsets[2], 1.0); }";
    let program = CompiledProgram::new(VS, FS, &[("position", 0)]).unwrap();
    let attributes: Vec<(&str, u32)> = program.attributes().iter().map(|a| (a.name.as_str(), a.location)).collect();
    // position is bound to 0; the others take the lowest free locations (mat2 takes two).
    assert_eq!(attributes, vec![("normal", 1), ("position", 0), ("twist", 2)]);
    assert_eq!(program.attribute_location("twist"), Some(2));
    let uniforms: Vec<(String, String, usize, u32)> =
        program.uniforms().iter().map(|u| (u.name.clone(), u.ty.to_string(), u.array_size, u.location)).collect();
    assert_eq!(
        uniforms,
        vec![
            ("mvp".into(), "mat4".into(), 1, 0),
            ("offsets".into(), "vec3".into(), 4, 1),
            ("s.a".into(), "float".into(), 1, 5),
            ("s.b".into(), "vec2".into(), 2, 6),
            ("tex".into(), "sampler2D".into(), 1, 8),
        ]
    );
    assert_eq!(program.uniform_location("offsets[3]"), Some(4));
    assert_eq!(program.uniform_location("offsets[4]"), None);
    assert_eq!(program.uniform_location("s.b[1]"), Some(7));
    assert_eq!(program.uniforms()[4].ty, Type::Sampler(tiler_glsl::SamplerKind::Sampler2D));
    // Only what the fragment shader reads is packed.
    assert_eq!(program.varyings().len(), 1);
    assert_eq!(program.varying_floats(), 3);
    assert!(!program.fragment_properties().discards);
    let mut values = program.new_uniform_values();
    let e = program.set_uniform(&mut values, 1, &[0.0; 15]).unwrap_err();
    assert!(e.to_string().contains("offsets"), "{e}");
    program.set_uniform(&mut values, 8, &[3.0]).unwrap();
    assert_eq!(program.sampler_units(&values), vec![("tex".to_string(), 3)]);

    // Link errors.
    let fs_missing = "varying vec2 nope; void main() { gl_FragColor = vec4(nope, 0.0, 1.0); }";
    let e = CompiledProgram::new(VS, fs_missing, &[]).unwrap_err();
    assert!(matches!(&e, Error::Link(m) if m.contains("nope")), "{e}");
    let fs_type = "varying vec2 n; void main() { gl_FragColor = vec4(n, 0.0, 1.0); }";
    assert!(matches!(CompiledProgram::new(VS, fs_type, &[]), Err(Error::Link(_))));
}

#[test]
fn fragment_data_and_determinism() {
    // gl_FragData[0] and a loop whose trip count varies per lane: two renders are identical.
    const FS: &str = "
varying vec2 uv;
void main() {
    vec4 acc = vec4(0.0);
    float t = uv.x;
    while (t < 1.0) { acc += vec4(t, t * t, 0.1, 0.0); t += 0.125 + uv.y * 0.1; }
    gl_FragData[0] = vec4(fract(acc.xyz), 1.0);
}";
    let program = glsl(PASS_VS, FS);
    let pipeline = glsl_pipeline(&program, &program.new_uniform_values(), &[]);
    let (a, _) = render(&pipeline);
    let (b, _) = render(&pipeline);
    assert_eq!(a, b);
    assert!(distinct_pixels(&a) > 20);
}

#[test]
fn attributes_are_read_from_their_locations() {
    const VS: &str = "
attribute vec2 second;
attribute vec4 first;
attribute mat2 m;
varying vec4 r;
varying vec2 c;
void main() { gl_Position = first; r = vec4(second, first.zw); c = m * vec2(1.0, 10.0); }";
    const FS: &str = "varying vec4 r; varying vec2 c; void main() { gl_FragColor = r + c.xyxy; }";
    let program = Arc::new(CompiledProgram::new(VS, FS, &[("first", 0), ("second", 5)]).unwrap());
    assert_eq!(program.attribute_location("m"), Some(1));
    // Relinking with other locations gives what compiling with them gives.
    let unbound = CompiledProgram::new(VS, FS, &[]).unwrap();
    let relinked = unbound.with_attribute_locations(&[("first", 0), ("second", 5)]).unwrap();
    assert_eq!(relinked.attributes(), program.attributes());
    assert_ne!(unbound.attributes(), program.attributes(), "the locations moved");
    let beyond = [("first", tiler::MAX_VERTEX_ATTRIBUTES as u32)];
    assert!(CompiledProgram::new(VS, FS, &beyond).is_err(), "a location beyond the last");
    assert!(unbound.with_attribute_locations(&beyond).is_err(), "the same link error");
    let (shader, _) = tiler_glsl::shaders(&program, &program.new_uniform_values(), &[], HEIGHT);
    let mut input = VertexInput { attributes: [Vec4::ZERO; tiler::MAX_VERTEX_ATTRIBUTES], vertex_index: 0 };
    input.attributes[0] = Vec4::new(1.0, 2.0, 3.0, 4.0);
    input.attributes[1] = Vec4::new(0.5, 0.25, 0.0, 0.0); // column 0 of m
    input.attributes[2] = Vec4::new(2.0, 3.0, 0.0, 0.0); // column 1 of m
    input.attributes[5] = Vec4::new(7.0, 8.0, 0.0, 1.0);
    let mut out = VertexOutput::default();
    shader.shade(&input, &mut out);
    assert_eq!(&out.varyings[..6], &[7.0, 8.0, 3.0, 4.0, 0.5 + 20.0, 0.25 + 30.0]);
    // GL clip (1, 2, 3, 4) → tiler (x, −y, (z + w)/2, w).
    assert_eq!(out.position, Vec4::new(1.0, -2.0, 3.5, 4.0));
}

#[test]
fn derivatives_match_native_with_gl_y_up() {
    const FS: &str = "
#extension GL_OES_standard_derivatives : enable
precision highp float;
varying vec2 uv;
void main() {
    gl_FragColor = vec4(dFdx(uv.x) * 20.0, dFdy(uv.y) * 12.0, fwidth(uv.x * uv.y) * 10.0, 1.0);
}";
    struct Native;
    impl FragmentShader for Native {
        fn shade(&self, frag: &mut Fragments<'_>) {
            let [u, v] = frag.smooth_n::<2>(0);
            let w = u * v;
            let fw = w.ddx().abs() + (F32x8::ZERO - w.ddy()).abs();
            let r = u.ddx() * F32x8::splat(20.0);
            let g = (F32x8::ZERO - v.ddy()) * F32x8::splat(12.0);
            frag.set_color(0, [r, g, fw * F32x8::splat(10.0), F32x8::ONE]);
        }
    }
    let program = glsl(PASS_VS, FS);
    let (a, _) = render(&glsl_pipeline(&program, &program.new_uniform_values(), &[]));
    let (b, _) = render(&Pipeline::new(PassVs, Native, native_desc()).unwrap());
    assert_same(&a, &b, 10);
    // uv grows right and up (GL), half a unit per 20 and 12 pixels.
    assert!((127..=128).contains(&a[0]) && (127..=128).contains(&a[1]), "{:?}", &a[..4]);
}

#[test]
fn front_facing_follows_gl_winding_with_tiler_gl_front_face() {
    // The full-screen triangle is counter-clockwise in GL's window; tiler-gl maps GL's
    // `glFrontFace(GL_CCW)` to `FrontFace::CounterClockwise` (the picture is upright in both).
    const FS: &str =
        "void main() { gl_FragColor = gl_FrontFacing ? vec4(1.0, 0.0, 0.0, 1.0) : vec4(0.0, 1.0, 0.0, 1.0); }";
    let program = glsl(PASS_VS, FS);
    let uniforms = program.new_uniform_values();
    for (front_face, expected) in
        [(tiler::FrontFace::CounterClockwise, [255, 0, 0, 255]), (tiler::FrontFace::Clockwise, [0, 255, 0, 255])]
    {
        let desc = PipelineDesc { front_face, ..desc() };
        let pipeline = tiler_glsl::pipeline(&program, &uniforms, &[], HEIGHT, desc).unwrap();
        let (image, _) = render(&pipeline);
        assert!(image.chunks(4).all(|p| p == expected), "{front_face:?}: {:?}", &image[..4]);
    }
}

/// A caller's sampler that returns its coordinates and level: (s, t, lod or −1, 1).
#[derive(Debug)]
struct Probe;
impl tiler_glsl::TextureSource for Probe {
    fn sample(&self, s: f32, t: f32, lod: Option<f32>) -> [f32; 4] {
        [s, t, lod.unwrap_or(-1.0), 1.0]
    }
}

#[test]
fn custom_texture_sources_get_gl_coordinates_and_levels() {
    const VS: &str = "
attribute vec4 position;
uniform sampler2D probe;
varying vec4 fetched;
void main() {
    fetched = texture2DLod(probe, vec2(0.25, 0.75), 2.0);
    gl_Position = position;
}";
    const FS: &str = "
precision highp float;
uniform sampler2D probe;
varying vec4 fetched;
void main() {
    vec4 p = texture2DProj(probe, vec3(gl_FragCoord.xy, 2.0));
    gl_FragColor = vec4(p.x / 40.0, p.y / 24.0, -p.z * 0.5, 1.0);
}";
    let program = glsl(VS, FS);
    let mut uniforms = program.new_uniform_values();
    program.set_uniform(&mut uniforms, program.uniform_location("probe").unwrap(), &[1.0]).unwrap();
    let textures = [None, Some(TextureBinding::Custom(Arc::new(Probe)))];
    let (vs, _) = tiler_glsl::shaders(&program, &uniforms, &textures, HEIGHT);
    let input = VertexInput { attributes: [Vec4::ONE; tiler::MAX_VERTEX_ATTRIBUTES], vertex_index: 0 };
    let mut out = VertexOutput::default();
    vs.shade(&input, &mut out);
    assert_eq!(&out.varyings[..4], &[0.25, 0.75, 2.0, 1.0]);
    let (image, _) = render(&glsl_pipeline(&program, &uniforms, &textures));
    // Bottom-left pixel: GL (0.5, 0.5) / 2; no level in a fragment shader (−1 → 0.5 blue).
    let bottom_left = &image[((HEIGHT - 1) * WIDTH * 4) as usize..][..4];
    let unorm = |x: f32| (x * 255.0).round() as u8;
    assert_eq!(bottom_left, &[unorm(0.25 / 40.0), unorm(0.25 / 24.0), unorm(0.5), 255]);
}

/// A 16×16 cube whose face `i` has texel `(x, y)` = `(16 x, 16 y, 40 i, 255)`, mip-mapped.
fn cube_texture() -> Arc<Texture> {
    let faces: Vec<Vec<u8>> = (0..6u32)
        .map(|i| (0..256u32).flat_map(|p| [(p % 16 * 16) as u8, (p / 16 * 16) as u8, (40 * i) as u8, 255]).collect())
        .collect();
    let faces: [&[u8]; 6] = std::array::from_fn(|i| faces[i].as_slice());
    Arc::new(Texture::cube_from_rgba8(16, faces, ColorSpace::Linear, MipChain::Box).unwrap())
}

#[test]
fn texture_cube_matches_native_with_the_same_traffic() {
    // Directions sweeping several faces (x from −1 to 1 across the window, z from the
    // varying), sampled with a bias through a samplerCube uniform on unit 1 beside a 2D
    // texture on unit 0: the same pixels and texture bytes as a Rust shader calling the core.
    const FS: &str = "
precision highp float;
precision highp samplerCube;
precision highp sampler2D;
uniform sampler2D plain;
uniform samplerCube env;
uniform float bias;
varying vec2 uv;
void main() {
    vec3 d = vec3(uv.x * 2.0 - 1.0, 0.3, uv.y * 3.0 - 1.5);
    gl_FragColor = textureCube(env, d, bias) * 0.5 + texture2D(plain, uv) * 0.5;
}";
    struct Native {
        cube: Arc<Texture>,
        flat: Arc<Texture>,
        sampler: Sampler,
    }
    impl FragmentShader for Native {
        fn shade(&self, frag: &mut Fragments<'_>) {
            let [u, v] = frag.smooth_n::<2>(0);
            let d = [u * 2.0 - F32x8::ONE, F32x8::splat(0.3), v * 3.0 - F32x8::splat(1.5)];
            let biased = Sampler { lod_bias: 0.75, ..self.sampler };
            let cube = frag.sample_cube(&self.cube, &biased, d);
            let flat = frag.sample(&self.flat, &self.sampler, [u, F32x8::ONE - v]);
            frag.set_color(0, std::array::from_fn(|c| cube[c] * 0.5 + flat[c] * 0.5));
        }
    }
    let (cube, flat, sampler) = (cube_texture(), checker_texture(), Sampler::TRILINEAR_REPEAT);
    let program = glsl(PASS_VS, FS);
    let mut uniforms = program.new_uniform_values();
    program.set_uniform(&mut uniforms, program.uniform_location("env").unwrap(), &[1.0]).unwrap();
    program.set_uniform(&mut uniforms, program.uniform_location("bias").unwrap(), &[0.75]).unwrap();
    let textures =
        [Some(TextureBinding::Core(flat.clone(), sampler)), Some(TextureBinding::Core(cube.clone(), sampler))];
    let (a, ra) = render(&glsl_pipeline(&program, &uniforms, &textures));
    let (b, rb) = render(&Pipeline::new(PassVs, Native { cube, flat, sampler }, native_desc()).unwrap());
    assert_same(&a, &b, 40);
    assert_eq!(ra.ledger, rb.ledger, "texture traffic differs");
    // Several faces show: their blue channels (40 i, halved) differ.
    let blues: std::collections::BTreeSet<u8> = a.chunks_exact(4).map(|p| p[2] / 16).collect();
    assert!(blues.len() >= 3, "{blues:?}");
}

#[test]
fn vertex_shaders_fetch_cube_textures_at_explicit_levels() {
    const VS: &str = "
attribute vec4 position;
uniform samplerCube env;
varying vec4 base;
varying vec4 level1;
void main() {
    base = textureCube(env, vec3(-2.0, 1.0, 0.5));
    level1 = textureCubeLod(env, vec3(0.1, -1.0, 0.1), 1.0);
    gl_Position = position;
}";
    const FS: &str = "precision highp float;\nvarying vec4 base;\nvarying vec4 level1;\n\
                      void main() { gl_FragColor = base + level1; }";
    let program = glsl(VS, FS);
    let uniforms = program.new_uniform_values();
    let cube = cube_texture();
    let textures = [Some(TextureBinding::Core(cube.clone(), Sampler::NEAREST_REPEAT))];
    let (vs, _) = tiler_glsl::shaders(&program, &uniforms, &textures, HEIGHT);
    let input = VertexInput { attributes: [Vec4::ONE; tiler::MAX_VERTEX_ATTRIBUTES], vertex_index: 0 };
    let mut out = VertexOutput::default();
    vs.shade(&input, &mut out);
    // −X: sc = +rz = 0.5, tc = −ry = −1, |ma| = 2: s = 0.625, t = 0.25 → texel (10, 4) of face 1.
    assert_eq!(&out.varyings[..4], &[160.0 / 255.0, 64.0 / 255.0, 40.0 / 255.0, 1.0]);
    // −Y: sc = rx, tc = −rz: s = 0.55, t = 0.45 on level 1 (8×8, nearest): texel (4, 3).
    let nearest_mip = Sampler { mipmap: tiler::MipmapMode::Nearest, ..Sampler::NEAREST_REPEAT };
    let textures = [Some(TextureBinding::Core(cube.clone(), nearest_mip))];
    let (vs, _) = tiler_glsl::shaders(&program, &uniforms, &textures, HEIGHT);
    vs.shade(&input, &mut out);
    let texel = cube.face_texel(tiler::CubeFace::NegativeY, 1, 4, 3);
    assert_eq!(&out.varyings[4..8], &texel.map(|c| c as f32 * (1.0 / 255.0)));
    // A 2D texture on a samplerCube's unit reads opaque black, as an incomplete texture.
    let textures = [Some(TextureBinding::Core(checker_texture(), Sampler::NEAREST_REPEAT))];
    let (vs, _) = tiler_glsl::shaders(&program, &uniforms, &textures, HEIGHT);
    vs.shade(&input, &mut out);
    assert_eq!(&out.varyings[..4], &[0.0, 0.0, 0.0, 1.0]);
}

#[test]
fn vertex_shaders_fetch_core_textures_through_the_samplers_filter() {
    // A displacement map read in the vertex shader, as glmark2's terrain does: GL samples at
    // level of detail 0, so the magnification filter applies — bilinear here, between texels
    // 2 (red 40) and 3 (red 60) of the first row, then level 1 with an explicit level.
    const VS: &str = "
attribute vec4 position;
uniform sampler2D height;
varying vec4 fetched;
varying vec4 level1;
void main() {
    fetched = texture2D(height, vec2(3.0 / 8.0, 0.5 / 4.0));
    level1 = texture2DLod(height, vec2(0.0, 0.0), 1.0);
    gl_Position = position;
}";
    const FS: &str = "precision highp float;\nvarying vec4 fetched;\nvarying vec4 level1;\n\
                      void main() { gl_FragColor = fetched + level1; }";
    let program = glsl(VS, FS);
    let mut uniforms = program.new_uniform_values();
    program.set_uniform(&mut uniforms, program.uniform_location("height").unwrap(), &[0.0]).unwrap();
    // 8×4, red = 20 · x, rows stored top first (GL's t = 0.125 is the last row).
    let texels: Vec<u8> = (0..4).flat_map(|_| (0..8u8).flat_map(|x| [20 * x, 0, 0, 255])).collect();
    let texture = Arc::new(Texture::from_rgba8(8, 4, &texels, ColorSpace::Linear, MipChain::Box).unwrap());
    let vs_output = |sampler: Sampler| {
        let textures = [Some(TextureBinding::Core(texture.clone(), sampler))];
        let (vs, _) = tiler_glsl::shaders(&program, &uniforms, &textures, HEIGHT);
        let input = VertexInput { attributes: [Vec4::ONE; tiler::MAX_VERTEX_ATTRIBUTES], vertex_index: 0 };
        let mut out = VertexOutput::default();
        vs.shade(&input, &mut out);
        (out.varyings[0] * 255.0, out.varyings[4] * 255.0)
    };
    let (bilinear, level1) = vs_output(Sampler::TRILINEAR_REPEAT.with_wrap(tiler::Wrap::ClampToEdge));
    assert!((bilinear - 50.0).abs() < 1e-3, "{bilinear}");
    // Level 1 texel (0, 0) averages level 0's x = 0, 1: (0 + 20 + 0 + 20 + 2) >> 2 = 10.
    assert!((level1 - 10.0).abs() < 1e-3, "{level1}");
    // With a nearest filter the same fetch reads texel 3.
    let (nearest, _) = vs_output(Sampler::NEAREST_REPEAT);
    assert_eq!(nearest, 60.0 * (1.0f32 / 255.0) * 255.0);
}

#[test]
fn hostile_programs_fail_cleanly() {
    let vs = "attribute vec4 p; void main() { gl_Position = p; }";
    let fail = |fs: &str, needle: &str| {
        let e = CompiledProgram::new(vs, fs, &[]).unwrap_err();
        assert!(matches!(e, Error::Compile { stage: Stage::Fragment, .. }), "{e}");
        assert!(e.to_string().contains(needle), "{e}");
    };
    // Each level calls the one below four times: 4^12 inlined copies.
    let mut fs = String::from("float f0(float x) { return x * 2.0 + 1.0; }\n");
    for i in 1..=12 {
        let p = i - 1;
        fs += &format!("float f{i}(float x) {{ return f{p}(x) + f{p}(x + 1.0) + f{p}(x * 2.0) + f{p}(-x); }}\n");
    }
    fs += "void main() { gl_FragColor = vec4(f12(1.0)); }";
    fail(&fs, "too large");
    fail("void main() { float a[4096][4096]; gl_FragColor = vec4(a[0][0]); }", "at most");
    fail("void g() {}\nvoid main() { bool b = g() == g(); }", "compare");
    fail(
        "uniform sampler2D a; uniform sampler2D b; uniform bool c;\nvoid main() { gl_FragColor = texture2D(c ? a : b, vec2(0.0)); }",
        "?:",
    );
    fail(
        "uniform sampler2D a;\nvec4 f(sampler2D s) { s = a; return vec4(0.0); }\nvoid main() { gl_FragColor = f(a); }",
        "read-only",
    );
}

/// A convolution whose weights are the constants 0 and 1 (glmark2's effect2d with its
/// identity kernel) compiles to the one lookup whose weight is 1: the picture is the single
/// lookup's, bit for bit, and so is the texture traffic — the zero-weighted lookups are not
/// fetched, as a GPU's compiler removes them (see `fold.rs`).
#[test]
fn lookups_weighted_by_a_constant_zero_are_not_fetched() {
    const KERNEL: &str = "
precision highp float;
precision highp sampler2D;
const float K0 = 0.0;
const float K1 = 1.0;
const float Step = 0.0625;
uniform sampler2D tex;
varying vec2 uv;
void main() {
    vec4 result = texture2D(tex, uv + vec2(-Step, 0.0)) * K0 +
                  texture2D(tex, uv + vec2(0.0 * Step, 0.0)) * K1 +
                  texture2D(tex, uv + vec2(Step, Step)) * K0;
    gl_FragColor = vec4(result.xyz, 1.0);
}";
    const SINGLE: &str = "
precision highp float;
precision highp sampler2D;
uniform sampler2D tex;
varying vec2 uv;
void main() { gl_FragColor = vec4(texture2D(tex, uv).xyz, 1.0); }";
    let textures = [Some(TextureBinding::Core(checker_texture(), Sampler::BILINEAR_CLAMP))];
    let kernel = glsl(PASS_VS, KERNEL);
    let single = glsl(PASS_VS, SINGLE);
    assert_eq!(kernel.instruction_counts().1, single.instruction_counts().1);
    let (a, ra) = render(&glsl_pipeline(&kernel, &kernel.new_uniform_values(), &textures));
    let (b, rb) = render(&glsl_pipeline(&single, &single.new_uniform_values(), &textures));
    assert_same(&a, &b, 20);
    assert_eq!(ra.ledger, rb.ledger, "the zero-weighted lookups were fetched");
    assert_eq!(ra.counters.texels_read, rb.counters.texels_read);
    assert!(ra.ledger.get(Category::TextureFetch) > 0);

    // A weight that is not a constant keeps its lookup.
    let uniform_weight = KERNEL.replace("const float K0 = 0.0;", "uniform float K0;");
    let kept = glsl(PASS_VS, &uniform_weight);
    let (_, rk) = render(&glsl_pipeline(&kept, &kept.new_uniform_values(), &textures));
    assert_eq!(rk.counters.texels_read, 3 * rb.counters.texels_read);
}

#[test]
fn uniform_only_arithmetic_is_computed_once_per_instance() {
    const FS: &str = "
uniform vec3 u;
void main() { gl_FragColor = vec4(normalize(u) * 0.5 + 0.5, 1.0); }";
    let program = glsl(PASS_VS, FS);
    // gl_FragColor's four moves from the bank are all that is left per group (its zeroing
    // is overwritten before any read, and the stores at the top of `main` are moves).
    assert_eq!(program.instruction_counts().1, 4);
    let u = [0.3f32, -0.7, 0.2];
    let mut uniforms = program.new_uniform_values();
    program.set_uniform(&mut uniforms, 0, &u).unwrap();
    let (image, _) = render(&glsl_pipeline(&program, &uniforms, &[]));
    let len = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
    let unorm = |x: f32| (x * 255.0).round() as u8;
    let want: Vec<u8> = u.iter().map(|c| unorm(c / len * 0.5 + 0.5)).chain([255]).collect();
    assert!(image.chunks(4).all(|p| p == want.as_slice()), "{:?} vs {want:?}", &image[..4]);
}

/// Nesting as deep as the source limit allows compiles (or fails cleanly) instead of
/// overflowing the stack, which aborted the process; a macro chain that doubles at every step
/// is refused before it expands, and so is a source past the size limit.
#[test]
fn deep_nesting_and_macro_bombs_do_not_abort() {
    let vs = "attribute vec4 p; void main() { gl_Position = p; }";
    let limit = tiler_glsl::guard::MAX_SOURCE_BYTES;
    let chain = format!("void main() {{ gl_FragColor = vec4(1.0{}); }}", "+1.0".repeat((limit - 64) / 4));
    assert!(chain.len() <= limit);
    CompiledProgram::new(vs, &chain, &[]).unwrap();
    let blocks =
        format!("void main() {{ {}{} gl_FragColor = vec4(1.0); }}", "{".repeat(limit / 3), "}".repeat(limit / 3));
    CompiledProgram::new(vs, &blocks, &[]).unwrap();
    let negations = format!("void main() {{ gl_FragColor = vec4({}1.0); }}", "- ".repeat((limit - 64) / 2));
    CompiledProgram::new(vs, &negations, &[]).unwrap();

    let e = CompiledProgram::new(vs, &"//".repeat(limit), &[]).unwrap_err();
    assert!(matches!(e, Error::Compile { stage: Stage::Fragment, .. }) && e.to_string().contains("bytes"), "{e}");
    let mut bomb = String::from("#define A0 1.0\n");
    for i in 1..=24 {
        bomb += &format!("#define A{i} A{}+A{}\n", i - 1, i - 1);
    }
    bomb += "void main() { gl_FragColor = vec4(A24); }";
    let e = CompiledProgram::new(vs, &bomb, &[]).unwrap_err();
    // A0 is three tokens (`1`, `.`, `0`), so A19 is the first past 2^20.
    assert!(e.to_string().contains("line 20: macro A19 expands to more than"), "{e}");
}

/// Function-like macros defined each from the last twice over would expand to 2^30 copies:
/// refused from the definitions, before the preprocessor runs.
#[test]
fn function_like_macro_bombs_are_refused() {
    let vs = "attribute vec4 p; void main() { gl_Position = p; }";
    let mut fs = String::from("#define B0(x) x\n");
    for i in 1..=30 {
        fs += &format!("#define B{i}(x) B{p}(x)+B{p}(x)\n", p = i - 1);
    }
    fs += "void main() { gl_FragColor = vec4(B30(1.0)); }";
    let e = CompiledProgram::new(vs, &fs, &[]).unwrap_err();
    assert!(e.to_string().contains("expands to more than"), "{e}");
}

/// Each macro within its limit (A17 is 2^18 − 1 tokens to the lexer), but used nine times: what the preprocessor emits is cut
/// at the parser's token limit, with an error that says so.
#[test]
fn the_parser_reads_at_most_its_token_limit() {
    let vs = "attribute vec4 p; void main() { gl_Position = p; }";
    let mut fs = String::from("#define A0 1.0\n");
    for i in 1..=17 {
        fs += &format!("#define A{i} A{p}+A{p}\n", p = i - 1);
    }
    fs += &format!("void main() {{ gl_FragColor = vec4({}); }}", ["A17"; 9].join("+"));
    match CompiledProgram::new(vs, &fs, &[]) {
        Ok(_) => panic!("nine uses of a macro of 2^18 tokens compiled"),
        Err(e) => assert!(e.to_string().contains("the shader's text with its macros expands to more than"), "{e}"),
    }
}

/// A function-like macro that repeats its argument, applied in a chain of definitions
/// (`C1 = D(C0)`, …), multiplies inside the preprocessor: refused on paper first.
#[test]
fn repeated_arguments_are_counted_as_often_as_they_repeat() {
    let vs = "attribute vec4 p; void main() { gl_Position = p; }";
    let mut fs = String::from("#define D(x) x+x+x+x\n#define C0 1.0\n");
    for i in 1..=16 {
        fs += &format!("#define C{i} D(C{})\n", i - 1);
    }
    fs += "void main() { gl_FragColor = vec4(C16); }";
    let e = CompiledProgram::new(vs, &fs, &[]).map(|_| ()).unwrap_err();
    assert!(e.to_string().contains("expands to more than"), "{e}");
}

#[test]
fn a_batch_of_vertices_shades_each_as_it_would_alone() {
    // Lanes diverge: a loop whose count and a branch whose side depend on the attribute.
    const VS: &str = "
attribute vec4 position;
varying vec4 v;
void main() {
    float sum = 0.0;
    for (int i = 0; i < 8; i++) {
        if (float(i) >= position.x) break;
        sum += position.y * float(i) + 0.25;
    }
    if (position.z > 0.5) { v = vec4(sum, sqrt(position.z), 1.0, 0.0); }
    else { v = vec4(-sum, position.w * position.w + position.z, 0.0, 1.0); }
    gl_Position = vec4(position.xy * 0.1, sum, 1.0);
}";
    let program = glsl(VS, "precision highp float;\nvarying vec4 v;\nvoid main() { gl_FragColor = v; }");
    let (vs, _) = tiler_glsl::shaders(&program, &program.new_uniform_values(), &[], HEIGHT);
    let inputs: Vec<VertexInput> = (0..11)
        .map(|k| {
            let mut attributes = [Vec4::ZERO; tiler::MAX_VERTEX_ATTRIBUTES];
            attributes[0] = Vec4::new(k as f32 * 0.9, 0.3 - k as f32 * 0.07, (k % 3) as f32 * 0.4, k as f32 * 0.11);
            VertexInput { attributes, vertex_index: k }
        })
        .collect();
    let alone: Vec<VertexOutput> = inputs
        .iter()
        .map(|input| {
            let mut out = VertexOutput::default();
            vs.shade(input, &mut out);
            out
        })
        .collect();
    let bits = |out: &VertexOutput| {
        (out.position.to_array().map(f32::to_bits), <[f32; 4]>::try_from(&out.varyings[..4]).unwrap().map(f32::to_bits))
    };
    // A full batch, a short one, and more than a batch.
    for n in [8, 3, 11] {
        let mut outs = vec![VertexOutput::default(); n];
        vs.shade_batch(&inputs[..n], &mut outs);
        for (k, out) in outs.iter().enumerate() {
            assert_eq!(bits(out), bits(&alone[k]), "vertex {k} of a batch of {n}");
        }
    }
    assert_ne!(bits(&alone[1]).1, bits(&alone[2]).1, "the vertices differ");
}

#[test]
fn es300_inputs_outputs_locations_and_vertex_built_ins() {
    // `in` at a layout location and the lowest free one, `gl_VertexID`, `gl_InstanceID`.
    const VS: &str = "#version 300 es
layout(location = 3) in vec4 placed;
in vec2 free;
out vec4 ids;
out vec2 passed;
void main() {
    ids = vec4(float(gl_VertexID), float(gl_InstanceID), placed.x, placed.w);
    passed = free;
    gl_Position = placed;
}";
    const FS: &str = "#version 300 es
precision highp float;
in vec4 ids;
in vec2 passed;
layout(location = 0) out vec4 color;
uniform sampler2D tex;
void main() { color = ids + texture(tex, passed) + textureLod(tex, passed, 0.0); }";
    let program = Arc::new(CompiledProgram::new(VS, FS, &[]).unwrap());
    assert_eq!(program.attribute_location("placed"), Some(3));
    assert_eq!(program.attribute_location("free"), Some(0));
    let (mut shader, _) = tiler_glsl::shaders(&program, &program.new_uniform_values(), &[], HEIGHT);
    let mut input = VertexInput { attributes: [Vec4::ZERO; tiler::MAX_VERTEX_ATTRIBUTES], vertex_index: 7 };
    input.attributes[3] = Vec4::new(0.5, 0.25, 0.0, 2.0);
    input.attributes[0] = Vec4::new(-1.5, 9.0, 0.0, 1.0);
    let mut out = VertexOutput::default();
    shader.shade(&input, &mut out);
    assert_eq!(&out.varyings[..6], &[7.0, 0.0, 0.5, 2.0, -1.5, 9.0]);
    shader.set_instance(11);
    shader.shade(&input, &mut out);
    assert_eq!(&out.varyings[..2], &[7.0, 11.0]);
    // The built-ins are inputs: writing one is an error.
    let vs_write = "#version 300 es\nin vec4 p;\nvoid main() {\n  gl_InstanceID = 1;\n  gl_Position = p;\n}";
    let e = CompiledProgram::new(vs_write, FS, &[]).unwrap_err();
    assert!(matches!(e, Error::Compile { stage: Stage::Vertex, line: 4, .. }), "{e}");
}

/// `%` on integers (ES 3.00): exact, on vectors component-wise, folded when constant;
/// on floats a compile error that points to `mod()`.
#[test]
fn integer_remainder_is_exact() {
    const VS: &str = "#version 300 es
in vec4 a;
out vec4 r;
void main() {
    int x = int(a.x);
    ivec2 v = ivec2(int(a.y), 23) % ivec2(int(a.z), 6);
    r = vec4(float(x % 5), float(16777213 % 7), float(v.x), float(v.y));
    gl_Position = a;
}";
    const FS: &str = "#version 300 es
precision highp float;
in vec4 r;
out vec4 c;
void main() { c = r; }";
    let out = run_vertex(VS, FS, [17.0, 16777215.0, 65536.0, 1.0], |_, _| {});
    assert_eq!(out, [2.0, 5.0, 65535.0, 5.0]);
    let e = CompiledProgram::new(VS, &FS.replace("c = r;", "c = vec4(r.x % 2.0);"), &[]).unwrap_err();
    assert!(e.to_string().contains("mod()"), "{e}");
}

#[test]
fn es300_features_tiler_lacks_are_compile_errors_naming_the_line() {
    let vs = "#version 300 es\nin vec4 p;\nout vec4 v;\nvoid main() { v = p; gl_Position = p; }";
    let fs = "#version 300 es\nprecision highp float;\nin vec4 v;\nout vec4 c;\nvoid main() { c = v; }";
    CompiledProgram::new(vs, fs, &[]).unwrap();
    let cases = [
        // Integer varyings must be flat (GLSL ES 3.00 §4.3.6).
        (
            Stage::Vertex,
            "#version 300 es\nin vec4 p;\nout vec4 v;\nout uint u;\nvoid main() { v = p; gl_Position = p; }",
            4,
            "flat",
        ),
        (
            Stage::Vertex,
            "#version 300 es\nflat in vec4 p;\nout vec4 v;\nvoid main() { v = p; gl_Position = p; }",
            2,
            "flat",
        ),
        (
            Stage::Fragment,
            "#version 300 es\nprecision highp float;\nout vec2 c;\nvoid main() {\n  c = vec2(1.0);\n}",
            3,
            "vec4",
        ),
    ];
    for (stage, source, line, word) in cases {
        let e = match stage {
            Stage::Vertex => CompiledProgram::new(source, fs, &[]),
            Stage::Fragment => CompiledProgram::new(vs, source, &[]),
        }
        .unwrap_err();
        match &e {
            Error::Compile { stage: s, line: l, message } => {
                assert!(*s == stage && *l == line && message.contains(word), "{e}");
            }
            other => panic!("{other:?}"),
        }
    }
}

/// `flat` varyings, float and integer: a strip of two triangles (three vertices each pass on
/// their index in bits that are a NaN as floats, and as a float), each triangle coloured by
/// its last vertex (GL's provoking vertex); qualifiers that differ between the stages do not link.
#[test]
fn flat_varyings_come_from_the_last_vertex_bit_for_bit() {
    const VS: &str = "#version 300 es
in vec4 a;
flat out uint bits;
flat out float f;
out vec2 uv;
void main() {
    bits = 0xffc01200u + uint(gl_VertexID);
    f = float(gl_VertexID);
    uv = a.xy;
    gl_Position = a;
}";
    const FS: &str = "#version 300 es
precision highp float;
flat in uint bits;
flat in float f;
in vec2 uv;
out vec4 c;
void main() { c = vec4(float(bits - 0xffc01200u) / 255.0, f / 255.0, (bits >> 24) == 255u ? 1.0 : 0.0, 1.0); }";
    let program = glsl(VS, FS);
    let pipeline = tiler_glsl::pipeline(
        &program,
        &program.new_uniform_values(),
        &[],
        HEIGHT,
        PipelineDesc { topology: tiler::Topology::TriangleStrip, ..desc() },
    )
    .unwrap();
    let mut device = Device::new(DeviceConfig::default()).unwrap();
    let color = device.create_image(ImageDesc::new(WIDTH, HEIGHT, Format::Rgba8Unorm)).unwrap();
    // A strip over the screen: triangle 0 (0, 1, 2) on the left, 1 (1, 3, 2) on the right.
    let vertices: [[f32; 4]; 4] =
        [[-1.0, -1.0, 0.0, 1.0], [-1.0, 1.0, 0.0, 1.0], [1.0, -1.0, 0.0, 1.0], [1.0, 1.0, 0.0, 1.0]];
    let buffer = device.create_buffer_from(&vertices).unwrap();
    let mut pass = RenderPass::new(RenderPassDesc {
        color: vec![ColorAttachment::clear_store(color, [0.0; 4])],
        depth_stencil: None,
        render_area: None,
    });
    pass.draw(Draw::new(&pipeline, buffer, 0, 4));
    device.submit(&pass).unwrap();
    let image = device.read_rgba8(color).unwrap();
    let pixel = |x: u32, y: u32| &image[((y * WIDTH + x) * 4) as usize..][..4];
    assert_eq!(pixel(2, HEIGHT / 2), [2, 2, 255, 255], "triangle 0 takes vertex 2");
    assert_eq!(pixel(WIDTH - 3, HEIGHT / 2), [3, 3, 255, 255], "triangle 1 takes vertex 3");
    let smooth_fs = FS.replace("flat in float f", "in float f");
    let e = CompiledProgram::new(VS, &smooth_fs, &[]).unwrap_err();
    assert!(e.to_string().contains("'f' is flat in the vertex shader and smooth"), "{e}");
}

/// A shadow map whose depth is its `s` coordinate, compared `reference ≤ depth`.
#[derive(Debug)]
struct RampShadow;
impl tiler_glsl::TextureSource for RampShadow {
    fn sample(&self, s: f32, _: f32, _: Option<f32>) -> [f32; 4] {
        [s, s, s, 1.0]
    }
    fn sample_compare(&self, s: f32, _: f32, reference: f32, _: Option<f32>) -> f32 {
        tiler::depth_compare::compare(tiler::CompareOp::LessOrEqual, reference, s, true)
    }
}

#[test]
fn shadow_lookups_pass_the_reference_depth() {
    // Every form puts the reference 0.5 (projected: 1.0 / 2.0) against depth s: lit (1) right
    // of the middle, shadowed (0) left of it.
    let forms = [
        ("#version 100\n#extension GL_EXT_shadow_samplers : require\n", "shadow2DEXT(map, vec3(uv, 0.5))"),
        (
            "#version 100\n#extension GL_EXT_shadow_samplers : require\n",
            "shadow2DProjEXT(map, vec4(uv * 2.0, 1.0, 2.0))",
        ),
        ("#version 300 es\n", "texture(map, vec3(uv, 0.5))"),
        ("#version 300 es\n", "textureProj(map, vec4(uv * 2.0, 1.0, 2.0))"),
        ("#version 300 es\n", "textureLod(map, vec3(uv, 0.5), 0.0)"),
    ];
    for (version, lookup) in forms {
        let es3 = version.contains("300");
        let (vs, fs) = if es3 {
            (
                format!(
                    "{version}in vec4 position;\nout vec2 uv;\nvoid main() {{ gl_Position = position; uv = position.xy * 0.5 + 0.5; }}"
                ),
                format!(
                    "{version}precision highp float;\nprecision lowp sampler2DShadow;\nuniform sampler2DShadow map;\nin vec2 uv;\nout vec4 color;\n\
                     void main() {{ float lit = {lookup}; color = vec4(lit, 0.0, 0.0, 1.0); }}"
                ),
            )
        } else {
            (
                format!("{version}{PASS_VS}"),
                format!(
                    "{version}precision highp float;\nuniform sampler2DShadow map;\nvarying vec2 uv;\n\
                     void main() {{ float lit = {lookup}; gl_FragColor = vec4(lit, 0.0, 0.0, 1.0); }}"
                ),
            )
        };
        let program = glsl(&vs, &fs);
        let uniforms = program.new_uniform_values();
        let textures = [Some(TextureBinding::Custom(Arc::new(RampShadow)))];
        let (image, _) = render(&glsl_pipeline(&program, &uniforms, &textures));
        let red = |x: u32| image[((HEIGHT / 2 * WIDTH + x) * 4) as usize];
        for x in 0..WIDTH {
            let s = (x as f32 + 0.5) / WIDTH as f32;
            assert_eq!(red(x), if s >= 0.5 { 255 } else { 0 }, "{lookup} at x {x}");
        }
    }
    // A 2D lookup function on a shadow sampler, and a shadow one on a 2D sampler, are errors.
    let bad = [
        "uniform sampler2DShadow map;\nvoid main() { gl_FragColor = texture2D(map, vec2(0.5)); }",
        "#extension GL_EXT_shadow_samplers : require\nuniform sampler2D map;\nvoid main() { gl_FragColor = vec4(shadow2DEXT(map, vec3(0.5))); }",
        "#extension GL_EXT_shadow_samplers : require\nuniform sampler2DShadow map;\nvoid main() { gl_FragColor = vec4(shadow2DEXT(map, vec2(0.5))); }",
    ];
    for fs in bad {
        let e = CompiledProgram::new(PASS_VS, &format!("precision highp float;\n{fs}"), &[]).err();
        let e = e.unwrap_or_else(|| panic!("compiled: {fs}")).to_string();
        assert!(e.contains("sampler2D") || e.contains("coordinates"), "{e}");
    }
}

#[test]
fn only_the_extensions_the_compiler_has_are_defined() {
    // Qt Quick's fragment shaders on desktop GL start so: glsl-lang's preprocessor predefines a
    // macro for every extension it knows, which would take the branch and fail on the first.
    let guarded = "#ifdef GL_KHR_blend_equation_advanced\n#extension GL_ARB_fragment_coord_conventions : enable\n\
                   #extension GL_KHR_blend_equation_advanced : enable\n#endif\n";
    let fs = |body: &str| format!("{guarded}precision highp float;\nvarying vec2 uv;\nvoid main() {{\n{body}\n}}");
    let program = glsl(PASS_VS, &fs("gl_FragColor = vec4(uv, 0.0, 1.0);"));
    let (image, _) = render(&glsl_pipeline(&program, &program.new_uniform_values(), &[]));
    assert_eq!(image[3], 255, "the shader ran");
    // Defined: those it has; not defined: those it has not.
    let flag = |name: &str| {
        let body = format!("#ifdef {name}\ngl_FragColor = vec4(1.0);\n#else\ngl_FragColor = vec4(0.0);\n#endif");
        let program = glsl(PASS_VS, &fs(&body));
        let (image, _) = render(&glsl_pipeline(&program, &program.new_uniform_values(), &[]));
        image[0] == 255
    };
    assert!(flag("GL_OES_standard_derivatives") && flag("GL_OES_texture_3D") && flag("GL_EXT_shadow_samplers"));
    assert!(
        !flag("GL_KHR_blend_equation_advanced") && !flag("GL_OES_EGL_image_external") && !flag("GL_EXT_frag_depth")
    );
    // Enabling one it has not is a warning in GLSL ES (§3.4), so nothing; requiring it fails,
    // naming it as the shader does.
    let required = format!("#extension GL_OES_EGL_image_external : require\n{}", fs(""));
    let Err(e) = CompiledProgram::new(PASS_VS, &required, &[]) else {
        panic!("requiring a missing extension compiled")
    };
    let e = e.to_string();
    assert!(e.contains("GL_OES_EGL_image_external") && !e.contains("TILER_"), "{e}");
    glsl(PASS_VS, &format!("#extension GL_OES_EGL_image_external : enable\n{}", fs("gl_FragColor = vec4(1.0);")));
}

/// Runs a vertex shader on a batch of vertices (attribute 0 of each; the lanes diverge)
/// and returns each vertex's first four varyings.
fn run_vertex_batch(vs: &str, fs: &str, attributes: &[[f32; 4]]) -> Vec<[f32; 4]> {
    let program = glsl(vs, fs);
    let (shader, _) = tiler_glsl::shaders(&program, &program.new_uniform_values(), &[], HEIGHT);
    let inputs: Vec<VertexInput> = attributes
        .iter()
        .enumerate()
        .map(|(k, a)| {
            let mut attributes = [Vec4::ZERO; tiler::MAX_VERTEX_ATTRIBUTES];
            attributes[0] = Vec4::from_array(*a);
            VertexInput { attributes, vertex_index: k as u32 }
        })
        .collect();
    let mut outs = vec![VertexOutput::default(); inputs.len()];
    shader.shade_batch(&inputs, &mut outs);
    outs.iter().map(|o| <[f32; 4]>::try_from(&o.varyings[..4]).unwrap()).collect()
}

const PASS_FS_300: &str = "#version 300 es
precision highp float;
in vec4 r;
out vec4 c;
void main() { c = r; }";

/// `switch` with a selector that differs per lane: fall-through, `default` in the middle,
/// `break` out of the switch, `continue` through it to the enclosing loop.
#[test]
fn switch_falls_through_and_breaks_per_lane() {
    const VS: &str = "#version 300 es
in vec4 a;
out vec4 r;
void main() {
    int s = int(a.x);
    float acc = 0.0;
    float loops = 0.0;
    for (int i = 0; i < 3; i++) {
        switch (s + i) {
        case 0:
            acc += 1.0;
        case 1:
        case 2:
            acc += 10.0;
            break;
        default:
            acc += 100.0;
        case 5:
            acc += 1000.0;
            if (a.y > 0.5) break;
            acc += 10000.0;
            continue;
        case 3 + 4:
            acc += 100000.0;
        }
        loops += 1.0;
    }
    switch (s) { case 1: loops += 0.5; }
    r = vec4(acc, loops, 0.0, 0.0);
    gl_Position = a;
}";
    fn expect(s: i32, y: f32) -> [f32; 4] {
        let (mut acc, mut loops) = (0.0f32, 0.0f32);
        'each: for i in 0..3 {
            // The index of the label the switch enters at.
            let start = match s + i {
                0 => 0,
                1 | 2 => 1,
                5 => 3,
                7 => 4,
                _ => 2,
            };
            'switch: {
                if start <= 0 {
                    acc += 1.0;
                }
                if start <= 1 {
                    acc += 10.0;
                    break 'switch;
                }
                if start <= 2 {
                    acc += 100.0;
                }
                if start <= 3 {
                    acc += 1000.0;
                    if y > 0.5 {
                        break 'switch;
                    }
                    acc += 10000.0;
                    continue 'each;
                }
                acc += 100000.0;
            }
            loops += 1.0;
        }
        if s == 1 {
            loops += 0.5;
        }
        [acc, loops, 0.0, 0.0]
    }
    let attributes: Vec<[f32; 4]> = (0..22).map(|k| [(k % 11) as f32 - 2.0, (k / 11) as f32, 0.0, 1.0]).collect();
    for n in [8, 22] {
        let got = run_vertex_batch(VS, PASS_FS_300, &attributes[..n]);
        for (k, a) in attributes[..n].iter().enumerate() {
            assert_eq!(got[k], expect(a[0] as i32, a[1]), "vertex {k}: selector {}, y {}", a[0], a[1]);
        }
    }
    // What GLSL forbids, each an error naming its line.
    let body = |b: &str| {
        format!(
            "#version 300 es\nin vec4 a;\nout vec4 r;\nvoid main() {{\n  int s = int(a.x);\n  r = a;\n{b}\n  gl_Position = a;\n}}"
        )
    };
    let cases = [
        ("  switch (s) { case 1: r.x = 1.0; break; case 1: break; }", "twice"),
        ("  switch (a.x) { case 1: break; }", "selector"),
        ("  switch (s) { default: r.x = 1.0; default: break; }", "two default"),
        ("  switch (s) { r.x = 1.0; case 1: break; }", "before the first case"),
        ("  switch (s) { case int(a.y): break; }", "constant"),
        ("  switch (s) { case 1.0: break; }", "constant int"),
        ("  case 1: r.x = 1.0;", "outside a switch"),
        ("  break;", "break outside"),
        ("  switch (s) { case 1: continue; }", "continue outside"),
    ];
    for (code, word) in cases {
        let e = CompiledProgram::new(&body(code), PASS_FS_300, &[]).unwrap_err();
        match &e {
            Error::Compile { stage: Stage::Vertex, line: 7, message } if message.contains(word) => {}
            other => panic!("{code}: {other}"),
        }
    }
}

/// ES 3.00 integers are 32-bit: wrapping arithmetic, truncating division, the defined
/// results of what GLSL leaves undefined (division by zero → 0, shift counts modulo 32),
/// unsigned comparison, bit operations, conversions and bit casts — each lane checked
/// against Rust's integer arithmetic, bit for bit.
#[test]
fn integers_are_exact_32_bit() {
    const VS: &str = "#version 300 es
in vec4 a;
out vec4 r;
out vec4 q;
void main() {
    int x = floatBitsToInt(a.x);
    int y = floatBitsToInt(a.y);
    uint u = floatBitsToUint(a.x);
    uint v = floatBitsToUint(a.y);
    int sum = x + y, diff = x - y, prod = x * y, quot = x / y, rem = x % y;
    uint uq = u / v, ur = u % v;
    int bits = (x & y) ^ (x | 0x0f0) ^ ~y;
    int shifted = (x << (y & 63)) + (x >> 3) + int(u >> 3u);
    int cmp = (x < y ? 1 : 0) + (u < v ? 2 : 0) + (x == y ? 4 : 0) + (u >= v ? 8 : 0);
    ivec2 m = clamp(ivec2(x, y), -100, 100) + abs(ivec2(x, y)) + sign(ivec2(x, y)) + min(ivec2(x), y);
    uvec2 n = max(uvec2(u, v), 7u) ^ uvec2(1u, 2u);
    int z = 0;
    z += x;
    z *= 3;
    z <<= 2;
    z |= 1;
    z--;
    r = vec4(intBitsToFloat(sum ^ diff), intBitsToFloat(prod + quot * 7 + rem), uintBitsToFloat(uq + ur * 3u),
             intBitsToFloat(bits + shifted * 5 + cmp));
    q = vec4(intBitsToFloat(m.x ^ m.y), uintBitsToFloat(n.x + n.y), float(x) + float(u), intBitsToFloat(z + int(a.z)));
    gl_Position = vec4(0.0);
}";
    fn expect(x: i32, y: i32, w: f32) -> [u32; 8] {
        let (u, v) = (x as u32, y as u32);
        let div = |a: i32, b: i32| if b == 0 { 0 } else { a.wrapping_div(b) };
        let rem = |a: i32, b: i32| if b == 0 { 0 } else { a.wrapping_rem(b) };
        let (sum, diff, prod) = (x.wrapping_add(y), x.wrapping_sub(y), x.wrapping_mul(y));
        let (quot, rm) = (div(x, y), rem(x, y));
        let (uq, ur) = (u.checked_div(v).unwrap_or(0), u.checked_rem(v).unwrap_or(0));
        let bits = (x & y) ^ (x | 0x0f0) ^ !y;
        let shifted = x.wrapping_shl((y & 63) as u32).wrapping_add(x >> 3).wrapping_add((u >> 3) as i32);
        let cmp = i32::from(x < y) + 2 * i32::from(u < v) + 4 * i32::from(x == y) + 8 * i32::from(u >= v);
        let m =
            |c: i32| c.clamp(-100, 100).wrapping_add(c.wrapping_abs()).wrapping_add(c.signum()).wrapping_add(x.min(y));
        let (mx, my) = (m(x), m(y));
        let n = (u.max(7) ^ 1).wrapping_add(v.max(7) ^ 2);
        let z = ((x.wrapping_mul(3).wrapping_shl(2)) | 1).wrapping_sub(1);
        [
            (sum ^ diff) as u32,
            prod.wrapping_add(quot.wrapping_mul(7)).wrapping_add(rm) as u32,
            uq.wrapping_add(ur.wrapping_mul(3)),
            bits.wrapping_add(shifted.wrapping_mul(5)).wrapping_add(cmp) as u32,
            (mx ^ my) as u32,
            n,
            (x as f32 + u as f32).to_bits(),
            z.wrapping_add(w as i32) as u32,
        ]
    }
    let pairs: [(i32, i32); 12] = [
        (7, 2),
        (-7, 2),
        (7, -2),
        (i32::MIN, -1),
        (i32::MAX, 1),
        (123_456_789, 0),
        (-5, 33),
        (0x7fff_0000, 0x10001),
        (-1, -1),
        (16_777_217, 3),
        (1, 40),
        (-1_000_000_007, 65_537),
    ];
    let attributes: Vec<[f32; 4]> = pairs
        .iter()
        .enumerate()
        .map(|(k, &(x, y))| [f32::from_bits(x as u32), f32::from_bits(y as u32), k as f32 - 5.0, 1.0])
        .collect();
    let fs = "#version 300 es\nprecision highp float;\nin vec4 r;\nin vec4 q;\nout vec4 c;\nvoid main() { c = r + q; }";
    let program = glsl(VS, fs);
    let (shader, _) = tiler_glsl::shaders(&program, &program.new_uniform_values(), &[], HEIGHT);
    for chunk in [8, 12] {
        let inputs: Vec<VertexInput> = attributes[..chunk]
            .iter()
            .enumerate()
            .map(|(k, a)| {
                let mut attributes = [Vec4::ZERO; tiler::MAX_VERTEX_ATTRIBUTES];
                attributes[0] = Vec4::from_array(*a);
                VertexInput { attributes, vertex_index: k as u32 }
            })
            .collect();
        let mut outs = vec![VertexOutput::default(); chunk];
        shader.shade_batch(&inputs, &mut outs);
        for (k, out) in outs.iter().enumerate() {
            let got: Vec<u32> = out.varyings[..8].iter().map(|x| x.to_bits()).collect();
            let (x, y) = pairs[k];
            assert_eq!(got, expect(x, y, attributes[k][2]), "x {x}, y {y}");
        }
    }
}

/// `uint` literals, uniforms and `switch` on a uint; int uniforms keep the integer.
#[test]
fn uint_uniforms_and_switch() {
    const VS: &str = "#version 300 es
in vec4 a;
uniform uint mode;
uniform int offset;
out vec4 r;
void main() {
    uint k = mode + uint(int(a.x) + offset);
    float f = 0.0;
    switch (k) {
    case 0u: f = 1.0; break;
    case 4000000000u: f = 2.0; break;
    default: f = float(k) / 10.0;
    }
    r = vec4(f, float(mode), float(offset), float(k > 3u));
    gl_Position = a;
}";
    let got = run_vertex(VS, PASS_FS_300, [2.0, 0.0, 0.0, 1.0], |p, u| {
        p.set_uniform(u, p.uniform_location("mode").unwrap(), &[5.0]).unwrap();
        p.set_uniform(u, p.uniform_location("offset").unwrap(), &[-7.0]).unwrap();
    });
    assert_eq!(got, [1.0, 5.0, -7.0, 0.0]);
    let got = run_vertex(VS, PASS_FS_300, [30.0, 0.0, 0.0, 1.0], |p, u| {
        p.set_uniform(u, p.uniform_location("mode").unwrap(), &[5.0]).unwrap();
    });
    assert_eq!(got, [3.5, 5.0, 0.0, 1.0]);
    let e = CompiledProgram::new(&VS.replace("case 0u", "case 0"), PASS_FS_300, &[]).unwrap_err();
    assert!(e.to_string().contains("constant uint"), "{e}");
}

/// `mediump` arithmetic is computed in binary16, `highp` in single precision, and the
/// precision of an operation is that of its operands (a `highp` one wins, constants have
/// none), as Mesa lowers it for llvmpipe — each expected value below is what llvmpipe 22.3
/// computed for the same expression (read back as float bits from a probe shader).
#[test]
fn mediump_arithmetic_is_binary16() {
    const VS: &str = "
precision mediump float;
attribute vec4 a;
varying vec4 r0;
varying vec4 r1;
highp float exact(highp float x, highp float y) { return x + y; }
void main() {
    mediump vec4 m = a;
    highp vec4 h = a;
    mediump float seventh = 1.0 / 7.0;
    mediump float e3 = 3.0 * m.y;
    r0 = vec4(m.x + m.y, h.x + m.y, seventh * m.x, exact(m.x, m.y));
    // dot rounds once; written-out additions round each time.
    mediump vec4 v = vec4(m.x, e3, e3, 0.0);
    // p · (1/7) · (1/7) is reassociated to p · (1/7 · 1/7), as NIR does: 147 → 2.99….
    mediump float p = 146.0 + m.x;
    r1 = vec4(dot(v, vec4(1.0)), (m.x + e3) + e3, floor(p * seventh * seventh), m.z * m.z);
    gl_Position = a;
}";
    const FS: &str = "precision mediump float;
varying vec4 r0; varying vec4 r1;
void main() { gl_FragColor = r0 + r1; }";
    let e = 2f32.powi(-11);
    let got = run_vertex(VS, FS, [1.0, e, 0.1, 1.0], |_, _| {});
    let want = [
        1.0,           // 1 + 2⁻¹¹ is a tie in binary16: even, 1
        1.0 + e,       // a highp operand: single precision
        0.142_822_27,  // 1/7 in binary16
        1.0 + e,       // a highp parameter: single precision
        1.0 + 6.0 * e, // dot: one rounding
        1.0 + 8.0 * e, // two additions: 1 + 3·2⁻¹¹ → 1 + 4·2⁻¹¹ (tie, even), then again
        2.0,           // floor(147 · round16(round16(1/7)²)) = floor(2.998)
        half(half(0.1) * half(0.1)),
    ];
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&got), bits(&want), "got {got:?}\nwant {want:?}");

    // The same source with highp floats computes everything in single precision.
    let highp = VS.replace("precision mediump float;", "precision highp float;").replace("mediump ", "highp ");
    let got = run_vertex(&highp, FS, [1.0, e, 0.1, 1.0], |_, _| {});
    assert_eq!(got[0], 1.0 + e);
    assert_eq!(got[2], 1.0 / 7.0);
    assert_eq!(got[4], 1.0 + 6.0 * e);
    assert_eq!(got[7], 0.1 * 0.1);
}

fn half(x: f32) -> f32 {
    half::f16::from_f32(x).to_f32()
}

const PASS_VS_300: &str = "#version 300 es
in vec4 position;
out vec2 uv;
void main() {
    gl_Position = position;
    uv = position.xy * 0.5 + 0.5;
}";

/// `w × h × d` layers (or slices): texel `(x, y)` of layer `k` is `(16 x, 16 y, 40 k, 255)`.
fn layered_texels(w: u32, h: u32, d: u32) -> Vec<u8> {
    (0..d)
        .flat_map(|k| (0..w * h).flat_map(move |p| [(p % w * 16) as u8, (p / w * 16) as u8, (40 * k) as u8, 255]))
        .collect()
}

#[test]
fn array_and_3d_textures_match_native_with_the_same_traffic() {
    // A sampler2DArray whose layer changes across the window and a sampler3D whose r does,
    // both with derivatives (so mip levels and the minification filter take part), through
    // GLSL ES 3.00's `texture`: the same pixels and texture bytes as a Rust shader calling
    // the core's samplers.
    const FS: &str = "#version 300 es
precision highp float;
uniform highp sampler2DArray layers;
uniform highp sampler3D volume;
in vec2 uv;
out vec4 color;
void main() {
    vec4 a = texture(layers, vec3(uv * 3.0, uv.x * 4.0 - 0.3));
    vec4 b = texture(volume, vec3(uv.yx * 1.5, uv.x * 0.9 + uv.y * 0.2));
    color = a * 0.5 + b * 0.5;
}";
    struct Native {
        array: Arc<Texture>,
        volume: Arc<Texture>,
        sampler: Sampler,
    }
    impl FragmentShader for Native {
        fn shade(&self, frag: &mut Fragments<'_>) {
            let [u, v] = frag.smooth_n::<2>(0);
            let a = frag.sample_array(&self.array, &self.sampler, [u * 3.0, v * 3.0, u * 4.0 - F32x8::splat(0.3)]);
            let r = u * 0.9 + v * 0.2;
            let b = frag.sample_volume(&self.volume, &self.sampler, [v * 1.5, u * 1.5, r]);
            frag.set_color(0, std::array::from_fn(|c| a[c] * 0.5 + b[c] * 0.5));
        }
    }
    let array = Arc::new(
        Texture::array_from_rgba8(16, 8, 4, &layered_texels(16, 8, 4), ColorSpace::Linear, MipChain::Linear).unwrap(),
    );
    let volume = Arc::new(Texture::volume_from_rgba8(8, 8, 6, &layered_texels(8, 8, 6), ColorSpace::Linear).unwrap());
    let sampler = Sampler { wrap_w: tiler::Wrap::MirroredRepeat, ..Sampler::TRILINEAR_REPEAT };
    let program = glsl(PASS_VS_300, FS);
    let mut uniforms = program.new_uniform_values();
    program.set_uniform(&mut uniforms, program.uniform_location("volume").unwrap(), &[1.0]).unwrap();
    let textures =
        [Some(TextureBinding::Core(array.clone(), sampler)), Some(TextureBinding::Core(volume.clone(), sampler))];
    let (a, ra) = render(&glsl_pipeline(&program, &uniforms, &textures));
    let (b, rb) = render(&Pipeline::new(PassVs, Native { array, volume, sampler }, native_desc()).unwrap());
    assert_same(&a, &b, 60);
    assert_eq!(ra.ledger, rb.ledger, "texture traffic differs");
    assert!(ra.ledger.get(Category::TextureFetch) > 0);
    // Several layers show: their blue channels differ.
    let blues: std::collections::BTreeSet<u8> = a.chunks_exact(4).map(|p| p[2] / 8).collect();
    assert!(blues.len() >= 4, "{blues:?}");
}

#[test]
fn vertex_shaders_and_explicit_levels_read_layered_textures() {
    const VS: &str = "#version 300 es
in vec4 position;
uniform highp sampler2DArray layers;
uniform highp sampler3D volume;
out vec4 layer2;
out vec4 level1;
out vec4 slice;
void main() {
    layer2 = texture(layers, vec3(0.3, 0.6, 1.7));
    level1 = textureLod(layers, vec3(0.3, 0.6, 9.0), 1.0);
    slice = textureProj(volume, vec4(0.5, 0.5, 1.25, 2.0));
    gl_Position = position;
}";
    const FS: &str = "#version 300 es\nprecision highp float;\nin vec4 layer2;\nin vec4 level1;\nin vec4 slice;\n\
                      out vec4 c;\nvoid main() { c = layer2 + level1 + slice; }";
    let program = glsl(VS, FS);
    let mut uniforms = program.new_uniform_values();
    program.set_uniform(&mut uniforms, program.uniform_location("volume").unwrap(), &[1.0]).unwrap();
    let array = Arc::new(
        Texture::array_from_rgba8(8, 8, 3, &layered_texels(8, 8, 3), ColorSpace::Linear, MipChain::Box).unwrap(),
    );
    let volume = Arc::new(Texture::volume_from_rgba8(4, 4, 4, &layered_texels(4, 4, 4), ColorSpace::Linear).unwrap());
    let nearest_mip = Sampler { mipmap: tiler::MipmapMode::Nearest, ..Sampler::NEAREST_REPEAT };
    let textures =
        [Some(TextureBinding::Core(array.clone(), nearest_mip)), Some(TextureBinding::Core(volume, nearest_mip))];
    let (vs, _) = tiler_glsl::shaders(&program, &uniforms, &textures, HEIGHT);
    let input = VertexInput { attributes: [Vec4::ONE; tiler::MAX_VERTEX_ATTRIBUTES], vertex_index: 0 };
    let mut out = VertexOutput::default();
    vs.shade(&input, &mut out);
    // Layer round(1.7) = 2, texel (⌊0.3 · 8⌋, ⌊0.6 · 8⌋) = (2, 4), rows in GL's order.
    assert_eq!(&out.varyings[..4], &[32.0 / 255.0, 64.0 / 255.0, 80.0 / 255.0, 1.0]);
    // Layer 9 clamps to 2; level 1 (4×4): texel (1, 2).
    assert_eq!(&out.varyings[4..8], &array.layer_texel(2, 1, 1, 2).map(|c| c as f32 / 255.0));
    // (0.25, 0.25, 0.625): slice ⌊2.5⌋ = 2, texel (1, 1).
    assert_eq!(&out.varyings[8..12], &[16.0 / 255.0, 16.0 / 255.0, 80.0 / 255.0, 1.0]);
}

/// The packing built-ins (ES 3.00 §8.4) to the bit: unorm rounds and clamps, snorm is 16-bit
/// two's complement, half floats are IEEE binary16; unpacking inverts them; a wrong argument
/// type is a compile error naming the function.
#[test]
fn packing_functions_give_the_bits_es_3_00_defines() {
    const VS: &str = "#version 300 es
in vec4 a;
out vec4 r;
void main() {
    r.x = uintBitsToFloat(packUnorm2x16(a.xy));
    r.y = uintBitsToFloat(packSnorm2x16(vec2(a.z, -2.0)));
    r.z = uintBitsToFloat(packHalf2x16(vec2(a.w, -2.5)));
    uint u = floatBitsToUint(r.x);
    r.w = unpackHalf2x16(floatBitsToUint(r.z)).y + unpackSnorm2x16(floatBitsToUint(r.y)).y * 10.0
        + unpackUnorm2x16(u).y * 100.0 + unpackSnorm2x16(floatBitsToUint(r.y)).x * 1000.0;
    gl_Position = a;
}";
    let out = run_vertex(VS, PASS_FS_300, [0.5, 1.5, -0.25, 1.0], |_, _| {});
    assert_eq!(out[0].to_bits(), 0xffff_8000, "round(0.5·65535) = 32768, 1.5 clamps to 65535");
    assert_eq!(out[1].to_bits(), 0x8001_e000, "−0.25 → −8192, −2 clamps to −32767");
    assert_eq!(out[2].to_bits(), 0xc100_3c00, "1.0 and −2.5 as half floats");
    assert_eq!(out[3], -2.5 - 10.0 + 100.0 + (-8192.0f32 / 32767.0) * 1000.0);
    let bad = VS.replace("packUnorm2x16(a.xy)", "packUnorm2x16(a.xyz)");
    let e = CompiledProgram::new(&bad, PASS_FS_300, &[]).unwrap_err();
    assert!(matches!(&e, Error::Compile { line: 5, message, .. } if message.contains("packUnorm2x16(vec3)")), "{e}");
}

/// A function-like macro invoked in another's arguments expands (glsl-lang-pp alone leaves
/// the inner one a call), and an error after the aliases it takes names the application's line.
#[test]
fn nested_macro_invocations_expand_and_errors_keep_their_lines() {
    const VS: &str = "#version 300 es
#define D(x) ((x) * 2.0)
#define F(x, y) (D(x) + (y))
in vec4 a;
out vec4 r;
void main() {
    r = vec4(D(D(a.x)), F(D(a.y), D(D(D(1.0)))), D(F(1.0, D(a.z))), 0.0);
    gl_Position = a;
}";
    let out = run_vertex(VS, PASS_FS_300, [1.5, 0.25, 3.0, 1.0], |_, _| {});
    assert_eq!(out, [6.0, 1.0 + 8.0, 2.0 * (2.0 + 6.0), 0.0]);
    let bad = VS.replace("    gl_Position = a;", "    gl_Position = undeclared;");
    let e = CompiledProgram::new(&bad, PASS_FS_300, &[]).unwrap_err();
    assert!(matches!(&e, Error::Compile { line: 8, .. }), "{e}");
}

/// `determinant` and `inverse` (ES 3.00) on mat2, mat3 and mat4: the inverse times the matrix
/// is the identity within rounding, and the determinants are the hand-computed ones.
#[test]
fn inverse_and_determinant_of_every_square_size() {
    const VS: &str = "#version 300 es
in vec4 a;
out vec4 r;
void main() {
    mat2 m2 = mat2(a.x, 1.0, 2.0, 3.0);
    mat3 m3 = mat3(2.0, 0.0, 1.0, 1.0, a.y, 0.0, 0.0, 1.0, 4.0);
    mat4 m4 = mat4(a.z, 1.0, 0.0, 2.0, 0.0, 3.0, 1.0, 0.0, 1.0, 0.0, 2.0, 1.0, 0.0, 2.0, 0.0, 1.0);
    mat4 e4 = inverse(m4) * m4 - mat4(1.0);
    mat3 e3 = m3 * inverse(m3) - mat3(1.0);
    mat2 e2 = inverse(m2) * m2 - mat2(1.0);
    float err = 0.0;
    for (int i = 0; i < 4; i++) { err = max(err, max(max(abs(e4[i].x), abs(e4[i].y)), max(abs(e4[i].z), abs(e4[i].w)))); }
    for (int i = 0; i < 3; i++) { err = max(err, max(max(abs(e3[i].x), abs(e3[i].y)), abs(e3[i].z))); }
    for (int i = 0; i < 2; i++) { err = max(err, max(abs(e2[i].x), abs(e2[i].y))); }
    r = vec4(determinant(m2), determinant(m3), determinant(m4), err);
    gl_Position = a;
}";
    let out = run_vertex(VS, PASS_FS_300, [4.0, 5.0, 2.0, 1.0], |_, _| {});
    // m2 = [[4, 2], [1, 3]] (rows): 12 − 2. m3 rows [[2, 1, 0], [0, 5, 1], [1, 0, 4]]:
    // 2·20 − 1·(0 − 1) + 0 = 41. m4 (columns (2,1,0,2), (0,3,1,0), (1,0,2,1), (0,2,0,1)): 13 by
    // cofactor expansion.
    assert_eq!(out[..3], [10.0, 41.0, 13.0]);
    assert!(out[3] < 1e-5, "inverse · m differs from the identity by {}", out[3]);
}

/// ES 3.00 array constructors (§5.4.4), of scalars and of structs, in initialisers and
/// expressions; a wrong count or element type is an error naming the line.
#[test]
fn array_constructors_build_arrays_of_scalars_and_structs() {
    const VS: &str = "#version 300 es
in vec4 a;
out vec4 r;
struct Light { vec3 color; float power; };
void main() {
    float w[3] = float[3](1.0, a.x, 3.0);
    Light lights[2] = Light[2](Light(vec3(0.5), 2.0), Light(a.xyz, a.w));
    float s = 0.0;
    for (int i = 0; i < 2; i++) s += lights[i].power * lights[i].color.y;
    r = vec4(w[1] + w[2], s, float[2](4.0, 5.0)[1], lights[1].color.z);
    gl_Position = a;
}";
    let out = run_vertex(VS, PASS_FS_300, [0.25, 0.5, 0.75, 2.0], |_, _| {});
    assert_eq!(out[..4], [0.25 + 3.0, 2.0 * 0.5 + 2.0 * 0.5, 5.0, 0.75]);
    let wrong = VS.replace("float[3](1.0, a.x, 3.0)", "float[3](1.0, a.x)");
    let e = CompiledProgram::new(&wrong, PASS_FS_300, &[]).unwrap_err();
    assert!(e.to_string().contains("line 6") && e.to_string().contains("3 elements, 2 given"), "{e}");
}

/// GLSL ES 3.00's `texelFetch` and `textureSize` on a float (RGBA8) and an integer texture, an
/// integer attribute (`VertexFormat::Int`, as `glVertexAttribIPointer` fetches) passed `flat`,
/// and a `uvec4` output stored as its bits in an RGBA32UI attachment: every pixel holds exactly
/// the integers the rules give (out-of-range fetches read zeros), and the fragment shader's
/// texel reads are counted as texture fetch.
#[test]
fn texel_fetch_texture_size_and_integer_outputs_are_exact() {
    const VS: &str = "#version 300 es
in vec4 position;
in uvec4 code;
flat out uvec4 v_code;
void main() { v_code = code; gl_Position = position; }";
    const FS: &str = "#version 300 es
precision highp float;
precision highp int;
uniform highp sampler2D tex;
uniform highp isampler2D ints;
flat in uvec4 v_code;
layout(location = 0) out uvec4 o;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 s0 = textureSize(tex, 0);
    ivec2 s1 = textureSize(tex, 1);
    ivec2 si = textureSize(ints, 0);
    vec4 t = texelFetch(tex, p, 0);
    ivec4 i = texelFetch(ints, p, 0);
    uint sizes = uint(s0.x | s0.y << 4 | s1.x << 8 | s1.y << 12 | si.x << 16 | si.y << 20 | textureSize(tex, 9).x << 24);
    o = uvec4(uint(t.g * 255.0 + 0.5) | uint(i.x) << 8, uint(i.y), sizes, v_code.x + v_code.w);
}";
    let program = glsl(VS, FS);
    let mut uniforms = program.new_uniform_values();
    let (tw, th) = (5u32, 3u32);
    // GL texel i = y·w + x holds green i·13 + 7; a core texture's rows run the other way (its
    // v runs down), so its row r is GL's row h − 1 − r, as the GL context uploads it.
    let rgba: Vec<u8> = (0..th)
        .rev()
        .flat_map(|gl_y| (0..tw).map(move |x| gl_y * tw + x))
        .flat_map(|i| [0, (i * 13 + 7) as u8, 0, 255])
        .collect();
    let tex = Texture::from_rgba8(tw, th, &rgba, ColorSpace::Linear, MipChain::Box).unwrap();
    let int_format = tiler::IntFormat { channels: 2, bits: 16, signed: true };
    let (iw, ih) = (7u32, 2u32);
    let texels: Vec<u8> = (0..iw * ih)
        .flat_map(|i| [(i as i16 * 3 - 10).to_le_bytes(), (-(i as i16) * 1000).to_le_bytes()].concat())
        .collect();
    let ints = tiler::IntegerTexture::new(int_format, tiler::IntegerKind::Flat, iw, ih, &[&texels]).unwrap();
    for (name, unit) in [("tex", 0.0), ("ints", 1.0)] {
        program.set_uniform(&mut uniforms, program.uniform_location(name).unwrap(), &[unit]).unwrap();
    }
    let textures = [
        Some(TextureBinding::Core(Arc::new(tex), Sampler::NEAREST_REPEAT)),
        Some(TextureBinding::Integer(Arc::new(ints), Sampler::NEAREST_REPEAT)),
    ];
    let code_format = tiler::IntFormat { channels: 4, bits: 16, signed: false };
    let input = VertexInputState::interleaved(&[VertexFormat::Float32x4, VertexFormat::Int(code_format)]);
    let desc = PipelineDesc::new("integer", input);
    let pipeline = tiler_glsl::pipeline(&program, &uniforms, &textures, HEIGHT, desc).unwrap();
    let mut device = Device::new(DeviceConfig::default()).unwrap();
    let format = Format::Int(tiler::IntFormat { channels: 4, bits: 32, signed: false });
    let color = device.create_image(ImageDesc::new(WIDTH, HEIGHT, format)).unwrap();
    let mut vertices = Vec::new();
    for p in [[-1.0f32, -1.0, 0.25, 1.0], [3.0, -1.0, 0.25, 1.0], [-1.0, 3.0, 0.25, 1.0]] {
        vertices.extend(p.iter().flat_map(|c| c.to_le_bytes()));
        // The provoking (last) vertex's code reaches every pixel: 40000 + 60000 (a sum past
        // 16 bits, so the attribute was not narrowed).
        vertices.extend([40000u16, 1, 2, 60000].iter().flat_map(|c| c.to_le_bytes()));
    }
    let buffer = device.create_buffer(&vertices).unwrap();
    let clear = [7u32, 0, 0, 0].map(f32::from_bits);
    let mut pass = RenderPass::new(RenderPassDesc {
        color: vec![ColorAttachment::clear_store(color, clear)],
        depth_stencil: None,
        render_area: None,
    });
    pass.draw(Draw::new(&pipeline, buffer, 0, 3));
    let report = device.submit(&pass).unwrap();
    let data = device.image_data(color).unwrap();
    let sizes = 5 | 3 << 4 | 2 << 8 | 1 << 12 | 7 << 16 | 2 << 20;
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let at = ((y * WIDTH + x) * 16) as usize;
            let got: [u32; 4] =
                std::array::from_fn(|c| u32::from_le_bytes(data[at + 4 * c..at + 4 * c + 4].try_into().unwrap()));
            // GL's row y is tiler's row HEIGHT − 1 − y; texel rows are GL's.
            let gl_y = HEIGHT - 1 - y;
            let green = if x < tw && gl_y < th { (gl_y * tw + x) * 13 + 7 } else { 0 };
            let (ix, iy) = if x < iw && gl_y < ih {
                let i = (gl_y * iw + x) as i32;
                (i * 3 - 10, -i * 1000)
            } else {
                (0, 0)
            };
            let want = [(green & 0xff) | (ix as u32) << 8, iy as u32, sizes, 100_000];
            assert_eq!(got, want, "pixel ({x}, {y})");
        }
    }
    assert!(report.ledger.get(Category::TextureFetch) > 0, "texel fetches are counted");
}

/// `texelFetch`/`textureSize` where GLSL ES 3.00 has no such form, or with arguments of the
/// wrong type, are compile errors naming the line; `textureSize` of every sampler type links.
#[test]
fn texel_fetch_misuse_is_a_compile_error_naming_the_line() {
    let vs = "#version 300 es\nin vec4 p;\nvoid main() { gl_Position = p; }";
    let all = "#version 300 es\nprecision highp float;\nuniform sampler2D a;\nuniform samplerCube b;\n\
               uniform highp sampler2DShadow c;\nuniform highp sampler2DArray d;\nuniform highp sampler3D e;\n\
               uniform highp isampler2D f;\nuniform highp usampler2DArray g;\nuniform highp isampler3D h;\n\
               out vec4 o;\nvoid main() {\n  ivec2 s = textureSize(a, 0) + textureSize(b, 0) + textureSize(c, 0) \
               + textureSize(f, 0);\n  ivec3 t = textureSize(d, 0) + textureSize(e, 0) + textureSize(g, 0) + \
               textureSize(h, 0);\n  o = vec4(s.xyxy) + vec4(t.xyzx) + texelFetch(d, t, 1) + texelFetch(e, t, 0) + \
               vec4(texelFetch(g, t, 0)) + vec4(texture(f, vec2(0.5)));\n}";
    CompiledProgram::new(vs, all, &[]).unwrap_or_else(|e| panic!("{e}"));
    let cases = [
        ("uniform samplerCube s;", "texelFetch(s, ivec2(0), 0)", "no texelFetch"),
        ("uniform sampler2D s;", "texelFetch(s, vec2(0.0), 0)", "ivec2"),
        ("uniform highp sampler2DArray s;", "texelFetch(s, ivec2(0), 0)", "ivec3"),
        ("uniform sampler2D s;", "vec4(textureSize(s, 0.0), 0.0, 0.0)", "int"),
    ];
    for (uniform, call, word) in cases {
        let fs = format!(
            "#version 300 es\nprecision highp float;\n{uniform}\nout vec4 o;\nvoid main() {{\n  o = {call};\n}}"
        );
        match CompiledProgram::new(vs, &fs, &[]).unwrap_err() {
            Error::Compile { stage: Stage::Fragment, line: 6, message } => assert!(message.contains(word), "{message}"),
            other => panic!("{call}: {other:?}"),
        }
    }
}

/// `textureGrad` with the derivatives the quad would give reads what `texture` reads, bit for
/// bit and fetch for fetch (both through the core sampler and its cache model); larger
/// derivatives read a smaller level; `textureOffset` reads what `texture` reads one texel-
/// step over, through the cache model too.
#[test]
fn texture_grad_and_offset_go_through_the_core_sampler() {
    const FS: &str = "#version 300 es
precision highp float;
uniform highp sampler2D tex;
uniform int mode;
in vec2 uv;
out vec4 color;
void main() {
    vec2 p = uv * 1.5;
    if (mode == 0) color = texture(tex, p);
    else if (mode == 1) color = textureGrad(tex, p, dFdx(p), dFdy(p));
    else if (mode == 2) color = textureGrad(tex, p, 4.0 * dFdx(p), dFdy(p));
    else color = textureOffset(tex, p, ivec2(3, -2));
}";
    const VS: &str = "#version 300 es
in vec4 position;
out vec2 uv;
void main() { gl_Position = position; uv = position.xy * 0.5 + 0.5; }";
    let program = glsl(VS, FS);
    let texture = Arc::new(
        Texture::from_rgba8(16, 8, &checker_texture().level_texels(0).concat(), ColorSpace::Linear, MipChain::Box)
            .unwrap(),
    );
    let sampler = Sampler { wrap_u: tiler::Wrap::Repeat, wrap_v: tiler::Wrap::Repeat, ..Sampler::TRILINEAR_REPEAT };
    let textures = [Some(TextureBinding::Core(texture.clone(), sampler))];
    let draw = |mode: f32| {
        let mut uniforms = program.new_uniform_values();
        program.set_uniform(&mut uniforms, program.uniform_location("mode").unwrap(), &[mode]).unwrap();
        render(&glsl_pipeline(&program, &uniforms, &textures))
    };
    let (plain, plain_report) = draw(0.0);
    let (grad, grad_report) = draw(1.0);
    assert_same(&grad, &plain, 20);
    assert_eq!(grad_report.ledger, plain_report.ledger, "texture traffic differs");
    assert!(plain_report.ledger.get(Category::TextureFetch) > 0);
    let (minified, _) = draw(2.0);
    assert_ne!(minified, plain, "four times the x derivative reads a smaller level");

    // The offset against a native shader sampling through `Lookup` (GL's t up is the core's
    // v down: the offset's y changes sign).
    struct Native {
        texture: Arc<Texture>,
        sampler: Sampler,
    }
    impl FragmentShader for Native {
        fn shade(&self, frag: &mut Fragments<'_>) {
            let [u, v] = frag.smooth_n::<2>(0);
            let (s, t) = (u * 1.5, v * 1.5);
            let lookup = tiler::Lookup { gradients: None, offset: [3, 2] };
            let texel = frag.sample_with(&self.texture, &self.sampler, [s, F32x8::ONE - t], &lookup);
            frag.set_color(0, texel);
        }
    }
    let (offset, offset_report) = draw(3.0);
    let native = Native { texture, sampler };
    let (b, rb) = render(&Pipeline::new(PassVs, native, native_desc()).unwrap());
    assert_same(&offset, &b, 20);
    assert_eq!(offset_report.ledger, rb.ledger, "texture traffic differs");
    assert_ne!(offset, plain);
}

/// `textureLodOffset` in a vertex shader: the offset is added to the texel indices on the
/// level read and then wrapped (repeat) or clamped (clamp-to-edge), GL ES 3.0 §3.8.10;
/// `textureProjOffset` divides first; bad offsets and unsupported samplers are compile errors
/// naming the function.
#[test]
fn texel_offsets_wrap_after_they_are_added() {
    const VS: &str = "#version 300 es
in vec4 position;
uniform highp sampler2D tex;
out vec4 a;
out vec4 b;
void main() {
    // Texel (3, 2)'s centre of the 16×8 checker.
    a = textureLodOffset(tex, vec2(3.5 / 16.0, 2.5 / 8.0), 0.0, ivec2(-5, 7));
    b = textureProjOffset(tex, vec3(7.0 / 16.0, 5.0 / 8.0, 2.0), ivec2(1, -1));
    gl_Position = position;
}";
    const FS: &str = "#version 300 es\nprecision highp float;\nin vec4 a;\nin vec4 b;\nout vec4 c;\n\
                      void main() { c = a + b; }";
    let program = glsl(VS, FS);
    let uniforms = program.new_uniform_values();
    let texture = checker_texture();
    // A byte reads as `c · fl(1/255)` (llvmpipe's conversion, see `shade/texture.rs`).
    let texel = |x: u32, y: u32| texture.texel(0, x, y).map(|c| c as f32 * (1.0 / 255.0));
    // `texel` takes the core's rows (top down): GL's row 2 of 8 is row 5, and a t offset of
    // +7 is −7 rows: row −2, which repeats to 6 and clamps to 0.
    for (wrap, a) in [(tiler::Wrap::Repeat, texel(14, 6)), (tiler::Wrap::ClampToEdge, texel(0, 0))] {
        let sampler = Sampler { wrap_u: wrap, wrap_v: wrap, ..Sampler::NEAREST_REPEAT };
        let textures = [Some(TextureBinding::Core(texture.clone(), sampler))];
        let (vs, _) = tiler_glsl::shaders(&program, &uniforms, &textures, HEIGHT);
        let input = VertexInput { attributes: [Vec4::ONE; tiler::MAX_VERTEX_ATTRIBUTES], vertex_index: 0 };
        let mut out = VertexOutput::default();
        vs.shade(&input, &mut out);
        assert_eq!(&out.varyings[..4], &a, "{wrap:?}");
        // (7/32, 5/16) is texel (3, 2) (core row 5); offset (1, −1): GL's (4, 1), core row 6.
        assert_eq!(&out.varyings[4..8], &texel(4, 6), "{wrap:?}");
    }
    for (call, wanted) in [
        ("textureOffset(tex, uv, ivec2(8, 0))", "offset 8 is outside [-8, 7]"),
        ("textureOffset(tex, uv, ivec2(int(uv.x), 0))", "constant expression"),
        ("textureOffset(tex, uv, vec2(1.0))", "must be an ivec2"),
        ("textureGrad(tex, uv, uv)", "takes 4 arguments"),
        ("textureGrad(cube, vec3(uv, 1.0), vec3(0.0), vec3(0.0))", "samplerCube is not supported"),
        ("textureGrad(tex, uv, vec3(0.0), uv)", "dPdx cannot be a vec3"),
    ] {
        let fs = format!(
            "#version 300 es\nprecision highp float;\nuniform sampler2D tex;\nuniform samplerCube cube;\nin vec2 uv;\n\
             out vec4 c;\nvoid main() {{\n c = {call};\n}}"
        );
        let vs = "#version 300 es\nin vec4 p;\nout vec2 uv;\nvoid main() { gl_Position = p; uv = p.xy; }";
        let error = CompiledProgram::new(vs, &fs, &[]).unwrap_err().to_string();
        assert!(error.contains(wanted) && error.contains("line 8"), "{call}: {error}");
    }
}

/// Non-square matrices (ES 3.00 §4.1.6, §5.4.2, §5.9): constructors from components, from
/// a larger or smaller matrix and a scalar's diagonal; columns and components by index;
/// matrix × vector, vector × matrix and matrix × matrix with their shapes; `transpose`,
/// `outerProduct`, `matrixCompMult`; a uniform `mat2x3`; shape mismatches are errors naming
/// the line.
#[test]
fn non_square_matrices_have_their_shapes() {
    const VS: &str = "#version 300 es
in vec4 a;
uniform mat2x3 u;
out vec3 r0; out vec2 r1; out vec4 r2; out vec3 r3; out vec2 r4; out float r5; out vec3 r6; out vec4 r7;
void main() {
    mat2x3 m = mat2x3(1.0, 2.0, 3.0, 4.0, 5.0, 6.0);
    r0 = m * vec2(1.0, 10.0);
    r1 = vec3(1.0, 10.0, 100.0) * m;
    mat3x2 t = transpose(m);
    mat2 p = t * m;
    r2 = vec4(p[0], p[1]);
    r3 = u[1];
    mat4x2 o = outerProduct(vec2(1.0, 2.0), vec4(1.0, 2.0, 3.0, 4.0));
    r4 = o[3] + matrixCompMult(o, o)[2];
    r5 = m[1][2] + (m * 2.0)[0][1] - mat3x2(m)[1][1];
    mat3 big = mat3(m);
    r6 = big[2] + mat2x3(vec4(1.0, 2.0, 3.0, 4.0), 5.0, 6.0)[1];
    mat4x3 d = mat4x3(2.0);
    r7 = vec4(d[0].x, d[1].y, d[3].z, d[3].x) - vec4(t[2], 0.0, 0.0);
    gl_Position = a;
}";
    const FS: &str = "#version 300 es
precision highp float;
in vec3 r0; in vec2 r1; in vec4 r2; in vec3 r3; in vec2 r4; in float r5; in vec3 r6; in vec4 r7;
out vec4 c;
void main() { c = vec4(r0 + r3 + r6, r5) + vec4(r1, r4) + r2 + r7; }";
    let u: [f32; 6] = [0.5, 1.0, 1.5, 2.0, 2.5, 3.0];
    let got = run_vertex(VS, FS, [0.0; 4], |p, uniforms| {
        p.set_uniform(uniforms, p.uniform_location("u").unwrap(), &u).unwrap();
    });
    #[rustfmt::skip]
    let want = [
        41.0, 52.0, 63.0, // m · (1, 10)
        321.0, 654.0, // (1, 10, 100) · m
        14.0, 32.0, 32.0, 77.0, // transpose(m) · m
        2.0, 2.5, 3.0, // u[1]
        13.0, 44.0, // o[3] + (o ∘ o)[2]
        5.0, // 6 + 4 − 5
        4.0, 5.0, 7.0, // mat3(m)[2] + (4, 5, 6)
        -1.0, -4.0, 0.0, 0.0, // (2, 2, 0, 0) − (3, 6, 0, 0)
    ];
    assert_eq!(got, want);
    for (line, wanted) in [
        ("vec3 x = mat2x3(1.0) * vec3(1.0);", "mat2x3 * vec3: the shapes do not match"),
        ("mat2x3 x = mat2x3(1.0) * mat2x3(1.0);", "mat2x3 * mat2x3: the shapes do not match"),
        ("float x = determinant(mat3x2(1.0));", "square matrix"),
        ("mat2x3 x = mat3x2(1.0);", "mat2x3"),
        ("vec2 x = mat4x2(1.0, 2.0)[0];", "too few components for mat4x2"),
    ] {
        let vs = format!("#version 300 es\nin vec4 a;\nvoid main() {{\n  gl_Position = a;\n  {line}\n}}");
        let error = CompiledProgram::new(&vs, FS, &[]).unwrap_err().to_string();
        assert!(error.contains(wanted) && error.contains("line 5"), "{line}: {error}");
    }
}

#[test]
fn mix_with_a_boolean_selects_per_component() {
    // GLSL ES 3.00 §8.3: mix(x, y, bvec) takes y where the bool is true, x where it is false
    // (video players' debanding shaders use it); x and y must have the bools' shape.
    const VS: &str = "#version 300 es
in vec4 a;
out vec4 r;
void main() {
    bvec4 pick = greaterThan(a, vec4(0.5));
    r = mix(vec4(10.0, 20.0, 30.0, 40.0), a, pick) + vec4(mix(1.0, 2.0, a.x > 0.0), 0.0, 0.0, 0.0);
    gl_Position = a;
}";
    const FS: &str = "#version 300 es
precision highp float;
in vec4 r;
out vec4 color;
void main() { color = r; }";
    let got = run_vertex(VS, FS, [0.7, 0.2, 0.9, -1.0], |_, _| {});
    assert_eq!(got, [0.7 + 2.0, 20.0, 0.9, 40.0]);
    let Err(error) = CompiledProgram::new(&VS.replace("pick)", "pick.xy)"), FS, &[]) else {
        panic!("mix of vec4 with a bvec2 compiled");
    };
    assert!(error.to_string().contains("mix(vec4, vec4, bvec2)"), "{error}");
}

/// GLSL ES 3.00 §4.3.4: a structure of float-based members may be a varying; an integer
/// member needs it `flat`; a program may pass 64 varying floats (ES 3.0's 60 at least), not 65.
#[test]
fn structure_varyings_and_the_varying_limit() {
    let program = |vs_decl: &str, fs_decl: &str, write: &str| {
        let vs = format!(
            "#version 300 es\nstruct S {{ vec4 a; float b; }};\n{vs_decl}\nin vec4 p;\nvoid main() {{ {write} gl_Position = p; }}\n"
        );
        let fs = format!(
            "#version 300 es\nprecision highp float;\nstruct S {{ vec4 a; float b; }};\n{fs_decl}\nout vec4 c;\nvoid main() {{ c = vec4(0.0); }}\n"
        );
        CompiledProgram::new(&vs, &fs, &[])
    };
    program("out S s;", "in S s;", "s.a = p; s.b = 1.0;").unwrap();
    let e = program("struct T { int i; };\nout T t;", "struct T { int i; };\nin T t;", "").unwrap_err();
    assert!(e.to_string().contains("integer member 'i' (int) needs the varying qualified 'flat'"), "{e}");
    program("struct T { int i; };\nflat out T t;", "struct T { int i; };\nflat in T t;", "t.i = 1;").unwrap();
    let e = program("out S s;", "in S s;\nin S u;", "").unwrap_err();
    assert!(e.to_string().contains("'u' is read by the fragment shader but not declared"), "{e}");
    // 64 floats pass, 65 do not.
    program("out vec4 v[16];", "in vec4 v[16];", "").unwrap();
    let e = program("out vec4 v[16];\nout float w;", "in vec4 v[16];\nin float w;", "").unwrap_err();
    assert!(e.to_string().contains("65 varying floats, at most 64"), "{e}");
}
