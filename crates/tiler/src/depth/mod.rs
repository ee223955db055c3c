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
use crate::api::pipeline::CompareOp;
use crate::api::pipeline::{DepthStencilState, StencilFaceState};
use crate::ledger::Ledger;
use crate::ledger::framebuffer::{Aspect, FramebufferTraffic};
use crate::raster::coverage::Coverage;
use crate::raster::target::{BlockDepth, Surface};
use crate::simd::{F32x8, LANE_DX, LANE_DY, LANES, LaneMask, U32x8, array_from_fn};

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
    // The samples below are read and written: a fill deferred in the summary is owed first.
    surface.write_deferred_block(x, y);
    let stencil_test = state.stencil_test && format.has_stencil();
    if !stencil_test && !traffic.needs_addresses() {
        let write = state.depth_test && state.depth_write;
        let compare = if state.depth_test { state.depth_compare } else { crate::api::pipeline::CompareOp::Always };
        let (passed, tested, written, written_depths) = match format {
            Format::D16Unorm => depth_only::<D16>(surface, x, y, coverage, compare, write, &depth),
            Format::D24UnormS8Uint => depth_only::<D24>(surface, x, y, coverage, compare, write, &depth),
            _ => depth_only::<D32>(surface, x, y, coverage, compare, write, &depth),
        };
        if written > 0 {
            surface.group_written(x, y, written_depths);
        }
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
    // The depth bits written, for the block summary (`min > max`: none).
    let mut written_depths = BlockDepth { min: u32::MAX, max: 0 };
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
            // The block summary is widened by what is written, below.
            let bytes = &mut surface.plane_mut_tracked(s)[offset..offset + format.bytes_per_sample()];
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
                written_depths = written_depths.union(BlockDepth::constant(fragment_depth));
                let bytes = format.depth_access_bytes(stencil_written) as u32;
                traffic.access(ledger, Aspect::Depth, address, bytes, true);
            }
            if new_depth != stored_depth || new_stencil != stored_stencil {
                pack(format, bytes, new_depth, new_stencil);
            }
        }
        passed.set_sample(s, LaneMask(pass));
    }
    if written_depths.min <= written_depths.max {
        surface.group_written(x, y, written_depths);
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
    // The lanes go through `U32x8` so that they stay one vector (see there: as arrays this was
    // twice the instructions, partly scalar).
    let row: &mut [u8; 32] = (&mut row[..32]).try_into().expect("a row of eight words");
    let words: [u32; 8] = array_from_fn(|c| u32::from_le_bytes(row[4 * c..4 * c + 4].try_into().unwrap()));
    let (words, fragment) = (U32x8::from_array(words).to_array(), U32x8::from_array(*fragment).to_array());
    // All ones where the lane is covered and passes.
    let take = U32x8::from_fn(|c| {
        let passes = compare(fragment[c], words[c] & depth_mask);
        if passes & (covered >> c & 1 != 0) { u32::MAX } else { 0 }
    });
    let pass = take.top_bits();
    if write && pass != 0 {
        let take = take.to_array();
        let out = U32x8::from_fn(|c| {
            let new = (words[c] & !depth_mask) | fragment[c];
            (words[c] & !take[c]) | (new & take[c])
        })
        .to_array();
        for (c, word) in out.iter().enumerate() {
            row[4 * c..4 * c + 4].copy_from_slice(&word.to_le_bytes());
        }
    }
    pass
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
}

/// The depth test without stencil, for the common case: per sample, the two rows of four
/// pixels of the group are tested against their stored depths, and passing samples written.
/// Returns the samples that passed, how many were tested and written, and the range of the
/// depth bits written (meaningful when some were).
#[inline(always)]
fn depth_only<D: DepthBits>(
    surface: &mut Surface,
    x: i32,
    y: i32,
    coverage: Coverage,
    compare: CompareOp,
    write: bool,
    depth: &impl Fn(usize) -> F32x8,
) -> (Coverage, u64, u64, BlockDepth) {
    let format = D::format();
    let rows = [surface.offset(x, y), surface.offset(x, y + 1)];
    let mut passed = coverage;
    let (mut tested, mut written) = (0, 0);
    let mut written_depths = BlockDepth { min: u32::MAX, max: 0 };
    for s in 0..surface.samples() {
        let lanes = coverage.sample(s);
        if lanes.is_empty() {
            continue;
        }
        let z = depth(s);
        let fragment = format.depth_bits_lanes(z);
        // The caller widens the block summary by `written_depths`.
        let plane = surface.plane_mut_tracked(s);
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
                    written_depths = written_depths.union(BlockDepth::constant(fragment[lane]));
                }
            }
        }
        tested += lanes.count() as u64;
        written += if write { pass.count_ones() as u64 } else { 0 };
        passed.set_sample(s, LaneMask(pass));
    }
    (passed, tested, written, written_depths)
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

    /// Depths bounding every lane of every row of every sample of the block at `(x, y)` from
    /// both sides (each of those depths lies between the least and the greatest lane, and none
    /// is NaN), or `None` when not known. [`RowDepths::constant`]'s value by default.
    fn bounds(&self, _x: i32, _y: i32) -> Option<F32x8> {
        self.constant().map(F32x8::splat)
    }
}

/// The range of the depth bits of `bounds` (see [`RowDepths::bounds`]): depth conversion is
/// monotonic, so it holds every converted depth they bound.
#[inline(always)]
fn bits_range(format: Format, bounds: Option<F32x8>) -> Option<BlockDepth> {
    let bounds = bounds?;
    let bits = format.depth_bits_lanes(bounds);
    Some(BlockDepth { min: bits.into_iter().min().unwrap_or(0), max: bits.into_iter().max().unwrap_or(u32::MAX) })
}

/// A flat primitive's depth bits in `format` (see [`RowDepths::constant`]), as
/// [`test_block`] converts them: computed once per primitive for [`settle_flat_block`].
#[inline(always)]
pub fn flat_depth_bits(format: Format, z: f32) -> BlockDepth {
    BlockDepth::constant(format.depth_bits_lanes(F32x8::splat(z))[0])
}

/// What a block's depth summary decides for a flat primitive ([`settle_flat_block`]).
pub enum FlatBlock {
    /// Every covered sample failed, or passed without a write: masks and counts are done.
    Settled,
    /// Every sample of the block passes and takes the primitive's depth: run
    /// [`fill_flat_block`] with the summary's index and range.
    Fill(usize, BlockDepth),
    /// The summary cannot tell: run [`test_block`].
    Test,
}

/// [`test_block`]'s first steps on their own, for a primitive whose depth bits over the block
/// are `fragment` (a flat primitive's, [`flat_depth_bits`]), with the same outcome: a block
/// that every covered sample fails, or passes without a write, is settled here — the same
/// masks and counts as `test_block`; a block to fill or to test sample by sample is handed
/// back unchanged. Small enough to inline into the pixel pipeline, so that a block hidden behind
/// nearer geometry (early Z of front-to-back drawing) costs no call.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn settle_flat_block(
    surface: &Surface,
    x: i32,
    y: i32,
    masks: &mut [u64],
    state: &DepthStencilState,
    fragment: BlockDepth,
    traffic: &mut FramebufferTraffic,
    ledger: &mut Ledger,
) -> FlatBlock {
    let Some((index, stored)) = surface.block_depth(x, y) else { return FlatBlock::Test };
    match decide(state.depth_compare, fragment, stored) {
        Some(pass) if !pass || !state.depth_write => {
            settle_block(masks, pass, surface.format.depth_access_bytes(false) as u32, traffic, ledger);
            FlatBlock::Settled
        }
        Some(_) if masks.len() == surface.samples() && masks.iter().all(|m| *m == u64::MAX) => {
            FlatBlock::Fill(index, stored)
        }
        _ => FlatBlock::Test,
    }
}

/// [`test_block`]'s fill: every sample of the 8×8 block at `(x, y)` (summary `index`, holding
/// `stored`) passes and takes the one depth `fragment` — in the summary, the bytes written when
/// next used (`raster::target::DepthBlocks`, deferred fills).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn fill_flat_block(
    surface: &mut Surface,
    x: i32,
    y: i32,
    index: usize,
    stored: BlockDepth,
    fragment: BlockDepth,
    traffic: &mut FramebufferTraffic,
    ledger: &mut Ledger,
) {
    let format = surface.format;
    let value = fragment.min;
    debug_assert_eq!(surface.block_depth(x, y).map(|(i, _)| i), Some(index), "block ({x}, {y})");
    if stored.value() != Some(value) {
        surface.defer_fill(index, value);
    }
    let (bytes, count) = (format.depth_access_bytes(false) as u32, 64 * surface.samples() as u64);
    traffic.accesses(ledger, Aspect::Depth, bytes, count, false);
    traffic.accesses(ledger, Aspect::Depth, bytes, count, true);
}

/// Every covered sample of `masks` passes (`pass`) or fails without a write: the masks and the
/// counts of testing them one by one.
#[inline(always)]
fn settle_block(masks: &mut [u64], pass: bool, bytes: u32, traffic: &mut FramebufferTraffic, ledger: &mut Ledger) {
    let count: u64 = masks.iter().map(|m| m.count_ones() as u64).sum();
    if !pass {
        masks.fill(0);
    }
    traffic.accesses(ledger, Aspect::Depth, bytes, count, false);
    traffic.accesses(ledger, Aspect::Depth, bytes, 0, true);
}

/// Decides a depth compare for every sample at once from the range of the fragment depths
/// (`fragment`) and of the stored ones (`stored`): `Some(true)` when every sample passes,
/// `Some(false)` when every sample fails, `None` when the ranges cannot tell.
#[inline(always)]
fn decide(compare: CompareOp, fragment: BlockDepth, stored: BlockDepth) -> Option<bool> {
    let (f, s) = (fragment, stored);
    let disjoint = || f.max < s.min || f.min > s.max;
    let one_value = || f.min == f.max && s.min == s.max && f.min == s.min;
    match compare {
        CompareOp::Never => Some(false),
        CompareOp::Always => Some(true),
        CompareOp::Less if f.max < s.min => Some(true),
        CompareOp::Less if f.min >= s.max => Some(false),
        CompareOp::LessOrEqual if f.max <= s.min => Some(true),
        CompareOp::LessOrEqual if f.min > s.max => Some(false),
        CompareOp::Greater if f.min > s.max => Some(true),
        CompareOp::Greater if f.max <= s.min => Some(false),
        CompareOp::GreaterOrEqual if f.min >= s.max => Some(true),
        CompareOp::GreaterOrEqual if f.max < s.min => Some(false),
        CompareOp::Equal if disjoint() => Some(false),
        CompareOp::Equal if one_value() => Some(true),
        CompareOp::NotEqual if disjoint() => Some(true),
        CompareOp::NotEqual if one_value() => Some(false),
        _ => None,
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
    let write = state.depth_write;
    let format = surface.format;
    let bytes = format.depth_access_bytes(false) as u32;
    // Hierarchical Z in the tile (`raster::target::DepthBlocks`): the range of the stored
    // depths of the block against the range of the primitive's depths over it.
    let samples = masks.len();
    let summary = surface.block_depth(x, y);
    // (No closures here: they would be compiled for the baseline instruction set.)
    let fragment = match (summary, depth.constant()) {
        (None, _) => None,
        // (The lanes' conversion: the scalar one saturates, which costs more.)
        (Some(_), Some(z)) => Some(BlockDepth::constant(format.depth_bits_lanes(F32x8::splat(z))[0])),
        (Some(_), None) => bits_range(format, depth.bounds(x, y)),
    };
    if let (Some((index, stored)), Some(fragment)) = (summary, fragment) {
        match decide(state.depth_compare, fragment, stored) {
            // Every covered sample fails, or passes without a write: one compare, the same
            // results and counts as testing them one by one.
            Some(pass) if !pass || !write => {
                settle_block(masks, pass, bytes, traffic, ledger);
                return;
            }
            // Every sample passes and takes the primitive's one depth: one fill.
            Some(_)
                if fragment.min == fragment.max
                    && samples == surface.samples()
                    && masks.iter().all(|m| *m == u64::MAX) =>
            {
                fill_flat_block(surface, x, y, index, stored, fragment, traffic, ledger);
                return;
            }
            _ => {}
        }
    }
    // Sample by sample from here: a fill deferred in the summary is owed first.
    match summary {
        Some((index, _)) => surface.write_deferred_index(index),
        None => surface.write_deferred_block(x, y),
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
        match (summary, fragment) {
            // Every sample passed and was written: the block holds the primitive's depths.
            (Some((index, _)), Some(fragment))
                if samples == surface.samples() && masks.iter().all(|m| *m == u64::MAX) =>
            {
                surface.set_block_depth(index, fragment)
            }
            _ => surface.block_written(x, y, fragment),
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
        // Only the rows with a covered pixel: a small triangle's block has two or three.
        let mut rows = occupied_rows(*mask);
        while rows != 0 {
            let r = rows.trailing_zeros() as i32;
            rows &= rows - 1;
            let bits = (*mask >> (8 * r)) as u8;
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

/// The rows of a block mask (bit `8·row + column`) with a bit set, as the bits of a byte: each
/// byte folded onto its lowest bit, and the eight lowest bits gathered into the top byte by one
/// multiplication (bit `8·r` times `2^(56 − 7·r)` lands on bit `56 + r`; no two products carry
/// into each other).
#[inline(always)]
fn occupied_rows(mask: u64) -> u32 {
    let t = mask | (mask >> 4);
    let t = t | (t >> 2);
    let t = t | (t >> 1);
    ((t & 0x0101_0101_0101_0101).wrapping_mul(0x0102_0408_1020_4080) >> 56) as u32
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
    use crate::api::pipeline::{StencilFaceState, StencilOp};
    use crate::raster::PixelRect;
    use crate::raster::target::DepthBlocks;
    use crate::shade::interpolate::Interpolator;
    use proptest::prelude::*;

    proptest! {
        /// A block mask's occupied rows are the rows with a bit set, whatever the mask.
        #[test]
        fn occupied_rows_are_the_rows_with_a_bit(mask in any::<u64>(), keep in any::<u8>()) {
            // Whole rows cleared by `keep`, so that empty rows are common.
            let mask = (0..8).filter(|r| keep >> r & 1 != 0).fold(0, |m, r| m | mask & 0xff << (8 * r));
            let rows = (0..8).filter(|r| mask >> (8 * r) & 0xff != 0).fold(0, |b, r| b | 1 << r);
            prop_assert_eq!(occupied_rows(mask), rows);
        }
    }

    #[test]
    fn occupied_rows_of_single_bits() {
        for bit in 0..64 {
            assert_eq!(occupied_rows(1 << bit), 1 << (bit / 8), "bit {bit}");
        }
        assert_eq!(occupied_rows(0), 0);
        assert_eq!(occupied_rows(u64::MAX), 0xff);
    }

    /// Fragment depths of a block: one value, one per sample, row and lane (no bounds), or a
    /// depth plane sampled at each sample's offset within the pixel.
    struct Depths {
        x: i32,
        y0: i32,
        constant: Option<f32>,
        lanes: Vec<[f32; 8]>,
        plane: Option<Interpolator>,
    }

    /// Offsets of the samples within the pixel for the plane depths (sample 0 at the centre).
    const SAMPLE_OFFSETS: [(f32, f32); 4] = [(0.5, 0.5), (0.375, 0.125), (0.875, 0.375), (0.125, 0.625)];

    impl Depths {
        fn sample_offset(&self, sample: usize) -> (f32, f32) {
            SAMPLE_OFFSETS[sample]
        }
    }

    impl RowDepths for Depths {
        fn row(&self, sample: usize, y: i32) -> F32x8 {
            match (self.constant, &self.plane) {
                (Some(z), _) => F32x8::splat(z),
                (None, Some(plane)) => {
                    let (dx, dy) = self.sample_offset(sample);
                    plane.row_depth(self.x, y, dx, dy)
                }
                (None, None) => F32x8::from_array(self.lanes[sample * 8 + (y - self.y0) as usize]),
            }
        }
        fn constant(&self) -> Option<f32> {
            self.constant
        }
        fn bounds(&self, x: i32, y: i32) -> Option<F32x8> {
            match (self.constant, &self.plane) {
                (Some(z), _) => Some(F32x8::splat(z)),
                (None, Some(plane)) => plane.depth_corners(x, y, [0.125, 0.875], [0.125, 0.625]),
                (None, None) => None,
            }
        }
    }

    /// Gradients of the plane depths: flat, tiny, ordinary, steep, and not finite.
    const GRADIENTS: [f32; 10] = [0.0, -0.0, 1e-6, -1e-6, 0.01, -0.03, 0.2, 1e30, f32::INFINITY, f32::NAN];

    /// Depths with ties and out-of-range values, so that every compare op sees equal, lesser
    /// and greater values and the conversion clamps.
    const DEPTHS: [f32; 8] = [0.0, -0.0, 0.25, 0.5, 0.75, 1.0, 1.5, -2.0];

    #[derive(Clone, Debug)]
    enum Step {
        /// Sets every sample's depth to `DEPTHS[depth]` (a clear: the summary restarts).
        Clear { depth: usize },
        /// Tests block `block` of the tile.
        Test { block: usize, compare: usize, write: bool, full: bool, masks: [u64; 4], depth: Depth },
        /// Tests one 4×2 group of the tile (`test_group`: late tests, discard, stencil), with
        /// a stencil test (that writes) when `stencil` and the format has stencil.
        Group { group: usize, compare: usize, write: bool, stencil: Option<(usize, u8)>, lanes: [u8; 4], depth: Depth },
    }

    #[derive(Clone, Debug)]
    enum Depth {
        Constant(usize),
        Lanes(Vec<usize>),
        /// A plane: depth `DEPTHS[z0]` at `origin`, gradients `GRADIENTS[dz]`.
        Plane {
            origin: (i8, i8),
            z0: usize,
            dz: (usize, usize),
        },
    }

    impl Depth {
        fn depths(&self, x: i32, y0: i32) -> Depths {
            match self {
                Depth::Constant(i) => Depths { x, y0, constant: Some(DEPTHS[*i]), lanes: Vec::new(), plane: None },
                Depth::Lanes(indices) => Depths {
                    x,
                    y0,
                    constant: None,
                    lanes: indices.chunks(8).map(|c| std::array::from_fn(|l| DEPTHS[c[l]])).collect(),
                    plane: None,
                },
                Depth::Plane { origin, z0, dz } => Depths {
                    x,
                    y0,
                    constant: None,
                    lanes: Vec::new(),
                    plane: Some(Interpolator::depth_plane(
                        [origin.0 as f32 + 40.0, origin.1 as f32 + 24.0],
                        DEPTHS[*z0],
                        [GRADIENTS[dz.0], GRADIENTS[dz.1]],
                    )),
                },
            }
        }
    }

    fn step() -> impl Strategy<Value = Step> {
        let depth = || {
            prop_oneof![
                3 => (0..DEPTHS.len()).prop_map(Depth::Constant),
                1 => proptest::collection::vec(0..DEPTHS.len(), 4 * 64).prop_map(Depth::Lanes),
                3 => (any::<(i8, i8)>(), 0..DEPTHS.len(), (0..GRADIENTS.len(), 0..GRADIENTS.len()))
                    .prop_map(|(origin, z0, dz)| Depth::Plane { origin, z0, dz }),
            ]
        };
        prop_oneof![
            1 => (0..DEPTHS.len()).prop_map(|depth| Step::Clear { depth }),
            6 => (0..4usize, 0..8usize, any::<bool>(), prop::bool::weighted(0.6), any::<[u64; 4]>(), depth())
                .prop_map(|(block, compare, write, full, masks, depth)| Step::Test { block, compare, write, full, masks, depth }),
            2 => (0..32usize, 0..8usize, any::<bool>(), proptest::option::of((0..8usize, any::<u8>())), any::<[u8; 4]>(), depth())
                .prop_map(|(group, compare, write, stencil, lanes, depth)| Step::Group { group, compare, write, stencil, lanes, depth }),
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
            let (mut states, mut deferred) = (vec![BlockDepth::UNKNOWN; 4], vec![0u64; 1]);
            let mut with_blocks = Surface::new(format, origin, side, summarised.chunks_mut(plane))
                .with_blocks(DepthBlocks::new(&mut states, &mut deferred, side / 8));
            with_blocks.start_blocks(&rect, None);
            let mut per_sample = Surface::new(format, origin, side, reference.chunks_mut(plane));
            let (mut traffic_a, mut traffic_b) = (FramebufferTraffic::on_chip(), FramebufferTraffic::on_chip());
            let (mut ledger_a, mut ledger_b) = (Ledger::default(), Ledger::default());
            let last = steps.len() - 1;
            for (i, step) in steps.into_iter().enumerate() {
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
                        let depths = depth.depths(x, y);
                        let mut masks_a: Vec<u64> = (0..samples).map(|s| if full { u64::MAX } else { masks[s] }).collect();
                        let mut masks_b = masks_a.clone();
                        prop_assert!(block_test_applies(&with_blocks, &state, &traffic_a));
                        test_block(&mut with_blocks, x, y, &mut masks_a, &state, &depths, &mut traffic_a, &mut ledger_a);
                        test_block(&mut per_sample, x, y, &mut masks_b, &state, &depths, &mut traffic_b, &mut ledger_b);
                        prop_assert_eq!(&masks_a, &masks_b);
                        prop_assert_eq!(traffic_a.on_chip_bytes, traffic_b.on_chip_bytes);
                    }
                    Step::Group { group, compare, write, stencil, lanes, depth } => {
                        // Groups of 4×2 pixels, four across and eight down the tile.
                        let (x, y) = (origin.0 + 4 * (group % 4) as i32, origin.1 + 2 * (group / 4) as i32);
                        let face = match stencil {
                            Some((op, reference)) => StencilFaceState {
                                compare: COMPARES[op],
                                fail_op: StencilOp::Invert,
                                depth_fail_op: StencilOp::IncrementAndWrap,
                                pass_op: StencilOp::Replace,
                                reference,
                                ..StencilFaceState::KEEP
                            },
                            None => StencilFaceState::KEEP,
                        };
                        let state = DepthStencilState {
                            depth_test: true,
                            depth_write: write,
                            depth_compare: COMPARES[compare],
                            stencil_test: stencil.is_some(),
                            front: face,
                            back: face,
                        };
                        let depths = depth.depths(x & !7, y & !7);
                        let at = |s: usize| match (&depths.plane, depths.constant) {
                            (_, Some(z)) => F32x8::splat(z),
                            (Some(plane), None) => {
                                let (dx, dy) = depths.sample_offset(s);
                                let (px, py) = Interpolator::positions(x, y, dx, dy);
                                plane.depth(px, py)
                            }
                            (None, None) => F32x8::from_array(depths.lanes[s * 8 + (y & 7) as usize]),
                        };
                        let mut coverage = Coverage::NONE;
                        for (s, bits) in lanes.iter().enumerate().take(samples) {
                            coverage.set_sample(s, LaneMask(*bits));
                        }
                        let a = test_group(&mut with_blocks, x, y, coverage, &state, true, at, &mut traffic_a, &mut ledger_a);
                        let b = test_group(&mut per_sample, x, y, coverage, &state, true, at, &mut traffic_b, &mut ledger_b);
                        prop_assert_eq!(a, b);
                        prop_assert_eq!(traffic_a.on_chip_bytes, traffic_b.on_chip_bytes);
                    }
                }
                // Deferred fills stay deferred over most steps (block and group tests write
                // them when they need the bytes); every third step and the last write them and
                // compare the bytes.
                if i % 3 == 2 || i == last {
                    with_blocks.write_deferred();
                    for s in 0..samples {
                        prop_assert_eq!(with_blocks.plane(s), per_sample.plane(s));
                    }
                }
            }
            prop_assert_eq!(ledger_a, ledger_b);
        }
    }

    proptest! {
        /// A row of eight packed depth words tested at once ([`words_row`], D24S8 and D32)
        /// against the lane-by-lane rule: which covered lanes pass, and the bytes after (depth
        /// bits of the lanes that pass replaced when writing, every other bit kept).
        #[test]
        fn a_row_of_words_is_tested_lane_by_lane(
            words in any::<[u32; 8]>(),
            fragment in any::<[u32; 8]>(),
            covered in any::<u8>(),
            write in any::<bool>(),
            compare in 0..8usize,
            d24 in any::<bool>(),
            ties in any::<u8>(),
        ) {
            let mask = if d24 { 0x00ff_ffff } else { u32::MAX };
            // Some lanes equal to what is stored, so that every op sees ties.
            let fragment: [u32; 8] =
                std::array::from_fn(|c| if ties >> c & 1 != 0 { words[c] & mask } else { fragment[c] & mask });
            let op = COMPARES[compare];
            let mut row: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
            let pass = words_row(&mut row, &fragment, covered, write, |a, b| op.test(a, b), mask);
            for c in 0..8 {
                let passes = covered >> c & 1 != 0 && op.test(fragment[c], words[c] & mask);
                prop_assert_eq!(pass >> c & 1 != 0, passes, "lane {}", c);
                let want = if passes && write { (words[c] & !mask) | fragment[c] } else { words[c] };
                prop_assert_eq!(u32::from_le_bytes(row[4 * c..4 * c + 4].try_into().unwrap()), want, "lane {}", c);
            }
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
        let (mut states, mut deferred) = (vec![BlockDepth::UNKNOWN; 1], vec![0u64; 1]);
        let mut surface = Surface::new(format, (0, 0), 8, [&mut bytes[..]]).with_blocks(DepthBlocks::new(
            &mut states,
            &mut deferred,
            1,
        ));
        surface.start_blocks(&rect, Some(format.depth_bits(1.0)));
        let (mut traffic, mut ledger) = (FramebufferTraffic::on_chip(), Ledger::default());
        let near = Depths { x: 0, y0: 0, constant: Some(0.25), lanes: Vec::new(), plane: None };
        let mut masks = [u64::MAX];
        test_block(&mut surface, 0, 0, &mut masks, &DepthStencilState::LESS_WRITE, &near, &mut traffic, &mut ledger);
        assert_eq!(masks, [u64::MAX]);
        assert_eq!(surface.block_depth(0, 0), Some((0, BlockDepth::constant(format.depth_bits(0.25)))));
        // The fill is deferred: the bytes are written when next used.
        assert!(surface.has_deferred());
        let far = Depths { x: 0, y0: 0, constant: Some(0.5), lanes: Vec::new(), plane: None };
        test_block(&mut surface, 0, 0, &mut masks, &DepthStencilState::LESS_WRITE, &far, &mut traffic, &mut ledger);
        assert_eq!(masks, [0]);
        // Tested 64 + 64 samples, written 64, four bytes each.
        assert_eq!(traffic.on_chip_bytes, (64 + 64 + 64) * 4);
        // A partial block widens the range by what it wrote.
        let mut masks = [1u64];
        let nearer = Depths { x: 0, y0: 0, constant: Some(0.125), lanes: Vec::new(), plane: None };
        test_block(&mut surface, 0, 0, &mut masks, &DepthStencilState::LESS_WRITE, &nearer, &mut traffic, &mut ledger);
        let range = BlockDepth { min: format.depth_bits(0.125), max: format.depth_bits(0.25) };
        assert_eq!(surface.block_depth(0, 0), Some((0, range)));
        // A sloped primitive wholly behind the range is rejected from it, covering the block or
        // not, without reading a sample: the bytes stay as they are.
        let before = surface.plane(0).to_vec();
        let behind = Interpolator::depth_plane([0.0, 0.0], 0.3, [0.01, 0.02]);
        let sloped = Depths { x: 0, y0: 0, constant: None, lanes: Vec::new(), plane: Some(behind) };
        for covered in [u64::MAX, 0x00ff_ff00] {
            let mut masks = [covered];
            test_block(
                &mut surface,
                0,
                0,
                &mut masks,
                &DepthStencilState::LESS_WRITE,
                &sloped,
                &mut traffic,
                &mut ledger,
            );
            assert_eq!(masks, [0]);
        }
        assert_eq!(surface.plane(0), &before[..]);
        // One in front over the whole block passes and leaves the block the range of its
        // corners (those `Depths::bounds` gives, for any of the four samples' offsets).
        let front = Interpolator::depth_plane([0.0, 0.0], 0.01, [0.001, 0.002]);
        let sloped = Depths { x: 0, y0: 0, constant: None, lanes: Vec::new(), plane: Some(front) };
        let mut masks = [u64::MAX];
        test_block(&mut surface, 0, 0, &mut masks, &DepthStencilState::LESS_WRITE, &sloped, &mut traffic, &mut ledger);
        assert_eq!(masks, [u64::MAX]);
        let corners = front.depth_corners(0, 0, [0.125, 0.875], [0.125, 0.625]).unwrap();
        assert_eq!(surface.block_depth(0, 0).map(|(i, b)| (i, Some(b))), Some((0, bits_range(format, Some(corners)))));
        assert_eq!(
            stored_depth_bits(format, &surface.plane(0)[..4]),
            format.depth_bits(0.01 + 0.5 * 0.001 + 0.5 * 0.002)
        );
        // A deferred fill is written before an untracked write forgets the summary.
        surface.start_blocks(&rect, Some(0));
        let mut masks = [u64::MAX];
        let greater = DepthStencilState { depth_compare: CompareOp::Greater, ..DepthStencilState::LESS_WRITE };
        test_block(&mut surface, 0, 0, &mut masks, &greater, &near, &mut traffic, &mut ledger);
        assert!(surface.has_deferred());
        assert_eq!(stored_depth_bits(format, &surface.plane_mut(0)[..4]), format.depth_bits(0.25));
        assert!(!surface.has_deferred());
        // An untracked write forgets all of the summary.
        surface.start_blocks(&rect, Some(0));
        let _ = surface.plane_mut(0);
        assert_eq!(surface.block_depth(0, 0), None);
    }
}
