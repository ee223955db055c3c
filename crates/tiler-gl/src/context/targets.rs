//! Framebuffer completeness and what a framebuffer's attachments are for tiler: colour
//! images, and a depth-stencil image with the role of each of its aspects.
//!
//! # Separate depth and stencil
//!
//! tiler's only stencil format is packed with depth (`D24UnormS8Uint`), so GL's separate
//! depth and stencil renderbuffers map as follows: a framebuffer whose depth and stencil
//! attachments are *different* images is `GL_FRAMEBUFFER_UNSUPPORTED` (which GL ES allows a
//! driver to answer, and which many tilers do: use `depth24_stencil8`). A `depth24` image is
//! packed with a padding stencil byte and a `stencil8` image with padding depth bytes; padding
//! is never loaded or stored. A `depth24_stencil8` image attached at only one of the depth and
//! stencil points keeps its other half, which must then be loaded and stored with it (seed
//! 001) — the advisor warns about it.

use tiler::ImageId;

use super::{AttachmentRef, Context, Fallible};
use crate::call::TextureFormat;
use crate::report::Role;

/// The depth-stencil image of a framebuffer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct DepthStencilTarget {
    pub image: ImageId,
    pub gl_format: TextureFormat,
    /// `None` when tiler's format has no depth aspect.
    pub depth: Option<Role>,
    pub stencil: Option<Role>,
}

/// A colour attachment: the image rendered, and where it is resolved (multisampled
/// render-to-texture and multisampled windows).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ColorTarget {
    pub image: ImageId,
    pub format: TextureFormat,
    pub resolve: Option<ImageId>,
}

impl ColorTarget {
    /// What reading the attachment reads: the resolved image if there is one.
    pub fn readable(&self) -> ImageId {
        self.resolve.unwrap_or(self.image)
    }
}

/// A complete framebuffer's images.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Targets {
    pub color: Vec<ColorTarget>,
    pub depth_stencil: Option<DepthStencilTarget>,
    pub width: u32,
    pub height: u32,
    pub samples: u32,
}

impl Targets {
    /// Whether the depth aspect is attached (so GL's depth test applies).
    pub fn has_depth(&self) -> bool {
        self.depth_stencil.is_some_and(|d| d.depth == Some(Role::Attached))
    }

    pub fn has_stencil(&self) -> bool {
        self.depth_stencil.is_some_and(|d| d.stencil == Some(Role::Attached))
    }

    /// Every image the framebuffer renders or resolves into.
    pub fn images(&self) -> impl Iterator<Item = ImageId> + '_ {
        self.color.iter().flat_map(|c| [Some(c.image), c.resolve]).flatten().chain(self.depth_stencil.map(|d| d.image))
    }
}

impl Context {
    fn attachment_image(&self, r: AttachmentRef) -> Fallible<(ImageId, TextureFormat)> {
        let image = match r {
            AttachmentRef::Texture(id) => self.texture(id)?.image,
            AttachmentRef::Renderbuffer(id) => {
                self.renderbuffers.get(&id).ok_or_else(|| format!("renderbuffer {id} does not exist"))?.image
            }
            AttachmentRef::Surface(image) => image,
            AttachmentRef::MultisampleTexture { samples, .. } | AttachmentRef::SurfaceMultisample { samples, .. } => {
                samples
            }
        };
        let info = self.images.get(&image).ok_or("an attachment's storage was released")?;
        Ok((image, info.gl_format))
    }

    /// Whether the bound draw framebuffer has an sRGB colour attachment: draws into it encode
    /// to sRGB (what `GL_FRAMEBUFFER_SRGB_EXT` switches off, which tiler does not model).
    pub fn draws_into_srgb(&self) -> bool {
        let Some(fb) = self.framebuffers.get(&self.draw_framebuffer) else { return false };
        fb.color
            .iter()
            .flatten()
            .any(|&r| self.attachment_image(r).is_ok_and(|(_, format)| format == TextureFormat::Srgb8Alpha8))
    }

    /// The images of framebuffer `id`, if it is complete.
    ///
    /// # Errors
    /// The GL completeness status it fails, and why.
    pub(crate) fn targets(&self, id: u32) -> Fallible<Targets> {
        let fb = self.framebuffers.get(&id).ok_or_else(|| format!("framebuffer {id} does not exist"))?;
        let incomplete = |why: String| Err(format!("framebuffer {id} is incomplete: {why}"));
        let mut color = Vec::new();
        for (i, a) in fb.color.iter().enumerate() {
            if let Some(r) = a {
                if color.len() != i {
                    return incomplete(format!(
                        "colour attachment {i} follows an empty one; tiler needs colour attachments \
                         to start at color0 without gaps"
                    ));
                }
                let (image, format) = self.attachment_image(*r)?;
                if !format.is_color() {
                    return incomplete(format!(
                        "color{i} has format {} (GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT)",
                        format.name()
                    ));
                }
                let resolve = match *r {
                    AttachmentRef::MultisampleTexture { texture, .. } => {
                        let target = self.texture(texture)?.image;
                        let (d, t) = (self.images[&image].desc, self.images[&target].desc);
                        if (d.width, d.height) != (t.width, t.height) {
                            return incomplete(format!(
                                "texture {texture} was given new storage of another size after it was attached \
                                 multisampled: attach it again"
                            ));
                        }
                        Some(target)
                    }
                    AttachmentRef::SurfaceMultisample { resolve, .. } => Some(resolve),
                    _ => None,
                };
                color.push(ColorTarget { image, format, resolve });
            }
        }
        let depth = fb.depth.map(|r| self.attachment_image(r)).transpose()?;
        let stencil = fb.stencil.map(|r| self.attachment_image(r)).transpose()?;
        if let Some((_, f)) = depth
            && !f.has_depth()
        {
            return incomplete(format!("the depth attachment has format {} (no depth)", f.name()));
        }
        if let Some((_, f)) = stencil
            && !f.has_stencil()
        {
            return incomplete(format!("the stencil attachment has format {} (no stencil)", f.name()));
        }
        let depth_stencil = match (depth, stencil) {
            (None, None) => None,
            (Some(d), Some(s)) if d.0 != s.0 => {
                return Err(format!(
                    "framebuffer {id} is unsupported (GL_FRAMEBUFFER_UNSUPPORTED): its depth and stencil \
                     attachments are separate images; tiler packs depth and stencil in one image, so \
                     attach a depth24_stencil8 image at depth_stencil"
                ));
            }
            (d, s) => {
                let (image, gl_format) = d.or(s).expect("one of them");
                let format = gl_format.format();
                let role = |attached: bool, has: bool| {
                    if attached {
                        Role::Attached
                    } else if has {
                        Role::Preserved
                    } else {
                        Role::Padding
                    }
                };
                Some(DepthStencilTarget {
                    image,
                    gl_format,
                    depth: format.has_depth().then(|| role(d.is_some(), gl_format.has_depth())),
                    stencil: format.has_stencil().then(|| role(s.is_some(), gl_format.has_stencil())),
                })
            }
        };
        let mut size: Option<(u32, u32, u32)> = None;
        for image in color.iter().map(|c| c.image).chain(depth_stencil.map(|d| d.image)) {
            let d = self.images[&image].desc;
            match size {
                None => size = Some((d.width, d.height, d.samples)),
                Some((w, h, s)) => {
                    if (w, h) != (d.width, d.height) {
                        return incomplete(format!(
                            "its attachments have different sizes ({w}×{h} and {}×{}; \
                             GL_FRAMEBUFFER_INCOMPLETE_DIMENSIONS)",
                            d.width, d.height
                        ));
                    }
                    if s != d.samples {
                        return incomplete(format!(
                            "its attachments have different sample counts ({s} and {}; \
                             GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE)",
                            d.samples
                        ));
                    }
                }
            }
        }
        let Some((width, height, samples)) = size else {
            return incomplete("it has no attachments (GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT)".to_string());
        };
        Ok(Targets { color, depth_stencil, width, height, samples })
    }
}
