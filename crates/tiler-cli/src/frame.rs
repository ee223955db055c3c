//! Rendering one frame of a scene on one device preset, as a report column: a fresh device
//! per column, so nothing (transaction-elimination signatures, caches) carries over from
//! another device's frame.

use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use tiler::{Backend, Device, DeviceConfig, DevicePreset, FrameCost, ImageId, LoadOp, RenderPass, StoreOp};
use tiler_report::{AttachmentInfo, Column, PassInfo, Rgba8Image, SceneInfo};
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
    /// Each pass's attachments and their load and store ops, as the scene gave them.
    pub passes: Vec<PassInfo>,
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
    let passes = scene.passes.iter().map(|pass| pass_info(pass, &device)).collect();
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
        passes,
    })
}

/// A pass as the scene gave it: its attachments and their ops (the scene chose them).
fn pass_info(pass: &RenderPass, device: &Device) -> PassInfo {
    fn load<T>(op: &LoadOp<T>) -> &'static str {
        match op {
            LoadOp::Load => "load",
            LoadOp::Clear(_) => "clear",
            LoadOp::DontCare => "dont_care",
        }
    }
    fn store(op: StoreOp) -> &'static str {
        match op {
            StoreOp::Store => "store",
            StoreOp::DontCare => "dont_care",
        }
    }
    let desc = &pass.desc;
    let format =
        |id: ImageId| device.image_desc(id).map(|d| (d.format.name().to_string(), d.samples)).unwrap_or_default();
    let chosen = "the scene's render pass chose it".to_string();
    let mut attachments = Vec::new();
    for (i, c) in desc.color.iter().enumerate() {
        let (format, samples) = format(c.image);
        let resolve = if c.resolve.is_some() { "; resolved in the tile" } else { "" };
        attachments.push(AttachmentInfo {
            slot: format!("color{i}"),
            format,
            samples,
            load: load(&c.load).into(),
            load_reason: chosen.clone(),
            store: store(c.store).into(),
            store_reason: format!("{chosen}{resolve}"),
        });
    }
    if let Some(ds) = &desc.depth_stencil {
        let (format, samples) = format(ds.image);
        let aspects =
            device.image_desc(ds.image).map(|d| (d.format.has_depth(), d.format.has_stencil())).unwrap_or_default();
        let depth = ("depth", aspects.0, load(&ds.depth_load), store(ds.depth_store));
        let stencil = ("stencil", aspects.1, load(&ds.stencil_load), store(ds.stencil_store));
        for (slot, _, l, s) in [depth, stencil].into_iter().filter(|aspect| aspect.1) {
            attachments.push(AttachmentInfo {
                slot: slot.into(),
                format: format.clone(),
                samples,
                load: l.into(),
                load_reason: chosen.clone(),
                store: s.into(),
                store_reason: chosen.clone(),
            });
        }
    }
    PassInfo {
        frame: 0,
        target: desc
            .color
            .first()
            .map(|c| c.image)
            .or(desc.depth_stencil.map(|d| d.image))
            .map(|id| id.to_string())
            .unwrap_or_default(),
        began: "submitted by the scene".into(),
        ended: "the scene's next pass or the end of the frame".into(),
        attachments,
    }
}
