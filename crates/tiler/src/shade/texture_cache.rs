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
use crate::simd::{SimdLevel, SimdSupport, per_simd_level};

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

/// The cache state of one task: per way its line and when it was last read, and the counts.
///
/// Least recently used is kept as a time stamp per way, not as an order of the set's lines:
/// a read stamps its way with the read's time, and a miss replaces the way with the oldest
/// stamp (an unused way's is 0, older than any read). Ordering each set's ways by stamp, newest
/// first, gives the order the line-by-line model (the set's lines moved to the front as they
/// are read) keeps; the tests hold the two equal. A hit is then one tag search and one store,
/// wherever the line is in its set.
#[derive(Clone, Debug)]
pub struct TextureCache {
    config: TextureCacheConfig,
    line_shift: u32,
    /// `log2(ways)`: a set's ways start at `set << ways_shift`.
    ways_shift: u32,
    set_mask: u64,
    /// `sets × ways` line numbers, `EMPTY` when unused. Allocated on the first access, so
    /// tasks that sample nothing cost nothing.
    tags: Vec<u64>,
    /// When each way's line was last read (a value of `clock`); 0 when unused.
    stamps: Vec<u64>,
    /// The time of the last read (each read, or each group of up to 64, advances it).
    clock: u64,
    hits: u64,
    misses: u64,
    /// Misses already handed to the ledger.
    misses_reported: u64,
    /// Quads read from level 0 minified more than 2× by a sampler without mip maps, and the
    /// misses their reads caused ([`TextureCache::note_unmipped`]): what mip maps would save.
    unmipped_quads: u64,
    unmipped_misses: u64,
    /// Lines each the most recently read of its set, no two in one set, at `first_line +`
    /// each (the last group's distinct lines, [`TextureCache::read_group`]); the unused
    /// entries repeat the first. Empty (`recent_len` 0) after any other read.
    recent: [u32; RECENT_LINES],
    recent_first_line: u64,
    recent_len: usize,
    /// Groups found within [`TextureCache::recent`] (for the tests).
    #[cfg(test)]
    recent_groups: u64,
    /// With the `texture-cache-reference` feature (for tests): the same cache read one line
    /// at a time by the line-by-line model ([`LineByLine`]), held equal after every call.
    #[cfg(feature = "texture-cache-reference")]
    reference: Option<Box<LineByLine>>,
}

impl Default for TextureCache {
    fn default() -> TextureCache {
        TextureCache::new(TextureCacheConfig::DEFAULT)
    }
}

/// The most distinct lines a group's reads are checked for ([`TextureCache::access_lanes`]):
/// past that, its reads are made one by one.
const MAX_GROUP_LINES: usize = 16;

/// The most lines [`TextureCache::recent`] holds: a bilinear footprint's lines on one level.
const RECENT_LINES: usize = 4;

impl TextureCache {
    const EMPTY: u64 = u64::MAX;

    /// A cold cache.
    ///
    /// # Panics
    /// If `config` is invalid (check it with [`TextureCacheConfig::validate`] first).
    pub fn new(config: TextureCacheConfig) -> TextureCache {
        assert!(config.validate().is_ok(), "invalid texture cache configuration {config:?}");
        TextureCache {
            config,
            line_shift: config.line_bytes.trailing_zeros(),
            ways_shift: config.ways.trailing_zeros(),
            set_mask: config.sets() as u64 - 1,
            tags: Vec::new(),
            stamps: Vec::new(),
            clock: 0,
            hits: 0,
            misses: 0,
            misses_reported: 0,
            unmipped_quads: 0,
            unmipped_misses: 0,
            recent: [0; RECENT_LINES],
            recent_first_line: 0,
            recent_len: 0,
            #[cfg(test)]
            recent_groups: 0,
            #[cfg(feature = "texture-cache-reference")]
            reference: Some(Box::new(LineByLine::new(config))),
        }
    }

    pub fn config(&self) -> &TextureCacheConfig {
        &self.config
    }

    /// Reads the byte at modelled address `address`; returns whether it hit.
    #[inline]
    pub fn access(&mut self, address: u64) -> bool {
        self.allocate_once();
        self.recent_len = 0;
        self.clock += 1;
        let hit = self.read_line(address >> self.line_shift, self.clock);
        self.count(1, !hit as u64);
        #[cfg(feature = "texture-cache-reference")]
        if let Some(reference) = &mut self.reference {
            reference.access(address >> self.line_shift);
        }
        self.check_reference();
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
        self.allocate_once();
        self.recent_len = 0;
        let (mut previous, mut misses) = (None, 0);
        for &line in lines {
            self.clock += 1;
            if previous != Some(line) {
                misses += !self.read_line(first_line + line as u64, self.clock) as u64;
                previous = Some(line);
            }
        }
        self.count(lines.len() as u64, misses);
        #[cfg(feature = "texture-cache-reference")]
        if let Some(reference) = &mut self.reference {
            for &line in lines {
                reference.access(first_line + line as u64);
            }
        }
        self.check_reference();
    }

    /// Reads the lines of a quad's `counted` lanes, lane after lane, each lane `k` reading
    /// `rows[0][k]`, `rows[1][k]`, … in order (a row per texel a lane reads: the corners of its
    /// footprint on a level, level after level): the same as [`TextureCache::access_lines`] of
    /// each lane's lines in turn. `simd`: the instruction set to run it with (every level
    /// counts the same).
    #[inline]
    pub fn access_quad(&mut self, simd: SimdSupport, first_line: u64, rows: &[[u32; 4]], counted: [bool; 4]) {
        assert!(rows.len() <= MAX_LANE_LINES, "{} lines a lane, more than {MAX_LANE_LINES}", rows.len());
        let misses = read_quad(simd, self, first_line, rows, counted);
        self.count_group(rows.len(), &counted, misses);
        self.check_reference();
    }

    /// [`TextureCache::access_quad`] of a pair of quads' eight lanes (quad 0's, then quad
    /// 1's), the same reads in the same order.
    ///
    /// A group's reads (up to 64) are made at the cost of a tag check per distinct line, not
    /// per read, when that is exact: the distinct lines are found in the order of their first
    /// reads, each with the time of its last read ([`TextureCache::read_group`]); when no set
    /// gets more of them than it has ways, reading each once in that order, stamped with its
    /// last read's time, counts and leaves the cache exactly as the reads one by one:
    ///
    /// - Only a line's first read can miss: between two reads of a line, fewer than `ways`
    ///   other lines of its set are read, so it is still among the `ways` most recent.
    /// - Whether a first read hits depends on what the reads before it evicted, and each such
    ///   eviction is of the set's least recently used line, which is never one the group has
    ///   read (each of those is newer than every line read before the group, and the set holds
    ///   fewer than `ways` of them when another misses): the same victims, in the same order,
    ///   as the first reads alone make, whatever stamps the group's lines carry.
    /// - After the reads, a set's order is its group lines by last read, then the rest in their
    ///   old order: what the stamps of the last reads give.
    ///
    /// Otherwise (more lines in a set than ways, or more than [`MAX_GROUP_LINES`] distinct
    /// lines) the reads are made one by one.
    #[inline]
    pub fn access_lanes(&mut self, simd: SimdSupport, first_line: u64, rows: &[[u32; 8]], counted: [bool; 8]) {
        assert!(rows.len() <= MAX_LANE_LINES, "{} lines a lane, more than {MAX_LANE_LINES}", rows.len());
        let misses = read_pair(simd, self, first_line, rows, counted);
        self.count_group(rows.len(), &counted, misses);
        self.check_reference();
    }

    /// [`TextureCache::access_lanes`] of a pair's bilinear footprints on one level (four lines
    /// a lane), for callers compiled for AVX2 (the sampler's byte kernel): the same reads as
    /// `access_lanes` makes at that level, without its dispatch.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    pub(crate) fn access_footprints_avx2<const R: usize>(
        &mut self,
        first_line: u64,
        rows: &[[u32; 8]; R],
        counted: [bool; 8],
    ) {
        let misses = avx2::read_footprints(self, first_line, rows, counted);
        #[cfg(feature = "texture-cache-reference")]
        self.read_reference(first_line, rows, counted);
        self.count_group(rows.len(), &counted, misses);
        self.check_reference();
    }

    /// [`TextureCache::access_lanes`] of a pair's trilinear footprints (four lines a lane on
    /// one level, then four on the next), for callers compiled for AVX2 (the sampler's byte
    /// kernel): the same reads, without the dispatch.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    pub(crate) fn access_two_levels_avx2(
        &mut self,
        simd: SimdSupport,
        first_line: u64,
        rows: &[[u32; 8]; 8],
        counted: [bool; 8],
    ) {
        let misses = match avx2::read_two_levels(self, first_line, rows, counted) {
            Some(misses) => {
                #[cfg(feature = "texture-cache-reference")]
                self.read_reference(first_line, rows, counted);
                misses
            }
            // A line read on both levels: the eight-row square (which reads the reference).
            None => read_rows(simd, self, first_line, rows, counted),
        };
        self.count_group(rows.len(), &counted, misses);
        self.check_reference();
    }

    /// Counts a group's reads (`rows` a lane, of the `counted` lanes) with `misses` misses.
    #[inline(always)]
    fn count_group<const L: usize>(&mut self, rows: usize, counted: &[bool; L], misses: u64) {
        let reads = counted.iter().filter(|&&counted| counted).count() as u64 * rows as u64;
        self.count(reads, misses);
    }

    /// With the `texture-cache-reference` feature: reads a group's lines from the reference
    /// one by one and asserts that the two agree (counts and every set's order).
    #[cfg(feature = "texture-cache-reference")]
    fn read_reference<const L: usize>(&mut self, first_line: u64, rows: &[[u32; L]], counted: [bool; L]) {
        if let Some(reference) = &mut self.reference {
            for lane in (0..L).filter(|&lane| counted[lane]) {
                for row in rows {
                    reference.access(first_line + row[lane] as u64);
                }
            }
        }
    }

    /// With the `texture-cache-reference` feature: asserts that the cache and its reference
    /// agree — hits, misses, and each set's lines by recency.
    #[inline(always)]
    fn check_reference(&self) {
        #[cfg(feature = "texture-cache-reference")]
        if let Some(reference) = &self.reference {
            assert_eq!(
                (self.hits, self.misses, self.by_recency()),
                (reference.hits, reference.misses, reference.lines.clone()),
                "the texture cache model disagrees with its line-by-line reference"
            );
        }
    }

    /// Each set's lines, most recently read first, then `EMPTY` for unused ways: the order the
    /// line-by-line model keeps ([`LineByLine`]).
    #[cfg(any(test, feature = "texture-cache-reference"))]
    fn by_recency(&self) -> Vec<u64> {
        let ways = self.config.ways as usize;
        let sets = self.config.sets() as usize;
        if self.tags.is_empty() {
            return vec![Self::EMPTY; sets * ways];
        }
        let mut out = Vec::with_capacity(sets * ways);
        for set in 0..sets {
            let mut held: Vec<(u64, u64)> =
                (set * ways..(set + 1) * ways).map(|w| (self.stamps[w], self.tags[w])).collect();
            held.sort_by_key(|&(stamp, _)| std::cmp::Reverse(stamp));
            out.extend(held.iter().map(|&(stamp, tag)| if stamp == 0 { Self::EMPTY } else { tag }));
        }
        out
    }

    /// The misses of a group's reads ([`TextureCache::access_lanes`]): `L` lanes of `R` rows.
    #[inline(always)]
    fn read_group<const L: usize, const R: usize>(
        &mut self,
        simd: SimdSupport,
        first_line: u64,
        rows: &[[u32; L]; R],
        counted: [bool; L],
    ) -> u64 {
        const { assert!(L <= 8 && R <= 8) };
        if !counted.contains(&true) {
            return 0;
        }
        // Only for reads of one level: two levels' lines are seldom few enough (tried for
        // both, stop 24: atrium's cache model took 10% more instructions).
        let one_level = R <= 4;
        if one_level && self.within_recent(first_line, rows, counted) {
            self.found_within_recent();
            return 0;
        }
        let base = self.start_group();
        let mut distinct = [0u64; MAX_GROUP_LINES];
        let Some(d) = distinct_lines(simd, rows, counted, &mut distinct) else {
            return self.read_each(base, first_line, rows, counted);
        };
        self.read_distinct(base, first_line, rows, counted, &distinct[..d], one_level)
    }

    /// The rest of [`TextureCache::read_group`] once the group's `distinct` lines are known
    /// (`line << 8 | key`, [`distinct_lines`]; `base` its stamps' start): remembers them as
    /// [`TextureCache::recent`] (`one_level`) and reads each, or the reads one by one when a set
    /// gets more of them than it has ways.
    #[inline(always)]
    fn read_distinct<const L: usize, const R: usize>(
        &mut self,
        base: u64,
        first_line: u64,
        rows: &[[u32; L]; R],
        counted: [bool; L],
        distinct: &[u64],
        one_level: bool,
    ) -> u64 {
        let d = distinct.len();
        if one_level {
            self.remember_recent(first_line, distinct);
        } else {
            self.recent_len = 0;
        }
        let ways = 1usize << self.ways_shift;
        if d > ways {
            let mut sets = [u32::MAX; MAX_GROUP_LINES];
            for j in 0..d {
                sets[j] = ((first_line + (distinct[j] >> 8)) & self.set_mask) as u32;
            }
            for j in 0..d {
                let in_set: u32 = sets.iter().map(|&s| (s == sets[j]) as u32).sum();
                if in_set as usize > ways {
                    return self.read_each(base, first_line, rows, counted);
                }
            }
        }
        let mut misses = 0;
        for &entry in distinct {
            misses += !self.read_line(first_line + (entry >> 8), base + 1 + (entry & 0xff)) as u64;
        }
        misses
    }

    /// Notes a group found within [`TextureCache::recent`] (counted for the tests).
    #[inline(always)]
    fn found_within_recent(&mut self) {
        #[cfg(test)]
        {
            self.recent_groups += 1;
        }
    }

    /// Allocates the cache if it is cold and returns the time a group's reads are stamped
    /// from: `base + 1` to `base + 64`.
    #[inline(always)]
    fn start_group(&mut self) -> u64 {
        self.allocate_once();
        let base = self.clock;
        self.clock += 64;
        base
    }

    /// Whether every read of a group (as [`TextureCache::read_group`]) is of a line in
    /// [`TextureCache::recent`]. Such a group hits on every read and changes nothing: each line
    /// it reads is already the most recently read of its set, and the only one of the group
    /// there, so reading it again (however often, in whatever order) leaves each set's order
    /// as it was. The lines stay the newest of their sets, so the next group may be checked
    /// against them too.
    ///
    /// This is what a filter's taps a texel apart make: each reads the lines the tap before
    /// it read, and checking a group against a handful of lines costs less than finding its
    /// distinct lines.
    #[inline(always)]
    fn within_recent<const L: usize, const R: usize>(
        &self,
        first_line: u64,
        rows: &[[u32; L]; R],
        counted: [bool; L],
    ) -> bool {
        if self.recent_len == 0 || first_line != self.recent_first_line {
            return false;
        }
        let mut outside = [false; L];
        for row in rows {
            for k in 0..L {
                let line = row[k];
                outside[k] |= !self.recent.iter().fold(false, |found, &recent| found | (recent == line));
            }
        }
        (0..L).all(|k| !(outside[k] & counted[k]))
    }

    /// Keeps a group's `distinct` lines (`line << 8 | key`, [`distinct_lines`]) as
    /// [`TextureCache::recent`] when there are at most [`RECENT_LINES`] of them in as many
    /// sets: after the group, each is the most recently read of its set. Otherwise forgets
    /// the recent lines.
    #[inline(always)]
    fn remember_recent(&mut self, first_line: u64, distinct: &[u64]) {
        self.recent_len = 0;
        if distinct.is_empty() || distinct.len() > RECENT_LINES {
            return;
        }
        let set = |entry: u64| (first_line + (entry >> 8)) & self.set_mask;
        for (i, &a) in distinct.iter().enumerate() {
            if distinct[..i].iter().any(|&b| set(a) == set(b)) {
                return;
            }
        }
        let first = (distinct[0] >> 8) as u32;
        self.recent = [first; RECENT_LINES];
        for (slot, &entry) in self.recent.iter_mut().zip(distinct) {
            *slot = (entry >> 8) as u32;
        }
        self.recent_first_line = first_line;
        self.recent_len = distinct.len();
    }

    /// [`TextureCache::read_group`] read by read (read `8 · lane + row` stamped `base + 1 +` that).
    #[inline(never)]
    fn read_each<const L: usize, const R: usize>(
        &mut self,
        base: u64,
        first_line: u64,
        rows: &[[u32; L]; R],
        counted: [bool; L],
    ) -> u64 {
        self.recent_len = 0;
        let (mut previous, mut misses) = (None, 0);
        for lane in (0..L).filter(|&lane| counted[lane]) {
            for (r, row) in rows.iter().enumerate() {
                let line = row[lane];
                // The same line again is a hit on the set's newest way: nothing changes.
                if previous != Some(line) {
                    misses += !self.read_line(first_line + line as u64, base + 1 + (8 * lane + r) as u64) as u64;
                    previous = Some(line);
                }
            }
        }
        misses
    }

    /// Reads line `line` at time `stamp`; returns whether it hit (uncounted: the callers
    /// count). The cache is allocated.
    #[inline(always)]
    fn read_line(&mut self, line: u64, stamp: u64) -> bool {
        let first = ((line & self.set_mask) as usize) << self.ways_shift;
        match self.ways_shift {
            2 => self.read_in_set::<4>(first, line, stamp),
            _ => self.read_in_set_of_any(first, line, stamp),
        }
    }

    /// [`Self::read_line`] in a set of `W` ways starting at `first`.
    #[inline(always)]
    fn read_in_set<const W: usize>(&mut self, first: usize, line: u64, stamp: u64) -> bool {
        let tags: &mut [u64; W] = (&mut self.tags[first..first + W]).try_into().expect("a set has W ways");
        let stamps: &mut [u64; W] = (&mut self.stamps[first..first + W]).try_into().expect("a set has W ways");
        // A line is in at most one way of its set.
        let mut way = W;
        for (w, &tag) in tags.iter().enumerate() {
            if tag == line {
                way = w;
            }
        }
        if way < W {
            stamps[way] = stamp;
            return true;
        }
        let mut oldest = 0;
        for w in 1..W {
            if stamps[w] < stamps[oldest] {
                oldest = w;
            }
        }
        tags[oldest] = line;
        stamps[oldest] = stamp;
        false
    }

    /// [`Self::read_line`] in a set of any number of ways.
    #[inline(never)]
    fn read_in_set_of_any(&mut self, first: usize, line: u64, stamp: u64) -> bool {
        let ways = 1usize << self.ways_shift;
        let (tags, stamps) = (&mut self.tags[first..first + ways], &mut self.stamps[first..first + ways]);
        if let Some(way) = tags.iter().position(|&tag| tag == line) {
            stamps[way] = stamp;
            return true;
        }
        let oldest = (0..ways).min_by_key(|&w| stamps[w]).expect("a set has a way");
        tags[oldest] = line;
        stamps[oldest] = stamp;
        false
    }

    /// Allocates a cold cache's ways, all unused, on its first read.
    #[inline(always)]
    fn allocate_once(&mut self) {
        if self.tags.is_empty() {
            self.allocate();
        }
    }

    #[cold]
    #[inline(never)]
    fn allocate(&mut self) {
        let ways = self.config.sets() as usize * self.config.ways as usize;
        self.tags = vec![Self::EMPTY; ways];
        self.stamps = vec![0; ways];
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

/// The distinct lines of a group's reads (`rows[r][k]`, lane `k` of the `counted` lanes reading
/// rows 0, 1, … in turn, lane after lane) in the order of their first reads, each with a key
/// that orders their last reads (below 64), into `out` as `line << 8 | key`; returns how many,
/// or `None` past [`MAX_GROUP_LINES`].
///
/// The reads may be shortened first where that changes neither order: a lane that reads what
/// the lane before it read is dropped (its lines are read again in the same order, after every
/// other line), and so is a read of the line just read; or lengthened, a lane's last line read
/// again after it.
#[inline(always)]
fn distinct_lines<const L: usize, const R: usize>(
    simd: SimdSupport,
    rows: &[[u32; L]; R],
    counted: [bool; L],
    out: &mut [u64; MAX_GROUP_LINES],
) -> Option<usize> {
    #[cfg(target_arch = "x86_64")]
    if simd.level() == SimdLevel::Avx2 {
        // Eight rows of eight lanes: rows past `R` repeat the last, lanes past `L` are not read.
        let mut square = [[0u32; 8]; 8];
        for (r, row) in square.iter_mut().enumerate() {
            row[..L].copy_from_slice(&rows[r.min(R - 1)]);
        }
        // A byte of ones per counted lane (each `bool` a byte of 0 or 1).
        let mut lanes = [0u8; 8];
        for (lane, &counted) in lanes.iter_mut().zip(&counted) {
            *lane = counted as u8;
        }
        let reads = u64::from_le_bytes(lanes) * 0xff;
        // SAFETY: a `SimdSupport` of level `Avx2` exists only when this processor has every
        // feature `avx2::distinct_lines` is compiled with (`SimdSupport::detect`).
        return unsafe { avx2::distinct_lines(&square, reads, out) };
    }
    let _ = simd;
    // Lane `k` reads what lane `k − 1` reads (each row compared with itself one lane over).
    let mut repeats = [true; L];
    for row in rows {
        for k in 1..L {
            repeats[k] &= row[k] == row[k - 1];
        }
    }
    let (mut d, mut i, mut previous) = (0, 0u64, None);
    for k in 0..L {
        if !counted[k] || (k > 0 && repeats[k] && counted[k - 1]) {
            continue;
        }
        for row in rows {
            let line = row[k];
            if previous == Some(line) {
                continue;
            }
            previous = Some(line);
            match out[..d].iter().position(|&seen| (seen >> 8) as u32 == line) {
                Some(j) => out[j] = (line as u64) << 8 | i,
                None if d == MAX_GROUP_LINES => return None,
                None => {
                    out[d] = (line as u64) << 8 | i;
                    d += 1;
                }
            }
            i += 1;
        }
    }
    Some(d)
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use std::arch::x86_64::*;

    use super::{MAX_GROUP_LINES, TextureCache};

    /// A pair's reads as the bits of a word: the four bits `4 · k` to `4 · k + 3` set for each
    /// `counted` lane `k` (its rows 0–3).
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    fn counted_reads(counted: [bool; 8]) -> u32 {
        // A `bool` is a byte of 0 or 1.
        let counted_bytes = u64::from_le_bytes(counted.map(u8::from));
        let lanes = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(counted_bytes as i64));
        _mm256_movemask_epi8(_mm256_cmpgt_epi32(lanes, _mm256_setzero_si256())) as u32
    }

    /// Byte `r` of each 32-bit lane set, for `r` 0 to 3: where row `r`'s comparison goes in
    /// [`reads_of`].
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    fn row_bytes() -> [__m256i; 4] {
        let byte = |r: u32| _mm256_set1_epi32((0xffu32 << (8 * r)) as i32);
        [byte(0), byte(1), byte(2), byte(3)]
    }

    /// The reads of `line` among four rows of eight lanes, as the bits of a word in read order
    /// (lane `k`'s row `r` at bit `4 · k + r`): each row's comparison masked into its own byte
    /// of a lane (`bytes`, [`row_bytes`]), so that one `movemask` gives them in that order.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    fn reads_of(rows: &[__m256i; 4], bytes: &[__m256i; 4], line: u32) -> u32 {
        let x = _mm256_set1_epi32(line as i32);
        let low = _mm256_or_si256(
            _mm256_and_si256(_mm256_cmpeq_epi32(rows[0], x), bytes[0]),
            _mm256_and_si256(_mm256_cmpeq_epi32(rows[1], x), bytes[1]),
        );
        let high = _mm256_or_si256(
            _mm256_and_si256(_mm256_cmpeq_epi32(rows[2], x), bytes[2]),
            _mm256_and_si256(_mm256_cmpeq_epi32(rows[3], x), bytes[3]),
        );
        _mm256_movemask_epi8(_mm256_or_si256(low, high)) as u32
    }

    /// [`TextureCache::read_group`] of a pair's eight lanes reading `R` lines each — four (the
    /// corners of a bilinear footprint on one level) or one (a nearest texel) — the same checks
    /// in the same order, with the group's reads as the bits of a word in read order — lane
    /// `k`'s row `r` at bit `4 · k + r` — rather than the 64 of the eight-row square:
    ///
    /// - within [`TextureCache::recent`]: each row compared with each recent line;
    /// - one line for every read (the first read's: a nearest lookup's 4×2 texels, a magnified
    ///   one's footprints within a block): that line alone to [`TextureCache::read_distinct`],
    ///   without the search;
    /// - the distinct lines ([`super::distinct_lines`]): the lowest unread bit is the first
    ///   unread read; one comparison of the four rows with its line finds its reads (each row's
    ///   mask in its own byte of a lane, so that one `movemask` gives them in read order), and
    ///   the highest of them is its last read, whose position is its key. The keys are not
    ///   those of the eight-row square (`8 · k + r` there, rows 4–7 repeating row 3) but order
    ///   the lines' last reads the same, and only that order reaches the cache: a group's
    ///   stamps are `base + 1 + key`, above every earlier one.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    pub(super) fn read_footprints<const R: usize>(
        cache: &mut TextureCache,
        first_line: u64,
        rows: &[[u32; 8]; R],
        counted: [bool; 8],
    ) -> u64 {
        const { assert!(R == 1 || R == 4) };
        let zero = _mm256_setzero_si256();
        // Each counted lane's `R` reads.
        let reads = counted_reads(counted) & if R == 1 { 0x1111_1111 } else { u32::MAX };
        if reads == 0 {
            return 0;
        }
        // SAFETY (each load): reads the 32 bytes of one `[u32; 8]` of `rows`; unaligned loads
        // need no alignment. Rows past `R` repeat the last: reads of it again, which the
        // `reads` mask leaves out.
        let row = |r: usize| unsafe { _mm256_loadu_si256(rows[r.min(R - 1)].as_ptr().cast()) };
        let r = [row(0), row(1), row(2), row(3)];
        if cache.recent_len != 0 && first_line == cache.recent_first_line {
            let mut inside = [zero; 4];
            for &recent in &cache.recent {
                let x = _mm256_set1_epi32(recent as i32);
                for (inside, &row) in inside.iter_mut().zip(&r) {
                    *inside = _mm256_or_si256(*inside, _mm256_cmpeq_epi32(row, x));
                }
            }
            let all = _mm256_and_si256(_mm256_and_si256(inside[0], inside[1]), _mm256_and_si256(inside[2], inside[3]));
            if reads & !(_mm256_movemask_epi8(all) as u32) == 0 {
                cache.found_within_recent();
                return 0;
            }
        }
        let bytes = row_bytes();
        // The first read's line and all its reads: the first step of the search below, which
        // for many groups (a nearest lookup's 4×2 texels, a magnified one's footprints within a
        // block) is the whole of it.
        let first = reads.trailing_zeros() as usize;
        let line = rows[(first % 4).min(R - 1)][first / 4];
        let matched = reads_of(&r, &bytes, line) & reads;
        let entry = (line as u64) << 8 | (31 - matched.leading_zeros()) as u64;
        let base = cache.start_group();
        if matched == reads {
            return cache.read_distinct(base, first_line, rows, counted, &[entry], true);
        }
        let (mut unread, mut distinct, mut d) = (reads & !matched, [0u64; MAX_GROUP_LINES], 1);
        distinct[0] = entry;
        while unread != 0 {
            if d == MAX_GROUP_LINES {
                return cache.read_each(base, first_line, rows, counted);
            }
            let first = unread.trailing_zeros() as usize;
            let line = rows[(first % 4).min(R - 1)][first / 4];
            let matched = reads_of(&r, &bytes, line) & reads;
            unread &= !matched;
            distinct[d] = (line as u64) << 8 | (31 - matched.leading_zeros()) as u64;
            d += 1;
        }
        cache.read_distinct(base, first_line, rows, counted, &distinct[..d], true)
    }

    /// [`TextureCache::read_group`] of a pair's trilinear footprints — eight lanes reading the
    /// corners of a footprint on one level (rows 0–3) and then on the next (rows 4–7) — the
    /// same reads in the same order as the eight-row square of [`distinct_lines`], or `None`,
    /// having changed nothing, when a line is read on both levels (lines longer than blocks).
    ///
    /// The square finds the group's distinct lines one after another, each comparison waiting
    /// on the one before (the next line is the first read left unmatched): a chain of about 25
    /// cycles a line, which made this the costliest step of a trilinear lookup. Here each
    /// level's four rows are a word of 32 reads, as in [`read_footprints`], and the two levels'
    /// lines are found by two chains that do not wait on each other. A line's first and last
    /// reads in the square's order follow from its position `4 · k + r` in its level's word
    /// (`8 · k + r`, plus 4 on the second level); the two lists, each in the order of first
    /// reads, are merged by those, so [`TextureCache::read_distinct`] gets the square's list,
    /// keys and all.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    #[inline]
    pub(super) fn read_two_levels(
        cache: &mut TextureCache,
        first_line: u64,
        rows: &[[u32; 8]; 8],
        counted: [bool; 8],
    ) -> Option<u64> {
        // Each counted lane's four reads on a level.
        let reads = counted_reads(counted);
        if reads == 0 {
            return Some(0);
        }
        // SAFETY (each load): reads the 32 bytes of one `[u32; 8]` of `rows`; unaligned loads
        // need no alignment.
        let row = |r: usize| unsafe { _mm256_loadu_si256(rows[r].as_ptr().cast()) };
        let levels = [[row(0), row(1), row(2), row(3)], [row(4), row(5), row(6), row(7)]];
        let bytes = row_bytes();
        // The square's position of bit `b` of `level`'s word: lane `b / 4`, row `4 · level + b % 4`.
        let square = |level: usize, b: u32| 8 * (b / 4) + 4 * level as u32 + b % 4;
        // Per level: its distinct lines in the order of their first reads, and the square's
        // positions of each line's first and last reads.
        let mut lines = [[0u32; MAX_GROUP_LINES]; 2];
        let mut firsts = [[0u32; MAX_GROUP_LINES]; 2];
        let mut lasts = [[0u32; MAX_GROUP_LINES]; 2];
        let (mut unread, mut d) = ([reads; 2], [0usize; 2]);
        while unread[0] | unread[1] != 0 {
            if d[0] == MAX_GROUP_LINES || d[1] == MAX_GROUP_LINES {
                break;
            }
            // One step of each level's chain: independent work the processor overlaps.
            for level in 0..2 {
                if unread[level] != 0 {
                    let first = unread[level].trailing_zeros();
                    let line = rows[4 * level + (first % 4) as usize][(first / 4) as usize];
                    let matched = reads_of(&levels[level], &bytes, line) & reads;
                    unread[level] &= !matched;
                    let i = d[level];
                    lines[level][i] = line;
                    firsts[level][i] = square(level, first);
                    lasts[level][i] = square(level, 31 - matched.leading_zeros());
                    d[level] += 1;
                }
            }
        }
        let total = d[0] + d[1];
        if unread[0] | unread[1] != 0 || total > MAX_GROUP_LINES {
            // More distinct lines than are checked together: read one by one, which is exact
            // whether or not the two levels share a line.
            let base = cache.start_group();
            return Some(cache.read_each(base, first_line, rows, counted));
        }
        // The two lists merged by first reads: a line's place is its place in its own list
        // plus the other list's lines read first before it.
        let mut merged = [0u64; MAX_GROUP_LINES];
        for level in 0..2 {
            let other = 1 - level;
            let (other_firsts, other_lines) = (&firsts[other][..d[other]], &lines[other][..d[other]]);
            for i in 0..d[level] {
                if other_lines.contains(&lines[level][i]) {
                    return None;
                }
                let place = i + other_firsts.iter().filter(|&&first| first < firsts[level][i]).count();
                merged[place] = (lines[level][i] as u64) << 8 | lasts[level][i] as u64;
            }
        }
        let base = cache.start_group();
        Some(cache.read_distinct(base, first_line, rows, counted, &merged[..total], false))
    }

    /// [`super::distinct_lines`] of eight rows of eight lanes, read `8 · k + r` (lane `k`, row
    /// `r`) made where bit `8 · k + r` of `reads` is set: per distinct line, one comparison of
    /// all 64 reads with it (eight lanes at a time, the eight lanes' masks packed to bytes in
    /// read order), the first read not yet matched starting the next line. The key of a line's
    /// last read is its position.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    pub(super) fn distinct_lines(rows: &[[u32; 8]; 8], reads: u64, out: &mut [u64; MAX_GROUP_LINES]) -> Option<usize> {
        // SAFETY (each load): reads the 32 bytes of one `[u32; 8]` of `rows`; unaligned loads
        // need no alignment.
        let row = |r: usize| unsafe { _mm256_loadu_si256(rows[r].as_ptr().cast()) };
        let (r0, r1, r2, r3, r4, r5, r6, r7) = (row(0), row(1), row(2), row(3), row(4), row(5), row(6), row(7));
        // Transposed: `c[k]` holds lane k's eight rows.
        let (t0, t1) = (_mm256_unpacklo_epi32(r0, r1), _mm256_unpackhi_epi32(r0, r1));
        let (t2, t3) = (_mm256_unpacklo_epi32(r2, r3), _mm256_unpackhi_epi32(r2, r3));
        let (t4, t5) = (_mm256_unpacklo_epi32(r4, r5), _mm256_unpackhi_epi32(r4, r5));
        let (t6, t7) = (_mm256_unpacklo_epi32(r6, r7), _mm256_unpackhi_epi32(r6, r7));
        let (u0, u1) = (_mm256_unpacklo_epi64(t0, t2), _mm256_unpackhi_epi64(t0, t2));
        let (u2, u3) = (_mm256_unpacklo_epi64(t1, t3), _mm256_unpackhi_epi64(t1, t3));
        let (u4, u5) = (_mm256_unpacklo_epi64(t4, t6), _mm256_unpackhi_epi64(t4, t6));
        let (u6, u7) = (_mm256_unpacklo_epi64(t5, t7), _mm256_unpackhi_epi64(t5, t7));
        let c = [
            _mm256_permute2x128_si256::<0x20>(u0, u4),
            _mm256_permute2x128_si256::<0x20>(u1, u5),
            _mm256_permute2x128_si256::<0x20>(u2, u6),
            _mm256_permute2x128_si256::<0x20>(u3, u7),
            _mm256_permute2x128_si256::<0x31>(u0, u4),
            _mm256_permute2x128_si256::<0x31>(u1, u5),
            _mm256_permute2x128_si256::<0x31>(u2, u6),
            _mm256_permute2x128_si256::<0x31>(u3, u7),
        ];
        // After the packs, dword `j` of a half holds lane (j % 4)'s rows 0–3 (j < 4) or 4–7.
        let order = _mm256_setr_epi32(0, 4, 1, 5, 2, 6, 3, 7);
        let (mut d, mut unread) = (0, reads);
        while unread != 0 {
            if d == MAX_GROUP_LINES {
                return None;
            }
            let first = unread.trailing_zeros() as usize;
            let line = rows[first % 8][first / 8];
            let x = _mm256_set1_epi32(line as i32);
            let e = |k: usize| _mm256_cmpeq_epi32(c[k], x);
            let low = _mm256_packs_epi16(_mm256_packs_epi32(e(0), e(1)), _mm256_packs_epi32(e(2), e(3)));
            let high = _mm256_packs_epi16(_mm256_packs_epi32(e(4), e(5)), _mm256_packs_epi32(e(6), e(7)));
            let low = _mm256_movemask_epi8(_mm256_permutevar8x32_epi32(low, order)) as u32 as u64;
            let high = _mm256_movemask_epi8(_mm256_permutevar8x32_epi32(high, order)) as u32 as u64;
            let matched = (low | high << 32) & reads;
            unread &= !matched;
            out[d] = (line as u64) << 8 | (63 - matched.leading_zeros() as u64);
            d += 1;
        }
        Some(d)
    }
}

/// [`TextureCache::read_group`] of `rows.len()` rows (1, 2, 4 or 8, each compiled with its
/// count known; other counts are made read by read).
#[inline(always)]
fn read_rows<const L: usize>(
    simd: SimdSupport,
    cache: &mut TextureCache,
    first_line: u64,
    rows: &[[u32; L]],
    counted: [bool; L],
) -> u64 {
    let misses = if let Ok(rows) = <&[[u32; L]; 8]>::try_from(rows) {
        cache.read_group(simd, first_line, rows, counted)
    } else if let Ok(rows) = <&[[u32; L]; 4]>::try_from(rows) {
        cache.read_group(simd, first_line, rows, counted)
    } else if let Ok(rows) = <&[[u32; L]; 2]>::try_from(rows) {
        cache.read_group(simd, first_line, rows, counted)
    } else if let Ok(rows) = <&[[u32; L]; 1]>::try_from(rows) {
        cache.read_group(simd, first_line, rows, counted)
    } else if rows.is_empty() || !counted.contains(&true) {
        0
    } else {
        // Rows past the lane's last repeat it: reads of the line just read, which change nothing.
        let mut padded = [[0; L]; MAX_LANE_LINES];
        padded[..rows.len()].copy_from_slice(rows);
        for r in rows.len()..MAX_LANE_LINES {
            padded[r] = padded[r - 1];
        }
        let base = cache.start_group();
        cache.read_each(base, first_line, &padded, counted)
    };
    #[cfg(feature = "texture-cache-reference")]
    cache.read_reference(first_line, rows, counted);
    misses
}

per_simd_level! {
    /// The misses of a pair of quads' reads ([`TextureCache::access_lanes`]), compiled once per
    /// SIMD level.
    fn read_pair / read_pair_avx2 => read_pair_body, simd: simd, (
        simd: SimdSupport,
        cache: &mut TextureCache,
        first_line: u64,
        rows: &[[u32; 8]],
        counted: [bool; 8],
    ) -> u64
}

#[inline(always)]
fn read_pair_body(
    simd: SimdSupport,
    cache: &mut TextureCache,
    first_line: u64,
    rows: &[[u32; 8]],
    counted: [bool; 8],
) -> u64 {
    #[cfg(target_arch = "x86_64")]
    if simd.level() == SimdLevel::Avx2 {
        // SAFETY (each call): a `SimdSupport` of level `Avx2` exists only when this processor
        // has every feature `avx2::read_footprints` and `avx2::read_two_levels` are compiled
        // with (`SimdSupport::detect`).
        let misses = if let Ok(footprint) = <&[[u32; 8]; 4]>::try_from(rows) {
            Some(unsafe { avx2::read_footprints(cache, first_line, footprint, counted) })
        } else if let Ok(texel) = <&[[u32; 8]; 1]>::try_from(rows) {
            Some(unsafe { avx2::read_footprints(cache, first_line, texel, counted) })
        } else if let Ok(trilinear) = <&[[u32; 8]; 8]>::try_from(rows) {
            unsafe { avx2::read_two_levels(cache, first_line, trilinear, counted) }
        } else {
            None
        };
        if let Some(misses) = misses {
            #[cfg(feature = "texture-cache-reference")]
            cache.read_reference(first_line, rows, counted);
            return misses;
        }
    }
    read_rows(simd, cache, first_line, rows, counted)
}

per_simd_level! {
    /// The misses of a quad's reads ([`TextureCache::access_quad`]), compiled once per SIMD
    /// level.
    fn read_quad / read_quad_avx2 => read_quad_body, simd: simd, (
        simd: SimdSupport,
        cache: &mut TextureCache,
        first_line: u64,
        rows: &[[u32; 4]],
        counted: [bool; 4],
    ) -> u64
}

#[inline(always)]
fn read_quad_body(
    simd: SimdSupport,
    cache: &mut TextureCache,
    first_line: u64,
    rows: &[[u32; 4]],
    counted: [bool; 4],
) -> u64 {
    read_rows(simd, cache, first_line, rows, counted)
}

/// The cache model as it was first written, one line at a time, each set's lines in an order
/// (most recently used first) moved on every read: the reference the tests and the
/// `texture-cache-reference` feature hold [`TextureCache`] to.
#[cfg(any(test, feature = "texture-cache-reference"))]
#[derive(Clone, Debug)]
pub(crate) struct LineByLine {
    ways: usize,
    set_mask: u64,
    lines: Vec<u64>,
    hits: u64,
    misses: u64,
}

#[cfg(any(test, feature = "texture-cache-reference"))]
impl LineByLine {
    fn new(config: TextureCacheConfig) -> LineByLine {
        let (sets, ways) = (config.sets() as usize, config.ways as usize);
        LineByLine {
            ways,
            set_mask: sets as u64 - 1,
            lines: vec![TextureCache::EMPTY; sets * ways],
            hits: 0,
            misses: 0,
        }
    }

    /// Reads line `line`: moves it to the front of its set, each line before it one place
    /// back; when it was not in the set, the last falls out: a miss.
    fn access(&mut self, line: u64) -> bool {
        let first = (line & self.set_mask) as usize * self.ways;
        let mut moving = line;
        for entry in &mut self.lines[first..first + self.ways] {
            let was = std::mem::replace(entry, moving);
            if was == line {
                self.hits += 1;
                return true;
            }
            moving = was;
        }
        self.misses += 1;
        false
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;
    use crate::simd::SimdLevel;

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

    /// Groups that read only lines the group before read (a filter's taps a texel apart) are
    /// found within the recent lines, and count and leave the cache as the line-by-line model.
    #[test]
    fn groups_within_the_last_groups_lines_change_nothing() {
        for simd in simd_levels() {
            let config = TextureCacheConfig::DEFAULT;
            let (mut cache, mut reference) = (TextureCache::new(config), LineByLine::new(config));
            let first_line = 3 << 40;
            // Two lines a lane, then one of them; then a set shared by two lines (64 apart), which
            // is not remembered; then a line outside.
            let groups: [[[u32; 8]; 2]; 5] = [
                [[0, 0, 0, 0, 1, 1, 1, 1], [200, 200, 200, 200, 201, 201, 201, 201]],
                [[1, 1, 1, 1, 0, 0, 0, 0], [1, 1, 1, 1, 200, 200, 200, 200]],
                [[0, 0, 0, 0, 64, 64, 64, 64], [0; 8]],
                [[0, 0, 0, 0, 64, 64, 64, 64], [0; 8]],
                [[0, 0, 0, 0, 64, 64, 64, 65], [0; 8]],
            ];
            let mut within = Vec::new();
            for rows in &groups {
                let before = cache.recent_groups;
                cache.access_lanes(simd, first_line, rows, [true; 8]);
                within.push(cache.recent_groups - before);
                for k in 0..8 {
                    for row in rows {
                        reference.access(first_line + row[k] as u64);
                    }
                }
                assert_eq!((cache.hits(), cache.misses()), (reference.hits, reference.misses));
                assert_eq!(cache.by_recency(), reference.lines);
            }
            assert_eq!(within, [0, 1, 0, 0, 0], "{simd:?}");
            assert_eq!(cache.misses(), 4 + 1 + 1);
        }
    }

    /// The same with four lines a lane, the corners of bilinear footprints (which AVX2 reads
    /// without the eight-row square): taps a texel apart within the last group's lines, then
    /// a tap one line over, then one of two lanes that counts only what the last read.
    #[test]
    fn footprints_within_the_last_groups_lines_change_nothing() {
        for simd in simd_levels() {
            let config = TextureCacheConfig::DEFAULT;
            let (mut cache, mut reference) = (TextureCache::new(config), LineByLine::new(config));
            let first_line = 5 << 40;
            let footprint = |left: [u32; 8], below: u32| -> [[u32; 8]; 4] {
                [left, left.map(|l| l + 1), left.map(|l| l + below), left.map(|l| l + below + 1)]
            };
            let groups: [([[u32; 8]; 4], [bool; 8]); 5] = [
                (footprint([10, 10, 10, 10, 10, 10, 10, 10], 20), [true; 8]),
                (footprint([10, 10, 10, 10, 10, 10, 10, 10], 20), [true; 8]),
                (footprint([11, 11, 11, 11, 11, 11, 11, 11], 20), [true; 8]),
                (footprint([11, 11, 11, 11, 11, 11, 11, 10], 20), [true, true, true, true, true, true, true, false]),
                (footprint([11, 11, 11, 11, 11, 11, 11, 10], 20), [true; 8]),
            ];
            let mut within = Vec::new();
            for (rows, counted) in &groups {
                let before = cache.recent_groups;
                cache.access_lanes(simd, first_line, rows, *counted);
                within.push(cache.recent_groups - before);
                for k in (0..8).filter(|&k| counted[k]) {
                    for row in rows {
                        reference.access(first_line + row[k] as u64);
                    }
                }
                assert_eq!((cache.hits(), cache.misses()), (reference.hits, reference.misses));
                assert_eq!(cache.by_recency(), reference.lines);
            }
            assert_eq!(within, [0, 1, 0, 1, 0], "{simd:?}");
            assert_eq!(cache.misses(), 4 + 2);
        }
    }

    /// The SIMD levels this processor runs.
    fn simd_levels() -> Vec<SimdSupport> {
        [SimdLevel::Baseline, SimdLevel::Avx2].into_iter().filter_map(SimdSupport::detect).collect()
    }

    /// The cache and the line-by-line model agree: counts and every set's order.
    fn agree(cache: &TextureCache, reference: &LineByLine) -> Result<(), TestCaseError> {
        prop_assert_eq!((cache.hits(), cache.misses()), (reference.hits, reference.misses));
        prop_assert_eq!(cache.by_recency(), reference.lines.clone());
        Ok(())
    }

    proptest! {
        /// Runs of lines read together count and leave the cache exactly as the line-by-line
        /// model reading them one by one, whatever the shape (lines of 4 to 256 bytes, 1 to 64
        /// ways) and however often lines repeat; single addresses too.
        #[test]
        fn access_lines_is_access_of_each(
            shape in prop::sample::select(vec![(256u32, 64u32, 1u32), (1024, 64, 4), (512, 16, 2), (256, 4, 64), (8192, 256, 4)]),
            runs in prop::collection::vec((0u64..3, prop::collection::vec(0u32..24, 1..9)), 1..40),
        ) {
            let config = TextureCacheConfig { size_bytes: shape.0, line_bytes: shape.1, ways: shape.2 };
            let (mut together, mut one_by_one) = (TextureCache::new(config), LineByLine::new(config));
            for (texture, lines) in runs {
                let first_line = texture << 30;
                if lines.len() == 1 {
                    together.access((first_line + lines[0] as u64) << together.line_shift() | 3);
                } else {
                    together.access_lines(first_line, &lines);
                }
                for &line in &lines {
                    one_by_one.access(first_line + line as u64);
                }
                agree(&together, &one_by_one)?;
            }
        }

        /// A quad's (or a pair of quads') lanes read at the cost of a tag check per distinct
        /// line count and leave the cache exactly as the line-by-line model reading each line
        /// of each counted lane in turn: lanes repeated or not, counted or not, more lines of a
        /// set than it has ways (lines 64 apart share a set in every shape but the fully
        /// associative one), more distinct lines than are checked together, at every SIMD
        /// level.
        #[test]
        fn access_lanes_is_access_of_each(
            shape in prop::sample::select(vec![(256u32, 64u32, 1u32), (1024, 64, 4), (512, 16, 2), (256, 4, 64), (16384, 64, 4)]),
            quads in prop::collection::vec(
                (
                    0u64..3,
                    any::<bool>(),
                    prop::sample::select(vec![1usize, 2, 3, 4, 8]),
                    prop::collection::vec(prop_oneof![3 => 0u32..6, 1 => 0u32..200, 1 => (0u32..4).prop_map(|k| k * 64)], 16),
                    prop::collection::vec(any::<bool>(), 8),
                    prop::collection::vec(prop_oneof![4 => Just(true), 1 => Just(false)], 8),
                ),
                1..40,
            ),
        ) {
            let config = TextureCacheConfig { size_bytes: shape.0, line_bytes: shape.1, ways: shape.2 };
            for simd in simd_levels() {
                let (mut together, mut one_by_one) = (TextureCache::new(config), LineByLine::new(config));
                for (texture, pair, per_lane, lines, repeats, counted) in &quads {
                    let first_line = texture << 30;
                    // Lane k repeats lane k − 1 when `repeats[k]`, else takes lines of its own.
                    let mut lanes = [[0u32; MAX_LANE_LINES]; 8];
                    for (k, &repeat) in repeats.iter().enumerate() {
                        lanes[k] = if repeat && k > 0 { lanes[k - 1] } else { std::array::from_fn(|i| lines[(i + 3 * k) % 16]) };
                    }
                    if *pair {
                        let rows: Vec<[u32; 8]> = (0..*per_lane).map(|i| std::array::from_fn(|k| lanes[k][i])).collect();
                        together.access_lanes(simd, first_line, &rows, std::array::from_fn(|k| counted[k]));
                    } else {
                        let rows: Vec<[u32; 4]> = (0..*per_lane).map(|i| std::array::from_fn(|k| lanes[k][i])).collect();
                        together.access_quad(simd, first_line, &rows, std::array::from_fn(|k| counted[k]));
                    }
                    for k in (0..if *pair { 8 } else { 4 }).filter(|&k| counted[k]) {
                        for &line in &lanes[k][..*per_lane] {
                            one_by_one.access(first_line + line as u64);
                        }
                    }
                    agree(&together, &one_by_one)?;
                }
            }
        }

        /// One level's footprints through the sampler's direct entry (`avx2::read_footprints`),
        /// a line a lane (nearest) or four (bilinear corners), count and leave the cache as the
        /// line-by-line model: groups all of one line (a nearest lookup within a block), within
        /// the last group's lines, or spread over several, of two textures, lanes counted or not.
        #[test]
        fn footprints_are_read_as_one_group(
            shape in prop::sample::select(vec![(1024u32, 64u32, 4u32), (16384, 64, 4), (256, 64, 1), (512, 16, 2)]),
            groups in prop::collection::vec(
                (
                    any::<bool>(),
                    0u64..2,
                    prop::sample::select(vec![0u32, 1, 5]),
                    0u32..4,
                    prop::collection::vec(0u32..3, 32),
                    prop::collection::vec(prop_oneof![4 => Just(true), 1 => Just(false)], 8),
                ),
                1..40,
            ),
        ) {
            #[cfg(target_arch = "x86_64")]
            if SimdSupport::detect(SimdLevel::Avx2).is_some() {
                let config = TextureCacheConfig { size_bytes: shape.0, line_bytes: shape.1, ways: shape.2 };
                let (mut together, mut one_by_one) = (TextureCache::new(config), LineByLine::new(config));
                for (nearest, texture, spread, base, steps, counted) in &groups {
                    let first_line = texture << 30;
                    // Lane k's line `r` of its footprint: one line for all when `spread` is 0.
                    let line = |r: usize, k: usize| base + spread * steps[4 * k + r];
                    let counted: [bool; 8] = std::array::from_fn(|k| counted[k]);
                    let lanes: Vec<Vec<u32>> = if *nearest {
                        let rows: [[u32; 8]; 1] = [std::array::from_fn(|k| line(0, k))];
                        // SAFETY: `SimdSupport::detect` found AVX2: this processor has every
                        // feature the function is compiled with.
                        unsafe { together.access_footprints_avx2(first_line, &rows, counted) };
                        (0..8).map(|k| vec![rows[0][k]]).collect()
                    } else {
                        let rows: [[u32; 8]; 4] = std::array::from_fn(|r| std::array::from_fn(|k| line(r, k)));
                        // SAFETY: as above.
                        unsafe { together.access_footprints_avx2(first_line, &rows, counted) };
                        (0..8).map(|k| rows.iter().map(|row| row[k]).collect()).collect()
                    };
                    for k in (0..8).filter(|&k| counted[k]) {
                        for &line in &lanes[k] {
                            one_by_one.access(first_line + line as u64);
                        }
                    }
                    agree(&together, &one_by_one)?;
                }
            }
        }

        /// Trilinear groups — a pair's footprints on one level (rows 0–3) and on the next
        /// (rows 4–7), the second level's lines after the first's as a mip chain stores them —
        /// count and leave the cache as the line-by-line model: the two levels' lines found
        /// apart and merged by first reads (`avx2::read_two_levels`), through `access_lanes`
        /// and the sampler's direct entry, with sets shared across the levels (lines 64 apart)
        /// or not, a line on both levels now and then, and more distinct lines than are
        /// checked together.
        #[test]
        fn two_levels_are_read_as_one_group(
            shape in prop::sample::select(vec![(1024u32, 64u32, 4u32), (16384, 64, 4), (512, 16, 2)]),
            groups in prop::collection::vec(
                (
                    prop::sample::select(vec![8u32, 64, 70]),
                    prop::collection::vec(prop_oneof![4 => 0u32..4, 1 => 0u32..40], 64),
                    prop::collection::vec(prop_oneof![4 => Just(true), 1 => Just(false)], 8),
                    any::<bool>(),
                ),
                1..30,
            ),
        ) {
            let config = TextureCacheConfig { size_bytes: shape.0, line_bytes: shape.1, ways: shape.2 };
            for simd in simd_levels() {
                let (mut together, mut one_by_one) = (TextureCache::new(config), LineByLine::new(config));
                for (far_start, lines, counted, direct) in &groups {
                    // Lane k's near corners step with k, as a footprint's blocks do.
                    let rows: [[u32; 8]; 8] = std::array::from_fn(|r| {
                        std::array::from_fn(|k| {
                            let line = lines[8 * k + r] + k as u32 / 2;
                            if r < 4 { line } else { line / 2 + far_start }
                        })
                    });
                    let counted: [bool; 8] = std::array::from_fn(|k| counted[k]);
                    #[cfg(target_arch = "x86_64")]
                    if *direct && simd.level() == SimdLevel::Avx2 {
                        // SAFETY: a `SimdSupport` of level `Avx2` exists only on a processor
                        // with every feature the function is compiled with.
                        unsafe { together.access_two_levels_avx2(simd, 7, &rows, counted) };
                    } else {
                        together.access_lanes(simd, 7, &rows, counted);
                    }
                    #[cfg(not(target_arch = "x86_64"))]
                    together.access_lanes(simd, 7, &rows, counted);
                    for k in (0..8).filter(|&k| counted[k]) {
                        for row in &rows {
                            one_by_one.access(7 + row[k] as u64);
                        }
                    }
                    agree(&together, &one_by_one)?;
                }
            }
        }
    }
}
