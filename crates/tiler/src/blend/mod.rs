//! Blending: `op(src · src_factor, dst · dst_factor)` per channel, in f32 (Vulkan "Blend
//! Operations"). For normalised fixed-point attachments the source, destination and constant
//! are clamped to `[0, 1]` first, as Vulkan requires; the result is then packed to the format.

use crate::api::pipeline::{BlendComponent, BlendFactor, BlendOp, BlendState};
use crate::simd::{F32x8, Vec4x8};

/// Blends eight lanes: lane for lane exactly [`blend_pixel`] (the same operations in the
/// same order), so the scalar function is the reference it is tested against.
#[inline(always)]
pub fn blend_lanes(state: &BlendState, src: &Vec4x8, dst: &Vec4x8, constant: [f32; 4]) -> Vec4x8 {
    // A loop, not `std::array::from_fn` and a closure: those were left out of line, compiled for
    // the baseline, in the AVX2 pipeline.
    let mut out = [F32x8::ZERO; 4];
    for (c, out) in out.iter_mut().enumerate() {
        let component = if c < 3 { &state.color } else { &state.alpha };
        let (s, d) = (src[c], dst[c]);
        *out = match component.op {
            BlendOp::Min => s.min(d),
            BlendOp::Max => s.max(d),
            op => {
                let sf = factor_lanes(component.src, c, src, dst, constant);
                let df = factor_lanes(component.dst, c, src, dst, constant);
                match op {
                    BlendOp::Add => s * sf + d * df,
                    BlendOp::Subtract => s * sf - d * df,
                    BlendOp::ReverseSubtract => d * df - s * sf,
                    BlendOp::Min | BlendOp::Max => unreachable!(),
                }
            }
        };
    }
    out
}

#[inline(always)]
fn factor_lanes(f: BlendFactor, c: usize, src: &Vec4x8, dst: &Vec4x8, constant: [f32; 4]) -> F32x8 {
    let one = F32x8::ONE;
    match f {
        BlendFactor::Zero => F32x8::ZERO,
        BlendFactor::One => one,
        BlendFactor::SrcColor => src[c],
        BlendFactor::OneMinusSrcColor => one - src[c],
        BlendFactor::DstColor => dst[c],
        BlendFactor::OneMinusDstColor => one - dst[c],
        BlendFactor::SrcAlpha => src[3],
        BlendFactor::OneMinusSrcAlpha => one - src[3],
        BlendFactor::DstAlpha => dst[3],
        BlendFactor::OneMinusDstAlpha => one - dst[3],
        BlendFactor::ConstantColor => F32x8::splat(constant[c]),
        BlendFactor::OneMinusConstantColor => F32x8::splat(1.0 - constant[c]),
        BlendFactor::ConstantAlpha => F32x8::splat(constant[3]),
        BlendFactor::OneMinusConstantAlpha => F32x8::splat(1.0 - constant[3]),
        BlendFactor::SrcAlphaSaturate => {
            if c == 3 {
                one
            } else {
                src[3].min(one - dst[3])
            }
        }
    }
}

/// Blends one pixel. `dst` is the stored value unpacked (sRGB attachments: linear).
#[allow(dead_code, reason = "the scalar reference `blend_lanes` is tested equal to")]
#[inline]
pub fn blend_pixel(state: &BlendState, src: [f32; 4], dst: [f32; 4], constant: [f32; 4]) -> [f32; 4] {
    let mut out = [0.0; 4];
    for (c, out) in out.iter_mut().enumerate() {
        let component = if c < 3 { &state.color } else { &state.alpha };
        *out = blend_channel(component, c, src, dst, constant);
    }
    out
}

#[allow(dead_code, reason = "part of the scalar reference `blend_pixel`")]
#[inline(always)]
fn blend_channel(component: &BlendComponent, c: usize, src: [f32; 4], dst: [f32; 4], constant: [f32; 4]) -> f32 {
    let (s, d) = (src[c], dst[c]);
    match component.op {
        BlendOp::Min => s.min(d),
        BlendOp::Max => s.max(d),
        op => {
            let sf = factor(component.src, c, src, dst, constant);
            let df = factor(component.dst, c, src, dst, constant);
            match op {
                BlendOp::Add => s * sf + d * df,
                BlendOp::Subtract => s * sf - d * df,
                BlendOp::ReverseSubtract => d * df - s * sf,
                BlendOp::Min | BlendOp::Max => unreachable!(),
            }
        }
    }
}

/// The value of a blend factor for channel `c` (3 = alpha).
#[allow(dead_code, reason = "part of the scalar reference `blend_pixel`")]
#[inline(always)]
fn factor(f: BlendFactor, c: usize, src: [f32; 4], dst: [f32; 4], constant: [f32; 4]) -> f32 {
    match f {
        BlendFactor::Zero => 0.0,
        BlendFactor::One => 1.0,
        BlendFactor::SrcColor => src[c],
        BlendFactor::OneMinusSrcColor => 1.0 - src[c],
        BlendFactor::DstColor => dst[c],
        BlendFactor::OneMinusDstColor => 1.0 - dst[c],
        BlendFactor::SrcAlpha => src[3],
        BlendFactor::OneMinusSrcAlpha => 1.0 - src[3],
        BlendFactor::DstAlpha => dst[3],
        BlendFactor::OneMinusDstAlpha => 1.0 - dst[3],
        BlendFactor::ConstantColor => constant[c],
        BlendFactor::OneMinusConstantColor => 1.0 - constant[c],
        BlendFactor::ConstantAlpha => constant[3],
        BlendFactor::OneMinusConstantAlpha => 1.0 - constant[3],
        BlendFactor::SrcAlphaSaturate => {
            if c == 3 {
                1.0
            } else {
                src[3].min(1.0 - dst[3])
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::api::pipeline::BlendComponent;
    use crate::simd::LANES;

    #[test]
    fn alpha_blending_by_hand() {
        let out = blend_pixel(&BlendState::ALPHA, [1.0, 0.0, 0.0, 0.25], [0.0, 0.0, 1.0, 1.0], [0.0; 4]);
        assert_eq!(out, [0.25, 0.0, 0.75, 1.0]);
    }

    #[test]
    fn lanes_blend_exactly_like_pixels() {
        let factors = BlendFactor::ALL;
        let ops = BlendOp::ALL;
        let value = |i: usize, c: usize| ((i * 37 + c * 11) % 29) as f32 / 17.0 - 0.3;
        let src: Vec4x8 = std::array::from_fn(|c| F32x8::from_fn(|i| value(i, c)));
        let dst: Vec4x8 = std::array::from_fn(|c| F32x8::from_fn(|i| value(i + 5, c + 1)));
        let k = [0.3, 0.7, 0.1, 0.45];
        for (i, &sf) in factors.iter().enumerate() {
            let df = factors[(i * 7 + 3) % factors.len()];
            for op in ops {
                let c = BlendComponent { src: sf, dst: df, op };
                let state = BlendState { color: c, alpha: BlendComponent { src: df, dst: sf, op } };
                let lanes = blend_lanes(&state, &src, &dst, k);
                for lane in 0..LANES {
                    let s = [0, 1, 2, 3].map(|c| src[c].lane(lane));
                    let d = [0, 1, 2, 3].map(|c| dst[c].lane(lane));
                    let p = blend_pixel(&state, s, d, k);
                    for ch in 0..4 {
                        assert_eq!(lanes[ch].lane(lane).to_bits(), p[ch].to_bits(), "{sf:?} {df:?} {op:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn every_op() {
        let c = |op, src, dst| BlendComponent { src, dst, op };
        let src = [0.5, 0.25, 1.0, 0.5];
        let dst = [0.25, 0.75, 0.5, 1.0];
        let k = [0.1, 0.2, 0.3, 0.4];
        let state = |op, s, d| BlendState { color: c(op, s, d), alpha: c(op, s, d) };
        use BlendFactor::*;
        assert_eq!(blend_pixel(&state(BlendOp::Subtract, One, One), src, dst, k), [0.25, -0.5, 0.5, -0.5]);
        assert_eq!(blend_pixel(&state(BlendOp::ReverseSubtract, One, One), src, dst, k), [-0.25, 0.5, -0.5, 0.5]);
        assert_eq!(blend_pixel(&state(BlendOp::Min, Zero, Zero), src, dst, k), [0.25, 0.25, 0.5, 0.5]);
        assert_eq!(blend_pixel(&state(BlendOp::Max, Zero, Zero), src, dst, k), [0.5, 0.75, 1.0, 1.0]);
        assert_eq!(blend_pixel(&state(BlendOp::Add, DstColor, Zero), src, dst, k), [0.125, 0.1875, 0.5, 0.5]);
        assert_eq!(blend_pixel(&state(BlendOp::Add, ConstantColor, Zero), src, dst, k)[0], 0.05);
        assert_eq!(blend_pixel(&state(BlendOp::Add, SrcAlphaSaturate, Zero), src, dst, k), [0.0, 0.0, 0.0, 0.5]);
    }
}
