//! `tiler bench`: the benchmark scenes of SCENES.md, timed frame by frame, as a table or JSON
//! comparable with llvmpipe's figures (`../shared/peers/RESULTS.md`).

use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;
use tiler::{Backend, Device, DeviceConfig, SimdLevel};
use tiler_scene::bench::{BenchCase, BenchScene, build, standard_cases};

use crate::scene_args::{parse_samples, parse_size};

#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Scenes to run (comma-separated or repeated): clear, helmet, atrium, overdraw,
    /// overdraw_f2b, tris. Default: all of them.
    #[arg(long = "scene", value_delimiter = ',')]
    pub scenes: Vec<String>,

    /// Timed frames per scene.
    #[arg(long, default_value_t = 10)]
    pub frames: usize,

    /// Untimed frames before the timed ones.
    #[arg(long, default_value_t = 3)]
    pub warmup: usize,

    /// Framebuffer size, WIDTHxHEIGHT (SCENES.md's frame is 1920x1080).
    #[arg(long, default_value = "1920x1080", value_parser = parse_size)]
    pub size: (u32, u32),

    /// Worker threads (0 = one per core).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,

    /// Backend: `tbr` (tiler with early-Z) or `imr` (immediate mode).
    #[arg(long, default_value = "tbr")]
    pub backend: Backend,

    /// Tile size in pixels.
    #[arg(long, default_value_t = 32)]
    pub tile: u32,

    /// Samples per pixel of the colour and depth attachments (1, 2, 4, 8 or 16); the samples
    /// are resolved in the tile and only the resolved image is stored.
    #[arg(long, default_value_t = 1, value_parser = parse_samples)]
    pub msaa: u32,

    /// The instruction set of the pixel pipeline: `baseline` or `avx2` [default: the best this
    /// processor runs].
    #[arg(long)]
    pub simd: Option<SimdLevel>,

    /// Folder holding the glTF models (DamagedHelmet/, Atrium/) [default: $TILER_ASSETS, else
    /// ../shared/assets].
    #[arg(long)]
    pub assets: Option<PathBuf>,

    /// Write the last frame of each scene as `<scene>.png` into this folder.
    #[arg(long)]
    pub out: Option<PathBuf>,

    /// Print the results as JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// The figures of one scene.
#[derive(Debug, Serialize)]
struct SceneResult {
    scene: String,
    width: u32,
    height: u32,
    msaa: u32,
    frames: usize,
    warmup: usize,
    load_ms: f64,
    median_ms: f64,
    min_ms: f64,
    fps: f64,
    mpix_per_s: f64,
    triangles: u64,
    mtris_per_s: Option<f64>,
    mfrag_shaded_per_s: Option<f64>,
    /// External-memory bytes of one frame, every category.
    external_bytes: u64,
    texture_fetch_bytes: u64,
    fragments_shaded: u64,
    /// Primitives written to the frame data (tilers; immediate mode: rasterized).
    primitives: u64,
    /// Modelled frame-data bytes written per primitive: its primitive and state records and
    /// polygon-list entries (tilers; 0 on immediate mode).
    frame_data_bytes_per_primitive: f64,
    /// The most host memory the frame data held during a pass.
    frame_data_peak_host_bytes: u64,
    times_ms: Vec<f64>,
}

#[derive(Debug, Serialize)]
struct Report {
    backend: Backend,
    threads: usize,
    simd: String,
    tile: u32,
    results: Vec<SceneResult>,
    skipped: Vec<String>,
}

/// The most timed or warm-up frames a run may ask for (nothing is allocated per frame up
/// front, but a run should end: at 1 ms a frame this is over a minute and a half).
const MAX_FRAMES: usize = 100_000;

pub fn run(args: &BenchArgs) -> Result<()> {
    if args.frames == 0 || args.frames > MAX_FRAMES {
        bail!("--frames must be from 1 to {MAX_FRAMES}, not {}", args.frames);
    }
    if args.warmup > MAX_FRAMES {
        bail!("--warmup must be at most {MAX_FRAMES}, not {}", args.warmup);
    }
    if let Some(dir) = &args.out {
        crate::files::check_dir("--out", dir)?;
    }
    let assets = args
        .assets
        .clone()
        .or_else(|| std::env::var_os("TILER_ASSETS").map(PathBuf::from))
        .unwrap_or_else(|| PathBuf::from("../shared/assets"));
    let all = standard_cases(&assets);
    let cases: Vec<BenchCase> = if args.scenes.is_empty() {
        all
    } else {
        let mut chosen = Vec::new();
        for name in &args.scenes {
            match all.iter().find(|c| c.name.eq_ignore_ascii_case(name)) {
                Some(case) => chosen.push(case.clone()),
                None => {
                    let names: Vec<&str> = all.iter().map(|c| c.name.as_str()).collect();
                    bail!("unknown scene '{name}' (expected one of: {})", names.join(", "));
                }
            }
        }
        chosen
    };
    let (width, height) = args.size;
    let config =
        DeviceConfig { backend: args.backend, threads: args.threads, simd: args.simd, ..DeviceConfig::default() }
            .with_tile_size(args.tile);

    let mut skipped = Vec::new();
    let runnable: Vec<BenchCase> = cases
        .into_iter()
        .filter(|case| match &case.scene {
            BenchScene::Gltf { path } if !path.exists() => {
                skipped.push(format!("{}: {} not found (set TILER_ASSETS or --assets)", case.name, path.display()));
                false
            }
            _ => true,
        })
        .collect();
    // A scene asked for by name must run; only the default set skips missing models.
    if !args.scenes.is_empty()
        && let Some(first) = skipped.first()
    {
        bail!("cannot run {first}");
    }
    for s in &skipped {
        eprintln!("tiler: skipped {s}");
    }

    let total_frames = runnable.len() as u64 * (args.frames + args.warmup) as u64;
    let progress = if std::io::stdout().is_terminal() {
        let bar = ProgressBar::new(total_frames);
        bar.set_style(
            ProgressStyle::with_template("{spinner} {msg:<14} [{bar:30}] {pos}/{len} frames, {elapsed}")
                .expect("a valid template")
                .progress_chars("=> "),
        );
        bar
    } else {
        ProgressBar::hidden()
    };

    let mut results = Vec::new();
    let mut threads = 0;
    let mut simd = SimdLevel::best();
    for case in &runnable {
        progress.set_message(format!("{} (loading)", case.name));
        let mut device = Device::new(config.clone()).context("creating the device")?;
        threads = device.threads();
        simd = device.config().simd.unwrap_or_default();
        let started = Instant::now();
        let (scene, work) = build(&mut device, &case.scene, width, height, args.msaa)
            .with_context(|| format!("building scene {}", case.name))?;
        let load = started.elapsed();
        progress.set_message(case.name.clone());
        let mut times = Vec::new();
        let mut last = Vec::new();
        for frame in 0..args.warmup + args.frames {
            let started = Instant::now();
            last = scene.render(&mut device, args.backend).with_context(|| format!("rendering {}", case.name))?;
            let elapsed = started.elapsed();
            if frame >= args.warmup {
                times.push(elapsed);
            }
            progress.inc(1);
        }
        if let Some(dir) = &args.out {
            let pixels = device.read_rgba8(scene.color)?;
            let path = dir.join(format!("{}.png", row_name(case, args.msaa)));
            tiler_scene::compare::write_png(&path, width, height, &pixels).map_err(|e| anyhow::anyhow!(e))?;
        }
        let mut ledger = tiler::Ledger::default();
        let mut counters = tiler::Counters::default();
        let mut frame_data_host = 0;
        for report in &last {
            ledger.merge(&report.ledger);
            counters.merge(&report.counters);
            frame_data_host = frame_data_host.max(report.frame_data.peak_host_bytes);
        }
        let mut result = figures(case, args, width, height, load, &times, work, &ledger, &counters);
        result.frame_data_peak_host_bytes = frame_data_host;
        results.push(result);
    }
    progress.finish_and_clear();

    let report = Report { backend: args.backend, threads, simd: simd.to_string(), tile: args.tile, results, skipped };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", table(&report));
    }
    Ok(())
}

/// The row's name: the scene, with `_msaa4` when multisampled (as llvmpipe's runs name them).
fn row_name(case: &BenchCase, msaa: u32) -> String {
    if msaa > 1 { format!("{}_msaa{msaa}", case.name) } else { case.name.clone() }
}

#[expect(
    clippy::too_many_arguments,
    reason = "one row from the nine things measured for it, each named at the one call site; a struct would only repeat the names"
)]
fn figures(
    case: &BenchCase,
    args: &BenchArgs,
    width: u32,
    height: u32,
    load: Duration,
    times: &[Duration],
    work: tiler_scene::bench::BenchWork,
    ledger: &tiler::Ledger,
    counters: &tiler::Counters,
) -> SceneResult {
    let mut ms: Vec<f64> = times.iter().map(|t| t.as_secs_f64() * 1e3).collect();
    let times_ms = ms.clone();
    ms.sort_by(f64::total_cmp);
    let median = if ms.len() % 2 == 1 { ms[ms.len() / 2] } else { (ms[ms.len() / 2 - 1] + ms[ms.len() / 2]) / 2.0 };
    let seconds = median / 1e3;
    let per_second = |units: f64| units / seconds;
    SceneResult {
        scene: row_name(case, args.msaa),
        width,
        height,
        msaa: args.msaa,
        frames: args.frames,
        warmup: args.warmup,
        load_ms: load.as_secs_f64() * 1e3,
        median_ms: median,
        min_ms: ms[0],
        fps: per_second(1.0),
        mpix_per_s: per_second(width as f64 * height as f64 / 1e6),
        triangles: work.triangles,
        mtris_per_s: (work.triangles > 0).then(|| per_second(work.triangles as f64 / 1e6)),
        mfrag_shaded_per_s: work.fragments.map(|f| per_second(f as f64 / 1e6)),
        external_bytes: ledger.total(),
        texture_fetch_bytes: ledger.get(tiler::Category::TextureFetch),
        fragments_shaded: counters.fragments_shaded,
        primitives: counters.primitives,
        frame_data_bytes_per_primitive: if args.backend.is_tiler() && counters.primitives > 0 {
            ledger.get(tiler::Category::FrameDataWrite) as f64 / counters.primitives as f64
        } else {
            0.0
        },
        frame_data_peak_host_bytes: 0,
        times_ms,
    }
}

fn table(report: &Report) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "backend {}, {} threads, {}×{} tiles, {} pixel pipeline",
        report.backend, report.threads, report.tile, report.tile, report.simd
    );
    let _ = writeln!(
        out,
        "{:<14} {:>11} {:>7} {:>11} {:>9} {:>9} {:>10} {:>10} {:>11} {:>9} {:>9}",
        "scene",
        "size",
        "frames",
        "median ms",
        "min ms",
        "frames/s",
        "Mpixels/s",
        "Mtris/s",
        "ext MB/frame",
        "FD B/prim",
        "load ms"
    );
    for r in &report.results {
        let _ = writeln!(
            out,
            "{:<14} {:>11} {:>7} {:>11.2} {:>9.2} {:>9.2} {:>10.1} {:>10} {:>11.2} {:>9.1} {:>9.0}",
            r.scene,
            format!("{}x{}", r.width, r.height),
            r.frames,
            r.median_ms,
            r.min_ms,
            r.fps,
            r.mpix_per_s,
            r.mtris_per_s.map(|m| format!("{m:.2}")).unwrap_or_else(|| "-".into()),
            r.external_bytes as f64 / 1e6,
            r.frame_data_bytes_per_primitive,
            r.load_ms
        );
    }
    for s in &report.skipped {
        let _ = writeln!(out, "skipped {s}");
    }
    out
}
