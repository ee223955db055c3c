//! `tiler render`: render a scene, write the PNG, print the ledger of every backend.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::Args;
use tiler::{Backend, Device, DeviceConfig, PassReport};
use tiler_scene::Scene;

use crate::table;

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Backend that renders the picture: `tbr` (tiler with early-Z), `tbdr` (tiler with
    /// hidden-surface removal) or `imr` (immediate mode). The cost table shows every backend.
    #[arg(long, default_value = "tbr")]
    pub backend: Backend,

    /// Framebuffer size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x720", value_parser = parse_size)]
    pub size: (u32, u32),

    /// Tile size in pixels (a multiple of 8 from 8 to 256; 16, 32 and 64 are typical).
    #[arg(long, default_value_t = 32)]
    pub tile: u32,

    /// Worker threads (0 = one per core).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,

    /// Samples per pixel: 1, 2, 4 or 8 (MSAA, resolved in the tile on the tilers).
    #[arg(long, default_value_t = 1)]
    pub msaa: u32,

    /// Where to write the picture (PNG).
    #[arg(short, long, default_value = "render.png")]
    pub output: PathBuf,
}

/// Parses `WIDTHxHEIGHT`.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| format!("'{s}' is not WIDTHxHEIGHT (e.g. 1280x720)"))?;
    let parse = |v: &str| v.trim().parse::<u32>().map_err(|_| format!("'{v}' in '{s}' is not a whole number"));
    Ok((parse(w)?, parse(h)?))
}

pub fn run(args: &RenderArgs) -> Result<()> {
    let (width, height) = args.size;
    let config = DeviceConfig { backend: args.backend, threads: args.threads, ..DeviceConfig::default() }
        .with_tile_size(args.tile);
    let mut device = Device::new(config).context("creating the device")?;

    let started = Instant::now();
    let scene =
        tiler_scene::builtin::build(&mut device, width, height, args.msaa).context("building the built-in scene")?;
    let load_time = started.elapsed();

    // The picture, with the chosen backend.
    let started = Instant::now();
    let reports = scene.render(&mut device, args.backend).context("rendering")?;
    let render_time = started.elapsed();
    let pixels = device.read_rgba8(scene.color)?;
    write_png(&args.output, scene.width, scene.height, &pixels)?;

    println!(
        "{} scene: {}×{}, {} draws, {} triangles; built in {:.1} ms",
        scene.name,
        width,
        height,
        scene.draws(),
        scene.triangles,
        load_time.as_secs_f64() * 1e3
    );
    let tiles = match reports.first() {
        Some(r) if r.backend.is_tiler() => match r.tile_shrunk_from {
            Some((w, h)) => {
                format!("{}×{} tiles, shrunk from {w}×{h} to fit tile memory, ", r.tile_width, r.tile_height)
            }
            None => format!("{}×{} tiles, ", r.tile_width, r.tile_height),
        },
        _ => String::new(),
    };
    println!(
        "rendered with {} ({}{}× MSAA, {} threads) in {:.1} ms → {}",
        args.backend,
        tiles,
        args.msaa,
        device.threads(),
        render_time.as_secs_f64() * 1e3,
        args.output.display()
    );

    // The same frame on every backend, for the cost table.
    let mut columns: Vec<(Backend, Vec<PassReport>)> = Vec::new();
    for backend in Backend::ALL {
        let reports = if backend == args.backend {
            reports.clone()
        } else {
            render_again(&scene, &mut device, backend, &pixels)?
        };
        columns.push((backend, reports));
    }
    println!();
    print!("{}", table::ledger_table(&columns));
    Ok(())
}

/// Renders the scene with another backend and checks it gives the same picture.
fn render_again(scene: &Scene, device: &mut Device, backend: Backend, expected: &[u8]) -> Result<Vec<PassReport>> {
    let reports = scene.render(device, backend).with_context(|| format!("rendering with {backend}"))?;
    if device.read_rgba8(scene.color)? != expected {
        bail!("the {backend} backend gave a different image: this is a tiler bug, please report it");
    }
    Ok(reports)
}

pub fn write_png(path: &PathBuf, width: u32, height: u32, rgba: &[u8]) -> Result<()> {
    image::save_buffer(path, rgba, width, height, image::ExtendedColorType::Rgba8)
        .with_context(|| format!("writing {}", path.display()))
}
