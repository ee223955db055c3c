//! The public API, shaped like an explicit modern GPU API (names after Vulkan and wgpu):
//! images and buffers owned by a device, pipelines, render passes, submission.

pub mod buffer;
pub mod error;
pub mod format;
pub mod image;
pub mod pipeline;
pub mod render_pass;
pub mod shader;
