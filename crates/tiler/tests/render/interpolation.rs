//! Varyings: perspective-correct (`smooth`), screen-linear (`noperspective`) and `flat`,
//! against values computed by hand in f64; derivatives within quads.

use super::common::*;
use tiler::*;

/// Writes (smooth 0, linear 1, flat 2, d(smooth 0)/dx) to an `Rgba32Float` target.
struct ThreeWays;

impl FragmentShader for ThreeWays {
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        let smooth = frag.smooth(0);
        frag.set_color(0, [smooth, frag.linear(1), F32x8::splat(frag.flat(2)), smooth.ddx()]);
    }
}

#[test]
fn smooth_linear_and_flat_varyings() {
    let size = 64u32;
    // A triangle over the whole screen whose vertex B is four times farther away (w = 4).
    // Vertex colours carry u = (0, 1, 0) in all three varyings, flat gets 0.25 from A.
    let clip = |x: f32, y: f32, w: f32| [x * w, y * w, 0.5 * w, w];
    let verts: [Vertex; 3] = [
        {
            let p = clip(-1.0, -1.0, 1.0);
            [p[0], p[1], p[2], p[3], 0.0, 0.0, 0.25, 0.0]
        },
        {
            let p = clip(3.0, -1.0, 4.0);
            [p[0], p[1], p[2], p[3], 1.0, 1.0, 0.75, 0.0]
        },
        {
            let p = clip(-1.0, 3.0, 1.0);
            [p[0], p[1], p[2], p[3], 0.0, 0.0, 0.75, 0.0]
        },
    ];
    for backend in Backend::ALL {
        let mut device = device(backend, 16, 2);
        let color = device.create_image(ImageDesc::new(size, size, Format::Rgba32Float)).unwrap();
        let buffer = device.create_buffer_from(&verts).unwrap();
        let mut d = desc("interpolation");
        d.varyings =
            vec![Interpolation::Perspective, Interpolation::Linear, Interpolation::Flat, Interpolation::Perspective];
        let mut pass = RenderPass::new(RenderPassDesc {
            color: vec![ColorAttachment::clear_store(color, [0.0; 4])],
            depth_stencil: None,
            render_area: None,
        });
        pass.draw(Draw::new(&Pipeline::new(PassThrough, ThreeWays, d).unwrap(), buffer, 0, 3));
        device.submit(&pass).unwrap();
        let data = device.image_data(color).unwrap();
        for y in (0..size).step_by(7) {
            for x in (0..size).step_by(5) {
                let px = &data[((y * size + x) * 16) as usize..][..16];
                let got: [f32; 4] =
                    std::array::from_fn(|i| f32::from_le_bytes(px[4 * i..4 * i + 4].try_into().unwrap()));
                // Screen-space barycentric of B: B is the only vertex right of x = −1.
                let ndc_x = 2.0 * (x as f64 + 0.5) / size as f64 - 1.0;
                let lambda_b = (ndc_x + 1.0) / 4.0;
                let lambda_rest = 1.0 - lambda_b;
                let smooth = (lambda_b / 4.0) / (lambda_rest / 1.0 + lambda_b / 4.0);
                assert!((got[0] as f64 - smooth).abs() < 1e-5, "{backend} ({x},{y}): smooth {} vs {smooth}", got[0]);
                assert!(
                    (got[1] as f64 - lambda_b).abs() < 1e-5,
                    "{backend} ({x},{y}): linear {} vs {lambda_b}",
                    got[1]
                );
                assert_eq!(got[2], 0.25, "flat takes the provoking vertex");
                // The derivative across the quad is the difference of the two columns.
                let next = |dx: f64| {
                    let l = (2.0 * (x as f64 + dx + 0.5) / size as f64 - 1.0 + 1.0) / 4.0;
                    (l / 4.0) / ((1.0 - l) + l / 4.0)
                };
                let expected = if x % 2 == 0 { next(1.0) - next(0.0) } else { next(0.0) - next(-1.0) };
                assert!((got[3] as f64 - expected).abs() < 1e-4, "{backend} ({x},{y}): ddx {} vs {expected}", got[3]);
            }
        }
    }
}
