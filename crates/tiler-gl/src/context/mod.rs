//! The GL-style context: immediate-mode calls in, explicit render passes out.
//!
//! Nothing is rendered when a draw is called. The context keeps one *open render pass* — the
//! pass of the bound draw framebuffer — and gathers its draws as frame data: `draw.rs`
//! translates each GL draw and its state into tiler's terms, `pass.rs` decides the pass's
//! load and store ops exactly as the inference table of `DESIGN.md` says, and `submit.rs`
//! renders it on the device when it ends (the framebuffer is unbound, the frame is swapped,
//! or something forces a flush). `frames.rs` models the frames in flight behind the CPU.
//!
//! The context owns its [`Device`]; there are no globals. Every call goes through
//! [`Context::call`], which checks it, applies it, and records it when recording is on.

mod contexts;
mod cube;
mod draw;
mod encoded;
mod explicit;
mod feedback;
mod frames;
mod glsl;
mod instancing;
mod layered;
mod pass;
mod sampler_objects;
mod submit;
mod targets;
mod uniform_blocks;
mod vertex_array;

use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, HashMap};
use std::sync::Arc;
use tiler::{
    Backend, BlendFactor, BlendOp, BufferId, CompareOp, Device, DeviceConfig, ImageDesc, ImageId, StencilFaceState,
};

use crate::bytes::Bytes;
use crate::call::{
    AttachmentPoint, BufferSet, Call, Capability, ComponentType, Face, Filter, FramebufferTarget, Output, ProgramKind,
    ProgramSource, SwapBehavior, TextureFormat, UniformValue, Winding, Wrap,
};
use crate::program::{SamplerState, Uniforms};
use crate::report::{CallRef, FrameRecord, PassRecord, Report, StartCause};

pub(crate) use pass::OpenPass;

/// The most texture units.
pub const MAX_TEXTURE_UNITS: u32 = 8;
/// The most vertex attributes.
pub const MAX_VERTEX_ATTRIBS: u32 = 8;
/// The most colour attachments a draw writes (`glDrawBuffers`), as framebuffers have.
pub const MAX_DRAW_BUFFERS: u32 = 4;
/// The most uniform buffer bindings (GL ES 3.0's minimum `GL_MAX_UNIFORM_BUFFER_BINDINGS`).
pub const MAX_UNIFORM_BUFFER_BINDINGS: u32 = 24;
/// The largest number of frames in flight the model accepts.
pub const MAX_FRAMES_IN_FLIGHT: u32 = 16;

/// How a context is made: the window surface, the device, and the driver's model. This is
/// also the `config` object of a trace.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContextConfig {
    /// Window surface size in pixels.
    pub width: u32,
    pub height: u32,
    /// The window's colour buffer.
    #[serde(default = "default_color_format")]
    pub color_format: TextureFormat,
    /// The window's depth-stencil buffer; `null` for none.
    #[serde(default = "default_depth_stencil_format")]
    pub depth_stencil_format: Option<TextureFormat>,
    /// Samples per pixel of the window surface.
    #[serde(default = "default_one")]
    pub samples: u32,
    /// `EGL_SWAP_BEHAVIOR` at the start.
    #[serde(default)]
    pub swap_behavior: SwapBehavior,
    /// Frames between submission and results: 3 models seed 000 §23.6's CPU, geometry and
    /// fragment stages of a tiler, 2 an immediate-mode GPU's CPU and GPU; 1 is a GPU that
    /// finishes a frame before the next begins. Left out (`None`), it follows the backend
    /// (`Backend::frames_in_flight`); [`Context::new`] fills it in.
    #[serde(default)]
    pub frames_in_flight: Option<u32>,
    #[serde(default = "default_tile")]
    pub tile_width: u32,
    #[serde(default = "default_tile")]
    pub tile_height: u32,
    /// Frame-data bytes a pass may gather before an incremental render.
    #[serde(default = "default_budget")]
    pub frame_data_budget: u64,
    /// Count the display's scan-out of the window at each swap (`display`).
    #[serde(default = "default_true")]
    pub display: bool,
    /// Count a window-system compositor's read and write of the window at each swap.
    #[serde(default)]
    pub composition: bool,
    /// Which backend renders the passes.
    #[serde(default)]
    pub backend: Backend,
    /// Worker threads (0 = one per core). Results do not depend on it.
    #[serde(default)]
    pub threads: usize,
    /// The most bytes of images and buffers the context may allocate: a trace cannot make it
    /// allocate more.
    #[serde(default = "default_memory_limit")]
    pub memory_limit: u64,
    /// The device model beyond the fields above (tile memory, early-Z, vertex shading,
    /// caches, energy, transaction elimination, overdraw map), from a device preset; `None`:
    /// tiler's defaults. Set with [`ContextConfig::on_device`]; not part of a trace.
    #[serde(skip)]
    pub device: Option<DeviceConfig>,
    /// Keep the core's whole report of each pass (per-tile figures, overdraw map) in its
    /// [`PassRecord::core`](crate::report::PassRecord::core), for heat maps and the shared
    /// report; off, a long run keeps only the totals. Not part of a trace.
    #[serde(skip)]
    pub keep_pass_reports: bool,
    /// Record a digest of the window's picture at each swap in the frame's
    /// [`FrameRecord::presented_digest`](crate::report::FrameRecord::presented_digest), so
    /// that two runs can be checked to present the same pictures frame by frame
    /// (`tiler analyze --devices`, `--what-if`). Not part of a trace.
    #[serde(skip)]
    pub digest_presented: bool,
}

fn default_color_format() -> TextureFormat {
    TextureFormat::Rgba8
}
fn default_depth_stencil_format() -> Option<TextureFormat> {
    Some(TextureFormat::Depth24Stencil8)
}
fn default_one() -> u32 {
    1
}
fn default_tile() -> u32 {
    32
}
fn default_budget() -> u64 {
    DeviceConfig::default().frame_data_budget
}
fn default_true() -> bool {
    true
}
fn default_memory_limit() -> u64 {
    1 << 31
}

impl ContextConfig {
    /// A `width × height` RGBA8 window with a packed depth-stencil buffer and the defaults.
    pub fn new(width: u32, height: u32) -> ContextConfig {
        ContextConfig {
            width,
            height,
            color_format: default_color_format(),
            depth_stencil_format: default_depth_stencil_format(),
            samples: 1,
            swap_behavior: SwapBehavior::Destroyed,
            frames_in_flight: None,
            tile_width: default_tile(),
            tile_height: default_tile(),
            frame_data_budget: default_budget(),
            display: true,
            composition: false,
            backend: Backend::Tbr,
            threads: 0,
            memory_limit: default_memory_limit(),
            device: None,
            keep_pass_reports: false,
            digest_presented: false,
        }
    }

    /// This configuration on another device: the window, swap behaviour and frames in flight
    /// stay; the backend, tile size, frame-data budget, display model and the rest of the
    /// device model are `device`'s (a device preset's, `tiler analyze --device`).
    pub fn on_device(self, device: &DeviceConfig) -> ContextConfig {
        ContextConfig {
            backend: device.backend,
            tile_width: device.tile_width,
            tile_height: device.tile_height,
            frame_data_budget: device.frame_data_budget,
            display: device.display.scan_out,
            composition: device.display.composition,
            device: Some(device.clone()),
            ..self
        }
    }

    /// The core device this configuration renders on.
    pub fn device_config(&self) -> DeviceConfig {
        DeviceConfig {
            backend: self.backend,
            tile_width: self.tile_width,
            tile_height: self.tile_height,
            threads: self.threads,
            frame_data_budget: self.frame_data_budget,
            display: tiler::DisplayModel { scan_out: self.display, composition: self.composition },
            ..self.device.clone().unwrap_or_default()
        }
    }
}

/// An error: the call that caused it and what was wrong.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("frame {frame}, call {call} ({name}): {message}")]
pub struct Error {
    pub frame: u32,
    pub call: u32,
    /// The call's name as a trace spells it.
    pub name: &'static str,
    pub message: String,
}

type Fallible<T = ()> = std::result::Result<T, String>;

pub(crate) struct BufferObject {
    pub storage: BufferId,
    pub size: u64,
    /// The last frame a draw read it.
    pub last_use: Option<u32>,
}

pub(crate) struct TextureObject {
    pub image: ImageId,
    pub format: TextureFormat,
    pub sampler: SamplerState,
    /// It has a complete mip chain: `generate_mipmap` was called since the storage was made,
    /// or every level down to 1×1 was given (`levels`).
    pub mipmaps: bool,
    /// Levels 1, 2, … given by `tex_image_level` (RGBA8, rows top to bottom), `None` where not
    /// given yet.
    pub levels: Vec<Option<Arc<Vec<u8>>>>,
    /// The format `encoded_tex_image` uploaded it in (decoded into the image, which is RGBA8),
    /// the one its samples are counted in; `None` for storage of the image's own format.
    pub encoded: Option<crate::call::EncodedFormat>,
    /// A 16-bit normalised upload's level 0 as stored (rows top to bottom), which the image's
    /// RGBA8 rounds: sampled at 16 bits while the image still holds what it rounds to
    /// (`encoded.rs`).
    pub unorm16: Option<Arc<Vec<u8>>>,
}

impl TextureObject {
    /// The given levels 1, 2, … when they are the whole chain of a `width × height` level 0.
    pub fn given_chain(&self, width: u32, height: u32) -> Option<Vec<Arc<Vec<u8>>>> {
        let wanted = mip_levels(width, height) as usize - 1;
        if wanted == 0 || self.levels.len() != wanted {
            return None;
        }
        self.levels.iter().cloned().collect()
    }
}

/// Levels of a full mip chain of a `width × height` level 0, level 0 included:
/// `⌊log2(max(width, height))⌋ + 1`.
fn mip_levels(width: u32, height: u32) -> u32 {
    32 - width.max(height).max(1).leading_zeros()
}

pub(crate) struct RenderbufferObject {
    pub image: ImageId,
}

/// What a framebuffer attachment point refers to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum AttachmentRef {
    Texture(u32),
    Renderbuffer(u32),
    /// An image of the window surface (framebuffer 0).
    Surface(ImageId),
    /// Rendered in the multisampled image `samples`, resolved in the tile into the texture
    /// (EXT_multisampled_render_to_texture).
    MultisampleTexture {
        texture: u32,
        samples: ImageId,
    },
    /// The window's multisampled colour, resolved in the tile into the presented image.
    SurfaceMultisample {
        samples: ImageId,
        resolve: ImageId,
    },
}

impl AttachmentRef {
    /// The texture it renders into, if any.
    pub fn texture(self) -> Option<u32> {
        match self {
            AttachmentRef::Texture(t) | AttachmentRef::MultisampleTexture { texture: t, .. } => Some(t),
            _ => None,
        }
    }
}

#[derive(Default)]
pub(crate) struct FramebufferObject {
    pub color: [Option<AttachmentRef>; 4],
    pub depth: Option<AttachmentRef>,
    pub stencil: Option<AttachmentRef>,
    /// `draw_buffers`: draws write colour attachments `0..n` (`None`: GL's default, 1; 0:
    /// none).
    pub draw_buffers: Option<u32>,
}

pub(crate) enum ProgramObject {
    Builtin { kind: ProgramKind, uniforms: Uniforms },
    Glsl(glsl::GlslProgram),
}

#[derive(Default)]
pub(crate) struct QueryObject {
    pub ended: bool,
    pub samples: u64,
    /// Its draws still in the open pass.
    pub pending_draws: u32,
    /// The last frame whose work it depends on (its `end_query`, or a pass with its draws).
    pub last_frame: u32,
}

/// What the driver knows about an image.
pub(crate) struct ImageInfo {
    pub desc: ImageDesc,
    pub gl_format: TextureFormat,
    /// Whether the contents are defined, per aspect: `[colour or depth, stencil]`. Undefined
    /// contents (new storage, invalidated, after a destroying swap) are never loaded.
    pub defined: [bool; 2],
    /// The last frame that wrote it (a store, an upload).
    pub last_write: Option<u32>,
    /// The last frame a draw sampled it.
    pub last_use: Option<u32>,
}

/// Where a vertex attribute reads from.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum AttribSource {
    Buffer { buffer: u32, offset: u64 },
    Client { data: Bytes },
}

/// One attribute of a vertex array object.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Attrib {
    pub enabled: bool,
    /// Where, how many components of what type, normalized, the stride, and whether the
    /// integers are kept (`glVertexAttribIPointer`).
    pub source: Option<(AttribSource, u32, ComponentType, bool, u32, bool)>,
    /// `glVertexAttribDivisor`: 0 per vertex, `n` once every `n` instances.
    pub divisor: u32,
}

impl Attrib {
    const DEFAULT: Attrib = Attrib { enabled: false, source: None, divisor: 0 };
}

/// A context's fixed-function and binding state at some point ([`Context::saved_state`]),
/// for [`Call::RestoreState`].
#[derive(Clone, Debug, PartialEq)]
pub struct SavedState {
    /// The context (`make_current`) whose state it is.
    context: u32,
    state: Box<GlState>,
    /// The bound draw and read framebuffers; `None`: left as they are.
    framebuffers: Option<(u32, u32)>,
}

impl SavedState {
    /// The same state without the framebuffer bindings: restoring it leaves them as they are.
    pub fn without_framebuffers(self) -> SavedState {
        SavedState { framebuffers: None, ..self }
    }
}

/// The fixed-function and binding state, as GL's context holds it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct GlState {
    pub viewport: [i64; 4],
    pub depth_range: [f32; 2],
    pub scissor: [i64; 4],
    pub scissor_test: bool,
    pub depth_test: bool,
    pub stencil_test: bool,
    pub blend: bool,
    pub cull_face: bool,
    pub color_mask: [bool; 4],
    pub depth_mask: bool,
    pub depth_func: CompareOp,
    pub polygon_offset_fill: bool,
    /// `GL_PRIMITIVE_RESTART_FIXED_INDEX` (see `draw`).
    pub primitive_restart: bool,
    /// `GL_RASTERIZER_DISCARD` (`feedback.rs`): draws and clears touch no pixel.
    pub rasterizer_discard: bool,
    /// `glPolygonOffset`'s `(factor, units)`.
    pub polygon_offset: (f32, f32),
    pub line_width: f32,
    /// Stencil function, operations and write mask of front- and back-facing primitives.
    pub stencil: [StencilFaceState; 2],
    pub blend_func: [BlendFactor; 4],
    pub blend_equation: [BlendOp; 2],
    pub blend_color: [f32; 4],
    pub cull: Face,
    pub front: Winding,
    pub clear_color: [f32; 4],
    pub clear_depth: f32,
    pub clear_stencil: u8,
    /// The bound vertex array object's attributes and index buffer (`vertex_array.rs`).
    pub attribs: Vec<Attrib>,
    pub index_buffer: u32,
    /// The bound vertex array object (0: the default one).
    pub vertex_array: u32,
    /// Each attribute's current generic value (`glVertexAttrib4f`), read when disabled by
    /// GLSL programs; context state, not a vertex array's.
    pub generic: Vec<[f32; 4]>,
    /// Sampler objects' state per texture unit (`sampler_objects.rs`).
    pub unit_samplers: [Option<SamplerState>; MAX_TEXTURE_UNITS as usize],
    /// The `GL_TEXTURE_WRAP_R` of the sampler object on each unit (3-D textures read it).
    pub unit_wrap_r: [Wrap; MAX_TEXTURE_UNITS as usize],
    /// Uniform buffer bindings (`uniform_blocks.rs`).
    pub uniform_buffers: Vec<Option<uniform_blocks::UniformBufferBinding>>,
    pub textures: [u32; MAX_TEXTURE_UNITS as usize],
    /// Each unit's cube texture (`bind_cube_texture`), read by `samplerCube` uniforms.
    pub cube_textures: [u32; MAX_TEXTURE_UNITS as usize],
    /// Each unit's 2-D array and 3-D textures (`bind_layered_texture`, by
    /// `LayeredTarget::index`), read by `sampler2DArray` and `sampler3D` uniforms.
    pub layered_textures: [[u32; 2]; MAX_TEXTURE_UNITS as usize],
    pub program: u32,
}

impl GlState {
    fn new(width: u32, height: u32) -> GlState {
        let full = [0, 0, width as i64, height as i64];
        GlState {
            viewport: full,
            depth_range: [0.0, 1.0],
            scissor: full,
            scissor_test: false,
            depth_test: false,
            stencil_test: false,
            blend: false,
            cull_face: false,
            color_mask: [true; 4],
            depth_mask: true,
            depth_func: CompareOp::Less,
            polygon_offset_fill: false,
            primitive_restart: false,
            rasterizer_discard: false,
            polygon_offset: (0.0, 0.0),
            line_width: 1.0,
            stencil: [StencilFaceState::KEEP; 2],
            blend_func: [BlendFactor::One, BlendFactor::Zero, BlendFactor::One, BlendFactor::Zero],
            blend_equation: [BlendOp::Add, BlendOp::Add],
            blend_color: [0.0; 4],
            cull: Face::Back,
            front: Winding::Ccw,
            clear_color: [0.0; 4],
            clear_depth: 1.0,
            clear_stencil: 0,
            attribs: vec![Attrib::DEFAULT; MAX_VERTEX_ATTRIBS as usize],
            index_buffer: 0,
            vertex_array: 0,
            generic: vec![[0.0, 0.0, 0.0, 1.0]; MAX_VERTEX_ATTRIBS as usize],
            uniform_buffers: vec![None; MAX_UNIFORM_BUFFER_BINDINGS as usize],
            unit_samplers: [None; MAX_TEXTURE_UNITS as usize],
            unit_wrap_r: [Wrap::Repeat; MAX_TEXTURE_UNITS as usize],
            textures: [0; MAX_TEXTURE_UNITS as usize],
            cube_textures: [0; MAX_TEXTURE_UNITS as usize],
            layered_textures: [[0; 2]; MAX_TEXTURE_UNITS as usize],
            program: 0,
        }
    }
}

/// An active `start_tiling` region.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Tiling {
    /// tiler coordinates.
    pub region: tiler::Rect,
    pub preserve: BufferSet,
    /// Whether the first pass of the region has started (the preserve mask applies to it).
    pub started: bool,
}

/// The last store of an aspect of an image, until something reads it.
#[derive(Clone, Debug)]
pub(crate) struct PendingStore {
    pub pass: u32,
    pub frame: u32,
    pub bytes: u64,
    pub consumed: bool,
}

/// A GL-style context over a tiler device.
pub struct Context {
    pub(crate) device: Device,
    pub(crate) config: ContextConfig,
    pub(crate) buffers: BTreeMap<u32, BufferObject>,
    pub(crate) textures: BTreeMap<u32, TextureObject>,
    pub(crate) cubes: BTreeMap<u32, cube::CubeObject>,
    /// 2-D array and 3-D textures (`layered.rs`).
    pub(crate) layered: BTreeMap<u32, layered::LayeredObject>,
    pub(crate) renderbuffers: BTreeMap<u32, RenderbufferObject>,
    pub(crate) framebuffers: BTreeMap<u32, FramebufferObject>,
    pub(crate) programs: BTreeMap<u32, ProgramObject>,
    /// The vertex array objects other than the bound one (`vertex_array.rs`).
    pub(crate) vertex_arrays: BTreeMap<u32, vertex_array::VertexArray>,
    /// The program in use, deleted: it goes when another is used.
    deleted_program: Option<u32>,
    pub(crate) queries: BTreeMap<u32, QueryObject>,
    /// Fences (`fence_sync`): the frame they were put in, and the number of passes rendered
    /// then when the open pass held commands before them (that pass must render for them).
    pub(crate) fences: BTreeMap<u32, (u32, Option<u32>)>,
    pub(crate) images: HashMap<ImageId, ImageInfo>,
    buffer_pool: HashMap<u64, Vec<BufferId>>,
    image_pool: HashMap<ImageDesc, Vec<ImageId>>,
    /// Bytes of images, buffers and cube textures' texels, against `memory_limit`.
    allocated: u64,
    pub(crate) state: GlState,
    pub(crate) draw_framebuffer: u32,
    pub(crate) read_framebuffer: u32,
    pub(crate) pass: Option<OpenPass>,
    /// Why the next pass will start.
    pub(crate) next_start: (StartCause, CallRef),
    pub(crate) tiling: Option<Tiling>,
    pub(crate) active_query: Option<u32>,
    /// Transform feedback bindings and whether it is active (`feedback.rs`).
    pub(crate) feedback: feedback::FeedbackState,
    /// The current context (`contexts.rs`; 0, made with the context, until `make_current`).
    current_context: u32,
    /// The GL state of the contexts that are not current.
    other_contexts: BTreeMap<u32, contexts::ContextState>,
    pub(crate) swap_behavior: SwapBehavior,
    pub(crate) surface_color: ImageId,
    pub(crate) surface_depth_stencil: Option<ImageId>,
    pub(crate) frame: FrameRecord,
    pub(crate) frames: Vec<FrameRecord>,
    pub(crate) here: CallRef,
    pub(crate) passes_rendered: u32,
    /// The frame of the last pass rendered.
    pub(crate) last_submit_frame: Option<u32>,
    pub(crate) stores: HashMap<(ImageId, crate::report::Slot), PendingStore>,
    recording: Option<Vec<Vec<Call>>>,
    /// RGBA8 textures built for earlier submissions, kept while their image's texels are
    /// unchanged (`submit.rs`, `Context::program_texture`).
    pub(crate) built_textures: std::sync::Mutex<HashMap<ImageId, submit::BuiltTexture>>,
    /// Depth snapshots of submitted passes, whose buffers later snapshots fill again once
    /// nothing holds them (`Context::snapshot`): a shadow map read back each frame reuses its
    /// buffer instead of writing fresh pages (7.7 MB a frame for shadow.trace's 1600×1200).
    pub(crate) retired_depths: std::sync::Mutex<Vec<Arc<crate::program::TextureSnapshot>>>,
}

impl Context {
    /// Makes a context with its window surface.
    ///
    /// # Errors
    /// A configuration the device refuses (tile size, budget, surface size or samples), a
    /// surface format of the wrong kind, or `frames_in_flight` outside `1..=16`.
    pub fn new(config: ContextConfig) -> Result<Context, String> {
        let frames_in_flight = config.frames_in_flight.unwrap_or(config.backend.frames_in_flight());
        if !(1..=MAX_FRAMES_IN_FLIGHT).contains(&frames_in_flight) {
            return Err(format!("frames_in_flight {frames_in_flight} must be 1 to {MAX_FRAMES_IN_FLIGHT}"));
        }
        let config = ContextConfig { frames_in_flight: Some(frames_in_flight), ..config };
        if !config.color_format.is_color() {
            return Err(format!("color_format {} is not a colour format", config.color_format.name()));
        }
        if let Some(ds) = config.depth_stencil_format
            && ds.is_color()
        {
            return Err(format!("depth_stencil_format {} is not a depth or stencil format", ds.name()));
        }
        let mut device = Device::new(config.device_config()).map_err(|e| e.to_string())?;
        let (w, h, samples) = (config.width, config.height, config.samples);
        let mut images = HashMap::new();
        let mut allocated = 0;
        let mut surface_image = |format: TextureFormat, samples: u32| -> Fallible<ImageId> {
            let desc = ImageDesc::new(w, h, format.format()).with_samples(samples);
            desc.validate().map_err(|e| format!("window surface: {e}"))?;
            allocated += desc.size_bytes();
            if allocated > config.memory_limit {
                return Err(format!(
                    "the window surface needs more than the memory limit of {} bytes",
                    config.memory_limit
                ));
            }
            let image = device.create_image(desc).map_err(|e| e.to_string())?;
            images.insert(
                image,
                ImageInfo { desc, gl_format: format, defined: [false; 2], last_write: None, last_use: None },
            );
            Ok(image)
        };
        let surface_depth_stencil = config.depth_stencil_format.map(|f| surface_image(f, samples)).transpose()?;
        let mut fb = FramebufferObject::default();
        let surface_color = if samples > 1 {
            // A multisampled window: the samples live in the tile and are resolved into the
            // single-sample image that is presented.
            let msaa = surface_image(config.color_format, samples)?;
            let resolve = surface_image(config.color_format, 1)?;
            fb.color[0] = Some(AttachmentRef::SurfaceMultisample { samples: msaa, resolve });
            resolve
        } else {
            let image = surface_image(config.color_format, 1)?;
            fb.color[0] = Some(AttachmentRef::Surface(image));
            image
        };
        if let (Some(image), Some(format)) = (surface_depth_stencil, config.depth_stencil_format) {
            let r = Some(AttachmentRef::Surface(image));
            if format.has_depth() {
                fb.depth = r;
            }
            if format.has_stencil() {
                fb.stencil = r;
            }
        }
        let mut framebuffers = BTreeMap::new();
        framebuffers.insert(0, fb);
        Ok(Context {
            device,
            buffers: BTreeMap::new(),
            textures: BTreeMap::new(),
            cubes: BTreeMap::new(),
            layered: BTreeMap::new(),
            renderbuffers: BTreeMap::new(),
            framebuffers,
            programs: BTreeMap::new(),
            vertex_arrays: BTreeMap::new(),
            deleted_program: None,
            queries: BTreeMap::new(),
            fences: BTreeMap::new(),
            images,
            buffer_pool: HashMap::new(),
            image_pool: HashMap::new(),
            allocated,
            state: GlState::new(config.width, config.height),
            draw_framebuffer: 0,
            read_framebuffer: 0,
            pass: None,
            next_start: (StartCause::Bind, CallRef::default()),
            tiling: None,
            active_query: None,
            feedback: feedback::FeedbackState::default(),
            current_context: 0,
            other_contexts: BTreeMap::new(),
            swap_behavior: config.swap_behavior,
            surface_color,
            surface_depth_stencil,
            frame: FrameRecord { latency_frames: frames_in_flight, ..FrameRecord::default() },
            frames: Vec::new(),
            here: CallRef::default(),
            passes_rendered: 0,
            last_submit_frame: None,
            stores: HashMap::new(),
            recording: None,
            built_textures: std::sync::Mutex::new(HashMap::new()),
            retired_depths: std::sync::Mutex::new(Vec::new()),
            config,
        })
    }

    /// A context that records every call it is given, for [`Context::recording`].
    pub fn new_recording(config: ContextConfig) -> Result<Context, String> {
        let mut ctx = Context::new(config)?;
        ctx.recording = Some(vec![Vec::new()]);
        Ok(ctx)
    }

    pub fn config(&self) -> &ContextConfig {
        &self.config
    }

    pub fn device(&self) -> &Device {
        &self.device
    }

    /// The window's colour image.
    pub fn surface_color(&self) -> ImageId {
        self.surface_color
    }

    /// The window's colour buffer as RGBA8, rows top to bottom (tiler's order).
    pub fn surface_rgba8(&self) -> Vec<u8> {
        self.device.read_rgba8(self.surface_color).unwrap_or_default()
    }

    /// The image a texture currently stores its texels in.
    pub fn texture_image(&self, texture: u32) -> Option<ImageId> {
        self.textures.get(&texture).map(|t| t.image)
    }

    /// The width and height of a 2-D texture's level 0.
    pub fn texture_size(&self, texture: u32) -> Option<(u32, u32)> {
        let t = self.textures.get(&texture)?;
        self.images.get(&t.image).map(|image| (image.desc.width, image.desc.height))
    }

    /// Frames finished so far (each ended by a swap).
    pub fn frames(&self) -> &[FrameRecord] {
        &self.frames
    }

    /// The frame being built.
    pub fn current_frame(&self) -> &FrameRecord {
        &self.frame
    }

    /// Every pass rendered so far, in order, finished frames then the current one.
    pub fn passes(&self) -> impl Iterator<Item = &PassRecord> {
        self.frames.iter().chain(std::iter::once(&self.frame)).flat_map(|f| f.passes.iter())
    }

    /// The calls recorded so far, one list per frame (the last one is the frame being built).
    pub fn recorded_frames(&self) -> Option<&[Vec<Call>]> {
        self.recording.as_deref()
    }

    /// Renders whatever is still pending, closes the frame being built (if it did anything),
    /// and returns everything the context did with the advisor's findings. The frame records
    /// move into the report (a run's records, with the core's pass reports when
    /// [`ContextConfig::keep_pass_reports`], are held once, not copied): [`Context::frames`]
    /// is empty afterwards.
    ///
    /// # Errors
    /// A pending pass that fails to render.
    pub fn end(&mut self) -> Result<Report, Error> {
        let here = self.here;
        self.end_run().map_err(|message| Error { frame: here.frame, call: here.call, name: "end", message })?;
        Ok(Report::new(self.config.clone(), std::mem::take(&mut self.frames)))
    }

    /// Notes that the calls from here on come from call `call` of a capture (until the next
    /// note), so the report names the capture's call beside its own numbers (see
    /// [`CallRef::capture_call`]).
    pub fn set_capture_call(&mut self, call: u64) {
        self.here.capture_call = Some(call);
        // A pass of the new frame starts at its first call, which is this one.
        if self.next_start.1 == self.here {
            self.next_start.1.capture_call = Some(call);
        }
    }

    /// Executes one call.
    ///
    /// # Errors
    /// Anything GL would flag (unknown objects, incomplete framebuffers, out-of-range
    /// draws, …) and anything tiler does not support, naming the frame and the call. The
    /// context stays usable: a failed call changes nothing, except that a render pass that
    /// fails to render is dropped.
    pub fn call(&mut self, call: Call) -> Result<Output, Error> {
        let name = call.name();
        let here = self.here;
        let recorded = self.recording.is_some().then(|| call.clone());
        let result = self.execute(call);
        if let (Ok(_), Some(call)) = (&result, recorded)
            && let Some(frames) = &mut self.recording
        {
            frames.last_mut().expect("a frame").push(call);
            if name == "swap_buffers" {
                frames.push(Vec::new());
            }
        }
        // A failed call changes nothing and is not recorded, so it takes no index either: a
        // recording replays with the same call numbers.
        if name != "swap_buffers" && result.is_ok() {
            self.here.call += 1;
            self.frame.calls = self.here.call;
        }
        result.map_err(|message| Error { frame: here.frame, call: here.call, name, message })
    }

    fn execute(&mut self, call: Call) -> Fallible<Output> {
        use Call::*;
        match call {
            CreateBuffer { id, data } => self.create_buffer_object(id, data)?,
            BufferData { id, data } => self.buffer_data(id, data)?,
            BufferSubData { id, offset, data } => self.buffer_sub_data(id, offset, data)?,
            DeleteBuffer { id } => self.delete_buffer(id)?,
            CopyBufferSubData { src, dst, src_offset, dst_offset, size } => {
                self.copy_buffer_sub_data(src, dst, src_offset, dst_offset, size)?;
            }
            CreateTexture { id, width, height, format, data, transient } => {
                if id == 0
                    || self.textures.contains_key(&id)
                    || self.cubes.contains_key(&id)
                    || self.layered.contains_key(&id)
                {
                    return Err(name_taken("texture", id));
                }
                if transient && data.is_some() {
                    return Err(format!("texture {id} is transient (it has no memory), so it cannot be given data"));
                }
                self.texture_storage(id, width, height, format, data, transient)?;
            }
            TexImage { id, width, height, format, data } => {
                self.texture(id)?;
                self.texture_storage(id, width, height, format, data, false)?;
            }
            TexSubImage { id, x, y, width, height, data } => {
                if let Some(format) = self.texture(id)?.encoded {
                    return Err(format!(
                        "texture {id} is stored as {format:?}: its texels come by encoded_tex_sub_image"
                    ));
                }
                self.tex_sub_image(id, x, y, width, height, data)?
            }
            CubeTexImage { id, face, level, size, format, data } => {
                self.cube_tex_image(id, face, level, size, format, data)?;
            }
            CubeTexSubImage { id, face, x, y, width, height, data } => {
                self.cube_tex_sub_image(id, face, x, y, width, height, data)?;
            }
            LayeredTexImage { id, target, width, height, depth, format, data } => {
                self.layered_tex_image(id, target, (width, height, depth), format, data)?;
            }
            LayeredTexSubImage { id, x, y, z, width, height, depth, data } => {
                self.layered_tex_sub_image(id, (x, y, z), (width, height, depth), data)?;
            }
            TexWrapR { id, wrap } => self.layered_mut(id)?.wrap_r = wrap,
            EncodedTexImage { id, level, width, height, format, srgb, data } => {
                self.encoded_tex_image(id, level, (width, height), format, srgb, data)?
            }
            EncodedTexSubImage { id, x, y, width, height, format, data } => {
                self.encoded_tex_sub_image(id, (x, y, width, height), format, data)?
            }
            TexParameters { id, filter, wrap, mag_filter, wrap_t } => {
                let mut sampler = sampler_state(filter, wrap, mag_filter, wrap_t)?;
                if self.layered.contains_key(&id) {
                    sampler.compare = self.layered_mut(id)?.sampler.compare;
                    self.layered_mut(id)?.sampler = sampler;
                } else if self.cubes.contains_key(&id) {
                    sampler.compare = self.cube_mut(id)?.sampler.compare;
                    self.cube_mut(id)?.sampler = sampler;
                } else {
                    sampler.compare = self.texture_mut(id)?.sampler.compare;
                    self.texture_mut(id)?.sampler = sampler;
                }
            }
            TexCompare { id, compare } => {
                if self.layered.contains_key(&id) {
                    self.layered_mut(id)?.sampler.compare = compare;
                } else if self.cubes.contains_key(&id) {
                    self.cube_mut(id)?.sampler.compare = compare;
                } else {
                    self.texture_mut(id)?.sampler.compare = compare;
                }
            }
            GenerateMipmap { id } if self.cubes.contains_key(&id) => self.generate_cube_mipmap(id)?,
            GenerateMipmap { id } if self.layered.contains_key(&id) => self.generate_layered_mipmap(id)?,
            BindSampler { unit, filter, wrap, mag_filter, wrap_t, compare, wrap_r } => {
                let sampler = SamplerState { compare, ..sampler_state(filter, wrap, mag_filter, wrap_t)? };
                self.bind_sampler(unit, Some(sampler))?;
                self.state.unit_wrap_r[unit as usize] = wrap_r.unwrap_or(Wrap::Repeat);
            }
            UnbindSampler { unit } => self.bind_sampler(unit, None)?,
            GenerateMipmap { id } => {
                let image = self.texture(id)?.image;
                self.check_has_memory(image, &format!("generate_mipmap of texture {id}"))?;
                if let Some(format) = self.texture(id)?.encoded.filter(|f| f.texel_format().is_compressed()) {
                    return Err(format!(
                        "generate_mipmap of texture {id}, which is compressed ({format:?}): its levels must be given"
                    ));
                }
                if self.pass.as_ref().is_some_and(|p| p.images_sampled.contains(&image))
                    && !self.texture(id)?.levels.is_empty()
                {
                    return Err(format!(
                        "generate_mipmap replaces the given levels of texture {id}, which the open pass samples: \
                         not supported"
                    ));
                }
                let t = self.texture_mut(id)?;
                t.mipmaps = true;
                t.levels.clear();
            }
            TexImageLevel { id, level, width, height, data } => self.tex_image_level(id, level, width, height, data)?,
            DeleteTexture { id } if self.cubes.contains_key(&id) => self.delete_cube(id),
            DeleteTexture { id } if self.layered.contains_key(&id) => self.delete_layered(id)?,
            DeleteTexture { id } => self.delete_texture(id)?,
            CreateRenderbuffer { id, width, height, format, samples, transient } => {
                if id == 0 || self.renderbuffers.contains_key(&id) {
                    return Err(name_taken("renderbuffer", id));
                }
                let image = self.alloc_image_with(width, height, format, samples, transient)?;
                self.renderbuffers.insert(id, RenderbufferObject { image });
            }
            DeleteRenderbuffer { id } => self.delete_renderbuffer(id)?,
            CreateFramebuffer { id } => {
                if id == 0 || self.framebuffers.contains_key(&id) {
                    return Err(name_taken("framebuffer", id));
                }
                self.framebuffers.insert(id, FramebufferObject::default());
            }
            DeleteFramebuffer { id } => self.delete_framebuffer(id)?,
            FramebufferTexture { framebuffer, attachment, texture, samples } => {
                let r = match (texture, samples) {
                    (0, _) => None,
                    (_, 1) => {
                        self.texture(texture)?;
                        Some(AttachmentRef::Texture(texture))
                    }
                    _ => {
                        let t = self.texture(texture)?;
                        if attachment.color_index().is_none() || !t.format.is_color() {
                            return Err(
                                "multisampled render to texture is supported for colour textures only".to_string()
                            );
                        }
                        if framebuffer == 0 || !self.framebuffers.contains_key(&framebuffer) {
                            return Err(format!("framebuffer {framebuffer} cannot take attachments"));
                        }
                        let (format, desc) = (t.format, self.images[&t.image].desc);
                        if desc.transient {
                            return Err(format!(
                                "texture {texture} is transient (it has no memory), so multisamples cannot be \
                                 resolved into it: attach it single-sampled"
                            ));
                        }
                        let image = self.alloc_image(desc.width, desc.height, format, samples)?;
                        Some(AttachmentRef::MultisampleTexture { texture, samples: image })
                    }
                };
                self.attach(framebuffer, attachment, r)?;
            }
            FramebufferTextureLayer { framebuffer, attachment, texture, layer } => {
                self.framebuffer_texture_layer(framebuffer, attachment, texture, layer)?;
            }
            CopyTexSubImageLayer { texture, layer, x_offset, y_offset, x, y, width, height } => {
                let hidden = self.layer_texture(texture, layer)?;
                self.copy_tex_sub_image(hidden, [x_offset, y_offset], [x, y], [width, height], false)?;
            }
            FramebufferRenderbuffer { framebuffer, attachment, renderbuffer } => {
                if renderbuffer != 0 && !self.renderbuffers.contains_key(&renderbuffer) {
                    return Err(format!("renderbuffer {renderbuffer} does not exist"));
                }
                let r = (renderbuffer != 0).then_some(AttachmentRef::Renderbuffer(renderbuffer));
                self.attach(framebuffer, attachment, r)?;
            }
            BindFramebuffer { target, framebuffer } => self.bind_framebuffer(target, framebuffer)?,
            DrawBuffers { count } => {
                let framebuffer = self.draw_framebuffer;
                // A framebuffer may write no colour (a depth-only pass); the window writes its one.
                let (min, max) = if framebuffer == 0 { (1, 1) } else { (0, MAX_DRAW_BUFFERS) };
                if !(min..=max).contains(&count) {
                    return Err(format!("{count} draw buffers: framebuffer {framebuffer} takes {min} to {max}"));
                }
                self.framebuffers.get_mut(&framebuffer).expect("the bound framebuffer exists").draw_buffers =
                    Some(count);
            }
            BeginPass { framebuffer, subpasses, dependencies } => {
                self.begin_pass(framebuffer, &subpasses, &dependencies)?;
            }
            NextSubpass => self.next_subpass()?,
            EndPass => self.end_pass()?,
            CreateProgram { id, program } => {
                if id == 0 || self.programs.contains_key(&id) {
                    return Err(name_taken("program", id));
                }
                let object = match program {
                    ProgramSource::Builtin(kind) => ProgramObject::Builtin { kind, uniforms: Uniforms::default() },
                    ProgramSource::Glsl(source) => {
                        ProgramObject::Glsl(glsl::GlslProgram::new(source).map_err(|e| format!("program {id}: {e}"))?)
                    }
                };
                self.programs.insert(id, object);
            }
            BindAttribLocation { program, index, name } => self.bind_attrib_location(program, index, name)?,
            UseProgram { id } => self.use_program(id)?,
            DeleteProgram { id } => {
                if !self.programs.contains_key(&id) {
                    return Err(format!("program {id} does not exist"));
                }
                if self.state.program == id {
                    self.deleted_program = Some(id);
                } else {
                    self.drop_deleted_program(id);
                }
            }
            Uniform { name, value } => self.uniform(&name, value)?,
            Viewport { x, y, width, height } => {
                self.state.viewport = [x as i64, y as i64, width as i64, height as i64];
            }
            DepthRange { near, far } => {
                if !near.is_finite() || !far.is_finite() {
                    return Err(format!("depth range [{near}, {far}] is not finite"));
                }
                self.state.depth_range = [near.clamp(0.0, 1.0), far.clamp(0.0, 1.0)];
            }
            Scissor { x, y, width, height } => {
                self.state.scissor = [x as i64, y as i64, width as i64, height as i64];
            }
            Enable { cap } => self.set_capability(cap, true),
            Disable { cap } => self.set_capability(cap, false),
            ColorMask { red, green, blue, alpha } => self.state.color_mask = [red, green, blue, alpha],
            DepthMask { write } => self.state.depth_mask = write,
            LineWidth { width } => {
                // GL: a width not above 0 is an error; llvmpipe's widest line is 255 pixels.
                if !(width.is_finite() && width > 0.0) {
                    return Err(format!("line width {width} is not positive"));
                }
                self.state.line_width = width.min(255.0);
            }
            PolygonOffset { factor, units } => {
                if !factor.is_finite() || !units.is_finite() {
                    return Err(format!("polygon offset ({factor}, {units}) is not finite"));
                }
                self.state.polygon_offset = (factor, units);
            }
            StencilMask { mask, face } => self.stencil_faces(face).for_each(|f| f.write_mask = mask),
            DepthFunc { func } => self.state.depth_func = func,
            StencilFunc { func, reference, mask, face } => self.stencil_faces(face).for_each(|f| {
                (f.compare, f.reference, f.compare_mask) = (func, reference, mask);
            }),
            StencilOp { fail, depth_fail, pass, face } => self.stencil_faces(face).for_each(|f| {
                (f.fail_op, f.depth_fail_op, f.pass_op) = (fail, depth_fail, pass);
            }),
            BlendFunc { src, dst, src_alpha, dst_alpha } => {
                self.state.blend_func = [src, dst, src_alpha.unwrap_or(src), dst_alpha.unwrap_or(dst)];
            }
            BlendEquation { rgb, alpha } => self.state.blend_equation = [rgb, alpha.unwrap_or(rgb)],
            BlendColor { rgba } => self.state.blend_color = finite4("blend colour", rgba)?,
            CullFace { face } => self.state.cull = face,
            FrontFace { winding } => self.state.front = winding,
            ClearColor { rgba } => self.state.clear_color = finite4("clear colour", rgba)?,
            ClearDepth { depth } => {
                if !depth.is_finite() {
                    return Err(format!("clear depth {depth} is not finite"));
                }
                self.state.clear_depth = depth.clamp(0.0, 1.0);
            }
            ClearStencil { stencil } => self.state.clear_stencil = stencil,
            VertexAttribPointer { index, buffer, size, component, normalized, stride, offset } => {
                self.attrib_index(index)?;
                if !self.buffers.contains_key(&buffer) {
                    return Err(format!("buffer {buffer} does not exist"));
                }
                crate::context::draw::vertex_format(size, component, normalized, false)?;
                self.state.attribs[index as usize].source =
                    Some((AttribSource::Buffer { buffer, offset }, size, component, normalized, stride, false));
            }
            VertexAttribIPointer { index, buffer, size, component, stride, offset } => {
                self.attrib_index(index)?;
                if !self.buffers.contains_key(&buffer) {
                    return Err(format!("buffer {buffer} does not exist"));
                }
                crate::context::draw::vertex_format(size, component, false, true)?;
                self.state.attribs[index as usize].source =
                    Some((AttribSource::Buffer { buffer, offset }, size, component, false, stride, true));
            }
            VertexAttribI { index, value, signed } => {
                // Held as the value's float (exact to 2²⁴): an integer attribute takes a
                // generic value's integer back (`tiler_glsl`).
                self.attrib_index(index)?;
                let floats = value.map(|v| if signed { v as i32 as f32 } else { v as f32 });
                if floats.iter().any(|f| f.abs() > (1 << 24) as f32) {
                    return Err(format!(
                        "vertex attribute {index}: generic integer value {value:?} is beyond 2^24, which the context \
                         holds exactly"
                    ));
                }
                self.state.generic[index as usize] = floats;
            }
            // GL ES 3.0 §4.2.3: clears are discarded with the rasterizer (llvmpipe agrees).
            Clear { .. } | ClearBufferColor { .. } | ClearBufferDepthStencil { .. }
                if self.state.rasterizer_discard => {}
            ClearBufferColor { draw_buffer, value } => self.clear_buffer_color(draw_buffer, value)?,
            ClearBufferDepthStencil { depth, stencil } => {
                if depth.is_some_and(|d| !d.is_finite()) {
                    return Err(format!("clear depth {depth:?} is not finite"));
                }
                let depth = depth.map(|d| d.clamp(0.0, 1.0));
                self.clear_with(pass::ClearRequest { color: None, depth, stencil })?;
            }
            VertexAttribArray { index, size, component, normalized, stride, data } => {
                self.attrib_index(index)?;
                if self.state.vertex_array != 0 {
                    return Err(format!(
                        "client-side arrays need the default vertex array, but vertex array {} is bound (GL ES 3.0 \
                         §2.9.6)",
                        self.state.vertex_array
                    ));
                }
                crate::context::draw::vertex_format(size, component, normalized, false)?;
                self.state.attribs[index as usize].source =
                    Some((AttribSource::Client { data }, size, component, normalized, stride, false));
            }
            VertexAttribIArray { index, size, component, stride, data } => {
                self.attrib_index(index)?;
                if self.state.vertex_array != 0 {
                    return Err(format!(
                        "client-side arrays need the default vertex array, but vertex array {} is bound (GL ES 3.0                          §2.9.6)",
                        self.state.vertex_array
                    ));
                }
                crate::context::draw::vertex_format(size, component, false, true)?;
                self.state.attribs[index as usize].source =
                    Some((AttribSource::Client { data }, size, component, false, stride, true));
            }
            EnableVertexAttrib { index } => {
                self.attrib_index(index)?;
                self.state.attribs[index as usize].enabled = true;
            }
            VertexAttrib { index, value } => {
                self.attrib_index(index)?;
                self.state.generic[index as usize] = finite4(&format!("vertex attribute {index}"), value)?;
            }
            DisableVertexAttrib { index } => {
                self.attrib_index(index)?;
                self.state.attribs[index as usize].enabled = false;
            }
            BindIndexBuffer { buffer } => {
                if buffer != 0 && !self.buffers.contains_key(&buffer) {
                    return Err(format!("buffer {buffer} does not exist"));
                }
                self.state.index_buffer = buffer;
            }
            VertexAttribDivisor { index, divisor } => {
                self.attrib_index(index)?;
                self.state.attribs[index as usize].divisor = divisor;
            }
            CreateVertexArray { id } => self.create_vertex_array(id)?,
            BindVertexArray { id } => self.bind_vertex_array(id)?,
            DeleteVertexArray { id } => self.delete_vertex_array(id)?,
            UniformBlockBinding { program, block, binding } => self.uniform_block_binding(program, &block, binding)?,
            BindUniformBuffer { binding, buffer, offset, size } => {
                self.bind_uniform_buffer(binding, buffer, offset, size)?;
            }
            BindTexture { unit, texture } => {
                if unit >= MAX_TEXTURE_UNITS {
                    return Err(format!("texture unit {unit} is out of range (0 to {})", MAX_TEXTURE_UNITS - 1));
                }
                if texture != 0 {
                    self.texture(texture)?;
                }
                self.state.textures[unit as usize] = texture;
            }
            BindCubeTexture { unit, texture } => self.bind_cube_texture(unit, texture)?,
            BindLayeredTexture { unit, target, texture } => self.bind_layered_texture(unit, target, texture)?,
            DrawArrays { mode, first, count } => self.draw(mode, first, count, None, 1)?,
            DrawElements { mode, count, index_type, offset } => {
                self.draw(mode, 0, count, Some((index_type, offset)), 1)?;
            }
            DrawArraysInstanced { mode, first, count, instances } => self.draw(mode, first, count, None, instances)?,
            TransformFeedbackVaryings { program, varyings, separate } => {
                self.transform_feedback_varyings(program, varyings, separate)?;
            }
            BindTransformFeedbackBuffer { binding, buffer, offset, size } => {
                self.bind_transform_feedback_buffer(binding, buffer, offset, size)?;
            }
            BeginTransformFeedback { mode } => self.begin_transform_feedback(mode)?,
            EndTransformFeedback => self.end_transform_feedback()?,
            PauseTransformFeedback => self.pause_transform_feedback(true)?,
            ResumeTransformFeedback => self.pause_transform_feedback(false)?,
            DrawElementsInstanced { mode, count, index_type, offset, instances } => {
                self.draw(mode, 0, count, Some((index_type, offset)), instances)?;
            }
            Clear { color, depth, stencil } => self.clear(BufferSet { color, depth, stencil })?,
            Invalidate { attachments } => self.invalidate(&attachments)?,
            ReadPixels { x, y, width, height } => {
                return self.read_pixels(x, y, width, height, None).map(Output::Pixels);
            }
            ReadPixelsInteger { x, y, width, height, signed } => {
                return self.read_pixels(x, y, width, height, Some(signed)).map(Output::Pixels);
            }
            BlitFramebuffer { src, dst, filter } => self.blit(src, dst, filter)?,
            CopyTexSubImage { texture, x_offset, y_offset, x, y, width, height, alpha_one } => {
                self.copy_tex_sub_image(texture, [x_offset, y_offset], [x, y], [width, height], alpha_one)?;
            }
            Flush => self.flush_open_pass(crate::report::FlushCause::Flush)?,
            Finish => self.finish()?,
            FenceSync { id } => self.fence_sync(id)?,
            ClientWaitSync { id } => self.client_wait_sync(id)?,
            DeleteSync { id } => {
                self.fences.remove(&id).ok_or_else(|| format!("fence {id} does not exist"))?;
            }
            SwapBuffers => self.swap_buffers()?,
            RestoreState { state } => self.restore_state(state)?,
            SwapBehavior { behavior } => self.swap_behavior = behavior,
            ResizeSurface { width, height } => self.resize_surface(width, height)?,
            CreateContext { id } => self.create_context(id)?,
            MakeCurrent { id } => self.make_current(id)?,
            DestroyContext { id } => self.destroy_context(id)?,
            StartTiling { x, y, width, height, preserve } => self.start_tiling([x, y], [width, height], preserve)?,
            EndTiling { store } => self.end_tiling(store)?,
            CreateQuery { id } => {
                if id == 0 || self.queries.contains_key(&id) {
                    return Err(name_taken("query", id));
                }
                self.queries.insert(id, QueryObject::default());
            }
            DeleteQuery { id } => {
                if self.active_query == Some(id) {
                    return Err(format!("query {id} is active"));
                }
                self.queries.remove(&id).ok_or_else(|| format!("query {id} does not exist"))?;
            }
            BeginQuery { id } => {
                if let Some(active) = self.active_query {
                    return Err(format!("query {active} is already active"));
                }
                let q = self.queries.get_mut(&id).ok_or_else(|| format!("query {id} does not exist"))?;
                *q = QueryObject::default();
                self.active_query = Some(id);
            }
            EndQuery => {
                let id = self.active_query.take().ok_or("no query is active")?;
                let frame = self.here.frame;
                let q = self.queries.get_mut(&id).expect("active query exists");
                q.ended = true;
                q.last_frame = q.last_frame.max(frame);
            }
            QueryAvailable { id } => return self.query_available(id).map(Output::Available),
            QueryResult { id } => return self.query_result(id).map(Output::Samples),
        }
        Ok(Output::None)
    }

    fn attrib_index(&self, index: u32) -> Fallible {
        if index >= MAX_VERTEX_ATTRIBS {
            return Err(format!("vertex attribute {index} is out of range (0 to {})", MAX_VERTEX_ATTRIBS - 1));
        }
        Ok(())
    }

    fn set_capability(&mut self, cap: Capability, on: bool) {
        let s = &mut self.state;
        match cap {
            Capability::DepthTest => s.depth_test = on,
            Capability::StencilTest => s.stencil_test = on,
            Capability::Blend => s.blend = on,
            Capability::CullFace => s.cull_face = on,
            Capability::ScissorTest => s.scissor_test = on,
            Capability::PolygonOffsetFill => s.polygon_offset_fill = on,
            Capability::PrimitiveRestartFixedIndex => s.primitive_restart = on,
            Capability::RasterizerDiscard => s.rasterizer_discard = on,
        }
    }

    fn uniform(&mut self, name: &str, value: UniformValue) -> Fallible {
        let id = self.state.program;
        match self.programs.get_mut(&id).ok_or("no program is in use")? {
            ProgramObject::Builtin { kind, uniforms } => uniforms.set(*kind, name, value),
            ProgramObject::Glsl(program) => program.set_uniform(name, value).map_err(|e| format!("program {id}: {e}")),
        }
    }

    /// The bytes of buffer `id` (what a pixel unpack buffer hands a texel upload).
    ///
    /// # Errors
    /// No such buffer.
    pub fn buffer_bytes(&self, id: u32) -> Result<&[u8], String> {
        let b = self.buffers.get(&id).ok_or_else(|| format!("buffer {id} does not exist"))?;
        let bytes = self.device.buffer_data(b.storage).map_err(|e| e.to_string())?;
        Ok(&bytes[..(b.size as usize).min(bytes.len())])
    }

    pub(crate) fn texture(&self, id: u32) -> Fallible<&TextureObject> {
        self.textures.get(&id).ok_or_else(|| format!("texture {id} does not exist"))
    }

    /// The stencil states a `*_separate` call sets: `[front, back]`, or one of them.
    fn stencil_faces(&mut self, face: Face) -> impl Iterator<Item = &mut StencilFaceState> {
        let [front, back] = &mut self.state.stencil;
        let (f, b) = match face {
            Face::Front => (Some(front), None),
            Face::Back => (None, Some(back)),
            Face::FrontAndBack => (Some(front), Some(back)),
        };
        f.into_iter().chain(b)
    }

    fn texture_mut(&mut self, id: u32) -> Fallible<&mut TextureObject> {
        self.textures.get_mut(&id).ok_or_else(|| format!("texture {id} does not exist"))
    }

    /// `resize_surface`: new window images of `width × height` (contents undefined) in place
    /// of the old ones, after the open pass on the window (if any) has been rendered.
    fn resize_surface(&mut self, width: u32, height: u32) -> Fallible {
        if (width, height) == (self.config.width, self.config.height) {
            return Ok(());
        }
        if self.pass.as_ref().is_some_and(|p| p.framebuffer == 0) {
            self.flush_open_pass(crate::report::FlushCause::AttachmentChange)?;
        }
        let samples = self.config.samples;
        let depth_stencil = match self.config.depth_stencil_format {
            Some(format) => Some((self.alloc_image(width, height, format, samples)?, format)),
            None => None,
        };
        let color_format = self.config.color_format;
        let (color, presented) = if samples > 1 {
            let msaa = self.alloc_image(width, height, color_format, samples)?;
            let resolve = self.alloc_image(width, height, color_format, 1)?;
            (AttachmentRef::SurfaceMultisample { samples: msaa, resolve }, resolve)
        } else {
            let image = self.alloc_image(width, height, color_format, 1)?;
            (AttachmentRef::Surface(image), image)
        };
        let fb = self.framebuffers.get_mut(&0).expect("the window's framebuffer always exists");
        let mut old = Vec::new();
        for attachment in fb.color.iter().chain([&fb.depth, &fb.stencil]).flatten() {
            match *attachment {
                AttachmentRef::Surface(image) => old.push(image),
                AttachmentRef::SurfaceMultisample { samples, resolve } => old.extend([samples, resolve]),
                _ => {}
            }
        }
        fb.color[0] = Some(color);
        let r = depth_stencil.map(|(image, _)| AttachmentRef::Surface(image));
        fb.depth = depth_stencil.filter(|(_, f)| f.has_depth()).and(r);
        fb.stencil = depth_stencil.filter(|(_, f)| f.has_stencil()).and(r);
        old.sort_unstable();
        old.dedup();
        for image in old {
            self.retire_image(image);
        }
        self.surface_color = presented;
        self.surface_depth_stencil = depth_stencil.map(|(image, _)| image);
        self.config.width = width;
        self.config.height = height;
        Ok(())
    }

    // --- memory ----------------------------------------------------------------------------

    /// An image for `format`, from the pool or newly allocated within the memory limit. Its
    /// contents are undefined.
    pub(crate) fn alloc_image(
        &mut self,
        width: u32,
        height: u32,
        format: TextureFormat,
        samples: u32,
    ) -> Fallible<ImageId> {
        self.alloc_image_with(width, height, format, samples, false)
    }

    /// [`Context::alloc_image`], or a transient image (no memory, so nothing is reserved).
    pub(crate) fn alloc_image_with(
        &mut self,
        width: u32,
        height: u32,
        format: TextureFormat,
        samples: u32,
        transient: bool,
    ) -> Fallible<ImageId> {
        let mut desc = ImageDesc::new(width, height, format.format()).with_samples(samples);
        if transient {
            desc = desc.transient();
        }
        desc.validate().map_err(|e| e.to_string())?;
        let image = match self.image_pool.get_mut(&desc).and_then(|p| p.pop()) {
            Some(image) => image,
            None => {
                self.reserve(if transient { 0 } else { desc.size_bytes() })?;
                self.device.create_image(desc).map_err(|e| e.to_string())?
            }
        };
        self.images.insert(
            image,
            ImageInfo { desc, gl_format: format, defined: [false; 2], last_write: None, last_use: None },
        );
        Ok(image)
    }

    /// Returns an image to the pool (its stores die with it).
    pub(crate) fn free_image(&mut self, image: ImageId) {
        if let Some(info) = self.images.remove(&image) {
            self.forget_built_texture(image);
            self.forget_stores(image, "storage released");
            self.image_pool.entry(info.desc).or_default().push(image);
        }
    }

    /// A buffer holding `bytes`, from the pool or newly allocated within the memory limit.
    pub(crate) fn alloc_buffer(&mut self, bytes: &[u8]) -> Fallible<BufferId> {
        let len = bytes.len() as u64;
        if let Some(id) = self.buffer_pool.get_mut(&len).and_then(|p| p.pop()) {
            self.device.write_buffer(id, 0, bytes).map_err(|e| e.to_string())?;
            return Ok(id);
        }
        self.reserve(len)?;
        self.device.create_buffer(bytes).map_err(|e| e.to_string())
    }

    pub(crate) fn free_buffer(&mut self, id: BufferId, len: u64) {
        self.buffer_pool.entry(len).or_default().push(id);
    }

    fn reserve(&mut self, bytes: u64) -> Fallible {
        let total = self.allocated.saturating_add(bytes);
        if total > self.config.memory_limit {
            return Err(format!(
                "allocating {bytes} bytes would take the context's images and buffers to {total} bytes, \
                 above its memory limit of {} bytes",
                self.config.memory_limit
            ));
        }
        self.allocated = total;
        Ok(())
    }

    // --- buffers ---------------------------------------------------------------------------

    fn create_buffer_object(&mut self, id: u32, data: Bytes) -> Fallible {
        if id == 0 || self.buffers.contains_key(&id) {
            return Err(name_taken("buffer", id));
        }
        let storage = self.alloc_buffer(&data)?;
        self.buffers.insert(id, BufferObject { storage, size: data.len() as u64, last_use: None });
        Ok(())
    }

    /// `glBufferData`: new storage (orphaning) when the old one may still be read.
    fn buffer_data(&mut self, id: u32, data: Bytes) -> Fallible {
        let b = self.buffers.get(&id).ok_or_else(|| format!("buffer {id} does not exist"))?;
        let (storage, size) = (b.storage, b.size);
        let in_open_pass = self.pass.as_ref().is_some_and(|p| p.buffers_used.contains(&storage));
        if in_open_pass || size != data.len() as u64 {
            let new = self.alloc_buffer(&data)?;
            self.retire_buffer(storage, size);
            let b = self.buffers.get_mut(&id).expect("checked");
            b.storage = new;
            b.size = data.len() as u64;
        } else {
            self.device.write_buffer(storage, 0, &data).map_err(|e| e.to_string())?;
        }
        // Orphaned: no pending frame uses the new storage.
        self.buffers.get_mut(&id).expect("checked").last_use = None;
        Ok(())
    }

    fn buffer_sub_data(&mut self, id: u32, offset: u64, data: Bytes) -> Fallible {
        let b = self.buffers.get(&id).ok_or_else(|| format!("buffer {id} does not exist"))?;
        let (storage, size, last_use) = (b.storage, b.size, b.last_use);
        let end = offset.checked_add(data.len() as u64).filter(|e| *e <= size).ok_or_else(|| {
            format!(
                "a write of {} bytes at offset {offset} runs past the end of buffer {id} ({size} bytes)",
                data.len()
            )
        })?;
        let _ = end;
        if let Some(used) = last_use
            && self.in_flight(used)
        {
            self.count_copy_on_write(format!("buffer {id}"), used, size - data.len() as u64);
        }
        let in_open_pass = self.pass.as_ref().is_some_and(|p| p.buffers_used.contains(&storage));
        if in_open_pass {
            // The pending draws must keep reading the old contents: give the buffer a copy,
            // which no frame uses yet.
            let mut contents = self.device_buffer_bytes(storage, size)?;
            contents[offset as usize..offset as usize + data.len()].copy_from_slice(&data);
            let new = self.alloc_buffer(&contents)?;
            self.retire_buffer(storage, size);
            let b = self.buffers.get_mut(&id).expect("checked");
            b.storage = new;
            b.last_use = None;
        } else {
            self.device.write_buffer(storage, offset, &data).map_err(|e| e.to_string())?;
        }
        Ok(())
    }

    /// `copy_buffer_sub_data`: the source's bytes now, written into the destination as
    /// `buffer_sub_data` writes (the copy itself is not counted, as uploads are not).
    fn copy_buffer_sub_data(&mut self, src: u32, dst: u32, src_offset: u64, dst_offset: u64, size: u64) -> Fallible {
        let b = self.buffers.get(&src).ok_or_else(|| format!("buffer {src} does not exist"))?;
        let end = src_offset.checked_add(size).filter(|e| *e <= b.size).ok_or_else(|| {
            format!(
                "a copy of {size} bytes from offset {src_offset} runs past the end of buffer {src} ({} bytes)",
                b.size
            )
        })?;
        if src == dst && src_offset < dst_offset.saturating_add(size) && dst_offset < end {
            return Err(format!("copying buffer {src} onto itself with overlapping ranges"));
        }
        let bytes = self.device_buffer_bytes(b.storage, b.size)?[src_offset as usize..end as usize].to_vec();
        self.buffer_sub_data(dst, dst_offset, Bytes::from(bytes))
    }

    /// A buffer's bytes (the device has no read-back for buffers, so the context keeps none
    /// either: it reconstructs them by reading the storage through a scratch copy).
    pub(crate) fn device_buffer_bytes(&self, storage: BufferId, size: u64) -> Fallible<Vec<u8>> {
        self.device.buffer_data(storage).map(|b| b[..size as usize].to_vec()).map_err(|e| e.to_string())
    }

    /// Frees a buffer storage now, or when the open pass that reads it has been rendered.
    pub(crate) fn retire_buffer(&mut self, storage: BufferId, size: u64) {
        match &mut self.pass {
            Some(pass) if pass.buffers_used.contains(&storage) => pass.retired_buffers.push((storage, size)),
            _ => self.free_buffer(storage, size),
        }
    }

    fn delete_buffer(&mut self, id: u32) -> Fallible {
        let b = self.buffers.remove(&id).ok_or_else(|| format!("buffer {id} does not exist"))?;
        self.retire_buffer(b.storage, b.size);
        self.forget_buffer_in_vertex_arrays(id);
        self.forget_uniform_buffer(id);
        self.feedback.forget_buffer(id);
        Ok(())
    }

    // --- textures and renderbuffers --------------------------------------------------------

    /// Gives texture `id` new storage (creating the texture if needed).
    pub(crate) fn texture_storage(
        &mut self,
        id: u32,
        width: u32,
        height: u32,
        format: TextureFormat,
        data: Option<Bytes>,
        transient: bool,
    ) -> Fallible {
        if let Some(data) = &data {
            check_texel_bytes(format, width, height, data.len())?;
        }
        // Storage of an attachment of the open pass changes: the pass must end first.
        if self.textures.contains_key(&id) && self.open_pass_attaches(AttachmentRef::Texture(id)) {
            self.flush_open_pass(crate::report::FlushCause::AttachmentChange)?;
        }
        let image = self.alloc_image_with(width, height, format, 1, transient)?;
        if let Some(data) = data {
            self.upload(image, 0, 0, width, height, data)?;
        }
        let sampler = SamplerState::new(Filter::Nearest, Wrap::ClampToEdge);
        let old = self.textures.insert(
            id,
            TextureObject { image, format, sampler, mipmaps: false, levels: Vec::new(), encoded: None, unorm16: None },
        );
        if let Some(old) = old {
            // GL keeps the other levels of a texture whose level 0 is replaced by one of the same
            // size and format, so it stays complete.
            let d = self.images[&old.image].desc;
            let same = (d.width, d.height) == (width, height) && old.format == format;
            let t = self.textures.get_mut(&id).expect("inserted");
            t.sampler = old.sampler;
            t.mipmaps = old.mipmaps && same;
            if same {
                t.levels = old.levels;
            }
            self.retire_image(old.image);
        }
        Ok(())
    }

    /// Frees an image now, or after the open pass that samples it has been rendered.
    pub(crate) fn retire_image(&mut self, image: ImageId) {
        match &mut self.pass {
            Some(pass) if pass.images_sampled.contains(&image) => pass.retired_images.push(image),
            _ => self.free_image(image),
        }
    }

    pub(crate) fn tex_sub_image(&mut self, id: u32, x: u32, y: u32, width: u32, height: u32, data: Bytes) -> Fallible {
        let t = self.texture(id)?;
        let (image, format) = (t.image, t.format);
        let desc = self.images[&image].desc;
        if x as u64 + width as u64 > desc.width as u64 || y as u64 + height as u64 > desc.height as u64 {
            return Err(format!(
                "rectangle {width}×{height} at ({x}, {y}) is outside texture {id} ({}×{})",
                desc.width, desc.height
            ));
        }
        check_texel_bytes(format, width, height, data.len())?;
        self.check_has_memory(image, &format!("tex_sub_image of texture {id}"))?;
        if self.open_pass_attaches(AttachmentRef::Texture(id)) {
            self.flush_open_pass(crate::report::FlushCause::TextureUpdate)?;
        }
        let info = &self.images[&image];
        let last = info.last_use.max(info.last_write);
        if let Some(used) = last
            && self.in_flight(used)
        {
            let replaced = width as u64 * height as u64 * desc.format.bytes_per_sample() as u64;
            self.count_copy_on_write(format!("texture {id}"), used, desc.size_bytes() - replaced);
        }
        let sampled_by_open_pass = self.pass.as_ref().is_some_and(|p| p.images_sampled.contains(&image));
        let target = if sampled_by_open_pass {
            // Pending draws keep the old texels: the texture moves to a copy.
            let copy = self.alloc_image(desc.width, desc.height, format, 1)?;
            let old = self.device.image_data(image).map_err(|e| e.to_string())?.to_vec();
            self.device.write_image(copy, &old).map_err(|e| e.to_string())?;
            let info = &self.images[&image];
            let (defined, last_write) = (info.defined, info.last_write);
            let new = self.images.get_mut(&copy).expect("allocated");
            new.defined = defined;
            new.last_write = last_write;
            self.retire_image(image);
            self.textures.get_mut(&id).expect("checked").image = copy;
            copy
        } else {
            image
        };
        self.upload(target, x, y, width, height, data)
    }

    /// Writes texels (GL rows, bottom to top) into a rectangle of an image.
    fn upload(&mut self, image: ImageId, x: u32, y: u32, width: u32, height: u32, data: Bytes) -> Fallible {
        let desc = self.images[&image].desc;
        let bpp = desc.format.bytes_per_sample();
        let row_bytes = width as usize * bpp;
        let whole = (x, y, width, height) == (0, 0, desc.width, desc.height) && desc.samples == 1;
        if whole {
            // Every byte is replaced: the upload's own bytes become the image's, GL's rows
            // (bottom to top) turned over in place.
            let mut contents = data.into_vec();
            let rows = height as usize;
            for row in 0..rows / 2 {
                let (top, bottom) = contents.split_at_mut((rows - 1 - row) * row_bytes);
                top[row * row_bytes..(row + 1) * row_bytes].swap_with_slice(&mut bottom[..row_bytes]);
            }
            self.device.replace_image(image, contents).map_err(|e| e.to_string())?;
        } else {
            let mut contents = self.device.image_data(image).map_err(|e| e.to_string())?.to_vec();
            for row in 0..height as usize {
                // GL row y + row from the bottom is tiler row height − 1 − (y + row).
                let tiler_row = desc.height as usize - 1 - (y as usize + row);
                let dst = (tiler_row * desc.width as usize + x as usize) * bpp;
                let src = row * row_bytes;
                contents[dst..dst + row_bytes].copy_from_slice(&data[src..src + row_bytes]);
            }
            self.device.write_image(image, &contents).map_err(|e| e.to_string())?;
        }
        let frame = self.here.frame;
        let info = self.images.get_mut(&image).expect("known image");
        info.defined = [true; 2];
        info.last_write = Some(frame);
        self.forget_stores(image, "overwritten by an upload");
        Ok(())
    }

    fn tex_image_level(&mut self, id: u32, level: u32, width: u32, height: u32, data: Bytes) -> Fallible {
        let t = self.texture(id)?;
        let (image, format) = (t.image, t.format);
        if !matches!(format, TextureFormat::Rgba8 | TextureFormat::Srgb8Alpha8) {
            return Err(format!("mip level {level} of texture {id}: levels above 0 are RGBA8 only, not {format:?}"));
        }
        if t.mipmaps && t.levels.is_empty() {
            return Err(format!(
                "mip level {level} of texture {id} replaces one of its generated levels: not supported \
                 (give every level, or generate them)"
            ));
        }
        let desc = self.images[&image].desc;
        let levels = mip_levels(desc.width, desc.height);
        if level == 0 || level >= levels {
            return Err(format!(
                "mip level {level} of texture {id}: a {}×{} texture has levels 1 to {}",
                desc.width,
                desc.height,
                levels - 1
            ));
        }
        let expected = ((desc.width >> level).max(1), (desc.height >> level).max(1));
        if (width, height) != expected {
            return Err(format!(
                "mip level {level} of texture {id} is {width}×{height}, but level 0 is {}×{}, so it must be {}×{}",
                desc.width, desc.height, expected.0, expected.1
            ));
        }
        check_texel_bytes(format, width, height, data.len())?;
        if self.pass.as_ref().is_some_and(|p| p.images_sampled.contains(&image)) {
            return Err(format!("mip level {level} of texture {id}, which the open pass samples: not supported"));
        }
        // Rows bottom to top (GL) → top to bottom (tiler).
        let row = width as usize * 4;
        let texels: Vec<u8> = data.chunks_exact(row).rev().flatten().copied().collect();
        let t = self.texture_mut(id)?;
        let index = level as usize - 1;
        if t.levels.len() <= index {
            t.levels.resize(index + 1, None);
        }
        t.levels[index] = Some(Arc::new(texels));
        t.mipmaps = t.given_chain(desc.width, desc.height).is_some();
        Ok(())
    }

    pub(crate) fn delete_texture(&mut self, id: u32) -> Fallible {
        self.texture(id)?;
        if self.open_pass_attaches(AttachmentRef::Texture(id)) {
            self.flush_open_pass(crate::report::FlushCause::AttachmentChange)?;
        }
        let t = self.textures.remove(&id).expect("checked");
        self.retire_image(t.image);
        for unit in &mut self.state.textures {
            if *unit == id {
                *unit = 0;
            }
        }
        self.forget_texture_in_contexts(id);
        Ok(())
    }

    fn delete_renderbuffer(&mut self, id: u32) -> Fallible {
        if !self.renderbuffers.contains_key(&id) {
            return Err(format!("renderbuffer {id} does not exist"));
        }
        if self.open_pass_attaches(AttachmentRef::Renderbuffer(id)) {
            self.flush_open_pass(crate::report::FlushCause::AttachmentChange)?;
        }
        let r = self.renderbuffers.remove(&id).expect("checked");
        self.free_image(r.image);
        Ok(())
    }

    // --- framebuffers ----------------------------------------------------------------------

    pub(crate) fn attach(&mut self, framebuffer: u32, point: AttachmentPoint, r: Option<AttachmentRef>) -> Fallible {
        if framebuffer == 0 {
            return Err("the window's framebuffer (0) has fixed attachments".to_string());
        }
        if !self.framebuffers.contains_key(&framebuffer) {
            return Err(format!("framebuffer {framebuffer} does not exist"));
        }
        if self.pass.as_ref().is_some_and(|p| p.framebuffer == framebuffer) {
            // The frame data gathered so far applies to the old attachments (seed 000 §23.5).
            self.flush_open_pass(crate::report::FlushCause::AttachmentChange)?;
            self.pass = None;
        }
        let fb = self.framebuffers.get_mut(&framebuffer).expect("checked");
        let old = match point {
            AttachmentPoint::Depth => std::mem::replace(&mut fb.depth, r),
            AttachmentPoint::Stencil => std::mem::replace(&mut fb.stencil, r),
            AttachmentPoint::DepthStencil => {
                fb.depth = r;
                std::mem::replace(&mut fb.stencil, r)
            }
            colour => std::mem::replace(&mut fb.color[colour.color_index().expect("colour point")], r),
        };
        // The implicit multisampled image of a replaced multisampled attachment goes.
        if let Some(AttachmentRef::MultisampleTexture { samples, .. }) = old {
            self.free_image(samples);
        }
        Ok(())
    }

    fn delete_framebuffer(&mut self, id: u32) -> Fallible {
        if id == 0 {
            return Err("the window's framebuffer (0) cannot be deleted".to_string());
        }
        if !self.framebuffers.contains_key(&id) {
            return Err(format!("framebuffer {id} does not exist"));
        }
        if self.draw_framebuffer == id {
            self.bind_framebuffer(FramebufferTarget::Draw, 0)?;
        }
        if self.read_framebuffer == id {
            self.read_framebuffer = 0;
        }
        self.forget_framebuffer_in_contexts(id);
        let fb = self.framebuffers.remove(&id).expect("checked");
        for r in fb.color.into_iter().flatten() {
            if let AttachmentRef::MultisampleTexture { samples, .. } = r {
                self.free_image(samples);
            }
        }
        Ok(())
    }

    fn use_program(&mut self, id: u32) -> Fallible {
        if id != 0 && !self.programs.contains_key(&id) {
            return Err(format!("program {id} does not exist"));
        }
        if let Some(doomed) = self.deleted_program.take_if(|d| *d != id) {
            self.drop_deleted_program(doomed);
        }
        self.state.program = id;
        Ok(())
    }

    /// The fixed-function and binding state now, for a later [`Call::RestoreState`].
    pub fn saved_state(&self) -> SavedState {
        SavedState {
            context: self.current_context,
            state: Box::new(self.state.clone()),
            framebuffers: Some((self.draw_framebuffer, self.read_framebuffer)),
        }
    }

    /// Puts back a [`Context::saved_state`] of the current context. The bound vertex array
    /// object must be the same one (the attributes of the others live with them, not in the
    /// state); the program in use changes as `use_program` would change it, and the draw
    /// framebuffer, if the saved state has it, as `bind_framebuffer` would (ending the open
    /// pass).
    fn restore_state(&mut self, saved: SavedState) -> Fallible {
        if saved.context != self.current_context {
            return Err(format!(
                "the state put back is context {}'s, but context {} is current",
                saved.context, self.current_context
            ));
        }
        let state = *saved.state;
        if state.vertex_array != self.state.vertex_array {
            return Err(format!(
                "vertex array object {} is bound, the state put back had {}: the attributes of a vertex array \
                 object cannot be put back",
                self.state.vertex_array, state.vertex_array
            ));
        }
        self.use_program(state.program)?;
        if let Some((draw, read)) = saved.framebuffers {
            self.bind_framebuffer(FramebufferTarget::Draw, draw)?;
            self.bind_framebuffer(FramebufferTarget::Read, read)?;
        }
        self.state = state;
        Ok(())
    }

    fn bind_framebuffer(&mut self, target: FramebufferTarget, framebuffer: u32) -> Fallible {
        if !self.framebuffers.contains_key(&framebuffer) {
            return Err(format!("framebuffer {framebuffer} does not exist"));
        }
        if target != FramebufferTarget::Read && framebuffer != self.draw_framebuffer {
            if self.tiling.is_some() {
                return Err(
                    "a framebuffer cannot be bound inside a tiled-rendering region: call end_tiling first".to_string()
                );
            }
            // Binding another framebuffer ends the render pass of the previous one.
            self.end_open_pass(crate::report::EndCause::Bind)?;
            self.draw_framebuffer = framebuffer;
            self.next_start = (StartCause::Bind, self.here);
        }
        if target != FramebufferTarget::Draw {
            self.read_framebuffer = framebuffer;
        }
        Ok(())
    }

    /// Whether the open pass has an attachment referring to `r`.
    pub(crate) fn open_pass_attaches(&self, r: AttachmentRef) -> bool {
        let Some(pass) = &self.pass else { return false };
        if pass.copy_texture.is_some() {
            return false;
        }
        let Some(fb) = self.framebuffers.get(&pass.framebuffer) else { return false };
        fb.color
            .iter()
            .chain([&fb.depth, &fb.stencil])
            .flatten()
            .any(|a| *a == r || (r.texture().is_some() && a.texture() == r.texture()))
    }
}

impl Context {
    /// Refuses to read or write the memory of a transient image, which has none.
    pub(crate) fn check_has_memory(&self, image: ImageId, what: &str) -> Fallible {
        if self.images.get(&image).is_some_and(|i| i.desc.transient) {
            return Err(format!(
                "{what}: the image is transient (it has no memory), so it cannot be read back, sampled, copied or \
                 uploaded; read it as an input attachment in a later subpass of the pass that renders it"
            ));
        }
        Ok(())
    }
}

/// The sampling state `tex_parameters` (or `bind_sampler`) describes.
fn sampler_state(
    filter: Filter,
    wrap: Wrap,
    mag_filter: Option<Filter>,
    wrap_t: Option<Wrap>,
) -> Fallible<SamplerState> {
    if mag_filter.is_some_and(|f| f.mipmap().is_some()) {
        return Err(format!("magnification filter {mag_filter:?} is not nearest or linear"));
    }
    let mut sampler = SamplerState::new(filter, wrap);
    sampler.mag_filter = mag_filter.unwrap_or(sampler.mag_filter);
    sampler.wrap_t = wrap_t.unwrap_or(wrap);
    Ok(sampler)
}

fn name_taken(kind: &str, id: u32) -> String {
    if id == 0 { format!("{kind} name 0 is reserved") } else { format!("{kind} {id} already exists") }
}

fn finite4(what: &str, v: [f32; 4]) -> Fallible<[f32; 4]> {
    if v.iter().all(|c| c.is_finite()) { Ok(v) } else { Err(format!("{what} {v:?} is not finite")) }
}

/// Checks that `len` bytes are exactly a `width × height` image of `format`.
fn check_texel_bytes(format: TextureFormat, width: u32, height: u32, len: usize) -> Fallible {
    let expected = width as u64 * height as u64 * format.format().bytes_per_sample() as u64;
    if len as u64 != expected {
        return Err(format!("{len} bytes of texels, but {width}×{height} of {} needs {expected}", format.name()));
    }
    Ok(())
}
