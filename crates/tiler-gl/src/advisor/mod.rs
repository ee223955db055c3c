//! The advisor: reads what a run did (its frames, passes, stalls and copies) and reports each
//! pattern the seed documents warn about, with the rule behind it, the frame, pass and call at
//! fault, what it cost in that frame, and what to do instead.
//!
//! Costs are exact where the fix only removes traffic: the bytes a finding reports are the
//! bytes the same frame would not move with the fix (the example trace pairs check this). The
//! rules and their ids are [`RuleId`]s; ids are stable.
//!
//! A framebuffer bound again in a frame is `framebuffer-rebound` only when the work between
//! the two bindings could have gone first: when a pass between reads an image the first
//! binding drew (a ping-pong blur), draws into one it read, or draws into one it drew too (a
//! shared depth buffer), the rebinding is needed, and the second binding is judged as a fresh
//! one (`load-at-pass-start` then speaks of its loads only where its first draw paints over
//! every pixel: otherwise the frame's own earlier drawing is its starting point).
//!
//! | id | rule (seed §) | cost |
//! |---|---|---|
//! | `load-at-pass-start` | 001 "How to optimize render passes"; 000 §23.3 | the loads |
//! | `partial-clear` | 000 §23.3 (Listing 23.1); 001 | loads it kept + the clear-quad's frame data; fragments |
//! | `framebuffer-rebound` | 000 §23.5, §23.11; 001 "steps to avoid" | reloads + the stores they read |
//! | `flush-mid-pass` | 000 §23.5; 001 "steps to avoid" | reloads + the stores they read |
//! | `store-unread` | 000 §23.3 (discard); 001; 004 §24.3.2 | the stores |
//! | `incremental-render` | 000 §23.5, §23.10 | the extra loads and stores |
//! | `micro-triangles` | 000 §23.2, §23.11 | the pass's geometry and frame-data bytes |
//! | `copy-on-write` | 000 §23.6 | the copies |
//! | `packed-depth-stencil-half` | 001 "steps to avoid" | loads and stores of the other half |
//! | `preserved-swap` | 000 §23.4 | the window load + stores outside what was drawn |
//! | `readback-stall`, `query-stall`, `finish-stall` | 000 §23.6 | frames of lost pipelining |
//! | `early-z-disabled` | 000 §23.7; 002 "Depth Testing Optimizations" | fragments shaded then killed |
//! | `unsorted-opaque` | 000 §23.7, §23.11 | fragments shaded beyond one per pixel |
//! | `msaa-stored` | 000 §23.9, §23.3; 004 §24.3.3 | the multisampled stores |
//! | `post-process-chain` | 002 "Optimizing for TBR" (subpasses); 000 §23.5 | the intermediate store |
//! | `subpass-split` | 002 "Optimizing for TBR", "Best Practices for TBR" | the split's stores and reloads |
//! | `draws-discarded` (info) | 000 §23.10 | — |
//! | `minified-without-mipmaps` | 004 §24.3.4, §24.3.5 | the minified quads' texture fetch less `MIPMAPPED_QUAD_BYTES` a quad |
//! | `tile-memory-overflow` | 000 §23.1, §23.9; 001 | — (the ledger is a lower bound: the pass did not fit on chip) |
//!
//! # Priced for the device
//!
//! The advisor prices a run on the device that rendered it (the context's backend): on an
//! immediate-mode GPU the rules whose cost is tile loads and stores or work kept in the tile
//! ([`RuleId::tiler_only`]) cost nothing and are not reported, and a clear-quad costs its
//! shading but no kept loads. `tiler analyze --devices` replays a run on each device and
//! lists each finding with what it costs on each.
//!
//! # Every frame source, and proof by re-running
//!
//! Frames given as render passes (glTF, built-in scenes, the Rust API) are judged by the same
//! rules through [`advise_passes`]. [`what_if`] applies a finding's fix to a trace's calls so
//! the run can be replayed with it, and [`what_if::prove`] replays each fix and measures it:
//! on the example pairs each fix saves exactly its estimate on every built-in preset. On a
//! device with transaction elimination the estimate prices the stores as made, and so does
//! the measurement it is compared with: elimination skips the stores of tiles whose content
//! repeats what memory holds, which depends on the pictures rather than on the pattern (the
//! static example frames repeat, so there the device moves less than either figure), and
//! pricing it would make one frame's finding depend on what other frames store. What the
//! device moved fewer is reported beside it. Two costs are not priced: on a device that shades
//! vertices per tile, a flush also loses the vertex-cache hits between the draws it puts in two
//! passes; on an immediate-mode GPU, a clear-quad's writes against a full clear's (the
//! fragments are priced).
//!
//! # Structure
//!
//! Each rule is one [`RuleId`] (its name, severity and seed section, in `rules.rs`) and one
//! function: `pass.rs` holds the rules about one render pass, `frame.rs` those about a frame's
//! copies, stalls and stores. A new rule is a variant and a function, called from
//! [`pass::check`] or [`frame::check`].
//!
//! # Linear in the length of the run
//!
//! A rule looks at one pass (or frame) and at the few passes it is compared with, which it
//! finds through [`PassIndex`] in constant time: the latest earlier pass of the same frame on
//! the same framebuffer (a map by frame and framebuffer), the pass rendered just before, the
//! bytes later passes sample from a stored image before it is stored again (one backward sweep
//! over the run), and a pass by its number (a map). Advising a run of `P` passes is then
//! `O(P)` plus the draws and attachments it holds. The first advisor compared each pass with
//! every earlier one: 10,000 short frames took 0.28 s, 40,000 took 3.25 s and 100,000 did not
//! finish (issue 13). Measured with `tiler analyze` (dev profile) on a generated trace of
//! short frames (two passes each, a multisampled one blitted to the window): 10,000 / 20,000
//! frames took 1.32 / 6.60 s of CPU before, 0.58 / 1.19 s after, and 40,000 / 100,000 take
//! 2.36 / 5.45 s. The index counts what it hands out, so a test checks the work grows in step
//! with the run, without timing anything.

mod frame;
mod pass;
mod passes;
mod rules;
pub mod what_if;

use std::cell::Cell;
use std::collections::HashMap;

use tiler::ImageId;
pub use tiler_finding::{CallAt, Finding, Location, Severity};

pub use self::passes::advise_passes;
pub use self::rules::{RuleId, RuleInfo};
use crate::context::ContextConfig;
use crate::report::{CallRef, FrameRecord, PassRecord, StoreKind};

/// Rendered fragments per primitive below which a pass counts as micro-triangles.
pub const MICRO_TRIANGLE_FRAGMENTS: f64 = 2.0;
/// Primitives a pass needs before micro-triangles are worth a finding.
pub const MICRO_TRIANGLE_MIN_PRIMITIVES: u64 = 1000;
/// Share of a pass's shaded fragments the discarding draws must have ("most of the frame").
pub const EARLY_Z_SHARE: f64 = 0.5;
/// The most draws a pass may have to count as a full-screen effect over the previous pass.
pub const POST_PROCESS_MAX_DRAWS: usize = 2;
/// Overdraw of opaque geometry (shaded fragments per pixel) above which its order matters.
pub const UNSORTED_OVERDRAW: f64 = 1.25;
/// What a quad of RGBA8 texels costs with mip maps, for the saving `minified-without-mipmaps`
/// estimates: at a level of detail near 0 a quad's four pixels read about four texels of
/// their level, 16 bytes, shared with no neighbour, and trilinear filtering adds a quarter of
/// that from the next level: 20 bytes.
pub const MIPMAPPED_QUAD_BYTES: u64 = 20;
/// Texture bytes a pass must be able to save before `minified-without-mipmaps` speaks.
pub const MIPMAP_MIN_SAVING: u64 = 4096;

/// What a finding costs in its frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Cost {
    /// External-memory bytes the fix would save.
    pub bytes: u64,
    /// Fragments shaded that the fix would not shade.
    pub fragments: u64,
    /// Frames of pipelining lost to a stall.
    pub stall_frames: u32,
}

/// A finding as a rule reports it, before the findings are put in order.
struct Draft {
    rule: RuleId,
    frame: u32,
    /// The render pass at fault (a global pass index), if one is.
    pass: Option<u32>,
    /// The call at fault, if one is.
    call: Option<CallRef>,
    cost: Cost,
    /// What happened, with the numbers.
    detail: String,
    /// What to do instead.
    fix: String,
}

impl Draft {
    /// A finding about a pass, in its frame.
    fn about(rule: RuleId, pass: &PassRecord, call: Option<CallRef>, cost: Cost, detail: String, fix: String) -> Draft {
        Draft { rule, frame: pass.frame, pass: Some(pass.index), call, cost, detail, fix }
    }

    fn finding(self) -> Finding {
        let nonzero = |n: u64| (n > 0).then_some(n);
        let frame = self.frame;
        Finding {
            id: self.rule.name().to_string(),
            severity: self.rule.severity(),
            rule: self.rule.rule(),
            location: Location {
                frame: Some(frame as u64),
                pass: self.pass.map(u64::from),
                call: self.call.map(|c| if c.frame == frame { c.in_frame() } else { c.to_string() }),
                call_at: self.call.map(CallAt::from),
            },
            cost_bytes: nonzero(self.cost.bytes),
            cost_fragments: nonzero(self.cost.fragments),
            cost_stall_frames: nonzero(self.cost.stall_frames as u64),
            message: self.detail,
            advice: self.fix,
            costs: Vec::new(),
            what_if: Vec::new(),
        }
    }
}

/// Runs every rule over a run's frames.
pub fn advise(config: &ContextConfig, frames: &[FrameRecord]) -> Vec<Finding> {
    advise_counting(config, frames).0
}

/// [`advise`], and the number of pass records the rules were handed (see [`PassIndex`]).
fn advise_counting(config: &ContextConfig, frames: &[FrameRecord]) -> (Vec<Finding>, u64) {
    let index = PassIndex::new(frames);
    let mut out = Vec::new();
    for position in 0..index.passes.len() {
        pass::check(config, &index, position, &mut out);
    }
    for frame in frames {
        frame::check(frame, &index, &mut out);
    }
    // Priced for the device: what exists only on a tiler costs an immediate-mode GPU nothing.
    if !config.backend.is_tiler() {
        out.retain(|draft| !draft.rule.tiler_only());
    }
    out.sort_by_key(|f| (f.frame, f.pass, f.call, f.rule.name()));
    (out.into_iter().map(Draft::finding).collect(), index.handed_out.get())
}

/// The run's passes, indexed so that a rule finds each pass it compares with in constant
/// time. Rules reach other passes only through it, and it counts every pass record it hands
/// out or steps over while being built, so the count bounds the rules' work.
/// The most passes between two bindings of a framebuffer that [`PassIndex::rebind_needed`]
/// looks through; with more, the rebinding is taken as needed.
const MAX_REBIND_SCAN: usize = 16;

pub(crate) struct PassIndex<'a> {
    /// Every pass, in the order rendered.
    passes: Vec<&'a PassRecord>,
    /// Passes by their number (the first, should two share one).
    by_number: HashMap<u32, &'a PassRecord>,
    /// For each pass, the latest earlier pass of its frame on its framebuffer that is not a
    /// copy's pass.
    same_framebuffer_before: Vec<Option<&'a PassRecord>>,
    /// The position of that pass.
    same_framebuffer_before_at: Vec<Option<usize>>,
    /// For each pass and each of its attachments, the bytes later passes sample from the
    /// attachment's image, up to and including the next pass that stores it again.
    reads_until_stored_again: Vec<Vec<u64>>,
    handed_out: Cell<u64>,
}

impl<'a> PassIndex<'a> {
    fn new(frames: &'a [FrameRecord]) -> PassIndex<'a> {
        let passes: Vec<&PassRecord> = frames.iter().flat_map(|f| f.passes.iter()).collect();
        let n = passes.len();

        let mut by_number = HashMap::with_capacity(n);
        let mut latest: HashMap<(u32, u32), usize> = HashMap::new();
        let mut same_framebuffer_before_at = Vec::with_capacity(n);
        for (position, &pass) in passes.iter().enumerate() {
            by_number.entry(pass.index).or_insert(pass);
            same_framebuffer_before_at.push(latest.get(&(pass.frame, pass.framebuffer)).copied());
            if pass.copy_texture.is_none() {
                latest.insert((pass.frame, pass.framebuffer), position);
            }
        }
        let same_framebuffer_before = same_framebuffer_before_at.iter().map(|at| at.map(|p| passes[p])).collect();

        // Backward: `pending[image]` is what the passes after the current one sample from the
        // image, up to and including the first of them that stores it.
        let mut pending: HashMap<ImageId, u64> = HashMap::new();
        let mut reads_until_stored_again = vec![Vec::new(); n];
        for (position, pass) in passes.iter().enumerate().rev() {
            reads_until_stored_again[position] =
                pass.attachments.iter().map(|a| pending.get(&a.image).copied().unwrap_or(0)).collect();
            for a in pass.attachments.iter().filter(|a| a.store == StoreKind::Store) {
                pending.insert(a.image, 0);
            }
            for d in &pass.draws {
                if let Some(image) = d.sampled {
                    *pending.entry(image).or_default() += d.texture_bytes;
                }
            }
        }

        // Built by two sweeps over the passes.
        let handed_out = Cell::new(2 * n as u64);
        PassIndex {
            passes,
            by_number,
            same_framebuffer_before,
            same_framebuffer_before_at,
            reads_until_stored_again,
            handed_out,
        }
    }

    fn hand_out<T>(&self, found: Option<T>) -> Option<T> {
        self.handed_out.set(self.handed_out.get() + 1);
        found
    }

    /// The pass at this position in the run.
    fn at(&self, position: usize) -> &'a PassRecord {
        self.hand_out(Some(self.passes[position])).expect("a position within the run")
    }

    /// The pass numbered `number`.
    fn numbered(&self, number: u32) -> Option<&'a PassRecord> {
        self.hand_out(self.by_number.get(&number).copied())
    }

    /// The latest earlier pass of the same frame on the same framebuffer (copies aside).
    fn same_framebuffer_before(&self, position: usize) -> Option<&'a PassRecord> {
        self.hand_out(self.same_framebuffer_before[position])
    }

    /// Why the work between the pass at `position` and the latest earlier pass of its frame on
    /// its framebuffer could not have gone before that pass: the first pass between them that
    /// reads an image the earlier pass wrote, writes one it read, or writes one it wrote too
    /// (a shared depth buffer, say). `None`: the two could have been one pass.
    fn rebind_needed(&self, position: usize) -> Option<String> {
        let before = self.same_framebuffer_before_at[position]?;
        let earlier = self.passes[before];
        let written = |p: &PassRecord| -> Vec<ImageId> {
            p.attachments.iter().flat_map(|a| std::iter::once(a.image).chain(a.resolve)).collect()
        };
        let earlier_wrote = written(earlier);
        let between = &self.passes[before + 1..position];
        if between.len() > MAX_REBIND_SCAN {
            self.handed_out.set(self.handed_out.get() + MAX_REBIND_SCAN as u64);
            return Some(format!("more than {MAX_REBIND_SCAN} passes lie between it and pass {}", earlier.index));
        }
        self.handed_out.set(self.handed_out.get() + between.len() as u64);
        let found = between.iter().find_map(|&between| {
            let wrote = written(between);
            if let Some(image) = between.reads.iter().find(|i| earlier_wrote.contains(i)) {
                Some(format!("pass {} reads {image}, which pass {} drew", between.index, earlier.index))
            } else if let Some(image) = wrote.iter().find(|i| earlier.reads.contains(i)) {
                Some(format!("pass {} draws into {image}, which pass {} read", between.index, earlier.index))
            } else {
                wrote.iter().find(|i| earlier_wrote.contains(i)).map(|image| {
                    format!("pass {} draws into {image}, which pass {} drew too", between.index, earlier.index)
                })
            }
        });
        self.hand_out(found)
    }

    /// The pass rendered just before, on any framebuffer.
    fn previous(&self, position: usize) -> Option<&'a PassRecord> {
        self.hand_out(position.checked_sub(1).map(|p| self.passes[p]))
    }

    /// What later passes sample from the image of the pass's `attachment`-th attachment
    /// before it is stored again.
    fn reads_until_stored_again(&self, position: usize, attachment: usize) -> u64 {
        self.reads_until_stored_again[position][attachment]
    }
}

/// `the window` or `framebuffer N`.
fn framebuffer_name(pass: &PassRecord) -> String {
    if pass.framebuffer == 0 { "the window".to_string() } else { format!("framebuffer {}", pass.framebuffer) }
}

fn bytes(n: u64) -> String {
    if n >= 10_000_000 {
        format!("{:.1} MB", n as f64 / 1e6)
    } else if n >= 10_000 {
        format!("{:.1} kB", n as f64 / 1e3)
    } else {
        format!("{n} B")
    }
}

fn slots(list: &[crate::report::Slot]) -> String {
    list.iter().map(|s| s.to_string()).collect::<Vec<_>>().join(", ")
}

impl From<CallRef> for CallAt {
    fn from(c: CallRef) -> CallAt {
        CallAt { frame: c.frame as u64, call: c.call as u64, capture_call: c.capture_call }
    }
}

#[cfg(test)]
mod tests;
