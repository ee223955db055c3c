//! The phases' internals, for the crate's own benchmarks only (`benches/`): not part of the
//! API, no stability promised. Everything here is safe to call: the SIMD level of a
//! `FragmentTally` is a detected `SimdSupport`.

pub use crate::geometry::primitive::Primitive;
pub use crate::geometry::setup::{DepthOffset, SetupOutcome, SetupParams, ViewportTransform, setup_triangle};
pub use crate::pixel::primitive::{FragmentTally, Mode, PrimitiveRun, rasterize};
pub use crate::raster::PixelRect;
pub use crate::raster::coverage::{BLOCK_SIZE, BlockCoverage, PrimitiveCoverage, block_rect_mask};
pub use crate::raster::samples::SampleLocations;
pub use crate::raster::target::{RenderTarget, Surface};
pub use crate::shade::texture_cache::TextureCache;
pub use crate::tile::buffer::TileBuffer;
pub use crate::tile::grid::TileGrid;
pub use crate::tile::load_store::{AttachmentOps, apply_load, apply_resolve, apply_store};
