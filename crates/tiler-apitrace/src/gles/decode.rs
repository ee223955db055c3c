//! Raw calls into [`Command`]s, tracking just enough state to resolve writes through mapped
//! buffers.
//!
//! apitrace cannot see what an application writes through the pointer `glMapBuffer*` returns;
//! at unmap (or flush) it writes a fake `memcpy(dest, src = blob, n)` with the bytes. Turning
//! that into "write these bytes at this offset of that buffer" needs which buffer the map
//! targeted (the binding of its target then: per context, the element-array binding per vertex
//! array object), the pointer it returned, and the mapped range's offset. [`Decoder`] tracks
//! those and nothing else.

use std::collections::HashMap;

use crate::wire::Call;

use super::args::Args;
use super::consts::{GL_ELEMENT_ARRAY_BUFFER, GL_FRONT_AND_BACK};
use super::{
    ClearValue, Command, DecodeError, DecodeErrorKind, GlEnum, GlesCall, Params, UniformValue, ignored, not_modelled,
};

type Result<T> = std::result::Result<T, DecodeErrorKind>;

/// One live mapping of a buffer.
#[derive(Clone, Copy, Debug)]
struct Mapping {
    buffer: u32,
    /// The address the map returned in the traced process.
    pointer: u64,
    /// The buffer offset `pointer` stands for.
    offset: u64,
    /// Mapped bytes, when known (the range's length, or the buffer's size).
    length: Option<u64>,
}

/// Buffer state of one context, as far as resolving mapped writes needs it.
#[derive(Clone, Debug, Default)]
struct ContextState {
    /// Buffer bindings other than `GL_ELEMENT_ARRAY_BUFFER`.
    bindings: HashMap<GlEnum, u32>,
    vertex_array: u32,
    /// `GL_ELEMENT_ARRAY_BUFFER` binding of each vertex array object (0: the default one).
    element_bindings: HashMap<u32, u32>,
    /// Sizes from `glBufferData`.
    sizes: HashMap<u32, u64>,
    mappings: Vec<Mapping>,
}

impl ContextState {
    fn bound(&self, target: GlEnum) -> u32 {
        let binding = if target == GL_ELEMENT_ARRAY_BUFFER {
            self.element_bindings.get(&self.vertex_array)
        } else {
            self.bindings.get(&target)
        };
        binding.copied().unwrap_or(0)
    }

    fn bind(&mut self, target: GlEnum, buffer: u32) {
        if target == GL_ELEMENT_ARRAY_BUFFER {
            self.element_bindings.insert(self.vertex_array, buffer);
        } else {
            self.bindings.insert(target, buffer);
        }
    }

    fn delete_buffers(&mut self, names: &[u32]) {
        for name in names.iter().filter(|&&name| name != 0) {
            for bound in self.bindings.values_mut().chain(self.element_bindings.values_mut()) {
                if bound == name {
                    *bound = 0;
                }
            }
            self.sizes.remove(name);
            self.mappings.retain(|m| m.buffer != *name);
        }
    }

    fn delete_vertex_arrays(&mut self, names: &[u32]) {
        for name in names.iter().filter(|&&name| name != 0) {
            self.element_bindings.remove(name);
            if self.vertex_array == *name {
                self.vertex_array = 0;
            }
        }
    }
}

/// Decodes raw calls into typed ones, in trace order.
#[derive(Clone, Debug, Default)]
pub struct Decoder {
    /// State by EGL context handle (0 before any `eglMakeCurrent`).
    contexts: HashMap<u64, ContextState>,
    current: u64,
}

impl Decoder {
    pub fn new() -> Decoder {
        Decoder::default()
    }

    /// Decodes one call; calls must come in the order the trace gives them.
    ///
    /// # Errors
    /// A call neither decoded nor on the ignore list, an argument missing or of the wrong type
    /// or range, a `memcpy` into no mapped buffer; the error names the call's number and name.
    pub fn decode(&mut self, call: Call) -> std::result::Result<GlesCall, DecodeError> {
        let number = call.number;
        let thread = call.thread;
        let fake = call.flags.fake;
        let mut args = Args { call };
        match self.command(&mut args) {
            Ok(command) => Ok(GlesCall { number, thread, fake, command }),
            Err(kind) => Err(DecodeError { call: number, function: args.call.sig.name.clone(), kind }),
        }
    }

    fn state(&mut self) -> &mut ContextState {
        self.contexts.entry(self.current).or_default()
    }

    fn command(&mut self, a: &mut Args) -> Result<Command> {
        let sig = a.call.sig.clone();
        let name = sig.name.as_str();
        if let Some(command) = self.buffer_command(name, a)? {
            return Ok(command);
        }
        if let Some(command) = decode_stateless(name, a)? {
            return Ok(command);
        }
        if let Some((function, reason)) = ignored(name) {
            return Ok(Command::Ignored { function, reason });
        }
        if let Some(feature) = not_modelled(name) {
            return Err(DecodeErrorKind::NotModelled { feature });
        }
        Err(DecodeErrorKind::Unknown)
    }

    /// Calls that read or change the tracked buffer and context state.
    fn buffer_command(&mut self, name: &str, a: &mut Args) -> Result<Option<Command>> {
        Ok(Some(match name {
            "glBindBuffer" => {
                let (target, buffer) = (a.enumeration(0)?, a.u32(1)?);
                self.state().bind(target, buffer);
                Command::BindBuffer { target, buffer }
            }
            "glBindBufferBase" | "glBindBufferRange" => {
                let (target, index, buffer) = (a.enumeration(0)?, a.u32(1)?, a.u32(2)?);
                let range = if name == "glBindBufferRange" { Some((a.u64(3)?, a.u64(4)?)) } else { None };
                // Both also bind the buffer to the generic binding point.
                self.state().bind(target, buffer);
                Command::BindBufferRange { target, index, buffer, range }
            }
            "glDeleteBuffers" => {
                let names = a.u32s(1)?;
                self.state().delete_buffers(&names);
                Command::DeleteBuffers { names }
            }
            "glBindVertexArray" | "glBindVertexArrayOES" => {
                let array = a.u32(0)?;
                self.state().vertex_array = array;
                Command::BindVertexArray { array }
            }
            "glDeleteVertexArrays" | "glDeleteVertexArraysOES" => {
                let names = a.u32s(1)?;
                self.state().delete_vertex_arrays(&names);
                Command::DeleteVertexArrays { names }
            }
            // Immutable storage (GL ES 3.2, EXT_buffer_storage) is storage as glBufferData
            // gives it; its flags (persistent, coherent mapping) change nothing tiler models.
            "glBufferData" | "glBufferStorage" | "glBufferStorageEXT" => {
                let (target, size) = (a.enumeration(0)?, a.u64(1)?);
                let usage = if name == "glBufferData" { a.enumeration(3)? } else { 0 };
                let data = a.memory(2)?;
                let state = self.state();
                let buffer = state.bound(target);
                state.sizes.insert(buffer, size);
                state.mappings.retain(|m| m.buffer != buffer);
                Command::BufferData { target, size, data, usage }
            }
            "glMapBufferOES" | "glMapBuffer" => {
                let (target, access) = (a.enumeration(0)?, a.enumeration(1)?);
                let pointer = a.ret_handle()?;
                self.map(target, 0, None, access, pointer)?
            }
            "glMapBufferRange" | "glMapBufferRangeEXT" => {
                let (target, offset, length) = (a.enumeration(0)?, a.u64(1)?, a.u64(2)?);
                let access = a.u32(3)?;
                let pointer = a.ret_handle()?;
                self.map(target, offset, Some(length), access, pointer)?
            }
            "glUnmapBuffer" | "glUnmapBufferOES" => {
                let target = a.enumeration(0)?;
                let state = self.state();
                let buffer = state.bound(target);
                state.mappings.retain(|m| m.buffer != buffer);
                Command::UnmapBuffer { target, buffer }
            }
            "memcpy" => {
                let dest = a.handle(0)?;
                let size = a.u64(2)?;
                let data = a.blob(1)?;
                if data.len() as u64 != size {
                    return Err(DecodeErrorKind::Count {
                        argument: "src".into(),
                        expected: size,
                        found: data.len() as u64,
                    });
                }
                self.buffer_write(dest, data)?
            }
            "eglMakeCurrent" => {
                let context = a.handle(3)?;
                self.current = context;
                Command::MakeCurrent { display: a.handle(0)?, draw: a.handle(1)?, read: a.handle(2)?, context }
            }
            "eglDestroyContext" => {
                let context = a.handle(1)?;
                if context != self.current {
                    self.contexts.remove(&context);
                }
                Command::DestroyContext { display: a.handle(0)?, context }
            }
            _ => return Ok(None),
        }))
    }

    fn map(&mut self, target: GlEnum, offset: u64, length: Option<u64>, access: u32, pointer: u64) -> Result<Command> {
        let state = self.state();
        let buffer = state.bound(target);
        if buffer == 0 {
            return Err(DecodeErrorKind::MapWithoutBuffer { target });
        }
        if pointer != 0 {
            let length = length.or_else(|| state.sizes.get(&buffer).copied());
            state.mappings.retain(|m| m.buffer != buffer);
            state.mappings.push(Mapping { buffer, pointer, offset, length });
        }
        Ok(Command::MapBuffer { target, buffer, offset, length, access, pointer })
    }

    /// A `memcpy` into a mapping: the buffer and offset it writes.
    fn buffer_write(&mut self, dest: u64, data: Vec<u8>) -> Result<Command> {
        let state = self.state();
        let size = data.len() as u64;
        let unmapped = || DecodeErrorKind::UnmappedWrite { dest, size };
        let mapping = state
            .mappings
            .iter()
            .filter(|m| m.pointer <= dest)
            .max_by_key(|m| m.pointer)
            .copied()
            .ok_or_else(unmapped)?;
        let into_mapping = dest - mapping.pointer;
        if let Some(length) = mapping.length
            && into_mapping.checked_add(size).is_none_or(|end| end > length)
        {
            return Err(unmapped());
        }
        let offset = mapping.offset.checked_add(into_mapping).ok_or_else(unmapped)?;
        if let Some(&buffer_size) = state.sizes.get(&mapping.buffer)
            && offset.checked_add(size).is_none_or(|end| end > buffer_size)
        {
            return Err(DecodeErrorKind::WriteOutsideBuffer { buffer: mapping.buffer, offset, size, buffer_size });
        }
        Ok(Command::BufferWrite { buffer: mapping.buffer, offset, data })
    }
}

/// Calls whose decoding needs no state.
fn decode_stateless(name: &str, a: &mut Args) -> Result<Option<Command>> {
    use Command as C;
    Ok(Some(match name {
        // Buffers.
        "glGenBuffers" => C::GenBuffers { names: a.u32s(1)? },
        "glBufferSubData" => {
            C::BufferSubData { target: a.enumeration(0)?, offset: a.u64(1)?, size: a.u64(2)?, data: a.memory(3)? }
        }
        "glCopyBufferSubData" => C::CopyBufferSubData {
            read_target: a.enumeration(0)?,
            write_target: a.enumeration(1)?,
            read_offset: a.u64(2)?,
            write_offset: a.u64(3)?,
            size: a.u64(4)?,
        },
        "glFlushMappedBufferRange" | "glFlushMappedBufferRangeEXT" => {
            C::FlushMappedBufferRange { target: a.enumeration(0)?, offset: a.u64(1)?, length: a.u64(2)? }
        }

        // Vertex arrays and attributes.
        "glGenVertexArrays" | "glGenVertexArraysOES" => C::GenVertexArrays { names: a.u32s(1)? },
        "glEnableVertexAttribArray" => C::EnableVertexAttribArray { index: a.u32(0)? },
        "glDisableVertexAttribArray" => C::DisableVertexAttribArray { index: a.u32(0)? },
        "glVertexAttribPointer" => C::VertexAttribPointer {
            index: a.u32(0)?,
            size: a.i32(1)?,
            kind: a.enumeration(2)?,
            normalized: a.bool(3)?,
            stride: a.i32(4)?,
            pointer: a.memory(5)?,
            integer: false,
        },
        "glVertexAttribIPointer" => C::VertexAttribPointer {
            index: a.u32(0)?,
            size: a.i32(1)?,
            kind: a.enumeration(2)?,
            normalized: false,
            stride: a.i32(3)?,
            pointer: a.memory(4)?,
            integer: true,
        },
        "glVertexAttribDivisor" | "glVertexAttribDivisorEXT" | "glVertexAttribDivisorANGLE" => {
            C::VertexAttribDivisor { index: a.u32(0)?, divisor: a.u32(1)? }
        }

        // Drawing.
        "glDrawArrays" => {
            C::DrawArrays { mode: a.enumeration(0)?, first: a.i32(1)?, count: a.i32(2)?, instance_count: 1 }
        }
        "glDrawArraysInstanced" | "glDrawArraysInstancedEXT" | "glDrawArraysInstancedANGLE" => {
            C::DrawArrays { mode: a.enumeration(0)?, first: a.i32(1)?, count: a.i32(2)?, instance_count: a.i32(3)? }
        }
        "glDrawElements" => draw_elements(a, Elements::PLAIN)?,
        "glDrawElementsInstanced" | "glDrawElementsInstancedEXT" | "glDrawElementsInstancedANGLE" => {
            draw_elements(a, Elements { instanced: true, ..Elements::PLAIN })?
        }
        "glDrawRangeElements" => draw_elements(a, Elements { range: true, ..Elements::PLAIN })?,
        "glDrawElementsBaseVertex" | "glDrawElementsBaseVertexOES" | "glDrawElementsBaseVertexEXT" => {
            draw_elements(a, Elements { base_vertex: true, ..Elements::PLAIN })?
        }
        "glDrawRangeElementsBaseVertex" | "glDrawRangeElementsBaseVertexOES" | "glDrawRangeElementsBaseVertexEXT" => {
            draw_elements(a, Elements { range: true, base_vertex: true, ..Elements::PLAIN })?
        }
        "glDrawElementsInstancedBaseVertex"
        | "glDrawElementsInstancedBaseVertexOES"
        | "glDrawElementsInstancedBaseVertexEXT" => {
            draw_elements(a, Elements { instanced: true, base_vertex: true, ..Elements::PLAIN })?
        }

        // Textures and samplers.
        "glGenTextures" => C::GenTextures { names: a.u32s(1)? },
        "glDeleteTextures" => C::DeleteTextures { names: a.u32s(1)? },
        "glActiveTexture" => C::ActiveTexture { unit: a.enumeration(0)? },
        "glBindTexture" => C::BindTexture { target: a.enumeration(0)?, texture: a.u32(1)? },
        "glTexImage2D" => C::TexImage2D {
            target: a.enumeration(0)?,
            level: a.i32(1)?,
            internal_format: a.enumeration(2)?,
            width: a.i32(3)?,
            height: a.i32(4)?,
            border: a.i32(5)?,
            format: a.enumeration(6)?,
            kind: a.enumeration(7)?,
            pixels: a.memory(8)?,
        },
        "glTexSubImage2D" => C::TexSubImage2D {
            target: a.enumeration(0)?,
            level: a.i32(1)?,
            x_offset: a.i32(2)?,
            y_offset: a.i32(3)?,
            width: a.i32(4)?,
            height: a.i32(5)?,
            format: a.enumeration(6)?,
            kind: a.enumeration(7)?,
            pixels: a.memory(8)?,
        },
        "glCompressedTexImage2D" => C::CompressedTexImage2D {
            target: a.enumeration(0)?,
            level: a.i32(1)?,
            internal_format: a.enumeration(2)?,
            width: a.i32(3)?,
            height: a.i32(4)?,
            border: a.i32(5)?,
            image_size: a.i32(6)?,
            data: a.memory(7)?,
        },
        "glCompressedTexSubImage2D" => C::CompressedTexSubImage2D {
            target: a.enumeration(0)?,
            level: a.i32(1)?,
            x_offset: a.i32(2)?,
            y_offset: a.i32(3)?,
            width: a.i32(4)?,
            height: a.i32(5)?,
            format: a.enumeration(6)?,
            image_size: a.i32(7)?,
            data: a.memory(8)?,
        },
        "glCopyTexImage2D" => C::CopyTexImage2D {
            target: a.enumeration(0)?,
            level: a.i32(1)?,
            internal_format: a.enumeration(2)?,
            x: a.i32(3)?,
            y: a.i32(4)?,
            width: a.i32(5)?,
            height: a.i32(6)?,
            border: a.i32(7)?,
        },
        "glCopyTexSubImage2D" => C::CopyTexSubImage2D {
            target: a.enumeration(0)?,
            level: a.i32(1)?,
            x_offset: a.i32(2)?,
            y_offset: a.i32(3)?,
            x: a.i32(4)?,
            y: a.i32(5)?,
            width: a.i32(6)?,
            height: a.i32(7)?,
        },
        "glTexStorage2D" | "glTexStorage2DEXT" => C::TexStorage2D {
            target: a.enumeration(0)?,
            levels: a.i32(1)?,
            internal_format: a.enumeration(2)?,
            width: a.i32(3)?,
            height: a.i32(4)?,
        },
        "glTexImage3D" | "glTexImage3DOES" => C::TexImage3D {
            target: a.enumeration(0)?,
            level: a.i32(1)?,
            internal_format: a.enumeration(2)?,
            width: a.i32(3)?,
            height: a.i32(4)?,
            depth: a.i32(5)?,
            border: a.i32(6)?,
            format: a.enumeration(7)?,
            kind: a.enumeration(8)?,
            pixels: a.memory(9)?,
        },
        "glTexSubImage3D" | "glTexSubImage3DOES" => C::TexSubImage3D {
            target: a.enumeration(0)?,
            level: a.i32(1)?,
            x_offset: a.i32(2)?,
            y_offset: a.i32(3)?,
            z_offset: a.i32(4)?,
            width: a.i32(5)?,
            height: a.i32(6)?,
            depth: a.i32(7)?,
            format: a.enumeration(8)?,
            kind: a.enumeration(9)?,
            pixels: a.memory(10)?,
        },
        "glTexStorage3D" => C::TexStorage3D {
            target: a.enumeration(0)?,
            levels: a.i32(1)?,
            internal_format: a.enumeration(2)?,
            width: a.i32(3)?,
            height: a.i32(4)?,
            depth: a.i32(5)?,
        },
        "glCopyTexSubImage3D" | "glCopyTexSubImage3DOES" => C::CopyTexSubImage3D {
            target: a.enumeration(0)?,
            level: a.i32(1)?,
            x_offset: a.i32(2)?,
            y_offset: a.i32(3)?,
            z_offset: a.i32(4)?,
            x: a.i32(5)?,
            y: a.i32(6)?,
            width: a.i32(7)?,
            height: a.i32(8)?,
        },
        "glFramebufferTextureLayer" => C::FramebufferTextureLayer {
            target: a.enumeration(0)?,
            attachment: a.enumeration(1)?,
            texture: a.u32(2)?,
            level: a.i32(3)?,
            layer: a.i32(4)?,
        },
        "glTexParameteri" | "glTexParameterf" | "glTexParameteriv" | "glTexParameterfv" => {
            C::TexParameter { target: a.enumeration(0)?, pname: a.enumeration(1)?, params: params(name, a, 2)? }
        }
        "glGenerateMipmap" => C::GenerateMipmap { target: a.enumeration(0)? },
        "glPixelStorei" => C::PixelStore { pname: a.enumeration(0)?, param: a.i32(1)? },
        "glTransformFeedbackVaryings" => {
            C::TransformFeedbackVaryings { program: a.u32(0)?, varyings: a.strings(2)?, mode: a.enumeration(3)? }
        }
        "glBeginTransformFeedback" => C::BeginTransformFeedback { mode: a.enumeration(0)? },
        "glEndTransformFeedback" => C::EndTransformFeedback,
        "glPauseTransformFeedback" => C::PauseTransformFeedback,
        "glResumeTransformFeedback" => C::ResumeTransformFeedback,
        "glGenTransformFeedbacks" => C::GenTransformFeedbacks { names: a.u32s(1)? },
        "glDeleteTransformFeedbacks" => C::DeleteTransformFeedbacks { names: a.u32s(1)? },
        "glBindTransformFeedback" => C::BindTransformFeedback { target: a.enumeration(0)?, id: a.u32(1)? },
        "glGenSamplers" => C::GenSamplers { names: a.u32s(1)? },
        "glDeleteSamplers" => C::DeleteSamplers { names: a.u32s(1)? },
        "glBindSampler" => C::BindSampler { unit: a.u32(0)?, sampler: a.u32(1)? },
        "glSamplerParameteri" | "glSamplerParameterf" | "glSamplerParameteriv" | "glSamplerParameterfv" => {
            C::SamplerParameter { sampler: a.u32(0)?, pname: a.enumeration(1)?, params: params(name, a, 2)? }
        }

        // Framebuffers and renderbuffers.
        "glGenFramebuffers" => C::GenFramebuffers { names: a.u32s(1)? },
        "glDeleteFramebuffers" => C::DeleteFramebuffers { names: a.u32s(1)? },
        "glBindFramebuffer" => C::BindFramebuffer { target: a.enumeration(0)?, framebuffer: a.u32(1)? },
        "glFramebufferTexture2D" => C::FramebufferTexture2D {
            target: a.enumeration(0)?,
            attachment: a.enumeration(1)?,
            texture_target: a.enumeration(2)?,
            texture: a.u32(3)?,
            level: a.i32(4)?,
            samples: 0,
        },
        "glFramebufferTexture2DMultisampleEXT" | "glFramebufferTexture2DMultisampleIMG" => C::FramebufferTexture2D {
            target: a.enumeration(0)?,
            attachment: a.enumeration(1)?,
            texture_target: a.enumeration(2)?,
            texture: a.u32(3)?,
            level: a.i32(4)?,
            samples: a.i32(5)?,
        },
        "glFramebufferRenderbuffer" => C::FramebufferRenderbuffer {
            target: a.enumeration(0)?,
            attachment: a.enumeration(1)?,
            renderbuffer_target: a.enumeration(2)?,
            renderbuffer: a.u32(3)?,
        },
        "glGenRenderbuffers" => C::GenRenderbuffers { names: a.u32s(1)? },
        "glDeleteRenderbuffers" => C::DeleteRenderbuffers { names: a.u32s(1)? },
        "glBindRenderbuffer" => C::BindRenderbuffer { target: a.enumeration(0)?, renderbuffer: a.u32(1)? },
        "glRenderbufferStorage" => C::RenderbufferStorage {
            target: a.enumeration(0)?,
            samples: 0,
            internal_format: a.enumeration(1)?,
            width: a.i32(2)?,
            height: a.i32(3)?,
        },
        "glRenderbufferStorageMultisample"
        | "glRenderbufferStorageMultisampleEXT"
        | "glRenderbufferStorageMultisampleIMG" => C::RenderbufferStorage {
            target: a.enumeration(0)?,
            samples: a.i32(1)?,
            internal_format: a.enumeration(2)?,
            width: a.i32(3)?,
            height: a.i32(4)?,
        },
        "glInvalidateFramebuffer" | "glDiscardFramebufferEXT" => {
            C::InvalidateFramebuffer { target: a.enumeration(0)?, attachments: a.u32s(2)?, region: None }
        }
        "glInvalidateSubFramebuffer" => C::InvalidateFramebuffer {
            target: a.enumeration(0)?,
            attachments: a.u32s(2)?,
            region: Some([a.i32(3)?, a.i32(4)?, a.i32(5)?, a.i32(6)?]),
        },
        "glBlitFramebuffer" => C::BlitFramebuffer {
            src: [a.i32(0)?, a.i32(1)?, a.i32(2)?, a.i32(3)?],
            dst: [a.i32(4)?, a.i32(5)?, a.i32(6)?, a.i32(7)?],
            mask: a.u32(8)?,
            filter: a.enumeration(9)?,
        },
        "glDrawBuffers" | "glDrawBuffersEXT" => C::DrawBuffers { buffers: a.u32s(1)? },
        "glReadBuffer" => C::ReadBuffer { source: a.enumeration(0)? },
        "glReadPixels" => C::ReadPixels {
            x: a.i32(0)?,
            y: a.i32(1)?,
            width: a.i32(2)?,
            height: a.i32(3)?,
            format: a.enumeration(4)?,
            kind: a.enumeration(5)?,
            pixels: a.memory(6)?,
        },

        // Shaders and programs.
        "glCreateShader" => C::CreateShader { kind: a.enumeration(0)?, shader: a.ret_u32()? },
        "glShaderSource" => C::ShaderSource { shader: a.u32(0)?, source: a.strings(2)?.concat() },
        "glCompileShader" => C::CompileShader { shader: a.u32(0)? },
        "glDeleteShader" => C::DeleteShader { shader: a.u32(0)? },
        "glShaderBinary" => C::ShaderBinary { shaders: a.u32s(1)?, format: a.enumeration(2)?, binary: a.memory(3)? },
        "glCreateProgram" => C::CreateProgram { program: a.ret_u32()? },
        "glAttachShader" => C::AttachShader { program: a.u32(0)?, shader: a.u32(1)? },
        "glDetachShader" => C::DetachShader { program: a.u32(0)?, shader: a.u32(1)? },
        "glBindAttribLocation" => C::BindAttribLocation { program: a.u32(0)?, index: a.u32(1)?, name: a.string(2)? },
        "glLinkProgram" => C::LinkProgram { program: a.u32(0)? },
        "glUseProgram" => C::UseProgram { program: a.u32(0)? },
        "glDeleteProgram" => C::DeleteProgram { program: a.u32(0)? },
        "glGetUniformLocation" => C::UniformLocation { program: a.u32(0)?, name: a.string(1)?, location: a.ret_i32()? },
        "glGetAttribLocation" => C::AttribLocation { program: a.u32(0)?, name: a.string(1)?, location: a.ret_i32()? },
        "glGetUniformBlockIndex" => {
            C::UniformBlockIndex { program: a.u32(0)?, name: a.string(1)?, index: a.ret_u32()? }
        }
        "glUniformBlockBinding" => {
            C::UniformBlockBinding { program: a.u32(0)?, block_index: a.u32(1)?, binding: a.u32(2)? }
        }

        // Fixed-function state.
        "glEnable" => C::Enable { cap: a.enumeration(0)? },
        "glDisable" => C::Disable { cap: a.enumeration(0)? },
        "glViewport" => C::Viewport { x: a.i32(0)?, y: a.i32(1)?, width: a.i32(2)?, height: a.i32(3)? },
        "glScissor" => C::Scissor { x: a.i32(0)?, y: a.i32(1)?, width: a.i32(2)?, height: a.i32(3)? },
        "glDepthFunc" => C::DepthFunc { func: a.enumeration(0)? },
        "glDepthMask" => C::DepthMask { write: a.bool(0)? },
        // Desktop OpenGL's double forms, the same state (a desktop context drawing with the
        // calls GLES has, as Qt Quick's does).
        "glDepthRangef" | "glDepthRange" => C::DepthRange { near: a.f32(0)?, far: a.f32(1)? },
        "glCullFace" => C::CullFace { mode: a.enumeration(0)? },
        "glFrontFace" => C::FrontFace { mode: a.enumeration(0)? },
        "glColorMask" => C::ColorMask { mask: [a.bool(0)?, a.bool(1)?, a.bool(2)?, a.bool(3)?] },
        "glBlendFunc" => {
            let (src, dst) = (a.enumeration(0)?, a.enumeration(1)?);
            C::BlendFunc { src_rgb: src, dst_rgb: dst, src_alpha: src, dst_alpha: dst }
        }
        "glBlendFuncSeparate" => C::BlendFunc {
            src_rgb: a.enumeration(0)?,
            dst_rgb: a.enumeration(1)?,
            src_alpha: a.enumeration(2)?,
            dst_alpha: a.enumeration(3)?,
        },
        "glBlendEquation" => {
            let mode = a.enumeration(0)?;
            C::BlendEquation { rgb: mode, alpha: mode }
        }
        "glBlendEquationSeparate" => C::BlendEquation { rgb: a.enumeration(0)?, alpha: a.enumeration(1)? },
        "glBlendColor" => C::BlendColor { color: [a.f32(0)?, a.f32(1)?, a.f32(2)?, a.f32(3)?] },
        "glStencilFunc" => {
            C::StencilFunc { face: GL_FRONT_AND_BACK, func: a.enumeration(0)?, reference: a.i32(1)?, mask: a.u32(2)? }
        }
        "glStencilFuncSeparate" => {
            C::StencilFunc { face: a.enumeration(0)?, func: a.enumeration(1)?, reference: a.i32(2)?, mask: a.u32(3)? }
        }
        "glStencilOp" => C::StencilOp {
            face: GL_FRONT_AND_BACK,
            stencil_fail: a.enumeration(0)?,
            depth_fail: a.enumeration(1)?,
            pass: a.enumeration(2)?,
        },
        "glStencilOpSeparate" => C::StencilOp {
            face: a.enumeration(0)?,
            stencil_fail: a.enumeration(1)?,
            depth_fail: a.enumeration(2)?,
            pass: a.enumeration(3)?,
        },
        "glStencilMask" => C::StencilMask { face: GL_FRONT_AND_BACK, mask: a.u32(0)? },
        "glStencilMaskSeparate" => C::StencilMask { face: a.enumeration(0)?, mask: a.u32(1)? },
        "glPolygonOffset" => C::PolygonOffset { factor: a.f32(0)?, units: a.f32(1)? },
        "glLineWidth" => C::LineWidth { width: a.f32(0)? },
        "glSampleCoverage" => C::SampleCoverage { value: a.f32(0)?, invert: a.bool(1)? },
        "glHint" => C::Hint { target: a.enumeration(0)?, mode: a.enumeration(1)? },

        // Clears, flushes, queries.
        "glClear" => C::Clear { mask: a.u32(0)? },
        "glClearColor" => C::ClearColor { color: [a.f32(0)?, a.f32(1)?, a.f32(2)?, a.f32(3)?] },
        "glClearDepthf" | "glClearDepth" => C::ClearDepth { depth: a.f32(0)? },
        "glClearStencil" => C::ClearStencil { stencil: a.i32(0)? },
        "glClearBufferfv" => C::ClearBuffer {
            buffer: a.enumeration(0)?,
            draw_buffer: a.i32(1)?,
            value: ClearValue::Float(pad(a.f32s(2)?)),
        },
        "glClearBufferiv" => C::ClearBuffer {
            buffer: a.enumeration(0)?,
            draw_buffer: a.i32(1)?,
            value: ClearValue::Int(pad(a.i32s(2)?)),
        },
        "glClearBufferuiv" => C::ClearBuffer {
            buffer: a.enumeration(0)?,
            draw_buffer: a.i32(1)?,
            value: ClearValue::UInt(pad(a.u32s(2)?)),
        },
        "glClearBufferfi" => C::ClearBuffer {
            buffer: a.enumeration(0)?,
            draw_buffer: a.i32(1)?,
            value: ClearValue::DepthStencil { depth: a.f32(2)?, stencil: a.i32(3)? },
        },
        "glFlush" => C::Flush,
        // Fences: the CPU waits for the GPU to reach one (`ClientWaitSync`); see tiler-gl's
        // `fence_sync` for what that costs.
        "glFinish" => C::Finish,
        "glFenceSync" => C::FenceSync { sync: a.ret_handle()? },
        "glClientWaitSync" => C::ClientWaitSync { sync: a.handle(0)?, flags: a.u32(1)?, timeout: a.u64(2)? },
        "glDeleteSync" => C::DeleteSync { sync: a.handle(0)? },
        "glGenQueries" | "glGenQueriesEXT" => C::GenQueries { names: a.u32s(1)? },
        "glDeleteQueries" | "glDeleteQueriesEXT" => C::DeleteQueries { names: a.u32s(1)? },
        "glBeginQuery" | "glBeginQueryEXT" => C::BeginQuery { target: a.enumeration(0)?, query: a.u32(1)? },
        "glEndQuery" | "glEndQueryEXT" => C::EndQuery { target: a.enumeration(0)? },
        "glQueryCounterEXT" => C::QueryCounter { query: a.u32(0)? },
        "glGetQueryObjectuiv"
        | "glGetQueryObjectuivEXT"
        | "glGetQueryObjectivEXT"
        | "glGetQueryObjectui64vEXT"
        | "glGetQueryObjecti64vEXT" => C::GetQueryResult { query: a.u32(0)?, pname: a.enumeration(1)? },
        "glStartTilingQCOM" => {
            C::StartTiling { x: a.u32(0)?, y: a.u32(1)?, width: a.u32(2)?, height: a.u32(3)?, preserve_mask: a.u32(4)? }
        }
        "glEndTilingQCOM" => C::EndTiling { preserve_mask: a.u32(0)? },

        // EGL.
        "eglCreateWindowSurface" | "eglCreatePlatformWindowSurface" | "eglCreatePlatformWindowSurfaceEXT" => {
            C::CreateWindowSurface {
                display: a.handle(0)?,
                config: a.handle(1)?,
                window: a.handle(2)?,
                attribs: a.i64s(3)?,
                surface: a.ret_handle()?,
            }
        }
        "eglCreatePbufferSurface" => C::CreatePbufferSurface {
            display: a.handle(0)?,
            config: a.handle(1)?,
            attribs: a.i64s(2)?,
            surface: a.ret_handle()?,
        },
        "eglDestroySurface" => C::DestroySurface { display: a.handle(0)?, surface: a.handle(1)? },
        "eglSurfaceAttrib" => {
            C::SurfaceAttrib { display: a.handle(0)?, surface: a.handle(1)?, attribute: a.i64(2)?, value: a.i64(3)? }
        }
        "eglCreateContext" => C::CreateContext {
            display: a.handle(0)?,
            config: a.handle(1)?,
            share_context: a.handle(2)?,
            attribs: a.i64s(3)?,
            context: a.ret_handle()?,
        },
        "eglSwapBuffers" | "eglSwapBuffersWithDamageKHR" | "eglSwapBuffersWithDamageEXT" => {
            C::SwapBuffers { display: a.handle(0)?, surface: a.handle(1)? }
        }

        _ => {
            if let Some(command) = uniform(name, a)? {
                return Ok(Some(command));
            }
            return vertex_attrib(name, a);
        }
    }))
}

/// The first four values, missing ones 0 (`glClearBuffer*v` reads as many as the buffer has).
/// Which arguments a `glDraw*Elements*` call has beyond `mode, count, type, indices`.
#[derive(Clone, Copy)]
struct Elements {
    /// `start, end` after `mode` (`glDrawRangeElements*`).
    range: bool,
    /// `instancecount` after `indices`.
    instanced: bool,
    /// `basevertex` last.
    base_vertex: bool,
}

impl Elements {
    const PLAIN: Elements = Elements { range: false, instanced: false, base_vertex: false };
}

/// Every `glDraw*Elements*` form as one [`Command::DrawElements`].
fn draw_elements(a: &mut Args, form: Elements) -> Result<Command> {
    let first = if form.range { 3 } else { 1 };
    let after = first + 3;
    let instance_count = if form.instanced { a.i32(after)? } else { 1 };
    let base_vertex = if form.base_vertex { a.i32(after + form.instanced as usize)? } else { 0 };
    Ok(Command::DrawElements {
        mode: a.enumeration(0)?,
        range: if form.range { Some((a.u32(1)?, a.u32(2)?)) } else { None },
        count: a.i32(first)?,
        kind: a.enumeration(first + 1)?,
        indices: a.memory(first + 2)?,
        instance_count,
        base_vertex,
    })
}

fn pad<T: Copy + Default>(values: Vec<T>) -> [T; 4] {
    let mut out = [T::default(); 4];
    for (slot, value) in out.iter_mut().zip(values) {
        *slot = value;
    }
    out
}

/// `gl{Tex,Sampler}Parameter{i,f,iv,fv}`'s value at `index`.
fn params(name: &str, a: &Args, index: usize) -> Result<Params> {
    Ok(if name.ends_with("iv") {
        Params::Int(a.i32s(index)?)
    } else if name.ends_with("fv") {
        Params::Float(a.f32s(index)?)
    } else if name.ends_with('i') {
        Params::Int(vec![a.i32(index)?])
    } else {
        Params::Float(vec![a.f32(index)?])
    })
}

/// `glUniform{1,2,3,4}{f,i,ui}[v]` and `glUniformMatrix{2,3,4}[x{2,3,4}]fv`, from the name.
fn uniform(name: &str, a: &Args) -> Result<Option<Command>> {
    let Some(rest) = name.strip_prefix("glUniform") else {
        return Ok(None);
    };
    let location = |a: &Args| a.i32(0);
    if let Some(shape) = rest.strip_prefix("Matrix").and_then(|r| r.strip_suffix("fv")) {
        let (columns, rows) = match shape.as_bytes() {
            [c] => (*c, *c),
            [c, b'x', r] => (*c, *r),
            _ => return Ok(None),
        };
        let (Some(columns), Some(rows)) = (dimension(columns), dimension(rows)) else {
            return Ok(None);
        };
        let count = a.u32(1)?;
        let values = a.f32s(3)?;
        check_count(a, 3, count, columns as u64 * rows as u64, values.len())?;
        return Ok(Some(Command::Uniform {
            location: location(a)?,
            value: UniformValue::Matrix { columns, rows, transpose: a.bool(2)?, values },
        }));
    }
    let Some(components) = rest.bytes().next().and_then(dimension_from_1) else {
        return Ok(None);
    };
    let (kind, vector) = match &rest[1..] {
        "f" => ("f", false),
        "i" => ("i", false),
        "ui" => ("ui", false),
        "fv" => ("f", true),
        "iv" => ("i", true),
        "uiv" => ("ui", true),
        _ => return Ok(None),
    };
    let n = components as usize;
    let value = if vector {
        let count = a.u32(1)?;
        let value = match kind {
            "f" => UniformValue::Float { components, values: a.f32s(2)? },
            "i" => UniformValue::Int { components, values: a.i32s(2)? },
            _ => UniformValue::UInt { components, values: a.u32s(2)? },
        };
        let len = match &value {
            UniformValue::Float { values, .. } => values.len(),
            UniformValue::Int { values, .. } => values.len(),
            UniformValue::UInt { values, .. } => values.len(),
            UniformValue::Matrix { values, .. } => values.len(),
        };
        check_count(a, 2, count, components as u64, len)?;
        value
    } else {
        match kind {
            "f" => UniformValue::Float { components, values: (1..=n).map(|i| a.f32(i)).collect::<Result<_>>()? },
            "i" => UniformValue::Int { components, values: (1..=n).map(|i| a.i32(i)).collect::<Result<_>>()? },
            _ => UniformValue::UInt { components, values: (1..=n).map(|i| a.u32(i)).collect::<Result<_>>()? },
        }
    };
    Ok(Some(Command::Uniform { location: location(a)?, value }))
}

/// `2`, `3` or `4` as a matrix dimension.
fn dimension(digit: u8) -> Option<u8> {
    matches!(digit, b'2'..=b'4').then(|| digit - b'0')
}

/// `1` to `4` as a vector size.
fn dimension_from_1(digit: u8) -> Option<u8> {
    matches!(digit, b'1'..=b'4').then(|| digit - b'0')
}

/// A `glUniform*v` array (argument `index`) holds `count` elements of `per_element` values.
fn check_count(a: &Args, index: usize, count: u32, per_element: u64, found: usize) -> Result<()> {
    let expected = count as u64 * per_element;
    if found as u64 != expected {
        return Err(DecodeErrorKind::Count {
            argument: a.call.sig.arg_names.get(index).cloned().unwrap_or_default(),
            expected,
            found: found as u64,
        });
    }
    Ok(())
}

/// `glVertexAttrib{1,2,3,4}f[v]`.
fn vertex_attrib(name: &str, a: &Args) -> Result<Option<Command>> {
    let Some(rest) = name.strip_prefix("glVertexAttrib") else {
        return Ok(None);
    };
    let Some(n) = rest.bytes().next().and_then(dimension_from_1) else {
        return Ok(None);
    };
    let given = match &rest[1..] {
        "f" => (1..=n as usize).map(|i| a.f32(i)).collect::<Result<Vec<f32>>>()?,
        "fv" => a.f32s(1)?,
        _ => return Ok(None),
    };
    if given.len() != n as usize {
        return Err(DecodeErrorKind::Count { argument: "v".into(), expected: n as u64, found: given.len() as u64 });
    }
    // GL fills the components not given from (0, 0, 0, 1).
    let mut value = [0.0, 0.0, 0.0, 1.0];
    value[..given.len()].copy_from_slice(&given);
    Ok(Some(Command::VertexAttrib { index: a.u32(0)?, value }))
}
