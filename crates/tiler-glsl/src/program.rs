//! Linking (attributes, varyings, uniforms, samplers) and program instances: a compiled
//! program with uniform values, textures and the framebuffer height, as tiler shaders.

use std::cell::RefCell;
use std::fmt;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use glam::Vec4;
use tiler::{
    F32x8, FragmentShader, Fragments, IntegerTexture, Interpolation, LaneMask, LayeredKind, Pipeline, PipelineDesc,
    Sampler, ShaderProperties, Texture, VertexInput, VertexOutput, VertexShader,
};

use crate::compile::{StageCode, compile};
use crate::exec::{Env, Executable, LodValue, run};
use crate::ir::{Axis, BANK, Inst, Reg};
use crate::types::{SamplerKind, Scalar, Type};
use crate::{Error, Stage};

/// A vertex attribute of a linked program.
#[derive(Clone, Debug, PartialEq)]
pub struct AttributeInfo {
    pub name: String,
    /// `float`, `vecN` or `matN` (a `matN` takes N consecutive locations, one per column).
    pub ty: Type,
    pub location: u32,
}

/// A varying of a linked program: where its floats sit in tiler's varyings.
#[derive(Clone, Debug, PartialEq)]
pub struct VaryingInfo {
    pub name: String,
    pub ty: Type,
    /// Its first float in [`VertexOutput::varyings`]; it takes `ty.size()` floats.
    pub first: usize,
    /// Qualified `flat`: the provoking vertex's value (every integer varying is).
    pub flat: bool,
}

/// An active uniform as GL introspection lists it: arrays of basic types are one entry
/// (`name` without `[0]`), structs are listed field by field (`light.color`,
/// `lights[1].color`).
#[derive(Clone, Debug, PartialEq)]
pub struct UniformInfo {
    pub name: String,
    /// The element type: a scalar, vector, matrix or `sampler2D`/`samplerCube`.
    pub ty: Type,
    /// 1 for a non-array.
    pub array_size: usize,
    /// The location of element 0; element `k` is at `location + k`.
    pub location: u32,
    /// Where its values start in [`UniformValues`] (floats; each element `ty.size()`).
    offset: usize,
}

/// A uniform block (ES 3.00) of a program: its members' values are read from a buffer laid
/// out `std140` ([`CompiledProgram::set_uniform_block`]).
#[derive(Clone, Debug, PartialEq)]
pub struct UniformBlockInfo {
    /// The block's name (not its instance name), as `glGetUniformBlockIndex` takes it.
    pub name: String,
    /// The bytes the block takes in its buffer.
    pub size: usize,
    ty: Type,
    /// Where its values start in [`UniformValues`].
    offset: usize,
}

/// A compiled and linked GLSL ES program.
#[derive(Clone, Debug)]
pub struct CompiledProgram {
    vertex: StageCode,
    fragment: StageCode,
    /// The stages' code as the executor runs it (one register file, checked registers).
    vertex_executable: Executable,
    fragment_executable: Executable,
    attributes: Vec<AttributeInfo>,
    varyings: Vec<VaryingInfo>,
    uniforms: Vec<UniformInfo>,
    blocks: Vec<UniformBlockInfo>,
    /// For each declared uniform of each stage, its offset in the values.
    vertex_uniform_offsets: Vec<usize>,
    fragment_uniform_offsets: Vec<usize>,
    uniform_floats: usize,
    /// Floats of tiler varyings the program uses (the varyings, then `w` if needed).
    varying_floats: usize,
    /// The hidden varying carrying clip-space w for `gl_FragCoord.w`.
    w_varying: Option<usize>,
    /// The hidden varying carrying `gl_PointSize`, when the vertex shader names it.
    point_size_varying: Option<usize>,
    /// The hidden pair of varyings the core fills with `gl_PointCoord` at a point's corners.
    point_coord_varying: Option<usize>,
    /// The sampler uniforms (name, array element) whose texture the compiled code reads: the
    /// active ones. A sampler whose every read the compiler removed (a branch on a constant)
    /// reads nothing, as in GL, where it is inactive (`glGetUniformLocation` gives -1).
    /// (index in `uniforms`, array element), sorted.
    read_samplers: Vec<(usize, usize)>,
}

/// Sampler slots that the instructions in `code` read.
fn slots_read(code: &[Inst], out: &mut Vec<u16>) {
    for inst in code {
        match inst {
            Inst::Sample { slot, .. }
            | Inst::SampleCube { slot, .. }
            | Inst::SampleLayered { slot, .. }
            | Inst::Fetch { slot, .. } => out.push(*slot),
            Inst::If(_, then, otherwise) => {
                slots_read(then, out);
                slots_read(otherwise, out);
            }
            Inst::Loop { cond_code, body, step, .. } => {
                slots_read(cond_code, out);
                slots_read(body, out);
                slots_read(step, out);
            }
            Inst::Call(body) | Inst::Breakable(body) => slots_read(body, out),
            _ => {}
        }
    }
}

/// The sampler uniforms (name, array element) whose texture `stage`'s code reads.
fn samplers_read(stage: &StageCode) -> impl Iterator<Item = (String, usize)> + '_ {
    let mut slots = Vec::new();
    slots_read(&stage.code, &mut slots);
    slots.into_iter().filter_map(|slot| {
        let &(uniform, element) = stage.samplers.get(slot as usize)?;
        Some((stage.uniforms[uniform].name.clone(), element))
    })
}

/// Uniform values by location, as `glUniform*` sets them (ints and samplers' texture units
/// stored as floats; matrices column-major).
#[derive(Clone, Debug, PartialEq)]
pub struct UniformValues {
    values: Vec<f32>,
}

/// A texture lookup the caller implements (formats the core sampler does not take: depth,
/// float). Coordinates are GL's (t = 0 at the first row uploaded, the bottom); `lod` is the
/// explicit level, or `None` for the base level.
pub trait TextureSource: Send + Sync + fmt::Debug {
    fn sample(&self, s: f32, t: f32, lod: Option<f32>) -> [f32; 4];

    /// [`TextureSource::sample`] at the base level (`lod` `None`) of each lane
    /// `(s[i], t[i])`, into `out[i]`: one call for a group's lanes, so that a source can
    /// resolve its state once for them all. The values must be `sample`'s, lane by lane, which
    /// this default asks for.
    fn sample_lanes(&self, s: &[f32], t: &[f32], out: &mut [[f32; 4]]) {
        for ((o, &s), &t) in out.iter_mut().zip(s).zip(t) {
            *o = self.sample(s, t, None);
        }
    }

    /// A shadow sampler's lookup (`sampler2DShadow`): the texels compared with `reference`
    /// by the source's compare function and the results filtered (see
    /// `tiler::depth_compare`); a source without compare mode returns its depth, red, which
    /// is what this default does.
    fn sample_compare(&self, s: f32, t: f32, reference: f32, lod: Option<f32>) -> f32 {
        let _ = reference;
        self.sample(s, t, lod)[0]
    }

    /// `texelFetch`: texel `(x, y)` (row 0 the first uploaded) of level `level`; `None` out of
    /// range (it reads zeros) — and for a source without texel reads, which this default is.
    fn fetch(&self, x: i32, y: i32, level: i32) -> Option<[f32; 4]> {
        let _ = (x, y, level);
        None
    }

    /// `textureSize` at level `level`: width and height, zeros for a level it lacks (and for
    /// a source that does not say, which this default is).
    fn size(&self, level: i32) -> [u32; 2] {
        let _ = level;
        [0; 2]
    }
}

/// What a texture unit holds.
#[derive(Clone, Debug)]
pub enum TextureBinding {
    /// A core texture: fragment shaders sample it through [`Fragments::sample`] (the LOD from
    /// quad derivatives, reads counted in the texture-cache model), at `(s, 1 − t)` since the
    /// core's v runs down the rows; vertex shaders (level of detail 0) and explicit levels
    /// read through the same filters at that level (not counted).
    Core(Arc<Texture>, Sampler),
    /// The caller's own sampler; shadow samplers read it through
    /// [`TextureSource::sample_compare`] (a core texture read by a shadow sampler reads as by
    /// a sampler2D, its red channel the result: GL leaves that undefined).
    Custom(Arc<dyn TextureSource>),
    /// An integer texture (`isampler2D`, `usampler2D`, …): `texelFetch` reads it by texel,
    /// `texture` its nearest texel of level 0 with the sampler's wraps (GL never filters
    /// integers); fragment shaders' reads are counted in the texture-cache model.
    Integer(Arc<IntegerTexture>, Sampler),
}

/// An integer texel's channels as a shader's registers hold them (their bits).
fn integer_texel(texel: [u32; 4]) -> [f32; 4] {
    texel.map(f32::from_bits)
}

/// `texelFetch` of lanes `0..lanes` one by one, not counted in the ledger (the others, and
/// every lane of an unbound unit, read zeros; a cube has no texel fetch).
fn fetch_lanes<const W: usize>(
    binding: Option<&TextureBinding>,
    coord: [[i32; W]; 3],
    level: [i32; W],
    lanes: usize,
) -> [[f32; W]; 4] {
    let mut out = [[0.0; W]; 4];
    for lane in 0..lanes {
        let at = coord.map(|c| c[lane]);
        let texel = match binding {
            Some(TextureBinding::Core(texture, _)) => {
                let at = core_rows(texture, [[at[0]], [at[1]], [at[2]]], [level[lane]]).map(|c| c[0]);
                texture.fetch(level[lane], at).map(|(v, _)| v)
            }
            Some(TextureBinding::Integer(texture, _)) => texture.fetch(level[lane], at).map(|(v, _)| integer_texel(v)),
            Some(TextureBinding::Custom(source)) if at[2] == 0 => source.fetch(at[0], at[1], level[lane]),
            _ => None,
        };
        for c in 0..4 {
            out[c][lane] = texel.map_or(0.0, |t| t[c]);
        }
    }
    out
}

/// `textureGather` of channel `comp` (see `ir::Lod::Gather`) at GL coordinates `coord` with
/// `offset` added to the texel indices before the wrap, through `env`'s `texelFetch` of level
/// 0 (so a fragment shader's reads are counted as its texel fetches are); zeros for an unbound
/// unit or a texture without a level 0.
fn gather<const W: usize>(
    env: &mut impl Env<W>,
    slot: usize,
    binding: Option<&TextureBinding>,
    coord: [[f32; W]; 2],
    offset: [i32; 2],
    comp: u8,
) -> [[f32; W]; 4] {
    let clamp = [tiler::Wrap::ClampToEdge; 2];
    let (size, wrap) = match binding {
        Some(TextureBinding::Core(texture, sampler)) => {
            let [w, h, _] = texture.size(0);
            ([w, h], [sampler.wrap_u, sampler.wrap_v])
        }
        Some(TextureBinding::Integer(texture, sampler)) => {
            let [w, h, _] = texture.size(0);
            ([w, h], [sampler.wrap_u, sampler.wrap_v])
        }
        Some(TextureBinding::Custom(source)) => (source.size(0), clamp),
        None => ([0, 0], clamp),
    };
    if size.contains(&0) {
        return [[0.0; W]; 4];
    }
    // Texel indices of the footprint's lower-left corner, then each corner wrapped.
    let wrapped = |i: i64, n: u32, wrap: tiler::Wrap| wrap.texel(i, n) as i32;
    let mut corners = [[[0i32; W]; 3]; 4];
    for lane in 0..W {
        let base = |c: usize| ((coord[c][lane] * size[c] as f32 - 0.5).floor() as i64).saturating_add(offset[c] as i64);
        let (i0, j0) = (base(0), base(1));
        let (i0, i1) = (wrapped(i0, size[0], wrap[0]), wrapped(i0.saturating_add(1), size[0], wrap[0]));
        let (j0, j1) = (wrapped(j0, size[1], wrap[1]), wrapped(j0.saturating_add(1), size[1], wrap[1]));
        for (k, (i, j)) in [(i0, j1), (i1, j1), (i1, j0), (i0, j0)].into_iter().enumerate() {
            corners[k][0][lane] = i;
            corners[k][1][lane] = j;
        }
    }
    let channel = (comp as usize).min(3);
    corners.map(|at| env.fetch(slot, at, [0; W])[channel])
}

/// `texelFetch` coordinates (GL's: row 0 is the first row uploaded) as a core texture's, whose
/// rows run the other way (its v runs down; see [`TextureBinding::Core`]): `y` becomes
/// `height − 1 − y` of the lane's level. Lanes of a level the texture lacks are left as they
/// are (the fetch reads zeros there).
fn core_rows<const W: usize>(texture: &Texture, mut coord: [[i32; W]; 3], level: [i32; W]) -> [[i32; W]; 3] {
    for lane in 0..W {
        let height = texture.size(level[lane])[1] as i32;
        if height > 0 {
            coord[1][lane] = height - 1 - coord[1][lane];
        }
    }
    coord
}

/// `textureSize` of every lane: width, height and layers (1 for a 2D or cube texture), zeros
/// for an unbound unit or a level the texture lacks.
fn size_lanes<const W: usize>(binding: Option<&TextureBinding>, level: [i32; W]) -> [[i32; W]; 3] {
    let mut out = [[0; W]; 3];
    for (lane, &level) in level.iter().enumerate() {
        let size = match binding {
            Some(TextureBinding::Core(texture, _)) => texture.size(level),
            Some(TextureBinding::Integer(texture, _)) => texture.size(level),
            Some(TextureBinding::Custom(source)) => match source.size(level) {
                [0, _] | [_, 0] => [0; 3],
                [w, h] => [w, h, 1],
            },
            None => [0; 3],
        };
        for c in 0..3 {
            out[c][lane] = size[c] as i32;
        }
    }
    out
}

/// An integer texture's nearest texels at GL's `coord` (`(s, t)` or `(s, t, r)`, see
/// `IntegerTexture::nearest`) in lanes `0..lanes`, as texel coordinates of level 0.
fn integer_nearest<const W: usize, const N: usize>(
    texture: &IntegerTexture,
    sampler: &Sampler,
    coord: [[f32; W]; N],
    lanes: usize,
) -> [[i32; W]; 3] {
    let mut out = [[0; W]; 3];
    for lane in 0..lanes {
        let at = std::array::from_fn(|c| if c < N { coord[c][lane] } else { 0.0 });
        let texel = texture.nearest(sampler, at);
        for c in 0..3 {
            out[c][lane] = texel[c];
        }
    }
    out
}

impl CompiledProgram {
    /// Compiles and links a vertex and a fragment shader. `attribute_locations` are the
    /// `glBindAttribLocation` bindings; other attributes take the lowest free locations in
    /// declaration order.
    ///
    /// # Errors
    /// A compile error (naming the stage and the line) or a link error.
    pub fn new(vertex: &str, fragment: &str, attribute_locations: &[(&str, u32)]) -> Result<CompiledProgram, Error> {
        crate::guard::check_source(Stage::Vertex, vertex)?;
        crate::guard::check_source(Stage::Fragment, fragment)?;
        let (vertex, fragment) =
            crate::guard::with_deep_stacks(|| compile(Stage::Vertex, vertex), || compile(Stage::Fragment, fragment))?;
        let executable = |code: &StageCode| {
            Executable::new(&code.code, code.work_regs, code.bank.len())
                .ok_or_else(|| Error::Link(format!("the {} was lowered with a register out of range", code.stage)))
        };
        let (vertex_executable, fragment_executable) = (executable(&vertex)?, executable(&fragment)?);
        let attributes = link_attributes(&vertex, attribute_locations)?;
        let (varyings, hidden, varying_floats) = link_varyings(&vertex, &fragment)?;
        let (uniforms, blocks, vertex_uniform_offsets, fragment_uniform_offsets, uniform_floats) =
            link_uniforms(&vertex, &fragment)?;
        let mut read_samplers: Vec<(usize, usize)> = samplers_read(&vertex)
            .chain(samplers_read(&fragment))
            .filter_map(|(name, k)| Some((uniforms.iter().position(|u| u.name == name)?, k)))
            .collect();
        read_samplers.sort_unstable();
        read_samplers.dedup();
        Ok(CompiledProgram {
            vertex,
            fragment,
            vertex_executable,
            fragment_executable,
            attributes,
            varyings,
            uniforms,
            blocks,
            vertex_uniform_offsets,
            fragment_uniform_offsets,
            uniform_floats,
            varying_floats,
            w_varying: hidden.w,
            point_size_varying: hidden.point_size,
            point_coord_varying: hidden.point_coord,
            read_samplers,
        })
    }

    /// The program linked again with `attribute_locations` (as [`CompiledProgram::new`] takes
    /// them): the same program as compiling its sources again with them would give, since
    /// only the attributes' locations depend on them, without compiling (a capture binds
    /// attribute after attribute, relinking each time).
    ///
    /// # Errors
    /// A link error of the locations (see `new`).
    pub fn with_attribute_locations(&self, attribute_locations: &[(&str, u32)]) -> Result<CompiledProgram, Error> {
        let attributes = link_attributes(&self.vertex, attribute_locations)?;
        Ok(CompiledProgram { attributes, ..self.clone() })
    }

    /// Attributes in declaration order, with their locations.
    pub fn attributes(&self) -> &[AttributeInfo] {
        &self.attributes
    }

    pub fn varyings(&self) -> &[VaryingInfo] {
        &self.varyings
    }

    /// Active uniforms in declaration order (vertex shader's first), locations ascending.
    pub fn uniforms(&self) -> &[UniformInfo] {
        &self.uniforms
    }

    /// What `glGetUniformLocation` returns: `name`, `name[0]` or `name[k]` for arrays.
    pub fn uniform_location(&self, name: &str) -> Option<u32> {
        let (base, index) = match name.strip_suffix(']').and_then(|n| n.rsplit_once('[')) {
            Some((base, index)) => (base, index.parse::<usize>().ok()?),
            None => (name, 0),
        };
        let u = self.uniforms.iter().find(|u| u.name == base)?;
        (index < u.array_size).then_some(u.location + index as u32)
    }

    pub fn attribute_location(&self, name: &str) -> Option<u32> {
        self.attributes.iter().find(|a| a.name == name).map(|a| a.location)
    }

    /// Instructions of the vertex and fragment code (inlined calls included).
    pub fn instruction_counts(&self) -> (usize, usize) {
        (crate::ir::count_insts(&self.vertex.code), crate::ir::count_insts(&self.fragment.code))
    }

    /// Floats of tiler varyings the program's pipeline declares.
    pub fn varying_floats(&self) -> usize {
        self.varying_floats
    }

    /// The fragment shader's properties: `discards` iff its code can discard.
    /// The vertex stage's code (transform feedback reads its outputs).
    pub(crate) fn vertex_code(&self) -> &StageCode {
        &self.vertex
    }

    pub fn fragment_properties(&self) -> ShaderProperties {
        ShaderProperties { discards: self.fragment.discards, ..ShaderProperties::default() }
    }

    /// Uniform values all zero (GL's initial values).
    pub fn new_uniform_values(&self) -> UniformValues {
        UniformValues { values: vec![0.0; self.uniform_floats] }
    }

    /// Sets the uniform at `location` from `values` (its components, then the next array
    /// elements', as `glUniform*v` with a count). Ints, uints and texture units go as floats
    /// (exact to 2²⁴); an int or uint uniform keeps the integer (truncated, saturated; see
    /// `ir` for how integers are held).
    ///
    /// # Errors
    /// An unknown location, or more values than the uniform has from that element on.
    pub fn set_uniform(&self, uniforms: &mut UniformValues, location: u32, values: &[f32]) -> Result<(), Error> {
        let (u, slots) = self.uniform_slots(location, values.len())?;
        let slots = &mut uniforms.values[slots];
        match u.ty.scalar() {
            Some(Scalar::Int) => slots.iter_mut().zip(values).for_each(|(s, &v)| *s = crate::exec::int(v as i32)),
            Some(Scalar::UInt) => slots.iter_mut().zip(values).for_each(|(s, &v)| *s = crate::exec::uint(v as u32)),
            _ => slots.copy_from_slice(values),
        }
        Ok(())
    }

    /// Sets an `int`/`uint` uniform (scalar, vector or array element) from its components'
    /// 32 bits, exactly whatever their size ([`CompiledProgram::set_uniform`] takes floats,
    /// exact only to ±2²⁴).
    ///
    /// # Errors
    /// No uniform at `location`, a uniform that is not of integers, or too many values.
    pub fn set_uniform_integers(&self, uniforms: &mut UniformValues, location: u32, bits: &[u32]) -> Result<(), Error> {
        let (u, slots) = self.uniform_slots(location, bits.len())?;
        if !matches!(u.ty.scalar(), Some(Scalar::Int | Scalar::UInt)) {
            return Err(Error::Uniform(format!("uniform '{}' is a {}, not of integers", u.name, u.ty)));
        }
        for (slot, &b) in uniforms.values[slots].iter_mut().zip(bits) {
            *slot = f32::from_bits(b);
        }
        Ok(())
    }

    /// The uniform at `location` and the slots `count` values set from there: whole
    /// components, no more than the uniform has from that element on.
    fn uniform_slots(&self, location: u32, count: usize) -> Result<(&UniformInfo, std::ops::Range<usize>), Error> {
        let u = self
            .uniforms
            .iter()
            .find(|u| (u.location..u.location + u.array_size as u32).contains(&location))
            .ok_or_else(|| Error::Uniform(format!("no uniform at location {location}")))?;
        let size = u.ty.size();
        let element = (location - u.location) as usize;
        let room = (u.array_size - element) * size;
        if count > room || !count.is_multiple_of(size) {
            return Err(Error::Uniform(format!(
                "uniform '{}' (location {location}): {count} values for {room} components of {}",
                u.name, u.ty
            )));
        }
        let start = u.offset + element * size;
        Ok((u, start..start + count))
    }

    /// The program's uniform blocks; a block's index is its place here.
    pub fn uniform_blocks(&self) -> &[UniformBlockInfo] {
        &self.blocks
    }

    /// Sets the members of uniform block `block` from `bytes`, the block's data in its
    /// buffer (`std140`, from the bound range's start).
    ///
    /// # Errors
    /// An unknown block, or fewer bytes than the block takes.
    pub fn set_uniform_block(&self, uniforms: &mut UniformValues, block: usize, bytes: &[u8]) -> Result<(), Error> {
        let b = self.blocks.get(block).ok_or_else(|| Error::Uniform(format!("no uniform block {block}")))?;
        if bytes.len() < b.size {
            return Err(Error::Uniform(format!(
                "uniform block '{}' takes {} bytes, but its buffer range has {}",
                b.name,
                b.size,
                bytes.len()
            )));
        }
        let mut values = Vec::with_capacity(b.ty.size());
        crate::std140::read(&b.ty, bytes, &mut values);
        uniforms.values[b.offset..b.offset + values.len()].copy_from_slice(&values);
        Ok(())
    }

    /// The texture units the program's samplers read, per uniform location (for checks).
    pub fn sampler_units(&self, uniforms: &UniformValues) -> Vec<(String, u32)> {
        self.uniforms
            .iter()
            .filter(|u| matches!(u.ty, Type::Sampler(_)))
            .flat_map(|u| (0..u.array_size).map(move |k| (u, k)))
            .map(|(u, k)| (u.name.clone(), uniforms.values[u.offset + k] as u32))
            .collect()
    }

    /// [`CompiledProgram::sampler_units`] of the samplers of one kind (a unit holds a 2D and a
    /// cube texture, each read by its kind of sampler) that the code reads: a sampler whose
    /// reads the compiler removed needs no texture.
    pub fn sampler_units_of(&self, kind: SamplerKind, uniforms: &UniformValues) -> Vec<(String, u32)> {
        self.read_samplers
            .iter()
            .map(|&(i, k)| (&self.uniforms[i], k))
            .filter(|(u, _)| u.ty == Type::Sampler(kind))
            .map(|(u, k)| (u.name.clone(), uniforms.values[u.offset + k] as u32))
            .collect()
    }

    /// The pipeline's varyings: one per float, flat for `flat` varyings, else smooth (the
    /// hidden ones too). GL takes flat values from a primitive's last vertex: the pipeline
    /// needs `ProvokingVertex::Last`.
    pub fn pipeline_varyings(&self) -> Vec<Interpolation> {
        let mut out = vec![Interpolation::Perspective; self.varying_floats];
        for v in self.varyings.iter().filter(|v| v.flat) {
            out[v.first..v.first + v.ty.size()].fill(Interpolation::Flat);
        }
        out
    }

    /// The varying holding each vertex's `gl_PointSize`, if the vertex shader names it.
    pub fn point_size_varying(&self) -> Option<usize> {
        self.point_size_varying
    }

    /// The first of the two varyings a point's corners give `gl_PointCoord`, if the fragment
    /// shader reads it.
    pub fn point_coord_varying(&self) -> Option<usize> {
        self.point_coord_varying
    }
}

/// Locations for the vertex shader's attributes, in its declaration order: bound ones first,
/// then the others at the lowest free locations (a `matN` takes N in a row).
fn link_attributes(vertex: &StageCode, bound: &[(&str, u32)]) -> Result<Vec<AttributeInfo>, Error> {
    let max = tiler::MAX_VERTEX_ATTRIBUTES;
    let columns = |ty: &Type| if let Type::Matrix(c, _) = ty { *c } else { 1 };
    let mut used = vec![false; max];
    let mut locations: Vec<Option<usize>> = vec![None; vertex.inputs.len()];
    for (i, a) in vertex.inputs.iter().enumerate() {
        let Some(loc) = bound.iter().find(|(n, _)| *n == a.name).map(|(_, l)| *l).or(a.location) else { continue };
        let (loc, n) = (loc as usize, columns(&a.ty));
        if loc + n > max {
            return Err(Error::Link(format!("attribute '{}' at location {loc} exceeds {max} attributes", a.name)));
        }
        used[loc..loc + n].fill(true);
        locations[i] = Some(loc);
    }
    for (i, a) in vertex.inputs.iter().enumerate() {
        if locations[i].is_some() {
            continue;
        }
        let n = columns(&a.ty);
        let loc = (0..=max - n)
            .find(|&l| used[l..l + n].iter().all(|u| !u))
            .ok_or_else(|| Error::Link(format!("no free location for attribute '{}'", a.name)))?;
        used[loc..loc + n].fill(true);
        locations[i] = Some(loc);
    }
    Ok(vertex
        .inputs
        .iter()
        .zip(locations)
        .map(|(a, loc)| AttributeInfo {
            name: a.name.clone(),
            ty: a.ty.clone(),
            location: loc.expect("assigned") as u32,
        })
        .collect())
}

/// The hidden varyings after the declared ones: each the index of its first float.
struct HiddenVaryings {
    w: Option<usize>,
    point_size: Option<usize>,
    point_coord: Option<usize>,
}

fn link_varyings(vertex: &StageCode, fragment: &StageCode) -> Result<(Vec<VaryingInfo>, HiddenVaryings, usize), Error> {
    let mut out = Vec::new();
    let mut next = 0;
    for v in &fragment.inputs {
        let Some(vs) = vertex.outputs.iter().find(|o| o.name == v.name) else {
            return Err(Error::Link(format!(
                "varying '{}' is read by the fragment shader but not declared by the vertex shader",
                v.name
            )));
        };
        if vs.ty != v.ty {
            return Err(Error::Link(format!(
                "varying '{}' is a {} in the vertex shader and a {} in the fragment shader",
                v.name, vs.ty, v.ty
            )));
        }
        if vs.flat != v.flat {
            // GLSL ES 3.00 §4.3.9: the stages' interpolation qualifiers must match.
            return Err(Error::Link(format!(
                "varying '{}' is {} in the vertex shader and {} in the fragment shader",
                v.name,
                if vs.flat { "flat" } else { "smooth" },
                if v.flat { "flat" } else { "smooth" }
            )));
        }
        out.push(VaryingInfo { name: v.name.clone(), ty: v.ty.clone(), first: next, flat: v.flat });
        next += v.ty.size();
    }
    let mut hidden = |needed: bool, floats: usize| {
        needed.then(|| {
            next += floats;
            next - floats
        })
    };
    let w = hidden(fragment.frag_coord.is_some(), 1);
    let point_size = hidden(vertex.point_size.is_some(), 1);
    let point_coord = hidden(fragment.point_coord.is_some(), 2);
    if next > tiler::MAX_VARYINGS {
        return Err(Error::Link(format!("{next} varying floats, at most {}", tiler::MAX_VARYINGS)));
    }
    Ok((out, HiddenVaryings { w, point_size, point_coord }, next))
}

type UniformLink = (Vec<UniformInfo>, Vec<UniformBlockInfo>, Vec<usize>, Vec<usize>, usize);

fn link_uniforms(vertex: &StageCode, fragment: &StageCode) -> Result<UniformLink, Error> {
    // Declared uniforms, merged by name: (name, type, offset).
    let mut declared: Vec<(String, Type, usize)> = Vec::new();
    let mut floats = 0;
    let mut offsets = [Vec::new(), Vec::new()];
    for (s, stage) in [vertex, fragment].into_iter().enumerate() {
        for u in &stage.uniforms {
            match declared.iter().find(|(n, _, _)| *n == u.name) {
                Some((_, ty, offset)) => {
                    if *ty != u.ty {
                        return Err(Error::Link(format!(
                            "uniform '{}' is a {ty} in the vertex shader and a {} in the fragment shader",
                            u.name, u.ty
                        )));
                    }
                    offsets[s].push(*offset);
                }
                None => {
                    declared.push((u.name.clone(), u.ty.clone(), floats));
                    offsets[s].push(floats);
                    floats += u.ty.size();
                }
            }
        }
    }
    let mut infos = Vec::new();
    let mut blocks = Vec::new();
    let mut location = 0;
    for (name, ty, offset) in &declared {
        // A block's members have no locations (GL ES 3.0 §2.12.6): their values come from a
        // buffer.
        if vertex.blocks.contains(name) || fragment.blocks.contains(name) {
            let size = crate::std140::size(ty);
            blocks.push(UniformBlockInfo { name: name.clone(), size, ty: ty.clone(), offset: *offset });
        } else {
            leaves(name, ty, *offset, &mut infos, &mut location);
        }
    }
    let [v, f] = offsets;
    Ok((infos, blocks, v, f, floats))
}

/// Lists the GL-visible leaves of a uniform of type `ty` at `offset`.
fn leaves(name: &str, ty: &Type, offset: usize, out: &mut Vec<UniformInfo>, location: &mut u32) {
    match ty {
        Type::Struct(s) => {
            let mut o = offset;
            for (field, fty) in &s.fields {
                leaves(&format!("{name}.{field}"), fty, o, out, location);
                o += fty.size();
            }
        }
        Type::Array(elem, n) if matches!(**elem, Type::Struct(_) | Type::Array(..)) => {
            for k in 0..*n {
                leaves(&format!("{name}[{k}]"), elem, offset + k * elem.size(), out, location);
            }
        }
        Type::Array(elem, n) => {
            out.push(UniformInfo {
                name: name.into(),
                ty: (**elem).clone(),
                array_size: *n,
                location: *location,
                offset,
            });
            *location += *n as u32;
        }
        _ => {
            out.push(UniformInfo { name: name.into(), ty: ty.clone(), array_size: 1, location: *location, offset });
            *location += 1;
        }
    }
}

/// A stage's bank with the uniform values in place, and its sampler slots' bindings.
fn stage_state<const W: usize>(
    code: &StageCode,
    offsets: &[usize],
    uniforms: &UniformValues,
    textures: &[Option<TextureBinding>],
) -> (Vec<[f32; W]>, Vec<Option<TextureBinding>>) {
    let mut bank: Vec<[f32; W]> = code.bank.iter().map(|&x| [x; W]).collect();
    let mut slots = vec![None; code.samplers.len()];
    for (u, var) in code.uniforms.iter().enumerate() {
        let base = offsets[u];
        for (k, &r) in var.regs.iter().enumerate() {
            let value = uniforms.values[base + k];
            if r & BANK != 0 {
                bank[(r & !BANK) as usize] = [value; W];
            } else if value >= 0.0 {
                slots[r as usize] = textures.get(value as usize).cloned().flatten();
            }
        }
    }
    crate::exec::run_bank(&code.bank_program, &mut bank);
    (bank, slots)
}

/// A program with its uniform values and textures: builds the vertex and fragment shaders.
///
/// `textures[unit]` is what texture unit `unit` holds (an unbound unit reads as opaque
/// black, as an incomplete texture does in GL). `framebuffer_height` turns tiler's window y
/// (down) into GL's `gl_FragCoord.y` (up).
pub fn shaders(
    program: &Arc<CompiledProgram>,
    uniforms: &UniformValues,
    textures: &[Option<TextureBinding>],
    framebuffer_height: u32,
) -> (GlslVertexShader, GlslFragmentShader) {
    let (vbank, vslots) =
        stage_state::<VERTEX_LANES>(&program.vertex, &program.vertex_uniform_offsets, uniforms, textures);
    let (fbank, fslots) = stage_state::<8>(&program.fragment, &program.fragment_uniform_offsets, uniforms, textures);
    let outputs: Vec<(Reg, usize)> = program
        .varyings
        .iter()
        .flat_map(|v| {
            let vs = program.vertex.outputs.iter().find(|o| o.name == v.name).expect("linked");
            vs.regs.iter().enumerate().map(move |(k, &r)| (r, v.first + k))
        })
        .collect();
    // Each attribute component the vertex code reads: its register, location (a matrix takes
    // one per column), row, and whether it is an integer.
    let read = program.vertex_executable.read_registers();
    let attributes: Vec<AttributeComponent> = program
        .attributes
        .iter()
        .zip(&program.vertex.inputs)
        .flat_map(|(attr, var)| {
            var.regs.iter().enumerate().map(move |(k, &register)| {
                let (column, row) = match var.ty {
                    Type::Matrix(_, rows) => (k / rows, k % rows),
                    _ => (0, k),
                };
                let integer = var.ty.scalar().filter(|s| matches!(s, Scalar::Int | Scalar::UInt));
                AttributeComponent { register, location: attr.location as usize + column, row, integer, constant: None }
            })
        })
        .filter(|c| read.get(c.register as usize).copied().unwrap_or(true))
        .collect();
    // Only the varying components the fragment code reads are interpolated: a shader may
    // declare varyings it never reads (glmark2's `conditionals` a `vec4`), and an unread
    // register changes nothing.
    let read = program.fragment_executable.read_registers();
    let inputs: Vec<(Reg, usize, bool)> = program
        .fragment
        .inputs
        .iter()
        .zip(&program.varyings)
        .flat_map(|(input, v)| input.regs.iter().enumerate().map(move |(k, &r)| (r, v.first + k, v.flat)))
        .filter(|&(r, ..)| read.get(r as usize).copied().unwrap_or(true))
        .collect();
    (
        GlslVertexShader {
            program: program.clone(),
            id: new_instance(),
            bank: vbank,
            slots: vslots,
            attributes,
            outputs,
            instance: 0,
            bit_attributes: 0,
        },
        GlslFragmentShader {
            program: program.clone(),
            id: new_instance(),
            bank: fbank,
            slots: fslots,
            inputs,
            height: framebuffer_height as f32,
        },
    )
}

/// [`shaders`] made into a pipeline: `desc.varyings` is set to the program's.
///
/// # Errors
/// What [`Pipeline::new`] refuses.
pub fn pipeline(
    program: &Arc<CompiledProgram>,
    uniforms: &UniformValues,
    textures: &[Option<TextureBinding>],
    framebuffer_height: u32,
    mut desc: PipelineDesc,
) -> tiler::Result<Pipeline> {
    desc.varyings = program.pipeline_varyings();
    desc.provoking_vertex = tiler::ProvokingVertex::Last;
    let (mut vs, fs) = shaders(program, uniforms, textures, framebuffer_height);
    vs.set_integer_attributes(&desc.vertex_input, 0);
    Pipeline::new(vs, fs, desc)
}

/// The lanes the vertex shader runs: a batch of [`tiler::VERTEX_BATCH`] vertices.
const VERTEX_LANES: usize = tiler::VERTEX_BATCH;

/// A program's vertex shader: a batch of vertices per call, one lane each.
pub struct GlslVertexShader {
    program: Arc<CompiledProgram>,
    /// This instance's identity (see `WorkFile`).
    id: u64,
    bank: Vec<[f32; VERTEX_LANES]>,
    slots: Vec<Option<TextureBinding>>,
    /// The attribute components the code reads, in the order of the program's attributes.
    attributes: Vec<AttributeComponent>,
    /// Each linked varying component's vertex register and float.
    outputs: Vec<(Reg, usize)>,
    /// `gl_InstanceID`.
    instance: u32,
    /// Bit `l`: attribute location `l` arrives as integer bits (`VertexFormat::Int`), not as
    /// a float whose value an integer attribute takes.
    bit_attributes: u32,
}

/// Where a vertex shader's attribute component comes from: row `row` of attribute location
/// `location`, into `register`; `integer`: an `int` or `uint` attribute's scalar type.
#[derive(Clone, Copy, Debug)]
struct AttributeComponent {
    register: Reg,
    location: usize,
    row: usize,
    integer: Option<Scalar>,
    /// The value every vertex takes, for a location fed a constant
    /// ([`GlslVertexShader::set_constant_attributes`]) rather than fetched.
    constant: Option<f32>,
}

impl GlslVertexShader {
    /// Makes the shader run instance `instance` of an instanced draw (`gl_InstanceID`;
    /// 0 unless set).
    pub fn set_instance(&mut self, instance: u32) {
        self.instance = instance;
    }

    /// Tells the shader which attribute locations `input` fetches as integers
    /// (`VertexFormat::Int`, GL's `glVertexAttribIPointer`): an integer attribute there takes
    /// the bits as they are (exact over 32 bits); elsewhere it takes a float's value.
    /// `also` adds locations (a disabled attribute's integer generic value, say).
    /// Feeds attribute locations a constant instead of what the core fetches for them: GL's
    /// generic attribute value of an attribute whose array is disabled (`glVertexAttrib4f`),
    /// `(location, value)`. Every vertex takes the value as it would had the core fetched it.
    /// (Patching each fetched `VertexInput` instead — 144 bytes copied a vertex — cost 2.4%
    /// of the glmark2 shading capture.)
    pub fn set_constant_attributes(&mut self, constants: &[(usize, [f32; 4])]) {
        for component in &mut self.attributes {
            component.constant =
                constants.iter().rev().find(|(l, _)| *l == component.location).map(|(_, v)| v[component.row]);
        }
    }

    pub fn set_integer_attributes(&mut self, input: &tiler::VertexInputState, also: u32) {
        self.bit_attributes = also;
        for a in &input.attributes {
            if matches!(a.format, tiler::VertexFormat::Int(_)) && a.location < 32 {
                self.bit_attributes |= 1 << a.location;
            }
        }
    }
}

/// A program's fragment shader: one 4×2 group per call, run with eight lanes.
pub struct GlslFragmentShader {
    program: Arc<CompiledProgram>,
    /// This instance's identity (see `WorkFile`).
    id: u64,
    bank: Vec<[f32; 8]>,
    slots: Vec<Option<TextureBinding>>,
    /// The varying components the fragment code reads: each one's register, float (its
    /// index among the varyings) and whether it is flat.
    inputs: Vec<(Reg, usize, bool)>,
    height: f32,
}

/// A register file: the work registers, then the bank of the shader instance it was last
/// loaded for.
struct WorkFile<const W: usize> {
    regs: Vec<[f32; W]>,
    /// The instance whose bank is in place (0: none).
    instance: u64,
}

impl<const W: usize> WorkFile<W> {
    const EMPTY: WorkFile<W> = WorkFile { regs: Vec::new(), instance: 0 };

    /// The file for `instance`: its bank is copied in when another instance ran last here,
    /// so a run of groups (or vertex batches) of one draw copies it once.
    fn load(&mut self, instance: u64, program: &Executable, bank: &[[f32; W]]) -> &mut [[f32; W]] {
        if self.instance != instance {
            self.regs.resize(program.registers(), [0.0; W]);
            self.regs[program.work_regs()..].copy_from_slice(bank);
            self.instance = instance;
        }
        &mut self.regs
    }
}

thread_local! {
    /// The register files of the shaders running on this thread: every work register is
    /// written before it is read within a call (see `compile`), so no state passes between
    /// calls; the bank part is the instance's and is never written.
    static VERTEX_WORK: RefCell<WorkFile<VERTEX_LANES>> = const { RefCell::new(WorkFile::EMPTY) };
    static FRAGMENT_WORK: RefCell<WorkFile<8>> = const { RefCell::new(WorkFile::EMPTY) };
}

/// Identities of shader instances (which bank a thread's register file holds); 0 is none.
static NEXT_INSTANCE: AtomicU64 = AtomicU64::new(1);

fn new_instance() -> u64 {
    NEXT_INSTANCE.fetch_add(1, Ordering::Relaxed)
}

/// Unbound units read opaque black.
const UNBOUND: [f32; 4] = [0.0, 0.0, 0.0, 1.0];

/// A core texture at GL `(s, t)` and level of detail `lod`, filtered as the sampler says
/// (GL §8.14: a vertex shader's `λ` is 0, so the magnification filter on level 0; an explicit
/// level is `λ`), through the core's own filter arithmetic. Not counted in the ledger.
fn core_texel(texture: &Texture, sampler: &Sampler, s: f32, t: f32, lod: f32, offset: [i32; 2]) -> [f32; 4] {
    // The core's v runs down the rows, GL's t up: a texel offset in t is one in −v.
    texture.sample_lod_offset(sampler, s, 1.0 - t, lod, [offset[0], -offset[1]])
}

/// The quads' differences of GL's `(s, t)` along window x and y, for the core's level of
/// detail: taken of `t` itself, not of the core's `v = 1 − t`, whose rounding would change the
/// differences' last bits (llvmpipe differences the coordinates as the shader gives them).
/// The sign of `t`'s differences is the core's, though only their squares count.
fn gl_gradients(coord: [[f32; 8]; 2]) -> [[F32x8; 2]; 2] {
    let (s, t) = (F32x8::from_array(coord[0]), F32x8::from_array(coord[1]));
    [[s.ddx(), F32x8::ZERO - t.ddx()], [s.ddy(), F32x8::ZERO - t.ddy()]]
}

/// Each lane's level of detail from `textureGrad`'s derivatives on a core texture (level 0
/// on anything else, which reads at the base level anyway).
fn grad_lods<const W: usize>(binding: Option<&TextureBinding>, dx: [[f32; W]; 3], dy: [[f32; W]; 3]) -> [f32; W] {
    match binding {
        Some(TextureBinding::Core(texture, _)) => {
            std::array::from_fn(|lane| texture.grad_lod(dx.map(|d| d[lane]), dy.map(|d| d[lane])))
        }
        _ => [0.0; W],
    }
}

/// An explicit level of detail per lane (`None`: level 0, the base level of a vertex shader's
/// lookups), `textureGrad`'s computed from its derivatives.
fn explicit_lods<const W: usize>(binding: Option<&TextureBinding>, lod: LodValue<W>) -> Option<[f32; W]> {
    match lod {
        LodValue::Explicit(l) => Some(l),
        LodValue::Grad(dx, dy) => Some(grad_lods(binding, dx, dy)),
        LodValue::Implicit | LodValue::Bias(_) | LodValue::Gather(_) => None,
    }
}

/// Looks up lanes `0..lanes` one by one (the others read zero); `offset` texels are added
/// on a core texture's level read (a caller's source reads without them).
fn lookup_lanes<const W: usize>(
    binding: Option<&TextureBinding>,
    coord: [[f32; W]; 2],
    lod: Option<[f32; W]>,
    reference: Option<[f32; W]>,
    offset: [i32; 2],
    lanes: usize,
) -> [[f32; W]; 4] {
    let mut out = [[0.0; W]; 4];
    if let (Some(TextureBinding::Custom(source)), None, None) = (binding, lod, reference) {
        let mut texels = [[0.0; 4]; W];
        source.sample_lanes(&coord[0][..lanes], &coord[1][..lanes], &mut texels[..lanes]);
        for (lane, texel) in texels[..lanes].iter().enumerate() {
            for c in 0..4 {
                out[c][lane] = texel[c];
            }
        }
        return out;
    }
    for lane in 0..lanes {
        let (s, t) = (coord[0][lane], coord[1][lane]);
        let l = lod.map(|l| l[lane]);
        let texel = match (binding, reference) {
            (None, _) => UNBOUND,
            (Some(TextureBinding::Integer(texture, sampler)), _) => {
                let at = texture.nearest(sampler, [s, t, 0.0]);
                texture.fetch(0, at).map_or([0.0; 4], |(v, _)| integer_texel(v))
            }
            (Some(TextureBinding::Core(texture, sampler)), _) => {
                core_texel(texture, sampler, s, t, l.unwrap_or(0.0), offset)
            }
            (Some(TextureBinding::Custom(source)), None) => source.sample(s, t, l),
            (Some(TextureBinding::Custom(source)), Some(reference)) => {
                let r = source.sample_compare(s, t, reference[lane], l);
                [r, r, r, 1.0]
            }
        };
        for c in 0..4 {
            out[c][lane] = texel[c];
        }
    }
    out
}

/// A cube texture's lanes at explicit levels of detail (`None`: level 0), through the core's
/// own filter arithmetic, not counted in the ledger. Anything but a core cube texture (an
/// unbound unit, a 2D or caller's texture) reads opaque black, as an incomplete texture does.
fn cube_lookup_lanes<const W: usize>(
    binding: Option<&TextureBinding>,
    direction: [[f32; W]; 3],
    lod: Option<[f32; W]>,
    lanes: usize,
) -> [[f32; W]; 4] {
    let mut out = [[0.0; W]; 4];
    for lane in 0..lanes {
        let texel = match binding {
            Some(TextureBinding::Core(texture, sampler)) if texture.is_cube() => {
                let lambda = lod.map_or(0.0, |l| l[lane]);
                texture.sample_cube_lod(sampler, direction.map(|c| c[lane]), lambda)
            }
            _ => UNBOUND,
        };
        for c in 0..4 {
            out[c][lane] = texel[c];
        }
    }
    out
}

/// A 2-D array or 3-D texture's lanes at explicit levels of detail (`None`: level 0), through
/// the core's own filter arithmetic, not counted in the ledger. Anything but a core layered
/// texture reads opaque black, as an incomplete texture does.
fn layered_lookup_lanes<const W: usize>(
    binding: Option<&TextureBinding>,
    coord: [[f32; W]; 3],
    lod: Option<[f32; W]>,
    lanes: usize,
) -> [[f32; W]; 4] {
    let mut out = [[0.0; W]; 4];
    for lane in 0..lanes {
        let at = coord.map(|c| c[lane]);
        let lambda = lod.map_or(0.0, |l| l[lane]);
        let texel = match binding {
            Some(TextureBinding::Core(texture, sampler)) => match texture.layered() {
                Some((LayeredKind::Array, _)) => texture.sample_array_lod(sampler, at, lambda),
                Some((LayeredKind::Volume, _)) => texture.sample_volume_lod(sampler, at, lambda),
                None => UNBOUND,
            },
            Some(TextureBinding::Integer(texture, sampler)) => {
                texture.fetch(0, texture.nearest(sampler, at)).map_or([0.0; 4], |(v, _)| integer_texel(v))
            }
            _ => UNBOUND,
        };
        for c in 0..4 {
            out[c][lane] = texel[c];
        }
    }
    out
}

struct VertexEnv<'a> {
    slots: &'a [Option<TextureBinding>],
    /// The lanes holding vertices of the batch (the first ones).
    lanes: usize,
}

impl Env<VERTEX_LANES> for VertexEnv<'_> {
    fn sample(
        &mut self,
        slot: usize,
        coord: [[f32; VERTEX_LANES]; 2],
        lod: LodValue<VERTEX_LANES>,
        reference: Option<[f32; VERTEX_LANES]>,
        offset: [i32; 2],
    ) -> [[f32; VERTEX_LANES]; 4] {
        let binding = self.slots[slot].as_ref();
        if let LodValue::Gather(comp) = lod {
            let slots = self.slots;
            return gather(self, slot, slots[slot].as_ref(), coord, offset, comp);
        }
        lookup_lanes(binding, coord, explicit_lods(binding, lod), reference, offset, self.lanes)
    }

    fn sample_cube(
        &mut self,
        slot: usize,
        direction: [[f32; VERTEX_LANES]; 3],
        lod: LodValue<VERTEX_LANES>,
    ) -> [[f32; VERTEX_LANES]; 4] {
        let lod = match lod {
            LodValue::Explicit(l) => Some(l),
            _ => None,
        };
        cube_lookup_lanes(self.slots[slot].as_ref(), direction, lod, self.lanes)
    }

    fn sample_layered(
        &mut self,
        slot: usize,
        coord: [[f32; VERTEX_LANES]; 3],
        lod: LodValue<VERTEX_LANES>,
    ) -> [[f32; VERTEX_LANES]; 4] {
        let binding = self.slots[slot].as_ref();
        layered_lookup_lanes(binding, coord, explicit_lods(binding, lod), self.lanes)
    }

    fn fetch(
        &mut self,
        slot: usize,
        coord: [[i32; VERTEX_LANES]; 3],
        level: [i32; VERTEX_LANES],
    ) -> [[f32; VERTEX_LANES]; 4] {
        fetch_lanes(self.slots[slot].as_ref(), coord, level, self.lanes)
    }

    fn size(&mut self, slot: usize, level: [i32; VERTEX_LANES]) -> [[i32; VERTEX_LANES]; 3] {
        size_lanes(self.slots[slot].as_ref(), level)
    }
}

struct FragmentEnv<'a, 'f> {
    slots: &'a [Option<TextureBinding>],
    frag: &'a mut Fragments<'f>,
}

impl Env<8> for FragmentEnv<'_, '_> {
    /// Fine derivatives within each 2×2 quad; tiler's y runs down, GL's up, so `dFdy` is the
    /// top pixel minus the bottom one.
    fn derivative(&mut self, v: [f32; 8], axis: Axis) -> [f32; 8] {
        match axis {
            Axis::X => F32x8::from_array(v).ddx().to_array(),
            Axis::Y => (F32x8::ZERO - F32x8::from_array(v).ddy()).to_array(),
        }
    }

    /// The common lookup, with the sampler as it is bound, inlined into the interpreter.
    #[inline(always)]
    fn sample_implicit(&mut self, slot: usize, coord: [[f32; 8]; 2]) -> [[f32; 8]; 4] {
        if let Some(TextureBinding::Core(texture, sampler)) = &self.slots[slot] {
            // GL's own derivatives of (s, t), for a texture that needs a level of detail.
            let gradients = texture.reads_lod(sampler).then(|| gl_gradients(coord));
            let lookup = tiler::Lookup { gradients, offset: [0, 0] };
            let t = F32x8::from_fn(|i| 1.0 - coord[1][i]);
            // Unpacked by hand: `map` copied through a temporary (16 instructions a lookup).
            let [r, g, b, a] = self.frag.sample_with(texture, sampler, [F32x8::from_array(coord[0]), t], &lookup);
            return [r.to_array(), g.to_array(), b.to_array(), a.to_array()];
        }
        self.sample(slot, coord, LodValue::Implicit, None, [0, 0])
    }

    /// A run of common lookups of one texture: the binding looked at once, and the run handed
    /// to the core in one call when no lookup needs its own derivatives.
    #[inline(always)]
    fn sample_implicit_run(&mut self, slot: usize, coords: &[[[f32; 8]; 2]], out: &mut [[[f32; 8]; 4]]) {
        if let Some(TextureBinding::Core(texture, sampler)) = &self.slots[slot]
            && !texture.reads_lod(sampler)
        {
            // The core's v runs down the rows, GL's t up.
            let mut uvs = [[F32x8::ZERO; 2]; crate::exec::MAX_RUN];
            for (uv, coord) in uvs.iter_mut().zip(coords) {
                *uv = [F32x8::from_array(coord[0]), F32x8::splat(1.0) - F32x8::from_array(coord[1])];
            }
            self.frag.sample_run(texture, sampler, &uvs[..coords.len()], out);
            return;
        }
        for (coord, out) in coords.iter().zip(out) {
            *out = self.sample_implicit(slot, *coord);
        }
    }

    fn sample(
        &mut self,
        slot: usize,
        coord: [[f32; 8]; 2],
        lod: LodValue<8>,
        reference: Option<[f32; 8]>,
        offset: [i32; 2],
    ) -> [[f32; 8]; 4] {
        if let LodValue::Gather(comp) = lod {
            let slots = self.slots;
            return gather(self, slot, slots[slot].as_ref(), coord, offset, comp);
        }
        match (&self.slots[slot], lod) {
            (Some(TextureBinding::Core(..)), LodValue::Implicit) if offset == [0, 0] => {
                self.sample_implicit(slot, coord)
            }
            (Some(TextureBinding::Integer(texture, sampler)), _) => {
                let at = integer_nearest(texture, sampler, coord, 8);
                self.frag.fetch_integer(texture, [0; 8], at).map(|c| c.map(f32::from_bits))
            }
            (
                Some(TextureBinding::Core(texture, sampler)),
                LodValue::Implicit | LodValue::Bias(_) | LodValue::Grad(..),
            ) => {
                let mut sampler = *sampler;
                if let LodValue::Bias(b) = lod {
                    // The core takes one bias per draw; the group's first lane's stands for
                    // all (biases are uniform in practice).
                    sampler.lod_bias += b[0];
                }
                // The core's v runs down the rows, GL's t up: t's derivatives and offset
                // change sign.
                let gradients = match lod {
                    LodValue::Grad(dx, dy) => {
                        let d = |d: [[f32; 8]; 3]| [F32x8::from_array(d[0]), F32x8::ZERO - F32x8::from_array(d[1])];
                        Some([d(dx), d(dy)])
                    }
                    _ => texture.reads_lod(&sampler).then(|| gl_gradients(coord)),
                };
                let lookup = tiler::Lookup { gradients, offset: [offset[0], -offset[1]] };
                let t = F32x8::from_array(coord[1].map(|t| 1.0 - t));
                let texel = self.frag.sample_with(texture, &sampler, [F32x8::from_array(coord[0]), t], &lookup);
                texel.map(|c| c.to_array())
            }
            (binding, lod) => {
                let binding = binding.as_ref();
                lookup_lanes(binding, coord, explicit_lods(binding, lod), reference, offset, 8)
            }
        }
    }

    /// Directions are GL's: a core cube texture's faces keep GL's rows (`t = 0` first), so
    /// nothing is flipped.
    fn sample_cube(&mut self, slot: usize, direction: [[f32; 8]; 3], lod: LodValue<8>) -> [[f32; 8]; 4] {
        match (&self.slots[slot], lod) {
            (Some(TextureBinding::Core(texture, sampler)), LodValue::Implicit | LodValue::Bias(_))
                if texture.is_cube() =>
            {
                let mut sampler = *sampler;
                if let LodValue::Bias(b) = lod {
                    // As for 2D: the group's first lane's bias stands for all.
                    sampler.lod_bias += b[0];
                }
                self.frag.sample_cube(texture, &sampler, direction.map(F32x8::from_array)).map(|c| c.to_array())
            }
            (binding, LodValue::Explicit(l)) => cube_lookup_lanes(binding.as_ref(), direction, Some(l), 8),
            (binding, _) => cube_lookup_lanes(binding.as_ref(), direction, None, 8),
        }
    }

    /// Coordinates are GL's: a core layered texture's rows are in GL's order (`t = 0`
    /// first), as a cube face's, so nothing is flipped.
    fn sample_layered(&mut self, slot: usize, coord: [[f32; 8]; 3], lod: LodValue<8>) -> [[f32; 8]; 4] {
        match (&self.slots[slot], lod) {
            (Some(TextureBinding::Integer(texture, sampler)), _) => {
                let at = integer_nearest(texture, sampler, coord, 8);
                self.frag.fetch_integer(texture, [0; 8], at).map(|c| c.map(f32::from_bits))
            }
            (Some(TextureBinding::Core(texture, sampler)), LodValue::Implicit | LodValue::Bias(_))
                if texture.layered().is_some() =>
            {
                let mut sampler = *sampler;
                if let LodValue::Bias(b) = lod {
                    // As for 2D: the group's first lane's bias stands for all.
                    sampler.lod_bias += b[0];
                }
                let coord = coord.map(F32x8::from_array);
                let texel = match texture.layered() {
                    Some((LayeredKind::Volume, _)) => self.frag.sample_volume(texture, &sampler, coord),
                    _ => self.frag.sample_array(texture, &sampler, coord),
                };
                texel.map(|c| c.to_array())
            }
            (binding, lod) => {
                let binding = binding.as_ref();
                layered_lookup_lanes(binding, coord, explicit_lods(binding, lod), 8)
            }
        }
    }

    /// Texel reads of core and integer textures go through the texture-cache model (every
    /// quad with a covered pixel); a caller's source is read as in a vertex shader.
    fn fetch(&mut self, slot: usize, coord: [[i32; 8]; 3], level: [i32; 8]) -> [[f32; 8]; 4] {
        match &self.slots[slot] {
            Some(TextureBinding::Core(texture, _)) if !texture.is_cube() => {
                let coord = core_rows(texture, coord, level);
                self.frag.fetch(texture, level, coord).map(|c| c.to_array())
            }
            Some(TextureBinding::Integer(texture, _)) => {
                self.frag.fetch_integer(texture, level, coord).map(|c| c.map(f32::from_bits))
            }
            binding => fetch_lanes(binding.as_ref(), coord, level, 8),
        }
    }

    fn size(&mut self, slot: usize, level: [i32; 8]) -> [[i32; 8]; 3] {
        size_lanes(self.slots[slot].as_ref(), level)
    }
}

impl VertexShader for GlslVertexShader {
    fn shade(&self, input: &VertexInput, out: &mut VertexOutput) {
        self.shade_batch(std::slice::from_ref(input), std::slice::from_mut(out));
    }

    fn shade_batch(&self, inputs: &[VertexInput], outs: &mut [VertexOutput]) {
        for (inputs, outs) in inputs.chunks(VERTEX_LANES).zip(outs.chunks_mut(VERTEX_LANES)) {
            self.shade_lanes(inputs, outs);
        }
    }
}

impl GlslVertexShader {
    /// Shades up to [`VERTEX_LANES`] vertices, each in a lane of its own: the first lanes;
    /// the others compute on stale inputs and are not read.
    fn shade_lanes(&self, inputs: &[VertexInput], outs: &mut [VertexOutput]) {
        let code = &self.program.vertex;
        self.run_batch(inputs, |regs, lanes| {
            let position = code.position.expect("vertex shaders have gl_Position");
            for (lane, out) in outs[..lanes].iter_mut().enumerate() {
                let p = position.map(|r| regs[r as usize][lane]);
                // GL clip space → tiler's (Vulkan's): y down, depth [−w, w] → [0, w].
                out.position = Vec4::new(p[0], -p[1], (p[2] + p[3]) * 0.5, p[3]);
                for &(r, float) in &self.outputs {
                    out.varyings[float] = regs[r as usize][lane];
                }
                if let Some(w) = self.program.w_varying {
                    out.varyings[w] = p[3];
                }
                if let (Some(v), Some(r)) = (self.program.point_size_varying, code.point_size) {
                    out.varyings[v] = regs[r as usize][lane];
                }
            }
        });
    }

    /// Runs the vertex shader on up to [`VERTEX_LANES`] vertices, one a lane, and hands
    /// `finish` the register file and the lanes in use.
    pub(crate) fn run_batch(&self, inputs: &[VertexInput], finish: impl FnOnce(&[[f32; VERTEX_LANES]], usize)) {
        let code = &self.program.vertex;
        let lanes = inputs.len();
        debug_assert!(lanes <= VERTEX_LANES);
        // Taken out of the thread's slot and put back after, rather than used in
        // `with_borrow_mut`'s closure: that closure is a function of std's, kept out of line
        // and compiled for the baseline instruction set, so the inputs' copies would not run
        // at the caller's (for fragments it was 4.5% of desktop.trace's replay).
        let mut file = VERTEX_WORK.replace(WorkFile::EMPTY);
        {
            let executable = &self.program.vertex_executable;
            let regs = file.load(self.id, executable, &self.bank);
            for &AttributeComponent { register, location, row, integer, constant } in &self.attributes {
                // The core fetches attributes as floats; an integer attribute takes the
                // value's integer (exact to 2²⁴), or the bits of one fetched as integers
                // (`set_integer_attributes`). One loop over the lanes per case.
                let bits = self.bit_attributes & (1 << location) != 0;
                let dst = &mut regs[register as usize];
                if let Some(value) = constant {
                    let value = match integer {
                        Some(Scalar::Int) if !bits => crate::exec::int(value as i32),
                        Some(Scalar::UInt) if !bits => crate::exec::uint(value as u32),
                        _ => value,
                    };
                    dst[..lanes].fill(value);
                    continue;
                }
                let lanes = dst.iter_mut().zip(&inputs[..lanes]);
                match integer {
                    Some(Scalar::Int) if !bits => {
                        lanes.for_each(|(d, input)| *d = crate::exec::int(input.attributes[location][row] as i32))
                    }
                    Some(Scalar::UInt) if !bits => {
                        lanes.for_each(|(d, input)| *d = crate::exec::uint(input.attributes[location][row] as u32))
                    }
                    _ => lanes.for_each(|(d, input)| *d = input.attributes[location][row]),
                }
            }
            // Ints are held as their bits (`ir`).
            if let Some(r) = code.vertex_id {
                for (lane, input) in inputs[..lanes].iter().enumerate() {
                    regs[r as usize][lane] = crate::exec::int(input.vertex_index as i32);
                }
            }
            if let Some(r) = code.instance_id {
                regs[r as usize] = [crate::exec::int(self.instance as i32); VERTEX_LANES];
            }
            let active = (1u64 << lanes) - 1;
            run(executable, regs, active, &mut VertexEnv { slots: &self.slots, lanes });
            finish(regs, lanes);
        }
        VERTEX_WORK.set(file);
    }
}

impl FragmentShader for GlslFragmentShader {
    fn properties(&self) -> ShaderProperties {
        self.program.fragment_properties()
    }

    // Inlined into each instruction set's pixel pipeline (see `FragmentShader`): the inputs'
    // interpolation and the outputs' copies then run at that set, not the baseline's.
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        let code = &self.program.fragment;
        // See `run_batch`.
        let mut file = FRAGMENT_WORK.replace(WorkFile::EMPTY);
        {
            let executable = &self.program.fragment_executable;
            let regs = file.load(self.id, executable, &self.bank);
            for &(r, float, flat) in &self.inputs {
                // A flat value is copied, so an integer's bits arrive as they left.
                regs[r as usize] = if flat { [frag.flat(float); 8] } else { frag.smooth(float).to_array() };
            }
            if let Some(fc) = code.frag_coord {
                let (x, y) = frag.position();
                regs[fc[0] as usize] = x.to_array();
                regs[fc[1] as usize] = y.to_array().map(|y| self.height - y);
                regs[fc[2] as usize] = frag.depth().to_array();
                let w = self.program.w_varying.map_or(F32x8::ONE, |w| frag.smooth(w));
                regs[fc[3] as usize] = w.to_array().map(|w| 1.0 / w);
            }
            if let (Some(pc), Some(v)) = (code.point_coord, self.program.point_coord_varying) {
                regs[pc[0] as usize] = frag.smooth(v).to_array();
                regs[pc[1] as usize] = frag.smooth(v + 1).to_array();
            }
            if let Some(ff) = code.front_facing {
                regs[ff as usize] = [if frag.front_facing() { 1.0 } else { 0.0 }; 8];
            }
            let discarded = run(executable, regs, 0xff, &mut FragmentEnv { slots: &self.slots, frag });
            if discarded != 0 {
                frag.discard(LaneMask(discarded as u8));
            }
            for (attachment, c) in &code.colors {
                frag.set_color(*attachment, c.map(|r| F32x8::from_array(regs[r as usize])));
            }
        }
        FRAGMENT_WORK.set(file);
    }
}

// Shaders are shared across tile threads.
const _: () = {
    const fn send_sync<T: Send + Sync>() {}
    send_sync::<CompiledProgram>();
    send_sync::<GlslFragmentShader>();
};
