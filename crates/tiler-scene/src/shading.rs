//! Shading of glTF materials, and the scene a loaded model becomes: one draw per primitive,
//! opaque first, blended last.
//!
//! Two shading modes, chosen per scene:
//!
//! - [`Shading::Scenes`] reproduces SCENES.md §4.2, the setup llvmpipe's reference images were
//!   rendered with: base colour × Lambert term, textures used as stored (no sRGB decode) with
//!   a `(a+b+c+d+2)>>2` box mip chain, always sampled trilinear with `REPEAT` whatever the
//!   file's sampler says, no culling (unless asked), BLEND primitives in traversal order, a
//!   linear RGBA8 colour attachment. `tiler bench` and the reference comparisons use it.
//! - [`Shading::Gltf`] follows the glTF specification where SCENES.md simplifies: base-colour
//!   textures are sRGB and decoded before filtering, their samplers (filters and wraps) are
//!   honoured, single-sided materials cull back faces, double-sided ones light back faces
//!   with the reversed normal, BLEND primitives are sorted back to front, missing normals are
//!   flat, and the colour attachment is sRGB (`Rgba8UnormSrgb`), so lighting is computed in
//!   linear light. The lighting model itself is the same base colour × Lambert term.
//!
//! A material becomes a pipeline in [`material_pipeline`]: one `match` on the mode, where a
//! future shading model (metallic-roughness, unlit) adds its arm and its fragment shader.

use glam::{Mat4, Vec4};
use tiler::api::format::srgb8_to_linear;
use tiler::simd::{dot3, normalize3};
use tiler::*;

use crate::Scene;
use crate::camera::{CameraChoice, Placement, place};
use crate::gltf::{AlphaMode, GltfVertex, Material, Model, TextureBinding};

/// How glTF materials are shaded (see the module notes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Shading {
    /// SCENES.md §4.2 exactly, as llvmpipe rendered the reference images.
    #[default]
    Scenes,
    /// The glTF specification's rules for textures, samplers, culling and blending.
    Gltf,
}

impl Shading {
    pub const fn name(self) -> &'static str {
        match self {
            Shading::Scenes => "scenes",
            Shading::Gltf => "gltf",
        }
    }
}

impl std::str::FromStr for Shading {
    type Err = String;
    fn from_str(s: &str) -> Result<Shading, String> {
        match s.to_ascii_lowercase().as_str() {
            "scenes" => Ok(Shading::Scenes),
            "gltf" => Ok(Shading::Gltf),
            _ => Err(format!("unknown shading '{s}' (expected scenes or gltf)")),
        }
    }
}

/// Which faces are culled.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CullPolicy {
    /// Both faces drawn (SCENES.md's default).
    None,
    /// Back faces of materials that are not `doubleSided` culled (glTF; SCENES.md `--cull gltf`).
    Gltf,
}

/// The clear colour of every SCENES.md frame, RGBA8 (64, 64, 80, 255).
pub const CLEAR_RGBA8: [u8; 4] = [64, 64, 80, 255];

/// The direction towards the light, `normalize(0.3, 1.0, 0.5)` as SCENES.md's shader computes
/// it: `(0.3, 1.0, 0.5) · inversesqrt(1.34)` in single precision.
pub fn light_direction() -> [f32; 3] {
    let inv = 1.0 / 1.34f32.sqrt();
    [0.3 * inv, 1.0 * inv, 0.5 * inv]
}

/// GL clip coordinates → tiler's (Vulkan): `(x, −y, (z + w)/2, w)`. The picture is the same:
/// y flips because Vulkan's framebuffer y grows downwards, and depth `z_w = (z/w + 1)/2` is
/// GL's window depth (SCENES.md §1).
#[inline]
pub fn gl_to_vulkan_clip(clip: Vec4) -> Vec4 {
    Vec4::new(clip.x, -clip.y, (clip.z + clip.w) * 0.5, clip.w)
}

/// SCENES.md's glTF vertex shader: world-space vertices (position, normal, uv) →
/// `uViewProj · (p, 1)` in single precision, normal and uv passed on.
pub struct WorldVertexShader {
    /// OpenGL clip conventions; converted to Vulkan's after the product.
    pub gl_view_proj: Mat4,
}

/// The varyings [`WorldVertexShader`] writes: normal (3), uv (2).
pub const WORLD_VARYINGS: [Interpolation; 5] = [Interpolation::Perspective; 5];

impl VertexShader for WorldVertexShader {
    fn shade(&self, input: &VertexInput, out: &mut VertexOutput) {
        let p = input.attributes[0];
        let clip = self.gl_view_proj * Vec4::new(p.x, p.y, p.z, 1.0);
        out.position = gl_to_vulkan_clip(clip);
        let n = input.attributes[1];
        let uv = input.attributes[2];
        out.varyings[..5].copy_from_slice(&[n.x, n.y, n.z, uv.x, uv.y]);
    }
}

/// Base colour × Lambert (SCENES.md §4.2):
/// `rgb = base.rgb · (0.2 + 0.8 · max(dot(normalize(n), L), 0))`, `base = factor · texture(uv)`;
/// MASK discards `base.a < cutoff`; alpha written is `base.a` for BLEND, else 1.
pub struct BaseColorLambert {
    pub factor: [f32; 4],
    pub texture: Option<TextureBinding>,
    pub alpha: AlphaMode,
    /// Back faces are lit with the reversed normal (glTF `doubleSided`, [`Shading::Gltf`]).
    pub two_sided_lighting: bool,
    pub light: [f32; 3],
}

impl FragmentShader for BaseColorLambert {
    fn properties(&self) -> ShaderProperties {
        ShaderProperties { discards: matches!(self.alpha, AlphaMode::Mask { .. }), ..ShaderProperties::default() }
    }

    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        let (base, n) = material_surface(frag, self.factor, self.texture.as_ref(), self.alpha, self.two_sided_lighting);
        let l = self.light.map(F32x8::splat);
        let lambert = F32x8::splat(0.2) + F32x8::splat(0.8) * dot3(n, l).max(F32x8::ZERO);
        let alpha = if self.alpha == AlphaMode::Blend { base[3] } else { F32x8::ONE };
        frag.set_color(0, [base[0] * lambert, base[1] * lambert, base[2] * lambert, alpha]);
    }
}

/// A glTF material's surface at the fragments of [`WorldVertexShader`]: the base colour
/// (`factor` × the texture at the uv varyings; MASK discards alpha below the cutoff) and the
/// unit normal, reversed on back faces when `two_sided`.
#[inline(always)]
pub fn material_surface(
    frag: &mut Fragments<'_>,
    factor: [f32; 4],
    texture: Option<&TextureBinding>,
    alpha: AlphaMode,
    two_sided: bool,
) -> ([F32x8; 4], [F32x8; 3]) {
    let mut base = factor.map(F32x8::splat);
    if let Some(binding) = texture {
        let uv = frag.smooth_n::<2>(3);
        let texel = frag.sample(&binding.texture, &binding.sampler, uv);
        for c in 0..4 {
            base[c] *= texel[c];
        }
    }
    if let AlphaMode::Mask { cutoff } = alpha {
        frag.discard(base[3].lt(F32x8::splat(cutoff)));
    }
    let mut n = normalize3(frag.smooth_n::<3>(0));
    if two_sided && !frag.front_facing() {
        n = n.map(|c| -c);
    }
    (base, n)
}

/// The pipeline that draws `material` in `shading` mode.
///
/// # Errors
/// Whatever [`Pipeline::new`] refuses (nothing, for these fixed layouts).
pub fn material_pipeline(
    label: String,
    material: &Material,
    shading: Shading,
    cull: CullPolicy,
    gl_view_proj: Mat4,
) -> Result<Pipeline> {
    let input =
        VertexInputState::interleaved(&[VertexFormat::Float32x3, VertexFormat::Float32x3, VertexFormat::Float32x2]);
    debug_assert_eq!(input.bindings[0].stride as usize, std::mem::size_of::<GltfVertex>());
    let mut desc = PipelineDesc::new(label, input);
    desc.varyings = WORLD_VARYINGS.to_vec();
    desc.front_face = FrontFace::CounterClockwise;
    desc.cull_mode = match cull {
        CullPolicy::Gltf if !material.double_sided => CullMode::Back,
        _ => CullMode::None,
    };
    if material.alpha_mode == AlphaMode::Blend {
        desc.depth_stencil = DepthStencilState::LESS_NO_WRITE;
        desc.color_targets = vec![ColorTargetState::ALPHA_BLEND];
    } else {
        desc.depth_stencil = DepthStencilState::LESS_WRITE;
    }
    let vertex = WorldVertexShader { gl_view_proj };
    match shading {
        Shading::Scenes | Shading::Gltf => Pipeline::new(
            vertex,
            BaseColorLambert {
                factor: material.base_color_factor,
                texture: material.base_color_texture.clone(),
                alpha: material.alpha_mode,
                two_sided_lighting: shading == Shading::Gltf && material.double_sided,
                light: light_direction(),
            },
            desc,
        ),
    }
}

/// How a loaded model is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelSceneOptions {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel of the colour and depth attachments.
    pub samples: u32,
    pub camera: CameraChoice,
    /// `None`: the shading mode's default ([`CullPolicy::None`] for scenes, [`CullPolicy::Gltf`]
    /// for glTF).
    pub cull: Option<CullPolicy>,
}

impl ModelSceneOptions {
    /// SCENES.md's camera and the shading mode's culling at `width × height`, one sample.
    pub fn new(width: u32, height: u32) -> ModelSceneOptions {
        ModelSceneOptions { width, height, samples: 1, camera: CameraChoice::Auto, cull: None }
    }
}

/// Why a model could not become a scene.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("{0}")]
    Camera(String),
    #[error(transparent)]
    Device(#[from] tiler::Error),
}

/// Records the frame of SCENES.md §4.2 for `model` on `device`: clear to (64, 64, 80, 255)
/// and depth 1, every opaque and MASK primitive in traversal order, then every BLEND primitive
/// (traversal order for [`Shading::Scenes`], back to front for [`Shading::Gltf`]), shaded in
/// the mode the model was loaded for. Depth is a 24-bit attachment that is never stored.
///
/// # Errors
/// A camera that cannot be placed, or a size the device refuses.
pub fn build_model_scene(
    device: &mut Device,
    model: &Model,
    options: &ModelSceneOptions,
) -> Result<(Scene, Placement), SceneError> {
    let ModelSceneOptions { width, height, samples, camera, cull } = *options;
    let shading = model.shading;
    let placement = place(model, camera, width as f64 / height as f64).map_err(SceneError::Camera)?;
    let cull = cull.unwrap_or(match shading {
        Shading::Scenes => CullPolicy::None,
        Shading::Gltf => CullPolicy::Gltf,
    });
    let (format, clear) = match shading {
        Shading::Scenes => (Format::Rgba8Unorm, CLEAR_RGBA8.map(|c| c as f32 / 255.0)),
        Shading::Gltf => {
            let [r, g, b, _] = CLEAR_RGBA8;
            (Format::Rgba8UnormSrgb, [srgb8_to_linear(r), srgb8_to_linear(g), srgb8_to_linear(b), 1.0])
        }
    };
    let (desc, color) = crate::frame_targets(device, width, height, format, samples, clear)?;
    let mut pass = RenderPass::new(desc);

    let is_blend = |p: &&crate::gltf::DrawPrimitive| model.materials[p.material].alpha_mode == AlphaMode::Blend;
    let mut order: Vec<&crate::gltf::DrawPrimitive> = model.primitives.iter().filter(|p| !is_blend(p)).collect();
    let mut blended: Vec<&crate::gltf::DrawPrimitive> = model.primitives.iter().filter(is_blend).collect();
    if shading == Shading::Gltf {
        // Back to front by the distance from the eye to the centre of each primitive's bounds.
        let eye = placement.eye.as_vec3();
        let distance = |p: &crate::gltf::DrawPrimitive| {
            let centre = (glam::Vec3::from(p.min) + glam::Vec3::from(p.max)) * 0.5;
            centre.distance(eye)
        };
        blended.sort_by(|a, b| distance(b).total_cmp(&distance(a)));
    }
    order.extend(blended);

    let mut triangles = 0;
    for primitive in order {
        let material = &model.materials[primitive.material];
        let vertices = device.create_buffer_from::<GltfVertex>(&primitive.vertices)?;
        let indices = device.create_buffer_from::<u32>(&primitive.indices)?;
        let pipeline = material_pipeline(primitive.label.clone(), material, shading, cull, placement.gl_view_proj)?;
        triangles += primitive.triangles() as u64;
        pass.draw(Draw::indexed(&pipeline, vertices, indices, IndexType::U32, 0, primitive.indices.len() as u32));
    }
    let scene = Scene { name: model.file_name(), width, height, color, passes: vec![pass], triangles };
    Ok((scene, placement))
}
