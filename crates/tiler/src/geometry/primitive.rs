//! The primitive: a set-up triangle, what the geometry phase produces and every later phase
//! (binning, rasterization, interpolation) reads.

use crate::raster::PixelRect;
use crate::raster::edge::Edge;
use crate::raster::fixed::SubPixel;

/// A set-up triangle, ready to rasterize in any tile.
///
/// Vertices are ordered so the signed area is positive (vertex 0 is the provoking vertex).
/// Interpolation uses screen-space barycentrics `λ1, λ2` of vertices 1 and 2, as planes
/// relative to vertex 0's window position `origin`:
/// `λk(x, y) = lk[0]·(x − origin.x) + lk[1]·(y − origin.y)`. The planes come from the window
/// positions before they are snapped to the sub-pixel grid (the edges use the snapped ones).
/// Depth is `z[0] + λ1·z[1] + λ2·z[2]` (linear in screen space, Vulkan); varyings are
/// perspective-correct through `q = 1/w` of each vertex.
#[derive(Clone, Copy, Debug)]
pub struct Primitive {
    /// The three vertices' window positions in sub-pixels, in the order above. The edge
    /// functions follow from them exactly ([`Primitive::edges`]): a record of
    /// 112 bytes rather than 160 with the edges stored, which matters because the tile pass
    /// reads records scattered over the frame data, each a cache miss (docs/benchmarking.md,
    /// "Primitive records").
    pub window: [(SubPixel, SubPixel); 3],
    /// Pixels that may hold a covered sample, within the draw's clip rectangle.
    pub bbox: PixelRect,
    /// Vertex 0's window position in pixels before snapping, the origin of the planes.
    pub origin: [f32; 2],
    pub l1: [f32; 2],
    pub l2: [f32; 2],
    pub z: [f32; 3],
    pub q: [f32; 3],
    /// Index of the state record.
    pub state: u32,
    /// Offset of the three vertices' varyings in the frame data's varyings
    /// (`binning::frame_data::FrameData::varyings`).
    pub varyings: u32,
    /// The draw's vertices this primitive came from (clipped pieces keep their triangle's).
    pub vertex_ids: [u32; 3],
    pub front_facing: bool,
}

impl Primitive {
    /// The edge functions, vertex 0 → 1 → 2 → 0.
    #[inline(always)]
    pub fn edges(&self) -> [Edge; 3] {
        let p = &self.window;
        [Edge::new(p[0], p[1]), Edge::new(p[1], p[2]), Edge::new(p[2], p[0])]
    }
}
