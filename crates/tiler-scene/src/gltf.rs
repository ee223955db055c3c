//! glTF 2.0 loading: `.gltf` (external or `data:` buffers and images) and `.glb`, checked at
//! the front door and flattened into world-space triangle lists ready to draw.
//!
//! What is read, after SCENES.md §4.2 (the rules llvmpipe's reference images were made with):
//!
//! - **Scene.** The default scene (`scene`, else scene 0; without scenes, every node that is
//!   no node's child), depth first, children in file order. A node's world matrix is
//!   `parent · local`, local = `matrix` (column-major) when present and not the identity, else
//!   `T · R · S`. Every node with a mesh draws every primitive of it (a mesh used by k nodes is
//!   drawn k times). Cameras of the scene's nodes are kept, in traversal order.
//! - **Primitives.** Triangles (indexed or not), triangle strips and fans converted to lists
//!   (strips: odd triangles `(i+1, i, i+2)`; fans: `(i+1, i+2, 0)`, glTF §3.7.2.1); points and
//!   lines are skipped with a warning. An index count that is not a multiple of 3 is
//!   truncated.
//! - **Vertices**, transformed at load in double precision and stored as `f32` (32 bytes:
//!   position, normal, uv): `p_world = M · (p, 1)`; `n_world = normalize(inverse(M3)ᵀ · n)`
//!   (zero stays zero); NORMAL absent: the sum of the unnormalised face normals
//!   `cross(p1 − p0, p2 − p0)` of the triangles using the vertex ([`Shading::Scenes`]), or
//!   true flat normals, each triangle with vertices of its own ([`Shading::Gltf`], as the glTF
//!   specification asks); TEXCOORD_0 as floats or normalised integers, absent: (0, 0). When
//!   `det(M3) < 0` the winding is reversed so front faces stay front faces.
//! - **Materials**: `pbrMetallicRoughness.baseColorFactor` and `baseColorTexture` with its
//!   sampler, `alphaMode`/`alphaCutoff`, `doubleSided`. Other textures are not loaded. Images
//!   are PNG or JPEG, decoded to RGBA8 (grey and RGB expanded, alpha 255 when absent), row 0 at
//!   `v = 0`; only images some drawn primitive uses are decoded.
//!
//! **Hostile files.** A model is a file people download, so loading it is safe whatever it
//! holds: the files it names are read only from its folder, only if they are regular files,
//! and through caps checked as bytes arrive (`tiler_io`); every size, count and offset taken
//! from it is checked arithmetic; the node hierarchy is walked without recursion; and what
//! parsing and drawing it may cost is bounded ([`MAX_JSON_BYTES`], [`MAX_LOADED_BYTES`],
//! [`MAX_ACCESSOR_ELEMENTS`], [`MAX_DRAWN_PRIMITIVES`], [`MAX_NODE_VISITS`]). Only glTF 2.x is
//! read (`asset.version`).
//!
//! Errors name the file and the object at fault (`Box.gltf: accessor 3: …`). A required
//! extension is refused (tiler supports none: Draco, meshopt, texture transforms, …); an optional
//! one is ignored with a warning. A missing or undecodable *image* is a warning and the
//! material is drawn untextured (base colour factor only), as the reference renders did; a
//! missing *buffer* is an error.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DMat3, DMat4, DVec3, DVec4};
use gltf::json;
use tiler::{ColorSpace, Filter, MipChain, MipmapMode, Sampler, Texture, Wrap};

use crate::shading::Shading;

/// The largest glTF JSON read (a `.gltf` file, or a GLB's JSON chunk). Parsing costs several
/// times the text (the glTF crate's structures are ~300 bytes a node), so this bounds the
/// memory of the parse to about a gigabyte; the largest JSON of the sample models is well
/// under a megabyte.
pub const MAX_JSON_BYTES: u64 = 32 << 20;
/// Bytes of files one model may read: the glTF or GLB, its buffers and images, and its data
/// URIs decoded.
pub const MAX_LOADED_BYTES: u64 = 1 << 30;
/// Elements of one accessor (16 Mi: a POSITION accessor read as doubles is then 384 MiB).
pub const MAX_ACCESSOR_ELEMENTS: usize = 1 << 24;
/// Primitives the default scene may draw, over all the nodes that use them (the sample
/// models draw at most a few hundred; each costs a draw, its buffers and its records).
pub const MAX_DRAWN_PRIMITIVES: usize = 1 << 17;
/// Vertices the default scene may draw, summed over its primitives (32 bytes each).
pub const MAX_DRAWN_VERTICES: u64 = 1 << 25;
/// Nodes the traversal may visit (a node reached along k paths counts k times, so a small
/// file whose nodes each name the next one twice cannot make it visit 2^n nodes).
pub const MAX_NODE_VISITS: usize = 1 << 20;

/// A glTF file that could not be loaded: the file, and what is wrong where.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{file}: {message}")]
pub struct LoadError {
    pub file: String,
    pub message: String,
}

/// One vertex as the glTF shaders read it (32 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GltfVertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
}

/// How a material's alpha is used (glTF `alphaMode`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AlphaMode {
    /// Alpha ignored, written as 1.
    Opaque,
    /// Fragments whose alpha is below the cutoff are discarded; written alpha 1.
    Mask { cutoff: f32 },
    /// Blended over what is behind, after the opaque geometry, without depth writes.
    Blend,
}

/// A base-colour texture with its sampler.
#[derive(Clone, Debug)]
pub struct TextureBinding {
    pub texture: Arc<Texture>,
    pub sampler: Sampler,
    /// The glTF image it came from.
    pub image: usize,
}

/// A material as the shading models use it.
#[derive(Clone, Debug)]
pub struct Material {
    pub name: String,
    pub base_color_factor: [f32; 4],
    pub base_color_texture: Option<TextureBinding>,
    pub alpha_mode: AlphaMode,
    pub double_sided: bool,
}

impl Material {
    /// glTF's default material: white, opaque, single-sided.
    pub fn default_material() -> Material {
        Material {
            name: "default".into(),
            base_color_factor: [1.0; 4],
            base_color_texture: None,
            alpha_mode: AlphaMode::Opaque,
            double_sided: false,
        }
    }
}

/// One primitive of one node, in world space, ready to draw.
#[derive(Clone, Debug)]
pub struct DrawPrimitive {
    /// `mesh M, primitive P (node N)`.
    pub label: String,
    pub vertices: Vec<GltfVertex>,
    /// Triangle list, u32.
    pub indices: Vec<u32>,
    /// Index into [`Model::materials`].
    pub material: usize,
    /// World-space bounds of the vertices.
    pub min: [f32; 3],
    pub max: [f32; 3],
}

impl DrawPrimitive {
    pub fn triangles(&self) -> usize {
        self.indices.len() / 3
    }
}

/// A camera of the scene: its projection and its node's world matrix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GltfCamera {
    pub node: usize,
    pub world: DMat4,
    pub projection: GltfProjection,
}

/// A glTF camera projection (GL conventions).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GltfProjection {
    Perspective { yfov_radians: f64, aspect_ratio: Option<f64>, znear: f64, zfar: Option<f64> },
    Orthographic { xmag: f64, ymag: f64, znear: f64, zfar: f64 },
}

/// A loaded glTF file: what the default scene draws.
#[derive(Clone, Debug)]
pub struct Model {
    pub path: PathBuf,
    /// The shading mode it was loaded for (it decided how textures were decoded).
    pub shading: Shading,
    /// Primitives in traversal order.
    pub primitives: Vec<DrawPrimitive>,
    /// The file's materials, then glTF's default material last.
    pub materials: Vec<Material>,
    /// How many images were decoded (those of the drawn primitives' base colours).
    pub textures_loaded: usize,
    /// Cameras in traversal order.
    pub cameras: Vec<GltfCamera>,
    /// World-space bounds of every drawn vertex (as stored, f32, widened).
    pub min: DVec3,
    pub max: DVec3,
    /// What was ignored or replaced (optional extensions, skipped primitives, missing images).
    pub warnings: Vec<String>,
    /// The files read to load it: the glTF or GLB itself (when loaded with [`load`]), then its
    /// buffers and images, so a command can refuse to overwrite any of them.
    pub inputs: Vec<PathBuf>,
}

impl Model {
    pub fn triangles(&self) -> u64 {
        self.primitives.iter().map(|p| p.triangles() as u64).sum()
    }

    pub fn vertices(&self) -> u64 {
        self.primitives.iter().map(|p| p.vertices.len() as u64).sum()
    }

    /// The file name, for messages.
    pub fn file_name(&self) -> String {
        file_label(&self.path)
    }
}

fn file_label(path: &Path) -> String {
    path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| path.display().to_string())
}

/// Loads `path` for drawing with `shading` (which decides how textures are decoded and
/// filtered, and how missing normals are made; see [`Shading`]).
///
/// # Errors
/// A file that cannot be read or parsed, a required extension, a missing or short buffer, an
/// accessor or index out of range, an unsupported component type or accessor shape, a
/// non-finite position, a node hierarchy with a cycle, or a default scene with nothing to draw.
/// Each error names the file and the object.
pub fn load(path: &Path, shading: Shading) -> Result<Model, LoadError> {
    let file = path.display().to_string();
    let fail = |message: String| LoadError { file: file.clone(), message };
    let bytes = tiler_io::read_file(path, MAX_LOADED_BYTES).map_err(|e| fail(e.message))?;
    let base_dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut model = load_from_slice(&bytes, &base_dir, path, shading).map_err(fail)?;
    model.inputs.insert(0, path.to_path_buf());
    Ok(model)
}

/// The magic that starts every GLB file (glTF §4.4.2).
const GLB_MAGIC: &[u8; 4] = b"glTF";

/// Checks what kind of file `bytes` is before parsing it, and that its JSON is small enough
/// to parse: a GLB (starting with `glTF`) or JSON (starting with `{`).
fn check_container(bytes: &[u8], path: &Path) -> Result<(), String> {
    let json_len = if bytes.starts_with(GLB_MAGIC) {
        // Header (magic, version, length), then the first chunk's length: the JSON chunk.
        let word = |at: usize| bytes.get(at..at + 4).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as u64);
        let (Some(length), Some(json_len)) = (word(8), word(12)) else {
            return Err("invalid GLB container: shorter than its 20-byte header".into());
        };
        // The glTF crate subtracts the header from `length` unchecked.
        if !(20..=bytes.len() as u64).contains(&length) {
            return Err(format!(
                "invalid GLB container: its header gives a length of {length} bytes, but the file has {}",
                bytes.len()
            ));
        }
        json_len
    } else if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("glb")) {
        return Err("invalid GLB container: bad magic (a GLB file starts with the bytes 'glTF')".into());
    } else if bytes.iter().find(|b| !b.is_ascii_whitespace()) != Some(&b'{') {
        return Err(
            "neither glTF JSON (which starts with '{') nor a GLB container (which starts with the magic 'glTF')".into(),
        );
    } else {
        bytes.len() as u64
    };
    if json_len > MAX_JSON_BYTES {
        return Err(format!("its JSON is {json_len} bytes, more than the {MAX_JSON_BYTES} tiler reads"));
    }
    Ok(())
}

/// Refuses a file that is not glTF 2.x (`asset.version`, and `asset.minVersion` when given).
fn check_version(asset: &json::Asset) -> Result<(), String> {
    let major_minor = |v: &str| -> Option<(u32, u32)> {
        let (major, minor) = v.split_once('.')?;
        Some((major.parse().ok()?, minor.parse().ok()?))
    };
    match major_minor(&asset.version) {
        Some((2, _)) => {}
        _ => return Err(format!("asset.version is \"{}\"; tiler reads glTF 2.x", asset.version)),
    }
    if let Some(min) = &asset.min_version
        && major_minor(min) != Some((2, 0))
    {
        return Err(format!("asset.minVersion is \"{min}\"; tiler reads glTF 2.0"));
    }
    Ok(())
}

/// Loads a glTF or GLB held in memory; relative URIs are read from `base_dir`. `path` names
/// the file in messages and decides nothing else.
///
/// # Errors
/// As [`load`].
pub fn load_from_slice(bytes: &[u8], base_dir: &Path, path: &Path, shading: Shading) -> Result<Model, String> {
    check_container(bytes, path)?;
    let gltf = gltf::Gltf::from_slice_without_validation(bytes).map_err(describe_parse_error)?;
    let mut warnings = Vec::new();
    {
        let root = gltf.document.as_json();
        check_version(&root.asset)?;
        if let Some(ext) = root.extensions_required.first() {
            return Err(format!("requires extension {ext}, which tiler does not support"));
        }
        for ext in &root.extensions_used {
            warnings.push(format!("uses optional extension {ext}, which tiler ignores"));
        }
    }
    let root = gltf.document.into_json();
    // The gltf crate's validation indexes the POSITION accessor without a bounds check: check
    // it first so a bad index is an error, not a panic.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            for (semantic, accessor) in &primitive.attributes {
                if accessor.value() >= root.accessors.len() {
                    let name = match semantic {
                        json::validation::Checked::Valid(s) => s.to_string(),
                        json::validation::Checked::Invalid => "an attribute".into(),
                    };
                    return Err(format!(
                        "mesh {m}, primitive {p}: {name} names accessor {}, but there are {} accessors",
                        accessor.value(),
                        root.accessors.len()
                    ));
                }
            }
        }
    }
    let document = gltf::Document::from_json(root).map_err(describe_parse_error)?;
    let mut loader = Loader {
        document: &document,
        root: document.as_json(),
        blob: gltf.blob.as_deref(),
        base_dir,
        shading,
        buffers: Vec::new(),
        warnings,
        loaded: bytes.len() as u64,
        inputs: Vec::new(),
    };
    loader.load_buffers()?;
    loader.load(path)
}

/// The message of a parse or validation error, without the crate's prefixes.
fn describe_parse_error(e: gltf::Error) -> String {
    match e {
        gltf::Error::Deserialize(e) => format!("invalid glTF JSON: {e}"),
        gltf::Error::Binary(e) => format!("invalid GLB container: {e}"),
        gltf::Error::Validation(errors) => {
            let list: Vec<String> = errors.iter().take(5).map(|(path, error)| format!("{path}: {error}")).collect();
            let more = if errors.len() > 5 { format!(" (and {} more)", errors.len() - 5) } else { String::new() };
            format!("invalid glTF: {}{more}", list.join("; "))
        }
        other => format!("invalid glTF: {other}"),
    }
}

struct Loader<'a> {
    document: &'a gltf::Document,
    root: &'a json::Root,
    blob: Option<&'a [u8]>,
    base_dir: &'a Path,
    shading: Shading,
    buffers: Vec<Vec<u8>>,
    warnings: Vec<String>,
    /// Bytes read so far (files and decoded data URIs), against [`MAX_LOADED_BYTES`].
    loaded: u64,
    /// Files read so far.
    inputs: Vec<PathBuf>,
}

/// An accessor's bytes, from its first element, `stride` bytes from one element to the next.
struct StridedBytes<'b> {
    data: &'b [u8],
    stride: usize,
}

/// A mesh instance found by the traversal.
struct Instance {
    node: usize,
    mesh: usize,
    world: DMat4,
}

impl Loader<'_> {
    fn load_buffers(&mut self) -> Result<(), String> {
        for (i, buffer) in self.root.buffers.iter().enumerate() {
            let what = match &buffer.uri {
                Some(uri) if !uri.starts_with("data:") => format!("buffer {i} ({uri})"),
                _ => format!("buffer {i}"),
            };
            let data = match &buffer.uri {
                None => self.blob.ok_or_else(|| format!("{what}: no uri and no GLB binary chunk"))?.to_vec(),
                Some(uri) => self.read_uri(uri).map_err(|e| format!("{what}: {e}"))?,
            };
            let declared = buffer.byte_length.0;
            if (data.len() as u64) < declared {
                return Err(format!("{what}: {} bytes, but byteLength is {declared}", data.len()));
            }
            self.buffers.push(data);
        }
        Ok(())
    }

    /// The bytes a URI names: a `data:` URI (base64), or a file inside the glTF's folder
    /// (percent-decoded), counted against [`MAX_LOADED_BYTES`].
    fn read_uri(&mut self, uri: &str) -> Result<Vec<u8>, String> {
        let left = MAX_LOADED_BYTES.saturating_sub(self.loaded);
        let data = if let Some(rest) = uri.strip_prefix("data:") {
            decode_data_uri(rest)?
        } else {
            let relative = percent_decode(uri).ok_or_else(|| format!("URI '{uri}' has invalid percent-encoding"))?;
            let path = tiler_io::resolve_inside(self.base_dir, &relative).map_err(|e| e.to_string())?;
            let data = tiler_io::read_file(&path, left)
                .map_err(|e| format!("{e} (a model may read {MAX_LOADED_BYTES} bytes in all)"))?;
            if !self.inputs.contains(&path) {
                self.inputs.push(path);
            }
            data
        };
        if data.len() as u64 > left {
            return Err(format!("the model's data exceeds the {MAX_LOADED_BYTES} bytes a model may read"));
        }
        self.loaded += data.len() as u64;
        Ok(data)
    }

    fn load(mut self, path: &Path) -> Result<Model, String> {
        let (instances, cameras) = self.traverse()?;
        let mut materials: Vec<Material> = Vec::new();
        let mut primitives = Vec::new();
        let default_material = self.root.materials.len();
        // Which images the drawn primitives' materials use, decoded once each.
        let mut used_materials = vec![false; self.root.materials.len()];
        let mut drawn_vertices: u64 = 0;
        for instance in &instances {
            let mesh = self.document.meshes().nth(instance.mesh).expect("validated mesh index");
            for primitive in mesh.primitives() {
                if let Some(m) = primitive.material().index() {
                    used_materials[m] = true;
                }
                if let Some(p) = self.primitive(instance, &primitive)? {
                    drawn_vertices += p.vertices.len() as u64;
                    if primitives.len() >= MAX_DRAWN_PRIMITIVES || drawn_vertices > MAX_DRAWN_VERTICES {
                        return Err(format!(
                            "node {}: the default scene draws more than {MAX_DRAWN_PRIMITIVES} primitives or \
                             {MAX_DRAWN_VERTICES} vertices, more than tiler loads",
                            instance.node
                        ));
                    }
                    primitives.push(DrawPrimitive {
                        material: primitive.material().index().unwrap_or(default_material),
                        ..p
                    });
                }
            }
        }
        if primitives.is_empty() {
            return Err("the default scene has no triangles to draw".into());
        }
        let textures = self.load_textures(&used_materials)?;
        for material in self.document.materials() {
            materials.push(self.material(&material, &textures));
        }
        materials.push(Material::default_material());

        let mut min = DVec3::splat(f64::INFINITY);
        let mut max = DVec3::splat(f64::NEG_INFINITY);
        for p in &primitives {
            min = min.min(DVec3::from(p.min.map(f64::from)));
            max = max.max(DVec3::from(p.max.map(f64::from)));
        }
        Ok(Model {
            path: path.to_path_buf(),
            shading: self.shading,
            primitives,
            materials,
            textures_loaded: textures.values().filter(|t| t.is_some()).count(),
            cameras,
            min,
            max,
            warnings: self.warnings,
            inputs: self.inputs,
        })
    }

    /// The default scene's mesh instances and cameras, depth first.
    fn traverse(&mut self) -> Result<(Vec<Instance>, Vec<GltfCamera>), String> {
        let root = self.root;
        let roots: Vec<usize> = if root.scenes.is_empty() {
            let mut is_child = vec![false; root.nodes.len()];
            for node in &root.nodes {
                for c in node.children.iter().flatten() {
                    is_child[c.value()] = true;
                }
            }
            (0..root.nodes.len()).filter(|&n| !is_child[n]).collect()
        } else {
            let scene = root.scene.map(|s| s.value()).unwrap_or(0);
            root.scenes[scene].nodes.iter().map(|n| n.value()).collect()
        };
        // Depth first with an explicit stack (a hierarchy 200,000 deep must not overflow the
        // thread's stack); `on_path` finds cycles in constant time per node.
        enum Step {
            Enter(usize, DMat4),
            Leave(usize),
        }
        let mut stack: Vec<Step> = roots.iter().rev().map(|&n| Step::Enter(n, DMat4::IDENTITY)).collect();
        let mut on_path = vec![false; root.nodes.len()];
        let mut visits = 0usize;
        let mut instances = Vec::new();
        let mut cameras = Vec::new();
        while let Some(step) = stack.pop() {
            let (index, parent) = match step {
                Step::Leave(index) => {
                    on_path[index] = false;
                    continue;
                }
                Step::Enter(index, parent) => (index, parent),
            };
            if on_path[index] {
                return Err(format!("node {index}: is its own ancestor (the node hierarchy has a cycle)"));
            }
            visits += 1;
            if visits > MAX_NODE_VISITS || instances.len() > MAX_DRAWN_PRIMITIVES {
                return Err(format!(
                    "node {index}: the default scene has more than {MAX_NODE_VISITS} node instances or \
                     {MAX_DRAWN_PRIMITIVES} mesh instances, more than tiler loads"
                ));
            }
            let node = &root.nodes[index];
            let world = parent * local_matrix(node);
            if let Some(mesh) = node.mesh {
                instances.push(Instance { node: index, mesh: mesh.value(), world });
            }
            if let Some(camera) = node.camera {
                cameras.push(GltfCamera { node: index, world, projection: self.projection(camera.value()) });
            }
            on_path[index] = true;
            stack.push(Step::Leave(index));
            for child in node.children.iter().flatten().rev() {
                stack.push(Step::Enter(child.value(), world));
            }
        }
        Ok((instances, cameras))
    }

    fn projection(&self, camera: usize) -> GltfProjection {
        let camera = self.document.cameras().nth(camera).expect("validated camera index");
        match camera.projection() {
            gltf::camera::Projection::Perspective(p) => GltfProjection::Perspective {
                yfov_radians: p.yfov() as f64,
                aspect_ratio: p.aspect_ratio().map(f64::from),
                znear: p.znear() as f64,
                zfar: p.zfar().map(f64::from),
            },
            gltf::camera::Projection::Orthographic(o) => GltfProjection::Orthographic {
                xmag: o.xmag() as f64,
                ymag: o.ymag() as f64,
                znear: o.znear() as f64,
                zfar: o.zfar() as f64,
            },
        }
    }

    /// One primitive of one instance, in world space; `None` when it draws nothing.
    fn primitive(
        &mut self,
        instance: &Instance,
        primitive: &gltf::Primitive<'_>,
    ) -> Result<Option<DrawPrimitive>, String> {
        let label = format!("mesh {}, primitive {}", instance.mesh, primitive.index());
        let fail = |e: String| format!("{label}: {e}");
        let mode = primitive.mode();
        let Some(position) = primitive.get(&gltf::Semantic::Positions) else {
            self.warnings.push(format!("{label}: no POSITION, skipped"));
            return Ok(None);
        };
        use gltf::mesh::Mode;
        if !matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
            self.warnings.push(format!("{label}: mode {mode:?} skipped (only triangles are drawn)"));
            return Ok(None);
        }
        let positions = self.read_vec3(&position, "POSITION").map_err(fail)?;
        let n = positions.len();
        if let Some(bad) = positions.iter().position(|p| !p.is_finite()) {
            return Err(fail(format!("POSITION (accessor {}): vertex {bad} is not finite", position.index())));
        }
        let mut indices = match primitive.indices() {
            Some(accessor) => self.read_indices(&accessor).map_err(fail)?,
            None => (0..n as u32).collect(),
        };
        if let Some(position_in_list) = indices.iter().position(|&i| i as usize >= n) {
            let accessor = primitive.indices().map(|a| a.index()).unwrap_or(0);
            return Err(fail(format!(
                "indices (accessor {accessor}): index {} at position {position_in_list} is out of range for {n} vertices",
                indices[position_in_list]
            )));
        }
        indices = triangle_list(mode, &indices);
        let mut normals = match primitive.get(&gltf::Semantic::Normals) {
            Some(accessor) => Some(self.read_vec3(&accessor, "NORMAL").map_err(fail)?),
            None => None,
        };
        let uvs = match primitive.get(&gltf::Semantic::TexCoords(0)) {
            Some(accessor) => self.read_uvs(&accessor).map_err(fail)?,
            None => vec![[0.0; 2]; n],
        };
        for (name, count) in [("NORMAL", normals.as_ref().map(Vec::len)), ("TEXCOORD_0", Some(uvs.len()))] {
            if let Some(count) = count.filter(|&c| c != n) {
                return Err(fail(format!("{name} has {count} elements but POSITION has {n}")));
            }
        }
        if indices.is_empty() {
            return Ok(None);
        }

        let mut positions = positions;
        let mut uvs = uvs;
        if normals.is_none() {
            if self.shading == Shading::Gltf {
                if indices.len() > MAX_ACCESSOR_ELEMENTS {
                    return Err(fail(format!(
                        "flat normals would give {} vertices, more than the {MAX_ACCESSOR_ELEMENTS} tiler makes",
                        indices.len()
                    )));
                }
                // Flat: every triangle gets vertices of its own.
                positions = indices.iter().map(|&i| positions[i as usize]).collect();
                uvs = indices.iter().map(|&i| uvs[i as usize]).collect();
                indices = (0..indices.len() as u32).collect();
            }
            normals = Some(face_normal_sums(&positions, &indices));
        }
        let normals = normals.expect("made above");

        let m = instance.world;
        let m3 = DMat3::from_mat4(m);
        let normal_matrix = m3.inverse().transpose();
        let mut vertices = Vec::with_capacity(positions.len());
        let mut min = [f32::INFINITY; 3];
        let mut max = [f32::NEG_INFINITY; 3];
        for ((p, nrm), uv) in positions.iter().zip(&normals).zip(&uvs) {
            let world = m.transform_point3(*p).as_vec3().to_array();
            if world.iter().any(|c| !c.is_finite()) {
                return Err(fail(format!("node {}: the world transform makes a position non-finite", instance.node)));
            }
            let n = normal_matrix * *nrm;
            let length = n.length();
            let n = if length > 0.0 && length.is_finite() { n / length } else { DVec3::ZERO };
            for c in 0..3 {
                min[c] = min[c].min(world[c]);
                max[c] = max[c].max(world[c]);
            }
            vertices.push(GltfVertex { position: world, normal: n.as_vec3().to_array(), uv: *uv });
        }
        if m3.determinant() < 0.0 {
            for t in indices.chunks_exact_mut(3) {
                t.swap(1, 2);
            }
        }
        Ok(Some(DrawPrimitive {
            label: format!("{label} (node {})", instance.node),
            vertices,
            indices,
            material: 0,
            min,
            max,
        }))
    }

    /// The bytes of an accessor's elements from its first, and the stride between them, bounds
    /// checked; `None` for an accessor without a buffer view (all zeros).
    fn accessor_bytes(&self, accessor: &gltf::Accessor<'_>) -> Result<Option<StridedBytes<'_>>, String> {
        let what = format!("accessor {}", accessor.index());
        if accessor.sparse().is_some() {
            return Err(format!("{what}: sparse accessors are not supported"));
        }
        let element = accessor.size();
        let Some(view) = accessor.view() else { return Ok(None) };
        let buffer = &self.buffers[view.buffer().index()];
        let view_end = view.offset().checked_add(view.length()).filter(|&e| e <= buffer.len()).ok_or_else(|| {
            format!(
                "{what}: buffer view {} (bytes {}..{}) is past the end of buffer {} ({} bytes)",
                view.index(),
                view.offset(),
                view.offset() as u64 + view.length() as u64,
                view.buffer().index(),
                buffer.len()
            )
        })?;
        let data = &buffer[view.offset()..view_end];
        let stride = view.stride().unwrap_or(element);
        if stride < element {
            return Err(format!(
                "{what}: byteStride {stride} of buffer view {} is below its element size {element}",
                view.index()
            ));
        }
        let count = accessor.count() as u64;
        if count > 0 {
            let needed = (count - 1)
                .checked_mul(stride as u64)
                .and_then(|n| n.checked_add(accessor.offset() as u64))
                .and_then(|n| n.checked_add(element as u64))
                .unwrap_or(u64::MAX);
            if needed > data.len() as u64 {
                return Err(format!(
                    "{what}: {count} elements of {element} bytes (stride {stride}, offset {}) need {needed} bytes, \
                     but buffer view {} has {}",
                    accessor.offset(),
                    view.index(),
                    data.len()
                ));
            }
        }
        Ok(Some(StridedBytes { data: &data[accessor.offset().min(data.len())..], stride }))
    }

    /// Reads an accessor of `N` components as doubles, converting normalised integers.
    fn read_components<const N: usize>(
        &self,
        accessor: &gltf::Accessor<'_>,
        semantic: &str,
        allowed: &[(gltf::accessor::DataType, bool)],
    ) -> Result<Vec<[f64; N]>, String> {
        use gltf::accessor::{DataType, Dimensions};
        let what = format!("{semantic} (accessor {})", accessor.index());
        let dims = accessor.dimensions();
        let expected = match N {
            1 => Dimensions::Scalar,
            2 => Dimensions::Vec2,
            3 => Dimensions::Vec3,
            _ => Dimensions::Vec4,
        };
        if dims != expected {
            return Err(format!("{what}: type {dims:?}, expected {expected:?}"));
        }
        let (ty, normalized) = (accessor.data_type(), accessor.normalized());
        if !allowed.contains(&(ty, normalized)) {
            let allowed: Vec<String> =
                allowed.iter().map(|(t, n)| if *n { format!("normalized {t:?}") } else { format!("{t:?}") }).collect();
            return Err(format!(
                "{what}: component type {}{ty:?} is not supported (expected {})",
                if normalized { "normalized " } else { "" },
                allowed.join(" or ")
            ));
        }
        let count = accessor.count();
        if count > MAX_ACCESSOR_ELEMENTS {
            return Err(format!("{what}: {count} elements, more than the {MAX_ACCESSOR_ELEMENTS} tiler reads"));
        }
        let Some(StridedBytes { data, stride }) = self.accessor_bytes(accessor)? else {
            return Ok(vec![[0.0; N]; count]);
        };
        let size = ty.size();
        let read = |b: &[u8]| -> f64 {
            let v = match ty {
                DataType::F32 => return f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                DataType::U8 => b[0] as f64,
                DataType::I8 => b[0] as i8 as f64,
                DataType::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
                DataType::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
                DataType::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            };
            if !normalized {
                return v;
            }
            // glTF §3.11: unsigned c / max; signed max(c / max, −1).
            match ty {
                DataType::U8 => v / 255.0,
                DataType::U16 => v / 65535.0,
                DataType::I8 => (v / 127.0).max(-1.0),
                DataType::I16 => (v / 32767.0).max(-1.0),
                _ => v,
            }
        };
        Ok((0..count)
            .map(|i| std::array::from_fn(|c| read(&data[i * stride + c * size..i * stride + (c + 1) * size])))
            .collect())
    }

    fn read_vec3(&self, accessor: &gltf::Accessor<'_>, semantic: &str) -> Result<Vec<DVec3>, String> {
        use gltf::accessor::DataType;
        let v = self.read_components::<3>(accessor, semantic, &[(DataType::F32, false)])?;
        Ok(v.into_iter().map(DVec3::from).collect())
    }

    fn read_uvs(&self, accessor: &gltf::Accessor<'_>) -> Result<Vec<[f32; 2]>, String> {
        use gltf::accessor::DataType;
        let allowed = [(DataType::F32, false), (DataType::U8, true), (DataType::U16, true)];
        let v = self.read_components::<2>(accessor, "TEXCOORD_0", &allowed)?;
        Ok(v.into_iter().map(|uv| uv.map(|c| c as f32)).collect())
    }

    fn read_indices(&self, accessor: &gltf::Accessor<'_>) -> Result<Vec<u32>, String> {
        use gltf::accessor::DataType;
        let allowed = [(DataType::U8, false), (DataType::U16, false), (DataType::U32, false)];
        let v = self.read_components::<1>(accessor, "indices", &allowed)?;
        Ok(v.into_iter().map(|[i]| i as u32).collect())
    }

    /// Decodes the base-colour images of the used materials, in parallel.
    fn load_textures(&mut self, used_materials: &[bool]) -> Result<HashMap<usize, Option<Arc<Texture>>>, String> {
        let mut wanted: Vec<usize> = Vec::new();
        for (m, material) in self.root.materials.iter().enumerate() {
            if !used_materials[m] {
                continue;
            }
            if let Some(info) = &material.pbr_metallic_roughness.base_color_texture {
                let texture = &self.root.textures[info.index.value()];
                let image = texture.source.value();
                if !wanted.contains(&image) {
                    wanted.push(image);
                }
            }
        }
        let mut encoded: Vec<(usize, Result<Vec<u8>, String>)> = Vec::new();
        for &image in &wanted {
            encoded.push((image, self.image_bytes(image)?));
        }
        let (color_space, mips) = match self.shading {
            Shading::Scenes => (ColorSpace::Linear, MipChain::Box),
            Shading::Gltf => (ColorSpace::Srgb, MipChain::Box),
        };
        let decoded: Vec<(usize, Result<Texture, String>)> = {
            use rayon::prelude::*;
            encoded
                .into_par_iter()
                .map(|(image, bytes)| {
                    let texture = bytes.and_then(|bytes| {
                        let rgba =
                            image::load_from_memory(&bytes).map_err(|e| format!("cannot decode: {e}"))?.to_rgba8();
                        Texture::from_rgba8(rgba.width(), rgba.height(), rgba.as_raw(), color_space, mips)
                            .map_err(|e| e.to_string())
                    });
                    (image, texture)
                })
                .collect()
        };
        let mut textures = HashMap::new();
        for (image, texture) in decoded {
            match texture {
                Ok(t) => {
                    textures.insert(image, Some(Arc::new(t)));
                }
                Err(e) => {
                    self.warnings.push(format!("image {image}: {e}; its materials are drawn untextured"));
                    textures.insert(image, None);
                }
            }
        }
        Ok(textures)
    }

    /// The encoded bytes of an image: `Err` inside for a file that cannot be read (a warning
    /// later), `Err` outside for a broken reference into a buffer (an error).
    fn image_bytes(&mut self, index: usize) -> Result<Result<Vec<u8>, String>, String> {
        let image = &self.root.images[index];
        if let Some(view) = image.buffer_view {
            let view = &self.root.buffer_views[view.value()];
            let buffer = &self.buffers[view.buffer.value()];
            let start = view.byte_offset.map(|o| o.0 as usize).unwrap_or(0);
            let end = start.checked_add(view.byte_length.0 as usize).filter(|&e| e <= buffer.len());
            return match end {
                Some(end) => Ok(Ok(buffer[start..end].to_vec())),
                None => Err(format!(
                    "image {index}: its buffer view is past the end of buffer {} ({} bytes)",
                    view.buffer.value(),
                    buffer.len()
                )),
            };
        }
        match &image.uri {
            Some(uri) => Ok(self.read_uri(uri)),
            None => Err(format!("image {index}: neither uri nor bufferView")),
        }
    }

    fn material(&mut self, material: &gltf::Material<'_>, textures: &HashMap<usize, Option<Arc<Texture>>>) -> Material {
        let index = material.index().expect("a material of the file");
        let pbr = material.pbr_metallic_roughness();
        let base_color_texture = pbr.base_color_texture().and_then(|info| {
            let texture = info.texture();
            let image = self.root.textures[texture.index()].source.value();
            if info.tex_coord() != 0 {
                self.warnings.push(format!(
                    "material {index}: base colour texture uses TEXCOORD_{}; TEXCOORD_0 is used instead",
                    info.tex_coord()
                ));
            }
            let loaded = textures.get(&image)?.clone()?;
            let sampler = match self.shading {
                Shading::Scenes => Sampler::TRILINEAR_REPEAT,
                Shading::Gltf => gltf_sampler(&texture.sampler()),
            };
            Some(TextureBinding { texture: loaded, sampler, image })
        });
        let alpha_mode = match material.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => AlphaMode::Mask { cutoff: material.alpha_cutoff().unwrap_or(0.5) },
            gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        };
        Material {
            name: material.name().map(str::to_owned).unwrap_or_else(|| format!("material {index}")),
            base_color_factor: pbr.base_color_factor(),
            base_color_texture,
            alpha_mode,
            double_sided: material.double_sided(),
        }
    }
}

/// The tiler sampler for a glTF sampler; glTF leaves undefined filters to the implementation:
/// linear magnification and trilinear minification.
fn gltf_sampler(sampler: &gltf::texture::Sampler<'_>) -> Sampler {
    use gltf::texture::{MagFilter, MinFilter, WrappingMode};
    let mag_filter = match sampler.mag_filter() {
        Some(MagFilter::Nearest) => Filter::Nearest,
        _ => Filter::Linear,
    };
    let (min_filter, mipmap) = match sampler.min_filter() {
        Some(MinFilter::Nearest) => (Filter::Nearest, MipmapMode::None),
        Some(MinFilter::Linear) => (Filter::Linear, MipmapMode::None),
        Some(MinFilter::NearestMipmapNearest) => (Filter::Nearest, MipmapMode::Nearest),
        Some(MinFilter::LinearMipmapNearest) => (Filter::Linear, MipmapMode::Nearest),
        Some(MinFilter::NearestMipmapLinear) => (Filter::Nearest, MipmapMode::Linear),
        Some(MinFilter::LinearMipmapLinear) | None => (Filter::Linear, MipmapMode::Linear),
    };
    let wrap = |w: WrappingMode| match w {
        WrappingMode::Repeat => Wrap::Repeat,
        WrappingMode::ClampToEdge => Wrap::ClampToEdge,
        WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
    };
    Sampler {
        mag_filter,
        min_filter,
        mipmap,
        wrap_u: wrap(sampler.wrap_s()),
        wrap_v: wrap(sampler.wrap_t()),
        wrap_w: tiler::Wrap::Repeat,
        lod_bias: 0.0,
    }
}

/// A node's local matrix: `matrix` when present and not the identity, else `T · R · S` with the
/// rotation quaternion as given (SCENES.md §4.2 does not normalise it).
fn local_matrix(node: &json::Node) -> DMat4 {
    const IDENTITY: [f32; 16] = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0];
    if let Some(m) = node.matrix.filter(|m| *m != IDENTITY) {
        return DMat4::from_cols_array(&m.map(f64::from));
    }
    let t = DVec3::from(node.translation.unwrap_or([0.0; 3]).map(f64::from));
    let [x, y, z, w] = node.rotation.as_ref().map(|q| q.0).unwrap_or([0.0, 0.0, 0.0, 1.0]).map(f64::from);
    let s = DVec3::from(node.scale.unwrap_or([1.0; 3]).map(f64::from));
    let r = DMat3::from_cols(
        DVec3::new(1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y + z * w), 2.0 * (x * z - y * w)),
        DVec3::new(2.0 * (x * y - z * w), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z + x * w)),
        DVec3::new(2.0 * (x * z + y * w), 2.0 * (y * z - x * w), 1.0 - 2.0 * (x * x + y * y)),
    );
    DMat4::from_cols(
        (r.x_axis * s.x).extend(0.0),
        (r.y_axis * s.y).extend(0.0),
        (r.z_axis * s.z).extend(0.0),
        DVec4::new(t.x, t.y, t.z, 1.0),
    )
}

/// Converts strip and fan indices to a triangle list; a list is truncated to whole triangles.
fn triangle_list(mode: gltf::mesh::Mode, indices: &[u32]) -> Vec<u32> {
    use gltf::mesh::Mode;
    match mode {
        Mode::TriangleStrip => (0..indices.len().saturating_sub(2))
            .flat_map(|i| {
                let (a, b, c) = (indices[i], indices[i + 1], indices[i + 2]);
                if i % 2 == 0 { [a, b, c] } else { [b, a, c] }
            })
            .collect(),
        Mode::TriangleFan => {
            (1..indices.len().saturating_sub(1)).flat_map(|i| [indices[i], indices[i + 1], indices[0]]).collect()
        }
        _ => indices[..indices.len() / 3 * 3].to_vec(),
    }
}

/// Per vertex, the sum of the unnormalised normals `cross(p1 − p0, p2 − p0)` of its triangles.
fn face_normal_sums(positions: &[DVec3], indices: &[u32]) -> Vec<DVec3> {
    let mut normals = vec![DVec3::ZERO; positions.len()];
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [t[0] as usize, t[1] as usize, t[2] as usize];
        let face = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
        for v in [a, b, c] {
            normals[v] += face;
        }
    }
    normals
}

/// The bytes of a `data:` URI (after `data:`): base64 only (RFC 2397), padding optional.
fn decode_data_uri(rest: &str) -> Result<Vec<u8>, String> {
    use base64::Engine;
    use base64::engine::{DecodePaddingMode, GeneralPurpose, GeneralPurposeConfig};
    const BASE64: GeneralPurpose = GeneralPurpose::new(
        &base64::alphabet::STANDARD,
        GeneralPurposeConfig::new().with_decode_padding_mode(DecodePaddingMode::Indifferent),
    );
    let (header, data) = rest.split_once(',').ok_or("data URI without a comma")?;
    if !header.ends_with(";base64") {
        return Err("data URI that is not base64".into());
    }
    BASE64.decode(data).map_err(|e| format!("data URI with invalid base64: {e}"))
}

/// `%XX` escapes decoded (RFC 3986); `None` for a bad escape or invalid UTF-8.
fn percent_decode(s: &str) -> Option<String> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn data_uris_decode_rfc4648_vectors() {
        for (text, plain) in
            [("", ""), ("Zg==", "f"), ("Zg", "f"), ("Zm8=", "fo"), ("Zm9v", "foo"), ("Zm9vYmFy", "foobar")]
        {
            assert_eq!(decode_data_uri(&format!("application/octet-stream;base64,{text}")).unwrap(), plain.as_bytes());
        }
        assert!(decode_data_uri("application/octet-stream;base64,Zm9v!").is_err());
        assert!(decode_data_uri("text/plain,abc").unwrap_err().contains("not base64"));
    }

    #[test]
    fn percent_decoding() {
        assert_eq!(percent_decode("a%20b.bin").unwrap(), "a b.bin");
        assert_eq!(percent_decode("plain.png").unwrap(), "plain.png");
        assert!(percent_decode("bad%2").is_none());
    }

    #[test]
    fn strips_and_fans_become_lists() {
        use gltf::mesh::Mode;
        assert_eq!(triangle_list(Mode::TriangleStrip, &[0, 1, 2, 3, 4]), [0, 1, 2, 2, 1, 3, 2, 3, 4]);
        assert_eq!(triangle_list(Mode::TriangleFan, &[0, 1, 2, 3]), [1, 2, 0, 2, 3, 0]);
        assert_eq!(triangle_list(Mode::Triangles, &[0, 1, 2, 3]), [0, 1, 2]);
        assert!(triangle_list(Mode::TriangleStrip, &[0, 1]).is_empty());
    }

    #[test]
    fn trs_matches_the_quaternion_formula() {
        let node = json::Node {
            rotation: Some(json::scene::UnitQuaternion([
                0.0,
                std::f32::consts::FRAC_1_SQRT_2,
                0.0,
                std::f32::consts::FRAC_1_SQRT_2,
            ])),
            translation: Some([1.0, 2.0, 3.0]),
            scale: Some([2.0, 2.0, 2.0]),
            ..Default::default()
        };
        let m = local_matrix(&node);
        // 90° about y: x → −z, scaled by 2, then translated.
        let p = m.transform_point3(DVec3::X);
        assert!((p - DVec3::new(1.0, 2.0, 1.0)).length() < 1e-6, "{p}");
    }
}
