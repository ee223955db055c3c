//! The calls a [`Context`](crate::Context) takes: one enum that is both the API's vocabulary
//! and a trace's (`{"call": "draw_arrays", "mode": "triangles", "first": 0, "count": 3}`).
//!
//! [`Call`] is generic over how bulk data (buffer contents, texels, client-side vertex arrays)
//! is held: [`Bytes`] when executing, a [`DataSource`](crate::trace::DataSource) in a trace
//! file (inline numbers, base64, a binary side file or a glTF accessor). Every field name and
//! enum value here is part of the trace format (version [`TRACE_VERSION`](crate::trace::TRACE_VERSION)):
//! renaming one is a format change. `docs/trace-format.md` in this crate lists them all.
//!
//! Rectangles are in GL window coordinates (origin at the bottom-left, y up); the context
//! flips them onto tiler's framebuffer rows (row 0 at the top) — see the crate docs.

use serde::{Deserialize, Serialize};
use tiler::{BlendFactor, BlendOp, CompareOp};

use crate::bytes::Bytes;

/// One call of the GL-style API. Names follow OpenGL ES with the `gl` prefix dropped and
/// object creation folded into one call (`create_buffer` = `glGenBuffers` + `glBufferData`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "call", rename_all = "snake_case", deny_unknown_fields)]
pub enum Call<D = Bytes> {
    // --- buffers -------------------------------------------------------------------------
    /// Creates buffer `id` holding `data` (`glGenBuffers` + `glBufferData`).
    CreateBuffer {
        id: u32,
        data: D,
    },
    /// Replaces a buffer's whole contents, possibly resizing it (`glBufferData`): the driver
    /// gives the buffer new storage ("orphaning"), so nothing is copied even when a pending
    /// frame still reads the old contents.
    BufferData {
        id: u32,
        data: D,
    },
    /// Overwrites part of a buffer (`glBufferSubData`, or a mapped write). When a pending
    /// frame still uses the buffer the driver copies it first: copy-on-write.
    BufferSubData {
        id: u32,
        offset: u64,
        data: D,
    },
    DeleteBuffer {
        id: u32,
    },
    /// `glCopyBufferSubData`: `size` bytes of buffer `src` from `src_offset` into buffer `dst`
    /// at `dst_offset` (a write into `dst` as `buffer_sub_data` makes one, copy-on-write
    /// included). The ranges may not overlap within one buffer.
    CopyBufferSubData {
        src: u32,
        dst: u32,
        #[serde(default)]
        src_offset: u64,
        #[serde(default)]
        dst_offset: u64,
        size: u64,
    },

    // --- textures and renderbuffers ---------------------------------------------------------
    /// Creates texture `id` with storage (`glGenTextures` + `glTexImage2D`); `data` rows run
    /// bottom to top as in GL; without `data` the contents are undefined. A `transient`
    /// texture has no memory (Vulkan's transient attachment, lazily allocated): it can only be
    /// rendered and read as an input attachment within a pass, never uploaded, sampled or read
    /// back, and its contents do not outlive a pass.
    CreateTexture {
        id: u32,
        width: u32,
        height: u32,
        format: TextureFormat,
        #[serde(default = "none", skip_serializing_if = "Option::is_none")]
        data: Option<D>,
        #[serde(default, skip_serializing_if = "is_false")]
        transient: bool,
    },
    /// Gives a texture new storage (`glTexImage2D` on an existing texture).
    TexImage {
        id: u32,
        width: u32,
        height: u32,
        format: TextureFormat,
        #[serde(default = "none", skip_serializing_if = "Option::is_none")]
        data: Option<D>,
    },
    /// Level `level` (≥ 1) of texture `id` (`glTexImage2D` with `level > 0`): RGBA8 texels,
    /// rows bottom to top, `max(1, w >> level) × max(1, h >> level)` for level 0's `w × h`.
    /// Once every level down to 1×1 is given, a `*_mipmap_*` filter samples them as given;
    /// `generate_mipmap` replaces them, and new storage of another size or format drops them.
    TexImageLevel {
        id: u32,
        level: u32,
        width: u32,
        height: u32,
        data: D,
    },
    /// Level `level` of texture `id` in a format tiler samples but does not render to
    /// (`glCompressedTexImage2D`, and `glTexImage2D` of 4444 or 5551 texels): `data` is the
    /// format's blocks or packed texels, (block) rows bottom to top as GL uploads them. Level 0
    /// gives the texture new storage (as `tex_image`); a level above 0 is as `tex_image_level`
    /// and has level 0's format. The texture is decoded once, sampled as RGBA8 and counted in
    /// `texture_fetch` by what its format stores: compressed blocks, 2-byte texels. `srgb`: the
    /// colour is sRGB-encoded (`GL_COMPRESSED_SRGB8_*`).
    EncodedTexImage {
        id: u32,
        #[serde(default)]
        level: u32,
        width: u32,
        height: u32,
        format: EncodedFormat,
        #[serde(default, skip_serializing_if = "is_false")]
        srgb: bool,
        data: D,
    },
    /// Overwrites a rectangle of level 0 of a texture given by `encoded_tex_image`, in its
    /// format (`glCompressedTexSubImage2D`, `glTexSubImage2D` of 4444 or 5551 texels): a
    /// compressed rectangle starts on a block and ends on one or at the texture's edge.
    EncodedTexSubImage {
        id: u32,
        x: u32,
        y: u32,
        width: u32,
        height: u32,
        format: EncodedFormat,
        data: D,
    },
    /// Overwrites a rectangle of a texture (`glTexSubImage2D`); rows bottom to top.
    TexSubImage {
        id: u32,
        x: u32,
        y: u32,
        width: u32,
        height: u32,
        data: D,
    },
    /// Level `level` of face `face` of cube texture `id` (`glTexImage2D` on
    /// `GL_TEXTURE_CUBE_MAP_POSITIVE_X + face`), creating the cube texture when `id` is new:
    /// `size × size` RGBA8 (or sRGB8_alpha8) texels, rows bottom to top (GL's `t = 0` first),
    /// zeros without `data`; level `i > 0` is `max(1, size >> i)` of level 0's `size`. Every
    /// face's level 0 has the same size and format. `tex_parameters`, `generate_mipmap` and
    /// `delete_texture` take cube textures too; a mipmap filter samples generated levels, or
    /// levels given down to 1×1 on every face; a cube missing a face samples (0, 0, 0, 1).
    CubeTexImage {
        id: u32,
        face: CubeFace,
        #[serde(default, skip_serializing_if = "is_zero")]
        level: u32,
        size: u32,
        format: TextureFormat,
        #[serde(default = "none", skip_serializing_if = "Option::is_none")]
        data: Option<D>,
    },
    /// Overwrites a rectangle of level 0 of a cube face (`glTexSubImage2D` on a face); rows
    /// bottom to top.
    CubeTexSubImage {
        id: u32,
        face: CubeFace,
        x: u32,
        y: u32,
        width: u32,
        height: u32,
        data: D,
    },
    /// Level 0 of 2-D array or 3-D texture `id` (`glTexImage3D` or `glTexStorage3D` on
    /// `GL_TEXTURE_2D_ARRAY` / `GL_TEXTURE_3D`), creating it when `id` is new: `depth`
    /// layers (slices) of `width × height` RGBA8 (or sRGB8_alpha8) texels one after the
    /// other, each's rows bottom to top (GL's `t = 0` first), zeros without `data`.
    /// `tex_parameters`, `tex_wrap_r`, `generate_mipmap` (2-D arrays only: a 3-D texture's
    /// mip chain is refused) and `delete_texture` take them too.
    LayeredTexImage {
        id: u32,
        target: LayeredTarget,
        width: u32,
        height: u32,
        depth: u32,
        format: TextureFormat,
        #[serde(default = "none", skip_serializing_if = "Option::is_none")]
        data: Option<D>,
    },
    /// Overwrites a box of level 0 of a 2-D array or 3-D texture (`glTexSubImage3D`): layers
    /// `z .. z + depth`, rows bottom to top.
    LayeredTexSubImage {
        id: u32,
        x: u32,
        y: u32,
        z: u32,
        width: u32,
        height: u32,
        depth: u32,
        data: D,
    },
    /// `GL_TEXTURE_WRAP_R` of 3-D texture `id` (kept by `tex_parameters`; 2-D arrays take it
    /// and do not read it).
    TexWrapR {
        id: u32,
        wrap: Wrap,
    },
    /// Sampling state of a texture (`glTexParameteri` for the filters and wraps): `filter`
    /// minifies and `wrap` wraps s; `mag_filter` (default: `filter`'s first word) magnifies and
    /// `wrap_t` (default: `wrap`) wraps t.
    TexParameters {
        id: u32,
        #[serde(default)]
        filter: Filter,
        #[serde(default)]
        wrap: Wrap,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        mag_filter: Option<Filter>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        wrap_t: Option<Wrap>,
    },
    /// Depth comparison of texture `id` (`glTexParameteri` of `GL_TEXTURE_COMPARE_MODE` and
    /// `GL_TEXTURE_COMPARE_FUNC`): with `compare`, a shadow sampler (`sampler2DShadow`)
    /// reading the depth texture gets `reference OP depth` per texel, the results filtered
    /// (see `tiler::depth_compare`); without, it reads the depth. Kept by `tex_parameters`.
    TexCompare {
        id: u32,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        compare: Option<CompareOp>,
    },
    /// A sampler object on texture unit `unit` (`glBindSampler` + `glSamplerParameter*`): the
    /// unit samples its texture with these parameters (as `tex_parameters` and `tex_compare`
    /// take them) instead of the texture's own.
    BindSampler {
        unit: u32,
        #[serde(default)]
        filter: Filter,
        #[serde(default)]
        wrap: Wrap,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        mag_filter: Option<Filter>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        wrap_t: Option<Wrap>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        compare: Option<CompareOp>,
        /// `GL_TEXTURE_WRAP_R` (default `GL_REPEAT`): wraps a 3-D texture's r.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        wrap_r: Option<Wrap>,
    },
    /// `glBindSampler(unit, 0)`: the unit samples with its texture's parameters again.
    UnbindSampler {
        unit: u32,
    },
    /// `glGenerateMipmap`: texture `id` gets a mip chain, each level a bilinear sample of the
    /// one above at each texel's centre (the core's `MipChain::Linear`: Mesa's chain, a 2×2
    /// box filter wherever a side halves exactly), sampled with a `*_mipmap_*` filter. The levels
    /// are made from level 0 as it is when a pass that samples it is rendered, so later
    /// uploads and renders into level 0 reach them too (GL would need another
    /// `glGenerateMipmap`). Textures the core samples (RGBA8, RGB565, 4444, 5551, floats within
    /// [0, 1]); a compressed texture's levels must be given (an error, as GL ES 3.0's
    /// `INVALID_OPERATION`); others sample level 0.
    GenerateMipmap {
        id: u32,
    },
    DeleteTexture {
        id: u32,
    },
    /// Creates renderbuffer `id` (`glGenRenderbuffers` + `glRenderbufferStorageMultisample`);
    /// `transient` as for `create_texture`: no memory, contents live only within a pass.
    CreateRenderbuffer {
        id: u32,
        width: u32,
        height: u32,
        format: TextureFormat,
        #[serde(default = "one")]
        samples: u32,
        #[serde(default, skip_serializing_if = "is_false")]
        transient: bool,
    },
    DeleteRenderbuffer {
        id: u32,
    },

    // --- framebuffers ----------------------------------------------------------------------
    /// Creates framebuffer object `id` with no attachments. Framebuffer 0 is the window's.
    CreateFramebuffer {
        id: u32,
    },
    DeleteFramebuffer {
        id: u32,
    },
    /// Attaches texture `texture` (0 detaches) to `attachment` of framebuffer `framebuffer`
    /// (`glFramebufferTexture2D`). With `samples` above 1 the framebuffer renders that many
    /// samples and resolves them into the texture in the tile
    /// (`glFramebufferTexture2DMultisampleEXT`, EXT_multisampled_render_to_texture).
    FramebufferTexture {
        framebuffer: u32,
        attachment: AttachmentPoint,
        texture: u32,
        #[serde(default = "one", skip_serializing_if = "is_one")]
        samples: u32,
    },
    /// `glFramebufferTextureLayer`: attaches layer `layer` of 2-D array or 3-D texture
    /// `texture` (0 detaches) as a colour attachment.
    FramebufferTextureLayer {
        framebuffer: u32,
        attachment: AttachmentPoint,
        texture: u32,
        layer: u32,
    },
    /// `glCopyTexSubImage3D`: `copy_tex_sub_image` into layer `layer` of 2-D array or 3-D
    /// texture `texture`, through its layer image.
    CopyTexSubImageLayer {
        texture: u32,
        layer: u32,
        x_offset: u32,
        y_offset: u32,
        x: i32,
        y: i32,
        width: u32,
        height: u32,
    },
    /// Attaches a renderbuffer (0 detaches) (`glFramebufferRenderbuffer`).
    FramebufferRenderbuffer {
        framebuffer: u32,
        attachment: AttachmentPoint,
        renderbuffer: u32,
    },
    /// Binds a framebuffer for drawing and reading (`glBindFramebuffer`). Binding another
    /// draw framebuffer ends the render pass of the previous one.
    BindFramebuffer {
        #[serde(default)]
        target: FramebufferTarget,
        framebuffer: u32,
    },

    // --- explicit render passes ---------------------------------------------------------
    /// Binds `framebuffer` for drawing and begins an explicit render pass on it with these
    /// subpasses (Vulkan's `vkCmdBeginRenderPass`; in GL terms, what a driver would infer,
    /// made explicit). Load and store ops are still inferred (a `clear` before the first draw
    /// clears, `invalidate` drops the store, transient attachments are never loaded or
    /// stored); draws go to the current subpass until `next_subpass`. Nothing may end the pass
    /// early: binding another framebuffer, flushes, read-backs and swaps are errors until
    /// `end_pass`.
    BeginPass {
        framebuffer: u32,
        subpasses: Vec<SubpassSpec>,
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        dependencies: Vec<DependencySpec>,
    },
    /// Moves on to the next subpass (`vkCmdNextSubpass`).
    NextSubpass,
    /// Ends the explicit pass in its last subpass and renders it (`vkCmdEndRenderPass`).
    EndPass,

    // --- programs and uniforms -------------------------------------------------------------
    /// Creates program object `id`: a built-in program (see [`ProgramKind`]; its uniforms
    /// start at their defaults), or a GLSL ES program compiled and linked now (`glCreateShader`
    /// … `glLinkProgram`; its uniforms start at zero, as in GL).
    CreateProgram {
        id: u32,
        program: ProgramSource,
    },
    /// `glBindAttribLocation`: GLSL attribute `name` of program `program` reads attribute
    /// `index`. Valid at any time; it applies to the program's later draws (GL applies it at
    /// the next link; the context relinks at once).
    BindAttribLocation {
        program: u32,
        index: u32,
        name: String,
    },
    UseProgram {
        id: u32,
    },
    /// `glDeleteProgram`: a program in use stays until another is used, as in GL; draws
    /// already made keep theirs.
    DeleteProgram {
        id: u32,
    },
    /// Sets a uniform of the program in use (`glUniform*`). For a GLSL program `name` may
    /// name an array element (`lights[2]`; `x` is `x[0]`) or a struct field (`light.color`).
    Uniform {
        name: String,
        value: UniformValue,
    },

    // --- fixed-function state ------------------------------------------------------------
    Viewport {
        x: i32,
        y: i32,
        width: u32,
        height: u32,
    },
    DepthRange {
        near: f32,
        far: f32,
    },
    /// `glLineWidth`: the width in pixels of lines drawn after it.
    LineWidth {
        width: f32,
    },
    /// `glPolygonOffset`: with `polygon_offset_fill` enabled, each triangle's depth moves by
    /// `factor × its largest depth slope + units × r` (`r` the depth format's resolvable
    /// difference; see `tiler::DepthBias`).
    PolygonOffset {
        factor: f32,
        units: f32,
    },
    Scissor {
        x: i32,
        y: i32,
        width: u32,
        height: u32,
    },
    Enable {
        cap: Capability,
    },
    Disable {
        cap: Capability,
    },
    ColorMask {
        red: bool,
        green: bool,
        blue: bool,
        alpha: bool,
    },
    DepthMask {
        write: bool,
    },
    /// `glStencilMaskSeparate`; `face` defaults to both (`glStencilMask`). Clears use the
    /// front mask, as in GL.
    StencilMask {
        mask: u8,
        #[serde(default = "both_faces", skip_serializing_if = "is_both_faces")]
        face: Face,
    },
    DepthFunc {
        func: CompareOp,
    },
    /// `glStencilFuncSeparate`; `face` defaults to both (`glStencilFunc`).
    StencilFunc {
        func: CompareOp,
        reference: u8,
        mask: u8,
        #[serde(default = "both_faces", skip_serializing_if = "is_both_faces")]
        face: Face,
    },
    /// `glStencilOpSeparate`; `face` defaults to both (`glStencilOp`).
    StencilOp {
        fail: tiler::StencilOp,
        depth_fail: tiler::StencilOp,
        pass: tiler::StencilOp,
        #[serde(default = "both_faces", skip_serializing_if = "is_both_faces")]
        face: Face,
    },
    /// `glBlendFuncSeparate`; with only `src` and `dst`, alpha uses the same factors.
    BlendFunc {
        src: BlendFactor,
        dst: BlendFactor,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        src_alpha: Option<BlendFactor>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        dst_alpha: Option<BlendFactor>,
    },
    BlendEquation {
        rgb: BlendOp,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        alpha: Option<BlendOp>,
    },
    BlendColor {
        rgba: [f32; 4],
    },
    CullFace {
        face: Face,
    },
    FrontFace {
        winding: Winding,
    },
    ClearColor {
        rgba: [f32; 4],
    },
    ClearDepth {
        depth: f32,
    },
    ClearStencil {
        stencil: u8,
    },

    // --- vertex input ----------------------------------------------------------------------
    /// Attribute `index` reads buffer `buffer` (`glBindBuffer(GL_ARRAY_BUFFER)` +
    /// `glVertexAttribPointer`): `size` components of `type` every `stride` bytes (0 =
    /// tightly packed) from byte `offset`.
    VertexAttribPointer {
        index: u32,
        buffer: u32,
        size: u32,
        #[serde(rename = "type")]
        component: ComponentType,
        #[serde(default)]
        normalized: bool,
        #[serde(default)]
        stride: u32,
        #[serde(default)]
        offset: u64,
    },
    /// Attribute `index` reads a client-side array (`glVertexAttribPointer` with no buffer
    /// bound): the data is copied at each draw, as a driver must.
    VertexAttribArray {
        index: u32,
        size: u32,
        #[serde(rename = "type")]
        component: ComponentType,
        #[serde(default)]
        normalized: bool,
        #[serde(default)]
        stride: u32,
        data: D,
    },
    EnableVertexAttrib {
        index: u32,
    },
    /// `glVertexAttrib4f`: the value a disabled attribute reads in a GLSL program (initially
    /// `(0, 0, 0, 1)`).
    VertexAttrib {
        index: u32,
        value: [f32; 4],
    },
    /// `glVertexAttribIPointer` with a buffer: as `vertex_attrib_pointer`, the integers kept
    /// as integers for an `int`/`uint` attribute (`type` an integer type).
    VertexAttribIPointer {
        index: u32,
        buffer: u32,
        size: u32,
        #[serde(rename = "type")]
        component: ComponentType,
        #[serde(default)]
        stride: u32,
        #[serde(default)]
        offset: u64,
    },
    /// `glVertexAttribIPointer` into a client-side array (see `vertex_attrib_array`).
    VertexAttribIArray {
        index: u32,
        size: u32,
        #[serde(rename = "type")]
        component: ComponentType,
        #[serde(default)]
        stride: u32,
        data: D,
    },
    /// `glVertexAttribI4i[v]` (`signed`) / `I4ui[v]`: a disabled integer attribute's generic
    /// value, its 32-bit patterns (an `int`'s two's complement).
    VertexAttribI {
        index: u32,
        value: [u32; 4],
        #[serde(default)]
        signed: bool,
    },
    DisableVertexAttrib {
        index: u32,
    },
    /// `glBindBuffer(GL_ELEMENT_ARRAY_BUFFER)`; 0 unbinds.
    BindIndexBuffer {
        buffer: u32,
    },
    /// Attribute `index` advances once every `divisor` instances instead of once per vertex
    /// (`glVertexAttribDivisor`); 0, the default, is per vertex.
    VertexAttribDivisor {
        index: u32,
        divisor: u32,
    },
    /// Creates vertex array object `id` (`glGenVertexArrays`): every attribute disabled,
    /// without a pointer, divisor 0, no index buffer.
    CreateVertexArray {
        id: u32,
    },
    /// `glBindVertexArray`: the attributes' enables, pointers and divisors and the index
    /// buffer binding are those of vertex array `id` until another is bound; 0 is the
    /// default vertex array. Generic values (`vertex_attrib`) are the context's, not the
    /// array's.
    BindVertexArray {
        id: u32,
    },
    /// `glDeleteVertexArrays`; deleting the bound array binds 0.
    DeleteVertexArray {
        id: u32,
    },
    /// `glActiveTexture` + `glBindTexture`; 0 unbinds.
    BindTexture {
        unit: u32,
        texture: u32,
    },
    /// `glActiveTexture` + `glBindTexture(GL_TEXTURE_CUBE_MAP)`: a unit holds a 2D and a cube
    /// texture, `samplerCube` uniforms read the latter; 0 unbinds.
    BindCubeTexture {
        unit: u32,
        texture: u32,
    },
    /// `glActiveTexture` + `glBindTexture(GL_TEXTURE_2D_ARRAY | GL_TEXTURE_3D)`: a unit holds
    /// one texture of each target, `sampler2DArray` / `sampler3D` uniforms read those; 0
    /// unbinds.
    BindLayeredTexture {
        unit: u32,
        target: LayeredTarget,
        texture: u32,
    },

    /// `glUniformBlockBinding`: uniform block `block` (by name) of GLSL program `program`
    /// reads the buffer bound at uniform buffer binding `binding` (initially 0).
    UniformBlockBinding {
        program: u32,
        block: String,
        binding: u32,
    },
    /// `glBindBufferBase` / `glBindBufferRange(GL_UNIFORM_BUFFER)`: uniform buffer binding
    /// `binding` holds buffer `buffer` (0 unbinds) from byte `offset`, `size` bytes (to the
    /// buffer's end without one). A draw reads the blocks' values from it (`std140`).
    BindUniformBuffer {
        binding: u32,
        buffer: u32,
        #[serde(default)]
        offset: u64,
        #[serde(default = "none", skip_serializing_if = "Option::is_none")]
        size: Option<u64>,
    },

    // --- transform feedback -------------------------------------------------------------
    /// `glTransformFeedbackVaryings` as linked: GLSL program `program` captures the vertex
    /// outputs `varyings` (`gl_Position`, `gl_PointSize`, outputs, `a[k]`), in one buffer
    /// (interleaved) or each into the binding of its index (`separate`).
    TransformFeedbackVaryings {
        program: u32,
        varyings: Vec<String>,
        #[serde(default)]
        separate: bool,
    },
    /// `glBindBufferBase` / `glBindBufferRange(GL_TRANSFORM_FEEDBACK_BUFFER)`: transform
    /// feedback binding `binding` (0–3) writes into buffer `buffer` (0 unbinds) from byte
    /// `offset`, at most `size` bytes (to the buffer's end without one).
    BindTransformFeedbackBuffer {
        binding: u32,
        buffer: u32,
        #[serde(default)]
        offset: u64,
        #[serde(default = "none", skip_serializing_if = "Option::is_none")]
        size: Option<u64>,
    },
    /// `glBeginTransformFeedback`: draws of `mode`'s primitives (strips, loops and fans are
    /// taken apart) write the program's captured outputs into the bound buffers, from their
    /// starts, until `end_transform_feedback`.
    BeginTransformFeedback {
        mode: FeedbackMode,
    },
    EndTransformFeedback,
    /// `glPauseTransformFeedback`: draws capture nothing until resumed.
    PauseTransformFeedback,
    ResumeTransformFeedback,

    // --- drawing ---------------------------------------------------------------------------
    DrawArrays {
        mode: Mode,
        first: u32,
        count: u32,
    },
    DrawElements {
        mode: Mode,
        count: u32,
        #[serde(rename = "type")]
        index_type: IndexKind,
        #[serde(default)]
        offset: u64,
    },
    /// `glDrawArraysInstanced`: `instances` copies of the draw; attributes with a divisor
    /// read element `instance / divisor`, and `gl_InstanceID` is the copy's number.
    DrawArraysInstanced {
        mode: Mode,
        first: u32,
        count: u32,
        instances: u32,
    },
    /// `glDrawElementsInstanced`, as `draw_arrays_instanced`.
    DrawElementsInstanced {
        mode: Mode,
        count: u32,
        #[serde(rename = "type")]
        index_type: IndexKind,
        #[serde(default)]
        offset: u64,
        instances: u32,
    },
    /// `glDrawBuffers` on the bound draw framebuffer: draws write colour outputs `0..count`
    /// to colour attachments `0..count` (GL's default is 1; the window takes only 1).
    DrawBuffers {
        count: u32,
    },
    /// `glClear` of the buffers set to `true`.
    Clear {
        #[serde(default)]
        color: bool,
        #[serde(default)]
        depth: bool,
        #[serde(default)]
        stencil: bool,
    },
    /// `glInvalidateFramebuffer` / `glDiscardFramebufferEXT` on the draw framebuffer.
    Invalidate {
        attachments: Vec<AttachmentPoint>,
    },
    /// `glClearBuffer{f,i,ui}v(GL_COLOR, draw_buffer, value)`: colour attachment
    /// `draw_buffer` of the draw framebuffer's draw buffers cleared to `value`, which must
    /// match its format (floats for fixed-point and float formats, ints or uints for integer
    /// ones), under the scissor and the colour write mask as `clear` is.
    ClearBufferColor {
        draw_buffer: u32,
        value: ClearColorValue,
    },
    /// `glClearBufferfv(GL_DEPTH)`, `glClearBufferiv(GL_STENCIL)`, `glClearBufferfi`: the
    /// depth and/or the stencil cleared to these values, as `clear` does with them.
    ClearBufferDepthStencil {
        #[serde(default)]
        depth: Option<f32>,
        #[serde(default)]
        stencil: Option<u8>,
    },
    /// `glReadPixels(GL_RGBA_INTEGER, GL_INT or GL_UNSIGNED_INT)` of an integer colour
    /// attachment 0 (`signed` must match its format): 16 bytes a pixel, the four channels'
    /// 32-bit little-endian integers (missing ones 0, alpha 1), rows bottom to top.
    ReadPixelsInteger {
        x: i32,
        y: i32,
        width: u32,
        height: u32,
        #[serde(default)]
        signed: bool,
    },
    /// `glReadPixels` of colour attachment 0 of the read framebuffer, as RGBA8, rows bottom
    /// to top. Synchronous: the CPU waits for the result.
    ReadPixels {
        x: i32,
        y: i32,
        width: u32,
        height: u32,
    },
    /// `glBlitFramebuffer` of colour from the read to the draw framebuffer; rectangles are
    /// `[x0, y0, x1, y1]`.
    BlitFramebuffer {
        src: [i32; 4],
        dst: [i32; 4],
        #[serde(default)]
        filter: Filter,
    },
    /// `glCopyTexSubImage2D`: copies a rectangle of the read framebuffer's colour into a
    /// texture at (`x_offset`, `y_offset`). With `alpha_one` the copied texels' alpha is 1:
    /// a texture whose GL format has no alpha (`glCopyTexImage2D` with `GL_RGB`).
    CopyTexSubImage {
        texture: u32,
        x_offset: u32,
        y_offset: u32,
        x: i32,
        y: i32,
        width: u32,
        height: u32,
        #[serde(default, skip_serializing_if = "is_false")]
        alpha_one: bool,
    },
    Flush,
    Finish,
    /// `glFenceSync`: fence `id` after the commands so far.
    FenceSync {
        id: u32,
    },
    /// `glClientWaitSync` that waits: the CPU waits until the GPU has done the commands before
    /// fence `id` (the pass holding them is flushed if it is still open).
    ClientWaitSync {
        id: u32,
    },
    DeleteSync {
        id: u32,
    },
    /// `eglSwapBuffers`: ends the frame. In a trace it is the last call of a frame.
    SwapBuffers,
    /// Not a GL call: puts back the fixed-function and binding state a context had at some
    /// point ([`Context::saved_state`](crate::Context::saved_state)), the bound framebuffers
    /// included. The advisor's what-if uses it to move calls with the state they ran in. It is
    /// written to JSON without its state and cannot be read back.
    #[serde(skip_deserializing)]
    RestoreState {
        #[serde(skip_serializing)]
        state: crate::context::SavedState,
    },
    /// `eglSurfaceAttrib(EGL_SWAP_BEHAVIOR)`.
    SwapBehavior {
        behavior: SwapBehavior,
    },
    /// The window changed size: the window surface gets new colour and depth-stencil images of
    /// this size, whose contents are undefined (EGL resizes a window surface to its window's
    /// size, OpenGL ES 3.0 §2.1.1 leaves when to the platform).
    ResizeSurface {
        width: u32,
        height: u32,
    },
    /// `eglCreateContext` sharing every object with the contexts already made: a context
    /// `id` with GL state of its own (the defaults, the viewport and scissor the window's), not
    /// current yet. Context 0 is made with the context and is current at the start.
    ///
    /// What is each context's (OpenGL ES 3.0 appendix D): the fixed-function state, the
    /// bound framebuffers, program, texture units and sampler objects, uniform buffer
    /// bindings, the default vertex array and the one bound, generic vertex attributes, the
    /// active query and transform feedback. Buffers, textures, renderbuffers, programs,
    /// framebuffers, vertex arrays and queries are named in one space all contexts share.
    CreateContext {
        id: u32,
    },
    /// `eglMakeCurrent`: calls from now on use context `id`'s GL state. Not a flush: a pass
    /// ends only if the context's draw framebuffer is another one (as `bind_framebuffer`
    /// would end it).
    MakeCurrent {
        id: u32,
    },
    /// `eglDestroyContext` of a context that is not current: its GL state goes (its objects
    /// stay, as the share group's).
    DestroyContext {
        id: u32,
    },
    /// `glStartTilingQCOM`: until `end_tiling`, only the tiles meeting this rectangle are
    /// processed; `preserve` says which buffers' contents there must be loaded.
    StartTiling {
        x: i32,
        y: i32,
        width: u32,
        height: u32,
        #[serde(default)]
        preserve: BufferSet,
    },
    /// `glEndTilingQCOM`: which buffers to store.
    EndTiling {
        #[serde(default)]
        store: BufferSet,
    },

    // --- occlusion queries -----------------------------------------------------------------
    CreateQuery {
        id: u32,
    },
    DeleteQuery {
        id: u32,
    },
    /// `glBeginQuery(GL_ANY_SAMPLES_PASSED)`: counts samples passing depth and stencil.
    BeginQuery {
        id: u32,
    },
    EndQuery,
    /// `glGetQueryObjectuiv(GL_QUERY_RESULT_AVAILABLE)`: never waits.
    QueryAvailable {
        id: u32,
    },
    /// `glGetQueryObjectuiv(GL_QUERY_RESULT)`: waits if it must (and flushes a pending pass
    /// holding the query).
    QueryResult {
        id: u32,
    },
}

fn one() -> u32 {
    1
}

fn is_one(v: &u32) -> bool {
    *v == 1
}

fn is_zero(v: &u32) -> bool {
    *v == 0
}

fn is_false(v: &bool) -> bool {
    !*v
}

fn none<T>() -> Option<T> {
    None
}

fn both_faces() -> Face {
    Face::FrontAndBack
}

fn is_both_faces(face: &Face) -> bool {
    *face == Face::FrontAndBack
}

impl<D> Call<D> {
    /// The call's name as a trace spells it.
    pub fn name(&self) -> &'static str {
        use Call::*;
        match self {
            CreateBuffer { .. } => "create_buffer",
            BufferData { .. } => "buffer_data",
            BufferSubData { .. } => "buffer_sub_data",
            DeleteBuffer { .. } => "delete_buffer",
            CopyBufferSubData { .. } => "copy_buffer_sub_data",
            CreateTexture { .. } => "create_texture",
            TexImage { .. } => "tex_image",
            TexImageLevel { .. } => "tex_image_level",
            EncodedTexImage { .. } => "encoded_tex_image",
            EncodedTexSubImage { .. } => "encoded_tex_sub_image",
            TexSubImage { .. } => "tex_sub_image",
            CubeTexImage { .. } => "cube_tex_image",
            CubeTexSubImage { .. } => "cube_tex_sub_image",
            LayeredTexImage { .. } => "layered_tex_image",
            LayeredTexSubImage { .. } => "layered_tex_sub_image",
            TexWrapR { .. } => "tex_wrap_r",
            TexParameters { .. } => "tex_parameters",
            TexCompare { .. } => "tex_compare",
            BindSampler { .. } => "bind_sampler",
            UnbindSampler { .. } => "unbind_sampler",
            GenerateMipmap { .. } => "generate_mipmap",
            DeleteTexture { .. } => "delete_texture",
            CreateRenderbuffer { .. } => "create_renderbuffer",
            DeleteRenderbuffer { .. } => "delete_renderbuffer",
            CreateFramebuffer { .. } => "create_framebuffer",
            DeleteFramebuffer { .. } => "delete_framebuffer",
            FramebufferTexture { .. } => "framebuffer_texture",
            FramebufferTextureLayer { .. } => "framebuffer_texture_layer",
            CopyTexSubImageLayer { .. } => "copy_tex_sub_image_layer",
            FramebufferRenderbuffer { .. } => "framebuffer_renderbuffer",
            BindFramebuffer { .. } => "bind_framebuffer",
            BeginPass { .. } => "begin_pass",
            NextSubpass => "next_subpass",
            EndPass => "end_pass",
            CreateProgram { .. } => "create_program",
            BindAttribLocation { .. } => "bind_attrib_location",
            UseProgram { .. } => "use_program",
            DeleteProgram { .. } => "delete_program",
            Uniform { .. } => "uniform",
            Viewport { .. } => "viewport",
            DepthRange { .. } => "depth_range",
            PolygonOffset { .. } => "polygon_offset",
            LineWidth { .. } => "line_width",
            Scissor { .. } => "scissor",
            Enable { .. } => "enable",
            Disable { .. } => "disable",
            ColorMask { .. } => "color_mask",
            DepthMask { .. } => "depth_mask",
            StencilMask { .. } => "stencil_mask",
            DepthFunc { .. } => "depth_func",
            StencilFunc { .. } => "stencil_func",
            StencilOp { .. } => "stencil_op",
            BlendFunc { .. } => "blend_func",
            BlendEquation { .. } => "blend_equation",
            BlendColor { .. } => "blend_color",
            CullFace { .. } => "cull_face",
            FrontFace { .. } => "front_face",
            ClearColor { .. } => "clear_color",
            ClearDepth { .. } => "clear_depth",
            ClearStencil { .. } => "clear_stencil",
            VertexAttribPointer { .. } => "vertex_attrib_pointer",
            VertexAttribArray { .. } => "vertex_attrib_array",
            EnableVertexAttrib { .. } => "enable_vertex_attrib",
            VertexAttrib { .. } => "vertex_attrib",
            VertexAttribIPointer { .. } => "vertex_attrib_i_pointer",
            VertexAttribIArray { .. } => "vertex_attrib_i_array",
            VertexAttribI { .. } => "vertex_attrib_i",
            ClearBufferColor { .. } => "clear_buffer_color",
            ClearBufferDepthStencil { .. } => "clear_buffer_depth_stencil",
            DisableVertexAttrib { .. } => "disable_vertex_attrib",
            BindIndexBuffer { .. } => "bind_index_buffer",
            VertexAttribDivisor { .. } => "vertex_attrib_divisor",
            CreateVertexArray { .. } => "create_vertex_array",
            BindVertexArray { .. } => "bind_vertex_array",
            DeleteVertexArray { .. } => "delete_vertex_array",
            UniformBlockBinding { .. } => "uniform_block_binding",
            BindUniformBuffer { .. } => "bind_uniform_buffer",
            BindTexture { .. } => "bind_texture",
            BindCubeTexture { .. } => "bind_cube_texture",
            BindLayeredTexture { .. } => "bind_layered_texture",
            DrawArrays { .. } => "draw_arrays",
            DrawElements { .. } => "draw_elements",
            TransformFeedbackVaryings { .. } => "transform_feedback_varyings",
            BindTransformFeedbackBuffer { .. } => "bind_transform_feedback_buffer",
            BeginTransformFeedback { .. } => "begin_transform_feedback",
            EndTransformFeedback => "end_transform_feedback",
            PauseTransformFeedback => "pause_transform_feedback",
            ResumeTransformFeedback => "resume_transform_feedback",
            DrawArraysInstanced { .. } => "draw_arrays_instanced",
            DrawElementsInstanced { .. } => "draw_elements_instanced",
            DrawBuffers { .. } => "draw_buffers",
            Clear { .. } => "clear",
            Invalidate { .. } => "invalidate",
            ReadPixels { .. } => "read_pixels",
            ReadPixelsInteger { .. } => "read_pixels_integer",
            BlitFramebuffer { .. } => "blit_framebuffer",
            CopyTexSubImage { .. } => "copy_tex_sub_image",
            Flush => "flush",
            Finish => "finish",
            FenceSync { .. } => "fence_sync",
            ClientWaitSync { .. } => "client_wait_sync",
            DeleteSync { .. } => "delete_sync",
            SwapBuffers => "swap_buffers",
            RestoreState { .. } => "restore_state",
            SwapBehavior { .. } => "swap_behavior",
            ResizeSurface { .. } => "resize_surface",
            CreateContext { .. } => "create_context",
            MakeCurrent { .. } => "make_current",
            DestroyContext { .. } => "destroy_context",
            StartTiling { .. } => "start_tiling",
            EndTiling { .. } => "end_tiling",
            CreateQuery { .. } => "create_query",
            DeleteQuery { .. } => "delete_query",
            BeginQuery { .. } => "begin_query",
            EndQuery => "end_query",
            QueryAvailable { .. } => "query_available",
            QueryResult { .. } => "query_result",
        }
    }

    /// The same call with its bulk data converted by `f` (e.g. a trace's data sources read
    /// into bytes, or bytes written out to a side file).
    ///
    /// # Errors
    /// The first error `f` returns.
    pub fn try_map_data<E, Err>(self, mut f: impl FnMut(D) -> Result<E, Err>) -> Result<Call<E>, Err> {
        use Call::*;
        Ok(match self {
            CreateBuffer { id, data } => CreateBuffer { id, data: f(data)? },
            BufferData { id, data } => BufferData { id, data: f(data)? },
            BufferSubData { id, offset, data } => BufferSubData { id, offset, data: f(data)? },
            CreateTexture { id, width, height, format, data, transient } => {
                CreateTexture { id, width, height, format, data: data.map(&mut f).transpose()?, transient }
            }
            TexImage { id, width, height, format, data } => {
                TexImage { id, width, height, format, data: data.map(&mut f).transpose()? }
            }
            TexImageLevel { id, level, width, height, data } => {
                TexImageLevel { id, level, width, height, data: f(data)? }
            }
            TexSubImage { id, x, y, width, height, data } => TexSubImage { id, x, y, width, height, data: f(data)? },
            CubeTexImage { id, face, level, size, format, data } => {
                CubeTexImage { id, face, level, size, format, data: data.map(&mut f).transpose()? }
            }
            CubeTexSubImage { id, face, x, y, width, height, data } => {
                CubeTexSubImage { id, face, x, y, width, height, data: f(data)? }
            }
            LayeredTexImage { id, target, width, height, depth, format, data } => {
                LayeredTexImage { id, target, width, height, depth, format, data: data.map(&mut f).transpose()? }
            }
            LayeredTexSubImage { id, x, y, z, width, height, depth, data } => {
                LayeredTexSubImage { id, x, y, z, width, height, depth, data: f(data)? }
            }
            TexWrapR { id, wrap } => TexWrapR { id, wrap },
            EncodedTexImage { id, level, width, height, format, srgb, data } => {
                EncodedTexImage { id, level, width, height, format, srgb, data: f(data)? }
            }
            EncodedTexSubImage { id, x, y, width, height, format, data } => {
                EncodedTexSubImage { id, x, y, width, height, format, data: f(data)? }
            }
            VertexAttribArray { index, size, component, normalized, stride, data } => {
                VertexAttribArray { index, size, component, normalized, stride, data: f(data)? }
            }
            VertexAttribIArray { index, size, component, stride, data } => {
                VertexAttribIArray { index, size, component, stride, data: f(data)? }
            }
            DeleteBuffer { id } => DeleteBuffer { id },
            CopyBufferSubData { src, dst, src_offset, dst_offset, size } => {
                CopyBufferSubData { src, dst, src_offset, dst_offset, size }
            }
            TexParameters { id, filter, wrap, mag_filter, wrap_t } => {
                TexParameters { id, filter, wrap, mag_filter, wrap_t }
            }
            TexCompare { id, compare } => TexCompare { id, compare },
            BindSampler { unit, filter, wrap, mag_filter, wrap_t, compare, wrap_r } => {
                BindSampler { unit, filter, wrap, mag_filter, wrap_t, compare, wrap_r }
            }
            UnbindSampler { unit } => UnbindSampler { unit },
            GenerateMipmap { id } => GenerateMipmap { id },
            DeleteTexture { id } => DeleteTexture { id },
            CreateRenderbuffer { id, width, height, format, samples, transient } => {
                CreateRenderbuffer { id, width, height, format, samples, transient }
            }
            DeleteRenderbuffer { id } => DeleteRenderbuffer { id },
            CreateFramebuffer { id } => CreateFramebuffer { id },
            DeleteFramebuffer { id } => DeleteFramebuffer { id },
            FramebufferTexture { framebuffer, attachment, texture, samples } => {
                FramebufferTexture { framebuffer, attachment, texture, samples }
            }
            FramebufferTextureLayer { framebuffer, attachment, texture, layer } => {
                FramebufferTextureLayer { framebuffer, attachment, texture, layer }
            }
            CopyTexSubImageLayer { texture, layer, x_offset, y_offset, x, y, width, height } => {
                CopyTexSubImageLayer { texture, layer, x_offset, y_offset, x, y, width, height }
            }
            FramebufferRenderbuffer { framebuffer, attachment, renderbuffer } => {
                FramebufferRenderbuffer { framebuffer, attachment, renderbuffer }
            }
            BindFramebuffer { target, framebuffer } => BindFramebuffer { target, framebuffer },
            BeginPass { framebuffer, subpasses, dependencies } => BeginPass { framebuffer, subpasses, dependencies },
            NextSubpass => NextSubpass,
            EndPass => EndPass,
            CreateProgram { id, program } => CreateProgram { id, program },
            BindAttribLocation { program, index, name } => BindAttribLocation { program, index, name },
            UseProgram { id } => UseProgram { id },
            DeleteProgram { id } => DeleteProgram { id },
            Uniform { name, value } => Uniform { name, value },
            Viewport { x, y, width, height } => Viewport { x, y, width, height },
            DepthRange { near, far } => DepthRange { near, far },
            PolygonOffset { factor, units } => PolygonOffset { factor, units },
            LineWidth { width } => LineWidth { width },
            Scissor { x, y, width, height } => Scissor { x, y, width, height },
            Enable { cap } => Enable { cap },
            Disable { cap } => Disable { cap },
            ColorMask { red, green, blue, alpha } => ColorMask { red, green, blue, alpha },
            DepthMask { write } => DepthMask { write },
            StencilMask { mask, face } => StencilMask { mask, face },
            DepthFunc { func } => DepthFunc { func },
            StencilFunc { func, reference, mask, face } => StencilFunc { func, reference, mask, face },
            StencilOp { fail, depth_fail, pass, face } => StencilOp { fail, depth_fail, pass, face },
            BlendFunc { src, dst, src_alpha, dst_alpha } => BlendFunc { src, dst, src_alpha, dst_alpha },
            BlendEquation { rgb, alpha } => BlendEquation { rgb, alpha },
            BlendColor { rgba } => BlendColor { rgba },
            CullFace { face } => CullFace { face },
            FrontFace { winding } => FrontFace { winding },
            ClearColor { rgba } => ClearColor { rgba },
            ClearDepth { depth } => ClearDepth { depth },
            ClearStencil { stencil } => ClearStencil { stencil },
            VertexAttribPointer { index, buffer, size, component, normalized, stride, offset } => {
                VertexAttribPointer { index, buffer, size, component, normalized, stride, offset }
            }
            EnableVertexAttrib { index } => EnableVertexAttrib { index },
            VertexAttrib { index, value } => VertexAttrib { index, value },
            VertexAttribIPointer { index, buffer, size, component, stride, offset } => {
                VertexAttribIPointer { index, buffer, size, component, stride, offset }
            }
            VertexAttribI { index, value, signed } => VertexAttribI { index, value, signed },
            ClearBufferColor { draw_buffer, value } => ClearBufferColor { draw_buffer, value },
            ClearBufferDepthStencil { depth, stencil } => ClearBufferDepthStencil { depth, stencil },
            DisableVertexAttrib { index } => DisableVertexAttrib { index },
            BindIndexBuffer { buffer } => BindIndexBuffer { buffer },
            VertexAttribDivisor { index, divisor } => VertexAttribDivisor { index, divisor },
            CreateVertexArray { id } => CreateVertexArray { id },
            BindVertexArray { id } => BindVertexArray { id },
            DeleteVertexArray { id } => DeleteVertexArray { id },
            UniformBlockBinding { program, block, binding } => UniformBlockBinding { program, block, binding },
            BindUniformBuffer { binding, buffer, offset, size } => BindUniformBuffer { binding, buffer, offset, size },
            BindTexture { unit, texture } => BindTexture { unit, texture },
            BindCubeTexture { unit, texture } => BindCubeTexture { unit, texture },
            BindLayeredTexture { unit, target, texture } => BindLayeredTexture { unit, target, texture },
            DrawArrays { mode, first, count } => DrawArrays { mode, first, count },
            DrawElements { mode, count, index_type, offset } => DrawElements { mode, count, index_type, offset },
            TransformFeedbackVaryings { program, varyings, separate } => {
                TransformFeedbackVaryings { program, varyings, separate }
            }
            BindTransformFeedbackBuffer { binding, buffer, offset, size } => {
                BindTransformFeedbackBuffer { binding, buffer, offset, size }
            }
            BeginTransformFeedback { mode } => BeginTransformFeedback { mode },
            EndTransformFeedback => EndTransformFeedback,
            PauseTransformFeedback => PauseTransformFeedback,
            ResumeTransformFeedback => ResumeTransformFeedback,
            DrawArraysInstanced { mode, first, count, instances } => {
                DrawArraysInstanced { mode, first, count, instances }
            }
            DrawElementsInstanced { mode, count, index_type, offset, instances } => {
                DrawElementsInstanced { mode, count, index_type, offset, instances }
            }
            DrawBuffers { count } => DrawBuffers { count },
            Clear { color, depth, stencil } => Clear { color, depth, stencil },
            Invalidate { attachments } => Invalidate { attachments },
            ReadPixels { x, y, width, height } => ReadPixels { x, y, width, height },
            ReadPixelsInteger { x, y, width, height, signed } => ReadPixelsInteger { x, y, width, height, signed },
            BlitFramebuffer { src, dst, filter } => BlitFramebuffer { src, dst, filter },
            CopyTexSubImage { texture, x_offset, y_offset, x, y, width, height, alpha_one } => {
                CopyTexSubImage { texture, x_offset, y_offset, x, y, width, height, alpha_one }
            }
            Flush => Flush,
            Finish => Finish,
            FenceSync { id } => FenceSync { id },
            ClientWaitSync { id } => ClientWaitSync { id },
            DeleteSync { id } => DeleteSync { id },
            SwapBuffers => SwapBuffers,
            RestoreState { state } => RestoreState { state },
            SwapBehavior { behavior } => SwapBehavior { behavior },
            ResizeSurface { width, height } => ResizeSurface { width, height },
            CreateContext { id } => CreateContext { id },
            MakeCurrent { id } => MakeCurrent { id },
            DestroyContext { id } => DestroyContext { id },
            StartTiling { x, y, width, height, preserve } => StartTiling { x, y, width, height, preserve },
            EndTiling { store } => EndTiling { store },
            CreateQuery { id } => CreateQuery { id },
            DeleteQuery { id } => DeleteQuery { id },
            BeginQuery { id } => BeginQuery { id },
            EndQuery => EndQuery,
            QueryAvailable { id } => QueryAvailable { id },
            QueryResult { id } => QueryResult { id },
        })
    }
}

/// The value of a `glClearBuffer*v` of a colour buffer.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ClearColorValue {
    Float([f32; 4]),
    Int([i32; 4]),
    Uint([u32; 4]),
}

/// What a call returns.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Output {
    None,
    /// `read_pixels`: RGBA8, rows bottom to top.
    Pixels(Vec<u8>),
    /// `query_available`.
    Available(bool),
    /// `query_result`: samples that passed.
    Samples(u64),
}

/// Image formats of textures and renderbuffers, with GL's names.
///
/// tiler has one packed depth-stencil format (`D24UnormS8Uint`) and no stencil-only format,
/// so `depth24` is a packed image whose stencil byte is padding and `stencil8` one whose
/// depth bytes are padding: a padding aspect is never loaded or stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TextureFormat {
    Rgba8,
    Srgb8Alpha8,
    Rgb565,
    Rgba16f,
    Rgba32f,
    R32f,
    Depth16,
    Depth24,
    Depth32f,
    Depth24Stencil8,
    Stencil8,
    /// GL ES 3.0's integer formats (`rgba8ui`, `r32i`, …).
    Int(tiler::IntFormat),
}

impl TextureFormat {
    /// The tiler format that stores it.
    pub fn format(self) -> tiler::Format {
        use tiler::Format;
        match self {
            TextureFormat::Rgba8 => Format::Rgba8Unorm,
            TextureFormat::Srgb8Alpha8 => Format::Rgba8UnormSrgb,
            TextureFormat::Rgb565 => Format::Rgb565Unorm,
            TextureFormat::Rgba16f => Format::Rgba16Float,
            TextureFormat::Rgba32f => Format::Rgba32Float,
            TextureFormat::R32f => Format::R32Float,
            TextureFormat::Depth16 => Format::D16Unorm,
            TextureFormat::Depth24 | TextureFormat::Depth24Stencil8 | TextureFormat::Stencil8 => Format::D24UnormS8Uint,
            TextureFormat::Depth32f => Format::D32Float,
            TextureFormat::Int(f) => Format::Int(f),
        }
    }

    /// Whether the GL format has a depth aspect (padding does not count).
    pub fn has_depth(self) -> bool {
        matches!(
            self,
            TextureFormat::Depth16 | TextureFormat::Depth24 | TextureFormat::Depth32f | TextureFormat::Depth24Stencil8
        )
    }

    /// Whether the GL format has a stencil aspect (padding does not count).
    pub fn has_stencil(self) -> bool {
        matches!(self, TextureFormat::Depth24Stencil8 | TextureFormat::Stencil8)
    }

    pub fn is_color(self) -> bool {
        !self.has_depth() && !self.has_stencil()
    }

    pub fn name(self) -> &'static str {
        match self {
            TextureFormat::Rgba8 => "rgba8",
            TextureFormat::Srgb8Alpha8 => "srgb8_alpha8",
            TextureFormat::Rgb565 => "rgb565",
            TextureFormat::Rgba16f => "rgba16f",
            TextureFormat::Rgba32f => "rgba32f",
            TextureFormat::R32f => "r32f",
            TextureFormat::Depth16 => "depth16",
            TextureFormat::Depth24 => "depth24",
            TextureFormat::Depth32f => "depth32f",
            TextureFormat::Depth24Stencil8 => "depth24_stencil8",
            TextureFormat::Stencil8 => "stencil8",
            TextureFormat::Int(f) => f.name(),
        }
    }
}

/// Formats of `encoded_tex_image`: textures tiler samples (decoded) but does not render to,
/// with GL's names (`GL_COMPRESSED_RGBA8_ETC2_EAC` is `etc2_rgba8`, `GL_ETC1_RGB8_OES`
/// `etc1_rgb8`, `GL_COMPRESSED_RGBA_ASTC_6x6_KHR` `astc_6x6`, `GL_UNSIGNED_SHORT_4_4_4_4`
/// texels `rgba4444`). See the core's `TexelFormat` for how each decodes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EncodedFormat {
    Rgba4444,
    Rgba5551,
    /// `GL_UNSIGNED_INT_2_10_10_10_REV` texels (`GL_RGB10_A2`).
    #[serde(rename = "rgb10_a2")]
    Rgb10A2,
    /// `GL_UNSIGNED_INT_10F_11F_11F_REV` texels (`GL_R11F_G11F_B10F`).
    #[serde(rename = "r11f_g11f_b10f")]
    R11fG11fB10f,
    /// `GL_UNSIGNED_INT_5_9_9_9_REV` texels (`GL_RGB9_E5`).
    #[serde(rename = "rgb9_e5")]
    Rgb9E5,
    /// `EXT_texture_norm16`'s 16-bit normalised `R16`, `RG16`, `RGB16`, `RGBA16` of
    /// `GL_UNSIGNED_SHORT` texels.
    R16,
    Rg16,
    Rgb16,
    Rgba16,
    Etc1Rgb8,
    Etc2Rgb8,
    #[serde(rename = "etc2_rgb8_a1")]
    Etc2Rgb8A1,
    Etc2Rgba8,
    EacR11,
    EacRg11,
    #[serde(rename = "astc_4x4")]
    Astc4x4,
    #[serde(rename = "astc_5x4")]
    Astc5x4,
    #[serde(rename = "astc_5x5")]
    Astc5x5,
    #[serde(rename = "astc_6x5")]
    Astc6x5,
    #[serde(rename = "astc_6x6")]
    Astc6x6,
    #[serde(rename = "astc_8x5")]
    Astc8x5,
    #[serde(rename = "astc_8x6")]
    Astc8x6,
    #[serde(rename = "astc_8x8")]
    Astc8x8,
    #[serde(rename = "astc_10x5")]
    Astc10x5,
    #[serde(rename = "astc_10x6")]
    Astc10x6,
    #[serde(rename = "astc_10x8")]
    Astc10x8,
    #[serde(rename = "astc_10x10")]
    Astc10x10,
    #[serde(rename = "astc_12x10")]
    Astc12x10,
    #[serde(rename = "astc_12x12")]
    Astc12x12,
}

impl EncodedFormat {
    /// The ASTC formats in GL's enum order (`0x93B0` + index), the footprints of
    /// `tiler::ASTC_FOOTPRINTS`.
    pub const ASTC: [EncodedFormat; 14] = [
        EncodedFormat::Astc4x4,
        EncodedFormat::Astc5x4,
        EncodedFormat::Astc5x5,
        EncodedFormat::Astc6x5,
        EncodedFormat::Astc6x6,
        EncodedFormat::Astc8x5,
        EncodedFormat::Astc8x6,
        EncodedFormat::Astc8x8,
        EncodedFormat::Astc10x5,
        EncodedFormat::Astc10x6,
        EncodedFormat::Astc10x8,
        EncodedFormat::Astc10x10,
        EncodedFormat::Astc12x10,
        EncodedFormat::Astc12x12,
    ];

    /// The core's format.
    pub fn texel_format(self) -> tiler::TexelFormat {
        use tiler::TexelFormat as T;
        match self {
            EncodedFormat::Rgba4444 => T::Rgba4444,
            EncodedFormat::Rgba5551 => T::Rgba5551,
            EncodedFormat::Rgb10A2 => T::Rgb10A2,
            EncodedFormat::R11fG11fB10f => T::Rg11B10Float,
            EncodedFormat::Rgb9E5 => T::Rgb9E5,
            EncodedFormat::R16 => T::R16,
            EncodedFormat::Rg16 => T::Rg16,
            EncodedFormat::Rgb16 => T::Rgb16,
            EncodedFormat::Rgba16 => T::Rgba16,
            EncodedFormat::Etc1Rgb8 => T::Etc1Rgb8,
            EncodedFormat::Etc2Rgb8 => T::Etc2Rgb8,
            EncodedFormat::Etc2Rgb8A1 => T::Etc2Rgb8A1,
            EncodedFormat::Etc2Rgba8 => T::Etc2Rgba8,
            EncodedFormat::EacR11 => T::EacR11,
            EncodedFormat::EacRg11 => T::EacRg11,
            astc => {
                let index = EncodedFormat::ASTC.iter().position(|&f| f == astc).expect("the rest are ASTC");
                let (block_width, block_height) = tiler::ASTC_FOOTPRINTS[index];
                T::Astc { block_width, block_height }
            }
        }
    }
}

/// Where an image is attached to a framebuffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AttachmentPoint {
    Color0,
    Color1,
    Color2,
    Color3,
    Depth,
    Stencil,
    /// Both depth and stencil (`GL_DEPTH_STENCIL_ATTACHMENT`).
    DepthStencil,
}

impl AttachmentPoint {
    /// The point as a trace spells it.
    pub fn name(self) -> &'static str {
        match self {
            AttachmentPoint::Color0 => "color0",
            AttachmentPoint::Color1 => "color1",
            AttachmentPoint::Color2 => "color2",
            AttachmentPoint::Color3 => "color3",
            AttachmentPoint::Depth => "depth",
            AttachmentPoint::Stencil => "stencil",
            AttachmentPoint::DepthStencil => "depth_stencil",
        }
    }

    pub fn color_index(self) -> Option<usize> {
        match self {
            AttachmentPoint::Color0 => Some(0),
            AttachmentPoint::Color1 => Some(1),
            AttachmentPoint::Color2 => Some(2),
            AttachmentPoint::Color3 => Some(3),
            _ => None,
        }
    }
}

/// Which framebuffer binding a `bind_framebuffer` sets.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FramebufferTarget {
    /// Both draw and read (`GL_FRAMEBUFFER`).
    #[default]
    Framebuffer,
    Draw,
    Read,
}

/// A set of framebuffer buffers (for tiled rendering's preserve and store masks).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BufferSet {
    #[serde(default)]
    pub color: bool,
    #[serde(default)]
    pub depth: bool,
    #[serde(default)]
    pub stencil: bool,
}

impl BufferSet {
    pub const NONE: BufferSet = BufferSet { color: false, depth: false, stencil: false };
    pub const COLOR: BufferSet = BufferSet { color: true, depth: false, stencil: false };
    pub const ALL: BufferSet = BufferSet { color: true, depth: true, stencil: true };
}

/// One subpass of a `begin_pass` (Vulkan's `VkSubpassDescription`), naming the
/// framebuffer's attachments by their GL attachment points.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SubpassSpec {
    /// Colour attachments written (`color0` … `color3`); the program's output goes to the
    /// first.
    #[serde(default)]
    pub color: Vec<AttachmentPoint>,
    /// Whether depth and stencil tests use the framebuffer's depth-stencil attachment.
    #[serde(default)]
    pub depth_stencil: bool,
    /// Input attachments, read at the same pixel by programs that read inputs (`composite`):
    /// `color0` … `color3`, or `depth` / `stencil` / `depth_stencil` (the depth-stencil attachment, read as
    /// `(depth, stencil, 0, 1)`).
    #[serde(default)]
    pub input: Vec<AttachmentPoint>,
}

/// An ordering between two subpasses of a `begin_pass` (Vulkan's `VkSubpassDependency`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DependencySpec {
    pub src: u32,
    pub dst: u32,
    /// `dst` reads only what `src` wrote at the same pixel (`VK_DEPENDENCY_BY_REGION_BIT`):
    /// both stay in the tile. Without it a tiler finishes `src` everywhere first, storing and
    /// reloading every attachment through memory.
    #[serde(default)]
    pub by_region: bool,
}

/// `glEnable` capabilities.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Capability {
    DepthTest,
    StencilTest,
    Blend,
    CullFace,
    ScissorTest,
    PolygonOffsetFill,
    /// GL ES 3.0's `GL_PRIMITIVE_RESTART_FIXED_INDEX`: the largest value of an indexed draw's
    /// index type ends the primitive being assembled and starts a new one.
    PrimitiveRestartFixedIndex,
    /// GL ES 3.0's `GL_RASTERIZER_DISCARD`: draws stop after the vertex shader (and transform
    /// feedback); they and clears touch no pixel.
    RasterizerDiscard,
}

/// The primitives transform feedback captures (`glBeginTransformFeedback`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FeedbackMode {
    Points,
    Lines,
    Triangles,
}

impl FeedbackMode {
    /// The mode whose primitives a draw of `mode` assembles.
    pub fn of(mode: Mode) -> FeedbackMode {
        match mode {
            Mode::Points => FeedbackMode::Points,
            Mode::Lines | Mode::LineStrip | Mode::LineLoop => FeedbackMode::Lines,
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan => FeedbackMode::Triangles,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Face {
    Front,
    Back,
    FrontAndBack,
}

/// Which winding is front-facing, in GL window coordinates (y up).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Winding {
    Ccw,
    Cw,
}

/// Primitive modes. Lines are drawn `line_width` pixels wide, as parallelograms of two
/// triangles (GL ES 2.0 §3.4.2), points as squares `gl_PointSize` pixels wide (1 for built-in
/// programs; §3.3), with `gl_PointCoord` (see `tiler::geometry::line`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    Triangles,
    TriangleStrip,
    TriangleFan,
    Lines,
    LineStrip,
    LineLoop,
    Points,
}

/// Vertex attribute component types.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ComponentType {
    Float,
    HalfFloat,
    Byte,
    UnsignedByte,
    Short,
    UnsignedShort,
    UnsignedInt,
    /// `GL_INT` (integer attributes only).
    Int,
}

/// Index types. tiler fetches shorts and ints; bytes are widened to shorts at each draw.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum IndexKind {
    UnsignedByte,
    UnsignedShort,
    UnsignedInt,
}

/// Texture filters, with GL's names. The `*_mipmap_*` ones are minification filters: in
/// `tex_parameters` they sample the levels `generate_mipmap` made (the first word filters within
/// a level, the last between levels); a texture without levels is then incomplete and samples
/// as (0, 0, 0, 1), as GL ES 2.0 §3.8.2 says. In a blit they act as their first word.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Filter {
    #[default]
    Nearest,
    Linear,
    NearestMipmapNearest,
    LinearMipmapNearest,
    NearestMipmapLinear,
    LinearMipmapLinear,
}

impl Filter {
    /// The filter within a level: `nearest` or `linear`.
    pub const fn base(self) -> Filter {
        match self {
            Filter::Nearest | Filter::NearestMipmapNearest | Filter::NearestMipmapLinear => Filter::Nearest,
            Filter::Linear | Filter::LinearMipmapNearest | Filter::LinearMipmapLinear => Filter::Linear,
        }
    }

    /// The filter between levels, if it is a mipmap filter.
    pub fn mipmap(self) -> Option<Filter> {
        match self {
            Filter::Nearest | Filter::Linear => None,
            Filter::NearestMipmapNearest | Filter::LinearMipmapNearest => Some(Filter::Nearest),
            Filter::NearestMipmapLinear | Filter::LinearMipmapLinear => Some(Filter::Linear),
        }
    }
}

/// The target of a layered texture: `GL_TEXTURE_2D_ARRAY` or `GL_TEXTURE_3D`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LayeredTarget {
    #[serde(rename = "2d_array")]
    Array2D,
    #[serde(rename = "3d")]
    Texture3D,
}

impl LayeredTarget {
    /// Its place in a unit's layered bindings.
    pub fn index(self) -> usize {
        self as usize
    }

    /// As GL names it.
    pub fn name(self) -> &'static str {
        match self {
            LayeredTarget::Array2D => "2-D array",
            LayeredTarget::Texture3D => "3-D",
        }
    }
}

/// A face of a cube texture, in GL's order (`GL_TEXTURE_CUBE_MAP_POSITIVE_X + index`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CubeFace {
    PositiveX,
    NegativeX,
    PositiveY,
    NegativeY,
    PositiveZ,
    NegativeZ,
}

impl CubeFace {
    /// The faces in GL's order.
    pub const ALL: [CubeFace; 6] = [
        CubeFace::PositiveX,
        CubeFace::NegativeX,
        CubeFace::PositiveY,
        CubeFace::NegativeY,
        CubeFace::PositiveZ,
        CubeFace::NegativeZ,
    ];

    /// Its place in GL's order, 0 to 5.
    pub fn index(self) -> usize {
        self as usize
    }

    /// As a trace spells it.
    pub fn name(self) -> &'static str {
        ["positive_x", "negative_x", "positive_y", "negative_y", "positive_z", "negative_z"][self.index()]
    }
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Wrap {
    #[default]
    ClampToEdge,
    Repeat,
    MirroredRepeat,
}

/// What `eglSwapBuffers` does to the colour buffer (`EGL_SWAP_BEHAVIOR`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SwapBehavior {
    /// `EGL_BUFFER_DESTROYED`, the default: the contents are undefined after a swap.
    #[default]
    Destroyed,
    /// `EGL_BUFFER_PRESERVED`: the colour buffer is kept.
    Preserved,
}

/// The built-in programs (tiler's shaders are Rust, so a trace names a program instead of
/// carrying GLSL). Attribute indices and uniforms are listed in `program.rs`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ProgramKind {
    /// Position (0) × `mvp`; colour `color`.
    Solid,
    /// Position (0) × `mvp`; colour from attribute 1; discards alpha below `alpha_cutoff`.
    VertexColor,
    /// Position (0) × `mvp`, normal (1) × `model`; Lambert lighting of `color` from `light_dir`.
    Lambert,
    /// Position (0) × `mvp`, texture coordinate (1); samples unit `sampler` times `color`;
    /// discards alpha below `alpha_cutoff`.
    Textured,
    /// Position (0) × `mvp`; reads input attachment 0 of the current subpass at the pixel
    /// and writes it times `color` (a lighting or composite subpass over a G-buffer).
    Composite,
}

/// What a program object is made of: a built-in program by name (`"program": "solid"`) or
/// GLSL ES source (`"program": {"glsl": {"vertex": "...", "fragment": "..."}}`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(from = "ProgramSourceRepr", into = "ProgramSourceRepr")]
pub enum ProgramSource {
    Builtin(ProgramKind),
    Glsl(GlslSource),
}

impl From<ProgramKind> for ProgramSource {
    fn from(kind: ProgramKind) -> ProgramSource {
        ProgramSource::Builtin(kind)
    }
}

/// The two shaders of a GLSL ES 1.00 program (see the `tiler-glsl` crate for the language).
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GlslSource {
    pub vertex: String,
    pub fragment: String,
}

/// `ProgramSource` as a trace spells it: the built-in names as strings (as version 1 always
/// had them) and `{"glsl": ...}` beside them, serde's external tagging.
#[derive(Clone, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
enum ProgramSourceRepr {
    Solid,
    VertexColor,
    Lambert,
    Textured,
    Composite,
    Glsl(GlslSource),
}

impl From<ProgramSourceRepr> for ProgramSource {
    fn from(r: ProgramSourceRepr) -> ProgramSource {
        match r {
            ProgramSourceRepr::Solid => ProgramSource::Builtin(ProgramKind::Solid),
            ProgramSourceRepr::VertexColor => ProgramSource::Builtin(ProgramKind::VertexColor),
            ProgramSourceRepr::Lambert => ProgramSource::Builtin(ProgramKind::Lambert),
            ProgramSourceRepr::Textured => ProgramSource::Builtin(ProgramKind::Textured),
            ProgramSourceRepr::Composite => ProgramSource::Builtin(ProgramKind::Composite),
            ProgramSourceRepr::Glsl(g) => ProgramSource::Glsl(g),
        }
    }
}

impl From<ProgramSource> for ProgramSourceRepr {
    fn from(s: ProgramSource) -> ProgramSourceRepr {
        match s {
            ProgramSource::Builtin(ProgramKind::Solid) => ProgramSourceRepr::Solid,
            ProgramSource::Builtin(ProgramKind::VertexColor) => ProgramSourceRepr::VertexColor,
            ProgramSource::Builtin(ProgramKind::Lambert) => ProgramSourceRepr::Lambert,
            ProgramSource::Builtin(ProgramKind::Textured) => ProgramSourceRepr::Textured,
            ProgramSource::Builtin(ProgramKind::Composite) => ProgramSourceRepr::Composite,
            ProgramSource::Glsl(g) => ProgramSourceRepr::Glsl(g),
        }
    }
}

/// A uniform value (`{"mat4": [16 floats, column-major]}`, `{"vec4": [...]}`, ...).
///
/// Built-in programs take exactly their uniforms' types. GLSL programs follow `glUniform*`'s
/// rules: `float`/`vecN` set float and bool uniforms of that size, `int`/`ivecN` set int and
/// bool uniforms of that size and `int` sets samplers (the texture unit), `matN` sets `matN`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum UniformValue {
    Float(f32),
    Int(i32),
    Vec2([f32; 2]),
    Vec3([f32; 3]),
    Vec4([f32; 4]),
    #[serde(rename = "ivec2")]
    IVec2([i32; 2]),
    #[serde(rename = "ivec3")]
    IVec3([i32; 3]),
    #[serde(rename = "ivec4")]
    IVec4([i32; 4]),
    /// `glUniform*ui` (ES 3.00).
    #[serde(rename = "uint")]
    UInt(u32),
    #[serde(rename = "uvec2")]
    UVec2([u32; 2]),
    #[serde(rename = "uvec3")]
    UVec3([u32; 3]),
    #[serde(rename = "uvec4")]
    UVec4([u32; 4]),
    /// Column-major, as `glUniformMatrix2fv` with `transpose = GL_FALSE`.
    Mat2([f32; 4]),
    /// Column-major.
    Mat3([f32; 9]),
    /// Column-major, as `glUniformMatrix4fv` with `transpose = GL_FALSE`.
    Mat4([f32; 16]),
    /// Column-major: 2 columns of 3 (`glUniformMatrix2x3fv`).
    #[serde(rename = "mat2x3")]
    Mat2x3([f32; 6]),
    /// Column-major: 2 columns of 4 (`glUniformMatrix2x4fv`).
    #[serde(rename = "mat2x4")]
    Mat2x4([f32; 8]),
    /// Column-major: 3 columns of 2 (`glUniformMatrix3x2fv`).
    #[serde(rename = "mat3x2")]
    Mat3x2([f32; 6]),
    /// Column-major: 3 columns of 4 (`glUniformMatrix3x4fv`).
    #[serde(rename = "mat3x4")]
    Mat3x4([f32; 12]),
    /// Column-major: 4 columns of 2 (`glUniformMatrix4x2fv`).
    #[serde(rename = "mat4x2")]
    Mat4x2([f32; 8]),
    /// Column-major: 4 columns of 3 (`glUniformMatrix4x3fv`).
    #[serde(rename = "mat4x3")]
    Mat4x3([f32; 12]),
}

impl UniformValue {
    pub fn type_name(&self) -> &'static str {
        match self {
            UniformValue::Float(_) => "float",
            UniformValue::Int(_) => "int",
            UniformValue::Vec2(_) => "vec2",
            UniformValue::Vec3(_) => "vec3",
            UniformValue::Vec4(_) => "vec4",
            UniformValue::IVec2(_) => "ivec2",
            UniformValue::IVec3(_) => "ivec3",
            UniformValue::IVec4(_) => "ivec4",
            UniformValue::UInt(_) => "uint",
            UniformValue::UVec2(_) => "uvec2",
            UniformValue::UVec3(_) => "uvec3",
            UniformValue::UVec4(_) => "uvec4",
            UniformValue::Mat2(_) => "mat2",
            UniformValue::Mat3(_) => "mat3",
            UniformValue::Mat4(_) => "mat4",
            UniformValue::Mat2x3(_) => "mat2x3",
            UniformValue::Mat2x4(_) => "mat2x4",
            UniformValue::Mat3x2(_) => "mat3x2",
            UniformValue::Mat3x4(_) => "mat3x4",
            UniformValue::Mat4x2(_) => "mat4x2",
            UniformValue::Mat4x3(_) => "mat4x3",
        }
    }

    /// Its components as floats (ints converted), in GL's order.
    /// The components of an integer value as their 32 bits (`i32` two's complement), or
    /// `None` for a float or matrix value.
    pub fn integer_bits(&self) -> Option<Vec<u32>> {
        Some(match self {
            UniformValue::Int(v) => vec![*v as u32],
            UniformValue::IVec2(v) => v.iter().map(|&c| c as u32).collect(),
            UniformValue::IVec3(v) => v.iter().map(|&c| c as u32).collect(),
            UniformValue::IVec4(v) => v.iter().map(|&c| c as u32).collect(),
            UniformValue::UInt(v) => vec![*v],
            UniformValue::UVec2(v) => v.to_vec(),
            UniformValue::UVec3(v) => v.to_vec(),
            UniformValue::UVec4(v) => v.to_vec(),
            _ => return None,
        })
    }

    pub fn components(&self) -> Vec<f32> {
        match self {
            UniformValue::Float(v) => vec![*v],
            UniformValue::Int(v) => vec![*v as f32],
            UniformValue::Vec2(v) => v.to_vec(),
            UniformValue::Vec3(v) => v.to_vec(),
            UniformValue::Vec4(v) => v.to_vec(),
            UniformValue::IVec2(v) => v.iter().map(|&c| c as f32).collect(),
            UniformValue::IVec3(v) => v.iter().map(|&c| c as f32).collect(),
            UniformValue::IVec4(v) => v.iter().map(|&c| c as f32).collect(),
            UniformValue::UInt(v) => vec![*v as f32],
            UniformValue::UVec2(v) => v.iter().map(|&c| c as f32).collect(),
            UniformValue::UVec3(v) => v.iter().map(|&c| c as f32).collect(),
            UniformValue::UVec4(v) => v.iter().map(|&c| c as f32).collect(),
            UniformValue::Mat2(v) => v.to_vec(),
            UniformValue::Mat3(v) => v.to_vec(),
            UniformValue::Mat4(v) => v.to_vec(),
            UniformValue::Mat2x3(v) => v.to_vec(),
            UniformValue::Mat2x4(v) => v.to_vec(),
            UniformValue::Mat3x2(v) => v.to_vec(),
            UniformValue::Mat3x4(v) => v.to_vec(),
            UniformValue::Mat4x2(v) => v.to_vec(),
            UniformValue::Mat4x3(v) => v.to_vec(),
        }
    }

    pub fn is_finite(&self) -> bool {
        self.components().iter().all(|c| c.is_finite())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    type Parsed = Call<serde_json::Value>;

    fn parse(json: &str) -> Parsed {
        serde_json::from_str(json).unwrap()
    }

    #[test]
    fn calls_of_older_traces_take_the_new_fields_defaults_and_write_back_unchanged() {
        let old = [
            r#"{"call":"tex_parameters","id":1,"filter":"linear","wrap":"repeat"}"#,
            r#"{"call":"stencil_func","func":"equal","reference":3,"mask":255}"#,
            r#"{"call":"stencil_op","fail":"keep","depth_fail":"keep","pass":"replace"}"#,
            r#"{"call":"stencil_mask","mask":15}"#,
        ];
        for json in old {
            let call = parse(json);
            assert_eq!(serde_json::to_string(&call).unwrap(), json);
        }
        assert_eq!(
            parse(old[0]),
            Parsed::TexParameters { id: 1, filter: Filter::Linear, wrap: Wrap::Repeat, mag_filter: None, wrap_t: None }
        );
        assert_eq!(parse(old[3]), Parsed::StencilMask { mask: 15, face: Face::FrontAndBack });
        let separate = parse(r#"{"call":"stencil_mask","mask":15,"face":"back"}"#);
        assert_eq!(separate, Parsed::StencilMask { mask: 15, face: Face::Back });
        let sampler = parse(
            r#"{"call":"tex_parameters","id":1,"filter":"nearest_mipmap_linear","wrap":"repeat","mag_filter":"linear","wrap_t":"clamp_to_edge"}"#,
        );
        assert_eq!(
            sampler,
            Parsed::TexParameters {
                id: 1,
                filter: Filter::NearestMipmapLinear,
                wrap: Wrap::Repeat,
                mag_filter: Some(Filter::Linear),
                wrap_t: Some(Wrap::ClampToEdge)
            }
        );
    }
}
