//! Depth-compare sampling (shadow samplers): each texel's depth compared with a reference,
//! then the 0/1 results filtered.
//!
//! The rule is OpenGL ES 3.0 §3.8.16 "Texture Comparison Modes": with
//! `TEXTURE_COMPARE_MODE = COMPARE_REF_TO_TEXTURE` a lookup of a depth texture returns
//! `r = 1` where `D_ref OP D_t` holds (`OP` the `TEXTURE_COMPARE_FUNC`, `D_t` the texel's
//! depth), else 0; for a fixed-point depth format both are clamped to `[0, 1]` first. With
//! `LINEAR` filtering the specification lets the implementation combine the results of the
//! texels it reads "in an implementation-dependent manner"; llvmpipe (gallivm's
//! `lp_build_sample_compare` on the four texels of `lp_build_sample_image_linear`) compares
//! each of the four texels of the bilinear footprint and blends the 0/1 results with the
//! bilinear weights, so a shadow's edge gets a one-texel ramp. That is what this does, so the
//! pictures match the reference.

use crate::api::pipeline::CompareOp;

/// 1 where `reference OP texel` holds, else 0 (GL ES 3.0 table 3.22: `LEQUAL` is
/// `reference ≤ texel`). `clamp`: a fixed-point depth format, whose reference is clamped to
/// `[0, 1]` (its texels already are). A NaN reference passes `NOTEQUAL` and `ALWAYS` only.
#[inline]
pub fn compare(op: CompareOp, reference: f32, texel: f32, clamp: bool) -> f32 {
    let reference = if clamp { reference.clamp(0.0, 1.0) } else { reference };
    let pass = op.test(reference, texel);
    if pass { 1.0 } else { 0.0 }
}

/// The bilinear blend of the compare results of a footprint's four texels, `texels` =
/// `[t00, t10, t01, t11]` (x then y), `alpha` and `beta` the weights of `x + 1` and `y + 1`
/// in `[0, 1)`: `lerp(lerp(r00, r10, α), lerp(r01, r11, α), β)`, as llvmpipe blends them.
#[inline]
pub fn compare_bilinear(op: CompareOp, reference: f32, texels: [f32; 4], alpha: f32, beta: f32, clamp: bool) -> f32 {
    let r = texels.map(|t| compare(op, reference, t, clamp));
    let top = r[0] + (r[1] - r[0]) * alpha;
    let bottom = r[2] + (r[3] - r[2]) * alpha;
    top + (bottom - top) * beta
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_function_compares_reference_with_texel() {
        let cases = [
            (CompareOp::Never, [0.0, 0.0, 0.0]),
            (CompareOp::Less, [1.0, 0.0, 0.0]),
            (CompareOp::LessOrEqual, [1.0, 1.0, 0.0]),
            (CompareOp::Equal, [0.0, 1.0, 0.0]),
            (CompareOp::NotEqual, [1.0, 0.0, 1.0]),
            (CompareOp::GreaterOrEqual, [0.0, 1.0, 1.0]),
            (CompareOp::Greater, [0.0, 0.0, 1.0]),
            (CompareOp::Always, [1.0, 1.0, 1.0]),
        ];
        for (op, want) in cases {
            // Reference below, equal to, above the texel's 0.5.
            let got = [0.25, 0.5, 0.75].map(|r| compare(op, r, 0.5, true));
            assert_eq!(got, want, "{op:?}");
        }
    }

    #[test]
    fn fixed_point_formats_clamp_the_reference() {
        // A reference beyond the far plane equals a texel at 1.0 once clamped.
        assert_eq!(compare(CompareOp::LessOrEqual, 1.5, 1.0, true), 1.0);
        assert_eq!(compare(CompareOp::LessOrEqual, 1.5, 1.0, false), 0.0);
        assert_eq!(compare(CompareOp::GreaterOrEqual, -0.5, 0.0, true), 1.0);
        assert_eq!(compare(CompareOp::Less, f32::NAN, 0.5, false), 0.0);
        assert_eq!(compare(CompareOp::NotEqual, f32::NAN, 0.5, false), 1.0);
    }

    #[test]
    fn linear_filtering_blends_the_results_not_the_depths() {
        // Left texels occlude (0.2), right ones do not (0.9); reference 0.5 with LEQUAL.
        let texels = [0.2, 0.9, 0.2, 0.9];
        let op = CompareOp::LessOrEqual;
        assert_eq!(compare_bilinear(op, 0.5, texels, 0.0, 0.0, true), 0.0);
        assert_eq!(compare_bilinear(op, 0.5, texels, 0.25, 0.5, true), 0.25);
        assert_eq!(compare_bilinear(op, 0.5, texels, 0.75, 0.9, true), 0.75);
        // Filtering the depths first (0.55 at α = ½) would pass the compare: 1, not ½.
        assert_eq!(compare_bilinear(op, 0.5, texels, 0.5, 0.0, true), 0.5);
        // Both directions: one lit texel of four, weighted α·β.
        let corner = [0.2, 0.2, 0.2, 0.9];
        assert_eq!(compare_bilinear(op, 0.5, corner, 0.5, 0.5, true), 0.25);
        assert_eq!(compare_bilinear(op, 0.5, corner, 0.25, 0.5, true), 0.125);
    }
}
