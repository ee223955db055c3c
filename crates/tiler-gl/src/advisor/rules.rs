//! The rules the advisor checks: one [`RuleId`] per rule, with its stable name, its severity
//! and the seed document and section it comes from. The check itself is one function, in
//! `pass.rs` (rules about one render pass) or `frame.rs` (rules about a frame's copies, stalls
//! and stores).

use tiler_finding::{Rule, Severity};

/// A rule the advisor checks. Its [`name`](RuleId::name) is the finding's stable id.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum RuleId {
    LoadAtPassStart,
    PartialClear,
    FramebufferRebound,
    FlushMidPass,
    StoreUnread,
    IncrementalRender,
    MicroTriangles,
    CopyOnWrite,
    PackedDepthStencilHalf,
    PreservedSwap,
    ReadbackStall,
    QueryStall,
    FinishStall,
    EarlyZDisabled,
    UnsortedOpaque,
    MsaaStored,
    PostProcessChain,
    SubpassSplit,
    DrawsDiscarded,
    MinifiedWithoutMipmaps,
    TileMemoryOverflow,
}

/// What the seed documents say about a rule.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RuleInfo {
    /// The stable id findings carry, e.g. `load-at-pass-start`.
    pub name: &'static str,
    /// `000` … `004`: the documents in `../shared/seeds/`.
    pub seed: &'static str,
    pub section: &'static str,
    /// The rule, in a sentence.
    pub text: &'static str,
}

impl RuleId {
    /// Every rule, in the order of the advisor's table.
    pub const ALL: [RuleId; 21] = [
        RuleId::LoadAtPassStart,
        RuleId::PartialClear,
        RuleId::FramebufferRebound,
        RuleId::FlushMidPass,
        RuleId::StoreUnread,
        RuleId::IncrementalRender,
        RuleId::MicroTriangles,
        RuleId::CopyOnWrite,
        RuleId::PackedDepthStencilHalf,
        RuleId::PreservedSwap,
        RuleId::ReadbackStall,
        RuleId::QueryStall,
        RuleId::FinishStall,
        RuleId::EarlyZDisabled,
        RuleId::UnsortedOpaque,
        RuleId::MsaaStored,
        RuleId::PostProcessChain,
        RuleId::SubpassSplit,
        RuleId::DrawsDiscarded,
        RuleId::MinifiedWithoutMipmaps,
        RuleId::TileMemoryOverflow,
    ];

    /// The stable id of the rule's findings.
    pub const fn name(self) -> &'static str {
        self.info().name
    }

    /// Draws thrown away cost nothing by themselves; everything else costs bytes, shading or
    /// latency.
    pub const fn severity(self) -> Severity {
        match self {
            RuleId::DrawsDiscarded => Severity::Info,
            _ => Severity::Warning,
        }
    }

    /// Whether what the rule's findings cost exists only on a tiler: tile loads and stores,
    /// work kept in the tile. An immediate-mode GPU reads and writes its framebuffers in
    /// memory at every fragment whatever the passes look like, so these cost it nothing and
    /// the advisor does not report them there: replayed on `imr`, the example pairs of these
    /// rules cost no more in their bad form than in their good one (`tests/gl/traces.rs`;
    /// clearing at the start and resolving in the tile even cost an IMR more). Stalls,
    /// copies on write, shading order, the fragments of a clear-quad and the geometry of
    /// micro-triangles cost every GPU.
    pub const fn tiler_only(self) -> bool {
        !matches!(
            self,
            RuleId::CopyOnWrite
                | RuleId::ReadbackStall
                | RuleId::QueryStall
                | RuleId::FinishStall
                | RuleId::EarlyZDisabled
                | RuleId::UnsortedOpaque
                | RuleId::DrawsDiscarded
                | RuleId::PartialClear
                | RuleId::MicroTriangles
                | RuleId::MinifiedWithoutMipmaps
        )
    }

    /// The rule as a finding cites it.
    pub fn rule(self) -> Rule {
        let info = self.info();
        Rule { seed: info.seed.to_string(), section: info.section.to_string(), text: info.text.to_string() }
    }

    /// The rule with this name.
    pub fn from_name(name: &str) -> Option<RuleId> {
        RuleId::ALL.into_iter().find(|r| r.name() == name)
    }

    /// The rule's name, source and text.
    pub const fn info(self) -> RuleInfo {
        match self {
            RuleId::LoadAtPassStart => RuleInfo {
                name: "load-at-pass-start",
                seed: "001, 000",
                section: "001 \"How to optimize render passes\"; 000 §23.3",
                text: "When starting a render pass, clear or invalidate every attachment, unless its previous contents are the starting point.",
            },
            RuleId::PartialClear => RuleInfo {
                name: "partial-clear",
                seed: "000, 001",
                section: "000 §23.3, Listing 23.1; 001 \"How to optimize render passes\"",
                text: "Clear colour, depth and stencil together with the scissor test off and every write mask on: a scissored, masked or partial clear is a draw, and the frame data cannot be thrown away.",
            },
            RuleId::FramebufferRebound => RuleInfo {
                name: "framebuffer-rebound",
                seed: "000, 001",
                section: "000 §23.5, §23.11; 001 \"Render pass steps to avoid\"",
                text: "Bind each framebuffer once per frame and submit all its commands before unbinding it.",
            },
            RuleId::FlushMidPass => RuleInfo {
                name: "flush-mid-pass",
                seed: "000, 001",
                section: "000 §23.5; 001 \"Render pass steps to avoid\"",
                text: "Do not split a render pass: reading pixels, copying, flushing, finishing or sampling the framebuffer mid-pass renders it early and the rest must reload what it stored.",
            },
            RuleId::StoreUnread => RuleInfo {
                name: "store-unread",
                seed: "000, 001, 004",
                section: "000 §23.3 (EXT_discard_framebuffer); 001 \"How to optimize render passes\"; 004 §24.3.2",
                text: "Invalidate attachments that are not needed after the pass (depth, above all) before unbinding, so they are never written out.",
            },
            RuleId::IncrementalRender => RuleInfo {
                name: "incremental-render",
                seed: "000",
                section: "000 §23.5, §23.10",
                text: "Keep a pass's geometry within the frame-data budget: past it the driver flushes and stores and reloads every attachment, depth, stencil and all samples — a performance cliff.",
            },
            RuleId::MicroTriangles => RuleInfo {
                name: "micro-triangles",
                seed: "000",
                section: "000 §23.2, §23.11",
                text: "Keep polygon counts reasonable and avoid micropolygons: every triangle costs frame data, written once and read by each tile it touches.",
            },
            RuleId::CopyOnWrite => RuleInfo {
                name: "copy-on-write",
                seed: "000",
                section: "000 §23.6",
                text: "Do not modify a buffer or texture a frame in flight still uses: the driver copies it. Update before use, orphan with a full buffer_data, or rotate copies.",
            },
            RuleId::PackedDepthStencilHalf => RuleInfo {
                name: "packed-depth-stencil-half",
                seed: "001",
                section: "001 \"Render pass steps to avoid\"",
                text: "Do not create a packed depth-stencil image and attach only one of its two halves: the other half must be loaded and stored with it.",
            },
            RuleId::PreservedSwap => RuleInfo {
                name: "preserved-swap",
                seed: "000",
                section: "000 §23.4",
                text: "A preserved back buffer must be loaded into every tile each frame; redraw the frame, or update only the region that changes with QCOM_tiled_rendering.",
            },
            RuleId::ReadbackStall => RuleInfo {
                name: "readback-stall",
                seed: "000",
                section: "000 §23.6",
                text: "Synchronous read_pixels stalls the CPU until the GPU catches up; read a framebuffer rendered frames in flight ago (rotate framebuffers).",
            },
            RuleId::QueryStall => RuleInfo {
                name: "query-stall",
                seed: "000",
                section: "000 §23.6",
                text: "Asking for an occlusion query's result before it is available stalls the pipeline: poll query_available, or read it frames in flight later.",
            },
            RuleId::FinishStall => RuleInfo {
                name: "finish-stall",
                seed: "000, 001",
                section: "000 §23.6; 001 \"Render pass steps to avoid\"",
                text: "finish waits for every frame in flight: the CPU and GPU stop overlapping.",
            },
            RuleId::EarlyZDisabled => RuleInfo {
                name: "early-z-disabled",
                seed: "000, 002",
                section: "000 §23.7; 002 \"Depth Testing Optimizations\"",
                text: "A shader that may discard (alpha test) or write depth is depth-tested after shading: hidden fragments are shaded. Use it only on the objects that need it.",
            },
            RuleId::UnsortedOpaque => RuleInfo {
                name: "unsorted-opaque",
                seed: "000",
                section: "000 §23.7, §23.11",
                text: "Without hidden-surface removal, submit opaque objects front to back so early depth tests reject hidden fragments before shading.",
            },
            RuleId::MsaaStored => RuleInfo {
                name: "msaa-stored",
                seed: "000, 004",
                section: "000 §23.9, §23.3; 004 §24.3.3",
                text: "Resolve multisampled images in the tile and never store the samples: multisampling is then free in bandwidth.",
            },
            RuleId::PostProcessChain => RuleInfo {
                name: "post-process-chain",
                seed: "002, 000",
                section: "002 \"Optimizing for TBR\" (subpasses); 000 §23.5",
                text: "A full-screen pass that only reads the previous pass's colour could be folded into it (or be a subpass reading an input attachment), keeping the intermediate image on chip.",
            },
            RuleId::SubpassSplit => RuleInfo {
                name: "subpass-split",
                seed: "002",
                section: "002 \"Optimizing for TBR\" (subpasses), \"Best Practices for TBR\"",
                text: "Make a subpass dependency by-region when each pixel reads only its own pixel of what the earlier subpass wrote (input attachments): otherwise a tiler must split the pass and store and reload every attachment, transient ones included, through memory.",
            },
            RuleId::DrawsDiscarded => RuleInfo {
                name: "draws-discarded",
                seed: "000",
                section: "000 §23.10",
                text: "A full clear after draws throws those draws away before they are rendered.",
            },
            RuleId::MinifiedWithoutMipmaps => RuleInfo {
                name: "minified-without-mipmaps",
                seed: "004",
                section: "004 §24.3.4, §24.3.5",
                text: "Give textures that are drawn smaller than they are mip maps and a mipmapped minification filter: read from level 0, neighbouring pixels fall on different cache lines and almost every texel is fetched from memory, while a smaller level hits in the texture cache.",
            },
            RuleId::TileMemoryOverflow => RuleInfo {
                name: "tile-memory-overflow",
                seed: "000, 001",
                section: "000 §23.1, §23.9; 001 \"How to optimize render passes\"",
                text: "Keep a pass's attachments, at every sample, within the tile memory: a GPU shrinks the tile to fit them, and where even its smallest tile cannot hold them the pass cannot stay on chip.",
            },
        }
    }
}

impl std::fmt::Display for RuleId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::RuleId;

    #[test]
    fn every_rule_has_its_own_name_and_a_source() {
        for (i, rule) in RuleId::ALL.iter().enumerate() {
            assert_eq!(RuleId::from_name(rule.name()), Some(*rule));
            assert!(RuleId::ALL[..i].iter().all(|r| r != rule), "{rule} listed twice");
            let info = rule.info();
            assert!(!info.seed.is_empty() && !info.section.is_empty() && !info.text.is_empty(), "{rule}");
        }
        assert_eq!(RuleId::from_name("no-such-rule"), None);
    }
}
