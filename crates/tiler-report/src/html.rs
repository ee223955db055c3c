//! The HTML report: one self-contained file — inline CSS, inline SVG charts, the picture and
//! the map layers as `data:` PNGs, no scripts, nothing fetched — laid out for a 1280-pixel
//! window.
//!
//! Every figure comes from [`Document`], the same values as the JSON report. Each numeric
//! cell carries the exact value and its JSON path within its column
//! (`data-col="0" data-key="frame.total_bytes" data-value="6630912" data-unit="MB"`), so a
//! test (or a reader's tool) can check what the page shows against the JSON.
//!
//! The picture is embedded once, as a CSS background; every map shows it through a dimming
//! filter under a colour layer: per-tile layers are one pixel per tile, scaled up without
//! smoothing, overdraw layers one pixel per pixel.

use std::fmt::Write;

use base64::Engine;
use base64::engine::general_purpose::STANDARD as BASE64;
use tiler::ledger::HsrFallbacks;
use tiler::{Backend, Category};

use crate::format;
use crate::heatmap::{
    DIM, TileMetric, hex, overdraw_overlay, overdraw_t, png_bytes, report_overdraw_max, report_overdraw_top,
    tile_overlay, tile_values, viridis,
};
use crate::schema::{ColumnFigures, Document, PassFigures};
use crate::svg::{category_color, gradient_legend, stacked_bars};
use crate::text::COUNTER_ROWS;
use crate::{Report, Rgba8Image};

/// Escapes text for HTML content and attribute values.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            _ => out.push(c),
        }
    }
    out
}

/// Escaped text with `` `code` `` spans as `<code>`.
fn with_code(text: &str) -> String {
    text.split('`')
        .enumerate()
        .map(|(i, part)| if i % 2 == 1 { format!("<code>{}</code>", escape(part)) } else { escape(part) })
        .collect()
}

/// A PNG `data:` URI of an image; `None` if it cannot be encoded (a malformed image).
fn png_data_uri(image: &Rgba8Image) -> Option<String> {
    if !image.is_consistent() || image.width == 0 || image.height == 0 {
        return None;
    }
    png_bytes(image).ok().map(|png| format!("data:image/png;base64,{}", BASE64.encode(&png)))
}

/// How a numeric cell shows its value.
#[derive(Clone, Copy)]
enum Unit {
    /// Bytes, shown as megabytes.
    Megabytes,
    /// Bytes per second, shown as megabytes per second.
    MegabytesPerSecond,
    /// A whole number, shown with separators.
    Count,
    /// Shown as it is, with [`format::figure`]'s decimals.
    Number,
}

/// The units of a run's totals: `MB/run`, `mJ/run` where a single frame's say `MB/frame`.
pub(crate) fn per_run(text: &str) -> String {
    text.replace("MB/frame", "MB/run").replace("mJ/frame", "mJ/run")
}

/// A numeric `<td>` with its value and JSON path within column `col`.
fn cell(col: usize, key: &str, value: f64, unit: Unit) -> String {
    let (text, unit_name) = match unit {
        Unit::Megabytes => (format::megabytes(value), "MB"),
        Unit::MegabytesPerSecond => (format::megabytes(value), "MB/s"),
        Unit::Count => (format::count(value as u64), "count"),
        Unit::Number => (format::figure(value), "number"),
    };
    format!(
        r#"<td class="num" data-col="{col}" data-key="{key}" data-value="{value}" data-unit="{unit_name}">{text}</td>"#
    )
}

const CSS: &str = r#"
:root { --ink: #1d232b; --muted: #5b6573; --line: #e3e6eb; --card: #ffffff; --page: #f3f4f7; --accent: #2f6db5; }
* { box-sizing: border-box; }
body { margin: 0; background: var(--page); color: var(--ink);
  font: 14px/1.45 system-ui, -apple-system, "Segoe UI", Roboto, "Helvetica Neue", Arial, sans-serif; }
main { max-width: 1200px; margin: 0 auto; padding: 24px 20px 40px; }
header h1 { font-size: 26px; margin: 0 0 2px; letter-spacing: -0.01em; }
header p { margin: 0; color: var(--muted); }
details { margin-top: 10px; } summary { cursor: pointer; font-weight: 600; } table.ops { margin-bottom: 12px; }
section { background: var(--card); border: 1px solid var(--line); border-radius: 10px; padding: 18px 20px; margin-top: 18px; }
h2 { font-size: 18px; margin: 0 0 4px; }
h3 { font-size: 15px; margin: 16px 0 6px; }
p.lead { margin: 0 0 12px; color: var(--muted); max-width: 100ch; }
.overview { display: grid; grid-template-columns: minmax(0, 11fr) minmax(0, 10fr); gap: 22px; align-items: start; }
.stack { position: relative; overflow: hidden; border-radius: 6px; background: #000; width: 100%; }
.frame { position: absolute; inset: 0; background-size: 100% 100%; background-repeat: no-repeat; }
.frame.dim { filter: brightness(DIM); }
.overlay { position: absolute; left: 0; top: 0; }
.overlay.tiles { image-rendering: pixelated; }
figure { margin: 0; }
figcaption { color: var(--muted); font-size: 13px; margin-top: 6px; }
dl.facts { display: grid; grid-template-columns: max-content 1fr; gap: 3px 14px; margin: 0 0 14px; }
dl.facts dt { color: var(--muted); }
dl.facts dd { margin: 0; }
table.headline { font-size: 13px; }
table.headline th, table.headline td { padding: 5px 5px; }
sup { font-size: 10px; color: var(--muted); margin-left: 2px; }
.desc { display: block; font-weight: 400; color: var(--muted); font-size: 12.5px; white-space: normal; margin-top: 1px; }
td.nowrap { white-space: nowrap; }
table { border-collapse: collapse; width: 100%; font-variant-numeric: tabular-nums; }
th, td { padding: 4px 8px; border-bottom: 1px solid var(--line); text-align: left; vertical-align: top; }
thead th { font-weight: 600; border-bottom: 2px solid #cfd4db; white-space: nowrap; }
thead th.sub { font-weight: 500; color: var(--muted); font-size: 12px; }
td.num, th.num { text-align: right; white-space: nowrap; }
tr.total td, tr.total th { font-weight: 600; border-top: 2px solid #cfd4db; }
tr.minor th { font-weight: 400; color: var(--muted); padding-left: 22px; }
tbody th { font-weight: 400; white-space: nowrap; }
td.group, th.group { border-left: 1px solid var(--line); }
.swatch { display: inline-block; width: 11px; height: 11px; border-radius: 2px; margin-right: 7px; vertical-align: -1px; }
.legend-list { display: flex; flex-wrap: wrap; gap: 4px 16px; margin: 8px 0 0; padding: 0; list-style: none; font-size: 13px; }
svg.chart text { font-size: 13px; fill: var(--ink); }
svg.chart .tick, svg.legend .tick { font-size: 11px; fill: var(--muted); }
svg.chart .grid { stroke: var(--line); stroke-width: 1; }
svg.chart .bar-note { fill: var(--muted); }
svg.chart .strong { fill: var(--ink); font-weight: 600; }
svg.chart rect:hover { opacity: 0.8; }
svg.legend text { font-size: 11px; }
.maps { display: grid; grid-template-columns: repeat(3, minmax(0, 1fr)); gap: 14px; }
.maps.two { grid-template-columns: repeat(2, minmax(0, 1fr)); }
.map-head { display: flex; justify-content: space-between; align-items: baseline; gap: 8px; margin-top: 6px; }
.map-head .title { font-weight: 600; font-size: 13px; }
.map-head .max { color: var(--muted); font-size: 12px; white-space: nowrap; }
.steps { display: flex; flex-wrap: wrap; gap: 2px; margin: 8px 0 14px; font-size: 12px; }
.steps span { min-width: 34px; padding: 2px 6px; text-align: center; border-radius: 3px; color: #fff; }
.note { color: var(--muted); font-size: 13px; }
.estimate { display: inline-block; font-size: 11px; font-weight: 600; text-transform: uppercase; letter-spacing: 0.05em;
  background: #fff4d6; color: #7a5a00; border-radius: 4px; padding: 1px 6px; margin-left: 8px; vertical-align: 2px; }
.badge { display: inline-block; font-size: 11px; font-weight: 600; border-radius: 4px; padding: 1px 6px; text-transform: uppercase; }
.badge.info { background: #e3eefb; color: #1f4f8a; }
.badge.warning { background: #fff0d0; color: #7a5200; }
.badge.error { background: #fbe0e0; color: #8a1f1f; }
.finding { border-top: 1px solid var(--line); padding: 10px 0; }
.finding:first-of-type { border-top: 0; }
.finding .id { font-family: ui-monospace, SFMono-Regular, Menlo, Consolas, monospace; font-size: 13px; margin-left: 6px; }
.finding .meta { color: var(--muted); font-size: 13px; }
.finding p { margin: 4px 0; }
code { font-family: ui-monospace, SFMono-Regular, Menlo, Consolas, monospace; font-size: 12.5px; background: #f1f3f6; padding: 0 3px; border-radius: 3px; }
.ok { color: #2e7d32; font-weight: 600; }
.bad { color: #b3261e; font-weight: 600; }
footer { color: var(--muted); font-size: 12px; margin-top: 18px; text-align: center; }
"#;

/// The HTML report.
pub fn to_html(report: &Report) -> String {
    let document = Document::new(report);
    let picture = report.columns.first().and_then(|c| png_data_uri(&c.image));
    let mut html = String::new();
    let title = format!("tiler report · {}", document.title);
    let _ = write!(
        html,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<meta name=\"generator\" content=\"{}\">\n<title>{}</title>\n<style>{}",
        document.generator,
        escape(&title),
        CSS.replace("brightness(DIM)", &format!("brightness({DIM})")),
    );
    if let Some(uri) = &picture {
        let _ = writeln!(html, ".frame {{ background-image: url({uri}); }}");
    }
    html.push_str("</style>\n</head>\n<body>\n<main>\n");

    header(&mut html, &document);
    if document.columns.is_empty() {
        html.push_str("<section><p class=\"note\">This report has no devices.</p></section>\n");
    } else {
        overview(&mut html, &document, report, picture.is_some());
        findings(&mut html, &document);
        devices(&mut html, &document);
        bytes_chart(&mut html, &document);
        bytes_table(&mut html, &document);
        energy(&mut html, &document);
        time(&mut html, &document);
        counters(&mut html, &document);
        frames_table(&mut html, &document);
        passes(&mut html, &document);
        tile_maps(&mut html, &document, report);
        overdraw_maps(&mut html, &document, report);
    }
    formulas(&mut html, &document);
    if document.frame_count > 1 {
        // A run's columns hold the whole run: its totals are per run, not per frame.
        html = per_run(&html);
    }
    let _ = write!(
        html,
        "<footer>Written by {} · JSON schema <code>{}</code> · every figure is also in the JSON report</footer>\n</main>\n</body>\n</html>\n",
        document.generator, document.schema
    );
    html
}

fn samples_text(samples: u32) -> String {
    if samples <= 1 { "1 sample per pixel".to_string() } else { format!("{samples}× MSAA") }
}

fn header(html: &mut String, document: &Document) {
    let scene = &document.scene;
    let _ = writeln!(
        html,
        "<header><h1>{}</h1><p>{} scene · {}×{} · {} · {} frames/s · {} device{}</p></header>",
        escape(&format!("tiler report · {}", document.title)),
        escape(&scene.name),
        scene.width,
        scene.height,
        samples_text(scene.samples),
        document.fps,
        document.columns.len(),
        if document.columns.len() == 1 { "" } else { "s" },
    );
}

/// The `aspect-ratio` of a picture.
fn aspect(width: u32, height: u32) -> String {
    format!("aspect-ratio: {} / {}", width.max(1), height.max(1))
}

fn overview(html: &mut String, document: &Document, report: &Report, has_picture: bool) {
    let scene = &document.scene;
    let image = document.image;
    html.push_str("<section class=\"overview\">\n<figure>");
    if has_picture {
        let _ = write!(
            html,
            r#"<div class="stack" role="img" aria-label="the rendered picture" style="{}"><div class="frame"></div></div>"#,
            aspect(image.width, image.height)
        );
    } else {
        html.push_str("<p class=\"note\">The picture could not be embedded.</p>");
    }
    let same = if image.identical_across_columns {
        match (document.columns.len() > 1, document.frame_count > 1) {
            // A run's report is written only when every presented frame matched
            // (`tiler analyze` checks them one by one); the picture shown is the last.
            (true, true) => format!(
                "the last of {} frames · <span class=\"ok\">every device presented the same picture in every frame, \
                 bit for bit</span>",
                document.frame_count
            ),
            (true, false) => {
                "<span class=\"ok\">every device rendered the same picture, bit for bit</span>".to_string()
            }
            (false, true) => format!("the last of {} frames", document.frame_count),
            (false, false) => "the rendered picture".to_string(),
        }
    } else {
        let differing: Vec<String> =
            report.columns.iter().filter(|c| c.image != report.columns[0].image).map(|c| escape(&c.label)).collect();
        format!("<span class=\"bad\">pictures differ from the first device's: {}</span>", differing.join(", "))
    };
    let _ = write!(html, "<figcaption>{}×{} · {same}</figcaption></figure>\n<div>", image.width, image.height);
    let _ = write!(
        html,
        "<h2>The frame</h2><dl class=\"facts\"><dt>scene</dt><dd>{}</dd><dt>size</dt><dd>{}×{} pixels</dd><dt>samples</dt><dd>{}</dd><dt>draws</dt><dd>{}</dd><dt>triangles</dt><dd>{}</dd><dt>frame rate</dt><dd>{} frames/s (for the per-second figures)</dd><dt>render passes</dt><dd>{}</dd></dl>",
        escape(&scene.name),
        scene.width,
        scene.height,
        samples_text(scene.samples),
        format::count(scene.draws),
        format::count(scene.triangles),
        document.fps,
        document.columns[0].passes.len(),
    );
    html.push_str(
        "<h2>What it costs</h2><table class=\"headline\"><thead><tr><th>device</th><th class=\"num\">MB/frame</th><th class=\"num\">MB/s</th><th class=\"num\">mW<sup>est.</sup></th><th class=\"num\">overdraw</th><th class=\"num\">vs first</th></tr></thead><tbody>",
    );
    for column in &document.columns {
        let frame = &column.frame;
        let _ = write!(
            html,
            "<tr><th><b>{}</b></th><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{:.2}</td><td class=\"num\">{}</td></tr>",
            escape(&column.label),
            format::megabytes(frame.total_bytes as f64),
            format::megabytes(frame.bytes_per_second),
            format::figure(frame.energy.milliwatts),
            frame.overdraw,
            frame.ratio_to_first.map(format::ratio).unwrap_or_else(|| "n/a".into()),
        );
    }
    html.push_str("</tbody></table></div>\n</section>\n");
}

fn findings(html: &mut String, document: &Document) {
    if document.findings.is_empty() {
        return;
    }
    let _ = write!(
        html,
        "<section id=\"findings\"><h2>Findings</h2><p class=\"lead\">{} thing{} to look at, most serious first, each with the rule behind it and what it costs in this frame.</p>",
        document.findings.len(),
        if document.findings.len() == 1 { "" } else { "s" }
    );
    let mut sorted: Vec<_> = document.findings.iter().collect();
    sorted.sort_by_key(|f| std::cmp::Reverse(f.severity));
    for finding in sorted {
        let severity = finding.severity.name();
        let mut meta = vec![rule_citation(&finding.rule)];
        let location = finding.location.describe();
        if !location.is_empty() {
            meta.push(format!("at {}", escape(&location)));
        }
        if let Some(bytes) = finding.cost_bytes {
            meta.push(format!("costs {} MB in its frame", format::megabytes(bytes as f64)));
        }
        if let Some(fragments) = finding.cost_fragments {
            meta.push(format!("costs {} fragments shaded", format::count(fragments)));
        }
        let per_device = device_costs(document, finding);
        if !per_device.is_empty() {
            meta.push(per_device);
        }
        let tried = what_if_lines(finding);
        let _ = write!(
            html,
            "<div class=\"finding\"><span class=\"badge {severity}\">{severity}</span><span class=\"id\">{}</span><p>{}</p><p><b>Advice:</b> {}</p>{tried}<div class=\"meta\">{}</div></div>",
            escape(&finding.id),
            with_code(&finding.message),
            with_code(&finding.advice),
            meta.join(" · "),
        );
    }
    html.push_str("</section>\n");
}

/// The finding's fix, applied and replayed on each device (`tiler analyze --what-if`): the
/// bytes it saved beside the estimate and whether the picture held; empty when not tried.
fn what_if_lines(finding: &crate::Finding) -> String {
    if finding.what_if.is_empty() {
        return String::new();
    }
    let mut html = String::from("<p><b>What if</b> (the fix applied and the frame replayed):</p><ul>");
    for w in &finding.what_if {
        let result = match (w.applied, w.measured_bytes, w.same_picture) {
            (true, Some(measured), Some(same)) => {
                let saved = |n: i64, unit: &str| {
                    if n >= 0 {
                        format!("{} {unit} saved", format::count(n as u64))
                    } else {
                        format!("{} {unit} more", format::count(n.unsigned_abs()))
                    }
                };
                let mut figures = vec![format!(
                    "<b>{}</b> (estimated {})",
                    saved(w.measured_bytes_before_elimination.unwrap_or(measured), "B"),
                    format::count(w.estimated_bytes.unwrap_or(0))
                )];
                if w.measured_bytes_before_elimination.is_some() {
                    figures.push(format!(
                        "of which the device moved {} (transaction elimination skips the stores of unchanged tiles)",
                        saved(measured, "B")
                    ));
                }
                if w.estimated_fragments.is_some() || w.measured_fragments.is_some_and(|n| n != 0) {
                    figures.push(format!(
                        "<b>{}</b> (estimated {})",
                        saved(w.measured_fragments.unwrap_or(0), "fragments"),
                        format::count(w.estimated_fragments.unwrap_or(0))
                    ));
                }
                format!(
                    "{}: {}, {}",
                    escape(&w.fix),
                    figures.join(", "),
                    match (same, w.different_frame) {
                        (true, _) => "same pictures".to_string(),
                        (false, Some(frame)) => format!("<b>the picture changed</b> (from frame {frame})"),
                        (false, None) => "<b>the picture changed</b>".to_string(),
                    }
                )
            }
            _ => format!("not tried: {}", escape(&w.fix)),
        };
        let _ = write!(html, "<li>on <b>{}</b>: {result}</li>", escape(&w.device));
    }
    html.push_str("</ul>");
    html
}

/// What a finding costs on each device of the report, and on which it costs nothing:
/// `on tbr: 0.197 MB · on tbdr: 0.197 MB · nothing on imr`; empty for a one-device report.
fn device_costs(document: &Document, finding: &crate::Finding) -> String {
    if finding.costs.is_empty() {
        return String::new();
    }
    let mut parts = Vec::new();
    for cost in &finding.costs {
        let mut what = Vec::new();
        if let Some(bytes) = cost.cost_bytes {
            what.push(format!("{} MB", format::megabytes(bytes as f64)));
        }
        if let Some(fragments) = cost.cost_fragments {
            what.push(format!("{} fragments", format::count(fragments)));
        }
        if let Some(frames) = cost.cost_stall_frames {
            what.push(format!("{frames} frame(s) stalled"));
        }
        parts.push(format!("<b>on {}</b>: {}", escape(&cost.device), what.join(", ")));
    }
    let free: Vec<String> = document
        .columns
        .iter()
        .filter(|c| finding.costs.iter().all(|cost| cost.device != c.label))
        .map(|c| escape(&c.label))
        .collect();
    if !free.is_empty() {
        parts.push(format!("costs nothing on {}", free.join(", ")));
    }
    parts.join(" · ")
}

/// The tile size of a column's first pass, with any shrink: `16×16 (shrunk from 32×32)`.
fn tile_text(column: &ColumnFigures) -> String {
    match column.passes.first() {
        Some(pass) if pass.backend.is_tiler() => {
            let mut text = format!("{}×{}", pass.tile_width, pass.tile_height);
            if let Some([w, h]) = pass.tile_shrunk_from {
                let _ = write!(text, " (shrunk from {w}×{h} to fit tile memory)");
            }
            text
        }
        _ => "–".to_string(),
    }
}

/// A memory size as configured: `2 MiB`, `16 KiB`, `300 B`.
fn binary_size(bytes: u64) -> String {
    const KIB: u64 = 1 << 10;
    const MIB: u64 = 1 << 20;
    if bytes >= MIB && bytes.is_multiple_of(MIB) {
        format!("{} MiB", bytes / MIB)
    } else if bytes >= KIB && bytes.is_multiple_of(KIB) {
        format!("{} KiB", bytes / KIB)
    } else {
        format!("{bytes} B")
    }
}

fn devices(html: &mut String, document: &Document) {
    html.push_str(
        "<section id=\"devices\"><h2>Devices</h2><p class=\"lead\">Each column of this report is one device preset (a data file: <code>tiler --device NAME|FILE</code>) rendering the same frame.</p><table><thead><tr><th>device</th><th>backend</th><th>tiles</th><th>tile memory</th><th>vertex shading</th><th>transaction elim.</th><th>framebuffer cache</th><th>display</th></tr></thead><tbody>",
    );
    for column in &document.columns {
        let device = &column.preset.device;
        let tiler = column.backend.is_tiler();
        let (backend, description) = if device.backend == column.backend {
            (column.backend.name().to_string(), column.preset.description.clone())
        } else {
            (
                format!("{} (preset: {})", column.backend.name(), device.backend.name()),
                format!("the '{}' preset, rendered with the {} backend instead", column.preset.name, column.backend),
            )
        };
        let cache = &device.framebuffer_cache;
        let cache = if column.backend != Backend::Imr {
            "–".to_string()
        } else if cache.is_enabled() {
            format!("{}, {}-way, {}-byte lines", binary_size(cache.size_bytes as u64), cache.ways, cache.line_bytes)
        } else {
            "none".to_string()
        };
        let display = match (device.display.scan_out, device.display.composition) {
            (true, true) => "scan-out + composition",
            (true, false) => "scan-out",
            (false, true) => "composition",
            (false, false) => "not counted",
        };
        let or_dash = |text: String| if tiler { text } else { "–".to_string() };
        let _ = write!(
            html,
            "<tr><th><b>{}</b><span class=\"desc\">{}</span></th><td class=\"nowrap\">{}</td><td>{}</td><td class=\"nowrap\">{}</td><td class=\"nowrap\">{}</td><td class=\"nowrap\">{}</td><td>{}</td><td class=\"nowrap\">{}</td></tr>",
            escape(&column.label),
            escape(&description),
            escape(&backend),
            tile_text(column),
            or_dash(binary_size(device.tile_memory_bytes)),
            or_dash(match device.vertex_shading {
                tiler::VertexShading::Once => "once".to_string(),
                tiler::VertexShading::PerTile => "per tile".to_string(),
            }),
            or_dash(if device.transaction_elimination { "yes".to_string() } else { "no".to_string() }),
            cache,
            display,
        );
    }
    html.push_str("</tbody></table></section>\n");
}

fn legend_list(categories: &[Category]) -> String {
    let mut out = String::from("<ul class=\"legend-list\">");
    for category in categories {
        let _ = write!(
            out,
            "<li title=\"{}\"><span class=\"swatch\" style=\"background:{}\"></span>{}</li>",
            escape(&category.formula()),
            category_color(*category),
            category.name().replace('_', " ")
        );
    }
    out.push_str("</ul>");
    out
}

fn bytes_chart(html: &mut String, document: &Document) {
    let categories = document.categories_in_use();
    let _ = writeln!(
        html,
        "<section id=\"chart\"><h2>External memory per frame</h2><p class=\"lead\">Bytes that cross between the GPU and external memory in one frame, by category (hover a segment for its figure). Beside each bar: the total, the bandwidth at {} frames/s, and the ratio to the first device.</p>{}{}</section>",
        document.fps,
        stacked_bars(document, &categories),
        legend_list(&categories),
    );
}

/// `<th>` headings, one per column, each spanning `span` cells.
fn column_heads(document: &Document, span: usize) -> String {
    document
        .columns
        .iter()
        .map(|c| format!("<th class=\"num group\" colspan=\"{span}\">{}</th>", escape(&c.label)))
        .collect()
}

fn category_head(category: Category) -> String {
    format!(
        "<th title=\"{}\"><span class=\"swatch\" style=\"background:{}\"></span>{}</th>",
        escape(&category.formula()),
        category_color(category),
        category.name().replace('_', " ")
    )
}

fn bytes_table(html: &mut String, document: &Document) {
    let fps = document.fps;
    let _ = write!(
        html,
        "<section id=\"bytes\"><h2>Bytes by category</h2><p class=\"lead\">Megabytes (10⁶ bytes) per frame and per second at {fps} frames/s. Categories no device used are left out; how each is counted is at the end of the report.</p><table><thead><tr><th rowspan=\"2\">category</th>{}</tr><tr>",
        column_heads(document, 2)
    );
    for _ in &document.columns {
        html.push_str("<th class=\"num sub group\">MB/frame</th><th class=\"num sub\">MB/s</th>");
    }
    html.push_str("</tr></thead><tbody>");
    for category in document.categories_in_use() {
        let _ = write!(html, "<tr>{}", category_head(category));
        for (i, column) in document.columns.iter().enumerate() {
            let bytes = column.frame.bytes.get(category) as f64;
            html.push_str(&cell(i, &format!("frame.bytes.{}", category.name()), bytes, Unit::Megabytes).replacen(
                "class=\"num\"",
                "class=\"num group\"",
                1,
            ));
            html.push_str(&format!("<td class=\"num\">{}</td>", format::megabytes(bytes * fps)));
        }
        html.push_str("</tr>");
    }
    html.push_str("<tr class=\"total\"><th>total</th>");
    for (i, column) in document.columns.iter().enumerate() {
        html.push_str(&cell(i, "frame.total_bytes", column.frame.total_bytes as f64, Unit::Megabytes).replacen(
            "class=\"num\"",
            "class=\"num group\"",
            1,
        ));
        html.push_str(&cell(i, "frame.bytes_per_second", column.frame.bytes_per_second, Unit::MegabytesPerSecond));
    }
    html.push_str("</tr><tr class=\"minor\"><th>read</th>");
    for (i, column) in document.columns.iter().enumerate() {
        html.push_str(&cell(i, "frame.read_bytes", column.frame.read_bytes as f64, Unit::Megabytes));
        html.push_str(&format!("<td class=\"num\">{}</td>", format::megabytes(column.frame.read_bytes as f64 * fps)));
    }
    html.push_str("</tr><tr class=\"minor\"><th>written</th>");
    for (i, column) in document.columns.iter().enumerate() {
        html.push_str(&cell(i, "frame.written_bytes", column.frame.written_bytes as f64, Unit::Megabytes));
        html.push_str(&format!(
            "<td class=\"num\">{}</td>",
            format::megabytes(column.frame.written_bytes as f64 * fps)
        ));
    }
    html.push_str("</tr><tr class=\"total\"><th>ratio to the first device</th>");
    for (i, column) in document.columns.iter().enumerate() {
        match column.frame.ratio_to_first {
            Some(ratio) => {
                let _ = write!(
                    html,
                    r#"<td class="num group" colspan="2" data-col="{i}" data-key="frame.ratio_to_first" data-value="{ratio}" data-unit="ratio">{}</td>"#,
                    format::ratio(ratio)
                );
            }
            None => html.push_str("<td class=\"num group\" colspan=\"2\">n/a</td>"),
        }
    }
    html.push_str("</tr></tbody></table></section>\n");
}

fn energy(html: &mut String, document: &Document) {
    let fps = document.fps;
    let _ = write!(
        html,
        "<section id=\"energy\"><h2>Energy<span class=\"estimate\">estimate</span></h2><p class=\"lead\">Estimated from bytes moved, not measured: energy per frame = external bytes × the preset's picojoules per byte of external memory (DRAM) + on-chip bytes (tile buffer, framebuffer cache) × its picojoules per byte of on-chip SRAM; power = energy per frame × {fps} frames/s. Computation, caches other than those modelled, and static power are left out, so the figures compare devices' memory traffic rather than predict a phone's battery drain.</p><table><thead><tr><th></th>{}</tr></thead><tbody>",
        column_heads(document, 1)
    );
    #[rustfmt::skip]
    let rows: [FigureRow; 7] = [
        ("external memory, pJ/byte (assumed)", "frame.energy.external_pj_per_byte", |c| c.frame.energy.external_pj_per_byte, Unit::Number, false),
        ("on-chip memory, pJ/byte (assumed)", "frame.energy.on_chip_pj_per_byte", |c| c.frame.energy.on_chip_pj_per_byte, Unit::Number, false),
        ("on-chip bytes, MB/frame", "frame.on_chip_bytes", |c| c.frame.on_chip_bytes as f64, Unit::Megabytes, false),
        ("external memory, mJ/frame", "frame.energy.external_millijoules", |c| c.frame.energy.external_millijoules, Unit::Number, false),
        ("on-chip memory, mJ/frame", "frame.energy.on_chip_millijoules", |c| c.frame.energy.on_chip_millijoules, Unit::Number, false),
        ("total, mJ/frame", "frame.energy.millijoules", |c| c.frame.energy.millijoules, Unit::Number, true),
        ("power at the frame rate, mW", "frame.energy.milliwatts", |c| c.frame.energy.milliwatts, Unit::Number, true),
    ];
    figure_rows(html, document, &rows);
    html.push_str("</tbody></table></section>\n");
}

/// A row of figures, one cell per device: its label, its key in the JSON, how to read it, its
/// unit, and whether it is a total (drawn in bold).
type FigureRow = (&'static str, &'static str, fn(&ColumnFigures) -> f64, Unit, bool);

/// One table row per figure, one cell per device.
fn figure_rows(html: &mut String, document: &Document, rows: &[FigureRow]) {
    for &(label, key, get, unit, total) in rows {
        let class = if total { " class=\"total\"" } else { "" };
        let _ = write!(html, "<tr{class}><th>{label}</th>");
        for (i, column) in document.columns.iter().enumerate() {
            html.push_str(&cell(i, key, get(column), unit));
        }
        html.push_str("</tr>");
    }
}

/// The time estimate of each device: its stages, the frame's time and bound, the share of its
/// bandwidth used (`frame.time`; `tiler::ledger::time`).
fn time(html: &mut String, document: &Document) {
    let fps = document.fps;
    let _ = write!(
        html,
        "<section id=\"time\"><h2>Time<span class=\"estimate\">estimate</span></h2><p class=\"lead\">Estimated from the counters and bytes with each preset's clock, cores, per-core rates and bandwidth (their sources are in the preset files), not measured: geometry = vertices shaded ÷ vertex rate; fragment = the largest of fragments shaded (helpers included) ÷ pixel rate, texels read ÷ 4 ÷ bilinear texel rate, and samples blended ÷ blend rate; memory = external bytes ÷ bandwidth. The stages overlap, so the frame takes as long as the slowest, which bounds it. Shader length, caches' latency and clocks that change are left out: a lower bound. Bandwidth used is bytes per frame × {fps} frames/s ÷ the device's bandwidth.</p><table><thead><tr><th></th>{}</tr></thead><tbody>",
        column_heads(document, 1)
    );
    #[rustfmt::skip]
    let rows: [FigureRow; 5] = [
        ("geometry, ms/frame", "frame.time.geometry_ms", |c| c.frame.time.geometry_ms, Unit::Number, false),
        ("fragment, ms/frame", "frame.time.fragment_ms", |c| c.frame.time.fragment_ms, Unit::Number, false),
        ("memory, ms/frame", "frame.time.memory_ms", |c| c.frame.time.memory_ms, Unit::Number, false),
        ("frame, ms", "frame.time.ms", |c| c.frame.time.ms, Unit::Number, true),
        ("share of the bandwidth used at the frame rate (1 = all)", "frame.time.bandwidth_share", |c| c.frame.time.bandwidth_share, Unit::Number, false),
    ];
    figure_rows(html, document, &rows);
    html.push_str("<tr><th>bound by</th>");
    for column in &document.columns {
        let _ = write!(html, "<td class=\"num\">{}</td>", column.frame.time.bound.name());
    }
    html.push_str("</tr><tr><th>frames in flight</th>");
    for column in &document.columns {
        let _ = write!(html, "<td class=\"num\">{}</td>", column.frame.time.frames_in_flight);
    }
    html.push_str("</tr></tbody></table></section>\n");
}

/// HSR fallback reasons with their JSON field names.
type FallbackRow = (&'static str, &'static str, fn(&HsrFallbacks) -> u64);
const FALLBACK_ROWS: [FallbackRow; 7] = [
    ("discard in the shader", "discard", |f| f.discard),
    ("blending", "blending", |f| f.blending),
    ("depth written by the shader", "shader_depth", |f| f.shader_depth),
    ("alpha to coverage", "alpha_to_coverage", |f| f.alpha_to_coverage),
    ("sample mask", "sample_mask", |f| f.sample_mask),
    ("partial colour write mask", "partial_write_mask", |f| f.partial_write_mask),
    ("side effects", "side_effects", |f| f.side_effects),
];

fn counters(html: &mut String, document: &Document) {
    let _ = write!(
        html,
        "<section id=\"counters\"><h2>What the GPU did</h2><p class=\"lead\">Counters of the whole frame. Overdraw is fragments shaded per pixel; HSR fallbacks are fragments a deferred tiler had to shade in submission order, by reason; transaction elimination counts tile stores skipped because the tile had not changed since the previous frame (none in a first frame).</p><table><thead><tr><th></th>{}</tr></thead><tbody>",
        column_heads(document, 1)
    );
    for (label, key, get) in COUNTER_ROWS {
        let _ = write!(html, "<tr><th>{label}</th>");
        for (i, column) in document.columns.iter().enumerate() {
            let value = get(&column.frame.counters) as f64;
            if key.is_empty() {
                let _ = write!(html, "<td class=\"num\">{}</td>", format::count(value as u64));
            } else {
                html.push_str(&cell(i, &format!("frame.counters.{key}"), value, Unit::Count));
            }
        }
        html.push_str("</tr>");
        if label == "HSR fallbacks" {
            for (label, field, get) in FALLBACK_ROWS {
                if document.columns.iter().all(|c| get(&c.frame.counters.hsr_fallback) == 0) {
                    continue;
                }
                let _ = write!(html, "<tr class=\"minor\"><th>HSR fallback: {label}</th>");
                for (i, column) in document.columns.iter().enumerate() {
                    let value = get(&column.frame.counters.hsr_fallback) as f64;
                    html.push_str(&cell(i, &format!("frame.counters.hsr_fallback.{field}"), value, Unit::Count));
                }
                html.push_str("</tr>");
            }
        }
    }
    html.push_str("<tr class=\"total\"><th>overdraw (shaded per pixel)</th>");
    for (i, column) in document.columns.iter().enumerate() {
        let _ = write!(
            html,
            r#"<td class="num" data-col="{i}" data-key="frame.overdraw" data-value="{}" data-unit="number">{:.2}</td>"#,
            column.frame.overdraw, column.frame.overdraw
        );
    }
    html.push_str("</tr><tr><th>transaction elimination saved, MB</th>");
    for (i, column) in document.columns.iter().enumerate() {
        let saved = column.frame.transaction_elimination_saved_bytes as f64;
        html.push_str(&cell(i, "frame.transaction_elimination_saved_bytes", saved, Unit::Megabytes));
    }
    html.push_str("</tr></tbody></table></section>\n");
}

/// A run's frames, each device's total per frame (nothing for a single frame).
fn frames_table(html: &mut String, document: &Document) {
    let Some(first) = document.columns.first().filter(|c| !c.frames.is_empty()) else { return };
    let _ = write!(
        html,
        "<section id=\"frames\"><h2>Frames</h2><p class=\"lead\">{} frames; the figures above are the whole run's, per-second figures the average frame's at {} frames/s. Each frame's external-memory bytes, MB{}:</p><table><thead><tr><th>frame</th><th>passes</th>{}</tr></thead><tbody>",
        document.frame_count,
        document.fps,
        if first.frames.len() > MAX_FRAMES_LISTED {
            format!(" (the first {MAX_FRAMES_LISTED})")
        } else {
            String::new()
        },
        column_heads(document, 1)
    );
    for (f, frame) in first.frames.iter().enumerate().take(MAX_FRAMES_LISTED) {
        let _ = write!(html, "<tr><th>{}</th><td class=\"num\">{}</td>", frame.index, frame.passes);
        for (i, column) in document.columns.iter().enumerate() {
            match column.frames.get(f) {
                Some(totals) => html.push_str(&cell(
                    i,
                    &format!("frames.{f}.total_bytes"),
                    totals.total_bytes as f64,
                    Unit::Megabytes,
                )),
                None => html.push_str("<td></td>"),
            }
        }
        html.push_str("</tr>");
    }
    html.push_str("</tbody></table></section>\n");
}

/// The most frames of a run whose passes the page lists (the JSON report has them all).
const MAX_FRAMES_LISTED: usize = 64;

fn passes(html: &mut String, document: &Document) {
    let pass_count = document.columns.iter().map(|c| c.passes.len()).max().unwrap_or(0);
    let frames = document.columns.first().map(|c| c.frames.as_slice()).unwrap_or_default();
    if frames.is_empty() {
        let _ = write!(
            html,
            "<section id=\"passes\"><h2>Render passes</h2><p class=\"lead\">{pass_count} render pass{} per frame; presenting the frame (display, composition) is counted in the frame's totals, not here.</p>",
            if pass_count == 1 { "" } else { "es" }
        );
        for p in 0..pass_count {
            pass_table(html, document, p);
        }
        html.push_str("</section>\n");
        return;
    }
    let _ = write!(
        html,
        "<section id=\"passes\"><h2>Render passes</h2><p class=\"lead\">{pass_count} render pass{} in {} frames; open a frame to see its passes{}. Presenting a frame (display, composition) is counted in its totals, not in its passes.</p>",
        if pass_count == 1 { "" } else { "es" },
        frames.len(),
        if frames.len() > MAX_FRAMES_LISTED {
            format!(" (the first {MAX_FRAMES_LISTED} are listed; the JSON report has every one)")
        } else {
            String::new()
        }
    );
    for frame in frames.iter().take(MAX_FRAMES_LISTED) {
        let totals: Vec<String> = document
            .columns
            .iter()
            .filter_map(|c| c.frames.iter().find(|f| f.index == frame.index))
            .map(|f| format!("{} MB", format::megabytes(f.total_bytes as f64)))
            .collect();
        let _ = write!(
            html,
            "<details><summary>Frame {} · {} pass{} · {}</summary>",
            frame.index,
            frame.passes,
            if frame.passes == 1 { "" } else { "es" },
            totals.join(" / ")
        );
        for p in frame.first_pass..frame.first_pass + frame.passes {
            pass_table(html, document, p);
        }
        html.push_str("</details>");
    }
    html.push_str("</section>\n");
}

/// The driver's account of pass `p`: what it renders to, why it began and ended, and each
/// attachment's load and store op and why.
fn pass_ops(html: &mut String, document: &Document, p: usize) {
    let Some(info) = document.passes.get(p) else { return };
    let _ = write!(
        html,
        "<p class=\"note\">Renders to {}; began: {}; ended: {}.</p><table class=\"ops\"><thead><tr><th>attachment</th><th>format</th><th>load op</th><th>why</th><th>store op</th><th>why</th></tr></thead><tbody>",
        escape(&info.target),
        escape(&info.began),
        escape(&info.ended)
    );
    for a in &info.attachments {
        let _ = write!(
            html,
            "<tr><th>{}</th><td>{}{}</td><td><code>{}</code></td><td>{}</td><td><code>{}</code></td><td>{}</td></tr>",
            escape(&a.slot),
            escape(&a.format),
            if a.samples > 1 { format!(" ×{}", a.samples) } else { String::new() },
            escape(&a.load),
            escape(&a.load_reason),
            escape(&a.store),
            escape(&a.store_reason)
        );
    }
    html.push_str("</tbody></table>");
}

/// Pass `p` side by side on every device.
fn pass_table(html: &mut String, document: &Document, p: usize) {
    {
        let pass_of = |c: &ColumnFigures| c.passes.get(p).cloned();
        let first = document.columns.iter().find_map(pass_of);
        let Some(first) = first else { return };
        let frame = document.passes.get(p).map(|i| format!("frame {} · ", i.frame)).unwrap_or_default();
        let _ = write!(
            html,
            "<h3>Pass {p} · {frame}{}×{} · {}</h3>",
            first.width,
            first.height,
            samples_text(first.samples)
        );
        pass_ops(html, document, p);
        let _ = write!(html, "<table><thead><tr><th></th>{}</tr></thead><tbody>", column_heads(document, 1));
        let text_row = |html: &mut String, label: &str, text: &dyn Fn(&PassFigures) -> String| {
            let _ = write!(html, "<tr><th>{label}</th>");
            for column in &document.columns {
                let _ = write!(html, "<td class=\"num\">{}</td>", column.passes.get(p).map(text).unwrap_or_default());
            }
            html.push_str("</tr>");
        };
        text_row(html, "tiles", &|pass| {
            if !pass.backend.is_tiler() {
                return "–".to_string();
            }
            let shrunk = pass.tile_shrunk_from.map(|[w, h]| format!(", shrunk from {w}×{h}")).unwrap_or_default();
            format!("{}×{} px, {}×{} grid{shrunk}", pass.tile_width, pass.tile_height, pass.tiles_x, pass.tiles_y)
        });
        text_row(html, "tile memory used per tile", &|pass| {
            if pass.backend.is_tiler() { format::bytes_with_unit(pass.tile_bytes as f64) } else { "–".to_string() }
        });
        text_row(html, "frame data, peak", &|pass| {
            if pass.backend.is_tiler() {
                format::bytes_with_unit(pass.frame_data.peak_bytes as f64)
            } else {
                "–".to_string()
            }
        });
        let categories: Vec<Category> = Category::ALL
            .into_iter()
            .filter(|c| document.columns.iter().any(|col| col.passes.get(p).is_some_and(|pass| pass.bytes.get(*c) > 0)))
            .collect();
        for category in categories {
            let _ = write!(html, "<tr>{}", category_head(category));
            for (i, column) in document.columns.iter().enumerate() {
                match column.passes.get(p) {
                    Some(pass) => html.push_str(&cell(
                        i,
                        &format!("passes.{p}.bytes.{}", category.name()),
                        pass.bytes.get(category) as f64,
                        Unit::Megabytes,
                    )),
                    None => html.push_str("<td></td>"),
                }
            }
            html.push_str("</tr>");
        }
        type PassRow = (&'static str, &'static str, fn(&PassFigures) -> f64, Unit);
        #[rustfmt::skip]
        let rows: [PassRow; 6] = [
            ("total, MB", "total_bytes", |p| p.total_bytes as f64, Unit::Megabytes),
            ("fragments shaded", "counters.fragments_shaded", |p| p.counters.fragments_shaded as f64, Unit::Count),
            ("overdraw (shaded per pixel)", "overdraw", |p| p.overdraw, Unit::Number),
            ("incremental renders", "counters.incremental_renders", |p| p.counters.incremental_renders as f64, Unit::Count),
            ("draws", "counters.draws", |p| p.counters.draws as f64, Unit::Count),
            ("transaction elimination saved, MB", "transaction_elimination_saved_bytes", |p| p.transaction_elimination_saved_bytes as f64, Unit::Megabytes),
        ];
        for (index, (label, key, get, unit)) in rows.into_iter().enumerate() {
            let class = if index == 0 { " class=\"total\"" } else { "" };
            let _ = write!(html, "<tr{class}><th>{label}</th>");
            for (i, column) in document.columns.iter().enumerate() {
                match column.passes.get(p) {
                    Some(pass) => html.push_str(&cell(i, &format!("passes.{p}.{key}"), get(pass), unit)),
                    None => html.push_str("<td></td>"),
                }
            }
            html.push_str("</tr>");
        }
        html.push_str("</tbody></table>");
    }
}

/// A map: the dimmed picture (or black, for a pass of another size) under a colour layer
/// stretched over `layer_width × layer_height` pixels of the pass.
fn map_figure(
    html: &mut String,
    picture_fits: bool,
    (width, height): (u32, u32),
    layer: &Rgba8Image,
    (layer_width, layer_height): (u32, u32),
    pixelated: bool,
    caption: &str,
) {
    let frame = if picture_fits { "<div class=\"frame dim\"></div>" } else { "" };
    let Some(uri) = png_data_uri(layer) else { return };
    let _ = write!(
        html,
        r#"<div class="stack" style="{}">{frame}<img class="overlay{}" alt="" src="{uri}" style="width: {:.4}%; height: {:.4}%"></div>{caption}"#,
        aspect(width, height),
        if pixelated { " tiles" } else { "" },
        layer_width as f64 / width.max(1) as f64 * 100.0,
        layer_height as f64 / height.max(1) as f64 * 100.0,
    );
}

/// The passes a column's maps show: every pass of a single frame; of a run, the last frame's
/// (the picture the maps lie over is the last frame's, and a page of maps for every pass of a
/// long run would grow with it; the JSON report keeps every pass's per-tile figures). Each
/// with its index in the column's passes and its heading.
fn mapped_passes(column: &crate::Column) -> Vec<(usize, String)> {
    match column.frames.last() {
        Some(last) => (last.first_pass..last.first_pass + last.passes)
            .map(|p| (p, format!("frame {} · pass {p}", last.index)))
            .collect(),
        None => (0..column.frame.passes.len()).map(|p| (p, format!("pass {p}"))).collect(),
    }
}

/// A note under a run's maps: which frame they show.
fn maps_note(report: &Report) -> String {
    match report.columns.first().and_then(|c| c.frames.last()) {
        Some(last) if report.columns[0].frames.len() > 1 => format!(
            " For this run of {} frames, the maps are the last frame's (frame {}); the JSON report has every pass's \
             per-tile figures.",
            report.columns[0].frames.len(),
            last.index
        ),
        _ => String::new(),
    }
}

fn tile_maps(html: &mut String, document: &Document, report: &Report) {
    let image = &report.columns[0].image;
    let mut body = String::new();
    for (index, (column, figures)) in report.columns.iter().zip(&document.columns).enumerate() {
        for (p, heading) in mapped_passes(column) {
            let Some(pass) = column.frame.passes.get(p) else { continue };
            if tile_values(pass, TileMetric::ListEntries).is_none() {
                continue;
            }
            let _ = write!(
                body,
                "<h3>{} · {heading} · {}×{} tiles{}</h3><div class=\"maps\">",
                escape(&figures.label),
                pass.tile_width,
                pass.tile_height,
                pass.tile_shrunk_from.map(|(w, h)| format!(" (shrunk from {w}×{h})")).unwrap_or_default()
            );
            for metric in TileMetric::ALL {
                let Some(values) = tile_values(pass, metric) else { continue };
                let max = values.iter().copied().max().unwrap_or(0);
                let layer = tile_overlay(&values, pass.tiles_x, pass.tiles_y);
                let max_text = if metric.is_bytes() { format::bytes_with_unit(max as f64) } else { format::count(max) };
                // A map with every working tile at the maximum has no contrast: say so.
                let working: Vec<u64> = values.iter().copied().filter(|v| *v > 0).collect();
                let uniform = working.len() > 1 && working.iter().all(|v| *v == max);
                let max_text = if uniform { format!("every tile {max_text}") } else { format!("max {max_text}") };
                let caption = format!(
                    "<div class=\"map-head\"><span class=\"title\">{}</span><span class=\"max\">{max_text}</span></div>{}",
                    metric.title(),
                    gradient_legend(&format!("g-{index}-{p}-{}", metric.name()), max, metric.is_bytes()),
                );
                body.push_str("<figure>");
                map_figure(
                    &mut body,
                    fits(image, pass.width, pass.height),
                    (pass.width, pass.height),
                    &layer,
                    (pass.tiles_x * pass.tile_width, pass.tiles_y * pass.tile_height),
                    true,
                    &caption,
                );
                body.push_str("</figure>");
            }
            body.push_str("</div>");
        }
    }
    if body.is_empty() {
        return;
    }
    let _ = writeln!(
        html,
        "<section id=\"heatmaps\"><h2>Per-tile heat maps</h2><p class=\"lead\">Each tiler's tiles coloured by the work they did, over the dimmed picture: how many polygon-list entries the tile read back (geometry that touched it), how many fragments it shaded, and how many bytes its store ops wrote. Each map is scaled from 0 to its own maximum; uncoloured tiles did none of that work.{}</p>{body}</section>",
        maps_note(report)
    );
}

fn fits(image: &Rgba8Image, width: u32, height: u32) -> bool {
    image.width == width && image.height == height && image.is_consistent()
}

fn overdraw_maps(html: &mut String, document: &Document, report: &Report) {
    let image = &report.columns[0].image;
    let max = report_overdraw_max(report);
    let top = report_overdraw_top(report);
    let mut body = String::new();
    for (column, figures) in report.columns.iter().zip(&document.columns) {
        for (p, heading) in mapped_passes(column) {
            let Some(pass) = column.frame.passes.get(p) else { continue };
            let Some(map) = pass.overdraw_map.as_ref() else { continue };
            if map.len() != pass.width as usize * pass.height as usize {
                continue;
            }
            let layer = overdraw_overlay(map, pass.width, pass.height, top);
            let passes = column.frame.passes.len();
            let caption = format!(
                "<div class=\"map-head\"><span class=\"title\">{}{}</span><span class=\"max\">{:.2} shaded/pixel · max {}</span></div>",
                escape(&figures.label),
                if passes > 1 { format!(" · {heading}") } else { String::new() },
                figures.passes[p].overdraw,
                map.iter().max().copied().unwrap_or(0),
            );
            body.push_str("<figure>");
            map_figure(
                &mut body,
                fits(image, pass.width, pass.height),
                (pass.width, pass.height),
                &layer,
                (pass.width, pass.height),
                false,
                &caption,
            );
            body.push_str("</figure>");
        }
    }
    html.push_str("<section id=\"overdraw\"><h2>Overdraw</h2>");
    if body.is_empty() {
        html.push_str("<p class=\"note\">No overdraw map was recorded (the device's <code>overdraw_map</code> setting was off).</p></section>\n");
        return;
    }
    let _ = write!(
        html,
        "<p class=\"lead\">Fragments shaded per pixel, over the dimmed picture. Every map uses the same colours, so devices compare directly: a deferred tiler's hidden-surface removal shades most pixels once; early-Z alone depends on the order of the draws.</p><div class=\"steps\"><span style=\"background:#3a3f47\">0</span>"
    );
    for count in 1..=top {
        let t = overdraw_t(count, top).unwrap_or(0.0);
        let color = viridis(t);
        let text_color = if t > 0.6 { "#1d232b" } else { "#ffffff" };
        let label = if count == top && max > top { format!("{count}+") } else { count.to_string() };
        let _ = write!(html, "<span style=\"background:{};color:{text_color}\">{label}</span>", hex(color));
    }
    let columns = if report.columns.len() == 2 || report.columns.len() == 4 { "maps two" } else { "maps" };
    let _ = writeln!(html, "</div><div class=\"{columns}\">{body}</div></section>");
}

fn formulas(html: &mut String, document: &Document) {
    html.push_str(
        "<section id=\"formulas\"><h2>How each category is counted</h2><p class=\"lead\">Every byte is recorded at one place in the renderer, next to its formula; the text below is that documentation (<code>tiler::Category</code>).</p><table><tbody>",
    );
    for info in &document.categories {
        let category = Category::ALL.into_iter().find(|c| c.name() == info.name);
        let head = match category {
            Some(c) => category_head(c),
            None => format!("<th>{}</th>", escape(info.name)),
        };
        let _ = write!(html, "<tr>{head}<td>{}</td></tr>", with_code(&info.formula));
    }
    html.push_str("</tbody></table></section>\n");
}

/// `rule: seed 000 §23.6`, or the section alone when it is a whole citation already (the GL
/// advisor's name their seeds: `000 §23.3; 001 "How to optimize render passes"`).
fn rule_citation(rule: &crate::Rule) -> String {
    if rule.section.contains('§') || rule.section.contains('"') {
        format!("rule: {}", escape(&rule.section))
    } else {
        format!("rule: seed {} §{}", escape(&rule.seed), escape(&rule.section))
    }
}
