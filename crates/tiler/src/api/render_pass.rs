//! Render passes: attachments with their load and store ops, and the draws recorded into them.

use serde::{Deserialize, Serialize};

use super::buffer::BufferId;
use super::image::ImageId;

/// A rectangle of pixels, `x, y` its top-left corner (y down).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Rect {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

impl Rect {
    pub const fn new(x: u32, y: u32, width: u32, height: u32) -> Rect {
        Rect { x, y, width, height }
    }

    pub const fn right(&self) -> u64 {
        self.x as u64 + self.width as u64
    }

    pub const fn bottom(&self) -> u64 {
        self.y as u64 + self.height as u64
    }

    pub const fn area(&self) -> u64 {
        self.width as u64 * self.height as u64
    }
}

/// The transform from normalised device coordinates to window coordinates (Vulkan's):
/// `x_w = x + (x_ndc + 1) · width / 2`, `y_w = y + (y_ndc + 1) · height / 2`,
/// `z_w = min_depth + z_ndc · (max_depth − min_depth)`. Primitives are clipped to it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Viewport {
    pub x: f32,
    pub y: f32,
    pub width: f32,
    pub height: f32,
    pub min_depth: f32,
    pub max_depth: f32,
}

impl Viewport {
    /// The whole of a `width × height` framebuffer, depth range `[0, 1]`.
    pub fn full(width: u32, height: u32) -> Viewport {
        Viewport { x: 0.0, y: 0.0, width: width as f32, height: height as f32, min_depth: 0.0, max_depth: 1.0 }
    }
}

/// What happens to an attachment's contents when a render pass starts.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LoadOp<T> {
    /// Read the contents from external memory into the tile buffer.
    Load,
    /// Start from this value; nothing is read.
    Clear(T),
    /// The previous contents do not matter; nothing is read. The attachment then holds an
    /// undefined value, which tiler makes zero on every backend, so images stay comparable.
    DontCare,
}

/// What happens to an attachment's contents when a render pass ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StoreOp {
    /// Write the contents to external memory.
    Store,
    /// Throw them away; nothing is written (the image in memory is left as it was on a tiler).
    DontCare,
}

/// A colour attachment of a render pass.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ColorAttachment {
    pub image: ImageId,
    pub load: LoadOp<[f32; 4]>,
    pub store: StoreOp,
    /// A single-sample image of the same size and format that receives the average of the
    /// samples at the end of the pass (resolved in the tile on a tiler).
    #[serde(default)]
    pub resolve: Option<ImageId>,
}

impl ColorAttachment {
    /// Cleared at the start, stored at the end: the usual render target.
    pub fn clear_store(image: ImageId, color: [f32; 4]) -> ColorAttachment {
        ColorAttachment { image, load: LoadOp::Clear(color), store: StoreOp::Store, resolve: None }
    }

    /// A multisampled attachment cleared, resolved into `resolve` and not stored itself: what
    /// MSAA should be on a tiler (the samples never leave the chip).
    pub fn clear_resolve(image: ImageId, color: [f32; 4], resolve: ImageId) -> ColorAttachment {
        ColorAttachment { image, load: LoadOp::Clear(color), store: StoreOp::DontCare, resolve: Some(resolve) }
    }

    /// Loaded and stored, no resolve.
    pub fn load_store(image: ImageId) -> ColorAttachment {
        ColorAttachment { image, load: LoadOp::Load, store: StoreOp::Store, resolve: None }
    }
}

/// The depth-stencil attachment of a render pass, with separate ops for each aspect.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct DepthStencilAttachment {
    pub image: ImageId,
    pub depth_load: LoadOp<f32>,
    pub depth_store: StoreOp,
    pub stencil_load: LoadOp<u8>,
    pub stencil_store: StoreOp,
}

impl DepthStencilAttachment {
    /// Depth cleared to `depth` and thrown away at the end, stencil cleared to 0 and thrown
    /// away: what a frame's depth buffer should be on a tiler.
    pub fn clear_discard(image: ImageId, depth: f32) -> DepthStencilAttachment {
        DepthStencilAttachment {
            image,
            depth_load: LoadOp::Clear(depth),
            depth_store: StoreOp::DontCare,
            stencil_load: LoadOp::Clear(0),
            stencil_store: StoreOp::DontCare,
        }
    }

    /// Depth and stencil cleared and stored.
    pub fn clear_store(image: ImageId, depth: f32, stencil: u8) -> DepthStencilAttachment {
        DepthStencilAttachment {
            image,
            depth_load: LoadOp::Clear(depth),
            depth_store: StoreOp::Store,
            stencil_load: LoadOp::Clear(stencil),
            stencil_store: StoreOp::Store,
        }
    }
}

/// The attachments of a render pass and the area it renders.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RenderPassDesc {
    /// Up to [`MAX_COLOR_ATTACHMENTS`](super::pipeline::MAX_COLOR_ATTACHMENTS).
    pub color: Vec<ColorAttachment>,
    pub depth_stencil: Option<DepthStencilAttachment>,
    /// The pixels the pass may touch; `None` = the whole attachment. Load and store ops act
    /// only inside it, and primitives are clipped to it.
    pub render_area: Option<Rect>,
}

/// Which vertex buffer a binding reads, from which byte offset.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct VertexBufferBinding {
    pub buffer: BufferId,
    pub offset: u64,
}

/// The width of the indices in an index buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum IndexType {
    U16,
    U32,
}

impl IndexType {
    pub const fn size_bytes(self) -> u64 {
        match self {
            IndexType::U16 => 2,
            IndexType::U32 => 4,
        }
    }
}

/// An index buffer binding.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct IndexBufferBinding {
    pub buffer: BufferId,
    pub offset: u64,
    pub index_type: IndexType,
}

/// An attachment of the pass named by a subpass.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AttachmentRef {
    /// The pass's colour attachment at this index.
    Color(u32),
    /// The pass's depth-stencil attachment.
    DepthStencil,
}

/// One subpass: which of the pass's attachments it writes and reads (Vulkan
/// `VkSubpassDescription`).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SubpassDesc {
    /// Colour attachments written, as indices into the pass's colour attachments; fragment
    /// shader output `i` goes to `color[i]`.
    pub color: Vec<u32>,
    /// Whether depth and stencil tests use the pass's depth-stencil attachment.
    pub depth_stencil: bool,
    /// Input attachments: what an earlier subpass wrote, read at the same pixel (and sample)
    /// with [`Fragments::input`](crate::Fragments::input), from the tile buffer on a tiler.
    pub input: Vec<AttachmentRef>,
    /// Per colour output, an image to resolve it into (resolved when the pass ends; no later
    /// subpass may write that attachment).
    #[serde(default)]
    pub resolve: Vec<Option<ImageId>>,
}

/// An ordering between two subpasses (Vulkan `VkSubpassDependency`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct SubpassDependency {
    pub src: u32,
    pub dst: u32,
    /// The destination reads only what the source wrote at the same pixel (Vulkan's
    /// `BY_REGION`): a tiler keeps both in the tile. Without it, a tiler must finish the
    /// source everywhere first: the pass is split there, through external memory.
    pub by_region: bool,
}

/// The load and store ops of one attachment, per aspect.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AttachmentOps {
    Color { load: LoadOp<[f32; 4]>, store: StoreOp },
    DepthStencil { depth_load: LoadOp<f32>, depth_store: StoreOp, stencil_load: LoadOp<u8>, stencil_store: StoreOp },
}

impl AttachmentOps {
    /// The ops of an incremental render's middle: load and store everything.
    pub fn load_store_all(&self) -> AttachmentOps {
        match self {
            AttachmentOps::Color { .. } => AttachmentOps::Color { load: LoadOp::Load, store: StoreOp::Store },
            AttachmentOps::DepthStencil { .. } => AttachmentOps::DepthStencil {
                depth_load: LoadOp::Load,
                depth_store: StoreOp::Store,
                stencil_load: LoadOp::Load,
                stencil_store: StoreOp::Store,
            },
        }
    }

    /// These ops with the load ops replaced by `Load` (a continuation after a flush).
    pub fn with_load(&self) -> AttachmentOps {
        match *self {
            AttachmentOps::Color { store, .. } => AttachmentOps::Color { load: LoadOp::Load, store },
            AttachmentOps::DepthStencil { depth_store, stencil_store, .. } => AttachmentOps::DepthStencil {
                depth_load: LoadOp::Load,
                depth_store,
                stencil_load: LoadOp::Load,
                stencil_store,
            },
        }
    }

    /// These ops with every store op `Store` (the end of a flush that is not the last).
    pub fn with_store(&self) -> AttachmentOps {
        match *self {
            AttachmentOps::Color { load, .. } => AttachmentOps::Color { load, store: StoreOp::Store },
            AttachmentOps::DepthStencil { depth_load, stencil_load, .. } => AttachmentOps::DepthStencil {
                depth_load,
                depth_store: StoreOp::Store,
                stencil_load,
                stencil_store: StoreOp::Store,
            },
        }
    }
}

/// The most input attachments a subpass may read.
pub const MAX_INPUT_ATTACHMENTS: usize = 4;

/// A validated subpass, naming attachments by their index in the validated pass's
/// attachments (`pass::resolved::ResolvedPass`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ResolvedSubpass {
    /// Attachment of each colour output.
    pub color: Vec<usize>,
    pub depth_stencil: Option<usize>,
    /// Attachment of each input.
    pub inputs: Vec<usize>,
    /// Resolve images of colour outputs (before validation into the pass's resolves).
    pub resolves: Vec<Option<ImageId>>,
    /// A dependency into this subpass is not by-region: a tiler must split the pass here.
    pub split_before: bool,
}
