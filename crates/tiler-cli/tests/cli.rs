//! The `tiler` command end to end: `render` of a glTF file and of the built-in scene, `bench`
//! with JSON output, and errors that name what is wrong.

#[path = "cli/hostile.rs"]
mod hostile;

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
    let b64 = base64::Engine::encode(&base64::engine::general_purpose::STANDARD, &bin);
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
    let reference = dir.join("reference.png");
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
        reference.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
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
        reference.to_str().unwrap(),
    ]);
    // The same picture drawn again matches its first drawing.
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
    // 64 triangles binned, each with its records and polygon-list entries in the frame data.
    assert_eq!(results[1]["primitives"], 64);
    assert!(results[1]["frame_data_bytes_per_primitive"].as_f64().unwrap() > 16.0);
    assert!(results[1]["frame_data_peak_host_bytes"].as_u64().unwrap() > 0);
    let out = tiler(&["bench", "--scene", "nothing"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown scene 'nothing'"));
}

#[test]
fn diff_holds_pictures_to_the_reference_tolerance() {
    let dir = scratch("diff");
    let write = |name: &str, pixels: &[[u8; 4]]| {
        let path = dir.join(name);
        image::save_buffer(&path, pixels.as_flattened(), pixels.len() as u32, 1, image::ExtendedColorType::Rgba8)
            .unwrap();
        path
    };
    let reference = write("reference.png", &[[100, 100, 100, 255]; 100]);
    let mut close = [[100, 100, 100, 255]; 100];
    close[0] = [150, 100, 100, 255];
    let close = write("close.png", &close);
    let far = write("far.png", &[[108, 91, 100, 255]; 100]);
    let diff_png = dir.join("far.diff.png");
    let s = |p: &Path| p.to_str().unwrap().to_string();

    // 99 of 100 pixels within 8/255: a match; 0 of 100: different, with the difference image.
    let out = tiler(&["diff", &s(&close), &s(&reference)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("99.000% of pixels within 8/255"));
    let out = tiler(&["diff", &s(&far), &s(&reference), "--out", &s(&diff_png)]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stdout).contains("largest difference 9"));
    assert!(String::from_utf8_lossy(&out.stderr).contains("far.png differs from"));
    assert_eq!(image::open(&diff_png).unwrap().to_rgba8().get_pixel(0, 0).0, [91, 0, 0, 255]);
    // A tolerance of 9 passes it; pictures of different sizes are an error that says so.
    assert!(tiler(&["diff", &s(&far), &s(&reference), "--tolerance", "9"]).status.success());
    let small = write("small.png", &[[0, 0, 0, 255]; 3]);
    let out = tiler(&["diff", &s(&small), &s(&reference)]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("is 3×1 but"));
    // The same colours with another alpha differ, unless only colour is compared.
    let translucent = write("translucent.png", &[[100, 100, 100, 0]; 100]);
    assert!(!tiler(&["diff", &s(&translucent), &s(&reference)]).status.success());
    let out = tiler(&["diff", &s(&translucent), &s(&reference), "--color-only"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("100.000% of pixels within 8/255"));
}

#[test]
fn bench_runs_each_simd_level_alike() {
    let run = |simd: &str| {
        let out = tiler(&[
            "bench", "--scene", "tris", "--size", "96x64", "--frames", "1", "--warmup", "0", "--json", "--simd", simd,
        ]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(report["simd"], simd);
        report["results"][0]["fragments_shaded"].as_u64().unwrap()
    };
    let baseline = run("baseline");
    assert!(baseline > 0);
    if tiler::SimdLevel::Avx2.is_available() {
        assert_eq!(run("avx2"), baseline);
    }
    let out = tiler(&["bench", "--simd", "neon"]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown SIMD level 'neon'"));
}

#[test]
fn analyze_a_capture_writes_every_presented_frame() {
    let Some(traces) = tiler_test_support::traces_dir() else { return };
    let dir = scratch("analyze-capture");
    let frames = dir.join("frames");
    let trace = traces.join("glmark2/pulsar.trace");
    let out = tiler(&["analyze", trace.to_str().unwrap(), "--frames", frames.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("pass"), "the passes are printed: {stdout}");
    let mut names: Vec<_> =
        std::fs::read_dir(&frames).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    names.sort();
    let expected: Vec<_> = (0..6).map(|i| format!("frame-{i:04}.png")).collect();
    assert_eq!(names, expected);
    let image = image::open(frames.join("frame-0005.png")).unwrap();
    assert_eq!((image.width(), image.height()), (800, 600));
}
