//! Energy: an estimate from bytes moved, per memory level. It is a model with stated
//! assumptions, not a measurement: energy = external bytes × pJ/byte of DRAM + on-chip bytes ×
//! pJ/byte of SRAM; power = energy per frame × frames per second. Compute, caches other than
//! those modelled, and static power are left out.

use serde::{Deserialize, Serialize};

/// Picojoules per byte at each memory level.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnergyModel {
    /// External memory (LPDDR). Default 100 pJ/byte: Arm's rule of thumb of 100 mW per GB/s
    /// of DRAM traffic (1 GB/s × 100 pJ/B = 0.1 W).
    pub external_pj_per_byte: f64,
    /// On-chip SRAM (tile buffer, caches). Default 2.5 pJ/byte: about 20 pJ per 64-bit access
    /// to a 32 KiB SRAM (Horowitz, "Computing's energy problem", ISSCC 2014, 45 nm).
    pub on_chip_pj_per_byte: f64,
}

impl Default for EnergyModel {
    fn default() -> EnergyModel {
        EnergyModel { external_pj_per_byte: 100.0, on_chip_pj_per_byte: 2.5 }
    }
}

/// Energy of some traffic.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct EnergyEstimate {
    pub external_joules: f64,
    pub on_chip_joules: f64,
}

impl EnergyModel {
    pub fn estimate(&self, external_bytes: u64, on_chip_bytes: u64) -> EnergyEstimate {
        EnergyEstimate {
            external_joules: external_bytes as f64 * self.external_pj_per_byte * 1e-12,
            on_chip_joules: on_chip_bytes as f64 * self.on_chip_pj_per_byte * 1e-12,
        }
    }

    pub fn validate(&self) -> Result<(), String> {
        let ok = |v: f64| v.is_finite() && v >= 0.0;
        if ok(self.external_pj_per_byte) && ok(self.on_chip_pj_per_byte) {
            Ok(())
        } else {
            Err(format!("energy: picojoules per byte must be finite and non-negative, got {self:?}"))
        }
    }
}

impl EnergyEstimate {
    pub fn total_joules(&self) -> f64 {
        self.external_joules + self.on_chip_joules
    }

    /// Average power in milliwatts at `fps` frames per second.
    pub fn milliwatts(&self, fps: f64) -> f64 {
        self.total_joules() * fps * 1e3
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_gigabyte_per_second_is_a_hundred_milliwatts() {
        let e = EnergyModel::default().estimate(1_000_000_000 / 60, 0);
        assert!((e.milliwatts(60.0) - 100.0).abs() < 1e-3);
    }
}
