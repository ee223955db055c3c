//! Cube textures in the context: six square faces of RGBA8 texels, each with its mip chain,
//! sampled by `samplerCube` uniforms through the core's cube sampler (`tiler::Texture`'s cube
//! textures: GLES 2.0 face selection, the 2D filters within a face, the texture cache and the
//! ledger's `texture fetch`).
//!
//! A cube texture's faces live on the host, as uploaded (rows bottom to top: GL's `t = 0`
//! first, which is the core cube's row order), not in device images: nothing renders into
//! them (`framebuffer_texture` takes 2D textures only). A draw takes the core texture of the
//! cube as it is at the draw, built once per change and shared by the draws until the next
//! change, so an upload after a draw never reaches it (what GL's copy-on-write gives).
//!
//! GL ES 2.0's completeness (§3.7.10, "cube complete"): every face's level 0 given, square, of
//! one size and format; with a mipmap filter also a chain on every face, generated or given
//! down to 1×1. An incomplete cube samples (0, 0, 0, 1), as an incomplete 2D texture does. A
//! face of another size than the cube's other faces, or a non-square face, is refused at once
//! (GL would accept it and leave the cube incomplete until every face matches).

use std::sync::{Arc, OnceLock};

use super::{Context, Fallible, MAX_TEXTURE_UNITS, mip_levels, name_taken};
use crate::bytes::Bytes;
use crate::call::{CubeFace, Filter, TextureFormat, Wrap};
use crate::program::SamplerState;

/// A cube texture object.
pub(crate) struct CubeObject {
    format: TextureFormat,
    /// Level 0's face size (0 before a face is given).
    size: u32,
    /// Each face's level 0, RGBA8, rows bottom to top.
    faces: [Option<Arc<Vec<u8>>>; 6],
    /// Each face's levels 1, 2, … as given, `None` where not given.
    levels: [Vec<Option<Arc<Vec<u8>>>>; 6],
    pub sampler: SamplerState,
    /// `generate_mipmap` was called since level 0's size last changed.
    generated: bool,
    /// The core texture of the cube as it is, made at the first draw after a change: sampled
    /// without mip maps (`[0]`) and with them (`[1]`; a sampler object on the unit may want
    /// them where the cube's own filter does not).
    core: [OnceLock<Option<Arc<tiler::Texture>>>; 2],
}

impl CubeObject {
    fn new(format: TextureFormat) -> CubeObject {
        CubeObject {
            format,
            size: 0,
            faces: Default::default(),
            levels: Default::default(),
            sampler: SamplerState::new(Filter::NearestMipmapLinear, Wrap::Repeat),
            generated: false,
            core: Default::default(),
        }
    }

    /// Forgets the core texture made from the old contents (draws made before keep theirs).
    fn changed(&mut self) {
        self.core = Default::default();
    }

    /// Every face's given chain, when every face has one down to 1×1.
    fn given_chains(&self) -> Option<[Vec<&[u8]>; 6]> {
        let wanted = mip_levels(self.size, self.size) as usize - 1;
        let chain = |face: usize| -> Option<Vec<&[u8]>> {
            let base = self.faces[face].as_deref()?.as_slice();
            if self.levels[face].len() != wanted {
                return None;
            }
            let mut chain = vec![base];
            for level in &self.levels[face] {
                chain.push(level.as_deref()?.as_slice());
            }
            Some(chain)
        };
        let chains: Vec<Vec<&[u8]>> = (0..6).map(chain).collect::<Option<_>>()?;
        chains.try_into().ok()
    }

    /// The core texture to sample with a mipmap filter (`wants_mips`) or without, `None` when
    /// GL's rules make the cube incomplete.
    fn core(&self, wants_mips: bool) -> Fallible<Option<Arc<tiler::Texture>>> {
        if let Some(core) = self.core[wants_mips as usize].get() {
            return Ok(core.clone());
        }
        let color_space = match self.format {
            TextureFormat::Srgb8Alpha8 => tiler::ColorSpace::Srgb,
            _ => tiler::ColorSpace::Linear,
        };
        let faces: Option<Vec<&[u8]>> = self.faces.iter().map(|f| f.as_deref().map(Vec::as_slice)).collect();
        let built = match faces {
            None => None,
            Some(faces) => {
                let faces: [&[u8]; 6] = faces.try_into().expect("six faces");
                match (wants_mips, self.generated, self.given_chains()) {
                    (false, _, _) => {
                        Some(tiler::Texture::cube_from_rgba8(self.size, faces, color_space, tiler::MipChain::BaseOnly))
                    }
                    (true, true, _) => {
                        Some(tiler::Texture::cube_from_rgba8(self.size, faces, color_space, tiler::MipChain::Box))
                    }
                    (true, false, Some(chains)) => {
                        let chains: [&[&[u8]]; 6] = std::array::from_fn(|i| chains[i].as_slice());
                        Some(tiler::Texture::cube_from_rgba8_levels(self.size, chains, color_space))
                    }
                    (true, false, None) => None,
                }
            }
        };
        let built = built.transpose().map_err(|e| e.to_string())?.map(Arc::new);
        Ok(self.core[wants_mips as usize].get_or_init(|| built).clone())
    }

    /// Host memory its texels take (counted against the context's memory limit).
    fn host_bytes(&self) -> u64 {
        let faces = self.faces.iter().flatten().map(|f| f.len() as u64);
        faces.chain(self.levels.iter().flatten().flatten().map(|l| l.len() as u64)).sum()
    }

    /// Whether the cube has its faces' mip chains (generated, or given on every face).
    fn has_mipmaps(&self) -> bool {
        self.generated || self.given_chains().is_some()
    }
}

impl Context {
    /// `cube_tex_image`: level `level` of face `face` of cube texture `id`, created if new.
    /// The texels count against the context's memory limit while the cube holds them.
    pub(crate) fn cube_tex_image(
        &mut self,
        id: u32,
        face: CubeFace,
        level: u32,
        size: u32,
        format: TextureFormat,
        data: Option<Bytes>,
    ) -> Fallible {
        if id == 0 {
            return Err(name_taken("texture", id));
        }
        if self.textures.contains_key(&id) {
            return Err(format!("texture {id} is a 2D texture, not a cube texture"));
        }
        let before = self.cubes.get(&id).map_or(0, CubeObject::host_bytes);
        // The new texels, at most (the size is checked below, before they are made).
        let new_bytes = (size.min(tiler::MAX_CUBE_DIMENSION) as u64).pow(2) * 4;
        self.reserve(new_bytes)?;
        let result = self.store_cube_texels(id, face, level, size, format, data);
        let after = self.cubes.get(&id).map_or(0, CubeObject::host_bytes);
        self.allocated = self.allocated - new_bytes - before + after;
        result
    }

    /// [`Context::cube_tex_image`] once its memory is reserved.
    fn store_cube_texels(
        &mut self,
        id: u32,
        face: CubeFace,
        level: u32,
        size: u32,
        format: TextureFormat,
        data: Option<Bytes>,
    ) -> Fallible {
        if !matches!(format, TextureFormat::Rgba8 | TextureFormat::Srgb8Alpha8) {
            return Err(format!(
                "cube texture {id}: format {} (cube textures are RGBA8 or sRGB8_alpha8)",
                format.name()
            ));
        }
        if size == 0 || size > tiler::MAX_CUBE_DIMENSION {
            return Err(format!(
                "cube texture {id}, face {}: size {size}×{size} must be from 1×1 to {max}×{max}",
                face.name(),
                max = tiler::MAX_CUBE_DIMENSION
            ));
        }
        let bytes = size as usize * size as usize * 4;
        if let Some(data) = &data
            && data.len() != bytes
        {
            return Err(format!(
                "cube texture {id}, face {}: {} bytes of texels, but {size}×{size} RGBA8 needs {bytes}",
                face.name(),
                data.len()
            ));
        }
        let cube = self.cubes.entry(id).or_insert_with(|| CubeObject::new(format));
        let texels = Arc::new(data.map_or_else(|| vec![0; bytes], |d| d.to_vec()));
        let f = face.index();
        if level == 0 {
            let others = (0..6).filter(|&i| i != f && cube.faces[i].is_some()).count();
            if others > 0 && (size != cube.size || format != cube.format) {
                return Err(format!(
                    "cube texture {id}, face {}: {size}×{size} {}, but its other faces are {s}×{s} {}: every face \
                     has the same size and format",
                    face.name(),
                    format.name(),
                    cube.format.name(),
                    s = cube.size
                ));
            }
            if size != cube.size {
                // A new size: the levels given for the old one, and generated ones, go.
                cube.levels = Default::default();
                cube.generated = false;
            }
            (cube.size, cube.format) = (size, format);
            cube.faces[f] = Some(texels);
        } else {
            if cube.size == 0 {
                return Err(format!("cube texture {id}, face {}: mip level {level} before level 0", face.name()));
            }
            let levels = mip_levels(cube.size, cube.size);
            if level >= levels {
                return Err(format!(
                    "cube texture {id}, face {}: mip level {level}, but a {s}×{s} face has levels 1 to {}",
                    face.name(),
                    levels - 1,
                    s = cube.size
                ));
            }
            let expected = (cube.size >> level).max(1);
            if size != expected || format != cube.format {
                return Err(format!(
                    "cube texture {id}, face {}: mip level {level} is {size}×{size} {}, but level 0 is {s}×{s} {}, so \
                     it must be {expected}×{expected}",
                    face.name(),
                    format.name(),
                    cube.format.name(),
                    s = cube.size
                ));
            }
            if cube.generated {
                return Err(format!(
                    "cube texture {id}, face {}: mip level {level} replaces one of its generated levels: not \
                     supported (give every level, or generate them)",
                    face.name()
                ));
            }
            let index = level as usize - 1;
            if cube.levels[f].len() <= index {
                cube.levels[f].resize(index + 1, None);
            }
            cube.levels[f][index] = Some(texels);
        }
        cube.changed();
        Ok(())
    }

    /// `cube_tex_sub_image`: a rectangle of level 0 of a face.
    #[allow(clippy::too_many_arguments)] // The call's fields, as `tex_sub_image` takes them.
    pub(crate) fn cube_tex_sub_image(
        &mut self,
        id: u32,
        face: CubeFace,
        x: u32,
        y: u32,
        width: u32,
        height: u32,
        data: Bytes,
    ) -> Fallible {
        let cube = self.cube_mut(id)?;
        let f = face.index();
        let size = cube.size;
        let Some(texels) = cube.faces[f].as_mut() else {
            return Err(format!("cube texture {id}, face {}: no level 0 to update", face.name()));
        };
        if x as u64 + width as u64 > size as u64 || y as u64 + height as u64 > size as u64 {
            return Err(format!(
                "cube texture {id}, face {}: rectangle {width}×{height} at ({x}, {y}) is outside the {size}×{size} face",
                face.name()
            ));
        }
        let row = width as usize * 4;
        if data.len() != row * height as usize {
            return Err(format!(
                "cube texture {id}, face {}: {} bytes of texels, but {width}×{height} RGBA8 needs {}",
                face.name(),
                data.len(),
                row * height as usize
            ));
        }
        // Both in GL's row order (bottom first): row r of the rectangle is face row y + r.
        let texels = Arc::make_mut(texels);
        for (r, src) in data.chunks_exact(row.max(1)).enumerate().take(height as usize) {
            let at = ((y as usize + r) * size as usize + x as usize) * 4;
            texels[at..at + row].copy_from_slice(src);
        }
        cube.changed();
        Ok(())
    }

    /// `generate_mipmap` of a cube texture: every face must have its level 0 (GL: "cube
    /// complete").
    pub(crate) fn generate_cube_mipmap(&mut self, id: u32) -> Fallible {
        let cube = self.cube_mut(id)?;
        if let Some(face) = CubeFace::ALL.iter().find(|f| cube.faces[f.index()].is_none()) {
            return Err(format!(
                "generate_mipmap of cube texture {id}: face {} has no level 0 (the cube is not complete)",
                face.name()
            ));
        }
        let before = cube.host_bytes();
        cube.generated = true;
        cube.levels = Default::default();
        cube.changed();
        let freed = before - cube.host_bytes();
        self.allocated -= freed;
        Ok(())
    }

    /// `bind_cube_texture`.
    pub(crate) fn bind_cube_texture(&mut self, unit: u32, texture: u32) -> Fallible {
        if unit >= MAX_TEXTURE_UNITS {
            return Err(format!("texture unit {unit} is out of range (0 to {})", MAX_TEXTURE_UNITS - 1));
        }
        if texture != 0 {
            self.cube_mut(texture)?;
        }
        self.state.cube_textures[unit as usize] = texture;
        Ok(())
    }

    /// Deletes cube texture `id`, unbinding it from every unit.
    pub(crate) fn delete_cube(&mut self, id: u32) {
        if let Some(cube) = self.cubes.remove(&id) {
            self.allocated -= cube.host_bytes();
        }
        for unit in &mut self.state.cube_textures {
            if *unit == id {
                *unit = 0;
            }
        }
        self.forget_texture_in_contexts(id);
    }

    /// What a `samplerCube` reading texture unit `unit` samples at a draw (`what` names it in
    /// errors): the core texture and sampler, or `None` for an incomplete cube.
    ///
    /// # Errors
    /// No cube texture on the unit, or a face the core refuses.
    pub(crate) fn cube_binding(
        &self,
        unit: u32,
        what: &str,
    ) -> Fallible<Option<(Arc<tiler::Texture>, tiler::Sampler)>> {
        let id = self.state.cube_textures.get(unit as usize).copied().unwrap_or(0);
        let cube = self
            .cubes
            .get(&id)
            .ok_or_else(|| format!("{what} reads texture unit {unit}, which has no cube texture"))?;
        // A sampler object on the unit replaces the cube's parameters, as for 2D textures.
        let state = self.state.unit_samplers.get(unit as usize).copied().flatten().unwrap_or(cube.sampler);
        let wants_mips = state.min_filter.mipmap().is_some();
        let core = cube.core(wants_mips).map_err(|e| format!("{what}: cube texture {id}: {e}"))?;
        let sampler = super::submit::core_sampler(state, cube.has_mipmaps());
        Ok(core.map(|t| (t, sampler)))
    }

    /// Cube texture `id`'s object.
    pub(crate) fn cube_mut(&mut self, id: u32) -> Fallible<&mut CubeObject> {
        if self.textures.contains_key(&id) {
            return Err(format!("texture {id} is a 2D texture, not a cube texture"));
        }
        self.cubes.get_mut(&id).ok_or_else(|| format!("cube texture {id} does not exist"))
    }
}
