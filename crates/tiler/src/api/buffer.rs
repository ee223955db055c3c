//! Buffers in external memory: vertex and index data.

/// The largest buffer, in bytes: 1 GiB.
pub const MAX_BUFFER_BYTES: u64 = 1 << 30;

/// A handle to a buffer owned by a [`Device`](crate::Device).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize)]
pub struct BufferId(pub(crate) u32);

impl std::fmt::Display for BufferId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "buffer {}", self.0)
    }
}
