//! Explicit render passes: `begin_pass`, `next_subpass`, `end_pass` — subpasses and their
//! dependencies, as Vulkan says them, on top of the inferred pass.
//!
//! An explicit pass is the open pass of `pass.rs` with a subpass structure: its load and store
//! ops are still inferred (a clear before the first draw is the load op, an invalidate drops
//! the store, a transient attachment is never loaded or stored), so the only new decisions
//! are which attachments each draw writes and reads. Everything is checked here, at the front
//! door, against the framebuffer's attachments; the core checks the rest (an input read
//! before anything wrote it) when the pass is rendered at `end_pass`.
//!
//! Nothing may end an explicit pass early: GL's implicit flushes (read-backs, copies, a
//! sampled attachment, a bind, a swap) are errors inside one, since a split the application
//! did not ask for is exactly what it is written to avoid. A dependency that is not
//! by-region is the one split it does ask for: the core finishes the source subpass in every
//! tile first, storing and reloading every attachment through memory (counted as
//! `subpass_splits`), and the advisor reports it (`subpass-split`).

use tiler::{AttachmentRef as CoreRef, SubpassDependency, SubpassDesc};

use super::{Context, Fallible};
use crate::call::{AttachmentPoint, DependencySpec, SubpassSpec};
use crate::report::{CallRef, EndCause, LoadKind, Slot, StartCause};

/// What [`Context::outside_explicit_pass`] is told at the end of a run.
pub(crate) const END_OF_TRACE: &str = "the end of the trace";

/// The subpass structure of an open explicit pass.
#[derive(Clone, Debug)]
pub(crate) struct ExplicitPass {
    pub begun_at: CallRef,
    pub subpasses: Vec<SubpassDesc>,
    pub dependencies: Vec<SubpassDependency>,
    /// The subpass draws go to now.
    pub current: usize,
    /// The index of the first draw of each subpass after the first.
    pub starts: Vec<usize>,
}

impl ExplicitPass {
    pub fn subpass(&self) -> &SubpassDesc {
        &self.subpasses[self.current]
    }
}

impl Context {
    /// The explicit pass being recorded, if any.
    pub(crate) fn explicit(&self) -> Option<&ExplicitPass> {
        self.pass.as_ref().and_then(|p| p.explicit.as_ref())
    }

    /// Refuses `what` inside an explicit pass: it would end the pass before `end_pass`.
    pub(crate) fn outside_explicit_pass(&self, what: &str) -> Fallible {
        match self.explicit() {
            Some(e) if what == END_OF_TRACE => {
                Err(format!("the explicit pass begun at {} was never ended: call end_pass", e.begun_at))
            }
            Some(e) => Err(format!(
                "{what} inside the explicit pass begun at {}: it would end the pass early; call end_pass first",
                e.begun_at
            )),
            None => Ok(()),
        }
    }

    /// `begin_pass`: checks the subpasses against the framebuffer, ends the open pass, binds
    /// the framebuffer for drawing and opens the explicit pass on it.
    pub(crate) fn begin_pass(
        &mut self,
        framebuffer: u32,
        subpasses: &[SubpassSpec],
        dependencies: &[DependencySpec],
    ) -> Fallible {
        self.outside_explicit_pass("begin_pass")?;
        if self.tiling.is_some() {
            return Err("begin_pass inside a tiled-rendering region: call end_tiling first".to_string());
        }
        let targets = self.targets(framebuffer)?;
        if targets.color.iter().any(|c| c.resolve.is_some()) {
            return Err(format!(
                "framebuffer {framebuffer} resolves multisampled colour in the tile (a multisampled window or \
                 framebuffer_texture with samples); explicit passes do not support that yet"
            ));
        }
        if subpasses.is_empty() {
            return Err("begin_pass needs at least one subpass".to_string());
        }
        let colors = targets.color.len();
        let color_index = |s: usize, what: &str, p: AttachmentPoint| -> Fallible<u32> {
            let name = p.name();
            let i = p.color_index().ok_or_else(|| {
                format!("subpass {s}: {what} {name} is not a colour attachment point (color0 … color3)")
            })?;
            if i >= colors {
                return Err(format!(
                    "subpass {s}: {what} {name} is not attached to framebuffer {framebuffer} (it has {colors} colour \
                     attachment(s))"
                ));
            }
            Ok(i as u32)
        };
        let mut descs = Vec::with_capacity(subpasses.len());
        for (s, spec) in subpasses.iter().enumerate() {
            let mut color = Vec::new();
            for &p in &spec.color {
                let i = color_index(s, "colour", p)?;
                if color.contains(&i) {
                    return Err(format!("subpass {s}: colour attachment {i} is listed twice"));
                }
                color.push(i);
            }
            if spec.depth_stencil && targets.depth_stencil.is_none() {
                return Err(format!(
                    "subpass {s}: depth_stencil is true but framebuffer {framebuffer} has no depth or stencil attachment"
                ));
            }
            let mut input = Vec::new();
            for (i, &p) in spec.input.iter().enumerate() {
                let r = match p {
                    AttachmentPoint::Depth | AttachmentPoint::Stencil | AttachmentPoint::DepthStencil => {
                        if targets.depth_stencil.is_none() {
                            return Err(format!(
                                "subpass {s}: input {i} reads the depth-stencil attachment, but framebuffer \
                                 {framebuffer} has none"
                            ));
                        }
                        CoreRef::DepthStencil
                    }
                    c => {
                        let index = color_index(s, &format!("input {i}"), c)?;
                        if color.contains(&index) {
                            return Err(format!(
                                "subpass {s}: input {i} (color{index}) is also written by this subpass; read what an \
                                 earlier subpass wrote"
                            ));
                        }
                        CoreRef::Color(index)
                    }
                };
                input.push(r);
            }
            if input.len() > tiler::MAX_INPUT_ATTACHMENTS {
                return Err(format!(
                    "subpass {s}: {} input attachments, at most {}",
                    input.len(),
                    tiler::MAX_INPUT_ATTACHMENTS
                ));
            }
            descs.push(SubpassDesc { color, depth_stencil: spec.depth_stencil, input, resolve: Vec::new() });
        }
        let n = subpasses.len() as u32;
        let mut deps = Vec::with_capacity(dependencies.len());
        for (i, d) in dependencies.iter().enumerate() {
            if d.src >= n || d.dst >= n {
                return Err(format!(
                    "dependency {i}: subpass {} → {}, but the pass has {n} subpass(es) (0 to {})",
                    d.src,
                    d.dst,
                    n - 1
                ));
            }
            if d.src >= d.dst {
                return Err(format!("dependency {i}: src {} must be an earlier subpass than dst {}", d.src, d.dst));
            }
            deps.push(SubpassDependency { src: d.src, dst: d.dst, by_region: d.by_region });
        }

        // Checked: now end whatever is open, bind, and open the explicit pass.
        let here = self.here;
        self.end_open_pass(EndCause::Bind)?;
        self.draw_framebuffer = framebuffer;
        self.next_start = (StartCause::BeginPass, here);
        let pass = self.ensure_pass()?;
        pass.explicit =
            Some(ExplicitPass { begun_at: here, subpasses: descs, dependencies: deps, current: 0, starts: Vec::new() });
        Ok(())
    }

    /// `next_subpass`.
    pub(crate) fn next_subpass(&mut self) -> Fallible {
        let pass =
            self.pass.as_mut().filter(|p| p.explicit.is_some()).ok_or("next_subpass outside an explicit pass")?;
        let draws = pass.draws.len();
        let e = pass.explicit.as_mut().expect("checked");
        if e.current + 1 >= e.subpasses.len() {
            return Err(format!(
                "next_subpass past the last subpass: the pass begun at {} has {} subpass(es) and is in subpass {}",
                e.begun_at,
                e.subpasses.len(),
                e.current
            ));
        }
        e.current += 1;
        e.starts.push(draws);
        Ok(())
    }

    /// `end_pass`: renders the explicit pass.
    pub(crate) fn end_pass(&mut self) -> Fallible {
        let e = self.explicit().ok_or("end_pass outside an explicit pass")?;
        if e.current + 1 != e.subpasses.len() {
            return Err(format!(
                "end_pass in subpass {} of the {} of the pass begun at {}: call next_subpass until the last subpass",
                e.current,
                e.subpasses.len(),
                e.begun_at
            ));
        }
        // An input must hold something: written by an earlier subpass, or loaded or cleared.
        let pass = self.pass.as_ref().expect("an explicit pass is open");
        for (s, sp) in e.subpasses.iter().enumerate() {
            for (i, input) in sp.input.iter().enumerate() {
                let (written, name) = match *input {
                    CoreRef::Color(c) => {
                        (e.subpasses[..s].iter().any(|p| p.color.contains(&c)), Slot::Color(c as u8).to_string())
                    }
                    CoreRef::DepthStencil => {
                        (e.subpasses[..s].iter().any(|p| p.depth_stencil), "the depth-stencil attachment".to_string())
                    }
                };
                let defined = pass
                    .aspects
                    .iter()
                    .filter(|a| match *input {
                        CoreRef::Color(c) => a.slot == Slot::Color(c as u8),
                        CoreRef::DepthStencil => !matches!(a.slot, Slot::Color(_)),
                    })
                    .any(|a| a.load != LoadKind::DontCare);
                if !written && !defined {
                    return Err(format!(
                        "subpass {s} reads {name} as input {i}, but no earlier subpass writes it and the pass neither \
                         loads nor clears it: its contents are undefined"
                    ));
                }
            }
        }
        let here = self.here;
        self.end_open_pass(EndCause::EndPass)?;
        self.next_start = (StartCause::Bind, here);
        Ok(())
    }
}
