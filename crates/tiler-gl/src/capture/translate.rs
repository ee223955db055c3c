//! GL ES 2.0 calls of a capture → [`Call`]s of a [`Context`]; see the module docs of
//! [`crate::capture`] for the rules.

mod cube;
mod feedback;
mod layered;

use std::borrow::Cow;
use std::collections::{HashMap, HashSet};

use tiler::{BlendFactor, BlendOp, CompareOp, StencilOp};
use tiler_apitrace::GlesCall;
use tiler_apitrace::gles::{Command, EglHandle, GlEnum, Memory, Params, UniformValue as GlUniform};

use super::encoded;
use super::texels::{self, Upload};
use super::{CaptureError, Replay};
use crate::bytes::Bytes;
use crate::call::{
    AttachmentPoint, BufferSet, Call, Capability, ClearColorValue, ComponentType, EncodedFormat, Face, Filter,
    FramebufferTarget, IndexKind, Mode, SwapBehavior, TextureFormat, Winding, Wrap,
};
use crate::context::{Context, ContextConfig, MAX_TEXTURE_UNITS, MAX_VERTEX_ATTRIBS};

type Fallible<T = ()> = Result<T, String>;

mod gles3;

const GL_NEAREST: u32 = 0x2600;
const GL_LINEAR: u32 = 0x2601;
const GL_NEAREST_MIPMAP_LINEAR: u32 = 0x2702;
const GL_REPEAT: u32 = 0x2901;
const GL_CLAMP_TO_EDGE: u32 = 0x812f;
const GL_MIRRORED_REPEAT: u32 = 0x8370;
const GL_TEXTURE_2D: u32 = 0x0de1;
const GL_ARRAY_BUFFER: u32 = 0x8892;
const GL_ELEMENT_ARRAY_BUFFER: u32 = 0x8893;
const GL_FRAMEBUFFER: u32 = 0x8d40;
const GL_READ_FRAMEBUFFER: u32 = 0x8ca8;
const GL_DRAW_FRAMEBUFFER: u32 = 0x8ca9;
const GL_VERTEX_SHADER: u32 = 0x8b31;
const GL_FRAGMENT_SHADER: u32 = 0x8b30;
const GL_FRONT_AND_BACK: u32 = 0x0408;
const GL_TEXTURE0: u32 = 0x84c0;

/// A texture's GL state.
#[derive(Clone, Debug)]
struct Texture {
    /// The context's texture, once the texture has storage.
    id: Option<u32>,
    upload: Option<Upload>,
    size: (u32, u32),
    min: u32,
    mag: u32,
    wrap: [u32; 2],
    /// Bound to `GL_TEXTURE_CUBE_MAP` (its target from then on).
    cube: bool,
    /// Bound to `GL_TEXTURE_2D_ARRAY` or `GL_TEXTURE_3D` (its target from then on).
    layered: Option<crate::call::LayeredTarget>,
    /// `GL_TEXTURE_WRAP_R` (default `GL_REPEAT`).
    wrap_r: u32,
    /// Its GL format has no alpha (`glCopyTexImage2D` with `GL_RGB`): copies into it get
    /// alpha 1.
    opaque: bool,
    /// Its GL format has only red (and green) channels (`R8`, `RG8`, `GL_RED`, `GL_RG`): it
    /// is stored as RGBA8 with green, blue and alpha as GL reads them (0, 0, 1), which holds
    /// for uploads; rendering or copying into it would write them, so that is refused.
    red_green: bool,
    /// `GL_TEXTURE_MAX_LEVEL` (GL's default 1000). At 0 a texture is complete with level 0
    /// alone and a mipmap minification filter samples level 0 only, so it is sampled with its
    /// first word (`LINEAR_MIPMAP_*` as `LINEAR`); a level between 0 and the chain's last is
    /// refused where it is sampled.
    max_level: u32,
    /// `GL_TEXTURE_COMPARE_MODE` is `GL_COMPARE_REF_TO_TEXTURE`.
    compare_mode: bool,
    /// `GL_TEXTURE_COMPARE_FUNC` (default `GL_LEQUAL`).
    compare_func: u32,
    /// The compare mode or function was set: the context is told (`tex_compare`).
    compare_set: bool,
    /// `GL_TEXTURE_SWIZZLE_R/G/B/A` (GL ES 3.0 §3.8.14): what each sampled channel reads, as
    /// [`Swizzle`] sources. Applied to the texels as they are uploaded, which samples the same
    /// (filtering is per channel); so it may not change once the texture has storage, and
    /// rendering or copying into a swizzled texture is refused (see [`Translator::swizzled`]).
    swizzle: [u8; 4],
}

/// [`Texture::swizzle`]: channels 0–3 (red to alpha), then the constants 0 and 1.
const SWIZZLE_IDENTITY: [u8; 4] = [0, 1, 2, 3];
const SWIZZLE_ZERO: u8 = 4;
const SWIZZLE_ONE: u8 = 5;

/// A `GL_TEXTURE_SWIZZLE_*` value as a [`Texture::swizzle`] source.
fn swizzle_source(value: f64) -> Option<u8> {
    Some(match value as u32 {
        0x1903 => 0, // GL_RED
        0x1904 => 1, // GL_GREEN
        0x1905 => 2, // GL_BLUE
        0x1906 => 3, // GL_ALPHA
        0 => SWIZZLE_ZERO,
        1 => SWIZZLE_ONE,
        _ => return None,
    })
    .filter(|_| value.fract() == 0.0)
}

/// Whether a texture of this internal format has only red (and green) channels.
fn red_green_format(internal_format: u32) -> bool {
    matches!(internal_format, texels::GL_RED | texels::GL_RG | 0x8229 | 0x822b | 0x822d | 0x822f | 0x8230)
}

impl Default for Texture {
    fn default() -> Texture {
        Texture {
            id: None,
            upload: None,
            size: (0, 0),
            min: GL_NEAREST_MIPMAP_LINEAR,
            mag: GL_LINEAR,
            wrap: [GL_REPEAT; 2],
            cube: false,
            layered: None,
            wrap_r: GL_REPEAT,
            opaque: false,
            red_green: false,
            max_level: 1000,
            compare_mode: false,
            compare_func: GL_LEQUAL,
            compare_set: false,
            swizzle: SWIZZLE_IDENTITY,
        }
    }
}

/// A texture's sampling state as the context takes it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct SamplerParameters {
    min: Filter,
    mag: Filter,
    wrap_s: Wrap,
    wrap_t: Wrap,
    compare: Option<tiler::CompareOp>,
}

impl Texture {
    /// The context's sampling state, or why the GL state has none. A mipmap filter on a
    /// texture without levels is GL's incomplete texture, which the context samples as
    /// (0, 0, 0, 1).
    fn sampler(&self) -> Fallible<SamplerParameters> {
        let mag = match self.mag {
            GL_NEAREST => Filter::Nearest,
            GL_LINEAR => Filter::Linear,
            f => return Err(format!("magnification filter {f:#06x} is not a GL one")),
        };
        let chain = 32 - self.size.0.max(self.size.1).max(1).leading_zeros();
        let mipmapped = matches!(self.min, 0x2700..=0x2703);
        if mipmapped && self.max_level != 0 && self.max_level + 1 < chain {
            return Err(format!(
                "GL_TEXTURE_MAX_LEVEL {} of a {}-level chain: only 0 or the whole chain is supported",
                self.max_level, chain
            ));
        }
        let min = match self.min {
            GL_NEAREST => Filter::Nearest,
            GL_LINEAR => Filter::Linear,
            0x2700 | 0x2702 if self.max_level == 0 => Filter::Nearest,
            0x2701 | 0x2703 if self.max_level == 0 => Filter::Linear,
            0x2700 => Filter::NearestMipmapNearest,
            0x2701 => Filter::LinearMipmapNearest,
            GL_NEAREST_MIPMAP_LINEAR => Filter::NearestMipmapLinear,
            0x2703 => Filter::LinearMipmapLinear,
            f => return Err(format!("minification filter {f:#06x} is not a GL one")),
        };
        let wrap = |w: u32| match w {
            GL_REPEAT => Ok(Wrap::Repeat),
            GL_CLAMP_TO_EDGE => Ok(Wrap::ClampToEdge),
            GL_MIRRORED_REPEAT => Ok(Wrap::MirroredRepeat),
            w => Err(format!("wrap {w:#06x} is not a GLES wrap")),
        };
        let compare = match (self.compare_mode, self.compare_func) {
            (false, _) => None,
            (true, f) => Some(compare_func(f)?),
        };
        Ok(SamplerParameters { min, mag, wrap_s: wrap(self.wrap[0])?, wrap_t: wrap(self.wrap[1])?, compare })
    }

    /// A `GL_TEXTURE_COMPARE_MODE` / `GL_TEXTURE_COMPARE_FUNC` parameter (of a texture or a
    /// sampler object); `Ok(false)` for any other.
    fn compare_parameter(&mut self, pname: u32, value: f64) -> Fallible<bool> {
        match (pname, value) {
            (GL_TEXTURE_COMPARE_MODE, 0.0) => self.compare_mode = false,
            (GL_TEXTURE_COMPARE_MODE, v) if v == f64::from(GL_COMPARE_REF_TO_TEXTURE) => self.compare_mode = true,
            (GL_TEXTURE_COMPARE_MODE, v) => return Err(format!("GL_TEXTURE_COMPARE_MODE {v} is not a GL one")),
            (GL_TEXTURE_COMPARE_FUNC, v) => {
                compare_func(v as u32)?;
                self.compare_func = v as u32;
            }
            _ => return Ok(false),
        }
        self.compare_set = true;
        Ok(true)
    }
}

const GL_LEQUAL: u32 = 0x0203;
const GL_TEXTURE_COMPARE_MODE: u32 = 0x884c;
const GL_TEXTURE_COMPARE_FUNC: u32 = 0x884d;
const GL_COMPARE_REF_TO_TEXTURE: u32 = 0x884e;

/// A GL comparison function (`GL_NEVER` … `GL_ALWAYS`, 0x0200 to 0x0207).
fn compare_func(f: u32) -> Fallible<tiler::CompareOp> {
    use tiler::CompareOp as C;
    Ok(match f {
        0x0200 => C::Never,
        0x0201 => C::Less,
        0x0202 => C::Equal,
        GL_LEQUAL => C::LessOrEqual,
        0x0204 => C::Greater,
        0x0205 => C::NotEqual,
        0x0206 => C::GreaterOrEqual,
        0x0207 => C::Always,
        f => return Err(format!("comparison function {f:#06x} is not a GL one")),
    })
}

#[derive(Clone, Debug, Default)]
struct Program {
    shaders: Vec<u32>,
    /// `glBindAttribLocation` calls made so far (they take effect at link).
    bindings: Vec<(u32, String)>,
    /// The context's program from the last successful link.
    id: Option<u32>,
    /// Uniform location → name, from `glGetUniformLocation`'s return values.
    uniforms: HashMap<i32, String>,
    /// Uniform block index → name, from `glGetUniformBlockIndex`'s return values.
    blocks: HashMap<u32, String>,
    /// `glDeleteProgram` while in use: it goes when another program is used.
    deleted: bool,
    /// `glTransformFeedbackVaryings`: the outputs captured and whether separately (applied at
    /// link).
    feedback: Option<(Vec<String>, bool)>,
}

/// The objects of one EGL context (GL names → the context's ids).
#[derive(Debug, Default)]
struct Objects {
    buffers: HashMap<u32, Option<u32>>,
    textures: HashMap<u32, Texture>,
    renderbuffers: HashMap<u32, Option<u32>>,
    shaders: HashMap<u32, (GlEnum, Option<String>)>,
    /// Shaders `glDeleteShader` deleted while attached: they go when detached from every program.
    deleted_shaders: Vec<u32>,
    programs: HashMap<u32, Program>,
    /// Sampler objects: their sampling parameters (a texture's, unused fields aside).
    samplers: HashMap<u32, Texture>,
}

/// The objects GL keeps per context, not per share group (OpenGL ES 3.0 appendix D):
/// framebuffers, vertex arrays and queries, by GL name → the context's ids.
#[derive(Default)]
pub(super) struct ContextObjects {
    framebuffers: HashMap<u32, u32>,
    queries: HashMap<u32, u32>,
    /// Queries last begun as `GL_TIME_ELAPSED_EXT` timers (`EXT_disjoint_timer_query`).
    timer_queries: HashSet<u32>,
    pub(super) vertex_arrays: HashMap<u32, u32>,
}

impl Objects {
    /// Forgets a deleted program, and the deleted shaders only it had attached.
    fn remove_program(&mut self, program: u32) {
        self.programs.remove(&program);
        self.collect_shaders();
    }

    /// Forgets the deleted shaders no program has attached (GL ES 2.0 §2.10.3).
    fn collect_shaders(&mut self) {
        let (programs, shaders) = (&self.programs, &mut self.shaders);
        self.deleted_shaders.retain(|shader| {
            let attached = programs.values().any(|p| p.shaders.contains(shader));
            if !attached {
                shaders.remove(shader);
            }
            attached
        });
    }
}

/// GL state the context does not keep (or keeps in its own ids).
#[derive(Debug)]
struct Bindings {
    active_unit: u32,
    textures: [u32; MAX_TEXTURE_UNITS as usize],
    /// Each unit's `GL_TEXTURE_CUBE_MAP` binding.
    cube_textures: [u32; MAX_TEXTURE_UNITS as usize],
    /// Each unit's `GL_TEXTURE_2D_ARRAY` and `GL_TEXTURE_3D` bindings (`LayeredTarget::index`).
    layered_textures: [[u32; 2]; MAX_TEXTURE_UNITS as usize],
    array_buffer: u32,
    element_buffer: u32,
    renderbuffer: u32,
    draw_framebuffer: u32,
    read_framebuffer: u32,
    program: u32,
    unpack_alignment: u32,
    /// `GL_UNPACK_ROW_LENGTH`, `GL_UNPACK_SKIP_ROWS`, `GL_UNPACK_SKIP_PIXELS` (GL ES 3.0
    /// §3.7.1, `EXT_unpack_subimage`): a sub-rectangle of a larger client image.
    unpack_row_length: u32,
    unpack_skip_rows: u32,
    unpack_skip_pixels: u32,
    enabled_attribs: [bool; MAX_VERTEX_ATTRIBS as usize],
    /// Attributes pointing at client memory whose bytes the capture has not (yet) recorded.
    unrecorded_client_attribs: [bool; MAX_VERTEX_ATTRIBS as usize],
    /// `glVertexAttribDivisor`s.
    divisors: [u32; MAX_VERTEX_ATTRIBS as usize],
    /// The bound vertex array object; `element_buffer` and the attribute arrays above are its
    /// state, the other arrays' is kept here (`gles3.rs`).
    vertex_array: u32,
    unbound_vertex_arrays: HashMap<u32, gles3::VertexArrayState>,
    /// The GL ES 3.0 buffer targets that only name a buffer for other calls
    /// (`GL_UNIFORM_BUFFER`, `GL_COPY_READ_BUFFER`, `GL_COPY_WRITE_BUFFER`).
    other_buffers: HashMap<GlEnum, u32>,
    /// Uniform buffer bindings: index → (buffer name, offset, size), kept so that a buffer
    /// bound before it has storage is bound in the context when the storage arrives.
    uniform_bindings: HashMap<u32, (u32, u64, Option<u64>)>,
    /// The sampler object bound to each texture unit.
    samplers: [u32; MAX_TEXTURE_UNITS as usize],
    /// Transform feedback objects and their buffer bindings (`feedback.rs`).
    feedback: feedback::FeedbackBindings,
    /// Framebuffers (by GL name) whose read buffer `glReadBuffer` set to `GL_NONE`.
    read_none: std::collections::HashSet<u32>,
    /// `glDisable(GL_FRAMEBUFFER_SRGB_EXT)` (EXT_sRGB_write_control): draws into sRGB
    /// attachments would not encode. Harmless until such a draw, which is refused.
    srgb_write_off: bool,
}

impl Default for Bindings {
    fn default() -> Bindings {
        Bindings {
            active_unit: 0,
            textures: [0; MAX_TEXTURE_UNITS as usize],
            cube_textures: [0; MAX_TEXTURE_UNITS as usize],
            layered_textures: [[0; 2]; MAX_TEXTURE_UNITS as usize],
            array_buffer: 0,
            element_buffer: 0,
            renderbuffer: 0,
            draw_framebuffer: 0,
            read_framebuffer: 0,
            program: 0,
            unpack_alignment: 4,
            unpack_row_length: 0,
            unpack_skip_rows: 0,
            unpack_skip_pixels: 0,
            enabled_attribs: [false; MAX_VERTEX_ATTRIBS as usize],
            unrecorded_client_attribs: [false; MAX_VERTEX_ATTRIBS as usize],
            divisors: [0; MAX_VERTEX_ATTRIBS as usize],
            vertex_array: 0,
            unbound_vertex_arrays: HashMap::new(),
            other_buffers: HashMap::new(),
            uniform_bindings: HashMap::new(),
            samplers: [0; MAX_TEXTURE_UNITS as usize],
            feedback: feedback::FeedbackBindings::default(),
            read_none: std::collections::HashSet::new(),
            srgb_write_off: false,
        }
    }
}

/// Replays decoded calls on a [`Context`], keeping the GL state it does not.
pub struct Translator {
    config: ContextConfig,
    /// The context records the calls it is given (`ReplayOptions::record`).
    record: bool,
    window: Option<(u32, u32)>,
    /// Whether the window grows to a viewport or scissor reaching past it while the window is
    /// bound for drawing, as apitrace's retrace resizes its window (not when the caller gave
    /// the size, nor for a pbuffer surface).
    window_grows: bool,
    ctx: Option<Context>,
    /// EGL context handle → generation.
    generations: HashMap<EglHandle, u32>,
    /// Generation → its share group (the generation of the context created without a share
    /// context that it shares objects with, itself for that one): `objects` is by group.
    groups: HashMap<u32, u32>,
    /// Generations that have changed GL state while current (see `make_current`); apitrace's
    /// fake calls (the window's viewport at a context's first `eglMakeCurrent`) do not count.
    touched: HashSet<u32>,
    /// An `eglMakeCurrent` (its call number, draw surface and context) away from a live
    /// context that has changed state, not made yet: it is made (and refused) at the first
    /// call that is not a query, and dropped if another `eglMakeCurrent` comes first — GTK 4
    /// makes its share context current and at once the drawing one again, calling nothing
    /// between.
    pending_switch: Option<(u64, EglHandle, EglHandle)>,
    /// The call being translated is one of apitrace's fake ones.
    fake: bool,
    /// Why framebuffer 0 is not the window for the current context: it was made current
    /// without a surface, or on a pbuffer beside the window.
    not_window: Option<&'static str>,
    /// Pbuffer surfaces made beside the window (Qt makes a 1×1 one for its offscreen
    /// context): a context may be current on one as long as it does not draw to it.
    other_surfaces: HashSet<EglHandle>,
    /// `glFenceSync` handles → the context's fences.
    fences: HashMap<EglHandle, u32>,
    objects: HashMap<u32, Objects>,
    /// Generation → the objects that are its own.
    own: HashMap<u32, ContextObjects>,
    /// The current generation, if a context is current.
    current: Option<u32>,
    /// The generation whose GL state is the context's current one (`active_slot`'s), until
    /// another one is made current; `None` once it is destroyed.
    last_current: Option<u32>,
    /// Generation → the context's context ([`Call::MakeCurrent`]) holding its GL state. A
    /// context that has changed no state gives its slot up to the next one made current.
    slots: HashMap<u32, u32>,
    /// The context's current context.
    active_slot: u32,
    next_slot: u32,
    /// The bindings of the contexts' contexts that are not current, by slot.
    saved_bindings: HashMap<u32, Bindings>,
    next_generation: u32,
    window_surface: Option<EglHandle>,
    bindings: Bindings,
    next_id: u32,
    /// The scratch index buffer for client-side indices.
    scratch_indices: Option<u32>,
    presented: Option<(u32, u64)>,
    frames: u32,
    swaps: Vec<u64>,
    /// The call being translated, for errors.
    call: u64,
    function: String,
}

impl Translator {
    pub fn new(config: ContextConfig, window: Option<(u32, u32)>, record: bool) -> Translator {
        Translator {
            config,
            record,
            window,
            window_grows: window.is_none(),
            ctx: None,
            generations: HashMap::new(),
            groups: HashMap::new(),
            touched: HashSet::new(),
            pending_switch: None,
            fake: false,
            not_window: None,
            other_surfaces: HashSet::new(),
            fences: HashMap::new(),
            objects: HashMap::new(),
            own: HashMap::new(),
            current: None,
            last_current: None,
            slots: HashMap::new(),
            active_slot: 0,
            next_slot: 1,
            saved_bindings: HashMap::new(),
            next_generation: 1,
            window_surface: None,
            bindings: Bindings::default(),
            next_id: 1,
            scratch_indices: None,
            presented: None,
            frames: 0,
            swaps: Vec::new(),
            call: 0,
            function: String::new(),
        }
    }

    /// The context, once the window exists.
    pub fn context(&self) -> Option<&Context> {
        self.ctx.as_ref()
    }

    /// The frame presented by the last call applied, if it was a swap: (frame index, call).
    pub fn take_presented(&mut self) -> Option<(u32, u64)> {
        self.presented.take()
    }

    /// The picture of the framebuffer bound for drawing now (see [`Context::draw_snapshot`]):
    /// the frames presented before it, its width, height and RGBA8 rows.
    pub fn snapshot(&mut self) -> Result<(u32, u32, u32, Vec<u8>), String> {
        let frames = self.swaps.len() as u32;
        let ctx = self.ctx.as_mut().ok_or("the capture has made no context yet")?;
        let (width, height, rgba) = ctx.draw_snapshot()?;
        Ok((frames, width, height, rgba))
    }

    /// Renders what is pending and returns the run.
    pub fn finish(mut self, calls: u64) -> Result<Replay, CaptureError> {
        let mut ctx = match self.ctx.take() {
            Some(ctx) => ctx,
            None => self.new_context(1, 1).map_err(|message| self.error(message))?,
        };
        self.function = "end of capture".into();
        let report = ctx.end().map_err(|e| self.error(e.message))?;
        Ok(Replay { report, context: ctx, calls, swaps: self.swaps })
    }

    fn error(&self, message: String) -> CaptureError {
        CaptureError::Call { call: self.call, function: self.function.clone(), message }
    }

    fn new_context(&self, width: u32, height: u32) -> Result<Context, String> {
        let config = self.window_config(width, height);
        if self.record { Context::new_recording(config) } else { Context::new(config) }
    }

    fn window_config(&self, width: u32, height: u32) -> ContextConfig {
        let (width, height) = self.window.unwrap_or((width, height));
        ContextConfig { width, height, ..self.config.clone() }
    }

    /// Applies one decoded call; `function` is its name in the capture.
    ///
    /// # Errors
    /// A call the context cannot express or refuses, naming the call.
    pub fn apply(&mut self, call: &GlesCall, function: &str) -> Result<(), CaptureError> {
        self.call = call.number;
        // Every context call this one becomes names it, those made outside `emit` too (a
        // context switch's).
        if let Some(ctx) = self.ctx.as_mut() {
            ctx.set_capture_call(call.number);
        }
        if self.function != function {
            self.function.clear();
            self.function.push_str(function);
        }
        self.fake = call.fake;
        self.command(&call.command, call.fake).map_err(|m| self.error(m))
    }

    fn ctx(&mut self) -> Fallible<&mut Context> {
        if self.ctx.is_none() {
            // Before any surface or viewport gave the window's size (a compositor compiles its
            // shaders on a surfaceless context, then makes its pbuffer current), the window is
            // 1×1 until the size comes (`Translator::window_known`); a draw, clear, read or
            // swap of it before then is refused.
            let (w, h) = self.window.unwrap_or((1, 1));
            let mut ctx = self.new_context(w, h)?;
            // Made during a call: its calls name that one (`apply` names the later ones).
            ctx.set_capture_call(self.call);
            self.ctx = Some(ctx);
        }
        Ok(self.ctx.as_mut().expect("made above"))
    }

    /// The window's size, from a surface or the first viewport: kept if none was known yet,
    /// and given to a context made before it (with a 1×1 window, see [`Translator::ctx`]).
    fn window_known(&mut self, size: (u32, u32)) -> Fallible {
        if self.window.is_none() {
            self.window = Some(size);
            if self.ctx.is_some() {
                self.emit(Call::ResizeSurface { width: size.0, height: size.1 })?;
            }
        }
        Ok(())
    }

    pub(super) fn emit(&mut self, call: Call) -> Fallible<crate::call::Output> {
        // Making and linking programs changes objects of the share group, not the context's
        // own state: GTK 4 compiles every shader on its share context, then draws on another.
        let shared_only = matches!(
            call,
            Call::CreateProgram { .. } | Call::BindAttribLocation { .. } | Call::TransformFeedbackVaryings { .. }
        );
        if let Some(generation) = self.current.filter(|_| !self.fake && !shared_only) {
            self.touched.insert(generation);
        }
        self.ctx()?.call(call).map_err(|e| e.message)
    }

    pub(super) fn fresh_id(&mut self) -> u32 {
        let id = self.next_id;
        self.next_id += 1;
        id
    }

    fn objects(&mut self) -> Fallible<&mut Objects> {
        let generation = self.current.ok_or("no EGL context is current")?;
        let group = self.groups.get(&generation).copied().unwrap_or(generation);
        Ok(self.objects.entry(group).or_default())
    }

    /// The current context's own objects (framebuffers, vertex arrays, queries).
    pub(super) fn own(&mut self) -> Fallible<&mut ContextObjects> {
        let generation = self.current.ok_or("no EGL context is current")?;
        Ok(self.own.entry(generation).or_default())
    }

    fn command(&mut self, command: &Command, fake: bool) -> Fallible {
        match self.unpack_from_buffer(command)? {
            Some(command) => self.command_unpacked(&command, fake),
            None => self.command_unpacked(command, fake),
        }
    }

    /// [`Translator::command`] once uploads from a pixel unpack buffer carry their bytes.
    fn command_unpacked(&mut self, command: &Command, fake: bool) -> Fallible {
        use Command as C;
        // A switch put off is made first: the checks below read the bindings of the context
        // that is current.
        if let Some((call, draw, context)) = self.pending_switch {
            match command {
                C::Ignored { .. } => return Ok(()),
                C::MakeCurrent { .. } => self.pending_switch = None,
                _ => {
                    self.pending_switch = None;
                    self.make_current(draw, context).map_err(|e| format!("{e} (made current at call {call})"))?;
                }
            }
        }
        let reads_colour = matches!(
            command,
            C::ReadPixels { .. }
                | C::BlitFramebuffer { .. }
                | C::CopyTexImage2D { .. }
                | C::CopyTexSubImage2D { .. }
                | C::CopyTexSubImage3D { .. }
        );
        if reads_colour && self.bindings.read_none.contains(&self.bindings.read_framebuffer) {
            return Err(format!(
                "reading colour from framebuffer {}, whose read buffer is GL_NONE (a GL error)",
                self.bindings.read_framebuffer
            ));
        }
        let writes_colour = matches!(
            command,
            C::DrawArrays { .. } | C::DrawElements { .. } | C::Clear { .. } | C::BlitFramebuffer { .. }
        );
        let uses_window = (writes_colour && self.bindings.draw_framebuffer == 0)
            || (reads_colour && self.bindings.read_framebuffer == 0)
            || matches!(command, C::SwapBuffers { .. });
        if uses_window && self.window.is_none() {
            return Err("the window's size is not known yet (no surface or glViewport before this call; give the \
                        replay a window size)"
                .into());
        }
        if let Some(why) = self.not_window
            && ((writes_colour && self.bindings.draw_framebuffer == 0)
                || (reads_colour && self.bindings.read_framebuffer == 0))
        {
            // Without a surface (EGL_KHR_surfaceless_context) framebuffer 0 is
            // GL_FRAMEBUFFER_UNDEFINED, so GL draws and reads nothing; on a pbuffer beside the
            // window it is the pbuffer. The replay would draw into the window.
            return Err(format!("drawing or reading framebuffer 0 while the context is current {why}"));
        }
        if writes_colour && self.bindings.srgb_write_off && self.ctx.as_ref().is_some_and(Context::draws_into_srgb) {
            return Err("drawing into an sRGB colour attachment with GL_FRAMEBUFFER_SRGB_EXT disabled \
                        (no sRGB encoding) is not supported"
                .into());
        }
        if self.cube_command(command)? || self.layered_command(command)? || self.feedback_command(command)? {
            return Ok(());
        }
        match command {
            C::Ignored { .. } => {}

            // ---- EGL ----------------------------------------------------------------------
            C::CreateContext { share_context, context, .. } => {
                let generation = self.next_generation;
                // A context sharing objects with another (EGL 1.5 §3.7.1) joins its share
                // group: textures, buffers, renderbuffers, shaders and programs are the
                // group's; framebuffers, vertex arrays and queries are its own (`own`).
                let group = match *share_context {
                    0 => generation,
                    share => {
                        let shared =
                            self.generations.get(&share).ok_or("shares objects with a context never created")?;
                        self.groups.get(shared).copied().unwrap_or(*shared)
                    }
                };
                self.next_generation += 1;
                self.generations.insert(*context, generation);
                self.groups.insert(generation, group);
            }
            C::MakeCurrent { draw, context, .. } => {
                if self.switches_away_from_live_state(*context) {
                    self.pending_switch = Some((self.call, *draw, *context));
                } else {
                    self.make_current(*draw, *context)?;
                }
            }
            C::DestroyContext { context, .. } => {
                let generation = self.generations.remove(context).ok_or("destroys a context never created")?;
                // The group's objects go with its last context.
                let group = self.groups.remove(&generation).unwrap_or(generation);
                let others = self.generations.values().any(|g| self.groups.get(g) == Some(&group));
                self.destroy_objects(generation, (!others).then_some(group))?;
                if self.current == Some(generation) {
                    self.current = None;
                }
            }
            C::CreateWindowSurface { surface, .. } => {
                if self.window_surface.is_some_and(|s| s != *surface) {
                    return Err("a second window surface is not supported".into());
                }
                self.window_surface = Some(*surface);
            }
            C::CreatePbufferSurface { surface, attribs, .. } => {
                // A program without a window (headless, `EGL_PLATFORM_SURFACELESS_MESA`) draws
                // into a pbuffer: it is the default framebuffer, sized by its attributes.
                if self.window_surface.is_some_and(|s| s != *surface) {
                    self.other_surfaces.insert(*surface);
                    return Ok(());
                }
                const EGL_HEIGHT: i64 = 0x3056;
                const EGL_WIDTH: i64 = 0x3057;
                let attrib = |name: i64| {
                    attribs.chunks_exact(2).find(|kv| kv[0] == name).map_or(Ok(0), |kv| {
                        u32::try_from(kv[1]).map_err(|_| format!("pbuffer attribute {name:#x} = {} is negative", kv[1]))
                    })
                };
                let (width, height) = (attrib(EGL_WIDTH)?, attrib(EGL_HEIGHT)?);
                if width == 0 || height == 0 {
                    return Err(format!("a pbuffer of {width}×{height} pixels has nothing to draw into"));
                }
                self.window_known((width, height))?;
                self.window_grows = false;
                self.window_surface = Some(*surface);
            }
            C::DestroySurface { surface, .. } => {
                self.other_surfaces.remove(surface);
            }
            C::SurfaceAttrib { attribute, value, .. } => {
                const EGL_SWAP_BEHAVIOR: i64 = 0x3093;
                let behavior = match (*attribute, *value) {
                    (EGL_SWAP_BEHAVIOR, 0x3094) => SwapBehavior::Preserved,
                    (EGL_SWAP_BEHAVIOR, 0x3095) => SwapBehavior::Destroyed,
                    _ => return Err(format!("surface attribute {attribute:#x} = {value:#x} is not supported")),
                };
                self.emit(Call::SwapBehavior { behavior })?;
            }
            C::SwapBuffers { surface, .. } => {
                if self.other_surfaces.contains(surface) {
                    return Err("swapping a pbuffer made beside the window is not supported".into());
                }
                self.emit(Call::SwapBuffers)?;
                self.presented = Some((self.frames, self.call));
                self.swaps.push(self.call);
                self.frames += 1;
            }

            // ---- buffers --------------------------------------------------------------------
            C::GenBuffers { names } => {
                let objects = self.objects()?;
                for &name in names {
                    objects.buffers.entry(name).or_insert(None);
                }
            }
            C::DeleteBuffers { names } => {
                for &name in names {
                    if let Some(Some(id)) = self.objects()?.buffers.remove(&name) {
                        self.emit(Call::DeleteBuffer { id })?;
                    }
                    let b = &mut self.bindings;
                    for bound in [&mut b.array_buffer, &mut b.element_buffer] {
                        if *bound == name {
                            *bound = 0;
                        }
                    }
                    gles3::forget_buffer(b, name);
                    b.feedback.forget_buffer(name);
                    b.other_buffers.retain(|_, bound| *bound != name);
                }
            }
            C::BindBuffer { target, buffer } => {
                if *buffer != 0 {
                    self.objects()?.buffers.entry(*buffer).or_insert(None);
                }
                match *target {
                    GL_ARRAY_BUFFER => self.bindings.array_buffer = *buffer,
                    GL_ELEMENT_ARRAY_BUFFER => {
                        self.bindings.element_buffer = *buffer;
                        let id = self.buffer_id(*buffer)?.unwrap_or(0);
                        self.emit(Call::BindIndexBuffer { buffer: id })?;
                    }
                    t if gles3::OTHER_BUFFER_TARGETS.contains(&t) => {
                        self.bindings.other_buffers.insert(t, *buffer);
                    }
                    t => return Err(format!("buffer target {t:#06x} is not supported")),
                }
            }
            C::BufferData { target, size, data, .. } => {
                let name = self.bound_buffer(*target)?;
                let bytes = match data {
                    Memory::Client(bytes) if bytes.len() as u64 == *size => Bytes::from(bytes.clone()),
                    Memory::Client(bytes) => {
                        return Err(format!("{} bytes recorded for a buffer of {size}", bytes.len()));
                    }
                    Memory::Null => {
                        let size = usize::try_from(*size).map_err(|_| format!("buffer size {size} is too large"))?;
                        if size as u64 > self.config.memory_limit {
                            return Err(format!("buffer size {size} is above the memory limit"));
                        }
                        Bytes::from(vec![0u8; size])
                    }
                    Memory::Offset(_) => return Err("the buffer's data was not recorded".into()),
                };
                match self.buffer_id(name)? {
                    Some(id) => {
                        self.emit(Call::BufferData { id, data: bytes })?;
                    }
                    None => {
                        let id = self.fresh_id();
                        self.emit(Call::CreateBuffer { id, data: bytes })?;
                        self.objects()?.buffers.insert(name, Some(id));
                        if self.bindings.element_buffer == name {
                            self.emit(Call::BindIndexBuffer { buffer: id })?;
                        }
                        self.bind_new_uniform_buffer(name, id)?;
                        self.bind_new_feedback_buffer(name, id)?;
                    }
                }
            }
            C::BufferSubData { target, offset, data, .. } => {
                let name = self.bound_buffer(*target)?;
                let bytes = data.bytes().ok_or("the data was not recorded")?;
                let id = self.buffer_id(name)?.ok_or_else(|| format!("buffer {name} has no storage"))?;
                self.emit(Call::BufferSubData { id, offset: *offset, data: Bytes::from(bytes) })?;
            }
            C::CopyBufferSubData { read_target, write_target, read_offset, write_offset, size } => {
                let (src, dst) = (self.bound_buffer(*read_target)?, self.bound_buffer(*write_target)?);
                let storage =
                    |t: &mut Self, name: u32| t.buffer_id(name)?.ok_or_else(|| format!("buffer {name} has no storage"));
                let (src, dst) = (storage(self, src)?, storage(self, dst)?);
                let (src_offset, dst_offset, size) = (*read_offset, *write_offset, *size);
                self.emit(Call::CopyBufferSubData { src, dst, src_offset, dst_offset, size })?;
            }
            C::MapBuffer { .. } | C::UnmapBuffer { .. } | C::FlushMappedBufferRange { .. } => {}
            C::BufferWrite { buffer, offset, data } => {
                let id = self.buffer_id(*buffer)?.ok_or_else(|| format!("buffer {buffer} has no storage"))?;
                self.emit(Call::BufferSubData { id, offset: *offset, data: Bytes::from(data.as_slice()) })?;
            }

            // ---- vertex input ---------------------------------------------------------------
            C::EnableVertexAttribArray { index } | C::DisableVertexAttribArray { index } => {
                let enable = matches!(command, C::EnableVertexAttribArray { .. });
                if !enable && (MAX_VERTEX_ATTRIBS..RECORDED_MAX_VERTEX_ATTRIBS).contains(index) {
                    // Apps disable every array up to the GL_MAX_VERTEX_ATTRIBS they were told
                    // (16 on llvmpipe and on most GPUs). An array the context does not have is
                    // never enabled (that is refused), so disabling it changes nothing.
                    return Ok(());
                }
                let slot = attrib_slot(*index)?;
                self.bindings.enabled_attribs[slot] = enable;
                let index = *index;
                self.emit(if enable {
                    Call::EnableVertexAttrib { index }
                } else {
                    Call::DisableVertexAttrib { index }
                })?;
            }
            C::VertexAttribPointer { index, size, kind, normalized, stride, pointer, integer } => {
                let slot = attrib_slot(*index)?;
                let component = component_type(*kind)?;
                let size = u32::try_from(*size).map_err(|_| format!("size {size} is negative"))?;
                let stride = u32::try_from(*stride).map_err(|_| format!("stride {stride} is negative"))?;
                let (index, normalized) = (*index, *normalized);
                self.bindings.unrecorded_client_attribs[slot] = false;
                if self.bindings.array_buffer != 0 {
                    let name = self.bindings.array_buffer;
                    let buffer = match self.buffer_id(name)? {
                        Some(id) => id,
                        None => {
                            // GL takes a pointer into a buffer whose storage comes later
                            // (glBufferData): an empty buffer now, its data when it comes.
                            let id = self.fresh_id();
                            self.emit(Call::CreateBuffer { id, data: Bytes::from(Vec::new()) })?;
                            self.objects()?.buffers.insert(name, Some(id));
                            id
                        }
                    };
                    let offset = match pointer {
                        Memory::Null => 0,
                        Memory::Offset(offset) => *offset,
                        Memory::Client(_) => return Err("a buffer offset was expected".into()),
                    };
                    self.emit(if *integer {
                        Call::VertexAttribIPointer { index, buffer, size, component, stride, offset }
                    } else {
                        Call::VertexAttribPointer { index, buffer, size, component, normalized, stride, offset }
                    })?;
                } else if let Memory::Client(bytes) = pointer {
                    let data = Bytes::from(bytes.as_slice());
                    self.emit(if *integer {
                        Call::VertexAttribIArray { index, size, component, stride, data }
                    } else {
                        Call::VertexAttribArray { index, size, component, normalized, stride, data }
                    })?;
                } else if fake {
                    return Err("a client-side array without its bytes".into());
                } else {
                    // The application's own call into client memory: apitrace records the
                    // bytes in a fake call before each draw that reads them.
                    self.bindings.unrecorded_client_attribs[slot] = true;
                }
            }
            C::VertexAttribDivisor { index, divisor } => self.vertex_attrib_divisor(*index, *divisor)?,
            C::GenVertexArrays { names } => self.gen_vertex_arrays(names)?,
            C::BindVertexArray { array } => self.bind_vertex_array(*array)?,
            C::DeleteVertexArrays { names } => self.delete_vertex_arrays(names)?,
            C::VertexAttrib { index, value } => {
                attrib_slot(*index)?;
                self.emit(Call::VertexAttrib { index: *index, value: *value })?;
            }

            // ---- drawing --------------------------------------------------------------------
            C::DrawArrays { mode, first, count, instance_count } => {
                let instances = self.check_draw(*instance_count)?;
                let mode = draw_mode(*mode)?;
                let first = u32::try_from(*first).map_err(|_| format!("first {first} is negative"))?;
                let count = u32::try_from(*count).map_err(|_| format!("count {count} is negative"))?;
                self.emit(match instances {
                    None => Call::DrawArrays { mode, first, count },
                    Some(instances) => Call::DrawArraysInstanced { mode, first, count, instances },
                })?;
            }
            C::DrawElements { mode, count, kind, indices, instance_count, base_vertex, .. } => {
                if *base_vertex != 0 {
                    return Err(format!("base vertex {base_vertex}: only 0 is supported"));
                }
                let instances = self.check_draw(*instance_count)?;
                let mode = draw_mode(*mode)?;
                let count = u32::try_from(*count).map_err(|_| format!("count {count} is negative"))?;
                self.draw_elements(mode, count, *kind, indices, instances)?;
            }
            C::Clear { mask } => {
                const KNOWN: u32 = 0x4000 | 0x0100 | 0x0400;
                if mask & !KNOWN != 0 {
                    return Err(format!("clear mask {mask:#x} has unknown bits"));
                }
                self.emit(Call::Clear {
                    color: mask & 0x4000 != 0,
                    depth: mask & 0x0100 != 0,
                    stencil: mask & 0x0400 != 0,
                })?;
            }
            C::Flush => {
                self.emit(Call::Flush)?;
            }
            C::Finish => {
                self.emit(Call::Finish)?;
            }
            C::FenceSync { sync } => {
                let id = self.fresh_id();
                self.emit(Call::FenceSync { id })?;
                self.fences.insert(*sync, id);
            }
            // A zero timeout polls: nothing waits (GL_SYNC_FLUSH_COMMANDS_BIT flushes).
            C::ClientWaitSync { flags, timeout: 0, .. } => {
                if flags & 1 != 0 {
                    self.emit(Call::Flush)?;
                }
            }
            C::ClientWaitSync { sync, .. } => match self.fences.get(sync) {
                Some(&id) => {
                    self.emit(Call::ClientWaitSync { id })?;
                }
                // A fence put before the capture began (a trimmed capture's): taken as the
                // last command, as glFinish.
                None => {
                    self.emit(Call::Finish)?;
                }
            },
            C::DeleteSync { sync } => {
                if let Some(id) = self.fences.remove(sync) {
                    self.emit(Call::DeleteSync { id })?;
                }
            }

            // ---- textures -------------------------------------------------------------------
            C::GenTextures { names } => {
                let objects = self.objects()?;
                for &name in names {
                    objects.textures.entry(name).or_default();
                }
            }
            C::DeleteTextures { names } => {
                for &name in names {
                    if let Some(Texture { id: Some(id), .. }) = self.objects()?.textures.remove(&name) {
                        self.emit(Call::DeleteTexture { id })?;
                    }
                    let layered = self.bindings.layered_textures.as_flattened_mut();
                    for bound in
                        self.bindings.textures.iter_mut().chain(&mut self.bindings.cube_textures).chain(layered)
                    {
                        if *bound == name {
                            *bound = 0;
                        }
                    }
                }
            }
            C::ActiveTexture { unit } => {
                // A unit beyond the context's may be made active: apps unbind every unit up to
                // the GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS they were told (192 on llvmpipe).
                // Binding texture 0 there changes nothing; anything else is refused
                // (`Translator::unit`).
                let unit = unit.wrapping_sub(GL_TEXTURE0);
                if unit >= RECORDED_MAX_TEXTURE_UNITS {
                    return Err(format!("texture unit {unit} is beyond GL's limit of {RECORDED_MAX_TEXTURE_UNITS}"));
                }
                self.bindings.active_unit = unit;
            }
            C::BindTexture { target, texture } => {
                if *target != GL_TEXTURE_2D {
                    return Err(format!("texture target {target:#06x} is not supported (2D only)"));
                }
                if *texture == 0 && self.bindings.active_unit >= MAX_TEXTURE_UNITS {
                    return Ok(());
                }
                let unit = self.unit()?;
                let id = if *texture == 0 {
                    0
                } else {
                    let t = self.objects()?.textures.entry(*texture).or_default();
                    if t.cube || t.layered.is_some() {
                        return Err(format!(
                            "texture {texture} is a cube map, 2-D array or 3-D texture: binding it as 2D is a GL error"
                        ));
                    }
                    t.id.unwrap_or(0)
                };
                self.bindings.textures[unit] = *texture;
                self.emit(Call::BindTexture { unit: unit as u32, texture: id })?;
            }
            // Desktop GL's proxy target asks whether a texture could be made, and makes none
            // (Qt's glyph cache asks so before its first atlas).
            C::TexImage2D { target: GL_PROXY_TEXTURE_2D, .. } => {}
            C::TexImage2D { target, level, internal_format, width, height, border, format, kind, pixels }
                if encoded::packed_format(*format, *kind).is_some() =>
            {
                check_2d_level0(*target, 0)?;
                // The unsized format, or GL ES 3.0's sized RGBA4, RGB5_A1, RGB10_A2,
                // R11F_G11F_B10F, RGB9_E5 of their packed types, or EXT_texture_norm16's R16,
                // RG16, RGB16, RGBA16 of theirs.
                let sized = matches!(
                    (*internal_format, *kind),
                    (0x8056, 0x8033) | (0x8057, 0x8034) | (0x8059, 0x8368) | (0x8c3a, 0x8c3b) | (0x8c3d, 0x8c3e)
                ) || matches!(
                    (*internal_format, *format),
                    (0x822a, texels::GL_RED)
                        | (0x822c, texels::GL_RG)
                        | (0x8054, texels::GL_RGB)
                        | (0x805b, texels::GL_RGBA)
                ) && *kind == texels::GL_UNSIGNED_SHORT;
                if *border != 0 || (internal_format != format && !sized) {
                    return Err(format!(
                        "border {border} must be 0, internal format {internal_format:#06x} the format"
                    ));
                }
                let level = u32::try_from(*level).map_err(|_| format!("mip level {level} is negative"))?;
                let packed = encoded::packed_format(*format, *kind).expect("matched");
                self.packed_tex_image(level, size2(*width, *height)?, packed, pixels)?;
            }
            C::TexSubImage2D { target, level, x_offset, y_offset, width, height, format, kind, pixels }
                if encoded::packed_format(*format, *kind).is_some() =>
            {
                check_2d_level0(*target, *level)?;
                let packed = encoded::packed_format(*format, *kind).expect("matched");
                let (offset, size) = (size2(*x_offset, *y_offset)?, size2(*width, *height)?);
                self.packed_tex_sub_image(offset, size, packed, pixels)?;
            }
            C::CompressedTexImage2D { target, level, internal_format, width, height, border, image_size, data } => {
                check_2d_level0(*target, 0)?;
                if *border != 0 {
                    return Err(format!("border {border} must be 0"));
                }
                self.compressed_tex_image(*level, *internal_format, size2(*width, *height)?, *image_size, data)?;
            }
            C::CompressedTexSubImage2D {
                target,
                level,
                x_offset,
                y_offset,
                width,
                height,
                format,
                image_size,
                data,
            } => {
                check_2d_level0(*target, *level)?;
                let (offset, size) = (size2(*x_offset, *y_offset)?, size2(*width, *height)?);
                self.compressed_tex_sub_image(offset, size, *format, *image_size, data)?;
            }
            C::TexImage2D { target, level, internal_format, width, height, border, format, kind, pixels }
                if *level > 0 =>
            {
                check_2d_level0(*target, 0)?;
                if *border != 0 {
                    return Err(format!("border {border} must be 0"));
                }
                let (width, height) = size2(*width, *height)?;
                let upload = Upload::new(*internal_format, *format, *kind)?;
                let name = self.bound_texture()?;
                let id = self
                    .texture_id(name)?
                    .ok_or_else(|| format!("mip level {level} of texture {name} before its level 0"))?;
                // No texels (NULL): the level's contents are undefined until drawn into or
                // generated (Qt allocates a layer's levels so); zeros here.
                let data = match self.texels(&upload, pixels, width, height)? {
                    Some(data) => self.swizzled(name, upload.format, data)?,
                    None => {
                        // Sized as level 0 allows (the context checks it; this bounds the zeros).
                        let (w0, h0) = self.ctx()?.texture_size(id).unwrap_or((0, 0));
                        if width > w0 || height > h0 {
                            return Err(format!(
                                "mip level {level} of texture {name} is {width}×{height}, larger than its level 0 \
                                 ({w0}×{h0})"
                            ));
                        }
                        Bytes::from(vec![0; width as usize * height as usize * 4])
                    }
                };
                self.emit(Call::TexImageLevel { id, level: *level as u32, width, height, data })?;
            }
            C::TexImage2D { target, level, internal_format, width, height, border, format, kind, pixels } => {
                check_2d_level0(*target, *level)?;
                if *border != 0 {
                    return Err(format!("border {border} must be 0"));
                }
                let (width, height) = size2(*width, *height)?;
                let upload = Upload::new(*internal_format, *format, *kind)?;
                let data = self.texels(&upload, pixels, width, height)?;
                let name = self.bound_texture()?;
                let data = data.map(|data| self.swizzled(name, upload.format, data)).transpose()?;
                let format = upload.format;
                let texture = self.objects()?.textures.entry(name).or_default().clone();
                let id = match texture.id {
                    Some(id) => {
                        self.emit(Call::TexImage { id, width, height, format, data })?;
                        id
                    }
                    None => {
                        let id = self.fresh_id();
                        self.emit(Call::CreateTexture { id, width, height, format, data, transient: false })?;
                        self.bind_new_texture(name, id)?;
                        id
                    }
                };
                let t = self.objects()?.textures.get_mut(&name).expect("inserted above");
                t.id = Some(id);
                t.upload = Some(upload);
                t.red_green = red_green_format(*internal_format);
                t.opaque = matches!(
                    *internal_format,
                    texels::GL_RGB
                        | texels::GL_LUMINANCE
                        | texels::GL_RED
                        | texels::GL_RG
                        | 0x8051
                        | 0x8d62
                        | 0x8229
                        | 0x822b
                );
                t.size = (width, height);
                self.update_sampler(name)?;
            }
            C::TexSubImage2D { target, level, x_offset, y_offset, width, height, format, kind, pixels }
                if *level > 0 =>
            {
                check_2d_level0(*target, 0)?;
                let (x, y) = size2(*x_offset, *y_offset)?;
                let (width, height) = size2(*width, *height)?;
                self.tex_sub_image_level(*level as u32, [x, y, width, height], *format, *kind, pixels)?;
            }
            C::TexSubImage2D { target, level, x_offset, y_offset, width, height, format, kind, pixels } => {
                check_2d_level0(*target, *level)?;
                let name = self.bound_texture()?;
                let texture = self.objects()?.textures.get(&name).cloned().unwrap_or_default();
                let (Some(id), Some(stored)) = (texture.id, texture.upload) else {
                    return Err(format!("texture {name} has no storage"));
                };
                let upload = Upload::new(*format, *format, *kind)?;
                if !upload.fills(stored.format) {
                    return Err(format!(
                        "texels of format {format:#06x} / type {kind:#06x} into a texture stored as {}",
                        stored.format.name()
                    ));
                }
                let (width, height) = size2(*width, *height)?;
                let (x, y) = size2(*x_offset, *y_offset)?;
                let data = self.texels(&upload, pixels, width, height)?.ok_or("the texels were not recorded")?;
                let data = self.swizzled(name, stored.format, data)?;
                self.emit(Call::TexSubImage { id, x, y, width, height, data })?;
            }
            C::TexStorage2D {
                target,
                levels: 1,
                internal_format:
                    internal @ (0x8056 | 0x8057 | 0x8059 | 0x8c3a | 0x8c3d | 0x822a | 0x822c | 0x8054 | 0x805b),
                width,
                height,
            } => {
                // RGBA4 / RGB5_A1 / RGB10_A2 / R11F_G11F_B10F / RGB9_E5 storage, for glTexSubImage2D of packed texels: an
                // encoded level of zeros (GL leaves it undefined), as glTexImage2D without data.
                check_2d_level0(*target, 0)?;
                let format = match *internal {
                    0x8056 => EncodedFormat::Rgba4444,
                    0x8057 => EncodedFormat::Rgba5551,
                    0x8059 => EncodedFormat::Rgb10A2,
                    0x8c3a => EncodedFormat::R11fG11fB10f,
                    0x822a => EncodedFormat::R16,
                    0x822c => EncodedFormat::Rg16,
                    0x8054 => EncodedFormat::Rgb16,
                    0x805b => EncodedFormat::Rgba16,
                    _ => EncodedFormat::Rgb9E5,
                };
                let (width, height) = size2(*width, *height)?;
                if self.texture_id(self.bound_texture()?)?.is_some() {
                    return Err(format!("texture {} already has storage", self.bound_texture()?));
                }
                let zeros = Bytes::from(vec![0u8; width as usize * height as usize * encoded::texel_bytes(format)]);
                self.encoded_tex_image(0, (width, height), (format, false), zeros)?;
            }
            C::TexStorage2D { target, levels, internal_format, width, height } => {
                check_2d_level0(*target, 0)?;
                let red_green = red_green_format(*internal_format);
                let format = match *internal_format {
                    0x8229 | 0x822b => TextureFormat::Rgba8,
                    0x822d | 0x822f => TextureFormat::Rgba16f,
                    0x8230 => TextureFormat::Rgba32f,
                    f => renderbuffer_format(f)?,
                };
                let (width, height) = size2(*width, *height)?;
                gles3::check_storage_levels(*levels, width, height)?;
                let name = self.bound_texture()?;
                if self.objects()?.textures.get(&name).is_some_and(|t| t.id.is_some()) {
                    return Err(format!("texture {name} already has storage"));
                }
                let id = self.fresh_id();
                self.emit(Call::CreateTexture { id, width, height, format, data: None, transient: false })?;
                self.bind_new_texture(name, id)?;
                let t = self.objects()?.textures.entry(name).or_default();
                t.id = Some(id);
                t.size = (width, height);
                t.upload = gles3::storage_upload(format);
                t.red_green = red_green;
                self.update_sampler(name)?;
            }
            C::TexParameter { target, pname, params } => {
                if ![GL_TEXTURE_2D, cube::GL_TEXTURE_CUBE_MAP, layered::GL_TEXTURE_2D_ARRAY, layered::GL_TEXTURE_3D]
                    .contains(target)
                {
                    return Err(format!(
                        "texture target {target:#06x} is not supported (2D, cube map, 2-D array and 3-D only)"
                    ));
                }
                let number = match params {
                    Params::Int(v) if v.len() == 1 => v[0] as f64,
                    Params::Float(v) if v.len() == 1 => f64::from(v[0]),
                    _ => return Err(format!("parameter {pname:#06x}: {params:?} is not a single value")),
                };
                let value = number as u32;
                let name = match layered::layered_target(*target) {
                    Some(layered) => self.bound_layered(layered)?,
                    None if *target == GL_TEXTURE_2D => self.bound_texture()?,
                    None => self.bound_cube()?,
                };
                let t = self.objects()?.textures.entry(name).or_default();
                if t.compare_parameter(*pname, number)? {
                    self.update_sampler(name)?;
                    return Ok(());
                }
                match (*pname, number) {
                    (0x2801, _) => t.min = value,
                    (0x2800, _) => t.mag = value,
                    (0x2802, _) => t.wrap[0] = value,
                    (0x2803, _) => t.wrap[1] = value,
                    // WRAP_R: a 3-D texture's third coordinate (2D and cube textures keep it
                    // and do not read it).
                    (0x8072, _) => t.wrap_r = value,
                    // GL ES 3.0 parameters apps set to their defaults, or to what changes
                    // nothing here: the LOD range's defaults, base level 0, identity swizzles.
                    (0x813a, -1000.0) | (0x813b, 1000.0) | (0x813c, 0.0) => {}
                    (p @ 0x8e42..=0x8e45, v) if swizzle_source(v).is_some() => {
                        let (channel, source) = ((p - 0x8e42) as usize, swizzle_source(v).expect("checked"));
                        if t.swizzle[channel] != source {
                            if t.id.is_some() {
                                return Err(format!(
                                    "texture {name}: changing GL_TEXTURE_SWIZZLE_* once it has storage is not \
                                     supported (set it before glTexImage2D / glTexStorage2D)"
                                ));
                            }
                            t.swizzle[channel] = source;
                        }
                    }
                    // GL_TEXTURE_MAX_ANISOTROPY_EXT at its default, 1: no anisotropic filtering.
                    (0x84fe, 1.0) => {}
                    // GL_TEXTURE_MAX_LEVEL (see `Texture::max_level`).
                    (0x813d, v) if v >= 0.0 => t.max_level = v.min(1000.0) as u32,
                    (p, v) => return Err(format!("texture parameter {p:#06x} = {v} is not supported")),
                }
                self.update_sampler(name)?;
            }
            C::GenerateMipmap { target } => {
                check_2d_level0(*target, 0)?;
                let name = self.bound_texture()?;
                let id = self.texture_id(name)?.ok_or_else(|| format!("texture {name} has no storage"))?;
                self.emit(Call::GenerateMipmap { id })?;
            }
            C::PixelStore { pname, param } => match (*pname, *param) {
                (0x0cf5, a @ (1 | 2 | 4 | 8)) => self.bindings.unpack_alignment = a as u32,
                (0x0cf2, n @ 0..) => self.bindings.unpack_row_length = n as u32,
                (0x0cf3, n @ 0..) => self.bindings.unpack_skip_rows = n as u32,
                (0x0cf4, n @ 0..) => self.bindings.unpack_skip_pixels = n as u32,
                // GL_UNPACK_IMAGE_HEIGHT and GL_UNPACK_SKIP_IMAGES at their defaults.
                (0x806e | 0x806d, 0) => {}
                // GL_PACK_ALIGNMENT: read-backs return RGBA8 rows, whose length is a multiple
                // of every alignment.
                (0x0d05, 1 | 2 | 4 | 8) => {}
                (p, v) => return Err(format!("pixel store {p:#06x} = {v} is not supported")),
            },
            C::CopyTexImage2D { target, level, internal_format, x, y, width, height, border } => {
                check_2d_level0(*target, *level)?;
                if *border != 0 {
                    return Err(format!("border {border} must be 0"));
                }
                // GL_RGB: a texture whose alpha reads 1, so the copy's alpha is 1.
                let opaque = match *internal_format {
                    texels::GL_RGBA => false,
                    texels::GL_RGB => true,
                    f => return Err(format!("copying into internal format {f:#06x}: only GL_RGBA and GL_RGB")),
                };
                let (width, height) = size2(*width, *height)?;
                let upload = Upload::new(texels::GL_RGBA, texels::GL_RGBA, texels::GL_UNSIGNED_BYTE)?;
                let format = upload.format;
                let name = self.bound_texture()?;
                // New storage, then a copy from the read framebuffer into all of it: the copy
                // ends the pass that renders the source, as a read-back does.
                let id = match self.texture_id(name)? {
                    Some(id) => {
                        self.emit(Call::TexImage { id, width, height, format, data: None })?;
                        id
                    }
                    None => {
                        let id = self.fresh_id();
                        self.emit(Call::CreateTexture { id, width, height, format, data: None, transient: false })?;
                        self.bind_new_texture(name, id)?;
                        id
                    }
                };
                let t = self.objects()?.textures.entry(name).or_default();
                t.id = Some(id);
                t.upload = Some(upload);
                t.size = (width, height);
                t.opaque = opaque;
                self.update_sampler(name)?;
                let (x, y, alpha_one) = (*x, *y, opaque);
                let copy =
                    Call::CopyTexSubImage { texture: id, x_offset: 0, y_offset: 0, x, y, width, height, alpha_one };
                self.emit(copy)?;
            }
            C::CopyTexSubImage2D { target, level, x_offset, y_offset, x, y, width, height } => {
                check_2d_level0(*target, *level)?;
                let name = self.bound_texture()?;
                let id = self.texture_id(name)?.ok_or_else(|| format!("texture {name} has no storage"))?;
                self.check_renderable(name)?;
                let (x_offset, y_offset) = size2(*x_offset, *y_offset)?;
                let (width, height) = size2(*width, *height)?;
                let alpha_one = self.objects()?.textures.get(&name).is_some_and(|t| t.opaque);
                let (x, y) = (*x, *y);
                self.emit(Call::CopyTexSubImage { texture: id, x_offset, y_offset, x, y, width, height, alpha_one })?;
            }

            // ---- framebuffers and renderbuffers ----------------------------------------------
            // A framebuffer is made at its first bind (`framebuffer_id`), in the context's own
            // names.
            C::GenFramebuffers { .. } | C::GenRenderbuffers { .. } => {}
            C::BindFramebuffer { target, framebuffer } => {
                let target = match *target {
                    GL_FRAMEBUFFER => FramebufferTarget::Framebuffer,
                    GL_DRAW_FRAMEBUFFER => FramebufferTarget::Draw,
                    GL_READ_FRAMEBUFFER => FramebufferTarget::Read,
                    t => return Err(format!("framebuffer target {t:#06x} is not a GL one")),
                };
                let id = self.framebuffer_id(*framebuffer)?;
                if target != FramebufferTarget::Read {
                    self.bindings.draw_framebuffer = *framebuffer;
                }
                if target != FramebufferTarget::Draw {
                    self.bindings.read_framebuffer = *framebuffer;
                }
                self.emit(Call::BindFramebuffer { target, framebuffer: id })?;
            }
            C::DeleteFramebuffers { names } => {
                for &name in names {
                    if let Some(id) = self.own()?.framebuffers.remove(&name) {
                        self.emit(Call::DeleteFramebuffer { id })?;
                    }
                    let b = &mut self.bindings;
                    b.read_none.remove(&name);
                    for bound in [&mut b.draw_framebuffer, &mut b.read_framebuffer] {
                        if *bound == name {
                            *bound = 0;
                        }
                    }
                }
            }
            C::FramebufferTexture2D { target, attachment, texture_target, texture, level, samples } => {
                let framebuffer = self.attachment_target(*target)?;
                let attachment = attachment_point(*attachment)?;
                let texture = if *texture == 0 {
                    0
                } else {
                    check_2d_level0(*texture_target, *level)?;
                    self.check_renderable(*texture)?;
                    self.texture_id(*texture)?.ok_or_else(|| format!("texture {texture} has no storage"))?
                };
                let samples = granted_samples(*samples)?;
                self.emit(Call::FramebufferTexture { framebuffer, attachment, texture, samples })?;
            }
            C::BindRenderbuffer { renderbuffer, .. } => {
                self.bindings.renderbuffer = *renderbuffer;
                if *renderbuffer != 0 {
                    self.objects()?.renderbuffers.entry(*renderbuffer).or_insert(None);
                }
            }
            C::RenderbufferStorage { samples, internal_format, width, height, .. } => {
                let name = self.bindings.renderbuffer;
                if name == 0 {
                    return Err("no renderbuffer is bound".into());
                }
                if self.objects()?.renderbuffers.get(&name).is_some_and(Option::is_some) {
                    return Err(format!("renderbuffer {name} already has storage: new storage is not supported"));
                }
                let format = renderbuffer_format(*internal_format)?;
                let (width, height) = size2(*width, *height)?;
                let id = self.fresh_id();
                let samples = granted_samples(*samples)?;
                self.emit(Call::CreateRenderbuffer { id, width, height, format, samples, transient: false })?;
                self.objects()?.renderbuffers.insert(name, Some(id));
            }
            C::FramebufferRenderbuffer { target, attachment, renderbuffer, .. } => {
                let framebuffer = self.attachment_target(*target)?;
                let attachment = attachment_point(*attachment)?;
                let renderbuffer = if *renderbuffer == 0 {
                    0
                } else {
                    self.objects()?
                        .renderbuffers
                        .get(renderbuffer)
                        .copied()
                        .flatten()
                        .ok_or_else(|| format!("renderbuffer {renderbuffer} has no storage"))?
                };
                self.emit(Call::FramebufferRenderbuffer { framebuffer, attachment, renderbuffer })?;
            }
            C::DeleteRenderbuffers { names } => {
                for &name in names {
                    if let Some(Some(id)) = self.objects()?.renderbuffers.remove(&name) {
                        self.emit(Call::DeleteRenderbuffer { id })?;
                    }
                    if self.bindings.renderbuffer == name {
                        self.bindings.renderbuffer = 0;
                    }
                }
            }
            C::InvalidateFramebuffer { target, attachments, region } => {
                if region.is_some() {
                    return Err("invalidating part of a framebuffer is not supported".into());
                }
                if *target == GL_READ_FRAMEBUFFER {
                    return Err("invalidating the read framebuffer is not supported".into());
                }
                let default = self.bindings.draw_framebuffer == 0;
                let attachments =
                    attachments.iter().map(|&a| invalidate_point(a, default)).collect::<Fallible<Vec<_>>>()?;
                self.emit(Call::Invalidate { attachments })?;
            }
            C::BlitFramebuffer { src, dst, mask, filter } => {
                if *mask != 0x4000 {
                    return Err(format!("blit mask {mask:#x}: only colour blits are supported"));
                }
                let filter = match *filter {
                    GL_NEAREST => Filter::Nearest,
                    GL_LINEAR => Filter::Linear,
                    f => return Err(format!("blit filter {f:#06x} is not a GL one")),
                };
                self.emit(Call::BlitFramebuffer { src: *src, dst: *dst, filter })?;
            }
            C::DrawBuffers { buffers } => self.draw_buffers(buffers)?,
            C::ReadBuffer { source } => {
                // GL_NONE (a depth-only framebuffer, say) reads nothing: later colour reads
                // are GL errors, refused as such.
                let framebuffer = self.bindings.read_framebuffer;
                let default = framebuffer == 0;
                if *source == 0 {
                    self.bindings.read_none.insert(framebuffer);
                } else if *source == if default { 0x0405 } else { 0x8ce0 } {
                    self.bindings.read_none.remove(&framebuffer);
                } else {
                    return Err(format!(
                        "read buffer {source:#06x}: only GL_NONE and the default (GL_BACK, GL_COLOR_ATTACHMENT0) are \
                         supported"
                    ));
                }
            }
            C::ReadPixels { x, y, width, height, format, kind, .. } => {
                let (width, height) = size2(*width, *height)?;
                let (x, y) = (*x, *y);
                self.emit(match (*format, *kind) {
                    (texels::GL_RGBA, texels::GL_UNSIGNED_BYTE) => Call::ReadPixels { x, y, width, height },
                    (texels::GL_RGBA_INTEGER, texels::GL_INT | texels::GL_UNSIGNED_INT) => {
                        Call::ReadPixelsInteger { x, y, width, height, signed: *kind == texels::GL_INT }
                    }
                    _ => {
                        return Err(format!(
                            "reading format {format:#06x} / type {kind:#06x}: only RGBA bytes and RGBA_INTEGER ints"
                        ));
                    }
                })?;
            }

            // ---- shaders and programs ----------------------------------------------------------
            C::CreateShader { kind, shader } => {
                if ![GL_VERTEX_SHADER, GL_FRAGMENT_SHADER].contains(kind) {
                    return Err(format!("shader type {kind:#06x} is not a GLES 2.0 one"));
                }
                self.objects()?.shaders.insert(*shader, (*kind, None));
            }
            C::ShaderSource { shader, source } => {
                let s =
                    self.objects()?.shaders.get_mut(shader).ok_or_else(|| format!("shader {shader} does not exist"))?;
                s.1 = Some(source.clone());
            }
            C::CompileShader { shader } => {
                if !self.objects()?.shaders.contains_key(shader) {
                    return Err(format!("shader {shader} does not exist"));
                }
            }
            C::DeleteShader { shader } => {
                let objects = self.objects()?;
                if *shader != 0 && objects.shaders.contains_key(shader) {
                    objects.deleted_shaders.push(*shader);
                    objects.collect_shaders();
                }
            }
            C::CreateProgram { program } => {
                self.objects()?.programs.insert(*program, Program::default());
            }
            C::AttachShader { program, shader } => self.program(*program)?.shaders.push(*shader),
            C::DetachShader { program, shader } => {
                self.program(*program)?.shaders.retain(|s| s != shader);
                self.objects()?.collect_shaders();
            }
            C::BindAttribLocation { program, index, name } => {
                attrib_slot(*index)?;
                let p = self.program(*program)?;
                p.bindings.retain(|(_, n)| n != name);
                p.bindings.push((*index, name.clone()));
            }
            C::LinkProgram { program } => self.link(*program)?,
            C::UseProgram { program } => {
                let id = if *program == 0 {
                    0
                } else {
                    self.program(*program)?.id.ok_or_else(|| format!("program {program} is not linked"))?
                };
                let previous = std::mem::replace(&mut self.bindings.program, *program);
                self.emit(Call::UseProgram { id })?;
                if previous != *program && self.objects()?.programs.get(&previous).is_some_and(|p| p.deleted) {
                    self.objects()?.remove_program(previous);
                }
            }
            C::DeleteProgram { program } => {
                // GL: a program in use is deleted once another is used; the context does the same
                // with its program.
                if *program != 0 {
                    let p = self.program(*program)?;
                    p.deleted = true;
                    if let Some(id) = p.id {
                        self.emit(Call::DeleteProgram { id })?;
                    }
                    if self.bindings.program != *program {
                        self.objects()?.remove_program(*program);
                    }
                }
            }
            C::UniformLocation { program, name, location } => {
                if *location >= 0 {
                    self.program(*program)?.uniforms.insert(*location, name.clone());
                }
            }
            C::AttribLocation { program, name, location } => {
                if *location >= 0 {
                    let index = *location as u32;
                    attrib_slot(index)?;
                    let id = self.program(*program)?.id.ok_or_else(|| format!("program {program} is not linked"))?;
                    self.emit(glsl::bind_attrib_location(id, index, name.clone())?)?;
                }
            }
            C::Uniform { location, value } => self.uniform(*location, value)?,
            C::UniformBlockIndex { program, name, index } => {
                // GL_INVALID_INDEX: no such block.
                if *index != u32::MAX {
                    self.program(*program)?.blocks.insert(*index, name.clone());
                }
            }
            C::UniformBlockBinding { program, block_index, binding } => {
                self.uniform_block_binding(*program, *block_index, *binding)?;
            }
            C::GenSamplers { names } => {
                let objects = self.objects()?;
                for &name in names {
                    objects.samplers.insert(name, Texture::default());
                }
            }
            C::DeleteSamplers { names } => self.delete_samplers(names)?,
            C::BindSampler { unit, sampler } => self.bind_sampler(*unit, *sampler)?,
            C::SamplerParameter { sampler, pname, params } => self.sampler_parameter(*sampler, *pname, params)?,
            C::BindBufferRange { target, index, buffer, range } => {
                self.bind_buffer_range(*target, *index, *buffer, *range)?;
            }

            // ---- fixed-function state ------------------------------------------------------------
            C::Enable { cap } | C::Disable { cap } => {
                let on = matches!(command, C::Enable { .. });
                let capability = match *cap {
                    0x0b71 => Some(Capability::DepthTest),
                    0x0b90 => Some(Capability::StencilTest),
                    0x0be2 => Some(Capability::Blend),
                    0x0b44 => Some(Capability::CullFace),
                    0x0c11 => Some(Capability::ScissorTest),
                    0x8037 => Some(Capability::PolygonOffsetFill),
                    0x8d69 => Some(Capability::PrimitiveRestartFixedIndex),
                    0x8c89 => Some(Capability::RasterizerDiscard),
                    // Dithering may be a no-op in GL; neither llvmpipe nor tiler dithers.
                    0x0bd0 => None,
                    // Off by default; turning them off changes nothing.
                    0x809e | 0x80a0 if !on => None,
                    // GL_FRAMEBUFFER_SRGB_EXT: on by default; see `Bindings::srgb_write_off`.
                    0x8db9 => {
                        self.bindings.srgb_write_off = !on;
                        None
                    }
                    c => return Err(format!("capability {c:#06x} is not supported")),
                };
                if let Some(cap) = capability {
                    self.emit(if on { Call::Enable { cap } } else { Call::Disable { cap } })?;
                }
            }
            C::Viewport { x, y, width, height } => {
                let (w, h) = size2(*width, *height)?;
                self.window_known((w, h))?;
                self.grow_window(*x, *y, w, h)?;
                self.emit(Call::Viewport { x: *x, y: *y, width: w, height: h })?;
            }
            C::Scissor { x, y, width, height } => {
                let (width, height) = size2(*width, *height)?;
                self.grow_window(*x, *y, width, height)?;
                self.emit(Call::Scissor { x: *x, y: *y, width, height })?;
            }
            C::DepthFunc { func } => {
                let func = compare_op(*func)?;
                self.emit(Call::DepthFunc { func })?;
            }
            C::DepthMask { write } => {
                self.emit(Call::DepthMask { write: *write })?;
            }
            C::DepthRange { near, far } => {
                self.emit(Call::DepthRange { near: *near, far: *far })?;
            }
            C::CullFace { mode } => {
                let face = match *mode {
                    0x0404 => Face::Front,
                    0x0405 => Face::Back,
                    GL_FRONT_AND_BACK => Face::FrontAndBack,
                    m => return Err(format!("cull face {m:#06x} is not a GL one")),
                };
                self.emit(Call::CullFace { face })?;
            }
            C::FrontFace { mode } => {
                let winding = match *mode {
                    0x0900 => Winding::Cw,
                    0x0901 => Winding::Ccw,
                    m => return Err(format!("front face {m:#06x} is not a GL one")),
                };
                self.emit(Call::FrontFace { winding })?;
            }
            C::ColorMask { mask } => {
                let [red, green, blue, alpha] = *mask;
                self.emit(Call::ColorMask { red, green, blue, alpha })?;
            }
            C::BlendFunc { src_rgb, dst_rgb, src_alpha, dst_alpha } => {
                let (src, dst) = (blend_factor(*src_rgb)?, blend_factor(*dst_rgb)?);
                let (src_alpha, dst_alpha) = (Some(blend_factor(*src_alpha)?), Some(blend_factor(*dst_alpha)?));
                self.emit(Call::BlendFunc { src, dst, src_alpha, dst_alpha })?;
            }
            C::BlendEquation { rgb, alpha } => {
                let (rgb, alpha) = (blend_op(*rgb)?, Some(blend_op(*alpha)?));
                self.emit(Call::BlendEquation { rgb, alpha })?;
            }
            C::BlendColor { color } => {
                self.emit(Call::BlendColor { rgba: *color })?;
            }
            C::StencilFunc { face, func, reference, mask } => {
                let face = stencil_face(*face)?;
                let func = compare_op(*func)?;
                let (reference, mask) = ((*reference).clamp(0, 255) as u8, *mask as u8);
                self.emit(Call::StencilFunc { func, reference, mask, face })?;
            }
            C::StencilOp { face, stencil_fail, depth_fail, pass } => {
                let face = stencil_face(*face)?;
                let (fail, depth_fail, pass) =
                    (stencil_op(*stencil_fail)?, stencil_op(*depth_fail)?, stencil_op(*pass)?);
                self.emit(Call::StencilOp { fail, depth_fail, pass, face })?;
            }
            C::StencilMask { face, mask } => {
                let face = stencil_face(*face)?;
                self.emit(Call::StencilMask { mask: *mask as u8, face })?;
            }
            C::ClearColor { color } => {
                self.emit(Call::ClearColor { rgba: *color })?;
            }
            C::ClearDepth { depth } => {
                self.emit(Call::ClearDepth { depth: *depth })?;
            }
            C::ClearStencil { stencil } => {
                self.emit(Call::ClearStencil { stencil: *stencil as u8 })?;
            }
            C::ClearBuffer { buffer, draw_buffer, value } => {
                use tiler_apitrace::gles::ClearValue as V;
                let call = match (*buffer, value) {
                    (0x1800, value) => {
                        let draw_buffer = u32::try_from(*draw_buffer)
                            .map_err(|_| format!("draw buffer {draw_buffer} is negative"))?;
                        let value = match value {
                            V::Float(v) => ClearColorValue::Float(*v),
                            V::Int(v) => ClearColorValue::Int(*v),
                            V::UInt(v) => ClearColorValue::Uint(*v),
                            V::DepthStencil { .. } => return Err("glClearBufferfi of GL_COLOR".into()),
                        };
                        Call::ClearBufferColor { draw_buffer, value }
                    }
                    (0x1801, V::Float(v)) => Call::ClearBufferDepthStencil { depth: Some(v[0]), stencil: None },
                    (0x1802, V::Int(v)) => Call::ClearBufferDepthStencil { depth: None, stencil: Some(v[0] as u8) },
                    (0x84f9, V::DepthStencil { depth, stencil }) => {
                        Call::ClearBufferDepthStencil { depth: Some(*depth), stencil: Some(*stencil as u8) }
                    }
                    (buffer, value) => {
                        return Err(format!(
                            "glClearBuffer of buffer {buffer:#06x} with {value:?} is not a valid call"
                        ));
                    }
                };
                self.emit(call)?;
            }
            C::PolygonOffset { factor, units } => {
                self.emit(Call::PolygonOffset { factor: *factor, units: *units })?;
            }
            C::LineWidth { width } => {
                self.emit(Call::LineWidth { width: *width })?;
            }
            // Hints may be ignored by any GL; coverage matters only under capabilities the
            // replay refuses to enable.
            C::Hint { .. } | C::SampleCoverage { .. } => {}

            // ---- queries and tiling ---------------------------------------------------------------
            C::GenQueries { names } => {
                for &name in names {
                    let id = self.fresh_id();
                    self.emit(Call::CreateQuery { id })?;
                    self.own()?.queries.insert(name, id);
                }
            }
            C::DeleteQueries { names } => {
                for &name in names {
                    self.own()?.timer_queries.remove(&name);
                    if let Some(id) = self.own()?.queries.remove(&name) {
                        self.emit(Call::DeleteQuery { id })?;
                    }
                }
            }
            // A timer query (`EXT_disjoint_timer_query`) measures the GPU's time, which tiler
            // does not model as GL reports it: it changes nothing drawn or stored. Reading its
            // result waits for the GPU to finish the measured commands, as glFinish.
            C::BeginQuery { target: GL_TIME_ELAPSED, query } => {
                self.query_id(*query)?;
                self.own()?.timer_queries.insert(*query);
            }
            C::EndQuery { target: GL_TIME_ELAPSED } => {}
            C::QueryCounter { query } => {
                self.query_id(*query)?;
                self.own()?.timer_queries.insert(*query);
            }
            C::BeginQuery { target, query } => {
                if ![0x8c2f, 0x8d6a].contains(target) {
                    return Err(format!(
                        "query target {target:#06x}: only GL_ANY_SAMPLES_PASSED(_CONSERVATIVE) and \
                         GL_TIME_ELAPSED_EXT are supported"
                    ));
                }
                let id = self.query_id(*query)?;
                self.own()?.timer_queries.remove(query);
                self.emit(Call::BeginQuery { id })?;
            }
            C::EndQuery { .. } => {
                self.emit(Call::EndQuery)?;
            }
            C::GetQueryResult { query, pname } if self.own()?.timer_queries.contains(query) => {
                self.query_id(*query)?;
                match *pname {
                    0x8866 => {
                        self.emit(Call::Finish)?;
                    }
                    0x8867 => {}
                    p => return Err(format!("query parameter {p:#06x} is not supported")),
                }
            }
            C::GetQueryResult { query, pname } => {
                let id = self.query_id(*query)?;
                match *pname {
                    0x8866 => self.emit(Call::QueryResult { id })?,
                    0x8867 => self.emit(Call::QueryAvailable { id })?,
                    p => return Err(format!("query parameter {p:#06x} is not supported")),
                };
            }
            C::StartTiling { x, y, width, height, preserve_mask } => {
                let x = i32::try_from(*x).map_err(|_| format!("x {x} is out of range"))?;
                let y = i32::try_from(*y).map_err(|_| format!("y {y} is out of range"))?;
                let preserve = qcom_buffers(*preserve_mask);
                self.emit(Call::StartTiling { x, y, width: *width, height: *height, preserve })?;
            }
            C::EndTiling { preserve_mask } => {
                self.emit(Call::EndTiling { store: qcom_buffers(*preserve_mask) })?;
            }

            other => return Err(format!("not supported by the context: {}", command_name(other))),
        }
        Ok(())
    }

    /// Whether making `context` current switches away from the state of a live context that
    /// has changed it, which stays in the context's context of its own
    /// ([`Translator::make_current`]).
    fn switches_away_from_live_state(&self, context: EglHandle) -> bool {
        let Some(&generation) = self.generations.get(&context) else { return false };
        self.last_current.is_some_and(|last| {
            last != generation && self.generations.values().any(|&g| g == last) && self.touched.contains(&last)
        })
    }

    fn make_current(&mut self, draw: EglHandle, context: EglHandle) -> Fallible {
        if context == 0 {
            self.current = None;
            return Ok(());
        }
        let generation = *self.generations.get(&context).ok_or("makes current a context never created")?;
        // No surface (EGL_KHR_surfaceless_context: a context current only to make or query
        // objects, as toolkits' share contexts are), the window, or a pbuffer beside it that
        // is not drawn to.
        self.not_window = if draw == 0 {
            Some("without a surface (GL_FRAMEBUFFER_UNDEFINED, a GL error)")
        } else if self.other_surfaces.contains(&draw) {
            Some("on a pbuffer made beside the window (drawing to a second surface is not supported)")
        } else if self.window_surface.is_some_and(|s| s != draw) {
            return Err("drawing to a surface other than the window is not supported".into());
        } else {
            None
        };
        // Each EGL context's GL state is in a context of the replay's context (its slot). A
        // context that changed no state (its state is the defaults, which `reset_state` gives
        // back) or is gone gives its slot up to the next one made current, so that captures
        // whose contexts take turns (a share context that only made programs, a context made
        // after the last one was destroyed) replay on one.
        if self.last_current == Some(generation) {
        } else if let Some(&slot) = self.slots.get(&generation) {
            self.switch_slot(slot)?;
            self.last_current = Some(generation);
        } else if self.switches_away_from_live_state(context) {
            let slot = self.next_slot;
            self.next_slot += 1;
            self.ctx()?.call(Call::CreateContext { id: slot }).map_err(|e| e.message)?;
            self.switch_slot(slot)?;
            self.slots.insert(generation, slot);
            self.last_current = Some(generation);
        } else {
            if let Some(last) = self.last_current {
                self.slots.remove(&last);
                let fresh = !self.touched.contains(&generation);
                self.current = Some(generation);
                self.reset_state()?;
                if fresh {
                    self.touched.remove(&generation);
                }
            }
            self.slots.insert(generation, self.active_slot);
            self.last_current = Some(generation);
        }
        self.current = Some(generation);
        Ok(())
    }

    /// Makes the context's context `slot` current, its bindings with it. The slot left goes
    /// if no EGL context's state is in it any more (its context was destroyed).
    fn switch_slot(&mut self, slot: u32) -> Fallible {
        let left = self.active_slot;
        self.ctx()?.call(Call::MakeCurrent { id: slot }).map_err(|e| e.message)?;
        let bindings = self.saved_bindings.remove(&slot).unwrap_or_default();
        self.saved_bindings.insert(left, std::mem::replace(&mut self.bindings, bindings));
        self.active_slot = slot;
        if !self.slots.values().any(|&s| s == left) {
            self.saved_bindings.remove(&left);
            self.ctx()?.call(Call::DestroyContext { id: left }).map_err(|e| e.message)?;
        }
        Ok(())
    }

    /// A new context's GL state: the defaults, with the viewport and scissor of the window.
    fn reset_state(&mut self) -> Fallible {
        let old = std::mem::take(&mut self.bindings);
        let Some(ctx) = self.ctx.as_ref() else { return Ok(()) };
        let (width, height) = (ctx.config().width, ctx.config().height);
        // Back to the default vertex array first: the resets below are its state.
        let mut calls = gles3::default_gles3_calls(&old);
        calls.extend([
            Call::BindFramebuffer { target: FramebufferTarget::Framebuffer, framebuffer: 0 },
            Call::UseProgram { id: 0 },
            Call::BindIndexBuffer { buffer: 0 },
            Call::Viewport { x: 0, y: 0, width, height },
            Call::Scissor { x: 0, y: 0, width, height },
            Call::DepthRange { near: 0.0, far: 1.0 },
            Call::PolygonOffset { factor: 0.0, units: 0.0 },
            Call::LineWidth { width: 1.0 },
            Call::ColorMask { red: true, green: true, blue: true, alpha: true },
            Call::DepthMask { write: true },
            Call::StencilMask { mask: 0xff, face: Face::FrontAndBack },
            Call::DepthFunc { func: CompareOp::Less },
            Call::StencilFunc { func: CompareOp::Always, reference: 0, mask: 0xff, face: Face::FrontAndBack },
            Call::StencilOp {
                fail: StencilOp::Keep,
                depth_fail: StencilOp::Keep,
                pass: StencilOp::Keep,
                face: Face::FrontAndBack,
            },
            Call::BlendFunc { src: BlendFactor::One, dst: BlendFactor::Zero, src_alpha: None, dst_alpha: None },
            Call::BlendEquation { rgb: BlendOp::Add, alpha: None },
            Call::BlendColor { rgba: [0.0; 4] },
            Call::CullFace { face: Face::Back },
            Call::FrontFace { winding: Winding::Ccw },
            Call::ClearColor { rgba: [0.0; 4] },
            Call::ClearDepth { depth: 1.0 },
            Call::ClearStencil { stencil: 0 },
        ]);
        for cap in [
            Capability::DepthTest,
            Capability::StencilTest,
            Capability::Blend,
            Capability::CullFace,
            Capability::ScissorTest,
            Capability::PolygonOffsetFill,
            Capability::PrimitiveRestartFixedIndex,
        ] {
            calls.push(Call::Disable { cap });
        }
        for unit in 0..MAX_TEXTURE_UNITS {
            calls.push(Call::BindTexture { unit, texture: 0 });
            calls.push(Call::BindCubeTexture { unit, texture: 0 });
        }
        for index in 0..MAX_VERTEX_ATTRIBS {
            calls.push(Call::DisableVertexAttrib { index });
            calls.push(Call::VertexAttrib { index, value: [0.0, 0.0, 0.0, 1.0] });
        }
        for call in calls {
            // The window's framebuffer is bound by the first call, so a pass in flight is
            // ended by it only if another framebuffer was bound.
            self.emit(call)?;
        }
        Ok(())
    }

    /// A destroyed context's bindings go, and with the last context of its share group
    /// (`group`), the group's objects.
    fn destroy_objects(&mut self, generation: u32, group: Option<u32>) -> Fallible {
        // Unbind first, as a destroyed context's bindings go with it.
        if self.last_current == Some(generation) {
            self.reset_state()?;
            self.last_current = None;
            self.slots.remove(&generation);
        } else if let Some(slot) = self.slots.remove(&generation) {
            self.saved_bindings.remove(&slot);
            self.ctx()?.call(Call::DestroyContext { id: slot }).map_err(|e| e.message)?;
        }
        let own = self.own.remove(&generation).unwrap_or_default();
        let objects = group.and_then(|group| self.objects.remove(&group)).unwrap_or_default();
        if self.ctx.is_none() {
            return Ok(());
        }
        let sorted = |ids: Vec<u32>| {
            let mut ids = ids;
            ids.sort_unstable();
            ids
        };
        let mut calls = Vec::new();
        calls.extend(
            sorted(own.framebuffers.values().copied().collect()).into_iter().map(|id| Call::DeleteFramebuffer { id }),
        );
        calls.extend(
            sorted(objects.renderbuffers.values().flatten().copied().collect())
                .into_iter()
                .map(|id| Call::DeleteRenderbuffer { id }),
        );
        calls.extend(
            sorted(objects.textures.values().filter_map(|t| t.id).collect())
                .into_iter()
                .map(|id| Call::DeleteTexture { id }),
        );
        calls.extend(
            sorted(objects.buffers.values().flatten().copied().collect())
                .into_iter()
                .map(|id| Call::DeleteBuffer { id }),
        );
        calls.extend(sorted(own.queries.values().copied().collect()).into_iter().map(|id| Call::DeleteQuery { id }));
        calls.extend(
            sorted(own.vertex_arrays.values().copied().collect()).into_iter().map(|id| Call::DeleteVertexArray { id }),
        );
        // Deleted programs were deleted in the context when GL deleted them.
        let programs = objects.programs.values().filter(|p| !p.deleted).filter_map(|p| p.id).collect();
        calls.extend(sorted(programs).into_iter().map(|id| Call::DeleteProgram { id }));
        for call in calls {
            self.emit(call)?;
        }
        Ok(())
    }

    fn program(&mut self, program: u32) -> Fallible<&mut Program> {
        self.objects()?.programs.get_mut(&program).ok_or_else(|| format!("program {program} does not exist"))
    }

    fn link(&mut self, program: u32) -> Fallible {
        let p = self.program(program)?.clone();
        let objects = self.objects()?;
        let mut sources = [None, None];
        for shader in &p.shaders {
            let (kind, source) =
                objects.shaders.get(shader).ok_or_else(|| format!("shader {shader} does not exist"))?;
            let source = source.clone().ok_or_else(|| format!("shader {shader} has no source"))?;
            sources[usize::from(*kind == GL_FRAGMENT_SHADER)] = Some(source);
        }
        let [Some(vertex), Some(fragment)] = sources else {
            return Err(format!("program {program} needs a vertex and a fragment shader"));
        };
        let id = self.fresh_id();
        self.emit(glsl::create_program(id, vertex, fragment)?)?;
        for (index, name) in p.bindings {
            self.emit(glsl::bind_attrib_location(id, index, name)?)?;
        }
        if let Some((varyings, separate)) = p.feedback {
            self.emit(Call::TransformFeedbackVaryings { program: id, varyings, separate })?;
        }
        let p = self.program(program)?;
        let old = p.id.replace(id);
        let deleted = p.deleted;
        p.uniforms.clear();
        p.blocks.clear();
        if self.bindings.program == program {
            self.emit(Call::UseProgram { id })?;
        }
        // The previous link's program is no one's now (a deleted one the context has let go).
        if let Some(old) = old.filter(|_| !deleted) {
            self.emit(Call::DeleteProgram { id: old })?;
        }
        Ok(())
    }

    fn uniform(&mut self, location: i32, value: &GlUniform) -> Fallible {
        if location == -1 {
            return Ok(()); // GL ignores location -1.
        }
        let program = self.bindings.program;
        if program == 0 {
            return Err("no program is in use".into());
        }
        let name = self.program(program)?.uniforms.get(&location).cloned().ok_or_else(|| {
            format!("location {location} was never returned by glGetUniformLocation for program {program}")
        })?;
        let values = glsl::uniform_values(value)?;
        let count = values.len();
        // GL ES 3.0 §2.12.6: values for elements past the array's last are ignored
        // (GStreamer's blur sets 9 floats into a `float kernel[7]`).
        let (base, first) = match name.strip_suffix(']').and_then(|n| n.rsplit_once('[')) {
            Some((base, i)) => (base, i.parse::<usize>().unwrap_or(0)),
            None => (name.as_str(), 0),
        };
        let id = self.program(program)?.id;
        let elements = match (count > 1, id) {
            (true, Some(id)) => self.ctx()?.uniform_elements(id, base),
            _ => None,
        };
        let count = elements.map_or(count, |n| count.min(n.saturating_sub(first)).max(1));
        for (k, value) in values.into_iter().take(count).enumerate() {
            let name = element_name(&name, k, count)?;
            self.emit(Call::Uniform { name, value })?;
        }
        Ok(())
    }

    /// Checks what a draw reads; returns its instance count unless it is 1 (a draw of one
    /// instance is a plain draw: per-instance attributes read their first element in both).
    fn check_draw(&mut self, instance_count: i32) -> Fallible<Option<u32>> {
        let instances = match instance_count {
            1 => None,
            n => Some(u32::try_from(n).map_err(|_| format!("instance count {n} is negative"))?),
        };
        for slot in 0..MAX_VERTEX_ATTRIBS as usize {
            if self.bindings.enabled_attribs[slot] && self.bindings.unrecorded_client_attribs[slot] {
                return Err(format!("attribute {slot} reads client memory the capture did not record"));
            }
        }
        let textures = self.bindings.textures;
        for (unit, name) in textures.iter().enumerate().filter(|(_, name)| **name != 0) {
            if let Some(t) = self.objects()?.textures.get(name)
                && t.id.is_some()
            {
                t.sampler().map_err(|e| format!("texture {name} on unit {unit}: {e}"))?;
            }
        }
        Ok(instances)
    }

    fn draw_elements(
        &mut self,
        mode: Mode,
        count: u32,
        kind: GlEnum,
        indices: &Memory,
        instances: Option<u32>,
    ) -> Fallible {
        let index_type = match kind {
            texels::GL_UNSIGNED_SHORT => IndexKind::UnsignedShort,
            texels::GL_UNSIGNED_INT => IndexKind::UnsignedInt,
            // Client-side bytes are widened here, into the scratch buffer; in a buffer object
            // the context widens them at the draw.
            texels::GL_UNSIGNED_BYTE if matches!(indices, Memory::Client(_)) => IndexKind::UnsignedShort,
            texels::GL_UNSIGNED_BYTE => IndexKind::UnsignedByte,
            k => return Err(format!("index type {k:#06x} is not a GL one")),
        };
        let draw = |offset| match instances {
            None => Call::DrawElements { mode, count, index_type, offset },
            Some(instances) => Call::DrawElementsInstanced { mode, count, index_type, offset, instances },
        };
        match indices {
            Memory::Client(bytes) => {
                // Client-side indices: through a scratch index buffer, bytes widened to shorts.
                let data: Vec<u8> = if kind == texels::GL_UNSIGNED_BYTE {
                    bytes.iter().flat_map(|&i| u16::from(i).to_le_bytes()).collect()
                } else {
                    bytes.clone()
                };
                let data = Bytes::from(data);
                let scratch = match self.scratch_indices {
                    Some(id) => {
                        self.emit(Call::BufferData { id, data })?;
                        id
                    }
                    None => {
                        let id = self.fresh_id();
                        self.emit(Call::CreateBuffer { id, data })?;
                        self.scratch_indices = Some(id);
                        id
                    }
                };
                self.emit(Call::BindIndexBuffer { buffer: scratch })?;
                let drawn = self.emit(draw(0));
                let bound = self.buffer_id(self.bindings.element_buffer)?.unwrap_or(0);
                self.emit(Call::BindIndexBuffer { buffer: bound })?;
                drawn?;
            }
            Memory::Null => {
                self.emit(draw(0))?;
            }
            Memory::Offset(offset) => {
                self.emit(draw(*offset))?;
            }
        }
        Ok(())
    }

    fn buffer_id(&mut self, name: u32) -> Fallible<Option<u32>> {
        if name == 0 {
            return Ok(None);
        }
        Ok(self.objects()?.buffers.get(&name).copied().flatten())
    }

    fn bound_buffer(&self, target: GlEnum) -> Fallible<u32> {
        let name = match target {
            GL_ARRAY_BUFFER => self.bindings.array_buffer,
            GL_ELEMENT_ARRAY_BUFFER => self.bindings.element_buffer,
            t if gles3::OTHER_BUFFER_TARGETS.contains(&t) => self.bindings.other_buffers.get(&t).copied().unwrap_or(0),
            t => return Err(format!("buffer target {t:#06x} is not supported")),
        };
        if name == 0 {
            return Err(format!("no buffer is bound to target {target:#06x}"));
        }
        Ok(name)
    }

    /// The active texture unit, an index of the context's units.
    ///
    /// # Errors
    /// The unit is beyond the context's [`MAX_TEXTURE_UNITS`].
    pub(super) fn unit(&self) -> Fallible<usize> {
        let unit = self.bindings.active_unit;
        if unit >= MAX_TEXTURE_UNITS {
            return Err(format!("texture unit {unit} is beyond the context's {MAX_TEXTURE_UNITS}"));
        }
        Ok(unit as usize)
    }

    pub(super) fn bound_texture(&self) -> Fallible<u32> {
        match self.bindings.textures[self.unit()?] {
            0 => Err("the default texture (0) is not supported: bind a texture".into()),
            name => Ok(name),
        }
    }

    /// Binds a texture that just got storage on the units GL bound its name to.
    pub(super) fn bind_new_texture(&mut self, name: u32, id: u32) -> Fallible {
        for unit in 0..MAX_TEXTURE_UNITS {
            if self.bindings.textures[unit as usize] == name {
                self.emit(Call::BindTexture { unit, texture: id })?;
            }
        }
        Ok(())
    }

    /// Texture `name` got storage `id` of `size` from an encoded upload: its texels come
    /// encoded from now on (`capture::encoded`).
    pub(super) fn set_encoded_storage(&mut self, name: u32, id: u32, size: (u32, u32)) -> Fallible {
        let t = self.objects()?.textures.entry(name).or_default();
        t.id = Some(id);
        t.upload = None;
        t.size = size;
        Ok(())
    }

    /// A texel upload while a pixel unpack buffer is bound reads its texels from the buffer,
    /// at the offset the pointer gives (GL ES 3.0 §3.7.1): the same upload with the bytes from
    /// there to the buffer's end in place of the pointer, or `None` for any other command.
    /// (A driver copies them on the GPU; the context counts them as an upload.)
    fn unpack_from_buffer(&mut self, command: &Command) -> Fallible<Option<Command>> {
        use Command as C;
        let name = self.bindings.other_buffers.get(&gles3::GL_PIXEL_UNPACK_BUFFER).copied().unwrap_or(0);
        if name == 0 {
            return Ok(None);
        }
        let mut command = command.clone();
        let pixels = match &mut command {
            C::TexImage2D { pixels, .. }
            | C::TexSubImage2D { pixels, .. }
            | C::TexImage3D { pixels, .. }
            | C::TexSubImage3D { pixels, .. } => pixels,
            C::CompressedTexImage2D { data, .. } | C::CompressedTexSubImage2D { data, .. } => data,
            _ => return Ok(None),
        };
        let offset = match pixels {
            // apitrace writes a null offset as an empty blob.
            Memory::Null => 0,
            Memory::Client(bytes) if bytes.is_empty() => 0,
            Memory::Offset(offset) => *offset,
            Memory::Client(_) => return Err("client texels while a pixel unpack buffer is bound".into()),
        };
        let id = self.buffer_id(name)?.ok_or_else(|| format!("pixel unpack buffer {name} has no storage"))?;
        let bytes = self.ctx()?.buffer_bytes(id)?;
        let start = usize::try_from(offset).ok().filter(|&o| o <= bytes.len()).ok_or_else(|| {
            format!("offset {offset} is past the end of pixel unpack buffer {name} ({} bytes)", bytes.len())
        })?;
        *pixels = Memory::Client(bytes[start..].to_vec());
        Ok(Some(command))
    }

    /// A viewport or scissor rectangle on the window that reaches past it grows the window to
    /// hold it, as apitrace's retrace does (its `updateDrawable`): a capture records the
    /// window's size when its context was first made current, and an application whose
    /// window was resized later says so only through its viewports.
    fn grow_window(&mut self, x: i32, y: i32, width: u32, height: u32) -> Fallible {
        if !self.window_grows || self.ctx.is_none() || self.bindings.draw_framebuffer != 0 {
            return Ok(());
        }
        let Some((w, h)) = self.window else { return Ok(()) };
        let (right, top) = (x as i64 + width as i64, y as i64 + height as i64);
        if right <= 0 || top <= 0 || (right <= w as i64 && top <= h as i64) {
            return Ok(());
        }
        let size = (size_limit(right.max(w as i64))?, size_limit(top.max(h as i64))?);
        self.emit(Call::ResizeSurface { width: size.0, height: size.1 })?;
        self.window = Some(size);
        Ok(())
    }

    /// The `width × height` texels of `texel_bytes` each that an upload reads from `bytes` under
    /// the unpack state, and the alignment of their rows: `bytes` as given when no row length
    /// or skip is set, else the rows copied out tight (alignment 1).
    pub(super) fn unpacked<'a>(
        &self,
        bytes: &'a [u8],
        (width, height): (u32, u32),
        texel_bytes: usize,
    ) -> Fallible<(Cow<'a, [u8]>, u32)> {
        let b = &self.bindings;
        if b.unpack_row_length == 0 && b.unpack_skip_rows == 0 && b.unpack_skip_pixels == 0 {
            return Ok((Cow::Borrowed(bytes), b.unpack_alignment));
        }
        let row_texels = if b.unpack_row_length > 0 { b.unpack_row_length } else { width };
        if b.unpack_skip_pixels as u64 + width as u64 > row_texels as u64 {
            return Err(format!(
                "{width} texels a row from texel {} of rows {row_texels} long (GL_UNPACK_ROW_LENGTH) overrun the row",
                b.unpack_skip_pixels
            ));
        }
        let align = b.unpack_alignment as u64;
        let stride = (row_texels as u64 * texel_bytes as u64).div_ceil(align) * align;
        let row = width as u64 * texel_bytes as u64;
        let first = b.unpack_skip_rows as u64 * stride + b.unpack_skip_pixels as u64 * texel_bytes as u64;
        let needed = if height == 0 { 0 } else { first + (height as u64 - 1) * stride + row };
        if (bytes.len() as u64) < needed {
            return Err(format!(
                "{} bytes of texels, but {width}×{height} from rows of {row_texels} texels aligned to {align}, \
                 skipping {} rows and {} texels, needs {needed}",
                bytes.len(),
                b.unpack_skip_rows,
                b.unpack_skip_pixels
            ));
        }
        let mut out = Vec::with_capacity((row * height as u64) as usize);
        for y in 0..height as u64 {
            let start = (first + y * stride) as usize;
            out.extend_from_slice(&bytes[start..start + row as usize]);
        }
        Ok((Cow::Owned(out), 1))
    }

    /// `data`, texels of texture `name` stored as `format`, with the texture's swizzle
    /// ([`Texture::swizzle`]) applied.
    ///
    /// # Errors
    /// A swizzle on a texture not stored as RGBA8 bytes.
    pub(super) fn swizzled(&mut self, name: u32, format: TextureFormat, data: Bytes) -> Fallible<Bytes> {
        let swizzle = self.objects()?.textures.get(&name).map_or(SWIZZLE_IDENTITY, |t| t.swizzle);
        if swizzle == SWIZZLE_IDENTITY {
            return Ok(data);
        }
        if format != TextureFormat::Rgba8 {
            return Err(format!(
                "texture {name}: GL_TEXTURE_SWIZZLE_* on a texture stored as {} is not supported (8-bit RGBA, \
                 RGB, RG, red, luminance only)",
                format.name()
            ));
        }
        let mut out = data.to_vec();
        for texel in out.chunks_exact_mut(4) {
            let source = [texel[0], texel[1], texel[2], texel[3], 0, 255];
            for (channel, &from) in texel.iter_mut().zip(&swizzle) {
                *channel = source[from as usize];
            }
        }
        Ok(Bytes::from(out))
    }

    /// Refuses an upload the swizzle is not applied to (compressed, packed, cube and layered
    /// textures) when texture `name` has one.
    pub(super) fn check_unswizzled(&mut self, name: u32) -> Fallible {
        if self.objects()?.textures.get(&name).is_some_and(|t| t.swizzle != SWIZZLE_IDENTITY) {
            return Err(format!(
                "texture {name}: GL_TEXTURE_SWIZZLE_* is supported on 2D textures of 8-bit texels only"
            ));
        }
        Ok(())
    }

    /// Refuses to render or copy into a red/green texture (see [`Texture::red_green`]) or a
    /// swizzled one ([`Texture::swizzle`]).
    fn check_renderable(&mut self, name: u32) -> Fallible {
        if self.objects()?.textures.get(&name).is_some_and(|t| t.swizzle != SWIZZLE_IDENTITY) {
            return Err(format!(
                "texture {name} has a GL_TEXTURE_SWIZZLE_*: the replay samples it, but rendering or copying into \
                 one is not supported"
            ));
        }
        if self.objects()?.textures.get(&name).is_some_and(|t| t.red_green) {
            return Err(format!(
                "texture {name} has only red (and green) channels (R8, RG8): the replay samples those, but rendering \
                 or copying into one is not supported"
            ));
        }
        Ok(())
    }

    pub(super) fn texture_id(&mut self, name: u32) -> Fallible<Option<u32>> {
        Ok(self.objects()?.textures.get(&name).and_then(|t| t.id))
    }

    pub(super) fn update_sampler(&mut self, name: u32) -> Fallible {
        let t = self.objects()?.textures.get(&name).cloned().unwrap_or_default();
        // A GL state the context cannot sample is refused when it is drawn with.
        if let (Some(id), Ok(p)) = (t.id, t.sampler()) {
            self.emit(Call::TexParameters {
                id,
                filter: p.min,
                wrap: p.wrap_s,
                mag_filter: Some(p.mag),
                wrap_t: Some(p.wrap_t),
            })?;
            if t.compare_set {
                self.emit(Call::TexCompare { id, compare: p.compare })?;
            }
            if t.layered.is_some() {
                let wrap = layered::wrap_r(t.wrap_r)?;
                self.emit(Call::TexWrapR { id, wrap })?;
            }
        }
        Ok(())
    }

    fn texels(&self, upload: &Upload, pixels: &Memory, width: u32, height: u32) -> Fallible<Option<Bytes>> {
        match pixels {
            Memory::Null => Ok(None),
            Memory::Client(bytes) => {
                let (bytes, alignment) = self.unpacked(bytes, (width, height), upload.client_bytes)?;
                Ok(Some(Bytes::from(upload.convert(&bytes, width, height, alignment)?)))
            }
            Memory::Offset(_) => Err("texels from a pixel unpack buffer are not supported".into()),
        }
    }

    fn framebuffer_id(&mut self, name: u32) -> Fallible<u32> {
        if name == 0 {
            return Ok(0);
        }
        if let Some(&id) = self.own()?.framebuffers.get(&name) {
            return Ok(id);
        }
        let id = self.fresh_id();
        self.emit(Call::CreateFramebuffer { id })?;
        self.own()?.framebuffers.insert(name, id);
        Ok(id)
    }

    /// The context's framebuffer a `glFramebuffer*` call attaches to.
    pub(super) fn attachment_target(&mut self, target: GlEnum) -> Fallible<u32> {
        let name = match target {
            GL_FRAMEBUFFER | GL_DRAW_FRAMEBUFFER => self.bindings.draw_framebuffer,
            GL_READ_FRAMEBUFFER => self.bindings.read_framebuffer,
            t => return Err(format!("framebuffer target {t:#06x} is not a GL one")),
        };
        if name == 0 {
            return Err("the window's framebuffer takes no attachments".into());
        }
        self.framebuffer_id(name)
    }

    fn query_id(&mut self, name: u32) -> Fallible<u32> {
        self.own()?.queries.get(&name).copied().ok_or_else(|| format!("query {name} does not exist"))
    }
}

/// A window dimension, refused beyond what any surface could be.
fn size_limit(v: i64) -> Fallible<u32> {
    const MAX: i64 = 16384;
    if v > MAX {
        return Err(format!("a viewport or scissor reaching {v} pixels would grow the window past {MAX}"));
    }
    Ok(v as u32)
}

/// `GL_TIME_ELAPSED_EXT`, a timer query's target.
const GL_TIME_ELAPSED: GlEnum = 0x88bf;

/// The name `glUniform*v` sets for element `k` of `count` at a location named `name`.
fn element_name(name: &str, k: usize, count: usize) -> Fallible<String> {
    if count == 1 {
        return Ok(name.to_string());
    }
    if let Some(open) = name.strip_suffix(']').and_then(|n| n.rfind('[').map(|i| (n, i))) {
        let (base, i) = open;
        let first: usize = base[i + 1..].parse().map_err(|_| format!("uniform name {name} has a bad index"))?;
        return Ok(format!("{}[{}]", &base[..i], first + k));
    }
    Ok(format!("{name}[{k}]"))
}

/// The `GL_MAX_VERTEX_ATTRIBS` a recording GPU may have reported: OpenGL ES 3.0's minimum, and
/// what llvmpipe and most GPUs report.
const RECORDED_MAX_VERTEX_ATTRIBS: u32 = 16;

/// The most texture units a recording GPU may have reported (GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS:
/// 192 on llvmpipe); beyond it, a unit is a GL error.
const RECORDED_MAX_TEXTURE_UNITS: u32 = 1024;

fn attrib_slot(index: u32) -> Fallible<usize> {
    if index >= MAX_VERTEX_ATTRIBS {
        return Err(format!("vertex attribute {index} is beyond the context's {MAX_VERTEX_ATTRIBS}"));
    }
    Ok(index as usize)
}

fn size2(a: i32, b: i32) -> Fallible<(u32, u32)> {
    match (u32::try_from(a), u32::try_from(b)) {
        (Ok(a), Ok(b)) => Ok((a, b)),
        _ => Err(format!("{a}, {b}: negative sizes or offsets are GL errors")),
    }
}

/// `GL_PROXY_TEXTURE_2D` (desktop OpenGL).
const GL_PROXY_TEXTURE_2D: GlEnum = 0x8064;

fn check_2d_level0(target: GlEnum, level: i32) -> Fallible {
    if target != GL_TEXTURE_2D {
        return Err(format!("texture target {target:#06x} is not supported (2D only)"));
    }
    if level != 0 {
        return Err(format!("mip level {level}: the context has no mip maps"));
    }
    Ok(())
}

/// The face of a `glStencil*Separate` call (`GL_FRONT_AND_BACK` for the others).
fn stencil_face(face: GlEnum) -> Fallible<Face> {
    match face {
        0x0404 => Ok(Face::Front),
        0x0405 => Ok(Face::Back),
        GL_FRONT_AND_BACK => Ok(Face::FrontAndBack),
        f => Err(format!("stencil face {f:#06x} is not a GL one")),
    }
}

fn qcom_buffers(mask: u32) -> BufferSet {
    // GL_COLOR_BUFFER_BIT0_QCOM etc.: colour bits 0x0000_00ff, depth 0x0000_ff00, stencil
    // 0x00ff_0000.
    BufferSet { color: mask & 0xff != 0, depth: mask & 0xff00 != 0, stencil: mask & 0xff_0000 != 0 }
}

fn draw_mode(mode: GlEnum) -> Fallible<Mode> {
    match mode {
        0x0000 => Ok(Mode::Points),
        0x0001 => Ok(Mode::Lines),
        0x0002 => Ok(Mode::LineLoop),
        0x0003 => Ok(Mode::LineStrip),
        0x0004 => Ok(Mode::Triangles),
        0x0005 => Ok(Mode::TriangleStrip),
        0x0006 => Ok(Mode::TriangleFan),
        m => Err(format!("primitive mode {m:#06x} is not a GLES one")),
    }
}

fn component_type(kind: GlEnum) -> Fallible<ComponentType> {
    Ok(match kind {
        0x1406 => ComponentType::Float,
        0x140b | 0x8d61 => ComponentType::HalfFloat,
        0x1400 => ComponentType::Byte,
        0x1401 => ComponentType::UnsignedByte,
        0x1402 => ComponentType::Short,
        0x1403 => ComponentType::UnsignedShort,
        0x1405 => ComponentType::UnsignedInt,
        0x1404 => ComponentType::Int,
        k => return Err(format!("vertex component type {k:#06x} is not supported")),
    })
}

fn compare_op(func: GlEnum) -> Fallible<CompareOp> {
    Ok(match func {
        0x0200 => CompareOp::Never,
        0x0201 => CompareOp::Less,
        0x0202 => CompareOp::Equal,
        0x0203 => CompareOp::LessOrEqual,
        0x0204 => CompareOp::Greater,
        0x0205 => CompareOp::NotEqual,
        0x0206 => CompareOp::GreaterOrEqual,
        0x0207 => CompareOp::Always,
        f => return Err(format!("comparison {f:#06x} is not a GL one")),
    })
}

fn stencil_op(op: GlEnum) -> Fallible<StencilOp> {
    Ok(match op {
        0x1e00 => StencilOp::Keep,
        0 => StencilOp::Zero,
        0x1e01 => StencilOp::Replace,
        0x1e02 => StencilOp::IncrementAndClamp,
        0x1e03 => StencilOp::DecrementAndClamp,
        0x150a => StencilOp::Invert,
        0x8507 => StencilOp::IncrementAndWrap,
        0x8508 => StencilOp::DecrementAndWrap,
        o => return Err(format!("stencil operation {o:#06x} is not a GL one")),
    })
}

fn blend_factor(f: GlEnum) -> Fallible<BlendFactor> {
    Ok(match f {
        0 => BlendFactor::Zero,
        1 => BlendFactor::One,
        0x0300 => BlendFactor::SrcColor,
        0x0301 => BlendFactor::OneMinusSrcColor,
        0x0302 => BlendFactor::SrcAlpha,
        0x0303 => BlendFactor::OneMinusSrcAlpha,
        0x0304 => BlendFactor::DstAlpha,
        0x0305 => BlendFactor::OneMinusDstAlpha,
        0x0306 => BlendFactor::DstColor,
        0x0307 => BlendFactor::OneMinusDstColor,
        0x0308 => BlendFactor::SrcAlphaSaturate,
        0x8001 => BlendFactor::ConstantColor,
        0x8002 => BlendFactor::OneMinusConstantColor,
        0x8003 => BlendFactor::ConstantAlpha,
        0x8004 => BlendFactor::OneMinusConstantAlpha,
        f => return Err(format!("blend factor {f:#06x} is not a GL one")),
    })
}

fn blend_op(op: GlEnum) -> Fallible<BlendOp> {
    Ok(match op {
        0x8006 => BlendOp::Add,
        0x800a => BlendOp::Subtract,
        0x800b => BlendOp::ReverseSubtract,
        0x8007 => BlendOp::Min,
        0x8008 => BlendOp::Max,
        o => return Err(format!("blend equation {o:#06x} is not a GL one")),
    })
}

pub(super) fn attachment_point(a: GlEnum) -> Fallible<AttachmentPoint> {
    Ok(match a {
        0x8ce0 => AttachmentPoint::Color0,
        0x8ce1 => AttachmentPoint::Color1,
        0x8ce2 => AttachmentPoint::Color2,
        0x8ce3 => AttachmentPoint::Color3,
        0x8d00 => AttachmentPoint::Depth,
        0x8d20 => AttachmentPoint::Stencil,
        0x821a => AttachmentPoint::DepthStencil,
        a => return Err(format!("attachment {a:#06x} is not supported")),
    })
}

/// An attachment of `glInvalidateFramebuffer`; the window's framebuffer names its buffers
/// `GL_COLOR`, `GL_DEPTH`, `GL_STENCIL` (`GL_COLOR_EXT` … for the discard extension).
fn invalidate_point(a: GlEnum, default: bool) -> Fallible<AttachmentPoint> {
    match (a, default) {
        (0x1800, true) => Ok(AttachmentPoint::Color0),
        (0x1801, true) => Ok(AttachmentPoint::Depth),
        (0x1802, true) => Ok(AttachmentPoint::Stencil),
        (a, false) => attachment_point(a),
        (a, true) => Err(format!("attachment {a:#06x} is not one of the window's")),
    }
}

/// The samples a multisampled renderbuffer or render-to-texture gets when the application asks
/// for `samples`: at least as many, and no more than the next count the implementation
/// supports (GL ES 3.0 §4.4.2.1), so 0 is one sample, 3 is 4 and 9 is 16. Above the largest
/// count (16, the context's `GL_MAX_SAMPLES`) GL fails the call, and so does the replay.
fn granted_samples(samples: i32) -> Fallible<u32> {
    let supported = tiler::api::image::SUPPORTED_SAMPLE_COUNTS;
    let asked = samples.max(1) as u32;
    supported.iter().copied().find(|&n| n >= asked).ok_or_else(|| {
        format!("{samples} samples: more than GL_MAX_SAMPLES ({})", supported.iter().max().unwrap_or(&1))
    })
}

fn renderbuffer_format(f: GlEnum) -> Fallible<TextureFormat> {
    Ok(match f {
        // RGBA4 and RGB5_A1 are kept at 8 bits per channel, as llvmpipe keeps them.
        0x8058 | 0x8051 | 0x8056 | 0x8057 => TextureFormat::Rgba8,
        0x8d62 => TextureFormat::Rgb565,
        0x8c43 => TextureFormat::Srgb8Alpha8,
        0x881a => TextureFormat::Rgba16f,
        0x8814 => TextureFormat::Rgba32f,
        0x822e => TextureFormat::R32f,
        0x81a5 => TextureFormat::Depth16,
        0x81a6 => TextureFormat::Depth24,
        0x8cac => TextureFormat::Depth32f,
        0x88f0 => TextureFormat::Depth24Stencil8,
        0x8d48 => TextureFormat::Stencil8,
        f if texels::integer_internal_format(f).is_some() => {
            texels::integer_storage(texels::integer_internal_format(f).expect("matched"))
        }
        f => return Err(format!("internal format {f:#06x} is not supported")),
    })
}

/// The function name of a command the replay refuses (for messages).
fn command_name(command: &Command) -> String {
    let debug = format!("{command:?}");
    debug.split([' ', '{', '(']).next().unwrap_or("?").to_string()
}

/// The GLSL side: programs from source, attribute bindings, uniform values.
mod glsl {
    use super::{Fallible, GlUniform};
    use crate::call::{Call, GlslSource, ProgramSource, UniformValue};

    pub(super) fn create_program(id: u32, vertex: String, fragment: String) -> Fallible<Call> {
        Ok(Call::CreateProgram { id, program: ProgramSource::Glsl(GlslSource { vertex, fragment }) })
    }

    pub(super) fn bind_attrib_location(program: u32, index: u32, name: String) -> Fallible<Call> {
        Ok(Call::BindAttribLocation { program, index, name })
    }

    /// One value per array element.
    pub(super) fn uniform_values(value: &GlUniform) -> Fallible<Vec<UniformValue>> {
        let unsupported = || format!("uniform {value:?} is not of a type the context takes");
        let per = |n: usize, len: usize| if n == 0 || !len.is_multiple_of(n) { Err(unsupported()) } else { Ok(n) };
        Ok(match value {
            GlUniform::Float { components, values } => values
                .chunks_exact(per(usize::from(*components), values.len())?)
                .map(|v| match *v {
                    [x] => Ok(UniformValue::Float(x)),
                    [x, y] => Ok(UniformValue::Vec2([x, y])),
                    [x, y, z] => Ok(UniformValue::Vec3([x, y, z])),
                    [x, y, z, w] => Ok(UniformValue::Vec4([x, y, z, w])),
                    _ => Err(unsupported()),
                })
                .collect::<Fallible<_>>()?,
            GlUniform::Int { components, values } => values
                .chunks_exact(per(usize::from(*components), values.len())?)
                .map(|v| match *v {
                    [x] => Ok(UniformValue::Int(x)),
                    [x, y] => Ok(UniformValue::IVec2([x, y])),
                    [x, y, z] => Ok(UniformValue::IVec3([x, y, z])),
                    [x, y, z, w] => Ok(UniformValue::IVec4([x, y, z, w])),
                    _ => Err(unsupported()),
                })
                .collect::<Fallible<_>>()?,
            GlUniform::UInt { components, values } => values
                .chunks_exact(per(usize::from(*components), values.len())?)
                .map(|v| match *v {
                    [x] => Ok(UniformValue::UInt(x)),
                    [x, y] => Ok(UniformValue::UVec2([x, y])),
                    [x, y, z] => Ok(UniformValue::UVec3([x, y, z])),
                    [x, y, z, w] => Ok(UniformValue::UVec4([x, y, z, w])),
                    _ => Err(unsupported()),
                })
                .collect::<Fallible<_>>()?,
            GlUniform::Matrix { columns, rows, transpose, values }
                if (2..=4).contains(columns) && (2..=4).contains(rows) =>
            {
                let (n, rows) = (usize::from(*columns), usize::from(*rows));
                values
                    .chunks_exact(per(n * rows, values.len())?)
                    .map(|m| {
                        // Column-major; a transposed matrix (GLES 3.0: rows of `n`) is turned back.
                        let at = |c: usize, r: usize| if *transpose { m[r * n + c] } else { m[c * rows + r] };
                        let v: Vec<f32> = (0..n).flat_map(|c| (0..rows).map(move |r| at(c, r))).collect();
                        fn array<const N: usize>(v: Vec<f32>) -> [f32; N] {
                            v.try_into().expect("the shape's values")
                        }
                        match (n, rows) {
                            (2, 2) => UniformValue::Mat2(array(v)),
                            (3, 3) => UniformValue::Mat3(array(v)),
                            (4, 4) => UniformValue::Mat4(array(v)),
                            (2, 3) => UniformValue::Mat2x3(array(v)),
                            (2, 4) => UniformValue::Mat2x4(array(v)),
                            (3, 2) => UniformValue::Mat3x2(array(v)),
                            (3, 4) => UniformValue::Mat3x4(array(v)),
                            (4, 2) => UniformValue::Mat4x2(array(v)),
                            _ => UniformValue::Mat4x3(array(v)),
                        }
                    })
                    .collect()
            }
            _ => return Err(unsupported()),
        })
    }
}
