//! 2-D array and 3-D texture calls of a capture: `glBindTexture(GL_TEXTURE_2D_ARRAY |
//! GL_TEXTURE_3D)`, `glTexImage3D`, `glTexStorage3D`, `glTexSubImage3D` and `glGenerateMipmap`
//! on those targets, as the context's layered-texture calls (`glTexParameter*` on them is the
//! 2D rule's, with `GL_TEXTURE_WRAP_R`). A texture name is layered from its first binding to
//! one of those targets on, as in GL. Refused, naming the call: mip levels above 0 given by
//! `glTexImage3D`/`glTexSubImage3D` (a 2-D array's chain comes from `glGenerateMipmap`), a 3-D
//! texture's mip chain, texel formats other than RGBA8 and sRGB8_alpha8. Rendering into a layer
//! (`glFramebufferTextureLayer`, level 0) is the context's `framebuffer_texture_layer`.

use tiler_apitrace::gles::{Command, GlEnum};

use super::{Fallible, Translator, gles3, size2};
use crate::call::{Call, LayeredTarget, TextureFormat, Wrap};
use crate::capture::texels::Upload;
use crate::context::MAX_TEXTURE_UNITS;

pub(super) const GL_TEXTURE_2D_ARRAY: u32 = 0x8c1a;
pub(super) const GL_TEXTURE_3D: u32 = 0x806f;

/// The layered target `target` names, if it is one.
pub(super) fn layered_target(target: GlEnum) -> Option<LayeredTarget> {
    match target {
        GL_TEXTURE_2D_ARRAY => Some(LayeredTarget::Array2D),
        GL_TEXTURE_3D => Some(LayeredTarget::Texture3D),
        _ => None,
    }
}

/// `GL_TEXTURE_WRAP_R`'s value as the context takes it.
pub(super) fn wrap_r(value: u32) -> Fallible<Wrap> {
    match value {
        0x2901 => Ok(Wrap::Repeat),
        0x812f => Ok(Wrap::ClampToEdge),
        0x8370 => Ok(Wrap::MirroredRepeat),
        w => Err(format!("GL_TEXTURE_WRAP_R {w:#06x} is not a GLES wrap")),
    }
}

/// Three sizes (or offsets) of a call, each 0 or more.
fn size3(x: i32, y: i32, z: i32) -> Fallible<(u32, u32, u32)> {
    let (x, y) = size2(x, y)?;
    let z = u32::try_from(z).map_err(|_| format!("depth {z} is negative"))?;
    Ok((x, y, z))
}

impl Translator {
    /// Translates `command` if it is a 2-D array or 3-D texture call; `false` leaves it to the
    /// other rules.
    pub(super) fn layered_command(&mut self, command: &Command) -> Fallible<bool> {
        use Command as C;
        match command {
            C::BindTexture { target, texture } if layered_target(*target).is_some() => {
                let layered = layered_target(*target).expect("a layered target");
                if *texture == 0 && self.bindings.active_unit >= MAX_TEXTURE_UNITS {
                    return Ok(true);
                }
                let unit = self.unit()? as u32;
                let id = if *texture == 0 {
                    0
                } else {
                    let t = self.objects()?.textures.entry(*texture).or_default();
                    if (t.id.is_some() || t.cube) && t.layered != Some(layered) {
                        return Err(format!(
                            "texture {texture} has another target: binding it as a {} texture is a GL error",
                            layered.name()
                        ));
                    }
                    t.layered = Some(layered);
                    t.id.unwrap_or(0)
                };
                self.bindings.layered_textures[unit as usize][layered.index()] = *texture;
                self.emit(Call::BindLayeredTexture { unit, target: layered, texture: id })?;
            }
            C::TexImage3D { target, level, internal_format, width, height, depth, border, format, kind, pixels } => {
                let layered = self.layered_level0(*target, *level)?;
                if *border != 0 {
                    return Err(format!("border {border} must be 0"));
                }
                let (width, height, depth) = size3(*width, *height, *depth)?;
                let upload = layered_upload(*internal_format, *format, *kind)?;
                let rows = height.checked_mul(depth).ok_or("the texture is too large")?;
                let data = self.texels(&upload, pixels, width, rows)?;
                let name = self.bound_layered(layered)?;
                let data = data.map(|data| self.swizzled(name, upload.format, data)).transpose()?;
                self.layered_storage(layered, (width, height, depth), upload, data)?;
            }
            C::TexStorage3D { target, levels, internal_format, width, height, depth } => {
                let layered = layered_target(*target)
                    .ok_or_else(|| format!("glTexStorage3D target {target:#06x} is not GL_TEXTURE_2D_ARRAY or 3D"))?;
                let (width, height, depth) = size3(*width, *height, *depth)?;
                match layered {
                    LayeredTarget::Texture3D if *levels != 1 => {
                        return Err(format!(
                            "{levels} mip levels of a 3-D texture: mipmapped 3-D textures are not supported (1 level)"
                        ));
                    }
                    _ => gles3::check_storage_levels(*levels, width, height)?,
                }
                let format = match *internal_format {
                    0x8058 => TextureFormat::Rgba8,
                    0x8c43 => TextureFormat::Srgb8Alpha8,
                    f => {
                        return Err(format!(
                            "{} texture storage of internal format {f:#06x}: only GL_RGBA8 and GL_SRGB8_ALPHA8",
                            layered.name()
                        ));
                    }
                };
                let upload = gles3::storage_upload(format).ok_or("RGBA8 uploads")?;
                let name = self.bound_layered(layered)?;
                if self.texture_id(name)?.is_some() {
                    return Err(format!("texture {name} already has storage"));
                }
                self.layered_storage(layered, (width, height, depth), upload, None)?;
            }
            C::TexSubImage3D {
                target,
                level,
                x_offset,
                y_offset,
                z_offset,
                width,
                height,
                depth,
                format,
                kind,
                pixels,
            } => {
                let layered = self.layered_level0(*target, *level)?;
                let name = self.bound_layered(layered)?;
                let texture = self.objects()?.textures.get(&name).cloned().unwrap_or_default();
                let (Some(id), Some(_)) = (texture.id, texture.upload) else {
                    return Err(format!("{} texture {name} has no storage", layered.name()));
                };
                // RGBA8 and sRGB8_alpha8 storage both take bytes (`layered_upload`).
                let upload = layered_upload(*format, *format, *kind)?;
                let (width, height, depth) = size3(*width, *height, *depth)?;
                let (x, y, z) = size3(*x_offset, *y_offset, *z_offset)?;
                let rows = height.checked_mul(depth).ok_or("the box is too large")?;
                let data = self.texels(&upload, pixels, width, rows)?.ok_or("the texels were not recorded")?;
                let data = self.swizzled(name, texture.upload.map_or(upload.format, |u| u.format), data)?;
                self.emit(Call::LayeredTexSubImage { id, x, y, z, width, height, depth, data })?;
            }
            C::GenerateMipmap { target } if layered_target(*target).is_some() => {
                let layered = layered_target(*target).expect("a layered target");
                let name = self.bound_layered(layered)?;
                let id = self
                    .texture_id(name)?
                    .ok_or_else(|| format!("{} texture {name} has no storage", layered.name()))?;
                self.emit(Call::GenerateMipmap { id })?;
            }
            C::CopyTexSubImage3D { target, level, x_offset, y_offset, z_offset, x, y, width, height } => {
                let layered = self.layered_level0(*target, *level)?;
                let name = self.bound_layered(layered)?;
                let texture = self
                    .texture_id(name)?
                    .ok_or_else(|| format!("{} texture {name} has no storage", layered.name()))?;
                let (x_offset, y_offset, layer) = size3(*x_offset, *y_offset, *z_offset)?;
                let (width, height) = size2(*width, *height)?;
                let (x, y) = (*x, *y);
                self.emit(Call::CopyTexSubImageLayer { texture, layer, x_offset, y_offset, x, y, width, height })?;
            }
            C::FramebufferTextureLayer { target, attachment, texture, level, layer } => {
                let framebuffer = self.attachment_target(*target)?;
                let attachment = super::attachment_point(*attachment)?;
                let (texture, layer) = if *texture == 0 {
                    (0, 0)
                } else {
                    if *level != 0 {
                        return Err(format!(
                            "mip level {level} of texture {texture} as an attachment: only level 0 is supported"
                        ));
                    }
                    let layer = u32::try_from(*layer).map_err(|_| format!("layer {layer} is negative"))?;
                    let known = self.objects()?.textures.get(texture).cloned().unwrap_or_default();
                    if known.layered.is_none() {
                        return Err(format!("texture {texture} is not a 2-D array or 3-D texture"));
                    }
                    let id = known.id.ok_or_else(|| format!("texture {texture} has no storage"))?;
                    (id, layer)
                };
                self.emit(Call::FramebufferTextureLayer { framebuffer, attachment, texture, layer })?;
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    /// The layered target of a `glTexImage3D`-style call at `level`, which must be 0.
    fn layered_level0(&self, target: GlEnum, level: i32) -> Fallible<LayeredTarget> {
        let layered = layered_target(target)
            .ok_or_else(|| format!("texture target {target:#06x} is not GL_TEXTURE_2D_ARRAY or GL_TEXTURE_3D"))?;
        if level != 0 {
            return Err(format!(
                "mip level {level} of a {} texture: only level 0 is supported (a 2-D array's levels come from \
                 glGenerateMipmap)",
                layered.name()
            ));
        }
        Ok(layered)
    }

    /// Level 0 of the layered texture bound to `layered`, with `data` (zeros without).
    fn layered_storage(
        &mut self,
        layered: LayeredTarget,
        (width, height, depth): (u32, u32, u32),
        upload: Upload,
        data: Option<crate::bytes::Bytes>,
    ) -> Fallible {
        let name = self.bound_layered(layered)?;
        let known = self.texture_id(name)?;
        let id = known.unwrap_or_else(|| self.fresh_id());
        let format = upload.format;
        self.emit(Call::LayeredTexImage { id, target: layered, width, height, depth, format, data })?;
        let t = self.objects()?.textures.entry(name).or_default();
        t.id = Some(id);
        t.upload = Some(upload);
        t.size = (width, height);
        if known.is_none() {
            for unit in 0..MAX_TEXTURE_UNITS {
                if self.bindings.layered_textures[unit as usize][layered.index()] == name {
                    self.emit(Call::BindLayeredTexture { unit, target: layered, texture: id })?;
                }
            }
        }
        self.update_sampler(name)
    }

    /// The texture bound to `layered` on the active unit.
    pub(super) fn bound_layered(&self, layered: LayeredTarget) -> Fallible<u32> {
        match self.bindings.layered_textures[self.unit()?][layered.index()] {
            0 => Err(format!("the default {} texture (0) is not supported: bind a texture", layered.name())),
            name => Ok(name),
        }
    }
}

/// A layered upload's storage: the context's 2-D array and 3-D textures are RGBA8.
fn layered_upload(internal_format: u32, format: u32, kind: u32) -> Fallible<Upload> {
    let upload = Upload::new(internal_format, format, kind)?;
    if !matches!(upload.format, TextureFormat::Rgba8 | TextureFormat::Srgb8Alpha8) {
        return Err(format!(
            "2-D array / 3-D texels of format {format:#06x} / type {kind:#06x} are stored as {}: these textures are \
             RGBA8",
            upload.format.name()
        ));
    }
    Ok(upload)
}
