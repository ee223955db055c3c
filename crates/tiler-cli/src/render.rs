//! `tiler render`: render a glTF file or the built-in scene, write the PNG, print the ledger
//! of every backend.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};
use clap::{Args, ValueEnum};
use tiler::{Backend, Device, DeviceConfig, PassReport};
use tiler_scene::Scene;
use tiler_scene::camera::CameraChoice;
use tiler_scene::compare::{REFERENCE_MIN_FRACTION, REFERENCE_TOLERANCE, compare_rgba8, read_png};
use tiler_scene::shading::{CullPolicy, ModelSceneOptions, Shading, build_model_scene};

use crate::table;

/// Which faces `--cull` removes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum CullArg {
    /// Draw both faces of everything.
    None,
    /// Cull back faces of materials that are not doubleSided.
    Gltf,
}

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// A glTF 2.0 file (.gltf or .glb) to render; without it, the built-in scene.
    pub scene: Option<PathBuf>,

    /// How glTF materials are shaded: `scenes` reproduces SCENES.md (llvmpipe's reference
    /// images: texel values as stored, every texture trilinear and REPEAT, no culling);
    /// `gltf` follows the glTF specification (sRGB textures, the file's samplers, back faces of
    /// single-sided materials culled, BLEND sorted back to front, sRGB output).
    #[arg(long, default_value = "scenes", value_parser = parse_shading)]
    pub shading: Shading,

    /// glTF camera: `auto` (SCENES.md: `interior` for files named sponza*/atrium*, else
    /// `orbit`), `orbit`, `interior`, `gltf` or `gltf:N` (the file's own camera), or
    /// `EX,EY,EZ:TX,TY,TZ[:FOV]` (eye, target, vertical field of view in degrees, default 60).
    #[arg(long, default_value = "auto", value_parser = parse_camera)]
    pub camera: CameraChoice,

    /// Face culling for glTF files; default: `none` with `--shading scenes`, `gltf` with
    /// `--shading gltf`.
    #[arg(long, value_enum)]
    pub cull: Option<CullArg>,

    /// A reference PNG to compare the picture with (at least 99% of pixels within 8/255 per
    /// channel); on failure the difference image is written beside the output as
    /// `<output>.diff.png`.
    #[arg(long)]
    pub compare: Option<PathBuf>,

    /// Backend that renders the picture: `tbr` (tiler with early-Z), `tbdr` (tiler with
    /// hidden-surface removal) or `imr` (immediate mode). The cost table shows every backend.
    #[arg(long, default_value = "tbr")]
    pub backend: Backend,

    /// Framebuffer size, WIDTHxHEIGHT [default: 1280x720 for the built-in scene, 1920x1080
    /// (SCENES.md's frame) for a glTF file].
    #[arg(long, value_parser = parse_size)]
    pub size: Option<(u32, u32)>,

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

fn parse_shading(s: &str) -> Result<Shading, String> {
    s.parse()
}

fn parse_camera(s: &str) -> Result<CameraChoice, String> {
    s.parse()
}

pub fn run(args: &RenderArgs) -> Result<()> {
    let default_size = if args.scene.is_some() { (1920, 1080) } else { (1280, 720) };
    let (width, height) = args.size.unwrap_or(default_size);
    let config = DeviceConfig { backend: args.backend, threads: args.threads, ..DeviceConfig::default() }
        .with_tile_size(args.tile);
    let mut device = Device::new(config).context("creating the device")?;

    let started = Instant::now();
    let scene = match &args.scene {
        None => {
            tiler_scene::builtin::build(&mut device, width, height, args.msaa).context("building the built-in scene")?
        }
        Some(path) => load_model_scene(&mut device, path, args, width, height)?,
    };
    let load_time = started.elapsed();

    // The picture, with the chosen backend.
    let started = Instant::now();
    let reports = scene.render(&mut device, args.backend).context("rendering")?;
    let render_time = started.elapsed();
    let pixels = device.read_rgba8(scene.color)?;
    write_png(&args.output, scene.width, scene.height, &pixels)?;

    println!(
        "{} scene: {}×{}, {} draws, {} triangles; loaded in {:.1} ms",
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
    if let Some(reference) = &args.compare {
        compare_with(reference, &args.output, scene.width, scene.height, &pixels)?;
    }
    Ok(())
}

/// Loads a glTF file and records its frame.
fn load_model_scene(device: &mut Device, path: &Path, args: &RenderArgs, width: u32, height: u32) -> Result<Scene> {
    let model = tiler_scene::gltf::load(path, args.shading)?;
    for warning in &model.warnings {
        eprintln!("tiler: warning: {}: {warning}", model.file_name());
    }
    let cull = args.cull.map(|c| match c {
        CullArg::None => CullPolicy::None,
        CullArg::Gltf => CullPolicy::Gltf,
    });
    let options =
        ModelSceneOptions { camera: args.camera, cull, samples: args.msaa, ..ModelSceneOptions::new(width, height) };
    let (scene, placement) = build_model_scene(device, &model, &options)?;
    let e = placement.eye;
    println!(
        "{}: {} primitives, {} vertices, {} textures; {} shading, {} camera at ({:.3}, {:.3}, {:.3})",
        model.file_name(),
        model.primitives.len(),
        model.vertices(),
        model.textures_loaded,
        args.shading.name(),
        placement.name,
        e.x,
        e.y,
        e.z
    );
    Ok(scene)
}

/// Compares the picture with a reference PNG; writes the difference image when it fails.
fn compare_with(reference: &Path, output: &Path, width: u32, height: u32, pixels: &[u8]) -> Result<()> {
    let (rw, rh, expected) = read_png(reference).map_err(|e| anyhow!(e))?;
    if (rw, rh) != (width, height) {
        bail!("{} is {rw}×{rh}, the picture is {width}×{height}", reference.display());
    }
    let c = compare_rgba8(pixels, &expected, width, height, REFERENCE_TOLERANCE);
    println!(
        "\ncompared with {}: {:.3}% of pixels within {}/255 per channel (largest difference {})",
        reference.display(),
        100.0 * c.fraction_within(),
        c.tolerance,
        c.max_difference
    );
    if !c.passes(REFERENCE_MIN_FRACTION) {
        let diff = output.with_extension("diff.png");
        tiler_scene::compare::write_png(&diff, width, height, &c.difference_image).map_err(|e| anyhow!(e))?;
        bail!(
            "the picture differs from {}: fewer than {}% of pixels within tolerance; difference image: {}",
            reference.display(),
            100.0 * REFERENCE_MIN_FRACTION,
            diff.display()
        );
    }
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

pub fn write_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> Result<()> {
    image::save_buffer(path, rgba, width, height, image::ExtendedColorType::Rgba8)
        .with_context(|| format!("writing {}", path.display()))
}
