//! Hidden-surface removal: the TBDR backend shades each covered sample once, with the surface
//! that ends up visible, whatever order opaque geometry was drawn in (seed 000 §23.7, seed 004
//! §24.2.2; PowerVR's "deferred" rendering).
//!
//! # How a tile's list is processed
//!
//! The list is cut into *segments* of consecutive primitives whose draws can wait for
//! visibility. For a segment, pass one rasterizes every primitive and runs the depth and
//! stencil tests (and their writes) in submission order, without shading; each sample that
//! passes is *claimed* in the visibility buffer by the primitive (its position in the list).
//! Pass two shades, for each primitive that still owns samples, exactly the samples it owns,
//! and writes their colours. Because pass one applies the real tests in order, the depth,
//! stencil and colour left in the tile are those in-order rendering leaves, for any compare
//! op and whether or not depth writes are on: tiler never needs in-order shading for depth
//! reasons, which is stricter than the seeds ask and keeps HSR on for more draws.
//!
//! A primitive whose draw cannot wait (see [`HsrFallback`]) ends the segment: the pending
//! segment is resolved and shaded first, then the primitive is rendered in order (with early-Z
//! where allowed), and a new segment starts after it. So HSR stays on for the opaque geometry
//! before and after translucent or alpha-tested draws, as on PowerVR. The counters record how
//! many fragments were rendered in order and why.
//!
//! A draw that writes no colour at all (a depth prepass) takes part in pass one but claims
//! nothing: its depth hides what is behind it, and the colour already in the tile stays.

use crate::api::format::ColorWrites;
use crate::api::pipeline::PipelineDesc;
use crate::api::shader::ShaderProperties;
pub use crate::ledger::hsr::HsrFallback;
use crate::raster::PixelRect;

/// How a draw takes part in hidden-surface removal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HsrMode {
    /// Waits for visibility; `claims` is false for draws that write no colour.
    Deferred { claims: bool },
    /// Rendered in submission order, for this reason.
    InOrder(HsrFallback),
}

impl HsrMode {
    /// Decides from the pipeline's state and its shader's properties, for a subpass with
    /// `color_count` colour attachments.
    pub fn of(desc: &PipelineDesc, properties: ShaderProperties, color_count: usize) -> HsrMode {
        if properties.side_effects {
            return HsrMode::InOrder(HsrFallback::SideEffects);
        }
        if properties.discards {
            return HsrMode::InOrder(HsrFallback::Discard);
        }
        if properties.reads_local {
            return HsrMode::InOrder(HsrFallback::PixelLocalRead);
        }
        if properties.writes_depth {
            return HsrMode::InOrder(HsrFallback::ShaderDepth);
        }
        if properties.writes_sample_mask {
            return HsrMode::InOrder(HsrFallback::SampleMask);
        }
        if desc.multisample.alpha_to_coverage {
            return HsrMode::InOrder(HsrFallback::AlphaToCoverage);
        }
        let targets = &desc.color_targets[..desc.color_targets.len().min(color_count)];
        if targets.iter().any(|t| t.blend.is_some() && t.write_mask != ColorWrites::NONE) {
            return HsrMode::InOrder(HsrFallback::Blending);
        }
        let full = targets.iter().filter(|t| t.write_mask == ColorWrites::ALL).count();
        let none = targets.iter().filter(|t| t.write_mask == ColorWrites::NONE).count();
        if full + none != targets.len() || (full > 0 && none > 0) {
            return HsrMode::InOrder(HsrFallback::PartialWriteMask);
        }
        HsrMode::Deferred { claims: full > 0 }
    }
}

/// No primitive owns the sample: the colour in the tile buffer stays.
pub const NO_OWNER: u32 = u32::MAX;

/// The visibility buffer: which list entry owns each sample of the tile. One per worker,
/// reused from tile to tile (tile-sized, like the tile buffer; a tag buffer on PowerVR).
pub struct Visibility {
    owners: Vec<u32>,
    tile_width: usize,
    plane: usize,
    origin: (i32, i32),
    /// Scratch: which entries of the current segment own samples, from `first_visible` on.
    visible: Vec<bool>,
    first_visible: u32,
}

impl Visibility {
    pub fn new(tile_width: u32, tile_height: u32, samples: u32) -> Visibility {
        let plane = (tile_width * tile_height) as usize;
        Visibility {
            owners: vec![NO_OWNER; plane * samples as usize],
            tile_width: tile_width as usize,
            plane,
            origin: (0, 0),
            visible: Vec::new(),
            first_visible: 0,
        }
    }

    /// Starts a segment in the tile whose top-left pixel is that of `tile`: nothing owned.
    pub fn reset(&mut self, tile: &PixelRect) {
        self.origin = (tile.x0, tile.y0);
        self.owners.fill(NO_OWNER);
    }

    #[inline(always)]
    fn index(&self, sample: usize, x: i32, y: i32) -> usize {
        sample * self.plane + (y - self.origin.1) as usize * self.tile_width + (x - self.origin.0) as usize
    }

    #[inline(always)]
    pub fn owner(&self, sample: usize, x: i32, y: i32) -> u32 {
        self.owners[self.index(sample, x, y)]
    }

    #[inline(always)]
    pub fn claim(&mut self, sample: usize, x: i32, y: i32, entry: u32) {
        let i = self.index(sample, x, y);
        self.owners[i] = entry;
    }

    /// Claims the pixels of `mask` (bit `8·row + column`) of sample `s` in the 8×8 block at
    /// `(x, y)` for `entry`.
    #[inline]
    pub fn claim_block(&mut self, sample: usize, x: i32, y: i32, mask: u64, entry: u32) {
        if mask == 0 {
            return;
        }
        let whole_rows = x >= self.origin.0 && x + 8 <= self.origin.0 + self.tile_width as i32;
        if whole_rows && mask == u64::MAX {
            // The whole block (the common case of HSR: a primitive covering it and in front):
            // one bounds check, then eight row stores. (Inlined into the pixel pipeline, this
            // made the overdraw shader's loop spill: +3% on front to back, measured.)
            let (first, pitch) = (self.index(sample, x, y), self.tile_width);
            let block = &mut self.owners[first..first + 7 * pitch + 8];
            for r in 0..8 {
                let row: &mut [u32; 8] = (&mut block[r * pitch..][..8]).try_into().expect("eight owners");
                *row = [entry; 8];
            }
            return;
        }
        self.claim_partial(sample, x, y, mask, entry, whole_rows);
    }

    /// Claims every pixel of sample `sample` in `rect` (inside the tile) for `entry`: what
    /// [`Visibility::claim_block`] of each whole block of it does, as one fill a row (one in
    /// all when `rect` spans the tile's width).
    pub fn claim_rect(&mut self, sample: usize, rect: &PixelRect, entry: u32) {
        let (x0, y0) = self.origin;
        let height = (self.plane / self.tile_width.max(1)) as i32;
        assert!(
            rect.x0 >= x0 && rect.y0 >= y0 && rect.x1 <= x0 + self.tile_width as i32 && rect.y1 <= y0 + height,
            "{rect:?} outside the tile at {:?}",
            self.origin
        );
        if rect.x0 >= rect.x1 || rect.y0 >= rect.y1 {
            return;
        }
        let width = (rect.x1 - rect.x0) as usize;
        let first = self.index(sample, rect.x0, rect.y0);
        let rows = (rect.y1 - rect.y0) as usize;
        if width == self.tile_width {
            self.owners[first..first + rows * width].fill(entry);
        } else {
            for row in 0..rows {
                let start = first + row * self.tile_width;
                self.owners[start..start + width].fill(entry);
            }
        }
    }

    /// [`Visibility::claim_block`] for a block not wholly covered or not wholly in the tile.
    #[inline(never)]
    fn claim_partial(&mut self, sample: usize, x: i32, y: i32, mask: u64, entry: u32, whole_rows: bool) {
        for r in 0..8 {
            let bits = (mask >> (8 * r)) as u8;
            if bits == 0 {
                continue;
            }
            if whole_rows {
                let i = self.index(sample, x, y + r);
                for (c, owner) in self.owners[i..i + 8].iter_mut().enumerate() {
                    if bits >> c & 1 != 0 {
                        *owner = entry;
                    }
                }
            } else {
                for c in 0..8 {
                    if bits >> c & 1 != 0 {
                        self.claim(sample, x + c, y + r, entry);
                    }
                }
            }
        }
    }

    /// The pixels of sample `s` in the 8×8 block at `(x, y)` that `entry` owns (bit
    /// `8·row + column`); pixels outside the tile are not owned.
    #[inline]
    pub fn owned_block(&self, sample: usize, x: i32, y: i32, entry: u32) -> u64 {
        let (x0, y0) = self.origin;
        let rows = self.owners.len() / self.plane.max(1);
        let height = (self.plane / self.tile_width.max(1)) as i32;
        debug_assert!(rows > sample);
        let whole_rows = x >= x0 && x + 8 <= x0 + self.tile_width as i32;
        let mut mask = 0u64;
        for r in 0..8 {
            let py = y + r;
            if py < y0 || py >= y0 + height {
                continue;
            }
            let mut bits = 0u64;
            if whole_rows {
                let i = self.index(sample, x, py);
                for (c, owner) in self.owners[i..i + 8].iter().enumerate() {
                    bits |= ((*owner == entry) as u64) << c;
                }
            } else {
                for c in 0..8 {
                    let px = x + c;
                    if px >= x0 && px < x0 + self.tile_width as i32 {
                        bits |= ((self.owner(sample, px, py) == entry) as u64) << c;
                    }
                }
            }
            mask |= bits << (8 * r);
        }
        mask
    }

    /// Finds the entries in `first..first + count` that own at least one sample; [`owners`]
    /// then lists them in order. The flags are per-worker scratch kept from segment to segment
    /// (no allocation per segment in steady state).
    ///
    /// [`owners`]: Visibility::owners
    pub fn mark_owners(&mut self, first: u32, count: usize) {
        self.first_visible = first;
        self.visible.clear();
        self.visible.resize(count, false);
        // Owners come in long runs (a primitive claims whole rows and blocks): compare eight at
        // a time with the last owner marked and look closer only where one differs.
        let mut last = NO_OWNER;
        for chunk in self.owners.chunks(8) {
            if chunk.iter().fold(true, |same, &o| same & (o == last)) {
                continue;
            }
            for &owner in chunk {
                if owner != last {
                    last = owner;
                    if owner != NO_OWNER && owner >= first && ((owner - first) as usize) < count {
                        self.visible[(owner - first) as usize] = true;
                    }
                }
            }
        }
    }

    /// The entries [`Visibility::mark_owners`] found, in order.
    pub fn owners(&self) -> impl Iterator<Item = u32> + '_ {
        let first = self.first_visible;
        self.visible.iter().enumerate().filter(|(_, v)| **v).map(move |(i, _)| first + i as u32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::api::pipeline::{ColorTargetState, VertexInputState};

    #[test]
    fn owners_are_the_entries_that_own_samples() {
        let tile = PixelRect { x0: 32, y0: 64, x1: 64, y1: 96 };
        let mut v = Visibility::new(32, 32, 2);
        for round in 0..3u32 {
            v.reset(&tile);
            // Runs, single samples and blocks of entries in and out of the segment.
            let mut state = 12345u32.wrapping_add(round);
            for _ in 0..40 {
                state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                let entry = 90 + (state >> 20) % 30;
                let (s, x, y) =
                    ((state >> 8) as usize % 2, 32 + (state >> 12) as i32 % 32, 64 + (state >> 3) as i32 % 32);
                if state % 3 == 0 {
                    v.claim_block(s, x & !7, y & !7, u64::MAX >> (state % 64), entry);
                } else {
                    v.claim(s, x, y, entry);
                }
            }
            let (first, count) = (95 + round, 17usize);
            let mut expected: Vec<u32> =
                v.owners.iter().copied().filter(|&o| o >= first && o < first + count as u32).collect();
            expected.sort_unstable();
            expected.dedup();
            v.mark_owners(first, count);
            assert_eq!(v.owners().collect::<Vec<_>>(), expected, "round {round}");
            assert!(!expected.is_empty());
        }
    }

    #[test]
    fn what_switches_hsr_off() {
        let desc = PipelineDesc::new("p", VertexInputState::default());
        let props = ShaderProperties::default();
        assert_eq!(HsrMode::of(&desc, props, 1), HsrMode::Deferred { claims: true });
        let discard = ShaderProperties { discards: true, ..props };
        assert_eq!(HsrMode::of(&desc, discard, 1), HsrMode::InOrder(HsrFallback::Discard));
        let mut blend = desc.clone();
        blend.color_targets = vec![ColorTargetState::ALPHA_BLEND];
        assert_eq!(HsrMode::of(&blend, props, 1), HsrMode::InOrder(HsrFallback::Blending));
        let mut prepass = desc.clone();
        prepass.color_targets[0].write_mask = ColorWrites::NONE;
        assert_eq!(HsrMode::of(&prepass, props, 1), HsrMode::Deferred { claims: false });
        let mut partial = desc.clone();
        partial.color_targets[0].write_mask = ColorWrites::COLOR;
        assert_eq!(HsrMode::of(&partial, props, 1), HsrMode::InOrder(HsrFallback::PartialWriteMask));
        let mut a2c = desc;
        a2c.multisample.alpha_to_coverage = true;
        assert_eq!(HsrMode::of(&a2c, props, 1), HsrMode::InOrder(HsrFallback::AlphaToCoverage));
    }
}
