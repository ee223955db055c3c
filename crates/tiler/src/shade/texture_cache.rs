//! The texture cache model: which texel reads reach external memory.
//!
//! A set-associative cache with least-recently-used replacement, in front of every texture
//! read of a shading task. The ledger's `TextureFetch` category is counted from it, once per
//! task (`pixel::pipeline`):
//!
//! ```text
//! TextureFetch bytes = cache misses × line size
//! ```
//!
//! so it reports the bytes fetched from external memory, not the texels touched: a magnified
//! texture costs each line once, a minified one without mip maps costs a line for almost every
//! texel read.
//!
//! Addresses are modelled, not host pointers: texture `id` at `id · 2^40`, its levels one after
//! another, each level in blocks in row-major order, as its format stores it
//! (`Texture::texel_address`, `texel_format::StoredLayout`): 4×4-texel blocks of uncompressed
//! texels (64 bytes for RGBA8, 32 for RGB565, 256 for RGBA32F), or the compressed blocks of
//! ETC2 (4×4 texels in 8 or 16 bytes) and ASTC (16 bytes for its footprint), each read whole by
//! any of its texels. Storing textures in blocks is what GPUs do (block-linear or
//! Morton layouts) so that a cache line holds a square of texels, not a thin row.
//!
//! Every task (a band of tiles on a tiler, a band of rows for one draw in immediate mode) starts
//! with a cold cache of its own, so the counts depend only on the task's work, never on the
//! thread that ran it or on the order tasks ran in. Texture ids only make tags unique: any
//! distinct ids give the same counts.
//!
//! The default geometry, 16 KiB, 64-byte lines, 4 ways, is in the range of the per-core L1
//! texture caches of mobile GPUs (Mali-G7x: 16 KiB per core; Adreno 6xx: 8–16 KiB).

use crate::api::error::{Error, Result};

/// The most lines one lane of a quad reads ([`TextureCache::access_quad`]): four texels on
/// each of two levels.
pub const MAX_LANE_LINES: usize = 8;

/// The shape of the texture cache.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct TextureCacheConfig {
    /// Capacity in bytes.
    pub size_bytes: u32,
    /// Bytes per line: the unit fetched from external memory on a miss.
    pub line_bytes: u32,
    /// Lines per set (1 = direct mapped; `size_bytes / line_bytes` = fully associative).
    pub ways: u32,
}

impl Default for TextureCacheConfig {
    fn default() -> TextureCacheConfig {
        TextureCacheConfig::DEFAULT
    }
}

impl TextureCacheConfig {
    /// 16 KiB, 64-byte lines, 4-way set associative (see the module notes).
    pub const DEFAULT: TextureCacheConfig = TextureCacheConfig { size_bytes: 16 << 10, line_bytes: 64, ways: 4 };

    /// The number of sets.
    pub fn sets(&self) -> u32 {
        (self.size_bytes as u64 / (self.line_bytes as u64 * self.ways as u64).max(1)) as u32
    }

    /// Checks the shape: powers of two, lines of 4 bytes to 4 KiB, 1 to 64 ways, at least one
    /// set, at most 64 MiB.
    ///
    /// # Errors
    /// Any of the above broken, naming the value.
    pub fn validate(&self) -> Result<()> {
        let what = "texture cache";
        let TextureCacheConfig { size_bytes, line_bytes, ways } = *self;
        if !line_bytes.is_power_of_two() || !(4..=4096).contains(&line_bytes) {
            return Err(Error::invalid(what, format!("line size {line_bytes} must be a power of two from 4 to 4096")));
        }
        if !ways.is_power_of_two() || ways > 64 {
            return Err(Error::invalid(what, format!("{ways} ways must be a power of two from 1 to 64")));
        }
        if !size_bytes.is_power_of_two()
            || size_bytes > 64 << 20
            || (size_bytes as u64) < line_bytes as u64 * ways as u64
        {
            return Err(Error::invalid(
                what,
                format!(
                    "size {size_bytes} must be a power of two of at least one set ({line_bytes} × {ways} bytes) and at most 64 MiB"
                ),
            ));
        }
        Ok(())
    }
}

/// The cache state of one task: tags per set, most recently used first, and the counts.
#[derive(Clone, Debug)]
pub struct TextureCache {
    config: TextureCacheConfig,
    line_shift: u32,
    /// `log2(ways)`: a set's lines start at `set << ways_shift`.
    ways_shift: u32,
    set_mask: u64,
    /// `sets × ways` line addresses, each set's most recently used first; `EMPTY` when unused.
    /// Allocated on the first access, so tasks that sample nothing cost nothing.
    lines: Vec<u64>,
    hits: u64,
    misses: u64,
    /// Misses already handed to the ledger.
    misses_reported: u64,
    /// Quads read from level 0 minified more than 2× by a sampler without mip maps, and the
    /// misses their reads caused ([`TextureCache::note_unmipped`]): what mip maps would save.
    unmipped_quads: u64,
    unmipped_misses: u64,
    /// With the `texture-cache-reference` feature (for tests): the same cache read one line
    /// at a time, as the model was first written, held equal after every quad.
    #[cfg(feature = "texture-cache-reference")]
    reference: Option<Box<TextureCache>>,
}

impl Default for TextureCache {
    fn default() -> TextureCache {
        TextureCache::new(TextureCacheConfig::DEFAULT)
    }
}

impl TextureCache {
    const EMPTY: u64 = u64::MAX;

    /// A cold cache.
    ///
    /// # Panics
    /// If `config` is invalid (check it with [`TextureCacheConfig::validate`] first).
    pub fn new(config: TextureCacheConfig) -> TextureCache {
        assert!(config.validate().is_ok(), "invalid texture cache configuration {config:?}");
        #[allow(unused_mut)] // Changed with the `texture-cache-reference` feature only.
        let mut cache = TextureCache {
            config,
            line_shift: config.line_bytes.trailing_zeros(),
            ways_shift: config.ways.trailing_zeros(),
            set_mask: config.sets() as u64 - 1,
            lines: Vec::new(),
            hits: 0,
            misses: 0,
            misses_reported: 0,
            unmipped_quads: 0,
            unmipped_misses: 0,
            #[cfg(feature = "texture-cache-reference")]
            reference: None,
        };
        #[cfg(feature = "texture-cache-reference")]
        {
            cache.reference = Some(Box::new(cache.clone()));
        }
        cache
    }

    pub fn config(&self) -> &TextureCacheConfig {
        &self.config
    }

    /// Reads the byte at modelled address `address`; returns whether it hit.
    #[inline]
    pub fn access(&mut self, address: u64) -> bool {
        let hit = self.access_line(address >> self.line_shift);
        self.count(1, !hit as u64);
        #[cfg(feature = "texture-cache-reference")]
        if let Some(reference) = &mut self.reference {
            reference.access(address);
        }
        hit
    }

    /// Counts `reads` reads of which `misses` missed.
    #[inline(always)]
    fn count(&mut self, reads: u64, misses: u64) {
        self.hits += reads - misses;
        self.misses += misses;
    }

    /// `log2` of the line size: the line of modelled address `a` is `a >> line_shift()`.
    #[inline(always)]
    pub fn line_shift(&self) -> u32 {
        self.line_shift
    }

    /// Reads one byte of each line `first_line + lines[i]` in order (line numbers: see
    /// [`TextureCache::line_shift`]): the same as [`TextureCache::access`] of an address in each.
    /// A line equal to the one before it is a hit that changes nothing — the access before left
    /// it most recently used in its set — and costs one comparison: texels next to each other
    /// usually share a line.
    #[inline]
    pub fn access_lines(&mut self, first_line: u64, lines: &[u32]) {
        let misses = self.read_lines(first_line, lines);
        self.count(lines.len() as u64, misses);
        #[cfg(feature = "texture-cache-reference")]
        if let Some(reference) = &mut self.reference {
            for &line in lines {
                reference.access((first_line + line as u64) << reference.line_shift);
            }
        }
    }

    /// [`Self::access_lines`] without counting: returns the misses. (Counts kept in registers
    /// by the callers, not incremented in memory read after read.)
    #[inline(always)]
    fn read_lines(&mut self, first_line: u64, lines: &[u32]) -> u64 {
        let (mut previous, mut misses) = (None, 0);
        for &line in lines {
            if previous != Some(line) {
                misses += !self.access_line(first_line + line as u64) as u64;
                previous = Some(line);
            }
        }
        misses
    }

    /// Reads the lines of a quad's `counted` lanes, lane after lane, each lane `k` reading
    /// `rows[0][k]`, `rows[1][k]`, … in order (a row per texel a lane reads: the corners of its
    /// footprint on a level, level after level): the same as [`TextureCache::access_lines`] of
    /// each lane's lines in turn, with one comparison for a lane that reads what the lane
    /// before it read.
    ///
    /// Why that is exact: once a run of lines has been read, each of its lines is among the
    /// run's lines at the front of its set, in the order of their last reads — as long as no
    /// set holds more of the run's lines than it has ways, none falls out. Reading the same run
    /// again then hits every time and leaves every set as it was. Neighbouring pixels usually
    /// read the same texels' lines: most lanes cost a comparison instead of a tag check per
    /// texel.
    ///
    /// The row counts the sampler reads (one texel, four, on one level or two) each get a copy
    /// with the count known, whose loops the compiler unrolls.
    #[inline]
    pub fn access_quad(&mut self, first_line: u64, rows: &[[u32; 4]], counted: [bool; 4]) {
        self.access_lanes(first_line, rows, counted);
    }

    /// [`TextureCache::access_quad`] of `L` lanes: a quad's four, or a pair of quads' eight
    /// (quad 0's lanes, then quad 1's), the same reads in the same order.
    #[inline]
    pub fn access_lanes<const L: usize>(&mut self, first_line: u64, rows: &[[u32; L]], counted: [bool; L]) {
        debug_assert!(rows.len() <= MAX_LANE_LINES);
        let misses = if let Ok(rows) = <&[[u32; L]; 4]>::try_from(rows) {
            self.read_quad(first_line, rows, counted)
        } else if let Ok(rows) = <&[[u32; L]; 8]>::try_from(rows) {
            self.read_quad(first_line, rows, counted)
        } else if let Ok(rows) = <&[[u32; L]; 1]>::try_from(rows) {
            self.read_quad(first_line, rows, counted)
        } else if let Ok(rows) = <&[[u32; L]; 2]>::try_from(rows) {
            self.read_quad(first_line, rows, counted)
        } else {
            self.read_quad(first_line, rows, counted)
        };
        let reads = counted.iter().filter(|&&counted| counted).count() as u64 * rows.len() as u64;
        self.count(reads, misses);
        #[cfg(feature = "texture-cache-reference")]
        if let Some(reference) = &mut self.reference {
            for lane in (0..L).filter(|&lane| counted[lane]) {
                for row in rows {
                    reference.access((first_line + row[lane] as u64) << reference.line_shift);
                }
            }
            assert_eq!(
                (self.hits, self.misses, &self.lines),
                (reference.hits, reference.misses, &reference.lines),
                "the texture cache model disagrees with its line-by-line reference"
            );
        }
    }

    /// [`Self::access_lanes`] without counting: returns the misses.
    #[inline(always)]
    fn read_quad<const L: usize>(&mut self, first_line: u64, rows: &[[u32; L]], counted: [bool; L]) -> u64 {
        // The lane read before, and whether its lines fit in their sets: it read no more runs
        // of a line than the sets have ways (so no more distinct lines either). When they may
        // not, the next lane is read line by line, repeated or not.
        let mut previous: Option<(usize, bool)> = None;
        let mut misses = 0;
        for lane in (0..L).filter(|&lane| counted[lane]) {
            if let Some((before, true)) = previous
                && rows.iter().all(|row| row[lane] == row[before])
            {
                continue;
            }
            let (lane_misses, runs) = self.read_lane(first_line, rows, lane);
            misses += lane_misses;
            previous = Some((lane, runs <= self.config.ways as usize));
        }
        misses
    }

    /// [`Self::read_lines`] of lane `lane` of `rows` (see [`Self::access_quad`]): returns the
    /// misses and the runs of a line read.
    #[inline(always)]
    fn read_lane<const L: usize>(&mut self, first_line: u64, rows: &[[u32; L]], lane: usize) -> (u64, usize) {
        let (mut previous, mut misses, mut runs) = (None, 0, 0);
        for row in rows {
            let line = row[lane];
            if previous != Some(line) {
                misses += !self.access_line(first_line + line as u64) as u64;
                runs += 1;
                previous = Some(line);
            }
        }
        (misses, runs)
    }

    /// Reads line `line`; returns whether it hit (uncounted: the callers count). The hit on
    /// the set's most recently used line changes no state and is the common case, inline; the
    /// rest is [`Self::access_slow`].
    #[inline(always)]
    fn access_line(&mut self, line: u64) -> bool {
        let first = ((line & self.set_mask) as usize) << self.ways_shift;
        // An empty `lines` (a cold cache not yet allocated) takes the slow path too.
        if self.lines.get(first) == Some(&line) {
            return true;
        }
        self.access_slow(first, line)
    }

    /// [`Self::access_line`] past its fast path: moves `line` to the front of its set, each line
    /// before it one place back; when it was not in the set, the least recently used (the
    /// last) line falls out: a miss.
    #[inline(never)]
    fn access_slow(&mut self, first: usize, line: u64) -> bool {
        if self.lines.is_empty() {
            self.allocate();
        }
        let set = &mut self.lines[first..first + self.config.ways as usize];
        // The second most recently used line of the set is the common case here: two lines
        // read in turn (a block and the one below it share a set in textures 256 texels wide
        // or more).
        if set.get(1) == Some(&line) {
            set.swap(0, 1);
            return true;
        }
        let mut moving = line;
        for entry in set {
            let was = std::mem::replace(entry, moving);
            if was == line {
                return true;
            }
            moving = was;
        }
        false
    }

    /// Allocates a cold cache's lines, all empty.
    #[cold]
    #[inline(never)]
    fn allocate(&mut self) {
        self.lines = vec![Self::EMPTY; self.config.sets() as usize * self.config.ways as usize];
    }

    pub fn hits(&self) -> u64 {
        self.hits
    }

    pub fn misses(&self) -> u64 {
        self.misses
    }

    /// Counts the quad just read as minified without mip maps: one quad, and the misses since
    /// `misses_before` (what [`TextureCache::misses`] was before its reads).
    pub fn note_unmipped(&mut self, misses_before: u64) {
        self.unmipped_quads += 1;
        self.unmipped_misses += self.misses - misses_before;
    }

    /// Quads read minified more than 2× without mip maps ([`TextureCache::note_unmipped`])
    /// since the last call, and the bytes they fetched from external memory (their misses ×
    /// line size).
    pub fn take_unmipped(&mut self) -> (u64, u64) {
        let taken = (self.unmipped_quads, self.unmipped_misses * self.config.line_bytes as u64);
        (self.unmipped_quads, self.unmipped_misses) = (0, 0);
        taken
    }

    /// Bytes fetched from external memory since the last call: `misses × line size`.
    pub fn take_fetched_bytes(&mut self) -> u64 {
        let new = self.misses - self.misses_reported;
        self.misses_reported = self.misses;
        new * self.config.line_bytes as u64
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    #[test]
    fn default_config_is_valid() {
        assert!(TextureCacheConfig::DEFAULT.validate().is_ok());
        assert_eq!(TextureCacheConfig::DEFAULT.sets(), 64);
    }

    #[test]
    fn invalid_configs_are_refused() {
        let bad = [
            TextureCacheConfig { size_bytes: 1000, line_bytes: 64, ways: 4 },
            TextureCacheConfig { size_bytes: 16384, line_bytes: 48, ways: 4 },
            TextureCacheConfig { size_bytes: 16384, line_bytes: 64, ways: 3 },
            TextureCacheConfig { size_bytes: 128, line_bytes: 64, ways: 4 },
        ];
        for config in bad {
            assert!(config.validate().is_err(), "{config:?}");
        }
    }

    #[test]
    fn a_line_is_fetched_once_while_it_stays() {
        let mut cache = TextureCache::new(TextureCacheConfig { size_bytes: 256, line_bytes: 64, ways: 2 });
        // Every byte of one line: one miss, 63 hits.
        for a in 0..64 {
            cache.access(a);
        }
        assert_eq!((cache.misses(), cache.hits()), (1, 63));
        assert_eq!(cache.take_fetched_bytes(), 64);
        assert_eq!(cache.take_fetched_bytes(), 0);
    }

    #[test]
    fn least_recently_used_line_is_evicted() {
        // 2 sets of 2 ways: lines 0, 2, 4 all map to set 0.
        let mut cache = TextureCache::new(TextureCacheConfig { size_bytes: 256, line_bytes: 64, ways: 2 });
        let line = |n: u64| n * 64;
        assert!(!cache.access(line(0)));
        assert!(!cache.access(line(2)));
        assert!(cache.access(line(0))); // 0 is now most recent, 2 least
        assert!(!cache.access(line(4))); // evicts 2
        assert!(cache.access(line(0)));
        assert!(!cache.access(line(2)));
        // The other set is untouched by all this.
        assert!(!cache.access(line(1)));
        assert_eq!(cache.misses(), 5);
        assert_eq!(cache.take_fetched_bytes(), 5 * 64);
    }

    #[test]
    fn direct_mapped_conflicts_thrash() {
        let mut cache = TextureCache::new(TextureCacheConfig { size_bytes: 128, line_bytes: 64, ways: 1 });
        for _ in 0..3 {
            cache.access(0);
            cache.access(128);
        }
        assert_eq!(cache.misses(), 6);
    }

    proptest! {
        /// Runs of lines read together count and leave the cache exactly as the reads of an
        /// address in each, one by one, whatever the shape (lines of 4 to 256 bytes, 1 to 64
        /// ways) and however often lines repeat.
        #[test]
        fn access_lines_is_access_of_each(
            shape in prop::sample::select(vec![(256u32, 64u32, 1u32), (1024, 64, 4), (512, 16, 2), (256, 4, 64), (8192, 256, 4)]),
            runs in prop::collection::vec((0u64..3, prop::collection::vec(0u32..24, 1..9)), 1..40),
        ) {
            let config = TextureCacheConfig { size_bytes: shape.0, line_bytes: shape.1, ways: shape.2 };
            let (mut together, mut one_by_one) = (TextureCache::new(config), TextureCache::new(config));
            for (texture, lines) in runs {
                let first_line = texture << 30;
                together.access_lines(first_line, &lines);
                for &line in &lines {
                    one_by_one.access((first_line + line as u64) << one_by_one.line_shift() | 3);
                }
                prop_assert_eq!((together.hits(), together.misses()), (one_by_one.hits(), one_by_one.misses()));
                prop_assert_eq!(&together.lines, &one_by_one.lines);
            }
        }

        /// A quad's (or a pair of quads') lanes read with one comparison for a lane that
        /// repeats the one before count and leave the cache exactly as the reads of an address
        /// in each line, one by one: lanes repeated or not, counted or not, more lines of a set
        /// than it has ways (lines 64 apart share a set in every shape but the fully
        /// associative one).
        #[test]
        fn access_lanes_is_access_of_each(
            shape in prop::sample::select(vec![(256u32, 64u32, 1u32), (1024, 64, 4), (512, 16, 2), (256, 4, 64), (16384, 64, 4)]),
            quads in prop::collection::vec(
                (
                    0u64..3,
                    any::<bool>(),
                    prop::sample::select(vec![1usize, 2, 4, 8]),
                    prop::collection::vec(prop_oneof![3 => 0u32..6, 1 => 0u32..200, 1 => (0u32..4).prop_map(|k| k * 64)], 16),
                    prop::collection::vec(any::<bool>(), 8),
                    prop::collection::vec(prop_oneof![4 => Just(true), 1 => Just(false)], 8),
                ),
                1..40,
            ),
        ) {
            let config = TextureCacheConfig { size_bytes: shape.0, line_bytes: shape.1, ways: shape.2 };
            let (mut together, mut one_by_one) = (TextureCache::new(config), TextureCache::new(config));
            for (texture, pair, per_lane, lines, repeats, counted) in quads {
                let first_line = texture << 30;
                // Lane k repeats lane k − 1 when `repeats[k]`, else takes lines of its own.
                let mut lanes = [[0u32; MAX_LANE_LINES]; 8];
                for (k, &repeat) in repeats.iter().enumerate() {
                    lanes[k] = if repeat && k > 0 { lanes[k - 1] } else { std::array::from_fn(|i| lines[(i + 3 * k) % 16]) };
                }
                if pair {
                    let rows: Vec<[u32; 8]> = (0..per_lane).map(|i| std::array::from_fn(|k| lanes[k][i])).collect();
                    together.access_lanes(first_line, &rows, std::array::from_fn(|k| counted[k]));
                } else {
                    let rows: Vec<[u32; 4]> = (0..per_lane).map(|i| std::array::from_fn(|k| lanes[k][i])).collect();
                    together.access_quad(first_line, &rows, std::array::from_fn(|k| counted[k]));
                }
                for k in (0..if pair { 8 } else { 4 }).filter(|&k| counted[k]) {
                    for &line in &lanes[k][..per_lane] {
                        one_by_one.access((first_line + line as u64) << one_by_one.line_shift());
                    }
                }
                prop_assert_eq!((together.hits(), together.misses()), (one_by_one.hits(), one_by_one.misses()));
                prop_assert_eq!(&together.lines, &one_by_one.lines);
            }
        }
    }
}
