//! The fill rule: a mesh covering a region covers every pixel exactly once; a triangle covers
//! exactly the samples an independent brute-force rasterizer says; binning lists a triangle
//! in every tile where it covers a sample, and not in tiles it only boxes.

use proptest::prelude::*;

use super::common::*;
use tiler::*;

/// Additive blending of 1.0 in red per fragment into an `Rgba32Float` image: red counts how
/// many fragments landed on each pixel.
fn count_fragments(
    width: u32,
    height: u32,
    window_vertices: &[[f64; 2]],
    backend: Backend,
    tile: u32,
) -> (Vec<f32>, PassReport) {
    let mut device = device(backend, tile, 2);
    let color = device.create_image(ImageDesc::new(width, height, Format::Rgba32Float)).unwrap();
    let verts: Vec<Vertex> = window_vertices
        .iter()
        .map(|p| {
            let x = (p[0] / width as f64 * 2.0 - 1.0) as f32;
            let y = (p[1] / height as f64 * 2.0 - 1.0) as f32;
            v(x, y, 0.5, [1.0, 0.0, 0.0, 1.0])
        })
        .collect();
    let buffer = device.create_buffer_from(&verts).unwrap();
    let mut d = desc("count");
    d.color_targets = vec![ColorTargetState { blend: Some(BlendState::ADDITIVE), write_mask: ColorWrites::ALL }];
    let mut pass = RenderPass::new(RenderPassDesc {
        color: vec![ColorAttachment::clear_store(color, [0.0; 4])],
        depth_stencil: None,
        render_area: None,
    });
    pass.draw(Draw::new(&pipeline(Solid([1.0, 0.0, 0.0, 0.0]), d), buffer, 0, verts.len() as u32));
    let report = device.submit(&pass).unwrap();
    let data = device.image_data(color).unwrap();
    let counts = data.chunks_exact(16).map(|px| f32::from_le_bytes(px[..4].try_into().unwrap())).collect();
    (counts, report)
}

/// A grid mesh whose border lies on the framebuffer's edges and whose inner vertices are
/// jittered by whole sub-pixels (including onto pixel centres and edges).
fn jittered_grid(width: u32, height: u32, cols: usize, rows: usize, jitter: &[(i32, i32)]) -> Vec<[f64; 2]> {
    let mut points = vec![[0.0f64; 2]; (cols + 1) * (rows + 1)];
    for r in 0..=rows {
        for c in 0..=cols {
            let mut x = width as f64 * c as f64 / cols as f64;
            let mut y = height as f64 * r as f64 / rows as f64;
            if c > 0 && c < cols && r > 0 && r < rows {
                let (jx, jy) = jitter[(r * (cols + 1) + c) % jitter.len()];
                x = (x * 256.0).round() / 256.0 + jx as f64 / 256.0;
                y = (y * 256.0).round() / 256.0 + jy as f64 / 256.0;
            }
            points[r * (cols + 1) + c] = [x, y];
        }
    }
    let mut triangles = Vec::new();
    for r in 0..rows {
        for c in 0..cols {
            let at = |rr: usize, cc: usize| points[rr * (cols + 1) + cc];
            let (a, b, cc, d) = (at(r, c), at(r, c + 1), at(r + 1, c), at(r + 1, c + 1));
            // Alternate the diagonal, and the winding, so both orientations and both
            // diagonals meet every rule.
            if (r + c) % 2 == 0 {
                triangles.extend([a, b, d, a, d, cc]);
            } else {
                triangles.extend([a, cc, b, b, cc, d]);
            }
        }
    }
    triangles
}

fn jitter_strategy() -> impl Strategy<Value = Vec<(i32, i32)>> {
    // Mostly arbitrary sub-pixel offsets, sometimes exactly on centres (±128) or corners.
    let offset = prop_oneof![-600i32..600, Just(0), Just(128), Just(-128), Just(256), Just(-256)];
    prop::collection::vec((offset.clone(), offset), 1..40)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn a_mesh_covers_every_pixel_exactly_once(
        cols in 2usize..7,
        rows in 2usize..7,
        jitter in jitter_strategy(),
        tile in prop::sample::select(vec![8u32, 16, 32]),
    ) {
        let (width, height) = (61, 43);
        let tris = jittered_grid(width, height, cols, rows, &jitter);
        for backend in Backend::ALL {
            let (counts, _) = count_fragments(width, height, &tris, backend, tile);
            let wrong: Vec<(usize, f32)> = counts.iter().copied().enumerate().filter(|(_, c)| *c != 1.0).collect();
            prop_assert!(wrong.is_empty(), "{backend}: pixels covered other than once: {:?}", &wrong[..wrong.len().min(10)]);
        }
    }

    #[test]
    fn coverage_matches_a_brute_force_rasterizer(
        pts in prop::collection::vec((-2000i64..12000, -2000i64..9000), 3),
        tile in prop::sample::select(vec![8u32, 16, 64]),
    ) {
        let (width, height) = (40u32, 30u32);
        let window: Vec<[f64; 2]> = pts.iter().map(|&(x, y)| [x as f64 / 256.0, y as f64 / 256.0]).collect();
        let expected = brute_force(&pts, width, height);
        for backend in Backend::ALL {
            let (counts, _) = count_fragments(width, height, &window, backend, tile);
            for (i, (c, e)) in counts.iter().zip(&expected).enumerate() {
                prop_assert_eq!(*c, *e as u8 as f32, "{} pixel ({}, {})", backend, i as u32 % width, i as u32 / width);
            }
        }
    }
}

/// Which pixel centres a triangle (in sub-pixels) covers, computed directly from the rule:
/// inside all three edges, or on an edge that is a top edge (horizontal, triangle below) or a
/// left edge (triangle to its right), for the triangle in either winding.
fn brute_force(p: &[(i64, i64)], width: u32, height: u32) -> Vec<bool> {
    let area = (p[1].0 - p[0].0) * (p[2].1 - p[0].1) - (p[1].1 - p[0].1) * (p[2].0 - p[0].0);
    let mut out = vec![false; (width * height) as usize];
    if area == 0 {
        return out;
    }
    let q = if area > 0 { [p[0], p[1], p[2]] } else { [p[0], p[2], p[1]] };
    for y in 0..height as i64 {
        for x in 0..width as i64 {
            let (sx, sy) = (x * 256 + 128, y * 256 + 128);
            let inside = (0..3).all(|i| {
                let (a, b) = (q[i], q[(i + 1) % 3]);
                // Cross product of the edge and the sample: positive inside (y down).
                let e = (b.0 - a.0) * (sy - a.1) - (b.1 - a.1) * (sx - a.0);
                let dy = b.1 - a.1;
                let top = dy == 0 && b.0 > a.0;
                let left = dy < 0;
                e > 0 || (e == 0 && (top || left))
            });
            out[(y * width as i64 + x) as usize] = inside;
        }
    }
    out
}

#[test]
fn binning_skips_tiles_a_triangle_only_boxes() {
    // A right triangle over tiles (0,0), (1,0), (0,1) of 16×16 tiles whose hypotenuse passes
    // short of tile (1,1), which its bounding box meets.
    let tris = [[2.0, 2.0], [28.0, 2.0], [2.0, 28.0]];
    let (counts, report) = count_fragments(32, 32, &tris, Backend::Tbr, 16);
    let listed: Vec<u32> = report.tiles.iter().map(|t| t.list_entries).collect();
    assert_eq!(listed, vec![1, 1, 1, 0]);
    // And every tile where it covers a pixel lists it.
    for (i, c) in counts.iter().enumerate() {
        let (x, y) = (i % 32, i / 32);
        if *c > 0.0 {
            assert_eq!(listed[(y / 16) * 2 + x / 16], 1);
        }
    }
}

#[test]
fn shared_edges_at_pixel_centres_follow_top_left() {
    // Two triangles sharing the vertical edge x = 4.5 (through pixel centres) and a
    // horizontal edge at y = 2.5: each centre on a shared edge goes to exactly one of them.
    let tris = [[0.0, 0.0], [4.5, 0.0], [4.5, 8.0], [4.5, 0.0], [9.0, 0.0], [4.5, 8.0]];
    let (counts, _) = count_fragments(9, 8, &tris, Backend::Tbr, 8);
    let column4: Vec<f32> = (0..8).map(|y| counts[y * 9 + 4]).collect();
    // The right triangle's edge at x = 4.5 is a left edge for it, so it owns those centres.
    assert!(column4.iter().all(|c| *c <= 1.0));
    let tris = [[0.0, 0.0], [8.0, 0.0], [0.0, 2.5], [8.0, 0.0], [8.0, 2.5], [0.0, 2.5]];
    let (counts, _) = count_fragments(8, 4, &tris, Backend::Imr, 8);
    // Row 2 has centres exactly on y = 2.5, the bottom edge of both triangles: not covered.
    assert_eq!(&counts[16..24], &[0.0; 8]);
    assert_eq!(&counts[8..16], &[1.0; 8]);
}
