//! Deferred shading of many lights in one render pass (G-buffer subpass → lighting subpass,
//! the G-buffer transient) against the same frame as two render passes through memory.
//!
//! `cargo run --release -p tiler-scene --example deferred` writes `deferred.png` and prints
//! what each way costs in external memory on a tiler and in immediate mode.

use tiler::{Backend, Category, Device, DeviceConfig};
use tiler_scene::deferred::{self, Variant};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (width, height) = (1280, 720);
    let mut pictures = Vec::new();
    println!("{:<26}{:>9}{:>14}{:>14}{:>14}{:>12}", "", "backend", "tile store", "tile load", "total", "saved mem");
    for variant in [Variant::Subpasses, Variant::Passes] {
        for backend in [Backend::Tbr, Backend::Imr] {
            let mut device = Device::new(DeviceConfig { backend, ..DeviceConfig::default() })?;
            let scene = deferred::build(&mut device, width, height, variant)?;
            let reports = scene.render(&mut device, backend)?;
            let total = |c: Category| reports.iter().map(|r| r.ledger.get(c)).sum::<u64>();
            let all: u64 = reports.iter().map(|r| r.ledger.total()).sum();
            let saved: u64 = reports.iter().map(|r| r.transient_bytes_saved).sum();
            println!(
                "{:<26}{:>9}{:>11.2} MB{:>11.2} MB{:>11.2} MB{:>9.2} MB",
                scene.name,
                backend.name(),
                total(Category::TileStore) as f64 / 1e6,
                total(Category::TileLoad) as f64 / 1e6,
                all as f64 / 1e6,
                saved as f64 / 1e6
            );
            pictures.push(device.read_rgba8(scene.color)?);
        }
    }
    assert!(pictures.windows(2).all(|p| p[0] == p[1]), "every variant and backend gives the same picture");
    image::save_buffer("deferred.png", &pictures[0], width, height, image::ExtendedColorType::Rgba8)?;
    println!("same picture every way → deferred.png");
    Ok(())
}
