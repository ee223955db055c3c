//! Render-pass inference: how GL calls become passes with load and store ops. What a draw
//! becomes in tiler's terms is `draw.rs`'s; rendering an ended pass is `submit.rs`'s.
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
//! | exceeds the frame-data budget | incremental render (in the core: the tbr backend) | — |
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

use std::collections::HashSet;

use tiler::{
    BufferId, ColorTargetState, ColorWrites, CompareOp, DepthStencilState, ImageId, PipelineDesc, Rect,
    StencilFaceState, StencilOp, VertexInputState, Viewport,
};

use super::draw::{DrawSource, PendingDraw, color_writes, gl_rect, intersect};
use super::targets::Targets;
use super::{Context, Fallible, Tiling};
use crate::call::BufferSet;
use crate::report::{
    CallRef, DrawKind, Dropped, EndCause, FlushCause, LoadKind, PartialClear, Role, Slot, StartCause, StoreKind,
};

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
        let s = &self.state;
        let request = ClearRequest {
            color: buffers.color.then_some((None, s.clear_color)),
            depth: buffers.depth.then_some(s.clear_depth),
            stencil: buffers.stencil.then_some(s.clear_stencil),
        };
        self.clear_with(request)
    }

    /// `glClearBuffer*`: one colour attachment (`color.0`, `None`: every one) and/or depth
    /// and stencil, to the values given, as `glClear` clears (the same load-op inference). A
    /// colour value is given as its bits for an integer attachment (see `tiler::IntFormat`).
    pub(crate) fn clear_with(&mut self, request: ClearRequest) -> Fallible {
        let here = self.here;
        let s = &self.state;
        let (scissor_test, scissor, color_mask, depth_mask, stencil_mask) =
            (s.scissor_test, s.scissor, s.color_mask, s.depth_mask, s.stencil[0].write_mask);
        let clear_color = request.color.map_or([0.0; 4], |(_, c)| c);
        let clear_depth = request.depth.unwrap_or(s.clear_depth);
        let clear_stencil = request.stencil.unwrap_or(s.clear_stencil);
        let color_target = request.color.and_then(|(t, _)| t);
        let buffers = BufferSet {
            color: request.color.is_some(),
            depth: request.depth.is_some(),
            stencil: request.stencil.is_some(),
        };
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
                    Slot::Color(i) => (
                        buffers.color && color_target.is_none_or(|t| t == i),
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
            desc.color_targets = (0..pass.targets.color.len())
                .map(|i| ColorTargetState {
                    blend: None,
                    write_mask: if quad_slots.contains(&Slot::Color(i as u8)) { mask } else { ColorWrites::NONE },
                })
                .collect();
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

    /// `glClearBuffer*v` of one colour buffer: `draw_buffer` must be one of the framebuffer's
    /// draw buffers, and `value` of its kind (GL ES 3.0 §4.2.3 leaves a mismatch undefined:
    /// refused).
    pub(crate) fn clear_buffer_color(&mut self, draw_buffer: u32, value: crate::call::ClearColorValue) -> Fallible {
        use crate::call::ClearColorValue as V;
        let framebuffer = self.draw_framebuffer;
        let draw_buffers = self.framebuffers.get(&framebuffer).map_or(1, |fb| fb.draw_buffers.unwrap_or(1));
        if draw_buffer >= draw_buffers {
            // GL: a draw buffer set to NONE is not cleared.
            return Ok(());
        }
        let format = self.ensure_pass()?.targets.color.get(draw_buffer as usize).map(|t| t.format.format());
        let Some(format) = format else { return Ok(()) };
        let bits = match (value, format) {
            (V::Float(v), f) if !f.is_integer() => super::finite4("clear colour", v)?,
            (V::Int(v), tiler::Format::Int(f)) if f.signed => v.map(|c| f32::from_bits(c as u32)),
            (V::Uint(v), tiler::Format::Int(f)) if !f.signed => v.map(f32::from_bits),
            (value, f) => {
                return Err(format!(
                    "glClearBuffer of draw buffer {draw_buffer} ({f}) with {value:?}: the value's type does not match                      the format (GL leaves that undefined)"
                ));
            }
        };
        let color = Some((Some(draw_buffer as u8), bits));
        self.clear_with(ClearRequest { color, depth: None, stencil: None })
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
}

/// Gathers a draw; an aspect it writes after an invalidate is stored again.
pub(super) fn push_draw(pass: &mut OpenPass, draw: PendingDraw) {
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

/// What a clear clears, with its values: the colour attachment (`None`: every one) and its
/// value, the depth, the stencil.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ClearRequest {
    pub color: Option<(Option<u8>, [f32; 4])>,
    pub depth: Option<f32>,
    pub stencil: Option<u8>,
}
