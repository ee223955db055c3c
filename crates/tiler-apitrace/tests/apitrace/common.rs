//! Where the shared captures and reference images are.

use std::path::PathBuf;

pub use tiler_test_support::{reference_dir, traces_dir};

/// The glmark2 captures, sorted by name, with their scene names.
pub fn glmark2_traces() -> Option<Vec<(String, PathBuf)>> {
    let dir = traces_dir()?.join("glmark2");
    let mut traces: Vec<(String, PathBuf)> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("listing {}: {e}", dir.display()))
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|ext| ext == "trace"))
        .map(|path| (path.file_stem().unwrap().to_string_lossy().into_owned(), path))
        .collect();
    traces.sort();
    assert!(!traces.is_empty(), "no .trace files in {}", dir.display());
    Some(traces)
}
