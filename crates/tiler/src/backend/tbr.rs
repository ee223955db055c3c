//! The tilers: bin the whole pass into frame data, then render tile by tile — in submission
//! order with early-Z (TBR), or with hidden-surface removal first (TBDR, see `depth::hsr`).
//!
//! # Incremental render
//!
//! Frame data has a budget (`DeviceConfig::frame_data_budget`), and never exceeds it.
//! Triangles are set up in chunks of [`BIN_CHUNK`]; primitives are appended while their
//! frame data surely fits (a primitive record plus one polygon-list entry per tile its box
//! meets, an upper bound of what binning writes). When the next one would not fit, everything
//! binned so far is rendered — storing *every* attachment, depth, stencil and all samples,
//! whatever its store op — and the frame data is emptied; the next flush loads everything
//! back (seed 000 §23.5, Mali's "incremental rendering", llvmpipe's flush-and-retry). Only
//! the last flush uses the pass's own store ops and resolves, so the ledger shows the cliff as
//! extra tile loads and stores. Transient attachments, which have no memory, are spilled to
//! scratch memory for this (as PowerVR and Apple GPUs do); the spill is counted like any store.
//!
//! # Tile memory
//!
//! A tile holds every attachment at every sample. When that exceeds the tile memory
//! (`DeviceConfig::tile_memory_bytes`), the tile shrinks — the wider side halved, repeatedly —
//! as GPUs with a fixed tile buffer do for MSAA or many render targets (seed 000 §23.9).

use rayon::prelude::*;

use super::pass::{ResolvedPass, attachment_images, data_bands};
use super::{Backend, FrameDataReport, PassReport, PassTotals, Workers, samples_blended};
use crate::api::error::Result;
use crate::api::image::Image;
use crate::api::image::TileSignatures;
use crate::api::render_pass::AttachmentOps;
use crate::binning::binner::bin;
use crate::binning::frame_data::{FrameData, StateRecord};
use crate::binning::grid::TileGrid;
use crate::config::DeviceConfig;
use crate::depth::hsr::{HsrMode, Visibility};
use crate::geometry::vertex::ShadedVertices;
use crate::geometry::{SetupBatch, prepare_draw};
use crate::ledger::{Category, Counters, TileStats};
use crate::pass::{Draw, RenderPass};
use crate::raster::samples::SampleLocations;
use crate::shade::texture_cache::TextureCacheConfig;
use crate::tile::buffer::TileBuffer;
use crate::tile::task::{BandResult, FlushPlan, Worker, render_band};

/// Triangles set up and binned at a time.
pub const BIN_CHUNK: u32 = 16384;

/// The smallest tile side the tile memory may shrink a tile to.
pub const MIN_TILE_SIDE: u32 = 8;

/// The tile size for a pass: the configured one, halved until every attachment at every
/// sample fits the tile memory (or the tile is 8×8).
pub fn tile_size(config: &DeviceConfig, bytes_per_pixel: u64) -> (u32, u32) {
    let (mut w, mut h) = (config.tile_width, config.tile_height);
    while w as u64 * h as u64 * bytes_per_pixel > config.tile_memory_bytes && (w > MIN_TILE_SIDE || h > MIN_TILE_SIDE) {
        if w >= h && w > MIN_TILE_SIDE {
            w /= 2;
        } else {
            h /= 2;
        }
    }
    (w.max(MIN_TILE_SIDE), h.max(MIN_TILE_SIDE))
}

/// What a tiler keeps from pass to pass, so that once the first frame has grown them a frame
/// allocates no frame data and no setup batches: the device holds one.
#[derive(Default)]
pub struct Scratch {
    /// Emptied after every pass (`FrameData::reset`), its memory kept.
    frame: Option<FrameData>,
    batches: Vec<SetupBatch>,
    /// The next chunk's, set up while `batches` is binned.
    next_batches: Vec<SetupBatch>,
    /// The last draw's shaded vertices, for the next draw to shade into.
    vertices: ShadedVertices,
}

/// Renders a validated pass as a tiler; `hsr` selects TBDR.
#[allow(clippy::too_many_arguments)]
pub fn render(
    pass: &RenderPass,
    resolved: &ResolvedPass,
    images: &mut [Image],
    buffers: &[Vec<u8>],
    config: &DeviceConfig,
    workers: Workers,
    hsr: bool,
    scratch: &mut Scratch,
) -> Result<PassReport> {
    let (tile_width, tile_height) = tile_size(config, resolved.tile_bytes_per_pixel());
    let grid = TileGrid::new(resolved.width, resolved.height, tile_width, tile_height);
    let samples = SampleLocations::new(resolved.samples, pass.sample_origin);
    let frame_info = resolved.frame(buffers);
    let mut memory = attachment_images(images, resolved);
    let mut frame = match scratch.frame.take() {
        Some(mut frame) => {
            frame.reset(grid, config.vertex_shading, config.frame_data_budget);
            frame
        }
        None => FrameData::new(grid, config.vertex_shading, config.frame_data_budget),
    };
    let pixels = resolved.width as usize * resolved.height as usize;
    let mut run = Run {
        resolved,
        pass_draws: &pass.draws,
        samples,
        hsr,
        early_z: config.early_z,
        totals: PassTotals::new(pass.draws.len(), config.overdraw_map.then_some(pixels)),
        tiles: vec![TileStats::default(); grid.tile_count()],
        frame_data: FrameDataReport::default(),
        transaction_elimination: config.transaction_elimination,
        transaction_elimination_saved: 0,
        texture_cache: config.texture_cache,
        vertex_cache: config.vertex_cache,
        simd: workers.simd,
        flushes: 0,
        scratch: resolved.attachments.iter().map(|_| None).collect(),
    };
    // Every band walks every new primitive: one band per thread (the lists are the same
    // whatever the number of bands).
    let bands = workers.threads;

    let mut subpass = 0;
    for (draw_index, draw) in pass.draws.iter().enumerate() {
        // A dependency that is not by-region ends the tile's work: everything so far is
        // rendered and stored, and the later subpasses load it back.
        let draw_subpass = pass.subpass_of(draw_index);
        if draw_subpass != subpass {
            if resolved.subpasses[subpass + 1..=draw_subpass].iter().any(|s| s.split_before) && !frame.is_empty() {
                run.flush(&frame, &mut memory, Flush::SubpassSplit);
                frame.clear();
            }
            subpass = draw_subpass;
        }
        let geometry = prepare_draw(
            draw_index,
            draw.geometry_input(),
            &frame_info,
            config.post_transform_cache,
            config.vertex_cache,
            std::mem::take(&mut scratch.vertices),
        )?;
        geometry.record(&mut run.totals.counters, &mut run.totals.ledger);
        let varying_count = geometry.vertices.varying_count;
        let state = StateRecord {
            draw: draw_index as u32,
            varying_count: varying_count as u32,
            hsr: HsrMode::of(draw.pipeline.desc(), draw.pipeline.object.properties(), resolved.color_count),
            fetch: geometry.fetch.clone(),
            subpass: pass.subpass_of(draw_index) as u32,
            flat_only: flat_only(draw.pipeline.desc(), varying_count),
        };
        let mut state_index = None;
        let chunks = geometry.triangles.div_ceil(BIN_CHUNK);
        let chunk = |c: u32| c * BIN_CHUNK..((c + 1) * BIN_CHUNK).min(geometry.triangles);
        let mut used = if chunks > 0 { geometry.setup_into(chunk(0), &samples, 0, &mut scratch.batches) } else { 0 };
        for c in 0..chunks {
            // Chunk `c` is appended and binned while chunk `c + 1` is set up beside it: the
            // serial appending overlaps parallel setup.
            let (current, next) = (&scratch.batches[..used], &mut scratch.next_batches);
            let ((), next_used) = rayon::join(
                || {
                    for batch in current {
                        run.totals.counters.merge(&batch.counters);
                        run.totals.draws[draw_index].primitives += batch.counters.primitives;
                        // Append the longest run of primitives the frame data says surely
                        // fits its budget; render it (an incremental render) when it is full.
                        // Binning waits for the end of the chunk unless the frame data,
                        // counting what waits at its bound, is not sure the run fits.
                        let mut i = 0;
                        while i < batch.primitives.len() {
                            let index = *state_index.get_or_insert_with(|| frame.push_state(state.clone()));
                            let mut fitting = frame.fitting(&batch.primitives[i..], varying_count);
                            if fitting < batch.primitives.len() - i && frame.unbinned() {
                                bin(&mut frame, &samples, bands);
                                fitting = frame.fitting(&batch.primitives[i..], varying_count);
                            }
                            if fitting == 0 && !frame.is_empty() {
                                run.flush(&frame, &mut memory, Flush::Incremental);
                                frame.clear();
                                state_index = None;
                                continue;
                            }
                            // A primitive too large for an empty budget still goes in alone.
                            let k = i + fitting.max(1);
                            frame.append(&batch.primitives[i..k], &batch.varyings, index, varying_count);
                            i = k;
                        }
                    }
                    bin(&mut frame, &samples, bands);
                    run.frame_data.peak_bytes = run.frame_data.peak_bytes.max(frame.bytes().total());
                    run.frame_data.peak_host_bytes = run.frame_data.peak_host_bytes.max(frame.host_bytes());
                },
                || if c + 1 < chunks { geometry.setup_into(chunk(c + 1), &samples, 0, next) } else { 0 },
            );
            std::mem::swap(&mut scratch.batches, &mut scratch.next_batches);
            used = next_used;
        }
        scratch.vertices = geometry.vertices;
    }
    run.flush(&frame, &mut memory, Flush::Final);
    frame.clear();
    scratch.frame = Some(frame);

    let shrunk = (tile_width, tile_height) != (config.tile_width, config.tile_height);
    // Transient attachments that never had to spill never needed memory at all.
    let transient_bytes_saved = resolved
        .attachments
        .iter()
        .zip(&run.scratch)
        .filter(|(a, scratch)| a.transient && scratch.is_none())
        .map(|(a, _)| images_desc_size(resolved, a))
        .sum();
    Ok(PassReport {
        backend: if hsr { Backend::Tbdr } else { Backend::Tbr },
        width: resolved.width,
        height: resolved.height,
        samples: resolved.samples,
        render_area: resolved.render_area_rect(),
        tile_width,
        tile_height,
        tile_shrunk_from: shrunk.then_some((config.tile_width, config.tile_height)),
        tile_bytes: tile_width as u64 * tile_height as u64 * resolved.tile_bytes_per_pixel(),
        tiles_x: grid.tiles_x,
        tiles_y: grid.tiles_y,
        ledger: run.totals.ledger,
        on_chip_bytes: run.totals.on_chip_bytes,
        transaction_elimination_saved: run.transaction_elimination_saved,
        transient_bytes_saved,
        overdraw_map: run.totals.overdraw,
        counters: Counters { samples_blended: samples_blended(pass, &run.totals.draws), ..run.totals.counters },
        frame_data: run.frame_data,
        tiles: run.tiles,
        draws: run.totals.draws,
    })
}

/// Bytes an attachment's image would occupy in memory.
fn images_desc_size(resolved: &ResolvedPass, a: &super::pass::ResolvedAttachment) -> u64 {
    resolved.width as u64 * resolved.height as u64 * resolved.samples as u64 * a.format.bytes_per_sample() as u64
}

/// Why the frame data is being rendered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Flush {
    /// It outgrew its budget (an incremental render).
    Incremental,
    /// A subpass dependency is not by-region.
    SubpassSplit,
    /// The pass is done.
    Final,
}

/// The state of one pass being rendered.
struct Run<'a> {
    resolved: &'a ResolvedPass,
    pass_draws: &'a [Draw],
    samples: SampleLocations,
    hsr: bool,
    early_z: bool,
    totals: PassTotals,
    tiles: Vec<TileStats>,
    frame_data: FrameDataReport,
    transaction_elimination: bool,
    transaction_elimination_saved: u64,
    texture_cache: TextureCacheConfig,
    vertex_cache: crate::ledger::cache::CacheConfig,
    simd: crate::simd::SimdSupport,
    flushes: u64,
    /// Spill memory for transient attachments, made at their first incremental render.
    scratch: Vec<Option<Image>>,
}

impl Run<'_> {
    /// Renders the frame data into every tile of the render area. The first flush uses the
    /// pass's load ops, later ones load everything; the last uses the pass's store ops and
    /// resolves, earlier ones store everything.
    fn flush(&mut self, frame: &FrameData, memory: &mut [&mut Image], kind: Flush) {
        let last = kind == Flush::Final;
        let resolved = self.resolved;
        let first = self.flushes == 0;
        let ops: Vec<AttachmentOps> = resolved
            .attachments
            .iter()
            .map(|a| {
                let ops = if first { a.ops } else { a.ops.with_load() };
                if last { ops } else { ops.with_store() }
            })
            .collect();
        if !last {
            for (a, attachment) in resolved.attachments.iter().enumerate() {
                if attachment.transient && self.scratch[a].is_none() {
                    let mut desc = memory[a].desc;
                    desc.transient = false;
                    self.scratch[a] = Some(Image::new(desc).expect("validated size"));
                }
            }
        }
        let grid = frame.grid();
        let (tx0, ty0, tx1, ty1) = grid.tiles_meeting(&resolved.render_area);

        // Cut every image into bands of tile rows: bands[row][image] = sample slices (and the
        // row's tile signatures, under transaction elimination). Images are the attachments
        // (or their spill memory), then the resolve targets.
        let mut per_image: Vec<std::vec::IntoIter<Vec<&mut [u8]>>> = Vec::new();
        let mut per_signatures: Vec<Option<std::slice::ChunksMut<u64>>> = Vec::new();
        let mut scratch = self.scratch.iter_mut();
        for (i, image) in memory.iter_mut().enumerate() {
            let image: &mut Image = match scratch.next() {
                Some(Some(spill)) => spill,
                _ => image,
            };
            let Image { desc, data, signatures } = image;
            let eliminates = self.transaction_elimination && i < resolved.attachments.len();
            let rows = if eliminates {
                let grid_matches = signatures.as_ref().is_some_and(|s| {
                    (s.tile_width, s.tile_height, s.hashes.len())
                        == (grid.tile_width, grid.tile_height, grid.tile_count())
                });
                if !grid_matches {
                    *signatures = Some(TileSignatures {
                        tile_width: grid.tile_width,
                        tile_height: grid.tile_height,
                        hashes: vec![TileSignatures::UNKNOWN; grid.tile_count()],
                    });
                }
                signatures.as_mut().map(|s| s.hashes.chunks_mut(grid.tiles_x as usize))
            } else {
                *signatures = None;
                None
            };
            per_signatures.push(rows);
            per_image.push(data_bands(desc, data, grid.tile_height as usize).into_iter());
        }
        let mut bands = Vec::new();
        for ty in 0..grid.tiles_y {
            let slices: Vec<Option<Vec<&mut [u8]>>> = per_image.iter_mut().map(|a| a.next()).collect();
            let signatures: Vec<Option<&mut [u64]>> =
                per_signatures.iter_mut().map(|s| s.as_mut().and_then(|rows| rows.next())).collect();
            if (ty0..=ty1).contains(&ty) {
                bands.push((ty, slices, signatures));
            }
        }
        let plan = FlushPlan {
            resolved,
            draws: self.pass_draws,
            ops,
            resolve: last,
            samples: self.samples,
            hsr: self.hsr,
            early_z: self.early_z,
            vertex_shading: frame.vertex_shading(),
            overdraw: self.totals.overdraw.is_some(),
            texture_cache: self.texture_cache,
            vertex_cache: self.vertex_cache,
            simd: self.simd,
        };
        let spec: Vec<_> = resolved.attachments.iter().map(|a| (a.format, resolved.samples)).collect();
        // One band a job: a band's cost follows what the picture holds there (a model in the
        // middle rows, sky above), and coarser jobs can leave one worker with the heavy rows
        // while the other idles at the end of the pass.
        let results: Vec<BandResult> = bands
            .into_par_iter()
            .with_max_len(1)
            .map_init(
                || Worker {
                    buffer: TileBuffer::new(grid.tile_width, grid.tile_height, &spec),
                    visibility: plan.hsr.then(|| Visibility::new(grid.tile_width, grid.tile_height, resolved.samples)),
                    tile_vertices: Default::default(),
                },
                |worker, (ty, slices, signatures)| render_band(frame, &plan, worker, ty, slices, signatures, tx0..=tx1),
            )
            .collect();
        for band in results {
            self.totals.add_tally(&band.tally);
            self.totals.on_chip_bytes += band.on_chip_bytes;
            self.totals.ledger.merge(&band.ledger);
            self.transaction_elimination_saved += band.eliminated_bytes;
            for (index, stats) in band.tiles {
                let t = &mut self.tiles[index];
                t.list_entries += stats.list_entries;
                t.fragments_shaded += stats.fragments_shaded;
                t.bytes_loaded += stats.bytes_loaded;
                t.bytes_stored += stats.bytes_stored;
            }
        }
        self.totals.ledger.add(Category::FrameDataWrite, frame.bytes().total());
        match kind {
            Flush::Incremental => self.totals.counters.incremental_renders += 1,
            Flush::SubpassSplit => self.totals.counters.subpass_splits += 1,
            Flush::Final => {}
        }
        self.flushes += 1;
    }
}

/// Whether a draw's primitives carry the same varyings at their three vertices, so that the
/// frame data can keep one vertex's (`StateRecord::flat_only`): every varying flat, and no
/// point coordinate written per corner of a point's square.
fn flat_only(desc: &crate::api::pipeline::PipelineDesc, varying_count: usize) -> bool {
    use crate::api::pipeline::Interpolation;
    varying_count > 0
        && desc.varyings.len() == varying_count
        && desc.point_coord_varying.is_none()
        && desc.varyings.iter().all(|v| *v == Interpolation::Flat)
}
