//! Backends: the same render pass, the same setup, rasterization and shading code, in a
//! different order of work and with the bytes going to different places.
//!
//! - [`Backend::Tbr`]: a tiler. Geometry for the whole pass is binned into frame data; then
//!   each tile runs its load ops into the tile buffer, its polygon list in submission order
//!   (with early-Z), and its store ops.
//! - [`Backend::Tbdr`]: a tiler with hidden-surface removal: each tile resolves visibility
//!   before shading, so each sample is shaded once by the surface that stays visible.
//! - [`Backend::Imr`]: immediate mode. Each draw's primitives go in submission order straight
//!   into the images in external memory, and every depth, stencil and colour access is traffic.
//!
//! Every backend gives the same image, bit for bit, for every tile size and thread count;
//! only the counters and the ledger differ.

pub mod imr;
pub mod pass;
pub mod tbr;

use serde::Serialize;

pub use crate::config::Backend;
use crate::ledger::{Counters, DrawStats, Ledger, TileStats, merge_draw_stats};
use crate::pixel::primitive::FragmentTally;
use crate::simd::SimdSupport;

/// What a pass did and moved, summed over its fragment tasks (bands of tiles or of rows) in a
/// fixed order: the one place both backends merge their tasks' counts.
pub(crate) struct PassTotals {
    pub counters: Counters,
    pub ledger: Ledger,
    pub draws: Vec<DrawStats>,
    /// Bytes moved on chip (tile buffer, framebuffer cache hits).
    pub on_chip_bytes: u64,
    /// Fragments shaded per pixel, when an overdraw map is wanted.
    pub overdraw: Option<Vec<u16>>,
}

impl PassTotals {
    pub fn new(draws: usize, overdraw_pixels: Option<usize>) -> PassTotals {
        PassTotals {
            counters: Counters::default(),
            ledger: Ledger::default(),
            draws: vec![DrawStats::default(); draws],
            on_chip_bytes: 0,
            overdraw: overdraw_pixels.map(|pixels| vec![0; pixels]),
        }
    }

    /// Adds what one fragment task did.
    pub fn add_tally(&mut self, tally: &FragmentTally) {
        if let (Some(map), Some(rows)) = (self.overdraw.as_mut(), tally.overdraw.as_ref()) {
            rows.add_to(map);
        }
        self.counters.merge(&tally.counters);
        // Every texel read is one lookup in the task's texture cache, hit or miss.
        let cache = &tally.context.texture_cache;
        self.counters.texels_read += cache.hits() + cache.misses();
        self.ledger.merge(&tally.ledger);
        merge_draw_stats(&mut self.draws, &tally.draws);
        self.on_chip_bytes += tally.framebuffer.on_chip_bytes;
    }
}

/// Samples written through blending in a pass: per draw, its samples that passed the depth
/// and stencil tests × its colour targets that blend.
pub fn samples_blended(pass: &crate::pass::RenderPass, draws: &[DrawStats]) -> u64 {
    pass.draws
        .iter()
        .zip(draws)
        .map(|(draw, stats)| {
            let blending = draw.pipeline.desc.color_targets.iter().filter(|t| t.blend.is_some()).count() as u64;
            stats.samples_passed * blending
        })
        .sum()
}

/// How a device runs a pass, beyond its configuration: not part of the model (every choice
/// gives the same image and counters).
#[derive(Clone, Copy, Debug)]
pub struct Workers {
    /// Worker threads in the device's pool.
    pub threads: usize,
    /// The pixel pipeline's instruction set, detected on this processor.
    pub simd: SimdSupport,
}

/// Frame-data figures of a pass (tilers only).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct FrameDataReport {
    /// The largest the frame data grew between flushes, modelled bytes.
    pub peak_bytes: u64,
    /// The largest host memory it held.
    pub peak_host_bytes: u64,
}

/// What a render pass did and cost.
#[derive(Clone, Debug, Serialize)]
pub struct PassReport {
    pub backend: Backend,
    pub width: u32,
    pub height: u32,
    pub samples: u32,
    /// The pixels the pass covered when fewer than the framebuffer's: the render area it was
    /// given, or the box its draws' scissors bound (`pass::resolved`); tiles outside it
    /// were neither loaded nor stored. `None`: the whole framebuffer.
    pub render_area: Option<crate::Rect>,
    pub tile_width: u32,
    pub tile_height: u32,
    /// The configured tile size, when the tile memory made the tile smaller.
    pub tile_shrunk_from: Option<(u32, u32)>,
    /// Tile memory used per tile: every attachment at every sample (tilers).
    pub tile_bytes: u64,
    pub tiles_x: u32,
    pub tiles_y: u32,
    pub ledger: Ledger,
    /// Bytes moved within on-chip memory: tile-buffer accesses of tilers (fragments, loads,
    /// stores, resolves), framebuffer-cache accesses of immediate mode. For energy.
    pub on_chip_bytes: u64,
    /// Bytes of tile stores transaction elimination skipped (unchanged tiles).
    pub transaction_elimination_saved: u64,
    /// Memory transient attachments did not need (their full size; tilers only, and only if
    /// they never spilled in an incremental render).
    pub transient_bytes_saved: u64,
    /// Fragments shaded per pixel, row-major, when the device records an overdraw map.
    pub overdraw_map: Option<Vec<u16>>,
    pub counters: Counters,
    pub frame_data: FrameDataReport,
    /// Per tile, row-major (tilers); empty for immediate mode.
    pub tiles: Vec<TileStats>,
    /// Per draw, in submission order.
    pub draws: Vec<DrawStats>,
}

impl PassReport {
    /// Shaded fragments per pixel of the render target.
    pub fn overdraw(&self) -> f64 {
        self.counters.fragments_shaded as f64 / (self.width as f64 * self.height as f64)
    }
}
