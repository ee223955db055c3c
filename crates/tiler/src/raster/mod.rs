//! Rasterization: fixed-point positions, edge functions with the top-left rule, sample
//! locations, hierarchical coverage (block → 4×2 group → sample), and the per-primitive
//! fragment pipeline that every backend shares.

pub mod coverage;
pub mod edge;
pub mod fixed;
pub mod samples;
pub mod target;

/// A rectangle of pixels, `[x0, x1) × [y0, y1)` in window coordinates (y down).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct PixelRect {
    pub x0: i32,
    pub y0: i32,
    pub x1: i32,
    pub y1: i32,
}

impl PixelRect {
    pub const EMPTY: PixelRect = PixelRect { x0: 0, y0: 0, x1: 0, y1: 0 };

    pub const fn new(x0: i32, y0: i32, x1: i32, y1: i32) -> PixelRect {
        PixelRect { x0, y0, x1, y1 }
    }

    pub fn from_rect(rect: crate::Rect) -> PixelRect {
        PixelRect::new(rect.x as i32, rect.y as i32, rect.right() as i32, rect.bottom() as i32)
    }

    #[inline]
    pub fn is_empty(&self) -> bool {
        self.x0 >= self.x1 || self.y0 >= self.y1
    }

    #[inline]
    pub fn intersect(&self, other: &PixelRect) -> PixelRect {
        PixelRect::new(self.x0.max(other.x0), self.y0.max(other.y0), self.x1.min(other.x1), self.y1.min(other.y1))
    }

    #[inline]
    pub fn width(&self) -> i32 {
        (self.x1 - self.x0).max(0)
    }

    #[inline]
    pub fn height(&self) -> i32 {
        (self.y1 - self.y0).max(0)
    }

    /// Pixels inside (0 when empty).
    #[inline]
    pub fn area(&self) -> u64 {
        self.width() as u64 * self.height() as u64
    }
}
