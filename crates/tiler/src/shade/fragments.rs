//! The fragment shader's side of the pixel pipeline: the [`FragmentShader`] trait and the
//! [`Fragments`] of a 4×2 group it shades (varyings, derivatives, textures, input attachments,
//! colour outputs).

use crate::api::pipeline::MAX_COLOR_ATTACHMENTS;
use crate::api::render_pass::MAX_INPUT_ATTACHMENTS;
use crate::api::shader::ShaderProperties;
use crate::raster::target::Surface;
use crate::shade::ShadeContext;
use crate::shade::texture::{IntegerTexture, Lookup, Sampler, Texture};
use crate::simd::{F32x8, LaneMask, SimdSupport, Vec4x8};
use crate::simd::{LANE_DX, LANE_DY, LANES};

/// A fragment shader.
pub trait FragmentShader: Send + Sync + 'static {
    /// What this shader may do; the default is a pure function of its inputs.
    fn properties(&self) -> ShaderProperties {
        ShaderProperties::default()
    }

    /// Shades the eight lanes of `frag`, writing colours with [`Fragments::set_color`].
    ///
    /// Mark implementations `#[inline(always)]`: the pixel pipeline is compiled once per
    /// instruction set (`SimdLevel`) with the shader inlined into it; a shader left out of
    /// line is compiled for the baseline only (on x86-64, four lanes at a time instead of
    /// eight).
    fn shade(&self, frag: &mut Fragments<'_>);
}

/// Eight fragments (a 4×2 group of pixels: lanes 0–3 the top row, 4–7 the bottom row) of one
/// primitive: the fragment shader's inputs and outputs.
///
/// Lanes that the primitive does not cover are helper lanes: they are shaded so that
/// derivatives exist, and their outputs are thrown away.
pub struct Fragments<'a> {
    pub(crate) x: F32x8,
    pub(crate) y: F32x8,
    pub(crate) z: F32x8,
    /// Perspective-correct barycentric weights of vertices 1 and 2.
    pub(crate) b1: F32x8,
    pub(crate) b2: F32x8,
    /// Screen-linear barycentric weights of vertices 1 and 2.
    pub(crate) l1: F32x8,
    pub(crate) l2: F32x8,
    /// The three vertices' varyings, each `vertex_stride` floats after the one before (0
    /// when the three are the same values, stored once: a flat-only draw's).
    pub(crate) varyings: &'a [f32],
    pub(crate) vertex_stride: usize,
    pub(crate) front_facing: bool,
    pub(crate) covered: LaneMask,
    pub(crate) color: &'a mut [Vec4x8; MAX_COLOR_ATTACHMENTS],
    pub(crate) written_depth: F32x8,
    pub(crate) discarded: LaneMask,
    /// Per lane, bit `s` = sample `s` may stay covered.
    pub(crate) sample_mask: [u32; 8],
    /// The group's top-left pixel and the sample being shaded (0 when shading per pixel).
    pub(crate) group: (i32, i32),
    pub(crate) sample: usize,
    /// The subpass's input attachments and colour outputs, for reads.
    pub(crate) inputs: [Option<&'a Surface<'a>>; MAX_INPUT_ATTACHMENTS],
    pub(crate) locals: [Option<&'a Surface<'a>>; MAX_COLOR_ATTACHMENTS],
    /// Bytes read from input attachments and from colour outputs (pixel-local reads).
    pub(crate) input_bytes: u64,
    pub(crate) local_bytes: u64,
    pub(crate) context: &'a mut ShadeContext,
    /// The instruction set the pipeline runs with: texture sampling runs with it too.
    pub(crate) simd: SimdSupport,
}

impl<'a> Fragments<'a> {
    /// Window coordinates of the pixel centres (`x + 0.5`, `y + 0.5`, y down).
    #[inline(always)]
    pub fn position(&self) -> (F32x8, F32x8) {
        (self.x, self.y)
    }

    /// Interpolated window depth at the pixel centres.
    #[inline(always)]
    pub fn depth(&self) -> F32x8 {
        self.z
    }

    #[inline(always)]
    pub fn front_facing(&self) -> bool {
        self.front_facing
    }

    /// Lanes the primitive covers (the others are helper lanes).
    #[inline(always)]
    pub fn covered(&self) -> LaneMask {
        self.covered
    }

    /// Varying `i`, interpolated perspective-correctly (GLSL `smooth`).
    #[inline(always)]
    pub fn smooth(&self, i: usize) -> F32x8 {
        let (v0, v1, v2) = self.vertex_values(i);
        F32x8::splat(v0) + self.b1 * (v1 - v0) + self.b2 * (v2 - v0)
    }

    /// Varyings `first .. first + N`, interpolated perspective-correctly.
    #[inline(always)]
    pub fn smooth_n<const N: usize>(&self, first: usize) -> [F32x8; N] {
        crate::simd::array_from_fn(|k| self.smooth(first + k))
    }

    /// Varying `i`, interpolated linearly in screen space (GLSL `noperspective`).
    #[inline(always)]
    pub fn linear(&self, i: usize) -> F32x8 {
        let (v0, v1, v2) = self.vertex_values(i);
        F32x8::splat(v0) + self.l1 * (v1 - v0) + self.l2 * (v2 - v0)
    }

    /// Varying `i` of the provoking vertex (GLSL `flat`).
    #[inline(always)]
    pub fn flat(&self, i: usize) -> f32 {
        self.varyings[i]
    }

    #[inline(always)]
    fn vertex_values(&self, i: usize) -> (f32, f32, f32) {
        let n = self.vertex_stride;
        (self.varyings[i], self.varyings[n + i], self.varyings[2 * n + i])
    }

    /// Writes the colour for colour attachment `attachment` of the subpass.
    #[inline(always)]
    pub fn set_color(&mut self, attachment: usize, rgba: Vec4x8) {
        self.color[attachment] = rgba;
    }

    /// Replaces the fragment depth (the shader must declare `writes_depth`).
    #[inline(always)]
    pub fn set_depth(&mut self, z: F32x8) {
        self.written_depth = z;
    }

    /// Discards the given lanes (the shader must declare `discards`).
    #[inline(always)]
    pub fn discard(&mut self, lanes: LaneMask) {
        self.discarded = self.discarded | lanes;
    }

    /// Limits which samples each lane covers: bit `s` of `masks[lane]` keeps sample `s` (the
    /// shader must declare `writes_sample_mask`).
    #[inline(always)]
    pub fn set_sample_mask(&mut self, masks: [u32; 8]) {
        self.sample_mask = masks;
    }

    /// Input attachment `i` of the subpass at each lane's pixel (and sample): what an earlier
    /// subpass wrote there, read from the tile buffer on a tiler. Colour attachments give their
    /// RGBA; a depth-stencil attachment gives (depth, stencil, 0, 1). An input the subpass
    /// does not have reads as zero.
    #[inline]
    pub fn input(&mut self, i: usize) -> Vec4x8 {
        let surface = self.inputs.get(i).copied().flatten();
        let (value, bytes) = read_lanes(surface, self.group, self.sample);
        self.input_bytes += bytes;
        value
    }

    /// Colour output `i` of the subpass as it is now at each lane's pixel (and sample), before
    /// this fragment writes it: pixel-local storage (`VK_KHR_dynamic_rendering_local_read`).
    /// Fragments run in submission order per pixel, as with blending; the shader must declare
    /// `reads_local`.
    #[inline]
    pub fn local(&mut self, i: usize) -> Vec4x8 {
        let surface = self.locals.get(i).copied().flatten();
        let (value, bytes) = read_lanes(surface, self.group, self.sample);
        self.local_bytes += bytes;
        value
    }

    /// Samples `texture` at `uv` with `sampler`, the level of detail from this group's quad
    /// derivatives (see `shade::texture`). The texel reads of every quad with a covered pixel,
    /// helper lanes included, go through the task's texture cache and so into the ledger.
    #[inline]
    pub fn sample(&mut self, texture: &Texture, sampler: &Sampler, uv: [F32x8; 2]) -> Vec4x8 {
        texture.sample(self.simd, sampler, uv[0], uv[1], self.covered.quads(), &mut self.context.texture_cache)
    }

    /// [`Fragments::sample`] with explicit derivatives or a texel offset (GLSL ES 3.00's
    /// `textureGrad`, `textureOffset`). Inlined, as `sample`, so that the SIMD level's kernel
    /// is chosen in the shader's own code (a shader crate's call was kept out of line, compiled
    /// for the baseline: 2% of desktop.trace's replay).
    #[inline]
    pub fn sample_with(&mut self, texture: &Texture, sampler: &Sampler, uv: [F32x8; 2], lookup: &Lookup) -> Vec4x8 {
        let (simd, counted, cache) = (self.simd, self.covered.quads(), &mut self.context.texture_cache);
        texture.sample_with(simd, sampler, uv[0], uv[1], counted, cache, lookup)
    }

    /// [`Fragments::sample`] at each of `uvs` in turn, into `out` (as many as `uvs` gives),
    /// with the kernel for `texture` and `sampler` chosen once ([`Texture::sample_run`]).
    #[inline]
    pub fn sample_run(&mut self, texture: &Texture, sampler: &Sampler, uvs: &[[F32x8; 2]], out: &mut [[[f32; 8]; 4]]) {
        let (simd, counted, cache) = (self.simd, self.covered.quads(), &mut self.context.texture_cache);
        texture.sample_run(simd, sampler, uvs, counted, cache, out)
    }

    /// Samples cube texture `texture` in the directions `direction` with `sampler`, as
    /// [`Fragments::sample`] samples a 2D one (level of detail from the quad's face
    /// coordinates, reads of covered quads into the texture cache and the ledger).
    pub fn sample_cube(&mut self, texture: &Texture, sampler: &Sampler, direction: [F32x8; 3]) -> Vec4x8 {
        texture.sample_cube(self.simd, sampler, direction, self.covered.quads(), &mut self.context.texture_cache)
    }

    /// Samples 2-D array texture `texture` at `(s, t, layer)` with `sampler`, as
    /// [`Fragments::sample`] samples a 2D one (rows in GL's order: `t = 0` is row 0).
    pub fn sample_array(&mut self, texture: &Texture, sampler: &Sampler, coord: [F32x8; 3]) -> Vec4x8 {
        texture.sample_array(self.simd, sampler, coord, self.covered.quads(), &mut self.context.texture_cache)
    }

    /// Samples 3-D texture `texture` at `(s, t, r)` with `sampler`, as [`Fragments::sample`]
    /// samples a 2D one (rows in GL's order: `t = 0` is row 0).
    pub fn sample_volume(&mut self, texture: &Texture, sampler: &Sampler, coord: [F32x8; 3]) -> Vec4x8 {
        texture.sample_volume(self.simd, sampler, coord, self.covered.quads(), &mut self.context.texture_cache)
    }

    /// `texelFetch` of `texture` in the eight lanes: texel `coord` (`[x, y, layer]`) of level
    /// `level`, unfiltered, `(0, 0, 0, 0)` out of range (see `shade::texture::fetch`). The
    /// reads of every quad with a covered pixel go through the texture cache and the ledger.
    pub fn fetch(&mut self, texture: &Texture, level: [i32; 8], coord: [[i32; 8]; 3]) -> Vec4x8 {
        self.fetch_lanes(level, coord, |level, at| texture.fetch(level, at)).map(F32x8::from_array)
    }

    /// [`Fragments::fetch`] of an integer texture: each channel's 32-bit pattern, zeros out of
    /// range.
    pub fn fetch_integer(&mut self, texture: &IntegerTexture, level: [i32; 8], coord: [[i32; 8]; 3]) -> [[u32; 8]; 4] {
        self.fetch_lanes(level, coord, |level, at| texture.fetch(level, at))
    }

    /// Texel `coord` of level `level` in each lane through `read` (its value and modelled
    /// address), the reads of covered quads' lanes counted in the texture cache; zeros where
    /// `read` finds none.
    fn fetch_lanes<T: Copy + Default>(
        &mut self,
        level: [i32; 8],
        coord: [[i32; 8]; 3],
        read: impl Fn(i32, [i32; 3]) -> Option<([T; 4], u64)>,
    ) -> [[T; 8]; 4] {
        let counted = self.covered.quads();
        let mut out = [[T::default(); 8]; 4];
        for lane in 0..8 {
            if let Some((value, address)) = read(level[lane], coord.map(|c| c[lane])) {
                if counted.contains(lane) {
                    self.context.texture_cache.access(address);
                }
                for c in 0..4 {
                    out[c][lane] = value[c];
                }
            }
        }
        out
    }

    /// Per-tile state shaders may use (texture caches and their counters).
    #[inline(always)]
    pub fn context(&mut self) -> &mut ShadeContext {
        self.context
    }
}

/// Reads a view at the eight pixels of the group at `group` (sample `sample`, or the last one
/// the view has); pixels outside the view read as zero. Returns the values and bytes read.
fn read_lanes(surface: Option<&Surface>, group: (i32, i32), sample: usize) -> (Vec4x8, u64) {
    let Some(surface) = surface else { return ([F32x8::ZERO; 4], 0) };
    let format = surface.format;
    let bytes = format.bytes_per_sample();
    let sample = sample.min(surface.samples() - 1);
    let mut out = [[0.0f32; LANES]; 4];
    let mut read = 0;
    for lane in 0..LANES {
        let (x, y) = (group.0 + LANE_DX[lane] as i32, group.1 + LANE_DY[lane] as i32);
        if !surface.contains(x, y) {
            continue;
        }
        let offset = surface.offset(x, y);
        let texel = &surface.plane(sample)[offset..offset + bytes];
        let value = if format.is_color() {
            format.decode_color(texel)
        } else {
            let word = if bytes == 2 {
                u16::from_le_bytes([texel[0], texel[1]]) as u32
            } else {
                u32::from_le_bytes([texel[0], texel[1], texel[2], texel[3]])
            };
            let (depth, stencil) =
                if format.has_stencil() { (word & 0x00ff_ffff, (word >> 24) as f32) } else { (word, 0.0) };
            [format.depth_from_bits(depth), stencil, 0.0, 1.0]
        };
        for c in 0..4 {
            out[c][lane] = value[c];
        }
        read += bytes as u64;
    }
    (out.map(F32x8::from_array), read)
}
