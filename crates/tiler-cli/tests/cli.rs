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

/// `--msaa` takes the counts the core renders, 16 included, and names any other.
#[test]
fn msaa_takes_sixteen_samples_and_names_other_counts() {
    let dir = scratch("msaa16");
    let png = dir.join("out.png");
    let out = tiler(&["render", "--size", "64x48", "--msaa", "16", "-o", png.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(png.exists());
    for bad in ["3", "32", "many"] {
        let out = tiler(&["render", "--size", "64x48", "--msaa", bad]);
        assert!(!out.status.success(), "--msaa {bad}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains("--msaa") && stderr.contains(bad), "{stderr}");
    }
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
    let png = dir.join("last.png");
    let out = tiler(&[
        "analyze",
        trace.to_str().unwrap(),
        "--frames",
        frames.to_str().unwrap(),
        "--png",
        png.to_str().unwrap(),
    ]);
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
    // `--png`: the window's last picture, the last frame presented.
    assert_eq!(image::open(&png).unwrap().to_rgba8(), image.to_rgba8());

    // The capture on two devices: the shared report, one picture, a column per device.
    let json = dir.join("r.json");
    let out = tiler(&["analyze", trace.to_str().unwrap(), "--devices", "tbr,imr", "--report", json.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let doc: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(doc["frame_count"], 6);
    assert_eq!(doc["image"]["identical_across_columns"], true);
    assert_eq!(doc["columns"].as_array().unwrap().len(), 2);
}

fn example_trace(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tiler-gl/traces").join(name)
}

/// `tiler analyze --devices` gives the report `render` and `compare` give: the devices side
/// by side, the same picture on each, per-frame totals, every pass with its ops and why, and
/// each finding priced per device — none of the tiler advice on the immediate-mode GPU.
#[test]
fn analyze_replays_a_trace_on_several_devices_into_the_shared_report() {
    let dir = scratch("analyze-devices");
    let (json, html, maps) = (dir.join("r.json"), dir.join("r.html"), dir.join("maps"));
    let trace = example_trace("rebind-bad.json");
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let out = tiler(&[
        "analyze",
        &s(&trace),
        "--devices",
        "tbr,tbdr,imr",
        "--report",
        &s(&json),
        "--report",
        &s(&html),
        "--heatmaps",
        &s(&maps),
        "--fps",
        "30",
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}\n{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("nothing on imr"), "{stdout}");
    let doc: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(doc["schema"], "tiler-report/1");
    assert_eq!(doc["fps"], 30.0);
    assert_eq!(doc["image"]["identical_across_columns"], true);
    let labels: Vec<&str> = doc["columns"].as_array().unwrap().iter().map(|c| c["label"].as_str().unwrap()).collect();
    assert_eq!(labels, ["tbr", "tbdr", "imr"]);
    assert_eq!(doc["frame_count"], 3);
    // Per-frame totals add up to the run's.
    for column in doc["columns"].as_array().unwrap() {
        let frames = column["frames"].as_array().unwrap();
        assert_eq!(frames.len(), 3);
        let sum: u64 = frames.iter().map(|f| f["total_bytes"].as_u64().unwrap()).sum();
        assert_eq!(sum, column["frame"]["total_bytes"].as_u64().unwrap(), "{}", column["label"]);
        let passes: u64 = frames.iter().map(|f| f["passes"].as_u64().unwrap()).sum();
        assert_eq!(passes as usize, column["passes"].as_array().unwrap().len());
    }
    // The driver's passes: the rebound window's pass loads what the first pass stored.
    let passes = doc["passes"].as_array().unwrap();
    assert_eq!(passes.len(), 9);
    assert_eq!(passes[2]["target"], "the window");
    assert_eq!(passes[2]["attachments"][0]["load"], "load");
    // Priced per device: the rebind costs both tilers, not the immediate-mode GPU.
    let findings = doc["findings"].as_array().unwrap();
    assert!(!findings.is_empty());
    for f in findings {
        assert_eq!(f["id"], "framebuffer-rebound");
        let devices: Vec<&str> = f["costs"].as_array().unwrap().iter().map(|c| c["device"].as_str().unwrap()).collect();
        assert_eq!(devices, ["tbr", "tbdr"], "{f}");
    }
    let page = std::fs::read_to_string(&html).unwrap();
    for text in ["costs nothing on imr", "Frames", "<details>", "load op", "MB/run"] {
        assert!(page.contains(text), "the page shows '{text}'");
    }
    assert!(std::fs::read_dir(&maps).unwrap().count() > 0, "heat maps written");
}

/// A bad device or report name is an error naming it, and nothing is written.
#[test]
fn analyze_names_a_bad_option_and_writes_nothing() {
    let dir = scratch("analyze-bad");
    let trace = example_trace("clear-bad.json");
    let json = dir.join("r.json");
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let out = tiler(&["analyze", &s(&trace), "--devices", "tbr,no-such-gpu", "--report", &s(&json)]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains("no-such-gpu"), "{stderr}");
    let out = tiler(&["analyze", &s(&trace), "--report", &s(&dir.join("r.txt"))]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains("r.txt"), "{stderr}");
    let out = tiler(&["analyze", &s(&trace), "--device", "tbr", "--devices", "imr"]);
    assert!(!out.status.success());
    assert!(!json.exists());
}

/// A flat grid of `columns × rows` quads (two triangles each) in a `.gltf`.
fn grid_gltf(dir: &Path, columns: u32, rows: u32) -> PathBuf {
    let mut bin = Vec::new();
    let at = |i: u32, n: u32| -1.0 + 2.0 * i as f32 / n as f32;
    for row in 0..rows {
        for column in 0..columns {
            let (x0, x1, y0, y1) = (at(column, columns), at(column + 1, columns), at(row, rows), at(row + 1, rows));
            for [x, y] in [[x0, y0], [x1, y0], [x1, y1], [x0, y0], [x1, y1], [x0, y1]] {
                for c in [x, y, 0.0f32] {
                    bin.extend(c.to_le_bytes());
                }
            }
        }
    }
    let count = columns * rows * 6;
    let b64 = base64::Engine::encode(&base64::engine::general_purpose::STANDARD, &bin);
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scenes": [{{"nodes": [0]}}], "nodes": [{{"mesh": 0}}],
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
        "buffers": [{{"byteLength": {len}, "uri": "data:application/octet-stream;base64,{b64}"}}],
        "bufferViews": [{{"buffer": 0, "byteLength": {len}}}],
        "accessors": [{{"bufferView": 0, "componentType": 5126, "count": {count}, "type": "VEC3",
                        "min": [-1, -1, 0], "max": [1, 1, 0]}}]}}"#,
        len = bin.len()
    );
    let path = dir.join("grid.gltf");
    std::fs::write(&path, json).unwrap();
    path
}

/// `tiler render` runs the advisor on a glTF frame: a mesh of sub-pixel triangles earns
/// `micro-triangles`, priced on each backend (frame data on the tilers, only geometry on
/// immediate mode); a coarse mesh earns nothing.
#[test]
fn render_reports_findings_the_scene_earns() {
    let dir = scratch("render-findings");
    let findings = |columns: u32, rows: u32| {
        let gltf = grid_gltf(&dir, columns, rows);
        let json = dir.join("r.json");
        let png = dir.join("out.png");
        let out = tiler(&[
            "render",
            gltf.to_str().unwrap(),
            "--size",
            "64x48",
            "-o",
            png.to_str().unwrap(),
            "--report",
            json.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let doc: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        // The pass as the scene gave it: colour cleared and stored, depth cleared, not stored.
        let ops = &doc["passes"][0]["attachments"];
        assert_eq!((&ops[0]["load"], &ops[0]["store"]), (&"clear".into(), &"store".into()), "{ops}");
        assert_eq!(ops[1]["slot"], "depth");
        doc["findings"].as_array().unwrap().clone()
    };
    assert_eq!(findings(4, 3), Vec::<serde_json::Value>::new(), "a coarse grid earns nothing");
    let fine = findings(64, 48);
    assert_eq!(fine.len(), 1, "{fine:#?}");
    assert_eq!(fine[0]["id"], "micro-triangles");
    let costs = fine[0]["costs"].as_array().unwrap();
    let cost = |device: &str| costs.iter().find(|c| c["device"] == device).unwrap()["cost_bytes"].as_u64().unwrap();
    assert!(cost("tbr") > cost("imr") && cost("imr") > 0, "{costs:?}");
}

/// `tiler analyze --what-if` replays each fix and writes what it saved beside the estimate,
/// per device; on a device without transaction elimination the two agree.
#[test]
fn analyze_what_if_measures_each_fix() {
    let dir = scratch("analyze-what-if");
    let json = dir.join("r.json");
    let trace = example_trace("rebind-bad.json");
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let out = tiler(&["analyze", &s(&trace), "--devices", "tbdr,imr", "--what-if", "--report", &s(&json)]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}\n{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("what if"), "{stdout}");
    let doc: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let findings = doc["findings"].as_array().unwrap();
    assert_eq!(findings.len(), 3);
    for f in findings {
        let tried = f["what_if"].as_array().unwrap();
        assert_eq!(tried.len(), 1, "tbdr only: imr has no rebind finding");
        assert_eq!(tried[0]["device"], "tbdr");
        assert_eq!(tried[0]["applied"], true);
        assert_eq!(tried[0]["same_picture"], true);
        assert_eq!(tried[0]["measured_bytes"].as_i64().unwrap(), f["cost_bytes"].as_i64().unwrap());
    }
    let out = tiler(&["analyze", &s(&trace), "--what-if", "--gl-report", &s(&trace)]);
    assert!(!out.status.success(), "an input named as output is refused");
}

/// `--snapshot` writes the window after the calls it names, mid-frame included: the probe's
/// shadow scene draws its left half (call 97) and then its right half (call 101) before the
/// swap (call 103).
#[test]
fn analyze_snapshots_the_window_after_given_calls() {
    let dir = scratch("analyze-snapshot");
    let frames = dir.join("frames");
    let trace = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tiler-gl/tests/data/gles3-probe/shadow.trace");
    let trace = trace.to_str().unwrap();
    let out = tiler(&["analyze", trace, "--frames", frames.to_str().unwrap(), "--snapshot", "97,101"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let mut names: Vec<_> =
        std::fs::read_dir(&frames).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    names.sort();
    assert_eq!(names, ["call-00000097.png", "call-00000101.png", "frame-0000.png"]);
    let rgba = |name: &str| image::open(frames.join(name)).unwrap().to_rgba8();
    let (half, whole, presented) = (rgba("call-00000097.png"), rgba("call-00000101.png"), rgba("frame-0000.png"));
    assert_eq!((half.width(), half.height()), (64, 64));
    // The scene's blue is 0.3 wherever it drew; the clear is black.
    assert!(half.get_pixel(10, 32)[2] > 60 && half.get_pixel(50, 32)[2] == 0);
    assert!(whole.get_pixel(50, 32)[2] > 60);
    assert_eq!(whole, presented, "nothing is drawn between call 101 and the swap");

    // A call the capture does not have, and --snapshot without --frames, are errors.
    let out = tiler(&["analyze", trace, "--frames", frames.to_str().unwrap(), "--snapshot", "5000"]);
    assert!(!out.status.success());
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("--snapshot 5000"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = tiler(&["analyze", trace, "--snapshot", "97"]);
    assert!(!out.status.success());
}

/// With a framebuffer object bound, `--snapshot` writes that framebuffer's first colour
/// attachment, not the window: the probe's blit scene clears texture 1 (32×32, attached to
/// framebuffer 1) to (0.1, 0.1, 0.4) at call 35 and draws a triangle into it at call 44, while
/// the window is still black.
#[test]
fn analyze_snapshots_the_bound_framebuffer() {
    let dir = scratch("analyze-snapshot-fbo");
    let frames = dir.join("frames");
    let trace = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tiler-gl/tests/data/gles3-probe/blit.trace");
    let trace = trace.to_str().unwrap();
    let out = tiler(&["analyze", trace, "--frames", frames.to_str().unwrap(), "--snapshot", "35,44"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let rgba = |name: &str| image::open(frames.join(name)).unwrap().to_rgba8();
    let (cleared, drawn) = (rgba("call-00000035.png"), rgba("call-00000044.png"));
    assert_eq!((cleared.width(), cleared.height()), (32, 32), "the texture's size, not the window's");
    assert!(cleared.pixels().all(|p| p.0 == [26, 26, 102, 255]), "{:?}", cleared.get_pixel(0, 0));
    let changed = cleared.pixels().zip(drawn.pixels()).filter(|(a, b)| a != b).count();
    assert!(changed > 32 && changed < 32 * 32, "the triangle covers part of the texture: {changed} pixels");
}
