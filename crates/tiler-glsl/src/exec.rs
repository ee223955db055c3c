//! The shader executor: interprets the IR over `W` lanes at once.
//!
//! Every instruction processes all `W` lanes; the lane count is a const generic, so the
//! fragment shader runs 8 lanes (tiler's 4×2 group), the vertex shader 8 (a batch of
//! vertices), and a wider batch or a JIT can replace [`run`] without touching the compiler. Dispatch (one `match` per
//! instruction) is amortised over the lanes; see the crate docs for measured costs.
//!
//! Masks: `active` holds the lanes still executing; `break`/`continue` move lanes out of it
//! into the innermost loop's (or `switch`'s, [`Inst::Breakable`]) exit mask or the loop's
//! continue mask, `return` into the innermost call's
//! return mask, `discard` into the discarded mask. After an `if`, the lanes that left neither
//! branch carry on; after a loop, those that left it by its condition or by `break`.
//!
//! Loops stop after [`MAX_ITERATIONS`] iterations (lanes still looping leave as if by
//! `break`), so a shader that never ends cannot hang a render.

use crate::ir::{Axis, BANK, BinOp, Inst, Lod, Reg, TriOp, UnOp};

#[cfg(target_arch = "x86_64")]
mod jit;

/// Iterations after which a loop is cut off.
pub const MAX_ITERATIONS: u32 = 1 << 16;

/// The most lookups taken as one run ([`run_length`]).
pub const MAX_RUN: usize = 16;

/// How many instructions from the start of `code` are common lookups of one slot that may
/// run together ([`Env::sample_implicit_run`]): none reads a register an earlier one of them
/// writes (so each reads what it would read one by one), at most [`MAX_RUN`]. `0` when the
/// first is no such lookup.
pub fn run_length(code: &[Inst]) -> usize {
    let Some(slot) = code.first().and_then(crate::schedule::runs_together) else { return 0 };
    let mut written: Vec<Reg> = Vec::new();
    let mut n = 0;
    for inst in code.iter().take(MAX_RUN) {
        let Inst::Sample { dst, coord, .. } = inst else { break };
        if crate::schedule::runs_together(inst) != Some(slot) || coord.iter().any(|c| written.contains(c)) {
            break;
        }
        written.extend(dst);
        n += 1;
    }
    n
}

/// What the executor asks of its caller: texture lookups.
pub trait Env<const W: usize> {
    /// Samples texture slot `slot` at `coord` in the lanes (all `W`; lanes not active have
    /// finite, deterministic coordinates).
    /// `reference`: a shadow sampler's reference depth, `offset` texels added before the wrap
    /// (see `ir::Inst::Sample`).
    fn sample(
        &mut self,
        slot: usize,
        coord: [[f32; W]; 2],
        lod: LodValue<W>,
        reference: Option<[f32; W]>,
        offset: [i32; 2],
    ) -> [[f32; W]; 4];

    /// [`Env::sample`] with an implicit level of detail, no reference and no offset: the
    /// common lookup, which an environment may answer without building the general call's
    /// arguments (mark it `#[inline(always)]`: it is inlined into each instruction set's
    /// interpreter).
    #[inline(always)]
    fn sample_implicit(&mut self, slot: usize, coord: [[f32; W]; 2]) -> [[f32; W]; 4] {
        self.sample(slot, coord, LodValue::Implicit, None, [0, 0])
    }

    /// [`Env::sample_implicit`] at several coordinates of one slot: `out[i]` the texels at
    /// `coords[i]`. An environment may share the lookups' work, but their values and the
    /// texels they read (and the order of the reads) must be those of the lookups one by one,
    /// in order.
    #[inline(always)]
    fn sample_implicit_run(&mut self, slot: usize, coords: &[[[f32; W]; 2]], out: &mut [[[f32; W]; 4]]) {
        for (coord, out) in coords.iter().zip(out) {
            *out = self.sample_implicit(slot, *coord);
        }
    }

    /// Samples cube texture slot `slot` in the direction `direction` in the lanes (finite, as
    /// `sample`'s coordinates).
    fn sample_cube(&mut self, slot: usize, direction: [[f32; W]; 3], lod: LodValue<W>) -> [[f32; W]; 4];

    /// Samples 2-D array or 3-D texture slot `slot` at `coord` (`(s, t, layer)` or
    /// `(s, t, r)`, finite) in the lanes; without such textures, opaque black.
    fn sample_layered(&mut self, slot: usize, coord: [[f32; W]; 3], lod: LodValue<W>) -> [[f32; W]; 4] {
        let _ = (slot, coord, lod);
        [[0.0; W], [0.0; W], [0.0; W], [1.0; W]]
    }

    /// `texelFetch` of slot `slot` (see `ir::Inst::Fetch`): texel `coord` of level `level` in
    /// the lanes, out of range `(0, 0, 0, 0)`; without textures, zeros.
    fn fetch(&mut self, slot: usize, coord: [[i32; W]; 3], level: [i32; W]) -> [[f32; W]; 4] {
        let _ = (slot, coord, level);
        [[0.0; W]; 4]
    }

    /// `textureSize` of slot `slot` at level `level`: width, height, layers; without
    /// textures, zeros.
    fn size(&mut self, slot: usize, level: [i32; W]) -> [[i32; W]; 3] {
        let _ = (slot, level);
        [[0; W]; 3]
    }

    /// The derivative of `v` along `axis` (zero where lanes are not pixels of quads).
    fn derivative(&mut self, v: [f32; W], axis: Axis) -> [f32; W] {
        let _ = (v, axis);
        [0.0; W]
    }
}

/// A level-of-detail argument with its lane values.
#[derive(Clone, Copy, Debug)]
pub enum LodValue<const W: usize> {
    Implicit,
    Bias([f32; W]),
    Explicit([f32; W]),
    /// Derivatives of the coordinates along window x and y (`textureGrad`).
    Grad([[f32; W]; 3], [[f32; W]; 3]),
    /// `textureGather` of a channel (see `ir::Lod::Gather`).
    Gather(u8),
}

/// The lanes' masks while running (`repr(C)`: the compiled code reads them, `jit`).
#[repr(C)]
struct Masks {
    active: u64,
    /// Lanes that executed `return` in the innermost call.
    returned: u64,
    /// Lanes that left the innermost loop (by `break` or its condition).
    exited: u64,
    /// Lanes that executed `continue` in the innermost loop's current iteration.
    continued: u64,
    discarded: u64,
}

/// Code ready to run: the bank's registers renumbered after the work registers, so that one
/// register file holds both (`[work … | bank …]`) and an operand is one index, and every
/// register checked once against the file's size, so that the executor reads and writes
/// without bounds checks.
#[derive(Clone, Debug)]
pub struct Executable {
    code: Vec<Inst>,
    work_regs: usize,
    registers: usize,
    /// The code compiled to machine code for eight lanes (`jit`), where the processor runs it.
    #[cfg(target_arch = "x86_64")]
    compiled: Option<std::sync::Arc<jit::Compiled>>,
}

impl Executable {
    /// `code` over `work_regs` work registers and a bank of `bank_len`; `None` if a register
    /// is out of range or the code writes to the bank (a compiler bug).
    pub fn new(code: &[Inst], work_regs: usize, bank_len: usize) -> Option<Executable> {
        let mut code = code.to_vec();
        let mut valid = true;
        let mut remap = |r: &mut Reg, written: bool| {
            let index = (*r & !BANK) as usize;
            if *r & BANK != 0 && !written && index < bank_len {
                *r = (work_regs + index) as Reg;
            } else if *r & BANK != 0 || index >= work_regs {
                valid = false;
            }
        };
        registers_mut(&mut code, &mut remap);
        if !valid {
            return None;
        }
        #[cfg(target_arch = "x86_64")]
        let compiled = jit::available().then(|| jit::Compiled::new(&code)).flatten().map(std::sync::Arc::new);
        Some(Executable {
            code,
            work_regs,
            registers: work_regs + bank_len,
            #[cfg(target_arch = "x86_64")]
            compiled,
        })
    }

    /// The same program without its machine code: [`run`] interprets it (for tests and
    /// measurements of the two, which give the same bits).
    pub fn interpreted(&self) -> Executable {
        Executable {
            #[cfg(target_arch = "x86_64")]
            compiled: None,
            ..self.clone()
        }
    }

    /// Per register of the file, whether any instruction reads it.
    pub fn read_registers(&self) -> Vec<bool> {
        let mut read = vec![false; self.registers];
        registers_mut(&mut self.code.clone(), &mut |r, written| {
            if !written {
                read[*r as usize] = true;
            }
        });
        read
    }

    /// Whether [`run`] runs machine code compiled from it for eight lanes.
    pub fn is_compiled(&self) -> bool {
        #[cfg(target_arch = "x86_64")]
        return self.compiled.is_some();
        #[cfg(not(target_arch = "x86_64"))]
        false
    }

    /// Where the bank starts in the register file.
    pub fn work_regs(&self) -> usize {
        self.work_regs
    }

    /// The registers the file must hold: the work registers, then the bank.
    pub fn registers(&self) -> usize {
        self.registers
    }

    pub fn code(&self) -> &[Inst] {
        &self.code
    }
}

/// Calls `f` on every register of `code` (nested blocks included), with whether it is
/// written.
fn registers_mut(code: &mut [Inst], f: &mut impl FnMut(&mut Reg, bool)) {
    for inst in code {
        match inst {
            Inst::Un(_, d, a) => {
                f(d, true);
                f(a, false);
            }
            Inst::Bin(_, d, a, b) => {
                f(d, true);
                f(a, false);
                f(b, false);
            }
            Inst::Tri(_, d, a, b, c) => {
                f(d, true);
                f(a, false);
                f(b, false);
                f(c, false);
            }
            Inst::Store(d, s) => {
                f(d, true);
                f(s, false);
            }
            Inst::StoreIf(d, s, c) => {
                f(d, true);
                f(s, false);
                f(c, false);
            }
            Inst::If(c, then, els) => {
                f(c, false);
                registers_mut(then, f);
                registers_mut(els, f);
            }
            Inst::Loop { cond_code, cond, body, step, .. } => {
                if let Some(c) = cond {
                    f(c, false);
                }
                registers_mut(cond_code, f);
                registers_mut(body, f);
                registers_mut(step, f);
            }
            Inst::Call(body) | Inst::Breakable(body) => registers_mut(body, f),
            Inst::Derivative { dst, src, .. } => {
                f(dst, true);
                f(src, false);
            }
            Inst::Sample { dst, coord, lod, reference, .. } => {
                dst.iter_mut().for_each(|d| f(d, true));
                coord.iter_mut().for_each(|c| f(c, false));
                if let Some(r) = reference {
                    f(r, false);
                }
                lod.for_each_reg(|r| f(r, false));
            }
            Inst::SampleCube { dst, direction, lod, .. } | Inst::SampleLayered { dst, coord: direction, lod, .. } => {
                dst.iter_mut().for_each(|d| f(d, true));
                direction.iter_mut().for_each(|c| f(c, false));
                lod.for_each_reg(|r| f(r, false));
            }
            Inst::Fetch { dst, coord, level, .. } => {
                dst.iter_mut().for_each(|d| f(d, true));
                coord.iter_mut().for_each(|c| f(c, false));
                f(level, false);
            }
            Inst::Break | Inst::Continue | Inst::Return | Inst::Discard => {}
        }
    }
}

/// Runs `program` on the register file `regs` (its work registers, then the bank's values
/// from [`Executable::work_regs`] on), for the lanes in `active`. Returns the lanes discarded.
///
/// # Panics
/// If `regs` holds fewer than [`Executable::registers`].
pub fn run<const W: usize, E: Env<W>>(program: &Executable, regs: &mut [[f32; W]], active: u64, env: &mut E) -> u64 {
    assert!(regs.len() >= program.registers, "a register file of {} for {} registers", regs.len(), program.registers);
    let mut masks = Masks { active, returned: 0, exited: 0, continued: 0, discarded: 0 };
    let mut machine = Machine { regs, env };
    #[cfg(target_arch = "x86_64")]
    if W == jit::LANES
        && let Some(compiled) = &program.compiled
    {
        // SAFETY: code is compiled only where the processor has AVX2 and F16C
        // (`jit::available`), from this program's code, whose registers are all below
        // `program.registers` (`Executable::new`), which `regs` holds (asserted above); `W` is
        // eight.
        unsafe { compiled.run(&mut machine, &mut masks) };
        return masks.discarded;
    }
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("f16c") {
        // SAFETY: the processor has AVX2 and F16C (checked just above), the features
        // `block_avx2` enables; every register of the code is below `program.registers`
        // (`Executable::new`), which `regs` holds (asserted above).
        unsafe { machine.block_avx2(&program.code, &mut masks) };
        return masks.discarded;
    }
    // SAFETY: as above, every register is within `regs`.
    unsafe { machine.block(&program.code, &mut masks) };
    masks.discarded
}

/// How a block runs its nested blocks: with the instruction set it was compiled for.
///
/// # Safety
/// Every register of `code` must be within the machine's register file.
trait Nested {
    unsafe fn block<const W: usize, E: Env<W>>(machine: &mut Machine<'_, W, E>, code: &[Inst], m: &mut Masks);

    /// [`round_half`] of every lane.
    ///
    /// # Safety
    /// The instruction set must be the processor's (for `Avx2`: only inside `block_avx2`).
    unsafe fn half<const W: usize>(a: [f32; W]) -> [f32; W];

    /// [`half_toward_zero`] of every lane.
    ///
    /// # Safety
    /// As [`Nested::half`].
    unsafe fn half_toward_zero<const W: usize>(a: [f32; W]) -> [f32; W];
}

/// The baseline instruction set.
struct Baseline;

impl Nested for Baseline {
    unsafe fn block<const W: usize, E: Env<W>>(machine: &mut Machine<'_, W, E>, code: &[Inst], m: &mut Masks) {
        // SAFETY: the caller's guarantee, passed on.
        unsafe { machine.block(code, m) };
    }

    #[inline(always)]
    unsafe fn half<const W: usize>(a: [f32; W]) -> [f32; W] {
        a.map(round_half)
    }

    #[inline(always)]
    unsafe fn half_toward_zero<const W: usize>(a: [f32; W]) -> [f32; W] {
        a.map(half_toward_zero)
    }
}

/// AVX2 and F16C: the lanes' arithmetic in 256-bit registers. The operations are the same
/// IEEE operations (Rust never fuses a multiply and an add), so results are bit for bit those
/// of the baseline; binary16 roundings are F16C's conversions there and back (IEEE's
/// round-to-nearest-even, as [`round_half`]), NaNs kept as they were, as `round_half` keeps
/// them.
#[cfg(target_arch = "x86_64")]
struct Avx2;

#[cfg(target_arch = "x86_64")]
impl Nested for Avx2 {
    unsafe fn block<const W: usize, E: Env<W>>(machine: &mut Machine<'_, W, E>, code: &[Inst], m: &mut Masks) {
        // SAFETY: `Avx2` blocks only run inside `block_avx2`, which `run` calls only when the
        // processor has AVX2 and F16C; the registers are the caller's guarantee.
        unsafe { machine.block_avx2(code, m) }
    }

    #[inline(always)]
    unsafe fn half<const W: usize>(a: [f32; W]) -> [f32; W] {
        // SAFETY: the caller's guarantee: the processor has AVX2 and F16C.
        unsafe { halves::<W, { std::arch::x86_64::_MM_FROUND_TO_NEAREST_INT }>(a, round_half) }
    }

    #[inline(always)]
    unsafe fn half_toward_zero<const W: usize>(a: [f32; W]) -> [f32; W] {
        // SAFETY: as above.
        unsafe { halves::<W, { std::arch::x86_64::_MM_FROUND_TO_ZERO }>(a, half_toward_zero) }
    }
}

/// [`half8`] with rounding `ROUND` of every group of eight lanes, `scalar` of the rest.
///
/// # Safety
/// The processor must have AVX2 and F16C.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn halves<const W: usize, const ROUND: i32>(a: [f32; W], scalar: fn(f32) -> f32) -> [f32; W] {
    let mut out = a;
    let (groups, rest) = out.as_chunks_mut::<8>();
    for g in groups {
        // SAFETY: the caller's guarantee.
        unsafe { half8::<ROUND>(g) };
    }
    for x in rest {
        *x = scalar(*x);
    }
    out
}

/// Eight lanes rounded to binary16 by F16C's conversion there and back, with rounding
/// `ROUND` (imm8 `_MM_FROUND_TO_NEAREST_INT`: [`round_half`], ties to even;
/// `_MM_FROUND_TO_ZERO`: [`half_toward_zero`], ±65504 beyond binary16's range, ±∞ kept); NaNs
/// are put back as they were (the conversion quiets them and drops payload bits).
///
/// # Safety
/// The processor must have AVX2 and F16C.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,f16c")]
#[inline]
unsafe fn half8<const ROUND: i32>(lanes: &mut [f32; 8]) {
    use std::arch::x86_64::{
        _CMP_UNORD_Q, _mm256_blendv_ps, _mm256_cmp_ps, _mm256_cvtph_ps, _mm256_cvtps_ph, _mm256_loadu_ps,
        _mm256_storeu_ps,
    };
    // SAFETY: `lanes` is eight f32s, read and written unaligned.
    let x = unsafe { _mm256_loadu_ps(lanes.as_ptr()) };
    let rounded = _mm256_cvtph_ps(_mm256_cvtps_ph::<ROUND>(x));
    let nan = _mm256_cmp_ps::<_CMP_UNORD_Q>(x, x);
    // SAFETY: as above.
    unsafe { _mm256_storeu_ps(lanes.as_mut_ptr(), _mm256_blendv_ps(rounded, x, nan)) };
}

/// The register file (work registers, then the bank) and the caller's environment.
struct Machine<'a, const W: usize, E> {
    regs: &'a mut [[f32; W]],
    env: &'a mut E,
}

const fn full<const W: usize>() -> u64 {
    if W >= 64 { u64::MAX } else { (1u64 << W) - 1 }
}

/// A lookup's coordinate with NaNs and infinities made 0 (every lane's, active or not).
#[inline(always)]
fn finite<const W: usize>(v: [f32; W]) -> [f32; W] {
    v.map(|x| if x.is_finite() { x } else { 0.0 })
}

impl<const W: usize, E: Env<W>> Machine<'_, W, E> {
    /// # Safety
    /// `r` must be within the register file.
    #[inline(always)]
    unsafe fn get(&self, r: Reg) -> [f32; W] {
        debug_assert!((r as usize) < self.regs.len());
        // SAFETY: the caller's guarantee.
        unsafe { *self.regs.get_unchecked(r as usize) }
    }

    /// # Safety
    /// `r` must be within the register file.
    #[inline(always)]
    unsafe fn set(&mut self, r: Reg, value: [f32; W]) {
        debug_assert!((r as usize) < self.regs.len());
        // SAFETY: the caller's guarantee.
        unsafe { *self.regs.get_unchecked_mut(r as usize) = value };
    }

    /// The lanes where register `r` is true.
    ///
    /// # Safety
    /// `r` must be within the register file.
    #[inline(always)]
    unsafe fn truth(&self, r: Reg) -> u64 {
        // SAFETY: the caller's guarantee.
        let v = unsafe { self.get(r) };
        let mut mask = 0;
        for (lane, &x) in v.iter().enumerate() {
            if x != 0.0 {
                mask |= 1 << lane;
            }
        }
        mask
    }

    /// # Safety
    /// `dst` must be within the register file.
    #[inline(always)]
    unsafe fn store(&mut self, dst: Reg, src: [f32; W], mask: u64) {
        // SAFETY: the caller's guarantee.
        unsafe {
            if mask == full::<W>() {
                self.set(dst, src);
            } else if mask != 0 {
                let mut v = self.get(dst);
                for (lane, x) in v.iter_mut().enumerate() {
                    if mask >> lane & 1 != 0 {
                        *x = src[lane];
                    }
                }
                self.set(dst, v);
            }
        }
    }

    /// One `Inst::Sample` (its fields), as every instruction set's interpreter runs it.
    ///
    /// # Safety
    /// Every register named must be within the register file (and `N` runnable).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)] // the instruction's fields
    unsafe fn sample_inst<N: Nested>(
        &mut self,
        slot: u16,
        dst: &[Reg; 4],
        coord: &[Reg; 2],
        lod: &Lod,
        reference: Option<Reg>,
        offset: [i8; 2],
        round: bool,
    ) {
        // Every register read or written is one of the instruction's (the caller's guarantee).
        #![allow(unsafe_op_in_unsafe_fn)]
        let coord = [finite(self.get(coord[0])), finite(self.get(coord[1]))];
        let texel = if let (Lod::Implicit, None, [0, 0]) = (lod, reference, offset) {
            self.env.sample_implicit(slot as usize, coord)
        } else {
            self.sample_general(slot, coord, lod, reference, offset)
        };
        self.write_texels::<N>(dst, texel, round);
    }

    /// A lookup's texels into its destinations, rounded toward zero to binary16 first when
    /// `round` (every lane: inactive lanes' coordinates are finite, so their texels are too).
    ///
    /// # Safety
    /// Every register of `dst` must be within the register file (and `N` runnable).
    #[inline(always)]
    unsafe fn write_texels<N: Nested>(&mut self, dst: &[Reg; 4], texel: [[f32; W]; 4], round: bool) {
        // SAFETY (each write): the caller's guarantee.
        if round {
            for (c, &d) in dst.iter().enumerate() {
                unsafe { self.set(d, N::half_toward_zero(texel[c])) };
            }
        } else {
            for (c, &d) in dst.iter().enumerate() {
                unsafe { self.set(d, texel[c]) };
            }
        }
    }

    /// A run of common lookups of one slot, as [`run_length`] admits them: every coordinate
    /// read, the lookups made in one call ([`Env::sample_implicit_run`]), then every texel
    /// written — what [`Machine::sample_inst`] of each in turn writes, as none reads what an
    /// earlier one writes.
    ///
    /// # Safety
    /// Every register named must be within the register file (and `N` runnable); `run` must
    /// be at most [`MAX_RUN`] instructions that [`run_length`] takes together.
    #[inline(always)]
    unsafe fn sample_run_inst<N: Nested>(&mut self, run: &[Inst]) {
        // Every register read or written is one of the instructions' (the caller's guarantee).
        #![allow(unsafe_op_in_unsafe_fn)]
        let mut coords = [[[0.0; W]; 2]; MAX_RUN];
        let mut texels = [[[0.0; W]; 4]; MAX_RUN];
        let mut slot = 0;
        for (inst, coords) in run.iter().zip(&mut coords) {
            if let Inst::Sample { slot: s, coord, .. } = inst {
                slot = *s as usize;
                *coords = [finite(self.get(coord[0])), finite(self.get(coord[1]))];
            }
        }
        let n = run.len();
        self.env.sample_implicit_run(slot, &coords[..n], &mut texels[..n]);
        for (inst, &texel) in run.iter().zip(&texels) {
            if let Inst::Sample { dst, round, .. } = inst {
                self.write_texels::<N>(dst, texel, *round);
            }
        }
    }

    /// [`Machine::sample_run_inst`] with AVX2, under `m` (nothing when no lane is active): what
    /// the compiled code calls for a run of lookups.
    ///
    /// # Safety
    /// As [`Machine::block_avx2`], and `run` as [`Machine::sample_run_inst`] takes it.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,f16c")]
    unsafe fn sample_run_avx2(&mut self, run: &[Inst], m: &Masks) {
        if m.active != 0 {
            // SAFETY: the caller's guarantee.
            unsafe { self.sample_run_inst::<Avx2>(run) };
        }
    }

    /// [`Machine::block_avx2`] of the one instruction `inst`, an `Inst::Sample` with an
    /// implicit level of detail, no reference and no offset, under `m`: the same code, without
    /// the frame and dispatch of the whole interpreter (what the compiled code calls for the
    /// common lookup).
    ///
    /// # Safety
    /// As [`Machine::block_avx2`].
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,f16c")]
    unsafe fn sample_implicit_avx2(&mut self, inst: &Inst, m: &mut Masks) {
        match inst {
            Inst::Sample { slot, dst, coord, lod, reference, offset, round } if m.active != 0 => {
                // SAFETY: the caller's guarantee.
                unsafe { self.sample_inst::<Avx2>(*slot, dst, coord, lod, *reference, *offset, *round) };
            }
            // SAFETY: the caller's guarantee.
            _ => unsafe { self.block_avx2(std::slice::from_ref(inst), m) },
        }
    }

    /// A 2D lookup with an explicit, biased, gradient or gather level of detail, a reference or
    /// an offset (out of line: the common lookup is [`Env::sample_implicit`]).
    ///
    /// # Safety
    /// The registers of `lod` and `reference` must be within the register file.
    #[inline(never)]
    unsafe fn sample_general(
        &mut self,
        slot: u16,
        coord: [[f32; W]; 2],
        lod: &Lod,
        reference: Option<Reg>,
        offset: [i8; 2],
    ) -> [[f32; W]; 4] {
        // SAFETY: the caller's guarantee.
        let get = |r: Reg| unsafe { self.get(r) };
        let lod = match lod {
            Lod::Implicit => LodValue::Implicit,
            Lod::Bias(r) => LodValue::Bias(finite(get(*r))),
            Lod::Explicit(r) => LodValue::Explicit(finite(get(*r))),
            Lod::Grad { dx, dy } => LodValue::Grad(dx.map(|r| finite(get(r))), dy.map(|r| finite(get(r)))),
            Lod::Gather(c) => LodValue::Gather(*c),
        };
        // A NaN reference stays NaN: the compare rules say what it gives.
        let reference = reference.map(get);
        self.env.sample(slot as usize, coord, lod, reference, offset.map(i32::from))
    }

    /// # Safety
    /// Every register of `code` must be within the register file.
    unsafe fn block(&mut self, code: &[Inst], m: &mut Masks) {
        // SAFETY: the caller's guarantee.
        unsafe { self.block_in::<Baseline>(code, m) };
    }

    /// # Safety
    /// The processor must have AVX2 and F16C, and every register of `code` must be within the
    /// register file.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,f16c")]
    unsafe fn block_avx2(&mut self, code: &[Inst], m: &mut Masks) {
        // SAFETY: the caller's guarantee.
        unsafe { self.block_in::<Avx2>(code, m) };
    }

    /// Runs `code`; nested blocks run through `N` (the same instruction set).
    ///
    /// # Safety
    /// Every register of `code` must be within the register file (and `N` runnable).
    #[inline(always)]
    unsafe fn block_in<N: Nested>(&mut self, code: &[Inst], m: &mut Masks) {
        // SAFETY: every register access below is of a register of `code`, within the file by
        // the caller's guarantee; nested blocks are parts of `code`.
        unsafe { self.block_in_body::<N>(code, m) }
    }

    #[inline(always)]
    unsafe fn block_in_body<N: Nested>(&mut self, code: &[Inst], m: &mut Masks) {
        // Every operation here reads or writes registers of `code` (see `block_in`).
        #![allow(unsafe_op_in_unsafe_fn)]
        // Only control flow changes the active lanes: checked on entry and after each such
        // instruction (not before every instruction).
        if m.active == 0 {
            return;
        }
        for inst in code {
            match inst {
                // The binary16 roundings, through the instruction set's own rounding.
                Inst::Un(UnOp::Half, d, a) => {
                    let a = self.get(*a);
                    self.set(*d, N::half(a));
                }
                Inst::Un(UnOp::HalfTowardZero, d, a) => {
                    let a = self.get(*a);
                    self.set(*d, N::half_toward_zero(a));
                }
                Inst::Bin(
                    op @ (BinOp::AddHalf | BinOp::SubHalf | BinOp::MulHalf | BinOp::DivHalf | BinOp::HalfMulHalf),
                    d,
                    a,
                    b,
                ) => {
                    let (a, b) = (self.get(*a), self.get(*b));
                    let r: [f32; W] = match op {
                        BinOp::AddHalf => std::array::from_fn(|i| a[i] + b[i]),
                        BinOp::SubHalf => std::array::from_fn(|i| a[i] - b[i]),
                        BinOp::MulHalf => std::array::from_fn(|i| a[i] * b[i]),
                        BinOp::DivHalf => std::array::from_fn(|i| a[i] / b[i]),
                        _ => {
                            let a = N::half(a);
                            std::array::from_fn(|i| a[i] * b[i])
                        }
                    };
                    self.set(*d, N::half(r));
                }
                Inst::Tri(op @ (TriOp::MulAddHalf | TriOp::HalfMulAddHalf), d, a, b, c) => {
                    let (a, b, c) = (self.get(*a), self.get(*b), self.get(*c));
                    let a = if *op == TriOp::HalfMulAddHalf { N::half(a) } else { a };
                    let product: [f32; W] = N::half(std::array::from_fn(|i| a[i] * b[i]));
                    let sum: [f32; W] = std::array::from_fn(|i| product[i] + c[i]);
                    self.set(*d, N::half(sum));
                }
                Inst::Un(op, d, a) => {
                    let a = self.get(*a);
                    self.set(*d, unary(*op, a));
                }
                Inst::Bin(op, d, a, b) => {
                    let (a, b) = (self.get(*a), self.get(*b));
                    self.set(*d, binary(*op, a, b));
                }
                Inst::Tri(op, d, a, b, c) => {
                    let (a, b, c) = (self.get(*a), self.get(*b), self.get(*c));
                    self.set(*d, ternary(*op, a, b, c));
                }
                Inst::Store(d, s) => {
                    let s = self.get(*s);
                    self.store(*d, s, m.active);
                }
                Inst::StoreIf(d, s, c) => {
                    let s = self.get(*s);
                    let mask = m.active & self.truth(*c);
                    self.store(*d, s, mask);
                }
                Inst::If(c, then, els) => {
                    let entry = m.active;
                    let cond = self.truth(*c);
                    m.active = entry & cond;
                    if m.active != 0 {
                        N::block(self, then, m);
                    }
                    let after_then = m.active;
                    m.active = entry & !cond;
                    if m.active != 0 {
                        N::block(self, els, m);
                    }
                    m.active |= after_then;
                    if m.active == 0 {
                        return;
                    }
                }
                Inst::Loop { cond_code, cond, body, step, test_first } => {
                    let (outer_exited, outer_continued) = (m.exited, m.continued);
                    m.exited = 0;
                    let mut first = true;
                    let mut iterations = 0;
                    loop {
                        if !first || *test_first {
                            N::block(self, cond_code, m);
                            if let Some(c) = cond {
                                let t = self.truth(*c);
                                m.exited |= m.active & !t;
                                m.active &= t;
                            }
                        }
                        first = false;
                        iterations += 1;
                        if m.active == 0 || iterations > MAX_ITERATIONS {
                            break;
                        }
                        m.continued = 0;
                        N::block(self, body, m);
                        m.active |= m.continued;
                        N::block(self, step, m);
                    }
                    m.active |= m.exited;
                    m.exited = outer_exited;
                    m.continued = outer_continued;
                    if m.active == 0 {
                        return;
                    }
                }
                Inst::Break => {
                    m.exited |= m.active;
                    m.active = 0;
                    return;
                }
                Inst::Continue => {
                    m.continued |= m.active;
                    m.active = 0;
                    return;
                }
                Inst::Return => {
                    m.returned |= m.active;
                    m.active = 0;
                    return;
                }
                Inst::Discard => {
                    m.discarded |= m.active;
                    m.active = 0;
                    return;
                }
                Inst::Call(body) => {
                    let outer = m.returned;
                    m.returned = 0;
                    N::block(self, body, m);
                    m.active |= m.returned;
                    m.returned = outer;
                    if m.active == 0 {
                        return;
                    }
                }
                Inst::Breakable(body) => {
                    let outer = m.exited;
                    m.exited = 0;
                    N::block(self, body, m);
                    m.active |= m.exited;
                    m.exited = outer;
                    if m.active == 0 {
                        return;
                    }
                }
                Inst::Derivative { dst, src, axis } => {
                    let v = self.get(*src);
                    let d = self.env.derivative(v, *axis);
                    self.set(*dst, d);
                }
                Inst::Sample { slot, dst, coord, lod, reference, offset, round } => {
                    self.sample_inst::<N>(*slot, dst, coord, lod, *reference, *offset, *round);
                }
                Inst::SampleCube { slot, dst, direction, lod } => {
                    let direction = direction.map(|r| finite(self.get(r)));
                    let lod = match lod {
                        Lod::Implicit => LodValue::Implicit,
                        Lod::Bias(r) => LodValue::Bias(finite(self.get(*r))),
                        Lod::Explicit(r) => LodValue::Explicit(finite(self.get(*r))),
                        Lod::Grad { dx, dy } => {
                            LodValue::Grad(dx.map(|r| finite(self.get(r))), dy.map(|r| finite(self.get(r))))
                        }
                        Lod::Gather(c) => LodValue::Gather(*c),
                    };
                    let texel = self.env.sample_cube(*slot as usize, direction, lod);
                    for (c, &d) in dst.iter().enumerate() {
                        self.set(d, texel[c]);
                    }
                }
                Inst::Fetch { slot, dst, coord, level, size } => {
                    let ints = |v: [f32; W]| v.map(|x| x.to_bits() as i32);
                    let level = ints(self.get(*level));
                    if *size {
                        let size = self.env.size(*slot as usize, level);
                        for (c, &d) in dst.iter().enumerate() {
                            self.set(d, size.get(c).map_or([0.0; W], |v| v.map(int)));
                        }
                    } else {
                        let coord = coord.map(|r| ints(self.get(r)));
                        let texel = self.env.fetch(*slot as usize, coord, level);
                        for (c, &d) in dst.iter().enumerate() {
                            self.set(d, texel[c]);
                        }
                    }
                }
                Inst::SampleLayered { slot, dst, coord, lod } => {
                    let coord = coord.map(|r| finite(self.get(r)));
                    let lod = match lod {
                        Lod::Implicit => LodValue::Implicit,
                        Lod::Bias(r) => LodValue::Bias(finite(self.get(*r))),
                        Lod::Explicit(r) => LodValue::Explicit(finite(self.get(*r))),
                        Lod::Grad { dx, dy } => {
                            LodValue::Grad(dx.map(|r| finite(self.get(r))), dy.map(|r| finite(self.get(r))))
                        }
                        Lod::Gather(c) => LodValue::Gather(*c),
                    };
                    let texel = self.env.sample_layered(*slot as usize, coord, lod);
                    for (c, &d) in dst.iter().enumerate() {
                        self.set(d, texel[c]);
                    }
                }
            }
        }
    }
}

#[inline(always)]
fn b(x: bool) -> f32 {
    if x { 1.0 } else { 0.0 }
}

/// An int's register value (its bits; see `ir`).
#[inline(always)]
pub fn int(x: i32) -> f32 {
    f32::from_bits(x as u32)
}

/// The int a register holds.
#[inline(always)]
pub fn as_int(x: f32) -> i32 {
    x.to_bits() as i32
}

/// A uint's register value.
#[inline(always)]
pub fn uint(x: u32) -> f32 {
    f32::from_bits(x)
}

/// Runs straight-line arithmetic over bank registers (a program instance's hoisted code).
pub fn run_bank<const W: usize>(code: &[Inst], bank: &mut [[f32; W]]) {
    let at = |r: Reg| (r & !BANK) as usize;
    for inst in code {
        match *inst {
            Inst::Un(op, d, a) => bank[at(d)] = unary(op, bank[at(a)]),
            Inst::Bin(op, d, a, b) => bank[at(d)] = binary(op, bank[at(a)], bank[at(b)]),
            Inst::Tri(op, d, a, b, c) => bank[at(d)] = ternary(op, bank[at(a)], bank[at(b)], bank[at(c)]),
            _ => debug_assert!(false, "only arithmetic is hoisted"),
        }
    }
}

#[inline(always)]
pub(crate) fn unary<const W: usize>(op: UnOp, a: [f32; W]) -> [f32; W] {
    let f: fn(f32) -> f32 = match op {
        UnOp::Mov => return a,
        UnOp::Neg => return a.map(|x| -x),
        UnOp::Not => |x| b(x == 0.0),
        UnOp::Abs => f32::abs,
        UnOp::Sign => |x| {
            if x > 0.0 {
                1.0
            } else if x < 0.0 {
                -1.0
            } else {
                0.0
            }
        },
        UnOp::Floor => return a.map(f32::floor),
        UnOp::Ceil => f32::ceil,
        UnOp::Fract => return a.map(|x| x - x.floor()),
        UnOp::Trunc => f32::trunc,
        UnOp::Round => f32::round,
        UnOp::Sin => f32::sin,
        UnOp::Cos => f32::cos,
        UnOp::Tan => f32::tan,
        UnOp::Asin => f32::asin,
        UnOp::Acos => f32::acos,
        UnOp::Atan => f32::atan,
        UnOp::Exp => f32::exp,
        UnOp::Log => f32::ln,
        UnOp::Exp2 => f32::exp2,
        UnOp::Log2 => f32::log2,
        UnOp::Sqrt => return a.map(f32::sqrt),
        UnOp::InverseSqrt => return a.map(|x| 1.0 / x.sqrt()),
        UnOp::Radians => |x| x * (std::f32::consts::PI / 180.0),
        UnOp::Degrees => |x| x * (180.0 / std::f32::consts::PI),
        UnOp::ToBool => |x| b(x != 0.0),
        UnOp::IToBool => |x| b(x.to_bits() != 0),
        UnOp::INeg => |x| int(as_int(x).wrapping_neg()),
        UnOp::IAbs => |x| int(as_int(x).wrapping_abs()),
        UnOp::ISign => |x| int(as_int(x).signum()),
        UnOp::BitNot => |x| f32::from_bits(!x.to_bits()),
        UnOp::IToF => |x| as_int(x) as f32,
        UnOp::UToF => |x| x.to_bits() as f32,
        // `as` truncates toward zero and saturates, NaN → 0.
        UnOp::FToI => |x| int(x as i32),
        UnOp::FToU => |x| f32::from_bits(x as u32),
        UnOp::Half => {
            let mut out = a;
            for x in &mut out {
                *x = round_half(*x);
            }
            return out;
        }
        UnOp::HalfTowardZero => half_toward_zero,
        UnOp::FToHalf => |x| f32::from_bits(u32::from(half::f16::from_f32(x).to_bits())),
        UnOp::HalfToF => |x| half::f16::from_bits(x.to_bits() as u16).to_f32(),
    };
    a.map(f)
}

/// `x` rounded to the nearest IEEE binary16 value (ties to even), as an `f32`: ±∞ beyond
/// the largest (65504), binary16's subnormals below 2⁻¹⁴, NaN and ∞ kept. The same value as
/// `half::f16::from_f32(x).to_f32()` (tested), without the conversion's feature detection per
/// call.
#[inline(always)]
pub(crate) fn round_half(x: f32) -> f32 {
    // Branch-free, so that eight lanes compile to vector code.
    let bits = x.to_bits();
    let sign = bits & 0x8000_0000;
    let abs = bits & 0x7fff_ffff;
    // Keep 10 of the 23 fraction bits, rounding to nearest even; a carry moves the exponent.
    // 2¹⁶ and beyond (65520 rounds there) are out of range: ∞.
    let normal = (abs + 0xfff + ((abs >> 13) & 1)) & !0x1fff;
    let normal = if normal >= 0x4780_0000 { 0x7f80_0000 } else { normal };
    // Below 2⁻¹⁴ binary16 steps by 2⁻²⁴: adding ½ (whose ulp is 2⁻²⁴) rounds to it.
    let subnormal = ((f32::from_bits(abs) + 0.5) - 0.5).to_bits();
    let r = if abs >= 0x7f80_0000 {
        abs
    } else if abs < 0x3880_0000 {
        subnormal
    } else {
        normal
    };
    f32::from_bits(r | sign)
}

/// `x` rounded toward zero to an IEEE binary16 value, as an `f32`: ±65504 beyond it,
/// binary16's subnormals (steps of 2⁻²⁴) below 2⁻¹⁴, NaN and ∞ kept.
pub(crate) fn half_toward_zero(x: f32) -> f32 {
    let abs = x.abs();
    let r = if !abs.is_finite() {
        abs
    } else if abs >= 65504.0 {
        65504.0
    } else if abs < f32::from_bits(0x3880_0000) {
        // Exact: scaling by a power of two and truncating to an integer below 2¹⁰.
        (abs * 16_777_216.0).trunc() / 16_777_216.0
    } else {
        // Drop 13 of the 23 fraction bits.
        f32::from_bits(abs.to_bits() & !0x1fff)
    };
    r.copysign(x)
}

#[inline(always)]
pub(crate) fn binary<const W: usize>(op: BinOp, a: [f32; W], c: [f32; W]) -> [f32; W] {
    let mut out = [0.0; W];
    macro_rules! lanes {
        ($f:expr) => {{
            let f = $f;
            for i in 0..W {
                out[i] = f(a[i], c[i]);
            }
        }};
    }
    // Integer operations: the registers' bits as i32 or u32.
    macro_rules! ilanes {
        ($f:expr) => {{
            let f = $f;
            for i in 0..W {
                out[i] = f(as_int(a[i]), as_int(c[i]));
            }
        }};
    }
    macro_rules! ulanes {
        ($f:expr) => {{
            let f = $f;
            for i in 0..W {
                out[i] = f(a[i].to_bits(), c[i].to_bits());
            }
        }};
    }
    match op {
        BinOp::Add => lanes!(|x: f32, y: f32| x + y),
        BinOp::AddHalf => lanes!(|x: f32, y: f32| round_half(x + y)),
        BinOp::SubHalf => lanes!(|x: f32, y: f32| round_half(x - y)),
        BinOp::MulHalf => lanes!(|x: f32, y: f32| round_half(x * y)),
        BinOp::DivHalf => lanes!(|x: f32, y: f32| round_half(x / y)),
        BinOp::HalfMulHalf => lanes!(|x: f32, y: f32| round_half(round_half(x) * y)),
        BinOp::Sub => lanes!(|x: f32, y: f32| x - y),
        BinOp::Mul => lanes!(|x: f32, y: f32| x * y),
        BinOp::Div => lanes!(|x: f32, y: f32| x / y),
        BinOp::IAdd => ilanes!(|x: i32, y: i32| int(x.wrapping_add(y))),
        BinOp::ISub => ilanes!(|x: i32, y: i32| int(x.wrapping_sub(y))),
        BinOp::IMul => ilanes!(|x: i32, y: i32| int(x.wrapping_mul(y))),
        BinOp::IDiv => ilanes!(|x: i32, y: i32| int(if y == 0 { 0 } else { x.wrapping_div(y) })),
        BinOp::IRem => ilanes!(|x: i32, y: i32| int(if y == 0 { 0 } else { x.wrapping_rem(y) })),
        BinOp::UDiv => ulanes!(|x: u32, y: u32| uint(x.checked_div(y).unwrap_or(0))),
        BinOp::URem => ulanes!(|x: u32, y: u32| uint(x.checked_rem(y).unwrap_or(0))),
        BinOp::IMin => ilanes!(|x: i32, y: i32| int(x.min(y))),
        BinOp::IMax => ilanes!(|x: i32, y: i32| int(x.max(y))),
        BinOp::UMin => ulanes!(|x: u32, y: u32| uint(x.min(y))),
        BinOp::UMax => ulanes!(|x: u32, y: u32| uint(x.max(y))),
        BinOp::ILt => ilanes!(|x: i32, y: i32| b(x < y)),
        BinOp::ILe => ilanes!(|x: i32, y: i32| b(x <= y)),
        BinOp::IGt => ilanes!(|x: i32, y: i32| b(x > y)),
        BinOp::IGe => ilanes!(|x: i32, y: i32| b(x >= y)),
        BinOp::ULt => ulanes!(|x: u32, y: u32| b(x < y)),
        BinOp::ULe => ulanes!(|x: u32, y: u32| b(x <= y)),
        BinOp::UGt => ulanes!(|x: u32, y: u32| b(x > y)),
        BinOp::UGe => ulanes!(|x: u32, y: u32| b(x >= y)),
        BinOp::IEq => ulanes!(|x: u32, y: u32| b(x == y)),
        BinOp::INe => ulanes!(|x: u32, y: u32| b(x != y)),
        BinOp::BitAnd => ulanes!(|x: u32, y: u32| uint(x & y)),
        BinOp::BitOr => ulanes!(|x: u32, y: u32| uint(x | y)),
        BinOp::BitXor => ulanes!(|x: u32, y: u32| uint(x ^ y)),
        // `wrapping_sh*` take the count modulo 32.
        BinOp::Shl => ulanes!(|x: u32, y: u32| uint(x.wrapping_shl(y))),
        BinOp::IShr => ulanes!(|x: u32, y: u32| int((x as i32).wrapping_shr(y))),
        BinOp::UShr => ulanes!(|x: u32, y: u32| uint(x.wrapping_shr(y))),
        BinOp::Mod => lanes!(|x: f32, y: f32| x - y * (x / y).floor()),
        BinOp::Min => lanes!(|x: f32, y: f32| if y < x { y } else { x }),
        BinOp::Max => lanes!(|x: f32, y: f32| if x < y { y } else { x }),
        BinOp::Pow => lanes!(f32::powf),
        BinOp::Atan2 => lanes!(f32::atan2),
        BinOp::Step => lanes!(|edge: f32, x: f32| if x < edge { 0.0 } else { 1.0 }),
        BinOp::Lt => lanes!(|x: f32, y: f32| b(x < y)),
        BinOp::Le => lanes!(|x: f32, y: f32| b(x <= y)),
        BinOp::Gt => lanes!(|x: f32, y: f32| b(x > y)),
        BinOp::Ge => lanes!(|x: f32, y: f32| b(x >= y)),
        BinOp::Eq => lanes!(|x: f32, y: f32| b(x == y)),
        BinOp::Ne => lanes!(|x: f32, y: f32| b(x != y)),
        BinOp::And => lanes!(|x: f32, y: f32| b(x != 0.0 && y != 0.0)),
        BinOp::Or => lanes!(|x: f32, y: f32| b(x != 0.0 || y != 0.0)),
        BinOp::Xor => lanes!(|x: f32, y: f32| b((x != 0.0) != (y != 0.0))),
    }
    out
}

#[inline(always)]
pub(crate) fn ternary<const W: usize>(op: TriOp, a: [f32; W], b: [f32; W], c: [f32; W]) -> [f32; W] {
    let mut out = [0.0; W];
    macro_rules! lanes {
        ($f:expr) => {{
            let f = $f;
            for i in 0..W {
                out[i] = f(a[i], b[i], c[i]);
            }
        }};
    }
    match op {
        TriOp::Clamp => lanes!(clamp),
        TriOp::IClamp => lanes!(|x: f32, lo: f32, hi: f32| int(as_int(x).max(as_int(lo)).min(as_int(hi)))),
        TriOp::UClamp => lanes!(|x: f32, lo: f32, hi: f32| uint(x.to_bits().max(lo.to_bits()).min(hi.to_bits()))),
        TriOp::Mix => lanes!(|x: f32, y: f32, t: f32| x * (1.0 - t) + y * t),
        TriOp::Smoothstep => lanes!(smoothstep),
        TriOp::Select => lanes!(|c: f32, x: f32, y: f32| if c != 0.0 { x } else { y }),
        TriOp::MulAdd => lanes!(|x: f32, y: f32, z: f32| x * y + z),
        TriOp::MulAddHalf => lanes!(|x: f32, y: f32, z: f32| round_half(round_half(x * y) + z)),
        TriOp::HalfMulAddHalf => {
            lanes!(|x: f32, y: f32, z: f32| round_half(round_half(round_half(x) * y) + z))
        }
    }
    out
}

/// GLSL `clamp`: `min(max(x, lo), hi)` with GLSL's `min`/`max` (the second operand when
/// the comparison fails, so NaN handling is fixed).
#[inline(always)]
pub fn clamp(x: f32, lo: f32, hi: f32) -> f32 {
    let m = if x < lo { lo } else { x };
    if hi < m { hi } else { m }
}

/// GLSL `smoothstep`.
#[inline(always)]
pub fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = clamp((x - e0) / (e1 - e0), 0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    struct NoTextures;
    impl<const W: usize> Env<W> for NoTextures {
        fn sample_cube(&mut self, _: usize, _: [[f32; W]; 3], _: LodValue<W>) -> [[f32; W]; 4] {
            unreachable!("no textures")
        }
        fn sample(
            &mut self,
            _: usize,
            _: [[f32; W]; 2],
            _: LodValue<W>,
            _: Option<[f32; W]>,
            _: [i32; 2],
        ) -> [[f32; W]; 4] {
            [[0.0; W]; 4]
        }
    }

    /// Runs `code` over the work registers `regs` and the bank `bank` (the register file is
    /// both; the work registers are copied back).
    fn run_with_bank<const W: usize>(code: &[Inst], regs: &mut [[f32; W]], bank: &[[f32; W]], active: u64) -> u64 {
        let program = Executable::new(code, regs.len(), bank.len()).expect("registers in range");
        let mut file: Vec<[f32; W]> = regs.iter().chain(bank).copied().collect();
        let discarded = run(&program, &mut file, active, &mut NoTextures);
        regs.copy_from_slice(&file[..regs.len()]);
        discarded
    }

    #[test]
    fn out_of_range_registers_and_bank_writes_are_refused() {
        assert!(Executable::new(&[Inst::Un(UnOp::Mov, 0, BANK)], 1, 1).is_some());
        assert!(Executable::new(&[Inst::Un(UnOp::Mov, 1, BANK)], 1, 1).is_none());
        assert!(Executable::new(&[Inst::Un(UnOp::Mov, 0, BANK | 1)], 1, 1).is_none());
        assert!(Executable::new(&[Inst::Un(UnOp::Mov, BANK, 0)], 1, 1).is_none());
        let nested = Inst::If(0, vec![], vec![Inst::Store(3, 0)]);
        assert!(Executable::new(&[nested], 2, 4).is_none());
    }

    #[test]
    fn divergent_loop_break_keeps_each_lanes_count() {
        // r0 = lane limit (input), r1 = counter, r2 = cond, bank 0 = 1.0, bank 1 = 100.
        // while (true) { if (r1 >= r0) break; r1 += 1; }
        let code = vec![Inst::Loop {
            cond_code: vec![],
            cond: None,
            body: vec![
                Inst::Bin(BinOp::Ge, 2, 1, 0),
                Inst::If(2, vec![Inst::Break], vec![]),
                Inst::Bin(BinOp::Add, 3, 1, BANK),
                Inst::Store(1, 3),
            ],
            step: vec![],
            test_first: true,
        }];
        let mut regs = [[0.0f32; 4]; 4];
        regs[0] = [0.0, 1.0, 5.0, 3.0];
        let bank = [[1.0f32; 4]];
        let discarded = run_with_bank(&code, &mut regs, &bank, 0b1111);
        assert_eq!(discarded, 0);
        assert_eq!(regs[1], [0.0, 1.0, 5.0, 3.0]);
    }

    /// The AVX2 and baseline interpreters give the same bits.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn round_half_is_binary16_rounding() {
        // Every 251st bit pattern, and the edges: around 2⁻¹⁴, 2⁻²⁴, 65504, ties.
        let edges = [
            0x3880_0000u32,
            0x387f_ffff,
            0x3380_0000,
            0x3300_0000,
            0x3300_0001,
            0x477f_e000,
            0x477f_efff,
            0x477f_f000,
            0x4780_0000,
            0x3f80_1000,
            0x3f80_3000,
            0x7fc0_0000,
            0x7f80_0000,
        ];
        for bits in (0..=u32::MAX).step_by(251).chain(edges).chain(edges.map(|b| b | 0x8000_0000)) {
            let x = f32::from_bits(bits);
            let want = half::f16::from_f32(x).to_f32();
            let got = super::round_half(x);
            assert!(got.to_bits() == want.to_bits() || got.is_nan() && want.is_nan(), "{bits:#x}: {got} {want}");
        }
    }

    /// `half_toward_zero` gives the binary16 value of largest magnitude not beyond `x`.
    #[test]
    fn half_toward_zero_is_binary16_truncation() {
        let edges =
            [0x3880_0000u32, 0x387f_ffff, 0x3380_0001, 0x3300_0000, 0x477f_e000, 0x477f_ffff, 0x4780_0000, 0x3d70_e000];
        for bits in (0..=u32::MAX).step_by(251).chain(edges).chain(edges.map(|b| b | 0x8000_0000)) {
            let x = f32::from_bits(bits);
            let nearest = half::f16::from_f32(x.abs());
            let want = if nearest.to_f32() > x.abs() { half::f16::from_bits(nearest.to_bits() - 1) } else { nearest };
            let want = want.to_f32().copysign(x);
            let got = super::half_toward_zero(x);
            assert!(got.to_bits() == want.to_bits() || got.is_nan() && x.is_nan(), "{bits:#x}: {got} {want}");
        }
        // 30/255 (a texel of an RGBA8 texture): 1927.53 steps of 2⁻¹⁴, llvmpipe's 1927.
        assert_eq!(super::half_toward_zero(30.0 / 255.0), 1927.0 / 16384.0);
    }

    /// F16C's rounding, NaNs included, gives `round_half`'s bits.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn f16c_rounding_is_round_half() {
        if !(std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("f16c")) {
            eprintln!("skipped: no AVX2 and F16C");
            return;
        }
        let edges = [0x3880_0000u32, 0x387f_ffff, 0x3300_0000, 0x3300_0001, 0x477f_efff, 0x477f_f000, 0x7fc0_0001];
        let patterns: Vec<u32> =
            (0..=u32::MAX).step_by(97).chain(edges).chain(edges.map(|b| b | 0x8000_0000)).collect();
        let mut rounded = 0;
        for chunk in patterns.chunks(8) {
            let mut lanes = [0.0f32; 8];
            for (l, &b) in lanes.iter_mut().zip(chunk) {
                *l = f32::from_bits(b);
            }
            let want = lanes.map(round_half);
            // SAFETY: AVX2 and F16C were detected above.
            let got = unsafe { <Avx2 as Nested>::half(lanes) };
            assert_eq!(got.map(f32::to_bits), want.map(f32::to_bits), "{chunk:#x?}");
            rounded += usize::from(want != lanes);
            // Toward zero the same way (F16C's imm8 3), NaNs kept.
            let want = lanes.map(half_toward_zero);
            // SAFETY: as above.
            let got = unsafe { <Avx2 as Nested>::half_toward_zero(lanes) };
            assert_eq!(got.map(f32::to_bits), want.map(f32::to_bits), "toward zero: {chunk:#x?}");
        }
        assert!(rounded > 0, "some lanes were rounded");
    }

    #[test]
    fn avx2_matches_baseline() {
        if !(std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("f16c")) {
            return;
        }
        let ops = [BinOp::Add, BinOp::Sub, BinOp::Mul, BinOp::Div, BinOp::Mod, BinOp::Min, BinOp::Pow];
        let mut code = Vec::new();
        for (i, &op) in ops.iter().enumerate() {
            code.push(Inst::Bin(op, 2 + i as Reg, 0, 1));
        }
        code.push(Inst::Un(UnOp::Sqrt, 20, 4));
        code.push(Inst::Un(UnOp::InverseSqrt, 21, 1));
        code.push(Inst::Tri(TriOp::Smoothstep, 22, 0, 1, 4));
        code.push(Inst::Tri(TriOp::Mix, 23, 0, 1, 3));
        code.push(Inst::Tri(TriOp::MulAdd, 19, 0, 1, 3));
        code.push(Inst::Un(UnOp::Half, 9, 2));
        code.push(Inst::Un(UnOp::HalfTowardZero, 17, 2));
        code.push(Inst::Un(UnOp::HalfTowardZero, 18, 1));
        code.push(Inst::Bin(BinOp::AddHalf, 10, 0, 1));
        code.push(Inst::Bin(BinOp::SubHalf, 11, 0, 1));
        code.push(Inst::Bin(BinOp::MulHalf, 12, 0, 1));
        code.push(Inst::Bin(BinOp::DivHalf, 13, 0, 1));
        code.push(Inst::Bin(BinOp::HalfMulHalf, 14, 0, 1));
        code.push(Inst::Tri(TriOp::MulAddHalf, 15, 0, 1, 3));
        code.push(Inst::Tri(TriOp::HalfMulAddHalf, 16, 0, 1, 3));
        let mut inputs = [[0.0f32; 8]; 24];
        inputs[0] = [0.1, -2.5, 3.3, 1e-8, 7.0, -0.0, 1e30, 0.3];
        inputs[1] = [0.7, 1.9, -4.1, 3.0, 0.001, 2.0, 1e-30, 0.9];
        let (mut a, mut b) = (inputs, inputs);
        let masks = || Masks { active: 0xff, returned: 0, exited: 0, continued: 0, discarded: 0 };
        // SAFETY: the code's registers are below 24, the files' size.
        unsafe { Machine { regs: &mut a, env: &mut NoTextures }.block(&code, &mut masks()) };
        // SAFETY: AVX2 and F16C were detected above, and the registers are as above.
        unsafe { Machine { regs: &mut b, env: &mut NoTextures }.block_avx2(&code, &mut masks()) };
        let bits = |r: &[[f32; 8]; 24]| r.map(|v| v.map(f32::to_bits));
        assert_eq!(bits(&a), bits(&b));
        assert_ne!(a[20], inputs[20], "the code ran");
    }

    /// Texels made of the coordinates: `s` (plus the offset's x), `s + t`, `s + 2t`, and NaNs
    /// with payloads in alpha.
    struct CoordTexels;
    impl Env<8> for CoordTexels {
        fn sample_cube(&mut self, _: usize, _: [[f32; 8]; 3], _: LodValue<8>) -> [[f32; 8]; 4] {
            unreachable!("no cube textures")
        }
        fn sample(
            &mut self,
            _: usize,
            coord: [[f32; 8]; 2],
            _: LodValue<8>,
            _: Option<[f32; 8]>,
            offset: [i32; 2],
        ) -> [[f32; 8]; 4] {
            std::array::from_fn(|c| {
                std::array::from_fn(|i| match c {
                    0 => coord[0][i] + offset[0] as f32,
                    // NaNs with payloads, signalling and quiet.
                    3 => f32::from_bits(0x7f80_0001 + 0x0011_1111 * i as u32),
                    _ => coord[0][i] + c as f32 * coord[1][i],
                })
            })
        }
    }

    /// A lookup that rounds its texels (`Sample`'s `round`) writes what the lookup and four
    /// `HalfTowardZero`s write, through the common lookup and the general one, at both
    /// instruction sets.
    #[test]
    fn a_rounding_lookup_is_a_lookup_and_its_roundings() {
        use crate::ir::Lod;
        let sample = |dst: [Reg; 4], round, offset| Inst::Sample {
            slot: 0,
            dst,
            coord: [0, 1],
            lod: Lod::Implicit,
            reference: None,
            offset,
            round,
        };
        let mut inputs = [[0.0f32; 8]; 16];
        inputs[0] = [0.1, -2.5, 7.0e4, 1e-6, f32::from_bits(0x7fc0_1234), -0.0, 65519.0, 0.3];
        inputs[1] = [0.7, 1.9, -4.1, 3.0, 0.001, f32::from_bits(0x7f80_0001), 1e-30, 0.9];
        for offset in [[0, 0], [1, 0]] {
            let mut apart = vec![sample([2, 3, 4, 5], false, offset)];
            apart.extend((0..4).map(|c| Inst::Un(UnOp::HalfTowardZero, 6 + c, 2 + c)));
            let folded = vec![sample([6, 7, 8, 9], true, offset)];
            let masks = || Masks { active: 0xff, returned: 0, exited: 0, continued: 0, discarded: 0 };
            let mut results = Vec::new();
            for code in [&apart, &folded] {
                let mut regs = inputs;
                // SAFETY: the code's registers are below 16, the file's size.
                unsafe { Machine { regs: &mut regs, env: &mut CoordTexels }.block(code, &mut masks()) };
                results.push(regs[6..10].iter().map(|v| v.map(f32::to_bits)).collect::<Vec<_>>());
                #[cfg(target_arch = "x86_64")]
                if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("f16c") {
                    let mut regs = inputs;
                    // SAFETY: AVX2 and F16C were detected, and the registers are as above.
                    unsafe { Machine { regs: &mut regs, env: &mut CoordTexels }.block_avx2(code, &mut masks()) };
                    results.push(regs[6..10].iter().map(|v| v.map(f32::to_bits)).collect::<Vec<_>>());
                }
            }
            assert!(results.iter().all(|r| *r == results[0]), "{offset:?}: {results:x?}");
            assert_ne!(results[0][0], inputs[0].map(f32::to_bits), "the texels were rounded");
        }
    }

    #[test]
    fn endless_loop_is_cut_off() {
        let code = vec![Inst::Loop { cond_code: vec![], cond: None, body: vec![], step: vec![], test_first: true }];
        let mut regs = [[0.0f32; 1]; 1];
        run_with_bank(&code, &mut regs, &[], 1);
    }

    #[test]
    fn masked_store_leaves_inactive_lanes() {
        let code = vec![Inst::Store(0, BANK)];
        let mut regs = [[5.0f32; 2]];
        run_with_bank(&code, &mut regs, &[[7.0, 7.0]], 0b10);
        assert_eq!(regs[0], [5.0, 7.0]);
    }
}
