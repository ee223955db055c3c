//! The pipeline object: the one place where the shaders' types are erased. The phases call
//! it once per draw (vertex shading) and once per run of a draw's primitives in a tile or band
//! (rasterization); inside, everything is monomorphised for the pipeline's shaders.

use std::sync::Arc;

use crate::api::error::Result;
use crate::api::pipeline::PipelineDesc;
use crate::api::shader::{ShaderProperties, VertexShader};
use crate::geometry::VertexStage;
use crate::geometry::fetch::VertexFetcher;
use crate::geometry::vertex::{NonFinitePosition, ShadedVertices, VertexSet, shade_vertices};
use crate::ledger::Category;
use crate::pixel::primitive::{FragmentTally, Mode, PrimitiveRun, rasterize};
use crate::raster::target::RenderTarget;
use crate::shade::fragments::FragmentShader;
use crate::simd::SimdLevel;

/// A pipeline's shaders behind one dynamic call per draw (its [`VertexStage`], for the
/// geometry phase) or per run of primitives.
pub trait PipelineObject: VertexStage {
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

impl<V: VertexShader, F: FragmentShader> VertexStage for Shaders<V, F> {
    fn shade_vertices(
        &self,
        fetcher: &VertexFetcher,
        set: &VertexSet,
        varying_count: usize,
        out: &mut ShadedVertices,
    ) -> std::result::Result<(), NonFinitePosition> {
        shade_vertices(&self.vertex, fetcher, set, varying_count, out)
    }
}

impl<V: VertexShader, F: FragmentShader> PipelineObject for Shaders<V, F> {
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
        let (quads, bytes) = tally.context.texture_cache.take_unmipped();
        if quads > 0 {
            tally.counters.quads_minified_unmipped += quads;
            tally.counters.texture_fetch_minified_unmipped += bytes;
            let draw = tally.draw_stats();
            draw.quads_minified_unmipped += quads;
            draw.texture_fetch_minified_unmipped += bytes;
        }
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

/// A compiled pipeline: shaders plus state. Cheap to clone; draws hold it by reference count.
#[derive(Clone)]
pub struct Pipeline {
    pub(crate) desc: Arc<PipelineDesc>,
    pub(crate) object: Arc<dyn PipelineObject>,
}

impl Pipeline {
    /// Builds a pipeline from its shaders and state.
    ///
    /// # Errors
    /// When the state breaks a limit above or is inconsistent (an attribute outside its
    /// binding's stride, two attributes at one location, …).
    pub fn new<V: VertexShader, F: FragmentShader>(vertex: V, fragment: F, desc: PipelineDesc) -> Result<Pipeline> {
        desc.validate()?;
        let desc = Arc::new(desc);
        let object = Arc::new(Shaders::new(vertex, fragment, desc.clone()));
        Ok(Pipeline { desc, object })
    }

    pub fn desc(&self) -> &PipelineDesc {
        &self.desc
    }

    /// What its fragment shader may do (discard, write depth, …): what an advisor needs to
    /// know of the shader.
    pub fn properties(&self) -> ShaderProperties {
        self.object.properties()
    }
}

impl std::fmt::Debug for Pipeline {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Pipeline").field("label", &self.desc.label).finish_non_exhaustive()
    }
}
