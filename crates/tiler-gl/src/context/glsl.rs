//! Programs in the context: GLSL ES program objects (compiled and linked by `tiler-glsl`),
//! GL's uniform rules for them, and what a draw of any program reads and renders with.
//!
//! A GLSL program is compiled and linked at `create_program`; `bind_attrib_location` relinks
//! it at once (GL waits for the next `glLinkProgram`, but a capture's recorded attribute
//! locations are exactly those the application then used, so binding them any time is what a
//! replay needs). Relinking keeps the uniform values: the uniforms' layout depends on the
//! source only.
//!
//! A draw reads the program's attributes from the enabled arrays at their locations; a
//! disabled attribute reads its current generic value (`vertex_attrib`, initially
//! `(0, 0, 0, 1)`), as in GL. Each sampler uniform names a texture unit; the texture bound
//! there is sampled as the `textured` built-in samples it (see `program`): RGBA8 through the
//! core's sampler and texture cache (`texture_fetch` in the ledger), other formats (depth,
//! float, 565) through a [`TextureSnapshot`]. A sampler whose unit has no texture is an error
//! here (GL would read an incomplete texture as black, which is almost always a bug in a
//! trace). The fragment shader's `discard` reaches tiler as [`tiler::ShaderProperties`], so
//! early depth tests and HSR behave as they do on hardware for discarding shaders.

use std::collections::HashMap;
use std::sync::Arc;

use tiler::{ImageId, Pipeline, PipelineDesc};
use tiler_glsl::{CompiledProgram, SamplerKind, Scalar, TextureBinding, TextureSource, Type, UniformValues};

use super::{Context, Fallible, MAX_TEXTURE_UNITS, MAX_VERTEX_ATTRIBS, ProgramObject};
use crate::call::{GlslSource, LayeredTarget, ProgramKind, UniformValue};
use crate::program::{ProgramTexture, SamplerState, TextureSnapshot, Uniforms, program_pipeline};

/// A GLSL program object.
pub(crate) struct GlslProgram {
    /// `bind_attrib_location`s so far, in order (a name bound again moves).
    bindings: Vec<(String, u32)>,
    compiled: Arc<CompiledProgram>,
    uniforms: UniformValues,
    /// Each uniform block's uniform buffer binding (`uniform_blocks.rs`).
    pub(super) block_bindings: Vec<u32>,
    /// The outputs transform feedback captures, and whether into separate buffers
    /// (`feedback.rs`; found in the compiled program at each draw, as a relink moves them).
    pub(super) feedback: Option<(Vec<String>, bool)>,
}

impl GlslProgram {
    /// Compiles and links `source`; uniforms start at zero.
    ///
    /// # Errors
    /// A compile error naming the shader and the line, or a link error.
    pub fn new(source: GlslSource) -> Result<GlslProgram, tiler_glsl::Error> {
        let compiled = CompiledProgram::new(&source.vertex, &source.fragment, &[])?;
        let uniforms = compiled.new_uniform_values();
        let block_bindings = vec![0; compiled.uniform_blocks().len()];
        Ok(GlslProgram { bindings: Vec::new(), compiled: Arc::new(compiled), uniforms, block_bindings, feedback: None })
    }

    /// Binds attribute `name` to `index` and relinks, unless nothing would change: the same
    /// binding again (a capture repeats them), or a name the program does not declare (GL
    /// accepts it, for a later source).
    fn bind_attrib_location(&mut self, name: String, index: u32) -> Result<(), tiler_glsl::Error> {
        if self.bindings.iter().any(|(n, l)| *n == name && *l == index) {
            return Ok(());
        }
        if self.compiled.attribute_location(&name).is_none() {
            self.bindings.retain(|(n, _)| *n != name);
            self.bindings.push((name, index));
            return Ok(());
        }
        let mut bindings = self.bindings.clone();
        bindings.retain(|(n, _)| *n != name);
        bindings.push((name, index));
        let pairs: Vec<(&str, u32)> = bindings.iter().map(|(n, l)| (n.as_str(), *l)).collect();
        let compiled = self.compiled.with_attribute_locations(&pairs)?;
        self.compiled = Arc::new(compiled);
        self.bindings = bindings;
        Ok(())
    }

    pub(super) fn compiled(&self) -> &CompiledProgram {
        &self.compiled
    }

    /// The texture units its samplers of `kind` read.
    pub(super) fn units_of(&self, kind: SamplerKind) -> Vec<u32> {
        self.compiled.sampler_units_of(kind, &self.uniforms).into_iter().map(|(_, unit)| unit).collect()
    }

    /// `glUniform*` by name, with GL's type rules (see [`UniformValue`]).
    ///
    /// # Errors
    /// An unknown uniform, a value of a type that cannot set it, a non-finite value, or a
    /// texture unit out of range.
    pub fn set_uniform(&mut self, name: &str, value: UniformValue) -> Fallible {
        let program = &self.compiled;
        let Some(location) = program.uniform_location(name) else {
            return Err(format!("no active uniform '{name}' (it has: {})", uniform_names(program).join(", ")));
        };
        let info = program
            .uniforms()
            .iter()
            .find(|u| (u.location..u.location + u.array_size as u32).contains(&location))
            .expect("a uniform location belongs to a uniform");
        let values = uniform_components(&info.ty, value).ok_or_else(|| {
            format!("uniform '{name}' is a {}, which a {} value cannot set", info.ty, value.type_name())
        })?;
        if !value.is_finite() {
            return Err(format!("uniform '{name}' has a non-finite value {value:?}"));
        }
        // An integer uniform takes the value's bits, exactly.
        if matches!(info.ty.scalar(), Some(Scalar::Int | Scalar::UInt))
            && let Some(bits) = value.integer_bits()
        {
            return program.set_uniform_integers(&mut self.uniforms, location, &bits).map_err(|e| e.to_string());
        }
        // Other values travel to the program as floats: integers are exact to 2²⁴ (a bool, a
        // sampler's unit).
        let integer = matches!(
            value,
            UniformValue::Int(_)
                | UniformValue::IVec2(_)
                | UniformValue::IVec3(_)
                | UniformValue::IVec4(_)
                | UniformValue::UInt(_)
                | UniformValue::UVec2(_)
                | UniformValue::UVec3(_)
                | UniformValue::UVec4(_)
        );
        if let Some(big) = value.components().iter().find(|c| integer && c.abs() > (1 << 24) as f32) {
            return Err(format!(
                "uniform '{name}' set to {big}: not supported: integer uniforms beyond ±2^24 (they reach the \
                 shader as floats)"
            ));
        }
        if let (Type::Sampler(_), UniformValue::Int(unit)) = (&info.ty, value)
            && !(0..MAX_TEXTURE_UNITS as i32).contains(&unit)
        {
            return Err(format!("sampler '{name}' set to texture unit {unit}, outside 0 to {}", MAX_TEXTURE_UNITS - 1));
        }
        program.set_uniform(&mut self.uniforms, location, &values).map_err(|e| e.to_string())
    }
}

/// Active uniform names as `glGetActiveUniform` lists them (an array as `name[0]`).
fn uniform_names(program: &CompiledProgram) -> Vec<String> {
    program
        .uniforms()
        .iter()
        .map(|u| if u.array_size > 1 { format!("{}[0]", u.name) } else { u.name.clone() })
        .collect()
}

/// The floats `value` stores into a uniform of type `ty` under `glUniform*`'s rules, or
/// `None` when that call cannot set it: `glUniform{1,2,3,4}f` sets float and bool scalars
/// and vectors of its size, `glUniform{1,2,3,4}i` int and bool ones and (`1i`) samplers,
/// `glUniform{1,2,3,4}ui` uint and bool ones,
/// `glUniformMatrixNfv` `matN` and `glUniformMatrixCxRfv` `matCxR`. Bools store 1 or 0, as the compiler's `true` and `false`.
fn uniform_components(ty: &Type, value: UniformValue) -> Option<Vec<f32>> {
    use UniformValue as V;
    let components = value.components();
    let floats = matches!(value, V::Float(_) | V::Vec2(_) | V::Vec3(_) | V::Vec4(_));
    let ints = matches!(value, V::Int(_) | V::IVec2(_) | V::IVec3(_) | V::IVec4(_));
    let uints = matches!(value, V::UInt(_) | V::UVec2(_) | V::UVec3(_) | V::UVec4(_));
    // A matrix value's shape (columns, rows); the uniform's must be the same.
    let matrix = match value {
        V::Mat2(_) => Some((2, 2)),
        V::Mat3(_) => Some((3, 3)),
        V::Mat4(_) => Some((4, 4)),
        V::Mat2x3(_) => Some((2, 3)),
        V::Mat2x4(_) => Some((2, 4)),
        V::Mat3x2(_) => Some((3, 2)),
        V::Mat3x4(_) => Some((3, 4)),
        V::Mat4x2(_) => Some((4, 2)),
        V::Mat4x3(_) => Some((4, 3)),
        _ => None,
    };
    let same_size = ty.size() == components.len();
    match ty {
        Type::Scalar(Scalar::Float) | Type::Vector(Scalar::Float, _) if floats && same_size => Some(components),
        Type::Scalar(Scalar::Int) | Type::Vector(Scalar::Int, _) if ints && same_size => Some(components),
        Type::Scalar(Scalar::UInt) | Type::Vector(Scalar::UInt, _) if uints && same_size => Some(components),
        Type::Scalar(Scalar::Bool) | Type::Vector(Scalar::Bool, _) if (floats || ints || uints) && same_size => {
            Some(components.into_iter().map(|c| if c != 0.0 { 1.0 } else { 0.0 }).collect())
        }
        Type::Matrix(c, r) if matrix == Some((*c, *r)) && same_size => Some(components),
        Type::Sampler(_) if matches!(value, V::Int(_)) => Some(components),
        _ => None,
    }
}

/// A texture a draw samples.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SampledTexture {
    pub unit: u32,
    pub image: ImageId,
    pub sampler: SamplerState,
    /// It has a mip chain (`generate_mipmap`).
    pub mipmaps: bool,
}

/// The program of a gathered draw, with its uniforms as they were at the draw.
#[derive(Clone, Debug)]
pub(crate) enum ProgramDraw {
    Builtin {
        kind: ProgramKind,
        uniforms: Uniforms,
    },
    Glsl {
        program: Arc<CompiledProgram>,
        uniforms: UniformValues,
        /// Disabled attribute locations the program reads, and their generic values (and
        /// per-instance attributes, their instance's values: `instancing.rs`).
        generic: Vec<(u32, [f32; 4])>,
        /// The units `samplerCube`, `sampler2DArray` and `sampler3D` uniforms read and their
        /// core textures as they were at the draw (`None`: an incomplete cube).
        cubes: Vec<(u32, Option<CoreCube>)>,
        /// `gl_InstanceID`.
        instance: u32,
    },
}

/// A cube texture as the core samples it.
pub(crate) type CoreCube = (Arc<tiler::Texture>, tiler::Sampler);

impl ProgramDraw {
    /// The built-in program, if it is one.
    pub fn kind(&self) -> Option<ProgramKind> {
        match self {
            ProgramDraw::Builtin { kind, .. } => Some(*kind),
            ProgramDraw::Glsl { .. } => None,
        }
    }

    /// Whether the fragment shader may discard.
    pub fn discards(&self) -> bool {
        match self {
            ProgramDraw::Builtin { kind: ProgramKind::VertexColor | ProgramKind::Textured, uniforms } => {
                uniforms.alpha_cutoff > 0.0
            }
            ProgramDraw::Builtin { .. } => false,
            ProgramDraw::Glsl { program, .. } => program.fragment_properties().discards,
        }
    }
}

/// What a draw of the program in use reads, checked against the context's state.
pub(crate) struct DrawProgram {
    /// The program as errors and pipeline labels name it.
    pub label: String,
    /// Attribute locations read from arrays, and their names.
    pub attributes: Vec<(u32, String)>,
    pub textures: Vec<SampledTexture>,
    /// Input attachments it reads.
    pub inputs: usize,
    /// The buffers its uniform blocks read (their values are in `source`).
    pub uniform_buffers: Vec<u32>,
    pub source: ProgramDraw,
}

impl Context {
    /// What a draw of the program in use reads: its attributes, its textures (each unit
    /// once), its input attachments.
    pub(crate) fn draw_program(&self) -> Fallible<DrawProgram> {
        let id = self.state.program;
        match self.programs.get(&id).ok_or("no program is in use")? {
            ProgramObject::Builtin { kind, uniforms } => {
                let info = kind.info();
                let mut textures = Vec::new();
                if info.samples_texture {
                    let unit = uniforms.sampler;
                    if !(0..MAX_TEXTURE_UNITS as i32).contains(&unit) {
                        return Err(format!("uniform 'sampler' is {unit}, not a texture unit"));
                    }
                    let texture = self.state.textures[unit as usize];
                    if texture != 0 {
                        let t = self.texture(texture)?;
                        let (image, sampler, mipmaps) = (t.image, self.unit_sampler(unit as u32, t), t.mipmaps);
                        self.check_has_memory(image, &format!("program '{}' samples texture {texture}", kind.name()))?;
                        textures.push(SampledTexture { unit: unit as u32, image, sampler, mipmaps });
                    }
                }
                Ok(DrawProgram {
                    label: kind.name().to_string(),
                    attributes: info.attributes.iter().map(|(i, n)| (*i, n.to_string())).collect(),
                    textures,
                    inputs: kind.inputs(),
                    uniform_buffers: Vec::new(),
                    source: ProgramDraw::Builtin { kind: *kind, uniforms: *uniforms },
                })
            }
            ProgramObject::Glsl(p) => {
                let label = format!("GLSL program {id}");
                let mut attributes = Vec::new();
                let mut generic = Vec::new();
                for a in p.compiled.attributes() {
                    let columns = if let Type::Matrix(c, _) = a.ty { c as u32 } else { 1 };
                    for location in a.location..a.location + columns {
                        if location >= MAX_VERTEX_ATTRIBS {
                            return Err(format!(
                                "{label}: attribute '{}' is at location {location}, but the context has {} vertex \
                                 attributes",
                                a.name, MAX_VERTEX_ATTRIBS
                            ));
                        }
                        let attrib = &self.state.attribs[location as usize];
                        if attrib.enabled {
                            attributes.push((location, a.name.clone()));
                        } else {
                            generic.push((location, self.state.generic[location as usize]));
                        }
                    }
                }
                let mut textures: Vec<SampledTexture> = Vec::new();
                // A shadow sampler reads the unit's 2D texture, which must be a depth one
                // (GL ES 3.0 §3.8.16 leaves a colour texture's compare undefined).
                let shadow = p.compiled.sampler_units_of(SamplerKind::Sampler2DShadow, &p.uniforms);
                let plain = p.compiled.sampler_units_of(SamplerKind::Sampler2D, &p.uniforms);
                for (name, unit) in shadow.iter().chain(&plain).cloned() {
                    if textures.iter().any(|t| t.unit == unit) {
                        continue;
                    }
                    let texture = self.state.textures.get(unit as usize).copied().unwrap_or(0);
                    if texture == 0 {
                        return Err(format!(
                            "{label}: sampler '{name}' reads texture unit {unit}, which has no texture"
                        ));
                    }
                    let t = self.texture(texture)?;
                    if self.images[&t.image].desc.format.is_integer() {
                        return Err(format!(
                            "{label}: sampler '{name}' reads integer texture {texture} ({}) on unit {unit}: integer \
                             textures are read by isampler/usampler (GL leaves this undefined)",
                            self.images[&t.image].desc.format
                        ));
                    }
                    if shadow.iter().any(|(_, u)| *u == unit) && self.images[&t.image].desc.format.is_color() {
                        return Err(format!(
                            "{label}: sampler2DShadow '{name}' reads texture {texture} on unit {unit}, which is not a \
                             depth texture"
                        ));
                    }
                    let (image, sampler, mipmaps) = (t.image, self.unit_sampler(unit, t), t.mipmaps);
                    self.check_has_memory(image, &format!("{label}: sampler '{name}' reads texture {texture}"))?;
                    textures.push(SampledTexture { unit, image, sampler, mipmaps });
                }
                self.integer_samplers(&label, p, &mut textures)?;
                let mut cubes: Vec<(u32, Option<CoreCube>)> = Vec::new();
                for (name, unit) in p.compiled.sampler_units_of(SamplerKind::SamplerCube, &p.uniforms) {
                    if cubes.iter().any(|(u, _)| *u == unit) {
                        continue;
                    }
                    if textures.iter().any(|t| t.unit == unit) {
                        return Err(format!(
                            "{label}: samplerCube '{name}' and a sampler2D both read texture unit {unit} (a GL error)"
                        ));
                    }
                    cubes.push((unit, self.cube_binding(unit, &format!("{label}: sampler '{name}'"))?));
                }
                // 2-D array and 3-D textures go with the cubes: core textures bound by unit.
                let mut layered_units: Vec<(u32, SamplerKind)> = Vec::new();
                for (kind, target) in [
                    (SamplerKind::Sampler2DArray, LayeredTarget::Array2D),
                    (SamplerKind::Sampler3D, LayeredTarget::Texture3D),
                ] {
                    for (name, unit) in p.compiled.sampler_units_of(kind, &p.uniforms) {
                        if layered_units.contains(&(unit, kind)) {
                            continue;
                        }
                        if cubes.iter().any(|(u, _)| *u == unit) || textures.iter().any(|t| t.unit == unit) {
                            return Err(format!(
                                "{label}: sampler '{name}' ({kind:?}) and a sampler of another type both read \
                                 texture unit {unit} (a GL error)"
                            ));
                        }
                        let what = format!("{label}: sampler '{name}'");
                        cubes.push((unit, Some(self.layered_binding(unit, target, &what)?)));
                        layered_units.push((unit, kind));
                    }
                }
                let mut uniforms = p.uniforms.clone();
                let uniform_buffers = self.read_uniform_blocks(&label, p, &mut uniforms)?;
                Ok(DrawProgram {
                    label,
                    attributes,
                    textures,
                    inputs: 0,
                    uniform_buffers,
                    source: ProgramDraw::Glsl { program: p.compiled.clone(), uniforms, generic, cubes, instance: 0 },
                })
            }
        }
    }

    /// The 2D textures of a program's `isampler2D`/`usampler2D` samplers, checked: an integer
    /// texture of the sampler's signedness, one level, nearest filters (GL ES 3.0 §3.8.13: a
    /// linear filter makes an integer texture incomplete). 2-D array and 3-D integer textures
    /// are refused.
    fn integer_samplers(&self, label: &str, p: &GlslProgram, textures: &mut Vec<SampledTexture>) -> Fallible {
        use tiler_glsl::IntegerShape;
        for shape in [IntegerShape::Flat, IntegerShape::Array, IntegerShape::Volume] {
            for unsigned in [false, true] {
                let kind = SamplerKind::Integer { shape, unsigned };
                for (name, unit) in p.compiled.sampler_units_of(kind, &p.uniforms) {
                    let what = format!("{label}: {} '{name}' on unit {unit}", Type::Sampler(kind));
                    if shape != IntegerShape::Flat {
                        return Err(format!("{what}: 2-D array and 3-D integer textures are not supported"));
                    }
                    if let Some(other) = textures.iter().find(|t| t.unit == unit) {
                        if !self.images[&other.image].desc.format.is_integer() {
                            return Err(format!("{what}: a sampler of another type reads the same unit (a GL error)"));
                        }
                        continue;
                    }
                    let texture = self.state.textures.get(unit as usize).copied().unwrap_or(0);
                    if texture == 0 {
                        return Err(format!("{what}: the unit has no texture"));
                    }
                    let t = self.texture(texture)?;
                    let format = self.images[&t.image].desc.format;
                    match format {
                        tiler::Format::Int(f) if f.signed != unsigned => {}
                        _ => {
                            return Err(format!(
                                "{what} reads texture {texture} ({format}), not an {} integer texture (GL leaves \
                                 that undefined)",
                                if unsigned { "unsigned" } else { "signed" }
                            ));
                        }
                    }
                    let sampler = self.unit_sampler(unit, t);
                    let nearest = |f: crate::call::Filter| {
                        matches!(f, crate::call::Filter::Nearest | crate::call::Filter::NearestMipmapNearest)
                    };
                    if !nearest(sampler.min_filter) || !nearest(sampler.mag_filter) {
                        return Err(format!(
                            "{what}: texture {texture} ({format}) is filtered {:?}/{:?}; an integer texture with a \
                             linear filter is incomplete (GL ES 3.0 §3.8.13): set NEAREST",
                            sampler.min_filter, sampler.mag_filter
                        ));
                    }
                    if t.mipmaps {
                        return Err(format!("{what}: mip-mapped integer textures are not supported"));
                    }
                    self.check_has_memory(t.image, &format!("{what} reads texture {texture}"))?;
                    textures.push(SampledTexture { unit, image: t.image, sampler, mipmaps: false });
                }
            }
        }
        Ok(())
    }

    /// An integer image as a GLSL integer texture: its rows (tiler's, top first) turned into
    /// GL's (the first uploaded, the bottom, first).
    fn integer_texture(&self, image: ImageId, sampler: SamplerState) -> Fallible<TextureBinding> {
        let d = self.images[&image].desc;
        let tiler::Format::Int(format) = d.format else { unreachable!("checked by integer_samplers") };
        let data = self.device.image_data(image).map_err(|e| e.to_string())?;
        let row = d.width as usize * format.bytes();
        let rows: Vec<u8> = data[..row * d.height as usize].chunks_exact(row).rev().flatten().copied().collect();
        let texture = tiler::IntegerTexture::new(format, tiler::IntegerKind::Flat, d.width, d.height, &[&rows])
            .map_err(|e| e.to_string())?;
        Ok(TextureBinding::Integer(Arc::new(texture), super::submit::core_sampler(sampler, false)))
    }

    /// The pipeline of a gathered draw of a program, its textures made once per submission
    /// (`snapshots`, `cores`); `framebuffer_height` gives GLSL's `gl_FragCoord` its y up.
    ///
    /// # Errors
    /// A texture that cannot be read (outer); what `Pipeline::new` refuses (inner).
    pub(crate) fn program_draw_pipeline(
        &self,
        program: &ProgramDraw,
        textures: &[SampledTexture],
        snapshots: &mut HashMap<ImageId, Arc<TextureSnapshot>>,
        cores: &mut HashMap<ImageId, Arc<tiler::Texture>>,
        framebuffer_height: u32,
        mut desc: PipelineDesc,
    ) -> Fallible<tiler::Result<Pipeline>> {
        match program {
            ProgramDraw::Builtin { kind, uniforms } => {
                let texture = match textures.first() {
                    Some(t) => Some(self.program_texture(snapshots, cores, t.image, t.sampler, t.mipmaps)?),
                    None => None,
                };
                Ok(program_pipeline(*kind, uniforms, texture, desc))
            }
            ProgramDraw::Glsl { program, uniforms, generic, cubes, instance } => {
                let units = self.texture_units(textures, cubes, snapshots, cores)?;
                desc.varyings = program.pipeline_varyings();
                // GL ES 3.0 §2.18: flat varyings come from each primitive's last vertex.
                desc.provoking_vertex = tiler::ProvokingVertex::Last;
                if desc.topology == tiler::Topology::PointList {
                    desc.point_size_varying = program.point_size_varying();
                    desc.point_coord_varying = program.point_coord_varying();
                }
                let (mut vertex, fragment) = tiler_glsl::shaders(program, uniforms, &units, framebuffer_height);
                vertex.set_instance(*instance);
                vertex.set_integer_attributes(&desc.vertex_input, 0);
                let generic: Vec<(usize, [f32; 4])> = generic.iter().map(|(l, v)| (*l as usize, *v)).collect();
                vertex.set_constant_attributes(&generic);
                Ok(Pipeline::new(vertex, fragment, desc))
            }
        }
    }

    /// What each texture unit holds for a GLSL program's draw: its 2D textures (`textures`),
    /// cubes and layered textures (`cubes`), made once per submission (`snapshots`, `cores`).
    pub(crate) fn texture_units(
        &self,
        textures: &[SampledTexture],
        cubes: &[(u32, Option<CoreCube>)],
        snapshots: &mut HashMap<ImageId, Arc<TextureSnapshot>>,
        cores: &mut HashMap<ImageId, Arc<tiler::Texture>>,
    ) -> Fallible<Vec<Option<TextureBinding>>> {
        let mut units: Vec<Option<TextureBinding>> = vec![None; MAX_TEXTURE_UNITS as usize];
        for t in textures {
            if self.images[&t.image].desc.format.is_integer() {
                units[t.unit as usize] = Some(self.integer_texture(t.image, t.sampler)?);
                continue;
            }
            units[t.unit as usize] =
                Some(match self.program_texture(snapshots, cores, t.image, t.sampler, t.mipmaps)? {
                    ProgramTexture::Core(texture, sampler) => TextureBinding::Core(texture, sampler),
                    ProgramTexture::Snapshot(snapshot, state) => {
                        TextureBinding::Custom(Arc::new(SnapshotSource { snapshot, state }))
                    }
                });
        }
        for (unit, cube) in cubes {
            // An incomplete cube (`None`) reads (0, 0, 0, 1), as an unbound unit does.
            units[*unit as usize] = cube.clone().map(|(texture, sampler)| TextureBinding::Core(texture, sampler));
        }
        Ok(units)
    }

    /// `glBindAttribLocation`.
    pub(crate) fn bind_attrib_location(&mut self, program: u32, index: u32, name: String) -> Fallible {
        if index >= MAX_VERTEX_ATTRIBS {
            return Err(format!("vertex attribute {index} is out of range (0 to {})", MAX_VERTEX_ATTRIBS - 1));
        }
        if name.starts_with("gl_") {
            return Err(format!("attribute name '{name}' is reserved (it starts with gl_)"));
        }
        match self.programs.get_mut(&program).ok_or_else(|| format!("program {program} does not exist"))? {
            ProgramObject::Builtin { kind, .. } => match kind.info().attributes.iter().find(|(_, n)| *n == name) {
                Some((fixed, _)) if *fixed != index => Err(format!(
                    "built-in program '{}' reads '{name}' from attribute {fixed}; its locations are fixed",
                    kind.name()
                )),
                _ => Ok(()),
            },
            ProgramObject::Glsl(p) => p
                .bind_attrib_location(name.clone(), index)
                .map_err(|e| format!("program {program}, relinked with '{name}' at {index}: {e}")),
        }
    }

    /// The uniforms of program `program` a `uniform` call can name, as `glGetActiveUniform`
    /// lists them (arrays as `name[0]`, struct members as `light.color`); `None` if there is
    /// no such program.
    pub fn uniform_names(&self, program: u32) -> Option<Vec<String>> {
        Some(match self.programs.get(&program)? {
            ProgramObject::Builtin { kind, .. } => kind.info().uniforms.iter().map(|(n, _)| n.to_string()).collect(),
            ProgramObject::Glsl(p) => uniform_names(&p.compiled),
        })
    }

    /// Elements of the uniform array `base` of program `program` (1 for a uniform that is not
    /// an array); `None` if there is no such program or GLSL uniform.
    pub fn uniform_elements(&self, program: u32, base: &str) -> Option<usize> {
        match self.programs.get(&program)? {
            ProgramObject::Builtin { .. } => None,
            ProgramObject::Glsl(p) => p.compiled.uniforms().iter().find(|u| u.name == base).map(|u| u.array_size),
        }
    }

    /// The attribute locations of program `program` after linking, `(name, location)`;
    /// `None` if there is no such program.
    pub fn attribute_locations(&self, program: u32) -> Option<Vec<(String, u32)>> {
        Some(match self.programs.get(&program)? {
            ProgramObject::Builtin { kind, .. } => {
                kind.info().attributes.iter().map(|(i, n)| (n.to_string(), *i)).collect()
            }
            ProgramObject::Glsl(p) => p.compiled.attributes().iter().map(|a| (a.name.clone(), a.location)).collect(),
        })
    }
}

/// A [`TextureSnapshot`] as a GLSL texture unit: no mip levels, so an explicit LOD reads the
/// base level.
#[derive(Debug)]
struct SnapshotSource {
    snapshot: Arc<TextureSnapshot>,
    state: SamplerState,
}

impl TextureSource for SnapshotSource {
    fn sample(&self, s: f32, t: f32, _lod: Option<f32>) -> [f32; 4] {
        self.snapshot.sample(s, t, self.state)
    }

    fn sample_lanes(&self, s: &[f32], t: &[f32], out: &mut [[f32; 4]]) {
        self.snapshot.sample_lanes(s, t, self.state, out);
    }

    fn sample_compare(&self, s: f32, t: f32, reference: f32, _lod: Option<f32>) -> f32 {
        self.snapshot.sample_compare(s, t, reference, self.state)
    }

    fn fetch(&self, x: i32, y: i32, level: i32) -> Option<[f32; 4]> {
        self.snapshot.fetch(x, y, level)
    }

    fn size(&self, level: i32) -> [u32; 2] {
        match level {
            0 => [self.snapshot.width, self.snapshot.height],
            _ => [0; 2],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;
    use tiler::{VertexInput, VertexOutput, VertexShader};

    /// Disabled attributes read their generic values (`set_constant_attributes`): a batch
    /// shades each vertex as `shade` does alone, and as the fetched inputs patched with the
    /// values would (what the driver did before, copying every vertex).
    #[test]
    fn generic_attributes_shade_a_batch_as_one_by_one() {
        let vs = "attribute vec2 p;\nattribute vec4 tint;\nattribute float k;\nvarying vec4 v;\n\
                  void main() { v = tint * p.x + vec4(p.y) + k; gl_Position = vec4(p, 0.0, 1.0); }";
        let fs = "precision mediump float;\nvarying vec4 v;\nvoid main() { gl_FragColor = v; }";
        let program = Arc::new(CompiledProgram::new(vs, fs, &[("p", 0), ("tint", 1), ("k", 2)]).unwrap());
        let uniforms = program.new_uniform_values();
        let (mut shader, _) = tiler_glsl::shaders(&program, &uniforms, &[], 16);
        let (plain, _) = tiler_glsl::shaders(&program, &uniforms, &[], 16);
        let generic = [(1usize, [0.25, 2.0, -1.0, 0.5]), (2, [3.0, 0.0, 0.0, 1.0])];
        shader.set_constant_attributes(&generic);
        let inputs: Vec<VertexInput> = (0..11)
            .map(|i| {
                let mut input = VertexInput::default();
                input.attributes[0] = Vec4::new(i as f32 * 0.5, 1.0 - i as f32, 0.0, 1.0);
                input.attributes[1] = Vec4::splat(99.0);
                input.attributes[2] = Vec4::splat(-7.0);
                input
            })
            .collect();
        let patched: Vec<VertexInput> = inputs
            .iter()
            .map(|input| {
                let mut input = *input;
                for (location, value) in generic {
                    input.attributes[location] = Vec4::from_array(value);
                }
                input
            })
            .collect();
        let mut one_by_one = vec![VertexOutput::default(); inputs.len()];
        for (input, out) in inputs.iter().zip(&mut one_by_one) {
            shader.shade(input, out);
        }
        let mut batched = vec![VertexOutput::default(); inputs.len()];
        shader.shade_batch(&inputs, &mut batched);
        let mut reference = vec![VertexOutput::default(); inputs.len()];
        plain.shade_batch(&patched, &mut reference);
        for ((a, b), c) in one_by_one.iter().zip(&batched).zip(&reference) {
            assert_eq!(a.position, b.position);
            assert_eq!(a.varyings[..4], b.varyings[..4]);
            assert_eq!(b.position, c.position);
            assert_eq!(b.varyings[..4], c.varyings[..4]);
        }
        assert_eq!(
            batched[2].varyings[..4],
            [0.25 - 1.0 + 3.0, 2.0 - 1.0 + 3.0, -1.0 - 1.0 + 3.0, 0.5 - 1.0 + 3.0],
            "the generic values"
        );
    }
}
