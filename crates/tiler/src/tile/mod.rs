//! The tile phase: the tile grid, the tile buffer, load and store ops, and the views through
//! which the pixel pipeline reaches an attachment (in the tile buffer, or in external memory
//! for immediate mode).

pub mod buffer;
pub mod list;
pub mod load_store;
pub mod task;

pub use crate::binning::grid;
