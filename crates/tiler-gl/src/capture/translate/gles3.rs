//! GL ES 3.0 calls that map onto the context: vertex array objects (and
//! `OES_vertex_array_object`'s names), attribute divisors (with the `ANGLE`/`EXT`
//! variants), uniform blocks and uniform buffer bindings, sampler objects, the mip levels
//! of `glTexStorage2D` textures, and `glDrawBuffers`. Instanced draws are in
//! `translate.rs`'s draw calls.
//!
//! The context keeps each vertex array's attributes and index buffer; the translation keeps
//! its own view of them (the element buffer binding, which attributes are enabled, read
//! unrecorded client memory, or have a divisor), swapped on `glBindVertexArray` as the
//! context swaps its own.

use tiler_apitrace::gles::{GlEnum, Memory, Params};

use super::texels::{self, Upload};
use crate::call::{Call, TextureFormat};
use crate::context::{MAX_TEXTURE_UNITS, MAX_VERTEX_ATTRIBS};

use super::{Bindings, Fallible, Translator, attrib_slot};

const GL_UNIFORM_BUFFER: GlEnum = 0x8a11;

/// Buffer targets that only name a buffer for other calls: `GL_UNIFORM_BUFFER`,
/// `GL_COPY_READ_BUFFER`, `GL_COPY_WRITE_BUFFER`, `GL_TRANSFORM_FEEDBACK_BUFFER`,
/// `GL_PIXEL_PACK_BUFFER`, `GL_PIXEL_UNPACK_BUFFER`.
pub(super) const OTHER_BUFFER_TARGETS: [GlEnum; 6] = [
    GL_UNIFORM_BUFFER,
    0x8f36,
    0x8f37,
    super::feedback::GL_TRANSFORM_FEEDBACK_BUFFER,
    GL_PIXEL_PACK_BUFFER,
    GL_PIXEL_UNPACK_BUFFER,
];

/// `GL_PIXEL_PACK_BUFFER`: `glReadPixels` into a buffer (refused where it happens).
pub(super) const GL_PIXEL_PACK_BUFFER: GlEnum = 0x88eb;
/// `GL_PIXEL_UNPACK_BUFFER`: texel uploads read from a buffer (see `Translator::unpack_from_buffer`).
pub(super) const GL_PIXEL_UNPACK_BUFFER: GlEnum = 0x88ec;

/// The translation's view of a vertex array that is not bound.
#[derive(Clone, Debug, Default)]
pub(super) struct VertexArrayState {
    element_buffer: u32,
    enabled_attribs: [bool; MAX_VERTEX_ATTRIBS as usize],
    unrecorded_client_attribs: [bool; MAX_VERTEX_ATTRIBS as usize],
    divisors: [u32; MAX_VERTEX_ATTRIBS as usize],
}

impl VertexArrayState {
    /// Swaps this state with the bound array's in `bindings`.
    fn swap(&mut self, b: &mut Bindings) {
        std::mem::swap(&mut self.element_buffer, &mut b.element_buffer);
        std::mem::swap(&mut self.enabled_attribs, &mut b.enabled_attribs);
        std::mem::swap(&mut self.unrecorded_client_attribs, &mut b.unrecorded_client_attribs);
        std::mem::swap(&mut self.divisors, &mut b.divisors);
    }
}

/// The calls that bring the context back to the default vertex array with divisors 0 and no
/// sampler objects, from the GL state `old` (none for an application that never used them,
/// so such a capture's context sees the same calls as before they existed).
pub(super) fn default_gles3_calls(old: &Bindings) -> Vec<Call> {
    let mut calls = Vec::new();
    for unit in 0..MAX_TEXTURE_UNITS {
        if old.samplers[unit as usize] != 0 {
            calls.push(Call::UnbindSampler { unit });
        }
    }
    let divisors = if old.vertex_array != 0 {
        calls.push(Call::BindVertexArray { id: 0 });
        old.unbound_vertex_arrays.get(&0).map(|a| a.divisors).unwrap_or_default()
    } else {
        old.divisors
    };
    for (index, divisor) in (0..).zip(divisors) {
        if divisor != 0 {
            calls.push(Call::VertexAttribDivisor { index, divisor: 0 });
        }
    }
    calls
}

/// `glTexStorage2D`'s level count: 1, or the whole chain down to 1×1 (the context samples a
/// chain it has all of; a shorter immutable chain would be complete in GL).
pub(super) fn check_storage_levels(levels: i32, width: u32, height: u32) -> Fallible {
    let chain = 32 - width.max(height).max(1).leading_zeros() as i32;
    if levels == 1 || levels == chain {
        return Ok(());
    }
    Err(format!("{levels} mip levels of a {width}×{height} texture: only 1 or the whole chain ({chain}) is supported"))
}

/// What `glTexSubImage2D` into storage of `format` (from `glTexStorage2D`) converts from.
pub(super) fn storage_upload(format: TextureFormat) -> Option<Upload> {
    let (format, kind) = match format {
        TextureFormat::Rgba8 | TextureFormat::Srgb8Alpha8 => (texels::GL_RGBA, texels::GL_UNSIGNED_BYTE),
        TextureFormat::Rgb565 => (texels::GL_RGB, texels::GL_UNSIGNED_SHORT_5_6_5),
        TextureFormat::Rgba16f => (texels::GL_RGBA, texels::GL_HALF_FLOAT),
        TextureFormat::Rgba32f => (texels::GL_RGBA, texels::GL_FLOAT),
        TextureFormat::R32f => (texels::GL_RED, texels::GL_FLOAT),
        TextureFormat::Int(f) => texels::integer_client(f),
        _ => return None,
    };
    Upload::new(format, format, kind).ok()
}

/// A deleted buffer is no unbound array's element buffer any more (the context forgets it in
/// every array too).
pub(super) fn forget_buffer(bindings: &mut Bindings, name: u32) {
    bindings.uniform_bindings.retain(|_, (bound, ..)| *bound != name);
    for array in bindings.unbound_vertex_arrays.values_mut() {
        if array.element_buffer == name {
            array.element_buffer = 0;
        }
    }
}

impl Translator {
    pub(super) fn vertex_attrib_divisor(&mut self, index: u32, divisor: u32) -> Fallible {
        let slot = attrib_slot(index)?;
        self.bindings.divisors[slot] = divisor;
        self.emit(Call::VertexAttribDivisor { index, divisor })?;
        Ok(())
    }

    /// `glGenVertexArrays`: each name gets its array in the context at once (GL creates it
    /// at the first bind; nothing can tell the difference).
    pub(super) fn gen_vertex_arrays(&mut self, names: &[u32]) -> Fallible {
        for &name in names {
            if name == 0 || self.own()?.vertex_arrays.contains_key(&name) {
                return Err(format!("vertex array name {name} is already in use"));
            }
            let id = self.fresh_id();
            self.emit(Call::CreateVertexArray { id })?;
            self.own()?.vertex_arrays.insert(name, id);
        }
        Ok(())
    }

    pub(super) fn bind_vertex_array(&mut self, name: u32) -> Fallible {
        let id = match name {
            0 => 0,
            name => *self
                .own()?
                .vertex_arrays
                .get(&name)
                .ok_or_else(|| format!("vertex array {name} was not made by glGenVertexArrays"))?,
        };
        if name == self.bindings.vertex_array {
            return Ok(());
        }
        self.emit(Call::BindVertexArray { id })?;
        let mut next = self.bindings.unbound_vertex_arrays.remove(&name).unwrap_or_default();
        next.swap(&mut self.bindings);
        let previous = std::mem::replace(&mut self.bindings.vertex_array, name);
        self.bindings.unbound_vertex_arrays.insert(previous, next);
        Ok(())
    }

    /// `glDeleteVertexArrays`: deleting the bound array binds 0; unknown names and 0 are
    /// ignored, as in GL.
    pub(super) fn delete_vertex_arrays(&mut self, names: &[u32]) -> Fallible {
        for &name in names {
            let Some(&id) = self.own()?.vertex_arrays.get(&name) else { continue };
            if self.bindings.vertex_array == name {
                self.bind_vertex_array(0)?;
            }
            self.emit(Call::DeleteVertexArray { id })?;
            self.own()?.vertex_arrays.remove(&name);
            self.bindings.unbound_vertex_arrays.remove(&name);
        }
        Ok(())
    }

    /// `glUniformBlockBinding`: the block named by the index `glGetUniformBlockIndex`
    /// returned.
    pub(super) fn uniform_block_binding(&mut self, program: u32, block_index: u32, binding: u32) -> Fallible {
        let p = self.program(program)?;
        let block = p.blocks.get(&block_index).cloned().ok_or_else(|| {
            format!(
                "uniform block index {block_index} was never returned by glGetUniformBlockIndex for program {program}"
            )
        })?;
        let id = p.id.ok_or_else(|| format!("program {program} is not linked"))?;
        self.emit(Call::UniformBlockBinding { program: id, block, binding })?;
        Ok(())
    }

    /// `glBindBufferBase` / `glBindBufferRange` (`range`: offset and size) of
    /// `GL_UNIFORM_BUFFER`; they bind the generic target too.
    pub(super) fn bind_buffer_range(
        &mut self,
        target: GlEnum,
        index: u32,
        name: u32,
        range: Option<(u64, u64)>,
    ) -> Fallible {
        if target != GL_UNIFORM_BUFFER {
            return Err(format!("indexed buffer target {target:#06x} is not supported (GL_UNIFORM_BUFFER is)"));
        }
        if name != 0 {
            self.objects()?.buffers.entry(name).or_insert(None);
        }
        self.bindings.other_buffers.insert(target, name);
        let (offset, size) = match range {
            Some((offset, size)) => (offset, Some(size)),
            None => (0, None),
        };
        self.bindings.uniform_bindings.insert(index, (name, offset, size));
        // A buffer without storage yet is bound when it gets some.
        let buffer = self.buffer_id(name)?.unwrap_or(0);
        self.emit(Call::BindUniformBuffer { binding: index, buffer, offset, size })?;
        Ok(())
    }

    /// Binds buffer `name`, which just got storage `id`, where GL bound it as a uniform buffer.
    pub(super) fn bind_new_uniform_buffer(&mut self, name: u32, id: u32) -> Fallible {
        let mut bound: Vec<(u32, u64, Option<u64>)> = (self.bindings.uniform_bindings.iter())
            .filter(|(_, (n, ..))| *n == name)
            .map(|(&binding, &(_, offset, size))| (binding, offset, size))
            .collect();
        bound.sort_unstable_by_key(|b| b.0);
        for (binding, offset, size) in bound {
            self.emit(Call::BindUniformBuffer { binding, buffer: id, offset, size })?;
        }
        Ok(())
    }

    /// `glBindSampler`: the unit samples with the sampler's parameters until unbound.
    pub(super) fn bind_sampler(&mut self, unit: u32, sampler: u32) -> Fallible {
        if unit >= MAX_TEXTURE_UNITS {
            return Err(format!("texture unit {unit} is beyond the context's {MAX_TEXTURE_UNITS}"));
        }
        if sampler != 0 && !self.objects()?.samplers.contains_key(&sampler) {
            return Err(format!("sampler {sampler} was not made by glGenSamplers"));
        }
        self.bindings.samplers[unit as usize] = sampler;
        self.emit_unit_sampler(unit)
    }

    /// The context's sampler state of `unit` from the sampler bound there.
    fn emit_unit_sampler(&mut self, unit: u32) -> Fallible {
        let name = self.bindings.samplers[unit as usize];
        if name == 0 {
            self.emit(Call::UnbindSampler { unit })?;
            return Ok(());
        }
        let object = self.objects()?.samplers.get(&name).cloned().unwrap_or_default();
        let p = object.sampler()?;
        let (filter, wrap, mag_filter, wrap_t) = (p.min, p.wrap_s, Some(p.mag), Some(p.wrap_t));
        // Only a non-default WRAP_R is written, so that older call lists read the same.
        let wrap_r = match super::layered::wrap_r(object.wrap_r)? {
            crate::call::Wrap::Repeat => None,
            w => Some(w),
        };
        self.emit(Call::BindSampler { unit, filter, wrap, mag_filter, wrap_t, compare: p.compare, wrap_r })?;
        Ok(())
    }

    /// `glSamplerParameter*`: filters and wraps (`GL_TEXTURE_WRAP_R` wraps 3-D textures' r),
    /// depth comparison; level-of-detail ranges only at their defaults.
    pub(super) fn sampler_parameter(&mut self, sampler: u32, pname: GlEnum, params: &Params) -> Fallible {
        let value = match params {
            Params::Int(v) if v.len() == 1 => v[0] as f32,
            Params::Float(v) if v.len() == 1 => v[0],
            _ => return Err(format!("parameter {pname:#06x}: {params:?} is not a single value")),
        };
        let s = self
            .objects()?
            .samplers
            .get_mut(&sampler)
            .ok_or_else(|| format!("sampler {sampler} was not made by glGenSamplers"))?;
        let enumeration = value as u32;
        if s.compare_parameter(pname, f64::from(value))? {
            s.sampler()?;
            for unit in 0..MAX_TEXTURE_UNITS {
                if self.bindings.samplers[unit as usize] == sampler {
                    self.emit_unit_sampler(unit)?;
                }
            }
            return Ok(());
        }
        match (pname, value) {
            (0x2801, _) => s.min = enumeration,
            (0x2800, _) => s.mag = enumeration,
            (0x2802, _) => s.wrap[0] = enumeration,
            (0x2803, _) => s.wrap[1] = enumeration,
            (0x8072, _) => {
                super::layered::wrap_r(enumeration)?;
                s.wrap_r = enumeration;
            }
            // GL_TEXTURE_MIN_LOD / MAX_LOD at -1000 / 1000.
            (0x813a, -1000.0) | (0x813b, 1000.0) => {}
            (p, v) => return Err(format!("sampler parameter {p:#06x} = {v} is not supported")),
        }
        s.sampler()?;
        for unit in 0..MAX_TEXTURE_UNITS {
            if self.bindings.samplers[unit as usize] == sampler {
                self.emit_unit_sampler(unit)?;
            }
        }
        Ok(())
    }

    /// `glDeleteSamplers`: units that had one bound sample with their textures' parameters.
    pub(super) fn delete_samplers(&mut self, names: &[u32]) -> Fallible {
        for &name in names {
            if name == 0 || self.objects()?.samplers.remove(&name).is_none() {
                continue;
            }
            for unit in 0..MAX_TEXTURE_UNITS {
                if self.bindings.samplers[unit as usize] == name {
                    self.bind_sampler(unit, 0)?;
                }
            }
        }
        Ok(())
    }

    /// `glTexSubImage2D` at `level` > 0: a whole level (`rect` = x, y, width, height) becomes
    /// the context's `tex_image_level`.
    pub(super) fn tex_sub_image_level(
        &mut self,
        level: u32,
        rect: [u32; 4],
        format: GlEnum,
        kind: GlEnum,
        pixels: &Memory,
    ) -> Fallible {
        let [x, y, width, height] = rect;
        let name = self.bound_texture()?;
        let texture = self.objects()?.textures.get(&name).cloned().unwrap_or_default();
        let (Some(id), Some(stored)) = (texture.id, texture.upload) else {
            return Err(format!("texture {name} has no storage"));
        };
        let upload = Upload::new(format, format, kind)?;
        if !upload.fills(stored.format) {
            return Err(format!(
                "texels of format {format:#06x} / type {kind:#06x} into a texture stored as {}",
                stored.format.name()
            ));
        }
        let (w, h) = texture.size;
        let expected = ((w >> level).max(1), (h >> level).max(1));
        if (x, y, width, height) != (0, 0, expected.0, expected.1) {
            return Err(format!(
                "part of mip level {level} ({width}×{height} at {x}, {y}) of a {w}×{h} texture: only whole levels \
                 ({}×{}) are supported",
                expected.0, expected.1
            ));
        }
        let data = self.texels(&upload, pixels, width, height)?.ok_or("the texels were not recorded")?;
        let data = self.swizzled(name, stored.format, data)?;
        self.emit(Call::TexImageLevel { id, level, width, height, data })?;
        Ok(())
    }

    /// `glDrawBuffers`: the window's `GL_BACK`, or a framebuffer's colour attachments in order
    /// (`GL_COLOR_ATTACHMENT0`, `1`, …, then only `GL_NONE`s) — outputs `i` to attachment `i`,
    /// as the context draws them; none (a shadow map's depth-only pass) writes no colour.
    pub(super) fn draw_buffers(&mut self, buffers: &[GlEnum]) -> Fallible {
        const GL_BACK: GlEnum = 0x0405;
        const GL_COLOR_ATTACHMENT0: GlEnum = 0x8ce0;
        if self.bindings.draw_framebuffer == 0 {
            if buffers != [GL_BACK] {
                return Err(format!("draw buffers {buffers:x?} of the window: only GL_BACK is supported"));
            }
            return Ok(());
        }
        let count = buffers.iter().take_while(|&&b| b != 0).count();
        let in_order = (0..).zip(&buffers[..count]).all(|(i, &b)| b == GL_COLOR_ATTACHMENT0 + i);
        // No colour at all (`glDrawBuffers(0, NULL)`, or only `GL_NONE`): a depth-only pass.
        if !in_order || buffers[count..].iter().any(|&b| b != 0) {
            return Err(format!(
                "draw buffers {buffers:x?}: only colour attachments 0, 1, … in order (then GL_NONE) are supported"
            ));
        }
        self.emit(Call::DrawBuffers { count: count as u32 })?;
        Ok(())
    }
}
