//! The example of the crate docs, in detail.

use super::common::*;
use tiler::Category;
use tiler_gl::report::{LoadKind::*, StoreKind};
use tiler_gl::*;

#[test]
fn one_cleared_frame_is_one_pass() {
    let mut gl = context(64, 48);
    geometry(&mut gl, 1, ProgramKind::Solid, &quad(-1.0, -1.0, 0.0, 0.0, 0.5));
    set_color(&mut gl, [1.0, 0.0, 0.0, 1.0]);
    c(&mut gl, Call::ClearColor { rgba: [0.0, 0.0, 1.0, 1.0] });
    clear_all(&mut gl);
    draw(&mut gl, 6);
    swap(&mut gl);
    let image = gl.surface_rgba8();
    let report = gl.end().unwrap();
    let p = passes(&report);
    assert_eq!(p.len(), 1);
    assert_eq!(op(p[0], Slot::Color(0)), (Clear, StoreKind::Store));
    assert_eq!(op(p[0], Slot::Depth), (Clear, StoreKind::DontCare));
    assert_eq!(op(p[0], Slot::Stencil), (Clear, StoreKind::DontCare));
    // The quad covers the bottom-left quarter in GL: the bottom-left of the picture.
    assert_eq!(pixel(&image, 64, 5, 40), [255, 0, 0, 255]);
    assert_eq!(pixel(&image, 64, 5, 5), [0, 0, 255, 255]);
    assert_eq!(pixel(&image, 64, 40, 40), [0, 0, 255, 255]);
    let frame = &report.frames[0];
    assert_eq!(frame.ledger.get(Category::TileStore), 64 * 48 * 4);
    assert_eq!(frame.ledger.get(Category::TileLoad), 0);
    assert_eq!(frame.ledger.get(Category::Display), 64 * 48 * 4);
    assert!(report.findings.is_empty());
}

/// GL's window coordinates (y up) for viewports and scissors, and GL's front faces.
#[test]
fn gl_coordinates_and_front_faces() {
    let mut gl = context(64, 48);
    // A full-screen triangle pair, counter-clockwise in GL.
    geometry(&mut gl, 1, ProgramKind::Solid, &quad(-1.0, -1.0, 1.0, 1.0, 0.0));
    set_color(&mut gl, [0.0, 1.0, 0.0, 1.0]);
    clear_all(&mut gl);
    // The viewport's origin is GL's bottom-left: this one is the bottom-right 32×24.
    c(&mut gl, Call::Viewport { x: 32, y: 0, width: 32, height: 24 });
    draw(&mut gl, 6);
    // A scissor over GL's top-left 8×8 pixels, with a full viewport.
    c(&mut gl, Call::Viewport { x: 0, y: 0, width: 64, height: 48 });
    c(&mut gl, Call::Scissor { x: 0, y: 40, width: 8, height: 8 });
    c(&mut gl, Call::Enable { cap: Capability::ScissorTest });
    set_color(&mut gl, [1.0, 0.0, 0.0, 1.0]);
    draw(&mut gl, 6);
    c(&mut gl, Call::Disable { cap: Capability::ScissorTest });
    swap(&mut gl);
    let image = gl.surface_rgba8();
    assert_eq!(pixel(&image, 64, 40, 40), [0, 255, 0, 255], "bottom-right quarter");
    assert_eq!(pixel(&image, 64, 40, 10), [0, 0, 0, 0]);
    assert_eq!(pixel(&image, 64, 2, 2), [255, 0, 0, 255], "top-left scissor");
    assert_eq!(pixel(&image, 64, 2, 10), [0, 0, 0, 0]);

    // Counter-clockwise is front-facing, as in GL: culling back faces keeps the quad,
    // culling front faces removes it; with cw front faces it is the other way round.
    for (winding, face, drawn) in
        [(Winding::Ccw, Face::Back, true), (Winding::Ccw, Face::Front, false), (Winding::Cw, Face::Front, true)]
    {
        c(&mut gl, Call::Enable { cap: Capability::CullFace });
        c(&mut gl, Call::FrontFace { winding });
        c(&mut gl, Call::CullFace { face });
        clear_all(&mut gl);
        draw(&mut gl, 6);
        swap(&mut gl);
        let image = gl.surface_rgba8();
        assert_eq!(pixel(&image, 64, 30, 30)[0] == 255, drawn, "{winding:?} {face:?}");
    }
}

#[test]
fn a_program_deleted_in_use_draws_until_another_is_used() {
    let mut gl = context(8, 8);
    geometry(&mut gl, 1, ProgramKind::Solid, &quad(-1.0, -1.0, 1.0, 1.0, 0.0));
    c(&mut gl, Call::CreateProgram { id: 2, program: ProgramKind::Solid.into() });
    c(&mut gl, Call::DeleteProgram { id: 1 });
    set_color(&mut gl, [0.0, 1.0, 0.0, 1.0]);
    clear_all(&mut gl);
    draw(&mut gl, 6);
    swap(&mut gl);
    assert_eq!(pixel(&gl.surface_rgba8(), 8, 4, 4), [0, 255, 0, 255]);
    // Using it again is fine until another program is used; then it is gone.
    c(&mut gl, Call::UseProgram { id: 1 });
    c(&mut gl, Call::UseProgram { id: 2 });
    let error = gl.call(Call::UseProgram { id: 1 }).unwrap_err();
    assert!(error.message.contains("program 1 does not exist"), "{}", error.message);
    // A program not in use goes at once.
    c(&mut gl, Call::DeleteProgram { id: 2 });
    c(&mut gl, Call::UseProgram { id: 0 });
    assert!(gl.call(Call::UseProgram { id: 2 }).is_err());
}

#[test]
fn byte_indices_in_a_buffer_draw_as_shorts_would() {
    let vertices = quad(-1.0, -1.0, 1.0, 1.0, 0.0);
    let mut images = Vec::new();
    for (kind, indices) in [
        (IndexKind::UnsignedByte, vec![0u8, 1, 2, 3, 4, 5]),
        (IndexKind::UnsignedShort, [0u16, 1, 2, 3, 4, 5].iter().flat_map(|i| i.to_le_bytes()).collect()),
    ] {
        let mut gl = context(8, 8);
        geometry(&mut gl, 1, ProgramKind::Solid, &vertices);
        // One index of padding, so byte indices start at an odd offset.
        let size = indices.len() / 6;
        let mut data = vec![9u8; size];
        data.extend(&indices);
        c(&mut gl, Call::CreateBuffer { id: 2, data: Bytes::from(data) });
        c(&mut gl, Call::BindIndexBuffer { buffer: 2 });
        set_color(&mut gl, [1.0, 0.5, 0.0, 1.0]);
        clear_all(&mut gl);
        let size = size as u64;
        c(&mut gl, Call::DrawElements { mode: Mode::Triangles, count: 6, index_type: kind, offset: size });
        swap(&mut gl);
        images.push(gl.surface_rgba8());
    }
    assert_eq!(pixel(&images[0], 8, 4, 4), [255, 128, 0, 255]);
    assert_eq!(images[0], images[1]);
}
