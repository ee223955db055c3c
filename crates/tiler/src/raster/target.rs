//! Views of an attachment for the pixel pipeline: where sample `s` of pixel `(x, y)` lives,
//! whether in a tile buffer or in a band of an image in external memory.

use crate::api::format::Format;
use crate::api::image::{Image, ImageDesc};
use crate::api::pipeline::MAX_COLOR_ATTACHMENTS;
use crate::api::render_pass::{MAX_INPUT_ATTACHMENTS, ResolvedSubpass};
use crate::raster::PixelRect;
use crate::raster::samples::{MAX_SAMPLES, SampleLocations};

/// A rectangle of one attachment, every sample plane of it: pixel `(x, y)` of sample `s` is at
/// byte `((y − origin_y) · stride + (x − origin_x)) · bytes_per_sample` of plane `s`.
pub struct Surface<'a> {
    pub format: Format,
    planes: [&'a mut [u8]; MAX_SAMPLES],
    samples: usize,
    origin_x: i32,
    origin_y: i32,
    /// Pixels per row.
    stride: usize,
    bytes_per_sample: usize,
    /// For an image in external memory: the address of this view's first byte and the bytes
    /// between sample planes (cache models need addresses).
    memory: Option<(u64, u64)>,
}

impl<'a> Surface<'a> {
    /// A view of `planes` (one slice per sample) whose first byte is pixel `origin`.
    pub fn new(
        format: Format,
        origin: (i32, i32),
        stride: usize,
        planes: impl IntoIterator<Item = &'a mut [u8]>,
    ) -> Surface<'a> {
        let mut array: [&'a mut [u8]; MAX_SAMPLES] = Default::default();
        let mut samples = 0;
        for (slot, plane) in array.iter_mut().zip(planes) {
            *slot = plane;
            samples += 1;
        }
        Surface {
            format,
            planes: array,
            samples,
            origin_x: origin.0,
            origin_y: origin.1,
            stride,
            bytes_per_sample: format.bytes_per_sample(),
            memory: None,
        }
    }

    /// Gives the view addresses: its first byte is at `base`, planes `plane_bytes` apart.
    pub fn with_memory(self, base: u64, plane_bytes: u64) -> Surface<'a> {
        Surface { memory: Some((base, plane_bytes)), ..self }
    }

    /// The external-memory address of sample `s` of pixel `(x, y)` (0 for on-chip views).
    #[inline(always)]
    pub fn address(&self, sample: usize, x: i32, y: i32) -> u64 {
        match self.memory {
            Some((base, plane)) => base + sample as u64 * plane + self.offset(x, y) as u64,
            None => 0,
        }
    }

    pub fn samples(&self) -> usize {
        self.samples
    }

    pub fn bytes_per_sample(&self) -> usize {
        self.bytes_per_sample
    }

    /// Byte offset of pixel `(x, y)` within a plane.
    #[inline(always)]
    pub fn offset(&self, x: i32, y: i32) -> usize {
        debug_assert!(x >= self.origin_x && y >= self.origin_y);
        ((y - self.origin_y) as usize * self.stride + (x - self.origin_x) as usize) * self.bytes_per_sample
    }

    #[inline(always)]
    pub fn plane(&self, sample: usize) -> &[u8] {
        self.planes[sample]
    }

    #[inline(always)]
    pub fn plane_mut(&mut self, sample: usize) -> &mut [u8] {
        self.planes[sample]
    }

    /// The bytes of pixels `x0..x1` of row `y` in plane `sample`.
    #[inline]
    pub fn row(&self, sample: usize, y: i32, x0: i32, x1: i32) -> &[u8] {
        let start = self.offset(x0, y);
        &self.planes[sample][start..start + (x1 - x0) as usize * self.bytes_per_sample]
    }

    #[inline]
    pub fn row_mut(&mut self, sample: usize, y: i32, x0: i32, x1: i32) -> &mut [u8] {
        let start = self.offset(x0, y);
        let len = (x1 - x0) as usize * self.bytes_per_sample;
        &mut self.planes[sample][start..start + len]
    }

    /// Whether columns `x0..x1` all lie in this view's rows.
    #[inline(always)]
    pub fn holds_columns(&self, x0: i32, x1: i32) -> bool {
        x0 >= self.origin_x && x1 <= self.origin_x + self.stride as i32
    }

    /// Whether pixel `(x, y)` lies in this view.
    #[inline(always)]
    pub fn contains(&self, x: i32, y: i32) -> bool {
        let rows = self.planes[0].len() / (self.stride * self.bytes_per_sample).max(1);
        x >= self.origin_x
            && y >= self.origin_y
            && ((x - self.origin_x) as usize) < self.stride
            && ((y - self.origin_y) as usize) < rows
    }

    /// Whether this view is of external memory (an image), not of the tile buffer.
    pub fn is_external(&self) -> bool {
        self.memory.is_some()
    }
}

/// What the pixel pipeline reads and writes for one primitive of a subpass, and where it may
/// write: the subpass's colour outputs and depth-stencil attachment, and its input attachments
/// (read only), borrowed from a tile's (or a band's) views of every attachment of the pass.
pub struct RenderTarget<'t, 'a> {
    pub color: [Option<&'t mut Surface<'a>>; MAX_COLOR_ATTACHMENTS],
    pub depth_stencil: Option<&'t mut Surface<'a>>,
    pub inputs: [Option<&'t Surface<'a>>; MAX_INPUT_ATTACHMENTS],
    pub samples: SampleLocations,
    /// The pixels this target holds (a tile, or a band of the framebuffer) ∩ the render area.
    pub clip: PixelRect,
    /// Whether depth and stencil tests may run before shading (the device's early-Z).
    pub early_z: bool,
}

impl<'t, 'a> RenderTarget<'t, 'a> {
    /// The target of `subpass` over `surfaces`, one view per attachment of the pass.
    pub fn for_subpass(
        surfaces: &'t mut [Surface<'a>],
        subpass: &ResolvedSubpass,
        samples: SampleLocations,
        clip: PixelRect,
        early_z: bool,
    ) -> RenderTarget<'t, 'a> {
        let mut color: [Option<&'t mut Surface<'a>>; MAX_COLOR_ATTACHMENTS] = Default::default();
        let mut depth_stencil = None;
        let mut inputs: [Option<&'t Surface<'a>>; MAX_INPUT_ATTACHMENTS] = Default::default();
        for (index, surface) in surfaces.iter_mut().enumerate() {
            if let Some(slot) = subpass.color.iter().position(|c| *c == index) {
                color[slot] = Some(surface);
            } else if subpass.depth_stencil == Some(index) {
                depth_stencil = Some(surface);
            } else if let Some(slot) = subpass.inputs.iter().position(|c| *c == index) {
                inputs[slot] = Some(surface);
            }
        }
        RenderTarget { color, depth_stencil, inputs, samples, clip, early_z }
    }
}

/// Cuts an image into bands of `rows` rows: for each band, one slice per sample plane.
/// A transient image (no memory) gives no bands.
pub fn image_bands(image: &mut Image, rows: usize) -> Vec<Vec<&mut [u8]>> {
    data_bands(&image.desc, &mut image.data, rows)
}

/// [`image_bands`] over an image's description and data, borrowed apart.
pub fn data_bands<'a>(desc: &ImageDesc, data: &'a mut [u8], rows: usize) -> Vec<Vec<&'a mut [u8]>> {
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
pub fn band_surface<'a>(image_format: Format, width: u32, band_y0: i32, slices: Vec<&'a mut [u8]>) -> Surface<'a> {
    Surface::new(image_format, (0, band_y0), width as usize, slices)
}
