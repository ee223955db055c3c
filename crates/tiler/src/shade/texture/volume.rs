//! 3-D textures: `depth` slices of `width × height` RGBA8 texels (laid out as a 2-D array's
//! layers, `array`), filtered in all three coordinates.
//!
//! The rules are the 2D ones (OpenGL ES 3.0 §3.8.10–3.8.11) with a third coordinate:
//!
//! - **Level of detail**, once per 2×2 quad from the upper-left pixel's differences, with
//!   `r · depth` in texels too: `ρ² = max(∂s/∂x² + ∂t/∂x² + ∂r/∂x², … y)`, `λ = ½ · log2(ρ²)`;
//!   it picks the magnification or the minification filter for all three axes.
//! - **Slices**: nearest reads slice `⌊r · d⌋`; linear reads slices `k0 = ⌊r · d − ½⌋` and
//!   `k0 + 1`, each with the 2D bilinear filter, blended with the 8-bit weight
//!   `γ = ⌊256 · frac(r · d − ½)⌋` by the filter's `lerp` (as llvmpipe filters RGBA8 volumes in
//!   fixed point: bilinear in each slice, then across). `WRAP_R` (the sampler's `wrap_w`)
//!   wraps the slice index as `s` and `t` are wrapped.
//! - **Mip maps**: level 0 only. The GL context refuses to make a 3-D texture's mip chain and
//!   to sample one with a mipmap minification filter (GL would find it incomplete, §3.8.13),
//!   so a volume is only ever sampled at level 0 (a sampler whose mipmap mode is not `None`
//!   reads level 0 here, as the 2D sampler does for a texture without levels).
//!
//! Both slices' texels are read through the texture-cache model (the ledger's `texture
//! fetch`), slice `k0`'s footprint and then `k0 + 1`'s.

use super::*;

impl Texture {
    /// Samples a 3-D texture at `(s, t, r)` in the eight lanes with the instruction set of
    /// `simd`, as [`Texture::sample`] samples a 2D one (see the module notes).
    #[inline]
    pub fn sample_volume(
        &self,
        simd: SimdSupport,
        sampler: &Sampler,
        coord: [F32x8; 3],
        counted: LaneMask,
        cache: &mut TextureCache,
    ) -> Vec4x8 {
        debug_assert!(
            self.layered().is_some_and(|(kind, _)| kind == LayeredKind::Volume),
            "sample_volume of another kind"
        );
        sample_volume_group(simd, self, sampler, coord, counted, cache)
    }

    /// [`Texture::sample_volume`]'s body.
    #[inline(always)]
    fn sample_volume_quads(
        &self,
        simd: SimdSupport,
        sampler: &Sampler,
        coord: [F32x8; 3],
        counted: LaneMask,
        cache: &mut TextureCache,
    ) -> Vec4x8 {
        let depth = self.layers.map_or(1, |l| l.count) as f32;
        let [u, v, r] = coord;
        let (width, height) = (self.width() as f32, self.height() as f32);
        let mut quads = [[[0u32; 4]; 4]; 2];
        for (quad, lanes) in QUAD_LANES.iter().enumerate() {
            let [tl, tr, bl, _] = *lanes;
            // Differences scaled to texels, as in 2D (`quad_rho_squared`).
            let d = |c: F32x8, n: f32, to: usize| (c.lane(to) - c.lane(tl)) * n;
            let length = |to: usize| {
                let (ds, dt, dr) = (d(u, width, to), d(v, height, to), d(r, depth, to));
                ds * ds + dt * dt + dr * dr
            };
            let lambda = lod_of_rho_squared(length(tr).max(length(bl))) + sampler.lod_bias;
            let quad_of = |c: F32x8| super::lanes(|i| c.lane(lanes[i]));
            let counted = lanes.map(|lane| counted.contains(lane));
            let minified_unmipped = sampler.mipmap == MipmapMode::None && lambda > super::UNMIPPED_LOD;
            let mut sample =
                |at: &QuadAt| self.sample_quad::<false>(simd, sampler, lambda, at, counted, minified_unmipped, cache);
            quads[quad] = match self.volume_slices(sampler, lambda, quad_of(u), quad_of(v), quad_of(r)) {
                Slices::One(at) => sample(&at),
                Slices::Two(near, far, gamma) => {
                    let (a, b) = (sample(&near), sample(&far));
                    std::array::from_fn(|c| super::lanes(|i| lerp(a[c][i], b[c][i], gamma[i])))
                }
            };
        }
        group_of_quads(quads, false)
    }

    /// The slices a quad's lanes read at level of detail `lambda` and where in them.
    #[inline(always)]
    fn volume_slices(&self, sampler: &Sampler, lambda: f32, u: Quad, v: Quad, r: Quad) -> Slices {
        let depth = self.layers.map_or(1, |l| l.count);
        let filter = match self.plan(sampler, lambda) {
            LevelPlan::Single { filter, .. } | LevelPlan::Blend { filter, .. } => filter,
        };
        let (u, v, r) =
            (reduce_quad(u, sampler.wrap_u), reduce_quad(v, sampler.wrap_v), reduce_quad(r, sampler.wrap_w));
        let at = |slices: [u32; 4]| QuadAt {
            u,
            v,
            face_offsets: slices.map(|k| self.layer_offset(k)),
            offset: [0, 0],
            bytes: false,
        };
        match filter {
            Filter::Nearest => Slices::One(at(nearest_texels(r, depth, sampler.wrap_w))),
            Filter::Linear => {
                let ([k0, k1], gamma) = linear_texels(r, depth, sampler.wrap_w);
                Slices::Two(at(k0), at(k1), gamma)
            }
        }
    }

    /// Samples a 3-D texture at one point `(s, t, r)` at the level of detail `lambda` (bias
    /// added; it only picks the filter, see the module notes), as [`Texture::sample_lod`]
    /// samples a 2D one. Reads are not counted.
    pub fn sample_volume_lod(&self, sampler: &Sampler, coord: [f32; 3], lambda: f32) -> [f32; 4] {
        let lambda = lambda + sampler.lod_bias;
        let [u, v, r] = coord.map(|c| [c; 4]);
        let at_level0 = |at: &QuadAt| {
            let filter = match self.plan(sampler, lambda) {
                LevelPlan::Single { filter, .. } | LevelPlan::Blend { filter, .. } => filter,
            };
            self.filter(&self.footprint::<false, 4>(0, filter, sampler, at, 0))
        };
        let rgba = match self.volume_slices(sampler, lambda, u, v, r) {
            Slices::One(at) => at_level0(&at),
            Slices::Two(near, far, gamma) => {
                let (a, b) = (at_level0(&near), at_level0(&far));
                std::array::from_fn(|c| super::lanes(|i| lerp(a[c][i], b[c][i], gamma[i])))
            }
        };
        rgba.map(|channel| unorm16_to_f32(channel[0]))
    }
}

/// What a quad reads of a volume: one slice per lane, or two blended by 8-bit weights.
enum Slices {
    One(QuadAt),
    Two(QuadAt, QuadAt, [u32; 4]),
}

per_simd_level! {
    /// [`Texture::sample_volume`], compiled once per SIMD level (as `sample_group`).
    fn sample_volume_group / sample_volume_group_avx2 => sample_volume_group_body, simd: simd, (
        simd: SimdSupport,
        texture: &Texture,
        sampler: &Sampler,
        coord: [F32x8; 3],
        counted: LaneMask,
        cache: &mut TextureCache,
    ) -> Vec4x8
}

#[inline(always)]
fn sample_volume_group_body(
    simd: SimdSupport,
    texture: &Texture,
    sampler: &Sampler,
    coord: [F32x8; 3],
    counted: LaneMask,
    cache: &mut TextureCache,
) -> Vec4x8 {
    texture.sample_volume_quads(simd, sampler, coord, counted, cache)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shade::texture_cache::TextureCacheConfig;

    /// Slice `k` of `w × h`: texel `(x, y)` is `(16 x, 16 y, 40 k, 255)`.
    fn volume(w: u32, h: u32, d: u32) -> Texture {
        let texels: Vec<u8> = (0..d)
            .flat_map(|k| {
                (0..w * h).flat_map(move |p| [(16 * (p % w)) as u8, (16 * (p / w)) as u8, (40 * k) as u8, 255])
            })
            .collect();
        Texture::volume_from_rgba8(w, h, d, &texels, ColorSpace::Linear).unwrap()
    }

    const LINEAR: Sampler = Sampler { wrap_w: Wrap::ClampToEdge, ..Sampler::BILINEAR_CLAMP };

    #[test]
    fn linear_filtering_blends_two_slices_with_an_8_bit_weight() {
        let t = volume(4, 4, 4);
        // r · 4 − ½ = 1.25: slices 1 and 2, γ = 64; blue 40 → 80: 40 · 257 + (40 · 257 · 64 + 128) >> 8.
        let blue = 40 * 257 + ((40 * 257 * 64 + 128) >> 8);
        let c = t.sample_volume_lod(&LINEAR, [0.5, 0.5, 1.75 / 4.0], 0.0);
        assert_eq!(c[2], blue as f32 / 65535.0);
        // s · 4 − ½ = 1 exactly: texel 1 alone; r · 4 − ½ = 2: slice 2 alone.
        let c = t.sample_volume_lod(&LINEAR, [0.375, 0.125, 0.625], 0.0);
        assert_eq!(c[..3], [16.0 / 255.0, 0.0, 80.0 / 255.0]);
        // Nearest reads slice ⌊r · d⌋.
        let nearest = Sampler { wrap_w: Wrap::Repeat, ..Sampler::NEAREST_REPEAT };
        assert_eq!(t.sample_volume_lod(&nearest, [0.1, 0.1, 0.74], 0.0)[2], 80.0 / 255.0);
        // WRAP_R: repeat takes r mod 1, clamp the edge slice.
        assert_eq!(t.sample_volume_lod(&nearest, [0.1, 0.1, 1.99], 0.0)[2], 120.0 / 255.0);
        assert_eq!(t.sample_volume_lod(&nearest, [0.1, 0.1, 2.1], 0.0)[2], 0.0);
        let clamp_r = Sampler { wrap_w: Wrap::ClampToEdge, ..nearest };
        assert_eq!(t.sample_volume_lod(&clamp_r, [0.1, 0.1, 2.1], 0.0)[2], 120.0 / 255.0);
        // Linear at r = 0 clamped: slice 0 alone; repeated: slices 3 and 0 blended half and half.
        assert_eq!(t.sample_volume_lod(&LINEAR, [0.5, 0.5, 0.0], 0.0)[2], 0.0);
        let repeat = Sampler { wrap_w: Wrap::Repeat, ..LINEAR };
        let half = 120 * 257 + ((0 - 120 * 257 * 128 + 128) >> 8);
        assert_eq!(t.sample_volume_lod(&repeat, [0.5, 0.5, 0.0], 0.0)[2], half as f32 / 65535.0);
    }

    #[test]
    fn a_group_samples_as_its_lanes_one_by_one_and_counts_both_slices() {
        let t = volume(8, 8, 4);
        let mut cache = TextureCache::new(TextureCacheConfig::DEFAULT);
        let u = F32x8::from_fn(|i| 0.2 + LANE_DX[i] as f32 * 0.125);
        let v = F32x8::from_fn(|i| 0.3 + LANE_DY[i] as f32 * 0.125);
        let r = F32x8::from_fn(|i| 0.1 + i as f32 * 0.1);
        let c = t.sample_volume(SimdSupport::BASELINE, &LINEAR, [u, v, r], LaneMask::ALL, &mut cache);
        for lane in 0..8 {
            // One texel a pixel: λ 0, magnified.
            let want = t.sample_volume_lod(&LINEAR, [u.lane(lane), v.lane(lane), r.lane(lane)], 0.0);
            assert_eq!([0, 1, 2, 3].map(|ch| c[ch].lane(lane)), want, "lane {lane}");
        }
        // An 8×8 slice is four 64-byte blocks; these footprints span the slices' lines.
        assert!(cache.misses() > 4, "{}", cache.misses());
        // One counted lane at a texel corner inside one block of slices 1 and 2: two lines.
        let mut cache = TextureCache::new(TextureCacheConfig::DEFAULT);
        let at = [F32x8::splat(0.25), F32x8::splat(0.25), F32x8::splat(0.5)];
        t.sample_volume(SimdSupport::BASELINE, &LINEAR, at, LaneMask(1), &mut cache);
        assert_eq!((cache.misses(), cache.hits()), (2, 6));
        assert_eq!(cache.take_fetched_bytes(), 2 * 64);
    }

    #[test]
    fn every_simd_level_samples_the_same_bits() {
        let t = volume(16, 8, 8);
        let levels: Vec<SimdSupport> = [crate::simd::SimdLevel::Baseline, crate::simd::SimdLevel::Avx2]
            .into_iter()
            .filter_map(SimdSupport::detect)
            .collect();
        let repeat = Sampler { wrap_w: Wrap::MirroredRepeat, ..Sampler::TRILINEAR_REPEAT };
        for seed in 0..32u32 {
            let f = |k: u32| ((seed * 7 + k * 13) % 17) as f32 / 8.0 - 1.0;
            let coord = [0, 1, 2].map(|c| {
                F32x8::from_fn(|i| f(c) + (LANE_DX[i] as f32 * f(c + 3) + LANE_DY[i] as f32 * f(c + 6)) * 0.2)
            });
            let mut results = levels.iter().map(|&simd| {
                let mut cache = TextureCache::default();
                let c = t.sample_volume(simd, &repeat, coord, LaneMask::ALL, &mut cache);
                (c.map(|c| c.to_array().map(f32::to_bits)), cache.misses(), cache.hits())
            });
            let first = results.next().unwrap();
            for other in results {
                assert_eq!(other, first);
            }
        }
    }
}
