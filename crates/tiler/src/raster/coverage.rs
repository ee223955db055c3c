//! Hierarchical coverage: an 8×8-pixel block is classified against the three edges as
//! `Outside`, `Partial` or `Full` (llvmpipe's trivial reject / trivial accept); only in partial
//! blocks are the edge functions evaluated per sample, for 4×2 groups of pixels at a time.
//!
//! Everything is evaluated at absolute sample positions from the primitive's integer edge
//! functions, so coverage does not depend on which tile or band asks for it.

use super::PixelRect;
use super::edge::Edge;
use super::fixed::{SUBPIXEL_SCALE, SubPixel};
use super::samples::{MAX_SAMPLES, SampleLocations};
use crate::simd::LaneMask;

/// Side of a coverage block, in pixels. Tiles are multiples of it.
pub const BLOCK_SIZE: i32 = 8;

/// Which samples of a 4×2 group are covered: byte `s` is the lane mask of sample `s`, for up
/// to [`MAX_SAMPLES`] (16) samples.
///
/// One 128-bit word rather than a 64-bit word for 1–8 samples plus a second one for 16: the
/// word is what every stage passes per group, and a single type keeps one pipeline for every
/// sample count (no copy per width, and no second monomorphisation of every shader's
/// pipeline, which is most of the release build's time). Measured with callgrind on
/// `tiler bench --scene helmet --frames 1 --threads 1` against the 64-bit word: see
/// docs/benchmarking.md ("16× MSAA").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Coverage(pub u128);

/// One bit per byte: a lane mask repeated for every sample.
const EVERY_SAMPLE: u128 = u128::MAX / 0xff;

const _: () = assert!(MAX_SAMPLES * 8 == u128::BITS as usize, "a byte per sample fills the word");

impl Coverage {
    pub const NONE: Coverage = Coverage(0);

    /// Every lane of every one of `samples` samples.
    #[cfg(test)]
    pub fn full(samples: usize) -> Coverage {
        Coverage(if samples >= MAX_SAMPLES { u128::MAX } else { (1u128 << (8 * samples)) - 1 })
    }

    /// The coverage whose sample `s` has the lanes `lanes[s]` (the others none).
    #[inline(always)]
    pub fn from_samples(lanes: [u8; MAX_SAMPLES]) -> Coverage {
        Coverage(u128::from_le_bytes(lanes))
    }

    // Samples are read and written as bytes, not by shifting the word: a shift of a 128-bit
    // word by a variable amount is several instructions on x86-64 (measured: see the type).
    #[inline(always)]
    pub fn sample(self, s: usize) -> LaneMask {
        LaneMask(self.0.to_le_bytes()[s])
    }

    #[inline(always)]
    pub fn set_sample(&mut self, s: usize, lanes: LaneMask) {
        let mut bytes = self.0.to_le_bytes();
        bytes[s] = lanes.0;
        self.0 = u128::from_le_bytes(bytes);
    }

    /// Only sample `s` of this coverage.
    #[inline(always)]
    pub fn only_sample(self, s: usize) -> Coverage {
        let mut bytes = [0u8; MAX_SAMPLES];
        bytes[s] = self.0.to_le_bytes()[s];
        Coverage::from_samples(bytes)
    }

    /// Lanes with at least one covered sample.
    #[inline(always)]
    pub fn lanes(self) -> LaneMask {
        let mut v = (self.0 as u64) | (self.0 >> 64) as u64;
        v |= v >> 32;
        v |= v >> 16;
        v |= v >> 8;
        LaneMask(v as u8)
    }

    /// Keeps only the given lanes, in every sample.
    #[inline(always)]
    pub fn restrict(self, lanes: LaneMask) -> Coverage {
        Coverage(self.0 & (lanes.0 as u128 * EVERY_SAMPLE))
    }

    #[inline(always)]
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// Covered samples in total.
    #[inline(always)]
    pub fn count(self) -> u32 {
        self.0.count_ones()
    }
}

/// How an 8×8 block relates to a primitive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BlockCoverage {
    /// No sample of the block is covered.
    Outside,
    /// Some samples may be covered: evaluate per sample.
    Partial,
    /// Every sample of the block is covered.
    Full,
}

/// A primitive's edges prepared for coverage queries at one sample count.
///
/// Built once per primitive per tile, so it is kept small: the edges and a reference to the
/// pass's sample locations (`A·sx + B·sy` of a sample's offset is worked out where a block
/// mask needs it, two multiplications an edge). A table of those offsets for sixteen samples
/// made the value about 500 bytes, zeroed, filled and moved for every primitive, which cost
/// tris more than the multiplications it saved (docs/benchmarking.md, "Geometry and
/// overdraw, round three").
#[derive(Clone, Debug)]
pub struct PrimitiveCoverage<'a> {
    edges: [Edge; 3],
    locations: &'a SampleLocations,
}

impl<'a> PrimitiveCoverage<'a> {
    pub fn new(edges: &[Edge; 3], locations: &'a SampleLocations) -> PrimitiveCoverage<'a> {
        PrimitiveCoverage { edges: *edges, locations }
    }

    /// `A·sx + B·sy` of edge `e` for sample `s`'s offset within its pixel.
    #[inline(always)]
    fn sample_offset(edge: &Edge, (sx, sy): (i32, i32)) -> i64 {
        edge.a * sx as i64 + edge.b * sy as i64
    }

    /// Classifies the `size × size` block whose top-left pixel is `(x, y)`, using the
    /// extreme sample positions of the block.
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn classify_block(&self, x: i32, y: i32, size: i32) -> BlockCoverage {
        self.classify_rect(&PixelRect::new(x, y, x + size, y + size))
    }

    /// Classifies the pixels of `rect` (not empty) as [`PrimitiveCoverage::classify_block`]
    /// does a block: each edge is linear, so its extremes over the rectangle of the extreme
    /// sample positions are at its corners. `Full` means every sample of every pixel is
    /// covered, so every block inside `rect` is `Full` too; `Outside`, that none is.
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn classify_rect(&self, rect: &PixelRect) -> BlockCoverage {
        let (hx0, hy0, hx1, hy1) = self.locations.hull();
        let x0 = SubPixel::pixel_corner(rect.x0) + hx0 as i64;
        let y0 = SubPixel::pixel_corner(rect.y0) + hy0 as i64;
        let x1 = SubPixel::pixel_corner(rect.x1 - 1) + hx1 as i64;
        let y1 = SubPixel::pixel_corner(rect.y1 - 1) + hy1 as i64;
        let mut full = true;
        for e in &self.edges {
            if e.max_over(x0, y0, x1, y1) < 0 {
                return BlockCoverage::Outside;
            }
            full &= e.min_over(x0, y0, x1, y1) >= 0;
        }
        if full { BlockCoverage::Full } else { BlockCoverage::Partial }
    }

    /// The covered pixels of sample `s` in the 8×8 block whose top-left pixel is `(x, y)`:
    /// bit `8·row + column`. The edges are evaluated incrementally along the rows: those whose
    /// values over the block fit 32 bits (an edge shorter than about 2000 pixels) together,
    /// one sign test a row for all of them, the others in 64-bit lanes; edges that cover the
    /// whole block cost nothing. Only block rows `rows` are evaluated; the others come back
    /// empty.
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn block_mask(&self, x: i32, y: i32, s: usize, rows: std::ops::Range<i32>) -> u64 {
        let corner_x = SubPixel::pixel_corner(x);
        let corner_y = SubPixel::pixel_corner(y);
        let scale = SUBPIXEL_SCALE as i64;
        let offset = self.locations.offset(s);
        let last = (BLOCK_SIZE - 1) as i64;
        // The edges that cut the block and whose values over it fit 32 bits are evaluated
        // together; an unused slot is the edge 0, which covers everything.
        let mut near = [(0i32, 0i32, 0i32); 3];
        let mut count = 0;
        let mut mask = u64::MAX;
        for edge in &self.edges {
            let at_corner = edge.eval(corner_x, corner_y) + Self::sample_offset(edge, offset);
            let (step_x, step_y) = (edge.a * scale, edge.b * scale);
            let lo = at_corner + last * step_x.min(0) + last * step_y.min(0);
            let hi = at_corner + last * step_x.max(0) + last * step_y.max(0);
            if hi < 0 {
                return 0;
            }
            if lo >= 0 {
                continue;
            }
            // Every value lies in [lo, hi], which contains 0: when the span fits, so does
            // everything.
            if hi - lo < 1 << 30 {
                near[count] = (at_corner as i32, step_x as i32, step_y as i32);
                count += 1;
            } else {
                mask &= far_edge_block_mask(at_corner, step_x, step_y, rows.clone());
            }
        }
        if count > 0 {
            mask &= near_edges_block_mask(near, rows.clone());
        }
        mask & row_span(rows.start, rows.end)
    }

    /// Whether the sample `s` of pixel `(x, y)` is covered: the scalar reference that
    /// [`PrimitiveCoverage::block_mask`] must agree with.
    pub fn covers(&self, x: i32, y: i32, s: usize) -> bool {
        let px = SubPixel::pixel_corner(x);
        let py = SubPixel::pixel_corner(y);
        let offset = self.locations.offset(s);
        self.edges.iter().all(|edge| edge.eval(px, py) + Self::sample_offset(edge, offset) >= 0)
    }
}

/// The pixels of an 8×8 block, in `rows`, where all three edges are at least 0 (bit
/// `8·row + column`), each `E = at_corner + column·step_x + row·step_y` with its values over
/// the block fitting 32 bits. The three values are or-ed, so one sign test per row serves
/// all of them: the or is negative exactly when one of them is.
#[inline(always)]
fn near_edges_block_mask(edges: [(i32, i32, i32); 3], rows: std::ops::Range<i32>) -> u64 {
    let first = rows.start;
    let row = |(e0, sx, sy): (i32, i32, i32)| -> [i32; 8] { std::array::from_fn(|c| e0 + c as i32 * sx + first * sy) };
    let (mut r0, mut r1, mut r2) = (row(edges[0]), row(edges[1]), row(edges[2]));
    let mut mask = 0u64;
    for r in rows {
        let any: [i32; 8] = std::array::from_fn(|c| r0[c] | r1[c] | r2[c]);
        mask |= (!crate::simd::sign_bits(any) as u64) << (8 * r);
        // The last row's step may leave the block's range; it is never used.
        r0 = r0.map(|v| v.wrapping_add(edges[0].2));
        r1 = r1.map(|v| v.wrapping_add(edges[1].2));
        r2 = r2.map(|v| v.wrapping_add(edges[2].2));
    }
    mask
}

/// The pixels of an 8×8 block where `E ≥ 0`, for an edge whose values over the block do not
/// fit 32 bits (an edge longer than about 2000 pixels), in 64-bit arithmetic.
fn far_edge_block_mask(at_corner: i64, step_x: i64, step_y: i64, rows: std::ops::Range<i32>) -> u64 {
    let row: [i64; 8] = std::array::from_fn(|c| at_corner + c as i64 * step_x);
    let mut mask = 0u64;
    for r in rows {
        let offset = r as i64 * step_y;
        let mut bits = 0u64;
        for (c, v) in row.iter().enumerate() {
            bits |= ((v + offset >= 0) as u64) << c;
        }
        mask |= bits << (8 * r);
    }
    mask
}

/// The pixels of the 8×8 block at `(x, y)` that lie inside `rect` (bit `8·row + column`).
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn block_rect_mask(x: i32, y: i32, rect: &super::PixelRect) -> u64 {
    let columns = span(rect.x0 - x, rect.x1 - x, 1);
    (columns * 0x0101_0101_0101_0101) & row_span(rect.y0 - y, rect.y1 - y)
}

/// Bits `unit·lo .. unit·hi` of a word (`lo`, `hi` clamped to 0..8): columns lo..hi of a row
/// (unit 1), or rows lo..hi of a block (unit 8).
#[inline(always)]
fn span(lo: i32, hi: i32, unit: u32) -> u64 {
    let (lo, hi) = (lo.clamp(0, 8) as u32 * unit, hi.clamp(0, 8) as u32 * unit);
    if hi <= lo {
        return 0;
    }
    let below_hi = if hi >= 64 { u64::MAX } else { (1u64 << hi) - 1 };
    below_hi & !((1u64 << lo) - 1)
}

/// Rows `lo..hi` of a block mask.
#[inline(always)]
fn row_span(lo: i32, hi: i32) -> u64 {
    span(lo, hi, 8)
}

/// The lanes of the 4×2 group at offset `(gx, gy)` in a block (gx ∈ {0, 4}, gy even), from a
/// block mask.
#[inline(always)]
pub fn group_lanes(block: u64, gx: i32, gy: i32) -> LaneMask {
    let top = (block >> (8 * gy + gx)) & 0xf;
    let bottom = (block >> (8 * (gy + 1) + gx)) & 0xf;
    LaneMask((top | bottom << 4) as u8)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simd::{LANE_DX, LANE_DY, LANES};

    fn triangle(points: [(i32, i32); 3]) -> [Edge; 3] {
        let p = points.map(|(x, y)| (SubPixel(x), SubPixel(y)));
        [Edge::new(p[0], p[1]), Edge::new(p[1], p[2]), Edge::new(p[2], p[0])]
    }

    #[test]
    fn block_masks_agree_with_the_scalar_reference() {
        // A small triangle (32-bit path), a huge one (64-bit path), a thin sliver, and both paths.
        let cases = [
            triangle([(100, 50), (3000, 700), (900, 2500)]),
            triangle([(-4_000_000, -3_000_000), (5_000_000, 200), (300, 6_000_000)]),
            triangle([(0, 0), (4000, 37), (4010, 60)]),
            // Two long edges (64-bit) and a short one (32-bit) cutting the same blocks.
            triangle([(0, 0), (3_000_000, 1000), (500, 3000)]),
        ];
        for edges in cases {
            for samples in [1, 2, 4, 8, 16] {
                let locations = SampleLocations::standard(samples);
                let cov = PrimitiveCoverage::new(&edges, &locations);
                for by in (-8..24).step_by(8) {
                    for bx in (-8..24).step_by(8) {
                        for s in 0..samples as usize {
                            let mask = cov.block_mask(bx, by, s, 0..8);
                            let middle = cov.block_mask(bx, by, s, 2..5);
                            assert_eq!(middle, mask & 0x00ff_ffff_0000, "rows 2..5 only");
                            for bit in 0..64 {
                                let (c, r) = (bit % 8, bit / 8);
                                let expected = cov.covers(bx + c, by + r, s);
                                assert_eq!(mask >> bit & 1 != 0, expected, "block ({bx}, {by}) pixel ({c}, {r}) s{s}");
                            }
                            for gy in [0, 2, 4, 6] {
                                for gx in [0, 4] {
                                    for lane in 0..LANES {
                                        let (c, r) = (gx + LANE_DX[lane] as i32, gy + LANE_DY[lane] as i32);
                                        assert_eq!(
                                            group_lanes(mask, gx, gy).contains(lane),
                                            cov.covers(bx + c, by + r, s)
                                        );
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn block_rect_masks() {
        let rect = super::super::PixelRect::new(3, 2, 20, 5);
        let m = block_rect_mask(0, 0, &rect);
        assert_eq!(m, (0b1111_1000u64 << 16) | (0b1111_1000u64 << 24) | (0b1111_1000u64 << 32));
        assert_eq!(block_rect_mask(8, 0, &rect) >> 16 & 0xff, 0xff);
        assert_eq!(block_rect_mask(0, 8, &rect), 0);
    }

    #[test]
    fn block_classes_are_consistent_with_groups() {
        let edges = triangle([(0, 0), (40 * 256, 0), (0, 40 * 256)]);
        let locations = SampleLocations::standard(4);
        let cov = PrimitiveCoverage::new(&edges, &locations);
        assert_eq!(cov.classify_block(0, 0, 8), BlockCoverage::Full);
        assert_eq!(cov.classify_block(48, 48, 8), BlockCoverage::Outside);
        assert_eq!(cov.classify_block(16, 16, 8), BlockCoverage::Partial);
        for s in 0..4 {
            assert_eq!(cov.block_mask(0, 0, s, 0..8), u64::MAX);
            assert_eq!(cov.block_mask(48, 48, s, 0..8), 0);
        }
    }

    #[test]
    fn coverage_lane_folding() {
        let mut c = Coverage::NONE;
        c.set_sample(2, LaneMask(0b1000_0001));
        c.set_sample(0, LaneMask(0b0000_0010));
        assert_eq!(c.lanes(), LaneMask(0b1000_0011));
        assert_eq!(c.restrict(LaneMask(0b0000_0011)).lanes(), LaneMask(0b0000_0011));
        assert_eq!(Coverage::full(8).count(), 64);
        assert_eq!(Coverage::full(16).count(), 128);
        let mut high = Coverage::NONE;
        high.set_sample(15, LaneMask(0b0100_0000));
        high.set_sample(9, LaneMask(0b0000_0100));
        assert_eq!(high.lanes(), LaneMask(0b0100_0100));
        assert_eq!(high.only_sample(15).count(), 1);
        assert_eq!(high.sample(15), LaneMask(0b0100_0000));
        assert!(high.restrict(LaneMask(0b0000_0100)).sample(15).is_empty());
        assert_eq!(high.restrict(LaneMask(0b0000_0100)).sample(9), LaneMask(0b0000_0100));
    }
}
