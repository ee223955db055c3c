//! Views of an attachment for the pixel pipeline: where sample `s` of pixel `(x, y)` lives,
//! whether in a tile buffer or in a band of an image in external memory.

use crate::api::format::Format;
use crate::api::image::{Image, ImageDesc};
use crate::api::pipeline::MAX_COLOR_ATTACHMENTS;
use crate::api::render_pass::{MAX_INPUT_ATTACHMENTS, ResolvedSubpass};
use crate::raster::PixelRect;
use crate::raster::samples::{MAX_SAMPLES, SampleLocations};

/// A rectangle of one attachment, every sample plane of it: pixel `(x, y)` of sample `s` is at
/// byte `((y − origin_y) · stride + (x − origin_x)) · bytes_per_sample` of plane `s`.
pub struct Surface<'a> {
    pub format: Format,
    planes: [&'a mut [u8]; MAX_SAMPLES],
    samples: usize,
    origin_x: i32,
    origin_y: i32,
    /// Pixels per row.
    stride: usize,
    bytes_per_sample: usize,
    /// For an image in external memory: the address of this view's first byte and the bytes
    /// between sample planes (cache models need addresses).
    memory: Option<(u64, u64)>,
    /// The depth of each 8×8 block of a depth attachment in a tile buffer, when known to be one
    /// value (see [`DepthBlocks`]); `None` for other views.
    blocks: Option<DepthBlocks<'a>>,
}

/// What is known of one 8×8 block of a depth attachment in the tile buffer: every sample of
/// every pixel of the block holds depth bits in `min..=max` (stencil bits aside). The bounds
/// need not be tight; `min == max` means the block holds that one value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlockDepth {
    pub min: u32,
    pub max: u32,
}

impl BlockDepth {
    /// Nothing known: the samples may hold any depth (test them one by one).
    pub const UNKNOWN: BlockDepth = BlockDepth { min: 0, max: u32::MAX };

    /// Every sample holds `bits`.
    pub const fn constant(bits: u32) -> BlockDepth {
        BlockDepth { min: bits, max: bits }
    }

    /// The one value every sample holds, if the bounds say so.
    pub fn value(self) -> Option<u32> {
        (self.min == self.max).then_some(self.min)
    }

    /// Bounds holding both `self`'s values and `other`'s.
    #[inline(always)]
    pub fn union(self, other: BlockDepth) -> BlockDepth {
        BlockDepth { min: self.min.min(other.min), max: self.max.max(other.max) }
    }
}

/// Per-block depth summary of a tile's depth attachment: hierarchical Z in the tile.
///
/// The sample bytes stay authoritative — load, store, resolve, input attachments and the
/// group-by-group tests read them as before, and the ledger counts the modelled GPU's accesses
/// per sample whatever the host does. The summary (a range of stored depths per block) only
/// lets a block test (`depth::test_block`) decide with one compare of the primitive's depth
/// range over the block against the block's: all covered samples fail (early-Z or HSR rejects
/// them without reading a sample), or all pass (a covering primitive of one depth fills the
/// block with one value). The depth tests keep the ranges right as they write (a block test or
/// a group test widens its block's range by what it wrote); so that no other writer can leave
/// it stale, every other mutable access to the planes ([`Surface::plane_mut`],
/// [`Surface::row_mut`]) marks the whole summary unknown until the next
/// [`Surface::start_blocks`] (the next tile's load).
///
/// **Deferred fills.** A block that a flat primitive covers and passes everywhere takes one
/// value: the summary records it (`min == max`) and marks the block *deferred* instead of
/// writing its samples, so that 32 layers drawn back to front over a block cost one write of
/// its bytes, not 32 (on TBDR overdraw the read-modify-write of D24S8 rows, which keeps the
/// stencil bits, was 13% of the time). While a block is deferred its summary is the truth and
/// its bytes are stale in the depth bits only (nothing can write its stencil bits without
/// writing the fill first). The bytes are written ([`Surface::write_deferred`]) before anything
/// reads or writes them: the depth tests of that block ([`Surface::write_deferred_block`]),
/// every other mutable access (`plane_mut`, `row_mut`, a summary forgotten), and the tile task
/// after each subpass, before input attachments, stores, resolves and signatures read the tile
/// through shared references ([`Surface::plane`] and [`Surface::row`] check it in debug builds).
///
/// Measured on SCENES.md overdraw (TBDR, 960×540, one thread, callgrind) — see
/// docs/benchmarking.md, "TBDR overdraw: block-constant depth".
pub struct DepthBlocks<'a> {
    states: &'a mut [BlockDepth],
    /// One bit per block (block `i` is bit `i % 64` of word `i / 64`): its samples' depth bits
    /// are `states[i].min`, not yet written (a deferred fill).
    deferred: &'a mut [u64],
    /// Whether a bit of `deferred` may be set (false: none is), so that the depth tests of a
    /// tile without deferred fills check one flag.
    any_deferred: bool,
    /// Blocks per row of the tile.
    columns: usize,
    /// Whether `states` describes the planes (false after an untracked write).
    valid: bool,
}

impl<'a> DepthBlocks<'a> {
    /// A summary over `states`, one per block of a tile `columns` blocks wide, not yet valid,
    /// with `deferred` ([`DepthBlocks::deferred_words`] words) for its deferred fills.
    pub fn new(states: &'a mut [BlockDepth], deferred: &'a mut [u64], columns: usize) -> DepthBlocks<'a> {
        debug_assert!(deferred.len() >= Self::deferred_words(states.len()));
        DepthBlocks { states, deferred, any_deferred: true, columns, valid: false }
    }

    /// Words of deferred-fill bits for `blocks` blocks.
    pub const fn deferred_words(blocks: usize) -> usize {
        blocks.div_ceil(64)
    }
}

impl<'a> Surface<'a> {
    /// A view of `planes` (one slice per sample) whose first byte is pixel `origin`.
    pub fn new(
        format: Format,
        origin: (i32, i32),
        stride: usize,
        planes: impl IntoIterator<Item = &'a mut [u8]>,
    ) -> Surface<'a> {
        let mut array: [&'a mut [u8]; MAX_SAMPLES] = Default::default();
        let mut samples = 0;
        for (slot, plane) in array.iter_mut().zip(planes) {
            *slot = plane;
            samples += 1;
        }
        Surface {
            format,
            planes: array,
            samples,
            origin_x: origin.0,
            origin_y: origin.1,
            stride,
            bytes_per_sample: format.bytes_per_sample(),
            memory: None,
            blocks: None,
        }
    }

    /// Gives a tile's depth view its per-block summary (tiles whose width and height are
    /// multiples of 8, so blocks start at multiples of 8 from the origin).
    pub fn with_blocks(self, blocks: DepthBlocks<'a>) -> Surface<'a> {
        debug_assert!(self.format.has_depth());
        Surface { blocks: Some(blocks), ..self }
    }

    /// Restarts the block summary after a load of `rect`: blocks wholly inside it hold
    /// `depth_bits` when every sample was set to them, the others are unknown. No-op for
    /// views without a summary.
    pub fn start_blocks(&mut self, rect: &PixelRect, depth_bits: Option<u32>) {
        let (origin_x, origin_y) = (self.origin_x, self.origin_y);
        let Some(blocks) = self.blocks.as_mut() else { return };
        for (i, state) in blocks.states.iter_mut().enumerate() {
            let x = origin_x + 8 * (i % blocks.columns) as i32;
            let y = origin_y + 8 * (i / blocks.columns) as i32;
            let inside = x >= rect.x0 && y >= rect.y0 && x + 8 <= rect.x1 && y + 8 <= rect.y1;
            *state = match depth_bits {
                Some(bits) if inside => BlockDepth::constant(bits),
                _ => BlockDepth::UNKNOWN,
            };
        }
        // The load wrote every byte: no fill is owed.
        blocks.deferred.fill(0);
        blocks.any_deferred = false;
        blocks.valid = true;
    }

    /// Records that every sample of block `index` (from [`Surface::block_depth`], wholly in
    /// the view) now holds depth bits `bits`, stencil bits unchanged, without writing them: the
    /// fill is written when the bytes are next used (see [`DepthBlocks`]).
    #[inline(always)]
    pub(crate) fn defer_fill(&mut self, index: usize, bits: u32) {
        if let Some(blocks) = self.blocks.as_mut() {
            blocks.states[index] = BlockDepth::constant(bits);
            blocks.deferred[index / 64] |= 1 << (index % 64);
            blocks.any_deferred = true;
        }
    }

    /// Writes the deferred fill of the block holding the 8×8 block or the 4×2 group at
    /// `(x, y)`, if it has one (every deferred fill, if that is not inside one block of the
    /// summary): before the depth tests read or write its samples through
    /// [`Surface::plane_mut_tracked`].
    #[inline(always)]
    pub(crate) fn write_deferred_block(&mut self, x: i32, y: i32) {
        if self.blocks.as_ref().is_some_and(|b| b.any_deferred) {
            self.write_deferred_block_slow(x, y);
        }
    }

    #[cold]
    #[inline(never)]
    fn write_deferred_block_slow(&mut self, x: i32, y: i32) {
        let (origin_x, origin_y) = (self.origin_x, self.origin_y);
        let Some(blocks) = self.blocks.as_ref() else { return };
        let (dx, dy) = (x.wrapping_sub(origin_x) as u32, y.wrapping_sub(origin_y) as u32);
        let column = (dx >> 3) as usize;
        let index = (dy >> 3) as usize * blocks.columns + column;
        // (A block starts at a multiple of 8, a group inside one at most 4 columns and 6 rows
        // further.)
        if dx & 7 > 4 || dy & 7 > 6 || column >= blocks.columns || index >= blocks.states.len() {
            self.write_deferred();
            return;
        }
        let (word, bit) = (index / 64, 1u64 << (index % 64));
        if blocks.deferred[word] & bit != 0 {
            self.write_deferred_fill(index);
        }
    }

    /// Writes the deferred fill of block `index` (from [`Surface::block_depth`]), if it has one.
    #[inline(always)]
    pub(crate) fn write_deferred_index(&mut self, index: usize) {
        if let Some(blocks) = self.blocks.as_ref()
            && blocks.any_deferred
            && blocks.deferred[index / 64] >> (index % 64) & 1 != 0
        {
            self.write_deferred_fill(index);
        }
    }

    /// Writes every deferred fill (see [`DepthBlocks`]): after it the bytes hold what the
    /// summary says. The tile task calls it after each subpass.
    pub fn write_deferred(&mut self) {
        let Some(blocks) = self.blocks.as_ref().filter(|b| b.any_deferred) else { return };
        for word in 0..blocks.deferred.len() {
            // Each fill clears its own bit.
            while let Some(blocks) = self.blocks.as_ref()
                && blocks.deferred[word] != 0
            {
                let index = word * 64 + blocks.deferred[word].trailing_zeros() as usize;
                self.write_deferred_fill(index);
            }
        }
        if let Some(blocks) = self.blocks.as_mut() {
            blocks.any_deferred = false;
        }
    }

    /// Writes block `index`'s deferred fill and clears its bit.
    #[cold]
    #[inline(never)]
    fn write_deferred_fill(&mut self, index: usize) {
        let Some(blocks) = self.blocks.as_mut() else { return };
        blocks.deferred[index / 64] &= !(1 << (index % 64));
        let bits = blocks.states[index].min;
        let x = self.origin_x + 8 * (index % blocks.columns) as i32;
        let y = self.origin_y + 8 * (index / blocks.columns) as i32;
        self.fill_depth_block(x, y, bits);
    }

    /// Writes depth `bits` to every sample of the 8×8 block at `(x, y)` (wholly in the view),
    /// stencil bits kept: what `depth::test_block` would have written had every sample taken
    /// the one depth then.
    fn fill_depth_block(&mut self, x: i32, y: i32, bits: u32) {
        let first = self.offset(x, y);
        let pitch = self.stride * self.bytes_per_sample;
        let planes = &mut self.planes[..self.samples];
        // Depth in the low bits of a little-endian word (D24S8: the stencil byte above it is
        // kept).
        match self.format {
            Format::D16Unorm => fill_depth_rows::<2>(planes, first, pitch, bits, 0xffff),
            Format::D24UnormS8Uint => fill_depth_rows::<4>(planes, first, pitch, bits, 0x00ff_ffff),
            _ => fill_depth_rows::<4>(planes, first, pitch, bits, u32::MAX),
        }
    }

    /// Whether some block's fill is deferred.
    pub(crate) fn has_deferred(&self) -> bool {
        self.blocks.as_ref().is_some_and(|b| b.any_deferred && b.deferred.iter().any(|w| *w != 0))
    }

    /// The index and summary of the block whose top-left pixel is `(x, y)`, when the view
    /// has a valid summary and that is a block of it.
    #[inline(always)]
    pub fn block_depth(&self, x: i32, y: i32) -> Option<(usize, BlockDepth)> {
        let blocks = self.blocks.as_ref().filter(|b| b.valid)?;
        // Left of or above the origin wraps to a huge offset, which the bounds below reject.
        let (dx, dy) = (x.wrapping_sub(self.origin_x) as u32, y.wrapping_sub(self.origin_y) as u32);
        if (dx | dy) & 7 != 0 {
            return None;
        }
        let column = (dx >> 3) as usize;
        if column >= blocks.columns {
            return None;
        }
        let index = (dy >> 3) as usize * blocks.columns + column;
        blocks.states.get(index).map(|state| (index, *state))
    }

    /// Records what block `index` (from [`Surface::block_depth`]) now holds.
    #[inline(always)]
    pub fn set_block_depth(&mut self, index: usize, state: BlockDepth) {
        if let Some(blocks) = self.blocks.as_mut() {
            blocks.states[index] = state;
        }
    }

    /// Notes that the depth tests wrote samples of the 8×8 block at `(x, y)`, with depth bits
    /// within `written` (`None`: not known): its range widens to hold them (the whole summary
    /// becomes unknown if that is not a block of it).
    #[inline(always)]
    pub(crate) fn block_written(&mut self, x: i32, y: i32, written: Option<BlockDepth>) {
        match self.block_depth(x, y) {
            Some((index, known)) => {
                self.set_block_depth(index, written.map_or(BlockDepth::UNKNOWN, |w| known.union(w)))
            }
            None => self.forget_blocks(),
        }
    }

    /// Notes that the depth tests wrote depth bits within `written` to samples of the 4×2 group
    /// at `(x, y)`: the range of the block holding it widens to hold them (the whole summary
    /// becomes unknown if the group is not inside one block of it).
    #[inline(always)]
    pub(crate) fn group_written(&mut self, x: i32, y: i32, written: BlockDepth) {
        let (origin_x, origin_y) = (self.origin_x, self.origin_y);
        let Some(blocks) = self.blocks.as_mut().filter(|b| b.valid) else { return };
        let (dx, dy) = (x.wrapping_sub(origin_x) as u32, y.wrapping_sub(origin_y) as u32);
        let column = (dx >> 3) as usize;
        let index = (dy >> 3) as usize * blocks.columns + column;
        if dx & 7 <= 4 && dy & 7 <= 6 && column < blocks.columns && index < blocks.states.len() {
            blocks.states[index] = blocks.states[index].union(written);
        } else {
            self.forget_blocks();
        }
    }

    /// Marks the block summary unknown (until the next [`Surface::start_blocks`]), once the
    /// deferred fills it holds are written.
    #[inline(always)]
    fn forget_blocks(&mut self) {
        // (Colour views have no summary: one test, no call, for each of their writes.)
        if self.blocks.as_ref().is_some_and(|b| b.any_deferred) {
            self.write_deferred();
        }
        if let Some(blocks) = self.blocks.as_mut() {
            blocks.valid = false;
        }
    }

    /// Plane `sample` for the depth tests, which keep the block summary right themselves: each
    /// caller writes the deferred fill of the block it touches first
    /// ([`Surface::write_deferred_block`]) and sets [`Surface::set_block_depth`] for the blocks
    /// it writes, or [`Surface::plane_mut`] is the accessor to use.
    #[inline(always)]
    pub(crate) fn plane_mut_tracked(&mut self, sample: usize) -> &mut [u8] {
        self.planes[sample]
    }

    /// Gives the view addresses: its first byte is at `base`, planes `plane_bytes` apart.
    pub fn with_memory(self, base: u64, plane_bytes: u64) -> Surface<'a> {
        Surface { memory: Some((base, plane_bytes)), ..self }
    }

    /// The external-memory address of sample `s` of pixel `(x, y)` (0 for on-chip views).
    #[inline(always)]
    pub fn address(&self, sample: usize, x: i32, y: i32) -> u64 {
        match self.memory {
            Some((base, plane)) => base + sample as u64 * plane + self.offset(x, y) as u64,
            None => 0,
        }
    }

    pub fn samples(&self) -> usize {
        self.samples
    }

    pub fn bytes_per_sample(&self) -> usize {
        self.bytes_per_sample
    }

    /// Byte offset of pixel `(x, y)` within a plane.
    #[inline(always)]
    pub fn offset(&self, x: i32, y: i32) -> usize {
        debug_assert!(x >= self.origin_x && y >= self.origin_y);
        ((y - self.origin_y) as usize * self.stride + (x - self.origin_x) as usize) * self.bytes_per_sample
    }

    /// Plane `sample`, to read (no deferred fill may be pending: see [`DepthBlocks`]).
    #[inline(always)]
    pub fn plane(&self, sample: usize) -> &[u8] {
        debug_assert!(!self.has_deferred(), "a deferred depth fill was not written before a read");
        self.planes[sample]
    }

    /// Plane `sample`, to write: the block summary (if any) becomes unknown.
    #[inline(always)]
    pub fn plane_mut(&mut self, sample: usize) -> &mut [u8] {
        self.forget_blocks();
        self.planes[sample]
    }

    /// The bytes of pixels `x0..x1` of row `y` in plane `sample`.
    #[inline]
    pub fn row(&self, sample: usize, y: i32, x0: i32, x1: i32) -> &[u8] {
        debug_assert!(!self.has_deferred(), "a deferred depth fill was not written before a read");
        let start = self.offset(x0, y);
        &self.planes[sample][start..start + (x1 - x0) as usize * self.bytes_per_sample]
    }

    #[inline]
    pub fn row_mut(&mut self, sample: usize, y: i32, x0: i32, x1: i32) -> &mut [u8] {
        self.forget_blocks();
        let start = self.offset(x0, y);
        let len = (x1 - x0) as usize * self.bytes_per_sample;
        &mut self.planes[sample][start..start + len]
    }

    /// Whether columns `x0..x1` all lie in this view's rows.
    #[inline(always)]
    pub fn holds_columns(&self, x0: i32, x1: i32) -> bool {
        x0 >= self.origin_x && x1 <= self.origin_x + self.stride as i32
    }

    /// Whether pixel `(x, y)` lies in this view.
    #[inline(always)]
    pub fn contains(&self, x: i32, y: i32) -> bool {
        let rows = self.planes[0].len() / (self.stride * self.bytes_per_sample).max(1);
        x >= self.origin_x
            && y >= self.origin_y
            && ((x - self.origin_x) as usize) < self.stride
            && ((y - self.origin_y) as usize) < rows
    }

    /// Whether this view is of external memory (an image), not of the tile buffer.
    pub fn is_external(&self) -> bool {
        self.memory.is_some()
    }
}

/// Writes `bits` into the `depth_mask` bits of the `BYTES`-byte little-endian samples of eight
/// rows of eight, `pitch` bytes apart from byte `first`, in every plane.
fn fill_depth_rows<const BYTES: usize>(
    planes: &mut [&mut [u8]],
    first: usize,
    pitch: usize,
    bits: u32,
    depth_mask: u32,
) {
    for plane in planes {
        for row in 0..8 {
            let start = first + row * pitch;
            for stored in plane[start..start + 8 * BYTES].chunks_exact_mut(BYTES) {
                let mut word = [0u8; 4];
                word[..BYTES].copy_from_slice(stored);
                let word = (u32::from_le_bytes(word) & !depth_mask) | bits;
                stored.copy_from_slice(&word.to_le_bytes()[..BYTES]);
            }
        }
    }
}

/// What the pixel pipeline reads and writes for one primitive of a subpass, and where it may
/// write: the subpass's colour outputs and depth-stencil attachment, and its input attachments
/// (read only), borrowed from a tile's (or a band's) views of every attachment of the pass.
pub struct RenderTarget<'t, 'a> {
    pub color: [Option<&'t mut Surface<'a>>; MAX_COLOR_ATTACHMENTS],
    pub depth_stencil: Option<&'t mut Surface<'a>>,
    pub inputs: [Option<&'t Surface<'a>>; MAX_INPUT_ATTACHMENTS],
    pub samples: SampleLocations,
    /// The pixels this target holds (a tile, or a band of the framebuffer) ∩ the render area.
    pub clip: PixelRect,
    /// Whether depth and stencil tests may run before shading (the device's early-Z).
    pub early_z: bool,
}

impl<'t, 'a> RenderTarget<'t, 'a> {
    /// The target of `subpass` over `surfaces`, one view per attachment of the pass.
    pub fn for_subpass(
        surfaces: &'t mut [Surface<'a>],
        subpass: &ResolvedSubpass,
        samples: SampleLocations,
        clip: PixelRect,
        early_z: bool,
    ) -> RenderTarget<'t, 'a> {
        let mut color: [Option<&'t mut Surface<'a>>; MAX_COLOR_ATTACHMENTS] = Default::default();
        let mut depth_stencil = None;
        let mut inputs: [Option<&'t Surface<'a>>; MAX_INPUT_ATTACHMENTS] = Default::default();
        for (index, surface) in surfaces.iter_mut().enumerate() {
            if let Some(slot) = subpass.color.iter().position(|c| *c == index) {
                color[slot] = Some(surface);
            } else if subpass.depth_stencil == Some(index) {
                depth_stencil = Some(surface);
            } else if let Some(slot) = subpass.inputs.iter().position(|c| *c == index) {
                inputs[slot] = Some(surface);
            }
        }
        RenderTarget { color, depth_stencil, inputs, samples, clip, early_z }
    }
}

/// Cuts an image into bands of `rows` rows: for each band, one slice per sample plane.
/// A transient image (no memory) gives no bands.
pub fn image_bands(image: &mut Image, rows: usize) -> Vec<Vec<&mut [u8]>> {
    data_bands(&image.desc, &mut image.data, rows)
}

/// [`image_bands`] over an image's description and data, borrowed apart.
pub fn data_bands<'a>(desc: &ImageDesc, data: &'a mut [u8], rows: usize) -> Vec<Vec<&'a mut [u8]>> {
    if data.is_empty() || desc.transient {
        return Vec::new();
    }
    let plane = desc.plane_bytes();
    let band_bytes = desc.width as usize * desc.format.bytes_per_sample() * rows;
    let mut planes: Vec<_> = data.chunks_mut(plane).map(|p| p.chunks_mut(band_bytes)).collect();
    let bands = (desc.height as usize).div_ceil(rows);
    (0..bands).map(|_| planes.iter_mut().map(|p| p.next().expect("band")).collect()).collect()
}

/// A surface over one band of an image.
pub fn band_surface<'a>(image_format: Format, width: u32, band_y0: i32, slices: Vec<&'a mut [u8]>) -> Surface<'a> {
    Surface::new(image_format, (0, band_y0), width as usize, slices)
}
