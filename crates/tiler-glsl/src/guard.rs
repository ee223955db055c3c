//! Bounds on what compiling a hostile shader may cost, checked before the parser sees it.
//!
//! The parser and the compiler walk expressions and blocks recursively, and a capture is a file
//! from anywhere: `1.0+1.0+…` or `{{{…}}}` a hundred thousand deep overflowed the stack (an
//! abort, not an error), and a chain of macros each doubling the last (`#define A1 A0+A0`,
//! …, `A20`) expanded past what memory holds. So:
//!
//! - a stage's source is at most [`MAX_SOURCE_BYTES`], which bounds the nesting depth;
//! - object-like macros are expanded on paper first, each use counted as its body's tokens,
//!   and a shader whose macros would expand past [`MAX_MACRO_TOKENS`] is refused;
//! - compiling runs on a thread of its own whose stack ([`COMPILE_STACK_BYTES`], reserved,
//!   not committed) holds the deepest nesting that source size allows.
//!
//! Function-like macros are not estimated (an argument may be expanded many times); a shader
//! that nests them to blow up is the one known gap.

use std::collections::HashMap;

use crate::{Error, Stage};

/// The largest source of one stage (real shaders are a few KiB; large ones tens).
pub const MAX_SOURCE_BYTES: usize = 256 << 10;
/// The most tokens the object-like macros of one stage may expand to.
pub const MAX_MACRO_TOKENS: u64 = 1 << 20;
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
        if name.is_empty() || body.starts_with('(') {
            continue; // function-like: not estimated
        }
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
