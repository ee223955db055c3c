//! Bounds on what compiling a hostile shader may cost, checked before the parser sees it.
//!
//! The parser and the compiler walk expressions and blocks recursively, and a capture is a file
//! from anywhere: `1.0+1.0+…` or `{{{…}}}` a hundred thousand deep overflowed the stack (an
//! abort, not an error), and a chain of macros each doubling the last (`#define A1 A0+A0`,
//! …, `A20`) expanded past what memory holds. So:
//!
//! - a stage's source is at most [`MAX_SOURCE_BYTES`], which bounds the nesting depth;
//! - macros are expanded on paper first, each use counted as its body's tokens (a
//!   function-like macro's parameters as one token each), and a shader whose macros would
//!   expand past [`MAX_MACRO_TOKENS`] is refused;
//! - compiling runs on a thread of its own whose stack ([`COMPILE_STACK_BYTES`], reserved,
//!   not committed) holds the deepest nesting that source size allows.
//!
//! - the preprocessed token stream the parser reads is cut at [`MAX_TOKENS`] ([`CappedLexer`]).
//!
//! Known gap: a function-like macro that expands its argument several times, applied to a
//! macro that does the same, multiplies in the preprocessor before any token reaches the cap;
//! the estimate counts such an argument once. (glsl-lang's preprocessor does not expand an
//! invocation nested in another's arguments, `D(D(x))`, which limits how such chains can be
//! written, and is itself a conformance gap.)

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
    // Expanded size of each object-like macro, in tokens, in definition order (a macro's body
    // can only use what is defined before it is expanded; counting later definitions too
    // would only overestimate).
    let mut sizes: HashMap<&str, u64> = HashMap::new();
    for (index, line) in source.lines().enumerate() {
        let Some(rest) = line.trim_start().strip_prefix('#') else { continue };
        let Some(rest) = rest.trim_start().strip_prefix("define") else { continue };
        let rest = rest.trim_start();
        let name_len = rest.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(rest.len());
        let (name, body) = rest.split_at(name_len);
        if name.is_empty() {
            continue;
        }
        // A function-like macro: its body after the parameter list, each parameter counted as
        // one token (an argument expanded several times is what this misses; the token cap
        // below the parser is the backstop for what it emits).
        let body = match body.strip_prefix('(') {
            Some(params) => params.split_once(')').map_or("", |(_, body)| body),
            None => body,
        };
        let size = tokens(body).map(|t| sizes.get(t).copied().unwrap_or(1)).fold(0u64, u64::saturating_add);
        if size > MAX_MACRO_TOKENS {
            return Err(Error::Compile {
                stage,
                line: index as u32 + 1,
                message: format!("macro {name} expands to more than {MAX_MACRO_TOKENS} tokens"),
            });
        }
        sizes.insert(name, size.max(1));
    }
    Ok(())
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
        let handle = std::thread::Builder::new()
            .name("tiler-glsl compiler".into())
            .stack_size(COMPILE_STACK_BYTES)
            .spawn_scoped(scope, f)
            .map_err(|e| Error::Link(format!("cannot start the compiler's thread: {e}")))?;
        handle.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic))
    })
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
