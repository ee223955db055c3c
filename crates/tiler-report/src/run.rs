//! What a report knows beyond one frame's cost: the frames of a multi-frame run (a GL trace
//! or capture) and, per render pass, what the driver inferred — its target, why it began and
//! ended, and each attachment's load and store op and why.

use serde::Serialize;
use tiler::Ledger;

/// One frame of a run, within a column whose [`FrameCost`](tiler::FrameCost) holds the
/// passes of every frame in order.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FrameSpan {
    /// The frame's number, from 0.
    pub index: u64,
    /// Its first pass, an index into the column's passes.
    pub first_pass: usize,
    /// How many passes it has.
    pub passes: usize,
    /// Presenting it (display, composition).
    pub present: Ledger,
    /// The driver's costs outside its passes (copy-on-write).
    pub driver: Ledger,
}

/// How a render pass came about, as the driver inferred it (the same on every device).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct PassInfo {
    /// The frame it belongs to.
    pub frame: u64,
    /// What it renders to, e.g. `the window` or `framebuffer 2`.
    pub target: String,
    /// Why it began, e.g. `bind at frame 0, call 12`.
    pub began: String,
    /// Why it ended, e.g. `swap at frame 0, call 40`.
    pub ended: String,
    pub attachments: Vec<AttachmentInfo>,
}

/// One attachment (aspect) of a pass: its ops and why.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct AttachmentInfo {
    /// `color0`, `depth`, `stencil`.
    pub slot: String,
    pub format: String,
    pub samples: u32,
    /// `load`, `clear` or `dont_care`.
    pub load: String,
    pub load_reason: String,
    /// `store` or `dont_care`.
    pub store: String,
    pub store_reason: String,
}
