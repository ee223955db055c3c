//! Instanced draws (`draw_arrays_instanced`, `draw_elements_instanced`, attribute divisors).
//!
//! tiler's core draws one instance per draw, so the context expands an instanced draw into
//! one gathered draw per instance, all recorded at the same call. Each instance's draw reads
//! the per-vertex attributes as a plain draw does, and its per-instance attributes (divisor
//! `d`: element `instance / d`) are read by the driver and handed to the vertex shader as
//! constants, as disabled attributes' generic values are; GLSL's `gl_InstanceID` is the
//! instance's number.
//!
//! What the ledger counts is what a GPU pays:
//! - per-vertex attributes and indices: fetched for every instance, through the vertex
//!   cache, as each instance's vertices are shaded again (a GPU's post-transform cache does
//!   not span instances);
//! - a per-instance attribute: its bytes once per instance (`vertex_fetch`, in the pass's
//!   extra traffic), not once per vertex — the vertex cache keeps it while the instance's
//!   vertices are shaded. Its exact bytes, not whole cache lines: consecutive instances read
//!   consecutive elements, so the lines a GPU fills hold the following instances' elements.
//!
//! The report shows one draw per instance (its counters count `draws` likewise), each at the
//! instanced call.

use tiler::VertexFormat;

/// The most instances one call draws: each becomes a gathered draw, so the count bounds the
/// memory a call can take (a draw record per instance).
pub const MAX_INSTANCES: u32 = 1 << 16;

use super::draw::vertex_format;
use super::glsl::{DrawProgram, ProgramDraw};
use super::{AttribSource, Context, Fallible};

/// A per-instance attribute of a draw, checked.
#[derive(Clone, Debug)]
pub(crate) struct InstancedAttribute {
    index: u32,
    format: VertexFormat,
    stride: u32,
    divisor: u32,
    source: AttribSource,
}

/// Reads each instance's per-instance attributes from the bytes the draw's instances read
/// (from the attribute's offset on), taken once at the draw.
pub(crate) struct InstanceReader {
    attributes: Vec<(InstancedAttribute, Vec<u8>)>,
}

impl Context {
    /// Checks per-instance attribute `index` (`name`) of a draw of `program`, `instances`
    /// times: a GLSL program, a pointer, the last instance's element inside its data. Returns
    /// it with the bytes its instances read.
    pub(super) fn instanced_attribute(
        &self,
        program: &DrawProgram,
        index: u32,
        name: &str,
        instances: u32,
    ) -> Fallible<(InstancedAttribute, Vec<u8>)> {
        let attrib = &self.state.attribs[index as usize];
        let label = &program.label;
        if let ProgramDraw::Builtin { kind, .. } = &program.source {
            return Err(format!(
                "built-in program '{}' reads attribute {index} per instance (divisor {}): only GLSL programs take \
                 per-instance attributes",
                kind.name(),
                attrib.divisor
            ));
        }
        let Some((source, size, component, normalized, stride, integer)) = attrib.source.clone() else {
            return Err(format!("program '{label}' reads attribute {index} ({name}), which has no pointer"));
        };
        let format = vertex_format(size, component, normalized, integer)?;
        let stride = if stride == 0 { format.size_bytes() } else { stride };
        let divisor = attrib.divisor;
        let elements = instances.div_ceil(divisor) as u64;
        let end = match elements {
            0 => 0,
            n => (n - 1) * stride as u64 + format.size_bytes() as u64,
        };
        let (offset, bytes) = match &source {
            AttribSource::Buffer { buffer, offset } => {
                let b = self
                    .buffers
                    .get(buffer)
                    .ok_or_else(|| format!("attribute {index} ({name}) reads buffer {buffer}, which was deleted"))?;
                let bytes = self.device.buffer_data(b.storage).map_err(|e| e.to_string())?;
                (*offset, &bytes[..b.size as usize])
            }
            AttribSource::Client { data } => (0, &data[..]),
        };
        let available = bytes.len() as u64;
        if offset.checked_add(end).is_none_or(|e| e > available) {
            return Err(format!(
                "attribute {index} ({name}), divisor {divisor}: the {elements} elements of {instances} instances \
                 from byte {offset} need {end} bytes, past the end of its data ({available} bytes)"
            ));
        }
        let data = bytes[offset as usize..(offset + end) as usize].to_vec();
        Ok((InstancedAttribute { index, format, stride, divisor, source }, data))
    }

    /// The buffers per-instance attributes read, marked used in frame `frame`.
    pub(super) fn instanced_buffers_used(&mut self, reader: &InstanceReader, frame: u32) -> Vec<tiler::BufferId> {
        let mut used = Vec::new();
        for (a, _) in &reader.attributes {
            if let AttribSource::Buffer { buffer, .. } = &a.source {
                let b = self.buffers.get_mut(buffer).expect("checked by instanced_attribute");
                b.last_use = Some(frame);
                used.push(b.storage);
            }
        }
        used
    }
}

impl InstanceReader {
    pub fn new(attributes: Vec<(InstancedAttribute, Vec<u8>)>) -> InstanceReader {
        InstanceReader { attributes }
    }

    /// The program of instance `instance` — its per-instance attributes as generic values, its
    /// `gl_InstanceID` — and the attribute bytes it fetched.
    pub fn instance(&self, mut program: ProgramDraw, instance: u32) -> (ProgramDraw, u64) {
        let mut bytes = 0;
        if let ProgramDraw::Glsl { generic, instance: id, .. } = &mut program {
            *id = instance;
            for (a, data) in &self.attributes {
                let start = (instance / a.divisor) as usize * a.stride as usize;
                generic.push((a.index, tiler::read_attribute(a.format, &data[start..])));
                bytes += a.format.size_bytes() as u64;
            }
        }
        (program, bytes)
    }
}
