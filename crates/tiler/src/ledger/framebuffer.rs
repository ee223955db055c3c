//! Where the pixel pipeline's depth, stencil and colour accesses go: the tile buffer (on chip,
//! a tiler), external memory (an immediate-mode GPU without a framebuffer cache), or external
//! memory behind a framebuffer cache.
//!
//! Formulas: on chip, each access adds its bytes to the on-chip figure used for energy. In
//! external memory without a cache, each access is its own traffic: a depth test reads the
//! depth aspect of the sample (`ImrDepthRead`), a passing write writes it (`ImrDepthWrite`),
//! likewise stencil and colour (a colour read only for blending or a partial write mask).
//! With a cache ([`super::cache`]), only line fills (`…Read` of the access's aspect) and
//! write-backs (`…Write` of the line's attachment: colour, or depth for a depth-stencil
//! attachment) reach external memory, and every access is on-chip traffic.

use super::cache::{CacheConfig, CacheModel};
use super::{Category, Ledger};

/// The aspect of an attachment an access touches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Aspect {
    Color,
    Depth,
    Stencil,
}

impl Aspect {
    fn read_category(self) -> Category {
        match self {
            Aspect::Color => Category::ImrColorRead,
            Aspect::Depth => Category::ImrDepthRead,
            Aspect::Stencil => Category::ImrStencilRead,
        }
    }

    fn write_category(self) -> Category {
        match self {
            Aspect::Color => Category::ImrColorWrite,
            Aspect::Depth => Category::ImrDepthWrite,
            Aspect::Stencil => Category::ImrStencilWrite,
        }
    }

    /// The label of cache lines: what a write-back of the line counts as.
    fn line_kind(self) -> u8 {
        match self {
            Aspect::Color => 0,
            Aspect::Depth | Aspect::Stencil => 1,
        }
    }

    fn of_line_kind(kind: u8) -> Aspect {
        if kind == 0 { Aspect::Color } else { Aspect::Depth }
    }
}

#[derive(Debug)]
enum Memory {
    OnChip,
    External,
    Cached(Box<CacheModel>),
}

/// The memory behind one task's attachments, and what its accesses cost.
#[derive(Debug)]
pub struct FramebufferTraffic {
    memory: Memory,
    /// Bytes moved within on-chip memory (tile buffer or cache) by the pixel pipeline.
    pub on_chip_bytes: u64,
}

impl Default for FramebufferTraffic {
    fn default() -> FramebufferTraffic {
        FramebufferTraffic::on_chip()
    }
}

impl FramebufferTraffic {
    /// A tiler's tile buffer.
    pub fn on_chip() -> FramebufferTraffic {
        FramebufferTraffic { memory: Memory::OnChip, on_chip_bytes: 0 }
    }

    /// An immediate-mode GPU's framebuffer in external memory, behind `cache` if enabled.
    pub fn external(cache: CacheConfig) -> FramebufferTraffic {
        let memory =
            if cache.is_enabled() { Memory::Cached(Box::new(CacheModel::new(cache))) } else { Memory::External };
        FramebufferTraffic { memory, on_chip_bytes: 0 }
    }

    pub fn is_on_chip(&self) -> bool {
        matches!(self.memory, Memory::OnChip)
    }

    /// One access of `bytes` at `address` in the attachment's memory.
    #[inline]
    pub fn access(&mut self, ledger: &mut Ledger, aspect: Aspect, address: u64, bytes: u32, write: bool) {
        match &mut self.memory {
            Memory::OnChip => self.on_chip_bytes += bytes as u64,
            Memory::External => {
                let category = if write { aspect.write_category() } else { aspect.read_category() };
                ledger.add(category, bytes as u64);
            }
            Memory::Cached(cache) => {
                let t = cache.access(address, bytes, write, aspect.line_kind());
                self.on_chip_bytes += bytes as u64;
                ledger.add(aspect.read_category(), t.read);
                if t.written > 0 {
                    ledger.add(Aspect::of_line_kind(t.written_kind).write_category(), t.written);
                }
            }
        }
    }

    /// Whether accesses must be made one by one with their addresses (a cache model); when
    /// not, [`FramebufferTraffic::accesses`] counts many at once.
    #[inline(always)]
    pub fn needs_addresses(&self) -> bool {
        matches!(self.memory, Memory::Cached(_))
    }

    /// `count` accesses of `bytes` each, without a cache model.
    #[inline(always)]
    pub fn accesses(&mut self, ledger: &mut Ledger, aspect: Aspect, bytes: u32, count: u64, write: bool) {
        debug_assert!(!self.needs_addresses());
        let total = bytes as u64 * count;
        match self.memory {
            Memory::OnChip => self.on_chip_bytes += total,
            _ => ledger.add(if write { aspect.write_category() } else { aspect.read_category() }, total),
        }
    }

    /// Writes back what a cache still holds dirty (the end of a pass).
    pub fn finish(&mut self, ledger: &mut Ledger) {
        if let Memory::Cached(cache) = &mut self.memory {
            cache.flush(|kind, bytes| ledger.add(Aspect::of_line_kind(kind).write_category(), bytes));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_memory_counts_its_way() {
        let mut ledger = Ledger::default();
        let mut chip = FramebufferTraffic::on_chip();
        chip.access(&mut ledger, Aspect::Depth, 0, 4, false);
        assert_eq!((ledger.total(), chip.on_chip_bytes), (0, 4));
        let mut raw = FramebufferTraffic::external(CacheConfig::NONE);
        raw.access(&mut ledger, Aspect::Depth, 0, 4, false);
        raw.access(&mut ledger, Aspect::Color, 0, 4, true);
        assert_eq!(ledger.get(Category::ImrDepthRead), 4);
        assert_eq!(ledger.get(Category::ImrColorWrite), 4);
        let mut ledger = Ledger::default();
        let mut cached = FramebufferTraffic::external(CacheConfig { size_bytes: 1024, line_bytes: 64, ways: 4 });
        for i in 0..16 {
            cached.access(&mut ledger, Aspect::Color, i * 4, 4, true);
        }
        assert_eq!(ledger.get(Category::ImrColorRead), 0, "written lines are not filled");
        cached.access(&mut ledger, Aspect::Depth, 64, 4, false);
        assert_eq!(ledger.get(Category::ImrDepthRead), 64, "a read fills its line");
        cached.finish(&mut ledger);
        assert_eq!(ledger.get(Category::ImrColorWrite), 64, "one write-back");
        assert_eq!(ledger.get(Category::ImrDepthWrite), 0, "a clean line is not written back");
    }
}
