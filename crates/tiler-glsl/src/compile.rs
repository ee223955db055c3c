//! From GLSL ES source to the lane-wide IR: parsing (glsl-lang, preprocessor included), type
//! checking and lowering in one walk over the AST.
//!
//! User functions are inlined at each call (GLSL ES forbids recursion; a call chain deeper
//! than [`MAX_CALL_DEPTH`] is an error), inside an [`Inst::Call`] that scopes their
//! `return`s. Every declaration writes all lanes of its variable (its initializer, or zero),
//! so no lane ever reads a register left over from another call.
//!
//! Simplifications, all documented in the crate docs: the operands of `&&`, `||` and `?:`
//! are all evaluated (then selected per lane); integers may mix with floats (promoted, as in
//! desktop GLSL, with a conversion instruction since integers are held as their bits).

use std::collections::{HashMap, HashSet};
use std::sync::Arc;

use glsl_lang::ast::{self, NodeSpan};

use crate::exec::{int, uint};
use crate::ir::{Axis, BANK, BinOp, Inst, Lod, Reg, TriOp, UnOp};
use crate::types::{BOOL, FLOAT, INT, IntegerShape, SamplerKind, Scalar, StructType, Type, UINT};
use crate::{Error, Stage};

mod texfn;

/// Lines of predefined macros inserted into the source.
const PREDEFINED_LINES: usize = 3;

/// Instructions a stage may compile to, inlined calls included.
pub const MAX_INSTRUCTIONS: usize = 1 << 20;

/// Registers a stage may use (work file and bank each).
pub const MAX_REGISTERS: usize = 1 << 20;

/// Components an array may have.
pub const MAX_ARRAY_COMPONENTS: usize = 1 << 16;

/// How deep inlined calls may nest.
pub const MAX_CALL_DEPTH: usize = 64;

/// The length of `gl_FragData`.
pub const MAX_DRAW_BUFFERS: usize = tiler::MAX_COLOR_ATTACHMENTS;

/// A uniform, attribute, varying or output of a compiled stage.
#[derive(Clone, Debug)]
pub struct StageVar {
    pub name: String,
    pub ty: Type,
    /// Component registers (for samplers: slot numbers).
    pub regs: Vec<Reg>,
    /// `layout(location = n)`, if given (ES 3.00).
    pub location: Option<u32>,
    /// A varying qualified `flat` (ES 3.00): the provoking vertex's value, its bits copied.
    pub flat: bool,
}

/// One compiled shader stage.
#[derive(Clone, Debug)]
pub struct StageCode {
    pub stage: Stage,
    pub code: Vec<Inst>,
    /// Registers of the work file.
    pub work_regs: usize,
    /// The bank's values: constants, and zeros where uniforms and hoisted results go.
    pub bank: Vec<f32>,
    /// Instructions computing bank registers from uniforms and constants, run once per
    /// program instance (see `hoist`).
    pub bank_program: Vec<Inst>,
    pub uniforms: Vec<StageVar>,
    /// Attributes (vertex) or varyings (fragment).
    pub inputs: Vec<StageVar>,
    /// Varyings (vertex) or colour outputs (fragment, ES 3.00 `out`).
    pub outputs: Vec<StageVar>,
    /// Sampler slot → (index in `uniforms`, component of that uniform).
    pub samplers: Vec<(usize, usize)>,
    pub position: Option<[Reg; 4]>,
    pub frag_coord: Option<[Reg; 4]>,
    /// `gl_PointSize`, when the vertex shader names it (points then take their size from it).
    pub point_size: Option<Reg>,
    /// `gl_PointCoord`, when the fragment shader reads it.
    pub point_coord: Option<[Reg; 2]>,
    pub front_facing: Option<Reg>,
    /// `gl_VertexID` and `gl_InstanceID` (ES 3.00), filled by the caller before each vertex.
    pub vertex_id: Option<Reg>,
    pub instance_id: Option<Reg>,
    /// The uniforms that are uniform blocks (by name), whose values come from buffers.
    pub blocks: Vec<String>,
    /// `gl_FragColor` or `gl_FragData[i]` (colour attachment `i`).
    pub colors: Vec<(usize, [Reg; 4])>,
    pub discards: bool,
}

/// Compiles one stage's source.
pub fn compile(stage: Stage, source: &str) -> Result<StageCode, Error> {
    let aliased = crate::nested_macros::alias_nested_calls(source);
    let source = aliased.as_ref().map_or(source, |(text, _)| text.as_str());
    let (text, inserted_at) = with_gl_es_define(source);
    let mut lines = LineMap::new(&text, inserted_at);
    lines.original = aliased.map(|(_, original)| original);
    let unit = <ast::TranslationUnit as glsl_lang::parse::Parse>::parse::<crate::guard::CappedLexer>(text.as_str())
        .map_err(|e| {
            let offset = u32::from(e.pos().start()) as usize;
            let message = if crate::guard::was_cut() {
                format!("the preprocessed source is longer than {} tokens", crate::guard::MAX_TOKENS)
            } else {
                e.inner().to_string().replace(NO_EXTENSION, "")
            };
            Error::Compile { stage, line: lines.line(offset), message }
        })?;
    let mut c = Compiler::new(stage, &lines);
    c.unit(&unit).map_err(|(line, message)| Error::Compile { stage, line, message })?;
    Ok(c.finish())
}

/// The shadow-sampler extension of GLSL ES 1.00 (`shadow2DEXT`, `shadow2DProjEXT`).
const SHADOW_SAMPLERS: &str = "GL_EXT_shadow_samplers";

/// The extensions whose macros glsl-lang's preprocessor predefines that the compiler has
/// (besides [`SHADOW_SAMPLERS`], which it predefines itself): `dFdx`, `dFdy`, `fwidth`, and
/// `sampler3D` with `texture3D`.
const EXTENSIONS: [&str; 2] = ["GL_OES_standard_derivatives", "GL_OES_texture_3D"];

/// The prefix a name of an extension the compiler does not have is given in the source, so
/// that no macro of it is defined (`TILER_NO_GL_KHR_blend_equation_advanced`).
const NO_EXTENSION: &str = "TILER_NO_";

/// The macros an ES compiler predefines, as `#define`s after any `#version` line. The
/// preprocessor refuses to define names starting `GL_`, so they are renamed in the source
/// (whole words) to `TILER_…`. Returns the text and the byte offset of the inserted line.
///
/// glsl-lang's preprocessor does not know `GL_EXT_shadow_samplers` (whose `shadow2DEXT` the
/// compiler has) and refuses `#extension` lines that require it, so those lines are emptied
/// (line numbers stay) and the extension's macro is defined with the others.
///
/// It also predefines a macro for each of the 96 extensions it knows, which would send a
/// shader's `#ifdef GL_KHR_blend_equation_advanced` (Qt Quick's) down a path the compiler
/// cannot take: the names of those the compiler does not have ([`EXTENSIONS`]) are renamed
/// out of their way ([`NO_EXTENSION`]), so their macros are undefined, as a driver without
/// them leaves them. An `#extension` line that enables, warns of or disables an extension the
/// compiler does not have is emptied: GLSL ES 1.00 §3.4 asks only for a warning there, and
/// the extension then changes nothing; `require` stays, and fails naming it.
fn with_gl_es_define(source: &str) -> (String, usize) {
    let known = |name: &str| name == SHADOW_SAMPLERS || EXTENSIONS.contains(&name);
    let source: String = source
        .split_inclusive('\n')
        .map(|line| {
            let t = line.trim_start();
            let directive = t.strip_prefix('#').map(str::trim_start);
            let extension = directive.and_then(|d| d.strip_prefix("extension")).and_then(|rest| {
                let (name, behavior) = rest.split_once(':')?;
                Some((name.trim(), behavior.trim()))
            });
            let emptied = extension.is_some_and(|(name, behavior)| {
                name == SHADOW_SAMPLERS || (!known(name) && name != "all" && !behavior.starts_with("require"))
            });
            match (emptied, line.ends_with('\n')) {
                (true, true) => "\n",
                (true, false) => "",
                (false, _) => line,
            }
        })
        .collect();
    let mut renames: Vec<(&str, String)> = vec![
        ("GL_ES", "TILER_GL_ES".into()),
        ("GL_FRAGMENT_PRECISION_HIGH", "TILER_GL_FRAGMENT_PRECISION_HIGH".into()),
        (SHADOW_SAMPLERS, "TILER_GL_EXT_shadow_samplers".into()),
    ];
    for spec in glsl_lang_pp::exts::DEFAULT_REGISTRY.all() {
        let name: &str = spec.name().as_ref();
        if !known(name) && source.contains(name) {
            renames.push((name, format!("{NO_EXTENSION}{name}")));
        }
    }
    let renames: Vec<(&str, &str)> = renames.iter().map(|(from, to)| (*from, to.as_str())).collect();
    let source = &rename_words(&source, &renames);
    let mut at = 0;
    for line in source.split_inclusive('\n') {
        let t = line.trim();
        if t.starts_with("#version") {
            at += line.len();
            break;
        }
        if t.is_empty() || t.starts_with("//") {
            at += line.len();
            continue;
        }
        at = 0;
        break;
    }
    let mut text = String::with_capacity(source.len() + 32);
    text.push_str(&source[..at]);
    if at > 0 && !text.ends_with('\n') {
        text.push('\n');
    }
    let inserted = text.len();
    text.push_str(
        "#define TILER_GL_ES 1\n#define TILER_GL_FRAGMENT_PRECISION_HIGH 1\n#define TILER_GL_EXT_shadow_samplers 1\n",
    );
    text.push_str(&source[at..]);
    (text, inserted)
}

/// `text` with each whole-word `from` replaced by its `to`.
fn rename_words(text: &str, renames: &[(&str, &str)]) -> String {
    let is_word = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(start) = rest.find(|c: char| is_word(c)) {
        out.push_str(&rest[..start]);
        let word_len = rest[start..].find(|c: char| !is_word(c)).unwrap_or(rest.len() - start);
        let word = &rest[start..start + word_len];
        out.push_str(renames.iter().find(|(from, _)| *from == word).map_or(word, |(_, to)| to));
        rest = &rest[start + word_len..];
    }
    out.push_str(rest);
    out
}

/// Byte offset → line number of the original source (1-based).
struct LineMap {
    starts: Vec<usize>,
    inserted_at: usize,
    /// The application's line of each line of the source before the predefined lines went in,
    /// when lines were added to it (see `nested_macros`).
    original: Option<Vec<u32>>,
}

impl LineMap {
    fn new(text: &str, inserted_at: usize) -> LineMap {
        let mut starts = vec![0];
        starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
        LineMap { starts, inserted_at, original: None }
    }

    fn line(&self, offset: usize) -> u32 {
        let line = self.starts.partition_point(|&s| s <= offset);
        let inserted_line = self.starts.partition_point(|&s| s <= self.inserted_at);
        let line = (if line > inserted_line { line - PREDEFINED_LINES } else { line }) as u32;
        match &self.original {
            Some(original) => (line as usize).checked_sub(1).and_then(|i| original.get(i)).copied().unwrap_or(line),
            None => line,
        }
    }
}

type CResult<T> = Result<T, (u32, String)>;

/// A precision qualifier as the compiler uses it (GLSL ES 1.00 §4.5, 3.00 §4.5): `lowp` is
/// computed as `mediump` is, and `None` is what constants (and values made only from them)
/// have — they take the precision of what they meet.
///
/// **Lowering.** An operation on floats whose operands include a `mediump` (or `lowp`) value
/// and no `highp` one is computed in IEEE binary16: its operands are rounded to binary16
/// ([`UnOp::Half`]) and so is its result. That is what mobile GPUs do with `mediump` (Mali,
/// Adreno and PowerVR have binary16 ALUs), and what Mesa does too: its GLSL compiler lowers
/// such expressions to 16 bits when the driver has binary16 arithmetic, llvmpipe among them
/// (`lower_precision.cpp`: an expression tree is lowered when none of its leaves is `highp` and
/// one is `mediump`/`lowp`; constants and unqualified temporaries are neutral; a texture
/// lookup has its sampler's precision, a user function's result its declared precision).
/// Noise shaders (glmark2's terrain) hash lattice cells on values a binary16 rounding moves, so
/// without this the pictures differ in whole cells. Integers are not narrowed (llvmpipe also
/// computes `mediump int` in 16 bits; tiler keeps 32).
///
/// **Single-precision roots.** A `mediump` variable assigned a single-precision value (a
/// `highp` expression) holds it unrounded, and a `mediump` operation all of whose operands
/// are such variables is computed in single precision, unrounded, unless its result is in
/// turn an operand of a lowered operation, which then takes it in binary16
/// ([`Compiler::single`]). Measured on llvmpipe (tools/float-probe/experiments): for such
/// `m`, `u`, `m * u`, `m + u`, `sqrt(m)` and `1.0 / m` are single precision while `m - 0.2`,
/// `(m + u) + u` and `m * 3.0 + u` are binary16 — in Mesa the lowered tree's leaves are
/// conversions that may keep 32 bits, and a tree of one operation on such leaves keeps them.
/// Inputs, uniforms, texels and constants are binary16 leaves.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord)]
enum Prec {
    #[default]
    None,
    Medium,
    High,
}

/// The default precisions of a scope (`precision mediump float;` …): float, int, samplers.
#[derive(Clone, Copy, Debug)]
struct Defaults {
    float: Prec,
    int: Prec,
    sampler: Prec,
}

fn prec_of_qualifier(q: &ast::PrecisionQualifier) -> Prec {
    match q.content {
        ast::PrecisionQualifierData::High => Prec::High,
        ast::PrecisionQualifierData::Medium | ast::PrecisionQualifierData::Low => Prec::Medium,
    }
}

/// The precision qualifier written in `q`, if any.
fn written_prec(q: Option<&ast::TypeQualifier>) -> Option<Prec> {
    q?.qualifiers.iter().find_map(|spec| match &spec.content {
        ast::TypeQualifierSpecData::Precision(p) => Some(prec_of_qualifier(p)),
        _ => None,
    })
}

/// Whether a unary operation reads a float (not an int, uint or bool).
fn float_operand(op: UnOp) -> bool {
    !matches!(
        op,
        UnOp::Not
            | UnOp::IToBool
            | UnOp::INeg
            | UnOp::IAbs
            | UnOp::ISign
            | UnOp::BitNot
            | UnOp::IToF
            | UnOp::UToF
            | UnOp::HalfToF
    )
}

/// Whether a unary operation gives a float.
fn float_result(op: UnOp) -> bool {
    !matches!(
        op,
        UnOp::Not
            | UnOp::ToBool
            | UnOp::IToBool
            | UnOp::INeg
            | UnOp::IAbs
            | UnOp::ISign
            | UnOp::BitNot
            | UnOp::FToI
            | UnOp::FToU
            | UnOp::FToHalf
    )
}

/// Whether a unary operation on binary16 operands gives a binary16 value (no rounding needed).
fn exact_on_halves(op: UnOp) -> bool {
    matches!(
        op,
        UnOp::Mov
            | UnOp::Neg
            | UnOp::Abs
            | UnOp::Sign
            | UnOp::Floor
            | UnOp::Ceil
            | UnOp::Fract
            | UnOp::Trunc
            | UnOp::Round
            | UnOp::Half
            | UnOp::HalfTowardZero
    )
}

/// A value: its type and component registers.
#[derive(Clone, Debug)]
struct Value {
    ty: Type,
    regs: Vec<Reg>,
}

/// An assignable place: alternatives selected per lane by a condition (dynamic indexing).
#[derive(Clone, Debug)]
struct Place {
    ty: Type,
    alts: Vec<(Option<Reg>, Vec<Reg>)>,
}

#[derive(Clone, Debug)]
struct Symbol {
    ty: Type,
    regs: Vec<Reg>,
    writable: bool,
    /// The value of a `const` whose initializer is a constant expression.
    konst: Option<Vec<f32>>,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum ParamDir {
    In,
    Out,
    InOut,
}

struct Compiler<'a> {
    stage: Stage,
    lines: &'a LineMap,
    line: u32,
    code: Vec<Inst>,
    work: u32,
    bank: Vec<f32>,
    consts: HashMap<u32, Reg>,
    scopes: Vec<HashMap<String, Symbol>>,
    structs: Vec<HashMap<String, Arc<StructType>>>,
    functions: HashMap<String, Vec<&'a ast::FunctionDefinition>>,
    depth: usize,
    /// Return-value registers of the functions being inlined.
    returns: Vec<Option<Value>>,
    loops: usize,
    /// `switch` bodies being compiled (the scope of a `break` when no loop is nearer).
    switches: usize,
    uniforms: Vec<StageVar>,
    inputs: Vec<StageVar>,
    outputs: Vec<StageVar>,
    samplers: Vec<(usize, usize)>,
    position: Option<[Reg; 4]>,
    frag_coord: Option<[Reg; 4]>,
    point_size: Option<Reg>,
    point_coord: Option<[Reg; 2]>,
    front_facing: Option<Reg>,
    vertex_id: Option<Reg>,
    instance_id: Option<Reg>,
    blocks: Vec<String>,
    frag_color: Option<[Reg; 4]>,
    frag_data: Option<Vec<Reg>>,
    discards: bool,
    /// Global initialisers, run at the start of `main`.
    prologue: Vec<Inst>,
    /// Zeroing of lazily declared built-ins, run before the prologue.
    pending_front: Vec<Inst>,
    next_slot: Reg,
    /// Whether the code reads `gl_FragCoord` (which then needs a varying for `w`).
    reads_frag_coord: bool,
    /// Whether the code names `gl_PointSize` (vertex) or `gl_PointCoord` (fragment), which
    /// then need hidden varyings.
    names_point: bool,
    /// Instructions emitted so far.
    emitted: usize,
    /// The precision of registers that have one other than [`Prec::None`]: variables (their
    /// declared precision) and results of operations (see [`Prec`]).
    precision: HashMap<Reg, Prec>,
    /// Work registers known to hold binary16 values (results of lowered operations), which a
    /// lowered operation need not round again. Only registers written once are entered.
    halves: HashSet<Reg>,
    /// `mediump` variables whose current value was computed in single precision (by a
    /// `highp` operation, or one of [`Compiler::single`]), not written since.
    holds_single: HashSet<Reg>,
    /// `holds_single` as it was at the end of the block [`Compiler::block`] compiled last
    /// (a function body's, which an inlined call continues from).
    block_end_singles: HashSet<Reg>,
    /// `mediump` operations computed in single precision because none of their operands is a
    /// binary16 value (see [`Prec`]), with how to compute them in binary16 should a lowered
    /// operation take them as an operand.
    single: HashMap<Reg, Recipe>,
    /// Default precisions, one entry per scope (as `scopes`).
    defaults: Vec<Defaults>,
    /// The precision of each sampler slot's lookups.
    sampler_precision: HashMap<u16, Prec>,
    /// Register → its binary16 rounding computed earlier in the current straight run of code
    /// (a varying read by several `mediump` operations is rounded once). Emptied at block
    /// boundaries and when the register is written.
    rounded: HashMap<Reg, Reg>,
}

fn err<T>(line: u32, message: impl Into<String>) -> CResult<T> {
    Err((line, message.into()))
}

impl<'a> Compiler<'a> {
    fn new(stage: Stage, lines: &'a LineMap) -> Compiler<'a> {
        Compiler {
            stage,
            lines,
            line: 1,
            code: Vec::new(),
            work: 0,
            bank: Vec::new(),
            consts: HashMap::new(),
            scopes: vec![HashMap::new()],
            structs: vec![HashMap::new()],
            functions: HashMap::new(),
            depth: 0,
            returns: Vec::new(),
            loops: 0,
            switches: 0,
            uniforms: Vec::new(),
            inputs: Vec::new(),
            outputs: Vec::new(),
            samplers: Vec::new(),
            position: None,
            frag_coord: None,
            point_size: None,
            point_coord: None,
            front_facing: None,
            vertex_id: None,
            instance_id: None,
            blocks: Vec::new(),
            frag_color: None,
            frag_data: None,
            discards: false,
            prologue: Vec::new(),
            pending_front: Vec::new(),
            next_slot: 0,
            reads_frag_coord: false,
            names_point: false,
            emitted: 0,
            precision: HashMap::new(),
            halves: HashSet::new(),
            holds_single: HashSet::new(),
            block_end_singles: HashSet::new(),
            single: HashMap::new(),
            // GLSL ES: a vertex shader's floats and ints are highp unless declared otherwise;
            // a fragment shader has no default float precision (the source must give one;
            // tiler takes highp) and mediump ints; samplers are lowp in both.
            defaults: vec![match stage {
                Stage::Vertex => Defaults { float: Prec::High, int: Prec::High, sampler: Prec::Medium },
                Stage::Fragment => Defaults { float: Prec::High, int: Prec::Medium, sampler: Prec::Medium },
            }],
            sampler_precision: HashMap::new(),
            rounded: HashMap::new(),
        }
    }

    fn finish(self) -> StageCode {
        let mut colors = Vec::new();
        if let Some(c) = self.frag_color {
            colors.push((0, c));
        }
        if let Some(d) = &self.frag_data {
            for i in 0..MAX_DRAW_BUFFERS {
                colors.push((i, [d[4 * i], d[4 * i + 1], d[4 * i + 2], d[4 * i + 3]]));
            }
        }
        if self.stage == Stage::Fragment {
            let mut next = 0;
            for out in &self.outputs {
                let first = out.location.map_or(next, |l| l as usize);
                let n = out.regs.len() / 4;
                for k in 0..n {
                    let r = &out.regs[4 * k..4 * k + 4];
                    colors.push((first + k, [r[0], r[1], r[2], r[3]]));
                }
                next = first + n;
            }
            colors.retain(|(i, _)| *i < MAX_DRAW_BUFFERS);
        }
        // What the interface reads or fills stays in the work file (uniforms live in the
        // bank, or are sampler slots).
        let mut pinned: Vec<Reg> = Vec::new();
        for var in self.inputs.iter().chain(&self.outputs) {
            pinned.extend(&var.regs);
        }
        pinned.extend(self.position.iter().flatten());
        pinned.extend(self.frag_coord.iter().flatten());
        pinned.extend(self.point_size.filter(|_| self.names_point));
        pinned.extend(self.point_coord.iter().flatten());
        pinned.extend(self.front_facing);
        pinned.extend(self.vertex_id);
        pinned.extend(self.instance_id);
        for (_, c) in &colors {
            pinned.extend(c);
        }
        let mut code = self.code;
        let mut bank = self.bank;
        let constants = crate::fold::Constants::new(&mut bank, self.consts.values().copied());
        crate::fold::optimize(&mut code, self.work as usize, &mut { constants }, &pinned);
        let bank_program = crate::hoist::hoist(&mut code, self.work as usize, &mut bank, &pinned);
        crate::fuse::fuse(&mut code, self.work as usize, &pinned);
        crate::schedule::schedule(&mut code);
        StageCode {
            stage: self.stage,
            code,
            work_regs: self.work as usize,
            bank,
            bank_program,
            uniforms: self.uniforms,
            inputs: self.inputs,
            outputs: if self.stage == Stage::Vertex { self.outputs } else { Vec::new() },
            samplers: self.samplers,
            position: self.position,
            frag_coord: self.frag_coord.filter(|_| self.reads_frag_coord),
            point_size: self.point_size.filter(|_| self.names_point),
            point_coord: self.point_coord.filter(|_| self.names_point),
            front_facing: self.front_facing,
            vertex_id: self.vertex_id,
            instance_id: self.instance_id,
            blocks: self.blocks,
            colors,
            discards: self.discards,
        }
    }

    fn at(&mut self, span: &Option<NodeSpan>) {
        if let Some(span) = span {
            self.line = self.lines.line(u32::from(span.start().offset) as usize);
        }
    }

    fn fail<T>(&self, message: impl Into<String>) -> CResult<T> {
        err(self.line, message)
    }

    // ---- registers ----

    fn temp(&mut self) -> Reg {
        let r = self.work;
        self.work += 1;
        r
    }

    fn temps(&mut self, n: usize) -> Vec<Reg> {
        (0..n).map(|_| self.temp()).collect()
    }

    fn konst(&mut self, x: f32) -> Reg {
        if let Some(&r) = self.consts.get(&x.to_bits()) {
            return r;
        }
        let r = BANK | self.bank.len() as Reg;
        self.bank.push(x);
        self.consts.insert(x.to_bits(), r);
        r
    }

    /// An int constant (its bits; see `ir`).
    fn konst_int(&mut self, x: i32) -> Reg {
        self.konst(int(x))
    }

    fn emit(&mut self, mut inst: Inst) {
        self.emitted += 1;
        match &inst {
            // An inlined call ran its body once: what the body left holds after it.
            Inst::Call(_) => self.holds_single = std::mem::take(&mut self.block_end_singles),
            // After a branch or a loop, a variable written inside holds one of several values
            // (a phi in Mesa, of single precision).
            _ if !inst.is_straight_line() => {
                let mut written = Vec::new();
                written_within(&mut inst, &mut written);
                for r in written {
                    self.holds_single.remove(&r);
                }
            }
            Inst::Store(d, s) | Inst::Un(UnOp::Mov, d, s) => {
                if self.is_single(*s) {
                    self.holds_single.insert(*d);
                } else {
                    self.holds_single.remove(d);
                }
            }
            _ => crate::hoist::writes(&inst, &mut |r| {
                self.holds_single.remove(&r);
            }),
        }
        if !self.single.is_empty() {
            if !inst.is_straight_line() {
                self.single.clear();
            } else {
                crate::hoist::writes(&inst, &mut |w| self.single.retain(|&d, recipe| d != w && !recipe.reads(w)));
            }
        }
        if !self.rounded.is_empty() {
            if !inst.is_straight_line() {
                self.rounded.clear();
            }
            crate::hoist::writes(&inst, &mut |r| {
                self.rounded.remove(&r);
            });
        }
        self.code.push(inst);
    }

    /// Fails once the program outgrows [`MAX_INSTRUCTIONS`] or [`MAX_REGISTERS`] (inlining
    /// can grow code exponentially).
    fn check_budget(&self) -> CResult<()> {
        if self.emitted > MAX_INSTRUCTIONS || self.work as usize > MAX_REGISTERS || self.bank.len() > MAX_REGISTERS {
            return self.fail(format!(
                "the program is too large ({} instructions, {} registers; at most {MAX_INSTRUCTIONS} and {MAX_REGISTERS})",
                self.emitted,
                self.work as usize + self.bank.len()
            ));
        }
        Ok(())
    }

    fn un(&mut self, op: UnOp, a: Reg) -> Reg {
        let prec = self.prec(a);
        if let (UnOp::INeg, Some(x)) = (op, self.constant(a)) {
            // A negative int literal (`-2`) stays a constant (texel offsets must be).
            return self.konst_int((x.to_bits() as i32).wrapping_neg());
        }
        if op == UnOp::Mov {
            let d = self.temp();
            self.emit(Inst::Un(op, d, a));
            let half = self.halves.contains(&a);
            return self.lowered_result(d, prec, false, half);
        }
        let (float_in, float_out) = (float_operand(op), float_result(op));
        let lower = prec == Prec::Medium;
        if lower && float_in && float_out && !self.lowers(&[a]) {
            return self.single_precision(Recipe::Un(op, a), prec);
        }
        self.un_at(op, a, prec, lower)
    }

    /// [`Compiler::un`] with the lowering decided.
    fn un_at(&mut self, op: UnOp, a: Reg, prec: Prec, lower: bool) -> Reg {
        let (float_in, float_out) = (float_operand(op), float_result(op));
        let a = if lower && float_in { self.halved(a) } else { a };
        if lower && op == UnOp::InverseSqrt {
            // llvmpipe's binary16 `inversesqrt` is `1 / sqrt(x)`, both rounded (float-probe's
            // `ops.frag`: 63 of 63 texels; the correctly rounded one gave 48).
            let root = self.un_at(UnOp::Sqrt, a, prec, true);
            let one = self.konst(1.0);
            return self.bin_at(BinOp::Div, one, root, prec, true);
        }
        let d = self.temp();
        self.emit(Inst::Un(op, d, a));
        let exact = float_in && exact_on_halves(op);
        self.lowered_result(d, prec, lower && float_out && !exact, lower && float_out && exact)
    }

    fn bin(&mut self, op: BinOp, a: Reg, b: Reg) -> Reg {
        use BinOp as B;
        let prec = self.prec(a).max(self.prec(b));
        if let (Some(x), Some(y)) = (self.constant(a), self.constant(b)) {
            // Constants only (no precision): folded now, with the executor's arithmetic, as
            // `fold` would later; a variable initialised so is then seen to be a constant.
            return self.konst(crate::exec::binary(op, [x], [y])[0]);
        }
        let lower = prec == Prec::Medium
            && matches!(
                op,
                B::Add
                    | B::Sub
                    | B::Mul
                    | B::Div
                    | B::Mod
                    | B::Min
                    | B::Max
                    | B::Pow
                    | B::Atan2
                    | B::Step
                    | B::Lt
                    | B::Le
                    | B::Gt
                    | B::Ge
                    | B::Eq
                    | B::Ne
            );
        // `1.0 / x` is Mesa's `rcp(x)`: the constant is not an operand.
        let operands: &[Reg] = if op == B::Div && self.constant(a) == Some(1.0) { &[b] } else { &[a, b] };
        if lower && !self.lowers(operands) {
            return self.single_precision(Recipe::Bin(op, a, b), prec);
        }
        self.bin_at(op, a, b, prec, lower)
    }

    /// [`Compiler::bin`] with the lowering decided.
    fn bin_at(&mut self, op: BinOp, a: Reg, b: Reg, prec: Prec, lower: bool) -> Reg {
        use BinOp as B;
        let (a, b) = if lower { (self.halved(a), self.halved(b)) } else { (a, b) };
        if lower && op == B::Pow {
            // Mesa's `exp2(y · log2(x))`, each step rounded to binary16 (float-probe
            // `pow.frag`: 63 of 63 texels; rounding `pow` once gave 49).
            let log = self.un_at(UnOp::Log2, a, prec, true);
            let product = self.bin_at(B::Mul, b, log, prec, true);
            return self.un_at(UnOp::Exp2, product, prec, true);
        }
        let d = self.temp();
        self.emit(Inst::Bin(op, d, a, b));
        let float_out = !matches!(op, B::Lt | B::Le | B::Gt | B::Ge | B::Eq | B::Ne);
        let exact = matches!(op, B::Min | B::Max | B::Step);
        self.lowered_result(d, prec, lower && float_out && !exact, lower && float_out && exact)
    }

    fn tri(&mut self, op: TriOp, a: Reg, b: Reg, c: Reg) -> Reg {
        if op == TriOp::Select {
            // Picks one of two values (`?:`): lowered, it picks between their binary16
            // roundings (llvmpipe returns `c ? n : …` of a mediump `n = 1.0 / 7.0` as
            // 0.142822266).
            let prec = self.prec(b).max(self.prec(c));
            if prec == Prec::Medium && !self.lowers(&[b, c]) {
                return self.single_precision(Recipe::Tri(op, a, b, c), prec);
            }
            return self.tri_at(op, a, b, c, prec, prec == Prec::Medium);
        }
        let prec = self.prec(a).max(self.prec(b)).max(self.prec(c));
        let lower = prec == Prec::Medium;
        if lower && !self.lowers(&[a, b, c]) {
            return self.single_precision(Recipe::Tri(op, a, b, c), prec);
        }
        self.tri_at(op, a, b, c, prec, lower)
    }

    /// [`Compiler::tri`] with the lowering decided.
    fn tri_at(&mut self, op: TriOp, a: Reg, b: Reg, c: Reg, prec: Prec, lower: bool) -> Reg {
        if op == TriOp::Select {
            let (b, c) = if lower { (self.halved(b), self.halved(c)) } else { (b, c) };
            let d = self.temp();
            self.emit(Inst::Tri(op, d, a, b, c));
            return self.lowered_result(d, prec, false, lower);
        }
        let (a, b, c) = if lower { (self.halved(a), self.halved(b), self.halved(c)) } else { (a, b, c) };
        if lower && op == TriOp::Mix {
            // NIR's lowered `flrp`, every step rounded (float-probe `pow.frag`, 64 of 64
            // texels each): `x·(1 − t) + y·t` when `1 − t` folds to a constant, else
            // `x + t·(y − x)`.
            if self.constant(c).is_some() {
                let one = self.konst(1.0);
                let s = self.bin_at(BinOp::Sub, one, c, prec, true);
                let xs = self.bin_at(BinOp::Mul, a, s, prec, true);
                let yt = self.bin_at(BinOp::Mul, b, c, prec, true);
                return self.bin_at(BinOp::Add, xs, yt, prec, true);
            }
            let diff = self.bin_at(BinOp::Sub, b, a, prec, true);
            let step = self.bin_at(BinOp::Mul, c, diff, prec, true);
            return self.bin_at(BinOp::Add, a, step, prec, true);
        }
        let d = self.temp();
        self.emit(Inst::Tri(op, d, a, b, c));
        self.lowered_result(d, prec, lower, false)
    }

    /// Whether `r` holds a value computed in single precision: a `highp` result, one of
    /// [`Compiler::single`], or a variable last stored from one of those.
    fn is_single(&self, r: Reg) -> bool {
        self.prec(r) == Prec::High || self.single.contains_key(&r) || self.holds_single.contains(&r)
    }

    /// Whether a `mediump` operation on `operands` is lowered to binary16: unless every
    /// operand is a `mediump` variable holding a single-precision value (see [`Prec`]).
    fn lowers(&self, operands: &[Reg]) -> bool {
        operands.iter().any(|&r| self.single.contains_key(&r) || !self.holds_single.contains(&r))
    }

    /// A `mediump` operation none of whose operands is a binary16 value, computed in single
    /// precision (see [`Prec`]); [`Compiler::halved`] computes it in binary16 if a lowered
    /// operation takes it as an operand.
    fn single_precision(&mut self, recipe: Recipe, prec: Prec) -> Reg {
        let d = match &recipe {
            Recipe::Un(op, a) => self.un_at(*op, *a, prec, false),
            Recipe::Bin(op, a, b) => self.bin_at(*op, *a, *b, prec, false),
            Recipe::Tri(op, a, b, c) => self.tri_at(*op, *a, *b, *c, prec, false),
            Recipe::Dot(a, b) => self.dot_at(a, b, prec, false),
        };
        self.single.insert(d, recipe);
        d
    }

    /// The value of `r` if it is a compile-time constant of the bank.
    fn constant(&self, r: Reg) -> Option<f32> {
        if r & BANK == 0 {
            return None;
        }
        let value = self.bank[(r & !BANK) as usize];
        (self.consts.get(&value.to_bits()) == Some(&r)).then_some(value)
    }

    // ---- precision ----

    /// The precision of a register (see [`Prec`]).
    fn prec(&self, r: Reg) -> Prec {
        self.precision.get(&r).copied().unwrap_or_default()
    }

    /// Gives the registers of a declared variable (or parameter, or return value) its
    /// precision. They may be written again, so they are not known binary16 values.
    fn set_prec(&mut self, regs: &[Reg], prec: Prec) {
        for &r in regs {
            // A `mediump` variable given a single-precision value holds it (an assignment ends
            // Mesa's lowered tree) until written again.
            self.halves.remove(&r);
            let single = self.single.remove(&r).is_some() || self.prec(r) == Prec::High;
            if single && prec == Prec::Medium {
                self.holds_single.insert(r);
            } else {
                self.holds_single.remove(&r);
            }
            match prec {
                Prec::None => self.precision.remove(&r),
                p => self.precision.insert(r, p),
            };
        }
    }

    /// `r` as an operand of a lowered operation: rounded to binary16 (a constant at compile
    /// time), unless it already holds a binary16 value.
    fn halved(&mut self, r: Reg) -> Reg {
        if self.halves.contains(&r) {
            return r;
        }
        if r & BANK != 0 {
            let value = self.bank[(r & !BANK) as usize];
            if self.consts.get(&value.to_bits()) == Some(&r) {
                return self.konst(half::f16::from_f32(value).to_f32());
            }
        }
        if let Some(&d) = self.rounded.get(&r) {
            return d;
        }
        if let Some(recipe) = self.single.get(&r).cloned() {
            // Taken by a lowered operation: computed in binary16 after all.
            let prec = Prec::Medium;
            let d = match recipe {
                Recipe::Un(op, a) => self.un_at(op, a, prec, true),
                Recipe::Bin(op, a, b) => self.bin_at(op, a, b, prec, true),
                Recipe::Tri(op, a, b, c) => self.tri_at(op, a, b, c, prec, true),
                Recipe::Dot(a, b) => self.dot_at(&a, &b, prec, true),
            };
            let d = if self.halves.contains(&d) { d } else { self.halved_plain(d) };
            self.rounded.insert(r, d);
            return d;
        }
        self.halved_plain(r)
    }

    /// `r` rounded to binary16 by an instruction (shared within a straight run).
    fn halved_plain(&mut self, r: Reg) -> Reg {
        if let Some(&d) = self.rounded.get(&r) {
            return d;
        }
        let d = self.temp();
        self.emit(Inst::Un(UnOp::Half, d, r));
        self.halves.insert(d);
        self.rounded.insert(r, d);
        d
    }

    /// Records the precision of an operation's result `d`, rounding it to binary16 first when
    /// `round`; `half` says it is a binary16 value without rounding.
    fn lowered_result(&mut self, d: Reg, prec: Prec, round: bool, half: bool) -> Reg {
        let d = if round {
            let h = self.temp();
            self.emit(Inst::Un(UnOp::Half, h, d));
            self.halves.insert(h);
            h
        } else {
            if half {
                self.halves.insert(d);
            }
            d
        };
        if prec != Prec::None {
            self.precision.insert(d, prec);
        }
        d
    }

    /// The precision a declaration of type `ty` gets: the qualifier written, else the
    /// scope's default for the type (bools have none).
    fn declared_prec(&self, q: Option<&ast::TypeQualifier>, ty: &Type) -> Prec {
        if let Some(p) = written_prec(q) {
            return p;
        }
        let defaults = *self.defaults.last().expect("a scope");
        let mut ty = ty;
        while let Type::Array(t, _) = ty {
            ty = t;
        }
        match ty {
            Type::Sampler(_) => defaults.sampler,
            Type::Struct(_) => defaults.float,
            _ => match ty.scalar() {
                Some(Scalar::Float) => defaults.float,
                Some(Scalar::Int | Scalar::UInt) => defaults.int,
                _ => Prec::None,
            },
        }
    }

    /// Gives the variable just declared as `name` its precision: its registers', or for
    /// samplers their lookups'.
    fn declared(&mut self, name: &str, prec: Prec) {
        let Some(symbol) = self.lookup(name) else { return };
        let (ty, regs) = (symbol.ty.clone(), symbol.regs.clone());
        let mut base = &ty;
        while let Type::Array(t, _) = base {
            base = t;
        }
        match base {
            Type::Sampler(_) => {
                for r in regs {
                    self.sampler_precision.insert(r as u16, prec);
                }
            }
            // Samplers in a struct: their slots are not registers.
            _ if ty.contains_sampler() => {}
            _ => self.set_prec(&regs, prec),
        }
    }

    /// A `mediump` fragment input holds single-precision values, as a `mediump` variable
    /// assigned a `highp` expression does (see [`Prec`]): llvmpipe interpolates in single
    /// precision and Mesa's lowered operations take the input through a conversion it may
    /// drop. Measured (tools/float-probe/experiments `mediump-varyings.frag`): `v.x + v.y`,
    /// `v.x * v.y` and `sqrt(v.y)` single precision, `(v.x + v.y) + v.y` and `v.x - 0.1`
    /// binary16.
    fn input_declared(&mut self, name: &str, storage: Storage, prec: Prec) {
        let input = matches!(storage, Storage::Varying | Storage::In) && self.stage == Stage::Fragment;
        if !input || prec != Prec::Medium {
            return;
        }
        if let Some(symbol) = self.lookup(name) {
            let regs = symbol.regs.clone();
            self.holds_single.extend(regs);
        }
    }

    /// `precision q type;`: the default for the rest of the scope.
    fn default_precision(&mut self, q: &ast::PrecisionQualifier, spec: &ast::TypeSpecifier) {
        use ast::TypeSpecifierNonArrayData as T;
        let p = prec_of_qualifier(q);
        let defaults = self.defaults.last_mut().expect("a scope");
        match &spec.ty.content {
            T::Float => defaults.float = p,
            T::Int | T::UInt => defaults.int = p,
            _ => defaults.sampler = p,
        }
    }

    /// Runs `f` collecting what it emits into a separate block.
    fn block<T>(&mut self, f: impl FnOnce(&mut Self) -> CResult<T>) -> CResult<(T, Vec<Inst>)> {
        let saved = std::mem::take(&mut self.code);
        self.rounded.clear();
        self.single.clear();
        // Each block starts from what holds before it (the two branches of an `if` alike).
        let before = self.holds_single.clone();
        let result = f(self);
        self.block_end_singles = std::mem::replace(&mut self.holds_single, before);
        self.single.clear();
        self.rounded.clear();
        let code = std::mem::replace(&mut self.code, saved);
        Ok((result?, code))
    }

    // ---- scopes ----

    fn lookup(&self, name: &str) -> Option<&Symbol> {
        self.scopes.iter().rev().find_map(|s| s.get(name))
    }

    fn lookup_struct(&self, name: &str) -> Option<Arc<StructType>> {
        self.structs.iter().rev().find_map(|s| s.get(name)).cloned()
    }

    fn declare(&mut self, name: &str, symbol: Symbol) -> CResult<()> {
        if name.starts_with("gl_") {
            return self.fail(format!("'{name}': the gl_ prefix is reserved"));
        }
        let scope = self.scopes.last_mut().expect("a scope");
        if scope.contains_key(name) {
            return err(self.line, format!("'{name}' is already declared in this scope"));
        }
        scope.insert(name.to_string(), symbol);
        Ok(())
    }

    fn push_scope(&mut self) {
        self.scopes.push(HashMap::new());
        self.structs.push(HashMap::new());
        let inner = *self.defaults.last().expect("a scope");
        self.defaults.push(inner);
    }

    fn pop_scope(&mut self) {
        self.scopes.pop();
        self.structs.pop();
        self.defaults.pop();
    }

    // ---- types ----

    fn type_of(&mut self, spec: &ast::TypeSpecifier) -> CResult<Type> {
        use ast::TypeSpecifierNonArrayData as T;
        self.at(&spec.span);
        let base = match &spec.ty.content {
            T::Void => Type::Void,
            T::Bool => BOOL,
            T::Int => INT,
            T::Float => FLOAT,
            T::Vec2 => Type::vec(2),
            T::Vec3 => Type::vec(3),
            T::Vec4 => Type::vec(4),
            T::BVec2 => Type::Vector(Scalar::Bool, 2),
            T::BVec3 => Type::Vector(Scalar::Bool, 3),
            T::BVec4 => Type::Vector(Scalar::Bool, 4),
            T::IVec2 => Type::Vector(Scalar::Int, 2),
            T::IVec3 => Type::Vector(Scalar::Int, 3),
            T::IVec4 => Type::Vector(Scalar::Int, 4),
            T::UInt => UINT,
            T::UVec2 => Type::Vector(Scalar::UInt, 2),
            T::UVec3 => Type::Vector(Scalar::UInt, 3),
            T::UVec4 => Type::Vector(Scalar::UInt, 4),
            T::Mat2 | T::Mat22 => Type::Matrix(2, 2),
            T::Mat3 | T::Mat33 => Type::Matrix(3, 3),
            T::Mat4 | T::Mat44 => Type::Matrix(4, 4),
            T::Mat23 => Type::Matrix(2, 3),
            T::Mat24 => Type::Matrix(2, 4),
            T::Mat32 => Type::Matrix(3, 2),
            T::Mat34 => Type::Matrix(3, 4),
            T::Mat42 => Type::Matrix(4, 2),
            T::Mat43 => Type::Matrix(4, 3),
            T::Sampler2D => Type::Sampler(SamplerKind::Sampler2D),
            T::SamplerCube => Type::Sampler(SamplerKind::SamplerCube),
            T::Sampler2DShadow => Type::Sampler(SamplerKind::Sampler2DShadow),
            T::Sampler2DArray => Type::Sampler(SamplerKind::Sampler2DArray),
            T::Sampler3D => Type::Sampler(SamplerKind::Sampler3D),
            T::ISampler2D | T::USampler2D | T::ISampler2DArray | T::USampler2DArray | T::ISampler3D | T::USampler3D => {
                let shape = match &spec.ty.content {
                    T::ISampler2D | T::USampler2D => IntegerShape::Flat,
                    T::ISampler2DArray | T::USampler2DArray => IntegerShape::Array,
                    _ => IntegerShape::Volume,
                };
                let unsigned = matches!(&spec.ty.content, T::USampler2D | T::USampler2DArray | T::USampler3D);
                Type::Sampler(SamplerKind::Integer { shape, unsigned })
            }
            T::Struct(s) => Type::Struct(self.struct_type(s)?),
            T::TypeName(name) => match self.lookup_struct(name.as_str()) {
                Some(s) => Type::Struct(s),
                None => return self.fail(format!("unknown type '{}'", name.as_str())),
            },
            other => return self.fail(format!("type '{other:?}' is not supported")),
        };
        self.arrayed(base, spec.array_specifier.as_ref())
    }

    fn arrayed(&mut self, ty: Type, spec: Option<&ast::ArraySpecifier>) -> CResult<Type> {
        let Some(spec) = spec else { return Ok(ty) };
        let mut ty = ty;
        for dim in spec.dimensions.iter().rev() {
            match &dim.content {
                ast::ArraySpecifierDimensionData::Unsized => return self.fail("arrays need a constant size"),
                ast::ArraySpecifierDimensionData::ExplicitlySized(e) => {
                    let n = self.const_int(e).ok_or_else(|| (self.line, "array size is not a constant".to_string()))?;
                    if !(1..=4096).contains(&n) {
                        return self.fail(format!("array size {n} out of range 1..=4096"));
                    }
                    ty = Type::Array(Box::new(ty), n as usize);
                    if ty.size() > MAX_ARRAY_COMPONENTS {
                        return self.fail(format!("array of {} components, at most {MAX_ARRAY_COMPONENTS}", ty.size()));
                    }
                }
            }
        }
        Ok(ty)
    }

    fn struct_type(&mut self, s: &ast::StructSpecifier) -> CResult<Arc<StructType>> {
        let mut fields = Vec::new();
        for f in &s.fields {
            let ty = self.type_of(&f.ty)?;
            for id in &f.identifiers {
                let fty = self.arrayed(ty.clone(), id.array_spec.as_ref())?;
                fields.push((id.ident.as_str().to_string(), fty));
            }
        }
        let name = s.name.as_ref().map_or_else(|| "struct".to_string(), |n| n.as_str().to_string());
        let st = Arc::new(StructType { name: name.clone(), fields });
        if s.name.is_some() {
            self.structs.last_mut().expect("a scope").insert(name, st.clone());
        }
        Ok(st)
    }

    /// A constant integer expression (array sizes, constant indices).
    fn const_int(&self, e: &ast::Expr) -> Option<i64> {
        let v = self.const_eval(e)?;
        (v.len() == 1 && v[0].fract() == 0.0).then_some(v[0] as i64)
    }

    fn const_eval(&self, e: &ast::Expr) -> Option<Vec<f32>> {
        use ast::ExprData as E;
        match &e.content {
            E::IntConst(i) => Some(vec![*i as f32]),
            E::UIntConst(i) => Some(vec![*i as f32]),
            E::FloatConst(f) => Some(vec![*f]),
            E::BoolConst(b) => Some(vec![if *b { 1.0 } else { 0.0 }]),
            E::Variable(id) => self.lookup(id.as_str())?.konst.clone(),
            E::Unary(op, a) if matches!(op.content, ast::UnaryOpData::Minus) => {
                Some(self.const_eval(a)?.iter().map(|x| -x).collect())
            }
            E::Binary(op, a, b) => {
                let (a, b) = (self.const_eval(a)?, self.const_eval(b)?);
                if a.len() != 1 || b.len() != 1 {
                    return None;
                }
                let (x, y) = (a[0], b[0]);
                let is_int = x.fract() == 0.0 && y.fract() == 0.0;
                Some(vec![match op.content {
                    ast::BinaryOpData::Add => x + y,
                    ast::BinaryOpData::Sub => x - y,
                    ast::BinaryOpData::Mult => x * y,
                    ast::BinaryOpData::Div if is_int && y != 0.0 => (x / y).trunc(),
                    ast::BinaryOpData::Div => x / y,
                    _ => return None,
                }])
            }
            _ => None,
        }
    }

    // ---- declarations ----

    fn unit(&mut self, unit: &'a ast::TranslationUnit) -> CResult<()> {
        self.builtins();
        for decl in &unit.0 {
            if let ast::ExternalDeclarationData::FunctionDefinition(f) = &decl.content {
                self.functions.entry(f.prototype.name.as_str().to_string()).or_default().push(f);
            }
        }
        let mut main = None;
        for decl in &unit.0 {
            self.at(&decl.span);
            match &decl.content {
                ast::ExternalDeclarationData::Preprocessor(_) => {}
                ast::ExternalDeclarationData::Declaration(d) => {
                    let saved = std::mem::take(&mut self.code);
                    self.declaration(d, true)?;
                    let init = std::mem::replace(&mut self.code, saved);
                    self.prologue.extend(init);
                }
                ast::ExternalDeclarationData::FunctionDefinition(f) => {
                    if f.prototype.name.as_str() == "main" {
                        let void = |p: &ast::FunctionParameterDeclaration| {
                            matches!(&p.content, ast::FunctionParameterDeclarationData::Unnamed(_, t)
                                if t.ty.content == ast::TypeSpecifierNonArrayData::Void)
                        };
                        if !f.prototype.parameters.iter().all(void) {
                            return self.fail("main takes no parameters");
                        }
                        main = Some(f);
                    }
                }
            }
        }
        let Some(main) = main else { return self.fail("no main function") };
        self.code.clear();
        self.at(&main.span);
        self.returns.push(None);
        self.push_scope();
        let ((), body) = self.block(|c| c.statements(&main.statement.statement_list))?;
        self.pop_scope();
        self.returns.pop();
        let mut code = std::mem::take(&mut self.pending_front);
        code.append(&mut self.prologue);
        code.extend(body);
        self.code = code;
        Ok(())
    }

    /// Declares the built-in variables of the stage (zeroed at the start of `main`).
    fn builtins(&mut self) {
        let var = |c: &mut Self, name: &str, ty: Type, writable: bool| -> Vec<Reg> {
            let regs = c.temps(ty.size());
            for &r in &regs {
                let zero = c.konst(0.0);
                c.prologue.push(Inst::Un(UnOp::Mov, r, zero));
            }
            c.scopes[0].insert(name.to_string(), Symbol { ty, regs: regs.clone(), writable, konst: None });
            regs
        };
        let four = |r: Vec<Reg>| [r[0], r[1], r[2], r[3]];
        match self.stage {
            Stage::Vertex => {
                self.position = Some(four(var(self, "gl_Position", Type::vec(4), true)));
                self.point_size = Some(var(self, "gl_PointSize", FLOAT, true)[0]);
                // Inputs filled by the caller: declared directly, not zeroed.
                let input = |c: &mut Self, name: &str| {
                    let r = c.temp();
                    c.scopes[0].insert(name.into(), Symbol { ty: INT, regs: vec![r], writable: false, konst: None });
                    Some(r)
                };
                self.vertex_id = input(self, "gl_VertexID");
                self.instance_id = input(self, "gl_InstanceID");
            }
            Stage::Fragment => {
                // Inputs are filled by the caller, so they are not zeroed: declare them
                // directly.
                let coord = self.temps(4);
                self.scopes[0].insert(
                    "gl_FragCoord".into(),
                    Symbol { ty: Type::vec(4), regs: coord.clone(), writable: false, konst: None },
                );
                // Mesa declares gl_FragCoord highp (ES 1.00 says mediump).
                self.set_prec(&coord, Prec::High);
                self.frag_coord = Some(four(coord));
                let facing = self.temp();
                self.scopes[0].insert(
                    "gl_FrontFacing".into(),
                    Symbol { ty: BOOL, regs: vec![facing], writable: false, konst: None },
                );
                self.front_facing = Some(facing);
                // Filled by the caller from hidden varyings when read (see `names_point`).
                let coord = self.temps(2);
                self.scopes[0].insert(
                    "gl_PointCoord".into(),
                    Symbol { ty: Type::vec(2), regs: coord.clone(), writable: false, konst: None },
                );
                self.set_prec(&coord, Prec::Medium);
                self.point_coord = Some([coord[0], coord[1]]);
                self.frag_color = Some(four(var(self, "gl_FragColor", Type::vec(4), true)));
            }
        }
        let consts: [(&str, f32); 8] = [
            ("gl_MaxVertexAttribs", tiler::MAX_VERTEX_ATTRIBUTES as f32),
            ("gl_MaxVertexUniformVectors", 256.0),
            ("gl_MaxVaryingVectors", (tiler::MAX_VARYINGS / 4) as f32),
            ("gl_MaxVertexTextureImageUnits", 16.0),
            ("gl_MaxCombinedTextureImageUnits", 32.0),
            ("gl_MaxTextureImageUnits", 16.0),
            ("gl_MaxFragmentUniformVectors", 256.0),
            ("gl_MaxDrawBuffers", MAX_DRAW_BUFFERS as f32),
        ];
        for (name, v) in consts {
            let r = self.konst_int(v as i32);
            self.scopes[0]
                .insert(name.into(), Symbol { ty: INT, regs: vec![r], writable: false, konst: Some(vec![v]) });
        }
    }

    /// `gl_FragData` is declared on first use, so that shaders writing `gl_FragColor` do not
    /// write the other attachments.
    fn frag_data(&mut self) -> Symbol {
        if self.frag_data.is_none() {
            let regs = self.temps(4 * MAX_DRAW_BUFFERS);
            let zero = self.konst(0.0);
            // Zeroed before `main` runs, wherever the first use is.
            let zeroing = regs.iter().map(|&r| Inst::Un(UnOp::Mov, r, zero));
            self.pending_front.extend(zeroing);
            self.frag_data = Some(regs);
        }
        let regs = self.frag_data.clone().expect("declared");
        Symbol { ty: Type::Array(Box::new(Type::vec(4)), MAX_DRAW_BUFFERS), regs, writable: true, konst: None }
    }

    fn declaration(&mut self, d: &ast::Declaration, global: bool) -> CResult<()> {
        self.at(&d.span);
        match &d.content {
            ast::DeclarationData::FunctionPrototype(_) => Ok(()),
            ast::DeclarationData::Precision(q, spec) => {
                self.default_precision(q, spec);
                Ok(())
            }
            ast::DeclarationData::Invariant(_) => Ok(()),
            ast::DeclarationData::TypeOnly(_) => Ok(()),
            ast::DeclarationData::Block(b) => self.uniform_block(b),
            ast::DeclarationData::InitDeclaratorList(list) => {
                let head = &list.head;
                let base = self.type_of(&head.ty.ty)?;
                let storage = match (storage_of(head.ty.qualifier.as_ref()), self.stage) {
                    (Storage::In, Stage::Vertex) => Storage::Attribute,
                    (Storage::In, Stage::Fragment) => Storage::Varying,
                    (Storage::Out, Stage::Vertex) => Storage::Varying,
                    (Storage::Out, Stage::Fragment) => Storage::FragOut,
                    (s, _) => s,
                };
                let flat = is_flat(head.ty.qualifier.as_ref());
                if flat && storage != Storage::Varying {
                    // GLSL ES 3.00 §4.3.9: interpolation qualifiers only on vertex outputs and
                    // fragment inputs.
                    return self.fail("'flat' qualifies only vertex shader outputs and fragment shader inputs");
                }
                let location = location_of(head.ty.qualifier.as_ref(), self);
                // A `const` is a constant: neutral, as Mesa propagates it.
                let prec = match storage {
                    Storage::Const => Prec::None,
                    _ => self.declared_prec(head.ty.qualifier.as_ref(), &base),
                };
                let var = VarDecl { storage, location, flat, global, prec };
                if let Some(name) = &head.name {
                    let ty = self.arrayed(base.clone(), head.array_specifier.as_ref())?;
                    self.variable(name.as_str(), ty, var, head.initializer.as_ref())?;
                    self.declared(name.as_str(), prec);
                    self.input_declared(name.as_str(), storage, prec);
                }
                for tail in &list.tail {
                    self.at(&tail.span);
                    let ty = self.arrayed(base.clone(), tail.ident.array_spec.as_ref())?;
                    let var = VarDecl { location: None, ..var };
                    self.variable(tail.ident.ident.as_str(), ty, var, tail.initializer.as_ref())?;
                    self.declared(tail.ident.ident.as_str(), prec);
                    self.input_declared(tail.ident.ident.as_str(), storage, prec);
                }
                Ok(())
            }
        }
    }

    fn variable(&mut self, name: &str, ty: Type, var: VarDecl, init: Option<&ast::Initializer>) -> CResult<()> {
        let VarDecl { storage, location, flat, global, prec } = var;
        if ty == Type::Void {
            return self.fail(format!("'{name}' declared void"));
        }
        if ty.contains_sampler() && storage != Storage::Uniform {
            return self.fail(format!("sampler '{name}' must be a uniform"));
        }
        let stage = self.stage;
        let interface = |c: &Self, what: &str| -> CResult<()> {
            if !global {
                return c.fail(format!("{what} '{name}' must be declared at global scope"));
            }
            if init.is_some() {
                return c.fail(format!("{what} '{name}' cannot have an initializer"));
            }
            Ok(())
        };
        match storage {
            Storage::Uniform => {
                interface(self, "uniform")?;
                let regs = self.uniform_regs(&ty);
                let index = self.uniforms.len();
                self.uniforms.push(StageVar {
                    name: name.into(),
                    ty: ty.clone(),
                    regs: regs.clone(),
                    location,
                    flat: false,
                });
                for (k, &r) in regs.iter().enumerate() {
                    if r & BANK == 0 {
                        // A sampler component: its "register" is its slot.
                        debug_assert_eq!(r as usize, self.samplers.len());
                        self.samplers.push((index, k));
                    }
                }
                self.declare(name, Symbol { ty, regs, writable: false, konst: None })
            }
            Storage::Attribute if stage == Stage::Vertex => {
                interface(self, "attribute")?;
                // GLSL ES 3.00 §4.3.4: `int`/`uint` scalars and vectors too (their registers get
                // the bits `glVertexAttribIPointer` fetches).
                let integer = ty.scalar().is_some_and(Scalar::is_integer) && ty.width().is_some();
                if !(ty.is_float_based() || integer) || matches!(ty, Type::Array(..)) {
                    return self
                        .fail(format!("attribute '{name}' must be a float, vector or matrix, or an integer vector"));
                }
                let regs = self.temps(ty.size());
                self.inputs.push(StageVar {
                    name: name.into(),
                    ty: ty.clone(),
                    regs: regs.clone(),
                    location,
                    flat: false,
                });
                self.declare(name, Symbol { ty, regs, writable: false, konst: None })
            }
            Storage::Attribute => self.fail(format!("attribute '{name}' in a fragment shader")),
            Storage::Varying => {
                interface(self, "varying")?;
                let element = match &ty {
                    Type::Array(t, _) => t,
                    t => t,
                };
                let integer = element.scalar().is_some_and(Scalar::is_integer) && element.width().is_some();
                if integer && !flat {
                    // GLSL ES 3.00 §4.3.4, §4.3.6: integer vertex outputs and fragment inputs
                    // must be qualified flat.
                    return self.fail(format!("integer varying '{name}' ({ty}) must be qualified 'flat'"));
                }
                // GLSL ES 3.00 §4.3.4: a vertex output or fragment input may also be a structure
                // of those (GTK 4's renderer passes its rounded rectangles so); its members are
                // interpolated one float after another, as an array's elements are.
                if let Type::Struct(_) = element {
                    if let Some(bad) = varying_struct_error(element, flat) {
                        return self.fail(format!("varying '{name}': {bad}"));
                    }
                } else if !(ty.is_float_based() || integer) {
                    return self.fail(format!("varying '{name}' must be float-based or integer, not {ty}"));
                }
                let regs = self.temps(ty.size());
                let var = StageVar { name: name.into(), ty: ty.clone(), regs: regs.clone(), location, flat };
                let writable = stage == Stage::Vertex;
                if writable {
                    let zero = self.konst(0.0);
                    for &r in &regs {
                        self.emit(Inst::Un(UnOp::Mov, r, zero));
                    }
                    self.outputs.push(var);
                } else {
                    self.inputs.push(var);
                }
                self.declare(name, Symbol { ty, regs, writable, konst: None })
            }
            Storage::FragOut => {
                interface(self, "output")?;
                // An `ivec4`/`uvec4` output's registers hold its integers' bits, which an integer
                // attachment stores as they are (`tiler::IntFormat`).
                let four = |t: &Type| matches!(t, Type::Vector(Scalar::Float | Scalar::Int | Scalar::UInt, 4));
                if !four(&ty) && !matches!(&ty, Type::Array(t, _) if four(t)) {
                    return self.fail(format!(
                        "fragment output '{name}' must be a vec4, ivec4 or uvec4 (or an array of them)"
                    ));
                }
                let regs = self.temps(ty.size());
                let zero = self.konst(0.0);
                for &r in &regs {
                    self.emit(Inst::Un(UnOp::Mov, r, zero));
                }
                self.outputs.push(StageVar {
                    name: name.into(),
                    ty: ty.clone(),
                    regs: regs.clone(),
                    location,
                    flat: false,
                });
                self.declare(name, Symbol { ty, regs, writable: true, konst: None })
            }
            Storage::In | Storage::Out => self.fail(format!("'{name}': in/out at global scope resolve per stage")),
            Storage::Const | Storage::Local => {
                let is_const = storage == Storage::Const;
                let (regs, konst) = match init {
                    Some(init) => {
                        let konst = match &init.content {
                            ast::InitializerData::Simple(e) if is_const => self.const_eval(e),
                            _ => None,
                        };
                        let start = self.work;
                        let v = self.initializer(init, &ty)?;
                        // Registers the initializer just computed (each written in every
                        // lane, read by nothing else) become the variable's; anything else
                        // (another variable, a constant, a repeated register) is copied.
                        let fresh = v
                            .regs
                            .iter()
                            .enumerate()
                            .all(|(i, &r)| r & BANK == 0 && r >= start && !v.regs[..i].contains(&r));
                        let regs = if fresh && !ty.contains_sampler() {
                            v.regs
                        } else {
                            let regs = self.temps(ty.size());
                            // A `mediump` float initialised with a constant holds it in
                            // binary16: llvmpipe reads `mediump float n = 1.0 / 7.0` back as
                            // 0.142822266 even where only single precision uses it.
                            let round = !is_const && prec == Prec::Medium && ty.scalar() == Some(Scalar::Float);
                            for (&d, &s) in regs.iter().zip(&v.regs) {
                                let s = match self.constant(s) {
                                    Some(x) if round => self.konst(crate::exec::round_half(x)),
                                    _ => s,
                                };
                                self.emit(Inst::Un(UnOp::Mov, d, s));
                            }
                            regs
                        };
                        (regs, konst.filter(|k| k.len() == ty.size()))
                    }
                    None if is_const => return self.fail(format!("const '{name}' needs an initializer")),
                    None => {
                        let regs = self.temps(ty.size());
                        let zero = self.konst(0.0);
                        for &r in &regs {
                            self.emit(Inst::Un(UnOp::Mov, r, zero));
                        }
                        (regs, None)
                    }
                };
                self.declare(name, Symbol { ty, regs, writable: !is_const, konst })
            }
        }
    }

    /// `uniform Name { … } [instance];` (ES 3.00): a uniform of a struct type named after the
    /// block, its members visible directly (or through the instance name). Its values come
    /// from a buffer in the `std140` layout (`std140.rs`), which `shared`, the default, is
    /// taken to be (Mesa lays `shared` blocks out so).
    fn uniform_block(&mut self, b: &ast::Block) -> CResult<()> {
        if storage_of(Some(&b.qualifier)) != Storage::Uniform {
            return self.fail("only uniform blocks are supported (in/out blocks are not GLSL ES 3.00)");
        }
        let name = b.name.as_str();
        self.block_layout(Some(&b.qualifier), name)?;
        let mut fields = Vec::new();
        for f in &b.fields {
            self.at(&f.span);
            self.block_layout(f.qualifier.as_ref(), name)?;
            let ty = self.type_of(&f.ty)?;
            for id in &f.identifiers {
                let fty = self.arrayed(ty.clone(), id.array_spec.as_ref())?;
                if fty.contains_sampler() {
                    return self.fail(format!("uniform block '{name}' holds a sampler, which blocks cannot"));
                }
                fields.push((id.ident.as_str().to_string(), fty));
            }
        }
        if b.identifier.as_ref().is_some_and(|i| i.array_spec.is_some()) {
            return self.fail(format!("arrays of uniform blocks ('{name}') are not supported"));
        }
        if self.uniforms.iter().any(|u| u.name == name) {
            return self.fail(format!("'{name}' is declared twice"));
        }
        let block = Arc::new(StructType { name: name.to_string(), fields });
        let ty = Type::Struct(block.clone());
        let regs = self.uniform_regs(&ty);
        self.uniforms.push(StageVar {
            name: name.into(),
            ty: ty.clone(),
            regs: regs.clone(),
            location: None,
            flat: false,
        });
        self.blocks.push(name.to_string());
        match &b.identifier {
            Some(instance) => self.declare(instance.ident.as_str(), Symbol { ty, regs, writable: false, konst: None }),
            None => {
                let mut at = 0;
                for (field, fty) in &block.fields {
                    let n = fty.size();
                    let symbol =
                        Symbol { ty: fty.clone(), regs: regs[at..at + n].to_vec(), writable: false, konst: None };
                    self.declare(field, symbol)?;
                    at += n;
                }
                Ok(())
            }
        }
    }

    /// Checks a uniform block's (or member's) layout qualifiers: `std140`, `shared` and
    /// `column_major` are what tiler reads; `packed` and `row_major` are refused.
    fn block_layout(&mut self, q: Option<&ast::TypeQualifier>, block: &str) -> CResult<()> {
        for spec in q.iter().flat_map(|q| &q.qualifiers) {
            if let ast::TypeQualifierSpecData::Layout(l) = &spec.content {
                for id in &l.ids {
                    match &id.content {
                        ast::LayoutQualifierSpecData::Shared => {}
                        ast::LayoutQualifierSpecData::Identifier(n, None)
                            if matches!(n.as_str(), "std140" | "column_major") => {}
                        ast::LayoutQualifierSpecData::Identifier(n, _) => {
                            return self.fail(format!(
                                "uniform block '{block}': layout '{}' is not supported (std140, shared and \
                                 column_major are)",
                                n.as_str()
                            ));
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// Bank registers for a uniform's components; sampler components get slots instead.
    fn uniform_regs(&mut self, ty: &Type) -> Vec<Reg> {
        match ty {
            Type::Sampler(_) => {
                let slot = self.next_slot;
                self.next_slot += 1;
                vec![slot]
            }
            Type::Array(t, n) => (0..*n).flat_map(|_| self.uniform_regs(t)).collect(),
            Type::Struct(s) => s.fields.clone().iter().flat_map(|(_, t)| self.uniform_regs(t)).collect(),
            _ => (0..ty.size())
                .map(|_| {
                    let r = BANK | self.bank.len() as Reg;
                    self.bank.push(0.0);
                    r
                })
                .collect(),
        }
    }

    fn initializer(&mut self, init: &ast::Initializer, ty: &Type) -> CResult<Value> {
        self.at(&init.span);
        match &init.content {
            ast::InitializerData::Simple(e) => {
                let v = self.expr(e)?;
                self.convert(v, ty)
            }
            ast::InitializerData::List(_) => self.fail("initializer lists are not GLSL ES"),
        }
    }

    /// `v` as type `ty`: equal types, or an int or uint promoted to float.
    fn convert(&mut self, v: Value, ty: &Type) -> CResult<Value> {
        if v.ty == *ty {
            return Ok(v);
        }
        if v.ty.scalar().is_some_and(Scalar::is_integer)
            && ty.scalar() == Some(Scalar::Float)
            && v.ty.width().is_some()
            && v.ty.width() == ty.width()
        {
            return Ok(self.floated(v));
        }
        self.fail(format!("cannot convert {} to {ty}", v.ty))
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Storage {
    Local,
    Const,
    Uniform,
    Attribute,
    Varying,
    FragOut,
    In,
    Out,
}

fn storage_of(q: Option<&ast::TypeQualifier>) -> Storage {
    let Some(q) = q else { return Storage::Local };
    let mut storage = Storage::Local;
    for spec in &q.qualifiers {
        if let ast::TypeQualifierSpecData::Storage(s) = &spec.content {
            storage = match s.content {
                ast::StorageQualifierData::Const => Storage::Const,
                ast::StorageQualifierData::Uniform => Storage::Uniform,
                ast::StorageQualifierData::Attribute => Storage::Attribute,
                ast::StorageQualifierData::Varying => Storage::Varying,
                // ES 3.00 `in`/`out`: resolved per stage by the caller.
                ast::StorageQualifierData::In => Storage::In,
                ast::StorageQualifierData::Out => Storage::Out,
                _ => storage,
            };
        }
    }
    storage
}

/// How a global or local variable is declared, besides its name and type.
#[derive(Clone, Copy)]
struct VarDecl {
    storage: Storage,
    location: Option<u32>,
    flat: bool,
    global: bool,
    /// The declared precision (see [`Prec`]).
    prec: Prec,
}

/// Whether a declaration is qualified `flat` (ES 3.00).
fn is_flat(q: Option<&ast::TypeQualifier>) -> bool {
    q.is_some_and(|q| {
        q.qualifiers.iter().any(|spec| {
            matches!(&spec.content, ast::TypeQualifierSpecData::Interpolation(i)
                if i.content == ast::InterpolationQualifierData::Flat)
        })
    })
}

fn location_of(q: Option<&ast::TypeQualifier>, c: &Compiler) -> Option<u32> {
    let q = q?;
    for spec in &q.qualifiers {
        if let ast::TypeQualifierSpecData::Layout(l) = &spec.content {
            for id in &l.ids {
                if let ast::LayoutQualifierSpecData::Identifier(name, Some(e)) = &id.content
                    && name.as_str() == "location"
                {
                    return c.const_int(e).and_then(|v| u32::try_from(v).ok());
                }
            }
        }
    }
    None
}

// ---- statements ----

impl<'a> Compiler<'a> {
    fn statements(&mut self, list: &[ast::Statement]) -> CResult<()> {
        list.iter().try_for_each(|s| self.statement(s))
    }

    fn scoped(&mut self, s: &ast::Statement) -> CResult<Vec<Inst>> {
        self.push_scope();
        let result = self.block(|c| c.statement(s));
        self.pop_scope();
        Ok(result?.1)
    }

    fn statement(&mut self, s: &ast::Statement) -> CResult<()> {
        use ast::StatementData as S;
        self.at(&s.span);
        self.check_budget()?;
        match &s.content {
            S::Declaration(d) => self.declaration(d, false),
            S::Expression(e) => {
                if let Some(e) = &e.0 {
                    self.expr(e)?;
                }
                Ok(())
            }
            S::Selection(sel) => {
                let cond = self.bool_expr(&sel.cond)?;
                let (then, els) = match &sel.rest.content {
                    ast::SelectionRestStatementData::Statement(t) => (self.scoped(t)?, Vec::new()),
                    ast::SelectionRestStatementData::Else(t, e) => (self.scoped(t)?, self.scoped(e)?),
                };
                self.emit(Inst::If(cond, then, els));
                Ok(())
            }
            S::Switch(sw) => self.switch(sw),
            S::CaseLabel(_) => self.fail("a case label outside a switch body"),
            S::Iteration(it) => self.iteration(it),
            S::Jump(j) => self.jump(j),
            S::Compound(c) => {
                self.push_scope();
                let result = self.statements(&c.statement_list);
                self.pop_scope();
                result
            }
        }
    }

    /// A `switch` (ES 3.00) under lane masks: the selector is compared with every label,
    /// and each run of statements after a group of labels runs in the lanes that have
    /// `entered` the switch there or at an earlier group (fall-through); `default` enters
    /// the lanes no label matches. `break` leaves the [`Inst::Breakable`] that holds the
    /// body. Checked as GLSL requires: a scalar `int`/`uint` selector, constant labels of
    /// its type, no label twice, at most one `default`, no statement before the first label.
    fn switch(&mut self, sw: &ast::SwitchStatement) -> CResult<()> {
        let selector = self.expr(&sw.head)?;
        if selector.ty != INT && selector.ty != UINT {
            return self.fail(format!("a switch selector must be a scalar int or uint, not {}", selector.ty));
        }
        let (selector, selector_ty) = (selector.regs[0], selector.ty);
        // (labels, whether `default` is among them, statements), in order.
        struct Group<'s> {
            labels: Vec<i64>,
            default: bool,
            statements: Vec<&'s ast::Statement>,
        }
        let mut groups: Vec<Group> = Vec::new();
        let mut seen: Vec<i64> = Vec::new();
        let mut has_default = false;
        for st in &sw.body {
            let ast::StatementData::CaseLabel(label) = &st.content else {
                self.at(&st.span);
                match groups.last_mut() {
                    Some(g) => g.statements.push(st),
                    None => return self.fail("a statement before the first case label of a switch"),
                }
                continue;
            };
            self.at(&st.span);
            if groups.last().is_none_or(|g| !g.statements.is_empty()) {
                groups.push(Group { labels: Vec::new(), default: false, statements: Vec::new() });
            }
            let group = groups.last_mut().expect("a group was just pushed");
            match &label.content {
                ast::CaseLabelData::Def => {
                    if has_default {
                        return self.fail("a switch has two default labels");
                    }
                    has_default = true;
                    group.default = true;
                }
                ast::CaseLabelData::Case(e) => {
                    let ty = self.expr(e)?.ty;
                    let value = self.const_int(e).filter(|_| ty == selector_ty);
                    let Some(value) = value else {
                        return self.fail(format!(
                            "a case label must be a constant {selector_ty} expression (the selector's type)"
                        ));
                    };
                    if seen.contains(&value) {
                        return self.fail(format!("case label {value} appears twice in a switch"));
                    }
                    seen.push(value);
                    group.labels.push(value);
                }
            }
        }
        let matches = |c: &mut Self, labels: &[i64]| -> Option<Reg> {
            labels.iter().fold(None, |acc, &l| {
                let k = c.konst_int(l as i32);
                let eq = c.bin(BinOp::IEq, selector, k);
                Some(match acc {
                    Some(a) => c.bin(BinOp::Or, a, eq),
                    None => eq,
                })
            })
        };
        let no_label = if has_default {
            let all: Vec<i64> = groups.iter().flat_map(|g| g.labels.iter().copied()).collect();
            let any = matches(self, &all);
            Some(match any {
                Some(a) => self.un(UnOp::Not, a),
                None => self.konst(1.0),
            })
        } else {
            None
        };
        let entered = self.temp();
        let zero = self.konst(0.0);
        self.emit(Inst::Store(entered, zero));
        self.switches += 1;
        self.push_scope();
        let body = self.block(|c| {
            for g in &groups {
                let mut cond = matches(c, &g.labels);
                if g.default {
                    let d = no_label.expect("a default label was seen");
                    cond = Some(match cond {
                        Some(a) => c.bin(BinOp::Or, a, d),
                        None => d,
                    });
                }
                if let Some(cond) = cond {
                    let now = c.bin(BinOp::Or, entered, cond);
                    c.emit(Inst::Store(entered, now));
                }
                let ((), then) = c.block(|c| g.statements.iter().try_for_each(|st| c.statement(st)))?;
                c.emit(Inst::If(entered, then, Vec::new()));
            }
            Ok(())
        });
        self.pop_scope();
        self.switches -= 1;
        let ((), body) = body?;
        self.emit(Inst::Breakable(body));
        Ok(())
    }

    fn condition(&mut self, cond: &ast::Condition) -> CResult<Reg> {
        match &cond.content {
            ast::ConditionData::Expr(e) => self.bool_expr(e),
            ast::ConditionData::Assignment(..) => self.fail("declarations in loop conditions are not supported"),
        }
    }

    fn loop_body(&mut self, body: &ast::Statement) -> CResult<Vec<Inst>> {
        self.loops += 1;
        let result = self.scoped(body);
        self.loops -= 1;
        result
    }

    fn iteration(&mut self, it: &ast::IterationStatement) -> CResult<()> {
        use ast::IterationStatementData as I;
        self.push_scope();
        let result = (|| {
            let inst = match &it.content {
                I::While(cond, body) => {
                    let (cond, cond_code) = self.block(|c| c.condition(cond))?;
                    let body = self.loop_body(body)?;
                    Inst::Loop { cond_code, cond: Some(cond), body, step: Vec::new(), test_first: true }
                }
                I::DoWhile(body, cond) => {
                    let body = self.loop_body(body)?;
                    let (cond, cond_code) = self.block(|c| c.bool_expr(cond))?;
                    Inst::Loop { cond_code, cond: Some(cond), body, step: Vec::new(), test_first: false }
                }
                I::For(init, rest, body) => {
                    match &init.content {
                        ast::ForInitStatementData::Expression(Some(e)) => {
                            self.expr(e)?;
                        }
                        ast::ForInitStatementData::Expression(None) => {}
                        ast::ForInitStatementData::Declaration(d) => self.declaration(d, false)?,
                    }
                    let (cond, cond_code) = match &rest.condition {
                        Some(cond) => {
                            let (r, code) = self.block(|c| c.condition(cond))?;
                            (Some(r), code)
                        }
                        None => (None, Vec::new()),
                    };
                    let body = self.loop_body(body)?;
                    let ((), step) = self.block(|c| match &rest.post_expr {
                        Some(e) => c.expr(e).map(|_| ()),
                        None => Ok(()),
                    })?;
                    Inst::Loop { cond_code, cond, body, step, test_first: true }
                }
            };
            self.emit(inst);
            Ok(())
        })();
        self.pop_scope();
        result
    }

    fn jump(&mut self, j: &ast::JumpStatement) -> CResult<()> {
        match &j.content {
            ast::JumpStatementData::Continue if self.loops == 0 => self.fail("continue outside a loop"),
            ast::JumpStatementData::Break if self.loops == 0 && self.switches == 0 => {
                self.fail("break outside a loop or switch")
            }
            ast::JumpStatementData::Break => {
                self.emit(Inst::Break);
                Ok(())
            }
            ast::JumpStatementData::Continue => {
                self.emit(Inst::Continue);
                Ok(())
            }
            ast::JumpStatementData::Discard => {
                if self.stage != Stage::Fragment {
                    return self.fail("discard outside a fragment shader");
                }
                self.discards = true;
                self.emit(Inst::Discard);
                Ok(())
            }
            ast::JumpStatementData::Return(e) => {
                let target = self.returns.last().cloned().flatten();
                match (target, e) {
                    (None, None) => {}
                    (None, Some(_)) => return self.fail("a void function returns a value"),
                    (Some(t), None) => {
                        return self.fail(format!("return without a value in a function returning {}", t.ty));
                    }
                    (Some(t), Some(e)) => {
                        let v = self.expr(e)?;
                        let v = self.convert(v, &t.ty)?;
                        for (&d, &s) in t.regs.iter().zip(&v.regs) {
                            self.emit(Inst::Store(d, s));
                        }
                    }
                }
                self.emit(Inst::Return);
                Ok(())
            }
        }
    }

    fn bool_expr(&mut self, e: &ast::Expr) -> CResult<Reg> {
        let v = self.expr(e)?;
        if v.ty != BOOL {
            return self.fail(format!("condition must be a bool, not {}", v.ty));
        }
        Ok(v.regs[0])
    }
}

// ---- expressions ----

/// The component index of a swizzle letter.
fn swizzle_index(ch: char) -> Option<usize> {
    ["xyzw", "rgba", "stpq"].iter().find_map(|set| set.find(ch))
}

impl<'a> Compiler<'a> {
    fn expr(&mut self, e: &ast::Expr) -> CResult<Value> {
        use ast::ExprData as E;
        self.at(&e.span);
        match &e.content {
            E::Variable(_) | E::Dot(..) | E::Bracket(..) => {
                let (place, _) = self.place(e)?;
                Ok(self.read(&place))
            }
            E::IntConst(i) => Ok(Value { ty: INT, regs: vec![self.konst_int(*i)] }),
            E::UIntConst(i) => Ok(Value { ty: UINT, regs: vec![self.konst(uint(*i))] }),
            E::BoolConst(b) => Ok(Value { ty: BOOL, regs: vec![self.konst(if *b { 1.0 } else { 0.0 })] }),
            E::FloatConst(f) => Ok(Value { ty: FLOAT, regs: vec![self.konst(*f)] }),
            E::DoubleConst(f) => Ok(Value { ty: FLOAT, regs: vec![self.konst(*f as f32)] }),
            E::Unary(op, a) => self.unary(op, a),
            E::Binary(op, a, b) => {
                let (va, vb) = (self.expr(a)?, self.expr(b)?);
                self.at(&e.span);
                self.binary(&op.content, va, vb)
            }
            E::Ternary(c, a, b) => {
                let c = self.bool_expr(c)?;
                let (va, vb) = (self.expr(a)?, self.expr(b)?);
                let (va, vb) = self.promote(va, vb);
                if va.ty != vb.ty || va.ty.contains_sampler() {
                    return self.fail(format!("?: branches differ: {} and {}", va.ty, vb.ty));
                }
                let regs = va.regs.iter().zip(&vb.regs).map(|(&x, &y)| self.tri(TriOp::Select, c, x, y)).collect();
                Ok(Value { ty: va.ty, regs })
            }
            E::Assignment(l, op, r) => {
                let (place, writable) = self.place(l)?;
                if !writable {
                    return self.fail("assignment to a read-only value");
                }
                let mut v = self.expr(r)?;
                self.at(&e.span);
                if let Some(bop) = assign_op(&op.content) {
                    let current = self.read(&place);
                    v = self.binary(&bop, current, v)?;
                }
                let v = self.convert(v, &place.ty)?;
                self.write(&place, &v);
                Ok(v)
            }
            E::FunCall(f, args) => self.call(f, args),
            E::PostInc(a) | E::PostDec(a) => {
                let inc = matches!(e.content, E::PostInc(_));
                let (place, writable) = self.place(a)?;
                if !writable || !place.ty.is_numeric_scalar_or_vector() && !matches!(place.ty, Type::Matrix(..)) {
                    return self.fail("++/-- needs a writable number");
                }
                let old = self.read(&place);
                let copy: Vec<Reg> = old.regs.iter().map(|&r| self.un(UnOp::Mov, r)).collect();
                let (one, op) = self.step_one(&old.ty, inc);
                let new: Vec<Reg> = copy.iter().map(|&r| self.bin(op, r, one)).collect();
                self.write(&place, &Value { ty: old.ty.clone(), regs: new });
                Ok(Value { ty: old.ty, regs: copy })
            }
            E::Comma(a, b) => {
                self.expr(a)?;
                self.expr(b)
            }
        }
    }

    fn unary(&mut self, op: &ast::UnaryOp, a: &ast::Expr) -> CResult<Value> {
        use ast::UnaryOpData as U;
        match op.content {
            U::Inc | U::Dec => {
                let (place, writable) = self.place(a)?;
                if !writable || !place.ty.is_numeric_scalar_or_vector() && !matches!(place.ty, Type::Matrix(..)) {
                    return self.fail("++/-- needs a writable number");
                }
                let old = self.read(&place);
                let (one, op) = self.step_one(&old.ty, op.content == U::Inc);
                let new = Value { ty: old.ty.clone(), regs: old.regs.iter().map(|&r| self.bin(op, r, one)).collect() };
                self.write(&place, &new);
                Ok(new)
            }
            U::Add => {
                let v = self.expr(a)?;
                if !v.ty.is_numeric_scalar_or_vector() && !matches!(v.ty, Type::Matrix(..)) {
                    return self.fail(format!("unary + on {}", v.ty));
                }
                Ok(v)
            }
            U::Minus => {
                let v = self.expr(a)?;
                if !v.ty.is_numeric_scalar_or_vector() && !matches!(v.ty, Type::Matrix(..)) {
                    return self.fail(format!("unary - on {}", v.ty));
                }
                let neg = if v.ty.scalar().is_some_and(Scalar::is_integer) { UnOp::INeg } else { UnOp::Neg };
                Ok(Value { ty: v.ty.clone(), regs: v.regs.iter().map(|&r| self.un(neg, r)).collect() })
            }
            U::Not => {
                let v = self.expr(a)?;
                if v.ty != BOOL {
                    return self.fail(format!("! on {}", v.ty));
                }
                Ok(Value { ty: BOOL, regs: vec![self.un(UnOp::Not, v.regs[0])] })
            }
            U::Complement => {
                let v = self.expr(a)?;
                if !v.ty.scalar().is_some_and(Scalar::is_integer) || v.ty.width().is_none() {
                    return self.fail(format!("~ takes an integer scalar or vector, not {}", v.ty));
                }
                Ok(Value { ty: v.ty.clone(), regs: v.regs.iter().map(|&r| self.un(UnOp::BitNot, r)).collect() })
            }
        }
    }

    /// The constant 1 of `ty`'s kind and the add or subtract that steps by it (`++`/`--`).
    fn step_one(&mut self, ty: &Type, inc: bool) -> (Reg, BinOp) {
        if ty.scalar().is_some_and(Scalar::is_integer) {
            (self.konst_int(1), if inc { BinOp::IAdd } else { BinOp::ISub })
        } else {
            (self.konst(1.0), if inc { BinOp::Add } else { BinOp::Sub })
        }
    }

    /// An int or uint scalar or vector converted to float, component by component (ints
    /// beside floats are promoted, as desktop GLSL allows); other values unchanged.
    fn floated(&mut self, v: Value) -> Value {
        match v.ty.scalar() {
            Some(from @ (Scalar::Int | Scalar::UInt)) if v.ty.width().is_some() => {
                let regs = v.regs.iter().map(|&r| self.convert_component(r, from, Scalar::Float)).collect();
                Value { ty: v.ty.with_scalar(Scalar::Float), regs }
            }
            _ => v,
        }
    }

    /// Ints beside floats become floats.
    fn promote(&mut self, a: Value, b: Value) -> (Value, Value) {
        match (a.ty.scalar(), b.ty.scalar()) {
            (Some(Scalar::Int | Scalar::UInt), Some(Scalar::Float)) => (self.floated(a), b),
            (Some(Scalar::Float), Some(Scalar::Int | Scalar::UInt)) => (a, self.floated(b)),
            _ => (a, b),
        }
    }

    /// A float comparison's counterpart on scalar kind `s` (ints and uints compare as
    /// integers; equality of any integer compares bits).
    fn compare_op(op: BinOp, s: Option<Scalar>) -> BinOp {
        match (s, op) {
            (Some(Scalar::Int), BinOp::Lt) => BinOp::ILt,
            (Some(Scalar::Int), BinOp::Le) => BinOp::ILe,
            (Some(Scalar::Int), BinOp::Gt) => BinOp::IGt,
            (Some(Scalar::Int), BinOp::Ge) => BinOp::IGe,
            (Some(Scalar::UInt), BinOp::Lt) => BinOp::ULt,
            (Some(Scalar::UInt), BinOp::Le) => BinOp::ULe,
            (Some(Scalar::UInt), BinOp::Gt) => BinOp::UGt,
            (Some(Scalar::UInt), BinOp::Ge) => BinOp::UGe,
            (Some(Scalar::Int | Scalar::UInt), BinOp::Eq) => BinOp::IEq,
            (Some(Scalar::Int | Scalar::UInt), BinOp::Ne) => BinOp::INe,
            _ => op,
        }
    }

    /// `&`, `|`, `^`, `<<`, `>>` (ES 3.00) on int or uint scalars and vectors; a scalar
    /// operand beside a vector is applied to each component. The operands of `&`, `|` and
    /// `^` share a kind; a shift takes its left operand's type, and a count of either kind.
    fn bit_op(&mut self, op: &ast::BinaryOpData, a: Value, b: Value) -> CResult<Value> {
        use ast::BinaryOpData as B;
        let (sa, sb) = (a.ty.scalar(), b.ty.scalar());
        let integer = |s: Option<Scalar>| s.is_some_and(Scalar::is_integer);
        let shift = matches!(op, B::LShift | B::RShift);
        let (wa, wb) = (a.ty.width(), b.ty.width());
        let ok = integer(sa)
            && integer(sb)
            && wa.is_some()
            && wb.is_some()
            && (shift || sa == sb)
            && (wa == wb || wb == Some(1) || (!shift && wa == Some(1)));
        if !ok {
            return self.fail(format!("bit operation on {} and {}", a.ty, b.ty));
        }
        let bop = match op {
            B::BitAnd => BinOp::BitAnd,
            B::BitOr => BinOp::BitOr,
            B::BitXor => BinOp::BitXor,
            B::LShift => BinOp::Shl,
            _ if sa == Some(Scalar::Int) => BinOp::IShr,
            _ => BinOp::UShr,
        };
        let ty = if wa == Some(1) { b.ty.with_scalar(sa.expect("checked")) } else { a.ty.clone() };
        let at = |v: &Value, i: usize| if v.regs.len() == 1 { v.regs[0] } else { v.regs[i] };
        let regs = (0..ty.size()).map(|i| self.bin(bop, at(&a, i), at(&b, i))).collect();
        Ok(Value { ty, regs })
    }

    fn binary(&mut self, op: &ast::BinaryOpData, a: Value, b: Value) -> CResult<Value> {
        use ast::BinaryOpData as B;
        let (a, b) = self.promote(a, b);
        match op {
            B::Or | B::Xor | B::And => {
                if a.ty != BOOL || b.ty != BOOL {
                    return self.fail(format!("logical operator on {} and {}", a.ty, b.ty));
                }
                let op = match op {
                    B::Or => BinOp::Or,
                    B::Xor => BinOp::Xor,
                    _ => BinOp::And,
                };
                Ok(Value { ty: BOOL, regs: vec![self.bin(op, a.regs[0], b.regs[0])] })
            }
            B::Equal | B::NonEqual => {
                if a.ty != b.ty || a.ty.contains_sampler() || a.ty.size() == 0 {
                    return self.fail(format!("cannot compare {} with {}", a.ty, b.ty));
                }
                let eq = op == &B::Equal;
                let cmp = if eq { BinOp::Eq } else { BinOp::Ne };
                let join = if eq { BinOp::And } else { BinOp::Or };
                // Struct and array members each compare by their own kind.
                let kinds = scalar_kinds(&a.ty);
                let parts: Vec<Reg> = a
                    .regs
                    .iter()
                    .zip(&b.regs)
                    .zip(kinds)
                    .map(|((&x, &y), s)| self.bin(Self::compare_op(cmp, Some(s)), x, y))
                    .collect();
                let r = parts[1..].iter().fold(parts[0], |acc, &p| self.bin(join, acc, p));
                Ok(Value { ty: BOOL, regs: vec![r] })
            }
            B::Lt | B::Gt | B::Lte | B::Gte => {
                if a.ty != b.ty || !matches!(a.ty, Type::Scalar(Scalar::Float | Scalar::Int | Scalar::UInt)) {
                    return self.fail(format!("relational operator on {} and {}", a.ty, b.ty));
                }
                let op = match op {
                    B::Lt => BinOp::Lt,
                    B::Gt => BinOp::Gt,
                    B::Lte => BinOp::Le,
                    _ => BinOp::Ge,
                };
                let op = Self::compare_op(op, a.ty.scalar());
                Ok(Value { ty: BOOL, regs: vec![self.bin(op, a.regs[0], b.regs[0])] })
            }
            B::Add | B::Sub | B::Mult | B::Div => self.arith(op, a, b),
            B::Mod if a.ty.scalar().is_some_and(Scalar::is_integer) => self.arith(op, a, b),
            B::Mod => self.fail(format!("% takes integers (ES 3.00), not {} and {}; use mod()", a.ty, b.ty)),
            B::BitOr | B::BitXor | B::BitAnd | B::LShift | B::RShift => self.bit_op(op, a, b),
        }
    }

    fn arith(&mut self, op: &ast::BinaryOpData, a: Value, b: Value) -> CResult<Value> {
        use ast::BinaryOpData as B;
        let bad = |c: &Self| c.fail(format!("arithmetic on {} and {}", a.ty, b.ty));
        if a.ty.scalar().is_none() || b.ty.scalar().is_none() || a.ty.scalar() != b.ty.scalar() {
            return bad(self);
        }
        if a.ty.scalar() == Some(Scalar::Bool) {
            return bad(self);
        }
        if *op == B::Mult {
            match (&a.ty, &b.ty) {
                // ES 3.00 §5.9: a C×R matrix takes C-vectors and matrices of C rows on its
                // right, gives R-vectors; an R-vector times it gives a C-vector.
                (Type::Matrix(c, r), Type::Matrix(c2, r2)) if c == r2 => {
                    return Ok(self.mat_mul(*c, *r, *c2, &a.regs, &b.regs));
                }
                (Type::Matrix(c, r), Type::Vector(Scalar::Float, n)) if c == n => {
                    return Ok(Value { ty: Type::vec(*r), regs: self.mat_vec(*c, *r, &a.regs, &b.regs) });
                }
                (Type::Vector(Scalar::Float, n), Type::Matrix(c, r)) if r == n => {
                    let (c, r) = (*c, *r);
                    let regs = (0..c).map(|k| self.dot(&a.regs, &b.regs[k * r..k * r + r])).collect();
                    return Ok(Value { ty: Type::vec(c), regs });
                }
                (Type::Matrix(..), Type::Matrix(..) | Type::Vector(..)) | (Type::Vector(..), Type::Matrix(..)) => {
                    return self.fail(format!("{} * {}: the shapes do not match", a.ty, b.ty));
                }
                _ => {}
            }
        }
        let bop = match (a.ty.scalar(), op) {
            (Some(Scalar::Float), B::Add) => BinOp::Add,
            (Some(Scalar::Float), B::Sub) => BinOp::Sub,
            (Some(Scalar::Float), B::Mult) => BinOp::Mul,
            (Some(Scalar::Float), _) => BinOp::Div,
            (_, B::Add) => BinOp::IAdd,
            (_, B::Sub) => BinOp::ISub,
            (_, B::Mult) => BinOp::IMul,
            (Some(Scalar::Int), B::Mod) => BinOp::IRem,
            (Some(Scalar::Int), _) => BinOp::IDiv,
            (_, B::Mod) => BinOp::URem,
            _ => BinOp::UDiv,
        };
        let ty = match (&a.ty, &b.ty) {
            (x, y) if x == y => x.clone(),
            (Type::Scalar(_), y) => y.clone(),
            (x, Type::Scalar(_)) => x.clone(),
            _ => return bad(self),
        };
        let n = ty.size();
        let at = |v: &Value, i: usize| if v.regs.len() == 1 { v.regs[0] } else { v.regs[i] };
        let regs = (0..n).map(|i| self.bin(bop, at(&a, i), at(&b, i))).collect();
        Ok(Value { ty, regs })
    }

    /// The determinant of a square matrix given by rows, by cofactor expansion along the
    /// first row.
    fn determinant(&mut self, rows: &[Vec<Reg>]) -> Reg {
        let n = rows.len();
        if n == 1 {
            return rows[0][0];
        }
        if n == 2 {
            let a = self.bin(BinOp::Mul, rows[0][0], rows[1][1]);
            let b = self.bin(BinOp::Mul, rows[0][1], rows[1][0]);
            return self.bin(BinOp::Sub, a, b);
        }
        let mut acc = None;
        for j in 0..n {
            let minor: Vec<Vec<Reg>> = rows[1..]
                .iter()
                .map(|row| row.iter().enumerate().filter(|(k, _)| *k != j).map(|(_, &r)| r).collect())
                .collect();
            let d = self.determinant(&minor);
            let term = self.bin(BinOp::Mul, rows[0][j], d);
            acc = Some(match acc {
                None => term,
                Some(a) if j % 2 == 1 => self.bin(BinOp::Sub, a, term),
                Some(a) => self.bin(BinOp::Add, a, term),
            });
        }
        acc.expect("n > 2")
    }

    /// `Σ a[i]·b[i]`, in order. Lowered to binary16 (see [`Prec`]), it is Mesa's chain of
    /// multiply-adds from the last component, every product and sum rounded:
    /// `a₀b₀ + (a₁b₁ + a₂b₂)`. Measured on llvmpipe (tools/float-probe's `dot.frag`, 64 rows
    /// of texels): `dot(v, v)` of a `vec3` and `vec2` to the bit, and `dot((1, e, e, 0),
    /// (1, 1, 1, 1))` with `e = 3·2⁻¹¹` gives `1 + 6·2⁻¹¹` (rounding from the first component
    /// would give `1 + 8·2⁻¹¹`). Not modelled: NIR also factors `a·b + a·c` into `a·(b + c)`
    /// when two terms share an operand (`dot((a, b), (c, a))`).
    fn dot(&mut self, a: &[Reg], b: &[Reg]) -> Reg {
        let prec = a.iter().chain(b).map(|&r| self.prec(r)).max().unwrap_or_default();
        if prec == Prec::Medium {
            let operands: Vec<Reg> = a.iter().chain(b).copied().collect();
            if !self.lowers(&operands) {
                return self.single_precision(Recipe::Dot(a.to_vec(), b.to_vec()), prec);
            }
        }
        self.dot_at(a, b, prec, prec == Prec::Medium)
    }

    /// [`Compiler::dot`] with the lowering decided.
    fn dot_at(&mut self, a: &[Reg], b: &[Reg], prec: Prec, lower: bool) -> Reg {
        if !lower {
            let raw = |c: &mut Self, op, x, y| {
                let d = c.temp();
                c.emit(Inst::Bin(op, d, x, y));
                d
            };
            if prec == Prec::Medium {
                // Single precision throughout, every product and sum.
                let mut acc = raw(self, BinOp::Mul, a[0], b[0]);
                for i in 1..a.len() {
                    let p = raw(self, BinOp::Mul, a[i], b[i]);
                    acc = raw(self, BinOp::Add, acc, p);
                }
                return self.lowered_result(acc, prec, false, false);
            }
            // From the last component, unfused, as in binary16: llvmpipe's single-precision
            // `dot` of a `vec3` is `a₀b₀ + (a₁b₁ + a₂b₂)` (float-probe `highp-normalize.frag`:
            // 512 of 512 values with `normalize` below; 349 summed from the first).
            let last = a.len() - 1;
            let mut acc = self.bin(BinOp::Mul, a[last], b[last]);
            for i in (0..last).rev() {
                let p = self.bin(BinOp::Mul, a[i], b[i]);
                acc = self.bin(BinOp::Add, p, acc);
            }
            return acc;
        }
        // NIR's chain `fma(a₀, b₀, fma(a₁, b₁, a₂·b₂))`, factored as its inexact rules do
        // (`fma(x, y, x·z)` → `x·(y + z)`, `fma(x, y, fma(x, z, w))` → `fma(x, y + z, w)`),
        // then each fma computed as a rounded product and a rounded sum (measured unfused).
        let last = a.len() - 1;
        let mut chain = DotChain::Mul(DotTerm::Reg(a[last]), DotTerm::Reg(b[last]), None);
        for i in (0..last).rev() {
            let (x, y) = (a[i], b[i]);
            chain = match chain {
                DotChain::Mul(p, q, rest) => {
                    // In the order NIR's search tries the commutative operands: the outer
                    // fma's swapped before the inner product's (float-probe `ops.frag`,
                    // `dot((a, b, a), (b, a, b))` is `a·3b`, not `b·3a`).
                    let sum = |other: Reg, rest: &DotTerm| {
                        DotTerm::Add(Box::new(DotTerm::Reg(other)), Box::new(rest.clone()))
                    };
                    let common = if self.same_value(&p, x) {
                        Some((p.clone(), sum(y, &q)))
                    } else if self.same_value(&p, y) {
                        Some((p.clone(), sum(x, &q)))
                    } else if self.same_value(&q, x) {
                        Some((q.clone(), sum(y, &p)))
                    } else if self.same_value(&q, y) {
                        Some((q.clone(), sum(x, &p)))
                    } else {
                        None
                    };
                    match common {
                        Some((factor, sum)) => DotChain::Mul(factor, sum, rest),
                        None => {
                            DotChain::Mul(DotTerm::Reg(x), DotTerm::Reg(y), Some(Box::new(DotChain::Mul(p, q, rest))))
                        }
                    }
                }
            };
        }
        self.dot_chain(chain, prec)
    }

    /// Whether a factor of a lowered `dot` is the same value as `r`: the same register, or
    /// constants of equal value.
    fn same_value(&self, term: &DotTerm, r: Reg) -> bool {
        match term {
            DotTerm::Reg(t) => {
                *t == r
                    || matches!((self.constant(*t), self.constant(r)), (Some(x), Some(y)) if x.to_bits() == y.to_bits())
            }
            DotTerm::Add(..) => false,
        }
    }

    /// Emits a factored `dot` chain in binary16, every operation rounded.
    fn dot_chain(&mut self, chain: DotChain, prec: Prec) -> Reg {
        let DotChain::Mul(p, q, rest) = chain;
        let (p, q) = (self.dot_term(p, prec), self.dot_term(q, prec));
        let product = self.bin_at(BinOp::Mul, p, q, prec, true);
        match rest {
            None => product,
            Some(rest) => {
                let rest = self.dot_chain(*rest, prec);
                self.bin_at(BinOp::Add, product, rest, prec, true)
            }
        }
    }

    fn dot_term(&mut self, term: DotTerm, prec: Prec) -> Reg {
        match term {
            DotTerm::Reg(r) => r,
            DotTerm::Add(b, c) => {
                let (b, c) = (self.dot_term(*b, prec), self.dot_term(*c, prec));
                self.bin_at(BinOp::Add, b, c, prec, true)
            }
        }
    }

    /// `M · v` for a column-major matrix of `columns` columns of `rows` components: row r is
    /// `Σ_c m[c][r]·v[c]`, summed over c in order.
    fn mat_vec(&mut self, columns: usize, rows: usize, m: &[Reg], v: &[Reg]) -> Vec<Reg> {
        (0..rows)
            .map(|r| {
                let mut acc = self.bin(BinOp::Mul, m[r], v[0]);
                for c in 1..columns {
                    let p = self.bin(BinOp::Mul, m[c * rows + r], v[c]);
                    acc = self.bin(BinOp::Add, acc, p);
                }
                acc
            })
            .collect()
    }

    /// `A · B` for A of `columns` × `rows` and B of `b_columns` columns of `columns` rows.
    fn mat_mul(&mut self, columns: usize, rows: usize, b_columns: usize, a: &[Reg], b: &[Reg]) -> Value {
        let mut regs = Vec::with_capacity(b_columns * rows);
        for c in 0..b_columns {
            regs.extend(self.mat_vec(columns, rows, a, &b[c * columns..c * columns + columns]));
        }
        Value { ty: Type::Matrix(b_columns, rows), regs }
    }

    // ---- places ----

    /// An lvalue-like view of an expression, and whether it may be written.
    fn place(&mut self, e: &ast::Expr) -> CResult<(Place, bool)> {
        use ast::ExprData as E;
        self.at(&e.span);
        match &e.content {
            E::Variable(id) => {
                let name = id.as_str();
                self.reads_frag_coord |= name == "gl_FragCoord";
                self.names_point |= name == "gl_PointSize" || name == "gl_PointCoord";
                let symbol = if name == "gl_FragData" && self.stage == Stage::Fragment {
                    self.frag_data()
                } else {
                    match self.lookup(name) {
                        Some(s) => s.clone(),
                        None => return self.fail(format!("'{name}' is not declared")),
                    }
                };
                Ok((Place { ty: symbol.ty, alts: vec![(None, symbol.regs)] }, symbol.writable))
            }
            E::Dot(a, field) => {
                let (place, writable) = self.place(a)?;
                self.at(&e.span);
                let field = field.as_str();
                match &place.ty {
                    Type::Struct(s) => {
                        let mut offset = 0;
                        for (name, ty) in &s.fields {
                            if name == field {
                                let n = ty.size();
                                let alts =
                                    place.alts.iter().map(|(c, r)| (*c, r[offset..offset + n].to_vec())).collect();
                                return Ok((Place { ty: ty.clone(), alts }, writable));
                            }
                            offset += ty.size();
                        }
                        self.fail(format!("struct {} has no field '{field}'", s.name))
                    }
                    Type::Scalar(s) | Type::Vector(s, _) => {
                        let width = place.ty.width().expect("vector");
                        let idx: Option<Vec<usize>> = field.chars().map(swizzle_index).collect();
                        let idx = match idx {
                            Some(idx) if (1..=4).contains(&idx.len()) && idx.iter().all(|&i| i < width) => idx,
                            _ => return self.fail(format!("bad swizzle '.{field}' on {}", place.ty)),
                        };
                        let repeats = (1..idx.len()).any(|i| idx[..i].contains(&idx[i]));
                        let ty = Type::vector(*s, idx.len());
                        let alts = place.alts.iter().map(|(c, r)| (*c, idx.iter().map(|&i| r[i]).collect())).collect();
                        Ok((Place { ty, alts }, writable && !repeats))
                    }
                    other => self.fail(format!("'.{field}' on {other}")),
                }
            }
            E::Bracket(a, index) => {
                let (place, writable) = self.place(a)?;
                self.at(&e.span);
                let (elem, n) = match &place.ty {
                    Type::Array(t, n) => ((**t).clone(), *n),
                    Type::Vector(s, n) => (Type::Scalar(*s), *n),
                    Type::Matrix(c, r) => (Type::vec(*r), *c),
                    other => return self.fail(format!("indexing a {other}")),
                };
                let size = elem.size();
                if let Some(k) = self.const_int(index) {
                    if k < 0 || k as usize >= n {
                        return self.fail(format!("index {k} out of range for {}", place.ty));
                    }
                    let k = k as usize;
                    let alts = place.alts.iter().map(|(c, r)| (*c, r[k * size..(k + 1) * size].to_vec())).collect();
                    return Ok((Place { ty: elem, alts }, writable));
                }
                if elem.contains_sampler() {
                    return self.fail("samplers can only be indexed by constants");
                }
                let i = self.expr(index)?;
                if i.ty != INT && i.ty != UINT {
                    return self.fail(format!("index must be an int or uint, not {}", i.ty));
                }
                let mut alts = Vec::new();
                for (c, r) in &place.alts {
                    for k in 0..n {
                        let kr = self.konst_int(k as i32);
                        let eq = self.bin(BinOp::IEq, i.regs[0], kr);
                        let cond = match c {
                            Some(c) => self.bin(BinOp::And, *c, eq),
                            None => eq,
                        };
                        alts.push((Some(cond), r[k * size..(k + 1) * size].to_vec()));
                    }
                }
                Ok((Place { ty: elem, alts }, writable))
            }
            _ => {
                let v = self.expr(e)?;
                Ok((Place { ty: v.ty, alts: vec![(None, v.regs)] }, false))
            }
        }
    }

    fn read(&mut self, place: &Place) -> Value {
        let (last_cond, last) = place.alts.last().expect("a place has an alternative");
        if place.alts.len() == 1 && last_cond.is_none() {
            return Value { ty: place.ty.clone(), regs: last.clone() };
        }
        if place.ty.contains_sampler() {
            return Value { ty: place.ty.clone(), regs: last.clone() };
        }
        let mut regs = last.clone();
        for (cond, alt) in place.alts[..place.alts.len() - 1].iter().rev() {
            let cond = cond.expect("dynamic alternatives have conditions");
            regs = alt.iter().zip(&regs).map(|(&a, &acc)| self.tri(TriOp::Select, cond, a, acc)).collect();
        }
        Value { ty: place.ty.clone(), regs }
    }

    fn write(&mut self, place: &Place, v: &Value) {
        let aliased = place.alts.iter().any(|(_, r)| r.iter().any(|x| v.regs.contains(x)));
        let src: Vec<Reg> =
            if aliased { v.regs.iter().map(|&r| self.un(UnOp::Mov, r)).collect() } else { v.regs.clone() };
        for (cond, regs) in &place.alts {
            for (&d, &s) in regs.iter().zip(&src) {
                self.emit(match cond {
                    None => Inst::Store(d, s),
                    Some(c) => Inst::StoreIf(d, s, *c),
                });
            }
        }
    }
}

fn assign_op(op: &ast::AssignmentOpData) -> Option<ast::BinaryOpData> {
    use ast::AssignmentOpData as A;
    use ast::BinaryOpData as B;
    Some(match op {
        A::Equal => return None,
        A::Mult => B::Mult,
        A::Div => B::Div,
        A::Mod => B::Mod,
        A::Add => B::Add,
        A::Sub => B::Sub,
        A::LShift => B::LShift,
        A::RShift => B::RShift,
        A::And => B::BitAnd,
        A::Xor => B::BitXor,
        A::Or => B::BitOr,
    })
}

// ---- calls ----

impl<'a> Compiler<'a> {
    fn call(&mut self, f: &ast::FunIdentifier, args: &[ast::Expr]) -> CResult<Value> {
        let line = self.line;
        let name = match &f.content {
            ast::FunIdentifierData::TypeSpecifier(spec) => {
                if let ast::TypeSpecifierNonArrayData::TypeName(n) = &spec.ty.content
                    && spec.array_specifier.is_none()
                    && self.functions.contains_key(n.as_str())
                {
                    n.as_str().to_string()
                } else {
                    let ty = self.type_of(spec)?;
                    let values = self.args(args)?;
                    self.line = line;
                    return self.construct(ty, values);
                }
            }
            ast::FunIdentifierData::Expr(e) => match &e.content {
                ast::ExprData::Variable(id) => id.as_str().to_string(),
                _ => return self.fail("only named functions can be called"),
            },
        };
        if let Some(s) = self.lookup_struct(&name) {
            let values = self.args(args)?;
            self.line = line;
            return self.construct(Type::Struct(s), values);
        }
        if let Some(defs) = self.functions.get(&name).cloned() {
            let mut places = Vec::new();
            for a in args {
                places.push(self.place(a)?);
            }
            self.line = line;
            return self.inline(&name, &defs, places);
        }
        let values = self.args(args)?;
        self.line = line;
        self.builtin(&name, values)
    }

    fn args(&mut self, args: &[ast::Expr]) -> CResult<Vec<Value>> {
        args.iter()
            .filter(|a| !matches!(&a.content, ast::ExprData::Variable(id) if id.as_str() == "void"))
            .map(|a| self.expr(a))
            .collect()
    }

    fn inline(&mut self, name: &str, defs: &[&'a ast::FunctionDefinition], args: Vec<(Place, bool)>) -> CResult<Value> {
        if self.depth >= MAX_CALL_DEPTH {
            return self.fail(format!("calls nest deeper than {MAX_CALL_DEPTH} at '{name}' (recursion?)"));
        }
        // Functions see the globals only.
        let saved_scopes = self.scopes.split_off(1);
        let saved_structs = self.structs.split_off(1);
        let saved_defaults = self.defaults.split_off(1);
        let saved_loops = std::mem::take(&mut self.loops);
        let saved_switches = std::mem::take(&mut self.switches);
        let line = self.line;
        self.depth += 1;
        let result = self.inline_in_globals(name, defs, args);
        self.depth -= 1;
        self.line = line;
        self.loops = saved_loops;
        self.switches = saved_switches;
        self.scopes.extend(saved_scopes);
        self.structs.extend(saved_structs);
        self.defaults.extend(saved_defaults);
        result
    }

    fn inline_in_globals(
        &mut self,
        name: &str,
        defs: &[&'a ast::FunctionDefinition],
        args: Vec<(Place, bool)>,
    ) -> CResult<Value> {
        let line = self.line;
        // Resolve the overload: parameter types equal to the arguments' (ints may pass as
        // floats).
        let mut chosen = None;
        for def in defs {
            let mut params = Vec::new();
            for p in &def.prototype.parameters {
                let (q, spec, id) = match &p.content {
                    ast::FunctionParameterDeclarationData::Named(q, d) => (q, &d.ty, Some(&d.ident)),
                    ast::FunctionParameterDeclarationData::Unnamed(q, t) => (q, t, None),
                };
                let mut ty = self.type_of(spec)?;
                if let Some(id) = id {
                    ty = self.arrayed(ty, id.array_spec.as_ref())?;
                }
                if ty == Type::Void {
                    continue;
                }
                let dir = match q.as_ref().map(storage_dir) {
                    Some(d) => d,
                    None => ParamDir::In,
                };
                let prec = self.declared_prec(q.as_ref(), &ty);
                params.push((id.map(|i| i.ident.as_str().to_string()), ty, dir, prec));
            }
            let fits = params.len() == args.len()
                && params.iter().zip(&args).all(|((_, ty, dir, _), (place, _))| {
                    place.ty == *ty
                        || *dir == ParamDir::In
                            && place.ty.scalar().is_some_and(Scalar::is_integer)
                            && ty.scalar() == Some(Scalar::Float)
                            && place.ty.width() == ty.width()
                });
            if fits {
                chosen = Some((*def, params));
                break;
            }
        }
        self.line = line;
        let Some((def, params)) = chosen else {
            let types: Vec<String> = args.iter().map(|(p, _)| p.ty.to_string()).collect();
            return self.fail(format!("no function '{name}({})'", types.join(", ")));
        };
        let ret_ty = self.type_of(&def.prototype.ty.ty)?;
        let ret_prec = self.declared_prec(def.prototype.ty.qualifier.as_ref(), &ret_ty);
        self.line = line;
        self.push_scope();
        let mut copy_out = Vec::new();
        let zero = self.konst(0.0);
        if ret_ty.contains_sampler() {
            return self.fail(format!("function '{name}' cannot return a sampler"));
        }
        for ((pname, ty, dir, prec), (place, writable)) in params.into_iter().zip(args) {
            if ty.contains_sampler() && dir != ParamDir::In {
                return self.fail(format!("a sampler parameter of '{name}' must be 'in'"));
            }
            let regs = if ty.contains_sampler() {
                let value = self.read(&place);
                value.regs
            } else {
                let regs = self.temps(ty.size());
                if dir == ParamDir::Out {
                    for &r in &regs {
                        self.emit(Inst::Un(UnOp::Mov, r, zero));
                    }
                } else {
                    let value = self.read(&place);
                    let value = self.convert(value, &ty)?;
                    for (&d, &s) in regs.iter().zip(&value.regs) {
                        self.emit(Inst::Un(UnOp::Mov, d, s));
                    }
                }
                regs
            };
            if dir != ParamDir::In {
                if !writable {
                    return self.fail(format!("argument for out parameter of '{name}' is not writable"));
                }
                copy_out.push((place, Value { ty: ty.clone(), regs: regs.clone() }));
            }
            if !ty.contains_sampler() {
                self.set_prec(&regs, prec);
            }
            if let Some(pname) = pname {
                // Sampler "registers" are slot numbers: never written.
                let writable = !ty.contains_sampler();
                self.scopes.last_mut().expect("scope").insert(pname, Symbol { ty, regs, writable, konst: None });
            }
        }
        let ret = (ret_ty != Type::Void).then(|| {
            let regs = self.temps(ret_ty.size());
            for &r in &regs {
                self.emit(Inst::Un(UnOp::Mov, r, zero));
            }
            self.set_prec(&regs, ret_prec);
            Value { ty: ret_ty.clone(), regs }
        });
        self.returns.push(ret.clone());
        let body = self.block(|c| c.statements(&def.statement.statement_list));
        self.returns.pop();
        self.pop_scope();
        let ((), body) = body?;
        self.emit(Inst::Call(body));
        for (place, value) in copy_out {
            self.write(&place, &value);
        }
        Ok(ret.unwrap_or(Value { ty: Type::Void, regs: Vec::new() }))
    }

    /// A component converted to scalar kind `to`.
    /// Bools are 0.0/1.0, so they convert to numbers as floats do; int ↔ uint keeps the
    /// bits (GLSL's rule).
    fn convert_component(&mut self, r: Reg, from: Scalar, to: Scalar) -> Reg {
        match (from, to) {
            (Scalar::Float | Scalar::Bool, Scalar::Int) => self.un(UnOp::FToI, r),
            (Scalar::Float | Scalar::Bool, Scalar::UInt) => self.un(UnOp::FToU, r),
            (Scalar::Int, Scalar::Float) => self.un(UnOp::IToF, r),
            (Scalar::UInt, Scalar::Float) => self.un(UnOp::UToF, r),
            (Scalar::Float, Scalar::Bool) => self.un(UnOp::ToBool, r),
            (Scalar::Int | Scalar::UInt, Scalar::Bool) => self.un(UnOp::IToBool, r),
            _ => r,
        }
    }

    fn construct(&mut self, ty: Type, args: Vec<Value>) -> CResult<Value> {
        if args.is_empty() {
            return self.fail(format!("{ty}() needs arguments"));
        }
        match &ty {
            Type::Struct(s) => {
                if args.len() != s.fields.len() {
                    return self.fail(format!("{} has {} fields, {} given", s.name, s.fields.len(), args.len()));
                }
                let mut regs = Vec::new();
                for (v, (_, fty)) in args.into_iter().zip(&s.fields) {
                    regs.extend(self.convert(v, fty)?.regs);
                }
                Ok(Value { ty, regs })
            }
            Type::Scalar(to) | Type::Vector(to, _) => {
                let to = *to;
                let n = ty.size();
                let mut comps = Vec::new();
                for v in &args {
                    let Some(from) = v.ty.scalar() else {
                        return self.fail(format!("{ty} from {}", v.ty));
                    };
                    for &r in &v.regs {
                        comps.push(self.convert_component(r, from, to));
                    }
                }
                if args.len() == 1 && args[0].ty.width() == Some(1) {
                    return Ok(Value { ty, regs: vec![comps[0]; n] });
                }
                if comps.len() < n {
                    return self.fail(format!("too few components for {ty}"));
                }
                comps.truncate(n);
                Ok(Value { ty, regs: comps })
            }
            Type::Matrix(columns, rows) => {
                let (n, rows) = (*columns, *rows);
                let zero = self.konst(0.0);
                let one = self.konst(1.0);
                if args.len() == 1 {
                    match &args[0].ty {
                        Type::Scalar(from) => {
                            let d = self.convert_component(args[0].regs[0], *from, Scalar::Float);
                            let regs = (0..n * rows).map(|i| if i / rows == i % rows { d } else { zero }).collect();
                            return Ok(Value { ty, regs });
                        }
                        Type::Matrix(m, m_rows) => {
                            let (m, m_rows) = (*m, *m_rows);
                            let regs = (0..n * rows)
                                .map(|i| {
                                    let (c, r) = (i / rows, i % rows);
                                    if c < m && r < m_rows {
                                        args[0].regs[c * m_rows + r]
                                    } else if c == r {
                                        one
                                    } else {
                                        zero
                                    }
                                })
                                .collect();
                            return Ok(Value { ty, regs });
                        }
                        _ => {}
                    }
                }
                let mut comps = Vec::new();
                for v in &args {
                    match v.ty.scalar() {
                        Some(from) if !matches!(v.ty, Type::Matrix(..)) => {
                            for &r in &v.regs {
                                comps.push(self.convert_component(r, from, Scalar::Float));
                            }
                        }
                        _ => return self.fail(format!("{ty} from {}", v.ty)),
                    }
                }
                if comps.len() < n * rows {
                    return self.fail(format!("too few components for {ty}"));
                }
                comps.truncate(n * rows);
                Ok(Value { ty, regs: comps })
            }
            Type::Array(elem, n) => {
                // ES 3.00 §5.4.4: one argument per element, of the element's type.
                if args.len() != *n {
                    return self.fail(format!("{ty} needs {n} elements, {} given", args.len()));
                }
                let mut regs = Vec::with_capacity(ty.size());
                for v in args {
                    if v.ty != **elem {
                        return self.fail(format!("{ty}: an element of type {}", v.ty));
                    }
                    regs.extend(v.regs);
                }
                Ok(Value { ty, regs })
            }
            _ => self.fail(format!("cannot construct a {ty}")),
        }
    }
}

fn storage_dir(q: &ast::TypeQualifier) -> ParamDir {
    let mut dir = ParamDir::In;
    for spec in &q.qualifiers {
        if let ast::TypeQualifierSpecData::Storage(s) = &spec.content {
            match s.content {
                ast::StorageQualifierData::Out => dir = ParamDir::Out,
                ast::StorageQualifierData::InOut => dir = ParamDir::InOut,
                _ => {}
            }
        }
    }
    dir
}

// ---- built-in functions ----

impl<'a> Compiler<'a> {
    /// `v` as a float scalar or vector (ints promoted), or an error naming `name`.
    fn float_gen(&mut self, name: &str, v: Value) -> CResult<Value> {
        match v.ty {
            Type::Scalar(Scalar::Float | Scalar::Int | Scalar::UInt)
            | Type::Vector(Scalar::Float | Scalar::Int | Scalar::UInt, _) => Ok(self.floated(v)),
            _ => self.fail(format!("{name}() takes floats or float vectors, not {}", v.ty)),
        }
    }

    /// A component-wise built-in over float scalars/vectors; scalar arguments are broadcast
    /// to the vectors' width.
    fn componentwise(
        &mut self,
        name: &str,
        args: Vec<Value>,
        mut f: impl FnMut(&mut Self, &[Reg]) -> Reg,
    ) -> CResult<Value> {
        let args: Vec<Value> = args.into_iter().map(|a| self.float_gen(name, a)).collect::<CResult<_>>()?;
        let ty = args.iter().map(|a| a.ty.clone()).find(|t| t.width() != Some(1)).unwrap_or(FLOAT);
        let width = ty.width().expect("scalar or vector");
        if args.iter().any(|a| a.ty.width() != Some(1) && a.ty != ty) {
            let types: Vec<String> = args.iter().map(|a| a.ty.to_string()).collect();
            return self.fail(format!("{name}({}): mismatched arguments", types.join(", ")));
        }
        let regs = (0..width)
            .map(|i| {
                let ops: Vec<Reg> =
                    args.iter().map(|a| if a.regs.len() == 1 { a.regs[0] } else { a.regs[i] }).collect();
                f(self, &ops)
            })
            .collect();
        Ok(Value { ty, regs })
    }

    fn vector_arg(&mut self, name: &str, v: Value) -> CResult<Value> {
        self.float_gen(name, v)
    }

    /// The built-ins on integers (ES 3.00): `abs`, `sign`, `min`, `max`, `clamp` on int or
    /// uint scalars and vectors (a scalar beside a vector applies to each component), and
    /// the bit casts `floatBitsToInt`/`floatBitsToUint`/`intBitsToFloat`/`uintBitsToFloat`,
    /// which only relabel the register (see `ir`). `None` when `name` with these arguments is
    /// not one of them.
    fn integer_builtin(&mut self, name: &str, args: &[Value]) -> CResult<Option<Value>> {
        let cast = match name {
            "floatBitsToInt" => Some((Scalar::Float, Scalar::Int)),
            "floatBitsToUint" => Some((Scalar::Float, Scalar::UInt)),
            "intBitsToFloat" => Some((Scalar::Int, Scalar::Float)),
            "uintBitsToFloat" => Some((Scalar::UInt, Scalar::Float)),
            _ => None,
        };
        if let Some((from, to)) = cast {
            if args.len() != 1 || args[0].ty.scalar() != Some(from) || args[0].ty.width().is_none() {
                let types: Vec<String> = args.iter().map(|a| a.ty.to_string()).collect();
                return self.fail(format!("no function '{name}({})'", types.join(", ")));
            }
            return Ok(Some(Value { ty: args[0].ty.with_scalar(to), regs: args[0].regs.clone() }));
        }
        if let Some(v) = self.packing_builtin(name, args)? {
            return Ok(Some(v));
        }
        let Some(s) = args.first().and_then(|a| a.ty.scalar()).filter(|s| s.is_integer()) else {
            return Ok(None);
        };
        let signed = s == Scalar::Int;
        type Op<'c> = Box<dyn Fn(&mut Compiler<'c>, &[Reg]) -> Reg>;
        let (arity, op): (usize, Op<'a>) = match name {
            "abs" if signed => (1, Box::new(|c, r| c.un(UnOp::IAbs, r[0]))),
            "sign" if signed => (1, Box::new(|c, r| c.un(UnOp::ISign, r[0]))),
            "min" => {
                let op = if signed { BinOp::IMin } else { BinOp::UMin };
                (2, Box::new(move |c, r| c.bin(op, r[0], r[1])))
            }
            "max" => {
                let op = if signed { BinOp::IMax } else { BinOp::UMax };
                (2, Box::new(move |c, r| c.bin(op, r[0], r[1])))
            }
            "clamp" => {
                let op = if signed { TriOp::IClamp } else { TriOp::UClamp };
                (3, Box::new(move |c, r| c.tri(op, r[0], r[1], r[2])))
            }
            _ => return Ok(None),
        };
        let ty = args[0].ty.clone();
        let fits = args.len() == arity
            && ty.width().is_some()
            && args[1..].iter().all(|a| a.ty == ty || a.ty == Type::Scalar(s));
        if !fits {
            let types: Vec<String> = args.iter().map(|a| a.ty.to_string()).collect();
            return self.fail(format!("no function '{name}({})'", types.join(", ")));
        }
        let width = ty.width().expect("checked");
        let regs = (0..width)
            .map(|i| {
                let ops: Vec<Reg> =
                    args.iter().map(|a| if a.regs.len() == 1 { a.regs[0] } else { a.regs[i] }).collect();
                op(self, &ops)
            })
            .collect();
        Ok(Some(Value { ty, regs }))
    }

    /// The packing built-ins of ES 3.00 §8.4, as integer and float instructions:
    /// `packUnorm2x16(v)` = `round(clamp(v, 0, 1)·65535)` in the low and high 16 bits,
    /// `packSnorm2x16(v)` = `round(clamp(v, −1, 1)·32767)` as 16-bit two's complement,
    /// `packHalf2x16(v)` the half floats' bits (nearest, ties to even); the unpacks invert
    /// them (`unpackUnorm2x16` = `f / 65535`, `unpackSnorm2x16` = `clamp(f / 32767, −1, 1)`).
    /// `round` rounds halves away from zero (GLSL leaves the direction to the implementation).
    fn packing_builtin(&mut self, name: &str, args: &[Value]) -> CResult<Option<Value>> {
        let pack = matches!(name, "packUnorm2x16" | "packSnorm2x16" | "packHalf2x16");
        let unpack = matches!(name, "unpackUnorm2x16" | "unpackSnorm2x16" | "unpackHalf2x16");
        if !pack && !unpack {
            return Ok(None);
        }
        let wanted = if pack { Type::vec(2) } else { UINT };
        if args.len() != 1 || args[0].ty != wanted {
            let types: Vec<String> = args.iter().map(|a| a.ty.to_string()).collect();
            return self.fail(format!("no function '{name}({})'", types.join(", ")));
        }
        let regs = args[0].regs.clone();
        let sixteen = self.konst_int(16);
        let low_mask = self.konst(f32::from_bits(0xffff));
        if pack {
            let halves: Vec<Reg> = regs
                .iter()
                .map(|&x| match name {
                    "packHalf2x16" => self.un(UnOp::FToHalf, x),
                    "packUnorm2x16" => {
                        let (zero, one, scale) = (self.konst(0.0), self.konst(1.0), self.konst(65535.0));
                        let c = self.tri(TriOp::Clamp, x, zero, one);
                        let m = self.bin(BinOp::Mul, c, scale);
                        let r = self.un(UnOp::Round, m);
                        self.un(UnOp::FToU, r)
                    }
                    _ => {
                        let (lo, one, scale) = (self.konst(-1.0), self.konst(1.0), self.konst(32767.0));
                        let c = self.tri(TriOp::Clamp, x, lo, one);
                        let m = self.bin(BinOp::Mul, c, scale);
                        let r = self.un(UnOp::Round, m);
                        let i = self.un(UnOp::FToI, r);
                        self.bin(BinOp::BitAnd, i, low_mask)
                    }
                })
                .collect();
            let high = self.bin(BinOp::Shl, halves[1], sixteen);
            let packed = self.bin(BinOp::BitOr, halves[0], high);
            return Ok(Some(Value { ty: UINT, regs: vec![packed] }));
        }
        let p = regs[0];
        let high = self.bin(BinOp::UShr, p, sixteen);
        let low = self.bin(BinOp::BitAnd, p, low_mask);
        let out = [low, high]
            .iter()
            .map(|&h| match name {
                "unpackHalf2x16" => self.un(UnOp::HalfToF, h),
                "unpackUnorm2x16" => {
                    let f = self.un(UnOp::UToF, h);
                    let scale = self.konst(65535.0);
                    self.bin(BinOp::Div, f, scale)
                }
                _ => {
                    // Sign-extended: shifted to the top, then arithmetically back.
                    let top = self.bin(BinOp::Shl, h, sixteen);
                    let i = self.bin(BinOp::IShr, top, sixteen);
                    let f = self.un(UnOp::IToF, i);
                    let (scale, lo, one) = (self.konst(32767.0), self.konst(-1.0), self.konst(1.0));
                    let q = self.bin(BinOp::Div, f, scale);
                    self.tri(TriOp::Clamp, q, lo, one)
                }
            })
            .collect();
        Ok(Some(Value { ty: Type::vec(2), regs: out }))
    }

    fn length(&mut self, v: &[Reg]) -> Reg {
        let d = self.dot(v, v);
        self.un(UnOp::Sqrt, d)
    }

    fn builtin(&mut self, name: &str, args: Vec<Value>) -> CResult<Value> {
        let n = args.len();
        let arity = |c: &Self, want: usize| -> CResult<()> {
            if n == want { Ok(()) } else { c.fail(format!("{name}() takes {want} arguments, {n} given")) }
        };
        if let Some(v) = self.integer_builtin(name, &args)? {
            return Ok(v);
        }
        let unop = match name {
            "radians" => Some(UnOp::Radians),
            "degrees" => Some(UnOp::Degrees),
            "sin" => Some(UnOp::Sin),
            "cos" => Some(UnOp::Cos),
            "tan" => Some(UnOp::Tan),
            "asin" => Some(UnOp::Asin),
            "acos" => Some(UnOp::Acos),
            "atan" if n == 1 => Some(UnOp::Atan),
            "exp" => Some(UnOp::Exp),
            "log" => Some(UnOp::Log),
            "exp2" => Some(UnOp::Exp2),
            "log2" => Some(UnOp::Log2),
            "sqrt" => Some(UnOp::Sqrt),
            "inversesqrt" => Some(UnOp::InverseSqrt),
            "abs" => Some(UnOp::Abs),
            "sign" => Some(UnOp::Sign),
            "floor" => Some(UnOp::Floor),
            "ceil" => Some(UnOp::Ceil),
            "fract" => Some(UnOp::Fract),
            "trunc" => Some(UnOp::Trunc),
            "round" => Some(UnOp::Round),
            _ => None,
        };
        if let Some(op) = unop {
            arity(self, 1)?;
            return self.componentwise(name, args, |c, r| c.un(op, r[0]));
        }
        let binop = match name {
            "atan" => Some(BinOp::Atan2),
            "pow" => Some(BinOp::Pow),
            "mod" => Some(BinOp::Mod),
            "min" => Some(BinOp::Min),
            "max" => Some(BinOp::Max),
            "step" => Some(BinOp::Step),
            _ => None,
        };
        if let Some(op) = binop {
            arity(self, 2)?;
            return self.componentwise(name, args, |c, r| c.bin(op, r[0], r[1]));
        }
        if name == "mix" && args.len() == 3 && args[2].ty.scalar() == Some(Scalar::Bool) {
            // GLSL ES 3.00 §8.3: `mix(x, y, a)` with a boolean `a` selects, component by
            // component, `y` where `a` is true and `x` where it is false.
            let (x, y, a) = (&args[0], &args[1], &args[2]);
            if x.ty != y.ty || x.ty.width().is_none() || x.ty.width() != a.ty.width() {
                return self.fail(format!("mix({}, {}, {}): x and y must have a's shape", x.ty, y.ty, a.ty));
            }
            let regs = (0..x.regs.len()).map(|i| self.tri(TriOp::Select, a.regs[i], y.regs[i], x.regs[i])).collect();
            return Ok(Value { ty: x.ty.clone(), regs });
        }
        let triop = match name {
            "clamp" => Some(TriOp::Clamp),
            "mix" => Some(TriOp::Mix),
            "smoothstep" => Some(TriOp::Smoothstep),
            _ => None,
        };
        if let Some(op) = triop {
            arity(self, 3)?;
            return self.componentwise(name, args, |c, r| c.tri(op, r[0], r[1], r[2]));
        }
        match name {
            "length" => {
                arity(self, 1)?;
                let v = self.vector_arg(name, args[0].clone())?;
                Ok(Value { ty: FLOAT, regs: vec![self.length(&v.regs)] })
            }
            "distance" => {
                arity(self, 2)?;
                let d = self.componentwise(name, args, |c, r| c.bin(BinOp::Sub, r[0], r[1]))?;
                Ok(Value { ty: FLOAT, regs: vec![self.length(&d.regs)] })
            }
            "dot" => {
                arity(self, 2)?;
                let (a, b) = (self.vector_arg(name, args[0].clone())?, self.vector_arg(name, args[1].clone())?);
                if a.ty != b.ty {
                    return self.fail(format!("dot({}, {})", a.ty, b.ty));
                }
                Ok(Value { ty: FLOAT, regs: vec![self.dot(&a.regs, &b.regs)] })
            }
            "cross" => {
                arity(self, 2)?;
                let (a, b) = (self.vector_arg(name, args[0].clone())?, self.vector_arg(name, args[1].clone())?);
                if a.ty != Type::vec(3) || b.ty != Type::vec(3) {
                    return self.fail("cross() takes two vec3");
                }
                let (a, b) = (a.regs, b.regs);
                let regs = [(1, 2), (2, 0), (0, 1)]
                    .iter()
                    .map(|&(i, j)| {
                        let p = self.bin(BinOp::Mul, a[i], b[j]);
                        let q = self.bin(BinOp::Mul, b[i], a[j]);
                        self.bin(BinOp::Sub, p, q)
                    })
                    .collect();
                Ok(Value { ty: Type::vec(3), regs })
            }
            "normalize" => {
                arity(self, 1)?;
                let v = self.vector_arg(name, args[0].clone())?;
                // Mesa's `v · inversesqrt(dot(v, v))`, and llvmpipe's `inversesqrt` is
                // `1 / sqrt(x)`, both rounded: in binary16 (see `un_at`) and in single precision
                // (float-probe `highp-normalize.frag`; `v / length(v)` gave 40 of 48 on a
                // `highp` varying),
                // which is also the native shaders' `normalize3`.
                let d = self.dot(&v.regs, &v.regs);
                let r = self.un(UnOp::InverseSqrt, d);
                Ok(Value { ty: v.ty.clone(), regs: v.regs.iter().map(|&c| self.bin(BinOp::Mul, c, r)).collect() })
            }
            "faceforward" => {
                arity(self, 3)?;
                let v: Vec<Value> = args.into_iter().map(|a| self.vector_arg(name, a)).collect::<CResult<_>>()?;
                if v[0].ty != v[1].ty || v[1].ty != v[2].ty {
                    return self.fail("faceforward() arguments differ in type");
                }
                let d = self.dot(&v[2].regs, &v[1].regs);
                let zero = self.konst(0.0);
                let lt = self.bin(BinOp::Lt, d, zero);
                let regs = v[0]
                    .regs
                    .iter()
                    .map(|&r| {
                        let neg = self.un(UnOp::Neg, r);
                        self.tri(TriOp::Select, lt, r, neg)
                    })
                    .collect();
                Ok(Value { ty: v[0].ty.clone(), regs })
            }
            "reflect" => {
                // I − 2·dot(N, I)·N
                arity(self, 2)?;
                let (i, nn) = (self.vector_arg(name, args[0].clone())?, self.vector_arg(name, args[1].clone())?);
                if i.ty != nn.ty {
                    return self.fail("reflect() arguments differ in type");
                }
                let d = self.dot(&nn.regs, &i.regs);
                let two = self.konst(2.0);
                let d2 = self.bin(BinOp::Mul, two, d);
                let regs = i
                    .regs
                    .iter()
                    .zip(&nn.regs)
                    .map(|(&i, &n)| {
                        let p = self.bin(BinOp::Mul, d2, n);
                        self.bin(BinOp::Sub, i, p)
                    })
                    .collect();
                Ok(Value { ty: i.ty.clone(), regs })
            }
            "refract" => {
                // k = 1 − η²·(1 − dot(N, I)²); k < 0 ? 0 : η·I − (η·dot(N, I) + √k)·N
                arity(self, 3)?;
                let (i, nn) = (self.vector_arg(name, args[0].clone())?, self.vector_arg(name, args[1].clone())?);
                let eta = self.float_gen(name, args[2].clone())?;
                if i.ty != nn.ty || eta.ty != FLOAT {
                    return self.fail("refract(I, N, eta) needs I and N of one type and a float eta");
                }
                let eta = eta.regs[0];
                let (one, zero) = (self.konst(1.0), self.konst(0.0));
                let d = self.dot(&nn.regs, &i.regs);
                let dd = self.bin(BinOp::Mul, d, d);
                let t = self.bin(BinOp::Sub, one, dd);
                let lowered = i.regs.iter().chain(&nn.regs).map(|&r| self.prec(r)).max() == Some(Prec::Medium);
                let ee = if lowered && self.prec(eta) == Prec::None {
                    // A constant η is the lowered builtin's parameter: NIR folds η² from
                    // binary16 η, rounded (float-probe `refract.frag`: η = 1/1.2 gives
                    // 0.69482422, not 1/1.44's 0.69433594; 33 of 640 values moved).
                    self.bin_at(BinOp::Mul, eta, eta, Prec::Medium, true)
                } else {
                    self.bin(BinOp::Mul, eta, eta)
                };
                let et = self.bin(BinOp::Mul, ee, t);
                let k = self.bin(BinOp::Sub, one, et);
                let neg = self.bin(BinOp::Lt, k, zero);
                let sk = self.un(UnOp::Sqrt, k);
                let ed = self.bin(BinOp::Mul, eta, d);
                let f = self.bin(BinOp::Add, ed, sk);
                let regs = i
                    .regs
                    .iter()
                    .zip(&nn.regs)
                    .map(|(&i, &n)| {
                        let a = self.bin(BinOp::Mul, eta, i);
                        let b = self.bin(BinOp::Mul, f, n);
                        let r = self.bin(BinOp::Sub, a, b);
                        self.tri(TriOp::Select, neg, zero, r)
                    })
                    .collect();
                Ok(Value { ty: i.ty.clone(), regs })
            }
            "matrixCompMult" => {
                arity(self, 2)?;
                if !matches!(args[0].ty, Type::Matrix(..)) || args[0].ty != args[1].ty {
                    return self.fail("matrixCompMult() takes two matrices of one size");
                }
                let regs = args[0].regs.iter().zip(&args[1].regs).map(|(&a, &b)| self.bin(BinOp::Mul, a, b)).collect();
                Ok(Value { ty: args[0].ty.clone(), regs })
            }
            "determinant" | "inverse" => {
                arity(self, 1)?;
                let Type::Matrix(m, rows) = args[0].ty else { return self.fail(format!("{name}() takes a matrix")) };
                if m != rows {
                    return self.fail(format!("{name}() takes a square matrix, not a {}", args[0].ty));
                }
                // rows[r][c] = element (row r, column c); the value is column-major.
                let rows: Vec<Vec<Reg>> = (0..m).map(|r| (0..m).map(|c| args[0].regs[c * m + r]).collect()).collect();
                let det = self.determinant(&rows);
                if name == "determinant" {
                    return Ok(Value { ty: FLOAT, regs: vec![det] });
                }
                // The adjugate over the determinant (GLSL leaves a singular matrix undefined:
                // here its entries are infinities or NaNs).
                let one = self.konst(1.0);
                let inv = self.bin(BinOp::Div, one, det);
                let mut regs = vec![0; m * m];
                for r in 0..m {
                    for c in 0..m {
                        // Entry (r, c) is the cofactor of (c, r).
                        let minor: Vec<Vec<Reg>> = (0..m)
                            .filter(|&i| i != c)
                            .map(|i| (0..m).filter(|&j| j != r).map(|j| rows[i][j]).collect())
                            .collect();
                        let d = self.determinant(&minor);
                        let v = self.bin(BinOp::Mul, d, inv);
                        regs[c * m + r] = if (r + c) % 2 == 1 { self.un(UnOp::Neg, v) } else { v };
                    }
                }
                Ok(Value { ty: args[0].ty.clone(), regs })
            }
            "transpose" => {
                arity(self, 1)?;
                let Type::Matrix(c, r) = args[0].ty else { return self.fail("transpose() takes a matrix") };
                // Column j, row k of the R×C result is column k, row j of the argument.
                let regs = (0..c * r).map(|i| args[0].regs[(i % c) * r + i / c]).collect();
                Ok(Value { ty: Type::Matrix(r, c), regs })
            }
            "outerProduct" => {
                // `outerProduct(c, r)`: a matrix of r's size columns, c's size rows, column j
                // being `c · r[j]`.
                arity(self, 2)?;
                let (c, r) = (self.float_gen(name, args[0].clone())?, self.float_gen(name, args[1].clone())?);
                if c.regs.len() < 2 || r.regs.len() < 2 {
                    return self.fail(format!("outerProduct({}, {}) takes two vectors", c.ty, r.ty));
                }
                let (rows, columns) = (c.regs.len(), r.regs.len());
                let regs =
                    (0..columns * rows).map(|i| self.bin(BinOp::Mul, c.regs[i % rows], r.regs[i / rows])).collect();
                Ok(Value { ty: Type::Matrix(columns, rows), regs })
            }
            "lessThan" | "lessThanEqual" | "greaterThan" | "greaterThanEqual" | "equal" | "notEqual" => {
                arity(self, 2)?;
                let (a, b) = (&args[0], &args[1]);
                let ok = matches!(a.ty, Type::Vector(..))
                    && a.ty == b.ty
                    && (a.ty.scalar() != Some(Scalar::Bool) || matches!(name, "equal" | "notEqual"));
                if !ok {
                    return self.fail(format!("{name}({}, {})", a.ty, b.ty));
                }
                let op = match name {
                    "lessThan" => BinOp::Lt,
                    "lessThanEqual" => BinOp::Le,
                    "greaterThan" => BinOp::Gt,
                    "greaterThanEqual" => BinOp::Ge,
                    "equal" => BinOp::Eq,
                    _ => BinOp::Ne,
                };
                let op = Self::compare_op(op, a.ty.scalar());
                let regs = a.regs.iter().zip(&b.regs).map(|(&x, &y)| self.bin(op, x, y)).collect();
                Ok(Value { ty: a.ty.with_scalar(Scalar::Bool), regs })
            }
            "any" | "all" | "not" => {
                arity(self, 1)?;
                let v = &args[0];
                if !matches!(v.ty, Type::Vector(Scalar::Bool, _)) {
                    return self.fail(format!("{name}() takes a bvec, not {}", v.ty));
                }
                if name == "not" {
                    return Ok(Value {
                        ty: v.ty.clone(),
                        regs: v.regs.iter().map(|&r| self.un(UnOp::Not, r)).collect(),
                    });
                }
                let op = if name == "any" { BinOp::Or } else { BinOp::And };
                let r = v.regs[1..].iter().fold(v.regs[0], |acc, &x| self.bin(op, acc, x));
                Ok(Value { ty: BOOL, regs: vec![r] })
            }
            "texture2D" | "texture2DProj" | "texture2DLod" | "texture2DProjLod" | "texture" | "textureProj"
            | "textureLod" | "shadow2DEXT" | "shadow2DProjEXT" => self.texture(name, args),
            "textureCube" | "textureCubeLod" => self.texture_cube(name, args),
            "texelFetch" | "textureSize" => self.texel_fetch(name, args),
            "textureGrad" | "textureOffset" | "textureLodOffset" | "textureProjOffset" | "textureGradOffset" => {
                self.texture_fn(name, args)
            }
            "textureGather" | "textureGatherOffset" => self.texture_gather(name, args),
            "dFdx" | "dFdy" | "fwidth" => {
                // OES_standard_derivatives.
                arity(self, 1)?;
                if self.stage != Stage::Fragment {
                    return self.fail(format!("{name}() outside a fragment shader"));
                }
                self.componentwise(name, args, |c, r| {
                    let derivative = |c: &mut Self, axis| {
                        let dst = c.temp();
                        c.emit(Inst::Derivative { dst, src: r[0], axis });
                        // Derivatives stay in single precision (Mesa does not lower them
                        // without binary16 derivatives, which llvmpipe lacks).
                        c.set_prec(&[dst], Prec::High);
                        dst
                    };
                    match name {
                        "dFdx" => derivative(c, Axis::X),
                        "dFdy" => derivative(c, Axis::Y),
                        _ => {
                            let (x, y) = (derivative(c, Axis::X), derivative(c, Axis::Y));
                            let (x, y) = (c.un(UnOp::Abs, x), c.un(UnOp::Abs, y));
                            c.bin(BinOp::Add, x, y)
                        }
                    }
                })
            }
            _ => self.fail(format!("no function '{name}'")),
        }
    }

    /// `texture2D`, `texture2DProj`, `texture2DLod`, `texture2DProjLod` and GLSL ES 3.00's
    /// `texture`, `textureProj`, `textureLod` on a sampler2D; on a sampler2DShadow (and
    /// `EXT_shadow_samplers`' `shadow2DEXT`, `shadow2DProjEXT`) the coordinates carry the
    /// reference depth last (`vec3` (s, t, ref), or `vec4` (s, t, ref, q) projected), and the
    /// result is the compare's float.
    /// A lookup's level of detail from its optional third argument: a level (`…Lod`), a bias
    /// (fragment shaders), else the quad's derivatives (fragment) or level 0 (vertex).
    fn lookup_lod(&mut self, name: &str, explicit: bool, extra: Option<&Value>) -> CResult<Lod> {
        let extra = match extra {
            Some(v) => Some(self.float_gen(name, v.clone())?),
            None => None,
        };
        if extra.as_ref().is_some_and(|v| v.ty != FLOAT) {
            return self.fail(format!("{name}(): bias or level must be a float"));
        }
        Ok(match (explicit, extra.map(|v| v.regs[0]), self.stage) {
            (true, Some(l), _) => Lod::Explicit(l),
            (true, None, _) => return self.fail(format!("{name}() needs a level")),
            (false, None, Stage::Fragment) => Lod::Implicit,
            (false, Some(b), Stage::Fragment) => Lod::Bias(b),
            (false, None, Stage::Vertex) => Lod::Explicit(self.konst(0.0)),
            (false, Some(_), Stage::Vertex) => return self.fail(format!("{name}() with a bias in a vertex shader")),
        })
    }

    fn texture(&mut self, name: &str, args: Vec<Value>) -> CResult<Value> {
        let proj = name.contains("Proj");
        let explicit = name.ends_with("Lod");
        if args.len() < 2 || args.len() > 3 {
            return self.fail(format!("{name}() takes 2 or 3 arguments"));
        }
        let shadow_name = name.starts_with("shadow");
        let (slot, shadow) = match args[0].ty {
            Type::Sampler(SamplerKind::Sampler2D) if !shadow_name => (args[0].regs[0] as u16, false),
            Type::Sampler(SamplerKind::Sampler2DShadow) if !name.starts_with("texture2D") => {
                (args[0].regs[0] as u16, true)
            }
            Type::Sampler(SamplerKind::SamplerCube) if matches!(name, "texture" | "textureLod") => {
                // GLSL ES 3.00's `texture`/`textureLod` on a samplerCube.
                return self.texture_cube(name, args);
            }
            Type::Sampler(SamplerKind::Sampler2DArray | SamplerKind::Sampler3D)
                if matches!(name, "texture" | "textureLod" | "textureProj") =>
            {
                return self.texture_layered(name, args);
            }
            Type::Sampler(SamplerKind::Integer { shape, .. }) if matches!(name, "texture" | "textureLod") => {
                if shape != IntegerShape::Flat {
                    return self.texture_layered(name, args);
                }
                (args[0].regs[0] as u16, false)
            }
            _ if shadow_name => return self.fail(format!("{name}() needs a sampler2DShadow, not {}", args[0].ty)),
            _ => return self.fail(format!("{name}() needs a sampler2D, not {}", args[0].ty)),
        };
        let coord = self.float_gen(name, args[1].clone())?;
        let want = match (shadow, proj) {
            (false, false) => coord.regs.len() == 2,
            (false, true) => [3, 4].contains(&coord.regs.len()),
            (true, false) => coord.regs.len() == 3,
            (true, true) => coord.regs.len() == 4,
        };
        if !want {
            return self.fail(format!("{name}() coordinates cannot be a {}", coord.ty));
        }
        let (s, t) = if proj {
            let q = *coord.regs.last().expect("3 or 4 components");
            (self.bin(BinOp::Div, coord.regs[0], q), self.bin(BinOp::Div, coord.regs[1], q))
        } else {
            (coord.regs[0], coord.regs[1])
        };
        let reference = match (shadow, proj) {
            (false, _) => None,
            (true, false) => Some(coord.regs[2]),
            (true, true) => Some(self.bin(BinOp::Div, coord.regs[2], coord.regs[3])),
        };
        let lod = self.lookup_lod(name, explicit, args.get(2))?;
        let dst = self.temps(4);
        let dst4 = [dst[0], dst[1], dst[2], dst[3]];
        self.emit(Inst::Sample { slot, dst: dst4, coord: [s, t], lod, reference, offset: [0, 0], round: false });
        if shadow {
            let dst = self.texels(slot, vec![dst[0]]);
            return Ok(Value { ty: FLOAT, regs: dst });
        }
        Ok(self.texel_value(&args[0].ty, slot, dst))
    }

    /// `textureCube(samplerCube, vec3 [, bias])`, `textureCubeLod(samplerCube, vec3, lod)` (and
    /// GLSL ES 3.00's `texture`/`textureLod` on a samplerCube): the direction need not be
    /// normalised; a vertex shader's `textureCube` reads level 0 (`λ = 0`), as for 2D.
    fn texture_cube(&mut self, name: &str, args: Vec<Value>) -> CResult<Value> {
        let explicit = name.ends_with("Lod");
        if args.len() < 2 || args.len() > 3 {
            return self.fail(format!("{name}() takes 2 or 3 arguments"));
        }
        let slot = match args[0].ty {
            Type::Sampler(SamplerKind::SamplerCube) => args[0].regs[0] as u16,
            _ => return self.fail(format!("{name}() needs a samplerCube, not {}", args[0].ty)),
        };
        let direction = self.float_gen(name, args[1].clone())?;
        if direction.regs.len() != 3 {
            return self.fail(format!("{name}() takes a vec3 direction, not a {}", direction.ty));
        }
        let lod = self.lookup_lod(name, explicit, args.get(2))?;
        let dst = self.temps(4);
        let direction = [direction.regs[0], direction.regs[1], direction.regs[2]];
        self.emit(Inst::SampleCube { slot, dst: [dst[0], dst[1], dst[2], dst[3]], direction, lod });
        let dst = self.texels(slot, dst);
        Ok(Value { ty: Type::vec(4), regs: dst })
    }
}

impl Compiler<'_> {
    /// GLSL ES 3.00's `texture(s, vec3 [, bias])`, `textureLod(s, vec3, lod)` on a
    /// `sampler2DArray` (`(s, t, layer)`) or `sampler3D` (`(s, t, r)`), and `textureProj(s,
    /// vec4 [, bias])` on a `sampler3D` (`(s, t, r) / q`); a vertex shader's `texture` reads
    /// level 0 (`λ = 0`), as for 2D.
    fn texture_layered(&mut self, name: &str, args: Vec<Value>) -> CResult<Value> {
        let explicit = name.ends_with("Lod");
        let proj = name == "textureProj";
        if args.len() < 2 || args.len() > 3 {
            return self.fail(format!("{name}() takes 2 or 3 arguments"));
        }
        let kind = match args[0].ty {
            Type::Sampler(kind @ (SamplerKind::Sampler2DArray | SamplerKind::Sampler3D)) => kind,
            Type::Sampler(SamplerKind::Integer { shape: IntegerShape::Array, .. }) if !proj => {
                SamplerKind::Sampler2DArray
            }
            Type::Sampler(SamplerKind::Integer { shape: IntegerShape::Volume, .. }) => SamplerKind::Sampler3D,
            _ => return self.fail(format!("{name}() needs a sampler2DArray or sampler3D, not {}", args[0].ty)),
        };
        if proj && kind == SamplerKind::Sampler2DArray {
            return self.fail(format!("{name}() has no sampler2DArray form"));
        }
        let slot = args[0].regs[0] as u16;
        let coord = self.float_gen(name, args[1].clone())?;
        if coord.regs.len() != if proj { 4 } else { 3 } {
            return self.fail(format!("{name}({}) coordinates cannot be a {}", args[0].ty, coord.ty));
        }
        let coord = if proj {
            let q = coord.regs[3];
            [0, 1, 2].map(|c| self.bin(BinOp::Div, coord.regs[c], q))
        } else {
            [coord.regs[0], coord.regs[1], coord.regs[2]]
        };
        let lod = self.lookup_lod(name, explicit, args.get(2))?;
        let dst = self.temps(4);
        self.emit(Inst::SampleLayered { slot, dst: [dst[0], dst[1], dst[2], dst[3]], coord, lod });
        Ok(self.texel_value(&args[0].ty, slot, dst))
    }

    /// A lookup's four result registers as the value the sampler `sampler` gives: a `vec4` at
    /// the sampler's precision, or an integer sampler's `ivec4`/`uvec4` (whose registers hold
    /// the integers' bits, never rounded).
    fn texel_value(&mut self, sampler: &Type, slot: u16, dst: Vec<Reg>) -> Value {
        let result = match sampler {
            Type::Sampler(kind) => kind.result(),
            _ => Scalar::Float,
        };
        let dst = match result {
            Scalar::Float => self.texels(slot, dst),
            _ => {
                self.set_prec(&dst, Prec::High);
                dst
            }
        };
        Value { ty: Type::Vector(result, 4), regs: dst }
    }

    /// The float results `dst` of a lookup through the sampler in `slot`, at its precision.
    /// Through a `mediump`/`lowp` sampler they are binary16 values, rounded toward zero: what
    /// llvmpipe returns (Mesa lowers the lookup's result to 16 bits; tools/float-probe's
    /// `texels.frag` reads every texel of an RGBA8 texture back so, e.g. 30/255 = 1927.53
    /// steps of 2⁻¹⁴ as 1927, not 1928). Fragment shaders only: a vertex shader's lookups
    /// (llvmpipe's draw module) are not measured, and keep the sampler's value.
    fn texels(&mut self, slot: u16, dst: Vec<Reg>) -> Vec<Reg> {
        let prec = self.sampler_precision.get(&slot).copied().unwrap_or_default();
        if prec != Prec::Medium || self.stage != Stage::Fragment {
            self.set_prec(&dst, prec);
            return dst;
        }
        dst.into_iter()
            .map(|r| {
                let d = self.temp();
                self.emit(Inst::Un(UnOp::HalfTowardZero, d, r));
                self.lowered_result(d, prec, false, true)
            })
            .collect()
    }

    /// GLSL ES 3.00's `texelFetch(sampler, ivec P, int lod)` (texel `P` of level `lod`, no
    /// filter; `P` an `ivec3` with the layer or slice for a 2-D array or 3-D sampler) and
    /// `textureSize(sampler, int lod)` (an `ivec2`, or `ivec3` with the layers or depth), on
    /// every sampler type tiler has but those GLSL gives no `texelFetch`: samplerCube and
    /// sampler2DShadow have `textureSize` only.
    fn texel_fetch(&mut self, name: &str, args: Vec<Value>) -> CResult<Value> {
        let size = name == "textureSize";
        let want = if size { 2 } else { 3 };
        if args.len() != want {
            return self.fail(format!("{name}() takes {want} arguments"));
        }
        let kind = match args[0].ty {
            Type::Sampler(kind) => kind,
            _ => return self.fail(format!("{name}() needs a sampler, not {}", args[0].ty)),
        };
        let slot = args[0].regs[0] as u16;
        let dims = if kind == SamplerKind::SamplerCube || kind == SamplerKind::Sampler2DShadow {
            if !size {
                return self.fail(format!("no {name}() for a {}", args[0].ty));
            }
            2
        } else {
            kind.dimensions()
        };
        let level = args.last().expect("2 or 3 arguments");
        if level.ty != INT {
            return self.fail(format!("{name}(): the level must be an int, not {}", level.ty));
        }
        let level = level.regs[0];
        let dst = self.temps(4);
        let dst4 = [dst[0], dst[1], dst[2], dst[3]];
        if size {
            self.emit(Inst::Fetch { slot, dst: dst4, coord: [level; 3], level, size: true });
            self.set_prec(&dst, Prec::High);
            return Ok(Value { ty: Type::Vector(Scalar::Int, dims), regs: dst[..dims].to_vec() });
        }
        let coord = &args[1];
        if coord.ty != Type::Vector(Scalar::Int, dims) {
            return self.fail(format!("{name}({}) takes ivec{dims} coordinates, not {}", args[0].ty, coord.ty));
        }
        let zero = self.konst_int(0);
        let coord = [coord.regs[0], coord.regs[1], if dims == 3 { coord.regs[2] } else { zero }];
        self.emit(Inst::Fetch { slot, dst: dst4, coord, level, size: false });
        Ok(self.texel_value(&args[0].ty, slot, dst))
    }
}

/// The scalar kind of each component register of a value of type `ty`.
fn scalar_kinds(ty: &Type) -> Vec<Scalar> {
    match ty {
        Type::Struct(s) => s.fields.iter().flat_map(|(_, t)| scalar_kinds(t)).collect(),
        Type::Array(t, n) => scalar_kinds(t).repeat(*n),
        _ => vec![ty.scalar().unwrap_or(Scalar::Float); ty.size()],
    }
}

/// A lowered `dot` as Mesa's NIR has it after factoring (see [`Compiler::dot_at`]):
/// `Mul(p, q, rest)` is `p·q`, plus `rest` when there is one (an fma).
enum DotChain {
    Mul(DotTerm, DotTerm, Option<Box<DotChain>>),
}

/// A factor of a [`DotChain`]: an operand, or a sum of them that factoring made.
#[derive(Clone)]
enum DotTerm {
    Reg(Reg),
    Add(Box<DotTerm>, Box<DotTerm>),
}

/// A `mediump` operation computed in single precision, to compute again in binary16.
#[derive(Clone, Debug)]
enum Recipe {
    Un(UnOp, Reg),
    Bin(BinOp, Reg, Reg),
    Tri(TriOp, Reg, Reg, Reg),
    Dot(Vec<Reg>, Vec<Reg>),
}

impl Recipe {
    fn reads(&self, r: Reg) -> bool {
        match self {
            Recipe::Un(_, a) => *a == r,
            Recipe::Bin(_, a, b) => *a == r || *b == r,
            Recipe::Tri(_, a, b, c) => *a == r || *b == r || *c == r,
            Recipe::Dot(a, b) => a.contains(&r) || b.contains(&r),
        }
    }
}

/// Registers an instruction writes, its nested blocks' writes included.
fn written_within(inst: &mut Inst, out: &mut Vec<Reg>) {
    crate::hoist::writes(inst, &mut |r| out.push(r));
    for block in crate::hoist::blocks_mut(inst) {
        for inst in block {
            written_within(inst, out);
        }
    }
}

/// Why a structure cannot be a varying (GLSL ES 3.00 §4.3.4), or `None`: every member a
/// float-based type, an integer one only in a `flat` varying, or such a structure.
fn varying_struct_error(ty: &Type, flat: bool) -> Option<String> {
    match ty {
        Type::Struct(s) => s.fields.iter().find_map(|(field, t)| {
            let element = match t {
                Type::Array(t, _) => t,
                t => t,
            };
            let integer = element.scalar().is_some_and(Scalar::is_integer) && element.width().is_some();
            match element {
                Type::Struct(_) => varying_struct_error(element, flat),
                _ if t.is_float_based() => None,
                _ if integer && flat => None,
                _ if integer => Some(format!("integer member '{field}' ({t}) needs the varying qualified 'flat'")),
                _ => Some(format!("member '{field}' must be float-based or integer, not {t}")),
            }
        }),
        _ => None,
    }
}
