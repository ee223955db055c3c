//! Hostile glTF files, generated here: files named outside the model's folder, special files,
//! sizes that overflow, hierarchies too deep or too wide, and the corpus the fuzzing below
//! starts from. Every case ends in `Ok` or a clear error, never a panic, and leaves its
//! inputs as they were.

use std::path::{Path, PathBuf};

use proptest::prelude::*;
use serde_json::{Value, json};
use tiler_scene::gltf::{MAX_DRAWN_PRIMITIVES, Model, load, load_from_slice};
use tiler_scene::shading::Shading;

use crate::common::{base64, glb, quad, scratch_dir};

/// Every file in `dir` (not recursing) and its bytes, to compare before and after.
fn snapshot(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.symlink_metadata().is_ok_and(|m| m.is_file()))
        .map(|p| {
            let bytes = std::fs::read(&p).unwrap();
            (p, bytes)
        })
        .collect();
    files.sort();
    files
}

/// Writes the quad edited by `edit` into a fresh folder `name` and loads it; checks the
/// folder's files are unchanged.
fn load_edited(name: &str, edit: impl FnOnce(&Path, &mut Value)) -> Result<Model, String> {
    let dir = scratch_dir(name);
    let (mut json, bin) = quad();
    edit(&dir, &mut json);
    // Compact JSON: the large cases stay under the loader's JSON limit.
    std::fs::write(dir.join("quad.bin"), &bin).unwrap();
    let path = dir.join(format!("{name}.gltf"));
    std::fs::write(&path, serde_json::to_vec(&json).unwrap()).unwrap();
    let before = snapshot(&dir);
    let result = load(&path, Shading::Scenes).map_err(|e| e.to_string());
    assert_eq!(snapshot(&dir), before, "{name}: loading changed its inputs");
    result
}

fn expect_error(name: &str, parts: &[&str], edit: impl FnOnce(&Path, &mut Value)) -> String {
    let e = match load_edited(name, edit) {
        Ok(_) => panic!("{name}: loaded, but should fail"),
        Err(e) => e,
    };
    for part in parts {
        assert!(e.contains(part), "{name}: expected '{part}' in: {e}");
    }
    e
}

#[test]
fn buffers_outside_the_folder_are_not_read() {
    let e = expect_error("abs_buffer", &["buffer 0", "absolute path"], |_, json| {
        json["buffers"][0]["uri"] = json!("/etc/passwd");
    });
    assert!(!e.contains("root:"), "the error must not echo the file: {e}");
    expect_error("dotdot_buffer", &["buffer 0", "outside"], |dir, json| {
        std::fs::write(dir.parent().unwrap().join("secret.bin"), [0u8; 140]).unwrap();
        json["buffers"][0]["uri"] = json!("../secret.bin");
    });
    // `%2e%2e` is `..` once percent-decoded.
    expect_error("encoded_dotdot", &["outside"], |_, json| {
        json["buffers"][0]["uri"] = json!("%2e%2e/secret.bin");
    });
    #[cfg(unix)]
    expect_error("link_out", &["buffer 0", "link to a file outside"], |dir, json| {
        std::os::unix::fs::symlink("/etc/passwd", dir.join("passwd.bin")).unwrap();
        json["buffers"][0]["uri"] = json!("passwd.bin");
    });
}

#[test]
fn images_outside_the_folder_are_not_read() {
    let model = load_edited("abs_image", |_, json| {
        json["images"] = json!([{"uri": "/etc/passwd"}]);
        json["textures"] = json!([{"source": 0}]);
        json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": 0});
    })
    .unwrap();
    assert_eq!(model.textures_loaded, 0);
    assert!(model.warnings.iter().any(|w| w.contains("image 0") && w.contains("absolute")), "{:?}", model.warnings);
    assert!(!model.inputs.iter().any(|p| p.starts_with("/etc")), "{:?}", model.inputs);
}

#[test]
fn the_files_read_are_listed() {
    let model = load_edited("inputs", |_, _| {}).unwrap();
    let names: Vec<String> =
        model.inputs.iter().map(|p| p.file_name().unwrap().to_string_lossy().into_owned()).collect();
    assert_eq!(names, ["inputs.gltf", "quad.bin"]);
}

#[test]
fn directories_are_refused() {
    expect_error("dir_buffer", &["buffer 0", "a directory, not a regular file"], |dir, json| {
        std::fs::create_dir(dir.join("sub")).unwrap();
        json["buffers"][0]["uri"] = json!("sub");
    });
    let dir = scratch_dir("dir_model");
    let e = load(&dir, Shading::Scenes).unwrap_err().to_string();
    assert!(e.contains("a directory"), "{e}");
}

#[cfg(unix)]
#[test]
fn devices_and_fifos_are_refused_without_blocking() {
    let e = load(Path::new("/dev/zero"), Shading::Scenes).unwrap_err().to_string();
    assert!(e.contains("/dev/zero") && e.contains("a device"), "{e}");
    expect_error("fifo_buffer", &["buffer 0", "a FIFO"], |dir, json| {
        let status = std::process::Command::new("mkfifo").arg(dir.join("pipe.bin")).status().unwrap();
        assert!(status.success());
        json["buffers"][0]["uri"] = json!("pipe.bin");
    });
    // /dev/zero reached through a link inside the folder, as a buffer and as an image.
    expect_error("zero_buffer", &["buffer 0", "outside"], |dir, json| {
        std::os::unix::fs::symlink("/dev/zero", dir.join("zero.bin")).unwrap();
        json["buffers"][0]["uri"] = json!("zero.bin");
    });
    let model = load_edited("zero_image", |dir, json| {
        std::os::unix::fs::symlink("/dev/zero", dir.join("zero.png")).unwrap();
        json["images"] = json!([{"uri": "zero.png"}]);
        json["textures"] = json!([{"source": 0}]);
        json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": 0});
    })
    .unwrap();
    assert!(model.warnings.iter().any(|w| w.contains("zero.png") && w.contains("outside")), "{:?}", model.warnings);
    let dir = scratch_dir("fifo_model");
    let fifo = dir.join("model.gltf");
    assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let e = load(&fifo, Shading::Scenes).unwrap_err().to_string();
    assert!(e.contains("a FIFO"), "{e}");
}

#[test]
fn counts_near_two_to_the_63_are_errors() {
    for (name, view, part) in [("huge_count_view", Some(0), "accessor 0"), ("huge_count_no_view", None, "accessors[0]")]
    {
        expect_error(name, &[part], |_, json| {
            json["accessors"][0]["count"] = json!(9_223_372_036_854_775_000u64);
            match view {
                Some(v) => json["accessors"][0]["bufferView"] = json!(v),
                None => {
                    json["accessors"][0].as_object_mut().unwrap().remove("bufferView");
                }
            }
        });
    }
    expect_error("huge_stride", &["accessor 0"], |_, json| {
        json["bufferViews"][0]["byteStride"] = json!(252);
        json["accessors"][0]["count"] = json!(4_000_000_000u64);
    });
}

#[test]
fn a_deep_hierarchy_loads_without_recursion() {
    let depth = 200_000;
    let model = load_edited("deep", |_, json| {
        let mut nodes: Vec<Value> = (0..depth).map(|i| json!({"children": [i + 1]})).collect();
        nodes.push(json!({"mesh": 0, "translation": [0.0, 0.0, 1.0]}));
        json["nodes"] = Value::Array(nodes);
    })
    .unwrap();
    assert_eq!(model.primitives.len(), 1);
    assert_eq!(model.primitives[0].vertices[0].position, [-1.0, -1.0, 1.0]);
}

#[test]
fn a_deep_cycle_is_found() {
    expect_error("deep_cycle", &["cycle"], |_, json| {
        let n = 50_000;
        let mut nodes: Vec<Value> = (0..n).map(|i| json!({"children": [(i + 1) % n]})).collect();
        nodes[0]["mesh"] = json!(0);
        json["nodes"] = Value::Array(nodes);
    });
}

#[test]
fn instancing_beyond_the_limits_is_an_error() {
    // One mesh on a million nodes.
    let wide = 1_000_000;
    expect_error("million_nodes", &["more than", &MAX_DRAWN_PRIMITIVES.to_string()], |_, json| {
        let mut nodes = vec![json!({"children": (1..=wide).collect::<Vec<u32>>()})];
        nodes.extend((0..wide).map(|_| json!({"mesh": 0})));
        json["nodes"] = Value::Array(nodes);
    });
    // 64 nodes, each naming the next twice: 2^64 paths.
    expect_error("doubling", &["node instances"], |_, json| {
        let mut nodes: Vec<Value> = (0..64).map(|i| json!({"children": [i + 1, i + 1]})).collect();
        nodes.push(json!({"mesh": 0}));
        json["nodes"] = Value::Array(nodes);
    });
}

#[test]
fn glb_with_a_bad_magic_is_named_so() {
    let dir = scratch_dir("bad_magic");
    let (mut json, bin) = quad();
    json["buffers"] = json!([{"byteLength": bin.len()}]);
    let mut bytes = glb(&json, &bin);
    bytes[..4].copy_from_slice(b"glTX");
    let path = dir.join("bad_magic.glb");
    std::fs::write(&path, &bytes).unwrap();
    let e = load(&path, Shading::Scenes).unwrap_err().to_string();
    assert!(e.contains("bad_magic.glb") && e.contains("bad magic"), "{e}");
    // Neither JSON nor GLB, whatever the name.
    let path = dir.join("noise.gltf");
    std::fs::write(&path, b"\x00\x01garbage").unwrap();
    let e = load(&path, Shading::Scenes).unwrap_err().to_string();
    assert!(e.contains("neither glTF JSON"), "{e}");
}

#[test]
fn extras_are_accepted() {
    let model = load_edited("extras", |_, json| {
        json["extras"] = json!({"author": "test", "tags": [1, 2]});
        json["nodes"][0]["extras"] = json!({"note": "x"});
        json["meshes"][0]["extras"] = json!(3);
        json["asset"]["extras"] = json!(null);
    })
    .unwrap();
    assert_eq!(model.triangles(), 2);
}

#[test]
fn only_gltf_2_is_read() {
    expect_error("version3", &["asset.version is \"3.0\"", "2.x"], |_, json| {
        json["asset"]["version"] = json!("3.0");
    });
    expect_error("version_junk", &["asset.version"], |_, json| {
        json["asset"]["version"] = json!("two");
    });
    expect_error("min_version", &["asset.minVersion"], |_, json| {
        json["asset"]["minVersion"] = json!("2.1");
    });
    assert!(load_edited("version21", |_, json| json["asset"]["version"] = json!("2.1")).is_ok());
}

/// The corpus of small hostile files the fuzzing starts from: the quad as glTF (its buffer a
/// data URI) and as GLB, and some of the cases above.
fn corpus() -> Vec<Vec<u8>> {
    let (json, bin) = quad();
    let mut inline = json.clone();
    inline["buffers"][0]["uri"] = json!(format!("data:application/octet-stream;base64,{}", base64(&bin)));
    let mut binary = json.clone();
    binary["buffers"] = json!([{"byteLength": bin.len()}]);
    let mut cyclic = inline.clone();
    cyclic["nodes"] = json!([{"mesh": 0, "children": [1]}, {"children": [0]}]);
    let mut huge = inline.clone();
    huge["accessors"][0]["count"] = json!(u64::MAX / 2);
    let mut camera = inline.clone();
    camera["cameras"] = json!([{"type": "perspective", "perspective": {"yfov": 1.0, "znear": 0.1}}]);
    camera["nodes"][0]["camera"] = json!(0);
    vec![
        serde_json::to_vec(&inline).unwrap(),
        glb(&binary, &bin),
        serde_json::to_vec(&cyclic).unwrap(),
        serde_json::to_vec(&huge).unwrap(),
        serde_json::to_vec(&camera).unwrap(),
    ]
}

/// Numbers and words a mutation writes over a JSON value: boundaries of every integer type,
/// and the names of glTF's objects, so indices point at objects that do and do not exist.
const WORDS: &[&str] = &[
    "0",
    "1",
    "-1",
    "3",
    "255",
    "65535",
    "4294967295",
    "4294967296",
    "9223372036854775807",
    "18446744073709551615",
    "1e308",
    "-0.0",
    "null",
    "true",
    "[]",
    "{}",
    "\"\"",
    "\"VEC3\"",
    "\"SCALAR\"",
    "\"MAT4\"",
    "5120",
    "5121",
    "5122",
    "5123",
    "5125",
    "5126",
    "\"data:,\"",
    "\"../x.bin\"",
    "\"/dev/zero\"",
    "\"2.0\"",
    "\"3.0\"",
    "[0, 0]",
    "{\"children\": [0]}",
];

/// Mutates `bytes`: overwrite a run of bytes, insert a word at a position, or truncate.
fn mutate(bytes: &[u8], op: u8, at: usize, len: usize, word: usize, fill: u8) -> Vec<u8> {
    let mut out = bytes.to_vec();
    let at = at % (out.len() + 1);
    match op % 4 {
        0 => {
            for b in out.iter_mut().skip(at).take(len % 9 + 1) {
                *b = fill;
            }
        }
        1 => {
            let w = WORDS[word % WORDS.len()].as_bytes();
            out.splice(at..at, w.iter().copied());
        }
        2 => {
            // Replace the number or word starting at `at` by a word.
            let end = out[at..].iter().position(|b| b",}] \n".contains(b)).map_or(out.len(), |e| at + e);
            let w = WORDS[word % WORDS.len()].as_bytes();
            out.splice(at..end, w.iter().copied());
        }
        _ => out.truncate(at),
    }
    out
}

/// Loads `bytes` as a `.gltf` and a `.glb` from memory, with a folder holding nothing: the
/// loader returns, whatever the bytes.
fn load_any(bytes: &[u8], dir: &Path) {
    for name in ["fuzz.gltf", "fuzz.glb"] {
        for shading in [Shading::Scenes, Shading::Gltf] {
            if let Ok(model) = load_from_slice(bytes, dir, Path::new(name), shading) {
                assert!(!model.primitives.is_empty());
                assert!(model.primitives.iter().all(|p| p.indices.iter().all(|&i| (i as usize) < p.vertices.len())));
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, failure_persistence: None, ..ProptestConfig::default() })]

    /// Mutated glTF JSON and GLB bytes load or fail; never a panic, never unbounded memory
    /// (the caps above bound what any file may cost).
    #[test]
    fn mutated_files_load_or_fail(
        seed in 0usize..5,
        mutations in prop::collection::vec((any::<u8>(), any::<usize>(), any::<usize>(), any::<usize>(), any::<u8>()), 1..4),
    ) {
        let dir = scratch_dir("fuzz_empty");
        let mut bytes = corpus()[seed].clone();
        for (op, at, len, word, fill) in mutations {
            bytes = mutate(&bytes, op, at, len, word, fill);
        }
        load_any(&bytes, &dir);
    }
}

#[test]
fn the_corpus_itself_loads_or_fails() {
    let dir = scratch_dir("corpus");
    for bytes in corpus() {
        load_any(&bytes, &dir);
    }
}
