//! Our renders against llvmpipe's (`../shared/reference`, see its README): every model at
//! 960×540 and the benchmark scenes at 1920×1080, with SCENES.md's shading and camera, on
//! every backend. The bar: at least 99% of pixels within 8/255 per channel. On failure the
//! difference image and our picture are written to `target/tiler-test-output/` and named in
//! the message.

use std::path::Path;

use tiler::{Backend, Device, DeviceConfig};
use tiler_scene::Scene;
use tiler_scene::bench::{BenchScene, LayerOrder, build};
use tiler_scene::compare::{REFERENCE_MIN_FRACTION, REFERENCE_TOLERANCE, compare_rgba8, read_png, write_png};
use tiler_scene::gltf::load;
use tiler_scene::shading::{ModelSceneOptions, Shading, build_model_scene};

use crate::common::{assets_dir, output_dir, reference_dir};

/// Renders with `backend` and compares with `reference/<reference>.png`; returns our pixels.
fn render_and_compare(device: &mut Device, scene: &Scene, backend: Backend, reference: &Path) -> Vec<u8> {
    scene.render(device, backend).unwrap();
    let ours = device.read_rgba8(scene.color).unwrap();
    let (w, h, expected) = read_png(reference).unwrap();
    assert_eq!((w, h), (scene.width, scene.height), "{}: size", reference.display());
    let c = compare_rgba8(&ours, &expected, w, h, REFERENCE_TOLERANCE);
    let stem = reference.file_stem().unwrap().to_string_lossy();
    eprintln!(
        "{stem} ({backend}): {:.3}% of pixels within {}/255 (largest difference {})",
        100.0 * c.fraction_within(),
        c.tolerance,
        c.max_difference
    );
    if !c.passes(REFERENCE_MIN_FRACTION) {
        let dir = output_dir();
        let diff = dir.join(format!("{stem}_{backend}_diff.png"));
        let picture = dir.join(format!("{stem}_{backend}.png"));
        write_png(&diff, w, h, &c.difference_image).unwrap();
        write_png(&picture, w, h, &ours).unwrap();
        panic!(
            "{stem} on {backend}: only {:.3}% of pixels within {}/255 of {} (need {}%); difference image {}, our picture {}",
            100.0 * c.fraction_within(),
            c.tolerance,
            reference.display(),
            100.0 * REFERENCE_MIN_FRACTION,
            diff.display(),
            picture.display()
        );
    }
    ours
}

/// Every backend gives the reference picture, and the same picture as the others.
fn check_on_every_backend(reference: &Path, build_scene: impl Fn(&mut Device) -> Scene) {
    let mut first: Option<Vec<u8>> = None;
    for backend in Backend::ALL {
        let mut device = Device::new(DeviceConfig { backend, ..DeviceConfig::default() }).unwrap();
        let scene = build_scene(&mut device);
        let pixels = render_and_compare(&mut device, &scene, backend, reference);
        match &first {
            None => first = Some(pixels),
            Some(f) => assert!(*f == pixels, "{}: {backend} differs from tbr", reference.display()),
        }
    }
}

fn model(name: &str) {
    let (Some(assets), Some(references)) = (assets_dir(), reference_dir()) else { return };
    let path = assets.join(name).join(format!("{name}.gltf"));
    let model = load(&path, Shading::Scenes).unwrap();
    let options = ModelSceneOptions::new(960, 540);
    check_on_every_backend(&references.join(format!("{name}.png")), |device| {
        build_model_scene(device, &model, &options).unwrap().0
    });
}

fn bench(reference: &str, scene: BenchScene) {
    bench_with_samples(reference, scene, 1);
}

fn bench_with_samples(reference: &str, scene: BenchScene, samples: u32) {
    let Some(references) = reference_dir() else { return };
    if let BenchScene::Gltf { path } = &scene
        && !path.exists()
    {
        crate::common::skip(&format!("{} not found", path.display()));
        return;
    }
    check_on_every_backend(&references.join(format!("{reference}.png")), |device| {
        build(device, &scene, 1920, 1080, samples).unwrap().0
    });
}

macro_rules! model_tests {
    ($($test:ident: $name:literal),* $(,)?) => {$(
        #[test]
        fn $test() {
            model($name);
        }
    )*};
}

model_tests! {
    alpha_blend_mode_test: "AlphaBlendModeTest",
    avocado: "Avocado",
    box_: "Box",
    box_interleaved: "BoxInterleaved",
    box_textured: "BoxTextured",
    box_vertex_colors: "BoxVertexColors",
    damaged_helmet: "DamagedHelmet",
    duck: "Duck",
    flight_helmet: "FlightHelmet",
    reciprocating_saw: "ReciprocatingSaw",
    texture_coordinate_test: "TextureCoordinateTest",
    // SCENES.md shading samples every texture with REPEAT, as llvmpipe did: comparable.
    texture_settings_test: "TextureSettingsTest",
    triangle_without_indices: "TriangleWithoutIndices",
    two_sided_plane: "TwoSidedPlane",
    vc: "VC",
}

#[test]
fn bench_clear() {
    bench("bench_clear", BenchScene::Clear);
}

#[test]
fn bench_helmet() {
    let Some(assets) = assets_dir() else { return };
    bench("bench_helmet", BenchScene::Gltf { path: assets.join("DamagedHelmet/DamagedHelmet.gltf") });
}

/// Four samples per pixel, resolved (averaged) when the picture is read back: the frame's
/// resolve is not modelled yet, the picture is.
#[test]
fn bench_helmet_msaa4() {
    let Some(assets) = assets_dir() else { return };
    bench_with_samples(
        "bench_helmet_msaa4",
        BenchScene::Gltf { path: assets.join("DamagedHelmet/DamagedHelmet.gltf") },
        4,
    );
}

#[test]
fn bench_atrium() {
    let Some(assets) = assets_dir() else { return };
    bench("bench_atrium", BenchScene::Gltf { path: assets.join("Atrium/Atrium.gltf") });
}

/// The reference is the back-to-front order; front to back gives the same picture (the nearest
/// layer) for a 32nd of the shading, which keeps this test cheap. `textured.rs` checks that
/// both orders give identical images.
#[test]
fn bench_overdraw() {
    bench("bench_overdraw", BenchScene::Overdraw { layers: 32, order: LayerOrder::FrontToBack });
}

#[test]
fn bench_tris() {
    bench("bench_tris", BenchScene::Tris { count: 1_000_000, seed: 1 });
}
