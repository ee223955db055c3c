//! Depth and stencil: every compare op on every depth format, depth writes, every stencil op,
//! masks, and separate front and back state.

use super::common::*;
use tiler::*;

const SIZE: u32 = 24;

/// A quad over the whole framebuffer at depth `z`, counter-clockwise (front-facing) or not.
fn quad(z: f32, color: [f32; 4], front: bool) -> Vec<Vertex> {
    let (a, b, c, d) = (v(-1.0, -1.0, z, color), v(1.0, -1.0, z, color), v(1.0, 1.0, z, color), v(-1.0, 1.0, z, color));
    // y down: (−1,−1) top-left → (1,−1) top-right → (1,1) is clockwise on screen.
    if front { vec![a, d, c, a, c, b] } else { vec![a, b, c, a, c, d] }
}

struct Result {
    color: Vec<u8>,
    depth: Vec<f32>,
    stencil: Vec<u8>,
}

/// Clears depth to `clear_depth` and stencil to `clear_stencil`, draws each (vertices, state)
/// in order with a solid red shader.
fn draw(
    format: Format,
    clear_depth: f32,
    clear_stencil: u8,
    draws: &[(Vec<Vertex>, DepthStencilState)],
    backend: Backend,
) -> Result {
    let mut device = device(backend, 8, 2);
    let color = device.create_image(ImageDesc::new(SIZE, SIZE, Format::Rgba8Unorm)).unwrap();
    let ds = device.create_image(ImageDesc::new(SIZE, SIZE, format)).unwrap();
    let mut pass = RenderPass::new(RenderPassDesc {
        color: vec![ColorAttachment::clear_store(color, [0.0, 0.0, 0.0, 1.0])],
        depth_stencil: Some(DepthStencilAttachment::clear_store(ds, clear_depth, clear_stencil)),
        render_area: None,
    });
    for (verts, state) in draws {
        let buffer = device.create_buffer_from(verts).unwrap();
        let mut d = desc("ds");
        d.depth_stencil = *state;
        pass.draw(Draw::new(&pipeline(FlatColor, d), buffer, 0, verts.len() as u32));
    }
    device.submit(&pass).unwrap();
    Result {
        color: device.read_rgba8(color).unwrap(),
        depth: device.read_depth(ds).unwrap(),
        stencil: if format.has_stencil() { device.read_stencil(ds).unwrap() } else { Vec::new() },
    }
}

const RED: [f32; 4] = [1.0, 0.0, 0.0, 1.0];

#[test]
fn every_compare_op_on_every_depth_format() {
    use CompareOp::*;
    // (op, passes for z < stored, z == stored, z > stored)
    let table = [
        (Never, [false, false, false]),
        (Less, [true, false, false]),
        (Equal, [false, true, false]),
        (LessOrEqual, [true, true, false]),
        (Greater, [false, false, true]),
        (NotEqual, [true, false, true]),
        (GreaterOrEqual, [false, true, true]),
        (Always, [true, true, true]),
    ];
    for format in [Format::D16Unorm, Format::D24UnormS8Uint, Format::D32Float] {
        for backend in Backend::ALL {
            for (op, expected) in table {
                for (z, pass) in [0.25f32, 0.5, 0.75].into_iter().zip(expected) {
                    let state = DepthStencilState {
                        depth_test: true,
                        depth_write: true,
                        depth_compare: op,
                        ..DepthStencilState::DISABLED
                    };
                    let r = draw(format, 0.5, 0, &[(quad(z, RED, true), state)], backend);
                    let red = r.color.chunks(4).all(|p| p == [255, 0, 0, 255]);
                    let black = r.color.chunks(4).all(|p| p == [0, 0, 0, 255]);
                    assert!(if pass { red } else { black }, "{format} {backend} {op:?} z={z}");
                    let expected_depth = if pass { z } else { 0.5 };
                    assert!(
                        r.depth.iter().all(|d| (d - expected_depth).abs() < 1e-4),
                        "{format} {op:?} depth {:?}",
                        r.depth[0]
                    );
                }
            }
        }
    }
}

#[test]
fn depth_writes_off_leave_depth_alone() {
    let state = DepthStencilState::LESS_NO_WRITE;
    for backend in Backend::ALL {
        let r = draw(
            Format::D32Float,
            0.5,
            0,
            &[(quad(0.25, RED, true), state), (quad(0.4, [0.0, 1.0, 0.0, 1.0], true), state)],
            backend,
        );
        assert!(r.depth.iter().all(|d| *d == 0.5));
        // The second quad passes too (depth was never written): green over red.
        assert!(r.color.chunks(4).all(|p| p == [0, 255, 0, 255]));
    }
}

#[test]
fn every_stencil_op() {
    use StencilOp::*;
    // (op, stored before, reference, expected after)
    let table = [
        (Keep, 200, 7, 200),
        (Zero, 200, 7, 0),
        (Replace, 200, 7, 7),
        (IncrementAndClamp, 200, 7, 201),
        (IncrementAndClamp, 255, 7, 255),
        (DecrementAndClamp, 200, 7, 199),
        (DecrementAndClamp, 0, 7, 0),
        (Invert, 200, 7, 55),
        (IncrementAndWrap, 255, 7, 0),
        (DecrementAndWrap, 0, 7, 255),
    ];
    for backend in Backend::ALL {
        for (op, before, reference, after) in table {
            let face = StencilFaceState { pass_op: op, reference, ..StencilFaceState::KEEP };
            let state = DepthStencilState::DISABLED.with_stencil(face);
            let r = draw(Format::D24UnormS8Uint, 1.0, before, &[(quad(0.5, RED, true), state)], backend);
            assert!(r.stencil.iter().all(|s| *s == after), "{backend} {op:?}: {} ≠ {after}", r.stencil[0]);
        }
    }
}

#[test]
fn stencil_masks_fail_and_depth_fail_ops() {
    for backend in Backend::ALL {
        // Write mask: only the low nibble changes.
        let face = StencilFaceState {
            pass_op: StencilOp::Replace,
            reference: 0xab,
            write_mask: 0x0f,
            ..StencilFaceState::KEEP
        };
        let r = draw(
            Format::D24UnormS8Uint,
            1.0,
            0x50,
            &[(quad(0.5, RED, true), DepthStencilState::DISABLED.with_stencil(face))],
            backend,
        );
        assert!(r.stencil.iter().all(|s| *s == 0x5b));
        // Compare mask: 0x5? compared as 0x?5 & 0x0f; fail op applies, nothing is drawn.
        let face = StencilFaceState {
            compare: CompareOp::Equal,
            fail_op: StencilOp::Zero,
            reference: 0x06,
            compare_mask: 0x0f,
            ..StencilFaceState::KEEP
        };
        let r = draw(
            Format::D24UnormS8Uint,
            1.0,
            0x55,
            &[(quad(0.5, RED, true), DepthStencilState::DISABLED.with_stencil(face))],
            backend,
        );
        assert!(r.stencil.iter().all(|s| *s == 0));
        assert!(r.color.chunks(4).all(|p| p == [0, 0, 0, 255]));
        // Stencil passes, depth fails: depth-fail op.
        let face = StencilFaceState { depth_fail_op: StencilOp::IncrementAndClamp, ..StencilFaceState::KEEP };
        let state = DepthStencilState::LESS_WRITE.with_stencil(face);
        let r = draw(Format::D24UnormS8Uint, 0.25, 9, &[(quad(0.5, RED, true), state)], backend);
        assert!(r.stencil.iter().all(|s| *s == 10));
        assert!(r.depth.iter().all(|d| (d - 0.25).abs() < 1e-6));
    }
}

#[test]
fn front_and_back_faces_use_their_own_stencil_state() {
    for backend in Backend::ALL {
        let mut state = DepthStencilState::DISABLED.with_stencil(StencilFaceState::KEEP);
        state.front.pass_op = StencilOp::Replace;
        state.front.reference = 1;
        state.back.pass_op = StencilOp::Replace;
        state.back.reference = 2;
        let front = draw(Format::D24UnormS8Uint, 1.0, 0, &[(quad(0.5, RED, true), state)], backend);
        let back = draw(Format::D24UnormS8Uint, 1.0, 0, &[(quad(0.5, RED, false), state)], backend);
        assert!(front.stencil.iter().all(|s| *s == 1));
        assert!(back.stencil.iter().all(|s| *s == 2));
    }
}

#[test]
fn stencil_then_test_draws_only_where_marked() {
    for backend in Backend::ALL {
        // Mark the left half of the screen with 1, then draw green where the stencil is 1.
        let mark = StencilFaceState { pass_op: StencilOp::Replace, reference: 1, ..StencilFaceState::KEEP };
        let left = [
            v(-1.0, -1.0, 0.5, RED),
            v(-1.0, 1.0, 0.5, RED),
            v(0.0, 1.0, 0.5, RED),
            v(-1.0, -1.0, 0.5, RED),
            v(0.0, 1.0, 0.5, RED),
            v(0.0, -1.0, 0.5, RED),
        ];
        let test = StencilFaceState { compare: CompareOp::Equal, reference: 1, ..StencilFaceState::KEEP };
        let green = [0.0, 1.0, 0.0, 1.0];
        let r = draw(
            Format::D24UnormS8Uint,
            1.0,
            0,
            &[
                (left.to_vec(), DepthStencilState::DISABLED.with_stencil(mark)),
                (quad(0.5, green, true), DepthStencilState::DISABLED.with_stencil(test)),
            ],
            backend,
        );
        for y in 0..SIZE as usize {
            for x in 0..SIZE as usize {
                let px = &r.color[(y * SIZE as usize + x) * 4..][..4];
                let expected: &[u8] = if x < SIZE as usize / 2 { &[0, 255, 0, 255] } else { &[0, 0, 0, 255] };
                assert_eq!(px, expected, "{backend} ({x}, {y})");
            }
        }
    }
}

#[test]
fn per_draw_samples_passed_count_what_an_occlusion_query_sees() {
    for backend in Backend::ALL {
        let mut device = device(backend, 8, 2);
        let color = device.create_image(ImageDesc::new(SIZE, SIZE, Format::Rgba8Unorm)).unwrap();
        let ds = device.create_image(ImageDesc::new(SIZE, SIZE, Format::D32Float)).unwrap();
        let mut pass = color_pass(color, Some(DepthStencilAttachment::clear_discard(ds, 1.0)));
        let mut d = desc("occluder");
        d.depth_stencil = DepthStencilState::LESS_WRITE;
        let p = pipeline(FlatColor, d);
        let near = device.create_buffer_from(&quad(0.25, RED, true)).unwrap();
        let far = device.create_buffer_from(&quad(0.75, RED, true)).unwrap();
        let half = device.create_buffer_from(&quad(0.1, RED, true)[..3]).unwrap();
        pass.draw(Draw::new(&p, near, 0, 6));
        pass.draw(Draw::new(&p, far, 0, 6));
        pass.draw(Draw::new(&p, half, 0, 3));
        let report = device.submit(&pass).unwrap();
        let pixels = (SIZE * SIZE) as u64;
        assert_eq!(report.draws[0].samples_passed, pixels, "{backend}");
        assert_eq!(report.draws[1].samples_passed, 0, "{backend}: hidden behind the first");
        assert!(report.draws[2].samples_passed > pixels / 3 && report.draws[2].samples_passed < pixels * 2 / 3);
        assert_eq!(report.draws.iter().map(|d| d.primitives).collect::<Vec<_>>(), vec![2, 2, 1]);
    }
}
