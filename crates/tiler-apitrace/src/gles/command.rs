//! The typed calls: what an OpenGL ES 2.0/3.0 or EGL call asks, with GL's own numbers.
//!
//! Enums are GL's raw `GLenum` values (see [`super::consts`] for the common ones); names are
//! `GLuint`; sizes and coordinates are `GLint`/`GLsizei` as the application passed them —
//! checking them is the consumer's job, as a GL driver's. Buffer sizes and offsets
//! (`GLsizeiptr`, `GLintptr`) are `u64`: a negative one is refused here.

/// A GL enum value (`GLenum`).
pub type GlEnum = u32;

/// An EGL handle (`EGLDisplay`, `EGLSurface`, `EGLContext`, `EGLConfig`): an address in the
/// traced process, 0 for none.
pub type EglHandle = u64;

/// Memory a call passes by pointer: vertex attributes, indices, pixels, buffer contents.
#[derive(Clone, Debug, PartialEq)]
pub enum Memory {
    /// A null pointer: no data (`glBufferData` that only allocates, `glTexImage2D` without
    /// pixels, a zero buffer offset).
    Null,
    /// Bytes apitrace copied from the application's memory, starting at the pointer. For a
    /// client-side vertex array apitrace writes, just before each draw, a fake
    /// `glVertexAttribPointer` whose blob covers the vertices that draw reads.
    Client(Vec<u8>),
    /// An offset into the buffer bound for this purpose (`GL_ARRAY_BUFFER` for
    /// `glVertexAttribPointer`, `GL_ELEMENT_ARRAY_BUFFER` for indices, `GL_PIXEL_UNPACK_BUFFER`
    /// for pixels), or an address apitrace could not follow.
    Offset(u64),
}

impl Memory {
    /// The client bytes, if the call passed any.
    pub fn bytes(&self) -> Option<&[u8]> {
        match self {
            Memory::Client(bytes) => Some(bytes),
            _ => None,
        }
    }
}

/// Parameter values of `glTexParameter*`, `glSamplerParameter*`.
#[derive(Clone, Debug, PartialEq)]
pub enum Params {
    Int(Vec<i32>),
    Float(Vec<f32>),
}

/// The values of one `glUniform*` call: `count` elements of `components` each, flattened.
#[derive(Clone, Debug, PartialEq)]
pub enum UniformValue {
    /// `glUniform{1,2,3,4}f[v]`.
    Float { components: u8, values: Vec<f32> },
    /// `glUniform{1,2,3,4}i[v]` (also how samplers are set).
    Int { components: u8, values: Vec<i32> },
    /// `glUniform{1,2,3,4}ui[v]` (GLES 3.0).
    UInt { components: u8, values: Vec<u32> },
    /// `glUniformMatrix{C}x{R}fv`: `columns × rows` floats per matrix, column-major unless
    /// `transpose`.
    Matrix { columns: u8, rows: u8, transpose: bool, values: Vec<f32> },
}

/// The value of one `glClearBuffer*` call.
#[derive(Clone, Debug, PartialEq)]
pub enum ClearValue {
    Float([f32; 4]),
    Int([i32; 4]),
    UInt([u32; 4]),
    /// `glClearBufferfi`: depth and stencil together.
    DepthStencil {
        depth: f32,
        stencil: i32,
    },
}

/// A call that draws, changes state, or creates or destroys something, decoded; or one on the
/// ignore list.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    // ---- Buffers -------------------------------------------------------------------------
    GenBuffers {
        names: Vec<u32>,
    },
    DeleteBuffers {
        names: Vec<u32>,
    },
    BindBuffer {
        target: GlEnum,
        buffer: u32,
    },
    /// `glBindBufferBase` (`range` `None`) and `glBindBufferRange` (`(offset, size)`).
    BindBufferRange {
        target: GlEnum,
        index: u32,
        buffer: u32,
        range: Option<(u64, u64)>,
    },
    BufferData {
        target: GlEnum,
        size: u64,
        data: Memory,
        usage: GlEnum,
    },
    BufferSubData {
        target: GlEnum,
        offset: u64,
        size: u64,
        data: Memory,
    },
    CopyBufferSubData {
        read_target: GlEnum,
        write_target: GlEnum,
        read_offset: u64,
        write_offset: u64,
        size: u64,
    },
    /// `glMapBufferOES` (whole buffer: `offset` 0, `length` `None`) or `glMapBufferRange`.
    /// `pointer` is the address the map returned in the traced process (0 if it failed).
    MapBuffer {
        target: GlEnum,
        buffer: u32,
        offset: u64,
        length: Option<u64>,
        access: u32,
        pointer: u64,
    },
    FlushMappedBufferRange {
        target: GlEnum,
        offset: u64,
        length: u64,
    },
    /// `glUnmapBuffer` / `glUnmapBufferOES`.
    UnmapBuffer {
        target: GlEnum,
        buffer: u32,
    },
    /// Bytes written through a mapped pointer: apitrace's fake `memcpy` into a mapping,
    /// resolved to the mapped buffer and the offset in it (destination minus the pointer the
    /// map returned, plus the mapped range's offset).
    BufferWrite {
        buffer: u32,
        offset: u64,
        data: Vec<u8>,
    },

    // ---- Vertex arrays and attributes ----------------------------------------------------
    GenVertexArrays {
        names: Vec<u32>,
    },
    DeleteVertexArrays {
        names: Vec<u32>,
    },
    BindVertexArray {
        array: u32,
    },
    EnableVertexAttribArray {
        index: u32,
    },
    DisableVertexAttribArray {
        index: u32,
    },
    /// `glVertexAttribPointer` (`integer` false) or `glVertexAttribIPointer` (true).
    VertexAttribPointer {
        index: u32,
        size: i32,
        kind: GlEnum,
        normalized: bool,
        stride: i32,
        pointer: Memory,
        integer: bool,
    },
    /// `glVertexAttrib{1,2,3,4}f[v]`: the constant value of a disabled array, missing
    /// components filled as GL does (0, 0, 1).
    VertexAttrib {
        index: u32,
        value: [f32; 4],
    },
    VertexAttribDivisor {
        index: u32,
        divisor: u32,
    },

    // ---- Drawing -------------------------------------------------------------------------
    /// `glDrawArrays` (`instance_count` 1) and `glDrawArraysInstanced`.
    DrawArrays {
        mode: GlEnum,
        first: i32,
        count: i32,
        instance_count: i32,
    },
    /// `glDrawElements`, `glDrawRangeElements` (`range` `(start, end)`),
    /// `glDrawElementsInstanced`, and their `…BaseVertex` forms (GL ES 3.2,
    /// `OES`/`EXT_draw_elements_base_vertex`; 0 for the others).
    DrawElements {
        mode: GlEnum,
        count: i32,
        kind: GlEnum,
        indices: Memory,
        instance_count: i32,
        range: Option<(u32, u32)>,
        base_vertex: i32,
    },

    // ---- Textures and samplers -----------------------------------------------------------
    GenTextures {
        names: Vec<u32>,
    },
    DeleteTextures {
        names: Vec<u32>,
    },
    ActiveTexture {
        unit: GlEnum,
    },
    BindTexture {
        target: GlEnum,
        texture: u32,
    },
    TexImage2D {
        target: GlEnum,
        level: i32,
        internal_format: GlEnum,
        width: i32,
        height: i32,
        border: i32,
        format: GlEnum,
        kind: GlEnum,
        pixels: Memory,
    },
    TexSubImage2D {
        target: GlEnum,
        level: i32,
        x_offset: i32,
        y_offset: i32,
        width: i32,
        height: i32,
        format: GlEnum,
        kind: GlEnum,
        pixels: Memory,
    },
    CompressedTexImage2D {
        target: GlEnum,
        level: i32,
        internal_format: GlEnum,
        width: i32,
        height: i32,
        border: i32,
        image_size: i32,
        data: Memory,
    },
    CompressedTexSubImage2D {
        target: GlEnum,
        level: i32,
        x_offset: i32,
        y_offset: i32,
        width: i32,
        height: i32,
        format: GlEnum,
        image_size: i32,
        data: Memory,
    },
    CopyTexImage2D {
        target: GlEnum,
        level: i32,
        internal_format: GlEnum,
        x: i32,
        y: i32,
        width: i32,
        height: i32,
        border: i32,
    },
    CopyTexSubImage2D {
        target: GlEnum,
        level: i32,
        x_offset: i32,
        y_offset: i32,
        x: i32,
        y: i32,
        width: i32,
        height: i32,
    },
    TexStorage2D {
        target: GlEnum,
        levels: i32,
        internal_format: GlEnum,
        width: i32,
        height: i32,
    },
    /// `glTexImage3D` (2-D array and 3-D textures).
    TexImage3D {
        target: GlEnum,
        level: i32,
        internal_format: GlEnum,
        width: i32,
        height: i32,
        depth: i32,
        border: i32,
        format: GlEnum,
        kind: GlEnum,
        pixels: Memory,
    },
    /// `glTexSubImage3D`.
    TexSubImage3D {
        target: GlEnum,
        level: i32,
        x_offset: i32,
        y_offset: i32,
        z_offset: i32,
        width: i32,
        height: i32,
        depth: i32,
        format: GlEnum,
        kind: GlEnum,
        pixels: Memory,
    },
    /// `glTexStorage3D`.
    TexStorage3D {
        target: GlEnum,
        levels: i32,
        internal_format: GlEnum,
        width: i32,
        height: i32,
        depth: i32,
    },
    /// `glCopyTexSubImage3D` (and its OES name): a rectangle of the read framebuffer into
    /// layer `z_offset` of the bound 2-D array or 3-D texture.
    CopyTexSubImage3D {
        target: GlEnum,
        level: i32,
        x_offset: i32,
        y_offset: i32,
        z_offset: i32,
        x: i32,
        y: i32,
        width: i32,
        height: i32,
    },
    /// `glFramebufferTextureLayer`.
    FramebufferTextureLayer {
        target: GlEnum,
        attachment: GlEnum,
        texture: u32,
        level: i32,
        layer: i32,
    },
    /// `glTexParameter{i,f}[v]`.
    TexParameter {
        target: GlEnum,
        pname: GlEnum,
        params: Params,
    },
    GenerateMipmap {
        target: GlEnum,
    },
    PixelStore {
        pname: GlEnum,
        param: i32,
    },
    /// `glTransformFeedbackVaryings`: the vertex outputs a program captures once linked, in
    /// `mode` (`GL_INTERLEAVED_ATTRIBS` or `GL_SEPARATE_ATTRIBS`).
    TransformFeedbackVaryings {
        program: u32,
        varyings: Vec<String>,
        mode: GlEnum,
    },
    /// `glBeginTransformFeedback` with its primitive mode.
    BeginTransformFeedback {
        mode: GlEnum,
    },
    EndTransformFeedback,
    PauseTransformFeedback,
    ResumeTransformFeedback,
    GenTransformFeedbacks {
        names: Vec<u32>,
    },
    DeleteTransformFeedbacks {
        names: Vec<u32>,
    },
    BindTransformFeedback {
        target: GlEnum,
        id: u32,
    },
    GenSamplers {
        names: Vec<u32>,
    },
    DeleteSamplers {
        names: Vec<u32>,
    },
    BindSampler {
        unit: u32,
        sampler: u32,
    },
    /// `glSamplerParameter{i,f}[v]`.
    SamplerParameter {
        sampler: u32,
        pname: GlEnum,
        params: Params,
    },

    // ---- Framebuffers and renderbuffers --------------------------------------------------
    GenFramebuffers {
        names: Vec<u32>,
    },
    DeleteFramebuffers {
        names: Vec<u32>,
    },
    BindFramebuffer {
        target: GlEnum,
        framebuffer: u32,
    },
    /// `glFramebufferTexture2D` (`samples` 0) and `glFramebufferTexture2DMultisampleEXT`/`IMG`
    /// (rendered with `samples`, resolved in the tile: the attachment holds one sample).
    FramebufferTexture2D {
        target: GlEnum,
        attachment: GlEnum,
        texture_target: GlEnum,
        texture: u32,
        level: i32,
        samples: i32,
    },
    FramebufferRenderbuffer {
        target: GlEnum,
        attachment: GlEnum,
        renderbuffer_target: GlEnum,
        renderbuffer: u32,
    },
    GenRenderbuffers {
        names: Vec<u32>,
    },
    DeleteRenderbuffers {
        names: Vec<u32>,
    },
    BindRenderbuffer {
        target: GlEnum,
        renderbuffer: u32,
    },
    /// `glRenderbufferStorage` (`samples` 0) and `glRenderbufferStorageMultisample[EXT]`.
    RenderbufferStorage {
        target: GlEnum,
        samples: i32,
        internal_format: GlEnum,
        width: i32,
        height: i32,
    },
    /// `glInvalidateFramebuffer`, `glInvalidateSubFramebuffer` (`region` `[x, y, w, h]`) and
    /// `glDiscardFramebufferEXT`.
    InvalidateFramebuffer {
        target: GlEnum,
        attachments: Vec<GlEnum>,
        region: Option<[i32; 4]>,
    },
    BlitFramebuffer {
        src: [i32; 4],
        dst: [i32; 4],
        mask: u32,
        filter: GlEnum,
    },
    /// `glDrawBuffers` / `glDrawBuffersEXT`.
    DrawBuffers {
        buffers: Vec<GlEnum>,
    },
    ReadBuffer {
        source: GlEnum,
    },
    ReadPixels {
        x: i32,
        y: i32,
        width: i32,
        height: i32,
        format: GlEnum,
        kind: GlEnum,
        pixels: Memory,
    },

    // ---- Shaders and programs ------------------------------------------------------------
    CreateShader {
        kind: GlEnum,
        shader: u32,
    },
    /// `glShaderSource`: the strings joined, as GL joins them.
    ShaderSource {
        shader: u32,
        source: String,
    },
    CompileShader {
        shader: u32,
    },
    DeleteShader {
        shader: u32,
    },
    ShaderBinary {
        shaders: Vec<u32>,
        format: GlEnum,
        binary: Memory,
    },
    CreateProgram {
        program: u32,
    },
    AttachShader {
        program: u32,
        shader: u32,
    },
    DetachShader {
        program: u32,
        shader: u32,
    },
    BindAttribLocation {
        program: u32,
        index: u32,
        name: String,
    },
    LinkProgram {
        program: u32,
    },
    UseProgram {
        program: u32,
    },
    DeleteProgram {
        program: u32,
    },
    /// `glGetUniformLocation`: changes nothing, but `location` is what later `glUniform*`
    /// calls of this program use.
    UniformLocation {
        program: u32,
        name: String,
        location: i32,
    },
    /// `glGetAttribLocation`: `location` is the attribute index later calls use.
    AttribLocation {
        program: u32,
        name: String,
        location: i32,
    },
    /// `glGetUniformBlockIndex`: `index` is what `glUniformBlockBinding` uses.
    UniformBlockIndex {
        program: u32,
        name: String,
        index: u32,
    },
    Uniform {
        location: i32,
        value: UniformValue,
    },
    UniformBlockBinding {
        program: u32,
        block_index: u32,
        binding: u32,
    },

    // ---- Fixed-function state ------------------------------------------------------------
    Enable {
        cap: GlEnum,
    },
    Disable {
        cap: GlEnum,
    },
    Viewport {
        x: i32,
        y: i32,
        width: i32,
        height: i32,
    },
    Scissor {
        x: i32,
        y: i32,
        width: i32,
        height: i32,
    },
    DepthFunc {
        func: GlEnum,
    },
    DepthMask {
        write: bool,
    },
    /// `glDepthRangef` (desktop GL: `glDepthRange`).
    DepthRange {
        near: f32,
        far: f32,
    },
    CullFace {
        mode: GlEnum,
    },
    FrontFace {
        mode: GlEnum,
    },
    ColorMask {
        mask: [bool; 4],
    },
    /// `glBlendFunc` (RGB and alpha the same) and `glBlendFuncSeparate`.
    BlendFunc {
        src_rgb: GlEnum,
        dst_rgb: GlEnum,
        src_alpha: GlEnum,
        dst_alpha: GlEnum,
    },
    /// `glBlendEquation` (both the same) and `glBlendEquationSeparate`.
    BlendEquation {
        rgb: GlEnum,
        alpha: GlEnum,
    },
    BlendColor {
        color: [f32; 4],
    },
    /// `glStencilFunc` (`face` `GL_FRONT_AND_BACK`) and `glStencilFuncSeparate`.
    StencilFunc {
        face: GlEnum,
        func: GlEnum,
        reference: i32,
        mask: u32,
    },
    /// `glStencilOp` (`face` `GL_FRONT_AND_BACK`) and `glStencilOpSeparate`.
    StencilOp {
        face: GlEnum,
        stencil_fail: GlEnum,
        depth_fail: GlEnum,
        pass: GlEnum,
    },
    /// `glStencilMask` (`face` `GL_FRONT_AND_BACK`) and `glStencilMaskSeparate`.
    StencilMask {
        face: GlEnum,
        mask: u32,
    },
    PolygonOffset {
        factor: f32,
        units: f32,
    },
    LineWidth {
        width: f32,
    },
    SampleCoverage {
        value: f32,
        invert: bool,
    },
    Hint {
        target: GlEnum,
        mode: GlEnum,
    },

    // ---- Clears, flushes, queries --------------------------------------------------------
    Clear {
        mask: u32,
    },
    ClearColor {
        color: [f32; 4],
    },
    /// `glClearDepthf` (desktop GL: `glClearDepth`).
    ClearDepth {
        depth: f32,
    },
    ClearStencil {
        stencil: i32,
    },
    /// `glClearBuffer{f,i,ui}v`, `glClearBufferfi`.
    ClearBuffer {
        buffer: GlEnum,
        draw_buffer: i32,
        value: ClearValue,
    },
    Flush,
    Finish,
    /// `glFenceSync`: a fence after the commands so far, named by the returned handle.
    FenceSync {
        sync: u64,
    },
    /// `glClientWaitSync`: the CPU waits (up to `timeout` ns; 0 polls) for the fence.
    ClientWaitSync {
        sync: u64,
        flags: u32,
        timeout: u64,
    },
    DeleteSync {
        sync: u64,
    },
    /// `glGenQueries[EXT]`.
    GenQueries {
        names: Vec<u32>,
    },
    DeleteQueries {
        names: Vec<u32>,
    },
    BeginQuery {
        target: GlEnum,
        query: u32,
    },
    EndQuery {
        target: GlEnum,
    },
    /// `glQueryCounterEXT`: the GPU writes a timestamp into the query when it gets there.
    QueryCounter {
        query: u32,
    },
    /// `glGetQueryObjectuiv[EXT]`: reading a query's result waits for the pass that holds it.
    GetQueryResult {
        query: u32,
        pname: GlEnum,
    },
    /// `glStartTilingQCOM`: only tiles meeting the region are rendered; `preserve_mask` says
    /// which buffers keep their contents (load) there.
    StartTiling {
        x: u32,
        y: u32,
        width: u32,
        height: u32,
        preserve_mask: u32,
    },
    /// `glEndTilingQCOM`: `preserve_mask` says which buffers are stored.
    EndTiling {
        preserve_mask: u32,
    },

    // ---- EGL -----------------------------------------------------------------------------
    /// `eglCreateWindowSurface`, `eglCreatePlatformWindowSurface[EXT]`.
    CreateWindowSurface {
        display: EglHandle,
        config: EglHandle,
        window: u64,
        attribs: Vec<i64>,
        surface: EglHandle,
    },
    CreatePbufferSurface {
        display: EglHandle,
        config: EglHandle,
        attribs: Vec<i64>,
        surface: EglHandle,
    },
    DestroySurface {
        display: EglHandle,
        surface: EglHandle,
    },
    /// `eglSurfaceAttrib` (e.g. `EGL_SWAP_BEHAVIOR`: whether the next frame starts by loading).
    SurfaceAttrib {
        display: EglHandle,
        surface: EglHandle,
        attribute: i64,
        value: i64,
    },
    CreateContext {
        display: EglHandle,
        config: EglHandle,
        share_context: EglHandle,
        attribs: Vec<i64>,
        context: EglHandle,
    },
    DestroyContext {
        display: EglHandle,
        context: EglHandle,
    },
    MakeCurrent {
        display: EglHandle,
        draw: EglHandle,
        read: EglHandle,
        context: EglHandle,
    },
    /// `eglSwapBuffers` and `eglSwapBuffersWithDamage{KHR,EXT}`: the end of a frame.
    SwapBuffers {
        display: EglHandle,
        surface: EglHandle,
    },

    /// A call on the ignore list ([`super::IGNORED`]): it changes nothing tiler models.
    Ignored {
        function: &'static str,
        reason: &'static str,
    },
}
