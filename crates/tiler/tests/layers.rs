//! The core's top-level modules form a DAG in data-flow order (issue 12): a cycle between
//! them is a defect. This reads `src`, prints the graph (`cargo test -p tiler --test layers --
//! --nocapture`, or `cargo run -p tiler --example module-graph`) and fails on a cycle, naming
//! the modules and where each of their imports is.
//!
//! It also holds the SIMD dispatch to what detection checks: every `#[target_feature]` of the
//! crate (benches included) enables exactly `simd::AVX2_FEATURES`.

mod module_graph;

use std::path::Path;

use module_graph::ModuleGraph;

fn src() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/src"))
}

#[test]
fn top_level_modules_form_a_dag() {
    let graph = ModuleGraph::read(src());
    println!("{}", graph.render());
    assert!(graph.modules.len() >= 10, "found only {:?} in lib.rs", graph.modules);
    let cycles = graph.cycles();
    let mut report = String::new();
    for cycle in &cycles {
        report.push_str(&format!("cycle: {}\n", cycle.join(" ⇄ ")));
        for from in cycle {
            for (to, sites) in &graph.edges[from] {
                if cycle.contains(to) {
                    let shown: Vec<String> = sites.iter().take(3).map(|(f, l)| format!("{f}:{l}")).collect();
                    report.push_str(&format!("  {from} → {to}: {}\n", shown.join(", ")));
                }
            }
        }
    }
    assert!(cycles.is_empty(), "top-level modules import each other:\n{report}");
    assert!(graph.layers().is_some());
}

#[test]
fn the_graph_reader_finds_cycles() {
    // Two modules naming each other (one through a brace group, one through a root
    // re-export), and comments and strings that must not count.
    let dir = std::env::temp_dir().join(format!("tiler-layers-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("b")).unwrap();
    std::fs::write(
        dir.join("lib.rs"),
        "pub mod a;\npub(crate) mod b;\nmod c;\npub use b::thing::{Thing, Other as O};\n",
    )
    .unwrap();
    std::fs::write(dir.join("a.rs"), "use crate::{b::x, c};\n// crate::a is not code\n").unwrap();
    std::fs::write(dir.join("b/mod.rs"), "pub mod thing;\n").unwrap();
    std::fs::write(dir.join("b/thing.rs"), "fn f() -> crate::Other { todo!() }\nconst S: &str = \"crate::c\";\n")
        .unwrap();
    std::fs::write(dir.join("c.rs"), "/* crate::a */ fn g(_: crate::Thing) {}\n").unwrap();
    let graph = ModuleGraph::read(&dir);
    let keys = |m: &str| graph.edges[m].keys().cloned().collect::<Vec<_>>();
    assert_eq!(keys("a"), ["b", "c"]);
    assert_eq!(keys("b"), ["b"; 0]);
    assert_eq!(keys("c"), ["b"]);
    assert!(graph.cycles().is_empty());
    std::fs::write(dir.join("b/thing.rs"), "use crate::a::f;\n").unwrap();
    let graph = ModuleGraph::read(&dir);
    assert_eq!(graph.cycles(), [["a", "b", "c"]]);
    assert!(graph.layers().is_none());
    assert!(graph.render().contains("a ⇄ b ⇄ c"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn avx2_code_enables_only_the_features_detection_checks() {
    let simd = std::fs::read_to_string(src().join("simd.rs")).unwrap();
    let line = simd.lines().find(|l| l.starts_with("pub const AVX2_FEATURES")).expect("simd::AVX2_FEATURES");
    let list = &line[line.find("= [").expect("an array") + 3..line.rfind(']').unwrap()];
    let declared: Vec<String> = list.split(',').map(|f| f.trim().trim_matches('"').to_string()).collect();
    assert!(declared.contains(&"avx2".to_string()), "{declared:?}");
    let mut files = Vec::new();
    for dir in ["src", "benches"] {
        collect(&Path::new(env!("CARGO_MANIFEST_DIR")).join(dir), &mut files);
    }
    let mut seen = 0;
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        for (i, line) in text.lines().enumerate() {
            let Some(at) = line.find("#[target_feature(enable = \"") else { continue };
            let rest = &line[at + "#[target_feature(enable = \"".len()..];
            let enabled: Vec<&str> = rest[..rest.find('"').unwrap()].split(',').map(str::trim).collect();
            assert_eq!(enabled, declared, "{}:{}: enables other features than detection checks", file.display(), i + 1);
            seen += 1;
        }
    }
    assert!(seen >= 3, "found only {seen} #[target_feature] functions");
}

fn collect(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            collect(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}
