//! Texture formats through the public API: `texture fetch` counts the lines the stored format
//! occupies (packed texels, or ETC2/ASTC blocks), mip maps cut it for a minified texture, and
//! every backend, tile size and thread count draws the same picture from every format.

use super::common::*;
use tiler::*;

/// Samples a texture at the interpolated colour's red and green (as u, v).
struct Textured(Texture, Sampler);

impl FragmentShader for Textured {
    fn shade(&self, frag: &mut Fragments<'_>) {
        let c = frag.smooth_n::<4>(0);
        let color = frag.sample(&self.0, &self.1, [c[0], c[1]]);
        frag.set_color(0, color);
    }
}

/// A full-screen quad whose colour's red and green are u, v from 0 to 1 across the screen.
fn uv_quad() -> Vec<Vertex> {
    let at = |x: f32, y: f32| v(x, y, 0.5, [(x + 1.0) / 2.0, (y + 1.0) / 2.0, 0.0, 1.0]);
    vec![at(-1.0, -1.0), at(-1.0, 1.0), at(1.0, 1.0), at(-1.0, -1.0), at(1.0, 1.0), at(1.0, -1.0)]
}

/// Draws `texture` over a `size × size` framebuffer: its RGBA8 pixels and the pass's
/// `texture fetch`.
fn draw(texture: &Texture, sampler: Sampler, size: u32, backend: Backend, tile: u32, threads: usize) -> (Vec<u8>, u64) {
    let mut device = device(backend, tile, threads);
    let color = device.create_image(ImageDesc::new(size, size, Format::Rgba8Unorm)).unwrap();
    let mut pass = color_pass(color, None);
    let quad = device.create_buffer_from(&uv_quad()).unwrap();
    pass.draw(Draw::new(&pipeline(Textured(texture.clone(), sampler), desc("textured")), quad, 0, 6));
    let report = device.submit(&pass).unwrap();
    (device.image_data(color).unwrap().to_vec(), report.ledger.get(Category::TextureFetch))
}

/// One-task configurations: a framebuffer of one tile on a tiler, so one cold cache reads
/// every line once.
const ONE_TASK: [Backend; 2] = [Backend::Tbr, Backend::Tbdr];

/// An ASTC void-extent block (a constant colour, LDR): UNORM16 channels, high bytes `rgba`.
fn astc_constant(rgba: [u8; 4]) -> [u8; 16] {
    let mut block = [0xff; 16];
    block[..2].copy_from_slice(&[0xfc, 0xfd]);
    for (c, v) in rgba.iter().enumerate() {
        block[8 + 2 * c..10 + 2 * c].copy_from_slice(&[0, *v]);
    }
    block
}

/// An ETC2 RGBA8 block of one colour: EAC alpha with multiplier 0 (every texel the base
/// alpha `alpha`), then an ETC1 individual-mode block whose halves share the 4-bit colour
/// `rgb4`, table 0, every index 0 (modifier +2): the colour `c · 17 + 2`.
fn etc2_rgba8_constant(rgb4: [u8; 3], alpha: u8) -> [u8; 16] {
    let mut block = [0u8; 16];
    block[0] = alpha;
    let [r, g, b] = rgb4.map(|c| c << 4 | c);
    block[8..12].copy_from_slice(&[r, g, b, 0]);
    block
}

/// `width × height` texels of `format` from a deterministic generator: packed texels of any
/// bits (floats included: NaN and out-of-range values decode too), ETC2 blocks of any bits
/// (every ETC2 bit pattern is a block), ASTC constant blocks of varied colours.
fn encoded(format: TexelFormat, width: u32, height: u32, seed: u32) -> Vec<u8> {
    let mut rng = Rng(seed);
    let bytes = format.data_bytes(width, height) as usize;
    match format {
        TexelFormat::Astc { .. } => {
            (0..bytes / 16).flat_map(|_| astc_constant(std::array::from_fn(|_| rng.next_u32() as u8))).collect()
        }
        _ => (0..bytes).map(|_| rng.next_u32() as u8).collect(),
    }
}

const FORMATS: [TexelFormat; 16] = [
    TexelFormat::Rgba8,
    TexelFormat::Rgb10A2,
    TexelFormat::Rg11B10Float,
    TexelFormat::Rgb9E5,
    TexelFormat::Rgb565,
    TexelFormat::Rgba4444,
    TexelFormat::Rgba5551,
    TexelFormat::Rgba16Float,
    TexelFormat::Rgba32Float,
    TexelFormat::Etc2Rgb8,
    TexelFormat::Etc2Rgba8,
    TexelFormat::EacR11,
    TexelFormat::Astc { block_width: 4, block_height: 4 },
    TexelFormat::Astc { block_width: 5, block_height: 5 },
    TexelFormat::Astc { block_width: 6, block_height: 6 },
    TexelFormat::Astc { block_width: 8, block_height: 8 },
];

/// A 32×32 texture drawn texel for pixel on a 32×32 framebuffer of one tile, nearest: one
/// cold cache reads every stored line of the texture exactly once (16 KiB, 4 ways: even
/// RGBA32F's 256 lines fill each of the 64 sets with 4 and nothing falls out), so `texture
/// fetch` is the stored bytes rounded up to 64-byte lines:
///
/// | format | stored | lines | bytes |
/// |---|---|---|---|
/// | RGBA8, RGB10_A2, R11F_G11F_B10F, RGB9_E5 | 32·32·4 = 4096 | 64 | 4096 |
/// | RGB565, 4444, 5551 | 2048 | 32 | 2048 |
/// | RGBA16F | 8192 | 128 | 8192 |
/// | RGBA32F | 16384 | 256 | 16384 |
/// | ETC2 RGB8, EAC R11 | 8·8 blocks · 8 = 512 | 8 | 512 |
/// | ETC2 RGBA8, ASTC 4×4 | 8·8 · 16 = 1024 | 16 | 1024 |
/// | ASTC 5×5 | 7·7 · 16 = 784 | 13 (12.25) | 832 |
/// | ASTC 6×6 | 6·6 · 16 = 576 | 9 | 576 |
/// | ASTC 8×8 | 4·4 · 16 = 256 | 4 | 256 |
#[test]
fn texture_fetch_is_the_stored_lines_of_each_format() {
    let expected = |format: TexelFormat| match format {
        TexelFormat::Rgba8 | TexelFormat::Rgb10A2 | TexelFormat::Rg11B10Float | TexelFormat::Rgb9E5 => 4096,
        TexelFormat::Rgb565 | TexelFormat::Rgba4444 | TexelFormat::Rgba5551 => 2048,
        TexelFormat::Rgba16Float => 8192,
        TexelFormat::Rgba32Float => 16384,
        TexelFormat::Etc2Rgb8 | TexelFormat::EacR11 => 512,
        TexelFormat::Etc2Rgba8 | TexelFormat::Astc { block_width: 4, .. } => 1024,
        TexelFormat::Astc { block_width: 5, .. } => 13 * 64,
        TexelFormat::Astc { block_width: 6, .. } => 576,
        TexelFormat::Astc { block_width: 8, .. } => 256,
        _ => unreachable!(),
    };
    for format in FORMATS {
        let data = encoded(format, 32, 32, 7);
        let texture = Texture::from_encoded(format, 32, 32, &data, ColorSpace::Linear, MipChain::BaseOnly).unwrap();
        assert_eq!(texture.format(), format);
        for backend in ONE_TASK {
            let (_, fetched) = draw(&texture, Sampler::NEAREST_REPEAT, 32, backend, 32, 1);
            assert_eq!(fetched, expected(format), "{} on {backend}", format.name());
        }
    }
}

/// Every format draws the same picture on every backend, tile size and thread count, and
/// the packed formats read as the RGBA8 texture of their decoded texels would, pixel for pixel.
#[test]
fn every_format_keeps_the_invariant() {
    for format in FORMATS {
        let data = encoded(format, 24, 40, 11);
        let texture = Texture::from_encoded(format, 24, 40, &data, ColorSpace::Linear, MipChain::Box).unwrap();
        let reference = draw(&texture, Sampler::TRILINEAR_REPEAT, 48, Backend::Tbr, 16, 1).0;
        for backend in Backend::ALL {
            for (tile, threads) in [(16, 1), (32, 3), (8, 2)] {
                let (image, _) = draw(&texture, Sampler::TRILINEAR_REPEAT, 48, backend, tile, threads);
                assert!(image == reference, "{} on {backend}, tile {tile}, {threads} threads", format.name());
            }
        }
        // The decoded texels as an RGBA8 texture: the same picture, other bytes fetched.
        let rgba: Vec<u8> = texture.level_texels(0).concat();
        let as_rgba8 = Texture::from_rgba8(24, 40, &rgba, ColorSpace::Linear, MipChain::Box).unwrap();
        assert!(
            draw(&as_rgba8, Sampler::TRILINEAR_REPEAT, 48, Backend::Tbr, 16, 1).0 == reference,
            "{}",
            format.name()
        );
    }
}

/// ETC2 RGBA8 costs a quarter of RGBA8 for the same picture: a 128×128 texture of flat 4×4
/// blocks (which ETC2 encodes exactly, see `etc2_rgba8_constant`) drawn 1:1 and bilinear on
/// 128×128 pixels. The pictures are equal; 16 bytes a block instead of 64 make the fetch a
/// quarter, within what tile edges add (a tile's bilinear footprint reaches a texel row and
/// column into its neighbours' blocks, a whole line of either format).
#[test]
fn etc2_costs_a_quarter_of_rgba8_for_the_same_picture() {
    let size = 128u32;
    let blocks = size / 4;
    // 4-bit colours up to 14: `c · 17 + 2` stays a byte.
    let colour = |bx: u32, by: u32| ([(bx % 15) as u8, (by % 15) as u8, ((bx + by) % 15) as u8], (bx * 8) as u8);
    let etc2: Vec<u8> = (0..blocks * blocks)
        .flat_map(|i| {
            let (rgb4, alpha) = colour(i % blocks, i / blocks);
            etc2_rgba8_constant(rgb4, alpha)
        })
        .collect();
    let mut rgba = vec![0u8; (size * size * 4) as usize];
    for y in 0..size {
        for x in 0..size {
            let (rgb4, alpha) = colour(x / 4, y / 4);
            let at = ((y * size + x) * 4) as usize;
            rgba[at..at + 4].copy_from_slice(&[rgb4[0] * 17 + 2, rgb4[1] * 17 + 2, rgb4[2] * 17 + 2, alpha]);
        }
    }
    let compressed =
        Texture::from_encoded(TexelFormat::Etc2Rgba8, size, size, &etc2, ColorSpace::Linear, MipChain::BaseOnly)
            .unwrap();
    let plain = Texture::from_rgba8(size, size, &rgba, ColorSpace::Linear, MipChain::BaseOnly).unwrap();
    assert_eq!((compressed.stored_bytes(), plain.stored_bytes()), (16 * 1024, 64 * 1024));
    for backend in Backend::ALL {
        for tile in [16, 32] {
            let (etc2_image, etc2_fetch) = draw(&compressed, Sampler::BILINEAR_CLAMP, size, backend, tile, 2);
            let (rgba_image, rgba_fetch) = draw(&plain, Sampler::BILINEAR_CLAMP, size, backend, tile, 2);
            assert!(etc2_image == rgba_image, "{backend}, tile {tile}: the same picture");
            let ratio = etc2_fetch as f64 / rgba_fetch as f64;
            assert!((0.22..=0.3).contains(&ratio), "{backend}, tile {tile}: {etc2_fetch} / {rgba_fetch} = {ratio}");
        }
    }
}

/// Mip maps cut `texture fetch` for a minified texture (seed 004 §24.3.5: a minified texture
/// without mip maps reads texels far apart, a line each). A 256×256 RGBA8 texture on 32×32
/// pixels of one tile, nearest filtering: 8× minification, λ = 3.
///
/// - Without mip maps, pixel `i` reads texel `8i + 4` of level 0: every pixel a block of its
///   own, 1024 lines. The 16 quads on the diagonal are shaded by both triangles (2 covered
///   lanes and 2 helpers each time), and the second triangle finds their 4 lines a quad long
///   evicted: 64 lines more, 1088 lines, 69632 bytes.
/// - With mip maps (`NEAREST_MIPMAP_NEAREST`), level 3 (32×32) texel for pixel: its 4096
///   bytes, 64 lines, which stay in the cache — a seventeenth.
///
/// On every backend and tile size the cut holds, by about the same factor.
#[test]
fn mip_maps_cut_texture_fetch_for_a_minified_texture() {
    let mut rng = Rng(3);
    let rgba: Vec<u8> = (0..256 * 256 * 4).map(|_| rng.next_u32() as u8).collect();
    let texture = Texture::from_rgba8(256, 256, &rgba, ColorSpace::Linear, MipChain::Box).unwrap();
    let without = Sampler::NEAREST_REPEAT;
    let with = Sampler { mipmap: MipmapMode::Nearest, ..without };
    for backend in ONE_TASK {
        assert_eq!(draw(&texture, without, 32, backend, 32, 1).1, 1088 * 64, "{backend}");
        assert_eq!(draw(&texture, with, 32, backend, 32, 1).1, 4096, "{backend}");
    }
    for backend in Backend::ALL {
        for tile in [8, 16] {
            let (without, with) =
                (draw(&texture, without, 32, backend, tile, 2).1, draw(&texture, with, 32, backend, tile, 2).1);
            assert!(with * 12 < without, "{backend}, tile {tile}: {with} with mip maps, {without} without");
        }
    }
}

/// The same cut for ETC2: the chain given level by level (as `glCompressedTexImage2D` uploads
/// it), each level of flat blocks. Without mip maps pixel `(i, j)` reads block `(2i + 1, 2j + 1)`
/// of level 0: a 64-byte line holds 4 blocks of 16 bytes, two of them read by neighbouring
/// pixels, so 16 lines a row of pixels, 512 lines; the diagonal's quads, read again by the
/// second triangle, 2 lines each: 544 lines, 34816 bytes (RGBA8 fetched 1088, a line a pixel).
/// With them, level 3 (32×32, 64 blocks, 1024 bytes): 16 lines.
#[test]
fn compressed_mip_chains_are_counted_by_their_blocks() {
    let mut levels = Vec::new();
    let mut size = 256u32;
    loop {
        let blocks = size.div_ceil(4) * size.div_ceil(4);
        levels.push((0..blocks).flat_map(|i| etc2_rgba8_constant([(i % 16) as u8, 3, 9], 255)).collect::<Vec<u8>>());
        if size == 1 {
            break;
        }
        size /= 2;
    }
    let given: Vec<&[u8]> = levels.iter().map(|l| l.as_slice()).collect();
    let texture = Texture::from_encoded_levels(TexelFormat::Etc2Rgba8, 256, 256, &given, ColorSpace::Linear).unwrap();
    assert_eq!(texture.levels().len(), 9);
    let without = Sampler::NEAREST_REPEAT;
    let with = Sampler { mipmap: MipmapMode::Nearest, ..without };
    for backend in ONE_TASK {
        assert_eq!(draw(&texture, without, 32, backend, 32, 1).1, 544 * 64, "{backend}");
        assert_eq!(draw(&texture, with, 32, backend, 32, 1).1, 1024, "{backend}");
    }
    // A level of the wrong size is refused, naming it.
    let mut short = given.clone();
    short[2] = &given[2][..given[2].len() - 16];
    let e = Texture::from_encoded_levels(TexelFormat::Etc2Rgba8, 256, 256, &short, ColorSpace::Linear).unwrap_err();
    assert!(e.to_string().contains("level 2"), "{e}");
}

/// `stored_as` keeps the texels and the picture and changes only what is fetched: the same
/// as a texture made from the format's data.
#[test]
fn stored_as_is_made_from_the_format() {
    let format = TexelFormat::Astc { block_width: 6, block_height: 6 };
    let data = encoded(format, 32, 32, 5);
    let made = Texture::from_encoded(format, 32, 32, &data, ColorSpace::Linear, MipChain::Box).unwrap();
    let rgba: Vec<u8> = made.level_texels(0).concat();
    let decoded = Texture::from_rgba8(32, 32, &rgba, ColorSpace::Linear, MipChain::Box).unwrap();
    let restored = decoded.clone().stored_as(format).unwrap();
    assert_eq!((restored.format(), restored.stored_bytes()), (format, made.stored_bytes()));
    for sampler in [Sampler::NEAREST_REPEAT, Sampler::TRILINEAR_REPEAT] {
        let (a, b, c) = (
            draw(&made, sampler, 32, Backend::Tbr, 32, 1),
            draw(&restored, sampler, 32, Backend::Tbr, 32, 1),
            draw(&decoded, sampler, 32, Backend::Tbr, 32, 1),
        );
        assert!(a == b, "{sampler:?}");
        assert!(c.0 == a.0 && c.1 > a.1, "{sampler:?}: RGBA8 draws the same and fetches more");
    }
}

/// ASTC as an encoder writes it: a 60×60 pattern encoded by astcenc's exhaustive search at
/// every 2D footprint (`tests/data/astc/make.sh`; one to four partitions, dual planes and
/// void-extent blocks among its 1,280 blocks) is legal block by block and decodes as
/// astcenc's own decoder does, within one step of 8 bits: `texture2ddecoder` rounds some
/// interpolated channels the other way (2–10% of texels differ, by one).
#[test]
fn astc_from_an_encoder_decodes_as_the_reference_decoder_does() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/astc");
    for (bw, bh) in ASTC_FOOTPRINTS {
        let file = std::fs::read(dir.join(format!("pattern-{bw}x{bh}.astc"))).unwrap();
        // The .astc header: magic, the footprint (x, y, z), the size (x, y, z, 24 bits each).
        assert_eq!(&file[..4], &[0x13, 0xab, 0xa1, 0x5c]);
        assert_eq!((file[4], file[5], file[6]), (bw, bh, 1));
        let size = |at: usize| u32::from_le_bytes([file[at], file[at + 1], file[at + 2], 0]);
        let (width, height) = (size(7), size(10));
        let format = TexelFormat::Astc { block_width: bw, block_height: bh };
        let texels = format
            .decode(width, height, &file[16..])
            .unwrap_or_else(|e| panic!("{bw}×{bh}: an encoder's block refused: {e}"));
        let reference = image::open(dir.join(format!("decoded-{bw}x{bh}.png"))).unwrap().to_rgba8();
        assert_eq!(reference.dimensions(), (width, height));
        for (i, (texel, expected)) in texels.iter().zip(reference.pixels()).enumerate() {
            let step = (0..4).map(|c| texel[c].abs_diff(expected.0[c])).max().unwrap();
            assert!(step <= 1, "{bw}×{bh} texel {i}: {texel:?}, astcenc {:?}", expected.0);
        }
    }
}
