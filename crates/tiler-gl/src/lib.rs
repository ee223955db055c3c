//! tiler-gl: an OpenGL ES-style deferred driver over tiler, JSON traces of its calls, and an
//! advisor that explains what the frames cost.
//!
//! OpenGL ES does not say where render passes begin and end; a tiler's driver infers them.
//! [`Context`] takes GL-style immediate-mode calls ([`Call`]) and gathers them as frame data
//! per framebuffer; nothing is rendered when a draw is called. It infers the render passes,
//! their load and store ops and their flushes exactly as `DESIGN.md`'s table says (see
//! `context::pass` for the rules and where each is implemented), renders them on a
//! [`tiler::Device`], and models the frames in flight behind the CPU (`context::frames`).
//! [`trace`] reads and writes sequences of frames of calls as JSON; [`capture`] replays apitrace
//! captures of real OpenGL ES 2.0 applications on the context; [`advisor`] turns a run's
//! [`Report`] into findings that cite the seed documents and name the bytes at stake.
//!
//! ```
//! use tiler_gl::{Call, Context, ContextConfig, ProgramKind, Bytes, ComponentType, Mode};
//!
//! let mut gl = Context::new(ContextConfig::new(64, 64)).unwrap();
//! let triangle: [[f32; 2]; 3] = [[-1.0, -1.0], [3.0, -1.0], [-1.0, 3.0]];
//! gl.call(Call::CreateBuffer { id: 1, data: Bytes::from_slice(&triangle) }).unwrap();
//! gl.call(Call::CreateProgram { id: 1, program: ProgramKind::Solid.into() }).unwrap();
//! gl.call(Call::UseProgram { id: 1 }).unwrap();
//! gl.call(Call::VertexAttribPointer {
//!     index: 0, buffer: 1, size: 2, component: ComponentType::Float, normalized: false, stride: 0, offset: 0,
//! }).unwrap();
//! gl.call(Call::EnableVertexAttrib { index: 0 }).unwrap();
//! gl.call(Call::Clear { color: true, depth: true, stencil: true }).unwrap();
//! gl.call(Call::DrawArrays { mode: Mode::Triangles, first: 0, count: 3 }).unwrap();
//! gl.call(Call::SwapBuffers).unwrap();
//! let report = gl.end().unwrap();
//! // One pass: colour and depth-stencil cleared; colour stored; depth and stencil not.
//! assert_eq!(report.frames[0].passes.len(), 1);
//! assert!(report.findings.is_empty());
//! ```
//!
//! # What is modelled, and what is not yet
//!
//! - Multisampling: renderbuffers and windows with samples, and multisampled render to texture
//!   (`framebuffer_texture` with `samples`, EXT_multisampled_render_to_texture) resolved in the
//!   tile; blits resolve multisampled sources.
//! - Depth and stencil: tiler packs them in one image, so separate depth and stencil images are
//!   `GL_FRAMEBUFFER_UNSUPPORTED`; `depth24` and `stencil8` are packed images with a padding
//!   half (see `context::targets`).
//! - Textures: the `textured` program samples RGBA8 textures with the core's sampler and
//!   texture cache (`texture_fetch` in the ledger), nearest or bilinear, with the mip chain of
//!   `generate_mipmap` under a `*_mipmap_*` filter;
//!   other formats (float, 565, depth) with a context-side sampler whose reads are not
//!   counted. Blits and copies count their source reads by formula (see `program`).
//! - Programs: five built-in programs written in Rust (`program`), or GLSL ES 1.00 programs
//!   compiled at run time by `tiler-glsl` (`"program": {"glsl": …}`; `context::glsl` says how
//!   attributes, uniforms and samplers meet the context's state). GLSL samplers read textures as
//!   `textured` does; a `discard` in the fragment shader turns early depth tests and HSR off for
//!   the draw, as on hardware.
//! - Explicit render passes: a trace (or program) may begin a pass with subpasses and their
//!   dependencies (`begin_pass`, `next_subpass`, `end_pass`; `context::explicit`), mapped to
//!   [`tiler::RenderPass::with_subpasses`], with transient textures and renderbuffers (no
//!   memory) and the `composite` program reading input attachment 0. Load and store ops are
//!   still inferred; everything else keeps inferring single-subpass passes.
//! - Costs are a tiler's: with the immediate-mode backend the passes and images are the same,
//!   the ledger is immediate mode's, and the advisor's costs describe what a tiler would pay.
//!
//! # Coordinates
//!
//! Every rectangle the API takes (viewport, scissor, tiled-rendering region, `read_pixels`,
//! blits, texture uploads) is in GL window coordinates: origin at the bottom-left, y up.
//! tiler's framebuffers have row 0 at the top, so the context flips y once, where the call
//! enters: GL row `y` is tiler row `height − 1 − y`. Programs convert GL clip space to tiler's
//! (`y` negated, depth `[−w, w]` → `[0, w]`), so a picture comes out upright in tiler's images
//! (and PNGs); texture data, given bottom row first as in GL, is stored flipped too, so render
//! to texture and uploaded textures sample alike. `read_pixels` returns rows bottom first, as
//! GL does; [`Context::surface_rgba8`] returns tiler's top-first rows. Front faces are GL's
//! (counter-clockwise as seen on screen), which is tiler's counter-clockwise too, the picture
//! being upright in both.

pub mod advisor;
pub mod bytes;
pub mod call;
pub mod capture;
pub mod context;
pub mod program;
pub mod report;
pub mod text;
pub mod trace;

pub use advisor::{Finding, RuleId, Severity};
pub use bytes::Bytes;
pub use call::{
    AttachmentPoint, BufferSet, Call, Capability, ClearColorValue, ComponentType, CubeFace, DependencySpec,
    EncodedFormat, Face, Filter, FramebufferTarget, GlslSource, IndexKind, LayeredTarget, Mode, Output, ProgramKind,
    ProgramSource, SubpassSpec, SwapBehavior, TextureFormat, UniformValue, Winding, Wrap,
};
pub use context::{Context, ContextConfig, Error, SavedState};
pub use report::{CallRef, FrameRecord, PassRecord, Report, Slot};
pub use text::{pass_began, pass_ended, text_report};
pub use trace::{Limits, Trace, TraceError};
