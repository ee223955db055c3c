//! Load and store ops: how a tile's attachments start and end.
//!
//! These two functions are the only places attachment bytes move between external memory and
//! the tile buffer, so the ledger's `TileLoad` and `TileStore` formulas live here:
//! bytes = pixels of the tile inside the render area × samples × bytes of each aspect moved,
//! where a packed D24S8 sample moves as one 32-bit word: 4 bytes whether one aspect or both
//! move (`Format::depth_access_bytes`).
//! The same load function initialises an image in place for immediate mode, where a clear is
//! a write to external memory (`ImrClear`).

use crate::api::format::Format;
pub use crate::api::render_pass::AttachmentOps;
use crate::api::render_pass::{LoadOp, StoreOp};
use crate::raster::PixelRect;
use crate::raster::target::Surface;

/// What a load did: bytes read from external memory, and bytes set to a clear value.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LoadBytes {
    pub loaded: u64,
    pub cleared: u64,
}

/// Bytes a load of `rect` under `ops` reads from external memory (when there is a source
/// image) and sets to a clear value: pixels × samples × bytes of each aspect.
pub fn load_bytes(
    format: Format,
    samples: usize,
    has_source: bool,
    rect: &PixelRect,
    ops: &AttachmentOps,
) -> LoadBytes {
    let pixels = rect.area() * samples as u64;
    let mut bytes = LoadBytes::default();
    match *ops {
        AttachmentOps::Color { load, .. } => match load {
            LoadOp::Load if has_source => bytes.loaded = pixels * format.bytes_per_sample() as u64,
            LoadOp::Clear(_) => bytes.cleared = pixels * format.bytes_per_sample() as u64,
            _ => {}
        },
        AttachmentOps::DepthStencil { depth_load, stencil_load, .. } => {
            // A packed depth-stencil sample moves as one word: an aspect alone costs all of
            // it, both share it (`Format::depth_access_bytes`).
            let stencil_load = if format.has_stencil() { stencil_load } else { LoadOp::DontCare };
            let (depth_loads, stencil_loads) = (depth_load.is_load(), stencil_load.is_load());
            if has_source {
                bytes.loaded += depth_loads as u64 * pixels * format.depth_access_bytes(stencil_loads) as u64;
                bytes.loaded += stencil_loads as u64 * pixels * format.stencil_access_bytes(depth_loads) as u64;
            }
            let depth_clears = matches!(depth_load, LoadOp::Clear(_));
            let stencil_clears = matches!(stencil_load, LoadOp::Clear(_));
            bytes.cleared += depth_clears as u64 * pixels * format.depth_access_bytes(stencil_clears) as u64;
            bytes.cleared += stencil_clears as u64 * pixels * format.stencil_access_bytes(depth_clears) as u64;
        }
    }
    bytes
}

/// What every sample of a tile holds after its load ops, when that does not depend on memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TileStart {
    /// Every sample holds this packed value (a clear; `DontCare` is zero).
    Value([u8; 16]),
    /// Every aspect is loaded from memory: a tile nothing draws in stores back what it loaded.
    Loaded,
    /// Some aspects loaded and others set (D24S8 with one aspect cleared).
    Mixed,
}

/// What the load ops put in a tile of an attachment in `format`.
pub fn tile_start(format: Format, ops: &AttachmentOps) -> TileStart {
    match *ops {
        AttachmentOps::Color { load, .. } => match load {
            LoadOp::Load => TileStart::Loaded,
            LoadOp::Clear(color) => {
                let mut pattern = [0u8; 16];
                format.encode_color(color, &mut pattern[..format.bytes_per_sample()]);
                TileStart::Value(pattern)
            }
            LoadOp::DontCare => TileStart::Value([0; 16]),
        },
        AttachmentOps::DepthStencil { depth_load, stencil_load, .. } => {
            let stencil_load = if format.has_stencil() { stencil_load } else { LoadOp::DontCare };
            let (keep_depth, keep_stencil) = (depth_load.is_load(), stencil_load.is_load() && format.has_stencil());
            if keep_depth && (keep_stencil || !format.has_stencil()) {
                return TileStart::Loaded;
            }
            if keep_depth || keep_stencil {
                return TileStart::Mixed;
            }
            let depth_value = match depth_load {
                LoadOp::Clear(z) => format.depth_bits(z),
                _ => 0,
            };
            let stencil_value = match stencil_load {
                LoadOp::Clear(s) => s,
                _ => 0,
            };
            let word = pack_depth_stencil(format, depth_value, stencil_value);
            let mut pattern = [0u8; 16];
            pattern[..4].copy_from_slice(&word);
            TileStart::Value(pattern)
        }
    }
}

/// The resolve of a pixel whose every sample holds `pattern` (the same arithmetic as
/// [`apply_resolve`], so a tile resolved either way holds the same bytes).
pub fn resolved_value(format: Format, samples: usize, pattern: &[u8; 16]) -> [u8; 16] {
    let mut out = [0u8; 16];
    format.resolve_samples(std::iter::repeat_n(&pattern[..format.bytes_per_sample()], samples), &mut out);
    out
}

/// Sets every sample of `rect` of `dst` to the packed value `pattern`.
pub fn fill_value(dst: &mut Surface, rect: &PixelRect, pattern: &[u8; 16]) {
    fill_rect(dst, rect, &pattern[..dst.format.bytes_per_sample()]);
}

/// Initialises `rect` of `dst` as the load ops say. For a tiler `dst` is the tile buffer and
/// `src` the image in external memory; for immediate mode `dst` is the image itself and `src`
/// is `None` (a `Load` then has nothing to do).
pub fn apply_load(dst: &mut Surface, src: Option<&Surface>, rect: &PixelRect, ops: &AttachmentOps) -> LoadBytes {
    let format = dst.format;
    let samples = dst.samples();
    let bytes = load_bytes(format, samples, src.is_some(), rect, ops);
    match tile_start(format, ops) {
        TileStart::Value(pattern) => {
            fill_value(dst, rect, &pattern);
            if format.has_depth() {
                let bytes = &pattern[..format.bytes_per_sample()];
                dst.start_blocks(rect, Some(crate::depth::stored_depth_bits(format, bytes)));
            }
        }
        TileStart::Loaded => {
            if let Some(src) = src {
                copy_rect(dst, src, rect);
            }
        }
        TileStart::Mixed => {
            if let Some(src) = src {
                copy_rect(dst, src, rect);
            }
            // D24S8 with one aspect loaded and the other set: patch per sample.
            let AttachmentOps::DepthStencil { depth_load, stencil_load, .. } = *ops else {
                unreachable!("only depth-stencil ops mix")
            };
            let keep_depth = depth_load.is_load();
            let depth_value = match depth_load {
                LoadOp::Clear(z) => format.depth_bits(z),
                _ => 0,
            };
            let stencil_value = match stencil_load {
                LoadOp::Clear(s) => s,
                _ => 0,
            };
            let word = pack_depth_stencil(format, depth_value, stencil_value);
            let mask: u32 = if keep_depth { 0xff00_0000 } else { 0x00ff_ffff };
            let value = u32::from_le_bytes(word) & mask;
            for s in 0..samples {
                for y in rect.y0..rect.y1 {
                    for px in dst.row_mut(s, y, rect.x0, rect.x1).chunks_exact_mut(4) {
                        let old = u32::from_le_bytes(px.try_into().unwrap());
                        px.copy_from_slice(&((old & !mask) | value).to_le_bytes());
                    }
                }
            }
        }
    }
    if !matches!(tile_start(format, ops), TileStart::Value(_)) && format.has_depth() {
        dst.start_blocks(rect, None);
    }
    bytes
}

/// Bytes a store of `rect` of `src` writes to external memory under `ops`: pixels × samples ×
/// bytes of each aspect stored.
pub fn store_bytes(src: &Surface, rect: &PixelRect, ops: &AttachmentOps) -> u64 {
    store_bytes_of(src.format, src.samples(), rect, ops)
}

/// [`store_bytes`] for an attachment in `format` with `samples` samples.
pub fn store_bytes_of(format: Format, samples: usize, rect: &PixelRect, ops: &AttachmentOps) -> u64 {
    let per_sample = match *ops {
        AttachmentOps::Color { store, .. } => (store == StoreOp::Store) as u64 * format.bytes_per_sample() as u64,
        AttachmentOps::DepthStencil { depth_store, stencil_store, .. } => {
            // A packed depth-stencil sample moves as one word (`Format::depth_access_bytes`).
            let depth = depth_store == StoreOp::Store;
            let stencil = stencil_store == StoreOp::Store && format.has_stencil();
            depth as u64 * format.depth_access_bytes(stencil) as u64
                + stencil as u64 * format.stencil_access_bytes(depth) as u64
        }
    };
    rect.area() * samples as u64 * per_sample
}

/// Writes `rect` of the tile `src` to the image `dst` as the store ops say; returns the bytes
/// written to external memory ([`store_bytes`]).
pub fn apply_store(src: &Surface, dst: &mut Surface, rect: &PixelRect, ops: &AttachmentOps) -> u64 {
    let bytes = store_bytes(src, rect, ops);
    if bytes > 0 {
        copy_rect(dst, src, rect);
    }
    bytes
}

/// A signature of `rect` of a tile (every sample), for transaction elimination.
pub fn tile_signature(surface: &Surface, rect: &PixelRect) -> u64 {
    // The rectangle is part of the signature: a store of another part of the tile must not
    // match.
    let corners = [rect.x0, rect.y0, rect.x1, rect.y1].map(|c| c as u32).map(u32::to_le_bytes).concat();
    let mut hash = crate::api::image::TileSignatures::hash(0x243f_6a88_85a3_08d3, &corners);
    for s in 0..surface.samples() {
        for y in rect.y0..rect.y1 {
            hash = crate::api::image::TileSignatures::hash(hash, surface.row(s, y, rect.x0, rect.x1));
        }
    }
    hash
}

/// Averages the samples of `rect` of the multisampled `src` into the single-sample `dst`:
/// each channel is the mean of the samples' values (linear values for sRGB formats), packed
/// again in the format; linear 8-bit UNORM formats take the byte nearest the mean, computed on
/// the integers. Returns the pixels resolved.
pub fn apply_resolve(src: &Surface, dst: &mut Surface, rect: &PixelRect) -> u64 {
    let format = src.format;
    let bytes = format.bytes_per_sample();
    let samples = src.samples();
    if format.resolves_as_integers() {
        resolve_bytes(src, dst, rect);
        return rect.area();
    }
    for y in rect.y0..rect.y1 {
        for x in rect.x0..rect.x1 {
            let offset = src.offset(x, y);
            let out = dst.offset(x, y);
            let pixel = (0..samples).map(|s| &src.plane(s)[offset..offset + bytes]);
            format.resolve_samples(pixel, &mut dst.plane_mut(0)[out..out + bytes]);
        }
    }
    rect.area()
}

/// The mean of `samples` bytes whose sum is `sum`, rounded to nearest, halves up:
/// `⌊(Σc + n/2) / n⌋`, the byte nearest the mean of the values `c/255` they encode (the rule
/// of `Format::resolve_samples`).
#[inline(always)]
fn integer_mean(sum: u32, samples: u32) -> u8 {
    ((sum + samples / 2) / samples) as u8
}

/// [`apply_resolve`] of a format that `Format::resolves_as_integers`: per row, every sample's bytes
/// summed into 16-bit lanes, then divided — loops the compiler vectorises.
fn resolve_bytes(src: &Surface, dst: &mut Surface, rect: &PixelRect) {
    const CHUNK: usize = 512;
    let samples = src.samples();
    let n = samples as u32;
    for y in rect.y0..rect.y1 {
        let out = dst.row_mut(0, y, rect.x0, rect.x1);
        for start in (0..out.len()).step_by(CHUNK) {
            let end = (start + CHUNK).min(out.len());
            let mut sums = [0u16; CHUNK];
            for s in 0..samples {
                let row = &src.row(s, y, rect.x0, rect.x1)[start..end];
                for (sum, &c) in sums.iter_mut().zip(row) {
                    *sum += c as u16;
                }
            }
            for (out, &sum) in out[start..end].iter_mut().zip(&sums) {
                *out = integer_mean(sum as u32, n);
            }
        }
    }
}

/// Depth and stencil packed as the format stores them (little-endian bytes).
fn pack_depth_stencil(format: Format, depth_bits: u32, stencil: u8) -> [u8; 4] {
    match format {
        Format::D16Unorm => {
            let b = (depth_bits as u16).to_le_bytes();
            [b[0], b[1], 0, 0]
        }
        Format::D24UnormS8Uint => (depth_bits | (stencil as u32) << 24).to_le_bytes(),
        Format::D32Float => depth_bits.to_le_bytes(),
        _ => unreachable!("depth-stencil ops on colour format {format}"),
    }
}

fn fill_rect(dst: &mut Surface, rect: &PixelRect, pattern: &[u8]) {
    let Some(first) = pattern.first() else { return };
    let uniform = pattern.iter().all(|b| b == first);
    // The pattern repeated over a chunk (pattern sizes 1–16 divide it), then chunk copies
    // (memcpy speed).
    let mut buffer = [0u8; 4096];
    let row_bytes = rect.width() as usize * pattern.len();
    let chunk = &mut buffer[..row_bytes.min(4096)];
    if !uniform && !chunk.is_empty() {
        chunk[..pattern.len()].copy_from_slice(pattern);
        let mut filled = pattern.len();
        while filled < chunk.len() {
            let n = filled.min(chunk.len() - filled);
            chunk.copy_within(..n, filled);
            filled += n;
        }
    }
    for s in 0..dst.samples() {
        for y in rect.y0..rect.y1 {
            let row = dst.row_mut(s, y, rect.x0, rect.x1);
            if uniform {
                row.fill(*first);
            } else {
                for part in row.chunks_mut(chunk.len()) {
                    part.copy_from_slice(&chunk[..part.len()]);
                }
            }
        }
    }
}

fn copy_rect(dst: &mut Surface, src: &Surface, rect: &PixelRect) {
    for s in 0..dst.samples() {
        for y in rect.y0..rect.y1 {
            dst.row_mut(s, y, rect.x0, rect.x1).copy_from_slice(src.row(s, y, rect.x0, rect.x1));
        }
    }
}

impl<T> LoadOp<T> {
    pub fn is_load(&self) -> bool {
        matches!(self, LoadOp::Load)
    }
}

#[cfg(test)]
mod resolve_tests {
    use super::*;

    /// UNORM8 samples resolve to the byte nearest their mean (halves up), wherever the rect
    /// is, and the uniform-tile shortcut agrees with the general resolve.
    #[test]
    fn unorm8_resolves_to_the_nearest_byte_of_the_mean() {
        let (width, height) = (37usize, 5usize);
        for samples in [2usize, 4, 8, 16] {
            let mut state = 7u32;
            let mut planes: Vec<Vec<u8>> = (0..samples)
                .map(|_| {
                    (0..width * height * 4)
                        .map(|_| {
                            state = state.wrapping_mul(1_103_515_245).wrapping_add(12_345);
                            (state >> 23) as u8
                        })
                        .collect()
                })
                .collect();
            let expected: Vec<u8> = (0..width * height * 4)
                .map(|i| {
                    let sum: u32 = planes.iter().map(|p| p[i] as u32).sum();
                    let mean = sum as f64 / samples as f64;
                    // Nearest, halves up.
                    (mean + 0.5).floor() as u8
                })
                .collect();
            let src = Surface::new(Format::Rgba8Unorm, (0, 0), width, planes.iter_mut().map(|p| p.as_mut_slice()));
            let mut out = vec![0u8; width * height * 4];
            let mut dst = Surface::new(Format::Rgba8Unorm, (0, 0), width, [out.as_mut_slice()]);
            let rect = PixelRect { x0: 3, y0: 1, x1: width as i32, y1: height as i32 };
            assert_eq!(apply_resolve(&src, &mut dst, &rect), rect.area());
            for y in 0..height {
                for x in 0..width * 4 {
                    let i = y * width * 4 + x;
                    let inside = y >= 1 && x >= 12;
                    assert_eq!(out[i], if inside { expected[i] } else { 0 }, "{samples} samples, byte {i}");
                }
            }
            let pattern = [200, 13, 0, 255, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0];
            assert_eq!(resolved_value(Format::Rgba8Unorm, samples, &pattern)[..4], pattern[..4]);
            // The row-wise resolve is the per-pixel rule of `Format::resolve_samples`.
            for i in (0..width * height).map(|p| p * 4) {
                let mut one = [0u8; 4];
                Format::Rgba8Unorm.resolve_samples(planes.iter().map(|p| &p[i..i + 4]), &mut one);
                assert_eq!(one[..], expected[i..i + 4], "{samples} samples, pixel {}", i / 4);
            }
        }
    }
}
