//! Integration tests of the GL-style context, traces and advisor, in one binary (link time
//! matters on 2 cores).

#[path = "gl/common.rs"]
mod common;
#[path = "gl/contexts.rs"]
mod contexts;
#[path = "gl/encoded.rs"]
mod encoded;
#[path = "gl/fuzz.rs"]
mod fuzz;
#[path = "gl/gles3.rs"]
mod gles3;
#[path = "gl/glsl.rs"]
mod glsl;
#[path = "gl/inference.rs"]
mod inference;
#[path = "gl/smoke.rs"]
mod smoke;
#[path = "gl/subpasses.rs"]
mod subpasses;
#[path = "gl/traces.rs"]
mod traces;
