//! The advisor over a frame given as render passes (glTF and built-in scenes, the Rust API):
//! each pass and what the core reported for it become the records a GL run's passes are, so
//! the same rules, one function each, judge every frame source. What only a GL driver knows
//! (clears drawn as quads, rebinds, flushes, copies, stalls) does not arise here.

use tiler::{DevicePreset, Format, ImageDesc, ImageId, LoadOp, PassReport, Rect, RenderPass, StoreOp};

use super::Finding;
use crate::call::TextureFormat;
use crate::context::ContextConfig;
use crate::report::{
    AttachmentRecord, DrawKind, DrawRecord, EndCause, FrameRecord, LoadKind, PassCost, PassRecord, Role, Slot,
    StartCause, StoreKind,
};

/// The findings of one frame of render passes on `preset`: `passes[i]` rendered as
/// `reports[i]`, its images described by `image`.
///
/// A pass's "framebuffer" is its first attachment's image, so passes drawing into the same
/// images compare as a GL run's passes on one framebuffer do.
pub fn advise_passes(
    preset: &DevicePreset,
    passes: &[RenderPass],
    reports: &[PassReport],
    image: &dyn Fn(ImageId) -> Option<ImageDesc>,
) -> Vec<Finding> {
    let device = &preset.device;
    let first = reports.first();
    let config = ContextConfig::new(first.map_or(1, |r| r.width), first.map_or(1, |r| r.height)).on_device(device);
    // Framebuffers numbered from 1 by their first attachment, in order of first use.
    let mut targets: Vec<ImageId> = Vec::new();
    let mut records = Vec::with_capacity(passes.len());
    for (index, (pass, report)) in passes.iter().zip(reports).enumerate() {
        let target = pass.desc.color.first().map(|c| c.image).or(pass.desc.depth_stencil.map(|d| d.image));
        let framebuffer = match target {
            Some(id) => match targets.iter().position(|t| *t == id) {
                Some(p) => p as u32 + 1,
                None => {
                    targets.push(id);
                    targets.len() as u32
                }
            },
            None => 0,
        };
        records.push(record(index, framebuffer, pass, report, image));
    }
    let frame = FrameRecord { passes: records, ..FrameRecord::default() };
    super::advise(&config, std::slice::from_ref(&frame))
}

/// A GL format of the same storage, for the records' `gl_format` (only named in messages).
fn gl_format(format: Format) -> TextureFormat {
    const ALL: [TextureFormat; 10] = [
        TextureFormat::Rgba8,
        TextureFormat::Srgb8Alpha8,
        TextureFormat::Rgb565,
        TextureFormat::Rgba16f,
        TextureFormat::Rgba32f,
        TextureFormat::R32f,
        TextureFormat::Depth16,
        TextureFormat::Depth24Stencil8,
        TextureFormat::Depth32f,
        TextureFormat::Stencil8,
    ];
    ALL.into_iter().find(|f| f.format() == format).unwrap_or(TextureFormat::Rgba8)
}

fn load_kind<T>(op: &LoadOp<T>) -> (LoadKind, &'static str) {
    match op {
        LoadOp::Load => (LoadKind::Load, "LoadOp::Load"),
        LoadOp::Clear(_) => (LoadKind::Clear, "LoadOp::Clear"),
        LoadOp::DontCare => (LoadKind::DontCare, "LoadOp::DontCare"),
    }
}

fn store_kind(op: StoreOp) -> (StoreKind, &'static str) {
    match op {
        StoreOp::Store => (StoreKind::Store, "StoreOp::Store"),
        StoreOp::DontCare => (StoreKind::DontCare, "StoreOp::DontCare"),
    }
}

/// The record of pass `index`, as a GL run would have it.
fn record(
    index: usize,
    framebuffer: u32,
    pass: &RenderPass,
    report: &PassReport,
    image: &dyn Fn(ImageId) -> Option<ImageDesc>,
) -> PassRecord {
    let desc = &pass.desc;
    let area = match desc.render_area {
        Some(r) => r.area(),
        None => report.width as u64 * report.height as u64,
    };
    let samples = report.samples;
    let mut attachments = Vec::new();
    let mut aspect =
        |slot: Slot, id: ImageId, load: (LoadKind, &str), store: (StoreKind, &str), resolve: Option<ImageId>| {
            let Some(d) = image(id) else { return };
            let aspect_bytes = match slot {
                Slot::Color(_) => d.format.bytes_per_sample(),
                Slot::Depth => d.format.depth_aspect_bytes(),
                Slot::Stencil => d.format.stencil_aspect_bytes(),
            } as u64;
            let bytes = area * samples as u64 * aspect_bytes;
            let resolve_bytes = match resolve.and_then(image) {
                Some(r) => area * r.format.bytes_per_sample() as u64,
                None => 0,
            };
            attachments.push(AttachmentRecord {
                slot,
                image: id,
                format: d.format,
                gl_format: gl_format(d.format),
                samples,
                role: Role::Attached,
                load: load.0,
                load_reason: format!("the pass says {}", load.1),
                store: store.0,
                store_reason: format!("the pass says {}", store.1),
                load_bytes: if load.0 == LoadKind::Load { bytes } else { 0 },
                store_bytes: if store.0 == StoreKind::Store { bytes } else { 0 },
                resolve,
                resolve_bytes,
            });
        };
    for (i, c) in desc.color.iter().enumerate() {
        aspect(Slot::Color(i as u8), c.image, load_kind(&c.load), store_kind(c.store), c.resolve);
    }
    if let Some(ds) = &desc.depth_stencil {
        let format = image(ds.image).map(|d| d.format);
        if format.is_some_and(|f| f.depth_aspect_bytes() > 0) {
            aspect(Slot::Depth, ds.image, load_kind(&ds.depth_load), store_kind(ds.depth_store), None);
        }
        if format.is_some_and(|f| f.stencil_aspect_bytes() > 0) {
            aspect(Slot::Stencil, ds.image, load_kind(&ds.stencil_load), store_kind(ds.stencil_store), None);
        }
    }
    let full = desc.render_area.unwrap_or(Rect::new(0, 0, report.width, report.height));
    let draws = pass
        .draws
        .iter()
        .zip(&report.draws)
        .enumerate()
        .map(|(i, (draw, stats))| {
            let p = draw.pipeline.desc();
            DrawRecord {
                call: crate::report::CallRef::new(0, i as u32),
                kind: DrawKind::Draw,
                program: None,
                clip_rect: full,
                blend: p.color_targets.iter().any(|t| t.blend.is_some()),
                depth_test: p.depth_stencil.depth_test,
                depth_write: p.depth_stencil.depth_write,
                discards: draw.pipeline.properties().discards,
                texture_bytes: 0,
                sampled: None,
                stats: *stats,
                partial_clear: None,
            }
        })
        .collect();
    PassRecord {
        index: index as u32,
        frame: 0,
        framebuffer,
        copy_texture: None,
        window_preserved: false,
        width: report.width,
        height: report.height,
        samples,
        render_area: desc.render_area,
        start: StartCause::BeginPass,
        started_at: Default::default(),
        end: EndCause::EndPass,
        ended_at: Default::default(),
        attachments,
        subpasses: Vec::new(),
        dependencies: Vec::new(),
        draw_subpasses: Vec::new(),
        draws,
        reads: Vec::new(),
        dropped: Vec::new(),
        cost: PassCost::from(report),
        extra: Default::default(),
        core: None,
    }
}
