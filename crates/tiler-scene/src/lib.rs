//! Scenes for tiler: the built-in scene made in code, glTF 2.0 models and their shading, the
//! benchmark scenes of SCENES.md, cameras, procedural meshes, and image comparison.
//!
//! A [`Scene`] is a set of render passes recorded against a [`Device`]'s images and buffers;
//! rendering it submits them in order.

pub mod bench;
pub mod builtin;
pub mod camera;
pub mod compare;
pub mod deferred;
pub mod gltf;
pub mod mesh;
pub mod shading;

use tiler::{
    Backend, ColorAttachment, DepthStencilAttachment, Device, Format, ImageDesc, ImageId, PassReport, RenderPass,
    RenderPassDesc, Result,
};

/// Render passes ready to submit, and the image they produce.
pub struct Scene {
    pub name: String,
    pub width: u32,
    pub height: u32,
    /// The image to look at when the passes are done.
    pub color: ImageId,
    pub passes: Vec<RenderPass>,
    /// Triangles submitted per frame.
    pub triangles: u64,
}

impl Scene {
    /// Submits every pass with `backend`; returns their reports.
    ///
    /// # Errors
    /// Whatever the device reports for a pass.
    pub fn render(&self, device: &mut Device, backend: Backend) -> Result<Vec<PassReport>> {
        self.passes.iter().map(|pass| device.submit_with(pass, backend)).collect()
    }

    pub fn draws(&self) -> usize {
        self.passes.iter().map(|p| p.draws.len()).sum()
    }
}

/// The attachments of a frame as a tiler should have them: colour cleared and stored (with
/// MSAA: the samples cleared, resolved in the tile into a single-sample image, never stored,
/// and transient), a D24S8 depth buffer cleared, never stored, transient. Returns the render
/// pass description and the image holding the picture.
///
/// # Errors
/// A size the device refuses.
pub fn frame_targets(
    device: &mut Device,
    width: u32,
    height: u32,
    format: Format,
    samples: u32,
    clear: [f32; 4],
) -> Result<(RenderPassDesc, ImageId)> {
    let depth =
        device.create_image(ImageDesc::new(width, height, Format::D24UnormS8Uint).with_samples(samples).transient())?;
    let (picture, color) = if samples > 1 {
        let msaa = device.create_image(ImageDesc::new(width, height, format).with_samples(samples).transient())?;
        let resolve = device.create_image(ImageDesc::new(width, height, format))?;
        (resolve, ColorAttachment::clear_resolve(msaa, clear, resolve))
    } else {
        let image = device.create_image(ImageDesc::new(width, height, format))?;
        (image, ColorAttachment::clear_store(image, clear))
    };
    let desc = RenderPassDesc {
        color: vec![color],
        depth_stencil: Some(DepthStencilAttachment::clear_discard(depth, 1.0)),
        render_area: None,
    };
    Ok((desc, picture))
}
