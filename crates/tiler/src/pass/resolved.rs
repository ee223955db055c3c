//! Render-pass validation at the front door: a pass's attachments, subpasses and draws checked
//! against the device's images, into a [`ResolvedPass`] the backends take as given.

use crate::api::error::{Error, Result};
use crate::api::image::Image;
use crate::api::pipeline::MAX_COLOR_ATTACHMENTS;
use crate::api::render_pass::{AttachmentOps, AttachmentRef, LoadOp, MAX_INPUT_ATTACHMENTS, ResolvedSubpass, StoreOp};
use crate::geometry::PassFrame;
use crate::pass::RenderPass;
use crate::raster::PixelRect;

/// A validated attachment.
#[derive(Clone, Copy, Debug)]
pub struct ResolvedAttachment {
    /// Index of the image on the device.
    pub image: usize,
    pub format: crate::Format,
    pub transient: bool,
    pub ops: AttachmentOps,
}

/// A resolve at the end of the pass: colour attachment `color` averaged into `image`.
#[derive(Clone, Copy, Debug)]
pub struct ResolveTarget {
    pub color: usize,
    /// Index of the single-sample image on the device.
    pub image: usize,
}

/// A validated render pass: colour attachments first, then the depth-stencil attachment.
#[derive(Clone, Debug)]
pub struct ResolvedPass {
    pub width: u32,
    pub height: u32,
    pub samples: u32,
    pub render_area: PixelRect,
    pub attachments: Vec<ResolvedAttachment>,
    pub resolves: Vec<ResolveTarget>,
    pub color_count: usize,
    pub has_depth_stencil: bool,
    pub subpasses: Vec<ResolvedSubpass>,
}

impl ResolvedPass {
    /// What the geometry phase needs of the pass around its draws.
    pub(crate) fn frame<'a>(&self, buffers: &'a [Vec<u8>]) -> PassFrame<'a> {
        let depth_format = self.has_depth_stencil.then(|| self.attachments[self.color_count].format);
        PassFrame { width: self.width, height: self.height, render_area: self.render_area, buffers, depth_format }
    }

    /// The render area as a [`Rect`](crate::Rect), `None` when it is the whole framebuffer.
    pub fn render_area_rect(&self) -> Option<crate::Rect> {
        let a = self.render_area;
        let whole = a == PixelRect::new(0, 0, self.width as i32, self.height as i32);
        (!whole).then(|| crate::Rect::new(a.x0 as u32, a.y0 as u32, a.width() as u32, a.height() as u32))
    }

    /// Tile-buffer bytes per pixel: every attachment, every sample.
    pub fn tile_bytes_per_pixel(&self) -> u64 {
        self.attachments.iter().map(|a| a.format.bytes_per_sample() as u64 * self.samples as u64).sum()
    }

    /// The device images the pass touches: its attachments, then its resolve targets.
    pub fn memory_images(&self) -> Vec<usize> {
        self.attachments.iter().map(|a| a.image).chain(self.resolves.iter().map(|r| r.image)).collect()
    }
}

impl ResolvedPass {
    /// Checks a pass's attachments against the images and each other.
    ///
    /// # Errors
    /// Unknown or repeated images, wrong formats for the slot, mismatched sizes or sample
    /// counts, a render area outside the framebuffer, transient images loaded or stored,
    /// non-finite clear values, or a pipeline writing more colour attachments than exist.
    pub fn new(pass: &RenderPass, images: &[Image]) -> Result<ResolvedPass> {
        let desc = &pass.desc;
        if desc.color.len() > MAX_COLOR_ATTACHMENTS {
            return Err(Error::invalid(
                "render pass",
                format!("{} colour attachments, at most {MAX_COLOR_ATTACHMENTS}", desc.color.len()),
            ));
        }
        if desc.color.is_empty() && desc.depth_stencil.is_none() {
            return Err(Error::invalid("render pass", "it has no attachments"));
        }
        let mut attachments = Vec::new();
        let mut first: Option<(String, u32, u32, u32)> = None;
        let mut check = |what: String,
                         id: crate::ImageId,
                         ops: AttachmentOps,
                         attachments: &mut Vec<ResolvedAttachment>| {
            let Some(image) = images.get(id.0 as usize) else {
                return Err(Error::invalid(what, format!("{id} does not exist")));
            };
            if attachments.iter().any(|a: &ResolvedAttachment| a.image == id.0 as usize) {
                return Err(Error::invalid(what, format!("{id} is already attached to this pass")));
            }
            let d = image.desc;
            match ops {
                AttachmentOps::Color { load, .. } => {
                    if !d.format.is_color() {
                        return Err(Error::invalid(what, format!("{id} has format {}, not a colour format", d.format)));
                    }
                    // An integer format's clear value is its integers' bits (`IntFormat`), any
                    // pattern.
                    if let LoadOp::Clear(c) = load
                        && !d.format.is_integer()
                        && c.iter().any(|v| !v.is_finite())
                    {
                        return Err(Error::invalid(what, format!("clear colour {c:?} is not finite")));
                    }
                }
                AttachmentOps::DepthStencil { depth_load, .. } => {
                    if !d.format.has_depth() {
                        return Err(Error::invalid(
                            what,
                            format!(
                                "{id} has format {}, which has no depth: a depth attachment needs a depth format",
                                d.format
                            ),
                        ));
                    }
                    if let LoadOp::Clear(z) = depth_load
                        && !(0.0..=1.0).contains(&z)
                    {
                        return Err(Error::invalid(what, format!("clear depth {z} is outside [0, 1]")));
                    }
                }
            }
            if d.transient {
                let (loads, stores) = match ops {
                    AttachmentOps::Color { load, store } => (load.is_load(), store == StoreOp::Store),
                    AttachmentOps::DepthStencil { depth_load, depth_store, stencil_load, stencil_store } => (
                        depth_load.is_load() || stencil_load.is_load(),
                        depth_store == StoreOp::Store || stencil_store == StoreOp::Store,
                    ),
                };
                if loads || stores {
                    return Err(Error::invalid(
                        what,
                        format!(
                            "{id} is transient (it has no memory), so it cannot be {}: use Clear or DontCare to load and DontCare to store",
                            if loads { "loaded" } else { "stored" }
                        ),
                    ));
                }
            }
            match &first {
                None => first = Some((what.clone(), d.width, d.height, d.samples)),
                Some((first_what, w, h, s)) => {
                    if (d.width, d.height) != (*w, *h) {
                        return Err(Error::invalid(
                            what,
                            format!(
                                "{id} is {}×{} but {first_what} is {w}×{h}: attachments must be the same size",
                                d.width, d.height
                            ),
                        ));
                    }
                    if d.samples != *s {
                        return Err(Error::invalid(
                            what,
                            format!("{id} has {} samples but {first_what} has {s}", d.samples),
                        ));
                    }
                }
            }
            attachments.push(ResolvedAttachment {
                image: id.0 as usize,
                format: d.format,
                transient: d.transient,
                ops,
            });
            Ok(())
        };
        for (i, c) in desc.color.iter().enumerate() {
            check(
                format!("colour attachment {i}"),
                c.image,
                AttachmentOps::Color { load: c.load, store: c.store },
                &mut attachments,
            )?;
        }
        if let Some(ds) = &desc.depth_stencil {
            let ops = AttachmentOps::DepthStencil {
                depth_load: ds.depth_load,
                depth_store: ds.depth_store,
                stencil_load: ds.stencil_load,
                stencil_store: ds.stencil_store,
            };
            check("depth-stencil attachment".to_string(), ds.image, ops, &mut attachments)?;
        }
        let (_, width, height, samples) = first.expect("at least one attachment");
        let mut resolves = Vec::new();
        for (i, c) in desc.color.iter().enumerate() {
            let Some(id) = c.resolve else { continue };
            let what = format!("colour attachment {i}'s resolve target");
            let Some(image) = images.get(id.0 as usize) else {
                return Err(Error::invalid(what, format!("{id} does not exist")));
            };
            let d = image.desc;
            let used = attachments.iter().map(|a| a.image).chain(resolves.iter().map(|r: &ResolveTarget| r.image));
            if used.clone().any(|u| u == id.0 as usize) {
                return Err(Error::invalid(what, format!("{id} is already used by this pass")));
            }
            if samples == 1 {
                return Err(Error::invalid(what, "only a multisampled attachment can be resolved"));
            }
            if d.samples != 1 || d.transient {
                return Err(Error::invalid(what, format!("{id} must be a single-sample image with memory")));
            }
            if (d.width, d.height) != (width, height) || d.format != attachments[i].format {
                return Err(Error::invalid(
                    what,
                    format!(
                        "{id} is {}×{} {}, the attachment is {width}×{height} {}: they must match",
                        d.width, d.height, d.format, attachments[i].format
                    ),
                ));
            }
            resolves.push(ResolveTarget { color: i, image: id.0 as usize });
        }
        let full = PixelRect::new(0, 0, width as i32, height as i32);
        let render_area = match desc.render_area {
            None => full,
            Some(r) => {
                if r.width == 0 || r.height == 0 || r.right() > width as u64 || r.bottom() > height as u64 {
                    return Err(Error::invalid(
                        "render area",
                        format!("{r:?} must be non-empty and inside the {width}×{height} framebuffer"),
                    ));
                }
                PixelRect::from_rect(r)
            }
        };
        let render_area = scissor_render_area(pass, render_area, &attachments, &resolves);
        let color_count = desc.color.len();
        let depth_index = desc.depth_stencil.is_some().then_some(color_count);
        let subpasses = resolve_subpasses(pass, &attachments, depth_index, &mut |what, id| {
            // A subpass resolve target: checked like a pass-level one.
            let Some(image) = images.get(id.0 as usize) else {
                return Err(Error::invalid(what, format!("{id} does not exist")));
            };
            Ok(image.desc)
        })?;
        for (s, subpass) in subpasses.iter().enumerate() {
            for (output, target) in subpass.resolves.iter().enumerate() {
                let Some(id) = target else { continue };
                let color = subpass.color[output];
                let what = format!("subpass {s}: resolve target of colour output {output}");
                let d = images[id.0 as usize].desc;
                let used = attachments.iter().map(|a| a.image).chain(resolves.iter().map(|r: &ResolveTarget| r.image));
                if used.clone().any(|u| u == id.0 as usize) {
                    return Err(Error::invalid(what, format!("{id} is already used by this pass")));
                }
                if samples == 1 || d.samples != 1 || d.transient {
                    return Err(Error::invalid(
                        what,
                        format!(
                            "resolving needs a multisampled attachment and a single-sample image with memory ({id})"
                        ),
                    ));
                }
                if (d.width, d.height) != (width, height) || d.format != attachments[color].format {
                    return Err(Error::invalid(what, format!("{id} must match the attachment's size and format")));
                }
                if subpasses[s + 1..].iter().any(|later| later.color.contains(&color)) {
                    return Err(Error::invalid(
                        what,
                        format!(
                            "colour attachment {color} is written again by a later subpass, so it cannot be resolved here"
                        ),
                    ));
                }
                resolves.push(ResolveTarget { color, image: id.0 as usize });
            }
        }
        for (i, draw) in pass.draws.iter().enumerate() {
            let subpass = &subpasses[pass.subpass_of(i)];
            let targets = draw.pipeline.desc().color_targets.len();
            if targets > subpass.color.len() {
                return Err(Error::draw(
                    i,
                    format!(
                        "pipeline '{}' writes {targets} colour outputs but subpass {} has {}",
                        draw.pipeline.desc().label,
                        pass.subpass_of(i),
                        subpass.color.len()
                    ),
                ));
            }
        }
        Ok(ResolvedPass {
            width,
            height,
            samples,
            render_area,
            color_count,
            has_depth_stencil: desc.depth_stencil.is_some(),
            attachments,
            resolves,
            subpasses,
        })
    }
}

/// The render area a pass needs when every draw lies inside a scissor box: the bounding box
/// of the draws' scissors (within `area`), so the tiles outside it are neither loaded nor
/// stored (seed 001 "How to optimize render passes": a scissor box limits a pass to a
/// sub-region, as `QCOM_tiled_rendering` does). Otherwise `area`.
///
/// Narrowing keeps the picture only if nothing outside the box would have changed: every
/// attachment that is stored must be loaded (a `Clear` or `DontCare` load would have
/// replaced the outside with the clear value or zero), and nothing is resolved (a resolve
/// writes the whole area). Attachments not stored may start any way: their outside is never
/// seen. A pass without draws keeps its area (its loads and stores are its whole work).
fn scissor_render_area(
    pass: &RenderPass,
    area: PixelRect,
    attachments: &[ResolvedAttachment],
    resolves: &[ResolveTarget],
) -> PixelRect {
    let stored_without_load = attachments.iter().any(|a| match a.ops {
        AttachmentOps::Color { load, store } => store == StoreOp::Store && !load.is_load(),
        AttachmentOps::DepthStencil { depth_load, depth_store, stencil_load, stencil_store } => {
            (depth_store == StoreOp::Store && !depth_load.is_load())
                || (stencil_store == StoreOp::Store && !stencil_load.is_load())
        }
    });
    if pass.draws.is_empty() || stored_without_load || !resolves.is_empty() {
        return area;
    }
    // The bounding box of the scissors (an empty one draws nothing and adds nothing).
    let mut bounds: Option<PixelRect> = None;
    for draw in &pass.draws {
        let Some(scissor) = &draw.scissor else { return area };
        let r = crate::geometry::scissor_rect(scissor);
        if r.is_empty() {
            continue;
        }
        bounds = Some(match bounds {
            None => r,
            Some(b) => PixelRect::new(b.x0.min(r.x0), b.y0.min(r.y0), b.x1.max(r.x1), b.y1.max(r.y1)),
        });
    }
    let Some(bounds) = bounds else { return area };
    let narrowed = area.intersect(&bounds);
    if narrowed.is_empty() { area } else { narrowed }
}

/// Checks the pass's subpasses (or makes the implicit one) and its dependencies.
fn resolve_subpasses(
    pass: &RenderPass,
    attachments: &[ResolvedAttachment],
    depth_index: Option<usize>,
    image_desc: &mut dyn FnMut(String, crate::ImageId) -> Result<crate::ImageDesc>,
) -> Result<Vec<ResolvedSubpass>> {
    let color_count = pass.desc.color.len();
    if pass.subpasses.is_empty() {
        if !pass.subpass_starts.is_empty() || !pass.dependencies.is_empty() {
            return Err(Error::invalid("render pass", "next_subpass or dependencies without explicit subpasses"));
        }
        return Ok(vec![ResolvedSubpass {
            color: (0..color_count).collect(),
            depth_stencil: depth_index,
            inputs: Vec::new(),
            resolves: Vec::new(),
            split_before: false,
        }]);
    }
    if pass.subpass_starts.len() >= pass.subpasses.len() {
        return Err(Error::invalid(
            "render pass",
            format!(
                "next_subpass was called {} times but the pass has {} subpasses",
                pass.subpass_starts.len(),
                pass.subpasses.len()
            ),
        ));
    }
    let mut out: Vec<ResolvedSubpass> = Vec::new();
    for (s, subpass) in pass.subpasses.iter().enumerate() {
        let what = || format!("subpass {s}");
        let mut color = Vec::new();
        for &c in &subpass.color {
            if c as usize >= color_count {
                return Err(Error::invalid(
                    what(),
                    format!("colour attachment {c} does not exist (the pass has {color_count})"),
                ));
            }
            if color.contains(&(c as usize)) {
                return Err(Error::invalid(what(), format!("colour attachment {c} is named twice")));
            }
            color.push(c as usize);
        }
        if color.len() > crate::MAX_COLOR_ATTACHMENTS {
            return Err(Error::invalid(
                what(),
                format!("{} colour outputs, at most {}", color.len(), crate::MAX_COLOR_ATTACHMENTS),
            ));
        }
        let depth_stencil = match (subpass.depth_stencil, depth_index) {
            (true, None) => {
                return Err(Error::invalid(what(), "uses the depth-stencil attachment, but the pass has none"));
            }
            (true, Some(d)) => Some(d),
            (false, _) => None,
        };
        if subpass.input.len() > MAX_INPUT_ATTACHMENTS {
            return Err(Error::invalid(
                what(),
                format!("{} input attachments, at most {MAX_INPUT_ATTACHMENTS}", subpass.input.len()),
            ));
        }
        let mut inputs = Vec::new();
        for (i, input) in subpass.input.iter().enumerate() {
            let index = match *input {
                AttachmentRef::Color(c) if (c as usize) < color_count => c as usize,
                AttachmentRef::Color(c) => {
                    return Err(Error::invalid(
                        what(),
                        format!("input {i} names colour attachment {c}, which does not exist"),
                    ));
                }
                AttachmentRef::DepthStencil => depth_index.ok_or_else(|| {
                    Error::invalid(
                        what(),
                        format!("input {i} names the depth-stencil attachment, but the pass has none"),
                    )
                })?,
            };
            if color.contains(&index) || depth_stencil == Some(index) {
                return Err(Error::invalid(
                    what(),
                    format!(
                        "input {i} is also written by this subpass; to read what this subpass wrote, use pixel-local reads (Fragments::local)"
                    ),
                ));
            }
            let written_before = out.iter().any(|p| p.color.contains(&index) || p.depth_stencil == Some(index));
            let loaded = match attachments[index].ops {
                AttachmentOps::Color { load, .. } => !matches!(load, LoadOp::DontCare),
                AttachmentOps::DepthStencil { depth_load, .. } => !matches!(depth_load, LoadOp::DontCare),
            };
            if !written_before && !loaded {
                return Err(Error::invalid(
                    what(),
                    format!(
                        "input {i} ({input:?}) is read without being written by an earlier subpass, and its load op is DontCare"
                    ),
                ));
            }
            inputs.push(index);
        }
        if subpass.resolve.len() > color.len() {
            return Err(Error::invalid(
                what(),
                format!("{} resolve targets for {} colour outputs", subpass.resolve.len(), color.len()),
            ));
        }
        for (o, target) in subpass.resolve.iter().enumerate() {
            if let Some(id) = target {
                image_desc(format!("subpass {s}: resolve target of colour output {o}"), *id)?;
            }
        }
        out.push(ResolvedSubpass {
            color,
            depth_stencil,
            inputs,
            resolves: subpass.resolve.clone(),
            split_before: false,
        });
    }
    for (d, dependency) in pass.dependencies.iter().enumerate() {
        if dependency.src >= dependency.dst || dependency.dst as usize >= out.len() {
            return Err(Error::invalid(
                format!("dependency {d}"),
                format!(
                    "subpass {} → {} must go from an earlier subpass to a later one of the {}",
                    dependency.src,
                    dependency.dst,
                    out.len()
                ),
            ));
        }
        if !dependency.by_region {
            out[dependency.dst as usize].split_before = true;
        }
    }
    Ok(out)
}

/// Mutable references to the images a pass touches, in the order of
/// [`ResolvedPass::memory_images`]: attachments, then resolve targets.
pub fn attachment_images<'a>(images: &'a mut [Image], pass: &ResolvedPass) -> Vec<&'a mut Image> {
    let wanted = pass.memory_images();
    let mut out: Vec<Option<&'a mut Image>> = wanted.iter().map(|_| None).collect();
    for (index, image) in images.iter_mut().enumerate() {
        if let Some(slot) = wanted.iter().position(|w| *w == index) {
            out[slot] = Some(image);
        }
    }
    out.into_iter().map(|i| i.expect("validated attachment")).collect()
}
