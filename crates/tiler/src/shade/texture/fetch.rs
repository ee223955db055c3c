//! Reads by texel coordinates (GLSL ES 3.00's `texelFetch`, `textureSize`), and integer
//! textures, which nothing but such reads and nearest lookups ever touch.
//!
//! - **`texelFetch`** (OpenGL ES 3.0 §3.8.10, GLSL ES 3.00 §8.8): texel `(x, y)` of level `lod`
//!   (layer or slice `z` of a 2-D array or 3-D texture), unfiltered, no wrap. Coordinates or
//!   a level out of range give undefined results in GL; here, as in llvmpipe (its
//!   `lp_build_fetch_texel` selects zero for out-of-bounds texels), they read `(0, 0, 0, 0)`
//!   and touch no memory. A texel read goes through the texture-cache model like a filter's
//!   (the ledger's `texture fetch`), for the lanes of every quad with a covered pixel.
//! - **`textureSize`**: level `lod`'s width and height (`max(1, ⌊w / 2^lod⌋)`), and a 2-D
//!   array's layer count or a 3-D texture's depth; a level the texture lacks reads 0 (as
//!   llvmpipe's size query does for an out-of-range level).
//! - **Integer textures** ([`IntegerTexture`], GL's `RGBA8UI`, `R32I`, …) keep each texel's
//!   channels as 32-bit patterns, zero- or sign-extended from the stored bits, which the
//!   shader reads as `uint`s or `int`s. GL never filters them (a linear filter makes them
//!   incomplete, §3.8.13; the GL layer refuses that); a lookup by normalised coordinates
//!   (`texture` on an `isampler2D`) reads the nearest texel of level 0 with the sampler's
//!   wraps. They are modelled as stored in their own format, 4×4 texels a block as every
//!   uncompressed format (`texel_format::StoredLayout`), so a fetch counts the lines the
//!   stored bytes occupy.

use super::*;
use crate::api::format::IntFormat;

impl Texture {
    /// `texelFetch`: texel `(x, y)` of level `level`, of layer or slice `z` if the texture is
    /// layered (else `z` must be 0), decoded as the filter decodes it (the value a nearest
    /// lookup of it gives), with its modelled address; `None` out of range (see the module
    /// notes). A cube texture has no texel fetch in GL: `None`.
    pub fn fetch(&self, level: i32, [x, y, z]: [i32; 3]) -> Option<([f32; 4], u64)> {
        if self.is_cube() {
            return None;
        }
        let l = self.levels.get(usize::try_from(level).ok()?)?;
        let count = self.layers.map_or(1, |l| l.count);
        let (x, y, z) = (u32::try_from(x).ok()?, u32::try_from(y).ok()?, u32::try_from(z).ok()?);
        if x >= l.width || y >= l.height || z >= count {
            return None;
        }
        let index = self.layer_offset(z) as usize / TEXEL_BYTES as usize + l.texel_index(x, y);
        let texel = self.texels.decoded(index);
        // A stored byte `c` reads `c · fl(1/255)`, as llvmpipe converts it (probe
        // `tools/float-probe/fetch.frag`); other texels their 16-bit UNORM.
        let bytes = self.holds_bytes();
        let value = std::array::from_fn(|c| channel_to_f32(texel_channel(texel[c / 2], c as u32), bytes));
        Some((value, self.layer_texel_address(z, level as usize, x, y)))
    }

    /// `textureSize` at level `level`: width, height and layers (or depth; 1 for a 2D or cube
    /// texture); zeros for a level it lacks.
    pub fn size(&self, level: i32) -> [u32; 3] {
        match usize::try_from(level).ok().and_then(|level| self.levels.get(level)) {
            Some(l) => [l.width, l.height, self.layers.map_or(1, |l| l.count)],
            None => [0; 3],
        }
    }
}

/// What an integer texture's third coordinate is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IntegerKind {
    /// A 2D texture (`isampler2D`).
    Flat,
    /// A 2-D array (`isampler2DArray`) or a 3-D texture (`isampler3D`) of this many layers or
    /// slices; a 3-D one has level 0 only.
    Layered(LayeredKind, u32),
}

/// A texture of integers (see the module notes).
#[derive(Clone, Debug)]
pub struct IntegerTexture {
    id: u64,
    format: IntFormat,
    kind: IntegerKind,
    /// Each level's width and height, its first texel in `texels` and its modelled address
    /// relative to its layer's chain.
    levels: Vec<IntegerLevel>,
    /// Bytes of one layer's chain in the modelled memory.
    layer_bytes: u64,
    /// Layer after layer, level after level, rows top (GL's first) to bottom.
    texels: Vec<[u32; 4]>,
}

#[derive(Clone, Copy, Debug)]
struct IntegerLevel {
    width: u32,
    height: u32,
    first: usize,
    address: u64,
}

impl IntegerTexture {
    /// A texture of `format` from its levels, level 0 first (each `max(1, ⌊w / 2^i⌋) ×
    /// max(1, ⌊h / 2^i⌋)` texels a layer, layer after layer, rows in GL's order, channels as
    /// `format` stores them).
    ///
    /// # Errors
    /// A zero or too large size, no level or more than the chain has, a level's data of the
    /// wrong length, or levels below 0 of a 3-D texture.
    pub fn new(
        format: IntFormat,
        kind: IntegerKind,
        width: u32,
        height: u32,
        given: &[&[u8]],
    ) -> Result<IntegerTexture> {
        let what = format!("{} texture", format.name());
        let count = match kind {
            IntegerKind::Flat => 1,
            IntegerKind::Layered(LayeredKind::Array, n) if (1..=MAX_ARRAY_LAYERS).contains(&n) => n,
            IntegerKind::Layered(LayeredKind::Volume, n) if (1..=MAX_VOLUME_DIMENSION).contains(&n) => n,
            IntegerKind::Layered(_, n) => return Err(Error::invalid(what, format!("{n} layers are out of range"))),
        };
        if width == 0 || height == 0 || width > MAX_TEXTURE_DIMENSION || height > MAX_TEXTURE_DIMENSION {
            return Err(Error::invalid(
                what,
                format!("size {width}×{height}: each side must be from 1 to {MAX_TEXTURE_DIMENSION}"),
            ));
        }
        let chain = 32 - width.max(height).leading_zeros() as usize;
        if given.is_empty() || given.len() > chain {
            return Err(Error::invalid(what, format!("{} levels (1 to {chain})", given.len())));
        }
        if given.len() > 1 && matches!(kind, IntegerKind::Layered(LayeredKind::Volume, _)) {
            return Err(Error::invalid(what, "a 3-D integer texture with mip levels is not supported".to_string()));
        }
        let bytes = format.bytes() as u64;
        let (mut levels, mut address, mut texel_count) = (Vec::new(), 0u64, 0usize);
        for i in 0..given.len() {
            let (w, h) = ((width >> i).max(1), (height >> i).max(1));
            levels.push(IntegerLevel { width: w, height: h, first: texel_count, address });
            address += w.div_ceil(BLOCK_TEXELS) as u64 * h.div_ceil(BLOCK_TEXELS) as u64 * 16 * bytes;
            texel_count += w as usize * h as usize;
        }
        let layer_bytes = address.next_multiple_of(64);
        if layer_bytes * count as u64 >= 1 << 40 {
            return Err(Error::invalid(what, format!("{width}×{height}×{count} is too large")));
        }
        let mut texels = Vec::with_capacity(texel_count * count as usize);
        for layer in 0..count as usize {
            for (i, (level, data)) in levels.iter().zip(given).enumerate() {
                let layer_len = level.width as usize * level.height as usize * bytes as usize;
                if data.len() != layer_len * count as usize {
                    return Err(Error::invalid(
                        what,
                        format!("level {i}: {} bytes of texels, not {}", data.len(), layer_len * count as usize),
                    ));
                }
                let layer_data = &data[layer * layer_len..(layer + 1) * layer_len];
                texels.extend(layer_data.chunks_exact(bytes as usize).map(|t| format.unpack(t)));
            }
        }
        Ok(IntegerTexture {
            id: NEXT_TEXTURE_ID.fetch_add(1, Ordering::Relaxed),
            format,
            kind,
            levels,
            layer_bytes,
            texels,
        })
    }

    pub fn format(&self) -> IntFormat {
        self.format
    }

    pub fn kind(&self) -> IntegerKind {
        self.kind
    }

    pub fn width(&self) -> u32 {
        self.levels[0].width
    }

    pub fn height(&self) -> u32 {
        self.levels[0].height
    }

    /// Mip levels it has.
    pub fn level_count(&self) -> usize {
        self.levels.len()
    }

    fn layers(&self) -> u32 {
        match self.kind {
            IntegerKind::Flat => 1,
            IntegerKind::Layered(_, n) => n,
        }
    }

    /// Bytes the texture occupies in external memory (every level and layer, as stored).
    pub fn stored_bytes(&self) -> u64 {
        self.texels.len() as u64 * self.format.bytes() as u64
    }

    /// `texelFetch` (see the module notes): the channels' 32-bit patterns of texel `(x, y)` of
    /// level `level` (layer or slice `z`), with its modelled address; `None` out of range.
    pub fn fetch(&self, level: i32, [x, y, z]: [i32; 3]) -> Option<([u32; 4], u64)> {
        let l = self.levels.get(usize::try_from(level).ok()?)?;
        let (x, y, z) = (u32::try_from(x).ok()?, u32::try_from(y).ok()?, u32::try_from(z).ok()?);
        if x >= l.width || y >= l.height || z >= self.layers() {
            return None;
        }
        let layer_texels = self.texels.len() / self.layers() as usize;
        let value = self.texels[z as usize * layer_texels + l.first + (y * l.width + x) as usize];
        let (block, within) = ((y / 4) * l.width.div_ceil(4) + x / 4, (y % 4) * 4 + x % 4);
        let bytes = self.format.bytes() as u64;
        let offset = l.address + block as u64 * 16 * bytes + within as u64 * bytes;
        Some((value, (self.id << 40) + z as u64 * self.layer_bytes + offset))
    }

    /// `textureSize` at level `level`: width, height and layers (1 for a 2D texture); zeros
    /// for a level it lacks.
    pub fn size(&self, level: i32) -> [u32; 3] {
        match usize::try_from(level).ok().and_then(|level| self.levels.get(level)) {
            Some(l) => [l.width, l.height, self.layers()],
            None => [0; 3],
        }
    }

    /// The texel a nearest lookup at GL's `(s, t, r)` reads on level 0 with `sampler`'s wraps
    /// (`r` is a layer index for an array, rounded and clamped as GL says, §3.8.10: `clamp(⌊r + ½⌋, 0, layers − 1)`; a slice coordinate for a 3-D texture), as
    /// `[x, y, z]`.
    pub fn nearest(&self, sampler: &Sampler, [s, t, r]: [f32; 3]) -> [i32; 3] {
        let l = &self.levels[0];
        let x = nearest_texels([reduce(s, sampler.wrap_u)], l.width, sampler.wrap_u)[0];
        let y = nearest_texels([reduce(t, sampler.wrap_v)], l.height, sampler.wrap_v)[0];
        let z = match self.kind {
            IntegerKind::Flat => 0,
            IntegerKind::Layered(LayeredKind::Array, n) => floor(r + 0.5).clamp(0.0, (n - 1) as f32) as u32,
            IntegerKind::Layered(LayeredKind::Volume, n) => {
                nearest_texels([reduce(r, sampler.wrap_w)], n, sampler.wrap_w)[0]
            }
        };
        [x as i32, y as i32, z as i32]
    }
}
