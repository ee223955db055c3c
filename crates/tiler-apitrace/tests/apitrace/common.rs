//! Where the shared captures and reference images are.

use std::path::{Path, PathBuf};

/// `$TILER_TRACES`, else `../shared/traces` from the workspace root; `None` (and a note) when
/// absent, so tests that need it skip.
pub fn traces_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("TILER_TRACES")
        .map(PathBuf::from)
        .unwrap_or_else(|| workspace_root().join("../shared/traces"));
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!("skipping: no captures at {} (set TILER_TRACES)", dir.display());
        None
    }
}

/// `../shared/reference` beside the workspace, if present.
pub fn reference_dir() -> Option<PathBuf> {
    let dir = workspace_root().join("../shared/reference");
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!("skipping: no reference images at {}", dir.display());
        None
    }
}

pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

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
