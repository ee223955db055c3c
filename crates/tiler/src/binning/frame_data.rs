//! The frame data: what the geometry phase hands to the tile phase — primitive records, the
//! state records they refer to, and one polygon list per tile.
//!
//! # Modelled layout (what the ledger counts)
//!
//! tiler counts frame-data bytes as a GPU with this layout would move them:
//!
//! | record | bytes | written | read |
//! |---|---|---|---|
//! | primitive record | `8 + 3 × (16 + 4 × varyings)`: a header (state index, flags) and, per vertex, the post-transform position (x, y, z, w as f32) and the varyings (f32 each); with position-only binning (`VertexShading::PerTile`) `8 + 3 × 16`, positions only | once, when binned | by every tile whose list names it |
//! | polygon-list entry | 4 (primitive index) | once per tile the primitive is binned to | by that tile |
//! | state record | 64 (shader and fixed-function state, viewport, scissor) | once per draw with primitives | by a tile each time its list changes state |
//!
//! With position-only binning a tile also fetches and shades again each vertex its primitives
//! use (once per tile): `VertexFetch` grows by the vertex-cache lines each tile's vertices fill.
//!
//! The host keeps a richer record per primitive (the set-up edge functions and interpolation
//! planes, see [`Primitive`]) so that tiles need not set triangles up again; its size is
//! reported separately as host memory. The budget applies to the modelled bytes, as on a GPU.

use crate::binning::grid::TileGrid;
use crate::depth::hsr::HsrMode;
use crate::geometry::VertexShading;
use crate::huge_pages::{HUGE_PAGE_BYTES, advise_huge_pages};

pub use crate::geometry::primitive::Primitive;

/// Bytes of a primitive record's header (state index and flags).
pub const PRIMITIVE_HEADER_BYTES: u64 = 8;
/// Bytes of a post-transform vertex position (x, y, z, w as f32).
pub const VERTEX_POSITION_BYTES: u64 = 16;
/// Bytes of a polygon-list entry.
pub const POLYGON_LIST_ENTRY_BYTES: u64 = 4;
/// Bytes of a state record.
pub const STATE_RECORD_BYTES: u64 = 64;

/// Modelled bytes of one primitive record with `varyings` f32 varyings per vertex, when
/// vertices are shaded once and their varyings stored in the frame data.
pub const fn primitive_record_bytes(varyings: usize) -> u64 {
    PRIMITIVE_HEADER_BYTES + 3 * (VERTEX_POSITION_BYTES + 4 * varyings as u64)
}

/// Modelled bytes of one primitive record under a vertex-shading placement: with
/// position-only binning the record holds positions only (varyings are recomputed per tile).
pub const fn record_bytes(varyings: usize, shading: VertexShading) -> u64 {
    match shading {
        VertexShading::Once => primitive_record_bytes(varyings),
        VertexShading::PerTile => PRIMITIVE_HEADER_BYTES + 3 * VERTEX_POSITION_BYTES,
    }
}

/// The state record of primitives by index (see [`FrameData::state_cursor`]).
#[derive(Clone, Copy)]
pub struct StateCursor<'a> {
    starts: &'a [u32],
    /// The state of the last primitive asked about.
    current: usize,
}

impl StateCursor<'_> {
    /// The state record of the primitive at `index`: a step or two forward from the last
    /// answer when indices ascend, a binary search otherwise.
    #[inline]
    pub fn state_of(&mut self, index: u32) -> u32 {
        let starts = self.starts;
        let here = starts.get(self.current).is_some_and(|&start| start <= index);
        let ahead = starts.get(self.current + 1).is_some_and(|&start| start <= index);
        if here && ahead {
            self.current += starts[self.current + 1..].partition_point(|&start| start <= index);
        } else if !here {
            self.current = starts.partition_point(|&start| start <= index).saturating_sub(1);
        }
        self.current as u32
    }
}

/// What every primitive of a draw shares.
#[derive(Clone, Debug)]
pub struct StateRecord {
    /// The draw's index in its render pass (the tile phase finds its pipeline there).
    pub draw: u32,
    pub varying_count: u32,
    /// Whether the draw can wait for hidden-surface removal (TBDR).
    pub hsr: HsrMode,
    /// Where the draw's attributes are: a tile shading vertices again fetches them again.
    pub fetch: std::sync::Arc<crate::geometry::fetch::FetchLayout>,
    /// The subpass the draw belongs to.
    pub subpass: u32,
    /// Every varying of the draw is flat, so a primitive's three vertices carry the same
    /// values (setup gives them the provoking vertex's): the frame data keeps one vertex's,
    /// `varying_count` floats per primitive instead of three times as many — a third of the
    /// bytes for a tile to miss on (docs/benchmarking.md, "Flat-only varyings"). Host layout
    /// only: the modelled record is unchanged.
    pub flat_only: bool,
}

/// Bytes of frame data, as modelled and as held in host memory.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameDataBytes {
    pub primitive_records: u64,
    pub polygon_list_entries: u64,
    pub state_records: u64,
}

impl FrameDataBytes {
    pub fn total(&self) -> u64 {
        self.primitive_records + self.polygon_list_entries + self.state_records
    }
}

/// Primitive records, state records and polygon lists of the draws binned since the last flush.
pub struct FrameData {
    pub(super) grid: TileGrid,
    /// Where vertices are shaded, which decides the modelled record size.
    pub(super) vertex_shading: VertexShading,
    pub(super) primitives: Vec<Primitive>,
    pub(super) varyings: Vec<f32>,
    pub(super) states: Vec<StateRecord>,
    /// The first primitive of each state record: primitives are appended under the latest
    /// state, so state `s` holds primitives `state_starts[s]..state_starts[s + 1]`, and a
    /// tile finds the state of a list entry here without reading its record (the records are
    /// what a tile misses the caches on: see docs/benchmarking.md, "Primitive records").
    state_starts: Vec<u32>,
    /// One polygon list per tile, row-major; entries are primitive indices in submission order.
    pub(super) lists: Vec<Vec<u32>>,
    pub(super) bytes: FrameDataBytes,
    /// Primitives from this index on are appended but not binned yet ([`FrameData::unbinned`]).
    pub(super) binned: usize,
    /// A bound of the polygon-list bytes binning them will write (every tile their boxes meet).
    pub(super) unbinned_bound: u64,
    /// Modelled bytes it may hold before an incremental render (the device's
    /// `frame_data_budget`): the frame data says when it is full ([`FrameData::fitting`]).
    budget: u64,
}

impl FrameData {
    pub fn new(grid: TileGrid, vertex_shading: VertexShading, budget: u64) -> FrameData {
        FrameData {
            budget,
            vertex_shading,
            lists: vec![Vec::new(); grid.tile_count()],
            grid,
            primitives: Vec::new(),
            varyings: Vec::new(),
            states: Vec::new(),
            state_starts: Vec::new(),
            bytes: FrameDataBytes::default(),
            binned: 0,
            unbinned_bound: 0,
        }
    }

    /// Empties the frame data for a pass over `grid`, keeping every allocation it can (the
    /// records, and the lists of the tiles both grids have): a device reuses one frame data
    /// for all its passes, so a frame allocates nothing once the first has grown it.
    pub fn reset(&mut self, grid: TileGrid, vertex_shading: VertexShading, budget: u64) {
        self.clear();
        self.lists.resize_with(grid.tile_count(), Vec::new);
        self.grid = grid;
        self.vertex_shading = vertex_shading;
        self.budget = budget;
    }

    pub fn grid(&self) -> TileGrid {
        self.grid
    }

    /// Where vertices are shaded, which decides the modelled record size.
    pub fn vertex_shading(&self) -> VertexShading {
        self.vertex_shading
    }

    /// Every primitive record, in submission order.
    pub fn primitives(&self) -> &[Primitive] {
        &self.primitives
    }

    /// The varyings of every primitive's vertices (see [`FrameData::varyings_of`]).
    pub fn varyings(&self) -> &[f32] {
        &self.varyings
    }

    pub fn states(&self) -> &[StateRecord] {
        &self.states
    }

    /// One polygon list per tile, row-major; entries are primitive indices in submission order.
    pub fn lists(&self) -> &[Vec<u32>] {
        &self.lists
    }

    /// Modelled bytes held now.
    pub fn bytes(&self) -> FrameDataBytes {
        self.bytes
    }

    pub fn is_empty(&self) -> bool {
        self.primitives.is_empty()
    }

    /// Forgets everything binned, keeping the allocations.
    pub fn clear(&mut self) {
        self.primitives.clear();
        self.varyings.clear();
        self.states.clear();
        self.state_starts.clear();
        for list in &mut self.lists {
            list.clear();
        }
        self.bytes = FrameDataBytes::default();
        self.binned = 0;
        self.unbinned_bound = 0;
    }

    /// Whether some primitives are appended but not binned yet.
    pub fn unbinned(&self) -> bool {
        self.binned < self.primitives.len()
    }

    /// How many primitives from the front of `primitives` (of a draw with `varying_count`
    /// varyings) surely fit the budget: each costs its record and a polygon-list entry for
    /// every tile its box meets (a bound on the entries binning writes). 0 means full: the
    /// caller renders what is here (an incremental render), clears, and tries again; a
    /// primitive too large for an empty budget still goes in alone.
    ///
    /// Primitives appended but not binned yet count with their bound too, so the answer may
    /// be smaller than once they are binned — never larger. A caller that gets fewer than all
    /// bins them and asks again; when all fit, binning first would have said so as well.
    pub fn fitting(&self, primitives: &[Primitive], varying_count: usize) -> usize {
        let record = record_bytes(varying_count, self.vertex_shading);
        let mut room = self.budget.saturating_sub(self.bytes.total() + self.unbinned_bound);
        let mut count = 0;
        for primitive in primitives {
            let cost = record + POLYGON_LIST_ENTRY_BYTES * self.grid.tiles_meeting_count(&primitive.bbox);
            if cost > room {
                break;
            }
            room -= cost;
            count += 1;
        }
        count
    }

    /// Appends `primitives` under state record `state`, with their varyings: `3 ×
    /// varying_count` per primitive in `varyings`, the first primitive's at its own offset
    /// (one vertex's kept when the state is [`StateRecord::flat_only`]).
    /// Counts their modelled record bytes.
    pub fn append(&mut self, primitives: &[Primitive], varyings: &[f32], state: u32, varying_count: usize) {
        let Some(first) = primitives.first() else { return };
        assert_eq!(state as usize + 1, self.states.len(), "primitives are appended under the latest state record");
        let modelled = record_bytes(varying_count, self.vertex_shading);
        let first_varying = first.varyings as usize;
        let base = self.varyings.len() as u32;
        let flat_only = self.states[state as usize].flat_only && varying_count > 0;
        reserve_huge(&mut self.primitives, primitives.len());
        self.primitives.extend(primitives.iter().enumerate().map(|(k, p)| {
            let mut p = *p;
            p.varyings =
                if flat_only { base + (k * varying_count) as u32 } else { p.varyings - first_varying as u32 + base };
            p.state = state;
            p
        }));
        if flat_only {
            let n = varying_count;
            for chunk in varyings[first_varying..first_varying + 3 * n * primitives.len()].chunks_exact(3 * n) {
                debug_assert!(
                    chunk[..n]
                        .iter()
                        .zip(&chunk[n..2 * n])
                        .chain(chunk[..n].iter().zip(&chunk[2 * n..]))
                        .all(|(a, b)| a.to_bits() == b.to_bits()),
                    "a flat-only primitive's vertices carry the same varyings"
                );
                reserve_huge(&mut self.varyings, n);
                self.varyings.extend_from_slice(&chunk[..n]);
            }
        } else {
            let new = &varyings[first_varying..first_varying + 3 * varying_count * primitives.len()];
            reserve_huge(&mut self.varyings, new.len());
            self.varyings.extend_from_slice(new);
        }
        self.bytes.primitive_records += primitives.len() as u64 * modelled;
        let grid = self.grid;
        self.unbinned_bound +=
            POLYGON_LIST_ENTRY_BYTES * primitives.iter().map(|p| grid.tiles_meeting_count(&p.bbox)).sum::<u64>();
    }

    /// Adds a state record and returns its index.
    pub fn push_state(&mut self, state: StateRecord) -> u32 {
        self.states.push(state);
        self.state_starts.push(self.primitives.len() as u32);
        self.bytes.state_records += STATE_RECORD_BYTES;
        (self.states.len() - 1) as u32
    }

    /// Modelled bytes a tile reads of its polygon `list`: its entries, the record of each
    /// primitive they name, and a state record at each change of state along the list (the
    /// ledger's `FrameDataRead`, counted by the tile task).
    pub fn bytes_read_by(&self, list: &[u32]) -> u64 {
        let mut bytes = list.len() as u64 * POLYGON_LIST_ENTRY_BYTES;
        let mut states = self.state_cursor();
        let mut last_state = u32::MAX;
        for &entry in list {
            let state = states.state_of(entry);
            if state != last_state {
                bytes += STATE_RECORD_BYTES;
                last_state = state;
            }
            bytes += self.state_record_bytes(state);
        }
        bytes
    }

    /// Modelled bytes of a primitive record under state record `state`.
    fn state_record_bytes(&self, state: u32) -> u64 {
        record_bytes(self.states[state as usize].varying_count as usize, self.vertex_shading)
    }

    /// Finds the state record of primitives by index, fastest for ascending indices (a tile's
    /// list), without reading their records.
    pub fn state_cursor(&self) -> StateCursor<'_> {
        StateCursor { starts: &self.state_starts, current: 0 }
    }

    /// Bytes of host memory the frame data occupies.
    pub fn host_bytes(&self) -> u64 {
        (self.primitives.capacity() * std::mem::size_of::<Primitive>()
            + self.varyings.capacity() * 4
            + self.lists.iter().map(|l| l.capacity() * 4).sum::<usize>()) as u64
    }
}

/// Makes room for `additional` more elements as `Vec::reserve` does — the same capacities, so
/// the host bytes reported do not move — except that a buffer of 2 MiB or more is allocated
/// anew and advised for transparent huge pages before anything is written to it.
///
/// Why: a tile reads the records its list names, scattered over the whole array (tris: 1M
/// records, 112 MB), and with 4 KiB pages nearly every one of those cache misses is a TLB miss
/// too, a page walk before the line can even be requested. With 2 MiB pages the array is a
/// few dozen TLB entries. The device keeps its frame data from frame to frame, so only the
/// first frame pays for the copies and the zeroing of the larger pages (docs/benchmarking.md,
/// "Geometry and overdraw, round three").
fn reserve_huge<T: Copy>(v: &mut Vec<T>, additional: usize) {
    if v.capacity() - v.len() >= additional {
        return;
    }
    let required = v.len().checked_add(additional).expect("frame data capacity overflow");
    // `Vec`'s own amortised growth (twice the capacity, or what is required if more).
    let capacity = required.max(2 * v.capacity());
    let bytes = capacity.saturating_mul(std::mem::size_of::<T>());
    if bytes < HUGE_PAGE_BYTES {
        v.reserve(additional);
        return;
    }
    let mut grown = Vec::<T>::with_capacity(capacity);
    advise_huge_pages(grown.as_mut_ptr().cast::<u8>(), bytes);
    grown.extend_from_slice(v);
    *v = grown;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::PixelRect;
    use crate::raster::fixed::SubPixel;

    fn primitive(bbox: PixelRect) -> Primitive {
        let corner = (SubPixel(bbox.x0 * 256), SubPixel(bbox.y0 * 256));
        Primitive {
            window: [corner; 3],
            bbox,
            origin: [bbox.x0 as f32, bbox.y0 as f32],
            l1: [0.0; 2],
            l2: [0.0; 2],
            z: [0.0; 3],
            q: [1.0; 3],
            state: 0,
            varyings: 0,
            vertex_ids: [0, 1, 2],
            front_facing: true,
        }
    }

    #[test]
    fn huge_page_growth_keeps_vec_capacities_and_contents() {
        // Steps of 3, 1000 and 300,000 floats: past the 2 MiB threshold by the end, where the
        // buffer is allocated anew. The capacities must be `Vec`'s (host bytes are reported).
        let (mut ours, mut plain) = (Vec::<f32>::new(), Vec::<f32>::new());
        let mut next = 0.0f32;
        for step in [3usize, 1000, 3, 300_000, 1, 300_000, 700_000, 5] {
            let values: Vec<f32> = (0..step)
                .map(|_| {
                    next += 1.0;
                    next
                })
                .collect();
            reserve_huge(&mut ours, values.len());
            let before = ours.capacity();
            ours.extend_from_slice(&values);
            assert_eq!(ours.capacity(), before, "reserve_huge made room for the step");
            plain.extend_from_slice(&values);
            assert_eq!(ours.capacity(), plain.capacity(), "after a step of {step}");
        }
        assert!(ours.capacity() * 4 >= HUGE_PAGE_BYTES);
        assert_eq!(ours, plain);
    }

    #[test]
    fn a_flat_only_draw_keeps_one_vertex_of_varyings() {
        let grid = TileGrid::new(64, 64, 32, 32);
        let mut frame = FrameData::new(grid, VertexShading::Once, u64::MAX);
        let state_record = |draw, flat_only| StateRecord {
            draw,
            varying_count: 2,
            hsr: HsrMode::Deferred { claims: true },
            fetch: Default::default(),
            subpass: 0,
            flat_only,
        };
        // A batch whose first primitive's varyings start at 6: three primitives, three equal
        // vertices of two varyings each.
        let mut batch = [0, 1, 2].map(|_| primitive(PixelRect::new(0, 0, 8, 8)));
        let mut varyings = vec![-1.0; 6];
        for (k, p) in batch.iter_mut().enumerate() {
            p.varyings = varyings.len() as u32;
            for _ in 0..3 {
                varyings.extend([10.0 * k as f32, 10.0 * k as f32 + 1.0]);
            }
        }
        let flat = frame.push_state(state_record(0, true));
        frame.append(&batch, &varyings, flat, 2);
        assert_eq!(frame.varyings(), &[0.0, 1.0, 10.0, 11.0, 20.0, 21.0]);
        assert_eq!(frame.primitives().iter().map(|p| p.varyings).collect::<Vec<_>>(), [0, 2, 4]);
        // The modelled record still holds three vertices' varyings.
        assert_eq!(frame.bytes.primitive_records, 3 * primitive_record_bytes(2));
        // Another state keeps all three vertices, after them.
        let smooth = frame.push_state(state_record(1, false));
        frame.append(&batch[1..], &varyings, smooth, 2);
        assert_eq!(frame.varyings().len(), 6 + 12);
        assert_eq!(frame.primitives()[3].varyings, 6);
        assert_eq!(frame.primitives()[4].varyings, 12);
        assert_eq!(&frame.varyings()[12..18], &[20.0, 21.0, 20.0, 21.0, 20.0, 21.0]);
    }

    #[test]
    fn the_frame_data_says_when_it_is_full() {
        // 64×64 pixels in 32×32 tiles; no varyings: a record is 8 + 3 × 16 = 56 bytes.
        let grid = TileGrid::new(64, 64, 32, 32);
        let one_tile = primitive(PixelRect::new(0, 0, 8, 8)); // 56 + 4 = 60 bytes
        let four_tiles = primitive(PixelRect::new(16, 16, 48, 48)); // 56 + 16 = 72 bytes
        let budget = STATE_RECORD_BYTES + 60 + 72 + 59;
        let mut frame = FrameData::new(grid, VertexShading::Once, budget);
        let state = frame.push_state(StateRecord {
            draw: 0,
            varying_count: 0,
            hsr: HsrMode::Deferred { claims: true },
            fetch: Default::default(),
            subpass: 0,
            flat_only: false,
        });
        let batch = [one_tile, four_tiles, one_tile];
        assert_eq!(frame.fitting(&batch, 0), 2, "the third needs 60 bytes, 59 are left");
        frame.append(&batch[..2], &[], state, 0);
        assert_eq!(frame.bytes.primitive_records, 2 * 56);
        // Appended, not binned: their entries count at their bound (1 + 4 tiles), 59 left.
        assert_eq!(frame.fitting(&batch[2..], 0), 0);
        // Binning wrote fewer (the 4-tile box has samples in 3 of its tiles): 63 left.
        frame.binned = 2;
        frame.unbinned_bound = 0;
        frame.bytes.polygon_list_entries += 4 * POLYGON_LIST_ENTRY_BYTES;
        assert_eq!(frame.fitting(&batch[2..], 0), 1);
        frame.bytes.polygon_list_entries += POLYGON_LIST_ENTRY_BYTES;
        assert_eq!(frame.fitting(&batch[2..], 0), 0, "full");
        frame.clear();
        assert_eq!(frame.fitting(&batch, 0), 3);
    }

    #[test]
    fn the_state_of_a_primitive_comes_from_the_state_starts() {
        let grid = TileGrid::new(64, 64, 32, 32);
        let mut frame = FrameData::new(grid, VertexShading::Once, u64::MAX);
        let one = primitive(PixelRect::new(0, 0, 8, 8));
        // States with 3, 1, 0 (pushed, never used) and 5 primitives.
        let mut expected = Vec::new();
        for (draw, count) in [3usize, 1, 0, 5].into_iter().enumerate() {
            let state = frame.push_state(StateRecord {
                draw: draw as u32,
                varying_count: 0,
                hsr: HsrMode::Deferred { claims: true },
                fetch: Default::default(),
                subpass: draw as u32 / 2,
                flat_only: false,
            });
            frame.append(&vec![one; count], &[], state, 0);
            expected.extend(std::iter::repeat_n(state, count));
        }
        assert_eq!(frame.primitives().iter().map(|p| p.state).collect::<Vec<_>>(), expected);
        // Ascending (a tile's list), with jumps over several states, and out of order.
        for order in [vec![0, 1, 2, 3, 4, 5, 6, 7, 8], vec![0, 8], vec![2, 4, 8], vec![8, 3, 0, 5, 1, 4]] {
            let mut cursor = frame.state_cursor();
            for index in order {
                assert_eq!(cursor.state_of(index), expected[index as usize], "primitive {index}");
            }
        }
        // Modelled bytes read: three state changes, six records of 56 bytes and six entries.
        assert_eq!(frame.bytes_read_by(&[0, 1, 2, 3, 4, 8]), 3 * STATE_RECORD_BYTES + 6 * (56 + 4));
    }
}
