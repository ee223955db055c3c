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
//! math is f32), `float`/`int`/`bool` and their vectors, `mat2`–`mat4`, `sampler2D`,
//! `samplerCube`, structs,
//! arrays (constant sizes; dynamic indices allowed), `const`, user functions with
//! `in`/`out`/`inout` parameters (inlined at each call), `if`/`else`, `for`/`while`/
//! `do`-`while` with `break`/`continue`/`return`/`discard` in divergent control flow, and the
//! ES 1.00 built-in functions: angle and trigonometry, exponentials, `abs` … `smoothstep`,
//! the geometric functions, `matrixCompMult`, the vector relational functions, `texture2D`
//! (with a bias), `texture2DProj`, `texture2DLod`/`texture2DProjLod`, `textureCube` (with a
//! bias), `textureCubeLod` (core cube textures, in both stages), and
//! `OES_standard_derivatives`' `dFdx`/`dFdy`/`fwidth` (fine derivatives within each 2×2
//! quad, y up as in GL). Built-in variables:
//! `gl_Position`, `gl_PointSize` and `gl_PointCoord` (each a hidden varying when named: the
//! core sizes points from the first and fills the second at their corners; see
//! `CompiledProgram::point_size_varying`), `gl_FragCoord`, `gl_FrontFacing`, `gl_FragColor`,
//! `gl_FragData[n]`. From ES 3.00 where it is
//! cheap (`#version 300 es`): `in`/`out` (inputs and outputs with `layout(location)`),
//! `texture`/`textureProj`/`textureLod`, `trunc`, `round`, `transpose`, `gl_VertexID` and
//! `gl_InstanceID` (the caller's, [`GlslVertexShader::set_instance`]), and uniform blocks
//! (`uniform Name { … } [instance];`, laid out `std140` — `shared` is taken to be the same —
//! and set from a buffer's bytes with [`CompiledProgram::set_uniform_block`]; see [`std140`]).
//!
//! Also from ES 3.00 (any version is accepted): `switch` (fall-through, `break`, per-lane
//! selectors), 32-bit `int` and `uint`/`uvecN` with `1u` literals, wrapping arithmetic,
//! `%`, the bit operations and shifts, and the integer built-ins `abs`, `sign`, `min`,
//! `max`, `clamp` and the bit casts (`floatBitsToInt` …); undefined cases are defined (see
//! [`ir`]: division by zero gives 0, shift counts are taken modulo 32, float → integer
//! saturates).
//!
//! ES 3.00's `sampler2DArray` and `sampler3D` (core 2-D array and 3-D textures) take
//! `texture` (with a bias), `textureLod` and, on a `sampler3D`, `textureProj`, in both stages.
//!
//! Not supported (a compile error naming the shader and line): `flat` (GL takes a flat
//! varying from a primitive's last vertex, tiler's core from its first) and so integer
//! varyings, integer attributes, integer colour outputs and integer samplers, in/out blocks,
//! arrays of uniform blocks, `packed` and `row_major` blocks. Simplifications: the operands
//! of `&&`, `||` and `?:` are all evaluated and then selected per lane (a side effect in the
//! untaken one happens); ints and uints mix with floats (converted, as desktop GLSL allows).
//!
//! Limits, each a compile error: [`compile::MAX_INSTRUCTIONS`] instructions and
//! [`compile::MAX_REGISTERS`] registers per stage (inlining can grow code exponentially),
//! [`compile::MAX_ARRAY_COMPONENTS`] per array, [`compile::MAX_CALL_DEPTH`] nested calls.
//!
//! # Linking and instances
//!
//! Attributes bound by the caller (`glBindAttribLocation`) or by `layout(location)` keep
//! their locations; the others take the lowest free ones in declaration order (a `matN`
//! takes N). Varyings the fragment shader reads must be declared by the vertex shader with
//! the same type; they are packed in the fragment shader's order, as smooth floats
//! ([`CompiledProgram::pipeline_varyings`]). Uniforms get locations in declaration order,
//! the vertex shader's first, then the fragment shader's new ones; an array takes one per
//! element, a struct is listed field by field (`light.color`), as GL's introspection lists
//! them. A program's recorded locations (a trace's `glGetUniformLocation` results) map to
//! these by name. Sampler uniforms hold texture units; each unit is a [`TextureBinding`]: a
//! core texture sampled through `Fragments::sample` (counted in the texture-cache model) or
//! the caller's [`TextureSource`]. A vertex shader reads a core texture filtered at level of
//! detail 0 (GL's rule: the magnification filter on level 0) or at its explicit level, and an
//! explicit level in a fragment shader reads the same way, all uncounted; a bias applies per
//! 4×2 group (its first lane's).
//!
//! # IR and executor
//!
//! Values are lists of component registers, each `W` lanes of f32 ([`ir`]); arithmetic is
//! scalarised (a `vec4` add is four instructions; `dot`, matrix products, `normalize` expand
//! into adds, multiplies and a square root in a fixed order, which the tests reproduce in
//! Rust bit for bit). Control flow stays structured and runs under lane masks ([`exec`]).
//! The executor is generic over the lane count: fragment shaders run 8 lanes (tiler's 4×2
//! group, helper lanes included), vertex shaders 8 lanes (the core hands
//! `VertexShader::shade_batch` up to 8 vertices), so wider batches or compiled code (below)
//! can replace the interpreter without touching the compiler. Results are deterministic: every register a
//! call reads was written in that call, loops are capped at [`exec::MAX_ITERATIONS`], and the
//! built-ins are std's f32 functions.
//!
//! Before running, [`ir`] code is optimised as a GPU's compiler would (`fold`: constant
//! folding, `x·1 → x`, `x·0 → 0`, `x + 0 → x`, and removal of whatever nothing reads —
//! texture lookups included, so a convolution weight of the constant 0.0 removes its fetch
//! from the ledger, as it does on hardware; GLSL ES does not require the NaN, infinity and
//! signed-zero results these rules can change), hoisted (uniform-only arithmetic computed
//! once per instance, `hoist`) and fused (a multiply whose only use is an add becomes one
//! [`ir::TriOp::MulAdd`], rounded twice as the pair was, `fuse`), then scheduled (lookups of
//! one texture that do not depend on each other brought together, every dependency and the
//! order of texture reads kept, `schedule`: the executor takes such a run as one call). The
//! executor runs an
//! [`exec::Executable`]: the code with the bank renumbered after the work registers, so that
//! one register file per thread holds both and every register is range-checked once.
//!
//! Measured with `benches/executor.rs` (a Blinn-Phong fragment shader over a 256×256
//! full-screen triangle through `Device`, one tile thread; the interpreter's AVX2 build), on
//! a 2-core machine under a load average of 9–11 (2026-11-26): after subtracting the
//! pipeline's own cost (a flat shader), the shader costs ≈ 39–43 ns per fragment native
//! (`powf` per lane) and ≈ 30–38 ns interpreted, i.e. no more than native, because the
//! per-lane `powf` both call dominates and the interpreter's dispatch is amortised over 8
//! lanes.
//! Shaders of cheap arithmetic show the interpreter more: it was 11–19% of the
//! instructions of the arithmetic-heavy glmark2 captures (callgrind), see
//! docs/benchmarking.md.
//!
//! On x86-64 processors with AVX2 and F16C, each executable is also compiled to machine code
//! when it is made (`exec::jit`, a template compiler: every instruction becomes the AVX2
//! instructions the interpreter's own loop performs, registers left in the register file;
//! transcendentals, conversions, texture lookups and derivatives call the interpreter for
//! that one instruction), and [`exec::run`] runs that code for eight lanes. It gives the
//! interpreter's bits (tested on random programs); `TILER_GLSL_JIT=0` in the environment
//! switches it off. It took glmark2's `conditionals` capture 16% and `shading` 7% faster
//! (docs/benchmarking.md).
//!
//! # Coordinate conventions
//!
//! `gl_Position` is GL clip space; the vertex shader hands tiler `(x, −y, (z + w)/2, w)`, as
//! tiler-gl's built-in programs do. `gl_FragCoord` is GL's window position: `x` and
//! `height − y` from tiler's pixel centres (y down), window depth, and `1/w` (a hidden
//! varying carries clip w when the fragment shader reads `gl_FragCoord`). Texture
//! coordinates are GL's (t up): a core texture is sampled at `(s, 1 − t)`, as tiler stores
//! rows top first. `gl_FrontFacing` is tiler's front-facing flag: with tiler-gl's mapping of
//! `glFrontFace` (`GL_CCW` → `FrontFace::CounterClockwise`, the picture being upright in both
//! windows) it is GL's (tested).

pub mod compile;
pub mod exec;
mod feedback;
mod fold;
mod fuse;
pub mod guard;
mod hoist;
pub mod ir;
mod nested_macros;
mod program;
mod schedule;
pub mod std140;
pub mod types;

pub use feedback::FeedbackVarying;
pub use program::{
    AttributeInfo, CompiledProgram, GlslFragmentShader, GlslVertexShader, TextureBinding, TextureSource,
    UniformBlockInfo, UniformInfo, UniformValues, VaryingInfo, pipeline, shaders,
};
pub use types::{IntegerShape, SamplerKind, Scalar, StructType, Type};

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
