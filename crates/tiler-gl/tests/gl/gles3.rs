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
