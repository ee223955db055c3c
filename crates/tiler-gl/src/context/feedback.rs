//! Transform feedback (GL ES 3.0 §2.15) and `GL_RASTERIZER_DISCARD` (§3.1).
//!
//! A GLSL program names the vertex outputs it captures (`transform_feedback_varyings`,
//! applied at link by the translator); `bind_transform_feedback_buffer` binds buffer ranges to
//! bindings 0–3; between `begin_transform_feedback` and `end_transform_feedback` (outside a
//! pause) every `draw_arrays` runs the program's vertex shader on the CPU through
//! `tiler-glsl`'s executor — the same code, uniforms and textures as the draw's — for the
//! vertices of its primitives taken apart as GL specifies (a strip's odd triangle as
//! `i + 1, i, i + 2`, keeping its winding; a fan's as `0, i, i + 1`; a loop's closing line),
//! and writes the outputs' 32-bit words into the bound buffers, one after the other from
//! where the last draw stopped: interleaved into binding 0, or output `k` into binding `k`.
//! Later draws read the buffers as vertex data. Indexed draws while capturing are refused
//! (GL ES 3.0 allows only `glDrawArrays*`), as is a draw whose primitives do not fit in the
//! bound ranges (GL's `INVALID_OPERATION`).
//!
//! The buffers are written when the draw is called; a pending draw of the open pass that
//! reads one keeps its old contents (the buffer gets new storage, as `buffer_sub_data`
//! gives it, not counted as a copy: the GPU writes it in command order).
//!
//! What it costs: the words written, `vertices captured × bytes per vertex`, are the
//! frame's `transform_feedback_write` (the context ledger: transform feedback runs in the
//! geometry phase, before and outside any render pass's tiles). With the rasterizer on, the
//! draw also goes into the pass as any draw, whose vertex fetch and shading the core counts
//! (a GPU shades once for both). With `GL_RASTERIZER_DISCARD` the draw ends there: no pass
//! gets it, and the attributes it read are counted in the context ledger's `vertex_fetch` as
//! `vertices captured × Σ attribute sizes` (without a vertex cache). Clears are discarded
//! with the rasterizer, as in GL.

use std::collections::HashMap;

use tiler::{Category, VertexAttribute, VertexInput, VertexInputState};

use super::draw::vertex_format;
use super::glsl::ProgramDraw;
use super::{AttribSource, Context, Fallible, ProgramObject};
use crate::call::{FeedbackMode, Mode};
use crate::report::FlushCause;

/// Transform feedback buffer bindings (`GL_MAX_TRANSFORM_FEEDBACK_SEPARATE_ATTRIBS`, GL ES
/// 3.0's minimum).
pub(crate) const MAX_FEEDBACK_BUFFERS: u32 = 4;
/// Components one output may have in separate mode, and all outputs together interleaved
/// (GL ES 3.0's minimums).
const MAX_SEPARATE_COMPONENTS: usize = 4;
const MAX_INTERLEAVED_COMPONENTS: usize = 64;

/// A buffer range transform feedback writes into.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FeedbackBinding {
    buffer: u32,
    offset: u64,
    size: Option<u64>,
}

/// Transform feedback between begin and end.
#[derive(Clone, Copy, Debug)]
struct Active {
    mode: FeedbackMode,
    paused: bool,
    /// The program in use at begin (GL forbids changing it while active).
    program: u32,
    /// Bytes written into each binding since begin.
    written: [u64; MAX_FEEDBACK_BUFFERS as usize],
}

/// The context's transform feedback state (the translator swaps transform feedback objects'
/// bindings in and out).
#[derive(Debug, Default)]
pub(crate) struct FeedbackState {
    bindings: [Option<FeedbackBinding>; MAX_FEEDBACK_BUFFERS as usize],
    active: Option<Active>,
}

impl FeedbackState {
    /// Between begin and end, paused or not.
    pub fn active(&self) -> bool {
        self.active.is_some()
    }

    /// Unbinds a deleted buffer.
    pub fn forget_buffer(&mut self, buffer: u32) {
        for b in &mut self.bindings {
            if b.is_some_and(|b| b.buffer == buffer) {
                *b = None;
            }
        }
    }

    /// Active and not paused: draws capture.
    pub fn capturing(&self) -> bool {
        self.active.is_some_and(|a| !a.paused)
    }
}

/// The vertices a draw of `mode` hands transform feedback: its primitives, each whole, in
/// order (GL ES 3.0 §2.15.2).
fn decompose(mode: Mode, first: u32, count: u32) -> Vec<u32> {
    let mut v = Vec::new();
    match mode {
        Mode::Points => v.extend(0..count),
        Mode::Lines => v.extend(0..count / 2 * 2),
        Mode::Triangles => v.extend(0..count / 3 * 3),
        Mode::LineStrip | Mode::LineLoop if count >= 2 => {
            for i in 0..count - 1 {
                v.extend([i, i + 1]);
            }
            if mode == Mode::LineLoop {
                v.extend([count - 1, 0]);
            }
        }
        Mode::TriangleStrip if count >= 3 => {
            for i in 0..count - 2 {
                v.extend(if i.is_multiple_of(2) { [i, i + 1, i + 2] } else { [i + 1, i, i + 2] });
            }
        }
        Mode::TriangleFan if count >= 3 => {
            for i in 1..count - 1 {
                v.extend([0, i, i + 1]);
            }
        }
        _ => {}
    }
    v.iter_mut().for_each(|i| *i += first);
    v
}

impl Context {
    /// `transform_feedback_varyings`: checked against the program's vertex shader now.
    pub(crate) fn transform_feedback_varyings(
        &mut self,
        program: u32,
        varyings: Vec<String>,
        separate: bool,
    ) -> Fallible {
        let p = match self.programs.get_mut(&program) {
            Some(ProgramObject::Glsl(p)) => p,
            Some(ProgramObject::Builtin { .. }) => {
                return Err(format!("program {program} is built in: only GLSL programs have transform feedback"));
            }
            None => return Err(format!("program {program} does not exist")),
        };
        let found = p.compiled().feedback_varyings(&varyings).map_err(|e| format!("program {program}: {e}"))?;
        if separate {
            if found.len() > MAX_FEEDBACK_BUFFERS as usize {
                return Err(format!(
                    "{} separate transform feedback varyings: at most {MAX_FEEDBACK_BUFFERS}",
                    found.len()
                ));
            }
            if let Some(v) = found.iter().find(|v| v.components() > MAX_SEPARATE_COMPONENTS) {
                return Err(format!(
                    "transform feedback varying '{}' has {} components: at most {MAX_SEPARATE_COMPONENTS} in \
                     separate mode",
                    v.name,
                    v.components()
                ));
            }
        } else {
            let total: usize = found.iter().map(|v| v.components()).sum();
            if total > MAX_INTERLEAVED_COMPONENTS {
                return Err(format!(
                    "{total} interleaved transform feedback components: at most {MAX_INTERLEAVED_COMPONENTS}"
                ));
            }
        }
        p.feedback = (!varyings.is_empty()).then_some((varyings, separate));
        Ok(())
    }

    /// `bind_transform_feedback_buffer`.
    pub(crate) fn bind_transform_feedback_buffer(
        &mut self,
        binding: u32,
        buffer: u32,
        offset: u64,
        size: Option<u64>,
    ) -> Fallible {
        if binding >= MAX_FEEDBACK_BUFFERS {
            return Err(format!(
                "transform feedback binding {binding} is out of range (0 to {})",
                MAX_FEEDBACK_BUFFERS - 1
            ));
        }
        if self.feedback.active.is_some() {
            return Err("binding a transform feedback buffer while transform feedback is active (a GL error)".into());
        }
        if buffer == 0 {
            self.feedback.bindings[binding as usize] = None;
            return Ok(());
        }
        if !self.buffers.contains_key(&buffer) {
            return Err(format!("buffer {buffer} does not exist"));
        }
        if !offset.is_multiple_of(4) || size.is_some_and(|s| s == 0 || !s.is_multiple_of(4)) {
            return Err(format!(
                "transform feedback range at offset {offset}, size {size:?}: both must be multiples of 4 (and the size \
                 above 0)"
            ));
        }
        self.feedback.bindings[binding as usize] = Some(FeedbackBinding { buffer, offset, size });
        Ok(())
    }

    /// `begin_transform_feedback`: the program in use must capture something, into bound
    /// buffers.
    pub(crate) fn begin_transform_feedback(&mut self, mode: FeedbackMode) -> Fallible {
        if self.feedback.active.is_some() {
            return Err("transform feedback is already active".into());
        }
        let program = self.state.program;
        let (varyings, separate) = self.feedback_varyings(program)?;
        let needed = if separate { varyings } else { 1 };
        if let Some(b) = (0..needed).find(|&b| self.feedback.bindings[b].is_none()) {
            return Err(format!("transform feedback binding {b} has no buffer"));
        }
        self.feedback.active =
            Some(Active { mode, paused: false, program, written: [0; MAX_FEEDBACK_BUFFERS as usize] });
        Ok(())
    }

    pub(crate) fn end_transform_feedback(&mut self) -> Fallible {
        self.feedback.active.take().map(|_| ()).ok_or_else(|| "transform feedback is not active".into())
    }

    /// `pause_transform_feedback` (`pause`) and `resume_transform_feedback`.
    pub(crate) fn pause_transform_feedback(&mut self, pause: bool) -> Fallible {
        match &mut self.feedback.active {
            Some(a) if a.paused != pause => {
                a.paused = pause;
                Ok(())
            }
            Some(_) => Err(format!("transform feedback is {}", if pause { "paused already" } else { "not paused" })),
            None => Err("transform feedback is not active".into()),
        }
    }

    /// The number of outputs program `program` captures and whether separately.
    fn feedback_varyings(&self, program: u32) -> Fallible<(usize, bool)> {
        match self.programs.get(&program) {
            Some(ProgramObject::Glsl(p)) => match &p.feedback {
                Some((names, separate)) => Ok((names.len(), *separate)),
                None => Err(format!(
                    "program {program} captures no vertex outputs (glTransformFeedbackVaryings before its link)"
                )),
            },
            Some(ProgramObject::Builtin { .. }) => Err(format!("program {program} is built in: no transform feedback")),
            None => Err("no program is in use".into()),
        }
    }

    /// A draw while transform feedback is active and not paused: its vertices shaded and
    /// written into the bound buffers (see the module docs).
    pub(crate) fn capture_feedback(&mut self, mode: Mode, first: u32, count: u32, instances: u32) -> Fallible {
        let Some(active) = self.feedback.active.filter(|a| !a.paused) else {
            return Ok(());
        };
        if FeedbackMode::of(mode) != active.mode {
            return Err(format!(
                "a {mode:?} draw while transform feedback captures {:?}: GL ES 3.0 needs the same primitives",
                active.mode
            ));
        }
        if self.state.program != active.program {
            return Err(format!(
                "program {} is in use, but transform feedback began with program {} (GL forbids the change)",
                self.state.program, active.program
            ));
        }
        let Some(ProgramObject::Glsl(p)) = self.programs.get(&active.program) else {
            return Err(format!("program {} was deleted while transform feedback is active", active.program));
        };
        let (names, separate) = p.feedback.clone().expect("checked at begin");
        let varyings =
            p.compiled().feedback_varyings(&names).map_err(|e| format!("program {}: {e}", active.program))?;
        let order = decompose(mode, first, count);
        let vertices = order.len() as u64 * instances as u64;
        if vertices == 0 {
            return Ok(());
        }

        // Room in every binding, before anything is shaded.
        let words: Vec<u64> = varyings.iter().map(|v| v.components() as u64).collect();
        let per_vertex: Vec<u64> =
            if separate { words.iter().map(|w| w * 4).collect() } else { vec![words.iter().sum::<u64>() * 4] };
        let mut targets = Vec::new();
        for (b, bytes) in per_vertex.iter().enumerate() {
            let binding =
                self.feedback.bindings[b].ok_or_else(|| format!("transform feedback binding {b} has no buffer"))?;
            let buffer = self
                .buffers
                .get(&binding.buffer)
                .ok_or_else(|| format!("transform feedback binding {b}: buffer {} was deleted", binding.buffer))?;
            let room = buffer.size.saturating_sub(binding.offset);
            let room = binding.size.map_or(room, |s| s.min(room));
            let needed = vertices * bytes;
            let at = active.written[b];
            if at + needed > room {
                return Err(format!(
                    "transform feedback binding {b} (buffer {}, {room} bytes from offset {}) has {} bytes left, but \
                     the draw captures {vertices} vertices of {bytes} bytes (GL_INVALID_OPERATION)",
                    binding.buffer,
                    binding.offset,
                    room.saturating_sub(at)
                ));
            }
            targets.push((binding.buffer, binding.offset + at, needed));
        }

        // The program as the draw would run it: uniforms, blocks, textures, generic values.
        let program = self.draw_program()?;
        if self
            .pass
            .as_ref()
            .is_some_and(|p| p.has_work() && program.textures.iter().any(|t| p.targets.images().any(|i| i == t.image)))
        {
            self.flush_open_pass(FlushCause::SampleAttachment)?;
        }
        let ProgramDraw::Glsl { program: compiled, uniforms, generic, cubes, .. } = &program.source else {
            unreachable!("a GLSL program")
        };
        let units = self.texture_units(&program.textures, cubes, &mut HashMap::new(), &mut HashMap::new())?;
        let (mut shader, _) = tiler_glsl::shaders(compiled, uniforms, &units, 1);

        // The attributes, fetched as the core fetches them.
        struct Source {
            location: usize,
            format: tiler::VertexFormat,
            stride: u64,
            bytes: Vec<u8>,
            divisor: u32,
        }
        let mut sources = Vec::new();
        let mut input_state = VertexInputState::default();
        let last = order.iter().copied().max().unwrap_or(0) as u64;
        for (location, name) in &program.attributes {
            let attrib = &self.state.attribs[*location as usize];
            let Some((source, size, component, normalized, stride, integer)) = attrib.source.clone() else {
                return Err(format!("attribute {location} ({name}) is enabled without a pointer"));
            };
            let format = vertex_format(size, component, normalized, integer)?;
            let stride = if stride == 0 { format.size_bytes() } else { stride } as u64;
            let bytes = match &source {
                AttribSource::Buffer { buffer, offset } => {
                    let b = self
                        .buffers
                        .get(buffer)
                        .ok_or_else(|| format!("attribute {location} reads buffer {buffer}, which was deleted"))?;
                    let all = self.device_buffer_bytes(b.storage, b.size)?;
                    all.get(*offset as usize..).unwrap_or_default().to_vec()
                }
                AttribSource::Client { data } => data.to_vec(),
            };
            let divisor = attrib.divisor;
            let elements = (instances as u64 - 1).checked_div(divisor as u64).map_or(last + 1, |e| e + 1);
            let end = (elements - 1) * stride + format.size_bytes() as u64;
            if end > bytes.len() as u64 {
                return Err(format!(
                    "attribute {location} ({name}) of element {} ends at byte {end} of its data, which has {}",
                    elements - 1,
                    bytes.len()
                ));
            }
            input_state.attributes.push(VertexAttribute { location: *location, binding: 0, format, offset: 0 });
            sources.push(Source { location: *location as usize, format, stride, bytes, divisor });
        }
        shader.set_integer_attributes(&input_state, 0);

        // Shade, instance by instance, and lay the words out per binding.
        let mut words_out: Vec<Vec<u32>> = vec![Vec::new(); varyings.len()];
        let mut inputs = Vec::with_capacity(order.len());
        for instance in 0..instances {
            shader.set_instance(instance);
            inputs.clear();
            for &index in &order {
                let mut input = VertexInput { vertex_index: index, ..VertexInput::default() };
                for (location, value) in generic {
                    input.attributes[*location as usize] = glam::Vec4::from_array(*value);
                }
                for s in &sources {
                    let element = instance.checked_div(s.divisor).unwrap_or(index) as u64;
                    let at = (element * s.stride) as usize;
                    input.attributes[s.location] =
                        glam::Vec4::from_array(tiler::read_attribute(s.format, &s.bytes[at..]));
                }
                inputs.push(input);
            }
            shader.shade_feedback(&inputs, &varyings, &mut words_out);
        }
        let mut buffers: Vec<Vec<u8>> = Vec::new();
        if separate {
            buffers.extend(words_out.iter().map(|w| w.iter().flat_map(|x| x.to_le_bytes()).collect()));
        } else {
            let mut bytes = Vec::with_capacity(targets[0].2 as usize);
            for v in 0..vertices as usize {
                for (k, w) in words_out.iter().enumerate() {
                    let n = words[k] as usize;
                    bytes.extend(w[v * n..(v + 1) * n].iter().flat_map(|x| x.to_le_bytes()));
                }
            }
            buffers.push(bytes);
        }

        let mut written = 0;
        for (b, ((buffer, offset, needed), bytes)) in targets.into_iter().zip(buffers).enumerate() {
            debug_assert_eq!(bytes.len() as u64, needed);
            self.feedback_write(buffer, offset, &bytes)?;
            written += needed;
            if let Some(a) = &mut self.feedback.active {
                a.written[b] += needed;
            }
        }
        self.frame.context_ledger.add(Category::TransformFeedbackWrite, written);
        if self.state.rasterizer_discard {
            let fetched: u64 = sources.iter().map(|s| s.format.size_bytes() as u64).sum();
            self.frame.context_ledger.add(Category::VertexFetch, vertices * fetched);
        }
        Ok(())
    }

    /// Writes transform feedback's output into buffer `id` at `offset`: in place, or into new
    /// storage when a draw of the open pass reads the old one (which keeps it).
    fn feedback_write(&mut self, id: u32, offset: u64, bytes: &[u8]) -> Fallible {
        let b = self.buffers.get(&id).ok_or_else(|| format!("buffer {id} does not exist"))?;
        let (storage, size) = (b.storage, b.size);
        let in_open_pass = self.pass.as_ref().is_some_and(|p| p.buffers_used.contains(&storage));
        if in_open_pass {
            let mut contents = self.device_buffer_bytes(storage, size)?;
            contents[offset as usize..offset as usize + bytes.len()].copy_from_slice(bytes);
            let new = self.alloc_buffer(&contents)?;
            self.retire_buffer(storage, size);
            let b = self.buffers.get_mut(&id).expect("checked");
            b.storage = new;
            b.last_use = None;
        } else {
            self.device.write_buffer(storage, offset, bytes).map_err(|e| e.to_string())?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_fans_and_loops_come_apart_as_gl_takes_them() {
        assert_eq!(decompose(Mode::TriangleStrip, 10, 5), [10, 11, 12, 12, 11, 13, 12, 13, 14]);
        assert_eq!(decompose(Mode::TriangleFan, 0, 5), [0, 1, 2, 0, 2, 3, 0, 3, 4]);
        assert_eq!(decompose(Mode::LineLoop, 0, 3), [0, 1, 1, 2, 2, 0]);
        assert_eq!(decompose(Mode::LineStrip, 2, 3), [2, 3, 3, 4]);
        assert_eq!(decompose(Mode::Triangles, 0, 7), [0, 1, 2, 3, 4, 5]);
        assert_eq!(decompose(Mode::Lines, 1, 3), [1, 2]);
        assert_eq!(decompose(Mode::TriangleStrip, 0, 2), Vec::<u32>::new());
    }
}
