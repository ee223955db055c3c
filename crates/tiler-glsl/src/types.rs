//! GLSL types as the compiler checks them, and how many component registers each takes.

use std::fmt;
use std::sync::Arc;

/// A scalar kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Scalar {
    Float,
    /// `int`: 32-bit two's complement, its bits held in the register (see `ir`).
    Int,
    /// `uint` (ES 3.00): 32 bits, held as `int` is.
    UInt,
    Bool,
}

impl Scalar {
    /// `int` or `uint`.
    pub fn is_integer(self) -> bool {
        matches!(self, Scalar::Int | Scalar::UInt)
    }
}

/// A sampler kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SamplerKind {
    Sampler2D,
    SamplerCube,
    /// A depth-compare sampler (`sampler2DShadow`): its lookups take a reference depth and
    /// return the filtered compare result.
    Sampler2DShadow,
    /// `sampler2DArray`: lookups take `(s, t, layer)`.
    Sampler2DArray,
    /// `sampler3D`: lookups take `(s, t, r)`.
    Sampler3D,
    /// `isampler2D`, `usampler2D`, `isampler2DArray`, …: an integer texture's sampler of
    /// shape `shape` (`Sampler2D`, `Sampler2DArray` or `Sampler3D`), reading `int`s or `uint`s.
    Integer {
        shape: IntegerShape,
        unsigned: bool,
    },
}

/// The shapes integer samplers come in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum IntegerShape {
    Flat,
    Array,
    Volume,
}

impl SamplerKind {
    /// The scalar of its lookups' results: `float`, or `int`/`uint` for an integer sampler.
    pub fn result(self) -> Scalar {
        match self {
            SamplerKind::Integer { unsigned: true, .. } => Scalar::UInt,
            SamplerKind::Integer { unsigned: false, .. } => Scalar::Int,
            _ => Scalar::Float,
        }
    }

    /// Components of its texel coordinates (`texelFetch`, `textureSize`): 2, or 3 for a
    /// layered one.
    pub fn dimensions(self) -> usize {
        match self {
            SamplerKind::Sampler2DArray
            | SamplerKind::Sampler3D
            | SamplerKind::Integer { shape: IntegerShape::Array | IntegerShape::Volume, .. } => 3,
            _ => 2,
        }
    }
}

/// A GLSL type.
#[derive(Clone, Debug, PartialEq)]
pub enum Type {
    Void,
    Scalar(Scalar),
    /// `vecN`, `ivecN`, `uvecN`, `bvecN` (N = 2, 3, 4).
    Vector(Scalar, usize),
    /// `matCxR` (columns, rows: 2, 3, 4; `matN` is `matNxN`), column-major: C columns of R
    /// components.
    Matrix(usize, usize),
    Sampler(SamplerKind),
    Struct(Arc<StructType>),
    Array(Box<Type>, usize),
}

/// A user-declared struct.
#[derive(Debug, PartialEq)]
pub struct StructType {
    pub name: String,
    pub fields: Vec<(String, Type)>,
}

pub const FLOAT: Type = Type::Scalar(Scalar::Float);
pub const INT: Type = Type::Scalar(Scalar::Int);
pub const UINT: Type = Type::Scalar(Scalar::UInt);
pub const BOOL: Type = Type::Scalar(Scalar::Bool);

impl Type {
    pub fn vec(n: usize) -> Type {
        Type::vector(Scalar::Float, n)
    }

    /// A scalar (`n` = 1) or a vector of `n` components.
    pub fn vector(s: Scalar, n: usize) -> Type {
        if n == 1 { Type::Scalar(s) } else { Type::Vector(s, n) }
    }

    /// Component registers a value of this type takes (samplers: one slot number).
    pub fn size(&self) -> usize {
        match self {
            Type::Void => 0,
            Type::Scalar(_) | Type::Sampler(_) => 1,
            Type::Vector(_, n) => *n,
            Type::Matrix(c, r) => c * r,
            Type::Struct(s) => s.fields.iter().map(|(_, t)| t.size()).sum(),
            Type::Array(t, n) => t.size() * n,
        }
    }

    /// The scalar kind of a scalar, vector or matrix.
    pub fn scalar(&self) -> Option<Scalar> {
        match self {
            Type::Scalar(s) | Type::Vector(s, _) => Some(*s),
            Type::Matrix(..) => Some(Scalar::Float),
            _ => None,
        }
    }

    /// Components of a scalar or vector (1 for scalars).
    pub fn width(&self) -> Option<usize> {
        match self {
            Type::Scalar(_) => Some(1),
            Type::Vector(_, n) => Some(*n),
            _ => None,
        }
    }

    pub fn is_numeric_scalar_or_vector(&self) -> bool {
        matches!(self.scalar(), Some(Scalar::Float | Scalar::Int | Scalar::UInt)) && self.width().is_some()
    }

    pub fn is_float_based(&self) -> bool {
        match self {
            Type::Scalar(Scalar::Float) | Type::Vector(Scalar::Float, _) | Type::Matrix(..) => true,
            Type::Array(t, _) => t.is_float_based(),
            _ => false,
        }
    }

    pub fn contains_sampler(&self) -> bool {
        match self {
            Type::Sampler(_) => true,
            Type::Array(t, _) => t.contains_sampler(),
            Type::Struct(s) => s.fields.iter().any(|(_, t)| t.contains_sampler()),
            _ => false,
        }
    }

    /// The same shape with another scalar kind (a scalar or vector).
    pub fn with_scalar(&self, s: Scalar) -> Type {
        Type::vector(s, self.width().unwrap_or(1))
    }
}

impl fmt::Display for Type {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Type::Void => write!(f, "void"),
            Type::Scalar(Scalar::Float) => write!(f, "float"),
            Type::Scalar(Scalar::Int) => write!(f, "int"),
            Type::Scalar(Scalar::UInt) => write!(f, "uint"),
            Type::Scalar(Scalar::Bool) => write!(f, "bool"),
            Type::Vector(Scalar::Float, n) => write!(f, "vec{n}"),
            Type::Vector(Scalar::Int, n) => write!(f, "ivec{n}"),
            Type::Vector(Scalar::UInt, n) => write!(f, "uvec{n}"),
            Type::Vector(Scalar::Bool, n) => write!(f, "bvec{n}"),
            Type::Matrix(c, r) if c == r => write!(f, "mat{c}"),
            Type::Matrix(c, r) => write!(f, "mat{c}x{r}"),
            Type::Sampler(SamplerKind::Sampler2D) => write!(f, "sampler2D"),
            Type::Sampler(SamplerKind::SamplerCube) => write!(f, "samplerCube"),
            Type::Sampler(SamplerKind::Sampler2DShadow) => write!(f, "sampler2DShadow"),
            Type::Sampler(SamplerKind::Sampler2DArray) => write!(f, "sampler2DArray"),
            Type::Sampler(SamplerKind::Sampler3D) => write!(f, "sampler3D"),
            Type::Sampler(SamplerKind::Integer { shape, unsigned }) => {
                let shape = match shape {
                    IntegerShape::Flat => "2D",
                    IntegerShape::Array => "2DArray",
                    IntegerShape::Volume => "3D",
                };
                write!(f, "{}sampler{shape}", if *unsigned { "u" } else { "i" })
            }
            Type::Struct(s) => write!(f, "{}", s.name),
            Type::Array(t, n) => write!(f, "{t}[{n}]"),
        }
    }
}
