//! Deferred shading with many lights, two ways (seed 002 "Render Pass Structure"):
//!
//! - [`Variant::Subpasses`]: one render pass. Subpass 0 writes the G-buffer — albedo, world
//!   normal, depth — into transient attachments; subpass 1 reads them as input attachments
//!   from the tile buffer and lights each pixel with every light. Only the lit colour is
//!   stored: the G-buffer never reaches external memory, nor even needs memory.
//! - [`Variant::Passes`]: the same frame as two render passes, the G-buffer stored to images in
//!   external memory by the first and loaded back by the second — what an application does
//!   without subpasses, and what it costs.
//!
//! Both give the same picture, bit for bit: the G-buffer holds the same values either way.
//!
//! The geometry is the built-in scene's opaque objects ([`build`]) or a glTF model's opaque and
//! alpha-masked primitives ([`build_model`], lit by a grid of lights over its bounds; BLEND
//! materials are left out: a G-buffer holds one surface per pixel).

use glam::Mat4;
use tiler::simd::{dot3, normalize3};
use tiler::*;

use crate::Scene;
use crate::builtin::{self, LIT_VARYINGS, LitVertexShader};
use crate::camera::{CameraChoice, place};
use crate::gltf::{AlphaMode, GltfVertex, Model, TextureBinding};
use crate::mesh::Vertex;
use crate::shading::{WORLD_VARYINGS, WorldVertexShader, material_surface};

/// How the frame is split into passes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// One render pass, two subpasses, the G-buffer transient.
    Subpasses,
    /// Two render passes through G-buffer images in memory.
    Passes,
}

/// Number of point lights.
pub const LIGHTS: usize = 48;

/// G-buffer formats: albedo, world normal, depth.
const ALBEDO: Format = Format::Rgba8Unorm;
const NORMAL: Format = Format::Rgba16Float;
const DEPTH: Format = Format::D32Float;

/// Writes the G-buffer: albedo (checkered floor as in the built-in scene) and world normal.
struct GBufferShader {
    color: [f32; 4],
    checker: Option<[f32; 4]>,
}

impl FragmentShader for GBufferShader {
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        let n = normalize3(frag.smooth_n::<3>(0));
        let albedo: [F32x8; 4] = match self.checker {
            None => self.color.map(F32x8::splat),
            Some(other) => {
                let [x, _, z] = frag.smooth_n::<3>(3);
                let cell = (x * 1.5).floor() + (z * 1.5).floor();
                let odd = cell - (cell * 0.5).floor() * 2.0;
                std::array::from_fn(|c| F32x8::splat(self.color[c]) + odd * (other[c] - self.color[c]))
            }
        };
        frag.set_color(0, [albedo[0], albedo[1], albedo[2], F32x8::ONE]);
        frag.set_color(1, [n[0], n[1], n[2], F32x8::ONE]);
    }
}

/// Writes the G-buffer of a glTF material: albedo = base colour factor × texture (alpha-masked
/// materials discard below their cutoff) and the world normal (reversed on the back of
/// double-sided materials).
struct GBufferModelShader {
    factor: [f32; 4],
    texture: Option<TextureBinding>,
    alpha: AlphaMode,
    two_sided: bool,
}

impl FragmentShader for GBufferModelShader {
    fn properties(&self) -> ShaderProperties {
        ShaderProperties { discards: matches!(self.alpha, AlphaMode::Mask { .. }), ..ShaderProperties::default() }
    }

    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        let (base, n) = material_surface(frag, self.factor, self.texture.as_ref(), self.alpha, self.two_sided);
        frag.set_color(0, [base[0], base[1], base[2], F32x8::ONE]);
        frag.set_color(1, [n[0], n[1], n[2], F32x8::ONE]);
    }
}

/// A full-screen triangle.
struct FullScreen;

impl VertexShader for FullScreen {
    fn shade(&self, input: &VertexInput, out: &mut VertexOutput) {
        out.position = input.attributes[0];
    }
}

/// A point light: position, colour, radius of influence.
#[derive(Clone, Copy, Debug)]
struct Light {
    position: [f32; 3],
    color: [f32; 3],
    radius: f32,
}

/// Lights every pixel from the G-buffer inputs: albedo × (ambient + directional + Σ point
/// lights with a smooth falloff). Pixels the geometry never covered (depth 1) get the sky.
struct LightingShader {
    inverse_view_proj: Mat4,
    width: f32,
    height: f32,
    lights: Vec<Light>,
}

const SKY: [f32; 4] = [0.42, 0.55, 0.72, 1.0];

impl FragmentShader for LightingShader {
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        let albedo = frag.input(0);
        let normal = frag.input(1);
        let depth = frag.input(2)[0];
        let (x, y) = frag.position();
        // Window → NDC (Vulkan: y down, depth 0..1) → world.
        let ndc_x = x * (2.0 / self.width) - 1.0;
        let ndc_y = y * (2.0 / self.height) - 1.0;
        let m = self.inverse_view_proj.to_cols_array();
        let row = |r: usize| {
            F32x8::splat(m[r]) * ndc_x + F32x8::splat(m[4 + r]) * ndc_y + F32x8::splat(m[8 + r]) * depth + m[12 + r]
        };
        let w = row(3);
        let world = [row(0) / w, row(1) / w, row(2) / w];
        let n = [normal[0], normal[1], normal[2]];
        let sun = [0.37, 0.86, 0.35].map(F32x8::splat);
        let mut light = [F32x8::splat(0.18) + n[1] * 0.08; 3];
        let direct = dot3(n, sun).max(F32x8::ZERO) * 0.35;
        for c in &mut light {
            *c += direct;
        }
        for l in &self.lights {
            let to = [
                F32x8::splat(l.position[0]) - world[0],
                F32x8::splat(l.position[1]) - world[1],
                F32x8::splat(l.position[2]) - world[2],
            ];
            let distance2 = dot3(to, to);
            let falloff = (F32x8::ONE - distance2 * (1.0 / (l.radius * l.radius))).max(F32x8::ZERO);
            let lambert = dot3(n, normalize3(to)).max(F32x8::ZERO);
            let k = lambert * falloff * falloff;
            for (c, channel) in light.iter_mut().enumerate() {
                *channel += k * l.color[c];
            }
        }
        let sky = depth.ge(F32x8::ONE);
        let out: [F32x8; 3] = std::array::from_fn(|c| F32x8::select(sky, F32x8::splat(SKY[c]), albedo[c] * light[c]));
        frag.set_color(0, [out[0], out[1], out[2], F32x8::ONE]);
    }
}

/// Lights on a grid over the courtyard floor, colours from a fixed palette.
fn lights() -> Vec<Light> {
    let palette =
        [[1.0, 0.55, 0.25], [0.3, 0.6, 1.0], [0.4, 1.0, 0.5], [1.0, 0.35, 0.7], [0.9, 0.9, 0.6], [0.5, 0.4, 1.0]];
    (0..LIGHTS)
        .map(|i| {
            let (gx, gz) = ((i % 8) as f32, (i / 8) as f32);
            Light {
                position: [-5.0 + gx * 1.45, 0.35 + 0.25 * (i % 3) as f32, -4.0 + gz * 1.5],
                color: palette[i % palette.len()].map(|c| c * 0.9),
                radius: 2.2,
            }
        })
        .collect()
}

/// Builds the deferred frame of the built-in scene's opaque objects on `device`.
///
/// # Errors
/// A size the device refuses.
pub fn build(device: &mut Device, width: u32, height: u32, variant: Variant) -> Result<Scene> {
    let camera = builtin::camera();
    let view_proj = camera.view_proj(width as f32 / height as f32);

    // G-buffer draws.
    let input = VertexInputState::interleaved(&[VertexFormat::Float32x3, VertexFormat::Float32x3]);
    let mut gbuffer_draws = Vec::new();
    let mut triangles = 0;
    for (i, object) in builtin::objects().into_iter().filter(|o| !o.translucent).enumerate() {
        let vertices = device.create_buffer_from::<Vertex>(&object.mesh.vertices)?;
        let indices = device.create_buffer_from::<u32>(&object.mesh.indices)?;
        let mut desc = PipelineDesc::new(format!("g-buffer {i}"), input.clone());
        desc.varyings = LIT_VARYINGS.to_vec();
        desc.cull_mode = CullMode::Back;
        desc.depth_stencil = DepthStencilState::LESS_WRITE;
        desc.color_targets = vec![ColorTargetState::REPLACE; 2];
        let pipeline = Pipeline::new(
            LitVertexShader::new(object.model, view_proj),
            GBufferShader { color: object.color, checker: object.checker },
            desc,
        )?;
        triangles += object.mesh.triangles() as u64;
        gbuffer_draws.push(Draw::indexed(
            &pipeline,
            vertices,
            indices,
            IndexType::U32,
            0,
            object.mesh.indices.len() as u32,
        ));
    }

    let name = match variant {
        Variant::Subpasses => "deferred (subpasses)",
        Variant::Passes => "deferred (two passes)",
    };
    let frame = Geometry { view_proj, gbuffer_draws, triangles, lights: lights() };
    assemble(device, width, height, variant, frame, name.into())
}

/// The deferred frame of a glTF model's opaque and alpha-masked primitives, seen from
/// `camera` (as [`crate::shading::build_model_scene`] places it), lit by [`LIGHTS`] point
/// lights on a grid over the model's bounds.
///
/// # Errors
/// A size the device refuses, a camera that cannot be placed, a model with nothing opaque.
pub fn build_model(
    device: &mut Device,
    model: &Model,
    width: u32,
    height: u32,
    camera: CameraChoice,
    variant: Variant,
) -> Result<Scene> {
    let placement = place(model, camera, width as f64 / height as f64)
        .map_err(|reason| Error::invalid(model.file_name(), reason))?;
    // GL clip space → Vulkan's, as `gl_to_vulkan_clip` does per vertex: (x, −y, (z + w)/2, w).
    let gl_to_vulkan =
        Mat4::from_cols_array(&[1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.5, 1.0]);
    let view_proj = gl_to_vulkan * placement.gl_view_proj;

    let input =
        VertexInputState::interleaved(&[VertexFormat::Float32x3, VertexFormat::Float32x3, VertexFormat::Float32x2]);
    let mut gbuffer_draws = Vec::new();
    let mut triangles = 0;
    for primitive in &model.primitives {
        let material = &model.materials[primitive.material];
        if material.alpha_mode == AlphaMode::Blend {
            continue;
        }
        let vertices = device.create_buffer_from::<GltfVertex>(&primitive.vertices)?;
        let indices = device.create_buffer_from::<u32>(&primitive.indices)?;
        let mut desc = PipelineDesc::new(format!("g-buffer {}", primitive.label), input.clone());
        desc.varyings = WORLD_VARYINGS.to_vec();
        desc.front_face = FrontFace::CounterClockwise;
        desc.cull_mode = CullMode::None;
        desc.depth_stencil = DepthStencilState::LESS_WRITE;
        desc.color_targets = vec![ColorTargetState::REPLACE; 2];
        let shader = GBufferModelShader {
            factor: material.base_color_factor,
            texture: material.base_color_texture.clone(),
            alpha: material.alpha_mode,
            two_sided: material.double_sided,
        };
        let pipeline = Pipeline::new(WorldVertexShader { gl_view_proj: placement.gl_view_proj }, shader, desc)?;
        triangles += primitive.triangles() as u64;
        gbuffer_draws.push(Draw::indexed(
            &pipeline,
            vertices,
            indices,
            IndexType::U32,
            0,
            primitive.indices.len() as u32,
        ));
    }
    if gbuffer_draws.is_empty() {
        return Err(Error::invalid(model.file_name(), "no opaque or alpha-masked primitive to shade deferred"));
    }
    let name = format!(
        "{} deferred ({})",
        model.file_name(),
        if variant == Variant::Subpasses { "subpasses" } else { "two passes" }
    );
    let frame = Geometry { view_proj, gbuffer_draws, triangles, lights: model_lights(model) };
    assemble(device, width, height, variant, frame, name)
}

/// Lights on an 8 × 6 grid over the model's bounds, a little above the middle of its height,
/// each reaching about a quarter of its width.
fn model_lights(model: &Model) -> Vec<Light> {
    let (min, max) = (model.min.as_vec3(), model.max.as_vec3());
    let size = max - min;
    let palette = lights();
    (0..LIGHTS)
        .map(|i| {
            let (gx, gz) = ((i % 8) as f32 + 0.5, (i / 8) as f32 + 0.5);
            let lift = 0.35 + 0.15 * (i % 3) as f32;
            Light {
                position: [min.x + size.x * gx / 8.0, min.y + size.y * lift, min.z + size.z * gz / 6.0],
                color: palette[i].color,
                radius: 0.25 * size.x.max(size.z).max(size.y),
            }
        })
        .collect()
}

/// What the G-buffer subpass draws, and what lights the lighting subpass.
struct Geometry {
    /// Vulkan clip space (y down, depth 0..1) of the world.
    view_proj: Mat4,
    gbuffer_draws: Vec<Draw>,
    triangles: u64,
    lights: Vec<Light>,
}

/// The frame's passes around its G-buffer draws: one pass with two subpasses, or two passes.
fn assemble(
    device: &mut Device,
    width: u32,
    height: u32,
    variant: Variant,
    frame: Geometry,
    name: String,
) -> Result<Scene> {
    let Geometry { view_proj, gbuffer_draws, mut triangles, lights } = frame;
    let transient = variant == Variant::Subpasses;
    let image = |device: &mut Device, format| {
        let desc = ImageDesc::new(width, height, format);
        device.create_image(if transient { desc.transient() } else { desc })
    };
    let lit = device.create_image(ImageDesc::new(width, height, Format::Rgba8Unorm))?;
    let albedo = image(device, ALBEDO)?;
    let normal = image(device, NORMAL)?;
    let depth = image(device, DEPTH)?;

    // The lighting draw: one triangle over the screen.
    let corners: [[f32; 4]; 3] = [[-1.0, -1.0, 0.0, 1.0], [3.0, -1.0, 0.0, 1.0], [-1.0, 3.0, 0.0, 1.0]];
    let screen = device.create_buffer_from(&corners)?;
    let lighting = Pipeline::new(
        FullScreen,
        LightingShader { inverse_view_proj: view_proj.inverse(), width: width as f32, height: height as f32, lights },
        PipelineDesc::new("lighting", VertexInputState::interleaved(&[VertexFormat::Float32x4])),
    )?;
    let lighting_draw = Draw::new(&lighting, screen, 0, 3);
    triangles += 1;

    let clear_gbuffer = |store| ColorAttachment { image: albedo, load: LoadOp::Clear([0.0; 4]), store, resolve: None };
    let passes = match variant {
        Variant::Subpasses => {
            let desc = RenderPassDesc {
                color: vec![
                    ColorAttachment::clear_store(lit, SKY),
                    clear_gbuffer(StoreOp::DontCare),
                    ColorAttachment {
                        image: normal,
                        load: LoadOp::Clear([0.0; 4]),
                        store: StoreOp::DontCare,
                        resolve: None,
                    },
                ],
                depth_stencil: Some(DepthStencilAttachment::clear_discard(depth, 1.0)),
                render_area: None,
            };
            let subpasses = vec![
                SubpassDesc { color: vec![1, 2], depth_stencil: true, ..SubpassDesc::default() },
                SubpassDesc {
                    color: vec![0],
                    input: vec![AttachmentRef::Color(1), AttachmentRef::Color(2), AttachmentRef::DepthStencil],
                    ..SubpassDesc::default()
                },
            ];
            let dependency = SubpassDependency { src: 0, dst: 1, by_region: true };
            let mut pass = RenderPass::with_subpasses(desc, subpasses, vec![dependency]);
            for draw in gbuffer_draws {
                pass.draw(draw);
            }
            pass.next_subpass().draw(lighting_draw);
            vec![pass]
        }
        Variant::Passes => {
            let mut first = RenderPass::new(RenderPassDesc {
                color: vec![
                    clear_gbuffer(StoreOp::Store),
                    ColorAttachment {
                        image: normal,
                        load: LoadOp::Clear([0.0; 4]),
                        store: StoreOp::Store,
                        resolve: None,
                    },
                ],
                depth_stencil: Some(DepthStencilAttachment::clear_store(depth, 1.0, 0)),
                render_area: None,
            });
            for draw in gbuffer_draws {
                first.draw(draw);
            }
            let load = |image| ColorAttachment { image, load: LoadOp::Load, store: StoreOp::DontCare, resolve: None };
            let desc = RenderPassDesc {
                color: vec![ColorAttachment::clear_store(lit, SKY), load(albedo), load(normal)],
                depth_stencil: Some(DepthStencilAttachment {
                    image: depth,
                    depth_load: LoadOp::Load,
                    depth_store: StoreOp::DontCare,
                    stencil_load: LoadOp::DontCare,
                    stencil_store: StoreOp::DontCare,
                }),
                render_area: None,
            };
            let subpass = SubpassDesc {
                color: vec![0],
                input: vec![AttachmentRef::Color(1), AttachmentRef::Color(2), AttachmentRef::DepthStencil],
                ..SubpassDesc::default()
            };
            let mut second = RenderPass::with_subpasses(desc, vec![subpass], Vec::new());
            second.draw(lighting_draw);
            vec![first, second]
        }
    };
    Ok(Scene { name, width, height, color: lit, passes, triangles })
}
