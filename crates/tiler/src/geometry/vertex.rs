//! Vertex shading: runs the vertex shader once for every vertex a draw references, in
//! parallel, in batches of [`VERTEX_BATCH`], and checks that every position it writes is finite.

use glam::Vec4;
use rayon::prelude::*;

use super::fetch::VertexFetcher;
use crate::api::shader::{VERTEX_BATCH, VertexInput, VertexOutput, VertexShader};

/// Vertices shaded per parallel task.
const CHUNK: usize = 4096;

/// Which vertices a draw references, and where each one's results go ("slots").
#[derive(Clone, Debug)]
pub enum VertexSet {
    /// Slot `i` is vertex `first + i`; all are referenced.
    Range { first: u32, count: u32 },
    /// Slot `i` is vertex `min + i`; bit `i` of `referenced` says whether it is used.
    Dense { min: u32, count: u32, referenced: Vec<u64> },
    /// Slot `i` is vertex `vertices[i]` (sorted, unique): for draws whose indices are spread
    /// too thinly for a dense table.
    Sparse { vertices: Vec<u32> },
}

impl VertexSet {
    pub fn slots(&self) -> usize {
        match self {
            VertexSet::Range { count, .. } | VertexSet::Dense { count, .. } => *count as usize,
            VertexSet::Sparse { vertices } => vertices.len(),
        }
    }

    /// The vertex of slot `slot`, if the draw uses it.
    #[inline]
    fn vertex(&self, slot: usize) -> Option<u32> {
        match self {
            VertexSet::Range { first, .. } => Some(first + slot as u32),
            VertexSet::Dense { min, referenced, .. } => {
                (referenced[slot / 64] >> (slot % 64) & 1 != 0).then_some(min + slot as u32)
            }
            VertexSet::Sparse { vertices } => Some(vertices[slot]),
        }
    }
}

/// The vertex shader's results, per slot.
#[derive(Default)]
pub struct ShadedVertices {
    pub positions: Vec<Vec4>,
    /// `varying_stride` floats per slot.
    pub varyings: Vec<f32>,
    pub varying_count: usize,
    pub varying_stride: usize,
}

impl ShadedVertices {
    #[inline]
    pub fn varyings_of(&self, slot: usize) -> &[f32] {
        &self.varyings[slot * self.varying_stride..slot * self.varying_stride + self.varying_count]
    }
}

/// A vertex whose shaded position is not finite.
#[derive(Clone, Copy, Debug)]
pub struct NonFinitePosition {
    pub vertex: u32,
    pub position: [f32; 4],
}

/// Shades every referenced vertex of `set` into `out`, reusing its memory.
///
/// # Errors
/// The lowest-numbered vertex whose position has a NaN or infinite component.
pub fn shade_vertices<V: VertexShader>(
    shader: &V,
    fetcher: &VertexFetcher,
    set: &VertexSet,
    varying_count: usize,
    out: &mut ShadedVertices,
) -> Result<(), NonFinitePosition> {
    let slots = set.slots();
    let stride = varying_count.max(1);
    out.positions.clear();
    out.positions.resize(slots, Vec4::ZERO);
    out.varyings.clear();
    out.varyings.resize(slots * stride, 0.0);
    out.varying_count = varying_count;
    out.varying_stride = stride;
    let error = out
        .positions
        .par_chunks_mut(CHUNK)
        .zip(out.varyings.par_chunks_mut(CHUNK * stride))
        .enumerate()
        .map(|(chunk, (positions, varyings))| {
            let mut inputs = [VertexInput::default(); VERTEX_BATCH];
            let mut outs = [VertexOutput::default(); VERTEX_BATCH];
            // The chunk's slots of the vertices in `inputs`.
            let mut batch = [0usize; VERTEX_BATCH];
            let mut error = None;
            let mut slots = (0..positions.len()).filter_map(|i| set.vertex(chunk * CHUNK + i).map(|v| (i, v)));
            loop {
                let mut n = 0;
                for (i, vertex) in slots.by_ref().take(VERTEX_BATCH) {
                    fetcher.fetch(vertex, &mut inputs[n]);
                    batch[n] = i;
                    n += 1;
                }
                if n == 0 {
                    break;
                }
                shader.shade_batch(&inputs[..n], &mut outs[..n]);
                for (&i, (out, input)) in batch[..n].iter().zip(outs.iter().zip(&inputs)) {
                    if !out.position.is_finite() && error.is_none() {
                        error =
                            Some(NonFinitePosition { vertex: input.vertex_index, position: out.position.to_array() });
                    }
                    positions[i] = out.position;
                    varyings[i * stride..i * stride + varying_count].copy_from_slice(&out.varyings[..varying_count]);
                }
            }
            error
        })
        .flatten()
        .min_by_key(|e| e.vertex);
    match error {
        Some(error) => Err(error),
        None => Ok(()),
    }
}
