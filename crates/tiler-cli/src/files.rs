//! The files a command reads and writes beyond its scene: outputs checked before any work
//! (a known format, a place to write, never one of the command's inputs) and written
//! atomically, and device presets read through `tiler_io`'s caps. The rules themselves live in
//! `tiler_io`.

use std::path::{Path, PathBuf};

use anyhow::{Result, anyhow, bail};
use tiler::{DeviceConfig, DevicePreset};

/// Checks that `path` can take an output of the option `what` and is none of `inputs`.
///
/// # Errors
/// A directory, a special file, a missing folder, or an input, naming the path.
pub fn check_output(what: &str, path: &Path, inputs: &[PathBuf]) -> Result<()> {
    tiler_io::check_output(what, path, inputs).map_err(|e| anyhow!(e))
}

/// [`check_output`] for a picture: tiler writes RGBA pictures as PNG, so the name must end in
/// `.png` (an RGBA frame has no JPEG form, and finding that out after rendering would leave
/// nothing written).
///
/// # Errors
/// As [`check_output`], and another extension.
pub fn check_png(what: &str, path: &Path, inputs: &[PathBuf]) -> Result<()> {
    check_output(what, path, inputs)?;
    if !path.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) {
        bail!("{what} {}: pictures are written as PNG; the name must end in .png", path.display());
    }
    Ok(())
}

/// Checks that `dir` can hold outputs: a folder, or a name free for one.
///
/// # Errors
/// `dir` is a file or a special file.
pub fn check_dir(what: &str, dir: &Path) -> Result<()> {
    tiler_io::check_output_dir(what, dir).map_err(|e| anyhow!(e))
}

/// Writes RGBA8 pixels as a PNG, atomically.
///
/// # Errors
/// A file that cannot be written, naming it.
pub fn write_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> Result<()> {
    tiler_scene::compare::write_png(path, width, height, rgba).map_err(|e| anyhow!("writing {e}"))
}

/// The preset `name` names: a built-in one, or a `.toml` / `.json` file (read as a regular file
/// of at most a megabyte), with the file when there is one. `None`: tiler's default device.
///
/// # Errors
/// An unreadable or invalid file, naming it.
pub fn load_preset(name: Option<&str>) -> Result<(DevicePreset, Option<PathBuf>)> {
    let Some(name) = name else {
        return Ok((
            DevicePreset {
                name: "default".into(),
                description: "tiler's default device: 32×32 tiles, 32 KiB tile memory, early-Z, no framebuffer cache"
                    .into(),
                device: DeviceConfig::default(),
            },
            None,
        ));
    };
    if DevicePreset::builtin_names().contains(&name) {
        return Ok((DevicePreset::builtin(name)?, None));
    }
    let path = PathBuf::from(name);
    let preset = DevicePreset::from_file(&path)?;
    Ok((preset, Some(path)))
}
