//! Prints the graph of the core's top-level modules, read from `crates/tiler/src`: its layers
//! bottom-up (or its cycles) and every edge with where it is. `cargo run -p tiler --example
//! module-graph`; the `layers` test fails on a cycle.

#[path = "../tests/module_graph/mod.rs"]
mod module_graph;

fn main() {
    let src = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/src"));
    print!("{}", module_graph::ModuleGraph::read(src).render());
}
