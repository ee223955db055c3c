//! A frame: the render passes between two presents, what presenting it costs, and the totals
//! a report shows — bytes, bytes per second, energy, time.

use serde::Serialize;

use crate::backend::PassReport;
use crate::ledger::energy::{EnergyEstimate, EnergyModel};
use crate::ledger::time::{TimeEstimate, TimeModel};
use crate::ledger::{Counters, Ledger};

/// What one frame cost.
#[derive(Clone, Debug, Default, Serialize)]
pub struct FrameCost {
    pub passes: Vec<PassReport>,
    /// Display scan-out and composition of the presented image ([`crate::Device::present`]).
    pub present: Ledger,
    /// Costs a driver adds outside render passes (copy-on-write of resources in use).
    pub driver: Ledger,
}

impl FrameCost {
    pub fn new(passes: Vec<PassReport>) -> FrameCost {
        FrameCost { passes, ..FrameCost::default() }
    }

    /// Every external-memory byte of the frame, by category.
    pub fn ledger(&self) -> Ledger {
        let mut ledger = self.present;
        ledger.merge(&self.driver);
        for pass in &self.passes {
            ledger.merge(&pass.ledger);
        }
        ledger
    }

    /// Bytes moved within on-chip memory.
    pub fn on_chip_bytes(&self) -> u64 {
        self.passes.iter().map(|p| p.on_chip_bytes).sum()
    }

    pub fn counters(&self) -> Counters {
        let mut counters = Counters::default();
        for pass in &self.passes {
            counters.merge(&pass.counters);
        }
        counters
    }

    /// External-memory bandwidth at `fps` frames per second, bytes per second.
    pub fn bytes_per_second(&self, fps: f64) -> f64 {
        self.ledger().total() as f64 * fps
    }

    /// The energy estimate of the frame under `model`.
    pub fn energy(&self, model: &EnergyModel) -> EnergyEstimate {
        model.estimate(self.ledger().total(), self.on_chip_bytes())
    }

    /// The time estimate of the frame under `model`: its passes' work and every byte of the
    /// frame, presenting and the driver's copies included.
    pub fn time(&self, model: &TimeModel) -> TimeEstimate {
        model.estimate(&self.counters(), &self.ledger())
    }
}
