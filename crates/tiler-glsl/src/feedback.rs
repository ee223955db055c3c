//! Transform feedback (GL ES 3.0 §2.15): the vertex shader outputs a program captures, found
//! by name ([`CompiledProgram::feedback_varyings`]), and a batch of vertices shaded for them
//! ([`GlslVertexShader::shade_feedback`]) — each output's components as the 32-bit words GL
//! writes into the buffer (floats as their bits, `int`/`uint` as their values' bits).

use crate::ir::Reg;
use crate::types::{Scalar, Type};
use crate::{CompiledProgram, Error, GlslVertexShader};

/// A vertex shader output transform feedback captures.
#[derive(Clone, Debug, PartialEq)]
pub struct FeedbackVarying {
    /// As `glTransformFeedbackVaryings` named it (`gl_Position`, `v`, `a[2]`).
    pub name: String,
    /// Its type (an array element's for `a[k]`); it takes `components` words a vertex.
    pub ty: Type,
    /// Its component registers in the vertex shader.
    pub(crate) regs: Vec<Reg>,
}

impl FeedbackVarying {
    /// The 32-bit words it writes per vertex.
    pub fn components(&self) -> usize {
        self.regs.len()
    }
}

impl CompiledProgram {
    /// The vertex outputs `names` name, in order, as `glTransformFeedbackVaryings` takes them:
    /// user `out`s (whole, or `a[k]` of an array), `gl_Position`, `gl_PointSize`.
    ///
    /// # Errors
    /// A name the vertex shader does not write, named twice, a subscript out of range, or an
    /// output of a type transform feedback cannot capture (GL ES 3.0 §2.15.2: a link error).
    pub fn feedback_varyings(&self, names: &[String]) -> Result<Vec<FeedbackVarying>, Error> {
        let code = self.vertex_code();
        let mut out: Vec<FeedbackVarying> = Vec::new();
        for name in names {
            if out.iter().any(|v| v.name == *name) {
                return Err(Error::Link(format!("transform feedback varying '{name}' is named twice")));
            }
            let varying = match name.as_str() {
                "gl_Position" => {
                    let regs =
                        code.position.ok_or_else(|| Error::Link("the vertex shader has no gl_Position".into()))?;
                    FeedbackVarying { name: name.clone(), ty: Type::Vector(Scalar::Float, 4), regs: regs.to_vec() }
                }
                "gl_PointSize" => {
                    let r = code.point_size.ok_or_else(|| {
                        Error::Link(
                            "transform feedback varying 'gl_PointSize' is not written by the vertex shader".into(),
                        )
                    })?;
                    FeedbackVarying { name: name.clone(), ty: Type::Scalar(Scalar::Float), regs: vec![r] }
                }
                _ => {
                    let (base, index) = match name.strip_suffix(']').and_then(|n| n.rsplit_once('[')) {
                        Some((base, index)) => {
                            let k = index.parse::<usize>().map_err(|_| {
                                Error::Link(format!("transform feedback varying '{name}': '{index}' is not an index"))
                            })?;
                            (base, Some(k))
                        }
                        None => (name.as_str(), None),
                    };
                    let o = code.outputs.iter().find(|o| o.name == base).ok_or_else(|| {
                        Error::Link(format!(
                            "transform feedback varying '{name}' is not an output of the vertex shader"
                        ))
                    })?;
                    let (ty, regs) = match (index, &o.ty) {
                        (None, ty) => (ty.clone(), o.regs.clone()),
                        (Some(k), Type::Array(element, n)) if k < *n => {
                            let size = element.size();
                            ((**element).clone(), o.regs[k * size..(k + 1) * size].to_vec())
                        }
                        (Some(k), ty) => {
                            return Err(Error::Link(format!(
                                "transform feedback varying '{name}': element {k} of a {ty} does not exist"
                            )));
                        }
                    };
                    if !captured(&ty) {
                        return Err(Error::Link(format!(
                            "transform feedback varying '{name}' is a {ty}, which transform feedback does not capture"
                        )));
                    }
                    FeedbackVarying { name: name.clone(), ty, regs }
                }
            };
            out.push(varying);
        }
        Ok(out)
    }
}

/// Types whose components are 32-bit words: float, int and uint scalars, vectors, matrices
/// and arrays of them.
fn captured(ty: &Type) -> bool {
    match ty {
        Type::Scalar(s) | Type::Vector(s, _) => matches!(s, Scalar::Float | Scalar::Int | Scalar::UInt),
        Type::Matrix(..) => true,
        Type::Array(element, _) => captured(element),
        _ => false,
    }
}

impl GlslVertexShader {
    /// Shades `inputs` (any number, in batches of the shader's lanes) and appends each
    /// vertex's words of `varyings[k]` to `out[k]`, vertex after vertex.
    ///
    /// # Panics
    /// If `out` is shorter than `varyings`.
    pub fn shade_feedback(&self, inputs: &[tiler::VertexInput], varyings: &[FeedbackVarying], out: &mut [Vec<u32>]) {
        for batch in inputs.chunks(tiler::VERTEX_BATCH) {
            self.run_batch(batch, |regs: &[[f32; tiler::VERTEX_BATCH]], lanes| {
                (0..lanes).for_each(|lane| {
                    for (v, words) in varyings.iter().zip(out.iter_mut()) {
                        words.extend(v.regs.iter().map(|&r| regs[r as usize][lane].to_bits()));
                    }
                });
            });
        }
    }
}
