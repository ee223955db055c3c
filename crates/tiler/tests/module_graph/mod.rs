//! The graph of the core's top-level modules, read from its sources: module `a` depends on `b`
//! when a file of `a` names `crate::b…` (in a `use`, a path, or a brace group `crate::{b, …}`),
//! or names an item the crate root re-exports from `b` (`crate::Format` is `api`'s).
//! Comments are skipped, so doc links do not count. Shared by the `layers` test and the
//! `module-graph` example.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Where each dependency was seen: `(file, line)`, for the report.
pub type Sites = Vec<(String, usize)>;

/// Top-level modules and, for each, the modules it depends on with where.
pub struct ModuleGraph {
    pub modules: Vec<String>,
    pub edges: BTreeMap<String, BTreeMap<String, Sites>>,
}

impl ModuleGraph {
    /// Reads `src` (the crate's `src` directory).
    pub fn read(src: &Path) -> ModuleGraph {
        let lib = std::fs::read_to_string(src.join("lib.rs")).expect("read lib.rs");
        let lib = strip_comments(&lib);
        let modules: Vec<String> = lib
            .lines()
            .filter_map(|l| {
                let l = l.trim();
                // `mod x;` after any visibility (`pub`, `pub(crate)`, …).
                let l = match l.strip_prefix("pub") {
                    Some(rest) if rest.starts_with('(') => rest[rest.find(')')? + 1..].trim_start(),
                    Some(rest) => rest.trim_start(),
                    None => l,
                };
                let rest = l.strip_prefix("mod ")?;
                let name = rest.strip_suffix(';')?.trim();
                Some(name.to_string())
            })
            .collect();
        let reexports = root_reexports(&lib, &modules);
        let mut edges: BTreeMap<String, BTreeMap<String, Sites>> =
            modules.iter().map(|m| (m.clone(), BTreeMap::new())).collect();
        for module in &modules {
            let dir = src.join(module);
            let mut files = Vec::new();
            if dir.is_dir() {
                collect_rs(&dir, &mut files);
            }
            let single = src.join(format!("{module}.rs"));
            if single.is_file() {
                files.push(single);
            }
            files.sort();
            for file in files {
                let text = strip_comments(&std::fs::read_to_string(&file).expect("read source"));
                let shown = file.strip_prefix(src).unwrap_or(&file).display().to_string();
                for (line_index, line) in text.lines().enumerate() {
                    for target in crate_references(line, &modules, &reexports) {
                        if &target != module {
                            edges
                                .get_mut(module)
                                .unwrap()
                                .entry(target)
                                .or_default()
                                .push((shown.clone(), line_index + 1));
                        }
                    }
                }
            }
        }
        ModuleGraph { modules, edges }
    }

    /// Groups of modules that depend on each other (strongly connected components of more than
    /// one module), each sorted.
    pub fn cycles(&self) -> Vec<Vec<String>> {
        // Tarjan's algorithm, recursive: a dozen modules.
        struct State<'g> {
            graph: &'g ModuleGraph,
            index: BTreeMap<&'g str, usize>,
            low: BTreeMap<&'g str, usize>,
            stack: Vec<&'g str>,
            on_stack: BTreeSet<&'g str>,
            components: Vec<Vec<String>>,
        }
        fn visit<'g>(s: &mut State<'g>, v: &'g str) {
            let i = s.index.len();
            s.index.insert(v, i);
            s.low.insert(v, i);
            s.stack.push(v);
            s.on_stack.insert(v);
            for w in s.graph.edges[v].keys() {
                let w = w.as_str();
                if !s.index.contains_key(w) {
                    visit(s, w);
                    let low = s.low[v].min(s.low[w]);
                    s.low.insert(v, low);
                } else if s.on_stack.contains(w) {
                    let low = s.low[v].min(s.index[w]);
                    s.low.insert(v, low);
                }
            }
            if s.low[v] == s.index[v] {
                let mut component = Vec::new();
                loop {
                    let w = s.stack.pop().unwrap();
                    s.on_stack.remove(w);
                    component.push(w.to_string());
                    if w == v {
                        break;
                    }
                }
                if component.len() > 1 {
                    component.sort();
                    s.components.push(component);
                }
            }
        }
        let mut state = State {
            graph: self,
            index: BTreeMap::new(),
            low: BTreeMap::new(),
            stack: Vec::new(),
            on_stack: BTreeSet::new(),
            components: Vec::new(),
        };
        for m in &self.modules {
            if !state.index.contains_key(m.as_str()) {
                visit(&mut state, m);
            }
        }
        state.components
    }

    /// The modules bottom-up (each after everything it depends on), when there is no cycle.
    pub fn layers(&self) -> Option<Vec<Vec<String>>> {
        let mut placed: BTreeMap<&str, usize> = BTreeMap::new();
        let mut layers: Vec<Vec<String>> = Vec::new();
        while placed.len() < self.modules.len() {
            let ready: Vec<&str> = self
                .modules
                .iter()
                .map(String::as_str)
                .filter(|m| !placed.contains_key(m) && self.edges[*m].keys().all(|d| placed.contains_key(d.as_str())))
                .collect();
            if ready.is_empty() {
                return None;
            }
            for m in &ready {
                placed.insert(m, layers.len());
            }
            layers.push(ready.iter().map(|m| m.to_string()).collect());
        }
        Some(layers)
    }

    /// The graph as text: the layers bottom-up (or the cycles), then every edge with its first
    /// site.
    pub fn render(&self) -> String {
        let mut out = String::new();
        match self.layers() {
            Some(layers) => {
                out.push_str("layers, bottom up (a module depends only on modules of lower layers):\n");
                for (i, layer) in layers.iter().enumerate() {
                    out.push_str(&format!("  {i:2}: {}\n", layer.join(", ")));
                }
            }
            None => {
                out.push_str("CYCLES (modules that depend on each other):\n");
                for cycle in self.cycles() {
                    out.push_str(&format!("  {}\n", cycle.join(" ⇄ ")));
                }
            }
        }
        out.push_str("edges (module → dependency: first site, uses):\n");
        for (from, targets) in &self.edges {
            for (to, sites) in targets {
                let (file, line) = &sites[0];
                out.push_str(&format!("  {from} → {to}: {file}:{line} ({} uses)\n", sites.len()));
            }
        }
        out
    }
}

fn collect_rs(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("read source directory") {
        let path = entry.expect("directory entry").path();
        if path.is_dir() {
            collect_rs(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The text with `//` and `/* */` comments blanked (line breaks kept) and string literals
/// emptied, so only code is searched.
fn strip_comments(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let chars: Vec<char> = text.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            i += 2;
            while i < chars.len() && !(chars[i] == '*' && chars.get(i + 1) == Some(&'/')) {
                if chars[i] == '\n' {
                    out.push('\n');
                }
                i += 1;
            }
            i += 2;
        } else if c == '"' {
            out.push('"');
            i += 1;
            while i < chars.len() && chars[i] != '"' {
                if chars[i] == '\\' {
                    i += 1;
                }
                if chars.get(i) == Some(&'\n') {
                    out.push('\n');
                }
                i += 1;
            }
            out.push('"');
            i += 1;
        } else if c == '\'' && next.is_some() && chars.get(i + 2) == Some(&'\'') {
            // A character literal such as '"'.
            out.push_str("' '");
            i += 3;
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

/// Item name → module, for `pub use module::…::{a, b}` lines of the crate root.
fn root_reexports(lib: &str, modules: &[String]) -> BTreeMap<String, String> {
    let mut map = BTreeMap::new();
    // `pub use` statements may span lines: join them up to their `;`.
    for statement in lib.split(';') {
        let statement = statement.split_whitespace().collect::<Vec<_>>().join(" ");
        let Some(path) = statement.strip_prefix("pub use ") else { continue };
        let path = path.strip_prefix("crate::").unwrap_or(path);
        let Some(module) = modules.iter().find(|m| path.starts_with(&format!("{m}::"))) else { continue };
        let names = match (path.find('{'), path.rfind('}')) {
            (Some(open), Some(close)) => path[open + 1..close].to_string(),
            _ => path.rsplit("::").next().unwrap_or("").to_string(),
        };
        for name in names.split(',') {
            let name = name.trim();
            let name = name.rsplit(" as ").next().unwrap_or(name).rsplit("::").next().unwrap_or(name).trim();
            if !name.is_empty() {
                map.insert(name.to_string(), module.clone());
            }
        }
    }
    map
}

/// The top-level modules a line of code names through `crate::`.
fn crate_references(line: &str, modules: &[String], reexports: &BTreeMap<String, String>) -> Vec<String> {
    let mut found = Vec::new();
    let mut rest = line;
    while let Some(at) = rest.find("crate::") {
        // `$crate::` and `tiler_crate::` are not this crate's root.
        let before = rest[..at].chars().last();
        let after = &rest[at + "crate::".len()..];
        rest = after;
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '$') {
            continue;
        }
        let heads: Vec<String> = if let Some(group) = after.strip_prefix('{') {
            // `crate::{a::x, b}`: the first segment of each top-level item of the group.
            let mut depth = 0;
            let mut items = vec![String::new()];
            for c in group.chars() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => break,
                    '}' => depth -= 1,
                    ',' if depth == 0 => items.push(String::new()),
                    _ if depth == 0 => items.last_mut().unwrap().push(c),
                    _ => {}
                }
            }
            items.iter().map(|i| identifier(i.trim())).collect()
        } else {
            vec![identifier(after)]
        };
        for head in heads {
            if modules.contains(&head) {
                found.push(head);
            } else if let Some(module) = reexports.get(&head) {
                found.push(module.clone());
            }
        }
    }
    found
}

fn identifier(s: &str) -> String {
    s.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect()
}
