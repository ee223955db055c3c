//! The rules about one render pass: how it starts (loads, clears, rebinding, flushes), what
//! it holds (packed halves, subpass splits, incremental renders, micro-triangles, shaders
//! without early-Z, unsorted opaque draws, draws thrown away), how it relates to the pass
//! before it (post-processing), and what it stores (multisampled images).

use tiler::Rect;
use tiler::{Backend, Category};
use tiler::{POLYGON_LIST_ENTRY_BYTES, STATE_RECORD_BYTES, primitive_record_bytes};

use super::{
    Cost, Draft, EARLY_Z_SHARE, MICRO_TRIANGLE_FRAGMENTS, MICRO_TRIANGLE_MIN_PRIMITIVES, MIPMAP_MIN_SAVING,
    MIPMAPPED_QUAD_BYTES, POST_PROCESS_MAX_DRAWS, PassIndex, RuleId, UNSORTED_OVERDRAW, bytes, framebuffer_name, slots,
};
use crate::context::ContextConfig;
use crate::report::{AttachmentRecord, DrawKind, EndCause, LoadKind, PassRecord, Role, Slot, StartCause, StoreKind};

/// What a pass rule sees: the pass, its neighbours in the run, and the configuration.
struct PassView<'a> {
    config: &'a ContextConfig,
    index: &'a PassIndex<'a>,
    /// The pass's position in the run.
    position: usize,
    pass: &'a PassRecord,
    /// The latest earlier pass of this frame on this framebuffer.
    same_framebuffer_before: Option<&'a PassRecord>,
    /// Bound again after an earlier pass of the frame on the same framebuffer ended by an
    /// unbind, with nothing between that needed the earlier pass done first: the second pass
    /// reloads what the first stored, and the two could have been one. A rebinding the work
    /// between needed (a ping-pong blur) is a fresh bind: its loads are the application's choice.
    rebound: bool,
    /// Bound again after an earlier pass of the frame on the same framebuffer ended by an
    /// unbind, where the work between needed that pass done first: this pass continues the
    /// frame's own drawing on the framebuffer.
    continues: bool,
    /// `the window` or `framebuffer N`.
    fb: String,
}

impl PassView<'_> {
    /// Started by a bind (or a new frame) whose loads the application chose, not a rebind.
    fn fresh_start(&self) -> bool {
        matches!(self.pass.start, StartCause::Bind | StartCause::NewFrame) && !self.rebound
    }

    /// For each draw, the loads of a fresh pass that a clear-quad at its start kept: the
    /// aspects it covers that a full clear would have cleared instead (each counted once, for
    /// the first clear-quad covering it).
    fn loads_kept_by_partial_clears(&self) -> Vec<Vec<Slot>> {
        let mut counted: Vec<Slot> = Vec::new();
        let fresh_start = self.fresh_start();
        let pass = self.pass;
        pass.draws
            .iter()
            .map(|d| {
                let mut kept = Vec::new();
                if let Some(pc) = &d.partial_clear
                    && pc.at_start
                {
                    for slot in &pc.slots {
                        if let Some(a) = pass.attachment(*slot)
                            && a.load == LoadKind::Load
                            && fresh_start
                            && !counted.contains(slot)
                        {
                            kept.push(*slot);
                            counted.push(*slot);
                        }
                    }
                }
                kept
            })
            .collect()
    }
}

/// Runs every pass rule over the pass at `position`.
pub(super) fn check(config: &ContextConfig, index: &PassIndex, position: usize, out: &mut Vec<Draft>) {
    let pass = index.at(position);
    let same_framebuffer_before = index.same_framebuffer_before(position);
    let bound_again = matches!(pass.start, StartCause::Bind | StartCause::NewFrame)
        && same_framebuffer_before.is_some_and(|q| q.end == EndCause::Bind);
    let needed = bound_again && index.rebind_needed(position).is_some();
    let (rebound, continues) = (bound_again && !needed, needed);
    let view = PassView {
        config,
        index,
        position,
        pass,
        same_framebuffer_before,
        rebound,
        continues,
        fb: framebuffer_name(pass),
    };
    partial_clear(&view, out);
    flush_mid_pass(&view, out);
    framebuffer_rebound(&view, out);
    load_at_pass_start(&view, out);
    preserved_swap(&view, out);
    packed_depth_stencil_half(&view, out);
    subpass_split(&view, out);
    incremental_render(&view, out);
    micro_triangles(&view, out);
    early_z_disabled(&view, out);
    unsorted_opaque(&view, out);
    post_process_chain(&view, out);
    draws_discarded(&view, out);
    msaa_stored(&view, out);
    minified_without_mipmaps(&view, out);
    tile_memory_overflow(&view, out);
}

/// A pass whose attachments do not fit the tile memory even in the smallest tile.
fn tile_memory_overflow(v: &PassView, out: &mut Vec<Draft>) {
    let (pass, fb) = (v.pass, &v.fb);
    let memory = v.config.device_config().tile_memory_bytes;
    let cost = &pass.cost;
    if !v.config.backend.is_tiler() || cost.tile_bytes <= memory {
        return;
    }
    let pixels = cost.tile_width as u64 * cost.tile_height as u64;
    let per_pixel = cost.tile_bytes / pixels.max(1);
    out.push(Draft::about(
        RuleId::TileMemoryOverflow,
        pass,
        None,
        Cost::default(),
        format!(
            "pass {} on {fb} holds {per_pixel} bytes per pixel ({} attachment(s) at {} sample(s)): even the smallest tile, {}×{}, \
             needs {}, more than the {} of tile memory, so no tile of this GPU holds it; tiler rendered it in an \
             oversized tile, and a GPU would store and reload it through memory or refuse the framebuffer, so its \
             real cost is higher than this ledger",
            pass.index,
            pass.attachments.len(),
            pass.samples,
            cost.tile_width,
            cost.tile_height,
            bytes(cost.tile_bytes),
            bytes(memory),
        ),
        "use fewer or narrower attachments (RGBA8 rather than RGBA16F or RGBA32F, a packed depth format) or fewer \
         samples, or split the pass"
            .to_string(),
    ));
}

/// Textures read from level 0 while drawn much smaller than they are.
fn minified_without_mipmaps(v: &PassView, out: &mut Vec<Draft>) {
    let (pass, fb) = (v.pass, &v.fb);
    let counters = &pass.cost.counters;
    let (quads, fetched) = (counters.quads_minified_unmipped, counters.texture_fetch_minified_unmipped);
    let saving = fetched.saturating_sub(quads * MIPMAPPED_QUAD_BYTES);
    if saving < MIPMAP_MIN_SAVING {
        return;
    }
    let draw = pass.draws.iter().max_by_key(|d| d.stats.texture_fetch_minified_unmipped);
    let total = pass.cost.ledger.get(Category::TextureFetch);
    out.push(Draft::about(
        RuleId::MinifiedWithoutMipmaps,
        pass,
        draw.filter(|d| d.stats.texture_fetch_minified_unmipped > 0).map(|d| d.call),
        Cost { bytes: saving, ..Cost::default() },
        format!(
            "pass {} on {fb} samples textures more than 2× smaller than their level 0, with no mip maps, in {quads} \
             quads: they fetch {} of the pass's {} of texture reads, {:.0} bytes a quad where a mip level would \
             read about {MIPMAPPED_QUAD_BYTES}",
            pass.index,
            bytes(fetched),
            bytes(total),
            fetched as f64 / quads as f64,
        ),
        "give the texture mip maps (glGenerateMipmap after its upload, or upload the levels) and a *_MIPMAP_* \
         minification filter, which also stops a minified texture shimmering; a texture rendered each frame (a \
         blur's source) can instead be downsampled in 2× steps"
            .to_string(),
    ));
}

/// A clear drawn as a clear-quad: its shading, its frame data, and the loads it kept.
fn partial_clear(v: &PassView, out: &mut Vec<Draft>) {
    let (pass, fb) = (v.pass, &v.fb);
    for (d, kept) in pass.draws.iter().zip(v.loads_kept_by_partial_clears()) {
        let Some(pc) = &d.partial_clear else { continue };
        // An immediate-mode GPU has no loads to keep (nor frame data): the quad's shading
        // is what it costs there.
        let kept = if v.config.backend.is_tiler() { kept } else { Vec::new() };
        let kept_bytes: u64 = kept.iter().filter_map(|s| pass.attachment(*s)).map(|a| a.load_bytes).sum();
        let cost = quad_frame_data_bytes(pass, d.clip_rect, d.stats.primitives) + kept_bytes;
        let loads = if kept.is_empty() {
            String::new()
        } else {
            format!(" and keeps the load of {} ({})", slots(&kept), bytes(kept_bytes))
        };
        out.push(Draft::about(
            RuleId::PartialClear,
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
            partial_clear_fix(pass, d.clip_rect, pc.reasons.iter().any(|r| r.contains("scissor"))),
        ));
    }
}

/// What to do about a clear-quad. A scissored clear usually means the application redraws
/// only a region and keeps the rest (seed 001): a full clear would erase what lies outside,
/// so the advice is to keep the scissor around the whole pass (tiler then covers only the
/// box's tiles) or to use a tiled-rendering region that starts the region cleared without
/// loading it; a full clear only if nothing outside must be kept.
fn partial_clear_fix(pass: &PassRecord, region: Rect, scissored: bool) -> String {
    let full_clear = "disable the scissor test and set every write mask before clearing, and clear colour, depth and \
                      stencil together at the start of the pass (Listing 23.1)";
    if !scissored {
        return full_clear.to_string();
    }
    let gl_y = pass.height.saturating_sub(region.y + region.height);
    let preserved = if pass.window_preserved { " (the window is preserved: a full clear would erase it)" } else { "" };
    format!(
        "to redraw only the {}×{} region at ({}, {gl_y}) and keep what lies outside it{preserved}, keep the scissor box \
         around every draw of the pass (tiler then loads and stores only the tiles it touches), or better \
         start_tiling({}, {gl_y}, {}, {}) with no preserve mask and end_tiling with the colour \
         (QCOM_tiled_rendering), so the region starts cleared without loading; only if nothing outside must be \
         kept, {full_clear}",
        region.width, region.height, region.x, region.x, region.width, region.height
    )
}

/// A flush cut the previous pass on this framebuffer short: it stored, this pass reloads.
fn flush_mid_pass(v: &PassView, out: &mut Vec<Draft>) {
    let StartCause::AfterFlush { flush } = v.pass.start else { return };
    let Some(q) = v.same_framebuffer_before else { return };
    let (pass, fb) = (v.pass, &v.fb);
    let (cost, what) = reload_cost(pass, q);
    if cost > 0 {
        out.push(Draft::about(
            RuleId::FlushMidPass,
            q,
            Some(q.ended_at),
            Cost { bytes: cost, ..Cost::default() },
            format!(
                "{} at {} flushed the pass on {fb}: it stored {what} and the rest of the frame's drawing (pass {}) \
                 reloads them",
                flush.describe(),
                q.ended_at,
                pass.index
            ),
            "move the read-back, copy or flush after all drawing to this framebuffer (the end of the frame), or read \
             a framebuffer finished frames ago"
                .to_string(),
        ));
    }
}

/// The framebuffer was bound again in the same frame: this pass reloads what the last stored.
fn framebuffer_rebound(v: &PassView, out: &mut Vec<Draft>) {
    if matches!(v.pass.start, StartCause::AfterFlush { .. }) || !v.rebound {
        return;
    }
    let (pass, fb) = (v.pass, &v.fb);
    let q = v.same_framebuffer_before.expect("a rebound pass has a pass before it");
    let (mut cost, reloaded) = reload_cost(pass, q);
    let mut what = Vec::new();
    if cost > 0 {
        what.push(format!("pass {} stored {reloaded} and this pass reloads them", q.index));
    }
    // What the first pass stored of the aspects this one clears or does not keep: nothing
    // between read it (or the rebinding would be needed), so in one pass it is never stored.
    let overwritten: Vec<&AttachmentRecord> = q
        .attachments
        .iter()
        .filter(|e| e.store == StoreKind::Store && e.store_bytes > 0)
        .filter(|e| pass.attachment(e.slot).is_some_and(|a| a.load != LoadKind::Load))
        .collect();
    if !overwritten.is_empty() {
        let stored: u64 = overwritten.iter().map(|e| e.store_bytes).sum();
        let aspects: Vec<Slot> = overwritten.iter().map(|e| e.slot).collect();
        cost += stored;
        what.push(format!(
            "pass {} stored {} ({}), which this pass clears or throws away",
            q.index,
            slots(&aspects),
            bytes(stored)
        ));
    }
    let what = what.join("; ");
    if cost > 0 {
        out.push(Draft::about(
            RuleId::FramebufferRebound,
            pass,
            Some(pass.started_at),
            Cost { bytes: cost, ..Cost::default() },
            format!(
                "{fb} is bound again at {} after pass {} ended at {}: {what}",
                pass.started_at, q.index, q.ended_at
            ),
            format!(
                "do everything for {fb} in one binding: render the other framebuffers first (e.g. render-to-texture \
                 before the scene that uses it)"
            ),
        ));
    }
}

/// Whether the loads at the start of this pass are the application's choice: a bind, a new
/// frame or an explicit pass, not a rebind (nor a continuation, a tiling region or a copy).
fn loads_chosen(v: &PassView) -> bool {
    match v.pass.start {
        StartCause::AfterFlush { .. } | StartCause::Tiling | StartCause::Copy => false,
        StartCause::Bind | StartCause::NewFrame => !v.rebound,
        StartCause::BeginPass => true,
    }
}

/// Attachments loaded at the start of a pass that nothing cleared or invalidated (the
/// preserved window's colour aside, which is `preserved-swap`'s, and what a clear-quad at the
/// start kept, which is `partial-clear`'s).
fn load_at_pass_start(v: &PassView, out: &mut Vec<Draft>) {
    if !loads_chosen(v) {
        return;
    }
    let (pass, fb) = (v.pass, &v.fb);
    let partial_at_start: Vec<Slot> = v.loads_kept_by_partial_clears().concat();
    // A pass that continues what this frame drew earlier on the framebuffer starts from that
    // drawing unless its first draw paints over every pixel.
    let painted_over = !v.continues || first_draw_paints_over(pass);
    let mut loaded = Vec::new();
    let mut cost = 0;
    for a in pass.attachments.iter().filter(|a| a.load == LoadKind::Load && a.role == Role::Attached) {
        if partial_at_start.contains(&a.slot) || (pass.window_preserved && matches!(a.slot, Slot::Color(_))) {
            continue;
        }
        if !painted_over || (v.continues && !matches!(a.slot, Slot::Color(_))) {
            continue;
        }
        loaded.push(a.slot);
        cost += a.load_bytes;
    }
    if cost > 0 {
        out.push(Draft::about(
            RuleId::LoadAtPassStart,
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
                "clear {} (or invalidate them) right after binding {fb}, unless the previous contents are the \
                 starting point",
                slots(&loaded)
            ),
        ));
    }
}

/// Whether the pass's first draw writes every pixel of the pass with colour that does not
/// depend on what was there: no blending, no discard, no depth or stencil test, a clip
/// rectangle over the whole area and a fragment for each of its pixels.
fn first_draw_paints_over(pass: &PassRecord) -> bool {
    let area = match pass.render_area {
        Some(r) => r,
        None => Rect::new(0, 0, pass.width, pass.height),
    };
    pass.draws.first().is_some_and(|d| {
        d.kind == DrawKind::Draw
            && !d.blend
            && !d.discards
            && !d.depth_test
            && d.clip_rect == area
            && d.stats.fragments_shaded >= area.area()
    })
}

/// The preserved swap behaviour: the window's colour is loaded every frame.
fn preserved_swap(v: &PassView, out: &mut Vec<Draft>) {
    if !loads_chosen(v) || !v.pass.window_preserved {
        return;
    }
    let pass = v.pass;
    let partial_at_start: Vec<Slot> = v.loads_kept_by_partial_clears().concat();
    let load: u64 = pass
        .attachments
        .iter()
        .filter(|a| a.load == LoadKind::Load && a.role == Role::Attached)
        .filter(|a| !partial_at_start.contains(&a.slot) && matches!(a.slot, Slot::Color(_)))
        .map(|a| a.load_bytes)
        .sum();
    if load == 0 {
        return;
    }
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
    out.push(Draft::about(
        RuleId::PreservedSwap,
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

/// The other half of a packed depth-stencil image, loaded and stored to keep it.
fn packed_depth_stencil_half(v: &PassView, out: &mut Vec<Draft>) {
    let (pass, fb) = (v.pass, &v.fb);
    let preserved: Vec<_> = pass.attachments.iter().filter(|a| a.role == Role::Preserved).collect();
    if preserved.is_empty() {
        return;
    }
    let cost: u64 = preserved.iter().map(|a| a.load_bytes + a.store_bytes).sum();
    let half = preserved.iter().map(|a| a.slot).collect::<Vec<_>>();
    out.push(Draft::about(
        RuleId::PackedDepthStencilHalf,
        pass,
        Some(pass.started_at),
        Cost { bytes: cost, ..Cost::default() },
        format!(
            "{fb} attaches only one half of packed {} image {}; its {} must be loaded and stored with it",
            preserved[0].gl_format.name(),
            preserved[0].image.to_string().trim_start_matches("image "),
            slots(&half)
        ),
        "attach the image at depth_stencil, or use a depth-only format (depth16, depth24, depth32f) when no stencil \
         is needed"
            .to_string(),
    ));
}

/// Subpass dependencies that are not by-region: the pass split through memory.
fn subpass_split(v: &PassView, out: &mut Vec<Draft>) {
    let (pass, fb) = (v.pass, &v.fb);
    let splits = pass.cost.counters.subpass_splits;
    if splits == 0 {
        return;
    }
    // What the split moved beyond the pass's own loads and stores; when incremental renders
    // also stored and reloaded, the two cannot be told apart and the cost is theirs.
    let planned: u64 = pass.attachments.iter().map(|a| a.load_bytes + a.store_bytes).sum();
    let moved = pass.cost.ledger.get(Category::TileLoad) + pass.cost.ledger.get(Category::TileStore);
    let extra = if pass.cost.counters.incremental_renders == 0 { moved.saturating_sub(planned) } else { 0 };
    let deps: Vec<String> =
        pass.dependencies.iter().filter(|d| !d.by_region).map(|d| format!("subpass {} → {}", d.src, d.dst)).collect();
    let cost_text = if extra > 0 {
        format!("{} more than the pass's own loads and stores", bytes(extra))
    } else {
        "its cost is counted with the pass's incremental renders".to_string()
    };
    out.push(Draft::about(
        RuleId::SubpassSplit,
        pass,
        Some(pass.started_at),
        Cost { bytes: extra, ..Cost::default() },
        format!(
            "the dependency {} of the explicit pass {} on {fb} (begun at {}) is not by-region, so the tiler split the \
             pass {splits} time(s): every tile stored every attachment — the transient ones through spill memory they \
             would not otherwise need — and reloaded them for the next subpass; {cost_text}",
            deps.join(", "),
            pass.index,
            pass.started_at
        ),
        "set \"by_region\": true on the dependency when each pixel of the later subpass reads only its own pixel of \
         what the earlier one wrote (input attachments always do); only reads of other pixels need the split"
            .to_string(),
    ));
}

/// The frame data outgrew its budget: every attachment stored and reloaded each time.
fn incremental_render(v: &PassView, out: &mut Vec<Draft>) {
    let (pass, fb) = (v.pass, &v.fb);
    let incremental = pass.cost.counters.incremental_renders;
    if incremental == 0 {
        return;
    }
    let planned: u64 = pass.attachments.iter().map(|a| a.load_bytes + a.store_bytes).sum();
    let moved = pass.cost.ledger.get(Category::TileLoad) + pass.cost.ledger.get(Category::TileStore);
    let extra = moved.saturating_sub(planned);
    out.push(Draft::about(
        RuleId::IncrementalRender,
        pass,
        Some(pass.ended_at),
        Cost { bytes: extra, ..Cost::default() },
        format!(
            "the frame data of pass {} on {fb} outgrew its budget ({} bytes) {incremental} time(s): each time every \
             attachment — depth, stencil and all {} sample(s) — was stored and reloaded, {} more than the pass's own \
             loads and stores",
            pass.index,
            v.config.frame_data_budget,
            pass.samples,
            bytes(extra)
        ),
        "draw less geometry in the pass (level of detail, culling), or split it across frames".to_string(),
    ));
}

/// Many primitives covering a pixel or two each.
fn micro_triangles(v: &PassView, out: &mut Vec<Draft>) {
    let (pass, fb) = (v.pass, &v.fb);
    let counters = &pass.cost.counters;
    if counters.primitives < MICRO_TRIANGLE_MIN_PRIMITIVES {
        return;
    }
    let per = counters.fragments_rasterized as f64 / counters.primitives as f64;
    if per >= MICRO_TRIANGLE_FRAGMENTS {
        return;
    }
    let l = &pass.cost.ledger;
    let cost = l.get(Category::FrameDataWrite)
        + l.get(Category::FrameDataRead)
        + l.get(Category::VertexFetch)
        + l.get(Category::IndexFetch);
    out.push(Draft::about(
        RuleId::MicroTriangles,
        pass,
        pass.draws.iter().max_by_key(|d| d.stats.primitives).map(|d| d.call),
        Cost { bytes: cost, ..Cost::default() },
        format!(
            "pass {} on {fb} sets up {} primitives that cover {per:.2} pixels each on average: its geometry and frame \
             data cost {}",
            pass.index,
            counters.primitives,
            bytes(cost)
        ),
        format!("use coarser meshes (level of detail) so triangles cover at least {MICRO_TRIANGLE_FRAGMENTS} pixels"),
    ));
}

/// Shaders that turn early-Z off for most of the pass.
fn early_z_disabled(v: &PassView, out: &mut Vec<Draft>) {
    let (pass, fb) = (v.pass, &v.fb);
    let counters = &pass.cost.counters;
    let shaded = counters.fragments_shaded.max(1);
    let discarding: u64 =
        pass.draws.iter().filter(|d| d.discards && d.depth_test).map(|d| d.stats.fragments_shaded).sum();
    if discarding as f64 <= EARLY_Z_SHARE * shaded as f64 || counters.fragments_late_killed == 0 {
        return;
    }
    let first = pass.draws.iter().find(|d| d.discards && d.depth_test);
    let call = first.map(|d| d.call);
    // The built-in programs discard by their `alpha_cutoff` uniform; a GLSL program by a
    // `discard` statement in its fragment shader.
    let fix = if first.is_some_and(|d| d.program.is_some()) {
        "use alpha_cutoff (discard) only on the draws that need it; draw opaque objects with a shader that never \
         discards"
    } else {
        "keep `discard` only in the fragment shaders of the draws that need it (alpha-tested cut-outs); draw opaque \
         objects with a program whose fragment shader has no `discard`, before the discarding draws"
    };
    out.push(Draft::about(
        RuleId::EarlyZDisabled,
        pass,
        call,
        Cost { fragments: counters.fragments_late_killed, ..Cost::default() },
        format!(
            "{:.0}% of the fragments of pass {} on {fb} come from shaders that may discard, so depth is tested after \
             shading: {} fragments were shaded and then failed the depth test",
            100.0 * discarding as f64 / shaded as f64,
            pass.index,
            counters.fragments_late_killed
        ),
        fix.to_string(),
    ));
}

/// Opaque geometry drawn back to front, without hidden-surface removal to make up for it.
fn unsorted_opaque(v: &PassView, out: &mut Vec<Draft>) {
    let (pass, fb) = (v.pass, &v.fb);
    let counters = &pass.cost.counters;
    let opaque: Vec<_> = pass
        .draws
        .iter()
        .filter(|d| d.kind == DrawKind::Draw && d.depth_test && d.depth_write && !d.blend && !d.discards)
        .collect();
    let opaque_shaded: u64 = opaque.iter().map(|d| d.stats.fragments_shaded).sum();
    let area = pass.area();
    let hidden_surface_removal = v.config.backend == Backend::Tbdr;
    if hidden_surface_removal || opaque.len() <= 1 || opaque_shaded as f64 <= UNSORTED_OVERDRAW * area as f64 {
        return;
    }
    let overdrawn = opaque_shaded - area;
    if counters.fragments_early_z_killed >= overdrawn {
        return;
    }
    // An immediate-mode GPU without a framebuffer cache also writes each covered fragment's
    // colour and depth to memory, once per sample (a cache absorbs the overwrites): sorted,
    // those writes are not made. The depth tests (reads) are the same either way.
    let device = v.config.device_config();
    let bytes = if !device.backend.is_tiler() && device.framebuffer_cache.size_bytes == 0 {
        let written: u64 = pass
            .attachments
            .iter()
            .filter(|a| a.role == Role::Attached && matches!(a.slot, Slot::Color(_) | Slot::Depth))
            .map(|a| a.format.bytes_per_sample() as u64)
            .sum();
        overdrawn * written * pass.samples as u64
    } else {
        0
    };
    out.push(Draft::about(
        RuleId::UnsortedOpaque,
        pass,
        opaque.first().map(|d| d.call),
        Cost { fragments: overdrawn, bytes, ..Cost::default() },
        format!(
            "the opaque draws of pass {} on {fb} shade {opaque_shaded} fragments for {area} pixels ({:.2} per pixel) \
             while early-Z rejected only {}: at least {overdrawn} were shaded and then covered",
            pass.index,
            opaque_shaded as f64 / area as f64,
            counters.fragments_early_z_killed
        ),
        "sort opaque draws front to back (or draw a depth-only pass first); a GPU with hidden-surface removal would \
         not need it"
            .to_string(),
    ));
}

/// A full-screen pass reading only the previous pass's colour.
fn post_process_chain(v: &PassView, out: &mut Vec<Draft>) {
    let (pass, fb) = (v.pass, &v.fb);
    if let Some(prev) = v.index.previous(v.position)
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
        out.push(Draft::about(
            RuleId::PostProcessChain,
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
}

/// Draws thrown away by a full clear or invalidate before they were rendered.
fn draws_discarded(v: &PassView, out: &mut Vec<Draft>) {
    let (pass, fb) = (v.pass, &v.fb);
    for d in &pass.dropped {
        out.push(Draft::about(
            RuleId::DrawsDiscarded,
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
fn msaa_stored(v: &PassView, out: &mut Vec<Draft>) {
    let (pass, fb) = (v.pass, &v.fb);
    if matches!(pass.end, EndCause::Flush { .. }) {
        return;
    }
    for (i, a) in pass.attachments.iter().enumerate() {
        if a.samples <= 1 || a.store != StoreKind::Store {
            continue;
        }
        let s = a.samples as u64;
        let reads = v.index.reads_until_stored_again(v.position, i);
        let cost = (a.store_bytes + reads) * (s - 1) / s;
        out.push(Draft::about(
            RuleId::MsaaStored,
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
            "render to a single-sampled texture with multisampling resolved in the tile (framebuffer_texture with \
             samples, EXT_multisampled_render_to_texture) and invalidate the multisampled depth"
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
