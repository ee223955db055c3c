//! The fragment pipeline for one primitive in one region (a tile, or a band of the
//! framebuffer): coverage → early depth/stencil → shading → discard → late depth/stencil →
//! blending and colour writes. Every backend calls this same function; they differ only in
//! which region they hand it and whether that region lives in the tile buffer or in external
//! memory.
//!
//! Work goes block by block (8×8 pixels, classified outside / partial / full), then 4×2 group
//! by group: eight lanes, two 2×2 quads, every sample of each.
//!
//! Early-Z: when the fragment shader neither discards, nor writes depth, nor has side effects,
//! the depth and stencil tests (and their writes) run before shading, in submission order, so
//! fragments that fail are never shaded. Otherwise the tests run after shading.

use super::PixelRect;
use super::coverage::{BLOCK_SIZE, BlockCoverage, Coverage, PrimitiveCoverage, lanes_inside};
use crate::api::format::ColorWrites;
use crate::api::pipeline::{ColorTargetState, MAX_COLOR_ATTACHMENTS, PipelineDesc};
use crate::api::shader::{FragmentShader, Fragments};
use crate::binning::frame_data::Primitive;
use crate::blend::blend_pixel;
use crate::depth;
use crate::ledger::{Category, Counters, DrawStats, Ledger};
use crate::shade::ShadeContext;
use crate::shade::interpolate::Interpolator;
use crate::simd::{F32x8, LANE_DX, LANE_DY, LANES, LaneMask, Vec4x8};
use crate::tile::target::{RenderTarget, Surface};

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
}

impl FragmentTally {
    /// The stats of the current draw.
    #[inline]
    fn draw_stats(&mut self) -> &mut DrawStats {
        if self.draws.len() <= self.draw {
            self.draws.resize(self.draw + 1, DrawStats::default());
        }
        &mut self.draws[self.draw]
    }
}

/// How one colour attachment is written, prepared once per primitive.
#[derive(Clone, Copy)]
struct ColorPlan {
    state: ColorTargetState,
    /// Byte mask of the channels written (see `Format::write_mask_bytes`).
    mask: [u8; 16],
    /// Some channel of the format is not written: the old value must be read and merged.
    partial: bool,
}

/// Rasterizes and shades `primitive` into `target`.
pub fn rasterize<F: FragmentShader>(
    shader: &F,
    desc: &PipelineDesc,
    primitive: &Primitive,
    varyings: &[f32],
    target: &mut RenderTarget,
    tally: &mut FragmentTally,
) {
    let rect = primitive.bbox.intersect(&target.clip);
    if rect.is_empty() {
        return;
    }
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
                colors[i] = Some(ColorPlan { state: *state, mask, partial: mask[..bytes].iter().any(|b| *b != 0xff) });
            }
        }
    }
    let raster = PrimitiveRaster {
        shader,
        desc,
        primitive,
        varyings,
        varying_count: desc.varyings.len(),
        coverage: PrimitiveCoverage::new(&primitive.edges, &target.samples),
        interpolator: Interpolator::new(primitive),
        tests,
        early_tests: tests && !(properties.discards || properties.writes_depth || properties.side_effects),
        colors,
    };
    raster.run(&rect, target, tally);
}

struct PrimitiveRaster<'a, F> {
    shader: &'a F,
    desc: &'a PipelineDesc,
    primitive: &'a Primitive,
    varyings: &'a [f32],
    varying_count: usize,
    coverage: PrimitiveCoverage,
    interpolator: Interpolator,
    tests: bool,
    early_tests: bool,
    colors: [Option<ColorPlan>; MAX_COLOR_ATTACHMENTS],
}

impl<F: FragmentShader> PrimitiveRaster<'_, F> {
    fn run(&self, rect: &PixelRect, target: &mut RenderTarget, tally: &mut FragmentTally) {
        let samples = target.samples.count();
        let mut by = rect.y0 & !(BLOCK_SIZE - 1);
        while by < rect.y1 {
            let mut bx = rect.x0 & !(BLOCK_SIZE - 1);
            while bx < rect.x1 {
                let class = self.coverage.classify_block(bx, by, BLOCK_SIZE);
                if class != BlockCoverage::Outside {
                    let block = PixelRect::new(bx, by, bx + BLOCK_SIZE, by + BLOCK_SIZE);
                    let inside_rect = rect.intersect(&block) == block;
                    for gy in (by..by + BLOCK_SIZE).step_by(2) {
                        if gy + 2 <= rect.y0 || gy >= rect.y1 {
                            continue;
                        }
                        for gx in [bx, bx + 4] {
                            if gx + 4 <= rect.x0 || gx >= rect.x1 {
                                continue;
                            }
                            let mut coverage = match class {
                                BlockCoverage::Full => Coverage::full(samples),
                                _ => self.coverage.group(gx, gy),
                            };
                            if !inside_rect {
                                coverage = coverage.restrict(lanes_inside(gx, gy, rect));
                            }
                            if !coverage.is_empty() {
                                self.group(gx, gy, coverage, target, tally);
                            }
                        }
                    }
                }
                bx += BLOCK_SIZE;
            }
            by += BLOCK_SIZE;
        }
    }

    /// The fragment pipeline for the covered samples of the 4×2 group at `(x, y)`.
    fn group(&self, x: i32, y: i32, mut coverage: Coverage, target: &mut RenderTarget, tally: &mut FragmentTally) {
        let counters = &mut tally.counters;
        let rasterized = coverage.lanes();
        counters.fragments_rasterized += rasterized.count() as u64;
        let (cx, cy) = Interpolator::positions(x, y, 0.5, 0.5);
        let (l1, l2) = self.interpolator.lambdas(cx, cy);
        let centre_depth = self.interpolator.depth(l1, l2);
        let multisampled = target.samples.count() > 1;
        let front_facing = self.primitive.front_facing;

        if self.early_tests {
            let surface = target.depth_stencil.as_mut().expect("tests need a depth-stencil attachment");
            let ledger = target.external.then_some(&mut tally.ledger);
            coverage = depth::test_group(
                surface,
                x,
                y,
                coverage,
                &self.desc.depth_stencil,
                front_facing,
                |s| self.sample_depth(x, y, s, &target.samples, multisampled, centre_depth),
                ledger,
            );
            let survivors = coverage.lanes();
            counters.fragments_early_z_killed += (rasterized.count() - survivors.count()) as u64;
            if survivors.is_empty() {
                return;
            }
        }

        let live = coverage.lanes();
        let (b1, b2) = self.interpolator.perspective(l1, l2);
        let mut frag = Fragments {
            x: cx,
            y: cy,
            z: centre_depth,
            b1,
            b2,
            l1,
            l2,
            varyings: self.varyings,
            varying_count: self.varying_count,
            front_facing,
            covered: live,
            color: [[F32x8::ZERO; 4]; MAX_COLOR_ATTACHMENTS],
            written_depth: centre_depth,
            discarded: LaneMask::NONE,
            context: &mut tally.context,
        };
        self.shader.shade(&mut frag);
        let (out_color, out_depth, discarded) = (frag.color, frag.written_depth, frag.discarded);
        counters.fragments_shaded += live.count() as u64;
        counters.helper_invocations += (live.quads().count() - live.count()) as u64;

        let discarded = discarded & live;
        if !discarded.is_empty() {
            counters.fragments_discarded += discarded.count() as u64;
            coverage = coverage.restrict(!discarded);
        }

        if self.tests && !self.early_tests && !coverage.is_empty() {
            let before = coverage.lanes().count();
            let surface = target.depth_stencil.as_mut().expect("tests need a depth-stencil attachment");
            let writes_depth = self.shader.properties().writes_depth;
            let ledger = target.external.then_some(&mut tally.ledger);
            coverage = depth::test_group(
                surface,
                x,
                y,
                coverage,
                &self.desc.depth_stencil,
                front_facing,
                |s| {
                    if writes_depth {
                        out_depth
                    } else {
                        self.sample_depth(x, y, s, &target.samples, multisampled, centre_depth)
                    }
                },
                ledger,
            );
            counters.fragments_late_killed += (before - coverage.lanes().count()) as u64;
        }

        let passed = coverage.lanes();
        counters.fragments_passed += passed.count() as u64;
        let stats = tally.draw_stats();
        stats.fragments_shaded += live.count() as u64;
        stats.samples_passed += coverage.count() as u64;
        if passed.is_empty() {
            return;
        }
        for (i, plan) in self.colors.iter().enumerate() {
            let (Some(plan), Some(surface)) = (plan, target.color[i].as_mut()) else { continue };
            let ledger = target.external.then_some(&mut tally.ledger);
            write_color(surface, x, y, coverage, &out_color[i], plan, self.desc.blend_constant, ledger);
        }
    }

    /// Fragment depth at sample `s` of every lane (at the pixel centre for one sample).
    #[inline(always)]
    fn sample_depth(
        &self,
        x: i32,
        y: i32,
        s: usize,
        locations: &super::samples::SampleLocations,
        multisampled: bool,
        centre: F32x8,
    ) -> F32x8 {
        if !multisampled {
            return centre;
        }
        let (l1, l2) = self.interpolator.sample_lambdas(x, y, locations.offset(s));
        self.interpolator.depth(l1, l2)
    }
}

/// Blends and writes one colour attachment for the covered samples of a group.
#[allow(clippy::too_many_arguments)]
#[inline]
fn write_color(
    surface: &mut Surface,
    x: i32,
    y: i32,
    coverage: Coverage,
    color: &Vec4x8,
    plan: &ColorPlan,
    constant: [f32; 4],
    ledger: Option<&mut Ledger>,
) {
    let format = surface.format;
    let bytes = format.bytes_per_sample();
    let clamp = format.is_normalized();
    let constant = if clamp { constant.map(|c| c.clamp(0.0, 1.0)) } else { constant };
    let (mut reads, mut writes) = (0u64, 0u64);
    for lane in 0..LANES {
        if !coverage.lanes().contains(lane) {
            continue;
        }
        let mut src = [color[0].lane(lane), color[1].lane(lane), color[2].lane(lane), color[3].lane(lane)];
        if clamp && plan.state.blend.is_some() {
            src = src.map(|c| if c > 0.0 { c.min(1.0) } else { 0.0 });
        }
        let offset = surface.offset(x + LANE_DX[lane] as i32, y + LANE_DY[lane] as i32);
        // Without blending, every sample of the pixel gets the same packed value.
        let mut packed = [0u8; 16];
        if plan.state.blend.is_none() {
            format.encode_color(src, &mut packed[..bytes]);
        }
        for s in 0..surface.samples() {
            if !coverage.sample(s).contains(lane) {
                continue;
            }
            let stored = &mut surface.plane_mut(s)[offset..offset + bytes];
            if let Some(blend) = &plan.state.blend {
                let dst = format.decode_color(stored);
                let out = blend_pixel(blend, src, dst, constant);
                format.encode_color(out, &mut packed[..bytes]);
                reads += 1;
            } else if plan.partial {
                reads += 1;
            }
            if plan.partial {
                for ((old, new), m) in stored.iter_mut().zip(&packed[..bytes]).zip(&plan.mask) {
                    *old = (new & m) | (*old & !m);
                }
            } else {
                stored.copy_from_slice(&packed[..bytes]);
            }
            writes += 1;
        }
    }
    if let Some(ledger) = ledger {
        ledger.add(Category::ImrColorRead, reads * bytes as u64);
        ledger.add(Category::ImrColorWrite, writes * bytes as u64);
    }
}
