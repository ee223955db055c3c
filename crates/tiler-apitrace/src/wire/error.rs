//! What went wrong reading a trace, and where.

use std::fmt;

/// Where in a trace something happened: a byte of the uncompressed stream, the snappy chunk
/// holding it (when the file is snappy), and the call being read (when there is one).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Location {
    /// Byte offset in the uncompressed stream (the `at` magic is not part of it).
    pub offset: u64,
    /// The snappy chunk holding that byte.
    pub chunk: Option<ChunkLocation>,
    /// The number of the call being read.
    pub call: Option<u64>,
}

/// A byte inside one snappy chunk.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ChunkLocation {
    /// File offset of the chunk's 4-byte length.
    pub file_offset: u64,
    /// Offset of the byte in the chunk's uncompressed data.
    pub offset_in_chunk: u64,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(call) = self.call {
            write!(f, "call {call}, ")?;
        }
        write!(f, "stream byte {}", self.offset)?;
        if let Some(chunk) = self.chunk {
            write!(f, " (chunk at file byte {}, byte {} in it)", chunk.file_offset, chunk.offset_in_chunk)?;
        }
        Ok(())
    }
}

/// A trace that could not be read, with where it went wrong.
#[derive(Debug, thiserror::Error)]
#[error("{location}: {kind}")]
pub struct ReadError {
    pub location: Location,
    pub kind: ReadErrorKind,
}

/// What went wrong reading a trace.
#[derive(Debug, thiserror::Error)]
pub enum ReadErrorKind {
    #[error("reading the file: {0}")]
    Io(#[source] std::io::Error),
    #[error("the file is empty or shorter than its 2-byte magic")]
    Empty,
    #[error(
        "not an apitrace capture: it starts with {0:02x?}; captures start with `at` (snappy) or \
         1f 8b (gzip), and brotli ones, which this reader does not support, have no magic"
    )]
    UnknownContainer(Vec<u8>),
    #[error("{0} compression is not supported; `apitrace repack IN OUT` rewrites a capture as snappy")]
    UnsupportedCompression(&'static str),
    #[error("gzip stream: {0}")]
    Gzip(#[source] std::io::Error),
    #[error("the file ends inside a chunk's 4-byte length ({got} bytes of it present)")]
    TruncatedChunkLength { got: usize },
    #[error("a chunk declares {declared} compressed bytes but the file ends after {got}")]
    TruncatedChunk { declared: u64, got: u64 },
    #[error("a chunk declares 0 compressed bytes")]
    EmptyChunk,
    #[error("snappy chunk: {0}")]
    Snappy(#[source] snap::Error),
    #[error("trace format version {0} is newer than this reader understands (up to 6)")]
    UnsupportedVersion(u64),
    #[error("semantic version {semantic} is above the format version {version}")]
    SemanticVersionAboveVersion { semantic: u64, version: u64 },
    #[error("the stream ends inside {0}")]
    UnexpectedEnd(&'static str),
    #[error("{0}: a variable-length integer does not fit in 64 bits")]
    VarintOverflow(&'static str),
    #[error("a negative integer of magnitude {0} does not fit in 64 bits")]
    NegativeOverflow(u64),
    #[error("unknown event byte {0:#04x} (0 enters a call, 1 leaves one)")]
    UnknownEvent(u8),
    #[error("unknown call detail {0:#04x}")]
    UnknownCallDetail(u8),
    #[error("unknown value tag {0:#04x}")]
    UnknownValueTag(u8),
    #[error("unknown backtrace detail {0:#04x}")]
    UnknownBacktraceDetail(u8),
    #[error("{what} has type tag {tag:#04x}, expected a signed (0x03) or unsigned (0x04) integer")]
    ExpectedInteger { what: &'static str, tag: u8 },
    #[error("argument index {index} of `{function}`, which has {count} arguments")]
    ArgumentIndex { index: u64, function: String, count: usize },
    #[error("call {0} leaves but was never entered or has already left")]
    LeaveUnknownCall(u64),
    #[error("{what}: {value} exceeds the limit of {limit}")]
    Limit { what: &'static str, value: u64, limit: u64 },
}

impl ReadErrorKind {
    pub(crate) fn limit(what: &'static str, value: u64, limit: impl TryInto<u64>) -> Self {
        ReadErrorKind::Limit { what, value, limit: limit.try_into().unwrap_or(u64::MAX) }
    }
}
