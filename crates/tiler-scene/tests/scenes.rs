//! Integration tests of scene loading and rendering, in one binary (link time matters on 2
//! cores): generated glTF files (good and broken), hostile files and fuzzing, every model of `../shared/assets`, the
//! llvmpipe reference images, the benchmark scenes' checksums, and textured rendering.

#[path = "scenes/assets.rs"]
mod assets;
#[path = "scenes/bench_scenes.rs"]
mod bench_scenes;
#[path = "scenes/common.rs"]
mod common;
#[path = "scenes/gltf_files.rs"]
mod gltf_files;
#[path = "scenes/hostile.rs"]
mod hostile;
#[path = "scenes/made_in_code.rs"]
mod made_in_code;
#[path = "scenes/reference.rs"]
mod reference;
#[path = "scenes/textured.rs"]
mod textured;
