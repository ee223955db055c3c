//! Clipping: triangles crossing the near plane, vertices behind the eye (w ≤ 0), triangles
//! far larger than the guard band.

use super::common::*;
use tiler::*;

fn render_clip_space(width: u32, height: u32, verts: &[[f32; 4]], backend: Backend) -> (Vec<f32>, PassReport) {
    let mut device = device(backend, 16, 2);
    let color = device.create_image(ImageDesc::new(width, height, Format::Rgba32Float)).unwrap();
    let data: Vec<Vertex> = verts.iter().map(|p| [p[0], p[1], p[2], p[3], 1.0, 0.0, 0.0, 1.0]).collect();
    let buffer = device.create_buffer_from(&data).unwrap();
    let mut d = desc("clip");
    d.color_targets = vec![ColorTargetState { blend: Some(BlendState::ADDITIVE), write_mask: ColorWrites::ALL }];
    let mut pass = RenderPass::new(RenderPassDesc {
        color: vec![ColorAttachment::clear_store(color, [0.0; 4])],
        depth_stencil: None,
        render_area: None,
    });
    pass.draw(Draw::new(&pipeline(Solid([1.0, 0.0, 0.0, 0.0]), d), buffer, 0, data.len() as u32));
    let report = device.submit(&pass).unwrap();
    let counts = device
        .image_data(color)
        .unwrap()
        .chunks_exact(16)
        .map(|p| f32::from_le_bytes(p[..4].try_into().unwrap()))
        .collect();
    (counts, report)
}

/// A perspective projection (Vulkan conventions: y down, depth 0 at `near`), 90° field of
/// view, square aspect.
fn project(p: [f32; 3]) -> [f32; 4] {
    let (near, far) = (0.1f32, 100.0f32);
    // Camera at the origin looking down −z, y up in the world, y down in clip space.
    let x = p[0];
    let y = -p[1];
    let z = (far / (near - far)) * p[2] + (near * far) / (near - far);
    let w = -p[2];
    [x, y, z, w]
}

#[test]
fn a_floor_through_the_eye_is_clipped_not_mirrored() {
    // A floor at y = −1 from 20 units behind the eye to 90 in front, far wider than the view.
    let corners = [[-1000.0, -1.0, 20.0], [1000.0, -1.0, 20.0], [1000.0, -1.0, -90.0], [-1000.0, -1.0, -90.0]];
    let c = corners.map(project);
    let verts = [c[0], c[1], c[2], c[0], c[2], c[3]];
    assert!(c[0][3] < 0.0, "the near corners are behind the eye");
    let (size, half) = (64u32, 32usize);
    for backend in Backend::ALL {
        let (counts, report) = render_clip_space(size, size, &verts, backend);
        assert_eq!(report.counters.triangles_clipped, 2);
        for y in 0..size as usize {
            let row = &counts[y * size as usize..(y + 1) * size as usize];
            if y < half {
                assert!(row.iter().all(|c| *c == 0.0), "{backend}: row {y} above the horizon drawn: {row:?}");
            } else if y > half + 1 {
                assert!(row.iter().all(|c| *c == 1.0), "{backend}: row {y} below the horizon: {row:?}");
            }
        }
    }
}

#[test]
fn triangles_behind_the_eye_or_degenerate_in_w_draw_nothing() {
    let behind = [project([0.0, 0.0, 5.0]), project([1.0, 0.0, 5.0]), project([0.0, 1.0, 5.0])];
    // A point at infinity in direction (1, 1): the triangle is a wedge reaching off screen.
    let zero_w = [[1.0, 1.0, 0.0, 0.0], [0.5, 0.0, 0.5, 1.0], [0.0, 0.5, 0.5, 1.0]];
    let all_zero = [[0.0f32; 4]; 3];
    for backend in Backend::ALL {
        let (counts, report) = render_clip_space(16, 16, &behind, backend);
        assert!(counts.iter().all(|c| *c == 0.0));
        assert_eq!(report.counters.triangles_clip_rejected, 1);
        // A vertex at w = 0 is cut off by the w > 0 plane; what remains is drawn once, in the
        // lower right quarter towards which the point at infinity lies.
        let (counts, _) = render_clip_space(16, 16, &zero_w, backend);
        assert!(counts.iter().all(|c| *c <= 1.0));
        assert!(counts[15 * 16 + 15] == 1.0 && counts[0] == 0.0, "{counts:?}");
        let (counts, _) = render_clip_space(16, 16, &all_zero, backend);
        assert!(counts.iter().all(|c| *c == 0.0));
    }
}

#[test]
fn triangles_sharing_an_edge_across_the_near_plane_stay_watertight() {
    // A quad whose far edge is in front of the eye and near edge behind it, split along a
    // diagonal that crosses the near plane: after clipping, every covered pixel is covered once.
    let q = [[-3.0, -1.0, 4.0], [3.0, -1.0, 4.0], [2.0, 1.0, -6.0], [-2.5, 0.8, -5.0]].map(project);
    let verts = [q[0], q[1], q[2], q[0], q[2], q[3]];
    for backend in Backend::ALL {
        let (counts, _) = render_clip_space(48, 48, &verts, backend);
        assert!(counts.iter().all(|c| *c <= 1.0), "{backend}: overlap along the clipped diagonal");
        assert!(counts.iter().filter(|c| **c == 1.0).count() > 300);
        // No holes inside: each row's covered pixels are contiguous.
        for y in 0..48 {
            let row: Vec<bool> = (0..48).map(|x| counts[y * 48 + x] == 1.0).collect();
            let runs = row.windows(2).filter(|w| w[0] != w[1]).count();
            assert!(runs <= 2, "{backend}: row {y} has a hole: {row:?}");
        }
    }
}

#[test]
fn huge_triangles_cover_the_screen_exactly_once() {
    // Two triangles 10^7 pixels across, sharing a diagonal through the screen.
    let big = 1.0e5f32;
    let verts = [
        [-big, -big, 0.5, 1.0],
        [big, -big * 0.999, 0.5, 1.0],
        [big * 1.001, big, 0.5, 1.0],
        [-big, -big, 0.5, 1.0],
        [big * 1.001, big, 0.5, 1.0],
        [-big * 0.998, big, 0.5, 1.0],
    ];
    for backend in Backend::ALL {
        let (counts, report) = render_clip_space(37, 29, &verts, backend);
        assert!(counts.iter().all(|c| *c == 1.0), "{backend}: {:?}", counts);
        assert_eq!(report.counters.triangles_clipped, 2, "both cross the guard band");
    }
}
