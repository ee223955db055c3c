//! Fusion: a multiply whose only use is an add becomes one
//! [`TriOp::MulAdd`], so the executor dispatches once and keeps the product out of the
//! register file. `dot`, matrix products and weighted sums (a convolution's
//! `texel * weight + sum`) are chains of these.
//!
//! Before that, an add, subtract, multiply or divide whose only use is its rounding to
//! binary16 (a `mediump` operation, see `compile`'s precision lowering) becomes one
//! instruction that rounds its result ([`BinOp::AddHalf`] …), and a rounded multiply whose
//! only use is a rounded add one [`TriOp::MulAddHalf`]: a `mediump` weighted sum then costs
//! what a `highp` one does.
//!
//! The fused instruction still rounds the product and then the sum (it is not an FMA), so
//! results stay bit for bit those of the two instructions. A pair fuses when the product's
//! register is written only by the multiply, read only by an add later in the same block, and
//! not part of the stage's interface (see [`block`] for what may come between).

use crate::hoist::{blocks_mut, reads_mut, writes};
use crate::ir::{BANK, BinOp, Inst, Reg, TriOp, UnOp};

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
    rounded_texels(code, &uses);
    halves(code, &uses);
    rounded_factors(code, &uses);
    block(code, &uses);
}

/// Folds a `mediump` sampler's roundings of its texels (`UnOp::HalfTowardZero` of each
/// channel, right after the lookup) into the lookup ([`Inst::Sample`]'s `round`): one
/// dispatch instead of up to five, as desktop.trace's blur spends them. A rounding folds when
/// it follows the lookup with only other such roundings between, and its operand is a
/// channel no other instruction reads; a channel nothing reads is rounded too (harmless), a
/// channel read otherwise keeps the lookup as it was. A rounding that writes one of the
/// lookup's channels (or a register another rounding writes) stays, so the lookup never
/// writes a register twice.
fn rounded_texels(code: &mut Vec<Inst>, uses: &Uses) {
    let mut at = 0;
    while at < code.len() {
        for nested in blocks_mut(&mut code[at]) {
            rounded_texels(nested, uses);
        }
        if let Inst::Sample { dst, round: false, .. } = code[at] {
            // The roundings that follow: (index, channel, rounded register).
            let mut folded: Vec<(usize, usize, Reg)> = Vec::new();
            let mut next = at + 1;
            while let Some(&Inst::Un(UnOp::HalfTowardZero, d, x)) = code.get(next)
                && let Some(c) = dst.iter().position(|&r| r == x)
                && uses.single(x)
                && !dst.contains(&d)
                && !folded.iter().any(|f| f.1 == c || f.2 == d)
            {
                folded.push((next, c, d));
                next += 1;
            }
            let unread = |r: Reg| r & BANK == 0 && uses.reads[r as usize] == 0;
            let all = (0..4).all(|c| folded.iter().any(|f| f.1 == c) || unread(dst[c]));
            if all && !folded.is_empty() {
                if let Inst::Sample { dst, round, .. } = &mut code[at] {
                    for &(_, c, d) in &folded {
                        dst[c] = d;
                    }
                    *round = true;
                }
                code.drain(at + 1..next);
            }
        }
        at += 1;
    }
}

/// The operation that also rounds its result to binary16, for the float operations that have
/// one.
fn rounded(op: BinOp) -> Option<BinOp> {
    match op {
        BinOp::Add => Some(BinOp::AddHalf),
        BinOp::Sub => Some(BinOp::SubHalf),
        BinOp::Mul => Some(BinOp::MulHalf),
        BinOp::Div => Some(BinOp::DivHalf),
        _ => None,
    }
}

/// Folds each rounding to binary16 into the operation it rounds when that result has no
/// other use: the operation moves down to the rounding (as a multiply moves to its add in
/// [`block`]) and writes the rounding's register.
fn halves(code: &mut Vec<Inst>, uses: &Uses) {
    let mut out: Vec<Option<Inst>> = Vec::with_capacity(code.len());
    // Operations that may still move: (result, rounded operation, operands, index in `out`).
    let mut pending: Vec<(Reg, BinOp, [Reg; 2], usize)> = Vec::new();
    for mut inst in code.drain(..) {
        let flows = !inst.is_straight_line();
        for nested in blocks_mut(&mut inst) {
            halves(nested, uses);
        }
        if flows {
            pending.clear();
        }
        if let Inst::Un(UnOp::Half, d, x) = inst
            && let Some(at) = pending.iter().rposition(|p| p.0 == x)
        {
            let (_, op, [a, b], index) = pending.swap_remove(at);
            out[index] = None;
            inst = Inst::Bin(op, d, a, b);
        }
        writes(&inst, &mut |w| pending.retain(|p| p.2[0] != w && p.2[1] != w));
        if let Inst::Bin(op, t, a, b) = inst
            && let Some(op) = rounded(op)
            && uses.single(t)
        {
            pending.push((t, op, [a, b], out.len()));
        }
        out.push(Some(inst));
    }
    *code = out.into_iter().flatten().collect();
}

/// Folds the rounding of a factor into the rounded multiply that is its only use
/// ([`BinOp::HalfMulHalf`]): a texel or a varying weighted in `mediump` is rounded, then
/// multiplied and rounded again. The factor's read moves down to the multiply.
fn rounded_factors(code: &mut Vec<Inst>, uses: &Uses) {
    let mut out: Vec<Option<Inst>> = Vec::with_capacity(code.len());
    // Roundings that may still move: (result, rounded register, index in `out`).
    let mut pending: Vec<(Reg, Reg, usize)> = Vec::new();
    for mut inst in code.drain(..) {
        let flows = !inst.is_straight_line();
        for nested in blocks_mut(&mut inst) {
            rounded_factors(nested, uses);
        }
        if flows {
            pending.clear();
        }
        if let Inst::Bin(BinOp::MulHalf, d, a, b) = inst
            && let Some(at) = pending.iter().rposition(|p| p.0 == a || p.0 == b)
        {
            let (t, x, index) = pending.swap_remove(at);
            let other = if a == t { b } else { a };
            out[index] = None;
            inst = Inst::Bin(BinOp::HalfMulHalf, d, x, other);
        }
        writes(&inst, &mut |w| pending.retain(|p| p.1 != w));
        if let Inst::Un(UnOp::Half, t, x) = inst
            && uses.single(t)
        {
            pending.push((t, x, out.len()));
        }
        out.push(Some(inst));
    }
    *code = out.into_iter().flatten().collect();
}

/// Fuses within `code` and its nested blocks. A multiply moves down to its add, so it pairs
/// with an add later in the same block as long as nothing between writes its operands and no
/// nested block or jump comes between (`a * b + c` on vectors is four multiplies, then four
/// adds).
fn block(code: &mut Vec<Inst>, uses: &Uses) {
    let mut out: Vec<Option<Inst>> = Vec::with_capacity(code.len());
    // Multiplies that may still move: (product, factors, index in `out`, the fused operation
    // it makes with a rounded add if it is a rounded multiply).
    let mut pending: Vec<(Reg, [Reg; 2], usize, Option<TriOp>)> = Vec::new();
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
        // A rounded product pairs with a rounded sum only, a plain one with a plain one.
        if let Inst::Bin(add @ (BinOp::Add | BinOp::AddHalf), d, x, y) = inst
            && let half = add == BinOp::AddHalf
            && let Some(at) = pending.iter().rposition(|p| (p.0 == x || p.0 == y) && p.3.is_some() == half)
        {
            let (t, [a, b], index, rounded) = pending.swap_remove(at);
            let addend = if x == t { y } else { x };
            out[index] = None;
            inst = Inst::Tri(rounded.unwrap_or(TriOp::MulAdd), d, a, b, addend);
        }
        writes(&inst, &mut |w| pending.retain(|p| p.1[0] != w && p.1[1] != w));
        if let Inst::Bin(mul @ (BinOp::Mul | BinOp::MulHalf | BinOp::HalfMulHalf), t, a, b) = inst
            && uses.single(t)
        {
            let rounded = match mul {
                BinOp::MulHalf => Some(TriOp::MulAddHalf),
                BinOp::HalfMulHalf => Some(TriOp::HalfMulAddHalf),
                _ => None,
            };
            pending.push((t, [a, b], out.len(), rounded));
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

    #[test]
    fn roundings_fold_into_the_operations_they_round_and_rounded_pairs_fuse() {
        // r5 = half(half(half(r0)·r1) + r2), as `mediump` lowers `t * w + sum`; r6 = half(r0 − r1)
        // read twice stays apart from its rounding's other use.
        let mut code = vec![
            Inst::Un(UnOp::Half, 3, 0),
            Inst::Bin(BinOp::Mul, 4, 3, 1),
            Inst::Un(UnOp::Half, 7, 4),
            Inst::Bin(BinOp::Add, 8, 7, 2),
            Inst::Un(UnOp::Half, 5, 8),
            Inst::Bin(BinOp::Sub, 9, 0, 1),
            Inst::Un(UnOp::Half, 6, 9),
            Inst::Store(10, 9),
        ];
        fuse(&mut code, 11, &[5, 6, 10]);
        assert_eq!(
            code,
            vec![
                Inst::Tri(TriOp::HalfMulAddHalf, 5, 0, 1, 2),
                Inst::Bin(BinOp::Sub, 9, 0, 1),
                Inst::Un(UnOp::Half, 6, 9),
                Inst::Store(10, 9),
            ]
        );
        // A rounded product does not pair with a plain sum.
        let mut mixed =
            vec![Inst::Bin(BinOp::Mul, 2, 0, 1), Inst::Un(UnOp::Half, 3, 2), Inst::Bin(BinOp::Add, 4, 3, 0)];
        fuse(&mut mixed, 5, &[4]);
        assert_eq!(mixed, vec![Inst::Bin(BinOp::MulHalf, 3, 0, 1), Inst::Bin(BinOp::Add, 4, 3, 0)]);
        // A factor's rounding stays where its register is stored to before the multiply.
        let mut stored = vec![
            Inst::Un(UnOp::Half, 2, 0),
            Inst::Store(0, 1),
            Inst::Bin(BinOp::Mul, 3, 1, 2),
            Inst::Un(UnOp::Half, 4, 3),
        ];
        fuse(&mut stored, 5, &[4]);
        assert_eq!(stored, vec![Inst::Un(UnOp::Half, 2, 0), Inst::Store(0, 1), Inst::Bin(BinOp::MulHalf, 4, 1, 2)]);
    }

    #[test]
    fn texel_roundings_fold_into_their_lookup_when_they_are_its_channels_only_reads() {
        use crate::ir::Lod;
        let sample = |dst: [Reg; 4], round| Inst::Sample {
            slot: 0,
            dst,
            coord: [0, 1],
            lod: Lod::Implicit,
            reference: None,
            offset: [0, 0],
            round,
        };
        // Three channels rounded (alpha unread): one rounding lookup into the roundings'
        // registers.
        let mut code = vec![
            sample([2, 3, 4, 5], false),
            Inst::Un(UnOp::HalfTowardZero, 6, 2),
            Inst::Un(UnOp::HalfTowardZero, 7, 3),
            Inst::Un(UnOp::HalfTowardZero, 8, 4),
        ];
        fuse(&mut code, 9, &[6, 7, 8]);
        assert_eq!(code, vec![sample([6, 7, 8, 5], true)]);
        // Alpha read unrounded, or a rounding not next to the lookup: nothing folds.
        let unfolded = vec![
            sample([2, 3, 4, 5], false),
            Inst::Un(UnOp::HalfTowardZero, 6, 2),
            Inst::Un(UnOp::HalfTowardZero, 7, 3),
            Inst::Un(UnOp::HalfTowardZero, 8, 4),
            Inst::Store(9, 5),
        ];
        let mut code = unfolded.clone();
        fuse(&mut code, 10, &[6, 7, 8, 9]);
        assert_eq!(code, unfolded);
        let apart = vec![
            sample([2, 3, 4, 5], false),
            Inst::Store(9, 0),
            Inst::Un(UnOp::HalfTowardZero, 6, 2),
            Inst::Un(UnOp::HalfTowardZero, 7, 3),
            Inst::Un(UnOp::HalfTowardZero, 8, 4),
        ];
        let mut code = apart.clone();
        fuse(&mut code, 10, &[6, 7, 8, 9]);
        assert_eq!(code, apart);
    }

    #[test]
    fn fused_roundings_compute_the_same_bits() {
        use crate::exec::{binary, round_half, ternary, unary};
        let xs: [f32; 8] = [0.1, -3.7, 1.0e-6, 65519.0, 7.0e4, -0.0, 1.0 / 3.0, 2049.5];
        let ys: [f32; 8] = [0.7, 0.001, -5.5, 1.0, 2.0, 3.0, 1.0e-3, -1.25];
        let zs: [f32; 8] = [0.25, 1.0e5, -0.5, 2.0e-5, 9.0, -7.0, 0.3, 11.0];
        for (plain, half) in [
            (BinOp::Add, BinOp::AddHalf),
            (BinOp::Sub, BinOp::SubHalf),
            (BinOp::Mul, BinOp::MulHalf),
            (BinOp::Div, BinOp::DivHalf),
        ] {
            let two = unary(UnOp::Half, binary(plain, xs, ys));
            assert_eq!(binary(half, xs, ys).map(f32::to_bits), two.map(f32::to_bits), "{half:?}");
        }
        let product = binary(BinOp::MulHalf, xs, ys);
        let two = binary(BinOp::AddHalf, product, zs);
        assert_eq!(ternary(TriOp::MulAddHalf, xs, ys, zs).map(f32::to_bits), two.map(f32::to_bits));
        let factor = unary(UnOp::Half, xs);
        let product = binary(BinOp::MulHalf, factor, ys);
        assert_eq!(binary(BinOp::HalfMulHalf, xs, ys).map(f32::to_bits), product.map(f32::to_bits));
        let three = binary(BinOp::AddHalf, product, zs);
        assert_eq!(ternary(TriOp::HalfMulAddHalf, xs, ys, zs).map(f32::to_bits), three.map(f32::to_bits));
        assert_eq!(round_half(1.0 / 3.0), 0.333_251_95);
    }
}
