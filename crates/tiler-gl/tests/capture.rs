//! Replaying apitrace captures on the context: generated captures (names per EGL context,
//! state reset, texel uploads, errors naming the call) and the shared glmark2 captures against
//! llvmpipe's frames.

#[path = "../../tiler-apitrace/tests/apitrace/writer.rs"]
#[allow(dead_code)]
mod writer;

use std::path::Path;
use std::time::Instant;

use tiler_gl::capture::{CaptureError, ReplayOptions, replay_reader};
use tiler_scene::compare::{REFERENCE_MIN_FRACTION, REFERENCE_TOLERANCE, compare_rgba8, read_png, write_png};
use writer::{W, Writer};

fn e(name: &'static str, value: u32) -> W {
    W::gl_enum(name, value as i64)
}

/// The EGL set-up glmark2 records: a window surface, a context made current, and apitrace's
/// fake viewport with the window's size.
fn begin_context(w: &mut Writer, context: u64, width: u64, height: u64) {
    let attribs = W::Array(vec![W::UInt(0x3098), W::UInt(2), W::UInt(0x3038)]);
    w.call(
        "eglCreateContext",
        &[("dpy", W::Pointer(1)), ("config", W::Pointer(2)), ("share_context", W::Null), ("attrib_list", attribs)],
        Some(W::Pointer(context)),
        false,
    );
    w.call(
        "eglMakeCurrent",
        &[("dpy", W::Pointer(1)), ("draw", W::Pointer(3)), ("read", W::Pointer(3)), ("ctx", W::Pointer(context))],
        Some(W::Bool(true)),
        false,
    );
    let viewport = [("x", W::UInt(0)), ("y", W::UInt(0)), ("width", W::UInt(width)), ("height", W::UInt(height))];
    w.call("glViewport", &viewport, None, true);
}

fn window_surface(w: &mut Writer) {
    w.call(
        "eglCreateWindowSurface",
        &[("dpy", W::Pointer(1)), ("config", W::Pointer(2)), ("win", W::UInt(9)), ("attrib_list", W::Array(vec![]))],
        Some(W::Pointer(3)),
        false,
    );
}

fn clear(w: &mut Writer, rgba: [f32; 4]) {
    let args = [
        ("red", W::Float(rgba[0])),
        ("green", W::Float(rgba[1])),
        ("blue", W::Float(rgba[2])),
        ("alpha", W::Float(rgba[3])),
    ];
    w.call("glClearColor", &args, None, false);
    w.call("glClear", &[("mask", W::UInt(0x4100))], None, false);
}

fn swap(w: &mut Writer) -> u64 {
    w.call("eglSwapBuffers", &[("dpy", W::Pointer(1)), ("surface", W::Pointer(3))], Some(W::Bool(true)), false)
}

fn texture_rgb(w: &mut Writer, name: u64, width: u64, height: u64, texels: Vec<u8>) {
    w.call("glGenTextures", &[("n", W::UInt(1)), ("textures", W::Array(vec![W::UInt(name)]))], None, false);
    w.call("glBindTexture", &[("target", e("GL_TEXTURE_2D", 0x0de1)), ("texture", W::UInt(name))], None, false);
    w.call(
        "glTexImage2D",
        &[
            ("target", e("GL_TEXTURE_2D", 0x0de1)),
            ("level", W::UInt(0)),
            ("internalformat", e("GL_RGB", 0x1907)),
            ("width", W::UInt(width)),
            ("height", W::UInt(height)),
            ("border", W::UInt(0)),
            ("format", e("GL_RGB", 0x1907)),
            ("type", e("GL_UNSIGNED_BYTE", 0x1401)),
            ("pixels", W::Blob(texels)),
        ],
        None,
        false,
    );
}

type Frames = Vec<(u32, u64, u32, u32, Vec<u8>)>;

fn replay(w: &Writer) -> (Result<tiler_gl::capture::Replay, CaptureError>, Frames) {
    let mut frames = Vec::new();
    let result = replay_reader(&w.snappy(1 << 16)[..], &ReplayOptions::default(), &mut |f| {
        frames.push((f.index, f.call, f.width, f.height, f.rgba.to_vec()));
        Ok(())
    });
    (result, frames)
}

fn solid(width: u32, height: u32, rgba: [u8; 4]) -> Vec<u8> {
    rgba.repeat((width * height) as usize)
}

#[test]
fn a_new_context_restarts_names_and_state_and_frames_come_out_in_order() {
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 8, 4);
    // Context A: texture 1, a scissored clear.
    texture_rgb(&mut w, 1, 2, 2, vec![0; 14]);
    w.call("glEnable", &[("cap", e("GL_SCISSOR_TEST", 0x0c11))], None, false);
    let scissor = [("x", W::UInt(0)), ("y", W::UInt(0)), ("width", W::UInt(1)), ("height", W::UInt(1))];
    w.call("glScissor", &scissor, None, false);
    clear(&mut w, [1.0, 0.0, 0.0, 1.0]);
    let first = swap(&mut w);
    w.call("eglDestroyContext", &[("dpy", W::Pointer(1)), ("ctx", W::Pointer(100))], Some(W::Bool(true)), false);
    // Context B: the same name again is a new texture; the scissor test is off again.
    begin_context(&mut w, 200, 8, 4);
    texture_rgb(&mut w, 1, 4, 4, vec![0; 48]);
    clear(&mut w, [0.0, 1.0, 0.0, 1.0]);
    let second = swap(&mut w);

    let (result, frames) = replay(&w);
    let replay = result.unwrap();
    assert_eq!(replay.swaps, [first, second]);
    assert_eq!(frames.len(), 2);
    assert_eq!((frames[0].0, frames[0].1, frames[0].2, frames[0].3), (0, first, 8, 4));
    assert_eq!((frames[1].0, frames[1].1), (1, second));
    // Frame 0: only the bottom-left pixel (GL y up: the last row) was cleared to red.
    assert_eq!(&frames[0].4[(3 * 8) * 4..(3 * 8) * 4 + 4], &[255, 0, 0, 255]);
    // Frame 1: the whole window, scissor reset by the new context.
    assert_eq!(frames[1].4, solid(8, 4, [0, 255, 0, 255]));
    // Context A's texture was deleted with its context; B's is a different object.
    let ctx = &replay.context;
    assert!(ctx.texture_image(1).is_none(), "the destroyed context's texture is deleted");
    assert!(ctx.texture_image(2).is_some());
    assert_eq!(replay.report.frames.len(), 2);
}

#[test]
fn the_report_names_the_capture_call_beside_its_own_numbers() {
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 8, 4);
    w.call(
        "glClearColor",
        &[("red", W::Float(1.0)), ("green", W::Float(0.0)), ("blue", W::Float(0.0)), ("alpha", W::Float(1.0))],
        None,
        false,
    );
    let cleared = w.call("glClear", &[("mask", W::UInt(0x4100))], None, false);
    let swapped = swap(&mut w);

    let (result, _) = replay(&w);
    let report = result.unwrap().report;
    let pass = report.frames[0].passes.last().expect("the window's pass");
    // Numbered in the frame as in a JSON trace, and by the capture's own call numbers.
    assert_eq!(pass.ended_at.capture_call, Some(swapped));
    let text = tiler_gl::text_report(&report);
    assert!(text.contains(&format!("(capture call {cleared}) before any draw")), "{text}");
    assert!(text.contains(&format!("swap at frame 0, call {} (capture call {swapped})", pass.ended_at.call)), "{text}");
    // The next frame's pass starts at its first call.
    let mut w2 = w;
    let first = w2.call("glClear", &[("mask", W::UInt(0x4100))], None, false);
    swap(&mut w2);
    let report = replay(&w2).0.unwrap().report;
    assert_eq!(report.frames[1].passes[0].started_at.capture_call, Some(first));
}

/// A desktop OpenGL context as Qt Quick makes one over EGL: bound to `EGL_OPENGL_API`, with a
/// pbuffer beside the window that it makes current to make objects, a proxy texture query,
/// mip levels allocated without texels, and `glClearDepth`'s double.
fn desktop_context(w: &mut Writer) {
    w.call("eglBindAPI", &[("api", e("EGL_OPENGL_API", 0x30a2))], Some(W::Bool(true)), false);
    window_surface(w);
    begin_context(w, 100, 8, 4);
    let attribs = W::Array(vec![W::UInt(0x3057), W::UInt(2), W::UInt(0x3056), W::UInt(2), W::UInt(0x3038)]);
    w.call(
        "eglCreatePbufferSurface",
        &[("dpy", W::Pointer(1)), ("config", W::Pointer(2)), ("attrib_list", attribs)],
        Some(W::Pointer(4)),
        false,
    );
    let current = |w: &mut Writer, surface: u64| {
        let args = [
            ("dpy", W::Pointer(1)),
            ("draw", W::Pointer(surface)),
            ("read", W::Pointer(surface)),
            ("ctx", W::Pointer(100)),
        ];
        w.call("eglMakeCurrent", &args, Some(W::Bool(true)), false)
    };
    current(w, 4);
    texture_rgb(w, 1, 4, 4, vec![0; 48]);
    let image = |w: &mut Writer, target: (&'static str, u32), level: u64, size: u64, format: (&'static str, u32)| {
        let args = [
            ("target", e(target.0, target.1)),
            ("level", W::UInt(level)),
            ("internalformat", e("GL_RGBA", 0x1908)),
            ("width", W::UInt(size)),
            ("height", W::UInt(size)),
            ("border", W::UInt(0)),
            ("format", e(format.0, format.1)),
            ("type", e("GL_UNSIGNED_BYTE", 0x1401)),
            ("pixels", W::Null),
        ];
        w.call("glTexImage2D", &args, None, false)
    };
    image(w, ("GL_PROXY_TEXTURE_2D", 0x8064), 0, 1 << 14, ("GL_RGBA", 0x1908));
    image(w, ("GL_TEXTURE_2D", 0x0de1), 0, 4, ("GL_BGRA", 0x80e1));
    image(w, ("GL_TEXTURE_2D", 0x0de1), 1, 2, ("GL_RGBA", 0x1908));
    current(w, 3);
}

#[test]
fn a_desktop_context_drawing_with_the_calls_gles_has_replays() {
    let mut w = Writer::new(6);
    desktop_context(&mut w);
    w.call("glClearDepth", &[("depth", W::Double(0.5))], None, false);
    clear(&mut w, [0.0, 0.0, 1.0, 1.0]);
    let swapped = swap(&mut w);
    let (result, frames) = replay(&w);
    let replayed = result.unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(replayed.swaps, [swapped]);
    assert_eq!(frames[0].4, solid(8, 4, [0, 0, 255, 255]));

    // Drawing while the pbuffer is current is refused, naming the call.
    let mut w = Writer::new(6);
    desktop_context(&mut w);
    let args = [("dpy", W::Pointer(1)), ("draw", W::Pointer(4)), ("read", W::Pointer(4)), ("ctx", W::Pointer(100))];
    w.call("eglMakeCurrent", &args, Some(W::Bool(true)), false);
    let cleared = w.call("glClear", &[("mask", W::UInt(0x4000))], None, false);
    let e = replay(&w).0.err().expect("a clear of the pbuffer fails").to_string();
    assert!(e.contains(&format!("call {cleared}")) && e.contains("pbuffer"), "{e}");
}

#[test]
fn rgb_texels_reach_the_window_upright_through_a_blit() {
    // A 2×2 RGB texture (rows bottom first, aligned to 4 bytes), attached to a framebuffer
    // and blitted onto the 2×2 window.
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 2, 2);
    let texels = vec![
        10, 20, 30, 40, 50, 60, 0, 0, // bottom row + padding
        70, 80, 90, 100, 110, 120, 0, 0, // top row + padding
    ];
    texture_rgb(&mut w, 5, 2, 2, texels);
    blit_texture_to_window(&mut w, 5, 2, 2);
    swap(&mut w);
    let (result, frames) = replay(&w);
    result.unwrap();
    // Top row of the picture first.
    assert_eq!(frames[0].4, [70, 80, 90, 255, 100, 110, 120, 255, 10, 20, 30, 255, 40, 50, 60, 255]);
}

/// Blits the texture `name` (`width × height`) onto the same-sized window through
/// framebuffer 3.
fn blit_texture_to_window(w: &mut Writer, name: u64, width: u64, height: u64) {
    w.call("glGenFramebuffers", &[("n", W::UInt(1)), ("framebuffers", W::Array(vec![W::UInt(3)]))], None, false);
    w.call(
        "glBindFramebuffer",
        &[("target", e("GL_READ_FRAMEBUFFER", 0x8ca8)), ("framebuffer", W::UInt(3))],
        None,
        false,
    );
    w.call(
        "glFramebufferTexture2D",
        &[
            ("target", e("GL_READ_FRAMEBUFFER", 0x8ca8)),
            ("attachment", e("GL_COLOR_ATTACHMENT0", 0x8ce0)),
            ("textarget", e("GL_TEXTURE_2D", 0x0de1)),
            ("texture", W::UInt(name)),
            ("level", W::UInt(0)),
        ],
        None,
        false,
    );
    let corners = [("X0", 0), ("Y0", 0), ("X1", width), ("Y1", height)];
    let names: Vec<String> =
        ["src", "dst"].iter().flat_map(|p| corners.iter().map(move |(c, _)| format!("{p}{c}"))).collect();
    let mut args: Vec<(&str, W)> =
        names.iter().zip(corners.iter().chain(&corners)).map(|(n, &(_, v))| (n.as_str(), W::UInt(v))).collect();
    args.push(("mask", W::UInt(0x4000)));
    args.push(("filter", e("GL_NEAREST", 0x2600)));
    w.call("glBlitFramebuffer", &args, None, false);
}

#[test]
fn many_calls_and_a_large_upload_replay_in_order_up_to_an_error() {
    // Calls go from the reader to the replay in batches: a frame of more calls than a batch
    // holds, an upload larger than a batch's bytes (an odd number of rows, turned over in
    // place), then frames each of a few calls and an unsupported call after the last swap.
    let (width, height) = (300u64, 301u64);
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, width, height);
    for k in 0..300 {
        clear(&mut w, [k as f32 / 300.0, 0.0, 0.0, 1.0]);
    }
    // Row y (from the bottom) of texel x: (x, y, x + y) modulo 256; rows of 900 bytes, which
    // the default alignment of 4 leaves unpadded.
    let texels: Vec<u8> =
        (0..height).flat_map(|y| (0..width).flat_map(move |x| [x as u8, y as u8, (x + y) as u8])).collect();
    assert!(texels.len() > 256 << 10, "larger than a batch's bytes");
    texture_rgb(&mut w, 5, width, height, texels);
    blit_texture_to_window(&mut w, 5, width, height);
    swap(&mut w);
    let colors = [[0.0, 1.0, 0.0, 1.0], [0.0, 0.0, 1.0, 1.0], [1.0, 1.0, 1.0, 1.0]];
    w.call("glBindFramebuffer", &[("target", e("GL_FRAMEBUFFER", 0x8d40)), ("framebuffer", W::UInt(0))], None, false);
    for rgba in colors {
        clear(&mut w, rgba);
        swap(&mut w);
    }
    let call = w.call("glEnable", &[("cap", e("GL_SAMPLE_ALPHA_TO_COVERAGE", 0x809e))], None, false);
    let (result, frames) = replay(&w);
    let error = result.err().expect("alpha to coverage is not supported");
    assert_eq!(error.call(), Some(call), "{error}");
    assert_eq!(frames.iter().map(|f| f.0).collect::<Vec<_>>(), [0, 1, 2, 3]);
    // The blit: the window's top row is the texture's last (GL's rows go up).
    let first = &frames[0].4;
    for y in 0..height {
        for x in [0, 1, width / 2, width - 1] {
            let gl_row = height - 1 - y;
            let at = ((y * width + x) * 4) as usize;
            let expected = [x as u8, gl_row as u8, (x + gl_row) as u8, 255];
            assert_eq!(first[at..at + 4], expected, "pixel ({x}, {y}) from the top");
        }
    }
    for (frame, rgba) in frames[1..].iter().zip(colors) {
        let expected = rgba.map(|c| (c * 255.0) as u8);
        assert!(frame.4.chunks_exact(4).all(|p| p == expected), "frame {} is {expected:?}", frame.0);
    }
}

/// A framebuffer whose colour is a multisampled RGBA8 renderbuffer of `samples` samples
/// (`glRenderbufferStorageMultisample`), cleared to red and blitted onto the 8×4 window.
/// Returns the storage call's number.
fn multisampled_renderbuffer_capture(w: &mut Writer, samples: u64) -> u64 {
    window_surface(w);
    begin_context(w, 100, 8, 4);
    let renderbuffer = e("GL_RENDERBUFFER", 0x8d41);
    let framebuffer = e("GL_FRAMEBUFFER", 0x8d40);
    w.call("glGenRenderbuffers", &[("n", W::UInt(1)), ("renderbuffers", W::Array(vec![W::UInt(1)]))], None, false);
    w.call("glBindRenderbuffer", &[("target", renderbuffer.clone()), ("renderbuffer", W::UInt(1))], None, false);
    let storage = w.call(
        "glRenderbufferStorageMultisample",
        &[
            ("target", renderbuffer.clone()),
            ("samples", W::UInt(samples)),
            ("internalformat", e("GL_RGBA8", 0x8058)),
            ("width", W::UInt(8)),
            ("height", W::UInt(4)),
        ],
        None,
        false,
    );
    w.call("glGenFramebuffers", &[("n", W::UInt(1)), ("framebuffers", W::Array(vec![W::UInt(3)]))], None, false);
    w.call("glBindFramebuffer", &[("target", framebuffer.clone()), ("framebuffer", W::UInt(3))], None, false);
    w.call(
        "glFramebufferRenderbuffer",
        &[
            ("target", framebuffer.clone()),
            ("attachment", e("GL_COLOR_ATTACHMENT0", 0x8ce0)),
            ("renderbuffertarget", renderbuffer),
            ("renderbuffer", W::UInt(1)),
        ],
        None,
        false,
    );
    clear(w, [1.0, 0.0, 0.0, 1.0]);
    w.call(
        "glBindFramebuffer",
        &[("target", e("GL_DRAW_FRAMEBUFFER", 0x8ca9)), ("framebuffer", W::UInt(0))],
        None,
        false,
    );
    w.call(
        "glBindFramebuffer",
        &[("target", e("GL_READ_FRAMEBUFFER", 0x8ca8)), ("framebuffer", W::UInt(3))],
        None,
        false,
    );
    let rect = |a, b, c, d| [W::UInt(a), W::UInt(b), W::UInt(c), W::UInt(d)];
    let [s0, s1, s2, s3] = rect(0, 0, 8, 4);
    let [d0, d1, d2, d3] = rect(0, 0, 8, 4);
    w.call(
        "glBlitFramebuffer",
        &[
            ("srcX0", s0),
            ("srcY0", s1),
            ("srcX1", s2),
            ("srcY1", s3),
            ("dstX0", d0),
            ("dstY0", d1),
            ("dstX1", d2),
            ("dstY1", d3),
            ("mask", W::UInt(0x4000)),
            ("filter", e("GL_NEAREST", 0x2600)),
        ],
        None,
        false,
    );
    swap(w);
    storage
}

#[test]
fn multisampled_renderbuffers_get_the_sample_count_gl_grants() {
    // Asked → granted: at least as many, no more than the next supported count (GL ES 3.0
    // §4.4.2.1); 16 is the most.
    for (asked, granted) in [(16, 16), (9, 16), (3, 4), (0, 1)] {
        let mut w = Writer::new(6);
        multisampled_renderbuffer_capture(&mut w, asked);
        let (result, frames) = replay(&w);
        let replay = result.unwrap_or_else(|e| panic!("{asked} samples: {e}"));
        assert_eq!(frames[0].4, solid(8, 4, [255, 0, 0, 255]), "{asked} samples");
        let pass = replay.report.passes().find(|p| p.framebuffer != 0).expect("the renderbuffer's pass");
        let color = pass.attachment(tiler_gl::report::Slot::Color(0)).expect("a colour attachment");
        assert_eq!(color.samples, granted, "{asked} samples asked");
        // Stored at every sample: 8 × 4 pixels × granted samples × 4 bytes.
        assert_eq!(color.store_bytes, 8 * 4 * granted as u64 * 4, "{asked} samples asked");
    }
    let mut w = Writer::new(6);
    let call = multisampled_renderbuffer_capture(&mut w, 17);
    let (result, frames) = replay(&w);
    let error = result.err().expect("17 samples is more than GL_MAX_SAMPLES");
    assert_eq!(error.call(), Some(call));
    assert!(error.to_string().contains("GL_MAX_SAMPLES"), "{error}");
    assert!(frames.is_empty());
}

#[test]
fn an_unsupported_call_fails_with_its_number_and_function() {
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 8, 4);
    clear(&mut w, [0.0; 4]);
    let call = w.call("glEnable", &[("cap", e("GL_SAMPLE_ALPHA_TO_COVERAGE", 0x809e))], None, false);
    swap(&mut w);
    let (result, frames) = replay(&w);
    let error = result.err().expect("alpha to coverage is not supported");
    assert_eq!(error.call(), Some(call));
    let message = error.to_string();
    assert!(message.contains(&format!("call {call}")) && message.contains("`glEnable`"), "{message}");
    assert!(frames.is_empty());
}

#[test]
fn a_call_neither_known_nor_ignored_fails_with_its_number_and_function() {
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 8, 4);
    let call = w.call("glTexImage3D", &[("target", W::UInt(0x806f))], None, false);
    let (result, _) = replay(&w);
    let message = result.err().expect("an unknown call").to_string();
    assert!(message.contains(&format!("call {call}")) && message.contains("glTexImage3D"), "{message}");
}

#[test]
fn ignored_calls_change_nothing_and_a_missing_window_size_is_an_error() {
    let mut w = Writer::new(6);
    window_surface(&mut w);
    let attribs = W::Array(vec![W::UInt(0x3038)]);
    w.call(
        "eglCreateContext",
        &[("dpy", W::Pointer(1)), ("config", W::Pointer(2)), ("share_context", W::Null), ("attrib_list", attribs)],
        Some(W::Pointer(100)),
        false,
    );
    w.call(
        "eglMakeCurrent",
        &[("dpy", W::Pointer(1)), ("draw", W::Pointer(3)), ("read", W::Pointer(3)), ("ctx", W::Pointer(100))],
        Some(W::Bool(true)),
        false,
    );
    w.call("glGetError", &[], Some(W::UInt(0)), false);
    let call = w.call("glClear", &[("mask", W::UInt(0x4000))], None, false);
    let (result, _) = replay(&w);
    let error = result.err().expect("no window size");
    assert_eq!(error.call(), Some(call));
    assert!(error.to_string().contains("window"), "{error}");
}

// ---- the shared glmark2 captures -------------------------------------------------------

const SCENES: [&str; 10] =
    ["buffer", "build", "bump", "conditionals", "desktop", "effect2d", "pulsar", "shading", "shadow", "texture"];

/// llvmpipe's frames of a scene, in presentation order: (swap call, path).
fn references(dir: &Path, scene: &str) -> Vec<(u64, std::path::PathBuf)> {
    let mut refs: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|entry| {
            let path = entry.ok()?.path();
            let stem = path.file_stem()?.to_str()?.to_string();
            let (name, call) = stem.rsplit_once('-')?;
            (name == scene && path.extension()? == "png").then(|| Some((call.parse().ok()?, path.clone())))?
        })
        .collect();
    refs.sort();
    refs
}

/// Replays a scene and compares every frame; the problems found, if any.
fn check_scene(traces: &Path, reference: &Path, scene: &str) -> Result<(), String> {
    let refs = references(reference, scene);
    if refs.is_empty() {
        return Err(format!("{scene}: no reference frames"));
    }
    let mut problems = Vec::new();
    let started = Instant::now();
    let result =
        tiler_gl::capture::replay_file(traces.join(format!("{scene}.trace")), &ReplayOptions::default(), &mut |f| {
            let Some((call, path)) = refs.get(f.index as usize) else {
                return Err(format!("frame {} has no reference", f.index));
            };
            if *call != f.call {
                problems.push(format!("frame {} presented at call {}, llvmpipe's at {call}", f.index, f.call));
            }
            let (w, h, expected) = read_png(path)?;
            if (w, h) != (f.width, f.height) {
                return Err(format!("frame {}: {}×{}, reference {w}×{h}", f.index, f.width, f.height));
            }
            // eglretrace's snapshots are RGB: the reference says nothing of alpha (buffer's
            // triangles write 0.8 there), so only colour is compared.
            let mut ours = f.rgba.to_vec();
            ours.iter_mut().skip(3).step_by(4).for_each(|a| *a = 255);
            let c = compare_rgba8(&ours, &expected, w, h, REFERENCE_TOLERANCE);
            if !c.passes(REFERENCE_MIN_FRACTION) {
                let out = tiler_test_support::output_dir().join(format!("capture-{scene}-{:04}", f.index));
                write_png(&out.with_extension("diff.png"), w, h, &c.difference_image)?;
                write_png(&out.with_extension("png"), w, h, f.rgba)?;
                problems.push(format!(
                    "frame {}: {:.2}% of pixels within {REFERENCE_TOLERANCE}/255 (max difference {}); see {}",
                    f.index,
                    c.fraction_within() * 100.0,
                    c.max_difference,
                    out.display()
                ));
            }
            Ok(())
        });
    let replay = result.map_err(|e| format!("{scene}: {e}"))?;
    eprintln!("{scene}: {} frames replayed in {:.2?}", replay.swaps.len(), started.elapsed());
    if replay.swaps.len() != refs.len() {
        problems.push(format!("{} frames presented, llvmpipe presented {}", replay.swaps.len(), refs.len()));
    }
    if problems.is_empty() { Ok(()) } else { Err(format!("{scene}: {}", problems.join("; "))) }
}

#[test]
fn glmark2_captures_replay_and_match_llvmpipe() {
    let (Some(traces), Some(reference)) = (tiler_test_support::traces_dir(), tiler_test_support::reference_dir())
    else {
        return;
    };
    let (traces, reference) = (traces.join("glmark2"), reference.join("glmark2"));
    let mut failures = Vec::new();
    for scene in SCENES {
        match check_scene(&traces, &reference, scene) {
            Ok(()) => eprintln!("{scene}: every frame matches llvmpipe"),
            Err(problem) => failures.push(problem),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A program drawing a full-window triangle in the colour of `colors[2]`, set by one
/// `glUniform4fv` of three elements at the location recorded for `colors`; then
/// `extra` (calls after the draw) and a swap.
fn uniform_array_capture(before_draw: impl FnOnce(&mut Writer), extra: impl FnOnce(&mut Writer)) -> (Writer, u64) {
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 4, 4);
    let fragment = "precision mediump float;\nuniform vec4 colors[3];\nvoid main() { gl_FragColor = colors[2]; }\n";
    full_window_program(
        &mut w,
        "attribute vec2 where;\nvoid main() { gl_Position = vec4(where, 0.0, 1.0); }\n",
        fragment,
    );
    w.call("glGetUniformLocation", &[("program", W::UInt(7)), ("name", W::Str("colors"))], Some(W::UInt(3)), false);
    let values = [1.0f32, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 0.2, 0.4, 0.6, 1.0].map(W::Float).to_vec();
    w.call(
        "glUniform4fv",
        &[("location", W::UInt(3)), ("count", W::UInt(3)), ("value", W::Array(values))],
        None,
        false,
    );
    before_draw(&mut w);
    draw_triangle(&mut w);
    extra(&mut w);
    let swap = swap(&mut w);
    (w, swap)
}

/// A full-window triangle in buffer 1, read by attribute `where` (recorded at location 5) of
/// program 7, linked from `vertex` and `fragment` and in use.
fn full_window_program(w: &mut Writer, vertex: &'static str, fragment: &'static str) {
    link_program(w, vertex, fragment);
    use_program_on_full_window_triangle(w);
}

/// Program 7 made of shaders 2 and 3 from `vertex` and `fragment`, linked, not used.
fn link_program(w: &mut Writer, vertex: &'static str, fragment: &'static str) {
    w.call("glCreateProgram", &[], Some(W::UInt(7)), false);
    let shaders = [(0x8b31, "GL_VERTEX_SHADER", 2, vertex), (0x8b30, "GL_FRAGMENT_SHADER", 3, fragment)];
    for (kind, kind_name, shader, source) in shaders {
        w.call("glCreateShader", &[("type", e(kind_name, kind))], Some(W::UInt(shader)), false);
        let strings = W::Array(vec![W::Str(source)]);
        w.call(
            "glShaderSource",
            &[("shader", W::UInt(shader)), ("count", W::UInt(1)), ("string", strings), ("length", W::Null)],
            None,
            false,
        );
        w.call("glCompileShader", &[("shader", W::UInt(shader))], None, false);
        w.call("glAttachShader", &[("program", W::UInt(7)), ("shader", W::UInt(shader))], None, false);
    }
    w.call("glLinkProgram", &[("program", W::UInt(7))], None, false);
}

/// Program 7 used, its attribute `where` fed the full-window triangle from buffer 1.
fn use_program_on_full_window_triangle(w: &mut Writer) {
    let triangle: Vec<u8> = [-1.0f32, -1.0, 3.0, -1.0, -1.0, 3.0].iter().flat_map(|v| v.to_le_bytes()).collect();
    w.call("glGenBuffers", &[("n", W::UInt(1)), ("buffers", W::Array(vec![W::UInt(1)]))], None, false);
    w.call("glBindBuffer", &[("target", e("GL_ARRAY_BUFFER", 0x8892)), ("buffer", W::UInt(1))], None, false);
    w.call(
        "glBufferData",
        &[
            ("target", e("GL_ARRAY_BUFFER", 0x8892)),
            ("size", W::UInt(24)),
            ("data", W::Blob(triangle)),
            ("usage", e("GL_STATIC_DRAW", 0x88e4)),
        ],
        None,
        false,
    );
    w.call("glUseProgram", &[("program", W::UInt(7))], None, false);
    w.call("glGetAttribLocation", &[("program", W::UInt(7)), ("name", W::Str("where"))], Some(W::UInt(5)), false);
    w.call("glEnableVertexAttribArray", &[("index", W::UInt(5))], None, false);
    w.call(
        "glVertexAttribPointer",
        &[
            ("index", W::UInt(5)),
            ("size", W::UInt(2)),
            ("type", e("GL_FLOAT", 0x1406)),
            ("normalized", W::Bool(false)),
            ("stride", W::UInt(0)),
            ("pointer", W::Null),
        ],
        None,
        false,
    );
}

/// `glDrawArrays(GL_TRIANGLES, 0, 3)`: the full-window triangle of [`full_window_program`].
fn draw_triangle(w: &mut Writer) {
    let draw = [("mode", e("GL_TRIANGLES", 4)), ("first", W::UInt(0)), ("count", W::UInt(3))];
    w.call("glDrawArrays", &draw, None, false);
}

#[test]
fn glsl_programs_link_from_the_capture_and_uniform_arrays_set_consecutive_elements() {
    let (w, _) = uniform_array_capture(|_| {}, |_| {});
    let (result, frames) = replay(&w);
    result.unwrap();
    // colors[2] = (0.2, 0.4, 0.6, 1.0), through the attribute at the location the capture
    // recorded (5).
    assert_eq!(frames[0].4, solid(4, 4, [51, 102, 153, 255]));
}

#[test]
fn a_uniform_location_never_returned_is_an_error_naming_the_call() {
    let mut call = 0;
    let (w, _) = uniform_array_capture(
        |_| {},
        |w| {
            call = w.call("glUniform1f", &[("location", W::UInt(9)), ("v0", W::Float(1.0))], None, false);
        },
    );
    let (result, _) = replay(&w);
    let error = result.err().expect("location 9 was never returned");
    assert_eq!(error.call(), Some(call));
    let message = error.to_string();
    assert!(message.contains("`glUniform1f`") && message.contains("location 9"), "{message}");
}

fn tex_parameter(w: &mut Writer, pname: (&'static str, u32), value: (&'static str, u32)) {
    tex_parameter_call(w, pname, value);
}

/// [`tex_parameter`], returning the call's number.
fn tex_parameter_call(w: &mut Writer, pname: (&'static str, u32), value: (&'static str, u32)) -> u64 {
    w.call(
        "glTexParameteri",
        &[("target", e("GL_TEXTURE_2D", 0x0de1)), ("pname", e(pname.0, pname.1)), ("param", e(value.0, value.1))],
        None,
        false,
    )
}

#[test]
fn a_mipmap_filter_without_levels_is_an_incomplete_texture_not_an_error() {
    let trilinear = |w: &mut Writer| {
        texture_rgb(w, 4, 4, 4, vec![200; 48]);
        tex_parameter(w, ("GL_TEXTURE_MIN_FILTER", 0x2801), ("GL_LINEAR_MIPMAP_LINEAR", 0x2703));
        tex_parameter(w, ("GL_TEXTURE_MAG_FILTER", 0x2800), ("GL_LINEAR", 0x2601));
    };
    // Bound but not sampled by the program: GL draws, and so does the replay.
    let (w, _) = uniform_array_capture(trilinear, |_| {});
    let (result, frames) = replay(&w);
    result.unwrap();
    assert_eq!(frames[0].4, solid(4, 4, [51, 102, 153, 255]));

    let (w, _) = uniform_array_capture(
        |w| {
            trilinear(w);
            w.call("glGenerateMipmap", &[("target", e("GL_TEXTURE_2D", 0x0de1))], None, false);
        },
        |_| {},
    );
    let (result, frames) = replay(&w);
    result.unwrap();
    assert_eq!(frames[0].4, solid(4, 4, [51, 102, 153, 255]));
}

#[test]
fn mip_levels_uploaded_by_the_application_are_sampled() {
    // A 4×4 texture with levels 1 (2×2) and 2 (1×1) given by glTexImage2D, read at level 2
    // by a vertex shader's texture2DLod: level 2's colour, as uploaded (GL_RGB, alpha 1).
    let level = |w: &mut Writer, level: u64, size: u64, rgb: [u8; 3]| {
        // Rows padded to GL_UNPACK_ALIGNMENT's default, 4.
        let mut row = rgb.repeat(size as usize);
        row.resize(row.len().next_multiple_of(4), 0);
        let texels = row.repeat(size as usize);
        let args = [
            ("target", e("GL_TEXTURE_2D", 0x0de1)),
            ("level", W::UInt(level)),
            ("internalformat", e("GL_RGB", 0x1907)),
            ("width", W::UInt(size)),
            ("height", W::UInt(size)),
            ("border", W::UInt(0)),
            ("format", e("GL_RGB", 0x1907)),
            ("type", e("GL_UNSIGNED_BYTE", 0x1401)),
            ("pixels", W::Blob(texels)),
        ];
        w.call("glTexImage2D", &args, None, false)
    };
    let capture = |levels: &[(u64, u64, [u8; 3])]| {
        let mut w = Writer::new(6);
        window_surface(&mut w);
        begin_context(&mut w, 100, 4, 4);
        texture_rgb(&mut w, 4, 4, 4, vec![10; 48]);
        let mut last = 0;
        for &(l, size, rgb) in levels {
            last = level(&mut w, l, size, rgb);
        }
        tex_parameter(&mut w, ("GL_TEXTURE_MIN_FILTER", 0x2801), ("GL_NEAREST_MIPMAP_NEAREST", 0x2700));
        let vertex = "attribute vec2 where;\nuniform sampler2D height;\nvarying vec4 fetched;\n\
                      void main() { fetched = texture2DLod(height, vec2(0.5, 0.5), 2.0); gl_Position = vec4(where, 0.0, 1.0); }\n";
        let fragment = "precision mediump float;\nvarying vec4 fetched;\nvoid main() { gl_FragColor = fetched; }\n";
        full_window_program(&mut w, vertex, fragment);
        let draw = [("mode", e("GL_TRIANGLES", 4)), ("first", W::UInt(0)), ("count", W::UInt(3))];
        w.call("glDrawArrays", &draw, None, false);
        swap(&mut w);
        (w, last)
    };
    let (w, _) = capture(&[(1, 2, [90, 90, 90]), (2, 1, [30, 60, 120])]);
    let (result, frames) = replay(&w);
    result.unwrap();
    assert_eq!(frames[0].4, solid(4, 4, [30, 60, 120, 255]));
    // A level of the wrong size fails at its call.
    let (w, call) = capture(&[(1, 3, [90, 90, 90])]);
    let (result, _) = replay(&w);
    let error = result.err().expect("a 3×3 level 1 of a 4×4 texture");
    assert_eq!(error.call(), Some(call));
    assert!(error.to_string().contains("must be 2×2"), "{error}");
}

#[test]
fn max_level_zero_makes_a_mipmap_filter_sample_level_zero_and_compare_mode_leaves_sampler2d_alone() {
    // A 4×4 texture without levels and a trilinear filter read at level 2: incomplete (black)
    // in GL ES 2.0, but complete with GL_TEXTURE_MAX_LEVEL 0, which samples level 0.
    let capture = |max_level: Option<u64>, compare: bool| {
        let mut w = Writer::new(6);
        window_surface(&mut w);
        begin_context(&mut w, 100, 4, 4);
        texture_rgb(&mut w, 4, 4, 4, vec![40; 48]);
        tex_parameter(&mut w, ("GL_TEXTURE_MIN_FILTER", 0x2801), ("GL_LINEAR_MIPMAP_LINEAR", 0x2703));
        let int_parameter = |w: &mut Writer, pname: (&'static str, u32), value: u64| {
            let args =
                [("target", e("GL_TEXTURE_2D", 0x0de1)), ("pname", e(pname.0, pname.1)), ("param", W::UInt(value))];
            w.call("glTexParameteri", &args, None, false)
        };
        // Defaults apps set explicitly change nothing.
        int_parameter(&mut w, ("GL_TEXTURE_BASE_LEVEL", 0x813c), 0);
        tex_parameter(&mut w, ("GL_TEXTURE_WRAP_R", 0x8072), ("GL_CLAMP_TO_EDGE", 0x812f));
        tex_parameter(&mut w, ("GL_TEXTURE_SWIZZLE_R", 0x8e42), ("GL_RED", 0x1903));
        let mut last = 0;
        if let Some(level) = max_level {
            last = int_parameter(&mut w, ("GL_TEXTURE_MAX_LEVEL", 0x813d), level);
        }
        if compare {
            last =
                tex_parameter_call(&mut w, ("GL_TEXTURE_COMPARE_MODE", 0x884c), ("GL_COMPARE_REF_TO_TEXTURE", 0x884e));
        }
        let vertex = "attribute vec2 where;\nuniform sampler2D height;\nvarying vec4 fetched;\n\
                      void main() { fetched = texture2DLod(height, vec2(0.5, 0.5), 2.0); gl_Position = vec4(where, 0.0, 1.0); }\n";
        let fragment = "precision mediump float;\nvarying vec4 fetched;\nvoid main() { gl_FragColor = fetched; }\n";
        full_window_program(&mut w, vertex, fragment);
        let draw = [("mode", e("GL_TRIANGLES", 4)), ("first", W::UInt(0)), ("count", W::UInt(3))];
        let draw_call = w.call("glDrawArrays", &draw, None, false);
        swap(&mut w);
        (w, last, draw_call)
    };
    let (w, ..) = capture(None, false);
    let (result, frames) = replay(&w);
    result.unwrap();
    assert_eq!(frames[0].4, solid(4, 4, [0, 0, 0, 255]), "incomplete without levels");
    let (w, ..) = capture(Some(0), false);
    let (result, frames) = replay(&w);
    result.unwrap();
    assert_eq!(frames[0].4, solid(4, 4, [40, 40, 40, 255]), "level 0 with GL_TEXTURE_MAX_LEVEL 0");
    // A max level inside the chain is refused where the texture is drawn with.
    let (w, _, draw_call) = capture(Some(1), false);
    let error = replay(&w).0.err().expect("max level 1 of a 3-level chain");
    assert_eq!(error.call(), Some(draw_call));
    assert!(error.to_string().contains("GL_TEXTURE_MAX_LEVEL 1"), "{error}");
    // Compare mode matters to shadow samplers only: a sampler2D reads the texels.
    let (w, ..) = capture(Some(0), true);
    let (result, frames) = replay(&w);
    result.unwrap();
    assert_eq!(frames[0].4, solid(4, 4, [40, 40, 40, 255]), "compare mode with a sampler2D");
}

#[test]
fn vertex_shader_fetches_are_filtered_as_the_texture_says() {
    // A height map read in the vertex shader, as glmark2's terrain reads one: a 2×1 texture
    // (black, grey 200) fetched half way between its texels. GL samples at level of detail 0,
    // so the magnification filter decides: linear blends the two, nearest takes the second.
    let capture = |mag: (&'static str, u32)| {
        let mut w = Writer::new(6);
        window_surface(&mut w);
        begin_context(&mut w, 100, 4, 4);
        texture_rgb(&mut w, 4, 2, 1, vec![0, 0, 0, 200, 200, 200, 0, 0]);
        tex_parameter(&mut w, ("GL_TEXTURE_MIN_FILTER", 0x2801), mag);
        tex_parameter(&mut w, ("GL_TEXTURE_MAG_FILTER", 0x2800), mag);
        let vertex = "attribute vec2 where;\nuniform sampler2D height;\nvarying vec4 fetched;\n\
                      void main() { fetched = texture2D(height, vec2(0.5, 0.5)); gl_Position = vec4(where, 0.0, 1.0); }\n";
        let fragment = "precision mediump float;\nvarying vec4 fetched;\nvoid main() { gl_FragColor = fetched; }\n";
        full_window_program(&mut w, vertex, fragment);
        let draw = [("mode", e("GL_TRIANGLES", 4)), ("first", W::UInt(0)), ("count", W::UInt(3))];
        w.call("glDrawArrays", &draw, None, false);
        swap(&mut w);
        let (result, frames) = replay(&w);
        result.unwrap();
        frames[0].4.clone()
    };
    assert_eq!(capture(("GL_LINEAR", 0x2601)), solid(4, 4, [100, 100, 100, 255]));
    assert_eq!(capture(("GL_NEAREST", 0x2600)), solid(4, 4, [200, 200, 200, 255]));
}

// ---- our own GLES2 probe's captures (tests/data/gles2-probe, see its README) ---------------

/// The frames of one probe capture replayed with `config`.
/// A capture of one of our probes: `probe` is its directory under `tests/data`.
fn replay_probe_in(probe: &str, scene: &str, config: tiler_gl::ContextConfig) -> Result<Frames, String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(probe).join(format!("{scene}.trace"));
    let mut frames = Vec::new();
    let options = ReplayOptions { config, ..ReplayOptions::default() };
    tiler_gl::capture::replay_file(path, &options, &mut |f| {
        frames.push((f.index, f.call, f.width, f.height, f.rgba.to_vec()));
        Ok(())
    })
    .map_err(|e| format!("{scene}: {e}"))?;
    Ok(frames)
}

/// Replays a probe capture, compares its one frame with llvmpipe's and checks that every
/// backend, two tile sizes and two thread counts give the same bytes.
fn check_probe(scene: &str) {
    check_probe_in("gles2-probe", scene);
}

/// [`check_probe`] of a capture of the probe in `tests/data/{probe}`.
fn check_probe_in(probe: &str, scene: &str) {
    let reference = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(probe).join(format!("{scene}.png"));
    let base = ReplayOptions::default().config;
    let frames = replay_probe_in(probe, scene, base.clone()).unwrap();
    assert_eq!(frames.len(), 1, "{scene}: one frame");
    let (_, _, w, h, rgba) = &frames[0];
    let (rw, rh, expected) = read_png(&reference).unwrap();
    assert_eq!((rw, rh), (*w, *h), "{scene}: size");
    let mut ours = rgba.clone();
    ours.iter_mut().skip(3).step_by(4).for_each(|a| *a = 255);
    let c = compare_rgba8(&ours, &expected, *w, *h, REFERENCE_TOLERANCE);
    eprintln!("{scene}: {:.3}% within, max {}", c.fraction_within() * 100.0, c.max_difference);
    if !c.passes(REFERENCE_MIN_FRACTION) {
        let out = tiler_test_support::output_dir().join(format!("probe-{scene}"));
        write_png(&out.with_extension("diff.png"), *w, *h, &c.difference_image).unwrap();
        write_png(&out.with_extension("png"), *w, *h, rgba).unwrap();
        panic!(
            "{scene}: {:.2}% of pixels within {REFERENCE_TOLERANCE}/255 of llvmpipe (max difference {}); see {}",
            c.fraction_within() * 100.0,
            c.max_difference,
            out.display()
        );
    }
    for backend in [tiler::Backend::Tbr, tiler::Backend::Tbdr, tiler::Backend::Imr] {
        for (tile, threads) in [(16, 1), (32, 2)] {
            let config =
                tiler_gl::ContextConfig { backend, tile_width: tile, tile_height: tile, threads, ..base.clone() };
            let other = replay_probe_in(probe, scene, config).unwrap();
            assert!(other[0].4 == *rgba, "{scene}: {backend:?} with {tile}×{tile} tiles differs");
        }
    }
}

#[test]
fn probe_separate_filters_and_wraps_match_llvmpipe() {
    check_probe("sampler");
}

#[test]
fn probe_incomplete_textures_match_llvmpipe() {
    check_probe("incomplete");
}

#[test]
fn probe_separate_front_and_back_stencil_matches_llvmpipe() {
    check_probe("stencil");
}

#[test]
fn probe_byte_indices_in_a_buffer_and_a_deleted_program_in_use_match_llvmpipe() {
    check_probe("indices");
}

#[test]
fn probe_polygon_offset_matches_llvmpipe() {
    check_probe("offset");
}

#[test]
fn probe_copy_tex_image_matches_llvmpipe() {
    check_probe("copy");
}

#[test]
fn probe_lines_match_llvmpipe() {
    check_probe("lines");
}

#[test]
fn deleted_shaders_and_a_deleted_program_live_while_attached_and_in_use_then_go() {
    let deletes = |w: &mut Writer| {
        for shader in [2, 3] {
            w.call("glDeleteShader", &[("shader", W::UInt(shader))], None, false);
        }
        w.call("glDeleteProgram", &[("program", W::UInt(7))], None, false);
    };
    // Still in use at the draw: it draws.
    let (w, _) = uniform_array_capture(deletes, |_| {});
    let (result, frames) = replay(&w);
    result.unwrap();
    assert_eq!(frames[0].4, solid(4, 4, [51, 102, 153, 255]));
    // Once another program is used, the program and its deleted shaders are gone.
    let mut gone = 0;
    let (w, _) = uniform_array_capture(deletes, |w| {
        w.call("glUseProgram", &[("program", W::UInt(0))], None, false);
        gone = w.call("glCompileShader", &[("shader", W::UInt(2))], None, false);
    });
    let (result, _) = replay(&w);
    let error = result.err().expect("shader 2 was deleted");
    assert_eq!(error.call(), Some(gone));
    assert!(error.to_string().contains("shader 2 does not exist"), "{error}");
}

#[test]
fn probe_points_match_llvmpipe() {
    check_probe("points");
}

#[test]
fn probe_cube_maps_match_llvmpipe() {
    check_probe("cube");
}

/// Level 0 of face `face` (0 = +X … 5 = −Z) of the cube map bound to the active unit:
/// `width × height` RGBA texels of one colour; returns the call's number.
fn cube_face(w: &mut Writer, face: u32, width: u64, height: u64, rgba: [u8; 4]) -> u64 {
    let args = [
        ("target", e("GL_TEXTURE_CUBE_MAP_POSITIVE_X", 0x8515 + face)),
        ("level", W::UInt(0)),
        ("internalformat", e("GL_RGBA", 0x1908)),
        ("width", W::UInt(width)),
        ("height", W::UInt(height)),
        ("border", W::UInt(0)),
        ("format", e("GL_RGBA", 0x1908)),
        ("type", e("GL_UNSIGNED_BYTE", 0x1401)),
        ("pixels", W::Blob(rgba.repeat((width * height) as usize))),
    ];
    w.call("glTexImage2D", &args, None, false)
}

/// A cube map (name 8, unit 1) whose faces are `sizes[face]` squares of colour
/// `(40 · face, 0, 0)`, a 2D texture (name 4, unit 0) beside it, and a program whose vertex
/// shader reads the cube in direction −Y and the 2D texture: returns the capture and the
/// numbers of the face uploads.
fn cube_capture(sizes: [(u64, u64); 6]) -> (Writer, Vec<u64>) {
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 4, 4);
    texture_rgb(&mut w, 4, 1, 1, vec![0, 200, 0, 0]);
    tex_parameter(&mut w, ("GL_TEXTURE_MIN_FILTER", 0x2801), ("GL_NEAREST", 0x2600));
    w.call("glActiveTexture", &[("texture", e("GL_TEXTURE1", 0x84c1))], None, false);
    w.call("glGenTextures", &[("n", W::UInt(1)), ("textures", W::Array(vec![W::UInt(8)]))], None, false);
    let cube = e("GL_TEXTURE_CUBE_MAP", 0x8513);
    w.call("glBindTexture", &[("target", cube.clone()), ("texture", W::UInt(8))], None, false);
    let calls =
        (0..6).map(|f| cube_face(&mut w, f, sizes[f as usize].0, sizes[f as usize].1, [40 * f as u8, 0, 0, 255]));
    let calls: Vec<u64> = calls.collect();
    w.call("glGenerateMipmap", &[("target", cube.clone())], None, false);
    let filter = [("target", cube), ("pname", e("GL_TEXTURE_MIN_FILTER", 0x2801)), ("param", e("GL_LINEAR", 0x2601))];
    w.call("glTexParameteri", &filter, None, false);
    let vertex = "attribute vec2 where;\nuniform samplerCube env;\nuniform sampler2D plain;\nvarying vec4 fetched;\n\
                  void main() { fetched = textureCube(env, vec3(0.2, -1.0, 0.3)) + texture2D(plain, vec2(0.5));\n\
                  gl_Position = vec4(where, 0.0, 1.0); }\n";
    let fragment = "precision mediump float;\nvarying vec4 fetched;\nvoid main() { gl_FragColor = fetched; }\n";
    full_window_program(&mut w, vertex, fragment);
    for (location, name, unit) in [(2, "env", 1), (3, "plain", 0)] {
        let get = [("program", W::UInt(7)), ("name", W::Str(name))];
        w.call("glGetUniformLocation", &get, Some(W::UInt(location)), false);
        w.call("glUniform1i", &[("location", W::UInt(location)), ("v0", W::UInt(unit))], None, false);
    }
    draw_triangle(&mut w);
    swap(&mut w);
    (w, calls)
}

#[test]
fn a_cube_map_and_a_2d_texture_on_other_units_are_sampled_by_their_samplers() {
    let (w, _) = cube_capture([(2, 2); 6]);
    let (result, frames) = replay(&w);
    result.unwrap();
    // −Y is face 3 (red 120); the 2D texture adds green 200.
    assert_eq!(frames[0].4, solid(4, 4, [120, 200, 0, 255]));
}

#[test]
fn a_cube_face_of_the_wrong_size_or_not_square_is_an_error_naming_the_call() {
    let mut sizes = [(2, 2); 6];
    sizes[4] = (4, 4);
    let (w, calls) = cube_capture(sizes);
    let error = replay(&w).0.err().expect("a 4×4 face beside 2×2 ones");
    assert_eq!(error.call(), Some(calls[4]));
    let message = error.to_string();
    assert!(
        message.contains("`glTexImage2D`") && message.contains("positive_z") && message.contains("2×2"),
        "{message}"
    );
    sizes[4] = (2, 1);
    let (w, calls) = cube_capture(sizes);
    let error = replay(&w).0.err().expect("a 2×1 face");
    assert_eq!(error.call(), Some(calls[4]));
    assert!(error.to_string().contains("square"), "{error}");
}

/// The window cleared with alpha 0.5, copied by `glCopyTexImage2D` with `internal_format`,
/// then drawn with the texture's alpha in every channel: returns the frame's first pixel.
fn copied_alpha(internal_format: (&'static str, u32)) -> [u8; 4] {
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 4, 4);
    clear(&mut w, [0.2, 0.4, 0.6, 0.5]);
    w.call("glGenTextures", &[("n", W::UInt(1)), ("textures", W::Array(vec![W::UInt(4)]))], None, false);
    w.call("glBindTexture", &[("target", e("GL_TEXTURE_2D", 0x0de1)), ("texture", W::UInt(4))], None, false);
    let copy = [
        ("target", e("GL_TEXTURE_2D", 0x0de1)),
        ("level", W::UInt(0)),
        ("internalformat", e(internal_format.0, internal_format.1)),
        ("x", W::UInt(0)),
        ("y", W::UInt(0)),
        ("width", W::UInt(4)),
        ("height", W::UInt(4)),
        ("border", W::UInt(0)),
    ];
    w.call("glCopyTexImage2D", &copy, None, false);
    // A later sub-image copy into the same texture keeps its format's alpha rule.
    let sub = [
        ("target", e("GL_TEXTURE_2D", 0x0de1)),
        ("level", W::UInt(0)),
        ("xoffset", W::UInt(0)),
        ("yoffset", W::UInt(0)),
        ("x", W::UInt(0)),
        ("y", W::UInt(0)),
        ("width", W::UInt(2)),
        ("height", W::UInt(2)),
    ];
    w.call("glCopyTexSubImage2D", &sub, None, false);
    tex_parameter(&mut w, ("GL_TEXTURE_MIN_FILTER", 0x2801), ("GL_NEAREST", 0x2600));
    let vertex = "attribute vec2 where;\nvarying vec2 uv;\nvoid main() { uv = where * 0.5 + 0.5; gl_Position = vec4(where, 0.0, 1.0); }\n";
    let fragment = "precision mediump float;\nuniform sampler2D copied;\nvarying vec2 uv;\n\
                    void main() { gl_FragColor = vec4(texture2D(copied, uv).a); }\n";
    full_window_program(&mut w, vertex, fragment);
    draw_triangle(&mut w);
    swap(&mut w);
    let (result, frames) = replay(&w);
    result.unwrap();
    frames[0].4[..4].try_into().unwrap()
}

#[test]
fn copy_tex_image_into_gl_rgb_reads_alpha_one() {
    assert_eq!(copied_alpha(("GL_RGB", 0x1907)), [255; 4]);
    // GL_RGBA keeps the window's alpha, 0.5.
    assert_eq!(copied_alpha(("GL_RGBA", 0x1908)), [128; 4]);
}

/// ETC2 RGBA8 and ASTC 8×8 textures with mip chains given by `glCompressedTexImage2D` (GL ES
/// 3; llvmpipe exposes `KHR_texture_compression_astc_ldr` by decoding in software), flat
/// blocks: the picture matches llvmpipe's, and `texture fetch` is the compressed blocks
/// fetched. Each half of the 64×64 window samples level 1 of its 64×128 texture (32×64 texels
/// on 32×64 pixels, `NEAREST_MIPMAP_NEAREST`). With 32×32 tiles, one per half and row:
///
/// - ETC2: level 1 is 8×16 blocks of 16 bytes, a block row 128 bytes, 2 lines of 64. A tile
///   reads 8 block rows, 16 lines; 2 tiles: 32 lines, 2048 bytes.
/// - ASTC 8×8: level 1 is 4×8 blocks of 16 bytes, a block row one line. A tile reads 4 block
///   rows, 4 lines; 2 tiles: 8 lines, 512 bytes.
///
/// The levels' lines start on line boundaries (level 0 is 8192 and 2048 bytes), tiles share
/// no line, and the second triangle's helpers find their lines in the cache: 2560 bytes.
#[test]
fn probe_compressed_mip_chains_match_llvmpipe_and_fetch_their_blocks() {
    check_probe("compressed");
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gles2-probe/compressed.trace");
    for backend in [tiler::Backend::Tbr, tiler::Backend::Tbdr] {
        let config = tiler_gl::ContextConfig {
            backend,
            tile_width: 32,
            tile_height: 32,
            threads: 2,
            ..ReplayOptions::default().config
        };
        let options = ReplayOptions { config, ..ReplayOptions::default() };
        let replay = tiler_gl::capture::replay_file(&path, &options, &mut |_| Ok(())).unwrap();
        let fetched: u64 = replay.report.passes().map(|p| p.cost.ledger.get(tiler::Category::TextureFetch)).sum();
        assert_eq!(fetched, 2048 + 512, "{backend:?}");
    }
}

/// `glCompressedTexImage2D` (ETC2 RGBA8) and `glTexImage2D` of 4444 texels replay, each texel
/// decoded as GL does; a compressed upload whose size does not match its blocks fails at its
/// call, naming the sizes.
#[test]
fn compressed_and_packed_uploads_replay_and_bad_sizes_fail_at_their_call() {
    let capture = |upload: &dyn Fn(&mut Writer) -> u64| {
        let mut w = Writer::new(6);
        window_surface(&mut w);
        begin_context(&mut w, 100, 4, 4);
        w.call("glGenTextures", &[("n", W::UInt(1)), ("textures", W::Array(vec![W::UInt(1)]))], None, false);
        w.call("glBindTexture", &[("target", e("GL_TEXTURE_2D", 0x0de1)), ("texture", W::UInt(1))], None, false);
        let call = upload(&mut w);
        tex_parameter(&mut w, ("GL_TEXTURE_MIN_FILTER", 0x2801), ("GL_NEAREST", 0x2600));
        let vertex = "attribute vec2 where;\nvoid main() { gl_Position = vec4(where, 0.0, 1.0); }\n";
        let fragment = "precision mediump float;\nuniform sampler2D tex;\nvoid main() { gl_FragColor = texture2D(tex, vec2(0.4, 0.6)); }\n";
        full_window_program(&mut w, vertex, fragment);
        let draw = [("mode", e("GL_TRIANGLES", 4)), ("first", W::UInt(0)), ("count", W::UInt(3))];
        w.call("glDrawArrays", &draw, None, false);
        swap(&mut w);
        (w, call)
    };
    let compressed = |size: u64, blocks: Vec<u8>| {
        move |w: &mut Writer| {
            let args = [
                ("target", e("GL_TEXTURE_2D", 0x0de1)),
                ("level", W::UInt(0)),
                ("internalformat", e("GL_COMPRESSED_RGBA8_ETC2_EAC", 0x9278)),
                ("width", W::UInt(size)),
                ("height", W::UInt(size)),
                ("border", W::UInt(0)),
                ("imageSize", W::UInt(blocks.len() as u64)),
                ("data", W::Blob(blocks.clone())),
            ];
            w.call("glCompressedTexImage2D", &args, None, false)
        }
    };
    // One flat ETC2 RGBA8 block: alpha 200, individual mode of the 4-bit colour (1, 2, 3), all
    // modifiers +2: (19, 36, 53).
    let mut block = vec![0u8; 16];
    block[0] = 200;
    block[8..11].copy_from_slice(&[0x11, 0x22, 0x33]);
    let (w, _) = capture(&compressed(4, block.clone()));
    let (result, frames) = replay(&w);
    result.unwrap();
    assert_eq!(frames[0].4, solid(4, 4, [19, 36, 53, 200]));
    let (w, call) = capture(&compressed(8, block));
    let (result, _) = replay(&w);
    let error = result.err().expect("one block for an 8×8 texture");
    assert_eq!(error.call(), Some(call));
    assert!(error.to_string().contains("16 bytes of ETC2 RGBA8 data for 8×8, which needs 2×2 blocks"), "{error}");

    // 2×2 texels of 4444: red 15, green 0, blue 8, alpha 15.
    let (w, _) = capture(&|w: &mut Writer| {
        let args = [
            ("target", e("GL_TEXTURE_2D", 0x0de1)),
            ("level", W::UInt(0)),
            ("internalformat", e("GL_RGBA", 0x1908)),
            ("width", W::UInt(2)),
            ("height", W::UInt(2)),
            ("border", W::UInt(0)),
            ("format", e("GL_RGBA", 0x1908)),
            ("type", e("GL_UNSIGNED_SHORT_4_4_4_4", 0x8033)),
            ("pixels", W::Blob(0xf08fu16.to_le_bytes().repeat(4))),
        ];
        w.call("glTexImage2D", &args, None, false)
    });
    let (result, frames) = replay(&w);
    result.unwrap();
    assert_eq!(frames[0].4, solid(4, 4, [255, 0, 136, 255]));
}

#[test]
fn probe_vertex_array_objects_match_llvmpipe() {
    check_probe_in("gles3-probe", "vao");
}

#[test]
fn probe_instanced_draws_match_llvmpipe() {
    check_probe_in("gles3-probe", "instanced");
}

#[test]
fn probe_uniform_blocks_match_llvmpipe() {
    check_probe_in("gles3-probe", "ubo");
}

#[test]
fn probe_storage_levels_sampler_objects_and_buffer_copies_match_llvmpipe() {
    check_probe_in("gles3-probe", "objects");
}

#[test]
fn probe_multiple_render_targets_match_llvmpipe() {
    check_probe_in("gles3-probe", "mrt");
}

#[test]
fn probe_glsl_es_300_matches_llvmpipe() {
    check_probe_in("gles3-probe", "glsl3");
}

#[test]
fn probe_blits_and_a_multisample_resolve_by_blit_match_llvmpipe() {
    check_probe_in("gles3-probe", "blit");
    // The 4-sample renderbuffer's resolve (the window's top-right quarter) to the byte but
    // for rounding: its edge pixels cover the samples llvmpipe's do, which in a framebuffer
    // object lie mirrored from the window's (`tiler::SampleOrigin`). With the window's
    // locations 31 edge pixels differed, by up to 80/255.
    let frames = replay_probe_in("gles3-probe", "blit", ReplayOptions::default().config).unwrap();
    let reference = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gles3-probe/blit.png");
    let (w, _, expected) = read_png(&reference).unwrap();
    let ours = &frames[0].4;
    for y in 0..32 {
        for x in 32..64 {
            let i = ((y * w + x) * 4) as usize;
            let worst = (0..3).map(|c| ours[i + c].abs_diff(expected[i + c])).max().unwrap();
            assert!(worst <= 2, "pixel ({x}, {y}): {:?}, llvmpipe {:?}", &ours[i..i + 4], &expected[i..i + 4]);
        }
    }
}

#[test]
fn probe_invalidated_attachments_match_llvmpipe() {
    check_probe_in("gles3-probe", "invalidate");
}

#[test]
fn probe_primitive_restart_and_range_elements_match_llvmpipe() {
    check_probe_in("gles3-probe", "restart");
}

#[test]
fn probe_texture_formats_through_tex_sub_image_match_llvmpipe() {
    check_probe_in("gles3-probe", "formats");
}

#[test]
fn probe_float_and_srgb_render_targets_match_llvmpipe() {
    check_probe_in("gles3-probe", "float-srgb");
}

#[test]
fn probe_read_pixels_mid_frame_a_mapped_range_and_a_fence_match_llvmpipe() {
    check_probe_in("gles3-probe", "readback");
}

#[test]
fn probe_depth_compare_textures_match_llvmpipe() {
    check_probe_in("gles3-probe", "shadow");
}

#[test]
fn probe_packed_float_textures_match_llvmpipe() {
    check_probe_in("gles3-probe", "packed-float");
}

#[test]
fn probe_rgb10_a2_textures_match_llvmpipe() {
    check_probe_in("gles3-probe", "rgb10a2");
}

#[test]
fn probe_depth_compare_through_a_sampler_object_matches_llvmpipe() {
    check_probe_in("gles3-probe", "shadow-sampler");
}

#[test]
fn probe_transform_feedback_drawn_from_its_buffers_matches_llvmpipe() {
    check_probe_in("gles3-probe", "feedback");
}

#[test]
fn transform_feedback_writes_are_counted_in_the_context_ledger() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gles3-probe/feedback.trace");
    let replay = tiler_gl::capture::replay_file(path, &ReplayOptions::default(), &mut |_| Ok(())).unwrap();
    let ledger = &replay.report.frames[0].context_ledger;
    // Six points of a vec4 and a vec3 (28 bytes), then two triangles' six vertices of a vec4
    // and a uint into separate buffers (16 + 4 bytes).
    assert_eq!(ledger.get(tiler::Category::TransformFeedbackWrite), 6 * 28 + 6 * 20);
    // The discarded draws' attributes (a vec2 per captured point) are fetched outside passes;
    // the strip's are the core's, as it is drawn too.
    assert_eq!(ledger.get(tiler::Category::VertexFetch), 6 * 8);
}

#[test]
fn probe_rendering_into_array_and_volume_layers_matches_llvmpipe() {
    check_probe_in("gles3-probe", "layer");
}

#[test]
fn probe_copies_into_array_and_volume_layers_match_llvmpipe() {
    check_probe_in("gles3-probe", "copy-layer");
}

#[test]
fn a_layer_rendered_into_is_a_pass_of_its_own_loaded_and_stored_as_an_attachment() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gles3-probe/layer.trace");
    let replay = tiler_gl::capture::replay_file(path, &ReplayOptions::default(), &mut |_| Ok(())).unwrap();
    let passes = &replay.report.frames[0].passes;
    // The array's layer (16×16, loaded: it has texels), the volume's slice (8×8, cleared,
    // one pass with its triangle), the window.
    let sizes: Vec<(u32, u32)> = passes.iter().map(|p| (p.width, p.height)).collect();
    assert_eq!(sizes, [(16, 16), (8, 8), (64, 64)], "{passes:#?}");
    assert_eq!(passes[0].cost.ledger.get(tiler::Category::TileLoad), 16 * 16 * 4);
    assert_eq!(passes[0].cost.ledger.get(tiler::Category::TileStore), 16 * 16 * 4);
    assert_eq!(passes[1].cost.ledger.get(tiler::Category::TileLoad), 0);
    assert_eq!(passes[1].cost.ledger.get(tiler::Category::TileStore), 8 * 8 * 4);
}

// ---- glsl4's probe scenes ----

#[test]
fn probe_flat_varyings_take_the_last_vertex_as_llvmpipe_does() {
    check_probe_in("gles3-probe", "flat");
}

#[test]
fn probe_switch_and_integer_arithmetic_match_llvmpipe() {
    check_probe_in("gles3-probe", "int-switch");
}

// ---- integer textures and render targets ----

#[test]
fn probe_integer_targets_attributes_and_texel_fetch_match_llvmpipe() {
    check_probe_in("gles3-probe", "integer");
}

/// A program whose fragment shader reads uniform block `Colors` (with `uniform_array_capture`'s
/// full-window triangle).
fn uniform_block_capture(before_draw: impl FnOnce(&mut Writer)) -> (Writer, u64) {
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 4, 4);
    full_window_program(
        &mut w,
        "#version 300 es\nin vec2 where;\nvoid main() { gl_Position = vec4(where, 0.0, 1.0); }\n",
        "#version 300 es\nprecision mediump float;\nuniform Colors { vec4 a; vec4 b; };\nout vec4 c;\n\
         void main() { c = b; }\n",
    );
    let index = [("program", W::UInt(7)), ("uniformBlockName", W::Str("Colors"))];
    w.call("glGetUniformBlockIndex", &index, Some(W::UInt(0)), false);
    before_draw(&mut w);
    let draw = [("mode", e("GL_TRIANGLES", 4)), ("first", W::UInt(0)), ("count", W::UInt(3))];
    let call = w.call("glDrawArrays", &draw, None, false);
    swap(&mut w);
    (w, call)
}

#[test]
fn uniform_blocks_read_their_bound_buffer_and_errors_name_the_call() {
    let values: Vec<u8> = [0.0f32, 0.0, 0.0, 1.0, 0.2, 0.4, 0.6, 1.0].iter().flat_map(|v| v.to_le_bytes()).collect();
    let bind_and_fill = |w: &mut Writer, binding: u64| {
        w.call("glGenBuffers", &[("n", W::UInt(1)), ("buffers", W::Array(vec![W::UInt(4)]))], None, false);
        // Bound by index before it has storage: bound in the context when it gets some.
        let base = [("target", e("GL_UNIFORM_BUFFER", 0x8a11)), ("index", W::UInt(binding)), ("buffer", W::UInt(4))];
        w.call("glBindBufferBase", &base, None, false);
        w.call(
            "glBufferData",
            &[
                ("target", e("GL_UNIFORM_BUFFER", 0x8a11)),
                ("size", W::UInt(32)),
                ("data", W::Blob(values.clone())),
                ("usage", e("GL_STATIC_DRAW", 0x88e4)),
            ],
            None,
            false,
        );
    };
    let block_binding = |w: &mut Writer, index: u64, binding: u64| {
        let args =
            [("program", W::UInt(7)), ("uniformBlockIndex", W::UInt(index)), ("uniformBlockBinding", W::UInt(binding))];
        w.call("glUniformBlockBinding", &args, None, false)
    };
    // Binding 3.
    let (w, _) = uniform_block_capture(|w| {
        block_binding(w, 0, 3);
        bind_and_fill(w, 3);
    });
    let (result, frames) = replay(&w);
    result.unwrap();
    assert_eq!(frames[0].4, solid(4, 4, [51, 102, 153, 255]));
    // The block reads binding 3, where nothing is bound: the draw names the block.
    let (w, draw) = uniform_block_capture(|w| {
        block_binding(w, 0, 3);
        bind_and_fill(w, 1);
    });
    let (result, _) = replay(&w);
    let error = result.err().expect("binding 3 is empty");
    assert_eq!(error.call(), Some(draw));
    let message = error.to_string();
    assert!(message.contains("`glDrawArrays`") && message.contains("uniform block 'Colors' (binding 3)"), "{message}");
    // A block index glGetUniformBlockIndex never returned.
    let mut call = 0;
    let (w, _) = uniform_block_capture(|w| call = block_binding(w, 4, 0));
    let (result, _) = replay(&w);
    let error = result.err().expect("index 4 was never returned");
    assert_eq!(error.call(), Some(call));
    assert!(error.to_string().contains("`glUniformBlockBinding`"), "{error}");
}

#[test]
fn gles3_vertex_state_errors_name_their_call() {
    let expect_error = |w: &Writer, call: u64, words: &[&str]| {
        let (result, _) = replay(w);
        let error = result.err().expect("an error");
        assert_eq!(error.call(), Some(call), "{error}");
        let message = error.to_string();
        assert!(words.iter().all(|word| message.contains(word)), "{message}");
    };
    // A divisor on an attribute the context does not have.
    let mut call = 0;
    let (w, _) = uniform_array_capture(
        |w| {
            let args = [("index", W::UInt(9)), ("divisor", W::UInt(1))];
            call = w.call("glVertexAttribDivisor", &args, None, false);
        },
        |_| {},
    );
    expect_error(&w, call, &["`glVertexAttribDivisor`", "vertex attribute 9"]);
    // Per-instance data too short for the instances drawn: `where` (3 elements) advancing
    // every instance, 4 instances.
    let (w, _) = uniform_array_capture(
        |w| {
            w.call("glVertexAttribDivisor", &[("index", W::UInt(5)), ("divisor", W::UInt(1))], None, false);
        },
        |w| {
            let args = [
                ("mode", e("GL_TRIANGLES", 4)),
                ("first", W::UInt(0)),
                ("count", W::UInt(3)),
                ("instancecount", W::UInt(4)),
            ];
            call = w.call("glDrawArraysInstanced", &args, None, false);
        },
    );
    expect_error(&w, call, &["`glDrawArraysInstanced`", "attribute 5 (where), divisor 1", "past the end"]);
    // A vertex array name glGenVertexArrays never returned.
    let (w, _) = uniform_array_capture(
        |w| {
            call = w.call("glBindVertexArray", &[("array", W::UInt(3))], None, false);
        },
        |_| {},
    );
    expect_error(&w, call, &["`glBindVertexArray`", "vertex array 3"]);
}

#[test]
fn gles3_object_errors_name_their_call() {
    let expect_error = |call: &dyn Fn(&mut Writer) -> u64, function: &str, words: &[&str]| {
        let mut number = 0;
        let (w, _) = uniform_array_capture(|w| number = call(w), |_| {});
        let (result, _) = replay(&w);
        let error = result.err().expect("an error");
        assert_eq!(error.call(), Some(number), "{error}");
        let message = error.to_string();
        assert!(message.contains(&format!("`{function}`")), "{message}");
        assert!(words.iter().all(|word| message.contains(word)), "{message}");
    };
    expect_error(
        &|w| w.call("glBindSampler", &[("unit", W::UInt(0)), ("sampler", W::UInt(9))], None, false),
        "glBindSampler",
        &["sampler 9"],
    );
    expect_error(
        &|w| {
            w.call("glGenSamplers", &[("n", W::UInt(1)), ("samplers", W::Array(vec![W::UInt(2)]))], None, false);
            let lod = [("sampler", W::UInt(2)), ("pname", e("GL_TEXTURE_MIN_LOD", 0x813a)), ("param", W::Float(2.0))];
            w.call("glSamplerParameterf", &lod, None, false)
        },
        "glSamplerParameterf",
        &["0x813a"],
    );
    expect_error(
        &|w| {
            w.call("glGenTextures", &[("n", W::UInt(1)), ("textures", W::Array(vec![W::UInt(4)]))], None, false);
            w.call("glBindTexture", &[("target", e("GL_TEXTURE_2D", 0x0de1)), ("texture", W::UInt(4))], None, false);
            let storage = [
                ("target", e("GL_TEXTURE_2D", 0x0de1)),
                ("levels", W::UInt(2)),
                ("internalformat", e("GL_RGBA8", 0x8058)),
                ("width", W::UInt(8)),
                ("height", W::UInt(8)),
            ];
            w.call("glTexStorage2D", &storage, None, false)
        },
        "glTexStorage2D",
        &["2 mip levels", "whole chain (4)"],
    );
    expect_error(
        &|w| w.call("glDrawBuffers", &[("n", W::UInt(1)), ("bufs", W::Array(vec![W::UInt(0)]))], None, false),
        "glDrawBuffers",
        &["of the window"],
    );
}

/// `ReplayOptions::record` keeps the calls a capture became, a JSON trace of the same frames:
/// `--what-if` edits it. A `glFlush` between two draws on the window splits its pass
/// (`flush-mid-pass`); the recorded calls replay to the same picture and report, and with
/// the advisor's fix (the flush moved to the end of the pass) they save what it estimated and
/// keep the picture.
#[test]
fn recorded_capture_calls_replay_and_take_the_advisors_fixes() {
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 16, 16);
    clear(&mut w, [0.1, 0.2, 0.3, 1.0]);
    let vertex = "attribute vec2 where;\nvoid main() { gl_Position = vec4(where * 0.5, 0.0, 1.0); }\n";
    let fragment = "precision mediump float;\nvoid main() { gl_FragColor = vec4(0.9, 0.5, 0.1, 1.0); }\n";
    full_window_program(&mut w, vertex, fragment);
    draw_triangle(&mut w);
    w.call("glFlush", &[], None, false);
    draw_triangle(&mut w);
    swap(&mut w);

    let options = ReplayOptions { record: true, ..ReplayOptions::default() };
    let replay = replay_reader(&w.snappy(1 << 16)[..], &options, &mut |_| Ok(())).unwrap();
    let frames = replay.context.recorded_frames().expect("recorded").to_vec();
    let frames = frames.into_iter().map(|calls| tiler_gl::trace::TraceFrame { repeat: 1, calls }).collect();
    let config = replay.context.config().clone();
    let trace = tiler_gl::Trace { description: None, config, frames };
    let again = trace.replay().unwrap();
    assert_eq!(again.context.surface_rgba8(), replay.context.surface_rgba8());
    assert_eq!(again.report.totals.ledger, replay.report.totals.ledger);

    let finding = replay.report.findings_with("flush-mid-pass").next().expect("the flush splits the pass");
    let mut fixer = tiler_gl::advisor::what_if::Fixer::new(&trace).unwrap();
    fixer.add(finding, &replay.report).unwrap();
    let fixed = fixer.fixed(&trace).replay().unwrap();
    let saved = replay.report.totals.ledger.total() - fixed.report.totals.ledger.total();
    assert_eq!(Some(saved), finding.cost_bytes);
    assert_eq!(fixed.context.surface_rgba8(), replay.context.surface_rgba8());
}

/// A shared capture replayed with its calls recorded, as `tiler analyze --what-if` replays it
/// (every presented frame's digest kept), and the calls as a trace the advisor can edit.
fn recorded_glmark2(traces: &Path, scene: &str) -> (tiler_gl::trace::Replay, tiler_gl::Trace) {
    let config = tiler_gl::ContextConfig { digest_presented: true, ..tiler_gl::ContextConfig::new(1, 1) };
    let options = ReplayOptions { config, record: true, ..ReplayOptions::default() };
    let path = traces.join(format!("{scene}.trace"));
    let replay = tiler_gl::capture::replay_file(path, &options, &mut |_| Ok(())).unwrap();
    let frames = replay.context.recorded_frames().expect("recorded").to_vec();
    let frames = frames.into_iter().map(|calls| tiler_gl::trace::TraceFrame { repeat: 1, calls }).collect();
    let trace = tiler_gl::Trace { description: None, config: replay.context.config().clone(), frames };
    (tiler_gl::trace::Replay { report: replay.report, context: replay.context }, trace)
}

/// glmark2's shadow scene clears the window, renders the shadow map into framebuffer 1 with a
/// program and uniforms set while the window was still bound, then binds the window again and
/// reloads what it cleared: `framebuffer-rebound`. The advisor's fix moves the shadow-map work
/// (with the state set up for it) before the window's pass, each part in the GL state it ran
/// in, and in every frame after the first (frame 0 also creates the objects) it saves exactly
/// the estimate and keeps every picture. The other fixes keep the pictures too.
#[test]
fn glmark2_shadow_rebinding_fix_saves_its_estimate() {
    let Some(traces) = tiler_test_support::traces_dir() else { return };
    let (run, trace) = recorded_glmark2(&traces.join("glmark2"), "shadow");
    let picture = run.context.surface_rgba8();
    let config = run.context.config().clone();
    let what_if = tiler_gl::advisor::what_if::Run { config: &config, report: &run.report, picture: &picture };
    let proven = tiler_gl::advisor::what_if::prove(&trace, &what_if, "tbr").unwrap();
    let mut rebound_later_frames = 0;
    for (finding, result) in run.report.findings.iter().zip(&proven) {
        let what = format!("{} ({}): {}", finding.id, finding.location.describe(), result.fix);
        if !result.applied {
            continue;
        }
        assert_eq!(result.same_picture, Some(true), "{what}");
        if finding.id == "framebuffer-rebound" && finding.location.frame.is_some_and(|f| f > 0) {
            rebound_later_frames += 1;
            assert_eq!(result.measured_bytes, finding.cost_bytes.map(|b| b as i64), "{what}");
        }
    }
    assert_eq!(rebound_later_frames, 5, "one rebinding in each of frames 1 to 5");
}

/// glmark2's desktop scene blurs by ping-pong: a pass reads what the pass before drew into
/// another framebuffer and draws into it, then the first framebuffer is bound again to draw
/// with what the second holds. Those rebindings are needed (the work between reads what the
/// first binding drew), so `framebuffer-rebound` names none of them; the one it names (the
/// window, bound again after work that reads nothing the window's pass drew) can be undone.
#[test]
fn glmark2_desktop_needed_rebindings_are_not_advised() {
    let Some(traces) = tiler_test_support::traces_dir() else { return };
    let (run, _) = recorded_glmark2(&traces.join("glmark2"), "desktop");
    let passes: Vec<_> = run.report.passes().collect();
    // The pass between that reads what the earlier binding of the pass's framebuffer drew.
    let needed_by = |at: usize| -> Option<u32> {
        let pass = passes[at];
        let earlier = passes[..at]
            .iter()
            .rposition(|p| p.frame == pass.frame && p.framebuffer == pass.framebuffer && p.copy_texture.is_none())?;
        let drew: Vec<_> = passes[earlier].attachments.iter().map(|a| a.image).collect();
        passes[earlier + 1..at].iter().find(|b| b.reads.iter().any(|i| drew.contains(i))).map(|b| b.index)
    };
    let mut advised = 0;
    for finding in run.report.findings_with("framebuffer-rebound") {
        advised += 1;
        let at = passes.iter().position(|p| Some(p.index as u64) == finding.location.pass).unwrap();
        assert_eq!(needed_by(at), None, "pass {} is advised to join a binding the work between needed", at);
    }
    let needed = (0..passes.len()).filter(|&at| needed_by(at).is_some()).count();
    assert!(needed >= 6 * 4, "{needed} needed rebindings (four blur ping-pongs a frame)");
    assert!(advised >= 6, "{advised} framebuffer-rebound findings (the window, bound again, each frame)");
}

// ---- Probe scenes of the tex3d branch: 2-D array and 3-D textures.

#[test]
fn probe_2d_array_textures_match_llvmpipe() {
    check_probe_in("gles3-probe", "array");
}

#[test]
fn probe_3d_textures_match_llvmpipe() {
    check_probe_in("gles3-probe", "volume");
}

/// A 2-D array texture (name 9) of two 1×1 layers made by `glTexImage3D` at `level`, then
/// `glFramebufferTextureLayer` of it: returns the capture and the two calls' numbers.
fn array_capture(level: u64, layer: u64) -> (Writer, [u64; 2]) {
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 4, 4);
    w.call("glGenTextures", &[("n", W::UInt(1)), ("textures", W::Array(vec![W::UInt(9)]))], None, false);
    let array = e("GL_TEXTURE_2D_ARRAY", 0x8c1a);
    w.call("glBindTexture", &[("target", array.clone()), ("texture", W::UInt(9))], None, false);
    let image = [
        ("target", array),
        ("level", W::UInt(level)),
        ("internalformat", e("GL_RGBA8", 0x8058)),
        ("width", W::UInt(1)),
        ("height", W::UInt(1)),
        ("depth", W::UInt(2)),
        ("border", W::UInt(0)),
        ("format", e("GL_RGBA", 0x1908)),
        ("type", e("GL_UNSIGNED_BYTE", 0x1401)),
        ("pixels", W::Blob(vec![10, 20, 30, 255, 40, 50, 60, 255])),
    ];
    let upload = w.call("glTexImage3D", &image, None, false);
    w.call("glGenFramebuffers", &[("n", W::UInt(1)), ("framebuffers", W::Array(vec![W::UInt(5)]))], None, false);
    w.call("glBindFramebuffer", &[("target", e("GL_FRAMEBUFFER", 0x8d40)), ("framebuffer", W::UInt(5))], None, false);
    let layer = [
        ("target", e("GL_FRAMEBUFFER", 0x8d40)),
        ("attachment", e("GL_COLOR_ATTACHMENT0", 0x8ce0)),
        ("texture", W::UInt(9)),
        ("level", W::UInt(0)),
        ("layer", W::UInt(layer)),
    ];
    let attach = w.call("glFramebufferTextureLayer", &layer, None, false);
    swap(&mut w);
    (w, [upload, attach])
}

#[test]
fn array_uploads_above_level_0_and_a_layer_past_the_last_are_errors_naming_the_call() {
    let (w, [upload, _]) = array_capture(1, 1);
    let error = replay(&w).0.err().expect("level 1 of an array");
    assert_eq!(error.call(), Some(upload));
    assert!(error.to_string().contains("mip level 1 of a 2-D array texture"), "{error}");
    // Layer 1 of two is rendered into (since 2026-11-27); layer 2 does not exist.
    let (w, _) = array_capture(0, 1);
    replay(&w).0.unwrap();
    let (w, [_, attach]) = array_capture(0, 2);
    let error = replay(&w).0.err().expect("layer 2 of two");
    assert_eq!(error.call(), Some(attach));
    let message = error.to_string();
    assert!(
        message.contains("glFramebufferTextureLayer") && message.contains("layer 2 of 2-D array texture"),
        "{message}"
    );
}

/// `tools/float-probe`'s `precision.frag`, recorded on llvmpipe (a headless program drawing into
/// a pbuffer, which tiler takes as its window): each pixel holds the bits of one float, a
/// `mediump` or `highp` expression per column. tiler computes llvmpipe's bits exactly, the
/// binary16 `inversesqrt` (and so `normalize`) included: `1 / sqrt(x)`, both rounded.
#[test]
fn float_probe_precision_is_llvmpipes_to_the_bit() {
    let values = float_probe("precision", 29);
    assert_eq!(values.len(), 64);
    let differ: Vec<_> = values.into_iter().filter(|&(.., got, want)| got != want).collect();
    assert!(differ.is_empty(), "differ from llvmpipe (y, x, tiler, llvmpipe): {differ:x?}");
}

/// `mediump` texels and arithmetic on them, llvmpipe's to the bit (`tools/float-probe`'s
/// `texels.frag`, `ops.frag`, `dot.frag`, `pow.frag` with an uploaded 8×8 texture): texels
/// through a `mediump` sampler are binary16 rounded toward zero; `dot` is NIR's factored
/// multiply-add chain from the last component, `inversesqrt` `1/sqrt`, `pow`
/// `exp2(y·log2 x)` and `mix` the lowered `flrp`, every step rounded to binary16; `refract`
/// (`refract.frag`) with a constant η squares η in binary16 (33 of 640 values differed when η²
/// was folded in single precision).
#[test]
fn float_probe_mediump_texels_and_builtins_are_llvmpipes_to_the_bit() {
    for (name, count) in [
        ("texels", 16 * 8),
        ("mediump-ops", 16 * 64),
        ("mediump-dot", 10 * 64),
        ("mediump-pow", 10 * 64),
        ("mediump-refract", 10 * 64),
    ] {
        let values = float_probe(name, 40);
        assert_eq!(values.len(), count, "{name}");
        let differ: Vec<_> = values.iter().filter(|&&(.., got, want)| got != want).collect();
        assert!(differ.is_empty(), "{name}: {} differ (y, x, tiler, llvmpipe) {differ:x?}", differ.len());
    }
}

/// `highp` `dot`, `length` and `normalize` (`tools/float-probe`'s `highp-normalize.frag`, vectors
/// from exact per-row products), llvmpipe's to the bit: `dot` is summed from the last
/// component, `a₀b₀ + (a₁b₁ + a₂b₂)`, and `normalize(v)` is `v · (1 / sqrt(dot(v, v)))`
/// (163 of 512 values differed with the sum from the first component and `v / length(v)`).
#[test]
fn float_probe_highp_normalize_is_llvmpipes_to_the_bit() {
    let values = float_probe("highp-normalize", 33);
    assert_eq!(values.len(), 8 * 64);
    let differ: Vec<_> = values.into_iter().filter(|&(.., got, want)| got != want).collect();
    assert!(differ.is_empty(), "{} differ from llvmpipe (y, x, tiler, llvmpipe): {differ:x?}", differ.len());
}

/// Replays a float-probe capture (`tools/float-probe`) with a snapshot at `call` (its
/// `glReadPixels`) and gives each probed pixel's float bits, tiler's and llvmpipe's, as
/// `(y, x, tiler, llvmpipe)`.
fn float_probe(name: &str, call: u64) -> Vec<(usize, usize, u32, u32)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/float-probe");
    let expected = std::fs::read_to_string(dir.join(format!("{name}.txt"))).unwrap();
    let expected: Vec<Vec<u32>> =
        expected.lines().map(|l| l.split_whitespace().map(|w| u32::from_str_radix(w, 16).unwrap()).collect()).collect();
    let options = ReplayOptions { snapshots: vec![call], ..ReplayOptions::default() };
    let mut frames = Vec::new();
    tiler_gl::capture::replay_file(dir.join(format!("{name}.trace")), &options, &mut |f| {
        frames.push((f.width, f.height, f.rgba.to_vec()));
        Ok(())
    })
    .unwrap();
    let (w, h, rgba) = &frames[0];
    assert_eq!((*w, *h), (64, 64), "the pbuffer's size");
    let mut values = Vec::new();
    for (y, row) in expected.iter().enumerate() {
        for (x, &want) in row.iter().enumerate() {
            // Rows top first in the snapshot; the probe printed from y = 0 (the bottom) up.
            let at = ((*h as usize - 1 - y) * *w as usize + x) * 4;
            let got = u32::from_be_bytes(rgba[at..at + 4].try_into().unwrap());
            values.push((y, x, got, want));
        }
    }
    values
}

/// A varying interpolated over a triangle inside the window with unequal w (perspective):
/// within 2 ulps of llvmpipe at every probed pixel. Its planes come from the window positions
/// before snapping, as llvmpipe's do; from the snapped positions it was up to 103 ulps (618
/// with equal w), enough to flip a `NEAREST` texel where a pixel centre falls on a texel edge.
#[test]
fn float_probe_interpolation_is_within_two_ulps_of_llvmpipe() {
    let values = float_probe("interpolation", 33);
    assert_eq!(values.len(), 64);
    let worst = values.iter().map(|&(y, x, got, want)| ((got as i64 - want as i64).abs(), y, x)).max().unwrap();
    assert!(worst.0 <= 2, "(ulps, y, x) of the worst pixel: {worst:?}");
    let equal = values.iter().filter(|&&(.., got, want)| got == want).count();
    assert!(equal >= 24, "only {equal} of 64 values are llvmpipe's to the bit");
}

// ---- Probe scene of the texfn branch: textureGrad, texel offsets, sampler objects on cube
// and 3-D textures.

#[test]
fn probe_texture_grad_offsets_and_sampler_objects_match_llvmpipe() {
    check_probe_in("gles3-probe", "texfn");
}

#[test]
fn probe_two_live_contexts_drawing_interleaved_match_llvmpipe() {
    // One context renders into a texture (without a surface), the other samples it on the
    // window, twice each, neither rebinding anything after a switch; framebuffer and vertex
    // array name 1 is each context's own.
    check_probe_in("gles3-probe", "contexts");
}

#[test]
fn two_live_contexts_recorded_from_a_capture_replay_from_json_the_same() {
    // The probe's two contexts as the replay's calls: the switches are `make_current`s of the
    // context's contexts, which a JSON trace writes and reads back to the same picture and
    // the same ledger.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gles3-probe/contexts.trace");
    let options = ReplayOptions { record: true, ..ReplayOptions::default() };
    let replay = tiler_gl::capture::replay_file(path, &options, &mut |_| Ok(())).unwrap();
    let trace = replay.context.recording().expect("recorded");
    let json = trace.to_json();
    let switches = json.matches(r#""call":"make_current""#).count();
    assert_eq!(switches, 4, "one make_current per switch the probe makes after its first");
    assert_eq!(json.matches(r#""call":"create_context""#).count(), 1);
    let again = tiler_gl::Trace::parse(&json, None).unwrap().replay().unwrap();
    assert_eq!(again.context.surface_rgba8(), replay.context.surface_rgba8());
    assert_eq!(again.report.totals.ledger, replay.report.totals.ledger);
}

// ---- The GLSL ES 3.00 probe scene every branch added to: integer and bit operations,
// switch, do-while, struct arrays, non-square matrices, inverse/transpose, textureSize,
// texelFetch (rows counted from the first uploaded), textureGrad, textureOffset, packing,
// float bit casts, and a uint uniform beyond 2^24.

#[test]
fn probe_glsl3_more_matches_llvmpipe() {
    check_probe_in("gles3-probe", "glsl3-more");
}

/// `glPixelStorei(pname, value)`.
fn pixel_store(w: &mut Writer, pname: (&'static str, u32), value: u64) {
    w.call("glPixelStorei", &[("pname", e(pname.0, pname.1)), ("param", W::UInt(value))], None, false);
}

#[test]
fn the_window_grows_to_a_viewport_that_reaches_past_it_as_apitraces_retrace_does() {
    // The capture recorded a 4×4 window when the context was made current; the application's
    // window was then resized to 8×6, which the capture shows only through its viewport.
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 4, 4);
    clear(&mut w, [1.0, 0.0, 0.0, 1.0]);
    let first = swap(&mut w);
    let viewport = [("x", W::UInt(0)), ("y", W::UInt(0)), ("width", W::UInt(8)), ("height", W::UInt(6))];
    w.call("glViewport", &viewport, None, false);
    clear(&mut w, [0.0, 1.0, 0.0, 1.0]);
    swap(&mut w);
    // A smaller viewport does not shrink it.
    let viewport = [("x", W::UInt(0)), ("y", W::UInt(0)), ("width", W::UInt(2)), ("height", W::UInt(2))];
    w.call("glViewport", &viewport, None, false);
    clear(&mut w, [0.0, 0.0, 1.0, 1.0]);
    swap(&mut w);

    let (result, frames) = replay(&w);
    result.unwrap();
    assert_eq!((frames[0].1, frames[0].2, frames[0].3), (first, 4, 4));
    assert_eq!(frames[0].4, solid(4, 4, [255, 0, 0, 255]));
    assert_eq!((frames[1].2, frames[1].3), (8, 6));
    assert_eq!(frames[1].4, solid(8, 6, [0, 255, 0, 255]));
    assert_eq!((frames[2].2, frames[2].3), (8, 6));
    assert_eq!(frames[2].4, solid(8, 6, [0, 0, 255, 255]), "glClear ignores the viewport");
}

#[test]
fn norm16_texels_upload_from_a_sub_rectangle_of_a_longer_client_image() {
    // EXT_texture_norm16's R16 from GL_RED/GL_UNSIGNED_SHORT texels, as video players upload
    // 10- and 16-bit planes; GL_UNPACK_ROW_LENGTH / SKIP_PIXELS / SKIP_ROWS pick a 1×1
    // rectangle out of a 3×2 client image; a timer query around the draw changes nothing.
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 4, 4);
    let vertex = "attribute vec2 where;\nvoid main() { gl_Position = vec4(where, 0.0, 1.0); }\n";
    let fragment = "precision highp float;\nuniform sampler2D plane;\n\
                    void main() { gl_FragColor = vec4(texture2D(plane, vec2(0.5)).rgb, 1.0); }\n";
    full_window_program(&mut w, vertex, fragment);
    w.call("glGenTextures", &[("n", W::UInt(1)), ("textures", W::Array(vec![W::UInt(1)]))], None, false);
    w.call("glBindTexture", &[("target", e("GL_TEXTURE_2D", 0x0de1)), ("texture", W::UInt(1))], None, false);
    tex_parameter(&mut w, ("GL_TEXTURE_MIN_FILTER", 0x2801), ("GL_NEAREST", 0x2600));
    tex_parameter(&mut w, ("GL_TEXTURE_MAG_FILTER", 0x2800), ("GL_NEAREST", 0x2600));
    pixel_store(&mut w, ("GL_UNPACK_ALIGNMENT", 0x0cf5), 2);
    pixel_store(&mut w, ("GL_UNPACK_ROW_LENGTH", 0x0cf2), 3);
    pixel_store(&mut w, ("GL_UNPACK_SKIP_PIXELS", 0x0cf4), 2);
    pixel_store(&mut w, ("GL_UNPACK_SKIP_ROWS", 0x0cf3), 1);
    // Row 1, texel 2 is 0x8080 (round(255 · 32896 / 65535) = 128); every other texel 0xffff.
    let mut texels = vec![0xffu8; 12];
    texels[10..12].copy_from_slice(&0x8080u16.to_le_bytes());
    w.call(
        "glTexImage2D",
        &[
            ("target", e("GL_TEXTURE_2D", 0x0de1)),
            ("level", W::UInt(0)),
            ("internalformat", e("GL_R16_EXT", 0x822a)),
            ("width", W::UInt(1)),
            ("height", W::UInt(1)),
            ("border", W::UInt(0)),
            ("format", e("GL_RED", 0x1903)),
            ("type", e("GL_UNSIGNED_SHORT", 0x1403)),
            ("pixels", W::Blob(texels)),
        ],
        None,
        false,
    );
    w.call("glGenQueriesEXT", &[("n", W::UInt(1)), ("ids", W::Array(vec![W::UInt(4)]))], None, false);
    let timer = [("target", e("GL_TIME_ELAPSED_EXT", 0x88bf))];
    w.call("glBeginQueryEXT", &[timer[0].clone(), ("id", W::UInt(4))], None, false);
    draw_triangle(&mut w);
    w.call("glEndQueryEXT", &timer, None, false);
    let result = [("id", W::UInt(4)), ("pname", e("GL_QUERY_RESULT", 0x8866)), ("params", W::Array(vec![W::UInt(1)]))];
    w.call("glGetQueryObjectui64vEXT", &result, None, false);
    swap(&mut w);

    let (result, frames) = replay(&w);
    let run = result.unwrap();
    assert_eq!(frames[0].4, solid(4, 4, [128, 0, 0, 255]));
    // Reading the timer's result waited for the GPU, as glFinish.
    let ids: Vec<&str> = run.report.findings.iter().map(|f| f.id.as_str()).collect();
    assert_eq!(run.report.findings_with("finish-stall").count(), 1, "{ids:?}");

    // A row length too short for the skipped texels is an error naming the call.
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 4, 4);
    w.call("glGenTextures", &[("n", W::UInt(1)), ("textures", W::Array(vec![W::UInt(1)]))], None, false);
    w.call("glBindTexture", &[("target", e("GL_TEXTURE_2D", 0x0de1)), ("texture", W::UInt(1))], None, false);
    pixel_store(&mut w, ("GL_UNPACK_ROW_LENGTH", 0x0cf2), 2);
    pixel_store(&mut w, ("GL_UNPACK_SKIP_PIXELS", 0x0cf4), 1);
    let upload = w.call(
        "glTexImage2D",
        &[
            ("target", e("GL_TEXTURE_2D", 0x0de1)),
            ("level", W::UInt(0)),
            ("internalformat", e("GL_RGBA", 0x1908)),
            ("width", W::UInt(2)),
            ("height", W::UInt(1)),
            ("border", W::UInt(0)),
            ("format", e("GL_RGBA", 0x1908)),
            ("type", e("GL_UNSIGNED_BYTE", 0x1401)),
            ("pixels", W::Blob(vec![0; 16])),
        ],
        None,
        false,
    );
    let (result, _) = replay(&w);
    let error = result.err().expect("the rectangle overruns the row");
    assert_eq!(error.call(), Some(upload));
    assert!(error.to_string().contains("GL_UNPACK_ROW_LENGTH"), "{error}");
}

#[test]
fn an_attribute_may_point_into_a_buffer_before_its_storage_arrives() {
    // glVertexAttribPointer into buffer 1 while it has no storage (GL allows it; video
    // players set up their vertex arrays so), then glBufferData, then the draw.
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 4, 4);
    let vertex = "attribute vec2 where;\nvoid main() { gl_Position = vec4(where, 0.0, 1.0); }\n";
    let fragment = "precision mediump float;\nvoid main() { gl_FragColor = vec4(0.0, 0.0, 1.0, 1.0); }\n";
    full_window_program(&mut w, vertex, fragment);
    w.call("glGenBuffers", &[("n", W::UInt(1)), ("buffers", W::Array(vec![W::UInt(2)]))], None, false);
    w.call("glBindBuffer", &[("target", e("GL_ARRAY_BUFFER", 0x8892)), ("buffer", W::UInt(2))], None, false);
    let pointer = [
        ("index", W::UInt(5)),
        ("size", W::UInt(2)),
        ("type", e("GL_FLOAT", 0x1406)),
        ("normalized", W::Bool(false)),
        ("stride", W::UInt(0)),
        ("pointer", W::Null),
    ];
    w.call("glVertexAttribPointer", &pointer, None, false);
    let triangle: Vec<u8> = [-1.0f32, -1.0, 3.0, -1.0, -1.0, 3.0].iter().flat_map(|v| v.to_le_bytes()).collect();
    let data = [
        ("target", e("GL_ARRAY_BUFFER", 0x8892)),
        ("size", W::UInt(24)),
        ("data", W::Blob(triangle)),
        ("usage", e("GL_STATIC_DRAW", 0x88e4)),
    ];
    w.call("glBufferData", &data, None, false);
    draw_triangle(&mut w);
    swap(&mut w);
    let (result, frames) = replay(&w);
    result.unwrap();
    assert_eq!(frames[0].4, solid(4, 4, [0, 0, 255, 255]));
}

#[test]
fn texture_gather_returns_the_bilinear_footprint_in_gls_order() {
    // A 2×2 RGBA texture (rows bottom first): red 10, 20 in row 0 and 30, 40 in row 1. At its
    // centre the footprint is all four: (i0, j1), (i1, j1), (i1, j0), (i0, j0) = 30, 40, 20, 10
    // (GL ES 3.1 §8.14.2); with an offset of (1, 0) and REPEAT, i0 and i1 swap; green gathered
    // by its component index.
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 4, 4);
    let vertex = "#version 310 es\nin vec2 where;\nvoid main() { gl_Position = vec4(where, 0.0, 1.0); }\n";
    let fragment = "#version 310 es\nprecision highp float;\nuniform highp sampler2D t;\nout vec4 color;\n\
                    void main() {\n\
                      vec4 g = gl_FragCoord.x < 2.0 ? textureGather(t, vec2(0.5)) : textureGatherOffset(t, vec2(0.5), ivec2(1, 0));\n\
                      color = gl_FragCoord.y < 2.0 ? g : textureGather(t, vec2(0.5), 1);\n\
                    }\n";
    full_window_program(&mut w, vertex, fragment);
    w.call("glGenTextures", &[("n", W::UInt(1)), ("textures", W::Array(vec![W::UInt(1)]))], None, false);
    w.call("glBindTexture", &[("target", e("GL_TEXTURE_2D", 0x0de1)), ("texture", W::UInt(1))], None, false);
    tex_parameter(&mut w, ("GL_TEXTURE_MIN_FILTER", 0x2801), ("GL_NEAREST", 0x2600));
    let texels = vec![10, 1, 0, 0, 20, 2, 0, 0, 30, 3, 0, 0, 40, 4, 0, 0];
    w.call(
        "glTexImage2D",
        &[
            ("target", e("GL_TEXTURE_2D", 0x0de1)),
            ("level", W::UInt(0)),
            ("internalformat", e("GL_RGBA", 0x1908)),
            ("width", W::UInt(2)),
            ("height", W::UInt(2)),
            ("border", W::UInt(0)),
            ("format", e("GL_RGBA", 0x1908)),
            ("type", e("GL_UNSIGNED_BYTE", 0x1401)),
            ("pixels", W::Blob(texels)),
        ],
        None,
        false,
    );
    draw_triangle(&mut w);
    swap(&mut w);
    let (result, frames) = replay(&w);
    result.unwrap();
    // Frames come top row first: rows 2–3 (GL y < 2) are the bottom of the window.
    let pixel = |x: usize, y: usize| frames[0].4[(y * 4 + x) * 4..(y * 4 + x) * 4 + 4].to_vec();
    assert_eq!(pixel(0, 3), [30, 40, 20, 10], "textureGather, red");
    assert_eq!(pixel(3, 3), [40, 30, 10, 20], "textureGatherOffset (1, 0), red");
    assert_eq!(pixel(0, 0), [3, 4, 2, 1], "textureGather, green");
}

#[test]
fn texels_upload_from_a_pixel_unpack_buffer_at_the_pointers_offset() {
    // GStreamer's GL upload: immutable storage (glBufferStorageEXT) bound to
    // GL_PIXEL_UNPACK_BUFFER, then glTexImage2D whose pointer is an offset into it.
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 4, 4);
    let vertex = "attribute vec2 where;\nvoid main() { gl_Position = vec4(where, 0.0, 1.0); }\n";
    let fragment =
        "precision mediump float;\nuniform sampler2D t;\nvoid main() { gl_FragColor = texture2D(t, vec2(0.5)); }\n";
    full_window_program(&mut w, vertex, fragment);
    let unpack = ("target", e("GL_PIXEL_UNPACK_BUFFER", 0x88ec));
    w.call("glGenBuffers", &[("n", W::UInt(1)), ("buffers", W::Array(vec![W::UInt(9)]))], None, false);
    w.call("glBindBuffer", &[unpack.clone(), ("buffer", W::UInt(9))], None, false);
    let storage = [
        unpack.clone(),
        ("size", W::UInt(8)),
        ("data", W::Blob(vec![1, 2, 3, 4, 200, 100, 50, 255])),
        ("flags", W::UInt(0x0100)),
    ];
    w.call("glBufferStorageEXT", &storage, None, false);
    w.call("glGenTextures", &[("n", W::UInt(1)), ("textures", W::Array(vec![W::UInt(1)]))], None, false);
    w.call("glBindTexture", &[("target", e("GL_TEXTURE_2D", 0x0de1)), ("texture", W::UInt(1))], None, false);
    tex_parameter(&mut w, ("GL_TEXTURE_MIN_FILTER", 0x2801), ("GL_NEAREST", 0x2600));
    let upload = |offset: W| {
        [
            ("target", e("GL_TEXTURE_2D", 0x0de1)),
            ("level", W::UInt(0)),
            ("internalformat", e("GL_RGBA", 0x1908)),
            ("width", W::UInt(1)),
            ("height", W::UInt(1)),
            ("border", W::UInt(0)),
            ("format", e("GL_RGBA", 0x1908)),
            ("type", e("GL_UNSIGNED_BYTE", 0x1401)),
            ("pixels", offset),
        ]
    };
    w.call("glTexImage2D", &upload(W::Pointer(4)), None, false);
    w.call("glBindBuffer", &[unpack.clone(), ("buffer", W::UInt(0))], None, false);
    draw_triangle(&mut w);
    swap(&mut w);
    // An offset past the buffer's end is an error naming the call.
    w.call("glBindBuffer", &[unpack, ("buffer", W::UInt(9))], None, false);
    let past = w.call("glTexImage2D", &upload(W::Pointer(12)), None, false);

    let (result, frames) = replay(&w);
    assert_eq!(frames[0].4, solid(4, 4, [200, 100, 50, 255]));
    let error = result.err().expect("offset 12 of 8 bytes");
    assert_eq!(error.call(), Some(past));
    assert!(error.to_string().contains("past the end of pixel unpack buffer 9"), "{error}");
}

#[test]
fn read_buffer_none_is_taken_and_a_colour_read_after_it_names_the_call() {
    // glReadBuffer(GL_NONE) on the window is a GL error in ES 3.0, but tiler takes it as a
    // state change like any framebuffer's; a read of colour then fails, naming the call.
    let read_none = |w: &mut Writer| w.call("glReadBuffer", &[("src", e("GL_NONE", 0))], None, false);
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 4, 4);
    clear(&mut w, [1.0, 0.0, 0.0, 1.0]);
    read_none(&mut w);
    w.call("glReadBuffer", &[("src", e("GL_BACK", 0x0405))], None, false);
    swap(&mut w);
    let (result, frames) = replay(&w);
    result.unwrap();
    assert_eq!(frames[0].4, solid(4, 4, [255, 0, 0, 255]));

    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 4, 4);
    read_none(&mut w);
    let args = [
        ("x", W::UInt(0)),
        ("y", W::UInt(0)),
        ("width", W::UInt(1)),
        ("height", W::UInt(1)),
        ("format", e("GL_RGBA", 0x1908)),
        ("type", e("GL_UNSIGNED_BYTE", 0x1401)),
        ("pixels", W::Blob(vec![0; 4])),
    ];
    let call = w.call("glReadPixels", &args, None, false);
    let (result, _) = replay(&w);
    let error = result.err().expect("a colour read with GL_NONE");
    assert_eq!(error.call(), Some(call));
    assert!(error.to_string().contains("GL_NONE"), "{error}");
}

#[test]
fn uniform_array_values_past_the_last_element_are_ignored() {
    // GL ES 3.0 §2.12.6: glUniform4fv of 5 elements into `vec4 colors[3]` sets the three and
    // ignores the rest (GStreamer's blur sets 9 floats into `float kernel[7]`).
    let (w, _) = uniform_array_capture(
        |w| {
            let mut values = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.6, 0.4, 0.2, 1.0].to_vec();
            values.extend([9.0f32; 8]);
            let values = values.into_iter().map(W::Float).collect();
            let args = [("location", W::UInt(3)), ("count", W::UInt(5)), ("value", W::Array(values))];
            w.call("glUniform4fv", &args, None, false);
        },
        |_| {},
    );
    let (result, frames) = replay(&w);
    result.unwrap();
    assert_eq!(frames[0].4, solid(4, 4, [153, 102, 51, 255]));
}

/// textureGather of an uploaded and of a rendered 8×8 texture at irregular coordinates: the
/// four texels and their order are llvmpipe's, every byte (`gather.frag`; each texel's red
/// names it).
#[test]
fn float_probe_texture_gather_is_llvmpipes_for_uploaded_and_rendered_textures() {
    for (name, call) in [("gather-upload", 40), ("gather-render", 61)] {
        let values = float_probe(name, call);
        assert_eq!(values.len(), 64);
        let differ: Vec<_> = values.iter().filter(|&&(.., got, want)| got != want).collect();
        assert!(differ.is_empty(), "{name}: (y, x, tiler, llvmpipe) {differ:x?}");
    }
}

/// Linear filtering of RGBA8 textures, llvmpipe's to the bit (`tools/float-probe`'s
/// `filter.frag` and `filter-lod.frag` on `FLOAT_PROBE_TEXTURE=varied` textures of bytes from
/// a generator, at irregular sub-texel positions inside and outside `[0, 1]`): llvmpipe's AoS
/// sampler takes the coordinate in fixed point (`round(256 · s · n) − 128`, its low byte the
/// weight), lerps bytes (`a + ((b − a) · w + 128) >> 8`), blends levels by `⌊256 · fract(λ)⌋`
/// and converts the byte as `c · fl(1/255)`. Clamp-to-edge and repeat, a 7×5 texture
/// (`texture`) and an 8×8 one with its levels given (`textureLod` at irregular levels): from
/// 0–44 of 256 values equal before, to all.
#[test]
fn float_probe_linear_filter_is_llvmpipes_to_the_bit() {
    for (name, call) in
        [("filter-npot-repeat", 42), ("filter-npot-clamp", 42), ("filter-lod-repeat", 48), ("filter-lod-clamp", 48)]
    {
        let values = float_probe(name, call);
        assert_eq!(values.len(), 256, "{name}");
        let differ: Vec<_> = values.iter().filter(|&&(.., got, want)| got != want).collect();
        assert!(differ.is_empty(), "{name}: {} differ (y, x, tiler, llvmpipe) {differ:x?}", differ.len());
    }
}

/// The level of detail of `texture()` in a fragment shader, llvmpipe's to the bit
/// (`tools/float-probe`'s `filter-implicit.frag`: quads whose derivatives vary from quad to
/// quad, skewed, and a bias varying between groups, on the 8×8 texture with its levels given;
/// λ from about −3 to 3): one λ per quad from its first pixel's differences of the
/// coordinates, scaled to texels after the difference, `ρ²` the larger squared length, and
/// `λ = ½ · fast_log2(ρ²) + bias` with llvmpipe's piecewise linear `fast_log2` (`⌊log2 x⌋ − 1 +
/// mantissa`); trilinear blends by `⌊256 · fract(λ)⌋`, `LINEAR_MIPMAP_NEAREST` takes `λ`
/// rounded, halves up. With the exact logarithm and the differences of scaled coordinates,
/// 657 of the 1024 trilinear values differed (and 28 with `LINEAR_MIPMAP_NEAREST`).
#[test]
fn float_probe_implicit_level_of_detail_is_llvmpipes_to_the_bit() {
    for name in ["filter-implicit-repeat", "filter-implicit-clamp", "filter-implicit-mip-nearest"] {
        let values = float_probe(name, 48);
        assert_eq!(values.len(), 1024, "{name}");
        let differ: Vec<_> = values.iter().filter(|&&(.., got, want)| got != want).collect();
        assert!(differ.is_empty(), "{name}: {} differ (y, x, tiler, llvmpipe) {differ:x?}", differ.len());
    }
}

/// `texelFetch` of an RGBA8 texture converts each byte as llvmpipe does, `c · fl(1/255)`
/// (`fetch.frag`, every texel of an 8×8 texture of generated bytes): 54 of 256 values differed
/// by an ulp when it divided by 255.
#[test]
fn float_probe_texel_fetch_is_llvmpipes_to_the_bit() {
    let values = float_probe("fetch", 40);
    assert_eq!(values.len(), 256);
    let differ: Vec<_> = values.iter().filter(|&&(.., got, want)| got != want).collect();
    assert!(differ.is_empty(), "{} differ (y, x, tiler, llvmpipe) {differ:x?}", differ.len());
}

#[test]
fn ten_bit_samples_in_r16_texels_are_sampled_at_sixteen_bits() {
    // mpv's 10-bit video: samples in the low bits of R16 texels, scaled by 65535/1023 in the
    // shader. Texel 700 reads 700/65535 · 65535/1023 = 0.684 (174/255); at 8 bits it would be
    // byte 3, 0.754 (192/255). The right texel comes from a glTexSubImage2D.
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 4, 4);
    let vertex = "attribute vec2 where;\nvoid main() { gl_Position = vec4(where, 0.0, 1.0); }\n";
    let fragment = "precision highp float;\nuniform sampler2D plane;\n\
                    void main() { float s = gl_FragCoord.x < 2.0 ? 0.25 : 0.75;\n\
                    gl_FragColor = vec4(texture2D(plane, vec2(s, 0.5)).r * (65535.0 / 1023.0), 0.0, 0.0, 1.0); }\n";
    full_window_program(&mut w, vertex, fragment);
    w.call("glGenTextures", &[("n", W::UInt(1)), ("textures", W::Array(vec![W::UInt(1)]))], None, false);
    w.call("glBindTexture", &[("target", e("GL_TEXTURE_2D", 0x0de1)), ("texture", W::UInt(1))], None, false);
    tex_parameter(&mut w, ("GL_TEXTURE_MIN_FILTER", 0x2801), ("GL_NEAREST", 0x2600));
    tex_parameter(&mut w, ("GL_TEXTURE_MAG_FILTER", 0x2800), ("GL_NEAREST", 0x2600));
    let texels: Vec<u8> = [700u16, 0].iter().flat_map(|c| c.to_le_bytes()).collect();
    let image = |w: &mut Writer, call: &str, x: u64, width: u64, texels: Vec<u8>| {
        let mut args = vec![("target", e("GL_TEXTURE_2D", 0x0de1)), ("level", W::UInt(0))];
        if call == "glTexImage2D" {
            args.push(("internalformat", e("GL_R16_EXT", 0x822a)));
        } else {
            args.extend([("xoffset", W::UInt(x)), ("yoffset", W::UInt(0))]);
        }
        args.extend([("width", W::UInt(width)), ("height", W::UInt(1))]);
        if call == "glTexImage2D" {
            args.push(("border", W::UInt(0)));
        }
        args.extend([
            ("format", e("GL_RED", 0x1903)),
            ("type", e("GL_UNSIGNED_SHORT", 0x1403)),
            ("pixels", W::Blob(texels)),
        ]);
        w.call(call, &args, None, false);
    };
    image(&mut w, "glTexImage2D", 0, 2, texels);
    image(&mut w, "glTexSubImage2D", 1, 1, 700u16.to_le_bytes().to_vec());
    draw_triangle(&mut w);
    swap(&mut w);
    let (result, frames) = replay(&w);
    result.unwrap();
    for x in [0, 3] {
        let red = frames[0].4[x * 4];
        assert!(red.abs_diff(174) <= 1, "pixel {x}: red {red}, not 174 (192 is 8 bits)");
    }
}

/// `eglCreateContext` sharing objects with `share` (0: none).
fn create_context(w: &mut Writer, context: u64, share: u64) {
    let attribs = W::Array(vec![W::UInt(0x3098), W::UInt(2), W::UInt(0x3038)]);
    let share = if share == 0 { W::Null } else { W::Pointer(share) };
    w.call(
        "eglCreateContext",
        &[("dpy", W::Pointer(1)), ("config", W::Pointer(2)), ("share_context", share), ("attrib_list", attribs)],
        Some(W::Pointer(context)),
        false,
    );
}

/// `eglMakeCurrent` of `context` (0: none) on `surface` (0: none).
fn make_current(w: &mut Writer, surface: u64, context: u64) -> u64 {
    let handle = |h: u64| if h == 0 { W::Null } else { W::Pointer(h) };
    w.call(
        "eglMakeCurrent",
        &[("dpy", W::Pointer(1)), ("draw", handle(surface)), ("read", handle(surface)), ("ctx", handle(context))],
        Some(W::Bool(true)),
        false,
    )
}

#[test]
fn contexts_sharing_objects_see_each_others_textures() {
    // The window's context is made current (apitrace's fake viewport gives the window's size)
    // and released; a loader context sharing its objects, current without a surface as
    // toolkits' share contexts are, uploads a texture and goes; the window's context draws
    // with it.
    let mut w = Writer::new(6);
    window_surface(&mut w);
    create_context(&mut w, 100, 0);
    create_context(&mut w, 200, 100);
    make_current(&mut w, 3, 200);
    let viewport = [("x", W::UInt(0)), ("y", W::UInt(0)), ("width", W::UInt(4)), ("height", W::UInt(4))];
    w.call("glViewport", &viewport, None, true);
    make_current(&mut w, 0, 0);
    make_current(&mut w, 0, 100);
    texture_rgb(&mut w, 5, 1, 1, vec![30, 60, 90, 0]);
    tex_parameter(&mut w, ("GL_TEXTURE_MIN_FILTER", 0x2801), ("GL_NEAREST", 0x2600));
    make_current(&mut w, 0, 0);
    w.call("eglDestroyContext", &[("dpy", W::Pointer(1)), ("ctx", W::Pointer(100))], Some(W::Bool(true)), false);
    make_current(&mut w, 3, 200);
    let vertex = "attribute vec2 where;\nvoid main() { gl_Position = vec4(where, 0.0, 1.0); }\n";
    let fragment =
        "precision mediump float;\nuniform sampler2D t;\nvoid main() { gl_FragColor = texture2D(t, vec2(0.5)); }\n";
    full_window_program(&mut w, vertex, fragment);
    w.call("glBindTexture", &[("target", e("GL_TEXTURE_2D", 0x0de1)), ("texture", W::UInt(5))], None, false);
    draw_triangle(&mut w);
    swap(&mut w);
    let (result, frames) = replay(&w);
    result.unwrap();
    assert_eq!(frames[0].4, solid(4, 4, [30, 60, 90, 255]));
}

#[test]
fn programs_linked_on_a_live_share_context_are_drawn_with_on_another() {
    // GTK 4: a share context, current without a surface, compiles and links every program
    // (objects of the share group, no state of its own changed) and stays alive; the window's
    // context is made current and draws with them. The program passes a structure from
    // vertex to fragment shader (GLSL ES 3.00 §4.3.4), as GTK's rounded rectangles are.
    let mut w = Writer::new(6);
    window_surface(&mut w);
    create_context(&mut w, 100, 0);
    create_context(&mut w, 200, 100);
    make_current(&mut w, 0, 100);
    let vertex = "#version 300 es\nstruct Rect { vec4 bounds; vec2 corner; };\nin vec2 where;\nout Rect r;\n\
                  void main() { r.bounds = vec4(0.25, 0.5, 0.75, 1.0); r.corner = vec2(where.x * 0.0 + 0.125, 0.375);\n\
                  gl_Position = vec4(where, 0.0, 1.0); }\n";
    let fragment = "#version 300 es\nprecision mediump float;\nstruct Rect { vec4 bounds; vec2 corner; };\nin Rect r;\n\
                    out vec4 color;\nvoid main() { color = vec4(r.bounds.xy, r.corner.y + r.bounds.w - 1.0, 1.0); }\n";
    link_program(&mut w, vertex, fragment);
    let switch = make_current(&mut w, 3, 200);
    let viewport = [("x", W::UInt(0)), ("y", W::UInt(0)), ("width", W::UInt(4)), ("height", W::UInt(4))];
    w.call("glViewport", &viewport, None, true);
    use_program_on_full_window_triangle(&mut w);
    draw_triangle(&mut w);
    swap(&mut w);
    let (result, frames) = replay(&w);
    result.unwrap_or_else(|e| panic!("at call {switch}: {e}"));
    assert_eq!(frames[0].4, solid(4, 4, [64, 128, 96, 255]));
}

#[test]
fn two_live_contexts_that_changed_state_each_keep_theirs() {
    // Context 100 sets a red clear colour and a 2×2 viewport; 200, sharing its objects, sets
    // green and clears the whole window; back on 100, a clear is red again and a triangle
    // drawn fills only 100's viewport (the lower-left 2×2).
    let mut w = Writer::new(6);
    window_surface(&mut w);
    create_context(&mut w, 100, 0);
    create_context(&mut w, 200, 100);
    make_current(&mut w, 3, 100);
    let viewport = |w: &mut Writer, size: u64, fake: bool| {
        let args = [("x", W::UInt(0)), ("y", W::UInt(0)), ("width", W::UInt(size)), ("height", W::UInt(size))];
        w.call("glViewport", &args, None, fake);
    };
    viewport(&mut w, 4, true);
    clear(&mut w, [1.0, 0.0, 0.0, 1.0]);
    viewport(&mut w, 2, false);
    // Made current and at once released, then 100 again, nothing called between: nothing is
    // switched (GTK 4 does this each frame).
    make_current(&mut w, 0, 200);
    make_current(&mut w, 0, 0);
    make_current(&mut w, 3, 100);
    swap(&mut w);
    make_current(&mut w, 3, 200);
    clear(&mut w, [0.0, 1.0, 0.0, 1.0]);
    make_current(&mut w, 3, 100);
    let vertex = "attribute vec2 where;\nvoid main() { gl_Position = vec4(where, 0.0, 1.0); }\n";
    let fragment = "precision mediump float;\nvoid main() { gl_FragColor = vec4(0.0, 0.0, 1.0, 1.0); }\n";
    full_window_program(&mut w, vertex, fragment);
    draw_triangle(&mut w);
    swap(&mut w);
    let (result, frames) = replay(&w);
    result.unwrap();
    assert_eq!(frames[0].4, solid(4, 4, [255, 0, 0, 255]));
    let picture = &frames[1].4;
    for y in 0..4 {
        for x in 0..4 {
            let i = (y * 4 + x) * 4;
            // tiler's rows run top to bottom: 100's viewport is rows 2 and 3, columns 0 and 1.
            let expected = if y >= 2 && x < 2 { [0, 0, 255, 255] } else { [0, 255, 0, 255] };
            assert_eq!(picture[i..i + 4], expected, "pixel ({x}, {y})");
        }
    }
}

#[test]
fn drawing_to_framebuffer_0_without_a_surface_is_refused_naming_the_call() {
    // A context current without a surface has no default framebuffer
    // (EGL_KHR_surfaceless_context): GL draws nothing there, the replay would draw into the
    // window, so the clear is refused by name.
    let mut w = Writer::new(6);
    window_surface(&mut w);
    create_context(&mut w, 100, 0);
    create_context(&mut w, 200, 100);
    make_current(&mut w, 3, 100);
    let viewport = [("x", W::UInt(0)), ("y", W::UInt(0)), ("width", W::UInt(4)), ("height", W::UInt(4))];
    w.call("glViewport", &viewport, None, true);
    clear(&mut w, [1.0, 0.0, 0.0, 1.0]);
    make_current(&mut w, 0, 200);
    clear(&mut w, [0.0, 1.0, 0.0, 1.0]);
    let call = w.call("glFlush", &[], None, false) - 1;
    let (result, _) = replay(&w);
    let error = result.err().expect("a clear of framebuffer 0 without a surface");
    assert_eq!(error.call(), Some(call), "{error}");
    assert!(error.to_string().contains("without a surface"), "{error}");
}

#[test]
fn a_pbuffer_beside_the_window_may_be_current_but_not_drawn_to() {
    // Qt makes a 1×1 pbuffer for its offscreen context beside the window. Made (and current
    // for object work) it changes nothing; a clear of it is refused by name, as a swap of it.
    let capture = |draw_on_pbuffer: bool| {
        let mut w = Writer::new(6);
        window_surface(&mut w);
        create_context(&mut w, 100, 0);
        let attribs = W::Array([0x3057, 1, 0x3056, 1, 0x3038].map(W::UInt).to_vec());
        let args = [("dpy", W::Pointer(1)), ("config", W::Pointer(2)), ("attrib_list", attribs)];
        w.call("eglCreatePbufferSurface", &args, Some(W::Pointer(4)), false);
        make_current(&mut w, 3, 100);
        let viewport = [("x", W::UInt(0)), ("y", W::UInt(0)), ("width", W::UInt(4)), ("height", W::UInt(4))];
        w.call("glViewport", &viewport, None, true);
        clear(&mut w, [0.0, 1.0, 0.0, 1.0]);
        make_current(&mut w, 4, 100);
        let call = draw_on_pbuffer.then(|| {
            clear(&mut w, [1.0, 0.0, 0.0, 1.0]);
            w.call("glFlush", &[], None, false) - 1
        });
        make_current(&mut w, 3, 100);
        swap(&mut w);
        (w, call)
    };
    let (w, _) = capture(false);
    let (result, frames) = replay(&w);
    result.unwrap();
    assert_eq!(frames[0].4, solid(4, 4, [0, 255, 0, 255]));
    let (w, call) = capture(true);
    let (result, _) = replay(&w);
    let error = result.err().expect("a clear of the pbuffer");
    assert_eq!(error.call(), call, "{error}");
    assert!(error.to_string().contains("on a pbuffer made beside the window"), "{error}");
}

#[test]
fn a_client_wait_stalls_only_while_its_fences_frame_is_in_flight() {
    // Frame 0 clears and puts a fence; frames 1–3 clear. Frame 3 waits on frame 0's fence,
    // frames in flight (3) old: no stall. Frame 3 then puts a fence and waits on it at once:
    // its pass is flushed and the CPU waits for the frame (one finish-stall, named by the call).
    // A zero timeout polls and never waits; a wait on a fence the capture does not have (made
    // before a trimmed capture begins) is taken as a glFinish.
    let fence = |w: &mut Writer, handle: u64| {
        let args = [("condition", e("GL_SYNC_GPU_COMMANDS_COMPLETE", 0x9117)), ("flags", W::UInt(0))];
        w.call("glFenceSync", &args, Some(W::UInt(handle)), false);
    };
    let wait = |w: &mut Writer, handle: u64, timeout: u64| {
        let args = [("sync", W::UInt(handle)), ("flags", W::UInt(1)), ("timeout", W::UInt(timeout))];
        w.call("glClientWaitSync", &args, Some(e("GL_CONDITION_SATISFIED", 0x911c)), false)
    };
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 4, 4);
    clear(&mut w, [1.0, 0.0, 0.0, 1.0]);
    fence(&mut w, 0x10);
    swap(&mut w);
    for _ in 0..3 {
        clear(&mut w, [0.0, 1.0, 0.0, 1.0]);
        wait(&mut w, 0x10, 0);
        swap(&mut w);
    }
    clear(&mut w, [0.0, 0.0, 1.0, 1.0]);
    wait(&mut w, 0x10, 1_000_000_000);
    fence(&mut w, 0x20);
    wait(&mut w, 0x20, 1_000_000_000);
    swap(&mut w);
    let (result, frames) = replay(&w);
    let run = result.unwrap();
    assert_eq!(frames[4].4, solid(4, 4, [0, 0, 255, 255]));
    let stalls: Vec<_> = run.report.findings_with("finish-stall").collect();
    assert_eq!(stalls.len(), 1, "{stalls:?}");
    assert!(stalls[0].message.contains("client_wait_sync"), "{}", stalls[0].message);

    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 4, 4);
    clear(&mut w, [1.0, 0.0, 0.0, 1.0]);
    wait(&mut w, 0x30, 1_000_000_000);
    swap(&mut w);
    let (result, _) = replay(&w);
    let stalls: Vec<_> = result.unwrap().report.findings_with("finish-stall").map(|f| f.message.clone()).collect();
    assert!(stalls.len() == 1 && stalls[0].contains("finish at"), "{stalls:?}");
}

/// A 1×1 `GL_RG8` font texture on unit 0 read as luminance–alpha through swizzles, and a 1×1
/// cube map from `glTexStorage2D` on unit 1: what LÖVE makes at start-up. `extra` runs before
/// the draw, an indexed one through `glDrawElementsBaseVertex` with `base_vertex`.
fn swizzle_and_cube_capture(base_vertex: u64, extra: impl FnOnce(&mut Writer)) -> (Writer, u64) {
    let mut w = Writer::new(6);
    window_surface(&mut w);
    begin_context(&mut w, 100, 4, 4);
    let vertex = "attribute vec2 where;\nvoid main() { gl_Position = vec4(where, 0.0, 1.0); }\n";
    let fragment = "precision mediump float;\nuniform sampler2D font;\nuniform samplerCube cube;\n\
                    void main() { vec4 f = texture2D(font, vec2(0.5));\n\
                    gl_FragColor = gl_FragCoord.x < 2.0 ? vec4(f.r, f.g, f.a, 1.0) : textureCube(cube, vec3(1.0, 0.0, 0.0)); }\n";
    full_window_program(&mut w, vertex, fragment);
    w.call("glGetUniformLocation", &[("program", W::UInt(7)), ("name", W::Str("cube"))], Some(W::UInt(4)), false);
    w.call("glUniform1i", &[("location", W::UInt(4)), ("v0", W::UInt(1))], None, false);
    // LÖVE's start-up: every array up to GL_MAX_VERTEX_ATTRIBS (16) disabled, every unit up to
    // GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS unbound, sRGB writes off, no anisotropy.
    w.call("glDisableVertexAttribArray", &[("index", W::UInt(12))], None, false);
    w.call("glActiveTexture", &[("texture", e("GL_TEXTURE20", 0x84c0 + 20))], None, false);
    w.call("glBindTexture", &[("target", e("GL_TEXTURE_2D", 0x0de1)), ("texture", W::UInt(0))], None, false);
    w.call("glBindTexture", &[("target", e("GL_TEXTURE_CUBE_MAP", 0x8513)), ("texture", W::UInt(0))], None, false);
    w.call("glDisable", &[("cap", e("GL_FRAMEBUFFER_SRGB_EXT", 0x8db9))], None, false);

    w.call("glActiveTexture", &[("texture", e("GL_TEXTURE0", 0x84c0))], None, false);
    w.call("glGenTextures", &[("n", W::UInt(1)), ("textures", W::Array(vec![W::UInt(1)]))], None, false);
    w.call("glBindTexture", &[("target", e("GL_TEXTURE_2D", 0x0de1)), ("texture", W::UInt(1))], None, false);
    tex_parameter(&mut w, ("GL_TEXTURE_MIN_FILTER", 0x2801), ("GL_NEAREST", 0x2600));
    tex_parameter(&mut w, ("GL_TEXTURE_MAG_FILTER", 0x2800), ("GL_NEAREST", 0x2600));
    let anisotropy = [("target", e("GL_TEXTURE_2D", 0x0de1)), ("pname", e("GL_TEXTURE_MAX_ANISOTROPY_EXT", 0x84fe))];
    w.call("glTexParameterf", &[anisotropy[0].clone(), anisotropy[1].clone(), ("param", W::Float(1.0))], None, false);
    for (pname, value) in [(0x8e42, ("GL_RED", 0x1903)), (0x8e43, ("GL_RED", 0x1903)), (0x8e44, ("GL_RED", 0x1903))] {
        tex_parameter(&mut w, ("GL_TEXTURE_SWIZZLE", pname), value);
    }
    tex_parameter(&mut w, ("GL_TEXTURE_SWIZZLE_A", 0x8e45), ("GL_GREEN", 0x1904));
    let storage = |w: &mut Writer, target: (&'static str, u32), format: (&'static str, u32)| {
        let args = [
            ("target", e(target.0, target.1)),
            ("levels", W::UInt(1)),
            ("internalformat", e(format.0, format.1)),
            ("width", W::UInt(1)),
            ("height", W::UInt(1)),
        ];
        w.call("glTexStorage2D", &args, None, false);
    };
    let sub_image = |w: &mut Writer, target: (&'static str, u32), format: (&'static str, u32), texels: Vec<u8>| {
        let args = [
            ("target", e(target.0, target.1)),
            ("level", W::UInt(0)),
            ("xoffset", W::UInt(0)),
            ("yoffset", W::UInt(0)),
            ("width", W::UInt(1)),
            ("height", W::UInt(1)),
            ("format", e(format.0, format.1)),
            ("type", e("GL_UNSIGNED_BYTE", 0x1401)),
            ("pixels", W::Blob(texels)),
        ];
        w.call("glTexSubImage2D", &args, None, false)
    };
    storage(&mut w, ("GL_TEXTURE_2D", 0x0de1), ("GL_RG8", 0x822b));
    sub_image(&mut w, ("GL_TEXTURE_2D", 0x0de1), ("GL_RG", 0x8227), vec![200, 100]);

    w.call("glActiveTexture", &[("texture", e("GL_TEXTURE1", 0x84c1))], None, false);
    w.call("glGenTextures", &[("n", W::UInt(1)), ("textures", W::Array(vec![W::UInt(2)]))], None, false);
    w.call("glBindTexture", &[("target", e("GL_TEXTURE_CUBE_MAP", 0x8513)), ("texture", W::UInt(2))], None, false);
    storage(&mut w, ("GL_TEXTURE_CUBE_MAP", 0x8513), ("GL_RGBA8", 0x8058));
    for face in 0..6u32 {
        let texel = if face == 0 { vec![10, 20, 30, 255] } else { vec![255, 0, 255, 255] };
        sub_image(&mut w, ("GL_TEXTURE_CUBE_MAP_POSITIVE_X", 0x8515 + face), ("GL_RGBA", 0x1908), texel);
    }
    extra(&mut w);
    let indices: Vec<u8> = [0u16, 1, 2].iter().flat_map(|i| i.to_le_bytes()).collect();
    let args = [
        ("mode", e("GL_TRIANGLES", 4)),
        ("count", W::UInt(3)),
        ("type", e("GL_UNSIGNED_SHORT", 0x1403)),
        ("indices", W::Blob(indices)),
        ("basevertex", W::UInt(base_vertex)),
    ];
    let draw = w.call("glDrawElementsBaseVertex", &args, None, false);
    swap(&mut w);
    (w, draw)
}

#[test]
fn swizzled_red_green_textures_and_cube_storage_sample_as_gl_says() {
    let (w, _) = swizzle_and_cube_capture(0, |_| {});
    let (result, frames) = replay(&w);
    result.unwrap();
    let pixel = |x: usize| &frames[0].4[x * 4..x * 4 + 4];
    // Swizzled RRRG: (200, 200, 200, 100), drawn as (r, g, a).
    assert_eq!(pixel(0), [200, 200, 100, 255]);
    // The cube's +X face, from glTexSubImage2D into glTexStorage2D storage.
    assert_eq!(pixel(3), [10, 20, 30, 255]);
}

#[test]
fn what_the_replay_cannot_apply_after_lenient_start_up_calls_fails_with_its_call() {
    let refused = |w: Writer, call: u64, what: &str| {
        let (result, _) = replay(&w);
        let error = result.err().expect("refused");
        assert_eq!(error.call(), Some(call), "{error}");
        assert!(error.to_string().contains(what), "{error}");
    };
    // A base vertex other than 0.
    let (w, draw) = swizzle_and_cube_capture(1, |_| {});
    refused(w, draw, "base vertex 1");
    // A texture bound on a unit beyond the context's.
    let mut call = 0;
    let (w, _) = swizzle_and_cube_capture(0, |w| {
        w.call("glActiveTexture", &[("texture", e("GL_TEXTURE12", 0x84c0 + 12))], None, false);
        call = w.call("glBindTexture", &[("target", e("GL_TEXTURE_2D", 0x0de1)), ("texture", W::UInt(1))], None, false);
    });
    refused(w, call, "texture unit 12");
    // A swizzle changed once the texture has storage.
    let (w, _) = swizzle_and_cube_capture(0, |w| {
        w.call("glActiveTexture", &[("texture", e("GL_TEXTURE0", 0x84c0))], None, false);
        call = tex_parameter_call(w, ("GL_TEXTURE_SWIZZLE_R", 0x8e42), ("GL_GREEN", 0x1904));
    });
    refused(w, call, "GL_TEXTURE_SWIZZLE");
    // An array beyond the context's enabled.
    let (w, _) = swizzle_and_cube_capture(0, |w| {
        call = w.call("glEnableVertexAttribArray", &[("index", W::UInt(12))], None, false);
    });
    refused(w, call, "vertex attribute 12");
}

/// A compositor's start-up (Weston's GL renderer): its context current without a surface
/// while it compiles a program, then a 4×4 pbuffer made current; the program samples a
/// `GL_BGRA_EXT` texture in the branch a constant selects and an unbound unit in the other.
/// `before_surface` runs before the pbuffer exists.
fn surfaceless_start_capture(before_surface: impl FnOnce(&mut Writer)) -> Writer {
    let mut w = Writer::new(6);
    create_context(&mut w, 100, 0);
    make_current(&mut w, 0, 100);
    let vertex = "attribute vec2 where;\nvoid main() { gl_Position = vec4(where, 0.0, 1.0); }\n";
    let fragment = "precision mediump float;\nuniform sampler2D tex;\nuniform sampler2D other;\n\
                    const int variant = 1;\n\
                    vec4 pick() { if (variant == 1) return texture2D(tex, vec2(0.5));\n\
                    return texture2D(other, vec2(0.5)); }\n\
                    void main() { gl_FragColor = pick(); }\n";
    full_window_program(&mut w, vertex, fragment);
    w.call("glGetUniformLocation", &[("program", W::UInt(7)), ("name", W::Str("other"))], Some(W::UInt(4)), false);
    w.call("glUniform1i", &[("location", W::UInt(4)), ("v0", W::UInt(1))], None, false);
    before_surface(&mut w);
    let attribs = W::Array([0x3057, 4, 0x3056, 4, 0x3038].map(W::UInt).to_vec());
    w.call(
        "eglCreatePbufferSurface",
        &[("dpy", W::Pointer(1)), ("config", W::Pointer(2)), ("attrib_list", attribs)],
        Some(W::Pointer(3)),
        false,
    );
    make_current(&mut w, 3, 100);
    // apitrace's fake viewport: EGL sets it to the surface the first time one is current.
    let viewport = [("x", W::UInt(0)), ("y", W::UInt(0)), ("width", W::UInt(4)), ("height", W::UInt(4))];
    w.call("glViewport", &viewport, None, true);
    w.call("glGenTextures", &[("n", W::UInt(1)), ("textures", W::Array(vec![W::UInt(1)]))], None, false);
    w.call("glBindTexture", &[("target", e("GL_TEXTURE_2D", 0x0de1)), ("texture", W::UInt(1))], None, false);
    tex_parameter(&mut w, ("GL_TEXTURE_MIN_FILTER", 0x2801), ("GL_NEAREST", 0x2600));
    let args = [
        ("target", e("GL_TEXTURE_2D", 0x0de1)),
        ("level", W::UInt(0)),
        ("internalformat", e("GL_BGRA_EXT", 0x80e1)),
        ("width", W::UInt(1)),
        ("height", W::UInt(1)),
        ("border", W::UInt(0)),
        ("format", e("GL_BGRA_EXT", 0x80e1)),
        ("type", e("GL_UNSIGNED_BYTE", 0x1401)),
        ("pixels", W::Blob(vec![10, 20, 30, 255])),
    ];
    w.call("glTexImage2D", &args, None, false);
    draw_triangle(&mut w);
    w.call("eglSwapBuffers", &[("dpy", W::Pointer(1)), ("surface", W::Pointer(3))], Some(W::Bool(true)), false);
    w
}

#[test]
fn a_context_current_without_a_surface_takes_the_size_of_the_pbuffer_made_current_later() {
    let (result, frames) = replay(&surfaceless_start_capture(|_| {}));
    result.unwrap();
    assert_eq!(frames.len(), 1);
    assert_eq!((frames[0].2, frames[0].3), (4, 4));
    // BGRA bytes (10, 20, 30) are red 30, green 20, blue 10; the sampler on the unbound unit
    // is read only in the branch the constant removes, so it needs no texture.
    assert_eq!(frames[0].4, solid(4, 4, [30, 20, 10, 255]));

    // Drawing into the window before its size is known is refused, naming the call.
    let mut call = 0;
    let w = surfaceless_start_capture(|w| {
        w.call("glClear", &[("mask", W::UInt(0x4000))], None, false);
        call = w.call(
            "glDrawArrays",
            &[("mode", e("GL_TRIANGLES", 4)), ("first", W::UInt(0)), ("count", W::UInt(3))],
            None,
            false,
        );
    });
    let (result, _) = replay(&w);
    let error = result.err().expect("a draw into a window of unknown size");
    assert_eq!(error.call(), Some(call - 1), "{error}");
    assert!(error.to_string().contains("window's size is not known"), "{error}");
}

#[test]
fn srgb_writes_switched_off_are_refused_only_where_they_would_matter() {
    // LÖVE switches GL_FRAMEBUFFER_SRGB_EXT off at start-up: harmless on the window (not
    // sRGB), refused on a draw into an sRGB texture (tiler would encode it).
    let capture = |attach_srgb: bool| {
        let mut w = Writer::new(6);
        window_surface(&mut w);
        begin_context(&mut w, 100, 2, 2);
        w.call("glDisable", &[("cap", e("GL_FRAMEBUFFER_SRGB_EXT", 0x8db9))], None, false);
        if attach_srgb {
            w.call("glGenTextures", &[("n", W::UInt(1)), ("textures", W::Array(vec![W::UInt(5)]))], None, false);
            w.call("glBindTexture", &[("target", e("GL_TEXTURE_2D", 0x0de1)), ("texture", W::UInt(5))], None, false);
            let args = [
                ("target", e("GL_TEXTURE_2D", 0x0de1)),
                ("level", W::UInt(0)),
                ("internalformat", e("GL_SRGB8_ALPHA8", 0x8c43)),
                ("width", W::UInt(2)),
                ("height", W::UInt(2)),
                ("border", W::UInt(0)),
                ("format", e("GL_RGBA", 0x1908)),
                ("type", e("GL_UNSIGNED_BYTE", 0x1401)),
                ("pixels", W::Null),
            ];
            w.call("glTexImage2D", &args, None, false);
            let fb = [("n", W::UInt(1)), ("framebuffers", W::Array(vec![W::UInt(3)]))];
            w.call("glGenFramebuffers", &fb, None, false);
            let bind = [("target", e("GL_FRAMEBUFFER", 0x8d40)), ("framebuffer", W::UInt(3))];
            w.call("glBindFramebuffer", &bind, None, false);
            let attach = [
                ("target", e("GL_FRAMEBUFFER", 0x8d40)),
                ("attachment", e("GL_COLOR_ATTACHMENT0", 0x8ce0)),
                ("textarget", e("GL_TEXTURE_2D", 0x0de1)),
                ("texture", W::UInt(5)),
                ("level", W::UInt(0)),
            ];
            w.call("glFramebufferTexture2D", &attach, None, false);
        }
        let call = w.call("glClear", &[("mask", W::UInt(0x4000))], None, false);
        swap(&mut w);
        (w, call)
    };
    let (w, _) = capture(false);
    replay(&w).0.unwrap();
    let (w, call) = capture(true);
    let error = replay(&w).0.err().expect("an sRGB attachment with sRGB writes off");
    assert_eq!(error.call(), Some(call), "{error}");
    assert!(error.to_string().contains("GL_FRAMEBUFFER_SRGB_EXT"), "{error}");
}
