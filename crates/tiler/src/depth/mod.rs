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
use crate::raster::target::Surface;
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
    // Depth alone: a packed D24S8 sample moves as a whole word.
    let bytes = surface.format.depth_access_bytes(false) as u32;
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
            let plane = surface.plane_mut(s);
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
