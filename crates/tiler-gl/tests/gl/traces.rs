//! The example traces, malformed traces, and recording.

use std::path::{Path, PathBuf};

use super::common::*;
use tiler::Category;
use tiler_gl::trace::Replay;
use tiler_gl::*;

fn traces() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("traces")
}

fn replay(name: &str) -> Replay {
    let trace = Trace::read(&traces().join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
    let limits = Limits { threads: Some(1), ..Limits::default() };
    trace.replay_with(limits).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Each pair, and the findings its bad form must have (and only those).
const PAIRS: [(&str, &[&str]); 15] = [
    ("clear", &["load-at-pass-start"]),
    ("rebind", &["framebuffer-rebound"]),
    ("invalidate", &["store-unread"]),
    ("readback", &["flush-mid-pass", "readback-stall"]),
    ("masked-clear", &["partial-clear"]),
    ("query", &["flush-mid-pass", "query-stall"]),
    ("tiled", &["preserved-swap"]),
    ("copy-on-write", &["copy-on-write"]),
    ("packed-depth-stencil", &["packed-depth-stencil-half"]),
    ("alpha-test", &["early-z-disabled"]),
    ("glsl-alpha-test", &["early-z-disabled"]),
    ("sort", &["unsorted-opaque"]),
    ("budget", &["micro-triangles", "incremental-render"]),
    ("msaa", &["msaa-stored"]),
    ("subpass", &["subpass-split"]),
];

/// The good form has no finding; the bad form has the pair's findings; the bad form costs
/// more than the good one by exactly what they report, and both draw the same picture.
#[test]
fn each_example_pair_differs_by_what_the_advisor_reports() {
    for (name, ids) in PAIRS {
        let good = replay(&format!("{name}-good.json"));
        let bad = replay(&format!("{name}-bad.json"));
        assert!(good.report.findings.is_empty(), "{name}-good: {:#?}", good.report.findings);
        for id in ids {
            assert!(bad.report.findings_with(id).count() > 0, "{name}-bad has no {id}");
        }
        for f in &bad.report.findings {
            assert!(ids.contains(&f.id.as_str()), "{name}-bad: unexpected {}: {}", f.id, f.message);
        }
        assert_eq!(good.context.surface_rgba8(), bad.context.surface_rgba8(), "{name}: the pictures differ");
        let bytes = |r: &Replay| r.report.totals.ledger.total();
        let fragments = |r: &Replay| r.report.totals.counters.fragments_shaded;
        let reported: u64 = bad.report.findings.iter().map(|f| f.cost_bytes.unwrap_or(0)).sum();
        let reported_fragments: u64 = bad.report.findings.iter().map(|f| f.cost_fragments.unwrap_or(0)).sum();
        if name == "budget" {
            // The fix changes the geometry: the good form's own (coarse) geometry and frame
            // data remain, on top of which the bad form pays exactly what is reported.
            let l = &good.report.totals.ledger;
            let coarse: u64 =
                [Category::VertexFetch, Category::IndexFetch, Category::FrameDataWrite, Category::FrameDataRead]
                    .iter()
                    .map(|c| l.get(*c))
                    .sum();
            assert_eq!(bytes(&bad) - bytes(&good), reported - coarse, "{name}");
        } else {
            assert_eq!(bytes(&bad) - bytes(&good), reported, "{name}: bytes");
            assert_eq!(fragments(&bad) - fragments(&good), reported_fragments, "{name}: fragments");
        }
    }
}

/// The msaa pair with 16 samples in its JSON (renderbuffers and render to texture): the good
/// form resolves in the tile; the bad form stores the samples and a blit reads them back,
/// which the advisor prices by hand arithmetic.
#[test]
fn the_msaa_pair_at_sixteen_samples() {
    let at_16 = |name: &str| {
        let json = std::fs::read_to_string(traces().join(name)).unwrap();
        assert!(json.contains("\"samples\": 4"), "{name}");
        let json = json.replace("\"samples\": 4", "\"samples\": 16");
        let trace = Trace::parse(&json, Some(&traces())).unwrap_or_else(|e| panic!("{name}: {e}"));
        trace.replay_with(Limits { threads: Some(1), ..Limits::default() }).unwrap_or_else(|e| panic!("{name}: {e}"))
    };
    let (good, bad) = (at_16("msaa-good.json"), at_16("msaa-bad.json"));
    for replay in [&good, &bad] {
        let samples = replay.report.passes().flat_map(|p| &p.attachments).map(|a| a.samples).max();
        assert_eq!(samples, Some(16));
    }
    assert!(good.report.findings.is_empty(), "{:#?}", good.report.findings);
    assert_eq!(good.context.surface_rgba8(), bad.context.surface_rgba8());
    // Per frame (3 frames): 128 × 96 pixels × 16 samples × 4 B = 786,432 B of colour stored,
    // and as many read back by the resolving blit; resolved in the tile, 1/16 of each.
    let reported: u64 = bad.report.findings.iter().map(|f| f.cost_bytes.unwrap_or(0)).sum();
    assert!(bad.report.findings.iter().all(|f| f.id == "msaa-stored"), "{:#?}", bad.report.findings);
    assert_eq!(reported, 3 * (786_432 + 786_432) * 15 / 16);
    assert_eq!(bad.report.totals.ledger.total() - good.report.totals.ledger.total(), reported);
}

/// A pass whose attachments do not fit the tile memory even in an 8×8 tile is reported (the
/// msaa pair's good form, 4 samples of RGBA8 colour and depth, on a device with 1 KiB of tile
/// memory: 8 × 8 × 4 × 8 = 2,048 bytes); with the default 32 KiB it fits and is not.
#[test]
fn attachments_beyond_the_tile_memory_are_reported() {
    let mut trace = Trace::read(&traces().join("msaa-good.json")).unwrap();
    let device = tiler::DeviceConfig { tile_memory_bytes: 1024, ..trace.config.device.clone().unwrap_or_default() };
    trace.config.device = Some(device);
    let small = trace.replay_with(Limits { threads: Some(1), ..Limits::default() }).unwrap();
    let overflows: Vec<_> = small.report.findings_with("tile-memory-overflow").collect();
    assert!(!overflows.is_empty(), "{:#?}", small.report.findings);
    let f = overflows[0];
    assert!(f.message.contains("the smallest tile, 8×8, needs 2048 B, more than the 1024 B"), "{}", f.message);
    let default = replay("msaa-good.json");
    assert_eq!(default.report.findings_with("tile-memory-overflow").count(), 0);
    // The picture is the same: tiler renders the pass in the oversized tile.
    assert_eq!(small.context.surface_rgba8(), default.context.surface_rgba8());
}

/// On an immediate-mode GPU the pairs about loads, stores, flushes and frame data cost the
/// same in both forms, and the advisor reports none of them there: what remains (stalls,
/// copies, shading order) still differs by exactly what it reports.
#[test]
fn on_an_immediate_mode_gpu_only_what_costs_it_is_reported() {
    let on_imr = |name: &str| {
        let mut trace = Trace::read(&traces().join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        trace.config.backend = tiler::Backend::Imr;
        trace.replay_with(Limits { threads: Some(1), ..Limits::default() }).unwrap_or_else(|e| panic!("{name}: {e}"))
    };
    let mut tiler_only_pairs = 0;
    for (name, ids) in PAIRS {
        let good = on_imr(&format!("{name}-good.json"));
        let bad = on_imr(&format!("{name}-bad.json"));
        for f in &bad.report.findings {
            let rule = RuleId::from_name(&f.id).unwrap();
            assert!(!rule.tiler_only(), "{name}-bad on imr: {} is tiler-only advice: {}", f.id, f.message);
        }
        assert_eq!(good.context.surface_rgba8(), bad.context.surface_rgba8(), "{name}: the pictures differ");
        let bytes = |r: &Replay| r.report.totals.ledger.total();
        let reported: u64 = bad.report.findings.iter().map(|f| f.cost_bytes.unwrap_or(0)).sum();
        if ids.iter().all(|id| RuleId::from_name(id).unwrap().tiler_only()) {
            // Nothing to report: and indeed the good form saves an IMR nothing.
            assert!(bad.report.findings.is_empty(), "{name}-bad on imr: {:#?}", bad.report.findings);
            assert!(bytes(&bad) <= bytes(&good), "{name} on imr: bad {} good {}", bytes(&bad), bytes(&good));
            tiler_only_pairs += 1;
        } else if name == "copy-on-write" {
            assert_eq!(bytes(&bad) - bytes(&good), reported, "{name} on imr");
        }
    }
    // clear, rebind, invalidate, tiled, packed-depth-stencil, msaa, subpass.
    assert_eq!(tiler_only_pairs, 7, "pairs with only tiler advice");
}

/// `tiler analyze`'s text names the findings.
#[test]
fn the_text_report_names_the_findings() {
    let bad = replay("rebind-bad.json");
    let text = text_report(&bad.report);
    assert!(text.contains("framebuffer-rebound"), "{text}");
    assert!(text.contains("000 §23.5"), "{text}");
    let good = replay("gltf-mesh.json");
    assert!(text_report(&good.report).contains("no findings"));
    let json = serde_json::to_value(&bad.report).unwrap();
    assert_eq!(json["format"], "tiler-gl-report");
    assert_eq!(json["findings"][0]["id"], "framebuffer-rebound");
    assert!(json["frames"][0]["passes"][2]["attachments"][0]["load"] == "load");
}

/// The text's first line counts the frames, and says how many were presented when calls
/// follow the last swap (a frame `--frames` does not write).
#[test]
fn the_text_report_counts_presented_frames() {
    let trace = |last_swaps: bool| {
        let last = if last_swaps { r#", {"call": "swap_buffers"}"# } else { "" };
        let json = format!(
            r#"{{"format": "tiler-gl-trace", "version": 1, "config": {{"width": 16, "height": 16}},
                "frames": [{{"calls": [{{"call": "clear", "color": true}}, {{"call": "swap_buffers"}}], "repeat": 2}},
                           {{"calls": [{{"call": "clear", "color": true}}{last}]}}]}}"#
        );
        let replay =
            Trace::parse(&json, None).unwrap().replay_with(Limits { threads: Some(1), ..Limits::default() }).unwrap();
        text_report(&replay.report).lines().next().unwrap().to_string()
    };
    assert!(trace(true).starts_with("3 frame(s), "), "{}", trace(true));
    assert!(trace(false).starts_with("3 frame(s), 2 presented, "), "{}", trace(false));
}

/// Bad traces get an error naming the frame, the call and the problem.
#[test]
fn malformed_traces_are_errors_that_say_where() {
    let frame = |calls: &str| {
        format!(
            r#"{{"format": "tiler-gl-trace", "version": 1, "config": {{"width": 16, "height": 16}},
                "frames": [{{"calls": [{calls}]}}]}}"#
        )
    };
    let cases: Vec<(String, &str)> = vec![
        ("{".to_string(), "trace: invalid JSON"),
        (r#"{"format": "x", "version": 1}"#.to_string(), "\"format\""),
        (r#"{"format": "tiler-gl-trace", "version": 2}"#.to_string(), "version 1"),
        (
            r#"{"format": "tiler-gl-trace", "version": 1, "config": {"width": 8}}"#.to_string(),
            "config: missing field `height`",
        ),
        (frame(r#"{"call": "draw_quads"}"#), "frame 0, call 0: draw_quads: unknown variant `draw_quads`"),
        (
            frame(r#"{"call": "flush"}, {"call": "viewport", "x": "a", "y": 0, "width": 1, "height": 1}"#),
            "frame 0, call 1: viewport: invalid type",
        ),
        (
            frame(r#"{"call": "draw_arrays", "mode": "triangles"}"#),
            "frame 0, call 0: draw_arrays: missing field `first`",
        ),
        (frame(r#"{"call": "flush", "now": true}"#), "frame 0, call 0: flush: unknown field `now`"),
        (
            frame(r#"{"call": "scissor", "x": 0, "y": 0, "width": 1, "height": 1, "z": 0}"#),
            "scissor: unknown field `z`",
        ),
        (frame(r#"{"call": "use_program", "id": 7}"#), "frame 0, call 0: use_program: program 7 does not exist"),
        (
            frame(r#"{"call": "draw_arrays", "mode": "triangles", "first": 0, "count": 3}"#),
            "frame 0, call 0: draw_arrays: no program is in use",
        ),
        (
            frame(
                r#"{"call": "create_program", "id": 1, "program": "solid"}, {"call": "use_program", "id": 1},
                {"call": "create_framebuffer", "id": 1}, {"call": "bind_framebuffer", "framebuffer": 1},
                {"call": "draw_arrays", "mode": "triangles", "first": 0, "count": 3}"#,
            ),
            "frame 0, call 4: draw_arrays: framebuffer 1 is incomplete: it has no attachments",
        ),
        (
            frame(r#"{"call": "bind_framebuffer", "framebuffer": 3}"#),
            "call 0: bind_framebuffer: framebuffer 3 does not exist",
        ),
        (
            frame(
                r#"{"call": "create_buffer", "id": 1, "data": {"f32": [0, 0, 0]}}, {"call": "create_program", "id": 1, "program": "solid"},
                {"call": "use_program", "id": 1}, {"call": "vertex_attrib_pointer", "index": 0, "buffer": 1, "size": 3, "type": "float"},
                {"call": "enable_vertex_attrib", "index": 0}, {"call": "draw_arrays", "mode": "triangles", "first": 0, "count": 3}"#,
            ),
            "frame 0, call 5: draw_arrays: attribute 0 (position) of vertex 2 ends at byte 36, past the end of its data (12 bytes)",
        ),
        (frame(r#"{"call": "swap_buffers"}, {"call": "flush"}"#), "frame 0, call 0: swap_buffers ends a frame"),
        (
            r#"{"format": "tiler-gl-trace", "version": 1, "config": {"width": 16, "height": 16},
                "frames": [{"calls": [{"call": "flush"}]}, {"calls": []}]}"#
                .to_string(),
            "frame 0: a frame must end with swap_buffers",
        ),
        (frame(r#"{"call": "create_buffer", "id": 1, "data": {"f32": [1], "u8": [1]}}"#), "exactly one of"),
        (frame(r#"{"call": "create_buffer", "id": 1, "data": {"base64": "AB$="}}"#), "invalid base64 character"),
        (frame(r#"{"call": "create_buffer", "id": 1, "data": {"file": "x.bin"}}"#), "relative path"),
        (
            frame(r#"{"call": "create_texture", "id": 1, "width": 16384, "height": 16384, "format": "rgba32f"}"#),
            "frame 0, call 0: create_texture: image size 16384×16384 is invalid",
        ),
        (
            frame(r#"{"call": "create_texture", "id": 1, "width": 8192, "height": 8192, "format": "rgba8"}"#),
            "above its memory limit",
        ),
        (
            frame(
                r#"{"call": "create_program", "id": 1, "program": "solid"}, {"call": "use_program", "id": 1},
                {"call": "uniform", "name": "color", "value": {"float": 1e39}}"#,
            ),
            "frame 0, call 2: uniform: uniform 'color' is a vec4, not a float",
        ),
        (
            frame(
                r#"{"call": "create_program", "id": 1, "program": "solid"}, {"call": "use_program", "id": 1},
                {"call": "uniform", "name": "color", "value": {"vec4": [1e39, 0, 0, 1]}}"#,
            ),
            "non-finite",
        ),
        (
            r#"{"format": "tiler-gl-trace", "version": 1, "config": {"width": 16, "height": 16},
                "frames": [{"repeat": 0, "calls": [{"call": "swap_buffers"}]}]}"#
                .to_string(),
            "\"repeat\" is 0",
        ),
        (frame(r#"{"call": "end_tiling"}"#), "frame 0, call 0: end_tiling: end_tiling without start_tiling"),
        (frame(r#"{"call": "query_result", "id": 1}"#), "query 1 does not exist"),
        (
            // A NaN position (0x7fc00000) is found when the pass renders, and named.
            frame(
                r#"{"call": "create_buffer", "id": 1, "data": {"base64": "AADAfwAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAgD8AAAAA"}},
                {"call": "create_program", "id": 1, "program": "solid"}, {"call": "use_program", "id": 1},
                {"call": "vertex_attrib_pointer", "index": 0, "buffer": 1, "size": 3, "type": "float"},
                {"call": "enable_vertex_attrib", "index": 0}, {"call": "draw_arrays", "mode": "triangles", "first": 0, "count": 3},
                {"call": "swap_buffers"}"#,
            ),
            "frame 0, call 6: swap_buffers: the render pass of framebuffer 0 begun at frame 0, call 0 could not be \
             rendered (the draw recorded at frame 0, call 5): draw 0, vertex 0: the vertex shader wrote a non-finite position",
        ),
    ];
    let limits = Limits { memory_limit: Some(64 << 20), threads: Some(1), ..Limits::default() };
    for (json, expected) in cases {
        let error = match Trace::parse_with(&json, None, limits) {
            Err(e) => e,
            Ok(trace) => match trace.replay_with(limits) {
                Err(e) => e,
                Ok(_) => panic!("no error for {json}"),
            },
        };
        let text = error.to_string();
        assert!(text.contains(expected), "expected {expected:?} in {text:?}");
    }
}

/// A program using most of the API, recording.
fn recorded_program() -> Context {
    let mut gl = Context::new_recording(config(48, 40)).unwrap();
    geometry(&mut gl, 1, ProgramKind::Solid, &quad(-0.8, -0.8, 0.5, 0.6, 0.2));
    framebuffer(&mut gl, 2, 48, 40);
    let texels: Vec<u8> = (0..8 * 8 * 4).map(|i| (i * 7 % 256) as u8).collect();
    c(
        &mut gl,
        Call::CreateTexture {
            id: 3,
            width: 8,
            height: 8,
            format: TextureFormat::Rgba8,
            data: Some(Bytes::from(texels)),
            transient: false,
        },
    );
    c(
        &mut gl,
        Call::TexParameters { id: 3, filter: Filter::Linear, wrap: Wrap::Repeat, mag_filter: None, wrap_t: None },
    );
    c(&mut gl, Call::CreateProgram { id: 4, program: ProgramKind::Textured.into() });
    c(&mut gl, Call::CreateProgram { id: 5, program: ProgramKind::VertexColor.into() });
    c(&mut gl, Call::CreateQuery { id: 1 });
    for frame in 0..3 {
        bind(&mut gl, 2);
        c(&mut gl, Call::ClearColor { rgba: [0.1, 0.2, 0.3, 1.0] });
        clear_all(&mut gl);
        c(&mut gl, Call::Enable { cap: Capability::DepthTest });
        bind_geometry(&mut gl, 1);
        set_color(&mut gl, [0.9, 0.5, 0.1, 1.0]);
        c(&mut gl, Call::BeginQuery { id: 1 });
        draw(&mut gl, 6);
        c(&mut gl, Call::EndQuery);
        // A client-side array with vertex colours, blended.
        c(&mut gl, Call::UseProgram { id: 5 });
        let v: Vec<[f32; 7]> = vec![
            [-1.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.5],
            [1.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.5],
            [0.0, 1.0 - 0.3 * frame as f32, 0.0, 0.0, 0.0, 1.0, 0.5],
        ];
        let data = Bytes::from_slice(&v);
        c(
            &mut gl,
            Call::VertexAttribArray {
                index: 0,
                size: 3,
                component: ComponentType::Float,
                normalized: false,
                stride: 28,
                data: data.clone(),
            },
        );
        let colors: Vec<u8> = data.iter().copied().skip(12).collect();
        c(
            &mut gl,
            Call::VertexAttribArray {
                index: 1,
                size: 4,
                component: ComponentType::Float,
                normalized: false,
                stride: 28,
                data: Bytes::from(colors),
            },
        );
        c(&mut gl, Call::EnableVertexAttrib { index: 1 });
        c(&mut gl, Call::Enable { cap: Capability::Blend });
        c(
            &mut gl,
            Call::BlendFunc {
                src: tiler::BlendFactor::SrcAlpha,
                dst: tiler::BlendFactor::OneMinusSrcAlpha,
                src_alpha: None,
                dst_alpha: None,
            },
        );
        draw(&mut gl, 3);
        c(&mut gl, Call::Disable { cap: Capability::Blend });
        c(&mut gl, Call::DisableVertexAttrib { index: 1 });
        c(&mut gl, Call::Invalidate { attachments: vec![AttachmentPoint::DepthStencil] });
        bind(&mut gl, 0);
        clear_all(&mut gl);
        // The render target and the uploaded texture, on a strip.
        c(&mut gl, Call::UseProgram { id: 4 });
        let uv: Vec<[f32; 4]> =
            vec![[-1.0, -1.0, 0.0, 0.0], [1.0, -1.0, 2.0, 0.0], [-1.0, 0.0, 0.0, 1.0], [1.0, 0.0, 2.0, 1.0]];
        c(&mut gl, Call::CreateBuffer { id: 10 + frame, data: Bytes::from_slice(&uv) });
        for (index, offset) in [(0, 0), (1, 8)] {
            c(
                &mut gl,
                Call::VertexAttribPointer {
                    index,
                    buffer: 10 + frame,
                    size: 2,
                    component: ComponentType::Float,
                    normalized: false,
                    stride: 16,
                    offset,
                },
            );
            c(&mut gl, Call::EnableVertexAttrib { index });
        }
        c(&mut gl, Call::BindTexture { unit: 0, texture: 3 });
        c(&mut gl, Call::DrawArrays { mode: Mode::TriangleStrip, first: 0, count: 4 });
        c(&mut gl, Call::BindTexture { unit: 0, texture: 2 });
        c(&mut gl, Call::Viewport { x: 0, y: 20, width: 48, height: 20 });
        c(&mut gl, Call::DrawArrays { mode: Mode::TriangleStrip, first: 0, count: 4 });
        c(&mut gl, Call::Viewport { x: 0, y: 0, width: 48, height: 40 });
        c(&mut gl, Call::DisableVertexAttrib { index: 1 });
        c(&mut gl, Call::BufferSubData { id: 1, offset: 0, data: Bytes::from_slice(&[[-0.9f32, -0.9, 0.2]]) });
        c(&mut gl, Call::ReadPixels { x: 0, y: 0, width: 4, height: 4 });
        c(&mut gl, Call::QueryResult { id: 1 });
        swap(&mut gl);
    }
    gl
}

/// Recording a run and replaying its trace reproduces the images and the counters exactly,
/// with data inline or in a side file.
#[test]
fn recording_and_replaying_reproduces_the_run() {
    let mut gl = recorded_program();
    let trace = gl.recording().unwrap();
    let image = gl.surface_rgba8();
    let texture = gl.device().image_data(gl.texture_image(2).unwrap()).unwrap().to_vec();
    let report = serde_json::to_value(gl.end().unwrap()).unwrap();
    assert!(!report["findings"].as_array().unwrap().is_empty(), "the program is not a model of good practice");

    let inline = trace.to_json();
    let parsed = Trace::parse(&inline, None).unwrap();
    assert_eq!(parsed, trace);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("gl-record");
    std::fs::create_dir_all(&dir).unwrap();
    let (json, blob) = trace.to_json_with_side_file("recorded.bin");
    std::fs::write(dir.join("recorded.json"), json).unwrap();
    std::fs::write(dir.join("recorded.bin"), blob).unwrap();
    let side = Trace::read(&dir.join("recorded.json")).unwrap();
    assert_eq!(side, trace);

    for t in [parsed, side] {
        let replay = t.replay().unwrap();
        assert_eq!(replay.context.surface_rgba8(), image);
        let t2 = replay.context.device().image_data(replay.context.texture_image(2).unwrap()).unwrap();
        assert_eq!(t2, &texture[..]);
        assert_eq!(serde_json::to_value(&replay.report).unwrap(), report, "the counters and ledgers are identical");
    }
}

/// A GLB container works as a data source too.
#[test]
fn glb_accessors_are_read() {
    let positions: Vec<u8> =
        [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]].iter().flatten().flat_map(|f| f.to_le_bytes()).collect();
    let indices: Vec<u8> = vec![0, 1, 2, 0];
    let mut bin = positions.clone();
    bin.extend(&indices);
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "buffers": [{{"byteLength": {}}}],
            "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 36}}, {{"buffer": 0, "byteOffset": 36, "byteLength": 3}}],
            "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}},
                          {{"bufferView": 1, "componentType": 5121, "count": 3, "type": "SCALAR"}}],
            "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1}}]}}]}}  "#,
        bin.len()
    );
    let mut glb = Vec::new();
    let total = 12 + 8 + json.len() + 8 + bin.len();
    glb.extend(0x4654_6c67u32.to_le_bytes());
    glb.extend(2u32.to_le_bytes());
    glb.extend((total as u32).to_le_bytes());
    glb.extend((json.len() as u32).to_le_bytes());
    glb.extend(0x4e4f_534au32.to_le_bytes());
    glb.extend(json.as_bytes());
    glb.extend((bin.len() as u32).to_le_bytes());
    glb.extend(0x004e_4942u32.to_le_bytes());
    glb.extend(&bin);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("gl-glb");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("t.glb"), glb).unwrap();
    let trace = r#"{"format": "tiler-gl-trace", "version": 1, "config": {"width": 8, "height": 8}, "frames": [{"calls": [
            {"call": "create_buffer", "id": 1, "data": {"gltf": "t.glb", "attribute": "POSITION"}},
            {"call": "create_buffer", "id": 2, "data": {"gltf": "t.glb", "attribute": "indices"}}]}]}"#;
    let t = Trace::parse(trace, Some(&dir)).unwrap();
    let Call::CreateBuffer { data, .. } = &t.frames[0].calls[0] else { panic!() };
    assert_eq!(data.as_slice(), &positions[..]);
    let Call::CreateBuffer { data, .. } = &t.frames[0].calls[1] else { panic!() };
    assert_eq!(data.as_slice(), &[0, 0, 1, 0, 2, 0], "u8 indices widened to u16");
}

/// Every backend draws the same pictures from the same trace; only the costs differ.
#[test]
fn every_backend_draws_the_same_pictures() {
    for (name, _) in PAIRS.iter().filter(|(n, _)| *n != "budget") {
        let trace = Trace::read(&traces().join(format!("{name}-bad.json"))).unwrap();
        let mut images = Vec::new();
        for backend in [tiler::Backend::Tbr, tiler::Backend::Tbdr, tiler::Backend::Imr] {
            let mut t = trace.clone();
            t.config.backend = backend;
            let replay = t.replay_with(Limits { threads: Some(1), ..Limits::default() }).unwrap();
            images.push(replay.context.surface_rgba8());
        }
        assert!(images.windows(2).all(|w| w[0] == w[1]), "{name}: the backends disagree");
    }
}

/// `--what-if`, on every built-in device preset: the bad form of each pair whose advice is an
/// edit of the calls, with every fix applied, costs what the good form costs and presents the
/// same pictures; each fix alone, replayed by `what_if::prove`, saves exactly its finding's
/// estimate on that device (counting the stores transaction elimination skipped, which depend
/// on the pictures: `measured_bytes_before_elimination`) and changes no presented picture.
#[test]
fn each_fix_applied_to_the_bad_form_costs_what_the_good_form_costs() {
    use tiler_gl::advisor::what_if::{self, Fixer};
    let limits = Limits { threads: Some(1), ..Limits::default() };
    let mut table = String::new();
    for preset in tiler::DevicePreset::builtins() {
        for name in ["clear", "rebind", "invalidate", "readback", "sort", "masked-clear", "query", "msaa"] {
            let on_device = |file: &str| {
                let mut trace = Trace::read(&traces().join(file)).unwrap();
                trace.config = ContextConfig { digest_presented: true, ..trace.config.on_device(&preset.device) };
                trace
            };
            let trace = on_device(&format!("{name}-bad.json"));
            let bad = trace.replay_with(limits).unwrap();
            let good = on_device(&format!("{name}-good.json")).replay_with(limits).unwrap();
            let config = bad.context.config().clone();
            let picture = bad.context.surface_rgba8();
            let run = what_if::Run { config: &config, report: &bad.report, picture: &picture };
            let proven = what_if::prove(&trace, &run, &preset.name).unwrap();
            let mut all = Fixer::new(&trace).unwrap();
            let mut fixed_findings = 0;
            for (f, w) in bad.report.findings.iter().zip(&proven) {
                let what = format!("{}: {name}: {} ({}): {}", preset.name, f.id, f.location.describe(), w.fix);
                if f.id.ends_with("-stall") {
                    assert!(!w.applied, "{what}: a stall has no edit");
                    continue;
                }
                assert!(w.applied, "{what}: not applied");
                all.add(f, &bad.report).unwrap();
                fixed_findings += 1;
                assert_eq!(w.same_picture, Some(true), "{what}: the pictures");
                let mut measured = w.measured_bytes_before_elimination.or(w.measured_bytes);
                // Shading vertices again in each tile, a device loses the vertex-cache hits
                // between the draws a flush puts in two passes: a cost the estimate (the reload)
                // leaves out. Everything else the fix saved is the estimate.
                if f.id == "flush-mid-pass"
                    && preset.device.vertex_shading == tiler::VertexShading::PerTile
                    && measured != f.cost_bytes.map(|b| b as i64)
                {
                    let mut one = Fixer::new(&trace).unwrap();
                    one.add(f, &bad.report).unwrap();
                    let mut fixed = one.fixed(&trace);
                    fixed.config = config.clone();
                    let fixed = fixed.replay_with(limits).unwrap();
                    let fetch = |r: &Replay| r.report.totals.ledger.get(Category::VertexFetch) as i64;
                    let lost_hits = fetch(&bad) - fetch(&fixed);
                    assert!(lost_hits > 0, "{what}");
                    measured = measured.map(|m| m - lost_hits);
                }
                // Not priced: what an immediate-mode GPU's full clear writes in memory against
                // what the clear-quad's fragments write (more with a framebuffer cache, less
                // without one); the fragments are.
                let unpriced = f.id == "partial-clear" && !preset.device.backend.is_tiler();
                if !unpriced {
                    assert_eq!(measured, Some(f.cost_bytes.unwrap_or(0) as i64), "{what}: measured vs estimate");
                }
                assert_eq!(w.measured_fragments, Some(f.cost_fragments.unwrap_or(0) as i64), "{what}: fragments");
                if !preset.device.transaction_elimination {
                    assert_eq!(w.measured_bytes_before_elimination, None, "{what}");
                }
                table.push_str(&format!(
                    "{} {name} {} {:?} {:?} {:?}\n",
                    preset.name, f.id, f.cost_bytes, measured, w.measured_bytes
                ));
            }
            let total = |r: &Replay| r.report.totals.ledger.total();
            let eliminated = |r: &Replay| r.report.transaction_elimination_saved();
            let shaded = |r: &Replay| r.report.totals.counters.fragments_shaded;
            // No advice where the pattern costs the device nothing: an immediate-mode GPU gets
            // no tiler-only advice (its bad form moves no more bytes; a clear-quad shades more
            // but its full clear writes more), hidden-surface removal needs no sorting.
            if fixed_findings == 0 {
                if !bad.report.findings.is_empty() {
                    // Only stalls, which no edit of the calls fixes: the good form differs in
                    // more than the pattern (the query pair uses three queries).
                    continue;
                }
                assert!(
                    total(&bad) + eliminated(&bad) <= total(&good) + eliminated(&good),
                    "{}: {name}: no finding, but the bad form moves more bytes",
                    preset.name
                );
                assert!(
                    !preset.device.backend.is_tiler() || shaded(&bad) <= shaded(&good),
                    "{}: {name}: no finding, but the bad form shades more",
                    preset.name
                );
                continue;
            }
            let mut fixed = all.fixed(&trace);
            fixed.config = config.clone();
            let fixed = fixed.replay_with(limits).unwrap();
            assert_eq!(
                tiler_gl::report::first_different_frame(&fixed.report.frames, &good.report.frames),
                None,
                "{}: {name}: the pictures",
                preset.name
            );
            if name == "masked-clear" && !preset.device.backend.is_tiler() {
                assert_eq!(shaded(&fixed), shaded(&good), "{}: {name}", preset.name);
                continue;
            }
            assert_eq!(
                total(&fixed) + eliminated(&fixed),
                total(&good) + eliminated(&good),
                "{}: {name}: every fix applied costs what the good form costs",
                preset.name
            );
        }
    }
    println!("{table}");
}

/// A fix that changes a picture before the last frame is caught, and the frame named: the
/// what-if compares every presented frame, not only the last. Here frame 1 draws over what
/// frame 0 left in a texture (its load is its starting point), so clearing at the start of
/// frame 1's pass changes frame 1's picture; frame 2 clears and redraws, so its picture is
/// the same either way.
#[test]
fn a_fix_that_changes_a_middle_frame_is_named() {
    use tiler_gl::advisor::what_if;
    let draw_texture_to_window = r#"
      {"call": "bind_framebuffer", "framebuffer": 0},
      {"call": "clear", "color": true, "depth": true, "stencil": true},
      {"call": "use_program", "id": 2},
      {"call": "bind_texture", "unit": 0, "texture": 1},
      {"call": "vertex_attrib_pointer", "index": 0, "buffer": 3, "size": 2, "type": "float", "stride": 16, "offset": 0},
      {"call": "enable_vertex_attrib", "index": 0},
      {"call": "vertex_attrib_pointer", "index": 1, "buffer": 3, "size": 2, "type": "float", "stride": 16, "offset": 8},
      {"call": "enable_vertex_attrib", "index": 1},
      {"call": "draw_arrays", "mode": "triangles", "first": 0, "count": 6},
      {"call": "disable_vertex_attrib", "index": 1},
      {"call": "swap_buffers"}"#;
    let quad = |color: &str| {
        format!(
            r#"{{"call": "use_program", "id": 1}},
      {{"call": "vertex_attrib_pointer", "index": 0, "buffer": 2, "size": 3, "type": "float"}},
      {{"call": "enable_vertex_attrib", "index": 0}},
      {{"call": "uniform", "name": "color", "value": {{"vec4": [{color}]}}}},
      {{"call": "draw_arrays", "mode": "triangles", "first": 0, "count": 6}},"#
        )
    };
    let text = format!(
        r#"{{"format": "tiler-gl-trace", "version": 1, "config": {{"width": 64, "height": 64}}, "frames": [
    {{"calls": [
      {{"call": "create_program", "id": 1, "program": "solid"}},
      {{"call": "create_program", "id": 2, "program": "textured"}},
      {{"call": "create_buffer", "id": 2, "data": {{"f32": [-0.5, -0.5, 0.0, 0.5, -0.5, 0.0, 0.5, 0.5, 0.0, -0.5, -0.5, 0.0, 0.5, 0.5, 0.0, -0.5, 0.5, 0.0]}}}},
      {{"call": "create_buffer", "id": 3, "data": {{"f32": [-1, -1, 0, 0, 1, -1, 1, 0, 1, 1, 1, 1, -1, -1, 0, 0, 1, 1, 1, 1, -1, 1, 0, 1]}}}},
      {{"call": "create_texture", "id": 1, "width": 64, "height": 64, "format": "rgba8"}},
      {{"call": "create_framebuffer", "id": 1}},
      {{"call": "framebuffer_texture", "framebuffer": 1, "attachment": "color0", "texture": 1}},
      {{"call": "bind_framebuffer", "framebuffer": 1}},
      {{"call": "clear_color", "rgba": [1.0, 0.0, 0.0, 1.0]}},
      {{"call": "clear", "color": true}},
      {{"call": "clear_color", "rgba": [0.0, 0.0, 0.0, 1.0]}},
      {draw_texture_to_window}]}},
    {{"calls": [
      {{"call": "bind_framebuffer", "framebuffer": 1}},
      {q1}
      {draw_texture_to_window}]}},
    {{"calls": [
      {{"call": "bind_framebuffer", "framebuffer": 1}},
      {{"call": "clear", "color": true}},
      {q2}
      {draw_texture_to_window}]}}]}}"#,
        q1 = quad("0.0, 1.0, 0.0, 1.0"),
        q2 = quad("0.0, 0.0, 1.0, 1.0"),
    );
    let mut trace = Trace::parse(&text, None).unwrap();
    trace.config.digest_presented = true;
    let run = trace.replay().unwrap();
    let loads: Vec<_> = run.report.findings_with("load-at-pass-start").collect();
    assert_eq!(loads.len(), 1, "{:#?}", run.report.findings);
    assert_eq!(loads[0].location.frame, Some(1));
    let picture = run.context.surface_rgba8();
    let config = run.context.config().clone();
    let proven =
        what_if::prove(&trace, &what_if::Run { config: &config, report: &run.report, picture: &picture }, "tbr")
            .unwrap();
    let (finding, result) =
        run.report.findings.iter().zip(&proven).find(|(f, _)| f.id == "load-at-pass-start").unwrap();
    assert!(result.applied, "{}", result.fix);
    assert_eq!(result.same_picture, Some(false), "{}", finding.message);
    assert_eq!(result.different_frame, Some(1), "the middle frame is named");
    // Without the presented pictures recorded, nothing can be proven.
    let mut plain = config.clone();
    plain.digest_presented = false;
    let err = what_if::prove(&trace, &what_if::Run { config: &plain, report: &run.report, picture: &picture }, "tbr")
        .unwrap_err();
    assert!(err.contains("digest_presented"), "{err}");
}

/// The depth-prepass pair (seed 000 §23.7): opaque layers back to front, without and with a
/// depth-only prepass. On a tiler the prepass removes the overdraw the bad form's
/// `unsorted-opaque` finding reports (the colour shader runs once per pixel) and costs no
/// depth bandwidth — only its geometry again: vertex fetch and frame data exactly doubled. On
/// an immediate-mode GPU it also costs depth traffic. Its own fragments are depth-only.
#[test]
fn a_depth_prepass_trades_geometry_for_shading() {
    let good = replay("depth-prepass-good.json");
    let bad = replay("depth-prepass-bad.json");
    assert!(good.report.findings.is_empty(), "{:#?}", good.report.findings);
    let overdraw: u64 = bad.report.findings_with("unsorted-opaque").map(|f| f.cost_fragments.unwrap_or(0)).sum();
    let pixels = 128 * 96;
    assert_eq!(overdraw, 3 * pixels, "three hidden layers shaded");
    assert_eq!(good.context.surface_rgba8(), bad.context.surface_rgba8());
    let (g, b) = (&good.report.totals, &bad.report.totals);
    // The bad form's 4 layers; the good form's depth-only 4 layers and 1 layer in colour.
    assert_eq!(b.counters.fragments_shaded, 4 * pixels);
    assert_eq!(g.counters.fragments_shaded, 4 * pixels + (4 * pixels - overdraw));
    for category in Category::ALL {
        let (with, without) = (g.ledger.get(category), b.ledger.get(category));
        match category {
            Category::VertexFetch | Category::FrameDataWrite | Category::FrameDataRead => {
                assert_eq!(with, 2 * without, "{category:?}: every draw's geometry again")
            }
            _ => assert_eq!(with, without, "{category:?}: no other traffic on a tiler"),
        }
    }
    // Immediate mode: the prepass reads and writes depth for every layer again.
    let imr = |name: &str| {
        let mut trace = Trace::read(&traces().join(name)).unwrap();
        trace.config.backend = tiler::Backend::Imr;
        trace.replay_with(Limits { threads: Some(1), ..Limits::default() }).unwrap().report.totals.ledger
    };
    let (with, without) = (imr("depth-prepass-good.json"), imr("depth-prepass-bad.json"));
    assert!(with.get(Category::ImrDepthRead) > without.get(Category::ImrDepthRead));
    assert!(with.total() > without.total());
}

/// The window's packed D24S8 depth and stencil, stored and never read: one word per sample is
/// written whichever half is kept, so the advice names both halves in one finding, priced at
/// the whole word (4 B per sample), and never one half alone (which would save nothing).
#[test]
fn dead_packed_depth_and_stencil_are_one_finding_for_the_whole_word() {
    let bad = replay("invalidate-bad.json");
    let dead: Vec<_> = bad.report.findings_with("store-unread").collect();
    assert!(!dead.is_empty());
    for finding in dead {
        assert!(finding.message.contains("stored the depth and stencil of"), "{}", finding.message);
        assert_eq!(finding.cost_bytes, Some(128 * 96 * 4), "{}", finding.message);
    }
}

/// A long run's records are held once: `Context::end` moves the frames into the report (the
/// context keeps none), and each pass keeps exactly one core report, whose per-tile arrays are
/// one entry per tile and whose overdraw map is absent unless the device records one. So the
/// memory of a run with `keep_pass_reports` grows by a fixed amount per pass, counted here in
/// records and entries rather than timed: 12 frames hold 12 frame records, and every frame
/// after the first holds the same passes, tile entries and draws.
#[test]
fn a_runs_records_are_held_once_and_grow_linearly_small() {
    let mut trace = Trace::read(&traces().join("rebind-good.json")).unwrap();
    let frames_in_file: u32 = trace.frames.iter().map(|f| f.repeat).sum();
    let extra = 12 - frames_in_file;
    trace.frames.last_mut().unwrap().repeat += extra;
    trace.config.keep_pass_reports = true;
    let mut replay = trace.replay_with(Limits { threads: Some(1), ..Limits::default() }).unwrap();
    assert!(replay.context.frames().is_empty(), "the context keeps no copy of the records");
    assert_eq!(replay.context.end().unwrap().frames.len(), 0, "ending again adds nothing");
    let report = &replay.report;
    assert_eq!(report.frames.len(), 12);
    let passes: Vec<_> = report.passes().collect();
    let tiles = |p: &&tiler_gl::report::PassRecord| (p.cost.tiles_x * p.cost.tiles_y) as usize;
    for pass in &passes {
        let core = pass.core.as_ref().expect("kept");
        assert_eq!(core.tiles.len(), tiles(pass), "pass {}: one entry per tile", pass.index);
        assert_eq!(core.draws.len(), pass.draws.len(), "pass {}: one entry per draw", pass.index);
        assert!(core.overdraw_map.is_none(), "pass {}: no per-pixel map unless the device records one", pass.index);
    }
    // Every frame holds the same: the records grow in step with the frames.
    let per_frame: Vec<(usize, usize, usize)> = report
        .frames
        .iter()
        .skip(1)
        .map(|f| {
            let tile_entries = f.passes.iter().map(|p| p.core.as_ref().unwrap().tiles.len()).sum();
            let draws = f.passes.iter().map(|p| p.draws.len()).sum();
            (f.passes.len(), tile_entries, draws)
        })
        .collect();
    assert!(per_frame.windows(2).all(|w| w[0] == w[1]), "{per_frame:?}");
}

/// The what-if's `restore_state` carries a context's state in memory only: a trace holding
/// one writes it as a bare call (no panic) and reading that back is an error naming it.
#[test]
fn a_restore_state_call_is_written_but_not_read_back() {
    let gl = tiler_gl::Context::new(ContextConfig::new(4, 4)).unwrap();
    let frames = vec![tiler_gl::trace::TraceFrame {
        repeat: 1,
        calls: vec![tiler_gl::Call::RestoreState { state: gl.saved_state() }, tiler_gl::Call::SwapBuffers],
    }];
    let trace = Trace { description: None, config: ContextConfig::new(4, 4), frames };
    assert_eq!(trace.replay().unwrap().report.frames.len(), 1);
    let json = trace.to_json();
    assert!(json.contains(r#""call":"restore_state""#), "{json}");
    let error = Trace::parse(&json, None).unwrap_err().to_string();
    assert!(error.contains("restore_state"), "{error}");
}
