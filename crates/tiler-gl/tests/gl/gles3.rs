//! GL ES 3.0 state in the context: vertex array objects keep their attributes and index
//! buffer, and instanced draws give the picture of one draw per instance while a
//! per-instance attribute is fetched once per instance.

use tiler::{Backend, Category};
use tiler_gl::*;

use crate::common::*;

fn glsl(vertex: &str, fragment: &str) -> ProgramSource {
    ProgramSource::Glsl(GlslSource { vertex: vertex.into(), fragment: fragment.into() })
}

fn pointer(index: u32, buffer: u32, size: u32) -> Call {
    Call::VertexAttribPointer {
        index,
        buffer,
        size,
        component: ComponentType::Float,
        normalized: false,
        stride: 0,
        offset: 0,
    }
}

const FRAGMENT: &str = "#version 300 es
precision mediump float;
in vec4 v_color;
layout(location = 0) out vec4 color;
void main() { color = v_color; }";

/// Four instances of a small triangle, offset per instance (attribute 1, divisor 1) and
/// coloured by `gl_InstanceID`.
const INSTANCED_VS: &str = "#version 300 es
layout(location = 0) in vec2 position;
layout(location = 1) in vec2 offset;
out vec4 v_color;
void main() {
    v_color = vec4(float(gl_InstanceID) * 0.25, 1.0, 0.5, 1.0);
    gl_Position = vec4(position + offset, 0.0, 1.0);
}";

/// The same, one draw per instance: the offset and the instance number are generic values.
const REFERENCE_VS: &str = "#version 300 es
layout(location = 0) in vec2 position;
layout(location = 1) in vec2 offset;
layout(location = 2) in float instance;
out vec4 v_color;
void main() {
    v_color = vec4(instance * 0.25, 1.0, 0.5, 1.0);
    gl_Position = vec4(position + offset, 0.0, 1.0);
}";

const OFFSETS: [[f32; 2]; 4] = [[-0.5, -0.5], [0.5, -0.5], [-0.5, 0.5], [0.5, 0.5]];

/// Draws the four instances (`instanced`) or four draws; returns the picture and the frame's
/// vertex fetch bytes.
fn four_triangles(backend: Backend, tile: u32, instanced: bool) -> (Vec<u8>, u64) {
    let mut gl =
        Context::new(ContextConfig { backend, tile_width: tile, tile_height: tile, ..config(32, 32) }).unwrap();
    let triangle = [[-0.3f32, -0.3], [0.3, -0.3], [0.0, 0.3]];
    c(&mut gl, Call::CreateBuffer { id: 1, data: Bytes::from_slice(&triangle) });
    c(&mut gl, Call::CreateBuffer { id: 2, data: Bytes::from_slice(&OFFSETS) });
    let vertex = if instanced { INSTANCED_VS } else { REFERENCE_VS };
    c(&mut gl, Call::CreateProgram { id: 1, program: glsl(vertex, FRAGMENT) });
    c(&mut gl, Call::UseProgram { id: 1 });
    c(&mut gl, pointer(0, 1, 2));
    c(&mut gl, Call::EnableVertexAttrib { index: 0 });
    c(&mut gl, Call::ClearColor { rgba: [0.0, 0.0, 0.0, 1.0] });
    c(&mut gl, Call::Clear { color: true, depth: true, stencil: true });
    if instanced {
        c(&mut gl, pointer(1, 2, 2));
        c(&mut gl, Call::EnableVertexAttrib { index: 1 });
        c(&mut gl, Call::VertexAttribDivisor { index: 1, divisor: 1 });
        c(&mut gl, Call::DrawArraysInstanced { mode: Mode::Triangles, first: 0, count: 3, instances: 4 });
    } else {
        for (i, [x, y]) in OFFSETS.into_iter().enumerate() {
            c(&mut gl, Call::VertexAttrib { index: 1, value: [x, y, 0.0, 1.0] });
            c(&mut gl, Call::VertexAttrib { index: 2, value: [i as f32, 0.0, 0.0, 1.0] });
            c(&mut gl, Call::DrawArrays { mode: Mode::Triangles, first: 0, count: 3 });
        }
    }
    swap(&mut gl);
    let report = gl.end().unwrap();
    (gl.surface_rgba8(), report.frames[0].ledger.get(Category::VertexFetch))
}

#[test]
fn an_instanced_draw_is_one_draw_per_instance_and_fetches_per_instance_attributes_once_per_instance() {
    let (reference, reference_fetch) = four_triangles(Backend::Tbdr, 16, false);
    let (picture, fetch) = four_triangles(Backend::Tbdr, 16, true);
    // Four distinct colours, one per instance.
    let mut colors: Vec<[u8; 4]> = picture.chunks_exact(4).map(|p| p.try_into().unwrap()).collect();
    colors.sort_unstable();
    colors.dedup();
    assert_eq!(colors.len(), 5, "four instances and the background: {colors:?}");
    assert!(picture == reference, "the instances draw what four draws draw");
    // The per-vertex positions cost what the four draws cost; each instance's offset (two
    // floats) is read once, not once per vertex.
    assert!(reference_fetch > 0);
    assert_eq!(fetch, reference_fetch + 4 * 8);
    for backend in [Backend::Tbr, Backend::Imr] {
        for tile in [16, 32] {
            assert!(four_triangles(backend, tile, true).0 == picture, "{backend:?}, {tile}×{tile} tiles");
        }
    }
}

#[test]
fn a_divisor_reads_one_element_per_divisor_instances_and_short_data_is_an_error() {
    let mut gl = context(8, 8);
    c(&mut gl, Call::CreateBuffer { id: 1, data: Bytes::from_slice(&[[-1.0f32, -1.0], [3.0, -1.0], [-1.0, 3.0]]) });
    // Two elements: enough for four instances at divisor 2, not at divisor 1.
    c(&mut gl, Call::CreateBuffer { id: 2, data: Bytes::from_slice(&[[0.0f32, 0.0], [0.0, 0.0]]) });
    c(&mut gl, Call::CreateProgram { id: 1, program: glsl(INSTANCED_VS, FRAGMENT) });
    c(&mut gl, Call::UseProgram { id: 1 });
    c(&mut gl, pointer(0, 1, 2));
    c(&mut gl, Call::EnableVertexAttrib { index: 0 });
    c(&mut gl, pointer(1, 2, 2));
    c(&mut gl, Call::EnableVertexAttrib { index: 1 });
    c(&mut gl, Call::VertexAttribDivisor { index: 1, divisor: 2 });
    let draw = Call::DrawArraysInstanced { mode: Mode::Triangles, first: 0, count: 3, instances: 4 };
    c(&mut gl, draw.clone());
    c(&mut gl, Call::VertexAttribDivisor { index: 1, divisor: 1 });
    let error = gl.call(draw).unwrap_err();
    assert_eq!(error.name, "draw_arrays_instanced");
    assert!(
        error.message.contains("attribute 1 (offset), divisor 1") && error.message.contains("past the end"),
        "{error}"
    );
    assert!(gl.call(Call::VertexAttribDivisor { index: 8, divisor: 1 }).is_err());
    // Each instance is a draw of its own: a call's instances are bounded.
    let many = Call::DrawArraysInstanced { mode: Mode::Triangles, first: 0, count: 3, instances: u32::MAX };
    assert!(gl.call(many).unwrap_err().message.contains("at most 65536"));
}

#[test]
fn vertex_arrays_keep_their_attributes_and_index_buffer() {
    let mut gl = context(8, 8);
    let quad = [[-1.0f32, -1.0, 0.0], [1.0, -1.0, 0.0], [-1.0, 1.0, 0.0], [1.0, 1.0, 0.0]];
    c(&mut gl, Call::CreateBuffer { id: 1, data: Bytes::from_slice(&quad) });
    c(&mut gl, Call::CreateBuffer { id: 2, data: Bytes::from_slice(&[0u16, 1, 2, 2, 1, 3]) });
    c(&mut gl, Call::CreateProgram { id: 1, program: ProgramKind::Solid.into() });
    c(&mut gl, Call::UseProgram { id: 1 });
    set_color(&mut gl, [0.0, 1.0, 0.0, 1.0]);
    // Array 5 gets the quad and its indices; the default array has nothing.
    c(&mut gl, Call::CreateVertexArray { id: 5 });
    c(&mut gl, Call::BindVertexArray { id: 5 });
    bind_geometry(&mut gl, 1);
    c(&mut gl, Call::BindIndexBuffer { buffer: 2 });
    c(&mut gl, Call::BindVertexArray { id: 0 });
    let indexed =
        Call::DrawElements { mode: Mode::Triangles, count: 6, index_type: IndexKind::UnsignedShort, offset: 0 };
    let error = gl.call(indexed.clone()).unwrap_err();
    assert!(error.message.contains("no index buffer"), "{error}");
    c(&mut gl, Call::BindVertexArray { id: 5 });
    c(&mut gl, indexed.clone());
    swap(&mut gl);
    assert_eq!(pixel(&gl.surface_rgba8(), 8, 3, 3), [0, 255, 0, 255]);
    // Client arrays belong to the default array only; names are checked.
    let client = Call::VertexAttribArray {
        index: 0,
        size: 3,
        component: ComponentType::Float,
        normalized: false,
        stride: 0,
        data: Bytes::from_slice(&quad),
    };
    assert!(gl.call(client).unwrap_err().message.contains("vertex array 5 is bound"));
    assert!(gl.call(Call::BindVertexArray { id: 6 }).is_err());
    assert!(gl.call(Call::CreateVertexArray { id: 5 }).is_err());
    // Deleting the bound array binds the default one; deleting a buffer detaches it from
    // every array.
    c(&mut gl, Call::DeleteVertexArray { id: 5 });
    assert!(gl.call(indexed.clone()).is_err());
    c(&mut gl, Call::CreateVertexArray { id: 7 });
    c(&mut gl, Call::BindVertexArray { id: 7 });
    c(&mut gl, Call::BindIndexBuffer { buffer: 2 });
    bind_geometry(&mut gl, 1);
    c(&mut gl, Call::BindVertexArray { id: 0 });
    c(&mut gl, Call::DeleteBuffer { id: 2 });
    c(&mut gl, Call::BindVertexArray { id: 7 });
    assert!(gl.call(indexed).unwrap_err().message.contains("no index buffer"));
}

/// An `R32UI` target written through a `uvec4` output from a `glVertexAttribIPointer`
/// attribute of 32-bit integers beyond 2²⁴ (kept exactly) after `glClearBufferuiv`, then read
/// by a `usampler2D`'s `texelFetch` into the window; what GL calls undefined or incomplete is
/// an error naming it.
#[test]
fn integer_targets_attributes_and_fetches_are_exact_and_misuse_is_an_error() {
    const WRITE_VS: &str = "#version 300 es
layout(location = 0) in vec2 position;
layout(location = 1) in uint code;
flat out uint v_code;
void main() { v_code = code; gl_Position = vec4(position, 0.0, 1.0); }";
    const WRITE_FS: &str = "#version 300 es
precision highp int;
flat in uint v_code;
layout(location = 0) out uvec4 o;
void main() { o = uvec4(v_code + uint(gl_FragCoord.x), 0u, 0u, 0u); }";
    const SHOW_FS: &str = "#version 300 es
precision highp float;
precision highp int;
uniform highp usampler2D codes;
out vec4 color;
void main() {
    uint v = texelFetch(codes, ivec2(gl_FragCoord.xy), 0).r;
    // 0x1234_5678 + x drawn, 0xdead_beef cleared: tell them apart by their low bytes.
    color = vec4(float(v & 0xffu) / 255.0, float((v >> 24) & 0xffu) / 255.0, 0.0, 1.0);
}";
    let mut gl = context(8, 8);
    let r32ui = TextureFormat::Int(tiler::IntFormat { channels: 1, bits: 32, signed: false });
    c(&mut gl, Call::CreateTexture { id: 5, width: 8, height: 8, format: r32ui, data: None, transient: false });
    c(&mut gl, Call::CreateFramebuffer { id: 5 });
    let attach =
        Call::FramebufferTexture { framebuffer: 5, attachment: AttachmentPoint::Color0, texture: 5, samples: 1 };
    c(&mut gl, attach);
    bind(&mut gl, 5);
    // A float clear value for an integer buffer: GL leaves it undefined.
    let float_clear = Call::ClearBufferColor { draw_buffer: 0, value: ClearColorValue::Float([0.0; 4]) };
    assert!(gl.call(float_clear).unwrap_err().message.contains("does not match"));
    c(&mut gl, Call::ClearBufferColor { draw_buffer: 0, value: ClearColorValue::Uint([0xdead_beef, 0, 0, 0]) });
    // The left half of the window.
    let triangle = [[-1.0f32, -1.0], [0.0, -1.0], [-1.0, 3.0], [0.0, 3.0]];
    c(&mut gl, Call::CreateBuffer { id: 1, data: Bytes::from_slice(&triangle) });
    c(&mut gl, Call::CreateBuffer { id: 2, data: Bytes::from_slice(&[0x1234_5678u32; 4]) });
    c(&mut gl, Call::CreateProgram { id: 1, program: glsl(WRITE_VS, WRITE_FS) });
    c(&mut gl, Call::UseProgram { id: 1 });
    c(&mut gl, pointer(0, 1, 2));
    c(&mut gl, Call::EnableVertexAttrib { index: 0 });
    let ipointer =
        |component| Call::VertexAttribIPointer { index: 1, buffer: 2, size: 1, component, stride: 0, offset: 0 };
    assert!(gl.call(ipointer(ComponentType::Float)).unwrap_err().message.contains("integer types"));
    c(&mut gl, ipointer(ComponentType::UnsignedInt));
    c(&mut gl, Call::EnableVertexAttrib { index: 1 });
    c(&mut gl, Call::DrawArrays { mode: Mode::TriangleStrip, first: 0, count: 4 });
    bind(&mut gl, 0);
    c(&mut gl, Call::CreateProgram { id: 2, program: glsl(WRITE_VS, SHOW_FS) });
    c(&mut gl, Call::UseProgram { id: 2 });
    c(&mut gl, Call::Uniform { name: "codes".into(), value: UniformValue::Int(0) });
    c(&mut gl, Call::BindTexture { unit: 0, texture: 5 });
    let whole = [[-1.0f32, -1.0], [1.0, -1.0], [-1.0, 1.0], [1.0, 1.0]];
    c(&mut gl, Call::CreateBuffer { id: 3, data: Bytes::from_slice(&whole) });
    c(&mut gl, pointer(0, 3, 2));
    // A linear filter leaves an integer texture incomplete.
    let filter =
        |filter| Call::TexParameters { id: 5, filter, wrap: Wrap::ClampToEdge, mag_filter: None, wrap_t: None };
    c(&mut gl, filter(Filter::Linear));
    let draw = Call::DrawArrays { mode: Mode::TriangleStrip, first: 0, count: 4 };
    let error = gl.call(draw.clone()).unwrap_err();
    assert!(error.message.contains("incomplete") && error.message.contains("'codes'"), "{error}");
    c(&mut gl, filter(Filter::Nearest));
    c(&mut gl, draw);
    swap(&mut gl);
    let rgba = gl.surface_rgba8();
    // glReadPixels of the integer buffer as RGBA_INTEGER / UNSIGNED_INT; as bytes or as INT
    // it is GL_INVALID_OPERATION.
    bind(&mut gl, 5);
    let read = |signed| Call::ReadPixelsInteger { x: 3, y: 0, width: 2, height: 1, signed };
    let Output::Pixels(ints) = c(&mut gl, read(false)) else { panic!("pixels") };
    let words: Vec<u32> = ints.chunks_exact(4).map(|b| u32::from_le_bytes(b.try_into().unwrap())).collect();
    assert_eq!(words, [0x1234_5678 + 3, 0, 0, 1, 0xdead_beef, 0, 0, 1]);
    assert!(gl.call(read(true)).unwrap_err().message.contains("INVALID_OPERATION"));
    let bytes = Call::ReadPixels { x: 0, y: 0, width: 1, height: 1 };
    assert!(gl.call(bytes).unwrap_err().message.contains("INVALID_OPERATION"));
    gl.end().unwrap();
    for x in 0..8 {
        let want = if x < 4 { [(0x78 + x) as u8, 0x12, 0, 255] } else { [0xef, 0xde, 0, 255] };
        assert_eq!(pixel(&rgba, 8, x, 3), want, "pixel {x}");
    }
}
