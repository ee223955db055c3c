//! Texel uploads: GL's client formats, unpacked with `GL_UNPACK_ALIGNMENT`, into the formats
//! the context stores.

use crate::call::TextureFormat;

pub(crate) const GL_ALPHA: u32 = 0x1906;
pub(crate) const GL_RGB: u32 = 0x1907;
pub(crate) const GL_RGBA: u32 = 0x1908;
pub(crate) const GL_LUMINANCE: u32 = 0x1909;
pub(crate) const GL_LUMINANCE_ALPHA: u32 = 0x190a;
pub(crate) const GL_RED: u32 = 0x1903;
pub(crate) const GL_RG: u32 = 0x8227;
/// `EXT_texture_format_BGRA8888` (and `APPLE_texture_format_BGRA8888`): bytes in blue,
/// green, red, alpha order, what compositors and video players upload from their buffers.
pub(crate) const GL_BGRA_EXT: u32 = 0x80e1;
/// Desktop OpenGL's packed type of four bytes in a 32-bit word, first component lowest.
const GL_UNSIGNED_INT_8_8_8_8_REV: u32 = 0x8367;
pub(crate) const GL_DEPTH_COMPONENT: u32 = 0x1902;
pub(crate) const GL_DEPTH_STENCIL: u32 = 0x84f9;
pub(crate) const GL_UNSIGNED_BYTE: u32 = 0x1401;
pub(crate) const GL_UNSIGNED_SHORT: u32 = 0x1403;
pub(crate) const GL_UNSIGNED_INT: u32 = 0x1405;
pub(crate) const GL_UNSIGNED_INT_24_8: u32 = 0x84fa;
pub(crate) const GL_UNSIGNED_SHORT_4_4_4_4: u32 = 0x8033;
pub(crate) const GL_UNSIGNED_SHORT_5_5_5_1: u32 = 0x8034;
pub(crate) const GL_UNSIGNED_SHORT_5_6_5: u32 = 0x8363;
pub(crate) const GL_FLOAT: u32 = 0x1406;
/// `OES_texture_half_float`'s type (GL ES 3.0's `GL_HALF_FLOAT` is `0x140b`).
pub(crate) const GL_HALF_FLOAT_OES: u32 = 0x8d61;
pub(crate) const GL_HALF_FLOAT: u32 = 0x140b;
pub(crate) const GL_BYTE: u32 = 0x1400;
pub(crate) const GL_SHORT: u32 = 0x1402;
pub(crate) const GL_INT: u32 = 0x1404;
pub(crate) const GL_RED_INTEGER: u32 = 0x8d94;
pub(crate) const GL_RG_INTEGER: u32 = 0x8228;
pub(crate) const GL_RGB_INTEGER: u32 = 0x8d98;
pub(crate) const GL_RGBA_INTEGER: u32 = 0x8d99;

/// How a `(format, type)` pair is stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Upload {
    /// The context's format.
    pub format: TextureFormat,
    /// Bytes per texel in the client's memory.
    pub client_bytes: usize,
    format_enum: u32,
    kind: u32,
}

impl Upload {
    /// The storage of a `glTexImage2D` with this internal format, format and type.
    pub fn new(internal_format: u32, format: u32, kind: u32) -> Result<Upload, String> {
        // Desktop GL's `UNSIGNED_INT_8_8_8_8_REV` puts the first component in the lowest byte
        // of a 32-bit word: on the little-endian machines captures come from, the bytes of
        // `UNSIGNED_BYTE` (Qt uploads images as BGRA so).
        let kind = match (format, kind) {
            (GL_RGBA | GL_BGRA_EXT, GL_UNSIGNED_INT_8_8_8_8_REV) => GL_UNSIGNED_BYTE,
            _ => kind,
        };
        // GLES 2.0: the internal format is the format. GL ES 3.0 also takes a sized internal
        // format of the format's base (its table 3.2, `RGBA8` for `RGBA`, `DEPTH_COMPONENT24`
        // for `DEPTH_COMPONENT`, …); the sized ones the replay stores are listed in `sized`.
        if let Some(upload) = integer_upload(internal_format, format, kind)? {
            return Ok(upload);
        }
        let sized = sized_internal_format(internal_format);
        // BGRA bytes into an RGBA texture: APPLE_texture_format_BGRA8888, and desktop OpenGL
        // (Qt Quick's canvas uploads so).
        let base = if format == GL_BGRA_EXT { GL_RGBA } else { format };
        let internal_ok = internal_format == format
            || internal_format == base
            || sized.is_some_and(|(sized_base, _)| sized_base == format || sized_base == base);
        if !internal_ok {
            return Err(format!(
                "internal format {internal_format:#06x} with format {format:#06x} is not a combination the replay \
                 converts (GLES 2.0's unsized formats and GL ES 3.0's RGBA8, RGB8, RG8, R8, RGB565, RGBA4, \
                 RGB5_A1, SRGB8_ALPHA8, RGBA16F/32F, RGB16F/32F, RG16F/32F, R16F/32F, DEPTH_COMPONENT16/24/32F, \
                 DEPTH24_STENCIL8)"
            ));
        }
        let (mut stored, client_bytes) = match (format, kind) {
            (GL_RGBA | GL_BGRA_EXT, GL_UNSIGNED_BYTE) => (TextureFormat::Rgba8, 4),
            (GL_RGB, GL_UNSIGNED_BYTE) => (TextureFormat::Rgba8, 3),
            (GL_LUMINANCE_ALPHA | GL_RG, GL_UNSIGNED_BYTE) => (TextureFormat::Rgba8, 2),
            (GL_LUMINANCE | GL_ALPHA | GL_RED, GL_UNSIGNED_BYTE) => (TextureFormat::Rgba8, 1),
            (GL_RGB, GL_UNSIGNED_SHORT_5_6_5) => (TextureFormat::Rgb565, 2),
            (GL_RGBA, GL_HALF_FLOAT_OES | GL_HALF_FLOAT) => (TextureFormat::Rgba16f, 8),
            (GL_RGB, GL_HALF_FLOAT_OES | GL_HALF_FLOAT) => (TextureFormat::Rgba16f, 6),
            (GL_RGBA, GL_FLOAT) => (TextureFormat::Rgba32f, 16),
            (GL_RGB, GL_FLOAT) => (TextureFormat::Rgba32f, 12),
            (GL_RG, GL_HALF_FLOAT_OES | GL_HALF_FLOAT) => (TextureFormat::Rgba16f, 4),
            (GL_RED, GL_HALF_FLOAT_OES | GL_HALF_FLOAT) => (TextureFormat::Rgba16f, 2),
            (GL_RG, GL_FLOAT) => (TextureFormat::Rgba32f, 8),
            (GL_RED, GL_FLOAT) => (TextureFormat::R32f, 4),
            (GL_DEPTH_COMPONENT, GL_UNSIGNED_SHORT) => (TextureFormat::Depth16, 2),
            (GL_DEPTH_COMPONENT, GL_UNSIGNED_INT) => (TextureFormat::Depth24, 4),
            (GL_DEPTH_COMPONENT, GL_FLOAT) => (TextureFormat::Depth32f, 4),
            (GL_DEPTH_STENCIL, GL_UNSIGNED_INT_24_8) => (TextureFormat::Depth24Stencil8, 4),
            _ => {
                return Err(format!(
                    "texel format {format:#06x} of type {kind:#06x} is not one the replay converts (RGBA, RGB, RG, \
                     RED, LUMINANCE, LUMINANCE_ALPHA, ALPHA, BGRA bytes; 565; RGBA, RGB, RG, RED halves and floats; \
                     DEPTH_COMPONENT; 4444 and 5551 are encoded uploads)"
                ));
            }
        };
        // A sized internal format picks the storage where the type alone does not say it: sRGB
        // bytes, the depth format's precision. Sized formats of more precision than the
        // client's type (RGB565 from bytes: GL rounds each texel to 5/6 bits) are refused
        // rather than stored at the type's precision.
        if let Some((_, storage)) = sized {
            match (storage, stored) {
                (Some(storage), _) if storage.has_depth() || storage == TextureFormat::Srgb8Alpha8 => stored = storage,
                (Some(TextureFormat::Rgb565), TextureFormat::Rgba8) => {
                    return Err(format!(
                        "internal format RGB565 ({internal_format:#06x}) from type {kind:#06x}: the replay converts \
                         RGB565 from UNSIGNED_SHORT_5_6_5 texels only"
                    ));
                }
                _ => {}
            }
        }
        Ok(Upload { format: stored, client_bytes, format_enum: format, kind })
    }

    /// Whether these texels can fill (part of) a texture stored as `stored`: the same storage,
    /// or bytes into sRGB storage (GL ES 3.0 uploads `SRGB8_ALPHA8` from `RGBA` bytes, stored
    /// as given).
    pub fn fills(&self, stored: TextureFormat) -> bool {
        self.format == stored || (self.format == TextureFormat::Rgba8 && stored == TextureFormat::Srgb8Alpha8)
    }

    /// Converts `width × height` client texels (rows bottom to top, each starting at a
    /// multiple of `alignment`) into the stored format, rows bottom to top and packed.
    pub fn convert(&self, data: &[u8], width: u32, height: u32, alignment: u32) -> Result<Vec<u8>, String> {
        if !self.format.is_color() {
            return Err(format!("uploading texels to a {} texture is not supported", self.format.name()));
        }
        let row = width as usize * self.client_bytes;
        let stride = row.div_ceil(alignment.max(1) as usize) * alignment.max(1) as usize;
        let needed = if height == 0 { 0 } else { stride * (height as usize - 1) + row };
        if data.len() < needed {
            return Err(format!(
                "{} bytes of texels, but {width}×{height} with rows aligned to {alignment} needs {needed}",
                data.len()
            ));
        }
        let out_bytes = self.format.format().bytes_per_sample();
        let mut out = Vec::with_capacity(width as usize * height as usize * out_bytes);
        for y in 0..height as usize {
            let src = &data[y * stride..y * stride + row];
            if let TextureFormat::Int(f) = self.format {
                if self.client_bytes == f.bytes() {
                    out.extend_from_slice(src);
                } else {
                    // RGB integers are stored as RGBA with alpha the integer 1 (what GL reads).
                    let one = &1u32.to_le_bytes()[..f.bits as usize / 8];
                    src.chunks_exact(self.client_bytes).for_each(|t| {
                        out.extend_from_slice(t);
                        out.extend_from_slice(one);
                    });
                }
                continue;
            }
            match (self.format_enum, self.kind) {
                (_, GL_UNSIGNED_SHORT_5_6_5)
                | (GL_RGBA, GL_UNSIGNED_BYTE | GL_HALF_FLOAT_OES | GL_HALF_FLOAT | GL_FLOAT)
                | (GL_RED, GL_FLOAT) => out.extend_from_slice(src),
                // Green and blue 0, alpha 1, as a half and as a float.
                (GL_RED | GL_RG, GL_HALF_FLOAT_OES | GL_HALF_FLOAT) => {
                    src.chunks_exact(self.client_bytes).for_each(|t| {
                        out.extend_from_slice(t);
                        out.resize(out.len() + 6 - t.len(), 0);
                        out.extend_from_slice(&0x3c00u16.to_le_bytes());
                    })
                }
                (GL_RG, GL_FLOAT) => src.chunks_exact(8).for_each(|t| {
                    out.extend_from_slice(t);
                    out.extend_from_slice(&0.0f32.to_le_bytes());
                    out.extend_from_slice(&1.0f32.to_le_bytes());
                }),
                // Alpha 1.0 as a half and as a float.
                (GL_RGB, GL_HALF_FLOAT_OES | GL_HALF_FLOAT) => src.chunks_exact(6).for_each(|t| {
                    out.extend_from_slice(t);
                    out.extend_from_slice(&0x3c00u16.to_le_bytes());
                }),
                (GL_RGB, GL_FLOAT) => src.chunks_exact(12).for_each(|t| {
                    out.extend_from_slice(t);
                    out.extend_from_slice(&1.0f32.to_le_bytes());
                }),
                // Written in place (a texel at a time through `extend_from_slice` checks the
                // capacity at each: an 800×600 upload took 2.6 ms).
                (GL_RGB, _) => {
                    let start = out.len();
                    out.resize(start + width as usize * 4, 255);
                    for (rgba, rgb) in out[start..].chunks_exact_mut(4).zip(src.chunks_exact(3)) {
                        rgba[..3].copy_from_slice(rgb);
                    }
                }
                (GL_BGRA_EXT, _) => src.chunks_exact(4).for_each(|t| out.extend_from_slice(&[t[2], t[1], t[0], t[3]])),
                (GL_LUMINANCE_ALPHA, _) => {
                    src.chunks_exact(2).for_each(|t| out.extend_from_slice(&[t[0], t[0], t[0], t[1]]))
                }
                (GL_LUMINANCE, _) => src.iter().for_each(|&l| out.extend_from_slice(&[l, l, l, 255])),
                // GL ES 3.0 §3.8.15: a texture without green or blue reads 0 there, alpha 1.
                (GL_RED, _) => src.iter().for_each(|&r| out.extend_from_slice(&[r, 0, 0, 255])),
                (GL_RG, _) => src.chunks_exact(2).for_each(|t| out.extend_from_slice(&[t[0], t[1], 0, 255])),
                (GL_ALPHA, _) => src.iter().for_each(|&a| out.extend_from_slice(&[0, 0, 0, a])),
                _ => unreachable!("Upload::new accepts only the pairs converted here"),
            }
        }
        Ok(out)
    }
}

/// A GL ES 3.0 integer internal format (`GL_RGBA8UI`, `GL_R32I`, … table 3.13): channels,
/// bits, signed. RGB ones are stored with an alpha channel (`integer_storage`).
pub(crate) fn integer_internal_format(internal_format: u32) -> Option<(u8, u8, bool)> {
    Some(match internal_format {
        0x8d70 => (4, 32, false),
        0x8d71 => (3, 32, false),
        0x8d76 => (4, 16, false),
        0x8d77 => (3, 16, false),
        0x8d7c => (4, 8, false),
        0x8d7d => (3, 8, false),
        0x8d82 => (4, 32, true),
        0x8d83 => (3, 32, true),
        0x8d88 => (4, 16, true),
        0x8d89 => (3, 16, true),
        0x8d8e => (4, 8, true),
        0x8d8f => (3, 8, true),
        0x8231 => (1, 8, true),
        0x8232 => (1, 8, false),
        0x8233 => (1, 16, true),
        0x8234 => (1, 16, false),
        0x8235 => (1, 32, true),
        0x8236 => (1, 32, false),
        0x8237 => (2, 8, true),
        0x8238 => (2, 8, false),
        0x8239 => (2, 16, true),
        0x823a => (2, 16, false),
        0x823b => (2, 32, true),
        0x823c => (2, 32, false),
        _ => return None,
    })
}

/// How the context stores an integer format of `channels` (3 is stored as 4, alpha 1).
pub(crate) fn integer_storage((channels, bits, signed): (u8, u8, bool)) -> TextureFormat {
    TextureFormat::Int(tiler::IntFormat { channels: if channels == 3 { 4 } else { channels }, bits, signed })
}

/// The client format and type of texels that fill an integer texture stored as `format`.
pub(crate) fn integer_client(format: tiler::IntFormat) -> (u32, u32) {
    let base = match format.channels {
        1 => GL_RED_INTEGER,
        2 => GL_RG_INTEGER,
        _ => GL_RGBA_INTEGER,
    };
    let kind = match (format.bits, format.signed) {
        (8, true) => GL_BYTE,
        (8, false) => GL_UNSIGNED_BYTE,
        (16, true) => GL_SHORT,
        (16, false) => GL_UNSIGNED_SHORT,
        (_, true) => GL_INT,
        (_, false) => GL_UNSIGNED_INT,
    };
    (base, kind)
}

/// The upload of integer texels (`*_INTEGER` formats, GL ES 3.0 table 3.2): `None` for
/// other formats; an integer internal format with a format or type it does not take is an
/// error.
fn integer_upload(internal_format: u32, format: u32, kind: u32) -> Result<Option<Upload>, String> {
    let internal = integer_internal_format(internal_format);
    let channels = match format {
        GL_RED_INTEGER => 1,
        GL_RG_INTEGER => 2,
        GL_RGB_INTEGER => 3,
        GL_RGBA_INTEGER => 4,
        _ if internal.is_some() => {
            return Err(format!(
                "integer internal format {internal_format:#06x} with format {format:#06x} (an *_INTEGER format is \
                 needed)"
            ));
        }
        _ => return Ok(None),
    };
    let (bits, signed) = match kind {
        GL_BYTE => (8, true),
        GL_UNSIGNED_BYTE => (8, false),
        GL_SHORT => (16, true),
        GL_UNSIGNED_SHORT => (16, false),
        GL_INT => (32, true),
        GL_UNSIGNED_INT => (32, false),
        _ => return Err(format!("integer texels of type {kind:#06x} (byte, short or int types only)")),
    };
    let given = (channels, bits, signed);
    if internal_format != format && internal != Some(given) {
        return Err(format!(
            "internal format {internal_format:#06x} from format {format:#06x} / type {kind:#06x}: not a combination \
             GL ES 3.0 takes (table 3.2)"
        ));
    }
    Ok(Some(Upload {
        format: integer_storage(given),
        client_bytes: channels as usize * bits as usize / 8,
        format_enum: format,
        kind,
    }))
}

/// A GL ES 3.0 sized internal format the replay stores: its base format and, where the sized
/// format decides it, the storage.
fn sized_internal_format(internal_format: u32) -> Option<(u32, Option<TextureFormat>)> {
    Some(match internal_format {
        // RGBA4, RGB5_A1, RGBA8
        0x8056..=0x8058 => (GL_RGBA, None),
        0x881a /* RGBA16F */ => (GL_RGBA, Some(TextureFormat::Rgba16f)),
        0x8814 /* RGBA32F */ => (GL_RGBA, Some(TextureFormat::Rgba32f)),
        0x8c43 /* SRGB8_ALPHA8 */ => (GL_RGBA, Some(TextureFormat::Srgb8Alpha8)),
        0x8051 /* RGB8 */ => (GL_RGB, None),
        0x8d62 /* RGB565 */ => (GL_RGB, Some(TextureFormat::Rgb565)),
        0x881b /* RGB16F */ => (GL_RGB, Some(TextureFormat::Rgba16f)),
        0x8815 /* RGB32F */ => (GL_RGB, Some(TextureFormat::Rgba32f)),
        0x822b /* RG8 */ => (GL_RG, None),
        0x8229 /* R8 */ => (GL_RED, None),
        0x822d /* R16F */ => (GL_RED, Some(TextureFormat::Rgba16f)),
        0x822f /* RG16F */ => (GL_RG, Some(TextureFormat::Rgba16f)),
        0x822e /* R32F */ => (GL_RED, Some(TextureFormat::R32f)),
        0x8230 /* RG32F */ => (GL_RG, Some(TextureFormat::Rgba32f)),
        0x81a5 /* DEPTH_COMPONENT16 */ => (GL_DEPTH_COMPONENT, Some(TextureFormat::Depth16)),
        0x81a6 /* DEPTH_COMPONENT24 */ => (GL_DEPTH_COMPONENT, Some(TextureFormat::Depth24)),
        0x8cac /* DEPTH_COMPONENT32F */ => (GL_DEPTH_COMPONENT, Some(TextureFormat::Depth32f)),
        0x88f0 /* DEPTH24_STENCIL8 */ => (GL_DEPTH_STENCIL, Some(TextureFormat::Depth24Stencil8)),
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rgb_rows_honour_the_unpack_alignment() {
        // 1×2 RGB: rows of 3 bytes padded to 4.
        let up = Upload::new(GL_RGB, GL_RGB, GL_UNSIGNED_BYTE).unwrap();
        let data = [1, 2, 3, 99, 4, 5, 6];
        assert_eq!(up.convert(&data, 1, 2, 4).unwrap(), [1, 2, 3, 255, 4, 5, 6, 255]);
        assert_eq!(up.convert(&data[..6], 1, 2, 1).unwrap(), [1, 2, 3, 255, 99, 4, 5, 255]);
        assert!(up.convert(&data[..6], 1, 2, 4).is_err());
    }

    #[test]
    fn float_rgb_gets_alpha_one() {
        let up = Upload::new(GL_RGB, GL_RGB, GL_HALF_FLOAT_OES).unwrap();
        assert_eq!(up.format, TextureFormat::Rgba16f);
        assert_eq!(up.convert(&[1, 2, 3, 4, 5, 6], 1, 1, 1).unwrap(), [1, 2, 3, 4, 5, 6, 0x00, 0x3c]);
        let up = Upload::new(0x8814, GL_RGBA, GL_FLOAT).unwrap();
        assert_eq!((up.format, up.client_bytes), (TextureFormat::Rgba32f, 16));
        let rgb: Vec<u8> = [0.5f32, 0.25, 1.0].iter().flat_map(|v| v.to_le_bytes()).collect();
        let rgba: Vec<u8> = [0.5f32, 0.25, 1.0, 1.0].iter().flat_map(|v| v.to_le_bytes()).collect();
        assert_eq!(Upload::new(GL_RGB, GL_RGB, GL_FLOAT).unwrap().convert(&rgb, 1, 1, 4).unwrap(), rgba);
    }

    #[test]
    fn single_channels_expand_to_rgba() {
        // 4444 and 5551 are encoded uploads (`capture::encoded`), decoded by the core.
        assert!(Upload::new(GL_RGBA, GL_RGBA, GL_UNSIGNED_SHORT_4_4_4_4).is_err());
        let up = Upload::new(GL_LUMINANCE, GL_LUMINANCE, GL_UNSIGNED_BYTE).unwrap();
        assert_eq!(up.convert(&[7], 1, 1, 1).unwrap(), [7, 7, 7, 255]);
        let up = Upload::new(GL_ALPHA, GL_ALPHA, GL_UNSIGNED_BYTE).unwrap();
        assert_eq!(up.convert(&[7], 1, 1, 1).unwrap(), [0, 0, 0, 7]);
    }

    #[test]
    fn gles3_sized_internal_formats_store_as_their_base_or_as_they_say() {
        let up = Upload::new(0x8058, GL_RGBA, GL_UNSIGNED_BYTE).unwrap();
        assert_eq!((up.format, up.client_bytes), (TextureFormat::Rgba8, 4));
        let up = Upload::new(0x8229, GL_RED, GL_UNSIGNED_BYTE).unwrap();
        assert_eq!(up.convert(&[9, 8, 0, 0, 7, 6], 2, 1, 4).unwrap(), [9, 0, 0, 255, 8, 0, 0, 255]);
        let up = Upload::new(0x822b, GL_RG, GL_UNSIGNED_BYTE).unwrap();
        assert_eq!(up.convert(&[9, 8], 1, 1, 4).unwrap(), [9, 8, 0, 255]);
        assert_eq!(Upload::new(0x8c43, GL_RGBA, GL_UNSIGNED_BYTE).unwrap().format, TextureFormat::Srgb8Alpha8);
        // Half-float red and red-green: green and blue 0, alpha 1.
        let up = Upload::new(0x822d, GL_RED, GL_HALF_FLOAT).unwrap();
        assert_eq!(up.convert(&[0x00, 0x38], 1, 1, 1).unwrap(), [0x00, 0x38, 0, 0, 0, 0, 0x00, 0x3c]);
        let up = Upload::new(0x822f, GL_RG, GL_HALF_FLOAT).unwrap();
        assert_eq!(up.convert(&[1, 2, 3, 4], 1, 1, 1).unwrap(), [1, 2, 3, 4, 0, 0, 0x00, 0x3c]);
        assert_eq!(Upload::new(0x822e, GL_RED, GL_FLOAT).unwrap().format, TextureFormat::R32f);
        assert_eq!(Upload::new(0x81a6, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT).unwrap().format, TextureFormat::Depth24);
        assert_eq!(Upload::new(0x81a5, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT).unwrap().format, TextureFormat::Depth16);
        assert_eq!(Upload::new(0x8cac, GL_DEPTH_COMPONENT, GL_FLOAT).unwrap().format, TextureFormat::Depth32f);
        // A sized format of another base, and RGB565 from bytes (GL would round to 5/6 bits).
        assert!(Upload::new(0x8058, GL_RGB, GL_UNSIGNED_BYTE).is_err());
        assert!(Upload::new(0x8d62, GL_RGB, GL_UNSIGNED_BYTE).unwrap_err().contains("RGB565"));
        assert_eq!(Upload::new(0x8d62, GL_RGB, GL_UNSIGNED_SHORT_5_6_5).unwrap().format, TextureFormat::Rgb565);
    }

    #[test]
    fn bgra_bytes_fill_rgba_textures() {
        // EXT_texture_format_BGRA8888's BGRA into BGRA, APPLE's and desktop GL's into RGBA(8).
        for internal in [GL_BGRA_EXT, GL_RGBA, 0x8058] {
            let up = Upload::new(internal, GL_BGRA_EXT, GL_UNSIGNED_BYTE).unwrap();
            assert_eq!(up.format, TextureFormat::Rgba8);
            assert_eq!(up.convert(&[1, 2, 3, 4], 1, 1, 4).unwrap(), [3, 2, 1, 4]);
        }
        assert!(Upload::new(GL_RGB, GL_BGRA_EXT, GL_UNSIGNED_BYTE).is_err());
        let up = Upload::new(GL_RGBA, GL_BGRA_EXT, GL_UNSIGNED_INT_8_8_8_8_REV).unwrap();
        assert_eq!(up.convert(&[1, 2, 3, 4], 1, 1, 4).unwrap(), [3, 2, 1, 4]);
    }

    #[test]
    fn refuses_what_it_does_not_convert() {
        assert!(Upload::new(GL_RGBA, GL_RGBA, GL_UNSIGNED_INT).is_err());
        assert!(Upload::new(GL_RGBA, GL_RGB, GL_UNSIGNED_BYTE).is_err());
    }
}
