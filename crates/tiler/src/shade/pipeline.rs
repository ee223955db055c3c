//! The pipeline object: the one place where the shaders' types are erased. The phases call
//! it once per draw (vertex shading) and once per run of a draw's primitives in a tile or band
//! (rasterization); inside, everything is monomorphised for the pipeline's shaders.

use std::sync::Arc;

use crate::api::pipeline::PipelineDesc;
use crate::api::shader::{FragmentShader, ShaderProperties, VertexShader};
use crate::geometry::fetch::VertexFetcher;
use crate::geometry::vertex::{NonFinitePosition, ShadedVertices, VertexSet, shade_vertices};
use crate::ledger::Category;
use crate::raster::primitive::{FragmentTally, Mode, PrimitiveRun, rasterize};
use crate::raster::target::RenderTarget;
use crate::simd::SimdLevel;

/// A pipeline's shaders behind one dynamic call per draw or per primitive.
pub trait PipelineObject: Send + Sync {
    fn shade_vertices(
        &self,
        fetcher: &VertexFetcher,
        set: &VertexSet,
        varying_count: usize,
    ) -> Result<ShadedVertices, NonFinitePosition>;

    /// Runs the primitives of `run` (all of this pipeline's draw) through the pixel pipeline.
    fn rasterize(&self, run: &PrimitiveRun, target: &mut RenderTarget, tally: &mut FragmentTally, mode: &mut Mode);

    /// What the fragment shader declares it may do.
    fn properties(&self) -> ShaderProperties;
}

/// A vertex and a fragment shader with the state they run under.
pub struct Shaders<V, F> {
    vertex: V,
    fragment: F,
    desc: Arc<PipelineDesc>,
}

impl<V, F> Shaders<V, F> {
    pub fn new(vertex: V, fragment: F, desc: Arc<PipelineDesc>) -> Shaders<V, F> {
        Shaders { vertex, fragment, desc }
    }
}

impl<V: VertexShader, F: FragmentShader> PipelineObject for Shaders<V, F> {
    fn shade_vertices(
        &self,
        fetcher: &VertexFetcher,
        set: &VertexSet,
        varying_count: usize,
    ) -> Result<ShadedVertices, NonFinitePosition> {
        shade_vertices(&self.vertex, fetcher, set, varying_count)
    }

    fn rasterize(&self, run: &PrimitiveRun, target: &mut RenderTarget, tally: &mut FragmentTally, mode: &mut Mode) {
        match tally.simd.level() {
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Avx2 => {
                // SAFETY: a `SimdSupport` of level `Avx2` exists only when this processor has
                // every feature `rasterize_avx2` is compiled with (`SimdSupport::detect`).
                unsafe { rasterize_avx2(&self.fragment, &self.desc, run, target, tally, mode) }
            }
            _ => rasterize(&self.fragment, &self.desc, run, target, tally, mode),
        }
        // The one call site of `TextureFetch` for textures: `misses × line size` of the task's
        // texture cache (`shade::texture_cache`), handed over after every run.
        let fetched = tally.context.texture_cache.take_fetched_bytes();
        tally.ledger.add(Category::TextureFetch, fetched);
    }

    fn properties(&self) -> ShaderProperties {
        self.fragment.properties()
    }
}

/// [`rasterize`] compiled for AVX2: `rasterize` and the pixel pipeline under it are
/// `#[inline(always)]`, so all of it is compiled again here with eight-lane instructions.
/// (A closure would not do: it stays a function of its own, compiled for the baseline.)
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
unsafe fn rasterize_avx2<F: FragmentShader>(
    shader: &F,
    desc: &PipelineDesc,
    run: &PrimitiveRun,
    target: &mut RenderTarget,
    tally: &mut FragmentTally,
    mode: &mut Mode,
) {
    rasterize(shader, desc, run, target, tally, mode)
}
