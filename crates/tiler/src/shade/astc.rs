//! Which ASTC blocks are legal: the checks the ASTC specification makes of a block before it
//! decodes one (Khronos Data Format Specification 1.3, §23.21 "Illegal Encodings", with the
//! LDR profile's rules for HDR content, KHR_texture_compression_astc_ldr).
//!
//! The specification decodes an illegal block as the error colour (magenta). tiler refuses the
//! upload instead, naming the block and the rule it breaks: no encoder writes such blocks, so
//! one in a capture is a damaged or misread upload, which a developer wants to hear about. The
//! decoder (`texture2ddecoder`) is handed legal blocks only: it checks none of these rules, and
//! on an illegal block it either panics (an out-of-range index or an overflow) or decodes
//! garbage without a word.
//!
//! The rules, with the block's 128 bits numbered from bit 0 of its first byte:
//!
//! - **Block mode** (bits 0–10): the two reserved layouts are illegal; the others give the
//!   weight grid's width and height, the weights' range, and whether there are two planes.
//! - **Weight grid**: no wider or taller than the block's footprint, at most 64 weights (both
//!   planes), and 24 to 96 bits of integer-sequence-encoded weights.
//! - **Partitions** (bits 11–12, one more than their value): not four with two planes.
//! - **Colour endpoint modes**: each partition's mode (bits 13–16 for one partition; for more,
//!   a selector at bits 23–24 and mode bits at 25–28 and just below the weights). HDR modes
//!   (2, 3, 7, 11, 14, 15) are illegal in the LDR profile. The modes' endpoint values, two per
//!   pair of components, number at most 18, and the bits left for them are at least
//!   `⌈13·n/5⌉`, the smallest range the encoding has (0–5).
//! - **Void-extent blocks** (bits 0–8 `0x1fc`, one constant colour): bits 10–11 are 1; the HDR
//!   flag (bit 9) is illegal in the LDR profile; the extent's coordinates (13 bits each from
//!   bit 12: low and high `s`, low and high `t`) are all ones, or each low below its high.

use std::fmt;

/// Why a block is illegal: the rule it breaks, with the values that break it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Illegal {
    /// The block mode is one of the two reserved layouts.
    ReservedBlockMode,
    /// A void-extent block's bits 10–11 are not both 1.
    VoidExtentReservedBits,
    /// A void-extent block's colour is HDR.
    VoidExtentHdr,
    /// A void-extent block's extent is neither all ones nor each low below its high.
    VoidExtentCoordinates,
    /// The weight grid is wider or taller than the footprint.
    GridLargerThanBlock { grid: (u32, u32), block: (u8, u8) },
    /// More than 64 weights.
    TooManyWeights(u32),
    /// The weights take fewer than 24 or more than 96 bits.
    WeightBits(u32),
    /// Four partitions with two weight planes.
    DualPlaneWithFourPartitions,
    /// An HDR colour endpoint mode.
    HdrEndpointMode(u32),
    /// More than 18 endpoint values.
    TooManyEndpointValues(u32),
    /// Fewer bits left for the endpoint values than their smallest range needs.
    TooFewEndpointBits { values: u32, available: i32 },
}

impl fmt::Display for Illegal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Illegal::ReservedBlockMode => write!(f, "its block mode is reserved"),
            Illegal::VoidExtentReservedBits => write!(f, "it is a void-extent block whose reserved bits are not 1"),
            Illegal::VoidExtentHdr => {
                write!(f, "it is an HDR void-extent block, which the LDR profile does not decode")
            }
            Illegal::VoidExtentCoordinates => {
                write!(f, "it is a void-extent block whose extent has a low coordinate not below its high")
            }
            Illegal::GridLargerThanBlock { grid: (w, h), block: (bw, bh) } => {
                write!(f, "its {w}×{h} weight grid is larger than the {bw}×{bh} block")
            }
            Illegal::TooManyWeights(n) => write!(f, "it has {n} weights (at most 64)"),
            Illegal::WeightBits(bits) => write!(f, "its weights take {bits} bits (24 to 96)"),
            Illegal::DualPlaneWithFourPartitions => write!(f, "it has four partitions and two weight planes"),
            Illegal::HdrEndpointMode(mode) => {
                write!(f, "its colour endpoint mode {mode} is HDR, which the LDR profile does not decode")
            }
            Illegal::TooManyEndpointValues(n) => write!(f, "its colour endpoint modes need {n} values (at most 18)"),
            Illegal::TooFewEndpointBits { values, available } => write!(
                f,
                "{available} bits are left for its {values} colour endpoint values, fewer than the {} they need",
                (13 * values).div_ceil(5)
            ),
        }
    }
}

/// Checks one block of a `width`×`height` footprint against the rules of the module notes.
pub fn check_block(block: &[u8; 16], width: u8, height: u8) -> Result<(), Illegal> {
    let bits = u128::from_le_bytes(*block);
    let field = |at: u32, count: u32| ((bits >> at) & ((1u128 << count) - 1)) as u32;
    let mode = field(0, 11);
    if mode & 0x1ff == 0x1fc {
        return check_void_extent(field);
    }
    let layout = block_mode(mode).ok_or(Illegal::ReservedBlockMode)?;
    let (grid_w, grid_h) = layout.grid;
    if grid_w > width as u32 || grid_h > height as u32 {
        return Err(Illegal::GridLargerThanBlock { grid: layout.grid, block: (width, height) });
    }
    let weights = grid_w * grid_h * if layout.dual_plane { 2 } else { 1 };
    if weights > 64 {
        return Err(Illegal::TooManyWeights(weights));
    }
    let weight_bits = sequence_bits(WEIGHT_LEVELS[layout.range as usize], weights);
    if !(24..=96).contains(&weight_bits) {
        return Err(Illegal::WeightBits(weight_bits));
    }
    let partitions = field(11, 2) + 1;
    if layout.dual_plane && partitions == 4 {
        return Err(Illegal::DualPlaneWithFourPartitions);
    }
    // Each partition's endpoint mode, and the bits the modes and the partitioning take.
    let mut modes = [0u32; 4];
    let mut config_bits = if partitions == 1 {
        modes[0] = field(13, 4);
        17
    } else {
        let selector = field(23, 2);
        if selector == 0 {
            modes = [field(25, 4); 4];
            29
        } else {
            // One class bit per partition at bit 25 on, then the modes' low two bits: those
            // that fit in bits 25–28, the rest just below the weights.
            let below = 128 - weight_bits;
            let low: [u32; 4] = match partitions {
                2 => [field(27, 2), field(below - 2, 2), 0, 0],
                3 => [field(28, 1) | field(below - 5, 1) << 1, field(below - 4, 2), field(below - 2, 2), 0],
                _ => std::array::from_fn(|i| field(below - 8 + 2 * i as u32, 2)),
            };
            for (i, mode) in modes.iter_mut().enumerate().take(partitions as usize) {
                *mode = (selector - 1 + field(25 + i as u32, 1)) << 2 | low[i];
            }
            25 + 3 * partitions
        }
    };
    if layout.dual_plane {
        config_bits += 2;
    }
    let modes = &modes[..partitions as usize];
    if let Some(&hdr) = modes.iter().find(|&&m| matches!(m, 2 | 3 | 7 | 11 | 14 | 15)) {
        return Err(Illegal::HdrEndpointMode(hdr));
    }
    let values: u32 = modes.iter().map(|m| 2 * ((m >> 2) + 1)).sum();
    if values > 18 {
        return Err(Illegal::TooManyEndpointValues(values));
    }
    let available = 128 - config_bits as i32 - weight_bits as i32;
    if available < (13 * values).div_ceil(5) as i32 {
        return Err(Illegal::TooFewEndpointBits { values, available });
    }
    Ok(())
}

fn check_void_extent(field: impl Fn(u32, u32) -> u32) -> Result<(), Illegal> {
    if field(10, 2) != 0b11 {
        return Err(Illegal::VoidExtentReservedBits);
    }
    if field(9, 1) == 1 {
        return Err(Illegal::VoidExtentHdr);
    }
    let [s_low, s_high, t_low, t_high] = [12, 25, 38, 51].map(|at| field(at, 13));
    let all_ones = [s_low, s_high, t_low, t_high].iter().all(|&c| c == 0x1fff);
    if !all_ones && (s_low >= s_high || t_low >= t_high) {
        return Err(Illegal::VoidExtentCoordinates);
    }
    Ok(())
}

/// A block mode's weight grid, the index of its weights' range in [`WEIGHT_LEVELS`] (the
/// high-precision bit above the three range bits) and whether it has two planes.
struct BlockMode {
    grid: (u32, u32),
    range: u32,
    dual_plane: bool,
}

/// Decodes the 11-bit block mode of a block that is not void-extent; `None` for the reserved
/// layouts (the specification's table of 2D block modes).
fn block_mode(mode: u32) -> Option<BlockMode> {
    let bit = |at: u32| (mode >> at) & 1;
    let a = (mode >> 5) & 3;
    let b = (mode >> 7) & 3;
    let high_precision = bit(9);
    let dual_plane = bit(10) == 1;
    if mode & 3 != 0 {
        let range = high_precision << 3 | (mode & 3) << 1 | bit(4);
        let grid = match (mode >> 2) & 3 {
            0 => (b + 4, a + 2),
            1 => (b + 8, a + 2),
            2 => (a + 2, b + 8),
            _ if bit(8) == 0 => (a + 2, bit(7) + 6),
            _ => (bit(7) + 2, a + 2),
        };
        return Some(BlockMode { grid, range, dual_plane });
    }
    if mode & 0xf == 0 {
        return None;
    }
    let range = high_precision << 3 | ((mode >> 2) & 3) << 1 | bit(4);
    let grid = match b {
        0 => (12, a + 2),
        1 => (a + 2, 12),
        // Two more bits of height where the precision and plane bits are: neither applies.
        2 => return Some(BlockMode { grid: (a + 6, ((mode >> 9) & 3) + 6), range: range & 7, dual_plane: false }),
        _ if bit(6) == 1 => return None,
        _ if bit(5) == 0 => (6, 10),
        _ => (10, 6),
    };
    Some(BlockMode { grid, range, dual_plane })
}

/// How many values each weight range holds, by index (high-precision bit, then three range
/// bits): 2 to 32, each a power of two times 1, 3 (a trit) or 5 (a quint). Indices 0, 1, 8
/// and 9 are never made (their layouts are reserved or void-extent): 1 there, no bits.
const WEIGHT_LEVELS: [u32; 16] = [1, 1, 2, 3, 4, 5, 6, 8, 1, 1, 10, 12, 16, 20, 24, 32];

/// The bits `count` values of a range of `levels` values take in an integer sequence: the
/// power of two's bits each, and five trits in 8 bits or three quints in 7, the last group
/// cut short.
fn sequence_bits(levels: u32, count: u32) -> u32 {
    let bits = levels.trailing_zeros();
    count * bits
        + match levels >> bits {
            3 => (8 * count).div_ceil(5),
            5 => (7 * count).div_ceil(3),
            _ => 0,
        }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shade::texel_format::ASTC_FOOTPRINTS;

    /// A block whose bits are `fields`' values at their positions, the rest zero.
    fn block(fields: &[(u32, u32)]) -> [u8; 16] {
        fields.iter().fold(0u128, |bits, &(at, value)| bits | (value as u128) << at).to_le_bytes()
    }

    /// An LDR void-extent block of colour zero and extent `coordinates`.
    fn void_extent(coordinates: [u32; 4]) -> [u8; 16] {
        let mut fields = vec![(0, 0x1fc), (10, 0b11)];
        fields.extend(coordinates.iter().zip([12, 25, 38, 51]).map(|(&c, at)| (at, c)));
        block(&fields)
    }

    #[test]
    fn void_extent_blocks_follow_their_rules() {
        assert_eq!(check_block(&void_extent([0x1fff; 4]), 4, 4), Ok(()));
        assert_eq!(check_block(&void_extent([0, 5, 2, 3]), 4, 4), Ok(()));
        assert_eq!(check_block(&void_extent([5, 5, 2, 3]), 4, 4), Err(Illegal::VoidExtentCoordinates));
        assert_eq!(check_block(&void_extent([0, 5, 3, 2]), 4, 4), Err(Illegal::VoidExtentCoordinates));
        let mut reserved = void_extent([0x1fff; 4]);
        reserved[1] &= !0x08; // bit 11
        assert_eq!(check_block(&reserved, 4, 4), Err(Illegal::VoidExtentReservedBits));
        let mut hdr = void_extent([0x1fff; 4]);
        hdr[1] |= 0x02; // bit 9
        assert_eq!(check_block(&hdr, 4, 4), Err(Illegal::VoidExtentHdr));
    }

    /// Block mode bits for a `w`×`h` grid of the layout with bits [3:2] `00` (`w` 4–7, `h`
    /// 2–5), range index `range` (2–7), one plane.
    fn mode_4x2(w: u32, h: u32, range: u32) -> u32 {
        assert!((4..=7).contains(&w) && (2..=5).contains(&h) && (2..=7).contains(&range));
        (range >> 1) | (range & 1) << 4 | (h - 2) << 5 | (w - 4) << 7
    }

    #[test]
    fn weight_grids_follow_their_rules() {
        // 4×2 grid, range 0–7 (3 bits): 24 bits, the least allowed; one partition, mode 0.
        let ok = block(&[(0, mode_4x2(4, 2, 7))]);
        assert_eq!(check_block(&ok, 4, 4), Ok(()));
        // The same grid in range 0–3 is 16 bits.
        assert_eq!(check_block(&block(&[(0, mode_4x2(4, 2, 4))]), 4, 4), Err(Illegal::WeightBits(16)));
        // 5×2 is wider than a 4×4 block, not than a 5×4 one.
        let wide = block(&[(0, mode_4x2(5, 2, 7))]);
        assert_eq!(check_block(&wide, 4, 4), Err(Illegal::GridLargerThanBlock { grid: (5, 2), block: (4, 4) }));
        assert_eq!(check_block(&wide, 5, 4), Ok(()));
        // 7×5 of 3 bits is 105 bits.
        assert_eq!(check_block(&block(&[(0, mode_4x2(7, 5, 7))]), 8, 8), Err(Illegal::WeightBits(105)));
        // Two planes of a 6×10 grid (bits [8:7] `11`, range 0–7, bit 10) are 120 weights.
        let dual_6x10 = 0b11 << 7 | 0b111 << 2 | 1 << 10;
        assert_eq!(check_block(&block(&[(0, dual_6x10)]), 12, 12), Err(Illegal::TooManyWeights(120)));
        // Reserved: bits [3:0] zero, or bits [8:6] all set with [1:0] zero.
        assert_eq!(check_block(&block(&[(0, 0b1_0000)]), 4, 4), Err(Illegal::ReservedBlockMode));
        assert_eq!(check_block(&block(&[(0, 0b111 << 6 | 0b01 << 2)]), 4, 4), Err(Illegal::ReservedBlockMode));
    }

    #[test]
    fn endpoint_modes_follow_their_rules() {
        let mode = mode_4x2(4, 2, 7);
        // One partition of mode 8 (RGB, 6 values) fits in the 87 bits left.
        assert_eq!(check_block(&block(&[(0, mode), (13, 8)]), 4, 4), Ok(()));
        // HDR modes are refused.
        for hdr in [2, 3, 7, 11, 14, 15] {
            assert_eq!(check_block(&block(&[(0, mode), (13, hdr)]), 4, 4), Err(Illegal::HdrEndpointMode(hdr)));
        }
        // Four partitions of mode 12 (RGBA, 8 values each) need 32 values.
        let four = block(&[(0, mode), (11, 3), (23, 0), (25, 12)]);
        assert_eq!(check_block(&four, 4, 4), Err(Illegal::TooManyEndpointValues(32)));
        // Four partitions of mode 0 (8 values, 21 bits at least): a 4×4 grid of range 0–23
        // (48 + ⌈128/5⌉ = 74 bits) leaves 25 bits, one of range 0–31 (80 bits) 19.
        let mode_74 = mode_4x2(4, 4, 6) | 1 << 9;
        assert_eq!(check_block(&block(&[(0, mode_74), (11, 3)]), 4, 4), Ok(()));
        let mode_big = mode_4x2(6, 4, 7) | 1 << 9; // 6×4 of range 0–31: 120 bits
        assert_eq!(check_block(&block(&[(0, mode_big)]), 8, 8), Err(Illegal::WeightBits(120)));
        let mode_80 = mode_4x2(4, 4, 7) | 1 << 9;
        assert_eq!(
            check_block(&block(&[(0, mode_80), (11, 3)]), 4, 4),
            Err(Illegal::TooFewEndpointBits { values: 8, available: 19 })
        );
        // Two planes and four partitions.
        let dual = mode | 1 << 10;
        assert_eq!(check_block(&block(&[(0, dual), (11, 3)]), 4, 4), Err(Illegal::DualPlaneWithFourPartitions));
    }

    /// Every block the checks pass decodes without a panic out of the decoder, over random
    /// blocks of every footprint; and random blocks are both passed and refused.
    #[test]
    fn legal_blocks_decode_without_a_panic() {
        let mut state = 7u64;
        let mut next = move || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 32) as u32
        };
        let mut passed = 0;
        let rounds = if cfg!(debug_assertions) { 3_000 } else { 30_000 };
        let mut out = [0u32; 144];
        for i in 0..rounds * ASTC_FOOTPRINTS.len() {
            let (bw, bh) = ASTC_FOOTPRINTS[i % ASTC_FOOTPRINTS.len()];
            let mut block: [u8; 16] = std::array::from_fn(|_| next() as u8);
            // Half the blocks take a legal-looking mode: one or two partitions of LDR modes,
            // so that the checks' later rules and the decoder's later stages are reached.
            if i % 2 == 0 {
                block[1] &= !0x18 | ((next() & 1) as u8) << 3;
            }
            if check_block(&block, bw, bh).is_ok() {
                passed += 1;
                let decoded = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    texture2ddecoder::decode_astc_block(&block, bw as usize, bh as usize, &mut out)
                }));
                assert!(decoded.is_ok(), "{bw}×{bh} block {block:02x?} passed the checks and the decoder panicked");
            }
        }
        let total = rounds * ASTC_FOOTPRINTS.len();
        assert!((total / 20..total * 19 / 20).contains(&passed), "{passed} of {total} passed");
    }
}
