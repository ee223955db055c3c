//! Subpasses, input attachments, pixel-local storage and transient attachments.

use super::common::*;
use tiler::*;

const W: u32 = 61;
const H: u32 = 37;

/// Writes `1 − input 0` (colour) and the input depth in alpha.
struct Invert;

impl FragmentShader for Invert {
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        let c = frag.input(0);
        let depth = frag.input(1)[0];
        frag.set_color(0, [F32x8::ONE - c[0], F32x8::ONE - c[1], F32x8::ONE - c[2], depth]);
    }
}

/// A full-screen triangle.
fn fullscreen_tri(device: &mut Device) -> BufferId {
    let c = [1.0; 4];
    device.create_buffer_from(&[v(-1.0, -1.0, 0.5, c), v(3.0, -1.0, 0.5, c), v(-1.0, 3.0, 0.5, c)]).unwrap()
}

/// Subpass 0 draws random triangles into a transient colour attachment with depth; subpass 1
/// reads colour and depth as inputs and writes the stored result.
fn two_subpasses(device: &mut Device, samples: u32, by_region: bool) -> TestScene {
    let out = device.create_image(ImageDesc::new(W, H, Format::Rgba32Float).with_samples(samples)).unwrap();
    let scratch =
        device.create_image(ImageDesc::new(W, H, Format::Rgba8Unorm).with_samples(samples).transient()).unwrap();
    let depth = device.create_image(ImageDesc::new(W, H, Format::D32Float).with_samples(samples).transient()).unwrap();
    let pass_desc = RenderPassDesc {
        color: vec![
            ColorAttachment::clear_store(out, [0.0; 4]),
            ColorAttachment {
                image: scratch,
                load: LoadOp::Clear([0.2, 0.4, 0.6, 1.0]),
                store: StoreOp::DontCare,
                resolve: None,
            },
        ],
        depth_stencil: Some(DepthStencilAttachment::clear_discard(depth, 1.0)),
        render_area: None,
    };
    let subpasses = vec![
        SubpassDesc { color: vec![1], depth_stencil: true, ..SubpassDesc::default() },
        SubpassDesc {
            color: vec![0],
            input: vec![AttachmentRef::Color(1), AttachmentRef::DepthStencil],
            ..SubpassDesc::default()
        },
    ];
    let mut pass =
        RenderPass::with_subpasses(pass_desc, subpasses, vec![SubpassDependency { src: 0, dst: 1, by_region }]);
    let mut rng = Rng(41);
    let tris: Vec<Vertex> = (0..3 * 30)
        .map(|_| v(rng.range(-1.2, 1.2), rng.range(-1.2, 1.2), rng.range(0.0, 1.0), rng.color(1.0)))
        .collect();
    let buffer = device.create_buffer_from(&tris).unwrap();
    let mut d = desc("g-buffer");
    d.depth_stencil = DepthStencilState::LESS_WRITE;
    pass.draw(Draw::new(&pipeline(Smooth, d), buffer, 0, 90));
    let screen = fullscreen_tri(device);
    pass.next_subpass().draw(Draw::new(&pipeline(Invert, desc("invert")), screen, 0, 3));
    TestScene { passes: vec![pass], images: vec![out] }
}

#[test]
fn every_backend_agrees_on_subpasses() {
    for samples in [1, 4] {
        for by_region in [true, false] {
            let build: Box<dyn Fn(&mut Device) -> TestScene> = Box::new(move |d| two_subpasses(d, samples, by_region));
            let build_fn = |d: &mut Device| build(d);
            let reference = {
                let mut device = device(Backend::Imr, 32, 1);
                let scene = build_fn(&mut device);
                device.submit(&scene.passes[0]).unwrap();
                device.image_data(scene.images[0]).unwrap().to_vec()
            };
            assert!(reference.iter().any(|b| *b != 0));
            for backend in Backend::ALL {
                for tile in [16, 32] {
                    for threads in [1, 2] {
                        let mut device = device(backend, tile, threads);
                        let scene = build_fn(&mut device);
                        let report = device.submit(&scene.passes[0]).unwrap();
                        assert!(
                            device.image_data(scene.images[0]).unwrap() == reference,
                            "{backend} {samples}× tile {tile}"
                        );
                        if backend.is_tiler() {
                            assert_eq!(report.counters.subpass_splits, !by_region as u64);
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn inputs_read_what_the_earlier_subpass_wrote() {
    let mut device = device(Backend::Tbr, 16, 2);
    let scene = two_subpasses(&mut device, 1, true);
    device.submit(&scene.passes[0]).unwrap();
    let data = device.image_data(scene.images[0]).unwrap();
    // A pixel no triangle covered: the clear colour (0.2, 0.4, 0.6) inverted, depth 1.
    let px = |i: usize| -> [f32; 4] {
        std::array::from_fn(|c| f32::from_le_bytes(data[16 * i + 4 * c..16 * i + 4 * c + 4].try_into().unwrap()))
    };
    let background = (0..(W * H) as usize).map(px).find(|p| p[3] == 1.0).expect("some background");
    let expect = [1.0 - 51.0 / 255.0, 1.0 - 102.0 / 255.0, 1.0 - 153.0 / 255.0, 1.0];
    for c in 0..4 {
        assert!((background[c] - expect[c]).abs() < 1e-6, "{background:?}");
    }
    assert!((0..(W * H) as usize).map(px).any(|p| p[3] < 1.0), "covered pixels carry their depth");
}

#[test]
fn by_region_keeps_the_g_buffer_on_chip_and_a_split_goes_through_memory() {
    let pixels = (W * H) as u64;
    let run = |by_region: bool, backend: Backend| {
        let mut device = device(backend, 16, 2);
        let scene = two_subpasses(&mut device, 1, by_region);
        device.submit(&scene.passes[0]).unwrap()
    };
    let kept = run(true, Backend::Tbr);
    assert_eq!(kept.ledger.get(Category::TileLoad), 0);
    assert_eq!(kept.ledger.get(Category::TileStore), pixels * 16, "only the output leaves the chip");
    assert_eq!(kept.transient_bytes_saved, pixels * (4 + 4));
    // Split: everything is stored (output 16 + scratch 4 + depth 4 bytes) and loaded back,
    // the transient attachments through spill memory.
    let split = run(false, Backend::Tbr);
    assert_eq!(split.counters.subpass_splits, 1);
    assert_eq!(split.ledger.get(Category::TileLoad), pixels * (16 + 4 + 4));
    assert_eq!(split.ledger.get(Category::TileStore), pixels * (16 + 4 + 4) + pixels * 16);
    assert_eq!(split.transient_bytes_saved, 0);
    // Immediate mode keeps everything in memory: the second subpass reads its inputs from
    // there, like textures.
    let imr = run(true, Backend::Imr);
    assert_eq!(imr.ledger.get(Category::TextureFetch), pixels * (4 + 4));
    assert_eq!(kept.ledger.get(Category::TextureFetch), 0);
}

/// Adds a quarter of the attachment's current red to itself plus 0.1: an accumulation that
/// needs the value under it, read from the tile (pixel-local storage), not blending.
struct Accumulate;

impl FragmentShader for Accumulate {
    fn properties(&self) -> ShaderProperties {
        ShaderProperties { reads_local: true, ..ShaderProperties::default() }
    }
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        let old = frag.local(0);
        let red = old[0] * 1.25 + 0.1;
        frag.set_color(0, [red, old[1], old[2], F32x8::ONE]);
    }
}

#[test]
fn pixel_local_storage_accumulates_in_submission_order() {
    let mut images = Vec::new();
    for backend in Backend::ALL {
        let mut device = device(backend, 16, 2);
        let out = device.create_image(ImageDesc::new(W, H, Format::Rgba32Float)).unwrap();
        let mut pass = color_pass(out, None);
        let mut rng = Rng(5);
        let tris: Vec<Vertex> =
            (0..3 * 40).map(|_| v(rng.range(-1.2, 1.2), rng.range(-1.2, 1.2), 0.5, [1.0; 4])).collect();
        let buffer = device.create_buffer_from(&tris).unwrap();
        pass.draw(Draw::new(&pipeline(Accumulate, desc("accumulate")), buffer, 0, 120));
        let report = device.submit(&pass).unwrap();
        if backend == Backend::Tbdr {
            assert_eq!(report.counters.hsr_fallback.pixel_local_read, report.counters.fragments_rasterized);
        }
        images.push(device.image_data(out).unwrap().to_vec());
    }
    assert!(images.windows(2).all(|p| p[0] == p[1]));
    // Each pixel's red is f applied once per covering triangle, from the clear value 0.1:
    // with k layers, r = 1.25^k · 0.1 + 0.1 · (1.25^k − 1) / 0.25; check it is one of those.
    let reds: Vec<f32> = images[0].chunks(16).map(|p| f32::from_le_bytes(p[..4].try_into().unwrap())).collect();
    let mut layered = [0.1f32; 40];
    for k in 1..40 {
        layered[k] = layered[k - 1] * 1.25 + 0.1;
    }
    assert!(reds.iter().all(|r| layered.contains(r)), "red values are whole numbers of layers");
    assert!(reds.iter().any(|r| *r > layered[3]), "some pixels have several layers");
}

#[test]
fn subpass_errors() {
    let mut device = device(Backend::Tbr, 16, 1);
    let a = device.create_image(ImageDesc::new(16, 16, Format::Rgba8Unorm)).unwrap();
    let b = device.create_image(ImageDesc::new(16, 16, Format::Rgba8Unorm)).unwrap();
    let submit = |device: &mut Device,
                  b_load: LoadOp<[f32; 4]>,
                  subpasses: Vec<SubpassDesc>,
                  deps: Vec<SubpassDependency>,
                  nexts: usize| {
        let desc = RenderPassDesc {
            color: vec![
                ColorAttachment::clear_store(a, [0.0; 4]),
                ColorAttachment { image: b, load: b_load, store: StoreOp::Store, resolve: None },
            ],
            depth_stencil: None,
            render_area: None,
        };
        let mut pass = RenderPass::with_subpasses(desc, subpasses, deps);
        for _ in 0..nexts {
            pass.next_subpass();
        }
        device.submit(&pass).map(|_| ()).unwrap_err().to_string()
    };
    let write = |c: u32| SubpassDesc { color: vec![c], ..SubpassDesc::default() };
    let read = |c: u32| SubpassDesc { color: vec![0], input: vec![AttachmentRef::Color(c)], ..SubpassDesc::default() };
    let e = submit(&mut device, LoadOp::DontCare, vec![write(0), read(1)], vec![], 1);
    assert!(e.contains("read without being written by an earlier subpass"), "{e}");
    let e = submit(&mut device, LoadOp::DontCare, vec![write(0), write(5)], vec![], 1);
    assert!(e.contains("colour attachment 5 does not exist"), "{e}");
    let e = submit(
        &mut device,
        LoadOp::DontCare,
        vec![write(1), SubpassDesc { input: vec![AttachmentRef::DepthStencil], ..write(0) }],
        vec![],
        1,
    );
    assert!(e.contains("the pass has none"), "{e}");
    let e = submit(
        &mut device,
        LoadOp::Load,
        vec![SubpassDesc { color: vec![0], input: vec![AttachmentRef::Color(0)], ..SubpassDesc::default() }],
        vec![],
        0,
    );
    assert!(e.contains("also written by this subpass"), "{e}");
    let e = submit(&mut device, LoadOp::Load, vec![write(0), write(1)], vec![], 2);
    assert!(e.contains("next_subpass was called 2 times"), "{e}");
    let e = submit(
        &mut device,
        LoadOp::Load,
        vec![write(0), write(1)],
        vec![SubpassDependency { src: 1, dst: 0, by_region: true }],
        1,
    );
    assert!(e.contains("dependency 0"), "{e}");
    // Loaded content may be read: no error.
    let desc = RenderPassDesc {
        color: vec![ColorAttachment::clear_store(a, [0.0; 4]), ColorAttachment::load_store(b)],
        depth_stencil: None,
        render_area: None,
    };
    assert!(device.submit(&RenderPass::with_subpasses(desc, vec![read(1)], vec![])).is_ok());
}

#[test]
fn a_transient_image_cannot_be_sampled_as_a_texture() {
    let mut device = device(Backend::Tbr, 16, 1);
    let transient = device.create_image(ImageDesc::new(16, 16, Format::Rgba8Unorm).transient()).unwrap();
    let e = device.texture_from_image(transient, MipChain::BaseOnly).unwrap_err().to_string();
    assert!(e.contains("transient image has no memory") && e.contains("input attachment"), "{e}");
    // An image with memory is sampled as it was stored: render to texture.
    let stored = device.create_image(ImageDesc::new(16, 16, Format::Rgba8Unorm)).unwrap();
    let pass = RenderPass::new(RenderPassDesc {
        color: vec![ColorAttachment::clear_store(stored, [1.0, 0.0, 0.0, 1.0])],
        depth_stencil: None,
        render_area: None,
    });
    device.submit(&pass).unwrap();
    let texture = device.texture_from_image(stored, MipChain::BaseOnly).unwrap();
    assert_eq!((texture.width(), texture.height()), (16, 16));
    let depth = device.create_image(ImageDesc::new(16, 16, Format::D32Float)).unwrap();
    assert!(device.texture_from_image(depth, MipChain::BaseOnly).is_err());
}
