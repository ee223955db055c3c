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
//! with a mipmap minification filter (GL would sample it incomplete: a silent black). A 2-D
//! array's chain is generated, as a 2D texture's (`MipChain::Linear`, each layer on its own).
//!
//! **Rendering into a layer** (`framebuffer_texture_layer`, GL's `glFramebufferTextureLayer`;
//! `copy_tex_sub_image_layer`, GL's `glCopyTexSubImage3D`, is a copy pass into the same image):
//! the layer gets a device image of its own, a hidden 2D texture holding the layer's texels,
//! attached as any texture is — so a pass that renders into it loads and stores it as any
//! attachment, and the ledger counts those loads and stores. The texture keeps its layer
//! images while it lives; when it is next read (a draw, an upload, `generate_mipmap`) after a
//! pass has rendered, the layer images' texels are copied back into the host texels (the
//! open pass is rendered first if it renders into one), and an upload into a layer reaches
//! its image too. The copies between the two are not counted: they stand for one memory.

use std::collections::BTreeMap;
use std::sync::{Arc, OnceLock};

use super::{AttachmentRef, Context, Fallible, MAX_TEXTURE_UNITS, name_taken};
use crate::bytes::Bytes;
use crate::call::{AttachmentPoint, Filter, LayeredTarget, TextureFormat, Wrap};
use crate::program::SamplerState;
use crate::report::FlushCause;

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
    /// Layers rendered into: layer → the hidden 2D texture holding its device image.
    layers: BTreeMap<u32, u32>,
    /// `passes_rendered` when the layer images were last copied back.
    synced: Option<u32>,
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

    /// Layer (slice) `layer`'s texels, rows bottom to top.
    fn layer_texels(&self, layer: u32) -> &[u8] {
        let size = self.width as usize * self.height as usize * 4;
        &self.texels[layer as usize * size..(layer as usize + 1) * size]
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
            layers: BTreeMap::new(),
            synced: None,
        };
        if self.layered.get(&id).is_some_and(|t| !t.layers.is_empty()) {
            return Err(format!(
                "new storage for {} texture {id}, whose layers have been framebuffer attachments: not supported",
                target.name()
            ));
        }
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
        self.sync_rendered_layers(id)?;
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
        let touched: Vec<(u32, u32)> = t.layers.range(z..z + depth).map(|(l, h)| (*l, *h)).collect();
        for (layer, hidden) in touched {
            let bytes = self.layered[&id].layer_texels(layer).to_vec();
            let (w, h) = (self.layered[&id].width, self.layered[&id].height);
            self.tex_sub_image(hidden, 0, 0, w, h, Bytes::from(bytes))?;
        }
        Ok(())
    }

    /// `generate_mipmap` of a layered texture: a 2-D array's layers each get their chain; a
    /// 3-D texture's is refused.
    pub(crate) fn generate_layered_mipmap(&mut self, id: u32) -> Fallible {
        self.sync_rendered_layers(id)?;
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
    pub(crate) fn delete_layered(&mut self, id: u32) -> Fallible {
        if let Some(t) = self.layered.remove(&id) {
            self.allocated -= t.host_bytes();
            for hidden in t.layers.into_values() {
                self.delete_texture(hidden)?;
            }
        }
        for unit in &mut self.state.layered_textures {
            for bound in unit {
                if *bound == id {
                    *bound = 0;
                }
            }
        }
        self.forget_texture_in_contexts(id);
        Ok(())
    }

    /// `framebuffer_texture_layer`: layer `layer` of 2-D array or 3-D texture `texture` becomes
    /// attachment `point` of `framebuffer` (0 detaches), through its layer image (made now,
    /// holding the layer's texels, if it has none yet).
    pub(crate) fn framebuffer_texture_layer(
        &mut self,
        framebuffer: u32,
        point: AttachmentPoint,
        texture: u32,
        layer: u32,
    ) -> Fallible {
        if texture == 0 {
            return self.attach(framebuffer, point, None);
        }
        if point.color_index().is_none() {
            return Err(format!("texture {texture} is colour: it cannot be a depth or stencil attachment"));
        }
        let hidden = self.layer_texture(texture, layer)?;
        self.attach(framebuffer, point, Some(AttachmentRef::Texture(hidden)))
    }

    /// The hidden 2D texture of layer `layer` of layered texture `texture`, made now (holding
    /// the layer's texels) if it has none yet.
    pub(crate) fn layer_texture(&mut self, texture: u32, layer: u32) -> Fallible<u32> {
        let t = self.layered_mut(texture)?;
        let what = format!("{} texture {texture}", t.target.name());
        if layer >= t.depth {
            return Err(format!("layer {layer} of {what}, which has {}", t.depth));
        }
        Ok(match t.layers.get(&layer) {
            Some(&hidden) => hidden,
            None => {
                let (w, h, format) = (t.width, t.height, t.format);
                let bytes = t.layer_texels(layer).to_vec();
                let hidden = (1..=u32::MAX)
                    .rev()
                    .find(|id| {
                        !self.textures.contains_key(id)
                            && !self.cubes.contains_key(id)
                            && !self.layered.contains_key(id)
                    })
                    .ok_or("no texture name is free for a layer image")?;
                self.texture_storage(hidden, w, h, format, Some(Bytes::from(bytes)), false)?;
                let t = self.layered_mut(texture)?;
                t.layers.insert(layer, hidden);
                t.synced = None;
                hidden
            }
        })
    }

    /// Copies the layer images of the layered textures the program in use samples back into
    /// their texels, where they have been rendered into (see the module docs).
    pub(crate) fn sync_sampled_layers(&mut self) -> Fallible {
        if self.layered.values().all(|t| t.layers.is_empty()) {
            return Ok(());
        }
        let Some(super::ProgramObject::Glsl(p)) = self.programs.get(&self.state.program) else {
            return Ok(());
        };
        let mut ids = Vec::new();
        for (kind, target) in [
            (tiler_glsl::SamplerKind::Sampler2DArray, LayeredTarget::Array2D),
            (tiler_glsl::SamplerKind::Sampler3D, LayeredTarget::Texture3D),
        ] {
            for unit in p.units_of(kind) {
                if let Some(id) = self.state.layered_textures.get(unit as usize).map(|u| u[target.index()]) {
                    ids.push(id);
                }
            }
        }
        ids.into_iter().try_for_each(|id| self.sync_rendered_layers(id))
    }

    /// Copies texture `id`'s layer images back into its texels if a pass may have rendered
    /// into them since the last copy (the open pass first, if it renders into one).
    pub(crate) fn sync_rendered_layers(&mut self, id: u32) -> Fallible {
        let Some(t) = self.layered.get(&id) else { return Ok(()) };
        if t.layers.is_empty() {
            return Ok(());
        }
        let layers: Vec<(u32, u32)> = t.layers.iter().map(|(l, h)| (*l, *h)).collect();
        let pending = self.pass.as_ref().is_some_and(|p| p.has_work());
        if pending && layers.iter().any(|(_, h)| self.open_pass_attaches(AttachmentRef::Texture(*h))) {
            self.flush_open_pass(FlushCause::SampleAttachment)?;
        }
        if self.layered[&id].synced == Some(self.passes_rendered) {
            return Ok(());
        }
        for (layer, hidden) in layers {
            let image = self.texture(hidden)?.image;
            let data = self.device.image_data(image).map_err(|e| e.to_string())?;
            let t = &self.layered[&id];
            let row = t.width as usize * 4;
            // The image's rows are tiler's (top first); the texels GL's (bottom first).
            let rows: Vec<u8> = data[..row * t.height as usize].chunks_exact(row).rev().flatten().copied().collect();
            if rows != t.layer_texels(layer) {
                let t = self.layered.get_mut(&id).expect("checked");
                let at = layer as usize * rows.len();
                Arc::make_mut(&mut t.texels)[at..at + rows.len()].copy_from_slice(&rows);
                t.core = OnceLock::new();
            }
        }
        let passes = self.passes_rendered;
        self.layered.get_mut(&id).expect("checked").synced = Some(passes);
        Ok(())
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
