//! Images in external memory: their description, limits and memory layout.

use super::error::{Error, Result};
use super::format::Format;

/// The largest width or height of an image, in pixels. It bounds the fixed-point range the
/// rasterizer must handle (see `raster::fixed`).
pub const MAX_IMAGE_DIMENSION: u32 = 16384;

/// The largest image, in bytes over all its samples: 1 GiB. Larger requests are refused rather
/// than allowed to exhaust memory.
pub const MAX_IMAGE_BYTES: u64 = 1 << 30;

/// The sample counts an image may declare.
pub const SUPPORTED_SAMPLE_COUNTS: [u32; 5] = [1, 2, 4, 8, 16];

/// What an image is: its size, format, samples per pixel, and whether it is transient.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ImageDesc {
    pub width: u32,
    pub height: u32,
    pub format: Format,
    pub samples: u32,
    /// A transient image has no backing memory (Vulkan's lazily allocated memory): it exists
    /// only in the tile buffer, so it may not be loaded or stored.
    pub transient: bool,
}

impl ImageDesc {
    /// A single-sample image with backing memory.
    pub fn new(width: u32, height: u32, format: Format) -> ImageDesc {
        ImageDesc { width, height, format, samples: 1, transient: false }
    }

    pub fn with_samples(self, samples: u32) -> ImageDesc {
        ImageDesc { samples, ..self }
    }

    pub fn transient(self) -> ImageDesc {
        ImageDesc { transient: true, ..self }
    }

    /// Bytes of one sample plane (`width × height × bytes_per_sample`).
    pub fn plane_bytes(&self) -> usize {
        self.width as usize * self.height as usize * self.format.bytes_per_sample()
    }

    /// Bytes of the whole image (all sample planes).
    pub fn size_bytes(&self) -> u64 {
        self.plane_bytes() as u64 * self.samples as u64
    }

    /// Checks the limits above.
    ///
    /// # Errors
    /// A zero or too large dimension, an unsupported sample count, or more than
    /// [`MAX_IMAGE_BYTES`].
    pub fn validate(&self) -> Result<()> {
        let (width, height) = (self.width, self.height);
        if width == 0 || height == 0 {
            return Err(Error::ImageSize { width, height, reason: "width and height must be at least 1".into() });
        }
        if width > MAX_IMAGE_DIMENSION || height > MAX_IMAGE_DIMENSION {
            return Err(Error::ImageSize {
                width,
                height,
                reason: format!("the largest supported dimension is {MAX_IMAGE_DIMENSION}"),
            });
        }
        if !SUPPORTED_SAMPLE_COUNTS.contains(&self.samples) {
            return Err(Error::SampleCount { samples: self.samples });
        }
        if self.size_bytes() > MAX_IMAGE_BYTES {
            return Err(Error::ImageSize {
                width,
                height,
                reason: format!(
                    "{} bytes with {} samples of {} exceeds the limit of {MAX_IMAGE_BYTES} bytes",
                    self.size_bytes(),
                    self.samples,
                    self.format
                ),
            });
        }
        Ok(())
    }
}

/// A handle to an image owned by a [`Device`](crate::Device).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize)]
pub struct ImageId(pub(crate) u32);

impl std::fmt::Display for ImageId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "image {}", self.0)
    }
}

/// An image's storage in external memory.
///
/// Layout: sample planes one after another; each plane is `height` rows top to bottom, each
/// row `width` samples left to right, `bytes_per_sample` bytes each:
/// byte offset of (x, y, sample s) = `((s · height + y) · width + x) · bytes_per_sample`.
/// A transient image has no storage (`data` is empty).
#[derive(Clone, Debug)]
pub struct Image {
    pub desc: ImageDesc,
    pub data: Vec<u8>,
    /// Transaction elimination: a signature of each tile's content as a tiler last stored it,
    /// valid only while nothing else has written the image.
    pub signatures: Option<TileSignatures>,
}

impl Image {
    pub fn new(desc: ImageDesc) -> Result<Image> {
        desc.validate()?;
        let data =
            if desc.transient { Vec::new() } else { crate::huge_pages::zeroed_bytes(desc.size_bytes() as usize) };
        Ok(Image { desc, data, signatures: None })
    }
}

/// Signatures of an image's tiles for one tile grid (Arm's transaction elimination keeps a
/// CRC per tile; tiler a 64-bit hash). [`TileSignatures::UNKNOWN`] marks a tile never stored.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TileSignatures {
    pub tile_width: u32,
    pub tile_height: u32,
    pub hashes: Vec<u64>,
}

impl TileSignatures {
    pub const UNKNOWN: u64 = 0;

    /// A 64-bit hash of bytes (multiply-rotate over 8-byte words); never [`Self::UNKNOWN`].
    pub fn hash(mut state: u64, bytes: &[u8]) -> u64 {
        const K: u64 = 0x9e37_79b9_7f4a_7c15;
        let (words, rest) = bytes.as_chunks::<8>();
        for w in words {
            state = (state ^ u64::from_le_bytes(*w)).wrapping_mul(K).rotate_left(29);
        }
        for b in rest {
            state = (state ^ *b as u64).wrapping_mul(K).rotate_left(29);
        }
        if state == Self::UNKNOWN { 1 } else { state }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_are_enforced() {
        assert!(ImageDesc::new(0, 10, Format::Rgba8Unorm).validate().is_err());
        assert!(ImageDesc::new(16385, 10, Format::Rgba8Unorm).validate().is_err());
        assert!(ImageDesc::new(16384, 16384, Format::Rgba32Float).validate().is_err());
        assert!(ImageDesc::new(64, 64, Format::Rgba8Unorm).with_samples(3).validate().is_err());
        assert!(ImageDesc::new(1920, 1080, Format::Rgba8Unorm).with_samples(8).validate().is_ok());
        assert!(ImageDesc::new(1920, 1080, Format::Rgba8Unorm).with_samples(16).validate().is_ok());
        assert!(ImageDesc::new(64, 64, Format::Rgba8Unorm).with_samples(32).validate().is_err());
    }
}
