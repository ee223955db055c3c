//! Cube-map calls of a capture: `glBindTexture(GL_TEXTURE_CUBE_MAP)`, `glTexImage2D` and
//! `glTexSubImage2D` on `GL_TEXTURE_CUBE_MAP_POSITIVE_X` … `NEGATIVE_Z`, and
//! `glTexParameter*`/`glGenerateMipmap` on the cube target, as the context's cube-texture
//! calls. A texture name is a cube map from its first binding to `GL_TEXTURE_CUBE_MAP` on,
//! as in GL. Rendering or copying into a cube face is refused, naming the call.

use tiler_apitrace::gles::{Command, GlEnum};

use super::{Fallible, Translator, gles3, size2};
use crate::call::{Call, CubeFace, TextureFormat};
use crate::capture::texels::Upload;
use crate::context::MAX_TEXTURE_UNITS;

pub(super) const GL_TEXTURE_CUBE_MAP: u32 = 0x8513;
const GL_TEXTURE_CUBE_MAP_POSITIVE_X: u32 = 0x8515;
const GL_RGBA8: u32 = 0x8058;

/// The face a `glTexImage2D`-style target names, if it is one.
pub(super) fn cube_face(target: GlEnum) -> Option<CubeFace> {
    let index = target.checked_sub(GL_TEXTURE_CUBE_MAP_POSITIVE_X)?;
    CubeFace::ALL.get(index as usize).copied()
}

impl Translator {
    /// Translates `command` if it is a cube-map call; `false` leaves it to the 2D rules.
    pub(super) fn cube_command(&mut self, command: &Command) -> Fallible<bool> {
        use Command as C;
        match command {
            C::BindTexture { target, texture } if *target == GL_TEXTURE_CUBE_MAP => {
                if *texture == 0 && self.bindings.active_unit >= MAX_TEXTURE_UNITS {
                    return Ok(true);
                }
                let unit = self.unit()? as u32;
                let id = if *texture == 0 {
                    0
                } else {
                    let t = self.objects()?.textures.entry(*texture).or_default();
                    if t.id.is_some() && !t.cube {
                        return Err(format!(
                            "texture {texture} is a 2D texture: binding it as a cube map is a GL error"
                        ));
                    }
                    t.cube = true;
                    t.id.unwrap_or(0)
                };
                self.bindings.cube_textures[unit as usize] = *texture;
                self.emit(Call::BindCubeTexture { unit, texture: id })?;
            }
            C::TexImage2D { target, level, internal_format, width, height, border, format, kind, pixels } => {
                let Some(face) = cube_face(*target) else { return Ok(false) };
                if *border != 0 {
                    return Err(format!("border {border} must be 0"));
                }
                let level = u32::try_from(*level).map_err(|_| format!("mip level {level} is negative"))?;
                let (width, height) = size2(*width, *height)?;
                if width != height {
                    return Err(format!("cube face {} is {width}×{height}: cube map faces are square", face.name()));
                }
                let upload = cube_upload(*internal_format, *format, *kind)?;
                let data = self.texels(&upload, pixels, width, height)?;
                let name = self.bound_cube()?;
                let data = data.map(|data| self.swizzled(name, upload.format, data)).transpose()?;
                let known = self.objects()?.textures.get(&name).and_then(|t| t.id);
                let id = known.unwrap_or_else(|| self.fresh_id());
                self.emit(Call::CubeTexImage { id, face, level, size: width, format: upload.format, data })?;
                let t = self.objects()?.textures.entry(name).or_default();
                t.id = Some(id);
                if level == 0 {
                    t.upload = Some(upload);
                    t.size = (width, height);
                }
                if known.is_none() {
                    for unit in 0..MAX_TEXTURE_UNITS {
                        if self.bindings.cube_textures[unit as usize] == name {
                            self.emit(Call::BindCubeTexture { unit, texture: id })?;
                        }
                    }
                }
                self.update_sampler(name)?;
            }
            C::TexStorage2D { target, levels, internal_format, width, height } if *target == GL_TEXTURE_CUBE_MAP => {
                // Every face and level at once, texels undefined (zeros here), as glTexImage2D
                // of each without data.
                if *internal_format != GL_RGBA8 {
                    return Err(format!(
                        "cube texture storage of internal format {internal_format:#06x}: cube textures are RGBA8"
                    ));
                }
                let (width, height) = size2(*width, *height)?;
                if width != height {
                    return Err(format!("cube texture storage {width}×{height}: cube map faces are square"));
                }
                gles3::check_storage_levels(*levels, width, height)?;
                let name = self.bound_cube()?;
                if self.objects()?.textures.get(&name).is_some_and(|t| t.id.is_some()) {
                    return Err(format!("cube texture {name} already has storage"));
                }
                let id = self.fresh_id();
                for level in 0..*levels as u32 {
                    let size = (width >> level).max(1);
                    for face in CubeFace::ALL {
                        self.emit(Call::CubeTexImage {
                            id,
                            face,
                            level,
                            size,
                            format: TextureFormat::Rgba8,
                            data: None,
                        })?;
                    }
                }
                let t = self.objects()?.textures.entry(name).or_default();
                t.id = Some(id);
                t.cube = true;
                t.upload = gles3::storage_upload(TextureFormat::Rgba8);
                t.size = (width, height);
                for unit in 0..MAX_TEXTURE_UNITS {
                    if self.bindings.cube_textures[unit as usize] == name {
                        self.emit(Call::BindCubeTexture { unit, texture: id })?;
                    }
                }
                self.update_sampler(name)?;
            }
            C::TexSubImage2D { target, level, x_offset, y_offset, width, height, format, kind, pixels } => {
                let Some(face) = cube_face(*target) else { return Ok(false) };
                if *level != 0 {
                    return Err(format!("mip level {level} of cube face {}: sub-images of level 0 only", face.name()));
                }
                let name = self.bound_cube()?;
                let texture = self.objects()?.textures.get(&name).cloned().unwrap_or_default();
                let (Some(id), Some(stored)) = (texture.id, texture.upload) else {
                    return Err(format!("cube texture {name} has no storage"));
                };
                let upload = cube_upload(*format, *format, *kind)?;
                if upload.format != stored.format {
                    return Err(format!(
                        "texels of format {format:#06x} / type {kind:#06x} into a cube texture stored as {}",
                        stored.format.name()
                    ));
                }
                let (width, height) = size2(*width, *height)?;
                let (x, y) = size2(*x_offset, *y_offset)?;
                let data = self.texels(&upload, pixels, width, height)?.ok_or("the texels were not recorded")?;
                let data = self.swizzled(name, stored.format, data)?;
                self.emit(Call::CubeTexSubImage { id, face, x, y, width, height, data })?;
            }
            C::GenerateMipmap { target } if *target == GL_TEXTURE_CUBE_MAP => {
                let name = self.bound_cube()?;
                let id = self.texture_id(name)?.ok_or_else(|| format!("cube texture {name} has no storage"))?;
                self.emit(Call::GenerateMipmap { id })?;
            }
            C::FramebufferTexture2D { texture_target, .. } if cube_face(*texture_target).is_some() => {
                let face = cube_face(*texture_target).expect("a face");
                return Err(format!(
                    "rendering into cube map face {} is not supported (cube textures are sampled only)",
                    face.name()
                ));
            }
            C::CopyTexImage2D { target, .. } | C::CopyTexSubImage2D { target, .. } if cube_face(*target).is_some() => {
                let face = cube_face(*target).expect("a face");
                return Err(format!("copying into cube map face {} is not supported", face.name()));
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    /// The cube map bound to the active unit.
    pub(super) fn bound_cube(&self) -> Fallible<u32> {
        match self.bindings.cube_textures[self.unit()?] {
            0 => Err("the default cube map (0) is not supported: bind a texture to GL_TEXTURE_CUBE_MAP".into()),
            name => Ok(name),
        }
    }
}

/// A face upload's storage: the context's cube textures are RGBA8.
fn cube_upload(internal_format: u32, format: u32, kind: u32) -> Fallible<Upload> {
    let upload = Upload::new(internal_format, format, kind)?;
    if upload.format != TextureFormat::Rgba8 {
        return Err(format!(
            "cube face texels of format {format:#06x} / type {kind:#06x} are stored as {}: cube textures are RGBA8",
            upload.format.name()
        ));
    }
    Ok(upload)
}
