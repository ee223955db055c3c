//! Textured rendering: the same image on every backend, tile size and thread count; texture
//! traffic counted through the cache model and independent of scheduling; front faces as GL
//! defines them; and both overdraw orders giving the same picture.

use glam::DVec3;
use serde_json::json;
use tiler::{Backend, Category, Device, DeviceConfig, PassReport};
use tiler_scene::bench::{BenchScene, LayerOrder, build};
use tiler_scene::camera::CameraChoice;
use tiler_scene::gltf::{Model, load};
use tiler_scene::shading::{CLEAR_RGBA8, CullPolicy, ModelSceneOptions, Shading, build_model_scene};

use crate::common::{base64, png, quad, scratch_dir, write_gltf};

/// The quad with a 256×256 texture of coloured stripes and dots, which the camera sees from far
/// enough that it is minified (mip levels 1 to 3 are read).
fn textured_quad(shading: Shading) -> Model {
    let dir = scratch_dir(&format!("textured_{}", shading.name()));
    let (mut json, bin) = quad();
    let mut texels = Vec::new();
    for y in 0..256u32 {
        for x in 0..256u32 {
            let stripe = if (x / 8 + y / 16) % 2 == 0 { 230 } else { 40 };
            texels.extend_from_slice(&[stripe, (x * 7 % 256) as u8, (y * 13 % 256) as u8, 255]);
        }
    }
    json["images"] = json!([{"uri": format!("data:image/png;base64,{}", base64(&png(256, 256, &texels)))}]);
    json["textures"] = json!([{"source": 0, "sampler": 0}]);
    json["samplers"] = json!([{"wrapS": 33648}]);
    json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": 0});
    // Tilted away, so the level of detail varies across the quad.
    json["nodes"][0]["rotation"] = json!([-0.5, 0.0, 0.0, 0.8660254]);
    let path = write_gltf(&dir, "textured.gltf", &json, Some(&bin));
    load(&path, shading).unwrap()
}

fn render(model: &Model, options: &ModelSceneOptions, config: DeviceConfig) -> (Vec<u8>, PassReport) {
    let backend = config.backend;
    let mut device = Device::new(config).unwrap();
    let (scene, _) = build_model_scene(&mut device, model, options).unwrap();
    let mut reports = scene.render(&mut device, backend).unwrap();
    (device.read_rgba8(scene.color).unwrap(), reports.pop().unwrap())
}

fn config(backend: Backend, tile: u32, threads: usize) -> DeviceConfig {
    DeviceConfig { backend, threads, ..DeviceConfig::default() }.with_tile_size(tile)
}

#[test]
fn textured_images_are_identical_everywhere_and_texture_traffic_is_deterministic() {
    for shading in [Shading::Scenes, Shading::Gltf] {
        let model = textured_quad(shading);
        let options = ModelSceneOptions {
            camera: CameraChoice::LookAt { eye: DVec3::new(0.3, 0.4, 6.0), target: DVec3::ZERO, fov_y_degrees: 40.0 },
            ..ModelSceneOptions::new(160, 96)
        };
        let (expected, base) = render(&model, &options, config(Backend::Tbr, 32, 1));
        let fetched = base.ledger.get(Category::TextureFetch);
        assert!(fetched > 0, "{shading:?}: no texture traffic");
        // A cache model, not texels touched: trilinear reads 8 texels of 4 bytes per fragment.
        let touched = (base.counters.fragments_shaded + base.counters.helper_invocations) * 8 * 4;
        assert!(fetched < touched / 4, "{shading:?}: {fetched} bytes fetched for {touched} bytes of texels read");
        // The quad is visible and textured: more than two colours.
        let mut colours: Vec<&[u8]> = expected.chunks_exact(4).collect();
        colours.sort();
        colours.dedup();
        assert!(colours.len() > 50, "{shading:?}: only {} colours", colours.len());

        for (backend, tile, threads) in [
            (Backend::Tbr, 32, 2),
            (Backend::Tbr, 32, 3),
            (Backend::Tbr, 8, 2),
            (Backend::Tbr, 64, 1),
            (Backend::Imr, 32, 1),
            (Backend::Imr, 32, 2),
        ] {
            let (pixels, report) = render(&model, &options, config(backend, tile, threads));
            assert!(
                pixels == expected,
                "{shading:?}: {backend}, {tile}-pixel tiles, {threads} threads: a different image"
            );
            if backend == Backend::Tbr && tile == 32 {
                assert_eq!(report.ledger.get(Category::TextureFetch), fetched, "{shading:?}: {threads} threads");
            }
            if backend == Backend::Imr {
                let (_, one_thread) = render(&model, &options, config(Backend::Imr, 32, 1));
                assert_eq!(report.ledger.get(Category::TextureFetch), one_thread.ledger.get(Category::TextureFetch));
            }
        }
    }
}

/// GL's counter-clockwise front faces stay front faces through the y flip: a single-sided quad
/// culled as glTF says is drawn from the front and not from behind.
#[test]
fn front_faces_are_counter_clockwise_as_in_gl() {
    let model = textured_quad(Shading::Scenes);
    let clear: Vec<u8> = CLEAR_RGBA8.to_vec();
    for (eye_z, visible) in [(6.0, true), (-6.0, false)] {
        let options = ModelSceneOptions {
            camera: CameraChoice::LookAt { eye: DVec3::new(0.0, 0.0, eye_z), target: DVec3::ZERO, fov_y_degrees: 40.0 },
            cull: Some(CullPolicy::Gltf),
            ..ModelSceneOptions::new(64, 48)
        };
        let (pixels, _) = render(&model, &options, config(Backend::Tbr, 32, 1));
        let drawn = pixels.chunks_exact(4).any(|p| p != clear.as_slice());
        assert_eq!(drawn, visible, "eye at z = {eye_z}");
    }
}

/// The picture's orientation: +y of the world is up in the image, +x is right (the camera
/// looks down −z).
#[test]
fn pictures_are_upright() {
    let dir = scratch_dir("upright");
    let (mut json, bin) = quad();
    // Shrink the quad to the upper-right quadrant.
    json["nodes"][0]["matrix"] =
        json!([0.5, 0.0, 0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.5, 0.5, 0.0, 1.0]);
    let model = load(&write_gltf(&dir, "upright.gltf", &json, Some(&bin)), Shading::Scenes).unwrap();
    let options = ModelSceneOptions {
        camera: CameraChoice::LookAt { eye: DVec3::new(0.0, 0.0, 3.0), target: DVec3::ZERO, fov_y_degrees: 60.0 },
        ..ModelSceneOptions::new(64, 64)
    };
    let (pixels, _) = render(&model, &options, config(Backend::Tbr, 32, 1));
    let at = |x: usize, y: usize| &pixels[(y * 64 + x) * 4..(y * 64 + x) * 4 + 4];
    assert_ne!(at(40, 24), CLEAR_RGBA8, "upper right");
    assert_eq!(at(24, 40), CLEAR_RGBA8, "lower left");
}

#[test]
fn both_overdraw_orders_give_the_same_picture() {
    let picture = |order| {
        let mut device = Device::new(config(Backend::Tbr, 16, 2)).unwrap();
        let (scene, _) = build(&mut device, &BenchScene::Overdraw { layers: 8, order }, 72, 40, 1).unwrap();
        let report = scene.render(&mut device, Backend::Tbr).unwrap();
        (device.read_rgba8(scene.color).unwrap(), report[0].counters.fragments_shaded)
    };
    let (back_to_front, shaded_b2f) = picture(LayerOrder::BackToFront);
    let (front_to_back, shaded_f2b) = picture(LayerOrder::FrontToBack);
    assert!(back_to_front == front_to_back);
    assert_eq!(shaded_b2f, 8 * 72 * 40);
    assert_eq!(shaded_f2b, 72 * 40);
}
