//! The errors tiler reports for bad input: each names what is wrong and where.

/// What went wrong, and where. Every check happens once, where input enters tiler (image and
/// buffer creation, pipeline creation, render-pass submission); past that point the phases
/// cannot fail.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    #[error("image size {width}×{height} is invalid: {reason}")]
    ImageSize { width: u32, height: u32, reason: String },

    #[error("{samples} samples per pixel is not supported (use 1, 2, 4, 8 or 16)")]
    SampleCount { samples: u32 },

    #[error("{what}: {reason}")]
    Invalid { what: String, reason: String },

    #[error("draw {draw}: {reason}")]
    Draw { draw: usize, reason: String },

    #[error(
        "draw {draw}: index {index} at position {position} of the index buffer is out of range \
         for {vertex_count} vertices"
    )]
    IndexOutOfRange { draw: usize, position: u64, index: u32, vertex_count: u64 },

    #[error("draw {draw}, vertex {vertex}: the vertex shader wrote a non-finite position {position:?}")]
    NonFinitePosition { draw: usize, vertex: u32, position: [f32; 4] },
}

impl Error {
    /// An `Invalid` error about `what`.
    pub fn invalid(what: impl Into<String>, reason: impl Into<String>) -> Error {
        Error::Invalid { what: what.into(), reason: reason.into() }
    }

    pub(crate) fn draw(draw: usize, reason: impl Into<String>) -> Error {
        Error::Draw { draw, reason: reason.into() }
    }
}

pub type Result<T, E = Error> = std::result::Result<T, E>;
