//! The cost model: each ledger formula on small hand-checked cases, and the seeds' arithmetic
//! through the public API.

use super::common::*;
use tiler::*;

fn device_with(config: DeviceConfig) -> Device {
    Device::new(DeviceConfig { threads: 2, ..config }).unwrap()
}

fn preset(name: &str) -> DeviceConfig {
    DevicePreset::builtin(name).unwrap().device
}

/// A full-screen quad (two triangles) at depth `z`.
fn fullscreen(z: f32) -> Vec<Vertex> {
    let c = [1.0, 1.0, 1.0, 1.0];
    vec![
        v(-1.0, -1.0, z, c),
        v(-1.0, 1.0, z, c),
        v(1.0, 1.0, z, c),
        v(-1.0, -1.0, z, c),
        v(1.0, 1.0, z, c),
        v(1.0, -1.0, z, c),
    ]
}

/// Seed 004 §24.3.2: 1024×768, 16-bit colour and depth, 60 frames/s. One full-screen access
/// is 94 MB/s; a clear-fill-display frame is 6 of them on an immediate-mode GPU (8 with
/// composition) and 2 on a tiler (4 with composition).
#[test]
fn the_seeds_clear_fill_display_arithmetic() {
    let access = 1024u64 * 768 * 2;
    assert_eq!((access as f64 * 60.0 / 1e6 * 100.0).round() / 100.0, 94.37);
    for (name, accesses, with_composition) in [("imr-no-cache", 6, 8), ("tbr", 2, 4), ("tbdr", 2, 4)] {
        for composition in [false, true] {
            let mut config = preset(name);
            config.display.composition = composition;
            let mut device = device_with(config);
            let color = device.create_image(ImageDesc::new(1024, 768, Format::Rgb565Unorm)).unwrap();
            let depth = device.create_image(ImageDesc::new(1024, 768, Format::D16Unorm)).unwrap();
            let mut pass = color_pass(color, Some(DepthStencilAttachment::clear_discard(depth, 1.0)));
            let mut d = desc("fill");
            d.depth_stencil = DepthStencilState::LESS_WRITE;
            let quad = device.create_buffer_from(&fullscreen(0.5)).unwrap();
            pass.draw(Draw::new(&pipeline(FlatColor, d), quad, 0, 6));
            let mut frame = FrameCost::new(vec![device.submit(&pass).unwrap()]);
            frame.present = device.present(color).unwrap();
            let ledger = frame.ledger();
            let framebuffer = ledger.total() - ledger.geometry_bytes();
            let expected = if composition { with_composition } else { accesses };
            assert_eq!(framebuffer, expected * access, "{name}, composition {composition}");
            let mb_per_second = framebuffer as f64 * 60.0 / 1e6;
            assert!((mb_per_second - expected as f64 * 94.371_84).abs() < 1e-3, "{name}: {mb_per_second} MB/s");
        }
    }
}

#[test]
fn one_triangle_geometry_and_frame_data() {
    let mut device = device_with(DeviceConfig::default().with_tile_size(16));
    let color = device.create_image(ImageDesc::new(32, 32, Format::Rgba8Unorm)).unwrap();
    let c = [1.0; 4];
    let vb = device.create_buffer_from(&[v(-0.9, -0.9, 0.5, c), v(0.9, -0.9, 0.5, c), v(-0.9, 0.9, 0.5, c)]).unwrap();
    let ib = device.create_buffer_from(&[0u16, 1, 2]).unwrap();
    let mut pass = color_pass(color, None);
    pass.draw(Draw::indexed(&pipeline(Smooth, desc("one")), vb, ib, IndexType::U16, 0, 3));
    let r = device.submit(&pass).unwrap();
    // Vertex fetch: 3 vertices × (16 + 16) attribute bytes = 96 bytes, read as the two
    // 64-byte lines they lie in; index fetch: 3 × 2.
    assert_eq!(r.ledger.get(Category::VertexFetch), 2 * 64);
    assert_eq!(r.ledger.get(Category::IndexFetch), 3 * 2);
    // The triangle covers 3 of the 4 tiles: one record (8 + 3 × (16 + 4 × 4 varyings)),
    // 3 list entries of 4 bytes, one 64-byte state record.
    let record = 8 + 3 * (16 + 4 * 4);
    assert_eq!(r.counters.polygon_list_entries, 3);
    assert_eq!(r.ledger.get(Category::FrameDataWrite), record + 3 * 4 + 64);
    // Each of the 3 tiles reads its entry, the record and the state.
    assert_eq!(r.ledger.get(Category::FrameDataRead), 3 * (4 + record + 64));
    // Colour is stored for all four tiles; nothing is loaded.
    assert_eq!(r.ledger.get(Category::TileStore), 32 * 32 * 4);
    assert_eq!(r.ledger.get(Category::TileLoad), 0);
}

#[test]
fn the_post_transform_cache_saves_shared_vertices() {
    let c = [1.0; 4];
    // Two triangles sharing two vertices.
    let verts = [v(-1.0, -1.0, 0.5, c), v(1.0, -1.0, 0.5, c), v(-1.0, 1.0, 0.5, c), v(1.0, 1.0, 0.5, c)];
    for (cache, shaded) in [(32, 4), (0, 6), (2, 4), (1, 5)] {
        let mut device = device_with(DeviceConfig { post_transform_cache: cache, ..DeviceConfig::default() });
        let mut exact = device_with(DeviceConfig {
            post_transform_cache: cache,
            vertex_cache: CacheConfig::NONE,
            ..DeviceConfig::default()
        });
        let color = device.create_image(ImageDesc::new(16, 16, Format::Rgba8Unorm)).unwrap();
        let vb = device.create_buffer_from(&verts).unwrap();
        let ib = device.create_buffer_from(&[0u32, 1, 2, 2, 1, 3]).unwrap();
        let mut pass = color_pass(color, None);
        pass.draw(Draw::indexed(&pipeline(Smooth, desc("quad")), vb, ib, IndexType::U32, 0, 6));
        let r = device.submit(&pass).unwrap();
        assert_eq!(r.counters.vertices_shaded, shaded, "cache of {cache}");
        // The 4 vertices' 128 bytes are two 64-byte lines: the vertex cache reads each once,
        // however often the post-transform cache misses.
        assert_eq!(r.ledger.get(Category::VertexFetch), 2 * 64);
        // Without a vertex cache every vertex shaded costs its exact 32 bytes.
        let exact_vb = exact.create_buffer_from(&verts).unwrap();
        let exact_ib = exact.create_buffer_from(&[0u32, 1, 2, 2, 1, 3]).unwrap();
        let exact_color = exact.create_image(ImageDesc::new(16, 16, Format::Rgba8Unorm)).unwrap();
        let mut pass = color_pass(exact_color, None);
        pass.draw(Draw::indexed(&pipeline(Smooth, desc("quad")), exact_vb, exact_ib, IndexType::U32, 0, 6));
        assert_eq!(exact.submit(&pass).unwrap().ledger.get(Category::VertexFetch), shaded * 32);
    }
}

#[test]
fn position_only_binning_shades_vertices_again_per_tile() {
    let mut config = preset("tbr-per-tile-vertex");
    config.tile_width = 16;
    config.tile_height = 16;
    let mut device = device_with(config);
    let color = device.create_image(ImageDesc::new(32, 16, Format::Rgba8Unorm)).unwrap();
    let c = [1.0; 4];
    // A triangle across both tiles of a 32×16 framebuffer.
    let vb = device.create_buffer_from(&[v(-0.9, -0.9, 0.5, c), v(0.9, -0.9, 0.5, c), v(0.0, 0.9, 0.5, c)]).unwrap();
    let mut pass = color_pass(color, None);
    pass.draw(Draw::new(&pipeline(Smooth, desc("wide")), vb, 0, 3));
    let r = device.submit(&pass).unwrap();
    assert_eq!(r.counters.polygon_list_entries, 2);
    // Binning fetches the 3 vertices once; each of the 2 tiles fetches them again: each time
    // their 96 bytes are two 64-byte lines.
    assert_eq!(r.ledger.get(Category::VertexFetch), (1 + 2) * 2 * 64);
    assert_eq!(r.counters.vertices_shaded, 3 + 2 * 3);
    // The record holds positions only: 8 + 3 × 16.
    assert_eq!(r.ledger.get(Category::FrameDataWrite), (8 + 3 * 16) + 2 * 4 + 64);
}

#[test]
fn a_framebuffer_cache_absorbs_repeated_accesses() {
    // Four full-screen layers back to front on 64×32 pixels: colour and depth (8 KiB each)
    // fit a 64 KiB cache, so each depth line is filled once and written back once; colour,
    // written without blending, is never read (write-validate).
    let (w, h) = (64u32, 32u32);
    let run = |cache: CacheConfig| {
        let mut config = preset("imr");
        config.framebuffer_cache = cache;
        let mut device = device_with(config);
        let color = device.create_image(ImageDesc::new(w, h, Format::Rgba8Unorm)).unwrap();
        let depth = device.create_image(ImageDesc::new(w, h, Format::D32Float)).unwrap();
        let mut pass = color_pass(color, Some(DepthStencilAttachment::clear_discard(depth, 1.0)));
        let mut d = desc("layers");
        d.depth_stencil = DepthStencilState::LESS_WRITE;
        let layers: Vec<Vertex> = (0..4).flat_map(|i| fullscreen(0.8 - 0.2 * i as f32)).collect();
        let vb = device.create_buffer_from(&layers).unwrap();
        pass.draw(Draw::new(&pipeline(FlatColor, d), vb, 0, 24));
        device.submit(&pass).unwrap()
    };
    let pixels = (w * h) as u64;
    let raw = run(CacheConfig::NONE);
    assert_eq!(raw.ledger.get(Category::ImrDepthRead), 4 * pixels * 4);
    assert_eq!(raw.ledger.get(Category::ImrDepthWrite), 4 * pixels * 4);
    assert_eq!(raw.ledger.get(Category::ImrColorWrite), 4 * pixels * 4);
    let cached = run(CacheConfig { size_bytes: 64 << 10, line_bytes: 64, ways: 8 });
    assert_eq!(cached.ledger.get(Category::ImrDepthRead), pixels * 4, "each depth line filled once");
    assert_eq!(cached.ledger.get(Category::ImrColorRead), 0, "colour lines are written without a fill");
    assert_eq!(cached.ledger.get(Category::ImrDepthWrite), pixels * 4, "each depth line written back once");
    assert_eq!(cached.ledger.get(Category::ImrColorWrite), pixels * 4);
    assert_eq!(
        cached.on_chip_bytes,
        raw.ledger.total() - raw.ledger.geometry_bytes() - raw.ledger.get(Category::ImrClear)
    );
    assert!(cached.ledger.total() < raw.ledger.total(), "the cache saves traffic");
}

#[test]
fn transaction_elimination_skips_unchanged_tiles() {
    let mut config = preset("tbr");
    config.tile_width = 16;
    config.tile_height = 16;
    let mut device = device_with(config);
    let color = device.create_image(ImageDesc::new(64, 32, Format::Rgba8Unorm)).unwrap();
    let c = [1.0, 0.0, 0.0, 1.0];
    let vb = device.create_buffer_from(&[v(-1.0, -1.0, 0.5, c), v(-0.8, -1.0, 0.5, c), v(-1.0, -0.8, 0.5, c)]).unwrap();
    let still = color_pass(color, None);
    let mut moved = color_pass(color, None);
    moved.draw(Draw::new(&pipeline(FlatColor, desc("corner")), vb, 0, 3));
    let first = device.submit(&still).unwrap();
    assert_eq!(first.ledger.get(Category::TileStore), 64 * 32 * 4);
    assert_eq!(first.transaction_elimination_saved, 0);
    let second = device.submit(&still).unwrap();
    assert_eq!(second.ledger.get(Category::TileStore), 0, "nothing changed");
    assert_eq!(second.transaction_elimination_saved, 64 * 32 * 4);
    // A triangle in the top-left corner changes one tile only.
    let third = device.submit(&moved).unwrap();
    assert_eq!(third.ledger.get(Category::TileStore), 16 * 16 * 4);
    assert_eq!(&device.read_rgba8(color).unwrap()[..4], &[255, 0, 0, 255]);
    // Writing the image another way forgets the signatures.
    device.write_image(color, &vec![0; 64 * 32 * 4]).unwrap();
    assert_eq!(device.submit(&moved).unwrap().ledger.get(Category::TileStore), 64 * 32 * 4);
}

#[test]
fn energy_and_on_chip_bytes() {
    let mut device = device_with(preset("tbr"));
    let color = device.create_image(ImageDesc::new(32, 32, Format::Rgba8Unorm)).unwrap();
    let frame = FrameCost::new(vec![device.submit(&color_pass(color, None)).unwrap()]);
    // A clear and a store: the store reads the tile buffer as it writes memory.
    assert_eq!(frame.ledger().total(), 32 * 32 * 4);
    assert_eq!(frame.on_chip_bytes(), 32 * 32 * 4);
    let model = EnergyModel { external_pj_per_byte: 100.0, on_chip_pj_per_byte: 2.0 };
    let energy = frame.energy(&model);
    assert!((energy.external_joules - 4096.0 * 100e-12).abs() < 1e-18);
    assert!((energy.on_chip_joules - 4096.0 * 2e-12).abs() < 1e-18);
    assert!((energy.milliwatts(60.0) - 4096.0 * 102e-12 * 60.0 * 1e3).abs() < 1e-12);
}

#[test]
fn the_overdraw_map_counts_shaded_fragments_per_pixel() {
    for (backend, per_pixel) in [(Backend::Tbr, 3), (Backend::Tbdr, 1), (Backend::Imr, 3)] {
        let mut device = device_with(DeviceConfig { backend, overdraw_map: true, ..DeviceConfig::default() });
        let color = device.create_image(ImageDesc::new(40, 24, Format::Rgba8Unorm)).unwrap();
        let depth = device.create_image(ImageDesc::new(40, 24, Format::D16Unorm)).unwrap();
        let mut pass = color_pass(color, Some(DepthStencilAttachment::clear_discard(depth, 1.0)));
        let mut d = desc("layers");
        d.depth_stencil = DepthStencilState::LESS_WRITE;
        let layers: Vec<Vertex> = (0..3).flat_map(|i| fullscreen(0.8 - 0.2 * i as f32)).collect();
        let vb = device.create_buffer_from(&layers).unwrap();
        pass.draw(Draw::new(&pipeline(FlatColor, d), vb, 0, 18));
        let r = device.submit(&pass).unwrap();
        let map = r.overdraw_map.expect("recorded");
        assert!(map.iter().all(|c| *c == per_pixel), "{backend}");
        assert_eq!(map.iter().map(|c| *c as u64).sum::<u64>(), r.counters.fragments_shaded);
    }
}

#[test]
fn present_costs_scan_out_and_composition() {
    let mut device = device_with(DeviceConfig {
        display: DisplayModel { scan_out: true, composition: true },
        ..DeviceConfig::default()
    });
    let color = device.create_image(ImageDesc::new(100, 10, Format::Rgba8Unorm)).unwrap();
    let ledger = device.present(color).unwrap();
    assert_eq!(ledger.get(Category::Display), 4000);
    assert_eq!(ledger.get(Category::Composition), 8000);
    let msaa = device.create_image(ImageDesc::new(100, 10, Format::Rgba8Unorm).with_samples(4)).unwrap();
    assert!(device.present(msaa).is_err());
}

/// Samples a texture bilinearly at the interpolated colour's red and green (as u, v).
struct Textured(Texture);

impl FragmentShader for Textured {
    fn shade(&self, frag: &mut Fragments<'_>) {
        let c = frag.smooth_n::<4>(0);
        let color = frag.sample(&self.0, &Sampler::BILINEAR_CLAMP, [c[0], c[1]]);
        frag.set_color(0, color);
    }
}

/// The time estimate through the public API: a 32×32 frame with a textured full-screen quad
/// and a blended one over it, on a device of round figures, stage by stage by hand.
#[test]
fn the_time_estimate_by_hand() {
    let texture = Texture::from_rgba8(8, 8, &[200; 8 * 8 * 4], ColorSpace::Linear, MipChain::BaseOnly).unwrap();
    for backend in Backend::ALL {
        let mut device = device_with(DeviceConfig { backend, ..preset("tbr") });
        let color = device.create_image(ImageDesc::new(32, 32, Format::Rgba8Unorm)).unwrap();
        let mut pass = color_pass(color, None);
        let quad = device.create_buffer_from(&fullscreen(0.5)).unwrap();
        pass.draw(Draw::new(&pipeline(Textured(texture.clone()), desc("textured")), quad, 0, 6));
        let mut blended = desc("blended");
        blended.color_targets = vec![ColorTargetState::ALPHA_BLEND];
        pass.draw(Draw::new(&pipeline(Solid([1.0, 0.0, 0.0, 0.5]), blended), quad, 0, 6));
        let frame = FrameCost::new(vec![device.submit(&pass).unwrap()]);
        let c = frame.counters();
        // 6 + 6 vertices; 1024 fragments per quad; the 16 quads on the diagonal are shaded by
        // both triangles, 4 covered lanes and 4 helper lanes: 64 helpers per draw. Bilinear: 4
        // texels per lane of the textured quad, helpers included: (1024 + 64) × 4. The blended
        // quad's 1024 samples through its one blending target.
        assert_eq!(
            (c.vertices_shaded, c.fragments_shaded, c.helper_invocations, c.texels_read, c.samples_blended),
            (12, 2048, 128, 4352, 1024),
            "{backend}"
        );
        let model = TimeModel {
            clock_mhz: 1.0,
            cores: 2,
            vertices_per_clock: 1.0,
            pixels_per_clock: 4.0,
            texels_per_clock: 2.0,
            blended_samples_per_clock: 1.0,
            bandwidth_gb_per_s: 0.001,
            frames_in_flight: 3,
        };
        let t = frame.time(&model);
        // 12 vertices / (1e6 Hz × 2 cores × 1) = 6 µs.
        assert!((t.geometry_seconds - 6e-6).abs() < 1e-15, "{backend}");
        // Shading 2176 / 8e6 = 272 µs; texturing 4352 / 4 / 4e6 = 272 µs; blending 1024 / 2e6
        // = 512 µs: blending bounds the fragment stage.
        assert!((t.fragment_seconds - 512e-6).abs() < 1e-15, "{backend}");
        // The bytes of the frame / 1e6 B/s.
        let bytes = frame.ledger().total();
        assert!((t.memory_seconds - bytes as f64 / 1e6).abs() < 1e-15, "{backend}");
        let (seconds, bound) =
            if t.memory_seconds > 512e-6 { (t.memory_seconds, Stage::Memory) } else { (512e-6, Stage::Fragment) };
        assert_eq!((t.seconds, t.bound), (seconds, bound), "{backend}");
        assert!((model.bandwidth_share(bytes, 60.0) - bytes as f64 * 60.0 / 1e6).abs() < 1e-12);
    }
}

/// Memory moves a packed D24S8 sample as one 32-bit word (issue 16): an access of depth alone
/// or stencil alone costs 4 bytes; depth and stencil together share the word, 3 + 1. Immediate
/// mode without a cache, one full-screen quad on 64×32 pixels, then with a framebuffer cache
/// of 64-byte lines (16 words a line).
#[test]
fn packed_depth_stencil_moves_whole_words() {
    let (w, h) = (64u32, 32u32);
    let pixels = (w * h) as u64;
    let replace = StencilFaceState { pass_op: StencilOp::Replace, reference: 5, ..StencilFaceState::KEEP };
    let run = |state: DepthStencilState, cache: CacheConfig| {
        let mut config = preset("imr-no-cache");
        config.framebuffer_cache = cache;
        let mut device = device_with(config);
        let color = device.create_image(ImageDesc::new(w, h, Format::Rgba8Unorm)).unwrap();
        let ds = device.create_image(ImageDesc::new(w, h, Format::D24UnormS8Uint)).unwrap();
        let mut pass = color_pass(color, Some(DepthStencilAttachment::clear_discard(ds, 1.0)));
        let mut d = desc("quad");
        d.depth_stencil = state;
        let vb = device.create_buffer_from(&fullscreen(0.5)).unwrap();
        pass.draw(Draw::new(&pipeline(FlatColor, d), vb, 0, 6));
        let ledger = device.submit(&pass).unwrap().ledger;
        [Category::ImrDepthRead, Category::ImrDepthWrite, Category::ImrStencilRead, Category::ImrStencilWrite]
            .map(|c| ledger.get(c) / pixels)
    };
    let none = CacheConfig::NONE;
    // Depth alone: the whole word read and written.
    assert_eq!(run(DepthStencilState::LESS_WRITE, none), [4, 4, 0, 0]);
    // Stencil alone (no depth test): the whole word.
    assert_eq!(run(DepthStencilState::DISABLED.with_stencil(replace), none), [0, 0, 4, 4]);
    // Both tested and both written: one word, 3 + 1 each way.
    assert_eq!(run(DepthStencilState::LESS_WRITE.with_stencil(replace), none), [3, 3, 1, 1]);
    // Both tested, only depth written (the stencil op keeps): read 3 + 1, write the word.
    assert_eq!(run(DepthStencilState::LESS_WRITE.with_stencil(StencilFaceState::KEEP), none), [3, 4, 1, 0]);
    // Behind a 64 KiB cache of 64-byte lines the 8 KiB of depth-stencil words is filled once
    // and written back once, whichever aspects are accessed: 2048 × 4 bytes = 128 lines each way.
    let cache = CacheConfig { size_bytes: 64 << 10, line_bytes: 64, ways: 8 };
    for state in [DepthStencilState::LESS_WRITE, DepthStencilState::LESS_WRITE.with_stencil(replace)] {
        let [depth_read, depth_write, stencil_read, stencil_write] = run(state, cache);
        assert_eq!((depth_read + stencil_read, depth_write + stencil_write), (4, 4), "{state:?}");
    }
}

/// Seed 004 §24.5: vertex fetch reads whole lines, so layouts cost what they touch. Six
/// vertices of a quad, position and colour (16 + 16 bytes): interleaved, 192 bytes in 3 lines;
/// in two separate buffers, each stream's 96 bytes take 2 lines, 4 in all — the separate
/// layout wastes the half line at the end of each stream, 64 bytes. A position-only pipeline
/// over the interleaved buffer (a hot/cold mix: the colour is cold) reads every line anyway,
/// where over a separate position buffer it reads only 2.
#[test]
fn vertex_fetch_reads_the_lines_each_layout_touches() {
    let c = [1.0, 0.5, 0.25, 1.0];
    let quad = fullscreen(0.5);
    let positions: Vec<[f32; 4]> = quad.iter().map(|v| [v[0], v[1], v[2], v[3]]).collect();
    let colors: Vec<[f32; 4]> = quad.iter().map(|_| c).collect();
    let fetch = |input: VertexInputState, separate: bool| {
        let mut device = device_with(preset("imr-no-cache"));
        let color = device.create_image(ImageDesc::new(16, 16, Format::Rgba8Unorm)).unwrap();
        let mut pass = color_pass(color, None);
        let mut d = desc("layout");
        d.vertex_input = input;
        let buffers = if separate {
            vec![device.create_buffer_from(&positions).unwrap(), device.create_buffer_from(&colors).unwrap()]
        } else {
            let interleaved: Vec<Vertex> =
                quad.iter().map(|v| [v[0], v[1], v[2], v[3], c[0], c[1], c[2], c[3]]).collect();
            vec![device.create_buffer_from(&interleaved).unwrap()]
        };
        let mut draw = Draw::new(&pipeline(FlatColor, d), buffers[0], 0, 6);
        draw.vertex_buffers = buffers.iter().map(|b| VertexBufferBinding { buffer: *b, offset: 0 }).collect();
        pass.draw(draw);
        let r = device.submit(&pass).unwrap();
        (r.ledger.get(Category::VertexFetch), device.read_rgba8(color).unwrap())
    };
    use VertexFormat::Float32x4;
    let (interleaved, picture) = fetch(VertexInputState::interleaved(&[Float32x4, Float32x4]), false);
    let (separate, same_picture) = fetch(VertexInputState::separate(&[Float32x4, Float32x4]), true);
    assert_eq!(picture, same_picture);
    assert_eq!((interleaved, separate), (3 * 64, 4 * 64));
    assert_eq!(separate - interleaved, 64, "the two half lines the separate streams waste");
    // Position only: over the interleaved buffer (stride 32) still 3 lines; over its own
    // buffer (stride 16) 2 lines.
    let mut position_only = VertexInputState::interleaved(&[Float32x4]);
    position_only.bindings[0].stride = 32;
    assert_eq!(fetch(position_only, false).0, 3 * 64);
    assert_eq!(fetch(VertexInputState::interleaved(&[Float32x4]), true).0, 2 * 64);
}

/// Seed 002: blending combined with depth writes disables early-Z. A blended quad behind an
/// opaque one (32×32 pixels) is rejected before shading when it does not write depth, and
/// shaded then rejected when it does; the picture is the same either way.
#[test]
fn blending_with_depth_writes_disables_early_z() {
    let pixels = 32 * 32;
    for backend in Backend::ALL {
        let run = |depth_write: bool| {
            let mut device = device_with(DeviceConfig { backend, ..DeviceConfig::default() });
            let color = device.create_image(ImageDesc::new(32, 32, Format::Rgba8Unorm)).unwrap();
            let depth = device.create_image(ImageDesc::new(32, 32, Format::D24UnormS8Uint)).unwrap();
            let mut pass = color_pass(color, Some(DepthStencilAttachment::clear_discard(depth, 1.0)));
            let mut opaque = desc("opaque");
            opaque.depth_stencil = DepthStencilState::LESS_WRITE;
            let front = device.create_buffer_from(&fullscreen(0.5)).unwrap();
            pass.draw(Draw::new(&pipeline(Solid([0.0, 1.0, 0.0, 1.0]), opaque), front, 0, 6));
            let mut blended = desc("blended");
            blended.color_targets = vec![ColorTargetState::ALPHA_BLEND];
            blended.depth_stencil =
                if depth_write { DepthStencilState::LESS_WRITE } else { DepthStencilState::LESS_NO_WRITE };
            let behind = device.create_buffer_from(&fullscreen(0.8)).unwrap();
            pass.draw(Draw::new(&pipeline(Solid([1.0, 0.0, 0.0, 0.5]), blended), behind, 0, 6));
            let c = device.submit(&pass).unwrap().counters;
            (c.fragments_shaded, c.fragments_early_z_killed, c.fragments_late_killed, device.read_rgba8(color).unwrap())
        };
        let (shaded, early, late, picture) = run(false);
        assert_eq!((early, late), (pixels, 0), "{backend}: early-Z rejects the hidden blended quad");
        let (shaded_with_write, early_with_write, late_with_write, same_picture) = run(true);
        assert_eq!((early_with_write, late_with_write), (0, pixels), "{backend}: tested after shading");
        assert_eq!(shaded_with_write, shaded + pixels, "{backend}");
        assert_eq!(picture, same_picture, "{backend}");
    }
}
