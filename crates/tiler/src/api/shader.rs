//! Shaders written as Rust code: the vertex shader runs once per vertex, the fragment shader
//! once per 4×2 group of pixels (two 2×2 quads) in eight SIMD lanes.
//!
//! Shaders are generic parameters of [`Pipeline::new`](crate::Pipeline::new), so every call is
//! monomorphised into the pixel loop; the only dynamic dispatch is once per primitive per tile.
//! Uniforms and textures are simply fields of the shader values.

use glam::Vec4;
use serde::{Deserialize, Serialize};

use super::pipeline::{MAX_VARYINGS, MAX_VERTEX_ATTRIBUTES};

/// What the vertex shader reads: each attribute fetched and converted to a vector.
#[derive(Clone, Copy, Debug)]
pub struct VertexInput {
    pub attributes: [Vec4; MAX_VERTEX_ATTRIBUTES],
    /// The vertex's index (from the index buffer, or its position in a non-indexed draw).
    pub vertex_index: u32,
}

/// What the vertex shader writes: the clip-space position (Vulkan conventions: x right, y
/// down, visible depth `0 ≤ z ≤ w`) and the varyings the pipeline declares.
#[derive(Clone, Copy, Debug)]
pub struct VertexOutput {
    pub position: Vec4,
    pub varyings: [f32; MAX_VARYINGS],
}

impl Default for VertexOutput {
    fn default() -> VertexOutput {
        VertexOutput { position: Vec4::ZERO, varyings: [0.0; MAX_VARYINGS] }
    }
}

/// A vertex shader.
pub trait VertexShader: Send + Sync + 'static {
    fn shade(&self, input: &VertexInput, out: &mut VertexOutput);

    /// Shades `inputs[i]` into `outs[i]` (the same length, at most [`VERTEX_BATCH`]), each as
    /// [`VertexShader::shade`] would: one by one unless the shader runs vertices side by side
    /// (an interpreter amortising its dispatch over lanes).
    fn shade_batch(&self, inputs: &[VertexInput], outs: &mut [VertexOutput]) {
        for (input, out) in inputs.iter().zip(outs) {
            self.shade(input, out);
        }
    }
}

/// The most vertices one [`VertexShader::shade_batch`] call is given: eight, the lanes of
/// an AVX2 register of `f32`.
pub const VERTEX_BATCH: usize = 8;

/// What a fragment shader may do that decides how early the depth test may run and whether
/// hidden-surface removal may skip it (seed 000 §23.7, seed 002 "Depth Testing").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct ShaderProperties {
    /// May call [`Fragments::discard`].
    pub discards: bool,
    /// Writes its own depth with [`Fragments::set_depth`].
    pub writes_depth: bool,
    /// Has effects besides its outputs (storage writes, counters): it must run for every
    /// fragment the rasterizer produces, before any test.
    pub side_effects: bool,
    /// Writes its own sample mask with [`Fragments::set_sample_mask`] (GLSL `gl_SampleMask`).
    pub writes_sample_mask: bool,
    /// Reads the current subpass's colour attachments with [`Fragments::local`] (pixel-local
    /// storage): its fragments must run in submission order, like blending.
    pub reads_local: bool,
}
