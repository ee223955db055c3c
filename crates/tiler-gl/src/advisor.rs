//! The advisor: reads what a run did (its frames, passes, stalls and copies) and reports each
//! pattern the seed documents warn about, with the rule behind it, the frame, pass and call at
//! fault, what it cost in that frame, and what to do instead.
//!
//! Costs are exact where the fix only removes traffic: the bytes a finding reports are the
//! bytes the same frame would not move with the fix (the example trace pairs check this). The
//! rules and their ids are listed in [`RULES`]; ids are stable.
//!
//! | id | rule (seed §) | cost |
//! |---|---|---|
//! | `load-at-pass-start` | 001 "How to optimize render passes"; 000 §23.3 | the loads |
//! | `partial-clear` | 000 §23.3 (Listing 23.1); 001 | loads it kept + the clear-quad's frame data; fragments |
//! | `framebuffer-rebound` | 000 §23.5, §23.11; 001 "steps to avoid" | reloads + the stores they read |
//! | `flush-mid-pass` | 000 §23.5; 001 "steps to avoid" | reloads + the stores they read |
//! | `store-unread` | 000 §23.3 (discard); 001; 004 §24.3.2 | the stores |
//! | `incremental-render` | 000 §23.5, §23.10 | the extra loads and stores |
//! | `micro-triangles` | 000 §23.2, §23.11 | the pass's geometry and frame-data bytes |
//! | `copy-on-write` | 000 §23.6 | the copies |
//! | `packed-depth-stencil-half` | 001 "steps to avoid" | loads and stores of the other half |
//! | `preserved-swap` | 000 §23.4 | the window load + stores outside what was drawn |
//! | `readback-stall`, `query-stall`, `finish-stall` | 000 §23.6 | frames of lost pipelining |
//! | `early-z-disabled` | 000 §23.7; 002 "Depth Testing Optimizations" | fragments shaded then killed |
//! | `unsorted-opaque` | 000 §23.7, §23.11 | fragments shaded beyond one per pixel |
//! | `msaa-stored` | 000 §23.9, §23.3; 004 §24.3.3 | the multisampled stores |
//! | `post-process-chain` | 002 "Optimizing for TBR" (subpasses); 000 §23.5 | the intermediate store |
//! | `subpass-split` | 002 "Optimizing for TBR", "Best Practices for TBR" | the split's stores and reloads |
//! | `draws-discarded` (info) | 000 §23.10 | — |

use serde::Serialize;
use tiler::binning::frame_data::{POLYGON_LIST_ENTRY_BYTES, STATE_RECORD_BYTES, primitive_record_bytes};
use tiler::{Category, Rect};

use crate::context::ContextConfig;
use crate::report::{
    CallRef, DrawKind, EndCause, FrameRecord, LoadKind, PassRecord, Role, Slot, StallCause, StartCause, StoreKind,
};

/// How much a finding matters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Severity {
    /// Costs bandwidth, shading or latency that the application can avoid.
    Warning,
    /// Worth knowing; costs nothing by itself.
    Info,
}

/// The seed rule behind a finding.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Rule {
    pub id: &'static str,
    /// `000` … `004`: the document in `../shared/seeds/`.
    pub seed: &'static str,
    pub section: &'static str,
    /// The rule, in a sentence.
    pub text: &'static str,
}

/// Every rule the advisor checks.
pub const RULES: [Rule; 19] = [
    Rule {
        id: "load-at-pass-start",
        seed: "001, 000",
        section: "001 \"How to optimize render passes\"; 000 §23.3",
        text: "When starting a render pass, clear or invalidate every attachment, unless its previous contents are the starting point.",
    },
    Rule {
        id: "partial-clear",
        seed: "000, 001",
        section: "000 §23.3, Listing 23.1; 001 \"How to optimize render passes\"",
        text: "Clear colour, depth and stencil together with the scissor test off and every write mask on: a scissored, masked or partial clear is a draw, and the frame data cannot be thrown away.",
    },
    Rule {
        id: "framebuffer-rebound",
        seed: "000, 001",
        section: "000 §23.5, §23.11; 001 \"Render pass steps to avoid\"",
        text: "Bind each framebuffer once per frame and submit all its commands before unbinding it.",
    },
    Rule {
        id: "flush-mid-pass",
        seed: "000, 001",
        section: "000 §23.5; 001 \"Render pass steps to avoid\"",
        text: "Do not split a render pass: reading pixels, copying, flushing, finishing or sampling the framebuffer mid-pass renders it early and the rest must reload what it stored.",
    },
    Rule {
        id: "store-unread",
        seed: "000, 001, 004",
        section: "000 §23.3 (EXT_discard_framebuffer); 001 \"How to optimize render passes\"; 004 §24.3.2",
        text: "Invalidate attachments that are not needed after the pass (depth, above all) before unbinding, so they are never written out.",
    },
    Rule {
        id: "incremental-render",
        seed: "000",
        section: "000 §23.5, §23.10",
        text: "Keep a pass's geometry within the frame-data budget: past it the driver flushes and stores and reloads every attachment, depth, stencil and all samples — a performance cliff.",
    },
    Rule {
        id: "micro-triangles",
        seed: "000",
        section: "000 §23.2, §23.11",
        text: "Keep polygon counts reasonable and avoid micropolygons: every triangle costs frame data, written once and read by each tile it touches.",
    },
    Rule {
        id: "copy-on-write",
        seed: "000",
        section: "000 §23.6",
        text: "Do not modify a buffer or texture a frame in flight still uses: the driver copies it. Update before use, orphan with a full buffer_data, or rotate copies.",
    },
    Rule {
        id: "packed-depth-stencil-half",
        seed: "001",
        section: "001 \"Render pass steps to avoid\"",
        text: "Do not create a packed depth-stencil image and attach only one of its two halves: the other half must be loaded and stored with it.",
    },
    Rule {
        id: "preserved-swap",
        seed: "000",
        section: "000 §23.4",
        text: "A preserved back buffer must be loaded into every tile each frame; redraw the frame, or update only the region that changes with QCOM_tiled_rendering.",
    },
    Rule {
        id: "readback-stall",
        seed: "000",
        section: "000 §23.6",
        text: "Synchronous read_pixels stalls the CPU until the GPU catches up; read a framebuffer rendered frames in flight ago (rotate framebuffers).",
    },
    Rule {
        id: "query-stall",
        seed: "000",
        section: "000 §23.6",
        text: "Asking for an occlusion query's result before it is available stalls the pipeline: poll query_available, or read it frames in flight later.",
    },
    Rule {
        id: "finish-stall",
        seed: "000, 001",
        section: "000 §23.6; 001 \"Render pass steps to avoid\"",
        text: "finish waits for every frame in flight: the CPU and GPU stop overlapping.",
    },
    Rule {
        id: "early-z-disabled",
        seed: "000, 002",
        section: "000 §23.7; 002 \"Depth Testing Optimizations\"",
        text: "A shader that may discard (alpha test) or write depth is depth-tested after shading: hidden fragments are shaded. Use it only on the objects that need it.",
    },
    Rule {
        id: "unsorted-opaque",
        seed: "000",
        section: "000 §23.7, §23.11",
        text: "Without hidden-surface removal, submit opaque objects front to back so early depth tests reject hidden fragments before shading.",
    },
    Rule {
        id: "msaa-stored",
        seed: "000, 004",
        section: "000 §23.9, §23.3; 004 §24.3.3",
        text: "Resolve multisampled images in the tile and never store the samples: multisampling is then free in bandwidth.",
    },
    Rule {
        id: "post-process-chain",
        seed: "002, 000",
        section: "002 \"Optimizing for TBR\" (subpasses); 000 §23.5",
        text: "A full-screen pass that only reads the previous pass's colour could be folded into it (or be a subpass reading an input attachment), keeping the intermediate image on chip.",
    },
    Rule {
        id: "subpass-split",
        seed: "002",
        section: "002 \"Optimizing for TBR\" (subpasses), \"Best Practices for TBR\"",
        text: "Make a subpass dependency by-region when each pixel reads only its own pixel of what the earlier subpass wrote (input attachments): otherwise a tiler must split the pass and store and reload every attachment, transient ones included, through memory.",
    },
    Rule {
        id: "draws-discarded",
        seed: "000",
        section: "000 §23.10",
        text: "A full clear after draws throws those draws away before they are rendered.",
    },
];

/// The rule with this id.
pub fn rule(id: &str) -> Rule {
    *RULES.iter().find(|r| r.id == id).unwrap_or_else(|| panic!("no advisor rule '{id}'"))
}

/// What a finding costs in its frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Cost {
    /// External-memory bytes the fix would save.
    pub bytes: u64,
    /// Fragments shaded that the fix would not shade.
    pub fragments: u64,
    /// Frames of pipelining lost to a stall.
    pub stall_frames: u32,
}

/// One finding.
#[derive(Clone, Debug, Serialize)]
pub struct Finding {
    /// Stable id of the rule (see [`RULES`]).
    pub id: &'static str,
    pub severity: Severity,
    pub rule: Rule,
    pub frame: u32,
    /// The render pass at fault (a global pass index), if one is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pass: Option<u32>,
    /// The call at fault, if one is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub call: Option<CallRef>,
    pub cost: Cost,
    /// What happened, with the numbers.
    pub detail: String,
    /// What to do instead.
    pub fix: String,
}

/// Rendered fragments per primitive below which a pass counts as micro-triangles.
pub const MICRO_TRIANGLE_FRAGMENTS: f64 = 2.0;
/// Primitives a pass needs before micro-triangles are worth a finding.
pub const MICRO_TRIANGLE_MIN_PRIMITIVES: u64 = 1000;
/// Share of a pass's shaded fragments the discarding draws must have ("most of the frame").
pub const EARLY_Z_SHARE: f64 = 0.5;
/// The most draws a pass may have to count as a full-screen effect over the previous pass.
pub const POST_PROCESS_MAX_DRAWS: usize = 2;
/// Overdraw of opaque geometry (shaded fragments per pixel) above which its order matters.
pub const UNSORTED_OVERDRAW: f64 = 1.25;

/// Runs every rule over a run's frames.
pub fn advise(config: &ContextConfig, frames: &[FrameRecord]) -> Vec<Finding> {
    let mut out = Vec::new();
    let passes: Vec<&PassRecord> = frames.iter().flat_map(|f| f.passes.iter()).collect();
    for (i, pass) in passes.iter().enumerate() {
        let earlier = &passes[..i];
        pass_findings(config, pass, earlier, &mut out);
        msaa_stored(pass, &passes[i + 1..], &mut out);
    }
    for frame in frames {
        frame_findings(frame, &passes, &mut out);
    }
    out.sort_by_key(|f| (f.frame, f.pass, f.call, f.id));
    out
}

fn finding(
    id: &'static str,
    pass: &PassRecord,
    call: Option<CallRef>,
    cost: Cost,
    detail: String,
    fix: String,
) -> Finding {
    Finding {
        id,
        severity: if id == "draws-discarded" { Severity::Info } else { Severity::Warning },
        rule: rule(id),
        frame: pass.frame,
        pass: Some(pass.index),
        call,
        cost,
        detail,
        fix,
    }
}

fn bytes(n: u64) -> String {
    if n >= 10_000_000 {
        format!("{:.1} MB", n as f64 / 1e6)
    } else if n >= 10_000 {
        format!("{:.1} kB", n as f64 / 1e3)
    } else {
        format!("{n} B")
    }
}

fn slots(list: &[Slot]) -> String {
    list.iter().map(|s| s.to_string()).collect::<Vec<_>>().join(", ")
}

/// The findings about one pass; `earlier` are the passes rendered before it.
fn pass_findings(config: &ContextConfig, pass: &PassRecord, earlier: &[&PassRecord], out: &mut Vec<Finding>) {
    let same_framebuffer_before = earlier
        .iter()
        .rev()
        .find(|p| p.frame == pass.frame && p.framebuffer == pass.framebuffer && p.copy_texture.is_none());
    let fb = if pass.framebuffer == 0 { "the window".to_string() } else { format!("framebuffer {}", pass.framebuffer) };

    let rebound = matches!(pass.start, StartCause::Bind | StartCause::NewFrame)
        && same_framebuffer_before.is_some_and(|q| q.end == EndCause::Bind);
    let fresh_start = matches!(pass.start, StartCause::Bind | StartCause::NewFrame) && !rebound;

    // Slots a clear-quad at the start covers: their loads are the partial clear's cost.
    let mut partial_at_start: Vec<Slot> = Vec::new();
    for d in &pass.draws {
        let Some(pc) = &d.partial_clear else { continue };
        let mut cost = quad_frame_data_bytes(pass, d.clip_rect, d.stats.primitives);
        let mut kept = Vec::new();
        if pc.at_start {
            for slot in &pc.slots {
                if let Some(a) = pass.attachment(*slot)
                    && a.load == LoadKind::Load
                    && fresh_start
                    && !partial_at_start.contains(slot)
                {
                    cost += a.load_bytes;
                    kept.push(*slot);
                    partial_at_start.push(*slot);
                }
            }
        }
        let loads = if kept.is_empty() {
            String::new()
        } else {
            format!(
                " and keeps the load of {} ({})",
                slots(&kept),
                bytes(kept.iter().filter_map(|s| pass.attachment(*s)).map(|a| a.load_bytes).sum())
            )
        };
        out.push(finding(
            "partial-clear",
            pass,
            Some(d.call),
            Cost { bytes: cost, fragments: d.stats.fragments_shaded, stall_frames: 0 },
            format!(
                "the clear at {} of {} on {fb} is drawn as a clear-quad because {}: it shades {} fragments, writes \
                 and reads frame data{loads}",
                d.call,
                slots(&pc.slots),
                pc.reasons.join(" and "),
                d.stats.fragments_shaded
            ),
            "disable the scissor test and set every write mask before clearing, and clear colour, depth and stencil \
             together at the start of the pass (Listing 23.1)"
                .to_string(),
        ));
    }

    // Loads at the start of a pass.
    match pass.start {
        StartCause::AfterFlush { flush } => {
            if let Some(q) = same_framebuffer_before {
                let (cost, what) = reload_cost(pass, q);
                if cost > 0 {
                    out.push(finding(
                        "flush-mid-pass",
                        q,
                        Some(q.ended_at),
                        Cost { bytes: cost, ..Cost::default() },
                        format!(
                            "{} at {} flushed the pass on {fb}: it stored {what} and the rest of the frame's \
                             drawing (pass {}) reloads them",
                            flush.describe(),
                            q.ended_at,
                            pass.index
                        ),
                        "move the read-back, copy or flush after all drawing to this framebuffer (the end of the \
                         frame), or read a framebuffer finished frames ago"
                            .to_string(),
                    ));
                }
            }
        }
        _ if rebound => {
            let q = same_framebuffer_before.expect("rebound");
            let (cost, what) = reload_cost(pass, q);
            if cost > 0 {
                out.push(finding(
                    "framebuffer-rebound",
                    pass,
                    Some(pass.started_at),
                    Cost { bytes: cost, ..Cost::default() },
                    format!(
                        "{fb} is bound again at {} after pass {} ended at {}: pass {} stored {what} and this pass \
                         reloads them",
                        pass.started_at, q.index, q.ended_at, q.index
                    ),
                    format!(
                        "do everything for {fb} in one binding: render the other framebuffers first (e.g. \
                         render-to-texture before the scene that uses it)"
                    ),
                ));
            }
        }
        StartCause::Bind | StartCause::NewFrame | StartCause::BeginPass => {
            let mut loaded = Vec::new();
            let mut cost = 0;
            let mut window_cost = 0;
            for a in pass.attachments.iter().filter(|a| a.load == LoadKind::Load && a.role == Role::Attached) {
                if partial_at_start.contains(&a.slot) {
                    continue;
                }
                if pass.window_preserved && matches!(a.slot, Slot::Color(_)) {
                    window_cost += a.load_bytes;
                    continue;
                }
                loaded.push(a.slot);
                cost += a.load_bytes;
            }
            if cost > 0 {
                out.push(finding(
                    "load-at-pass-start",
                    pass,
                    Some(pass.started_at),
                    Cost { bytes: cost, ..Cost::default() },
                    format!(
                        "pass {} on {fb} starts by loading {} ({}) because nothing cleared or invalidated them first",
                        pass.index,
                        slots(&loaded),
                        bytes(cost)
                    ),
                    format!(
                        "clear {} (or invalidate them) right after binding {fb}, unless the previous contents are \
                         the starting point",
                        slots(&loaded)
                    ),
                ));
            }
            if window_cost > 0 {
                preserved_swap(pass, window_cost, out);
            }
        }
        StartCause::Tiling | StartCause::Copy => {}
    }

    // The other half of a packed depth-stencil image.
    let preserved: Vec<_> = pass.attachments.iter().filter(|a| a.role == Role::Preserved).collect();
    if !preserved.is_empty() {
        let cost: u64 = preserved.iter().map(|a| a.load_bytes + a.store_bytes).sum();
        let half = preserved.iter().map(|a| a.slot).collect::<Vec<_>>();
        out.push(finding(
            "packed-depth-stencil-half",
            pass,
            Some(pass.started_at),
            Cost { bytes: cost, ..Cost::default() },
            format!(
                "{fb} attaches only one half of packed {} image {}; its {} must be loaded and stored with it",
                preserved[0].gl_format.name(),
                preserved[0].image.to_string().trim_start_matches("image "),
                slots(&half)
            ),
            "attach the image at depth_stencil, or use a depth-only format (depth16, depth24, depth32f) when no \
             stencil is needed"
                .to_string(),
        ));
    }

    // Subpass dependencies that are not by-region: the pass split through memory.
    let splits = pass.cost.counters.subpass_splits;
    if splits > 0 {
        // What the split moved beyond the pass's own loads and stores; when incremental
        // renders also stored and reloaded, the two cannot be told apart and the cost is theirs.
        let planned: u64 = pass.attachments.iter().map(|a| a.load_bytes + a.store_bytes).sum();
        let moved = pass.cost.ledger.get(Category::TileLoad) + pass.cost.ledger.get(Category::TileStore);
        let extra = if pass.cost.counters.incremental_renders == 0 { moved.saturating_sub(planned) } else { 0 };
        let deps: Vec<String> = pass
            .dependencies
            .iter()
            .filter(|d| !d.by_region)
            .map(|d| format!("subpass {} → {}", d.src, d.dst))
            .collect();
        let cost_text = if extra > 0 {
            format!("{} more than the pass's own loads and stores", bytes(extra))
        } else {
            "its cost is counted with the pass's incremental renders".to_string()
        };
        out.push(finding(
            "subpass-split",
            pass,
            Some(pass.started_at),
            Cost { bytes: extra, ..Cost::default() },
            format!(
                "the dependency {} of the explicit pass {} on {fb} (begun at {}) is not by-region, so the tiler \
                 split the pass {splits} time(s): every tile stored every attachment — the transient ones through \
                 spill memory they would not otherwise need — and reloaded them for the next subpass; {cost_text}",
                deps.join(", "),
                pass.index,
                pass.started_at
            ),
            "set \"by_region\": true on the dependency when each pixel of the later subpass reads only its own pixel \
             of what the earlier one wrote (input attachments always do); only reads of other pixels need the split"
                .to_string(),
        ));
    }

    // Incremental renders.
    let incremental = pass.cost.counters.incremental_renders;
    if incremental > 0 {
        let planned: u64 = pass.attachments.iter().map(|a| a.load_bytes + a.store_bytes).sum();
        let moved = pass.cost.ledger.get(Category::TileLoad) + pass.cost.ledger.get(Category::TileStore);
        let extra = moved.saturating_sub(planned);
        out.push(finding(
            "incremental-render",
            pass,
            Some(pass.ended_at),
            Cost { bytes: extra, ..Cost::default() },
            format!(
                "the frame data of pass {} on {fb} outgrew its budget ({} bytes) {incremental} time(s): each time every \
                 attachment — depth, stencil and all {} sample(s) — was stored and reloaded, {} more than the pass's \
                 own loads and stores",
                pass.index,
                config.frame_data_budget,
                pass.samples,
                bytes(extra)
            ),
            "draw less geometry in the pass (level of detail, culling), or split it across frames".to_string(),
        ));
    }

    // Micro-triangles.
    let counters = &pass.cost.counters;
    if counters.primitives >= MICRO_TRIANGLE_MIN_PRIMITIVES {
        let per = counters.fragments_rasterized as f64 / counters.primitives as f64;
        if per < MICRO_TRIANGLE_FRAGMENTS {
            let l = &pass.cost.ledger;
            let cost = l.get(Category::FrameDataWrite)
                + l.get(Category::FrameDataRead)
                + l.get(Category::VertexFetch)
                + l.get(Category::IndexFetch);
            out.push(finding(
                "micro-triangles",
                pass,
                pass.draws.iter().max_by_key(|d| d.stats.primitives).map(|d| d.call),
                Cost { bytes: cost, ..Cost::default() },
                format!(
                    "pass {} on {fb} sets up {} primitives that cover {per:.2} pixels each on average: its geometry and \
                     frame data cost {}",
                    pass.index,
                    counters.primitives,
                    bytes(cost)
                ),
                format!(
                    "use coarser meshes (level of detail) so triangles cover at least {MICRO_TRIANGLE_FRAGMENTS} pixels"
                ),
            ));
        }
    }

    // Shaders that turn early-Z off for most of the pass.
    let shaded = counters.fragments_shaded.max(1);
    let discarding: u64 =
        pass.draws.iter().filter(|d| d.discards && d.depth_test).map(|d| d.stats.fragments_shaded).sum();
    if discarding as f64 > EARLY_Z_SHARE * shaded as f64 && counters.fragments_late_killed > 0 {
        let call = pass.draws.iter().find(|d| d.discards && d.depth_test).map(|d| d.call);
        out.push(finding(
            "early-z-disabled",
            pass,
            call,
            Cost { fragments: counters.fragments_late_killed, ..Cost::default() },
            format!(
                "{:.0}% of the fragments of pass {} on {fb} come from shaders that may discard, so depth is tested \
                 after shading: {} fragments were shaded and then failed the depth test",
                100.0 * discarding as f64 / shaded as f64,
                pass.index,
                counters.fragments_late_killed
            ),
            "use alpha_cutoff (discard) only on the draws that need it; draw opaque objects with a shader that \
             never discards"
                .to_string(),
        ));
    }

    // Opaque geometry drawn back to front.
    let opaque: Vec<_> = pass
        .draws
        .iter()
        .filter(|d| d.kind == DrawKind::Draw && d.depth_test && d.depth_write && !d.blend && !d.discards)
        .collect();
    let opaque_shaded: u64 = opaque.iter().map(|d| d.stats.fragments_shaded).sum();
    let area = pass.area();
    let hidden_surface_removal = config.backend == tiler::Backend::Tbdr;
    if !hidden_surface_removal && opaque.len() > 1 && opaque_shaded as f64 > UNSORTED_OVERDRAW * area as f64 {
        let overdrawn = opaque_shaded - area;
        if counters.fragments_early_z_killed < overdrawn {
            out.push(finding(
                "unsorted-opaque",
                pass,
                opaque.first().map(|d| d.call),
                Cost { fragments: overdrawn, ..Cost::default() },
                format!(
                    "the opaque draws of pass {} on {fb} shade {opaque_shaded} fragments for {area} pixels ({:.2} per \
                     pixel) while early-Z rejected only {}: at least {overdrawn} were shaded and then covered",
                    pass.index,
                    opaque_shaded as f64 / area as f64,
                    counters.fragments_early_z_killed
                ),
                "sort opaque draws front to back (or draw a depth-only pass first); a GPU with hidden-surface removal \
                 would not need it"
                    .to_string(),
            ));
        }
    }

    // A full-screen pass reading only the previous pass's colour.
    if let Some(prev) = earlier.last()
        && prev.frame == pass.frame
        && pass.copy_texture.is_none()
        && !pass.draws.is_empty()
        && pass.draws.len() <= POST_PROCESS_MAX_DRAWS
        && pass.draws.iter().all(|d| d.kind == DrawKind::Draw)
        && pass.draws.iter().map(|d| d.stats.fragments_shaded).sum::<u64>() >= pass.area()
        && let Some(color) = prev.attachment(Slot::Color(0))
        && color.store == StoreKind::Store
        && prev.width == pass.width
        && prev.height == pass.height
        && pass.draws.iter().all(|d| d.sampled == Some(color.image))
    {
        out.push(finding(
            "post-process-chain",
            pass,
            pass.draws.first().map(|d| d.call),
            Cost { bytes: color.store_bytes, ..Cost::default() },
            format!(
                "pass {} on {fb} only draws full-screen over the colour pass {} just stored ({}), which it reads back",
                pass.index,
                prev.index,
                bytes(color.store_bytes)
            ),
            "apply the effect in the shaders of the first pass, or (Vulkan) make the two one render pass with a \
             subpass reading an input attachment"
                .to_string(),
        ));
    }

    // Draws thrown away.
    for d in &pass.dropped {
        out.push(finding(
            "draws-discarded",
            pass,
            Some(d.call),
            Cost::default(),
            format!("the {} at {} threw away {} draw(s) gathered before it on {fb}", d.by, d.call, d.draws),
            "if those draws were meant to be measured or seen, clear before them".to_string(),
        ));
    }
}

/// Multisampled colour stored (and read back, by a blit that resolves it) instead of resolved
/// in the tile. Resolving in the tile writes one value per pixel instead of `S` samples, and
/// whatever reads the result reads one value instead of `S`: the fix saves `(S − 1) / S` of
/// the store and of every read of it before it is stored again. Stores forced by a flush are
/// `flush-mid-pass`'s.
fn msaa_stored(pass: &PassRecord, later: &[&PassRecord], out: &mut Vec<Finding>) {
    if matches!(pass.end, EndCause::Flush { .. }) {
        return;
    }
    for a in pass.attachments.iter().filter(|a| a.samples > 1 && a.store == StoreKind::Store) {
        let s = a.samples as u64;
        let mut reads = 0;
        for p in later {
            reads += p.draws.iter().filter(|d| d.sampled == Some(a.image)).map(|d| d.texture_bytes).sum::<u64>();
            if p.attachments.iter().any(|b| b.image == a.image && b.store == StoreKind::Store) {
                break;
            }
        }
        let cost = (a.store_bytes + reads) * (s - 1) / s;
        let fb =
            if pass.framebuffer == 0 { "the window".to_string() } else { format!("framebuffer {}", pass.framebuffer) };
        out.push(finding(
            "msaa-stored",
            pass,
            Some(pass.ended_at),
            Cost { bytes: cost, ..Cost::default() },
            format!(
                "pass {} on {fb} stores its {} with {s} samples per pixel ({}) and {} are read back to resolve them: \
                 resolved in the tile, 1 value per pixel would be written and read",
                pass.index,
                a.slot,
                bytes(a.store_bytes),
                bytes(reads)
            ),
            "render to a single-sampled texture with multisampling resolved in the tile \
             (framebuffer_texture with samples, EXT_multisampled_render_to_texture) and invalidate the \
             multisampled depth"
                .to_string(),
        ));
    }
}

/// The bytes a continuation pass reloads that an earlier pass on the same framebuffer had to
/// store: for each aspect the pass loads, its load and the earlier pass's store.
fn reload_cost(pass: &PassRecord, earlier: &PassRecord) -> (u64, String) {
    let mut cost = 0;
    let mut what = Vec::new();
    for a in pass.attachments.iter().filter(|a| a.load == LoadKind::Load) {
        let stored = earlier.attachment(a.slot).map(|e| e.store_bytes).unwrap_or(0);
        cost += a.load_bytes + stored;
        what.push(a.slot);
    }
    (cost, format!("{} ({} stored and reloaded)", slots(&what), bytes(cost)))
}

/// The preserved swap behaviour: the window's colour is loaded every frame.
fn preserved_swap(pass: &PassRecord, load: u64, out: &mut Vec<Finding>) {
    // What the frame drew: the bounding box of every draw's pixels.
    let mut drawn: Option<Rect> = None;
    for d in pass.draws.iter().filter(|d| d.clip_rect.area() > 0) {
        drawn = Some(match drawn {
            None => d.clip_rect,
            Some(r) => {
                let x0 = r.x.min(d.clip_rect.x);
                let y0 = r.y.min(d.clip_rect.y);
                let x1 = r.right().max(d.clip_rect.right()) as u32;
                let y1 = r.bottom().max(d.clip_rect.bottom()) as u32;
                Rect::new(x0, y0, x1 - x0, y1 - y0)
            }
        });
    }
    let color = pass.attachment(Slot::Color(0));
    let per_pixel = color.map(|a| a.format.bytes_per_sample() as u64 * a.samples as u64).unwrap_or(0);
    let stored = color.is_some_and(|a| a.store == StoreKind::Store);
    let drawn_area = drawn.map(|r| r.area()).unwrap_or(0);
    let outside = if stored { (pass.area() - drawn_area.min(pass.area())) * per_pixel } else { 0 };
    let (fix, region) = match drawn {
        Some(r) if r.area() < pass.area() => {
            // GL coordinates of the region (y up).
            let gl_y = pass.height - r.y - r.height;
            (
                format!(
                    "update only the region that changes: start_tiling({}, {gl_y}, {}, {}) with no preserve mask, \
                     draw it, end_tiling with colour (QCOM_tiled_rendering), keeping the preserved swap",
                    r.x, r.width, r.height
                ),
                format!(" though the frame draws only {}×{} at ({}, {})", r.width, r.height, r.x, r.y),
            )
        }
        _ => ("use the destroyed swap behaviour and redraw the frame (clear at the start)".to_string(), String::new()),
    };
    out.push(finding(
        "preserved-swap",
        pass,
        Some(pass.started_at),
        Cost { bytes: load + outside, ..Cost::default() },
        format!(
            "the window is preserved across swaps, so pass {} loads its whole colour buffer ({}) and stores it back{region} \
             ({} stored outside it)",
            pass.index,
            bytes(load),
            bytes(outside)
        ),
        fix,
    ));
}

/// The frame data a clear-quad adds to a pass: one primitive record per primitive, a
/// polygon-list entry per tile its clip rectangle meets, one state record; each of those
/// tiles reads its entry, the record, and the state record (the quad is its own draw, so its
/// state always differs from its neighbours' in a list).
fn quad_frame_data_bytes(pass: &PassRecord, clip: Rect, primitives: u64) -> u64 {
    // Immediate mode has no frame data (and no tiles).
    if clip.area() == 0 || primitives == 0 || pass.cost.tile_width == 0 || pass.cost.tile_height == 0 {
        return 0;
    }
    let (tw, th) = (pass.cost.tile_width as u64, pass.cost.tile_height as u64);
    let tiles_x = (clip.right() - 1) / tw - clip.x as u64 / tw + 1;
    let tiles_y = (clip.bottom() - 1) / th - clip.y as u64 / th + 1;
    let tiles = tiles_x * tiles_y * primitives;
    let record = primitive_record_bytes(0);
    let written = primitives * record + tiles * POLYGON_LIST_ENTRY_BYTES + STATE_RECORD_BYTES;
    let read = tiles * (POLYGON_LIST_ENTRY_BYTES + record + STATE_RECORD_BYTES);
    written + read
}

/// The findings about a frame's copies, stalls and unread stores.
fn frame_findings(frame: &FrameRecord, passes: &[&PassRecord], out: &mut Vec<Finding>) {
    let frame_finding = |id: &'static str, call: CallRef, cost: Cost, detail: String, fix: String| Finding {
        id,
        severity: Severity::Warning,
        rule: rule(id),
        frame: frame.index,
        pass: None,
        call: Some(call),
        cost,
        detail,
        fix,
    };
    // One copy-on-write finding per object per frame.
    let mut objects: Vec<&str> = frame.copies.iter().map(|c| c.object.as_str()).collect();
    objects.dedup();
    objects.sort();
    objects.dedup();
    for object in objects {
        let copies: Vec<_> = frame.copies.iter().filter(|c| c.object == object).collect();
        let cost: u64 = copies.iter().map(|c| c.bytes).sum();
        out.push(frame_finding(
            "copy-on-write",
            copies[0].call,
            Cost { bytes: cost, ..Cost::default() },
            format!(
                "{object} was changed {} time(s) while a frame in flight (frame {}) still used it: the driver copied \
                 {} bytes ({} of traffic)",
                copies.len(),
                copies[0].used_in_frame,
                copies.iter().map(|c| c.bytes_copied).sum::<u64>(),
                bytes(cost)
            ),
            "make all updates before the draws that use it, replace it whole with buffer_data (orphaning), or rotate \
             as many copies as there are frames in flight"
                .to_string(),
        ));
    }
    for stall in &frame.stalls {
        let (id, what, fix) = match stall.cause {
            StallCause::ReadPixels => (
                "readback-stall",
                "read_pixels",
                "read from a framebuffer rendered frames in flight earlier (rotate several framebuffers)",
            ),
            StallCause::QueryResult => (
                "query-stall",
                "query_result",
                "poll query_available and read the result when it is true, frames in flight later",
            ),
            StallCause::Finish => ("finish-stall", "finish", "do not call finish; let the pipeline run"),
        };
        out.push(frame_finding(
            id,
            stall.call,
            Cost { stall_frames: stall.frames, ..Cost::default() },
            format!(
                "{what} at {} waited for frame {}'s work: {} frame(s) of pipelining lost (results arrive {} frame(s) \
                 after submission)",
                stall.call, stall.waited_for_frame, stall.frames, frame.latency_frames
            ),
            fix.to_string(),
        ));
    }
    for dead in &frame.dead_stores {
        let Some(pass) = passes.iter().find(|p| p.index == dead.pass) else { continue };
        let attachment = pass.attachment(dead.slot);
        if attachment.is_some_and(|a| a.role == Role::Preserved) {
            continue; // counted by packed-depth-stencil-half
        }
        let fb =
            if pass.framebuffer == 0 { "the window".to_string() } else { format!("framebuffer {}", pass.framebuffer) };
        let mut f = finding(
            "store-unread",
            pass,
            Some(pass.ended_at),
            Cost { bytes: dead.bytes, ..Cost::default() },
            format!(
                "pass {} stored the {} of {fb} ({}) and nothing read it before it was {}",
                pass.index,
                dead.slot,
                bytes(dead.bytes),
                dead.fate
            ),
            format!(
                "invalidate {} before unbinding {fb} (invalidate / glInvalidateFramebuffer), so it is never written out",
                dead.slot
            ),
        );
        f.frame = dead.frame;
        out.push(f);
    }
}
