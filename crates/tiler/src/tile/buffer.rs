//! The tile buffer: on-chip memory holding one tile of every attachment, every sample, in the
//! attachment's own format.

use crate::api::format::Format;
use crate::raster::PixelRect;
use crate::raster::target::{BlockDepth, DepthBlocks, Surface};

/// Storage for one tile of each attachment of a render pass. One per worker thread, reused
/// from tile to tile.
pub struct TileBuffer {
    tile_width: usize,
    tile_height: usize,
    attachments: Vec<(Format, usize, Vec<u8>)>,
    /// Per attachment, the per-8×8-block depth summary of a depth attachment (empty for colour,
    /// and for tiles whose sides are not multiples of 8): see `raster::target::DepthBlocks`.
    blocks: Vec<(Vec<BlockDepth>, Vec<u64>)>,
}

impl TileBuffer {
    /// For attachments given as `(format, samples)`.
    pub fn new(tile_width: u32, tile_height: u32, attachments: &[(Format, u32)]) -> TileBuffer {
        let (w, h) = (tile_width as usize, tile_height as usize);
        let blocks_fit = w % 8 == 0 && h % 8 == 0;
        TileBuffer {
            blocks: attachments
                .iter()
                .map(|&(format, _)| {
                    let summary = blocks_fit && format.has_depth();
                    let count = if summary { (w / 8) * (h / 8) } else { 0 };
                    (vec![BlockDepth::UNKNOWN; count], vec![0; DepthBlocks::deferred_words(count)])
                })
                .collect(),
            tile_width: w,
            tile_height: h,
            attachments: attachments
                .iter()
                .map(|&(format, samples)| {
                    (format, samples as usize, vec![0u8; w * h * samples as usize * format.bytes_per_sample()])
                })
                .collect(),
        }
    }

    /// Bytes of tile memory per tile (all attachments, all samples).
    pub fn bytes(&self) -> usize {
        self.attachments.iter().map(|a| a.2.len()).sum()
    }

    /// Views of every attachment for the tile whose top-left pixel is that of `tile`.
    pub fn surfaces(&mut self, tile: &PixelRect) -> Vec<Surface<'_>> {
        let plane_pixels = self.tile_width * self.tile_height;
        let stride = self.tile_width;
        let columns = self.tile_width / 8;
        self.attachments
            .iter_mut()
            .zip(&mut self.blocks)
            .map(|((format, _samples, data), (blocks, deferred))| {
                let plane_bytes = plane_pixels * format.bytes_per_sample();
                let surface = Surface::new(*format, (tile.x0, tile.y0), stride, data.chunks_mut(plane_bytes));
                if blocks.is_empty() {
                    surface
                } else {
                    surface.with_blocks(DepthBlocks::new(blocks, deferred, columns))
                }
            })
            .collect()
    }

    pub fn tile_height(&self) -> usize {
        self.tile_height
    }
}
