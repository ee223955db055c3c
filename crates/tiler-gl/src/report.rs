//! What a context did: frames → render passes → attachments, draws and cost, plus what the
//! driver did outside passes (copy-on-write, display, stalls). These records are the
//! JSON of `tiler analyze --gl-report`; every field name is stable (documented on the types
//! here), new fields may be added. A place is a [`CallRef`]: frame and index in the frame, and
//! for a replayed capture its call number too.

use serde::{Serialize, Serializer};
use tiler::FrameDataReport;
use tiler::{Counters, DrawStats, Format, ImageId, Ledger, PassReport, Rect};

use crate::advisor::Finding;
use crate::call::{ProgramKind, TextureFormat};
use crate::context::ContextConfig;

/// Where a call is: its frame (frames end at `swap_buffers`) and its index in that frame;
/// for a replayed capture, also the number of the capture's call it came from (one capture
/// call may become several context calls, or none).
///
/// The capture's call number is a note on the place, not part of it: two `CallRef`s are equal
/// (and ordered, and hashed) by frame and index alone, so a JSON trace recorded from a capture
/// names the same places as the capture did.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct CallRef {
    pub frame: u32,
    pub call: u32,
    /// The capture's call number (as `apitrace dump` prints it), when replaying a capture.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub capture_call: Option<u64>,
}

impl CallRef {
    /// The call at `call` in `frame`, of no capture.
    pub const fn new(frame: u32, call: u32) -> CallRef {
        CallRef { frame, call, capture_call: None }
    }

    fn key(self) -> (u32, u32) {
        (self.frame, self.call)
    }

    /// `call 12`, with the capture's call number when known: `call 12 (capture call 5780)`.
    pub fn in_frame(self) -> String {
        match self.capture_call {
            Some(n) => format!("call {} (capture call {n})", self.call),
            None => format!("call {}", self.call),
        }
    }
}

impl PartialEq for CallRef {
    fn eq(&self, other: &CallRef) -> bool {
        self.key() == other.key()
    }
}

impl Eq for CallRef {}

impl std::hash::Hash for CallRef {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.key().hash(state);
    }
}

impl PartialOrd for CallRef {
    fn partial_cmp(&self, other: &CallRef) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for CallRef {
    fn cmp(&self, other: &CallRef) -> std::cmp::Ordering {
        self.key().cmp(&other.key())
    }
}

impl From<tiler_finding::CallAt> for CallRef {
    /// A call a finding names; its numbers came from a `CallRef`.
    fn from(c: tiler_finding::CallAt) -> CallRef {
        CallRef { frame: c.frame as u32, call: c.call as u32, capture_call: c.capture_call }
    }
}

impl std::fmt::Display for CallRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "frame {}, {}", self.frame, self.in_frame())
    }
}

/// An aspect of a framebuffer: a colour attachment, or the depth or stencil of the
/// depth-stencil attachment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Slot {
    Color(u8),
    Depth,
    Stencil,
}

impl std::fmt::Display for Slot {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Slot::Color(i) => write!(f, "color{i}"),
            Slot::Depth => f.write_str("depth"),
            Slot::Stencil => f.write_str("stencil"),
        }
    }
}

impl Serialize for Slot {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// Why a render pass began.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case", tag = "cause")]
pub enum StartCause {
    /// The framebuffer was bound (or was bound and the previous pass on it ended with a swap
    /// or tiling region).
    Bind,
    /// The first pass of a frame on a framebuffer still bound from the previous frame.
    NewFrame,
    /// Drawing continued after a flush cut the previous pass short.
    AfterFlush { flush: FlushCause },
    /// `start_tiling` began a tiled-rendering region.
    Tiling,
    /// A `copy_tex_sub_image` renders into its texture.
    Copy,
    /// `begin_pass` began an explicit pass.
    BeginPass,
}

/// Why a pass was flushed before its framebuffer was unbound (seed 000 §23.5).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FlushCause {
    ReadPixels,
    CopyTexImage,
    BlitFramebuffer,
    Flush,
    Finish,
    /// The result of an occlusion query held by the pass was asked for.
    QueryResult,
    /// A draw sampled a texture that is an attachment of the pass.
    SampleAttachment,
    /// An attachment of the bound framebuffer changed (attach, detach, new storage, delete).
    AttachmentChange,
    /// A texture attached to the pass was written by the CPU.
    TextureUpdate,
    StartTiling,
}

impl FlushCause {
    pub fn describe(self) -> &'static str {
        match self {
            FlushCause::ReadPixels => "read_pixels",
            FlushCause::CopyTexImage => "copy_tex_sub_image",
            FlushCause::BlitFramebuffer => "blit_framebuffer",
            FlushCause::Flush => "flush",
            FlushCause::Finish => "finish",
            FlushCause::QueryResult => "query_result of a query in the pass",
            FlushCause::SampleAttachment => "a draw sampling the pass's own attachment",
            FlushCause::AttachmentChange => "an attachment change",
            FlushCause::TextureUpdate => "a CPU write to an attached texture",
            FlushCause::StartTiling => "start_tiling",
        }
    }
}

/// Why a render pass ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case", tag = "cause")]
pub enum EndCause {
    /// Another draw framebuffer was bound (or this one deleted).
    Bind,
    Swap,
    Flush {
        flush: FlushCause,
    },
    EndTiling,
    /// The copy of a `copy_tex_sub_image` is done.
    Copy,
    /// The trace (or the program) ended with work pending.
    End,
    /// `end_pass` ended an explicit pass.
    EndPass,
}

/// A load op as reported.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LoadKind {
    Load,
    Clear,
    DontCare,
}

/// A store op as reported.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StoreKind {
    Store,
    DontCare,
}

/// How an aspect takes part in a pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Role {
    /// Attached to the framebuffer.
    Attached,
    /// The other half of a packed depth-stencil image of which only one half is attached: it
    /// must be loaded and stored to be preserved (seed 001).
    Preserved,
    /// Bytes the GL format does not have (the stencil byte of `depth24`, the depth bytes of
    /// `stencil8`): never loaded or stored.
    Padding,
}

/// One aspect of one attachment of a pass: its ops, why, and what they moved.
#[derive(Clone, Debug, Serialize)]
pub struct AttachmentRecord {
    pub slot: Slot,
    pub image: ImageId,
    #[serde(serialize_with = "format_name")]
    pub format: Format,
    pub gl_format: TextureFormat,
    pub samples: u32,
    pub role: Role,
    pub load: LoadKind,
    pub load_reason: String,
    pub store: StoreKind,
    pub store_reason: String,
    /// `render-area pixels × samples × aspect bytes` when the load op is `Load` (the first
    /// load only; an incremental render reloads it again).
    pub load_bytes: u64,
    /// The same when the store op is `Store` (the last store only).
    pub store_bytes: u64,
    /// The single-sample image a multisampled colour is resolved into in the tile.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub resolve: Option<ImageId>,
    /// `render-area pixels × bytes per pixel of the resolve image` (`resolve` in the ledger).
    pub resolve_bytes: u64,
}

fn format_name<S: Serializer>(format: &Format, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(format.name())
}

/// What kind of draw a pass holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DrawKind {
    /// An application draw.
    Draw,
    /// A clear the load ops could not express (scissored, masked, or after draws).
    ClearQuad,
    /// A `blit_framebuffer`, drawn as a textured rectangle into the destination's pass.
    Blit,
    /// A `copy_tex_sub_image`, drawn as a textured rectangle into the texture.
    Copy,
}

/// Why a clear became a clear-quad.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct PartialClear {
    /// Each reason: `scissor test enabled`, `colour write mask`, …
    pub reasons: Vec<String>,
    /// The aspects the clear-quad writes.
    pub slots: Vec<Slot>,
    /// Whether it came before any application draw of the pass.
    pub at_start: bool,
}

/// One draw of a pass.
#[derive(Clone, Debug, Serialize)]
pub struct DrawRecord {
    pub call: CallRef,
    pub kind: DrawKind,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub program: Option<ProgramKind>,
    /// Pixels it may touch: viewport ∩ scissor ∩ render area, tiler coordinates (row 0 at
    /// the top).
    pub clip_rect: Rect,
    pub blend: bool,
    pub depth_test: bool,
    pub depth_write: bool,
    /// The fragment shader may discard, so depth is tested after shading (no early-Z).
    pub discards: bool,
    /// Bytes it reads that the context counts (a blit's or copy's source, as `texture_fetch`).
    pub texture_bytes: u64,
    /// The image it samples (a texture, or a blit's or copy's source).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sampled: Option<ImageId>,
    pub stats: DrawStats,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub partial_clear: Option<PartialClear>,
}

/// Draws thrown away before they were rendered (by a full clear or a full invalidate).
#[derive(Clone, Debug, Serialize)]
pub struct Dropped {
    pub call: CallRef,
    pub draws: u32,
    pub by: &'static str,
}

/// What the core reported for a pass (its ledger and counters), without per-tile detail.
#[derive(Clone, Debug, Serialize)]
pub struct PassCost {
    pub ledger: Ledger,
    pub counters: Counters,
    pub frame_data: FrameDataReport,
    pub tile_width: u32,
    pub tile_height: u32,
    pub tiles_x: u32,
    pub tiles_y: u32,
    /// Tile memory one tile of the pass needs: every attachment at every sample (tilers).
    pub tile_bytes: u64,
    /// Memory the pass's transient attachments did not need (tilers, when they never
    /// spilled to memory through an incremental render or a subpass split).
    pub transient_bytes_saved: u64,
    /// Bytes of tile stores transaction elimination skipped: tiles stored unchanged.
    pub transaction_elimination_saved: u64,
}

impl From<&PassReport> for PassCost {
    fn from(r: &PassReport) -> PassCost {
        PassCost {
            ledger: r.ledger,
            counters: r.counters,
            frame_data: r.frame_data,
            tile_width: r.tile_width,
            tile_height: r.tile_height,
            tiles_x: r.tiles_x,
            tiles_y: r.tiles_y,
            tile_bytes: r.tile_bytes,
            transient_bytes_saved: r.transient_bytes_saved,
            transaction_elimination_saved: r.transaction_elimination_saved,
        }
    }
}

/// An inferred render pass, after it was rendered.
#[derive(Clone, Debug, Serialize)]
pub struct PassRecord {
    /// Passes are numbered from 0 across the whole run.
    pub index: u32,
    pub frame: u32,
    pub framebuffer: u32,
    /// For the pass of a `copy_tex_sub_image`: the texture copied into (`framebuffer` is then
    /// the read framebuffer).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub copy_texture: Option<u32>,
    /// The window's pass while the swap behaviour is `preserved`.
    pub window_preserved: bool,
    pub width: u32,
    pub height: u32,
    pub samples: u32,
    /// The pixels the pass covered, tiler coordinates: the tiled-rendering region, or the
    /// scissor box every draw and clear-quad of the pass lies inside (tiles outside it are
    /// neither loaded nor stored); `None` = the whole framebuffer.
    pub render_area: Option<Rect>,
    pub start: StartCause,
    pub started_at: CallRef,
    pub end: EndCause,
    pub ended_at: CallRef,
    pub attachments: Vec<AttachmentRecord>,
    /// The subpasses of an explicit pass (`begin_pass`), as the core took them; empty for an
    /// inferred pass (one subpass writing everything).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub subpasses: Vec<tiler::SubpassDesc>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub dependencies: Vec<tiler::SubpassDependency>,
    /// The index of each draw's subpass, for explicit passes (empty otherwise).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub draw_subpasses: Vec<u32>,
    pub draws: Vec<DrawRecord>,
    /// Every image the pass's draws sample, and the sources of its blits and copies, in
    /// order of their ids: what the pass reads besides its attachments.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub reads: Vec<ImageId>,
    pub dropped: Vec<Dropped>,
    pub cost: PassCost,
    /// Traffic the context counts itself for this pass (blit and copy source reads, as
    /// `texture_fetch`: `source pixels × samples × bytes per sample`).
    pub extra: Ledger,
    /// The core's whole report of the pass (per-tile figures, overdraw map), when the
    /// configuration asked to keep it ([`ContextConfig::keep_pass_reports`]).
    #[serde(skip)]
    pub core: Option<Box<PassReport>>,
}

impl PassRecord {
    /// Pixels of the render area.
    pub fn area(&self) -> u64 {
        match self.render_area {
            Some(r) => r.area(),
            None => self.width as u64 * self.height as u64,
        }
    }

    pub fn attachment(&self, slot: Slot) -> Option<&AttachmentRecord> {
        self.attachments.iter().find(|a| a.slot == slot)
    }

    /// Everything this pass moved.
    pub fn total_bytes(&self) -> u64 {
        self.cost.ledger.total() + self.extra.total()
    }
}

/// Why the CPU waited for the GPU.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StallCause {
    ReadPixels,
    QueryResult,
    Finish,
    /// `client_wait_sync` on a fence whose commands were not done.
    FenceWait,
}

/// A wait for results still in the pipeline (seed 000 §23.6).
#[derive(Clone, Debug, Serialize)]
pub struct Stall {
    pub call: CallRef,
    pub cause: StallCause,
    /// The frame whose work had to complete.
    pub waited_for_frame: u32,
    /// Pipeline stages drained: `waited_for_frame + latency − current frame`.
    pub frames: u32,
}

/// A copy the driver made of a buffer or texture still used by a pending frame.
#[derive(Clone, Debug, Serialize)]
pub struct CopyOnWrite {
    pub call: CallRef,
    /// `buffer 3` or `texture 2`.
    pub object: String,
    /// The frame of the last pending use that forced the copy.
    pub used_in_frame: u32,
    /// Bytes of old contents copied (the object's size minus the bytes the update replaces).
    pub bytes_copied: u64,
    /// Ledger bytes (`copy_on_write`: read and write of the copy).
    pub bytes: u64,
}

/// A store whose contents nothing read before they were overwritten or became undefined.
#[derive(Clone, Debug, Serialize)]
pub struct DeadStore {
    /// The pass that stored it.
    pub pass: u32,
    pub frame: u32,
    pub slot: Slot,
    pub image: ImageId,
    pub bytes: u64,
    /// What ended its life: `overwritten by pass N`, `invalidated`, `swap`, `end of trace`.
    pub fate: String,
}

/// One frame: the calls between two swaps.
#[derive(Clone, Debug, Default, Serialize)]
pub struct FrameRecord {
    pub index: u32,
    pub calls: u32,
    /// Whether the frame ended with `swap_buffers`.
    pub swapped: bool,
    pub passes: Vec<PassRecord>,
    /// Traffic outside render passes: `copy_on_write`, `display` (scan-out of the window,
    /// `width × height × bytes per pixel` at each swap), `composition` (when configured).
    pub context_ledger: Ledger,
    /// Everything: passes, their extra traffic, and the context ledger.
    pub ledger: Ledger,
    pub counters: Counters,
    /// Frames between a frame's submission and its results (the three stages of seed 000
    /// §23.6: CPU, geometry, fragment, by default).
    pub latency_frames: u32,
    pub stalls: Vec<Stall>,
    pub copies: Vec<CopyOnWrite>,
    pub dead_stores: Vec<DeadStore>,
    /// The picture the frame presented, as [`picture_digest`], when the configuration asked
    /// for it ([`ContextConfig::digest_presented`]) and the frame ended with a swap.
    #[serde(skip)]
    pub presented_digest: Option<u64>,
}

/// FNV-1a (64-bit) of the width and height (little-endian u32 each) and the RGBA8 pixels: the
/// `image_digest` of the `tiler-report/1` schema. Equal pictures have equal digests.
pub fn picture_digest(width: u32, height: u32, rgba: &[u8]) -> u64 {
    const OFFSET_BASIS: u64 = 0xcbf2_9ce4_8422_2325;
    const PRIME: u64 = 0x0000_0100_0000_01b3;
    let mut hash = OFFSET_BASIS;
    for byte in width.to_le_bytes().iter().chain(&height.to_le_bytes()).chain(rgba) {
        hash ^= *byte as u64;
        hash = hash.wrapping_mul(PRIME);
    }
    hash
}

/// The first presented frame of two runs whose pictures differ (each run's frames'
/// [`FrameRecord::presented_digest`]s, in the order presented), or `None` when both presented
/// the same pictures. A picture one run presented and the other did not differs; frames that
/// presented nothing (a trace's last calls after its last swap) are not compared.
pub fn first_different_frame(a: &[FrameRecord], b: &[FrameRecord]) -> Option<u32> {
    let presented = |frames: &[FrameRecord]| -> Vec<(u32, u64)> {
        frames.iter().filter_map(|f| f.presented_digest.map(|d| (f.index, d))).collect()
    };
    let (a, b) = (presented(a), presented(b));
    (0..a.len().max(b.len())).find_map(|i| match (a.get(i), b.get(i)) {
        (Some((frame, x)), Some((_, y))) => (x != y).then_some(*frame),
        (Some((frame, _)), None) | (None, Some((frame, _))) => Some(*frame),
        (None, None) => None,
    })
}

impl FrameRecord {
    /// Sums the passes and the context ledger into `ledger` and `counters`.
    pub(crate) fn total(&mut self) {
        let mut ledger = self.context_ledger;
        let mut counters = Counters::default();
        for pass in &self.passes {
            ledger.merge(&pass.cost.ledger);
            ledger.merge(&pass.extra);
            counters.merge(&pass.cost.counters);
        }
        self.ledger = ledger;
        self.counters = counters;
    }
}

/// The version of the report format; it changes when a field changes meaning or goes away.
pub const REPORT_VERSION: u32 = 1;

/// Totals over a whole run.
#[derive(Clone, Debug, Serialize)]
pub struct Totals {
    pub frames: u32,
    pub passes: u32,
    pub ledger: Ledger,
    pub counters: Counters,
}

/// Everything a run did: the `--report` JSON of `tiler analyze`.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// `"tiler-gl-report"`.
    pub format: &'static str,
    pub version: u32,
    pub config: ContextConfig,
    pub frames: Vec<FrameRecord>,
    pub totals: Totals,
    /// The advisor's findings; written in this format's own shape (see [`GlFinding`]).
    #[serde(serialize_with = "gl_findings")]
    pub findings: Vec<Finding>,
}

/// A finding as `tiler-gl-report` version 1 writes it (`docs/report-format.md`): `id`,
/// `severity`, `rule` `{id, seed, section, text}`, `frame`, `pass`?, `call`? (a [`CallRef`]),
/// `cost` `{bytes, fragments, stall_frames}`, `detail`, `fix`. The same [`Finding`] as every
/// report shows, under the field names this format has always had.
#[derive(Serialize)]
struct GlFinding<'a> {
    id: &'a str,
    severity: crate::advisor::Severity,
    rule: GlRule<'a>,
    frame: u32,
    #[serde(skip_serializing_if = "Option::is_none")]
    pass: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    call: Option<CallRef>,
    cost: GlCost,
    detail: &'a str,
    fix: &'a str,
}

#[derive(Serialize)]
struct GlRule<'a> {
    id: &'a str,
    seed: &'a str,
    section: &'a str,
    text: &'a str,
}

#[derive(Serialize)]
struct GlCost {
    bytes: u64,
    fragments: u64,
    stall_frames: u64,
}

impl<'a> From<&'a Finding> for GlFinding<'a> {
    fn from(f: &'a Finding) -> GlFinding<'a> {
        GlFinding {
            id: &f.id,
            severity: f.severity,
            rule: GlRule { id: &f.id, seed: &f.rule.seed, section: &f.rule.section, text: &f.rule.text },
            frame: f.location.frame.unwrap_or(0) as u32,
            pass: f.location.pass.map(|p| p as u32),
            call: f.location.call_at.map(CallRef::from),
            cost: GlCost {
                bytes: f.cost_bytes.unwrap_or(0),
                fragments: f.cost_fragments.unwrap_or(0),
                stall_frames: f.cost_stall_frames.unwrap_or(0),
            },
            detail: &f.message,
            fix: &f.advice,
        }
    }
}

fn gl_findings<S: Serializer>(findings: &[Finding], s: S) -> Result<S::Ok, S::Error> {
    s.collect_seq(findings.iter().map(GlFinding::from))
}

impl Report {
    /// Totals the frames and runs the advisor over them.
    pub fn new(config: ContextConfig, frames: Vec<FrameRecord>) -> Report {
        let mut ledger = Ledger::default();
        let mut counters = Counters::default();
        for f in &frames {
            ledger.merge(&f.ledger);
            counters.merge(&f.counters);
        }
        let totals = Totals {
            frames: frames.len() as u32,
            passes: frames.iter().map(|f| f.passes.len() as u32).sum(),
            ledger,
            counters,
        };
        let findings = crate::advisor::advise(&config, &frames);
        Report { format: "tiler-gl-report", version: REPORT_VERSION, config, frames, totals, findings }
    }

    /// Every pass, in order.
    pub fn passes(&self) -> impl Iterator<Item = &PassRecord> {
        self.frames.iter().flat_map(|f| f.passes.iter())
    }

    /// Bytes of tile stores transaction elimination skipped over the run.
    pub fn transaction_elimination_saved(&self) -> u64 {
        self.passes().map(|p| p.cost.transaction_elimination_saved).sum()
    }

    /// The findings with this id.
    pub fn findings_with(&self, id: &str) -> impl Iterator<Item = &Finding> + '_ {
        let id = id.to_string();
        self.findings.iter().filter(move |f| f.id == id)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(digests: &[Option<u64>]) -> Vec<FrameRecord> {
        digests
            .iter()
            .enumerate()
            .map(|(i, d)| FrameRecord { index: i as u32, presented_digest: *d, ..FrameRecord::default() })
            .collect()
    }

    /// Every presented frame is compared, in order; the first that differs is named; a frame
    /// that presented nothing is not compared, and a picture one run presented and the other
    /// did not differs.
    #[test]
    fn the_first_different_presented_frame_is_named() {
        let a = run(&[Some(1), Some(2), Some(3), None]);
        assert_eq!(first_different_frame(&a, &run(&[Some(1), Some(2), Some(3)])), None);
        assert_eq!(first_different_frame(&a, &run(&[Some(1), Some(9), Some(3)])), Some(1));
        assert_eq!(first_different_frame(&a, &run(&[Some(1), Some(2)])), Some(2));
        assert_eq!(first_different_frame(&run(&[Some(1)]), &run(&[Some(1), Some(5)])), Some(1));
        let picture = [10u8, 20, 30, 255];
        assert_ne!(picture_digest(1, 1, &picture), picture_digest(1, 1, &[10, 20, 31, 255]));
        assert_ne!(picture_digest(1, 2, &[0; 8]), picture_digest(2, 1, &[0; 8]), "the size counts");
    }

    #[test]
    fn a_capture_call_number_is_a_note_not_part_of_the_place() {
        let from_capture = CallRef { frame: 2, call: 7, capture_call: Some(5780) };
        let from_json = CallRef::new(2, 7);
        assert_eq!(from_capture, from_json);
        assert!(from_json < CallRef::new(2, 8) && CallRef::new(1, 9) < from_capture);
        assert_eq!(from_capture.to_string(), "frame 2, call 7 (capture call 5780)");
        assert_eq!(from_json.to_string(), "frame 2, call 7");
        let at = tiler_finding::CallAt::from(from_capture);
        assert_eq!(CallRef::from(at).capture_call, Some(5780));
    }
}
