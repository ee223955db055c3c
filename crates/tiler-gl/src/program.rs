//! The built-in program library: what a GL program is for tiler's Rust shaders.
//!
//! tiler's own shaders are Rust types. A trace names one of these programs ([`ProgramKind`])
//! and sets its uniforms by name — or brings GLSL, which `tiler-glsl` compiles (see
//! `context::glsl`). Uniform values are snapshotted into each draw, as a driver snapshots state
//! into its frame data. Adding a built-in means a `ProgramKind` variant, its [`ProgramInfo`]
//! and its shaders here.
//!
//! | program | attributes | uniforms | varyings |
//! |---|---|---|---|
//! | `solid` | 0 position | `mvp` mat4, `color` vec4 | — |
//! | `vertex_color` | 0 position, 1 color | `mvp`, `alpha_cutoff` float | colour (4) |
//! | `lambert` | 0 position, 1 normal | `mvp`, `model` mat4, `color`, `light_dir` vec3 | normal (3) |
//! | `textured` | 0 position, 1 texcoord | `mvp`, `color`, `alpha_cutoff`, `sampler` int | texcoord (2) |
//! | `composite` | 0 position | `mvp`, `color` vec4 | — (reads input attachment 0) |
//!
//! Every vertex shader computes GL's `gl_Position = mvp · position` and converts it to
//! tiler's clip space (Vulkan's): `(x, −y, (z + w) / 2, w)`. The y negation maps GL's window
//! (y up) onto tiler's framebuffer rows (row 0 at the top), and `(z + w) / 2` maps GL's depth
//! range `[−w, w]` onto `[0, w]`, so window depth is GL's `(z_ndc + 1) / 2` within the depth
//! range. A `alpha_cutoff` above 0 makes the fragment shader discard (GLSL `discard`), which
//! tells tiler the shader may discard, so depth is tested after shading.
//!
//! # Texture sampling
//!
//! `textured` samples RGBA8 textures (linear or sRGB) with the core's sampler
//! ([`tiler::Texture`]): nearest or bilinear, on level 0 or, after `generate_mipmap` and with a
//! `*_mipmap_*` filter, on the core's mip chain (`MipChain::Linear`, as Mesa builds it), wrapped as
//! the texture says, through the core's texture-cache model, so its reads are `texture_fetch`
//! in the pass's ledger. The texture is the image's contents when its render pass is submitted
//! (render to texture included). RGB565 textures, `encoded_tex_image` ones (ETC2, ASTC, 4444,
//! 5551) and float ones whose values all lie in [0, 1] go through the core too, decoded to 8
//! bits and counted by what their format stores. Formats the core sampler does not take (floats
//! beyond [0, 1], depth — a shadow map) are sampled by [`TextureSnapshot`], the same filtering
//! on decoded texels, whose reads are not counted. Blits and copies use [`TextureSnapshot`] too (it averages the samples
//! of a multisampled source, a resolve) and count their source reads by formula (see
//! `context`).

use std::sync::Arc;

use glam::{Mat3, Mat4, Vec3, Vec4};
use tiler::{
    F32x8, FragmentShader, Fragments, Interpolation, Pipeline, PipelineDesc, ShaderProperties, VertexInput,
    VertexOutput, VertexShader,
};

use crate::call::{Filter, ProgramKind, UniformValue, Wrap};

/// What a built-in program reads.
pub struct ProgramInfo {
    /// `(attribute index, name)`.
    pub attributes: &'static [(u32, &'static str)],
    /// `(name, type name)`.
    pub uniforms: &'static [(&'static str, &'static str)],
    /// Whether it samples the texture on unit `sampler`.
    pub samples_texture: bool,
}

impl ProgramKind {
    pub const ALL: [ProgramKind; 5] = [
        ProgramKind::Solid,
        ProgramKind::VertexColor,
        ProgramKind::Lambert,
        ProgramKind::Textured,
        ProgramKind::Composite,
    ];

    pub fn name(self) -> &'static str {
        match self {
            ProgramKind::Solid => "solid",
            ProgramKind::VertexColor => "vertex_color",
            ProgramKind::Lambert => "lambert",
            ProgramKind::Textured => "textured",
            ProgramKind::Composite => "composite",
        }
    }

    pub fn info(self) -> ProgramInfo {
        match self {
            ProgramKind::Solid => ProgramInfo {
                attributes: &[(0, "position")],
                uniforms: &[("mvp", "mat4"), ("color", "vec4")],
                samples_texture: false,
            },
            ProgramKind::VertexColor => ProgramInfo {
                attributes: &[(0, "position"), (1, "color")],
                uniforms: &[("mvp", "mat4"), ("alpha_cutoff", "float")],
                samples_texture: false,
            },
            ProgramKind::Lambert => ProgramInfo {
                attributes: &[(0, "position"), (1, "normal")],
                uniforms: &[("mvp", "mat4"), ("model", "mat4"), ("color", "vec4"), ("light_dir", "vec3")],
                samples_texture: false,
            },
            ProgramKind::Textured => ProgramInfo {
                attributes: &[(0, "position"), (1, "texcoord")],
                uniforms: &[("mvp", "mat4"), ("color", "vec4"), ("alpha_cutoff", "float"), ("sampler", "int")],
                samples_texture: true,
            },
            ProgramKind::Composite => ProgramInfo {
                attributes: &[(0, "position")],
                uniforms: &[("mvp", "mat4"), ("color", "vec4")],
                samples_texture: false,
            },
        }
    }

    fn varyings(self) -> usize {
        match self {
            ProgramKind::Solid => 0,
            ProgramKind::VertexColor => 4,
            ProgramKind::Lambert => 3,
            ProgramKind::Textured => 2,
            ProgramKind::Composite => 0,
        }
    }

    /// How many input attachments the program reads (the current subpass must have them).
    pub fn inputs(self) -> usize {
        match self {
            ProgramKind::Composite => 1,
            _ => 0,
        }
    }
}

/// The uniform values of a program object; each program reads the ones it declares.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Uniforms {
    pub mvp: Mat4,
    pub model: Mat4,
    pub color: [f32; 4],
    pub light_dir: [f32; 3],
    pub alpha_cutoff: f32,
    pub sampler: i32,
}

impl Default for Uniforms {
    fn default() -> Uniforms {
        Uniforms {
            mvp: Mat4::IDENTITY,
            model: Mat4::IDENTITY,
            color: [1.0; 4],
            light_dir: [0.0, 0.0, 1.0],
            alpha_cutoff: 0.0,
            sampler: 0,
        }
    }
}

impl Uniforms {
    /// Sets uniform `name` of a `kind` program.
    ///
    /// # Errors
    /// A name the program does not declare, a value of the wrong type, or a non-finite value.
    pub fn set(&mut self, kind: ProgramKind, name: &str, value: UniformValue) -> Result<(), String> {
        let info = kind.info();
        let Some((_, expected)) = info.uniforms.iter().find(|(n, _)| *n == name) else {
            let names: Vec<_> = info.uniforms.iter().map(|(n, _)| *n).collect();
            return Err(format!("program '{}' has no uniform '{name}' (it has: {})", kind.name(), names.join(", ")));
        };
        if value.type_name() != *expected {
            return Err(format!("uniform '{name}' is a {expected}, not a {}", value.type_name()));
        }
        if !value.is_finite() {
            return Err(format!("uniform '{name}' has a non-finite value {value:?}"));
        }
        match (name, value) {
            ("mvp", UniformValue::Mat4(m)) => self.mvp = Mat4::from_cols_array(&m),
            ("model", UniformValue::Mat4(m)) => self.model = Mat4::from_cols_array(&m),
            ("color", UniformValue::Vec4(c)) => self.color = c,
            ("light_dir", UniformValue::Vec3(d)) => self.light_dir = d,
            ("alpha_cutoff", UniformValue::Float(a)) => self.alpha_cutoff = a,
            ("sampler", UniformValue::Int(u)) => self.sampler = u,
            _ => unreachable!("uniform table and setter disagree on '{name}'"),
        }
        Ok(())
    }
}

/// GL clip space → tiler clip space (see the module docs).
#[inline]
fn gl_to_tiler_clip(p: Vec4) -> Vec4 {
    Vec4::new(p.x, -p.y, (p.z + p.w) * 0.5, p.w)
}

/// The vertex shader of every built-in program.
struct ProgramVertexShader {
    kind: ProgramKind,
    mvp: Mat4,
    normal_matrix: Mat3,
}

impl VertexShader for ProgramVertexShader {
    fn shade(&self, input: &VertexInput, out: &mut VertexOutput) {
        out.position = gl_to_tiler_clip(self.mvp * input.attributes[0]);
        let a = input.attributes[1];
        match self.kind {
            ProgramKind::Solid | ProgramKind::Composite => {}
            ProgramKind::VertexColor => out.varyings[..4].copy_from_slice(&a.to_array()),
            ProgramKind::Lambert => {
                let n = self.normal_matrix * a.truncate();
                out.varyings[..3].copy_from_slice(&n.to_array());
            }
            ProgramKind::Textured => out.varyings[..2].copy_from_slice(&[a.x, a.y]),
        }
    }
}

struct SolidShader {
    color: [f32; 4],
}

impl FragmentShader for SolidShader {
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        frag.set_color(0, self.color.map(F32x8::splat));
    }
}

/// Input attachment 0 at the fragment's pixel (and sample), times a colour: what a lighting
/// or composite subpass reads from the G-buffer written by an earlier subpass, in the tile.
struct CompositeShader {
    color: [f32; 4],
}

impl FragmentShader for CompositeShader {
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        let input = frag.input(0);
        frag.set_color(0, std::array::from_fn(|c| input[c] * self.color[c]));
    }
}

struct VertexColorShader {
    alpha_cutoff: f32,
}

impl FragmentShader for VertexColorShader {
    fn properties(&self) -> ShaderProperties {
        ShaderProperties { discards: self.alpha_cutoff > 0.0, ..ShaderProperties::default() }
    }

    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        let c = frag.smooth_n::<4>(0);
        if self.alpha_cutoff > 0.0 {
            frag.discard(c[3].lt(F32x8::splat(self.alpha_cutoff)));
        }
        frag.set_color(0, c);
    }
}

struct LambertShader {
    color: [f32; 4],
    light: [f32; 3],
}

impl FragmentShader for LambertShader {
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        let n = tiler::simd::normalize3(frag.smooth_n::<3>(0));
        let diffuse = tiler::simd::dot3(n, self.light.map(F32x8::splat)).max(F32x8::ZERO);
        let lit = F32x8::splat(0.2) + diffuse * 0.8;
        let c = self.color;
        frag.set_color(0, [lit * c[0], lit * c[1], lit * c[2], F32x8::splat(c[3])]);
    }
}

/// A texture as the interim sampler reads it, row 0 at the top as tiler stores images (GL's
/// texture coordinate t = 0 is the bottom row). Texels are decoded when read, so a snapshot
/// costs no more memory than the image.
#[derive(Debug)]
pub struct TextureSnapshot {
    pub width: u32,
    pub height: u32,
    texels: Texels,
    /// Alpha reads as 1 (see [`TextureSnapshot::with_alpha_one`]).
    alpha_one: bool,
}

#[derive(Clone, Debug)]
enum Texels {
    /// An image's bytes; a multisampled one reads as its samples resolved, as the core
    /// resolves them (`Format::resolve_samples`).
    Color {
        format: tiler::Format,
        samples: u32,
        data: Vec<u8>,
    },
    /// Depths, read as `(z, z, z, 1)`; `fixed_point`: a UNORM depth format (its compares
    /// clamp the reference to `[0, 1]`).
    Depth {
        depths: Vec<f32>,
        fixed_point: bool,
    },
    Constant([f32; 4]),
}

/// Filtering and wrapping of one sampler binding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SamplerState {
    /// Minification; a `*_mipmap_*` filter reads the mip chain.
    pub min_filter: Filter,
    /// Magnification: `nearest` or `linear`.
    pub mag_filter: Filter,
    pub wrap_s: Wrap,
    pub wrap_t: Wrap,
    /// Depth comparison (`GL_TEXTURE_COMPARE_MODE` / `FUNC`): what a shadow sampler reading a
    /// depth texture compares with ([`TextureSnapshot::sample_compare`]).
    pub compare: Option<tiler::CompareOp>,
}

impl SamplerState {
    /// One filter (magnifying with its first word) and one wrap for both coordinates.
    pub const fn new(filter: Filter, wrap: Wrap) -> SamplerState {
        SamplerState { min_filter: filter, mag_filter: filter.base(), wrap_s: wrap, wrap_t: wrap, compare: None }
    }

    /// Whether GL's rules make a texture sampled this way incomplete (it then reads as
    /// (0, 0, 0, 1), GL ES 2.0 §3.8.2): a mipmap minification filter on a texture without levels.
    ///
    /// Non-power-of-two textures that repeat or have a mipmap filter are complete here, as
    /// under `OES_texture_npot`, which llvmpipe (the reference) and most GLES 2 drivers expose.
    pub fn incomplete(&self, mipmaps: bool) -> bool {
        self.min_filter.mipmap().is_some() && !mipmaps
    }
}

impl TextureSnapshot {
    /// A colour image's bytes (sample planes one after another, as the device stores them).
    pub fn color(width: u32, height: u32, format: tiler::Format, samples: u32, data: Vec<u8>) -> TextureSnapshot {
        debug_assert_eq!(data.len(), width as usize * height as usize * format.bytes_per_sample() * samples as usize);
        TextureSnapshot { width, height, texels: Texels::Color { format, samples, data }, alpha_one: false }
    }

    /// A depth image's depths, rows top to bottom; `fixed_point`: its format is UNORM (D16,
    /// D24), not float.
    pub fn depth(width: u32, height: u32, depths: Vec<f32>, fixed_point: bool) -> TextureSnapshot {
        TextureSnapshot { width, height, texels: Texels::Depth { depths, fixed_point }, alpha_one: false }
    }

    pub(crate) fn is_depth(&self) -> bool {
        matches!(self.texels, Texels::Depth { .. })
    }

    /// A depth snapshot's depths, to be filled again ([`TextureSnapshot::depth`]).
    pub(crate) fn into_depths(self) -> Option<Vec<f32>> {
        match self.texels {
            Texels::Depth { depths, .. } => Some(depths),
            _ => None,
        }
    }

    /// One texel of one value: what an unbound unit reads.
    pub fn constant(rgba: [f32; 4]) -> TextureSnapshot {
        TextureSnapshot { width: 1, height: 1, texels: Texels::Constant(rgba), alpha_one: false }
    }

    /// The same texels with alpha read as 1: what a copy into a texture without alpha
    /// (`glCopyTexImage2D` with `GL_RGB`) stores.
    pub fn with_alpha_one(&self) -> TextureSnapshot {
        TextureSnapshot { width: self.width, height: self.height, texels: self.texels.clone(), alpha_one: true }
    }

    /// The index of texel `(x, y_from_bottom)` wrapped as `state` says, in rows top first.
    #[inline]
    fn texel_index(&self, x: i64, y_from_bottom: i64, state: SamplerState) -> usize {
        let x = wrap_coord(x, self.width as i64, state.wrap_s);
        let y = wrap_coord(y_from_bottom, self.height as i64, state.wrap_t);
        let row = self.height as i64 - 1 - y;
        (row * self.width as i64 + x) as usize
    }

    #[inline]
    fn texel(&self, x: i64, y_from_bottom: i64, state: SamplerState) -> [f32; 4] {
        let index = self.texel_index(x, y_from_bottom, state);
        match &self.texels {
            Texels::Color { format, samples, data } => {
                let bpp = format.bytes_per_sample();
                let plane = self.width as usize * self.height as usize * bpp;
                let start = index * bpp;
                if *samples == 1 {
                    return format.decode_color(&data[start..start + bpp]);
                }
                // Resolved as the tile resolves (nearest byte of the mean for UNORM8), so a
                // blit's resolve gives the picture a resolve in the tile gives.
                let mut resolved = [0u8; 16];
                let pixel = (0..*samples as usize).map(|s| &data[s * plane + start..s * plane + start + bpp]);
                format.resolve_samples(pixel, &mut resolved);
                format.decode_color(&resolved[..bpp])
            }
            Texels::Depth { depths, .. } => {
                let z = depths[index];
                [z, z, z, 1.0]
            }
            Texels::Constant(v) => *v,
        }
    }

    /// `texelFetch` of level 0 (a snapshot has one): texel `(x, y)`, `y` from GL's first row
    /// (the bottom), `None` out of range (a constant snapshot, an incomplete texture, has no
    /// texels: `None` too).
    pub fn fetch(&self, x: i32, y: i32, level: i32) -> Option<[f32; 4]> {
        if level != 0 || matches!(self.texels, Texels::Constant(_)) {
            return None;
        }
        if !(0..self.width as i64).contains(&(x as i64)) || !(0..self.height as i64).contains(&(y as i64)) {
            return None;
        }
        let mut rgba = self.texel(x as i64, y as i64, SamplerState::new(Filter::Nearest, Wrap::ClampToEdge));
        if self.alpha_one {
            rgba[3] = 1.0;
        }
        Some(rgba)
    }

    /// Samples at GL texture coordinates `(s, t)`: nearest takes the texel containing the
    /// point; linear blends the four around it, texel centres at half-integers. A snapshot has
    /// one level and no derivatives, so it filters as GL magnifies (a level of detail of 0,
    /// what a render target read back at its own size has).
    #[inline]
    pub fn sample(&self, s: f32, t: f32, state: SamplerState) -> [f32; 4] {
        let mut rgba = self.sample_texels(s, t, state);
        if self.alpha_one {
            rgba[3] = 1.0;
        }
        rgba
    }

    /// [`TextureSnapshot::sample`] of each `(s[i], t[i])` into `out[i]`, the state resolved
    /// once: what a fragment group's lookup is.
    pub fn sample_lanes(&self, s: &[f32], t: &[f32], state: SamplerState, out: &mut [[f32; 4]]) {
        // The common case, a depth snapshot read nearest (a shadow map), in a loop of its own.
        if let (Texels::Depth { depths, .. }, Filter::Nearest, false) =
            (&self.texels, state.mag_filter.base(), self.alpha_one)
        {
            let fits_i32 = self.width as u64 * self.height as u64 <= i32::MAX as u64;
            if state.wrap_s == Wrap::ClampToEdge && state.wrap_t == Wrap::ClampToEdge && fits_i32 {
                self.depth_nearest_clamped(depths, s, t, out);
                return;
            }
            for ((o, &s), &t) in out.iter_mut().zip(s).zip(t) {
                let (u, v) = self.texel_coordinates(s, t);
                let z = depths[self.texel_index(floor_i64(u), floor_i64(v), state)];
                *o = [z, z, z, 1.0];
            }
            return;
        }
        for ((o, &s), &t) in out.iter_mut().zip(s).zip(t) {
            *o = self.sample(s, t, state);
        }
    }

    /// [`TextureSnapshot::sample_lanes`] of a depth snapshot read nearest with clamp-to-edge
    /// on both axes (a shadow map), eight lanes at a time in 32-bit arithmetic that vectorises:
    /// each lane's index is `texel_index`'s of the floored [`TextureSnapshot::texel_coordinates`],
    /// the coordinate clamped to the texels before it is made an integer, so that every value
    /// fits an `i32` exactly (the caller's check: at most `i32::MAX` texels).
    fn depth_nearest_clamped(&self, depths: &[f32], s: &[f32], t: &[f32], out: &mut [[f32; 4]]) {
        const N: usize = 8;
        let (width, height) = (self.width as i32, self.height as i32);
        let (last_x, last_y) = ((width - 1) as f32, (height - 1) as f32);
        // `floor(c)` clamped to `[0, last]` is `c` clamped to `[0, last]` then truncated: the
        // floor and the truncation differ below 0 only, which clamps to 0 either way (`c` is
        // finite, `last` below 2^24, so an exact float). In stages over arrays, so that each
        // stage is a loop of vector operations.
        let indices = |s: &[f32; N], t: &[f32; N]| -> [usize; N] {
            let (mut x, mut y) = ([0i32; N], [0i32; N]);
            for i in 0..N {
                let (u, v) = self.texel_coordinates(s[i], t[i]);
                (x[i], y[i]) = (u.clamp(0.0, last_x) as i32, v.clamp(0.0, last_y) as i32);
            }
            std::array::from_fn(|i| ((height - 1 - y[i]) * width + x[i]) as usize)
        };
        let write = |out: &mut [[f32; 4]], indices: [usize; N]| {
            for (o, i) in out.iter_mut().zip(indices) {
                let z = depths[i];
                *o = [z, z, z, 1.0];
            }
        };
        let lanes = out.len().min(s.len()).min(t.len());
        let whole = lanes / N * N;
        for base in (0..whole).step_by(N) {
            let lanes = |v: &[f32]| -> [f32; N] { v[base..base + N].try_into().expect("N lanes") };
            write(&mut out[base..base + N], indices(&lanes(s), &lanes(t)));
        }
        if whole < lanes {
            // The last lanes, padded with copies of the last of them.
            let padded = |v: &[f32]| -> [f32; N] { std::array::from_fn(|i| v[(whole + i).min(lanes - 1)]) };
            write(&mut out[whole..lanes], indices(&padded(s), &padded(t)));
        }
    }

    /// A shadow sampler's lookup at `(s, t)` with reference depth `reference`: with the
    /// state's compare function, each texel's depth compared (`tiler::depth_compare`) and,
    /// under linear filtering, the four 0/1 results blended with the bilinear weights, as
    /// llvmpipe does; without one, the depth (red of a colour texture: GL leaves that
    /// undefined).
    pub fn sample_compare(&self, s: f32, t: f32, reference: f32, state: SamplerState) -> f32 {
        let (Some(op), Texels::Depth { fixed_point, .. }) = (state.compare, &self.texels) else {
            return self.sample(s, t, state)[0];
        };
        let depth = |x: i64, y: i64| self.texel(x, y, state)[0];
        let (u, v) = self.texel_coordinates(s, t);
        match state.mag_filter.base() {
            Filter::Nearest => {
                tiler::depth_compare::compare(op, reference, depth(u.floor() as i64, v.floor() as i64), *fixed_point)
            }
            _ => {
                let (u, v) = (u - 0.5, v - 0.5);
                let (x0, y0) = (u.floor(), v.floor());
                let (fx, fy) = (u - x0, v - y0);
                let (x0, y0) = (x0 as i64, y0 as i64);
                let texels = [depth(x0, y0), depth(x0 + 1, y0), depth(x0, y0 + 1), depth(x0 + 1, y0 + 1)];
                tiler::depth_compare::compare_bilinear(op, reference, texels, fx, fy, *fixed_point)
            }
        }
    }

    /// GL texture coordinates `(s, t)` in texels of the snapshot (non-finite ones at 0,
    /// others kept where the conversions to integers are exact enough).
    #[inline]
    fn texel_coordinates(&self, s: f32, t: f32) -> (f32, f32) {
        let (s, t) = if s.is_finite() && t.is_finite() { (s, t) } else { (0.0, 0.0) };
        let (s, t) = (s.clamp(-65536.0, 65536.0), t.clamp(-65536.0, 65536.0));
        (s * self.width as f32, t * self.height as f32)
    }

    #[inline]
    fn sample_texels(&self, s: f32, t: f32, state: SamplerState) -> [f32; 4] {
        let (u, v) = self.texel_coordinates(s, t);
        match state.mag_filter.base() {
            Filter::Nearest => self.texel(floor_i64(u), floor_i64(v), state),
            _ => {
                let (u, v) = (u - 0.5, v - 0.5);
                let (x0, y0) = (floor_i64(u), floor_i64(v));
                // `u - u.floor()`: exact (`x0` is below 2²⁴ in size or `u` was whole), and
                // `+ 0.0` makes `-0.0 - 0.0` the `+0.0` that `-0.0 - (-0.0)` is.
                let (fx, fy) = (u - x0 as f32 + 0.0, v - y0 as f32 + 0.0);
                let a = self.texel(x0, y0, state);
                let b = self.texel(x0 + 1, y0, state);
                let c = self.texel(x0, y0 + 1, state);
                let d = self.texel(x0 + 1, y0 + 1, state);
                std::array::from_fn(|i| {
                    let top = a[i] + (b[i] - a[i]) * fx;
                    let bottom = c[i] + (d[i] - c[i]) * fx;
                    top + (bottom - top) * fy
                })
            }
        }
    }
}

/// `x.floor() as i64` for the finite `x` of texel coordinates (at most 2⁶² in size), without
/// a call of the C library's `floorf` (the baseline x86-64 has no rounding instruction):
/// the conversion truncates toward zero, and a negative `x` with a fraction goes one lower.
/// The comparison is exact: below 2²⁴ the integer is an `f32`, above it `x` is whole.
#[inline]
fn floor_i64(x: f32) -> i64 {
    let i = x as i64;
    if (i as f32) > x { i - 1 } else { i }
}

#[inline]
fn wrap_coord(i: i64, n: i64, wrap: Wrap) -> i64 {
    match wrap {
        Wrap::ClampToEdge => i.clamp(0, n - 1),
        Wrap::Repeat => i.rem_euclid(n),
        Wrap::MirroredRepeat => {
            let period = i.rem_euclid(2 * n);
            if period < n { period } else { 2 * n - 1 - period }
        }
    }
}

/// What a textured draw samples.
#[derive(Clone, Debug)]
pub enum ProgramTexture {
    /// An RGBA8 texture through the core's sampler and texture cache.
    Core(Arc<tiler::Texture>, tiler::Sampler),
    /// Any other format (or a blit's source), decoded on read.
    Snapshot(Arc<TextureSnapshot>, SamplerState),
}

/// Samples a texture at interpolated texture coordinates (varyings 0 and 1), times a colour.
struct TexturedShader {
    texture: ProgramTexture,
    color: [f32; 4],
    alpha_cutoff: f32,
}

impl FragmentShader for TexturedShader {
    fn properties(&self) -> ShaderProperties {
        ShaderProperties { discards: self.alpha_cutoff > 0.0, ..ShaderProperties::default() }
    }

    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        let [s, t] = frag.smooth_n::<2>(0);
        let color: [F32x8; 4] = match &self.texture {
            ProgramTexture::Core(texture, sampler) => {
                // The core's v runs down the rows as tiler stores them; GL's t runs up.
                let texel = frag.sample(texture, sampler, [s, F32x8::ONE - t]);
                std::array::from_fn(|c| texel[c] * self.color[c])
            }
            ProgramTexture::Snapshot(texture, sampler) => {
                let texels: [[f32; 4]; 8] =
                    std::array::from_fn(|lane| texture.sample(s.lane(lane), t.lane(lane), *sampler));
                std::array::from_fn(|c| F32x8::from_fn(|lane| texels[lane][c] * self.color[c]))
            }
        };
        if self.alpha_cutoff > 0.0 {
            frag.discard(color[3].lt(F32x8::splat(self.alpha_cutoff)));
        }
        frag.set_color(0, color);
    }
}

/// Builds the pipeline of a draw of a built-in program.
///
/// # Errors
/// What `Pipeline::new` refuses (the caller's state is validated before, so nothing
/// expected).
pub fn program_pipeline(
    kind: ProgramKind,
    uniforms: &Uniforms,
    texture: Option<ProgramTexture>,
    mut desc: PipelineDesc,
) -> tiler::Result<Pipeline> {
    desc.varyings = vec![Interpolation::Perspective; kind.varyings()];
    let model3 = Mat3::from_mat4(uniforms.model);
    let normal_matrix =
        if model3.determinant().abs() > f32::MIN_POSITIVE { model3.inverse().transpose() } else { Mat3::IDENTITY };
    let vertex = ProgramVertexShader { kind, mvp: uniforms.mvp, normal_matrix };
    match kind {
        ProgramKind::Solid => Pipeline::new(vertex, SolidShader { color: uniforms.color }, desc),
        ProgramKind::Composite => Pipeline::new(vertex, CompositeShader { color: uniforms.color }, desc),
        ProgramKind::VertexColor => {
            Pipeline::new(vertex, VertexColorShader { alpha_cutoff: uniforms.alpha_cutoff }, desc)
        }
        ProgramKind::Lambert => {
            let l = Vec3::from_array(uniforms.light_dir);
            let light = if l.length_squared() > 0.0 { l.normalize() } else { Vec3::Z };
            Pipeline::new(vertex, LambertShader { color: uniforms.color, light: light.to_array() }, desc)
        }
        ProgramKind::Textured => {
            let texture = texture.unwrap_or_else(|| {
                // An unbound unit samples as opaque black, as in GL.
                ProgramTexture::Snapshot(
                    Arc::new(TextureSnapshot::constant([0.0, 0.0, 0.0, 1.0])),
                    SamplerState::new(Filter::Nearest, Wrap::ClampToEdge),
                )
            });
            Pipeline::new(
                vertex,
                TexturedShader { texture, color: uniforms.color, alpha_cutoff: uniforms.alpha_cutoff },
                desc,
            )
        }
    }
}

/// A full-framebuffer triangle at depth `depth`: `(−1, −1), (3, −1), (−1, 3)` in tiler's
/// normalised device coordinates covers every pixel with one primitive (it stays inside the
/// guard band, so it is never cut).
struct ClearVertexShader {
    depth: f32,
}

impl VertexShader for ClearVertexShader {
    fn shade(&self, input: &VertexInput, out: &mut VertexOutput) {
        let (x, y) = match input.vertex_index {
            0 => (-1.0, -1.0),
            1 => (3.0, -1.0),
            _ => (-1.0, 3.0),
        };
        out.position = Vec4::new(x, y, self.depth, 1.0);
    }
}

/// Writes the clear colour to every colour attachment.
struct ClearShader {
    color: [f32; 4],
    targets: usize,
}

impl FragmentShader for ClearShader {
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        for t in 0..self.targets {
            frag.set_color(t, self.color.map(F32x8::splat));
        }
    }
}

/// The pipeline of a clear-quad: a draw that clears what a load op cannot (a scissored or
/// masked clear, or a clear of some buffers after draws). `desc` carries the masks and tests.
pub fn clear_pipeline(color: [f32; 4], depth: f32, targets: usize, desc: PipelineDesc) -> tiler::Result<Pipeline> {
    Pipeline::new(ClearVertexShader { depth }, ClearShader { color, targets }, desc)
}

/// A rectangle in tiler's normalised device coordinates (`x0, y0, x1, y1`, y down) and the
/// texture coordinates at its corners, for blits and copies: vertices 0..4 as a strip.
struct BlitVertexShader {
    ndc: [f32; 4],
    tex: [f32; 4],
}

impl VertexShader for BlitVertexShader {
    fn shade(&self, input: &VertexInput, out: &mut VertexOutput) {
        let right = input.vertex_index & 1 == 1;
        let bottom = input.vertex_index & 2 == 2;
        let x = if right { self.ndc[2] } else { self.ndc[0] };
        let y = if bottom { self.ndc[3] } else { self.ndc[1] };
        let s = if right { self.tex[2] } else { self.tex[0] };
        let t = if bottom { self.tex[3] } else { self.tex[1] };
        out.position = Vec4::new(x, y, 0.0, 1.0);
        out.varyings[0] = s;
        out.varyings[1] = t;
    }
}

/// The pipeline of a blit or copy: a textured rectangle (`ndc` and `tex` as above).
pub fn blit_pipeline(
    ndc: [f32; 4],
    tex: [f32; 4],
    texture: Arc<TextureSnapshot>,
    sampler: SamplerState,
    mut desc: PipelineDesc,
) -> tiler::Result<Pipeline> {
    desc.varyings = vec![Interpolation::Perspective; 2];
    Pipeline::new(
        BlitVertexShader { ndc, tex },
        TexturedShader { texture: ProgramTexture::Snapshot(texture, sampler), color: [1.0; 4], alpha_cutoff: 0.0 },
        desc,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floor_i64_is_floor() {
        let edges = [0.0f32, -0.0, 0.5, -0.5, 1.0, -1.0, 16_777_215.5, -16_777_216.0, 3e9, -3e9, 1e-30, -1e-30];
        let steps = (0..200_000)
            .map(|i| (i as f32 - 100_000.0) * 0.37)
            .chain((0..=u32::MAX).step_by(65_537).map(f32::from_bits));
        for x in edges.into_iter().chain(steps).filter(|x| x.is_finite() && x.abs() < 1e18) {
            assert_eq!(floor_i64(x), x.floor() as i64, "{x}");
        }
    }

    /// A group's lookups give each lane's `sample`, bit for bit, for depth and colour
    /// snapshots under each filter and wrap, coordinates inside and outside `[0, 1]`.
    #[test]
    fn sample_lanes_is_sample_lane_by_lane() {
        let (w, h) = (5u32, 3u32);
        let depths: Vec<f32> = (0..w * h).map(|i| i as f32 / 15.0).collect();
        let bytes: Vec<u8> = (0..w * h * 4).map(|i| (i * 37 % 256) as u8).collect();
        let snapshots = [
            TextureSnapshot::depth(w, h, depths, true),
            TextureSnapshot::color(w, h, tiler::Format::Rgba8Unorm, 1, bytes.clone()),
            TextureSnapshot::color(w, h, tiler::Format::Rgba8Unorm, 1, bytes).with_alpha_one(),
        ];
        // Then the edges: ±0, texel boundaries, the clamp's −1 and n, beyond the ±65536
        // clamp, non-finite (either coordinate makes both 0) — 75 lanes, a tail past the
        // eights that groups are read in.
        let special = [-0.0, 0.0, 0.2, 1.0, -0.2, 1.2, 1e-30, -1e-30, 7e4, -7e4, 1e30, f32::NAN, f32::INFINITY];
        let s: Vec<f32> = (0..62).map(|i| i as f32 * 0.061 - 1.3).chain(special).collect();
        let t: Vec<f32> = (0..62).map(|i| 2.1 - i as f32 * 0.047).chain(special.iter().rev().copied()).collect();
        for snapshot in &snapshots {
            for filter in [Filter::Nearest, Filter::Linear] {
                for wrap in [Wrap::ClampToEdge, Wrap::Repeat, Wrap::MirroredRepeat] {
                    let state = SamplerState::new(filter, wrap);
                    let mut out = vec![[0.0; 4]; s.len()];
                    snapshot.sample_lanes(&s, &t, state, &mut out);
                    for (i, o) in out.iter().enumerate() {
                        let want = snapshot.sample(s[i], t[i], state);
                        assert_eq!(o.map(f32::to_bits), want.map(f32::to_bits), "{filter:?} {wrap:?} lane {i}");
                    }
                }
            }
        }
    }
}
