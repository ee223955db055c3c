//! Test helpers shared by tiler's crates: where the shared real-world data is (`../shared`
//! beside the workspace: glTF assets, llvmpipe's reference images, apitrace captures), and how
//! a test that needs it and does not find it says so.
//!
//! A test that cannot run reports itself on the process's stderr, past the test harness's
//! capture, so a run without `../shared` shows what it did not check. Where
//! `TILER_REQUIRE_ASSETS` is set (`.ci/run` sets it: CI always has `../shared`), a skip is a
//! failure instead: a CI that silently checked nothing would be green for the wrong reason.

use std::io::Write;
use std::path::{Path, PathBuf};

/// The workspace's root folder.
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// `$TILER_ASSETS`, else `../shared/assets`: the glTF models.
pub fn assets_dir() -> Option<PathBuf> {
    shared_dir("TILER_ASSETS", "assets", "assets")
}

/// `../shared/reference`: llvmpipe's pictures.
pub fn reference_dir() -> Option<PathBuf> {
    shared_dir("TILER_REFERENCE", "reference", "reference images")
}

/// `$TILER_TRACES`, else `../shared/traces`: the apitrace captures.
pub fn traces_dir() -> Option<PathBuf> {
    shared_dir("TILER_TRACES", "traces", "captures")
}

/// `$VAR`, else `../shared/FOLDER` from the workspace root; `None` (after [`skip`]) when it is
/// not a folder.
fn shared_dir(var: &str, folder: &str, what: &str) -> Option<PathBuf> {
    let dir =
        std::env::var_os(var).map(PathBuf::from).unwrap_or_else(|| workspace_root().join("../shared").join(folder));
    if dir.is_dir() {
        Some(dir)
    } else {
        skip(&format!("no {what} at {} (set {var})", dir.display()));
        None
    }
}

/// Reports that the current test cannot run here, and why; panics instead where
/// `TILER_REQUIRE_ASSETS` is set.
pub fn skip(why: &str) {
    let test = std::thread::current().name().unwrap_or("?").to_owned();
    if std::env::var_os("TILER_REQUIRE_ASSETS").is_some() {
        panic!("{test}: {why}, and TILER_REQUIRE_ASSETS is set");
    }
    let _ = writeln!(std::io::stderr(), "skipped: {test}: {why}");
}

/// Where tests write what a person should look at when they fail (`target/tiler-test-output`).
pub fn output_dir() -> PathBuf {
    let dir = workspace_root().join("target/tiler-test-output");
    std::fs::create_dir_all(&dir).expect("creating target/tiler-test-output");
    dir
}
