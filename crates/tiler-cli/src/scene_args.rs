//! Which scene a command renders: the built-in scene, deferred shading made in code, or a glTF
//! file — and how (shading mode, camera, culling, size, samples).

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use tiler::Device;
use tiler_scene::Scene;
use tiler_scene::camera::CameraChoice;
use tiler_scene::deferred::{self, Variant};
use tiler_scene::gltf::Model;
use tiler_scene::shading::{CullPolicy, ModelSceneOptions, Shading, build_model_scene};

/// Which faces `--cull` removes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum CullArg {
    /// Draw both faces of everything.
    None,
    /// Cull back faces of materials that are not doubleSided.
    Gltf,
}

#[derive(Args, Debug, Clone)]
pub struct SceneArgs {
    /// How glTF materials are shaded: `scenes` reproduces SCENES.md (llvmpipe's reference
    /// images: texel values as stored, every texture trilinear and REPEAT, no culling);
    /// `gltf` follows the glTF specification (sRGB textures, the file's samplers, back faces of
    /// single-sided materials culled, BLEND sorted back to front, sRGB output).
    #[arg(long, default_value = "scenes", value_parser = parse_shading)]
    pub shading: Shading,

    /// glTF camera: `auto` (SCENES.md: `interior` for files named sponza*/atrium*, else
    /// `orbit`), `orbit`, `interior`, `gltf` or `gltf:N` (the file's own camera), or
    /// `EX,EY,EZ:TX,TY,TZ[:FOV]` (eye, target, vertical field of view in degrees, default 60).
    #[arg(long, default_value = "auto", value_parser = parse_camera)]
    pub camera: CameraChoice,

    /// Face culling for glTF files; default: `none` with `--shading scenes`, `gltf` with
    /// `--shading gltf`.
    #[arg(long, value_enum)]
    pub cull: Option<CullArg>,

    /// Framebuffer size, WIDTHxHEIGHT [default: 1280x720 for scenes made in code, 1920x1080
    /// (SCENES.md's frame) for a glTF file].
    #[arg(long, value_parser = parse_size)]
    pub size: Option<(u32, u32)>,

    /// Samples per pixel: 1, 2, 4, 8 or 16 (MSAA, resolved in the tile on the tilers).
    #[arg(long, default_value_t = 1, value_parser = parse_samples)]
    pub msaa: u32,
}

/// A scene named on the command line, ready to be built on any device.
pub enum SceneSource {
    Builtin,
    Deferred(Variant),
    /// Deferred shading of a glTF model's opaque primitives.
    DeferredModel(Variant, Box<Model>),
    Model(Box<Model>),
}

impl SceneSource {
    /// The files loading it read (a glTF model, its buffers and images).
    pub fn inputs(&self) -> Vec<PathBuf> {
        match self {
            SceneSource::Model(model) | SceneSource::DeferredModel(_, model) => model.inputs.clone(),
            SceneSource::Builtin | SceneSource::Deferred(_) => Vec::new(),
        }
    }
}

/// The names of the scenes made in code, for help texts.
pub const SCENE_NAMES: &str = "builtin, deferred (deferred shading in one pass with subpasses), deferred-passes (the same \
                               in two passes through memory), deferred:FILE or deferred-passes:FILE (the same on a glTF \
                               model), or a .gltf/.glb file";

impl SceneArgs {
    /// Resolves a scene name or file: glTF files are loaded (once), warnings printed.
    ///
    /// # Errors
    /// A file that does not load, naming it and the object at fault.
    pub fn source(&self, scene: Option<&str>) -> Result<SceneSource> {
        Ok(match scene.unwrap_or("builtin") {
            "builtin" => SceneSource::Builtin,
            "deferred" => SceneSource::Deferred(Variant::Subpasses),
            "deferred-passes" => SceneSource::Deferred(Variant::Passes),
            other => {
                if let Some(file) = other.strip_prefix("deferred:") {
                    SceneSource::DeferredModel(Variant::Subpasses, self.load(file)?)
                } else if let Some(file) = other.strip_prefix("deferred-passes:") {
                    SceneSource::DeferredModel(Variant::Passes, self.load(file)?)
                } else {
                    SceneSource::Model(self.load(other)?)
                }
            }
        })
    }

    /// Loads a glTF file, printing its warnings.
    fn load(&self, file: &str) -> Result<Box<Model>> {
        let path = PathBuf::from(file);
        if path.extension().is_none() && !path.exists() {
            bail!("'{file}' is neither a scene ({SCENE_NAMES}) nor a file");
        }
        let model = tiler_scene::gltf::load(&path, self.shading)?;
        for warning in &model.warnings {
            eprintln!("tiler: warning: {}: {warning}", model.file_name());
        }
        Ok(Box::new(model))
    }

    /// The framebuffer size for a source.
    pub fn size_for(&self, source: &SceneSource) -> (u32, u32) {
        self.size.unwrap_or(match source {
            SceneSource::Model(_) | SceneSource::DeferredModel(..) => (1920, 1080),
            _ => (1280, 720),
        })
    }

    /// Builds the scene on `device`.
    ///
    /// # Errors
    /// A size or sample count the device refuses, or a camera that cannot be placed.
    pub fn build(&self, source: &SceneSource, device: &mut Device) -> Result<Scene> {
        let (width, height) = self.size_for(source);
        Ok(match source {
            SceneSource::Builtin => {
                tiler_scene::builtin::build(device, width, height, self.msaa).context("building the built-in scene")?
            }
            SceneSource::Deferred(variant) => {
                if self.msaa != 1 {
                    bail!("the deferred scenes are single-sample");
                }
                deferred::build(device, width, height, *variant).context("building the deferred scene")?
            }
            SceneSource::DeferredModel(variant, model) => {
                if self.msaa != 1 {
                    bail!("the deferred scenes are single-sample");
                }
                deferred::build_model(device, model, width, height, self.camera, *variant)
                    .with_context(|| format!("building the deferred frame of {}", model.file_name()))?
            }
            SceneSource::Model(model) => {
                let cull = self.cull.map(|c| match c {
                    CullArg::None => CullPolicy::None,
                    CullArg::Gltf => CullPolicy::Gltf,
                });
                let options = ModelSceneOptions {
                    camera: self.camera,
                    cull,
                    samples: self.msaa,
                    ..ModelSceneOptions::new(width, height)
                };
                build_model_scene(device, model, &options)?.0
            }
        })
    }

    /// One line about a glTF model, or nothing for scenes made in code.
    pub fn describe(&self, source: &SceneSource) -> Option<String> {
        let SceneSource::Model(model) = source else { return None };
        Some(format!(
            "{}: {} primitives, {} vertices, {} textures; {} shading",
            model.file_name(),
            model.primitives.len(),
            model.vertices(),
            model.textures_loaded,
            self.shading.name(),
        ))
    }
}

/// Parses `WIDTHxHEIGHT`.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| format!("'{s}' is not WIDTHxHEIGHT (e.g. 1280x720)"))?;
    let parse = |v: &str| v.trim().parse::<u32>().map_err(|_| format!("'{v}' in '{s}' is not a whole number"));
    Ok((parse(w)?, parse(h)?))
}

/// Parses a sample count (`--msaa`) that images may have: the core's own check, so the
/// command line accepts exactly what `ImageDesc::validate` does.
pub fn parse_samples(s: &str) -> Result<u32, String> {
    let samples = s.trim().parse::<u32>().map_err(|_| format!("'{s}' is not a whole number"))?;
    tiler::ImageDesc::new(1, 1, tiler::Format::Rgba8Unorm)
        .with_samples(samples)
        .validate()
        .map_err(|e| e.to_string())?;
    Ok(samples)
}

fn parse_shading(s: &str) -> Result<Shading, String> {
    s.parse()
}

fn parse_camera(s: &str) -> Result<CameraChoice, String> {
    s.parse()
}
