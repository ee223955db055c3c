//! Fixed-point window coordinates: 8 sub-pixel bits, and the bit budget that keeps every edge
//! function exact in 64-bit integers.
//!
//! Vertex positions are snapped to 1/256 pixel (Vulkan requires at least 8 sub-pixel bits).
//! The guard band bounds window coordinates: clipping (see `geometry::clip`) keeps every
//! vertex within [`GUARD_BAND_PX`] pixels of its viewport's centre, and viewports lie within
//! [`MAX_VIEWPORT_EXTENT_PX`] of the origin, so `|x|, |y| < 2^16` pixels, `< 2^24` sub-pixels.
//!
//! Edge functions `E(x, y) = A·x + B·y + C` then have `|A|, |B| < 2^25` (differences of two
//! coordinates), `|C| ≤ 2·2^24·2^25 = 2^50`, and at any sample inside the guard band
//! `|E| < 3·2^49 < 2^51` — far inside `i64`. Triangles within the guard band are rasterized
//! exactly, however large; only those crossing it are clipped.

/// Sub-pixel precision: positions are multiples of `1 / 2^SUBPIXEL_BITS` pixel.
pub const SUBPIXEL_BITS: u32 = 8;
/// Sub-pixels per pixel.
pub const SUBPIXEL_SCALE: i32 = 1 << SUBPIXEL_BITS;
/// Half the width of the guard band around a viewport's centre, in pixels.
pub const GUARD_BAND_PX: f64 = 32000.0;
/// Viewport corners must lie within this many pixels of the window origin.
pub const MAX_VIEWPORT_EXTENT_PX: f64 = 32768.0;
/// The largest window coordinate magnitude a snapped vertex can have, in pixels.
pub const MAX_COORDINATE_PX: i64 = 1 << 16;

/// The largest sub-pixel coordinate magnitude.
const MAX_SUBPIXEL: i64 = MAX_COORDINATE_PX * SUBPIXEL_SCALE as i64;

// Vertices inside the guard band of a valid viewport stay within the coordinate range (with
// room for rounding), coordinates fit `i32`, and an edge function — three terms, each a
// difference of coordinates times a coordinate — fits `i64` with room to spare.
const _: () = assert!(GUARD_BAND_PX + MAX_VIEWPORT_EXTENT_PX < MAX_COORDINATE_PX as f64);
const _: () = assert!(MAX_SUBPIXEL <= 1 << 24);
const _: () = assert!(3 * (2 * MAX_SUBPIXEL) * MAX_SUBPIXEL < i64::MAX / 4);

/// A window coordinate in sub-pixels (1/256 pixel).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct SubPixel(pub i32);

impl SubPixel {
    /// Snaps a window coordinate in pixels to the nearest sub-pixel (halves away from zero).
    /// The caller guarantees `|px| ≤ MAX_COORDINATE_PX` (the clipper does).
    #[inline]
    pub fn from_window(px: f64) -> SubPixel {
        debug_assert!(px.abs() <= MAX_COORDINATE_PX as f64, "{px} outside the guard band");
        SubPixel(round_half_away_to_i32(px * SUBPIXEL_SCALE as f64))
    }

    #[inline]
    pub fn raw(self) -> i64 {
        self.0 as i64
    }

    /// The coordinate in pixels.
    #[inline]
    pub fn to_pixels(self) -> f64 {
        self.0 as f64 / SUBPIXEL_SCALE as f64
    }

    /// The sub-pixel position of a pixel's corner.
    #[inline]
    pub fn pixel_corner(px: i32) -> i64 {
        (px as i64) << SUBPIXEL_BITS
    }

    /// The index of the pixel containing this position (rounding down).
    #[inline]
    pub fn floor_pixel(value: i64) -> i64 {
        value >> SUBPIXEL_BITS
    }

    /// The smallest pixel index whose corner is at or after `value`.
    #[inline]
    pub fn ceil_pixel(value: i64) -> i64 {
        (value + SUBPIXEL_SCALE as i64 - 1) >> SUBPIXEL_BITS
    }
}

/// `v.round() as i32` (nearest, halves away from zero, saturating, NaN to 0) without the call
/// to libm's `round` that `f64::round` is on the x86-64 baseline (no `roundsd` before SSE4.1):
/// six snaps a triangle, and `round` was 1.4% of tris' `perf` samples.
///
/// `v as i64` truncates toward zero (saturating; NaN gives 0) and `v - t` is the exact
/// fractional part (below 2^52 its bits are `v`'s own below the unit place; above, `v` is an
/// integer and it is 0), so
/// a step away from zero when it is at least a half is the nearest integer, halves away from
/// zero. Beyond `i32`'s range the clamps give what the saturating `as i32` gives; NaN
/// compares false and stays 0.
#[inline]
fn round_half_away_to_i32(v: f64) -> i32 {
    let t = v as i64;
    let frac = v - t as f64;
    // The step is added without a branch: a snap's fraction is as good as random, and the
    // branches were mispredicted half the time (tris, `perf annotate`). Clamping `t` first to
    // a range far outside `i32`'s leaves room for the step and changes no result.
    const FAR: i64 = 1 << 40;
    let r = t.clamp(-FAR, FAR) + (frac >= 0.5) as i64 - (frac <= -0.5) as i64;
    r.clamp(i32::MIN as i64, i32::MAX as i64) as i32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inline_rounding_matches_f64_round() {
        let mut values = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.5,
            -1.5,
            2.5,
            -2.5,
            0.49999999999999994,
            -0.49999999999999994,
            4503599627370495.5,
            -4503599627370495.5,
            4503599627370497.0,
            (1u64 << 24) as f64 + 0.5,
            -((1u64 << 24) as f64) - 0.5,
            2147483647.5,
            -2147483648.5,
            2147483646.5,
            1e300,
            -1e300,
            f64::MAX,
            f64::MIN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            9.3e18,
            -9.3e18,
        ];
        // Every quarter and neighbouring float around the halves over the snapped range, and
        // a deterministic spread of window coordinates times the sub-pixel scale.
        for i in -4096i32..=4096 {
            let h = i as f64 * 4099.0 + 0.5;
            values.extend([h, h.next_down(), h.next_up(), h - 0.25, h + 0.25]);
        }
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        for _ in 0..100_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let px = (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 * MAX_COORDINATE_PX as f64 - MAX_COORDINATE_PX as f64;
            values.push(px * SUBPIXEL_SCALE as f64);
        }
        for v in values {
            assert_eq!(round_half_away_to_i32(v), v.round() as i32, "{v:e}");
        }
    }

    #[test]
    fn snapping_rounds_to_nearest() {
        assert_eq!(SubPixel::from_window(1.0).0, 256);
        assert_eq!(SubPixel::from_window(0.5 / 256.0).0, 1);
        assert_eq!(SubPixel::from_window(-0.5 / 256.0).0, -1);
        assert_eq!(SubPixel::from_window(0.49 / 256.0).0, 0);
        assert_eq!(SubPixel::floor_pixel(-1), -1);
        assert_eq!(SubPixel::ceil_pixel(257), 2);
        assert_eq!(SubPixel::ceil_pixel(256), 1);
    }
}
