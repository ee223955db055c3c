//! Renders frames of a built-in scene on one backend, for profilers (callgrind, perf):
//! `cargo run --release -p tiler-scene --example frame -- [tbr|tbdr|imr] [frames] [WxH] [msaa]`.

use tiler::{Backend, Device, DeviceConfig};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let backend: Backend = args.first().map(|s| s.parse()).transpose()?.unwrap_or(Backend::Tbr);
    let frames: usize = args.get(1).map(|s| s.parse()).transpose()?.unwrap_or(1);
    let (width, height) = match args.get(2).and_then(|s| s.split_once('x')) {
        Some((w, h)) => (w.parse()?, h.parse()?),
        None => (1280, 720),
    };
    let samples: u32 = args.get(3).map(|s| s.parse()).transpose()?.unwrap_or(1);
    let mut device = Device::new(DeviceConfig { backend, ..DeviceConfig::default() })?;
    let scene = tiler_scene::builtin::build(&mut device, width, height, samples)?;
    for _ in 0..frames {
        scene.render(&mut device, backend)?;
    }
    let pixels = device.read_rgba8(scene.color)?;
    println!("{} frames, checksum {}", frames, pixels.iter().map(|&b| b as u64).sum::<u64>());
    Ok(())
}
