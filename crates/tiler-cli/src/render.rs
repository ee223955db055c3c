//! `tiler render`: render a scene (built-in, made in code, or a glTF file), write the PNG,
//! print the cost of the frame on every backend, and write reports.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use tiler::{Backend, Device};
use tiler_report::Report;
use tiler_scene::compare::{REFERENCE_MIN_FRACTION, REFERENCE_TOLERANCE, compare_rgba8, read_png};

use crate::files;
use crate::frame::{self, Setup};
use crate::report_args::ReportArgs;
use crate::scene_args::SceneArgs;

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// The scene: `builtin` (default), `deferred` (deferred shading in one pass with
    /// subpasses), `deferred-passes` (the same in two passes through memory), or a glTF 2.0
    /// file (.gltf or .glb).
    pub scene: Option<String>,

    #[command(flatten)]
    pub scene_args: SceneArgs,

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

    /// Tile size in pixels (a multiple of 8 from 8 to 256; 16, 32 and 64 are typical);
    /// overrides the preset's.
    #[arg(long)]
    pub tile: Option<u32>,

    /// Worker threads (0 = one per core).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,

    /// The instruction set of the pixel pipeline: `baseline` or `avx2` [default: the best this
    /// processor runs]. Every level gives the same picture, bit for bit.
    #[arg(long)]
    pub simd: Option<tiler::SimdLevel>,

    /// A reference PNG to compare the picture with (at least 99% of pixels within 8/255 per
    /// channel); on failure the difference image is written beside the output as
    /// `<output>.diff.png`.
    #[arg(long)]
    pub compare: Option<PathBuf>,

    /// Where to write the picture (PNG).
    #[arg(short, long, default_value = "render.png")]
    pub output: PathBuf,

    #[command(flatten)]
    pub report: ReportArgs,
}

pub fn run(args: &RenderArgs) -> Result<()> {
    // Outputs first: a known format and a place to write, before anything is loaded.
    files::check_png("-o", &args.output, &[])?;
    args.report.check(&[])?;
    let (preset, preset_file) = files::load_preset(args.device.as_deref())
        .with_context(|| format!("--device {}", args.device.as_deref().unwrap_or("")))?;
    let backend = args.backend.unwrap_or(preset.device.backend);
    let setup =
        Setup { threads: args.threads, simd: args.simd, tile: args.tile, overdraw_map: args.report.wants_maps() };
    let source = args.scene_args.source(args.scene.as_deref())?;
    // Then no output may be an input: the model and its files, the preset, the reference.
    let mut inputs = source.inputs();
    inputs.extend(preset_file);
    inputs.extend(args.compare.clone());
    files::check_png("-o", &args.output, &inputs)?;
    args.report.check(&inputs)?;
    if args.compare.is_some() {
        files::check_png("the difference image", &diff_path(&args.output), &inputs)?;
    }
    if let Some(line) = args.scene_args.describe(&source) {
        println!("{line}");
    }
    let load = |device: &mut Device| args.scene_args.build(&source, device);

    // The picture, with the chosen backend.
    let first = frame::render(backend.name(), &preset, backend, &setup, &load)?;
    let image = &first.column.image;
    files::write_png(&args.output, image.width, image.height, &image.pixels)?;
    let scene = first.scene.clone();
    println!(
        "{} scene: {}×{}, {} draws, {} triangles; loaded in {:.1} ms",
        scene.name,
        scene.width,
        scene.height,
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
        args.scene_args.msaa,
        first.threads,
        first.render_time.as_secs_f64() * 1e3,
        args.output.display()
    );

    // The same frame on every other backend, for the cost table.
    let passes = first.passes;
    let mut findings = vec![(first.column.label.clone(), first.findings)];
    let mut columns = vec![first.column];
    for other in Backend::ALL.into_iter().filter(|b| *b != backend) {
        let rendered = frame::render(other.name(), &preset, other, &setup, &load)?;
        if rendered.column.image != columns[0].image {
            bail!("the {other} backend gave a different image: this is a tiler bug, please report it");
        }
        findings.push((rendered.column.label.clone(), rendered.findings));
        columns.push(rendered.column);
    }
    let (width, height) = (scene.width, scene.height);
    let pixels = columns[0].image.pixels.clone();
    let report = Report {
        title: format!("{} scene on '{}'", scene.name, preset.name),
        scene,
        fps: args.report.fps,
        columns,
        findings: tiler_report::finding::merge_per_device(&findings),
        passes,
    };
    args.report.write_and_print(&report)?;
    if let Some(reference) = &args.compare {
        compare_with(reference, &args.output, width, height, &pixels)?;
    }
    Ok(())
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
        let diff = diff_path(output);
        files::write_png(&diff, width, height, &c.difference_image)?;
        bail!(
            "the picture differs from {}: fewer than {}% of pixels within tolerance; difference image: {}",
            reference.display(),
            100.0 * REFERENCE_MIN_FRACTION,
            diff.display()
        );
    }
    Ok(())
}

/// Where `--compare` writes the difference image: beside the output, `<output>.diff.png`.
fn diff_path(output: &Path) -> PathBuf {
    output.with_extension("diff.png")
}
