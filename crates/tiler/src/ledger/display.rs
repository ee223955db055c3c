//! Presenting a frame: the display controller scans it out, and a window system may compose
//! it first (seed 004 §24.3.2).
//!
//! Formulas, per presented frame of `width × height` pixels of `b` bytes: scan-out reads the
//! frame once, `Display = width × height × b`; composition reads it and writes the composited
//! framebuffer, `Composition = 2 × width × height × b` (so with composition the display
//! path is three full-screen accesses, as the seed counts).

use serde::{Deserialize, Serialize};

use super::{Category, Ledger};

/// What happens to a frame after it is finished.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct DisplayModel {
    /// The display controller reads each presented frame.
    pub scan_out: bool,
    /// A compositor reads the frame and writes the screen's framebuffer.
    pub composition: bool,
}

impl DisplayModel {
    /// The traffic of presenting one frame.
    pub fn present(&self, width: u32, height: u32, bytes_per_pixel: u32) -> Ledger {
        let frame = width as u64 * height as u64 * bytes_per_pixel as u64;
        let mut ledger = Ledger::default();
        if self.scan_out {
            ledger.add(Category::Display, frame);
        }
        if self.composition {
            ledger.add(Category::Composition, 2 * frame);
        }
        ledger
    }
}
