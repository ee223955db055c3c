//! The benchmark scenes' geometry against SCENES.md's CHECKSUMS: the same work as llvmpipe's.

use sha2::{Digest, Sha256};
use tiler_scene::bench::{LayerOrder, overdraw_vertices, tris_vertices};
use tiler_scene::gltf::load;
use tiler_scene::shading::Shading;

use crate::common::assets_dir;

fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}

#[test]
fn tris_checksums() {
    let vertices = tris_vertices(1_000_000, 1);
    assert_eq!(vertices.len(), 3_000_000);
    let positions: Vec<u8> = vertices.iter().flat_map(|v| v.position.iter().flat_map(|c| c.to_le_bytes())).collect();
    let colors: Vec<u8> = vertices.iter().flat_map(|v| v.color).collect();
    assert_eq!(sha256_hex(&positions), "ba4cb3bb0d38b158d8b3c04fa2ade23027cd49d548fdbf772ae635262e608127");
    assert_eq!(sha256_hex(&colors), "747a78e84a2fb06190d16d8a78a73d20d1e0bc35beaf016c357dead6135ea584");
}

#[test]
fn overdraw_checksum() {
    let vertices = overdraw_vertices(32, LayerOrder::BackToFront);
    let bytes: Vec<u8> = vertices.iter().flat_map(|v| v.iter().flat_map(|c| c.to_le_bytes())).collect();
    assert_eq!(sha256_hex(&bytes), "2702744ca8b7e15f86fa06d146c835298321fc045b668d747be673885b50f282");
}

#[test]
fn atrium_is_the_measured_file() {
    let Some(assets) = assets_dir() else { return };
    let dir = assets.join("Atrium");
    let bin = std::fs::read(dir.join("Atrium.bin")).unwrap();
    assert_eq!(bin.len(), 7_903_168);
    assert_eq!(sha256_hex(&bin), "ca2e18d361828b4d9a0fadc1e5b54e5612a24b3f02b45d81706d51aa4f31363a");
    // Every image of the file, decoded to RGBA8, in image order.
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(dir.join("Atrium.gltf")).unwrap()).unwrap();
    let images = json["images"].as_array().unwrap();
    assert_eq!(images.len(), 25);
    let mut hasher = Sha256::new();
    for image in images {
        let uri = image["uri"].as_str().unwrap();
        hasher.update(image::open(dir.join(uri)).unwrap().to_rgba8().as_raw());
    }
    let digest: String = hasher.finalize().iter().map(|b| format!("{b:02x}")).collect();
    assert_eq!(digest, "834a8020d961f562883c71ad66ca6c778bbbaa51bc9e2da052135424c8ca82b2");

    let model = load(&dir.join("Atrium.gltf"), Shading::Scenes).unwrap();
    assert_eq!(model.primitives.len(), 99);
    assert_eq!(model.triangles(), 257_120);
    assert_eq!(model.vertices(), 150_554);
    assert_eq!(model.materials.len(), 25 + 1, "the file's 25 and glTF's default");
    assert_eq!(model.textures_loaded, 24, "material 2's 4×4 texture is used by no primitive");
    // SCENES.md §3's camera figures.
    assert_eq!(model.min.to_array(), [-15.5, -1.0, -8.5]);
    assert_eq!(model.max.to_array(), [15.5, 12.3f32 as f64, 8.5]);
}
