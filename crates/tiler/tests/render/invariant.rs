//! The central invariant: for one input, every backend, tile size and thread count gives the
//! same image, bit for bit — on scenes with overlap, blending, depth, stencil, discard,
//! clipped triangles, strips, scissors, render areas, several formats and incremental renders.

use super::common::*;
use tiler::*;

/// Odd sizes, so tiles are cut at the edges.
const W: u32 = 157;
const H: u32 = 101;

/// Random overlapping triangles with smooth colours and depth, some drawn twice with
/// `LESS_EQUAL`, some alpha-tested.
fn overlap_depth(device: &mut Device) -> TestScene {
    let color = device.create_image(ImageDesc::new(W, H, Format::Rgba8Unorm)).unwrap();
    let depth = device.create_image(ImageDesc::new(W, H, Format::D32Float)).unwrap();
    let mut rng = Rng(7);
    let tris: Vec<Vertex> = (0..3 * 60)
        .map(|_| v(rng.range(-1.3, 1.3), rng.range(-1.3, 1.3), rng.range(0.0, 1.0), rng.color_alpha(0.0, 1.0)))
        .collect();
    let buffer = device.create_buffer_from(&tris).unwrap();
    let mut d = desc("depth");
    d.depth_stencil = DepthStencilState::LESS_WRITE;
    let less = pipeline(Smooth, d.clone());
    d.depth_stencil = DepthStencilState::LESS_EQUAL_WRITE;
    let less_equal = pipeline(FlatColor, d.clone());
    let alpha_test = pipeline(AlphaTest, d);
    let mut pass = color_pass(color, Some(DepthStencilAttachment::clear_store(depth, 1.0, 0)));
    pass.draw(Draw::new(&less, buffer, 0, 90));
    pass.draw(Draw::new(&less_equal, buffer, 45, 90));
    pass.draw(Draw::new(&alpha_test, buffer, 90, 90));
    TestScene { passes: vec![pass], images: vec![color, depth] }
}

/// Blending with several equations over each other, and a write mask.
fn blending(device: &mut Device) -> TestScene {
    let color = device.create_image(ImageDesc::new(W, H, Format::Rgba8Unorm)).unwrap();
    let mut rng = Rng(11);
    let tris: Vec<Vertex> =
        (0..3 * 40).map(|_| v(rng.range(-1.2, 1.2), rng.range(-1.2, 1.2), 0.5, rng.color_alpha(0.1, 0.9))).collect();
    let buffer = device.create_buffer_from(&tris).unwrap();
    let mut pass = color_pass(color, None);
    let states = [
        ColorTargetState::ALPHA_BLEND,
        ColorTargetState { blend: Some(BlendState::ADDITIVE), write_mask: ColorWrites::ALL },
        ColorTargetState {
            blend: Some(BlendState {
                color: BlendComponent {
                    src: BlendFactor::DstColor,
                    dst: BlendFactor::SrcAlpha,
                    op: BlendOp::ReverseSubtract,
                },
                alpha: BlendComponent { src: BlendFactor::One, dst: BlendFactor::One, op: BlendOp::Max },
            }),
            write_mask: ColorWrites(ColorWrites::RED.0 | ColorWrites::ALPHA.0),
        },
    ];
    for (i, state) in states.iter().enumerate() {
        let mut d = desc("blend");
        d.color_targets = vec![*state];
        pass.draw(Draw::new(&pipeline(Smooth, d), buffer, 40 * i as u32, 40));
    }
    TestScene { passes: vec![pass], images: vec![color] }
}

/// Stencil writes with different front and back ops, then tests against them.
fn stencil(device: &mut Device) -> TestScene {
    let color = device.create_image(ImageDesc::new(W, H, Format::Rgba8Unorm)).unwrap();
    let ds = device.create_image(ImageDesc::new(W, H, Format::D24UnormS8Uint)).unwrap();
    let mut rng = Rng(3);
    let tris: Vec<Vertex> = (0..3 * 50)
        .map(|_| v(rng.range(-1.2, 1.2), rng.range(-1.2, 1.2), rng.range(0.0, 1.0), rng.color(1.0)))
        .collect();
    let buffer = device.create_buffer_from(&tris).unwrap();
    let face = |compare, pass_op, reference| StencilFaceState {
        compare,
        fail_op: StencilOp::Keep,
        depth_fail_op: StencilOp::DecrementAndWrap,
        pass_op,
        compare_mask: 0xff,
        write_mask: 0xff,
        reference,
    };
    let mut write = desc("stencil write");
    write.depth_stencil = DepthStencilState {
        stencil_test: true,
        front: face(CompareOp::Always, StencilOp::IncrementAndWrap, 0),
        back: face(CompareOp::Always, StencilOp::Invert, 0),
        ..DepthStencilState::LESS_WRITE
    };
    let mut test = desc("stencil test");
    test.depth_stencil = DepthStencilState {
        stencil_test: true,
        front: face(CompareOp::Greater, StencilOp::Replace, 1),
        back: face(CompareOp::NotEqual, StencilOp::Zero, 2),
        ..DepthStencilState::LESS_EQUAL_WRITE
    };
    let mut pass = color_pass(color, Some(DepthStencilAttachment::clear_store(ds, 1.0, 0)));
    pass.draw(Draw::new(&pipeline(Smooth, write), buffer, 0, 75));
    pass.draw(Draw::new(&pipeline(FlatColor, test), buffer, 75, 75));
    TestScene { passes: vec![pass], images: vec![color, ds] }
}

/// Triangles crossing the near and far planes, with vertices behind the eye (w < 0), and
/// triangles far larger than the guard band, under a perspective-like w.
fn clipped(device: &mut Device) -> TestScene {
    let color = device.create_image(ImageDesc::new(W, H, Format::Rgba8Unorm)).unwrap();
    let depth = device.create_image(ImageDesc::new(W, H, Format::D16Unorm)).unwrap();
    let mut rng = Rng(5);
    let mut tris: Vec<Vertex> = Vec::new();
    for _ in 0..40 {
        for _ in 0..3 {
            let w = rng.range(-0.5, 2.0);
            let c = rng.color(1.0);
            tris.push([rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), rng.range(-0.5, 2.0), w, c[0], c[1], c[2], c[3]]);
        }
    }
    // Huge: far outside the guard band.
    tris.push([-1e6, -1e6, 0.9, 1.0, 1.0, 0.0, 0.0, 1.0]);
    tris.push([1e6, -1e6, 0.9, 1.0, 0.0, 1.0, 0.0, 1.0]);
    tris.push([0.0, 1e6, 0.9, 1.0, 0.0, 0.0, 1.0, 1.0]);
    let buffer = device.create_buffer_from(&tris).unwrap();
    let mut d = desc("clipped");
    d.depth_stencil = DepthStencilState::LESS_WRITE;
    let mut pass = color_pass(color, Some(DepthStencilAttachment::clear_store(depth, 1.0, 0)));
    pass.draw(Draw::new(&pipeline(Smooth, d), buffer, 0, tris.len() as u32));
    TestScene { passes: vec![pass], images: vec![color, depth] }
}

/// Indexed strips and fans (u16 and u32), culling, a scissor, a viewport, and a second pass
/// that loads the first one's result inside a render area.
fn strips_scissor_load(device: &mut Device) -> TestScene {
    let color = device.create_image(ImageDesc::new(W, H, Format::Rgba8Unorm)).unwrap();
    let mut rng = Rng(9);
    let verts: Vec<Vertex> =
        (0..64).map(|_| v(rng.range(-1.1, 1.1), rng.range(-1.1, 1.1), 0.5, rng.color(1.0))).collect();
    let buffer = device.create_buffer_from(&verts).unwrap();
    let indices16: Vec<u16> = (0..40).map(|_| (rng.next_u32() % 64) as u16).collect();
    let indices32: Vec<u32> = (0..30).map(|_| rng.next_u32() % 64).collect();
    let ib16 = device.create_buffer_from(&indices16).unwrap();
    let ib32 = device.create_buffer_from(&indices32).unwrap();
    let mut strip = desc("strip");
    strip.topology = Topology::TriangleStrip;
    strip.cull_mode = CullMode::Back;
    let mut fan = desc("fan");
    fan.topology = Topology::TriangleFan;
    fan.front_face = FrontFace::Clockwise;
    fan.cull_mode = CullMode::Front;
    let mut first = color_pass(color, None);
    first.draw(
        Draw::indexed(&pipeline(Smooth, strip), buffer, ib16, IndexType::U16, 0, 40)
            .with_scissor(Rect::new(10, 5, 120, 80)),
    );
    first.draw(Draw::indexed(&pipeline(FlatColor, fan), buffer, ib32, IndexType::U32, 2, 28).with_viewport(Viewport {
        x: 20.5,
        y: -10.0,
        width: 100.0,
        height: 90.0,
        min_depth: 0.0,
        max_depth: 1.0,
    }));
    let mut second = RenderPass::new(RenderPassDesc {
        color: vec![ColorAttachment { image: color, load: LoadOp::Load, store: StoreOp::Store, resolve: None }],
        depth_stencil: None,
        render_area: Some(Rect::new(33, 17, 90, 61)),
    });
    let mut blend = desc("blend over");
    blend.color_targets = vec![ColorTargetState::ALPHA_BLEND];
    second.draw(Draw::new(&pipeline(Smooth, blend), buffer, 0, 63));
    TestScene { passes: vec![first, second], images: vec![color] }
}

/// Four colour attachments of different formats written at once.
fn formats(device: &mut Device) -> TestScene {
    struct Mrt;
    impl FragmentShader for Mrt {
        #[inline(always)]
        fn shade(&self, frag: &mut Fragments<'_>) {
            let c = frag.smooth_n::<4>(0);
            frag.set_color(0, c);
            frag.set_color(1, [c[2], c[1], c[0], c[3]]);
            frag.set_color(2, [c[0] * 4.0 - 1.0, c[1], c[2], c[3]]);
            frag.set_color(3, [c[1], c[0], c[3], c[2]]);
        }
    }
    let images = [Format::Rgb565Unorm, Format::Rgba16Float, Format::Bgra8Unorm, Format::Rgba8UnormSrgb]
        .map(|f| device.create_image(ImageDesc::new(W, H, f)).unwrap());
    let mut rng = Rng(13);
    let tris: Vec<Vertex> =
        (0..3 * 30).map(|_| v(rng.range(-1.2, 1.2), rng.range(-1.2, 1.2), 0.5, rng.color_alpha(0.0, 1.0))).collect();
    let buffer = device.create_buffer_from(&tris).unwrap();
    let mut d = desc("mrt");
    d.color_targets = vec![ColorTargetState::ALPHA_BLEND; 4];
    let mut pass = RenderPass::new(RenderPassDesc {
        color: images.iter().map(|&i| ColorAttachment::clear_store(i, [0.5, 0.25, 0.75, 1.0])).collect(),
        depth_stencil: None,
        render_area: None,
    });
    pass.draw(Draw::new(&Pipeline::new(PassThrough, Mrt, d).unwrap(), buffer, 0, 90));
    TestScene { passes: vec![pass], images: images.to_vec() }
}

/// Many small triangles, to force incremental renders under a small frame-data budget.
fn many_triangles(device: &mut Device) -> TestScene {
    let color = device.create_image(ImageDesc::new(W, H, Format::Rgba8Unorm)).unwrap();
    let depth = device.create_image(ImageDesc::new(W, H, Format::D24UnormS8Uint)).unwrap();
    let mut rng = Rng(21);
    let mut tris: Vec<Vertex> = Vec::new();
    for _ in 0..40_000 {
        let (cx, cy, z) = (rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(0.0, 1.0));
        let c = rng.color(1.0);
        for _ in 0..3 {
            tris.push(v(cx + rng.range(-0.06, 0.06), cy + rng.range(-0.06, 0.06), z, c));
        }
    }
    let buffer = device.create_buffer_from(&tris).unwrap();
    let mut d = desc("many");
    d.depth_stencil = DepthStencilState::LESS_WRITE;
    let mut pass = color_pass(color, Some(DepthStencilAttachment::clear_discard(depth, 1.0)));
    pass.draw(Draw::new(&pipeline(FlatColor, d), buffer, 0, tris.len() as u32));
    TestScene { passes: vec![pass], images: vec![color] }
}

/// A named scene builder.
type NamedScene = (&'static str, fn(&mut Device) -> TestScene);

const SCENES: [NamedScene; 6] = [
    ("overlap_depth", overlap_depth),
    ("blending", blending),
    ("stencil", stencil),
    ("clipped", clipped),
    ("strips_scissor_load", strips_scissor_load),
    ("formats", formats),
];

const BIG_BUDGET: u64 = 64 << 20;

#[test]
fn every_backend_tile_size_and_thread_count_gives_the_same_image() {
    for (name, build) in SCENES {
        let (reference, _) = render_scene(build, Backend::Imr, (32, 32), 1, BIG_BUDGET);
        assert!(reference.iter().any(|img| img.iter().any(|&b| b != 0)), "{name}: empty reference");
        for backend in Backend::ALL {
            for tile in [(16, 16), (32, 32), (64, 64), (8, 24)] {
                for threads in [1, 2, 3] {
                    let (images, _) = render_scene(build, backend, tile, threads, BIG_BUDGET);
                    for (i, (a, b)) in images.iter().zip(&reference).enumerate() {
                        assert!(a == b, "{name}: image {i} differs on {backend}, tile {tile:?}, {threads} threads");
                    }
                }
            }
        }
    }
}

#[test]
fn every_simd_level_gives_the_same_image() {
    let levels: Vec<SimdLevel> =
        [SimdLevel::Baseline, SimdLevel::Avx2].into_iter().filter(|l| l.is_available()).collect();
    if levels.len() < 2 {
        eprintln!("only the baseline SIMD level runs on this processor: nothing to compare");
    }
    for (name, build) in
        SCENES.iter().copied().chain([("many_triangles", many_triangles as fn(&mut Device) -> TestScene)])
    {
        let (reference, _) = render_scene_at(build, Backend::Imr, (32, 32), 1, BIG_BUDGET, Some(SimdLevel::Baseline));
        for &level in &levels {
            for backend in Backend::ALL {
                let (images, _) = render_scene_at(build, backend, (16, 16), 2, BIG_BUDGET, Some(level));
                for (i, (a, b)) in images.iter().zip(&reference).enumerate() {
                    assert!(a == b, "{name}: image {i} differs on {backend} at SIMD level {}", level.name());
                }
            }
        }
    }
}

#[test]
fn a_simd_level_the_processor_lacks_is_refused() {
    for level in [SimdLevel::Baseline, SimdLevel::Avx2] {
        let result = Device::new(DeviceConfig { simd: Some(level), ..DeviceConfig::default() });
        if level.is_available() {
            assert!(result.is_ok());
        } else {
            let message = result.err().expect("unavailable level accepted").to_string();
            assert!(message.contains(level.name()), "{message}");
        }
    }
}

#[test]
fn incremental_renders_give_the_same_image_and_cost_more() {
    let (reference, imr) = render_scene(many_triangles, Backend::Imr, (32, 32), 2, BIG_BUDGET);
    let (whole, one_flush) = render_scene(many_triangles, Backend::Tbr, (32, 32), 2, BIG_BUDGET);
    let (split, flushed) = render_scene(many_triangles, Backend::Tbr, (32, 32), 2, 1 << 20);
    let (deferred, _) = render_scene(many_triangles, Backend::Tbdr, (32, 32), 2, 1 << 20);
    assert_eq!(whole, reference);
    assert_eq!(split, reference);
    assert_eq!(deferred, reference);
    assert_eq!(one_flush.counters.incremental_renders, 0);
    assert!(flushed.counters.incremental_renders >= 2, "{:?}", flushed.counters);
    assert!(flushed.frame_data.peak_bytes <= 1 << 20, "over budget: {}", flushed.frame_data.peak_bytes);
    // Every flush but the last stores colour and depth (D24S8: 3 + 1 bytes) and the next
    // loads them back: the cliff of seed 000 §23.5.
    let pixels = (W * H) as u64;
    let n = flushed.counters.incremental_renders;
    assert_eq!(flushed.ledger.get(Category::TileStore), (n * (4 + 4) + 4) * pixels);
    assert_eq!(flushed.ledger.get(Category::TileLoad), n * (4 + 4) * pixels);
    assert_eq!(one_flush.ledger.get(Category::TileStore), 4 * pixels);
    assert_eq!(one_flush.ledger.get(Category::TileLoad), 0);
    assert_eq!(imr.counters.fragments_shaded, one_flush.counters.fragments_shaded);
}

/// Geometry and binning split across threads merge in submission order: many triangles, with
/// and without incremental renders, give the same image, ledger, counters and frame-data
/// figures on 1, 2 and 3 threads — also in a second frame on the same device, which reuses
/// the first frame's frame data, setup batches and shaded vertices.
#[test]
fn many_triangles_are_the_same_on_every_thread_count_and_frame() {
    for backend in [Backend::Tbr, Backend::Tbdr] {
        for budget in [BIG_BUDGET, 1 << 20] {
            let mut reference: Vec<(Vec<u8>, PassReport)> = Vec::new();
            for threads in [1, 2, 3] {
                let config = DeviceConfig { backend, threads, frame_data_budget: budget, ..DeviceConfig::default() };
                let mut device = Device::new(config).unwrap();
                let scene = many_triangles(&mut device);
                for frame in 0..2 {
                    let report = device.submit(&scene.passes[0]).unwrap();
                    let image = device.image_data(scene.images[0]).unwrap().to_vec();
                    assert!(image.iter().any(|&b| b != 0));
                    if threads == 1 {
                        reference.push((image, report));
                        continue;
                    }
                    let (want_image, want) = &reference[frame];
                    let at = format!("{backend}, budget {budget}, {threads} threads, frame {frame}");
                    assert!(&image == want_image, "image differs: {at}");
                    assert_eq!(report.ledger, want.ledger, "{at}");
                    assert_eq!(report.counters, want.counters, "{at}");
                    assert_eq!(report.frame_data.peak_bytes, want.frame_data.peak_bytes, "{at}");
                    assert_eq!(report.tiles, want.tiles, "{at}");
                }
            }
            if budget < BIG_BUDGET {
                assert!(reference[0].1.counters.incremental_renders >= 2);
            }
        }
    }
}
