//! Scheduling: lookups of one texture that do not depend on each other are brought together,
//! so that the executor takes them as one run (one call into the environment for all of them,
//! see `exec`): a blur's eleven taps of one texture, each followed by its multiply-add, become
//! eleven lookups in a row, then the multiply-adds.
//!
//! **The same results.** Instructions move only within a straight-line stretch of a block
//! (control flow, `discard` and the other instructions that are not
//! [`Inst::is_straight_line`] stay where they are, with the stretches around them), where
//! the active lanes do not change, and the new order keeps every dependency of the old one:
//! an instruction stays after those that write what it reads (read after write), after those
//! that read what it writes (write after read) and after those that write what it writes
//! (write after write). Texture instructions (lookups, fetches) also keep their order among
//! themselves, as the texture-cache model counts them in that order. Each instruction then
//! computes what it did, bit for bit, and the cache sees the same reads.
//!
//! **How.** The texture instructions of a stretch are taken in order and cut into runs: a run
//! is consecutive texture instructions that are all common lookups ([`runs_together`]) of the
//! same slot, none reading what an earlier one of the run writes. For each run, the
//! instructions it depends on that are not placed yet are placed (in their old order), then
//! the run; the rest of the stretch follows in its old order. That order is a topological
//! order of the dependencies (each instruction's predecessors come before it in the old order,
//! and are placed before it), so it is a valid one.

use crate::hoist::{blocks_mut, writes};
use crate::ir::{Inst, Lod, Reg};

/// Whether `inst` is a lookup the executor may take in a run with others of its slot: a
/// `texture2D` with the implicit level of detail, no reference and no offset.
pub fn runs_together(inst: &Inst) -> Option<u16> {
    match inst {
        Inst::Sample { slot, lod: Lod::Implicit, reference: None, offset: [0, 0], .. } => Some(*slot),
        _ => None,
    }
}

/// Whether `inst` reads or counts texels (its order among such instructions is kept).
fn touches_textures(inst: &Inst) -> bool {
    matches!(inst, Inst::Sample { .. } | Inst::SampleCube { .. } | Inst::SampleLayered { .. } | Inst::Fetch { .. })
}

/// The registers `inst` reads. A `StoreIf` also reads its destination: it keeps it in the
/// lanes where its condition is false.
fn reads(inst: &Inst) -> Vec<Reg> {
    let mut out = Vec::new();
    let mut copy = inst.clone();
    crate::hoist::reads_mut(&mut copy, &mut |r| out.push(*r));
    if let Inst::StoreIf(d, _, _) = inst {
        out.push(*d);
    }
    out
}

/// Reorders every straight-line stretch of `code` and of its nested blocks (see the module
/// notes).
pub fn schedule(code: &mut Vec<Inst>) {
    for inst in code.iter_mut() {
        for block in blocks_mut(inst) {
            schedule(block);
        }
    }
    let mut out = Vec::with_capacity(code.len());
    let mut stretch = Vec::new();
    for inst in code.drain(..) {
        if inst.is_straight_line() {
            stretch.push(inst);
        } else {
            out.extend(stretch_order(std::mem::take(&mut stretch)));
            out.push(inst);
        }
    }
    out.extend(stretch_order(stretch));
    *code = out;
}

/// One straight-line stretch in its new order.
fn stretch_order(stretch: Vec<Inst>) -> Vec<Inst> {
    let n = stretch.len();
    let textures: Vec<usize> = (0..n).filter(|&i| touches_textures(&stretch[i])).collect();
    // Nothing to bring together without two lookups of a slot.
    if textures.len() < 2 || textures.iter().filter(|&&i| runs_together(&stretch[i]).is_some()).count() < 2 {
        return stretch;
    }
    // Each instruction's predecessors by register: the last writer of each register it reads
    // or writes, and the readers since that write of each register it writes.
    let mut predecessors: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut last_writer: std::collections::HashMap<Reg, usize> = Default::default();
    let mut readers: std::collections::HashMap<Reg, Vec<usize>> = Default::default();
    for (i, inst) in stretch.iter().enumerate() {
        let read = reads(inst);
        let mut written = Vec::new();
        writes(inst, &mut |r| written.push(r));
        let p = &mut predecessors[i];
        for r in read.iter().chain(&written) {
            p.extend(last_writer.get(r).copied());
        }
        for r in &written {
            p.extend(readers.remove(r).unwrap_or_default());
        }
        for r in read {
            readers.entry(r).or_default().push(i);
        }
        for r in written {
            last_writer.insert(r, i);
        }
        p.retain(|&j| j != i);
    }
    let mut placed = vec![false; n];
    let mut order = Vec::with_capacity(n);
    // The unplaced instructions `targets` depend on, transitively.
    let unplaced_ancestors = |targets: &[usize], placed: &[bool]| {
        let mut ancestors = vec![false; n];
        let mut stack: Vec<usize> = targets.iter().flat_map(|&t| predecessors[t].iter().copied()).collect();
        while let Some(j) = stack.pop() {
            if !placed[j] && !ancestors[j] {
                ancestors[j] = true;
                stack.extend(predecessors[j].iter().copied());
            }
        }
        ancestors
    };
    let mut k = 0;
    while k < textures.len() {
        let first = textures[k];
        let mut run = vec![first];
        if let Some(slot) = runs_together(&stretch[first]) {
            // The same slot, and no dependency on any texture instruction from the run's first
            // on (so none on the run, through any register): the next could then not be placed
            // before the run.
            while let Some(&next) = textures.get(k + run.len()) {
                let joins = runs_together(&stretch[next]) == Some(slot)
                    && !unplaced_ancestors(&[next], &placed)
                        .iter()
                        .enumerate()
                        .any(|(j, &a)| a && j >= first && touches_textures(&stretch[j]));
                if !joins {
                    break;
                }
                run.push(next);
            }
        }
        // What the run depends on, in its old order, then the run.
        let ancestors = unplaced_ancestors(&run, &placed);
        for j in (0..n).filter(|&j| ancestors[j]) {
            placed[j] = true;
            order.push(j);
        }
        for &i in &run {
            placed[i] = true;
            order.push(i);
        }
        k += run.len();
    }
    order.extend((0..n).filter(|&i| !placed[i]));
    let mut slots: Vec<Option<Inst>> = stretch.into_iter().map(Some).collect();
    order.into_iter().map(|i| slots[i].take().expect("each instruction placed once")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exec::{Env, Executable, LodValue, run, run_length};
    use crate::ir::{BANK, BinOp, UnOp};

    /// Records every texture call (slot, kind, coordinates' bits) and answers with values made
    /// of the coordinates, so that a lookup moved past a write of its coordinates shows.
    #[derive(Default)]
    struct Recorder(Vec<TextureCall>);

    /// A texture call as [`Recorder`] keeps it: slot, kind (0 lookup, 1 fetch), the bits read.
    type TextureCall = (usize, u8, Vec<u32>);
    impl Env<8> for Recorder {
        fn sample(
            &mut self,
            slot: usize,
            coord: [[f32; 8]; 2],
            _: LodValue<8>,
            _: Option<[f32; 8]>,
            offset: [i32; 2],
        ) -> [[f32; 8]; 4] {
            let bits = coord.iter().flatten().map(|x| x.to_bits()).chain(offset.map(|o| o as u32)).collect();
            self.0.push((slot, 0, bits));
            let [s, t] = coord;
            [s, t, std::array::from_fn(|i| s[i] * 0.5 + t[i]), [slot as f32; 8]]
        }
        fn sample_cube(&mut self, _: usize, _: [[f32; 8]; 3], _: LodValue<8>) -> [[f32; 8]; 4] {
            unreachable!("no cube lookups")
        }
        fn fetch(&mut self, slot: usize, coord: [[i32; 8]; 3], level: [i32; 8]) -> [[f32; 8]; 4] {
            self.0.push((slot, 1, coord.iter().flatten().chain(&level).map(|&x| x as u32).collect()));
            [[level[0] as f32; 8]; 4]
        }
    }

    /// SplitMix64.
    struct Random(u64);
    impl Random {
        fn below(&mut self, n: u64) -> u64 {
            self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let z = (self.0 ^ (self.0 >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            let z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            (z ^ (z >> 31)) % n
        }
    }

    const REGS: u64 = 12;

    /// Straight-line code over few registers (so reads and writes of one register cross
    /// often): arithmetic, stores, lookups of two slots (some with an offset, which never run
    /// with others), fetches, and now and then an `if` (a stretch's end).
    fn program(r: &mut Random, len: usize) -> Vec<Inst> {
        let reg = |r: &mut Random| r.below(REGS) as Reg;
        let source = |r: &mut Random| if r.below(4) == 0 { BANK | r.below(2) as Reg } else { r.below(REGS) as Reg };
        (0..len)
            .map(|_| match r.below(14) {
                0..=1 => Inst::Bin(BinOp::Add, reg(r), source(r), source(r)),
                2 => Inst::Bin(BinOp::Mul, reg(r), source(r), source(r)),
                3 => Inst::Un(UnOp::Half, reg(r), source(r)),
                4 => Inst::Store(reg(r), source(r)),
                5 => Inst::StoreIf(reg(r), source(r), source(r)),
                6 => Inst::Fetch {
                    slot: 0,
                    dst: [reg(r), reg(r), reg(r), reg(r)],
                    coord: [0, 1, 2],
                    level: 3,
                    size: false,
                },
                7 => Inst::If(source(r), vec![Inst::Bin(BinOp::Add, reg(r), source(r), source(r))], vec![]),
                k => Inst::Sample {
                    slot: (r.below(5) == 0) as u16,
                    dst: [reg(r), reg(r), reg(r), reg(r)],
                    coord: [source(r), source(r)],
                    lod: Lod::Implicit,
                    reference: None,
                    offset: if k == 8 { [1, 0] } else { [0, 0] },
                    round: r.below(2) == 0,
                },
            })
            .collect()
    }

    fn execute(code: &[Inst], file: &[[f32; 8]], active: u64) -> (Vec<Vec<u32>>, Vec<TextureCall>) {
        let program = Executable::new(code, REGS as usize, 2).expect("registers in range");
        let mut file = file.to_vec();
        let mut recorder = Recorder::default();
        run(&program.interpreted(), &mut file, active, &mut recorder);
        (file.iter().map(|v| v.map(f32::to_bits).to_vec()).collect(), recorder.0)
    }

    /// Random straight-line code computes the same registers, bit for bit, and makes the same
    /// texture calls in the same order once scheduled; and scheduling brings lookups together.
    #[test]
    fn scheduled_code_computes_the_same_and_reads_textures_in_the_same_order() {
        let mut brought_together = 0;
        for seed in 0..2000 {
            let mut r = Random(seed);
            let len = 3 + r.below(40) as usize;
            let code = program(&mut r, len);
            let mut scheduled = code.clone();
            schedule(&mut scheduled);
            assert_eq!(scheduled.len(), code.len(), "seed {seed}");
            let file: Vec<[f32; 8]> =
                (0..REGS + 2).map(|k| std::array::from_fn(|i| (k as f32 + 1.0) * 0.37 + i as f32 * 0.11)).collect();
            let active = 1 + r.below(255);
            assert_eq!(
                execute(&scheduled, &file, active),
                execute(&code, &file, active),
                "seed {seed}\n{code:#?}\n{scheduled:#?}"
            );
            let runs = |code: &[Inst]| (0..code.len()).filter(|&i| run_length(&code[i..]) >= 2).count();
            brought_together += (runs(&scheduled) > runs(&code)) as u32;
        }
        assert!(brought_together > 200, "scheduling made longer runs in {brought_together} programs");
    }

    /// A blur's taps (a coordinate, a lookup, a multiply-add into the sum, eleven times)
    /// become one run of eleven lookups.
    #[test]
    fn a_blurs_taps_become_one_run() {
        let mut code = Vec::new();
        for tap in 0..11 {
            let (coord, texel) = (20 + tap * 6, 21 + tap * 6);
            code.push(Inst::Bin(BinOp::Add, coord, 0, BANK | tap));
            code.push(Inst::Sample {
                slot: 0,
                dst: [texel, texel + 1, texel + 2, texel + 3],
                coord: [coord, 1],
                lod: Lod::Implicit,
                reference: None,
                offset: [0, 0],
                round: true,
            });
            code.push(Inst::Tri(crate::ir::TriOp::MulAdd, 2, texel, BANK | 11, 2));
        }
        schedule(&mut code);
        let first = code.iter().position(|i| matches!(i, Inst::Sample { .. })).unwrap();
        assert_eq!(first, 11, "the eleven coordinates first");
        assert_eq!(run_length(&code[first..]), 11);
        assert!(code[first + 11..].iter().all(|i| matches!(i, Inst::Tri(..))));
    }
}
