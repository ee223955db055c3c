//! GLSL ES 3.00's lookups with explicit derivatives or a texel offset: `textureGrad`,
//! `textureOffset`, `textureLodOffset`, `textureProjOffset` and `textureGradOffset`.
//!
//! `textureGrad` takes the derivatives of the coordinates along window x and y in place of
//! the quad's differences (sampler2D, sampler2DArray, sampler3D; a level of detail the core
//! computes by its own formula, see `tiler::Lookup`). The offsets (sampler2D) are constant
//! `ivec2`s in GL ES 3.0's `[−8, 7]`, added to the texel indices of the level read before the
//! wrap (§3.8.10).

use super::{CResult, Compiler, Value};
use crate::ir::{BinOp, Inst, Lod};
use crate::types::{FLOAT, SamplerKind, Scalar, Type};

/// GL ES 3.0's `MIN_PROGRAM_TEXEL_OFFSET` and `MAX_PROGRAM_TEXEL_OFFSET` (llvmpipe's too).
const TEXEL_OFFSETS: std::ops::RangeInclusive<i32> = -8..=7;

/// GL ES 3.1's `MIN_PROGRAM_TEXTURE_GATHER_OFFSET` and `MAX_…` (llvmpipe's: −32, 31).
const GATHER_OFFSETS: std::ops::RangeInclusive<i32> = -32..=31;

impl Compiler<'_> {
    /// `textureGrad`, `textureOffset`, `textureLodOffset`, `textureProjOffset`,
    /// `textureGradOffset`.
    pub(super) fn texture_fn(&mut self, name: &str, mut args: Vec<Value>) -> CResult<Value> {
        let grad = name.starts_with("textureGrad");
        let explicit = name.starts_with("textureLod");
        let proj = name.starts_with("textureProj");
        let has_offset = name.ends_with("Offset");
        let fixed = 2 + 2 * grad as usize + explicit as usize + has_offset as usize;
        let bias_allowed = !grad && !explicit;
        if args.len() != fixed && !(bias_allowed && args.len() == fixed + 1) {
            let or_bias = if bias_allowed { format!(" (or {} with a bias)", fixed + 1) } else { String::new() };
            return self.fail(format!("{name}() takes {fixed} arguments{or_bias}, {} given", args.len()));
        }
        let kind = match args[0].ty {
            Type::Sampler(kind) => kind,
            ref other => return self.fail(format!("{name}() needs a sampler, not {other}")),
        };
        let slot = args[0].regs[0] as u16;
        let supported = match kind {
            SamplerKind::Sampler2D => true,
            SamplerKind::Sampler2DArray | SamplerKind::Sampler3D => grad && !has_offset,
            // Integer textures are fetched (`texelFetch`), never filtered by derivatives.
            SamplerKind::SamplerCube | SamplerKind::Sampler2DShadow | SamplerKind::Integer { .. } => false,
        };
        if !supported {
            return self.fail(format!("{name}() on a {} is not supported", args[0].ty));
        }
        let offset = if has_offset { self.texel_offset(name, &args.remove(fixed - 1), TEXEL_OFFSETS)? } else { [0, 0] };
        // Now `(sampler, P [, lod | dPdx, dPdy] [, bias])`.
        let coord = self.float_gen(name, args[1].clone())?;
        let width = if kind == SamplerKind::Sampler2D { 2 } else { 3 };
        let coord_ok = match proj {
            true => [3, 4].contains(&coord.regs.len()),
            false => coord.regs.len() == width,
        };
        if !coord_ok {
            return self.fail(format!("{name}({}) coordinates cannot be a {}", args[0].ty, coord.ty));
        }
        let coord = if proj {
            let q = *coord.regs.last().expect("3 or 4 components");
            vec![self.bin(BinOp::Div, coord.regs[0], q), self.bin(BinOp::Div, coord.regs[1], q)]
        } else {
            coord.regs
        };
        let lod = if grad {
            let derivatives = if kind == SamplerKind::Sampler3D { 3 } else { 2 };
            let d = |c: &mut Self, v: &Value, which: &str| -> CResult<[u32; 3]> {
                let v = c.float_gen(name, v.clone())?;
                if v.regs.len() != derivatives {
                    return c.fail(format!("{name}({}) {which} cannot be a {}", args[0].ty, v.ty));
                }
                let zero = c.konst(0.0);
                Ok(std::array::from_fn(|i| v.regs.get(i).copied().unwrap_or(zero)))
            };
            let dx = d(self, &args[2], "dPdx")?;
            let dy = d(self, &args[3], "dPdy")?;
            Lod::Grad { dx, dy }
        } else {
            let extra = args.get(2);
            if extra.is_some_and(|v| v.ty != FLOAT && v.ty.scalar() != Some(Scalar::Float)) {
                return self.fail(format!("{name}(): bias or level must be a float"));
            }
            self.lookup_lod(name, explicit, extra)?
        };
        let dst = self.temps(4);
        let dst4 = [dst[0], dst[1], dst[2], dst[3]];
        if kind == SamplerKind::Sampler2D {
            self.emit(Inst::Sample {
                slot,
                dst: dst4,
                coord: [coord[0], coord[1]],
                lod,
                reference: None,
                offset,
                round: false,
            });
        } else {
            self.emit(Inst::SampleLayered { slot, dst: dst4, coord: [coord[0], coord[1], coord[2]], lod });
        }
        let dst = self.texels(slot, dst);
        Ok(Value { ty: Type::vec(4), regs: dst })
    }

    /// GLSL ES 3.10's `textureGather(sampler2D, vec2 P [, int comp])` and
    /// `textureGatherOffset(sampler2D, vec2 P, ivec2 offset [, int comp])`: channel `comp`
    /// (a constant, red by default) of the four texels of level 0 a bilinear lookup at `P`
    /// would blend (see `ir::Lod::Gather`), `offset` a constant in [`GATHER_OFFSETS`].
    pub(super) fn texture_gather(&mut self, name: &str, mut args: Vec<Value>) -> CResult<Value> {
        let fixed = if name == "textureGatherOffset" { 3 } else { 2 };
        if args.len() != fixed && args.len() != fixed + 1 {
            return self.fail(format!("{name}() takes {fixed} or {} arguments, {} given", fixed + 1, args.len()));
        }
        if args[0].ty != Type::Sampler(SamplerKind::Sampler2D) {
            return self.fail(format!("{name}() on a {} is not supported (sampler2D only)", args[0].ty));
        }
        let slot = args[0].regs[0] as u16;
        let comp = match args.get(fixed) {
            None => 0,
            Some(v) => match (v.ty == Type::Scalar(Scalar::Int), self.constant(v.regs[0])) {
                (true, Some(c)) if (0..4).contains(&(c.to_bits() as i32)) => c.to_bits() as u8,
                _ => return self.fail(format!("{name}(): the component must be a constant int from 0 to 3")),
            },
        };
        args.truncate(fixed);
        let offset = if fixed == 3 { self.texel_offset(name, &args[2], GATHER_OFFSETS)? } else { [0, 0] };
        let coord = self.float_gen(name, args[1].clone())?;
        if coord.regs.len() != 2 {
            return self.fail(format!("{name}(sampler2D) coordinates cannot be a {}", coord.ty));
        }
        let dst = self.temps(4);
        let dst4 = [dst[0], dst[1], dst[2], dst[3]];
        let coord = [coord.regs[0], coord.regs[1]];
        self.emit(Inst::Sample {
            slot,
            dst: dst4,
            coord,
            lod: Lod::Gather(comp),
            reference: None,
            offset,
            round: false,
        });
        let dst = self.texels(slot, dst);
        Ok(Value { ty: Type::vec(4), regs: dst })
    }

    /// A lookup's texel offset: a constant `ivec2` within `range`.
    fn texel_offset(&mut self, name: &str, v: &Value, range: std::ops::RangeInclusive<i32>) -> CResult<[i8; 2]> {
        if v.ty != Type::Vector(Scalar::Int, 2) {
            return self.fail(format!("{name}(): the offset must be an ivec2, not a {}", v.ty));
        }
        let mut offset = [0; 2];
        for (o, &r) in offset.iter_mut().zip(&v.regs) {
            let Some(x) = self.constant(r).map(|x| x.to_bits() as i32) else {
                return self.fail(format!("{name}(): the offset must be a constant expression"));
            };
            if !range.contains(&x) {
                return self.fail(format!("{name}(): offset {x} is outside [{}, {}]", range.start(), range.end()));
            }
            *o = x as i8;
        }
        Ok(offset)
    }
}
