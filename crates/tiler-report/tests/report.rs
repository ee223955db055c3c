//! The reports: the JSON follows its schema and documents every field, the HTML shows the
//! JSON's numbers and needs nothing from the network, heat maps have the picture's size, and
//! the same frame on several devices compares picture for picture.

use std::path::{Path, PathBuf};

use serde_json::Value;
use tiler::{Backend, Category, Device, DeviceConfig, DevicePreset, FrameCost};
use tiler_report::{Column, Finding, Location, Report, Rgba8Image, Rule, SceneInfo, Severity, TileMetric};

/// Small enough to render in milliseconds, big enough for several tiles of every size.
const WIDTH: u32 = 96;
const HEIGHT: u32 = 64;

/// The built-in scene rendered on a built-in preset, as `tiler compare` renders it.
fn column(preset_name: &str, samples: u32) -> (Column, SceneInfo) {
    let preset = DevicePreset::builtin(preset_name).unwrap();
    let config = DeviceConfig { threads: 2, overdraw_map: true, ..preset.device.clone() };
    let mut device = Device::new(config).unwrap();
    let scene = tiler_scene::builtin::build(&mut device, WIDTH, HEIGHT, samples).unwrap();
    let mut frame = FrameCost::new(scene.render(&mut device, preset.device.backend).unwrap());
    frame.present = device.present(scene.color).unwrap();
    let image = Rgba8Image::new(scene.width, scene.height, device.read_rgba8(scene.color).unwrap()).unwrap();
    let info = SceneInfo {
        name: scene.name.clone(),
        width: scene.width,
        height: scene.height,
        samples,
        draws: scene.draws() as u64,
        triangles: scene.triangles,
    };
    let backend = preset.device.backend;
    (Column { label: preset.name.clone(), preset, backend, frame, image, frames: Vec::new() }, info)
}

fn report(presets: &[&str], samples: u32) -> Report {
    let mut columns = Vec::new();
    let mut scene = SceneInfo::default();
    for name in presets {
        let (column, info) = column(name, samples);
        columns.push(column);
        scene = info;
    }
    Report { title: "test".into(), scene, fps: 60.0, columns, findings: Vec::new(), passes: Vec::new() }
}

fn json(report: &Report) -> Value {
    serde_json::from_str(&tiler_report::to_json(report)).expect("the JSON report parses")
}

/// The value at a dotted path (`frame.bytes.tile_store`, `passes.0.total_bytes`).
fn at<'a>(value: &'a Value, path: &str) -> &'a Value {
    path.split('.').fold(value, |v, key| match key.parse::<usize>() {
        Ok(i) if v.is_array() => &v[i],
        _ => &v[key],
    })
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tiler-report-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn schema_doc_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/report-schema.md")
}

#[test]
fn json_has_the_schema_version_and_stable_fields() {
    let report = report(&["tbr", "imr"], 1);
    let doc = json(&report);
    assert_eq!(doc["schema"], "tiler-report/1");
    assert_eq!(doc["fps"], 60.0);
    assert_eq!(doc["scene"]["width"], WIDTH);
    assert_eq!(doc["image"]["identical_across_columns"], true);
    assert_eq!(doc["categories"].as_array().unwrap().len(), Category::COUNT);
    for (i, column) in report.columns.iter().enumerate() {
        let c = &doc["columns"][i];
        let ledger = column.frame.ledger();
        assert_eq!(c["label"], column.label.as_str());
        assert_eq!(c["backend"], column.backend.name());
        assert_eq!(c["preset"]["name"], column.label.as_str());
        for category in Category::ALL {
            assert_eq!(c["frame"]["bytes"][category.name()], ledger.get(category), "{}", category.name());
        }
        assert_eq!(c["frame"]["total_bytes"], ledger.total());
        assert_eq!(c["frame"]["bytes_per_second"].as_f64().unwrap(), ledger.total() as f64 * 60.0);
        assert_eq!(c["frame"]["counters"]["fragments_shaded"], column.frame.counters().fragments_shaded);
        let energy = column.frame.energy(&column.preset.device.energy);
        assert!((c["frame"]["energy"]["milliwatts"].as_f64().unwrap() - energy.milliwatts(60.0)).abs() < 1e-9);
        let pass = &c["passes"][0];
        assert_eq!(pass["width"], WIDTH);
        let histogram: u64 = pass["overdraw_histogram"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap()).sum();
        assert_eq!(histogram, (WIDTH * HEIGHT) as u64, "every pixel counted once");
        match column.backend {
            Backend::Imr => assert!(pass["tiles"].is_null()),
            _ => {
                let tiles = pass["tiles"]["list_entries"].as_array().unwrap().len() as u64;
                assert_eq!(tiles, pass["tiles_x"].as_u64().unwrap() * pass["tiles_y"].as_u64().unwrap());
            }
        }
    }
    assert_eq!(doc["columns"][0]["image_digest"], doc["columns"][1]["image_digest"]);
    let digest = doc["columns"][0]["image_digest"].as_str().unwrap();
    assert!(digest.starts_with("fnv1a64:") && digest.len() == 8 + 16, "{digest}");
}

/// Every key the JSON report holds is named in `docs/report-schema.md`.
#[test]
fn every_json_field_is_documented() {
    let mut report = report(&["tbdr", "imr"], 1);
    report.findings.push(finding());
    let doc = json(&report);
    let text = std::fs::read_to_string(schema_doc_path()).unwrap();
    let mut missing = Vec::new();
    fn walk(value: &Value, path: &str, text: &str, missing: &mut Vec<String>) {
        match value {
            Value::Object(map) => {
                for (key, v) in map {
                    if !text.contains(&format!("`{key}`")) {
                        missing.push(format!("{path}.{key}"));
                    }
                    walk(v, &format!("{path}.{key}"), text, missing);
                }
            }
            Value::Array(items) => {
                for v in items.iter().take(1) {
                    walk(v, &format!("{path}[]"), text, missing);
                }
            }
            _ => {}
        }
    }
    walk(&doc, "", &text, &mut missing);
    missing.sort();
    missing.dedup();
    assert!(missing.is_empty(), "fields missing from docs/report-schema.md: {missing:#?}");
}

/// The schema document's table of categories is `Category::formula()`, word for word;
/// `TILER_BLESS=1` rewrites it.
#[test]
fn the_schema_doc_quotes_every_category_formula() {
    const BEGIN: &str = "<!-- categories: generated from tiler::Category::formula() -->\n";
    const END: &str = "<!-- end of categories -->";
    let path = schema_doc_path();
    let text = std::fs::read_to_string(&path).unwrap();
    let (start, end) = (text.find(BEGIN).expect("begin marker") + BEGIN.len(), text.find(END).expect("end marker"));
    let mut table = String::from("| category | what it counts and its formula |\n| --- | --- |\n");
    for category in Category::ALL {
        table.push_str(&format!("| `{}` | {} |\n", category.name(), category.formula().replace('|', "\\|")));
    }
    if std::env::var_os("TILER_BLESS").is_some() {
        std::fs::write(&path, format!("{}{table}{}", &text[..start], &text[end..])).unwrap();
    } else {
        assert_eq!(
            &text[start..end],
            table,
            "docs/report-schema.md's categories are out of date: run TILER_BLESS=1 cargo test -p tiler-report"
        );
    }
}

/// A numeric cell of the HTML report: its column, JSON path, exact value, unit and text.
struct Cell {
    col: usize,
    key: String,
    value: f64,
    unit: String,
    text: String,
}

fn attribute(tag: &str, name: &str) -> Option<String> {
    let start = tag.find(&format!(" {name}=\""))? + name.len() + 3;
    let end = start + tag[start..].find('"')?;
    Some(tag[start..end].to_string())
}

fn cells(html: &str) -> Vec<Cell> {
    let mut cells = Vec::new();
    let mut rest = html;
    while let Some(start) = rest.find("<td ") {
        rest = &rest[start..];
        let tag_end = rest.find('>').unwrap();
        let tag = &rest[..tag_end];
        let text_end = rest.find("</td>").unwrap();
        if let Some(key) = attribute(tag, "data-key") {
            cells.push(Cell {
                col: attribute(tag, "data-col").unwrap().parse().unwrap(),
                key,
                value: attribute(tag, "data-value").unwrap().parse().unwrap(),
                unit: attribute(tag, "data-unit").unwrap(),
                text: rest[tag_end + 1..text_end].to_string(),
            });
        }
        rest = &rest[text_end..];
    }
    cells
}

/// The number a cell shows, in the unit of its value (bytes for MB), and how far from the
/// value rounding may take it.
fn shown(cell: &Cell) -> (f64, f64) {
    let text = cell.text.replace([',', '×'], "");
    if text == "–" {
        return (0.0, 0.0);
    }
    let number: f64 = text.parse().unwrap_or_else(|_| panic!("{}: '{}' is not a number", cell.key, cell.text));
    let decimals = text.split_once('.').map_or(0, |(_, d)| d.len()) as i32;
    let half_step = 0.5 * 10f64.powi(-decimals);
    match cell.unit.as_str() {
        "MB" | "MB/s" => (number * 1e6, half_step * 1e6),
        _ => (number, half_step),
    }
}

#[test]
fn the_html_shows_the_jsons_numbers() {
    let report = report(&["tbr", "tbdr", "imr-no-cache"], 1);
    let doc = json(&report);
    let html = tiler_report::to_html(&report);
    let cells = cells(&html);
    for cell in &cells {
        let expected = at(&doc["columns"][cell.col], &cell.key);
        let expected = expected.as_f64().unwrap_or_else(|| panic!("{} is not a number in the JSON", cell.key));
        // serde_json's default float parser may miss the last bit; the written values are exact.
        assert!(
            (cell.value - expected).abs() <= expected.abs() * 1e-15,
            "column {} {}: data-value {} but the JSON says {expected}",
            cell.col,
            cell.key,
            cell.value
        );
        let (number, tolerance) = shown(cell);
        assert!(
            (number - expected).abs() <= tolerance * (1.0 + 1e-9),
            "column {} {}: shows '{}' for {expected}",
            cell.col,
            cell.key,
            cell.text
        );
    }
    // The totals are among them, for every column.
    for col in 0..report.columns.len() {
        for key in [
            "frame.total_bytes",
            "frame.bytes_per_second",
            "frame.ratio_to_first",
            "frame.energy.millijoules",
            "frame.energy.milliwatts",
            "frame.counters.fragments_shaded",
            "frame.overdraw",
            "frame.bytes.tile_store",
            "passes.0.total_bytes",
        ] {
            let found = cells.iter().any(|c| c.col == col && c.key == key);
            let used = key != "frame.bytes.tile_store" || report.columns[col].backend.is_tiler();
            assert!(found || !used, "the HTML shows no {key} for column {col}");
        }
    }
}

#[test]
fn the_html_is_self_contained() {
    let mut report = report(&["tbr", "imr"], 1);
    report.findings.push(finding());
    let html = tiler_report::to_html(&report);
    assert!(html.starts_with("<!DOCTYPE html>"));
    for forbidden in ["http://", "https://", "<script", "<link", "@import", "src=\"//"] {
        assert!(!html.contains(forbidden), "the HTML holds '{forbidden}'");
    }
    assert!(html.contains("url(data:image/png;base64,"), "the picture is embedded");
    assert!(html.contains("<svg class=\"chart\""), "the bar chart is inline SVG");
    for metric in TileMetric::ALL {
        assert!(html.contains(metric.title()), "{}", metric.title());
    }
    assert!(html.contains("id=\"overdraw\"") && html.contains("estimate"));
    // The finding, with its rule, place and cost.
    for text in ["load-then-overwrite", "seed 003 §23.3", "pass 0", "glClear #1", "Advice:"] {
        assert!(html.contains(text), "the finding's '{text}'");
    }
    // A section that is a whole citation (the GL advisor's) is not prefixed again.
    let mut cited = finding();
    cited.rule.section = "000 §23.6; 001 \"Render pass steps to avoid\"".into();
    report.findings = vec![cited];
    let html = tiler_report::to_html(&report);
    assert!(html.contains("rule: 000 §23.6") && !html.contains("§000"), "the citation as given");
    // Every formula is quoted.
    assert!(html.contains("vertices shaded × Σ attribute sizes"));
}

fn finding() -> Finding {
    Finding {
        id: "load-then-overwrite".into(),
        severity: Severity::Warning,
        rule: Rule { seed: "003".into(), section: "23.3".into(), text: String::new() },
        location: Location { frame: Some(0), pass: Some(0), call: Some("glClear #1".into()), call_at: None },
        cost_bytes: Some(24_576),
        cost_fragments: None,
        cost_stall_frames: None,
        message: "The pass loads colour it then overwrites entirely.".into(),
        advice: "Clear the attachment (`LoadOp::Clear`) or invalidate it.".into(),
        costs: Vec::new(),
        what_if: Vec::new(),
    }
}

#[test]
fn findings_round_trip_through_the_json() {
    let mut report = report(&["tbr"], 1);
    report.findings.push(finding());
    let doc = json(&report);
    let back: Finding = serde_json::from_value(doc["findings"][0].clone()).unwrap();
    assert_eq!(back, finding());
    assert_eq!(doc["findings"][0]["severity"], "warning");
    assert!(doc["findings"][0]["cost_fragments"].is_null());
}

#[test]
fn heat_map_pngs_have_the_pictures_size() {
    let report = report(&["tbr", "imr"], 1);
    let dir = temp_dir("heatmaps");
    let written = tiler_report::write_heatmaps(&report, &dir).unwrap();
    // The tiler: three tile maps and an overdraw map; immediate mode: an overdraw map.
    let names: Vec<String> = written.iter().map(|p| p.file_name().unwrap().to_string_lossy().into_owned()).collect();
    assert_eq!(
        names,
        [
            "tbr-pass0-list-entries.png",
            "tbr-pass0-fragments-shaded.png",
            "tbr-pass0-bytes-stored.png",
            "tbr-pass0-overdraw.png",
            "imr-pass0-overdraw.png"
        ]
    );
    for path in &written {
        let image = image::open(path).unwrap();
        assert_eq!((image.width(), image.height()), (WIDTH, HEIGHT), "{}", path.display());
    }
    std::fs::remove_dir_all(&dir).unwrap();
    // A directory that cannot be made is an error naming it, not a panic.
    let file = temp_dir("not-a-dir");
    std::fs::write(&file, b"").unwrap();
    let error = tiler_report::write_heatmaps(&report, &file.join("maps")).unwrap_err().to_string();
    assert!(error.contains("not-a-dir"), "{error}");
    std::fs::remove_file(&file).unwrap();
}

/// `tiler compare`'s view: two presets, one picture, each total against the first.
#[test]
fn two_presets_compare_picture_for_picture_with_a_ratio() {
    let report = report(&["tbdr", "imr-no-cache"], 1);
    assert_eq!(report.columns[0].image, report.columns[1].image, "the same picture, bit for bit");
    let doc = json(&report);
    let totals: Vec<f64> = (0..2).map(|i| doc["columns"][i]["frame"]["total_bytes"].as_f64().unwrap()).collect();
    assert_eq!(doc["columns"][0]["frame"]["ratio_to_first"], 1.0);
    let ratio = doc["columns"][1]["frame"]["ratio_to_first"].as_f64().unwrap();
    assert!((ratio - totals[1] / totals[0]).abs() < 1e-12);
    let table = tiler_report::text_table(&report);
    let ratio_row = table.lines().find(|l| l.trim_start().starts_with("vs first column")).expect("a ratio row");
    assert!(ratio_row.contains("1.00×") && ratio_row.contains(&format!("{:.2}×", totals[1] / totals[0])), "{table}");
    assert!(!table.contains("different picture"), "{table}");
}

#[test]
fn a_report_of_an_msaa_frame() {
    let report = report(&["tbr", "imr"], 4);
    let doc = json(&report);
    assert_eq!(doc["scene"]["samples"], 4);
    let tbr = &doc["columns"][0];
    assert_eq!(tbr["passes"][0]["samples"], 4);
    // Colour samples live in the tile and are resolved there: one single-sample image stored.
    assert_eq!(tbr["frame"]["bytes"]["resolve"], WIDTH * HEIGHT * 4);
    assert_eq!(tbr["frame"]["bytes"]["tile_store"], 0);
    let html = tiler_report::to_html(&report);
    assert!(html.contains("4× MSAA"));
    assert!(cells(&html).iter().any(|c| c.key == "frame.bytes.resolve"));
    let dir = temp_dir("msaa");
    for path in tiler_report::write_heatmaps(&report, &dir).unwrap() {
        let image = image::open(&path).unwrap();
        assert_eq!((image.width(), image.height()), (WIDTH, HEIGHT), "{}", path.display());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn malformed_reports_do_not_panic() {
    let empty = Report {
        title: "nothing".into(),
        scene: SceneInfo::default(),
        fps: f64::NAN,
        columns: Vec::new(),
        findings: Vec::new(),
        passes: Vec::new(),
    };
    assert!(tiler_report::to_html(&empty).contains("no devices"));
    assert_eq!(json(&empty)["fps"], Value::Null);
    assert!(tiler_report::text_table(&empty).contains("total"));
    let mut broken = report(&["tbr"], 1);
    broken.columns[0].image.pixels.truncate(7);
    assert!(tiler_report::to_html(&broken).contains("could not be embedded"));
    assert!(tiler_report::write_heatmaps(&broken, &temp_dir("broken")).is_ok());
}

/// The time estimate in the JSON is the preset's figures applied to the frame's counters and
/// bytes (docs/time-model.md), recomputed here from the JSON alone; the text table and the
/// HTML show it.
#[test]
fn the_time_estimate_follows_its_formula() {
    let report = report(&["mali-g710", "adreno-650", "powervr-gx6450", "desktop-imr"], 1);
    let doc = json(&report);
    for column in doc["columns"].as_array().unwrap() {
        let t = &column["preset"]["device"]["time"];
        let f = |v: &Value| v.as_f64().unwrap();
        let rate = |per_clock: &str| f(&t["clock_mhz"]) * 1e6 * f(&t["cores"]) * f(&t[per_clock]);
        let c = &column["frame"]["counters"];
        let geometry = f(&c["vertices_shaded"]) / rate("vertices_per_clock") * 1e3;
        let fragment = ((f(&c["fragments_shaded"]) + f(&c["helper_invocations"])) / rate("pixels_per_clock"))
            .max(f(&c["texels_read"]) / 4.0 / rate("texels_per_clock"))
            .max(f(&c["samples_blended"]) / rate("blended_samples_per_clock"))
            * 1e3;
        let bytes = f(&column["frame"]["total_bytes"]);
        let memory = bytes / (f(&t["bandwidth_gb_per_s"]) * 1e9) * 1e3;
        let time = &column["frame"]["time"];
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs().max(1e-9);
        assert!(close(f(&time["geometry_ms"]), geometry), "{time}");
        assert!(close(f(&time["fragment_ms"]), fragment), "{time}");
        assert!(close(f(&time["memory_ms"]), memory), "{time}");
        let (bound, ms) = [("geometry", geometry), ("fragment", fragment), ("memory", memory)]
            .into_iter()
            .fold(("geometry", geometry), |a, b| if b.1 > a.1 { b } else { a });
        assert!(close(f(&time["ms"]), ms), "{time}");
        assert_eq!(time["bound"], bound);
        assert!(close(f(&time["bandwidth_share"]), bytes * 60.0 / (f(&t["bandwidth_gb_per_s"]) * 1e9)));
        assert!(c["vertices_shaded"].as_u64().unwrap() > 0);
    }
    // Tilers keep a frame more in flight than the immediate-mode GPU.
    let in_flight: Vec<u64> = doc["columns"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["frame"]["time"]["frames_in_flight"].as_u64().unwrap())
        .collect();
    assert_eq!(in_flight, [3, 3, 3, 2]);
    let text = tiler_report::text_table(&report);
    assert!(text.contains("bound by") && text.contains("time, ms/frame"), "{text}");
    let html = tiler_report::to_html(&report);
    assert!(html.contains("id=\"time\"") && html.contains("data-key=\"frame.time.ms\""));
}
