//! Time: an estimate of how long a pass or a frame takes on a device, and which stage bounds
//! it, from the counters and the ledger. It is a model with stated assumptions, not a
//! measurement, written as `docs/time-model.md` explains:
//!
//! ```text
//! rate(x)        = clock_mhz × 10⁶ × cores × x_per_clock          (per second)
//! geometry time  = vertices shaded / rate(vertices)
//! fragment time  = max( (fragments shaded + helper invocations) / rate(pixels),
//!                       texels read / 4 / rate(texels),
//!                       samples blended / rate(blended samples) )
//! memory time    = external bytes / (bandwidth_gb_per_s × 10⁹)
//! frame time     = max(geometry, fragment, memory)                 (the bound: the largest)
//! bandwidth used = external bytes × frames per second / (bandwidth_gb_per_s × 10⁹)
//! ```
//!
//! The stages are assumed to overlap perfectly (a GPU runs them as a pipeline, a tiler even
//! across frames), so the frame takes as long as its slowest stage: a lower bound. Shader
//! length (ALU cycles), rasterizer and setup limits, cache latency, DVFS and the bandwidth the
//! CPU and display take are left out; each stage runs at its peak rate.

use serde::{Deserialize, Serialize};

use super::{Counters, Ledger};

/// The most frames in flight a device may have.
pub const MAX_FRAMES_IN_FLIGHT: u32 = 16;

/// A device's clock, cores, per-core throughput and external bandwidth: the figures of the
/// time estimate. Presets give the public source of each.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeModel {
    /// Shader-core clock, MHz.
    pub clock_mhz: f64,
    /// Shader cores (Mali cores, Adreno SPs, PowerVR clusters, NVIDIA SMs).
    pub cores: u32,
    /// Vertices shaded per clock per core.
    pub vertices_per_clock: f64,
    /// Fragments (pixels) shaded per clock per core.
    pub pixels_per_clock: f64,
    /// Bilinear-filtered texels per clock per core, the vendors' "texel rate": each reads 4
    /// texels, so the estimate divides the texels read by 4 (a trilinear sample takes two
    /// bilinear steps, a point sample a quarter of one).
    pub texels_per_clock: f64,
    /// Samples blended per clock per core.
    pub blended_samples_per_clock: f64,
    /// External memory bandwidth, GB/s (10⁹ bytes per second).
    pub bandwidth_gb_per_s: f64,
    /// Frames the GPU works on at once behind the CPU (seed 000 §23.6): a tiler's extra
    /// stage (geometry of one frame while the tiles of the previous one are shaded) makes it
    /// 3, an immediate-mode GPU 2. Read-backs and queries wait that many frames.
    pub frames_in_flight: u32,
}

impl Default for TimeModel {
    /// The figures of the `mali-g710` preset (a Mali Valhall tiler, as the default device is);
    /// its file gives their sources.
    fn default() -> TimeModel {
        TimeModel {
            clock_mhz: 848.0,
            cores: 7,
            vertices_per_clock: 2.0,
            pixels_per_clock: 4.0,
            texels_per_clock: 8.0,
            blended_samples_per_clock: 4.0,
            bandwidth_gb_per_s: 51.2,
            frames_in_flight: 3,
        }
    }
}

/// The stage that takes longest.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stage {
    Geometry,
    Fragment,
    Memory,
}

impl Stage {
    pub const fn name(self) -> &'static str {
        match self {
            Stage::Geometry => "geometry",
            Stage::Fragment => "fragment",
            Stage::Memory => "memory",
        }
    }
}

/// The time estimate of a pass or frame, seconds.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TimeEstimate {
    pub geometry_seconds: f64,
    pub fragment_seconds: f64,
    pub memory_seconds: f64,
    /// `max(geometry, fragment, memory)`.
    pub seconds: f64,
    /// The stage whose time is the frame's (the first of geometry, fragment, memory on a tie).
    pub bound: Stage,
}

impl TimeModel {
    /// `per_clock × cores × clock`: events per second of one kind.
    fn rate(&self, per_clock: f64) -> f64 {
        self.clock_mhz * 1e6 * self.cores as f64 * per_clock
    }

    /// External bytes per second the device can move.
    pub fn bytes_per_second(&self) -> f64 {
        self.bandwidth_gb_per_s * 1e9
    }

    /// The time of the work in `counters` and the traffic in `ledger` (see the module's
    /// formulas).
    pub fn estimate(&self, counters: &Counters, ledger: &Ledger) -> TimeEstimate {
        let geometry_seconds = counters.vertices_shaded as f64 / self.rate(self.vertices_per_clock);
        let shading =
            (counters.fragments_shaded + counters.helper_invocations) as f64 / self.rate(self.pixels_per_clock);
        let texturing = counters.texels_read as f64 / 4.0 / self.rate(self.texels_per_clock);
        let blending = counters.samples_blended as f64 / self.rate(self.blended_samples_per_clock);
        let fragment_seconds = shading.max(texturing).max(blending);
        let memory_seconds = ledger.total() as f64 / self.bytes_per_second();
        let (bound, seconds) =
            [(Stage::Geometry, geometry_seconds), (Stage::Fragment, fragment_seconds), (Stage::Memory, memory_seconds)]
                .into_iter()
                .fold((Stage::Geometry, geometry_seconds), |best, next| if next.1 > best.1 { next } else { best });
        TimeEstimate { geometry_seconds, fragment_seconds, memory_seconds, seconds, bound }
    }

    /// The share of the device's bandwidth that `bytes` per frame use at `fps` frames per
    /// second (1 = all of it).
    pub fn bandwidth_share(&self, bytes: u64, fps: f64) -> f64 {
        bytes as f64 * fps / self.bytes_per_second()
    }

    pub fn validate(&self) -> Result<(), String> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        let rates = [
            ("clock_mhz", self.clock_mhz),
            ("vertices_per_clock", self.vertices_per_clock),
            ("pixels_per_clock", self.pixels_per_clock),
            ("texels_per_clock", self.texels_per_clock),
            ("blended_samples_per_clock", self.blended_samples_per_clock),
            ("bandwidth_gb_per_s", self.bandwidth_gb_per_s),
        ];
        if let Some((name, value)) = rates.iter().find(|(_, v)| !positive(*v)) {
            return Err(format!("time: {name} must be finite and above 0, got {value}"));
        }
        if !(1..=4096).contains(&self.cores) {
            return Err(format!("time: cores must be from 1 to 4096, got {}", self.cores));
        }
        if !(1..=MAX_FRAMES_IN_FLIGHT).contains(&self.frames_in_flight) {
            return Err(format!(
                "time: frames_in_flight must be from 1 to {}, got {}",
                MAX_FRAMES_IN_FLIGHT, self.frames_in_flight
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ledger::Category;

    fn model() -> TimeModel {
        TimeModel {
            clock_mhz: 1000.0,
            cores: 2,
            vertices_per_clock: 1.0,
            pixels_per_clock: 4.0,
            texels_per_clock: 8.0,
            blended_samples_per_clock: 2.0,
            bandwidth_gb_per_s: 10.0,
            frames_in_flight: 3,
        }
    }

    #[test]
    fn each_stage_by_hand() {
        let counters = Counters {
            vertices_shaded: 2_000_000,
            fragments_shaded: 7_000_000,
            helper_invocations: 1_000_000,
            texels_read: 128_000_000,
            samples_blended: 2_000_000,
            ..Counters::default()
        };
        let mut ledger = Ledger::default();
        ledger.add(Category::TileStore, 30_000_000);
        let t = model().estimate(&counters, &ledger);
        // 2e6 vertices / (1e9 Hz × 2 cores × 1) = 1 ms.
        assert!((t.geometry_seconds - 1e-3).abs() < 1e-12);
        // Shading 8e6 / 8e9 = 1 ms; texels 128e6 / 4 / 16e9 = 2 ms; blending 2e6 / 4e9 = 0.5 ms.
        assert!((t.fragment_seconds - 2e-3).abs() < 1e-12);
        // 30e6 bytes / 10e9 B/s = 3 ms.
        assert!((t.memory_seconds - 3e-3).abs() < 1e-12);
        assert_eq!((t.seconds, t.bound), (t.memory_seconds, Stage::Memory));
        // 30 MB × 60 frames/s = 1.8 GB/s of 10 GB/s.
        assert!((model().bandwidth_share(30_000_000, 60.0) - 0.18).abs() < 1e-12);
    }

    #[test]
    fn an_idle_frame_is_bound_by_geometry_at_zero() {
        let t = model().estimate(&Counters::default(), &Ledger::default());
        assert_eq!((t.seconds, t.bound), (0.0, Stage::Geometry));
    }

    #[test]
    fn bad_figures_are_refused_by_name() {
        let e = TimeModel { bandwidth_gb_per_s: 0.0, ..model() }.validate().unwrap_err();
        assert!(e.contains("bandwidth_gb_per_s"), "{e}");
        let e = TimeModel { clock_mhz: f64::NAN, ..model() }.validate().unwrap_err();
        assert!(e.contains("clock_mhz"), "{e}");
        let e = TimeModel { cores: 0, ..model() }.validate().unwrap_err();
        assert!(e.contains("cores"), "{e}");
        let e = TimeModel { frames_in_flight: 0, ..model() }.validate().unwrap_err();
        assert!(e.contains("frames_in_flight"), "{e}");
        assert!(TimeModel::default().validate().is_ok());
    }
}
