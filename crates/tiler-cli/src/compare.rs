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
        "\n{} scene: {}×{}, {} sample{} per pixel, {} draws, {} triangles; every device rendered the same picture\n",
        report.scene.name,
        report.scene.width,
        report.scene.height,
        report.scene.samples,
        if report.scene.samples == 1 { "" } else { "s" },
        report.scene.draws,
        report.scene.triangles,
    );
    print!("{}", tiler_report::text_table(&report));
    args.report.write(&report)
}
