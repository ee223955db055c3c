//! The side-by-side plain-text table `tiler render` and `tiler compare` print: bytes by
//! category, totals per frame and per second, energy, and the main counters, one column per
//! device, with the ratio of each total to the first column.

use std::fmt::Write;

use tiler::Counters;

use crate::Report;
use crate::format;
use crate::schema::{ColumnFigures, Document};

/// A counter's label, its field in the JSON counters (empty for a derived figure) and how
/// to read it.
type CounterRow = (&'static str, &'static str, fn(&Counters) -> u64);

/// The counters every table shows.
pub(crate) const COUNTER_ROWS: [CounterRow; 12] = [
    ("triangles in", "triangles_in", |c| c.triangles_in),
    ("primitives", "primitives", |c| c.primitives),
    ("polygon-list entries", "polygon_list_entries", |c| c.polygon_list_entries),
    ("tiles", "tiles_processed", |c| c.tiles_processed),
    ("fragments rasterized", "fragments_rasterized", |c| c.fragments_rasterized),
    ("killed by early-Z", "fragments_early_z_killed", |c| c.fragments_early_z_killed),
    ("killed by HSR", "fragments_hsr_killed", |c| c.fragments_hsr_killed),
    ("HSR fallbacks", "", |c| c.hsr_fallback.total()),
    ("fragments shaded", "fragments_shaded", |c| c.fragments_shaded),
    ("helper invocations", "helper_invocations", |c| c.helper_invocations),
    ("incremental renders", "incremental_renders", |c| c.incremental_renders),
    ("killed after shading", "fragments_late_killed", |c| c.fragments_late_killed),
];

/// Writes one row of the table: a label and one cell per column.
type RowWriter<'a> = dyn Fn(&mut String, &str, &dyn Fn(&ColumnFigures) -> String) + 'a;

/// The time estimate's rows: each stage, the frame, its bound and the bandwidth share.
fn time_rows(out: &mut String, document: &Document, row: &RowWriter<'_>) {
    row(out, "time, ms/frame (estimate)", &|c| format!("{:.3}", c.frame.time.ms));
    row(out, "  geometry, ms", &|c| format!("{:.3}", c.frame.time.geometry_ms));
    row(out, "  fragment, ms", &|c| format!("{:.3}", c.frame.time.fragment_ms));
    row(out, "  memory, ms", &|c| format!("{:.3}", c.frame.time.memory_ms));
    row(out, "  bound by", &|c| c.frame.time.bound.name().to_string());
    row(out, &format!("bandwidth used at {} frames/s", document.fps), &|c| {
        format!("{:.2}%", c.frame.time.bandwidth_share * 100.0)
    });
    row(out, "frames in flight", &|c| c.frame.time.frames_in_flight.to_string());
}

/// The table for a report.
pub fn text_table(report: &Report) -> String {
    let document = Document::new(report);
    let columns = &document.columns;
    let label_width = 30;
    // Each column as wide as its heading, and at least as wide as a figure.
    let widths: Vec<usize> = columns.iter().map(|c| (c.label.chars().count() + 2).max(12)).collect();
    let mut out = String::new();
    let row = |out: &mut String, label: &str, cell: &dyn Fn(&ColumnFigures) -> String| {
        let _ = write!(out, "{label:<label_width$}");
        for (column, width) in columns.iter().zip(&widths) {
            let _ = write!(out, "{:>width$}", cell(column));
        }
        out.push('\n');
    };

    row(&mut out, "external memory, MB/frame", &|c| c.label.clone());
    for category in document.categories_in_use() {
        row(&mut out, &format!("  {}", category.name().replace('_', " ")), &|c| {
            format::megabytes(c.frame.bytes.get(category) as f64)
        });
    }
    row(&mut out, "total, MB/frame", &|c| format::megabytes(c.frame.total_bytes as f64));
    row(&mut out, &format!("total, MB/s at {} frames/s", document.fps), &|c| {
        format::megabytes(c.frame.bytes_per_second)
    });
    row(&mut out, "  vs first column", &|c| c.frame.ratio_to_first.map(format::ratio).unwrap_or_else(|| "n/a".into()));
    row(&mut out, "energy, mJ/frame (estimate)", &|c| format::figure(c.frame.energy.millijoules));
    row(&mut out, &format!("power, mW at {} frames/s", document.fps), &|c| format::figure(c.frame.energy.milliwatts));
    time_rows(&mut out, &document, &row);
    out.push('\n');
    for (label, _, get) in COUNTER_ROWS {
        row(&mut out, label, &|c| format::count(get(&c.frame.counters)));
    }
    row(&mut out, "overdraw (shaded/pixel)", &|c| format!("{:.2}", c.frame.overdraw));
    if columns.iter().any(|c| c.frame.transaction_elimination_saved_bytes > 0) {
        row(&mut out, "transaction elim. saved, MB", &|c| {
            format::megabytes(c.frame.transaction_elimination_saved_bytes as f64)
        });
    }
    if document.frame_count > 1 {
        out = crate::html::per_run(&out);
        let _ = writeln!(
            out,
            "(a run of {} frames: totals are the run's, per-second figures the average frame's)",
            document.frame_count
        );
    }
    if !document.image.identical_across_columns {
        let differing: Vec<&str> =
            report.columns.iter().filter(|c| c.image != report.columns[0].image).map(|c| c.label.as_str()).collect();
        let _ = writeln!(out, "\nwarning: a different picture from the first column's: {}", differing.join(", "));
    }
    out
}
