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
