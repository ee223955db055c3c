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
        SubPixel((px * SUBPIXEL_SCALE as f64).round() as i32)
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

#[cfg(test)]
mod tests {
    use super::*;

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
