//! tiler-report: what a frame costs, written for people and for tools.
//!
//! A [`Report`] is one frame of one scene rendered on one or more devices (its *columns*: a
//! device preset, the backend that ran it, its [`FrameCost`] and the picture), the frame rate
//! the per-second figures assume, and the advisor's findings. From it:
//!
//! - [`to_json`]: the machine-readable report, schema [`SCHEMA`] (`docs/report-schema.md`);
//! - [`to_html`]: one self-contained HTML file (no scripts, no network): the picture, a stacked
//!   bar chart of bytes per category, tables per frame and per pass, energy, counters, per-tile
//!   heat maps and overdraw maps, findings, and the formula of every ledger category;
//! - [`text_table`]: the side-by-side table `tiler render` and `tiler compare` print;
//! - [`write_heatmaps`]: the heat maps and overdraw maps as PNG files.
//!
//! Every figure is computed once, in [`schema::Document`]; the JSON is that document, and
//! the HTML and text tables print its numbers, so the three always agree.

pub mod format;
pub mod heatmap;
mod html;
pub mod run;
pub mod schema;
mod svg;
mod text;

use tiler::{Backend, DevicePreset, FrameCost};

pub use heatmap::{TileMetric, write_heatmaps};
pub use html::to_html;
pub use run::{AttachmentInfo, FrameSpan, PassInfo};
pub use schema::{Document, SCHEMA};
pub use text::text_table;
/// The findings a report shows, as `tiler_report::finding` (their own crate, shared with the
/// advisors that produce them).
pub use tiler_finding as finding;
pub use tiler_finding::{CallAt, DeviceCost, Finding, Location, Rule, Severity, WhatIf};

/// One frame of a scene on one or more devices, and what the advisor found in it.
#[derive(Clone, Debug)]
pub struct Report {
    /// What the report is about, e.g. `built-in scene`.
    pub title: String,
    pub scene: SceneInfo,
    /// Frames per second the per-second figures (bandwidth, power) assume.
    pub fps: f64,
    /// The devices, in the order shown; ratios are to the first.
    pub columns: Vec<Column>,
    /// The advisor's findings, if any.
    pub findings: Vec<Finding>,
    /// Per render pass of the run (every column's passes, in order): its target, why it began
    /// and ended, its attachments' ops and why (as a GL driver inferred them, or as a scene
    /// gave them); empty when unknown.
    pub passes: Vec<PassInfo>,
}

/// The scene rendered.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct SceneInfo {
    pub name: String,
    /// Size of the presented image, pixels.
    pub width: u32,
    pub height: u32,
    /// Samples per pixel of the main colour attachment (1 = no MSAA).
    pub samples: u32,
    pub draws: u64,
    /// Triangles submitted per frame.
    pub triangles: u64,
}

/// One device's frame: the preset, the backend that ran it, what it cost and the picture.
#[derive(Clone, Debug)]
pub struct Column {
    /// The column's heading, e.g. the preset's name.
    pub label: String,
    /// The preset as loaded; its `device.backend` may differ from [`Column::backend`] when
    /// the backend was chosen separately (`tiler render --backend`).
    pub preset: DevicePreset,
    /// The backend the frame was rendered with.
    pub backend: Backend,
    /// The frame's cost; for a run of several frames, every pass of every frame, and their
    /// presenting and driver costs summed.
    pub frame: FrameCost,
    /// The presented picture (the last, for a run).
    pub image: Rgba8Image,
    /// The frames of a run, in order; empty for a single frame.
    pub frames: Vec<FrameSpan>,
}

/// A picture: 8-bit RGBA, rows top to bottom.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Rgba8Image {
    pub width: u32,
    pub height: u32,
    /// `width × height × 4` bytes.
    pub pixels: Vec<u8>,
}

impl Rgba8Image {
    /// Wraps pixels.
    ///
    /// # Errors
    /// `pixels` is not `width × height × 4` bytes long.
    pub fn new(width: u32, height: u32, pixels: Vec<u8>) -> Result<Rgba8Image, String> {
        let expected = width as u64 * height as u64 * 4;
        if pixels.len() as u64 != expected {
            return Err(format!("a {width}×{height} RGBA8 image needs {expected} bytes, got {}", pixels.len()));
        }
        Ok(Rgba8Image { width, height, pixels })
    }

    /// Whether the pixel array matches the size (a hand-built image may not).
    pub fn is_consistent(&self) -> bool {
        self.pixels.len() as u64 == self.width as u64 * self.height as u64 * 4
    }

    /// FNV-1a (64-bit) of the size and pixels: equal pictures have equal digests.
    pub fn digest(&self) -> u64 {
        const OFFSET_BASIS: u64 = 0xcbf2_9ce4_8422_2325;
        const PRIME: u64 = 0x0000_0100_0000_01b3;
        let mut hash = OFFSET_BASIS;
        for byte in self.width.to_le_bytes().iter().chain(&self.height.to_le_bytes()).chain(&self.pixels) {
            hash ^= *byte as u64;
            hash = hash.wrapping_mul(PRIME);
        }
        hash
    }
}

/// The JSON report (schema [`SCHEMA`]), pretty-printed.
pub fn to_json(report: &Report) -> String {
    let document = Document::new(report);
    serde_json::to_string_pretty(&document).expect("the report document serializes: plain data, string keys")
}
