//! Rendering one frame of a scene on one device preset, as a report column: a fresh device
//! per column, so nothing (transaction-elimination signatures, caches) carries over from
//! another device's frame.

use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use tiler::{Backend, Device, DeviceConfig, DevicePreset, FrameCost};
use tiler_report::{Column, Rgba8Image, SceneInfo};
use tiler_scene::Scene;

/// A rendered frame and what is known about its scene.
pub struct Rendered {
    pub column: Column,
    pub scene: SceneInfo,
    pub load_time: Duration,
    pub render_time: Duration,
    /// Worker threads the device used.
    pub threads: usize,
    /// The advisor's findings about the frame, priced on this device.
    pub findings: Vec<tiler_report::Finding>,
}

/// How a column's device is set up beyond its preset.
pub struct Setup {
    /// Worker threads (0 = one per core).
    pub threads: usize,
    /// The pixel pipeline's instruction set (`None`: the best this processor runs).
    pub simd: Option<tiler::SimdLevel>,
    /// Square tile size overriding the preset's.
    pub tile: Option<u32>,
    /// Record per-pixel overdraw (for heat maps).
    pub overdraw_map: bool,
}

/// The device configuration of a preset under `setup`, rendering with `backend`.
pub fn config(preset: &DevicePreset, backend: Backend, setup: &Setup) -> DeviceConfig {
    let config = DeviceConfig {
        backend,
        threads: setup.threads,
        simd: setup.simd,
        overdraw_map: setup.overdraw_map || preset.device.overdraw_map,
        ..preset.device.clone()
    };
    match setup.tile {
        Some(size) => config.with_tile_size(size),
        None => config,
    }
}

/// Builds the scene with `load` on a fresh device for `preset` and renders one frame with
/// `backend`, presenting it. The column's preset is the configuration that ran (with
/// `setup`'s overrides) but keeps the preset's own backend.
///
/// # Errors
/// An invalid configuration, a scene that cannot be built, a pass the device refuses.
pub fn render(
    label: &str,
    preset: &DevicePreset,
    backend: Backend,
    setup: &Setup,
    load: &dyn Fn(&mut Device) -> Result<Scene>,
) -> Result<Rendered> {
    let effective = config(preset, backend, setup);
    let mut device =
        Device::new(effective.clone()).with_context(|| format!("creating the device '{}' ({backend})", preset.name))?;
    let started = Instant::now();
    let scene = load(&mut device)?;
    let load_time = started.elapsed();
    let started = Instant::now();
    let passes = scene.render(&mut device, backend).with_context(|| format!("rendering on '{label}'"))?;
    let render_time = started.elapsed();
    let mut frame = FrameCost::new(passes);
    frame.present = device.present(scene.color).context("presenting the frame")?;
    let pixels = device.read_rgba8(scene.color).context("reading the picture")?;
    let as_ran = DevicePreset { device: effective.clone(), ..preset.clone() };
    let findings =
        tiler_gl::advisor::advise_passes(&as_ran, &scene.passes, &frame.passes, &|id| device.image_desc(id).ok());
    let image = Rgba8Image::new(scene.width, scene.height, pixels).map_err(anyhow::Error::msg)?;
    let info = SceneInfo {
        name: scene.name.clone(),
        width: scene.width,
        height: scene.height,
        samples: frame.passes.last().map_or(1, |p| p.samples),
        draws: scene.draws() as u64,
        triangles: scene.triangles,
    };
    // The preset as it ran (tile size overridden, overdraw map on), its own backend kept.
    let preset =
        DevicePreset { device: DeviceConfig { backend: preset.device.backend, ..effective }, ..preset.clone() };
    Ok(Rendered {
        column: Column { label: label.to_string(), preset, backend, frame, image, frames: Vec::new() },
        scene: info,
        load_time,
        render_time,
        threads: device.threads(),
        findings,
    })
}
