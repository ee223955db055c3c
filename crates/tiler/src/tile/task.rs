//! The tile task: the life of each tile of a band — load, the polygon list by draw, store,
//! resolve — and what it moved. Backends decide the order of work (`backend::tbr` bins and
//! flushes); every tile of every flush goes through [`render_band`].

use crate::binning::frame_data::FrameData;
use crate::depth::hsr::Visibility;
use crate::geometry::VertexShading;
use crate::ledger::{Category, Ledger, TileStats};
use crate::pass::Draw;
use crate::pass::resolved::ResolvedPass;
use crate::pixel::primitive::{FragmentTally, OverdrawRows};
use crate::raster::PixelRect;
use crate::raster::samples::SampleLocations;
use crate::raster::target::band_surface;
use crate::raster::target::{RenderTarget, Surface};
use crate::shade::ShadeContext;
use crate::shade::texture_cache::TextureCacheConfig;
use crate::tile::buffer::TileBuffer;
use crate::tile::list::{render_hsr, render_in_order};
use crate::tile::load_store::{
    AttachmentOps, TileStart, apply_load, apply_resolve, apply_store, fill_value, load_bytes, resolved_value,
    store_bytes, store_bytes_of, tile_signature, tile_start,
};

/// What one band of tiles did.
#[derive(Default)]
pub(crate) struct BandResult {
    pub(crate) tally: FragmentTally,
    pub(crate) ledger: Ledger,
    pub(crate) tiles: Vec<(usize, TileStats)>,
    /// Tile-buffer bytes moved by loads, stores and resolves.
    pub(crate) on_chip_bytes: u64,
    /// Bytes of stores skipped by transaction elimination.
    pub(crate) eliminated_bytes: u64,
}

/// Per-worker tile memory.
pub(crate) struct Worker {
    pub(crate) buffer: TileBuffer,
    pub(crate) visibility: Option<Visibility>,
    /// Scratch for counting the vertices a tile shades again (position-only binning).
    pub(crate) tile_vertices: std::collections::HashSet<(u32, u32)>,
}

/// What a flush does beyond the frame data.
pub(crate) struct FlushPlan<'a> {
    pub(crate) resolved: &'a ResolvedPass,
    /// The pass's draws: the tile phase finds each state record's pipeline here.
    pub(crate) draws: &'a [Draw],
    pub(crate) ops: Vec<AttachmentOps>,
    pub(crate) resolve: bool,
    pub(crate) samples: SampleLocations,
    pub(crate) hsr: bool,
    pub(crate) early_z: bool,
    pub(crate) vertex_shading: VertexShading,
    pub(crate) overdraw: bool,
    pub(crate) texture_cache: TextureCacheConfig,
    /// The vertex cache a tile re-fetches its vertices through (`VertexShading::PerTile`).
    pub(crate) vertex_cache: crate::ledger::cache::CacheConfig,
    pub(crate) simd: crate::simd::SimdSupport,
}

/// Renders the tiles `columns` of tile row `ty`.
pub(crate) fn render_band<'a>(
    frame: &FrameData,
    plan: &FlushPlan,
    worker: &mut Worker,
    ty: u32,
    slices: Vec<Option<Vec<&'a mut [u8]>>>,
    mut signatures: Vec<Option<&'a mut [u64]>>,
    columns: std::ops::RangeInclusive<u32>,
) -> BandResult {
    let resolved = plan.resolved;
    let grid = frame.grid();
    let band_y0 = (ty * grid.tile_height) as i32;
    let formats = resolved
        .attachments
        .iter()
        .map(|a| a.format)
        .chain(resolved.resolves.iter().map(|r| resolved.attachments[r.color].format));
    let mut images: Vec<Option<Surface>> = slices
        .into_iter()
        .zip(formats)
        .map(|(s, format)| s.map(|s| band_surface(format, grid.width, band_y0, s)))
        .collect();
    let (attachment_images, resolve_images) = images.split_at_mut(resolved.attachments.len());
    let mut result = BandResult::default();
    result.tally.context = ShadeContext::with_texture_cache(plan.texture_cache);
    result.tally.simd = plan.simd;
    if plan.overdraw {
        let rows = (grid.tile_height as i32).min(grid.height as i32 - band_y0);
        result.tally.overdraw = Some(OverdrawRows::new(band_y0, grid.width, rows as u32));
    }
    let starts: Vec<TileStart> =
        resolved.attachments.iter().zip(&plan.ops).map(|(a, ops)| tile_start(a.format, ops)).collect();
    // A tile no primitive touches can skip the tile buffer: its stores write the load ops'
    // values (or what was loaded) straight to memory. Same bytes, same ledger.
    let untouched_fast = signatures.iter().all(Option::is_none)
        && starts.iter().all(|s| *s != TileStart::Mixed)
        && resolved.resolves.iter().all(|r| !plan.resolve || matches!(starts[r.color], TileStart::Value(_)));
    let mut pending: Option<PixelRect> = None;
    for tx in columns {
        let tile = grid.tile_rect(tx, ty);
        let rect = tile.intersect(&resolved.render_area);
        if rect.is_empty() {
            continue;
        }
        let list = &frame.lists()[grid.index(tx, ty)];
        if untouched_fast && list.is_empty() {
            let mut stats = TileStats::default();
            let mut resolve_bytes = 0;
            for (a, attachment) in resolved.attachments.iter().enumerate() {
                let has_image = attachment_images[a].is_some();
                let samples = resolved.samples as usize;
                stats.bytes_loaded += load_bytes(attachment.format, samples, has_image, &rect, &plan.ops[a]).loaded;
                if has_image {
                    stats.bytes_stored += store_bytes_of(attachment.format, samples, &rect, &plan.ops[a]);
                }
            }
            if plan.resolve {
                for (r, target) in resolved.resolves.iter().enumerate() {
                    let format = resolved.attachments[target.color].format;
                    let bytes = rect.area() * format.bytes_per_sample() as u64;
                    resolve_bytes += bytes;
                    result.on_chip_bytes += bytes * resolved.samples as u64;
                    debug_assert!(resolve_images[r].is_some());
                }
            }
            finish_tile(&mut result, grid.index(tx, ty), stats, resolve_bytes, 0, 0);
            // Neighbouring untouched tiles are written in one go.
            pending = Some(match pending {
                Some(run) if run.x1 == rect.x0 => PixelRect::new(run.x0, run.y0, rect.x1, run.y1),
                Some(run) => {
                    fill_untouched(plan, &starts, attachment_images, resolve_images, &run);
                    rect
                }
                None => rect,
            });
            continue;
        }
        if let Some(run) = pending.take() {
            fill_untouched(plan, &starts, attachment_images, resolve_images, &run);
        }
        let images =
            BandImages { attachments: attachment_images, resolves: resolve_images, signatures: &mut signatures };
        render_tile(
            frame,
            plan,
            worker,
            &mut result,
            images,
            TileJob { tx, index: grid.index(tx, ty), tile, rect, list },
        );
    }
    if let Some(run) = pending.take() {
        fill_untouched(plan, &starts, attachment_images, resolve_images, &run);
    }
    result
}

/// Writes what untouched tiles over `rect` store: each attachment's load-op value where it
/// is stored, and its resolve.
fn fill_untouched(
    plan: &FlushPlan,
    starts: &[TileStart],
    attachment_images: &mut [Option<Surface>],
    resolve_images: &mut [Option<Surface>],
    rect: &PixelRect,
) {
    let resolved = plan.resolved;
    for (a, attachment) in resolved.attachments.iter().enumerate() {
        let Some(image) = attachment_images[a].as_mut() else { continue };
        let stored = store_bytes_of(attachment.format, resolved.samples as usize, rect, &plan.ops[a]) > 0;
        if stored && let TileStart::Value(pattern) = starts[a] {
            fill_value(image, rect, &pattern);
        }
    }
    if plan.resolve {
        for (r, target) in resolved.resolves.iter().enumerate() {
            let image = resolve_images[r].as_mut().expect("resolve targets have memory");
            let TileStart::Value(pattern) = starts[target.color] else { unreachable!("only cleared colour") };
            fill_value(image, rect, &resolved_value(image.format, resolved.samples as usize, &pattern));
        }
    }
}

/// The ledger and statistics of a rendered tile.
fn finish_tile(
    result: &mut BandResult,
    index: usize,
    mut stats: TileStats,
    resolve_bytes: u64,
    frame_data_read: u64,
    fragments_shaded: u32,
) {
    result.on_chip_bytes += stats.bytes_loaded + stats.bytes_stored;
    stats.bytes_stored += resolve_bytes;
    result.ledger.add(Category::TileLoad, stats.bytes_loaded);
    result.ledger.add(Category::TileStore, stats.bytes_stored - resolve_bytes);
    result.ledger.add(Category::Resolve, resolve_bytes);
    result.ledger.add(Category::FrameDataRead, frame_data_read);
    result.tally.counters.tiles_processed += 1;
    result.tally.counters.polygon_list_entries += stats.list_entries as u64;
    stats.fragments_shaded = fragments_shaded;
    result.tiles.push((index, stats));
}

/// One tile to render: its column, its index in the grid, its rectangle, the part of it inside
/// the render area, and its polygon list.
struct TileJob<'f> {
    tx: u32,
    index: usize,
    tile: PixelRect,
    rect: PixelRect,
    list: &'f [u32],
}

/// The band's views of external memory a tile loads from and stores to.
struct BandImages<'s, 'a> {
    attachments: &'s mut [Option<Surface<'a>>],
    resolves: &'s mut [Option<Surface<'a>>],
    /// Per attachment, the band's tile signatures (transaction elimination).
    signatures: &'s mut [Option<&'a mut [u64]>],
}

/// A tile's whole life: load ops into the tile buffer; the list by subpass and by draw (in
/// order, or with HSR); under position-only binning the vertices it shades again; store ops
/// (skipped for a tile stored unchanged, under transaction elimination); resolves. The ledger's
/// `TileLoad`, `TileStore`, `Resolve` and `FrameDataRead` are counted here (in
/// [`finish_tile`]) and nowhere else for a touched tile.
fn render_tile(
    frame: &FrameData,
    plan: &FlushPlan,
    worker: &mut Worker,
    result: &mut BandResult,
    images: BandImages,
    job: TileJob,
) {
    let resolved = plan.resolved;
    let list = job.list;
    let mut stats = TileStats::default();
    let mut surfaces = worker.buffer.surfaces(&job.tile);
    for (a, surface) in surfaces.iter_mut().enumerate() {
        stats.bytes_loaded += apply_load(surface, images.attachments[a].as_ref(), &job.rect, &plan.ops[a]).loaded;
    }

    // The list is in submission order, so each subpass's primitives are one run of it.
    let shaded_before = result.tally.counters.fragments_shaded;
    let mut start = 0;
    while start < list.len() {
        let mut states = frame.state_cursor();
        let subpass = frame.states()[states.state_of(list[start]) as usize].subpass;
        let run = list[start..]
            .iter()
            .take_while(|&&e| frame.states()[states.state_of(e) as usize].subpass == subpass)
            .count();
        let entries = &list[start..start + run];
        let mut target = RenderTarget::for_subpass(
            &mut surfaces,
            &resolved.subpasses[subpass as usize],
            plan.samples,
            job.rect,
            plan.early_z,
        );
        match worker.visibility.as_mut() {
            Some(visibility) => {
                render_hsr(entries, frame, plan.draws, &mut target, &mut result.tally, visibility, &job.tile)
            }
            None => render_in_order(entries, frame, plan.draws, &mut target, &mut result.tally),
        }
        // Input attachments of the next subpass, stores, resolves and signatures read the
        // depth bytes: the fills the block summary deferred are written now.
        for surface in surfaces.iter_mut() {
            surface.write_deferred();
        }
        start += run;
    }
    let frame_data_read = frame.bytes_read_by(list);
    if plan.vertex_shading == VertexShading::PerTile {
        // Position-only binning: the tile fetches and shades each vertex it uses again, in
        // the order its primitives name them, through a vertex cache of its own.
        worker.tile_vertices.clear();
        let mut cache = crate::ledger::cache::ReadCache::new(plan.vertex_cache);
        let mut bytes = 0;
        for &entry in list {
            let primitive = &frame.primitives()[entry as usize];
            let state = &frame.states()[primitive.state as usize];
            for id in primitive.vertex_ids {
                if worker.tile_vertices.insert((state.draw, id)) {
                    bytes += state.fetch.fetch(state.fetch.vertex_of_slot(id), &mut cache);
                }
            }
        }
        result.tally.counters.vertices_shaded += worker.tile_vertices.len() as u64;
        result.ledger.add(Category::VertexFetch, bytes);
    }

    for (a, surface) in surfaces.iter().enumerate() {
        let Some(image) = images.attachments[a].as_mut() else { continue };
        let bytes = store_bytes(surface, &job.rect, &plan.ops[a]);
        if bytes > 0
            && let Some(row) = images.signatures[a].as_mut()
        {
            // Transaction elimination: a tile stored unchanged is not written again.
            let signature = tile_signature(surface, &job.rect);
            if row[job.tx as usize] == signature {
                result.eliminated_bytes += bytes;
                continue;
            }
            row[job.tx as usize] = signature;
        }
        stats.bytes_stored += apply_store(surface, image, &job.rect, &plan.ops[a]);
    }
    let mut resolve_bytes = 0;
    if plan.resolve {
        for (r, target) in resolved.resolves.iter().enumerate() {
            let image = images.resolves[r].as_mut().expect("resolve targets have memory");
            let pixels = apply_resolve(&surfaces[target.color], image, &job.rect);
            resolve_bytes += pixels * image.format.bytes_per_sample() as u64;
            result.on_chip_bytes += pixels * image.format.bytes_per_sample() as u64 * resolved.samples as u64;
        }
    }
    let shaded = (result.tally.counters.fragments_shaded - shaded_before) as u32;
    stats.list_entries = list.len() as u32;
    finish_tile(result, job.index, stats, resolve_bytes, frame_data_read, shaded);
}
