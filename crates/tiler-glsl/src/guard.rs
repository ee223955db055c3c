//! Bounds on what compiling a hostile shader may cost, checked before the parser sees it.
//!
//! The parser and the compiler walk expressions and blocks recursively, and a capture is a file
//! from anywhere: `1.0+1.0+…` or `{{{…}}}` a hundred thousand deep overflowed the stack (an
//! abort, not an error), and a chain of macros each doubling the last (`#define A1 A0+A0`,
//! …, `A20`) expanded past what memory holds. So:
//!
//! - a stage's source is at most [`MAX_SOURCE_BYTES`], which bounds the nesting depth;
//! - macros, and the shader's text with them, are expanded on paper first, and a shader whose
//!   macros would expand past [`MAX_MACRO_TOKENS`] is refused;
//! - compiling runs on a thread of its own whose stack ([`COMPILE_STACK_BYTES`], reserved,
//!   not committed) holds the deepest nesting that source size allows.
//!
//! - the preprocessed token stream the parser reads is cut at [`MAX_TOKENS`] ([`CappedLexer`]).
//!
//! The estimate counts what stands in a function-like macro's call as many times as the macro
//! repeats a parameter, so `#define D(x) x+x+x+x` applied in a chain of definitions is
//! refused too. (glsl-lang's preprocessor does not expand an invocation nested in another's
//! arguments, `D(D(x))`; `nested_macros` works around that before the source gets here.)

use std::cell::Cell;
use std::collections::HashMap;

use glsl_lang::lexer::full::str::{Lexer, LexerIterator};
use glsl_lang::lexer::{HasLexerError, LangLexer, LangLexerIterator, ParseContext, ParseOptions, Token};
use lang_util::position::LexerPosition;

use crate::{Error, Stage};

/// The largest source of one stage (real shaders are a few KiB; large ones tens).
pub const MAX_SOURCE_BYTES: usize = 256 << 10;
/// The most tokens the object-like macros of one stage may expand to.
pub const MAX_MACRO_TOKENS: u64 = 1 << 20;
/// The most tokens the parser reads from one stage's preprocessed source.
pub const MAX_TOKENS: u64 = 1 << 21;
/// The compiler thread's stack: enough for [`MAX_SOURCE_BYTES`] of nesting in an optimised or
/// a test build.
pub const COMPILE_STACK_BYTES: usize = 1 << 30;

/// Checks one stage's source against the bounds above.
pub fn check_source(stage: Stage, source: &str) -> Result<(), Error> {
    if source.len() > MAX_SOURCE_BYTES {
        return Err(Error::Compile {
            stage,
            line: 1,
            message: format!("the source is {} bytes, more than the {MAX_SOURCE_BYTES} tiler compiles", source.len()),
        });
    }
    // Expanded size of each macro, in tokens, in definition order (a macro's body can only
    // use what is defined before it is expanded; counting later definitions too would only
    // overestimate), and how often a function-like macro repeats an argument.
    let mut macros: HashMap<&str, Macro> = HashMap::new();
    let mut text_size = 0u64;
    for (index, line) in source.lines().enumerate() {
        let too_big = |what: String| Error::Compile {
            stage,
            line: index as u32 + 1,
            message: format!("{what} expands to more than {MAX_MACRO_TOKENS} tokens"),
        };
        let Some(rest) = line.trim_start().strip_prefix('#') else {
            text_size = text_size.saturating_add(expanded_size(line, &macros));
            if text_size > MAX_MACRO_TOKENS {
                return Err(too_big("the shader's text with its macros".into()));
            }
            continue;
        };
        let Some(rest) = rest.trim_start().strip_prefix("define") else { continue };
        let rest = rest.trim_start();
        let name_len = rest.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(rest.len());
        let (name, body) = rest.split_at(name_len);
        if name.is_empty() {
            continue;
        }
        // A function-like macro: its body after the parameter list, and the most times it
        // repeats one parameter (an argument is counted that many times where it is used).
        let (body, repeats) = match body.strip_prefix('(') {
            Some(params) => {
                let (params, body) = params.split_once(')').unwrap_or(("", ""));
                let repeats = params
                    .split(',')
                    .map(|p| tokens(body).filter(|t| *t == p.trim()).count() as u64)
                    .max()
                    .unwrap_or(1)
                    .max(1);
                (body, repeats)
            }
            None => (body, 1),
        };
        let size = expanded_size(body, &macros);
        if size > MAX_MACRO_TOKENS {
            return Err(too_big(format!("macro {name}")));
        }
        let function_like = rest[name_len..].starts_with('(');
        macros.insert(name, Macro { size: size.max(1), repeats, function_like });
    }
    Ok(())
}

/// What the paper expansion knows of a macro.
struct Macro {
    /// Tokens its body expands to, each argument counted once.
    size: u64,
    /// The most times the body uses one parameter (1 for object-like macros).
    repeats: u64,
    function_like: bool,
}

/// Tokens `text` expands to, at most: each macro use counted as its expansion, and what stands
/// inside the parentheses of a function-like macro's call as many times as the macro repeats
/// an argument (nested calls multiply). Iterative: a stack of multipliers, one per open
/// parenthesis.
fn expanded_size(text: &str, macros: &HashMap<&str, Macro>) -> u64 {
    let mut total = 0u64;
    let mut multipliers = vec![1u64];
    let mut call_repeats = None;
    for token in tokens(text) {
        let current = *multipliers.last().expect("the outermost multiplier is never popped");
        match token {
            "(" => multipliers.push(current.saturating_mul(call_repeats.take().unwrap_or(1))),
            ")" if multipliers.len() > 1 => {
                multipliers.pop();
            }
            _ => {}
        }
        if token != "(" {
            call_repeats = None;
        }
        let (size, repeats) = match macros.get(token) {
            Some(m) if m.function_like => (m.size, Some(m.repeats)),
            Some(m) => (m.size, None),
            None => (1, None),
        };
        total = total.saturating_add(size.saturating_mul(current));
        if repeats.is_some() {
            call_repeats = repeats;
        }
    }
    total
}

/// The identifiers and other tokens of a macro body, roughly: identifiers whole, every other
/// non-space character one token (an overestimate for numbers and operators, which is safe).
fn tokens(body: &str) -> impl Iterator<Item = &str> {
    let is_word = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let mut rest = body;
    std::iter::from_fn(move || {
        rest = rest.trim_start();
        let first = rest.chars().next()?;
        let len =
            if is_word(first) { rest.find(|c: char| !is_word(c)).unwrap_or(rest.len()) } else { first.len_utf8() };
        let (token, tail) = rest.split_at(len);
        rest = tail;
        Some(token)
    })
}

/// Runs `f` on a thread with a [`COMPILE_STACK_BYTES`] stack.
pub fn with_deep_stack<T: Send>(f: impl FnOnce() -> Result<T, Error> + Send) -> Result<T, Error> {
    std::thread::scope(|scope| {
        let handle = spawn_deep(scope, f)?;
        handle.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic))
    })
}

/// Runs `a` and `b` side by side, each on a thread with a [`COMPILE_STACK_BYTES`] stack, and
/// returns both results, or `a`'s error before `b`'s: a program's two stages compiled at once
/// (a replay waits for each link, half a millisecond to a millisecond a stage).
pub fn with_deep_stacks<A: Send, B: Send>(
    a: impl FnOnce() -> Result<A, Error> + Send,
    b: impl FnOnce() -> Result<B, Error> + Send,
) -> Result<(A, B), Error> {
    std::thread::scope(|scope| {
        let b = spawn_deep(scope, b)?;
        let a = spawn_deep(scope, a)?.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        let b = b.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        Ok((a?, b?))
    })
}

fn spawn_deep<'scope, T: Send + 'scope>(
    scope: &'scope std::thread::Scope<'scope, '_>,
    f: impl FnOnce() -> Result<T, Error> + Send + 'scope,
) -> Result<std::thread::ScopedJoinHandle<'scope, Result<T, Error>>, Error> {
    std::thread::Builder::new()
        .name("tiler-glsl compiler".into())
        .stack_size(COMPILE_STACK_BYTES)
        .spawn_scoped(scope, f)
        .map_err(|e| Error::Link(format!("cannot start the compiler's thread: {e}")))
}

thread_local! {
    /// Whether the current thread's last parse was cut at [`MAX_TOKENS`].
    static CUT: Cell<bool> = const { Cell::new(false) };
}

/// Whether the last parse on this thread ended because it reached [`MAX_TOKENS`] (its error is
/// then about that, not about the source's last token).
pub fn was_cut() -> bool {
    CUT.with(Cell::get)
}

/// glsl-lang's full lexer (preprocessor included), ending the stream after [`MAX_TOKENS`].
pub struct CappedLexer<'i>(Lexer<'i>);

/// [`CappedLexer`]'s token stream.
pub struct CappedIter<'i> {
    inner: LexerIterator<'i>,
    left: u64,
}

impl<'i> HasLexerError for CappedLexer<'i> {
    type Error = <Lexer<'i> as HasLexerError>::Error;
}

impl<'i> LangLexer<'i> for CappedLexer<'i> {
    type Input = &'i str;
    type Iter = CappedIter<'i>;

    fn new(source: &'i str, opts: &ParseOptions) -> Self {
        CappedLexer(Lexer::new(source, opts))
    }

    fn run(self, ctx: ParseContext) -> CappedIter<'i> {
        CUT.with(|cut| cut.set(false));
        CappedIter { inner: self.0.run(ctx), left: MAX_TOKENS }
    }
}

impl<'i> HasLexerError for CappedIter<'i> {
    type Error = <LexerIterator<'i> as HasLexerError>::Error;
}

impl<'i> Iterator for CappedIter<'i> {
    type Item = <LexerIterator<'i> as Iterator>::Item;

    fn next(&mut self) -> Option<Self::Item> {
        if self.left == 0 {
            CUT.with(|cut| cut.set(true));
            return None;
        }
        self.left -= 1;
        self.inner.next()
    }
}

impl LangLexerIterator for CappedIter<'_> {
    fn resolve_err(
        &self,
        err: lalrpop_util::ParseError<LexerPosition, Token, Self::Error>,
    ) -> lang_util::error::ParseError<Self::Error> {
        self.inner.resolve_err(err)
    }
}
