//! Cube textures: six square RGBA8 faces, each with its mip chain, sampled by a direction.
//!
//! **Face selection** follows the OpenGL ES 2.0 specification, §3.7.5 "Cube Map Texture
//! Selection": the direction's component of largest magnitude (the major axis, `ma`) picks
//! the face, and the other two give the face coordinates
//!
//! | face | `sc` | `tc` | `ma` |
//! | --- | --- | --- | --- |
//! | +X | −rz | −ry | rx |
//! | −X | +rz | −ry | rx |
//! | +Y | +rx | +rz | ry |
//! | −Y | +rx | −rz | ry |
//! | +Z | +rx | −ry | rz |
//! | −Z | −rx | −ry | rz |
//!
//! `s = sc · (½ / |ma|) + ½`, `t = tc · (½ / |ma|) + ½` (the spec's `(sc / |ma| + 1) / 2`, in
//! the order of operations llvmpipe uses, whose pictures are our references); `t = 0` is the
//! face's first row as uploaded. The spec leaves ties to the implementation: like llvmpipe,
//! z wins over y and y over x when magnitudes are equal (x only when `|rx| > |ry|` and
//! `|rz| < |rx|`). A zero direction reads the centre of +Z.
//!
//! **Filtering** is the 2D sampler's (same fixed-point filter, same per-SIMD dispatch, same
//! texture-cache model and `texture fetch` ledger), within the selected face with
//! clamp-to-edge whatever the sampler's wraps (ES 2.0: "a single cube map face be selected and
//! used for filtering"; ES 3.0 made filtering seamless across faces, which is what llvmpipe
//! does for every ES context that Mesa gives version 3.0 or more — an ES 2 request gets one —
//! so along face edges our bilinear footprints differ from its pictures by half a texel).
//!
//! **Level of detail**, once per 2×2 quad like 2D, from the upper-left pixel (as llvmpipe
//! does): its face's coordinates are differentiated analytically from the quad's direction
//! differences, `∂s/∂x = ½ · (∂sc/∂x − sc · (∂ma/∂x) / ma) / ma` (and the same for `t` and `y`,
//! `ma` signed), scaled by the face size into texels, then `ρ² = max(∂s/∂x² + ∂t/∂x²,
//! ∂s/∂y² + ∂t/∂y²)` and `λ = ½ · log2(ρ²)` as for 2D. Lanes of the quad on other faces use
//! that level of detail too.

use super::*;

/// The largest face size of a cube texture: six faces of this size with every mip level keep
/// the modelled addresses below 2^32, as [`MAX_MODELLED_BYTES`] keeps a 2D texture's.
pub const MAX_CUBE_DIMENSION: u32 = 8192;

const _: () = assert!(6 * chain_modelled_bytes(MAX_CUBE_DIMENSION) <= 1 << 32);

/// The modelled bytes of a `size × size` face with every mip level.
const fn chain_modelled_bytes(size: u32) -> u64 {
    let (mut size, mut total) = (size, 0);
    loop {
        let blocks = size.div_ceil(BLOCK_TEXELS) as u64;
        total += blocks * blocks * BLOCK_BYTES;
        if size == 1 {
            break total;
        }
        size /= 2;
    }
}

/// A face of a cube texture, in GL's order (`GL_TEXTURE_CUBE_MAP_POSITIVE_X + index`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CubeFace {
    PositiveX,
    NegativeX,
    PositiveY,
    NegativeY,
    PositiveZ,
    NegativeZ,
}

impl CubeFace {
    /// The six faces in GL's order.
    pub const ALL: [CubeFace; 6] = [
        CubeFace::PositiveX,
        CubeFace::NegativeX,
        CubeFace::PositiveY,
        CubeFace::NegativeY,
        CubeFace::PositiveZ,
        CubeFace::NegativeZ,
    ];

    /// Its place in GL's order, 0 to 5.
    pub fn index(self) -> usize {
        self as usize
    }
}

/// The major axis of direction `r` (0: x, 1: y, 2: z) with llvmpipe's tie rule (see the module
/// notes).
#[inline(always)]
fn major_axis(r: [f32; 3]) -> usize {
    let (ax, ay, az) = (r[0].abs(), r[1].abs(), r[2].abs());
    if az >= ax.max(ay) {
        2
    } else if ax > ay {
        0
    } else {
        1
    }
}

/// `(sc, tc)` of `r` on the face of major axis `axis` whose `ma` is negative or not (the
/// module's table): a linear map of `r`, so it also maps derivatives of directions.
#[inline(always)]
fn face_plane(axis: usize, negative: bool, r: [f32; 3]) -> (f32, f32) {
    let signed = |c: f32| if negative { -c } else { c };
    match axis {
        0 => (-signed(r[2]), -r[1]),
        1 => (r[0], signed(r[2])),
        _ => (signed(r[0]), -r[1]),
    }
}

/// The face direction `r` selects and its coordinates `(s, t)` on it (see the module notes).
#[inline(always)]
pub fn cube_face_coordinates(r: [f32; 3]) -> (CubeFace, f32, f32) {
    let axis = major_axis(r);
    let ma = r[axis];
    let negative = ma.is_sign_negative();
    let (sc, tc) = face_plane(axis, negative, r);
    let magnitude = ma.abs();
    let half_over_ma = if magnitude > 0.0 { 0.5 / magnitude } else { 0.0 };
    let face = CubeFace::ALL[2 * axis + negative as usize];
    (face, sc * half_over_ma + 0.5, tc * half_over_ma + 0.5)
}

/// The level of detail of a quad before bias, from the directions of its lanes (upper-left,
/// upper-right, lower-left, lower-right) on faces of `size` texels (see the module notes).
#[inline(always)]
fn cube_quad_lod(x: Quad, y: Quad, z: Quad, size: f32) -> f32 {
    let r = [x[0], y[0], z[0]];
    let ddx = [x[1] - x[0], y[1] - y[0], z[1] - z[0]];
    let ddy = [x[2] - x[0], y[2] - y[0], z[2] - z[0]];
    let axis = major_axis(r);
    let ma = r[axis];
    let negative = ma.is_sign_negative();
    let (sc, tc) = face_plane(axis, negative, r);
    let inverse = 1.0 / ma;
    let half_inverse = 0.5 * inverse;
    let derivatives = |d: [f32; 3]| {
        let (dsc, dtc) = face_plane(axis, negative, d);
        let ma_over_ma = d[axis] * inverse;
        ((dsc - ma_over_ma * sc) * half_inverse * size, (dtc - ma_over_ma * tc) * half_inverse * size)
    };
    let ((dsdx, dtdx), (dsdy, dtdy)) = (derivatives(ddx), derivatives(ddy));
    let rho_squared = (dsdx * dsdx + dtdx * dtdx).max(dsdy * dsdy + dtdy * dtdy);
    lod_of_rho_squared(rho_squared)
}

impl Texture {
    /// A cube texture from six `size × size` RGBA8 faces in GL's order ([`CubeFace::ALL`]),
    /// rows in GL's order (row 0 is `t = 0`), each with the mip chain `mips` builds.
    ///
    /// # Errors
    /// A zero size or one above [`MAX_CUBE_DIMENSION`], or a face not `size × size × 4` bytes
    /// long (the error names the face).
    pub fn cube_from_rgba8(size: u32, faces: [&[u8]; 6], color_space: ColorSpace, mips: MipChain) -> Result<Texture> {
        check_cube_size(size)?;
        let faces = faces
            .iter()
            .enumerate()
            .map(|(i, rgba)| Texture::from_rgba8(size, size, rgba, color_space, mips).map_err(|e| face_error(i, e)));
        Texture::cube_of(faces.collect::<Result<Vec<_>>>()?)
    }

    /// A cube texture whose faces' mip chains are given (`faces[face][level]`, as
    /// [`Texture::from_rgba8_levels`] takes one), faces in GL's order.
    ///
    /// # Errors
    /// As [`Texture::cube_from_rgba8`], and a face's chain as `from_rgba8_levels` refuses it.
    pub fn cube_from_rgba8_levels(size: u32, faces: [&[&[u8]]; 6], color_space: ColorSpace) -> Result<Texture> {
        check_cube_size(size)?;
        let faces = faces.iter().enumerate().map(|(i, levels)| {
            Texture::from_rgba8_levels(size, size, levels, color_space).map_err(|e| face_error(i, e))
        });
        Texture::cube_of(faces.collect::<Result<Vec<_>>>()?)
    }

    /// The six faces (each built as a 2D texture of the same size and chain) as one cube
    /// texture: their texels one face after the other.
    fn cube_of(faces: Vec<Texture>) -> Result<Texture> {
        debug_assert_eq!(faces.len(), 6);
        let mut faces = faces.into_iter();
        let mut cube = faces.next().expect("six faces");
        let face_texels = cube.texels.len();
        for face in faces {
            debug_assert_eq!(face.texels.len(), face_texels);
            cube.texels.extend(&face.texels);
        }
        cube.face_bytes = Some((face_texels as u64 * TEXEL_BYTES) as u32);
        Ok(cube)
    }

    /// Whether it is a cube texture.
    pub fn is_cube(&self) -> bool {
        self.face_bytes.is_some()
    }

    /// Texel `(x, y)` of `level` of cube face `face` (rows in GL's order).
    pub fn face_texel(&self, face: CubeFace, level: usize, x: u32, y: u32) -> [u8; 4] {
        let l = &self.levels[level];
        debug_assert!(x < l.width && y < l.height);
        self.texel_bytes(self.face_offset(face) as usize / TEXEL_BYTES as usize + l.texel_index(x, y))
    }

    /// The modelled address of texel `(x, y)` of `level` of cube face `face` (see
    /// [`Texture::texel_address`]).
    pub fn face_texel_address(&self, face: CubeFace, level: usize, x: u32, y: u32) -> u64 {
        self.texel_address(level, x, y) + self.face_offset(face) as u64
    }

    /// Where face `face` starts in the modelled memory, relative to the texture.
    fn face_offset(&self, face: CubeFace) -> u32 {
        self.face_bytes.unwrap_or(0) * face.index() as u32
    }

    /// Samples a cube texture in the eight lanes' directions `(x, y, z)` (need not be
    /// normalised) with the instruction set of `simd`, as [`Texture::sample`] samples a 2D
    /// one: the same bits at every SIMD level, reads of the `counted` lanes through `cache`.
    /// The sampler's wraps are not used (clamp-to-edge within the face, see the module notes).
    #[inline]
    pub fn sample_cube(
        &self,
        simd: SimdSupport,
        sampler: &Sampler,
        direction: [F32x8; 3],
        counted: LaneMask,
        cache: &mut TextureCache,
    ) -> Vec4x8 {
        debug_assert!(self.is_cube(), "sample_cube of a 2D texture");
        sample_cube_group(simd, self, sampler, direction, counted, cache)
    }

    /// [`Texture::sample_cube`]'s body.
    #[inline(always)]
    fn sample_cube_quads(
        &self,
        simd: SimdSupport,
        sampler: &Sampler,
        direction: [F32x8; 3],
        counted: LaneMask,
        cache: &mut TextureCache,
    ) -> Vec4x8 {
        let sampler = sampler.with_wrap(Wrap::ClampToEdge);
        let size = self.width() as f32;
        let mut quads = [[[0u32; 4]; 4]; 2];
        for (quad, lanes) in QUAD_LANES.iter().enumerate() {
            let [x, y, z] = direction.map(|c| super::lanes(|i| c.lane(lanes[i])));
            let lambda = cube_quad_lod(x, y, z, size) + sampler.lod_bias;
            let at = self.cube_quad_at(x, y, z);
            let counted = lanes.map(|lane| counted.contains(lane));
            let minified_unmipped = sampler.mipmap == MipmapMode::None && lambda > super::UNMIPPED_LOD;
            quads[quad] = self.sample_quad::<false>(simd, &sampler, lambda, &at, counted, minified_unmipped, cache);
        }
        group_of_quads(quads, self.holds_bytes())
    }

    /// Where a quad's directions land: each lane's face and its coordinates, reduced.
    #[inline(always)]
    fn cube_quad_at(&self, x: Quad, y: Quad, z: Quad) -> QuadAt {
        let selected = super::lanes(|i| {
            let (face, s, t) = cube_face_coordinates([x[i], y[i], z[i]]);
            (self.face_offset(face), s, t)
        });
        QuadAt {
            u: reduce_quad(selected.map(|(_, s, _)| s), Wrap::ClampToEdge),
            v: reduce_quad(selected.map(|(_, _, t)| t), Wrap::ClampToEdge),
            face_offsets: selected.map(|(offset, _, _)| offset),
            offset: [0, 0],
            // A face is clamped to its edges, so the texels alone decide (see
            // `Texture::filters_bytes`).
            bytes: self.holds_bytes(),
        }
    }

    /// Samples a cube texture in one direction at the level of detail `lambda` given by the
    /// caller (bias added), as [`Texture::sample_lod`] samples a 2D one (what `textureCubeLod`
    /// and a vertex shader's `textureCube` read). Reads are not counted in the ledger.
    pub fn sample_cube_lod(&self, sampler: &Sampler, direction: [f32; 3], lambda: f32) -> [f32; 4] {
        debug_assert!(self.is_cube(), "sample_cube_lod of a 2D texture");
        let sampler = sampler.with_wrap(Wrap::ClampToEdge);
        let [x, y, z] = direction.map(|c| [c; 4]);
        self.sample_point(&sampler, &self.cube_quad_at(x, y, z), lambda)
    }
}

per_simd_level! {
    /// [`Texture::sample_cube`], compiled once per SIMD level (as `sample_group`).
    fn sample_cube_group / sample_cube_group_avx2 => sample_cube_group_body, simd: simd, (
        simd: SimdSupport,
        texture: &Texture,
        sampler: &Sampler,
        direction: [F32x8; 3],
        counted: LaneMask,
        cache: &mut TextureCache,
    ) -> Vec4x8
}

#[inline(always)]
fn sample_cube_group_body(
    simd: SimdSupport,
    texture: &Texture,
    sampler: &Sampler,
    direction: [F32x8; 3],
    counted: LaneMask,
    cache: &mut TextureCache,
) -> Vec4x8 {
    texture.sample_cube_quads(simd, sampler, direction, counted, cache)
}

fn check_cube_size(size: u32) -> Result<()> {
    if size == 0 || size > MAX_CUBE_DIMENSION {
        return Err(Error::invalid(
            "cube texture",
            format!("face size {size}×{size} must be from 1×1 to {MAX_CUBE_DIMENSION}×{MAX_CUBE_DIMENSION}"),
        ));
    }
    Ok(())
}

fn face_error(face: usize, error: Error) -> Error {
    Error::invalid("cube texture", format!("face {:?}: {error}", CubeFace::ALL[face]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shade::texture_cache::TextureCacheConfig;

    /// Face `i` of `size`: texel `(x, y)` is `(x, y, 40 · i, 255)`.
    fn face_texels(i: usize, size: u32) -> Vec<u8> {
        (0..size * size).flat_map(|p| [(p % size) as u8, (p / size) as u8, 40 * i as u8, 255]).collect()
    }

    fn cube(size: u32, mips: MipChain) -> Texture {
        let faces: Vec<Vec<u8>> = (0..6).map(|i| face_texels(i, size)).collect();
        let faces: [&[u8]; 6] = std::array::from_fn(|i| faces[i].as_slice());
        Texture::cube_from_rgba8(size, faces, ColorSpace::Linear, mips).unwrap()
    }

    #[test]
    fn face_selection_follows_the_spec_table() {
        // Hand-computed from §3.7.5: (direction) → face, s = (sc/|ma| + 1)/2, t = (tc/|ma| + 1)/2.
        let cases = [
            // +X: sc = −rz, tc = −ry: (2, 1, 0.5) → sc −0.5, tc −1 → s 0.375, t 0.25.
            ([2.0, 1.0, 0.5], CubeFace::PositiveX, 0.375, 0.25),
            // −X: sc = +rz, tc = −ry: (−4, −2, 1) → 0.625, 0.75.
            ([-4.0, -2.0, 1.0], CubeFace::NegativeX, 0.625, 0.75),
            // +Y: sc = +rx, tc = +rz: (0.5, 1, −0.25) → 0.75, 0.375.
            ([0.5, 1.0, -0.25], CubeFace::PositiveY, 0.75, 0.375),
            // −Y: sc = +rx, tc = −rz: (0.5, −2, −1) → 0.625, 0.75.
            ([0.5, -2.0, -1.0], CubeFace::NegativeY, 0.625, 0.75),
            // +Z: sc = +rx, tc = −ry: (−1, 0.5, 2) → 0.25, 0.375.
            ([-1.0, 0.5, 2.0], CubeFace::PositiveZ, 0.25, 0.375),
            // −Z: sc = −rx, tc = −ry: (−1, 0.5, −2) → 0.75, 0.375.
            ([-1.0, 0.5, -2.0], CubeFace::NegativeZ, 0.75, 0.375),
            // Ties: z over y over x, as llvmpipe.
            ([1.0, 1.0, 1.0], CubeFace::PositiveZ, 1.0, 0.0),
            ([1.0, -1.0, 0.5], CubeFace::NegativeY, 1.0, 0.25),
            // A zero direction: the centre of +Z.
            ([0.0, 0.0, 0.0], CubeFace::PositiveZ, 0.5, 0.5),
        ];
        for (r, face, s, t) in cases {
            assert_eq!(cube_face_coordinates(r), (face, s, t), "{r:?}");
        }
    }

    #[test]
    fn a_direction_reads_its_face_texel() {
        let t = cube(4, MipChain::Box);
        let nearest = Sampler::NEAREST_REPEAT;
        // +X at s 0.375, t 0.25 of a 4×4 face: texel (1, 1).
        assert_eq!(
            t.sample_cube_lod(&nearest, [2.0, 1.0, 0.5], 0.0),
            [1.0, 1.0, 0.0, 255.0].map(|c| c * (1.0 / 255.0))
        );
        // −Z at (0.75, 0.375): texel (3, 1) of face 5.
        let c = t.sample_cube_lod(&nearest, [-1.0, 0.5, -2.0], 0.0);
        assert_eq!(c, [3.0, 1.0, 200.0, 255.0].map(|c| c * (1.0 / 255.0)));
        assert_eq!(t.face_texel(CubeFace::NegativeZ, 0, 3, 1), [3, 1, 200, 255]);
        // Bilinear clamps within the face: at the +Y face's corner s = 1, t = 0 the edge texel
        // (3, 0) alone, never a texel of a neighbour face.
        let c = t.sample_cube_lod(&Sampler::BILINEAR_CLAMP, [1.0, 1.0, -1.0 + f32::EPSILON], 0.0);
        assert_eq!(c, [3.0, 0.0, 80.0, 255.0].map(|c| c * (1.0 / 255.0)));
        // Level 1 with a mip filter: face 2's 2×2 level.
        let mip = Sampler { mipmap: MipmapMode::Nearest, ..Sampler::NEAREST_REPEAT };
        let level1 = t.sample_cube_lod(&mip, [0.1, 1.0, 0.1], 1.0);
        let [r, g, b, a] = t.face_texel(CubeFace::PositiveY, 1, 1, 1);
        assert_eq!(level1, [r, g, b, a].map(|c| c as f32 * (1.0 / 255.0)));
    }

    #[test]
    fn a_face_samples_as_the_same_2d_texture_clamped() {
        let size = 8;
        let t = cube(size, MipChain::Box);
        let mut cache = TextureCache::default();
        for face in CubeFace::ALL {
            let flat =
                Texture::from_rgba8(size, size, &face_texels(face.index(), size), ColorSpace::Linear, MipChain::Box)
                    .unwrap();
            for (s, tt) in [(0.3f32, 0.7f32), (0.01, 0.99), (0.5, 0.5), (0.93, 0.12)] {
                // The direction of (s, t) on `face`, from the table: sc = 2s − 1, tc = 2t − 1.
                let (sc, tc) = (2.0 * s - 1.0, 2.0 * tt - 1.0);
                let r = match face {
                    CubeFace::PositiveX => [1.0, -tc, -sc],
                    CubeFace::NegativeX => [-1.0, -tc, sc],
                    CubeFace::PositiveY => [sc, 1.0, tc],
                    CubeFace::NegativeY => [sc, -1.0, -tc],
                    CubeFace::PositiveZ => [sc, -tc, 1.0],
                    CubeFace::NegativeZ => [-sc, -tc, -1.0],
                };
                let (selected, fs, ft) = cube_face_coordinates(r);
                assert_eq!(selected, face);
                assert!((fs - s).abs() < 1e-6 && (ft - tt).abs() < 1e-6, "{face:?} {s} {tt}: {fs} {ft}");
                let clamp = Sampler::TRILINEAR_REPEAT.with_wrap(Wrap::ClampToEdge);
                for lambda in [0.0, 0.6, 1.5, 9.0] {
                    let want = flat.sample_lod(&clamp, fs, ft, lambda);
                    // The cube ignores the sampler's wraps: repeat gives clamp-to-edge.
                    assert_eq!(t.sample_cube_lod(&Sampler::TRILINEAR_REPEAT, r, lambda), want, "{face:?} λ {lambda}");
                }
                // A whole group in that direction (no derivatives: level 0 magnified).
                let group =
                    t.sample_cube(SimdSupport::BASELINE, &clamp, r.map(F32x8::splat), LaneMask::ALL, &mut cache);
                let want = flat.sample_lod(&clamp, fs, ft, 0.0);
                assert_eq!([0, 1, 2, 3].map(|c| group[c].lane(5)), want);
            }
        }
    }

    #[test]
    fn level_of_detail_from_face_coordinate_derivatives() {
        // On +Z at the centre, x steps of 2/64 per pixel move s by 1/64: one texel of a 64
        // face (λ 0), two of a 128 face (λ 1); rz growing does not move s at the centre.
        let centre = |step: f32| {
            let x = super::super::lanes(|i| [0.0, step, 0.0, step][i]);
            let y = [0.0; 4];
            let z = super::super::lanes(|i| [1.0, 1.0, 1.0 + step, 1.0 + step][i]);
            (x, y, z)
        };
        let (x, y, z) = centre(2.0 / 64.0);
        assert!(cube_quad_lod(x, y, z, 64.0).abs() < 1e-6);
        assert!((cube_quad_lod(x, y, z, 128.0) - 1.0).abs() < 1e-6);
        // Off centre, ma changing shrinks the step: at s = 0.75 (rx = 0.5, rz = 1), moving rz
        // by 1/64 per pixel moves s by −½ · 0.5 · (1/64) = −1/256: 0.25 texel of 64, λ −2.
        let x = [0.5; 4];
        let z = super::super::lanes(|i| [1.0, 1.0 + 1.0 / 64.0, 1.0, 1.0][i]);
        assert!((cube_quad_lod(x, [0.0; 4], z, 64.0) + 2.0).abs() < 1e-4, "{}", cube_quad_lod(x, [0.0; 4], z, 64.0));
    }

    #[test]
    fn the_ledger_counts_cube_texel_fetches() {
        // 4×4 faces: each face's level 0 is one 64-byte block (one line of the default cache).
        let t = cube(4, MipChain::BaseOnly);
        let mut cache = TextureCache::new(TextureCacheConfig::DEFAULT);
        let centres =
            [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, -1.0]];
        for r in centres {
            let direction = r.map(F32x8::splat);
            // One counted lane, bilinear: four texel reads of one line.
            t.sample_cube(SimdSupport::BASELINE, &Sampler::BILINEAR_CLAMP, direction, LaneMask(1), &mut cache);
        }
        // Six faces, six lines: 6 misses of 64 bytes, 3 hits each.
        assert_eq!((cache.misses(), cache.hits()), (6, 18));
        assert_eq!(cache.take_fetched_bytes(), 6 * 64);
        // Faces sit one after the other: face 5 starts 5 face chains after face 0.
        let face_bytes = 64;
        assert_eq!(
            t.face_texel_address(CubeFace::NegativeZ, 0, 0, 0) - t.face_texel_address(CubeFace::PositiveX, 0, 0, 0),
            5 * face_bytes
        );
        // Again: all hits, nothing fetched.
        for r in centres {
            t.sample_cube(
                SimdSupport::BASELINE,
                &Sampler::BILINEAR_CLAMP,
                r.map(F32x8::splat),
                LaneMask(1),
                &mut cache,
            );
        }
        assert_eq!((cache.misses(), cache.hits()), (6, 42));
        assert_eq!(cache.take_fetched_bytes(), 0);
    }

    #[test]
    fn every_simd_level_samples_the_same_bits() {
        let t = cube(16, MipChain::Box);
        let levels: Vec<SimdSupport> = [crate::simd::SimdLevel::Baseline, crate::simd::SimdLevel::Avx2]
            .into_iter()
            .filter_map(SimdSupport::detect)
            .collect();
        for seed in 0..64u32 {
            let f = |k: u32| ((seed * 7 + k * 13) % 17) as f32 / 8.0 - 1.0;
            // Directions sweeping across faces, with derivatives of every size.
            let direction = [0, 1, 2].map(|c| {
                F32x8::from_fn(|i| f(c) + (LANE_DX[i] as f32 * f(c + 3) + LANE_DY[i] as f32 * f(c + 6)) * 0.05)
            });
            let mut results = levels.iter().map(|&simd| {
                let mut cache = TextureCache::default();
                let c = t.sample_cube(simd, &Sampler::TRILINEAR_REPEAT, direction, LaneMask::ALL, &mut cache);
                (c.map(|c| c.to_array().map(f32::to_bits)), cache.misses(), cache.hits())
            });
            let first = results.next().unwrap();
            for other in results {
                assert_eq!(other, first);
            }
        }
    }

    #[test]
    fn bad_cube_faces_are_refused_naming_the_face() {
        let good = face_texels(0, 4);
        let short = vec![0u8; 4 * 4 * 4 - 1];
        let error =
            Texture::cube_from_rgba8(4, [&good, &good, &good, &short, &good, &good], ColorSpace::Linear, MipChain::Box)
                .unwrap_err();
        assert!(error.to_string().contains("NegativeY"), "{error}");
        assert!(Texture::cube_from_rgba8(0, [&good; 6], ColorSpace::Linear, MipChain::Box).is_err());
        assert!(
            Texture::cube_from_rgba8(MAX_CUBE_DIMENSION + 1, [&good; 6], ColorSpace::Linear, MipChain::Box).is_err()
        );
    }
}
