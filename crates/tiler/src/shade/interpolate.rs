//! Interpolation of a primitive's depth and varyings at pixel centres and sample positions.
//!
//! Everything is computed from the primitive's planes at absolute pixel positions (relative to
//! its vertex 0), never accumulated across a tile, so results do not depend on tile size.
//! Varyings are perspective-correct: with screen-space barycentrics `λ1, λ2` and `q = 1/w`,
//! `b_k = λ_k·q_k / (λ0·q0 + λ1·q1 + λ2·q2)` (Vulkan "Barycentric Interpolation").

use crate::binning::frame_data::Primitive;
use crate::raster::fixed::SUBPIXEL_SCALE;
use crate::simd::{F32x8, LANE_DX, LANE_DY};

/// A primitive's interpolation planes.
#[derive(Clone, Copy, Debug)]
pub struct Interpolator {
    origin: [f32; 2],
    l1: [f32; 2],
    l2: [f32; 2],
    z: [f32; 3],
    q: [f32; 3],
}

impl Interpolator {
    pub fn new(p: &Primitive) -> Interpolator {
        Interpolator { origin: p.origin, l1: p.l1, l2: p.l2, z: p.z, q: p.q }
    }

    /// Window positions of the lanes of the group at `(x, y)`, offset within each pixel by
    /// `(dx, dy)` pixels (0.5, 0.5 for the centre).
    #[inline(always)]
    pub fn positions(x: i32, y: i32, dx: f32, dy: f32) -> (F32x8, F32x8) {
        let px = F32x8::from_fn(|i| (x + LANE_DX[i] as i32) as f32 + dx);
        let py = F32x8::from_fn(|i| (y + LANE_DY[i] as i32) as f32 + dy);
        (px, py)
    }

    /// Window positions of pixels `x..x + 8` of row `y`, offset within each pixel by
    /// `(dx, dy)`: per pixel exactly what [`Interpolator::positions`] gives.
    #[inline(always)]
    pub fn row_positions(x: i32, y: i32, dx: f32, dy: f32) -> (F32x8, F32x8) {
        let px = F32x8::from_fn(|i| (x + i as i32) as f32 + dx);
        (px, F32x8::splat(y as f32 + dy))
    }

    /// Screen-space barycentrics `(λ1, λ2)` at the given positions.
    #[inline(always)]
    pub fn lambdas(&self, px: F32x8, py: F32x8) -> (F32x8, F32x8) {
        let dx = px - self.origin[0];
        let dy = py - self.origin[1];
        (dx * self.l1[0] + dy * self.l1[1], dx * self.l2[0] + dy * self.l2[1])
    }

    /// Screen-space barycentrics at sample `(sx, sy)` (sub-pixels) of every lane.
    #[inline(always)]
    pub fn sample_lambdas(&self, x: i32, y: i32, sample: (i32, i32)) -> (F32x8, F32x8) {
        let scale = SUBPIXEL_SCALE as f32;
        let (px, py) = Self::positions(x, y, sample.0 as f32 / scale, sample.1 as f32 / scale);
        self.lambdas(px, py)
    }

    /// Window depth, linear in screen space.
    #[inline(always)]
    pub fn depth(&self, l1: F32x8, l2: F32x8) -> F32x8 {
        F32x8::splat(self.z[0]) + l1 * self.z[1] + l2 * self.z[2]
    }

    /// Perspective-correct barycentrics `(b1, b2)`.
    #[inline(always)]
    pub fn perspective(&self, l1: F32x8, l2: F32x8) -> (F32x8, F32x8) {
        let f0 = (F32x8::ONE - l1 - l2) * self.q[0];
        let f1 = l1 * self.q[1];
        let f2 = l2 * self.q[2];
        let inv = F32x8::ONE / (f0 + f1 + f2);
        (f1 * inv, f2 * inv)
    }
}
