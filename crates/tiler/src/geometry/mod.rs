//! The geometry phase: vertex fetch and shading, primitive assembly, clipping, culling, the
//! viewport transform and triangle setup. It never touches a pixel: its output is primitive
//! records, which the tilers bin into frame data and the immediate-mode backend rasterizes
//! directly.

pub mod assemble;
pub mod clip;
pub mod fetch;
pub mod line;
pub mod primitive;
pub mod setup;
pub mod vertex;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::api::buffer::BufferId;
use crate::api::error::{Error, Result};
use crate::api::pipeline::PipelineDesc;
use crate::api::pipeline::{CullMode, Interpolation, MAX_VARYINGS, ProvokingVertex, Topology};
use crate::api::render_pass::{IndexBufferBinding, IndexType, Rect, VertexBufferBinding, Viewport};
use crate::geometry::primitive::Primitive;
use crate::ledger::cache::{CacheConfig, ReadCache};
use crate::ledger::{Category, Counters, Ledger};
use crate::raster::PixelRect;
use crate::raster::fixed::MAX_VIEWPORT_EXTENT_PX;
use crate::raster::samples::SampleLocations;
use clip::{ClipVertex, ClipVolume};
use fetch::{FetchLayout, SlotVertices, VertexFetcher};
use setup::{DepthOffset, SetupOutcome, SetupParams, ViewportTransform, setup_triangle};
use vertex::{ShadedVertices, VertexSet};

/// Where vertex shading happens on a tiler (seed 004 §24.5).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum VertexShading {
    /// Once per vertex before binning; the post-transform position and varyings of every
    /// primitive are stored in the frame data.
    #[default]
    Once,
    /// A position-only binning pass stores positions; every tile that lists a primitive
    /// fetches its vertices' attributes again and shades them again (a vertex once per tile).
    PerTile,
}

/// Triangles set up per parallel task.
const SETUP_CHUNK: u32 = 1024;

/// An index buffer, decoded on the fly.
#[derive(Clone, Copy)]
struct IndexSource<'a> {
    bytes: &'a [u8],
    index_type: IndexType,
}

impl IndexSource<'_> {
    #[inline]
    fn get(&self, position: u32) -> u32 {
        let p = position as usize;
        match self.index_type {
            IndexType::U16 => u16::from_le_bytes([self.bytes[2 * p], self.bytes[2 * p + 1]]) as u32,
            IndexType::U32 => u32::from_le_bytes([
                self.bytes[4 * p],
                self.bytes[4 * p + 1],
                self.bytes[4 * p + 2],
                self.bytes[4 * p + 3],
            ]),
        }
    }
}

/// A validated draw with its vertices shaded, ready for setup.
pub struct DrawGeometry<'a> {
    pub desc: &'a PipelineDesc,
    indices: Option<IndexSource<'a>>,
    first: u32,
    /// Vertices the draw reads (a line loop's last segment closes on the first).
    count: u32,
    vertex_offset: i64,
    set: VertexSet,
    pub vertices: ShadedVertices,
    pub triangles: u32,
    pub viewport: Viewport,
    pub clip_rect: PixelRect,
    depth_format: Option<crate::Format>,
    /// Vertices a GPU shades for this draw: misses of its post-transform vertex cache.
    pub vertices_shaded: u64,
    /// Bytes of vertex attributes fetched for them: the vertex cache's line fills.
    pub vertex_fetch_bytes: u64,
    /// Where the draw's attributes are, for fetching its vertices again per tile.
    pub fetch: std::sync::Arc<FetchLayout>,
    /// Bytes of indices fetched.
    pub index_fetch_bytes: u64,
    /// Bit `i` set when varying `i` is `Interpolation::Flat`.
    flat_varyings: u64,
}

/// What the pass around a draw looks like.
pub struct PassFrame<'a> {
    pub width: u32,
    pub height: u32,
    pub render_area: PixelRect,
    /// The device's buffers, by id.
    pub buffers: &'a [Vec<u8>],
    /// The depth-stencil attachment's format, if the pass has one (it sets polygon offset's
    /// resolvable difference).
    pub depth_format: Option<crate::Format>,
}

impl<'a> PassFrame<'a> {
    /// The bytes of buffer `id`, if the device has it.
    pub fn buffer(&self, id: BufferId) -> Option<&'a [u8]> {
        self.buffers.get(id.0 as usize).map(Vec::as_slice)
    }
}

/// What the geometry phase reads of a draw (`pass::Draw`): its pipeline's state and vertex
/// stage, its buffers, and which vertices.
#[derive(Clone, Copy)]
pub struct DrawInput<'a> {
    pub desc: &'a PipelineDesc,
    pub vertex: &'a dyn VertexStage,
    pub vertex_buffers: &'a [VertexBufferBinding],
    pub index_buffer: Option<IndexBufferBinding>,
    /// The first vertex (non-indexed) or the first index (indexed).
    pub first: u32,
    /// How many vertices (non-indexed) or indices (indexed).
    pub count: u32,
    /// Added to every index of an indexed draw.
    pub vertex_offset: i32,
    pub viewport: Option<Viewport>,
    pub scissor: Option<Rect>,
}

/// A pipeline's vertex shader behind one dynamic call per draw (implemented by
/// `pixel::pipeline`, where the shaders' types are erased).
pub trait VertexStage: Send + Sync {
    /// Shades `set`'s vertices into `out`, reusing its memory.
    fn shade_vertices(
        &self,
        fetcher: &VertexFetcher,
        set: &VertexSet,
        varying_count: usize,
        out: &mut ShadedVertices,
    ) -> std::result::Result<(), vertex::NonFinitePosition>;
}

/// Validates a draw against its buffers and the pass, and shades its vertices into
/// `vertices` (whose memory is reused: a backend hands back the last draw's).
///
/// # Errors
/// Missing or too short buffers, indices out of range, bad viewports or scissors, and vertex
/// positions that are not finite — each naming the draw.
pub fn prepare_draw<'a>(
    draw_index: usize,
    draw: DrawInput<'a>,
    frame: &PassFrame<'a>,
    post_transform_cache: u32,
    vertex_cache: CacheConfig,
    mut vertices: ShadedVertices,
) -> Result<DrawGeometry<'a>> {
    let desc = draw.desc;
    let fail = |reason: String| Error::draw(draw_index, reason);
    let input = &desc.vertex_input;
    if draw.vertex_buffers.len() < input.bindings.len() {
        return Err(fail(format!(
            "pipeline '{}' reads {} vertex bindings but the draw binds {} vertex buffers",
            desc.label,
            input.bindings.len(),
            draw.vertex_buffers.len()
        )));
    }
    let mut bindings: Vec<&[u8]> = Vec::with_capacity(input.bindings.len());
    for (i, binding) in draw.vertex_buffers.iter().take(input.bindings.len()).enumerate() {
        let bytes = frame
            .buffer(binding.buffer)
            .ok_or_else(|| fail(format!("vertex binding {i}: {} does not exist", binding.buffer)))?;
        if binding.offset > bytes.len() as u64 {
            return Err(fail(format!(
                "vertex binding {i}: offset {} is past the end of {} ({} bytes)",
                binding.offset,
                binding.buffer,
                bytes.len()
            )));
        }
        bindings.push(&bytes[binding.offset as usize..]);
    }

    // The index stream and the range of vertices it references.
    let (indices, min_vertex, max_vertex, index_fetch_bytes) = match &draw.index_buffer {
        None => {
            if draw.count == 0 {
                (None, 0i64, -1i64, 0)
            } else {
                (None, draw.first as i64, draw.first as i64 + draw.count as i64 - 1, 0)
            }
        }
        Some(ib) => {
            let bytes =
                frame.buffer(ib.buffer).ok_or_else(|| fail(format!("index buffer: {} does not exist", ib.buffer)))?;
            let size = ib.index_type.size_bytes();
            let needed = ib.offset + (draw.first as u64 + draw.count as u64) * size;
            if needed > bytes.len() as u64 {
                return Err(fail(format!(
                    "indices {}..{} need {needed} bytes of {} from offset {}, which has {} bytes",
                    draw.first,
                    draw.first as u64 + draw.count as u64,
                    ib.buffer,
                    ib.offset,
                    bytes.len()
                )));
            }
            let source = IndexSource { bytes: &bytes[ib.offset as usize..], index_type: ib.index_type };
            let (mut lo, mut hi) = (i64::MAX, -1i64);
            for p in draw.first..draw.first + draw.count {
                let v = source.get(p) as i64 + draw.vertex_offset as i64;
                if v < 0 || v > u32::MAX as i64 {
                    return Err(fail(format!(
                        "index {} at position {p} plus vertex offset {} gives vertex {v}, outside 0..2^32",
                        source.get(p),
                        draw.vertex_offset
                    )));
                }
                lo = lo.min(v);
                hi = hi.max(v);
            }
            (Some(source), lo, hi, draw.count as u64 * size)
        }
    };

    // Every referenced vertex must have all its attributes inside their buffers.
    if max_vertex >= 0 {
        for (b, binding) in input.bindings.iter().enumerate() {
            let end = input
                .attributes
                .iter()
                .filter(|a| a.binding as usize == b)
                .map(|a| a.offset + a.format.size_bytes())
                .max();
            let Some(end) = end else { continue };
            let len = bindings[b].len() as u64;
            let available = if len < end as u64 {
                0
            } else if binding.stride == 0 {
                u64::MAX
            } else {
                (len - end as u64) / binding.stride as u64 + 1
            };
            if max_vertex as u64 >= available {
                return Err(match indices {
                    Some(source) => {
                        let position = (draw.first..draw.first + draw.count)
                            .find(|&p| (source.get(p) as i64 + draw.vertex_offset as i64) as u64 >= available)
                            .unwrap_or(draw.first);
                        Error::IndexOutOfRange {
                            draw: draw_index,
                            position: position as u64,
                            index: source.get(position),
                            vertex_count: available,
                        }
                    }
                    None => fail(format!(
                        "vertices {}..{} are out of range: vertex binding {b} holds {available} vertices",
                        draw.first,
                        draw.first as u64 + draw.count as u64
                    )),
                });
            }
        }
    }

    let viewport = draw.viewport.unwrap_or(Viewport::full(frame.width, frame.height));
    let viewport_rect = validate_viewport(&viewport).map_err(|r| fail(format!("viewport: {r}")))?;
    let mut clip_rect = viewport_rect.intersect(&frame.render_area);
    if let Some(scissor) = draw.scissor {
        clip_rect = clip_rect.intersect(&scissor_rect(&scissor));
    }

    // Which vertices to shade.
    let set = match indices {
        None => VertexSet::Range { first: draw.first, count: (max_vertex + 1 - min_vertex).max(0) as u32 },
        Some(source) => {
            let span = (max_vertex + 1 - min_vertex).max(0) as u64;
            let offset = draw.vertex_offset as i64;
            if span <= 4 * draw.count as u64 + 65536 {
                let mut referenced = vec![0u64; span.div_ceil(64) as usize];
                for p in draw.first..draw.first + draw.count {
                    let slot = (source.get(p) as i64 + offset - min_vertex) as usize;
                    referenced[slot / 64] |= 1 << (slot % 64);
                }
                VertexSet::Dense { min: min_vertex.max(0) as u32, count: span as u32, referenced }
            } else {
                let mut vertices: Vec<u32> =
                    (draw.first..draw.first + draw.count).map(|p| (source.get(p) as i64 + offset) as u32).collect();
                vertices.sort_unstable();
                vertices.dedup();
                VertexSet::Sparse { vertices }
            }
        }
    };

    let fetcher = VertexFetcher::new(input, &bindings);
    let slots = match &set {
        VertexSet::Range { first, .. } => SlotVertices::From(*first),
        VertexSet::Dense { min, .. } => SlotVertices::From(*min),
        VertexSet::Sparse { vertices } => SlotVertices::List(vertices.as_slice().into()),
    };
    let fetch = FetchLayout::new(input, draw.vertex_buffers, slots);
    // The vertex shader runs in parallel; the count of what a GPU fetches for it, a model
    // walked in stream order, runs beside it on one worker.
    let (shaded, (vertices_shaded, vertex_fetch_bytes)) = rayon::join(
        || draw.vertex.shade_vertices(&fetcher, &set, desc.varyings.len(), &mut vertices),
        || count_vertex_fetch(&draw, indices, &fetch, post_transform_cache, vertex_cache),
    );
    shaded.map_err(|e| Error::NonFinitePosition { draw: draw_index, vertex: e.vertex, position: e.position })?;
    let triangles = assemble::triangle_count(desc.topology, draw.count);
    Ok(DrawGeometry {
        desc: draw.desc,
        indices,
        first: draw.first,
        count: draw.count,
        vertex_offset: draw.vertex_offset as i64,
        set,
        vertices,
        triangles,
        viewport,
        clip_rect,
        depth_format: frame.depth_format,
        vertices_shaded,
        vertex_fetch_bytes,
        fetch: std::sync::Arc::new(fetch),
        index_fetch_bytes,
        flat_varyings: flat_mask(&desc.varyings),
    })
}

/// The work a GPU does for a draw's vertices: without indices every vertex of the stream is
/// shaded; with them, each index that misses the post-transform cache. Each vertex shaded is
/// fetched, in that order, through the vertex cache: `VertexFetch` is its line fills.
/// Returns (vertices shaded, bytes fetched).
fn count_vertex_fetch(
    draw: &DrawInput,
    indices: Option<IndexSource>,
    fetch: &FetchLayout,
    post_transform_cache: u32,
    vertex_cache: CacheConfig,
) -> (u64, u64) {
    let mut cache = ReadCache::new(vertex_cache);
    let mut bytes = 0;
    let range = draw.first..draw.first + draw.count;
    let shaded = match indices {
        Some(source) => {
            let offset = draw.vertex_offset as i64;
            let indices = range.map(|p| source.get(p));
            let mut shade = |index: u32| bytes += fetch.fetch((index as i64 + offset) as u32, &mut cache);
            if post_transform_cache > 0 {
                post_transform_fetch(indices, post_transform_cache, shade)
            } else {
                indices.for_each(&mut shade);
                draw.count as u64
            }
        }
        None => {
            for vertex in range {
                bytes += fetch.fetch(vertex, &mut cache);
            }
            draw.count as u64
        }
    };
    #[cfg(feature = "vertex-cache-reference")]
    assert_eq!(
        (shaded, bytes),
        count_vertex_fetch_reference(draw, indices, fetch, post_transform_cache, vertex_cache),
        "the vertex fetch count disagrees with its reference"
    );
    (shaded, bytes)
}

/// [`count_vertex_fetch`] as it was first written: a hashed FIFO and the general cache model
/// line by line (feature `vertex-cache-reference`).
#[cfg(feature = "vertex-cache-reference")]
fn count_vertex_fetch_reference(
    draw: &DrawInput,
    indices: Option<IndexSource>,
    fetch: &FetchLayout,
    post_transform_cache: u32,
    vertex_cache: CacheConfig,
) -> (u64, u64) {
    let mut cache = crate::ledger::cache::CacheModel::new(vertex_cache);
    let mut bytes = 0;
    let range = draw.first..draw.first + draw.count;
    let shaded = match indices {
        Some(source) if post_transform_cache > 0 => {
            let entries = post_transform_cache as usize;
            let mut fifo = std::collections::VecDeque::with_capacity(entries);
            let mut held = std::collections::HashSet::with_capacity(entries * 2);
            let mut misses = 0;
            for index in range.map(|p| source.get(p)) {
                if held.contains(&index) {
                    continue;
                }
                misses += 1;
                bytes += fetch.fetch_reference((index as i64 + draw.vertex_offset as i64) as u32, &mut cache);
                if fifo.len() == entries {
                    held.remove(&fifo.pop_front().expect("full"));
                }
                fifo.push_back(index);
                held.insert(index);
            }
            misses
        }
        Some(source) => {
            for p in range {
                bytes += fetch.fetch_reference((source.get(p) as i64 + draw.vertex_offset as i64) as u32, &mut cache);
            }
            draw.count as u64
        }
        None => {
            for vertex in range {
                bytes += fetch.fetch_reference(vertex, &mut cache);
            }
            draw.count as u64
        }
    };
    (shaded, bytes)
}

/// Misses of a FIFO post-transform vertex cache of `entries` over an index stream: the
/// vertices a GPU with such a cache shades and fetches, `miss(index)` called for each in
/// stream order. The cache is a ring of the last `entries` indices missed (all different), so
/// a lookup compares them all — a few dozen for real caches, faster than hashing.
fn post_transform_fetch(indices: impl Iterator<Item = u32>, entries: u32, mut miss: impl FnMut(u32)) -> u64 {
    // `u64::MAX` marks an empty entry: no index reaches it.
    let mut ring = vec![u64::MAX; entries as usize];
    let mut next = 0;
    let mut misses = 0;
    for index in indices {
        if ring.contains(&(index as u64)) {
            continue;
        }
        misses += 1;
        miss(index);
        ring[next] = index as u64;
        next = if next + 1 == ring.len() { 0 } else { next + 1 };
    }
    misses
}

/// Bit `i` for each flat varying `i` (`MAX_VARYINGS` fits: checked by the pipeline).
fn flat_mask(varyings: &[Interpolation]) -> u64 {
    const _: () = assert!(MAX_VARYINGS <= 64);
    varyings.iter().enumerate().filter(|(_, m)| **m == Interpolation::Flat).fold(0, |mask, (i, _)| mask | 1 << i)
}

/// Gives the flat varyings (bits of `mask`) of every vertex the provoking vertex's values, as
/// copies: an integer's bits stay as they are.
fn copy_flat(vertices: &mut [ClipVertex], provoking: &[f32; MAX_VARYINGS], mask: u64) {
    for v in vertices {
        let mut bits = mask;
        while bits != 0 {
            let i = bits.trailing_zeros() as usize;
            v.varyings[i] = provoking[i];
            bits &= bits - 1;
        }
    }
}

/// The pixels whose centres lie inside a viewport, after checking its limits.
fn validate_viewport(v: &Viewport) -> std::result::Result<PixelRect, String> {
    let values = [v.x, v.y, v.width, v.height, v.min_depth, v.max_depth];
    if values.iter().any(|f| !f.is_finite()) {
        return Err(format!("{v:?} has a non-finite value"));
    }
    if v.width <= 0.0 || v.height == 0.0 {
        return Err(format!(
            "width {} and height {} must be positive (height may be negative to flip)",
            v.width, v.height
        ));
    }
    let limit = MAX_VIEWPORT_EXTENT_PX as f32;
    let (x0, x1) = (v.x, v.x + v.width);
    let (y0, y1) = (v.y.min(v.y + v.height), v.y.max(v.y + v.height));
    if [x0, x1, y0, y1].iter().any(|c| c.abs() > limit) {
        return Err(format!("corners must lie within ±{limit} pixels of the origin"));
    }
    if !(0.0..=1.0).contains(&v.min_depth) || !(0.0..=1.0).contains(&v.max_depth) {
        return Err(format!("depth range [{}, {}] must lie in [0, 1]", v.min_depth, v.max_depth));
    }
    // Pixel centres p + 0.5 with x0 ≤ p + 0.5 < x1.
    let first = |c: f32| (c - 0.5).ceil() as i32;
    Ok(PixelRect::new(first(x0), first(y0), first(x1), first(y1)))
}

/// A scissor's pixels (coordinates past `i32::MAX` clamped).
pub(crate) fn scissor_rect(r: &Rect) -> PixelRect {
    let clamp = |v: u64| v.min(i32::MAX as u64) as i32;
    PixelRect::new(clamp(r.x as u64), clamp(r.y as u64), clamp(r.right()), clamp(r.bottom()))
}

/// Primitives set up from a range of a draw's triangles.
#[derive(Default)]
pub struct SetupBatch {
    pub primitives: Vec<Primitive>,
    pub varyings: Vec<f32>,
    pub counters: Counters,
}

impl DrawGeometry<'_> {
    /// Counts the draw and what its vertices cost before setup: vertices shaded, and the
    /// ledger's `VertexFetch` (the vertex cache's line fills fetching the vertices shaded, in
    /// the order they are shaded; `geometry::fetch::FetchLayout`) and `IndexFetch`
    /// (`indices × index size`) of the geometry phase — the one call site for both backends.
    pub fn record(&self, counters: &mut Counters, ledger: &mut Ledger) {
        counters.draws += 1;
        counters.vertices_shaded += self.vertices_shaded;
        ledger.add(Category::VertexFetch, self.vertex_fetch_bytes);
        ledger.add(Category::IndexFetch, self.index_fetch_bytes);
    }

    /// The vertex slots of triangle `t`, provoking vertex first.
    #[inline]
    fn triangle_slots(&self, t: u32) -> [usize; 3] {
        assemble::triangle(self.desc.topology, t).map(|p| self.slot(p))
    }

    /// The vertex slot of stream position `p` (relative to the draw's first).
    #[inline]
    fn slot(&self, p: u32) -> usize {
        match self.indices {
            None => p as usize,
            Some(source) => {
                let vertex = (source.get(self.first + p) as i64 + self.vertex_offset) as u32;
                match &self.set {
                    VertexSet::Dense { min, .. } => (vertex - min) as usize,
                    VertexSet::Sparse { vertices } => vertices.binary_search(&vertex).expect("referenced vertex"),
                    VertexSet::Range { .. } => unreachable!("indexed draws use dense or sparse sets"),
                }
            }
        }
    }

    /// Clips, culls and sets up triangles `range`, in parallel, in submission order.
    pub fn setup(&self, range: std::ops::Range<u32>, samples: &SampleLocations, state: u32) -> Vec<SetupBatch> {
        let mut batches = Vec::new();
        let used = self.setup_into(range, samples, state, &mut batches);
        batches.truncate(used);
        batches
    }

    /// [`DrawGeometry::setup`] into `batches`, reusing their memory (a pass sets up every
    /// chunk of every draw into the same batches): returns how many of them, from the first,
    /// hold the triangles' primitives, in submission order.
    pub fn setup_into(
        &self,
        range: std::ops::Range<u32>,
        samples: &SampleLocations,
        state: u32,
        batches: &mut Vec<SetupBatch>,
    ) -> usize {
        let desc = self.desc;
        let params = SetupParams {
            viewport: ViewportTransform::new(&self.viewport),
            clip_rect: self.clip_rect,
            cull_mode: desc.cull_mode,
            front_face: desc.front_face,
            samples: *samples,
            state,
            depth_bias: DepthOffset::new(desc.depth_bias, self.depth_format),
            always_front: false,
        };
        let chunks = if self.clip_rect.is_empty() { 1 } else { range.len().div_ceil(SETUP_CHUNK as usize) };
        if batches.len() < chunks {
            batches.resize_with(chunks, SetupBatch::default);
        }
        for batch in &mut batches[..chunks] {
            batch.primitives.clear();
            batch.varyings.clear();
            batch.counters = Counters::default();
        }
        if self.clip_rect.is_empty() {
            batches[0].counters.triangles_in = range.len() as u64;
            batches[0].counters.triangles_clip_rejected = range.len() as u64;
            return 1;
        }
        let volume = ClipVolume::new(self.viewport.width.abs(), self.viewport.height.abs());
        batches[..chunks].par_iter_mut().enumerate().for_each(|(c, batch)| {
            let start = range.start + c as u32 * SETUP_CHUNK;
            let end = (start + SETUP_CHUNK).min(range.end);
            batch.primitives.reserve((end - start) as usize);
            batch.varyings.reserve((end - start) as usize * 3 * self.vertices.varying_count);
            for t in start..end {
                self.setup_one(t, &params, &volume, batch);
            }
        });
        chunks
    }

    fn setup_one(&self, t: u32, params: &SetupParams, volume: &ClipVolume, batch: &mut SetupBatch) {
        if self.desc.topology.is_line() || self.desc.topology == Topology::PointList {
            return self.setup_line_half(t, params, volume, batch);
        }
        let counters = &mut batch.counters;
        counters.triangles_in += 1;
        let slots = self.triangle_slots(t);
        let positions = slots.map(|s| self.vertices.positions[s]);
        let codes = positions.map(|p| volume.outcode(p));
        if codes[0] & codes[1] & codes[2] != 0 {
            counters.triangles_clip_rejected += 1;
            return;
        }
        let planes = codes[0] | codes[1] | codes[2];
        let ids = slots.map(|s| s as u32);
        if planes == 0 {
            let varyings = slots.map(|s| self.vertices.varyings_of(s));
            let first = batch.varyings.len();
            let outcome = setup_triangle(params, positions, varyings, ids, &mut batch.primitives, &mut batch.varyings);
            if self.flat_varyings != 0 && outcome == SetupOutcome::Primitive {
                // Every vertex takes the provoking vertex's flat values: patched in the three
                // vertices setup appended, rather than copied into `ClipVertex`es first (three
                // 144-byte copies a triangle, measured on tris: docs/benchmarking.md).
                let corner = assemble::provoking_corner(self.desc.topology, t, self.desc.provoking_vertex);
                let provoking = self.vertices.varyings_of(slots[corner]);
                for vertex in batch.varyings[first..].chunks_exact_mut(self.vertices.varying_count) {
                    let mut bits = self.flat_varyings;
                    while bits != 0 {
                        let i = bits.trailing_zeros() as usize;
                        vertex[i] = provoking[i];
                        bits &= bits - 1;
                    }
                }
            }
            count_outcome(&mut batch.counters, outcome);
            return;
        }
        let mut triangle = [0, 1, 2].map(|i| ClipVertex::new(positions[i], self.vertices.varyings_of(slots[i])));
        if self.flat_varyings != 0 {
            // Every vertex carries the provoking vertex's flat values, so setup (which keeps
            // vertex 0's first) and the clipper (which copies vertex 0's) pass them on.
            let corner = assemble::provoking_corner(self.desc.topology, t, self.desc.provoking_vertex);
            let provoking = triangle[corner].varyings;
            copy_flat(&mut triangle, &provoking, self.flat_varyings);
        }
        self.clip_and_set_up(triangle, planes, ids, params, volume, batch);
    }

    /// Triangle `t % 2` of the parallelogram of segment `t / 2`, or of the square of point
    /// `t / 2` (see [`line`]): never culled, always front-facing.
    fn setup_line_half(&self, t: u32, params: &SetupParams, volume: &ClipVolume, batch: &mut SetupBatch) {
        batch.counters.triangles_in += 1;
        let half = [self.viewport.width.abs() / 2.0, self.viewport.height.abs() / 2.0];
        let n = self.vertices.varying_count;
        let vertex = |s: usize| ClipVertex::new(self.vertices.positions[s], self.vertices.varyings_of(s));
        let (corners, corner_ids) = if self.desc.topology == Topology::PointList {
            let slot = self.slot(t / 2);
            let p = vertex(slot);
            // GL clamps the size to the supported range: llvmpipe's is [1, 255].
            let size = self.desc.point_size_varying.map_or(1.0, |v| p.varyings[v]);
            let size = if size.is_nan() { 1.0 } else { size.clamp(1.0, 255.0) };
            (line::point_square(p, size, half, self.desc.point_coord_varying), [slot as u32; 4])
        } else {
            let slots = assemble::segment(self.desc.topology, t / 2, self.count).map(|p| self.slot(p));
            let [a, b] = slots.map(vertex);
            let mut corners = line::parallelogram(a, b, self.desc.line_width, half, n);
            if let Some(corners) = corners.as_mut().filter(|_| self.flat_varyings != 0) {
                // The segment's provoking endpoint, copied over what clipping computed.
                let provoking = match self.desc.provoking_vertex {
                    ProvokingVertex::First => a.varyings,
                    ProvokingVertex::Last => b.varyings,
                };
                copy_flat(corners, &provoking, self.flat_varyings);
            }
            (corners, [0, 1, 1, 0].map(|i| slots[i] as u32))
        };
        let Some(corners) = corners else {
            batch.counters.triangles_clip_rejected += 1;
            return;
        };
        let pick = if t.is_multiple_of(2) { [0, 1, 2] } else { [0, 2, 3] };
        let triangle = pick.map(|i| corners[i]);
        let ids = pick.map(|i| corner_ids[i]);
        let codes = triangle.map(|v| volume.outcode(v.position));
        if codes[0] & codes[1] & codes[2] != 0 {
            batch.counters.triangles_clip_rejected += 1;
            return;
        }
        let params = SetupParams { cull_mode: CullMode::None, always_front: true, ..*params };
        let planes = codes[0] | codes[1] | codes[2];
        if planes == 0 {
            let outcome = setup_triangle(
                &params,
                triangle.map(|v| v.position),
                [0, 1, 2].map(|i| &triangle[i].varyings[..n]),
                ids,
                &mut batch.primitives,
                &mut batch.varyings,
            );
            count_outcome(&mut batch.counters, outcome);
            return;
        }
        self.clip_and_set_up(triangle, planes, ids, &params, volume, batch);
    }

    /// Clips a triangle that crosses `planes` and sets up the pieces.
    fn clip_and_set_up(
        &self,
        triangle: [ClipVertex; 3],
        planes: u8,
        ids: [u32; 3],
        params: &SetupParams,
        volume: &ClipVolume,
        batch: &mut SetupBatch,
    ) {
        let n = self.vertices.varying_count;
        debug_assert!(n <= MAX_VARYINGS);
        let clipped = clip::clip_triangle(volume, triangle, planes, &self.desc.varyings);
        batch.counters.triangles_clipped += 1;
        let Some(poly) = clipped else {
            batch.counters.triangles_clip_rejected += 1;
            return;
        };
        for i in 1..poly.len - 1 {
            let fan = [&poly.vertices[0], &poly.vertices[i], &poly.vertices[i + 1]];
            let outcome = setup_triangle(
                params,
                fan.map(|v| v.position),
                fan.map(|v| &v.varyings[..n]),
                ids,
                &mut batch.primitives,
                &mut batch.varyings,
            );
            count_outcome(&mut batch.counters, outcome);
        }
    }
}

fn count_outcome(counters: &mut Counters, outcome: SetupOutcome) {
    match outcome {
        SetupOutcome::Primitive => counters.primitives += 1,
        SetupOutcome::Culled => counters.triangles_culled += 1,
        SetupOutcome::Degenerate => counters.triangles_degenerate += 1,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ring's misses are a FIFO's, index for index: checked against a queue searched
    /// front to back, over streams with reuse, far indices and `u32::MAX` itself.
    #[test]
    fn post_transform_ring_is_a_fifo() {
        let mut state = 7u32;
        let stream: Vec<u32> = (0..5000)
            .map(|i| {
                state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                match state >> 29 {
                    0 => u32::MAX,
                    1 => state,
                    _ => i / 3 + (state >> 24) % 8,
                }
            })
            .collect();
        for entries in [1, 3, 32, 100] {
            let mut queue = std::collections::VecDeque::new();
            let mut expected = Vec::new();
            for &index in &stream {
                if !queue.contains(&index) {
                    expected.push(index);
                    if queue.len() == entries {
                        queue.pop_front();
                    }
                    queue.push_back(index);
                }
            }
            let mut missed = Vec::new();
            let misses = post_transform_fetch(stream.iter().copied(), entries as u32, |i| missed.push(i));
            assert_eq!(missed, expected, "{entries} entries");
            assert_eq!(misses, expected.len() as u64);
            assert!(misses < stream.len() as u64);
        }
    }
}
