//! Replaying real captures: an apitrace capture of an OpenGL ES 2.0 / 3.0 / EGL application, read
//! by `tiler-apitrace`, drives a [`Context`] with [`Call`](crate::Call)s, so a real
//! application's frames get the same inferred passes, costs and findings as a JSON trace.
//!
//! ```no_run
//! use tiler_gl::capture::{replay_file, ReplayOptions};
//!
//! let replay = replay_file("glmark2-texture.trace", &ReplayOptions::default(), &mut |frame| {
//!     println!("frame {} presented at call {}", frame.index, frame.call);
//!     Ok(())
//! })
//! .unwrap();
//! print!("{}", tiler_gl::text_report(&replay.report));
//! ```
//!
//! # How GL maps onto the context
//!
//! The translation (`translate.rs`) keeps the GL state the context does not: bindings (array
//! buffer, active texture unit, renderbuffer, framebuffers), shader sources and attachments,
//! uniform locations, texture parameters, pixel-store alignment.
//!
//! - **Names.** Each EGL context is a *generation*; its GL names are mapped to fresh context
//!   ids, so a capture that destroys and recreates its context (every glmark2 scene does) can
//!   reuse names. Destroying a context deletes its framebuffers, vertex arrays and queries
//!   (each context's own, as in GL) and, with the last context of its share group, the
//!   group's buffers, textures, renderbuffers and programs. The window surface outlives
//!   contexts, as in EGL. A context created with a share context joins its share group, whose
//!   objects all its contexts see. Each context keeps its own GL state: a live context that
//!   has changed state keeps it in a context of the replay's context of its own
//!   (`create_context`, `make_current`), and a context that changed none, or is gone, gives
//!   its state up to the next one made current (reset to the defaults). Contexts may be
//!   current with the window or with no surface.
//! - **Objects** are created in the context when GL gives them storage (`glBufferData`,
//!   `glTexImage2D`, `glRenderbufferStorage`); bindings of names without storage are applied
//!   when the storage arrives.
//! - **Programs.** `glShaderSource` per shader, `glAttachShader`, `glBindAttribLocation`
//!   before link; `glLinkProgram` creates the program from its GLSL with those bindings. Every
//!   `glGetAttribLocation` return value ≥ 0 is bound too (the capture's indices are the ones the
//!   application then uses). Uniform locations are mapped back to the names
//!   `glGetUniformLocation` returned them for; `glUniform*v` with a count sets consecutive
//!   array elements (`base[i + k]`). A location never returned is an error naming the call.
//! - **GL ES 3.0 vertex state**: vertex array objects (`glGenVertexArrays`, and the
//!   `OES_vertex_array_object` names) become the context's, each keeping its attributes and
//!   element buffer; `glVertexAttribDivisor` (and its `ANGLE`/`EXT` names) and
//!   `glDraw*Instanced` become the context's divisors and instanced draws. Uniform block
//!   indices are mapped back to the names `glGetUniformBlockIndex` returned them for, as
//!   uniform locations are; `glBindBufferBase`/`Range(GL_UNIFORM_BUFFER)` become the
//!   context's uniform buffer bindings (a buffer bound before it has storage is bound when it
//!   gets some). Sampler objects are kept here and hand the context each unit's sampling
//!   state; `glCopyBufferSubData` is the context's buffer copy; `glTexStorage2D` takes 1 level
//!   or the whole chain, whose levels `glTexSubImage2D` fills whole; `glDrawBuffers` of
//!   colour attachments 0, 1, … in order is the context's `draw_buffers` (multiple render
//!   targets). `GL_PRIMITIVE_RESTART_FIXED_INDEX` is the context's capability of that name.
//! - **Client-side vertex arrays** (apitrace records the bytes a draw reads in a fake
//!   `glVertexAttribPointer` just before it) become client arrays the context copies at each
//!   draw, as a driver must; client-side indices go through a scratch index buffer. Writes
//!   through mapped buffers become `buffer_sub_data`.
//! - **Textures**: `RGBA`, `RGB`, `LUMINANCE`, `LUMINANCE_ALPHA`, `ALPHA` bytes and the 4444 /
//!   5551 packings are expanded to RGBA8 (what sampling returns is the same); 565 is kept as
//!   565; `DEPTH_COMPONENT` is a depth texture without data. GL ES 3.0's sized internal
//!   formats of those bases are taken too; `RED`/`RG` bytes, halves and floats (`R8`, `RG8`,
//!   `R16F`, …) are stored with green/blue 0 and alpha 1, as GL reads them, and are never
//!   render targets. `EXT_texture_norm16`'s `R16`, `RG16`, `RGB16`, `RGBA16` are encoded
//!   formats, sampled at 16 bits a channel (without a mip chain). Rows honour
//!   `GL_UNPACK_ALIGNMENT`, `GL_UNPACK_ROW_LENGTH`, `GL_UNPACK_SKIP_ROWS` and
//!   `GL_UNPACK_SKIP_PIXELS`; with a buffer bound to `GL_PIXEL_UNPACK_BUFFER` an upload reads
//!   its texels from that buffer at the pointer's offset.
//!   Level 0 only; `glGenerateMipmap` gives the context's mip chain, and the `*_MIPMAP_*`
//!   minification filters use it (with a magnification filter of the same first word; a mipmap
//!   filter on a texture without levels — incomplete in GL — is refused where it is drawn).
//! - **GL ES 3.0 textures and targets**: integer formats (`R8UI` … `RGBA32I`, uploaded with
//!   `*_INTEGER` formats, rendered to through `uvec4`/`ivec4` outputs, cleared by
//!   `glClearBuffer{ui,i}v`, read by `glReadPixels(GL_RGBA_INTEGER)`),
//!   `glVertexAttribIPointer`, 2-D array and 3-D textures (`glTexImage3D`, `glTexStorage3D`,
//!   `glTexSubImage3D`, `WRAP_R`), rendering and copying into their layers
//!   (`glFramebufferTextureLayer`, `glCopyTexSubImage3D`: the context's
//!   `framebuffer_texture_layer`, `copy_tex_sub_image_layer`), and the packed and float formats
//!   `docs/captures.md` lists. `glReadBuffer` takes `GL_NONE` (a colour read after it is refused
//!   as the GL error it is) and the default.
//! - **Transform feedback** (`translate/feedback.rs`): `glTransformFeedbackVaryings` is applied
//!   at link; `glBindBufferBase`/`Range(GL_TRANSFORM_FEEDBACK_BUFFER)`, begin/end/pause/resume
//!   and `GL_RASTERIZER_DISCARD` are the context's calls; transform feedback objects are kept
//!   here, each handing the context its buffer bindings when bound.
//! - **Queries and fences**: occlusion queries are the context's; `EXT_disjoint_timer_query`'s
//!   timer queries (`GL_TIME_ELAPSED_EXT`, `glQueryCounterEXT`) change nothing drawn, and
//!   reading one's result waits as `glFinish` does. `glFenceSync` / `glClientWaitSync` are the
//!   context's fences: a wait stalls only while the fence's frame is in flight (applications
//!   pace their frames by waiting on a fence frames old); a zero timeout polls (and flushes
//!   with `GL_SYNC_FLUSH_COMMANDS_BIT`).
//! - **The window**: its size is the size of the first `glViewport` (apitrace records the
//!   surface's size as a fake viewport when a context is first made current), grown to any
//!   later viewport or scissor on the window that reaches past it (apitrace's retrace does the
//!   same: an application whose window was resized says so only through them), unless
//!   [`ReplayOptions::window`] says; RGBA8 with packed depth-stencil. `eglSwapBuffers` is
//!   `swap_buffers`, and each presented picture is handed to the caller.
//!
//! A call that draws or changes state and that the context cannot express is an error naming
//! its call number and function; nothing is skipped silently. Calls on `tiler-apitrace`'s
//! ignore list change nothing, and so do hints (`glHint`), `glLineWidth` (lines are refused
//! where they are drawn), `GL_DITHER` (llvmpipe and tiler do not dither), and state that only
//! matters under a capability the replay refuses to enable (`glPolygonOffset`,
//! `glSampleCoverage`).

mod ahead;
mod encoded;
mod texels;
mod translate;

use std::io::{BufReader, Read};
use std::path::Path;

use tiler_apitrace::{Limits, TraceReader};

use crate::context::{Context, ContextConfig};
use crate::report::Report;

pub use translate::Translator;

/// How a capture is replayed.
#[derive(Clone, Debug)]
pub struct ReplayOptions {
    /// The context's configuration; its `width` and `height` are replaced by the window's.
    pub config: ContextConfig,
    /// The window's size; `None`: the size of the capture's first `glViewport`.
    pub window: Option<(u32, u32)>,
    /// Limits on what the capture reader holds in memory.
    pub limits: Limits,
    /// Record the context calls the capture became ([`Context::recorded_frames`] of the
    /// replay's context): a JSON trace of the same frames, which `--what-if` edits.
    pub record: bool,
    /// Call numbers after which the window's picture is also handed to `on_frame` (as a
    /// [`PresentedFrame`] with `snapshot` set): a look at a capture that never swaps, or at
    /// the middle of a frame. A snapshot renders the window's open pass as a `glReadPixels`
    /// of it would (so the report counts that pass's store, and the load after it).
    pub snapshots: Vec<u64>,
    /// Hand each presented frame to `on_frame`; `false` skips reading the window's picture
    /// at every swap (a caller that writes no frames saves a read-back a frame).
    pub presented_frames: bool,
}

impl Default for ReplayOptions {
    fn default() -> ReplayOptions {
        ReplayOptions {
            config: ContextConfig::new(1, 1),
            window: None,
            limits: Limits::default(),
            record: false,
            snapshots: Vec::new(),
            presented_frames: true,
        }
    }
}

/// One presented frame: the window's picture at an `eglSwapBuffers`, or after a call of
/// [`ReplayOptions::snapshots`].
#[derive(Clone, Debug)]
pub struct PresentedFrame<'a> {
    /// Frames presented before this one.
    pub index: u32,
    /// The `eglSwapBuffers` call's number in the capture (the snapshot's call).
    pub call: u64,
    /// A snapshot asked for by [`ReplayOptions::snapshots`], not a swap.
    pub snapshot: bool,
    pub width: u32,
    pub height: u32,
    /// RGBA8, rows top to bottom (the first row is the top of the window).
    pub rgba: &'a [u8],
}

/// What a replay did.
pub struct Replay {
    pub report: Report,
    /// The context at the end, with the window's last picture.
    pub context: Context,
    /// Calls read from the capture.
    pub calls: u64,
    /// The `eglSwapBuffers` call numbers, one per presented frame.
    pub swaps: Vec<u64>,
}

/// A replay that failed: the capture could not be read, or one of its calls could not be
/// replayed.
#[derive(Debug, thiserror::Error)]
pub enum CaptureError {
    #[error("{path}: {source}")]
    Open { path: String, source: std::io::Error },
    // The inner error is in the message and so is not also the `source` (`#[from]` would make
    // it one, and a printer of the error chain, as `tiler`'s, would then say it twice).
    #[error("reading the capture: {0}")]
    Read(tiler_apitrace::ReadError),
    #[error("decoding the capture: {0}")]
    Decode(tiler_apitrace::gles::DecodeError),
    /// A call the replay cannot express, or one the context refused.
    #[error("call {call} `{function}`: {message}")]
    Call { call: u64, function: String, message: String },
    /// The caller's frame handler failed.
    #[error("frame {frame} (call {call}): {message}")]
    Frame { frame: u32, call: u64, message: String },
    /// The system has no thread to spare for reading the capture.
    #[error("cannot start the thread that reads the capture: {0}")]
    Thread(std::io::Error),
}

impl From<tiler_apitrace::ReadError> for CaptureError {
    fn from(e: tiler_apitrace::ReadError) -> CaptureError {
        CaptureError::Read(e)
    }
}

impl From<tiler_apitrace::gles::DecodeError> for CaptureError {
    fn from(e: tiler_apitrace::gles::DecodeError) -> CaptureError {
        CaptureError::Decode(e)
    }
}

impl CaptureError {
    /// The capture's call number the error is about, if it is about one.
    pub fn call(&self) -> Option<u64> {
        match self {
            CaptureError::Call { call, .. } | CaptureError::Frame { call, .. } => Some(*call),
            CaptureError::Decode(e) => Some(e.call),
            _ => None,
        }
    }
}

/// Whether `bytes` (a file's first bytes) start an apitrace capture: snappy's `at` or gzip's
/// magic.
pub fn is_capture(bytes: &[u8]) -> bool {
    bytes.starts_with(b"at") || bytes.starts_with(&[0x1f, 0x8b])
}

/// Replays the capture at `path`; `on_frame` sees each presented frame.
///
/// # Errors
/// See [`CaptureError`].
pub fn replay_file(
    path: impl AsRef<Path>,
    options: &ReplayOptions,
    on_frame: &mut dyn FnMut(&PresentedFrame) -> Result<(), String>,
) -> Result<Replay, CaptureError> {
    let path = path.as_ref();
    // A regular file only: a FIFO would block, a device would stream forever (the reader's
    // limits bound what is read from a regular file).
    let file = tiler_io::open_regular(path).map_err(|e| CaptureError::Open {
        path: path.display().to_string(),
        source: std::io::Error::other(e.message),
    })?;
    replay_reader(BufReader::new(file), options, on_frame)
}

/// Replays a capture read from `reader`; `on_frame` sees each presented frame.
///
/// The capture is read and decoded on a thread of its own (see [`ahead`]), so that reading
/// overlaps rendering; the calls are replayed in order and the first error, of reading or of
/// replaying, ends the replay as it would without it.
///
/// # Errors
/// See [`CaptureError`].
pub fn replay_reader<R: Read + Send>(
    reader: R,
    options: &ReplayOptions,
    on_frame: &mut dyn FnMut(&PresentedFrame) -> Result<(), String>,
) -> Result<Replay, CaptureError> {
    let reader = TraceReader::new(reader, options.limits)?;
    let budget = ahead::Budget::new(ahead::AHEAD_BYTES);
    std::thread::scope(|scope| {
        let (sender, receiver) = std::sync::mpsc::sync_channel(ahead::AHEAD_BATCHES);
        let budget = &budget;
        let spawned = std::thread::Builder::new()
            .name("tiler-capture-reader".to_string())
            .spawn_scoped(scope, move || ahead::read(reader, &sender, budget));
        match spawned {
            Ok(_) => {
                // A replay that stops early frees a reader waiting for room.
                let _close = ahead::CloseOnDrop(budget);
                replay_calls(ahead::Received::new(receiver, budget), options, on_frame)
            }
            Err(e) => Err(CaptureError::Thread(e)),
        }
    })
}

/// Replays decoded calls in order.
fn replay_calls(
    decoded: impl Iterator<Item = Result<ahead::Decoded, CaptureError>>,
    options: &ReplayOptions,
    on_frame: &mut dyn FnMut(&PresentedFrame) -> Result<(), String>,
) -> Result<Replay, CaptureError> {
    let mut translator = Translator::new(options.config.clone(), options.window, options.record);
    let mut calls = 0;
    for item in decoded {
        let (call, sig) = item?;
        let number = call.number;
        calls += 1;
        translator.apply(&call, &sig.name)?;
        if let Some((index, swap)) = translator.take_presented()
            && options.presented_frames
        {
            let ctx = translator.context().expect("a swap needs the context");
            let (width, height) = (ctx.config().width, ctx.config().height);
            let rgba = ctx.surface_rgba8();
            on_frame(&PresentedFrame { index, call: swap, snapshot: false, width, height, rgba: &rgba })
                .map_err(|message| CaptureError::Frame { frame: index, call: swap, message })?;
        }
        if options.snapshots.contains(&number) {
            let (index, width, height, rgba) = translator.snapshot().map_err(|message| CaptureError::Call {
                call: number,
                function: sig.name.to_string(),
                message: format!("snapshot of the bound framebuffer: {message}"),
            })?;
            on_frame(&PresentedFrame { index, call: number, snapshot: true, width, height, rgba: &rgba })
                .map_err(|message| CaptureError::Frame { frame: index, call: number, message })?;
        }
    }
    translator.finish(calls)
}
