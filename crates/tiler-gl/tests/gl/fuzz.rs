//! Fuzzing the trace reader and the replay with proptest: the example traces, mutated (as
//! JSON values and as bytes), must parse or fail, replay or fail — never panic. The number of
//! cases is `PROPTEST_CASES` (default 64 per strategy, which keeps CI fast; run longer with
//! e.g. `PROPTEST_CASES=20000 cargo test -p tiler-gl --release --test gl fuzz`).

use std::path::Path;

use proptest::prelude::*;
use serde_json::{Map, Value};
use tiler_gl::{Limits, Trace};

/// Small traces to start from.
const SEEDS: [&str; 9] = [
    "clear-bad.json",
    "subpass-bad.json",
    "query-bad.json",
    "tiled-good.json",
    "copy-on-write-bad.json",
    "masked-clear-bad.json",
    "readback-bad.json",
    "alpha-test-bad.json",
    "glsl-alpha-test-bad.json",
];

/// Names a mutation may put anywhere: calls, fields, enum values.
const WORDS: &[&str] = &[
    "create_buffer",
    "buffer_data",
    "buffer_sub_data",
    "delete_buffer",
    "create_texture",
    "tex_image",
    "tex_sub_image",
    "tex_parameters",
    "delete_texture",
    "create_renderbuffer",
    "create_framebuffer",
    "delete_framebuffer",
    "framebuffer_texture",
    "framebuffer_renderbuffer",
    "bind_framebuffer",
    "create_program",
    "bind_attrib_location",
    "use_program",
    "uniform",
    "vertex_attrib",
    "generate_mipmap",
    "linear_mipmap_linear",
    "nearest_mipmap_nearest",
    "glsl",
    "vertex",
    "fragment",
    "name",
    "index",
    "value",
    "vec2",
    "ivec2",
    "ivec4",
    "mat2",
    "mat3",
    "viewport",
    "scissor",
    "enable",
    "disable",
    "clear",
    "invalidate",
    "read_pixels",
    "blit_framebuffer",
    "copy_tex_sub_image",
    "flush",
    "finish",
    "swap_buffers",
    "start_tiling",
    "end_tiling",
    "begin_query",
    "end_query",
    "query_result",
    "draw_arrays",
    "draw_elements",
    "vertex_attrib_pointer",
    "vertex_attrib_array",
    "bind_texture",
    "id",
    "data",
    "offset",
    "width",
    "height",
    "format",
    "x",
    "y",
    "framebuffer",
    "attachment",
    "texture",
    "count",
    "first",
    "mode",
    "type",
    "f32",
    "u16",
    "base64",
    "triangles",
    "triangle_strip",
    "rgba8",
    "depth24_stencil8",
    "stencil8",
    "color0",
    "depth_stencil",
    "textured",
    "solid",
    "float",
    "unsigned_short",
    "scissor_test",
    "depth_test",
    "preserved",
    "backend",
    "imr",
    "tbdr",
    "tbr",
    "samples",
    "frames_in_flight",
    "swap_behavior",
    "depth16",
    "depth24",
    "rgb565",
    "rgba16f",
    "r32f",
    "lambert",
    "vertex_color",
    "alpha_cutoff",
    "sampler",
    "mvp",
    "color",
    "repeat",
    "tile_width",
    "frame_data_budget",
    "triangle_fan",
    "draw",
    "read",
    "stencil",
    "depth",
    "color1",
    "begin_pass",
    "next_subpass",
    "end_pass",
    "subpasses",
    "dependencies",
    "by_region",
    "input",
    "transient",
    "composite",
    "depth_stencil",
];

fn seeds() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("traces");
    SEEDS.iter().map(|s| std::fs::read_to_string(dir.join(s)).unwrap()).collect()
}

fn cases() -> u32 {
    std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(64)
}

/// Tight limits, so a mutated trace stays cheap to replay.
fn limits() -> Limits {
    Limits { max_data_bytes: 4 << 20, max_frames: 16, max_calls: 4096, memory_limit: Some(4 << 20), threads: Some(1) }
}

/// Parses and replays; any error is fine, a panic is not.
fn survive(json: &str) {
    let limits = limits();
    if let Ok(trace) = Trace::parse_with(json, None, limits) {
        let _ = trace.replay_with(limits);
    }
}

fn word(n: u32) -> String {
    WORDS[n as usize % WORDS.len()].to_string()
}

/// A value chosen by `n`.
fn value(n: u32) -> Value {
    match n % 14 {
        0 => Value::from(0),
        1 => Value::from(1),
        2 => Value::from(-1),
        3 => Value::from(u32::MAX),
        4 => Value::from(1e12),
        5 => Value::from(0.5),
        6 => Value::from(n / 14 % 70000),
        7 => Value::Bool(n & 16 != 0),
        8 => Value::Null,
        9 => Value::String(word(n / 14)),
        10 => Value::Array(Vec::new()),
        11 => Value::Object(Map::new()),
        12 => Value::Array((0..n / 14 % 20).map(|i| Value::from(i as f64 * 0.37 - 2.0)).collect()),
        _ => {
            let mut call = Map::new();
            call.insert("call".into(), Value::String(word(n / 14)));
            call.insert(word(n / 97), value(n / 7));
            call.insert(word(n / 1003), value(n / 11));
            Value::Object(call)
        }
    }
}

/// A number for which [`value`] makes a call object.
fn call_value(n: u32) -> u32 {
    n % (u32::MAX / 14) * 14 + 13
}

/// Every path into a JSON value: object keys and array indices.
fn paths(v: &Value, prefix: &mut Vec<PathStep>, out: &mut Vec<Vec<PathStep>>) {
    out.push(prefix.clone());
    match v {
        Value::Object(m) => {
            for (k, child) in m {
                prefix.push(PathStep::Key(k.clone()));
                paths(child, prefix, out);
                prefix.pop();
            }
        }
        Value::Array(a) => {
            for (i, child) in a.iter().enumerate() {
                prefix.push(PathStep::Index(i));
                paths(child, prefix, out);
                prefix.pop();
            }
        }
        _ => {}
    }
}

#[derive(Clone, Debug)]
enum PathStep {
    Key(String),
    Index(usize),
}

fn get_mut<'a>(v: &'a mut Value, path: &[PathStep]) -> Option<&'a mut Value> {
    let mut v = v;
    for step in path {
        v = match step {
            PathStep::Key(k) => v.get_mut(k.as_str())?,
            PathStep::Index(i) => v.get_mut(*i)?,
        };
    }
    Some(v)
}

/// Applies mutations `(kind, where, what)` to a JSON value.
fn mutate(root: &mut Value, ops: &[(u32, u32, u32)]) {
    for &(kind, at, what) in ops {
        let mut all = Vec::new();
        paths(root, &mut Vec::new(), &mut all);
        let path = all[at as usize % all.len()].clone();
        match kind % 5 {
            // Replace a node.
            0 => {
                if let Some(v) = get_mut(root, &path) {
                    *v = value(what);
                }
            }
            // Remove a node from its parent.
            1 => {
                if let Some((last, parent)) = path.split_last()
                    && let Some(p) = get_mut(root, parent)
                {
                    match (p, last) {
                        (Value::Object(m), PathStep::Key(k)) => drop(m.remove(k)),
                        (Value::Array(a), PathStep::Index(i)) if *i < a.len() => drop(a.remove(*i)),
                        _ => {}
                    }
                }
            }
            // Duplicate an array element, or move it.
            2 => {
                if let Some((PathStep::Index(i), parent)) = path.split_last()
                    && let Some(Value::Array(a)) = get_mut(root, parent)
                    && *i < a.len()
                {
                    let item = a[*i].clone();
                    let to = what as usize % (a.len() + 1);
                    a.insert(to, item);
                }
            }
            // Set a known field on an object.
            3 => {
                if let Some(Value::Object(m)) = get_mut(root, &path) {
                    m.insert(word(what), value(what / 3));
                }
            }
            // Insert a random call into some array.
            _ => {
                if let Some(Value::Array(a)) = get_mut(root, &path) {
                    let to = what as usize % (a.len() + 1);
                    a.insert(to, value(call_value(what / 5)));
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), failure_persistence: None, ..ProptestConfig::default() })]

    /// Example traces with their JSON values changed, removed, duplicated, added to.
    #[test]
    fn mutated_traces_never_panic(seed in 0usize..SEEDS.len(), ops in prop::collection::vec((0u32..5, any::<u32>(), any::<u32>()), 1..6)) {
        let texts = seeds();
        let mut root: Value = serde_json::from_str(&texts[seed]).unwrap();
        mutate(&mut root, &ops);
        survive(&root.to_string());
    }

    /// Example traces with bytes flipped, inserted and deleted.
    #[test]
    fn corrupted_bytes_never_panic(seed in 0usize..SEEDS.len(), edits in prop::collection::vec((any::<u32>(), any::<u8>(), 0u8..3), 1..8)) {
        let mut bytes = seeds()[seed].clone().into_bytes();
        for (at, byte, kind) in edits {
            let at = at as usize % (bytes.len() + 1);
            match kind {
                0 if at < bytes.len() => bytes[at] = byte,
                1 => bytes.insert(at, byte),
                _ if at < bytes.len() => drop(bytes.remove(at)),
                _ => {}
            }
        }
        survive(&String::from_utf8_lossy(&bytes));
    }

    /// Traces made of random calls from the vocabulary.
    #[test]
    fn random_calls_never_panic(calls in prop::collection::vec(any::<u32>(), 0..40)) {
        let calls: Vec<Value> = calls.into_iter().map(|n| value(call_value(n))).collect();
        let trace = serde_json::json!({
            "format": "tiler-gl-trace", "version": 1, "config": {"width": 32, "height": 24},
            "frames": [{"calls": calls}]
        });
        survive(&trace.to_string());
    }
}
