//! Typed OpenGL ES 2.0 / 3.0 and EGL calls above the wire format.
//!
//! [`GlesReader`] reads a capture and decodes each call into a [`Command`]: every OpenGL ES 2.0
//! call that draws or changes state, the GLES 3.0 calls applications use most (vertex array
//! objects, invalidation, blits, draw buffers, instancing, uniform buffers, mapped ranges,
//! samplers, queries), their OES/EXT/ANGLE/IMG variants, QCOM tiling, and the EGL calls that
//! create, bind, present and destroy surfaces and contexts. apitrace's fake calls decode like
//! any other, flagged [`GlesCall::fake`]. Writes through mapped buffers (apitrace's fake
//! `memcpy`) are resolved to [`Command::BufferWrite`] by [`Decoder`].
//!
//! Calls that change nothing tiler models are on [`IGNORED`], each with its reason, and decode
//! to [`Command::Ignored`]. Any other call is a [`DecodeError`] with its number and name.

mod args;
mod command;
pub mod consts;
mod decode;
mod ignore;

use std::fs::File;
use std::io::{BufReader, Read};
use std::path::Path;

pub use command::{ClearValue, Command, EglHandle, GlEnum, Memory, Params, UniformValue};
pub use decode::Decoder;
pub use ignore::{IGNORED, NOT_MODELLED, ignored, not_modelled};

use crate::wire::{Header, Limits, ReadError, TraceReader};

/// One decoded call.
#[derive(Clone, Debug, PartialEq)]
pub struct GlesCall {
    /// The call's number in the trace (as `apitrace dump` shows it).
    pub number: u64,
    pub thread: u64,
    /// apitrace synthesised the call; it is applied like any other.
    pub fake: bool,
    pub command: Command,
}

/// A call that could not be decoded, with its number and function name.
#[derive(Debug, thiserror::Error)]
#[error("call {call} `{function}`: {kind}")]
pub struct DecodeError {
    pub call: u64,
    pub function: String,
    pub kind: DecodeErrorKind,
}

/// Why a call could not be decoded.
#[derive(Debug, thiserror::Error)]
pub enum DecodeErrorKind {
    #[error("not an OpenGL ES or EGL call this reader decodes, and not on its ignore list")]
    Unknown,
    /// A call of a feature tiler does not model, or of desktop OpenGL.
    #[error("not supported: {feature}")]
    NotModelled { feature: &'static str },
    #[error("argument `{argument}` is missing")]
    MissingArgument { argument: String },
    #[error("argument `{argument}`: expected {expected}, found a {found}")]
    WrongType { argument: String, expected: &'static str, found: &'static str },
    #[error("argument `{argument}`: {value} is out of range for {expected}")]
    OutOfRange { argument: String, expected: &'static str, value: String },
    #[error("argument `{argument}`: {found} values where {expected} were expected")]
    Count { argument: String, expected: u64, found: u64 },
    #[error("the return value is missing (the trace ended inside the call?)")]
    MissingReturn,
    #[error("the return value {value} is not of the expected type")]
    BadReturn { value: String },
    #[error("maps target {target:#06x}, to which no buffer is bound")]
    MapWithoutBuffer { target: GlEnum },
    #[error("writes {size} bytes at {dest:#x}, which is not inside a mapped buffer")]
    UnmappedWrite { dest: u64, size: u64 },
    #[error("writes {size} bytes at offset {offset} of buffer {buffer}, which holds {buffer_size}")]
    WriteOutsideBuffer { buffer: u32, offset: u64, size: u64, buffer_size: u64 },
}

/// Reading a capture failed, or decoding one of its calls.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error(transparent)]
    Read(#[from] ReadError),
    #[error(transparent)]
    Decode(#[from] DecodeError),
}

/// Reads a capture as typed calls, one at a time, in the order they leave.
pub struct GlesReader<R> {
    reader: TraceReader<R>,
    decoder: Decoder,
    done: bool,
}

impl GlesReader<BufReader<File>> {
    /// Opens a capture file with the default [`Limits`].
    ///
    /// # Errors
    /// When the file cannot be opened or its header is not a trace's.
    pub fn open(path: impl AsRef<Path>) -> Result<Self, ReadError> {
        Ok(GlesReader::from_reader(TraceReader::open(path)?))
    }
}

impl<R: Read> GlesReader<R> {
    /// Starts reading a capture from `reader`.
    ///
    /// # Errors
    /// As [`TraceReader::new`].
    pub fn new(reader: R, limits: Limits) -> Result<Self, ReadError> {
        Ok(GlesReader::from_reader(TraceReader::new(reader, limits)?))
    }

    /// Decodes the calls of a reader already open.
    pub fn from_reader(reader: TraceReader<R>) -> Self {
        GlesReader { reader, decoder: Decoder::new(), done: false }
    }

    pub fn header(&self) -> &Header {
        self.reader.header()
    }
}

impl<R: Read> Iterator for GlesReader<R> {
    type Item = Result<GlesCall, Error>;

    /// The next call, decoded; after the first error, `None`.
    fn next(&mut self) -> Option<Self::Item> {
        if self.done {
            return None;
        }
        let item = match self.reader.next()? {
            Ok(call) => self.decoder.decode(call).map_err(Error::from),
            Err(e) => Err(e.into()),
        };
        self.done = item.is_err();
        Some(item)
    }
}

impl<R: Read> std::iter::FusedIterator for GlesReader<R> {}
