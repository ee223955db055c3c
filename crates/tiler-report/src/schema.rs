//! The report document: every figure a report shows, computed once. Serialized, it is the
//! JSON report, schema [`SCHEMA`], documented field by field in `docs/report-schema.md`;
//! the HTML and text reports print the same values.
//!
//! Field names are the schema's: renaming or removing one, or changing its unit, is a new
//! schema version; adding a field is not.

use serde::Serialize;
use tiler::FrameDataReport;
use tiler::{Backend, Category, Counters, DevicePreset, DrawStats, Ledger, PassReport, Stage, TimeEstimate, TimeModel};

use crate::run::{FrameSpan, PassInfo};
use crate::{Finding, Report, SceneInfo};

/// The schema this crate writes.
pub const SCHEMA: &str = "tiler-report/1";

/// The program that wrote the report.
pub const GENERATOR: &str = concat!("tiler-report ", env!("CARGO_PKG_VERSION"));

/// A whole report.
#[derive(Clone, Debug, Serialize)]
pub struct Document {
    pub schema: &'static str,
    pub generator: &'static str,
    pub title: String,
    pub scene: SceneInfo,
    /// Frames per second of the per-second figures.
    pub fps: f64,
    pub image: ImageInfo,
    /// Every ledger category in the order reports show them, with its formula.
    pub categories: Vec<CategoryInfo>,
    pub columns: Vec<ColumnFigures>,
    pub findings: Vec<Finding>,
    /// Frames in the report: 1, or a run's length. With more than one, each column's `frame`
    /// is the run's totals and its per-second figures those of the average frame.
    pub frame_count: u64,
    /// Per render pass of the run: its target, why it began and ended, each attachment's ops
    /// and why (as a GL driver inferred them or a scene gave them); absent when unknown.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub passes: Vec<PassInfo>,
}

/// The presented picture.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct ImageInfo {
    pub width: u32,
    pub height: u32,
    /// Every column presented the same picture, bit for bit (the project's invariant).
    pub identical_across_columns: bool,
}

/// A ledger category and how it is counted.
#[derive(Clone, Debug, Serialize)]
pub struct CategoryInfo {
    pub name: &'static str,
    /// The formula, from the category's documentation in the `tiler` crate.
    pub formula: String,
}

/// One device's frame.
#[derive(Clone, Debug, Serialize)]
pub struct ColumnFigures {
    pub label: String,
    pub preset: DevicePreset,
    pub backend: Backend,
    /// `fnv1a64:` and 16 hex digits: equal pictures have equal digests.
    pub image_digest: String,
    pub frame: FrameFigures,
    /// Bytes of presenting the frame (display, composition), also in `frame.bytes`.
    pub present: Ledger,
    /// Bytes the driver adds outside render passes, also in `frame.bytes`.
    pub driver: Ledger,
    pub passes: Vec<PassFigures>,
    /// Each frame's totals, for a run of several frames (absent for one).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub frames: Vec<FrameTotals>,
}

/// One frame of a run: its passes and totals.
#[derive(Clone, Debug, Serialize)]
pub struct FrameTotals {
    pub index: u64,
    /// Its first pass, an index into the column's `passes`.
    pub first_pass: usize,
    pub passes: usize,
    /// Its passes, presenting it and the driver's costs, by category.
    pub bytes: Ledger,
    pub total_bytes: u64,
    /// `total_bytes × fps`.
    pub bytes_per_second: f64,
}

/// The totals of a frame: its passes, presenting it and the driver's costs.
#[derive(Clone, Debug, Serialize)]
pub struct FrameFigures {
    /// External-memory bytes per category, every category present.
    pub bytes: Ledger,
    pub total_bytes: u64,
    pub read_bytes: u64,
    pub written_bytes: u64,
    /// `total_bytes × fps` (divided by `frame_count` for a run: the average frame's).
    pub bytes_per_second: f64,
    /// `total_bytes` over the first column's; `null` when that is zero.
    pub ratio_to_first: Option<f64>,
    /// Bytes moved within on-chip memory (tile buffer, framebuffer cache).
    pub on_chip_bytes: u64,
    /// Tile stores transaction elimination skipped.
    pub transaction_elimination_saved_bytes: u64,
    pub energy: EnergyFigures,
    /// The time estimate of the frame on the preset's device.
    pub time: TimeFigures,
    pub counters: Counters,
    /// Pixels rendered: the sum of every pass's `width × height`.
    pub pixels: u64,
    /// `counters.fragments_shaded / pixels`.
    pub overdraw: f64,
}

/// The energy estimate of a frame (see `tiler::ledger::energy`): a model, not a measurement.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct EnergyFigures {
    /// The preset's figure for external memory, picojoules per byte.
    pub external_pj_per_byte: f64,
    /// The preset's figure for on-chip memory, picojoules per byte.
    pub on_chip_pj_per_byte: f64,
    /// `total_bytes × external_pj_per_byte`, millijoules per frame.
    pub external_millijoules: f64,
    /// `on_chip_bytes × on_chip_pj_per_byte`, millijoules per frame.
    pub on_chip_millijoules: f64,
    /// Their sum, millijoules per frame.
    pub millijoules: f64,
    /// `millijoules × fps` (over `frame_count` for a run): average power, milliwatts.
    pub milliwatts: f64,
}

/// The time estimate of a frame or pass (see `tiler::ledger::time`, `docs/time-model.md`):
/// a model with the preset's figures (`preset.device.time`), not a measurement.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct TimeFigures {
    /// `vertices_shaded / (clock × cores × vertices_per_clock)`, milliseconds.
    pub geometry_ms: f64,
    /// The largest of shading `(fragments_shaded + helper_invocations) / (clock × cores ×
    /// pixels_per_clock)`, texturing `texels_read / 4 / (clock × cores × texels_per_clock)`
    /// and blending `samples_blended / (clock × cores × blended_samples_per_clock)`, ms.
    pub fragment_ms: f64,
    /// `total_bytes / bandwidth`, milliseconds.
    pub memory_ms: f64,
    /// `max(geometry_ms, fragment_ms, memory_ms)`: the stages overlap.
    pub ms: f64,
    /// The stage of `ms`: `geometry`, `fragment` or `memory`.
    pub bound: Stage,
    /// `1000 / ms`: the frame rate the device could reach (`null` for no work).
    pub max_fps: Option<f64>,
    /// `total_bytes × fps / bandwidth`: the share of the device's bandwidth used at the
    /// report's frame rate (1 = all of it).
    pub bandwidth_share: f64,
    /// Frames in flight on the device (seed 000 §23.6): read-backs wait this many frames.
    pub frames_in_flight: u32,
}

impl TimeFigures {
    /// The figures of `frames` frames' work, `estimate` and `total_bytes`, as those of the
    /// average frame: every stage's time scales with its counts, so the run's estimate divided
    /// by the frames is the average frame's, bound by the same stage.
    fn new(model: &TimeModel, estimate: TimeEstimate, total_bytes: u64, fps: f64, frames: u64) -> TimeFigures {
        let per_frame = 1.0 / frames.max(1) as f64;
        let estimate = TimeEstimate {
            geometry_seconds: estimate.geometry_seconds * per_frame,
            fragment_seconds: estimate.fragment_seconds * per_frame,
            memory_seconds: estimate.memory_seconds * per_frame,
            seconds: estimate.seconds * per_frame,
            bound: estimate.bound,
        };
        TimeFigures {
            geometry_ms: estimate.geometry_seconds * 1e3,
            fragment_ms: estimate.fragment_seconds * 1e3,
            memory_ms: estimate.memory_seconds * 1e3,
            ms: estimate.seconds * 1e3,
            bound: estimate.bound,
            max_fps: (estimate.seconds > 0.0).then(|| 1.0 / estimate.seconds),
            bandwidth_share: model.bandwidth_share(total_bytes, fps) * per_frame,
            frames_in_flight: model.frames_in_flight,
        }
    }
}

/// One render pass.
#[derive(Clone, Debug, Serialize)]
pub struct PassFigures {
    /// The pass's position in the frame, from 0.
    pub index: usize,
    pub backend: Backend,
    pub width: u32,
    pub height: u32,
    pub samples: u32,
    pub tile_width: u32,
    pub tile_height: u32,
    /// The configured tile size, `[width, height]`, when the tile memory made tiles smaller.
    pub tile_shrunk_from: Option<[u32; 2]>,
    /// Tile memory a tile uses: every attachment at every sample.
    pub tile_bytes: u64,
    pub tiles_x: u32,
    pub tiles_y: u32,
    pub bytes: Ledger,
    pub total_bytes: u64,
    pub bytes_per_second: f64,
    pub on_chip_bytes: u64,
    pub transaction_elimination_saved_bytes: u64,
    /// The time estimate of the pass alone (its bandwidth share at the report's frame rate).
    pub time: TimeFigures,
    pub counters: Counters,
    pub overdraw: f64,
    pub frame_data: FrameDataReport,
    /// `overdraw_histogram[n]` = pixels shaded `n` times; `null` without an overdraw map.
    pub overdraw_histogram: Option<Vec<u64>>,
    /// Per-tile figures, row-major (`tiles_x` per row); `null` for immediate mode.
    pub tiles: Option<TileArrays>,
    /// Per draw, in submission order.
    pub draws: Vec<DrawStats>,
}

/// Per-tile figures as parallel arrays, row-major.
#[derive(Clone, Debug, Serialize)]
pub struct TileArrays {
    pub list_entries: Vec<u32>,
    pub fragments_shaded: Vec<u32>,
    pub bytes_loaded: Vec<u64>,
    pub bytes_stored: Vec<u64>,
}

impl Document {
    pub fn new(report: &Report) -> Document {
        let first_total = report.columns.first().map(|c| c.frame.ledger().total()).unwrap_or(0);
        let frame_count = report.columns.iter().map(|c| c.frames.len() as u64).max().unwrap_or(0).max(1);
        let columns: Vec<ColumnFigures> =
            report.columns.iter().map(|column| column_figures(column, report.fps, first_total, frame_count)).collect();
        let (width, height) = report.columns.first().map(|c| (c.image.width, c.image.height)).unwrap_or((0, 0));
        let identical_across_columns = report.columns.windows(2).all(|pair| pair[0].image == pair[1].image);
        Document {
            schema: SCHEMA,
            generator: GENERATOR,
            title: report.title.clone(),
            scene: report.scene.clone(),
            fps: report.fps,
            image: ImageInfo { width, height, identical_across_columns },
            categories: Category::ALL.iter().map(|c| CategoryInfo { name: c.name(), formula: c.formula() }).collect(),
            columns,
            findings: report.findings.clone(),
            frame_count,
            passes: report.passes.clone(),
        }
    }

    /// Categories with bytes in some column, in report order: the rows worth showing.
    pub fn categories_in_use(&self) -> Vec<Category> {
        Category::ALL.into_iter().filter(|c| self.columns.iter().any(|column| column.frame.bytes.get(*c) > 0)).collect()
    }
}

/// A column's figures; with `frame_count` frames, per-second figures are the average frame's.
fn column_figures(column: &crate::Column, fps: f64, first_total: u64, frame_count: u64) -> ColumnFigures {
    let frame = &column.frame;
    let ledger = frame.ledger();
    let counters = frame.counters();
    let total_bytes = ledger.total();
    let model = column.preset.device.energy;
    let energy = frame.energy(&model);
    let time_model = column.preset.device.time;
    let pixels: u64 = frame.passes.iter().map(|p| p.width as u64 * p.height as u64).sum();
    ColumnFigures {
        label: column.label.clone(),
        preset: column.preset.clone(),
        backend: column.backend,
        image_digest: format!("fnv1a64:{:016x}", column.image.digest()),
        frame: FrameFigures {
            bytes: ledger,
            total_bytes,
            read_bytes: ledger.read_bytes(),
            written_bytes: ledger.written_bytes(),
            bytes_per_second: frame.bytes_per_second(fps) / frame_count as f64,
            ratio_to_first: (first_total > 0).then(|| total_bytes as f64 / first_total as f64),
            on_chip_bytes: frame.on_chip_bytes(),
            transaction_elimination_saved_bytes: frame.passes.iter().map(|p| p.transaction_elimination_saved).sum(),
            energy: EnergyFigures {
                external_pj_per_byte: model.external_pj_per_byte,
                on_chip_pj_per_byte: model.on_chip_pj_per_byte,
                external_millijoules: energy.external_joules * 1e3,
                on_chip_millijoules: energy.on_chip_joules * 1e3,
                millijoules: energy.total_joules() * 1e3,
                milliwatts: energy.milliwatts(fps) / frame_count as f64,
            },
            time: TimeFigures::new(&time_model, frame.time(&time_model), total_bytes, fps, frame_count),
            counters,
            pixels,
            overdraw: per_pixel(counters.fragments_shaded, pixels),
        },
        present: frame.present,
        driver: frame.driver,
        passes: frame
            .passes
            .iter()
            .enumerate()
            .map(|(index, pass)| pass_figures(index, pass, fps, &time_model))
            .collect(),
        frames: column.frames.iter().map(|span| frame_totals(span, &frame.passes, fps)).collect(),
    }
}

fn frame_totals(span: &FrameSpan, passes: &[PassReport], fps: f64) -> FrameTotals {
    let mut bytes = span.present;
    bytes.merge(&span.driver);
    for pass in passes.iter().skip(span.first_pass).take(span.passes) {
        bytes.merge(&pass.ledger);
    }
    FrameTotals {
        index: span.index,
        first_pass: span.first_pass,
        passes: span.passes,
        bytes,
        total_bytes: bytes.total(),
        bytes_per_second: bytes.total() as f64 * fps,
    }
}

fn pass_figures(index: usize, pass: &PassReport, fps: f64, time_model: &TimeModel) -> PassFigures {
    let pixels = pass.width as u64 * pass.height as u64;
    PassFigures {
        index,
        backend: pass.backend,
        width: pass.width,
        height: pass.height,
        samples: pass.samples,
        tile_width: pass.tile_width,
        tile_height: pass.tile_height,
        tile_shrunk_from: pass.tile_shrunk_from.map(|(w, h)| [w, h]),
        tile_bytes: pass.tile_bytes,
        tiles_x: pass.tiles_x,
        tiles_y: pass.tiles_y,
        bytes: pass.ledger,
        total_bytes: pass.ledger.total(),
        bytes_per_second: pass.ledger.total() as f64 * fps,
        on_chip_bytes: pass.on_chip_bytes,
        transaction_elimination_saved_bytes: pass.transaction_elimination_saved,
        time: TimeFigures::new(
            time_model,
            time_model.estimate(&pass.counters, &pass.ledger),
            pass.ledger.total(),
            fps,
            1,
        ),
        counters: pass.counters,
        overdraw: per_pixel(pass.counters.fragments_shaded, pixels),
        frame_data: pass.frame_data,
        overdraw_histogram: pass.overdraw_map.as_deref().map(overdraw_histogram),
        tiles: (!pass.tiles.is_empty()).then(|| TileArrays {
            list_entries: pass.tiles.iter().map(|t| t.list_entries).collect(),
            fragments_shaded: pass.tiles.iter().map(|t| t.fragments_shaded).collect(),
            bytes_loaded: pass.tiles.iter().map(|t| t.bytes_loaded).collect(),
            bytes_stored: pass.tiles.iter().map(|t| t.bytes_stored).collect(),
        }),
        draws: pass.draws.clone(),
    }
}

/// `count / pixels`, 0 for no pixels.
fn per_pixel(count: u64, pixels: u64) -> f64 {
    if pixels == 0 { 0.0 } else { count as f64 / pixels as f64 }
}

/// Pixels by how many fragments were shaded in them.
pub fn overdraw_histogram(map: &[u16]) -> Vec<u64> {
    let max = map.iter().copied().max().unwrap_or(0) as usize;
    let mut histogram = vec![0u64; max + 1];
    for count in map {
        histogram[*count as usize] += 1;
    }
    histogram
}
