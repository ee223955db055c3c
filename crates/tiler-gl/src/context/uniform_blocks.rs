//! Uniform blocks (GL ES 3.0 §2.12.6): a GLSL program's block reads the buffer bound at its
//! uniform buffer binding (`uniform_block_binding`, initially 0; `bind_uniform_buffer`), laid
//! out `std140` (`tiler_glsl::std140`).
//!
//! The values are read from the buffer's bytes when a draw is called, as the other uniforms'
//! are taken then, and the buffer counts as used by the draw: changing it while the frame
//! that reads it is pending is a copy-on-write, as for vertex buffers. Reading the values is
//! not counted in the ledger (nor are other uniforms': the driver hands them to the shader
//! cores with the draw's state).

use tiler_glsl::UniformValues;

use super::glsl::GlslProgram;
use super::{Context, Fallible, MAX_UNIFORM_BUFFER_BINDINGS, ProgramObject};

/// What a uniform buffer binding holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct UniformBufferBinding {
    pub(super) buffer: u32,
    offset: u64,
    /// `None`: to the buffer's end.
    size: Option<u64>,
}

impl Context {
    /// `uniform_block_binding`.
    pub(super) fn uniform_block_binding(&mut self, program: u32, block: &str, binding: u32) -> Fallible {
        check_binding(binding)?;
        let p = match self.programs.get_mut(&program) {
            Some(ProgramObject::Glsl(p)) => p,
            Some(ProgramObject::Builtin { .. }) => {
                return Err(format!("built-in program {program} has no uniform blocks"));
            }
            None => return Err(format!("program {program} does not exist")),
        };
        let blocks = p.compiled().uniform_blocks();
        let Some(index) = blocks.iter().position(|b| b.name == block) else {
            let names: Vec<&str> = blocks.iter().map(|b| b.name.as_str()).collect();
            return Err(format!("program {program} has no uniform block '{block}' (it has: {})", names.join(", ")));
        };
        p.block_bindings[index] = binding;
        Ok(())
    }

    /// `bind_uniform_buffer`.
    pub(super) fn bind_uniform_buffer(
        &mut self,
        binding: u32,
        buffer: u32,
        offset: u64,
        size: Option<u64>,
    ) -> Fallible {
        check_binding(binding)?;
        let slot = &mut self.state.uniform_buffers[binding as usize];
        if buffer == 0 {
            *slot = None;
            return Ok(());
        }
        if !self.buffers.contains_key(&buffer) {
            return Err(format!("buffer {buffer} does not exist"));
        }
        if size == Some(0) {
            return Err("a uniform buffer range of 0 bytes".into());
        }
        self.state.uniform_buffers[binding as usize] = Some(UniformBufferBinding { buffer, offset, size });
        Ok(())
    }

    /// Unbinds a deleted buffer from the uniform buffer bindings.
    pub(super) fn forget_uniform_buffer(&mut self, id: u32) {
        for slot in &mut self.state.uniform_buffers {
            if slot.is_some_and(|b| b.buffer == id) {
                *slot = None;
            }
        }
    }

    /// Sets program `p`'s uniform blocks in `uniforms` from the buffers bound at their
    /// bindings; returns those buffers.
    ///
    /// # Errors
    /// A block whose binding holds no buffer, or a range outside its buffer or shorter than
    /// the block, naming the block.
    pub(super) fn read_uniform_blocks(
        &self,
        label: &str,
        p: &GlslProgram,
        uniforms: &mut UniformValues,
    ) -> Fallible<Vec<u32>> {
        let program = p.compiled();
        let mut used = Vec::new();
        for (index, (block, &binding)) in program.uniform_blocks().iter().zip(&p.block_bindings).enumerate() {
            let what = || format!("{label}: uniform block '{}' (binding {binding})", block.name);
            let Some(bound) = self.state.uniform_buffers[binding as usize] else {
                return Err(format!("{}: no buffer is bound there (glBindBufferBase)", what()));
            };
            let b = self.buffers.get(&bound.buffer).expect("bindings are cleared when buffers are deleted");
            let end = bound.size.map_or(b.size, |size| bound.offset.saturating_add(size));
            if bound.offset > b.size || end > b.size {
                return Err(format!(
                    "{}: the range from byte {} ({} bytes) is outside buffer {} ({} bytes)",
                    what(),
                    bound.offset,
                    end.saturating_sub(bound.offset),
                    bound.buffer,
                    b.size
                ));
            }
            let bytes = self.device.buffer_data(b.storage).map_err(|e| e.to_string())?;
            program
                .set_uniform_block(uniforms, index, &bytes[bound.offset as usize..end as usize])
                .map_err(|e| format!("{}: {e}", what()))?;
            if !used.contains(&bound.buffer) {
                used.push(bound.buffer);
            }
        }
        Ok(used)
    }
}

fn check_binding(binding: u32) -> Fallible {
    if binding >= MAX_UNIFORM_BUFFER_BINDINGS {
        return Err(format!(
            "uniform buffer binding {binding} is out of range (0 to {})",
            MAX_UNIFORM_BUFFER_BINDINGS - 1
        ));
    }
    Ok(())
}
