//! 2-D array textures: layers of one size, each a 2D texture with its own mip chain, one
//! selected per lane by the third coordinate (as a cube face is by the direction), the 2D
//! filter within it. 3-D textures (`volume`) are built the same way, one layer a slice.
//!
//! **Layer selection** follows OpenGL ES 3.0 §3.8.10 (eq. 3.26): layer
//! `clamp(⌊r + ½⌋, 0, layers − 1)`, per lane; a NaN `r` reads layer 0. (llvmpipe rounds `r`
//! to nearest even, so at `r` exactly half-way, `k + ½`, its layer can be the one below.)
//!
//! **Filtering** is the 2D sampler's: the same fixed-point filter, level of detail from the
//! quad's `(s, t)` derivatives as for a 2D texture of the layer's size, the sampler's wraps on
//! `s` and `t`, within the selected layer (a bilinear footprint never reads a neighbouring
//! layer) — GL's rule for array textures.
//!
//! **Memory** is the cube's model: the layers one after the other, `layer_bytes` apart, each a
//! chain as a 2D texture of that size lays it out, so every layer's texels are counted in the
//! texture-cache model (the ledger's `texture fetch`) at addresses of their own.

use super::*;

/// The most layers of a 2-D array texture: GL ES 3.0's minimum `MAX_ARRAY_TEXTURE_LAYERS`.
pub const MAX_ARRAY_LAYERS: u32 = 256;

/// The largest side of a 3-D texture: GL ES 3.0's minimum `MAX_3D_TEXTURE_SIZE`.
pub const MAX_VOLUME_DIMENSION: u32 = 256;

/// What the layers of a layered texture are.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LayeredKind {
    /// A 2-D array texture (`GL_TEXTURE_2D_ARRAY`, `sampler2DArray`): the third coordinate
    /// selects a layer.
    Array,
    /// A 3-D texture (`GL_TEXTURE_3D`, `sampler3D`): the third coordinate is filtered across
    /// slices (`volume`).
    Volume,
}

/// A layered texture's layers: how many, and how far apart in the modelled memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Layers {
    pub(super) kind: LayeredKind,
    pub(super) count: u32,
    /// Bytes from one layer's chain to the next's (a multiple of a block's 64 bytes).
    pub(super) layer_bytes: u32,
}

impl Texture {
    /// A 2-D array texture of `layers` layers of `width × height` RGBA8 texels, `rgba` the
    /// layers one after the other, each's rows in the order GL uploads them (row 0 is
    /// `t = 0`, as a cube face's), each layer with the mip chain `mips` builds.
    ///
    /// # Errors
    /// A size out of range (a layer as [`Texture::from_rgba8`] takes it, 1 to
    /// [`MAX_ARRAY_LAYERS`] layers), `rgba` not `width × height × layers × 4` bytes long, or
    /// more than 4 GiB of modelled texels.
    pub fn array_from_rgba8(
        width: u32,
        height: u32,
        layers: u32,
        rgba: &[u8],
        color_space: ColorSpace,
        mips: MipChain,
    ) -> Result<Texture> {
        check_layers("2-D array texture", width, height, layers, MAX_ARRAY_LAYERS, rgba)?;
        Texture::from_layers(LayeredKind::Array, width, height, layers, rgba, color_space, mips)
    }

    /// A 3-D texture of `depth` slices of `width × height` RGBA8 texels, `rgba` the slices
    /// one after the other (`r = 0` first), rows as for [`Texture::array_from_rgba8`]; level 0
    /// only (see `volume`).
    ///
    /// # Errors
    /// A side of 0 or above [`MAX_VOLUME_DIMENSION`], or `rgba` not `width × height × depth ×
    /// 4` bytes long.
    pub fn volume_from_rgba8(
        width: u32,
        height: u32,
        depth: u32,
        rgba: &[u8],
        color_space: ColorSpace,
    ) -> Result<Texture> {
        if width > MAX_VOLUME_DIMENSION || height > MAX_VOLUME_DIMENSION {
            return Err(Error::invalid(
                "3-D texture",
                format!("size {width}×{height}×{depth}: each side must be from 1 to {MAX_VOLUME_DIMENSION}"),
            ));
        }
        check_layers("3-D texture", width, height, depth, MAX_VOLUME_DIMENSION, rgba)?;
        Texture::from_layers(LayeredKind::Volume, width, height, depth, rgba, color_space, MipChain::BaseOnly)
    }

    /// The layers of `rgba` (checked), each built as a 2D texture, as one texture.
    fn from_layers(
        kind: LayeredKind,
        width: u32,
        height: u32,
        count: u32,
        rgba: &[u8],
        color_space: ColorSpace,
        mips: MipChain,
    ) -> Result<Texture> {
        let layer_len = width as usize * height as usize * 4;
        let mut layers =
            rgba.chunks_exact(layer_len).map(|layer| Texture::from_rgba8(width, height, layer, color_space, mips));
        let mut texture = layers.next().expect("at least one layer")?;
        let layer_texels = texture.texels.len();
        let layer_bytes = layer_texels as u64 * TEXEL_BYTES;
        if layer_bytes * count as u64 > u32::MAX as u64 {
            return Err(Error::invalid(
                "layered texture",
                format!("{width}×{height}×{count} with its mip chains takes more than 4 GiB"),
            ));
        }
        texture.texels.reserve(layer_texels * (count as usize - 1));
        for layer in layers {
            texture.texels.extend(&layer?.texels);
        }
        texture.layers = Some(Layers { kind, count, layer_bytes: layer_bytes as u32 });
        Ok(texture)
    }

    /// A layered texture's kind and number of layers (slices), `None` for a 2D or cube one.
    pub fn layered(&self) -> Option<(LayeredKind, u32)> {
        self.layers.map(|l| (l.kind, l.count))
    }

    /// Texel `(x, y)` of `level` of layer `layer` (rows in GL's order).
    pub fn layer_texel(&self, layer: u32, level: usize, x: u32, y: u32) -> [u8; 4] {
        let l = &self.levels[level];
        debug_assert!(x < l.width && y < l.height);
        self.texel_bytes(self.layer_offset(layer) as usize / TEXEL_BYTES as usize + l.texel_index(x, y))
    }

    /// The modelled address of texel `(x, y)` of `level` of layer `layer` (see
    /// [`Texture::texel_address`]).
    pub fn layer_texel_address(&self, layer: u32, level: usize, x: u32, y: u32) -> u64 {
        self.texel_address(level, x, y) + self.layer_offset(layer) as u64
    }

    /// Where layer `layer` starts in the modelled memory, relative to the texture.
    #[inline(always)]
    pub(super) fn layer_offset(&self, layer: u32) -> u32 {
        self.layers.map_or(0, |l| l.layer_bytes * layer)
    }

    /// Samples a 2-D array texture at `(s, t, r)` in the eight lanes with the instruction set
    /// of `simd`, as [`Texture::sample`] samples a 2D one (the same bits at every SIMD level,
    /// reads of the `counted` lanes through `cache`): layer `r` (see the module notes), `s`,
    /// `t` as GL gives them (row 0 is `t = 0`).
    #[inline]
    pub fn sample_array(
        &self,
        simd: SimdSupport,
        sampler: &Sampler,
        coord: [F32x8; 3],
        counted: LaneMask,
        cache: &mut TextureCache,
    ) -> Vec4x8 {
        debug_assert!(
            self.layered().is_some_and(|(kind, _)| kind == LayeredKind::Array),
            "sample_array of another kind"
        );
        sample_array_group(simd, self, sampler, coord, counted, cache)
    }

    /// [`Texture::sample_array`]'s body.
    #[inline(always)]
    fn sample_array_quads(
        &self,
        simd: SimdSupport,
        sampler: &Sampler,
        coord: [F32x8; 3],
        counted: LaneMask,
        cache: &mut TextureCache,
    ) -> Vec4x8 {
        let [u, v, r] = coord;
        let rho_squared = quad_rho_squared(u, v, self.width() as f32, self.height() as f32);
        let mut quads = [[[0u32; 4]; 4]; 2];
        for (quad, lanes) in QUAD_LANES.iter().enumerate() {
            let lambda = lod_of_rho_squared(rho_squared[quad]) + sampler.lod_bias;
            let at = self.array_quad_at(
                sampler,
                super::lanes(|i| u.lane(lanes[i])),
                super::lanes(|i| v.lane(lanes[i])),
                super::lanes(|i| r.lane(lanes[i])),
            );
            let counted = lanes.map(|lane| counted.contains(lane));
            let minified_unmipped = sampler.mipmap == MipmapMode::None && lambda > super::UNMIPPED_LOD;
            quads[quad] = self.sample_quad::<false>(simd, sampler, lambda, &at, counted, minified_unmipped, cache);
        }
        group_of_quads(quads, self.filters_bytes(sampler))
    }

    /// Where a quad's lanes read: `(s, t)` reduced for the wraps, each lane's layer.
    #[inline(always)]
    fn array_quad_at(&self, sampler: &Sampler, u: Quad, v: Quad, r: Quad) -> QuadAt {
        let count = self.layers.map_or(1, |l| l.count);
        QuadAt {
            u: reduce_quad(u, sampler.wrap_u),
            v: reduce_quad(v, sampler.wrap_v),
            face_offsets: r.map(|r| self.layer_offset(array_layer(r, count))),
            offset: [0, 0],
            bytes: self.filters_bytes(sampler),
        }
    }

    /// Samples a 2-D array texture at one point `(s, t, r)` at the level of detail `lambda`
    /// given by the caller (bias added), as [`Texture::sample_lod`] samples a 2D one (what
    /// `textureLod` and a vertex shader's `texture` read). Reads are not counted.
    pub fn sample_array_lod(&self, sampler: &Sampler, coord: [f32; 3], lambda: f32) -> [f32; 4] {
        let [u, v, r] = coord.map(|c| [c; 4]);
        self.sample_point(sampler, &self.array_quad_at(sampler, u, v, r), lambda)
    }
}

/// The layer of coordinate `r` among `count` (see the module notes).
#[inline(always)]
pub(super) fn array_layer(r: f32, count: u32) -> u32 {
    let layer = floor(r + 0.5);
    if layer >= (count - 1) as f32 {
        count - 1
    } else if layer >= 0.0 {
        layer as u32
    } else {
        0 // negative, or NaN
    }
}

per_simd_level! {
    /// [`Texture::sample_array`], compiled once per SIMD level (as `sample_group`).
    fn sample_array_group / sample_array_group_avx2 => sample_array_group_body, simd: simd, (
        simd: SimdSupport,
        texture: &Texture,
        sampler: &Sampler,
        coord: [F32x8; 3],
        counted: LaneMask,
        cache: &mut TextureCache,
    ) -> Vec4x8
}

#[inline(always)]
fn sample_array_group_body(
    simd: SimdSupport,
    texture: &Texture,
    sampler: &Sampler,
    coord: [F32x8; 3],
    counted: LaneMask,
    cache: &mut TextureCache,
) -> Vec4x8 {
    texture.sample_array_quads(simd, sampler, coord, counted, cache)
}

/// `count` layers of `width × height` (`what` names the texture in errors), and `rgba` their
/// texels.
fn check_layers(what: &str, width: u32, height: u32, count: u32, max: u32, rgba: &[u8]) -> Result<()> {
    if count == 0 || count > max {
        return Err(Error::invalid(what, format!("{count} layers: from 1 to {max}")));
    }
    check_size(width, height, TexelFormat::Rgba8)?;
    let want = width as u64 * height as u64 * count as u64 * 4;
    if rgba.len() as u64 != want {
        return Err(Error::invalid(
            what,
            format!("{} bytes of texels for {width}×{height}×{count} RGBA8, which needs {want}", rgba.len()),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shade::texture_cache::TextureCacheConfig;

    /// Layer `k` of `w × h`: texel `(x, y)` is `(x, y, 30 · k, 255)`.
    fn layers_texels(w: u32, h: u32, count: u32) -> Vec<u8> {
        (0..count)
            .flat_map(|k| (0..w * h).flat_map(move |p| [(p % w) as u8, (p / w) as u8, 30 * k as u8, 255]))
            .collect()
    }

    #[test]
    fn the_layer_is_r_rounded_and_clamped() {
        assert_eq!(
            [-3.0, -0.4, 0.49, 0.5, 1.2, 1.6, 2.4, 9.0, f32::NAN].map(|r| array_layer(r, 3)),
            [0, 0, 0, 1, 1, 2, 2, 2, 0]
        );
        assert_eq!(array_layer(7.0, 1), 0);
    }

    #[test]
    fn each_layer_samples_as_the_same_2d_texture() {
        let (w, h, count) = (8, 4, 5);
        let texels = layers_texels(w, h, count);
        let t = Texture::array_from_rgba8(w, h, count, &texels, ColorSpace::Linear, MipChain::Linear).unwrap();
        assert_eq!(t.layered(), Some((LayeredKind::Array, count)));
        let layer_len = (w * h * 4) as usize;
        let mut cache = TextureCache::default();
        for k in 0..count {
            let flat = Texture::from_rgba8(
                w,
                h,
                &texels[k as usize * layer_len..][..layer_len],
                ColorSpace::Linear,
                MipChain::Linear,
            )
            .unwrap();
            assert_eq!(t.layer_texel(k, 0, 3, 2), [3, 2, 30 * k as u8, 255]);
            for sampler in [Sampler::TRILINEAR_REPEAT, Sampler::BILINEAR_CLAMP, Sampler::NEAREST_REPEAT] {
                for (s, tt) in [(0.3f32, 0.7f32), (-0.2, 1.3), (0.5, 0.5)] {
                    for lambda in [0.0, 0.7, 1.5, 5.0] {
                        let r = k as f32 + 0.3;
                        assert_eq!(
                            t.sample_array_lod(&sampler, [s, tt, r], lambda),
                            flat.sample_lod(&sampler, s, tt, lambda),
                            "layer {k}"
                        );
                    }
                }
                // A group: the same as the flat texture's group, derivatives included.
                let u = F32x8::from_fn(|i| 0.1 + LANE_DX[i] as f32 * 0.07 + LANE_DY[i] as f32 * 0.01);
                let v = F32x8::from_fn(|i| 0.6 + LANE_DY[i] as f32 * 0.09);
                let r = F32x8::splat(k as f32 - 0.2);
                let got = t.sample_array(SimdSupport::BASELINE, &sampler, [u, v, r], LaneMask::ALL, &mut cache);
                let want = flat.sample(SimdSupport::BASELINE, &sampler, u, v, LaneMask::ALL, &mut cache);
                assert_eq!(got.map(|c| c.to_array()), want.map(|c| c.to_array()), "layer {k}");
            }
        }
    }

    #[test]
    fn the_ledger_counts_each_layer_at_its_own_addresses() {
        // 4×4 layers, no mips: one 64-byte block (one line) each.
        let t = Texture::array_from_rgba8(4, 4, 3, &layers_texels(4, 4, 3), ColorSpace::Linear, MipChain::BaseOnly)
            .unwrap();
        assert_eq!(t.layer_texel_address(2, 0, 0, 0) - t.layer_texel_address(0, 0, 0, 0), 2 * 64);
        let mut cache = TextureCache::new(TextureCacheConfig::DEFAULT);
        let uv = [F32x8::splat(0.5), F32x8::splat(0.5)];
        for layer in [0.0, 1.0, 2.0] {
            // One counted lane, bilinear: four reads of one line.
            t.sample_array(
                SimdSupport::BASELINE,
                &Sampler::BILINEAR_CLAMP,
                [uv[0], uv[1], F32x8::splat(layer)],
                LaneMask(1),
                &mut cache,
            );
        }
        assert_eq!((cache.misses(), cache.hits()), (3, 9));
        assert_eq!(cache.take_fetched_bytes(), 3 * 64);
        // Lanes reading different layers in one group: each its layer's line.
        let r = F32x8::from_fn(|i| (i % 3) as f32);
        let c = t.sample_array(
            SimdSupport::BASELINE,
            &Sampler::NEAREST_REPEAT,
            [uv[0], uv[1], r],
            LaneMask::ALL,
            &mut cache,
        );
        for lane in 0..8 {
            // A byte `c` reads `c · fl(1/255)` (llvmpipe's conversion).
            assert_eq!(c[2].lane(lane), (30 * (lane % 3)) as f32 * (1.0 / 255.0), "lane {lane}");
        }
        assert_eq!(cache.take_fetched_bytes(), 0, "all three lines are cached");
    }

    #[test]
    fn every_simd_level_samples_the_same_bits() {
        let t = Texture::array_from_rgba8(16, 8, 4, &layers_texels(16, 8, 4), ColorSpace::Srgb, MipChain::Box).unwrap();
        let levels: Vec<SimdSupport> = [crate::simd::SimdLevel::Baseline, crate::simd::SimdLevel::Avx2]
            .into_iter()
            .filter_map(SimdSupport::detect)
            .collect();
        for seed in 0..32u32 {
            let f = |k: u32| ((seed * 7 + k * 13) % 17) as f32 / 8.0 - 1.0;
            let coord = [0, 1, 2].map(|c| {
                F32x8::from_fn(|i| f(c) * 2.0 + (LANE_DX[i] as f32 * f(c + 3) + LANE_DY[i] as f32 * f(c + 6)) * 0.3)
            });
            let mut results = levels.iter().map(|&simd| {
                let mut cache = TextureCache::default();
                let c = t.sample_array(simd, &Sampler::TRILINEAR_REPEAT, coord, LaneMask::ALL, &mut cache);
                (c.map(|c| c.to_array().map(f32::to_bits)), cache.misses(), cache.hits())
            });
            let first = results.next().unwrap();
            for other in results {
                assert_eq!(other, first);
            }
        }
    }

    #[test]
    fn bad_arrays_are_refused() {
        let texels = layers_texels(4, 4, 2);
        assert!(Texture::array_from_rgba8(4, 4, 3, &texels, ColorSpace::Linear, MipChain::Box).is_err());
        assert!(Texture::array_from_rgba8(4, 4, 0, &[], ColorSpace::Linear, MipChain::Box).is_err());
        let error =
            Texture::array_from_rgba8(4, 4, MAX_ARRAY_LAYERS + 1, &[], ColorSpace::Linear, MipChain::Box).unwrap_err();
        assert!(error.to_string().contains("layers"), "{error}");
        assert!(Texture::volume_from_rgba8(MAX_VOLUME_DIMENSION + 1, 1, 1, &[0; 4 * 257], ColorSpace::Linear).is_err());
    }
}
