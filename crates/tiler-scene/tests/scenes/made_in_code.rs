//! The scenes made in code: every backend gives the same picture; the deferred frame costs
//! what subpasses promise.

use tiler::{Backend, Category, Device, DeviceConfig};
use tiler_scene::deferred::{self, Variant};

fn render(backend: Backend, build: impl Fn(&mut Device) -> tiler_scene::Scene) -> (Vec<u8>, Vec<tiler::PassReport>) {
    let mut device = Device::new(DeviceConfig { backend, threads: 2, ..DeviceConfig::default() }).unwrap();
    let scene = build(&mut device);
    let reports = scene.render(&mut device, backend).unwrap();
    (device.read_rgba8(scene.color).unwrap(), reports)
}

#[test]
fn the_builtin_scene_is_the_same_on_every_backend() {
    for samples in [1, 4] {
        let build = |d: &mut Device| tiler_scene::builtin::build(d, 320, 180, samples).unwrap();
        let (reference, _) = render(Backend::Imr, build);
        for backend in [Backend::Tbr, Backend::Tbdr] {
            assert!(render(backend, build).0 == reference, "{backend}, {samples} samples");
        }
    }
}

#[test]
fn deferred_shading_in_subpasses_keeps_the_g_buffer_in_the_tile() {
    let (width, height) = (256, 144);
    let pixels = (width * height) as u64;
    let (reference, _) = render(Backend::Imr, |d| deferred::build(d, width, height, Variant::Passes).unwrap());
    for backend in Backend::ALL {
        let (one_pass, one) = render(backend, |d| deferred::build(d, width, height, Variant::Subpasses).unwrap());
        let (two_pass, two) = render(backend, |d| deferred::build(d, width, height, Variant::Passes).unwrap());
        assert!(one_pass == reference && two_pass == reference, "{backend}: the same picture both ways");
        if backend.is_tiler() {
            let sum = |reports: &[tiler::PassReport], c| reports.iter().map(|r| r.ledger.get(c)).sum::<u64>();
            // One pass: only the lit RGBA8 colour leaves the chip; no G-buffer byte moves.
            assert_eq!(sum(&one, Category::TileStore), pixels * 4);
            assert_eq!(sum(&one, Category::TileLoad), 0);
            // Albedo (4) + normal (8) + depth (4) bytes per pixel never needed memory.
            assert_eq!(one[0].transient_bytes_saved, pixels * 16);
            // Two passes: the G-buffer is stored and loaded back.
            assert_eq!(sum(&two, Category::TileStore), pixels * (16 + 4));
            assert_eq!(sum(&two, Category::TileLoad), pixels * 16);
        }
    }
}

#[test]
fn deferred_shading_of_a_gltf_model_keeps_the_g_buffer_in_the_tile() {
    let Some(assets) = super::common::assets_dir() else { return };
    // The duck: one textured opaque material.
    let model = tiler_scene::gltf::load(&assets.join("Duck/Duck.gltf"), tiler_scene::shading::Shading::Scenes).unwrap();
    let (width, height) = (192, 108);
    let pixels = (width * height) as u64;
    let camera = tiler_scene::camera::CameraChoice::Orbit;
    let model = &model;
    let build =
        |variant| move |d: &mut Device| deferred::build_model(d, model, width, height, camera, variant).unwrap();
    let (reference, _) = render(Backend::Imr, build(Variant::Passes));
    // Lit and textured: many colours, not the sky alone.
    let colours: std::collections::HashSet<&[u8]> = reference.chunks_exact(4).collect();
    assert!(colours.len() > 100, "{} colours", colours.len());
    for backend in [Backend::Tbr, Backend::Tbdr] {
        let (one_pass, one) = render(backend, build(Variant::Subpasses));
        let (two_pass, _) = render(backend, build(Variant::Passes));
        assert!(one_pass == reference && two_pass == reference, "{backend}: the same picture both ways");
        let sum = |c| one.iter().map(|r: &tiler::PassReport| r.ledger.get(c)).sum::<u64>();
        assert_eq!(sum(Category::TileStore), pixels * 4);
        assert_eq!(sum(Category::TileLoad), 0);
        assert_eq!(one[0].transient_bytes_saved, pixels * 16);
    }
}
