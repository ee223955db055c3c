//! Blending: `op(src · src_factor, dst · dst_factor)` per channel, in f32 (Vulkan "Blend
//! Operations"). For normalised fixed-point attachments the source, destination and constant
//! are clamped to `[0, 1]` first, as Vulkan requires; the result is then packed to the format.

use crate::api::pipeline::{BlendComponent, BlendFactor, BlendOp, BlendState};

/// Blends one pixel. `dst` is the stored value unpacked (sRGB attachments: linear).
#[inline]
pub fn blend_pixel(state: &BlendState, src: [f32; 4], dst: [f32; 4], constant: [f32; 4]) -> [f32; 4] {
    let mut out = [0.0; 4];
    for (c, out) in out.iter_mut().enumerate() {
        let component = if c < 3 { &state.color } else { &state.alpha };
        *out = blend_channel(component, c, src, dst, constant);
    }
    out
}

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

    #[test]
    fn alpha_blending_by_hand() {
        let out = blend_pixel(&BlendState::ALPHA, [1.0, 0.0, 0.0, 0.25], [0.0, 0.0, 1.0, 1.0], [0.0; 4]);
        assert_eq!(out, [0.25, 0.0, 0.75, 1.0]);
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
