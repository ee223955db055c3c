//! A set-associative, write-back cache with LRU replacement that allocates on write without
//! fetching ("write-validate", as GPU render caches do): the model behind the framebuffer
//! cache of an immediate-mode GPU. It decides which accesses reach external memory; it never
//! changes a value.
//!
//! Traffic: a line keeps a mask of the bytes it holds. A write allocates the line if needed and
//! marks its bytes valid and dirty, with no read. A read of bytes the line does not hold fills
//! the whole line (`line_bytes` read; bytes written since are kept). Evicting a dirty line
//! writes it back (`line_bytes` written: one burst with byte enables); at the end,
//! [`CacheModel::flush`] writes back every dirty line. A cache of size 0 is no cache: every
//! access is traffic of its own size.
//!
//! Write-validate matters: with write-allocate fills, a colour buffer written without blending
//! would be read from memory line by line only to be overwritten, and the cache would cost
//! more traffic than no cache at all.

use serde::{Deserialize, Serialize};

/// The shape of a cache.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct CacheConfig {
    /// Total bytes; 0 disables the cache.
    pub size_bytes: u32,
    /// Bytes per line (a power of two).
    pub line_bytes: u32,
    /// Lines per set.
    pub ways: u32,
}

impl CacheConfig {
    pub const NONE: CacheConfig = CacheConfig { size_bytes: 0, line_bytes: 64, ways: 1 };

    pub fn is_enabled(&self) -> bool {
        self.size_bytes > 0
    }

    /// The most lines a cache may have: the model keeps 32 bytes of state per line, so a cache
    /// model costs at most 32 MiB of host memory (64 MiB of 64-byte lines).
    pub const MAX_LINES: u32 = 1 << 20;

    /// Checks the shape: at most 64 MiB and [`CacheConfig::MAX_LINES`] lines, power-of-two lines,
    /// whole sets. Every product is computed in `u64`, so no shape overflows into a valid one.
    pub fn validate(&self, what: &str) -> Result<(), String> {
        if !self.is_enabled() {
            return Ok(());
        }
        if self.size_bytes > 64 << 20 {
            return Err(format!("{what}: {} bytes is more than the 64 MiB the model allows", self.size_bytes));
        }
        if !self.line_bytes.is_power_of_two() || self.line_bytes < 4 || self.line_bytes > 4096 {
            return Err(format!("{what}: line size {} must be a power of two from 4 to 4096", self.line_bytes));
        }
        let set_bytes = self.line_bytes as u64 * self.ways as u64;
        if self.ways == 0 || set_bytes > self.size_bytes as u64 || !(self.size_bytes as u64).is_multiple_of(set_bytes) {
            return Err(format!(
                "{what}: {} bytes is not a whole number of {}-way sets of {}-byte lines",
                self.size_bytes, self.ways, self.line_bytes
            ));
        }
        let lines = self.size_bytes / self.line_bytes;
        if lines > CacheConfig::MAX_LINES {
            return Err(format!(
                "{what}: {lines} lines of {} bytes is more than the {} lines the model allows",
                self.line_bytes,
                CacheConfig::MAX_LINES
            ));
        }
        Ok(())
    }

    /// Sets of a valid, enabled shape (`line_bytes × ways` divides `size_bytes`, so it fits).
    fn sets(&self) -> u32 {
        (self.size_bytes as u64 / (self.line_bytes as u64 * self.ways as u64)) as u32
    }
}

/// What an access cost in external memory.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CacheTraffic {
    /// Bytes read from external memory (line fills).
    pub read: u64,
    /// Bytes written to external memory (write-backs).
    pub written: u64,
    /// The kind of the line written back (see [`CacheModel::access`]).
    pub written_kind: u8,
    /// Bytes served from the cache.
    pub hit: u64,
}

#[derive(Clone, Copy, Debug, Default)]
struct Line {
    tag: u64,
    /// Which granules of the line it holds (bit i = granule i; a granule is
    /// `line_bytes / 64` bytes, at least one); 0 = an empty slot.
    valid: u64,
    dirty: bool,
    /// The caller's label for what the line holds (to attribute its write-back).
    kind: u8,
    /// Higher = more recently used.
    age: u64,
}

/// The state of one cache.
#[derive(Clone, Debug)]
pub struct CacheModel {
    config: CacheConfig,
    lines: Vec<Line>,
    clock: u64,
    /// `log2(line_bytes)` (line sizes are powers of two, [`CacheConfig::validate`]).
    line_shift: u32,
    /// `sets − 1` when the number of sets is a power of two (a mask instead of a division).
    set_mask: Option<u64>,
    sets: u64,
}

impl CacheModel {
    pub fn new(config: CacheConfig) -> CacheModel {
        debug_assert!(config.validate("cache").is_ok(), "invalid cache shape {config:?}");
        let lines = if config.is_enabled() { config.sets() as usize * config.ways as usize } else { 0 };
        let sets = if config.is_enabled() { config.sets().max(1) as u64 } else { 1 };
        CacheModel {
            config,
            lines: vec![Line::default(); lines],
            clock: 0,
            line_shift: config.line_bytes.max(1).trailing_zeros(),
            set_mask: sets.is_power_of_two().then_some(sets - 1),
            sets,
        }
    }

    pub fn config(&self) -> &CacheConfig {
        &self.config
    }

    /// An access of `bytes` at `address` (any address space the caller chooses; accesses
    /// must not cross a line). `kind` labels the data, so a later write-back can be
    /// attributed to it.
    pub fn access(&mut self, address: u64, bytes: u32, write: bool, kind: u8) -> CacheTraffic {
        if !self.config.is_enabled() {
            return if write {
                CacheTraffic { written: bytes as u64, written_kind: kind, ..CacheTraffic::default() }
            } else {
                CacheTraffic { read: bytes as u64, ..CacheTraffic::default() }
            };
        }
        let line_bytes = self.config.line_bytes as u64;
        // Shifts and masks: the line size is a power of two, and so, usually, the sets.
        let line = address >> self.line_shift;
        let mask = granules(address & (line_bytes - 1), bytes as u64, line_bytes);
        let full = granules(0, line_bytes, line_bytes);
        let set = match self.set_mask {
            Some(m) => line & m,
            None => line % self.sets,
        } as usize;
        let ways = self.config.ways as usize;
        self.clock += 1;
        let clock = self.clock;
        let slots = &mut self.lines[set * ways..(set + 1) * ways];
        let mut traffic = CacheTraffic::default();
        let slot = match slots.iter().position(|l| l.valid != 0 && l.tag == line) {
            Some(hit) => hit,
            None => {
                let (victim, _) = slots
                    .iter()
                    .enumerate()
                    .min_by_key(|(_, l)| if l.valid != 0 { l.age } else { 0 })
                    .expect("ways > 0");
                let old = slots[victim];
                if old.valid != 0 && old.dirty {
                    traffic.written = line_bytes;
                    traffic.written_kind = old.kind;
                }
                slots[victim] = Line { tag: line, valid: 0, dirty: false, kind, age: clock };
                victim
            }
        };
        let entry = &mut slots[slot];
        entry.age = clock;
        if write {
            entry.valid |= mask;
            entry.dirty = true;
            entry.kind = kind;
            traffic.hit = bytes as u64;
        } else if entry.valid & mask == mask {
            traffic.hit = bytes as u64;
        } else {
            traffic.read = line_bytes;
            entry.valid = full;
        }
        traffic
    }

    /// Writes back every dirty line, leaving the cache clean; calls `written(kind, bytes)`
    /// for each.
    pub fn flush(&mut self, mut written: impl FnMut(u8, u64)) {
        let line_bytes = self.config.line_bytes as u64;
        for line in &mut self.lines {
            if line.valid != 0 && line.dirty {
                written(line.kind, line_bytes);
                line.dirty = false;
            }
        }
    }
}

/// A read-only cache of the same shape and LRU replacement as [`CacheModel`], for streams
/// that are only read (vertex attributes): every line is whole or absent and never dirty, so
/// a set is its line numbers, most recently used first, and a read that hits the most recent
/// line of its set — consecutive vertices of one attribute stream — is one comparison. Its
/// fills are exactly [`CacheModel::access`]'s for the same reads (an LRU cache's misses
/// depend only on the order of the lines read).
#[derive(Clone, Debug)]
pub struct ReadCache {
    config: CacheConfig,
    line_shift: u32,
    ways: usize,
    /// `sets − 1` when the number of sets is a power of two.
    set_mask: Option<u64>,
    sets: u64,
    /// `sets × ways` line numbers, each set's most recently used first; [`ReadCache::EMPTY`]
    /// for an empty way.
    lines: Vec<u64>,
    /// The line read last, [`ReadCache::EMPTY`] when none: always the first (most recent) of
    /// its set, so reading it again hits and changes nothing — one comparison, before the
    /// set's index and slice (the attributes of one vertex, and consecutive vertices, mostly
    /// read one line: 4.5% of tris's time went to this model).
    last: u64,
}

impl ReadCache {
    /// An empty way (no line number reaches it: addresses are below 2⁶⁴).
    const EMPTY: u64 = u64::MAX;

    pub fn new(config: CacheConfig) -> ReadCache {
        debug_assert!(config.validate("cache").is_ok(), "invalid cache shape {config:?}");
        let (sets, ways) =
            if config.is_enabled() { (config.sets().max(1) as u64, config.ways as usize) } else { (1, 0) };
        ReadCache {
            config,
            line_shift: config.line_bytes.max(1).trailing_zeros(),
            ways,
            set_mask: sets.is_power_of_two().then_some(sets - 1),
            sets,
            lines: vec![ReadCache::EMPTY; sets as usize * ways],
            last: ReadCache::EMPTY,
        }
    }

    pub fn config(&self) -> &CacheConfig {
        &self.config
    }

    /// Empties the cache, keeping its memory.
    pub fn clear(&mut self) {
        self.lines.fill(ReadCache::EMPTY);
        self.last = ReadCache::EMPTY;
    }

    /// Reads `bytes` (at least 1) at `address`, which may cross lines; returns the bytes read
    /// from external memory: the lines filled, or `bytes` without a cache.
    #[inline]
    pub fn read(&mut self, address: u64, bytes: u64) -> u64 {
        if self.ways == 0 {
            return bytes;
        }
        let first = address >> self.line_shift;
        let last = (address + bytes.max(1) - 1) >> self.line_shift;
        let mut filled = 0;
        for line in first..=last {
            if !self.read_line(line) {
                filled += 1;
            }
        }
        filled << self.line_shift
    }

    /// Reads line `line`; returns whether it hit.
    #[inline]
    fn read_line(&mut self, line: u64) -> bool {
        if line == self.last {
            return true;
        }
        self.last = line;
        let set = match self.set_mask {
            Some(m) => line & m,
            None => line % self.sets,
        } as usize;
        let ways = &mut self.lines[set * self.ways..(set + 1) * self.ways];
        if ways[0] == line {
            return true;
        }
        // The line moves to the front and those more recent than it one way back; a missing
        // line comes in at the front and the least recently used (or an empty way) drops out
        // at the end. Carried way by way: `rotate_right` called the C library's `memmove` for
        // the three words of a 4-way set.
        let (moved, hit) = match ways.iter().position(|&l| l == line) {
            Some(way) => (&mut ways[..=way], true),
            None => (ways, false),
        };
        let mut carried = line;
        for way in moved {
            carried = std::mem::replace(way, carried);
        }
        hit
    }
}

/// The granule mask of `bytes` bytes at `offset` in a line of `line_bytes`.
fn granules(offset: u64, bytes: u64, line_bytes: u64) -> u64 {
    let granule = (line_bytes / 64).max(1);
    let first = offset / granule;
    let last = (offset + bytes.max(1) - 1).min(line_bytes - 1) / granule;
    let count = last - first + 1;
    let ones = if count >= 64 { u64::MAX } else { (1u64 << count) - 1 };
    ones << first
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fills_hits_and_write_backs() {
        let mut c = CacheModel::new(CacheConfig { size_bytes: 256, line_bytes: 64, ways: 2 });
        let flushed = |c: &mut CacheModel| {
            let mut total = 0;
            c.flush(|_, b| total += b);
            total
        };
        // Two sets of two ways. Lines 0, 2, 4 map to set 0.
        assert_eq!(c.access(0, 4, true, 1).read, 0, "a write allocates without a fill");
        assert_eq!(c.access(0, 4, false, 1).hit, 4, "bytes written are held");
        assert_eq!(c.access(8, 4, false, 1).read, 64, "bytes not written are fetched");
        assert_eq!(c.access(12, 4, false, 1).hit, 4, "the fill brought the whole line");
        assert_eq!(c.access(128, 4, false, 2).read, 64);
        // Line 4 evicts the least recently used line 0, which is dirty.
        let t = c.access(256, 4, false, 2);
        assert_eq!((t.read, t.written, t.written_kind), (64, 64, 1));
        assert_eq!(flushed(&mut c), 0);
        c.access(128, 4, true, 2);
        assert_eq!(flushed(&mut c), 64);
    }

    #[test]
    fn granules_cover_the_bytes_accessed() {
        assert_eq!(granules(0, 4, 64), 0b1111);
        assert_eq!(granules(60, 4, 64), 0b1111 << 60);
        assert_eq!(granules(0, 64, 64), u64::MAX);
        assert_eq!(granules(0, 4, 256), 0b1, "4-byte granules in a 256-byte line");
        assert_eq!(granules(6, 4, 256), 0b110);
        assert_eq!(granules(0, 16, 16), 0xffff);
    }

    #[test]
    fn a_colour_buffer_written_once_costs_its_size() {
        // Every 4-byte pixel of 64 KiB written once through a 4 KiB cache: one write-back per
        // line, no fills.
        let mut c = CacheModel::new(CacheConfig { size_bytes: 4096, line_bytes: 64, ways: 4 });
        let (mut read, mut written) = (0, 0);
        for address in (0..65536).step_by(4) {
            let t = c.access(address, 4, true, 0);
            read += t.read;
            written += t.written;
        }
        c.flush(|_, b| written += b);
        assert_eq!((read, written), (0, 65536));
    }

    /// The read-only cache fills exactly the lines the general model fills, read for read,
    /// over shapes with power-of-two and other set counts and reads that cross lines.
    #[test]
    fn the_read_cache_fills_what_the_model_fills() {
        let shapes = [
            CacheConfig { size_bytes: 4096, line_bytes: 64, ways: 4 },
            CacheConfig { size_bytes: 192, line_bytes: 64, ways: 1 },
            CacheConfig { size_bytes: 768, line_bytes: 32, ways: 8 },
            CacheConfig { size_bytes: 256, line_bytes: 16, ways: 16 },
            CacheConfig::NONE,
        ];
        for config in shapes {
            let mut model = CacheModel::new(config);
            let mut fast = ReadCache::new(config);
            let mut state = 12345u32;
            let (mut expected, mut got) = (0, 0);
            for _ in 0..20_000 {
                state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                // Mostly nearby addresses (hits), sometimes far ones (misses and evictions).
                let address = ((state >> 8) % if state & 3 == 0 { 1 << 20 } else { 2048 }) as u64;
                let bytes = 1 + (state >> 28) as u64;
                let line = config.line_bytes as u64;
                let mut a = address;
                while a < address + bytes {
                    let next = (address + bytes).min((a | (line - 1)) + 1);
                    expected += model.access(a, (next - a) as u32, false, 0).read;
                    a = next;
                }
                got += fast.read(address, bytes);
            }
            assert_eq!(got, expected, "{config:?}");
            assert!(expected > 0);
        }
    }

    #[test]
    fn no_cache_passes_every_access_through() {
        let mut c = CacheModel::new(CacheConfig::NONE);
        assert_eq!(c.access(0, 4, false, 0).read, 4);
        assert_eq!(c.access(0, 4, true, 0).written, 4);
        let mut n = 0;
        c.flush(|_, _| n += 1);
        assert_eq!(n, 0);
    }
}
