//! The container: the uncompressed trace stream read one chunk at a time, with positions.
//!
//! A snappy capture is the two bytes `at`, then chunks: a little-endian `u32` compressed length
//! and one raw snappy block of that length (apitrace's own framing, older than snappy's framing
//! format; `trace_file_snappy.cpp`). apitrace writes blocks of at most 1 MiB uncompressed, and a
//! value may continue from one chunk into the next. A gzip capture (`1f 8b`, what apitrace wrote
//! before snappy) is one gzip stream of the same bytes. zstd captures (magic `28 b5 2f fd`) and
//! brotli ones (no magic at all) are recognised as far as they can be and refused.
//!
//! Only one chunk is held at a time, so memory is bounded by [`Limits::max_chunk_bytes`].

use std::io::{self, Read};

use flate2::read::GzDecoder;

use super::{ChunkLocation, Limits, Location, ReadError, ReadErrorKind};

/// How the stream is compressed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compression {
    Snappy,
    Gzip,
}

/// Bytes read by gzip per refill: the stream is not chunked, so pick a size.
const GZIP_READ_BYTES: usize = 64 << 10;

enum Container<R> {
    Snappy {
        reader: R,
        compressed: Vec<u8>,
        decoder: snap::raw::Decoder,
        /// File offset of the next chunk's length.
        file_offset: u64,
    },
    Gzip(Box<GzDecoder<io::Chain<io::Cursor<[u8; 2]>, R>>>),
}

pub(crate) struct ByteSource<R> {
    container: Container<R>,
    limits: Limits,
    /// The current chunk, uncompressed.
    chunk: Vec<u8>,
    /// Next byte to read in `chunk`.
    pos: usize,
    /// Stream offset of `chunk[0]`.
    chunk_start: u64,
    /// File offset of the current snappy chunk.
    chunk_file_offset: Option<u64>,
    ended: bool,
    /// The call being read, for error locations.
    pub(crate) call: Option<u64>,
}

/// Reads until `buf` is full or the reader ends; returns how much was read.
fn read_full(reader: &mut impl Read, buf: &mut [u8]) -> io::Result<usize> {
    let mut got = 0;
    while got < buf.len() {
        match reader.read(&mut buf[got..]) {
            Ok(0) => break,
            Ok(n) => got += n,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(got)
}

/// The zstd frame magic, little-endian on disk (RFC 8878 §3.1.1).
const ZSTD_MAGIC: [u8; 4] = [0x28, 0xb5, 0x2f, 0xfd];

impl<R: Read> ByteSource<R> {
    /// Recognises the container from its magic.
    pub(crate) fn open(mut reader: R, limits: Limits) -> Result<Self, ReadError> {
        let at_start = |kind| ReadError { location: Location::default(), kind };
        let mut magic = [0u8; 2];
        let got = read_full(&mut reader, &mut magic).map_err(|e| at_start(ReadErrorKind::Io(e)))?;
        if got < 2 {
            return Err(at_start(ReadErrorKind::Empty));
        }
        let container = match magic {
            [b'a', b't'] => {
                Container::Snappy { reader, compressed: Vec::new(), decoder: snap::raw::Decoder::new(), file_offset: 2 }
            }
            [0x1f, 0x8b] => Container::Gzip(Box::new(GzDecoder::new(io::Cursor::new(magic).chain(reader)))),
            _ => {
                let mut more = [0u8; 2];
                let got = read_full(&mut reader, &mut more).map_err(|e| at_start(ReadErrorKind::Io(e)))?;
                let start = [magic[0], magic[1], more[0], more[1]];
                let kind = if got == 2 && start == ZSTD_MAGIC {
                    ReadErrorKind::UnsupportedCompression("zstd")
                } else {
                    ReadErrorKind::UnknownContainer(start[..2 + got].to_vec())
                };
                return Err(at_start(kind));
            }
        };
        Ok(ByteSource {
            container,
            limits,
            chunk: Vec::new(),
            pos: 0,
            chunk_start: 0,
            chunk_file_offset: None,
            ended: false,
            call: None,
        })
    }

    pub(crate) fn compression(&self) -> Compression {
        match self.container {
            Container::Snappy { .. } => Compression::Snappy,
            Container::Gzip(_) => Compression::Gzip,
        }
    }

    /// Stream offset of the next byte.
    pub(crate) fn offset(&self) -> u64 {
        self.chunk_start + self.pos as u64
    }

    pub(crate) fn location(&self) -> Location {
        Location {
            offset: self.offset(),
            chunk: self
                .chunk_file_offset
                .map(|file_offset| ChunkLocation { file_offset, offset_in_chunk: self.pos as u64 }),
            call: self.call,
        }
    }

    pub(crate) fn error(&self, kind: ReadErrorKind) -> ReadError {
        ReadError { location: self.location(), kind }
    }

    /// Loads the next non-empty chunk; `false` at the end of the stream.
    fn refill(&mut self) -> Result<bool, ReadError> {
        while self.pos >= self.chunk.len() {
            if self.ended {
                return Ok(false);
            }
            self.chunk_start += self.chunk.len() as u64;
            self.chunk.clear();
            self.pos = 0;
            let loaded = match &mut self.container {
                Container::Snappy { reader, compressed, decoder, file_offset } => {
                    self.chunk_file_offset = Some(*file_offset);
                    let chunk = SnappyChunk { reader, compressed, decoder, file_offset };
                    chunk.load(&mut self.chunk, &self.limits, self.chunk_start)
                }
                Container::Gzip(decoder) => {
                    self.chunk.resize(GZIP_READ_BYTES, 0);
                    match read_full(decoder, &mut self.chunk) {
                        Ok(got) => {
                            self.chunk.truncate(got);
                            check_stream_length(&self.limits, self.chunk_start, got).map(|()| got > 0)
                        }
                        Err(e) => {
                            self.chunk.clear();
                            Err(ReadErrorKind::Gzip(e))
                        }
                    }
                }
            };
            match loaded {
                Ok(true) => {}
                Ok(false) => {
                    self.ended = true;
                    return Ok(false);
                }
                Err(kind) => {
                    self.chunk.clear();
                    self.ended = true;
                    return Err(self.error(kind));
                }
            }
        }
        Ok(true)
    }

    /// The next byte, or `None` at the end of the stream.
    #[inline]
    pub(crate) fn byte_or_end(&mut self) -> Result<Option<u8>, ReadError> {
        if self.pos >= self.chunk.len() && !self.refill()? {
            return Ok(None);
        }
        let byte = self.chunk[self.pos];
        self.pos += 1;
        Ok(Some(byte))
    }

    /// The next byte; the end of the stream is an error naming `what` was being read.
    #[inline]
    pub(crate) fn byte(&mut self, what: &'static str) -> Result<u8, ReadError> {
        self.byte_or_end()?.ok_or_else(|| self.error(ReadErrorKind::UnexpectedEnd(what)))
    }

    /// An unsigned LEB128 integer: 7 bits a byte, least significant first, the top bit set on
    /// every byte but the last.
    pub(crate) fn varint(&mut self, what: &'static str) -> Result<u64, ReadError> {
        let mut value = 0u64;
        let mut shift = 0u32;
        loop {
            let byte = self.byte(what)?;
            let bits = (byte & 0x7f) as u64;
            // The tenth byte may only carry bit 63.
            if shift == 63 && bits > 1 || shift > 63 {
                return Err(self.error(ReadErrorKind::VarintOverflow(what)));
            }
            value |= bits << shift;
            if byte & 0x80 == 0 {
                return Ok(value);
            }
            shift += 7;
        }
    }

    /// Appends `count` bytes to `out`, across chunks; the caller has checked `count`.
    pub(crate) fn bytes_into(&mut self, count: usize, out: &mut Vec<u8>, what: &'static str) -> Result<(), ReadError> {
        let mut left = count;
        while left > 0 {
            if self.pos >= self.chunk.len() && !self.refill()? {
                return Err(self.error(ReadErrorKind::UnexpectedEnd(what)));
            }
            let take = left.min(self.chunk.len() - self.pos);
            out.extend_from_slice(&self.chunk[self.pos..self.pos + take]);
            self.pos += take;
            left -= take;
        }
        Ok(())
    }

    pub(crate) fn array<const N: usize>(&mut self, what: &'static str) -> Result<[u8; N], ReadError> {
        let mut out = [0u8; N];
        for byte in &mut out {
            *byte = self.byte(what)?;
        }
        Ok(out)
    }
}

/// The parts of a snappy container that load one chunk.
struct SnappyChunk<'a, R> {
    reader: &'a mut R,
    compressed: &'a mut Vec<u8>,
    decoder: &'a mut snap::raw::Decoder,
    file_offset: &'a mut u64,
}

impl<R: Read> SnappyChunk<'_, R> {
    /// Reads one chunk into `out` (empty on entry); `false` at the end of the file.
    fn load(self, out: &mut Vec<u8>, limits: &Limits, stream_offset: u64) -> Result<bool, ReadErrorKind> {
        let mut length = [0u8; 4];
        let got = read_full(self.reader, &mut length).map_err(ReadErrorKind::Io)?;
        if got == 0 {
            return Ok(false);
        }
        if got < 4 {
            return Err(ReadErrorKind::TruncatedChunkLength { got });
        }
        let declared = u32::from_le_bytes(length) as u64;
        if declared == 0 {
            return Err(ReadErrorKind::EmptyChunk);
        }
        let max = snap::raw::max_compress_len(limits.max_chunk_bytes) as u64;
        if declared > max {
            return Err(ReadErrorKind::limit("compressed chunk bytes", declared, max));
        }
        self.compressed.clear();
        // `take` grows the buffer as bytes arrive, so a truncated file that declares a large
        // chunk does not allocate all of it.
        let got = self.reader.by_ref().take(declared).read_to_end(self.compressed).map_err(ReadErrorKind::Io)? as u64;
        if got < declared {
            return Err(ReadErrorKind::TruncatedChunk { declared, got });
        }
        let length = snap::raw::decompress_len(self.compressed).map_err(ReadErrorKind::Snappy)?;
        if length > limits.max_chunk_bytes {
            return Err(ReadErrorKind::limit("uncompressed chunk bytes", length as u64, limits.max_chunk_bytes));
        }
        check_stream_length(limits, stream_offset, length)?;
        out.resize(length, 0);
        self.decoder.decompress(self.compressed, out).map_err(ReadErrorKind::Snappy)?;
        *self.file_offset += 4 + declared;
        Ok(true)
    }
}

fn check_stream_length(limits: &Limits, stream_offset: u64, more: usize) -> Result<(), ReadErrorKind> {
    let total = stream_offset + more as u64;
    if total > limits.max_stream_bytes {
        return Err(ReadErrorKind::limit("uncompressed stream bytes", total, limits.max_stream_bytes));
    }
    Ok(())
}
