//! Shaders written as Rust code: the vertex shader runs once per vertex, the fragment shader
//! once per 4×2 group of pixels (two 2×2 quads) in eight SIMD lanes.
//!
//! Shaders are generic parameters of [`Pipeline::new`](crate::Pipeline::new), so every call is
//! monomorphised into the pixel loop; the only dynamic dispatch is once per primitive per tile.
//! Uniforms and textures are simply fields of the shader values.

use glam::Vec4;
use serde::{Deserialize, Serialize};

use super::pipeline::{MAX_COLOR_ATTACHMENTS, MAX_VARYINGS, MAX_VERTEX_ATTRIBUTES};
use crate::shade::ShadeContext;
use crate::shade::texture::{Sampler, Texture};
use crate::simd::{F32x8, LaneMask, Vec4x8};

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
}

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
}

/// A fragment shader.
pub trait FragmentShader: Send + Sync + 'static {
    /// What this shader may do; the default is a pure function of its inputs.
    fn properties(&self) -> ShaderProperties {
        ShaderProperties::default()
    }

    /// Shades the eight lanes of `frag`, writing colours with [`Fragments::set_color`].
    fn shade(&self, frag: &mut Fragments<'_>);
}

/// Eight fragments (a 4×2 group of pixels: lanes 0–3 the top row, 4–7 the bottom row) of one
/// primitive: the fragment shader's inputs and outputs.
///
/// Lanes that the primitive does not cover are helper lanes: they are shaded so that
/// derivatives exist, and their outputs are thrown away.
pub struct Fragments<'a> {
    pub(crate) x: F32x8,
    pub(crate) y: F32x8,
    pub(crate) z: F32x8,
    /// Perspective-correct barycentric weights of vertices 1 and 2.
    pub(crate) b1: F32x8,
    pub(crate) b2: F32x8,
    /// Screen-linear barycentric weights of vertices 1 and 2.
    pub(crate) l1: F32x8,
    pub(crate) l2: F32x8,
    /// The three vertices' varyings, vertex after vertex.
    pub(crate) varyings: &'a [f32],
    pub(crate) varying_count: usize,
    pub(crate) front_facing: bool,
    pub(crate) covered: LaneMask,
    pub(crate) color: [Vec4x8; MAX_COLOR_ATTACHMENTS],
    pub(crate) written_depth: F32x8,
    pub(crate) discarded: LaneMask,
    pub(crate) context: &'a mut ShadeContext,
}

impl<'a> Fragments<'a> {
    /// Window coordinates of the pixel centres (`x + 0.5`, `y + 0.5`, y down).
    #[inline(always)]
    pub fn position(&self) -> (F32x8, F32x8) {
        (self.x, self.y)
    }

    /// Interpolated window depth at the pixel centres.
    #[inline(always)]
    pub fn depth(&self) -> F32x8 {
        self.z
    }

    #[inline(always)]
    pub fn front_facing(&self) -> bool {
        self.front_facing
    }

    /// Lanes the primitive covers (the others are helper lanes).
    #[inline(always)]
    pub fn covered(&self) -> LaneMask {
        self.covered
    }

    /// Varying `i`, interpolated perspective-correctly (GLSL `smooth`).
    #[inline(always)]
    pub fn smooth(&self, i: usize) -> F32x8 {
        let (v0, v1, v2) = self.vertex_values(i);
        F32x8::splat(v0) + self.b1 * (v1 - v0) + self.b2 * (v2 - v0)
    }

    /// Varyings `first .. first + N`, interpolated perspective-correctly.
    #[inline(always)]
    pub fn smooth_n<const N: usize>(&self, first: usize) -> [F32x8; N] {
        std::array::from_fn(|k| self.smooth(first + k))
    }

    /// Varying `i`, interpolated linearly in screen space (GLSL `noperspective`).
    #[inline(always)]
    pub fn linear(&self, i: usize) -> F32x8 {
        let (v0, v1, v2) = self.vertex_values(i);
        F32x8::splat(v0) + self.l1 * (v1 - v0) + self.l2 * (v2 - v0)
    }

    /// Varying `i` of the provoking vertex (GLSL `flat`).
    #[inline(always)]
    pub fn flat(&self, i: usize) -> f32 {
        self.varyings[i]
    }

    #[inline(always)]
    fn vertex_values(&self, i: usize) -> (f32, f32, f32) {
        let n = self.varying_count;
        (self.varyings[i], self.varyings[n + i], self.varyings[2 * n + i])
    }

    /// Writes the colour for colour attachment `attachment` of the subpass.
    #[inline(always)]
    pub fn set_color(&mut self, attachment: usize, rgba: Vec4x8) {
        self.color[attachment] = rgba;
    }

    /// Replaces the fragment depth (the shader must declare `writes_depth`).
    #[inline(always)]
    pub fn set_depth(&mut self, z: F32x8) {
        self.written_depth = z;
    }

    /// Discards the given lanes (the shader must declare `discards`).
    #[inline(always)]
    pub fn discard(&mut self, lanes: LaneMask) {
        self.discarded = self.discarded | lanes;
    }

    /// Samples `texture` at `uv` with `sampler`, the level of detail from this group's quad
    /// derivatives (see `shade::texture`). The texel reads of every quad with a covered pixel,
    /// helper lanes included, go through the task's texture cache and so into the ledger.
    #[inline]
    pub fn sample(&mut self, texture: &Texture, sampler: &Sampler, uv: [F32x8; 2]) -> Vec4x8 {
        texture.sample(sampler, uv[0], uv[1], self.covered.quads(), &mut self.context.texture_cache)
    }

    /// Per-tile state shaders may use (texture caches and their counters).
    #[inline(always)]
    pub fn context(&mut self) -> &mut ShadeContext {
        self.context
    }
}
