//! Lines and points as triangles: each segment of a line topology becomes a parallelogram of two
//! triangles in clip space, which then take the triangles' path (clip, setup, rasterize).
//!
//! GL ES 2.0 §3.4.2 rasterizes a non-antialiased line of width `w` as a parallelogram: an
//! x-major segment (`|Δx| ≥ |Δy|` in window space) covers, at each x between its endpoints, a
//! column of `w` pixels centred on the line; a y-major one a row. So the endpoints move by
//! `±w/2` pixels in window y (x-major) or x (y-major): `±w/2 / (viewport half-height) · clip w`
//! in clip space, which keeps the offset exact in pixels after the perspective divide. Width 1
//! is the same rule (the spec's "diamond exit" for width 1 may differ at the endpoints; within
//! the llvmpipe comparison's tolerance). Segments are cut at the near plane and at `w ≥ W_MIN`
//! first, so both endpoints have a window position; everything is in f32 on the vertices of
//! one segment, so every backend and tile gets the same triangles.

use glam::Vec4;

use crate::api::pipeline::MAX_VARYINGS;
use crate::geometry::clip::{ClipVertex, W_MIN};

/// The parallelogram of segment `a`–`b`, `width` pixels wide in a viewport of half-size
/// `half` (pixels): corners `[a−, b−, b+, a+]`, or `None` when nothing of it is in front of
/// the near plane. Its triangles are `(a−, b−, b+)` and `(a−, b+, a+)`.
pub fn parallelogram(
    a: ClipVertex,
    b: ClipVertex,
    width: f32,
    half: [f32; 2],
    varyings: usize,
) -> Option<[ClipVertex; 4]> {
    let (mut a, mut b) = (a, b);
    for distance in [|p: Vec4| p.z, |p: Vec4| p.w - W_MIN] {
        let (da, db) = (distance(a.position), distance(b.position));
        if da < 0.0 && db < 0.0 {
            return None;
        }
        // From the inside endpoint towards the outside one, as the triangle clipper does.
        if da < 0.0 {
            a = lerp(&b, &a, db / (db - da), varyings);
        } else if db < 0.0 {
            b = lerp(&a, &b, da / (da - db), varyings);
        }
    }
    let (pa, pb) = (a.position, b.position);
    let dx = (pb.x / pb.w - pa.x / pa.w) * half[0];
    let dy = (pb.y / pb.w - pa.y / pa.w) * half[1];
    // Offsets in NDC per unit of clip w.
    let offset = if dx.abs() >= dy.abs() {
        Vec4::new(0.0, width / 2.0 / half[1], 0.0, 0.0)
    } else {
        Vec4::new(width / 2.0 / half[0], 0.0, 0.0, 0.0)
    };
    let moved = |v: &ClipVertex, sign: f32| ClipVertex { position: v.position + sign * offset * v.position.w, ..*v };
    Some([moved(&a, -1.0), moved(&b, -1.0), moved(&b, 1.0), moved(&a, 1.0)])
}

/// The square of point `p`, `size` pixels wide, as corners `[top-left, top-right,
/// bottom-right, bottom-left]` (tiler's window y runs down), or `None` when its centre is outside
/// the depth range (GL ES 2.0 §2.13: a point is clipped by its position). `coord` is the
/// varying the corners set to `gl_PointCoord` (§3.3: s right, t down, 0 to 1 across the square).
/// Triangles `(0, 1, 2)` and `(0, 2, 3)`.
pub fn point_square(p: ClipVertex, size: f32, half: [f32; 2], coord: Option<usize>) -> Option<[ClipVertex; 4]> {
    let c = p.position;
    if c.z < 0.0 || c.z > c.w || c.w < W_MIN {
        return None;
    }
    let (ox, oy) = (size / 2.0 / half[0] * c.w, size / 2.0 / half[1] * c.w);
    let mut corners = [p; 4];
    for (v, (sx, sy)) in corners.iter_mut().zip([(-1.0f32, -1.0f32), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]) {
        v.position = c + Vec4::new(sx * ox, sy * oy, 0.0, 0.0);
        if let Some(k) = coord {
            v.varyings[k] = (sx + 1.0) / 2.0;
            v.varyings[k + 1] = (sy + 1.0) / 2.0;
        }
    }
    Some(corners)
}

fn lerp(from: &ClipVertex, to: &ClipVertex, t: f32, varyings: usize) -> ClipVertex {
    let mut v = [0.0; MAX_VARYINGS];
    for (out, (f, to)) in v.iter_mut().zip(from.varyings.iter().zip(&to.varyings)).take(varyings) {
        *out = f + t * (to - f);
    }
    ClipVertex { position: from.position + t * (to.position - from.position), varyings: v }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_x_major_segment_widens_in_y_by_half_the_width_each_side() {
        let a = ClipVertex::new(Vec4::new(-0.5, 0.0, 0.5, 2.0), &[1.0]);
        let b = ClipVertex::new(Vec4::new(0.5, 0.1, 0.5, 1.0), &[2.0]);
        let q = parallelogram(a, b, 4.0, [50.0, 50.0], 1).unwrap();
        // 4 pixels wide in a 100-pixel viewport: ±2 px = ±0.04 in NDC, times each w.
        assert!((q[0].position.y - (0.0 - 0.04 * 2.0)).abs() < 1e-6);
        assert!((q[3].position.y - (0.0 + 0.04 * 2.0)).abs() < 1e-6);
        assert!((q[1].position.y - (0.1 - 0.04)).abs() < 1e-6);
        assert_eq!(q[0].position.x, -0.5);
        assert_eq!((q[0].varyings[0], q[2].varyings[0]), (1.0, 2.0));
    }

    #[test]
    fn a_point_is_a_square_of_its_size_with_point_coords_at_the_corners() {
        let p = ClipVertex::new(Vec4::new(0.2, -0.4, 0.5, 2.0), &[7.0, 0.0, 0.0]);
        let q = point_square(p, 5.0, [50.0, 25.0], Some(1)).unwrap();
        // 2.5 pixels each side: 0.05 in NDC x, 0.1 in y, times w = 2.
        assert!((q[0].position.x - (0.2 - 0.1)).abs() < 1e-6 && (q[0].position.y - (-0.4 - 0.2)).abs() < 1e-6);
        assert!((q[2].position.x - (0.2 + 0.1)).abs() < 1e-6 && (q[2].position.y - (-0.4 + 0.2)).abs() < 1e-6);
        assert_eq!(q.map(|v| [v.varyings[1], v.varyings[2]]), [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
        assert!(q.iter().all(|v| v.varyings[0] == 7.0 && v.position.z == 0.5 && v.position.w == 2.0));
        let behind = ClipVertex { position: Vec4::new(0.0, 0.0, -0.1, 1.0), ..p };
        assert!(point_square(behind, 5.0, [50.0, 25.0], None).is_none());
    }

    #[test]
    fn a_segment_crossing_the_near_plane_is_cut_and_one_behind_it_vanishes() {
        let a = ClipVertex::new(Vec4::new(0.0, -0.5, -1.0, 1.0), &[0.0]);
        let b = ClipVertex::new(Vec4::new(0.0, 0.5, 1.0, 1.0), &[4.0]);
        let q = parallelogram(a, b, 1.0, [10.0, 10.0], 1).unwrap();
        assert_eq!(q[0].position.z, 0.0);
        assert_eq!(q[0].varyings[0], 2.0);
        assert!(
            parallelogram(a, ClipVertex { position: Vec4::new(0.0, 0.5, -0.5, 1.0), ..b }, 1.0, [10.0; 2], 1).is_none()
        );
    }
}
