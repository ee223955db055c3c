//! Calls, values and the signatures they refer to, as the wire format carries them.

use std::fmt;
use std::sync::Arc;

/// A function signature: its name and the names of its arguments, defined once per trace.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FunctionSig {
    pub id: u64,
    pub name: String,
    pub arg_names: Vec<String>,
}

/// An enum signature: the name/value pairs a value of this type was written with.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EnumSig {
    pub id: u64,
    pub values: Vec<(String, i64)>,
}

impl EnumSig {
    /// The name of `value`, if the signature has one.
    pub fn name_of(&self, value: i64) -> Option<&str> {
        self.values.iter().find(|(_, v)| *v == value).map(|(name, _)| name.as_str())
    }
}

/// A bitmask signature: the flag names and their bits (a zero flag may come first).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BitmaskSig {
    pub id: u64,
    pub flags: Vec<(String, u64)>,
}

/// A struct signature: the struct's name and its members' names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StructSig {
    pub id: u64,
    pub name: String,
    pub member_names: Vec<String>,
}

/// One frame of a call's backtrace, defined once per trace and referred to by id.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct StackFrame {
    pub id: u64,
    pub module: Option<String>,
    pub function: Option<String>,
    pub filename: Option<String>,
    pub line: Option<u64>,
    pub offset: Option<u64>,
}

/// One value: an argument, a return value, or a part of one.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A null pointer.
    Null,
    Bool(bool),
    /// Written as a negative integer (tag 0x03); positive integers come as [`Value::UInt`].
    SInt(i64),
    UInt(u64),
    Float(f32),
    Double(f64),
    /// A character string, bytes as the application passed them (usually UTF-8).
    String(Vec<u8>),
    /// Bytes apitrace copied from the application's memory.
    Blob(Vec<u8>),
    Enum {
        sig: Arc<EnumSig>,
        value: i64,
    },
    Bitmask {
        sig: Arc<BitmaskSig>,
        value: u64,
    },
    Array(Vec<Value>),
    Struct {
        sig: Arc<StructSig>,
        members: Vec<Value>,
    },
    /// A pointer apitrace did not follow: an address in the traced process.
    Pointer(u64),
    /// A value shown one way and meaning another (`human` for people, `machine` for replay).
    Repr {
        human: Box<Value>,
        machine: Box<Value>,
    },
    /// A wide-character string, characters that are not Unicode scalar values replaced.
    WString(String),
}

impl Value {
    /// Bytes of the value's own data, counting each value as its size in memory.
    pub fn held_bytes(&self) -> usize {
        std::mem::size_of::<Value>()
            + match self {
                Value::String(bytes) | Value::Blob(bytes) => bytes.len(),
                Value::WString(s) => s.len(),
                Value::Array(values) | Value::Struct { members: values, .. } => {
                    values.iter().map(Value::held_bytes).sum()
                }
                Value::Repr { human, machine } => human.held_bytes() + machine.held_bytes(),
                _ => 0,
            }
    }

    /// The value as a signed integer, if it is one (integers, enums, bitmasks, booleans).
    pub fn as_i64(&self) -> Option<i64> {
        match *self {
            Value::SInt(v) => Some(v),
            Value::UInt(v) => i64::try_from(v).ok(),
            Value::Enum { value, .. } => Some(value),
            Value::Bitmask { value, .. } => i64::try_from(value).ok(),
            Value::Bool(b) => Some(b as i64),
            Value::Repr { ref machine, .. } => machine.as_i64(),
            _ => None,
        }
    }

    /// The value as an unsigned integer, if it is a non-negative one (or a pointer or null).
    pub fn as_u64(&self) -> Option<u64> {
        match *self {
            Value::UInt(v) | Value::Pointer(v) => Some(v),
            Value::Null => Some(0),
            Value::Bitmask { value, .. } => Some(value),
            Value::SInt(v) | Value::Enum { value: v, .. } => u64::try_from(v).ok(),
            Value::Bool(b) => Some(b as u64),
            Value::Repr { ref machine, .. } => machine.as_u64(),
            _ => None,
        }
    }

    /// The value as a float, if it is a number.
    pub fn as_f64(&self) -> Option<f64> {
        match *self {
            Value::Float(v) => Some(v as f64),
            Value::Double(v) => Some(v),
            Value::Repr { ref machine, .. } => machine.as_f64(),
            _ => self.as_i64().map(|v| v as f64),
        }
    }

    /// The string's text, if it is a string of valid UTF-8.
    pub fn as_str(&self) -> Option<&str> {
        match self {
            Value::String(bytes) => std::str::from_utf8(bytes).ok(),
            Value::WString(s) => Some(s),
            _ => None,
        }
    }

    /// A short name of the value's kind, for messages.
    pub fn kind(&self) -> &'static str {
        match self {
            Value::Null => "null",
            Value::Bool(_) => "bool",
            Value::SInt(_) => "negative integer",
            Value::UInt(_) => "integer",
            Value::Float(_) => "float",
            Value::Double(_) => "double",
            Value::String(_) => "string",
            Value::Blob(_) => "blob",
            Value::Enum { .. } => "enum",
            Value::Bitmask { .. } => "bitmask",
            Value::Array(_) => "array",
            Value::Struct { .. } => "struct",
            Value::Pointer(_) => "pointer",
            Value::Repr { .. } => "repr",
            Value::WString(_) => "wide string",
        }
    }
}

/// Flags of a call.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CallFlags {
    /// apitrace synthesised the call (flag bit 0), e.g. state set before a trim point or a
    /// `memcpy` standing for writes through a mapped pointer. Replay applies it like any call.
    pub fake: bool,
    /// The trace ended before the call left: outputs and return value are missing.
    pub incomplete: bool,
    /// Every flag bit the trace wrote, bit 0 included.
    pub raw: u64,
}

/// One call as the trace recorded it.
#[derive(Clone, Debug, PartialEq)]
pub struct Call {
    /// Counted from 0 at each enter event, as apitrace numbers calls.
    pub number: u64,
    pub thread: u64,
    pub sig: Arc<FunctionSig>,
    /// Argument values by index; `None` where the trace gave no value.
    pub args: Vec<Option<Value>>,
    pub ret: Option<Value>,
    pub backtrace: Vec<Arc<StackFrame>>,
    pub flags: CallFlags,
}

impl Call {
    pub fn name(&self) -> &str {
        &self.sig.name
    }

    /// The bytes its values hold: its strings, blobs and arrays (what a reader ahead of the
    /// replay keeps in memory for it; shared signatures are not counted).
    pub fn held_bytes(&self) -> usize {
        self.args.iter().flatten().chain(&self.ret).map(Value::held_bytes).sum()
    }

    /// The value of argument `index`, if the trace recorded one.
    pub fn arg(&self, index: usize) -> Option<&Value> {
        self.args.get(index).and_then(Option::as_ref)
    }
}

impl fmt::Display for Value {
    /// Formats the way `apitrace dump` does, closely enough to compare by eye.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Null => f.write_str("NULL"),
            Value::Bool(b) => write!(f, "{b}"),
            Value::SInt(v) => write!(f, "{v}"),
            Value::UInt(v) => write!(f, "{v}"),
            Value::Float(v) => write!(f, "{v}"),
            Value::Double(v) => write!(f, "{v}"),
            Value::String(bytes) => write!(f, "{:?}", String::from_utf8_lossy(bytes)),
            Value::WString(s) => write!(f, "L{s:?}"),
            Value::Blob(bytes) => write!(f, "blob({})", bytes.len()),
            Value::Enum { sig, value } => match sig.name_of(*value) {
                Some(name) => f.write_str(name),
                None => write!(f, "{value}"),
            },
            Value::Bitmask { sig, value } => write_bitmask(f, sig, *value),
            Value::Array(values) => {
                f.write_str("{")?;
                for (i, value) in values.iter().enumerate() {
                    if i > 0 {
                        f.write_str(", ")?;
                    }
                    write!(f, "{value}")?;
                }
                f.write_str("}")
            }
            Value::Struct { sig, members } => {
                f.write_str("{")?;
                for (i, value) in members.iter().enumerate() {
                    if i > 0 {
                        f.write_str(", ")?;
                    }
                    match sig.member_names.get(i) {
                        Some(name) => write!(f, "{name} = {value}")?,
                        None => write!(f, "{value}")?,
                    }
                }
                f.write_str("}")
            }
            Value::Pointer(address) => write!(f, "{address:#x}"),
            Value::Repr { human, .. } => write!(f, "{human}"),
        }
    }
}

fn write_bitmask(f: &mut fmt::Formatter<'_>, sig: &BitmaskSig, value: u64) -> fmt::Result {
    let mut left = value;
    let mut first = true;
    for (name, bits) in &sig.flags {
        let set = if *bits == 0 { value == 0 } else { left & bits == *bits };
        if set {
            if !first {
                f.write_str(" | ")?;
            }
            f.write_str(name)?;
            first = false;
            left &= !bits;
            if *bits == 0 {
                break;
            }
        }
    }
    if left != 0 || first {
        if !first {
            f.write_str(" | ")?;
        }
        write!(f, "{left:#x}")?;
    }
    Ok(())
}

impl fmt::Display for Call {
    /// `NUMBER name(arg = value, …) = return // fake`, as `apitrace dump` prints a call.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} {}(", self.number, self.sig.name)?;
        let mut first = true;
        for (index, value) in self.args.iter().enumerate() {
            let Some(value) = value else { continue };
            if !first {
                f.write_str(", ")?;
            }
            first = false;
            match self.sig.arg_names.get(index) {
                Some(name) => write!(f, "{name} = {value}")?,
                None => write!(f, "{value}")?,
            }
        }
        f.write_str(")")?;
        if let Some(ret) = &self.ret {
            write!(f, " = {ret}")?;
        }
        if self.flags.fake {
            f.write_str(" // fake")?;
        }
        if self.flags.incomplete {
            f.write_str(" // incomplete")?;
        }
        Ok(())
    }
}
