//! Hoisting: arithmetic whose operands are all uniforms or constants is the same in every
//! lane of every call, so it moves out of the shader into the bank, computed once per
//! program instance (`normalize(light_dir)` in a fragment shader costs nothing per group).
//!
//! An instruction moves when all its operands are bank registers (constants, uniforms, or
//! results moved before it) and its destination is written by no other instruction and is
//! not part of the stage's interface. What moves keeps its order, so the bank program runs
//! the same IEEE operations as the shader would have, bit for bit.

use crate::ir::{BANK, Inst, Reg};

/// Calls `f` on each register `inst` reads (not those of nested blocks).
pub(crate) fn reads_mut(inst: &mut Inst, f: &mut impl FnMut(&mut Reg)) {
    match inst {
        Inst::Un(_, _, a) => f(a),
        Inst::Bin(_, _, a, b) => {
            f(a);
            f(b);
        }
        Inst::Tri(_, _, a, b, c) => {
            f(a);
            f(b);
            f(c);
        }
        Inst::Store(_, s) => f(s),
        Inst::StoreIf(_, s, c) => {
            f(s);
            f(c);
        }
        Inst::If(c, _, _) => f(c),
        Inst::Loop { cond: Some(c), .. } => f(c),
        Inst::Sample { coord, lod, reference, .. } => {
            f(&mut coord[0]);
            f(&mut coord[1]);
            if let Some(r) = reference {
                f(r);
            }
            lod.for_each_reg(&mut *f);
        }
        Inst::SampleLayered { coord: direction, lod, .. } | Inst::SampleCube { direction, lod, .. } => {
            direction.iter_mut().for_each(&mut *f);
            lod.for_each_reg(&mut *f);
        }
        Inst::Fetch { coord, level, .. } => {
            coord.iter_mut().for_each(&mut *f);
            f(level);
        }
        Inst::Derivative { src, .. } => f(src),
        _ => {}
    }
}

/// Calls `f` on each register `inst` writes.
pub(crate) fn writes(inst: &Inst, f: &mut impl FnMut(Reg)) {
    match inst {
        Inst::Un(_, d, _) | Inst::Bin(_, d, _, _) | Inst::Tri(_, d, _, _, _) => f(*d),
        Inst::Store(d, _) | Inst::StoreIf(d, _, _) => f(*d),
        Inst::Sample { dst, .. }
        | Inst::SampleCube { dst, .. }
        | Inst::SampleLayered { dst, .. }
        | Inst::Fetch { dst, .. } => dst.iter().for_each(|&d| f(d)),
        Inst::Derivative { dst, .. } => f(*dst),
        _ => {}
    }
}

/// Nested blocks of an instruction.
pub(crate) fn blocks_mut(inst: &mut Inst) -> Vec<&mut Vec<Inst>> {
    match inst {
        Inst::If(_, a, b) => vec![a, b],
        Inst::Loop { cond_code, body, step, .. } => vec![cond_code, body, step],
        Inst::Call(body) | Inst::Breakable(body) => vec![body],
        _ => Vec::new(),
    }
}

fn count_writes(code: &mut [Inst], counts: &mut [u32]) {
    for inst in code {
        writes(inst, &mut |r| counts[r as usize] += 1);
        for block in blocks_mut(inst) {
            count_writes(block, counts);
        }
    }
}

struct Hoister<'a> {
    counts: &'a [u32],
    /// Work register → the bank register now holding it.
    renamed: Vec<Option<Reg>>,
    bank_len: usize,
    moved: Vec<Inst>,
}

impl Hoister<'_> {
    fn rename(&self, r: &mut Reg) {
        if *r & BANK == 0
            && let Some(b) = self.renamed[*r as usize]
        {
            *r = b;
        }
    }

    fn block(&mut self, code: &mut Vec<Inst>) {
        let mut kept = Vec::with_capacity(code.len());
        for mut inst in code.drain(..) {
            reads_mut(&mut inst, &mut |r| self.rename(r));
            let mut all_bank = true;
            reads_mut(&mut inst, &mut |r| all_bank &= *r & BANK != 0);
            let dst = match &mut inst {
                Inst::Un(_, d, _) | Inst::Bin(_, d, _, _) | Inst::Tri(_, d, _, _, _) => Some(d),
                _ => None,
            };
            if let Some(d) = dst
                && all_bank
                && self.counts[*d as usize] == 1
            {
                let bank = BANK | self.bank_len as Reg;
                self.bank_len += 1;
                self.renamed[*d as usize] = Some(bank);
                *d = bank;
                self.moved.push(inst);
                continue;
            }
            for block in blocks_mut(&mut inst) {
                self.block(block);
            }
            kept.push(inst);
        }
        *code = kept;
    }

    /// Renames reads everywhere again (a read placed before its write in program order).
    fn rename_all(&self, code: &mut [Inst]) {
        for inst in code {
            reads_mut(inst, &mut |r| self.rename(r));
            for block in blocks_mut(inst) {
                self.rename_all(block);
            }
        }
    }
}

/// Moves what can be computed once per instance out of `code`. `pinned` are registers the
/// stage's interface reads or fills; `bank` grows by a zero per moved result. Returns the
/// moved instructions (destinations in the bank), in order.
pub fn hoist(code: &mut Vec<Inst>, work_regs: usize, bank: &mut Vec<f32>, pinned: &[Reg]) -> Vec<Inst> {
    let mut counts = vec![0u32; work_regs];
    count_writes(code, &mut counts);
    for &r in pinned {
        if r & BANK == 0 {
            counts[r as usize] += 2;
        }
    }
    let mut h = Hoister { counts: &counts, renamed: vec![None; work_regs], bank_len: bank.len(), moved: Vec::new() };
    h.block(code);
    h.rename_all(code);
    bank.resize(h.bank_len, 0.0);
    h.moved
}
