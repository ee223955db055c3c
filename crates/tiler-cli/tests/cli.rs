//! The `tiler` command end to end: `render` of a glTF file and of the built-in scene, `bench`
//! with JSON output, and errors that name what is wrong.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn tiler(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tiler")).args(args).output().expect("running tiler")
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// One triangle in a `.gltf` with its buffer as a data URI.
fn triangle_gltf(dir: &Path) -> PathBuf {
    let mut bin = Vec::new();
    for c in [-1.0f32, -1.0, 0.0, 1.0, -1.0, 0.0, 0.0, 1.0, 0.0] {
        bin.extend(c.to_le_bytes());
    }
    let b64: String = {
        const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        bin.chunks(3)
            .flat_map(|c| {
                let n = (c[0] as u32) << 16 | (*c.get(1).unwrap_or(&0) as u32) << 8 | *c.get(2).unwrap_or(&0) as u32;
                (0..4).map(move |i| if i <= c.len() { A[(n >> (18 - 6 * i) & 63) as usize] as char } else { '=' })
            })
            .collect()
    };
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scenes": [{{"nodes": [0]}}], "nodes": [{{"mesh": 0}}],
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
        "buffers": [{{"byteLength": 36, "uri": "data:application/octet-stream;base64,{b64}"}}],
        "bufferViews": [{{"buffer": 0, "byteLength": 36}}],
        "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                        "min": [-1, -1, 0], "max": [1, 1, 0]}}]}}"#
    );
    let path = dir.join("triangle.gltf");
    std::fs::write(&path, json).unwrap();
    path
}

#[test]
fn render_a_gltf_file() {
    let dir = scratch("render");
    let gltf = triangle_gltf(&dir);
    let png = dir.join("out.png");
    let out = tiler(&["render", gltf.to_str().unwrap(), "--size", "64x48", "-o", png.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}\n{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("triangle.gltf: 1 primitives"), "{stdout}");
    assert!(stdout.contains("loaded in") && stdout.contains("with tbr"), "{stdout}");
    assert!(stdout.contains("external memory") && stdout.contains("total"), "{stdout}");
    assert!(png.exists());
    let again = dir.join("again.png");
    let out = tiler(&[
        "render",
        gltf.to_str().unwrap(),
        "--size",
        "64x48",
        "--shading",
        "gltf",
        "--camera",
        "0,0,3:0,0,0:50",
        "-o",
        again.to_str().unwrap(),
        "--compare",
        again.to_str().unwrap(),
    ]);
    // The picture is written before it is compared: comparing with itself passes.
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("100.000% of pixels"));
}

#[test]
fn render_errors_name_the_file() {
    let out = tiler(&["render", "/nonexistent/missing.gltf", "--size", "32x32"]);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("missing.gltf") && stderr.contains("cannot read"), "{stderr}");
    let out = tiler(&["render", "--camera", "sideways"]);
    assert!(!out.status.success());
}

#[test]
fn bench_prints_json() {
    let out = tiler(&[
        "bench",
        "--scene",
        "clear,overdraw",
        "--size",
        "64x32",
        "--frames",
        "2",
        "--warmup",
        "0",
        "--threads",
        "1",
        "--json",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    let results = report["results"].as_array().unwrap();
    assert_eq!(results.len(), 2);
    assert_eq!(results[0]["scene"], "clear");
    assert_eq!(results[1]["scene"], "overdraw");
    for r in results {
        assert_eq!(r["times_ms"].as_array().unwrap().len(), 2);
        assert!(r["median_ms"].as_f64().unwrap() > 0.0 && r["fps"].as_f64().unwrap() > 0.0);
    }
    assert_eq!(results[1]["fragments_shaded"], 32 * 64 * 32);
    let out = tiler(&["bench", "--scene", "nothing"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown scene 'nothing'"));
}
