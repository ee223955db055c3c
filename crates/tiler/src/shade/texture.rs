//! Textures and samplers: images with mip chains, stored in any `TexelFormat` and decoded to
//! RGBA8 when made (`shade::texel_format`), sampled eight lanes at a time with
//! nearest, bilinear or trilinear filtering, repeat / clamp-to-edge / mirrored-repeat wraps and
//! a level of detail from 2×2 quad derivatives. Every texel read goes through the texture cache
//! model (`shade::texture_cache`), which decides what the ledger counts.
//!
//! The rules follow the OpenGL 4.6 specification, §8.14 "Texture Minification" and §8.15
//! "Texture Magnification", which Vulkan's filtering matches:
//!
//! - **Level of detail**, once per 2×2 quad (as llvmpipe computes it by default, and as the GL
//!   spec allows: "implementations may approximate"): with `s = u · width`, `t = v · height` in
//!   texels of level 0 and the quad's upper-left pixel's differences to its right and lower
//!   neighbours, `ρ² = max(ds/dx² + dt/dx², ds/dy² + dt/dy²)` and `λ = ½ · log2(ρ²) + bias`.
//!   Using one λ per quad costs nothing in accuracy the eye can see and keeps the four pixels
//!   of a quad on the same levels.
//! - **Magnification or minification**: `λ ≤ c` magnifies (the magnification filter on level
//!   0), where `c = 0.5` when magnification is linear and minification is
//!   `NEAREST_MIPMAP_*`, else `c = 0`.
//! - **Mip level**: none — level 0; nearest — `d = ⌈λ + ½⌉ − 1` (0 when `λ ≤ ½`); linear — levels
//!   `⌊λ⌋` and `⌊λ⌋ + 1` blended by the 8-bit weight `⌊256 · (λ − ⌊λ⌋)⌋`; both clamped to the
//!   last level.
//! - **Texel coordinates** of level `(w, h)`: nearest takes texel `⌊u · w⌋`; linear takes
//!   `i0 = ⌊u · w − ½⌋`, `i1 = i0 + 1` weighted by the 8-bit `α = ⌊256 · frac(u · w − ½)⌋` (and
//!   the same in v), `c = lerp(lerp(t00, t10, α), lerp(t01, t11, α), β)`.
//! - **Wraps** act on integer texel indices `i` of an axis of `n` texels: repeat `i mod n`,
//!   clamp-to-edge `clamp(i, 0, n − 1)`, mirrored repeat `m = i mod 2n; m < n ? m : 2n − 1 − m`.
//!   Before scaling, repeat takes `u − ⌊u⌋` and mirrored repeat `u mod 2` (exact in f32), so
//!   large coordinates keep their sub-texel precision.
//! - **Colour**: texel values are UNORM8 (`c / 255`); sRGB textures decode their colour
//!   channels to linear before filtering (alpha stays linear), as GPUs do.
//!
//! **Filtering is fixed point**, as GPUs and llvmpipe filter RGBA8, in one of two forms:
//!
//! - **Bytes** (textures held as RGBA8 bytes — linear colour space, 8-bit channels — with
//!   repeat or clamp-to-edge wraps; `Texture::filters_bytes`): llvmpipe's AoS sampler
//!   (`lp_bld_sample_aos.c`) to the bit. A linear coordinate is fixed point in 1/256 texel,
//!   `P = round(256 · fl(r · n)) − 128` (to nearest, ties to even; `r` reduced as below, `n`
//!   the level's size), `i0 = P >> 8`, `i1 = i0 + 1` and the weight `α = P & 255` (the rule
//!   above gives `⌊256 · frac(r · n − ½)⌋` instead, which differs by the rounding); each
//!   `lerp(a, b, w) = a + ((b − a) · w + 128) >> 8` is on bytes and rounds to a byte (what
//!   `pmulhrsw` of `w` and `(b − a) << 7` gives); the two levels of a trilinear lookup blend
//!   by the same lerp; and a byte `c` becomes `c · fl(1/255)` in `f32` (one multiplication,
//!   as `lp_build_unsigned_norm_to_float` converts; within an ulp of `c / 255`, not always
//!   it). Nearest texels of such textures convert the same way. `tools/float-probe`'s
//!   `filter.frag` and `filter-lod.frag` hold it to llvmpipe's bits (test
//!   `float_probe_linear_filter_is_llvmpipes_to_the_bit`). At the AVX2 level a pair's filter
//!   runs in 16-bit lanes (`avx2::filter_bytes`), the same bits.
//! - **Sixteen bits** (sRGB textures, 16-bit textures without a chain, mirrored repeat —
//!   where llvmpipe filters in floats): every channel is a 16-bit UNORM (`c · 257` for a UNORM8
//!   byte, which is `c / 255` exactly; `round(65535 · linear)` for an sRGB colour channel), the
//!   weights are 8 bits (`w / 256`, `w ∈ [0, 256)`), and each `lerp` (the formula above)
//!   rounds to 16 bits — no rounding to 8 bits in between, so a gradient filtered from bytes
//!   keeps its steps. The result is `c / 65535` in `f32` (correctly rounded). Sixteen bits
//!   and 8-bit weights keep every product below 2^24: the lanes are 32-bit integers, whose
//!   operations every SIMD level has. 3-D textures filter their slices this way too.
//!
//! Coordinate arithmetic is plain IEEE single precision per lane, no fused multiply-add, and
//! the logarithm is computed here from basic operations rather than by the platform's `log2f`,
//! so a lane's result depends only on its quad's inputs: every backend, tile size, thread
//! count and SIMD level samples the same values.

mod array;
mod cube;
mod fetch;
mod volume;

use std::sync::atomic::{AtomicU64, Ordering};

pub use array::{LayeredKind, MAX_ARRAY_LAYERS, MAX_VOLUME_DIMENSION};
pub use cube::{CubeFace, MAX_CUBE_DIMENSION, cube_face_coordinates};
pub use fetch::{IntegerKind, IntegerTexture};

use super::texel_format::{StoredLayout, TexelFormat};
use super::texture_cache::{MAX_LANE_LINES, TextureCache};
use crate::api::error::{Error, Result};
use crate::api::format::{linear_to_srgb, srgb8_to_linear, unorm8};
use crate::simd::{F32x8, LANE_DX, LANE_DY, LaneMask, SimdLevel, SimdSupport, Vec4x8, per_simd_level};
// `lanes(f)`: `[f(0), …, f(N − 1)]` as a plain loop the vectoriser sees through, for a quad's
// four lanes or a pair of quads' eight (`PAIR_LANES`).
use crate::simd::array_from_fn as lanes;

/// The largest width or height of a texture.
pub const MAX_TEXTURE_DIMENSION: u32 = 16384;

/// Bytes per texel (RGBA8).
pub const TEXEL_BYTES: u64 = 4;

/// Modelled storage: 4×4 texels per block, blocks in row-major order.
const BLOCK_TEXELS: u32 = 4;
const BLOCK_BYTES: u64 = (BLOCK_TEXELS * BLOCK_TEXELS) as u64 * TEXEL_BYTES;

/// The modelled bytes of the largest texture, `MAX_TEXTURE_DIMENSION` squared with every mip
/// level (about 4/3 GiB). A level's bytes grow with its width and height, so every texture's
/// modelled addresses, relative to its own, fit in 32 bits — and so do its texel indices
/// (a quarter of the bytes).
const MAX_MODELLED_BYTES: u64 = {
    let (mut width, mut height, mut total) = (MAX_TEXTURE_DIMENSION, MAX_TEXTURE_DIMENSION, 0);
    loop {
        total += width.div_ceil(BLOCK_TEXELS) as u64 * height.div_ceil(BLOCK_TEXELS) as u64 * BLOCK_BYTES;
        if width == 1 && height == 1 {
            break total;
        }
        (width, height) = (if width > 1 { width / 2 } else { 1 }, if height > 1 { height / 2 } else { 1 });
    }
};
const _: () = assert!(MAX_MODELLED_BYTES <= 1 << 32);

/// How the colour channels of a texture are encoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ColorSpace {
    /// Values are used as stored (`c / 255`).
    Linear,
    /// Red, green and blue are sRGB-encoded and decoded to linear before filtering.
    Srgb,
}

/// Which mip levels a texture gets.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MipChain {
    /// Level 0 only.
    BaseOnly,
    /// Levels down to 1×1, each a 2×2 box filter of the one above: level `i + 1` is
    /// `max(1, ⌊w/2⌋) × max(1, ⌊h/2⌋)`, texel `(x, y)` the average of texels `(2x, 2y)`,
    /// `(2x+1, 2y)`, `(2x, 2y+1)`, `(2x+1, 2y+1)` of level `i`, coordinates clamped to the last
    /// row and column. Linear textures average the stored bytes exactly as SCENES.md §4.2
    /// builds its chain: `(a + b + c + d + 2) >> 2` per channel. sRGB textures average their
    /// colour in linear light (decode, mean, encode, round to nearest) and alpha as above.
    Box,
    /// Levels down to 1×1 of the same sizes as [`MipChain::Box`], each texel a bilinear sample
    /// of the level above at the texel's centre: what Mesa's `glGenerateMipmap` does (a
    /// linear-filtered blit from level to level), and so what a GL application's mip maps look
    /// like on llvmpipe. Along a side of `w` texels halved to `n`, texel `x` blends texels
    /// `⌊s⌋` and `⌊s⌋ + 1` at `s = (x + ½) · w / n − ½` with an 8-bit weight (round to
    /// nearest of the fraction · 256; 128 where the side halves exactly), so a 3-texel row
    /// halves to its middle texel and a 75-texel one weighs its neighbours unevenly, where the
    /// box would drop the last texel. Linear textures blend bytes as llvmpipe's AoS sampler
    /// does (see the module notes): each row's two texels, then the two rows, each lerp
    /// rounded to a byte — so where a side halves exactly, `lerp(lerp(a, b), lerp(c, d))` at
    /// weight 128, which is not the box's `(a + b + c + d + 2) >> 2` in about 4% of texels
    /// (every level of glmark2 refract's 1600×1200 chain, dumped from llvmpipe, is this to the
    /// byte). sRGB textures blend in linear light, in floats.
    Linear,
}

/// A texture filter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Filter {
    Nearest,
    Linear,
}

/// How mip levels are chosen when minifying.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MipmapMode {
    /// Level 0 only (GL `NEAREST` / `LINEAR` minification).
    None,
    /// The nearest level (GL `*_MIPMAP_NEAREST`).
    Nearest,
    /// The two nearest levels, blended (GL `*_MIPMAP_LINEAR`).
    Linear,
}

/// What happens to coordinates outside `[0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Wrap {
    Repeat,
    ClampToEdge,
    MirroredRepeat,
}

impl Wrap {
    /// Any integer texel index along an axis of `n` texels (`n ≥ 1`), wrapped: GL's
    /// `wrap(i)` (OpenGL ES 3.0 §3.8.10). The filters wrap reduced coordinates their own,
    /// cheaper way (`wrap_reduced`); this is for texel indices from elsewhere
    /// (`textureGather`) and the tests' reference.
    pub fn texel(self, i: i64, n: u32) -> u32 {
        let n = n as i64;
        let wrapped = match self {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::ClampToEdge => i.clamp(0, n - 1),
            Wrap::MirroredRepeat => {
                let m = i.rem_euclid(2 * n);
                if m < n { m } else { 2 * n - 1 - m }
            }
        };
        wrapped as u32
    }
}

/// How a texture is filtered and wrapped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sampler {
    pub mag_filter: Filter,
    pub min_filter: Filter,
    pub mipmap: MipmapMode,
    pub wrap_u: Wrap,
    pub wrap_v: Wrap,
    /// The third coordinate's wrap (GL's `WRAP_R`): read by 3-D textures only.
    pub wrap_w: Wrap,
    /// Added to the computed level of detail.
    pub lod_bias: f32,
}

impl Sampler {
    /// Trilinear, repeat in both directions (GL `LINEAR_MIPMAP_LINEAR`, `REPEAT`): what
    /// SCENES.md uses for every texture.
    pub const TRILINEAR_REPEAT: Sampler = Sampler {
        mag_filter: Filter::Linear,
        min_filter: Filter::Linear,
        mipmap: MipmapMode::Linear,
        wrap_u: Wrap::Repeat,
        wrap_v: Wrap::Repeat,
        wrap_w: Wrap::Repeat,
        lod_bias: 0.0,
    };
    /// Bilinear on level 0, clamped to the edges.
    pub const BILINEAR_CLAMP: Sampler = Sampler {
        mag_filter: Filter::Linear,
        min_filter: Filter::Linear,
        mipmap: MipmapMode::None,
        wrap_u: Wrap::ClampToEdge,
        wrap_v: Wrap::ClampToEdge,
        wrap_w: Wrap::ClampToEdge,
        lod_bias: 0.0,
    };
    /// Nearest texel of level 0, repeat.
    pub const NEAREST_REPEAT: Sampler = Sampler {
        mag_filter: Filter::Nearest,
        min_filter: Filter::Nearest,
        mipmap: MipmapMode::None,
        wrap_u: Wrap::Repeat,
        wrap_v: Wrap::Repeat,
        wrap_w: Wrap::Repeat,
        lod_bias: 0.0,
    };

    /// The same sampler with both wraps set to `wrap`.
    pub fn with_wrap(self, wrap: Wrap) -> Sampler {
        Sampler { wrap_u: wrap, wrap_v: wrap, ..self }
    }
}

/// One mip level: its size, where its decoded texels start in the texture's texels (× 4:
/// `address`, the modelled address of an RGBA8 texture) and where the texture's format stores
/// it in the modelled memory (`stored_address`, see `texture_cache` and [`StoredLayout`]),
/// both relative to the texture's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Level {
    pub width: u32,
    pub height: u32,
    address: u64,
    blocks_x: u32,
    stored_address: u64,
    /// The stored format's blocks across.
    stored_blocks_x: u32,
}

/// What to read for one quad: one level, or two levels blended.
#[derive(Clone, Copy, Debug, PartialEq)]
enum LevelPlan {
    Single {
        level: usize,
        filter: Filter,
    },
    /// `weight`: the 8-bit weight of `level + 1` (see the module notes).
    Blend {
        level: usize,
        filter: Filter,
        weight: u32,
    },
}

/// A texture with its mip chain, decoded to RGBA8, modelled as stored in its [`TexelFormat`].
#[derive(Clone, Debug)]
pub struct Texture {
    id: u64,
    color_space: ColorSpace,
    format: TexelFormat,
    layout: StoredLayout,
    levels: Vec<Level>,
    /// Every level's texels, level after level, in the modelled layout (`texture_cache`): 4×4
    /// blocks of 16 texels row-major, blocks row-major, so that texel `(x, y)` of a level is at
    /// its modelled address / 4 and a block is one 64-byte line of the host's caches too — a
    /// quad's footprint reads one or two of them, not rows kilobytes apart. Texels of the
    /// blocks past a level's right or bottom edge are zero and never read.
    ///
    /// How each texel is held: see [`Texels`]. This is the host's layout only: the modelled
    /// memory, and so the ledger, hold the texture's RGBA8 (or stored-format) bytes, whose
    /// addresses the cache model reads.
    texels: Texels,
    /// UNORM8 → the filter's 16-bit UNORM for the colour channels (see the module notes):
    /// `c · 257`, or the linear value of sRGB `c` when the texture is sRGB. Strictly
    /// increasing, so a decoded channel gives its byte back ([`Texture::texel_bytes`]).
    /// [`Texels::Decoded`] holds channels through it; [`Texels::Packed`] needs none.
    color_table: Box<[u16; 256]>,
    /// A cube texture's six faces (`cube`), each a chain laid out as `levels` say, one after
    /// the other `face_bytes` apart in the modelled memory; `None` for a 2D texture.
    face_bytes: Option<u32>,
    /// A 2-D array's layers or a 3-D texture's slices (`array`, `volume`); `None` otherwise.
    layers: Option<array::Layers>,
}

/// The level of detail (bias included) above which a quad read from level 0 without mip maps
/// is counted as minified ([`TextureCache::note_unmipped`]): more than 2× texels per pixel
/// along an axis, where a bilinear footprint stops sharing lines with its neighbours. Told
/// as `ρ² > 4^(UNMIPPED_LOD − bias)`.
const UNMIPPED_LOD: f32 = 1.0;

/// The `ρ²` above which a quad of `sampler` is minified more than [`UNMIPPED_LOD`] allows
/// without mip maps: `4^(UNMIPPED_LOD − bias)`.
#[inline(always)]
fn unmipped_rho_squared(sampler: &Sampler) -> f32 {
    if sampler.lod_bias == 0.0 { 4f32.powi(UNMIPPED_LOD as i32) } else { 4f32.powf(UNMIPPED_LOD - sampler.lod_bias) }
}

/// Hands out texture ids, the only process-wide state of the sampler: ids only make cache tags
/// of different textures differ, so their values never change a count.
static NEXT_TEXTURE_ID: AtomicU64 = AtomicU64::new(1);

impl Texture {
    /// A texture from `width × height` RGBA8 texels, rows top to bottom (row 0 is `v = 0`).
    ///
    /// # Errors
    /// A zero or too large size, or `rgba` not `width × height × 4` bytes long.
    pub fn from_rgba8(
        width: u32,
        height: u32,
        rgba: &[u8],
        color_space: ColorSpace,
        mips: MipChain,
    ) -> Result<Texture> {
        Texture::rgba8_in(width, height, rgba, color_space, mips, None)
    }

    /// [`Texture::from_rgba8`] of a texture that replaces `old`: a base-only one is built in
    /// `old`'s texel memory rather than in new memory. A render target sampled frame after
    /// frame is built again each frame, and writing fresh pages (a fault each, ten times the
    /// cost of the write) was most of an 800×600 build. The texture is the one
    /// [`Texture::from_rgba8`] makes (its own id too); only where its texels live differs.
    ///
    /// # Errors
    /// As [`Texture::from_rgba8`].
    pub fn from_rgba8_replacing(
        width: u32,
        height: u32,
        rgba: &[u8],
        color_space: ColorSpace,
        mips: MipChain,
        old: Texture,
    ) -> Result<Texture> {
        Texture::rgba8_in(width, height, rgba, color_space, mips, Some(old.texels))
    }

    /// [`Texture::from_rgba8`], a base-only texture's texels held in `spare`'s memory
    /// ([`Texture::store_in`]).
    fn rgba8_in(
        width: u32,
        height: u32,
        rgba: &[u8],
        color_space: ColorSpace,
        mips: MipChain,
        spare: Option<Texels>,
    ) -> Result<Texture> {
        check_base(width, height, rgba)?;
        let (texels, _) = rgba.as_chunks::<4>();
        if mips == MipChain::BaseOnly {
            // No chain to build: stored straight from the caller's bytes, not copied first
            // (a render target sampled pass after pass is built this way each time).
            let levels = vec![Level::new(width, height, 0)];
            return Ok(Texture::store_in(TexelFormat::Rgba8, texels, levels, &[0], color_space, spare));
        }
        Ok(Texture::build(TexelFormat::Rgba8, width, height, texels.to_vec(), color_space, mips))
    }

    /// A texture from a `width × height` level 0 stored in `format` (see
    /// `shade::texel_format` for the data's layout and how each format decodes), rows or
    /// block rows top to bottom. A `MipChain::Box` chain is built from the decoded texels and
    /// modelled as stored in `format` too (for a compressed format: as if encoded again).
    ///
    /// # Errors
    /// A zero or too large size, `data` not the size the format needs for it, or a block the
    /// decoder refuses.
    pub fn from_encoded(
        format: TexelFormat,
        width: u32,
        height: u32,
        data: &[u8],
        color_space: ColorSpace,
        mips: MipChain,
    ) -> Result<Texture> {
        check_size(width, height, format)?;
        let rows = format.decode(width, height, data)?;
        // A 16-bit normalised format keeps its 16 bits where the filter can: a linear texture
        // without a built chain holds its texels decoded, as stored (the box filters of a
        // chain work on bytes, so a chain is built from the bytes).
        let wide = match (color_space, mips) {
            (ColorSpace::Linear, MipChain::BaseOnly) => format.decode_unorm16(width, height, data).transpose()?,
            _ => None,
        };
        let mut texture = Texture::build(format, width, height, rows, color_space, mips);
        if let Some(wide) = wide {
            let level = texture.levels[0];
            let mut words = vec![[0u32; 2]; texture.texels.len()];
            for (i, [r, g, b, a]) in wide.into_iter().enumerate() {
                let (x, y) = (i as u32 % width, i as u32 / width);
                words[level.texel_index(x, y)] = [r as u32 | (g as u32) << 16, b as u32 | (a as u32) << 16];
            }
            texture.texels = Texels::Decoded(words);
        }
        Ok(texture)
    }

    /// The same texels modelled as stored in `format`: for texels decoded before they reach
    /// the core (a compressed upload the GL layer decoded once, say), so that sampling them
    /// fetches what `format` stores. The texture gets a new id (its cache lines are its own).
    ///
    /// # Errors
    /// An invalid ASTC footprint, or a chain `format` stores in more than 4 GiB.
    pub fn stored_as(self, format: TexelFormat) -> Result<Texture> {
        check_size(self.width(), self.height(), format)?;
        let rows: Vec<[u8; 4]> = (0..self.levels.len()).flat_map(|level| self.level_texels(level)).collect();
        // `store` takes the chain row-major: each level's first texel in `rows`.
        let mut row_starts = Vec::with_capacity(self.levels.len());
        let mut at = 0;
        for l in &self.levels {
            row_starts.push(at);
            at += l.width as usize * l.height as usize;
        }
        Ok(Texture::store(format, &rows, self.levels, &row_starts, self.color_space))
    }

    /// The texture of decoded level 0 texels `rows`, its chain built by `mips`.
    fn build(
        format: TexelFormat,
        width: u32,
        height: u32,
        mut rows: Vec<[u8; 4]>,
        color_space: ColorSpace,
        mips: MipChain,
    ) -> Texture {
        // The chain is built row-major, level after level (`rows`, each level's first texel in
        // `starts`), then stored in blocks.
        let (mut levels, mut starts) = (vec![Level::new(width, height, 0)], vec![0]);
        if mips != MipChain::BaseOnly {
            while let Some(&above) = levels.last().filter(|l| l.width > 1 || l.height > 1) {
                let next = Level::new(
                    (above.width / 2).max(1),
                    (above.height / 2).max(1),
                    above.address + above.modelled_bytes(),
                );
                let above_start = *starts.last().expect("level 0 is there");
                starts.push(rows.len());
                // sRGB sides that halve exactly keep the box (in linear light, as a float
                // blend at ½ would give it up to rounding).
                let odd = |from: u32, to: u32| from != 2 * to && from != 1;
                let srgb_box = color_space == ColorSpace::Srgb
                    && !(odd(above.width, next.width) || odd(above.height, next.height));
                if mips == MipChain::Linear && !srgb_box {
                    linear_filter(&mut rows, above_start, &above, &next, color_space);
                } else {
                    box_filter(&mut rows, above_start, &above, &next, color_space);
                }
                levels.push(next);
            }
        }
        Texture::store(format, &rows, levels, &starts, color_space)
    }

    /// A texture whose mip chain is given, level 0 first, rows top to bottom, each level
    /// `max(1, ⌊w/2^i⌋) × max(1, ⌊h/2^i⌋)` RGBA8 texels, down to 1×1: what an application
    /// uploads level by level (`glTexImage2D` with `level > 0`).
    ///
    /// # Errors
    /// A size out of range, a level of the wrong size, or a chain that does not end at 1×1.
    pub fn from_rgba8_levels(width: u32, height: u32, given: &[&[u8]], color_space: ColorSpace) -> Result<Texture> {
        let base = given.first().ok_or_else(|| Error::invalid("texture", "no levels".to_string()))?;
        check_base(width, height, base)?;
        Texture::from_encoded_levels(TexelFormat::Rgba8, width, height, given, color_space)
    }

    /// [`Texture::from_rgba8_levels`] for levels stored in `format` (each level's data as
    /// [`Texture::from_encoded`] takes it): what an application uploads level by level
    /// (`glCompressedTexImage2D` with `level > 0`, for instance).
    ///
    /// # Errors
    /// A size out of range, a level of the wrong size or data, a block the decoder refuses,
    /// or a chain that does not end at 1×1.
    pub fn from_encoded_levels(
        format: TexelFormat,
        width: u32,
        height: u32,
        given: &[&[u8]],
        color_space: ColorSpace,
    ) -> Result<Texture> {
        let base = given.first().ok_or_else(|| Error::invalid("texture", "no levels".to_string()))?;
        check_size(width, height, format)?;
        let (mut levels, mut starts) = (vec![Level::new(width, height, 0)], vec![0]);
        let mut rows = format.decode(width, height, base)?;
        for (i, data) in given.iter().enumerate().skip(1) {
            let above = *levels.last().expect("level 0 is there");
            if above.width == 1 && above.height == 1 {
                return Err(Error::invalid("texture", format!("level {i} is below the 1×1 level")));
            }
            let next =
                Level::new((above.width / 2).max(1), (above.height / 2).max(1), above.address + above.modelled_bytes());
            let texels = format.decode(next.width, next.height, data).map_err(|e| match e {
                Error::Invalid { reason, .. } => Error::invalid("texture", format!("level {i}: {reason}")),
                other => other,
            })?;
            starts.push(rows.len());
            rows.extend(texels);
            levels.push(next);
        }
        let last = levels.last().expect("level 0 is there");
        if last.width > 1 || last.height > 1 {
            return Err(Error::invalid(
                "texture",
                format!("the chain ends at level {} ({}×{}), not at 1×1", levels.len() - 1, last.width, last.height),
            ));
        }
        Ok(Texture::store(format, &rows, levels, &starts, color_space))
    }

    /// The texture of a chain built row-major (`rows`, each level's first texel in `starts`),
    /// stored in blocks; each level's stored address follows the level before it in `format`.
    fn store(
        format: TexelFormat,
        rows: &[[u8; 4]],
        levels: Vec<Level>,
        starts: &[usize],
        color_space: ColorSpace,
    ) -> Texture {
        Texture::store_in(format, rows, levels, starts, color_space, None)
    }

    /// [`Texture::store`] in the memory of `spare`'s texels, where they are held the same way.
    fn store_in(
        format: TexelFormat,
        rows: &[[u8; 4]],
        mut levels: Vec<Level>,
        starts: &[usize],
        color_space: ColorSpace,
        spare: Option<Texels>,
    ) -> Texture {
        let layout = format.layout();
        let mut stored_address = 0;
        for level in &mut levels {
            level.stored_address = stored_address;
            level.stored_blocks_x = layout.blocks(level.width, level.height).0;
            stored_address += layout.level_bytes(level.width, level.height);
        }
        let last = levels.last().expect("level 0 is there");
        let color_table: Box<[u16; 256]> = Box::new(std::array::from_fn(|c| match color_space {
            ColorSpace::Linear => unorm8_to_unorm16(c as u32) as u16,
            ColorSpace::Srgb => (srgb8_to_linear(c as u8) as f64 * 65535.0).round() as u16,
        }));
        debug_assert!(color_table.windows(2).all(|pair| pair[0] < pair[1]), "the colour table is strictly increasing");
        debug_assert_eq!(
            (last.address + last.modelled_bytes()) / TEXEL_BYTES,
            levels.iter().map(|l| l.modelled_bytes() / TEXEL_BYTES).sum::<u64>(),
            "the levels are contiguous"
        );
        let texels = match color_space {
            ColorSpace::Linear => {
                let spare = match spare {
                    Some(Texels::Packed(texels)) => texels,
                    _ => Vec::new(),
                };
                Texels::Packed(block_texels(&levels, starts, rows, 0, u32::from_le_bytes, spare))
            }
            ColorSpace::Srgb => {
                let decode = |[r, g, b, a]: [u8; 4]| {
                    let colour = |c: u8| color_table[c as usize] as u32;
                    [colour(r) | colour(g) << 16, colour(b) | unorm8_to_unorm16(a as u32) << 16]
                };
                let spare = match spare {
                    Some(Texels::Decoded(texels)) => texels,
                    _ => Vec::new(),
                };
                let texels = block_texels(&levels, starts, rows, [0; 2], decode, spare);
                Texels::Decoded(texels)
            }
        };
        Texture {
            id: NEXT_TEXTURE_ID.fetch_add(1, Ordering::Relaxed),
            color_space,
            format,
            layout,
            levels,
            texels,
            color_table,
            face_bytes: None,
            layers: None,
        }
    }

    pub fn width(&self) -> u32 {
        self.levels[0].width
    }

    pub fn height(&self) -> u32 {
        self.levels[0].height
    }

    pub fn color_space(&self) -> ColorSpace {
        self.color_space
    }

    /// The format its texels are stored in (they are sampled decoded to RGBA8).
    pub fn format(&self) -> TexelFormat {
        self.format
    }

    /// Bytes the stored format takes for every level: what the texture occupies in external
    /// memory.
    pub fn stored_bytes(&self) -> u64 {
        self.levels.iter().map(|l| self.layout.level_bytes(l.width, l.height)).sum()
    }

    pub fn levels(&self) -> &[Level] {
        &self.levels
    }

    /// The texels of level `level`, row-major (a copy: they are stored in blocks).
    pub fn level_texels(&self, level: usize) -> Vec<[u8; 4]> {
        let l = &self.levels[level];
        (0..l.height).flat_map(|y| (0..l.width).map(move |x| self.texel_bytes(l.texel_index(x, y)))).collect()
    }

    /// Texel `(x, y)` of level `level` (`x < width`, `y < height` of the level).
    pub fn texel(&self, level: usize, x: u32, y: u32) -> [u8; 4] {
        let l = &self.levels[level];
        debug_assert!(x < l.width && y < l.height);
        self.texel_bytes(l.texel_index(x, y))
    }

    /// The RGBA8 bytes of `texels[index]`: a packed texel's own bytes, or given back from its
    /// decoded channels (alpha is `c · 257`, a colour channel the one byte `color_table` maps
    /// to it).
    fn texel_bytes(&self, index: usize) -> [u8; 4] {
        let texel = match &self.texels {
            Texels::Packed(texels) => return texels[index].to_le_bytes(),
            Texels::Decoded(texels) => texels[index],
        };
        let channel = |c: u32| texel_channel(texel[c as usize / 2], c) as u16;
        // An sRGB channel is given back through the table it was decoded by; a linear one (a
        // 16-bit normalised texel, held as stored) is rounded to the nearest byte, which for
        // `c · 257` is `c`.
        let nearest = |c: u16| ((c as u32 + 128) / 257) as u8;
        let colour = |c: u32| match self.color_space {
            ColorSpace::Srgb => {
                let byte = self.color_table.binary_search(&channel(c));
                debug_assert!(byte.is_ok(), "an sRGB colour channel decoded from a byte");
                byte.unwrap_or_else(|at| at) as u8
            }
            ColorSpace::Linear => nearest(channel(c)),
        };
        [colour(0), colour(1), colour(2), nearest(channel(3))]
    }

    /// Host memory the texels take (4 bytes a texel of a linear texture, 8 of an sRGB one: see
    /// [`Texels`]).
    pub fn host_bytes(&self) -> usize {
        self.texels.host_bytes()
    }

    /// The modelled address of texel `(x, y)` of `level` (see `texture_cache`): where the
    /// texture's format stores it ([`StoredLayout`]).
    #[inline(always)]
    pub fn texel_address(&self, level: usize, x: u32, y: u32) -> u64 {
        (self.id << 40).wrapping_add(self.levels[level].stored_offset(&self.layout, x, y))
    }

    /// Samples the eight lanes at `(u, v)` with the instruction set of `simd` (every level
    /// gives the same values, bit for bit). Reads of the `counted` lanes go through `cache`
    /// (pass the lanes the GPU runs: every quad with a covered pixel, helpers included); the
    /// values of all lanes are computed the same way either way.
    ///
    /// A quad is sampled as a whole, as its lanes share a level plan: the texels of its four
    /// lanes, their weights and cache lines are computed side by side ([`Footprint`]), the
    /// cache model reads the lines in the order of the per-lane rules (lane by lane, each
    /// lane's first level, then its second), and the filter runs across the lanes, channel by
    /// channel. The tests hold it equal, bit for bit and count for count, to a lane-by-lane
    /// reference.
    #[inline]
    pub fn sample(
        &self,
        simd: SimdSupport,
        sampler: &Sampler,
        u: F32x8,
        v: F32x8,
        counted: LaneMask,
        cache: &mut TextureCache,
    ) -> Vec4x8 {
        self.sample_with(simd, sampler, u, v, counted, cache, &Lookup::default())
    }

    /// [`Texture::sample`] with explicit derivatives or a texel offset ([`Lookup`]).
    ///
    /// Always inlined, so that it is compiled with its caller's instruction set: kept out of
    /// line it was baseline code between two AVX2 functions (a shader's lookup and the byte
    /// kernel), and it copied the coordinates' 32-byte vectors as 16-byte halves, which the
    /// kernel then loaded whole — a load spanning two stores, which the processor cannot
    /// forward (desktop.trace: 12% of the replay).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)] // `sample`'s inputs and the lookup's extras
    pub fn sample_with(
        &self,
        simd: SimdSupport,
        sampler: &Sampler,
        u: F32x8,
        v: F32x8,
        counted: LaneMask,
        cache: &mut TextureCache,
        lookup: &Lookup,
    ) -> Vec4x8 {
        // The byte kernel is called from here, inlined into the caller, rather than from
        // `sample_group`: that function holds every other path, and its frame (several
        // kilobytes of spills) cost more to enter than the kernel's admission.
        #[cfg(target_arch = "x86_64")]
        if simd.level() == SimdLevel::Avx2
            && let Texels::Packed(texels) = &self.texels
        {
            if self.filters_bytes_linearly(sampler, lookup) {
                // SAFETY: a `SimdSupport` of level `Avx2` exists only when this processor has
                // every feature `avx2::sample_bytes` is compiled with (`SimdSupport::detect`).
                return unsafe { avx2::sample_bytes(simd, self, texels, sampler, lookup, [u, v], counted, cache) };
            }
            if self.reads_bytes_nearest(sampler, lookup) {
                // SAFETY: as above, for `avx2::sample_nearest_bytes`.
                return unsafe {
                    avx2::sample_nearest_bytes(simd, self, texels, sampler, lookup, [u, v], counted, cache)
                };
            }
        }
        sample_group(simd, self, sampler, [u, v], counted, cache, lookup)
    }

    /// [`Texture::sample`] at each of `uvs` in turn (the same values, and the same reads in
    /// the same order), into `out`: lookups of one texture without their own derivatives or
    /// offsets (a blur's taps), the kernel chosen once for all of them.
    #[inline(always)]
    pub fn sample_run(
        &self,
        simd: SimdSupport,
        sampler: &Sampler,
        uvs: &[[F32x8; 2]],
        counted: LaneMask,
        cache: &mut TextureCache,
        out: &mut [[[f32; 8]; 4]],
    ) {
        let lookup = Lookup::default();
        #[cfg(target_arch = "x86_64")]
        if simd.level() == SimdLevel::Avx2
            && let Texels::Packed(texels) = &self.texels
            && self.filters_bytes_linearly(sampler, &lookup)
        {
            // SAFETY: as in `sample_with`, for `avx2::sample_bytes_run`.
            unsafe { avx2::sample_bytes_run(simd, self, texels, sampler, uvs, counted, cache, out) };
            return;
        }
        for (&[u, v], out) in uvs.iter().zip(out) {
            let [r, g, b, a] = self.sample_with(simd, sampler, u, v, counted, cache, &lookup);
            *out = [r, g, b, a].map(F32x8::to_array);
        }
    }

    /// [`Texture::sample`] for one layout (`STORED`: see `sample_group_body`).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)] // `sample_with`'s inputs
    fn sample_layout<const STORED: bool, const BYTES: bool>(
        &self,
        simd: SimdSupport,
        sampler: &Sampler,
        u: F32x8,
        v: F32x8,
        counted: LaneMask,
        cache: &mut TextureCache,
        lookup: &Lookup,
    ) -> Vec4x8 {
        let GroupPlan { lambdas, plans, minified_unmipped } = self.group_plan(sampler, u, v, lookup);
        let offset = lookup.offset;
        let (wrap_u, wrap_v) = if offset == [0, 0] {
            (Reduction::from(sampler.wrap_u), Reduction::from(sampler.wrap_v))
        } else {
            (offset_reduction(sampler.wrap_u), offset_reduction(sampler.wrap_v))
        };
        let counted_quad = |quad: usize| lanes(|i| counted.contains(QUAD_LANES[quad][i]));
        let counted = [counted_quad(0), counted_quad(1)];
        if let Some(pair) = PairPlan::of(plans) {
            let at = QuadAt {
                u: reduce_quad(lanes(|i| u.lane(PAIR_LANES[i])), wrap_u),
                v: reduce_quad(lanes(|i| v.lane(PAIR_LANES[i])), wrap_v),
                face_offsets: [0; 8],
                offset,
                bytes: BYTES,
            };
            let rgba = self.sample_pair::<STORED>(simd, sampler, pair, &at, counted, minified_unmipped, cache);
            return group_of_pair(rgba, BYTES);
        }
        let mut quads = [[[0u32; 4]; 4]; 2];
        for (quad, lanes) in QUAD_LANES.iter().enumerate() {
            let at = QuadAt {
                u: reduce_quad(self::lanes(|i| u.lane(lanes[i])), wrap_u),
                v: reduce_quad(self::lanes(|i| v.lane(lanes[i])), wrap_v),
                face_offsets: [0; 4],
                offset,
                bytes: BYTES,
            };
            quads[quad] = self.sample_quad::<STORED>(
                simd,
                sampler,
                lambdas[quad],
                &at,
                counted[quad],
                minified_unmipped[quad],
                cache,
            );
        }
        group_of_quads(quads, BYTES)
    }

    /// What a group's quads read before any texel is read: each quad's level of detail
    /// (`λ`, bias added), its [`LevelPlan`], and whether it reads level 0 minified more than 2×
    /// without mip maps. What [`Texture::sample_layout`] and the AVX2 kernel share.
    #[inline(always)]
    fn group_plan(&self, sampler: &Sampler, u: F32x8, v: F32x8, lookup: &Lookup) -> GroupPlan {
        let (width, height) = (self.width() as f32, self.height() as f32);
        // Arrays of two written out, not `map`ped: `map` is a function of its own that LLVM may
        // keep out of line, compiled for the baseline instruction set (see `lanes`).
        let rho_squared = match &lookup.gradients {
            None => quad_rho_squared(u, v, width, height),
            Some(g) => {
                // A function, not a closure (see `quad_rho_squared`).
                #[inline(always)]
                fn rho(g: &[[F32x8; 2]; 2], width: f32, height: f32, tl: usize) -> f32 {
                    let (dsdx, dtdx) = (g[0][0].lane(tl) * width, g[0][1].lane(tl) * height);
                    let (dsdy, dtdy) = (g[1][0].lane(tl) * width, g[1][1].lane(tl) * height);
                    (dsdx * dsdx + dtdx * dtdx).max(dsdy * dsdy + dtdy * dtdy)
                }
                [rho(g, width, height, QUAD_LANES[0][0]), rho(g, width, height, QUAD_LANES[1][0])]
            }
        };
        let lods = if self.plan_ignores_lod(sampler) {
            [0.0; 2]
        } else {
            [lod_of_rho_squared(rho_squared[0]), lod_of_rho_squared(rho_squared[1])]
        };
        // Minified more than 2× (`λ > UNMIPPED_LOD`) without mip maps, told from `ρ²` so that
        // samplers whose plan ignores the level of detail need no logarithm.
        let unmipped = sampler.mipmap == MipmapMode::None;
        let unmipped_rho_squared = unmipped_rho_squared(sampler);
        let lambdas = [lods[0] + sampler.lod_bias, lods[1] + sampler.lod_bias];
        let plans = [self.plan(sampler, lambdas[0]), self.plan(sampler, lambdas[1])];
        let minified = |quad: usize| unmipped && rho_squared[quad] > unmipped_rho_squared;
        GroupPlan { lambdas, plans, minified_unmipped: [minified(0), minified(1)] }
    }

    /// Both quads of a group read on the same level(s) with the same filter (`pair`): their
    /// eight lanes' footprints and filter computed side by side ([`PAIR_LANES`] order), eight
    /// lanes per operation where [`Texture::sample_quad`] does four. The cache model reads
    /// quad 0's lines, then quad 1's, each in the order [`Texture::sample_quad`] reads them,
    /// so counts and cache state are the same; per lane the arithmetic is the same, so the values too.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)] // one group's inputs; a struct would only rename them
    fn sample_pair<const STORED: bool>(
        &self,
        simd: SimdSupport,
        sampler: &Sampler,
        pair: PairPlan,
        at: &QuadAt<8>,
        counted: [[bool; 4]; 2],
        minified_unmipped: [bool; 2],
        cache: &mut TextureCache,
    ) -> [[u32; 8]; 4] {
        let line_shift = cache.line_shift();
        // See `sample_quad`.
        let first_line = (self.id << 40) >> line_shift;
        // Both quads' lanes, read together: quad 0's, then quad 1's ([`PAIR_LANES`]).
        let counted_pair: [bool; 8] = lanes(|i| counted[i / 4][i % 4]);
        match pair {
            PairPlan::Single { level, filter } => {
                let near = self.footprint::<STORED, 8>(level, filter, sampler, at, line_shift);
                let near_rows = near.rows();
                read_one_level(simd, cache, first_line, near_rows, counted_pair, minified_unmipped);
                self.filter_pair(simd, &near)
            }
            PairPlan::Blend { level, filter, weights } => {
                let near = self.footprint::<STORED, 8>(level, filter, sampler, at, line_shift);
                let far = self.footprint::<STORED, 8>(level + 1, filter, sampler, at, line_shift);
                let (near_rows, far_rows) = (near.rows(), far.rows());
                let mut rows = [[0; 8]; MAX_LANE_LINES];
                rows[..near_rows.len()].copy_from_slice(near_rows);
                rows[near_rows.len()..near_rows.len() + far_rows.len()].copy_from_slice(far_rows);
                cache.access_lanes(simd, first_line, &rows[..near_rows.len() + far_rows.len()], counted_pair);
                let (a, b) = (self.filter_pair(simd, &near), self.filter_pair(simd, &far));
                let weight = lanes::<u32, 8>(|i| weights[i / 4]);
                blend_levels(&a, &b, &weight, at.bytes)
            }
        }
    }

    /// One quad's filtered colour at the level of detail `lambda` (bias added) and the reduced
    /// coordinates `at`, 16-bit UNORMs `[channel][lane of the quad]`: the cache model reads
    /// the `counted` lanes' lines in the order of the per-lane rules (lane by lane, each lane's
    /// first level, then its second). `minified_unmipped`: the quad reads level 0 minified
    /// more than 2× without mip maps, and its misses are noted as such
    /// ([`TextureCache::note_unmipped`]). What 2D and cube sampling share.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)] // one quad's inputs; a struct would only rename them
    fn sample_quad<const STORED: bool>(
        &self,
        simd: SimdSupport,
        sampler: &Sampler,
        lambda: f32,
        at: &QuadAt,
        counted: [bool; 4],
        minified_unmipped: bool,
        cache: &mut TextureCache,
    ) -> [Quad<u32>; 4] {
        let line_shift = cache.line_shift();
        // Texel (x, y)'s modelled address is `id · 2^40` plus an offset below 2^32
        // (`MAX_MODELLED_BYTES`), so its line is the texture's first line plus the offset's:
        // the low 40 bits of `id · 2^40` are zero, and lines are at most 2^12 bytes.
        let first_line = (self.id << 40) >> line_shift;
        match self.plan(sampler, lambda) {
            LevelPlan::Single { level, filter } => {
                let near = self.footprint::<STORED, 4>(level, filter, sampler, at, line_shift);
                let misses = cache.misses();
                cache.access_quad(simd, first_line, near.rows(), counted);
                if minified_unmipped && counted.contains(&true) {
                    cache.note_unmipped(misses);
                }
                self.filter(&near)
            }
            LevelPlan::Blend { level, filter, weight } => {
                let near = self.footprint::<STORED, 4>(level, filter, sampler, at, line_shift);
                let far = self.footprint::<STORED, 4>(level + 1, filter, sampler, at, line_shift);
                let (near_rows, far_rows) = (near.rows(), far.rows());
                let mut rows = [[0; 4]; MAX_LANE_LINES];
                rows[..near_rows.len()].copy_from_slice(near_rows);
                rows[near_rows.len()..near_rows.len() + far_rows.len()].copy_from_slice(far_rows);
                cache.access_quad(simd, first_line, &rows[..near_rows.len() + far_rows.len()], counted);
                let (a, b) = (self.filter(&near), self.filter(&far));
                blend_levels(&a, &b, &[weight; 4], at.bytes)
            }
        }
    }

    /// [`Texture::sample_lod`] at reduced coordinates `at` (one point in every lane), no cache.
    fn sample_point(&self, sampler: &Sampler, at: &QuadAt, lambda: f32) -> [f32; 4] {
        let rgba = match self.plan(sampler, lambda + sampler.lod_bias) {
            LevelPlan::Single { level, filter } => {
                self.filter(&self.footprint::<false, 4>(level, filter, sampler, at, 0))
            }
            LevelPlan::Blend { level, filter, weight } => {
                let a = self.filter(&self.footprint::<false, 4>(level, filter, sampler, at, 0));
                let b = self.filter(&self.footprint::<false, 4>(level + 1, filter, sampler, at, 0));
                std::array::from_fn(|c| lanes(|i| blend(a[c][i], b[c][i], weight, at.bytes)))
            }
        };
        rgba.map(|channel| channel_to_f32(channel[0], at.bytes))
    }

    /// Samples one point `(u, v)` at the level of detail `lambda` given by the caller (bias
    /// added), with the same rules and fixed-point arithmetic as [`Texture::sample`] but no
    /// derivatives and no cache model: what a vertex shader's fetch (GL: `λ = 0`, so the
    /// magnification filter on level 0) or a fragment shader's explicit level
    /// (`texture2DLod`) reads. Reads are not counted in the ledger.
    pub fn sample_lod(&self, sampler: &Sampler, u: f32, v: f32, lambda: f32) -> [f32; 4] {
        self.sample_lod_offset(sampler, u, v, lambda, [0, 0])
    }

    /// [`Texture::sample_lod`] with `offset` texels added on the level read, before the
    /// wrap (`textureLodOffset`; see [`Lookup::offset`]).
    pub fn sample_lod_offset(&self, sampler: &Sampler, u: f32, v: f32, lambda: f32, offset: [i32; 2]) -> [f32; 4] {
        let (wrap_u, wrap_v) = if offset == [0, 0] {
            (Reduction::from(sampler.wrap_u), Reduction::from(sampler.wrap_v))
        } else {
            (offset_reduction(sampler.wrap_u), offset_reduction(sampler.wrap_v))
        };
        let at = QuadAt {
            u: reduce_quad([u; 4], wrap_u),
            v: reduce_quad([v; 4], wrap_v),
            face_offsets: [0; 4],
            offset,
            bytes: self.filters_bytes(sampler),
        };
        self.sample_point(sampler, &at, lambda)
    }

    /// The level of detail (bias not added) that derivatives `dx`, `dy` of the coordinates
    /// along window x and y give, by [`Texture::sample`]'s formula: `½ · log2` of the larger
    /// of the two squared lengths in texels (`(s, t)` scaled by width and height, and a 3-D
    /// texture's `r` by its depth; an array's layer coordinate does not count). What
    /// `textureGrad` reads where it is not sampled as a quad.
    pub fn grad_lod(&self, dx: [f32; 3], dy: [f32; 3]) -> f32 {
        let depth = match self.layers {
            Some(l) if l.kind == LayeredKind::Volume => l.count as f32,
            _ => 0.0,
        };
        let size = [self.width() as f32, self.height() as f32, depth];
        let squared = |d: [f32; 3]| (0..3).map(|i| (d[i] * size[i]) * (d[i] * size[i])).fold(0.0, |a, b| a + b);
        lod_of_rho_squared(squared(dx).max(squared(dy)))
    }

    /// Whether a lookup (`lookup` with or without derivatives, without an offset) of
    /// `sampler` reads bilinearly as bytes on every level: an RGBA8 texture held as bytes,
    /// repeat or clamp-to-edge, and the linear filter for magnification and minification (so
    /// every [`LevelPlan`] is linear, on one level or two). What `avx2::sample_bytes` samples.
    /// Only the sampler's state and the lookup's kind decide it, not the coordinates.
    #[inline(always)]
    fn filters_bytes_linearly(&self, sampler: &Sampler, lookup: &Lookup) -> bool {
        // The filters first: they turn most other samplers away at once.
        sampler.mag_filter == Filter::Linear
            && sampler.min_filter == Filter::Linear
            && self.format == TexelFormat::Rgba8
            && self.filters_bytes(sampler)
            && lookup.offset == [0, 0]
    }

    /// Whether a lookup (`lookup` with or without derivatives, without an offset) of
    /// `sampler` reads nearest texels of bytes on every level: an RGBA8 texture held as
    /// bytes, repeat or clamp-to-edge, and the nearest filter for magnification and
    /// minification (so every [`LevelPlan`] is nearest, on one level or two). What
    /// `avx2::sample_nearest_bytes` samples. Only the sampler's state and the lookup's kind
    /// decide it, not the coordinates.
    #[inline(always)]
    fn reads_bytes_nearest(&self, sampler: &Sampler, lookup: &Lookup) -> bool {
        sampler.mag_filter == Filter::Nearest
            && sampler.min_filter == Filter::Nearest
            && self.format == TexelFormat::Rgba8
            && self.filters_bytes(sampler)
            && lookup.offset == [0, 0]
    }

    /// Whether the texels are held as RGBA8 bytes ([`Texels::Packed`]).
    #[inline(always)]
    fn holds_bytes(&self) -> bool {
        matches!(self.texels, Texels::Packed(_))
    }

    /// Whether `sampler` filters this texture's texels as bytes, as llvmpipe's AoS sampler
    /// does (see the module notes): texels held as RGBA8 bytes ([`Texels::Packed`]) and both
    /// wraps repeat or clamp-to-edge. Mirrored repeat, sRGB and 16-bit textures keep the
    /// 16-bit filter.
    #[inline(always)]
    fn filters_bytes(&self, sampler: &Sampler) -> bool {
        self.holds_bytes() && sampler.wrap_u != Wrap::MirroredRepeat && sampler.wrap_v != Wrap::MirroredRepeat
    }

    /// Whether `sampler` reads this texture at a level of detail (mip maps to choose from, or
    /// different filters for magnification and minification): if not, a lookup's
    /// [`Lookup::gradients`] only serve the ledger's note of minification without mip maps,
    /// which the quads' own differences serve as well.
    #[inline(always)]
    pub fn reads_lod(&self, sampler: &Sampler) -> bool {
        !self.plan_ignores_lod(sampler)
    }

    /// Whether [`Texture::plan`] gives the same plan at every level of detail: one filter for
    /// magnification and minification, and one level to read. Then the quads' levels of detail
    /// (two logarithms a group) need not be computed.
    #[inline(always)]
    fn plan_ignores_lod(&self, sampler: &Sampler) -> bool {
        sampler.min_filter == sampler.mag_filter && (sampler.mipmap == MipmapMode::None || self.levels.len() == 1)
    }

    /// The levels and filter for a level of detail `lambda` (GL §8.14–8.15, see the module
    /// notes). A NaN level of detail magnifies.
    #[inline(always)]
    fn plan(&self, sampler: &Sampler, lambda: f32) -> LevelPlan {
        if lambda.is_nan() || lambda <= 0.0 {
            return LevelPlan::Single { level: 0, filter: sampler.mag_filter };
        }
        let last = self.levels.len() - 1;
        let filter = sampler.min_filter;
        match sampler.mipmap {
            MipmapMode::None => LevelPlan::Single { level: 0, filter },
            MipmapMode::Nearest => {
                // `λ` rounded to the nearest level, halves up (llvmpipe's `(e + 1) >> 1` for
                // `ρ² = m · 2^e`, which is that of `½ · fast_log2(ρ²)`); `λ − ⌊λ⌋` is exact.
                let base = floor(lambda);
                let nearest = if lambda - base >= 0.5 { base + 1.0 } else { base };
                let level = nearest.min(last as f32) as usize;
                LevelPlan::Single { level, filter }
            }
            MipmapMode::Linear => {
                if lambda >= last as f32 {
                    return LevelPlan::Single { level: last, filter };
                }
                let base = floor(lambda);
                // `λ − ⌊λ⌋` is in `[0, 1)`, so the weight in `[0, 256)`.
                LevelPlan::Blend { level: base as usize, filter, weight: ((lambda - base) * 256.0) as u32 }
            }
        }
    }

    /// What a quad reads on `level` with `filter` at the reduced coordinates `at` of its
    /// lanes (see [`reduce`]): texels and weights, and the cache lines that hold the texels
    /// (`line_shift`: [`TextureCache::line_shift`]).
    #[inline(always)]
    fn footprint<const STORED: bool, const N: usize>(
        &self,
        level: usize,
        filter: Filter,
        sampler: &Sampler,
        at: &QuadAt<N>,
        line_shift: u32,
    ) -> Footprint<N> {
        let (u, v) = (at.u, at.v);
        let l = &self.levels[level];
        let (x, alpha, y, beta) = match filter {
            Filter::Nearest if at.offset != [0, 0] => {
                let x = nearest_texels_offset(u, l.width, sampler.wrap_u, at.offset[0]);
                let y = nearest_texels_offset(v, l.height, sampler.wrap_v, at.offset[1]);
                ([x; 2], [0; N], [y; 2], [0; N])
            }
            Filter::Linear if at.offset != [0, 0] => {
                let (x, alpha) = linear_texels_offset(u, l.width, sampler.wrap_u, at.offset[0], at.bytes);
                let (y, beta) = linear_texels_offset(v, l.height, sampler.wrap_v, at.offset[1], at.bytes);
                (x, alpha, y, beta)
            }
            Filter::Nearest => {
                let (x, y) = (nearest_texels(u, l.width, sampler.wrap_u), nearest_texels(v, l.height, sampler.wrap_v));
                ([x; 2], [0; N], [y; 2], [0; N])
            }
            Filter::Linear if at.bytes => {
                let (x, alpha) = linear_texels_bytes(u, l.width, sampler.wrap_u);
                let (y, beta) = linear_texels_bytes(v, l.height, sampler.wrap_v);
                (x, alpha, y, beta)
            }
            Filter::Linear => {
                let (x, alpha) = linear_texels(u, l.width, sampler.wrap_u);
                let (y, beta) = linear_texels(v, l.height, sampler.wrap_v);
                (x, alpha, y, beta)
            }
        };
        // Texel (x, y) is at `row_offset(y) + column_offset(x)` in the modelled memory of the
        // texture, and at a quarter of that in `texels`.
        let row_offset = |y: [u32; N]| lanes::<u32, N>(|i| l.row_offset(y[i]));
        let column_offset = |x: [u32; N]| lanes::<u32, N>(|i| l.column_offset(x[i]));
        let row_offsets = [row_offset(y[0]), row_offset(y[1])];
        let column_offsets = [column_offset(x[0]), column_offset(x[1])];
        let offset = |(cx, cy): (usize, usize)| {
            lanes::<u32, N>(|i| at.face_offsets[i] + row_offsets[cy][i] + column_offsets[cx][i])
        };
        let texel = |corner| {
            let offset = offset(corner);
            lanes(|i| offset[i] / TEXEL_BYTES as u32)
        };
        // An RGBA8 texture is stored as it is decoded; any other format (`STORED`) where its
        // layout says.
        let line = |(cx, cy): (usize, usize)| {
            if STORED {
                lanes(|i| (l.stored_offset(&self.layout, x[cx][i], y[cy][i]) >> line_shift) as u32)
            } else {
                let offset = offset((cx, cy));
                lanes(|i| offset[i] >> line_shift)
            }
        };
        let corners = [(0, 0), (1, 0), (0, 1), (1, 1)];
        Footprint {
            filter,
            bytes: at.bytes,
            texels: [texel(corners[0]), texel(corners[1]), texel(corners[2]), texel(corners[3])],
            lines: [line(corners[0]), line(corners[1]), line(corners[2]), line(corners[3])],
            alpha,
            beta,
        }
    }

    /// The filtered colour of a footprint's lanes as 16-bit UNORMs, `[channel][lane]` (see the
    /// module notes for the linear filter's formula), from the texels as they are held
    /// ([`Texels`]): one branch a footprint, the filter compiled once per layout.
    #[inline(always)]
    fn filter<const N: usize>(&self, footprint: &Footprint<N>) -> [[u32; N]; 4] {
        match &self.texels {
            Texels::Packed(texels) if footprint.bytes && footprint.filter == Filter::Linear => {
                filter_bytes(texels.as_slice(), footprint)
            }
            Texels::Packed(texels) => filter_texels(texels.as_slice(), footprint),
            Texels::Decoded(texels) => filter_texels(texels.as_slice(), footprint),
        }
    }
}

impl Texture {
    /// [`Texture::filter`] of a pair's eight lanes with the instruction set of `simd`: the
    /// byte filter through [`avx2::filter_bytes`] (16-bit lanes, `pmulhrsw`, as llvmpipe)
    /// at the AVX2 level, the same bits as [`filter_bytes`].
    #[inline(always)]
    fn filter_pair(&self, simd: SimdSupport, footprint: &Footprint<8>) -> [[u32; 8]; 4] {
        #[cfg(target_arch = "x86_64")]
        if let Texels::Packed(texels) = &self.texels
            && footprint.bytes
            && footprint.filter == Filter::Linear
            && simd.level() == SimdLevel::Avx2
        {
            let corners = footprint_corners::<u32, _, 4>(texels, footprint);
            // SAFETY: a `SimdSupport` of level `Avx2` exists only when this processor has
            // every feature `avx2::filter_bytes` is compiled with (`SimdSupport::detect`).
            return unsafe { avx2::filter_bytes(&corners, &footprint.alpha, &footprint.beta) };
        }
        let _ = simd;
        self.filter(footprint)
    }
}

/// Each lane's texel at the footprint's first `C` corners, `[corner][lane]` (`C` 1 for a
/// nearest footprint, 4 for a linear one), after one bounds check for all of them (the
/// largest index of the four corners; a nearest footprint's four are its one texel), not one
/// per texel read: 64 compares and branches a trilinear pair.
#[inline(always)]
fn footprint_corners<T: Copy + Default, const N: usize, const C: usize>(
    texels: &[T],
    footprint: &Footprint<N>,
) -> [[T; N]; C] {
    let largest = largest_texel(&footprint.texels);
    assert!(
        (largest as usize) < texels.len(),
        "texel {largest} of a footprint outside the texture's {} texels",
        texels.len()
    );
    std::array::from_fn(|corner| {
        lanes::<T, N>(|i| {
            let index = footprint.texels[corner][i] as usize;
            // SAFETY: `index` is one of the footprint's texel indices (the indexing above
            // panics for a corner past the fourth), all at most `largest`, which the
            // assertion above holds below `texels.len()`.
            unsafe { *texels.get_unchecked(index) }
        })
    })
}

/// Prefetches the lines of level `level`'s texels at `(x_lo, y)` and `(x_hi, y)` (in the block
/// layout, the two lines hold every texel of row `y` between them up to a block apart). The
/// sampler's AVX2 kernels prefetch the bottom edge of what the group two pixel rows below
/// their group is likely to read (`avx2::edge_below`): in the pixel pipeline that group is
/// shaded two groups later (a block's groups go left to right, then two rows down), so its
/// texels are on their way while this group and the next are shaded — a lookup's own
/// gathers come too late to hide a miss, and a texture larger than the caches misses often.
/// The bottom edge alone: the lines above it are mostly this group's. Only a hint: nothing is
/// read, and a wrong guess costs two prefetches.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn prefetch_edge(texels: &[u32], level: &Level, ([x_lo, x_hi], y): ([u32; 2], u32)) {
    let row = level.row_offset(y);
    for column in [level.column_offset(x_lo), level.column_offset(x_hi)] {
        let index = ((row + column) as u64 / TEXEL_BYTES) as usize;
        // `wrapping_add`: the address of a texel of the level, formed without asserting it.
        crate::simd::prefetch_line(texels.as_ptr().wrapping_add(index));
    }
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use std::arch::x86_64::*;

    use super::{
        BLOCK_BYTES, BLOCK_TEXELS, F32x8, LaneMask, Level, Lookup, PAIR_LANES, PairPlan, Sampler, SimdSupport,
        TEXEL_BYTES, Texture, TextureCache, Vec4x8, Wrap, lanes,
    };

    /// [`super::filter_bytes`] of eight lanes from their corners' packed texels
    /// (`[corner][lane]`) and weights, in 16-bit lanes as llvmpipe's AoS sampler: two
    /// texels' four channels per 128 bits (`unpack` with zero), each weight spread over its
    /// texel's channels (`pshufb`), and `lerp(a, b, w) = a + pmulhrsw(w, (b − a) << 7)` —
    /// `(w · (b − a) · 128 + 2^14) >> 15`, which is `(w · (b − a) + 128) >> 8`, arithmetic
    /// (`|b − a| · 128 < 2^15`); then packed back to bytes (the values are bytes, so
    /// `packus` is exact), each lane's four bytes packed as a texel's.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    fn filter_bytes_packed(corners: &[[u32; 8]; 4], alpha: &[u32; 8], beta: &[u32; 8]) -> __m256i {
        // SAFETY (each load): 32 bytes of one `[u32; 8]`; unaligned loads need no alignment.
        let load = |v: &[u32; 8]| unsafe { _mm256_loadu_si256(v.as_ptr().cast()) };
        let t = [load(&corners[0]), load(&corners[1]), load(&corners[2]), load(&corners[3])];
        filter_bytes_lanes(t, load(alpha), load(beta))
    }

    /// [`filter_bytes_packed`] of the corners' texels and the weights in registers.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    fn filter_bytes_lanes(t: [__m256i; 4], a: __m256i, b: __m256i) -> __m256i {
        let zero = _mm256_setzero_si256();
        let (spread_low, spread_high) = spreads();
        let half = |c: [__m256i; 4], spread: __m256i| {
            let (wa, wb) = (_mm256_shuffle_epi8(a, spread), _mm256_shuffle_epi8(b, spread));
            let top = lerp(c[0], c[1], wa);
            let bottom = lerp(c[2], c[3], wa);
            lerp(top, bottom, wb)
        };
        let low = half(t.map(|t| _mm256_unpacklo_epi8(t, zero)), spread_low);
        let high = half(t.map(|t| _mm256_unpackhi_epi8(t, zero)), spread_high);
        _mm256_packus_epi16(low, high)
    }

    /// `lerp(x, y, w) = x + pmulhrsw(w, (y − x) << 7)` of 16-bit lanes: `(w · (y − x) + 128) >> 8`
    /// added to `x` (see [`filter_bytes_packed`]).
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    fn lerp(x: __m256i, y: __m256i, w: __m256i) -> __m256i {
        let delta = _mm256_slli_epi16::<7>(_mm256_sub_epi16(y, x));
        _mm256_add_epi16(x, _mm256_mulhrs_epi16(w, delta))
    }

    /// The `pshufb` masks that spread each 32-bit lane's weight (its low byte) over its texel's
    /// four 16-bit channels after an `unpack` with zero: lanes 0, 1 (and 4, 5) of a 128-bit
    /// half for the low unpack, lanes 2, 3 (6, 7) for the high one.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    fn spreads() -> (__m256i, __m256i) {
        let low = _mm256_setr_epi8(
            0, -128, 0, -128, 0, -128, 0, -128, 4, -128, 4, -128, 4, -128, 4, -128, //
            0, -128, 0, -128, 0, -128, 0, -128, 4, -128, 4, -128, 4, -128, 4, -128,
        );
        let high = _mm256_setr_epi8(
            8, -128, 8, -128, 8, -128, 8, -128, 12, -128, 12, -128, 12, -128, 12, -128, //
            8, -128, 8, -128, 8, -128, 8, -128, 12, -128, 12, -128, 12, -128, 12, -128,
        );
        (low, high)
    }

    /// [`super::filter_bytes`] of eight lanes (see [`filter_bytes_packed`]), each channel
    /// spread to `c · 257`.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    pub(super) fn filter_bytes(corners: &[[u32; 8]; 4], alpha: &[u32; 8], beta: &[u32; 8]) -> [[u32; 8]; 4] {
        let packed = filter_bytes_packed(corners, alpha, beta);
        let byte_mask = _mm256_set1_epi32(0xff);
        let mut out = [[0u32; 8]; 4];
        for (c, out) in out.iter_mut().enumerate() {
            let channel = match c {
                0 => _mm256_and_si256(packed, byte_mask),
                1 => _mm256_and_si256(_mm256_srli_epi32::<8>(packed), byte_mask),
                2 => _mm256_and_si256(_mm256_srli_epi32::<16>(packed), byte_mask),
                _ => _mm256_srli_epi32::<24>(packed),
            };
            let widened = _mm256_or_si256(channel, _mm256_slli_epi32::<8>(channel));
            // SAFETY: see above.
            unsafe { _mm256_storeu_si256(out.as_mut_ptr().cast(), widened) };
        }
        out
    }

    /// [`super::sample_group_body`] of a group read with `sampler`, which
    /// [`Texture::filters_bytes_linearly`] admits, `texels` the texture's [`Texels::Packed`]
    /// words: the quads' plans as [`Texture::group_plan`] makes them, then, when both quads
    /// read the same level(s) ([`PairPlan::of`]), the pair path of [`Texture::sample_layout`]
    /// with the sampler's state known, eight lanes per AVX2 operation — [`reduce`],
    /// [`linear_texels_bytes`], the offsets of [`Level::row_offset`] and
    /// [`Level::column_offset`], the cache model's reads (the same rows in the same order),
    /// [`filter_bytes_packed`], the blend of two levels and [`channel_to_f32`]: the same
    /// operations in the same order per lane, so the same bits and the same reads. Quads on
    /// different levels go the general way ([`super::sample_group`]).
    ///
    /// `#[inline]` for [`sample_bytes_run`]: the lookups of a shader (compiled for AVX2 and
    /// F16C alone) cannot take in this function's wider set, and keep calling it.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    #[allow(clippy::too_many_arguments)] // one group's inputs, as `sample_group_body`'s
    pub(super) fn sample_bytes(
        simd: SimdSupport,
        texture: &Texture,
        texels: &[u32],
        sampler: &Sampler,
        lookup: &Lookup,
        [u, v]: [F32x8; 2],
        counted: LaneMask,
        cache: &mut TextureCache,
    ) -> Vec4x8 {
        const _: () = assert!(BLOCK_TEXELS == 4 && BLOCK_BYTES == 64 && TEXEL_BYTES == 4);
        let group = texture.group_plan(sampler, u, v, lookup);
        let Some(pair) = PairPlan::of(group.plans) else {
            return super::sample_group(simd, texture, sampler, [u, v], counted, cache, lookup);
        };
        let (level, weights) = match pair {
            PairPlan::Single { level, .. } => (level, None),
            PairPlan::Blend { level, weights, .. } => (level, Some(weights)),
        };
        let [u, v] = pair_coordinates([u, v]);
        let line_shift = cache.line_shift();
        let wraps = [sampler.wrap_u, sampler.wrap_v];
        let (near, near_box) = footprint_with_box(&texture.levels[level], [u, v], wraps, line_shift);
        let far_with_box = weights.map(|_| footprint_with_box(&texture.levels[level + 1], [u, v], wraps, line_shift));
        let far = far_with_box.as_ref().map(|(far, _)| far);
        let first_line = first_line(texture, line_shift);
        let counted_pair: [bool; 8] = lanes(|i| counted.contains(PAIR_LANES[i]));
        let minified_unmipped = group.minified_unmipped;
        // What the group two rows below reads, on its way (see `super::prefetch_edge`), written
        // out for each level: as a loop over `Option`s or a closure it was kept out of line.
        let near_level = &texture.levels[level];
        super::prefetch_edge(texels, near_level, edge_below(near_level, near_box[0], near_box[1]));
        if let Some((_, far_box)) = &far_with_box {
            let far_level = &texture.levels[level + 1];
            super::prefetch_edge(texels, far_level, edge_below(far_level, far_box[0], far_box[1]));
        }
        if let Some(far) = far {
            let mut rows = [[0u32; 8]; 8];
            rows[..4].copy_from_slice(&near.lines);
            rows[4..].copy_from_slice(&far.lines);
            cache.access_two_levels_avx2(simd, first_line, &rows, counted_pair);
        } else if minified_unmipped.contains(&true) {
            super::read_one_level(simd, cache, first_line, &near.lines, counted_pair, minified_unmipped);
        } else {
            // What `read_one_level` makes of it, without the dispatch (this is AVX2 code).
            cache.access_footprints_avx2(first_line, &near.lines, counted_pair);
        }
        let mut packed = filter_footprint(texels, &near);
        if let (Some(far), Some(weights)) = (far, weights) {
            // `blend` of bytes: `lerp_bytes` of each channel by the quad's weight.
            let weight = _mm256_setr_epi32(
                weights[0] as i32,
                weights[0] as i32,
                weights[0] as i32,
                weights[0] as i32,
                weights[1] as i32,
                weights[1] as i32,
                weights[1] as i32,
                weights[1] as i32,
            );
            packed = lerp_packed(packed, filter_footprint(texels, far), weight);
        }
        // `channel_to_f32` of bytes, `c · fl(1/255)`, back in the group's lanes.
        channels(packed, pair_lanes())
    }

    /// [`sample_bytes`] of each of `uvs` in turn into `out`, in one function: a run of
    /// lookups (see [`Texture::sample_run`]) without a call and its entry for each.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[allow(clippy::too_many_arguments)] // `sample_bytes`'s inputs
    pub(super) fn sample_bytes_run(
        simd: SimdSupport,
        texture: &Texture,
        texels: &[u32],
        sampler: &Sampler,
        uvs: &[[F32x8; 2]],
        counted: LaneMask,
        cache: &mut TextureCache,
        out: &mut [[[f32; 8]; 4]],
    ) {
        let lookup = Lookup::default();
        // The common run in three phases — every footprint, then the cache model's reads in
        // the lookups' order, then every filter — so that the lookups' independent work (and
        // their gathers) is in flight together: when every lookup reads one level, as one pair,
        // not minified without mip maps. Each lookup's operations are `sample_bytes`'s for that
        // case, the reads in the same order, so the same bits and counts.
        const PHASED: usize = 16;
        let mut prints: [Option<Footprint>; PHASED] = std::array::from_fn(|_| None);
        let line_shift = cache.line_shift();
        let wraps = [sampler.wrap_u, sampler.wrap_v];
        let phased = uvs.len() <= PHASED
            && uvs.iter().zip(&mut prints).all(|(&[u, v], print)| {
                let group = texture.group_plan(sampler, u, v, &lookup);
                match PairPlan::of(group.plans) {
                    Some(PairPlan::Single { level, .. }) if !group.minified_unmipped.contains(&true) => {
                        *print = Some(footprint(&texture.levels[level], pair_coordinates([u, v]), wraps, line_shift));
                        true
                    }
                    _ => false,
                }
            });
        if !phased {
            for (&uv, out) in uvs.iter().zip(out) {
                let [r, g, b, a] = sample_bytes(simd, texture, texels, sampler, &lookup, uv, counted, cache);
                *out = [r, g, b, a].map(F32x8::to_array);
            }
            return;
        }
        let prints = &prints[..uvs.len()];
        let first_line = first_line(texture, line_shift);
        let counted_pair: [bool; 8] = lanes(|i| counted.contains(PAIR_LANES[i]));
        for print in prints.iter().flatten() {
            cache.access_footprints_avx2(first_line, &print.lines, counted_pair);
        }
        for (print, out) in prints.iter().flatten().zip(out) {
            let [r, g, b, a] = channels(filter_footprint(texels, print), pair_lanes());
            *out = [r, g, b, a].map(F32x8::to_array);
        }
    }

    /// [`super::sample_group_body`] of a group read with `sampler`, which
    /// [`Texture::reads_bytes_nearest`] admits, `texels` the texture's [`Texels::Packed`]
    /// words: [`sample_bytes`] for the nearest filter. The quads' plans as
    /// [`Texture::group_plan`] makes them; when both quads read the same level(s)
    /// ([`PairPlan::of`]), the pair path of [`Texture::sample_layout`] with the sampler's state
    /// known, eight lanes per AVX2 operation — [`reduce`], [`nearest_texels`], the offsets of
    /// [`Level::row_offset`] and [`Level::column_offset`], the cache model's reads (one line a
    /// lane and level, in the same order), the blend of two levels ([`lerp_packed`], what
    /// `blend` of bytes is) and [`channel_to_f32`]: the same operations per lane, so the same
    /// bits and the same reads. Quads on different levels go the general way
    /// ([`super::sample_group`]).
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[allow(clippy::too_many_arguments)] // one group's inputs, as `sample_group_body`'s
    pub(super) fn sample_nearest_bytes(
        simd: SimdSupport,
        texture: &Texture,
        texels: &[u32],
        sampler: &Sampler,
        lookup: &Lookup,
        [u, v]: [F32x8; 2],
        counted: LaneMask,
        cache: &mut TextureCache,
    ) -> Vec4x8 {
        const _: () = assert!(BLOCK_TEXELS == 4 && BLOCK_BYTES == 64 && TEXEL_BYTES == 4);
        let group = texture.group_plan(sampler, u, v, lookup);
        let Some(pair) = PairPlan::of(group.plans) else {
            return super::sample_group(simd, texture, sampler, [u, v], counted, cache, lookup);
        };
        let (level, weights) = match pair {
            PairPlan::Single { level, .. } => (level, None),
            PairPlan::Blend { level, weights, .. } => (level, Some(weights)),
        };
        let [u, v] = pair_coordinates([u, v]);
        let line_shift = cache.line_shift();
        let wraps = [sampler.wrap_u, sampler.wrap_v];
        let near = nearest_footprint(&texture.levels[level], [u, v], wraps, line_shift);
        let far = weights.map(|_| nearest_footprint(&texture.levels[level + 1], [u, v], wraps, line_shift));
        // What the group two rows below reads, on its way (see `super::prefetch_edge`).
        let near_level = &texture.levels[level];
        super::prefetch_edge(texels, near_level, edge_below(near_level, [near.x; 2], [near.y; 2]));
        if let Some(far) = &far {
            let far_level = &texture.levels[level + 1];
            super::prefetch_edge(texels, far_level, edge_below(far_level, [far.x; 2], [far.y; 2]));
        }
        let first_line = first_line(texture, line_shift);
        let counted_pair: [bool; 8] = lanes(|i| counted.contains(PAIR_LANES[i]));
        if let Some(far) = &far {
            cache.access_lanes(simd, first_line, &[near.lines, far.lines], counted_pair);
        } else if group.minified_unmipped.contains(&true) {
            super::read_one_level(simd, cache, first_line, &[near.lines], counted_pair, group.minified_unmipped);
        } else {
            // What `read_one_level` makes of it, without the dispatch (as in `sample_bytes`).
            cache.access_footprints_avx2(first_line, &[near.lines], counted_pair);
        }
        let mut packed = near.texels(texels);
        if let (Some(far), Some(weights)) = (&far, weights) {
            let weight = _mm256_setr_epi32(
                weights[0] as i32,
                weights[0] as i32,
                weights[0] as i32,
                weights[0] as i32,
                weights[1] as i32,
                weights[1] as i32,
                weights[1] as i32,
                weights[1] as i32,
            );
            packed = lerp_packed(packed, far.texels(texels), weight);
        }
        channels(packed, pair_lanes())
    }

    /// `PAIR_LANES` as a permutation of eight 32-bit lanes; it is its own inverse.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    fn pair_lanes() -> __m256i {
        _mm256_setr_epi32(0, 1, 4, 5, 2, 3, 6, 7)
    }

    /// A group's coordinates in [`PAIR_LANES`] order, in registers.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    fn pair_coordinates([u, v]: [F32x8; 2]) -> [__m256; 2] {
        let (u, v) = (u.to_m256(), v.to_m256());
        [_mm256_permutevar8x32_ps(u, pair_lanes()), _mm256_permutevar8x32_ps(v, pair_lanes())]
    }

    /// The texture's first cache line (see `sample_quad`).
    #[inline]
    fn first_line(texture: &Texture, line_shift: u32) -> u64 {
        (texture.id << 40) >> line_shift
    }

    /// A lane's four bytes (packed as a texel's) as `channel_to_f32` of bytes gives them,
    /// `c · fl(1/255)` per channel, back in the group's lanes (`pair_lanes` is its own inverse).
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    fn channels(packed: __m256i, pair_lanes: __m256i) -> Vec4x8 {
        let scale = _mm256_set1_ps(1.0 / 255.0);
        let byte_mask = _mm256_set1_epi32(0xff);
        let channel = |c: __m256i| {
            let value = _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_and_si256(c, byte_mask)), scale);
            F32x8::from_m256(_mm256_permutevar8x32_ps(value, pair_lanes))
        };
        [
            channel(packed),
            channel(_mm256_srli_epi32::<8>(packed)),
            channel(_mm256_srli_epi32::<16>(packed)),
            channel(_mm256_srli_epi32::<24>(packed)),
        ]
    }

    /// What eight lanes (in [`PAIR_LANES`] order) read on one level with the nearest filter:
    /// per lane the cache line (relative to the texture's first) and the texel index, and the
    /// largest index.
    struct NearestFootprint {
        lines: [u32; 8],
        indices: [u32; 8],
        largest: u32,
        /// Each lane's texel column and row (wrapped).
        x: __m256i,
        y: __m256i,
    }

    impl NearestFootprint {
        /// The lanes' texels, packed.
        #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
        #[inline]
        fn texels(&self, texels: &[u32]) -> __m256i {
            assert!(
                (self.largest as usize) < texels.len(),
                "texel {} of a footprint outside the texture's {} texels",
                self.largest,
                texels.len()
            );
            let words = lanes::<u32, 8>(|i| {
                // SAFETY: every index is at most `self.largest`, which the assertion above holds
                // below `texels.len()`: the fields are private to this module, and only
                // `nearest_footprint` builds one, with `largest` the unsigned maximum of all 8.
                unsafe { *texels.get_unchecked(self.indices[i] as usize) }
            });
            // SAFETY: 32 bytes of one `[u32; 8]`; unaligned loads need no alignment.
            unsafe { _mm256_loadu_si256(words.as_ptr().cast()) }
        }
    }

    /// The [`NearestFootprint`] of lanes at `(u, v)` on `level`, read with the `wraps` (repeat
    /// or clamp-to-edge), as `reduce_quad` then `nearest_texels` and the level's offsets give it.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    fn nearest_footprint(
        level: &Level,
        [u, v]: [__m256; 2],
        [wrap_u, wrap_v]: [Wrap; 2],
        line_shift: u32,
    ) -> NearestFootprint {
        let (x, y) = (nearest_axis(u, level.width, wrap_u), nearest_axis(v, level.height, wrap_v));
        let offset = _mm256_add_epi32(row_offset(level, y), column_offset(x));
        let index = _mm256_srli_epi32::<2>(offset);
        let line = _mm256_srl_epi32(offset, _mm_cvtsi32_si128(line_shift as i32));
        let mut footprint = NearestFootprint { lines: [0; 8], indices: [0; 8], largest: 0, x, y };
        // SAFETY: 32 bytes of one `[u32; 8]`; unaligned stores need no alignment.
        unsafe {
            _mm256_storeu_si256(footprint.lines.as_mut_ptr().cast(), line);
            _mm256_storeu_si256(footprint.indices.as_mut_ptr().cast(), index);
        }
        footprint.largest = largest_lane(index);
        footprint
    }

    /// The unsigned maximum of eight 32-bit lanes.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    fn largest_lane(lanes: __m256i) -> u32 {
        let largest = _mm_max_epu32(_mm256_castsi256_si128(lanes), _mm256_extracti128_si256::<1>(lanes));
        let largest = _mm_max_epu32(largest, _mm_shuffle_epi32::<0b01_00_11_10>(largest));
        let largest = _mm_max_epu32(largest, _mm_shuffle_epi32::<0b10_11_00_01>(largest));
        _mm_cvtsi128_si32(largest) as u32
    }

    /// [`Level::row_offset`] of eight rows (the texture's offsets are below 2^32,
    /// `MAX_MODELLED_BYTES`, so 32-bit lanes hold them).
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    fn row_offset(level: &Level, y: __m256i) -> __m256i {
        let block_row = _mm256_mullo_epi32(_mm256_srli_epi32::<2>(y), _mm256_set1_epi32((level.blocks_x * 64) as i32));
        let within = _mm256_slli_epi32::<4>(_mm256_and_si256(y, _mm256_set1_epi32(3)));
        _mm256_add_epi32(_mm256_add_epi32(_mm256_set1_epi32(level.address as i32), block_row), within)
    }

    /// [`Level::column_offset`] of eight columns.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    fn column_offset(x: __m256i) -> __m256i {
        let block = _mm256_slli_epi32::<6>(_mm256_srli_epi32::<2>(x));
        _mm256_add_epi32(block, _mm256_slli_epi32::<2>(_mm256_and_si256(x, _mm256_set1_epi32(3))))
    }

    /// One axis of [`nearest_footprint`]: the texel index, as `reduce_quad` then
    /// `nearest_texels` give it for a level `n` texels across: `⌊r · n⌋` of the reduced
    /// coordinate (in `[0, n]` for repeat, `[−n, 2n]` for clamp-to-edge, so `floor` and the
    /// conversion are exact), wrapped.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    fn nearest_axis(r: __m256, n: u32, wrap: Wrap) -> __m256i {
        let reduced = if wrap == Wrap::Repeat {
            // `u − ⌊u⌋`, NaN (of a NaN or an infinity) to +0, as in `axis`.
            let reduced = _mm256_sub_ps(r, _mm256_floor_ps(r));
            _mm256_and_ps(_mm256_cmp_ps::<_CMP_ORD_Q>(reduced, reduced), reduced)
        } else {
            // `u.clamp(−1, 2)`, NaN to +0, as in `axis`.
            let ordered = _mm256_cmp_ps::<_CMP_ORD_Q>(r, r);
            let reduced = _mm256_min_ps(_mm256_max_ps(r, _mm256_set1_ps(-1.0)), _mm256_set1_ps(2.0));
            _mm256_and_ps(ordered, reduced)
        };
        let i = _mm256_cvttps_epi32(_mm256_floor_ps(_mm256_mul_ps(reduced, _mm256_set1_ps(n as f32))));
        let n = _mm256_set1_epi32(n as i32);
        if wrap == Wrap::Repeat {
            // `i ∈ [0, n]`: `n` wraps to 0 (`wrap_reduced`'s `i − n`; `i < 0` cannot occur).
            _mm256_andnot_si256(_mm256_cmpeq_epi32(i, n), i)
        } else {
            let last = _mm256_sub_epi32(n, _mm256_set1_epi32(1));
            _mm256_min_epi32(_mm256_max_epi32(i, _mm256_setzero_si256()), last)
        }
    }

    /// What eight lanes (in [`PAIR_LANES`] order) read on one level bilinearly: per corner
    /// (`(x0, y0)`, `(x1, y0)`, `(x0, y1)`, `(x1, y1)`) and lane the cache line (relative to the
    /// texture's first) and the texel index, the weights `α` and `β`, and the largest index.
    struct Footprint {
        lines: [[u32; 8]; 4],
        indices: [__m256i; 4],
        alpha: __m256i,
        beta: __m256i,
        largest: u32,
    }

    /// The [`Footprint`] of lanes at `(u, v)` on `level`, read with the `wraps` (repeat or
    /// clamp-to-edge), as `reduce_quad` then `linear_texels_bytes` and the level's offsets give it.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    fn footprint(level: &Level, uv: [__m256; 2], wraps: [Wrap; 2], line_shift: u32) -> Footprint {
        footprint_with_box(level, uv, wraps, line_shift).0
    }

    /// [`footprint`], and each lane's texel columns `[x0, x1]` and rows `[y0, y1]` (wrapped),
    /// for [`edge_below`]: apart, so that the footprints a run keeps do not carry them.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    fn footprint_with_box(
        level: &Level,
        [u, v]: [__m256; 2],
        [wrap_u, wrap_v]: [Wrap; 2],
        line_shift: u32,
    ) -> (Footprint, [[__m256i; 2]; 2]) {
        let [x0, x1, alpha] = axis(u, level.width, wrap_u);
        let [y0, y1, beta] = axis(v, level.height, wrap_v);
        let (rows, columns) = ([row_offset(level, y0), row_offset(level, y1)], [column_offset(x0), column_offset(x1)]);
        let offsets = [
            _mm256_add_epi32(rows[0], columns[0]),
            _mm256_add_epi32(rows[0], columns[1]),
            _mm256_add_epi32(rows[1], columns[0]),
            _mm256_add_epi32(rows[1], columns[1]),
        ];
        let shift = _mm_cvtsi32_si128(line_shift as i32);
        let mut lines = [[0u32; 8]; 4];
        let index = |corner: usize| _mm256_srli_epi32::<2>(offsets[corner]);
        let indices = [index(0), index(1), index(2), index(3)];
        let mut largest = _mm256_setzero_si256();
        for (corner, &offset) in offsets.iter().enumerate() {
            largest = _mm256_max_epu32(largest, indices[corner]);
            // SAFETY: 32 bytes of one `[u32; 8]`; unaligned stores need no alignment.
            unsafe { _mm256_storeu_si256(lines[corner].as_mut_ptr().cast(), _mm256_srl_epi32(offset, shift)) };
        }
        let footprint = Footprint { lines, indices, alpha, beta, largest: largest_lane(largest) };
        (footprint, [[x0, x1], [y0, y1]])
    }

    /// The bottom edge of what the group two pixel rows below is likely to read, for
    /// [`super::prefetch_edge`]: the columns from the top-left lane's first `x0` to the
    /// bottom-right lane's last `x1`, on the bottom-right lane's last row `y1` moved down by
    /// twice the rows between the group's two pixel rows (lanes in [`PAIR_LANES`] order),
    /// clamped to the level.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    fn edge_below(level: &Level, [x0, x1]: [__m256i; 2], [y0, y1]: [__m256i; 2]) -> ([u32; 2], u32) {
        // Pair lane 0 is the group's top-left pixel, pair lane 2 the one below it, pair
        // lane 7 the bottom-right one (`PAIR_LANES`).
        let down = 2 * (_mm256_extract_epi32::<2>(y0) - _mm256_extract_epi32::<0>(y0));
        let y = (_mm256_extract_epi32::<7>(y1) + down).clamp(0, level.height as i32 - 1) as u32;
        ([_mm256_extract_epi32::<0>(x0) as u32, _mm256_extract_epi32::<7>(x1) as u32], y)
    }

    /// One axis of [`footprint`]: the texel indices `(i0, i1)` wrapped and the weight `α`, as
    /// `reduce_quad` then `linear_texels_bytes` give them for a level `n` texels across.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    fn axis(r: __m256, n: u32, wrap: Wrap) -> [__m256i; 3] {
        let nf = _mm256_set1_ps(n as f32);
        let minus_one = _mm256_set1_ps(-1.0);
        let scaled = if wrap == Wrap::Repeat {
            // `u − ⌊u⌋` (`roundps` floors exactly, as `floor`), NaN (of a NaN or an
            // infinity) to +0.
            let reduced = _mm256_sub_ps(r, _mm256_floor_ps(r));
            let reduced = _mm256_and_ps(_mm256_cmp_ps::<_CMP_ORD_Q>(reduced, reduced), reduced);
            _mm256_mul_ps(reduced, nf)
        } else {
            // Clamp-to-edge (the only other wrap admitted): `u.clamp(−1, 2)`, NaN to +0
            // (`maxps` gives its second operand for a NaN first one, then the mask zeroes
            // it); the scaled coordinate clamped to `[−1, n]` (no NaN left). For numbers,
            // `maxps`/`minps` are `clamp`'s comparisons, ties giving equal values.
            let ordered = _mm256_cmp_ps::<_CMP_ORD_Q>(r, r);
            let reduced = _mm256_min_ps(_mm256_max_ps(r, minus_one), _mm256_set1_ps(2.0));
            let reduced = _mm256_and_ps(ordered, reduced);
            let p = _mm256_mul_ps(reduced, nf);
            _mm256_min_ps(_mm256_max_ps(p, minus_one), nf)
        };
        // `round_small(p · 256) − 128`: a multiplication and an addition, not fused.
        let magic = _mm256_set1_ps(12_582_912.0);
        let shifted = _mm256_add_ps(_mm256_mul_ps(scaled, _mm256_set1_ps(256.0)), magic);
        let fixed =
            _mm256_sub_epi32(_mm256_castps_si256(shifted), _mm256_set1_epi32(12_582_912f32.to_bits() as i32 + 128));
        let i0 = _mm256_srai_epi32::<8>(fixed);
        let alpha = _mm256_and_si256(fixed, _mm256_set1_epi32(0xff));
        let i1 = _mm256_add_epi32(i0, _mm256_set1_epi32(1));
        let n = _mm256_set1_epi32(n as i32);
        let (x0, x1) = if wrap == Wrap::Repeat {
            let below = _mm256_cmpgt_epi32(_mm256_setzero_si256(), i0);
            let x0 = _mm256_blendv_epi8(i0, _mm256_add_epi32(i0, n), below);
            (x0, _mm256_andnot_si256(_mm256_cmpeq_epi32(i1, n), i1))
        } else {
            let (zero, last) = (_mm256_setzero_si256(), _mm256_sub_epi32(n, _mm256_set1_epi32(1)));
            let clamp = |i: __m256i| _mm256_min_epi32(_mm256_max_epi32(i, zero), last);
            (clamp(i0), clamp(i1))
        };
        [x0, x1, alpha]
    }

    /// The texels of `footprint` filtered ([`filter_bytes_packed`]), each lane's four bytes
    /// packed as a texel's.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    fn filter_footprint(texels: &[u32], footprint: &Footprint) -> __m256i {
        // Every index is at most `largest` (an unsigned maximum), held below the texels' count
        // and below 2^31, so that the gather's signed indices are the same numbers.
        assert!(
            (footprint.largest as usize) < texels.len() && footprint.largest <= i32::MAX as u32,
            "texel {} of a footprint outside the texture's {} texels",
            footprint.largest,
            texels.len()
        );
        let base = texels.as_ptr().cast::<i32>();
        // SAFETY: each lane reads the 4-byte texel `base + 4 · index`, with `index` one of the
        // footprint's (a `Footprint`'s fields are private to this module, and only `footprint`
        // builds one, with `largest` the unsigned maximum of all 32), so in bounds by the
        // assertion above; `vpgatherdd` needs no alignment.
        let gather = |corner: usize| unsafe { _mm256_i32gather_epi32::<4>(base, footprint.indices[corner]) };
        let corners = [gather(0), gather(1), gather(2), gather(3)];
        filter_bytes_lanes(corners, footprint.alpha, footprint.beta)
    }

    /// `lerp_bytes` of each byte of the packed texels `a` and `b` by its lane's weight (a
    /// 32-bit lane below 256), as [`filter_bytes_packed`] lerps them.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    fn lerp_packed(a: __m256i, b: __m256i, weight: __m256i) -> __m256i {
        let zero = _mm256_setzero_si256();
        let (spread_low, spread_high) = spreads();
        let low =
            lerp(_mm256_unpacklo_epi8(a, zero), _mm256_unpacklo_epi8(b, zero), _mm256_shuffle_epi8(weight, spread_low));
        let high = lerp(
            _mm256_unpackhi_epi8(a, zero),
            _mm256_unpackhi_epi8(b, zero),
            _mm256_shuffle_epi8(weight, spread_high),
        );
        _mm256_packus_epi16(low, high)
    }
}

/// How a texture's texels are held on the host, in the modelled block layout (see
/// `Texture::texels`).
#[derive(Clone, Debug)]
enum Texels {
    /// A linear texture's RGBA8 bytes, one little-endian word a texel (red in the low byte):
    /// 4 bytes a texel, so a 4×4 block is one 64-byte host line. The filter widens a channel
    /// at sampling, `c · 257` — the 16-bit UNORM the decoded form would hold.
    Packed(Vec<u32>),
    /// An sRGB texture's texels decoded for the filter: the four channels as the 16-bit
    /// UNORMs the filter works on (see the module notes), red and green in the first 32-bit
    /// word, blue and alpha in the second, each channel in the low half first — a colour
    /// channel through `color_table`, alpha `c · 257` — so sampling needs no table lookup per
    /// colour channel (three a texel read). 8 bytes a texel.
    Decoded(Vec<[u32; 2]>),
}

impl Texels {
    fn len(&self) -> usize {
        match self {
            Texels::Packed(t) => t.len(),
            Texels::Decoded(t) => t.len(),
        }
    }

    fn host_bytes(&self) -> usize {
        match self {
            Texels::Packed(t) => std::mem::size_of_val(t.as_slice()),
            Texels::Decoded(t) => std::mem::size_of_val(t.as_slice()),
        }
    }

    /// Texel `index` as the filter's two words (see [`Texels::Decoded`]).
    fn decoded(&self, index: usize) -> [u32; 2] {
        match self {
            Texels::Packed(t) => {
                let w = t[index];
                [TexelWords::word(&w, 0), TexelWords::word(&w, 1)]
            }
            Texels::Decoded(t) => t[index],
        }
    }

    /// Appends `other`'s texels (another layer or face of the same texture, so held alike).
    fn extend(&mut self, other: &Texels) {
        match (self, other) {
            (Texels::Packed(a), Texels::Packed(b)) => a.extend_from_slice(b),
            (Texels::Decoded(a), Texels::Decoded(b)) => a.extend_from_slice(b),
            _ => unreachable!("the layers and faces of a texture share its colour space, and so its layout"),
        }
    }

    fn reserve(&mut self, additional: usize) {
        match self {
            Texels::Packed(t) => t.reserve(additional),
            Texels::Decoded(t) => t.reserve(additional),
        }
    }
}

/// A texel as [`Texels`] holds it, read by the filter.
trait TexelWords: Copy + Default {
    /// Word `w` (0 or 1) of the decoded form: red | green << 16, or blue | alpha << 16, each a
    /// 16-bit UNORM. A packed texel widens its bytes, `(r | g << 16) · 257` (each byte times
    /// 257 is below 2^16, so no product carries into the other half): `c · 257`, as
    /// `Texture::store` decodes a linear channel.
    fn word(&self, w: usize) -> u32;
}

impl TexelWords for u32 {
    #[inline(always)]
    fn word(&self, w: usize) -> u32 {
        let bytes = *self >> (16 * w as u32);
        ((bytes & 0xff) | ((bytes & 0xff00) << 8)) * 257
    }
}

impl TexelWords for [u32; 2] {
    #[inline(always)]
    fn word(&self, w: usize) -> u32 {
        self[w]
    }
}

/// [`Texture::filter`] for texels held as `texels`.
#[inline(always)]
fn filter_texels<T: TexelWords, const N: usize>(texels: &[T], footprint: &Footprint<N>) -> [[u32; N]; 4] {
    // Word `w` of each lane's texel of `t`.
    let words = |t: &[T; N], w: usize| lanes::<u32, N>(|i| t[i].word(w));
    match footprint.filter {
        Filter::Nearest => {
            let [t0] = footprint_corners::<T, N, 1>(texels, footprint);
            let t = [words(&t0, 0), words(&t0, 1)];
            let channel = |c: u32| lanes(|i| texel_channel(t[c as usize / 2][i], c));
            [channel(0), channel(1), channel(2), channel(3)]
        }
        Filter::Linear => {
            let t = footprint_corners::<T, N, 4>(texels, footprint);
            let rg = [words(&t[0], 0), words(&t[1], 0), words(&t[2], 0), words(&t[3], 0)];
            let ba = [words(&t[0], 1), words(&t[1], 1), words(&t[2], 1), words(&t[3], 1)];
            let (alpha, beta) = (&footprint.alpha, &footprint.beta);
            [
                bilinear_channel(&rg, 0, alpha, beta),
                bilinear_channel(&rg, 1, alpha, beta),
                bilinear_channel(&ba, 2, alpha, beta),
                bilinear_channel(&ba, 3, alpha, beta),
            ]
        }
    }
}

/// [`Texture::filter`]'s linear filter of bytes ([`Footprint::bytes`]): each channel's byte
/// from the packed texels, [`lerp_bytes`] across, then down, as the 16-bit UNORM `c · 257`
/// the rest of the sampler carries (so [`blend`] and [`channel_to_f32`] take the byte back
/// exactly, `c · 257 >> 8 = c`).
#[inline(always)]
fn filter_bytes<const N: usize>(texels: &[u32], footprint: &Footprint<N>) -> [[u32; N]; 4] {
    let t = footprint_corners::<u32, N, 4>(texels, footprint);
    let (alpha, beta) = (&footprint.alpha, &footprint.beta);
    [
        bilinear_byte_channel(&t, 0, alpha, beta),
        bilinear_byte_channel(&t, 1, alpha, beta),
        bilinear_byte_channel(&t, 2, alpha, beta),
        bilinear_byte_channel(&t, 3, alpha, beta),
    ]
}

/// Channel `c` of [`filter_bytes`] (a function of its own, not a closure, which LLVM kept out
/// of line: 36 M instructions of helmet's frame in calls; see [`bilinear_channel`]).
#[inline(always)]
fn bilinear_byte_channel<const N: usize>(t: &[[u32; N]; 4], c: u32, alpha: &[u32; N], beta: &[u32; N]) -> [u32; N] {
    let byte = |k: usize| lanes::<u32, N>(|i| (t[k][i] >> (8 * c)) & 0xff);
    let (t00, t10, t01, t11) = (byte(0), byte(1), byte(2), byte(3));
    let top = lanes::<u32, N>(|i| lerp_bytes(t00[i], t10[i], alpha[i]));
    let bottom = lanes::<u32, N>(|i| lerp_bytes(t01[i], t11[i], alpha[i]));
    lanes(|i| lerp_bytes(top[i], bottom[i], beta[i]) * 257)
}

/// llvmpipe's 8-bit lerp (`lp_build_lerp` of 8-bit UNORMs with prescaled weights, through
/// `pmulhrsw`): `a + ((b − a) · w + 128) >> 8` for bytes `a`, `b` and `w ∈ [0, 256)` — the
/// formula of [`lerp`], on bytes.
#[inline(always)]
fn lerp_bytes(a: u32, b: u32, w: u32) -> u32 {
    lerp(a, b, w)
}

/// [`blend`] of two levels' channels (`[channel][lane]`) lane by lane, with each lane's
/// `weight`. A function, not a closure: a closure may be kept out of line, compiled for the
/// baseline instruction set (it was 3% of the helmet scene).
#[inline(always)]
fn blend_levels<const N: usize>(a: &[[u32; N]; 4], b: &[[u32; N]; 4], weight: &[u32; N], bytes: bool) -> [[u32; N]; 4] {
    let mut out = [[0; N]; 4];
    for c in 0..4 {
        for i in 0..N {
            out[c][i] = blend(a[c][i], b[c][i], weight[i], bytes);
        }
    }
    out
}

/// The blend of two levels (or slices) `a`, `b` (16-bit UNORMs) by the 8-bit weight `w`:
/// [`lerp`], or with `bytes` ([`QuadAt::bytes`]) [`lerp_bytes`] of their bytes.
#[inline(always)]
fn blend(a: u32, b: u32, w: u32, bytes: bool) -> u32 {
    if bytes { lerp_bytes(a >> 8, b >> 8, w) * 257 } else { lerp(a, b, w) }
}

/// A filtered channel (16-bit UNORM) as `f32`: with `bytes` ([`QuadAt::bytes`]; the channel
/// is then a byte `c` times 257) `c · fl(1/255)`, as llvmpipe converts an 8-bit UNORM
/// (`lp_build_unsigned_norm_to_float`: one multiplication, within an ulp of `c / 255` and
/// not always it); otherwise [`unorm16_to_f32`].
#[inline(always)]
fn channel_to_f32(c: u32, bytes: bool) -> f32 {
    if bytes { (c >> 8) as i32 as f32 * (1.0 / 255.0) } else { unorm16_to_f32(c) }
}

/// The largest of a footprint's texel indices, as plain loops: an iterator's `flatten` here
/// was left a loop of its own in some of the sampler's kernels (59 M instructions of
/// effect2d's replay).
#[inline(always)]
fn largest_texel<const N: usize>(texels: &[[u32; N]; 4]) -> u32 {
    let mut largest = [0u32; N];
    for corner in texels {
        for (m, &t) in largest.iter_mut().zip(corner) {
            *m = (*m).max(t);
        }
    }
    largest.into_iter().fold(0, u32::max)
}

/// Level 0 of a texture: its size in range and `rgba` its RGBA8 texels.
fn check_base(width: u32, height: u32, rgba: &[u8]) -> Result<()> {
    check_size(width, height, TexelFormat::Rgba8)?;
    let texel_count = width as usize * height as usize;
    if rgba.len() != texel_count * 4 {
        return Err(Error::invalid(
            "texture",
            format!("{} bytes of texels for {width}×{height} RGBA8, which needs {}", rgba.len(), texel_count * 4),
        ));
    }
    Ok(())
}

/// A level 0 size in range, and small enough that `format` stores its whole chain in 4 GiB
/// (a texture's stored offsets, and so its lines, then fit in 32 bits; only RGBA32F above
/// 11585² is refused by the second rule).
fn check_size(width: u32, height: u32, format: TexelFormat) -> Result<()> {
    if width == 0 || height == 0 || width > MAX_TEXTURE_DIMENSION || height > MAX_TEXTURE_DIMENSION {
        return Err(Error::invalid(
            "texture",
            format!("size {width}×{height} must be from 1×1 to {MAX_TEXTURE_DIMENSION}×{MAX_TEXTURE_DIMENSION}"),
        ));
    }
    format.validate()?;
    let layout = format.layout();
    let (mut w, mut h, mut stored) = (width, height, 0);
    loop {
        stored += layout.level_bytes(w, h);
        if w == 1 && h == 1 {
            break;
        }
        (w, h) = ((w / 2).max(1), (h / 2).max(1));
    }
    if stored > 1 << 32 {
        return Err(Error::invalid(
            "texture",
            format!("{width}×{height} {} with its mip chain takes {stored} bytes, more than 4 GiB", format.name()),
        ));
    }
    Ok(())
}

/// Channel `c` (16-bit UNORM) of a decoded texel's word that holds it (see `Texture::texels`).
#[inline(always)]
fn texel_channel(word: u32, c: u32) -> u32 {
    (word >> (16 * (c % 2))) & 0xffff
}

/// Channel `c` of the lanes' bilinear filter: `t` holds the word of the decoded texels with
/// channel `c`, `[corner][lane]`. (Each channel through a function of its own, not a loop,
/// which LLVM would vectorise across the channels of a texel instead.)
#[inline(always)]
fn bilinear_channel<const N: usize>(t: &[[u32; N]; 4], c: u32, alpha: &[u32; N], beta: &[u32; N]) -> [u32; N] {
    let corner = |k: usize| lanes::<u32, N>(|i| texel_channel(t[k][i], c));
    let (t00, t10, t01, t11) = (corner(0), corner(1), corner(2), corner(3));
    let top = lanes::<u32, N>(|i| lerp(t00[i], t10[i], alpha[i]));
    let bottom = lanes::<u32, N>(|i| lerp(t01[i], t11[i], alpha[i]));
    lanes(|i| lerp(top[i], bottom[i], beta[i]))
}

/// `a + (b − a) · w / 256` rounded to nearest, ties up, for 16-bit UNORMs `a`, `b` and an
/// 8-bit weight `w ∈ [0, 256)` (see the module notes): `a + ((b − a) · w + 128) >> 8`, which
/// is `(a · (256 − w) + b · w + 128) >> 8` with one multiplication (`a · 256` is a multiple of
/// 256, so it passes the shift unchanged), and so between `a` and `b`. `|b − a| · w < 2^24`.
#[inline(always)]
fn lerp(a: u32, b: u32, w: u32) -> u32 {
    let (a, b, w) = (a as i32, b as i32, w as i32);
    (a + (((b - a) * w + 128) >> 8)) as u32
}

/// A UNORM8 byte as the filter's 16-bit UNORM: `c · 257 / 65535 = c / 255` exactly.
#[inline(always)]
fn unorm8_to_unorm16(c: u32) -> u32 {
    c * 257
}

/// A 16-bit UNORM as `f32`: `c / 65535`, correctly rounded (for `c = 257 · b`, the same float
/// as `b / 255`).
#[inline(always)]
fn unorm16_to_f32(c: u32) -> f32 {
    c as i32 as f32 / 65535.0
}

per_simd_level! {
    /// [`Texture::sample`], compiled once per SIMD level: the sampler is called by every
    /// shader's pipeline, so it is not inlined into them, and without this its one copy
    /// would run the baseline's instructions under every pipeline.
    fn sample_group / sample_group_avx2 => sample_group_body, simd: simd, (
        simd: SimdSupport,
        texture: &Texture,
        sampler: &Sampler,
        uv: [F32x8; 2],
        counted: LaneMask,
        cache: &mut TextureCache,
        lookup: &Lookup,
    ) -> Vec4x8
}

#[inline(always)]
fn sample_group_body(
    simd: SimdSupport,
    texture: &Texture,
    sampler: &Sampler,
    [u, v]: [F32x8; 2],
    counted: LaneMask,
    cache: &mut TextureCache,
    lookup: &Lookup,
) -> Vec4x8 {
    // A kernel per layout: RGBA8 finds its lines from the decoded texels' offsets, other
    // formats from their stored layout (`STORED`), with no branch on the format in the RGBA8
    // kernel. The colour space needs none: the texels are held decoded. (The AVX2 bilinear
    // kernel is called before this, by `Texture::sample_with`.)
    match (texture.format == TexelFormat::Rgba8, texture.filters_bytes(sampler)) {
        (true, true) => texture.sample_layout::<false, true>(simd, sampler, u, v, counted, cache, lookup),
        (true, false) => texture.sample_layout::<false, false>(simd, sampler, u, v, counted, cache, lookup),
        (false, true) => texture.sample_layout::<true, true>(simd, sampler, u, v, counted, cache, lookup),
        (false, false) => texture.sample_layout::<true, false>(simd, sampler, u, v, counted, cache, lookup),
    }
}

/// The cache model's reads of a pair of quads on one level (`rows` a lane, [`PAIR_LANES`]
/// order): all eight lanes together, or, where a quad reads level 0 minified more than 2×
/// without mip maps (`minified_unmipped`), quad by quad, so that each such quad's misses are
/// noted apart ([`TextureCache::note_unmipped`]). What the pair path and the AVX2 kernel share.
#[inline(always)]
fn read_one_level(
    simd: SimdSupport,
    cache: &mut TextureCache,
    first_line: u64,
    rows: &[[u32; 8]],
    counted: [bool; 8],
    minified_unmipped: [bool; 2],
) {
    if !minified_unmipped.contains(&true) {
        cache.access_lanes(simd, first_line, rows, counted);
        return;
    }
    for quad in 0..2 {
        let mut quad_rows = [[0u32; 4]; MAX_LANE_LINES];
        for (out, row) in quad_rows.iter_mut().zip(rows) {
            *out = lanes(|i| row[4 * quad + i]);
        }
        let counted_quad: [bool; 4] = lanes(|i| counted[4 * quad + i]);
        let misses = cache.misses();
        cache.access_quad(simd, first_line, &quad_rows[..rows.len()], counted_quad);
        if minified_unmipped[quad] && counted_quad.contains(&true) {
            cache.note_unmipped(misses);
        }
    }
}

/// What both quads of a group read when their [`LevelPlan`]s name the same levels and
/// filter: then they are sampled side by side ([`Texture::sample_pair`]).
#[derive(Clone, Copy, Debug, PartialEq)]
enum PairPlan {
    Single {
        level: usize,
        filter: Filter,
    },
    /// `weights`: each quad's 8-bit weight of `level + 1`.
    Blend {
        level: usize,
        filter: Filter,
        weights: [u32; 2],
    },
}

impl PairPlan {
    /// The pair plan of two quads' plans, if they read the same levels with the same filter.
    #[inline(always)]
    fn of(plans: [LevelPlan; 2]) -> Option<PairPlan> {
        match plans {
            [LevelPlan::Single { level, filter }, LevelPlan::Single { level: level1, filter: filter1 }]
                if level == level1 && filter == filter1 =>
            {
                Some(PairPlan::Single { level, filter })
            }
            [
                LevelPlan::Blend { level, filter, weight },
                LevelPlan::Blend { level: level1, filter: filter1, weight: weight1 },
            ] if level == level1 && filter == filter1 => {
                Some(PairPlan::Blend { level, filter, weights: [weight, weight1] })
            }
            _ => None,
        }
    }
}

/// What a group's quads read ([`Texture::group_plan`]): `[quad 0, quad 1]` each.
#[derive(Clone, Copy, Debug)]
struct GroupPlan {
    /// Levels of detail, bias added.
    lambdas: [f32; 2],
    plans: [LevelPlan; 2],
    /// Reads of level 0 minified more than 2× without mip maps ([`TextureCache::note_unmipped`]).
    minified_unmipped: [bool; 2],
}

/// The lanes of a group as [`Texture::sample_pair`] orders them: quad 0's then quad 1's, each
/// in [`QUAD_LANES`] order. The permutation is its own inverse.
const PAIR_LANES: [usize; 8] = [0, 1, 4, 5, 2, 3, 6, 7];

/// A pair's channels (`[channel][lane in PAIR_LANES order]`, 16-bit UNORMs) back in the
/// group's lanes, converted eight lanes at a time.
#[inline(always)]
fn group_of_pair(rgba: [[u32; 8]; 4], bytes: bool) -> Vec4x8 {
    // The branch outside the lanes, so that each conversion is one loop the vectoriser sees.
    if bytes {
        let channel = |c: usize| F32x8::from_array(lanes(|lane| channel_to_f32(rgba[c][PAIR_LANES[lane]], true)));
        [channel(0), channel(1), channel(2), channel(3)]
    } else {
        let channel = |c: usize| F32x8::from_array(lanes(|lane| channel_to_f32(rgba[c][PAIR_LANES[lane]], false)));
        [channel(0), channel(1), channel(2), channel(3)]
    }
}

/// Four lanes of a quad, in [`QUAD_LANES`] order.
type Quad<T = f32> = [T; 4];

/// Where a quad's lanes sample: coordinates reduced for the wraps ([`reduce`]) and, per
/// lane, the modelled offset of the cube face it reads (0 for a 2D texture).
struct QuadAt<const N: usize = 4> {
    u: [f32; N],
    v: [f32; N],
    face_offsets: [u32; N],
    /// A constant texel offset added to the texel indices before they wrap (GLSL ES 3.00's
    /// `textureOffset`, GL ES 3.0 §3.8.10); 2D textures only, else `[0, 0]`.
    offset: [i32; 2],
    /// Filtered as bytes ([`Texture::filters_bytes`]): fixed-point coordinates and 8-bit
    /// lerps, as llvmpipe's AoS sampler.
    bytes: bool,
}

/// What a 2D lookup adds to [`Texture::sample`]'s plain one: GLSL ES 3.00's `textureGrad`
/// and `textureOffset`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Lookup {
    /// Explicit derivatives of `(u, v)` along window x and y, `[[du/dx, dv/dx], [du/dy,
    /// dv/dy]]`, in place of the quad's differences: each quad's level of detail is the
    /// one its first (top-left) lane's derivatives give, by the same formula.
    pub gradients: Option<[[F32x8; 2]; 2]>,
    /// Texels added to the texel indices on the level read, before the wrap (each within
    /// GL ES 3.0's `[−8, 7]`).
    pub offset: [i32; 2],
}

/// The two quads' channels (`[quad][channel][lane of the quad]`, 16-bit UNORMs) back in the
/// group's lanes, with constant indices (so shuffles, not a store per lane), converted eight
/// lanes at a time.
#[inline(always)]
fn group_of_quads(quads: [[Quad<u32>; 4]; 2], bytes: bool) -> Vec4x8 {
    let [left, right] = quads;
    std::array::from_fn(|c| {
        let group = std::array::from_fn(|lane| {
            let quad = if LANE_DX[lane] < 2 { &left } else { &right };
            quad[c][(LANE_DX[lane] % 2 + 2 * LANE_DY[lane]) as usize]
        });
        if bytes {
            F32x8::from_array(group.map(|c| channel_to_f32(c, true)))
        } else {
            F32x8::from_array(group.map(|c| channel_to_f32(c, false)))
        }
    })
}

/// What a quad reads on one level: per lane, its texels (indices into the texture's `texels`)
/// and the cache lines that hold them (relative to the texture's first line), both
/// `[corner][lane]`. Nearest filtering reads corner 0; linear filtering reads `(x0, y0)`,
/// `(x1, y0)`, `(x0, y1)`, `(x1, y1)` and weighs them with `α` and `β`.
struct Footprint<const N: usize = 4> {
    filter: Filter,
    /// Linear filtering of bytes ([`QuadAt::bytes`]); `alpha` and `beta` are then the fixed-point
    /// coordinates' low bytes.
    bytes: bool,
    texels: [[u32; N]; 4],
    lines: [[u32; N]; 4],
    /// The 8-bit weights of the second texel in x and in y.
    alpha: [u32; N],
    beta: [u32; N],
}

impl<const N: usize> Footprint<N> {
    /// The lines each lane reads, `[texel][lane]` in the order of its texels.
    #[inline(always)]
    fn rows(&self) -> &[[u32; N]] {
        match self.filter {
            Filter::Nearest => &self.lines[..1],
            Filter::Linear => &self.lines,
        }
    }
}

impl Level {
    /// A level at `address` in the decoded layout (its stored address is set by `Texture::store`).
    fn new(width: u32, height: u32, address: u64) -> Level {
        Level { width, height, address, blocks_x: width.div_ceil(BLOCK_TEXELS), stored_address: 0, stored_blocks_x: 0 }
    }

    /// Where the texture's format stores texel `(x, y)`, relative to the texture's modelled
    /// address (see [`StoredLayout`]): below `2^32` (`check_size`).
    #[inline(always)]
    fn stored_offset(&self, layout: &StoredLayout, x: u32, y: u32) -> u64 {
        let (bx, by) = (x / layout.block_width, y / layout.block_height);
        let block = by as u64 * self.stored_blocks_x as u64 + bx as u64;
        let within = ((y - by * layout.block_height) * layout.block_width + (x - bx * layout.block_width)) as u64;
        self.stored_address + block * layout.block_bytes as u64 + within * layout.texel_bytes as u64
    }

    /// Where texel `(x, y)` is in the texture's texels: its modelled address / 4.
    #[inline(always)]
    fn texel_index(&self, x: u32, y: u32) -> usize {
        ((self.row_offset(y) + self.column_offset(x)) as u64 / TEXEL_BYTES) as usize
    }

    /// Bytes of the level in the modelled block layout.
    fn modelled_bytes(&self) -> u64 {
        self.blocks_x as u64 * self.height.div_ceil(BLOCK_TEXELS) as u64 * BLOCK_BYTES
    }

    /// The modelled address of texel `(x, y)` relative to the texture's (see
    /// [`Texture::texel_address`]) is `row_offset(y) + column_offset(x)`, below 2^32
    /// ([`MAX_MODELLED_BYTES`]): the level's, plus the block row's and the row's within the block.
    #[inline(always)]
    fn row_offset(&self, y: u32) -> u32 {
        let block_row = y / BLOCK_TEXELS * self.blocks_x;
        self.address as u32 + block_row * BLOCK_BYTES as u32 + y % BLOCK_TEXELS * (BLOCK_TEXELS * TEXEL_BYTES as u32)
    }

    /// See [`Level::row_offset`]: the block column's offset and the column's within the block.
    #[inline(always)]
    fn column_offset(&self, x: u32) -> u32 {
        x / BLOCK_TEXELS * BLOCK_BYTES as u32 + x % BLOCK_TEXELS * TEXEL_BYTES as u32
    }
}

/// The texels of every level of a chain held row-major (`rows`, level `i` from `starts[i]`)
/// in the block layout, each converted by `texel`, level after level (levels are contiguous:
/// see `Level::new`'s callers); a block's texels past its level's edge are `pad`.
///
/// Written in order, block by block, with no zero fill first: a render target sampled pass
/// after pass is built this way each time, on the main thread while the workers wait for the
/// pass. A large level is built by rayon's threads — the device's when the caller runs inside
/// `Device::install` (the same texels, whoever builds them).
///
/// The blocks are written into `spare`'s memory when it is a whole number of blocks (as every
/// texture's is), grown as needed; its contents are not read.
fn block_texels<T: bytemuck::Pod + Send + Sync>(
    levels: &[Level],
    starts: &[usize],
    rows: &[[u8; 4]],
    pad: T,
    texel: impl Fn([u8; 4]) -> T + Sync,
    mut spare: Vec<T>,
) -> Vec<T> {
    use rayon::prelude::*;
    /// Texels of a level above which its blocks are built in parallel.
    const PARALLEL_TEXELS: usize = 1 << 16;
    const B: usize = BLOCK_TEXELS as usize;
    // Every level's blocks appended to one vector, in place (no level built apart first).
    let total = levels.iter().map(|l| (l.modelled_bytes() / BLOCK_BYTES) as usize).sum();
    spare.clear();
    let mut blocks: Vec<[T; B * B]> = bytemuck::allocation::try_cast_vec(spare).unwrap_or_default();
    blocks.reserve(total);
    for (level, &start) in levels.iter().zip(starts) {
        let (width, height) = (level.width as usize, level.height as usize);
        let level_rows = &rows[start..start + width * height];
        let blocks_x = level.blocks_x as usize;
        let block = |index: usize| -> [T; B * B] {
            let (x0, y0) = (index % blocks_x * B, index / blocks_x * B);
            if x0 + B <= width && y0 + B <= height {
                // Inside the level: four runs of four texels, each one slice (one bounds check,
                // a 16-byte move for bytes).
                let mut out = [pad; B * B];
                for (r, out) in out.chunks_exact_mut(B).enumerate() {
                    let start = (y0 + r) * width + x0;
                    let run: &[[u8; 4]; B] = level_rows[start..start + B].try_into().expect("four texels");
                    for (out, &t) in out.iter_mut().zip(run) {
                        *out = texel(t);
                    }
                }
                out
            } else {
                std::array::from_fn(|i| {
                    let (x, y) = (x0 + i % B, y0 + i / B);
                    if x < width && y < height { texel(level_rows[y * width + x]) } else { pad }
                })
            }
        };
        let count = blocks_x * height.div_ceil(B);
        if width * height >= PARALLEL_TEXELS {
            // An indexed iterator: rayon writes it straight into the vector's spare room.
            blocks.par_extend((0..count).into_par_iter().map(block));
        } else {
            blocks.extend((0..count).map(block));
        }
    }
    blocks.into_flattened()
}

/// Appends level `next` to the row-major `texels`, the 2×2 box filter of level `above`, whose
/// first texel is `above_start` (see [`MipChain::Box`]).
fn box_filter(texels: &mut Vec<[u8; 4]>, above_start: usize, above: &Level, next: &Level, color_space: ColorSpace) {
    let (w, h) = (above.width as usize, above.height as usize);
    let at = |x: usize, y: usize| above_start + y.min(h - 1) * w + x.min(w - 1);
    for y in 0..next.height as usize {
        for x in 0..next.width as usize {
            let quad = [at(2 * x, 2 * y), at(2 * x + 1, 2 * y), at(2 * x, 2 * y + 1), at(2 * x + 1, 2 * y + 1)]
                .map(|i| texels[i]);
            let texel: [u8; 4] = std::array::from_fn(|c| {
                if color_space == ColorSpace::Srgb && c < 3 {
                    let [a, b, cc, d] = quad.map(|t| srgb8_to_linear(t[c]));
                    unorm8(linear_to_srgb(((a + b) + (cc + d)) * 0.25))
                } else {
                    let sum: u32 = quad.iter().map(|t| t[c] as u32).sum();
                    ((sum + 2) >> 2) as u8
                }
            });
            texels.push(texel);
        }
    }
}

/// Appends the level `next` made from `above` by [`MipChain::Linear`]'s bilinear samples.
fn linear_filter(texels: &mut Vec<[u8; 4]>, above_start: usize, above: &Level, next: &Level, color_space: ColorSpace) {
    // Per destination coordinate along one side: the two source texels and the weight of the
    // second, in 256ths. `s = ((2x + 1)·w − n) / 2n`, computed exactly in integers.
    let taps = |from: u32, to: u32| -> Vec<(usize, usize, u32)> {
        (0..to as u64)
            .map(|x| {
                let (from, to) = (from as u64, to as u64);
                let numerator = (2 * x + 1) * from - to; // ≥ 0: from ≥ to
                let (whole, rest) = (numerator / (2 * to), numerator % (2 * to));
                let weight = (rest * 256 + to) / (2 * to); // round(rest / 2n · 256)
                let first = whole.min(from - 1) as usize;
                (first, (first + 1).min(from as usize - 1), weight as u32)
            })
            .collect()
    };
    let (xs, ys) = (taps(above.width, next.width), taps(above.height, next.height));
    let w = above.width as usize;
    for &(y0, y1, fy) in &ys {
        for &(x0, x1, fx) in &xs {
            let at = |x: usize, y: usize| texels[above_start + y * w + x];
            let quad = [at(x0, y0), at(x1, y0), at(x0, y1), at(x1, y1)];
            let texel: [u8; 4] = std::array::from_fn(|c| {
                if color_space == ColorSpace::Srgb && c < 3 {
                    let [a, b, cc, d] = quad.map(|t| srgb8_to_linear(t[c]));
                    let (wx, wy) = (fx as f32 / 256.0, fy as f32 / 256.0);
                    let top = a * (1.0 - wx) + b * wx;
                    let bottom = cc * (1.0 - wx) + d * wx;
                    unorm8(linear_to_srgb(top * (1.0 - wy) + bottom * wy))
                } else {
                    let [a, b, cc, d] = quad.map(|t| t[c] as u32);
                    lerp_bytes(lerp_bytes(a, b, fx), lerp_bytes(cc, d, fx), fy) as u8
                }
            });
            texels.push(texel);
        }
    }
}

/// The lanes of the two quads of a 4×2 group, upper-left, upper-right, lower-left, lower-right.
const QUAD_LANES: [[usize; 4]; 2] = [[0, 1, 4, 5], [2, 3, 6, 7]];

/// The level of detail of each quad before bias: `½ · fast_log2(ρ²)` from the upper-left
/// pixel's differences (see the module notes) of `(u, v)` on a `width × height` level 0.
#[cfg(test)]
fn quad_lods(u: F32x8, v: F32x8, width: f32, height: f32) -> [f32; 2] {
    quad_rho_squared(u, v, width, height).map(lod_of_rho_squared)
}

/// `ρ²` of each quad: the larger squared length of the upper-left pixel's differences in x
/// and in y, in texels of a `width × height` level 0 ([`quad_lods`] is `½ · fast_log2` of it).
/// Each difference is of the coordinates as given, then scaled (`(u₁ − u₀) · width`, as
/// llvmpipe's `lp_build_rho` orders it, not `u₁ · width − u₀ · width`).
/// Always inlined, as its quads are a function and not a closure: a closure of an inlined
/// function may be kept out of line, compiled for the baseline instruction set, and called
/// on every lookup (it was 6–8% of desktop.trace's replay).
#[inline(always)]
pub fn quad_rho_squared(u: F32x8, v: F32x8, width: f32, height: f32) -> [f32; 2] {
    #[inline(always)]
    fn quad(u: &F32x8, v: &F32x8, width: f32, height: f32, [tl, tr, bl, _]: [usize; 4]) -> f32 {
        let (dsdx, dtdx) = ((u.lane(tr) - u.lane(tl)) * width, (v.lane(tr) - v.lane(tl)) * height);
        let (dsdy, dtdy) = ((u.lane(bl) - u.lane(tl)) * width, (v.lane(bl) - v.lane(tl)) * height);
        (dsdx * dsdx + dtdx * dtdx).max(dsdy * dsdy + dtdy * dtdy)
    }
    [quad(&u, &v, width, height, QUAD_LANES[0]), quad(&u, &v, width, height, QUAD_LANES[1])]
}

/// llvmpipe's level-of-detail logarithm (`lp_build_fast_log2`, which its sampler takes for
/// `λ = ½ · log2(ρ²)`): `⌊log2 x⌋ − 1 + m` for `x = m · 2^⌊log2 x⌋`, `m` in `[1, 2)` — a
/// piecewise linear `log2`, exact at powers of two and up to 0.086 below the logarithm
/// between them — the sum rounded to `f32`. Bit operations on `x` as llvmpipe does them:
/// zero gives −127 (so it magnifies), an infinity or NaN 128 or a little more (so it takes
/// the last level). A few integer and float operations, no series.
#[inline(always)]
pub fn fast_log2(x: f32) -> f32 {
    let bits = x.to_bits();
    let exponent = ((bits >> 23) & 0xff) as i32 - 128;
    let mantissa = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000);
    exponent as f32 + mantissa
}

/// The level of detail before bias of a quad whose `ρ²` (squared texels per pixel) is
/// `rho_squared`: `½ · fast_log2(ρ²)` ([`fast_log2`]).
#[inline(always)]
pub fn lod_of_rho_squared(rho_squared: f32) -> f32 {
    0.5 * fast_log2(rho_squared)
}

/// `x.floor()`, exactly, without a call to the C library's `floorf` (which the baseline x86-64
/// target has no instruction for): values of magnitude 2^23 or more, and NaN and infinities,
/// are already integers (or not numbers) and come back unchanged, as do both zeros. Below
/// 2^23, `(|x| + 2^23) − 2^23` rounds `|x|` to an integer (f32 has no fraction bits there), so
/// with `x`'s sign it is within 1 of `x`, and one step down where it is above `x` gives `⌊x⌋`
/// (`+0` for `x` in `(0, 1)`). Float operations and selects only — no conversion to integers,
/// whose saturation keeps lanes of `as i32` from vectorising.
#[inline(always)]
fn floor(x: f32) -> f32 {
    const TWO_POW_23: f32 = 8_388_608.0;
    let magnitude = x.abs();
    let rounded = ((magnitude + TWO_POW_23) - TWO_POW_23).copysign(x);
    let below = if rounded > x { rounded - 1.0 } else { rounded };
    let unchanged = x.is_nan() || magnitude >= TWO_POW_23 || x == 0.0;
    if unchanged { x } else { below }
}

/// `(⌊x⌋, ⌊x⌋ as i32)` for `|x| < 2^22`, the first bit for bit [`floor`]: `x + 1.5 · 2^23`
/// lies in `[2^23, 2^24)`, where consecutive floats are consecutive integers, so it rounds `x`
/// to an integer whose value its bits count up from those of `1.5 · 2^23`; with `x`'s sign,
/// one step down where that is above `x` gives `⌊x⌋`. Unlike `as i32`, whose saturation keeps
/// lanes of it from vectorising, this is float and integer arithmetic only.
#[inline(always)]
fn floor_small(x: f32) -> (f32, i32) {
    const ONE_AND_A_HALF_POW_23: f32 = 12_582_912.0;
    debug_assert!(x.abs() < 4_194_304.0);
    let shifted = x + ONE_AND_A_HALF_POW_23;
    let rounded = (shifted - ONE_AND_A_HALF_POW_23).copysign(x);
    let above = rounded > x;
    let integer = shifted.to_bits() as i32 - ONE_AND_A_HALF_POW_23.to_bits() as i32 - above as i32;
    (if above { rounded - 1.0 } else { rounded }, integer)
}

/// Reduces `u` for the wrap mode so that scaling keeps sub-texel precision: repeat to
/// `[0, 1]`, mirrored repeat to `[0, 2]` (and `−2^-149`, whose half rounds to −0), clamp-to-edge
/// to `[−1, 2]` (past which nothing changes). NaN becomes 0.
#[inline(always)]
fn reduce(u: f32, wrap: Wrap) -> f32 {
    let r = match wrap {
        Wrap::Repeat => u - floor(u),
        Wrap::MirroredRepeat => u - 2.0 * floor(u * 0.5),
        Wrap::ClampToEdge => u.clamp(-1.0, 2.0),
    };
    if r.is_nan() { 0.0 } else { r }
}

/// Applies the wrap to texel index `i` of an axis of `n` texels, for the indices that reduced
/// coordinates (see [`reduce`]) give, where `i mod n` and `i mod 2n` need one correction at
/// most, no division. Repeat reduces to `[0, 1]`, so nearest filtering gives `⌊u · n⌋ ∈ [0, n]`
/// and linear `i0 ∈ [−1, n − 1]`, `i1 ∈ [0, n]`, inside `[−n, 2n)` where one correction by
/// `n` is `i mod n`. Mirrored repeat reduces to `[0, 2]` (and keeps `−2^-149`, whose half is
/// −0), so `i ∈ [−1, 2n]`, inside `[−2n, 4n)` where one correction by `2n` is `i mod 2n`.
/// Clamp-to-edge takes any `i`.
#[inline(always)]
fn wrap_reduced(i: i32, n: u32, wrap: Wrap) -> u32 {
    let n = n as i32;
    let wrapped = match wrap {
        Wrap::Repeat => {
            debug_assert!((-n..2 * n).contains(&i));
            if i < 0 {
                i + n
            } else if i >= n {
                i - n
            } else {
                i
            }
        }
        Wrap::ClampToEdge => i.clamp(0, n - 1),
        Wrap::MirroredRepeat => {
            debug_assert!((-2 * n..4 * n).contains(&i));
            let m = if i < 0 {
                i + 2 * n
            } else if i >= 2 * n {
                i - 2 * n
            } else {
                i
            };
            if m < n { m } else { 2 * n - 1 - m }
        }
    };
    wrapped as u32
}

/// The reduction of coordinates whose texels are then offset ([`Lookup::offset`]): repeat
/// and mirrored repeat reduce as without an offset (a whole period changes nothing), but
/// clamp-to-edge keeps `[−9, 10]`, so that an offset of up to 8 texels cannot bring a
/// clamped coordinate back inside (past `[−9, 10]` every index, offset or not, is outside).
/// Told apart from [`reduce`]'s by a wrap mode that is only a reduction.
#[inline(always)]
fn offset_reduction(wrap: Wrap) -> Reduction {
    match wrap {
        Wrap::ClampToEdge => Reduction::WideClamp,
        w => Reduction::Wrap(w),
    }
}

/// How coordinates are reduced before their texels are found.
#[derive(Clone, Copy)]
enum Reduction {
    Wrap(Wrap),
    /// Clamp to `[−9, 10]` (see [`offset_reduction`]).
    WideClamp,
}

impl From<Wrap> for Reduction {
    fn from(w: Wrap) -> Reduction {
        Reduction::Wrap(w)
    }
}

/// Wraps texel index `i` of an axis of `n` texels, any `i` (offset texels).
#[inline(always)]
fn wrap_any(i: i32, n: u32, wrap: Wrap) -> u32 {
    let n = n as i32;
    (match wrap {
        Wrap::Repeat => i.rem_euclid(n),
        Wrap::ClampToEdge => i.clamp(0, n - 1),
        Wrap::MirroredRepeat => {
            let m = i.rem_euclid(2 * n);
            if m < n { m } else { 2 * n - 1 - m }
        }
    }) as u32
}

/// [`nearest_texels`] with `offset` texels added before the wrap.
#[inline(always)]
fn nearest_texels_offset<const N: usize>(r: [f32; N], n: u32, wrap: Wrap, offset: i32) -> [u32; N] {
    lanes(|i| wrap_any(floor_small(r[i] * n as f32).1 + offset, n, wrap))
}

/// [`linear_texels`] (or with `bytes` [`linear_texels_bytes`]) with `offset` texels added
/// before the wrap.
#[inline(always)]
fn linear_texels_offset<const N: usize>(
    r: [f32; N],
    n: u32,
    wrap: Wrap,
    offset: i32,
    bytes: bool,
) -> ([[u32; N]; 2], [u32; N]) {
    if bytes {
        // `r` is in `[−9, 10]` (or `[0, 1]`), so `256 · r · n` below 2^31.
        let fixed = lanes::<i32, N>(|i| (r[i] * n as f32 * 256.0).round_ties_even() as i32 - 128);
        let x0 = lanes(|i| wrap_any((fixed[i] >> 8) + offset, n, wrap));
        let x1 = lanes(|i| wrap_any((fixed[i] >> 8) + offset + 1, n, wrap));
        return ([x0, x1], lanes(|i| (fixed[i] & 0xff) as u32));
    }
    let x = lanes::<f32, N>(|i| r[i] * n as f32 - 0.5);
    let floors = lanes::<(f32, i32), N>(|i| floor_small(x[i]));
    let alpha = lanes(|i| floor_small((x[i] - floors[i].0) * 256.0).1 as u32);
    let x0 = lanes(|i| wrap_any(floors[i].1 + offset, n, wrap));
    let x1 = lanes(|i| wrap_any(floors[i].1 + offset + 1, n, wrap));
    ([x0, x1], alpha)
}

/// Reduces a quad's coordinates for `wrap` ([`reduce`]).
#[inline(always)]
fn reduce_quad<const N: usize>(u: [f32; N], wrap: impl Into<Reduction>) -> [f32; N] {
    let wrap = match wrap.into() {
        Reduction::Wrap(w) => w,
        Reduction::WideClamp => return lanes(|i| if u[i].is_nan() { 0.0 } else { u[i].clamp(-9.0, 10.0) }),
    };
    match wrap {
        Wrap::Repeat => lanes(|i| reduce(u[i], Wrap::Repeat)),
        Wrap::ClampToEdge => lanes(|i| reduce(u[i], Wrap::ClampToEdge)),
        Wrap::MirroredRepeat => lanes(|i| reduce(u[i], Wrap::MirroredRepeat)),
    }
}

/// The texel indices for nearest filtering at reduced coordinates `r`: `⌊r · n⌋`, wrapped.
/// (`⌊r · n⌋` is in `[−1, 2n]`, see [`wrap_reduced`].)
#[inline(always)]
fn nearest_texels<const N: usize>(r: [f32; N], n: u32, wrap: Wrap) -> [u32; N] {
    let i = lanes::<i32, N>(|i| floor_small(r[i] * n as f32).1);
    match wrap {
        Wrap::Repeat => lanes(|k| wrap_reduced(i[k], n, Wrap::Repeat)),
        Wrap::ClampToEdge => lanes(|k| wrap_reduced(i[k], n, Wrap::ClampToEdge)),
        Wrap::MirroredRepeat => lanes(|k| wrap_reduced(i[k], n, Wrap::MirroredRepeat)),
    }
}

/// The two texel indices of each lane and the 8-bit weight of the second for linear filtering
/// at reduced coordinates `r`: `i0 = ⌊r · n − ½⌋`, `i1 = i0 + 1`, `α = ⌊256 · frac(r · n − ½)⌋`
/// (`frac` is exact in f32, `256 · frac` too, in `[0, 256)`), wrapped
/// as [`wrap_reduced`] does, with only the correction each can need: repeat and mirrored
/// repeat take `i0` from `[−1, p)` and `i1` from `[0, p]`, `p` the period (`n`, `2n`).
#[inline(always)]
fn linear_texels<const N: usize>(r: [f32; N], n: u32, wrap: Wrap) -> ([[u32; N]; 2], [u32; N]) {
    let x = lanes::<f32, N>(|i| r[i] * n as f32 - 0.5);
    let floors = lanes::<(f32, i32), N>(|i| floor_small(x[i]));
    let i0 = lanes::<i32, N>(|i| floors[i].1);
    let (n, alpha) = (n as i32, lanes(|i| floor_small((x[i] - floors[i].0) * 256.0).1 as u32));
    let mirror = |m: i32| if m < n { m } else { 2 * n - 1 - m };
    let (x0, x1): ([i32; N], [i32; N]) = match wrap {
        Wrap::Repeat => (
            lanes(|i| if i0[i] < 0 { i0[i] + n } else { i0[i] }),
            lanes(|i| if i0[i] + 1 == n { 0 } else { i0[i] + 1 }),
        ),
        Wrap::ClampToEdge => (lanes(|i| i0[i].clamp(0, n - 1)), lanes(|i| (i0[i] + 1).clamp(0, n - 1))),
        Wrap::MirroredRepeat => (
            lanes(|i| mirror(if i0[i] < 0 { i0[i] + 2 * n } else { i0[i] })),
            lanes(|i| mirror(if i0[i] + 1 == 2 * n { 0 } else { i0[i] + 1 })),
        ),
    };
    ([lanes(|i| x0[i] as u32), lanes(|i| x1[i] as u32)], alpha)
}

/// [`linear_texels`] for a byte filter ([`QuadAt::bytes`]), in fixed point as llvmpipe's AoS
/// sampler (`lp_build_sample_image_linear`): the coordinate in 1/256 texel,
/// `P = round(256 · fl(r · n)) − 128` (to nearest, ties to even: `cvtps2dq`), `i0 = P >> 8`,
/// `α = P & 255`, `i1 = i0 + 1`, wrapped as [`linear_texels`] wraps. (llvmpipe scales the
/// unreduced coordinate by `256n` for power-of-two sizes and clamp-to-edge, and takes
/// `fract` first otherwise; scaling by a power of two is exact, so both are this.) For
/// clamp-to-edge `r · n` is first clamped to `[−1, n]`, which changes no texel read (beyond,
/// both texels are the edge's, and the weight between equal texels does not matter) and keeps
/// `256 · r · n` within `2^22`, where [`round_small`] rounds.
#[inline(always)]
fn linear_texels_bytes<const N: usize>(r: [f32; N], n: u32, wrap: Wrap) -> ([[u32; N]; 2], [u32; N]) {
    let scaled = lanes::<f32, N>(|i| {
        let p = r[i] * n as f32;
        if wrap == Wrap::ClampToEdge { p.clamp(-1.0, n as f32) } else { p }
    });
    let fixed = lanes::<i32, N>(|i| round_small(scaled[i] * 256.0) - 128);
    let i0 = lanes::<i32, N>(|i| fixed[i] >> 8);
    let alpha = lanes(|i| (fixed[i] & 0xff) as u32);
    let n = n as i32;
    let (x0, x1): ([i32; N], [i32; N]) = match wrap {
        Wrap::Repeat => (
            lanes(|i| if i0[i] < 0 { i0[i] + n } else { i0[i] }),
            lanes(|i| if i0[i] + 1 == n { 0 } else { i0[i] + 1 }),
        ),
        Wrap::ClampToEdge => (lanes(|i| i0[i].clamp(0, n - 1)), lanes(|i| (i0[i] + 1).clamp(0, n - 1))),
        Wrap::MirroredRepeat => unreachable!("mirrored repeat is not filtered as bytes (`Texture::filters_bytes`)"),
    };
    ([lanes(|i| x0[i] as u32), lanes(|i| x1[i] as u32)], alpha)
}

/// `x` rounded to the nearest integer, ties to even, for `|x| ≤ 2^22`: `x + 1.5 · 2^23` lies
/// in `(2^23, 2^24]`, where floats are the integers, so the addition rounds `x` (to nearest
/// even, IEEE's default), and its bits count up from those of `1.5 · 2^23` (2^24 is the next
/// bit pattern after `2^24 − 1`). Float and integer arithmetic only, so it vectorises at every
/// SIMD level (see [`floor_small`]).
#[inline(always)]
fn round_small(x: f32) -> i32 {
    const ONE_AND_A_HALF_POW_23: f32 = 12_582_912.0;
    debug_assert!(x.abs() <= 4_194_304.0 || x.is_nan());
    (x + ONE_AND_A_HALF_POW_23).to_bits() as i32 - ONE_AND_A_HALF_POW_23.to_bits() as i32
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;
    use crate::shade::texture_cache::TextureCacheConfig;
    use crate::simd::{LANE_DX, LANE_DY, SimdLevel};

    /// The scalar reference of [`Texture::sample`]: the module's rules lane by lane, every
    /// texel read through [`Texture::texel_address`] and [`TextureCache::access`] one by one.
    fn reference_sample(
        texture: &Texture,
        sampler: &Sampler,
        u: F32x8,
        v: F32x8,
        counted: LaneMask,
        cache: &mut TextureCache,
    ) -> Vec4x8 {
        let lods = quad_lods(u, v, texture.width() as f32, texture.height() as f32);
        let bytes = reference_filters_bytes(texture, sampler);
        let mut out = [[0u32; 8]; 4];
        for (quad, lanes) in QUAD_LANES.iter().enumerate() {
            let plan = texture.plan(sampler, lods[quad] + sampler.lod_bias);
            for &lane in lanes {
                let count = counted.contains(lane);
                let (lu, lv) = (u.lane(lane), v.lane(lane));
                let level = |level, filter, cache: &mut TextureCache| {
                    reference_sample_level(texture, level, filter, sampler, lu, lv, count, cache)
                };
                let rgba = match plan {
                    LevelPlan::Single { level: l, filter } => level(l, filter, cache),
                    LevelPlan::Blend { level: l, filter, weight } => {
                        let a = level(l, filter, cache);
                        let b = level(l + 1, filter, cache);
                        if bytes {
                            std::array::from_fn(|c| reference_lerp(a[c] / 257, b[c] / 257, weight) * 257)
                        } else {
                            std::array::from_fn(|c| reference_lerp(a[c], b[c], weight))
                        }
                    }
                };
                for c in 0..4 {
                    out[c][lane] = rgba[c];
                }
            }
        }
        if bytes {
            // llvmpipe's conversion of an 8-bit UNORM: one multiplication by `fl(1/255)`.
            out.map(|c| F32x8::from_array(c.map(|c| (c / 257) as f32 * (1.0 / 255.0))))
        } else {
            out.map(|c| F32x8::from_array(c.map(|c| c as f32 / 65535.0)))
        }
    }

    /// Whether the reference filters `texture` as bytes (llvmpipe's AoS sampler): texels held
    /// as RGBA8 bytes (linear colour space, 8-bit channels) and no mirrored wrap.
    fn reference_filters_bytes(texture: &Texture, sampler: &Sampler) -> bool {
        matches!(texture.texels, Texels::Packed(_)) && ![sampler.wrap_u, sampler.wrap_v].contains(&Wrap::MirroredRepeat)
    }

    /// `a · (1 − w/256) + b · w/256` for 16-bit UNORMs, rounded to nearest, ties up.
    fn reference_lerp(a: u32, b: u32, w: u32) -> u32 {
        assert!(a <= 65535 && b <= 65535 && w < 256);
        (a * (256 - w) + b * w + 128) >> 8
    }

    /// One lane's filtered colour on one level, 16-bit UNORMs.
    // Kept flat: the scalar reference the SIMD sampler is tested against, written as the textbook
    // formula with each input named (texture, level, filter, sampler, coordinates, cache).
    #[allow(clippy::too_many_arguments)]
    fn reference_sample_level(
        texture: &Texture,
        level: usize,
        filter: Filter,
        sampler: &Sampler,
        u: f32,
        v: f32,
        count: bool,
        cache: &mut TextureCache,
    ) -> [u32; 4] {
        let l = texture.levels[level];
        let mut fetch = |x: u32, y: u32| {
            assert!(x < l.width && y < l.height);
            if count {
                cache.access(texture.texel_address(level, x, y));
            }
            let [r, g, b, a] = texture.texel(level, x, y);
            let color = |c: u8| match texture.color_space {
                ColorSpace::Linear => c as u32 * 257,
                ColorSpace::Srgb => (srgb8_to_linear(c) as f64 * 65535.0).round() as u32,
            };
            [color(r), color(g), color(b), a as u32 * 257]
        };
        match filter {
            Filter::Nearest => {
                let nearest = |u: f32, n: u32, wrap: Wrap| {
                    wrap_index(reference_floor(reference_reduce(u, wrap) * n as f32) as i64, n, wrap)
                };
                let (x, y) = (nearest(u, l.width, sampler.wrap_u), nearest(v, l.height, sampler.wrap_v));
                fetch(x, y)
            }
            Filter::Linear if reference_filters_bytes(texture, sampler) => {
                let (x0, x1, alpha) = reference_linear_indices_bytes(u, l.width, sampler.wrap_u);
                let (y0, y1, beta) = reference_linear_indices_bytes(v, l.height, sampler.wrap_v);
                let (t00, t10, t01, t11) = (fetch(x0, y0), fetch(x1, y0), fetch(x0, y1), fetch(x1, y1));
                // Bytes lerped, each lerp rounded to a byte.
                std::array::from_fn(|c| {
                    let top = reference_lerp(t00[c] / 257, t10[c] / 257, alpha);
                    let bottom = reference_lerp(t01[c] / 257, t11[c] / 257, alpha);
                    reference_lerp(top, bottom, beta) * 257
                })
            }
            Filter::Linear => {
                let (x0, x1, alpha) = reference_linear_indices(u, l.width, sampler.wrap_u);
                let (y0, y1, beta) = reference_linear_indices(v, l.height, sampler.wrap_v);
                let (t00, t10, t01, t11) = (fetch(x0, y0), fetch(x1, y0), fetch(x0, y1), fetch(x1, y1));
                std::array::from_fn(|c| {
                    let top = reference_lerp(t00[c], t10[c], alpha);
                    let bottom = reference_lerp(t01[c], t11[c], alpha);
                    reference_lerp(top, bottom, beta)
                })
            }
        }
    }

    /// The two texel indices and the 8-bit weight of the second for linear filtering:
    /// `i0 = ⌊u · n − ½⌋`, `i1 = i0 + 1`, `α = ⌊256 · frac(u · n − ½)⌋`, wrapped.
    fn reference_linear_indices(u: f32, n: u32, wrap: Wrap) -> (u32, u32, u32) {
        let x = reference_reduce(u, wrap) * n as f32 - 0.5;
        let base = reference_floor(x);
        let i0 = base as i64;
        (wrap_index(i0, n, wrap), wrap_index(i0 + 1, n, wrap), ((x - base) as f64 * 256.0).floor() as u32)
    }

    /// The byte filter's texel indices and weight, llvmpipe's fixed point written out in 64-bit
    /// integers: `P = round(256 · (r · n)) − 128` (`r · n` in `f32`, the rounding to nearest,
    /// ties to even), `i0 = ⌊P / 256⌋`, `α = P mod 256`, wrapped.
    fn reference_linear_indices_bytes(u: f32, n: u32, wrap: Wrap) -> (u32, u32, u32) {
        let scaled = reference_reduce(u, wrap) * n as f32;
        let fixed = (scaled as f64 * 256.0).round_ties_even() as i64 - 128;
        let i0 = fixed.div_euclid(256);
        (wrap_index(i0, n, wrap), wrap_index(i0 + 1, n, wrap), fixed.rem_euclid(256) as u32)
    }

    /// [`reduce`] with [`reference_floor`].
    fn reference_reduce(u: f32, wrap: Wrap) -> f32 {
        let r = match wrap {
            Wrap::Repeat => u - reference_floor(u),
            Wrap::MirroredRepeat => u - 2.0 * reference_floor(u * 0.5),
            Wrap::ClampToEdge => u.clamp(-1.0, 2.0),
        };
        if r.is_nan() { 0.0 } else { r }
    }

    /// [`floor`] by truncation to an integer.
    fn reference_floor(x: f32) -> f32 {
        if x.is_nan() || x.abs() >= 8_388_608.0 || x == 0.0 {
            return x;
        }
        let t = x as i32 as f32;
        if t > x { t - 1.0 } else { t }
    }

    /// Applies the wrap to any integer texel index along an axis of `n` texels.
    fn wrap_index(i: i64, n: u32, wrap: Wrap) -> u32 {
        wrap.texel(i, n)
    }

    /// A texture whose texel (x, y) of level 0 has red = x, green = y (as bytes).
    fn ramp(width: u32, height: u32, mips: MipChain) -> Texture {
        let mut data = Vec::new();
        for y in 0..height {
            for x in 0..width {
                data.extend_from_slice(&[x as u8, y as u8, 0, 255]);
            }
        }
        Texture::from_rgba8(width, height, &data, ColorSpace::Linear, mips).unwrap()
    }

    /// Samples every lane at the same (u, v), with no derivative (level 0 magnified).
    fn sample_at(texture: &Texture, sampler: &Sampler, u: f32, v: f32) -> [f32; 4] {
        let mut cache = TextureCache::default();
        let c =
            texture.sample(SimdSupport::BASELINE, sampler, F32x8::splat(u), F32x8::splat(v), LaneMask::ALL, &mut cache);
        [c[0].lane(0), c[1].lane(0), c[2].lane(0), c[3].lane(0)]
    }

    fn bytes(c: [f32; 4]) -> [f32; 4] {
        c.map(|v| v * 255.0)
    }

    /// A byte as the byte filter gives it: `c · fl(1/255)`, llvmpipe's conversion.
    fn unorm8(c: u32) -> f32 {
        c as f32 * (1.0 / 255.0)
    }

    /// One step of the filter's 16-bit UNORMs, in bytes (see [`bytes`]).
    const ONE_UNORM16: f32 = 255.0 / 65535.0;

    #[test]
    fn a_texture_built_in_the_memory_of_the_one_it_replaces_is_the_same() {
        let pseudo = |seed: u32, n: usize| -> Vec<u8> {
            (0..n as u32).map(|i| (i.wrapping_mul(2_654_435_761) ^ seed).to_le_bytes()[1]).collect()
        };
        for color_space in [ColorSpace::Linear, ColorSpace::Srgb] {
            for mips in [MipChain::BaseOnly, MipChain::Box] {
                // Old textures larger, smaller and of another colour space than the new one.
                for (old_w, old_h, old_space) in
                    [(37, 29, color_space), (5, 3, color_space), (20, 11, ColorSpace::Srgb)]
                {
                    let old = pseudo(7, old_w * old_h * 4);
                    let old = Texture::from_rgba8(old_w as u32, old_h as u32, &old, old_space, mips).unwrap();
                    let (w, h) = (21u32, 13u32);
                    let data = pseudo(99, (w * h * 4) as usize);
                    let fresh = Texture::from_rgba8(w, h, &data, color_space, mips).unwrap();
                    let again = Texture::from_rgba8_replacing(w, h, &data, color_space, mips, old).unwrap();
                    assert_eq!(again.levels(), fresh.levels());
                    assert_eq!(again.stored_bytes(), fresh.stored_bytes());
                    for level in 0..fresh.levels().len() {
                        assert_eq!(again.level_texels(level), fresh.level_texels(level), "level {level}");
                    }
                    assert_ne!(again.id, fresh.id, "a texture of its own");
                }
            }
        }
        let bad = Texture::from_rgba8_replacing(
            4,
            4,
            &[0; 12],
            ColorSpace::Linear,
            MipChain::BaseOnly,
            ramp(2, 2, MipChain::BaseOnly),
        );
        assert!(bad.is_err());
    }

    #[test]
    fn fast_log2_is_exact_on_powers_of_two_and_a_chord_between_them() {
        for e in -126..=127 {
            let x = 2f32.powi(e);
            assert_eq!(fast_log2(x), e as f32, "2^{e}");
        }
        // Linear between powers of two: 1.5 is half way from 0 to 1, 12 half way from 3 to 4.
        assert_eq!(fast_log2(1.5), 0.5);
        assert_eq!(fast_log2(12.0), 3.5);
        assert_eq!(fast_log2(9.0), 3.125);
        // Below the logarithm (a chord of a concave curve) by at most 1 − (1 + ln ln 2)/ln 2.
        let mut bits = 0x1234_5678u32;
        for _ in 0..20_000 {
            bits = bits.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            // Normal positive floats: exponents 1 to 254.
            let x = f32::from_bits((bits & 0x007f_ffff) | ((1 + (bits >> 23) % 254) << 23));
            let below = (x as f64).log2() - fast_log2(x) as f64;
            assert!((-1e-5..0.0861).contains(&below), "{x:e}: {below}");
        }
        // Bit operations as llvmpipe does them: zero magnifies, infinity and NaN minify.
        assert_eq!(fast_log2(0.0), -127.0);
        assert_eq!(fast_log2(f32::INFINITY), 128.0);
        assert!(fast_log2(f32::NAN) > 128.0);
    }

    #[test]
    fn bilinear_weights_follow_texel_centres() {
        let t = ramp(4, 4, MipChain::BaseOnly);
        let s = Sampler::BILINEAR_CLAMP;
        // Texel centres are at (i + 0.5) / 4: exactly on a centre gives that texel.
        assert_eq!(sample_at(&t, &s, 1.5 / 4.0, 2.5 / 4.0), [1, 2, 0, 255].map(unorm8));
        // A quarter of the way from texel 1 to 2 in u (weight 64: 1 + (64 + 128) >> 8 = 1),
        // half way from 0 to 1 in v (weight 128: 0 + (128 + 128) >> 8 = 1): bytes, each lerp
        // rounded to nearest, ties up.
        assert_eq!(sample_at(&t, &s, 1.75 / 4.0, 1.0 / 4.0), [1, 1, 0, 255].map(unorm8));
        // Three quarters: 1 + (192 + 128) >> 8 = 2.
        assert_eq!(sample_at(&t, &s, 2.25 / 4.0, 0.5 / 4.0)[0], unorm8(2));
        // Clamp-to-edge: below the first centre, the edge texel alone.
        assert_eq!(sample_at(&t, &s, 0.0, 0.0), [0, 0, 0, 255].map(unorm8));
        assert_eq!(sample_at(&t, &s, -3.0, 7.0), [0, 3, 0, 255].map(unorm8));
        // Mirrored repeat keeps the 16-bit filter: a quarter is 1.25 there.
        let mirrored = bytes(sample_at(&t, &s.with_wrap(Wrap::MirroredRepeat), 1.75 / 4.0, 1.0 / 4.0));
        assert!((mirrored[0] - 1.25).abs() < ONE_UNORM16 && (mirrored[1] - 0.5).abs() < ONE_UNORM16, "{mirrored:?}");
    }

    #[test]
    fn floor_matches_the_library() {
        for x in [0.0f32, -0.0, 0.5, -0.5, 1.0, -1.0, 2.75, -2.75, 8_388_607.5, -8_388_607.5, 1.0e10, -1.0e10, 3.0e38] {
            assert_eq!(floor(x).to_bits(), x.floor().to_bits(), "{x}");
        }
        assert!(floor(f32::NAN).is_nan());
        assert_eq!(floor(f32::NEG_INFINITY), f32::NEG_INFINITY);
    }

    #[test]
    fn floor_and_floor_small_match_truncation_everywhere() {
        // Every 97th bit pattern (all exponents, both signs, NaNs, infinities), and the
        // neighbours of the integers and half-integers where rounding could go wrong.
        let strided = (0..=u32::MAX / 97).map(|i| f32::from_bits(i * 97));
        let near_integers = (-4096..4096).flat_map(|i| {
            let x = i as f32 * 0.5;
            [x, f32::from_bits(x.to_bits() + 1), f32::from_bits(x.to_bits().wrapping_sub(1))]
        });
        for x in strided.chain(near_integers) {
            let (got, want) = (floor(x), reference_floor(x));
            assert!(got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()), "{x:e}: {got} vs {want}");
            if x.abs() < 4_194_304.0 {
                let (floor, integer) = floor_small(x);
                assert_eq!((floor.to_bits(), integer), (want.to_bits(), want as i32), "{x:e}");
            }
        }
    }

    #[test]
    fn unorm16_of_a_byte_is_the_unorm8_value() {
        for c in 0..256 {
            let value = unorm16_to_f32(unorm8_to_unorm16(c));
            assert_eq!(value.to_bits(), crate::api::format::UNORM8_TO_F32[c as usize].to_bits(), "{c}");
        }
    }

    #[test]
    fn lerp_is_the_rounded_weighted_mean() {
        for (a, b) in [(0, 65535), (65535, 0), (257, 514), (1000, 999), (12345, 54321), (7, 7)] {
            for w in 0..256 {
                assert_eq!(lerp(a, b, w), reference_lerp(a, b, w), "{a} {b} {w}");
                let exact = a as f64 + (b as f64 - a as f64) * w as f64 / 256.0;
                assert!((lerp(a, b, w) as f64 - exact).abs() <= 0.5, "{a} {b} {w}");
            }
        }
    }

    #[test]
    fn wraps_on_texel_indices() {
        for (i, repeat, clamp, mirror) in
            [(-1i64, 3u32, 0u32, 0u32), (-4, 0, 0, 3), (4, 0, 3, 3), (5, 1, 3, 2), (8, 0, 3, 0), (-5, 3, 0, 3)]
        {
            assert_eq!(wrap_index(i, 4, Wrap::Repeat), repeat, "repeat {i}");
            assert_eq!(wrap_index(i, 4, Wrap::ClampToEdge), clamp, "clamp {i}");
            assert_eq!(wrap_index(i, 4, Wrap::MirroredRepeat), mirror, "mirror {i}");
        }
    }

    #[test]
    fn sixteen_bit_texels_keep_their_sixteen_bits_without_a_chain() {
        // A 2×1 R16 texture of 10-bit samples in the low bits (as video players upload them):
        // sampled at each texel's centre it reads c / 65535, not the byte c would round to.
        let data: Vec<u8> = [1023u16, 517].iter().flat_map(|c| c.to_le_bytes()).collect();
        let t = Texture::from_encoded(TexelFormat::R16, 2, 1, &data, ColorSpace::Linear, MipChain::BaseOnly).unwrap();
        let nearest = Sampler::NEAREST_REPEAT;
        assert_eq!(sample_at(&t, &nearest, 0.25, 0.5), [1023.0 / 65535.0, 0.0, 0.0, 1.0]);
        assert_eq!(sample_at(&t, &nearest, 0.75, 0.5)[0], 517.0 / 65535.0);
        // Bilinear between them: the 16-bit values blended, not their bytes (both read as 4
        // and 2 in bytes).
        let mid = sample_at(&t, &Sampler::BILINEAR_CLAMP, 0.5, 0.5)[0] * 65535.0;
        assert!((mid - 770.0).abs() <= 1.0, "{mid}");
        // Its bytes are the nearest ones (GL read-backs and copies take those).
        assert_eq!(t.texel(0, 0, 0), [4, 0, 0, 255]);
        // With a chain (built from bytes), 8 bits: 1023 / 65535 is byte 4.
        let chained = Texture::from_encoded(TexelFormat::R16, 2, 1, &data, ColorSpace::Linear, MipChain::Box).unwrap();
        assert_eq!(sample_at(&chained, &nearest, 0.25, 0.5)[0], 4.0 / 255.0);
    }

    #[test]
    fn wrap_modes_when_sampling() {
        let t = ramp(4, 4, MipChain::BaseOnly);
        let nearest = Sampler::NEAREST_REPEAT;
        // u = 1.1 → 0.1 → texel 0 with repeat; mirrored: 1.1 → 0.9 → texel 3; clamp: texel 3.
        assert_eq!(sample_at(&t, &nearest, 1.1, 0.0)[0], 0.0);
        assert_eq!(sample_at(&t, &nearest.with_wrap(Wrap::MirroredRepeat), 1.1, 0.0)[0] * 255.0, 3.0);
        assert_eq!(sample_at(&t, &nearest.with_wrap(Wrap::ClampToEdge), 1.1, 0.0)[0], unorm8(3));
        // Bilinear repeat at u = 0 blends the last and the first texel half and half: 3 and 0
        // by the weight 128, 3 + (−3 · 128 + 128) >> 8 = 2 in bytes.
        assert_eq!(sample_at(&t, &Sampler::TRILINEAR_REPEAT, 0.0, 0.5 / 4.0)[0], unorm8(2));
        // Huge and non-finite coordinates are wrapped, never a panic.
        for u in [1.0e30f32, -1.0e30, f32::INFINITY, f32::NAN] {
            for wrap in [Wrap::Repeat, Wrap::ClampToEdge, Wrap::MirroredRepeat] {
                sample_at(&t, &Sampler::TRILINEAR_REPEAT.with_wrap(wrap), u, u);
            }
        }
    }

    #[test]
    fn linear_mip_chain_blends_odd_sides_like_a_linear_blit() {
        // 5×1 → 2×1: s = 0.25 and 2.75, so texel 0 is ¼·t0 + ¾·t1, texel 1 is ¾·t3 + ¼·t4.
        let row = |v: [u8; 5]| v.iter().flat_map(|&r| [r, 0, 0, 255]).collect::<Vec<u8>>();
        let t = Texture::from_rgba8(5, 1, &row([0, 40, 80, 120, 160]), ColorSpace::Linear, MipChain::Linear).unwrap();
        assert_eq!(t.level_texels(1), &[[30, 0, 0, 255], [130, 0, 0, 255]]);
        // 3 → 1 is the middle texel (as Mesa halves a 3×2 level; the box takes texels 0, 1).
        let t =
            Texture::from_rgba8(3, 1, &row([10, 50, 200, 0, 0])[..12], ColorSpace::Linear, MipChain::Linear).unwrap();
        assert_eq!(t.level_texels(1), &[[50, 0, 0, 255]]);
        let box_chain =
            Texture::from_rgba8(5, 1, &row([0, 40, 80, 120, 160]), ColorSpace::Linear, MipChain::Box).unwrap();
        assert_eq!(box_chain.level_texels(1), &[[20, 0, 0, 255], [100, 0, 0, 255]]);
        // Sides that halve exactly blend at weight 128, a byte lerp of the rows' byte lerps
        // (llvmpipe's); sRGB keeps the box in linear light.
        let data: Vec<u8> = (0..8 * 4 * 4).map(|i| (i * 37 % 251) as u8).collect();
        let linear = Texture::from_rgba8(8, 4, &data, ColorSpace::Linear, MipChain::Linear).unwrap();
        let boxed = Texture::from_rgba8(8, 4, &data, ColorSpace::Linear, MipChain::Box).unwrap();
        let half = |a: u8, b: u8| a as i32 + (((b as i32 - a as i32) * 128 + 128) >> 8);
        let (mut differ, mut texels) = (0, 0);
        // 8×4 → 4×2 → 2×1 halve both sides (then 2×1 → 1×1 only one).
        for level in 1..3 {
            let (above, l) = (linear.level_texels(level - 1), linear.levels()[level]);
            let w = linear.levels()[level - 1].width as usize;
            for y in 0..l.height as usize {
                for x in 0..l.width as usize {
                    let at = |dx: usize, dy: usize| above[(2 * y + dy) * w + 2 * x + dx];
                    let want: [u8; 4] = std::array::from_fn(|c| {
                        let top = half(at(0, 0)[c], at(1, 0)[c]);
                        let bottom = half(at(0, 1)[c], at(1, 1)[c]);
                        (top + (((bottom - top) * 128 + 128) >> 8)) as u8
                    });
                    assert_eq!(linear.level_texels(level)[y * l.width as usize + x], want, "level {level} ({x}, {y})");
                }
            }
            texels += l.width * l.height;
            differ +=
                (linear.level_texels(level).iter().zip(boxed.level_texels(level)).filter(|(a, b)| **a != *b)).count();
        }
        // Not the box: texels 0, 1 over 1, 2 lerp to rows 1 and 2, then 2; the box gives
        // (0 + 1 + 1 + 2 + 2) >> 2 = 1.
        assert!(differ > 0, "{differ} of {texels}");
        let srgb = Texture::from_rgba8(8, 4, &data, ColorSpace::Srgb, MipChain::Linear).unwrap();
        let srgb_box = Texture::from_rgba8(8, 4, &data, ColorSpace::Srgb, MipChain::Box).unwrap();
        for level in 0..srgb.levels().len() {
            assert_eq!(srgb.level_texels(level), srgb_box.level_texels(level), "sRGB level {level}");
        }
    }

    #[test]
    fn box_mip_chain_rounds_like_scenes_md() {
        // 3×1: level 1 is 1×1 of texels 0 and 1 (rows clamped): (a + b + a + b + 2) >> 2.
        let data = [10u8, 0, 0, 255, 13, 0, 0, 255, 200, 0, 0, 255];
        let t = Texture::from_rgba8(3, 1, &data, ColorSpace::Linear, MipChain::Box).unwrap();
        assert_eq!(t.levels().len(), 2);
        assert_eq!(t.level_texels(1), &[[12, 0, 0, 255]]); // (10+13+10+13+2)>>2 = 12
        let t = ramp(8, 4, MipChain::Box);
        let sizes: Vec<_> = t.levels().iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sizes, [(8, 4), (4, 2), (2, 1), (1, 1)]);
        // Level 1 texel (1, 0) averages x 2,3 and y 0,1: red (2+3+2+3+2)>>2 = 3, green 1.
        assert_eq!(t.level_texels(1)[1], [3, 1, 0, 255]);
    }

    #[test]
    fn srgb_decodes_before_filtering() {
        let data = [0u8, 0, 0, 255, 255, 255, 255, 255];
        let t = Texture::from_rgba8(2, 1, &data, ColorSpace::Srgb, MipChain::Box).unwrap();
        // Half way between black and white is linear 0.5 (sRGB 188), not byte 128 decoded.
        let c = sample_at(&t, &Sampler::BILINEAR_CLAMP, 0.5, 0.5);
        assert!((c[0] - 0.5).abs() < 1.0 / 65535.0, "{c:?}");
        assert_eq!(t.level_texels(1), &[[188, 188, 188, 255]]);
        let linear = Texture::from_rgba8(2, 1, &data, ColorSpace::Linear, MipChain::Box).unwrap();
        assert_eq!(linear.level_texels(1), &[[128, 128, 128, 255]]);
    }

    /// Samples a quad whose texel-space footprint steps `step` texels per pixel in u.
    fn lod_of(texture: &Texture, step: f32) -> f32 {
        let s = F32x8::from_fn(|i| crate::simd::LANE_DX[i] as f32 * step / texture.width() as f32);
        quad_lods(s, F32x8::ZERO, texture.width() as f32, texture.height() as f32)[0]
    }

    #[test]
    fn level_of_detail_from_quad_derivatives() {
        let t = ramp(64, 64, MipChain::Box);
        assert_eq!(lod_of(&t, 1.0), 0.0);
        assert_eq!(lod_of(&t, 2.0), 1.0);
        assert_eq!(lod_of(&t, 8.0), 3.0);
        // Between powers of two the logarithm is llvmpipe's chord: ρ² = 9 gives ½ · 3.125.
        assert_eq!(lod_of(&t, 3.0), 1.5625);
        // ρ is the longer of the two derivative vectors: (3, 4) texels per pixel in y gives
        // ρ² = 25, `fast_log2` 4 + 0.5625.
        let t_coord = F32x8::from_fn(|i| crate::simd::LANE_DY[i] as f32 * 4.0 / 64.0);
        let s_coord = F32x8::from_fn(|i| crate::simd::LANE_DY[i] as f32 * 3.0 / 64.0);
        assert_eq!(quad_lods(s_coord, t_coord, 64.0, 64.0)[0], 2.28125);

        let s = Sampler::TRILINEAR_REPEAT;
        assert_eq!(t.plan(&s, -1.0), LevelPlan::Single { level: 0, filter: Filter::Linear });
        assert_eq!(t.plan(&s, 0.0), LevelPlan::Single { level: 0, filter: Filter::Linear });
        assert_eq!(t.plan(&s, 1.25), LevelPlan::Blend { level: 1, filter: Filter::Linear, weight: 64 });
        // 8-bit weights truncate: 1.999 is 255/256 of the way to level 2.
        assert_eq!(t.plan(&s, 1.999), LevelPlan::Blend { level: 1, filter: Filter::Linear, weight: 255 });
        assert_eq!(t.plan(&s, 6.0), LevelPlan::Single { level: 6, filter: Filter::Linear });
        assert_eq!(t.plan(&s, 60.0), LevelPlan::Single { level: 6, filter: Filter::Linear });
        assert_eq!(t.plan(&s, f32::NAN), LevelPlan::Single { level: 0, filter: Filter::Linear });
        let nearest_mip = Sampler { mipmap: MipmapMode::Nearest, min_filter: Filter::Nearest, ..s };
        // Magnification up to λ = 0 whatever the filters (llvmpipe's c = 0), then λ rounded,
        // halves up.
        assert_eq!(t.plan(&nearest_mip, 0.0), LevelPlan::Single { level: 0, filter: Filter::Linear });
        assert_eq!(t.plan(&nearest_mip, 0.4), LevelPlan::Single { level: 0, filter: Filter::Nearest });
        assert_eq!(t.plan(&nearest_mip, 0.5), LevelPlan::Single { level: 1, filter: Filter::Nearest });
        assert_eq!(t.plan(&nearest_mip, 0.6), LevelPlan::Single { level: 1, filter: Filter::Nearest });
        assert_eq!(t.plan(&nearest_mip, 1.49), LevelPlan::Single { level: 1, filter: Filter::Nearest });
        assert_eq!(t.plan(&nearest_mip, 1.51), LevelPlan::Single { level: 2, filter: Filter::Nearest });
    }

    #[test]
    fn a_given_chain_is_sampled_as_given_and_a_box_chain_given_equals_the_box_chain() {
        // A 4×2 texture's chain given explicitly: 4×2, 2×1, 1×1, each level one colour.
        let level = |w: usize, h: usize, c: u8| [c, 0, 0, 255].repeat(w * h);
        let (l0, l1, l2) = (level(4, 2, 10), level(2, 1, 200), level(1, 1, 77));
        let t = Texture::from_rgba8_levels(4, 2, &[&l0, &l1, &l2], ColorSpace::Linear).unwrap();
        assert_eq!(t.levels().len(), 3);
        let nearest_mip = Sampler { mipmap: MipmapMode::Nearest, ..Sampler::NEAREST_REPEAT };
        for (lambda, red) in [(0.0, 10), (1.0, 200), (2.0, 77), (9.0, 77)] {
            assert_eq!(t.sample_lod(&nearest_mip, 0.3, 0.6, lambda)[0], unorm8(red), "λ = {lambda}");
        }
        // The box chain, given back level by level, is the same texture.
        let ramp = ramp(8, 4, MipChain::Box);
        let levels: Vec<Vec<u8>> =
            (0..ramp.levels().len()).map(|i| ramp.level_texels(i).into_iter().flatten().collect()).collect();
        let given: Vec<&[u8]> = levels.iter().map(Vec::as_slice).collect();
        let again = Texture::from_rgba8_levels(8, 4, &given, ColorSpace::Linear).unwrap();
        for i in 0..ramp.levels().len() {
            assert_eq!(again.level_texels(i), ramp.level_texels(i), "level {i}");
        }
        // A level of the wrong size, and a chain that stops early, are refused.
        let wrong = level(3, 1, 0);
        assert!(Texture::from_rgba8_levels(4, 2, &[&l0, &wrong, &l2], ColorSpace::Linear).is_err());
        let error = Texture::from_rgba8_levels(4, 2, &[&l0, &l1], ColorSpace::Linear).unwrap_err();
        assert!(error.to_string().contains("not at 1×1"), "{error}");
        assert!(Texture::from_rgba8_levels(4, 2, &[&l0, &l1, &l2, &l2], ColorSpace::Linear).is_err());
    }

    #[test]
    fn trilinear_blends_two_levels() {
        // 2×2 texture: level 0 texels 0, 100, 200, 40 in red; level 1 = (340 + 2) >> 2 = 85.
        let data = [0u8, 0, 0, 255, 100, 0, 0, 255, 200, 0, 0, 255, 40, 0, 0, 255];
        let t = Texture::from_rgba8(2, 2, &data, ColorSpace::Linear, MipChain::Box).unwrap();
        assert_eq!(t.level_texels(1), &[[85, 0, 0, 255]]);
        // u steps 1.5 texels per pixel: ρ² = 2.25, λ = ½ · fast_log2(2.25) = 0.5625 at the
        // centre of texel (0, 0).
        let u = F32x8::from_fn(|i| 0.25 + crate::simd::LANE_DX[i] as f32 * 0.75);
        let v = F32x8::splat(0.25);
        let mut cache = TextureCache::default();
        let c = t.sample(SimdSupport::BASELINE, &Sampler::TRILINEAR_REPEAT, u, v, LaneMask::ALL, &mut cache);
        // Blended in bytes by the 8-bit weight ⌊256 λ⌋ = 144: 0 + (85 · 144 + 128) >> 8 = 48.
        assert_eq!(c[0].lane(0), unorm8(48));
        // One point at the quad's level of detail reads what the quad's lane did, bit for bit.
        let quad_lambda = quad_lods(u, v, 2.0, 2.0)[0];
        assert_eq!(quad_lambda, 0.5625);
        let point = t.sample_lod(&Sampler::TRILINEAR_REPEAT, u.lane(0), v.lane(0), quad_lambda);
        assert_eq!(point.map(f32::to_bits), [0, 1, 2, 3].map(|ch| c[ch].lane(0).to_bits()));
    }

    #[test]
    fn a_point_at_a_given_level_of_detail_filters_as_a_quad_does() {
        let t = ramp(8, 8, MipChain::Box);
        let mut cache = TextureCache::default();
        for sampler in [Sampler::TRILINEAR_REPEAT, Sampler::BILINEAR_CLAMP, Sampler::NEAREST_REPEAT] {
            for (u, v) in [(0.3f32, 0.7f32), (0.0, 0.0), (1.4, -0.2), (0.51, 0.49)] {
                // λ = 0 (a vertex shader's fetch): the magnification filter on level 0, as a
                // quad without derivatives is sampled.
                let (uu, vv) = (F32x8::splat(u), F32x8::splat(v));
                let quad = t.sample(SimdSupport::BASELINE, &sampler, uu, vv, LaneMask::NONE, &mut cache);
                let point = t.sample_lod(&sampler, u, v, 0.0);
                assert_eq!(point.map(f32::to_bits), [0, 1, 2, 3].map(|c| quad[c].lane(0).to_bits()), "{u}, {v}");
            }
        }
        // Bilinear on level 0 half way between texels 2 and 3 of a row (the ramp's red is x):
        // 2 + (128 + 128) >> 8 = 3 in bytes.
        let c = t.sample_lod(&Sampler::BILINEAR_CLAMP, 3.0 / 8.0, 0.5 / 8.0, 0.0);
        assert_eq!(c[0], unorm8(3), "{c:?}");
        // Level 1 exactly with a nearest-mipmap filter, and past the last level the last one.
        let nearest_mip =
            Sampler { mipmap: MipmapMode::Nearest, min_filter: Filter::Nearest, ..Sampler::NEAREST_REPEAT };
        let level1 = t.level_texels(1)[0][0] as f32 / 255.0;
        assert_eq!(t.sample_lod(&nearest_mip, 0.01, 0.01, 1.0)[0], level1);
        let last = t.level_texels(t.levels().len() - 1)[0][0] as f32 / 255.0;
        assert_eq!(t.sample_lod(&nearest_mip, 0.01, 0.01, 40.0)[0], last);
        // No cache was touched: the lanes above were not counted, and points never are.
        assert_eq!(cache.misses() + cache.hits(), 0);
    }

    #[test]
    fn cache_counts_lines_not_texels() {
        let t = ramp(64, 64, MipChain::BaseOnly);
        let mut cache = TextureCache::new(TextureCacheConfig::DEFAULT);
        // Nearest sampling of every texel of a 4×4 block: 16 reads, one 64-byte line.
        for y in 0..4 {
            for x in 0..4 {
                let u = F32x8::splat((x as f32 + 0.5) / 64.0);
                let v = F32x8::splat((y as f32 + 0.5) / 64.0);
                t.sample(SimdSupport::BASELINE, &Sampler::NEAREST_REPEAT, u, v, LaneMask(1), &mut cache);
            }
        }
        assert_eq!((cache.misses(), cache.hits()), (1, 15));
        assert_eq!(cache.take_fetched_bytes(), 64);
        // Lanes outside `counted` read nothing through the cache.
        t.sample(
            SimdSupport::BASELINE,
            &Sampler::NEAREST_REPEAT,
            F32x8::splat(0.9),
            F32x8::splat(0.9),
            LaneMask::NONE,
            &mut cache,
        );
        assert_eq!(cache.misses() + cache.hits(), 16);
    }

    #[test]
    fn texels_come_back_as_given_from_their_blocks() {
        for (width, height) in [(1, 1), (3, 5), (4, 4), (7, 9), (37, 21)] {
            let rgba: Vec<u8> = (0..width * height * 4).map(|i| (i * 7 % 251) as u8).collect();
            let t = Texture::from_rgba8(width, height, &rgba, ColorSpace::Linear, MipChain::Box).unwrap();
            let given: Vec<[u8; 4]> = rgba.chunks_exact(4).map(|t| [t[0], t[1], t[2], t[3]]).collect();
            assert_eq!(t.level_texels(0), given, "{width}×{height}");
            for (x, y) in [(0, 0), (width - 1, 0), (0, height - 1), (width - 1, height - 1), (width / 2, height / 2)] {
                assert_eq!(t.texel(0, x, y), given[(y * width + x) as usize], "{width}×{height} ({x}, {y})");
                // Stored where its modelled address says.
                let index = ((t.texel_address(0, x, y) - t.texel_address(0, 0, 0)) / TEXEL_BYTES) as usize;
                assert_eq!(t.texel_bytes(index), given[(y * width + x) as usize]);
            }
        }
    }

    /// The block layout as `Level::texel_index` defines it, built texel by texel: every texel
    /// where its index says, every texel of a block past the level's edge zero. Sizes on both
    /// sides of the parallel build's threshold, odd edges, one level and a chain, both colour
    /// spaces.
    #[test]
    fn blocks_are_laid_out_texel_by_texel_with_zero_padding() {
        for (width, height) in [(1, 1), (5, 3), (16, 16), (301, 259), (256, 256)] {
            let rgba: Vec<u8> = (0..width * height * 4).map(|i| (i * 13 % 251 + 1) as u8).collect();
            for mips in [MipChain::BaseOnly, MipChain::Box] {
                let t = Texture::from_rgba8(width, height, &rgba, ColorSpace::Linear, mips).unwrap();
                let Texels::Packed(texels) = &t.texels else { panic!("a linear RGBA8 texture holds bytes") };
                let mut expected = vec![0u32; texels.len()];
                for (i, level) in t.levels.iter().enumerate() {
                    let given = t.level_texels(i);
                    for y in 0..level.height {
                        for x in 0..level.width {
                            expected[level.texel_index(x, y)] =
                                u32::from_le_bytes(given[(y * level.width + x) as usize]);
                        }
                    }
                }
                assert_eq!(*texels, expected, "{width}×{height} {mips:?}");
                let given: Vec<[u8; 4]> = rgba.chunks_exact(4).map(|t| [t[0], t[1], t[2], t[3]]).collect();
                assert_eq!(t.level_texels(0), given, "{width}×{height} {mips:?}");

                let srgb = Texture::from_rgba8(width, height, &rgba, ColorSpace::Srgb, mips).unwrap();
                assert_eq!(srgb.level_texels(0), given, "sRGB {width}×{height} {mips:?}");
                let Texels::Decoded(decoded) = &srgb.texels else { panic!("an sRGB texture holds decoded texels") };
                assert_eq!(decoded.len(), texels.len());
                // Padding is zero; every texel holds a non-zero alpha.
                for (index, (d, p)) in decoded.iter().zip(&expected).enumerate() {
                    assert_eq!(*d == [0, 0], *p == 0, "sRGB {width}×{height} {mips:?}: texel {index}");
                }
            }
        }
    }

    /// A run of lookups gives what the lookups one by one give, value for value, and reads the
    /// same lines in the same order: at every SIMD level, for samplers the byte kernel takes
    /// (bilinear, clamped or repeated) and others (nearest, trilinear), with partly counted
    /// lanes.
    #[test]
    fn a_run_of_lookups_is_the_lookups_one_by_one() {
        let t = ramp(37, 29, MipChain::Box);
        let uvs: Vec<[F32x8; 2]> = (0..9)
            .map(|k| {
                let u = F32x8::from_fn(|i| (k as f32 * 0.13 + i as f32 * 0.011) % 1.3 - 0.1);
                let v = F32x8::from_fn(|i| (k as f32 * 0.07 + (i / 2) as f32 * 0.017) % 1.1);
                [u, v]
            })
            .collect();
        let samplers = [
            Sampler::BILINEAR_CLAMP,
            Sampler::BILINEAR_CLAMP.with_wrap(Wrap::Repeat),
            Sampler::NEAREST_REPEAT,
            Sampler::TRILINEAR_REPEAT,
        ];
        for simd in [SimdSupport::BASELINE, SimdSupport::best()] {
            for sampler in samplers {
                for counted in [LaneMask(0xff), LaneMask(0x0f)] {
                    let (mut one, mut run) = (
                        TextureCache::new(TextureCacheConfig::DEFAULT),
                        TextureCache::new(TextureCacheConfig::DEFAULT),
                    );
                    let each: Vec<[[u32; 8]; 4]> = uvs
                        .iter()
                        .map(|&[u, v]| {
                            t.sample(simd, &sampler, u, v, counted, &mut one).map(|c| c.to_array().map(f32::to_bits))
                        })
                        .collect();
                    let mut out = vec![[[0.0f32; 8]; 4]; uvs.len()];
                    t.sample_run(simd, &sampler, &uvs, counted, &mut run, &mut out);
                    let out: Vec<[[u32; 8]; 4]> = out.iter().map(|t| t.map(|c| c.map(f32::to_bits))).collect();
                    assert_eq!(out, each, "{sampler:?} {counted:?}");
                    assert_eq!((run.misses(), run.hits()), (one.misses(), one.hits()), "{sampler:?} {counted:?}");
                    assert_eq!(run.take_fetched_bytes(), one.take_fetched_bytes());
                }
            }
        }
    }

    #[test]
    fn texel_addresses_are_blocked() {
        let t = ramp(16, 8, MipChain::Box);
        let base = t.texel_address(0, 0, 0);
        assert_eq!(t.texel_address(0, 1, 0) - base, 4);
        assert_eq!(t.texel_address(0, 0, 1) - base, 16);
        assert_eq!(t.texel_address(0, 4, 0) - base, 64);
        assert_eq!(t.texel_address(0, 0, 4) - base, 4 * 64);
        // Level 1 starts after level 0's 8 blocks.
        assert_eq!(t.texel_address(1, 0, 0) - base, 8 * 64);
    }

    #[test]
    fn bad_sizes_are_refused() {
        assert!(Texture::from_rgba8(0, 4, &[], ColorSpace::Linear, MipChain::Box).is_err());
        assert!(Texture::from_rgba8(2, 2, &[0; 15], ColorSpace::Linear, MipChain::Box).is_err());
        assert!(Texture::from_rgba8(MAX_TEXTURE_DIMENSION + 1, 1, &[], ColorSpace::Linear, MipChain::Box).is_err());
    }

    #[test]
    fn wrap_reduced_matches_the_general_wrap_where_reduced_coordinates_land() {
        for n in (1..=70).chain([255, 256, 4097, MAX_TEXTURE_DIMENSION]) {
            let n64 = n as i64;
            for i in -1..=n64 {
                assert_eq!(
                    wrap_reduced(i as i32, n, Wrap::Repeat),
                    wrap_index(i, n, Wrap::Repeat),
                    "repeat {i} of {n}"
                );
            }
            for i in -1..=2 * n64 {
                let mirror = Wrap::MirroredRepeat;
                assert_eq!(wrap_reduced(i as i32, n, mirror), wrap_index(i, n, mirror), "mirror {i} of {n}");
            }
            for i in -n64 - 1..=2 * n64 {
                let clamp = Wrap::ClampToEdge;
                assert_eq!(wrap_reduced(i as i32, n, clamp), wrap_index(i, n, clamp), "clamp {i} of {n}");
            }
        }
    }

    #[test]
    fn reduced_coordinates_give_the_indices_wrap_reduced_takes() {
        // At the edges of what f32 can do (−2^-149: its half underflows to −0, so mirrored
        // repeat keeps it, and nearest filtering takes index −1).
        let specials = [
            0.0f32,
            -0.0,
            -1.0e-10,
            1.0e-10,
            -f32::MIN_POSITIVE,
            -f32::from_bits(1),
            -f32::from_bits(2),
            1.0 - f32::EPSILON / 2.0,
            -(1.0 - f32::EPSILON / 2.0),
            1.0,
            -1.0,
            2.0,
            -2.0,
            8_388_607.5,
            -8_388_607.5,
            1.0e30,
            -1.0e30,
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ];
        for u in specials {
            for n in [1u32, 2, 3, 7, 64, 1000, MAX_TEXTURE_DIMENSION] {
                let n64 = n as i64;
                for (wrap, range) in [
                    (Wrap::Repeat, -1..=n64),
                    (Wrap::MirroredRepeat, -1..=2 * n64),
                    (Wrap::ClampToEdge, -n64 - 1..=2 * n64),
                ] {
                    let r = reduce(u, wrap);
                    let x = r * n as f32 - 0.5;
                    for i in [floor(r * n as f32) as i64, floor(x) as i64, floor(x) as i64 + 1] {
                        assert!(range.contains(&i), "{wrap:?} {u} of {n}: index {i}");
                    }
                }
            }
        }
    }

    #[test]
    fn line_offsets_match_texel_addresses() {
        let t = ramp(37, 21, MipChain::Box);
        for config in cache_configs() {
            let shift = TextureCache::new(config).line_shift();
            for (level, l) in t.levels().iter().enumerate() {
                for (x, y) in [(0, 0), (1, 0), (3, 3), (4, 0), (0, 4), (l.width - 1, l.height - 1)] {
                    let line = ((t.id << 40) >> shift) + ((l.row_offset(y) + l.column_offset(x)) >> shift) as u64;
                    assert_eq!(line, t.texel_address(level, x, y) >> shift, "level {level} ({x}, {y})");
                }
            }
        }
    }

    /// Cache shapes to count with: the default, direct mapped, lines smaller and larger than a
    /// 4×4 block, fully associative.
    fn cache_configs() -> [TextureCacheConfig; 5] {
        let config = |size_bytes, line_bytes, ways| TextureCacheConfig { size_bytes, line_bytes, ways };
        [TextureCacheConfig::DEFAULT, config(256, 64, 1), config(512, 16, 2), config(8192, 256, 4), config(1024, 4, 64)]
    }

    /// A coordinate for the oracle: mostly ordinary, sometimes at the edges of f32.
    fn coordinate() -> impl Strategy<Value = f32> {
        prop_oneof![
            8 => -3.0f32..3.0,
            1 => -1.0e6f32..1.0e6,
            1 => prop::sample::select(vec![
                0.0f32,
                -0.0,
                -1.0e-10,
                1.0,
                8_388_607.5,
                1.0e30,
                -1.0e30,
                f32::INFINITY,
                f32::NEG_INFINITY,
                f32::NAN
            ]),
        ]
    }

    /// A texel-space step per pixel from far magnified to far minified.
    fn step() -> impl Strategy<Value = f32> {
        prop_oneof![4 => -0.1f32..0.1, 4 => -1.5f32..1.5, 1 => -200.0f32..200.0, 1 => Just(0.0)]
    }

    /// One 4×2 group: a base coordinate and its derivatives per pixel (as a rasterizer gives),
    /// a lane replaced by an arbitrary coordinate at times, and the counted lanes.
    fn group() -> impl Strategy<Value = (F32x8, F32x8, LaneMask)> {
        (
            coordinate(),
            coordinate(),
            step(),
            step(),
            step(),
            step(),
            any::<u8>(),
            prop::option::of((0..8usize, coordinate(), coordinate())),
        )
            .prop_map(|(u0, v0, dudx, dvdx, dudy, dvdy, counted, odd)| {
                let at = |base: f32, dx: f32, dy: f32, i: usize| base + dx * LANE_DX[i] as f32 + dy * LANE_DY[i] as f32;
                let mut u: [f32; 8] = std::array::from_fn(|i| at(u0, dudx, dudy, i));
                let mut v: [f32; 8] = std::array::from_fn(|i| at(v0, dvdx, dvdy, i));
                if let Some((lane, ou, ov)) = odd {
                    (u[lane], v[lane]) = (ou, ov);
                }
                (F32x8::from_array(u), F32x8::from_array(v), LaneMask(counted))
            })
    }

    fn sampler() -> impl Strategy<Value = Sampler> {
        let filter = || prop::sample::select(vec![Filter::Nearest, Filter::Linear]);
        let wrap = || prop::sample::select(vec![Wrap::Repeat, Wrap::ClampToEdge, Wrap::MirroredRepeat]);
        let mipmap = prop::sample::select(vec![MipmapMode::None, MipmapMode::Nearest, MipmapMode::Linear]);
        let lod_bias = prop_oneof![3 => Just(0.0f32), 1 => -4.0f32..4.0];
        (filter(), filter(), mipmap, wrap(), wrap(), lod_bias).prop_map(
            |(mag_filter, min_filter, mipmap, wrap_u, wrap_v, lod_bias)| Sampler {
                mag_filter,
                min_filter,
                mipmap,
                wrap_u,
                wrap_v,
                wrap_w: wrap_v,
                lod_bias,
            },
        )
    }

    /// A texture of random texels: any texel read in the wrong place shows. Mostly RGBA8;
    /// other formats (whose lines the reference finds through `texel_address`, the stored
    /// layout) from random bytes — ASTC blocks made void-extent (constant, random colours).
    fn texture() -> impl Strategy<Value = Texture> {
        let color_space = prop::sample::select(vec![ColorSpace::Linear, ColorSpace::Srgb]);
        let mips = prop::sample::select(vec![MipChain::Box, MipChain::BaseOnly]);
        let format = prop_oneof![
            4 => Just(TexelFormat::Rgba8),
            1 => prop::sample::select(vec![
                TexelFormat::Rgb565,
                TexelFormat::Rgba16Float,
                TexelFormat::Rgba32Float,
                TexelFormat::Etc2Rgb8,
                TexelFormat::Etc2Rgba8,
                TexelFormat::Astc { block_width: 5, block_height: 5 },
                TexelFormat::Astc { block_width: 12, block_height: 10 },
            ]),
        ];
        (1u32..70, 1u32..70, color_space, mips, format, any::<u64>()).prop_map(
            |(width, height, color_space, mips, format, seed)| {
                let mut state = seed;
                let mut data: Vec<u8> = (0..format.data_bytes(width, height))
                    .map(|_| {
                        // SplitMix64.
                        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
                        let z = (state ^ (state >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
                        ((z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb) >> 56) as u8
                    })
                    .collect();
                if let TexelFormat::Astc { .. } = format {
                    for block in data.chunks_exact_mut(16) {
                        block[..8].copy_from_slice(&[0xfc, 0xfd, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff]);
                    }
                }
                Texture::from_encoded(format, width, height, &data, color_space, mips).unwrap()
            },
        )
    }

    /// Every SIMD level this processor runs.
    fn simd_levels() -> Vec<SimdSupport> {
        [SimdLevel::Baseline, SimdLevel::Avx2].into_iter().filter_map(SimdSupport::detect).collect()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]

        /// The quad-at-a-time sampler gives the reference's colours bit for bit at every SIMD
        /// level, and the cache model sees the same hits and misses after every group.
        #[test]
        fn sampling_matches_the_reference(
            texture in texture(),
            sampler in sampler(),
            config in prop::sample::select(cache_configs().to_vec()),
            simd in prop::sample::select(simd_levels()),
            groups in prop::collection::vec(group(), 1..24),
        ) {
            let (mut fast, mut reference) = (TextureCache::new(config), TextureCache::new(config));
            for (u, v, counted) in groups {
                let got = texture.sample(simd, &sampler, u, v, counted, &mut fast);
                let want = reference_sample(&texture, &sampler, u, v, counted, &mut reference);
                let bits = |c: Vec4x8| c.map(|c| c.to_array().map(f32::to_bits));
                prop_assert_eq!(bits(got), bits(want), "u {:?} v {:?}", u, v);
                prop_assert_eq!((fast.hits(), fast.misses()), (reference.hits(), reference.misses()));
            }
        }

        /// The same for the states `avx2::sample_bytes` and `avx2::sample_nearest_bytes` take
        /// (linear RGBA8, one filter — linear or nearest — for magnification and minification,
        /// repeat or clamp-to-edge), which the general strategies above draw a few times in
        /// 256: without mip maps (minified quads noted quad by quad, as the general path notes
        /// them), with the nearest level or two levels blended, at every SIMD level; and with
        /// explicit derivatives (`Lookup::gradients`, which the reference does not take), the
        /// same as the baseline's general path.
        #[test]
        fn byte_sampling_matches_the_reference(
            filter in prop::sample::select(vec![Filter::Linear, Filter::Nearest]),
            (width, height, seed) in (1u32..70, 1u32..70, any::<u64>()),
            mips in prop::sample::select(vec![MipChain::Box, MipChain::BaseOnly]),
            mipmap in prop::sample::select(vec![MipmapMode::None, MipmapMode::Nearest, MipmapMode::Linear]),
            wraps in prop::sample::select(vec![Wrap::Repeat, Wrap::ClampToEdge]).prop_flat_map(|u| (Just(u), prop::sample::select(vec![Wrap::Repeat, Wrap::ClampToEdge]))),
            lod_bias in prop_oneof![3 => Just(0.0f32), 1 => -4.0f32..4.0],
            config in prop::sample::select(cache_configs().to_vec()),
            simd in prop::sample::select(simd_levels()),
            groups in prop::collection::vec((group(), prop::option::of(group())), 1..24),
        ) {
            let mut state = seed;
            let data: Vec<u8> = (0..width * height * 4)
                .map(|_| {
                    state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
                    ((state ^ (state >> 29)).wrapping_mul(0xbf58_476d_1ce4_e5b9) >> 56) as u8
                })
                .collect();
            let texture = Texture::from_rgba8(width, height, &data, ColorSpace::Linear, mips).unwrap();
            let sampler = Sampler {
                mag_filter: filter,
                min_filter: filter,
                mipmap,
                wrap_u: wraps.0,
                wrap_v: wraps.1,
                wrap_w: wraps.1,
                lod_bias,
            };
            // The baseline's general path notes minified quads without mip maps as before.
            let baseline = SimdSupport::detect(SimdLevel::Baseline).unwrap();
            let mut fast = TextureCache::new(config);
            let (mut reference, mut general) = (TextureCache::new(config), TextureCache::new(config));
            let bits = |c: Vec4x8| c.map(|c| c.to_array().map(f32::to_bits));
            for ((u, v, counted), derivatives) in groups {
                // Derivatives: another group's differences from its first lane.
                let gradients = derivatives.map(|(du, dv, _)| {
                    let d = |c: F32x8, lanes: [usize; 2]| F32x8::from_fn(|i| c.lane(lanes[i % 2]) - c.lane(0));
                    [[d(du, [0, 1]), d(dv, [0, 1])], [d(du, [0, 4]), d(dv, [0, 4])]]
                });
                let lookup = Lookup { gradients, offset: [0, 0] };
                let got = texture.sample_with(simd, &sampler, u, v, counted, &mut fast, &lookup);
                let general_got = texture.sample_with(baseline, &sampler, u, v, counted, &mut general, &lookup);
                prop_assert_eq!(bits(got), bits(general_got), "u {:?} v {:?} {:?}", u, v, gradients);
                prop_assert_eq!((fast.hits(), fast.misses()), (general.hits(), general.misses()));
                prop_assert_eq!(fast.take_unmipped(), general.take_unmipped());
                if gradients.is_none() {
                    let want = reference_sample(&texture, &sampler, u, v, counted, &mut reference);
                    prop_assert_eq!(bits(got), bits(want), "u {:?} v {:?}", u, v);
                    prop_assert_eq!((fast.hits(), fast.misses()), (reference.hits(), reference.misses()));
                } else {
                    // The reference takes no derivatives: it goes on from the general path's cache.
                    reference = general.clone();
                }
            }
        }
    }
}
