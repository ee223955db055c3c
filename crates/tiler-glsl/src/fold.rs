//! Constant folding, algebraic simplification and dead-code elimination, as a GPU's shader
//! compiler does them before the code runs (Mesa's NIR: `nir_opt_constant_folding`,
//! `nir_opt_algebraic`, `nir_opt_dce`).
//!
//! Folding: arithmetic whose operands are all constants is computed here, with the executor's
//! own operations, so the bits are those the shader would have computed. Simplification
//! replaces a result by one of its operands or by a constant:
//!
//! | exact (the same bits for every operand) | not exact |
//! | --- | --- |
//! | `x·1`, `1·x`, `x/1`, `x − 0`, `x + (−0)`, `mov x`, `c ? x : y` for a constant `c` | `x·0` → `0`, `x + 0` → `x`, `mix(x, y, 0)` → `x`, `mix(x, y, 1)` → `y` |
//!
//! The inexact ones differ only when `x` is NaN or infinite (`x·0` is then NaN) or a zero of
//! the other sign: GLSL ES does not require NaNs, infinities or signed zeros (ES 1.00 §4.5.1,
//! ES 3.00 §4.5.1: "operations … may not result in NaN or Inf"), and GPU compilers apply these
//! rules (NIR marks them inexact, `~fmul a 0.0 → 0.0`, and uses them unless the shader asks
//! for `precise`/`invariant` arithmetic, which ES 1.00 does not have).
//!
//! Dead code: an instruction whose results nothing reads (no later instruction, not the
//! stage's interface) is removed — texture lookups included. So a weight of the constant 0.0
//! in a convolution removes its lookup, as on hardware: glmark2's `effect2d` kernel with
//! eight zero weights of nine samples one texel per fragment, and the ledger's `texture
//! fetch` counts what a GPU running the compiled shader would fetch.
//!
//! Replacing a register by an operand is safe when the operand keeps its value from where the
//! register was computed to every read of it: a constant or uniform (the bank), a stage input
//! the code never writes, or a register written once, by arithmetic in every lane (not a
//! masked store), earlier in program order.

use std::collections::HashMap;

use crate::exec::{binary, ternary, unary};
use crate::hoist::{blocks_mut, reads_mut, writes};
use crate::ir::{BANK, BinOp, Inst, Reg, TriOp, UnOp};

/// Rounds of folding and dead-code removal before giving up on a fixed point (each round
/// is linear in the code; real shaders settle in two or three).
const MAX_ROUNDS: usize = 8;

/// The bank's constants, by value, with new ones added as folding makes them.
pub(crate) struct Constants<'a> {
    bank: &'a mut Vec<f32>,
    /// Bank index → its value, for the bank registers that are constants (not uniforms).
    values: HashMap<u32, f32>,
    /// Value bits → bank register.
    by_bits: HashMap<u32, Reg>,
}

impl<'a> Constants<'a> {
    /// `constants` are the bank registers holding compile-time constants (the others hold
    /// uniforms or hoisted results).
    pub(crate) fn new(bank: &'a mut Vec<f32>, constants: impl IntoIterator<Item = Reg>) -> Constants<'a> {
        let mut values = HashMap::new();
        let mut by_bits = HashMap::new();
        for r in constants {
            let x = bank[(r & !BANK) as usize];
            values.insert(r & !BANK, x);
            by_bits.entry(x.to_bits()).or_insert(r);
        }
        Constants { bank, values, by_bits }
    }

    fn value(&self, r: Reg) -> Option<f32> {
        if r & BANK == 0 { None } else { self.values.get(&(r & !BANK)).copied() }
    }

    fn reg(&mut self, x: f32) -> Reg {
        if let Some(&r) = self.by_bits.get(&x.to_bits()) {
            return r;
        }
        let index = self.bank.len() as u32;
        self.bank.push(x);
        self.values.insert(index, x);
        let r = BANK | index;
        self.by_bits.insert(x.to_bits(), r);
        r
    }
}

/// Folds, simplifies and removes dead code in `code` until nothing changes (see the module
/// notes). `pinned` are the registers the stage's interface reads or fills.
pub(crate) fn optimize(code: &mut Vec<Inst>, work_regs: usize, constants: &mut Constants<'_>, pinned: &[Reg]) {
    let mut pin = vec![false; work_regs];
    for &r in pinned {
        if r & BANK == 0 {
            pin[r as usize] = true;
        }
    }
    unmask_while_full(code);
    for _ in 0..MAX_ROUNDS {
        let folded = fold(code, work_regs, constants, &pin);
        let branches = take_constant_branches(code, constants);
        let overwritten = remove_overwritten(code);
        let removed = remove_dead(code, work_regs, &pin);
        if !folded && !branches && !overwritten && !removed {
            break;
        }
    }
    coalesce_outputs(code, work_regs, &pin);
}

/// Writes the interface's registers directly: where an output register is filled once, by a
/// move from a temporary computed in the same block and read nowhere else, the temporary's
/// instruction writes the output and the move goes (`gl_FragColor = texel` becomes the
/// lookup into `gl_FragColor`). The output is read by no instruction, so writing it earlier
/// in the block changes nothing that runs.
fn coalesce_outputs(code: &mut Vec<Inst>, work_regs: usize, pin: &[bool]) {
    let mut reads = vec![0u32; work_regs];
    count_reads(code, &mut reads);
    let mut w = Writes { count: vec![0; work_regs], whole: vec![false; work_regs] };
    count_writes(code, &mut w);
    coalesce_block(code, &reads, &w, pin);
}

fn coalesce_block(code: &mut Vec<Inst>, reads: &[u32], w: &Writes, pin: &[bool]) {
    // Temporary → the index of the instruction that computes it in this block.
    let mut computed: HashMap<Reg, usize> = HashMap::new();
    let mut renames: Vec<(usize, Reg, Reg)> = Vec::new();
    let mut moves = vec![false; code.len()];
    for (i, inst) in code.iter_mut().enumerate() {
        for block in blocks_mut(inst) {
            coalesce_block(block, reads, w, pin);
        }
        if let Inst::Un(UnOp::Mov, p, t) = *inst
            && t & BANK == 0
            && pin[p as usize]
            && w.count[p as usize] == 1
            && reads[p as usize] == 0
            && !pin[t as usize]
            && w.count[t as usize] == 1
            && reads[t as usize] == 1
            && let Some(&at) = computed.get(&t)
        {
            renames.push((at, t, p));
            moves[i] = true;
            continue;
        }
        if matches!(
            inst,
            Inst::Un(..)
                | Inst::Bin(..)
                | Inst::Tri(..)
                | Inst::Sample { .. }
                | Inst::SampleCube { .. }
                | Inst::SampleLayered { .. }
                | Inst::Fetch { .. }
        ) {
            writes(inst, &mut |r| {
                computed.insert(r, i);
            });
        }
    }
    for (at, t, p) in renames {
        match &mut code[at] {
            Inst::Un(_, d, _) | Inst::Bin(_, d, _, _) | Inst::Tri(_, d, _, _, _) if *d == t => *d = p,
            Inst::Sample { dst, .. }
            | Inst::SampleCube { dst, .. }
            | Inst::SampleLayered { dst, .. }
            | Inst::Fetch { dst, .. } => {
                dst.iter_mut().filter(|d| **d == t).for_each(|d| *d = p);
            }
            _ => unreachable!("a computed register's instruction writes it"),
        }
    }
    let mut moves = moves.into_iter();
    code.retain(|_| !moves.next().unwrap_or(false));
}

/// Replaces each `if` on a constant by the branch it takes, and drops what follows a `return`,
/// `break` or `continue` in its block (no lane runs it): `if (c_variant == SOLID) return
/// unicolor;` on a `const int` leaves nothing of the rest of the function, its texture
/// lookups included (NIR's `nir_opt_if` and `nir_opt_dead_cf`). Each is the same code run:
/// an `if` whose condition holds in every lane runs its branch with the lanes it started with.
/// Whether anything changed.
fn take_constant_branches(code: &mut Vec<Inst>, constants: &Constants<'_>) -> bool {
    let mut changed = false;
    let mut out = Vec::with_capacity(code.len());
    for mut inst in code.drain(..) {
        if let Inst::If(c, then, otherwise) = &mut inst
            && let Some(value) = constants.value(*c)
        {
            let mut taken = std::mem::take(if value != 0.0 { then } else { otherwise });
            take_constant_branches(&mut taken, constants);
            out.append(&mut taken);
            changed = true;
        } else {
            for block in blocks_mut(&mut inst) {
                changed |= take_constant_branches(block, constants);
            }
            out.push(inst);
        }
    }
    if let Some(jump) = out.iter().position(|i| matches!(i, Inst::Return | Inst::Break | Inst::Continue)) {
        changed |= jump + 1 < out.len();
        out.truncate(jump + 1);
    }
    *code = out;
    changed
}

/// Whether running `inst` may leave lanes inactive after it: a `discard`, or a `return`
/// from the shader itself (one inside an inlined call ends with the call).
fn may_leave(inst: &Inst, in_call: bool) -> bool {
    match inst {
        Inst::Discard => true,
        Inst::Return => !in_call,
        Inst::If(_, a, b) => a.iter().chain(b).any(|i| may_leave(i, in_call)),
        Inst::Loop { cond_code, body, step, .. } => {
            cond_code.iter().chain(body).chain(step).any(|i| may_leave(i, in_call))
        }
        Inst::Call(body) => body.iter().any(|i| may_leave(i, true)),
        Inst::Breakable(body) => body.iter().any(|i| may_leave(i, in_call)),
        _ => false,
    }
}

/// Stores at the top level of the shader, before anything that may leave lanes inactive, run
/// in every lane the call started with: they become plain moves, which folding can see
/// through (a variable assigned once at the top of `main` is then one value, not a masked
/// store over its zero initialisation).
fn unmask_while_full(code: &mut [Inst]) {
    for inst in code {
        if let Inst::Store(d, s) = *inst {
            *inst = Inst::Un(UnOp::Mov, d, s);
        }
        if may_leave(inst, false) {
            break;
        }
    }
}

/// Removes, within each straight run of a block, a write to a register that a later
/// arithmetic write (every lane) replaces before anything reads it; whether any went.
fn remove_overwritten(code: &mut Vec<Inst>) -> bool {
    let mut removed = false;
    let mut dead = vec![false; code.len()];
    // Register → the index of its last whole write, not read since.
    let mut unread: HashMap<Reg, usize> = HashMap::new();
    for (i, inst) in code.iter_mut().enumerate() {
        let nested = !blocks_mut(inst).is_empty();
        for block in blocks_mut(inst) {
            removed |= remove_overwritten(block);
        }
        if nested || !inst.is_straight_line() {
            // Blocks may read anything; jumps end the straight run.
            unread.clear();
            continue;
        }
        reads_mut(inst, &mut |r| {
            unread.remove(r);
        });
        let whole = matches!(inst, Inst::Un(..) | Inst::Bin(..) | Inst::Tri(..));
        writes(inst, &mut |r| {
            if whole {
                if let Some(earlier) = unread.insert(r, i) {
                    dead[earlier] = true;
                    removed = true;
                }
            } else {
                // A masked write keeps the other lanes' old values: it reads them.
                unread.remove(&r);
            }
        });
    }
    let mut dead = dead.into_iter();
    code.retain(|_| !dead.next().unwrap_or(false));
    removed
}

/// How each work register is written, over the whole program.
struct Writes {
    count: Vec<u32>,
    /// Written by arithmetic, a lookup or a derivative: every lane at once.
    whole: Vec<bool>,
}

fn count_writes(code: &mut [Inst], w: &mut Writes) {
    for inst in code {
        let whole = matches!(
            inst,
            Inst::Un(..)
                | Inst::Bin(..)
                | Inst::Tri(..)
                | Inst::Sample { .. }
                | Inst::SampleCube { .. }
                | Inst::SampleLayered { .. }
                | Inst::Fetch { .. }
                | Inst::Derivative { .. }
        );
        writes(inst, &mut |r| {
            w.count[r as usize] += 1;
            w.whole[r as usize] = whole;
        });
        for block in blocks_mut(inst) {
            count_writes(block, w);
        }
    }
}

struct Folder<'a, 'b> {
    constants: &'a mut Constants<'b>,
    pin: &'a [bool],
    writes: Writes,
    /// Registers whose single write has been passed, in program order.
    defined: Vec<bool>,
    /// Work register → the register (or constant) that replaces it.
    replaced: Vec<Option<Reg>>,
    /// Work register written once, by arithmetic, already passed → the instruction.
    defs: HashMap<Reg, Inst>,
    changed: bool,
}

impl Folder<'_, '_> {
    fn resolve(&self, mut r: Reg) -> Reg {
        // A chain is at most as long as the registers; the bound only guards a cycle.
        for _ in 0..self.replaced.len() {
            match (r & BANK == 0).then(|| self.replaced[r as usize]).flatten() {
                Some(next) => r = next,
                None => break,
            }
        }
        r
    }

    /// Whether `r` holds the same value at every read of a register computed from it now.
    fn stable(&self, r: Reg) -> bool {
        if r & BANK != 0 {
            return true;
        }
        let (count, whole) = (self.writes.count[r as usize], self.writes.whole[r as usize]);
        (count == 0 && self.pin[r as usize]) || (count == 1 && whole && self.defined[r as usize])
    }

    /// What the arithmetic `inst` (operands resolved) reduces to: a constant or an operand.
    fn simplify(&mut self, inst: &Inst) -> Option<Reg> {
        let k = |r: Reg| self.constants.value(r);
        let lanes = |x: f32| [x];
        match *inst {
            Inst::Un(op, _, a) => {
                if let Some(x) = k(a) {
                    return Some(self.constants.reg(unary(op, lanes(x))[0]));
                }
                // Rounding to binary16 twice is rounding once.
                let rounded = op == UnOp::Half && matches!(self.def(a), Some(Inst::Un(UnOp::Half, ..)));
                (op == UnOp::Mov || rounded).then_some(a)
            }
            Inst::Bin(op, _, a, b) => {
                if let (Some(x), Some(y)) = (k(a), k(b)) {
                    return Some(self.constants.reg(binary(op, lanes(x), lanes(y))[0]));
                }
                let is = |r: Reg, v: f32| k(r).is_some_and(|x| x.to_bits() == v.to_bits());
                let zero = |r: Reg| is(r, 0.0);
                match op {
                    BinOp::Mul if zero(a) || zero(b) => Some(self.constants.reg(0.0)),
                    BinOp::Mul if is(b, 1.0) => Some(a),
                    BinOp::Mul if is(a, 1.0) => Some(b),
                    BinOp::Div if is(b, 1.0) => Some(a),
                    BinOp::Add if zero(b) || is(b, -0.0) => Some(a),
                    BinOp::Add if zero(a) || is(a, -0.0) => Some(b),
                    BinOp::Sub if zero(b) => Some(a),
                    _ => None,
                }
            }
            Inst::Tri(op, _, a, b, c) => {
                if let (Some(x), Some(y), Some(z)) = (k(a), k(b), k(c)) {
                    return Some(self.constants.reg(ternary(op, lanes(x), lanes(y), lanes(z))[0]));
                }
                match (op, k(a), k(c)) {
                    (TriOp::Select, Some(cond), _) => Some(if cond != 0.0 { b } else { c }),
                    (TriOp::Mix, _, Some(0.0)) => Some(a),
                    (TriOp::Mix, _, Some(1.0)) => Some(b),
                    _ => None,
                }
            }
            _ => None,
        }
    }

    /// The arithmetic instruction that computed `r`, if it is written once and still holds it.
    fn def(&self, r: Reg) -> Option<Inst> {
        if r & BANK != 0 || !self.stable(r) {
            return None;
        }
        self.defs.get(&r).cloned()
    }

    /// `op` of a constant and a non-constant register that holds its value: (constant,
    /// register).
    fn constant_and_other(&self, a: Reg, b: Reg) -> Option<(f32, Reg)> {
        match (self.constants.value(a), self.constants.value(b)) {
            (Some(x), None) if self.stable(b) => Some((x, b)),
            (None, Some(y)) if self.stable(a) => Some((y, a)),
            _ => None,
        }
    }

    /// A multiplication or addition of a constant and another register, subtraction of a
    /// constant as addition of its negation: (operation, destination, constant, register).
    fn constant_operation(&self, inst: &Inst) -> Option<(BinOp, Reg, f32, Reg)> {
        match *inst {
            Inst::Bin(op @ (BinOp::Mul | BinOp::Add), d, a, b) => {
                let (c, x) = self.constant_and_other(a, b)?;
                Some((op, d, c, x))
            }
            Inst::Bin(BinOp::Sub, d, a, b) if self.constants.value(a).is_none() && self.stable(a) => {
                Some((BinOp::Add, d, -self.constants.value(b)?, a))
            }
            _ => None,
        }
    }

    /// Reassociates constants in a chain of multiplications or additions so they fold
    /// together, as NIR's inexact rules do (`~fmul #a (fmul b #c) → fmul (fmul a c) b`, the
    /// same for `fadd`): `(y · c₁) · c₂` becomes `y · (c₁ · c₂)`. In a binary16 chain (see
    /// `compile`'s precision lowering) the inner result is rounded (`half`) before the outer
    /// operation, and the folded constant is rounded too, as NIR folds 16-bit constants.
    /// Not exact: `glmark2`'s terrain noise computes `p · (1/7) · (1/7)` and takes its floor,
    /// which lands on the other side of an integer for some `p` unless it is reassociated as
    /// Mesa does.
    ///
    /// A subtraction of a constant is an addition of its negation, as in NIR (`fsub a #b` is
    /// `fadd a #-b`): the simplex noise's `x0 - 1.0 + 0.5` is `x0 + -0.5` (float-probe,
    /// llvmpipe's binary16 values of it to the bit).
    fn reassociate(&mut self, inst: &Inst) -> Option<Inst> {
        let (op, d, outer, x) = self.constant_operation(inst)?;
        let (inner_def, half) = match self.def(x)? {
            Inst::Un(UnOp::Half, _, t) => (self.def(t)?, true),
            other => (other, false),
        };
        let (inner_op, _, inner, y) = self.constant_operation(&inner_def)?;
        if inner_op != op {
            return None;
        }
        // In a binary16 chain the inner operation's operands are binary16 values; a single
        // precision product rounded to binary16 as the operand of a lowered operation is a
        // conversion between the two, which NIR does not reassociate across.
        let y_is_half = matches!(self.def(y), Some(Inst::Un(UnOp::Half, ..)));
        if half != y_is_half {
            return None;
        }
        let mut c = binary(op, [inner], [outer])[0];
        if half {
            c = unary(UnOp::Half, [c])[0];
        }
        Some(Inst::Bin(op, d, y, self.constants.reg(c)))
    }

    fn block(&mut self, code: &mut Vec<Inst>) {
        let mut kept = Vec::with_capacity(code.len());
        for mut inst in code.drain(..) {
            reads_mut(&mut inst, &mut |r| *r = self.resolve(*r));
            if let Some(re) = self.reassociate(&inst) {
                inst = re;
                self.changed = true;
            }
            let dst = match inst {
                Inst::Un(_, d, _) | Inst::Bin(_, d, _, _) | Inst::Tri(_, d, _, _, _) => Some(d),
                _ => None,
            };
            if let Some(d) = dst
                && !self.pin[d as usize]
                && self.writes.count[d as usize] == 1
                && let Some(r) = self.simplify(&inst)
                && self.stable(r)
            {
                self.replaced[d as usize] = Some(r);
                self.changed = true;
                continue;
            }
            for block in blocks_mut(&mut inst) {
                self.block(block);
            }
            writes(&inst, &mut |r| self.defined[r as usize] = true);
            if let Some(d) = dst
                && self.writes.count[d as usize] == 1
            {
                self.defs.insert(d, inst.clone());
            }
            kept.push(inst);
        }
        *code = kept;
    }

    /// Resolves reads everywhere again (a read placed before its write in program order).
    fn resolve_all(&self, code: &mut [Inst]) {
        for inst in code {
            reads_mut(inst, &mut |r| *r = self.resolve(*r));
            for block in blocks_mut(inst) {
                self.resolve_all(block);
            }
        }
    }
}

/// One pass of folding and simplification; whether anything changed.
fn fold(code: &mut Vec<Inst>, work_regs: usize, constants: &mut Constants<'_>, pin: &[bool]) -> bool {
    let mut w = Writes { count: vec![0; work_regs], whole: vec![false; work_regs] };
    count_writes(code, &mut w);
    let mut folder = Folder {
        constants,
        pin,
        writes: w,
        defined: vec![false; work_regs],
        replaced: vec![None; work_regs],
        defs: HashMap::new(),
        changed: false,
    };
    folder.block(code);
    folder.resolve_all(code);
    folder.changed
}

fn count_reads(code: &mut [Inst], reads: &mut [u32]) {
    for inst in code {
        reads_mut(inst, &mut |r| {
            if *r & BANK == 0 {
                reads[*r as usize] += 1;
            }
        });
        for block in blocks_mut(inst) {
            count_reads(block, reads);
        }
    }
}

/// Removes straight-line instructions whose results nothing reads, last first so that a chain goes
/// in one pass, and `if`s left with nothing to do; whether anything went.
fn remove_dead(code: &mut Vec<Inst>, work_regs: usize, pin: &[bool]) -> bool {
    let mut reads = vec![0u32; work_regs];
    count_reads(code, &mut reads);
    for (r, &p) in pin.iter().enumerate() {
        if p {
            reads[r] += 1;
        }
    }
    let mut removed = false;
    sweep(code, &mut reads, &mut removed);
    removed
}

fn sweep(code: &mut Vec<Inst>, reads: &mut [u32], removed: &mut bool) {
    let mut keep = vec![true; code.len()];
    for (i, inst) in code.iter_mut().enumerate().rev() {
        for block in blocks_mut(inst) {
            sweep(block, reads, removed);
        }
        let dead = if inst.is_straight_line() {
            let mut live = false;
            writes(inst, &mut |r| live |= reads[r as usize] > 0);
            !live
        } else {
            matches!(inst, Inst::If(_, a, b) if a.is_empty() && b.is_empty())
        };
        if dead {
            keep[i] = false;
            *removed = true;
            reads_mut(inst, &mut |r| {
                if *r & BANK == 0 {
                    reads[*r as usize] -= 1;
                }
            });
        }
    }
    let mut keep = keep.into_iter();
    code.retain(|_| keep.next().unwrap_or(true));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ir::Lod;

    fn optimized(mut code: Vec<Inst>, work_regs: usize, bank: &mut Vec<f32>, pinned: &[Reg]) -> Vec<Inst> {
        let constants = (0..bank.len() as Reg).map(|i| BANK | i).collect::<Vec<_>>();
        let mut c = Constants::new(bank, constants);
        optimize(&mut code, work_regs, &mut c, pinned);
        code
    }

    fn sample(dst: [Reg; 4], coord: [Reg; 2]) -> Inst {
        Inst::Sample { slot: 0, dst, coord, lod: Lod::Implicit, reference: None, offset: [0, 0], round: false }
    }

    #[test]
    fn a_lookup_weighted_by_zero_is_removed_and_a_weight_of_one_leaves_the_texel() {
        // bank 0 = 0.0, bank 1 = 1.0; r0, r1 = coordinates (input).
        // r2..r5 = texel A, r6..r9 = texel B; out r12 = A.x·0 + B.x·1.
        let mut bank = vec![0.0, 1.0];
        let code = vec![
            sample([2, 3, 4, 5], [0, 1]),
            sample([6, 7, 8, 9], [1, 0]),
            Inst::Bin(BinOp::Mul, 10, 2, BANK),
            Inst::Bin(BinOp::Mul, 11, 6, BANK | 1),
            Inst::Bin(BinOp::Add, 13, 10, 11),
            Inst::Store(12, 13),
        ];
        let code = optimized(code, 14, &mut bank, &[0, 1, 12]);
        // The store at the top of the shader is a move, and the output is looked up into.
        assert_eq!(code, vec![sample([12, 7, 8, 9], [1, 0])]);
    }

    #[test]
    fn constant_arithmetic_folds_to_the_executors_bits() {
        let mut bank = vec![0.1, 3.0];
        let code = vec![Inst::Bin(BinOp::Div, 0, BANK, BANK | 1), Inst::Un(UnOp::Sin, 1, 0), Inst::Store(2, 1)];
        let code = optimized(code, 3, &mut bank, &[2]);
        let [Inst::Un(UnOp::Mov, 2, r)] = code[..] else { panic!("{code:?}") };
        assert_eq!(bank[(r & !BANK) as usize].to_bits(), (0.1f32 / 3.0).sin().to_bits());
    }

    #[test]
    fn a_variable_stored_under_a_mask_is_not_an_alias() {
        // In a branch, r0 (input) is copied into r1 with a store (masked), then r2 = r1·1
        // must stay a read of r1 at that point: r1 is written again after it.
        let mut bank = vec![1.0];
        let code = vec![Inst::If(
            0,
            vec![
                Inst::Un(UnOp::Mov, 1, BANK),
                Inst::Store(1, 0),
                Inst::Bin(BinOp::Mul, 2, 1, BANK),
                Inst::Store(1, BANK),
                Inst::Store(3, 2),
            ],
            vec![],
        )];
        let code = optimized(code.clone(), 4, &mut bank, &[0, 3]);
        let Inst::If(_, then, _) = &code[0] else { panic!("{code:?}") };
        assert!(then.contains(&Inst::Bin(BinOp::Mul, 2, 1, BANK)), "{code:?}");
        assert!(then.contains(&Inst::Store(1, 0)), "{code:?}");
    }

    #[test]
    fn stores_after_a_possible_discard_stay_masked() {
        // r1 = output; a store before the discard runs in every lane, one after it may not.
        let mut bank = vec![0.0, 2.0];
        let code = vec![Inst::Store(1, BANK | 1), Inst::If(0, vec![Inst::Discard], vec![]), Inst::Store(1, 0)];
        let code = optimized(code, 2, &mut bank, &[0, 1]);
        assert_eq!(code[0], Inst::Un(UnOp::Mov, 1, BANK | 1));
        assert_eq!(code[2], Inst::Store(1, 0));
    }

    #[test]
    fn a_write_replaced_before_any_read_goes() {
        // r1 = 0 (a declaration's zeroing), then r1 = r0 + 2 in every lane, then output r2.
        let mut bank = vec![0.0, 2.0];
        let code = vec![Inst::If(
            0,
            vec![Inst::Un(UnOp::Mov, 1, BANK), Inst::Bin(BinOp::Add, 1, 0, BANK | 1), Inst::Store(2, 1)],
            vec![],
        )];
        let code = optimized(code, 3, &mut bank, &[0, 2]);
        let Inst::If(_, then, _) = &code[0] else { panic!("{code:?}") };
        assert_eq!(then[..], [Inst::Bin(BinOp::Add, 1, 0, BANK | 1), Inst::Store(2, 1)]);
    }

    #[test]
    fn a_branch_on_a_constant_is_taken_and_code_after_its_return_goes() {
        // Weston's shader variants: `if (c_variant == SOLID) return unicolor;` on a constant
        // in an inlined function, the texture lookups of the other variants after it.
        let mut bank = vec![1.0, 0.0];
        let call = Inst::Call(vec![
            Inst::If(BANK, vec![Inst::Store(1, 0), Inst::Return], vec![]),
            Inst::If(BANK | 1, vec![Inst::Un(UnOp::Sin, 3, 0)], vec![Inst::Un(UnOp::Cos, 3, 0)]),
            sample([4, 5, 6, 7], [0, 0]),
            Inst::Store(1, 4),
        ]);
        let code = optimized(vec![call], 8, &mut bank, &[0, 1]);
        assert_eq!(code, [Inst::Call(vec![Inst::Store(1, 0), Inst::Return])]);
        // The other way round: the constant is false and the lookup stays, the branch not
        // taken goes.
        let mut bank = vec![0.0];
        let code = vec![Inst::If(BANK, vec![Inst::Discard], vec![sample([1, 2, 3, 4], [0, 0]), Inst::Store(5, 1)])];
        let code = optimized(code, 6, &mut bank, &[0, 5]);
        assert!(
            matches!(code[..], [Inst::Sample { .. }, Inst::Store(5, 1)] | [Inst::Sample { .. }, Inst::Un(..)]),
            "{code:?}"
        );
    }

    #[test]
    fn side_effects_and_the_interface_stay() {
        let mut bank = vec![0.0];
        let code = vec![
            Inst::Bin(BinOp::Mul, 1, 0, BANK),
            Inst::If(0, vec![Inst::Discard], vec![]),
            Inst::Loop { cond_code: vec![], cond: None, body: vec![Inst::Break], step: vec![], test_first: true },
            Inst::Un(UnOp::Sin, 2, 0),
        ];
        let code = optimized(code, 3, &mut bank, &[0, 2]);
        assert_eq!(code.len(), 3, "{code:?}");
        assert!(matches!(code[2], Inst::Un(UnOp::Sin, 2, 0)));
    }
}
