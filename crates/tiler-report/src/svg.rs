//! The HTML report's charts as inline SVG: a stacked bar chart of bytes per category and the
//! gradient legend of heat maps. Written by hand: a few rectangles and labels, laid out once,
//! styled by the page's CSS, with a tooltip (`<title>`) on every segment.

use std::fmt::Write;

use tiler::Category;

use crate::format;
use crate::heatmap::{hex, viridis};
use crate::html::escape;
use crate::schema::Document;

/// The colour of a category: families share a hue — blue for geometry fetch, purple for
/// frame data, green for the tile buffer's loads and stores, gold for textures, grey for
/// presenting, reds and oranges for an immediate-mode GPU's framebuffer traffic.
pub fn category_color(category: Category) -> &'static str {
    match category {
        Category::VertexFetch => "#2f6db5",
        Category::IndexFetch => "#8fb3e3",
        Category::FrameDataWrite => "#6a3d9a",
        Category::FrameDataRead => "#b99bd8",
        Category::TileLoad => "#8fd0a4",
        Category::TileStore => "#2e8b57",
        Category::Resolve => "#1f5f5b",
        Category::TextureFetch => "#d4a017",
        Category::CopyOnWrite => "#8c564b",
        Category::TransformFeedbackWrite => "#4b8c8c",
        Category::Display => "#6b7280",
        Category::Composition => "#b8bec8",
        Category::ImrClear => "#7f1d1d",
        Category::ImrColorRead => "#f6b26b",
        Category::ImrColorWrite => "#e67e22",
        Category::ImrDepthRead => "#f4a3a3",
        Category::ImrDepthWrite => "#d64545",
        Category::ImrStencilRead => "#e7b7dc",
        Category::ImrStencilWrite => "#b5519b",
    }
}

/// A step of 1, 2 or 5 × 10ⁿ that cuts `max` into about `ticks` intervals.
fn nice_step(max: f64, ticks: f64) -> f64 {
    let raw = (max / ticks).max(f64::MIN_POSITIVE);
    let magnitude = 10f64.powf(raw.log10().floor());
    let fraction = raw / magnitude;
    let nice = if fraction <= 1.0 {
        1.0
    } else if fraction <= 2.0 {
        2.0
    } else if fraction <= 5.0 {
        5.0
    } else {
        10.0
    };
    nice * magnitude
}

/// Chart geometry, in SVG units (about pixels at the report's width).
const CHART_WIDTH: f64 = 1100.0;
const LABEL_WIDTH: f64 = 180.0;
const NOTE_WIDTH: f64 = 250.0;
const ROW_HEIGHT: f64 = 34.0;
const BAR_HEIGHT: f64 = 22.0;
const AXIS_HEIGHT: f64 = 26.0;

/// One horizontal bar per column, stacked by category, with the total, the bandwidth at the
/// report's frame rate and the ratio to the first column beside it.
pub fn stacked_bars(document: &Document, categories: &[Category]) -> String {
    let columns = &document.columns;
    let max_mb = columns.iter().map(|c| c.frame.total_bytes).max().unwrap_or(0) as f64 / format::BYTES_PER_MEGABYTE;
    let step = nice_step(if max_mb > 0.0 { max_mb } else { 1.0 }, 5.0);
    let axis_mb = (max_mb / step).ceil().max(1.0) * step;
    let bar_area = CHART_WIDTH - LABEL_WIDTH - NOTE_WIDTH;
    let x_of = |mb: f64| LABEL_WIDTH + mb / axis_mb * bar_area;
    let height = AXIS_HEIGHT + columns.len() as f64 * ROW_HEIGHT + 8.0;

    let mut svg = String::new();
    let _ = write!(
        svg,
        r#"<svg class="chart" viewBox="0 0 {CHART_WIDTH} {height}" width="100%" role="img" aria-label="External-memory bytes per frame by category, per device">"#
    );
    // Axis: gridlines and labels in MB.
    let ticks = (axis_mb / step).round() as usize;
    for i in 0..=ticks {
        let mb = i as f64 * step;
        let x = x_of(mb);
        let _ = write!(
            svg,
            r#"<line class="grid" x1="{x:.1}" y1="{AXIS_HEIGHT}" x2="{x:.1}" y2="{y2:.1}"/><text class="tick" x="{x:.1}" y="16" text-anchor="middle">{label}</text>"#,
            y2 = height - 4.0,
            label = tick_label(mb, step),
        );
    }
    let _ = write!(svg, r#"<text class="tick" x="{:.1}" y="16" text-anchor="end">MB/frame</text>"#, LABEL_WIDTH - 10.0);
    for (row, column) in columns.iter().enumerate() {
        let y = AXIS_HEIGHT + row as f64 * ROW_HEIGHT + (ROW_HEIGHT - BAR_HEIGHT) / 2.0;
        let label = escape(&column.label);
        let _ = write!(
            svg,
            r#"<text class="bar-label" x="{:.1}" y="{:.1}" text-anchor="end">{label}</text>"#,
            LABEL_WIDTH - 10.0,
            y + BAR_HEIGHT / 2.0 + 4.5
        );
        let total = column.frame.total_bytes;
        let mut mb_so_far = 0.0;
        for category in categories {
            let bytes = column.frame.bytes.get(*category);
            if bytes == 0 {
                continue;
            }
            let mb = bytes as f64 / format::BYTES_PER_MEGABYTE;
            let (x0, x1) = (x_of(mb_so_far), x_of(mb_so_far + mb));
            mb_so_far += mb;
            let _ = write!(
                svg,
                r#"<rect x="{x0:.2}" y="{y:.1}" width="{w:.2}" height="{BAR_HEIGHT}" fill="{fill}"><title>{label} · {name}: {mb_text} MB ({share:.1}%)</title></rect>"#,
                w = (x1 - x0).max(0.0),
                fill = category_color(*category),
                name = category.name().replace('_', " "),
                mb_text = format::megabytes(bytes as f64),
                share = bytes as f64 / total.max(1) as f64 * 100.0,
            );
        }
        let ratio = column.frame.ratio_to_first.map(format::ratio).unwrap_or_else(|| "n/a".into());
        let _ = write!(
            svg,
            r#"<text class="bar-note" x="{:.1}" y="{:.1}"><tspan class="strong">{} MB</tspan> · {} MB/s · {ratio}</text>"#,
            x_of(mb_so_far) + 8.0,
            y + BAR_HEIGHT / 2.0 + 4.5,
            format::megabytes(total as f64),
            format::megabytes(column.frame.bytes_per_second),
        );
    }
    svg.push_str("</svg>");
    svg
}

/// An axis label: as many decimals as the step needs.
fn tick_label(mb: f64, step: f64) -> String {
    let decimals = if step >= 1.0 { 0 } else { (-step.log10().floor()) as usize };
    format!("{mb:.decimals$}")
}

/// The legend of a heat map scaled from 0 to `max`: a viridis gradient with its ends and
/// middle labelled; `id` names the gradient (unique in the page).
pub fn gradient_legend(id: &str, max: u64, is_bytes: bool) -> String {
    let label = |v: f64| if is_bytes { format::bytes_with_unit(v) } else { format::count(v.round() as u64) };
    let mut svg = String::new();
    let _ = write!(
        svg,
        r#"<svg class="legend" viewBox="0 0 300 38" width="300" height="38" role="img" aria-label="colour scale from 0 to {max_text}"><defs><linearGradient id="{id}">"#,
        max_text = label(max as f64),
    );
    const STOPS: usize = 8;
    for i in 0..=STOPS {
        let t = i as f64 / STOPS as f64;
        let _ = write!(svg, r#"<stop offset="{t:.3}" stop-color="{}"/>"#, hex(viridis(t)));
    }
    let _ = write!(
        svg,
        r#"</linearGradient></defs><rect x="10" y="4" width="280" height="12" rx="2" fill="url(#{id})"/><text class="tick" x="10" y="32" text-anchor="start">0</text><text class="tick" x="150" y="32" text-anchor="middle">{}</text><text class="tick" x="290" y="32" text-anchor="end">{}</text></svg>"#,
        label(max as f64 / 2.0),
        label(max as f64),
    );
    svg
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_steps() {
        assert_eq!(nice_step(16.25, 5.0), 5.0);
        assert_eq!(nice_step(6.63, 5.0), 2.0);
        assert!((nice_step(0.04, 5.0) - 0.01).abs() < 1e-12);
        assert_eq!(tick_label(0.03, 0.01), "0.03");
        assert_eq!(tick_label(15.0, 5.0), "15");
    }
}
