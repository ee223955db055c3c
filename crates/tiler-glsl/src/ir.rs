//! The lane-wide IR: instructions over registers of `W` lanes of `f32`.
//!
//! Every value the compiler handles is a list of component registers: a `vec3` is three
//! registers, a `mat4` sixteen (column after column), a struct its fields' registers in order,
//! an array its elements'. Booleans are `0.0`/`1.0`; `int` and `uint` are their 32 bits
//! held in the register (`f32::from_bits(x as u32)`), worked on only by the integer
//! instructions (`I…`/`U…`, the bit operations and the conversions), which reinterpret the
//! bits — so one register file serves every type, a move or a select copies any of them,
//! and a later JIT needs only one vector type. Integer arithmetic wraps (two's
//! complement); what GLSL leaves undefined is defined here, the same on every backend:
//! division and remainder by zero give 0 (`i32::MIN / −1` wraps to `i32::MIN`, its
//! remainder is 0), shift counts are taken modulo 32, and float → integer conversions
//! truncate and saturate (NaN → 0, negative → 0 for `uint`).
//!
//! Registers whose index has [`BANK`] set live in the program instance's read-only bank
//! (uniforms and constants, splatted across the lanes once per instance); the others are
//! the per-call work file.
//!
//! Control flow stays structured ([`Inst::If`], [`Inst::Loop`], [`Inst::Call`]) and runs
//! under a lane mask: arithmetic writes temporaries in every lane, and only stores to
//! variables ([`Inst::Store`]) are masked by the lanes still active.

/// A register index; [`BANK`] set means the instance's bank.
pub type Reg = u32;

/// The bit of a [`Reg`] that selects the bank of uniforms and constants.
pub const BANK: Reg = 1 << 31;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnOp {
    Mov,
    Neg,
    Not,
    Abs,
    Sign,
    Floor,
    Ceil,
    Fract,
    Trunc,
    Round,
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Exp,
    Log,
    Exp2,
    Log2,
    Sqrt,
    InverseSqrt,
    Radians,
    Degrees,
    /// Float → bool (`x != 0`).
    ToBool,
    /// Integer (either signedness) → bool (`x != 0`).
    IToBool,
    /// Wrapping negation of an int.
    INeg,
    /// `abs` of an int (`abs(i32::MIN)` wraps to itself).
    IAbs,
    /// `sign` of an int.
    ISign,
    /// `~x`.
    BitNot,
    /// int → float (rounded to nearest).
    IToF,
    /// uint → float (rounded to nearest).
    UToF,
    /// float → int: truncated, saturated, NaN → 0.
    FToI,
    /// float → uint: truncated, saturated (negative → 0), NaN → 0.
    FToU,
    /// Rounds to the nearest IEEE binary16 value (ties to even; beyond ±65504 to ±∞), held
    /// as `f32`: what a `mediump`/`lowp` operation does to its operands and its result (see
    /// `compile`'s precision lowering).
    Half,
    /// Rounds toward zero to an IEEE binary16 value (beyond ±65504 to ±65504), held as
    /// `f32`: what llvmpipe does to the texels a `mediump`/`lowp` sampler returns (see
    /// `compile`'s precision lowering; measured with tools/float-probe's `texels.frag`).
    HalfTowardZero,
    /// float → the bits of the nearest half float, in the low 16 bits of a uint
    /// (`packHalf2x16`).
    FToHalf,
    /// The half float in the low 16 bits of a uint → float (`unpackHalf2x16`).
    HalfToF,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    /// Wrapping int (or uint: the same bits) addition, subtraction, multiplication.
    IAdd,
    ISub,
    IMul,
    /// int division: the quotient truncated toward zero; 0 for a zero divisor.
    IDiv,
    /// int remainder (`%`): `x − y·(x / y)` with that quotient; 0 for a zero divisor.
    IRem,
    /// uint division and remainder; 0 for a zero divisor.
    UDiv,
    URem,
    IMin,
    IMax,
    UMin,
    UMax,
    ILt,
    ILe,
    IGt,
    IGe,
    ULt,
    ULe,
    UGt,
    UGe,
    /// Equality of integers' bits (either signedness).
    IEq,
    INe,
    BitAnd,
    BitOr,
    BitXor,
    /// `x << (y mod 32)`.
    Shl,
    /// int `x >> (y mod 32)`, arithmetic (the sign copied in).
    IShr,
    /// uint `x >> (y mod 32)`, logical.
    UShr,
    /// GLSL `mod`: `x − y·floor(x/y)`.
    Mod,
    Min,
    Max,
    Pow,
    Atan2,
    /// GLSL `step(edge, x)`: `x < edge ? 0 : 1`.
    Step,
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
    And,
    Or,
    Xor,
    /// `Add`, `Sub`, `Mul` and `Div` with the result rounded to binary16 ([`UnOp::Half`]): a
    /// `mediump` operation and the rounding of its result in one instruction (see `fuse`).
    AddHalf,
    SubHalf,
    MulHalf,
    DivHalf,
    /// `MulHalf` of the first operand rounded to binary16 first: a `mediump` product of a
    /// value that is not binary16 yet (a texel, a varying).
    HalfMulHalf,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TriOp {
    /// `clamp(x, lo, hi)` = `min(max(x, lo), hi)`.
    Clamp,
    /// The same on ints and on uints.
    IClamp,
    UClamp,
    /// `mix(x, y, a)` = `x·(1 − a) + y·a`.
    Mix,
    /// `smoothstep(e0, e1, x)`: `t = clamp((x − e0)/(e1 − e0), 0, 1)`, `t·t·(3 − 2t)`.
    Smoothstep,
    /// `c != 0 ? a : b` (operands `c, a, b`).
    Select,
    /// `a·b + c`, rounded after the product and after the sum (not fused): a multiply and an
    /// add in one instruction (see `fuse`).
    MulAdd,
    /// `a·b + c` with the product and the sum each rounded to binary16: a `mediump`
    /// multiply-add, the same bits as `MulHalf` then `AddHalf` (see `fuse`).
    MulAddHalf,
    /// `MulAddHalf` with the first factor rounded to binary16 first (see `BinOp::HalfMulHalf`).
    HalfMulAddHalf,
}

/// A window axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    X,
    Y,
}

/// How a texture lookup chooses its level of detail.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lod {
    /// From the quad's derivatives (fragment shaders).
    Implicit,
    /// From the derivatives plus a bias register.
    Bias(Reg),
    /// An explicit level register.
    Explicit(Reg),
    /// Explicit derivatives of the coordinates along window x (`dx`) and y (`dy`)
    /// (`textureGrad`; components a lookup lacks are a zero constant).
    Grad { dx: [Reg; 3], dy: [Reg; 3] },
    /// `textureGather`: no filter and no level; the four texels of level 0 a bilinear
    /// lookup would blend, channel `0` (red) to `3` of each, as `(i0, j1), (i1, j1), (i1, j0),
    /// (i0, j0)` (GL ES 3.1 §8.14.2).
    Gather(u8),
}

impl Lod {
    /// Calls `f` on each register the level of detail reads.
    pub fn for_each_reg(&mut self, mut f: impl FnMut(&mut Reg)) {
        match self {
            Lod::Implicit | Lod::Gather(_) => {}
            Lod::Bias(r) | Lod::Explicit(r) => f(r),
            Lod::Grad { dx, dy } => dx.iter_mut().chain(dy.iter_mut()).for_each(f),
        }
    }
}

// A plain tag (`repr(u8)`) rather than one hidden in a `Vec`'s capacity: the executor's
// dispatch then reads one byte instead of decoding the niche (four instructions more per
// executed instruction).
#[derive(Clone, Debug, PartialEq)]
#[repr(u8)]
pub enum Inst {
    Un(UnOp, Reg, Reg),
    Bin(BinOp, Reg, Reg, Reg),
    Tri(TriOp, Reg, Reg, Reg, Reg),
    /// `dst = src` in the active lanes.
    Store(Reg, Reg),
    /// `dst = src` in the active lanes where `cond` is true (a write through a dynamic index).
    StoreIf(Reg, Reg, Reg),
    /// Runs `then` for the active lanes where the register is true, `else` for the others;
    /// a branch no lane takes is skipped.
    If(Reg, Vec<Inst>, Vec<Inst>),
    /// A loop: `cond_code` computes `cond` (none: always true), then `body`, then `step`.
    /// `test_first` is false for `do … while`.
    Loop {
        cond_code: Vec<Inst>,
        cond: Option<Reg>,
        body: Vec<Inst>,
        step: Vec<Inst>,
        test_first: bool,
    },
    /// Leaves the innermost [`Inst::Loop`] or [`Inst::Breakable`] in the active lanes.
    Break,
    Continue,
    /// Leaves the innermost [`Inst::Call`] (or the shader) in the active lanes.
    Return,
    Discard,
    /// An inlined function body: the scope of its `return`s.
    Call(Vec<Inst>),
    /// A `switch` body: the scope of its `break`s (lanes that break leave it and carry on
    /// after it; `continue` passes to the enclosing loop).
    Breakable(Vec<Inst>),
    /// The screen-space derivative of a register along x or y (GL's window axes), from the
    /// lanes of each 2×2 quad (fragment shaders).
    Derivative {
        dst: Reg,
        src: Reg,
        axis: Axis,
    },
    /// Samples texture slot `slot` at `(s, t)` into four registers; with a `reference` depth
    /// (a shadow sampler), the filtered result of comparing it with the texels, `(r, r, r, 1)`.
    Sample {
        slot: u16,
        dst: [Reg; 4],
        coord: [Reg; 2],
        lod: Lod,
        reference: Option<Reg>,
        /// Texels added to the texel indices before the wrap (`textureOffset`).
        offset: [i8; 2],
        /// The texels are rounded toward zero to binary16 (`UnOp::HalfTowardZero`) before
        /// they are written: a `mediump` sampler's roundings, folded in by `fuse`.
        round: bool,
    },
    /// Samples cube texture slot `slot` in the direction `(x, y, z)` into four registers.
    SampleCube {
        slot: u16,
        dst: [Reg; 4],
        direction: [Reg; 3],
        lod: Lod,
    },
    /// Samples a 2-D array (`(s, t, layer)`) or 3-D (`(s, t, r)`) texture slot `slot` into
    /// four registers.
    SampleLayered {
        slot: u16,
        dst: [Reg; 4],
        coord: [Reg; 3],
        lod: Lod,
    },
    /// `texelFetch` (`size` false): texel `coord` (ints `x`, `y` and a layer or slice, 0 for a
    /// 2D texture) of level `level` of slot `slot`, unfiltered, into four registers (floats, or
    /// an integer texture's ints); `textureSize` (`size` true): level `level`'s width, height
    /// and layers (ints) into the first three (`coord` then reads `level` and is ignored).
    Fetch {
        slot: u16,
        dst: [Reg; 4],
        coord: [Reg; 3],
        level: Reg,
        size: bool,
    },
}

impl Inst {
    /// Straight-line work: computes registers and has no effect but its writes (no block, no
    /// jump, no output, no discard). Dead-code removal may drop it when nothing reads its
    /// result, and multiply fusion may move a product past it.
    pub fn is_straight_line(&self) -> bool {
        matches!(
            self,
            Inst::Un(..)
                | Inst::Bin(..)
                | Inst::Tri(..)
                | Inst::Store(..)
                | Inst::StoreIf(..)
                | Inst::Sample { .. }
                | Inst::SampleCube { .. }
                | Inst::SampleLayered { .. }
                | Inst::Fetch { .. }
                | Inst::Derivative { .. }
        )
    }
}

/// Instructions in `code`, nested blocks included.
pub fn count_insts(code: &[Inst]) -> usize {
    code.iter()
        .map(|inst| match inst {
            Inst::If(_, a, b) => 1 + count_insts(a) + count_insts(b),
            Inst::Loop { cond_code, body, step, .. } => {
                1 + count_insts(cond_code) + count_insts(body) + count_insts(step)
            }
            Inst::Call(body) | Inst::Breakable(body) => 1 + count_insts(body),
            _ => 1,
        })
        .sum()
}
