//! Textures uploaded in formats tiler samples but does not render to (`encoded_tex_image`):
//! ETC2 and ASTC blocks, 4444 texels, and RGB565 textures; each sampled decoded and counted by
//! what its format stores.

use tiler::Category;
use tiler_gl::*;

use crate::common::*;

const SAMPLE_VS: &str = "attribute vec2 p;
varying vec2 uv;
void main() { uv = p * 0.5 + 0.5; gl_Position = vec4(p, 0.0, 1.0); }";

const SAMPLE_FS: &str = "precision mediump float;
uniform sampler2D tex;
varying vec2 uv;
void main() { gl_FragColor = texture2D(tex, uv); }";

/// A 16×16 window (one tile, one task) with a full-screen triangle sampling texture 1.
fn window() -> Context {
    let mut gl = context(16, 16);
    let triangle: [[f32; 2]; 3] = [[-1.0, -1.0], [3.0, -1.0], [-1.0, 3.0]];
    c(&mut gl, Call::CreateBuffer { id: 1, data: Bytes::from_slice(&triangle) });
    let pointer = Call::VertexAttribPointer {
        index: 0,
        buffer: 1,
        size: 2,
        component: ComponentType::Float,
        normalized: false,
        stride: 0,
        offset: 0,
    };
    c(&mut gl, pointer);
    c(&mut gl, Call::EnableVertexAttrib { index: 0 });
    let program = ProgramSource::Glsl(GlslSource { vertex: SAMPLE_VS.into(), fragment: SAMPLE_FS.into() });
    c(&mut gl, Call::CreateProgram { id: 1, program });
    c(&mut gl, Call::BindAttribLocation { program: 1, index: 0, name: "p".into() });
    c(&mut gl, Call::UseProgram { id: 1 });
    let texture =
        Call::CreateTexture { id: 1, width: 1, height: 1, format: TextureFormat::Rgba8, data: None, transient: false };
    c(&mut gl, texture);
    c(&mut gl, Call::BindTexture { unit: 0, texture: 1 });
    gl
}

/// Draws the window's triangle and ends: the picture and the pass's `texture_fetch`.
fn draw_texture(gl: &mut Context, filter: Filter) -> (Vec<u8>, u64) {
    let parameters = Call::TexParameters { id: 1, filter, wrap: Wrap::Repeat, mag_filter: None, wrap_t: None };
    c(gl, parameters);
    draw(gl, 3);
    swap(gl);
    let report = gl.end().unwrap();
    let fetched = passes(&report).iter().map(|p| p.cost.ledger.get(Category::TextureFetch)).sum();
    (gl.surface_rgba8(), fetched)
}

/// An ETC2 RGBA8 block of one colour: EAC alpha with multiplier 0, then an ETC1
/// individual-mode block of the 4-bit colour `rgb4`, table 0, every index 0 (+2): the colour
/// `c · 17 + 2`.
fn etc2_rgba8_constant(rgb4: [u8; 3], alpha: u8) -> [u8; 16] {
    let mut block = [0u8; 16];
    block[0] = alpha;
    let [r, g, b] = rgb4.map(|c| c << 4 | c);
    block[8..12].copy_from_slice(&[r, g, b, 0]);
    block
}

/// An ASTC void-extent block (a constant LDR colour, UNORM16 channels of high bytes `rgba`).
fn astc_constant(rgba: [u8; 4]) -> [u8; 16] {
    let mut block = [0xff; 16];
    block[..2].copy_from_slice(&[0xfc, 0xfd]);
    for (c, v) in rgba.iter().enumerate() {
        block[8 + 2 * c..10 + 2 * c].copy_from_slice(&[0, *v]);
    }
    block
}

/// A 16×16 ETC2 RGBA8 texture drawn texel for pixel: the blocks' colours in place (GL's first
/// block row at the bottom), and 16 blocks of 16 bytes fetched, 4 lines of 64 bytes — a
/// quarter of the same picture uploaded as RGBA8.
#[test]
fn etc2_is_drawn_from_its_blocks_and_fetches_them() {
    let colour = |bx: u8, by: u8| [bx * 3, by * 3, 7];
    let blocks: Vec<u8> = (0..16u8).flat_map(|i| etc2_rgba8_constant(colour(i % 4, i / 4), 255)).collect();
    let mut gl = window();
    let upload = Call::EncodedTexImage {
        id: 1,
        level: 0,
        width: 16,
        height: 16,
        format: EncodedFormat::Etc2Rgba8,
        srgb: false,
        data: Bytes::from(blocks),
    };
    c(&mut gl, upload);
    let (etc2, fetched) = draw_texture(&mut gl, Filter::Nearest);
    assert_eq!(fetched, 256);
    // Tiler's row 0 is GL's top row: block row 3.
    assert_eq!(pixel(&etc2, 16, 5, 0), [3 * 17 + 2, 9 * 17 + 2, 7 * 17 + 2, 255]);
    assert_eq!(pixel(&etc2, 16, 15, 15), [9 * 17 + 2, 2, 7 * 17 + 2, 255]);

    // The same picture as RGBA8 (GL rows bottom to top).
    let rgba: Vec<u8> = (0..16 * 16)
        .flat_map(|i: u32| {
            let [r, g, b] = colour((i % 16 / 4) as u8, (i / 16 / 4) as u8).map(|c| c * 17 + 2);
            [r, g, b, 255]
        })
        .collect();
    let mut gl = window();
    let upload =
        Call::TexImage { id: 1, width: 16, height: 16, format: TextureFormat::Rgba8, data: Some(Bytes::from(rgba)) };
    c(&mut gl, upload);
    let (plain, fetched) = draw_texture(&mut gl, Filter::Nearest);
    assert!(plain == etc2, "the same picture");
    assert_eq!(fetched, 1024);
}

/// An ASTC 4×4 chain given level by level, sampled with mip maps: a 64×64 texture on 16×16
/// pixels reads level 2 (λ = 2), 16×16 texels in 16 blocks: 256 bytes fetched.
#[test]
fn astc_levels_are_sampled_and_counted_by_their_blocks() {
    let mut gl = window();
    for level in 0..7u32 {
        let size = 64 >> level;
        let blocks = (size as usize).div_ceil(4).pow(2);
        let data: Vec<u8> = (0..blocks).flat_map(|_| astc_constant([10 * level as u8, 50, 60, 255])).collect();
        let upload = Call::EncodedTexImage {
            id: 1,
            level,
            width: size,
            height: size,
            format: EncodedFormat::Astc4x4,
            srgb: false,
            data: Bytes::from(data),
        };
        c(&mut gl, upload);
    }
    let (picture, fetched) = draw_texture(&mut gl, Filter::NearestMipmapNearest);
    assert!(picture.chunks(4).all(|p| p == [20, 50, 60, 255]), "{:?}", &picture[..4]);
    assert_eq!(fetched, 256);
}

/// 4444 texels are 2 bytes each (16×16: 512 bytes, 8 lines), RGB565 ones too.
#[test]
fn packed_texels_are_counted_at_two_bytes() {
    let mut gl = window();
    let data: Vec<u8> = (0..16 * 16).flat_map(|_| 0xf0ffu16.to_le_bytes()).collect();
    let upload = Call::EncodedTexImage {
        id: 1,
        level: 0,
        width: 16,
        height: 16,
        format: EncodedFormat::Rgba4444,
        srgb: false,
        data: Bytes::from(data.clone()),
    };
    c(&mut gl, upload);
    let (picture, fetched) = draw_texture(&mut gl, Filter::Nearest);
    assert!(picture.chunks(4).all(|p| p == [255, 0, 255, 255]), "{:?}", &picture[..4]);
    assert_eq!(fetched, 512);

    let mut gl = window();
    // 565: red 31, green 0, blue 16.
    let texel = (31u16 << 11) | 16;
    let data: Vec<u8> = (0..16 * 16).flat_map(|_| texel.to_le_bytes()).collect();
    let upload =
        Call::TexImage { id: 1, width: 16, height: 16, format: TextureFormat::Rgb565, data: Some(Bytes::from(data)) };
    c(&mut gl, upload);
    let (picture, fetched) = draw_texture(&mut gl, Filter::Nearest);
    assert!(picture.chunks(4).all(|p| p == [255, 0, 132, 255]), "{:?}", &picture[..4]);
    assert_eq!(fetched, 512);
}

/// Bad encoded uploads are errors naming the call, the level and what is wrong.
#[test]
fn bad_encoded_uploads_are_named() {
    let mut gl = window();
    let upload = |level: u32, width: u32, format: EncodedFormat, bytes: usize| Call::EncodedTexImage {
        id: 1,
        level,
        width,
        height: width,
        format,
        srgb: false,
        data: Bytes::from(vec![0u8; bytes]),
    };
    let e = gl.call(upload(0, 16, EncodedFormat::Etc2Rgba8, 100)).unwrap_err();
    assert_eq!(e.name, "encoded_tex_image");
    assert!(e.message.contains("100 bytes of ETC2 RGBA8 data for 16×16") && e.message.contains("256"), "{e}");
    c(&mut gl, upload(0, 16, EncodedFormat::Etc2Rgba8, 256));
    let e = gl.call(upload(1, 8, EncodedFormat::Etc2Rgb8, 32)).unwrap_err();
    assert!(e.message.contains("level 1 of texture 1 is etc2_rgb8, but its level 0 is etc2_rgba8"), "{e}");
    let e = gl.call(Call::GenerateMipmap { id: 1 }).unwrap_err();
    assert!(e.message.contains("compressed"), "{e}");
    let sub = |x: u32, width: u32| Call::EncodedTexSubImage {
        id: 1,
        x,
        y: 0,
        width,
        height: 4,
        format: EncodedFormat::Etc2Rgba8,
        data: Bytes::from(vec![0u8; width.div_ceil(4) as usize * 16]),
    };
    let e = gl.call(sub(2, 4)).unwrap_err();
    assert!(e.message.contains("not made of whole 4×4 blocks"), "{e}");
    c(&mut gl, sub(4, 12));
    let plain = Call::TexSubImage { id: 1, x: 0, y: 0, width: 1, height: 1, data: Bytes::from(vec![0u8; 4]) };
    assert!(gl.call(plain).unwrap_err().message.contains("encoded_tex_sub_image"));
    // A malformed ASTC block (one the decoder panics on) is refused, not a crash.
    let bad = [108u8, 130, 165, 98, 203, 128, 141, 16, 214, 50, 190, 137, 200, 81, 62, 191];
    let upload = Call::EncodedTexImage {
        id: 1,
        level: 0,
        width: 4,
        height: 4,
        format: EncodedFormat::Astc4x4,
        srgb: false,
        data: Bytes::from(bad.to_vec()),
    };
    let e = gl.call(upload).unwrap_err();
    assert!(e.message.contains("ASTC 4×4 block 0 (block column 0, row 0) is illegal"), "{e}");
}
