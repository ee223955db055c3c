//! Renders frames of one scene on one backend, for profilers (callgrind, perf):
//!
//! ```text
//! cargo run --release -p tiler-scene --example frame -- SCENE [tbr|tbdr|imr] [FRAMES] [WxH] [MSAA]
//! ```
//!
//! SCENE is `builtin`, or a benchmark scene of SCENES.md: `clear`, `helmet`, `atrium`,
//! `overdraw`, `overdraw_f2b`, `tris` or `tris:N` (N triangles). Models come from
//! `$TILER_ASSETS`, else `../shared/assets`.

use std::path::PathBuf;
use std::time::Instant;

use tiler::{Backend, Device, DeviceConfig};
use tiler_scene::bench::{self, BenchScene};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let name = args.first().map(String::as_str).unwrap_or("builtin");
    let backend: Backend = args.get(1).map(|s| s.parse()).transpose()?.unwrap_or(Backend::Tbr);
    let frames: usize = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or(1);
    let (width, height) = match args.get(3).and_then(|s| s.split_once('x')) {
        Some((w, h)) => (w.parse()?, h.parse()?),
        None => (1920, 1080),
    };
    let samples: u32 = args.get(4).map(|s| s.parse()).transpose()?.unwrap_or(1);
    let assets =
        std::env::var_os("TILER_ASSETS").map(PathBuf::from).unwrap_or_else(|| PathBuf::from("../shared/assets"));
    let threads = std::env::var("TILER_THREADS").ok().map(|t| t.parse()).transpose()?.unwrap_or(0);
    let simd = match std::env::var("TILER_SIMD").as_deref() {
        Ok("baseline") => Some(tiler::SimdLevel::Baseline),
        Ok("avx2") => Some(tiler::SimdLevel::Avx2),
        _ => None,
    };
    let mut device = Device::new(DeviceConfig { backend, threads, simd, ..DeviceConfig::default() })?;
    let scene = if name == "builtin" {
        tiler_scene::builtin::build(&mut device, width, height, samples)?
    } else if let Some(count) = name.strip_prefix("tris:") {
        bench::build(&mut device, &BenchScene::Tris { count: count.parse()?, seed: 1 }, width, height, samples)?.0
    } else {
        let case =
            bench::standard_cases(&assets).into_iter().find(|c| c.name == name).ok_or(format!("no scene '{name}'"))?;
        bench::build(&mut device, &case.scene, width, height, samples)?.0
    };
    let started = Instant::now();
    for _ in 0..frames {
        scene.render(&mut device, backend)?;
    }
    let per_frame = started.elapsed().as_secs_f64() * 1e3 / frames.max(1) as f64;
    let pixels = device.read_rgba8(scene.color)?;
    let checksum: u64 = pixels.iter().map(|&b| b as u64).sum();
    println!("{name}: {frames} frames on {backend}, {per_frame:.2} ms per frame, checksum {checksum}");
    Ok(())
}
