//! GL ES 3.0 calls that map onto the context: vertex array objects (and
//! `OES_vertex_array_object`'s names), attribute divisors (with the `ANGLE`/`EXT`
//! variants), uniform blocks and uniform buffer bindings. Instanced draws are in
//! `translate.rs`'s draw calls.
//!
//! The context keeps each vertex array's attributes and index buffer; the translation keeps
//! its own view of them (the element buffer binding, which attributes are enabled, read
//! unrecorded client memory, or have a divisor), swapped on `glBindVertexArray` as the
//! context swaps its own.

use tiler_apitrace::gles::GlEnum;

use crate::call::Call;
use crate::context::MAX_VERTEX_ATTRIBS;

use super::{Bindings, Fallible, Translator, attrib_slot};

const GL_UNIFORM_BUFFER: GlEnum = 0x8a11;

/// Buffer targets that only name a buffer for other calls: `GL_UNIFORM_BUFFER`,
/// `GL_COPY_READ_BUFFER`, `GL_COPY_WRITE_BUFFER`.
pub(super) const OTHER_BUFFER_TARGETS: [GlEnum; 3] = [GL_UNIFORM_BUFFER, 0x8f36, 0x8f37];

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

/// The calls that bring the context back to the default vertex array with divisors 0, from
/// the GL state `old` (none for an application that never used either, so such a capture's
/// context sees the same calls as before vertex arrays existed).
pub(super) fn default_vertex_array_calls(old: &Bindings) -> Vec<Call> {
    let mut calls = Vec::new();
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
            if name == 0 || self.objects()?.vertex_arrays.contains_key(&name) {
                return Err(format!("vertex array name {name} is already in use"));
            }
            let id = self.fresh_id();
            self.emit(Call::CreateVertexArray { id })?;
            self.objects()?.vertex_arrays.insert(name, id);
        }
        Ok(())
    }

    pub(super) fn bind_vertex_array(&mut self, name: u32) -> Fallible {
        let id = match name {
            0 => 0,
            name => *self
                .objects()?
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
            let Some(&id) = self.objects()?.vertex_arrays.get(&name) else { continue };
            if self.bindings.vertex_array == name {
                self.bind_vertex_array(0)?;
            }
            self.emit(Call::DeleteVertexArray { id })?;
            self.objects()?.vertex_arrays.remove(&name);
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
}
