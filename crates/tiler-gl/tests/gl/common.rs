//! Helpers shared by the tests: small contexts, a full-screen quad, and shorthand for calls.

#![allow(dead_code)]

use tiler_gl::report::{LoadKind, StoreKind};
use tiler_gl::*;

/// A small window (so tests stay fast) with one worker thread.
pub fn config(width: u32, height: u32) -> ContextConfig {
    ContextConfig { threads: 1, ..ContextConfig::new(width, height) }
}

pub fn context(width: u32, height: u32) -> Context {
    Context::new(config(width, height)).unwrap()
}

/// Executes a call, panicking with its error.
pub fn c(gl: &mut Context, call: Call) -> Output {
    gl.call(call).unwrap_or_else(|e| panic!("{e}"))
}

/// Two triangles covering NDC `[x0, x1] × [y0, y1]` (GL, y up) at depth `z`.
pub fn quad(x0: f32, y0: f32, x1: f32, y1: f32, z: f32) -> Vec<[f32; 3]> {
    vec![[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y0, z], [x1, y1, z], [x0, y1, z]]
}

/// Makes program `id` of `kind` and buffer `id` holding `vertices`, and points attribute 0
/// at it.
pub fn geometry(gl: &mut Context, id: u32, kind: ProgramKind, vertices: &[[f32; 3]]) {
    c(gl, Call::CreateBuffer { id, data: Bytes::from_slice(vertices) });
    c(gl, Call::CreateProgram { id, program: kind.into() });
    bind_geometry(gl, id);
}

/// Uses program `id` and reads attribute 0 from buffer `id`.
pub fn bind_geometry(gl: &mut Context, id: u32) {
    c(gl, Call::UseProgram { id });
    attribute_from(gl, id);
}

/// Reads attribute 0 (three floats a vertex) from `buffer`.
pub fn attribute_from(gl: &mut Context, buffer: u32) {
    c(
        gl,
        Call::VertexAttribPointer {
            index: 0,
            buffer,
            size: 3,
            component: ComponentType::Float,
            normalized: false,
            stride: 0,
            offset: 0,
        },
    );
    c(gl, Call::EnableVertexAttrib { index: 0 });
}

pub fn set_color(gl: &mut Context, rgba: [f32; 4]) {
    c(gl, Call::Uniform { name: "color".into(), value: UniformValue::Vec4(rgba) });
}

pub fn draw(gl: &mut Context, count: u32) {
    c(gl, Call::DrawArrays { mode: Mode::Triangles, first: 0, count });
}

pub fn clear_all(gl: &mut Context) {
    c(gl, Call::Clear { color: true, depth: true, stencil: true });
}

pub fn swap(gl: &mut Context) {
    c(gl, Call::SwapBuffers);
}

pub fn bind(gl: &mut Context, framebuffer: u32) {
    c(gl, Call::BindFramebuffer { target: FramebufferTarget::Framebuffer, framebuffer });
}

/// Framebuffer `id` with an RGBA8 colour texture `id` and a `depth24_stencil8` renderbuffer
/// `id`, all `w × h`.
pub fn framebuffer(gl: &mut Context, id: u32, w: u32, h: u32) {
    c(gl, Call::CreateTexture { id, width: w, height: h, format: TextureFormat::Rgba8, data: None, transient: false });
    c(
        gl,
        Call::CreateRenderbuffer {
            id,
            width: w,
            height: h,
            format: TextureFormat::Depth24Stencil8,
            samples: 1,
            transient: false,
        },
    );
    c(gl, Call::CreateFramebuffer { id });
    c(gl, Call::FramebufferTexture { framebuffer: id, attachment: AttachmentPoint::Color0, texture: id, samples: 1 });
    c(
        gl,
        Call::FramebufferRenderbuffer { framebuffer: id, attachment: AttachmentPoint::DepthStencil, renderbuffer: id },
    );
}

/// The ops of each aspect of a pass, as `(slot, load, store)`.
pub fn ops(pass: &PassRecord) -> Vec<(String, LoadKind, StoreKind)> {
    pass.attachments.iter().map(|a| (a.slot.to_string(), a.load, a.store)).collect()
}

/// The ops of one aspect.
pub fn op(pass: &PassRecord, slot: Slot) -> (LoadKind, StoreKind) {
    let a = pass.attachment(slot).unwrap_or_else(|| panic!("no {slot} in pass {}", pass.index));
    (a.load, a.store)
}

/// Every pass of a report.
pub fn passes(report: &Report) -> Vec<&PassRecord> {
    report.passes().collect()
}

/// The RGBA8 pixel at (x, y) of tiler's top-first rows.
pub fn pixel(rgba: &[u8], width: u32, x: u32, y: u32) -> [u8; 4] {
    let i = ((y * width + x) * 4) as usize;
    rgba[i..i + 4].try_into().unwrap()
}
