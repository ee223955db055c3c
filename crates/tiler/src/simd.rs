//! Eight-lane vectors for the pixel pipeline: one lane per pixel of a 4×2 group (two 2×2 quads).
//!
//! Every operation is defined lane by lane with the scalar IEEE operation (`a[i] + b[i]`,
//! `a[i].sqrt()`, …), written so LLVM's vectoriser turns it into SIMD instructions. There is
//! deliberately no fused multiply-add and no approximate reciprocal: a lane computes exactly
//! what the scalar reference computes, so results never depend on the SIMD level the compiler
//! chose (DESIGN: every backend, tile size and thread count gives the same image).
//!
//! Lane layout of a group at pixel `(x, y)` (x a multiple of 4, y a multiple of 2):
//!
//! ```text
//!   lane:  0 1 2 3      pixels (x..x+4, y)
//!          4 5 6 7      pixels (x..x+4, y+1)
//! ```
//!
//! so the two 2×2 quads are lanes {0, 1, 4, 5} and {2, 3, 6, 7}. Rows are contiguous in memory,
//! and quad derivatives are simple lane differences ([`F32x8::ddx`], [`F32x8::ddy`]).

use std::ops::{Add, AddAssign, BitAnd, Div, Mul, MulAssign, Neg, Sub, SubAssign};

/// The instruction sets the pixel pipeline is compiled for. The pipeline is compiled once per
/// level and the device picks one at run time; every level computes exactly the same values
/// (plain IEEE operations, no fused multiply-add: Rust never contracts `a * b + c`), which
/// tests hold bit for bit.
///
/// A level is a request: code runs at a level only through a [`SimdSupport`], which only
/// detection on this processor can make.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SimdLevel {
    /// The target's baseline (SSE2 on x86-64).
    #[default]
    Baseline,
    /// x86-64 with every feature of [`AVX2_FEATURES`]: eight `f32` lanes in one register.
    Avx2,
}

/// The processor features the `Avx2` pipeline is compiled with. Every
/// `#[target_feature(enable = …)]` of the crate names exactly these (a test reads the sources
/// to hold it), and [`SimdSupport::detect`] checks every one of them.
pub const AVX2_FEATURES: [&str; 6] = ["avx2", "fma", "bmi1", "bmi2", "lzcnt", "popcnt"];

impl SimdLevel {
    /// The best level this processor runs.
    pub fn best() -> SimdLevel {
        SimdSupport::best().level()
    }

    /// Whether this processor runs code of this level (every feature the level's code is
    /// compiled with).
    pub fn is_available(self) -> bool {
        SimdSupport::detect(self).is_some()
    }

    /// The features code of this level is compiled with, beyond the target's baseline.
    pub fn features(self) -> &'static [&'static str] {
        match self {
            SimdLevel::Baseline => &[],
            SimdLevel::Avx2 => &AVX2_FEATURES,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            SimdLevel::Baseline => "baseline",
            SimdLevel::Avx2 => "avx2",
        }
    }
}

/// Proof that this processor runs the code of a SIMD level: what the pixel pipeline takes to
/// choose its instruction set. Sound by construction: its field is private, and the only
/// constructors are the baseline and [`SimdSupport::detect`], which checks on this processor
/// every feature the level's code is compiled with ([`SimdLevel::features`]). So the
/// `unsafe` calls into `#[target_feature]` code need no promise from any caller.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct SimdSupport {
    level: SimdLevel,
}

impl SimdSupport {
    /// The target's baseline, which every processor of the target runs.
    pub const BASELINE: SimdSupport = SimdSupport { level: SimdLevel::Baseline };

    /// `level`, if this processor has every feature its code is compiled with.
    pub fn detect(level: SimdLevel) -> Option<SimdSupport> {
        SimdSupport::detect_with(level, processor_has)
    }

    /// The best level this processor runs.
    pub fn best() -> SimdSupport {
        SimdSupport::detect(SimdLevel::Avx2).unwrap_or(SimdSupport::BASELINE)
    }

    /// [`SimdSupport::detect`] over a given answer to "does the processor have this feature".
    fn detect_with(level: SimdLevel, has: impl Fn(&str) -> bool) -> Option<SimdSupport> {
        let possible = match level {
            SimdLevel::Baseline => true,
            SimdLevel::Avx2 => cfg!(target_arch = "x86_64"),
        };
        (possible && level.features().iter().all(|f| has(f))).then_some(SimdSupport { level })
    }

    pub fn level(self) -> SimdLevel {
        self.level
    }
}

/// Defines `$name`, a function that runs `$body` compiled for the SIMD level of `$simd` (a
/// [`SimdSupport`]): `$avx2` is `$body` compiled with AVX2 and the features that come with it,
/// and `$name` is never inlined, so each shader-independent stage exists once per level, not
/// once per shader type (the pixel stages) or per caller (texture sampling). The one `unsafe`
/// call of every such stage is here.
macro_rules! per_simd_level {
    (
        $(#[$attr:meta])*
        fn $name:ident / $avx2:ident => $body:ident, simd: $($simd:ident).+,
        ($($arg:ident: $ty:ty),* $(,)?) $(-> $ret:ty)?
    ) => {
        $(#[$attr])*
        #[inline(never)]
        fn $name($($arg: $ty),*) $(-> $ret)? {
            match $($simd).+.level() {
                #[cfg(target_arch = "x86_64")]
                $crate::simd::SimdLevel::Avx2 => {
                    // SAFETY: a `SimdSupport` of level `Avx2` exists only when this processor
                    // has every feature `$avx2` is compiled with (`SimdSupport::detect`).
                    unsafe { $avx2($($arg),*) }
                }
                _ => $body($($arg),*),
            }
        }

        #[doc = concat!("[`", stringify!($body), "`] compiled for AVX2.")]
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
        unsafe fn $avx2($($arg: $ty),*) $(-> $ret)? {
            $body($($arg),*)
        }
    };
}

pub(crate) use per_simd_level;

/// Whether this processor has a feature of [`AVX2_FEATURES`] (`false` for any other name).
fn processor_has(feature: &str) -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        match feature {
            "avx2" => std::arch::is_x86_feature_detected!("avx2"),
            "fma" => std::arch::is_x86_feature_detected!("fma"),
            "bmi1" => std::arch::is_x86_feature_detected!("bmi1"),
            "bmi2" => std::arch::is_x86_feature_detected!("bmi2"),
            "lzcnt" => std::arch::is_x86_feature_detected!("lzcnt"),
            "popcnt" => std::arch::is_x86_feature_detected!("popcnt"),
            _ => false,
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = feature;
        false
    }
}

impl std::str::FromStr for SimdLevel {
    type Err = String;
    fn from_str(s: &str) -> Result<SimdLevel, String> {
        [SimdLevel::Baseline, SimdLevel::Avx2]
            .into_iter()
            .find(|level| level.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| format!("unknown SIMD level '{s}' (expected one of: baseline, avx2)"))
    }
}

impl std::fmt::Display for SimdLevel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Number of lanes (pixels) processed together.
pub const LANES: usize = 8;

/// Horizontal pixel offset of each lane within its 4×2 group.
pub const LANE_DX: [u32; LANES] = [0, 1, 2, 3, 0, 1, 2, 3];
/// Vertical pixel offset of each lane within its 4×2 group.
pub const LANE_DY: [u32; LANES] = [0, 0, 0, 0, 1, 1, 1, 1];

/// A set of lanes, bit `i` for lane `i`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct LaneMask(pub u8);

impl LaneMask {
    pub const NONE: LaneMask = LaneMask(0);
    pub const ALL: LaneMask = LaneMask(0xff);

    #[inline(always)]
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }

    #[inline(always)]
    pub fn contains(self, lane: usize) -> bool {
        self.0 >> lane & 1 != 0
    }

    #[inline(always)]
    pub fn count(self) -> u32 {
        self.0.count_ones()
    }

    /// The lanes of every quad that has at least one lane in `self`: the lanes a GPU shades,
    /// helper invocations included, so that derivatives exist.
    #[inline(always)]
    pub fn quads(self) -> LaneMask {
        const QUAD0: u8 = 0b0011_0011;
        const QUAD1: u8 = 0b1100_1100;
        let mut m = 0;
        if self.0 & QUAD0 != 0 {
            m |= QUAD0;
        }
        if self.0 & QUAD1 != 0 {
            m |= QUAD1;
        }
        LaneMask(m)
    }
}

impl BitAnd for LaneMask {
    type Output = LaneMask;
    #[inline(always)]
    fn bitand(self, rhs: LaneMask) -> LaneMask {
        LaneMask(self.0 & rhs.0)
    }
}

impl std::ops::BitOr for LaneMask {
    type Output = LaneMask;
    #[inline(always)]
    fn bitor(self, rhs: LaneMask) -> LaneMask {
        LaneMask(self.0 | rhs.0)
    }
}

impl std::ops::Not for LaneMask {
    type Output = LaneMask;
    #[inline(always)]
    fn not(self) -> LaneMask {
        LaneMask(!self.0)
    }
}

/// Asks the processor to bring the cache line that holds `at` into its caches (a hint, as
/// [`prefetch`]).
#[inline(always)]
pub fn prefetch_line<T>(at: *const T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        // SAFETY: a prefetch is a hint that never faults and reads or writes nothing
        // architecturally, whatever the address (Intel SDM, PREFETCHh); SSE, which it needs,
        // is in the x86-64 baseline.
        unsafe { _mm_prefetch::<_MM_HINT_T0>(at.cast::<i8>()) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = at;
}

/// Asks the processor to bring the cache lines of `bytes` bytes from `start` into its caches
/// (a hint: no value changes, whatever the address). For the tile pass, whose list entries
/// name primitive records scattered over the frame data: each would otherwise be a cache miss
/// waited for in turn.
#[inline(always)]
pub fn prefetch<T>(start: *const T, bytes: usize) {
    let first = start as usize & !63;
    let end = start as usize + bytes;
    let mut line = first;
    while line < end {
        prefetch_line(line as *const u8);
        line += 64;
    }
}

/// Bit `i` set where lane `i` of `v` is negative: the sign bits, as the `movmskps` instruction
/// gathers them (LLVM does not find it for a loop of shifts and ors, which costs ~40
/// instructions).
#[inline(always)]
pub fn sign_bits(v: [i32; LANES]) -> u8 {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{__m128i, _mm_castsi128_ps, _mm_loadu_si128, _mm_movemask_ps};
        // SAFETY: SSE2 is part of the x86-64 baseline; both loads read 16 bytes inside `v`
        // (unaligned loads need no alignment).
        unsafe {
            let lo = _mm_loadu_si128(v.as_ptr().cast::<__m128i>());
            let hi = _mm_loadu_si128(v.as_ptr().add(4).cast::<__m128i>());
            (_mm_movemask_ps(_mm_castsi128_ps(lo)) | _mm_movemask_ps(_mm_castsi128_ps(hi)) << 4) as u8
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let mut m = 0u8;
        for (i, x) in v.iter().enumerate() {
            m |= ((*x < 0) as u8) << i;
        }
        m
    }
}

/// Bit `i` set where `bools[i]`.
#[inline(always)]
pub fn bool_bits(bools: [bool; LANES]) -> u8 {
    sign_bits(bools.map(|b| -(b as i32)))
}

/// `std::array::from_fn`, always inlined. The standard one goes through `try_from_fn`, which
/// LLVM often leaves out of line: in the AVX2 pipeline that is a call into code compiled for the
/// baseline, whose result comes back through memory in 16-byte stores and is read as 32-byte
/// vectors, a store-forwarding stall each time (atrium's `smooth_n`, +20% of the pipeline's
/// time, once `F32x8` became one vector).
#[inline(always)]
pub fn array_from_fn<T: Copy + Default, const N: usize>(mut f: impl FnMut(usize) -> T) -> [T; N] {
    let mut out = [T::default(); N];
    for (i, o) in out.iter_mut().enumerate() {
        *o = f(i);
    }
    out
}

/// Eight `f32` lanes.
///
/// Held as one 256-bit vector (`__m256` on x86-64), not as `[f32; 8]`: a value of a vector type
/// stays one vector through LLVM's optimisations, so in the AVX2 pipeline each arithmetic
/// operator is one 256-bit instruction, and in the baseline two SSE ones. Held as an array, the
/// SLP vectorizer takes the lanes apart and regroups them as it likes: in a loop that carries
/// several values (a shader's iterations) it kept them as 128-bit halves even in AVX2 code,
/// twice the instructions (overdraw's shader; docs/benchmarking.md, "F32x8 as one vector").
/// The lanes are read and written through [`F32x8::to_array`] and [`F32x8::from_array`].
#[derive(Clone, Copy)]
#[repr(transparent)]
pub struct F32x8(Lanes8);

#[cfg(target_arch = "x86_64")]
type Lanes8 = std::arch::x86_64::__m256;

#[cfg(not(target_arch = "x86_64"))]
#[derive(Clone, Copy)]
#[repr(C, align(32))]
struct Lanes8([f32; LANES]);

impl std::fmt::Debug for F32x8 {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("F32x8").field(&self.to_array()).finish()
    }
}

impl PartialEq for F32x8 {
    fn eq(&self, other: &F32x8) -> bool {
        self.to_array() == other.to_array()
    }
}

impl Default for F32x8 {
    fn default() -> F32x8 {
        F32x8::ZERO
    }
}

macro_rules! lanewise {
    ($a:expr, |$x:ident| $body:expr) => {{
        let a = $a.to_array();
        let mut out = [0.0f32; LANES];
        for i in 0..LANES {
            let $x = a[i];
            out[i] = $body;
        }
        F32x8::from_array(out)
    }};
    ($a:expr, $b:expr, |$x:ident, $y:ident| $body:expr) => {{
        let (a, b) = ($a.to_array(), $b.to_array());
        let mut out = [0.0f32; LANES];
        for i in 0..LANES {
            let ($x, $y) = (a[i], b[i]);
            out[i] = $body;
        }
        F32x8::from_array(out)
    }};
}

macro_rules! compare {
    ($name:ident, $op:tt, $doc:literal) => {
        #[doc = $doc]
        #[inline(always)]
        pub fn $name(self, rhs: F32x8) -> LaneMask {
            let (a, b) = (self.to_array(), rhs.to_array());
            let mut m = 0u8;
            for i in 0..LANES {
                m |= ((a[i] $op b[i]) as u8) << i;
            }
            LaneMask(m)
        }
    };
}

impl F32x8 {
    pub const ZERO: F32x8 = F32x8::splat(0.0);
    pub const ONE: F32x8 = F32x8::splat(1.0);

    #[inline(always)]
    pub const fn from_array(lanes: [f32; LANES]) -> F32x8 {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `[f32; 8]` and `__m256` are both 32 bytes of plain floats, every bit pattern
        // valid.
        let lanes = unsafe { std::mem::transmute::<[f32; LANES], Lanes8>(lanes) };
        #[cfg(not(target_arch = "x86_64"))]
        let lanes = Lanes8(lanes);
        F32x8(lanes)
    }

    #[inline(always)]
    pub const fn to_array(self) -> [f32; LANES] {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as in `from_array`.
        return unsafe { std::mem::transmute::<Lanes8, [f32; LANES]>(self.0) };
        #[cfg(not(target_arch = "x86_64"))]
        return self.0.0;
    }

    /// The lanes as the AVX vector they are held in.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub const fn to_m256(self) -> std::arch::x86_64::__m256 {
        self.0
    }

    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub const fn from_m256(lanes: std::arch::x86_64::__m256) -> F32x8 {
        F32x8(lanes)
    }

    #[inline(always)]
    pub const fn splat(v: f32) -> F32x8 {
        F32x8::from_array([v; LANES])
    }

    #[inline(always)]
    pub fn from_fn(f: impl FnMut(usize) -> f32) -> F32x8 {
        F32x8::from_array(array_from_fn(f))
    }

    #[inline(always)]
    pub fn lane(self, i: usize) -> f32 {
        self.to_array()[i]
    }

    /// Lane-wise UNORM conversion `round_half_up(clamp(v, 0, 1) · max)` (NaN gives 0), for
    /// `max < 2^24`: exactly `api::format::unorm` of each lane, in a form that vectorises.
    /// Defined for every input: `max` is clamped to `[0, 2^24]` (NaN to 0) first.
    #[inline(always)]
    pub fn unorm(self, max: f32) -> [i32; LANES] {
        // Once per call, not per lane; the identity for every `max` callers pass.
        let max = if max > 0.0 { max.min(16_777_216.0) } else { 0.0 };
        let mut out = [0i32; LANES];
        for (o, v) in out.iter_mut().zip(self.to_array()) {
            let v = if v > 0.0 { v.min(1.0) } else { 0.0 };
            let scaled = v * max + 0.5;
            // SAFETY: `v` is in [0, 1] (the comparison sends NaN to 0) and `max` in [0, 2^24]
            // (clamped above, NaN to 0), so `scaled` is finite and in [0.5, 2^24 + 0.5], where
            // truncation to i32 is defined — for every caller, whatever it passes. The
            // saturating `as` does not vectorise on x86-64 and made colour packing scalar
            // (tris scene: write_color went from 179M to 78M instructions per 100K triangles).
            *o = unsafe { scaled.to_int_unchecked::<i32>() };
        }
        out
    }

    /// Lane-wise `f32::min` (a NaN lane takes the other operand).
    #[inline(always)]
    pub fn min(self, rhs: F32x8) -> F32x8 {
        lanewise!(self, rhs, |a, b| a.min(b))
    }

    /// Lane-wise `f32::max` (a NaN lane takes the other operand).
    #[inline(always)]
    pub fn max(self, rhs: F32x8) -> F32x8 {
        lanewise!(self, rhs, |a, b| a.max(b))
    }

    /// Clamps every lane to `[lo, hi]`; NaN becomes `lo`.
    #[inline(always)]
    pub fn clamp(self, lo: f32, hi: f32) -> F32x8 {
        lanewise!(self, |a| if a > lo { a.min(hi) } else { lo })
    }

    #[inline(always)]
    pub fn sqrt(self) -> F32x8 {
        lanewise!(self, |a| a.sqrt())
    }

    #[inline(always)]
    pub fn abs(self) -> F32x8 {
        lanewise!(self, |a| a.abs())
    }

    /// The largest integer not above each lane ([`floor`]).
    #[inline(always)]
    pub fn floor(self) -> F32x8 {
        lanewise!(self, |a| floor(a))
    }

    /// The fractional part `a - floor(a)`, in `[0, 1]`.
    #[inline(always)]
    pub fn fract(self) -> F32x8 {
        lanewise!(self, |a| a - floor(a))
    }

    /// `1 / sqrt(a)` computed exactly (division and square root, no estimate).
    #[inline(always)]
    pub fn inverse_sqrt(self) -> F32x8 {
        lanewise!(self, |a| 1.0 / a.sqrt())
    }

    /// `mask ? a : b` per lane.
    #[inline(always)]
    pub fn select(mask: LaneMask, a: F32x8, b: F32x8) -> F32x8 {
        let (a, b) = (a.to_array(), b.to_array());
        F32x8::from_fn(|i| if mask.contains(i) { a[i] } else { b[i] })
    }

    compare!(lt, <, "Lanes where `self < rhs`.");
    compare!(le, <=, "Lanes where `self <= rhs`.");
    compare!(gt, >, "Lanes where `self > rhs`.");
    compare!(ge, >=, "Lanes where `self >= rhs`.");

    /// Horizontal derivative (`dFdxFine`): per quad row, right pixel minus left pixel.
    #[inline(always)]
    pub fn ddx(self) -> F32x8 {
        let a = self.to_array();
        F32x8::from_array([
            a[1] - a[0],
            a[1] - a[0],
            a[3] - a[2],
            a[3] - a[2],
            a[5] - a[4],
            a[5] - a[4],
            a[7] - a[6],
            a[7] - a[6],
        ])
    }

    /// Vertical derivative (`dFdyFine`): per quad column, bottom pixel minus top pixel.
    #[inline(always)]
    pub fn ddy(self) -> F32x8 {
        let a = self.to_array();
        let d = [a[4] - a[0], a[5] - a[1], a[6] - a[2], a[7] - a[3]];
        F32x8::from_array([d[0], d[1], d[2], d[3], d[0], d[1], d[2], d[3]])
    }
}

impl Add for F32x8 {
    type Output = F32x8;
    #[inline(always)]
    fn add(self, rhs: F32x8) -> F32x8 {
        lanewise!(self, rhs, |a, b| a + b)
    }
}

impl Sub for F32x8 {
    type Output = F32x8;
    #[inline(always)]
    fn sub(self, rhs: F32x8) -> F32x8 {
        lanewise!(self, rhs, |a, b| a - b)
    }
}

impl Mul for F32x8 {
    type Output = F32x8;
    #[inline(always)]
    fn mul(self, rhs: F32x8) -> F32x8 {
        lanewise!(self, rhs, |a, b| a * b)
    }
}

impl Div for F32x8 {
    type Output = F32x8;
    #[inline(always)]
    fn div(self, rhs: F32x8) -> F32x8 {
        lanewise!(self, rhs, |a, b| a / b)
    }
}

impl Mul<f32> for F32x8 {
    type Output = F32x8;
    #[inline(always)]
    fn mul(self, rhs: f32) -> F32x8 {
        self * F32x8::splat(rhs)
    }
}

impl Add<f32> for F32x8 {
    type Output = F32x8;
    #[inline(always)]
    fn add(self, rhs: f32) -> F32x8 {
        self + F32x8::splat(rhs)
    }
}

impl Sub<f32> for F32x8 {
    type Output = F32x8;
    #[inline(always)]
    fn sub(self, rhs: f32) -> F32x8 {
        self - F32x8::splat(rhs)
    }
}

impl Mul<F32x8> for f32 {
    type Output = F32x8;
    #[inline(always)]
    fn mul(self, rhs: F32x8) -> F32x8 {
        rhs * self
    }
}

impl Neg for F32x8 {
    type Output = F32x8;
    #[inline(always)]
    fn neg(self) -> F32x8 {
        lanewise!(self, |a| -a)
    }
}

impl AddAssign for F32x8 {
    #[inline(always)]
    fn add_assign(&mut self, rhs: F32x8) {
        *self = *self + rhs;
    }
}

impl SubAssign for F32x8 {
    #[inline(always)]
    fn sub_assign(&mut self, rhs: F32x8) {
        *self = *self - rhs;
    }
}

impl MulAssign for F32x8 {
    #[inline(always)]
    fn mul_assign(&mut self, rhs: F32x8) {
        *self = *self * rhs;
    }
}

/// `floor` by truncation, exact for every float and vectorisable without SSE4.1 (libm's
/// `floorf` is a call per lane there): magnitudes of 2^23 and above are integers already, and
/// NaN passes through. Unlike libm, `floor(-0.0)` is `+0.0`.
#[inline(always)]
pub fn floor(a: f32) -> f32 {
    // Not `a.abs() >= 2^23`: NaN must take this branch too.
    if a.abs().partial_cmp(&8_388_608.0) != Some(std::cmp::Ordering::Less) {
        return a;
    }
    let t = a as i32 as f32;
    if t > a { t - 1.0 } else { t }
}

/// Four-component vectors of lanes (colours, normals, positions).
pub type Vec4x8 = [F32x8; 4];

/// Dot product of the first three components.
#[inline(always)]
pub fn dot3(a: [F32x8; 3], b: [F32x8; 3]) -> F32x8 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Eight `u32` lanes, held as one 256-bit vector (`__m256i` on x86-64) for the reason
/// [`F32x8`] is: lane arrays carried through integer code (a depth row's words, its compare
/// masks) were taken apart by the SLP vectorizer — a D24S8 row test was 124 instructions in
/// AVX2 code, partly scalar; passed through this type, 60, all 256-bit. Only what moving lanes
/// in and out needs: the arithmetic is written as loops over [`U32x8::to_array`].
#[derive(Clone, Copy)]
#[repr(transparent)]
pub struct U32x8(LanesU8);

#[cfg(target_arch = "x86_64")]
type LanesU8 = std::arch::x86_64::__m256i;

#[cfg(not(target_arch = "x86_64"))]
#[derive(Clone, Copy)]
#[repr(C, align(32))]
struct LanesU8([u32; LANES]);

impl U32x8 {
    #[inline(always)]
    pub const fn from_array(lanes: [u32; LANES]) -> U32x8 {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `[u32; 8]` and `__m256i` are both 32 bytes of plain integers, every bit
        // pattern valid.
        let lanes = unsafe { std::mem::transmute::<[u32; LANES], LanesU8>(lanes) };
        #[cfg(not(target_arch = "x86_64"))]
        let lanes = LanesU8(lanes);
        U32x8(lanes)
    }

    #[inline(always)]
    pub const fn to_array(self) -> [u32; LANES] {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as in `from_array`.
        return unsafe { std::mem::transmute::<LanesU8, [u32; LANES]>(self.0) };
        #[cfg(not(target_arch = "x86_64"))]
        return self.0.0;
    }

    /// Lane `i` is `f(i)` (an always-inlined loop, as [`array_from_fn`]).
    #[inline(always)]
    pub fn from_fn(f: impl FnMut(usize) -> u32) -> U32x8 {
        U32x8::from_array(array_from_fn(f))
    }

    /// Bit `i` set where lane `i`'s top bit is (see [`sign_bits`]).
    #[inline(always)]
    pub fn top_bits(self) -> u8 {
        let lanes = self.to_array();
        sign_bits(array_from_fn(|i| lanes[i] as i32))
    }
}

impl std::fmt::Debug for U32x8 {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("U32x8").field(&self.to_array()).finish()
    }
}

/// Normalises a three-component vector lane by lane (`v * inversesqrt(dot(v, v))`).
#[inline(always)]
pub fn normalize3(v: [F32x8; 3]) -> [F32x8; 3] {
    let inv = dot3(v, v).inverse_sqrt();
    [v[0] * inv, v[1] * inv, v[2] * inv]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivatives_follow_the_quad_layout() {
        // v = x + 10 y over the 4x2 group.
        let v = F32x8::from_fn(|i| LANE_DX[i] as f32 + 10.0 * LANE_DY[i] as f32);
        assert_eq!(v.ddx(), F32x8::splat(1.0));
        assert_eq!(v.ddy(), F32x8::splat(10.0));
    }

    #[test]
    fn quads_expand_to_whole_quads() {
        assert_eq!(LaneMask(0b0000_0001).quads(), LaneMask(0b0011_0011));
        assert_eq!(LaneMask(0b1000_0000).quads(), LaneMask(0b1100_1100));
        assert_eq!(LaneMask(0).quads(), LaneMask(0));
    }

    #[test]
    fn floor_matches_libm() {
        for a in [
            0.0f32,
            0.5,
            -0.5,
            1.0,
            -1.0,
            2.999,
            -2.999,
            8_388_607.5,
            -8_388_607.5,
            1e10,
            -1e10,
            f32::INFINITY,
            0.1,
            -1e-30,
        ] {
            assert_eq!(floor(a), a.floor(), "{a}");
        }
        assert!(floor(f32::NAN).is_nan());
    }

    #[test]
    fn unorm_is_defined_for_every_input() {
        let v = F32x8::from_array([f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 1e30, -1e30, 0.5, 1.0, 0.0]);
        assert_eq!(v.unorm(255.0), [0, 255, 0, 255, 0, 128, 255, 0]);
        assert_eq!(v.unorm(65535.0), [0, 65535, 0, 65535, 0, 32768, 65535, 0]);
        // Out-of-contract scales are clamped, never undefined.
        let top = 16_777_216;
        assert_eq!(v.unorm(f32::INFINITY), [0, top, 0, top, 0, top / 2, top, 0]);
        assert_eq!(v.unorm(1e30), [0, top, 0, top, 0, top / 2, top, 0]);
        assert_eq!(v.unorm(f32::NAN), [0; LANES]);
        assert_eq!(v.unorm(-5.0), [0; LANES]);
    }

    #[test]
    fn avx2_needs_every_feature_it_is_compiled_with() {
        for missing in AVX2_FEATURES {
            let found = SimdSupport::detect_with(SimdLevel::Avx2, |f| f != missing);
            assert_eq!(found, None, "AVX2 granted without {missing}");
        }
        let all = SimdSupport::detect_with(SimdLevel::Avx2, |_| true);
        assert_eq!(all.map(SimdSupport::level), cfg!(target_arch = "x86_64").then_some(SimdLevel::Avx2));
        assert_eq!(SimdSupport::detect_with(SimdLevel::Baseline, |_| false), Some(SimdSupport::BASELINE));
        assert_eq!(SimdSupport::best().level(), SimdLevel::best());
        assert_eq!(SimdLevel::Avx2.is_available(), AVX2_FEATURES.iter().all(|f| processor_has(f)));
    }

    #[test]
    fn clamp_maps_nan_to_low() {
        let v = F32x8::from_array([f32::NAN, -1.0, 0.5, 2.0, 0.0, 1.0, -0.0, 0.25]);
        assert_eq!(v.clamp(0.0, 1.0).to_array(), [0.0, 0.0, 0.5, 1.0, 0.0, 1.0, 0.0, 0.25]);
    }
}
