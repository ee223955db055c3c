//! Uploads in formats the context samples but does not render to: `glCompressedTexImage2D`
//! and `glCompressedTexSubImage2D` of ETC1 (`GL_ETC1_RGB8_OES`), ETC2/EAC (OpenGL ES 3.0) and
//! ASTC LDR (`KHR_texture_compression_astc_ldr`), and `glTexImage2D`/`glTexSubImage2D` of
//! `GL_UNSIGNED_SHORT_4_4_4_4` and `5_5_5_1` texels, all `encoded_tex_image` /
//! `encoded_tex_sub_image` calls of the context, which decodes them once and counts samples
//! by what the format stores.

use tiler_apitrace::gles::{GlEnum, Memory};

use super::texels;
use super::translate::Translator;
use crate::bytes::Bytes;
use crate::call::{Call, EncodedFormat, TextureFormat};

type Fallible<T = ()> = Result<T, String>;

/// `GL_ETC1_RGB8_OES`.
const GL_ETC1_RGB8_OES: u32 = 0x8d64;
/// `GL_COMPRESSED_RGBA_ASTC_4x4_KHR`, the first of 14 (sRGB ones from `0x93d0`).
const GL_COMPRESSED_RGBA_ASTC_4X4: u32 = 0x93b0;
const GL_COMPRESSED_SRGB8_ALPHA8_ASTC_4X4: u32 = 0x93d0;

/// The format of a compressed internal format, and whether its colour is sRGB.
pub(super) fn compressed_format(internal_format: GlEnum) -> Fallible<(EncodedFormat, bool)> {
    use EncodedFormat as F;
    Ok(match internal_format {
        GL_ETC1_RGB8_OES => (F::Etc1Rgb8, false),
        0x9270 => (F::EacR11, false),
        0x9272 => (F::EacRg11, false),
        0x9274 => (F::Etc2Rgb8, false),
        0x9275 => (F::Etc2Rgb8, true),
        0x9276 => (F::Etc2Rgb8A1, false),
        0x9277 => (F::Etc2Rgb8A1, true),
        0x9278 => (F::Etc2Rgba8, false),
        0x9279 => (F::Etc2Rgba8, true),
        f if (GL_COMPRESSED_RGBA_ASTC_4X4..GL_COMPRESSED_RGBA_ASTC_4X4 + 14).contains(&f) => {
            (F::ASTC[(f - GL_COMPRESSED_RGBA_ASTC_4X4) as usize], false)
        }
        f if (GL_COMPRESSED_SRGB8_ALPHA8_ASTC_4X4..GL_COMPRESSED_SRGB8_ALPHA8_ASTC_4X4 + 14).contains(&f) => {
            (F::ASTC[(f - GL_COMPRESSED_SRGB8_ALPHA8_ASTC_4X4) as usize], true)
        }
        f => {
            return Err(format!(
                "compressed format {f:#06x} is not one the replay decodes (ETC1, ETC2/EAC unsigned, ASTC LDR 2D)"
            ));
        }
    })
}

/// `GL_UNSIGNED_INT_2_10_10_10_REV`.
const GL_UNSIGNED_INT_2_10_10_10_REV: u32 = 0x8368;

/// The packed type of `glTexImage2D` the context stores as uploaded (4444, 5551, 2_10_10_10,
/// 10F_11F_11F, 5_9_9_9, and the 16-bit normalised channels of `EXT_texture_norm16`),
/// if `kind` is one (RGB565 is a texture format of its own).
pub(super) fn packed_format(format: GlEnum, kind: GlEnum) -> Option<EncodedFormat> {
    match (format, kind) {
        (texels::GL_RGBA, texels::GL_UNSIGNED_SHORT_4_4_4_4) => Some(EncodedFormat::Rgba4444),
        (texels::GL_RGBA, texels::GL_UNSIGNED_SHORT_5_5_5_1) => Some(EncodedFormat::Rgba5551),
        (texels::GL_RGBA, GL_UNSIGNED_INT_2_10_10_10_REV) => Some(EncodedFormat::Rgb10A2),
        (texels::GL_RGB, 0x8c3b /* UNSIGNED_INT_10F_11F_11F_REV */) => Some(EncodedFormat::R11fG11fB10f),
        (texels::GL_RGB, 0x8c3e /* UNSIGNED_INT_5_9_9_9_REV */) => Some(EncodedFormat::Rgb9E5),
        // EXT_texture_norm16 (GL ES 3.0's own UNSIGNED_SHORT colour formats are integer ones,
        // uploaded as *_INTEGER).
        (texels::GL_RED, texels::GL_UNSIGNED_SHORT) => Some(EncodedFormat::R16),
        (texels::GL_RG, texels::GL_UNSIGNED_SHORT) => Some(EncodedFormat::Rg16),
        (texels::GL_RGB, texels::GL_UNSIGNED_SHORT) => Some(EncodedFormat::Rgb16),
        (texels::GL_RGBA, texels::GL_UNSIGNED_SHORT) => Some(EncodedFormat::Rgba16),
        _ => None,
    }
}

/// A compressed upload's bytes: `image_size` of them, as GL reads them.
fn compressed_bytes(data: &Memory, image_size: i32) -> Fallible<Bytes> {
    let bytes = match data {
        Memory::Client(bytes) => bytes,
        Memory::Null => return Err("no data (a null pointer): compressed uploads need their blocks".into()),
        Memory::Offset(_) => return Err("compressed blocks from a pixel unpack buffer are not supported".into()),
    };
    if image_size < 0 || bytes.len() != image_size as usize {
        return Err(format!("image size {image_size}, but {} bytes were recorded", bytes.len()));
    }
    Ok(Bytes::from(bytes.as_slice()))
}

/// Packed texels of `format` (2 or 4 bytes each), `width × height`, rows bottom to top each
/// starting at a multiple of `alignment`, packed tight.
fn packed_texels(bytes: &[u8], format: EncodedFormat, width: u32, height: u32, alignment: u32) -> Fallible<Bytes> {
    let row = width as usize * texel_bytes(format);
    let stride = row.div_ceil(alignment.max(1) as usize) * alignment.max(1) as usize;
    let needed = if height == 0 { 0 } else { stride * (height as usize - 1) + row };
    if bytes.len() < needed {
        return Err(format!(
            "{} bytes of texels, but {width}×{height} with rows aligned to {alignment} needs {needed}",
            bytes.len()
        ));
    }
    Ok(Bytes::from(
        (0..height as usize).flat_map(|y| &bytes[y * stride..y * stride + row]).copied().collect::<Vec<u8>>(),
    ))
}

/// Bytes of one packed texel of `format` (an uncompressed encoded format).
pub(super) fn texel_bytes(format: EncodedFormat) -> usize {
    format.texel_format().layout().texel_bytes as usize
}

impl Translator {
    /// An upload's packed texels from client memory, under the unpack state.
    fn client_packed_texels(&self, pixels: &Memory, format: EncodedFormat, size: (u32, u32)) -> Fallible<Bytes> {
        let bytes = match pixels {
            Memory::Client(bytes) => bytes,
            Memory::Null => return Err("no texels (a null pointer) for a packed texture".into()),
            Memory::Offset(_) => return Err("texels from a pixel unpack buffer are not supported".into()),
        };
        let (bytes, alignment) = self.unpacked(bytes, size, texel_bytes(format))?;
        packed_texels(&bytes, format, size.0, size.1, alignment)
    }

    /// `glCompressedTexImage2D` (level 0 gives the bound texture new storage) and
    /// `glTexImage2D` of packed texels (`data` already read): an `encoded_tex_image`.
    pub(super) fn encoded_tex_image(
        &mut self,
        level: u32,
        (width, height): (u32, u32),
        (format, srgb): (EncodedFormat, bool),
        data: Bytes,
    ) -> Fallible {
        let name = self.bound_texture()?;
        self.check_unswizzled(name)?;
        let id = match self.texture_id(name)? {
            Some(id) => id,
            None if level == 0 => {
                // Storage comes with level 0; the context's texture is made first.
                let id = self.fresh_id();
                let create = Call::CreateTexture {
                    id,
                    width,
                    height,
                    format: TextureFormat::Rgba8,
                    data: None,
                    transient: false,
                };
                self.emit(create)?;
                self.bind_new_texture(name, id)?;
                id
            }
            None => return Err(format!("mip level {level} of texture {name} before its level 0")),
        };
        self.emit(Call::EncodedTexImage { id, level, width, height, format, srgb, data })?;
        if level == 0 {
            self.set_encoded_storage(name, id, (width, height))?;
            self.update_sampler(name)?;
        }
        Ok(())
    }

    /// `glCompressedTexImage2D` as [`Translator::encoded_tex_image`] takes it.
    pub(super) fn compressed_tex_image(
        &mut self,
        level: i32,
        internal_format: GlEnum,
        size: (u32, u32),
        image_size: i32,
        data: &Memory,
    ) -> Fallible {
        let level = u32::try_from(level).map_err(|_| format!("mip level {level} is negative"))?;
        let format = compressed_format(internal_format)?;
        let data = compressed_bytes(data, image_size)?;
        self.encoded_tex_image(level, size, format, data)
    }

    /// `glCompressedTexSubImage2D` of level 0.
    pub(super) fn compressed_tex_sub_image(
        &mut self,
        (x, y): (u32, u32),
        (width, height): (u32, u32),
        format: GlEnum,
        image_size: i32,
        data: &Memory,
    ) -> Fallible {
        let (format, _) = compressed_format(format)?;
        let data = compressed_bytes(data, image_size)?;
        let name = self.bound_texture()?;
        self.check_unswizzled(name)?;
        let id = self.texture_id(name)?.ok_or_else(|| format!("texture {name} has no storage"))?;
        self.emit(Call::EncodedTexSubImage { id, x, y, width, height, format, data })?;
        Ok(())
    }

    /// `glTexImage2D` of packed 4444 or 5551 texels.
    pub(super) fn packed_tex_image(
        &mut self,
        level: u32,
        size: (u32, u32),
        format: EncodedFormat,
        pixels: &Memory,
    ) -> Fallible {
        let data = match pixels {
            // Storage without texels (GL leaves them undefined): zeros, for glTexSubImage2D.
            Memory::Null => Bytes::from(vec![0u8; size.0 as usize * size.1 as usize * texel_bytes(format)]),
            _ => self.client_packed_texels(pixels, format, size)?,
        };
        self.encoded_tex_image(level, size, (format, false), data)
    }

    /// `glTexSubImage2D` of packed 4444 or 5551 texels into level 0.
    pub(super) fn packed_tex_sub_image(
        &mut self,
        (x, y): (u32, u32),
        (width, height): (u32, u32),
        format: EncodedFormat,
        pixels: &Memory,
    ) -> Fallible {
        let data = self.client_packed_texels(pixels, format, (width, height))?;
        let name = self.bound_texture()?;
        self.check_unswizzled(name)?;
        let id = self.texture_id(name)?.ok_or_else(|| format!("texture {name} has no storage"))?;
        self.emit(Call::EncodedTexSubImage { id, x, y, width, height, format, data })?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gl_enums_map_to_formats() {
        assert_eq!(compressed_format(0x9278).unwrap(), (EncodedFormat::Etc2Rgba8, false));
        assert_eq!(compressed_format(0x9279).unwrap(), (EncodedFormat::Etc2Rgba8, true));
        assert_eq!(compressed_format(GL_ETC1_RGB8_OES).unwrap(), (EncodedFormat::Etc1Rgb8, false));
        assert_eq!(compressed_format(0x93b7).unwrap(), (EncodedFormat::Astc8x8, false));
        assert_eq!(compressed_format(0x93dd).unwrap(), (EncodedFormat::Astc12x12, true));
        assert_eq!(EncodedFormat::Astc6x6.texel_format(), tiler::TexelFormat::Astc { block_width: 6, block_height: 6 });
        // Signed EAC and 3D ASTC are not decoded.
        for f in [0x9271, 0x93be, 0x83f0] {
            assert!(compressed_format(f).unwrap_err().contains(&format!("{f:#06x}")));
        }
    }

    #[test]
    fn packed_rows_drop_their_alignment_and_sizes_are_checked() {
        // 3×2 texels of 2 bytes: rows of 6 bytes, 8 apart with an alignment of 4.
        let data: Vec<u8> = (0..14u8).collect();
        let packed = packed_texels(&data, EncodedFormat::Rgba4444, 3, 2, 4).unwrap();
        assert_eq!(&packed[..], &[0, 1, 2, 3, 4, 5, 8, 9, 10, 11, 12, 13]);
        assert!(packed_texels(&data, EncodedFormat::Rgba4444, 4, 2, 4).is_err());
        let e = compressed_bytes(&Memory::Client(vec![0; 15]), 16).unwrap_err();
        assert!(e.contains("image size 16, but 15 bytes"), "{e}");
    }
}
