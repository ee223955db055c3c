//! The kernels at the heart of a frame, one criterion group each, called through the crate's
//! public modules as the backends call them: `cargo bench -p tiler --bench kernels` (a couple
//! of minutes; add `-- <group>` for one group). Texture sampling has its own bench
//! (`benches/texture.rs`).
//!
//! - `setup`: `geometry::setup::setup_triangle` on 1024 small triangles (16 px across) of a
//!   1920×1080 viewport, one sample: perspective divide, snapping, facing, edge functions,
//!   bounding box, interpolation planes. Throughput in triangles.
//! - `coverage`: `raster::coverage::PrimitiveCoverage` over every 8×8 block of each triangle's
//!   bounding box, as the pixel pipeline walks it: classify the block (outside / partial /
//!   full), then a coverage mask per sample of the partial ones. Small (16 px) and large
//!   (128 px) triangles at one sample, small ones at 4×. Throughput in blocks visited.
//! - `shade`: `pixel::primitive::rasterize` — coverage, early-Z, shading of 4×2 groups,
//!   colour writes — of 400 triangles (32 px across, overdraw ≈ 2) over a 256×256 target cut
//!   into 32×32 tiles of a `TileBuffer`, each tile cleared first and given only the
//!   triangles whose box meets it (no binning, no store). `flat`: provoking-vertex colour into
//!   RGBA8; `smooth_depth`: perspective-correct colour, D24S8 `LESS_WRITE`. Each at the
//!   baseline instruction set and, where the processor has it, AVX2 (what `Device` picks).
//!   `device_*`: the same scenes as a whole render pass through `Device` (TBR, one thread):
//!   vertex shading, setup, binning, tiles, stores. Throughput in fragments rasterized.
//! - `tile_load_store`: `tile::load_store::apply_load` / `apply_store` of every 32×32 tile of
//!   a 1920×1080 image between the image and the tile buffer, RGBA8 and D24S8: `load`
//!   (image → tile), `store` (tile → image), `clear` (load op `Clear`). Throughput in bytes of
//!   the image.
//! - `resolve`: `tile::load_store::apply_resolve` of a 4× RGBA8 tile into every 32×32 tile of
//!   a single-sample 1920×1080 image, UNORM and sRGB (which averages linear values).
//!   Throughput in pixels resolved.

use std::hint::black_box;
use std::time::Duration;

use criterion::{
    BenchmarkGroup, Criterion, SamplingMode, Throughput, criterion_group, criterion_main, measurement::WallTime,
};
use glam::Vec4;
use tiler::__bench::{
    AttachmentOps, BLOCK_SIZE, BlockCoverage, DepthOffset, FragmentTally, Mode, PixelRect, Primitive,
    PrimitiveCoverage, PrimitiveRun, RenderTarget, SampleLocations, SetupOutcome, SetupParams, Surface, TileBuffer,
    TileGrid, ViewportTransform, apply_load, apply_resolve, apply_store, block_rect_mask, rasterize, setup_triangle,
};
use tiler::{
    ColorAttachment, CullMode, DepthStencilAttachment, DepthStencilState, Device, DeviceConfig, Draw, F32x8, Format,
    FragmentShader, Fragments, FrontFace, ImageDesc, Interpolation, LoadOp, MAX_COLOR_ATTACHMENTS, Pipeline,
    PipelineDesc, RenderPass, RenderPassDesc, SimdLevel, SimdSupport, StoreOp, VertexFormat, VertexInput,
    VertexInputState, VertexOutput, VertexShader, Viewport,
};

/// A group with short measurements, so the whole bench runs in a couple of minutes.
fn short_group<'a>(c: &'a mut Criterion, name: &str) -> BenchmarkGroup<'a, WallTime> {
    let mut group = c.benchmark_group(name);
    group.warm_up_time(Duration::from_millis(500));
    group.measurement_time(Duration::from_secs(2));
    group.sample_size(20);
    group
}

/// A pseudo-random number in `[0, 1)` (an LCG: the values do not matter, only that they vary
/// and are the same every run).
struct Lcg(u32);

impl Lcg {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (self.0 >> 8) as f32 / (1 << 24) as f32
    }
}

/// A triangle in clip space (`w = 1`) with an RGBA colour per vertex.
struct Triangle {
    positions: [Vec4; 3],
    colors: [[f32; 4]; 3],
}

/// `count` triangles over a `width × height` viewport, each inscribed in a circle
/// `size_px` pixels across (area ≈ 0.32·size²) at a random place, angle and depth.
fn triangles(count: usize, width: u32, height: u32, size_px: f32, seed: u32) -> Vec<Triangle> {
    let mut rng = Lcg(seed);
    let radius = size_px / 2.0;
    (0..count)
        .map(|_| {
            let cx = radius + rng.next() * (width as f32 - size_px);
            let cy = radius + rng.next() * (height as f32 - size_px);
            let angle = rng.next() * std::f32::consts::TAU;
            let z = 0.1 + 0.8 * rng.next();
            let positions = std::array::from_fn(|k| {
                let a = angle + k as f32 * std::f32::consts::TAU / 3.0;
                let (x, y) = (cx + radius * a.cos(), cy + radius * a.sin());
                Vec4::new(2.0 * x / width as f32 - 1.0, 2.0 * y / height as f32 - 1.0, z, 1.0)
            });
            let colors = std::array::from_fn(|_| [rng.next(), rng.next(), rng.next(), 1.0]);
            Triangle { positions, colors }
        })
        .collect()
}

fn setup_params(width: u32, height: u32, samples: u32) -> SetupParams {
    SetupParams {
        viewport: ViewportTransform::new(&Viewport::full(width, height)),
        clip_rect: PixelRect::new(0, 0, width as i32, height as i32),
        cull_mode: CullMode::None,
        front_face: FrontFace::CounterClockwise,
        samples: SampleLocations::standard(samples),
        state: 0,
        depth_bias: DepthOffset::None,
        always_front: false,
    }
}

/// Sets up `triangles`: the primitive records and their varyings (four per vertex).
fn set_up(params: &SetupParams, triangles: &[Triangle]) -> (Vec<Primitive>, Vec<f32>) {
    let (mut primitives, mut varyings) = (Vec::new(), Vec::new());
    for t in triangles {
        let colors = [&t.colors[0][..], &t.colors[1][..], &t.colors[2][..]];
        setup_triangle(params, t.positions, colors, [0, 1, 2], &mut primitives, &mut varyings);
    }
    (primitives, varyings)
}

fn setup(c: &mut Criterion) {
    const COUNT: usize = 1024;
    let mut group = short_group(c, "setup");
    group.throughput(Throughput::Elements(COUNT as u64));
    let params = setup_params(1920, 1080, 1);
    let triangles = triangles(COUNT, 1920, 1080, 16.0, 1);
    let (mut primitives, mut varyings) = (Vec::with_capacity(COUNT), Vec::with_capacity(COUNT * 12));
    group.bench_function("small_1x", |b| {
        b.iter(|| {
            primitives.clear();
            varyings.clear();
            for t in &triangles {
                let colors = [&t.colors[0][..], &t.colors[1][..], &t.colors[2][..]];
                let outcome = setup_triangle(&params, t.positions, colors, [0, 1, 2], &mut primitives, &mut varyings);
                debug_assert_eq!(outcome, SetupOutcome::Primitive);
            }
            primitives.len()
        })
    });
    group.finish();
}

/// Walks the 8×8 blocks of each primitive's box as `rasterize` does (without the shading):
/// returns the covered samples and the blocks visited.
fn walk_blocks(primitives: &[Primitive], locations: &SampleLocations) -> (u64, u64) {
    let (mut covered, mut blocks) = (0u64, 0u64);
    for primitive in primitives {
        let coverage = PrimitiveCoverage::new(&primitive.edges(), locations);
        let rect = primitive.bbox;
        let mut by = rect.y0 & !(BLOCK_SIZE - 1);
        while by < rect.y1 {
            let rows = (rect.y0 - by).max(0)..(rect.y1 - by).min(BLOCK_SIZE);
            let mut bx = rect.x0 & !(BLOCK_SIZE - 1);
            while bx < rect.x1 {
                blocks += 1;
                let clip = block_rect_mask(bx, by, &rect);
                match coverage.classify_block(bx, by, BLOCK_SIZE) {
                    BlockCoverage::Outside => {}
                    BlockCoverage::Full => covered += (clip.count_ones() as usize * locations.count()) as u64,
                    BlockCoverage::Partial => {
                        for s in 0..locations.count() {
                            covered += (clip & coverage.block_mask(bx, by, s, rows.clone())).count_ones() as u64;
                        }
                    }
                }
                bx += BLOCK_SIZE;
            }
            by += BLOCK_SIZE;
        }
    }
    (covered, blocks)
}

fn coverage(c: &mut Criterion) {
    let mut group = short_group(c, "coverage");
    let cases = [("small_1x", 1024, 16.0, 1), ("large_1x", 64, 128.0, 1), ("small_4x", 1024, 16.0, 4)];
    for (name, count, size_px, samples) in cases {
        let (primitives, _) = set_up(&setup_params(1920, 1080, samples), &triangles(count, 1920, 1080, size_px, 2));
        let locations = SampleLocations::standard(samples);
        let (_, blocks) = walk_blocks(&primitives, &locations);
        group.throughput(Throughput::Elements(blocks));
        group.bench_function(name, |b| b.iter(|| walk_blocks(black_box(&primitives), &locations).0));
    }
    group.finish();
}

/// Passes the vertex's position and colour (attributes 0 and 1) through.
struct PassThrough;

impl VertexShader for PassThrough {
    fn shade(&self, input: &VertexInput, out: &mut VertexOutput) {
        out.position = input.attributes[0];
        out.varyings[..4].copy_from_slice(&input.attributes[1].to_array());
    }
}

/// The provoking vertex's colour (GLSL `flat`).
#[derive(Clone, Copy)]
struct FlatColor;

impl FragmentShader for FlatColor {
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        let rgba = std::array::from_fn(|i| F32x8::splat(frag.flat(i)));
        frag.set_color(0, rgba);
    }
}

/// The colour interpolated perspective-correctly (GLSL `smooth`).
#[derive(Clone, Copy)]
struct SmoothColor;

impl FragmentShader for SmoothColor {
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        let rgba = frag.smooth_n::<4>(0);
        frag.set_color(0, rgba);
    }
}

const SHADE_SIZE: u32 = 256;
const SHADE_TILE: u32 = 32;

fn shade_pipeline<F: FragmentShader>(fragment: F, depth: bool) -> Pipeline {
    let mut desc =
        PipelineDesc::new("bench", VertexInputState::interleaved(&[VertexFormat::Float32x4, VertexFormat::Float32x4]));
    desc.varyings = vec![Interpolation::Perspective; 4];
    if depth {
        desc.depth_stencil = DepthStencilState::LESS_WRITE;
    }
    Pipeline::new(PassThrough, fragment, desc).unwrap()
}

/// A target of 32×32 tiles with the primitives of each, and the tile buffer to render them in.
struct TiledScene {
    grid: TileGrid,
    primitives: Vec<Primitive>,
    varyings: Vec<f32>,
    /// Per tile, row-major: the primitives whose box meets it, in order.
    lists: Vec<Vec<u32>>,
    buffer: TileBuffer,
    ops: Vec<AttachmentOps>,
}

impl TiledScene {
    fn new(triangles: &[Triangle], depth: bool) -> TiledScene {
        let grid = TileGrid::new(SHADE_SIZE, SHADE_SIZE, SHADE_TILE, SHADE_TILE);
        let (primitives, varyings) = set_up(&setup_params(SHADE_SIZE, SHADE_SIZE, 1), triangles);
        let mut lists = vec![Vec::new(); grid.tile_count()];
        for (i, primitive) in primitives.iter().enumerate() {
            let (x0, y0, x1, y1) = grid.tiles_meeting(&primitive.bbox);
            for ty in y0..=y1 {
                for tx in x0..=x1 {
                    lists[grid.index(tx, ty)].push(i as u32);
                }
            }
        }
        let mut attachments = vec![(Format::Rgba8Unorm, 1)];
        let mut ops = vec![AttachmentOps::Color { load: LoadOp::Clear([0.0, 0.0, 0.0, 1.0]), store: StoreOp::Store }];
        if depth {
            attachments.push((Format::D24UnormS8Uint, 1));
            ops.push(AttachmentOps::DepthStencil {
                depth_load: LoadOp::Clear(1.0),
                depth_store: StoreOp::DontCare,
                stencil_load: LoadOp::Clear(0),
                stencil_store: StoreOp::DontCare,
            });
        }
        let buffer = TileBuffer::new(SHADE_TILE, SHADE_TILE, &attachments);
        TiledScene { grid, primitives, varyings, lists, buffer, ops }
    }

    /// Clears each tile and rasterizes its primitives: `#[inline(always)]`, so that the whole
    /// pixel pipeline is compiled for the instruction set of the caller.
    #[inline(always)]
    fn render<F: FragmentShader>(&mut self, shader: &F, desc: &PipelineDesc, tally: &mut FragmentTally) {
        for ty in 0..self.grid.tiles_y {
            for tx in 0..self.grid.tiles_x {
                let tile = self.grid.tile_rect(tx, ty);
                let mut surfaces = self.buffer.surfaces(&tile);
                for (surface, ops) in surfaces.iter_mut().zip(&self.ops) {
                    apply_load(surface, None, &tile, ops);
                }
                let list = &self.lists[self.grid.index(tx, ty)];
                let run = PrimitiveRun::entries(&self.primitives, &self.varyings, list, 0, 4);
                let mut views = surfaces.iter_mut();
                let mut color: [Option<&mut Surface>; MAX_COLOR_ATTACHMENTS] = Default::default();
                color[0] = views.next();
                let mut target = RenderTarget {
                    color,
                    depth_stencil: views.next(),
                    inputs: Default::default(),
                    samples: SampleLocations::standard(1),
                    clip: tile,
                    early_z: true,
                };
                rasterize(shader, desc, &run, &mut target, tally, &mut Mode::InOrder);
            }
        }
    }
}

/// [`TiledScene::render`] compiled for AVX2, as the crate's pipeline object compiles
/// `rasterize` (`pixel::pipeline`; a closure would not do, it would stay baseline code).
///
/// # Safety
/// The processor must have every feature of `tiler::simd::AVX2_FEATURES` (a `SimdSupport` of
/// level `Avx2` is the proof).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
unsafe fn render_avx2<F: FragmentShader>(
    scene: &mut TiledScene,
    shader: &F,
    desc: &PipelineDesc,
    tally: &mut FragmentTally,
) {
    scene.render(shader, desc, tally);
}

/// Renders `scene` once at `simd` and returns the tally.
fn render_scene<F: FragmentShader>(
    scene: &mut TiledScene,
    shader: &F,
    desc: &PipelineDesc,
    simd: SimdSupport,
) -> FragmentTally {
    let mut tally = FragmentTally::default();
    tally.simd = simd;
    match simd.level() {
        #[cfg(target_arch = "x86_64")]
        SimdLevel::Avx2 => {
            // SAFETY: `simd` was detected on this processor (`SimdSupport::detect`), which
            // checks every feature `render_avx2` is compiled with.
            unsafe { render_avx2(scene, shader, desc, &mut tally) }
        }
        _ => scene.render(shader, desc, &mut tally),
    }
    tally
}

fn shade_case<F: FragmentShader + Copy>(
    group: &mut BenchmarkGroup<WallTime>,
    name: &str,
    shader: F,
    depth: bool,
    triangles: &[Triangle],
) {
    // `Pipeline` keeps its shader to itself: `rasterize` gets a copy.
    let pipeline = shade_pipeline(shader, depth);
    let desc = pipeline.desc();
    let mut scene = TiledScene::new(triangles, depth);
    let levels = [SimdLevel::Baseline, SimdLevel::Avx2].into_iter().filter_map(SimdSupport::detect);
    for simd in levels {
        let fragments = render_scene(&mut scene, &shader, desc, simd).counters.fragments_rasterized;
        group.throughput(Throughput::Elements(fragments));
        group.bench_function(format!("{name}_{}", simd.level()), |b| {
            b.iter(|| render_scene(&mut scene, &shader, desc, simd).counters.fragments_shaded)
        });
    }

    // The same scene as a render pass through the device.
    let mut device = Device::new(DeviceConfig { threads: 1, ..DeviceConfig::default() }).unwrap();
    let color = device.create_image(ImageDesc::new(SHADE_SIZE, SHADE_SIZE, Format::Rgba8Unorm)).unwrap();
    let depth_stencil = depth.then(|| {
        let image = device.create_image(ImageDesc::new(SHADE_SIZE, SHADE_SIZE, Format::D24UnormS8Uint)).unwrap();
        DepthStencilAttachment::clear_discard(image, 1.0)
    });
    let vertices: Vec<[f32; 8]> = triangles
        .iter()
        .flat_map(|t| {
            (0..3).map(|k| {
                let p = t.positions[k].to_array();
                let c = t.colors[k];
                [p[0], p[1], p[2], p[3], c[0], c[1], c[2], c[3]]
            })
        })
        .collect();
    let buffer = device.create_buffer_from(&vertices).unwrap();
    let mut pass = RenderPass::new(RenderPassDesc {
        color: vec![ColorAttachment::clear_store(color, [0.0, 0.0, 0.0, 1.0])],
        depth_stencil,
        render_area: None,
    });
    pass.draw(Draw::new(&pipeline, buffer, 0, vertices.len() as u32));
    let fragments = device.submit(&pass).unwrap().counters.fragments_rasterized;
    group.throughput(Throughput::Elements(fragments));
    group.bench_function(format!("device_{name}"), |b| {
        b.iter(|| device.submit(&pass).unwrap().counters.fragments_shaded)
    });
}

fn shade(c: &mut Criterion) {
    let mut group = short_group(c, "shade");
    let triangles = triangles(400, SHADE_SIZE, SHADE_SIZE, 32.0, 3);
    shade_case(&mut group, "flat", FlatColor, false, &triangles);
    shade_case(&mut group, "smooth_depth", SmoothColor, true, &triangles);
    group.finish();
}

const IMAGE_WIDTH: u32 = 1920;
const IMAGE_HEIGHT: u32 = 1080;
const TILE: u32 = 32;

/// Bytes of pseudo-random content, for images and tiles.
fn noise(len: usize, seed: u32) -> Vec<u8> {
    let mut rng = Lcg(seed);
    (0..len).map(|_| (rng.next() * 256.0) as u8).collect()
}

/// Runs `per_tile` on every tile of a 1920×1080 image, in the order a tiler does.
#[inline(always)]
fn for_each_tile(mut per_tile: impl FnMut(&PixelRect)) {
    let grid = TileGrid::new(IMAGE_WIDTH, IMAGE_HEIGHT, TILE, TILE);
    for ty in 0..grid.tiles_y {
        for tx in 0..grid.tiles_x {
            per_tile(&grid.tile_rect(tx, ty));
        }
    }
}

fn tile_load_store(c: &mut Criterion) {
    let mut group = short_group(c, "tile_load_store");
    let color = |load| AttachmentOps::Color { load, store: StoreOp::Store };
    let depth_stencil = |depth_load, stencil_load| AttachmentOps::DepthStencil {
        depth_load,
        depth_store: StoreOp::Store,
        stencil_load,
        stencil_store: StoreOp::Store,
    };
    let formats = [
        ("rgba8", Format::Rgba8Unorm, color(LoadOp::Load), color(LoadOp::Clear([0.25, 0.5, 0.75, 1.0]))),
        (
            "d24s8",
            Format::D24UnormS8Uint,
            depth_stencil(LoadOp::Load, LoadOp::Load),
            depth_stencil(LoadOp::Clear(1.0), LoadOp::Clear(0)),
        ),
    ];
    for (name, format, load, clear) in formats {
        let bytes = (IMAGE_WIDTH * IMAGE_HEIGHT) as usize * format.bytes_per_sample();
        group.throughput(Throughput::Bytes(bytes as u64));
        let mut memory = noise(bytes, 4);
        let mut image = Surface::new(format, (0, 0), IMAGE_WIDTH as usize, [memory.as_mut_slice()]);
        let mut buffer = TileBuffer::new(TILE, TILE, &[(format, 1)]);
        group.bench_function(format!("{name}_load"), |b| {
            b.iter(|| {
                for_each_tile(|rect| {
                    let mut tile = buffer.surfaces(rect);
                    apply_load(&mut tile[0], Some(&image), rect, &load);
                    black_box(tile[0].plane(0));
                })
            })
        });
        group.bench_function(format!("{name}_store"), |b| {
            b.iter(|| {
                for_each_tile(|rect| {
                    let tile = buffer.surfaces(rect);
                    apply_store(&tile[0], &mut image, rect, &load);
                })
            })
        });
        group.bench_function(format!("{name}_clear"), |b| {
            b.iter(|| {
                for_each_tile(|rect| {
                    let mut tile = buffer.surfaces(rect);
                    apply_load(&mut tile[0], Some(&image), rect, &clear);
                    black_box(tile[0].plane(0));
                })
            })
        });
        black_box(image.plane(0));
    }
    group.finish();
}

fn resolve(c: &mut Criterion) {
    const SAMPLES: u32 = 4;
    let mut group = short_group(c, "resolve");
    // A whole frame takes a tenth of a second or more: a few single iterations, not a ramp.
    group.sampling_mode(SamplingMode::Flat);
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(4));
    group.throughput(Throughput::Elements((IMAGE_WIDTH * IMAGE_HEIGHT) as u64));
    for (name, format) in [("rgba8_4x", Format::Rgba8Unorm), ("rgba8_srgb_4x", Format::Rgba8UnormSrgb)] {
        let mut memory = vec![0u8; (IMAGE_WIDTH * IMAGE_HEIGHT) as usize * format.bytes_per_sample()];
        let mut image = Surface::new(format, (0, 0), IMAGE_WIDTH as usize, [memory.as_mut_slice()]);
        let mut buffer = TileBuffer::new(TILE, TILE, &[(format, SAMPLES)]);
        // Samples that differ, so that every average is worked out.
        let mut tile = buffer.surfaces(&PixelRect::new(0, 0, TILE as i32, TILE as i32));
        for s in 0..SAMPLES as usize {
            let plane = tile[0].plane_mut(s);
            plane.copy_from_slice(&noise(plane.len(), 5 + s as u32));
        }
        drop(tile);
        group.bench_function(name, |b| {
            b.iter(|| {
                for_each_tile(|rect| {
                    let tile = buffer.surfaces(rect);
                    apply_resolve(&tile[0], &mut image, rect);
                })
            })
        });
        black_box(image.plane(0));
    }
    group.finish();
}

criterion_group!(benches, setup, coverage, shade, tile_load_store, resolve);
criterion_main!(benches);
