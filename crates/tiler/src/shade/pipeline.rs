//! The pipeline object: the one place where the shaders' types are erased. The phases call
//! it once per draw (vertex shading) and once per primitive per tile (rasterization); inside,
//! everything is monomorphised for the pipeline's shaders.

use std::sync::Arc;

use crate::api::pipeline::PipelineDesc;
use crate::api::shader::{FragmentShader, ShaderProperties, VertexShader};
use crate::binning::frame_data::Primitive;
use crate::geometry::fetch::VertexFetcher;
use crate::geometry::vertex::{NonFinitePosition, ShadedVertices, VertexSet, shade_vertices};
use crate::ledger::Category;
use crate::raster::primitive::{FragmentTally, Mode, rasterize};
use crate::tile::target::RenderTarget;

/// A pipeline's shaders behind one dynamic call per draw or per primitive.
pub trait PipelineObject: Send + Sync {
    fn shade_vertices(
        &self,
        fetcher: &VertexFetcher,
        set: &VertexSet,
        varying_count: usize,
    ) -> Result<ShadedVertices, NonFinitePosition>;

    fn rasterize(
        &self,
        primitive: &Primitive,
        varyings: &[f32],
        target: &mut RenderTarget,
        tally: &mut FragmentTally,
        mode: &mut Mode,
    );

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

    fn rasterize(
        &self,
        primitive: &Primitive,
        varyings: &[f32],
        target: &mut RenderTarget,
        tally: &mut FragmentTally,
        mode: &mut Mode,
    ) {
        rasterize(&self.fragment, &self.desc, primitive, varyings, target, tally, mode);
        // The one call site of `TextureFetch` for textures: `misses × line size` of the task's
        // texture cache (`shade::texture_cache`), handed over after every primitive.
        let fetched = tally.context.texture_cache.take_fetched_bytes();
        tally.ledger.add(Category::TextureFetch, fetched);
    }

    fn properties(&self) -> ShaderProperties {
        self.fragment.properties()
    }
}
