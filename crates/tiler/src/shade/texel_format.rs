//! Texel formats of sampled textures: how a texture is stored in external memory, decoded
//! once to the sampler's RGBA8 when the texture is made.
//!
//! The sampler filters RGBA8 (`shade::texture`), so every format is decoded to it at creation;
//! what the format changes is what the texture cache model fetches: a texel's modelled address
//! is where the format stores it ([`StoredLayout`]), so `texture fetch` counts the lines the
//! stored texels occupy — 2 bytes a texel for RGB565, 16 for RGBA32F, a whole 8- or 16-byte
//! block for every texel of an ETC2 or ASTC block.
//!
//! Decoding, per format (what a texel reads as, `c` the stored bits):
//!
//! - **RGBA8**: as stored.
//! - **RGB565, RGBA4444, RGBA5551** (GL's packed 16-bit types, a little-endian `u16`, red in
//!   the high bits) and **RGB10_A2** (`UNSIGNED_INT_2_10_10_10_REV`, a little-endian `u32`,
//!   red in the low bits): an `n`-bit channel `c` is `round(255 · c / (2^n − 1))`, the byte an
//!   8-bit display shows for the UNORM value `c / (2^n − 1)` that GL samples (for 4 bits that
//!   is `c · 17` exactly; 10-bit channels lose their two low bits of precision to the 8-bit
//!   sampler). Missing alpha is 255.
//! - **R16, RG16, RGB16, RGBA16** (`EXT_texture_norm16`, little-endian `u16` channels): each
//!   as the 10-bit channels above, `round(255 · c / 65535)`; missing green and blue are 0,
//!   missing alpha 255.
//! - **R11F_G11F_B10F, RGB9_E5** (GL's packed unsigned floats, a little-endian `u32`): each
//!   channel decoded to its float and then as RGBA16F below; alpha 255.
//! - **RGBA16F, RGBA32F, R32F** (little-endian halves or floats): each channel clamped to
//!   `[0, 1]` (NaN to 0) and rounded to the nearest byte, `round(255 · v)` — what llvmpipe's
//!   8-bit display shows of a float texel sampled with nearest filtering; linear filtering then
//!   blends the bytes, not the floats, a difference below one step of 8 bits. Values outside
//!   `[0, 1]` (HDR) are clamped here: a shader that scales them down again (tone mapping) sees
//!   1.0, so such textures are limited to what an 8-bit texel holds. R32F reads `(r, 0, 0, 1)`.
//! - **ETC1, ETC2 RGB8, ETC2 RGB8A1 (punch-through), ETC2 RGBA8 (EAC alpha), EAC R11, EAC RG11**
//!   (OpenGL ES 3.0 §C.1): decoded by the `texture2ddecoder` crate to bytes (the 11-bit EAC
//!   channels rounded to 8 bits); R11 reads `(r, 0, 0, 1)`, RG11 `(r, g, 0, 1)`.
//! - **ASTC LDR**, any of the 14 footprints from 4×4 to 12×12 (KHR_texture_compression_astc_ldr):
//!   decoded by `texture2ddecoder` to bytes. Each block is first checked against the
//!   specification's rules for illegal blocks (`shade::astc`: reserved block modes, weight grids
//!   larger than the footprint or of too many bits, HDR content, too few bits for the
//!   endpoints …), which the decoder does not check; where the specification decodes such a
//!   block as the error colour, the upload is refused with an error naming the block and the
//!   rule. Encoders never write them. (The decoder still runs under `catch_unwind`, so that a
//!   fault of its own on a legal block is an error, not a crash.)
//!
//! Blocks are in the data row after row from the first row given, each block's texels row
//! after row, as GL uploads them (OpenGL ES 3.0 §3.8.3); a level whose size is not a multiple
//! of the footprint has whole blocks past its edges, whose extra texels are never read.

use super::astc;
use crate::api::error::{Error, Result};

/// How a sampled texture's texels are stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TexelFormat {
    /// 4 bytes a texel (the sampler's own format).
    Rgba8,
    /// 2 bytes: red 5 bits (high), green 6, blue 5.
    Rgb565,
    /// 2 bytes: red, green, blue, alpha, 4 bits each, red high.
    Rgba4444,
    /// 2 bytes: red, green, blue 5 bits each, red high, alpha the low bit.
    Rgba5551,
    /// 4 bytes (GL's `RGB10_A2` of `UNSIGNED_INT_2_10_10_10_REV`, a little-endian `u32`): red
    /// the low 10 bits, then green and blue 10 each, alpha the top 2.
    Rgb10A2,
    /// 2 bytes (`EXT_texture_norm16`'s `R16`, a little-endian `u16`): red.
    R16,
    /// 4 bytes (`RG16`): red, green, 16 bits each.
    Rg16,
    /// 6 bytes (`RGB16`): red, green, blue, 16 bits each.
    Rgb16,
    /// 8 bytes (`RGBA16`): red, green, blue, alpha, 16 bits each.
    Rgba16,
    /// 4 bytes (GL's `R11F_G11F_B10F` of `UNSIGNED_INT_10F_11F_11F_REV`): unsigned floats,
    /// red 11 bits (5 exponent, 6 mantissa) low, green 11, blue 10 (5, 5) high.
    Rg11B10Float,
    /// 4 bytes (GL's `RGB9_E5` of `UNSIGNED_INT_5_9_9_9_REV`): 9-bit mantissas red (low),
    /// green, blue and a shared 5-bit exponent (high).
    Rgb9E5,
    /// 8 bytes: four IEEE halves.
    Rgba16Float,
    /// 16 bytes: four IEEE floats.
    Rgba32Float,
    /// 4 bytes: one IEEE float, red.
    R32Float,
    /// ETC1 (`GL_ETC1_RGB8_OES`): 8 bytes per 4×4 block.
    Etc1Rgb8,
    /// ETC2 RGB8: 8 bytes per 4×4 block.
    Etc2Rgb8,
    /// ETC2 RGB8 with punch-through alpha: 8 bytes per 4×4 block.
    Etc2Rgb8A1,
    /// ETC2 RGBA8 (ETC2 colour and EAC alpha): 16 bytes per 4×4 block.
    Etc2Rgba8,
    /// EAC R11 (unsigned): 8 bytes per 4×4 block.
    EacR11,
    /// EAC RG11 (unsigned): 16 bytes per 4×4 block.
    EacRg11,
    /// ASTC LDR: 16 bytes per `block_width × block_height` block, one of the footprints of
    /// [`ASTC_FOOTPRINTS`].
    Astc { block_width: u8, block_height: u8 },
}

/// The 2D ASTC footprints (`GL_COMPRESSED_RGBA_ASTC_4x4_KHR` … `12x12`), in GL's enum order.
pub const ASTC_FOOTPRINTS: [(u8, u8); 14] = [
    (4, 4),
    (5, 4),
    (5, 5),
    (6, 5),
    (6, 6),
    (8, 5),
    (8, 6),
    (8, 8),
    (10, 5),
    (10, 6),
    (10, 8),
    (10, 10),
    (12, 10),
    (12, 12),
];

/// Where a format puts a level's texels in the modelled memory (see `texture_cache`): blocks
/// of `block_width × block_height` texels of `block_bytes` each, row-major, and within an
/// uncompressed block texel `(x, y)` at `(y · block_width + x) · texel_bytes`. A compressed
/// block is read whole by any of its texels: `texel_bytes` is 0 and every texel is at its
/// block's first byte (a cache line smaller than a block is then counted once per block read;
/// the model is meant for lines of at least 16 bytes, as every GPU's are).
///
/// Uncompressed formats are stored in blocks of 4×4 texels, as RGBA8 always was: GPUs store
/// textures block-linear or in Morton order so that a cache line holds a square of texels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StoredLayout {
    pub block_width: u32,
    pub block_height: u32,
    pub block_bytes: u32,
    pub texel_bytes: u32,
}

impl StoredLayout {
    /// The blocks of a `width × height` level, across and down.
    pub fn blocks(&self, width: u32, height: u32) -> (u32, u32) {
        (width.div_ceil(self.block_width), height.div_ceil(self.block_height))
    }

    /// The bytes of a `width × height` level.
    pub fn level_bytes(&self, width: u32, height: u32) -> u64 {
        let (across, down) = self.blocks(width, height);
        across as u64 * down as u64 * self.block_bytes as u64
    }
}

impl TexelFormat {
    /// Its name, as errors and reports spell it.
    pub fn name(self) -> String {
        match self {
            TexelFormat::Rgba8 => "RGBA8".into(),
            TexelFormat::Rgb565 => "RGB565".into(),
            TexelFormat::Rgba4444 => "RGBA4444".into(),
            TexelFormat::Rgba5551 => "RGBA5551".into(),
            TexelFormat::Rgb10A2 => "RGB10_A2".into(),
            TexelFormat::R16 => "R16".into(),
            TexelFormat::Rg16 => "RG16".into(),
            TexelFormat::Rgb16 => "RGB16".into(),
            TexelFormat::Rgba16 => "RGBA16".into(),
            TexelFormat::Rg11B10Float => "R11F_G11F_B10F".into(),
            TexelFormat::Rgb9E5 => "RGB9_E5".into(),
            TexelFormat::Rgba16Float => "RGBA16F".into(),
            TexelFormat::Rgba32Float => "RGBA32F".into(),
            TexelFormat::R32Float => "R32F".into(),
            TexelFormat::Etc1Rgb8 => "ETC1 RGB8".into(),
            TexelFormat::Etc2Rgb8 => "ETC2 RGB8".into(),
            TexelFormat::Etc2Rgb8A1 => "ETC2 RGB8A1".into(),
            TexelFormat::Etc2Rgba8 => "ETC2 RGBA8".into(),
            TexelFormat::EacR11 => "EAC R11".into(),
            TexelFormat::EacRg11 => "EAC RG11".into(),
            TexelFormat::Astc { block_width, block_height } => format!("ASTC {block_width}×{block_height}"),
        }
    }

    /// Whether it is stored in compressed blocks.
    pub fn is_compressed(self) -> bool {
        self.layout().texel_bytes == 0
    }

    /// Checks an ASTC footprint is one of [`ASTC_FOOTPRINTS`] (every other format is valid).
    ///
    /// # Errors
    /// Another ASTC footprint, naming it.
    pub fn validate(self) -> Result<()> {
        match self {
            TexelFormat::Astc { block_width, block_height }
                if !ASTC_FOOTPRINTS.contains(&(block_width, block_height)) =>
            {
                Err(Error::invalid(
                    "texture",
                    format!("ASTC block {block_width}×{block_height} is not a 2D ASTC footprint (4×4 to 12×12)"),
                ))
            }
            _ => Ok(()),
        }
    }

    /// How it is laid out in the modelled memory.
    pub fn layout(self) -> StoredLayout {
        let texels = |texel_bytes: u32| StoredLayout {
            block_width: 4,
            block_height: 4,
            block_bytes: 16 * texel_bytes,
            texel_bytes,
        };
        let blocks = |block_width: u32, block_height: u32, block_bytes: u32| StoredLayout {
            block_width,
            block_height,
            block_bytes,
            texel_bytes: 0,
        };
        match self {
            TexelFormat::Rgba8
            | TexelFormat::R32Float
            | TexelFormat::Rgb10A2
            | TexelFormat::Rg11B10Float
            | TexelFormat::Rgb9E5
            | TexelFormat::Rg16 => texels(4),
            TexelFormat::Rgb565 | TexelFormat::Rgba4444 | TexelFormat::Rgba5551 | TexelFormat::R16 => texels(2),
            TexelFormat::Rgb16 => texels(6),
            TexelFormat::Rgba16Float | TexelFormat::Rgba16 => texels(8),
            TexelFormat::Rgba32Float => texels(16),
            TexelFormat::Etc1Rgb8 | TexelFormat::Etc2Rgb8 | TexelFormat::Etc2Rgb8A1 | TexelFormat::EacR11 => {
                blocks(4, 4, 8)
            }
            TexelFormat::Etc2Rgba8 | TexelFormat::EacRg11 => blocks(4, 4, 16),
            TexelFormat::Astc { block_width, block_height } => blocks(block_width as u32, block_height as u32, 16),
        }
    }

    /// The bytes a `width × height` level takes in this format, as uploaded: packed texels,
    /// or whole blocks.
    pub fn data_bytes(self, width: u32, height: u32) -> u64 {
        let layout = self.layout();
        if layout.texel_bytes == 0 {
            layout.level_bytes(width, height)
        } else {
            width as u64 * height as u64 * layout.texel_bytes as u64
        }
    }

    /// Decodes a `width × height` level to RGBA8 texels, rows in the order of the data (see the
    /// module notes).
    ///
    /// # Errors
    /// `data` not [`TexelFormat::data_bytes`] long, an invalid ASTC footprint, or a block the
    /// decoder refuses (naming the block).
    pub fn decode(self, width: u32, height: u32, data: &[u8]) -> Result<Vec<[u8; 4]>> {
        self.validate()?;
        let needed = self.data_bytes(width, height);
        if data.len() as u64 != needed {
            let layout = self.layout();
            let what = if layout.texel_bytes == 0 {
                let (across, down) = layout.blocks(width, height);
                format!("{across}×{down} blocks of {} bytes, {needed} bytes", layout.block_bytes)
            } else {
                format!("{needed} bytes")
            };
            return Err(Error::invalid(
                "texture",
                format!("{} bytes of {} data for {width}×{height}, which needs {what}", data.len(), self.name()),
            ));
        }
        let texels = |bytes: usize, f: &dyn Fn(&[u8]) -> [u8; 4]| data.chunks_exact(bytes).map(f).collect();
        let packed = |t: &[u8]| u16::from_le_bytes([t[0], t[1]]) as u32;
        Ok(match self {
            TexelFormat::Rgba8 => texels(4, &|t| [t[0], t[1], t[2], t[3]]),
            TexelFormat::Rgb565 => texels(2, &|t| {
                let v = packed(t);
                [unorm_bits(v >> 11, 5), unorm_bits(v >> 5, 6), unorm_bits(v, 5), 255]
            }),
            TexelFormat::Rgba4444 => texels(2, &|t| {
                let v = packed(t);
                [12, 8, 4, 0].map(|shift| unorm_bits(v >> shift, 4))
            }),
            TexelFormat::Rgba5551 => texels(2, &|t| {
                let v = packed(t);
                [unorm_bits(v >> 11, 5), unorm_bits(v >> 6, 5), unorm_bits(v >> 1, 5), unorm_bits(v, 1)]
            }),
            TexelFormat::Rgb10A2 => texels(4, &|t| {
                let v = u32::from_le_bytes([t[0], t[1], t[2], t[3]]);
                [unorm_bits(v, 10), unorm_bits(v >> 10, 10), unorm_bits(v >> 20, 10), unorm_bits(v >> 30, 2)]
            }),
            TexelFormat::R16 => texels(2, &|t| [unorm_bits(packed(t), 16), 0, 0, 255]),
            TexelFormat::Rg16 => texels(4, &|t| [unorm_bits(packed(t), 16), unorm_bits(packed(&t[2..]), 16), 0, 255]),
            TexelFormat::Rgb16 => texels(6, &|t| {
                let [r, g, b] = [0, 2, 4].map(|i| unorm_bits(packed(&t[i..]), 16));
                [r, g, b, 255]
            }),
            TexelFormat::Rgba16 => texels(8, &|t| [0, 2, 4, 6].map(|i| unorm_bits(packed(&t[i..]), 16))),
            TexelFormat::Rg11B10Float => texels(4, &|t| {
                let v = u32::from_le_bytes([t[0], t[1], t[2], t[3]]);
                let [r, g, b] = [(v, 6), (v >> 11, 6), (v >> 22, 5)].map(|(c, m)| unsigned_float(c, m));
                [float_to_unorm8(r), float_to_unorm8(g), float_to_unorm8(b), 255]
            }),
            TexelFormat::Rgb9E5 => texels(4, &|t| {
                let v = u32::from_le_bytes([t[0], t[1], t[2], t[3]]);
                // GL ES 3.0 §3.8.3.2: c = mantissa · 2^(exponent − 15 − 9).
                let scale = 2f32.powi((v >> 27) as i32 - 24);
                let [r, g, b] = [v, v >> 9, v >> 18].map(|m| (m & 0x1ff) as f32 * scale);
                [float_to_unorm8(r), float_to_unorm8(g), float_to_unorm8(b), 255]
            }),
            TexelFormat::Rgba16Float => texels(8, &|t| {
                std::array::from_fn(|c| float_to_unorm8(half::f16::from_le_bytes([t[2 * c], t[2 * c + 1]]).to_f32()))
            }),
            TexelFormat::Rgba32Float => texels(16, &|t| {
                std::array::from_fn(|c| {
                    float_to_unorm8(f32::from_le_bytes([t[4 * c], t[4 * c + 1], t[4 * c + 2], t[4 * c + 3]]))
                })
            }),
            TexelFormat::R32Float => {
                texels(4, &|t| [float_to_unorm8(f32::from_le_bytes([t[0], t[1], t[2], t[3]])), 0, 0, 255])
            }
            _ => decode_blocks(self, width, height, data)?,
        })
    }
}

impl TexelFormat {
    /// A 16-bit normalised format's level decoded to the sampler's 16-bit channels, as stored
    /// (missing green and blue 0, missing alpha 65535), rows in the order of the data; `None`
    /// for every other format (they decode to bytes: [`TexelFormat::decode`]).
    ///
    /// # Errors
    /// `data` not [`TexelFormat::data_bytes`] long.
    pub fn decode_unorm16(self, width: u32, height: u32, data: &[u8]) -> Option<Result<Vec<[u16; 4]>>> {
        let channels = match self {
            TexelFormat::R16 => 1,
            TexelFormat::Rg16 => 2,
            TexelFormat::Rgb16 => 3,
            TexelFormat::Rgba16 => 4,
            _ => return None,
        };
        let needed = self.data_bytes(width, height);
        if data.len() as u64 != needed {
            return Some(Err(Error::invalid(
                "texture",
                format!("{} bytes of {} data for {width}×{height}, which needs {needed}", data.len(), self.name()),
            )));
        }
        let texel = |t: &[u8]| {
            let mut c = [0, 0, 0, u16::MAX];
            for (i, word) in t.chunks_exact(2).enumerate() {
                c[i] = u16::from_le_bytes([word[0], word[1]]);
            }
            c
        };
        Some(Ok(data.chunks_exact(2 * channels).map(texel).collect()))
    }
}

/// The low `bits` bits of `v` as a UNORM8 byte: `round(255 · c / (2^bits − 1))`.
fn unorm_bits(v: u32, bits: u32) -> u8 {
    let max = (1 << bits) - 1;
    ((v & max) * 255 + max / 2).div_euclid(max) as u8
}

/// A float channel as the byte an 8-bit display shows: clamped to `[0, 1]` (NaN to 0),
/// `round(255 · v)`.
/// An unsigned small float (GL ES 3.0 §2.1.3, 11- and 10-bit): the low `mantissa_bits` of
/// `bits` above a 5-bit exponent; denormals below exponent 1, infinity and NaN at 31.
fn unsigned_float(bits: u32, mantissa_bits: u32) -> f32 {
    let m = (bits & ((1 << mantissa_bits) - 1)) as f32 / (1 << mantissa_bits) as f32;
    match (bits >> mantissa_bits) & 0x1f {
        0 => m * 2f32.powi(-14),
        31 if m == 0.0 => f32::INFINITY,
        31 => f32::NAN,
        e => (1.0 + m) * 2f32.powi(e as i32 - 15),
    }
}

fn float_to_unorm8(v: f32) -> u8 {
    if v.is_nan() { 0 } else { (v.clamp(0.0, 1.0) * 255.0).round() as u8 }
}

/// Decodes a level of a block-compressed format block by block (see the module notes).
fn decode_blocks(format: TexelFormat, width: u32, height: u32, data: &[u8]) -> Result<Vec<[u8; 4]>> {
    let layout = format.layout();
    let (bw, bh) = (layout.block_width as usize, layout.block_height as usize);
    let (across, down) = layout.blocks(width, height);
    let (width, height) = (width as usize, height as usize);
    let mut out = vec![[0u8; 4]; width * height];
    let mut block = [0u32; 144];
    for (index, bytes) in data.chunks_exact(layout.block_bytes as usize).enumerate() {
        let (bx, by) = (index % across as usize, index / across as usize);
        debug_assert!(by < down as usize);
        let texels = &mut block[..bw * bh];
        match format {
            TexelFormat::Etc1Rgb8 => texture2ddecoder::decode_etc1_block(bytes, texels),
            TexelFormat::Etc2Rgb8 => texture2ddecoder::decode_etc2_rgb_block(bytes, texels),
            TexelFormat::Etc2Rgb8A1 => texture2ddecoder::decode_etc2_rgba1_block(bytes, texels),
            TexelFormat::Etc2Rgba8 => texture2ddecoder::decode_etc2_rgba8_block(bytes, texels),
            TexelFormat::EacR11 => texture2ddecoder::decode_eacr_block(bytes, texels),
            TexelFormat::EacRg11 => texture2ddecoder::decode_eacrg_block(bytes, texels),
            TexelFormat::Astc { block_width, block_height } => {
                let block: &[u8; 16] = bytes.try_into().expect("ASTC blocks are 16 bytes");
                let refused = |why: &dyn std::fmt::Display| {
                    Error::invalid(
                        "texture",
                        format!("{} block {index} (block column {bx}, row {by}) is illegal: {why}", format.name()),
                    )
                };
                astc::check_block(block, block_width, block_height).map_err(|why| refused(&why))?;
                // The checks leave the decoder only legal blocks; should it still panic on one,
                // that is its fault, and the upload is refused rather than the process ended.
                let decoded = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    texture2ddecoder::decode_astc_block(bytes, bw, bh, texels)
                }));
                decoded.map_err(|_| refused(&"the decoder failed on it"))?;
            }
            _ => unreachable!("uncompressed formats are decoded by TexelFormat::decode"),
        }
        for y in 0..bh.min(height - by * bh) {
            for x in 0..bw.min(width - bx * bw) {
                // texture2ddecoder's texels are `u32::from_le_bytes([b, g, r, a])`.
                let [b, g, r, a] = texels[y * bw + x].to_le_bytes();
                out[(by * bh + y) * width + bx * bw + x] = [r, g, b, a];
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packed_channels_round_to_the_byte_a_display_shows() {
        // 565: red 31, green 32, blue 1.
        let v: u16 = (31 << 11) | (32 << 5) | 1;
        let t = TexelFormat::Rgb565.decode(1, 1, &v.to_le_bytes()).unwrap();
        // 32/63 · 255 = 129.52 → 130; 1/31 · 255 = 8.23 → 8.
        assert_eq!(t, [[255, 130, 8, 255]]);
        let t = TexelFormat::Rgba4444.decode(1, 1, &0xf08fu16.to_le_bytes()).unwrap();
        assert_eq!(t, [[255, 0, 136, 255]]);
        // Red 1023, green 0, blue 512, alpha 1 (of 3).
        let v: u32 = 1023 | (512 << 20) | (1 << 30);
        assert_eq!(TexelFormat::Rgb10A2.decode(1, 1, &v.to_le_bytes()).unwrap(), [[255, 0, 128, 85]]);
        assert_eq!(TexelFormat::Rgb10A2.layout().texel_bytes, 4);
        // 16-bit channels: 0x8080 → round(255 · 32896 / 65535) = 128, 0x807f → 128 too
        // (127.99), 0x7f7f → 127; missing green and blue 0, missing alpha 255.
        let words = |w: &[u16]| w.iter().flat_map(|v| v.to_le_bytes()).collect::<Vec<u8>>();
        assert_eq!(
            TexelFormat::R16.decode(2, 1, &words(&[0x8080, 0xffff])).unwrap(),
            [[128, 0, 0, 255], [255, 0, 0, 255]]
        );
        assert_eq!(TexelFormat::Rg16.decode(1, 1, &words(&[0x807f, 0x7f7f])).unwrap(), [[128, 127, 0, 255]]);
        assert_eq!(TexelFormat::Rgb16.decode(1, 1, &words(&[0, 0xffff, 0x8080])).unwrap(), [[0, 255, 128, 255]]);
        assert_eq!(TexelFormat::Rgba16.decode(1, 1, &words(&[1, 2, 3, 0x8080])).unwrap(), [[0, 0, 0, 128]]);
        assert_eq!(TexelFormat::Rgb16.layout().texel_bytes, 6);
        assert!(TexelFormat::Rgba16.decode(1, 1, &words(&[1, 2, 3])).is_err());
        // 1.0 (exponent 15), 0.5 (14, in green), 0.25 (13, in the 10-bit blue).
        let v: u32 = (15 << 6) | ((14 << 6) << 11) | ((13 << 5) << 22);
        assert_eq!(TexelFormat::Rg11B10Float.decode(1, 1, &v.to_le_bytes()).unwrap(), [[255, 128, 64, 255]]);
        // Exponent 15 (2^-9 per mantissa step): 511 → 0.998, 256 → 0.5, 0.
        let v: u32 = 511 | (256 << 9) | (15 << 27);
        assert_eq!(TexelFormat::Rgb9E5.decode(1, 1, &v.to_le_bytes()).unwrap(), [[255, 128, 0, 255]]);
        let t = TexelFormat::Rgba5551.decode(1, 1, &0xf800u16.to_le_bytes()).unwrap();
        assert_eq!(t, [[255, 0, 0, 0]]);
    }

    #[test]
    fn floats_clamp_and_round() {
        let halves: Vec<u8> = [0.5f32, 2.0, -1.0, 1.0 / 255.0 * 0.49]
            .iter()
            .flat_map(|&v| half::f16::from_f32(v).to_le_bytes())
            .collect();
        assert_eq!(TexelFormat::Rgba16Float.decode(1, 1, &halves).unwrap(), [[128, 255, 0, 0]]);
        let floats: Vec<u8> = [f32::NAN, 0.25, 1.0, 0.0].iter().flat_map(|v| v.to_le_bytes()).collect();
        assert_eq!(TexelFormat::Rgba32Float.decode(1, 1, &floats).unwrap(), [[0, 64, 255, 0]]);
        assert_eq!(TexelFormat::R32Float.decode(1, 1, &0.5f32.to_le_bytes()).unwrap(), [[128, 0, 0, 255]]);
    }

    #[test]
    fn data_sizes_are_checked_and_named() {
        // 6×6 ETC2 RGBA8: 2×2 blocks of 16 bytes.
        assert_eq!(TexelFormat::Etc2Rgba8.data_bytes(6, 6), 64);
        let e = TexelFormat::Etc2Rgba8.decode(6, 6, &[0; 48]).unwrap_err().to_string();
        assert!(
            e.contains("48 bytes of ETC2 RGBA8 data for 6×6") && e.contains("2×2 blocks of 16 bytes, 64 bytes"),
            "{e}"
        );
        assert_eq!(TexelFormat::Astc { block_width: 6, block_height: 6 }.data_bytes(13, 7), 3 * 2 * 16);
        assert!(TexelFormat::Astc { block_width: 7, block_height: 7 }.decode(7, 7, &[0; 16]).is_err());
        assert!(TexelFormat::Rgb565.decode(2, 1, &[0; 2]).is_err());
    }

    /// An ETC2 RGBA8 block of one colour: EAC alpha with multiplier 0 (every texel the base
    /// alpha), then an ETC1 "individual" block whose two halves have the same 4-bit colour and
    /// table 0 with every index pointing at modifier +2 — the colour `c · 17 + 2`.
    fn flat_etc2_rgba8(rgb4: [u8; 3], alpha: u8) -> [u8; 16] {
        let mut block = [0u8; 16];
        block[0] = alpha;
        let [r, g, b] = rgb4.map(|c| c << 4 | c);
        block[8..12].copy_from_slice(&[r, g, b, 0]);
        block
    }

    /// Any 16 bytes as an ASTC block of any footprint decode or are an error naming the
    /// block and the rule it breaks — never a panic. A deterministic sweep of random blocks:
    /// most random blocks are illegal (`shade::astc`), which the specification decodes as
    /// magenta.
    #[test]
    fn random_astc_blocks_decode_or_are_refused() {
        let mut state = 1u64;
        let mut refused = 0;
        for i in 0..2_000 {
            let (bw, bh) = ASTC_FOOTPRINTS[i % ASTC_FOOTPRINTS.len()];
            let block: [u8; 16] = std::array::from_fn(|_| {
                state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                (state >> 56) as u8
            });
            let format = TexelFormat::Astc { block_width: bw, block_height: bh };
            if let Err(e) = format.decode(bw as u32, bh as u32, &block) {
                assert!(e.to_string().contains("block 0 (block column 0, row 0) is illegal: "), "{e}");
                refused += 1;
            }
        }
        // Both kinds are in the sweep.
        assert!((1..2_000).contains(&refused), "{refused} of 2000 refused");
    }

    #[test]
    fn etc2_and_astc_blocks_decode() {
        let t = TexelFormat::Etc2Rgba8.decode(4, 4, &flat_etc2_rgba8([1, 2, 3], 200)).unwrap();
        assert!(t.iter().all(|&t| t == [19, 36, 53, 200]), "{:?}", t[0]);
        // ASTC void-extent block: LDR constant colour, UNORM16 channels (high bytes used).
        let mut astc = [0u8; 16];
        astc[..8].copy_from_slice(&[0xfc, 0xfd, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff]);
        for (c, v) in [10u8, 20, 30, 40].iter().enumerate() {
            astc[8 + 2 * c..10 + 2 * c].copy_from_slice(&[0, *v]);
        }
        let format = TexelFormat::Astc { block_width: 8, block_height: 8 };
        let t = format.decode(5, 3, &astc).unwrap();
        assert_eq!(t, vec![[10, 20, 30, 40]; 15]);
    }
}
