//! Several GL contexts sharing their objects (`create_context`, `make_current`,
//! `destroy_context`): EGL gives each context its own GL state and lets contexts share
//! objects (EGL 1.5 §3.7.1); a toolkit renders offscreen on one context and draws on the
//! window on another.
//!
//! The current context's state is where it always is (`Context::state`, the bound
//! framebuffers, the active query, transform feedback, the program in use deleted, the
//! default vertex array while another is bound); the other contexts' is kept here, and
//! `make_current` swaps it in. Objects are not duplicated: every context names the same
//! buffers, textures, renderbuffers, programs, framebuffers, vertex arrays and queries (GL
//! keeps framebuffers, vertex arrays and queries per context; a caller that makes them in
//! one context and uses them in another is not refused here — the capture translator gives
//! each context's its own names).
//!
//! A switch is not a flush (drivers queue both contexts' commands for the one GPU): the open
//! pass ends only when the context made current has another draw framebuffer bound, as
//! `bind_framebuffer` would end it.

use super::{Context, Fallible, GlState, feedback, vertex_array::VertexArray};
use crate::call::FramebufferTarget;

/// The GL state of a context that is not current.
#[derive(Debug)]
pub(crate) struct ContextState {
    state: GlState,
    draw_framebuffer: u32,
    read_framebuffer: u32,
    active_query: Option<u32>,
    feedback: feedback::FeedbackState,
    /// The program in use, deleted (`Context::deleted_program`).
    deleted_program: Option<u32>,
    /// The context's default vertex array, while another one is bound (the default array is
    /// each context's own: `Context::vertex_arrays` holds the current context's under 0).
    default_vertex_array: Option<VertexArray>,
}

impl ContextState {
    fn new(width: u32, height: u32) -> ContextState {
        ContextState {
            state: GlState::new(width, height),
            draw_framebuffer: 0,
            read_framebuffer: 0,
            active_query: None,
            feedback: feedback::FeedbackState::default(),
            deleted_program: None,
            default_vertex_array: None,
        }
    }
}

impl Context {
    /// `create_context`.
    pub(super) fn create_context(&mut self, id: u32) -> Fallible {
        if id == self.current_context || self.other_contexts.contains_key(&id) {
            return Err(format!("context {id} already exists"));
        }
        self.other_contexts.insert(id, ContextState::new(self.config.width, self.config.height));
        Ok(())
    }

    /// `destroy_context`.
    pub(super) fn destroy_context(&mut self, id: u32) -> Fallible {
        if id == self.current_context {
            return Err(format!("context {id} is current: make another one current before destroying it"));
        }
        let gone = self.other_contexts.remove(&id).ok_or_else(|| format!("context {id} does not exist"))?;
        if gone.active_query.is_some() || gone.feedback.active() {
            // Its query or transform feedback would never end; GL ends them with the context,
            // a replay would have to guess what they counted.
            return Err(format!("context {id} is destroyed with a query or transform feedback active"));
        }
        // The vertex array it had bound is an object like the others, deleted by name.
        if gone.state.vertex_array != 0 {
            let array = VertexArray { attribs: gone.state.attribs, index_buffer: gone.state.index_buffer };
            self.vertex_arrays.insert(gone.state.vertex_array, array);
        }
        // The program it used, deleted, goes unless another context uses it.
        if let Some(doomed) = gone.deleted_program {
            self.drop_deleted_program(doomed);
        }
        Ok(())
    }

    /// `make_current`: the current context's state is kept, `id`'s is put in its place.
    pub(super) fn make_current(&mut self, id: u32) -> Fallible {
        if id == self.current_context {
            return Ok(());
        }
        if !self.other_contexts.contains_key(&id) {
            return Err(format!("context {id} does not exist"));
        }
        if self.tiling.is_some() {
            return Err("another context cannot be made current inside a tiled-rendering region: call end_tiling \
                        first"
                .into());
        }
        let next = self.other_contexts.remove(&id).expect("checked");
        // The draw framebuffer changes as `bind_framebuffer` changes it: the open pass ends if
        // it is another framebuffer's. Its framebuffers exist: a deleted framebuffer is
        // unbound from every context (`forget_framebuffer_in_contexts`).
        let draw_framebuffer = self.draw_framebuffer;
        self.bind_framebuffer(FramebufferTarget::Draw, next.draw_framebuffer)?;
        let previous = ContextState {
            state: std::mem::replace(&mut self.state, next.state),
            draw_framebuffer,
            read_framebuffer: std::mem::replace(&mut self.read_framebuffer, next.read_framebuffer),
            active_query: std::mem::replace(&mut self.active_query, next.active_query),
            feedback: std::mem::replace(&mut self.feedback, next.feedback),
            deleted_program: std::mem::replace(&mut self.deleted_program, next.deleted_program),
            default_vertex_array: self.vertex_arrays.remove(&0),
        };
        if let Some(array) = next.default_vertex_array {
            self.vertex_arrays.insert(0, array);
        }
        let old = std::mem::replace(&mut self.current_context, id);
        self.other_contexts.insert(old, previous);
        Ok(())
    }

    /// Program `doomed`, deleted, is no longer used by the current context: it goes, or, if
    /// another context uses it, goes when that one stops using it.
    pub(super) fn drop_deleted_program(&mut self, doomed: u32) {
        match self.other_contexts.values_mut().find(|c| c.state.program == doomed) {
            Some(user) => user.deleted_program = Some(doomed),
            None => {
                self.programs.remove(&doomed);
            }
        }
    }

    /// Unbinds texture `id`, being deleted, from the other contexts' units (the current one's
    /// are unbound where it is deleted).
    pub(super) fn forget_texture_in_contexts(&mut self, id: u32) {
        for c in self.other_contexts.values_mut() {
            let units = c.state.textures.iter_mut().chain(&mut c.state.cube_textures);
            for unit in units.chain(c.state.layered_textures.iter_mut().flatten()) {
                if *unit == id {
                    *unit = 0;
                }
            }
        }
    }

    /// Detaches buffer `id`, being deleted, from the other contexts' vertex attributes,
    /// uniform buffer bindings and transform feedback.
    pub(super) fn forget_buffer_in_contexts(&mut self, id: u32) {
        for c in self.other_contexts.values_mut() {
            let arrays = std::iter::once((&mut c.state.attribs, &mut c.state.index_buffer))
                .chain(c.default_vertex_array.as_mut().map(|a| (&mut a.attribs, &mut a.index_buffer)));
            for (attribs, index_buffer) in arrays {
                VertexArray::forget_buffer(attribs, index_buffer, id);
            }
            for binding in &mut c.state.uniform_buffers {
                if binding.as_ref().is_some_and(|b| b.buffer == id) {
                    *binding = None;
                }
            }
            c.feedback.forget_buffer(id);
        }
    }

    /// Unbinds framebuffer `id`, being deleted, from the other contexts.
    pub(super) fn forget_framebuffer_in_contexts(&mut self, id: u32) {
        for c in self.other_contexts.values_mut() {
            if c.draw_framebuffer == id {
                c.draw_framebuffer = 0;
            }
            if c.read_framebuffer == id {
                c.read_framebuffer = 0;
            }
        }
    }
}
