//! The advisor's advice, proven by re-running: each finding's fix applied to the trace's
//! calls, the trace replayed, and what it saved measured beside what the finding estimated,
//! with a check that the picture is unchanged.
//!
//! A fix is an edit of the calls, not of the passes, so the replay goes through the same
//! driver inference as the original: `store-unread` invalidates the attachment before the
//! call that ends its pass; `load-at-pass-start` clears the loaded attachments right after
//! the bind; `framebuffer-rebound` moves the other framebuffers' work (the calls between the
//! first binding's last drawing and the second binding) before the first binding's first
//! drawing, each part run in the GL state it had ([`Call::RestoreState`] with the state a
//! replay of the original calls had there: GL state is global, and the moved work often uses
//! a program or uniforms set while the first framebuffer was still bound); `flush-mid-pass` moves the flushing call (a read
//! of pixels, a flush, a finish) to the end of the pass it cut short — before a swap, after
//! invalidating the window's depth and stencil, which the swap would throw away anyway;
//! `unsorted-opaque` reverses the order of the pass's opaque draws (each with the state calls
//! before it), the usual back-to-front submission turned front to back; `partial-clear`, for
//! a clear made a clear-quad by the scissor test alone with a box covering the framebuffer,
//! disables the test around the clear (a smaller box keeps what lies outside it: no fix). The
//! other rules change the content of the frame (geometry, shaders, formats) and have no
//! automatic fix. `msaa-stored` renders the finding's frame to a multisampled texture resolved in
//! the tile (a framebuffer and texture made for that frame) and has the frame's blits read
//! the resolved texture.

use tiler_finding::WhatIf;

use super::{Finding, RuleId};
use crate::call::{AttachmentPoint, Call};
use crate::context::{ContextConfig, SavedState};
use crate::report::{CallRef, PassRecord, Report, Slot, first_different_frame};
use crate::trace::{Trace, TraceFrame};

/// A run of a trace that [`prove`] compares its fixed replays with.
pub struct Run<'a> {
    /// The configuration it ran with; it must record the presented pictures
    /// ([`ContextConfig::digest_presented`]).
    pub config: &'a ContextConfig,
    pub report: &'a Report,
    /// The window's picture at the end (RGBA8), for what no swap presented.
    pub picture: &'a [u8],
}

/// Applies each finding of `run` alone to the trace's calls, replays the fixed trace as `run`
/// ran, and returns, per finding in order, what the fix saved beside what the finding
/// estimated (labelled `device`) and whether every presented picture stayed the same. A fix
/// whose edited calls fail to replay is reported as not applied, with the replay's error.
///
/// On a device with transaction elimination, stores of tiles whose content repeats what
/// memory holds are skipped, which depends on the pictures, not on the pattern the finding is
/// about: the estimate prices the stores as made, so the measured saving it is compared with
/// (`measured_bytes_before_elimination`) counts the stores elimination skipped as moved, and
/// `measured_bytes` says what the device moved fewer.
///
/// # Errors
/// A run whose configuration did not record the presented pictures, or a trace too long to
/// edit ([`MAX_WHAT_IF_CALLS`]).
pub fn prove(trace: &Trace, run: &Run, device: &str) -> Result<Vec<WhatIf>, String> {
    if !run.config.digest_presented {
        return Err("the run did not record its presented pictures (ContextConfig::digest_presented)".into());
    }
    let before = run.report.totals.ledger.total() as i64;
    let eliminated = |r: &Report| r.transaction_elimination_saved() as i64;
    let shaded = |r: &Report| r.totals.counters.fragments_shaded as i64;
    let mut results = Vec::with_capacity(run.report.findings.len());
    for finding in &run.report.findings {
        let mut fixer = Fixer::new(trace)?;
        let mut result = WhatIf {
            device: device.to_string(),
            estimated_bytes: finding.cost_bytes,
            estimated_fragments: finding.cost_fragments,
            ..WhatIf::default()
        };
        let fix = match fixer.add(finding, run.report) {
            Ok(fix) => fix,
            Err(why) => {
                result.fix = why;
                results.push(result);
                continue;
            }
        };
        let mut fixed = fixer.fixed(trace);
        fixed.config = run.config.clone();
        let replay = match fixed.replay() {
            Ok(replay) => replay,
            Err(e) => {
                result.fix = format!("{fix}: not applied, the edited calls fail: {e}");
                results.push(result);
                continue;
            }
        };
        let measured = before - replay.report.totals.ledger.total() as i64;
        let before_elimination = measured + eliminated(run.report) - eliminated(&replay.report);
        let different = first_different_frame(&run.report.frames, &replay.report.frames).or_else(|| {
            (replay.context.surface_rgba8() != run.picture)
                .then_some(run.report.frames.len().max(replay.report.frames.len()) as u32)
        });
        results.push(WhatIf {
            fix,
            applied: true,
            measured_bytes: Some(measured),
            measured_bytes_before_elimination: (before_elimination != measured).then_some(before_elimination),
            measured_fragments: Some(shaded(run.report) - shaded(&replay.report)),
            same_picture: Some(different.is_none()),
            different_frame: different.map(u64::from),
            ..result
        });
    }
    Ok(results)
}

/// The first of the names (textures, framebuffers) a fix creates: three per frame from here,
/// far above the names applications use.
pub const FIX_NAMES: u32 = 0x7000_0000;

/// The most calls (repeats expanded) a trace may have for fixes to be applied.
pub const MAX_WHAT_IF_CALLS: usize = 1 << 20;

/// Edits of one frame's calls, by the original call's index.
#[derive(Clone, Debug, Default)]
struct FrameEdits {
    /// Calls to put before call `i`.
    before: Vec<(usize, Vec<Call>)>,
    /// Calls to put after call `i`.
    after: Vec<(usize, Vec<Call>)>,
    /// Calls taken away from where they were (they were put elsewhere).
    moved: Vec<std::ops::Range<usize>>,
}

/// A trace's calls frame by frame (repeats expanded), and the edits to make.
pub struct Fixer {
    frames: Vec<Vec<Call>>,
    edits: Vec<FrameEdits>,
    /// The trace's configuration, to replay it for the state at a call.
    config: ContextConfig,
}

impl Fixer {
    /// The calls of `trace`, one list per frame as the report numbers them.
    ///
    /// # Errors
    /// More than [`MAX_WHAT_IF_CALLS`] calls once repeats are expanded.
    pub fn new(trace: &Trace) -> Result<Fixer, String> {
        let total: u64 = trace.frames.iter().map(|f| f.repeat as u64 * f.calls.len() as u64).sum();
        if total > MAX_WHAT_IF_CALLS as u64 {
            return Err(format!(
                "the trace has {total} calls once its repeats are expanded; fixes are applied to at most \
                 {MAX_WHAT_IF_CALLS}"
            ));
        }
        // Frames end at each swap_buffers, as the context numbers them.
        let mut frames: Vec<Vec<Call>> = vec![Vec::new()];
        for entry in &trace.frames {
            for _ in 0..entry.repeat {
                for call in &entry.calls {
                    let swap = matches!(call, Call::SwapBuffers);
                    frames.last_mut().expect("at least one frame").push(call.clone());
                    if swap {
                        frames.push(Vec::new());
                    }
                }
            }
        }
        if frames.last().is_some_and(Vec::is_empty) && frames.len() > 1 {
            frames.pop();
        }
        let edits = vec![FrameEdits::default(); frames.len()];
        Ok(Fixer { frames, edits, config: trace.config.clone() })
    }

    fn call(&self, at: CallRef) -> Option<&Call> {
        self.frames.get(at.frame as usize)?.get(at.call as usize)
    }

    /// Records the fix of `finding`; `Err` says why it has none.
    ///
    /// # Errors
    /// A rule without an automatic fix, or a finding whose calls cannot be found.
    pub fn add(&mut self, finding: &Finding, report: &Report) -> Result<String, String> {
        let rule = RuleId::from_name(&finding.id).ok_or_else(|| format!("unknown rule {}", finding.id))?;
        let pass = finding.location.pass.and_then(|p| report.passes().find(|q| q.index as u64 == p));
        let pass = pass.ok_or_else(|| "the finding names no pass".to_string());
        match rule {
            RuleId::StoreUnread => {
                let pass = pass?;
                let slots = slots_in(&finding.message, pass);
                if slots.is_empty() {
                    return Err("the finding names no attachment".into());
                }
                let attachments = slots.iter().map(|&slot| attachment_point(slot)).collect();
                self.before(pass.ended_at, vec![Call::Invalidate { attachments }])?;
                let names: Vec<String> = slots.iter().map(Slot::to_string).collect();
                Ok(format!("invalidate {} before {}", names.join(" and "), pass.ended_at))
            }
            RuleId::LoadAtPassStart => {
                let pass = pass?;
                let loaded = |s: fn(&Slot) -> bool| {
                    pass.attachments.iter().any(|a| a.load == crate::report::LoadKind::Load && s(&a.slot))
                };
                let clear = Call::Clear {
                    color: loaded(|s| matches!(s, Slot::Color(_))),
                    depth: loaded(|s| *s == Slot::Depth),
                    stencil: loaded(|s| *s == Slot::Stencil),
                };
                self.after(pass.started_at, vec![clear])?;
                Ok(format!("clear what was loaded right after {}", pass.started_at))
            }
            RuleId::FramebufferRebound => {
                let pass = pass?;
                let earlier = report
                    .passes()
                    .filter(|q| q.frame == pass.frame && q.framebuffer == pass.framebuffer && q.index < pass.index)
                    .filter(|q| q.copy_texture.is_none())
                    .last()
                    .ok_or("no earlier pass on the framebuffer")?;
                let (from, to) = (earlier.ended_at, pass.started_at);
                if from.frame != to.frame || earlier.started_at.frame != from.frame || from.call >= to.call {
                    return Err("the two bindings are not in one frame".into());
                }
                // Just before the first pass's first drawing: after whatever the calls before
                // it created (the objects the moved calls use, in a frame that sets up).
                let first_work = (earlier.started_at.call..from.call)
                    .find(|&i| self.frames[from.frame as usize].get(i as usize).is_some_and(changes_framebuffer));
                let to_first = CallRef::new(from.frame, first_work.unwrap_or(earlier.started_at.call));
                // The other framebuffers' work moves with what the first pass's binding set up
                // for it after its last drawing (the program and uniforms of a shadow-map pass,
                // set while the window was still bound), and each part runs in the GL state it
                // ran in: GL state is global.
                let frame = from.frame as usize;
                let drawn = (earlier.started_at.call as usize..from.call as usize)
                    .rev()
                    .find(|&i| self.frames[frame].get(i).is_some_and(changes_framebuffer))
                    .map_or(to_first.call as usize, |i| i + 1);
                let tail = CallRef::new(from.frame, drawn as u32);
                let [first, moved, after] = self.states_at([to_first, tail, to])?;
                let range = drawn..to.call as usize;
                let mut calls = vec![Call::RestoreState { state: moved }];
                calls.extend(self.frames[frame][range.clone()].iter().cloned());
                calls.push(Call::RestoreState { state: first });
                self.move_before_as(frame, range, to_first, calls)?;
                // The first framebuffer stays bound into the second binding, which continues
                // its pass.
                self.before(to, vec![Call::RestoreState { state: after.without_framebuffers() }])?;
                Ok(format!(
                    "move calls {drawn}–{} of frame {} before {to_first}, each part in the GL state it had",
                    to.call - 1,
                    from.frame
                ))
            }
            RuleId::FlushMidPass => {
                let at = finding.location.call_at.map(CallRef::from).ok_or("the finding names no call")?;
                if !matches!(
                    self.call(at),
                    Some(
                        Call::ReadPixels { .. }
                            | Call::ReadPixelsInteger { .. }
                            | Call::Flush
                            | Call::Finish
                            | Call::QueryResult { .. }
                    )
                ) {
                    return Err("only a read_pixels, query_result, flush or finish is moved".into());
                }
                // To the end of the pass it cut short: just before the call that ends the
                // pass drawing went on in.
                let flushed = pass?;
                let rest = report
                    .passes()
                    .find(|p| {
                        p.frame == flushed.frame && p.framebuffer == flushed.framebuffer && p.index > flushed.index
                    })
                    .ok_or("no pass after the flush")?;
                let to = rest.ended_at;
                if to.frame != at.frame || to.call <= at.call {
                    return Err("the pass does not end later in the frame".into());
                }
                // Before a swap, the window's depth and stencil would be stored with its
                // colour, though the swap would have thrown them away: invalidate them first.
                let window =
                    rest.framebuffer == 0 && !rest.window_preserved && matches!(self.call(to), Some(Call::SwapBuffers));
                let discarded: Vec<AttachmentPoint> = rest
                    .attachments
                    .iter()
                    .filter(|a| a.role == crate::report::Role::Attached && a.slot != Slot::Color(0))
                    .map(|a| attachment_point(a.slot))
                    .collect();
                if window && !discarded.is_empty() {
                    self.before(to, vec![Call::Invalidate { attachments: discarded }])?;
                }
                let call = at.call as usize;
                self.move_before(at.frame as usize, call..call + 1, to)?;
                let invalidated = if window { ", the window's depth and stencil invalidated first" } else { "" };
                Ok(format!("move {at} to just before {to}, the end of the pass{invalidated}"))
            }
            RuleId::MsaaStored => {
                let pass = pass?;
                self.resolve_in_tile(pass)
            }
            RuleId::PartialClear => {
                // A clear made a clear-quad only by the scissor test: clear with it off.
                let at = finding.location.call_at.map(CallRef::from).ok_or("the finding names no call")?;
                if !matches!(self.call(at), Some(Call::Clear { .. })) {
                    return Err("the finding names no clear".into());
                }
                let pass = pass?;
                let quad = pass.draws.iter().find(|d| d.call == at);
                let reasons =
                    quad.and_then(|d| d.partial_clear.as_ref()).map(|pc| pc.reasons.clone()).unwrap_or_default();
                // A box smaller than the framebuffer keeps what lies outside it: clearing
                // without it would change the picture, and the advice is then to keep it.
                if quad.is_some_and(|d| d.clip_rect.area() < pass.width as u64 * pass.height as u64) {
                    return Err("the scissor box is smaller than the framebuffer: without it the clear would clear \
                                more; keep the scissor around the pass or use a tiled-rendering region, as advised"
                        .into());
                }
                if reasons.is_empty() || reasons.iter().any(|r| !r.contains("scissor")) {
                    return Err(format!(
                        "only a clear made partial by the scissor test alone is fixed automatically (this one: {})",
                        reasons.join(", ")
                    ));
                }
                use crate::call::Capability;
                self.before(at, vec![Call::Disable { cap: Capability::ScissorTest }])?;
                self.after(at, vec![Call::Enable { cap: Capability::ScissorTest }])?;
                Ok(format!("disable the scissor test around the clear at {at}"))
            }
            RuleId::UnsortedOpaque => {
                let pass = pass?;
                self.reverse_opaque_draws(pass)?;
                Ok(format!(
                    "reverse the order of the {} opaque draws of pass {} (back to front becomes front to back)",
                    pass.draws.len(),
                    pass.index
                ))
            }
            _ => Err(format!("{} has no automatic fix: it changes the frame's content", finding.id)),
        }
    }

    /// Reverses the order of a pass's draws, each with the state calls just before it (the
    /// calls since the draw before it, or since the pass's last clear or bind for the first).
    /// Only for a pass whose draws are all opaque application draws in one frame, each
    /// setting its own state: a draw relying on state an earlier draw set would change.
    fn reverse_opaque_draws(&mut self, pass: &PassRecord) -> Result<(), String> {
        use crate::report::DrawKind;
        let opaque = |d: &crate::report::DrawRecord| {
            d.kind == DrawKind::Draw && d.depth_test && d.depth_write && !d.blend && !d.discards
        };
        if pass.draws.len() < 2 || !pass.draws.iter().all(opaque) {
            return Err("only a pass of opaque draws alone is reordered".into());
        }
        let frame = pass.draws[0].call.frame;
        if pass.draws.iter().any(|d| d.call.frame != frame) || pass.started_at.frame != frame {
            return Err("the pass spans frames".into());
        }
        let calls = &self.frames[frame as usize];
        let first = pass.draws[0].call.call as usize;
        let mut start = first;
        while start > pass.started_at.call as usize + 1
            && !calls.get(start - 1).is_some_and(|c| {
                is_draw(c)
                    || matches!(
                        c,
                        Call::Clear { .. }
                            | Call::ClearBufferColor { .. }
                            | Call::ClearBufferDepthStencil { .. }
                            | Call::BindFramebuffer { .. }
                    )
            })
        {
            start -= 1;
        }
        let mut segments = Vec::with_capacity(pass.draws.len());
        let mut from = start;
        for d in &pass.draws {
            let end = d.call.call as usize + 1;
            segments.push(calls[from..end].to_vec());
            from = end;
        }
        // Each draw must set what it draws with: its vertex data (its own attribute pointer).
        if segments.iter().any(|s| !s.iter().any(|c| matches!(c, Call::VertexAttribPointer { .. }))) {
            return Err("a draw relies on vertex state set by the one before it".into());
        }
        let reordered: Vec<Call> = segments.into_iter().rev().flatten().collect();
        let edits = &mut self.edits[frame as usize];
        if edits.moved.iter().any(|m| m.start < from && start < m.end) {
            return Err("the calls are already moved".into());
        }
        edits.moved.push(start..from);
        edits.before.push((start, reordered));
        Ok(())
    }

    /// `msaa-stored`: the pass renders to a multisampled texture resolved in the tile
    /// (`framebuffer_texture` with samples) instead of the multisampled colour renderbuffer,
    /// through a framebuffer made for this frame with the same other attachments; the reads
    /// of the framebuffer that follow in the frame (a blit's `bind_framebuffer` for reading)
    /// read the single-sampled texture. Only this frame changes, as the finding prices it.
    fn resolve_in_tile(&mut self, pass: &PassRecord) -> Result<String, String> {
        use crate::call::FramebufferTarget;
        let at = pass.started_at;
        let (target, fb) = match self.call(at) {
            Some(Call::BindFramebuffer { target, framebuffer })
                if *target != FramebufferTarget::Read && *framebuffer == pass.framebuffer && *framebuffer != 0 =>
            {
                (*target, *framebuffer)
            }
            _ => return Err("the pass does not begin by binding an application framebuffer".into()),
        };
        // The framebuffer's attachments as the calls up to the bind left them.
        let mut attached: Vec<(AttachmentPoint, Call)> = Vec::new();
        let mut renderbuffers: std::collections::HashMap<u32, (u32, u32, crate::call::TextureFormat, u32)> =
            std::collections::HashMap::new();
        let upto = self.frames[..=at.frame as usize].iter().enumerate().flat_map(|(f, calls)| {
            let end = if f == at.frame as usize { at.call as usize } else { calls.len() };
            calls[..end].iter()
        });
        for call in upto {
            match call {
                Call::CreateRenderbuffer { id, width, height, format, samples, .. } => {
                    renderbuffers.insert(*id, (*width, *height, *format, *samples));
                }
                Call::FramebufferRenderbuffer { framebuffer, attachment, .. }
                | Call::FramebufferTexture { framebuffer, attachment, .. }
                    if *framebuffer == fb =>
                {
                    attached.retain(|(point, _)| point != attachment);
                    attached.push((*attachment, call.clone()));
                }
                _ => {}
            }
        }
        let color = attached.iter().find(|(point, _)| *point == AttachmentPoint::Color0).map(|(_, c)| c);
        let Some(Call::FramebufferRenderbuffer { renderbuffer, .. }) = color else {
            return Err("only a multisampled colour renderbuffer at color0 is replaced".into());
        };
        let Some(&(width, height, format, samples)) = renderbuffers.get(renderbuffer) else {
            return Err(format!("renderbuffer {renderbuffer} is not created by the calls"));
        };
        if samples <= 1
            || attached.iter().any(|(point, _)| {
                !matches!(
                    point,
                    AttachmentPoint::Color0
                        | AttachmentPoint::Depth
                        | AttachmentPoint::Stencil
                        | AttachmentPoint::DepthStencil
                )
            })
        {
            return Err("only a framebuffer with one multisampled colour attachment is changed".into());
        }
        // Names of this frame's own: far above what applications use.
        let base = FIX_NAMES + 3 * at.frame;
        let (draw_fb, read_fb, texture) = (base, base + 1, base + 2);
        let mut setup = vec![
            Call::CreateTexture { id: texture, width, height, format, data: None, transient: false },
            Call::CreateFramebuffer { id: draw_fb },
            Call::FramebufferTexture { framebuffer: draw_fb, attachment: AttachmentPoint::Color0, texture, samples },
        ];
        for (_, call) in attached.iter().filter(|(point, _)| *point != AttachmentPoint::Color0) {
            setup.push(match call.clone() {
                Call::FramebufferRenderbuffer { attachment, renderbuffer, .. } => {
                    Call::FramebufferRenderbuffer { framebuffer: draw_fb, attachment, renderbuffer }
                }
                Call::FramebufferTexture { attachment, texture, samples, .. } => {
                    Call::FramebufferTexture { framebuffer: draw_fb, attachment, texture, samples }
                }
                other => other,
            });
        }
        setup.push(Call::CreateFramebuffer { id: read_fb });
        setup.push(Call::FramebufferTexture {
            framebuffer: read_fb,
            attachment: AttachmentPoint::Color0,
            texture,
            samples: 1,
        });
        setup.push(Call::BindFramebuffer { target, framebuffer: draw_fb });
        let frame = at.frame as usize;
        let bind = at.call as usize;
        // The reads that follow in the frame, until the framebuffer is drawn to again.
        let mut reads = Vec::new();
        for (i, call) in self.frames[frame].iter().enumerate().skip(pass.ended_at.call as usize) {
            match call {
                Call::BindFramebuffer { target: FramebufferTarget::Read, framebuffer } if *framebuffer == fb => {
                    reads.push(i)
                }
                Call::BindFramebuffer { framebuffer, .. } if *framebuffer == fb => break,
                _ => {}
            }
        }
        let edits = &mut self.edits[frame];
        if edits.moved.iter().any(|m| m.contains(&bind) || reads.iter().any(|r| m.contains(r))) {
            return Err("the calls are already moved".into());
        }
        edits.moved.push(bind..bind + 1);
        edits.before.push((bind, setup));
        for &i in &reads {
            edits.moved.push(i..i + 1);
            edits
                .before
                .push((i, vec![Call::BindFramebuffer { target: FramebufferTarget::Read, framebuffer: read_fb }]));
        }
        Ok(format!(
            "render frame {}'s pass on framebuffer {fb} to a {samples}× multisampled texture resolved in the tile \
             (framebuffer_texture with samples) instead of renderbuffer {renderbuffer}, and read the resolved texture \
             in the {} read(s) that follow",
            at.frame,
            reads.len()
        ))
    }

    fn check(&self, at: CallRef) -> Result<(), String> {
        let frame = self.frames.get(at.frame as usize).ok_or_else(|| format!("no frame {}", at.frame))?;
        if at.call as usize > frame.len() {
            return Err(format!("no call {at}"));
        }
        Ok(())
    }

    fn before(&mut self, at: CallRef, calls: Vec<Call>) -> Result<(), String> {
        self.check(at)?;
        self.edits[at.frame as usize].before.push((at.call as usize, calls));
        Ok(())
    }

    fn after(&mut self, at: CallRef, calls: Vec<Call>) -> Result<(), String> {
        self.check(at)?;
        self.edits[at.frame as usize].after.push((at.call as usize, calls));
        Ok(())
    }

    /// Moves calls `range` of `frame` to just before `to` (in the same frame; `to.call` may
    /// be the frame's length: its end).
    fn move_before(&mut self, frame: usize, range: std::ops::Range<usize>, to: CallRef) -> Result<(), String> {
        let calls = self.frames[frame][range.clone()].to_vec();
        self.move_before_as(frame, range, to, calls)
    }

    /// [`Fixer::move_before`], putting `calls` (the moved calls, edited) where they go.
    fn move_before_as(
        &mut self,
        frame: usize,
        range: std::ops::Range<usize>,
        to: CallRef,
        calls: Vec<Call>,
    ) -> Result<(), String> {
        self.check(to)?;
        let edits = &mut self.edits[frame];
        if edits.moved.iter().any(|m| m.start < range.end && range.start < m.end) || range.contains(&(to.call as usize))
        {
            return Err("the calls are already moved".into());
        }
        edits.moved.push(range);
        edits.before.push((to.call as usize, calls));
        Ok(())
    }

    /// The GL state just before each of `at` (in the order given), from a replay of the
    /// original calls up to the last of them.
    fn states_at<const N: usize>(&self, at: [CallRef; N]) -> Result<[SavedState; N], String> {
        let last = at.iter().copied().max_by_key(|c| (c.frame, c.call)).ok_or("no call")?;
        let mut gl = crate::Context::new(self.config.clone())?;
        let mut found: [Option<SavedState>; N] = std::array::from_fn(|_| None);
        'frames: for (f, calls) in self.frames.iter().enumerate() {
            for (c, call) in calls.iter().enumerate().chain(std::iter::once((calls.len(), &Call::Finish))) {
                let here = CallRef::new(f as u32, c as u32);
                for (slot, point) in found.iter_mut().zip(&at) {
                    if *point == here {
                        *slot = Some(gl.saved_state());
                    }
                }
                if here == last {
                    break 'frames;
                }
                if c == calls.len() {
                    break;
                }
                gl.call(call.clone()).map_err(|e| format!("replaying for the state at {here}: {}", e.message))?;
            }
        }
        let mut states = found.into_iter();
        let out: [Option<SavedState>; N] = std::array::from_fn(|_| states.next().flatten());
        if out.iter().any(Option::is_none) {
            return Err(format!("no call {last} in the trace"));
        }
        Ok(out.map(|s| s.expect("checked above")))
    }

    /// The trace with every recorded fix applied (each frame once: repeats expanded).
    pub fn fixed(&self, trace: &Trace) -> Trace {
        let mut frames = Vec::with_capacity(self.frames.len());
        for (calls, edits) in self.frames.iter().zip(&self.edits) {
            let mut out = Vec::with_capacity(calls.len() + 4);
            let at = |list: &Vec<(usize, Vec<Call>)>, i: usize, out: &mut Vec<Call>| {
                for (_, calls) in list.iter().filter(|(j, _)| *j == i) {
                    out.extend(calls.iter().cloned());
                }
            };
            for (i, call) in calls.iter().enumerate() {
                at(&edits.before, i, &mut out);
                if !edits.moved.iter().any(|m| m.contains(&i)) {
                    out.push(call.clone());
                }
                at(&edits.after, i, &mut out);
            }
            at(&edits.before, calls.len(), &mut out);
            frames.push(TraceFrame { repeat: 1, calls: out });
        }
        Trace { description: trace.description.clone(), config: trace.config.clone(), frames }
    }
}

/// Whether a call is a draw (of any kind).
fn is_draw(call: &Call) -> bool {
    matches!(
        call,
        Call::DrawArrays { .. }
            | Call::DrawElements { .. }
            | Call::DrawArraysInstanced { .. }
            | Call::DrawElementsInstanced { .. }
    )
}

/// Whether a call draws, clears, invalidates, copies, reads or flushes: work on a framebuffer,
/// not state.
fn changes_framebuffer(call: &Call) -> bool {
    is_draw(call)
        || matches!(
            call,
            Call::Clear { .. }
                | Call::ClearBufferColor { .. }
                | Call::ClearBufferDepthStencil { .. }
                | Call::Invalidate { .. }
                | Call::ReadPixels { .. }
                | Call::ReadPixelsInteger { .. }
                | Call::BlitFramebuffer { .. }
                | Call::CopyTexSubImage { .. }
                | Call::CopyTexSubImageLayer { .. }
                | Call::Flush
                | Call::Finish
                | Call::BeginPass { .. }
                | Call::NextSubpass
                | Call::EndPass
                | Call::StartTiling { .. }
                | Call::EndTiling { .. }
        )
}

/// The attachment a `store-unread` finding is about: the first of the pass's slots its
/// message names (`stored the depth of …`).
/// The attachments a `store-unread` finding names (both halves of a packed depth-stencil).
fn slots_in(message: &str, pass: &PassRecord) -> Vec<Slot> {
    if message.contains("stored the depth and stencil of") {
        return vec![Slot::Depth, Slot::Stencil];
    }
    pass.attachments.iter().map(|a| a.slot).filter(|slot| message.contains(&format!("stored the {slot} of"))).collect()
}

fn attachment_point(slot: Slot) -> AttachmentPoint {
    match slot {
        Slot::Color(0) => AttachmentPoint::Color0,
        Slot::Color(1) => AttachmentPoint::Color1,
        Slot::Color(2) => AttachmentPoint::Color2,
        Slot::Color(_) => AttachmentPoint::Color3,
        Slot::Depth => AttachmentPoint::Depth,
        Slot::Stencil => AttachmentPoint::Stencil,
    }
}
