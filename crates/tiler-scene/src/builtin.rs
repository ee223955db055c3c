//! The built-in scene: lit objects on a checkered floor, with overlap, depth complexity and one
//! translucent object, made entirely in code so `tiler render` needs no files.

use glam::{Mat3, Mat4, Quat, Vec3};
use tiler::simd::{dot3, normalize3};
use tiler::*;

use crate::Scene;
use crate::camera::Camera;
use crate::mesh::{Mesh, Vertex};

/// Direction towards the light, world space (y up).
const LIGHT: [f32; 3] = [0.37, 0.86, 0.35];

/// Transforms positions to clip space and passes the world normal and position on.
pub struct LitVertexShader {
    pub model: Mat4,
    pub normal_matrix: Mat3,
    pub view_proj: Mat4,
}

impl LitVertexShader {
    pub fn new(model: Mat4, view_proj: Mat4) -> LitVertexShader {
        LitVertexShader { model, normal_matrix: Mat3::from_mat4(model).inverse().transpose(), view_proj }
    }
}

impl VertexShader for LitVertexShader {
    fn shade(&self, input: &VertexInput, out: &mut VertexOutput) {
        let world = self.model * input.attributes[0].truncate().extend(1.0);
        let normal = self.normal_matrix * input.attributes[1].truncate();
        out.position = self.view_proj * world;
        out.varyings[..3].copy_from_slice(&normal.to_array());
        out.varyings[3..6].copy_from_slice(&world.truncate().to_array());
    }
}

/// The varyings [`LitVertexShader`] writes: world normal, world position.
pub const LIT_VARYINGS: [Interpolation; 6] = [Interpolation::Perspective; 6];

/// Lambert lighting with a hemisphere ambient term; optionally a checkerboard in world x/z.
pub struct LitFragmentShader {
    pub color: [f32; 4],
    /// Second colour of the checkerboard, if any.
    pub checker: Option<[f32; 4]>,
}

impl FragmentShader for LitFragmentShader {
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        let n = normalize3(frag.smooth_n::<3>(0));
        let light = LIGHT.map(F32x8::splat);
        let diffuse = dot3(n, light).max(F32x8::ZERO);
        let ambient = F32x8::splat(0.22) + n[1] * 0.12;
        let lit = ambient + diffuse * 0.72;
        let base: [F32x8; 4] = match self.checker {
            None => self.color.map(F32x8::splat),
            Some(other) => {
                let [x, _, z] = frag.smooth_n::<3>(3);
                let cell = (x * 1.5).floor() + (z * 1.5).floor();
                let odd = cell - (cell * 0.5).floor() * 2.0;
                std::array::from_fn(|c| F32x8::splat(self.color[c]) + odd * (other[c] - self.color[c]))
            }
        };
        frag.set_color(0, [base[0] * lit, base[1] * lit, base[2] * lit, base[3]]);
    }
}

/// One object of the scene.
pub struct Object {
    pub mesh: Mesh,
    pub model: Mat4,
    pub color: [f32; 4],
    pub checker: Option<[f32; 4]>,
    pub translucent: bool,
}

/// The built-in scene's camera.
pub fn camera() -> Camera {
    Camera::look_at(Vec3::new(0.4, 3.4, 8.0), Vec3::new(0.0, 0.7, 0.0), 45f32.to_radians(), 0.1, 60.0)
}

/// Builds the built-in scene on `device`: one render pass into a `width × height` RGBA8 image
/// with a transient D24S8 depth buffer, at `samples` samples per pixel (resolved in the tile).
///
/// # Errors
/// A size the device refuses (zero or above the limits).
pub fn build(device: &mut Device, width: u32, height: u32, samples: u32) -> Result<Scene> {
    let view_proj = camera().view_proj(width as f32 / height as f32);
    let objects = objects();
    build_with(device, width, height, samples, objects, view_proj)
}

/// The objects of the built-in scene, in draw order (the translucent one last).
pub fn objects() -> Vec<Object> {
    let at = |x: f32, y: f32, z: f32| Mat4::from_translation(Vec3::new(x, y, z));
    let opaque = |mesh, model, color: [f32; 3]| Object {
        mesh,
        model,
        color: [color[0], color[1], color[2], 1.0],
        checker: None,
        translucent: false,
    };
    let mut objects = vec![
        Object {
            mesh: Mesh::plane(8),
            model: Mat4::from_scale(Vec3::splat(7.0)),
            color: [0.78, 0.76, 0.72, 1.0],
            checker: Some([0.36, 0.38, 0.42, 1.0]),
            translucent: false,
        },
        // Back row first: the front objects overdraw it.
        opaque(Mesh::cube(), at(-1.2, 1.6, -3.2) * Mat4::from_scale(Vec3::new(0.6, 1.6, 0.6)), [0.55, 0.5, 0.75]),
        opaque(Mesh::sphere(24, 48), at(1.6, 1.1, -2.6) * Mat4::from_scale(Vec3::splat(1.1)), [0.85, 0.55, 0.2]),
        opaque(Mesh::sphere(32, 64), at(-2.1, 1.0, 0.0), [0.85, 0.2, 0.18]),
        opaque(
            Mesh::cube(),
            at(2.1, 0.75, 0.4) * Mat4::from_quat(Quat::from_rotation_y(0.6)) * Mat4::from_scale(Vec3::splat(0.75)),
            [0.2, 0.42, 0.85],
        ),
        opaque(
            Mesh::torus(1.0, 0.32, 64, 24),
            at(0.0, 1.05, 1.0) * Mat4::from_quat(Quat::from_rotation_x(1.1) * Quat::from_rotation_z(0.35)),
            [0.92, 0.75, 0.25],
        ),
    ];
    for i in 0..5 {
        let x = -2.4 + 1.2 * i as f32;
        objects.push(opaque(
            Mesh::sphere(12, 24),
            at(x, 0.35, 2.9) * Mat4::from_scale(Vec3::splat(0.35)),
            [0.25 + 0.15 * i as f32, 0.7, 0.45],
        ));
    }
    objects.push(Object {
        mesh: Mesh::sphere(24, 48),
        model: at(0.9, 1.25, 2.1) * Mat4::from_scale(Vec3::splat(0.9)),
        color: [0.35, 0.85, 0.95, 0.45],
        checker: None,
        translucent: true,
    });
    objects
}

fn build_with(
    device: &mut Device,
    width: u32,
    height: u32,
    samples: u32,
    objects: Vec<Object>,
    view_proj: Mat4,
) -> Result<Scene> {
    // The depth buffer only ever lives in the tile: transient, cleared, never stored. With
    // MSAA the colour samples are too, resolved into a single-sample image in the tile.
    let sky = [0.42, 0.55, 0.72, 1.0];
    let depth =
        device.create_image(ImageDesc::new(width, height, Format::D24UnormS8Uint).with_samples(samples).transient())?;
    let (color, attachment) = if samples > 1 {
        let msaa =
            device.create_image(ImageDesc::new(width, height, Format::Rgba8Unorm).with_samples(samples).transient())?;
        let resolve = device.create_image(ImageDesc::new(width, height, Format::Rgba8Unorm))?;
        (resolve, ColorAttachment::clear_resolve(msaa, sky, resolve))
    } else {
        let color = device.create_image(ImageDesc::new(width, height, Format::Rgba8Unorm))?;
        (color, ColorAttachment::clear_store(color, sky))
    };
    let mut pass = RenderPass::new(RenderPassDesc {
        color: vec![attachment],
        depth_stencil: Some(DepthStencilAttachment::clear_discard(depth, 1.0)),
        render_area: None,
    });
    let input = VertexInputState::interleaved(&[VertexFormat::Float32x3, VertexFormat::Float32x3]);
    let mut triangles = 0;
    for (i, object) in objects.into_iter().enumerate() {
        let vertices = device.create_buffer_from::<Vertex>(&object.mesh.vertices)?;
        let indices = device.create_buffer_from::<u32>(&object.mesh.indices)?;
        let mut desc = PipelineDesc::new(format!("object {i}"), input.clone());
        desc.varyings = LIT_VARYINGS.to_vec();
        desc.cull_mode = CullMode::Back;
        if object.translucent {
            desc.depth_stencil = DepthStencilState::LESS_NO_WRITE;
            desc.color_targets = vec![ColorTargetState::ALPHA_BLEND];
        } else {
            desc.depth_stencil = DepthStencilState::LESS_WRITE;
        }
        let pipeline = Pipeline::new(
            LitVertexShader::new(object.model, view_proj),
            LitFragmentShader { color: object.color, checker: object.checker },
            desc,
        )?;
        triangles += object.mesh.triangles() as u64;
        pass.draw(Draw::indexed(&pipeline, vertices, indices, IndexType::U32, 0, object.mesh.indices.len() as u32));
    }
    Ok(Scene { name: "built-in".into(), width, height, color, passes: vec![pass], triangles })
}
