//! A set-associative, write-back, write-allocate cache with LRU replacement: the model behind
//! the framebuffer cache of an immediate-mode GPU. It decides which accesses reach external
//! memory; it never changes a value.
//!
//! Traffic: a miss fills a whole line (`line_bytes` read); evicting a dirty line writes it back
//! (`line_bytes` written); at the end, [`CacheModel::flush`] writes back every dirty line. A
//! cache of size 0 is no cache: every access is traffic of its own size.

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

    /// Checks the shape: power-of-two lines, whole sets.
    pub fn validate(&self, what: &str) -> Result<(), String> {
        if !self.is_enabled() {
            return Ok(());
        }
        if !self.line_bytes.is_power_of_two() || self.line_bytes < 4 || self.line_bytes > 4096 {
            return Err(format!("{what}: line size {} must be a power of two from 4 to 4096", self.line_bytes));
        }
        if self.ways == 0 || !self.size_bytes.is_multiple_of(self.line_bytes * self.ways) {
            return Err(format!(
                "{what}: {} bytes is not a whole number of {}-way sets of {}-byte lines",
                self.size_bytes, self.ways, self.line_bytes
            ));
        }
        if self.size_bytes > 64 << 20 {
            return Err(format!("{what}: {} bytes is more than the 64 MiB the model allows", self.size_bytes));
        }
        Ok(())
    }

    fn sets(&self) -> u32 {
        self.size_bytes / (self.line_bytes * self.ways)
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
    valid: bool,
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
}

impl CacheModel {
    pub fn new(config: CacheConfig) -> CacheModel {
        let lines = if config.is_enabled() { (config.sets() * config.ways) as usize } else { 0 };
        CacheModel { config, lines: vec![Line::default(); lines], clock: 0 }
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
        let line = address / line_bytes;
        let set = (line % self.config.sets() as u64) as usize;
        let ways = self.config.ways as usize;
        self.clock += 1;
        let slots = &mut self.lines[set * ways..(set + 1) * ways];
        if let Some(hit) = slots.iter_mut().find(|l| l.valid && l.tag == line) {
            hit.age = self.clock;
            hit.dirty |= write;
            return CacheTraffic { hit: bytes as u64, ..CacheTraffic::default() };
        }
        let victim = slots.iter_mut().min_by_key(|l| if l.valid { l.age } else { 0 }).expect("ways > 0");
        let mut traffic = CacheTraffic { read: line_bytes, ..CacheTraffic::default() };
        if victim.valid && victim.dirty {
            traffic.written = line_bytes;
            traffic.written_kind = victim.kind;
        }
        *victim = Line { tag: line, valid: true, dirty: write, kind, age: self.clock };
        traffic
    }

    /// Writes back every dirty line, leaving the cache clean; calls `written(kind, bytes)`
    /// for each.
    pub fn flush(&mut self, mut written: impl FnMut(u8, u64)) {
        let line_bytes = self.config.line_bytes as u64;
        for line in &mut self.lines {
            if line.valid && line.dirty {
                written(line.kind, line_bytes);
                line.dirty = false;
            }
        }
    }
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
        assert_eq!(c.access(0, 4, true, 1).read, 64);
        assert_eq!(c.access(8, 4, false, 1).hit, 4);
        assert_eq!(c.access(128, 4, false, 2).read, 64);
        // Line 4 evicts the least recently used line 0, which is dirty.
        let t = c.access(256, 4, false, 2);
        assert_eq!((t.read, t.written, t.written_kind), (64, 64, 1));
        assert_eq!(flushed(&mut c), 0);
        c.access(128, 4, true, 2);
        assert_eq!(flushed(&mut c), 64);
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
