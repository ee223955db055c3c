//! Immediate mode (IMR): primitives in submission order, straight into the images in external
//! memory, as a desktop GPU does. There is no frame data and no tile buffer; every depth,
//! stencil and colour access of every fragment goes to external memory (through the
//! framebuffer cache, if the device has one), and a `Clear` load op writes the whole render
//! area.
//!
//! The framebuffer is split into fixed bands of [`BAND_ROWS`] rows that work in parallel, each
//! walking every primitive in submission order — the way a GPU's render back-ends split the
//! screen. The bands do not depend on the thread count, so neither do the results; each band
//! has its slice of the framebuffer cache, in proportion to its share of the screen, as a
//! GPU's L2 slices serve screen regions.

use rayon::prelude::*;

use super::pass::{ResolvedPass, attachment_images, band_surface, image_bands};
use super::{Backend, FrameDataReport, PassReport, PassTotals, samples_blended};
use crate::api::error::Result;
use crate::api::image::Image;
use crate::config::DeviceConfig;
use crate::geometry::prepare_draw;
use crate::ledger::cache::CacheConfig;
use crate::ledger::framebuffer::FramebufferTraffic;
use crate::ledger::{Category, Counters};
use crate::pass::RenderPass;
use crate::pixel::primitive::{FragmentTally, Mode, OverdrawRows, PrimitiveRun};
use crate::raster::PixelRect;
use crate::raster::samples::SampleLocations;
use crate::raster::target::{RenderTarget, Surface};
use crate::shade::ShadeContext;
use crate::simd::SimdSupport;
use crate::tile::load_store::{apply_load, apply_resolve};

/// Rows per band of the framebuffer.
pub const BAND_ROWS: u32 = 32;

/// Address space of the framebuffer cache: each attachment gets its own 2^40-byte range.
const ATTACHMENT_ADDRESS_BITS: u32 = 40;

/// One band of the framebuffer: its rows of every attachment and of every resolve target, and
/// what its fragment work has done so far.
struct Band<'a> {
    /// One view per attachment of the pass.
    surfaces: Vec<Surface<'a>>,
    resolves: Vec<Surface<'a>>,
    /// The band's rows ∩ the render area.
    clip: PixelRect,
    tally: FragmentTally,
}

/// The slice of the framebuffer cache one band of `rows` rows out of `height` gets: whole
/// sets, at least one.
fn cache_slice(cache: CacheConfig, rows: u32, height: u32) -> CacheConfig {
    if !cache.is_enabled() {
        return cache;
    }
    let set = cache.line_bytes as u64 * cache.ways as u64;
    let share = cache.size_bytes as u64 * rows as u64 / height as u64;
    CacheConfig { size_bytes: ((share / set).max(1) * set) as u32, ..cache }
}

/// Renders a validated pass in immediate mode.
pub fn render(
    pass: &RenderPass,
    resolved: &ResolvedPass,
    images: &mut [Image],
    buffers: &[Vec<u8>],
    config: &DeviceConfig,
    simd: SimdSupport,
) -> Result<PassReport> {
    let samples = SampleLocations::new(resolved.samples, pass.sample_origin);
    let frame_info = resolved.frame(buffers);
    // Transient attachments have no memory on a tiler; an immediate-mode GPU needs some.
    let mut scratch: Vec<Image> = resolved
        .attachments
        .iter()
        .filter(|a| a.transient)
        .map(|a| {
            let mut desc = images[a.image].desc;
            desc.transient = false;
            Image::new(desc).expect("validated size")
        })
        .collect();
    let mut attached = attachment_images(images, resolved);
    let mut scratch_iter = scratch.iter_mut();
    for (slot, attachment) in attached.iter_mut().zip(&resolved.attachments) {
        if attachment.transient {
            *slot = scratch_iter.next().expect("one scratch image per transient attachment");
        }
    }
    let plane_bytes: Vec<u64> = attached.iter().map(|image| image.desc.plane_bytes() as u64).collect();
    // Whatever a tiler stored before is overwritten here: its tile signatures no longer hold.
    for image in attached.iter_mut() {
        image.signatures = None;
    }

    // Bands, each a render target over its rows of every attachment, with its rows of the
    // resolve targets.
    let mut per_image: Vec<std::vec::IntoIter<Vec<&mut [u8]>>> =
        attached.iter_mut().map(|image| image_bands(image, BAND_ROWS as usize).into_iter()).collect();
    let formats: Vec<_> = resolved
        .attachments
        .iter()
        .map(|a| a.format)
        .chain(resolved.resolves.iter().map(|r| resolved.attachments[r.color].format))
        .collect();
    let band_count = resolved.height.div_ceil(BAND_ROWS);
    let mut bands: Vec<Band> = Vec::new();
    for b in 0..band_count {
        let y0 = (b * BAND_ROWS) as i32;
        let rows = PixelRect::new(0, y0, resolved.width as i32, (y0 + BAND_ROWS as i32).min(resolved.height as i32));
        let mut surfaces: Vec<Surface> = per_image
            .iter_mut()
            .zip(&formats)
            .enumerate()
            .map(|(i, (a, format))| {
                let base = ((i as u64) << ATTACHMENT_ADDRESS_BITS)
                    + y0 as u64 * resolved.width as u64 * format.bytes_per_sample() as u64;
                band_surface(*format, resolved.width, y0, a.next().expect("band")).with_memory(base, plane_bytes[i])
            })
            .collect::<Vec<_>>();
        let clip = rows.intersect(&resolved.render_area);
        if clip.is_empty() {
            continue;
        }
        let resolves = surfaces.split_off(resolved.attachments.len());
        let cache = cache_slice(config.framebuffer_cache, rows.height() as u32, resolved.height);
        let tally = FragmentTally {
            framebuffer: FramebufferTraffic::external(cache),
            overdraw: config.overdraw_map.then(|| OverdrawRows::new(y0, resolved.width, rows.height() as u32)),
            context: ShadeContext::with_texture_cache(config.texture_cache),
            simd,
            ..FragmentTally::default()
        };
        bands.push(Band { surfaces, resolves, clip, tally });
    }

    let pixels = resolved.width as usize * resolved.height as usize;
    let mut totals = PassTotals::new(pass.draws.len(), config.overdraw_map.then_some(pixels));
    let PassTotals { counters, ledger, draws, .. } = &mut totals;

    // Load ops act on the images themselves: a clear writes the render area.
    let cleared: u64 = bands
        .par_iter_mut()
        .map(|band| {
            let clip = band.clip;
            let surfaces = band.surfaces.iter_mut();
            surfaces.zip(&resolved.attachments).map(|(s, a)| apply_load(s, None, &clip, &a.ops).cleared).sum::<u64>()
        })
        .sum();
    ledger.add(Category::ImrClear, cleared);

    for (draw_index, draw) in pass.draws.iter().enumerate() {
        let geometry = prepare_draw(
            draw_index,
            draw.geometry_input(),
            &frame_info,
            config.post_transform_cache,
            config.vertex_cache,
            Default::default(),
        )?;
        geometry.record(counters, ledger);
        let batches = geometry.setup(0..geometry.triangles, &samples, 0);
        for batch in &batches {
            counters.merge(&batch.counters);
            draws[draw_index].primitives += batch.counters.primitives;
        }
        let object = &draw.pipeline.object;
        let subpass = &resolved.subpasses[pass.subpass_of(draw_index)];
        bands.par_iter_mut().for_each(|band| {
            let target =
                &mut RenderTarget::for_subpass(&mut band.surfaces, subpass, samples, band.clip, config.early_z);
            band.tally.draw = draw_index;
            for batch in &batches {
                let run = PrimitiveRun::all(&batch.primitives, &batch.varyings, geometry.vertices.varying_count);
                object.rasterize(&run, target, &mut band.tally, &mut Mode::InOrder);
            }
        });
    }

    // What the framebuffer cache still holds dirty goes to memory at the end of the pass;
    // then resolve the way an immediate-mode GPU does: every sample read back from memory,
    // the average written: pixels × bytes × (samples + 1).
    let resolved_bytes: u64 = bands
        .par_iter_mut()
        .map(|band| {
            band.tally.framebuffer.finish(&mut band.tally.ledger);
            let mut bytes = 0;
            for (r, target) in resolved.resolves.iter().enumerate() {
                let source = &band.surfaces[target.color];
                let pixels = apply_resolve(source, &mut band.resolves[r], &band.clip);
                bytes += pixels * source.bytes_per_sample() as u64 * (resolved.samples as u64 + 1);
            }
            bytes
        })
        .sum();
    ledger.add(Category::Resolve, resolved_bytes);
    for band in &bands {
        totals.add_tally(&band.tally);
    }

    Ok(PassReport {
        backend: Backend::Imr,
        width: resolved.width,
        height: resolved.height,
        samples: resolved.samples,
        render_area: resolved.render_area_rect(),
        tile_width: 0,
        tile_height: 0,
        tile_shrunk_from: None,
        tile_bytes: 0,
        tiles_x: 0,
        tiles_y: 0,
        ledger: totals.ledger,
        on_chip_bytes: totals.on_chip_bytes,
        transaction_elimination_saved: 0,
        transient_bytes_saved: 0,
        overdraw_map: totals.overdraw,
        counters: Counters { samples_blended: samples_blended(pass, &totals.draws), ..totals.counters },
        frame_data: FrameDataReport::default(),
        tiles: Vec::new(),
        draws: totals.draws,
    })
}
