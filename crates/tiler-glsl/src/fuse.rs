//! Fusion: a multiply whose only use is an add becomes one
//! [`TriOp::MulAdd`], so the executor dispatches once and keeps the product out of the
//! register file. `dot`, matrix products and weighted sums (a convolution's
//! `texel * weight + sum`) are chains of these.
//!
//! The fused instruction still rounds the product and then the sum (it is not an FMA), so
//! results stay bit for bit those of the two instructions. A pair fuses when the product's
//! register is written only by the multiply, read only by an add later in the same block, and
//! not part of the stage's interface (see [`block`] for what may come between).

use crate::hoist::{blocks_mut, reads_mut, writes};
use crate::ir::{BANK, BinOp, Inst, Reg, TriOp};

/// Reads and writes of each work register, nested blocks and the interface included.
struct Uses {
    reads: Vec<u32>,
    writes: Vec<u32>,
}

impl Uses {
    fn count(&mut self, code: &mut [Inst]) {
        for inst in code {
            reads_mut(inst, &mut |r| {
                if *r & BANK == 0 {
                    self.reads[*r as usize] += 1;
                }
            });
            writes(inst, &mut |r| self.writes[r as usize] += 1);
            for block in blocks_mut(inst) {
                self.count(block);
            }
        }
    }

    /// Whether `t` is a temporary holding one value for one reader.
    fn single(&self, t: Reg) -> bool {
        t & BANK == 0 && self.reads[t as usize] == 1 && self.writes[t as usize] == 1
    }
}

/// Fuses the multiply-add pairs of `code` (see the module notes). `pinned` are the
/// registers the stage's interface reads or fills.
pub fn fuse(code: &mut Vec<Inst>, work_regs: usize, pinned: &[Reg]) {
    let mut uses = Uses { reads: vec![0; work_regs], writes: vec![0; work_regs] };
    uses.count(code);
    for &r in pinned {
        if r & BANK == 0 {
            uses.reads[r as usize] += 2;
        }
    }
    block(code, &uses);
}

/// Fuses within `code` and its nested blocks. A multiply moves down to its add, so it pairs
/// with an add later in the same block as long as nothing between writes its operands and no
/// nested block or jump comes between (`a * b + c` on vectors is four multiplies, then four
/// adds).
fn block(code: &mut Vec<Inst>, uses: &Uses) {
    let mut out: Vec<Option<Inst>> = Vec::with_capacity(code.len());
    // Multiplies that may still move: (product, factors, index in `out`).
    let mut pending: Vec<(Reg, [Reg; 2], usize)> = Vec::new();
    for mut inst in code.drain(..) {
        // Anything but straight-line work (blocks, jumps, and whatever the IR gains later)
        // stops multiplies from moving past it.
        let flows = !inst.is_straight_line();
        for nested in blocks_mut(&mut inst) {
            block(nested, uses);
        }
        if flows {
            pending.clear();
        }
        // The latest product read, so that a sum of two keeps the first in place.
        if let Inst::Bin(BinOp::Add, d, x, y) = inst
            && let Some(at) = pending.iter().rposition(|p| p.0 == x || p.0 == y)
        {
            let (t, [a, b], index) = pending.swap_remove(at);
            let addend = if x == t { y } else { x };
            out[index] = None;
            inst = Inst::Tri(TriOp::MulAdd, d, a, b, addend);
        }
        writes(&inst, &mut |w| pending.retain(|p| p.1[0] != w && p.1[1] != w));
        if let Inst::Bin(BinOp::Mul, t, a, b) = inst
            && uses.single(t)
        {
            pending.push((t, [a, b], out.len()));
        }
        out.push(Some(inst));
    }
    *code = out.into_iter().flatten().collect();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dot_product_fuses_into_a_multiply_and_two_multiply_adds() {
        // r6 = r0·r3 + r1·r4 + r2·r5, as `dot` lowers it.
        let mut code = vec![
            Inst::Bin(BinOp::Mul, 6, 0, 3),
            Inst::Bin(BinOp::Mul, 7, 1, 4),
            Inst::Bin(BinOp::Add, 8, 6, 7),
            Inst::Bin(BinOp::Mul, 9, 2, 5),
            Inst::Bin(BinOp::Add, 10, 8, 9),
        ];
        fuse(&mut code, 11, &[10]);
        assert_eq!(
            code,
            vec![
                Inst::Bin(BinOp::Mul, 6, 0, 3),
                Inst::Tri(TriOp::MulAdd, 8, 1, 4, 6),
                Inst::Tri(TriOp::MulAdd, 10, 2, 5, 8),
            ]
        );
    }

    #[test]
    fn vector_multiplies_move_down_to_their_adds_unless_a_factor_changes_between() {
        // vec2: r4, r5 = r0·r2, r1·r3; r1 is stored to between; then r6, r7 = r4 + r8, r9 + r5.
        let mut code = vec![
            Inst::Bin(BinOp::Mul, 4, 0, 2),
            Inst::Bin(BinOp::Mul, 5, 1, 3),
            Inst::Store(1, 8),
            Inst::Bin(BinOp::Add, 6, 4, 8),
            Inst::Bin(BinOp::Add, 7, 9, 5),
        ];
        fuse(&mut code, 10, &[6, 7]);
        assert_eq!(
            code,
            vec![
                Inst::Bin(BinOp::Mul, 5, 1, 3),
                Inst::Store(1, 8),
                Inst::Tri(TriOp::MulAdd, 6, 0, 2, 8),
                Inst::Bin(BinOp::Add, 7, 9, 5),
            ]
        );
    }

    #[test]
    fn a_product_read_twice_or_pinned_stays() {
        let pair = || vec![Inst::Bin(BinOp::Mul, 2, 0, 1), Inst::Bin(BinOp::Add, 3, 2, 0)];
        let mut read_twice = pair();
        read_twice.push(Inst::Store(4, 2));
        fuse(&mut read_twice, 5, &[]);
        assert_eq!(read_twice[..2], pair()[..]);
        let mut pinned = pair();
        fuse(&mut pinned, 4, &[2]);
        assert_eq!(pinned, pair());
        // `t + t` reads the product twice.
        let mut doubled = vec![Inst::Bin(BinOp::Mul, 2, 0, 1), Inst::Bin(BinOp::Add, 3, 2, 2)];
        fuse(&mut doubled, 4, &[]);
        assert_eq!(doubled.len(), 2);
    }

    #[test]
    fn pairs_fuse_inside_nested_blocks_but_not_across_them() {
        let mut code = vec![
            Inst::Bin(BinOp::Mul, 2, 0, 1),
            Inst::If(0, vec![Inst::Bin(BinOp::Mul, 3, 0, 1), Inst::Bin(BinOp::Add, 4, 0, 3)], vec![]),
            Inst::Bin(BinOp::Add, 5, 2, 1),
        ];
        fuse(&mut code, 6, &[]);
        assert_eq!(
            code,
            vec![
                Inst::Bin(BinOp::Mul, 2, 0, 1),
                Inst::If(0, vec![Inst::Tri(TriOp::MulAdd, 4, 0, 1, 0)], vec![]),
                Inst::Bin(BinOp::Add, 5, 2, 1),
            ]
        );
    }
}
