//! Typed access to a call's arguments and return value, with errors naming the argument.

use crate::wire::{Call, Value};

use super::{DecodeErrorKind, Memory};

type Result<T> = std::result::Result<T, DecodeErrorKind>;

/// A call being decoded; owns it so blobs move out without a copy.
pub(crate) struct Args {
    pub(crate) call: Call,
}

impl Args {
    fn name(&self, index: usize) -> String {
        self.call.sig.arg_names.get(index).cloned().unwrap_or_else(|| format!("#{index}"))
    }

    fn value(&self, index: usize) -> Result<&Value> {
        self.call.arg(index).ok_or_else(|| DecodeErrorKind::MissingArgument { argument: self.name(index) })
    }

    fn wrong(&self, index: usize, expected: &'static str, found: &Value) -> DecodeErrorKind {
        DecodeErrorKind::WrongType { argument: self.name(index), expected, found: found.kind() }
    }

    fn out_of_range(&self, index: usize, expected: &'static str, found: &Value) -> DecodeErrorKind {
        DecodeErrorKind::OutOfRange { argument: self.name(index), expected, value: found.to_string() }
    }

    fn integer<T: TryFrom<i64> + TryFrom<u64>>(&self, index: usize, expected: &'static str) -> Result<T> {
        let value = self.value(index)?;
        integer(value)
            .ok_or_else(|| self.wrong(index, expected, value))?
            .ok_or_else(|| self.out_of_range(index, expected, value))
    }

    /// A `GLuint` (names, indices, masks).
    pub(crate) fn u32(&self, index: usize) -> Result<u32> {
        self.integer(index, "an unsigned 32-bit integer")
    }

    /// A `GLint` or `GLsizei`.
    pub(crate) fn i32(&self, index: usize) -> Result<i32> {
        self.integer(index, "a signed 32-bit integer")
    }

    /// A `GLenum`.
    pub(crate) fn enumeration(&self, index: usize) -> Result<u32> {
        self.integer(index, "a GL enum")
    }

    /// A `GLsizeiptr` or `GLintptr`: a non-negative byte count or offset.
    pub(crate) fn u64(&self, index: usize) -> Result<u64> {
        self.integer(index, "a non-negative size or offset")
    }

    /// An EGL handle or attribute: an address, null, or an integer.
    pub(crate) fn handle(&self, index: usize) -> Result<u64> {
        let value = self.value(index)?;
        value.as_u64().ok_or_else(|| self.wrong(index, "a handle", value))
    }

    pub(crate) fn i64(&self, index: usize) -> Result<i64> {
        self.integer(index, "an integer")
    }

    /// A `GLboolean`: apitrace writes it as the enum `GL_FALSE`/`GL_TRUE`.
    pub(crate) fn bool(&self, index: usize) -> Result<bool> {
        let value = self.value(index)?;
        match value {
            Value::Bool(b) => Ok(*b),
            _ => match integer::<u8>(value) {
                Some(Some(0)) => Ok(false),
                Some(Some(1)) => Ok(true),
                Some(_) => Err(self.out_of_range(index, "GL_FALSE or GL_TRUE", value)),
                None => Err(self.wrong(index, "a boolean", value)),
            },
        }
    }

    /// A `GLfloat` (integers are accepted, as GL converts them).
    pub(crate) fn f32(&self, index: usize) -> Result<f32> {
        let value = self.value(index)?;
        value.as_f64().map(|v| v as f32).ok_or_else(|| self.wrong(index, "a number", value))
    }

    /// A string argument (names, sources); bytes that are not UTF-8 are replaced.
    pub(crate) fn string(&self, index: usize) -> Result<String> {
        let value = self.value(index)?;
        text(value).ok_or_else(|| self.wrong(index, "a string", value))
    }

    /// An array argument; null counts as empty.
    fn array(&self, index: usize) -> Result<&[Value]> {
        match self.value(index)? {
            Value::Array(values) => Ok(values),
            Value::Null => Ok(&[]),
            other => Err(self.wrong(index, "an array", other)),
        }
    }

    fn numbers<T>(
        &self,
        index: usize,
        expected: &'static str,
        convert: impl Fn(&Value) -> Option<T>,
    ) -> Result<Vec<T>> {
        self.array(index)?.iter().map(|v| convert(v).ok_or_else(|| self.out_of_range(index, expected, v))).collect()
    }

    pub(crate) fn u32s(&self, index: usize) -> Result<Vec<u32>> {
        self.numbers(index, "unsigned 32-bit integers", |v| integer(v).flatten())
    }

    pub(crate) fn i32s(&self, index: usize) -> Result<Vec<i32>> {
        self.numbers(index, "signed 32-bit integers", |v| integer(v).flatten())
    }

    pub(crate) fn i64s(&self, index: usize) -> Result<Vec<i64>> {
        self.numbers(index, "integers", Value::as_i64)
    }

    pub(crate) fn f32s(&self, index: usize) -> Result<Vec<f32>> {
        self.numbers(index, "numbers", |v| v.as_f64().map(|v| v as f32))
    }

    pub(crate) fn strings(&self, index: usize) -> Result<Vec<String>> {
        self.numbers(index, "strings", text)
    }

    /// Memory passed by pointer, moved out of the call.
    pub(crate) fn memory(&mut self, index: usize) -> Result<Memory> {
        self.value(index)?;
        let value = self.call.args[index].take().expect("checked above");
        match value {
            Value::Null => Ok(Memory::Null),
            Value::Blob(bytes) => Ok(Memory::Client(bytes)),
            Value::UInt(offset) | Value::Pointer(offset) => Ok(Memory::Offset(offset)),
            other => {
                let error = self.wrong(index, "a pointer, offset or blob", &other);
                self.call.args[index] = Some(other);
                Err(error)
            }
        }
    }

    /// A blob moved out of the call (`memcpy`'s source).
    pub(crate) fn blob(&mut self, index: usize) -> Result<Vec<u8>> {
        match self.memory(index)? {
            Memory::Client(bytes) => Ok(bytes),
            Memory::Null => Ok(Vec::new()),
            Memory::Offset(_) => {
                Err(DecodeErrorKind::WrongType { argument: self.name(index), expected: "a blob", found: "pointer" })
            }
        }
    }

    fn ret(&self) -> Result<&Value> {
        self.call.ret.as_ref().ok_or(DecodeErrorKind::MissingReturn)
    }

    pub(crate) fn ret_u32(&self) -> Result<u32> {
        let value = self.ret()?;
        integer(value).flatten().ok_or_else(|| DecodeErrorKind::BadReturn { value: value.to_string() })
    }

    pub(crate) fn ret_i32(&self) -> Result<i32> {
        let value = self.ret()?;
        integer(value).flatten().ok_or_else(|| DecodeErrorKind::BadReturn { value: value.to_string() })
    }

    /// A returned handle or pointer (0 for null).
    pub(crate) fn ret_handle(&self) -> Result<u64> {
        let value = self.ret()?;
        value.as_u64().ok_or_else(|| DecodeErrorKind::BadReturn { value: value.to_string() })
    }
}

/// `None` if `value` is not an integer; `Some(None)` if it is one out of `T`'s range.
fn integer<T: TryFrom<i64> + TryFrom<u64>>(value: &Value) -> Option<Option<T>> {
    match *value {
        Value::UInt(v) | Value::Bitmask { value: v, .. } => Some(T::try_from(v).ok()),
        Value::SInt(v) | Value::Enum { value: v, .. } => Some(T::try_from(v).ok()),
        Value::Bool(b) => Some(T::try_from(b as u64).ok()),
        Value::Repr { ref machine, .. } => integer(machine),
        _ => None,
    }
}

fn text(value: &Value) -> Option<String> {
    match value {
        Value::String(bytes) => Some(String::from_utf8_lossy(bytes).into_owned()),
        Value::WString(s) => Some(s.clone()),
        _ => None,
    }
}
