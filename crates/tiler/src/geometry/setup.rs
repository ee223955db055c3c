//! Triangle setup: perspective divide, viewport transform, snapping to fixed point, facing and
//! culling, edge functions, the bounding box of possibly covered pixels, and the
//! interpolation planes — everything a tile needs to rasterize the triangle.

use glam::Vec4;

use crate::api::format::Format;
use crate::api::pipeline::{CullMode, DepthBias, FrontFace};
use crate::api::render_pass::Viewport;
use crate::geometry::primitive::Primitive;
use crate::raster::PixelRect;
use crate::raster::fixed::{SUBPIXEL_SCALE, SubPixel};
use crate::raster::samples::SampleLocations;

/// Vulkan's viewport transform, in f64.
#[derive(Clone, Copy, Debug)]
pub struct ViewportTransform {
    origin_x: f64,
    origin_y: f64,
    half_width: f64,
    half_height: f64,
    depth_scale: f64,
    depth_offset: f64,
}

impl ViewportTransform {
    pub fn new(v: &Viewport) -> ViewportTransform {
        ViewportTransform {
            origin_x: v.x as f64 + v.width as f64 / 2.0,
            origin_y: v.y as f64 + v.height as f64 / 2.0,
            half_width: v.width as f64 / 2.0,
            half_height: v.height as f64 / 2.0,
            depth_scale: v.max_depth as f64 - v.min_depth as f64,
            depth_offset: v.min_depth as f64,
        }
    }
}

/// Everything setup needs to know about the draw.
#[derive(Clone, Copy, Debug)]
pub struct SetupParams {
    pub viewport: ViewportTransform,
    pub clip_rect: PixelRect,
    pub cull_mode: CullMode,
    pub front_face: FrontFace,
    pub samples: SampleLocations,
    pub state: u32,
    pub depth_bias: DepthOffset,
    /// Every triangle is front-facing whatever its winding (a line's, GL ES 2.0 §3.4).
    pub always_front: bool,
}

/// A pipeline's depth bias with its depth format's resolvable difference (see [`DepthBias`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DepthOffset {
    /// No bias, or no depth attachment.
    None,
    /// A UNORM format: `r = 1 / (2^b − 1)`.
    Unorm { bias: DepthBias, r: f64 },
    /// D32F: `r = 2^(e − 23)`, `e` from the triangle's depths.
    Float { bias: DepthBias },
}

impl DepthOffset {
    pub fn new(bias: DepthBias, format: Option<Format>) -> DepthOffset {
        if bias.is_none() {
            return DepthOffset::None;
        }
        let unorm = |bits: i32| DepthOffset::Unorm { bias, r: 1.0 / (2f64.powi(bits) - 1.0) };
        match format {
            Some(Format::D16Unorm) => unorm(16),
            Some(Format::D24UnormS8Uint) => unorm(24),
            Some(Format::D32Float) => DepthOffset::Float { bias },
            _ => DepthOffset::None,
        }
    }

    /// The offset of a triangle with window depths `z` and depth slopes `dz_dx`, `dz_dy`
    /// (per pixel), in f64 so that every backend and tile adds the same value.
    fn offset(&self, z: [f64; 3], dz_dx: f64, dz_dy: f64) -> f64 {
        let (bias, r) = match *self {
            DepthOffset::None => return 0.0,
            DepthOffset::Unorm { bias, r } => (bias, r),
            DepthOffset::Float { bias } => {
                let largest = z.iter().fold(0.0f64, |m, z| m.max(z.abs())) as f32;
                // The exponent of a normal float; zero and denormals take the smallest one.
                let e = ((largest.to_bits() >> 23) & 0xff).max(1) as i32 - 127;
                (bias, 2f64.powi(e - 23))
            }
        };
        let m = dz_dx.abs().max(dz_dy.abs());
        bias.slope_factor as f64 * m + bias.constant_factor as f64 * r
    }
}

/// What became of a triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SetupOutcome {
    Primitive,
    Culled,
    /// Zero area, or no sample position inside it and the clip rectangle.
    Degenerate,
}

/// Sets up one triangle (clip-space positions with `w > 0`, from the clipper) and appends its
/// primitive record and varyings. `vertex_ids` name the draw's vertices it came from (for
/// the cost model of shading vertices per tile).
pub fn setup_triangle(
    params: &SetupParams,
    positions: [Vec4; 3],
    varyings: [&[f32]; 3],
    vertex_ids: [u32; 3],
    primitives: &mut Vec<Primitive>,
    out_varyings: &mut Vec<f32>,
) -> SetupOutcome {
    let vp = &params.viewport;
    let mut window = [(SubPixel::default(), SubPixel::default()); 3];
    // The window positions before snapping: the interpolation planes come from these (as in
    // Mesa's llvmpipe, whose attribute planes use the float positions; coverage uses the
    // snapped ones), so a varying does not move by the snapping error (up to 1/512 pixel).
    let mut exact = [(0.0f64, 0.0f64); 3];
    let mut z = [0.0f64; 3];
    let mut q = [0.0f64; 3];
    for i in 0..3 {
        let p = positions[i];
        let inv_w = 1.0 / p.w as f64;
        let (x, y) =
            (vp.origin_x + vp.half_width * (p.x as f64 * inv_w), vp.origin_y + vp.half_height * (p.y as f64 * inv_w));
        window[i] = (SubPixel::from_window(x), SubPixel::from_window(y));
        exact[i] = (x, y);
        z[i] = vp.depth_offset + vp.depth_scale * (p.z as f64 * inv_w);
        q[i] = inv_w;
    }
    let d1 = (window[1].0.raw() - window[0].0.raw(), window[1].1.raw() - window[0].1.raw());
    let d2 = (window[2].0.raw() - window[0].0.raw(), window[2].1.raw() - window[0].1.raw());
    let area2 = d1.0 * d2.1 - d1.1 * d2.0;
    if area2 == 0 {
        return SetupOutcome::Degenerate;
    }
    // Vulkan's signed area is a = −area2 / 2 in framebuffer coordinates (y down); a > 0 is
    // counter-clockwise.
    let counter_clockwise = area2 < 0;
    let front_facing = params.always_front
        || match params.front_face {
            FrontFace::CounterClockwise => counter_clockwise,
            FrontFace::Clockwise => !counter_clockwise,
        };
    let culled = match params.cull_mode {
        CullMode::None => false,
        CullMode::Front => front_facing,
        CullMode::Back => !front_facing,
        CullMode::FrontAndBack => true,
    };
    if culled {
        return SetupOutcome::Culled;
    }
    // Keep vertex 0 (the provoking vertex) first; swap 1 and 2 to make the area positive.
    let order = if area2 > 0 { [0, 1, 2] } else { [0, 2, 1] };
    let p = order.map(|i| window[i]);

    let Some(bbox) = sample_bbox(&p, &params.samples).map(|b| b.intersect(&params.clip_rect)) else {
        return SetupOutcome::Degenerate;
    };
    if bbox.is_empty() {
        return SetupOutcome::Degenerate;
    }

    let [o0, o1, o2] = order;
    let mut q_at = order.map(|i| exact[i]);
    let edge = |q: &[(f64, f64); 3], k: usize| (q[k].0 - q[0].0, q[k].1 - q[0].1);
    let (mut e1, mut e2) = (edge(&q_at, 1), edge(&q_at, 2));
    // Twice the signed area of the ordered vertices (the planes below hold for either sign).
    // A sliver whose unsnapped area vanishes while its snapped one does not takes the snapped
    // positions.
    let mut area = e1.0 * e2.1 - e1.1 * e2.0;
    if area == 0.0 || !area.is_finite() {
        q_at = p.map(|(x, y)| (x.to_pixels(), y.to_pixels()));
        (e1, e2) = (edge(&q_at, 1), edge(&q_at, 2));
        let scale = SUBPIXEL_SCALE as f64;
        area = area2.abs() as f64 / (scale * scale);
    }
    // Depth is z0 + λ1·(z1 − z0) + λ2·(z2 − z0); its slopes follow from the λ planes.
    let (dz1, dz2) = (z[o1] - z[o0], z[o2] - z[o0]);
    let (dz_dx, dz_dy) = ((e2.1 * dz1 - e1.1 * dz2) / area, (e1.0 * dz2 - e2.0 * dz1) / area);
    let z0 = z[o0] + params.depth_bias.offset(z, dz_dx, dz_dy);
    let varying_offset = out_varyings.len() as u32;
    for &i in &order {
        out_varyings.extend_from_slice(varyings[i]);
    }
    primitives.push(Primitive {
        window: p,
        bbox,
        origin: [q_at[0].0 as f32, q_at[0].1 as f32],
        l1: [(e2.1 / area) as f32, (-e2.0 / area) as f32],
        l2: [(-e1.1 / area) as f32, (e1.0 / area) as f32],
        z: [z0 as f32, dz1 as f32, dz2 as f32],
        q: [q[o0] as f32, q[o1] as f32, q[o2] as f32],
        state: params.state,
        varyings: varying_offset,
        vertex_ids: order.map(|i| vertex_ids[i]),
        front_facing,
    });
    SetupOutcome::Primitive
}

/// The pixels whose sample positions can lie inside the triangle's bounding box, or `None`
/// if there are none.
fn sample_bbox(p: &[(SubPixel, SubPixel); 3], samples: &SampleLocations) -> Option<PixelRect> {
    let (hx0, hy0, hx1, hy1) = samples.hull();
    let xs = p.map(|v| v.0.raw());
    let ys = p.map(|v| v.1.raw());
    let (min_x, max_x) = (*xs.iter().min().unwrap(), *xs.iter().max().unwrap());
    let (min_y, max_y) = (*ys.iter().min().unwrap(), *ys.iter().max().unwrap());
    // Pixel px has samples at px·256 + [h0, h1]: it can be covered when that range meets
    // [min, max].
    let x0 = SubPixel::ceil_pixel(min_x - hx1 as i64);
    let x1 = SubPixel::floor_pixel(max_x - hx0 as i64) + 1;
    let y0 = SubPixel::ceil_pixel(min_y - hy1 as i64);
    let y1 = SubPixel::floor_pixel(max_y - hy0 as i64) + 1;
    let rect = PixelRect::new(x0 as i32, y0 as i32, x1 as i32, y1 as i32);
    (!rect.is_empty()).then_some(rect)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params(cull_mode: CullMode) -> SetupParams {
        SetupParams {
            viewport: ViewportTransform::new(&Viewport::full(100, 100)),
            clip_rect: PixelRect::new(0, 0, 100, 100),
            cull_mode,
            front_face: FrontFace::CounterClockwise,
            samples: SampleLocations::standard(1),
            state: 0,
            depth_bias: DepthOffset::None,
            always_front: false,
        }
    }

    #[test]
    fn facing_and_culling() {
        // In NDC with y down: (−0.5,−0.5) top-left, (0.5,−0.5) top-right, (−0.5,0.5) bottom-left
        // is clockwise on screen.
        let cw = [Vec4::new(-0.5, -0.5, 0.5, 1.0), Vec4::new(0.5, -0.5, 0.5, 1.0), Vec4::new(-0.5, 0.5, 0.5, 1.0)];
        let ccw = [cw[0], cw[2], cw[1]];
        let none: [&[f32]; 3] = [&[], &[], &[]];
        let (mut prims, mut vars) = (Vec::new(), Vec::new());
        assert_eq!(
            setup_triangle(&params(CullMode::Back), cw, none, [0, 1, 2], &mut prims, &mut vars),
            SetupOutcome::Culled
        );
        assert_eq!(
            setup_triangle(&params(CullMode::Back), ccw, none, [0, 1, 2], &mut prims, &mut vars),
            SetupOutcome::Primitive
        );
        assert!(prims[0].front_facing);
        assert_eq!(
            setup_triangle(&params(CullMode::None), cw, none, [0, 1, 2], &mut prims, &mut vars),
            SetupOutcome::Primitive
        );
        assert!(!prims[1].front_facing);
    }

    #[test]
    fn depth_bias_adds_slope_and_resolvable_units() {
        // Depth rises 0.5 across the 100-pixel viewport in x: a slope of 0.005 per pixel.
        let tri = [Vec4::new(-1.0, -1.0, 0.0, 1.0), Vec4::new(1.0, -1.0, 0.5, 1.0), Vec4::new(-1.0, 1.0, 0.0, 1.0)];
        let none: [&[f32]; 3] = [&[], &[], &[]];
        let bias = DepthBias { constant_factor: 3.0, slope_factor: 2.0 };
        let z0 = |depth_bias: DepthOffset| {
            let (mut prims, mut vars) = (Vec::new(), Vec::new());
            let p = SetupParams { depth_bias, ..params(CullMode::None) };
            setup_triangle(&p, tri, none, [0, 1, 2], &mut prims, &mut vars);
            prims[0].z[0] as f64
        };
        let plain = z0(DepthOffset::None);
        assert_eq!(plain, 0.0);
        let d24 = z0(DepthOffset::new(bias, Some(Format::D24UnormS8Uint)));
        let expected = 2.0 * 0.005 + 3.0 / 16777215.0;
        assert!((d24 - expected).abs() < 1e-7, "{d24} vs {expected}");
        // D32F: the largest depth is 0.5, exponent −1, so r = 2^−24.
        let d32 = z0(DepthOffset::new(bias, Some(Format::D32Float)));
        let expected = 2.0 * 0.005 + 3.0 * 2f64.powi(-24);
        assert!((d32 - expected).abs() < 1e-7, "{d32} vs {expected}");
        assert_eq!(DepthOffset::new(bias, None), DepthOffset::None);
        assert_eq!(DepthOffset::new(DepthBias::NONE, Some(Format::D16Unorm)), DepthOffset::None);
    }

    #[test]
    fn barycentric_planes_hit_the_vertices() {
        let tri = [Vec4::new(-0.5, -0.5, 0.25, 1.0), Vec4::new(0.5, -0.3, 0.5, 2.0), Vec4::new(0.1, 0.6, 0.75, 1.0)];
        let (mut prims, mut vars) = (Vec::new(), Vec::new());
        let vs: [&[f32]; 3] = [&[1.0], &[2.0], &[3.0]];
        setup_triangle(&params(CullMode::None), tri, vs, [0, 1, 2], &mut prims, &mut vars);
        let p = prims[0];
        // Vertices 1 and 2 are at window (62.5, 42.5) and (55, 80), in either order: check λ at both.
        let at = |x: f32, y: f32| {
            let (dx, dy) = (x - p.origin[0], y - p.origin[1]);
            (p.l1[0] * dx + p.l1[1] * dy, p.l2[0] * dx + p.l2[1] * dy)
        };
        let (a, b) = at(62.5, 42.5);
        let (c, d) = at(55.0, 80.0);
        assert!(((a - 1.0).abs() < 1e-5 && b.abs() < 1e-5) || ((b - 1.0).abs() < 1e-5 && a.abs() < 1e-5));
        assert!(((c - 1.0).abs() < 1e-5 && d.abs() < 1e-5) || ((d - 1.0).abs() < 1e-5 && c.abs() < 1e-5));
        assert_eq!(vars[0], 1.0, "provoking vertex first");
    }
}
