//! Texel uploads: GL's client formats, unpacked with `GL_UNPACK_ALIGNMENT`, into the formats
//! the context stores.

use crate::call::TextureFormat;

pub(crate) const GL_ALPHA: u32 = 0x1906;
pub(crate) const GL_RGB: u32 = 0x1907;
pub(crate) const GL_RGBA: u32 = 0x1908;
pub(crate) const GL_LUMINANCE: u32 = 0x1909;
pub(crate) const GL_LUMINANCE_ALPHA: u32 = 0x190a;
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
        // GLES 2.0: the internal format is the format (sized RGBA8/RGB8 from GLES 3.0 too).
        // Float textures (`OES_texture_float`, `OES_texture_half_float`; GL ES 3.0's sized
        // RGBA16F/RGBA32F/RGB16F/RGB32F).
        let internal_ok = internal_format == format
            || matches!(
                (internal_format, format),
                (0x8058 | 0x881a | 0x8814, GL_RGBA) | (0x8051 | 0x8d62 | 0x881b | 0x8815, GL_RGB)
            );
        if !internal_ok {
            return Err(format!(
                "internal format {internal_format:#06x} with format {format:#06x} is not a GLES 2.0 combination the \
                 replay converts"
            ));
        }
        let (stored, client_bytes) = match (format, kind) {
            (GL_RGBA, GL_UNSIGNED_BYTE) => (TextureFormat::Rgba8, 4),
            (GL_RGB, GL_UNSIGNED_BYTE) => (TextureFormat::Rgba8, 3),
            (GL_LUMINANCE_ALPHA, GL_UNSIGNED_BYTE) => (TextureFormat::Rgba8, 2),
            (GL_LUMINANCE | GL_ALPHA, GL_UNSIGNED_BYTE) => (TextureFormat::Rgba8, 1),
            (GL_RGB, GL_UNSIGNED_SHORT_5_6_5) => (TextureFormat::Rgb565, 2),
            (GL_RGBA, GL_HALF_FLOAT_OES | GL_HALF_FLOAT) => (TextureFormat::Rgba16f, 8),
            (GL_RGB, GL_HALF_FLOAT_OES | GL_HALF_FLOAT) => (TextureFormat::Rgba16f, 6),
            (GL_RGBA, GL_FLOAT) => (TextureFormat::Rgba32f, 16),
            (GL_RGB, GL_FLOAT) => (TextureFormat::Rgba32f, 12),
            (GL_DEPTH_COMPONENT, GL_UNSIGNED_SHORT) => (TextureFormat::Depth16, 2),
            (GL_DEPTH_COMPONENT, GL_UNSIGNED_INT) => (TextureFormat::Depth24, 4),
            (GL_DEPTH_STENCIL, GL_UNSIGNED_INT_24_8) => (TextureFormat::Depth24Stencil8, 4),
            _ => {
                return Err(format!(
                    "texel format {format:#06x} of type {kind:#06x} is not one the replay converts (RGBA, RGB, \
                     LUMINANCE, LUMINANCE_ALPHA, ALPHA bytes; 565; RGBA, RGB halves and floats; DEPTH_COMPONENT; 4444 and 5551 \
                     are encoded uploads)"
                ));
            }
        };
        Ok(Upload { format: stored, client_bytes, format_enum: format, kind })
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
            match (self.format_enum, self.kind) {
                (_, GL_UNSIGNED_SHORT_5_6_5)
                | (GL_RGBA, GL_UNSIGNED_BYTE | GL_HALF_FLOAT_OES | GL_HALF_FLOAT | GL_FLOAT) => {
                    out.extend_from_slice(src)
                }
                // Alpha 1.0 as a half and as a float.
                (GL_RGB, GL_HALF_FLOAT_OES | GL_HALF_FLOAT) => src.chunks_exact(6).for_each(|t| {
                    out.extend_from_slice(t);
                    out.extend_from_slice(&0x3c00u16.to_le_bytes());
                }),
                (GL_RGB, GL_FLOAT) => src.chunks_exact(12).for_each(|t| {
                    out.extend_from_slice(t);
                    out.extend_from_slice(&1.0f32.to_le_bytes());
                }),
                (GL_RGB, _) => src.chunks_exact(3).for_each(|t| out.extend_from_slice(&[t[0], t[1], t[2], 255])),
                (GL_LUMINANCE_ALPHA, _) => {
                    src.chunks_exact(2).for_each(|t| out.extend_from_slice(&[t[0], t[0], t[0], t[1]]))
                }
                (GL_LUMINANCE, _) => src.iter().for_each(|&l| out.extend_from_slice(&[l, l, l, 255])),
                (GL_ALPHA, _) => src.iter().for_each(|&a| out.extend_from_slice(&[0, 0, 0, a])),
                _ => unreachable!("Upload::new accepts only the pairs converted here"),
            }
        }
        Ok(out)
    }
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
    fn refuses_what_it_does_not_convert() {
        assert!(Upload::new(GL_RGBA, GL_RGBA, GL_UNSIGNED_INT).is_err());
        assert!(Upload::new(GL_RGBA, GL_RGB, GL_UNSIGNED_BYTE).is_err());
    }
}
