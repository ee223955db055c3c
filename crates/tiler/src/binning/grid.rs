//! The tile grid: how a framebuffer is cut into tiles.

use crate::raster::PixelRect;

/// Tiles of `tile_width × tile_height` pixels over a `width × height` framebuffer, row-major.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TileGrid {
    pub tile_width: u32,
    pub tile_height: u32,
    pub width: u32,
    pub height: u32,
    pub tiles_x: u32,
    pub tiles_y: u32,
}

impl TileGrid {
    pub fn new(width: u32, height: u32, tile_width: u32, tile_height: u32) -> TileGrid {
        TileGrid {
            tile_width,
            tile_height,
            width,
            height,
            tiles_x: width.div_ceil(tile_width),
            tiles_y: height.div_ceil(tile_height),
        }
    }

    pub fn tile_count(&self) -> usize {
        (self.tiles_x * self.tiles_y) as usize
    }

    #[inline]
    pub fn index(&self, tile_x: u32, tile_y: u32) -> usize {
        (tile_y * self.tiles_x + tile_x) as usize
    }

    /// The pixels of a tile (cut at the framebuffer's edge).
    #[inline]
    pub fn tile_rect(&self, tile_x: u32, tile_y: u32) -> PixelRect {
        let x0 = tile_x * self.tile_width;
        let y0 = tile_y * self.tile_height;
        PixelRect::new(
            x0 as i32,
            y0 as i32,
            (x0 + self.tile_width).min(self.width) as i32,
            (y0 + self.tile_height).min(self.height) as i32,
        )
    }

    /// The inclusive range of tiles `(x0, y0, x1, y1)` a non-empty rectangle meets.
    #[inline]
    pub fn tiles_meeting(&self, rect: &PixelRect) -> (u32, u32, u32, u32) {
        debug_assert!(!rect.is_empty() && rect.x0 >= 0 && rect.y0 >= 0);
        // Tiles are usually powers of two: a shift, not a division, for every primitive binned.
        let (w, h) = (self.tile_width, self.tile_height);
        if w.is_power_of_two() && h.is_power_of_two() {
            let (sx, sy) = (w.trailing_zeros(), h.trailing_zeros());
            return (
                rect.x0 as u32 >> sx,
                rect.y0 as u32 >> sy,
                (rect.x1 as u32 - 1) >> sx,
                (rect.y1 as u32 - 1) >> sy,
            );
        }
        (rect.x0 as u32 / w, rect.y0 as u32 / h, (rect.x1 as u32 - 1) / w, (rect.y1 as u32 - 1) / h)
    }

    /// How many tiles a non-empty rectangle meets.
    #[inline]
    pub fn tiles_meeting_count(&self, rect: &PixelRect) -> u64 {
        let (x0, y0, x1, y1) = self.tiles_meeting(rect);
        (x1 - x0 + 1) as u64 * (y1 - y0 + 1) as u64
    }
}
