//! Vertex array objects (GL ES 3.0 §2.10, `OES_vertex_array_object`): each holds, per
//! attribute, whether it is enabled, its pointer and its divisor, and the index buffer
//! binding. Array 0 is the default one; it always exists.
//!
//! The bound array's state is the context's `GlState::attribs` and `index_buffer`, which every
//! attribute call and every draw reads and writes; binding another array swaps it with the one
//! kept in `Context::vertex_arrays`. Generic values (`vertex_attrib`) are the context's.
//!
//! Deleting a buffer detaches it from every array, bound or not: GL ES 3.0 keeps a deleted
//! buffer alive while an unbound array still points at it, but a replay that drew from it
//! would read storage the context has already retired, so such a draw is an error naming the
//! attribute instead (see `draw.rs`).

use super::{Attrib, AttribSource, Context, Fallible, MAX_VERTEX_ATTRIBS};

/// The state of a vertex array object that is not bound.
#[derive(Clone, Debug)]
pub(crate) struct VertexArray {
    pub attribs: Vec<Attrib>,
    pub index_buffer: u32,
}

impl VertexArray {
    fn new() -> VertexArray {
        VertexArray { attribs: vec![Attrib::DEFAULT; MAX_VERTEX_ATTRIBS as usize], index_buffer: 0 }
    }
}

impl Context {
    fn vertex_array_exists(&self, id: u32) -> bool {
        id == 0 || id == self.state.vertex_array || self.vertex_arrays.contains_key(&id)
    }

    /// `create_vertex_array`.
    pub(super) fn create_vertex_array(&mut self, id: u32) -> Fallible {
        if self.vertex_array_exists(id) {
            return Err(super::name_taken("vertex array", id));
        }
        self.vertex_arrays.insert(id, VertexArray::new());
        Ok(())
    }

    /// `bind_vertex_array`: the bound array's state goes back to the map, `id`'s comes out.
    pub(super) fn bind_vertex_array(&mut self, id: u32) -> Fallible {
        if id == self.state.vertex_array {
            return Ok(());
        }
        let mut next = match self.vertex_arrays.remove(&id) {
            Some(array) => array,
            // The default array is created with the context and kept in the map while unbound.
            None if id == 0 => VertexArray::new(),
            None => return Err(format!("vertex array {id} does not exist")),
        };
        std::mem::swap(&mut next.attribs, &mut self.state.attribs);
        std::mem::swap(&mut next.index_buffer, &mut self.state.index_buffer);
        let previous = std::mem::replace(&mut self.state.vertex_array, id);
        self.vertex_arrays.insert(previous, next);
        Ok(())
    }

    /// `delete_vertex_array`: deleting the bound array binds the default one (GL ES 3.0
    /// §2.10); the default array cannot be deleted.
    pub(super) fn delete_vertex_array(&mut self, id: u32) -> Fallible {
        if id == 0 || !self.vertex_array_exists(id) {
            return Err(format!("vertex array {id} does not exist"));
        }
        if self.state.vertex_array == id {
            self.bind_vertex_array(0)?;
        }
        self.vertex_arrays.remove(&id);
        Ok(())
    }

    /// Detaches buffer `id`, being deleted, from every vertex array (the other contexts'
    /// bound and default arrays too).
    pub(super) fn forget_buffer_in_vertex_arrays(&mut self, id: u32) {
        let bound = std::iter::once((&mut self.state.attribs, &mut self.state.index_buffer));
        let unbound = self.vertex_arrays.values_mut().map(|a| (&mut a.attribs, &mut a.index_buffer));
        for (attribs, index_buffer) in bound.chain(unbound) {
            VertexArray::forget_buffer(attribs, index_buffer, id);
        }
        self.forget_buffer_in_contexts(id);
    }
}

impl VertexArray {
    /// Detaches buffer `id` from an array's attributes and index buffer.
    pub(super) fn forget_buffer(attribs: &mut [Attrib], index_buffer: &mut u32, id: u32) {
        for attrib in attribs.iter_mut() {
            if let Some((AttribSource::Buffer { buffer, .. }, ..)) = &attrib.source
                && *buffer == id
            {
                attrib.source = None;
            }
        }
        if *index_buffer == id {
            *index_buffer = 0;
        }
    }
}
