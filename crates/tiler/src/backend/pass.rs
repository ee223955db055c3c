//! Render-pass validation at the front door, and what the backends share: the resolved
//! attachments, and views of images cut into bands of rows.

use crate::api::error::{Error, Result};
use crate::api::image::Image;
use crate::api::pipeline::MAX_COLOR_ATTACHMENTS;
use crate::api::render_pass::{LoadOp, RenderPass, StoreOp};
use crate::raster::PixelRect;
use crate::tile::load_store::AttachmentOps;
use crate::tile::target::Surface;

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
}

impl ResolvedPass {
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
                    if let LoadOp::Clear(c) = load
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
        for (i, draw) in pass.draws.iter().enumerate() {
            let targets = draw.pipeline.desc().color_targets.len();
            if targets > desc.color.len() {
                return Err(Error::draw(
                    i,
                    format!(
                        "pipeline '{}' writes {targets} colour attachments but the pass has {}",
                        draw.pipeline.desc().label,
                        desc.color.len()
                    ),
                ));
            }
        }
        Ok(ResolvedPass {
            width,
            height,
            samples,
            render_area,
            color_count: desc.color.len(),
            has_depth_stencil: desc.depth_stencil.is_some(),
            attachments,
            resolves,
        })
    }
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

/// Cuts an image into bands of `rows` rows: for each band, one slice per sample plane.
/// A transient image (no memory) gives no bands.
pub fn image_bands(image: &mut Image, rows: usize) -> Vec<Vec<&mut [u8]>> {
    data_bands(&image.desc, &mut image.data, rows)
}

/// [`image_bands`] over an image's description and data, borrowed apart.
pub fn data_bands<'a>(desc: &crate::ImageDesc, data: &'a mut [u8], rows: usize) -> Vec<Vec<&'a mut [u8]>> {
    if data.is_empty() || desc.transient {
        return Vec::new();
    }
    let plane = desc.plane_bytes();
    let band_bytes = desc.width as usize * desc.format.bytes_per_sample() * rows;
    let mut planes: Vec<_> = data.chunks_mut(plane).map(|p| p.chunks_mut(band_bytes)).collect();
    let bands = (desc.height as usize).div_ceil(rows);
    (0..bands).map(|_| planes.iter_mut().map(|p| p.next().expect("band")).collect()).collect()
}

/// A surface over one band of an image.
pub fn band_surface<'a>(
    image_format: crate::Format,
    width: u32,
    band_y0: i32,
    slices: Vec<&'a mut [u8]>,
) -> Surface<'a> {
    Surface::new(image_format, (0, band_y0), width as usize, slices)
}
