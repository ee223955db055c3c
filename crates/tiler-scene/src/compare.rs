//! Comparing a render with a reference image: the share of pixels whose every channel is
//! within a tolerance, and a difference image to look at.
//!
//! The reference renders (`../shared/reference`, from llvmpipe) are not expected to match bit
//! for bit: edge rules, filtering details and float order differ between renderers. The bar
//! they set (`../shared/reference/README.md`): at least 99% of pixels within 8/255 per channel.

use std::path::Path;

/// The tolerance of the reference comparisons: 8/255 per channel.
pub const REFERENCE_TOLERANCE: u8 = 8;
/// The share of pixels that must be within the tolerance.
pub const REFERENCE_MIN_FRACTION: f64 = 0.99;

/// The outcome of comparing two RGBA8 images of the same size.
#[derive(Clone, Debug)]
pub struct Comparison {
    pub width: u32,
    pub height: u32,
    pub tolerance: u8,
    /// Pixels whose four channels all differ by at most `tolerance`.
    pub pixels_within: u64,
    /// The largest difference of any channel of any pixel.
    pub max_difference: u8,
    /// RGBA8, rows top to bottom: pixels within the tolerance as a dim grey copy of the
    /// reference, the others red, brighter the larger the difference.
    pub difference_image: Vec<u8>,
}

impl Comparison {
    pub fn pixels(&self) -> u64 {
        self.width as u64 * self.height as u64
    }

    /// The share of pixels within the tolerance, 0 to 1.
    pub fn fraction_within(&self) -> f64 {
        self.pixels_within as f64 / self.pixels().max(1) as f64
    }

    pub fn passes(&self, min_fraction: f64) -> bool {
        self.fraction_within() >= min_fraction
    }
}

/// Compares `ours` with `reference`, both `width × height` RGBA8.
///
/// # Panics
/// If either slice is not `width × height × 4` bytes long.
pub fn compare_rgba8(ours: &[u8], reference: &[u8], width: u32, height: u32, tolerance: u8) -> Comparison {
    let len = width as usize * height as usize * 4;
    assert!(ours.len() == len && reference.len() == len, "images of {width}×{height} need {len} bytes each");
    let mut pixels_within = 0;
    let mut max_difference = 0;
    let mut difference_image = vec![0u8; len];
    for ((a, b), out) in ours.chunks_exact(4).zip(reference.chunks_exact(4)).zip(difference_image.chunks_exact_mut(4)) {
        let diff = (0..4).map(|c| a[c].abs_diff(b[c])).max().unwrap_or(0);
        max_difference = max_difference.max(diff);
        if diff <= tolerance {
            pixels_within += 1;
            let luma = ((b[0] as u32 * 3 + b[1] as u32 * 6 + b[2] as u32) / 10 / 3) as u8;
            out.copy_from_slice(&[luma, luma, luma, 255]);
        } else {
            let level = (64 + diff as u32 * 3).min(255) as u8;
            out.copy_from_slice(&[level, 0, 0, 255]);
        }
    }
    Comparison { width, height, tolerance, pixels_within, max_difference, difference_image }
}

/// The largest picture file read (a 16384² RGBA PNG stored uncompressed is a gigabyte).
pub const MAX_PICTURE_BYTES: u64 = 1 << 30;

/// Reads a PNG as RGBA8, rows top to bottom: a regular file of at most [`MAX_PICTURE_BYTES`],
/// decoded within the image crate's default allocation limit.
///
/// # Errors
/// A file that cannot be read or decoded.
pub fn read_png(path: &Path) -> Result<(u32, u32, Vec<u8>), String> {
    let bytes = tiler_io::read_file(path, MAX_PICTURE_BYTES).map_err(|e| e.to_string())?;
    let image = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| format!("{}: {e}", path.display()))?
        .decode()
        .map_err(|e| format!("{}: {e}", path.display()))?
        .to_rgba8();
    Ok((image.width(), image.height(), image.into_raw()))
}

/// Writes RGBA8 pixels, rows top to bottom, as a PNG (creating the folder if needed),
/// atomically: encoded to a temporary file beside `path` and renamed over it when complete.
///
/// # Errors
/// A file that cannot be written.
pub fn write_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> Result<(), String> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    tiler_io::write_atomic_with(path, |out| {
        use image::ImageEncoder;
        image::codecs::png::PngEncoder::new(out)
            .write_image(rgba, width, height, image::ExtendedColorType::Rgba8)
            .map_err(std::io::Error::other)
    })
    .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_pixels_within_tolerance() {
        let reference = [10, 10, 10, 255, 100, 100, 100, 255];
        let ours = [18, 2, 10, 255, 100, 109, 100, 255];
        let c = compare_rgba8(&ours, &reference, 2, 1, 8);
        assert_eq!(c.pixels_within, 1);
        assert_eq!(c.max_difference, 9);
        assert_eq!(c.fraction_within(), 0.5);
        assert!(!c.passes(0.99));
        assert_eq!(&c.difference_image[4..8], &[64 + 27, 0, 0, 255]);
    }
}
