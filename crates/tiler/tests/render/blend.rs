//! Blending: every factor and equation against hand-written expectations, clamping for
//! normalised targets, write masks, and blending in linear space for sRGB targets.

use super::common::*;
use tiler::*;

const SRC: [f32; 4] = [0.5, 0.25, 0.75, 0.4];
const DST: [f32; 4] = [0.2, 0.6, 0.1, 0.8];
const K: [f32; 4] = [0.3, 0.3, 0.3, 0.5];

/// Draws a full-screen quad of `src` over `dst` with `target` state; returns the first pixel.
fn blend_one(format: Format, target: ColorTargetState, src: [f32; 4], dst: [f32; 4], backend: Backend) -> Vec<u8> {
    let mut device = device(backend, 8, 1);
    let color = device.create_image(ImageDesc::new(8, 8, format)).unwrap();
    let verts = [v(-1.0, -1.0, 0.5, src), v(3.0, -1.0, 0.5, src), v(-1.0, 3.0, 0.5, src)];
    let buffer = device.create_buffer_from(&verts).unwrap();
    let mut d = desc("blend");
    d.color_targets = vec![target];
    d.blend_constant = K;
    let mut pass = RenderPass::new(RenderPassDesc {
        color: vec![ColorAttachment::clear_store(color, dst)],
        depth_stencil: None,
        render_area: None,
    });
    pass.draw(Draw::new(&pipeline(Solid(src), d), buffer, 0, 3));
    device.submit(&pass).unwrap();
    let data = device.image_data(color).unwrap();
    data[..format.bytes_per_sample()].to_vec()
}

fn floats(bytes: &[u8]) -> [f32; 4] {
    std::array::from_fn(|i| f32::from_le_bytes(bytes[4 * i..4 * i + 4].try_into().unwrap()))
}

fn state(src: BlendFactor, dst: BlendFactor, op: BlendOp) -> ColorTargetState {
    let c = BlendComponent { src, dst, op };
    ColorTargetState { blend: Some(BlendState { color: c, alpha: c }), write_mask: ColorWrites::ALL }
}

#[test]
fn every_source_factor() {
    use BlendFactor::*;
    let s = SRC;
    let (d, k) = (DST, K);
    // Expected factor per channel (alpha uses the alpha rule of the factor).
    let table: [(BlendFactor, [f32; 4]); 15] = [
        (Zero, [0.0; 4]),
        (One, [1.0; 4]),
        (SrcColor, s),
        (OneMinusSrcColor, s.map(|c| 1.0 - c)),
        (DstColor, d),
        (OneMinusDstColor, d.map(|c| 1.0 - c)),
        (SrcAlpha, [s[3]; 4]),
        (OneMinusSrcAlpha, [1.0 - s[3]; 4]),
        (DstAlpha, [d[3]; 4]),
        (OneMinusDstAlpha, [1.0 - d[3]; 4]),
        (ConstantColor, k),
        (OneMinusConstantColor, k.map(|c| 1.0 - c)),
        (ConstantAlpha, [k[3]; 4]),
        (OneMinusConstantAlpha, [1.0 - k[3]; 4]),
        (SrcAlphaSaturate, {
            let f = s[3].min(1.0 - d[3]);
            [f, f, f, 1.0]
        }),
    ];
    for backend in Backend::ALL {
        for (factor, f) in table {
            let got = floats(&blend_one(Format::Rgba32Float, state(factor, Zero, BlendOp::Add), SRC, DST, backend));
            let expected: [f32; 4] = std::array::from_fn(|c| s[c] * f[c] + d[c] * 0.0);
            assert_eq!(got, expected, "{backend} source factor {factor:?}");
            let got = floats(&blend_one(Format::Rgba32Float, state(Zero, factor, BlendOp::Add), SRC, DST, backend));
            let expected: [f32; 4] = std::array::from_fn(|c| s[c] * 0.0 + d[c] * f[c]);
            assert_eq!(got, expected, "{backend} destination factor {factor:?}");
        }
    }
}

#[test]
fn every_equation() {
    use BlendFactor::*;
    for backend in Backend::ALL {
        let f = |op| floats(&blend_one(Format::Rgba32Float, state(SrcAlpha, One, op), SRC, DST, backend));
        let a = SRC[3];
        assert_eq!(f(BlendOp::Add), std::array::from_fn(|c| SRC[c] * a + DST[c]));
        assert_eq!(f(BlendOp::Subtract), std::array::from_fn(|c| SRC[c] * a - DST[c]));
        assert_eq!(f(BlendOp::ReverseSubtract), std::array::from_fn(|c| DST[c] - SRC[c] * a));
        assert_eq!(f(BlendOp::Min), std::array::from_fn(|c| SRC[c].min(DST[c])));
        assert_eq!(f(BlendOp::Max), std::array::from_fn(|c| SRC[c].max(DST[c])));
    }
}

#[test]
fn normalised_targets_clamp_and_round() {
    use BlendFactor::*;
    for backend in Backend::ALL {
        // Source above one is clamped before blending: 1 + 0.5 → 255; below zero to zero:
        // 0 + 128/255 → 128; 0.25 + 128/255 = 0.752 → 192.
        let got = blend_one(
            Format::Rgba8Unorm,
            state(One, One, BlendOp::Add),
            [2.0, -1.0, 0.25, 1.0],
            [0.5, 0.5, 0.5, 0.5],
            backend,
        );
        assert_eq!(got, vec![255, 128, 192, 255]);
        // Alpha blending in RGBA8: 0.4·red + 0.6·(0.2, 0.6, 0.1).
        let got = blend_one(Format::Rgba8Unorm, ColorTargetState::ALPHA_BLEND, [1.0, 0.0, 0.0, 0.4], DST, backend);
        let dst8 = DST.map(|c| (c * 255.0 + 0.5).floor() / 255.0);
        let expected: Vec<u8> = (0..3)
            .map(|c| (([1.0, 0.0, 0.0][c] * 0.4 + dst8[c] * (1.0 - 0.4f32)) * 255.0 + 0.5) as u8)
            .chain([((0.4 + dst8[3] * 0.6f32) * 255.0 + 0.5) as u8])
            .collect();
        assert_eq!(got, expected);
    }
}

#[test]
fn write_masks_keep_unwritten_channels() {
    for backend in Backend::ALL {
        let target =
            ColorTargetState { blend: None, write_mask: ColorWrites(ColorWrites::GREEN.0 | ColorWrites::ALPHA.0) };
        let got = blend_one(Format::Rgba8Unorm, target, [1.0, 1.0, 1.0, 0.0], [0.2, 0.6, 0.1, 0.8], backend);
        assert_eq!(got, vec![51, 255, 26, 0]);
        let got = blend_one(
            Format::Rgb565Unorm,
            ColorTargetState { blend: None, write_mask: ColorWrites::RED },
            [1.0; 4],
            [0.0; 4],
            backend,
        );
        assert_eq!(u16::from_le_bytes([got[0], got[1]]), 0xf800);
        let target = ColorTargetState { blend: None, write_mask: ColorWrites::NONE };
        assert_eq!(blend_one(Format::Rgba8Unorm, target, [1.0; 4], [0.0; 4], backend), vec![0, 0, 0, 0]);
    }
}

#[test]
fn srgb_targets_blend_in_linear_space() {
    for backend in Backend::ALL {
        // Half of linear white over black is linear 0.5, stored as sRGB 188.
        let got = blend_one(
            Format::Rgba8UnormSrgb,
            ColorTargetState::ALPHA_BLEND,
            [1.0, 1.0, 1.0, 0.5],
            [0.0, 0.0, 0.0, 1.0],
            backend,
        );
        assert_eq!(&got[..3], &[188, 188, 188]);
    }
}
