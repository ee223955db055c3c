//! Pipelines: a vertex shader, a fragment shader and the fixed-function state around them,
//! all plain data with named presets (Vulkan's graphics pipeline, without dynamic dispatch per
//! fragment: the shaders are monomorphised into the pixel loop).

use serde::{Deserialize, Serialize};

use super::error::{Error, Result};
use super::format::{ColorWrites, IntFormat};

/// The most colour attachments a subpass may write.
pub const MAX_COLOR_ATTACHMENTS: usize = 4;
/// The most vertex attributes a pipeline may read.
pub const MAX_VERTEX_ATTRIBUTES: usize = 8;
/// The most vertex buffer bindings a pipeline may use.
pub const MAX_VERTEX_BINDINGS: usize = 4;
/// The most `f32` varyings a vertex shader may pass to the fragment shader.
pub const MAX_VARYINGS: usize = 64;

/// A comparison, `fragment OP stored` for depth and `(reference & mask) OP (stored & mask)`
/// for stencil (Vulkan `VkCompareOp`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CompareOp {
    Never,
    Less,
    Equal,
    LessOrEqual,
    Greater,
    NotEqual,
    GreaterOrEqual,
    Always,
}

impl CompareOp {
    /// Whether `a OP b` holds (a NaN operand passes `NotEqual` and `Always` only).
    #[inline(always)]
    pub fn test<T: PartialOrd>(self, a: T, b: T) -> bool {
        match self {
            CompareOp::Never => false,
            CompareOp::Less => a < b,
            CompareOp::Equal => a == b,
            CompareOp::LessOrEqual => a <= b,
            CompareOp::Greater => a > b,
            CompareOp::NotEqual => a != b,
            CompareOp::GreaterOrEqual => a >= b,
            CompareOp::Always => true,
        }
    }
}

/// What a stencil test outcome does to the stored value (Vulkan `VkStencilOp`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StencilOp {
    Keep,
    Zero,
    Replace,
    IncrementAndClamp,
    DecrementAndClamp,
    Invert,
    IncrementAndWrap,
    DecrementAndWrap,
}

impl StencilOp {
    #[inline(always)]
    pub fn apply(self, stored: u8, reference: u8) -> u8 {
        match self {
            StencilOp::Keep => stored,
            StencilOp::Zero => 0,
            StencilOp::Replace => reference,
            StencilOp::IncrementAndClamp => stored.saturating_add(1),
            StencilOp::DecrementAndClamp => stored.saturating_sub(1),
            StencilOp::Invert => !stored,
            StencilOp::IncrementAndWrap => stored.wrapping_add(1),
            StencilOp::DecrementAndWrap => stored.wrapping_sub(1),
        }
    }
}

/// The stencil state of one facing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct StencilFaceState {
    pub compare: CompareOp,
    /// Applied when the stencil test fails.
    pub fail_op: StencilOp,
    /// Applied when the stencil test passes and the depth test fails.
    pub depth_fail_op: StencilOp,
    /// Applied when both tests pass.
    pub pass_op: StencilOp,
    pub compare_mask: u8,
    pub write_mask: u8,
    pub reference: u8,
}

impl StencilFaceState {
    /// Always passes, changes nothing.
    pub const KEEP: StencilFaceState = StencilFaceState {
        compare: CompareOp::Always,
        fail_op: StencilOp::Keep,
        depth_fail_op: StencilOp::Keep,
        pass_op: StencilOp::Keep,
        compare_mask: 0xff,
        write_mask: 0xff,
        reference: 0,
    };

    /// Whether any outcome changes the stored value.
    pub fn writes(&self) -> bool {
        self.write_mask != 0 && [self.fail_op, self.depth_fail_op, self.pass_op].iter().any(|op| *op != StencilOp::Keep)
    }
}

/// Depth and stencil tests.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct DepthStencilState {
    pub depth_test: bool,
    pub depth_write: bool,
    pub depth_compare: CompareOp,
    pub stencil_test: bool,
    pub front: StencilFaceState,
    pub back: StencilFaceState,
}

impl DepthStencilState {
    /// No depth or stencil test.
    pub const DISABLED: DepthStencilState = DepthStencilState {
        depth_test: false,
        depth_write: false,
        depth_compare: CompareOp::Always,
        stencil_test: false,
        front: StencilFaceState::KEEP,
        back: StencilFaceState::KEEP,
    };
    /// `LESS` test with depth writes: the usual opaque geometry.
    pub const LESS_WRITE: DepthStencilState =
        DepthStencilState { depth_test: true, depth_write: true, depth_compare: CompareOp::Less, ..Self::DISABLED };
    /// `LESS_OR_EQUAL` test with depth writes.
    pub const LESS_EQUAL_WRITE: DepthStencilState = DepthStencilState {
        depth_test: true,
        depth_write: true,
        depth_compare: CompareOp::LessOrEqual,
        ..Self::DISABLED
    };
    /// `LESS` test without writes: transparent geometry after the opaque.
    pub const LESS_NO_WRITE: DepthStencilState =
        DepthStencilState { depth_test: true, depth_write: false, depth_compare: CompareOp::Less, ..Self::DISABLED };

    /// The same state with the stencil test on, both faces as given.
    pub fn with_stencil(self, face: StencilFaceState) -> DepthStencilState {
        DepthStencilState { stencil_test: true, front: face, back: face, ..self }
    }

    /// Whether the depth or the stencil test can change the stored depth/stencil values.
    pub fn writes(&self) -> bool {
        (self.depth_test && self.depth_write) || (self.stencil_test && (self.front.writes() || self.back.writes()))
    }
}

/// Declares a fieldless enum and its `ALL`, every variant in declaration order, from one list
/// of variants (so that the list cannot miss one the enum gains).
macro_rules! enum_with_all {
    ($(#[$meta:meta])* $vis:vis enum $name:ident { $($variant:ident),+ $(,)? }) => {
        $(#[$meta])*
        $vis enum $name {
            $($variant),+
        }

        impl $name {
            /// Every variant, in declaration order.
            pub const ALL: [$name; [$($name::$variant),+].len()] = [$($name::$variant),+];
        }
    };
}

enum_with_all! {
    /// A blend factor (Vulkan `VkBlendFactor`).
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
    #[serde(rename_all = "snake_case")]
    pub enum BlendFactor {
        Zero,
        One,
        SrcColor,
        OneMinusSrcColor,
        DstColor,
        OneMinusDstColor,
        SrcAlpha,
        OneMinusSrcAlpha,
        DstAlpha,
        OneMinusDstAlpha,
        ConstantColor,
        OneMinusConstantColor,
        ConstantAlpha,
        OneMinusConstantAlpha,
        SrcAlphaSaturate,
    }
}

enum_with_all! {
    /// A blend equation (Vulkan `VkBlendOp`). `Min` and `Max` ignore the factors.
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
    #[serde(rename_all = "snake_case")]
    pub enum BlendOp {
        Add,
        Subtract,
        ReverseSubtract,
        Min,
        Max,
    }
}

/// `op(src · src_factor, dst · dst_factor)` for the colour or the alpha channel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct BlendComponent {
    pub src: BlendFactor,
    pub dst: BlendFactor,
    pub op: BlendOp,
}

impl BlendComponent {
    pub const REPLACE: BlendComponent =
        BlendComponent { src: BlendFactor::One, dst: BlendFactor::Zero, op: BlendOp::Add };
    pub const OVER: BlendComponent =
        BlendComponent { src: BlendFactor::One, dst: BlendFactor::OneMinusSrcAlpha, op: BlendOp::Add };
    pub const ADD: BlendComponent = BlendComponent { src: BlendFactor::One, dst: BlendFactor::One, op: BlendOp::Add };
}

/// Blending of one colour attachment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct BlendState {
    pub color: BlendComponent,
    pub alpha: BlendComponent,
}

impl BlendState {
    /// Non-premultiplied alpha: `src·a + dst·(1−a)`, alpha `a + dst_a·(1−a)` (the glTF BLEND
    /// mode of SCENES.md).
    pub const ALPHA: BlendState = BlendState {
        color: BlendComponent { src: BlendFactor::SrcAlpha, dst: BlendFactor::OneMinusSrcAlpha, op: BlendOp::Add },
        alpha: BlendComponent::OVER,
    };
    /// Premultiplied alpha: `src + dst·(1−a)`.
    pub const PREMULTIPLIED_ALPHA: BlendState = BlendState { color: BlendComponent::OVER, alpha: BlendComponent::OVER };
    /// `src + dst`.
    pub const ADDITIVE: BlendState = BlendState { color: BlendComponent::ADD, alpha: BlendComponent::ADD };
}

/// How a colour attachment is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct ColorTargetState {
    /// `None`: the fragment's colour replaces the stored one.
    pub blend: Option<BlendState>,
    pub write_mask: ColorWrites,
}

impl ColorTargetState {
    pub const REPLACE: ColorTargetState = ColorTargetState { blend: None, write_mask: ColorWrites::ALL };
    pub const ALPHA_BLEND: ColorTargetState =
        ColorTargetState { blend: Some(BlendState::ALPHA), write_mask: ColorWrites::ALL };
}

/// Which facing is culled.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CullMode {
    None,
    Front,
    Back,
    FrontAndBack,
}

/// Which winding is front-facing, in framebuffer coordinates (y down), as Vulkan defines it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrontFace {
    CounterClockwise,
    Clockwise,
}

/// How vertices form triangles.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Topology {
    /// Vertices (3i, 3i+1, 3i+2).
    TriangleList,
    /// Vertices (i, i+1, i+2), odd triangles with their first two vertices swapped so every
    /// triangle keeps the strip's winding (Vulkan's rule).
    TriangleStrip,
    /// Vertices (i+1, i+2, 0).
    TriangleFan,
    /// Segments (2i, 2i+1), each drawn as a parallelogram of two triangles (see
    /// `geometry::line`).
    LineList,
    /// Segments (i, i+1).
    LineStrip,
    /// Segments (i, i+1) and (n−1, 0).
    LineLoop,
    /// Each vertex a square `PipelineDesc::point_size_varying` pixels wide (see
    /// `geometry::line::point_square`).
    PointList,
}

impl Topology {
    /// Whether it draws lines (segments widened to `PipelineDesc::line_width` pixels).
    pub fn is_line(self) -> bool {
        matches!(self, Topology::LineList | Topology::LineStrip | Topology::LineLoop)
    }
}

/// How a varying is interpolated across a triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Interpolation {
    /// Perspective-correct (GLSL `smooth`).
    Perspective,
    /// Linear in screen space (GLSL `noperspective`).
    Linear,
    /// The provoking vertex's value everywhere (GLSL `flat`; see [`ProvokingVertex`]). The
    /// value is copied, never computed with, so any 32 bits (an integer's) arrive unchanged.
    Flat,
}

/// Which vertex of a primitive gives its `flat` varyings.
///
/// Vulkan's default is the first (`VK_PROVOKING_VERTEX_MODE_FIRST_VERTEX_EXT`): triangle `t`
/// of a list takes vertex `3t`, of a strip `t`, of a fan `t + 1`; segment `s` of a line list
/// `2s`, of a strip or loop `s`. OpenGL ES takes the last (ES 3.0 §2.18, table 2.12): `3t + 2`,
/// `t + 2` for strips and fans alike, `2s + 1`, `s + 1`. A point is its own provoking vertex.
/// The core's native users keep the first (their scenes were written for it); the GL context
/// picks the last.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ProvokingVertex {
    #[default]
    First,
    Last,
}

/// How a vertex attribute is stored in its buffer; it is fetched as a 4-component float
/// vector, missing components `(0, 0, 0, 1)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VertexFormat {
    Float32,
    Float32x2,
    Float32x3,
    Float32x4,
    Unorm8x4,
    Snorm8x4,
    Uint8x4,
    Unorm16x2,
    Unorm16x4,
    Snorm16x2,
    Snorm16x4,
    Float16x2,
    Float16x4,
    Uint16x2,
    Uint32,
    /// Integers kept as integers (GL's `glVertexAttribIPointer`): `channels` (1 to 4) of
    /// `bits` each, delivered as the bits of each component zero- or sign-extended to 32
    /// (what a shader's `int`/`uint` register holds), missing components 0 and `w` the
    /// integer 1.
    Int(IntFormat),
}

impl VertexFormat {
    pub const fn size_bytes(self) -> u32 {
        match self {
            VertexFormat::Float32 | VertexFormat::Uint32 => 4,
            VertexFormat::Float32x2 => 8,
            VertexFormat::Float32x3 => 12,
            VertexFormat::Float32x4 => 16,
            VertexFormat::Unorm8x4 | VertexFormat::Snorm8x4 | VertexFormat::Uint8x4 => 4,
            VertexFormat::Unorm16x2 | VertexFormat::Snorm16x2 | VertexFormat::Float16x2 | VertexFormat::Uint16x2 => 4,
            VertexFormat::Unorm16x4 | VertexFormat::Snorm16x4 | VertexFormat::Float16x4 => 8,
            VertexFormat::Int(f) => f.bytes() as u32,
        }
    }
}

/// One vertex buffer binding: its stride between consecutive vertices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct VertexBinding {
    pub stride: u32,
}

/// One vertex attribute: read from `binding` at `offset` within each vertex, delivered to the
/// vertex shader as `attributes[location]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct VertexAttribute {
    pub location: u32,
    pub binding: u32,
    pub format: VertexFormat,
    pub offset: u32,
}

/// Where the vertex shader's attributes come from.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct VertexInputState {
    pub bindings: Vec<VertexBinding>,
    pub attributes: Vec<VertexAttribute>,
}

impl VertexInputState {
    /// One interleaved buffer: consecutive attributes at locations 0, 1, … packed in order.
    pub fn interleaved(formats: &[VertexFormat]) -> VertexInputState {
        let mut offset = 0;
        let attributes = formats
            .iter()
            .enumerate()
            .map(|(location, &format)| {
                let attribute = VertexAttribute { location: location as u32, binding: 0, format, offset };
                offset += format.size_bytes();
                attribute
            })
            .collect();
        VertexInputState { bindings: vec![VertexBinding { stride: offset }], attributes }
    }

    /// One buffer per attribute: attribute `i` at location `i` from binding `i`, tightly packed.
    pub fn separate(formats: &[VertexFormat]) -> VertexInputState {
        VertexInputState {
            bindings: formats.iter().map(|f| VertexBinding { stride: f.size_bytes() }).collect(),
            attributes: formats
                .iter()
                .enumerate()
                .map(|(i, &format)| VertexAttribute { location: i as u32, binding: i as u32, format, offset: 0 })
                .collect(),
        }
    }

    /// Bytes of attribute data fetched per vertex.
    pub fn fetch_bytes_per_vertex(&self) -> u64 {
        self.attributes.iter().map(|a| a.format.size_bytes() as u64).sum()
    }
}

/// Multisampling state (Vulkan `VkPipelineMultisampleStateCreateInfo`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct MultisampleState {
    /// Run the fragment shader once per covered sample, at the sample's position, instead of
    /// once per pixel (Vulkan `sampleShadingEnable` with a minimum of 1.0).
    pub sample_shading: bool,
    /// Turn the alpha of colour output 0 into a sample mask: `round(alpha × samples)` of the
    /// pixel's samples stay covered, the lowest-numbered first.
    pub alpha_to_coverage: bool,
    /// Samples that may be covered: bit `s` for sample `s` (Vulkan `pSampleMask`).
    pub sample_mask: u32,
}

impl MultisampleState {
    pub const DEFAULT: MultisampleState =
        MultisampleState { sample_shading: false, alpha_to_coverage: false, sample_mask: u32::MAX };
}

impl Default for MultisampleState {
    fn default() -> MultisampleState {
        MultisampleState::DEFAULT
    }
}

/// Everything about a pipeline except its shaders.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PipelineDesc {
    /// A name for reports and errors.
    pub label: String,
    pub vertex_input: VertexInputState,
    pub topology: Topology,
    /// The interpolation of each `f32` varying the vertex shader writes, in order.
    pub varyings: Vec<Interpolation>,
    pub cull_mode: CullMode,
    pub front_face: FrontFace,
    pub depth_stencil: DepthStencilState,
    /// One per colour attachment of the subpass, in order.
    pub color_targets: Vec<ColorTargetState>,
    pub blend_constant: [f32; 4],
    pub multisample: MultisampleState,
    /// Polygon offset of every triangle's depth (GL's `glPolygonOffset` with
    /// `GL_POLYGON_OFFSET_FILL`, Vulkan's depth bias).
    pub depth_bias: DepthBias,
    /// Width in pixels of line topologies' segments (GL's `glLineWidth`).
    pub line_width: f32,
    /// The varying holding each point's size in pixels (GL's `gl_PointSize`); 1 without one.
    pub point_size_varying: Option<usize>,
    /// The first of two varyings a point's corners set to GL's `gl_PointCoord`: (0, 0) at its
    /// top-left, (1, 1) at its bottom-right.
    pub point_coord_varying: Option<usize>,
    /// The vertex whose values `Interpolation::Flat` varyings take.
    #[serde(default)]
    pub provoking_vertex: ProvokingVertex,
}

/// A depth offset per triangle, computed in setup (GL ES 2.0 §3.5.2):
/// `slope_factor × m + constant_factor × r`, where `m = max(|∂z/∂x|, |∂z/∂y|)` is the largest
/// window-space depth slope of the triangle (the approximation the spec allows, and llvmpipe's)
/// and `r` the depth format's minimum resolvable difference: `1 / (2^b − 1)` for a `b`-bit
/// UNORM format (D16, D24, as llvmpipe), `2^(e − 23)` for D32F with `e` the exponent of the
/// triangle's largest `|z|` (the GL 4.6 / Vulkan rule). The offset is added before the depth is
/// stored, which clamps it to `[0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct DepthBias {
    /// GL's `units`.
    pub constant_factor: f32,
    /// GL's `factor`.
    pub slope_factor: f32,
}

impl DepthBias {
    /// No offset.
    pub const NONE: DepthBias = DepthBias { constant_factor: 0.0, slope_factor: 0.0 };

    pub fn is_none(&self) -> bool {
        self.constant_factor == 0.0 && self.slope_factor == 0.0
    }
}

impl PipelineDesc {
    /// A triangle-list pipeline writing one colour attachment without blending, no depth test,
    /// no culling, no varyings: change what you need.
    pub fn new(label: impl Into<String>, vertex_input: VertexInputState) -> PipelineDesc {
        PipelineDesc {
            label: label.into(),
            vertex_input,
            topology: Topology::TriangleList,
            varyings: Vec::new(),
            cull_mode: CullMode::None,
            front_face: FrontFace::CounterClockwise,
            depth_stencil: DepthStencilState::DISABLED,
            color_targets: vec![ColorTargetState::REPLACE],
            blend_constant: [0.0; 4],
            multisample: MultisampleState::DEFAULT,
            depth_bias: DepthBias::NONE,
            line_width: 1.0,
            point_size_varying: None,
            point_coord_varying: None,
            provoking_vertex: ProvokingVertex::First,
        }
    }

    pub(crate) fn validate(&self) -> Result<()> {
        let what = || format!("pipeline '{}'", self.label);
        if !(self.line_width.is_finite() && self.line_width > 0.0) {
            return Err(Error::invalid(what(), format!("line width {} is not positive", self.line_width)));
        }
        let n = self.varyings.len();
        if self.point_size_varying.is_some_and(|v| v >= n) || self.point_coord_varying.is_some_and(|v| v + 2 > n) {
            return Err(Error::invalid(what(), format!("a point varying is beyond its {n} varyings")));
        }
        let bias = self.depth_bias;
        if !bias.constant_factor.is_finite() || !bias.slope_factor.is_finite() {
            return Err(Error::invalid(what(), format!("depth bias {bias:?} is not finite")));
        }
        if self.varyings.len() > MAX_VARYINGS {
            return Err(Error::invalid(what(), format!("{} varyings, at most {MAX_VARYINGS}", self.varyings.len())));
        }
        if self.color_targets.len() > MAX_COLOR_ATTACHMENTS {
            return Err(Error::invalid(
                what(),
                format!("{} colour targets, at most {MAX_COLOR_ATTACHMENTS}", self.color_targets.len()),
            ));
        }
        let input = &self.vertex_input;
        if input.bindings.len() > MAX_VERTEX_BINDINGS {
            return Err(Error::invalid(
                what(),
                format!("{} vertex bindings, at most {MAX_VERTEX_BINDINGS}", input.bindings.len()),
            ));
        }
        for (i, attribute) in input.attributes.iter().enumerate() {
            if attribute.location as usize >= MAX_VERTEX_ATTRIBUTES {
                return Err(Error::invalid(
                    what(),
                    format!("attribute {i} has location {}, at most {}", attribute.location, MAX_VERTEX_ATTRIBUTES - 1),
                ));
            }
            if input.attributes[..i].iter().any(|a| a.location == attribute.location) {
                return Err(Error::invalid(
                    what(),
                    format!("location {} is used by two attributes", attribute.location),
                ));
            }
            let Some(binding) = input.bindings.get(attribute.binding as usize) else {
                return Err(Error::invalid(
                    what(),
                    format!("attribute {i} reads binding {}, which is not declared", attribute.binding),
                ));
            };
            if binding.stride != 0 && attribute.offset + attribute.format.size_bytes() > binding.stride {
                return Err(Error::invalid(
                    what(),
                    format!(
                        "attribute {i} ({:?} at offset {}) does not fit in the stride {} of binding {}",
                        attribute.format, attribute.offset, binding.stride, attribute.binding
                    ),
                ));
            }
        }
        if self.blend_constant.iter().any(|c| !c.is_finite()) {
            return Err(Error::invalid(what(), "the blend constant is not finite"));
        }
        Ok(())
    }
}
