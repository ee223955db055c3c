//! 2-D array and 3-D textures in the context: `depth` layers (slices) of RGBA8 texels,
//! sampled by `sampler2DArray` / `sampler3D` uniforms through the core's layered samplers
//! (`tiler::Texture`'s array and volume textures: a layer per lane, the 2D filters within it,
//! a 3-D texture's slices blended, the texture cache and the ledger's `texture fetch`).
//!
//! As cube textures (`cube.rs`), their texels live on the host as uploaded (rows bottom to
//! top, GL's `t = 0` first, the core's row order for layered textures), not in device images;
//! a draw takes the core texture as it is at the draw, built once per change.
//!
//! What is refused, by name: mip levels given by `glTexImage3D` with `level > 0` (the
//! translator), a 3-D texture's mip chain (`generate_mipmap`) and so a 3-D texture sampled
//! with a mipmap minification filter (GL would sample it incomplete: a silent black), and
//! rendering into a layer (`glFramebufferTextureLayer`, the translator). A 2-D array's chain
//! is generated, as a 2D texture's (`MipChain::Linear`, each layer on its own).

use std::sync::{Arc, OnceLock};

use super::{Context, Fallible, MAX_TEXTURE_UNITS, name_taken};
use crate::bytes::Bytes;
use crate::call::{Filter, LayeredTarget, TextureFormat, Wrap};
use crate::program::SamplerState;

/// A 2-D array or 3-D texture object.
pub(crate) struct LayeredObject {
    target: LayeredTarget,
    format: TextureFormat,
    width: u32,
    height: u32,
    depth: u32,
    /// Level 0's layers one after the other, RGBA8, rows bottom to top.
    texels: Arc<Vec<u8>>,
    pub sampler: SamplerState,
    /// `GL_TEXTURE_WRAP_R`.
    pub wrap_r: Wrap,
    /// `generate_mipmap` was called since level 0 was last given.
    generated: bool,
    /// The core texture as it is, made at the first draw after a change.
    core: OnceLock<Arc<tiler::Texture>>,
}

impl LayeredObject {
    /// The core texture to sample.
    fn core(&self) -> Fallible<Arc<tiler::Texture>> {
        if let Some(core) = self.core.get() {
            return Ok(core.clone());
        }
        let color_space = match self.format {
            TextureFormat::Srgb8Alpha8 => tiler::ColorSpace::Srgb,
            _ => tiler::ColorSpace::Linear,
        };
        let (w, h, d) = (self.width, self.height, self.depth);
        let built = match self.target {
            LayeredTarget::Array2D => {
                let mips = if self.generated { tiler::MipChain::Linear } else { tiler::MipChain::BaseOnly };
                tiler::Texture::array_from_rgba8(w, h, d, &self.texels, color_space, mips)
            }
            LayeredTarget::Texture3D => tiler::Texture::volume_from_rgba8(w, h, d, &self.texels, color_space),
        };
        let built = Arc::new(built.map_err(|e| e.to_string())?);
        Ok(self.core.get_or_init(|| built).clone())
    }

    fn host_bytes(&self) -> u64 {
        self.texels.len() as u64
    }
}

impl Context {
    /// `layered_tex_image`: level 0 of 2-D array or 3-D texture `id`, created if new. The
    /// texels count against the context's memory limit while the texture holds them.
    pub(crate) fn layered_tex_image(
        &mut self,
        id: u32,
        target: LayeredTarget,
        (width, height, depth): (u32, u32, u32),
        format: TextureFormat,
        data: Option<Bytes>,
    ) -> Fallible {
        if id == 0 || self.textures.contains_key(&id) || self.cubes.contains_key(&id) {
            return Err(name_taken("texture", id));
        }
        if let Some(t) = self.layered.get(&id)
            && t.target != target
        {
            return Err(format!("texture {id} is a {} texture, not a {} one", t.target.name(), target.name()));
        }
        if !matches!(format, TextureFormat::Rgba8 | TextureFormat::Srgb8Alpha8) {
            return Err(format!(
                "{} texture {id}: format {} (2-D array and 3-D textures are RGBA8 or sRGB8_alpha8)",
                target.name(),
                format.name()
            ));
        }
        let (max_side, max_depth) = match target {
            LayeredTarget::Array2D => (tiler::MAX_TEXTURE_DIMENSION, tiler::MAX_ARRAY_LAYERS),
            LayeredTarget::Texture3D => (tiler::MAX_VOLUME_DIMENSION, tiler::MAX_VOLUME_DIMENSION),
        };
        if width == 0 || height == 0 || depth == 0 || width > max_side || height > max_side || depth > max_depth {
            return Err(format!(
                "{} texture {id}: size {width}×{height}×{depth} must be from 1×1×1 to {max_side}×{max_side}×{max_depth}",
                target.name()
            ));
        }
        let bytes = width as u64 * height as u64 * depth as u64 * 4;
        if let Some(data) = &data
            && data.len() as u64 != bytes
        {
            return Err(format!(
                "{} texture {id}: {} bytes of texels, but {width}×{height}×{depth} RGBA8 needs {bytes}",
                target.name(),
                data.len()
            ));
        }
        let before = self.layered.get(&id).map_or(0, LayeredObject::host_bytes);
        self.reserve(bytes)?;
        self.allocated -= before;
        let texels = Arc::new(data.map_or_else(|| vec![0; bytes as usize], |d| d.to_vec()));
        let (sampler, wrap_r) = self
            .layered
            .get(&id)
            .map_or((SamplerState::new(Filter::NearestMipmapLinear, Wrap::Repeat), Wrap::Repeat), |t| {
                (t.sampler, t.wrap_r)
            });
        let object = LayeredObject {
            target,
            format,
            width,
            height,
            depth,
            texels,
            sampler,
            wrap_r,
            generated: false,
            core: OnceLock::new(),
        };
        self.layered.insert(id, object);
        Ok(())
    }

    /// `layered_tex_sub_image`: a box of level 0.
    pub(crate) fn layered_tex_sub_image(
        &mut self,
        id: u32,
        (x, y, z): (u32, u32, u32),
        (width, height, depth): (u32, u32, u32),
        data: Bytes,
    ) -> Fallible {
        let t = self.layered_mut(id)?;
        let what = format!("{} texture {id}", t.target.name());
        if x as u64 + width as u64 > t.width as u64
            || y as u64 + height as u64 > t.height as u64
            || z as u64 + depth as u64 > t.depth as u64
        {
            return Err(format!(
                "{what}: box {width}×{height}×{depth} at ({x}, {y}, {z}) is outside its {}×{}×{} texels",
                t.width, t.height, t.depth
            ));
        }
        let row = width as usize * 4;
        let want = row * height as usize * depth as usize;
        if data.len() != want {
            return Err(format!(
                "{what}: {} bytes of texels, but {width}×{height}×{depth} RGBA8 needs {want}",
                data.len()
            ));
        }
        let (tw, th) = (t.width as usize, t.height as usize);
        let texels = Arc::make_mut(&mut t.texels);
        for (r, src) in data.chunks_exact(row.max(1)).enumerate().take(height as usize * depth as usize) {
            let (layer, row_in_layer) = (z as usize + r / height as usize, y as usize + r % height as usize);
            let at = ((layer * th + row_in_layer) * tw + x as usize) * 4;
            texels[at..at + row].copy_from_slice(src);
        }
        t.core = OnceLock::new();
        Ok(())
    }

    /// `generate_mipmap` of a layered texture: a 2-D array's layers each get their chain; a
    /// 3-D texture's is refused.
    pub(crate) fn generate_layered_mipmap(&mut self, id: u32) -> Fallible {
        let t = self.layered_mut(id)?;
        if t.target == LayeredTarget::Texture3D {
            return Err(format!(
                "generate_mipmap of 3-D texture {id}: mipmapped 3-D textures are not supported (tiler samples a \
                 3-D texture's level 0)"
            ));
        }
        t.generated = true;
        t.core = OnceLock::new();
        Ok(())
    }

    /// `bind_layered_texture`.
    pub(crate) fn bind_layered_texture(&mut self, unit: u32, target: LayeredTarget, texture: u32) -> Fallible {
        if unit >= MAX_TEXTURE_UNITS {
            return Err(format!("texture unit {unit} is out of range (0 to {})", MAX_TEXTURE_UNITS - 1));
        }
        if texture != 0 {
            let t = self.layered_mut(texture)?;
            if t.target != target {
                return Err(format!("texture {texture} is a {} texture, not a {} one", t.target.name(), target.name()));
            }
        }
        self.state.layered_textures[unit as usize][target.index()] = texture;
        Ok(())
    }

    /// Deletes layered texture `id`, unbinding it from every unit.
    pub(crate) fn delete_layered(&mut self, id: u32) {
        if let Some(t) = self.layered.remove(&id) {
            self.allocated -= t.host_bytes();
        }
        for unit in &mut self.state.layered_textures {
            for bound in unit {
                if *bound == id {
                    *bound = 0;
                }
            }
        }
    }

    /// What a `sampler2DArray` / `sampler3D` reading texture unit `unit` samples at a draw
    /// (`what` names it in errors): the core texture and sampler.
    ///
    /// # Errors
    /// No such texture on the unit, a 3-D texture with a mipmap minification filter, or
    /// texels the core refuses.
    pub(crate) fn layered_binding(
        &self,
        unit: u32,
        target: LayeredTarget,
        what: &str,
    ) -> Fallible<(Arc<tiler::Texture>, tiler::Sampler)> {
        let id = self.state.layered_textures.get(unit as usize).map_or(0, |u| u[target.index()]);
        let t = self
            .layered
            .get(&id)
            .ok_or_else(|| format!("{what} reads texture unit {unit}, which has no {} texture", target.name()))?;
        // A sampler object on the unit replaces the texture's parameters, `WRAP_R` included.
        let unit_sampler = self.state.unit_samplers.get(unit as usize).copied().flatten();
        let state = unit_sampler.unwrap_or(t.sampler);
        let wrap_r = if unit_sampler.is_some() { self.state.unit_wrap_r[unit as usize] } else { t.wrap_r };
        if target == LayeredTarget::Texture3D && state.min_filter.mipmap().is_some() {
            return Err(format!(
                "{what}: 3-D texture {id} is minified with a mipmap filter ({:?}): mipmapped 3-D textures are not \
                 supported (set GL_TEXTURE_MIN_FILTER to GL_NEAREST or GL_LINEAR)",
                state.min_filter
            ));
        }
        let core = t.core().map_err(|e| format!("{what}: {} texture {id}: {e}", target.name()))?;
        let mut sampler = super::submit::core_sampler(state, t.generated);
        sampler.wrap_w = match wrap_r {
            Wrap::ClampToEdge => tiler::Wrap::ClampToEdge,
            Wrap::Repeat => tiler::Wrap::Repeat,
            Wrap::MirroredRepeat => tiler::Wrap::MirroredRepeat,
        };
        Ok((core, sampler))
    }

    /// Layered texture `id`'s object.
    pub(crate) fn layered_mut(&mut self, id: u32) -> Fallible<&mut LayeredObject> {
        self.layered.get_mut(&id).ok_or_else(|| format!("texture {id} is not a 2-D array or 3-D texture"))
    }
}
