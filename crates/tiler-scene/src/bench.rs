//! The benchmark scenes of SCENES.md §4 — `clear`, `gltf` (DamagedHelmet, Atrium),
//! `overdraw`, `tris` — built from the same formulas as llvmpipe's runs, so that the work is
//! identical: the vertices are bit for bit those SCENES.md's CHECKSUMS describe.
//!
//! Every scene draws into an RGBA8 (linear) colour attachment cleared to (64, 64, 80, 255) and
//! a 24-bit depth attachment cleared to 1 and never stored, with depth test `LESS`. GL clip
//! coordinates become tiler's with `(x, −y, (z + w)/2, w)` (see `shading::gl_to_vulkan_clip`).

use std::path::{Path, PathBuf};

use tiler::*;

use crate::Scene;
use crate::gltf::{LoadError, load};
use crate::shading::{CLEAR_RGBA8, ModelSceneOptions, SceneError, Shading, build_model_scene};

/// PCG-RXS-M-XS 32-bit hash (Jarzynski & Olano, "Hash Functions for GPU Rendering", JCGT 2020),
/// SCENES.md §2; all arithmetic modulo 2^32.
#[inline]
pub fn pcg_hash(x: u32) -> u32 {
    let state = x.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// Value `k` (0..8) of item `i`: `pcg_hash(seed + 8·i + k)`, wrapping.
#[inline]
pub fn rand(seed: u32, i: u32, k: u32) -> u32 {
    pcg_hash(seed.wrapping_add(i.wrapping_mul(8)).wrapping_add(k))
}

/// `(h >> 8) · 2^−24`: uniform in `[0, 1)`, exact in f32 and f64.
#[inline]
pub fn u01(h: u32) -> f64 {
    (h >> 8) as f64 * (1.0 / 16_777_216.0)
}

/// The order of the overdraw scene's layers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LayerOrder {
    /// Farthest first: every layer passes the depth test.
    BackToFront,
    /// Nearest first: early-Z rejects all but the first.
    FrontToBack,
}

/// One benchmark scene.
#[derive(Clone, Debug, PartialEq)]
pub enum BenchScene {
    /// No draw: the clear alone (§4.1).
    Clear,
    /// A glTF model with SCENES.md's shading and camera (§4.2).
    Gltf { path: PathBuf },
    /// `layers` full-screen quads (§4.3).
    Overdraw { layers: u32, order: LayerOrder },
    /// `count` small flat triangles from the PCG generator (§4.4).
    Tris { count: u32, seed: u32 },
}

/// A named benchmark scene, as `tiler bench` lists it.
#[derive(Clone, Debug, PartialEq)]
pub struct BenchCase {
    pub name: String,
    pub scene: BenchScene,
}

/// The scenes `tiler bench` runs, with the names of the llvmpipe runs (`peers/RESULTS.md`):
/// clear, helmet (DamagedHelmet), atrium, overdraw (K = 32, back to front), overdraw_f2b, tris
/// (M = 1,000,000, seed 1). glTF models are read from `assets`.
pub fn standard_cases(assets: &Path) -> Vec<BenchCase> {
    let case = |name: &str, scene| BenchCase { name: name.into(), scene };
    vec![
        case("clear", BenchScene::Clear),
        case("helmet", BenchScene::Gltf { path: assets.join("DamagedHelmet/DamagedHelmet.gltf") }),
        case("atrium", BenchScene::Gltf { path: assets.join("Atrium/Atrium.gltf") }),
        case("overdraw", BenchScene::Overdraw { layers: 32, order: LayerOrder::BackToFront }),
        case("overdraw_f2b", BenchScene::Overdraw { layers: 32, order: LayerOrder::FrontToBack }),
        case("tris", BenchScene::Tris { count: 1_000_000, seed: 1 }),
    ]
}

/// Why a benchmark scene could not be built.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    #[error(transparent)]
    Load(#[from] LoadError),
    #[error(transparent)]
    Scene(#[from] SceneError),
    #[error(transparent)]
    Device(#[from] tiler::Error),
}

/// What one frame of a scene is, for throughput figures.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BenchWork {
    pub triangles: u64,
    /// Fragments the scene shades per frame by construction (overdraw: `K · W · H`).
    pub fragments: Option<u64>,
}

/// Builds `scene` on `device` at `width × height` with `samples` per pixel.
///
/// # Errors
/// A glTF file that does not load, or a size or sample count the device refuses.
pub fn build(
    device: &mut Device,
    scene: &BenchScene,
    width: u32,
    height: u32,
    samples: u32,
) -> Result<(Scene, BenchWork), BenchError> {
    let pixels = width as u64 * height as u64;
    match scene {
        BenchScene::Clear => {
            let (pass, color) = frame_pass(device, width, height, samples)?;
            let name = "clear".to_string();
            Ok((Scene { name, width, height, color, passes: vec![pass], triangles: 0 }, BenchWork::default()))
        }
        BenchScene::Gltf { path } => {
            let model = load(path, Shading::Scenes)?;
            let options = ModelSceneOptions { samples, ..ModelSceneOptions::new(width, height) };
            let (scene, _) = build_model_scene(device, &model, &options)?;
            let triangles = scene.triangles;
            Ok((scene, BenchWork { triangles, fragments: None }))
        }
        BenchScene::Overdraw { layers, order } => {
            let (mut pass, color) = frame_pass(device, width, height, samples)?;
            let vertices = overdraw_vertices(*layers, *order);
            let buffer = device.create_buffer_from(&vertices)?;
            let mut desc = PipelineDesc::new("overdraw", VertexInputState::interleaved(&[VertexFormat::Float32x4]));
            desc.varyings = vec![Interpolation::Flat];
            desc.depth_stencil = DepthStencilState::LESS_WRITE;
            let shader = OverdrawShader::new(width, height);
            let pipeline = Pipeline::new(LayerVertexShader, shader, desc)?;
            pass.draw(Draw::new(&pipeline, buffer, 0, vertices.len() as u32));
            let triangles = 2 * *layers as u64;
            let scene = Scene { name: "overdraw".into(), width, height, color, passes: vec![pass], triangles };
            Ok((scene, BenchWork { triangles, fragments: Some(*layers as u64 * pixels) }))
        }
        BenchScene::Tris { count, seed } => {
            let (mut pass, color) = frame_pass(device, width, height, samples)?;
            let vertices = tris_vertices(*count, *seed);
            let buffer = device.create_buffer_from(&vertices)?;
            let input = VertexInputState::interleaved(&[VertexFormat::Float32x3, VertexFormat::Unorm8x4]);
            let mut desc = PipelineDesc::new("tris", input);
            desc.varyings = vec![Interpolation::Flat; 4];
            desc.depth_stencil = DepthStencilState::LESS_WRITE;
            let pipeline = Pipeline::new(ColorVertexShader, FlatColorShader, desc)?;
            pass.draw(Draw::new(&pipeline, buffer, 0, vertices.len() as u32));
            let triangles = *count as u64;
            let scene = Scene { name: "tris".into(), width, height, color, passes: vec![pass], triangles };
            Ok((scene, BenchWork { triangles, fragments: None }))
        }
    }
}

/// The frame of SCENES.md §1: colour cleared to (64, 64, 80, 255) and stored (with MSAA:
/// resolved, in the tile), 24-bit depth cleared to 1 and thrown away.
fn frame_pass(device: &mut Device, width: u32, height: u32, samples: u32) -> Result<(RenderPass, ImageId)> {
    let clear = CLEAR_RGBA8.map(|c| c as f32 / 255.0);
    let (desc, color) = crate::frame_targets(device, width, height, Format::Rgba8Unorm, samples, clear)?;
    Ok((RenderPass::new(desc), color))
}

/// The overdraw scene's vertices `(x, y, z, t)`: layer `j` (0 farthest) at
/// `z_j = 1 − 2(j + 1)/(K + 1)`, `t_j = (j + ½)/K`, both in double precision then rounded;
/// two triangles per layer, in draw order (SCENES.md §4.3).
pub fn overdraw_vertices(layers: u32, order: LayerOrder) -> Vec<[f32; 4]> {
    const CORNERS: [(f32, f32); 6] = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let k = layers as f64;
    let js: Vec<u32> = match order {
        LayerOrder::BackToFront => (0..layers).collect(),
        LayerOrder::FrontToBack => (0..layers).rev().collect(),
    };
    js.into_iter()
        .flat_map(|j| {
            let z = (1.0 - 2.0 * (j as f64 + 1.0) / (k + 1.0)) as f32;
            let t = ((j as f64 + 0.5) / k) as f32;
            CORNERS.map(|(x, y)| [x, y, z, t])
        })
        .collect()
}

/// One vertex of the tris scene: NDC position and an RGBA8 colour (16 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TrisVertex {
    pub position: [f32; 3],
    pub color: [u8; 4],
}

/// The tris scene's `3 · count` vertices (SCENES.md §4.4), computed in double precision in the
/// stated order (Rust never fuses a multiply and an add), rounded to f32 once.
pub fn tris_vertices(count: u32, seed: u32) -> Vec<TrisVertex> {
    let q = 3f64.sqrt() * 0.5;
    let mut vertices = Vec::with_capacity(3 * count as usize);
    for i in 0..count {
        let h = |k| rand(seed, i, k);
        let cx = -1.0 + 2.0 * u01(h(0));
        let cy = -1.0 + 2.0 * u01(h(1));
        let z = -1.0 + 2.0 * u01(h(2));
        let r = 1.5 + 1.5 * u01(h(3));
        let t = -1.0 + 2.0 * u01(h(4));
        let d = 1.0 + t * t;
        let c0 = (1.0 - t * t) / d;
        let s0 = (2.0 * t) / d;
        let c1 = c0 * -0.5 - s0 * q;
        let s1 = s0 * -0.5 + c0 * q;
        let c2 = c0 * -0.5 + s0 * q;
        let s2 = s0 * -0.5 - c0 * q;
        let color = h(5).to_le_bytes();
        let color = [color[0], color[1], color[2], 255];
        for (c, s) in [(c0, s0), (c1, s1), (c2, s2)] {
            let x = cx + (r * c) / 960.0;
            let y = cy + (r * s) / 540.0;
            vertices.push(TrisVertex { position: [x as f32, y as f32, z as f32], color });
        }
    }
    vertices
}

/// GL NDC (`w = 1`) → tiler's clip space: `(x, −y, (z + 1)/2, 1)`.
#[inline]
fn ndc_to_clip(p: glam::Vec4) -> glam::Vec4 {
    glam::Vec4::new(p.x, -p.y, (p.z + 1.0) * 0.5, 1.0)
}

/// The overdraw scene's vertex shader: `(x, y, z, t)`, position in GL NDC, `t` a flat varying.
pub struct LayerVertexShader;

impl VertexShader for LayerVertexShader {
    fn shade(&self, input: &VertexInput, out: &mut VertexOutput) {
        let p = input.attributes[0];
        out.position = ndc_to_clip(p);
        out.varyings[0] = p.w;
    }
}

/// The tris scene's vertex shader: position in GL NDC, the colour as four flat varyings.
pub struct ColorVertexShader;

impl VertexShader for ColorVertexShader {
    fn shade(&self, input: &VertexInput, out: &mut VertexOutput) {
        out.position = ndc_to_clip(input.attributes[0]);
        out.varyings[..4].copy_from_slice(&input.attributes[1].to_array());
    }
}

/// The tris scene's fragment shader: the flat colour as it is.
pub struct FlatColorShader;

impl FragmentShader for FlatColorShader {
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        let c = [0, 1, 2, 3].map(|i| F32x8::splat(frag.flat(i)));
        frag.set_color(0, c);
    }
}

/// The overdraw scene's fragment shader (SCENES.md §4.3): 64 iterations of a 4-wide
/// multiply-add on `(p.x, p.y, t, 1)`, `p = gl_FragCoord.xy · (1/W, 1/H)` with GL's window y
/// (counted up from the bottom: `H − y` of tiler's pixel centre, exact).
pub struct OverdrawShader {
    inverse_size: [f32; 2],
    height: f32,
}

impl OverdrawShader {
    pub fn new(width: u32, height: u32) -> OverdrawShader {
        OverdrawShader {
            inverse_size: [(1.0 / width as f64) as f32, (1.0 / height as f64) as f32],
            height: height as f32,
        }
    }
}

impl FragmentShader for OverdrawShader {
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        const A: [f32; 4] = [0.97, 0.98, 0.99, 0.96];
        const B: [f32; 4] = [0.03, 0.02, 0.01, 0.04];
        let (x, y) = frag.position();
        let gl_y = F32x8::splat(self.height) - y;
        let (mut vx, mut vy, mut vz, mut vw) =
            (x * self.inverse_size[0], gl_y * self.inverse_size[1], F32x8::splat(frag.flat(0)), F32x8::ONE);
        // v = v · A + v.yzwx · B, component by component (written out: the compiler keeps each
        // component in its own registers).
        for _ in 0..64 {
            (vx, vy, vz, vw) =
                (vx * A[0] + vy * B[0], vy * A[1] + vz * B[1], vz * A[2] + vw * B[2], vw * A[3] + vx * B[3]);
        }
        frag.set_color(0, [vx, vy, vz, F32x8::ONE]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pcg_hash_test_vectors() {
        assert_eq!(pcg_hash(0), 0x07bb2fe2);
        assert_eq!(pcg_hash(1), 0xa8beea3c);
        assert_eq!(pcg_hash(2), 0x7a7ecc88);
        assert_eq!(pcg_hash(3), 0x7f0ef6bc);
    }

    #[test]
    fn tris_test_vectors() {
        let v = tris_vertices(2, 1);
        let bits = |i: usize| v[i].position.map(f32::to_bits);
        assert_eq!(bits(0), [0x3ea3e8d0, 0xbd2ffb81, 0xbbf10a00]);
        assert_eq!(bits(1), [0x3ea28276, 0xbd24d2ff, 0xbbf10a00]);
        assert_eq!(bits(2), [0x3ea287b2, 0xbd3ba500, 0xbbf10a00]);
        assert_eq!(v[0].color, [164, 177, 80, 255]);
        assert_eq!(bits(3), [0xbec955ea, 0xbe037daa, 0xbee8ddbc]);
        assert_eq!(bits(4), [0xbec8ed08, 0xbdfaa0a9, 0xbee8ddbc]);
        assert_eq!(bits(5), [0xbecaa2a3, 0xbdfe4814, 0xbee8ddbc]);
        assert_eq!(v[3].color, [188, 213, 54, 255]);
    }

    #[test]
    fn overdraw_layers() {
        let v = overdraw_vertices(32, LayerOrder::BackToFront);
        assert_eq!(v.len(), 6 * 32);
        assert_eq!(v[0][2], (1.0 - 2.0 / 33.0) as f32);
        assert_eq!(v[0][3], (0.5 / 32.0) as f32);
        let f2b = overdraw_vertices(32, LayerOrder::FrontToBack);
        assert_eq!(f2b[0], v[v.len() - 6]);
    }
}
