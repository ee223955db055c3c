//! Render passes as recorded: draws (a pipeline, its buffers, its vertices) in submission
//! order, grouped into subpasses; and their validation at the front door ([`resolved`]).

pub mod resolved;

use crate::api::buffer::BufferId;
use crate::api::render_pass::{
    IndexBufferBinding, IndexType, Rect, RenderPassDesc, SubpassDependency, SubpassDesc, VertexBufferBinding, Viewport,
};
use crate::geometry::DrawInput;
use crate::pixel::Pipeline;
use crate::raster::samples::SampleOrigin;

/// One draw: a pipeline, its buffers, and which vertices (or indices) to draw.
#[derive(Clone, Debug)]
pub struct Draw {
    pub pipeline: Pipeline,
    pub vertex_buffers: Vec<VertexBufferBinding>,
    pub index_buffer: Option<IndexBufferBinding>,
    /// The first vertex (non-indexed) or the first index (indexed).
    pub first: u32,
    /// How many vertices (non-indexed) or indices (indexed).
    pub count: u32,
    /// Added to every index of an indexed draw.
    pub vertex_offset: i32,
    /// `None` = the whole framebuffer.
    pub viewport: Option<Viewport>,
    /// `None` = no scissor.
    pub scissor: Option<Rect>,
}

impl Draw {
    /// What the geometry phase reads of this draw.
    pub(crate) fn geometry_input(&self) -> DrawInput<'_> {
        DrawInput {
            desc: self.pipeline.desc(),
            vertex: &*self.pipeline.object,
            vertex_buffers: &self.vertex_buffers,
            index_buffer: self.index_buffer,
            first: self.first,
            count: self.count,
            vertex_offset: self.vertex_offset,
            viewport: self.viewport,
            scissor: self.scissor,
        }
    }

    /// A non-indexed draw of `count` vertices from one vertex buffer.
    pub fn new(pipeline: &Pipeline, vertex_buffer: BufferId, first: u32, count: u32) -> Draw {
        Draw {
            pipeline: pipeline.clone(),
            vertex_buffers: vec![VertexBufferBinding { buffer: vertex_buffer, offset: 0 }],
            index_buffer: None,
            first,
            count,
            vertex_offset: 0,
            viewport: None,
            scissor: None,
        }
    }

    /// An indexed draw of `count` indices from one vertex buffer and an index buffer.
    pub fn indexed(
        pipeline: &Pipeline,
        vertex_buffer: BufferId,
        index_buffer: BufferId,
        index_type: IndexType,
        first: u32,
        count: u32,
    ) -> Draw {
        Draw {
            index_buffer: Some(IndexBufferBinding { buffer: index_buffer, offset: 0, index_type }),
            ..Draw::new(pipeline, vertex_buffer, first, count)
        }
    }

    pub fn with_viewport(self, viewport: Viewport) -> Draw {
        Draw { viewport: Some(viewport), ..self }
    }

    pub fn with_scissor(self, scissor: Rect) -> Draw {
        Draw { scissor: Some(scissor), ..self }
    }
}

/// A render pass: its description, its subpasses and its draws in submission order.
#[derive(Clone, Debug)]
pub struct RenderPass {
    pub desc: RenderPassDesc,
    /// Empty: one subpass writing every colour attachment and using the depth-stencil one.
    pub subpasses: Vec<SubpassDesc>,
    pub dependencies: Vec<SubpassDependency>,
    pub draws: Vec<Draw>,
    /// The index of the first draw of each subpass after the first.
    pub subpass_starts: Vec<usize>,
    /// Which way up the sample locations of a multisampled pass are laid out.
    pub sample_origin: SampleOrigin,
}

impl RenderPass {
    /// A pass with one subpass that writes every attachment.
    pub fn new(desc: RenderPassDesc) -> RenderPass {
        RenderPass {
            desc,
            subpasses: Vec::new(),
            dependencies: Vec::new(),
            draws: Vec::new(),
            subpass_starts: Vec::new(),
            sample_origin: SampleOrigin::UpperLeft,
        }
    }

    /// The pass with its sample locations laid out from `origin` (see [`SampleOrigin`]).
    pub fn with_sample_origin(self, origin: SampleOrigin) -> RenderPass {
        RenderPass { sample_origin: origin, ..self }
    }

    /// A pass with explicit subpasses; draws go to the first until [`RenderPass::next_subpass`].
    pub fn with_subpasses(
        desc: RenderPassDesc,
        subpasses: Vec<SubpassDesc>,
        dependencies: Vec<SubpassDependency>,
    ) -> RenderPass {
        RenderPass { subpasses, dependencies, ..RenderPass::new(desc) }
    }

    /// Records a draw in the current subpass.
    pub fn draw(&mut self, draw: Draw) -> &mut RenderPass {
        self.draws.push(draw);
        self
    }

    /// Moves on to the next subpass (Vulkan `vkCmdNextSubpass`).
    pub fn next_subpass(&mut self) -> &mut RenderPass {
        self.subpass_starts.push(self.draws.len());
        self
    }

    /// The subpass draw `draw` belongs to.
    pub fn subpass_of(&self, draw: usize) -> usize {
        self.subpass_starts.iter().take_while(|&&start| start <= draw).count()
    }
}
