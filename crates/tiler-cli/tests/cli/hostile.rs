//! The `tiler` command pointed at hostile inputs and outputs: files named outside the input's
//! folder, special files, sizes that wrap or grow without bound, outputs that are inputs, and
//! unclear errors. Each case ends in a clear error and a non-zero exit (or, where the input is
//! legitimate, success), and leaves every input byte for byte as it was.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use super::{scratch, tiler, triangle_gltf};

/// Every regular file under `dir` and its bytes.
fn snapshot(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(d) = pending.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            let meta = path.symlink_metadata().unwrap();
            if meta.is_dir() {
                pending.push(path);
            } else if meta.is_file() {
                let bytes = std::fs::read(&path).unwrap();
                out.push((path, bytes));
            }
        }
    }
    out.sort();
    out
}

/// Runs `tiler args` and checks: it fails without hanging, stderr holds every `parts` and no
/// panic, and no file of `dir` changed (none written, none removed).
///
/// The time bound catches a command that waits forever (a FIFO opened for reading blocks until
/// a writer comes); it is generous because a loaded 2-core machine running the whole test
/// suite once stalled a refusal that takes milliseconds for 84 s. Where the time a case takes
/// is the point (huge inputs), `run_measured` bounds the child's own CPU time instead.
fn fails(dir: &Path, args: &[&str], parts: &[&str]) -> String {
    let before = snapshot(dir);
    let started = Instant::now();
    let out = tiler(args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(started.elapsed() < Duration::from_secs(300), "{args:?} hung: {:?}", started.elapsed());
    assert!(!out.status.success(), "{args:?} succeeded:\n{}", String::from_utf8_lossy(&out.stdout));
    assert!(out.status.code() == Some(1), "{args:?} did not exit with an error: {:?}\n{stderr}", out.status);
    assert!(!stderr.contains("panicked"), "{args:?} panicked:\n{stderr}");
    for part in parts {
        assert!(stderr.contains(part), "{args:?}: expected '{part}' in:\n{stderr}");
    }
    assert_eq!(snapshot(dir), before, "{args:?} changed its folder");
    stderr
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A trace of one frame: `data` as a buffer's data source, a clear, a swap.
fn trace(dir: &Path, name: &str, data: &str) -> PathBuf {
    let json = format!(
        r#"{{"format": "tiler-gl-trace", "version": 1, "config": {{"width": 32, "height": 32}},
        "frames": [{{"calls": [
            {{"call": "create_buffer", "id": 1, "data": {data}}},
            {{"call": "clear", "color": true, "depth": true, "stencil": true}},
            {{"call": "swap_buffers"}}]}}]}}"#
    );
    let path = dir.join(name);
    std::fs::write(&path, json).unwrap();
    path
}

/// A red 2×2 PNG.
fn png(path: &Path) {
    image::save_buffer(path, &[255, 0, 0, 255].repeat(4), 2, 2, image::ExtendedColorType::Rgba8).unwrap();
}

#[test]
fn files_outside_the_inputs_folder_are_not_read() {
    let root = scratch("outside");
    let dir = root.join("t");
    std::fs::create_dir(&dir).unwrap();
    std::fs::write(root.join("secret.bin"), b"SECRET-BYTES-1234").unwrap();
    let out_png = dir.join("out.png");
    for (name, data, rule) in [
        ("abs.json", r#"{"file": "/etc/passwd"}"#, "absolute path"),
        ("up.json", r#"{"file": "../secret.bin"}"#, "outside"),
        ("gltf-abs.json", r#"{"gltf": "/etc/model.gltf", "attribute": "POSITION"}"#, "absolute path"),
        ("gltf-up.json", r#"{"gltf": "../m.gltf", "attribute": "POSITION"}"#, "outside"),
    ] {
        let t = trace(&dir, name, data);
        let e = fails(&root, &["analyze", s(&t), "--png", s(&out_png)], &[name, rule]);
        assert!(!e.contains("SECRET") && !e.contains("root:"), "{e}");
    }
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(root.join("secret.bin"), dir.join("link.bin")).unwrap();
        let t = trace(&dir, "link.json", r#"{"file": "link.bin"}"#);
        fails(&root, &["analyze", s(&t), "--png", s(&out_png)], &["link to a file outside"]);
    }

    // A glTF's buffer: an error; its image: a warning, and the picture drawn untextured.
    let model = dir.join("m.gltf");
    let mut json: serde_json::Value = serde_json::from_slice(&std::fs::read(triangle_gltf(&dir)).unwrap()).unwrap();
    json["buffers"][0]["uri"] = "/etc/passwd".into();
    std::fs::write(&model, json.to_string()).unwrap();
    fails(&root, &["render", s(&model), "--size", "16x16", "-o", s(&out_png)], &["buffer 0", "absolute path"]);
}

#[test]
fn images_outside_the_folder_are_a_warning_not_a_read() {
    let dir = scratch("image-outside");
    let model = triangle_gltf(&dir);
    let mut json: serde_json::Value = serde_json::from_slice(&std::fs::read(&model).unwrap()).unwrap();
    json["images"] = serde_json::json!([{"uri": "../../../../../../etc/passwd"}]);
    json["textures"] = serde_json::json!([{"source": 0}]);
    json["materials"] = serde_json::json!([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]);
    json["meshes"][0]["primitives"][0]["material"] = 0.into();
    std::fs::write(&model, json.to_string()).unwrap();
    let out = tiler(&["render", s(&model), "--size", "16x16", "-o", s(&dir.join("o.png"))]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("image 0") && stderr.contains("outside"), "{stderr}");
}

#[cfg(unix)]
#[test]
fn special_files_are_refused_without_blocking() {
    let dir = scratch("special");
    let out_png = dir.join("out.png");
    fails(&dir, &["analyze", "/dev/zero"], &["/dev/zero", "a device"]);
    fails(&dir, &["render", "/dev/zero", "-o", s(&out_png)], &["/dev/zero", "a device"]);
    fails(&dir, &["render", "--device", "/dev/zero", "-o", s(&out_png)], &["/dev/zero", "a device"]);
    fails(&dir, &["diff", "/dev/zero", "/dev/zero"], &["a device"]);
    fails(&dir, &["analyze", s(&dir)], &["a directory"]);

    let fifo = dir.join("pipe");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    fails(&dir, &["analyze", s(&fifo)], &["a FIFO"]);
    fails(&dir, &["render", s(&fifo), "-o", s(&out_png)], &["a FIFO"]);
    let t = trace(&dir, "fifo.json", r#"{"file": "pipe"}"#);
    fails(&dir, &["analyze", s(&t)], &["pipe", "a FIFO"]);
    let t = trace(&dir, "gltf-fifo.json", r#"{"gltf": "pipe", "attribute": "POSITION"}"#);
    fails(&dir, &["analyze", s(&t)], &["pipe", "a FIFO"]);
    std::fs::create_dir(dir.join("sub")).unwrap();
    let t = trace(&dir, "dir.json", r#"{"file": "sub"}"#);
    fails(&dir, &["analyze", s(&t)], &["sub", "a directory"]);
}

#[test]
fn sizes_that_would_wrap_or_preallocate_are_errors() {
    let dir = scratch("sizes");
    fails(&dir, &["bench", "--scene", "clear", "--frames", "4294967295"], &["--frames must be from 1"]);
    fails(&dir, &["bench", "--scene", "clear", "--warmup", "18446744073709551615"], &["--warmup"]);
    let model = triangle_gltf(&dir);
    let mut json: serde_json::Value = serde_json::from_slice(&std::fs::read(&model).unwrap()).unwrap();
    json["accessors"][0]["count"] = 9_223_372_036_854_775_000u64.into();
    std::fs::write(&model, json.to_string()).unwrap();
    fails(&dir, &["render", s(&model), "--size", "16x16", "-o", s(&dir.join("o.png"))], &["accessor 0"]);
}

#[cfg(unix)]
#[test]
fn a_closed_pipe_ends_the_program_quietly() {
    use std::os::unix::process::ExitStatusExt;
    let dir = scratch("pipe");
    let t = trace(&dir, "t.json", r#"{"u8": [1, 2, 3]}"#);
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let out = Command::new(env!("CARGO_BIN_EXE_tiler"))
        .args(["analyze", s(&t)])
        .stdout(writer)
        .stderr(std::process::Stdio::piped())
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(out.status.signal(), Some(libc::SIGPIPE), "{:?}: {stderr}", out.status);
}

#[cfg(unix)]
#[test]
fn a_200_mb_trace_stays_under_2_gb() {
    let dir = scratch("big-trace");
    let path = dir.join("big.json");
    {
        use std::io::Write;
        let mut f = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
        write!(f, r#"{{"format": "tiler-gl-trace", "version": 1, "config": {{"width": 32, "height": 32}}, "frames": [{{"calls": ["#).unwrap();
        let numbers = "0,".repeat(1 << 20);
        for i in 0..100 {
            write!(f, r#"{{"call": "create_buffer", "id": {}, "data": {{"u8": [{numbers}0]}}}},"#, i + 1).unwrap();
        }
        write!(f, r#"{{"call": "swap_buffers"}}]}}]}}"#).unwrap();
    }
    assert!(std::fs::metadata(&path).unwrap().len() > 200 << 20);
    // Address space capped at 2 GiB too: an allocation past it would fail, and Rust abort.
    let mut command = Command::new("sh");
    command
        .args(["-c", &format!("ulimit -v 2097152 && exec '{}' analyze '{}'", env!("CARGO_BIN_EXE_tiler"), s(&path))]);
    let (status, cpu, max_resident, stderr) = run_measured(&mut command, &dir.join("stderr.txt"));
    assert!(status.success(), "{status:?}: {stderr}");
    // CPU time, not wall time: the machine running the tests may be busy with other work.
    assert!(cpu < Duration::from_secs(20), "took {cpu:?} of CPU");
    assert!(max_resident < 2 << 30, "{max_resident} bytes resident");
    std::fs::remove_file(&path).unwrap();
}

/// Runs `command` to its end: its exit status, CPU time (user and system), largest resident
/// set in bytes, and standard error.
#[cfg(unix)]
#[expect(clippy::zombie_processes, reason = "the child is waited for with wait4, which gives its resource usage")]
fn run_measured(command: &mut Command, stderr_file: &Path) -> (std::process::ExitStatus, Duration, u64, String) {
    use std::os::unix::process::ExitStatusExt;
    let child = command
        .stdout(std::process::Stdio::null())
        .stderr(std::fs::File::create(stderr_file).unwrap())
        .spawn()
        .unwrap();
    let mut status = 0;
    // SAFETY: `rusage` is plain data, valid when all zero.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: the pid is our child's, not yet waited for; both out-pointers are valid for the
    // call. `wait4` is the one call that gives one child's resource usage.
    let waited = unsafe { libc::wait4(child.id() as libc::pid_t, &mut status, 0, &mut usage) };
    assert_eq!(waited, child.id() as libc::pid_t);
    let time = |t: libc::timeval| Duration::new(t.tv_sec as u64, t.tv_usec as u32 * 1000);
    let cpu = time(usage.ru_utime) + time(usage.ru_stime);
    // ru_maxrss is in kilobytes on Linux.
    let max_resident = usage.ru_maxrss as u64 * 1024;
    let stderr = std::fs::read_to_string(stderr_file).unwrap();
    (std::process::ExitStatus::from_raw(status), cpu, max_resident, stderr)
}

#[test]
fn outputs_that_are_inputs_are_refused() {
    let dir = scratch("overwrite");
    let t = trace(&dir, "t.json", r#"{"u8": [1, 2, 3]}"#);
    fails(&dir, &["analyze", s(&t), "--report", s(&t)], &["--report", "also an input"]);
    // The same file spelled another way, and a side file of the trace.
    let spelled = dir.join(".").join("t.json");
    fails(&dir, &["analyze", s(&t), "--report", s(&spelled)], &["also an input"]);
    std::fs::write(dir.join("side.bin"), [0u8; 16]).unwrap();
    let t2 = trace(&dir, "t2.json", r#"{"file": "side.bin"}"#);
    fails(&dir, &["analyze", s(&t2), "--gl-report", s(&dir.join("side.bin"))], &["side.bin", "also an input"]);

    let a = dir.join("a.png");
    let reference = dir.join("ref.png");
    png(&a);
    png(&reference);
    fails(&dir, &["diff", s(&a), s(&reference), "--out", s(&reference)], &["--out", "also an input"]);
    fails(&dir, &["render", "--size", "16x16", "-o", s(&reference), "--compare", s(&reference)], &["also an input"]);

    // A model's texture as the output.
    let model_dir = dir.join("M");
    std::fs::create_dir(&model_dir).unwrap();
    let model = triangle_gltf(&model_dir);
    let mut json: serde_json::Value = serde_json::from_slice(&std::fs::read(&model).unwrap()).unwrap();
    png(&model_dir.join("texture.png"));
    json["images"] = serde_json::json!([{"uri": "texture.png"}]);
    json["textures"] = serde_json::json!([{"source": 0}]);
    json["materials"] = serde_json::json!([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]);
    json["meshes"][0]["primitives"][0]["material"] = 0.into();
    std::fs::write(&model, json.to_string()).unwrap();
    let texture = model_dir.join("texture.png");
    fails(&dir, &["render", s(&model), "--size", "16x16", "-o", s(&texture)], &["texture.png", "also an input"]);
    let o = dir.join("x.png");
    fails(&dir, &["render", s(&model), "--size", "16x16", "-o", s(&o), "--report", s(&model)], &["--report"]);
}

#[test]
fn outputs_are_checked_before_any_work() {
    let dir = scratch("output-checks");
    let jpg = dir.join("x.jpg");
    std::fs::write(&jpg, b"a good picture").unwrap();
    fails(&dir, &["render", "--size", "16x16", "-o", s(&jpg)], &["x.jpg", "PNG"]);
    let e = fails(&dir, &["render", "--size", "16x16", "-o", s(&dir)], &["is a directory"]);
    assert!(!e.contains("could not be determined"), "{e}");
    fails(&dir, &["render", "--size", "16x16", "-o", s(&dir.join("missing/x.png"))], &["does not exist"]);
    let o = dir.join("o.png");
    fails(&dir, &["render", "--size", "16x16", "-o", s(&o), "--heatmaps", s(&jpg)], &["--heatmaps", "is a file"]);
    fails(&dir, &["bench", "--scene", "clear", "--size", "16x16", "--out", s(&jpg)], &["--out", "is a file"]);
    let t = trace(&dir, "t.json", r#"{"u8": [1]}"#);
    fails(&dir, &["analyze", s(&t), "--png", s(&jpg)], &["PNG"]);
}

#[test]
fn a_successful_write_replaces_the_file_whole() {
    let dir = scratch("replace");
    let out = dir.join("o.png");
    std::fs::write(&out, b"old").unwrap();
    let run = tiler(&["render", "--size", "16x16", "-o", s(&out)]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    assert_eq!(image::open(&out).unwrap().width(), 16);
    let names: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names.len(), 1, "no temporary file is left: {names:?}");
}

#[test]
fn unclear_errors_are_clear() {
    let dir = scratch("clear-errors");
    let (json, _) = {
        let model = triangle_gltf(&dir);
        let json: serde_json::Value = serde_json::from_slice(&std::fs::read(&model).unwrap()).unwrap();
        (json, model)
    };
    let o = dir.join("o.png");
    // A GLB with a bad magic.
    let glb = dir.join("bad.glb");
    std::fs::write(&glb, b"glTX\x02\0\0\0\x20\0\0\0\x00\0\0\0JSON").unwrap();
    fails(&dir, &["render", s(&glb), "-o", s(&o)], &["bad.glb", "bad magic"]);
    // glTF 3.0.
    let mut v3 = json.clone();
    v3["asset"]["version"] = "3.0".into();
    let path = dir.join("v3.gltf");
    std::fs::write(&path, v3.to_string()).unwrap();
    fails(&dir, &["render", s(&path), "-o", s(&o)], &["asset.version is \"3.0\""]);
    // Extras are valid glTF.
    let mut extras = json.clone();
    extras["extras"] = serde_json::json!({"k": [1, 2]});
    extras["nodes"][0]["extras"] = serde_json::json!("x");
    let path = dir.join("extras.gltf");
    std::fs::write(&path, extras.to_string()).unwrap();
    let out = tiler(&["render", s(&path), "--size", "16x16", "-o", s(&o)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // A camera looking straight down.
    let out = tiler(&["render", s(&path), "--size", "16x16", "--camera", "0,5,0:0,0,0", "-o", s(&o)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // A benchmark scene asked for by name whose model is missing.
    let missing = dir.join("no-assets");
    fails(&dir, &["bench", "--scene", "helmet", "--assets", s(&missing), "--size", "16x16"], &["helmet", "not found"]);
}

#[cfg(unix)]
#[test]
fn huge_node_hierarchies_stay_bounded() {
    let dir = scratch("nodes");
    let model = triangle_gltf(&dir);
    let base: serde_json::Value = serde_json::from_slice(&std::fs::read(&model).unwrap()).unwrap();
    let o = dir.join("o.png");
    let command_for = |name: &str, nodes: serde_json::Value| {
        let mut json = base.clone();
        json["nodes"] = nodes;
        let path = dir.join(name);
        std::fs::write(&path, json.to_string()).unwrap();
        let mut command = Command::new(env!("CARGO_BIN_EXE_tiler"));
        command.args(["render", s(&path), "--size", "16x16", "-o", s(&o)]);
        run_measured(&mut command, &dir.join("stderr.txt"))
    };
    // One mesh on a million nodes: a clear error.
    let mut nodes = vec![serde_json::json!({"children": (1..=1_000_000u32).collect::<Vec<_>>()})];
    nodes.extend((0..1_000_000).map(|_| serde_json::json!({"mesh": 0})));
    let (status, cpu, resident, stderr) = command_for("wide.gltf", serde_json::Value::Array(nodes));
    assert_eq!(status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("more than") && !stderr.contains("panicked"), "{stderr}");
    assert!(cpu < Duration::from_secs(20) && resident < 2 << 30, "{cpu:?}, {resident} bytes");
    // 200,000 nodes deep: drawn.
    let mut nodes: Vec<serde_json::Value> = (1..=200_000u32).map(|i| serde_json::json!({"children": [i]})).collect();
    nodes.push(serde_json::json!({"mesh": 0}));
    let (status, cpu, resident, stderr) = command_for("deep.gltf", serde_json::Value::Array(nodes));
    assert!(status.success(), "{status:?}: {stderr}");
    assert!(cpu < Duration::from_secs(20) && resident < 2 << 30, "{cpu:?}, {resident} bytes");
    assert!(o.exists());
}
