//! Scenes for tiler: the built-in scene made in code, cameras and procedural meshes.
//!
//! A [`Scene`] is a set of render passes recorded against a [`Device`]'s images and buffers;
//! rendering it submits them in order.

pub mod builtin;
pub mod camera;
pub mod deferred;
pub mod mesh;

use tiler::{Backend, Device, ImageId, PassReport, RenderPass, Result};

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
