//! Load and store ops: their effect on the images and on the ledger, on each backend.

use super::common::*;
use tiler::*;

const W: u32 = 80;
const H: u32 = 48;
const PIXELS: u64 = (W * H) as u64;

/// A device with a colour image filled with `pattern` bytes and a D24S8 image filled with
/// depth 0.25 and stencil 9.
fn setup(backend: Backend) -> (Device, ImageId, ImageId) {
    let mut device = device(backend, 16, 2);
    let color = device.create_image(ImageDesc::new(W, H, Format::Rgba8Unorm)).unwrap();
    let ds = device.create_image(ImageDesc::new(W, H, Format::D24UnormS8Uint)).unwrap();
    device.write_image(color, &[7u8, 8, 9, 10].repeat(PIXELS as usize)).unwrap();
    let word = (Format::D24UnormS8Uint.depth_bits(0.25) | 9 << 24).to_le_bytes();
    device.write_image(ds, &word.repeat(PIXELS as usize)).unwrap();
    (device, color, ds)
}

/// A small red triangle in the top-left corner.
fn small_triangle(device: &mut Device, pass: &mut RenderPass) {
    let red = [1.0, 0.0, 0.0, 1.0];
    let buffer = device
        .create_buffer_from(&[v(-1.0, -1.0, 0.1, red), v(-0.8, -1.0, 0.1, red), v(-1.0, -0.8, 0.1, red)])
        .unwrap();
    let mut d = desc("small");
    d.depth_stencil = DepthStencilState::LESS_WRITE;
    pass.draw(Draw::new(&pipeline(FlatColor, d), buffer, 0, 3));
}

fn pass(color: ColorAttachment, depth: Option<DepthStencilAttachment>) -> RenderPass {
    RenderPass::new(RenderPassDesc { color: vec![color], depth_stencil: depth, render_area: None })
}

#[test]
fn clear_and_store() {
    for backend in Backend::ALL {
        let (mut device, color, _) = setup(backend);
        let report = device.submit(&pass(ColorAttachment::clear_store(color, [0.0, 1.0, 0.0, 1.0]), None)).unwrap();
        assert!(device.read_rgba8(color).unwrap().chunks(4).all(|p| p == [0, 255, 0, 255]));
        match backend {
            Backend::Tbr | Backend::Tbdr => {
                assert_eq!(report.ledger.get(Category::TileLoad), 0, "a clear reads nothing");
                assert_eq!(report.ledger.get(Category::TileStore), PIXELS * 4);
                assert_eq!(report.ledger.total(), PIXELS * 4);
                assert_eq!(report.counters.tiles_processed, 15);
            }
            Backend::Imr => {
                assert_eq!(report.ledger.get(Category::ImrClear), PIXELS * 4);
                assert_eq!(report.ledger.total(), PIXELS * 4);
            }
        }
    }
}

#[test]
fn load_keeps_what_was_there() {
    for backend in Backend::ALL {
        let (mut device, color, _) = setup(backend);
        let mut p =
            pass(ColorAttachment { image: color, load: LoadOp::Load, store: StoreOp::Store, resolve: None }, None);
        small_triangle(&mut device, &mut p);
        let report = device.submit(&p).unwrap();
        let image = device.read_rgba8(color).unwrap();
        assert_eq!(&image[..4], &[255, 0, 0, 255]);
        assert_eq!(&image[image.len() - 4..], &[7, 8, 9, 10]);
        if backend.is_tiler() {
            assert_eq!(report.ledger.get(Category::TileLoad), PIXELS * 4);
            assert_eq!(report.ledger.get(Category::TileStore), PIXELS * 4);
        } else {
            assert_eq!(report.ledger.get(Category::ImrClear), 0);
            assert_eq!(report.ledger.get(Category::ImrColorWrite), report.counters.fragments_passed * 4);
        }
    }
}

#[test]
fn dont_care_store_writes_nothing() {
    let (mut device, color, _) = setup(Backend::Tbr);
    let mut p = pass(
        ColorAttachment { image: color, load: LoadOp::Clear([0.0; 4]), store: StoreOp::DontCare, resolve: None },
        None,
    );
    small_triangle(&mut device, &mut p);
    let report = device.submit(&p).unwrap();
    assert_eq!(report.ledger.get(Category::TileStore), 0);
    assert_eq!(report.ledger.get(Category::TileLoad), 0);
    // The tiler never wrote the image: it still holds what it held.
    assert!(device.image_data(color).unwrap().chunks(4).all(|p| p == [7, 8, 9, 10]));
}

#[test]
fn dont_care_load_reads_nothing_and_is_defined_as_zero() {
    for backend in Backend::ALL {
        let (mut device, color, _) = setup(backend);
        let report = device
            .submit(&pass(
                ColorAttachment { image: color, load: LoadOp::DontCare, store: StoreOp::Store, resolve: None },
                None,
            ))
            .unwrap();
        assert_eq!(report.ledger.get(Category::TileLoad), 0);
        assert!(device.image_data(color).unwrap().iter().all(|b| *b == 0), "{backend}");
    }
}

#[test]
fn depth_discarded_at_the_end_costs_nothing() {
    for backend in Backend::ALL {
        let (mut device, color, ds) = setup(backend);
        let mut p =
            pass(ColorAttachment::clear_store(color, [0.0; 4]), Some(DepthStencilAttachment::clear_discard(ds, 1.0)));
        small_triangle(&mut device, &mut p);
        let report = device.submit(&p).unwrap();
        if backend.is_tiler() {
            // Only colour leaves the chip.
            assert_eq!(report.ledger.get(Category::TileStore), PIXELS * 4);
            assert_eq!(report.ledger.get(Category::TileLoad), 0);
        } else {
            // Immediate mode clears depth and stencil in memory (the packed word's 3 + 1
            // bytes), and tests and writes depth per fragment: with no stencil test, depth
            // alone, and memory moves a D24S8 sample as one 32-bit word, so 4 bytes each.
            assert_eq!(report.ledger.get(Category::ImrClear), PIXELS * (4 + 3 + 1));
            let fragments = report.counters.fragments_rasterized;
            assert_eq!(report.ledger.get(Category::ImrDepthRead), fragments * 4);
            assert_eq!(report.ledger.get(Category::ImrDepthWrite), fragments * 4);
        }
    }
}

#[test]
fn depth_and_stencil_aspects_load_separately() {
    for backend in Backend::ALL {
        let (mut device, color, ds) = setup(backend);
        let depth = DepthStencilAttachment {
            image: ds,
            depth_load: LoadOp::Clear(1.0),
            depth_store: StoreOp::Store,
            stencil_load: LoadOp::Load,
            stencil_store: StoreOp::Store,
        };
        let report = device.submit(&pass(ColorAttachment::clear_store(color, [0.0; 4]), Some(depth))).unwrap();
        assert!(device.read_depth(ds).unwrap().iter().all(|d| *d == 1.0), "{backend}: depth cleared");
        assert!(device.read_stencil(ds).unwrap().iter().all(|s| *s == 9), "{backend}: stencil kept");
        if backend.is_tiler() {
            // Only the stencil is loaded, but memory moves a D24S8 sample as one 32-bit word.
            assert_eq!(report.ledger.get(Category::TileLoad), PIXELS * 4, "the stencil's whole word is loaded");
            assert_eq!(report.ledger.get(Category::TileStore), PIXELS * (4 + 4));
        } else {
            // Colour, and depth alone: its whole word.
            assert_eq!(report.ledger.get(Category::ImrClear), PIXELS * (4 + 4));
        }
    }
}

#[test]
fn render_area_limits_loads_stores_and_drawing() {
    for backend in Backend::ALL {
        let (mut device, color, _) = setup(backend);
        let area = Rect::new(10, 6, 33, 21);
        let mut p = RenderPass::new(RenderPassDesc {
            color: vec![ColorAttachment::clear_store(color, [0.0, 0.0, 1.0, 1.0])],
            depth_stencil: None,
            render_area: Some(area),
        });
        // A full-screen triangle: only the render area may change.
        let buffer = device
            .create_buffer_from(&[
                v(-1.0, -1.0, 0.5, [1.0; 4]),
                v(3.0, -1.0, 0.5, [1.0; 4]),
                v(-1.0, 3.0, 0.5, [1.0; 4]),
            ])
            .unwrap();
        p.draw(Draw::new(&pipeline(Solid([1.0, 1.0, 0.0, 1.0]), desc("full")), buffer, 0, 3));
        let report = device.submit(&p).unwrap();
        let image = device.read_rgba8(color).unwrap();
        for y in 0..H {
            for x in 0..W {
                let inside = (10..43).contains(&x) && (6..27).contains(&y);
                let px = &image[((y * W + x) * 4) as usize..][..4];
                assert_eq!(
                    px,
                    if inside { &[255, 255, 0, 255][..] } else { &[7, 8, 9, 10][..] },
                    "{backend} ({x}, {y})"
                );
            }
        }
        assert_eq!(report.counters.fragments_shaded, area.area());
        match backend {
            Backend::Tbr | Backend::Tbdr => assert_eq!(report.ledger.get(Category::TileStore), area.area() * 4),
            Backend::Imr => assert_eq!(report.ledger.get(Category::ImrClear), area.area() * 4),
        }
    }
}

#[test]
fn clear_fill_frame_costs_what_the_seed_says() {
    // Seed 004 §24.3.2 without display: 1024×768, RGB565 colour, 16-bit depth, clear both and
    // draw one full-screen opaque quad. Immediate mode: clear colour, clear depth, read depth,
    // write depth, write colour = 5 full-screen accesses; a tiler with depth discarded: 1.
    let access = 1024 * 768 * 2;
    for backend in Backend::ALL {
        let mut device = device(backend, 32, 2);
        let color = device.create_image(ImageDesc::new(1024, 768, Format::Rgb565Unorm)).unwrap();
        let depth = device.create_image(ImageDesc::new(1024, 768, Format::D16Unorm)).unwrap();
        let mut p = pass(
            ColorAttachment::clear_store(color, [0.0; 4]),
            Some(DepthStencilAttachment::clear_discard(depth, 1.0)),
        );
        let white = [1.0; 4];
        let quad = [
            v(-1.0, -1.0, 0.5, white),
            v(-1.0, 1.0, 0.5, white),
            v(1.0, 1.0, 0.5, white),
            v(-1.0, -1.0, 0.5, white),
            v(1.0, 1.0, 0.5, white),
            v(1.0, -1.0, 0.5, white),
        ];
        let buffer = device.create_buffer_from(&quad).unwrap();
        let mut d = desc("fill");
        d.depth_stencil = DepthStencilState::LESS_WRITE;
        p.draw(Draw::new(&pipeline(FlatColor, d), buffer, 0, 6));
        let report = device.submit(&p).unwrap();
        let framebuffer = report.ledger.total()
            - report.ledger.get(Category::VertexFetch)
            - report.ledger.get(Category::FrameDataWrite)
            - report.ledger.get(Category::FrameDataRead);
        match backend {
            Backend::Imr => assert_eq!(framebuffer, 5 * access),
            Backend::Tbr | Backend::Tbdr => assert_eq!(framebuffer, access),
        }
    }
}

/// Seed 001: a pass whose every draw lies inside one scissor box covers only that box —
/// the tiles outside it are neither loaded nor stored — and draws the same picture, on every
/// backend, tile size and thread count, as the same pass made to cover everything (by a
/// draw without a scissor that draws nothing). A pass that clears keeps its whole area: the
/// clear must reach every pixel.
#[test]
fn a_scissor_box_around_every_draw_is_the_render_area() {
    let scissor = Rect::new(10, 6, 33, 21);
    let render = |backend: Backend, tile: u32, threads: usize, narrowable: bool, clear: bool| {
        let mut device = device(backend, tile, threads);
        let color = device.create_image(ImageDesc::new(W, H, Format::Rgba8Unorm)).unwrap();
        let ds = device.create_image(ImageDesc::new(W, H, Format::D24UnormS8Uint)).unwrap();
        device.write_image(color, &[7u8, 8, 9, 10].repeat(PIXELS as usize)).unwrap();
        let word = (Format::D24UnormS8Uint.depth_bits(0.25) | 9 << 24).to_le_bytes();
        device.write_image(ds, &word.repeat(PIXELS as usize)).unwrap();
        let color_attachment = if clear {
            ColorAttachment::clear_store(color, [0.0, 0.0, 1.0, 1.0])
        } else {
            ColorAttachment::load_store(color)
        };
        let depth = DepthStencilAttachment {
            image: ds,
            depth_load: LoadOp::Load,
            depth_store: StoreOp::Store,
            stencil_load: LoadOp::Load,
            stencil_store: StoreOp::Store,
        };
        let mut p = pass(color_attachment, Some(depth));
        let full = device
            .create_buffer_from(&[
                v(-1.0, -1.0, 0.1, [1.0; 4]),
                v(3.0, -1.0, 0.1, [1.0; 4]),
                v(-1.0, 3.0, 0.1, [1.0; 4]),
            ])
            .unwrap();
        let mut d = desc("full");
        d.depth_stencil = DepthStencilState::LESS_WRITE;
        let solid = pipeline(Solid([1.0, 1.0, 0.0, 1.0]), d);
        p.draw(Draw::new(&solid, full, 0, 3).with_scissor(scissor));
        p.draw(Draw::new(&solid, full, 0, 3).with_scissor(Rect::new(12, 8, 4, 4)));
        if !narrowable {
            let nothing = device.create_buffer_from(&[v(0.0, 0.0, 0.1, [1.0; 4]); 3]).unwrap();
            p.draw(Draw::new(&solid, nothing, 0, 3));
        }
        let report = device.submit(&p).unwrap();
        let pictures =
            (device.read_rgba8(color).unwrap(), device.read_depth(ds).unwrap(), device.read_stencil(ds).unwrap());
        (report, pictures)
    };
    let (_, reference) = render(Backend::Imr, 16, 1, false, false);
    for backend in Backend::ALL {
        for (tile, threads) in [(8, 1), (16, 2), (32, 3)] {
            let (narrowed, picture) = render(backend, tile, threads, true, false);
            assert_eq!(picture, reference, "{backend}, {tile}×{tile} tiles, {threads} threads: the picture");
            assert_eq!(narrowed.render_area, Some(scissor), "{backend}");
            let (whole, whole_picture) = render(backend, tile, threads, false, false);
            assert_eq!(whole_picture, reference);
            assert_eq!(whole.render_area, None);
            if backend.is_tiler() {
                // Colour (4 bytes) and depth-stencil (4 bytes), in the box only.
                assert_eq!(narrowed.ledger.get(Category::TileLoad), scissor.area() * 8, "{backend} {tile}");
                assert_eq!(narrowed.ledger.get(Category::TileStore), scissor.area() * 8, "{backend} {tile}");
                assert_eq!(whole.ledger.get(Category::TileLoad), PIXELS * 8);
                let untouched = narrowed.tiles.iter().filter(|t| t.bytes_loaded == 0 && t.bytes_stored == 0).count();
                let (tx0, ty0) = (scissor.x / tile, scissor.y / tile);
                let (tx1, ty1) = ((scissor.right() as u32 - 1) / tile, (scissor.bottom() as u32 - 1) / tile);
                let touched = ((tx1 - tx0 + 1) * (ty1 - ty0 + 1)) as usize;
                assert_eq!(untouched, narrowed.tiles.len() - touched, "{backend} {tile}: only the box's tiles");
            }
        }
        let (cleared, _) = render(backend, 16, 1, true, true);
        assert_eq!(cleared.render_area, None, "{backend}: a clear covers the whole framebuffer");
    }
}

/// An image's version changes with every write of it — a write, a pass with it as an
/// attachment, whatever its store op — and with nothing else: another image's pass or write,
/// a read, a failed write.
#[test]
fn image_versions_change_with_every_write_of_the_image() {
    for backend in Backend::ALL {
        let (mut device, color, ds) = setup(backend);
        let other = device.create_image(ImageDesc::new(W, H, Format::Rgba8Unorm)).unwrap();
        let versions = |device: &Device| [color, ds, other].map(|i| device.image_version(i).unwrap());
        let before = versions(&device);
        assert!(before[0] != before[1] && before[1] != before[2] && before[0] != before[2]);

        device.submit(&pass(ColorAttachment::clear_store(other, [0.0, 1.0, 0.0, 1.0]), None)).unwrap();
        let after_other = versions(&device);
        assert_eq!(after_other[..2], before[..2], "{backend:?}: a pass into another image");
        assert_ne!(after_other[2], before[2], "{backend:?}: a pass into the image");

        device.read_rgba8(color).unwrap();
        assert!(device.write_image(color, &[0; 3]).is_err());
        assert_eq!(versions(&device), after_other, "{backend:?}: a read and a refused write");

        device.write_image(color, &[1u8; PIXELS as usize * 4]).unwrap();
        let after_write = versions(&device);
        assert_ne!(after_write[0], after_other[0], "{backend:?}: a write");
        assert_eq!(after_write[1..], after_other[1..]);

        // A pass that stores nothing into the colour image still counts as writing it, and its
        // depth attachment too.
        let depth = DepthStencilAttachment::clear_store(ds, 1.0, 0);
        let dont_store = ColorAttachment { store: StoreOp::DontCare, ..ColorAttachment::clear_store(color, [0.0; 4]) };
        let mut p = pass(dont_store, Some(depth));
        small_triangle(&mut device, &mut p);
        device.submit(&p).unwrap();
        let after_pass = versions(&device);
        assert_ne!(after_pass[0], after_write[0], "{backend:?}: a pass not storing the image");
        assert_ne!(after_pass[1], after_write[1], "{backend:?}: the depth attachment");
        assert_eq!(after_pass[2], after_write[2]);
    }
}
