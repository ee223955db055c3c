//! Transform feedback calls of a capture: `glTransformFeedbackVaryings` (kept with the
//! program and applied at its link), `glBindBufferBase`/`Range(GL_TRANSFORM_FEEDBACK_BUFFER)`,
//! `glBegin`/`End`/`Pause`/`ResumeTransformFeedback` as the context's calls, and transform
//! feedback objects (`glGen`/`Bind`/`DeleteTransformFeedbacks`), kept here: each object's
//! buffer bindings are handed to the context when it is bound. Binding another object while
//! one is active (paused) is refused.

use std::collections::HashMap;

use tiler_apitrace::gles::{Command, GlEnum};

use super::{Fallible, Translator};
use crate::call::{Call, FeedbackMode};

pub(super) const GL_TRANSFORM_FEEDBACK_BUFFER: GlEnum = 0x8c8e;
const GL_TRANSFORM_FEEDBACK: GlEnum = 0x8e22;
const GL_INTERLEAVED_ATTRIBS: GlEnum = 0x8c8c;
const GL_SEPARATE_ATTRIBS: GlEnum = 0x8c8d;
/// The context's transform feedback bindings.
const BINDINGS: usize = 4;

/// A buffer range bound for transform feedback: the buffer's name, offset and size.
type Range = (u32, u64, Option<u64>);

/// Transform feedback objects and which is bound.
#[derive(Debug, Default)]
pub(super) struct FeedbackBindings {
    /// The bound object (0: the default one).
    bound: u32,
    /// Each object's bindings (the default one's under 0).
    objects: HashMap<u32, [Option<Range>; BINDINGS]>,
    /// Transform feedback is active on the bound object (paused or not).
    active: bool,
}

impl FeedbackBindings {
    /// Forgets deleted buffer `name` (GL unbinds it from the bound object's bindings; the
    /// others let go of it too here).
    pub fn forget_buffer(&mut self, name: u32) {
        for bindings in self.objects.values_mut() {
            for b in bindings.iter_mut() {
                if b.is_some_and(|(n, ..)| n == name) {
                    *b = None;
                }
            }
        }
    }
}

impl Translator {
    /// Translates `command` if it is a transform feedback call; `false` leaves it to the
    /// other rules.
    pub(super) fn feedback_command(&mut self, command: &Command) -> Fallible<bool> {
        use Command as C;
        match command {
            C::TransformFeedbackVaryings { program, varyings, mode } => {
                let separate = match *mode {
                    GL_INTERLEAVED_ATTRIBS => false,
                    GL_SEPARATE_ATTRIBS => true,
                    m => return Err(format!("transform feedback buffer mode {m:#06x} is not a GL one")),
                };
                self.program(*program)?.feedback = Some((varyings.clone(), separate));
            }
            C::BeginTransformFeedback { mode } => {
                let mode = match *mode {
                    0 => FeedbackMode::Points,
                    1 => FeedbackMode::Lines,
                    4 => FeedbackMode::Triangles,
                    m => {
                        return Err(format!(
                            "transform feedback primitive mode {m:#06x} is not GL_POINTS, LINES or TRIANGLES"
                        ));
                    }
                };
                self.emit(Call::BeginTransformFeedback { mode })?;
                self.bindings.feedback.active = true;
            }
            C::EndTransformFeedback => {
                self.emit(Call::EndTransformFeedback)?;
                self.bindings.feedback.active = false;
            }
            C::PauseTransformFeedback => {
                self.emit(Call::PauseTransformFeedback)?;
            }
            C::ResumeTransformFeedback => {
                self.emit(Call::ResumeTransformFeedback)?;
            }
            C::GenTransformFeedbacks { names } => {
                for &name in names {
                    self.bindings.feedback.objects.entry(name).or_default();
                }
            }
            C::DeleteTransformFeedbacks { names } => {
                for &name in names.iter().filter(|&&n| n != 0) {
                    if self.bindings.feedback.bound == name {
                        if self.bindings.feedback.active {
                            return Err(format!("deleting transform feedback object {name} while it is active"));
                        }
                        self.bind_feedback_object(0)?;
                    }
                    self.bindings.feedback.objects.remove(&name);
                }
            }
            C::BindTransformFeedback { target, id } => {
                if *target != GL_TRANSFORM_FEEDBACK {
                    return Err(format!("transform feedback target {target:#06x} is not GL_TRANSFORM_FEEDBACK"));
                }
                if *id != 0 && !self.bindings.feedback.objects.contains_key(id) {
                    return Err(format!("transform feedback object {id} was not made by glGenTransformFeedbacks"));
                }
                if *id != self.bindings.feedback.bound {
                    if self.bindings.feedback.active {
                        return Err(format!(
                            "binding transform feedback object {id} while object {} is active (paused): not supported",
                            self.bindings.feedback.bound
                        ));
                    }
                    self.bind_feedback_object(*id)?;
                }
            }
            C::BindBufferRange { target: GL_TRANSFORM_FEEDBACK_BUFFER, index, buffer, range } => {
                let index = *index as usize;
                if index >= BINDINGS {
                    return Err(format!("transform feedback binding {index} is out of range (0 to {})", BINDINGS - 1));
                }
                if *buffer != 0 {
                    self.objects()?.buffers.entry(*buffer).or_insert(None);
                }
                self.bindings.other_buffers.insert(GL_TRANSFORM_FEEDBACK_BUFFER, *buffer);
                let (offset, size) = match range {
                    Some((offset, size)) => (*offset, Some(*size)),
                    None => (0, None),
                };
                let bound = self.bindings.feedback.bound;
                let range = (*buffer != 0).then_some((*buffer, offset, size));
                self.bindings.feedback.objects.entry(bound).or_default()[index] = range;
                self.emit_feedback_binding(index as u32, range)?;
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    /// Binds transform feedback object `id`: the context gets its buffer bindings.
    fn bind_feedback_object(&mut self, id: u32) -> Fallible {
        self.bindings.feedback.bound = id;
        let bindings = self.bindings.feedback.objects.get(&id).copied().unwrap_or_default();
        for (index, range) in (0..).zip(bindings) {
            self.emit_feedback_binding(index, range)?;
        }
        Ok(())
    }

    /// Hands the context binding `index`: a buffer without storage yet is bound when it
    /// gets some.
    fn emit_feedback_binding(&mut self, index: u32, range: Option<Range>) -> Fallible {
        let (buffer, offset, size) = match range {
            Some((name, offset, size)) => (self.buffer_id(name)?.unwrap_or(0), offset, size),
            None => (0, 0, None),
        };
        self.emit(Call::BindTransformFeedbackBuffer { binding: index, buffer, offset, size })?;
        Ok(())
    }

    /// Binds buffer `name`, which just got storage `id`, where the bound transform feedback
    /// object has it.
    pub(super) fn bind_new_feedback_buffer(&mut self, name: u32, id: u32) -> Fallible {
        let bound = self.bindings.feedback.bound;
        let bindings = self.bindings.feedback.objects.get(&bound).copied().unwrap_or_default();
        for (index, range) in (0..).zip(bindings) {
            if let Some((_, offset, size)) = range.filter(|r| r.0 == name) {
                self.emit(Call::BindTransformFeedbackBuffer { binding: index, buffer: id, offset, size })?;
            }
        }
        Ok(())
    }
}
