//! Bad input gets a clear error naming what and where — never a panic or a wrong picture.

use super::common::*;
use tiler::*;

fn simple_pass(device: &mut Device) -> (ImageId, RenderPass) {
    let color = device.create_image(ImageDesc::new(16, 16, Format::Rgba8Unorm)).unwrap();
    (color, color_pass(color, None))
}

fn message(result: Result<impl std::fmt::Debug>) -> String {
    result.expect_err("must be refused").to_string()
}

#[test]
fn index_out_of_range() {
    for backend in Backend::ALL {
        let mut device = device(backend, 16, 1);
        let (_, mut pass) = simple_pass(&mut device);
        let verts: Vec<Vertex> = (0..64).map(|i| v(i as f32 / 64.0, 0.0, 0.5, [1.0; 4])).collect();
        let vb = device.create_buffer_from(&verts).unwrap();
        let ib = device.create_buffer_from(&[0u16, 1, 2, 3, 70, 5]).unwrap();
        pass.draw(Draw::indexed(&pipeline(Smooth, desc("indexed")), vb, ib, IndexType::U16, 0, 6));
        let err = device.submit(&pass).unwrap_err();
        assert_eq!(err, Error::IndexOutOfRange { draw: 0, position: 4, index: 70, vertex_count: 64 });
        assert!(err.to_string().contains("index 70 at position 4"), "{err}");
    }
}

#[test]
fn non_finite_positions() {
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        for backend in Backend::ALL {
            let mut device = device(backend, 16, 2);
            let (color, mut pass) = simple_pass(&mut device);
            let vb = device
                .create_buffer_from(&[
                    v(0.0, 0.0, 0.5, [1.0; 4]),
                    v(bad, 0.0, 0.5, [1.0; 4]),
                    v(0.0, 1.0, 0.5, [1.0; 4]),
                ])
                .unwrap();
            pass.draw(Draw::new(&pipeline(Smooth, desc("nan")), vb, 0, 3));
            let err = device.submit(&pass).unwrap_err();
            assert!(matches!(err, Error::NonFinitePosition { draw: 0, vertex: 1, .. }), "{err}");
            // A tiler had not flushed yet: the image is as it was.
            if backend.is_tiler() {
                assert!(device.image_data(color).unwrap().iter().all(|b| *b == 0));
            }
        }
    }
}

#[test]
fn image_sizes() {
    let mut device = device(Backend::Tbr, 16, 1);
    assert!(message(device.create_image(ImageDesc::new(0, 16, Format::Rgba8Unorm))).contains("0×16"));
    assert!(message(device.create_image(ImageDesc::new(20000, 16, Format::Rgba8Unorm))).contains("16384"));
    assert!(message(device.create_image(ImageDesc::new(16384, 16384, Format::Rgba32Float))).contains("exceeds"));
    assert!(
        message(device.create_image(ImageDesc::new(16, 16, Format::Rgba8Unorm).with_samples(3))).contains("3 samples")
    );
}

#[test]
fn attachments_that_do_not_fit_together() {
    let mut device = device(Backend::Tbr, 16, 1);
    let color = device.create_image(ImageDesc::new(16, 16, Format::Rgba8Unorm)).unwrap();
    let other = device.create_image(ImageDesc::new(16, 8, Format::Rgba8Unorm)).unwrap();
    let msaa = device.create_image(ImageDesc::new(16, 16, Format::Rgba8Unorm).with_samples(4)).unwrap();
    let depth = device.create_image(ImageDesc::new(16, 16, Format::D32Float)).unwrap();
    let transient = device.create_image(ImageDesc::new(16, 16, Format::D16Unorm).transient()).unwrap();
    let submit =
        |device: &mut Device, color: Vec<ColorAttachment>, ds: Option<DepthStencilAttachment>, area: Option<Rect>| {
            device
                .submit(&RenderPass::new(RenderPassDesc { color, depth_stencil: ds, render_area: area }))
                .unwrap_err()
                .to_string()
        };
    let clear = |image| ColorAttachment::clear_store(image, [0.0; 4]);
    assert!(submit(&mut device, vec![clear(color), clear(other)], None, None).contains("same size"));
    assert!(submit(&mut device, vec![clear(color), clear(msaa)], None, None).contains("samples"));
    assert!(submit(&mut device, vec![clear(color), clear(color)], None, None).contains("already attached"));
    let color2 = device.create_image(ImageDesc::new(16, 16, Format::Rgba8Unorm)).unwrap();
    let e = submit(&mut device, vec![clear(color)], Some(DepthStencilAttachment::clear_store(color2, 1.0, 0)), None);
    assert!(e.contains("depth-stencil attachment") && e.contains("needs a depth format"), "{e}");
    assert!(submit(&mut device, vec![clear(depth)], None, None).contains("not a colour format"));
    let e = submit(&mut device, vec![clear(color)], Some(DepthStencilAttachment::clear_store(transient, 1.0, 0)), None);
    assert!(e.contains("transient") && e.contains("stored"), "{e}");
    assert!(submit(&mut device, vec![clear(color)], None, Some(Rect::new(8, 8, 9, 4))).contains("render area"));
    assert!(submit(&mut device, vec![], None, None).contains("no attachments"));
    let nan = ColorAttachment::clear_store(color, [f32::NAN, 0.0, 0.0, 1.0]);
    assert!(submit(&mut device, vec![nan], None, None).contains("not finite"));
    let e = submit(&mut device, vec![clear(color)], Some(DepthStencilAttachment::clear_store(depth, 2.0, 0)), None);
    assert!(e.contains("outside [0, 1]"), "{e}");
    // A transient depth buffer cleared and discarded is fine.
    let ok = device.submit(&RenderPass::new(RenderPassDesc {
        color: vec![clear(color)],
        depth_stencil: Some(DepthStencilAttachment::clear_discard(transient, 1.0)),
        render_area: None,
    }));
    assert!(ok.is_ok());
}

#[test]
fn buffers_and_pipelines() {
    let mut device = device(Backend::Tbr, 16, 1);
    let (_, base) = simple_pass(&mut device);
    let vb = device.create_buffer_from(&[v(0.0, 0.0, 0.5, [1.0; 4]); 3]).unwrap();
    let submit = |device: &mut Device, draw: Draw| {
        let mut pass = base.clone();
        pass.draw(draw);
        device.submit(&pass).unwrap_err().to_string()
    };
    let p = pipeline(Smooth, desc("p"));
    assert!(submit(&mut device, Draw::new(&p, vb, 0, 6)).contains("vertex binding 0 holds 3 vertices"));
    let short_ib = device.create_buffer_from(&[0u16, 1]).unwrap();
    assert!(submit(&mut device, Draw::indexed(&p, vb, short_ib, IndexType::U16, 0, 3)).contains("need 6 bytes"));
    // A buffer id from another device does not exist here.
    let mut other = self::device(Backend::Tbr, 16, 1);
    for _ in 0..5 {
        other.create_buffer(&[0u8; 4]).unwrap();
    }
    let foreign = other.create_buffer(&[0u8; 4]).unwrap();
    assert!(submit(&mut device, Draw::new(&p, foreign, 0, 3)).contains("does not exist"));
    let mut no_buffers = Draw::new(&p, vb, 0, 3);
    no_buffers.vertex_buffers.clear();
    assert!(submit(&mut device, no_buffers).contains("binds 0 vertex buffers"));
    let mut two = desc("two targets");
    two.color_targets = vec![ColorTargetState::REPLACE; 2];
    assert!(submit(&mut device, Draw::new(&pipeline(Smooth, two), vb, 0, 3)).contains("writes 2 colour outputs"));
    let bad_viewport = Viewport { x: 0.0, y: 0.0, width: f32::NAN, height: 4.0, min_depth: 0.0, max_depth: 1.0 };
    assert!(submit(&mut device, Draw::new(&p, vb, 0, 3).with_viewport(bad_viewport)).contains("viewport"));

    let mut d = desc("varyings");
    d.varyings = vec![Interpolation::Flat; MAX_VARYINGS + 1];
    assert!(Pipeline::new(PassThrough, Smooth, d).unwrap_err().to_string().contains("varyings"));
    let mut d = desc("stride");
    d.vertex_input.attributes[1].offset = 20;
    assert!(Pipeline::new(PassThrough, Smooth, d).unwrap_err().to_string().contains("does not fit in the stride"));
    let mut d = desc("location");
    d.vertex_input.attributes[1].location = 0;
    assert!(Pipeline::new(PassThrough, Smooth, d).unwrap_err().to_string().contains("location 0"));
}

#[test]
fn device_configuration() {
    for tile in [0, 12, 512] {
        let e = Device::new(DeviceConfig::default().with_tile_size(tile)).err().expect("refused");
        assert!(e.to_string().contains("multiple of 8"), "{e}");
    }
    let e = Device::new(DeviceConfig { frame_data_budget: 1000, ..DeviceConfig::default() }).err().expect("refused");
    assert!(e.to_string().contains("budget"));
}

#[test]
fn a_failed_submission_leaves_the_device_usable() {
    let mut device = device(Backend::Tbr, 16, 2);
    let (color, mut pass) = simple_pass(&mut device);
    let vb = device
        .create_buffer_from(&[v(-1.0, -1.0, 0.5, [1.0; 4]), v(3.0, -1.0, 0.5, [1.0; 4]), v(-1.0, 3.0, 0.5, [1.0; 4])])
        .unwrap();
    let ib = device.create_buffer_from(&[0u32, 1, 9]).unwrap();
    let mut bad = pass.clone();
    bad.draw(Draw::indexed(&pipeline(Smooth, desc("bad")), vb, ib, IndexType::U32, 0, 3));
    assert!(device.submit(&bad).is_err());
    pass.draw(Draw::new(&pipeline(Smooth, desc("good")), vb, 0, 3));
    device.submit(&pass).unwrap();
    assert!(device.read_rgba8(color).unwrap().chunks(4).all(|p| p == [255, 255, 255, 255]));
}
