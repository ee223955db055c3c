//! Render-pass inference: how GL calls become passes with load and store ops.
//!
//! This is `DESIGN.md`'s table, row by row, and where each row is implemented:
//!
//! | the application does | the driver does | here |
//! |---|---|---|
//! | binds a framebuffer | ends the open pass; the next command starts a pass on it | `bind_framebuffer`, [`Context::ensure_pass`] |
//! | clears every attachment, no scissor, no masks | load op `Clear` for all; the gathered draws are thrown away | [`Context::clear`] |
//! | clears with a scissor or a write mask, or only some buffers | a clear-quad draw; what was not fully cleared keeps its load op | [`Context::clear`] |
//! | invalidates attachments | store op `DontCare` (and load op `DontCare` before any draw) | [`Context::invalidate`] |
//! | reads pixels, copies, blits, flushes, finishes, asks a query of the pass, samples the pass's texture | flush: the pass renders now, drawing continues in a pass that loads what was stored | [`Context::flush_open_pass`] |
//! | binds the same framebuffer again later | a second pass, loading | [`Context::ensure_pass`] |
//! | swaps (destroyed / preserved) | the window's next pass starts `DontCare` / `Load` | `frames.rs` |
//! | `start_tiling` / `end_tiling` | render area = the region; load and store as the masks say | [`Context::start_tiling`] |
//! | exceeds the frame-data budget | incremental render (in the core: `tiler::backend::tbr`) | — |
//! | changes a buffer a pending frame uses | copy-on-write, counted | `mod.rs`, `frames.rs` |
//! | begins an explicit pass (`begin_pass`) | the same inference, with the given subpasses; nothing may end it before `end_pass` | `explicit.rs` |
//! | attaches a transient image | never loaded or stored (load `DontCare` or `Clear`, store `DontCare`) | `start_aspect` |
//!
//! # Load ops
//!
//! A pass starts with `Load` for every attached aspect whose contents are *defined*, and
//! `DontCare` for the rest: new storage, invalidated contents, and the window after a
//! destroying swap are undefined, and a driver never reads undefined memory. Clears and
//! invalidates before the first draw then change them. A clear is *full* for an aspect when
//! the scissor test is off and its write mask is all on; only a full clear of every attached
//! aspect throws the gathered draws away (seed 000 §23.3: "using a scissor or a mask or only
//! clearing a subset … will prevent the frame data from being freed"). Even a scissor box
//! covering the whole framebuffer counts as a scissor, as in the portable advice of Listing
//! 23.1; a fully masked aspect is not cleared at all, as in GL.
//!
//! # Store ops
//!
//! Every attached aspect is stored unless invalidated; a write after an invalidate stores it
//! again. The window's depth and stencil are not stored at a swap (EGL leaves them undefined
//! after it). The unattached half of a packed depth-stencil image is loaded and stored with
//! the attached half, to keep it.
//!
//! # When a pass renders
//!
//! A pass is rendered on the device the moment it ends: when its framebuffer is unbound, at a
//! swap, or at a flush. A pass with nothing to do (no draws, no clears) is not rendered. So the
//! only pass ever pending is the open one, and a flush only ever cuts that one short.

use std::collections::{HashMap, HashSet};
use std::sync::Arc;

use tiler::{
    BlendComponent, BlendState, BufferId, ColorAttachment, ColorTargetState, ColorWrites, CompareOp, CullMode,
    DepthStencilAttachment, DepthStencilState, Draw, FrontFace, ImageId, IndexBufferBinding, IndexType, LoadOp,
    PipelineDesc, Rect, RenderPass, RenderPassDesc, StencilFaceState, StencilOp, StoreOp, Topology, VertexAttribute,
    VertexBinding, VertexBufferBinding, VertexFormat, VertexInputState, Viewport,
};

use super::targets::Targets;
use super::{AttribSource, Context, Fallible, Tiling};
use crate::call::{BufferSet, ComponentType, Face, Filter, IndexKind, Mode, Winding, Wrap};
use crate::program::{ProgramTexture, SamplerState, TextureSnapshot, blit_pipeline, clear_pipeline};
use crate::report::{
    AttachmentRecord, CallRef, DrawKind, DrawRecord, Dropped, EndCause, FlushCause, LoadKind, PartialClear, PassCost,
    PassRecord, Role, Slot, StartCause, StoreKind,
};

/// The largest viewport extent GL accepts here (`GL_MAX_VIEWPORT_DIMS`); offsets are clamped
/// to the same distance so every corner stays within tiler's viewport limits.
const MAX_VIEWPORT: i64 = 16384;

/// One aspect of the open pass and its ops.
#[derive(Clone, Debug)]
pub(crate) struct PassAspect {
    pub slot: Slot,
    pub image: ImageId,
    pub role: Role,
    pub load: LoadKind,
    /// The clear value: a colour, or the depth in `[0]`, or the stencil in `[0]`.
    pub clear: [f32; 4],
    pub load_reason: String,
    pub store: StoreKind,
    pub store_reason: String,
    pub invalidated: bool,
    /// Where a multisampled colour is resolved, in the tile, at the end of the pass.
    pub resolve: Option<ImageId>,
    /// A transient image: never loaded or stored, whatever happens in the pass.
    pub transient: bool,
}

/// Which aspects a draw writes.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Writes {
    pub color: bool,
    pub depth: bool,
    pub stencil: bool,
}

impl Writes {
    fn writes(&self, slot: Slot) -> bool {
        match slot {
            Slot::Color(_) => self.color,
            Slot::Depth => self.depth,
            Slot::Stencil => self.stencil,
        }
    }
}

/// What a gathered draw draws.
#[derive(Clone, Debug)]
pub(crate) enum DrawSource {
    Program {
        program: super::glsl::ProgramDraw,
        textures: Vec<super::glsl::SampledTexture>,
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

/// The render pass being gathered.
pub(crate) struct OpenPass {
    pub framebuffer: u32,
    /// Set for the pass of a `copy_tex_sub_image` into this texture.
    pub copy_texture: Option<u32>,
    /// The window's pass under the preserved swap behaviour.
    pub window_preserved: bool,
    pub targets: Targets,
    pub aspects: Vec<PassAspect>,
    pub draws: Vec<PendingDraw>,
    pub start: StartCause,
    pub started_at: CallRef,
    /// The tiled-rendering region (tiler coordinates).
    pub region: Option<Rect>,
    pub dropped: Vec<Dropped>,
    pub buffers_used: HashSet<BufferId>,
    pub images_sampled: HashSet<ImageId>,
    /// Storage to free once the pass is rendered: `(buffer, bytes)`.
    pub retired_buffers: Vec<(BufferId, u64)>,
    pub retired_images: Vec<ImageId>,
    /// The subpasses of a `begin_pass`; `None` for an inferred pass.
    pub explicit: Option<super::explicit::ExplicitPass>,
}

impl OpenPass {
    /// Whether rendering it would change anything: a draw, or a clear.
    pub fn has_work(&self) -> bool {
        !self.draws.is_empty() || self.aspects.iter().any(|a| a.load == LoadKind::Clear)
    }

    fn attached(&self) -> impl Iterator<Item = &PassAspect> {
        self.aspects.iter().filter(|a| a.role == Role::Attached)
    }

    /// Throws the gathered draws away (a full clear or invalidate), freeing their queries.
    fn drop_draws(
        &mut self,
        queries: &mut std::collections::BTreeMap<u32, super::QueryObject>,
        at: CallRef,
        by: &'static str,
    ) {
        if self.draws.is_empty() {
            return;
        }
        for d in &self.draws {
            if let Some(q) = d.query.and_then(|q| queries.get_mut(&q)) {
                q.pending_draws = q.pending_draws.saturating_sub(1);
            }
        }
        self.dropped.push(Dropped { call: at, draws: self.draws.len() as u32, by });
        self.draws.clear();
    }
}

/// The key of an aspect of an image in the store tracker (a colour image has one aspect).
pub(crate) fn store_key(image: ImageId, slot: Slot) -> (ImageId, Slot) {
    match slot {
        Slot::Color(_) => (image, Slot::Color(0)),
        s => (image, s),
    }
}

/// Index of an aspect in `ImageInfo::defined`.
pub(crate) fn defined_index(slot: Slot) -> usize {
    if slot == Slot::Stencil { 1 } else { 0 }
}

/// The tiler vertex format of a GL attribute pointer.
///
/// # Errors
/// Combinations tiler cannot fetch.
pub(crate) fn vertex_format(size: u32, component: ComponentType, normalized: bool) -> Fallible<VertexFormat> {
    use ComponentType::*;
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

fn intersect(a: Rect, b: Rect) -> Rect {
    let x0 = a.x.max(b.x);
    let y0 = a.y.max(b.y);
    let x1 = a.right().min(b.right()) as u32;
    let y1 = a.bottom().min(b.bottom()) as u32;
    Rect::new(x0, y0, x1.saturating_sub(x0), y1.saturating_sub(y0))
}

impl Context {
    /// The open pass, starting one on the bound draw framebuffer if there is none.
    ///
    /// # Errors
    /// The bound framebuffer is incomplete.
    pub(crate) fn ensure_pass(&mut self) -> Fallible<&mut OpenPass> {
        if self.pass.is_none() {
            let framebuffer = self.draw_framebuffer;
            let targets = self.targets(framebuffer)?;
            let (mut start, started_at) = self.next_start;
            let mut region = None;
            let mut preserve = None;
            if let Some(Tiling { region: r, preserve: p, started }) = &mut self.tiling {
                region = Some(*r);
                if !*started {
                    *started = true;
                    start = StartCause::Tiling;
                    preserve = Some(*p);
                }
            }
            let mut aspects = Vec::new();
            for (i, target) in targets.color.iter().enumerate() {
                let mut aspect = self.start_aspect(Slot::Color(i as u8), target.image, Role::Attached, preserve);
                if let Some(resolve) = target.resolve {
                    aspect.resolve = Some(resolve);
                    aspect.store = StoreKind::DontCare;
                    aspect.store_reason =
                        format!("multisampled: resolved in the tile into {resolve}; the samples are not kept");
                }
                aspects.push(aspect);
            }
            if let Some(ds) = targets.depth_stencil {
                if let Some(role) = ds.depth {
                    aspects.push(self.start_aspect(Slot::Depth, ds.image, role, preserve));
                }
                if let Some(role) = ds.stencil {
                    aspects.push(self.start_aspect(Slot::Stencil, ds.image, role, preserve));
                }
            }
            let window_preserved = framebuffer == 0 && self.swap_behavior == crate::call::SwapBehavior::Preserved;
            self.pass = Some(OpenPass {
                framebuffer,
                copy_texture: None,
                window_preserved,
                targets,
                aspects,
                draws: Vec::new(),
                start,
                started_at,
                region,
                dropped: Vec::new(),
                buffers_used: HashSet::new(),
                images_sampled: HashSet::new(),
                retired_buffers: Vec::new(),
                retired_images: Vec::new(),
                explicit: None,
            });
        }
        Ok(self.pass.as_mut().expect("just made"))
    }

    /// The initial ops of one aspect of a new pass.
    fn start_aspect(&self, slot: Slot, image: ImageId, role: Role, preserve: Option<BufferSet>) -> PassAspect {
        let info = &self.images[&image];
        let defined = info.defined[defined_index(slot)];
        let transient = info.desc.transient;
        let (load, load_reason, store, store_reason) = match role {
            _ if transient => (
                LoadKind::DontCare,
                "transient: it has no memory, so it is never loaded".to_string(),
                StoreKind::DontCare,
                "transient: it has no memory, so it is never stored".to_string(),
            ),
            Role::Padding => (
                LoadKind::DontCare,
                format!("padding: {} has no {slot} aspect", info.gl_format.name()),
                StoreKind::DontCare,
                "padding".to_string(),
            ),
            _ => {
                let in_mask = preserve.is_none_or(|p| match slot {
                    Slot::Color(_) => p.color,
                    Slot::Depth => p.depth,
                    Slot::Stencil => p.stencil,
                });
                let (load, why) = if !in_mask {
                    (LoadKind::DontCare, "not in start_tiling's preserve mask".to_string())
                } else if defined {
                    (LoadKind::Load, "its contents are defined, so they are loaded".to_string())
                } else {
                    (LoadKind::DontCare, "its contents are undefined (new, invalidated, or after a swap)".to_string())
                };
                let store_reason = if role == Role::Preserved {
                    format!("the unattached half of packed {} is kept", info.gl_format.name())
                } else {
                    "kept for later use (not invalidated)".to_string()
                };
                (load, why, StoreKind::Store, store_reason)
            }
        };
        PassAspect {
            slot,
            image,
            role,
            load,
            clear: [0.0; 4],
            load_reason,
            store,
            store_reason,
            invalidated: false,
            resolve: None,
            transient,
        }
    }

    /// `glClear`.
    pub(crate) fn clear(&mut self, buffers: BufferSet) -> Fallible {
        let here = self.here;
        let s = &self.state;
        let (scissor_test, scissor, color_mask, depth_mask, stencil_mask) =
            (s.scissor_test, s.scissor, s.color_mask, s.depth_mask, s.stencil_write_mask);
        let (clear_color, clear_depth, clear_stencil) = (s.clear_color, s.clear_depth, s.clear_stencil);
        let mut queries = std::mem::take(&mut self.queries);
        let result = (|| {
            let pass = self.ensure_pass()?;
            let (width, height) = (pass.targets.width, pass.targets.height);
            let scissor_rect =
                scissor_test.then(|| gl_rect(scissor[0], scissor[1], scissor[2], scissor[3], width, height));
            if scissor_rect.is_some_and(|r| r.area() == 0) {
                return Ok(());
            }
            // What the clear does to each attached aspect: nothing (fully masked), fully, or
            // partially (with the reasons).
            let mut effects: Vec<(Slot, Option<Vec<String>>)> = Vec::new();
            for a in pass.attached() {
                let (requested, mask_full, mask_none, mask_what) = match a.slot {
                    Slot::Color(_) => (
                        buffers.color,
                        color_mask.iter().all(|m| *m),
                        color_mask.iter().all(|m| !*m),
                        "the colour write mask",
                    ),
                    Slot::Depth => (buffers.depth, depth_mask, !depth_mask, "the depth write mask"),
                    Slot::Stencil => {
                        (buffers.stencil, stencil_mask == 0xff, stencil_mask == 0, "the stencil write mask")
                    }
                };
                if !requested || mask_none {
                    continue;
                }
                let mut reasons = Vec::new();
                if scissor_rect.is_some() {
                    reasons.push("the scissor test is enabled".to_string());
                }
                if !mask_full {
                    reasons.push(format!("{mask_what} is partly off"));
                }
                effects.push((a.slot, if reasons.is_empty() { None } else { Some(reasons) }));
            }
            if effects.is_empty() {
                return Ok(());
            }
            let every_aspect_fully =
                pass.attached().all(|a| effects.iter().any(|(slot, partial)| *slot == a.slot && partial.is_none()));
            let value = |slot: Slot| match slot {
                Slot::Color(_) => clear_color,
                Slot::Depth => [clear_depth, 0.0, 0.0, 0.0],
                Slot::Stencil => [clear_stencil as f32, 0.0, 0.0, 0.0],
            };
            let explicit = pass.explicit.is_some();
            if explicit && !pass.draws.is_empty() {
                return Err(
                    "a clear after draws in an explicit pass: clear before the first draw (it becomes the load op)"
                        .to_string(),
                );
            }
            if every_aspect_fully {
                // Row 2: a full clear. Everything gathered so far is thrown away.
                pass.drop_draws(&mut queries, here, "clear");
                for a in pass.aspects.iter_mut().filter(|a| a.role == Role::Attached) {
                    a.load = LoadKind::Clear;
                    a.clear = value(a.slot);
                    a.load_reason = format!("full clear at {here}");
                    restore_store(a, here);
                }
                return Ok(());
            }
            let at_start = pass.draws.is_empty();
            let mut quad_slots = Vec::new();
            let mut quad_reasons: Vec<String> = Vec::new();
            for (slot, partial) in &effects {
                match partial {
                    None if at_start => {
                        let a = pass.aspects.iter_mut().find(|a| a.slot == *slot).expect("attached aspect");
                        a.load = LoadKind::Clear;
                        a.clear = value(*slot);
                        a.load_reason = format!("cleared at {here} before any draw");
                        restore_store(a, here);
                    }
                    None => {
                        quad_slots.push(*slot);
                        let why = "only some buffers are cleared after draws".to_string();
                        if !quad_reasons.contains(&why) {
                            quad_reasons.push(why);
                        }
                    }
                    Some(reasons) => {
                        quad_slots.push(*slot);
                        for r in reasons {
                            if !quad_reasons.contains(r) {
                                quad_reasons.push(r.clone());
                            }
                        }
                    }
                }
            }
            if quad_slots.is_empty() {
                return Ok(());
            }
            if explicit {
                return Err(format!(
                    "a clear that needs a clear-quad draw ({}) in an explicit pass: clear whole buffers with the \
                     scissor test off and every write mask on",
                    quad_reasons.join(", ")
                ));
            }
            // Row 3: a clear-quad draw; the load ops stay as they are.
            let color = quad_slots.iter().any(|s| matches!(s, Slot::Color(_)));
            let depth = quad_slots.contains(&Slot::Depth);
            let stencil = quad_slots.contains(&Slot::Stencil);
            let mut desc = PipelineDesc::new("clear-quad", VertexInputState::default());
            let mask = if color { color_writes(color_mask) } else { ColorWrites::NONE };
            desc.color_targets = vec![ColorTargetState { blend: None, write_mask: mask }; pass.targets.color.len()];
            desc.depth_stencil = DepthStencilState {
                depth_test: depth,
                depth_write: depth,
                depth_compare: CompareOp::Always,
                ..DepthStencilState::DISABLED
            };
            if stencil {
                desc.depth_stencil = desc.depth_stencil.with_stencil(StencilFaceState {
                    compare: CompareOp::Always,
                    fail_op: StencilOp::Replace,
                    depth_fail_op: StencilOp::Replace,
                    pass_op: StencilOp::Replace,
                    compare_mask: 0xff,
                    write_mask: stencil_mask,
                    reference: clear_stencil,
                });
            }
            let full = Rect::new(0, 0, width, height);
            let mut clip_rect = scissor_rect.unwrap_or(full);
            if let Some(region) = pass.region {
                clip_rect = intersect(clip_rect, region);
            }
            let draw = PendingDraw {
                call: here,
                kind: DrawKind::ClearQuad,
                source: DrawSource::Clear { color: clear_color, depth: clear_depth, targets: pass.targets.color.len() },
                desc,
                vertex_buffers: Vec::new(),
                index: None,
                first: 0,
                count: 3,
                viewport: Viewport::full(width, height),
                scissor: scissor_rect,
                query: None,
                writes: Writes { color, depth, stencil },
                clip_rect,
                partial_clear: Some(PartialClear { reasons: quad_reasons, slots: quad_slots, at_start }),
            };
            push_draw(pass, draw);
            Ok(())
        })();
        self.queries = queries;
        result
    }

    /// `glInvalidateFramebuffer`.
    pub(crate) fn invalidate(&mut self, points: &[crate::call::AttachmentPoint]) -> Fallible {
        use crate::call::AttachmentPoint as P;
        let here = self.here;
        let mut queries = std::mem::take(&mut self.queries);
        let result = (|| {
            let pass = self.ensure_pass()?;
            let mut slots = Vec::new();
            for p in points {
                match p {
                    P::Depth => slots.push(Slot::Depth),
                    P::Stencil => slots.push(Slot::Stencil),
                    P::DepthStencil => slots.extend([Slot::Depth, Slot::Stencil]),
                    c => slots.push(Slot::Color(c.color_index().expect("colour point") as u8)),
                }
            }
            let at_start = pass.draws.is_empty();
            for a in pass.aspects.iter_mut().filter(|a| a.role == Role::Attached && slots.contains(&a.slot)) {
                a.store = StoreKind::DontCare;
                a.store_reason = format!("invalidated at {here}");
                a.invalidated = true;
                if at_start {
                    a.load = LoadKind::DontCare;
                    a.load_reason = format!("invalidated at {here} before any draw");
                }
            }
            if !at_start && pass.explicit.is_none() && pass.attached().all(|a| a.invalidated) {
                // Every attachment is undefined now: nothing gathered can matter.
                pass.drop_draws(&mut queries, here, "invalidate");
                for a in pass.aspects.iter_mut().filter(|a| a.role == Role::Attached) {
                    a.load = LoadKind::DontCare;
                    a.load_reason = format!("everything was invalidated at {here}");
                }
            }
            Ok(())
        })();
        self.queries = queries;
        result
    }

    /// A draw of the program in use: checked now, gathered into the open pass.
    pub(crate) fn draw(&mut self, mode: Mode, first: u32, count: u32, indexed: Option<(IndexKind, u64)>) -> Fallible {
        let here = self.here;
        if self.pass.is_none() {
            // A draw needs a complete framebuffer before anything else.
            self.targets(self.draw_framebuffer)?;
        }
        let program = self.draw_program()?;

        // Indices: bound, aligned, inside their buffer; the largest gives the vertex range.
        let mut index_binding = None;
        let max_vertex: Option<u64> = match indexed {
            None => (count > 0).then(|| first as u64 + count as u64 - 1),
            Some((index_kind, offset)) => {
                let id = self.state.index_buffer;
                let buffer = self.buffers.get(&id).ok_or("draw_elements with no index buffer bound")?;
                let (index_type, size) = match index_kind {
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
                let bytes =
                    &self.device.buffer_data(buffer.storage).map_err(|e| e.to_string())?[offset as usize..end as usize];
                let max = match index_type {
                    IndexType::U16 => bytes.chunks_exact(2).map(|b| u16::from_le_bytes([b[0], b[1]]) as u64).max(),
                    IndexType::U32 => {
                        bytes.chunks_exact(4).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as u64).max()
                    }
                };
                index_binding =
                    Some((buffer.storage, IndexBufferBinding { buffer: buffer.storage, offset, index_type }));
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
        for (index, name) in &program.attributes {
            let index = *index;
            let attrib = &self.state.attribs[index as usize];
            let Some((source, size, component, normalized, stride)) = attrib.source.clone().filter(|_| attrib.enabled)
            else {
                return Err(format!(
                    "program '{}' reads attribute {index} ({name}), which is not enabled with a pointer",
                    program.label
                ));
            };
            let format = vertex_format(size, component, normalized)?;
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
        if max_vertex.is_none() || count < 3 {
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
        let (func, reference, compare_mask) = s.stencil_func;
        let face = StencilFaceState {
            compare: func,
            fail_op: s.stencil_ops.0,
            depth_fail_op: s.stencil_ops.1,
            pass_op: s.stencil_ops.2,
            compare_mask,
            write_mask: s.stencil_write_mask,
            reference,
        };
        let depth_stencil = DepthStencilState {
            depth_test,
            depth_write: depth_test && s.depth_mask,
            depth_compare: s.depth_func,
            stencil_test,
            front: face,
            back: face,
        };
        let blend = s.blend.then(|| BlendState {
            color: BlendComponent { src: s.blend_func[0], dst: s.blend_func[1], op: s.blend_equation[0] },
            alpha: BlendComponent { src: s.blend_func[2], dst: s.blend_func[3], op: s.blend_equation[1] },
        });
        let write_mask = color_writes(s.color_mask);
        let writes = Writes {
            color: !targets.color.is_empty() && subpass_color && write_mask != ColorWrites::NONE,
            depth: depth_stencil.depth_write,
            stencil: stencil_test && (face.writes()),
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
        desc.color_targets = if targets.color.is_empty() || !subpass_color {
            Vec::new()
        } else {
            vec![ColorTargetState { blend, write_mask }]
        };
        desc.blend_constant = blend_constant;
        if let Some(q) = query.and_then(|q| self.queries.get_mut(&q)) {
            q.pending_draws += 1;
        }
        let pass = self.pass.as_mut().expect("ensured above");
        pass.buffers_used.extend(used);
        pass.retired_buffers.extend(client);
        pass.images_sampled.extend(program.textures.iter().map(|t| t.image));
        push_draw(
            pass,
            PendingDraw {
                call: here,
                kind: DrawKind::Draw,
                source: DrawSource::Program { program: program.source, textures: program.textures },
                desc,
                vertex_buffers,
                index: index_binding.map(|b| b.1),
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
        Ok(())
    }

    /// A draw sampled `image`: its last store has been read.
    pub(crate) fn sampled(&mut self, image: ImageId, frame: u32) {
        if let Some(info) = self.images.get_mut(&image) {
            info.last_use = Some(frame);
            let slot = if info.gl_format.is_color() { Slot::Color(0) } else { Slot::Depth };
            self.consume(image, slot);
        }
    }

    /// Flush: the open pass renders now, and drawing continues in a new pass (row 5).
    pub(crate) fn flush_open_pass(&mut self, cause: FlushCause) -> Fallible {
        self.outside_explicit_pass(cause.describe())?;
        if self.pass.as_ref().is_some_and(|p| p.has_work()) {
            self.end_open_pass(EndCause::Flush { flush: cause })?;
            self.next_start = (StartCause::AfterFlush { flush: cause }, self.here);
        }
        Ok(())
    }

    /// `glStartTilingQCOM`.
    pub(crate) fn start_tiling(&mut self, [x, y]: [i32; 2], [w, h]: [u32; 2], preserve: BufferSet) -> Fallible {
        if self.tiling.is_some() {
            return Err("start_tiling inside a tiled-rendering region: call end_tiling first".to_string());
        }
        self.outside_explicit_pass("start_tiling")?;
        let targets = self.targets(self.draw_framebuffer)?;
        let region = gl_rect(x as i64, y as i64, w as i64, h as i64, targets.width, targets.height);
        if region.area() == 0 {
            return Err(format!(
                "the region {w}×{h} at ({x}, {y}) does not meet the {}×{} framebuffer",
                targets.width, targets.height
            ));
        }
        if self.pass.as_ref().is_some_and(|p| p.has_work()) {
            self.end_open_pass(EndCause::Flush { flush: FlushCause::StartTiling })?;
        }
        self.pass = None;
        self.tiling = Some(Tiling { region, preserve, started: false });
        self.next_start = (StartCause::Tiling, self.here);
        Ok(())
    }

    /// `glEndTilingQCOM`.
    pub(crate) fn end_tiling(&mut self, store: BufferSet) -> Fallible {
        if self.tiling.is_none() {
            return Err("end_tiling without start_tiling".to_string());
        }
        let here = self.here;
        if let Some(pass) = &mut self.pass {
            for a in pass.aspects.iter_mut().filter(|a| a.role == Role::Attached) {
                let keep = match a.slot {
                    Slot::Color(_) => store.color,
                    Slot::Depth => store.depth,
                    Slot::Stencil => store.stencil,
                };
                if !keep {
                    a.store = StoreKind::DontCare;
                    a.store_reason = format!("not in end_tiling's store mask at {here}");
                }
            }
        }
        self.end_open_pass(EndCause::EndTiling)?;
        self.tiling = None;
        self.next_start = (StartCause::Bind, here);
        Ok(())
    }

    /// Ends the open pass: renders it if it has work, and keeps the books.
    pub(crate) fn end_open_pass(&mut self, cause: EndCause) -> Fallible {
        if cause != EndCause::EndPass {
            let what = match cause {
                EndCause::Bind => "binding another framebuffer",
                EndCause::Swap => "swap_buffers",
                EndCause::EndTiling => "end_tiling",
                EndCause::Copy => "copy_tex_sub_image",
                EndCause::End => super::explicit::END_OF_TRACE,
                EndCause::Flush { flush } => flush.describe(),
                EndCause::EndPass => unreachable!(),
            };
            self.outside_explicit_pass(what)?;
        }
        let Some(mut pass) = self.pass.take() else { return Ok(()) };
        let here = self.here;
        if cause == EndCause::Swap && pass.framebuffer == 0 && pass.copy_texture.is_none() {
            for a in pass.aspects.iter_mut() {
                if matches!(a.slot, Slot::Depth | Slot::Stencil)
                    && a.role == Role::Attached
                    && a.store == StoreKind::Store
                {
                    a.store = StoreKind::DontCare;
                    a.store_reason = "the window's depth and stencil are undefined after a swap (EGL)".to_string();
                }
            }
        }
        if let EndCause::Flush { .. } = cause {
            // The rest of the pass needs the samples: a flush keeps them.
            for a in pass.aspects.iter_mut() {
                if a.resolve.is_some() && !a.invalidated && !a.transient && a.store == StoreKind::DontCare {
                    a.store = StoreKind::Store;
                    a.store_reason = "the samples are kept for the rest of the pass, cut by a flush".to_string();
                }
            }
        }
        let full_area = pass.region.is_none_or(|r| r.area() == pass.targets.width as u64 * pass.targets.height as u64);
        if !pass.has_work() {
            // Nothing to render; what was invalidated is undefined from now on.
            for a in &pass.aspects {
                if a.invalidated && full_area {
                    self.undefine(a.image, a.slot, "invalidated");
                }
            }
            self.release(pass);
            return Ok(());
        }

        // The explicit render pass.
        let load_color = |a: &PassAspect| match a.load {
            LoadKind::Load => LoadOp::Load,
            LoadKind::Clear => LoadOp::Clear(a.clear),
            LoadKind::DontCare => LoadOp::DontCare,
        };
        let store = |a: &PassAspect| match a.store {
            StoreKind::Store => StoreOp::Store,
            StoreKind::DontCare => StoreOp::DontCare,
        };
        let color = pass
            .aspects
            .iter()
            .filter(|a| matches!(a.slot, Slot::Color(_)))
            .map(|a| ColorAttachment {
                image: a.image,
                load: load_color(a),
                store: store(a),
                resolve: a.resolve.filter(|_| !a.invalidated),
            })
            .collect();
        let depth_stencil = pass.targets.depth_stencil.map(|ds| {
            let find = |slot| pass.aspects.iter().find(|a| a.slot == slot);
            let (depth_load, depth_store) = match find(Slot::Depth) {
                Some(a) => (load_color(a).map(|c| c[0]), store(a)),
                None => (LoadOp::DontCare, StoreOp::DontCare),
            };
            let (stencil_load, stencil_store) = match find(Slot::Stencil) {
                Some(a) => (load_color(a).map(|c| c[0] as u8), store(a)),
                None => (LoadOp::DontCare, StoreOp::DontCare),
            };
            DepthStencilAttachment { image: ds.image, depth_load, depth_store, stencil_load, stencil_store }
        });
        let mut snapshots: HashMap<ImageId, Arc<TextureSnapshot>> = HashMap::new();
        let mut textures: HashMap<ImageId, Arc<tiler::Texture>> = HashMap::new();
        let mut draws = Vec::with_capacity(pass.draws.len());
        let mut extra = tiler::Ledger::default();
        for d in &pass.draws {
            let pipeline = match &d.source {
                DrawSource::Program { program, textures: sampled } => self.program_draw_pipeline(
                    program,
                    sampled,
                    &mut snapshots,
                    &mut textures,
                    pass.targets.height,
                    d.desc.clone(),
                )?,
                DrawSource::Clear { color, depth, targets } => clear_pipeline(*color, *depth, *targets, d.desc.clone()),
                DrawSource::Rectangle { image, ndc, tex, sampler, read_bytes } => {
                    extra.add(tiler::Category::TextureFetch, *read_bytes);
                    let snapshot = self.snapshot(&mut snapshots, *image)?;
                    blit_pipeline(*ndc, *tex, snapshot, *sampler, d.desc.clone())
                }
            }
            .map_err(|e| format!("draw recorded at {}: {e}", d.call))?;
            draws.push(Draw {
                pipeline,
                vertex_buffers: d.vertex_buffers.clone(),
                index_buffer: d.index,
                first: d.first,
                count: d.count,
                vertex_offset: 0,
                viewport: Some(d.viewport),
                scissor: d.scissor,
            });
        }
        let desc = RenderPassDesc { color, depth_stencil, render_area: pass.region };
        let mut render_pass = match &pass.explicit {
            Some(e) => {
                let mut p = RenderPass::with_subpasses(desc, e.subpasses.clone(), e.dependencies.clone());
                p.subpass_starts = e.starts.clone();
                p
            }
            None => RenderPass::new(desc),
        };
        render_pass.draws = draws;
        let report = match self.device.submit(&render_pass) {
            Ok(report) => report,
            Err(e) => {
                let at = match &e {
                    tiler::Error::Draw { draw, .. }
                    | tiler::Error::IndexOutOfRange { draw, .. }
                    | tiler::Error::NonFinitePosition { draw, .. } => {
                        pass.draws.get(*draw).map(|d| format!(" (the draw recorded at {})", d.call))
                    }
                    _ => None,
                };
                let what = match pass.copy_texture {
                    Some(t) => format!("the copy into texture {t}"),
                    None => format!("the render pass of framebuffer {} begun at {}", pass.framebuffer, pass.started_at),
                };
                self.release(pass);
                return Err(format!("{what} could not be rendered{}: {e}", at.unwrap_or_default()));
            }
        };

        // The books: queries, what was read and written, and the pass record.
        let index = self.passes_rendered;
        self.passes_rendered += 1;
        let frame = here.frame;
        self.last_submit_frame = Some(frame);
        for (d, stats) in pass.draws.iter().zip(&report.draws) {
            if let Some(q) = d.query.and_then(|q| self.queries.get_mut(&q)) {
                q.samples += stats.samples_passed;
                q.pending_draws = q.pending_draws.saturating_sub(1);
                q.last_frame = q.last_frame.max(frame);
            }
        }
        let area = match pass.region {
            Some(r) => r.area(),
            None => pass.targets.width as u64 * pass.targets.height as u64,
        };
        let samples = pass.targets.samples as u64;
        let mut attachments = Vec::new();
        for a in &pass.aspects {
            let info = &self.images[&a.image];
            let format = info.desc.format;
            let aspect_bytes = match a.slot {
                Slot::Color(_) => format.bytes_per_sample(),
                Slot::Depth => format.depth_aspect_bytes(),
                Slot::Stencil => format.stencil_aspect_bytes(),
            } as u64;
            let bytes = area * samples * aspect_bytes;
            let gl_format = info.gl_format;
            if a.load == LoadKind::Load {
                self.consume(a.image, a.slot);
            }
            match a.store {
                StoreKind::Store => {
                    let info = self.images.get_mut(&a.image).expect("attached image");
                    info.defined[defined_index(a.slot)] = true;
                    info.last_write = Some(frame);
                    self.register_store(a.image, a.slot, index, bytes, full_area);
                }
                StoreKind::DontCare if a.role == Role::Attached && full_area => {
                    self.undefine(a.image, a.slot, &format!("not stored by pass {index}"));
                }
                StoreKind::DontCare => {}
            }
            let mut resolve_bytes = 0;
            if let Some(resolve) = a.resolve.filter(|_| !a.invalidated) {
                let d = self.images[&resolve].desc;
                resolve_bytes = area * d.format.bytes_per_sample() as u64;
                let info = self.images.get_mut(&resolve).expect("resolve image");
                info.defined[0] = true;
                info.last_write = Some(frame);
                self.register_store(resolve, Slot::Color(0), index, resolve_bytes, full_area);
            }
            attachments.push(AttachmentRecord {
                slot: a.slot,
                image: a.image,
                format,
                gl_format,
                samples: pass.targets.samples,
                role: a.role,
                load: a.load,
                load_reason: a.load_reason.clone(),
                store: a.store,
                store_reason: a.store_reason.clone(),
                load_bytes: if a.load == LoadKind::Load { bytes } else { 0 },
                store_bytes: if a.store == StoreKind::Store { bytes } else { 0 },
                resolve: a.resolve.filter(|_| !a.invalidated),
                resolve_bytes,
            });
        }
        let draws = pass
            .draws
            .iter()
            .zip(&report.draws)
            .map(|(d, stats)| DrawRecord {
                call: d.call,
                kind: d.kind,
                program: match &d.source {
                    DrawSource::Program { program, .. } => program.kind(),
                    _ => None,
                },
                clip_rect: d.clip_rect,
                blend: d.desc.color_targets.iter().any(|t| t.blend.is_some()),
                depth_test: d.desc.depth_stencil.depth_test,
                depth_write: d.desc.depth_stencil.depth_write,
                discards: match &d.source {
                    DrawSource::Program { program, .. } => program.discards(),
                    _ => false,
                },
                texture_bytes: match &d.source {
                    DrawSource::Rectangle { read_bytes, .. } => *read_bytes,
                    _ => 0,
                },
                sampled: match &d.source {
                    DrawSource::Program { textures, .. } => textures.first().map(|t| t.image),
                    DrawSource::Rectangle { image, .. } => Some(*image),
                    DrawSource::Clear { .. } => None,
                },
                stats: *stats,
                partial_clear: d.partial_clear.clone(),
            })
            .collect();
        let record = PassRecord {
            index,
            frame,
            framebuffer: pass.framebuffer,
            copy_texture: pass.copy_texture,
            window_preserved: pass.window_preserved,
            width: pass.targets.width,
            height: pass.targets.height,
            samples: pass.targets.samples,
            render_area: pass.region,
            start: pass.start,
            started_at: pass.started_at,
            end: cause,
            ended_at: here,
            attachments,
            subpasses: render_pass.subpasses.clone(),
            dependencies: render_pass.dependencies.clone(),
            draw_subpasses: if pass.explicit.is_some() {
                (0..pass.draws.len()).map(|i| render_pass.subpass_of(i) as u32).collect()
            } else {
                Vec::new()
            },
            draws,
            dropped: std::mem::take(&mut pass.dropped),
            cost: PassCost::from(&report),
            extra,
        };
        self.frame.passes.push(record);
        self.release(pass);
        Ok(())
    }

    /// Frees what a finished pass held on to.
    fn release(&mut self, pass: OpenPass) {
        for (buffer, len) in pass.retired_buffers {
            self.free_buffer(buffer, len);
        }
        for image in pass.retired_images {
            self.free_image(image);
        }
    }

    /// What a textured draw samples: RGBA8 images through the core's sampler, others through
    /// a snapshot; each texture made once per submission.
    pub(crate) fn program_texture(
        &self,
        snapshots: &mut HashMap<ImageId, Arc<TextureSnapshot>>,
        textures: &mut HashMap<ImageId, Arc<tiler::Texture>>,
        image: ImageId,
        sampler: SamplerState,
        mipmaps: bool,
    ) -> Fallible<ProgramTexture> {
        let d = self.images[&image].desc;
        let color_space = match d.format {
            tiler::Format::Rgba8Unorm => tiler::ColorSpace::Linear,
            tiler::Format::Rgba8UnormSrgb => tiler::ColorSpace::Srgb,
            _ => return Ok(ProgramTexture::Snapshot(self.snapshot(snapshots, image)?, sampler)),
        };
        if d.samples != 1 {
            return Ok(ProgramTexture::Snapshot(self.snapshot(snapshots, image)?, sampler));
        }
        let mip_chain = if mipmaps { tiler::MipChain::Box } else { tiler::MipChain::BaseOnly };
        let texture = match textures.get(&image) {
            Some(t) => t.clone(),
            None => {
                let data = self.device.image_data(image).map_err(|e| e.to_string())?;
                let t = tiler::Texture::from_rgba8(d.width, d.height, data, color_space, mip_chain)
                    .map_err(|e| e.to_string())?;
                let t = Arc::new(t);
                textures.insert(image, t.clone());
                t
            }
        };
        let core_filter = |f: Filter| match f.base() {
            Filter::Nearest => tiler::Filter::Nearest,
            _ => tiler::Filter::Linear,
        };
        let filter = core_filter(sampler.filter);
        let mipmap = match sampler.filter.mipmap().filter(|_| mipmaps) {
            None => tiler::MipmapMode::None,
            Some(Filter::Nearest) => tiler::MipmapMode::Nearest,
            Some(_) => tiler::MipmapMode::Linear,
        };
        let wrap = match sampler.wrap {
            Wrap::ClampToEdge => tiler::Wrap::ClampToEdge,
            Wrap::Repeat => tiler::Wrap::Repeat,
            Wrap::MirroredRepeat => tiler::Wrap::MirroredRepeat,
        };
        let core = tiler::Sampler {
            mag_filter: filter,
            min_filter: filter,
            mipmap,
            wrap_u: wrap,
            wrap_v: wrap,
            lod_bias: 0.0,
        };
        Ok(ProgramTexture::Core(texture, core))
    }

    /// The decoded texels of an image, once per submission.
    pub(crate) fn snapshot(
        &self,
        cache: &mut HashMap<ImageId, Arc<TextureSnapshot>>,
        image: ImageId,
    ) -> Fallible<Arc<TextureSnapshot>> {
        if let Some(s) = cache.get(&image) {
            return Ok(s.clone());
        }
        let d = self.images[&image].desc;
        let snapshot = if d.format.is_color() {
            let data = self.device.image_data(image).map_err(|e| e.to_string())?.to_vec();
            Arc::new(TextureSnapshot::color(d.width, d.height, d.format, d.samples, data))
        } else {
            let depths = self.device.read_depth(image).map_err(|e| e.to_string())?;
            Arc::new(TextureSnapshot::depth(d.width, d.height, depths))
        };
        cache.insert(image, snapshot.clone());
        Ok(snapshot)
    }

    /// Records a textured rectangle (a blit) into the open pass.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn push_rectangle(
        &mut self,
        kind: DrawKind,
        image: ImageId,
        dst: Rect,
        ndc: [f32; 4],
        tex: [f32; 4],
        filter: Filter,
        read_bytes: u64,
        scissor: Option<Rect>,
    ) -> Fallible {
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
                    sampler: SamplerState { filter, wrap: Wrap::ClampToEdge },
                    read_bytes,
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

/// Gathers a draw; an aspect it writes after an invalidate is stored again.
fn push_draw(pass: &mut OpenPass, draw: PendingDraw) {
    for a in pass.aspects.iter_mut() {
        if a.invalidated && !a.transient && a.role == Role::Attached && draw.writes.writes(a.slot) {
            a.invalidated = false;
            a.store = StoreKind::Store;
            a.store_reason = format!("written at {} after being invalidated", draw.call);
        }
    }
    pass.draws.push(draw);
}

/// A clear defines the contents again: an invalidated aspect is stored after all.
fn restore_store(a: &mut PassAspect, here: CallRef) {
    if a.invalidated && !a.transient {
        a.invalidated = false;
        a.store = StoreKind::Store;
        a.store_reason = format!("cleared at {here} after being invalidated");
    }
}

/// GL's colour mask as tiler's write mask.
fn color_writes(mask: [bool; 4]) -> ColorWrites {
    let bits = [ColorWrites::RED, ColorWrites::GREEN, ColorWrites::BLUE, ColorWrites::ALPHA];
    ColorWrites(mask.iter().zip(bits).filter(|(on, _)| **on).fold(0, |acc, (_, b)| acc | b.0))
}

trait MapLoad<T> {
    fn map<U>(self, f: impl FnOnce(T) -> U) -> LoadOp<U>;
}

impl<T> MapLoad<T> for LoadOp<T> {
    fn map<U>(self, f: impl FnOnce(T) -> U) -> LoadOp<U> {
        match self {
            LoadOp::Load => LoadOp::Load,
            LoadOp::Clear(v) => LoadOp::Clear(f(v)),
            LoadOp::DontCare => LoadOp::DontCare,
        }
    }
}
