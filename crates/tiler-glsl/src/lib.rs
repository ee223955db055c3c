//! GLSL ES 1.00 programs compiled at run time and run as tiler shaders.
//!
//! [`CompiledProgram::new`] parses a vertex and a fragment shader (with
//! [glsl-lang](https://docs.rs/glsl-lang), preprocessor included; `GL_ES` is predefined),
//! type-checks and lowers them into a lane-wide IR ([`ir`]), and links them: attributes get
//! locations, varyings are matched by name and packed into tiler's varyings, uniforms get
//! GL-style locations. [`shaders`] (or [`pipeline`]) turns the program, its uniform values,
//! its texture units and the framebuffer height into a [`tiler::VertexShader`] and a
//! [`tiler::FragmentShader`], which run the IR in the executor ([`exec`]).
//!
//! # Language
//!
//! GLSL ES 1.00: `attribute`/`varying`/`uniform`, precision qualifiers (parsed; all float
//! math is f32), `float`/`int`/`bool` and their vectors, `mat2`–`mat4`, `sampler2D`, structs,
//! arrays (constant sizes; dynamic indices allowed), `const`, user functions with
//! `in`/`out`/`inout` parameters (inlined at each call), `if`/`else`, `for`/`while`/
//! `do`-`while` with `break`/`continue`/`return`/`discard` in divergent control flow, and the
//! ES 1.00 built-in functions: angle and trigonometry, exponentials, `abs` … `smoothstep`,
//! the geometric functions, `matrixCompMult`, the vector relational functions, `texture2D`
//! (with a bias), `texture2DProj`, `texture2DLod`/`texture2DProjLod`, and
//! `OES_standard_derivatives`' `dFdx`/`dFdy`/`fwidth` (fine derivatives within each 2×2
//! quad, y up as in GL). Built-in variables:
//! `gl_Position`, `gl_PointSize` (accepted, unused), `gl_FragCoord`, `gl_FrontFacing`,
//! `gl_FragColor`, `gl_FragData[n]`, `gl_PointCoord` (reads zero). From ES 3.00 where it is
//! cheap: `in`/`out` (outputs with `layout(location)`), `texture`/`textureProj`/`textureLod`,
//! `trunc`, `round`, `transpose`.
//!
//! Not supported (a compile error naming the shader and line): `samplerCube`/`textureCube`
//! (tiler has no cube textures), `switch`, bit operations and `%`,
//! interface blocks. Simplifications: the operands of `&&`, `||` and `?:` are all evaluated
//! and then selected per lane (a side effect in the untaken one happens); ints mix with
//! floats (promoted, as desktop GLSL allows); ints are held in f32 (exact to 2²⁴, beyond ES
//! 1.00's required ±2¹⁶).
//!
//! # IR and executor
//!
//! Values are lists of component registers, each `W` lanes of f32 ([`ir`]); arithmetic is
//! scalarised (a `vec4` add is four instructions; `dot`, matrix products, `normalize` expand
//! into adds, multiplies and a square root in a fixed order, which the tests reproduce in
//! Rust bit for bit). Control flow stays structured and runs under lane masks ([`exec`]).
//! The executor is generic over the lane count: fragment shaders run 8 lanes (tiler's 4×2
//! group, helper lanes included), vertex shaders 1 lane per `VertexShader::shade` call, so
//! batching vertices, wider fragment batches or a JIT can replace the interpreter without
//! touching the compiler. Results are deterministic: every register a call reads was
//! written in that call, loops are capped at [`exec::MAX_ITERATIONS`], and the built-ins are
//! std's f32 functions.
//!
//! # Coordinate conventions
//!
//! `gl_Position` is GL clip space; the vertex shader hands tiler `(x, −y, (z + w)/2, w)`, as
//! tiler-gl's built-in programs do. `gl_FragCoord` is GL's window position: `x` and
//! `height − y` from tiler's pixel centres (y down), window depth, and `1/w` (a hidden
//! varying carries clip w when the fragment shader reads `gl_FragCoord`). Texture
//! coordinates are GL's (t up): a core texture is sampled at `(s, 1 − t)`, as tiler stores
//! rows top first. `gl_FrontFacing` is tiler's front-facing flag; the pipeline's front face
//! must be set for the flipped y (as tiler-gl does).

pub mod compile;
pub mod exec;
pub mod ir;
mod program;
pub mod types;

pub use program::{
    AttributeInfo, CompiledProgram, GlslFragmentShader, GlslVertexShader, TextureBinding, TextureSource, UniformInfo,
    UniformValues, VaryingInfo, pipeline, shaders,
};
pub use types::{SamplerKind, Scalar, StructType, Type};

/// A shader stage.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Stage {
    Vertex,
    Fragment,
}

impl std::fmt::Display for Stage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Stage::Vertex => "vertex shader",
            Stage::Fragment => "fragment shader",
        })
    }
}

/// What compiling, linking or setting a uniform refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Error {
    #[error("{stage}, line {line}: {message}")]
    Compile { stage: Stage, line: u32, message: String },
    #[error("link: {0}")]
    Link(String),
    #[error("{0}")]
    Uniform(String),
}
