//! Hidden-surface removal (TBDR) and multisampling: shading counts, resolve traffic, analytic
//! edge coverage, tile shrinking, and the invariant at every sample count.

use super::common::*;
use tiler::*;

/// `layers` full-screen opaque quads at depths from far to near (or near to far), each with
/// its own flat colour, into a cleared colour + D32F attachment pair.
fn layers_scene(
    device: &mut Device,
    size: (u32, u32),
    layers: usize,
    back_to_front: bool,
    samples: u32,
) -> (RenderPass, ImageId) {
    let color = device.create_image(ImageDesc::new(size.0, size.1, Format::Rgba8Unorm).with_samples(samples)).unwrap();
    let depth = device
        .create_image(ImageDesc::new(size.0, size.1, Format::D32Float).with_samples(samples).transient())
        .unwrap();
    let resolve =
        (samples > 1).then(|| device.create_image(ImageDesc::new(size.0, size.1, Format::Rgba8Unorm)).unwrap());
    let mut verts = Vec::new();
    for k in 0..layers {
        let j = if back_to_front { k } else { layers - 1 - k };
        let z = 1.0 - (j as f32 + 1.0) / (layers as f32 + 1.0);
        let c = [j as f32 / layers as f32, 0.5, 1.0 - j as f32 / layers as f32, 1.0];
        verts.extend([
            v(-1.0, -1.0, z, c),
            v(-1.0, 1.0, z, c),
            v(1.0, 1.0, z, c),
            v(-1.0, -1.0, z, c),
            v(1.0, 1.0, z, c),
            v(1.0, -1.0, z, c),
        ]);
    }
    let buffer = device.create_buffer_from(&verts).unwrap();
    let mut d = desc("layers");
    d.depth_stencil = DepthStencilState::LESS_WRITE;
    let color_attachment = match resolve {
        Some(r) => ColorAttachment::clear_resolve(color, [0.0; 4], r),
        None => ColorAttachment::clear_store(color, [0.0; 4]),
    };
    let mut pass = RenderPass::new(RenderPassDesc {
        color: vec![color_attachment],
        depth_stencil: Some(DepthStencilAttachment::clear_discard(depth, 1.0)),
        render_area: None,
    });
    pass.draw(Draw::new(&pipeline(FlatColor, d), buffer, 0, verts.len() as u32));
    (pass, resolve.unwrap_or(color))
}

#[test]
fn thirty_two_layers_back_to_front_shade_once_with_hsr() {
    let (w, h) = (96, 64);
    let pixels = (w * h) as u64;
    let mut images = Vec::new();
    for back_to_front in [true, false] {
        for backend in Backend::ALL {
            let mut device = device(backend, 32, 2);
            let (pass, color) = layers_scene(&mut device, (w, h), 32, back_to_front, 1);
            let report = device.submit(&pass).unwrap();
            let shaded = report.counters.fragments_shaded;
            match (backend, back_to_front) {
                (Backend::Tbdr, _) => {
                    assert_eq!(shaded, pixels, "TBDR shades each pixel once in any order");
                    if back_to_front {
                        assert_eq!(report.counters.fragments_hsr_killed, 31 * pixels);
                    }
                }
                (_, true) => assert_eq!(shaded, 32 * pixels, "{backend}: every layer passes the depth test"),
                (_, false) => {
                    assert_eq!(shaded, pixels, "{backend}: early-Z rejects the hidden layers");
                    assert_eq!(report.counters.fragments_early_z_killed, 31 * pixels);
                }
            }
            images.push(device.read_rgba8(color).unwrap());
        }
    }
    assert!(images.windows(2).all(|p| p[0] == p[1]), "every backend and order shows the nearest layer");
}

#[test]
fn msaa_resolved_in_the_tile_stores_what_one_sample_stores() {
    let (w, h) = (128, 96);
    let pixels = (w * h) as u64;
    let framebuffer = |r: &PassReport| {
        r.ledger.total()
            - r.ledger.get(Category::VertexFetch)
            - r.ledger.get(Category::FrameDataWrite)
            - r.ledger.get(Category::FrameDataRead)
    };
    let run = |backend, samples| {
        let mut device = device(backend, 32, 2);
        let (pass, _) = layers_scene(&mut device, (w, h), 4, false, samples);
        device.submit(&pass).unwrap()
    };
    for backend in [Backend::Tbr, Backend::Tbdr] {
        let one = run(backend, 1);
        assert_eq!(one.ledger.get(Category::TileStore), pixels * 4);
        for samples in [4, 16] {
            let many = run(backend, samples);
            assert_eq!(many.ledger.get(Category::TileStore), 0, "the samples never leave the chip");
            assert_eq!(many.ledger.get(Category::Resolve), pixels * 4);
            assert_eq!(framebuffer(&many), framebuffer(&one), "{backend}, {samples}×: same bytes as one sample");
        }
    }
    // Immediate mode: every framebuffer access is per sample, S× the single-sample traffic
    // (seed 000 §23.9), and the resolve reads the S samples back and writes 1 on top of it.
    let one = run(Backend::Imr, 1);
    for samples in [4u64, 16] {
        let many = run(Backend::Imr, samples as u32);
        let resolve = many.ledger.get(Category::Resolve);
        assert_eq!(framebuffer(&many) - resolve, samples * framebuffer(&one));
        assert_eq!(resolve, pixels * 4 * (samples + 1), "read {samples} samples, write 1");
    }
}

#[test]
fn storing_samples_costs_samples_times_bytes() {
    let mut device = device(Backend::Tbr, 32, 2);
    let color = device.create_image(ImageDesc::new(64, 32, Format::Rgba8Unorm).with_samples(4)).unwrap();
    let report = device
        .submit(&RenderPass::new(RenderPassDesc {
            color: vec![ColorAttachment::clear_store(color, [1.0, 0.0, 0.0, 1.0])],
            depth_stencil: None,
            render_area: None,
        }))
        .unwrap();
    assert_eq!(report.ledger.get(Category::TileStore), 64 * 32 * 4 * 4);
    assert!(device.image_data(color).unwrap().chunks(4).all(|p| p == [255, 0, 0, 255]));
}

/// Which of the standard sample positions of pixel (x, y) a triangle (window coordinates,
/// exact in 1/256) covers, by the top-left rule.
fn analytic_coverage(tri: &[(i64, i64); 3], x: i64, y: i64, positions: &[(i64, i64)]) -> usize {
    let area = (tri[1].0 - tri[0].0) * (tri[2].1 - tri[0].1) - (tri[1].1 - tri[0].1) * (tri[2].0 - tri[0].0);
    let q = if area > 0 { *tri } else { [tri[0], tri[2], tri[1]] };
    positions
        .iter()
        .filter(|&&(sx, sy)| {
            let (px, py) = (x * 256 + sx, y * 256 + sy);
            (0..3).all(|i| {
                let (a, b) = (q[i], q[(i + 1) % 3]);
                let e = (b.0 - a.0) * (py - a.1) - (b.1 - a.1) * (px - a.0);
                e > 0 || (e == 0 && ((b.1 - a.1) < 0 || (b.1 == a.1 && b.0 > a.0)))
            })
        })
        .count()
}

#[test]
fn edges_are_antialiased_with_the_standard_pattern() {
    let size = 32u32;
    // Window coordinates in 1/256 pixel: a long thin triangle with edges at odd slopes.
    let tri: [(i64, i64); 3] = [(300, 500), (7900, 1900), (2100, 7700)];
    // The Vulkan specification's "Standard sample locations", in 1/16 pixel from the
    // pixel's top-left corner, written out here independently of the rasterizer's table.
    let positions4 = [(6, 2), (14, 6), (2, 10), (10, 14)];
    let positions16 = [
        (9, 9),
        (7, 5),
        (5, 10),
        (12, 7),
        (3, 6),
        (10, 13),
        (13, 11),
        (11, 3),
        (6, 14),
        (8, 1),
        (4, 2),
        (2, 12),
        (0, 8),
        (15, 4),
        (14, 15),
        (1, 0),
    ];
    let patterns: [&[(i64, i64)]; 2] = [&positions4, &positions16];
    for pattern in patterns {
        let samples = pattern.len() as u32;
        let positions: Vec<(i64, i64)> = pattern.iter().map(|&(x, y)| (x * 16, y * 16)).collect();
        for backend in Backend::ALL {
            for simd in [None, Some(SimdLevel::Baseline)] {
                let config =
                    DeviceConfig { backend, tile_width: 16, tile_height: 16, threads: 2, simd, ..Default::default() };
                let mut device = Device::new(config).unwrap();
                let msaa =
                    device.create_image(ImageDesc::new(size, size, Format::Rgba32Float).with_samples(samples)).unwrap();
                let resolve = device.create_image(ImageDesc::new(size, size, Format::Rgba32Float)).unwrap();
                let verts: Vec<Vertex> = tri
                    .iter()
                    .map(|&(x, y)| {
                        v(
                            (x as f32 / 256.0) / size as f32 * 2.0 - 1.0,
                            (y as f32 / 256.0) / size as f32 * 2.0 - 1.0,
                            0.5,
                            [1.0; 4],
                        )
                    })
                    .collect();
                let buffer = device.create_buffer_from(&verts).unwrap();
                let mut pass = RenderPass::new(RenderPassDesc {
                    color: vec![ColorAttachment::clear_resolve(msaa, [0.0; 4], resolve)],
                    depth_stencil: None,
                    render_area: None,
                });
                pass.draw(Draw::new(&pipeline(Solid([1.0; 4]), desc("white")), buffer, 0, 3));
                device.submit(&pass).unwrap();
                let data = device.image_data(resolve).unwrap();
                let mut edge_pixels = 0;
                let mut levels = std::collections::BTreeSet::new();
                for y in 0..size as i64 {
                    for x in 0..size as i64 {
                        let i = (y * size as i64 + x) as usize * 16;
                        let value = f32::from_le_bytes(data[i..i + 4].try_into().unwrap());
                        let covered = analytic_coverage(&tri, x, y, &positions);
                        assert_eq!(value, covered as f32 / samples as f32, "{samples}×, {backend} pixel ({x}, {y})");
                        if covered > 0 && covered < samples as usize {
                            edge_pixels += 1;
                            levels.insert(covered);
                        }
                    }
                }
                assert!(edge_pixels > 40, "the test must cross many edge pixels: {edge_pixels}");
                // Sixteen samples give the edges more shades than four can.
                assert!(levels.len() >= if samples == 16 { 10 } else { 3 }, "{samples}×: {levels:?}");
            }
        }
    }
}

#[test]
fn silhouettes_shade_more_fragments_with_msaa() {
    // Many small overlapping triangles: more pixels touch an edge with four samples.
    let build = |samples: u32| {
        move |device: &mut Device| {
            let color = device.create_image(ImageDesc::new(120, 80, Format::Rgba8Unorm).with_samples(samples)).unwrap();
            let mut rng = Rng(17);
            let tris: Vec<Vertex> =
                (0..3 * 200).map(|_| v(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.5, rng.color(1.0))).collect();
            let buffer = device.create_buffer_from(&tris).unwrap();
            let mut pass = color_pass(color, None);
            pass.draw(Draw::new(&pipeline(FlatColor, desc("tris")), buffer, 0, tris.len() as u32));
            pass
        }
    };
    let shaded = |samples: u32| {
        let mut device = device(Backend::Tbr, 32, 2);
        let pass = build(samples)(&mut device);
        device.submit(&pass).unwrap().counters.fragments_shaded
    };
    let (one, four) = (shaded(1), shaded(4));
    let extra = four as f64 / one as f64 - 1.0;
    assert!((0.02..0.5).contains(&extra), "extra fragments along silhouettes: {:.1}%", extra * 100.0);
}

/// Per-sample shading: each sample gets its own colour (here, its own position).
struct SamplePosition;

impl FragmentShader for SamplePosition {
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        let (x, y) = frag.position();
        frag.set_color(0, [x.fract(), y.fract(), F32x8::splat(0.5), F32x8::ONE]);
    }
}

/// Writes a sample mask keeping the even samples in even columns, the odd ones in odd columns.
struct Checkered;

impl FragmentShader for Checkered {
    fn properties(&self) -> ShaderProperties {
        ShaderProperties { writes_sample_mask: true, ..ShaderProperties::default() }
    }
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        frag.set_sample_mask(std::array::from_fn(|lane| if lane % 2 == 0 { 0x5555 } else { 0xaaaa }));
        frag.set_color(0, frag.smooth_n::<4>(0));
    }
}

/// Many features at once, at every sample count, for the invariant.
fn msaa_features(device: &mut Device, samples: u32) -> TestScene {
    let (w, h) = (83, 57);
    let color = device.create_image(ImageDesc::new(w, h, Format::Rgba8Unorm).with_samples(samples)).unwrap();
    let resolve = device.create_image(ImageDesc::new(w, h, Format::Rgba8Unorm)).unwrap();
    let ds = device.create_image(ImageDesc::new(w, h, Format::D24UnormS8Uint).with_samples(samples)).unwrap();
    let mut rng = Rng(23);
    let tris: Vec<Vertex> = (0..3 * 120)
        .map(|_| v(rng.range(-1.2, 1.2), rng.range(-1.2, 1.2), rng.range(0.0, 1.0), rng.color_alpha(0.0, 1.0)))
        .collect();
    let buffer = device.create_buffer_from(&tris).unwrap();
    let color_attachment = if samples > 1 {
        ColorAttachment {
            image: color,
            load: LoadOp::Clear([0.2, 0.1, 0.0, 1.0]),
            store: StoreOp::Store,
            resolve: Some(resolve),
        }
    } else {
        ColorAttachment::clear_store(color, [0.2, 0.1, 0.0, 1.0])
    };
    let mut pass = RenderPass::new(RenderPassDesc {
        color: vec![color_attachment],
        depth_stencil: Some(DepthStencilAttachment::clear_store(ds, 1.0, 0)),
        render_area: None,
    });
    let mut opaque = desc("opaque");
    opaque.depth_stencil = DepthStencilState::LESS_WRITE;
    pass.draw(Draw::new(&pipeline(Smooth, opaque.clone()), buffer, 0, 60));
    let mut a2c = opaque.clone();
    a2c.multisample.alpha_to_coverage = true;
    pass.draw(Draw::new(&pipeline(Smooth, a2c), buffer, 60, 60));
    pass.draw(Draw::new(&pipeline(AlphaTest, opaque.clone()), buffer, 120, 60));
    let mut per_sample = opaque.clone();
    per_sample.multisample.sample_shading = true;
    pass.draw(Draw::new(&pipeline(SamplePosition, per_sample), buffer, 180, 60));
    let mut masked = opaque.clone();
    // Samples 1 and 2, and 14 and 15 at 16×.
    masked.multisample.sample_mask = 0xc006;
    pass.draw(Draw::new(&pipeline(FlatColor, masked), buffer, 240, 30));
    pass.draw(Draw::new(&pipeline(Checkered, opaque.clone()), buffer, 270, 30));
    let mut blended = opaque;
    blended.depth_stencil = DepthStencilState::LESS_NO_WRITE;
    blended.color_targets = vec![ColorTargetState::ALPHA_BLEND];
    pass.draw(Draw::new(&pipeline(Smooth, blended), buffer, 300, 60));
    let images = if samples > 1 { vec![color, resolve, ds] } else { vec![color, ds] };
    TestScene { passes: vec![pass], images }
}

#[test]
fn every_backend_agrees_at_every_sample_count() {
    let builders: [fn(&mut Device) -> TestScene; 5] = [
        |d| msaa_features(d, 1),
        |d| msaa_features(d, 2),
        |d| msaa_features(d, 4),
        |d| msaa_features(d, 8),
        |d| msaa_features(d, 16),
    ];
    for (i, build) in builders.into_iter().enumerate() {
        let (reference, _) = render_scene(build, Backend::Imr, (32, 32), 1, 64 << 20);
        for backend in Backend::ALL {
            for tile in [(16, 16), (32, 32), (64, 32)] {
                for threads in [1, 3] {
                    let (images, report) = render_scene(build, backend, tile, threads, 64 << 20);
                    for (k, (a, b)) in images.iter().zip(&reference).enumerate() {
                        assert!(
                            a == b,
                            "{} samples: image {k} differs on {backend}, tile {tile:?}, {threads} threads",
                            1 << i
                        );
                    }
                    if backend == Backend::Tbdr {
                        let fallback = report.counters.hsr_fallback;
                        assert!(fallback.alpha_to_coverage > 0 && fallback.discard > 0 && fallback.blending > 0);
                        assert!(fallback.sample_mask > 0);
                    }
                }
            }
            // The baseline pipeline (the others above ran at the best level this processor has).
            let (images, _) = render_scene_at(build, backend, (32, 32), 2, 64 << 20, Some(SimdLevel::Baseline));
            assert!(images == reference, "{} samples: the baseline SIMD level differs on {backend}", 1 << i);
        }
    }
}

#[test]
fn the_tile_shrinks_when_attachments_outgrow_tile_memory() {
    let build = |device: &mut Device| -> TestScene {
        let scene = msaa_features(device, 8);
        TestScene { passes: scene.passes, images: scene.images }
    };
    // 8 samples × (4 + 4) bytes × 32×32 = 64 KiB > 32 KiB: 32×16 tiles.
    let (images, report) = render_scene(build, Backend::Tbr, (32, 32), 2, 64 << 20);
    assert_eq!(report.tile_shrunk_from, Some((32, 32)));
    assert_eq!((report.tile_width, report.tile_height), (16, 32));
    assert_eq!(report.tile_bytes, 32 << 10);
    let (reference, _) = render_scene(build, Backend::Imr, (32, 32), 2, 64 << 20);
    assert_eq!(images, reference);
}

#[test]
fn sixteen_samples_shrink_the_tile_further() {
    let build = |device: &mut Device| -> TestScene {
        let scene = msaa_features(device, 16);
        TestScene { passes: scene.passes, images: scene.images }
    };
    // 16 samples × (4 + 4) bytes × 32×32 = 128 KiB > 32 KiB: halved twice, to 16×16 (32 KiB).
    let (images, report) = render_scene(build, Backend::Tbdr, (32, 32), 2, 64 << 20);
    assert_eq!(report.tile_shrunk_from, Some((32, 32)));
    assert_eq!((report.tile_width, report.tile_height), (16, 16));
    assert_eq!(report.tile_bytes, 32 << 10);
    let (reference, _) = render_scene(build, Backend::Imr, (32, 32), 2, 64 << 20);
    assert_eq!(images, reference);
}

/// A 40×24 pass at 16 samples that loads and stores everything: an RGBA8 colour attachment
/// also resolved into a single-sample image, and a packed D24S8 attachment.
fn sixteen_samples_load_store(device: &mut Device) -> TestScene {
    let (w, h) = (40, 24);
    let color = device.create_image(ImageDesc::new(w, h, Format::Rgba8Unorm).with_samples(16)).unwrap();
    let resolve = device.create_image(ImageDesc::new(w, h, Format::Rgba8Unorm)).unwrap();
    let ds = device.create_image(ImageDesc::new(w, h, Format::D24UnormS8Uint).with_samples(16)).unwrap();
    let tris = [
        v(-1.0, -1.0, 0.5, [1.0, 0.0, 0.0, 1.0]),
        v(0.9, -0.7, 0.5, [1.0, 0.0, 0.0, 1.0]),
        v(-0.4, 1.0, 0.5, [1.0, 0.0, 0.0, 1.0]),
    ];
    let buffer = device.create_buffer_from(&tris).unwrap();
    let mut pass = RenderPass::new(RenderPassDesc {
        color: vec![ColorAttachment {
            image: color,
            load: LoadOp::Load,
            store: StoreOp::Store,
            resolve: Some(resolve),
        }],
        depth_stencil: Some(DepthStencilAttachment {
            image: ds,
            depth_load: LoadOp::Load,
            depth_store: StoreOp::Store,
            stencil_load: LoadOp::Load,
            stencil_store: StoreOp::Store,
        }),
        render_area: None,
    });
    let mut d = desc("tri");
    d.depth_stencil = DepthStencilState::LESS_WRITE;
    pass.draw(Draw::new(&pipeline(FlatColor, d), buffer, 0, 3));
    TestScene { passes: vec![pass], images: vec![color, resolve, ds] }
}

#[test]
fn the_ledger_counts_sixteen_samples_by_hand() {
    // 40×24 = 960 pixels, 16 samples each.
    // Tile load: colour 960 × 16 × 4 B = 61,440 B; D24S8, both aspects sharing one 32-bit
    // word per sample, 960 × 16 × 4 B = 61,440 B; in all 122,880 B. The store is the same.
    // Resolve: one RGBA8 value per pixel, 960 × 4 B = 3,840 B.
    for backend in [Backend::Tbr, Backend::Tbdr] {
        for tile in [(16, 16), (64, 64)] {
            let (_, report) = render_scene(sixteen_samples_load_store, backend, tile, 2, 64 << 20);
            assert_eq!(report.ledger.get(Category::TileLoad), 122_880, "{backend}, tile {tile:?}");
            assert_eq!(report.ledger.get(Category::TileStore), 122_880, "{backend}, tile {tile:?}");
            assert_eq!(report.ledger.get(Category::Resolve), 3_840, "{backend}, tile {tile:?}");
        }
    }
    // Frame data does not depend on the sample count: full-screen quads (their boxes meet
    // every tile whatever the sample pattern) bin the same at 1 and 16 samples.
    let frame_data = |samples| {
        let config = DeviceConfig { tile_memory_bytes: 1 << 20, ..Default::default() };
        let mut device = Device::new(DeviceConfig { backend: Backend::Tbr, ..config }).unwrap();
        let (pass, _) = layers_scene(&mut device, (128, 96), 4, false, samples);
        let report = device.submit(&pass).unwrap();
        assert_eq!(report.tile_shrunk_from, None);
        (report.ledger.get(Category::FrameDataWrite), report.ledger.get(Category::FrameDataRead))
    };
    assert_eq!(frame_data(16), frame_data(1));
}

#[test]
fn transient_msaa_survives_incremental_renders() {
    // Many triangles into a transient 4× attachment, resolved, with a tiny frame-data budget:
    // the samples spill to scratch memory between flushes and the picture is unchanged.
    let build = |device: &mut Device| -> TestScene {
        let (w, h) = (64, 48);
        let msaa = device.create_image(ImageDesc::new(w, h, Format::Rgba8Unorm).with_samples(4).transient()).unwrap();
        let resolve = device.create_image(ImageDesc::new(w, h, Format::Rgba8Unorm)).unwrap();
        let depth = device.create_image(ImageDesc::new(w, h, Format::D16Unorm).with_samples(4).transient()).unwrap();
        let mut rng = Rng(31);
        let mut tris = Vec::new();
        for _ in 0..30_000 {
            let (cx, cy, z, c) = (rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(0.0, 1.0), rng.color(1.0));
            for _ in 0..3 {
                tris.push(v(cx + rng.range(-0.08, 0.08), cy + rng.range(-0.08, 0.08), z, c));
            }
        }
        let buffer = device.create_buffer_from(&tris).unwrap();
        let mut d = desc("many");
        d.depth_stencil = DepthStencilState::LESS_WRITE;
        let mut pass = RenderPass::new(RenderPassDesc {
            color: vec![ColorAttachment::clear_resolve(msaa, [0.0; 4], resolve)],
            depth_stencil: Some(DepthStencilAttachment::clear_discard(depth, 1.0)),
            render_area: None,
        });
        pass.draw(Draw::new(&pipeline(FlatColor, d), buffer, 0, tris.len() as u32));
        TestScene { passes: vec![pass], images: vec![resolve] }
    };
    let (reference, _) = render_scene(build, Backend::Imr, (32, 32), 2, 64 << 20);
    for backend in [Backend::Tbr, Backend::Tbdr] {
        let (images, report) = render_scene(build, backend, (32, 32), 2, 1 << 20);
        assert!(report.counters.incremental_renders > 0);
        assert_eq!(images, reference, "{backend}");
        // Spills store and reload all four samples of colour and depth.
        let n = report.counters.incremental_renders;
        assert_eq!(report.ledger.get(Category::TileStore), n * 64 * 48 * 4 * (4 + 2));
    }
}
