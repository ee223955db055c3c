//! Cameras: view and projection matrices in tiler's clip conventions (Vulkan: y down in
//! clip space, depth 0 at the near plane and 1 at the far plane).

use glam::{Mat4, Vec3};

/// A perspective camera looking from `eye` at `target`, y up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub fov_y_radians: f32,
    pub near: f32,
    pub far: f32,
}

impl Camera {
    pub fn look_at(eye: Vec3, target: Vec3, fov_y_radians: f32, near: f32, far: f32) -> Camera {
        Camera { eye, target, fov_y_radians, near, far }
    }

    /// World → clip for a viewport of the given aspect (width / height): right-handed view,
    /// Vulkan projection (y down, depth in [0, 1]), so a triangle counter-clockwise seen from
    /// the front is counter-clockwise in tiler's framebuffer.
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let view = glam::camera::rh::view::look_at_mat4(self.eye, self.target, Vec3::Y);
        let proj = glam::camera::rh::proj::vulkan::perspective(self.fov_y_radians, aspect, self.near, self.far);
        proj * view
    }
}
