//! Draw translation: a GL draw and the state bound when it is called (program, vertex
//! attributes, index buffer, viewport, scissor, depth, stencil, blend, cull, masks) become a
//! draw gathered into the open pass — tiler's `PipelineDesc`, vertex and index bindings and
//! the pixels it may touch — after every check its frame data must pass. The driver's own
//! draws (blits and copies as textured rectangles) are gathered here too. Nothing is rendered
//! until the pass is submitted (`submit.rs`); which pass a draw lands in, and its load and
//! store ops, are `pass.rs`'s.

use tiler::{
    BlendComponent, BlendState, BufferId, ColorTargetState, ColorWrites, CullMode, DepthBias, DepthStencilState,
    FrontFace, ImageId, IndexBufferBinding, IndexType, PipelineDesc, Rect, Topology, VertexAttribute, VertexBinding,
    VertexBufferBinding, VertexFormat, VertexInputState, Viewport,
};

use super::pass::{Writes, push_draw};
use super::{AttribSource, Context, Fallible};
use crate::call::{ComponentType, Face, Filter, IndexKind, Mode, Winding, Wrap};
use crate::program::SamplerState;
use crate::report::{CallRef, DrawKind, FlushCause, PartialClear};

/// The largest viewport extent GL accepts here (`GL_MAX_VIEWPORT_DIMS`); offsets are clamped
/// to the same distance so every corner stays within tiler's viewport limits.
const MAX_VIEWPORT: i64 = 16384;

/// What a gathered draw draws.
#[derive(Clone, Debug)]
pub(crate) enum DrawSource {
    Program {
        program: super::glsl::ProgramDraw,
        textures: Vec<super::glsl::SampledTexture>,
        /// The per-instance attribute bytes the driver read for this instance, counted as
        /// `vertex_fetch` (see `instancing.rs`).
        instance_fetch_bytes: u64,
    },
    Clear {
        color: [f32; 4],
        depth: f32,
        targets: usize,
    },
    /// A textured rectangle (blit or copy); `read_bytes` is the source read it costs.
    Rectangle {
        image: ImageId,
        ndc: [f32; 4],
        tex: [f32; 4],
        sampler: SamplerState,
        read_bytes: u64,
        /// The texels' alpha is replaced by 1 (a copy into a texture without alpha).
        alpha_one: bool,
    },
}

/// A draw gathered into the open pass (its frame data, in GL's terms).
#[derive(Clone, Debug)]
pub(crate) struct PendingDraw {
    pub call: CallRef,
    pub kind: DrawKind,
    pub source: DrawSource,
    pub desc: PipelineDesc,
    pub vertex_buffers: Vec<VertexBufferBinding>,
    pub index: Option<IndexBufferBinding>,
    pub first: u32,
    pub count: u32,
    pub viewport: Viewport,
    pub scissor: Option<Rect>,
    pub query: Option<u32>,
    pub writes: Writes,
    pub clip_rect: Rect,
    pub partial_clear: Option<PartialClear>,
}

/// The tiler vertex format of a GL attribute pointer.
///
/// # Errors
/// Combinations tiler cannot fetch.
pub(crate) fn vertex_format(
    size: u32,
    component: ComponentType,
    normalized: bool,
    integer: bool,
) -> Fallible<VertexFormat> {
    use ComponentType::*;
    if integer {
        // `glVertexAttribIPointer`: the integers as they are (`VertexFormat::Int`).
        let (bits, signed) = match component {
            Byte => (8, true),
            UnsignedByte => (8, false),
            Short => (16, true),
            UnsignedShort => (16, false),
            Int => (32, true),
            UnsignedInt => (32, false),
            Float | HalfFloat => {
                return Err(format!("glVertexAttribIPointer of {component:?}: integer attributes take integer types"));
            }
        };
        if !(1..=4).contains(&size) {
            return Err(format!("integer vertex attributes of {size} components (1 to 4)"));
        }
        return Ok(VertexFormat::Int(tiler::IntFormat { channels: size as u8, bits, signed }));
    }
    Ok(match (component, size, normalized) {
        (Float, 1, _) => VertexFormat::Float32,
        (Float, 2, _) => VertexFormat::Float32x2,
        (Float, 3, _) => VertexFormat::Float32x3,
        (Float, 4, _) => VertexFormat::Float32x4,
        (HalfFloat, 2, _) => VertexFormat::Float16x2,
        (HalfFloat, 4, _) => VertexFormat::Float16x4,
        (UnsignedByte, 4, true) => VertexFormat::Unorm8x4,
        (UnsignedByte, 4, false) => VertexFormat::Uint8x4,
        (Byte, 4, true) => VertexFormat::Snorm8x4,
        (UnsignedShort, 2, true) => VertexFormat::Unorm16x2,
        (UnsignedShort, 4, true) => VertexFormat::Unorm16x4,
        (UnsignedShort, 2, false) => VertexFormat::Uint16x2,
        (Short, 2, true) => VertexFormat::Snorm16x2,
        (Short, 4, true) => VertexFormat::Snorm16x4,
        (UnsignedInt, 1, false) => VertexFormat::Uint32,
        _ => {
            return Err(format!(
                "vertex attributes of {size} × {component:?}{} are not supported (floats of 1–4 components, \
                 half floats ×2/×4, normalized bytes ×4, shorts ×2/×4 are)",
                if normalized { " (normalized)" } else { "" }
            ));
        }
    })
}

/// A GL window rectangle (origin bottom-left) as tiler pixels (origin top-left), clamped to a
/// `width × height` framebuffer.
pub(crate) fn gl_rect(x: i64, y: i64, w: i64, h: i64, width: u32, height: u32) -> Rect {
    let (fw, fh) = (width as i64, height as i64);
    let x0 = x.clamp(0, fw);
    let x1 = (x + w).clamp(0, fw);
    let y0 = y.clamp(0, fh);
    let y1 = (y + h).clamp(0, fh);
    Rect::new(x0 as u32, (fh - y1) as u32, (x1 - x0).max(0) as u32, (y1 - y0).max(0) as u32)
}

pub(super) fn intersect(a: Rect, b: Rect) -> Rect {
    let x0 = a.x.max(b.x);
    let y0 = a.y.max(b.y);
    let x1 = a.right().min(b.right()) as u32;
    let y1 = a.bottom().min(b.bottom()) as u32;
    Rect::new(x0, y0, x1.saturating_sub(x0), y1.saturating_sub(y0))
}

impl Context {
    /// A draw of the program in use, `instances` times: checked now, gathered into the open
    /// pass (each instance a draw of its own, see `instancing`).
    pub(crate) fn draw(
        &mut self,
        mode: Mode,
        first: u32,
        count: u32,
        indexed: Option<(IndexKind, u64)>,
        instances: u32,
    ) -> Fallible {
        // Layers rendered into and sampled now (`layered.rs`).
        self.sync_sampled_layers()?;
        if self.feedback.capturing() {
            if indexed.is_some() {
                return Err("an indexed draw while transform feedback is active: GL ES 3.0 captures only \
                            glDrawArrays and glDrawArraysInstanced"
                    .into());
            }
            self.capture_feedback(mode, first, count, instances)?;
        }
        if self.state.rasterizer_discard {
            // GL_RASTERIZER_DISCARD: nothing reaches the rasterizer (`feedback.rs`).
            return Ok(());
        }
        if let (true, Some((index_kind, offset))) = (self.state.primitive_restart, indexed) {
            return self.draw_restarting(mode, first, count, index_kind, offset, instances);
        }
        let here = self.here;
        if instances > super::instancing::MAX_INSTANCES {
            return Err(format!(
                "{instances} instances: the context draws each instance as a draw of its own, at most {} per call",
                super::instancing::MAX_INSTANCES
            ));
        }
        if self.pass.is_none() {
            // A draw needs a complete framebuffer before anything else.
            self.targets(self.draw_framebuffer)?;
        }
        let program = self.draw_program()?;

        // Indices: bound, aligned, inside their buffer; the largest gives the vertex range.
        let mut index_binding = None;
        // Byte indices widened to shorts, copied into a buffer the pass owns once the draw is sure.
        let mut widened = None;
        let max_vertex: Option<u64> = match indexed {
            None => (count > 0).then(|| first as u64 + count as u64 - 1),
            Some((index_kind, offset)) => {
                let id = self.state.index_buffer;
                let buffer = self.buffers.get(&id).ok_or("draw_elements with no index buffer bound")?;
                let (index_type, size) = match index_kind {
                    IndexKind::UnsignedByte => (IndexType::U16, 1u64),
                    IndexKind::UnsignedShort => (IndexType::U16, 2u64),
                    IndexKind::UnsignedInt => (IndexType::U32, 4u64),
                };
                if offset % size != 0 {
                    return Err(format!("index offset {offset} is not a multiple of the index size {size}"));
                }
                let end = offset + count as u64 * size;
                if end > buffer.size {
                    return Err(format!(
                        "{count} indices from byte {offset} need {end} bytes, but index buffer {id} has {}",
                        buffer.size
                    ));
                }
                let storage = buffer.storage;
                let bytes =
                    &self.device.buffer_data(storage).map_err(|e| e.to_string())?[offset as usize..end as usize];
                let max = match index_kind {
                    IndexKind::UnsignedByte => bytes.iter().map(|&b| b as u64).max(),
                    IndexKind::UnsignedShort => {
                        bytes.chunks_exact(2).map(|b| u16::from_le_bytes([b[0], b[1]]) as u64).max()
                    }
                    IndexKind::UnsignedInt => {
                        bytes.chunks_exact(4).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as u64).max()
                    }
                };
                index_binding = Some((storage, IndexBufferBinding { buffer: storage, offset, index_type }));
                if index_kind == IndexKind::UnsignedByte {
                    // tiler fetches shorts and ints: the driver widens byte indices per draw, as
                    // it copies client arrays (the ledger counts the copy's 2 bytes per index).
                    widened = Some(bytes.iter().flat_map(|&i| u16::from(i).to_le_bytes()).collect::<Vec<u8>>());
                }
                max
            }
        };

        // Vertex attributes: one binding per (storage, stride, base) so interleaved
        // attributes share a binding and separate arrays get their own.
        struct Input {
            index: u32,
            format: VertexFormat,
            stride: u32,
            offset: u64,
            source: AttribSource,
        }
        let mut inputs = Vec::new();
        let mut per_instance = Vec::new();
        for (index, name) in &program.attributes {
            let index = *index;
            let attrib = &self.state.attribs[index as usize];
            if attrib.enabled && attrib.divisor > 0 {
                per_instance.push(self.instanced_attribute(&program, index, name, instances)?);
                continue;
            }
            let Some((source, size, component, normalized, stride, integer)) =
                attrib.source.clone().filter(|_| attrib.enabled)
            else {
                return Err(format!(
                    "program '{}' reads attribute {index} ({name}), which is not enabled with a pointer",
                    program.label
                ));
            };
            let format = vertex_format(size, component, normalized, integer)?;
            let stride = if stride == 0 { format.size_bytes() } else { stride };
            if stride < format.size_bytes() {
                return Err(format!(
                    "attribute {index} ({name}): stride {stride} is smaller than its {} bytes",
                    format.size_bytes()
                ));
            }
            let (offset, available) = match &source {
                AttribSource::Buffer { buffer, offset } => {
                    let b = self
                        .buffers
                        .get(buffer)
                        .ok_or_else(|| format!("attribute {index} reads buffer {buffer}, which was deleted"))?;
                    (*offset, b.size)
                }
                AttribSource::Client { data } => (0, data.len() as u64),
            };
            if let Some(max) = max_vertex {
                let end = offset as u128 + max as u128 * stride as u128 + format.size_bytes() as u128;
                if end > available as u128 {
                    return Err(format!(
                        "attribute {index} ({name}) of vertex {max} ends at byte {end}, past the end of its data ({available} bytes)"
                    ));
                }
            }
            inputs.push(Input { index, format, stride, offset, source });
        }

        // The subpass the draw goes to, and the input attachments the program reads.
        let subpass = self.explicit().map(|e| (e.current, e.subpass().clone()));
        let input_count = program.inputs;
        if input_count > 0 {
            match &subpass {
                None => {
                    return Err(format!(
                        "program '{}' reads input attachment 0, which only a subpass of an explicit pass has \
                         (begin_pass with \"input\")",
                        program.label
                    ));
                }
                Some((s, d)) if d.input.len() < input_count => {
                    return Err(format!(
                        "program '{}' reads {input_count} input attachment(s), but subpass {s} has {}",
                        program.label,
                        d.input.len()
                    ));
                }
                _ => {}
            }
        }
        // A texture the program samples that is an attachment of the open pass: flush it.
        if self
            .pass
            .as_ref()
            .is_some_and(|p| p.has_work() && program.textures.iter().any(|t| p.targets.images().any(|i| i == t.image)))
        {
            self.flush_open_pass(FlushCause::SampleAttachment)?;
        }

        let targets = self.ensure_pass()?.targets.clone();
        // `draw_buffers` of the pass's framebuffer (explicit subpasses write theirs all).
        let framebuffer = self.pass.as_ref().expect("ensured").framebuffer;
        let draw_buffers = match (&subpass, self.framebuffers.get(&framebuffer)) {
            (None, Some(fb)) => (fb.draw_buffers.unwrap_or(1) as usize).min(targets.color.len()),
            _ => 1,
        };
        let fewest = match mode {
            Mode::Points => 1,
            Mode::Lines | Mode::LineStrip | Mode::LineLoop => 2,
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan => 3,
        };
        if max_vertex.is_none() || count < fewest || instances == 0 {
            return Ok(());
        }
        let (width, height) = (targets.width, targets.height);
        let s = &self.state;
        let [vx, vy, vw, vh] = s.viewport;
        let vw = vw.min(MAX_VIEWPORT);
        let vh = vh.min(MAX_VIEWPORT);
        if vw <= 0 || vh <= 0 {
            return Ok(());
        }
        let vx = vx.clamp(-MAX_VIEWPORT, MAX_VIEWPORT);
        let vy = vy.clamp(-MAX_VIEWPORT, MAX_VIEWPORT);
        let viewport = Viewport {
            x: vx as f32,
            y: (height as i64 - (vy + vh)) as f32,
            width: vw as f32,
            height: vh as f32,
            min_depth: s.depth_range[0],
            max_depth: s.depth_range[1],
        };
        let scissor =
            s.scissor_test.then(|| gl_rect(s.scissor[0], s.scissor[1], s.scissor[2], s.scissor[3], width, height));
        let mut clip_rect = gl_rect(vx, vy, vw, vh, width, height);
        if let Some(sc) = scissor {
            clip_rect = intersect(clip_rect, sc);
        }
        if let Some(region) = self.tiling.map(|t| t.region) {
            clip_rect = intersect(clip_rect, region);
        }

        // In a subpass without the depth-stencil attachment, there is nothing to test against.
        let subpass_depth = subpass.as_ref().is_none_or(|(_, d)| d.depth_stencil);
        let subpass_color = subpass.as_ref().is_none_or(|(_, d)| !d.color.is_empty());
        let depth_test = s.depth_test && targets.has_depth() && subpass_depth;
        let stencil_test = s.stencil_test && targets.has_stencil() && subpass_depth;
        let [front, back] = s.stencil;
        let depth_stencil = DepthStencilState {
            depth_test,
            depth_write: depth_test && s.depth_mask,
            depth_compare: s.depth_func,
            stencil_test,
            front,
            back,
        };
        let blend = s.blend.then(|| BlendState {
            color: BlendComponent { src: s.blend_func[0], dst: s.blend_func[1], op: s.blend_equation[0] },
            alpha: BlendComponent { src: s.blend_func[2], dst: s.blend_func[3], op: s.blend_equation[1] },
        });
        let write_mask = color_writes(s.color_mask);
        let writes = Writes {
            color: !targets.color.is_empty() && subpass_color && write_mask != ColorWrites::NONE,
            depth: depth_stencil.depth_write,
            stencil: stencil_test && (front.writes() || back.writes()),
        };
        let mut vertex_input = VertexInputState::default();
        let mut desc_cull = CullMode::None;
        if s.cull_face {
            desc_cull = match s.cull {
                Face::Front => CullMode::Front,
                Face::Back => CullMode::Back,
                Face::FrontAndBack => CullMode::FrontAndBack,
            };
        }
        // The picture is upright in both GL's window (y up) and tiler's framebuffer (y down,
        // row 0 at the top), so a winding seen on screen is the same in both.
        let front_face = match s.front {
            Winding::Ccw => FrontFace::CounterClockwise,
            Winding::Cw => FrontFace::Clockwise,
        };
        let topology = match mode {
            Mode::Triangles => Topology::TriangleList,
            Mode::TriangleStrip => Topology::TriangleStrip,
            Mode::TriangleFan => Topology::TriangleFan,
            Mode::Lines => Topology::LineList,
            Mode::LineStrip => Topology::LineStrip,
            Mode::LineLoop => Topology::LineLoop,
            Mode::Points => Topology::PointList,
        };
        let blend_constant = s.blend_color;
        let query = self.active_query;

        // Bind the vertex data: client arrays are copied into buffers the pass owns.
        let mut vertex_buffers: Vec<VertexBufferBinding> = Vec::new();
        let mut keys: Vec<(BufferId, u32, u64)> = Vec::new();
        let mut used = Vec::new();
        let mut client = Vec::new();
        for input in &inputs {
            let storage = match &input.source {
                AttribSource::Buffer { buffer, .. } => {
                    let b = self.buffers.get_mut(buffer).expect("checked");
                    b.last_use = Some(here.frame);
                    b.storage
                }
                AttribSource::Client { data } => {
                    let id = self.alloc_buffer(data)?;
                    client.push((id, data.len() as u64));
                    id
                }
            };
            used.push(storage);
            let base = input.offset - input.offset % input.stride as u64;
            let key = (storage, input.stride, base);
            let binding = match keys.iter().position(|k| *k == key) {
                Some(b) => b,
                None => {
                    keys.push(key);
                    vertex_input.bindings.push(VertexBinding { stride: input.stride });
                    vertex_buffers.push(VertexBufferBinding { buffer: storage, offset: base });
                    keys.len() - 1
                }
            };
            vertex_input.attributes.push(VertexAttribute {
                location: input.index,
                binding: binding as u32,
                format: input.format,
                offset: (input.offset - base) as u32,
            });
        }
        if let (Some(shorts), Some((_, binding))) = (widened, &mut index_binding) {
            let copy = self.alloc_buffer(&shorts)?;
            client.push((copy, shorts.len() as u64));
            (binding.buffer, binding.offset) = (copy, 0);
        }
        for id in &program.uniform_buffers {
            let b = self.buffers.get_mut(id).expect("checked by read_uniform_blocks");
            b.last_use = Some(here.frame);
            used.push(b.storage);
        }
        if let Some((storage, _)) = index_binding {
            used.push(storage);
            let id = self.state.index_buffer;
            self.buffers.get_mut(&id).expect("checked").last_use = Some(here.frame);
        }
        for t in &program.textures {
            self.sampled(t.image, here.frame);
        }

        let mut desc = PipelineDesc::new(program.label, vertex_input);
        desc.topology = topology;
        desc.cull_mode = desc_cull;
        desc.front_face = front_face;
        desc.depth_stencil = depth_stencil;
        desc.line_width = self.state.line_width;
        // GL's polygon offset applies to polygons only.
        if self.state.polygon_offset_fill && !topology.is_line() && topology != Topology::PointList {
            let (slope_factor, constant_factor) = self.state.polygon_offset;
            desc.depth_bias = DepthBias { constant_factor, slope_factor };
        }
        desc.color_targets = if targets.color.is_empty() || !subpass_color {
            Vec::new()
        } else {
            vec![ColorTargetState { blend, write_mask }; draw_buffers]
        };
        desc.blend_constant = blend_constant;
        if let Some(q) = query.and_then(|q| self.queries.get_mut(&q)) {
            q.pending_draws += 1;
        }
        if let Some(q) = query.and_then(|q| self.queries.get_mut(&q)) {
            q.pending_draws += instances - 1;
        }
        let per_instance = super::instancing::InstanceReader::new(per_instance);
        used.extend(self.instanced_buffers_used(&per_instance, here.frame));
        let pass = self.pass.as_mut().expect("ensured above");
        pass.buffers_used.extend(used);
        pass.retired_buffers.extend(client);
        pass.images_sampled.extend(program.textures.iter().map(|t| t.image));
        // The last instance (the only one of a plain draw) takes the draw's state, the others
        // copies.
        let mut state = Some((program.source, program.textures, desc, vertex_buffers));
        for instance in 0..instances {
            let (source, textures, desc, vertex_buffers) = if instance + 1 == instances {
                state.take().expect("taken by the last instance only")
            } else {
                state.clone().expect("taken by the last instance only")
            };
            let (source, instance_fetch_bytes) = per_instance.instance(source, instance);
            push_draw(
                pass,
                PendingDraw {
                    call: here,
                    kind: DrawKind::Draw,
                    source: DrawSource::Program { program: source, textures, instance_fetch_bytes },
                    desc,
                    vertex_buffers,
                    index: index_binding.as_ref().map(|b| b.1),
                    first,
                    count,
                    viewport,
                    scissor,
                    query,
                    writes,
                    clip_rect,
                    partial_clear: None,
                },
            );
        }
        Ok(())
    }

    /// Records a textured rectangle (a blit or a copy) into the open pass.
    /// An indexed draw with `GL_PRIMITIVE_RESTART_FIXED_INDEX` (GL ES 3.0 §2.8.1): each index
    /// of the type's largest value (0xFF, 0xFFFF, 0xFFFFFFFF) ends the primitive being
    /// assembled, and assembly starts anew after it. Each run of indices between restarts is
    /// drawn as a draw of its own — the same primitives, in the same order, as one draw with
    /// restarts (a partial primitive at a run's end is dropped, as GL drops it); the report
    /// counts one draw per run. A draw without a restart index is drawn as it is.
    fn draw_restarting(
        &mut self,
        mode: Mode,
        first: u32,
        count: u32,
        index_kind: IndexKind,
        offset: u64,
        instances: u32,
    ) -> Fallible {
        let id = self.state.index_buffer;
        let buffer = self.buffers.get(&id).ok_or("draw_elements with no index buffer bound")?;
        let size: u64 = match index_kind {
            IndexKind::UnsignedByte => 1,
            IndexKind::UnsignedShort => 2,
            IndexKind::UnsignedInt => 4,
        };
        let end = offset.saturating_add(count as u64 * size);
        // Out-of-range draws are left to `draw`, which says why.
        let runs = if !offset.is_multiple_of(size) || end > buffer.size {
            None
        } else {
            let data = self.device.buffer_data(buffer.storage).map_err(|e| e.to_string())?;
            let bytes = &data[offset as usize..end as usize];
            let restart = |i: &[u8]| i.iter().all(|&b| b == 0xff);
            let mut runs = Vec::new();
            let mut start = 0u32;
            for (i, index) in bytes.chunks_exact(size as usize).enumerate() {
                if restart(index) {
                    runs.push((start, i as u32 - start));
                    start = i as u32 + 1;
                }
            }
            (!runs.is_empty()).then(|| {
                runs.push((start, count - start));
                runs
            })
        };
        self.state.primitive_restart = false;
        let result = match runs {
            None => self.draw(mode, first, count, Some((index_kind, offset)), instances),
            Some(runs) => runs.into_iter().filter(|&(_, n)| n > 0).try_for_each(|(start, n)| {
                self.draw(mode, first, n, Some((index_kind, offset + start as u64 * size)), instances)
            }),
        };
        self.state.primitive_restart = true;
        result
    }

    pub(crate) fn push_rectangle(&mut self, rect: TexturedRect) -> Fallible {
        let TexturedRect { kind, image, dst, ndc, tex, filter, read_bytes, scissor, alpha_one } = rect;
        let here = self.here;
        let pass = self.ensure_pass()?;
        let (width, height) = (pass.targets.width, pass.targets.height);
        let mut desc = PipelineDesc::new("blit", VertexInputState::default());
        desc.topology = Topology::TriangleStrip;
        desc.color_targets = vec![ColorTargetState::REPLACE];
        let mut clip_rect = intersect(dst, Rect::new(0, 0, width, height));
        if let Some(s) = scissor {
            clip_rect = intersect(clip_rect, s);
        }
        if let Some(region) = pass.region {
            clip_rect = intersect(clip_rect, region);
        }
        pass.images_sampled.insert(image);
        push_draw(
            pass,
            PendingDraw {
                call: here,
                kind,
                source: DrawSource::Rectangle {
                    image,
                    ndc,
                    tex,
                    sampler: SamplerState::new(filter, Wrap::ClampToEdge),
                    read_bytes,
                    alpha_one,
                },
                desc,
                vertex_buffers: Vec::new(),
                index: None,
                first: 0,
                count: 4,
                viewport: Viewport::full(width, height),
                scissor,
                query: None,
                writes: Writes { color: true, depth: false, stencil: false },
                clip_rect,
                partial_clear: None,
            },
        );
        Ok(())
    }
}

/// A textured rectangle the driver draws itself: a `blit_framebuffer` or a
/// `copy_tex_sub_image`.
pub(crate) struct TexturedRect {
    pub kind: DrawKind,
    /// The image sampled.
    pub image: ImageId,
    /// Pixels written, tiler coordinates.
    pub dst: Rect,
    /// Two opposite corners in normalized device coordinates, `[x0, y0, x1, y1]`.
    pub ndc: [f32; 4],
    /// The texture coordinates at those corners, `[u0, v0, u1, v1]`.
    pub tex: [f32; 4],
    pub filter: Filter,
    /// Source bytes read, counted as `texture_fetch`.
    pub read_bytes: u64,
    pub scissor: Option<Rect>,
    /// The texels drawn get alpha 1 (a copy into a texture whose format has no alpha).
    pub alpha_one: bool,
}

/// GL's colour mask as tiler's write mask.
pub(super) fn color_writes(mask: [bool; 4]) -> ColorWrites {
    let bits = [ColorWrites::RED, ColorWrites::GREEN, ColorWrites::BLUE, ColorWrites::ALPHA];
    ColorWrites(mask.iter().zip(bits).filter(|(on, _)| **on).fold(0, |acc, (_, b)| acc | b.0))
}
