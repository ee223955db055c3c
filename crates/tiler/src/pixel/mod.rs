//! The pixel pipeline: a run of one draw's primitives through coverage, the depth and stencil
//! tests (or HSR's visibility), shading and blending into a render target, compiled once per
//! pipeline (`pipeline`: the one place the shaders' types are erased) and per SIMD level.
//! Tilers run it per tile, immediate mode per band of rows: the same code for every backend.

pub mod pipeline;
pub mod primitive;

pub use pipeline::Pipeline;
