//! `tiler compare`: the same frame on several device presets, side by side — bytes by
//! category, MB/frame and MB/s, estimated energy, fragments shaded, overdraw, and the ratio
//! to the first device — with a check that every device rendered the same picture.

use anyhow::{Context, Result, bail};
use clap::Args;
use tiler::{Device, DevicePreset};
use tiler_report::{Column, Report};
use tiler_scene::Scene;

use crate::frame::{self, Setup};
use crate::render::parse_size;
use crate::report_args::ReportArgs;

#[derive(Args, Debug)]
pub struct CompareArgs {
    /// Devices to compare, comma-separated: built-in preset names (tbr, tbdr,
    /// tbr-per-tile-vertex, imr, imr-no-cache) or preset files (.toml, .json). Default: every
    /// built-in preset. Ratios are to the first.
    #[arg(long, value_delimiter = ',', value_name = "NAME|FILE,...")]
    pub devices: Vec<String>,

    /// Framebuffer size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x720", value_parser = parse_size)]
    pub size: (u32, u32),

    /// Samples per pixel: 1, 2, 4 or 8 (MSAA, resolved in the tile on the tilers).
    #[arg(long, default_value_t = 1)]
    pub msaa: u32,

    /// Worker threads (0 = one per core).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,

    #[command(flatten)]
    pub report: ReportArgs,
}

/// The scene every device renders: the built-in one. (A scene file argument plugs in here.)
pub fn load_scene(device: &mut Device, args: &CompareArgs) -> Result<Scene> {
    let (width, height) = args.size;
    tiler_scene::builtin::build(device, width, height, args.msaa).context("building the built-in scene")
}

/// The presets named, or every built-in one.
fn presets(names: &[String]) -> Result<Vec<DevicePreset>> {
    if names.is_empty() {
        return Ok(DevicePreset::builtins());
    }
    names
        .iter()
        .map(|name| DevicePreset::load(name.trim()).with_context(|| format!("--devices: loading '{}'", name.trim())))
        .collect()
}

pub fn run(args: &CompareArgs) -> Result<()> {
    args.report.check()?;
    let presets = presets(&args.devices)?;
    let setup = Setup { threads: args.threads, tile: None, overdraw_map: args.report.wants_maps() };
    let load = |device: &mut Device| load_scene(device, args);
    let mut columns: Vec<Column> = Vec::with_capacity(presets.len());
    let mut scene = None;
    for preset in &presets {
        let rendered = frame::render(&preset.name, preset, preset.device.backend, &setup, &load)?;
        if let Some(first) = columns.first()
            && first.image != rendered.column.image
        {
            bail!(
                "'{}' rendered a different picture from '{}': every device must give the same picture, bit for \
                 bit; this is a tiler bug, please report it",
                preset.name,
                first.label
            );
        }
        println!(
            "{:<22} {:>5} rendered in {:>7.1} ms",
            preset.name,
            preset.device.backend.name(),
            rendered.render_time.as_secs_f64() * 1e3
        );
        scene.get_or_insert(rendered.scene);
        columns.push(rendered.column);
    }
    let scene = scene.unwrap_or_default();
    let report = Report {
        title: format!("{} scene on {} devices", scene.name, columns.len()),
        scene,
        fps: args.report.fps,
        columns,
        findings: Vec::new(),
    };
    println!(
        "\n{} scene: {}×{}, {} sample{} per pixel, {} draws, {} triangles; every device rendered the same picture",
        report.scene.name,
        report.scene.width,
        report.scene.height,
        report.scene.samples,
        if report.scene.samples == 1 { "" } else { "s" },
        report.scene.draws,
        report.scene.triangles,
    );
    args.report.write_and_print(&report)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(devices: &[&str], reports: Vec<std::path::PathBuf>) -> CompareArgs {
        CompareArgs {
            devices: devices.iter().map(|d| d.to_string()).collect(),
            size: (64, 48),
            msaa: 1,
            threads: 2,
            report: ReportArgs { fps: 30.0, report: reports, heatmaps: None },
        }
    }

    #[test]
    fn two_presets_give_one_picture_and_a_ratio_to_the_first() {
        let path = std::env::temp_dir().join(format!("tiler-compare-test-{}.json", std::process::id()));
        run(&args(&["tbdr", "imr-no-cache"], vec![path.clone()])).unwrap();
        let doc: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        std::fs::remove_file(&path).unwrap();
        assert_eq!(doc["image"]["identical_across_columns"], true);
        assert_eq!(doc["fps"], 30.0);
        let columns = doc["columns"].as_array().unwrap();
        let labels: Vec<&str> = columns.iter().map(|c| c["label"].as_str().unwrap()).collect();
        assert_eq!(labels, ["tbdr", "imr-no-cache"]);
        let totals: Vec<f64> = columns.iter().map(|c| c["frame"]["total_bytes"].as_f64().unwrap()).collect();
        assert_eq!(columns[0]["frame"]["ratio_to_first"], 1.0);
        let ratio = columns[1]["frame"]["ratio_to_first"].as_f64().unwrap();
        assert!((ratio - totals[1] / totals[0]).abs() < 1e-12);
        assert!(columns[1]["passes"][0]["overdraw_histogram"].is_array(), "reports record overdraw maps");
    }

    #[test]
    fn bad_devices_and_report_paths_are_errors_naming_them() {
        let error = run(&args(&["tbr", "/nonexistent/my-gpu.toml"], Vec::new())).unwrap_err();
        assert!(format!("{error:#}").contains("my-gpu.toml"), "{error:#}");
        let error = run(&args(&["tbr"], vec!["/nonexistent-dir/out.html".into()])).unwrap_err();
        assert!(format!("{error:#}").contains("/nonexistent-dir"), "{error:#}");
    }
}
