//! The apitrace wire format: container, header, events, signatures and values.
//!
//! See the crate documentation for the format as implemented.

mod error;
mod limits;
mod parser;
mod source;
mod value;

pub use error::{ChunkLocation, Location, ReadError, ReadErrorKind};
pub use limits::Limits;
pub use parser::{Header, MAX_VERSION, TraceReader};
pub use source::Compression;
pub use value::{BitmaskSig, Call, CallFlags, EnumSig, FunctionSig, StackFrame, StructSig, Value};
