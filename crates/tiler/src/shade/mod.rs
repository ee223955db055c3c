//! Shading: interpolation of depth and varyings at pixel centres and samples, the per-tile
//! context shaders see, and the pipeline object that ties monomorphised shaders to the
//! phases.

pub mod interpolate;
pub mod pipeline;

/// Per-task state a fragment shader may use. Texture sampling will keep its cache model here;
/// one context per tile (or band) keeps results independent of thread scheduling.
#[derive(Debug, Default)]
pub struct ShadeContext {
    _private: (),
}
