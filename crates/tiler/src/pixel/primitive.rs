//! The fragment pipeline for one primitive in one region (a tile, or a band of the
//! framebuffer): coverage → early depth/stencil → shading → discard and coverage changes →
//! late depth/stencil → blending and colour writes. Every backend calls this same code; they
//! differ only in which region they hand it, whether that region lives in the tile buffer or
//! in external memory, and — for hidden-surface removal — in splitting the work into a
//! visibility pass and a shading pass ([`Mode`]).
//!
//! Work goes block by block (8×8 pixels, classified outside / partial / full), then 4×2 group
//! by group: eight lanes, two 2×2 quads, every sample of each.
//!
//! Early-Z: when the fragment shader neither discards, nor writes depth or the sample mask,
//! nor has side effects, and alpha-to-coverage is off, the depth and stencil tests (and their
//! writes) run before shading, in submission order, so fragments that fail are never shaded.
//! Otherwise the tests run after shading, on the coverage the shader left.

use crate::api::format::{ColorWrites, Format};
use crate::api::pipeline::{ColorTargetState, DepthStencilState, MAX_COLOR_ATTACHMENTS, PipelineDesc};
use crate::api::shader::ShaderProperties;
use crate::depth;
use crate::depth::hsr::Visibility;
use crate::geometry::primitive::Primitive;
use crate::ledger::framebuffer::{Aspect, FramebufferTraffic};
use crate::ledger::{Category, Counters, DrawStats, Ledger};
use crate::raster::PixelRect;
use crate::raster::coverage::{BLOCK_SIZE, BlockCoverage, Coverage, PrimitiveCoverage, block_rect_mask, group_lanes};
use crate::raster::samples::MAX_SAMPLES;
use crate::raster::samples::SampleLocations;
use crate::raster::target::{BlockDepth, RenderTarget, Surface};
use crate::shade::ShadeContext;
use crate::shade::fragments::{FragmentShader, Fragments};
use crate::shade::interpolate::Interpolator;
use crate::simd::{
    F32x8, LANE_DX, LANE_DY, LANES, LaneMask, SimdLevel, SimdSupport, Vec4x8, array_from_fn, per_simd_level,
};

/// What the fragment work of one task did and moved.
#[derive(Debug, Default)]
pub struct FragmentTally {
    pub counters: Counters,
    /// Immediate-mode framebuffer traffic (empty for tilers, whose traffic is at load/store).
    pub ledger: Ledger,
    pub context: ShadeContext,
    /// Per-draw figures, indexed by the draw's position in its pass.
    pub draws: Vec<DrawStats>,
    /// The draw whose primitive is being rasterized (set by the caller).
    pub draw: usize,
    /// Hidden-surface removal: fragments that passed the tests and claimed samples, not yet
    /// known to survive until shading.
    pub hsr_candidates: u64,
    /// Where depth, stencil and colour accesses go, and what they cost.
    pub framebuffer: FramebufferTraffic,
    /// Fragments shaded per pixel of the task's rows, when an overdraw map is wanted.
    pub overdraw: Option<OverdrawRows>,
    /// The fragment shader's colour outputs for the current group (kept here, not copied
    /// around: 512 bytes per group).
    pub(crate) outputs: [Vec4x8; MAX_COLOR_ATTACHMENTS],
    /// The instruction set the pipeline runs with, detected on this processor.
    pub simd: SimdSupport,
}

/// Fragments shaded per pixel over some rows of the framebuffer.
#[derive(Clone, Debug, Default)]
pub struct OverdrawRows {
    pub y0: i32,
    pub width: u32,
    pub counts: Vec<u16>,
}

impl OverdrawRows {
    pub fn new(y0: i32, width: u32, rows: u32) -> OverdrawRows {
        OverdrawRows { y0, width, counts: vec![0; width as usize * rows as usize] }
    }

    #[inline]
    fn add(&mut self, x: i32, y: i32) {
        let i = (y - self.y0) as usize * self.width as usize + x as usize;
        self.counts[i] = self.counts[i].saturating_add(1);
    }

    /// Adds these rows into a whole-framebuffer map.
    pub fn add_to(&self, map: &mut [u16]) {
        let start = self.y0 as usize * self.width as usize;
        for (m, c) in map[start..start + self.counts.len()].iter_mut().zip(&self.counts) {
            *m = m.saturating_add(*c);
        }
    }
}

impl FragmentTally {
    /// The stats of the current draw.
    #[inline]
    pub(crate) fn draw_stats(&mut self) -> &mut DrawStats {
        if self.draws.len() <= self.draw {
            self.draws.resize(self.draw + 1, DrawStats::default());
        }
        &mut self.draws[self.draw]
    }
}

/// Which part of the fragment pipeline to run.
pub enum Mode<'a> {
    /// Everything, in submission order (TBR, IMR, and TBDR's fallback).
    InOrder,
    /// Hidden-surface removal, pass one: coverage and the depth/stencil tests with their
    /// writes, no shading; samples that pass are claimed for the primitive's entry if `claims`.
    Resolve { visibility: &'a mut Visibility, claims: bool },
    /// Hidden-surface removal, pass two: shade and write the samples each primitive's entry
    /// owns.
    Shade { visibility: &'a Visibility },
}

/// Primitives of one draw handed to the pixel pipeline in one call, in order.
#[derive(Clone, Copy)]
pub struct PrimitiveRun<'a> {
    pub primitives: &'a [Primitive],
    /// Where each primitive's varyings are (`Primitive::varyings` is an offset into this).
    pub varyings: &'a [f32],
    /// Which primitives: indices into `primitives` (every one when `None`).
    pub indices: Option<&'a [u32]>,
    /// Floats from one vertex's varyings to the next: the varying count, or 0 when the
    /// varyings hold one vertex per primitive (`StateRecord::flat_only`).
    pub vertex_stride: usize,
    /// The entry (position in the tile's list) of the first primitive; the others follow it.
    /// Hidden-surface removal claims samples by entry.
    pub first_entry: u32,
}

impl<'a> PrimitiveRun<'a> {
    /// Every primitive of `primitives`, with three vertices' varyings each
    /// (`varying_count` floats a vertex).
    pub fn all(primitives: &'a [Primitive], varyings: &'a [f32], varying_count: usize) -> PrimitiveRun<'a> {
        PrimitiveRun { primitives, varyings, indices: None, first_entry: 0, vertex_stride: varying_count }
    }

    /// The primitives `indices` of `primitives`, the first being entry `first_entry`; one
    /// vertex's varyings follow the other's `vertex_stride` floats on.
    pub fn entries(
        primitives: &'a [Primitive],
        varyings: &'a [f32],
        indices: &'a [u32],
        first_entry: u32,
        vertex_stride: usize,
    ) -> PrimitiveRun<'a> {
        PrimitiveRun { primitives, varyings, indices: Some(indices), first_entry, vertex_stride }
    }
}

/// How one colour attachment is written, prepared once per run of primitives.
#[derive(Clone, Copy)]
struct ColorPlan {
    state: ColorTargetState,
    /// Byte mask of the channels written (see `Format::write_mask_bytes`).
    mask: [u8; 16],
    /// Some channel of the format is not written: the old value must be read and merged.
    partial: bool,
}

/// Where the shader is evaluated within each pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ShadePoint {
    /// The pixel centre (one invocation per pixel).
    Centre,
    /// Sample `s` (per-sample shading).
    Sample(usize),
}

/// What the fragment shader produced for a group besides its colours (which stay in
/// [`FragmentTally::outputs`]).
struct ShadeOutput {
    depth: F32x8,
    discarded: LaneMask,
    sample_mask: [u32; 8],
}

/// How many list entries ahead [`rasterize`] prefetches primitive records.
const PREFETCH_RECORDS: usize = 8;
/// How many list entries ahead [`rasterize`] prefetches varyings (their records were
/// prefetched `PREFETCH_RECORDS - PREFETCH_VARYINGS` entries earlier).
const PREFETCH_VARYINGS: usize = 4;

/// Rasterizes the primitives of `run` into `target`, in order, running the part of the
/// pipeline `mode` says. What depends only on the draw and the target is worked out once.
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn rasterize<F: FragmentShader>(
    shader: &F,
    desc: &PipelineDesc,
    run: &PrimitiveRun,
    target: &mut RenderTarget,
    tally: &mut FragmentTally,
    mode: &mut Mode,
) {
    let plan = RasterPlan::new(shader, desc, target, tally);
    let count = run.indices.map_or(run.primitives.len(), <[u32]>::len);
    // A primitive's varyings: three vertices `vertex_stride` apart.
    let varying_span = 2 * run.vertex_stride + plan.varying_count;
    for position in 0..count {
        let index = run.indices.map_or(position, |indices| indices[position] as usize);
        if let Some(indices) = run.indices {
            // A tile's entries name records far apart: fetch the records a few entries ahead,
            // and the varyings of nearer ones (whose records arrived already), so the misses
            // overlap instead of each stalling its primitive (docs/benchmarking.md,
            // "Primitive records").
            if let Some(&ahead) = indices.get(position + PREFETCH_RECORDS) {
                crate::simd::prefetch(&run.primitives[ahead as usize], std::mem::size_of::<Primitive>());
            }
            if let Some(&near) = indices.get(position + PREFETCH_VARYINGS) {
                let offset = run.primitives[near as usize].varyings as usize;
                crate::simd::prefetch(run.varyings.as_ptr().wrapping_add(offset), 4 * varying_span);
            }
        }
        let primitive = &run.primitives[index];
        let rect = primitive.bbox.intersect(&target.clip);
        if rect.is_empty() {
            continue;
        }
        let start = primitive.varyings as usize;
        let interpolator = Interpolator::new(primitive);
        // Only for primitives whose box spans two blocks each way: a smaller one (tris's
        // triangles, a few pixels) seldom covers a block whose summary decides, and the check
        // cost tris 2.4% of its instructions (docs/benchmarking.md, "Early Z and HSR: flat
        // blocks in the pipeline"). Either way the results are those of `depth::test_block`.
        let large = rect.x1 - rect.x0 >= 2 * BLOCK_SIZE && rect.y1 - rect.y0 >= 2 * BLOCK_SIZE;
        let flat_depth = match (plan.block_tests && large, interpolator.constant_depth(), &target.depth_stencil) {
            (true, Some(z), Some(surface)) => Some(depth::flat_depth_bits(surface.format, z)),
            _ => None,
        };
        let raster = PrimitiveRaster {
            plan: &plan,
            primitive,
            varyings: &run.varyings[start..start + varying_span],
            vertex_stride: run.vertex_stride,
            coverage: PrimitiveCoverage::new(&primitive.edges(), &plan.locations),
            interpolator,
            flat_depth,
            entry: run.first_entry + position as u32,
        };
        raster.run(&rect, target, tally, mode);
    }
}

/// What the pixel pipeline does for every primitive of a draw on a target.
struct RasterPlan<'a, F> {
    shader: &'a F,
    desc: &'a PipelineDesc,
    properties: ShaderProperties,
    varying_count: usize,
    locations: SampleLocations,
    /// The pipeline's sample mask: bit `s` set when sample `s` may be written.
    static_samples: u32,
    sample_shading: bool,
    tests: bool,
    early_tests: bool,
    /// The tests can run on whole blocks ([`depth::test_block`]).
    block_tests: bool,
    colors: [Option<ColorPlan>; MAX_COLOR_ATTACHMENTS],
    /// Some attachment or input lives in external memory (immediate mode).
    external: bool,
    /// The common case, run block by block without per-sample bookkeeping: one sample, tests
    /// (if any) before shading on whole blocks, coverage the shader cannot change, and colour
    /// outputs that replace 4-byte values in memory that needs no addresses.
    single_sample_fast: bool,
}

impl<'a, F: FragmentShader> RasterPlan<'a, F> {
    fn new(shader: &'a F, desc: &'a PipelineDesc, target: &RenderTarget, tally: &FragmentTally) -> Self {
        let properties = shader.properties();
        let ds = &desc.depth_stencil;
        let tests = match &target.depth_stencil {
            Some(surface) => ds.depth_test || (ds.stencil_test && surface.format.has_stencil()),
            None => false,
        };
        let mut colors = [None; MAX_COLOR_ATTACHMENTS];
        for (i, state) in desc.color_targets.iter().enumerate() {
            if let Some(surface) = &target.color[i] {
                let format = surface.format;
                let mask = format.write_mask_bytes(state.write_mask);
                let bytes = format.bytes_per_sample();
                if state.write_mask != ColorWrites::NONE && mask[..bytes].iter().any(|b| *b != 0) {
                    // GL ES 3.0 §4.1.7: blending is off for an integer attachment; its values
                    // are stored as the shader gives them.
                    let state =
                        ColorTargetState { blend: if format.is_integer() { None } else { state.blend }, ..*state };
                    colors[i] = Some(ColorPlan { state, mask, partial: mask[..bytes].iter().any(|b| *b != 0xff) });
                }
            }
        }
        let samples = target.samples.count();
        let coverage_changes =
            properties.discards || properties.writes_sample_mask || desc.multisample.alpha_to_coverage;
        let block_tests = tests
            && match &target.depth_stencil {
                Some(surface) => depth::block_test_applies(surface, ds, &tally.framebuffer),
                None => false,
            };
        // Seed 002 ("Avoid operations that disable early-Z") lists what moves the depth and
        // stencil tests after shading: discard and sample-mask writes (coverage changes), depth
        // written by the shader, storage writes (side effects), and blending combined with depth
        // writes. (Depth bounds, the last case it lists, does not exist here.)
        let blends_with_depth_write = ds.depth_test
            && ds.depth_write
            && target.depth_stencil.as_ref().is_some_and(|s| s.format.has_depth())
            && colors.iter().flatten().any(|plan| plan.state.blend.is_some());
        let early_tests = tests
            && target.early_z
            && !(coverage_changes || properties.writes_depth || properties.side_effects || blends_with_depth_write);
        let simple_colors = colors.iter().zip(&target.color).all(|(plan, surface)| match (plan, surface) {
            (Some(plan), Some(surface)) => {
                plan.state.blend.is_none()
                    && !plan.partial
                    && surface.format.pack_lanes_u32(&[F32x8::ZERO; 4]).is_some()
            }
            _ => true,
        });
        let single_sample_fast = samples == 1
            && desc.multisample.sample_mask & 1 != 0
            && !(coverage_changes || properties.writes_depth)
            && (!tests || (early_tests && block_tests))
            && simple_colors
            && !tally.framebuffer.needs_addresses();
        RasterPlan {
            shader,
            desc,
            properties,
            varying_count: desc.varyings.len(),
            locations: target.samples,
            static_samples: desc.multisample.sample_mask,
            sample_shading: desc.multisample.sample_shading && samples > 1,
            tests,
            early_tests,
            block_tests,
            single_sample_fast,
            colors,
            external: target.color.iter().chain([&target.depth_stencil]).flatten().any(|s| s.is_external())
                || target.inputs.iter().flatten().any(|s| s.is_external()),
        }
    }
}

/// One primitive going through the pipeline under its draw's plan (whose fields it
/// dereferences to).
struct PrimitiveRaster<'p, 'a, F> {
    plan: &'p RasterPlan<'a, F>,
    primitive: &'p Primitive,
    varyings: &'p [f32],
    /// Floats from one vertex's varyings to the next (see [`PrimitiveRun::vertex_stride`]).
    vertex_stride: usize,
    coverage: PrimitiveCoverage<'p>,
    interpolator: Interpolator,
    /// The depth bits of a flat primitive (both depth gradients zero) when the draw's tests
    /// run on whole blocks: converted once, not per block ([`depth::settle_flat_block`]).
    flat_depth: Option<BlockDepth>,
    /// The primitive's entry, for hidden-surface removal.
    entry: u32,
}

impl<'a, F> std::ops::Deref for PrimitiveRaster<'_, 'a, F> {
    type Target = RasterPlan<'a, F>;
    fn deref(&self) -> &RasterPlan<'a, F> {
        self.plan
    }
}

impl<F: FragmentShader> PrimitiveRaster<'_, '_, F> {
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn run(&self, rect: &PixelRect, target: &mut RenderTarget, tally: &mut FragmentTally, mode: &mut Mode) {
        let samples = self.locations.count();
        let block_tests = self.block_tests;
        // Pass one of hidden-surface removal for a flat primitive over whole blocks: the
        // rectangle classified at once, and each block it covers wholly decided by its depth
        // summary without rasterizing (see `resolve_covered`).
        if block_tests
            && whole_rects()
            && let Some(fragment) = self.flat_depth
            && let Mode::Resolve { visibility, claims } = mode
            && (rect.x0 | rect.y0 | rect.x1 | rect.y1) & (BLOCK_SIZE - 1) == 0
            // (A row's blocks are bits of a word; tiles are at most 256 pixels, 32 blocks.)
            && rect.x1 - rect.x0 <= 64 * BLOCK_SIZE
            && self.static_samples & low_bits(samples) == low_bits(samples)
        {
            match self.coverage.classify_rect(rect) {
                BlockCoverage::Outside => return,
                BlockCoverage::Full => {
                    return self.resolve_covered(rect, fragment, visibility, *claims, target, tally);
                }
                BlockCoverage::Partial => {}
            }
        }
        // A primitive narrower or shorter than a block covers no block wholly, and a block it
        // misses gets an empty mask from `block_mask` anyway: its blocks go to the masks
        // without being classified first (tris' triangles, a few pixels across). The masks are
        // the same either way: a wholly covered block's mask is its clip mask. Shading after
        // hidden-surface removal takes the clip mask without the edges (ownership implies
        // coverage), so only the classification keeps it out of blocks the primitive misses.
        let small = rect.x1 - rect.x0 < BLOCK_SIZE || rect.y1 - rect.y0 < BLOCK_SIZE;
        let classify = !small || matches!(mode, Mode::Shade { .. });
        let mut by = rect.y0 & !(BLOCK_SIZE - 1);
        while by < rect.y1 {
            let mut bx = rect.x0 & !(BLOCK_SIZE - 1);
            while bx < rect.x1 {
                let class =
                    if classify { self.coverage.classify_block(bx, by, BLOCK_SIZE) } else { BlockCoverage::Partial };
                if class != BlockCoverage::Outside {
                    let clip = block_rect_mask(bx, by, rect);
                    let rows = (rect.y0 - by).max(0)..(rect.y1 - by).min(BLOCK_SIZE);
                    let mut masks = [0u64; MAX_SAMPLES];
                    let mut any = 0u64;
                    for (s, mask) in masks[..samples].iter_mut().enumerate() {
                        if self.static_samples >> s & 1 == 0 {
                            continue;
                        }
                        *mask = match (class, &mode) {
                            // Ownership implies coverage: no need to rasterize again.
                            (_, Mode::Shade { .. }) | (BlockCoverage::Full, _) => clip,
                            _ => clip & self.coverage.block_mask(bx, by, s, rows.clone()),
                        };
                        any |= *mask;
                    }
                    if any != 0 {
                        self.block(bx, by, &mut masks, any, block_tests, target, tally, mode);
                    }
                }
                bx += BLOCK_SIZE;
            }
            by += BLOCK_SIZE;
        }
    }

    /// Pass one of hidden-surface removal ([`Mode::Resolve`]) for this primitive, flat at depth
    /// `fragment`, over `rect` (block-aligned), every sample of which it covers and may write:
    /// each block settled or filled from its depth summary as [`PrimitiveRaster::block`] would
    /// ([`depth::settle_flat_block`], [`depth::fill_flat_block`]), with the same counts, and
    /// the blocks that pass claimed a row of blocks at a time ([`Visibility::claim_rect`]) when
    /// all of the row pass. A block the summary cannot decide goes through
    /// [`PrimitiveRaster::block`]. On TBDR overdraw (32 full-screen layers) this replaces 16
    /// classifications, mask builds, calls and claims a tile and layer by one pass over the
    /// tile's summaries (docs/benchmarking.md, "Whole covered tiles in HSR").
    #[allow(clippy::too_many_arguments)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn resolve_covered(
        &self,
        rect: &PixelRect,
        fragment: BlockDepth,
        visibility: &mut Visibility,
        claims: bool,
        target: &mut RenderTarget,
        tally: &mut FragmentTally,
    ) {
        #[cfg(test)]
        WHOLE_RECTS_TAKEN.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let samples = self.locations.count();
        let state = &self.desc.depth_stencil;
        let (mut decided, mut passed) = (0u64, 0u64);
        let mut by = rect.y0;
        while by < rect.y1 {
            // Bit `c` set: the block in column `c` of the row passed (and is to be claimed).
            let (mut row_passed, mut row_all) = (0u64, true);
            let mut bx = rect.x0;
            while bx < rect.x1 {
                let column = ((bx - rect.x0) / BLOCK_SIZE) as u32;
                let outcome = target.depth_stencil.as_mut().and_then(|surface| {
                    let (traffic, ledger) = (&mut tally.framebuffer, &mut tally.ledger);
                    flat_covered_block(surface, bx, by, samples, state, fragment, traffic, ledger)
                });
                match outcome {
                    Some(pass) => {
                        decided += 1;
                        passed += pass as u64;
                        row_passed |= (pass as u64) << column;
                        row_all &= pass;
                    }
                    None => {
                        row_all = false;
                        let mut masks = [0u64; MAX_SAMPLES];
                        masks[..samples].fill(u64::MAX);
                        let mut mode = Mode::Resolve { visibility: &mut *visibility, claims };
                        self.block(bx, by, &mut masks, u64::MAX, true, target, tally, &mut mode);
                    }
                }
                bx += BLOCK_SIZE;
            }
            if claims && row_all {
                let rows = PixelRect::new(rect.x0, by, rect.x1, by + BLOCK_SIZE);
                for s in 0..samples {
                    visibility.claim_rect(s, &rows, self.entry);
                }
            } else if claims {
                while row_passed != 0 {
                    let x = rect.x0 + BLOCK_SIZE * row_passed.trailing_zeros() as i32;
                    for s in 0..samples {
                        visibility.claim_block(s, x, by, u64::MAX, self.entry);
                    }
                    row_passed &= row_passed - 1;
                }
            }
            by += BLOCK_SIZE;
        }
        // What `block` counts for each decided block: 64 pixels rasterized, each passing or
        // killed as its block does.
        let pixels = (BLOCK_SIZE * BLOCK_SIZE) as u64;
        let counters = &mut tally.counters;
        counters.fragments_rasterized += decided * pixels;
        counters.fragments_early_z_killed += (decided - passed) * pixels;
        counters.fragments_passed += passed * pixels;
        if claims {
            tally.hsr_candidates += passed * pixels;
        }
        if decided != 0 {
            tally.draw_stats().samples_passed += passed * pixels * samples as u64;
        }
    }

    /// The fragment pipeline for the 8×8 block at `(x, y)`, whose covered pixels of sample `s`
    /// are `masks[s]` (`any` their union). Depth tests that can run before shading run for the
    /// whole block at once where [`depth::test_block`] applies; the rest goes group by group.
    // Kept flat (measured code, not style): a pixel-pipeline kernel inlined into every shader's
    // loop and run per 8×8 block. Its arguments are the block's position, coverage masks and test
    // choice and the state it updates, which no single owner holds together; a parameter struct
    // would be assembled per call in the hottest loop, and its code generation was tuned with the
    // kernel bench.
    #[allow(clippy::too_many_arguments)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn block(
        &self,
        x: i32,
        y: i32,
        masks: &mut [u64; MAX_SAMPLES],
        any: u64,
        block_tests: bool,
        target: &mut RenderTarget,
        tally: &mut FragmentTally,
        mode: &mut Mode,
    ) {
        let samples = self.locations.count();
        match mode {
            Mode::InOrder if self.single_sample_fast => self.single_sample_block(x, y, masks[0], target, tally),
            Mode::InOrder if self.early_tests && block_tests && !self.sample_shading => {
                tally.counters.fragments_rasterized += any.count_ones() as u64;
                self.test_block(x, y, &mut masks[..samples], target, tally);
                let left = masks[..samples].iter().fold(0, |a, m| a | m);
                tally.counters.fragments_early_z_killed += (any.count_ones() - left.count_ones()) as u64;
                for (gx, gy, coverage) in self.groups(x, y, masks) {
                    self.in_order(gx, gy, coverage, ShadePoint::Centre, false, target, tally);
                }
            }
            Mode::Resolve { visibility, claims } if block_tests => {
                tally.counters.fragments_rasterized += any.count_ones() as u64;
                self.test_block(x, y, &mut masks[..samples], target, tally);
                let left = masks[..samples].iter().fold(0, |a, m| a | m);
                tally.counters.fragments_early_z_killed += (any.count_ones() - left.count_ones()) as u64;
                tally.counters.fragments_passed += left.count_ones() as u64;
                let passed_samples: u32 = masks[..samples].iter().map(|m| m.count_ones()).sum();
                tally.draw_stats().samples_passed += passed_samples as u64;
                if *claims {
                    tally.hsr_candidates += left.count_ones() as u64;
                    for (s, mask) in masks[..samples].iter().enumerate() {
                        visibility.claim_block(s, x, y, *mask, self.entry);
                    }
                }
            }
            Mode::Shade { visibility } => {
                for (s, mask) in masks[..samples].iter_mut().enumerate() {
                    if *mask != 0 {
                        *mask &= visibility.owned_block(s, x, y, self.entry);
                    }
                }
                for (gx, gy, owned) in self.groups(x, y, masks) {
                    if self.sample_shading {
                        for s in 0..samples {
                            let one = owned.only_sample(s);
                            if !one.is_empty() {
                                self.shade_owned(gx, gy, one, ShadePoint::Sample(s), target, tally);
                            }
                        }
                    } else {
                        self.shade_owned(gx, gy, owned, ShadePoint::Centre, target, tally);
                    }
                }
            }
            _ => {
                for (gx, gy, coverage) in self.groups(x, y, masks) {
                    self.group(gx, gy, coverage, target, tally, mode);
                }
            }
        }
    }

    /// The fragment pipeline of a single-sample block in the common case
    /// ([`RasterPlan::single_sample_fast`]): the same work and counts as group by group, with
    /// the bookkeeping done once per block.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn single_sample_block(&self, x: i32, y: i32, covered: u64, target: &mut RenderTarget, tally: &mut FragmentTally) {
        tally.counters.fragments_rasterized += covered.count_ones() as u64;
        let mut mask = [covered];
        if self.tests {
            self.test_block(x, y, &mut mask, target, tally);
            tally.counters.fragments_early_z_killed += (covered.count_ones() - mask[0].count_ones()) as u64;
        }
        let passed = mask[0];
        if passed == 0 {
            return;
        }
        for gy in [0, 2, 4, 6] {
            if (passed >> (8 * gy)) & 0xffff == 0 {
                continue;
            }
            for gx in [0, 4] {
                let lanes = group_lanes(passed, gx, gy);
                if lanes.is_empty() {
                    continue;
                }
                self.shade(x + gx, y + gy, lanes, ShadePoint::Centre, target, tally);
                for (i, plan) in self.colors.iter().enumerate() {
                    if let (Some(_), Some(surface)) = (plan, target.color[i].as_mut()) {
                        write_packed(surface, x + gx, y + gy, lanes, &tally.outputs[i]);
                    }
                }
            }
        }
        let count = passed.count_ones() as u64;
        tally.counters.fragments_passed += count;
        let stats = tally.draw_stats();
        stats.fragments_shaded += count;
        stats.samples_passed += count;
        for (plan, surface) in self.colors.iter().zip(&target.color) {
            if let (Some(_), Some(surface)) = (plan, surface) {
                let bytes = surface.format.bytes_per_sample() as u32;
                tally.framebuffer.accesses(&mut tally.ledger, Aspect::Color, bytes, count, true);
            }
        }
    }

    /// The 4×2 groups of the block at `(x, y)` with covered samples: their top-left pixels
    /// and coverage, in order (no closures: the caller's loop body stays inline, which keeps it
    /// compiled for the dispatched instruction set).
    #[inline(always)]
    fn groups(
        &self,
        x: i32,
        y: i32,
        masks: &[u64; MAX_SAMPLES],
    ) -> impl Iterator<Item = (i32, i32, Coverage)> + use<F> {
        let samples = self.locations.count();
        let any = masks[..samples].iter().fold(0, |a, m| a | m);
        let mut list = [(0, 0, Coverage::NONE); 8];
        let mut len = 0;
        for gy in [0, 2, 4, 6] {
            if (any >> (8 * gy)) & 0xffff == 0 {
                continue;
            }
            for gx in [0, 4] {
                if group_lanes(any, gx, gy).is_empty() {
                    continue;
                }
                let mut lanes = [0u8; MAX_SAMPLES];
                for (lanes, mask) in lanes[..samples].iter_mut().zip(masks) {
                    *lanes = group_lanes(*mask, gx, gy).0;
                }
                list[len] = (x + gx, y + gy, Coverage::from_samples(lanes));
                len += 1;
            }
        }
        list.into_iter().take(len)
    }

    /// The early depth test of a whole block (see [`block_tests`]).
    #[inline(always)]
    fn test_block(&self, x: i32, y: i32, masks: &mut [u64], target: &mut RenderTarget, tally: &mut FragmentTally) {
        if let (Some(fragment), Some(surface)) = (self.flat_depth, target.depth_stencil.as_ref()) {
            let (traffic, ledger) = (&mut tally.framebuffer, &mut tally.ledger);
            match depth::settle_flat_block(surface, x, y, masks, &self.desc.depth_stencil, fragment, traffic, ledger) {
                depth::FlatBlock::Settled => return,
                depth::FlatBlock::Fill(index, stored) => {
                    return flat_fills(x, y, index, stored, fragment, target, tally);
                }
                depth::FlatBlock::Test => {}
            }
        }
        block_tests(&self.test_inputs(), x, y, masks, target, tally);
    }

    /// What the depth and stencil tests of this primitive read.
    #[inline(always)]
    fn test_inputs(&self) -> TestInputs<'_> {
        TestInputs {
            state: &self.desc.depth_stencil,
            interpolator: &self.interpolator,
            locations: &self.locations,
            front_facing: self.primitive.front_facing,
        }
    }

    /// The fragment pipeline for the covered samples of the 4×2 group at `(x, y)`.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn group(
        &self,
        x: i32,
        y: i32,
        coverage: Coverage,
        target: &mut RenderTarget,
        tally: &mut FragmentTally,
        mode: &mut Mode,
    ) {
        match mode {
            Mode::InOrder => {
                tally.counters.fragments_rasterized += coverage.lanes().count() as u64;
                if self.sample_shading {
                    for s in 0..self.locations.count() {
                        let one = coverage.only_sample(s);
                        if !one.is_empty() {
                            self.in_order(x, y, one, ShadePoint::Sample(s), self.early_tests, target, tally);
                        }
                    }
                } else {
                    self.in_order(x, y, coverage, ShadePoint::Centre, self.early_tests, target, tally);
                }
            }
            Mode::Resolve { visibility, claims } => {
                tally.counters.fragments_rasterized += coverage.lanes().count() as u64;
                self.resolve(x, y, coverage, target, tally, visibility, self.entry, *claims);
            }
            Mode::Shade { .. } => unreachable!("blocks shade the samples they own"),
        }
    }

    /// In-order rendering of the covered samples; `early_tests` runs the depth and stencil
    /// tests before shading (false when they ran already, or must run after).
    // Kept flat (measured code, not style): a pixel-pipeline kernel inlined into every shader's
    // loop and run per 4×2 group. Its arguments are the group's position, coverage and shading
    // point and the state it updates, which no single owner holds together; a parameter struct
    // would be assembled per call in the hottest loop, and its code generation was tuned with the
    // kernel bench.
    #[allow(clippy::too_many_arguments)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn in_order(
        &self,
        x: i32,
        y: i32,
        mut coverage: Coverage,
        at: ShadePoint,
        early_tests: bool,
        target: &mut RenderTarget,
        tally: &mut FragmentTally,
    ) {
        let rasterized = coverage.lanes();
        if early_tests {
            coverage = self.test(x, y, coverage, None, target, tally);
            tally.counters.fragments_early_z_killed += (rasterized.count() - coverage.lanes().count()) as u64;
        }
        let live = coverage.lanes();
        if live.is_empty() {
            return;
        }
        let out = self.shade(x, y, live, at, target, tally);

        if self.properties.discards {
            let discarded = out.discarded & live;
            tally.counters.fragments_discarded += discarded.count() as u64;
            coverage = coverage.restrict(!discarded);
        }
        if self.properties.writes_sample_mask {
            coverage = Coverage(coverage.0 & lane_sample_masks(&out.sample_mask, self.locations.count()).0);
        }
        if self.desc.multisample.alpha_to_coverage {
            coverage = Coverage(coverage.0 & alpha_to_coverage(tally.outputs[0][3], self.locations.count()).0);
        }
        if self.tests && !self.early_tests && !coverage.is_empty() {
            let before = coverage.lanes().count();
            let depth = self.properties.writes_depth.then_some(out.depth);
            coverage = self.test(x, y, coverage, depth, target, tally);
            tally.counters.fragments_late_killed += (before - coverage.lanes().count()) as u64;
        }

        let passed = coverage.lanes();
        tally.counters.fragments_passed += passed.count() as u64;
        let stats = tally.draw_stats();
        stats.fragments_shaded += live.count() as u64;
        stats.samples_passed += coverage.count() as u64;
        if !passed.is_empty() {
            self.write_colors(x, y, coverage, target, tally);
        }
    }

    /// HSR pass one: the tests, and claims on the samples that pass.
    // Kept flat (measured code, not style): a pixel-pipeline kernel inlined into every shader's
    // loop and run per 4×2 group. Its arguments are the group's position, coverage and HSR claim
    // and the state it updates, which no single owner holds together; a parameter struct would be
    // assembled per call in the hottest loop, and its code generation was tuned with the kernel
    // bench.
    #[allow(clippy::too_many_arguments)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn resolve(
        &self,
        x: i32,
        y: i32,
        mut coverage: Coverage,
        target: &mut RenderTarget,
        tally: &mut FragmentTally,
        visibility: &mut Visibility,
        entry: u32,
        claims: bool,
    ) {
        let rasterized = coverage.lanes().count();
        if self.tests {
            coverage = self.test(x, y, coverage, None, target, tally);
            tally.counters.fragments_early_z_killed += (rasterized - coverage.lanes().count()) as u64;
        }
        let passed = coverage.lanes();
        tally.counters.fragments_passed += passed.count() as u64;
        tally.draw_stats().samples_passed += coverage.count() as u64;
        if claims {
            tally.hsr_candidates += passed.count() as u64;
            for s in 0..self.locations.count() {
                let lanes = coverage.sample(s);
                for lane in 0..LANES {
                    if lanes.contains(lane) {
                        visibility.claim(s, x + LANE_DX[lane] as i32, y + LANE_DY[lane] as i32, entry);
                    }
                }
            }
        }
    }

    /// HSR pass two: shade and write the samples this primitive owns.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn shade_owned(
        &self,
        x: i32,
        y: i32,
        owned: Coverage,
        at: ShadePoint,
        target: &mut RenderTarget,
        tally: &mut FragmentTally,
    ) {
        let live = owned.lanes();
        self.shade(x, y, live, at, target, tally);
        tally.draw_stats().fragments_shaded += live.count() as u64;
        self.write_colors(x, y, owned, target, tally);
    }

    /// Runs the fragment shader on the lanes of the group (`live` are covered, the rest of
    /// their quads are helpers).
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn shade(
        &self,
        x: i32,
        y: i32,
        live: LaneMask,
        at: ShadePoint,
        target: &RenderTarget,
        tally: &mut FragmentTally,
    ) -> ShadeOutput {
        let (dx, dy) = match at {
            ShadePoint::Centre => (0.5, 0.5),
            ShadePoint::Sample(s) => {
                let (sx, sy) = self.locations.offset(s);
                let scale = crate::raster::fixed::SUBPIXEL_SCALE as f32;
                (sx as f32 / scale, sy as f32 / scale)
            }
        };
        let (px, py) = Interpolator::positions(x, y, dx, dy);
        let (l1, l2) = self.interpolator.lambdas(px, py);
        let depth = self.interpolator.depth(px, py);
        let (b1, b2) = self.interpolator.perspective(l1, l2);
        // Outputs the shader does not write read as zero, whatever ran before.
        for output in &mut tally.outputs[..self.desc.color_targets.len()] {
            *output = [F32x8::ZERO; 4];
        }
        let mut frag = Fragments {
            x: px,
            y: py,
            z: depth,
            b1,
            b2,
            l1,
            l2,
            varyings: self.varyings,
            vertex_stride: self.vertex_stride,
            front_facing: self.primitive.front_facing,
            covered: live,
            color: &mut tally.outputs,
            written_depth: depth,
            discarded: LaneMask::NONE,
            sample_mask: [u32::MAX; 8],
            group: (x, y),
            sample: match at {
                ShadePoint::Centre => 0,
                ShadePoint::Sample(s) => s,
            },
            inputs: target.inputs,
            locals: target.color.each_ref().map(|c| c.as_deref()),
            input_bytes: 0,
            local_bytes: 0,
            context: &mut tally.context,
            simd: tally.simd,
        };
        self.shader.shade(&mut frag);
        let (input_bytes, local_bytes) = (frag.input_bytes, frag.local_bytes);
        let out = ShadeOutput { depth: frag.written_depth, discarded: frag.discarded, sample_mask: frag.sample_mask };
        // Reads of attachments: from the tile buffer on a tiler; from memory in immediate mode,
        // where an input attachment is an image the earlier subpass stored (a texture read).
        if self.external {
            tally.ledger.add(Category::TextureFetch, input_bytes);
            tally.ledger.add(Category::ImrColorRead, local_bytes);
        } else {
            tally.framebuffer.on_chip_bytes += input_bytes + local_bytes;
        }
        tally.counters.fragments_shaded += live.count() as u64;
        tally.counters.helper_invocations += (live.quads().count() - live.count()) as u64;
        if let Some(overdraw) = tally.overdraw.as_mut() {
            for lane in 0..LANES {
                if live.contains(lane) {
                    overdraw.add(x + LANE_DX[lane] as i32, y + LANE_DY[lane] as i32);
                }
            }
        }
        out
    }

    /// Depth and stencil tests of the covered samples (see [`group_tests`]).
    #[inline(always)]
    fn test(
        &self,
        x: i32,
        y: i32,
        coverage: Coverage,
        shader_depth: Option<F32x8>,
        target: &mut RenderTarget,
        tally: &mut FragmentTally,
    ) -> Coverage {
        group_tests(&self.test_inputs(), x, y, coverage, shader_depth, target, tally)
    }

    /// Blends and writes the colour outputs (see [`write_colors`]).
    #[inline(always)]
    fn write_colors(&self, x: i32, y: i32, coverage: Coverage, target: &mut RenderTarget, tally: &mut FragmentTally) {
        write_colors(&self.colors, self.desc.blend_constant, x, y, coverage, target, tally);
    }
}

// The stages below do not depend on the fragment shader. Each is compiled once per SIMD level
// (a dispatcher, never inlined, calls the AVX2 copy or the baseline copy of its body) instead of
// being inlined into every shader's pipeline: the shaders' pipelines call them once per group or
// block. That keeps the code monomorphised per shader type small, which is most of the release
// build's time, at the cost of a call per group (measured: docs/benchmarking.md).

/// What the depth and stencil tests of a primitive read.
#[derive(Clone, Copy)]
struct TestInputs<'a> {
    state: &'a DepthStencilState,
    interpolator: &'a Interpolator,
    locations: &'a SampleLocations,
    front_facing: bool,
}

per_simd_level! {
    /// Depth and stencil tests of the `coverage` of the group at `(x, y)`; `shader_depth` replaces
    /// the interpolated depth when the shader wrote one. Returns the samples that passed.
    fn group_tests / group_tests_avx2 => group_tests_body, simd: tally.simd, (
        inputs: &TestInputs,
        x: i32,
        y: i32,
        coverage: Coverage,
        shader_depth: Option<F32x8>,
        target: &mut RenderTarget,
        tally: &mut FragmentTally,
    ) -> Coverage
}

#[inline(always)]
fn group_tests_body(
    inputs: &TestInputs,
    x: i32,
    y: i32,
    coverage: Coverage,
    shader_depth: Option<F32x8>,
    target: &mut RenderTarget,
    tally: &mut FragmentTally,
) -> Coverage {
    let surface = target.depth_stencil.as_mut().expect("tests need a depth-stencil attachment");
    let multisampled = inputs.locations.count() > 1;
    depth::test_group(
        surface,
        x,
        y,
        coverage,
        inputs.state,
        inputs.front_facing,
        |s| match shader_depth {
            Some(z) => z,
            None if multisampled => {
                let (px, py) = Interpolator::sample_positions(x, y, inputs.locations.offset(s));
                inputs.interpolator.depth(px, py)
            }
            None => {
                let (px, py) = Interpolator::positions(x, y, 0.5, 0.5);
                inputs.interpolator.depth(px, py)
            }
        },
        &mut tally.framebuffer,
        &mut tally.ledger,
    )
}

/// Whether pass one may take a wholly covered rectangle at once
/// ([`PrimitiveRaster::resolve_covered`]); tests turn it off to hold the block-by-block path to it.
#[cfg(test)]
pub(crate) static WHOLE_RECTS: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(true);

/// Rectangles [`PrimitiveRaster::resolve_covered`] took (for the tests).
#[cfg(test)]
pub(crate) static WHOLE_RECTS_TAKEN: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

#[inline(always)]
fn whole_rects() -> bool {
    #[cfg(test)]
    return WHOLE_RECTS.load(std::sync::atomic::Ordering::Relaxed);
    #[cfg(not(test))]
    true
}

/// The first `n` bits set.
#[inline(always)]
fn low_bits(n: usize) -> u32 {
    if n >= 32 { u32::MAX } else { (1 << n) - 1 }
}

/// The early depth test of the 8×8 block at `(x, y)`, every one of its `samples` samples
/// covered, by a flat primitive at depth `fragment`, when the block's depth summary decides it
/// ([`depth::settle_flat_block`], then [`depth::fill_flat_block`] for a block that passes and
/// takes the depth): whether the block passes, or `None` when it must be tested sample by
/// sample. The same accesses as [`PrimitiveRaster::test_block`] counts.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn flat_covered_block(
    surface: &mut Surface,
    x: i32,
    y: i32,
    samples: usize,
    state: &DepthStencilState,
    fragment: BlockDepth,
    traffic: &mut FramebufferTraffic,
    ledger: &mut Ledger,
) -> Option<bool> {
    let mut masks = [u64::MAX; MAX_SAMPLES];
    match depth::settle_flat_block(surface, x, y, &mut masks[..samples], state, fragment, traffic, ledger) {
        // Every mask kept (all pass) or cleared (all fail).
        depth::FlatBlock::Settled => Some(masks[0] != 0),
        depth::FlatBlock::Fill(index, stored) => {
            depth::fill_flat_block(surface, x, y, index, stored, fragment, traffic, ledger);
            Some(true)
        }
        depth::FlatBlock::Test => None,
    }
}

per_simd_level! {
    /// The early depth test of the 8×8 block at `(x, y)` (see [`depth::test_block`]): `masks[s]`
    /// keeps the pixels of sample `s` that pass.
    fn block_tests / block_tests_avx2 => block_tests_body, simd: tally.simd, (
        inputs: &TestInputs,
        x: i32,
        y: i32,
        masks: &mut [u64],
        target: &mut RenderTarget,
        tally: &mut FragmentTally,
    )
}

#[inline(always)]
fn block_tests_body(
    inputs: &TestInputs,
    x: i32,
    y: i32,
    masks: &mut [u64],
    target: &mut RenderTarget,
    tally: &mut FragmentTally,
) {
    let surface = target.depth_stencil.as_mut().expect("tests need a depth-stencil attachment");
    let depths = BlockDepths { interpolator: inputs.interpolator, locations: inputs.locations, x };
    depth::test_block(surface, x, y, masks, inputs.state, &depths, &mut tally.framebuffer, &mut tally.ledger);
}

per_simd_level! {
    /// Fills the 8×8 block at `(x, y)` with a flat primitive's depth (see
    /// [`depth::fill_flat_block`]).
    fn flat_fills / flat_fills_avx2 => flat_fills_body, simd: tally.simd, (
        x: i32,
        y: i32,
        index: usize,
        stored: BlockDepth,
        fragment: BlockDepth,
        target: &mut RenderTarget,
        tally: &mut FragmentTally,
    )
}

#[inline(always)]
fn flat_fills_body(
    x: i32,
    y: i32,
    index: usize,
    stored: BlockDepth,
    fragment: BlockDepth,
    target: &mut RenderTarget,
    tally: &mut FragmentTally,
) {
    let surface = target.depth_stencil.as_mut().expect("tests need a depth-stencil attachment");
    depth::fill_flat_block(surface, x, y, index, stored, fragment, &mut tally.framebuffer, &mut tally.ledger);
}

per_simd_level! {
    /// Blends and writes the colour outputs of the group at `(x, y)` (in
    /// [`FragmentTally::outputs`]) to the covered samples of every attachment `colors` writes.
    fn write_colors / write_colors_avx2 => write_colors_body, simd: tally.simd, (
        colors: &[Option<ColorPlan>; MAX_COLOR_ATTACHMENTS],
        constant: [f32; 4],
        x: i32,
        y: i32,
        coverage: Coverage,
        target: &mut RenderTarget,
        tally: &mut FragmentTally,
    )
}

#[inline(always)]
fn write_colors_body(
    colors: &[Option<ColorPlan>; MAX_COLOR_ATTACHMENTS],
    constant: [f32; 4],
    x: i32,
    y: i32,
    coverage: Coverage,
    target: &mut RenderTarget,
    tally: &mut FragmentTally,
) {
    let FragmentTally { outputs, framebuffer, ledger, simd, .. } = tally;
    for (i, plan) in colors.iter().enumerate() {
        let (Some(plan), Some(surface)) = (plan, target.color[i].as_mut()) else { continue };
        write_color(surface, x, y, coverage, &outputs[i], plan, constant, framebuffer, ledger, *simd);
    }
}

/// The fragment depths of a block's rows: at pixel centres with one sample, at each sample's
/// location with several (the same values the group-by-group tests use).
struct BlockDepths<'a> {
    interpolator: &'a Interpolator,
    locations: &'a SampleLocations,
    x: i32,
}

impl depth::RowDepths for BlockDepths<'_> {
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn row(&self, sample: usize, y: i32) -> F32x8 {
        let (dx, dy) = if self.locations.count() > 1 {
            let (sx, sy) = self.locations.offset(sample);
            let scale = crate::raster::fixed::SUBPIXEL_SCALE as f32;
            (sx as f32 / scale, sy as f32 / scale)
        } else {
            (0.5, 0.5)
        };
        self.interpolator.row_depth(self.x, y, dx, dy)
    }

    #[cfg_attr(not(debug_assertions), inline(always))]
    fn constant(&self) -> Option<f32> {
        self.interpolator.constant_depth()
    }

    #[cfg_attr(not(debug_assertions), inline(always))]
    fn bounds(&self, x: i32, y: i32) -> Option<F32x8> {
        if let Some(z) = self.interpolator.constant_depth() {
            return Some(F32x8::splat(z));
        }
        // The offsets `row` uses, least and greatest over the samples.
        let (dx, dy) = if self.locations.count() > 1 {
            let scale = crate::raster::fixed::SUBPIXEL_SCALE as f32;
            let (mut dx, mut dy) = ([f32::INFINITY, f32::NEG_INFINITY], [f32::INFINITY, f32::NEG_INFINITY]);
            for s in 0..self.locations.count() {
                let (sx, sy) = self.locations.offset(s);
                let (sx, sy) = (sx as f32 / scale, sy as f32 / scale);
                (dx, dy) = ([dx[0].min(sx), dx[1].max(sx)], [dy[0].min(sy), dy[1].max(sy)]);
            }
            (dx, dy)
        } else {
            ([0.5; 2], [0.5; 2])
        };
        self.interpolator.depth_corners(x, y, dx, dy)
    }
}

/// Per-lane sample masks as coverage.
fn lane_sample_masks(masks: &[u32; 8], samples: usize) -> Coverage {
    let mut c = Coverage::NONE;
    for s in 0..samples {
        let mut lanes = 0u8;
        for (lane, mask) in masks.iter().enumerate() {
            lanes |= ((mask >> s & 1) as u8) << lane;
        }
        c.set_sample(s, LaneMask(lanes));
    }
    c
}

/// Alpha-to-coverage: a lane keeps its first `round(clamp(alpha) × samples)` samples
/// (Vulkan leaves the pattern to the implementation; this one is deterministic and ordered).
fn alpha_to_coverage(alpha: F32x8, samples: usize) -> Coverage {
    let masks: [u32; 8] = std::array::from_fn(|lane| {
        let a = alpha.lane(lane);
        let a = if a > 0.0 { a.min(1.0) } else { 0.0 };
        let kept = (a * samples as f32 + 0.5) as u32;
        if kept >= 32 { u32::MAX } else { (1u32 << kept) - 1 }
    });
    lane_sample_masks(&masks, samples)
}

/// Writes a 4-byte colour (no blending, every channel) to the `lanes` of the group at `(x, y)`
/// of a single-sample surface.
#[inline(always)]
fn write_packed(surface: &mut Surface, x: i32, y: i32, lanes: LaneMask, color: &Vec4x8) {
    let packed = surface.format.pack_lanes_u32(color).expect("a 4-byte UNORM8 format");
    let rows = [surface.offset(x, y), surface.offset(x, y + 1)];
    store_packed(surface.plane_mut(0), rows, lanes, &packed);
}

/// Stores the packed 4-byte colours of the `lanes` of a group whose two rows start at bytes
/// `rows` of `plane`: a whole row of four as one 16-byte copy.
#[inline(always)]
fn store_packed(plane: &mut [u8], rows: [usize; 2], lanes: LaneMask, packed: &[u32; LANES]) {
    for (row, offset) in rows.into_iter().enumerate() {
        let bits = lanes.0 >> (4 * row) & 0xf;
        let words = &packed[4 * row..4 * row + 4];
        if bits == 0xf {
            let mut quad = [0u8; 16];
            for (chunk, word) in quad.chunks_exact_mut(4).zip(words) {
                chunk.copy_from_slice(&word.to_le_bytes());
            }
            plane[offset..offset + 16].copy_from_slice(&quad);
        } else if bits != 0 {
            for (i, word) in words.iter().enumerate() {
                if bits >> i & 1 != 0 {
                    plane[offset + 4 * i..offset + 4 * i + 4].copy_from_slice(&word.to_le_bytes());
                }
            }
        }
    }
}

/// Counts the colour traffic of writing the covered samples of a group (`written` of them),
/// each read first when `reads` (blending, partial write masks): by address when the device
/// caches the framebuffer, else as a number of accesses.
// Kept flat (measured code, not style): a pixel-pipeline kernel inlined into every shader's loop
// and run per 4×2 group and attachment. Its arguments are the group's position, coverage and counts
// and the state it updates, which no single owner holds together; a parameter struct would be
// assembled per call in the hottest loop, and its code generation was tuned with the kernel bench.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn count_color_traffic(
    surface: &Surface,
    x: i32,
    y: i32,
    coverage: Coverage,
    written: u64,
    reads: bool,
    traffic: &mut FramebufferTraffic,
    ledger: &mut Ledger,
) {
    let bytes = surface.format.bytes_per_sample() as u32;
    if traffic.needs_addresses() {
        for s in 0..surface.samples() {
            for lane in 0..LANES {
                if coverage.sample(s).contains(lane) {
                    let address = surface.address(s, x + LANE_DX[lane] as i32, y + LANE_DY[lane] as i32);
                    if reads {
                        traffic.access(ledger, Aspect::Color, address, bytes, false);
                    }
                    traffic.access(ledger, Aspect::Color, address, bytes, true);
                }
            }
        }
    } else {
        if reads {
            traffic.accesses(ledger, Aspect::Color, bytes, written, false);
        }
        traffic.accesses(ledger, Aspect::Color, bytes, written, true);
    }
}

/// Blends and writes one colour attachment for the covered samples of a group.
// Kept flat (measured code, not style): a pixel-pipeline kernel inlined into every shader's loop
// and run per 4×2 group and attachment. Its arguments are the group's position, coverage, colour
// and plan and the state it updates, which no single owner holds together; a parameter struct would
// be assembled per call in the hottest loop, and its code generation was tuned with the kernel
// bench.
#[allow(clippy::too_many_arguments)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn write_color(
    surface: &mut Surface,
    x: i32,
    y: i32,
    coverage: Coverage,
    color: &Vec4x8,
    plan: &ColorPlan,
    constant: [f32; 4],
    traffic: &mut FramebufferTraffic,
    ledger: &mut Ledger,
    simd: SimdSupport,
) {
    let reads = plan.state.blend.is_some() || plan.partial;
    if !reads && let Some(packed) = surface.format.pack_lanes_u32(color) {
        // The common case: a 4-byte colour replacing what is there.
        let rows = [surface.offset(x, y), surface.offset(x, y + 1)];
        let mut written = 0u64;
        for s in 0..surface.samples() {
            let lanes = coverage.sample(s);
            written += lanes.count() as u64;
            store_packed(surface.plane_mut(s), rows, lanes, &packed);
        }
        count_color_traffic(surface, x, y, coverage, written, false, traffic, ledger);
        return;
    }
    blend_and_write(simd, surface, x, y, coverage, color, plan, constant, traffic, ledger);
}

/// [`write_color`] past its common case (blending, write masks, formats of other sizes): not
/// generic, so compiled once per SIMD level for every shader, not inlined into each.
// Kept flat: the same arguments as `write_color`, forwarded once per SIMD level.
#[allow(clippy::too_many_arguments)]
#[inline(never)]
fn blend_and_write(
    simd: SimdSupport,
    surface: &mut Surface,
    x: i32,
    y: i32,
    coverage: Coverage,
    color: &Vec4x8,
    plan: &ColorPlan,
    constant: [f32; 4],
    traffic: &mut FramebufferTraffic,
    ledger: &mut Ledger,
) {
    match simd.level() {
        #[cfg(target_arch = "x86_64")]
        SimdLevel::Avx2 => {
            // SAFETY: a `SimdSupport` of level `Avx2` exists only when this processor has
            // every feature `blend_and_write_avx2` is compiled with (`SimdSupport::detect`).
            unsafe { blend_and_write_avx2(surface, x, y, coverage, color, plan, constant, traffic, ledger) }
        }
        _ => blend_and_write_body(surface, x, y, coverage, color, plan, constant, traffic, ledger),
    }
}

/// [`blend_and_write_body`] compiled for AVX2.
// Kept flat: `blend_and_write_body`'s arguments, compiled for AVX2.
#[allow(clippy::too_many_arguments)]
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
unsafe fn blend_and_write_avx2(
    surface: &mut Surface,
    x: i32,
    y: i32,
    coverage: Coverage,
    color: &Vec4x8,
    plan: &ColorPlan,
    constant: [f32; 4],
    traffic: &mut FramebufferTraffic,
    ledger: &mut Ledger,
) {
    blend_and_write_body(surface, x, y, coverage, color, plan, constant, traffic, ledger)
}

// Kept flat (measured code, not style): a pixel-pipeline kernel inlined into every shader's loop
// and run per 4×2 group and attachment. Its arguments are the group's position, coverage, colour
// and plan and the state it updates, which no single owner holds together; a parameter struct would
// be assembled per call in the hottest loop, and its code generation was tuned with the kernel
// bench.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn blend_and_write_body(
    surface: &mut Surface,
    x: i32,
    y: i32,
    coverage: Coverage,
    color: &Vec4x8,
    plan: &ColorPlan,
    constant: [f32; 4],
    traffic: &mut FramebufferTraffic,
    ledger: &mut Ledger,
) {
    let format = surface.format;
    let bytes = format.bytes_per_sample();
    let rows = [surface.offset(x, y), surface.offset(x, y + 1)];
    let reads = plan.state.blend.is_some() || plan.partial;
    let clamp = format.is_normalized();
    let mut packed = [[0u8; 16]; LANES];
    let src = match plan.state.blend {
        // Normalised attachments blend a source clamped to [0, 1] (Vulkan).
        Some(_) if clamp => color.map(|c| c.clamp(0.0, 1.0)),
        _ => *color,
    };
    if plan.state.blend.is_none() {
        // Every sample of a pixel gets the same packed value.
        format.encode_lanes(&src, &mut packed);
    }
    let constant = if clamp { constant.map(|c| c.clamp(0.0, 1.0)) } else { constant };
    if format == Format::Rgba8Unorm
        && !plan.partial
        && let Some(blend) = &plan.state.blend
        && let Some(written) = blend_rgba8(surface, rows, coverage, &src, blend, constant)
    {
        count_color_traffic(surface, x, y, coverage, written, reads, traffic, ledger);
        return;
    }
    let mut written = 0u64;
    for s in 0..surface.samples() {
        let lanes = coverage.sample(s);
        if lanes.is_empty() {
            continue;
        }
        written += lanes.count() as u64;
        let plane = surface.plane_mut(s);
        if let Some(blend) = &plan.state.blend {
            let mut dst = [[0.0f32; LANES]; 4];
            for lane in 0..LANES {
                if lanes.contains(lane) {
                    let offset = rows[lane / 4] + (lane % 4) * bytes;
                    let value = format.decode_color(&plane[offset..offset + bytes]);
                    for c in 0..4 {
                        dst[c][lane] = value[c];
                    }
                }
            }
            let out = crate::blend::blend_lanes(blend, &src, &dst.map(F32x8::from_array), constant);
            format.encode_lanes(&out, &mut packed);
        }
        for lane in 0..LANES {
            if !lanes.contains(lane) {
                continue;
            }
            let offset = rows[lane / 4] + (lane % 4) * bytes;
            let stored = &mut plane[offset..offset + bytes];
            if plan.partial {
                for ((old, new), m) in stored.iter_mut().zip(&packed[lane][..bytes]).zip(&plan.mask) {
                    *old = (new & m) | (*old & !m);
                }
            } else {
                stored.copy_from_slice(&packed[lane][..bytes]);
            }
        }
    }
    count_color_traffic(surface, x, y, coverage, written, reads, traffic, ledger);
}

/// [`blend_and_write_body`]'s blend of an RGBA8 attachment written whole, eight lanes at a
/// time: each sample's two rows of four pixels read as words, decoded (`c / 255`, what
/// `Format::decode_color`'s table holds), blended and packed (`Format::pack_lanes_u32`, the
/// bytes of `encode_lanes`), and each row written back whole, the covered lanes' new words
/// beside the other lanes' old ones — the same bytes as lane by lane (the lanes not covered are
/// blended from what memory holds and dropped, where the general path blends zeros). Returns the samples written, or `None`, with nothing written,
/// when a row of the group leaves the planes (a group at the right edge of a surface whose
/// width is not a multiple of four).
#[inline(always)]
fn blend_rgba8(
    surface: &mut Surface,
    rows: [usize; 2],
    coverage: Coverage,
    src: &Vec4x8,
    blend: &crate::api::pipeline::BlendState,
    constant: [f32; 4],
) -> Option<u64> {
    const ROW: usize = 4 * 4;
    let samples = surface.samples();
    // Every plane has the same length.
    let first = (0..samples).find(|&s| !coverage.sample(s).is_empty())?;
    let plane_len = surface.plane_mut(first).len();
    if rows.iter().any(|&r| r + ROW > plane_len) {
        return None;
    }
    let mut written = 0;
    for s in first..samples {
        let lanes = coverage.sample(s);
        if lanes.is_empty() {
            continue;
        }
        written += lanes.count() as u64;
        let plane = surface.plane_mut(s);
        // The two rows of four words, each one 16-byte read (`rows` fit, checked above).
        let row = |r: usize| -> [u8; ROW] { plane[r..r + ROW].try_into().expect("a row of four pixels") };
        let bytes = [row(rows[0]), row(rows[1])];
        let words: [u32; LANES] = array_from_fn(|lane| {
            let at = (lane % 4) * 4;
            u32::from_le_bytes(bytes[lane / 4][at..at + 4].try_into().expect("a word"))
        });
        let dst: Vec4x8 =
            array_from_fn(|c| F32x8::from_fn(|lane| ((words[lane] >> (8 * c)) & 0xff) as f32) / F32x8::splat(255.0));
        let out = crate::blend::blend_lanes(blend, src, &dst, constant);
        let packed = Format::Rgba8Unorm.pack_lanes_u32(&out).expect("RGBA8 packs to words");
        // The covered lanes' new words, the others' old ones: each row one 16-byte write.
        let merged: [u32; LANES] = array_from_fn(|lane| if lanes.contains(lane) { packed[lane] } else { words[lane] });
        for (half, &r) in rows.iter().enumerate() {
            let mut out = [0u8; ROW];
            for (i, chunk) in out.chunks_exact_mut(4).enumerate() {
                chunk.copy_from_slice(&merged[4 * half + i].to_le_bytes());
            }
            plane[r..r + ROW].copy_from_slice(&out);
        }
    }
    Some(written)
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;
    use crate::api::pipeline::{BlendComponent, BlendFactor, BlendOp, BlendState};
    use crate::simd::SimdLevel;

    fn component() -> impl Strategy<Value = BlendComponent> {
        let factor = || prop::sample::select(BlendFactor::ALL.to_vec());
        (factor(), factor(), prop::sample::select(BlendOp::ALL.to_vec())).prop_map(|(src, dst, op)| BlendComponent {
            src,
            dst,
            op,
        })
    }

    fn channel() -> impl Strategy<Value = f32> {
        prop_oneof![4 => 0.0f32..1.0, 1 => -2.0f32..3.0, 1 => Just(f32::NAN), 1 => Just(1.0), 1 => Just(0.0)]
    }

    proptest! {
        /// Blending into an RGBA8 attachment (the eight-lane path) stores, lane for lane, what
        /// the scalar rules give: the stored bytes decoded, `blend_pixel` of the clamped
        /// source (a NaN lane clamped to 0, as the pipeline clamps colours), encoded; lanes and samples not covered keep their bytes. Groups at every
        /// position of a surface 10 pixels wide, whose last group leaves the rows (the
        /// general path).
        #[test]
        fn rgba8_blending_is_the_scalar_rules(
            (color, alpha) in (component(), component()),
            src in prop::collection::vec(channel(), 32),
            constant in prop::array::uniform4(channel()),
            stored in prop::collection::vec(any::<u8>(), 10 * 2 * 4 * 4),
            coverage in any::<u32>(),
            samples in prop::sample::select(vec![1usize, 4]),
            x in prop::sample::select(vec![0, 4, 8]),
        ) {
            let blend = BlendState { color, alpha };
            let plan = ColorPlan {
                state: ColorTargetState { blend: Some(blend), write_mask: ColorWrites::ALL },
                mask: Format::Rgba8Unorm.write_mask_bytes(ColorWrites::ALL),
                partial: false,
            };
            let src: Vec4x8 = std::array::from_fn(|c| F32x8::from_fn(|lane| src[4 * lane + c]));
            // Lanes right of the surface are never covered.
            let inside = (0..LANES).filter(|lane| x as usize + lane % 4 < 10).fold(0u8, |m, lane| m | 1 << lane);
            let bytes: [u8; MAX_SAMPLES] =
                std::array::from_fn(|s| if s < samples { (coverage >> (8 * s)) as u8 & inside } else { 0 });
            let cover = Coverage::from_samples(bytes);
            for simd in [SimdLevel::Baseline, SimdLevel::Avx2].into_iter().filter_map(SimdSupport::detect) {
                let plane_bytes = 10 * 2 * 4;
                let mut memory = stored[..plane_bytes * samples].to_vec();
                let planes = memory.chunks_mut(plane_bytes);
                let mut surface = Surface::new(Format::Rgba8Unorm, (0, 0), 10, planes);
                let (mut traffic, mut ledger) = (FramebufferTraffic::default(), Ledger::default());
                blend_and_write(simd, &mut surface, x, 0, cover, &src, &plan, constant, &mut traffic, &mut ledger);
                for s in 0..samples {
                    for lane in 0..LANES {
                        let (px, py) = (x as usize + lane % 4, lane / 4);
                        if px >= 10 {
                            continue;
                        }
                        let at = s * plane_bytes + (py * 10 + px) * 4;
                        let old = &stored[at..at + 4];
                        let want: Vec<u8> = if cover.sample(s).contains(lane) {
                            let dst = Format::Rgba8Unorm.decode_color(old);
                            let source = [0, 1, 2, 3].map(|c| src[c].clamp(0.0, 1.0).lane(lane));
                            let constant = constant.map(|c| c.clamp(0.0, 1.0));
                            let out = crate::blend::blend_pixel(&blend, source, dst, constant);
                            let mut encoded = [0u8; 4];
                            Format::Rgba8Unorm.encode_color(out, &mut encoded);
                            encoded.to_vec()
                        } else {
                            old.to_vec()
                        };
                        prop_assert_eq!(&memory[at..at + 4], &want[..], "{:?} sample {} lane {}", simd, s, lane);
                    }
                }
            }
        }
    }

    #[test]
    fn alpha_to_coverage_keeps_the_first_samples() {
        let alpha = F32x8::from_array([0.0, 0.1, 0.3, 0.5, 0.6, 0.9, 1.0, 2.0]);
        let c = alpha_to_coverage(alpha, 4);
        let kept: Vec<u32> = (0..8).map(|lane| (0..4).filter(|&s| c.sample(s).contains(lane)).count() as u32).collect();
        assert_eq!(kept, vec![0, 0, 1, 2, 2, 4, 4, 4]);
        assert!(c.sample(0).contains(4) && c.sample(1).contains(4) && !c.sample(2).contains(4));
    }
}
