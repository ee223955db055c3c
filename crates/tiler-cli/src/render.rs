//! `tiler render`: render a scene, write the PNG, print the cost of the frame on every
//! backend, and write reports.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use tiler::{Backend, Device, DeviceConfig, DevicePreset};
use tiler_report::Report;

use crate::frame::{self, Setup};
use crate::report_args::ReportArgs;

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Device preset: a built-in name (tbr, tbdr, tbr-per-tile-vertex, imr, imr-no-cache) or
    /// a preset file (.toml or .json). Default: tiler's default device (32×32 tiles, 32 KiB
    /// tile memory, no framebuffer cache).
    #[arg(long, value_name = "NAME|FILE")]
    pub device: Option<String>,

    /// Backend that renders the picture: `tbr` (tiler with early-Z), `tbdr` (tiler with
    /// hidden-surface removal) or `imr` (immediate mode); overrides the preset's. The cost
    /// table shows every backend, this one first.
    #[arg(long)]
    pub backend: Option<Backend>,

    /// Framebuffer size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x720", value_parser = parse_size)]
    pub size: (u32, u32),

    /// Tile size in pixels (a multiple of 8 from 8 to 256; 16, 32 and 64 are typical);
    /// overrides the preset's.
    #[arg(long)]
    pub tile: Option<u32>,

    /// Worker threads (0 = one per core).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,

    /// Samples per pixel: 1, 2, 4 or 8 (MSAA, resolved in the tile on the tilers).
    #[arg(long, default_value_t = 1)]
    pub msaa: u32,

    /// Where to write the picture (PNG).
    #[arg(short, long, default_value = "render.png")]
    pub output: PathBuf,

    #[command(flatten)]
    pub report: ReportArgs,
}

/// Parses `WIDTHxHEIGHT`.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| format!("'{s}' is not WIDTHxHEIGHT (e.g. 1280x720)"))?;
    let parse = |v: &str| v.trim().parse::<u32>().map_err(|_| format!("'{v}' in '{s}' is not a whole number"));
    Ok((parse(w)?, parse(h)?))
}

/// The preset `--device` names, or tiler's default device.
fn device_preset(device: Option<&str>) -> Result<DevicePreset> {
    match device {
        Some(name) => DevicePreset::load(name).with_context(|| format!("--device {name}")),
        None => Ok(DevicePreset {
            name: "default".into(),
            description: "tiler's default device: 32×32 tiles, 32 KiB tile memory, early-Z, no framebuffer cache"
                .into(),
            device: DeviceConfig::default(),
        }),
    }
}

pub fn run(args: &RenderArgs) -> Result<()> {
    args.report.check()?;
    let (width, height) = args.size;
    let preset = device_preset(args.device.as_deref())?;
    let backend = args.backend.unwrap_or(preset.device.backend);
    let setup = Setup { threads: args.threads, tile: args.tile, overdraw_map: args.report.wants_maps() };
    let load = |device: &mut Device| {
        tiler_scene::builtin::build(device, width, height, args.msaa).context("building the built-in scene")
    };

    // The picture, with the chosen backend.
    let first = frame::render(backend.name(), &preset, backend, &setup, &load)?;
    let image = &first.column.image;
    write_png(&args.output, image.width, image.height, &image.pixels)?;
    let scene = first.scene.clone();
    println!(
        "{} scene: {}×{}, {} draws, {} triangles; built in {:.1} ms",
        scene.name,
        width,
        height,
        scene.draws,
        scene.triangles,
        first.load_time.as_secs_f64() * 1e3
    );
    let tiles = match first.column.frame.passes.first() {
        Some(r) if r.backend.is_tiler() => match r.tile_shrunk_from {
            Some((w, h)) => {
                format!("{}×{} tiles, shrunk from {w}×{h} to fit tile memory, ", r.tile_width, r.tile_height)
            }
            None => format!("{}×{} tiles, ", r.tile_width, r.tile_height),
        },
        _ => String::new(),
    };
    println!(
        "rendered on '{}' with {} ({}{}× MSAA, {} threads) in {:.1} ms → {}",
        preset.name,
        backend,
        tiles,
        args.msaa,
        first.threads,
        first.render_time.as_secs_f64() * 1e3,
        args.output.display()
    );

    // The same frame on every other backend, for the cost table.
    let mut columns = vec![first.column];
    for other in Backend::ALL.into_iter().filter(|b| *b != backend) {
        let rendered = frame::render(other.name(), &preset, other, &setup, &load)?;
        if rendered.column.image != columns[0].image {
            bail!("the {other} backend gave a different image: this is a tiler bug, please report it");
        }
        columns.push(rendered.column);
    }
    let report = Report {
        title: format!("{} scene on '{}'", scene.name, preset.name),
        scene,
        fps: args.report.fps,
        columns,
        findings: Vec::new(),
    };
    args.report.write_and_print(&report)
}

pub fn write_png(path: &PathBuf, width: u32, height: u32, rgba: &[u8]) -> Result<()> {
    image::save_buffer(path, rgba, width, height, image::ExtendedColorType::Rgba8)
        .with_context(|| format!("writing {}", path.display()))
}
