//! Depth and stencil tests on the samples of a 4×2 group, in the tile buffer or (immediate
//! mode) in external memory.
//!
//! Order per sample (Vulkan "Fragment Operations"): stencil test, then depth test; the stencil
//! op is the fail op when the stencil test fails, the depth-fail op when only the depth test
//! fails, the pass op otherwise; depth is written only when both pass and writes are on.
//! Stored depths compare as integers (see `Format::depth_bits`), so UNORM and float depth
//! buffers need no special cases.

pub mod hsr;

use crate::api::format::Format;
use crate::api::pipeline::{DepthStencilState, StencilFaceState};
use crate::ledger::Ledger;
use crate::ledger::framebuffer::{Aspect, FramebufferTraffic};
use crate::raster::coverage::Coverage;
use crate::raster::target::{BlockDepth, Surface};
use crate::simd::{F32x8, LANE_DX, LANE_DY, LANES, LaneMask};

/// Tests the covered samples of the group at `(x, y)`, applies the stencil ops and depth
/// writes, and returns the samples that passed. `depth(s)` gives the fragment depths of
/// sample `s`. Every access goes through `traffic` (tile buffer, or external memory).
// Kept flat (measured code, not style): a pixel-pipeline kernel inlined into every shader's loop
// and run per 4×2 group. Its arguments are the group's position, coverage, state, facing and depths
// and the state it updates, which no single owner holds together; a parameter struct would be
// assembled per call in the hottest loop, and its code generation was tuned with the kernel bench.
#[allow(clippy::too_many_arguments)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn test_group(
    surface: &mut Surface,
    x: i32,
    y: i32,
    coverage: Coverage,
    state: &DepthStencilState,
    front_facing: bool,
    depth: impl Fn(usize) -> F32x8,
    traffic: &mut FramebufferTraffic,
    ledger: &mut Ledger,
) -> Coverage {
    let format = surface.format;
    let face: &StencilFaceState = if front_facing { &state.front } else { &state.back };
    let stencil_test = state.stencil_test && format.has_stencil();
    if !stencil_test && !traffic.needs_addresses() {
        let write = state.depth_test && state.depth_write;
        let compare = if state.depth_test { state.depth_compare } else { crate::api::pipeline::CompareOp::Always };
        let (passed, tested, written) = match format {
            Format::D16Unorm => depth_only::<D16>(surface, x, y, coverage, compare, write, &depth),
            Format::D24UnormS8Uint => depth_only::<D24>(surface, x, y, coverage, compare, write, &depth),
            _ => depth_only::<D32>(surface, x, y, coverage, compare, write, &depth),
        };
        // Depth alone: a packed D24S8 sample moves as a whole word.
        let bytes = format.depth_access_bytes(false) as u32;
        if state.depth_test {
            traffic.accesses(ledger, Aspect::Depth, bytes, tested, false);
        }
        traffic.accesses(ledger, Aspect::Depth, bytes, written, true);
        return passed;
    }
    let mut passed = coverage;
    // A packed D24S8 sample moves as one word: the aspects an access reads or writes share
    // its 4 bytes, an aspect alone costs all of them (`Format::depth_access_bytes`).
    let depth_read_bytes = format.depth_access_bytes(stencil_test) as u32;
    let stencil_read_bytes = format.stencil_access_bytes(state.depth_test) as u32;
    for s in 0..surface.samples() {
        let lanes = coverage.sample(s);
        if lanes.is_empty() {
            continue;
        }
        let z = depth(s);
        let mut pass = 0u8;
        for lane in 0..LANES {
            if !lanes.contains(lane) {
                continue;
            }
            let (px, py) = (x + LANE_DX[lane] as i32, y + LANE_DY[lane] as i32);
            let address = surface.address(s, px, py);
            if state.depth_test {
                traffic.access(ledger, Aspect::Depth, address, depth_read_bytes, false);
            }
            if stencil_test {
                traffic.access(ledger, Aspect::Stencil, address, stencil_read_bytes, false);
            }
            let offset = surface.offset(px, py);
            let bytes = &mut surface.plane_mut(s)[offset..offset + format.bytes_per_sample()];
            let (stored_depth, stored_stencil) = unpack(format, bytes);
            let stencil_pass = !stencil_test
                || face
                    .compare
                    .test((face.reference & face.compare_mask) as u32, (stored_stencil & face.compare_mask) as u32);
            let fragment_depth = format.depth_bits(z.lane(lane));
            let depth_pass = !state.depth_test || state.depth_compare.test(fragment_depth, stored_depth);
            let mut new_depth = stored_depth;
            let mut new_stencil = stored_stencil;
            let mut stencil_written = false;
            if stencil_test {
                let op = if !stencil_pass {
                    face.fail_op
                } else if !depth_pass {
                    face.depth_fail_op
                } else {
                    face.pass_op
                };
                let value = op.apply(stored_stencil, face.reference);
                new_stencil = (value & face.write_mask) | (stored_stencil & !face.write_mask);
                stencil_written = op != crate::api::pipeline::StencilOp::Keep && face.write_mask != 0;
            }
            let passes = stencil_pass && depth_pass;
            let depth_written = passes && state.depth_test && state.depth_write;
            if stencil_written {
                let bytes = format.stencil_access_bytes(depth_written) as u32;
                traffic.access(ledger, Aspect::Stencil, address, bytes, true);
            }
            if passes {
                pass |= 1 << lane;
            }
            if depth_written {
                new_depth = fragment_depth;
                let bytes = format.depth_access_bytes(stencil_written) as u32;
                traffic.access(ledger, Aspect::Depth, address, bytes, true);
            }
            if new_depth != stored_depth || new_stencil != stored_stencil {
                pack(format, bytes, new_depth, new_stencil);
            }
        }
        passed.set_sample(s, LaneMask(pass));
    }
    passed
}

/// How a depth format stores depth bits (the depth aspect only).
trait DepthBits {
    const BYTES: usize;
    fn load(bytes: &[u8]) -> u32;
    /// Writes the depth bits, leaving any stencil bits alone.
    fn store(bytes: &mut [u8], bits: u32);
    fn format() -> Format;

    /// Writes depth `bits` to a row of eight stored samples (the first `8 · BYTES` bytes of
    /// `row`), leaving any stencil bits alone.
    #[inline(always)]
    fn fill_row(row: &mut [u8], bits: u32) {
        for stored in row[..8 * Self::BYTES].chunks_exact_mut(Self::BYTES) {
            Self::store(stored, bits);
        }
    }

    /// Tests a whole row of eight stored samples (`row`, `8 · BYTES` bytes) against
    /// `fragment`, writes the passing ones when `write`, and returns which of `covered`
    /// passed. Rows are read and written whole (lanes that do not pass are written back
    /// unchanged), which vectorises.
    #[inline(always)]
    fn test_row(
        row: &mut [u8],
        fragment: &[u32; 8],
        covered: u8,
        write: bool,
        compare: impl Fn(u32, u32) -> bool,
    ) -> u8 {
        let stored: [u32; 8] = std::array::from_fn(|c| Self::load(&row[c * Self::BYTES..]));
        let pass = crate::simd::bool_bits(std::array::from_fn(|c| compare(fragment[c], stored[c]))) & covered;
        if write && pass != 0 {
            for c in 0..8 {
                if pass >> c & 1 != 0 {
                    Self::store(&mut row[c * Self::BYTES..], fragment[c]);
                }
            }
        }
        pass
    }
}

struct D16;
struct D24;
struct D32;

impl DepthBits for D16 {
    const BYTES: usize = 2;
    #[inline(always)]
    fn load(b: &[u8]) -> u32 {
        u16::from_le_bytes([b[0], b[1]]) as u32
    }
    #[inline(always)]
    fn store(b: &mut [u8], bits: u32) {
        b[..2].copy_from_slice(&(bits as u16).to_le_bytes());
    }
    fn format() -> Format {
        Format::D16Unorm
    }
}

impl DepthBits for D24 {
    const BYTES: usize = 4;
    #[inline(always)]
    fn load(b: &[u8]) -> u32 {
        u32::from_le_bytes([b[0], b[1], b[2], b[3]]) & 0x00ff_ffff
    }
    #[inline(always)]
    fn store(b: &mut [u8], bits: u32) {
        b[..3].copy_from_slice(&bits.to_le_bytes()[..3]);
    }
    fn format() -> Format {
        Format::D24UnormS8Uint
    }
    #[inline(always)]
    fn fill_row(row: &mut [u8], bits: u32) {
        fill_words(row, bits, 0x00ff_ffff);
    }
    #[inline(always)]
    fn test_row(
        row: &mut [u8],
        fragment: &[u32; 8],
        covered: u8,
        write: bool,
        compare: impl Fn(u32, u32) -> bool,
    ) -> u8 {
        words_row(row, fragment, covered, write, compare, 0x00ff_ffff)
    }
}

/// [`DepthBits::test_row`] for depth in the low bits (`depth_mask`) of 32-bit words: whole
/// words selected and stored at once, the other bits (stencil) kept.
#[inline(always)]
fn words_row(
    row: &mut [u8],
    fragment: &[u32; 8],
    covered: u8,
    write: bool,
    compare: impl Fn(u32, u32) -> bool,
    depth_mask: u32,
) -> u8 {
    let row: &mut [u8; 32] = (&mut row[..32]).try_into().expect("a row of eight words");
    let words: [u32; 8] = std::array::from_fn(|c| u32::from_le_bytes(row[4 * c..4 * c + 4].try_into().unwrap()));
    let pass = crate::simd::bool_bits(std::array::from_fn(|c| compare(fragment[c], words[c] & depth_mask))) & covered;
    if write && pass != 0 {
        let keep: [u32; 8] = std::array::from_fn(|c| if pass >> c & 1 != 0 { 0 } else { u32::MAX });
        for c in 0..8 {
            let new = (words[c] & !depth_mask) | fragment[c];
            let word = (words[c] & keep[c]) | (new & !keep[c]);
            row[4 * c..4 * c + 4].copy_from_slice(&word.to_le_bytes());
        }
    }
    pass
}

/// [`DepthBits::fill_row`] for depth in the low bits (`depth_mask`) of 32-bit words, whole
/// words at once (which vectorises), the other bits (stencil) kept.
#[inline(always)]
fn fill_words(row: &mut [u8], bits: u32, depth_mask: u32) {
    let row: &mut [u8; 32] = (&mut row[..32]).try_into().expect("a row of eight words");
    if depth_mask == u32::MAX {
        *row = words_bytes([bits; 8]);
        return;
    }
    let words: [u32; 8] = std::array::from_fn(|c| u32::from_le_bytes(row[4 * c..4 * c + 4].try_into().unwrap()));
    *row = words_bytes(words.map(|word| (word & !depth_mask) | bits));
}

/// Eight words as their 32 little-endian bytes.
#[inline(always)]
fn words_bytes(words: [u32; 8]) -> [u8; 32] {
    let mut bytes = [0u8; 32];
    for (chunk, word) in bytes.chunks_exact_mut(4).zip(words) {
        chunk.copy_from_slice(&word.to_le_bytes());
    }
    bytes
}

impl DepthBits for D32 {
    const BYTES: usize = 4;
    #[inline(always)]
    fn test_row(
        row: &mut [u8],
        fragment: &[u32; 8],
        covered: u8,
        write: bool,
        compare: impl Fn(u32, u32) -> bool,
    ) -> u8 {
        words_row(row, fragment, covered, write, compare, u32::MAX)
    }
    #[inline(always)]
    fn load(b: &[u8]) -> u32 {
        u32::from_le_bytes([b[0], b[1], b[2], b[3]])
    }
    #[inline(always)]
    fn store(b: &mut [u8], bits: u32) {
        b[..4].copy_from_slice(&bits.to_le_bytes());
    }
    fn format() -> Format {
        Format::D32Float
    }
    #[inline(always)]
    fn fill_row(row: &mut [u8], bits: u32) {
        fill_words(row, bits, u32::MAX);
    }
}

/// The depth test without stencil, for the common case: per sample, the two rows of four
/// pixels of the group are tested against their stored depths, and passing samples written.
/// Returns the samples that passed, and how many were tested and written.
#[inline(always)]
fn depth_only<D: DepthBits>(
    surface: &mut Surface,
    x: i32,
    y: i32,
    coverage: Coverage,
    compare: crate::api::pipeline::CompareOp,
    write: bool,
    depth: &impl Fn(usize) -> F32x8,
) -> (Coverage, u64, u64) {
    let format = D::format();
    let rows = [surface.offset(x, y), surface.offset(x, y + 1)];
    let mut passed = coverage;
    let (mut tested, mut written) = (0, 0);
    for s in 0..surface.samples() {
        let lanes = coverage.sample(s);
        if lanes.is_empty() {
            continue;
        }
        let z = depth(s);
        let fragment = format.depth_bits_lanes(z);
        let plane = surface.plane_mut(s);
        let mut pass = 0u8;
        for lane in 0..LANES {
            if !lanes.contains(lane) {
                continue;
            }
            let offset = rows[lane / 4] + (lane % 4) * D::BYTES;
            let stored = &mut plane[offset..offset + D::BYTES];
            if compare.test(fragment[lane], D::load(stored)) {
                pass |= 1 << lane;
                if write {
                    D::store(stored, fragment[lane]);
                }
            }
        }
        tested += lanes.count() as u64;
        written += if write { pass.count_ones() as u64 } else { 0 };
        passed.set_sample(s, LaneMask(pass));
    }
    (passed, tested, written)
}

/// Whether [`test_block`] can run the tests of `state` on `surface`: a depth test without a
/// stencil test, in memory whose accesses need no addresses (a tile buffer, or memory without
/// a cache model).
pub fn block_test_applies(surface: &Surface, state: &DepthStencilState, traffic: &FramebufferTraffic) -> bool {
    state.depth_test
        && !(state.stencil_test && surface.format.has_stencil())
        && !traffic.needs_addresses()
        && matches!(surface.format, Format::D16Unorm | Format::D24UnormS8Uint | Format::D32Float)
}

/// Fragment depths of the rows of a block, per sample.
pub trait RowDepths {
    /// The fragment depths of sample `sample` for the block's pixels of row `y`.
    fn row(&self, sample: usize, y: i32) -> F32x8;

    /// `Some(z)` when every row of every sample gives `z` in every lane (up to the sign of a
    /// zero): the primitive's depth is one value over the block.
    fn constant(&self) -> Option<f32> {
        None
    }
}

/// The depth bits of one stored sample (`bytes`, `format.bytes_per_sample()` of them).
pub(crate) fn stored_depth_bits(format: Format, bytes: &[u8]) -> u32 {
    unpack(format, bytes).0
}

/// The depth test (and writes) of a whole 8×8 block: `masks[s]` holds the covered pixels of
/// sample `s` (bit `8·row + column`) and keeps those that pass. `depth` gives the fragment
/// depths of each row. The caller has checked
/// [`block_test_applies`]. Counts the same accesses as [`test_group`].
// Kept flat (measured code, not style): a pixel-pipeline kernel inlined into every shader's loop
// and run per 8×8 block. Its arguments are the block's position, masks, state and depths and the
// state it updates, which no single owner holds together; a parameter struct would be assembled per
// call in the hottest loop, and its code generation was tuned with the kernel bench.
#[allow(clippy::too_many_arguments)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn test_block(
    surface: &mut Surface,
    x: i32,
    y: i32,
    masks: &mut [u64],
    state: &DepthStencilState,
    depth: &impl RowDepths,
    traffic: &mut FramebufferTraffic,
    ledger: &mut Ledger,
) {
    use crate::api::pipeline::CompareOp;
    let write = state.depth_write;
    // Hierarchical Z in the tile (`raster::target::DepthBlocks`): a block wholly covered, in
    // every sample, by a primitive of one depth.
    let samples = masks.len();
    // (The primitive's flatness first: it is two compares, the block's summary a lookup.)
    let full_constant = match depth.constant() {
        Some(z) if samples == surface.samples() && masks.iter().all(|m| *m == u64::MAX) => surface
            .block_depth(x, y)
            .map(|(index, known)| (index, known, surface.format.depth_bits_lanes(F32x8::splat(z))[0])),
        _ => None,
    };
    let bytes = surface.format.depth_access_bytes(false) as u32;
    if let Some((index, BlockDepth::Constant(stored), fragment)) = full_constant {
        // Every sample holds `stored`: one compare decides all of them, with the same
        // results, writes and counts as testing them one by one.
        let count = 64 * samples as u64;
        let written = if state.depth_compare.test(fragment, stored) {
            if write && fragment != stored {
                match surface.format {
                    Format::D16Unorm => fill_block::<D16>(surface, x, y, fragment),
                    Format::D24UnormS8Uint => fill_block::<D24>(surface, x, y, fragment),
                    _ => fill_block::<D32>(surface, x, y, fragment),
                }
                surface.set_block_depth(index, BlockDepth::Constant(fragment));
            }
            if write { count } else { 0 }
        } else {
            masks.fill(0);
            0
        };
        traffic.accesses(ledger, Aspect::Depth, bytes, count, false);
        traffic.accesses(ledger, Aspect::Depth, bytes, written, true);
        return;
    }
    macro_rules! run {
        ($d:ty) => {
            match state.depth_compare {
                CompareOp::Never => block_rows::<$d>(surface, x, y, masks, |_, _| false, write, depth),
                CompareOp::Less => block_rows::<$d>(surface, x, y, masks, |a, b| a < b, write, depth),
                CompareOp::Equal => block_rows::<$d>(surface, x, y, masks, |a, b| a == b, write, depth),
                CompareOp::LessOrEqual => block_rows::<$d>(surface, x, y, masks, |a, b| a <= b, write, depth),
                CompareOp::Greater => block_rows::<$d>(surface, x, y, masks, |a, b| a > b, write, depth),
                CompareOp::NotEqual => block_rows::<$d>(surface, x, y, masks, |a, b| a != b, write, depth),
                CompareOp::GreaterOrEqual => block_rows::<$d>(surface, x, y, masks, |a, b| a >= b, write, depth),
                CompareOp::Always => block_rows::<$d>(surface, x, y, masks, |_, _| true, write, depth),
            }
        };
    }
    let (tested, written) = match surface.format {
        Format::D16Unorm => run!(D16),
        Format::D24UnormS8Uint => run!(D24),
        _ => run!(D32),
    };
    if written > 0 {
        match full_constant {
            // Every sample passed and was written with the one fragment depth.
            Some((index, _, fragment)) if masks.iter().all(|m| *m == u64::MAX) => {
                surface.set_block_depth(index, BlockDepth::Constant(fragment))
            }
            _ => surface.block_written(x, y),
        }
    }
    // Depth alone: a packed D24S8 sample moves as a whole word.
    traffic.accesses(ledger, Aspect::Depth, bytes, tested, false);
    traffic.accesses(ledger, Aspect::Depth, bytes, written, true);
}

/// [`test_block`] for one depth format and compare op. Rows wholly inside the surface are
/// tested as eight lanes at once; others (a tile narrower than a block) lane by lane.
#[inline(always)]
fn block_rows<D: DepthBits>(
    surface: &mut Surface,
    x: i32,
    y: i32,
    masks: &mut [u64],
    compare: impl Fn(u32, u32) -> bool,
    write: bool,
    depth: &impl RowDepths,
) -> (u64, u64) {
    let format = D::format();
    let whole_rows = surface.holds_columns(x, x + 8);
    let (mut tested, mut written) = (0u64, 0u64);
    for (s, mask) in masks.iter_mut().enumerate() {
        if *mask == 0 {
            continue;
        }
        let mut kept = 0u64;
        for r in 0..8 {
            let bits = (*mask >> (8 * r)) as u8;
            if bits == 0 {
                continue;
            }
            let z = depth.row(s, y + r);
            let fragment = format.depth_bits_lanes(z);
            let offset = surface.offset(x, y + r);
            // `test_block` updates the block summary once the block is done.
            let plane = surface.plane_mut_tracked(s);
            let mut pass = 0u8;
            if whole_rows {
                pass = D::test_row(&mut plane[offset..offset + 8 * D::BYTES], &fragment, bits, write, &compare);
            } else {
                for (c, &fragment) in fragment.iter().enumerate() {
                    if bits >> c & 1 == 0 {
                        continue;
                    }
                    let at = offset + c * D::BYTES;
                    let stored = &mut plane[at..at + D::BYTES];
                    if compare(fragment, D::load(stored)) {
                        pass |= 1 << c;
                        if write {
                            D::store(stored, fragment);
                        }
                    }
                }
            }
            tested += bits.count_ones() as u64;
            written += if write { pass.count_ones() as u64 } else { 0 };
            kept |= (pass as u64) << (8 * r);
        }
        *mask = kept;
    }
    (tested, written)
}

/// Writes depth `bits` to every sample of the 8×8 block at `(x, y)` (wholly in `surface`),
/// leaving stencil bits alone. Inlined into the caller's instruction set: each row is one
/// 16- or 32-byte read, mask and write.
#[inline(always)]
fn fill_block<D: DepthBits>(surface: &mut Surface, x: i32, y: i32, bits: u32) {
    let first = surface.offset(x, y);
    let pitch = surface.offset(x, y + 1) - first;
    for s in 0..surface.samples() {
        let plane = surface.plane_mut_tracked(s);
        // One bounds check for the block's eight rows.
        let block = &mut plane[first..first + 7 * pitch + 8 * D::BYTES];
        for row in block.chunks_mut(pitch) {
            D::fill_row(row, bits);
        }
    }
}

/// Stored depth bits and stencil of one sample.
#[inline(always)]
fn unpack(format: Format, bytes: &[u8]) -> (u32, u8) {
    match format {
        Format::D16Unorm => (u16::from_le_bytes([bytes[0], bytes[1]]) as u32, 0),
        Format::D24UnormS8Uint => {
            let w = u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]);
            (w & 0x00ff_ffff, (w >> 24) as u8)
        }
        Format::D32Float => (u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]), 0),
        _ => unreachable!("depth test on colour format {format}"),
    }
}

#[inline(always)]
fn pack(format: Format, bytes: &mut [u8], depth: u32, stencil: u8) {
    match format {
        Format::D16Unorm => bytes.copy_from_slice(&(depth as u16).to_le_bytes()),
        Format::D24UnormS8Uint => bytes.copy_from_slice(&(depth | (stencil as u32) << 24).to_le_bytes()),
        Format::D32Float => bytes.copy_from_slice(&depth.to_le_bytes()),
        _ => unreachable!("depth write on colour format {format}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::api::pipeline::CompareOp;
    use crate::raster::PixelRect;
    use crate::raster::target::DepthBlocks;
    use proptest::prelude::*;

    /// Fragment depths of a block: one value, or one per sample, row and lane.
    struct Depths {
        y0: i32,
        constant: Option<f32>,
        lanes: Vec<[f32; 8]>,
    }

    impl RowDepths for Depths {
        fn row(&self, sample: usize, y: i32) -> F32x8 {
            match self.constant {
                Some(z) => F32x8::splat(z),
                None => F32x8(self.lanes[sample * 8 + (y - self.y0) as usize]),
            }
        }
        fn constant(&self) -> Option<f32> {
            self.constant
        }
    }

    /// Depths with ties and out-of-range values, so that every compare op sees equal, lesser
    /// and greater values and the conversion clamps.
    const DEPTHS: [f32; 8] = [0.0, -0.0, 0.25, 0.5, 0.75, 1.0, 1.5, -2.0];

    #[derive(Clone, Debug)]
    enum Step {
        /// Sets every sample's depth to `DEPTHS[depth]` (a clear: the summary restarts).
        Clear { depth: usize },
        /// Tests block `block` of the tile.
        Test { block: usize, compare: usize, write: bool, full: bool, masks: [u64; 4], depth: Depth },
    }

    #[derive(Clone, Debug)]
    enum Depth {
        Constant(usize),
        Lanes(Vec<usize>),
    }

    fn step() -> impl Strategy<Value = Step> {
        let depth = prop_oneof![
            3 => (0..DEPTHS.len()).prop_map(Depth::Constant),
            1 => proptest::collection::vec(0..DEPTHS.len(), 4 * 64).prop_map(Depth::Lanes),
        ];
        prop_oneof![
            1 => (0..DEPTHS.len()).prop_map(|depth| Step::Clear { depth }),
            6 => (0..4usize, 0..8usize, any::<bool>(), prop::bool::weighted(0.8), any::<[u64; 4]>(), depth)
                .prop_map(|(block, compare, write, full, masks, depth)| Step::Test { block, compare, write, full, masks, depth }),
        ]
    }

    const COMPARES: [CompareOp; 8] = [
        CompareOp::Never,
        CompareOp::Less,
        CompareOp::Equal,
        CompareOp::LessOrEqual,
        CompareOp::Greater,
        CompareOp::NotEqual,
        CompareOp::GreaterOrEqual,
        CompareOp::Always,
    ];

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]
        /// The per-block depth summary (hierarchical Z in the tile) against per-sample depth
        /// alone: every block test gives the same passing samples, the same access counts and
        /// the same stored bytes (stencil bits included), on every depth format.
        #[test]
        fn block_constant_depth_matches_per_sample_depth(
            format in prop_oneof![Just(Format::D16Unorm), Just(Format::D24UnormS8Uint), Just(Format::D32Float)],
            samples in prop_oneof![Just(1usize), Just(4usize)],
            initial in proptest::collection::vec(any::<u8>(), 16 * 16 * 4 * 4),
            steps in proptest::collection::vec(step(), 1..40),
        ) {
            // A 16×16 tile at (32, 16): four blocks.
            let (origin, side) = ((32, 16), 16usize);
            let rect = PixelRect::new(origin.0, origin.1, origin.0 + side as i32, origin.1 + side as i32);
            let plane = side * side * format.bytes_per_sample();
            let mut summarised = initial[..plane * samples].to_vec();
            let mut reference = summarised.clone();
            let mut states = vec![BlockDepth::Mixed; 4];
            let mut with_blocks = Surface::new(format, origin, side, summarised.chunks_mut(plane))
                .with_blocks(DepthBlocks::new(&mut states, side / 8));
            with_blocks.start_blocks(&rect, None);
            let mut per_sample = Surface::new(format, origin, side, reference.chunks_mut(plane));
            let (mut traffic_a, mut traffic_b) = (FramebufferTraffic::on_chip(), FramebufferTraffic::on_chip());
            let (mut ledger_a, mut ledger_b) = (Ledger::default(), Ledger::default());
            for step in steps {
                match step {
                    Step::Clear { depth } => {
                        let bits = format.depth_bits(DEPTHS[depth]);
                        for surface in [&mut with_blocks, &mut per_sample] {
                            for s in 0..samples {
                                for y in rect.y0..rect.y1 {
                                    let row = surface.row_mut(s, y, rect.x0, rect.x1);
                                    for stored in row.chunks_exact_mut(format.bytes_per_sample()) {
                                        let (_, stencil) = unpack(format, stored);
                                        pack(format, stored, bits, stencil);
                                    }
                                }
                            }
                        }
                        with_blocks.start_blocks(&rect, Some(bits));
                    }
                    Step::Test { block, compare, write, full, masks, depth } => {
                        let (x, y) = (origin.0 + 8 * (block % 2) as i32, origin.1 + 8 * (block / 2) as i32);
                        let state = DepthStencilState {
                            depth_test: true,
                            depth_write: write,
                            depth_compare: COMPARES[compare],
                            ..DepthStencilState::DISABLED
                        };
                        let depths = match depth {
                            Depth::Constant(i) => Depths { y0: y, constant: Some(DEPTHS[i]), lanes: Vec::new() },
                            Depth::Lanes(indices) => Depths {
                                y0: y,
                                constant: None,
                                lanes: indices.chunks(8).map(|c| std::array::from_fn(|l| DEPTHS[c[l]])).collect(),
                            },
                        };
                        let mut masks_a: Vec<u64> = (0..samples).map(|s| if full { u64::MAX } else { masks[s] }).collect();
                        let mut masks_b = masks_a.clone();
                        prop_assert!(block_test_applies(&with_blocks, &state, &traffic_a));
                        test_block(&mut with_blocks, x, y, &mut masks_a, &state, &depths, &mut traffic_a, &mut ledger_a);
                        test_block(&mut per_sample, x, y, &mut masks_b, &state, &depths, &mut traffic_b, &mut ledger_b);
                        prop_assert_eq!(&masks_a, &masks_b);
                        prop_assert_eq!(traffic_a.on_chip_bytes, traffic_b.on_chip_bytes);
                    }
                }
                for s in 0..samples {
                    prop_assert_eq!(with_blocks.plane(s), per_sample.plane(s));
                }
            }
            prop_assert_eq!(ledger_a, ledger_b);
        }
    }

    /// A block a flat primitive wholly covers, in front, is decided from the summary: after a
    /// clear, a nearer quad's depth becomes the block's one value, and a farther one is
    /// rejected without touching the samples.
    #[test]
    fn the_summary_follows_full_blocks_of_one_depth() {
        let format = Format::D24UnormS8Uint;
        let rect = PixelRect::new(0, 0, 8, 8);
        let mut bytes = vec![0u8; 64 * 4];
        let mut states = vec![BlockDepth::Mixed; 1];
        let mut surface =
            Surface::new(format, (0, 0), 8, [&mut bytes[..]]).with_blocks(DepthBlocks::new(&mut states, 1));
        surface.start_blocks(&rect, Some(format.depth_bits(1.0)));
        let (mut traffic, mut ledger) = (FramebufferTraffic::on_chip(), Ledger::default());
        let near = Depths { y0: 0, constant: Some(0.25), lanes: Vec::new() };
        let mut masks = [u64::MAX];
        test_block(&mut surface, 0, 0, &mut masks, &DepthStencilState::LESS_WRITE, &near, &mut traffic, &mut ledger);
        assert_eq!(masks, [u64::MAX]);
        assert_eq!(surface.block_depth(0, 0), Some((0, BlockDepth::Constant(format.depth_bits(0.25)))));
        let far = Depths { y0: 0, constant: Some(0.5), lanes: Vec::new() };
        test_block(&mut surface, 0, 0, &mut masks, &DepthStencilState::LESS_WRITE, &far, &mut traffic, &mut ledger);
        assert_eq!(masks, [0]);
        // Tested 64 + 64 samples, written 64, four bytes each.
        assert_eq!(traffic.on_chip_bytes, (64 + 64 + 64) * 4);
        // A partial block leaves the summary unknown; an untracked write forgets all of it.
        let mut masks = [1u64];
        let nearer = Depths { y0: 0, constant: Some(0.125), lanes: Vec::new() };
        test_block(&mut surface, 0, 0, &mut masks, &DepthStencilState::LESS_WRITE, &nearer, &mut traffic, &mut ledger);
        assert_eq!(surface.block_depth(0, 0), Some((0, BlockDepth::Mixed)));
        surface.start_blocks(&rect, Some(0));
        let _ = surface.plane_mut(0);
        assert_eq!(surface.block_depth(0, 0), None);
    }
}
