//! `tiler compare`: the same frame on several device presets (and, optionally, several
//! variants of a scene) side by side — bytes by category, MB/frame and MB/s, estimated
//! energy, fragments shaded, overdraw, and the ratio to the first column — with a check that
//! every device rendered the same picture of each scene.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use tiler::{Device, DevicePreset};
use tiler_report::{Column, Report};

use crate::frame::{self, Setup};
use crate::report_args::ReportArgs;
use crate::scene_args::SceneArgs;

#[derive(Args, Debug)]
pub struct CompareArgs {
    /// Devices to compare, comma-separated: built-in preset names (tbr, tbdr,
    /// tbr-per-tile-vertex, imr, imr-no-cache) or preset files (.toml, .json). Default: every
    /// built-in preset. Ratios are to the first.
    #[arg(long, value_delimiter = ',', value_name = "NAME|FILE,...")]
    pub devices: Vec<String>,

    /// The scenes: `builtin` (default), `deferred`, `deferred-passes` or glTF files. With more
    /// than one, every scene is rendered on every device and the columns are labelled
    /// `scene/device` — `tiler compare deferred deferred-passes --devices tbdr` sets subpasses
    /// against two passes through memory.
    pub scenes: Vec<String>,

    #[command(flatten)]
    pub scene_args: SceneArgs,

    /// Worker threads (0 = one per core).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,

    #[command(flatten)]
    pub report: ReportArgs,
}

/// The presets named, or every built-in one, and the preset files read.
pub(crate) fn presets(names: &[String]) -> Result<(Vec<DevicePreset>, Vec<PathBuf>)> {
    if names.is_empty() {
        return Ok((DevicePreset::builtins(), Vec::new()));
    }
    let mut presets = Vec::new();
    let mut files = Vec::new();
    for name in names {
        let (preset, file) = crate::files::load_preset(Some(name.trim()))
            .with_context(|| format!("--devices: loading '{}'", name.trim()))?;
        presets.push(preset);
        files.extend(file);
    }
    Ok((presets, files))
}

pub fn run(args: &CompareArgs) -> Result<()> {
    args.report.check(&[])?;
    let (presets, mut inputs) = presets(&args.devices)?;
    let names: Vec<&str> =
        if args.scenes.is_empty() { vec!["builtin"] } else { args.scenes.iter().map(String::as_str).collect() };
    // Every scene is loaded before anything is rendered, so no report overwrites one of its files.
    let sources = names.iter().map(|name| args.scene_args.source(Some(name))).collect::<Result<Vec<_>>>()?;
    inputs.extend(sources.iter().flat_map(|s| s.inputs()));
    args.report.check(&inputs)?;
    let setup = Setup { threads: args.threads, simd: None, tile: None, overdraw_map: args.report.wants_maps() };
    let mut columns: Vec<Column> = Vec::with_capacity(presets.len() * names.len());
    let mut scenes = Vec::with_capacity(names.len());
    let mut findings = Vec::with_capacity(columns.capacity());
    let mut passes = Vec::with_capacity(names.len());
    for (name, source) in names.iter().zip(sources) {
        if let Some(line) = args.scene_args.describe(&source) {
            println!("{line}");
        }
        let load = |device: &mut Device| args.scene_args.build(&source, device);
        let first_of_scene = columns.len();
        for preset in &presets {
            let label = if names.len() == 1 { preset.name.clone() } else { format!("{name}/{}", preset.name) };
            let rendered = frame::render(&label, preset, preset.device.backend, &setup, &load)?;
            if let Some(first) = columns.get(first_of_scene)
                && first.image != rendered.column.image
            {
                bail!(
                    "'{}' rendered a different picture of {name} from '{}': every device must give the same \
                     picture, bit for bit; this is a tiler bug, please report it",
                    preset.name,
                    first.label
                );
            }
            println!(
                "{:<30} {:>5} rendered in {:>7.1} ms",
                label,
                preset.device.backend.name(),
                rendered.render_time.as_secs_f64() * 1e3
            );
            if columns.len() == first_of_scene {
                scenes.push(rendered.scene.clone());
                passes.push(rendered.passes);
            }
            findings.push((rendered.column.label.clone(), rendered.findings));
            columns.push(rendered.column);
        }
    }
    let scene = scenes.first().cloned().unwrap_or_default();
    let title = if scenes.len() == 1 {
        format!("{} scene on {} devices", scene.name, columns.len())
    } else {
        let names: Vec<&str> = scenes.iter().map(|s| s.name.as_str()).collect();
        format!("{} on {} devices", names.join(" vs "), presets.len())
    };
    for info in &scenes {
        println!(
            "\n{} scene: {}×{}, {} sample{} per pixel, {} draws, {} triangles; every device rendered the same picture",
            info.name,
            info.width,
            info.height,
            info.samples,
            if info.samples == 1 { "" } else { "s" },
            info.draws,
            info.triangles,
        );
    }
    let findings = tiler_report::finding::merge_per_device(&findings);
    // Scene variants have passes of their own: the ops are shown for a single scene.
    let passes = if passes.len() == 1 { passes.remove(0) } else { Vec::new() };
    let report = Report { title, scene, fps: args.report.fps, columns, findings, passes };
    args.report.write_and_print(&report)
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::*;

    #[derive(Parser)]
    struct Wrapper {
        #[command(flatten)]
        scene_args: SceneArgs,
    }

    fn scene_args(args: &[&str]) -> SceneArgs {
        Wrapper::parse_from(std::iter::once("tiler").chain(args.iter().copied())).scene_args
    }

    fn args(devices: &[&str], reports: Vec<std::path::PathBuf>) -> CompareArgs {
        CompareArgs {
            devices: devices.iter().map(|d| d.to_string()).collect(),
            scenes: Vec::new(),
            scene_args: scene_args(&["--size", "64x48"]),
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
    fn scene_variants_are_columns_with_one_picture() {
        let path = std::env::temp_dir().join(format!("tiler-compare-variants-{}.json", std::process::id()));
        let mut args = args(&["tbdr"], vec![path.clone()]);
        args.scenes = vec!["deferred".into(), "deferred-passes".into()];
        run(&args).unwrap();
        let doc: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        std::fs::remove_file(&path).unwrap();
        let columns = doc["columns"].as_array().unwrap();
        let labels: Vec<&str> = columns.iter().map(|c| c["label"].as_str().unwrap()).collect();
        assert_eq!(labels, ["deferred/tbdr", "deferred-passes/tbdr"]);
        assert_eq!(doc["image"]["identical_across_columns"], true, "subpasses and passes draw the same picture");
        let ratio = columns[1]["frame"]["ratio_to_first"].as_f64().unwrap();
        // At 64×48 geometry and frame data weigh as much as the G-buffer, so the margin is small.
        assert!(ratio > 1.05, "two passes through memory cost more than subpasses: ratio {ratio}");
    }

    #[test]
    fn bad_devices_and_report_paths_are_errors_naming_them() {
        let error = run(&args(&["tbr", "/nonexistent/my-gpu.toml"], Vec::new())).unwrap_err();
        assert!(format!("{error:#}").contains("my-gpu.toml"), "{error:#}");
        let error = run(&args(&["tbr"], vec!["/nonexistent-dir/out.html".into()])).unwrap_err();
        assert!(format!("{error:#}").contains("/nonexistent-dir"), "{error:#}");
    }
}
