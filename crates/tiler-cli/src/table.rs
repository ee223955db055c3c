//! Plain-text tables of the ledger and counters, one column per backend.

use std::fmt::Write;

use tiler::{Backend, Category, Counters, Ledger, PassReport};

/// A counter's label and how to read it.
type CounterRow = (&'static str, fn(&Counters) -> u64);

/// Sums the reports of a frame's passes.
fn frame_totals(reports: &[PassReport]) -> (Ledger, Counters) {
    let mut ledger = Ledger::default();
    let mut counters = Counters::default();
    for r in reports {
        ledger.merge(&r.ledger);
        counters.merge(&r.counters);
    }
    (ledger, counters)
}

fn megabytes(bytes: u64) -> String {
    if bytes == 0 { "-".to_string() } else { format!("{:.2} MB", bytes as f64 / 1e6) }
}

fn count(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// External-memory traffic by category and the main counters, per backend, with the ratio of
/// each total to the first column.
pub fn ledger_table(columns: &[(Backend, Vec<PassReport>)]) -> String {
    let totals: Vec<(Ledger, Counters)> = columns.iter().map(|(_, r)| frame_totals(r)).collect();
    let width = 16;
    let mut out = String::new();
    let _ = write!(out, "{:<22}", "external memory");
    for (backend, _) in columns {
        let _ = write!(out, "{:>width$}", backend.name());
    }
    out.push('\n');
    for category in Category::ALL {
        if totals.iter().all(|(l, _)| l.get(category) == 0) {
            continue;
        }
        let _ = write!(out, "  {:<20}", category.name().replace('_', " "));
        for (ledger, _) in &totals {
            let _ = write!(out, "{:>width$}", megabytes(ledger.get(category)));
        }
        out.push('\n');
    }
    let _ = write!(out, "{:<22}", "total");
    for (ledger, _) in &totals {
        let _ = write!(out, "{:>width$}", megabytes(ledger.total()));
    }
    out.push('\n');
    let _ = write!(out, "{:<22}", "  vs first column");
    let base = totals[0].0.total().max(1) as f64;
    for (ledger, _) in &totals {
        let _ = write!(out, "{:>width$}", format!("{:.2}×", ledger.total() as f64 / base));
    }
    out.push_str("\n\n");
    let rows: [CounterRow; 9] = [
        ("triangles in", |c| c.triangles_in),
        ("primitives", |c| c.primitives),
        ("polygon-list entries", |c| c.polygon_list_entries),
        ("tiles", |c| c.tiles_processed),
        ("fragments rasterized", |c| c.fragments_rasterized),
        ("killed by early-Z", |c| c.fragments_early_z_killed),
        ("killed by HSR", |c| c.fragments_hsr_killed),
        ("fragments shaded", |c| c.fragments_shaded),
        ("incremental renders", |c| c.incremental_renders),
    ];
    for (name, get) in rows {
        let _ = write!(out, "{:<22}", name);
        for (_, counters) in &totals {
            let _ = write!(out, "{:>width$}", count(get(counters)));
        }
        out.push('\n');
    }
    let _ = write!(out, "{:<22}", "overdraw (shaded/px)");
    for (i, (_, counters)) in totals.iter().enumerate() {
        let pixels: f64 = columns[i].1.iter().map(|r| r.width as f64 * r.height as f64).sum::<f64>().max(1.0);
        let _ = write!(out, "{:>width$}", format!("{:.2}", counters.fragments_shaded as f64 / pixels));
    }
    out.push('\n');
    out
}
