//! libFuzzer target: any bytes as a `.gltf` and as a `.glb`, loaded from memory with an empty
//! folder beside them; loading must return `Ok` or `Err`, never panic, and stay within the
//! loader's caps. Seed the corpus with small models, e.g. those the tests in
//! `tests/scenes/hostile.rs` generate.

#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use tiler_scene::gltf::load_from_slice;
use tiler_scene::shading::Shading;

fuzz_target!(|data: &[u8]| {
    let dir = std::env::temp_dir().join("tiler-scene-fuzz-empty");
    let _ = std::fs::create_dir_all(&dir);
    for name in ["fuzz.gltf", "fuzz.glb"] {
        for shading in [Shading::Scenes, Shading::Gltf] {
            if let Ok(model) = load_from_slice(data, &dir, Path::new(name), shading) {
                assert!(!model.primitives.is_empty());
            }
        }
    }
});
