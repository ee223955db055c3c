//! What the backends share: the images a pass touches, and views of them cut into bands of
//! rows. (Validation, at the front door, is `pass::resolved`.)

use crate::api::image::Image;
use crate::raster::target::Surface;

pub use crate::api::render_pass::{MAX_INPUT_ATTACHMENTS, ResolvedSubpass};
pub use crate::pass::resolved::{ResolveTarget, ResolvedAttachment, ResolvedPass};

/// Mutable references to the images a pass touches, in the order of
/// [`ResolvedPass::memory_images`]: attachments, then resolve targets.
pub fn attachment_images<'a>(images: &'a mut [Image], pass: &ResolvedPass) -> Vec<&'a mut Image> {
    let wanted = pass.memory_images();
    let mut out: Vec<Option<&'a mut Image>> = wanted.iter().map(|_| None).collect();
    for (index, image) in images.iter_mut().enumerate() {
        if let Some(slot) = wanted.iter().position(|w| *w == index) {
            out[slot] = Some(image);
        }
    }
    out.into_iter().map(|i| i.expect("validated attachment")).collect()
}

/// Cuts an image into bands of `rows` rows: for each band, one slice per sample plane.
/// A transient image (no memory) gives no bands.
pub fn image_bands(image: &mut Image, rows: usize) -> Vec<Vec<&mut [u8]>> {
    data_bands(&image.desc, &mut image.data, rows)
}

/// [`image_bands`] over an image's description and data, borrowed apart.
pub fn data_bands<'a>(desc: &crate::ImageDesc, data: &'a mut [u8], rows: usize) -> Vec<Vec<&'a mut [u8]>> {
    if data.is_empty() || desc.transient {
        return Vec::new();
    }
    let plane = desc.plane_bytes();
    let band_bytes = desc.width as usize * desc.format.bytes_per_sample() * rows;
    let mut planes: Vec<_> = data.chunks_mut(plane).map(|p| p.chunks_mut(band_bytes)).collect();
    let bands = (desc.height as usize).div_ceil(rows);
    (0..bands).map(|_| planes.iter_mut().map(|p| p.next().expect("band")).collect()).collect()
}

/// A surface over one band of an image.
pub fn band_surface<'a>(
    image_format: crate::Format,
    width: u32,
    band_y0: i32,
    slices: Vec<&'a mut [u8]>,
) -> Surface<'a> {
    Surface::new(image_format, (0, band_y0), width as usize, slices)
}
