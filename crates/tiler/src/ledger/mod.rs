//! The ledger: every byte that crosses between the GPU (tile buffer, caches) and external
//! memory, by category, and the counters of what the pipeline did.
//!
//! Each category is recorded at exactly one call site, next to its formula, so the figures
//! can be checked by hand. Counts are plain data per task (tile, band, geometry chunk),
//! merged in a fixed order: there are no global counters.

pub mod cache;
pub mod display;
pub mod energy;
pub mod framebuffer;
pub mod hsr;
pub mod time;

use serde::{Deserialize, Serialize};

pub use hsr::HsrFallbacks;

/// Declares [`Category`] and derives [`Category::formula`] from each variant's doc comment, so
/// the formula of a category is written once, next to the code, and reports quote that text.
macro_rules! category_with_formulas {
    (
        $(#[$meta:meta])*
        pub enum Category { $( $(#[doc = $doc:literal])* $variant:ident, )* }
    ) => {
        $(#[$meta])*
        pub enum Category { $( $(#[doc = $doc])* $variant, )* }

        impl Category {
            /// What the category counts and its formula: the variant's doc comment as one line.
            pub fn formula(self) -> String {
                let doc = match self { $( Category::$variant => concat!($($doc, "\n"),*), )* };
                doc.lines().map(str::trim).filter(|l| !l.is_empty()).collect::<Vec<_>>().join(" ")
            }
        }
    };
}

category_with_formulas! {
/// A kind of external-memory traffic. The formula of each is recorded where it is counted.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Category {
    /// Vertex attributes read: the vertex cache's line fills as the vertices shaded are
    /// fetched, in shading order: `lines filled × line size` (`geometry::fetch`; without a
    /// cache, `vertices shaded × Σ attribute sizes`).
    VertexFetch,
    /// Indices read: `indices × index size` (`geometry`).
    IndexFetch,
    /// Frame data written by binning: primitive records, polygon-list entries and state
    /// records, sizes as `binning::frame_data` documents them.
    FrameDataWrite,
    /// Frame data read back by the tile phase: for every tile, its polygon-list entries, the
    /// record of each primitive they name, and a state record at each change of state.
    FrameDataRead,
    /// Attachments read into the tile buffer by `LoadOp::Load`:
    /// `pixels of the tile in the render area × samples × bytes of the loaded aspect` (a
    /// packed D24S8 sample moves as one 4-byte word, whichever aspects are loaded).
    TileLoad,
    /// Attachments written from the tile buffer by `StoreOp::Store`:
    /// `pixels of the tile in the render area × samples × bytes of the stored aspect` (a
    /// packed D24S8 sample: one 4-byte word), less the tiles transaction elimination skips.
    TileStore,
    /// Multisampled colour averaged and written to a single-sample resolve image:
    /// `pixels × bytes per pixel of the resolve image` (tilers: at store, from the tile
    /// buffer; immediate mode: plus reading every sample back from memory).
    Resolve,
    /// Texels fetched from external memory through the texture cache: `misses × line size`.
    TextureFetch,
    /// Copies a driver makes of a buffer or texture still used by a pending frame when the
    /// application changes it (copy-on-write): `bytes copied × 2` (read and write).
    CopyOnWrite,
    /// Vertex shader outputs transform feedback writes to buffers:
    /// `vertices captured × bytes captured per vertex` (`tiler-gl`'s transform feedback).
    TransformFeedbackWrite,
    /// The display controller reading the finished frame: `width × height × bytes per pixel`.
    Display,
    /// The window system compositing the frame: read and write of the frame.
    Composition,
    /// Immediate mode: a `LoadOp::Clear` writes the render area of the attachment:
    /// `pixels × samples × bytes of the cleared aspect`.
    ImrClear,
    /// Immediate mode: colour read for blending or a partial write mask, per sample written.
    ImrColorRead,
    /// Immediate mode: colour written, per covered sample that passed every test.
    ImrColorWrite,
    /// Immediate mode: depth read for the depth test, per sample tested (packed D24S8: the
    /// 4-byte word, or its 3 depth bytes when the stencil is read with it).
    ImrDepthRead,
    /// Immediate mode: depth written, per sample passing with depth writes on.
    ImrDepthWrite,
    /// Immediate mode: stencil read for the stencil test, per sample tested.
    ImrStencilRead,
    /// Immediate mode: stencil written, per sample whose stencil op writes.
    ImrStencilWrite,
}
}

impl Category {
    pub const ALL: [Category; 19] = [
        Category::VertexFetch,
        Category::IndexFetch,
        Category::FrameDataWrite,
        Category::FrameDataRead,
        Category::TileLoad,
        Category::TileStore,
        Category::Resolve,
        Category::TextureFetch,
        Category::CopyOnWrite,
        Category::TransformFeedbackWrite,
        Category::Display,
        Category::Composition,
        Category::ImrClear,
        Category::ImrColorRead,
        Category::ImrColorWrite,
        Category::ImrDepthRead,
        Category::ImrDepthWrite,
        Category::ImrStencilRead,
        Category::ImrStencilWrite,
    ];
    pub const COUNT: usize = Category::ALL.len();

    /// The name used in reports (`snake_case`).
    pub const fn name(self) -> &'static str {
        match self {
            Category::VertexFetch => "vertex_fetch",
            Category::IndexFetch => "index_fetch",
            Category::FrameDataWrite => "frame_data_write",
            Category::FrameDataRead => "frame_data_read",
            Category::TileLoad => "tile_load",
            Category::TileStore => "tile_store",
            Category::Resolve => "resolve",
            Category::TextureFetch => "texture_fetch",
            Category::CopyOnWrite => "copy_on_write",
            Category::TransformFeedbackWrite => "transform_feedback_write",
            Category::Display => "display",
            Category::Composition => "composition",
            Category::ImrClear => "imr_clear",
            Category::ImrColorRead => "imr_color_read",
            Category::ImrColorWrite => "imr_color_write",
            Category::ImrDepthRead => "imr_depth_read",
            Category::ImrDepthWrite => "imr_depth_write",
            Category::ImrStencilRead => "imr_stencil_read",
            Category::ImrStencilWrite => "imr_stencil_write",
        }
    }
}

/// Bytes of external-memory traffic per category.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Ledger {
    bytes: [u64; Category::COUNT],
}

impl Ledger {
    #[inline(always)]
    pub fn add(&mut self, category: Category, bytes: u64) {
        self.bytes[category as usize] += bytes;
    }

    pub fn get(&self, category: Category) -> u64 {
        self.bytes[category as usize]
    }

    /// All bytes, every category.
    pub fn total(&self) -> u64 {
        self.bytes.iter().sum()
    }

    /// Bytes read from external memory.
    pub fn read_bytes(&self) -> u64 {
        use Category::*;
        [
            VertexFetch,
            IndexFetch,
            FrameDataRead,
            TileLoad,
            TextureFetch,
            Display,
            ImrColorRead,
            ImrDepthRead,
            ImrStencilRead,
        ]
        .iter()
        .map(|c| self.get(*c))
        .sum()
    }

    /// Bytes of geometry: vertex and index fetch, frame data written and read.
    pub fn geometry_bytes(&self) -> u64 {
        use Category::*;
        [VertexFetch, IndexFetch, FrameDataWrite, FrameDataRead].iter().map(|c| self.get(*c)).sum()
    }

    /// Bytes written to external memory.
    pub fn written_bytes(&self) -> u64 {
        self.total() - self.read_bytes()
    }

    pub fn merge(&mut self, other: &Ledger) {
        for (a, b) in self.bytes.iter_mut().zip(other.bytes) {
            *a += b;
        }
    }

    /// Categories with their bytes, in the order of [`Category::ALL`].
    pub fn iter(&self) -> impl Iterator<Item = (Category, u64)> + '_ {
        Category::ALL.iter().map(|c| (*c, self.get(*c)))
    }
}

impl Serialize for Ledger {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut map = serializer.serialize_map(Some(Category::COUNT))?;
        for (c, b) in self.iter() {
            map.serialize_entry(c.name(), &b)?;
        }
        map.end()
    }
}

/// What the pipeline did in a pass: geometry, binning, tiles and fragments.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Counters {
    pub draws: u64,
    pub vertices_shaded: u64,
    /// Triangles assembled from the draws.
    pub triangles_in: u64,
    /// Dropped for facing the culled way.
    pub triangles_culled: u64,
    /// Dropped for having zero area or covering no sample position.
    pub triangles_degenerate: u64,
    /// Dropped for lying wholly outside the clip volume.
    pub triangles_clip_rejected: u64,
    /// Triangles that crossed a clip plane and were cut (each may give several primitives).
    pub triangles_clipped: u64,
    /// Primitives set up and written to the frame data (immediate mode: rasterized).
    pub primitives: u64,
    pub polygon_list_entries: u64,
    pub tiles_processed: u64,
    /// Flushes forced by the frame-data budget (each stores and reloads every attachment).
    pub incremental_renders: u64,
    /// Flushes at subpass dependencies that are not by-region (the pass split in two there).
    pub subpass_splits: u64,
    /// Pixels with at least one covered sample, per primitive.
    pub fragments_rasterized: u64,
    /// Fragments rejected by the depth or stencil test before shading (early-Z).
    pub fragments_early_z_killed: u64,
    /// Fragments the fragment shader ran for (helper lanes not included).
    pub fragments_shaded: u64,
    /// Helper lanes shaded only to complete 2×2 quads.
    pub helper_invocations: u64,
    pub fragments_discarded: u64,
    /// Fragments rejected by the depth or stencil test after shading.
    pub fragments_late_killed: u64,
    /// Fragments that passed every test and reached blending.
    pub fragments_passed: u64,
    /// Hidden-surface removal: fragments that passed the tests but were hidden by a later
    /// surface before being shaded.
    pub fragments_hsr_killed: u64,
    /// Hidden-surface removal: fragments rendered in submission order instead, by reason.
    pub hsr_fallback: HsrFallbacks,
    /// Texels the texture units read, each a lookup in the texture cache, hit or miss
    /// (a bilinear sample reads 4, a trilinear one 8). For the time estimate.
    pub texels_read: u64,
    /// Samples written through blending: per draw, its samples that passed the depth and
    /// stencil tests × its colour targets that blend. For the time estimate.
    pub samples_blended: u64,
    /// Quads that read a texture's level 0 minified more than 2× with a sampler that has no
    /// mip maps (GL `NEAREST`/`LINEAR` minification), each one lookup of its footprint.
    pub quads_minified_unmipped: u64,
    /// The bytes those quads fetched from external memory (part of `texture_fetch`): what
    /// mip maps would mostly save (seed 004 §24.3.5).
    pub texture_fetch_minified_unmipped: u64,
}

impl Counters {
    pub fn merge(&mut self, o: &Counters) {
        let Counters {
            draws,
            vertices_shaded,
            triangles_in,
            triangles_culled,
            triangles_degenerate,
            triangles_clip_rejected,
            triangles_clipped,
            primitives,
            polygon_list_entries,
            tiles_processed,
            incremental_renders,
            subpass_splits,
            fragments_rasterized,
            fragments_early_z_killed,
            fragments_shaded,
            helper_invocations,
            fragments_discarded,
            fragments_late_killed,
            fragments_passed,
            fragments_hsr_killed,
            hsr_fallback,
            texels_read,
            samples_blended,
            quads_minified_unmipped,
            texture_fetch_minified_unmipped,
        } = self;
        *draws += o.draws;
        *vertices_shaded += o.vertices_shaded;
        *triangles_in += o.triangles_in;
        *triangles_culled += o.triangles_culled;
        *triangles_degenerate += o.triangles_degenerate;
        *triangles_clip_rejected += o.triangles_clip_rejected;
        *triangles_clipped += o.triangles_clipped;
        *primitives += o.primitives;
        *polygon_list_entries += o.polygon_list_entries;
        *tiles_processed += o.tiles_processed;
        *incremental_renders += o.incremental_renders;
        *subpass_splits += o.subpass_splits;
        *fragments_rasterized += o.fragments_rasterized;
        *fragments_early_z_killed += o.fragments_early_z_killed;
        *fragments_shaded += o.fragments_shaded;
        *helper_invocations += o.helper_invocations;
        *fragments_discarded += o.fragments_discarded;
        *fragments_late_killed += o.fragments_late_killed;
        *fragments_passed += o.fragments_passed;
        *fragments_hsr_killed += o.fragments_hsr_killed;
        hsr_fallback.merge(&o.hsr_fallback);
        *texels_read += o.texels_read;
        *samples_blended += o.samples_blended;
        *quads_minified_unmipped += o.quads_minified_unmipped;
        *texture_fetch_minified_unmipped += o.texture_fetch_minified_unmipped;
    }
}

/// What one draw did, across every tile: for occlusion queries and per-draw reports.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct DrawStats {
    pub primitives: u64,
    pub fragments_shaded: u64,
    /// Samples that passed the depth and stencil tests (what an occlusion query counts).
    pub samples_passed: u64,
    /// Its share of [`Counters::quads_minified_unmipped`].
    pub quads_minified_unmipped: u64,
    /// Its share of [`Counters::texture_fetch_minified_unmipped`].
    pub texture_fetch_minified_unmipped: u64,
}

impl DrawStats {
    pub fn merge(&mut self, o: &DrawStats) {
        self.primitives += o.primitives;
        self.fragments_shaded += o.fragments_shaded;
        self.samples_passed += o.samples_passed;
        self.quads_minified_unmipped += o.quads_minified_unmipped;
        self.texture_fetch_minified_unmipped += o.texture_fetch_minified_unmipped;
    }
}

/// Adds per-draw stats `from` into `into`, growing it as needed.
pub fn merge_draw_stats(into: &mut Vec<DrawStats>, from: &[DrawStats]) {
    if into.len() < from.len() {
        into.resize(from.len(), DrawStats::default());
    }
    for (a, b) in into.iter_mut().zip(from) {
        a.merge(b);
    }
}

/// What one tile cost, for heat maps.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct TileStats {
    /// Polygon-list entries of the tile (summed over incremental renders).
    pub list_entries: u32,
    pub fragments_shaded: u32,
    pub bytes_loaded: u64,
    pub bytes_stored: u64,
}

/// Counters and ledger of one task (a tile, a band), merged into the pass report.
#[derive(Clone, Debug, Default)]
pub struct TaskTally {
    pub counters: Counters,
    pub ledger: Ledger,
}

impl TaskTally {
    pub fn merge(&mut self, other: &TaskTally) {
        self.counters.merge(&other.counters);
        self.ledger.merge(&other.ledger);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_formula_is_its_variants_doc_comment_on_one_line() {
        assert_eq!(
            Category::VertexFetch.formula(),
            "Vertex attributes read: the vertex cache's line fills as the vertices shaded are fetched, in shading \
             order: `lines filled × line size` (`geometry::fetch`; without a cache, `vertices shaded × Σ attribute \
             sizes`)."
        );
        assert!(Category::TileStore.formula().starts_with("Attachments written from the tile buffer by"));
        for category in Category::ALL {
            let formula = category.formula();
            assert!(!formula.is_empty() && !formula.contains('\n'), "{category:?}: {formula:?}");
        }
    }
}
