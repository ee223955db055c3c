//! Large buffers backed by transparent huge pages where the kernel has them.
//!
//! A first write to a fresh 4 KiB page is a page fault: 2.2 µs each on the machines tiler is
//! measured on, ten times the cost of writing the page once it is there. A render target, a
//! shadow map or a binned frame's records are megabytes written for the first time, so their
//! faults were milliseconds of a short replay; advised for huge pages, a 2 MiB page costs one
//! fault (docs/benchmarking.md, "Page faults").

/// Buffers this large or larger are advised for transparent huge pages; the size of such a
/// page on x86-64.
pub(crate) const HUGE_PAGE_BYTES: usize = 2 << 20;

/// `len` zero bytes, the whole 2 MiB pages within them advised for transparent huge pages
/// (when `len` is at least [`HUGE_PAGE_BYTES`]) before anything is written to them.
pub(crate) fn zeroed_bytes(len: usize) -> Vec<u8> {
    let mut bytes = vec![0u8; len];
    if len >= HUGE_PAGE_BYTES {
        advise_huge_pages(bytes.as_mut_ptr(), len);
    }
    bytes
}

/// Asks the kernel to back the whole 2 MiB pages within `bytes` from `start` with huge pages.
/// A hint: when the kernel has no transparent huge pages it says so and nothing changes.
#[cfg(target_os = "linux")]
pub(crate) fn advise_huge_pages(start: *mut u8, bytes: usize) {
    let first = (start as usize).next_multiple_of(HUGE_PAGE_BYTES);
    let end = (start as usize + bytes) & !(HUGE_PAGE_BYTES - 1);
    if first < end {
        // SAFETY: `first..end` lies inside the allocation of `bytes` bytes at `start` that the
        // caller owns, and `first` is page-aligned as `madvise` requires. `MADV_HUGEPAGE` only
        // changes how the kernel may back those pages: it changes no mapping, contents or
        // permissions (pages already there keep their bytes), so no Rust reference anywhere can
        // observe it; its failure (`EINVAL` without THP) is ignored, a hint not taken.
        unsafe {
            libc::madvise(first as *mut libc::c_void, end - first, libc::MADV_HUGEPAGE);
        }
    }
}

#[cfg(not(target_os = "linux"))]
pub(crate) fn advise_huge_pages(_start: *mut u8, _bytes: usize) {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zeroed_bytes_are_zero_whatever_their_size() {
        for len in [0, 1, 4095, HUGE_PAGE_BYTES - 1, HUGE_PAGE_BYTES, 3 * HUGE_PAGE_BYTES + 17] {
            let bytes = zeroed_bytes(len);
            assert_eq!(bytes.len(), len);
            assert!(bytes.iter().all(|&b| b == 0), "{len} bytes");
        }
    }
}
