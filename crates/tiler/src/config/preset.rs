//! Device presets: named GPUs as data — a TOML or JSON file holding a name, a description and
//! a [`DeviceConfig`]. The built-in ones live in `crates/tiler/presets/`, each number with
//! where it comes from; `tiler --device FILE` loads another.
//!
//! ```toml
//! name = "my-gpu"
//! description = "what it models"
//! [device]
//! backend = "tbdr"          # tbr | tbdr | imr
//! tile_width = 32
//! tile_height = 16
//! [device.energy]
//! external_pj_per_byte = 120.0
//! [device.time]             # the time estimate's figures (ledger::time), each with its source
//! clock_mhz = 848.0
//! cores = 7
//! vertices_per_clock = 2.0
//! pixels_per_clock = 4.0
//! texels_per_clock = 8.0
//! blended_samples_per_clock = 4.0
//! bandwidth_gb_per_s = 51.2
//! frames_in_flight = 3
//! ```
//!
//! Fields left out take [`DeviceConfig::default`]'s values; unknown fields are errors.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::DeviceConfig;
use crate::api::error::{Error, Result};

/// A named device configuration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DevicePreset {
    pub name: String,
    pub description: String,
    #[serde(default)]
    pub device: DeviceConfig,
}

/// The built-in presets' files, in the order `tiler compare` shows them.
const BUILTIN: [(&str, &str); 9] = [
    ("tbr", include_str!("../../presets/tbr.toml")),
    ("tbdr", include_str!("../../presets/tbdr.toml")),
    ("tbr-per-tile-vertex", include_str!("../../presets/tbr-per-tile-vertex.toml")),
    ("imr", include_str!("../../presets/imr.toml")),
    ("imr-no-cache", include_str!("../../presets/imr-no-cache.toml")),
    ("mali-g710", include_str!("../../presets/mali-g710.toml")),
    ("adreno-650", include_str!("../../presets/adreno-650.toml")),
    ("powervr-gx6450", include_str!("../../presets/powervr-gx6450.toml")),
    ("desktop-imr", include_str!("../../presets/desktop-imr.toml")),
];

impl DevicePreset {
    /// Every built-in preset.
    pub fn builtins() -> Vec<DevicePreset> {
        BUILTIN
            .iter()
            .map(|(name, text)| DevicePreset::parse_toml(text, name).expect("built-in presets are valid"))
            .collect()
    }

    /// The names of the built-in presets.
    pub fn builtin_names() -> Vec<&'static str> {
        BUILTIN.iter().map(|(name, _)| *name).collect()
    }

    /// A built-in preset by name.
    ///
    /// # Errors
    /// No built-in preset has that name.
    pub fn builtin(name: &str) -> Result<DevicePreset> {
        match BUILTIN.iter().find(|(n, _)| *n == name) {
            Some((n, text)) => DevicePreset::parse_toml(text, n),
            None => Err(Error::invalid(
                format!("device preset '{name}'"),
                format!("no such built-in preset (built-in: {})", DevicePreset::builtin_names().join(", ")),
            )),
        }
    }

    /// A preset from a built-in name or a `.toml` / `.json` file.
    ///
    /// # Errors
    /// An unreadable or invalid file, naming it and the field at fault.
    pub fn load(name_or_path: &str) -> Result<DevicePreset> {
        if BUILTIN.iter().any(|(n, _)| *n == name_or_path) {
            return DevicePreset::builtin(name_or_path);
        }
        DevicePreset::from_file(Path::new(name_or_path))
    }

    /// The largest preset file read: presets are a few hundred bytes.
    pub const MAX_FILE_BYTES: u64 = 1 << 20;

    /// Reads a preset file: JSON if its name ends in `.json`, TOML otherwise. Only a regular
    /// file of at most [`MAX_FILE_BYTES`](Self::MAX_FILE_BYTES) is read (a device or a FIFO is
    /// refused, not read forever or waited on).
    pub fn from_file(path: &Path) -> Result<DevicePreset> {
        let what = path.display().to_string();
        let text = tiler_io::read_text(path, Self::MAX_FILE_BYTES).map_err(|e| Error::invalid(&what, e.message))?;
        if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("json")) {
            DevicePreset::parse_json(&text, &what)
        } else {
            DevicePreset::parse_toml(&text, &what)
        }
    }

    /// Parses TOML; `what` names the source in errors.
    pub fn parse_toml(text: &str, what: &str) -> Result<DevicePreset> {
        let preset: DevicePreset =
            toml::from_str(text).map_err(|e| Error::invalid(what, e.to_string().trim().to_string()))?;
        preset.validated(what)
    }

    /// Parses JSON; `what` names the source in errors.
    pub fn parse_json(text: &str, what: &str) -> Result<DevicePreset> {
        let preset: DevicePreset = serde_json::from_str(text).map_err(|e| Error::invalid(what, e.to_string()))?;
        preset.validated(what)
    }

    fn validated(self, what: &str) -> Result<DevicePreset> {
        self.device.validate().map_err(|e| Error::invalid(what, e.to_string()))?;
        Ok(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Backend;

    #[test]
    fn builtins_parse_and_cover_the_three_architectures() {
        let presets = DevicePreset::builtins();
        for backend in Backend::ALL {
            assert!(presets.iter().any(|p| p.device.backend == backend), "{backend}");
        }
        assert_eq!(DevicePreset::builtin("tbr").unwrap().device.tile_width, 16);
    }

    /// The real GPUs of each kind, and the generic presets' time figures are theirs (seed
    /// 004 Table 24.1's desktop for immediate mode); tilers keep one frame more in flight.
    #[test]
    fn real_gpus_give_the_generic_presets_their_time_figures() {
        let time = |name: &str| DevicePreset::builtin(name).unwrap().device.time;
        assert_eq!(time("tbr"), time("mali-g710"));
        assert_eq!(time("tbdr"), time("powervr-gx6450"));
        assert_eq!(time("tbr-per-tile-vertex"), time("adreno-650"));
        assert_eq!(time("imr"), time("imr-no-cache"));
        assert_eq!(time("imr").bandwidth_gb_per_s, 25.7);
        assert_eq!(DeviceConfig::default().time, time("mali-g710"));
        for preset in DevicePreset::builtins() {
            let expected = if preset.device.backend.is_tiler() { 3 } else { 2 };
            assert_eq!(preset.device.time.frames_in_flight, expected, "{}", preset.name);
        }
        let time_table = "[device.time]\ncores = 1\nvertices_per_clock = 1.0\npixels_per_clock = 1.0\n\
            texels_per_clock = 1.0\nblended_samples_per_clock = 1.0\nbandwidth_gb_per_s = 1.0\nframes_in_flight = 2\n";
        let e = DevicePreset::parse_toml(&format!("name = \"x\"\ndescription = \"y\"\n{time_table}"), "gpu.toml")
            .unwrap_err();
        assert!(e.to_string().contains("gpu.toml") && e.to_string().contains("clock_mhz"), "{e}");
        let e = DevicePreset::parse_toml(
            &format!("name = \"x\"\ndescription = \"y\"\n{time_table}clock_mhz = -1.0\n"),
            "gpu.toml",
        )
        .unwrap_err();
        assert!(e.to_string().contains("gpu.toml") && e.to_string().contains("clock_mhz"), "{e}");
    }

    #[test]
    fn errors_name_the_file_and_field() {
        let e = DevicePreset::parse_toml("name = \"x\"\ndescription = \"y\"\n[device]\ntile_widht = 16\n", "gpu.toml")
            .unwrap_err();
        assert!(e.to_string().contains("gpu.toml") && e.to_string().contains("tile_widht"), "{e}");
        let e = DevicePreset::parse_toml("name = \"x\"\ndescription = \"y\"\n[device]\ntile_width = 12\n", "gpu.toml")
            .unwrap_err();
        assert!(e.to_string().contains("multiple of 8"), "{e}");
        let e = DevicePreset::parse_json("{\"name\": 3}", "gpu.json").unwrap_err();
        assert!(e.to_string().contains("gpu.json"), "{e}");
        let json = serde_json::to_string(&DevicePreset::builtin("imr").unwrap()).unwrap();
        assert_eq!(DevicePreset::parse_json(&json, "round trip").unwrap(), DevicePreset::builtin("imr").unwrap());
    }

    /// Issue 13: `line_bytes × ways` wrapped around `u32` and passed validation; the device
    /// then tried to allocate the cache model's lines and aborted.
    #[test]
    fn cache_shapes_that_overflow_are_refused_by_name() {
        let preset = |table: &str, size: u64, line: u64, ways: u64| {
            format!(
                "name = \"x\"\ndescription = \"y\"\n[device.{table}]\nsize_bytes = {size}\nline_bytes = {line}\nways = {ways}\n"
            )
        };
        // 4096 × (2^20 + 1) = 2^32 + 4096 ≡ 4096 (mod 2^32): a "whole set" of 4096 bytes.
        for (size, line, ways) in [(4096, 4096, (1 << 20) + 1), (1 << 26, 4096, 1 << 20), (4096, 64, u32::MAX as u64)] {
            let e = DevicePreset::parse_toml(&preset("framebuffer_cache", size, line, ways), "gpu.toml").unwrap_err();
            assert!(e.to_string().contains("gpu.toml") && e.to_string().contains("framebuffer cache"), "{e}");
            let e = DevicePreset::parse_toml(&preset("texture_cache", size, line, ways), "gpu.toml").unwrap_err();
            assert!(e.to_string().contains("gpu.toml") && e.to_string().contains("texture cache"), "{e}");
        }
        // Too many lines for the model, though the size is within 64 MiB.
        let e = DevicePreset::parse_toml(&preset("framebuffer_cache", 64 << 20, 4, 1), "gpu.toml").unwrap_err();
        assert!(e.to_string().contains("lines"), "{e}");
        // The largest shapes accepted build their cache models.
        let device =
            DevicePreset::parse_toml(&preset("framebuffer_cache", 64 << 20, 64, 16), "gpu.toml").unwrap().device;
        crate::ledger::cache::CacheModel::new(device.framebuffer_cache);
        let device = DevicePreset::parse_toml(&preset("texture_cache", 64 << 20, 4096, 64), "gpu.toml").unwrap().device;
        crate::shade::texture_cache::TextureCache::new(device.texture_cache);
    }

    /// A preset file that is a device or a FIFO is refused, not read until memory runs out or
    /// waited on forever; an oversized one is refused by its size (issue 13).
    #[cfg(unix)]
    #[test]
    fn preset_files_must_be_small_regular_files() {
        let e = DevicePreset::from_file(Path::new("/dev/zero")).unwrap_err();
        assert!(e.to_string().contains("/dev/zero"), "{e}");
        let dir = std::env::temp_dir().join(format!("tiler-preset-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let fifo = dir.join("gpu.toml");
        let _ = std::fs::remove_file(&fifo);
        assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
        let e = DevicePreset::from_file(&fifo).unwrap_err();
        assert!(e.to_string().contains("gpu.toml"), "{e}");
        let big = dir.join("big.toml");
        std::fs::write(&big, vec![b'#'; DevicePreset::MAX_FILE_BYTES as usize + 1]).unwrap();
        let e = DevicePreset::from_file(&big).unwrap_err();
        assert!(e.to_string().contains("limit"), "{e}");
        let e = DevicePreset::from_file(&dir).unwrap_err();
        assert!(e.to_string().contains(&*dir.to_string_lossy()), "{e}");
    }
}
