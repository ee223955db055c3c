//! Interpolation of a primitive's depth and varyings at pixel centres and sample positions.
//!
//! Everything is computed from the primitive's planes at absolute pixel positions (relative to
//! its vertex 0), never accumulated across a tile, so results do not depend on tile size.
//! Varyings are perspective-correct: with screen-space barycentrics `λ1, λ2` and `q = 1/w`,
//! `b_k = λ_k·q_k / (λ0·q0 + λ1·q1 + λ2·q2)` (Vulkan "Barycentric Interpolation").

use crate::geometry::primitive::Primitive;
use crate::raster::fixed::SUBPIXEL_SCALE;
use crate::simd::{F32x8, LANE_DX, LANE_DY};

/// A primitive's interpolation planes.
#[derive(Clone, Copy, Debug)]
pub struct Interpolator {
    origin: [f32; 2],
    l1: [f32; 2],
    l2: [f32; 2],
    /// Depth at the origin and its screen-space gradient:
    /// `z = (z0 + dy·dz/dy) + dx·dz/dx` with `(dx, dy)` from the origin.
    z0: f32,
    dz: [f32; 2],
    q: [f32; 3],
}

impl Interpolator {
    pub fn new(p: &Primitive) -> Interpolator {
        // The depth plane from the barycentric planes: z = z0 + λ1·(z1 − z0) + λ2·(z2 − z0).
        let dz = [0, 1].map(|axis| p.l1[axis] * p.z[1] + p.l2[axis] * p.z[2]);
        Interpolator { origin: p.origin, l1: p.l1, l2: p.l2, z0: p.z[0], dz, q: p.q }
    }

    /// Window positions of the lanes of the group at `(x, y)`, offset within each pixel by
    /// `(dx, dy)` pixels (0.5, 0.5 for the centre).
    #[inline(always)]
    pub fn positions(x: i32, y: i32, dx: f32, dy: f32) -> (F32x8, F32x8) {
        let px = F32x8::from_fn(|i| (x + LANE_DX[i] as i32) as f32 + dx);
        let py = F32x8::from_fn(|i| (y + LANE_DY[i] as i32) as f32 + dy);
        (px, py)
    }

    /// Screen-space barycentrics `(λ1, λ2)` at the given positions.
    #[inline(always)]
    pub fn lambdas(&self, px: F32x8, py: F32x8) -> (F32x8, F32x8) {
        let dx = px - self.origin[0];
        let dy = py - self.origin[1];
        (dx * self.l1[0] + dy * self.l1[1], dx * self.l2[0] + dy * self.l2[1])
    }

    /// Window positions at sample `(sx, sy)` (sub-pixels) of every lane of the group.
    #[inline(always)]
    pub fn sample_positions(x: i32, y: i32, sample: (i32, i32)) -> (F32x8, F32x8) {
        let scale = SUBPIXEL_SCALE as f32;
        Self::positions(x, y, sample.0 as f32 / scale, sample.1 as f32 / scale)
    }

    /// Window depth at the given positions, linear in screen space (the same formula
    /// wherever depth is needed, so every path tests and writes the same values).
    #[inline(always)]
    pub fn depth(&self, px: F32x8, py: F32x8) -> F32x8 {
        let row = (py - self.origin[1]) * self.dz[1] + self.z0;
        row + (px - self.origin[0]) * self.dz[0]
    }

    /// Window depth of pixels `x..x + 8` of row `y` at offset `(dx, dy)` within each pixel:
    /// per pixel exactly what [`Interpolator::depth`] gives at [`Interpolator::positions`].
    #[inline(always)]
    pub fn row_depth(&self, x: i32, y: i32, dx: f32, dy: f32) -> F32x8 {
        let row = (y as f32 + dy - self.origin[1]) * self.dz[1] + self.z0;
        let px = F32x8::from_fn(|i| (x + i as i32) as f32 + dx);
        F32x8::splat(row) + (px - self.origin[0]) * self.dz[0]
    }

    /// The depth of every point of a flat depth plane (both gradients zero, as for a quad
    /// facing the viewer), else `None`. Then [`Interpolator::depth`] and
    /// [`Interpolator::row_depth`] give `z0` at every position (`z0 ± 0`: the same value, or a
    /// zero of either sign, which depth conversion makes the same bits).
    #[inline(always)]
    pub fn constant_depth(&self) -> Option<f32> {
        (self.dz[0] == 0.0 && self.dz[1] == 0.0).then_some(self.z0)
    }

    /// Depths bounding [`Interpolator::row_depth`] over the rows `y..y + 8`, pixels
    /// `x..x + 8` and offsets within each pixel in `dx[0]..=dx[1]`, `dy[0]..=dy[1]`: its value
    /// at the four corners (lanes 0–3; the others repeat lane 0), computed with the same
    /// operations. Each operation rounds monotonically in each operand, so every depth it
    /// gives in that range lies between the corners' least and greatest. `None` when a
    /// gradient or a corner is not finite (then a depth inside could be NaN).
    #[inline(always)]
    pub fn depth_corners(&self, x: i32, y: i32, dx: [f32; 2], dy: [f32; 2]) -> Option<F32x8> {
        if !(self.dz[0].is_finite() && self.dz[1].is_finite()) {
            return None;
        }
        let row = |y: i32, dy: f32| (y as f32 + dy - self.origin[1]) * self.dz[1] + self.z0;
        let column = |x: i32, dx: f32| ((x as f32 + dx) - self.origin[0]) * self.dz[0];
        let rows = [row(y, dy[0]), row(y + 7, dy[1])];
        let columns = [column(x, dx[0]), column(x + 7, dx[1])];
        let corners = [rows[0] + columns[0], rows[0] + columns[1], rows[1] + columns[0], rows[1] + columns[1]];
        corners.iter().all(|z| z.is_finite()).then(|| F32x8::from_fn(|i| corners[if i < 4 { i } else { 0 }]))
    }

    /// An interpolator of depth alone: `z0` at `origin`, gradients `dz` (for tests of the
    /// depth paths).
    #[cfg(test)]
    pub(crate) fn depth_plane(origin: [f32; 2], z0: f32, dz: [f32; 2]) -> Interpolator {
        Interpolator { origin, l1: [0.0; 2], l2: [0.0; 2], z0, dz, q: [1.0; 3] }
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
