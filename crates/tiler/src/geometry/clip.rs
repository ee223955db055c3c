//! Clipping in homogeneous clip space (Vulkan conventions: the view volume is `0 ≤ z ≤ w`).
//!
//! Triangles are clipped against the near (`z ≥ 0`) and far (`z ≤ w`) planes, against a
//! guard band (`|x| ≤ g_x·w`, `|y| ≤ g_y·w`, with `g` chosen so the band spans
//! [`GUARD_BAND_PX`] pixels either side of the viewport's centre), and against `w ≥ W_MIN`,
//! so no vertex with `w ≤ 0` ever reaches setup. Inside the guard band nothing is cut: the
//! rasterizer's scissor to the viewport does the rest exactly, and large triangles keep their
//! exact edges. Only triangles that cross the band or the depth planes are cut, with
//! Sutherland–Hodgman, and the resulting polygon is split as a fan.
//!
//! A new vertex is always interpolated from the inside endpoint of its edge towards the
//! outside one, so two triangles sharing an edge produce the same new vertex on it.

use glam::Vec4;

use crate::api::pipeline::{Interpolation, MAX_VARYINGS};
use crate::raster::fixed::GUARD_BAND_PX;

/// The smallest `w` a vertex may have after clipping.
pub const W_MIN: f32 = 1.0e-6;
/// Planes: near, far, left, right, top, bottom, `w ≥ W_MIN`.
const PLANES: usize = 7;
/// The most vertices a triangle clipped by every plane can have.
pub const MAX_CLIPPED_VERTICES: usize = 3 + PLANES;

/// The clip volume of one viewport.
#[derive(Clone, Copy, Debug)]
pub struct ClipVolume {
    guard_x: f32,
    guard_y: f32,
}

impl ClipVolume {
    /// For a viewport of `width × height` pixels.
    pub fn new(width: f32, height: f32) -> ClipVolume {
        ClipVolume {
            guard_x: (GUARD_BAND_PX / (width as f64 / 2.0)) as f32,
            guard_y: (GUARD_BAND_PX / (height as f64 / 2.0)) as f32,
        }
    }

    /// Signed distances to the planes; negative = outside.
    #[inline(always)]
    fn distances(&self, p: Vec4) -> [f32; PLANES] {
        [
            p.z,
            p.w - p.z,
            p.x + self.guard_x * p.w,
            self.guard_x * p.w - p.x,
            p.y + self.guard_y * p.w,
            self.guard_y * p.w - p.y,
            p.w - W_MIN,
        ]
    }

    /// Bit `i` set when the point is outside plane `i`.
    #[inline(always)]
    pub fn outcode(&self, p: Vec4) -> u8 {
        let d = self.distances(p);
        let mut code = 0;
        for (i, v) in d.iter().enumerate() {
            code |= ((*v < 0.0) as u8) << i;
        }
        code
    }
}

/// A vertex being clipped: clip position and varyings.
#[derive(Clone, Copy)]
pub struct ClipVertex {
    pub position: Vec4,
    pub varyings: [f32; MAX_VARYINGS],
}

impl ClipVertex {
    pub fn new(position: Vec4, varyings: &[f32]) -> ClipVertex {
        let mut v = [0.0; MAX_VARYINGS];
        v[..varyings.len()].copy_from_slice(varyings);
        ClipVertex { position, varyings: v }
    }

    fn lerp(inside: &ClipVertex, outside: &ClipVertex, t: f32, n: usize) -> ClipVertex {
        let mut v = *inside;
        v.position = inside.position + (outside.position - inside.position) * t;
        for i in 0..n {
            v.varyings[i] = inside.varyings[i] + (outside.varyings[i] - inside.varyings[i]) * t;
        }
        v
    }
}

/// A polygon produced by clipping.
pub struct ClippedPolygon {
    pub vertices: [ClipVertex; MAX_CLIPPED_VERTICES],
    pub len: usize,
}

/// Clips a triangle against the planes in `planes` (an OR of outcodes). Flat varyings of every
/// output vertex are copies of `triangle[0]`'s (the caller puts the provoking vertex's values
/// there), never interpolated. Returns `None` when nothing is left.
pub fn clip_triangle(
    volume: &ClipVolume,
    triangle: [ClipVertex; 3],
    planes: u8,
    interpolation: &[Interpolation],
) -> Option<ClippedPolygon> {
    let n = interpolation.len();
    let mut poly = ClippedPolygon { vertices: [triangle[0]; MAX_CLIPPED_VERTICES], len: 3 };
    poly.vertices[1] = triangle[1];
    poly.vertices[2] = triangle[2];
    let mut scratch = [triangle[0]; MAX_CLIPPED_VERTICES];
    for plane in 0..PLANES {
        if planes & (1 << plane) == 0 {
            continue;
        }
        let mut out = 0;
        for i in 0..poly.len {
            let cur = &poly.vertices[i];
            let next = &poly.vertices[(i + 1) % poly.len];
            let dc = volume.distances(cur.position)[plane];
            let dn = volume.distances(next.position)[plane];
            if dc >= 0.0 {
                scratch[out] = *cur;
                out += 1;
            }
            if (dc >= 0.0) != (dn >= 0.0) {
                scratch[out] = if dc >= 0.0 {
                    ClipVertex::lerp(cur, next, dc / (dc - dn), n)
                } else {
                    ClipVertex::lerp(next, cur, dn / (dn - dc), n)
                };
                out += 1;
            }
        }
        if out < 3 {
            return None;
        }
        poly.vertices[..out].copy_from_slice(&scratch[..out]);
        poly.len = out;
    }
    for (i, mode) in interpolation.iter().enumerate() {
        if *mode == Interpolation::Flat {
            let provoking = triangle[0].varyings[i];
            for v in &mut poly.vertices[..poly.len] {
                v.varyings[i] = provoking;
            }
        }
    }
    Some(poly)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f32, y: f32, z: f32, w: f32) -> ClipVertex {
        ClipVertex::new(Vec4::new(x, y, z, w), &[x, 7.0])
    }

    #[test]
    fn near_plane_cuts_a_triangle_into_a_quad() {
        let volume = ClipVolume::new(100.0, 100.0);
        // One vertex behind the near plane (z < 0), even with w < 0.
        let tri = [v(0.0, 0.0, 0.5, 1.0), v(0.5, 0.0, 0.5, 1.0), v(0.0, 0.5, -1.0, -0.5)];
        let planes = tri.iter().fold(0, |acc, t| acc | volume.outcode(t.position));
        let poly = clip_triangle(&volume, tri, planes, &[Interpolation::Perspective, Interpolation::Flat]).unwrap();
        assert_eq!(poly.len, 4);
        for vertex in &poly.vertices[..poly.len] {
            assert!(vertex.position.z >= 0.0 && vertex.position.w > 0.0);
            assert_eq!(vertex.varyings[1], 7.0);
        }
    }

    #[test]
    fn shared_edges_clip_to_the_same_point() {
        let volume = ClipVolume::new(100.0, 100.0);
        let a = v(0.0, 0.0, 0.5, 1.0);
        let b = v(0.3, 0.7, -2.0, 3.0);
        let c = v(0.9, 0.1, 0.2, 1.0);
        let d = v(-0.4, 0.6, 0.9, 1.2);
        let interp = [Interpolation::Perspective, Interpolation::Perspective];
        let one = clip_triangle(&volume, [a, b, c], 1, &interp).unwrap();
        let two = clip_triangle(&volume, [b, a, d], 1, &interp).unwrap();
        let originals = [a, b, c, d].map(|v| v.position);
        let new_points = |p: &ClippedPolygon| {
            p.vertices[..p.len].iter().map(|v| v.position).filter(|q| !originals.contains(q)).collect::<Vec<_>>()
        };
        let (one, two) = (new_points(&one), new_points(&two));
        let shared: Vec<_> = one.iter().filter(|p| two.contains(p)).collect();
        assert_eq!(shared.len(), 1, "the point where a–b crosses the near plane is identical");
    }
}
