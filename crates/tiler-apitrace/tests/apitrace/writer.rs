//! A small apitrace writer for generated test captures: the stream, then a snappy or gzip
//! container around it.

use std::collections::HashSet;
use std::io::Write;

/// A value to write, one variant per wire tag. Signatures carry their id and definition; the
/// writer defines each id the first time it is written, as apitrace does.
#[derive(Clone, Debug)]
pub enum W {
    Null,
    Bool(bool),
    /// The magnitude of a negative integer.
    Neg(u64),
    UInt(u64),
    Float(f32),
    Double(f64),
    Str(&'static str),
    Blob(Vec<u8>),
    Enum {
        id: u64,
        values: Vec<(&'static str, i64)>,
        value: i64,
    },
    Bitmask {
        id: u64,
        flags: Vec<(&'static str, u64)>,
        value: u64,
    },
    Array(Vec<W>),
    Struct {
        id: u64,
        name: &'static str,
        members: Vec<&'static str>,
        values: Vec<W>,
    },
    Pointer(u64),
    Repr(Box<W>, Box<W>),
    Wide(Vec<u32>),
}

impl W {
    /// A GLenum the way apitrace writes one: a one-name enum signature per value.
    pub fn gl_enum(name: &'static str, value: i64) -> W {
        W::Enum { id: 1000 + value as u64, values: vec![(name, value)], value }
    }
}

pub struct Writer {
    pub stream: Vec<u8>,
    pub version: u64,
    next_call: u64,
    functions: Vec<String>,
    defined: HashSet<(u8, u64)>,
}

impl Writer {
    /// A stream of `version`, with the version-6 header fields when they apply.
    pub fn new(version: u64) -> Writer {
        let mut writer =
            Writer { stream: Vec::new(), version, next_call: 0, functions: Vec::new(), defined: HashSet::new() };
        writer.uint(version);
        if version >= 6 {
            writer.uint(version);
            writer.string(b"process.name");
            writer.string(b"test");
            writer.string(b"");
        }
        writer
    }

    pub fn byte(&mut self, byte: u8) {
        self.stream.push(byte);
    }

    pub fn uint(&mut self, mut value: u64) {
        loop {
            let byte = (value & 0x7f) as u8;
            value >>= 7;
            if value == 0 {
                self.stream.push(byte);
                return;
            }
            self.stream.push(byte | 0x80);
        }
    }

    pub fn string(&mut self, bytes: &[u8]) {
        self.uint(bytes.len() as u64);
        self.stream.extend_from_slice(bytes);
    }

    fn signed(&mut self, value: i64) {
        if value < 0 {
            self.byte(0x03);
            self.uint(value.unsigned_abs());
        } else {
            self.byte(0x04);
            self.uint(value as u64);
        }
    }

    /// Writes an enter event; returns the call's number.
    pub fn enter(&mut self, name: &str, arg_names: &[&str]) -> u64 {
        self.byte(0x00);
        if self.version >= 4 {
            self.uint(0);
        }
        let id = match self.functions.iter().position(|f| f == name) {
            Some(id) => {
                self.uint(id as u64);
                id
            }
            None => {
                let id = self.functions.len();
                self.functions.push(name.to_string());
                self.uint(id as u64);
                self.string(name.as_bytes());
                self.uint(arg_names.len() as u64);
                for arg in arg_names {
                    self.string(arg.as_bytes());
                }
                id
            }
        };
        let _ = id;
        let number = self.next_call;
        self.next_call += 1;
        number
    }

    pub fn leave(&mut self, number: u64) {
        self.byte(0x01);
        self.uint(number);
    }

    pub fn arg(&mut self, index: u64, value: &W) {
        self.byte(0x01);
        self.uint(index);
        self.value(value);
    }

    pub fn ret(&mut self, value: &W) {
        self.byte(0x02);
        self.value(value);
    }

    pub fn flags(&mut self, flags: u64) {
        self.byte(0x05);
        self.uint(flags);
    }

    pub fn end(&mut self) {
        self.byte(0x00);
    }

    /// A whole call: enter with its arguments (and flags), leave with its return value.
    pub fn call(&mut self, name: &str, args: &[(&str, W)], ret: Option<W>, fake: bool) -> u64 {
        let names: Vec<&str> = args.iter().map(|(name, _)| *name).collect();
        let number = self.enter(name, &names);
        for (index, (_, value)) in args.iter().enumerate() {
            self.arg(index as u64, value);
        }
        if fake {
            self.flags(1);
        }
        self.end();
        self.leave(number);
        if let Some(ret) = ret {
            self.ret(&ret);
        }
        self.end();
        number
    }

    fn first(&mut self, kind: u8, id: u64) -> bool {
        self.defined.insert((kind, id))
    }

    pub fn value(&mut self, value: &W) {
        match value {
            W::Null => self.byte(0x00),
            W::Bool(false) => self.byte(0x01),
            W::Bool(true) => self.byte(0x02),
            W::Neg(magnitude) => {
                self.byte(0x03);
                self.uint(*magnitude);
            }
            W::UInt(v) => {
                self.byte(0x04);
                self.uint(*v);
            }
            W::Float(v) => {
                self.byte(0x05);
                self.stream.extend(v.to_le_bytes());
            }
            W::Double(v) => {
                self.byte(0x06);
                self.stream.extend(v.to_le_bytes());
            }
            W::Str(s) => {
                self.byte(0x07);
                self.string(s.as_bytes());
            }
            W::Blob(bytes) => {
                self.byte(0x08);
                self.string(bytes);
            }
            W::Enum { id, values, value } => {
                self.byte(0x09);
                self.uint(*id);
                if self.first(0x09, *id) {
                    if self.version >= 3 {
                        self.uint(values.len() as u64);
                        for (name, v) in values {
                            self.string(name.as_bytes());
                            self.signed(*v);
                        }
                    } else {
                        self.string(values[0].0.as_bytes());
                        self.signed(values[0].1);
                    }
                }
                if self.version >= 3 {
                    self.signed(*value);
                }
            }
            W::Bitmask { id, flags, value } => {
                self.byte(0x0a);
                self.uint(*id);
                if self.first(0x0a, *id) {
                    self.uint(flags.len() as u64);
                    for (name, bits) in flags {
                        self.string(name.as_bytes());
                        self.uint(*bits);
                    }
                }
                self.uint(*value);
            }
            W::Array(values) => {
                self.byte(0x0b);
                self.uint(values.len() as u64);
                for v in values {
                    self.value(v);
                }
            }
            W::Struct { id, name, members, values } => {
                self.byte(0x0c);
                self.uint(*id);
                if self.first(0x0c, *id) {
                    self.string(name.as_bytes());
                    self.uint(members.len() as u64);
                    for member in members {
                        self.string(member.as_bytes());
                    }
                }
                for v in values {
                    self.value(v);
                }
            }
            W::Pointer(address) => {
                self.byte(0x0d);
                self.uint(*address);
            }
            W::Repr(human, machine) => {
                self.byte(0x0e);
                self.value(human);
                self.value(machine);
            }
            W::Wide(chars) => {
                self.byte(0x0f);
                self.uint(chars.len() as u64);
                for c in chars {
                    self.uint(*c as u64);
                }
            }
        }
    }

    /// The capture as apitrace writes it: `at`, then snappy chunks of `chunk_bytes` each.
    pub fn snappy(&self, chunk_bytes: usize) -> Vec<u8> {
        snappy_container(&self.stream, chunk_bytes)
    }

    /// The capture as one gzip stream.
    pub fn gzip(&self) -> Vec<u8> {
        let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        encoder.write_all(&self.stream).unwrap();
        encoder.finish().unwrap()
    }
}

/// `at`, then `stream` in snappy chunks of `chunk_bytes` uncompressed bytes each.
pub fn snappy_container(stream: &[u8], chunk_bytes: usize) -> Vec<u8> {
    let mut out = b"at".to_vec();
    let mut encoder = snap::raw::Encoder::new();
    for chunk in stream.chunks(chunk_bytes.max(1)) {
        let compressed = encoder.compress_vec(chunk).unwrap();
        out.extend((compressed.len() as u32).to_le_bytes());
        out.extend(compressed);
    }
    out
}
