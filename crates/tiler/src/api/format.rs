//! Image formats: their sizes, and how a value is packed into and unpacked from memory.
//!
//! The tile buffer holds every attachment in its own format, packed exactly as in external
//! memory. A `LoadOp::Load` is then a plain copy, and a blend reads the packed value back
//! wherever it lives. So the tile buffer of a tiler and the framebuffer of an immediate-mode
//! GPU hold the same bits at every step, and every backend gives the same image.
//!
//! Conversions follow Vulkan's rules ("Fixed-Point Data Conversions"):
//! float → UNORM is `round(clamp(f, 0, 1) · (2^b − 1))`, rounding half up, NaN → 0;
//! UNORM → float is `c / (2^b − 1)`. sRGB uses the piecewise sRGB transfer function.
//! Half floats round to nearest even.
//!
//! Integer formats ([`IntFormat`], GL ES 3.0's `RGBA8UI`, `R32I`, …) hold integers, not
//! colours: a shader's integer output reaches them as its bits (a register of an `int` or
//! `uint` holds the integer's bits, see `tiler-glsl`), and `encode_color` stores the low
//! `bits` of each channel's 32-bit pattern (the value modulo `2^bits`, two's complement for
//! signed ones); `decode_color` gives the channel back zero- or sign-extended to 32 bits, as
//! the bits of an `f32`, missing channels 0 and alpha the integer 1. They are never blended
//! (GL ES 3.0 §4.1.7: blending is off for integer draw buffers; see `pixel::primitive`) and a
//! resolve takes sample 0 (GL ES 3.0 §4.3.3: integer blits read one sample).

use serde::{Deserialize, Serialize};

/// The format of an image's samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Format {
    /// 8-bit red, green, blue, alpha, linear; bytes in that order.
    Rgba8Unorm,
    /// As `Rgba8Unorm`, with sRGB-encoded colour channels (alpha linear).
    Rgba8UnormSrgb,
    /// 8-bit blue, green, red, alpha; bytes in that order.
    Bgra8Unorm,
    /// 16 bits: red in bits 11–15, green 5–10, blue 0–4 (Vulkan `R5G6B5_UNORM_PACK16`).
    Rgb565Unorm,
    /// Four IEEE half floats.
    Rgba16Float,
    /// Four IEEE single floats.
    Rgba32Float,
    /// One IEEE single float (red); green and blue read as 0, alpha as 1.
    R32Float,
    /// 16-bit normalised depth.
    D16Unorm,
    /// 24-bit normalised depth in bits 0–23 and 8-bit stencil in bits 24–31 of a 32-bit word.
    D24UnormS8Uint,
    /// 32-bit float depth.
    D32Float,
    /// Unsigned or signed integers (see the module notes).
    Int(IntFormat),
}

/// An integer colour format: `channels` (1, 2 or 4: red, red-green, RGBA) of `bits` (8, 16
/// or 32) each, little-endian, channel after channel, signed or not. (A vertex attribute's
/// integers, `VertexFormat::Int`, may have 3 channels.)
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct IntFormat {
    pub channels: u8,
    pub bits: u8,
    pub signed: bool,
}

impl IntFormat {
    /// Every integer format GL ES 3.0 has, for tests and listings: unsigned then signed, 8, 16,
    /// 32 bits, 1, 2, 4 channels.
    pub const ALL: [IntFormat; 18] = {
        let mut all = [IntFormat { channels: 1, bits: 8, signed: false }; 18];
        let mut i = 0;
        while i < 18 {
            all[i] = IntFormat { channels: [1, 2, 4][i % 3], bits: [8, 16, 32][(i / 3) % 3], signed: i >= 9 };
            i += 1;
        }
        all
    };

    /// Bytes one texel or sample takes.
    pub const fn bytes(self) -> usize {
        self.channels as usize * self.bits as usize / 8
    }

    /// Channel `c`'s 32-bit pattern from its stored bytes (zero- or sign-extended).
    #[inline]
    pub fn channel(self, src: &[u8], c: usize) -> u32 {
        let n = self.bits as usize / 8;
        let mut word = [0u8; 4];
        word[..n].copy_from_slice(&src[c * n..(c + 1) * n]);
        let v = u32::from_le_bytes(word);
        let unused = 32 - self.bits as u32;
        if self.signed && unused > 0 { (((v << unused) as i32) >> unused) as u32 } else { v }
    }

    /// The four channels' 32-bit patterns of a stored texel: missing ones 0, alpha 1.
    #[inline]
    pub fn unpack(self, src: &[u8]) -> [u32; 4] {
        std::array::from_fn(|c| match c {
            c if c < self.channels as usize => self.channel(src, c),
            3 => 1,
            _ => 0,
        })
    }

    /// Stores the low `bits` of each present channel of `value` into `dst`.
    #[inline]
    pub fn pack(self, value: [u32; 4], dst: &mut [u8]) {
        let n = self.bits as usize / 8;
        for c in 0..self.channels as usize {
            dst[c * n..(c + 1) * n].copy_from_slice(&value[c].to_le_bytes()[..n]);
        }
    }

    /// GL's name of the sized internal format (`rgba8ui`, `r32i`).
    pub const fn name(self) -> &'static str {
        const NAMES: [&str; 18] = [
            "r8ui", "rg8ui", "rgba8ui", "r16ui", "rg16ui", "rgba16ui", "r32ui", "rg32ui", "rgba32ui", "r8i", "rg8i",
            "rgba8i", "r16i", "rg16i", "rgba16i", "r32i", "rg32i", "rgba32i",
        ];
        let channel = match self.channels {
            1 => 0,
            2 => 1,
            _ => 2,
        };
        let bits = match self.bits {
            8 => 0,
            16 => 1,
            _ => 2,
        };
        NAMES[channel + 3 * bits + if self.signed { 9 } else { 0 }]
    }
}

impl Format {
    /// Every format, for tests and listings.
    pub const ALL: [Format; 10] = [
        Format::Rgba8Unorm,
        Format::Rgba8UnormSrgb,
        Format::Bgra8Unorm,
        Format::Rgb565Unorm,
        Format::Rgba16Float,
        Format::Rgba32Float,
        Format::R32Float,
        Format::D16Unorm,
        Format::D24UnormS8Uint,
        Format::D32Float,
    ];

    /// Bytes one sample occupies in memory (and in the tile buffer).
    pub const fn bytes_per_sample(self) -> usize {
        match self {
            Format::Rgb565Unorm | Format::D16Unorm => 2,
            Format::Rgba8Unorm
            | Format::Rgba8UnormSrgb
            | Format::Bgra8Unorm
            | Format::R32Float
            | Format::D24UnormS8Uint
            | Format::D32Float => 4,
            Format::Rgba16Float => 8,
            Format::Rgba32Float => 16,
            Format::Int(f) => f.bytes(),
        }
    }

    pub const fn is_color(self) -> bool {
        !self.has_depth() && !self.has_stencil()
    }

    pub const fn has_depth(self) -> bool {
        matches!(self, Format::D16Unorm | Format::D24UnormS8Uint | Format::D32Float)
    }

    pub const fn has_stencil(self) -> bool {
        matches!(self, Format::D24UnormS8Uint)
    }

    /// Bytes of the depth aspect of one sample when both aspects move together: a packed
    /// depth-stencil word is split 3 + 1 between its depth and stencil aspects. What one
    /// access moves is [`Format::depth_access_bytes`].
    pub const fn depth_aspect_bytes(self) -> usize {
        match self {
            Format::D16Unorm => 2,
            Format::D24UnormS8Uint => 3,
            Format::D32Float => 4,
            _ => 0,
        }
    }

    /// Bytes of the stencil aspect of one sample (see [`Format::depth_aspect_bytes`]).
    pub const fn stencil_aspect_bytes(self) -> usize {
        match self {
            Format::D24UnormS8Uint => 1,
            _ => 0,
        }
    }

    /// Bytes memory moves for the depth aspect of one sample, `with_stencil` when the stencil
    /// aspect of the same sample moves in the same access. Memory moves a packed D24S8 sample
    /// as one 32-bit word (issue 16): a depth-only access costs all 4 bytes; with the stencil
    /// the word's 4 bytes are split 3 + 1 between the aspects, so the word is counted once.
    pub const fn depth_access_bytes(self, with_stencil: bool) -> usize {
        match self {
            Format::D24UnormS8Uint if !with_stencil => 4,
            _ => self.depth_aspect_bytes(),
        }
    }

    /// Bytes memory moves for the stencil aspect of one sample, `with_depth` when the depth
    /// aspect moves in the same access (see [`Format::depth_access_bytes`]): a stencil-only
    /// access of packed D24S8 costs 4 bytes.
    pub const fn stencil_access_bytes(self, with_depth: bool) -> usize {
        match self {
            Format::D24UnormS8Uint if !with_depth => 4,
            _ => self.stencil_aspect_bytes(),
        }
    }

    /// Whether it holds integers ([`IntFormat`]): never blended, resolved by sample 0.
    pub const fn is_integer(self) -> bool {
        matches!(self, Format::Int(_))
    }

    /// Whether colour values are clamped to `[0, 1]` (normalised fixed-point formats).
    pub const fn is_normalized(self) -> bool {
        matches!(self, Format::Rgba8Unorm | Format::Rgba8UnormSrgb | Format::Bgra8Unorm | Format::Rgb565Unorm)
    }

    /// The name used on the command line and in reports.
    pub const fn name(self) -> &'static str {
        match self {
            Format::Rgba8Unorm => "rgba8unorm",
            Format::Rgba8UnormSrgb => "rgba8unorm-srgb",
            Format::Bgra8Unorm => "bgra8unorm",
            Format::Rgb565Unorm => "rgb565unorm",
            Format::Rgba16Float => "rgba16float",
            Format::Rgba32Float => "rgba32float",
            Format::R32Float => "r32float",
            Format::D16Unorm => "d16unorm",
            Format::D24UnormS8Uint => "d24unorm-s8uint",
            Format::D32Float => "d32float",
            Format::Int(f) => f.name(),
        }
    }

    /// Packs an RGBA colour into `dst` (exactly `bytes_per_sample` bytes).
    ///
    /// # Panics
    /// If the format is not a colour format or `dst` has the wrong length (a tiler bug: formats
    /// are validated when a render pass is submitted).
    #[inline]
    pub fn encode_color(self, rgba: [f32; 4], dst: &mut [u8]) {
        let [r, g, b, a] = rgba;
        match self {
            Format::Rgba8Unorm => dst.copy_from_slice(&[unorm8(r), unorm8(g), unorm8(b), unorm8(a)]),
            Format::Rgba8UnormSrgb => dst.copy_from_slice(&[
                unorm8(linear_to_srgb(r)),
                unorm8(linear_to_srgb(g)),
                unorm8(linear_to_srgb(b)),
                unorm8(a),
            ]),
            Format::Bgra8Unorm => dst.copy_from_slice(&[unorm8(b), unorm8(g), unorm8(r), unorm8(a)]),
            Format::Rgb565Unorm => {
                let v = (unorm(r, 31.0) << 11) | (unorm(g, 63.0) << 5) | unorm(b, 31.0);
                dst.copy_from_slice(&(v as u16).to_le_bytes());
            }
            Format::Rgba16Float => {
                for (i, c) in rgba.iter().enumerate() {
                    dst[2 * i..2 * i + 2].copy_from_slice(&half::f16::from_f32(*c).to_le_bytes());
                }
            }
            Format::Rgba32Float => {
                for (i, c) in rgba.iter().enumerate() {
                    dst[4 * i..4 * i + 4].copy_from_slice(&c.to_le_bytes());
                }
            }
            Format::R32Float => dst.copy_from_slice(&r.to_le_bytes()),
            Format::Int(f) => f.pack(rgba.map(f32::to_bits), dst),
            Format::D16Unorm | Format::D24UnormS8Uint | Format::D32Float => {
                unreachable!("encode_color on depth format {self:?}")
            }
        }
    }

    /// Packs eight lanes of colour: lane `i` gets exactly `encode_color` of its values, in the
    /// first `bytes_per_sample` bytes of `out[i]`. RGBA8 and BGRA8 go lane-parallel.
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn encode_lanes(self, rgba: &crate::simd::Vec4x8, out: &mut [[u8; 16]; crate::simd::LANES]) {
        match self {
            Format::Rgba8Unorm | Format::Bgra8Unorm => {
                // unorm8 lane by lane: clamp (NaN to 0), scale, round half up, as encode_color
                // does; through i32, whose conversion vectorises.
                let channels: [[i32; 8]; 4] = rgba.map(|c| c.unorm(255.0));
                let order = if self == Format::Rgba8Unorm { [0, 1, 2, 3] } else { [2, 1, 0, 3] };
                for (lane, packed) in out.iter_mut().enumerate() {
                    for (byte, &c) in order.iter().enumerate() {
                        packed[byte] = channels[c][lane] as u8;
                    }
                }
            }
            _ => {
                let bytes = self.bytes_per_sample();
                for (lane, packed) in out.iter_mut().enumerate() {
                    self.encode_color([0, 1, 2, 3].map(|c| rgba[c].lane(lane)), &mut packed[..bytes]);
                }
            }
        }
    }

    /// Eight lanes of colour packed as 32-bit little-endian words, for the 4-byte UNORM8
    /// formats (`Rgba8Unorm`, `Bgra8Unorm`): exactly the bytes of [`Format::encode_lanes`].
    /// `None` for other formats.
    #[inline(always)]
    pub fn pack_lanes_u32(self, rgba: &crate::simd::Vec4x8) -> Option<[u32; 8]> {
        let order = match self {
            Format::Rgba8Unorm => [0, 1, 2, 3],
            Format::Bgra8Unorm => [2, 1, 0, 3],
            _ => return None,
        };
        // Loops, not closures: a closure may be left out of line, compiled for the baseline.
        let mut channels = [[0i32; 8]; 4];
        for (channel, value) in channels.iter_mut().zip(rgba) {
            *channel = value.unorm(255.0);
        }
        let mut packed = [0u32; 8];
        for (i, lane) in packed.iter_mut().enumerate() {
            *lane = (channels[order[0]][i]
                | channels[order[1]][i] << 8
                | channels[order[2]][i] << 16
                | channels[order[3]][i] << 24) as u32;
        }
        Some(packed)
    }

    /// Whether a resolve averages this format's channels as bytes, exactly: linear 8-bit UNORM.
    pub fn resolves_as_integers(self) -> bool {
        matches!(self, Format::Rgba8Unorm | Format::Bgra8Unorm)
    }

    /// The MSAA resolve of one pixel: its `samples` (each one sample in this format) averaged
    /// into `out`, in this format. Linear 8-bit UNORM takes, per byte, the byte nearest the
    /// mean, halves up: `⌊(Σc + n/2) / n⌋`, computed on the integers; other formats the mean
    /// of the decoded (linear) values, encoded again. The tile's resolve computes exactly this
    /// (`tile::load_store::apply_resolve`, tested equal), and so must whatever else reads a
    /// multisampled image as one value per pixel (a GL blit), or pictures differ by the
    /// rounding of the mean.
    pub fn resolve_samples<'a>(self, samples: impl ExactSizeIterator<Item = &'a [u8]>, out: &mut [u8]) {
        let n = samples.len() as u32;
        debug_assert!(n > 0, "a pixel has at least one sample");
        let bytes = self.bytes_per_sample();
        if self.is_integer() {
            // One sample, not a mean (see the module notes).
            let mut samples = samples;
            out[..bytes].copy_from_slice(&samples.next().expect("a sample")[..bytes]);
            return;
        }
        if self.resolves_as_integers() {
            let mut sums = [0u32; 16];
            for sample in samples {
                for (sum, &c) in sums.iter_mut().zip(&sample[..bytes]) {
                    *sum += c as u32;
                }
            }
            for (out, sum) in out[..bytes].iter_mut().zip(sums) {
                *out = ((sum + n / 2) / n) as u8;
            }
            return;
        }
        let mut sum = [0.0f32; 4];
        for sample in samples {
            let v = self.decode_color(&sample[..bytes]);
            for c in 0..4 {
                sum[c] += v[c];
            }
        }
        let scale = 1.0 / n as f32;
        self.encode_color(sum.map(|c| c * scale), &mut out[..bytes]);
    }

    /// Unpacks a colour stored in this format; missing channels read as 0 (alpha as 1).
    ///
    /// RGBA8, the window's format, is decoded in place (blending reads every destination
    /// pixel through here: desktop.trace ~35 M times); the other formats in a call.
    #[inline(always)]
    pub fn decode_color(self, src: &[u8]) -> [f32; 4] {
        match (self, src) {
            (Format::Rgba8Unorm, &[r, g, b, a, ..]) => [
                UNORM8_TO_F32[r as usize],
                UNORM8_TO_F32[g as usize],
                UNORM8_TO_F32[b as usize],
                UNORM8_TO_F32[a as usize],
            ],
            _ => self.decode_other_color(src),
        }
    }

    /// [`Format::decode_color`] past RGBA8.
    #[inline(never)]
    fn decode_other_color(self, src: &[u8]) -> [f32; 4] {
        match self {
            Format::Rgba8Unorm => [
                UNORM8_TO_F32[src[0] as usize],
                UNORM8_TO_F32[src[1] as usize],
                UNORM8_TO_F32[src[2] as usize],
                UNORM8_TO_F32[src[3] as usize],
            ],
            Format::Rgba8UnormSrgb => [
                srgb8_to_linear(src[0]),
                srgb8_to_linear(src[1]),
                srgb8_to_linear(src[2]),
                UNORM8_TO_F32[src[3] as usize],
            ],
            Format::Bgra8Unorm => [
                UNORM8_TO_F32[src[2] as usize],
                UNORM8_TO_F32[src[1] as usize],
                UNORM8_TO_F32[src[0] as usize],
                UNORM8_TO_F32[src[3] as usize],
            ],
            Format::Rgb565Unorm => {
                let v = u16::from_le_bytes([src[0], src[1]]) as u32;
                [(v >> 11) as f32 / 31.0, ((v >> 5) & 63) as f32 / 63.0, (v & 31) as f32 / 31.0, 1.0]
            }
            Format::Rgba16Float => {
                std::array::from_fn(|i| half::f16::from_le_bytes([src[2 * i], src[2 * i + 1]]).to_f32())
            }
            Format::Rgba32Float => {
                std::array::from_fn(|i| f32::from_le_bytes(src[4 * i..4 * i + 4].try_into().unwrap()))
            }
            Format::R32Float => [f32::from_le_bytes(src[0..4].try_into().unwrap()), 0.0, 0.0, 1.0],
            Format::Int(f) => f.unpack(src).map(f32::from_bits),
            Format::D16Unorm | Format::D24UnormS8Uint | Format::D32Float => {
                unreachable!("decode_color on depth format {self:?}")
            }
        }
    }

    /// The bits of a packed colour that the write mask lets through, as a byte mask over the
    /// sample's bytes (`0xff` = take the new byte, `0` = keep the old one), per channel bit.
    /// Packed 565 masks are bit masks over its little-endian 16-bit word.
    pub fn write_mask_bytes(self, writes: ColorWrites) -> [u8; 16] {
        let mut mask = [0u8; 16];
        let channel = |c: u8| writes.0 & c != 0;
        let bytes = self.bytes_per_sample();
        match self {
            Format::Rgb565Unorm => {
                let mut m: u16 = 0;
                if channel(ColorWrites::RED.0) {
                    m |= 0xf800;
                }
                if channel(ColorWrites::GREEN.0) {
                    m |= 0x07e0;
                }
                if channel(ColorWrites::BLUE.0) {
                    m |= 0x001f;
                }
                mask[..2].copy_from_slice(&m.to_le_bytes());
            }
            _ => {
                // Channel order in memory, and bytes per channel.
                let order: &[u8] = match self {
                    Format::Bgra8Unorm => &[4, 2, 1, 8],
                    Format::R32Float => &[1],
                    Format::Int(f) => &[1, 2, 4, 8][..f.channels as usize],
                    _ => &[1, 2, 4, 8],
                };
                let per_channel = bytes / order.len();
                for (i, c) in order.iter().enumerate() {
                    if channel(*c) {
                        mask[i * per_channel..(i + 1) * per_channel].fill(0xff);
                    }
                }
            }
        }
        mask
    }

    /// Converts a depth value to this format's stored depth bits, which compare as unsigned
    /// integers in the same order as the depths they hold. UNORM: `round(clamp(z) · (2^b − 1))`;
    /// float: the IEEE bits of `clamp(z, 0, 1)` (non-negative floats order like their bits).
    #[inline(always)]
    pub fn depth_bits(self, z: f32) -> u32 {
        // NaN cannot reach here (positions are validated) but would clamp to 0.
        let z = if z > 0.0 { z.min(1.0) } else { 0.0 };
        match self {
            // In range for i32, whose conversions vectorise (u32's do not).
            Format::D16Unorm => (z * 65535.0 + 0.5) as i32 as u32,
            Format::D24UnormS8Uint => (z as f64 * 16_777_215.0 + 0.5) as i32 as u32,
            Format::D32Float => z.to_bits(),
            _ => unreachable!("depth_bits on colour format {self:?}"),
        }
    }

    /// [`Format::depth_bits`] of eight lanes, written to vectorise.
    #[inline(always)]
    pub fn depth_bits_lanes(self, z: crate::simd::F32x8) -> [u32; 8] {
        let z = z.to_array();
        let z: [f32; 8] = std::array::from_fn(|i| if z[i] > 0.0 { z[i].min(1.0) } else { 0.0 });
        match self {
            Format::D16Unorm => crate::simd::F32x8::from_array(z).unorm(65535.0).map(|v| v as u32),
            // `⌊z·(2^24 − 1) + ½⌋` as the scalar form computes it in f64, here in f32 lanes (a
            // block test converts every row; the f64 round trip was 16% of tris' block
            // tests). With `Z = z·2^24` (exact), `I = ⌊Z⌋`, `f = Z − I` (exact), the value is
            // `I + ⌊f + ½ − z⌋`, and the floor is 1 when `f − ½ ≥ z`, −1 when `z − ½ > f`,
            // else 0. Both differences are exact where they can decide (`f − ½` when `Z ≥ ½`,
            // `z − ½` when `z ≥ ¼`) and keep their sign where they are not. Checked against
            // the scalar form on every float in [0, 1] (1,065,353,217 values); the test
            // sweeps a stride of them and the neighbours of the rounding points.
            Format::D24UnormS8Uint => std::array::from_fn(|i| {
                let big = z[i] * 16_777_216.0;
                // SAFETY: `z` is clamped to [0, 1] (NaN to 0) above, so `big` is finite and in
                // [0, 2^24], where truncation to i32 is defined. The unchecked form
                // vectorises; the saturating `as` makes this loop scalar (measured: the
                // overdraw scene on TBDR, 1080p, went from 455 to 262 ms per frame).
                let whole = unsafe { big.to_int_unchecked::<i32>() };
                let frac = big - whole as f32;
                (whole + (frac - 0.5 >= z[i]) as i32 - (z[i] - 0.5 > frac) as i32) as u32
            }),
            Format::D32Float => std::array::from_fn(|i| z[i].to_bits()),
            _ => unreachable!("depth_bits on colour format {self:?}"),
        }
    }

    /// The depth a stored value stands for: `bits / (2ⁿ − 1)` rounded to `f32` (for 24 bits,
    /// divided in `f64` and rounded once more). Computed as a product with the reciprocal in
    /// `f64`, which gives the same bits for every stored value (tested on all of them) and
    /// vectorises to a multiply where a division costs 4–16 times as much: a depth texture
    /// read for sampling converts every texel (a shadow map, each pass that reads it).
    #[inline]
    pub fn depth_from_bits(self, bits: u32) -> f32 {
        match self {
            Format::D16Unorm => (bits as f64 * (1.0 / 65_535.0)) as f32,
            Format::D24UnormS8Uint => (bits as f64 * (1.0 / 16_777_215.0)) as f32,
            Format::D32Float => f32::from_bits(bits),
            _ => unreachable!("depth_from_bits on colour format {self:?}"),
        }
    }
}

impl std::fmt::Display for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Which colour channels a draw writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct ColorWrites(pub u8);

impl ColorWrites {
    pub const RED: ColorWrites = ColorWrites(1);
    pub const GREEN: ColorWrites = ColorWrites(2);
    pub const BLUE: ColorWrites = ColorWrites(4);
    pub const ALPHA: ColorWrites = ColorWrites(8);
    pub const COLOR: ColorWrites = ColorWrites(7);
    pub const ALL: ColorWrites = ColorWrites(15);
    pub const NONE: ColorWrites = ColorWrites(0);
}

/// float → UNORM with `max = 2^b − 1`: `round(clamp(f, 0, 1) · max)`, half up; NaN → 0.
#[inline(always)]
pub fn unorm(c: f32, max: f32) -> u32 {
    let c = if c > 0.0 { c.min(1.0) } else { 0.0 };
    (c * max + 0.5) as u32
}

/// float → 8-bit UNORM.
#[inline(always)]
pub fn unorm8(c: f32) -> u8 {
    unorm(c, 255.0) as u8
}

/// 8-bit UNORM → float, `c / 255`, as a table.
pub static UNORM8_TO_F32: [f32; 256] = {
    let mut t = [0.0f32; 256];
    let mut i = 0;
    while i < 256 {
        t[i] = i as f32 / 255.0;
        i += 1;
    }
    t
};

/// The sRGB encoding of a linear value in `[0, 1]` (IEC 61966-2-1).
#[inline]
pub fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 { c * 12.92 } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 }
}

/// The linear value of an sRGB-encoded value in `[0, 1]`.
#[inline]
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.040_45 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

/// The linear value of an 8-bit sRGB-encoded channel.
#[inline]
pub fn srgb8_to_linear(c: u8) -> f32 {
    srgb_to_linear(UNORM8_TO_F32[c as usize])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unorm_rounds_half_up_and_clamps() {
        assert_eq!(unorm8(0.0), 0);
        assert_eq!(unorm8(1.0), 255);
        assert_eq!(unorm8(2.0), 255);
        assert_eq!(unorm8(-1.0), 0);
        assert_eq!(unorm8(f32::NAN), 0);
        assert_eq!(unorm8(0.5), 128); // 127.5 rounds up
        assert_eq!(unorm8(127.4 / 255.0), 127);
    }

    #[test]
    fn eight_bit_formats_round_trip_exactly() {
        for format in [Format::Rgba8Unorm, Format::Bgra8Unorm, Format::Rgba8UnormSrgb] {
            for v in 0..=255u8 {
                let bytes = [v, v.wrapping_mul(7), v.wrapping_add(3), 255 - v];
                let rgba = format.decode_color(&bytes);
                let mut back = [0u8; 4];
                format.encode_color(rgba, &mut back);
                assert_eq!(back, bytes, "{format}");
            }
        }
    }

    #[test]
    fn rgb565_layout() {
        let mut b = [0u8; 2];
        Format::Rgb565Unorm.encode_color([1.0, 0.0, 0.0, 1.0], &mut b);
        assert_eq!(u16::from_le_bytes(b), 0xf800);
        Format::Rgb565Unorm.encode_color([0.0, 1.0, 0.0, 1.0], &mut b);
        assert_eq!(u16::from_le_bytes(b), 0x07e0);
        assert_eq!(Format::Rgb565Unorm.decode_color(&0x001fu16.to_le_bytes()), [0.0, 0.0, 1.0, 1.0]);
    }

    #[test]
    fn depth_bits_lanes_match_the_scalar_conversion() {
        let mut values = vec![f32::NAN, -1.0, -0.0, 0.0, 1e-30, 0.5, 1.0, 1.5, f32::INFINITY];
        let mut x = 0x1234_5678u32;
        for _ in 0..20_000 {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            values.push(f32::from_bits(x & 0x3fff_ffff) % 1.25);
        }
        for format in [Format::D16Unorm, Format::D24UnormS8Uint, Format::D32Float] {
            for chunk in values.chunks(8) {
                let z = crate::simd::F32x8::from_fn(|i| chunk.get(i).copied().unwrap_or(0.25));
                let lanes = format.depth_bits_lanes(z);
                for (bits, z) in lanes.iter().zip(z.to_array()) {
                    assert_eq!(*bits, format.depth_bits(z), "{format} at {z}");
                }
            }
        }
    }

    #[test]
    fn d24_lanes_round_as_the_f64_conversion_does() {
        // A stride over every float in [0, 1], and the floats next to each sampled rounding
        // point `(k + ½) / (2^24 − 1)`, where the f32 form's comparisons decide.
        let mut values: Vec<f32> = (0..=1.0f32.to_bits()).step_by(251).map(f32::from_bits).collect();
        for k in (0..16_777_215u32).step_by(97).chain([0, 1, 8_388_607, 8_388_608, 16_777_214]) {
            let point = ((k as f64 + 0.5) / 16_777_215.0) as f32;
            values.extend([point.next_down(), point, point.next_up()].into_iter().filter(|z| (0.0..=1.0).contains(z)));
        }
        for chunk in values.chunks(8) {
            let z = crate::simd::F32x8::from_fn(|i| chunk.get(i).copied().unwrap_or(1.0));
            let lanes = Format::D24UnormS8Uint.depth_bits_lanes(z);
            for (bits, z) in lanes.iter().zip(z.to_array()) {
                let reference = Format::D24UnormS8Uint.depth_bits(z);
                assert_eq!(*bits, reference, "D24 at {z:e} ({:#x})", z.to_bits());
            }
        }
    }

    #[test]
    fn depths_from_bits_are_the_quotients() {
        for bits in 0..=0xffff_u32 {
            let quotient = bits as f32 / 65535.0;
            assert_eq!(Format::D16Unorm.depth_from_bits(bits).to_bits(), quotient.to_bits(), "{bits}");
        }
        for bits in 0..=0xff_ffff_u32 {
            let quotient = (bits as f64 / 16_777_215.0) as f32;
            assert_eq!(Format::D24UnormS8Uint.depth_from_bits(bits).to_bits(), quotient.to_bits(), "{bits}");
        }
    }

    #[test]
    fn depth_bits_order_like_depths() {
        for format in [Format::D16Unorm, Format::D24UnormS8Uint, Format::D32Float] {
            let mut last = 0;
            for i in 0..=1000 {
                let bits = format.depth_bits(i as f32 / 1000.0);
                assert!(bits >= last, "{format}");
                last = bits;
            }
            assert_eq!(format.depth_bits(-0.0), format.depth_bits(0.0));
            assert_eq!(format.depth_from_bits(format.depth_bits(1.0)), 1.0);
        }
        assert_eq!(Format::D24UnormS8Uint.depth_bits(1.0), 0xff_ffff);
        assert_eq!(Format::D16Unorm.depth_bits(0.5), 32768);
    }

    #[test]
    fn integer_formats_keep_the_low_bits_and_extend_them() {
        let mut bytes = [0u8; 16];
        let value = [-3i32 as u32, 300, 0x1234_5678, 7].map(f32::from_bits);
        for f in IntFormat::ALL {
            let format = Format::Int(f);
            let n = format.bytes_per_sample();
            assert_eq!(n, f.channels as usize * f.bits as usize / 8, "{format}");
            format.encode_color(value, &mut bytes[..n]);
            let back = format.decode_color(&bytes[..n]).map(f32::to_bits);
            let keep = |v: u32| match (f.bits, f.signed) {
                (32, _) => v,
                (b, false) => v & ((1 << b) - 1),
                (b, true) => (((v << (32 - b)) as i32) >> (32 - b)) as u32,
            };
            let want: [u32; 4] = std::array::from_fn(|c| match c {
                c if c < f.channels as usize => keep(value[c].to_bits()),
                3 => 1,
                _ => 0,
            });
            assert_eq!(back, want, "{format}");
        }
        assert_eq!(IntFormat::ALL.map(|f| f.name()).iter().collect::<std::collections::HashSet<_>>().len(), 18);
        assert_eq!(IntFormat { channels: 4, bits: 8, signed: false }.name(), "rgba8ui");
        assert_eq!(IntFormat { channels: 1, bits: 32, signed: true }.name(), "r32i");
    }

    #[test]
    fn write_masks_cover_the_channels() {
        assert_eq!(&Format::Rgba8Unorm.write_mask_bytes(ColorWrites::ALL)[..4], &[0xff; 4]);
        assert_eq!(&Format::Bgra8Unorm.write_mask_bytes(ColorWrites::RED)[..4], &[0, 0, 0xff, 0]);
        assert_eq!(&Format::Rgba16Float.write_mask_bytes(ColorWrites::GREEN)[..8], &[0, 0, 0xff, 0xff, 0, 0, 0, 0]);
        assert_eq!(&Format::Rgb565Unorm.write_mask_bytes(ColorWrites::BLUE)[..2], &[0x1f, 0]);
    }
}
