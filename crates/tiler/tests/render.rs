//! Integration tests of the rendering pipeline, in one binary (link time matters on 2 cores).

#[path = "render/blend.rs"]
mod blend;
#[path = "render/clipping.rs"]
mod clipping;
#[path = "render/common.rs"]
mod common;
#[path = "render/cost_model.rs"]
mod cost_model;
#[path = "render/depth_stencil.rs"]
mod depth_stencil;
#[path = "render/errors.rs"]
mod errors;
#[path = "render/fill_rule.rs"]
mod fill_rule;
#[path = "render/interpolation.rs"]
mod interpolation;
#[path = "render/invariant.rs"]
mod invariant;
#[path = "render/load_store.rs"]
mod load_store;
#[path = "render/msaa_hsr.rs"]
mod msaa_hsr;
#[path = "render/subpasses.rs"]
mod subpasses;
#[path = "render/texture_formats.rs"]
mod texture_formats;
