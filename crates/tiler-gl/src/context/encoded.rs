//! Textures in formats tiler samples but does not render to (`encoded_tex_image`): ETC1,
//! ETC2/EAC and ASTC blocks, 4444 and 5551 texels.
//!
//! The upload is decoded once, where it enters, into the texture's RGBA8 (or sRGB) image, so
//! everything else a texture does — copies, render to texture, read-back, snapshots — works
//! on it unchanged; the texture object remembers the format (`TextureObject::encoded`), and
//! the core texture a draw samples is modelled as stored in it (`tiler::Texture::stored_as`):
//! `texture_fetch` counts compressed blocks and 2-byte texels. The image itself, in the
//! context's memory accounting, is the decoded RGBA8.

use std::sync::Arc;

use tiler::TexelFormat;

use super::{Context, Fallible};
use crate::bytes::Bytes;
use crate::call::{EncodedFormat, TextureFormat};

impl Context {
    /// `encoded_tex_image`: level 0 gives texture `id` new storage, a level above 0 is a level
    /// of the chain (see `Call::EncodedTexImage`).
    pub(super) fn encoded_tex_image(
        &mut self,
        id: u32,
        level: u32,
        (width, height): (u32, u32),
        format: EncodedFormat,
        srgb: bool,
        data: Bytes,
    ) -> Fallible {
        let old = self.texture(id)?.encoded;
        let rgba = decode(format, width, height, &data).map_err(|e| format!("level {level} of texture {id}: {e}"))?;
        let stored = if srgb { TextureFormat::Srgb8Alpha8 } else { TextureFormat::Rgba8 };
        if level == 0 {
            self.texture_storage(id, width, height, stored, Some(rgba), false)?;
            let t = self.texture_mut(id)?;
            // Levels given in another format are no longer this texture's chain.
            if old != Some(format) {
                t.levels.clear();
                t.mipmaps = false;
            }
            t.encoded = Some(format);
            t.unorm16 = unorm16_rows(format, width, height, &data);
            return Ok(());
        }
        let t = self.texture(id)?;
        if old != Some(format) || t.format != stored {
            let base = old.map_or_else(|| t.format.name().to_string(), name);
            return Err(format!(
                "level {level} of texture {id} is {}{}, but its level 0 is {base}",
                if srgb { "sRGB " } else { "" },
                name(format)
            ));
        }
        self.tex_image_level(id, level, width, height, rgba)
    }

    /// `encoded_tex_sub_image`: a rectangle of level 0 in the texture's format; a compressed
    /// one starts on a block and ends on one or at the texture's edge.
    pub(super) fn encoded_tex_sub_image(
        &mut self,
        id: u32,
        (x, y, width, height): (u32, u32, u32, u32),
        format: EncodedFormat,
        data: Bytes,
    ) -> Fallible {
        let t = self.texture(id)?;
        if t.encoded != Some(format) {
            let stored = t.encoded.map_or_else(|| t.format.name().to_string(), name);
            return Err(format!("{} texels into texture {id}, which is stored as {stored}", name(format)));
        }
        let desc = self.images[&t.image].desc;
        let layout = format.texel_format().layout();
        if layout.texel_bytes == 0 {
            let (bw, bh) = (layout.block_width, layout.block_height);
            let aligned = |start: u32, size: u32, block: u32, edge: u32| {
                start.is_multiple_of(block) && (size.is_multiple_of(block) || start as u64 + size as u64 == edge as u64)
            };
            if !aligned(x, width, bw, desc.width) || !aligned(y, height, bh, desc.height) {
                return Err(format!(
                    "rectangle {width}×{height} at ({x}, {y}) of texture {id} ({}×{}) is not made of whole \
                     {bw}×{bh} blocks of {}",
                    desc.width,
                    desc.height,
                    name(format)
                ));
            }
        }
        let rgba = decode(format, width, height, &data).map_err(|e| format!("texture {id}: {e}"))?;
        self.tex_sub_image(id, x, y, width, height, rgba)?;
        // The 16 bits of a 16-bit normalised texture: the rectangle's rows, GL's bottom-up
        // `y` counted from the top.
        let texel = layout.texel_bytes as usize;
        let t = self.texture_mut(id)?;
        if let Some(stored) = &mut t.unorm16 {
            let stored = Arc::make_mut(stored);
            let row = width as usize * texel;
            for (j, src) in data.chunks_exact(row).take(height as usize).enumerate() {
                let y = (desc.height - 1 - (y + j as u32)) as usize;
                let at = (y * desc.width as usize + x as usize) * texel;
                stored[at..at + row].copy_from_slice(src);
            }
        }
        Ok(())
    }

    /// The core texture of `image`, a 16-bit normalised texture's, at 16 bits a channel: when
    /// the texture object keeps its upload's texels and the image still holds the bytes they
    /// round to (nothing has drawn or copied into it since), and no chain is sampled.
    pub(super) fn unorm16_texture(
        &self,
        image: tiler::ImageId,
        data: &[u8],
        mips: tiler::MipChain,
    ) -> Fallible<Option<tiler::Texture>> {
        let Some(t) = self.textures.values().find(|t| t.image == image) else { return Ok(None) };
        let (Some(format), Some(stored)) = (t.encoded, &t.unorm16) else { return Ok(None) };
        if mips != tiler::MipChain::BaseOnly {
            return Ok(None);
        }
        let desc = self.images[&image].desc;
        let format = format.texel_format();
        let bytes = format.decode(desc.width, desc.height, stored).map_err(|e| e.to_string())?;
        if bytes.concat() != data {
            return Ok(None);
        }
        let texture =
            tiler::Texture::from_encoded(format, desc.width, desc.height, stored, tiler::ColorSpace::Linear, mips)
                .map_err(|e| e.to_string())?;
        Ok(Some(texture))
    }

    /// The core format a texture made from `image`'s storage is modelled in when it is not the
    /// image's own: the encoded format it was uploaded in, if any.
    pub(super) fn encoded_format(&self, image: tiler::ImageId) -> Option<TexelFormat> {
        self.textures.values().find(|t| t.image == image).and_then(|t| t.encoded).map(EncodedFormat::texel_format)
    }
}

/// A 16-bit normalised upload's texels (rows bottom to top, as GL gives them) top to bottom,
/// as the core texture takes them; `None` for other formats.
fn unorm16_rows(format: EncodedFormat, width: u32, height: u32, data: &[u8]) -> Option<Arc<Vec<u8>>> {
    if !matches!(format, EncodedFormat::R16 | EncodedFormat::Rg16 | EncodedFormat::Rgb16 | EncodedFormat::Rgba16) {
        return None;
    }
    let row = width as usize * format.texel_format().layout().texel_bytes as usize;
    let rows: Vec<u8> = data.chunks_exact(row).take(height as usize).rev().flatten().copied().collect();
    (rows.len() == row * height as usize).then(|| Arc::new(rows))
}

/// `data` of `format`, `width × height`, decoded to RGBA8 rows in the same order.
fn decode(format: EncodedFormat, width: u32, height: u32, data: &[u8]) -> Result<Bytes, String> {
    let texels = format.texel_format().decode(width, height, data).map_err(|e| e.to_string())?;
    Ok(Bytes::from(texels.concat()))
}

/// The format as a trace spells it.
fn name(format: EncodedFormat) -> String {
    serde_json::to_value(format).ok().and_then(|v| v.as_str().map(str::to_string)).unwrap_or_default()
}
