//! Vertex fetch: reads each attribute of a vertex from its buffer and converts it to a
//! four-component float vector (missing components `(0, 0, 0, 1)`), as GPUs' input assemblers do.

use glam::Vec4;

use crate::api::pipeline::{MAX_VERTEX_ATTRIBUTES, VertexFormat, VertexInputState};
use crate::api::render_pass::VertexBufferBinding;
use crate::api::shader::VertexInput;
#[cfg(feature = "vertex-cache-reference")]
use crate::ledger::cache::CacheModel;
use crate::ledger::cache::ReadCache;

/// One attribute ready to fetch: where its bytes are.
#[derive(Clone, Copy)]
struct AttributeSource<'a> {
    location: usize,
    format: VertexFormat,
    /// The binding's buffer from the binding offset plus the attribute offset.
    bytes: &'a [u8],
    stride: usize,
}

/// Fetches the attributes of a draw's vertices. Built after validation: every vertex index it
/// is asked for has all its attributes inside their buffers.
pub struct VertexFetcher<'a> {
    attributes: Vec<AttributeSource<'a>>,
}

impl<'a> VertexFetcher<'a> {
    /// `bindings[i]` is the bytes of binding `i`'s buffer from the binding's offset on.
    pub fn new(input: &VertexInputState, bindings: &[&'a [u8]]) -> VertexFetcher<'a> {
        let attributes = input
            .attributes
            .iter()
            .map(|a| AttributeSource {
                location: a.location as usize,
                format: a.format,
                bytes: &bindings[a.binding as usize][a.offset as usize..],
                stride: input.bindings[a.binding as usize].stride as usize,
            })
            .collect();
        VertexFetcher { attributes }
    }

    /// Fills `input` with the attributes of vertex `index`.
    #[inline]
    pub fn fetch(&self, index: u32, input: &mut VertexInput) {
        input.vertex_index = index;
        for a in &self.attributes {
            let start = index as usize * a.stride;
            let bytes = &a.bytes[start..start + a.format.size_bytes() as usize];
            input.attributes[a.location] = decode(a.format, bytes);
        }
    }
}

/// Where a draw's attributes lie in external memory, to count what fetching them moves: the
/// vertex cache reads whole lines (64 bytes in the default `DeviceConfig::vertex_cache`), so
/// interleaved and separate layouts, hot/cold splits and strides cost the lines they touch
/// (seed 004 §24.5), not the attributes' exact bytes. Without a cache (size 0) a vertex costs
/// exactly its attributes' bytes.
///
/// Addresses: buffer `id`'s byte `b` is at `id × 2³² + b` (buffers are at most 2³⁰ bytes and
/// start on a line), so two bindings of one buffer share its lines.
#[derive(Clone, Debug, Default)]
pub struct FetchLayout {
    attributes: Vec<AttributeSpan>,
    /// The draw's vertex of each vertex slot (the numbering of `geometry::VertexSet`).
    slots: SlotVertices,
}

/// One attribute: the address of vertex 0's bytes, the binding's stride and the size.
#[derive(Clone, Copy, Debug)]
struct AttributeSpan {
    base: u64,
    stride: u64,
    size: u64,
}

/// How vertex slots map to vertices.
#[derive(Clone, Debug)]
pub enum SlotVertices {
    /// Slot `s` is vertex `first + s`.
    From(u32),
    /// Slot `s` is `vertices[s]`.
    List(std::sync::Arc<[u32]>),
}

impl Default for SlotVertices {
    fn default() -> SlotVertices {
        SlotVertices::From(0)
    }
}

impl FetchLayout {
    /// The layout of `input` over the draw's `buffers`, its slots numbered by `slots`.
    pub fn new(input: &VertexInputState, buffers: &[VertexBufferBinding], slots: SlotVertices) -> FetchLayout {
        let attributes = input
            .attributes
            .iter()
            .map(|a| {
                let binding = &buffers[a.binding as usize];
                AttributeSpan {
                    base: ((binding.buffer.0 as u64) << 32) + binding.offset + a.offset as u64,
                    stride: input.bindings[a.binding as usize].stride as u64,
                    size: a.format.size_bytes() as u64,
                }
            })
            .collect();
        FetchLayout { attributes, slots }
    }

    /// The vertex of slot `slot`.
    pub fn vertex_of_slot(&self, slot: u32) -> u32 {
        match &self.slots {
            SlotVertices::From(first) => first + slot,
            SlotVertices::List(vertices) => vertices[slot as usize],
        }
    }

    /// Reads `vertex`'s attributes through `cache`: returns the bytes read from external
    /// memory — the lines filled (each attribute's bytes split at line boundaries), or the
    /// attributes' own bytes without a cache.
    #[inline]
    pub fn fetch(&self, vertex: u32, cache: &mut ReadCache) -> u64 {
        self.attributes.iter().map(|a| cache.read(a.base + vertex as u64 * a.stride, a.size)).sum()
    }

    /// [`FetchLayout::fetch`] through the general cache model, line by line, as the count was
    /// first written: the reference the read cache is held to (feature
    /// `vertex-cache-reference`).
    #[cfg(feature = "vertex-cache-reference")]
    pub fn fetch_reference(&self, vertex: u32, cache: &mut CacheModel) -> u64 {
        if !cache.config().is_enabled() {
            return self.attributes.iter().map(|a| a.size).sum();
        }
        let line = cache.config().line_bytes as u64;
        let mut read = 0;
        for a in &self.attributes {
            let mut address = a.base + vertex as u64 * a.stride;
            let end = address + a.size;
            while address < end {
                let next = end.min((address | (line - 1)) + 1);
                read += cache.access(address, (next - address) as u32, false, 0).read;
                address = next;
            }
        }
        read
    }
}

impl Default for VertexInput {
    fn default() -> VertexInput {
        VertexInput { attributes: [Vec4::new(0.0, 0.0, 0.0, 1.0); MAX_VERTEX_ATTRIBUTES], vertex_index: 0 }
    }
}

/// Converts one attribute's bytes (little-endian) to a vector. Normalised integers follow
/// Vulkan: UNORM `c / (2^b − 1)`, SNORM `max(c / (2^(b−1) − 1), −1)`.
/// The vector vertex fetch makes of one attribute of `format` from its `size_bytes()` bytes
/// (little-endian), missing components `(0, 0, 0, 1)`: what a driver that reads an attribute
/// itself (a per-instance one, say) hands the vertex shader.
///
/// # Panics
/// If `bytes` is shorter than `format.size_bytes()`.
pub fn read_attribute(format: VertexFormat, bytes: &[u8]) -> [f32; 4] {
    decode(format, &bytes[..format.size_bytes() as usize]).to_array()
}

/// `format`'s value from its bytes `b` (at least `format.size_bytes()` of them).
///
/// # Panics
/// If `b` is shorter than the format.
#[inline]
pub(crate) fn decode(format: VertexFormat, b: &[u8]) -> Vec4 {
    // Float vectors, the common case, as whole words: one bounds check for the attribute
    // rather than one per byte (byte by byte this took 75 instructions a call, 5% of the
    // instructions of the glmark2 shading capture).
    #[inline(always)]
    fn floats<const N: usize>(b: &[u8]) -> Vec4 {
        let words: &[[u8; 4]; N] = b.as_chunks::<4>().0[..N].try_into().expect("N words");
        let mut v = [0.0, 0.0, 0.0, 1.0];
        for (v, word) in v.iter_mut().zip(words) {
            *v = f32::from_le_bytes(*word);
        }
        Vec4::from_array(v)
    }
    let u16_at = |i: usize| u16::from_le_bytes([b[2 * i], b[2 * i + 1]]);
    let unorm8 = |i: usize| b[i] as f32 / 255.0;
    let snorm8 = |i: usize| (b[i] as i8 as f32 / 127.0).max(-1.0);
    let unorm16 = |i: usize| u16_at(i) as f32 / 65535.0;
    let snorm16 = |i: usize| (u16_at(i) as i16 as f32 / 32767.0).max(-1.0);
    let half = |i: usize| half::f16::from_bits(u16_at(i)).to_f32();
    match format {
        VertexFormat::Float32 => floats::<1>(b),
        VertexFormat::Float32x2 => floats::<2>(b),
        VertexFormat::Float32x3 => floats::<3>(b),
        VertexFormat::Float32x4 => floats::<4>(b),
        VertexFormat::Unorm8x4 => Vec4::new(unorm8(0), unorm8(1), unorm8(2), unorm8(3)),
        VertexFormat::Snorm8x4 => Vec4::new(snorm8(0), snorm8(1), snorm8(2), snorm8(3)),
        VertexFormat::Uint8x4 => Vec4::new(b[0] as f32, b[1] as f32, b[2] as f32, b[3] as f32),
        VertexFormat::Unorm16x2 => Vec4::new(unorm16(0), unorm16(1), 0.0, 1.0),
        VertexFormat::Unorm16x4 => Vec4::new(unorm16(0), unorm16(1), unorm16(2), unorm16(3)),
        VertexFormat::Snorm16x2 => Vec4::new(snorm16(0), snorm16(1), 0.0, 1.0),
        VertexFormat::Snorm16x4 => Vec4::new(snorm16(0), snorm16(1), snorm16(2), snorm16(3)),
        VertexFormat::Float16x2 => Vec4::new(half(0), half(1), 0.0, 1.0),
        VertexFormat::Float16x4 => Vec4::new(half(0), half(1), half(2), half(3)),
        VertexFormat::Uint16x2 => Vec4::new(u16_at(0) as f32, u16_at(1) as f32, 0.0, 1.0),
        VertexFormat::Uint32 => Vec4::new(u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32, 0.0, 0.0, 1.0),
        VertexFormat::Int(f) => Vec4::from_array(f.unpack(b).map(f32::from_bits)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::api::buffer::BufferId;
    use crate::api::pipeline::VertexFormat::Float32x4;
    use crate::ledger::cache::CacheConfig;

    fn lines() -> ReadCache {
        ReadCache::new(CacheConfig { size_bytes: 4096, line_bytes: 64, ways: 4 })
    }

    /// Six vertices of a 16-byte position and a 16-byte colour: interleaved they fill 3
    /// lines; in two buffers each stream fills 1½ lines, so 4 lines are read — the half line
    /// at the end of each stream is the separate layout's waste.
    #[test]
    fn lines_of_interleaved_and_separate_layouts() {
        let interleaved = VertexInputState::interleaved(&[Float32x4, Float32x4]);
        let buffer = |id| VertexBufferBinding { buffer: BufferId(id), offset: 0 };
        let layout = FetchLayout::new(&interleaved, &[buffer(0)], SlotVertices::From(0));
        let mut cache = lines();
        assert_eq!((0..6).map(|v| layout.fetch(v, &mut cache)).sum::<u64>(), 3 * 64);
        let separate = VertexInputState::separate(&[Float32x4, Float32x4]);
        let layout = FetchLayout::new(&separate, &[buffer(0), buffer(1)], SlotVertices::From(0));
        let mut cache = lines();
        assert_eq!((0..6).map(|v| layout.fetch(v, &mut cache)).sum::<u64>(), 4 * 64);
        // Without a cache: the exact bytes, 6 × 32.
        let mut none = ReadCache::new(CacheConfig::NONE);
        assert_eq!((0..6).map(|v| layout.fetch(v, &mut none)).sum::<u64>(), 6 * 32);
        // An attribute across a line boundary reads both lines.
        let offset = VertexBufferBinding { buffer: BufferId(0), offset: 56 };
        let layout = FetchLayout::new(&interleaved, &[offset], SlotVertices::List(vec![0].into()));
        assert_eq!(layout.fetch(layout.vertex_of_slot(0), &mut lines()), 2 * 64);
    }

    #[test]
    fn decodes_normalised_integers() {
        assert_eq!(decode(VertexFormat::Unorm8x4, &[0, 255, 51, 255]), Vec4::new(0.0, 1.0, 0.2, 1.0));
        assert_eq!(decode(VertexFormat::Snorm8x4, &[0x80, 0x7f, 0, 0x81]), Vec4::new(-1.0, 1.0, 0.0, -1.0));
        let bytes: Vec<u8> = [1.5f32, -2.0, 3.25].iter().flat_map(|v| v.to_le_bytes()).collect();
        assert_eq!(decode(VertexFormat::Float32x3, &bytes), Vec4::new(1.5, -2.0, 3.25, 1.0));
        assert_eq!(decode(VertexFormat::Float32x2, &bytes), Vec4::new(1.5, -2.0, 0.0, 1.0));
        assert_eq!(decode(VertexFormat::Float32, &bytes), Vec4::new(1.5, 0.0, 0.0, 1.0));
        let four: Vec<u8> = [0.5f32, -0.0, f32::MAX, -7.0].iter().flat_map(|v| v.to_le_bytes()).collect();
        assert_eq!(
            decode(VertexFormat::Float32x4, &four).to_array().map(f32::to_bits),
            [0.5f32, -0.0, f32::MAX, -7.0].map(f32::to_bits)
        );
    }
}
