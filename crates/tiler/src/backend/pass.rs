//! What the backends share, re-exported from where it lives: validation at the front door
//! (`pass::resolved`), the images a pass touches, and views of them cut into bands of rows
//! (`raster::target`).

pub use crate::pass::resolved::{ResolvedAttachment, ResolvedPass, attachment_images};
pub use crate::raster::target::{band_surface, data_bands, image_bands};
