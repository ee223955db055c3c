//! Shading: interpolation of depth and varyings at pixel centres and samples, textures and
//! samplers, the per-task context shaders see (with its texture cache), and the pipeline
//! object that ties monomorphised shaders to the phases.

pub mod astc;
pub mod depth_compare;
pub mod fragments;
pub mod interpolate;
pub mod texel_format;
pub mod texture;
pub mod texture_cache;

use texture_cache::{TextureCache, TextureCacheConfig};

/// Per-task state a fragment shader may use: the texture cache model and its counts. One
/// context per task (a band of tiles, or a band of rows for one draw in immediate mode) keeps
/// results independent of thread scheduling. The backends create it with
/// `ShadeContext::default()`, so the cache has [`TextureCacheConfig::DEFAULT`]'s shape.
#[derive(Debug, Default)]
pub struct ShadeContext {
    pub texture_cache: TextureCache,
}

impl ShadeContext {
    /// A context whose texture cache has the given shape (validate it first).
    pub fn with_texture_cache(config: TextureCacheConfig) -> ShadeContext {
        ShadeContext { texture_cache: TextureCache::new(config) }
    }
}
