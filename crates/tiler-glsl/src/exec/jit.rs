//! The executor's template compiler: the IR of an [`Executable`](super::Executable) turned
//! into x86-64 machine code (AVX2 and F16C) once per program, run in place of the interpreter
//! for eight lanes.
//!
//! **Why.** The interpreter dispatches every instruction (a `match`, its operands' addresses,
//! a call per nested block): on glmark2's captures the executor is 15–30% of a replay, and
//! most of it is that dispatch. The compiled code is the same operations without it: each
//! instruction becomes the few AVX2 instructions the interpreter's own AVX2 loop performs,
//! with the registers left in the register file (`[rbx + 32·r]`), so that no register
//! allocation is needed and every instruction reads and writes memory where the interpreter
//! does.
//!
//! **The same bits.** Only operations whose x86 instructions give the interpreter's results
//! bit for bit are compiled inline: IEEE addition, subtraction, multiplication, division and
//! square root (`vaddps` …, never fused), comparisons to `0.0`/`1.0`, `min`/`max`/`clamp` in
//! the operand order that makes `minps`/`maxps` the interpreter's `if y < x { y } else { x }`,
//! `floor`/`ceil`/`trunc` (`roundps`), selects, the binary16 roundings (F16C's conversions
//! there and back with NaNs put back, as the interpreter's `half8`), wrapping integer
//! arithmetic, compares and bit operations. Every other instruction — transcendentals,
//! conversions with saturation, texture lookups, derivatives — is a call back into the
//! interpreter for that one instruction (a one-instruction block of
//! [`Machine::block_avx2`]), so it runs the interpreter's own code; the common lookup
//! (`texture2D` with an implicit level of detail) calls the interpreter's code for `Sample`
//! directly ([`sample_fallback`]), without the whole interpreter's frame and dispatch, and a
//! run of such lookups of one texture (`super::run_length`; the compiler brings them together,
//! see `schedule`) is one call for all of them ([`sample_run_fallback`]). Control flow (`if`,
//! loops, `break`/`continue`/`return`/`discard`, inlined calls, `switch` bodies) is compiled
//! with the interpreter's mask rules, restated beside each construct below; the masks stay in
//! the interpreter's [`Masks`], in memory. Tests hold the two equal on random programs,
//! register by register and bit by bit.
//!
//! **Safety.** The code addresses only the register file, at `rbx + 32·r` for registers `r`
//! that `Executable::new` checked to be below `Executable::registers` (which `run` asserts
//! the file holds); the [`Masks`] at `r12`; the lane-mask table at `r14` (256 entries, indexed
//! by a byte); its own stack frame; and constants in its own buffer. It calls only the three
//! fallbacks the caller hands over in the [`Context`], with their System V signature and the
//! stack aligned to 16 bytes, and restores every callee-saved register it uses. The buffer is
//! executable and not writable once finalised.

use std::ffi::c_void;

use dynasmrt::{AssemblyOffset, DynamicLabel, DynasmApi, DynasmLabelApi, ExecutableBuffer, dynasm, x64::Assembler};

use super::{Env, MAX_ITERATIONS, Machine, Masks};
use crate::ir::{BinOp, Inst, Lod, TriOp, UnOp, count_insts};

/// The largest program compiled (instructions, nested ones included): past it the interpreter
/// runs it (its code would be megabytes, compiled for every program instance's link).
const MAX_COMPILED_INSTRUCTIONS: usize = 1 << 16;

/// The lanes the compiled code runs: a register is 32 bytes.
pub(super) const LANES: usize = 8;

/// What the compiled code is handed: where the registers and masks are, and how to run one
/// instruction in the interpreter. The code and the fallback reach the register file, the
/// masks and the environment only through these pointers, each made once from the caller's
/// borrows, so no access invalidates another's pointer.
#[repr(C)]
pub(super) struct Context {
    regs: *mut [f32; LANES],
    masks: *mut Masks,
    fallback: Fallback,
    lane_masks: *const [u32; LANES],
    /// The register file's length, and the environment (an `E` of the fallback's).
    registers: usize,
    env: *mut c_void,
    /// The fallback for the common lookup (`Inst::Sample` with an implicit level of detail,
    /// no reference and no offset): the same interpreter code without its dispatch.
    sample: Fallback,
    /// The fallback for a run of common lookups of one slot (`super::run_length`).
    sample_run: RunFallback,
}

// The offsets the code reads the context at.
const CONTEXT_REGS: i32 = 0;
const CONTEXT_MASKS: i32 = 8;
const CONTEXT_FALLBACK: i32 = 16;
const CONTEXT_LANE_MASKS: i32 = 24;
const CONTEXT_SAMPLE: i32 = 48;
const CONTEXT_SAMPLE_RUN: i32 = 56;
const _: () = {
    assert!(std::mem::offset_of!(Context, regs) == CONTEXT_REGS as usize);
    assert!(std::mem::offset_of!(Context, masks) == CONTEXT_MASKS as usize);
    assert!(std::mem::offset_of!(Context, fallback) == CONTEXT_FALLBACK as usize);
    assert!(std::mem::offset_of!(Context, lane_masks) == CONTEXT_LANE_MASKS as usize);
    assert!(std::mem::offset_of!(Context, sample) == CONTEXT_SAMPLE as usize);
    assert!(std::mem::offset_of!(Context, sample_run) == CONTEXT_SAMPLE_RUN as usize);
};

// The offsets of the masks (`Masks` is `repr(C)`, five `u64`s).
const ACTIVE: i32 = 0;
const RETURNED: i32 = 8;
const EXITED: i32 = 16;
const CONTINUED: i32 = 24;
const DISCARDED: i32 = 32;
const _: () = {
    assert!(std::mem::offset_of!(Masks, active) == ACTIVE as usize);
    assert!(std::mem::offset_of!(Masks, returned) == RETURNED as usize);
    assert!(std::mem::offset_of!(Masks, exited) == EXITED as usize);
    assert!(std::mem::offset_of!(Masks, continued) == CONTINUED as usize);
    assert!(std::mem::offset_of!(Masks, discarded) == DISCARDED as usize);
};

/// Runs one instruction (`inst`) in the interpreter on the context's registers, masks and
/// environment (an `E` of the environment the fallback was made for).
type Fallback = unsafe extern "sysv64" fn(context: *const Context, inst: *const Inst);
type RunFallback = unsafe extern "sysv64" fn(context: *const Context, first: *const Inst, count: usize);

/// A program compiled: its machine code, and the instructions the code calls back into the
/// interpreter for. The code holds pointers to those instructions, into this tree, which is
/// never changed: they live in the vectors' heap buffers, which do not move with `Compiled`.
pub(super) struct Compiled {
    buffer: ExecutableBuffer,
    entry: AssemblyOffset,
    _tree: Vec<Inst>,
}

// SAFETY: `Compiled` is immutable once made: read-only executable memory and a tree of plain
// data that nothing changes, so it may be shared and sent between threads. (Its raw pointers
// are immediates in its machine code, into its own tree.)
unsafe impl Send for Compiled {}
// SAFETY: see above.
unsafe impl Sync for Compiled {}

impl std::fmt::Debug for Compiled {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Compiled").field("bytes", &self.buffer.len()).finish_non_exhaustive()
    }
}

/// `LANE_MASKS.0[m]`: lane `i` all ones where bit `i` of `m` is set (a mask byte as a vector).
#[repr(align(32))]
struct LaneMasks([[u32; LANES]; 256]);

static LANE_MASKS: LaneMasks = LaneMasks({
    let mut table = [[0u32; LANES]; 256];
    let mut m = 0;
    while m < 256 {
        let mut i = 0;
        while i < LANES {
            if m >> i & 1 != 0 {
                table[m][i] = u32::MAX;
            }
            i += 1;
        }
        m += 1;
    }
    table
});

/// Whether compiled code may run here: an x86-64 processor with AVX2 and F16C, and the
/// compiler not switched off by `TILER_GLSL_JIT=0` (read once; for measurements and bug
/// hunts, the interpreter giving the same bits).
pub(super) fn available() -> bool {
    static AVAILABLE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *AVAILABLE.get_or_init(|| {
        std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("f16c")
            && std::env::var_os("TILER_GLSL_JIT").is_none_or(|v| v != "0")
    })
}

impl Compiled {
    /// Compiles `code`, whose registers [`Executable::new`](super::Executable::new) checked
    /// and renumbered; `None` when it is too large or the assembler cannot map memory.
    pub(super) fn new(code: &[Inst]) -> Option<Compiled> {
        if count_insts(code) > MAX_COMPILED_INSTRUCTIONS {
            return None;
        }
        let tree = code.to_vec();
        let mut ops = Assembler::new().ok()?;
        let constants = Constants {
            one: ops.new_dynamic_label(),
            minus_one: ops.new_dynamic_label(),
            sign: ops.new_dynamic_label(),
            abs: ops.new_dynamic_label(),
            thirty_one: ops.new_dynamic_label(),
        };
        // Slots for the masks control flow saves, 8 bytes each, rounded up to keep the stack
        // 16-byte aligned at calls.
        let frame = (slots(&tree) * 8).next_multiple_of(16) as i32;
        let entry = ops.offset();
        dynasm!(ops
            ; .arch x64
            ; push rbx
            ; push r12
            ; push r13
            ; push r14
            ; push r15
            // Five pushes after the return address: 16-byte aligned again.
            ; sub rsp, DWORD frame
            ; mov r13, rdi
            ; mov rbx, [r13 + CONTEXT_REGS]
            ; mov r12, [r13 + CONTEXT_MASKS]
            ; mov r14, [r13 + CONTEXT_LANE_MASKS]
        );
        let mut emitter = Emitter { ops: &mut ops, constants, slot: 0 };
        let end = emitter.ops.new_dynamic_label();
        // The block ends at `end`, where the epilogue begins.
        emitter.block(&tree, end);
        dynasm!(emitter.ops
            ; .arch x64
            ; vzeroupper
            ; add rsp, DWORD frame
            ; pop r15
            ; pop r14
            ; pop r13
            ; pop r12
            ; pop rbx
            ; ret
        );
        emitter.constants();
        let buffer = ops.finalize().ok()?;
        Some(Compiled { buffer, entry, _tree: tree })
    }

    /// Runs the code on `machine`'s register file under `masks`.
    ///
    /// # Safety
    /// The processor must have AVX2 and F16C ([`available`]); every register of the compiled
    /// code must be within `machine`'s register file (as `run` asserts for its executable);
    /// `W` must be [`LANES`].
    pub(super) unsafe fn run<const W: usize, E: Env<W>>(&self, machine: &mut Machine<'_, W, E>, masks: &mut Masks) {
        assert_eq!(W, LANES, "compiled code runs eight lanes");
        let context = Context {
            regs: machine.regs.as_mut_ptr().cast(),
            masks,
            fallback: fallback::<W, E>,
            lane_masks: LANE_MASKS.0.as_ptr(),
            registers: machine.regs.len(),
            env: (machine.env as *mut E).cast(),
            sample: sample_fallback::<W, E>,
            sample_run: sample_run_fallback::<W, E>,
        };
        // SAFETY: the buffer holds a function `extern "sysv64" fn(*const Context)` at `entry`
        // (the prologue above); the caller's guarantees make every access of it valid (module
        // notes). `machine` is not used again until the code returns; the register file, the
        // masks and the environment are reached only through the context's pointers, by the
        // code and by the fallback it calls, one at a time (the code keeps no value read from
        // memory across a call).
        unsafe {
            let code: extern "sysv64" fn(*const Context) = std::mem::transmute(self.buffer.ptr(self.entry));
            code(&context);
        }
    }
}

/// The interpreter's run of the one instruction at `inst` on `context`'s register file,
/// masks and environment.
///
/// # Safety
/// `context` must be a live context made by [`Compiled::run`] for this `W` and `E`, `inst` an
/// instruction whose registers are within its file; the processor must have AVX2 and F16C.
unsafe extern "sysv64" fn fallback<const W: usize, E: Env<W>>(context: *const Context, inst: *const Inst) {
    // SAFETY: the caller's guarantee (`Compiled::run` makes the context from its machine,
    // whose file holds `registers` registers of `W` lanes; the code passes instructions of its
    // own tree, which `Executable::new` checked). The borrows made here end before the code
    // goes on.
    unsafe {
        let context = &*context;
        let regs = std::slice::from_raw_parts_mut(context.regs.cast::<[f32; W]>(), context.registers);
        let mut machine = Machine { regs, env: &mut *context.env.cast::<E>() };
        machine.block_avx2(std::slice::from_ref(&*inst), &mut *context.masks);
    }
}

/// [`fallback`] of an `Inst::Sample` with an implicit level of detail, no reference and no
/// offset (`Machine::sample_implicit_avx2`: the interpreter's code for it, not its dispatch).
///
/// # Safety
/// As [`fallback`].
unsafe extern "sysv64" fn sample_fallback<const W: usize, E: Env<W>>(context: *const Context, inst: *const Inst) {
    // SAFETY: as in `fallback`.
    unsafe {
        let context = &*context;
        let regs = std::slice::from_raw_parts_mut(context.regs.cast::<[f32; W]>(), context.registers);
        let mut machine = Machine { regs, env: &mut *context.env.cast::<E>() };
        machine.sample_implicit_avx2(&*inst, &mut *context.masks);
    }
}

/// [`fallback`] of the run of `count` lookups from `first` (`Machine::sample_run_avx2`).
///
/// # Safety
/// As [`fallback`], for each of the `count` instructions from `first`, which must be
/// consecutive instructions of one block that `super::run_length` takes together.
unsafe extern "sysv64" fn sample_run_fallback<const W: usize, E: Env<W>>(
    context: *const Context,
    first: *const Inst,
    count: usize,
) {
    // SAFETY: as in `fallback`; the run is `count` instructions of one block of the tree
    // (`Emitter::block` passes a slice's start and length).
    unsafe {
        let context = &*context;
        let regs = std::slice::from_raw_parts_mut(context.regs.cast::<[f32; W]>(), context.registers);
        let mut machine = Machine { regs, env: &mut *context.env.cast::<E>() };
        machine.sample_run_avx2(std::slice::from_raw_parts(first, count), &*context.masks);
    }
}

/// The 8-byte slots of the stack frame that `code`'s control flow needs at once.
fn slots(code: &[Inst]) -> usize {
    code.iter()
        .map(|inst| match inst {
            Inst::If(_, then, els) => IF_SLOTS + slots(then).max(slots(els)),
            Inst::Loop { cond_code, body, step, .. } => LOOP_SLOTS + slots(cond_code).max(slots(body)).max(slots(step)),
            Inst::Call(body) | Inst::Breakable(body) => 1 + slots(body),
            _ => 0,
        })
        .max()
        .unwrap_or(0)
}

/// An `if` saves the entry mask, the condition's lanes and the lanes after `then`.
const IF_SLOTS: usize = 3;
/// A loop saves the outer exited and continued masks, and counts its iterations.
const LOOP_SLOTS: usize = 3;

/// Labels of the constants, emitted after the code.
struct Constants {
    one: DynamicLabel,
    minus_one: DynamicLabel,
    sign: DynamicLabel,
    abs: DynamicLabel,
    thirty_one: DynamicLabel,
}

/// The code being emitted: `slot` is the first free slot of the frame.
struct Emitter<'a> {
    ops: &'a mut Assembler,
    constants: Constants,
    slot: usize,
}

/// The address of register `r` relative to `rbx`.
fn at(r: u32) -> i32 {
    // Registers are below 2^21 (`compile::MAX_REGISTERS` work and bank registers), 32 bytes
    // each: the offset fits an `i32`.
    (r as usize * 32) as i32
}

/// `vcmpps` predicates.
const EQ_OQ: i8 = 0x00;
const LT_OQ: i8 = 0x11;
const LE_OQ: i8 = 0x12;
const NEQ_UQ: i8 = 0x04;
const UNORD_Q: i8 = 0x03;
const GE_OQ: i8 = 0x1d;
const GT_OQ: i8 = 0x1e;

/// `vroundps` immediates (precision exceptions suppressed): floor, ceiling, toward zero.
const FLOOR: i8 = 0x09;
const CEIL: i8 = 0x0a;
const TRUNC: i8 = 0x0b;

/// `vcvtps2ph` immediates: to nearest even, toward zero.
const HALF_NEAREST: i8 = 0x00;
const HALF_TOWARD_ZERO: i8 = 0x03;

impl Emitter<'_> {
    /// Emits `code` as one block: it ends at `end` (where a `break`, `continue`, `return` or
    /// `discard`, or all lanes leaving, jump). As the interpreter's block, it does nothing
    /// when no lane is active on entry, and it stops after control flow leaves none.
    fn block(&mut self, code: &[Inst], end: DynamicLabel) {
        dynasm!(self.ops
            ; .arch x64
            ; cmp QWORD [r12 + ACTIVE], 0
            ; je =>end
        );
        let mut i = 0;
        while i < code.len() {
            let run = super::run_length(&code[i..]);
            if run >= 2 {
                // SAFETY of the code: the run is `run` consecutive instructions of this block
                // of the tree the compiled code keeps, which `run_length` takes together.
                let first = &code[i] as *const Inst as i64;
                dynasm!(self.ops
                    ; .arch x64
                    ; vzeroupper
                    ; mov rdi, r13
                    ; mov rsi, QWORD first
                    ; mov rdx, QWORD run as i64
                    ; call QWORD [r13 + CONTEXT_SAMPLE_RUN]
                );
                i += run;
            } else {
                self.inst(&code[i], end);
                i += 1;
            }
        }
        dynasm!(self.ops ; .arch x64 ; =>end);
    }

    /// A nested block with a label of its own.
    fn nested(&mut self, code: &[Inst]) {
        let end = self.ops.new_dynamic_label();
        self.block(code, end);
    }

    /// Jumps to `end` when no lane is active (after control flow, as the interpreter returns).
    fn leave_if_none(&mut self, end: DynamicLabel) {
        dynasm!(self.ops
            ; .arch x64
            ; cmp QWORD [r12 + ACTIVE], 0
            ; je =>end
        );
    }

    /// The frame offset of slot `k` of the current construct.
    fn slot(&self, k: usize) -> i32 {
        ((self.slot + k) * 8) as i32
    }

    /// `rcx` = the lanes where register `r` is true (`x != 0.0`, NaN true), as `truth`.
    fn truth(&mut self, r: u32) {
        self.load(r);
        dynasm!(self.ops ; .arch x64 ; vxorps ymm1, ymm1, ymm1);
        self.compare(0, 0, 1, NEQ_UQ);
        // `vmovmskps ecx, ymm0` (VEX.256.0F 50 /r), which the assembler refuses for 256-bit
        // sources.
        dynasm!(self.ops ; .arch x64 ; .bytes [0xc5u8, 0xfc, 0x50, 0xc8]);
    }

    /// `vcmpps ymm(dst), ymm(a), ymm(b), predicate`: lanes all ones where `a predicate b`.
    /// Encoded here (VEX.256.0F C2 /r ib, two-byte VEX): the assembler swaps the two sources
    /// of `vcmpps` and drops a memory operand (dynasm 5.1).
    fn compare(&mut self, dst: u8, a: u8, b: u8, predicate: i8) {
        debug_assert!(dst < 8 && a < 16 && b < 8);
        let vex = 0x80 | ((!a & 0xf) << 3) | 0x04;
        let modrm = 0xc0 | (dst << 3) | b;
        dynasm!(self.ops ; .arch x64 ; .bytes [0xc5u8, vex, 0xc2, modrm, predicate as u8]);
    }

    fn inst(&mut self, inst: &Inst, end: DynamicLabel) {
        match inst {
            Inst::Un(op, d, a) if self.unary(*op, *d, *a) => {}
            Inst::Bin(op, d, a, b) if self.binary(*op, *d, *a, *b) => {}
            Inst::Tri(op, d, a, b, c) if self.ternary(*op, *d, *a, *b, *c) => {}
            Inst::Store(d, s) => {
                // `dst = src` in the active lanes: the old value blended with the new under the
                // active lanes' vector.
                dynasm!(self.ops
                    ; .arch x64
                    ; movzx eax, BYTE [r12 + ACTIVE]
                    ; shl eax, 5
                    ; vmovdqu ymm2, [r14 + rax]
                    ; vmovups ymm0, [rbx + at(*d)]
                    ; vblendvps ymm0, ymm0, [rbx + at(*s)], ymm2
                    ; vmovups [rbx + at(*d)], ymm0
                );
            }
            Inst::StoreIf(d, s, c) => {
                // The same under the active lanes where `c` is true.
                dynasm!(self.ops
                    ; .arch x64
                    ; vmovups ymm2, [rbx + at(*c)]
                    ; vxorps ymm1, ymm1, ymm1
                );
                self.compare(2, 2, 1, NEQ_UQ);
                dynasm!(self.ops
                    ; .arch x64
                    ; movzx eax, BYTE [r12 + ACTIVE]
                    ; shl eax, 5
                    ; vandps ymm2, ymm2, [r14 + rax]
                    ; vmovups ymm0, [rbx + at(*d)]
                    ; vblendvps ymm0, ymm0, [rbx + at(*s)], ymm2
                    ; vmovups [rbx + at(*d)], ymm0
                );
            }
            Inst::If(c, then, els) => {
                // entry = active; cond = truth(c); active = entry & cond; then;
                // after_then = active; active = entry & !cond; else; active |= after_then.
                let (entry, cond, after_then) = (self.slot(0), self.slot(1), self.slot(2));
                self.slot += IF_SLOTS;
                self.truth(*c);
                dynasm!(self.ops
                    ; .arch x64
                    ; mov rax, [r12 + ACTIVE]
                    ; mov [rsp + entry], rax
                    ; mov [rsp + cond], rcx
                    ; and rax, rcx
                    ; mov [r12 + ACTIVE], rax
                );
                self.nested(then);
                dynasm!(self.ops
                    ; .arch x64
                    ; mov rax, [r12 + ACTIVE]
                    ; mov [rsp + after_then], rax
                    ; mov rax, [rsp + cond]
                    ; not rax
                    ; and rax, [rsp + entry]
                    ; mov [r12 + ACTIVE], rax
                );
                self.nested(els);
                dynasm!(self.ops
                    ; .arch x64
                    ; mov rax, [rsp + after_then]
                    ; or [r12 + ACTIVE], rax
                );
                self.slot -= IF_SLOTS;
                self.leave_if_none(end);
            }
            Inst::Loop { cond_code, cond, body, step, test_first } => {
                // (outer exited, continued) saved; exited = 0; then, iteration by iteration:
                // [cond_code; exited |= active & !t; active &= t] (skipped the first time for
                // `do … while`); iterations += 1; stop when no lane is active or past
                // MAX_ITERATIONS; continued = 0; body; active |= continued; step. After:
                // active |= exited; exited and continued restored.
                let (outer_exited, outer_continued, iterations) = (self.slot(0), self.slot(1), self.slot(2));
                self.slot += LOOP_SLOTS;
                let (top, counted, done) =
                    (self.ops.new_dynamic_label(), self.ops.new_dynamic_label(), self.ops.new_dynamic_label());
                dynasm!(self.ops
                    ; .arch x64
                    ; mov rax, [r12 + EXITED]
                    ; mov [rsp + outer_exited], rax
                    ; mov rax, [r12 + CONTINUED]
                    ; mov [rsp + outer_continued], rax
                    ; mov QWORD [r12 + EXITED], 0
                    ; mov QWORD [rsp + iterations], 0
                );
                if !*test_first {
                    dynasm!(self.ops ; .arch x64 ; jmp =>counted);
                }
                dynasm!(self.ops ; .arch x64 ; =>top);
                self.nested(cond_code);
                if let Some(c) = cond {
                    self.truth(*c);
                    dynasm!(self.ops
                        ; .arch x64
                        ; mov rax, [r12 + ACTIVE]
                        ; mov rdx, rcx
                        ; not rdx
                        ; and rdx, rax
                        ; or [r12 + EXITED], rdx
                        ; and rax, rcx
                        ; mov [r12 + ACTIVE], rax
                    );
                }
                dynasm!(self.ops
                    ; .arch x64
                    ; =>counted
                    ; add QWORD [rsp + iterations], 1
                    ; cmp QWORD [r12 + ACTIVE], 0
                    ; je =>done
                    ; cmp QWORD [rsp + iterations], DWORD MAX_ITERATIONS as i32
                    ; ja =>done
                    ; mov QWORD [r12 + CONTINUED], 0
                );
                self.nested(body);
                dynasm!(self.ops
                    ; .arch x64
                    ; mov rax, [r12 + CONTINUED]
                    ; or [r12 + ACTIVE], rax
                );
                self.nested(step);
                dynasm!(self.ops
                    ; .arch x64
                    ; jmp =>top
                    ; =>done
                    ; mov rax, [r12 + EXITED]
                    ; or [r12 + ACTIVE], rax
                    ; mov rax, [rsp + outer_exited]
                    ; mov [r12 + EXITED], rax
                    ; mov rax, [rsp + outer_continued]
                    ; mov [r12 + CONTINUED], rax
                );
                self.slot -= LOOP_SLOTS;
                self.leave_if_none(end);
            }
            // The active lanes move to a mask, and the block ends.
            Inst::Break => self.leave(EXITED, end),
            Inst::Continue => self.leave(CONTINUED, end),
            Inst::Return => self.leave(RETURNED, end),
            Inst::Discard => self.leave(DISCARDED, end),
            // outer = mask; mask = 0; body; active |= mask; mask = outer.
            Inst::Call(body) => self.scope(RETURNED, body, end),
            Inst::Breakable(body) => self.scope(EXITED, body, end),
            // The common lookup runs the interpreter's code for it, without the dispatch.
            Inst::Sample { lod: Lod::Implicit, reference: None, offset: [0, 0], .. } => {
                // SAFETY of the code: as for the other instructions below.
                let inst = inst as *const Inst as i64;
                dynasm!(self.ops
                    ; .arch x64
                    ; vzeroupper
                    ; mov rdi, r13
                    ; mov rsi, QWORD inst
                    ; call QWORD [r13 + CONTEXT_SAMPLE]
                );
            }
            // Everything else runs in the interpreter. Only these change no mask.
            other => {
                // SAFETY of the code: `other` is an instruction of the tree the compiled code
                // keeps (`Compiled::_tree`), so the pointer stays valid while the code can run.
                let inst = other as *const Inst as i64;
                dynasm!(self.ops
                    ; .arch x64
                    ; vzeroupper
                    ; mov rdi, r13
                    ; mov rsi, QWORD inst
                    ; call QWORD [r13 + CONTEXT_FALLBACK]
                );
                if !other.is_straight_line() {
                    self.leave_if_none(end);
                }
            }
        }
    }

    /// `mask |= active; active = 0`, and the block ends.
    fn leave(&mut self, mask: i32, end: DynamicLabel) {
        dynasm!(self.ops
            ; .arch x64
            ; mov rax, [r12 + ACTIVE]
            ; or [r12 + mask], rax
            ; mov QWORD [r12 + ACTIVE], 0
            ; jmp =>end
        );
    }

    /// A scope of `mask` (a call's returns, a `switch` body's breaks): `outer = mask; mask =
    /// 0; body; active |= mask; mask = outer`.
    fn scope(&mut self, mask: i32, body: &[Inst], end: DynamicLabel) {
        let outer = self.slot(0);
        self.slot += 1;
        dynasm!(self.ops
            ; .arch x64
            ; mov rax, [r12 + mask]
            ; mov [rsp + outer], rax
            ; mov QWORD [r12 + mask], 0
        );
        self.nested(body);
        dynasm!(self.ops
            ; .arch x64
            ; mov rax, [r12 + mask]
            ; or [r12 + ACTIVE], rax
            ; mov rax, [rsp + outer]
            ; mov [r12 + mask], rax
        );
        self.slot -= 1;
        self.leave_if_none(end);
    }

    /// `ymm0` rounded to binary16 (`imm`: nearest even or toward zero) and back, NaNs kept as
    /// they were: the interpreter's `half8`.
    fn half(&mut self, imm: i8) {
        dynasm!(self.ops
            ; .arch x64
            ; vcvtps2ph xmm1, ymm0, imm
            ; vcvtph2ps ymm1, xmm1
        );
        self.compare(2, 0, 0, UNORD_Q);
        dynasm!(self.ops ; .arch x64 ; vblendvps ymm0, ymm1, ymm0, ymm2);
    }

    /// `ymm0` as booleans: 1.0 where its lanes are all ones, 0.0 where zero.
    fn booleans(&mut self) {
        let one = self.constants.one;
        dynasm!(self.ops ; .arch x64 ; vandps ymm0, ymm0, [=>one]);
    }

    fn store(&mut self, d: u32) {
        dynasm!(self.ops ; .arch x64 ; vmovups [rbx + at(d)], ymm0);
    }

    fn load(&mut self, a: u32) {
        dynasm!(self.ops ; .arch x64 ; vmovups ymm0, [rbx + at(a)]);
    }

    /// Emits `d = op(a)` and returns true, or false for an operation left to the interpreter.
    fn unary(&mut self, op: UnOp, d: u32, a: u32) -> bool {
        use UnOp::*;
        let inline = matches!(
            op,
            Mov | Neg
                | Abs
                | Not
                | ToBool
                | IToBool
                | Sign
                | Floor
                | Ceil
                | Trunc
                | Fract
                | Sqrt
                | InverseSqrt
                | Half
                | HalfTowardZero
                | INeg
                | IAbs
                | BitNot
                | IToF
        );
        if !inline {
            return false;
        }
        let Constants { one, minus_one, sign, abs, .. } = self.constants;
        self.load(a);
        match op {
            UnOp::Mov => {}
            UnOp::Neg => dynasm!(self.ops ; .arch x64 ; vxorps ymm0, ymm0, [=>sign]),
            UnOp::Abs => dynasm!(self.ops ; .arch x64 ; vandps ymm0, ymm0, [=>abs]),
            // `x == 0.0`, `x != 0.0` as 1.0 or 0.0.
            UnOp::Not | UnOp::ToBool => {
                let predicate = if op == UnOp::Not { EQ_OQ } else { NEQ_UQ };
                dynasm!(self.ops ; .arch x64 ; vxorps ymm1, ymm1, ymm1);
                self.compare(0, 0, 1, predicate);
                self.booleans();
            }
            UnOp::IToBool => {
                dynasm!(self.ops
                    ; .arch x64
                    ; vpxor ymm1, ymm1, ymm1
                    ; vpcmpeqd ymm0, ymm0, ymm1
                    ; vpcmpeqd ymm1, ymm1, ymm1
                    ; vpxor ymm0, ymm0, ymm1
                );
                self.booleans();
            }
            // `x > 0 → 1`, `x < 0 → −1`, else (zeros, NaN) +0.
            UnOp::Sign => {
                dynasm!(self.ops ; .arch x64 ; vxorps ymm1, ymm1, ymm1);
                self.compare(2, 0, 1, GT_OQ);
                self.compare(3, 0, 1, LT_OQ);
                dynasm!(self.ops
                    ; .arch x64
                    ; vandps ymm2, ymm2, [=>one]
                    ; vandps ymm3, ymm3, [=>minus_one]
                    ; vorps ymm0, ymm2, ymm3
                );
            }
            UnOp::Floor => dynasm!(self.ops ; .arch x64 ; vroundps ymm0, ymm0, FLOOR),
            UnOp::Ceil => dynasm!(self.ops ; .arch x64 ; vroundps ymm0, ymm0, CEIL),
            UnOp::Trunc => dynasm!(self.ops ; .arch x64 ; vroundps ymm0, ymm0, TRUNC),
            // `x − floor(x)`.
            UnOp::Fract => dynasm!(self.ops
                ; .arch x64
                ; vroundps ymm1, ymm0, FLOOR
                ; vsubps ymm0, ymm0, ymm1
            ),
            UnOp::Sqrt => dynasm!(self.ops ; .arch x64 ; vsqrtps ymm0, ymm0),
            // `1 / sqrt(x)`.
            UnOp::InverseSqrt => dynasm!(self.ops
                ; .arch x64
                ; vsqrtps ymm1, ymm0
                ; vmovups ymm0, [=>one]
                ; vdivps ymm0, ymm0, ymm1
            ),
            UnOp::Half => self.half(HALF_NEAREST),
            UnOp::HalfTowardZero => self.half(HALF_TOWARD_ZERO),
            UnOp::INeg => dynasm!(self.ops
                ; .arch x64
                ; vpxor ymm1, ymm1, ymm1
                ; vpsubd ymm0, ymm1, ymm0
            ),
            UnOp::IAbs => dynasm!(self.ops ; .arch x64 ; vpabsd ymm0, ymm0),
            UnOp::BitNot => dynasm!(self.ops
                ; .arch x64
                ; vpcmpeqd ymm1, ymm1, ymm1
                ; vpxor ymm0, ymm0, ymm1
            ),
            UnOp::IToF => dynasm!(self.ops ; .arch x64 ; vcvtdq2ps ymm0, ymm0),
            _ => unreachable!("only the operations above are compiled inline"),
        }
        self.store(d);
        true
    }

    /// Emits `d = op(a, b)` and returns true, or false for an operation left to the
    /// interpreter.
    fn binary(&mut self, op: BinOp, d: u32, a: u32, b: u32) -> bool {
        let (ra, rb) = (at(a), at(b));
        let thirty_one = self.constants.thirty_one;
        // `ymm0 = a`, then `vop ymm0, ymm0, [b]`.
        macro_rules! with_b {
            ($($t:tt)*) => {{
                self.load(a);
                dynasm!(self.ops ; .arch x64 ; $($t)*);
            }};
        }
        // A float compare of `a` with `b` as 1.0 or 0.0.
        macro_rules! compare {
            ($predicate:expr) => {{
                with_b!(vmovups ymm1, [rbx + rb]);
                self.compare(0, 0, 1, $predicate);
                self.booleans();
            }};
        }
        match op {
            BinOp::Add => with_b!(vaddps ymm0, ymm0, [rbx + rb]),
            BinOp::Sub => with_b!(vsubps ymm0, ymm0, [rbx + rb]),
            BinOp::Mul => with_b!(vmulps ymm0, ymm0, [rbx + rb]),
            BinOp::Div => with_b!(vdivps ymm0, ymm0, [rbx + rb]),
            BinOp::AddHalf => {
                with_b!(vaddps ymm0, ymm0, [rbx + rb]);
                self.half(HALF_NEAREST);
            }
            BinOp::SubHalf => {
                with_b!(vsubps ymm0, ymm0, [rbx + rb]);
                self.half(HALF_NEAREST);
            }
            BinOp::MulHalf => {
                with_b!(vmulps ymm0, ymm0, [rbx + rb]);
                self.half(HALF_NEAREST);
            }
            BinOp::DivHalf => {
                with_b!(vdivps ymm0, ymm0, [rbx + rb]);
                self.half(HALF_NEAREST);
            }
            BinOp::HalfMulHalf => {
                self.load(a);
                self.half(HALF_NEAREST);
                dynasm!(self.ops ; .arch x64 ; vmulps ymm0, ymm0, [rbx + rb]);
                self.half(HALF_NEAREST);
            }
            // `if y < x { y } else { x }` is `minps(y, x)`; `if x < y { y } else { x }` is
            // `maxps(y, x)`.
            BinOp::Min => {
                self.load(b);
                dynasm!(self.ops ; .arch x64 ; vminps ymm0, ymm0, [rbx + ra]);
            }
            BinOp::Max => {
                self.load(b);
                dynasm!(self.ops ; .arch x64 ; vmaxps ymm0, ymm0, [rbx + ra]);
            }
            // `x − y · floor(x / y)`.
            BinOp::Mod => with_b!(
                vdivps ymm1, ymm0, [rbx + rb]
                ; vroundps ymm1, ymm1, FLOOR
                ; vmulps ymm1, ymm1, [rbx + rb]
                ; vsubps ymm0, ymm0, ymm1
            ),
            // `x < edge ? 0 : 1` (operands `edge, x`).
            BinOp::Step => {
                let one = self.constants.one;
                self.load(b);
                dynasm!(self.ops ; .arch x64 ; vmovups ymm1, [rbx + ra]);
                self.compare(0, 0, 1, LT_OQ);
                dynasm!(self.ops ; .arch x64 ; vandnps ymm0, ymm0, [=>one]);
            }
            BinOp::Lt => compare!(LT_OQ),
            BinOp::Le => compare!(LE_OQ),
            BinOp::Gt => compare!(GT_OQ),
            BinOp::Ge => compare!(GE_OQ),
            BinOp::Eq => compare!(EQ_OQ),
            BinOp::Ne => compare!(NEQ_UQ),
            // Booleans `x != 0.0` combined.
            BinOp::And | BinOp::Or | BinOp::Xor => {
                dynasm!(self.ops
                    ; .arch x64
                    ; vxorps ymm2, ymm2, ymm2
                    ; vmovups ymm0, [rbx + ra]
                    ; vmovups ymm1, [rbx + rb]
                );
                self.compare(0, 0, 2, NEQ_UQ);
                self.compare(1, 1, 2, NEQ_UQ);
                match op {
                    BinOp::And => dynasm!(self.ops ; .arch x64 ; vandps ymm0, ymm0, ymm1),
                    BinOp::Or => dynasm!(self.ops ; .arch x64 ; vorps ymm0, ymm0, ymm1),
                    _ => dynasm!(self.ops ; .arch x64 ; vxorps ymm0, ymm0, ymm1),
                }
                self.booleans();
            }
            BinOp::IAdd => with_b!(vpaddd ymm0, ymm0, [rbx + rb]),
            BinOp::ISub => with_b!(vpsubd ymm0, ymm0, [rbx + rb]),
            BinOp::IMul => with_b!(vpmulld ymm0, ymm0, [rbx + rb]),
            BinOp::IMin => with_b!(vpminsd ymm0, ymm0, [rbx + rb]),
            BinOp::IMax => with_b!(vpmaxsd ymm0, ymm0, [rbx + rb]),
            BinOp::UMin => with_b!(vpminud ymm0, ymm0, [rbx + rb]),
            BinOp::UMax => with_b!(vpmaxud ymm0, ymm0, [rbx + rb]),
            BinOp::BitAnd => with_b!(vpand ymm0, ymm0, [rbx + rb]),
            BinOp::BitOr => with_b!(vpor ymm0, ymm0, [rbx + rb]),
            BinOp::BitXor => with_b!(vpxor ymm0, ymm0, [rbx + rb]),
            // Shift counts modulo 32.
            BinOp::Shl | BinOp::IShr | BinOp::UShr => {
                dynasm!(self.ops
                    ; .arch x64
                    ; vmovdqu ymm1, [rbx + rb]
                    ; vpand ymm1, ymm1, [=>thirty_one]
                );
                self.load(a);
                match op {
                    BinOp::Shl => dynasm!(self.ops ; .arch x64 ; vpsllvd ymm0, ymm0, ymm1),
                    BinOp::IShr => dynasm!(self.ops ; .arch x64 ; vpsravd ymm0, ymm0, ymm1),
                    _ => dynasm!(self.ops ; .arch x64 ; vpsrlvd ymm0, ymm0, ymm1),
                }
            }
            // Integer compares as 1.0 or 0.0: `x == y`, `x != y`, `x > y`, `x < y` (signed),
            // `x >= y` as `!(y > x)`, `x <= y` as `!(x > y)`.
            BinOp::IEq | BinOp::INe => {
                with_b!(vpcmpeqd ymm0, ymm0, [rbx + rb]);
                if op == BinOp::INe {
                    self.invert();
                }
                self.booleans();
            }
            BinOp::IGt | BinOp::ILe => {
                with_b!(vpcmpgtd ymm0, ymm0, [rbx + rb]);
                if op == BinOp::ILe {
                    self.invert();
                }
                self.booleans();
            }
            BinOp::ILt | BinOp::IGe => {
                self.load(b);
                dynasm!(self.ops ; .arch x64 ; vpcmpgtd ymm0, ymm0, [rbx + ra]);
                if op == BinOp::IGe {
                    self.invert();
                }
                self.booleans();
            }
            _ => return false,
        }
        self.store(d);
        true
    }

    /// `ymm0 = !ymm0` (all bits).
    fn invert(&mut self) {
        dynasm!(self.ops
            ; .arch x64
            ; vpcmpeqd ymm1, ymm1, ymm1
            ; vpxor ymm0, ymm0, ymm1
        );
    }

    /// Emits `d = op(a, b, c)` and returns true, or false for an operation left to the
    /// interpreter.
    fn ternary(&mut self, op: TriOp, d: u32, a: u32, b: u32, c: u32) -> bool {
        let (ra, rb, rc) = (at(a), at(b), at(c));
        let one = self.constants.one;
        match op {
            // `a · b + c`, rounded after each.
            TriOp::MulAdd => {
                self.load(a);
                dynasm!(self.ops
                    ; .arch x64
                    ; vmulps ymm0, ymm0, [rbx + rb]
                    ; vaddps ymm0, ymm0, [rbx + rc]
                );
            }
            TriOp::MulAddHalf | TriOp::HalfMulAddHalf => {
                self.load(a);
                if op == TriOp::HalfMulAddHalf {
                    self.half(HALF_NEAREST);
                }
                dynasm!(self.ops ; .arch x64 ; vmulps ymm0, ymm0, [rbx + rb]);
                self.half(HALF_NEAREST);
                dynasm!(self.ops ; .arch x64 ; vaddps ymm0, ymm0, [rbx + rc]);
                self.half(HALF_NEAREST);
            }
            // `c != 0 ? a : b` (operands `c, a, b`).
            TriOp::Select => {
                dynasm!(self.ops
                    ; .arch x64
                    ; vxorps ymm1, ymm1, ymm1
                    ; vmovups ymm2, [rbx + ra]
                );
                self.compare(2, 2, 1, NEQ_UQ);
                dynasm!(self.ops
                    ; .arch x64
                    ; vmovups ymm0, [rbx + rc]
                    ; vblendvps ymm0, ymm0, [rbx + rb], ymm2
                );
            }
            // `m = if x < lo { lo } else { x }` is `maxps(lo, x)`; `if hi < m { hi } else { m }`
            // is `minps(hi, m)`.
            TriOp::Clamp => dynasm!(self.ops
                ; .arch x64
                ; vmovups ymm1, [rbx + rb]
                ; vmaxps ymm1, ymm1, [rbx + ra]
                ; vmovups ymm0, [rbx + rc]
                ; vminps ymm0, ymm0, ymm1
            ),
            // `x · (1 − t) + y · t`.
            TriOp::Mix => dynasm!(self.ops
                ; .arch x64
                ; vmovups ymm1, [=>one]
                ; vsubps ymm1, ymm1, [rbx + rc]
                ; vmulps ymm1, ymm1, [rbx + ra]
                ; vmovups ymm0, [rbx + rb]
                ; vmulps ymm0, ymm0, [rbx + rc]
                ; vaddps ymm0, ymm1, ymm0
            ),
            TriOp::IClamp => dynasm!(self.ops
                ; .arch x64
                ; vmovdqu ymm0, [rbx + ra]
                ; vpmaxsd ymm0, ymm0, [rbx + rb]
                ; vpminsd ymm0, ymm0, [rbx + rc]
            ),
            TriOp::UClamp => dynasm!(self.ops
                ; .arch x64
                ; vmovdqu ymm0, [rbx + ra]
                ; vpmaxud ymm0, ymm0, [rbx + rb]
                ; vpminud ymm0, ymm0, [rbx + rc]
            ),
            TriOp::Smoothstep => return false,
        }
        self.store(d);
        true
    }

    /// The constants the code reads, 32-byte aligned, after the code.
    fn constants(&mut self) {
        let Constants { one, minus_one, sign, abs, thirty_one } = self.constants;
        for (label, value) in [
            (one, 1.0f32.to_bits()),
            (minus_one, (-1.0f32).to_bits()),
            (sign, 0x8000_0000),
            (abs, 0x7fff_ffff),
            (thirty_one, 31),
        ] {
            dynasm!(self.ops ; .arch x64 ; .align 32 ; =>label);
            for _ in 0..LANES {
                dynasm!(self.ops ; .arch x64 ; .u32 value);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Executable, LodValue, run};
    use super::*;
    use crate::ir::{Axis, BANK, Lod, Reg};

    /// An environment whose lookups give values made of the coordinates (so a lookup in the
    /// wrong lanes or of the wrong registers shows), and whose derivatives are lane
    /// differences.
    struct Lanes;
    impl Env<8> for Lanes {
        fn sample(
            &mut self,
            slot: usize,
            coord: [[f32; 8]; 2],
            _: LodValue<8>,
            _: Option<[f32; 8]>,
            _: [i32; 2],
        ) -> [[f32; 8]; 4] {
            let [s, t] = coord;
            [s, t, std::array::from_fn(|i| s[i] * 0.5 + t[i]), [slot as f32; 8]]
        }
        fn sample_cube(&mut self, _: usize, d: [[f32; 8]; 3], _: LodValue<8>) -> [[f32; 8]; 4] {
            [d[0], d[1], d[2], [1.0; 8]]
        }
        fn derivative(&mut self, v: [f32; 8], axis: Axis) -> [f32; 8] {
            let step = if axis == Axis::X { 1 } else { 2 };
            std::array::from_fn(|i| v[i ^ step] - v[i])
        }
    }

    /// SplitMix64.
    struct Random(u64);
    impl Random {
        fn next(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let z = (self.0 ^ (self.0 >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            let z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^ (z >> 31)
        }
        fn below(&mut self, n: usize) -> usize {
            (self.next() % n as u64) as usize
        }
        /// A lane value: special floats, small integers' bits, ordinary and random bits.
        fn value(&mut self) -> f32 {
            const SPECIAL: [f32; 16] = [
                0.0,
                -0.0,
                1.0,
                -1.0,
                0.5,
                f32::NAN,
                f32::INFINITY,
                f32::NEG_INFINITY,
                65504.0,
                65520.0,
                6.0e-8,
                1.0e-40,
                3.0e38,
                0.1,
                -2.5,
                100.25,
            ];
            match self.below(4) {
                0 => SPECIAL[self.below(SPECIAL.len())],
                1 => f32::from_bits((self.below(80) as i32 - 40) as u32),
                2 => (self.below(2001) as f32 - 1000.0) / 37.0,
                _ => f32::from_bits(self.next() as u32),
            }
        }
    }

    /// Work registers the random code writes: floats below `INTS`, ints from it to `WORK`;
    /// loop counters (floats) above them are written only by their loop. The code is typed
    /// as a compiler's is: integer operations read ints, float operations floats, and values
    /// cross only by conversions (and booleans, 0.0 or 1.0). So a NaN's payload, which
    /// depends on the order the Rust compiler chose for an operation's operands (in the
    /// interpreter too), never reaches an integer.
    const INTS: u32 = 6;
    const WORK: u32 = 12;
    const COUNTERS: u32 = 4;
    /// Bank registers: 1.0, then random floats, then random ints.
    const BANK_LEN: u32 = 8;
    const BANK_INTS: u32 = 3;
    /// Bank registers 1 to `LIMITS − 1` are loop limits (0 to 5 iterations a lane).
    const LIMITS: u32 = 3;

    #[derive(Clone, Copy, PartialEq)]
    enum Ty {
        F,
        I,
    }

    // Each operation with its operands' types and its result's.
    const UNARY: [(UnOp, Ty, Ty); 38] = {
        use Ty::*;
        use UnOp::*;
        [
            (Mov, F, F),
            (Mov, I, I),
            (Neg, F, F),
            (Not, F, F),
            (Abs, F, F),
            (Sign, F, F),
            (Floor, F, F),
            (Ceil, F, F),
            (Fract, F, F),
            (Trunc, F, F),
            (Round, F, F),
            (Sin, F, F),
            (Cos, F, F),
            (Tan, F, F),
            (Asin, F, F),
            (Acos, F, F),
            (Atan, F, F),
            (Exp, F, F),
            (Log, F, F),
            (Exp2, F, F),
            (Log2, F, F),
            (Sqrt, F, F),
            (InverseSqrt, F, F),
            (Radians, F, F),
            (Degrees, F, F),
            (ToBool, F, F),
            (IToBool, I, F),
            (INeg, I, I),
            (IAbs, I, I),
            (ISign, I, I),
            (BitNot, I, I),
            (IToF, I, F),
            (UToF, I, F),
            (FToI, F, I),
            (FToU, F, I),
            (Half, F, F),
            (HalfTowardZero, F, F),
            (HalfToF, I, F),
        ]
    };
    const BINARY: [(BinOp, Ty, Ty); 51] = {
        use BinOp::*;
        use Ty::*;
        [
            (Add, F, F),
            (Sub, F, F),
            (Mul, F, F),
            (Div, F, F),
            (IAdd, I, I),
            (ISub, I, I),
            (IMul, I, I),
            (IDiv, I, I),
            (IRem, I, I),
            (UDiv, I, I),
            (URem, I, I),
            (IMin, I, I),
            (IMax, I, I),
            (UMin, I, I),
            (UMax, I, I),
            (ILt, I, F),
            (ILe, I, F),
            (IGt, I, F),
            (IGe, I, F),
            (ULt, I, F),
            (ULe, I, F),
            (UGt, I, F),
            (UGe, I, F),
            (IEq, I, F),
            (INe, I, F),
            (BitAnd, I, I),
            (BitOr, I, I),
            (BitXor, I, I),
            (Shl, I, I),
            (IShr, I, I),
            (UShr, I, I),
            (Mod, F, F),
            (Min, F, F),
            (Max, F, F),
            (Pow, F, F),
            (Atan2, F, F),
            (Step, F, F),
            (Lt, F, F),
            (Le, F, F),
            (Gt, F, F),
            (Ge, F, F),
            (Eq, F, F),
            (Ne, F, F),
            (And, F, F),
            (Or, F, F),
            (Xor, F, F),
            (AddHalf, F, F),
            (SubHalf, F, F),
            (MulHalf, F, F),
            (DivHalf, F, F),
            (HalfMulHalf, F, F),
        ]
    };
    const TERNARY: [(TriOp, Ty); 9] = {
        use TriOp::*;
        use Ty::*;
        [
            (Clamp, F),
            (IClamp, I),
            (UClamp, I),
            (Mix, F),
            (Smoothstep, F),
            (Select, F),
            (MulAdd, F),
            (MulAddHalf, F),
            (HalfMulAddHalf, F),
        ]
    };

    /// A register of type `ty` to read: work, counter or bank.
    fn source(r: &mut Random, ty: Ty) -> Reg {
        match (ty, r.below(8)) {
            (Ty::F, 0) => BANK | r.below((BANK_LEN - BANK_INTS) as usize) as Reg,
            (Ty::I, 0) => BANK | (BANK_LEN - BANK_INTS + r.below(BANK_INTS as usize) as u32) as Reg,
            (Ty::F, 1) => WORK + r.below(COUNTERS as usize) as Reg,
            (Ty::F, _) => r.below(INTS as usize) as Reg,
            (Ty::I, _) => INTS + r.below((WORK - INTS) as usize) as Reg,
        }
    }

    fn dest(r: &mut Random, ty: Ty) -> Reg {
        match ty {
            Ty::F => r.below(INTS as usize) as Reg,
            Ty::I => INTS + r.below((WORK - INTS) as usize) as Reg,
        }
    }

    fn ty(r: &mut Random) -> Ty {
        if r.below(3) == 0 { Ty::I } else { Ty::F }
    }

    /// A random block of up to `len` instructions; `depth` bounds the nesting, `loops` counts
    /// the loop counters in use.
    fn block(r: &mut Random, len: usize, depth: u32, loops: u32) -> Vec<Inst> {
        (0..r.below(len + 1)).map(|_| inst(r, depth, loops)).collect()
    }

    fn inst(r: &mut Random, depth: u32, loops: u32) -> Inst {
        use Ty::*;
        let nest = depth > 0;
        match r.below(if nest { 22 } else { 16 }) {
            0..=3 => {
                let (op, a, d) = UNARY[r.below(UNARY.len())];
                Inst::Un(op, dest(r, d), source(r, a))
            }
            4..=8 => {
                let (op, a, d) = BINARY[r.below(BINARY.len())];
                Inst::Bin(op, dest(r, d), source(r, a), source(r, a))
            }
            9..=10 => {
                let (op, t) = TERNARY[r.below(TERNARY.len())];
                // `Select`'s condition is a boolean (or any float); it may choose ints too.
                if op == TriOp::Select {
                    let t = ty(r);
                    Inst::Tri(op, dest(r, t), source(r, F), source(r, t), source(r, t))
                } else {
                    Inst::Tri(op, dest(r, t), source(r, t), source(r, t), source(r, t))
                }
            }
            11..=12 => {
                let t = ty(r);
                Inst::Store(dest(r, t), source(r, t))
            }
            13 => {
                let t = ty(r);
                Inst::StoreIf(dest(r, t), source(r, t), source(r, F))
            }
            14 => match r.below(6) {
                0 => Inst::Break,
                1 => Inst::Continue,
                2 => Inst::Return,
                3 => Inst::Discard,
                4 => Inst::Derivative {
                    dst: dest(r, F),
                    src: source(r, F),
                    axis: if r.below(2) == 0 { Axis::X } else { Axis::Y },
                },
                _ => Inst::Sample {
                    slot: r.below(3) as u16,
                    dst: [dest(r, F), dest(r, F), dest(r, F), dest(r, F)],
                    coord: [source(r, F), source(r, F)],
                    lod: Lod::Implicit,
                    reference: None,
                    offset: [0, 0],
                    round: r.below(2) == 0,
                },
            },
            15 => Inst::Un(UnOp::Half, dest(r, F), source(r, F)),
            16..=17 => {
                let t = ty(r);
                Inst::If(source(r, t), block(r, 6, depth - 1, loops), block(r, 4, depth - 1, loops))
            }
            18 if loops < COUNTERS => {
                // A loop counting register `counter` from 0 to a bank value, with random
                // code in its condition, body and step.
                let counter = WORK + loops;
                let (t, next) = (dest(r, F), dest(r, F));
                let mut body = block(r, 6, depth - 1, loops + 1);
                body.insert(0, Inst::Bin(BinOp::Add, next, counter, BANK));
                body.insert(1, Inst::Store(counter, next));
                let limit = BANK | (1 + r.below(LIMITS as usize - 1)) as Reg;
                let mut cond_code = block(r, 2, 0, loops + 1);
                cond_code.push(Inst::Bin(BinOp::Lt, t, counter, limit));
                Inst::Loop {
                    cond_code,
                    cond: Some(t),
                    body,
                    step: block(r, 2, 0, loops + 1),
                    test_first: r.below(3) != 0,
                }
            }
            19 => Inst::Call(block(r, 6, depth - 1, loops)),
            20 => Inst::Breakable(block(r, 6, depth - 1, loops)),
            _ => Inst::If(source(r, F), vec![Inst::Discard], vec![]),
        }
    }

    /// A register file for the random code (work registers, counters at 0, the bank: 1.0,
    /// small loop limits, random floats, random ints) and the active lanes.
    fn inputs(r: &mut Random) -> (Vec<[f32; 8]>, u64) {
        let mut file: Vec<[f32; 8]> = (0..WORK)
            .map(|k| {
                std::array::from_fn(
                    |_| if k < INTS { r.value() } else { f32::from_bits(r.next() as u32 >> r.below(32)) },
                )
            })
            .collect();
        file.extend((0..COUNTERS).map(|_| [0.0; 8]));
        file.push([1.0; 8]);
        for _ in 1..LIMITS {
            file.push(std::array::from_fn(|_| r.below(6) as f32));
        }
        for _ in LIMITS..BANK_LEN - BANK_INTS {
            file.push(std::array::from_fn(|_| r.value()));
        }
        for _ in 0..BANK_INTS {
            file.push(std::array::from_fn(|_| f32::from_bits(r.next() as u32 >> r.below(32))));
        }
        (file, r.next() & 0xff)
    }

    /// Equal bits, or both NaN (which NaN an operation of two NaNs gives depends on the
    /// order the compiler chose for its operands, in the interpreter too).
    fn same(a: f32, b: f32) -> bool {
        a.to_bits() == b.to_bits() || a.is_nan() && b.is_nan()
    }

    /// Random programs give the interpreter's registers and discarded lanes, lane for lane.
    #[test]
    fn compiled_code_is_the_interpreter() {
        if !available() {
            eprintln!("skipped: compiled_code_is_the_interpreter: no AVX2 and F16C");
            return;
        }
        let mut compiled_programs = 0;
        for seed in 0..3000u64 {
            let mut r = Random(seed);
            let code = block(&mut r, 24, 3, 0);
            assert!(compiled_is_interpreted(seed, &code, &mut r), "seed {seed}: not compiled");
            compiled_programs += 1;
        }
        assert_eq!(compiled_programs, 3000);
    }

    /// Runs `code` compiled and interpreted on the same random inputs and asserts the same
    /// registers and discarded lanes; whether it was compiled.
    fn compiled_is_interpreted(seed: u64, code: &[Inst], r: &mut Random) -> bool {
        let work = (WORK + COUNTERS) as usize;
        let program = Executable::new(code, work, BANK_LEN as usize).expect("registers in range");
        let (mut file, active) = inputs(r);
        let mut interpreted = file.clone();
        let want = run(&program.interpreted(), &mut interpreted, active, &mut Lanes);
        let got = run(&program, &mut file, active, &mut Lanes);
        assert_eq!(got, want, "seed {seed}: discarded lanes");
        for (k, (g, w)) in file.iter().zip(&interpreted).enumerate() {
            assert!(
                g.iter().zip(w).all(|(&g, &w)| same(g, w)),
                "seed {seed}: register {k}: {g:?} against the interpreter's {w:?}\n{code:#?}"
            );
        }
        program.is_compiled()
    }

    /// Runs of lookups (taken as one call, `run_length`) give the interpreter's registers:
    /// random programs with runs of two to six lookups put in, some of one slot and
    /// independent, some reading what an earlier one of them writes or of another slot (which
    /// cut the run).
    #[test]
    fn runs_of_lookups_are_the_interpreter() {
        if !available() {
            eprintln!("skipped: runs_of_lookups_are_the_interpreter: no AVX2 and F16C");
            return;
        }
        let mut runs = 0;
        for seed in 0..1000u64 {
            let mut r = Random(seed);
            let mut code = block(&mut r, 12, 2, 0);
            for _ in 0..2 {
                let at = r.below(code.len() + 1);
                let length = 2 + r.below(5);
                let mut dsts: Vec<Reg> = Vec::new();
                let lookups: Vec<Inst> = (0..length)
                    .map(|_| {
                        let coord = [0, 1].map(|_| match r.below(4) {
                            0 if !dsts.is_empty() => dsts[r.below(dsts.len())],
                            _ => source(&mut r, Ty::F),
                        });
                        let dst = [dest(&mut r, Ty::F), dest(&mut r, Ty::F), dest(&mut r, Ty::F), dest(&mut r, Ty::F)];
                        dsts.extend(dst);
                        Inst::Sample {
                            slot: (r.below(6) == 0) as u16,
                            dst,
                            coord,
                            lod: Lod::Implicit,
                            reference: None,
                            offset: [0, 0],
                            round: r.below(2) == 0,
                        }
                    })
                    .collect();
                code.splice(at..at, lookups);
            }
            runs += (0..code.len()).filter(|&i| super::super::run_length(&code[i..]) >= 2).count();
            assert!(compiled_is_interpreted(seed, &code, &mut r), "seed {seed}: not compiled");
        }
        assert!(runs > 1000, "only {runs} runs");
    }

    /// Shrinks a failing seed's program: drops instructions (at any depth) while it still
    /// fails. Debugging aid: `SEED=n cargo test -p tiler-glsl --lib shrink -- --ignored`.
    #[test]
    #[ignore]
    fn shrink() {
        let seed: u64 = std::env::var("SEED").unwrap().parse().unwrap();
        let mut r = Random(seed);
        let mut code = block(&mut r, 24, 3, 0);
        let work = (WORK + COUNTERS) as usize;
        let (file, active) = inputs(&mut r);
        let fails = |code: &[Inst]| {
            let program = Executable::new(code, work, BANK_LEN as usize).unwrap();
            let (mut a, mut b) = (file.clone(), file.clone());
            let want = run(&program.interpreted(), &mut a, active, &mut Lanes);
            let got = run(&program, &mut b, active, &mut Lanes);
            got != want || a.iter().zip(&b).any(|(x, y)| x.iter().zip(y).any(|(&x, &y)| !same(x, y)))
        };
        assert!(fails(&code));
        fn paths(code: &[Inst], prefix: Vec<usize>, out: &mut Vec<Vec<usize>>) {
            for (i, inst) in code.iter().enumerate() {
                let mut p = prefix.clone();
                p.push(i);
                out.push(p.clone());
                let kids: Vec<&Vec<Inst>> = match inst {
                    Inst::If(_, a, b) => vec![a, b],
                    Inst::Loop { cond_code, body, step, .. } => vec![cond_code, body, step],
                    Inst::Call(b) | Inst::Breakable(b) => vec![b],
                    _ => vec![],
                };
                for (k, kid) in kids.into_iter().enumerate() {
                    let mut q = p.clone();
                    q.push(usize::MAX - k);
                    paths(kid, q, out);
                }
            }
        }
        fn remove(code: &mut Vec<Inst>, path: &[usize]) -> bool {
            if path.len() == 1 {
                if path[0] < code.len() {
                    code.remove(path[0]);
                    return true;
                }
                return false;
            }
            let Some(inst) = code.get_mut(path[0]) else { return false };
            let k = usize::MAX - path[1];
            let kid = match (inst, k) {
                (Inst::If(_, a, _), 0) => a,
                (Inst::If(_, _, b), 1) => b,
                (Inst::Loop { cond_code, .. }, 0) => cond_code,
                (Inst::Loop { body, .. }, 1) => body,
                (Inst::Loop { step, .. }, 2) => step,
                (Inst::Call(b) | Inst::Breakable(b), 0) => b,
                _ => return false,
            };
            remove(kid, &path[2..])
        }
        loop {
            let mut all = Vec::new();
            paths(&code, vec![], &mut all);
            let mut changed = false;
            for p in all.iter().rev() {
                let mut c = code.clone();
                if remove(&mut c, p) && fails(&c) {
                    code = c;
                    changed = true;
                    break;
                }
            }
            if !changed {
                break;
            }
        }
        let program = Executable::new(&code, work, BANK_LEN as usize).unwrap();
        let (mut a, mut b) = (file.clone(), file.clone());
        run(&program.interpreted(), &mut a, active, &mut Lanes);
        run(&program, &mut b, active, &mut Lanes);
        eprintln!("active {active:#x}\n{code:#?}");
        for k in 0..a.len() {
            if a[k].iter().zip(&b[k]).any(|(&x, &y)| !same(x, y)) {
                eprintln!("reg {k}: interp {:?} jit {:?}", a[k], b[k]);
            }
        }
        for (k, v) in file.iter().enumerate() {
            eprintln!("input {k}: {v:?}");
        }
    }

    /// A loop that never ends stops after `MAX_ITERATIONS`, as in the interpreter: the lanes
    /// still looping leave with the count the interpreter gives.
    #[test]
    fn endless_loops_stop_where_the_interpreter_stops() {
        if !available() {
            eprintln!("skipped: endless_loops_stop_where_the_interpreter_stops: no AVX2 and F16C");
            return;
        }
        // r0 counts; lanes 0–3 leave when it reaches r1 (10), the others never.
        for test_first in [true, false] {
            let code = vec![Inst::Loop {
                cond_code: vec![Inst::Bin(BinOp::Lt, 2, 0, 1)],
                cond: Some(2),
                body: vec![Inst::Bin(BinOp::Add, 3, 0, BANK), Inst::Store(0, 3)],
                step: vec![],
                test_first,
            }];
            let program = Executable::new(&code, 4, 1).unwrap();
            let limits = [10.0, 10.0, 10.0, 10.0, f32::INFINITY, f32::INFINITY, f32::INFINITY, f32::INFINITY];
            let file = vec![[0.0; 8], limits, [0.0; 8], [0.0; 8], [1.0; 8]];
            let (mut a, mut b) = (file.clone(), file);
            run(&program.interpreted(), &mut a, 0xff, &mut Lanes);
            run(&program, &mut b, 0xff, &mut Lanes);
            assert_eq!(a, b);
            assert_eq!(b[0][0], 10.0);
            assert_eq!(b[0][7], MAX_ITERATIONS as f32, "{b:?}");
        }
    }

    /// The compiled code runs at all: one addition, its result checked by hand.
    #[test]
    fn an_addition_runs() {
        if !available() {
            eprintln!("skipped: an_addition_runs: no AVX2 and F16C");
            return;
        }
        let program = Executable::new(&[Inst::Bin(BinOp::Add, 2, 0, 1)], 3, 0).unwrap();
        assert!(program.is_compiled());
        let mut file = vec![[1.5f32; 8], [2.25; 8], [0.0; 8]];
        file[1][3] = -10.0;
        run(&program, &mut file, 0xff, &mut Lanes);
        assert_eq!(file[2], [3.75, 3.75, 3.75, -8.5, 3.75, 3.75, 3.75, 3.75]);
    }
}
