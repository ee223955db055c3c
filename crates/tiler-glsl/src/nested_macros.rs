//! A workaround for glsl-lang-pp 0.8.1, which does not expand a function-like macro invoked in
//! the arguments of another (`D(D(x))`, `F(D(x))` where `F` calls `D`).
//!
//! C and GLSL expand a macro's arguments before substituting them (C99 §6.10.3.1); glsl-lang-pp
//! substitutes them as written and rescans the result with the outer macro disabled, so an
//! inner `D` stays a call of a function named `D`. Invocations of *other* macros in that rescan
//! expand. So each function-like macro invocation nested `k` deep in macro arguments is renamed
//! to an alias `NAME__tiler_nested_k`, defined with the same parameters and body right after
//! every `#define NAME(…)` (and undefined after every `#undef NAME`). A shader without nested
//! invocations is left as it is. The inserted lines are mapped back to the original line
//! numbers for errors.

use std::collections::HashSet;

/// How deep nested invocations get aliases; deeper ones are left as written (and then fail as
/// an unknown function, naming the line).
const MAX_NESTING: usize = 4;

/// The source with nested invocations renamed and their aliases defined, and for each of its
/// lines the original line it came from (1-based), or `None` when nothing is nested.
pub(crate) fn alias_nested_calls(source: &str) -> Option<(String, Vec<u32>)> {
    let needed = scan(source, |_, _, _| {});
    if needed.is_empty() {
        return None;
    }
    let mut out = String::with_capacity(source.len() * 2);
    let mut lines = Vec::new();
    let mut renames: Vec<(usize, usize, String)> = Vec::new();
    scan(source, |line, at, alias| renames.push((line, at, alias.to_string())));
    let mut logical = String::new();
    let mut function_macros: HashSet<String> = HashSet::new();
    for (index, line) in source.split_inclusive('\n').enumerate() {
        let original = index as u32 + 1;
        // Renames on this line, from the right so earlier offsets stay valid.
        let mut text = line.to_string();
        for (_, at, alias) in renames.iter().rev().filter(|(l, _, _)| *l == index) {
            let name_len = text[*at..].find(|c: char| !is_ident(c)).unwrap_or(text.len() - at);
            text.replace_range(*at..*at + name_len, alias);
        }
        if !text.ends_with('\n') {
            text.push('\n');
        }
        out.push_str(&text);
        lines.push(original);
        // A directive (possibly continued over several lines) ends here: add the aliases.
        let body = text.trim_end_matches(['\n', '\r']);
        let continued = body.ends_with('\\');
        if !logical.is_empty() || body.trim_start().starts_with('#') {
            logical.push_str(body.strip_suffix('\\').unwrap_or(body));
            logical.push(' ');
        }
        if continued || logical.is_empty() {
            continue;
        }
        let directive = std::mem::take(&mut logical);
        let Some(rest) = directive.trim_start().strip_prefix('#') else { continue };
        let rest = rest.trim_start();
        let (keyword, rest) = rest.split_at(rest.find(|c: char| !is_ident(c)).unwrap_or(rest.len()));
        let rest = rest.trim_start();
        let name_len = rest.find(|c: char| !is_ident(c)).unwrap_or(rest.len());
        let (name, after) = rest.split_at(name_len);
        if keyword == "define" && after.starts_with('(') {
            function_macros.insert(name.to_string());
        }
        for (_, k) in needed.iter().filter(|(n, _)| n == name) {
            let alias = alias_name(name, *k);
            match keyword {
                "define" if after.starts_with('(') => {
                    out.push_str(&format!("#define {alias}{}\n", alias_body(after.trim_end(), *k, &function_macros)));
                }
                "undef" => out.push_str(&format!("#undef {alias}\n")),
                _ => continue,
            }
            lines.push(original);
        }
    }
    Some((out, lines))
}

fn alias_name(name: &str, depth: usize) -> String {
    format!("{name}__tiler_nested_{depth}")
}

fn is_ident(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// Walks the non-directive text outside comments, calling `rename(line, byte offset in the
/// line, alias)` for each function-like macro invocation nested in another's arguments; returns
/// the (name, depth) pairs that need aliases, with those the aliases' bodies need in turn.
fn scan(source: &str, mut rename: impl FnMut(usize, usize, &str)) -> Vec<(String, usize)> {
    let mut function_macros: HashSet<String> = HashSet::new();
    // Each definition's parameters and body, "(x) body".
    let mut definitions: Vec<(String, String)> = Vec::new();
    let mut needed: Vec<(String, usize)> = Vec::new();
    let need = |needed: &mut Vec<(String, usize)>, name: &str, depth: usize| {
        if !needed.iter().any(|(n, k)| n == name && *k == depth) {
            needed.push((name.to_string(), depth));
        }
    };
    // Open parentheses: whether each opened a macro's arguments.
    let mut parens: Vec<bool> = Vec::new();
    let mut in_comment = false;
    let mut directive = String::new();
    for (index, line) in source.split_inclusive('\n').enumerate() {
        let body = line.trim_end_matches(['\n', '\r']);
        if !directive.is_empty() || (!in_comment && body.trim_start().starts_with('#')) {
            directive.push_str(body.strip_suffix('\\').unwrap_or(body));
            directive.push(' ');
            if body.ends_with('\\') {
                continue;
            }
            let logical = std::mem::take(&mut directive);
            let rest = logical.trim_start().trim_start_matches('#').trim_start();
            if let Some(rest) = rest.strip_prefix("define") {
                let rest = rest.trim_start();
                let name_len = rest.find(|c: char| !is_ident(c)).unwrap_or(rest.len());
                if name_len > 0 && rest[name_len..].starts_with('(') {
                    function_macros.insert(rest[..name_len].to_string());
                    definitions.push((rest[..name_len].to_string(), rest[name_len..].trim_end().to_string()));
                }
            }
            continue;
        }
        calls(body, &function_macros, &mut parens, &mut in_comment, |at, word, depth| {
            if (1..=MAX_NESTING).contains(&depth) {
                need(&mut needed, word, depth);
                rename(index, at, &alias_name(word, depth));
            }
        });
    }
    // An alias's body calls macros at its own depth and deeper (see `alias_body`).
    let mut i = 0;
    while i < needed.len() {
        let (name, depth) = needed[i].clone();
        for (_, definition) in definitions.iter().filter(|(n, _)| *n == name) {
            let mut parens = Vec::new();
            calls(definition, &function_macros, &mut parens, &mut false, |_, word, j| {
                if depth + j <= MAX_NESTING {
                    need(&mut needed, word, depth + j);
                }
            });
        }
        i += 1;
    }
    needed
}

/// A definition's "(params) body" for its alias at `depth`: the macros it invokes renamed to
/// their aliases at `depth` plus their nesting in the body, since the macros whose arguments
/// the alias stands in are disabled while it expands.
fn alias_body(definition: &str, depth: usize, function_macros: &HashSet<String>) -> String {
    let mut renames = Vec::new();
    let mut parens = Vec::new();
    calls(definition, function_macros, &mut parens, &mut false, |at, word, j| {
        if depth + j <= MAX_NESTING {
            renames.push((at, word.len(), alias_name(word, depth + j)));
        }
    });
    let mut text = definition.to_string();
    for (at, len, alias) in renames.into_iter().rev() {
        text.replace_range(at..at + len, &alias);
    }
    text
}

/// Calls `found(byte offset, name, depth)` for each invocation of a function-like macro in
/// `body` outside comments, `depth` being how many macro argument lists enclose it (carried
/// across lines in `parens`).
fn calls(
    body: &str,
    function_macros: &HashSet<String>,
    parens: &mut Vec<bool>,
    in_comment: &mut bool,
    mut found: impl FnMut(usize, &str, usize),
) {
    let bytes = body.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        if *in_comment {
            match body[i..].find("*/") {
                Some(end) => {
                    *in_comment = false;
                    i += end + 2;
                }
                None => i = bytes.len(),
            }
            continue;
        }
        let c = bytes[i] as char;
        if body[i..].starts_with("//") {
            break;
        }
        if body[i..].starts_with("/*") {
            *in_comment = true;
            i += 2;
            continue;
        }
        if is_ident(c) && !c.is_ascii_digit() {
            let len = body[i..].find(|c: char| !is_ident(c)).unwrap_or(body.len() - i);
            let word = &body[i..i + len];
            let next = body[i + len..].trim_start();
            if function_macros.contains(word) && next.starts_with('(') {
                found(i, word, parens.iter().filter(|m| **m).count());
                // Its '(' opens macro arguments.
                let open = i + len + (body[i + len..].len() - next.len());
                parens.push(true);
                i = open + 1;
                continue;
            }
            i += len;
            continue;
        }
        match c {
            '(' => parens.push(false),
            ')' => {
                parens.pop();
            }
            _ => {}
        }
        // A whole character: text outside identifiers may hold any UTF-8.
        i += body[i..].chars().next().map_or(1, char::len_utf8);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nested_invocations_get_aliases_defined_after_the_macro() {
        let source = "#version 300 es\n#define D(x) ((x) * 2.0)\n#define F(x) D(x)\nfloat a = D(D(1.0));\n\
                      float b = F(D(D(2.0))); // D(D(\n#undef D\n";
        let (text, lines) = alias_nested_calls(source).unwrap();
        assert_eq!(
            text,
            "#version 300 es\n#define D(x) ((x) * 2.0)\n#define D__tiler_nested_1(x) ((x) * 2.0)\n\
             #define D__tiler_nested_2(x) ((x) * 2.0)\n#define F(x) D(x)\nfloat a = D(D__tiler_nested_1(1.0));\n\
             float b = F(D__tiler_nested_1(D__tiler_nested_2(2.0))); // D(D(\n#undef D\n\
             #undef D__tiler_nested_1\n#undef D__tiler_nested_2\n"
        );
        assert_eq!(lines, [1, 2, 2, 2, 3, 4, 5, 6, 6, 6]);
        assert!(alias_nested_calls("#define D(x) x\nfloat a = D(1.0) + D(2.0);\n").is_none());
    }

    #[test]
    fn characters_beyond_ascii_are_stepped_over_whole() {
        let source = "#define D(x) x\nfloat a = D(D(1.0)); // \u{e9}\u{fffd}\nfloat b = \u{fffd}f(1.0);\n";
        assert!(alias_nested_calls(source).is_some());
    }
}
