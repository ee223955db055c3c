//! Explicit passes in traces: subpasses, input attachments, transient attachments, and what a
//! dependency that is not by-region costs.

use std::path::Path;

use tiler::Category;
use tiler_gl::trace::Replay;
use tiler_gl::*;

fn read(name: &str) -> Trace {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("traces").join(name);
    Trace::read(&path).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn run(trace: &Trace) -> Replay {
    trace.replay_with(Limits { threads: Some(1), ..Limits::default() }).unwrap_or_else(|e| panic!("{e}"))
}

/// The explicit passes of a run.
fn explicit_passes(r: &Replay) -> Vec<&PassRecord> {
    r.report.passes().filter(|p| !p.subpasses.is_empty()).collect()
}

const PIXELS: u64 = 128 * 96;

/// By-region: the G-buffer (transient colour and depth-stencil) never leaves the tile and
/// needs no memory; only the lit output is stored.
#[test]
fn a_by_region_dependency_keeps_the_transient_g_buffer_on_chip() {
    let good = run(&read("subpass-good.json"));
    let passes = explicit_passes(&good);
    assert_eq!(passes.len(), 3, "one explicit pass per frame");
    for p in passes {
        assert_eq!(p.subpasses.len(), 2);
        assert_eq!(p.draw_subpasses, vec![0, 1]);
        assert_eq!(p.cost.counters.subpass_splits, 0);
        assert_eq!(p.cost.ledger.get(Category::TileLoad), 0);
        assert_eq!(p.cost.ledger.get(Category::TileStore), PIXELS * 4, "only color0 is stored");
        assert_eq!(p.cost.transient_bytes_saved, PIXELS * (4 + 4), "rgba8 albedo and packed depth-stencil");
        for a in p.attachments.iter().filter(|a| a.slot != report::Slot::Color(0)) {
            assert_eq!((a.load_bytes, a.store_bytes), (0, 0), "{} of a transient image moves nothing", a.slot);
        }
    }
    assert!(good.report.findings.is_empty(), "{:#?}", good.report.findings);
    assert!(text_report(&good.report).contains("transient attachments: 98.3 kB of memory not needed"));
}

/// Not by-region: the pass is split once, everything goes through memory, and the advisor
/// says which pass, why, and what it cost.
#[test]
fn a_dependency_that_is_not_by_region_splits_the_pass_and_the_advisor_says_so() {
    let bad = run(&read("subpass-bad.json"));
    let passes = explicit_passes(&bad);
    for p in &passes {
        assert_eq!(p.cost.counters.subpass_splits, 1);
        assert_eq!(p.cost.transient_bytes_saved, 0, "the split spilled the transient attachments");
        // Stored: output, albedo and depth-stencil at the split, and the output at the end;
        // loaded: all three for the lighting subpass.
        assert_eq!(p.cost.ledger.get(Category::TileStore), PIXELS * (4 + 4 + 4) + PIXELS * 4);
        assert_eq!(p.cost.ledger.get(Category::TileLoad), PIXELS * (4 + 4 + 4));
    }
    let findings: Vec<_> = bad.report.findings_with("subpass-split").collect();
    assert_eq!(findings.len(), passes.len());
    for (f, p) in findings.iter().zip(&passes) {
        assert_eq!(f.location.pass, Some(p.index as u64));
        assert_eq!(f.location.call_at.map(CallRef::from), Some(p.started_at), "the begin_pass call");
        assert_eq!(f.cost_bytes.unwrap_or(0), PIXELS * (4 + 4 + 4) * 2);
        assert!(f.message.contains("subpass 0 → 1") && f.message.contains("not by-region"), "{}", f.message);
        assert!(f.advice.contains("\"by_region\": true"), "{}", f.advice);
        assert_eq!(f.rule.seed, "002");
    }
}

/// The same G-buffer → lighting frame as two passes: the G-buffer stored to a texture, then
/// loaded by a one-subpass pass that reads it as an input attachment. Same picture, bit for
/// bit, as the subpasses — which keep the G-buffer on chip.
#[test]
fn subpasses_draw_what_two_passes_through_memory_draw() {
    let good = read("subpass-good.json");
    let two_passes = r#"{"format": "tiler-gl-trace", "version": 1, "config": {"width": 128, "height": 96}, "frames": [{"calls": [
      {"call": "create_program", "id": 1, "program": "vertex_color"},
      {"call": "create_program", "id": 2, "program": "composite"},
      {"call": "create_buffer", "id": 1, "data": {"f32": [-0.9, -0.8, 0.5, 0.7, -0.6, 0.5, -0.1, 0.9, 0.5, -0.6, 0.6, 0.2, 0.2, -0.9, 0.2, 0.95, 0.7, 0.2]}},
      {"call": "create_buffer", "id": 2, "data": {"f32": [0.9, 0.3, 0.2, 1, 0.2, 0.8, 0.3, 1, 0.3, 0.4, 0.9, 1, 0.9, 0.9, 0.9, 1, 0.6, 0.2, 0.7, 1, 0.1, 0.7, 0.8, 1]}},
      {"call": "create_buffer", "id": 3, "data": {"f32": [-1, -1, 0, 3, -1, 0, -1, 3, 0]}},
      {"call": "create_texture", "id": 1, "width": 128, "height": 96, "format": "rgba8"},
      {"call": "create_texture", "id": 2, "width": 128, "height": 96, "format": "rgba8"},
      {"call": "create_renderbuffer", "id": 3, "width": 128, "height": 96, "format": "depth24_stencil8"},
      {"call": "create_framebuffer", "id": 2},
      {"call": "framebuffer_texture", "framebuffer": 2, "attachment": "color0", "texture": 2},
      {"call": "framebuffer_renderbuffer", "framebuffer": 2, "attachment": "depth_stencil", "renderbuffer": 3},
      {"call": "create_framebuffer", "id": 1},
      {"call": "framebuffer_texture", "framebuffer": 1, "attachment": "color0", "texture": 1},
      {"call": "framebuffer_texture", "framebuffer": 1, "attachment": "color1", "texture": 2},
      {"call": "enable", "cap": "depth_test"},
      {"call": "bind_framebuffer", "framebuffer": 2},
      {"call": "clear", "color": true, "depth": true, "stencil": true},
      {"call": "use_program", "id": 1},
      {"call": "vertex_attrib_pointer", "index": 0, "buffer": 1, "size": 3, "type": "float"},
      {"call": "vertex_attrib_pointer", "index": 1, "buffer": 2, "size": 4, "type": "float"},
      {"call": "enable_vertex_attrib", "index": 0},
      {"call": "enable_vertex_attrib", "index": 1},
      {"call": "draw_arrays", "mode": "triangles", "first": 0, "count": 6},
      {"call": "invalidate", "attachments": ["depth_stencil"]},
      {"call": "begin_pass", "framebuffer": 1, "subpasses": [{"color": ["color0"], "input": ["color1"]}]},
      {"call": "clear_color", "rgba": [0, 0, 0, 0]},
      {"call": "use_program", "id": 2},
      {"call": "uniform", "name": "color", "value": {"vec4": [1.0, 0.85, 0.6, 1.0]}},
      {"call": "vertex_attrib_pointer", "index": 0, "buffer": 3, "size": 3, "type": "float"},
      {"call": "draw_arrays", "mode": "triangles", "first": 0, "count": 3},
      {"call": "end_pass"},
      {"call": "bind_framebuffer", "framebuffer": 0},
      {"call": "clear", "color": true, "depth": true, "stencil": true},
      {"call": "bind_framebuffer", "target": "read", "framebuffer": 1},
      {"call": "blit_framebuffer", "src": [0, 0, 128, 96], "dst": [0, 0, 128, 96]},
      {"call": "swap_buffers"}
    ]}]}"#;
    let two = run(&Trace::parse(two_passes, None).unwrap());
    let mut one_frame = good.clone();
    one_frame.frames.truncate(1);
    let sub = run(&one_frame);
    let picture = sub.context.surface_rgba8();
    assert!(picture.chunks(4).any(|p| p[0] > 0 && p[0] < 255), "something lit is drawn");
    assert_eq!(two.context.surface_rgba8(), picture, "bit for bit");
    // The second pass loads the G-buffer the first one stored: 2 × 4 bytes per pixel that
    // the subpasses never move.
    let gbuffer_pass = two.report.passes().find(|p| p.framebuffer == 2).unwrap();
    let lighting_pass = two.report.passes().find(|p| p.framebuffer == 1).unwrap();
    assert_eq!(gbuffer_pass.attachment(report::Slot::Color(0)).unwrap().store_bytes, PIXELS * 4);
    assert_eq!(lighting_pass.attachment(report::Slot::Color(1)).unwrap().load_bytes, PIXELS * 4);

    // Every backend draws the same subpass picture (immediate mode keeps the G-buffer in
    // scratch memory and reads its inputs from there).
    for backend in [tiler::Backend::Tbdr, tiler::Backend::Imr] {
        let mut t = one_frame.clone();
        t.config.backend = backend;
        assert_eq!(run(&t).context.surface_rgba8(), picture, "{backend:?}");
    }
}

/// The recorder writes the new calls and fields, and its trace replays to the same run.
#[test]
fn recording_round_trips_explicit_passes_and_transient_attachments() {
    let good = read("subpass-good.json");
    let mut gl = Context::new_recording(ContextConfig { threads: 1, ..good.config.clone() }).unwrap();
    for frame in &good.frames {
        for _ in 0..frame.repeat {
            for call in &frame.calls {
                gl.call(call.clone()).unwrap();
            }
        }
    }
    let recorded = gl.recording().unwrap();
    let json = recorded.to_json();
    assert!(json.contains("\"transient\": true") || json.contains("\"transient\":true"), "{json}");
    assert!(json.contains("begin_pass") && json.contains("next_subpass") && json.contains("end_pass"));
    let parsed = Trace::parse(&json, None).unwrap();
    assert_eq!(parsed, recorded);
    let picture = gl.surface_rgba8();
    let report = serde_json::to_value(gl.end().unwrap()).unwrap();
    let replay = run(&parsed);
    assert_eq!(replay.context.surface_rgba8(), picture);
    assert_eq!(serde_json::to_value(&replay.report).unwrap(), report);
}

/// Calls 0 to 9 make: program 1 `composite` in use reading a full-screen triangle;
/// framebuffer 1 with colour texture 1 at color0 and transient renderbuffer 2 at color1;
/// transient texture 3.
const PRELUDE: &str = r#"
    {"call": "create_program", "id": 1, "program": "composite"},
    {"call": "create_texture", "id": 1, "width": 16, "height": 16, "format": "rgba8"},
    {"call": "create_renderbuffer", "id": 2, "width": 16, "height": 16, "format": "rgba8", "transient": true},
    {"call": "create_framebuffer", "id": 1},
    {"call": "framebuffer_texture", "framebuffer": 1, "attachment": "color0", "texture": 1},
    {"call": "framebuffer_renderbuffer", "framebuffer": 1, "attachment": "color1", "renderbuffer": 2},
    {"call": "create_buffer", "id": 1, "data": {"f32": [-1, -1, 0, 3, -1, 0, -1, 3, 0]}},
    {"call": "use_program", "id": 1},
    {"call": "vertex_attrib_pointer", "index": 0, "buffer": 1, "size": 3, "type": "float"},
    {"call": "create_texture", "id": 3, "width": 16, "height": 16, "format": "rgba8", "transient": true}"#;

/// `begin_pass` on framebuffer 1: subpass 0 writes color1, subpass 1 reads it into color0.
const BEGIN: &str = r#"{"call": "begin_pass", "framebuffer": 1, "subpasses": [{"color": ["color1"]},
    {"color": ["color0"], "input": ["color1"]}], "dependencies": [{"src": 0, "dst": 1, "by_region": true}]}"#;

/// The error of a trace of the prelude and `calls`, reading or replaying.
fn error(calls: &str) -> String {
    let json = format!(
        r#"{{"format": "tiler-gl-trace", "version": 1, "config": {{"width": 16, "height": 16}},
            "frames": [{{"calls": [{PRELUDE}, {{"call": "enable_vertex_attrib", "index": 0}}, {calls}]}}]}}"#
    );
    match Trace::parse(&json, None) {
        Err(e) => e.to_string(),
        Ok(t) => match t.replay_with(Limits { threads: Some(1), ..Limits::default() }) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("no error for {calls}"),
        },
    }
}

/// Bad explicit passes and transient misuse: errors naming the frame, the call and the
/// problem, never panics. Call 11 is the first after the prelude.
#[test]
fn explicit_pass_errors_name_the_call() {
    let draw = r#"{"call": "draw_arrays", "mode": "triangles", "first": 0, "count": 3}"#;
    let cases: Vec<(String, &str)> = vec![
        (
            r#"{"call": "begin_pass", "framebuffer": 1, "subpasses": [{"color": ["color2"]}]}"#.into(),
            "frame 0, call 11: begin_pass: subpass 0: colour color2 is not attached to framebuffer 1 (it has 2",
        ),
        (
            r#"{"call": "begin_pass", "framebuffer": 1, "subpasses": [{"color": ["depth"]}]}"#.into(),
            "call 11: begin_pass: subpass 0: colour depth is not a colour attachment point",
        ),
        (
            r#"{"call": "begin_pass", "framebuffer": 1, "subpasses": [{"color": ["color0"], "input": ["color3"]}]}"#
                .into(),
            "call 11: begin_pass: subpass 0: input 0 color3 is not attached",
        ),
        (
            r#"{"call": "begin_pass", "framebuffer": 1, "subpasses": [{"color": ["color0"], "input": ["depth"]}]}"#
                .into(),
            "call 11: begin_pass: subpass 0: input 0 reads the depth-stencil attachment, but framebuffer 1 has none",
        ),
        (
            r#"{"call": "begin_pass", "framebuffer": 1, "subpasses": [{"color": ["color0"], "input": ["color0"]}]}"#
                .into(),
            "call 11: begin_pass: subpass 0: input 0 (color0) is also written by this subpass",
        ),
        (
            r#"{"call": "begin_pass", "framebuffer": 1, "subpasses": [{"depth_stencil": true}]}"#.into(),
            "call 11: begin_pass: subpass 0: depth_stencil is true but framebuffer 1 has no depth",
        ),
        (
            r#"{"call": "begin_pass", "framebuffer": 1, "subpasses": [{}], "dependencies": [{"src": 0, "dst": 1}]}"#
                .into(),
            "call 11: begin_pass: dependency 0: subpass 0 → 1, but the pass has 1 subpass(es)",
        ),
        (r#"{"call": "begin_pass", "framebuffer": 1, "subpasses": []}"#.into(), "call 11: begin_pass: begin_pass needs at least one subpass"),
        (r#"{"call": "begin_pass", "framebuffer": 7, "subpasses": [{}]}"#.into(), "call 11: begin_pass: framebuffer 7 does not exist"),
        (
            r#"{"call": "begin_pass", "framebuffer": 1, "subpasses": [{"color": ["color0"], "colour": []}]}"#.into(),
            "frame 0, call 11: begin_pass: unknown field `colour`",
        ),
        (
            r#"{"call": "begin_pass", "framebuffer": 1, "subpasses": [{}], "dependencies": [{"src": 0, "dst": 0, "region": true}]}"#.into(),
            "frame 0, call 11: begin_pass: unknown field `region`",
        ),
        (r#"{"call": "next_subpass", "to": 1}"#.into(), "frame 0, call 11: next_subpass: unknown field `to`"),
        (r#"{"call": "next_subpass"}"#.into(), "call 11: next_subpass: next_subpass outside an explicit pass"),
        (r#"{"call": "end_pass"}"#.into(), "call 11: end_pass: end_pass outside an explicit pass"),
        (
            format!(r#"{BEGIN}, {{"call": "next_subpass"}}, {{"call": "next_subpass"}}"#),
            "frame 0, call 13: next_subpass: next_subpass past the last subpass: the pass begun at frame 0, call 11 \
             has 2 subpass(es)",
        ),
        (format!(r#"{BEGIN}, {{"call": "end_pass"}}"#), "call 12: end_pass: end_pass in subpass 0 of the 2"),
        (format!(r#"{BEGIN}, {BEGIN}"#), "call 12: begin_pass: begin_pass inside the explicit pass begun at frame 0, call 11"),
        (
            format!(r#"{BEGIN}, {{"call": "bind_framebuffer", "framebuffer": 0}}"#),
            "call 12: bind_framebuffer: binding another framebuffer inside the explicit pass begun at frame 0, call 11",
        ),
        (format!(r#"{BEGIN}, {{"call": "flush"}}"#), "call 12: flush: flush inside the explicit pass"),
        (format!(r#"{BEGIN}, {{"call": "swap_buffers"}}"#), "call 12: swap_buffers: swap_buffers inside the explicit pass"),
        (
            format!(
                r#"{BEGIN}, {{"call": "bind_framebuffer", "target": "read", "framebuffer": 1}},
                   {{"call": "read_pixels", "x": 0, "y": 0, "width": 1, "height": 1}}"#
            ),
            "call 13: read_pixels: read_pixels inside the explicit pass",
        ),
        (format!(r#"{BEGIN}, {draw}"#), "call 12: draw_arrays: program 'composite' reads 1 input attachment(s), but subpass 0 has 0"),
        (draw.to_string(), "call 11: draw_arrays: program 'composite' reads input attachment 0, which only a subpass"),
        (
            format!(
                r#"{BEGIN}, {{"call": "create_program", "id": 2, "program": "solid"}}, {{"call": "use_program", "id": 2}},
                   {draw}, {{"call": "clear", "color": true}}"#
            ),
            "call 15: clear: a clear after draws in an explicit pass",
        ),
        (
            format!(r#"{BEGIN}, {{"call": "blit_framebuffer", "src": [0, 0, 16, 16], "dst": [0, 0, 16, 16]}}"#),
            "call 12: blit_framebuffer: blit_framebuffer inside the explicit pass begun at frame 0, call 11",
        ),
        (BEGIN.to_string(), "frame 0: at the end of the trace: the explicit pass begun at frame 0, call 11 was never ended"),
        // Checked at end_pass, once the load ops are known: an input nothing wrote.
        (
            format!(
                r#"{{"call": "begin_pass", "framebuffer": 1, "subpasses": [{{"color": ["color0"], "input": ["color1"]}}]}},
                   {draw}, {{"call": "end_pass"}}"#
            ),
            "frame 0, call 13: end_pass: subpass 0 reads color1 as input 0, but no earlier subpass writes it and the \
             pass neither loads nor clears it",
        ),
        // Transient images have no memory: nothing reads them back, samples, copies or
        // uploads them.
        (
            r#"{"call": "create_framebuffer", "id": 2}, {"call": "framebuffer_renderbuffer", "framebuffer": 2, "attachment": "color0", "renderbuffer": 2},
               {"call": "bind_framebuffer", "framebuffer": 2}, {"call": "read_pixels", "x": 0, "y": 0, "width": 1, "height": 1}"#.into(),
            "frame 0, call 14: read_pixels: read_pixels of framebuffer 2's color0: the image is transient",
        ),
        (
            r#"{"call": "create_framebuffer", "id": 2}, {"call": "framebuffer_renderbuffer", "framebuffer": 2, "attachment": "color0", "renderbuffer": 2},
               {"call": "bind_framebuffer", "target": "read", "framebuffer": 2}, {"call": "blit_framebuffer", "src": [0, 0, 16, 16], "dst": [0, 0, 16, 16]}"#.into(),
            "frame 0, call 14: blit_framebuffer: blit_framebuffer from framebuffer 2's color0: the image is transient",
        ),
        (
            r#"{"call": "create_program", "id": 2, "program": "textured"}, {"call": "use_program", "id": 2},
               {"call": "vertex_attrib_pointer", "index": 1, "buffer": 1, "size": 2, "type": "float"}, {"call": "enable_vertex_attrib", "index": 1},
               {"call": "bind_texture", "unit": 0, "texture": 3}, {"call": "draw_arrays", "mode": "triangles", "first": 0, "count": 3}"#.into(),
            "frame 0, call 16: draw_arrays: program 'textured' samples texture 3: the image is transient",
        ),
        (
            r#"{"call": "copy_tex_sub_image", "texture": 3, "x_offset": 0, "y_offset": 0, "x": 0, "y": 0, "width": 4, "height": 4}"#.into(),
            "call 11: copy_tex_sub_image: copy_tex_sub_image into texture 3: the image is transient",
        ),
        (
            r#"{"call": "tex_sub_image", "id": 3, "x": 0, "y": 0, "width": 1, "height": 1, "data": {"u8": [1, 2, 3, 4]}}"#.into(),
            "call 11: tex_sub_image: tex_sub_image of texture 3: the image is transient",
        ),
        (
            r#"{"call": "create_texture", "id": 4, "width": 1, "height": 1, "format": "rgba8", "transient": true, "data": {"u8": [1, 2, 3, 4]}}"#.into(),
            "call 11: create_texture: texture 4 is transient (it has no memory), so it cannot be given data",
        ),
    ];
    for (calls, expected) in cases {
        let e = error(&calls);
        assert!(e.contains(expected), "{calls}\n  gave: {e}\n  expected: {expected}");
    }
}

/// Inferred passes keep working with a transient depth buffer: never loaded or stored (not
/// even when it is attached again later, or when only one half of it is attached), counted
/// as memory not needed, and the API's draws see it as GL would within a pass.
#[test]
fn inferred_passes_take_transient_attachments() {
    use super::common::*;
    let mut gl = context(64, 64);
    c(
        &mut gl,
        Call::CreateTexture {
            id: 1,
            width: 64,
            height: 64,
            format: TextureFormat::Rgba8,
            data: None,
            transient: false,
        },
    );
    c(
        &mut gl,
        Call::CreateRenderbuffer {
            id: 2,
            width: 64,
            height: 64,
            format: TextureFormat::Depth24Stencil8,
            samples: 1,
            transient: true,
        },
    );
    c(&mut gl, Call::CreateFramebuffer { id: 1 });
    c(
        &mut gl,
        Call::FramebufferTexture { framebuffer: 1, attachment: AttachmentPoint::Color0, texture: 1, samples: 1 },
    );
    c(&mut gl, Call::FramebufferRenderbuffer { framebuffer: 1, attachment: AttachmentPoint::Depth, renderbuffer: 2 });
    geometry(&mut gl, 1, ProgramKind::Solid, &quad(-1.0, -1.0, 1.0, 1.0, 0.0));
    c(&mut gl, Call::Enable { cap: Capability::DepthTest });
    for _ in 0..2 {
        bind(&mut gl, 1);
        clear_all(&mut gl);
        draw(&mut gl, 6);
        bind(&mut gl, 0);
        clear_all(&mut gl);
    }
    swap(&mut gl);
    let report = gl.end().unwrap();
    let passes: Vec<_> = report.passes().filter(|p| p.framebuffer == 1).collect();
    assert_eq!(passes.len(), 2);
    for p in passes {
        assert_eq!(op(p, report::Slot::Depth), (report::LoadKind::Clear, report::StoreKind::DontCare));
        assert_eq!(op(p, report::Slot::Stencil).1, report::StoreKind::DontCare, "the unattached half too");
        assert_eq!(p.cost.ledger.get(Category::TileStore), 64 * 64 * 4, "colour only");
        assert_eq!(p.cost.transient_bytes_saved, 64 * 64 * 4);
    }
}
