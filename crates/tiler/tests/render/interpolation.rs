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

/// GL's provoking vertex (`ProvokingVertex::Last`) on lists, strips, fans and a clipped
/// triangle, on every backend, two tile sizes and two thread counts: each triangle's flat
/// varyings are its last vertex's (ES 3.0 table 2.12), copied bit for bit (one carries a NaN
/// payload, as an integer varying's bits may be), and Vulkan's first where asked.
#[test]
fn flat_varyings_take_the_provoking_vertex() {
    let size = 64u32;
    // Flat value of vertex i: 100 + i, and a NaN whose payload is i.
    let vertex =
        |x: f32, y: f32, z: f32, i: u32| v(x, y, z, [100.0 + i as f32, f32::from_bits(0x7fc0_1200 + i), 0.0, 1.0]);
    let strip = [(-1.0, -1.0), (-1.0, 1.0), (0.0, -1.0), (0.0, 1.0), (1.0, -1.0), (1.0, 1.0)];
    let fan = [(0.0, 0.0), (-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let list = [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let centroid = |pts: &[(f32, f32)], tri: [usize; 3]| {
        let (x, y) = tri.iter().fold((0.0, 0.0), |(x, y), &k| (x + pts[k].0, y + pts[k].1));
        (x / 3.0, y / 3.0)
    };
    // (topology, vertices, provoking vertex, points inside triangles with the vertex each takes).
    type Case = (Topology, Vec<Vertex>, ProvokingVertex, Vec<((f32, f32), u32)>);
    let cases: Vec<Case> = vec![
        (
            Topology::TriangleStrip,
            strip.iter().enumerate().map(|(i, p)| vertex(p.0, p.1, 0.5, i as u32)).collect(),
            ProvokingVertex::Last,
            (0..4).map(|t| (centroid(&strip, [t, t + 1, t + 2]), t as u32 + 2)).collect(),
        ),
        (
            Topology::TriangleStrip,
            strip.iter().enumerate().map(|(i, p)| vertex(p.0, p.1, 0.5, i as u32)).collect(),
            ProvokingVertex::First,
            (0..4).map(|t| (centroid(&strip, [t, t + 1, t + 2]), t as u32)).collect(),
        ),
        (
            Topology::TriangleFan,
            fan.iter().enumerate().map(|(i, p)| vertex(p.0, p.1, 0.5, i as u32)).collect(),
            ProvokingVertex::Last,
            (0..3).map(|t| (centroid(&fan, [0, t + 1, t + 2]), t as u32 + 2)).collect(),
        ),
        (
            Topology::TriangleList,
            list.iter().enumerate().map(|(i, p)| vertex(p.0, p.1, 0.5, i as u32)).collect(),
            ProvokingVertex::Last,
            vec![(centroid(&list, [0, 1, 2]), 2), (centroid(&list, [3, 4, 5]), 5)],
        ),
        (
            // The last vertex is behind the near plane: clipping keeps its values.
            Topology::TriangleList,
            vec![vertex(-1.0, -1.0, 0.5, 0), vertex(1.0, -1.0, 0.5, 1), vertex(0.0, 1.0, -1.5, 2)],
            ProvokingVertex::Last,
            vec![((0.0, -0.9), 2)],
        ),
    ];
    for (topology, verts, provoking, probes) in cases {
        let mut first: Option<Vec<u8>> = None;
        for backend in Backend::ALL {
            for (tile, threads) in [(16, 1), (32, 2)] {
                let mut device = device(backend, tile, threads);
                let color = device.create_image(ImageDesc::new(size, size, Format::Rgba32Float)).unwrap();
                let buffer = device.create_buffer_from(&verts).unwrap();
                let mut d = desc("flat");
                d.topology = topology;
                d.varyings = vec![Interpolation::Flat; 4];
                d.provoking_vertex = provoking;
                let mut pass = color_pass(color, None);
                pass.draw(Draw::new(&pipeline(FlatColor, d), buffer, 0, verts.len() as u32));
                device.submit(&pass).unwrap();
                let data = device.image_data(color).unwrap();
                for &((x, y), k) in &probes {
                    let (px, py) = (((x + 1.0) / 2.0 * size as f32) as u32, ((y + 1.0) / 2.0 * size as f32) as u32);
                    let at = |c: usize| {
                        let o = ((py * size + px) * 16) as usize + 4 * c;
                        u32::from_le_bytes(data[o..o + 4].try_into().unwrap())
                    };
                    let what = format!("{topology:?} {provoking:?} {backend} tile {tile} at ({px}, {py})");
                    assert_eq!(f32::from_bits(at(0)), 100.0 + k as f32, "{what}");
                    assert_eq!(at(1), 0x7fc0_1200 + k, "{what}: the NaN's payload");
                }
                match &first {
                    None => first = Some(data.to_vec()),
                    Some(bytes) => assert!(*bytes == data, "{topology:?} {backend} tile {tile}: other bytes"),
                }
            }
        }
    }
}
