//! How a device is built, as data: its backend, tiles, budgets and cost model
//! ([`DeviceConfig`]), and named presets of it ([`preset`]).

use serde::{Deserialize, Serialize};

pub mod preset;

use crate::api::error::{Error, Result};
use crate::geometry::VertexShading;
use crate::ledger::cache::CacheConfig;
use crate::ledger::display::DisplayModel;
use crate::ledger::energy::EnergyModel;
use crate::ledger::time::TimeModel;
use crate::shade::texture_cache::TextureCacheConfig;
use crate::simd::SimdLevel;

/// The smallest frame-data budget: it must hold at least one chunk of binned triangles.
pub const MIN_FRAME_DATA_BUDGET: u64 = 1 << 20;

/// How a device is built: its backend, tiles, budgets and the cost model. Presets are this,
/// as data (see [`preset`]); every field has a default, so a preset names only
/// what differs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DeviceConfig {
    /// The backend `submit` uses.
    pub backend: Backend,
    /// Tile size in pixels: multiples of 8 from 8 to 256.
    pub tile_width: u32,
    pub tile_height: u32,
    /// Worker threads; 0 = one per available core. Not part of the model.
    #[serde(skip)]
    pub threads: usize,
    /// The instruction set the pixel pipeline uses; `None` = the best this processor has.
    /// Not part of the model: every level renders the same pictures, bit for bit.
    #[serde(skip)]
    pub simd: Option<SimdLevel>,
    /// Bytes of frame data (as modelled, see `binning::frame_data`) before an incremental
    /// render. The default, 64 MiB, is in the range of mobile drivers' tiler heaps and above
    /// llvmpipe's 36 MiB scene limit.
    pub frame_data_budget: u64,
    /// Bytes of tile buffer for one tile: every attachment at every sample must fit, or the
    /// tile shrinks. The default, 32 KiB, is Apple's per-tile budget; 32×32 tiles of RGBA8
    /// and D24S8 at 4× MSAA fill it exactly.
    pub tile_memory_bytes: u64,
    /// Run the depth and stencil tests before shading when the shader allows it.
    pub early_z: bool,
    /// Where a tiler shades vertices.
    pub vertex_shading: VertexShading,
    /// Entries of the post-transform vertex cache (FIFO) that saves re-shading and
    /// re-fetching vertices shared by nearby triangles of an indexed draw; 0 = none. The
    /// default, 32, is the size commonly cited for mobile and desktop GPUs.
    pub post_transform_cache: u32,
    /// The vertex cache attribute fetches go through: `VertexFetch` counts its line fills, so
    /// attribute layouts cost the lines they touch. The default, 4 KiB of 64-byte lines in 4
    /// ways, is an assumption (a small L1 of the fetch path; vendors do not publish it); a
    /// size of 0 counts each attribute's exact bytes.
    pub vertex_cache: CacheConfig,
    /// The framebuffer cache of an immediate-mode GPU (its ROP/L2 share for colour and
    /// depth); size 0 = every access goes to memory, as the seeds' arithmetic assumes.
    pub framebuffer_cache: CacheConfig,
    /// The texture cache in front of every texture read (see `shade::texture_cache`).
    pub texture_cache: TextureCacheConfig,
    /// Picojoules per byte, for the energy estimate.
    pub energy: EnergyModel,
    /// Clock, cores, per-core throughput and bandwidth, for the time estimate
    /// (`ledger::time`); the default is a Mali-G710 MC7's.
    pub time: TimeModel,
    /// What presenting a frame costs.
    pub display: DisplayModel,
    /// Skip storing a tile whose content has not changed since the last frame (Arm's
    /// transaction elimination); the bytes saved are reported.
    pub transaction_elimination: bool,
    /// Record fragments shaded per pixel (for overdraw maps).
    pub overdraw_map: bool,
}

impl Default for DeviceConfig {
    fn default() -> DeviceConfig {
        DeviceConfig {
            backend: Backend::Tbr,
            tile_width: 32,
            tile_height: 32,
            threads: 0,
            simd: None,
            frame_data_budget: 64 << 20,
            tile_memory_bytes: 32 << 10,
            early_z: true,
            vertex_shading: VertexShading::Once,
            post_transform_cache: 32,
            vertex_cache: CacheConfig { size_bytes: 4096, line_bytes: 64, ways: 4 },
            framebuffer_cache: CacheConfig::NONE,
            texture_cache: TextureCacheConfig::DEFAULT,
            energy: EnergyModel::default(),
            time: TimeModel::default(),
            display: DisplayModel { scan_out: true, composition: false },
            transaction_elimination: false,
            overdraw_map: false,
        }
    }
}

impl DeviceConfig {
    /// Square tiles of `size` pixels.
    pub fn with_tile_size(self, size: u32) -> DeviceConfig {
        DeviceConfig { tile_width: size, tile_height: size, ..self }
    }

    /// Checks every field.
    ///
    /// # Errors
    /// A field outside its range, naming it.
    pub fn validate(&self) -> Result<()> {
        let fail = |reason: String| Err(Error::invalid("device config", reason));
        for (name, v) in [("tile width", self.tile_width), ("tile height", self.tile_height)] {
            if !(8..=256).contains(&v) || v % 8 != 0 {
                return fail(format!("{name} {v} must be a multiple of 8 from 8 to 256"));
            }
        }
        if self.frame_data_budget < MIN_FRAME_DATA_BUDGET {
            return fail(format!(
                "frame-data budget {} is below the minimum {MIN_FRAME_DATA_BUDGET} bytes",
                self.frame_data_budget
            ));
        }
        if self.tile_memory_bytes < 256 {
            return fail(format!("tile memory {} bytes is below 256 bytes", self.tile_memory_bytes));
        }
        if self.threads > 1024 {
            return fail(format!("{} threads is more than 1024", self.threads));
        }
        if self.post_transform_cache > 4096 {
            return fail(format!("a post-transform cache of {} entries is more than 4096", self.post_transform_cache));
        }
        self.vertex_cache.validate("vertex cache").or_else(fail)?;
        self.framebuffer_cache.validate("framebuffer cache").or_else(fail)?;
        self.texture_cache.validate()?;
        self.energy.validate().or_else(fail)?;
        self.time.validate().or_else(fail)?;
        Ok(())
    }
}

/// How a render pass is executed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Backend {
    /// Tile-based rendering with early-Z: tiles shade their lists in submission order.
    #[default]
    Tbr,
    /// Tile-based deferred rendering: hidden-surface removal before shading.
    Tbdr,
    /// Immediate-mode rendering into external memory.
    Imr,
}

impl Backend {
    pub const ALL: [Backend; 3] = [Backend::Tbr, Backend::Tbdr, Backend::Imr];

    pub const fn name(self) -> &'static str {
        match self {
            Backend::Tbr => "tbr",
            Backend::Tbdr => "tbdr",
            Backend::Imr => "imr",
        }
    }

    pub const fn is_tiler(self) -> bool {
        matches!(self, Backend::Tbr | Backend::Tbdr)
    }

    /// Frames a GPU of this kind works on at once behind the CPU (seed 000 §23.6): a tiler's
    /// geometry and fragment stages each hold a frame besides the CPU's, 3; an immediate-mode
    /// GPU has one stage, 2. Read-backs and query results wait that many frames.
    pub const fn frames_in_flight(self) -> u32 {
        if self.is_tiler() { 3 } else { 2 }
    }
}

impl std::fmt::Display for Backend {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Backend {
    type Err = String;
    fn from_str(s: &str) -> Result<Backend, String> {
        Backend::ALL
            .into_iter()
            .find(|b| b.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| format!("unknown backend '{s}' (expected one of: tbr, tbdr, imr)"))
    }
}
