//! The device: owns images and buffers (its external memory), its configuration and its
//! worker threads, and executes render passes.

use crate::api::buffer::{BufferId, MAX_BUFFER_BYTES};
use crate::api::error::{Error, Result};
use crate::api::format::Format;
use crate::api::image::{Image, ImageDesc, ImageId};
use crate::backend::{Backend, PassReport, Workers, imr, tbr};
use crate::config::DeviceConfig;
use crate::ledger::Ledger;
use crate::pass::RenderPass;
use crate::pass::resolved::ResolvedPass;
use crate::simd::SimdSupport;

/// A software GPU: its memory (images, buffers) and its workers.
pub struct Device {
    config: DeviceConfig,
    workers: Workers,
    pool: rayon::ThreadPool,
    images: Vec<Image>,
    /// Per image, the [`Device::image_version`] it has: a new one from `writes` at every
    /// operation that may change its bytes.
    versions: Vec<u64>,
    writes: u64,
    buffers: Vec<Vec<u8>>,
    /// The tilers' frame data and setup batches, kept from pass to pass.
    scratch: tbr::Scratch,
}

/// The processors to pin a pool of `threads` workers to, one each, when the pool has one worker
/// for every processor this process may run on (and more than one): `None` otherwise, or when
/// `TILER_PIN_WORKERS=0`.
///
/// Why: a frame of a capture is a burst of a few milliseconds after the workers slept while
/// the driver translated calls. The kernel wakes a sleeping worker on the processor of the
/// thread that woke it, and for a burst that short it seldom moves it, so on a two-core
/// machine both workers often took turns on one processor in 4 ms time slices while the other
/// idled (glmark2's build and shading captures: 12% longer on the median, bimodal from run to
/// run; docs/benchmarking.md, "Workers pinned"). Pinning keeps one worker per processor. A pool
/// smaller than the machine is not pinned: several such devices (tests run side by side) would
/// all crowd the first processors.
fn pinned_processors(threads: usize) -> Option<Vec<core_affinity::CoreId>> {
    if std::env::var_os("TILER_PIN_WORKERS").is_some_and(|v| v == "0") {
        return None;
    }
    pins(threads, core_affinity::get_core_ids()?)
}

/// [`pinned_processors`] given the processors this process may run on.
fn pins<T>(threads: usize, processors: Vec<T>) -> Option<Vec<T>> {
    (threads >= 2 && processors.len() == threads).then_some(processors)
}

impl Device {
    /// # Errors
    /// An invalid configuration, or when the worker threads cannot be started.
    pub fn new(config: DeviceConfig) -> Result<Device> {
        config.validate()?;
        let mut config = config;
        let simd = match config.simd {
            None => SimdSupport::best(),
            Some(level) => SimdSupport::detect(level).ok_or_else(|| {
                Error::invalid(
                    "device",
                    format!(
                        "this processor cannot run the {} pipeline (it needs {})",
                        level.name(),
                        level.features().join(", ")
                    ),
                )
            })?,
        };
        config.simd = Some(simd.level());
        let threads = if config.threads == 0 {
            std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1)
        } else {
            config.threads
        };
        let processors = pinned_processors(threads);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|i| format!("tiler-worker-{i}"))
            .start_handler(move |i| {
                if let Some(&processor) = processors.as_ref().and_then(|p| p.get(i)) {
                    // A hint like any affinity: where it is refused the worker runs unpinned.
                    core_affinity::set_for_current(processor);
                }
            })
            .build()
            .map_err(|e| Error::invalid("device", format!("cannot start {threads} worker threads: {e}")))?;
        Ok(Device {
            config,
            workers: Workers { threads, simd },
            pool,
            images: Vec::new(),
            versions: Vec::new(),
            writes: 0,
            buffers: Vec::new(),
            scratch: tbr::Scratch::default(),
        })
    }

    pub fn config(&self) -> &DeviceConfig {
        &self.config
    }

    /// Worker threads in use.
    pub fn threads(&self) -> usize {
        self.workers.threads
    }

    /// Creates an image, zero-filled.
    ///
    /// # Errors
    /// Zero or too large sizes, unsupported sample counts (see [`ImageDesc::validate`]).
    pub fn create_image(&mut self, desc: ImageDesc) -> Result<ImageId> {
        self.images.push(Image::new(desc)?);
        self.writes += 1;
        self.versions.push(self.writes);
        Ok(ImageId((self.images.len() - 1) as u32))
    }

    /// A number that changes whenever the image's bytes may have: equal versions of an image
    /// mean equal bytes (a driver keeps what it made of an image — a texture of a render
    /// target — while the version holds). Every write of the image makes a new one: each
    /// [`Device::write_image`], and each pass that has it as an attachment or resolve target,
    /// whatever its store ops.
    ///
    /// # Errors
    /// Unknown image.
    pub fn image_version(&self, id: ImageId) -> Result<u64> {
        self.image(id)?;
        Ok(self.versions[id.0 as usize])
    }

    /// A new version for image `index`, whose bytes are about to change.
    fn written(&mut self, index: usize) {
        self.writes += 1;
        self.versions[index] = self.writes;
    }

    /// Runs `f` on the device's worker threads: rayon's parallel iterators within it share
    /// them (and the device's thread count), as the device's own work does.
    pub fn install<R: Send>(&self, f: impl FnOnce() -> R + Send) -> R {
        self.pool.install(f)
    }

    fn image(&self, id: ImageId) -> Result<&Image> {
        self.images.get(id.0 as usize).ok_or_else(|| Error::invalid(id.to_string(), "no such image on this device"))
    }

    pub fn image_desc(&self, id: ImageId) -> Result<ImageDesc> {
        Ok(self.image(id)?.desc)
    }

    /// The image's bytes as laid out in memory (see the `Image` layout: sample planes of
    /// rows); empty for a transient image.
    pub fn image_data(&self, id: ImageId) -> Result<&[u8]> {
        Ok(&self.image(id)?.data)
    }

    /// Replaces an image's bytes.
    ///
    /// # Errors
    /// Unknown or transient image, or `data` of the wrong length.
    pub fn write_image(&mut self, id: ImageId, data: &[u8]) -> Result<()> {
        self.overwritten(id, data.len())?.copy_from_slice(data);
        Ok(())
    }

    /// [`Device::write_image`] of bytes the image takes as they are: a whole upload made for it
    /// goes in without a copy (nor the pages a copy would touch first).
    ///
    /// # Errors
    /// As [`Device::write_image`].
    pub fn replace_image(&mut self, id: ImageId, data: Vec<u8>) -> Result<()> {
        let len = data.len();
        *self.overwritten(id, len)? = data;
        Ok(())
    }

    /// The bytes of image `id`, which a write of `len` bytes replaces whole: checked (an image
    /// with memory, of that many bytes) and noted as written.
    fn overwritten(&mut self, id: ImageId, len: usize) -> Result<&mut Vec<u8>> {
        let index = id.0 as usize;
        let image =
            self.images.get(index).ok_or_else(|| Error::invalid(id.to_string(), "no such image on this device"))?;
        if len != image.data.len() || image.desc.transient {
            return Err(Error::invalid(
                id.to_string(),
                format!("write of {len} bytes, but the image holds {} bytes", image.data.len()),
            ));
        }
        self.written(index);
        let image = &mut self.images[index];
        image.signatures = None;
        Ok(&mut image.data)
    }

    /// A texture holding a rendered image's pixels — render to texture: a later pass samples
    /// what an earlier one stored. The image's format gives the texture's encoding
    /// (`Rgba8UnormSrgb`: sRGB; other colour formats are converted to 8-bit linear RGBA); a
    /// multisampled image is resolved first.
    ///
    /// # Errors
    /// Unknown or non-colour image, and a transient image: it has no memory, so nothing of it
    /// exists to sample (read it as an input attachment in a later subpass of its own pass
    /// instead, or make it an image with memory and store it).
    pub fn texture_from_image(&self, id: ImageId, mips: crate::MipChain) -> Result<crate::Texture> {
        let d = self.image(id)?.desc;
        if d.transient {
            return Err(Error::invalid(
                id.to_string(),
                "a transient image has no memory, so it cannot be sampled as a texture: read it as an input \
                 attachment in a later subpass of the same render pass, or create it with memory and store it",
            ));
        }
        let color_space = match d.format {
            Format::Rgba8UnormSrgb => crate::ColorSpace::Srgb,
            _ => crate::ColorSpace::Linear,
        };
        let rgba = self.read_rgba8(id)?;
        crate::Texture::from_rgba8(d.width, d.height, &rgba, color_space, mips)
    }

    /// A colour image as 8-bit RGBA, rows top to bottom; a multisampled image is resolved
    /// (the average of its samples).
    ///
    /// # Errors
    /// Unknown, transient or non-colour image.
    pub fn read_rgba8(&self, id: ImageId) -> Result<Vec<u8>> {
        let image = self.image(id)?;
        let d = image.desc;
        if !d.format.is_color() || d.format.is_integer() || d.transient {
            return Err(Error::invalid(
                id.to_string(),
                format!(
                    "cannot read a {} image as 8-bit colour",
                    if d.transient { "transient" } else { d.format.name() }
                ),
            ));
        }
        let pixels = d.width as usize * d.height as usize;
        let tables = ByteTables::of(d.format).filter(|_| d.samples == 1);
        if let Some(tables) = &tables
            && tables.source == [0, 1, 2, 3]
            && tables.table.iter().all(|t| t.iter().enumerate().all(|(v, &b)| v == b as usize))
        {
            // The tables change nothing (RGBA8, as stored): a copy, written once.
            return Ok(image.data[..pixels * 4].to_vec());
        }
        let mut out = vec![0u8; pixels * 4];
        if let Some(tables) = tables {
            // Every frame a replay presents is read back, so the common case is a table
            // lookup per byte rather than a decode and an encode per pixel.
            for (px, src) in out.chunks_exact_mut(4).zip(image.data[..pixels * 4].chunks_exact(4)) {
                for c in 0..4 {
                    px[c] = tables.table[c][src[tables.source[c]] as usize];
                }
            }
            return Ok(out);
        }
        let bpp = d.format.bytes_per_sample();
        let plane = d.plane_bytes();
        for (p, px) in out.chunks_exact_mut(4).enumerate() {
            let samples = (0..d.samples as usize).map(|s| &image.data[s * plane + p * bpp..s * plane + (p + 1) * bpp]);
            px.copy_from_slice(&resolve_rgba8(d.format, samples));
        }
        Ok(out)
    }

    /// The depths of a depth image's first sample, rows top to bottom.
    pub fn read_depth(&self, id: ImageId) -> Result<Vec<f32>> {
        let mut depths = Vec::new();
        self.read_depth_into(id, &mut depths)?;
        Ok(depths)
    }

    /// [`Device::read_depth`] into `depths`, whose memory is reused (a shadow map is read back
    /// every frame).
    pub fn read_depth_into(&self, id: ImageId, depths: &mut Vec<f32>) -> Result<()> {
        let image = self.image(id)?;
        let d = image.desc;
        if !d.format.has_depth() || d.transient {
            return Err(Error::invalid(id.to_string(), "not a depth image with memory"));
        }
        let data = &image.data[..d.plane_bytes()];
        // One loop per format, its conversion known (a shadow map is read every frame), run
        // in runs of rows on the device's threads: the pass that samples it waits for it (a
        // 1600×1200 shadow map read on the main thread was 8% of shadow.trace's replay).
        use rayon::prelude::*;
        const RUN: usize = 1 << 14;
        let bytes = d.format.bytes_per_sample();
        // Every depth is written below: a buffer of the right length is not cleared first, and
        // a new one comes zeroed from the allocator, its pages first written by the workers.
        let n = d.width as usize * d.height as usize;
        if depths.len() != n {
            *depths = vec![0.0f32; n];
        }
        let convert = |out: &mut [f32], data: &[u8]| match d.format {
            Format::D16Unorm => {
                for (depth, b) in out.iter_mut().zip(data.as_chunks::<2>().0) {
                    *depth = Format::D16Unorm.depth_from_bits(u16::from_le_bytes(*b) as u32);
                }
            }
            Format::D24UnormS8Uint => {
                for (depth, b) in out.iter_mut().zip(data.as_chunks::<4>().0) {
                    *depth = Format::D24UnormS8Uint.depth_from_bits(u32::from_le_bytes(*b) & 0xff_ffff);
                }
            }
            // D32Float, the other depth format of four bytes a sample.
            format => {
                for (depth, b) in out.iter_mut().zip(data.as_chunks::<4>().0) {
                    *depth = format.depth_from_bits(u32::from_le_bytes(*b));
                }
            }
        };
        self.pool.install(|| {
            depths.par_chunks_mut(RUN).zip(data.par_chunks(RUN * bytes)).for_each(|(out, data)| convert(out, data))
        });
        Ok(())
    }

    /// The stencil values of a depth-stencil image's first sample.
    pub fn read_stencil(&self, id: ImageId) -> Result<Vec<u8>> {
        let image = self.image(id)?;
        let d = image.desc;
        if !d.format.has_stencil() || d.transient {
            return Err(Error::invalid(id.to_string(), "not a stencil image with memory"));
        }
        Ok(image.data[..d.plane_bytes()].chunks_exact(4).map(|b| b[3]).collect())
    }

    /// Creates a buffer holding `bytes`.
    ///
    /// # Errors
    /// More than [`MAX_BUFFER_BYTES`].
    pub fn create_buffer(&mut self, bytes: &[u8]) -> Result<BufferId> {
        if bytes.len() as u64 > MAX_BUFFER_BYTES {
            return Err(Error::invalid(
                "buffer",
                format!("{} bytes exceeds the limit of {MAX_BUFFER_BYTES}", bytes.len()),
            ));
        }
        self.buffers.push(bytes.to_vec());
        Ok(BufferId((self.buffers.len() - 1) as u32))
    }

    /// Creates a buffer from plain data (vertices, indices).
    pub fn create_buffer_from<T: bytemuck::Pod>(&mut self, data: &[T]) -> Result<BufferId> {
        self.create_buffer(bytemuck::cast_slice(data))
    }

    /// A buffer's bytes (a driver copying a buffer still in use reads them).
    ///
    /// # Errors
    /// Unknown buffer.
    pub fn buffer_data(&self, id: BufferId) -> Result<&[u8]> {
        self.buffers
            .get(id.0 as usize)
            .map(|b| b.as_slice())
            .ok_or_else(|| Error::invalid(id.to_string(), "no such buffer"))
    }

    /// Overwrites part of a buffer.
    ///
    /// # Errors
    /// Unknown buffer, or a write past its end.
    pub fn write_buffer(&mut self, id: BufferId, offset: u64, bytes: &[u8]) -> Result<()> {
        let buffer =
            self.buffers.get_mut(id.0 as usize).ok_or_else(|| Error::invalid(id.to_string(), "no such buffer"))?;
        let end = offset.checked_add(bytes.len() as u64).filter(|e| *e <= buffer.len() as u64).ok_or_else(|| {
            Error::invalid(
                id.to_string(),
                format!("write of {} bytes at {offset} past its end ({})", bytes.len(), buffer.len()),
            )
        })?;
        buffer[offset as usize..end as usize].copy_from_slice(bytes);
        Ok(())
    }

    /// What presenting `image` costs under the device's display model: scan-out and,
    /// optionally, composition (see `ledger::display`).
    ///
    /// # Errors
    /// Unknown, transient, multisampled or non-colour image.
    pub fn present(&self, id: ImageId) -> Result<Ledger> {
        let d = self.image(id)?.desc;
        if !d.format.is_color() || d.transient || d.samples != 1 {
            return Err(Error::invalid(
                id.to_string(),
                "only a single-sample colour image with memory can be presented",
            ));
        }
        Ok(self.config.display.present(d.width, d.height, d.format.bytes_per_sample() as u32))
    }

    /// Renders a pass with the configured backend.
    pub fn submit(&mut self, pass: &RenderPass) -> Result<PassReport> {
        self.submit_with(pass, self.config.backend)
    }

    /// Renders a pass with the given backend and returns what it did and cost.
    ///
    /// # Errors
    /// Any invalid attachment, draw, buffer or vertex (each error names it). The attachments
    /// are checked before anything is rendered; a draw's errors are found when it is reached.
    /// After an error the attachments hold whatever was rendered before it: nothing, on a
    /// tiler that had not flushed yet; the cleared image and earlier draws in immediate mode.
    pub fn submit_with(&mut self, pass: &RenderPass, backend: Backend) -> Result<PassReport> {
        let resolved = ResolvedPass::new(pass, &self.images)?;
        // Every image the pass may write, written or not (an error part way leaves what was
        // rendered before it).
        for index in resolved.memory_images() {
            self.written(index);
        }
        let (images, buffers, config, workers) = (&mut self.images, &self.buffers, &self.config, self.workers);
        let scratch = &mut self.scratch;
        self.pool.install(|| match backend {
            Backend::Tbr => tbr::render(pass, &resolved, images, buffers, config, workers, false, scratch),
            Backend::Tbdr => tbr::render(pass, &resolved, images, buffers, config, workers, true, scratch),
            Backend::Imr => imr::render(pass, &resolved, images, buffers, config, workers.simd),
        })
    }
}

/// A pixel's samples (each in `format`) resolved to 8-bit RGBA: their average, encoded as
/// sRGB if the format is (PNGs are sRGB, so the stored encoding is kept), else linear.
fn resolve_rgba8<'a>(format: Format, samples: impl ExactSizeIterator<Item = &'a [u8]>) -> [u8; 4] {
    let n = samples.len() as f32;
    let mut sum = [0.0f32; 4];
    for sample in samples {
        let v = format.decode_color(sample);
        for c in 0..4 {
            sum[c] += v[c];
        }
    }
    let rgba = sum.map(|c| c / n);
    let mut bytes = [0u8; 4];
    let encoding = if format == Format::Rgba8UnormSrgb { format } else { Format::Rgba8Unorm };
    encoding.encode_color(rgba, &mut bytes);
    bytes
}

/// [`resolve_rgba8`] of one sample, as tables, for the formats of four bytes where each
/// output byte depends on one stored byte only.
struct ByteTables {
    /// Output channel `c` is `table[c][stored byte source[c]]`.
    source: [usize; 4],
    table: [[u8; 256]; 4],
}

impl ByteTables {
    fn of(format: Format) -> Option<ByteTables> {
        let source = match format {
            Format::Rgba8Unorm | Format::Rgba8UnormSrgb => [0, 1, 2, 3],
            Format::Bgra8Unorm => [2, 1, 0, 3],
            _ => return None,
        };
        let mut table = [[0u8; 256]; 4];
        for v in 0..=255u8 {
            let rgba = resolve_rgba8(format, std::iter::once(&[v; 4][..]));
            for c in 0..4 {
                table[c][v as usize] = rgba[c];
            }
        }
        Some(ByteTables { source, table })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Depths read back are each sample's own bits decoded, in order, for every depth format
    /// and across the runs the read is cut into (an image of several runs and a ragged last one).
    #[test]
    fn read_depth_decodes_every_sample_in_order() {
        let mut device = Device::new(DeviceConfig { threads: 2, ..DeviceConfig::default() }).unwrap();
        let (width, height) = (211, 97);
        for format in [Format::D16Unorm, Format::D24UnormS8Uint, Format::D32Float] {
            let id = device.create_image(ImageDesc::new(width, height, format)).unwrap();
            let pixels = (width * height) as usize;
            let bits: Vec<u32> = (0..pixels as u32)
                .map(|i| match format {
                    Format::D16Unorm => i.wrapping_mul(40_503) & 0xffff,
                    // A stencil byte above the depth, which the read leaves out.
                    Format::D24UnormS8Uint => i.wrapping_mul(2_654_435_761) & 0xff_ffff | (i % 251) << 24,
                    _ => (i as f32 / pixels as f32).to_bits(),
                })
                .collect();
            let data: Vec<u8> = match format {
                Format::D16Unorm => bits.iter().flat_map(|b| (*b as u16).to_le_bytes()).collect(),
                _ => bits.iter().flat_map(|b| b.to_le_bytes()).collect(),
            };
            device.write_image(id, &data).unwrap();
            let depths = device.read_depth(id).unwrap();
            assert_eq!(depths.len(), pixels);
            for (i, (&depth, &b)) in depths.iter().zip(&bits).enumerate() {
                let depth_bits = if format == Format::D24UnormS8Uint { b & 0xff_ffff } else { b };
                assert_eq!(depth.to_bits(), format.depth_from_bits(depth_bits).to_bits(), "{format:?}, sample {i}");
            }
            // Into a buffer of the right length holding other values, and into ones of other
            // lengths: the same depths.
            for stale in [vec![f32::NAN; pixels], vec![7.0; 3], vec![-1.0; pixels + 5]] {
                let mut reused = stale;
                device.read_depth_into(id, &mut reused).unwrap();
                assert!(reused.iter().map(|d| d.to_bits()).eq(depths.iter().map(|d| d.to_bits())), "{format:?}");
            }
        }
    }

    #[test]
    fn an_image_takes_replacing_bytes_of_its_size_only() {
        let mut device = Device::new(DeviceConfig { threads: 1, ..DeviceConfig::default() }).unwrap();
        let id = device.create_image(ImageDesc::new(5, 3, Format::Rgba8Unorm)).unwrap();
        let bytes: Vec<u8> = (0..60).collect();
        let e = device.replace_image(id, bytes[..59].to_vec()).unwrap_err().to_string();
        assert!(e.contains("write of 59 bytes, but the image holds 60"), "{e}");
        device.replace_image(id, bytes.clone()).unwrap();
        assert_eq!(device.image_data(id).unwrap(), &bytes[..]);
        let transient = device.create_image(ImageDesc::new(5, 3, Format::Rgba8Unorm).transient()).unwrap();
        assert!(device.replace_image(transient, bytes).is_err());
    }

    /// The tables give what decoding and encoding each pixel gives, for every byte in every
    /// channel (the channels of a pixel all different).
    #[test]
    fn byte_tables_match_the_per_pixel_resolve() {
        for format in [Format::Rgba8Unorm, Format::Rgba8UnormSrgb, Format::Bgra8Unorm] {
            let tables = ByteTables::of(format).expect("a format of bytes");
            for v in 0..=255u8 {
                let stored = [v, v.wrapping_mul(7).wrapping_add(3), v.wrapping_mul(13).wrapping_add(5), 255 - v];
                let fast: [u8; 4] = std::array::from_fn(|c| tables.table[c][stored[tables.source[c]] as usize]);
                assert_eq!(fast, resolve_rgba8(format, std::iter::once(&stored[..])), "{format:?}, {stored:?}");
            }
        }
        assert!(ByteTables::of(Format::Rgb565Unorm).is_none());
    }

    /// Workers are pinned one to a processor only when the pool has one for every processor
    /// (more than one); a pool smaller or larger than the machine is left to the kernel.
    #[test]
    fn workers_are_pinned_only_when_they_fill_the_machine() {
        assert_eq!(pins(2, vec![0, 1]), Some(vec![0, 1]));
        assert_eq!(pins(4, vec![3, 5, 6, 7]), Some(vec![3, 5, 6, 7]), "the processors allowed, in order");
        assert_eq!(pins(1, vec![0]), None, "one worker is not pinned");
        assert_eq!(pins(2, vec![0, 1, 2, 3]), None, "a pool smaller than the machine");
        assert_eq!(pins(8, vec![0, 1]), None, "a pool larger than the machine");
        // A device that fills the machine starts, its workers pinned. Where they run cannot
        // change an image: `tests/render/invariant.rs` renders on 1, 2 and 3 threads, the two
        // pinned on a two-processor machine such as CI's.
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
        let device = Device::new(DeviceConfig { threads, ..DeviceConfig::default() }).unwrap();
        assert_eq!(device.threads(), threads);
    }
}

// Here rather than beside the code it tests: it drives a whole device, and the pixel pipeline
// must not import the device (tests/layers.rs holds the modules to a DAG).
#[cfg(test)]
mod hsr_tests {
    /// Pass one's whole covered rectangles (`PrimitiveRaster::resolve_covered` in `pixel::primitive`) against the
    /// block-by-block path they replace, on TBDR: random layers of flat full-screen quads, flat
    /// block-aligned and unaligned rectangles, sloped quads (whose blocks the depth summary
    /// cannot decide, so that later flat layers fall back block by block), every compare op,
    /// depth writes on and off, depth prepasses (no claims) and blended draws (which end HSR
    /// segments), at 1 and 4 samples, three depth formats and three tile sizes. The pictures,
    /// the counters, the ledger, the per-tile and per-draw figures must be the same.
    #[test]
    fn whole_covered_rectangles_resolve_as_block_by_block() {
        use crate::api::format::{ColorWrites, Format};
        use crate::api::image::ImageDesc;
        use crate::api::pipeline::{
            ColorTargetState, CompareOp, DepthStencilState, Interpolation, PipelineDesc, VertexFormat, VertexInputState,
        };
        use crate::api::render_pass::{ColorAttachment, DepthStencilAttachment, RenderPassDesc};
        use crate::api::shader::{VertexInput, VertexOutput, VertexShader};
        use crate::config::{Backend, DeviceConfig};
        use crate::pixel::primitive::{WHOLE_RECTS, WHOLE_RECTS_TAKEN};
        use crate::shade::fragments::{FragmentShader, Fragments};
        use crate::simd::F32x8;
        use crate::{Device, Draw, Pipeline, RenderPass};
        use std::sync::atomic::Ordering;

        struct PassThrough;
        impl VertexShader for PassThrough {
            fn shade(&self, input: &VertexInput, out: &mut VertexOutput) {
                out.position = input.attributes[0];
                out.varyings[..4].copy_from_slice(&input.attributes[1].to_array());
            }
        }
        struct Flat;
        impl FragmentShader for Flat {
            fn shade(&self, frag: &mut Fragments<'_>) {
                let c = [0, 1, 2, 3].map(|i| F32x8::splat(frag.flat(i)));
                frag.set_color(0, c);
            }
        }
        const COMPARES: [CompareOp; 8] = [
            CompareOp::Less,
            CompareOp::LessOrEqual,
            CompareOp::Greater,
            CompareOp::Equal,
            CompareOp::Always,
            CompareOp::GreaterOrEqual,
            CompareOp::Never,
            CompareOp::NotEqual,
        ];
        let (width, height) = (96u32, 72u32);
        let scene = |device: &mut Device, seed: u32, samples: u32, format: Format| {
            let mut rng = seed;
            let mut next = move |n: u32| {
                rng = rng.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                (rng >> 8) % n
            };
            let color =
                device.create_image(ImageDesc::new(width, height, Format::Rgba8Unorm).with_samples(samples)).unwrap();
            let depth = device.create_image(ImageDesc::new(width, height, format).with_samples(samples)).unwrap();
            let resolve =
                (samples > 1).then(|| device.create_image(ImageDesc::new(width, height, Format::Rgba8Unorm)).unwrap());
            let ndc = |px: u32, size: u32| 2.0 * px as f32 / size as f32 - 1.0;
            let mut verts: Vec<[f32; 8]> = Vec::new();
            let mut draws = Vec::new();
            for _ in 0..24 {
                let z = [0.2, 0.35, 0.5, 0.5, 0.65, 0.8][next(6) as usize];
                let c = [next(256) as f32 / 255.0, next(256) as f32 / 255.0, next(256) as f32 / 255.0, 0.5];
                let (x0, y0, x1, y1) = match next(4) {
                    0 | 1 => (0, 0, width, height),
                    2 => {
                        let (a, b) = (8 * next(width / 8), 8 * next(height / 8));
                        (a, b, (a + 8 * (1 + next(6))).min(width), (b + 8 * (1 + next(6))).min(height))
                    }
                    _ => {
                        let (a, b) = (next(width / 2), next(height / 2));
                        (a, b, a + 1 + next(width / 2), b + 1 + next(height / 2))
                    }
                };
                let slope = if next(5) == 0 { 0.3 } else { 0.0 };
                let (l, r, t, b) = (ndc(x0, width), ndc(x1, width), ndc(y0, height), ndc(y1, height));
                let at = |x: f32, y: f32| [x, y, z + slope * x, 1.0, c[0], c[1], c[2], c[3]];
                let first = verts.len() as u32;
                verts.extend([at(l, t), at(r, t), at(r, b), at(l, t), at(r, b), at(l, b)]);
                let mut desc = PipelineDesc::new(
                    "layer",
                    VertexInputState::interleaved(&[VertexFormat::Float32x4, VertexFormat::Float32x4]),
                );
                desc.varyings = vec![Interpolation::Flat; 4];
                desc.depth_stencil = DepthStencilState {
                    depth_test: true,
                    depth_write: next(4) != 0,
                    depth_compare: COMPARES[next(8) as usize],
                    ..DepthStencilState::DISABLED
                };
                match next(8) {
                    0 => desc.color_targets[0].write_mask = ColorWrites::NONE,
                    1 => desc.color_targets = vec![ColorTargetState::ALPHA_BLEND],
                    _ => {}
                }
                draws.push((desc, first));
            }
            let buffer = device.create_buffer_from(&verts).unwrap();
            let color_attachment = match resolve {
                Some(r) => ColorAttachment::clear_resolve(color, [0.0; 4], r),
                None => ColorAttachment::clear_store(color, [0.0; 4]),
            };
            let mut pass = RenderPass::new(RenderPassDesc {
                color: vec![color_attachment],
                depth_stencil: Some(DepthStencilAttachment::clear_store(depth, 0.6, 0)),
                render_area: None,
            });
            for (desc, first) in draws {
                let pipeline = Pipeline::new(PassThrough, Flat, desc).unwrap();
                pass.draw(Draw::new(&pipeline, buffer, first, 6));
            }
            (pass, [resolve.unwrap_or(color), depth])
        };
        let render = |whole: bool, seed: u32, samples: u32, format: Format, tile: u32| {
            WHOLE_RECTS.store(whole, Ordering::Relaxed);
            let config = DeviceConfig { backend: Backend::Tbdr, threads: 2, ..DeviceConfig::default() };
            let mut device = Device::new(config.with_tile_size(tile)).unwrap();
            let (pass, images) = scene(&mut device, seed, samples, format);
            let report = device.submit(&pass).unwrap();
            WHOLE_RECTS.store(true, Ordering::Relaxed);
            let pictures: Vec<Vec<u8>> = images.iter().map(|id| device.image_data(*id).unwrap().to_vec()).collect();
            (pictures, report)
        };
        let taken_before = WHOLE_RECTS_TAKEN.load(Ordering::Relaxed);
        for seed in 0..6 {
            for (samples, format, tile) in [
                (1, Format::D32Float, 32),
                (1, Format::D24UnormS8Uint, 16),
                (4, Format::D16Unorm, 8),
                (4, Format::D32Float, 24),
            ] {
                let (whole, whole_report) = render(true, seed, samples, format, tile);
                let (blocks, blocks_report) = render(false, seed, samples, format, tile);
                let case = format!("seed {seed}, {samples} samples, {format:?}, {tile}×{tile} tiles");
                assert!(whole == blocks, "{case}: the pictures differ");
                assert_eq!(whole_report.counters, blocks_report.counters, "{case}");
                assert_eq!(whole_report.ledger, blocks_report.ledger, "{case}");
                assert_eq!(whole_report.on_chip_bytes, blocks_report.on_chip_bytes, "{case}");
                assert_eq!(whole_report.tiles, blocks_report.tiles, "{case}");
                assert_eq!(whole_report.draws, blocks_report.draws, "{case}");
            }
        }
        assert!(WHOLE_RECTS_TAKEN.load(Ordering::Relaxed) > taken_before, "the whole-rectangle path never ran");
    }
}
