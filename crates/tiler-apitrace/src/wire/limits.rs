//! How much a trace may ask the reader to hold, checked before anything is allocated.

/// Bounds on what one trace may make the reader allocate. Every length read from the file is
/// checked against these before memory is reserved for it, so a corrupt or hostile file gets a
/// [`ReadError`](super::ReadError) instead of an abort.
///
/// The defaults are far above what real captures need (the largest value in the shared glmark2
/// captures is a 1.8 MB vertex blob; apitrace writes 1 MiB chunks) and low enough that the reader
/// never holds more than about a gigabyte.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Uncompressed bytes of one snappy chunk. apitrace writes 1 MiB chunks.
    pub max_chunk_bytes: usize,
    /// Uncompressed bytes of the whole stream.
    pub max_stream_bytes: u64,
    /// Bytes of one string value (shader sources are the long ones) or one name.
    pub max_string_bytes: usize,
    /// Bytes of one blob (buffer and texture uploads).
    pub max_blob_bytes: usize,
    /// Elements of one array value (and characters of one wide string).
    pub max_array_len: usize,
    /// Argument names of a function, names of an enum or bitmask, members of a struct.
    pub max_signature_items: usize,
    /// Signatures of every kind (function, enum, bitmask, struct, backtrace frame) together.
    pub max_signatures: usize,
    /// Bytes of every name held by signatures together.
    pub max_signature_bytes: usize,
    /// Calls entered and not yet left.
    pub max_pending_calls: usize,
    /// Bytes held by the values of calls entered and not yet returned, together.
    pub max_held_bytes: u64,
    /// Nesting of arrays, structs and representations inside one value.
    pub max_depth: usize,
    /// Frames of one backtrace.
    pub max_backtrace_frames: usize,
}

impl Limits {
    /// The defaults described on [`Limits`].
    pub const DEFAULT: Limits = Limits {
        max_chunk_bytes: 16 << 20,
        max_stream_bytes: 64 << 30,
        max_string_bytes: 16 << 20,
        max_blob_bytes: 256 << 20,
        max_array_len: 1 << 22,
        max_signature_items: 1 << 16,
        max_signatures: 1 << 20,
        max_signature_bytes: 64 << 20,
        max_pending_calls: 1 << 12,
        max_held_bytes: 1 << 30,
        max_depth: 32,
        max_backtrace_frames: 1 << 10,
    };

    /// Small bounds for fuzzing and tests: a few megabytes at most.
    pub const SMALL: Limits = Limits {
        max_chunk_bytes: 1 << 20,
        max_stream_bytes: 8 << 20,
        max_string_bytes: 1 << 16,
        max_blob_bytes: 1 << 20,
        max_array_len: 1 << 12,
        max_signature_items: 1 << 10,
        max_signatures: 1 << 12,
        max_signature_bytes: 1 << 20,
        max_pending_calls: 64,
        max_held_bytes: 4 << 20,
        max_depth: 8,
        max_backtrace_frames: 64,
    };
}

impl Default for Limits {
    fn default() -> Self {
        Limits::DEFAULT
    }
}
