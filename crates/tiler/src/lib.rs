//! tiler: a tile-based deferred GPU built in software.
//!
//! It renders the way mobile tile-based GPUs do and counts every byte that crosses to
//! external memory:
//!
//! ```text
//!  render pass = attachments (format, samples, load op, store op) + draws (pipeline, buffers)
//!      │
//!  geometry phase (`geometry`): fetch → vertex shader → assemble → clip → cull → viewport
//!      → triangle setup in fixed point → BINNING (`binning`) into FRAME DATA
//!      │   (polygon lists per tile + primitive and state records; it has a budget)
//!  tile phase (`tile::task`), one tile at a time, in parallel: load op → the tile's list by
//!      draw through the pixel pipeline (`pixel`: coverage per sample from `raster`, early-Z
//!      or HSR from `depth`, 2×2 quads shaded by `shade`, `blend` in the tile buffer)
//!      → store op → resolve
//!      │
//!  external memory: images and buffers, and the LEDGER (`ledger`) of every byte moved
//! ```
//!
//! Backends (`backend`): `Tbr` (the above) and `Imr` (immediate mode: the same primitives in
//! submission order, straight into the images). For one input every backend, tile size and
//! thread count gives the same image, bit for bit; only the counters differ.
//!
//! The top-level modules import each other only downwards, in data-flow order (`simd`,
//! `ledger`, `api` at the bottom; `backend`, `device` at the top): the `layers` test fails on
//! a cycle, and `cargo run -p tiler --example module-graph` prints the graph with the site of
//! every import.
//!
//! Textures (`shade::texture`: RGBA8, packed 16-bit, float, ETC2/EAC and ASTC formats decoded
//! at creation (`shade::texel_format`), with mip chains, nearest/bilinear/trilinear filtering,
//! repeat/clamp/mirror wraps) are fields of shader values; [`Fragments::sample`] reads them with
//! a level of detail from 2×2 quad derivatives, through the texture-cache model of the shading
//! task (`shade::texture_cache`), whose misses the ledger counts as `TextureFetch`.
//!
//! Glossary: *frame data* — what binning writes (ARM: polygon lists; Imagination: parameter
//! buffer); *tile buffer* — on-chip memory for one tile of every attachment; *load/store op* —
//! what happens to an attachment at the start/end of a pass; *incremental render* — the
//! forced flush when frame data outgrows its budget; *early-Z* — depth test before shading.
//!
//! ```
//! use tiler::*;
//!
//! struct Flat;
//! impl VertexShader for Flat {
//!     fn shade(&self, input: &VertexInput, out: &mut VertexOutput) {
//!         out.position = input.attributes[0];
//!     }
//! }
//! impl FragmentShader for Flat {
//!     fn shade(&self, frag: &mut Fragments<'_>) {
//!         frag.set_color(0, [F32x8::ONE, F32x8::ZERO, F32x8::ZERO, F32x8::ONE]);
//!     }
//! }
//!
//! let mut device = Device::new(DeviceConfig::default()).unwrap();
//! let color = device.create_image(ImageDesc::new(64, 64, Format::Rgba8Unorm)).unwrap();
//! let vertices: [[f32; 4]; 3] = [[-1.0, -1.0, 0.5, 1.0], [3.0, -1.0, 0.5, 1.0], [-1.0, 3.0, 0.5, 1.0]];
//! let buffer = device.create_buffer_from(&vertices).unwrap();
//! let pipeline = Pipeline::new(
//!     Flat,
//!     Flat,
//!     PipelineDesc::new("flat", VertexInputState::interleaved(&[VertexFormat::Float32x4])),
//! )
//! .unwrap();
//! let mut pass = RenderPass::new(RenderPassDesc {
//!     color: vec![ColorAttachment::clear_store(color, [0.0, 0.0, 0.0, 1.0])],
//!     depth_stencil: None,
//!     render_area: None,
//! });
//! pass.draw(Draw::new(&pipeline, buffer, 0, 3));
//! let report = device.submit(&pass).unwrap();
//! assert_eq!(report.counters.fragments_shaded, 64 * 64);
//! assert_eq!(&device.read_rgba8(color).unwrap()[..4], &[255, 0, 0, 255]);
//! ```

#[doc(hidden)]
pub mod __bench;
pub mod api;
pub(crate) mod backend;
pub(crate) mod binning;
pub(crate) mod blend;
pub mod config;
pub(crate) mod depth;
pub mod device;
pub mod frame;
pub(crate) mod geometry;
pub(crate) mod huge_pages;
pub mod ledger;
pub(crate) mod pass;
pub(crate) mod pixel;
pub(crate) mod raster;
pub(crate) mod shade;
pub mod simd;
pub(crate) mod tile;

pub use api::buffer::BufferId;
pub use api::error::{Error, Result};
pub use api::format::{ColorWrites, Format, IntFormat};
pub use api::image::{ImageDesc, ImageId, MAX_IMAGE_BYTES, MAX_IMAGE_DIMENSION};
pub use api::pipeline::{
    BlendComponent, BlendFactor, BlendOp, BlendState, ColorTargetState, CompareOp, CullMode, DepthBias,
    DepthStencilState, FrontFace, Interpolation, MAX_COLOR_ATTACHMENTS, MAX_VARYINGS, MAX_VERTEX_ATTRIBUTES,
    PipelineDesc, ProvokingVertex, StencilFaceState, StencilOp, Topology, VertexAttribute, VertexBinding, VertexFormat,
    VertexInputState,
};
pub use api::render_pass::{
    AttachmentRef, ColorAttachment, DepthStencilAttachment, IndexBufferBinding, IndexType, LoadOp,
    MAX_INPUT_ATTACHMENTS, Rect, RenderPassDesc, StoreOp, SubpassDependency, SubpassDesc, VertexBufferBinding,
    Viewport,
};
pub use api::shader::{ShaderProperties, VERTEX_BATCH, VertexInput, VertexOutput, VertexShader};
pub use backend::{FrameDataReport, PassReport, Workers};
pub use binning::frame_data::{
    POLYGON_LIST_ENTRY_BYTES, PRIMITIVE_HEADER_BYTES, STATE_RECORD_BYTES, VERTEX_POSITION_BYTES, primitive_record_bytes,
};
pub use config::Backend;
pub use config::{DeviceConfig, preset::DevicePreset};
pub use device::Device;
pub use frame::FrameCost;
pub use geometry::VertexShading;
pub use geometry::fetch::read_attribute;
pub use ledger::cache::CacheConfig;
pub use ledger::display::DisplayModel;
pub use ledger::energy::{EnergyEstimate, EnergyModel};
pub use ledger::time::{Stage, TimeEstimate, TimeModel};
pub use ledger::{Category, Counters, DrawStats, Ledger, TileStats};
pub use pass::{Draw, RenderPass};
pub use pixel::Pipeline;
pub use raster::samples::SampleOrigin;
pub use shade::ShadeContext;
pub use shade::depth_compare;
pub use shade::fragments::{FragmentShader, Fragments};
pub use shade::texel_format::{ASTC_FOOTPRINTS, StoredLayout, TexelFormat};
pub use shade::texture::{
    ColorSpace, CubeFace, Filter, IntegerKind, IntegerTexture, LayeredKind, Lookup, MAX_ARRAY_LAYERS,
    MAX_CUBE_DIMENSION, MAX_TEXTURE_DIMENSION, MAX_VOLUME_DIMENSION, MipChain, MipmapMode, Sampler, Texture, Wrap,
    cube_face_coordinates,
};
pub use shade::texture_cache::TextureCacheConfig;
pub use simd::{F32x8, LaneMask, SimdLevel, SimdSupport, Vec4x8};
