//! The event parser: enter and leave events into whole calls, one at a time.

use std::collections::{HashMap, VecDeque};
use std::fs::File;
use std::io::{BufReader, Read};
use std::path::Path;
use std::sync::Arc;

use super::source::{ByteSource, Compression};
use super::{
    BitmaskSig, Call, CallFlags, EnumSig, FunctionSig, Limits, Location, ReadError, ReadErrorKind, StackFrame,
    StructSig, Value,
};

/// The newest format version this reader understands (apitrace's `TRACE_VERSION`).
pub const MAX_VERSION: u64 = 6;

/// What the stream says about itself before the first event.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Header {
    /// The format version (0–6).
    pub version: u64,
    /// How calls are meant to be replayed; equal to `version` before version 6.
    pub semantic_version: u64,
    /// Name/value pairs describing the traced process (`process.name`, …), version 6 on.
    pub properties: Vec<(String, String)>,
    pub compression: Compression,
}

/// Event bytes (`trace_format.hpp`).
const EVENT_ENTER: u8 = 0;
const EVENT_LEAVE: u8 = 1;

/// Call details.
const CALL_END: u8 = 0;
const CALL_ARG: u8 = 1;
const CALL_RET: u8 = 2;
const CALL_THREAD: u8 = 3;
const CALL_BACKTRACE: u8 = 4;
const CALL_FLAGS: u8 = 5;

/// Value tags.
const TYPE_NULL: u8 = 0x00;
const TYPE_FALSE: u8 = 0x01;
const TYPE_TRUE: u8 = 0x02;
const TYPE_SINT: u8 = 0x03;
const TYPE_UINT: u8 = 0x04;
const TYPE_FLOAT: u8 = 0x05;
const TYPE_DOUBLE: u8 = 0x06;
const TYPE_STRING: u8 = 0x07;
const TYPE_BLOB: u8 = 0x08;
const TYPE_ENUM: u8 = 0x09;
const TYPE_BITMASK: u8 = 0x0a;
const TYPE_ARRAY: u8 = 0x0b;
const TYPE_STRUCT: u8 = 0x0c;
const TYPE_OPAQUE: u8 = 0x0d;
const TYPE_REPR: u8 = 0x0e;
const TYPE_WSTRING: u8 = 0x0f;

/// Backtrace frame details.
const BACKTRACE_END: u8 = 0;
const BACKTRACE_MODULE: u8 = 1;
const BACKTRACE_FUNCTION: u8 = 2;
const BACKTRACE_FILENAME: u8 = 3;
const BACKTRACE_LINENUMBER: u8 = 4;
const BACKTRACE_OFFSET: u8 = 5;

/// The flag bit of a call apitrace synthesised.
const FLAG_FAKE: u64 = 1;

/// A call entered and not yet left, with the bytes its values hold.
struct Pending {
    call: Call,
    held_bytes: u64,
}

/// Reads a trace one call at a time: an iterator of calls in the order they leave.
///
/// Memory is bounded by [`Limits`]: one chunk, the signatures, and the calls entered but not
/// yet left. After the first error the iterator ends.
pub struct TraceReader<R> {
    source: ByteSource<R>,
    header: Header,
    limits: Limits,
    functions: HashMap<u64, Arc<FunctionSig>>,
    enums: HashMap<u64, Arc<EnumSig>>,
    bitmasks: HashMap<u64, Arc<BitmaskSig>>,
    structs: HashMap<u64, Arc<StructSig>>,
    frames: HashMap<u64, Arc<StackFrame>>,
    signature_bytes: usize,
    next_call: u64,
    pending: VecDeque<Pending>,
    /// Bytes held by the values of pending calls and the call being read.
    held_bytes: u64,
    done: bool,
}

impl TraceReader<BufReader<File>> {
    /// Opens a capture file with the default [`Limits`].
    ///
    /// # Errors
    /// When the file cannot be opened or its header is not a trace's.
    pub fn open(path: impl AsRef<Path>) -> Result<Self, ReadError> {
        let file =
            File::open(path).map_err(|e| ReadError { location: Location::default(), kind: ReadErrorKind::Io(e) })?;
        TraceReader::new(BufReader::new(file), Limits::DEFAULT)
    }
}

impl<R: Read> TraceReader<R> {
    /// Starts reading a capture: recognises the container and reads the header.
    ///
    /// # Errors
    /// An unknown or unsupported container, a version above [`MAX_VERSION`], a bad header.
    pub fn new(reader: R, limits: Limits) -> Result<Self, ReadError> {
        let mut source = ByteSource::open(reader, limits)?;
        let version = source.varint("the format version")?;
        if version > MAX_VERSION {
            return Err(source.error(ReadErrorKind::UnsupportedVersion(version)));
        }
        let mut header =
            Header { version, semantic_version: version, properties: Vec::new(), compression: source.compression() };
        let mut reader = TraceReader {
            source,
            header: header.clone(),
            limits,
            functions: HashMap::new(),
            enums: HashMap::new(),
            bitmasks: HashMap::new(),
            structs: HashMap::new(),
            frames: HashMap::new(),
            signature_bytes: 0,
            next_call: 0,
            pending: VecDeque::new(),
            held_bytes: 0,
            done: false,
        };
        if version >= 6 {
            let semantic = reader.source.varint("the semantic version")?;
            if semantic > version {
                return Err(reader.source.error(ReadErrorKind::SemanticVersionAboveVersion { semantic, version }));
            }
            header.semantic_version = semantic;
            loop {
                let name = reader.signature_string("a property name")?;
                if name.is_empty() {
                    break;
                }
                let value = reader.signature_string("a property value")?;
                header.properties.push((name, value));
            }
        }
        reader.header = header;
        Ok(reader)
    }

    pub fn header(&self) -> &Header {
        &self.header
    }

    /// Stream offset of the next byte to read.
    pub fn offset(&self) -> u64 {
        self.source.offset()
    }

    /// The next call to leave, or at the end of the stream a call that entered and never left
    /// (marked incomplete), or `None` when there are none.
    ///
    /// # Errors
    /// Malformed or truncated data, or a limit exceeded; the error names where.
    pub fn next_call(&mut self) -> Result<Option<Call>, ReadError> {
        if self.done {
            return Ok(None);
        }
        let result = self.read_until_leave();
        if !matches!(result, Ok(Some(_))) {
            self.done = true;
        }
        result
    }

    fn read_until_leave(&mut self) -> Result<Option<Call>, ReadError> {
        loop {
            self.source.call = None;
            match self.source.byte_or_end()? {
                Some(EVENT_ENTER) => self.enter()?,
                Some(EVENT_LEAVE) => return self.leave().map(Some),
                Some(other) => return Err(self.source.error(ReadErrorKind::UnknownEvent(other))),
                None => {
                    return Ok(self.pending.pop_front().map(|pending| {
                        self.held_bytes -= pending.held_bytes;
                        let mut call = pending.call;
                        call.flags.incomplete = true;
                        call
                    }));
                }
            }
        }
    }

    fn enter(&mut self) -> Result<(), ReadError> {
        let number = self.next_call;
        self.next_call += 1;
        self.source.call = Some(number);
        let thread = if self.header.version >= 4 { self.source.varint("a thread number")? } else { 0 };
        let sig = self.function_sig()?;
        if self.pending.len() >= self.limits.max_pending_calls {
            return Err(self.source.error(ReadErrorKind::limit(
                "calls entered and not left",
                self.pending.len() as u64 + 1,
                self.limits.max_pending_calls,
            )));
        }
        let mut pending = Pending {
            call: Call {
                number,
                thread,
                sig,
                args: Vec::new(),
                ret: None,
                backtrace: Vec::new(),
                flags: CallFlags::default(),
            },
            held_bytes: 0,
        };
        self.details(&mut pending)?;
        self.pending.push_back(pending);
        Ok(())
    }

    fn leave(&mut self) -> Result<Call, ReadError> {
        let number = self.source.varint("a call number")?;
        self.source.call = Some(number);
        let index = self
            .pending
            .iter()
            .position(|pending| pending.call.number == number)
            .ok_or_else(|| self.source.error(ReadErrorKind::LeaveUnknownCall(number)))?;
        let mut pending = self.pending.remove(index).expect("index found above");
        self.details(&mut pending)?;
        self.held_bytes -= pending.held_bytes;
        Ok(pending.call)
    }

    fn details(&mut self, pending: &mut Pending) -> Result<(), ReadError> {
        loop {
            match self.source.byte("a call detail")? {
                CALL_END => return Ok(()),
                CALL_ARG => {
                    let index = self.source.varint("an argument index")?;
                    let count = pending.call.sig.arg_names.len();
                    if index >= count as u64 {
                        return Err(self.source.error(ReadErrorKind::ArgumentIndex {
                            index,
                            function: pending.call.sig.name.clone(),
                            count,
                        }));
                    }
                    let value = self.value(pending, 0)?;
                    let index = index as usize;
                    if pending.call.args.len() <= index {
                        pending.call.args.resize(index + 1, None);
                    }
                    pending.call.args[index] = Some(value);
                }
                CALL_RET => pending.call.ret = Some(self.value(pending, 0)?),
                CALL_THREAD => pending.call.thread = self.source.varint("a thread number")?,
                CALL_BACKTRACE => self.backtrace(pending)?,
                CALL_FLAGS => {
                    let flags = self.source.varint("call flags")?;
                    pending.call.flags.raw |= flags;
                    pending.call.flags.fake |= flags & FLAG_FAKE != 0;
                }
                other => return Err(self.source.error(ReadErrorKind::UnknownCallDetail(other))),
            }
        }
    }

    /// Counts `bytes` against [`Limits::max_held_bytes`] for `pending`.
    fn hold(&mut self, pending: &mut Pending, bytes: u64) -> Result<(), ReadError> {
        let held = self.held_bytes + bytes;
        if held > self.limits.max_held_bytes {
            return Err(self.source.error(ReadErrorKind::limit(
                "bytes held by pending calls",
                held,
                self.limits.max_held_bytes,
            )));
        }
        self.held_bytes = held;
        pending.held_bytes += bytes;
        Ok(())
    }

    fn value(&mut self, pending: &mut Pending, depth: usize) -> Result<Value, ReadError> {
        if depth > self.limits.max_depth {
            return Err(self.source.error(ReadErrorKind::limit(
                "value nesting depth",
                depth as u64,
                self.limits.max_depth,
            )));
        }
        self.hold(pending, size_of::<Value>() as u64)?;
        let tag = self.source.byte("a value tag")?;
        Ok(match tag {
            TYPE_NULL => Value::Null,
            TYPE_FALSE => Value::Bool(false),
            TYPE_TRUE => Value::Bool(true),
            TYPE_SINT => Value::SInt(self.negative()?),
            TYPE_UINT => Value::UInt(self.source.varint("an integer")?),
            TYPE_FLOAT => Value::Float(f32::from_le_bytes(self.source.array("a float")?)),
            TYPE_DOUBLE => Value::Double(f64::from_le_bytes(self.source.array("a double")?)),
            TYPE_STRING => Value::String(self.bytes(pending, self.limits.max_string_bytes, "string")?),
            TYPE_BLOB => Value::Blob(self.bytes(pending, self.limits.max_blob_bytes, "blob")?),
            TYPE_ENUM => {
                if self.header.version >= 3 {
                    let sig = self.enum_sig()?;
                    let value = self.signed("an enum value")?;
                    Value::Enum { sig, value }
                } else {
                    let sig = self.old_enum_sig()?;
                    let value = sig.values[0].1;
                    Value::Enum { sig, value }
                }
            }
            TYPE_BITMASK => {
                let sig = self.bitmask_sig()?;
                let value = self.source.varint("a bitmask value")?;
                Value::Bitmask { sig, value }
            }
            TYPE_ARRAY => {
                let len = self.length(self.limits.max_array_len, "array elements")?;
                let mut values = Vec::new();
                for _ in 0..len {
                    values.push(self.value(pending, depth + 1)?);
                }
                Value::Array(values)
            }
            TYPE_STRUCT => {
                let sig = self.struct_sig()?;
                let mut members = Vec::with_capacity(sig.member_names.len());
                for _ in 0..sig.member_names.len() {
                    members.push(self.value(pending, depth + 1)?);
                }
                Value::Struct { sig, members }
            }
            TYPE_OPAQUE => Value::Pointer(self.source.varint("a pointer")?),
            TYPE_REPR => {
                let human = Box::new(self.value(pending, depth + 1)?);
                let machine = Box::new(self.value(pending, depth + 1)?);
                Value::Repr { human, machine }
            }
            TYPE_WSTRING => {
                let len = self.length(self.limits.max_array_len, "wide string characters")?;
                self.hold(pending, 4 * len as u64)?;
                let mut text = String::new();
                for _ in 0..len {
                    let code = self.source.varint("a wide character")?;
                    let c = u32::try_from(code).ok().and_then(char::from_u32).unwrap_or(char::REPLACEMENT_CHARACTER);
                    text.push(c);
                }
                Value::WString(text)
            }
            other => return Err(self.source.error(ReadErrorKind::UnknownValueTag(other))),
        })
    }

    /// A length prefix, checked against `limit`.
    fn length(&mut self, limit: usize, what: &'static str) -> Result<usize, ReadError> {
        let len = self.source.varint(what)?;
        if len > limit as u64 {
            return Err(self.source.error(ReadErrorKind::limit(what, len, limit)));
        }
        Ok(len as usize)
    }

    /// A length-prefixed byte string held by a call.
    fn bytes(&mut self, pending: &mut Pending, limit: usize, what: &'static str) -> Result<Vec<u8>, ReadError> {
        let len = self.length(limit, what)?;
        self.hold(pending, len as u64)?;
        let mut out = Vec::new();
        self.source.bytes_into(len, &mut out, what)?;
        Ok(out)
    }

    /// The magnitude of a negative integer (tag 0x03).
    fn negative(&mut self) -> Result<i64, ReadError> {
        let magnitude = self.source.varint("a negative integer")?;
        0i64.checked_sub_unsigned(magnitude)
            .ok_or_else(|| self.source.error(ReadErrorKind::NegativeOverflow(magnitude)))
    }

    /// A signed integer written with its own tag (enum values).
    fn signed(&mut self, what: &'static str) -> Result<i64, ReadError> {
        match self.source.byte(what)? {
            TYPE_SINT => self.negative(),
            TYPE_UINT => {
                let value = self.source.varint(what)?;
                i64::try_from(value).map_err(|_| self.source.error(ReadErrorKind::limit(what, value, i64::MAX as u64)))
            }
            tag => Err(self.source.error(ReadErrorKind::ExpectedInteger { what, tag })),
        }
    }

    /// A string held by a signature or the header, counted against the signature budget.
    fn signature_string(&mut self, what: &'static str) -> Result<String, ReadError> {
        let len = self.length(self.limits.max_string_bytes, what)?;
        self.signature_bytes += len;
        if self.signature_bytes > self.limits.max_signature_bytes {
            return Err(self.source.error(ReadErrorKind::limit(
                "bytes of signature names",
                self.signature_bytes as u64,
                self.limits.max_signature_bytes,
            )));
        }
        let mut out = Vec::new();
        self.source.bytes_into(len, &mut out, what)?;
        Ok(String::from_utf8(out).unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into()))
    }

    fn signature_count(&self) -> usize {
        self.functions.len() + self.enums.len() + self.bitmasks.len() + self.structs.len() + self.frames.len()
    }

    /// Checks there is room for one more signature.
    fn new_signature(&self) -> Result<(), ReadError> {
        let count = self.signature_count() + 1;
        if count > self.limits.max_signatures {
            return Err(self.source.error(ReadErrorKind::limit(
                "signatures",
                count as u64,
                self.limits.max_signatures,
            )));
        }
        Ok(())
    }

    fn items(&mut self, what: &'static str) -> Result<usize, ReadError> {
        self.length(self.limits.max_signature_items, what)
    }

    /// A function signature: defined at the first use of its id, only the id afterwards.
    fn function_sig(&mut self) -> Result<Arc<FunctionSig>, ReadError> {
        let id = self.source.varint("a function signature id")?;
        if let Some(sig) = self.functions.get(&id) {
            return Ok(sig.clone());
        }
        self.new_signature()?;
        let name = self.signature_string("a function name")?;
        let count = self.items("argument names")?;
        let mut arg_names = Vec::new();
        for _ in 0..count {
            arg_names.push(self.signature_string("an argument name")?);
        }
        let sig = Arc::new(FunctionSig { id, name, arg_names });
        self.functions.insert(id, sig.clone());
        Ok(sig)
    }

    fn enum_sig(&mut self) -> Result<Arc<EnumSig>, ReadError> {
        let id = self.source.varint("an enum signature id")?;
        if let Some(sig) = self.enums.get(&id) {
            return Ok(sig.clone());
        }
        self.new_signature()?;
        let count = self.items("enum values")?;
        let mut values = Vec::new();
        for _ in 0..count {
            let name = self.signature_string("an enum name")?;
            let value = self.signed("an enum signature value")?;
            values.push((name, value));
        }
        let sig = Arc::new(EnumSig { id, values });
        self.enums.insert(id, sig.clone());
        Ok(sig)
    }

    /// Before version 3 an enum signature held one name and its value.
    fn old_enum_sig(&mut self) -> Result<Arc<EnumSig>, ReadError> {
        let id = self.source.varint("an enum signature id")?;
        if let Some(sig) = self.enums.get(&id) {
            return Ok(sig.clone());
        }
        self.new_signature()?;
        let name = self.signature_string("an enum name")?;
        let value = self.signed("an enum signature value")?;
        let sig = Arc::new(EnumSig { id, values: vec![(name, value)] });
        self.enums.insert(id, sig.clone());
        Ok(sig)
    }

    fn bitmask_sig(&mut self) -> Result<Arc<BitmaskSig>, ReadError> {
        let id = self.source.varint("a bitmask signature id")?;
        if let Some(sig) = self.bitmasks.get(&id) {
            return Ok(sig.clone());
        }
        self.new_signature()?;
        let count = self.items("bitmask flags")?;
        let mut flags = Vec::new();
        for _ in 0..count {
            let name = self.signature_string("a bitmask flag name")?;
            let bits = self.source.varint("a bitmask flag value")?;
            flags.push((name, bits));
        }
        let sig = Arc::new(BitmaskSig { id, flags });
        self.bitmasks.insert(id, sig.clone());
        Ok(sig)
    }

    fn struct_sig(&mut self) -> Result<Arc<StructSig>, ReadError> {
        let id = self.source.varint("a struct signature id")?;
        if let Some(sig) = self.structs.get(&id) {
            return Ok(sig.clone());
        }
        self.new_signature()?;
        let name = self.signature_string("a struct name")?;
        let count = self.items("struct members")?;
        let mut member_names = Vec::new();
        for _ in 0..count {
            member_names.push(self.signature_string("a struct member name")?);
        }
        let sig = Arc::new(StructSig { id, name, member_names });
        self.structs.insert(id, sig.clone());
        Ok(sig)
    }

    fn backtrace(&mut self, pending: &mut Pending) -> Result<(), ReadError> {
        let count = self.length(self.limits.max_backtrace_frames, "backtrace frames")?;
        self.hold(pending, (count * size_of::<Arc<StackFrame>>()) as u64)?;
        let mut frames = Vec::with_capacity(count);
        for _ in 0..count {
            frames.push(self.frame()?);
        }
        pending.call.backtrace = frames;
        Ok(())
    }

    fn frame(&mut self) -> Result<Arc<StackFrame>, ReadError> {
        let id = self.source.varint("a backtrace frame id")?;
        if let Some(frame) = self.frames.get(&id) {
            return Ok(frame.clone());
        }
        self.new_signature()?;
        let mut frame = StackFrame { id, ..StackFrame::default() };
        loop {
            match self.source.byte("a backtrace frame detail")? {
                BACKTRACE_END => break,
                BACKTRACE_MODULE => frame.module = Some(self.signature_string("a module name")?),
                BACKTRACE_FUNCTION => frame.function = Some(self.signature_string("a function name")?),
                BACKTRACE_FILENAME => frame.filename = Some(self.signature_string("a source file name")?),
                BACKTRACE_LINENUMBER => frame.line = Some(self.source.varint("a line number")?),
                BACKTRACE_OFFSET => frame.offset = Some(self.source.varint("a module offset")?),
                other => {
                    return Err(self.source.error(ReadErrorKind::UnknownBacktraceDetail(other)));
                }
            }
        }
        let frame = Arc::new(frame);
        self.frames.insert(id, frame.clone());
        Ok(frame)
    }
}

impl<R: Read> Iterator for TraceReader<R> {
    type Item = Result<Call, ReadError>;

    fn next(&mut self) -> Option<Self::Item> {
        self.next_call().transpose()
    }
}

impl<R: Read> std::iter::FusedIterator for TraceReader<R> {}
