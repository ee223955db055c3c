//! GLSL ES programs in the context: the built-in programs rewritten in GLSL draw the same
//! pictures on every backend, traces carry GLSL, errors say where, textures (rendered, depth)
//! are sampled, and a discarding shader changes HSR as on hardware.

use glam::{Mat3, Mat4, Vec3};
use tiler::Backend;
use tiler_gl::*;

use crate::common::*;

const BACKENDS: [Backend; 3] = [Backend::Tbr, Backend::Tbdr, Backend::Imr];

const SOLID_VS: &str = "attribute vec4 position;
uniform mat4 mvp;
void main() { gl_Position = mvp * position; }";
const SOLID_FS: &str = "precision highp float;
uniform vec4 color;
void main() { gl_FragColor = color; }";

const VERTEX_COLOR_VS: &str = "attribute vec4 position;
attribute vec4 color;
uniform mat4 mvp;
varying vec4 v_color;
void main() { v_color = color; gl_Position = mvp * position; }";
const VERTEX_COLOR_FS: &str = "precision highp float;
uniform float alpha_cutoff;
varying vec4 v_color;
void main() {
    if (v_color.a < alpha_cutoff) discard;
    gl_FragColor = v_color;
}";

/// GLSL ES 1.00 has no `inverse`, so the normal matrix (the built-in computes it from
/// `model`) and the normalised light direction are uniforms.
const LAMBERT_VS: &str = "attribute vec4 position;
attribute vec3 normal;
uniform mat4 mvp;
uniform mat3 normal_matrix;
varying vec3 v_normal;
void main() { v_normal = normal_matrix * normal; gl_Position = mvp * position; }";
const LAMBERT_FS: &str = "precision highp float;
uniform vec4 color;
uniform vec3 light;
varying vec3 v_normal;
void main() {
    vec3 n = normalize(v_normal);
    float lit = 0.2 + max(dot(n, light), 0.0) * 0.8;
    gl_FragColor = vec4(lit * color.r, lit * color.g, lit * color.b, color.a);
}";

const TEXTURED_VS: &str = "attribute vec4 position;
attribute vec2 texcoord;
uniform mat4 mvp;
varying vec2 v_uv;
void main() { v_uv = texcoord; gl_Position = mvp * position; }";
const TEXTURED_FS: &str = "precision highp float;
precision highp sampler2D;
uniform sampler2D tex;
uniform vec4 color;
uniform float alpha_cutoff;
varying vec2 v_uv;
void main() {
    vec4 c = texture2D(tex, v_uv) * color;
    if (c.a < alpha_cutoff) discard;
    gl_FragColor = c;
}";

fn glsl(vertex: &str, fragment: &str) -> ProgramSource {
    ProgramSource::Glsl(GlslSource { vertex: vertex.into(), fragment: fragment.into() })
}

fn uniform(gl: &mut Context, name: &str, value: UniformValue) {
    c(gl, Call::Uniform { name: name.into(), value });
}

fn config_on(backend: Backend) -> ContextConfig {
    ContextConfig { backend, tile_width: 16, tile_height: 16, ..config(48, 40) }
}

/// A perspective view of a rotated model: enough arithmetic that a different order of
/// operations would show.
fn matrices() -> (Mat4, Mat4) {
    let model = Mat4::from_rotation_y(0.7) * Mat4::from_rotation_x(-0.4) * Mat4::from_scale(Vec3::new(1.2, 0.9, 1.1));
    let view = Mat4::from_translation(Vec3::new(0.1, -0.05, -3.0));
    // GL's perspective projection: 0.9 rad vertical field of view, near 0.5, far 10.
    let (f, aspect, near, far) = (1.0 / (0.45f32).tan(), 48.0 / 40.0, 0.5, 10.0);
    let projection = Mat4::from_cols_array(&[
        f / aspect,
        0.0,
        0.0,
        0.0,
        0.0,
        f,
        0.0,
        0.0,
        0.0,
        0.0,
        (far + near) / (near - far),
        -1.0,
        0.0,
        0.0,
        2.0 * far * near / (near - far),
        0.0,
    ]);
    (projection * view * model, model)
}

/// Six triangles of a cube-ish fan: positions (xyz) and a second attribute (4 floats:
/// colour, normal + 0, or texture coordinates + 0, 0).
fn mesh() -> (Vec<[f32; 3]>, Vec<[f32; 4]>) {
    let mut positions = Vec::new();
    let mut second = Vec::new();
    let corners = [[-1.0f32, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
    for (face, z) in [(0, 1.0f32), (1, -1.0)] {
        for tri in [[0, 1, 2], [0, 2, 3]] {
            for &k in &tri {
                let [x, y] = corners[k];
                positions.push([x, y * 0.8, z * (0.6 + 0.3 * x)]);
                let f = face as f32;
                second.push([0.5 + 0.5 * x, 0.5 + 0.5 * y, 0.3 + 0.6 * f, if k == 1 { 0.2 } else { 0.9 }]);
            }
        }
    }
    (positions, second)
}

/// Which program a scene draws with.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Solid,
    VertexColor,
    Lambert,
    Textured,
}

/// Draws the mesh with the built-in `kind` or its GLSL version, and returns the picture.
fn draw_scene(backend: Backend, kind: Kind, use_glsl: bool) -> Vec<u8> {
    let mut gl = Context::new(config_on(backend)).unwrap();
    let (positions, second) = mesh();
    let (mvp, model) = matrices();
    c(&mut gl, Call::CreateBuffer { id: 1, data: Bytes::from_slice(&positions) });
    c(&mut gl, Call::CreateBuffer { id: 2, data: Bytes::from_slice(&second) });
    let texels: Vec<u8> =
        (0..8 * 8).flat_map(|i| [(i * 37 % 256) as u8, (i * 11) as u8, 200, (i * 29 % 256) as u8]).collect();
    c(
        &mut gl,
        Call::CreateTexture {
            id: 1,
            width: 8,
            height: 8,
            format: TextureFormat::Rgba8,
            data: Some(Bytes::from(texels)),
            transient: false,
        },
    );
    c(
        &mut gl,
        Call::TexParameters { id: 1, filter: Filter::Linear, wrap: Wrap::Repeat, mag_filter: None, wrap_t: None },
    );
    c(&mut gl, Call::BindTexture { unit: 2, texture: 1 });
    let (builtin, vs, fs, second_name) = match kind {
        Kind::Solid => (ProgramKind::Solid, SOLID_VS, SOLID_FS, None),
        Kind::VertexColor => (ProgramKind::VertexColor, VERTEX_COLOR_VS, VERTEX_COLOR_FS, Some("color")),
        Kind::Lambert => (ProgramKind::Lambert, LAMBERT_VS, LAMBERT_FS, Some("normal")),
        Kind::Textured => (ProgramKind::Textured, TEXTURED_VS, TEXTURED_FS, Some("texcoord")),
    };
    let program = if use_glsl { glsl(vs, fs) } else { builtin.into() };
    c(&mut gl, Call::CreateProgram { id: 1, program });
    if use_glsl {
        // The built-ins read position at 0 and the second attribute at 1.
        c(&mut gl, Call::BindAttribLocation { program: 1, index: 0, name: "position".into() });
        if let Some(name) = second_name {
            c(&mut gl, Call::BindAttribLocation { program: 1, index: 1, name: name.into() });
        }
    }
    c(&mut gl, Call::UseProgram { id: 1 });
    let attrib = |index, buffer, size| Call::VertexAttribPointer {
        index,
        buffer,
        size,
        component: ComponentType::Float,
        normalized: false,
        stride: if index == 0 { 12 } else { 16 },
        offset: 0,
    };
    c(&mut gl, attrib(0, 1, 3));
    c(&mut gl, Call::EnableVertexAttrib { index: 0 });
    let second_size = match kind {
        Kind::Lambert => 3,
        Kind::Textured => 2,
        _ => 4,
    };
    c(&mut gl, attrib(1, 2, second_size));
    c(&mut gl, Call::EnableVertexAttrib { index: 1 });
    uniform(&mut gl, "mvp", UniformValue::Mat4(mvp.to_cols_array()));
    if kind != Kind::VertexColor {
        uniform(&mut gl, "color", UniformValue::Vec4([0.9, 0.7, 0.5, 0.8]));
    }
    if matches!(kind, Kind::VertexColor | Kind::Textured) {
        uniform(&mut gl, "alpha_cutoff", UniformValue::Float(0.5));
    }
    let light = [0.3f32, 0.5, 0.8];
    match (kind, use_glsl) {
        (Kind::Lambert, false) => {
            uniform(&mut gl, "model", UniformValue::Mat4(model.to_cols_array()));
            uniform(&mut gl, "light_dir", UniformValue::Vec3(light));
        }
        (Kind::Lambert, true) => {
            // As the built-in computes them.
            let normal_matrix = Mat3::from_mat4(model).inverse().transpose();
            uniform(&mut gl, "normal_matrix", UniformValue::Mat3(normal_matrix.to_cols_array()));
            uniform(&mut gl, "light", UniformValue::Vec3(Vec3::from_array(light).normalize().to_array()));
        }
        (Kind::Textured, false) => uniform(&mut gl, "sampler", UniformValue::Int(2)),
        (Kind::Textured, true) => uniform(&mut gl, "tex", UniformValue::Int(2)),
        _ => {}
    }
    c(&mut gl, Call::Enable { cap: Capability::DepthTest });
    c(&mut gl, Call::ClearColor { rgba: [0.1, 0.2, 0.3, 1.0] });
    clear_all(&mut gl);
    draw(&mut gl, positions.len() as u32);
    swap(&mut gl);
    gl.end().unwrap();
    gl.surface_rgba8()
}

/// The largest difference of any channel.
fn max_difference(a: &[u8], b: &[u8]) -> u8 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(x, y)| x.abs_diff(*y)).max().unwrap_or(0)
}

/// The GLSL versions do the same arithmetic in the same order as the built-ins (`mvp *
/// position` and `normal_matrix * normal` expand as glam's column sums, `normalize` and `dot`
/// as tiler's `normalize3` and `dot3`, the texture goes through the same core sampler), so
/// the pictures are equal bit for bit on every backend. They declare `highp` floats and
/// samplers, as the built-ins compute in single precision (a `mediump` operation is computed
/// in binary16). The `composite` built-in reads an input attachment, which GLSL ES 1.00
/// cannot express.
#[test]
fn builtin_programs_in_glsl_draw_the_same_pictures() {
    for backend in BACKENDS {
        for kind in [Kind::Solid, Kind::VertexColor, Kind::Lambert, Kind::Textured] {
            let builtin = draw_scene(backend, kind, false);
            let glsl = draw_scene(backend, kind, true);
            let background = [25u8, 51, 76, 255];
            let covered = builtin.chunks(4).filter(|p| *p != background).count();
            assert!(covered > 200, "{backend:?} {kind:?}: the mesh covers {covered} pixels");
            assert!(builtin == glsl, "{backend:?} {kind:?}: differ by up to {}", max_difference(&builtin, &glsl));
        }
    }
}

/// Every backend draws the same GLSL pictures.
#[test]
fn glsl_pictures_are_the_same_on_every_backend() {
    for kind in [Kind::Lambert, Kind::Textured] {
        let pictures: Vec<_> = BACKENDS.iter().map(|b| draw_scene(*b, kind, true)).collect();
        assert!(pictures.windows(2).all(|w| w[0] == w[1]), "{kind:?}: the backends disagree");
    }
}

const TRACE: &str = r#"{
  "format": "tiler-gl-trace",
  "version": 1,
  "config": { "width": 16, "height": 16, "threads": 1 },
  "frames": [ { "calls": [
    { "call": "create_buffer", "id": 1, "data": { "f32": [-1, -1, 3, -1, -1, 3] } },
    { "call": "create_program", "id": 1, "program": { "glsl": {
        "vertex": "attribute vec2 p;\nvoid main() { gl_Position = vec4(p, 0.0, 1.0); }",
        "fragment": "precision mediump float;\nuniform vec2 rg;\nuniform ivec2 ba;\nvoid main() { gl_FragColor = vec4(rg, vec2(ba)); }" } } },
    { "call": "create_program", "id": 2, "program": "solid" },
    { "call": "bind_attrib_location", "program": 1, "index": 3, "name": "p" },
    { "call": "use_program", "id": 1 },
    { "call": "uniform", "name": "rg", "value": { "vec2": [1, 0.5] } },
    { "call": "uniform", "name": "ba", "value": { "ivec2": [0, 1] } },
    { "call": "vertex_attrib", "index": 0, "value": [0, 0, 0, 1] },
    { "call": "vertex_attrib_pointer", "index": 3, "buffer": 1, "size": 2, "type": "float" },
    { "call": "enable_vertex_attrib", "index": 3 },
    { "call": "clear", "color": true },
    { "call": "draw_arrays", "mode": "triangles", "first": 0, "count": 3 },
    { "call": "swap_buffers" }
  ] } ]
}"#;

#[test]
fn a_trace_with_a_glsl_program_round_trips_and_replays() {
    let trace = Trace::parse(TRACE, None).unwrap();
    let Call::CreateProgram { program: ProgramSource::Glsl(source), .. } = &trace.frames[0].calls[1] else {
        panic!("not a GLSL program: {:?}", trace.frames[0].calls[1]);
    };
    assert!(source.fragment.contains("uniform ivec2 ba;"));
    assert_eq!(
        trace.frames[0].calls[2],
        Call::CreateProgram { id: 2, program: ProgramSource::Builtin(ProgramKind::Solid) }
    );
    let written = trace.to_json();
    assert!(written.contains(r#""program":"solid""#), "{written}");
    assert!(written.contains(r#""program":{"glsl":{"vertex":"#), "{written}");
    assert_eq!(Trace::parse(&written, None).unwrap(), trace);
    let replay = trace.replay().unwrap();
    let rgba = replay.context.surface_rgba8();
    assert_eq!(pixel(&rgba, 16, 5, 5), [255, 128, 0, 255]);
}

/// A context with a full-screen triangle in buffer 1 at attribute 0.
fn screen() -> Context {
    let mut gl = context(16, 16);
    let triangle: [[f32; 2]; 3] = [[-1.0, -1.0], [3.0, -1.0], [-1.0, 3.0]];
    c(&mut gl, Call::CreateBuffer { id: 1, data: Bytes::from_slice(&triangle) });
    c(
        &mut gl,
        Call::VertexAttribPointer {
            index: 0,
            buffer: 1,
            size: 2,
            component: ComponentType::Float,
            normalized: false,
            stride: 0,
            offset: 0,
        },
    );
    c(&mut gl, Call::EnableVertexAttrib { index: 0 });
    gl
}

const SCREEN_VS: &str = "attribute vec2 p;
varying vec2 uv;
void main() { uv = p * 0.5 + 0.5; gl_Position = vec4(p, 0.0, 1.0); }";

fn use_glsl(gl: &mut Context, id: u32, fragment: &str) {
    c(gl, Call::CreateProgram { id, program: glsl(SCREEN_VS, fragment) });
    c(gl, Call::BindAttribLocation { program: id, index: 0, name: "p".into() });
    c(gl, Call::UseProgram { id });
}

#[test]
fn glsl_errors_name_the_call_the_shader_and_the_line() {
    let mut gl = screen();
    let bad = "precision mediump float;\nvoid main() {\n    gl_FragColor = vec4(undeclared);\n}";
    let e = gl.call(Call::CreateProgram { id: 1, program: glsl(SCREEN_VS, bad) }).unwrap_err();
    assert_eq!(e.name, "create_program");
    let message = e.to_string();
    assert!(message.contains("fragment shader, line 3"), "{message}");
    assert!(message.contains("undeclared"), "{message}");
    let e = gl.call(Call::CreateProgram { id: 1, program: glsl("void main() { gl_Position = 1; }", "") });
    assert!(e.unwrap_err().to_string().contains("vertex shader, line 1"));

    let fragment = "precision mediump float;
uniform vec4 color;
uniform int count;
uniform bool flag;
uniform float weights[3];
uniform sampler2D tex;
varying vec2 uv;
void main() {
    float w = flag ? weights[2] : float(count);
    gl_FragColor = texture2D(tex, uv) * color * w;
}";
    use_glsl(&mut gl, 2, fragment);
    // Wrong types: GL's rules, then the uniform named.
    for (name, value) in [
        ("color", UniformValue::Vec3([1.0; 3])),
        ("color", UniformValue::IVec4([1; 4])),
        ("count", UniformValue::Float(1.0)),
        ("tex", UniformValue::Float(0.0)),
        ("weights[1]", UniformValue::Int(1)),
    ] {
        let e = gl.call(Call::Uniform { name: name.into(), value }).unwrap_err().to_string();
        let base = name.split('[').next().unwrap();
        assert!(e.contains(&format!("uniform '{name}'")) && e.contains("cannot set"), "{name}: {e}");
        assert!(!base.is_empty());
    }
    // What GL accepts: ints and floats set bools, an element of an array, "x" as "x[0]".
    uniform(&mut gl, "flag", UniformValue::Float(2.0));
    uniform(&mut gl, "flag", UniformValue::Int(1));
    uniform(&mut gl, "weights[2]", UniformValue::Float(0.5));
    uniform(&mut gl, "weights", UniformValue::Float(0.25));
    uniform(&mut gl, "color", UniformValue::Vec4([1.0; 4]));
    let e = gl.call(Call::Uniform { name: "weights[3]".into(), value: UniformValue::Float(1.0) });
    assert!(e.unwrap_err().to_string().contains("no active uniform 'weights[3]'"));
    let e = gl.call(Call::Uniform { name: "colour".into(), value: UniformValue::Vec4([1.0; 4]) }).unwrap_err();
    let e = e.to_string();
    assert!(e.contains("no active uniform 'colour'") && e.contains("color, count, flag, weights[0], tex"), "{e}");
    let e = gl.call(Call::Uniform { name: "tex".into(), value: UniformValue::Int(8) }).unwrap_err().to_string();
    assert!(e.contains("texture unit 8"), "{e}");
    let e = gl.call(Call::Uniform { name: "color".into(), value: UniformValue::Vec4([f32::NAN; 4]) });
    assert!(e.unwrap_err().to_string().contains("non-finite"));
    assert_eq!(
        gl.uniform_names(2).unwrap(),
        ["color", "count", "flag", "weights[0]", "tex"].map(String::from).to_vec()
    );
    assert_eq!(gl.uniform_names(9), None);

    // The sampler reads unit 1, which has no texture: the draw says so.
    uniform(&mut gl, "tex", UniformValue::Int(1));
    let e = gl.call(Call::DrawArrays { mode: Mode::Triangles, first: 0, count: 3 }).unwrap_err();
    assert_eq!(e.name, "draw_arrays");
    assert!(e.message.contains("sampler 'tex' reads texture unit 1, which has no texture"), "{e}");

    // Attributes: locations beyond the context's, reserved names, fixed built-ins.
    let e = gl.call(Call::BindAttribLocation { program: 2, index: 8, name: "p".into() }).unwrap_err();
    assert!(e.message.contains("out of range"), "{e}");
    let e = gl.call(Call::BindAttribLocation { program: 2, index: 1, name: "gl_Vertex".into() }).unwrap_err();
    assert!(e.message.contains("reserved"), "{e}");
    c(&mut gl, Call::CreateProgram { id: 3, program: ProgramKind::Solid.into() });
    let e = gl.call(Call::BindAttribLocation { program: 3, index: 1, name: "position".into() }).unwrap_err();
    assert!(e.message.contains("fixed"), "{e}");
    c(&mut gl, Call::BindAttribLocation { program: 3, index: 0, name: "position".into() });
}

/// `glUniform*ui` sets uint uniforms (not int or float ones), with every bit: integer uniforms
/// reach the shader as their 32 bits, beyond what a float holds exactly too.
#[test]
fn uint_uniforms_are_set_with_every_bit() {
    let mut gl = screen();
    let vs = "#version 300 es\nin vec2 p;\nvoid main() { gl_Position = vec4(p, 0.0, 1.0); }";
    let fs = "#version 300 es\nprecision highp float;\nuniform uint u;\nuniform ivec2 i;\nout vec4 c;\n\
              void main() { c = vec4(float(u % 256u) / 255.0, float(i.y) / 255.0, 0.0, 1.0); }";
    c(&mut gl, Call::CreateProgram { id: 1, program: glsl(vs, fs) });
    c(&mut gl, Call::BindAttribLocation { program: 1, index: 0, name: "p".into() });
    c(&mut gl, Call::UseProgram { id: 1 });
    uniform(&mut gl, "u", UniformValue::UInt(0x1234));
    uniform(&mut gl, "i", UniformValue::IVec2([0, 128]));
    for (name, value) in [("u", UniformValue::Int(3)), ("i", UniformValue::UVec2([1, 2]))] {
        let e = gl.call(Call::Uniform { name: name.into(), value }).unwrap_err().to_string();
        assert!(e.contains("cannot set"), "{name}: {e}");
    }
    draw(&mut gl, 3);
    // 0xA5A5_A5A7 is no float: rounded through one it would read 0x…A0 (% 256 = 160).
    uniform(&mut gl, "u", UniformValue::UInt(0xA5A5_A5A7));
    uniform(&mut gl, "i", UniformValue::IVec2([-(1 << 30) - 3, 64]));
    draw(&mut gl, 3);
    swap(&mut gl);
    gl.end().unwrap();
    assert_eq!(pixel(&gl.surface_rgba8(), 16, 5, 5), [0xA7, 64, 0, 255]);
}

#[test]
fn a_disabled_attribute_reads_its_generic_value() {
    let mut gl = screen();
    let vs = "attribute vec2 p;
attribute vec4 tint;
varying vec4 v_tint;
void main() { v_tint = tint; gl_Position = vec4(p, 0.0, 1.0); }";
    let fs = "precision mediump float;
varying vec4 v_tint;
void main() { gl_FragColor = v_tint; }";
    c(&mut gl, Call::CreateProgram { id: 1, program: glsl(vs, fs) });
    c(&mut gl, Call::BindAttribLocation { program: 1, index: 0, name: "p".into() });
    assert_eq!(gl.attribute_locations(1).unwrap(), vec![("p".to_string(), 0), ("tint".to_string(), 1)]);
    c(&mut gl, Call::UseProgram { id: 1 });
    draw(&mut gl, 3);
    c(&mut gl, Call::Finish);
    assert_eq!(pixel(&gl.surface_rgba8(), 16, 8, 8), [0, 0, 0, 255], "(0, 0, 0, 1) at first");
    c(&mut gl, Call::VertexAttrib { index: 1, value: [0.0, 1.0, 0.5, 1.0] });
    draw(&mut gl, 3);
    c(&mut gl, Call::Finish);
    assert_eq!(pixel(&gl.surface_rgba8(), 16, 8, 8), [0, 255, 128, 255]);
    let e = gl.call(Call::VertexAttrib { index: 1, value: [f32::INFINITY, 0.0, 0.0, 1.0] }).unwrap_err();
    assert!(e.message.contains("not finite"), "{e}");
}

const SAMPLE_FS: &str = "precision mediump float;
uniform sampler2D tex;
varying vec2 uv;
void main() { gl_FragColor = texture2D(tex, uv); }";

/// Rendered into a texture, then sampled by a GLSL program: the render pass is flushed
/// first, and the picture is upright (GL's t up, the lower half red).
#[test]
fn glsl_samples_a_texture_rendered_just_before() {
    let mut gl = screen();
    framebuffer(&mut gl, 2, 16, 16);
    bind(&mut gl, 2);
    c(&mut gl, Call::ClearColor { rgba: [0.0, 0.0, 1.0, 1.0] });
    clear_all(&mut gl);
    let lower_half = quad(-1.0, -1.0, 1.0, 0.0, 0.0);
    c(&mut gl, Call::CreateBuffer { id: 3, data: Bytes::from_slice(&lower_half) });
    c(&mut gl, Call::CreateProgram { id: 3, program: glsl(SOLID_VS, SOLID_FS) });
    c(&mut gl, Call::UseProgram { id: 3 });
    uniform(&mut gl, "mvp", UniformValue::Mat4(Mat4::IDENTITY.to_cols_array()));
    uniform(&mut gl, "color", UniformValue::Vec4([1.0, 0.0, 0.0, 1.0]));
    c(
        &mut gl,
        Call::VertexAttribPointer {
            index: 0,
            buffer: 3,
            size: 3,
            component: ComponentType::Float,
            normalized: false,
            stride: 0,
            offset: 0,
        },
    );
    draw(&mut gl, 6);
    bind(&mut gl, 0);
    c(
        &mut gl,
        Call::VertexAttribPointer {
            index: 0,
            buffer: 1,
            size: 2,
            component: ComponentType::Float,
            normalized: false,
            stride: 0,
            offset: 0,
        },
    );
    c(&mut gl, Call::BindTexture { unit: 0, texture: 2 });
    use_glsl(&mut gl, 1, SAMPLE_FS);
    draw(&mut gl, 3);
    swap(&mut gl);
    let report = gl.end().unwrap();
    let rgba = gl.surface_rgba8();
    assert_eq!(pixel(&rgba, 16, 4, 12), [255, 0, 0, 255], "the lower half (tiler's bottom rows)");
    assert_eq!(pixel(&rgba, 16, 4, 3), [0, 0, 255, 255], "the upper half");
    let p = passes(&report);
    assert_eq!(p.len(), 2);
    let texture_image = gl.texture_image(2).unwrap();
    assert_eq!(p[1].draws[0].sampled, Some(texture_image));
    assert!(p[1].cost.ledger.get(tiler::Category::TextureFetch) > 0, "RGBA8 goes through the core's sampler");
}

/// A depth texture (a shadow map) rendered into and sampled: depth reads as `(z, z, z, 1)`.
#[test]
fn glsl_samples_a_depth_texture() {
    for format in [TextureFormat::Depth16, TextureFormat::Depth24, TextureFormat::Depth32f] {
        let mut gl = screen();
        c(&mut gl, Call::CreateTexture { id: 2, width: 16, height: 16, format, data: None, transient: false });
        c(&mut gl, Call::CreateFramebuffer { id: 2 });
        c(
            &mut gl,
            Call::FramebufferTexture { framebuffer: 2, attachment: AttachmentPoint::Depth, texture: 2, samples: 1 },
        );
        bind(&mut gl, 2);
        c(&mut gl, Call::Enable { cap: Capability::DepthTest });
        clear_all(&mut gl);
        // The lower half at NDC z = 0.5: window depth 0.75.
        let lower_half = quad(-1.0, -1.0, 1.0, 0.0, 0.5);
        c(&mut gl, Call::CreateBuffer { id: 3, data: Bytes::from_slice(&lower_half) });
        c(&mut gl, Call::CreateProgram { id: 3, program: glsl(SOLID_VS, SOLID_FS) });
        c(&mut gl, Call::UseProgram { id: 3 });
        uniform(&mut gl, "mvp", UniformValue::Mat4(Mat4::IDENTITY.to_cols_array()));
        c(
            &mut gl,
            Call::VertexAttribPointer {
                index: 0,
                buffer: 3,
                size: 3,
                component: ComponentType::Float,
                normalized: false,
                stride: 0,
                offset: 0,
            },
        );
        draw(&mut gl, 6);
        bind(&mut gl, 0);
        c(&mut gl, Call::Disable { cap: Capability::DepthTest });
        c(
            &mut gl,
            Call::VertexAttribPointer {
                index: 0,
                buffer: 1,
                size: 2,
                component: ComponentType::Float,
                normalized: false,
                stride: 0,
                offset: 0,
            },
        );
        c(&mut gl, Call::BindTexture { unit: 3, texture: 2 });
        use_glsl(&mut gl, 1, SAMPLE_FS);
        uniform(&mut gl, "tex", UniformValue::Int(3));
        draw(&mut gl, 3);
        swap(&mut gl);
        gl.end().unwrap();
        let rgba = gl.surface_rgba8();
        let lower = pixel(&rgba, 16, 4, 12);
        assert!(lower[0].abs_diff(191) <= 1 && lower[0] == lower[1] && lower[3] == 255, "{format:?}: {lower:?}");
        assert_eq!(pixel(&rgba, 16, 4, 3), [255, 255, 255, 255], "{format:?}: cleared to 1");
    }
}

/// A far quad, then a near one over it, depth-tested, on TBDR: with an opaque shader HSR
/// shades only the near quad; a shader that may discard (it never does here) keeps the far
/// one's fragments, as hardware must. The pictures are the same.
#[test]
fn a_discarding_glsl_shader_turns_hsr_off() {
    let discarding = "precision mediump float;
uniform vec4 color;
void main() {
    if (color.a < 0.0) discard;
    gl_FragColor = color;
}";
    let run = |fragment: &str| {
        let mut gl = Context::new(ContextConfig { backend: Backend::Tbdr, ..config(32, 32) }).unwrap();
        let mut vertices = quad(-1.0, -1.0, 1.0, 1.0, 0.5);
        vertices.extend(quad(-1.0, -1.0, 1.0, 1.0, -0.5));
        c(&mut gl, Call::CreateBuffer { id: 1, data: Bytes::from_slice(&vertices) });
        c(&mut gl, Call::CreateProgram { id: 1, program: glsl(SOLID_VS, fragment) });
        bind_geometry(&mut gl, 1);
        uniform(&mut gl, "mvp", UniformValue::Mat4(Mat4::IDENTITY.to_cols_array()));
        c(&mut gl, Call::Enable { cap: Capability::DepthTest });
        clear_all(&mut gl);
        uniform(&mut gl, "color", UniformValue::Vec4([1.0, 0.0, 0.0, 1.0]));
        c(&mut gl, Call::DrawArrays { mode: Mode::Triangles, first: 0, count: 6 });
        uniform(&mut gl, "color", UniformValue::Vec4([0.0, 1.0, 0.0, 1.0]));
        c(&mut gl, Call::DrawArrays { mode: Mode::Triangles, first: 6, count: 6 });
        swap(&mut gl);
        let report = gl.end().unwrap();
        let draws = passes(&report)[0].draws.clone();
        (draws, gl.surface_rgba8())
    };
    let (opaque, opaque_picture) = run(SOLID_FS);
    let (discard, discard_picture) = run(discarding);
    assert_eq!(opaque_picture, discard_picture);
    assert_eq!(pixel(&opaque_picture, 32, 9, 9), [0, 255, 0, 255]);
    assert!(!opaque[0].discards && discard[0].discards);
    assert_eq!(opaque[0].stats.fragments_shaded, 0, "HSR removed the hidden quad");
    assert_eq!(discard[0].stats.fragments_shaded, 32 * 32, "a discarding shader runs for every fragment");
    assert_eq!(opaque[1].stats.fragments_shaded, discard[1].stats.fragments_shaded);
}

/// The GLSL alpha-test pair draws what the built-in pair draws, and costs the same.
#[test]
fn the_glsl_example_pair_matches_the_built_in_one() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("traces");
    for form in ["bad", "good"] {
        let glsl = Trace::read(&dir.join(format!("glsl-alpha-test-{form}.json"))).unwrap().replay().unwrap();
        let builtin = Trace::read(&dir.join(format!("alpha-test-{form}.json"))).unwrap().replay().unwrap();
        assert_eq!(glsl.context.surface_rgba8(), builtin.context.surface_rgba8(), "{form}");
        assert_eq!(glsl.report.totals.ledger, builtin.report.totals.ledger, "{form}");
        assert_eq!(
            glsl.report.totals.counters.fragments_shaded, builtin.report.totals.counters.fragments_shaded,
            "{form}"
        );
        // The advice speaks of what each program has: a `discard` statement, or the built-in's
        // alpha_cutoff uniform.
        let fixes = |r: &tiler_gl::trace::Replay| -> Vec<String> {
            r.report.findings_with("early-z-disabled").map(|f| f.advice.clone()).collect()
        };
        for fix in fixes(&glsl) {
            assert!(fix.contains("`discard`") && !fix.contains("alpha_cutoff"), "{fix}");
        }
        for fix in fixes(&builtin) {
            assert!(fix.contains("alpha_cutoff"), "{fix}");
        }
        assert_eq!(fixes(&glsl).len(), fixes(&builtin).len(), "{form}");
        assert_eq!(fixes(&glsl).is_empty(), form == "good", "{form}");
    }
}

/// A 64×64 one-texel checkerboard drawn over 16×16 pixels (a quarter size: LOD 2). With
/// `generate_mipmap` and a mipmap filter, level 2 is read: every texel the box-filtered grey
/// `(0 + 255 + 255 + 0 + 2) >> 2 = 128`. Without levels the filter reads level 0's nearest
/// texel, black or white. Both for the GLSL program and the `textured` built-in.
#[test]
fn generated_mipmaps_are_sampled_with_a_mipmap_filter() {
    let checker: Vec<u8> =
        (0..64 * 64).flat_map(|i| if (i % 64 + i / 64) % 2 == 0 { [0, 0, 0, 255] } else { [255; 4] }).collect();
    for glsl_program in [true, false] {
        for generate in [true, false] {
            let mut gl = screen();
            c(
                &mut gl,
                Call::CreateTexture {
                    id: 1,
                    width: 64,
                    height: 64,
                    format: TextureFormat::Rgba8,
                    data: Some(Bytes::from(checker.clone())),
                    transient: false,
                },
            );
            c(
                &mut gl,
                Call::TexParameters {
                    id: 1,
                    filter: Filter::NearestMipmapNearest,
                    wrap: Wrap::Repeat,
                    mag_filter: None,
                    wrap_t: None,
                },
            );
            if generate {
                c(&mut gl, Call::GenerateMipmap { id: 1 });
            }
            c(&mut gl, Call::BindTexture { unit: 0, texture: 1 });
            if glsl_program {
                use_glsl(&mut gl, 1, SAMPLE_FS);
            } else {
                let texcoords: [[f32; 2]; 3] = [[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]];
                c(&mut gl, Call::CreateBuffer { id: 2, data: Bytes::from_slice(&texcoords) });
                c(&mut gl, Call::CreateProgram { id: 1, program: ProgramKind::Textured.into() });
                c(&mut gl, Call::UseProgram { id: 1 });
                c(
                    &mut gl,
                    Call::VertexAttribPointer {
                        index: 1,
                        buffer: 2,
                        size: 2,
                        component: ComponentType::Float,
                        normalized: false,
                        stride: 0,
                        offset: 0,
                    },
                );
                c(&mut gl, Call::EnableVertexAttrib { index: 1 });
            }
            draw(&mut gl, 3);
            swap(&mut gl);
            gl.end().unwrap();
            let rgba = gl.surface_rgba8();
            let values: std::collections::BTreeSet<u8> = rgba.chunks(4).map(|p| p[0]).collect();
            let what = format!("glsl {glsl_program}, generate {generate}: {values:?}");
            if generate {
                assert_eq!(values.into_iter().collect::<Vec<_>>(), [128], "{what}");
            } else {
                assert!(values.iter().all(|v| *v == 0 || *v == 255), "{what}");
            }
        }
    }
}

/// Levels given by the application (`tex_image_level`, `glTexImage2D` with `level > 0`) are
/// sampled as given once the chain reaches 1×1: the same draw as above reads level 2, here
/// solid red 20. A chain with levels missing is incomplete (black); `generate_mipmap` replaces
/// the given levels with the box chain (grey 128); a level of the wrong size is refused.
#[test]
fn given_mip_levels_are_sampled_as_given() {
    let checker: Vec<u8> =
        (0..64 * 64).flat_map(|i| if (i % 64 + i / 64) % 2 == 0 { [0, 0, 0, 255] } else { [255; 4] }).collect();
    let level = |level: u32| -> Call {
        let size = 64 >> level;
        let data = [10 * level as u8, 0, 0, 255].repeat((size * size) as usize);
        Call::TexImageLevel { id: 1, level, width: size, height: size, data: Bytes::from(data) }
    };
    // (levels given, generate afterwards, the red every pixel must have)
    for (given, generate, expected) in [(1..=6, false, 20), (1..=2, false, 0), (1..=6, true, 128)] {
        let mut gl = screen();
        let base = Bytes::from(checker.clone());
        let texture = Call::CreateTexture {
            id: 1,
            width: 64,
            height: 64,
            format: TextureFormat::Rgba8,
            data: Some(base),
            transient: false,
        };
        c(&mut gl, texture);
        let parameters = Call::TexParameters {
            id: 1,
            filter: Filter::NearestMipmapNearest,
            wrap: Wrap::Repeat,
            mag_filter: None,
            wrap_t: None,
        };
        c(&mut gl, parameters);
        for i in given.clone() {
            c(&mut gl, level(i));
        }
        if generate {
            c(&mut gl, Call::GenerateMipmap { id: 1 });
        }
        c(&mut gl, Call::BindTexture { unit: 0, texture: 1 });
        use_glsl(&mut gl, 1, SAMPLE_FS);
        draw(&mut gl, 3);
        swap(&mut gl);
        gl.end().unwrap();
        let values: std::collections::BTreeSet<u8> = gl.surface_rgba8().chunks(4).map(|p| p[0]).collect();
        assert_eq!(values.into_iter().collect::<Vec<_>>(), [expected], "levels {given:?}, generate {generate}");
    }
    let mut gl = screen();
    let texture = Call::CreateTexture {
        id: 1,
        width: 64,
        height: 64,
        format: TextureFormat::Rgba8,
        data: None,
        transient: false,
    };
    c(&mut gl, texture);
    let wrong = Call::TexImageLevel { id: 1, level: 1, width: 16, height: 16, data: Bytes::from(vec![0; 16 * 16 * 4]) };
    let error = gl.call(wrong).unwrap_err().to_string();
    assert!(error.contains("mip level 1 of texture 1 is 16×16") && error.contains("must be 32×32"), "{error}");
    let below = Call::TexImageLevel { id: 1, level: 7, width: 1, height: 1, data: Bytes::from(vec![0; 4]) };
    let error = gl.call(below).unwrap_err().to_string();
    assert!(error.contains("levels 1 to 6"), "{error}");
}

/// `gl_FragCoord` is GL's window position: y up from the bottom row, pixel centres at .5.
#[test]
fn gl_frag_coord_counts_rows_from_the_bottom() {
    let mut gl = screen();
    use_glsl(
        &mut gl,
        1,
        "precision mediump float;
void main() { gl_FragColor = vec4(gl_FragCoord.x / 16.0, gl_FragCoord.y / 16.0, 0.0, 1.0); }",
    );
    draw(&mut gl, 3);
    c(&mut gl, Call::Finish);
    let rgba = gl.surface_rgba8();
    // tiler's row 15 is GL's row 0: y = 0.5, 0.5 / 16 · 255 = 7.97.
    assert_eq!(pixel(&rgba, 16, 0, 15), [8, 8, 0, 255]);
    assert_eq!(pixel(&rgba, 16, 15, 0), [247, 247, 0, 255]);
}

/// Two samplers on two units: an RGBA8 texture (the core's sampler, counted) and an `rgba32f`
/// one (the context-side sampler), added.
#[test]
fn samplers_read_their_own_units() {
    let mut gl = screen();
    let red: Vec<u8> = [200u8, 0, 0, 255].repeat(4);
    c(
        &mut gl,
        Call::CreateTexture {
            id: 1,
            width: 2,
            height: 2,
            format: TextureFormat::Rgba8,
            data: Some(Bytes::from(red)),
            transient: false,
        },
    );
    let blue: Vec<f32> = [0.0f32, 0.0, 0.5, 0.0].repeat(4);
    c(
        &mut gl,
        Call::CreateTexture {
            id: 2,
            width: 2,
            height: 2,
            format: TextureFormat::Rgba32f,
            data: Some(Bytes::from_slice(&blue)),
            transient: false,
        },
    );
    c(&mut gl, Call::BindTexture { unit: 0, texture: 1 });
    c(&mut gl, Call::BindTexture { unit: 5, texture: 2 });
    use_glsl(
        &mut gl,
        1,
        "precision mediump float;
uniform sampler2D a;
uniform sampler2D b;
varying vec2 uv;
void main() { gl_FragColor = texture2D(a, uv) + texture2D(b, uv); }",
    );
    uniform(&mut gl, "b", UniformValue::Int(5));
    draw(&mut gl, 3);
    swap(&mut gl);
    let report = gl.end().unwrap();
    assert_eq!(pixel(&gl.surface_rgba8(), 16, 7, 7), [200, 0, 128, 255]);
    let pass = passes(&report)[0];
    assert!(pass.cost.ledger.get(tiler::Category::TextureFetch) > 0);
    assert_eq!(pass.draws[0].sampled, gl.texture_image(1), "the first unit's texture is reported");
}

/// A 256×256 texture drawn over 16×16 pixels (16× minified): read from level 0 with `LINEAR`,
/// neighbouring pixels share no cache line, the core counts those quads and their fetch, and
/// the advisor says `minified-without-mipmaps` with the saving it estimates; with mip maps the
/// pass fetches far less and the finding is gone (seed 004 §24.3.5).
#[test]
fn minified_textures_without_mip_maps_cost_fetch_and_are_advised() {
    let noise: Vec<u8> = (0..256u32 * 256 * 4).map(|i| (i.wrapping_mul(2_654_435_761) >> 24) as u8).collect();
    let run = |filter: Filter, generate: bool| {
        let mut gl = screen();
        let texture = Call::CreateTexture {
            id: 1,
            width: 256,
            height: 256,
            format: TextureFormat::Rgba8,
            data: Some(Bytes::from(noise.clone())),
            transient: false,
        };
        c(&mut gl, texture);
        c(&mut gl, Call::TexParameters { id: 1, filter, wrap: Wrap::Repeat, mag_filter: None, wrap_t: None });
        if generate {
            c(&mut gl, Call::GenerateMipmap { id: 1 });
        }
        c(&mut gl, Call::BindTexture { unit: 0, texture: 1 });
        use_glsl(&mut gl, 1, SAMPLE_FS);
        draw(&mut gl, 3);
        swap(&mut gl);
        gl.end().unwrap()
    };
    let fetch = |report: &tiler_gl::Report| -> u64 {
        report.passes().map(|p| p.cost.ledger.get(tiler::Category::TextureFetch)).sum()
    };
    let bare = run(Filter::Linear, false);
    let pass = bare.passes().find(|p| p.cost.counters.quads_minified_unmipped > 0).expect("a minified pass");
    // 16×16 pixels are 64 quads, each reading level 0 at λ = 4.
    assert_eq!(pass.cost.counters.quads_minified_unmipped, 64);
    let unmipped = pass.cost.counters.texture_fetch_minified_unmipped;
    assert_eq!(unmipped, pass.cost.ledger.get(tiler::Category::TextureFetch), "all its fetch is minified");
    // Each pixel's bilinear footprint spans two rows of 4×4 blocks 16 texels from its
    // neighbours': at least one new 64-byte line per pixel.
    assert!(unmipped >= 256 * 64, "{unmipped}");
    assert_eq!(pass.draws.iter().map(|d| d.stats.texture_fetch_minified_unmipped).sum::<u64>(), unmipped);
    let finding = bare.findings_with("minified-without-mipmaps").next().expect("the finding");
    assert_eq!(finding.cost_bytes, Some(unmipped - 64 * tiler_gl::advisor::MIPMAPPED_QUAD_BYTES));
    assert!(finding.message.contains("64 quads"), "{}", finding.message);

    let mipped = run(Filter::LinearMipmapLinear, true);
    assert!(mipped.findings_with("minified-without-mipmaps").next().is_none());
    assert!(mipped.passes().all(|p| p.cost.counters.quads_minified_unmipped == 0));
    assert!(fetch(&mipped) * 8 < fetch(&bare), "mip maps: {} B, level 0: {} B", fetch(&mipped), fetch(&bare));
}

/// Cube textures through calls: six faces uploaded (`cube_tex_image`), levels generated or
/// given, bound to a unit beside nothing else, sampled by a `samplerCube`; a draw keeps the
/// texels it was made with; a missing face or level makes the cube incomplete (black); bad
/// faces are refused naming the face; the calls round-trip through a JSON trace.
#[test]
fn cube_textures_are_created_uploaded_and_sampled() {
    const CUBE_FS: &str = "precision mediump float;
uniform samplerCube env;
uniform float lod;
void main() { gl_FragColor = textureCubeLod(env, vec3(0.1, -0.2, -1.0), lod); }";
    let face = |face: usize, level: u32, red: u8| Call::CubeTexImage {
        id: 3,
        face: CubeFace::ALL[face],
        level,
        size: 4 >> level,
        format: TextureFormat::Rgba8,
        data: Some(Bytes::from([red, 10 * face as u8, 0, 255].repeat((16 >> (2 * level)) as usize))),
    };
    let red_of = |gl: &Context, x: u32| pixel(&gl.surface_rgba8(), 16, x, 8);
    let setup = |gl: &mut Context, faces: usize, filter: Filter| {
        for f in 0..faces {
            c(gl, face(f, 0, 100));
        }
        let parameters = Call::TexParameters { id: 3, filter, wrap: Wrap::Repeat, mag_filter: None, wrap_t: None };
        c(gl, parameters);
        c(gl, Call::BindCubeTexture { unit: 2, texture: 3 });
        use_glsl(gl, 1, CUBE_FS);
        c(gl, Call::Uniform { name: "env".into(), value: UniformValue::Int(2) });
    };
    // Generated levels: level 2 of −Z (face 5) is its colour averaged, the same.
    let mut gl = screen();
    setup(&mut gl, 6, Filter::NearestMipmapNearest);
    c(&mut gl, Call::GenerateMipmap { id: 3 });
    c(&mut gl, Call::Uniform { name: "lod".into(), value: UniformValue::Float(2.0) });
    c(&mut gl, Call::Viewport { x: 0, y: 0, width: 8, height: 16 });
    draw(&mut gl, 3);
    // An upload after a draw reaches only later draws (no flush needed: the draw keeps its
    // texels).
    c(
        &mut gl,
        Call::CubeTexSubImage {
            id: 3,
            face: CubeFace::NegativeZ,
            x: 0,
            y: 0,
            width: 4,
            height: 4,
            data: Bytes::from([7u8, 0, 0, 255].repeat(16)),
        },
    );
    c(&mut gl, Call::Uniform { name: "lod".into(), value: UniformValue::Float(0.0) });
    c(&mut gl, Call::Viewport { x: 8, y: 0, width: 8, height: 16 });
    draw(&mut gl, 3);
    c(&mut gl, Call::Finish);
    assert_eq!(red_of(&gl, 2), [100, 50, 0, 255]);
    assert_eq!(red_of(&gl, 12), [7, 0, 0, 255]);

    // Given levels, on every face, are sampled as given; one face short of a level is
    // incomplete with a mipmap filter, and complete without one.
    for (faces_with_levels, filter, expected) in [
        (6, Filter::NearestMipmapNearest, [30, 50, 0, 255]),
        (5, Filter::NearestMipmapNearest, [0, 0, 0, 255]),
        (5, Filter::Nearest, [100, 50, 0, 255]),
    ] {
        let mut gl = screen();
        setup(&mut gl, 6, filter);
        for f in 0..faces_with_levels {
            c(&mut gl, face(f, 1, 20));
            c(&mut gl, face(f, 2, 30));
        }
        c(&mut gl, Call::Uniform { name: "lod".into(), value: UniformValue::Float(2.0) });
        draw(&mut gl, 3);
        c(&mut gl, Call::Finish);
        assert_eq!(red_of(&gl, 8), expected, "{faces_with_levels} faces with levels, {filter:?}");
    }

    // A sampler object on the unit replaces the cube's own parameters: its mipmap filter reads
    // level 2 where the cube's own filter reads level 0; unbound, the cube's again.
    for (sampler_object, expected) in [(true, [30, 50, 0, 255]), (false, [100, 50, 0, 255])] {
        let mut gl = screen();
        setup(&mut gl, 6, Filter::Nearest);
        for f in 0..6 {
            c(&mut gl, face(f, 1, 20));
            c(&mut gl, face(f, 2, 30));
        }
        let filter = Filter::NearestMipmapNearest;
        let (wrap, mag_filter, wrap_t, compare, wrap_r) = (Wrap::Repeat, None, None, None, None);
        c(&mut gl, Call::BindSampler { unit: 2, filter, wrap, mag_filter, wrap_t, compare, wrap_r });
        if !sampler_object {
            c(&mut gl, Call::UnbindSampler { unit: 2 });
        }
        c(&mut gl, Call::Uniform { name: "lod".into(), value: UniformValue::Float(2.0) });
        draw(&mut gl, 3);
        c(&mut gl, Call::Finish);
        assert_eq!(red_of(&gl, 8), expected, "sampler object bound: {sampler_object}");
    }

    // A missing face: incomplete, black.
    let mut gl = screen();
    setup(&mut gl, 5, Filter::Nearest);
    c(&mut gl, Call::Uniform { name: "lod".into(), value: UniformValue::Float(0.0) });
    draw(&mut gl, 3);
    c(&mut gl, Call::Finish);
    assert_eq!(red_of(&gl, 8), [0, 0, 0, 255]);

    // Bad faces and uses are refused, naming what.
    let mut gl = screen();
    c(&mut gl, face(0, 0, 1));
    let mut wrong = face(1, 0, 1);
    if let Call::CubeTexImage { size, data, .. } = &mut wrong {
        *size = 8;
        *data = Some(Bytes::from(vec![0; 8 * 8 * 4]));
    }
    let error = gl.call(wrong).unwrap_err().to_string();
    assert!(error.contains("face negative_x: 8×8") && error.contains("other faces are 4×4"), "{error}");
    let below = Call::CubeTexImage {
        id: 3,
        face: CubeFace::PositiveX,
        level: 3,
        size: 1,
        format: TextureFormat::Rgba8,
        data: Some(Bytes::from(vec![0; 4])),
    };
    let error = gl.call(below).unwrap_err().to_string();
    assert!(error.contains("levels 1 to 2"), "{error}");
    let error = gl.call(Call::GenerateMipmap { id: 3 }).unwrap_err().to_string();
    assert!(error.contains("face negative_x has no level 0"), "{error}");
    let error = gl.call(Call::BindTexture { unit: 0, texture: 3 }).unwrap_err().to_string();
    assert!(error.contains("texture 3"), "{error}");
    use_glsl(&mut gl, 1, CUBE_FS);
    let error = gl.call(Call::DrawArrays { mode: Mode::Triangles, first: 0, count: 3 }).unwrap_err().to_string();
    assert!(error.contains("sampler 'env' reads texture unit 0, which has no cube texture"), "{error}");

    // Faces count against the context's memory limit until the cube is deleted.
    let mut gl = Context::new(ContextConfig { memory_limit: 1 << 20, ..ContextConfig::new(16, 16) }).unwrap();
    let quarter = |face: usize| Call::CubeTexImage {
        id: 5,
        face: CubeFace::ALL[face],
        level: 0,
        size: 256,
        format: TextureFormat::Rgba8,
        data: None,
    };
    for f in 0..3 {
        c(&mut gl, quarter(f));
    }
    let error = gl.call(quarter(3)).unwrap_err().to_string();
    assert!(error.contains("memory limit"), "{error}");
    c(&mut gl, Call::DeleteTexture { id: 5 });
    for f in 0..3 {
        c(&mut gl, quarter(f));
    }

    // The trace format: the calls as JSON and back.
    let call = face(4, 1, 9).try_map_data(|d: Bytes| Ok::<_, ()>(d.to_vec())).unwrap();
    let json = serde_json::to_string(&call).unwrap();
    assert!(json.contains(r#""call":"cube_tex_image""#) && json.contains(r#""face":"positive_z""#), "{json}");
    let bind: Call<Vec<u8>> =
        serde_json::from_str(r#"{"call": "bind_cube_texture", "unit": 1, "texture": 3}"#).unwrap();
    assert_eq!(bind, Call::BindCubeTexture { unit: 1, texture: 3 });
}

// ---- tex3d: 2-D array and 3-D textures through calls.

/// A 3-D texture through calls: created, a slice replaced by `layered_tex_sub_image`, bound,
/// sampled at a slice by a `sampler3D` with `tex_wrap_r`; what tiler refuses (a 3-D mip chain,
/// a mipmap minification filter on one, a wrong size of texels, another target's binding) is
/// refused naming what, and the texels count against the memory limit until deleted.
#[test]
fn layered_textures_are_created_uploaded_sampled_and_refused_by_name() {
    const FS: &str = "#version 300 es
precision mediump float;
uniform mediump sampler3D volume;
uniform float r;
out vec4 color;
void main() { color = texture(volume, vec3(0.5, 0.5, r)); }";
    let slices = |d: u32| -> Vec<u8> { (0..d).flat_map(|k| [40 * k as u8, 0, 0, 255].repeat(4)).collect() };
    let volume = |depth: u32| Call::LayeredTexImage {
        id: 3,
        target: LayeredTarget::Texture3D,
        width: 2,
        height: 2,
        depth,
        format: TextureFormat::Rgba8,
        data: Some(Bytes::from(slices(depth))),
    };
    let setup = |gl: &mut Context, filter: Filter, wrap_r: Wrap| {
        c(gl, volume(4));
        c(gl, Call::TexParameters { id: 3, filter, wrap: Wrap::ClampToEdge, mag_filter: None, wrap_t: None });
        c(gl, Call::TexWrapR { id: 3, wrap: wrap_r });
        c(gl, Call::BindLayeredTexture { unit: 1, target: LayeredTarget::Texture3D, texture: 3 });
        use_glsl(gl, 1, FS);
        c(gl, Call::Uniform { name: "volume".into(), value: UniformValue::Int(1) });
    };
    let red_at_with = |r: f32, wrap_r: Wrap, sub: bool, sampler_wrap_r: Option<Option<Wrap>>| {
        let mut gl = screen();
        setup(&mut gl, Filter::Nearest, wrap_r);
        if let Some(wrap_r) = sampler_wrap_r {
            let (filter, wrap, mag_filter, wrap_t, compare) = (Filter::Nearest, Wrap::ClampToEdge, None, None, None);
            c(&mut gl, Call::BindSampler { unit: 1, filter, wrap, mag_filter, wrap_t, compare, wrap_r });
        }
        if sub {
            let data = Bytes::from([200u8, 0, 0, 255].repeat(4));
            let sub = Call::LayeredTexSubImage { id: 3, x: 0, y: 0, z: 2, width: 2, height: 2, depth: 1, data };
            c(&mut gl, sub);
        }
        c(&mut gl, Call::Uniform { name: "r".into(), value: UniformValue::Float(r) });
        draw(&mut gl, 3);
        c(&mut gl, Call::Finish);
        pixel(&gl.surface_rgba8(), 16, 8, 8)[0]
    };
    let red_at = |r: f32, wrap_r: Wrap, sub: bool| red_at_with(r, wrap_r, sub, None);
    // Slice ⌊r · 4⌋; WRAP_R repeat takes r mod 1, clamp-to-edge the last slice.
    assert_eq!(red_at(0.6, Wrap::Repeat, false), 80);
    assert_eq!(red_at(1.3, Wrap::Repeat, false), 40);
    assert_eq!(red_at(1.3, Wrap::ClampToEdge, false), 120);
    assert_eq!(red_at(0.6, Wrap::Repeat, true), 200);
    // A sampler object's WRAP_R replaces the texture's (its default: repeat).
    assert_eq!(red_at_with(1.3, Wrap::Repeat, false, Some(Some(Wrap::ClampToEdge))), 120);
    assert_eq!(red_at_with(1.3, Wrap::ClampToEdge, false, Some(None)), 40);

    // Refused, naming what.
    let mut gl = screen();
    setup(&mut gl, Filter::Linear, Wrap::Repeat);
    let error = gl.call(Call::GenerateMipmap { id: 3 }).unwrap_err().to_string();
    assert!(error.contains("3-D texture 3") && error.contains("not supported"), "{error}");
    let mipmapped = Call::TexParameters {
        id: 3,
        filter: Filter::LinearMipmapLinear,
        wrap: Wrap::Repeat,
        mag_filter: None,
        wrap_t: None,
    };
    c(&mut gl, mipmapped);
    let error = gl.call(Call::DrawArrays { mode: Mode::Triangles, first: 0, count: 3 }).unwrap_err().to_string();
    assert!(error.contains("sampler 'volume'") && error.contains("mipmap"), "{error}");
    let mut short = volume(4);
    if let Call::LayeredTexImage { data, .. } = &mut short {
        *data = Some(Bytes::from(slices(3)));
    }
    let error = gl.call(short).unwrap_err().to_string();
    assert!(error.contains("3-D texture 3") && error.contains("needs 64"), "{error}");
    let error = gl
        .call(Call::BindLayeredTexture { unit: 0, target: LayeredTarget::Array2D, texture: 3 })
        .unwrap_err()
        .to_string();
    assert!(error.contains("texture 3 is a 3-D texture"), "{error}");
    let sub = Call::LayeredTexSubImage {
        id: 3,
        x: 1,
        y: 0,
        z: 3,
        width: 2,
        height: 2,
        depth: 1,
        data: Bytes::from(vec![0; 16]),
    };
    let error = gl.call(sub).unwrap_err().to_string();
    assert!(error.contains("outside"), "{error}");

    // Texels count against the memory limit until the texture is deleted.
    let mut gl = Context::new(ContextConfig { memory_limit: 1 << 20, ..ContextConfig::new(16, 16) }).unwrap();
    let big = |id: u32| Call::LayeredTexImage {
        id,
        target: LayeredTarget::Array2D,
        width: 256,
        height: 256,
        depth: 3,
        format: TextureFormat::Rgba8,
        data: None,
    };
    c(&mut gl, big(5));
    let error = gl.call(big(6)).unwrap_err().to_string();
    assert!(error.contains("memory limit"), "{error}");
    c(&mut gl, Call::DeleteTexture { id: 5 });
    c(&mut gl, big(6));

    // The calls' names in a JSON trace.
    let bind: Call<Vec<u8>> =
        serde_json::from_str(r#"{"call": "bind_layered_texture", "unit": 1, "target": "3d", "texture": 3}"#).unwrap();
    assert_eq!(bind, Call::BindLayeredTexture { unit: 1, target: LayeredTarget::Texture3D, texture: 3 });
    let wrap: Call<Vec<u8>> =
        serde_json::from_str(r#"{"call": "tex_wrap_r", "id": 3, "wrap": "mirrored_repeat"}"#).unwrap();
    assert_eq!(wrap, Call::TexWrapR { id: 3, wrap: Wrap::MirroredRepeat });
}

/// A `mat2x3` uniform is set by `glUniformMatrix2x3fv`'s value (column-major: two columns of
/// three) and refused, naming the uniform, from a `mat3x2` one of the same size.
#[test]
fn non_square_matrix_uniforms_take_their_own_shape() {
    const VS: &str = "#version 300 es\nin vec2 p;\nvoid main() { gl_Position = vec4(p, 0.0, 1.0); }";
    const FS: &str = "#version 300 es
precision highp float;
uniform mat2x3 m;
out vec4 c;
void main() { c = vec4(m * vec2(1.0, 0.5), 1.0); }";
    let mut gl = screen();
    c(&mut gl, Call::CreateProgram { id: 1, program: glsl(VS, FS) });
    c(&mut gl, Call::BindAttribLocation { program: 1, index: 0, name: "p".into() });
    c(&mut gl, Call::UseProgram { id: 1 });
    let value = UniformValue::Mat2x3([0.2, 0.4, 0.1, 0.2, 0.2, 0.6]);
    c(&mut gl, Call::Uniform { name: "m".into(), value });
    draw(&mut gl, 3);
    c(&mut gl, Call::Finish);
    // (0.2 + 0.1, 0.4 + 0.1, 0.1 + 0.3) = (0.3, 0.5, 0.4).
    let got = pixel(&gl.surface_rgba8(), 16, 8, 8);
    for (g, want) in got.iter().zip([0.3f32, 0.5, 0.4, 1.0]) {
        assert!((f32::from(*g) - want * 255.0).abs() <= 1.0, "{got:?}");
    }
    let wrong = UniformValue::Mat3x2([0.0; 6]);
    let error = gl.call(Call::Uniform { name: "m".into(), value: wrong }).unwrap_err().to_string();
    assert!(error.contains("mat3x2"), "{error}");
    let json = serde_json::to_string(&Call::<Vec<u8>>::Uniform { name: "m".into(), value }).unwrap();
    assert!(json.contains(r#""mat2x3":[0.2,0.4,0.1,0.2,0.2,0.6]"#), "{json}");
}
