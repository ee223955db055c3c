//! One test per row of DESIGN.md's inference table: the passes the context produced, their
//! load and store ops, and the ledger. The window is 64×64 with 32×32 tiles (4 tiles): colour
//! is 16384 bytes, depth 12288 (3 bytes of D24S8), stencil 4096.

use super::common::*;
use tiler::Category;
use tiler_gl::report::{EndCause, FlushCause, LoadKind::*, StartCause, StoreKind};
use tiler_gl::*;

const COLOR: u64 = 64 * 64 * 4;
const DEPTH: u64 = 64 * 64 * 3;
const STENCIL: u64 = 64 * 64;
/// The stencil of packed D24S8 moved alone: memory moves the sample's whole 32-bit word.
const STENCIL_WORD: u64 = 64 * 64 * 4;

/// A window with program 1 (solid) drawing buffer 1, a quad over the bottom-left quarter.
fn window() -> Context {
    let mut gl = context(64, 64);
    geometry(&mut gl, 1, ProgramKind::Solid, &quad(-1.0, -1.0, 0.0, 0.0, 0.0));
    set_color(&mut gl, [1.0, 0.0, 0.0, 1.0]);
    gl
}

fn store(pass: &PassRecord) -> u64 {
    pass.cost.ledger.get(Category::TileStore)
}

fn load(pass: &PassRecord) -> u64 {
    pass.cost.ledger.get(Category::TileLoad)
}

/// Row 1: binding a framebuffer ends the previous pass; nothing renders before.
#[test]
fn binding_a_framebuffer_ends_the_previous_pass() {
    let mut gl = window();
    framebuffer(&mut gl, 2, 64, 64);
    clear_all(&mut gl);
    draw(&mut gl, 6);
    assert!(gl.current_frame().passes.is_empty(), "a draw renders nothing: it is gathered");
    bind(&mut gl, 2);
    assert_eq!(gl.current_frame().passes.len(), 1, "binding framebuffer 2 ended the window's pass");
    // Binding the bound framebuffer again is not a new pass.
    bind(&mut gl, 2);
    clear_all(&mut gl);
    draw(&mut gl, 6);
    bind(&mut gl, 2);
    assert_eq!(gl.current_frame().passes.len(), 1);
    bind(&mut gl, 0);
    // Binding with nothing gathered renders nothing.
    bind(&mut gl, 2);
    bind(&mut gl, 0);
    let report = gl.end().unwrap();
    let p = passes(&report);
    assert_eq!(p.len(), 2);
    assert_eq!((p[0].framebuffer, p[0].start, p[0].end), (0, StartCause::Bind, EndCause::Bind));
    assert_eq!((p[1].framebuffer, p[1].start, p[1].end), (2, StartCause::Bind, EndCause::Bind));
    // Ended by a bind, not a swap: everything not invalidated is stored.
    assert_eq!(op(p[0], Slot::Color(0)), (Clear, StoreKind::Store));
    assert_eq!(op(p[0], Slot::Depth), (Clear, StoreKind::Store));
    assert_eq!(store(p[0]), COLOR + DEPTH + STENCIL);
    assert_eq!(load(p[0]), 0);
}

/// Row 2: a full clear is a `Clear` load op and throws the gathered draws away.
#[test]
fn a_full_clear_is_a_clear_load_op_and_drops_the_frame_data() {
    let mut gl = window();
    framebuffer(&mut gl, 2, 64, 64);
    // Give the framebuffer defined contents, so that only the clear avoids loading them.
    bind(&mut gl, 2);
    clear_all(&mut gl);
    draw(&mut gl, 6);
    bind(&mut gl, 0);
    bind(&mut gl, 2);
    draw(&mut gl, 6);
    draw(&mut gl, 6);
    c(&mut gl, Call::ClearColor { rgba: [0.0, 0.0, 1.0, 1.0] });
    clear_all(&mut gl);
    geometry(&mut gl, 3, ProgramKind::Solid, &quad(0.0, 0.0, 1.0, 1.0, 0.0));
    set_color(&mut gl, [0.0, 1.0, 0.0, 1.0]);
    draw(&mut gl, 6);
    bind(&mut gl, 0);
    let report = gl.end().unwrap();
    let p = passes(&report)[1];
    assert_eq!(p.framebuffer, 2);
    for slot in [Slot::Color(0), Slot::Depth, Slot::Stencil] {
        assert_eq!(op(p, slot).0, Clear, "{slot}");
    }
    assert_eq!(load(p), 0, "a cleared pass reads nothing");
    assert_eq!(p.dropped.len(), 1);
    assert_eq!(p.dropped[0].draws, 2);
    assert_eq!(p.draws.len(), 1);
    assert_eq!(p.cost.counters.draws, 1, "only the draw after the clear reached the GPU");
    assert_eq!(report.findings_with("draws-discarded").count(), 1);
    assert_eq!(report.findings_with("load-at-pass-start").count(), 0);
    let image = gl.device().read_rgba8(gl.texture_image(2).unwrap()).unwrap();
    assert_eq!(pixel(&image, 64, 10, 50), [0, 0, 255, 255], "the dropped draw is not there");
    assert_eq!(pixel(&image, 64, 50, 10), [0, 255, 0, 255]);
}

/// A framebuffer 2 whose colour, depth and stencil are defined (rendered in the previous
/// frame), bound.
fn defined_framebuffer() -> Context {
    let mut gl = window();
    framebuffer(&mut gl, 2, 64, 64);
    bind(&mut gl, 2);
    c(&mut gl, Call::ClearColor { rgba: [0.0, 0.0, 1.0, 1.0] });
    clear_all(&mut gl);
    bind(&mut gl, 0);
    swap(&mut gl);
    bind(&mut gl, 2);
    gl
}

/// Row 3: a scissored clear becomes a clear-quad draw; the load ops stay `Load`.
#[test]
fn a_scissored_clear_is_a_clear_quad_and_loads_stay() {
    let mut gl = defined_framebuffer();
    c(&mut gl, Call::Scissor { x: 0, y: 0, width: 32, height: 32 });
    c(&mut gl, Call::Enable { cap: Capability::ScissorTest });
    c(&mut gl, Call::ClearColor { rgba: [1.0, 1.0, 0.0, 1.0] });
    clear_all(&mut gl);
    c(&mut gl, Call::Disable { cap: Capability::ScissorTest });
    bind(&mut gl, 0);
    let report = gl.end().unwrap();
    let p = passes(&report)[1];
    assert_eq!(ops(p).iter().map(|o| o.1).collect::<Vec<_>>(), vec![Load, Load, Load]);
    // Every draw of the pass lies inside the scissor box: the pass covers only that quarter.
    assert_eq!(p.render_area, Some(tiler::Rect::new(0, 32, 32, 32)));
    assert_eq!(load(p), (COLOR + DEPTH + STENCIL) / 4);
    assert_eq!(p.draws.len(), 1);
    let quad = &p.draws[0];
    assert_eq!(quad.kind, report::DrawKind::ClearQuad);
    let partial = quad.partial_clear.as_ref().unwrap();
    assert_eq!(partial.slots, vec![Slot::Color(0), Slot::Depth, Slot::Stencil]);
    assert!(partial.reasons[0].contains("scissor"));
    assert_eq!(quad.stats.fragments_shaded, 32 * 32);
    // The advisor: the loads the clear failed to avoid, and the quad's frame data.
    let f: Vec<_> = report.findings_with("partial-clear").collect();
    assert_eq!(f.len(), 1);
    let frame_data = p.cost.ledger.get(Category::FrameDataWrite) + p.cost.ledger.get(Category::FrameDataRead);
    assert_eq!(f[0].cost_bytes.unwrap_or(0), (COLOR + DEPTH + STENCIL) / 4 + frame_data);
    assert!(
        f[0].advice.contains("keep the scissor box") && f[0].advice.contains("start_tiling(0, 0, 32, 32)"),
        "{}",
        f[0].advice
    );
    // Only the scissored bottom-left quarter was cleared.
    let image = gl.device().read_rgba8(gl.texture_image(2).unwrap()).unwrap();
    assert_eq!(pixel(&image, 64, 10, 50), [255, 255, 0, 255]);
    assert_eq!(pixel(&image, 64, 50, 10), [0, 0, 255, 255]);
}

/// Row 3: a masked clear is a clear-quad for the masked aspect; fully cleared aspects at the
/// start still become `Clear`.
#[test]
fn a_masked_clear_is_a_clear_quad_for_what_is_masked() {
    let mut gl = defined_framebuffer();
    c(&mut gl, Call::ColorMask { red: true, green: true, blue: true, alpha: false });
    clear_all(&mut gl);
    bind(&mut gl, 0);
    let report = gl.end().unwrap();
    let p = passes(&report)[1];
    assert_eq!(op(p, Slot::Color(0)), (Load, StoreKind::Store));
    assert_eq!(op(p, Slot::Depth).0, Clear);
    assert_eq!(op(p, Slot::Stencil).0, Clear);
    assert_eq!(load(p), COLOR);
    assert_eq!(p.draws[0].partial_clear.as_ref().unwrap().slots, vec![Slot::Color(0)]);
}

/// Row 3: clearing only some buffers after draws is a clear-quad; nothing is dropped. At the
/// start, the cleared buffers are `Clear` and the rest keep `Load`.
#[test]
fn clearing_some_buffers_keeps_the_frame_data() {
    let mut gl = defined_framebuffer();
    c(&mut gl, Call::Clear { color: true, depth: false, stencil: false });
    draw(&mut gl, 6);
    c(&mut gl, Call::Clear { color: false, depth: true, stencil: false });
    draw(&mut gl, 6);
    bind(&mut gl, 0);
    let report = gl.end().unwrap();
    let p = passes(&report)[1];
    assert_eq!(op(p, Slot::Color(0)).0, Clear);
    assert_eq!(op(p, Slot::Depth).0, Load, "depth was cleared only after a draw");
    assert_eq!(op(p, Slot::Stencil).0, Load);
    assert_eq!(load(p), DEPTH + STENCIL);
    assert!(p.dropped.is_empty());
    let kinds: Vec<_> = p.draws.iter().map(|d| d.kind).collect();
    assert_eq!(kinds, vec![report::DrawKind::Draw, report::DrawKind::ClearQuad, report::DrawKind::Draw]);
    assert_eq!(p.draws[1].partial_clear.as_ref().unwrap().slots, vec![Slot::Depth]);
    assert!(!p.draws[1].partial_clear.as_ref().unwrap().at_start);
}

/// Row 4: invalidated attachments are not stored; invalidated at the start, not loaded;
/// written again after an invalidate, stored again.
#[test]
fn invalidate_makes_the_store_op_dont_care() {
    let mut gl = defined_framebuffer();
    clear_all(&mut gl);
    draw(&mut gl, 6);
    c(&mut gl, Call::Invalidate { attachments: vec![AttachmentPoint::DepthStencil] });
    bind(&mut gl, 0);
    // Invalidated at the start: not loaded either.
    bind(&mut gl, 2);
    c(&mut gl, Call::Invalidate { attachments: vec![AttachmentPoint::Color0] });
    draw(&mut gl, 6);
    bind(&mut gl, 0);
    // Invalidated, then written with depth: depth is stored after all.
    bind(&mut gl, 2);
    clear_all(&mut gl);
    c(&mut gl, Call::Invalidate { attachments: vec![AttachmentPoint::Depth] });
    c(&mut gl, Call::Enable { cap: Capability::DepthTest });
    draw(&mut gl, 6);
    bind(&mut gl, 0);
    let report = gl.end().unwrap();
    let p = passes(&report);
    assert_eq!(op(p[1], Slot::Color(0)), (Clear, StoreKind::Store));
    assert_eq!(op(p[1], Slot::Depth), (Clear, StoreKind::DontCare));
    assert_eq!(op(p[1], Slot::Stencil), (Clear, StoreKind::DontCare));
    assert_eq!(store(p[1]), COLOR);
    // The invalidated colour is not loaded; depth and stencil are undefined after pass 1.
    assert_eq!(op(p[2], Slot::Color(0)), (DontCare, StoreKind::Store), "a draw wrote it after the invalidate");
    assert_eq!(op(p[2], Slot::Depth).0, DontCare);
    assert_eq!(load(p[2]), 0);
    // Invalidated right after its clear (before any draw): not even cleared; then written.
    assert_eq!(op(p[3], Slot::Depth), (DontCare, StoreKind::Store));
    assert_eq!(op(p[3], Slot::Stencil), (Clear, StoreKind::Store));
}

/// Row 4: invalidating everything after draws throws them away.
#[test]
fn invalidating_everything_drops_the_frame_data() {
    let mut gl = defined_framebuffer();
    draw(&mut gl, 6);
    c(&mut gl, Call::Invalidate { attachments: vec![AttachmentPoint::Color0, AttachmentPoint::DepthStencil] });
    bind(&mut gl, 0);
    let report = gl.end().unwrap();
    assert_eq!(passes(&report).len(), 1, "nothing was left to render");
}

/// The window pass, a draw, a flush trigger, another draw, a swap.
fn flushed(trigger: impl FnOnce(&mut Context)) -> Report {
    let mut gl = window();
    c(
        &mut gl,
        Call::CreateTexture {
            id: 9,
            width: 64,
            height: 64,
            format: TextureFormat::Rgba8,
            data: None,
            transient: false,
        },
    );
    c(&mut gl, Call::CreateQuery { id: 1 });
    c(&mut gl, Call::BeginQuery { id: 1 });
    clear_all(&mut gl);
    draw(&mut gl, 6);
    c(&mut gl, Call::EndQuery);
    trigger(&mut gl);
    draw(&mut gl, 6);
    swap(&mut gl);
    gl.end().unwrap()
}

fn check_flush(report: &Report, cause: FlushCause) {
    let p = passes(report);
    assert_eq!(p.len(), 2, "{cause:?}");
    assert_eq!(p[0].end, EndCause::Flush { flush: cause });
    assert_eq!(store(p[0]), COLOR + DEPTH + STENCIL, "{cause:?}: the flush stores everything");
    assert_eq!(p[1].start, StartCause::AfterFlush { flush: cause });
    assert_eq!(ops(p[1]).iter().map(|o| o.1).collect::<Vec<_>>(), vec![Load, Load, Load], "{cause:?}");
    assert_eq!(load(p[1]), COLOR + DEPTH + STENCIL);
    assert_eq!(op(p[1], Slot::Depth).1, StoreKind::DontCare, "the swap still discards depth");
    let f: Vec<_> = report.findings_with("flush-mid-pass").collect();
    assert_eq!(f.len(), 1, "{cause:?}");
    assert_eq!(f[0].cost_bytes.unwrap_or(0), 2 * (COLOR + DEPTH + STENCIL));
}

/// Row 5: reading pixels, copying, flushing, finishing, asking a query of the pass and
/// sampling the pass's texture flush it; drawing continues in a pass that loads.
#[test]
fn flush_triggers_render_the_pass_and_the_rest_loads() {
    check_flush(
        &flushed(|gl| {
            c(gl, Call::ReadPixels { x: 0, y: 0, width: 64, height: 64 });
        }),
        FlushCause::ReadPixels,
    );
    check_flush(
        &flushed(|gl| {
            c(gl, Call::Flush);
        }),
        FlushCause::Flush,
    );
    check_flush(
        &flushed(|gl| {
            c(gl, Call::Finish);
        }),
        FlushCause::Finish,
    );
    check_flush(
        &flushed(|gl| {
            c(gl, Call::QueryResult { id: 1 });
        }),
        FlushCause::QueryResult,
    );
    let copy = flushed(|gl| {
        let copy = Call::CopyTexSubImage {
            texture: 9,
            x_offset: 0,
            y_offset: 0,
            x: 0,
            y: 0,
            width: 64,
            height: 64,
            alpha_one: false,
        };
        c(gl, copy);
    });
    // The copy is a pass of its own, between the two halves.
    let p = passes(&copy);
    assert_eq!(p.len(), 3);
    assert_eq!(p[1].copy_texture, Some(9));
    assert_eq!(p[1].extra.get(Category::TextureFetch), COLOR, "the copy reads the window");
    assert_eq!(store(p[1]), COLOR);
    assert_eq!(p[0].end, EndCause::Flush { flush: FlushCause::CopyTexImage });
    assert_eq!(p[2].start, StartCause::AfterFlush { flush: FlushCause::CopyTexImage });
    assert_eq!(load(p[2]), COLOR + DEPTH + STENCIL);
}

/// Uses textured program `id` with positions and texture coordinates from buffer `id`
/// (`[x, y, s, t]` a vertex).
fn use_textured(gl: &mut Context, id: u32) {
    c(gl, Call::UseProgram { id });
    for (index, offset) in [(0, 0), (1, 8)] {
        c(
            gl,
            Call::VertexAttribPointer {
                index,
                buffer: id,
                size: 2,
                component: ComponentType::Float,
                normalized: false,
                stride: 16,
                offset,
            },
        );
        c(gl, Call::EnableVertexAttrib { index });
    }
}

/// Row 5: sampling the texture of the pass being drawn flushes it.
#[test]
fn sampling_the_pass_texture_flushes() {
    let mut gl = window();
    framebuffer(&mut gl, 2, 64, 64);
    bind(&mut gl, 2);
    clear_all(&mut gl);
    draw(&mut gl, 6);
    let uv: Vec<[f32; 4]> = vec![[-1.0, -1.0, 0.0, 0.0], [1.0, -1.0, 1.0, 0.0], [1.0, 1.0, 1.0, 1.0]];
    c(&mut gl, Call::CreateBuffer { id: 5, data: Bytes::from_slice(&uv) });
    c(&mut gl, Call::CreateProgram { id: 5, program: ProgramKind::Textured.into() });
    use_textured(&mut gl, 5);
    c(&mut gl, Call::BindTexture { unit: 0, texture: 2 });
    draw(&mut gl, 3);
    bind(&mut gl, 0);
    let report = gl.end().unwrap();
    let p = passes(&report);
    assert_eq!(p[0].end, EndCause::Flush { flush: FlushCause::SampleAttachment });
    assert_eq!(p[1].start, StartCause::AfterFlush { flush: FlushCause::SampleAttachment });
    assert_eq!(load(p[1]), COLOR + DEPTH + STENCIL);
}

/// A texture drawn into pass after pass and sampled after each: every sampling sees what the
/// texture holds then — a clear, a draw over part of it, an upload — never the texture as
/// the context built it for an earlier pass; and a texture sampled again unchanged reads the same.
#[test]
fn a_render_target_sampled_after_each_redraw_shows_its_latest_contents() {
    let mut gl = window();
    framebuffer(&mut gl, 2, 64, 64);
    // Full-screen textured quad, (s, t) = GL's (x, y) mapped onto [0, 1].
    let vertices: Vec<[f32; 4]> =
        quad(-1.0, -1.0, 1.0, 1.0, 0.0).iter().map(|&[x, y, _]| [x, y, (x + 1.0) / 2.0, (y + 1.0) / 2.0]).collect();
    c(&mut gl, Call::CreateBuffer { id: 5, data: Bytes::from_slice(&vertices) });
    c(&mut gl, Call::CreateProgram { id: 5, program: ProgramKind::Textured.into() });
    let sample_into_window = |gl: &mut Context| {
        bind(gl, 0);
        use_textured(gl, 5);
        c(gl, Call::BindTexture { unit: 0, texture: 2 });
        draw(gl, 6);
        swap(gl);
        gl.surface_rgba8()
    };
    let fill = |gl: &mut Context, rgba: [f32; 4]| {
        bind(gl, 2);
        c(gl, Call::ClearColor { rgba });
        clear_all(gl);
    };
    fill(&mut gl, [0.0, 1.0, 0.0, 1.0]);
    let green = sample_into_window(&mut gl);
    assert_eq!(pixel(&green, 64, 10, 10), [0, 255, 0, 255]);
    assert_eq!(sample_into_window(&mut gl), green, "sampled again unchanged");
    fill(&mut gl, [0.0, 0.0, 1.0, 1.0]);
    let blue = sample_into_window(&mut gl);
    assert_eq!(pixel(&blue, 64, 10, 10), [0, 0, 255, 255], "the new clear, not the texture built before");
    // The solid red quad over GL's bottom-left quarter, drawn into the texture.
    bind(&mut gl, 2);
    bind_geometry(&mut gl, 1);
    draw(&mut gl, 6);
    let drawn = sample_into_window(&mut gl);
    assert_eq!(pixel(&drawn, 64, 10, 54), [255, 0, 0, 255], "the draw");
    assert_eq!(pixel(&drawn, 64, 54, 10), [0, 0, 255, 255]);
    c(
        &mut gl,
        Call::TexSubImage { id: 2, x: 0, y: 0, width: 64, height: 64, data: Bytes::from(vec![255u8; 64 * 64 * 4]) },
    );
    let uploaded = sample_into_window(&mut gl);
    assert_eq!(pixel(&uploaded, 64, 10, 54), [255; 4], "the upload");
    assert_eq!(pixel(&uploaded, 64, 54, 10), [255; 4]);
}

/// Row 5: changing an attachment of the bound framebuffer, or writing its texture, flushes.
#[test]
fn attachment_changes_and_texture_writes_flush() {
    let mut gl = defined_framebuffer();
    draw(&mut gl, 6);
    c(&mut gl, Call::TexSubImage { id: 2, x: 0, y: 0, width: 1, height: 1, data: Bytes::from(vec![9u8; 4]) });
    draw(&mut gl, 6);
    c(
        &mut gl,
        Call::CreateTexture {
            id: 7,
            width: 64,
            height: 64,
            format: TextureFormat::Rgba8,
            data: None,
            transient: false,
        },
    );
    c(
        &mut gl,
        Call::FramebufferTexture { framebuffer: 2, attachment: AttachmentPoint::Color0, texture: 7, samples: 1 },
    );
    draw(&mut gl, 6);
    bind(&mut gl, 0);
    let report = gl.end().unwrap();
    let p = passes(&report);
    assert_eq!(p[1].end, EndCause::Flush { flush: FlushCause::TextureUpdate });
    assert_eq!(p[2].end, EndCause::Flush { flush: FlushCause::AttachmentChange });
    assert_eq!(op(p[3], Slot::Color(0)).0, DontCare, "the new texture's contents are undefined");
}

/// A blit reads a finished pass (counted as texture fetch) and draws into the open one.
#[test]
fn a_blit_is_a_draw_in_the_destination_pass() {
    let mut gl = defined_framebuffer();
    bind(&mut gl, 0);
    c(&mut gl, Call::ClearColor { rgba: [0.0; 4] });
    clear_all(&mut gl);
    c(&mut gl, Call::BindFramebuffer { target: FramebufferTarget::Read, framebuffer: 2 });
    c(&mut gl, Call::BlitFramebuffer { src: [0, 0, 64, 64], dst: [0, 0, 32, 32], filter: Filter::Nearest });
    swap(&mut gl);
    let image = gl.surface_rgba8();
    let report = gl.end().unwrap();
    let p = passes(&report);
    let window = p.last().unwrap();
    assert_eq!(window.draws[0].kind, report::DrawKind::Blit);
    assert_eq!(window.extra.get(Category::TextureFetch), COLOR);
    assert_eq!(pixel(&image, 64, 5, 60), [0, 0, 255, 255], "the blue texture, in the bottom-left quarter");
    assert_eq!(pixel(&image, 64, 40, 20), [0, 0, 0, 0]);
    bind(&mut gl, 0);
    let e =
        gl.call(Call::BlitFramebuffer { src: [0, 0, 1, 1], dst: [0, 0, 1, 1], filter: Filter::Nearest }).unwrap_err();
    assert!(e.message.contains("to itself"), "{e}");
}

/// Row 6: binding a framebuffer again in the frame is a second pass that loads.
#[test]
fn binding_again_is_a_second_pass_that_loads() {
    let mut gl = window();
    framebuffer(&mut gl, 2, 64, 64);
    bind(&mut gl, 2);
    clear_all(&mut gl);
    draw(&mut gl, 6);
    bind(&mut gl, 0);
    clear_all(&mut gl);
    draw(&mut gl, 6);
    bind(&mut gl, 2);
    draw(&mut gl, 6);
    bind(&mut gl, 0);
    swap(&mut gl);
    let report = gl.end().unwrap();
    let p: Vec<_> = passes(&report).into_iter().filter(|p| p.framebuffer == 2).collect();
    assert_eq!(p.len(), 2);
    assert_eq!(p[1].start, StartCause::Bind);
    assert_eq!(ops(p[1]).iter().map(|o| o.1).collect::<Vec<_>>(), vec![Load, Load, Load]);
    assert_eq!(load(p[1]), COLOR + DEPTH + STENCIL);
    let f: Vec<_> = report.findings_with("framebuffer-rebound").collect();
    assert_eq!(f.len(), 1);
    assert_eq!(f[0].cost_bytes.unwrap_or(0), 2 * (COLOR + DEPTH + STENCIL), "the reloads and the stores they read");
    assert_eq!(f[0].location.pass, Some(p[1].index as u64));
}

fn two_frames(behavior: SwapBehavior) -> Report {
    let mut gl = window();
    c(&mut gl, Call::SwapBehavior { behavior });
    clear_all(&mut gl);
    draw(&mut gl, 6);
    swap(&mut gl);
    draw(&mut gl, 6);
    swap(&mut gl);
    gl.end().unwrap()
}

/// Row 7: after a destroying swap the window starts `DontCare`; after a preserving one, its
/// colour is loaded. Depth and stencil are never kept across a swap.
#[test]
fn swap_behaviour_decides_the_next_frame_load() {
    let destroyed = two_frames(SwapBehavior::Destroyed);
    let p = passes(&destroyed)[1];
    assert_eq!(p.start, StartCause::NewFrame);
    assert_eq!(
        ops(p).iter().map(|o| (o.1, o.2)).collect::<Vec<_>>(),
        vec![(DontCare, StoreKind::Store), (DontCare, StoreKind::DontCare), (DontCare, StoreKind::DontCare)]
    );
    assert_eq!(load(p), 0);
    assert!(destroyed.findings.is_empty());
    let preserved = two_frames(SwapBehavior::Preserved);
    let p = passes(&preserved)[1];
    assert_eq!(op(p, Slot::Color(0)), (Load, StoreKind::Store));
    assert_eq!(op(p, Slot::Depth), (DontCare, StoreKind::DontCare));
    assert_eq!(load(p), COLOR);
    assert_eq!(preserved.findings_with("preserved-swap").count(), 1);
    // The display reads the window at every swap.
    assert_eq!(preserved.frames[1].context_ledger.get(Category::Display), COLOR);
}

/// Row 8: a tiled-rendering region processes only the tiles it meets, loading and storing
/// as the masks say.
#[test]
fn a_tiled_region_limits_the_tiles() {
    let mut gl = window();
    c(&mut gl, Call::SwapBehavior { behavior: SwapBehavior::Preserved });
    clear_all(&mut gl);
    swap(&mut gl);
    geometry(&mut gl, 2, ProgramKind::Solid, &quad(-1.0, -1.0, 1.0, 1.0, 0.0));
    set_color(&mut gl, [0.0, 1.0, 0.0, 1.0]);
    // GL's bottom-left 16×16 pixels: tiler rows 48..64, tile (0, 1) only.
    c(&mut gl, Call::StartTiling { x: 0, y: 0, width: 16, height: 16, preserve: BufferSet::COLOR });
    draw(&mut gl, 6);
    c(&mut gl, Call::EndTiling { store: BufferSet::COLOR });
    c(&mut gl, Call::StartTiling { x: 48, y: 48, width: 16, height: 16, preserve: BufferSet::NONE });
    draw(&mut gl, 6);
    c(&mut gl, Call::EndTiling { store: BufferSet::COLOR });
    swap(&mut gl);
    let image = gl.surface_rgba8();
    let report = gl.end().unwrap();
    let p = &report.frames[1].passes;
    assert_eq!(p.len(), 2);
    assert_eq!(p[0].render_area, Some(tiler::Rect::new(0, 48, 16, 16)));
    assert_eq!(p[0].cost.counters.tiles_processed, 1);
    assert_eq!(p[0].start, StartCause::Tiling);
    assert_eq!(op(&p[0], Slot::Color(0)), (Load, StoreKind::Store));
    assert_eq!(op(&p[0], Slot::Depth), (DontCare, StoreKind::DontCare));
    assert_eq!(load(&p[0]), 16 * 16 * 4);
    assert_eq!(store(&p[0]), 16 * 16 * 4);
    assert_eq!(op(&p[1], Slot::Color(0)), (DontCare, StoreKind::Store), "not in the preserve mask");
    assert_eq!(load(&p[1]), 0);
    assert_eq!(p[1].cost.counters.tiles_processed, 1);
    assert_eq!(pixel(&image, 64, 5, 60), [0, 255, 0, 255]);
    assert_eq!(pixel(&image, 64, 60, 5), [0, 255, 0, 255]);
    assert_eq!(pixel(&image, 64, 30, 30), [0, 0, 0, 0], "outside the regions, the preserved clear");
    assert!(report.findings.is_empty(), "{:#?}", report.findings);
}

/// Row 9: past the frame-data budget the pass is rendered incrementally, storing and
/// reloading everything (depth, stencil, every sample), and the ledger shows the cliff.
#[test]
fn exceeding_the_frame_data_budget_is_an_incremental_render() {
    let run = |budget: u64| {
        let mut gl = Context::new(ContextConfig { frame_data_budget: budget, ..config(64, 64) }).unwrap();
        // 4 samples per pixel, depth and stencil.
        c(
            &mut gl,
            Call::CreateRenderbuffer {
                id: 1,
                width: 64,
                height: 64,
                format: TextureFormat::Rgba8,
                samples: 4,
                transient: false,
            },
        );
        c(
            &mut gl,
            Call::CreateRenderbuffer {
                id: 2,
                width: 64,
                height: 64,
                format: TextureFormat::Depth24Stencil8,
                samples: 4,
                transient: false,
            },
        );
        c(&mut gl, Call::CreateFramebuffer { id: 1 });
        c(
            &mut gl,
            Call::FramebufferRenderbuffer { framebuffer: 1, attachment: AttachmentPoint::Color0, renderbuffer: 1 },
        );
        c(
            &mut gl,
            Call::FramebufferRenderbuffer {
                framebuffer: 1,
                attachment: AttachmentPoint::DepthStencil,
                renderbuffer: 2,
            },
        );
        // 128×80 cells of 2 triangles over the framebuffer: 20480 triangles.
        let mut v = Vec::new();
        let (nx, ny) = (128, 80);
        for j in 0..ny {
            for i in 0..nx {
                let x = |i: usize| -1.0 + 2.0 * i as f32 / nx as f32;
                let y = |j: usize| -1.0 + 2.0 * j as f32 / ny as f32;
                v.extend(quad(x(i), y(j), x(i + 1), y(j + 1), 0.0));
            }
        }
        geometry(&mut gl, 1, ProgramKind::Solid, &v);
        bind(&mut gl, 1);
        clear_all(&mut gl);
        c(&mut gl, Call::Enable { cap: Capability::DepthTest });
        for _ in 0..3 {
            draw(&mut gl, v.len() as u32);
        }
        c(&mut gl, Call::Invalidate { attachments: vec![AttachmentPoint::DepthStencil] });
        bind(&mut gl, 0);
        gl.end().unwrap()
    };
    let cliff = run(1 << 20);
    let p = passes(&cliff)[0];
    let k = p.cost.counters.incremental_renders;
    assert!(k >= 1, "3 × 20480 triangles outgrow a 1 MiB budget");
    let (color, depth_stencil) = (64 * 64 * 4 * 4, 64 * 64 * 4 * 4);
    // Every incremental render stores colour, depth and stencil, all samples, and reloads them.
    assert_eq!(store(p), (k + 1) * color + k * depth_stencil);
    assert_eq!(load(p), k * (color + depth_stencil));
    assert_eq!(op(p, Slot::Depth), (Clear, StoreKind::DontCare), "the pass's own ops are unchanged");
    let f: Vec<_> = cliff.findings_with("incremental-render").collect();
    assert_eq!(f.len(), 1);
    assert_eq!(f[0].cost_bytes.unwrap_or(0), k * (color + depth_stencil) * 2);
    // The same pass within its budget: no cliff, and the difference is exactly the finding.
    let smooth = run(64 << 20);
    let q = passes(&smooth)[0];
    assert_eq!(q.cost.counters.incremental_renders, 0);
    assert_eq!(load(q), 0);
    assert_eq!(store(p) + load(p) - store(q) - load(q), f[0].cost_bytes.unwrap_or(0));
}

/// Row 10: changing a buffer a pending frame uses makes the driver copy it, and the pending
/// draw still sees the old contents.
#[test]
fn changing_a_buffer_in_use_is_copy_on_write() {
    let mut gl = window();
    clear_all(&mut gl);
    draw(&mut gl, 6);
    // Move the quad to the top-right quarter: 6 vertices × 12 bytes, half of them rewritten.
    let moved = quad(0.0, 0.0, 1.0, 1.0, 0.0);
    c(&mut gl, Call::BufferSubData { id: 1, offset: 0, data: Bytes::from_slice(&moved[..3]) });
    c(&mut gl, Call::BufferSubData { id: 1, offset: 36, data: Bytes::from_slice(&moved[3..]) });
    draw(&mut gl, 6);
    swap(&mut gl);
    let image = gl.surface_rgba8();
    // The next frame: still in flight (3 frames), so copied again; orphaning is free.
    c(&mut gl, Call::BufferSubData { id: 1, offset: 0, data: Bytes::from_slice(&moved[..3]) });
    c(&mut gl, Call::BufferData { id: 1, data: Bytes::from_slice(&moved) });
    swap(&mut gl);
    swap(&mut gl);
    swap(&mut gl);
    // Three frames after its last use, the buffer is free to change in place.
    c(&mut gl, Call::BufferSubData { id: 1, offset: 0, data: Bytes::from_slice(&moved[..3]) });
    let report = gl.end().unwrap();
    assert_eq!(pixel(&image, 64, 10, 50), [255, 0, 0, 255], "the first draw used the old vertices");
    assert_eq!(pixel(&image, 64, 50, 10), [255, 0, 0, 255], "the second the new ones");
    // The first update copies the buffer (72 bytes, 36 replaced); the second writes the copy,
    // which nothing pending uses.
    let copies = &report.frames[0].copies;
    assert_eq!(copies.len(), 1);
    assert_eq!(copies[0].bytes_copied, 36);
    assert_eq!(report.frames[0].context_ledger.get(Category::CopyOnWrite), 2 * 36);
    assert_eq!(report.frames[1].copies.len(), 1);
    assert!(report.frames[4].copies.is_empty());
    let f: Vec<_> = report.findings_with("copy-on-write").collect();
    assert_eq!(f.len(), 2);
    assert_eq!(f[0].cost_bytes.unwrap_or(0), 72);
}

/// A sub-data update that replaces a pending buffer whole copies nothing (the driver renames
/// it): no copy-on-write is counted or found.
#[test]
fn replacing_a_buffer_in_use_whole_is_no_copy_on_write() {
    let mut gl = window();
    clear_all(&mut gl);
    draw(&mut gl, 6);
    let moved = quad(0.0, 0.0, 1.0, 1.0, 0.0);
    c(&mut gl, Call::BufferSubData { id: 1, offset: 0, data: Bytes::from_slice(&moved) });
    draw(&mut gl, 6);
    swap(&mut gl);
    let report = gl.end().unwrap();
    assert!(report.frames[0].copies.is_empty());
    assert_eq!(report.frames[0].context_ledger.get(Category::CopyOnWrite), 0);
    assert_eq!(report.findings_with("copy-on-write").count(), 0);
}

/// Row 11: attaching one half of a packed depth-stencil image keeps the other half, loaded
/// and stored, with a warning; separate depth and stencil images are unsupported.
#[test]
fn half_a_packed_depth_stencil_image_is_a_warning() {
    let mut gl = window();
    c(
        &mut gl,
        Call::CreateTexture {
            id: 2,
            width: 64,
            height: 64,
            format: TextureFormat::Rgba8,
            data: None,
            transient: false,
        },
    );
    c(
        &mut gl,
        Call::CreateRenderbuffer {
            id: 2,
            width: 64,
            height: 64,
            format: TextureFormat::Depth24Stencil8,
            samples: 1,
            transient: false,
        },
    );
    c(&mut gl, Call::CreateFramebuffer { id: 2 });
    c(
        &mut gl,
        Call::FramebufferTexture { framebuffer: 2, attachment: AttachmentPoint::Color0, texture: 2, samples: 1 },
    );
    c(&mut gl, Call::FramebufferRenderbuffer { framebuffer: 2, attachment: AttachmentPoint::Depth, renderbuffer: 2 });
    for _ in 0..2 {
        bind(&mut gl, 2);
        clear_all(&mut gl);
        draw(&mut gl, 6);
        c(&mut gl, Call::Invalidate { attachments: vec![AttachmentPoint::Depth] });
        bind(&mut gl, 0);
        swap(&mut gl);
    }
    let report = gl.end().unwrap();
    let p = passes(&report);
    let stencil = p[1].attachment(Slot::Stencil).unwrap();
    assert_eq!(stencil.role, report::Role::Preserved);
    assert_eq!((stencil.load, stencil.store), (Load, StoreKind::Store));
    assert_eq!(load(p[1]), STENCIL_WORD, "the unattached stencil is loaded, its whole word");
    assert_eq!(store(p[1]), COLOR + STENCIL_WORD);
    let f: Vec<_> = report.findings_with("packed-depth-stencil-half").collect();
    assert_eq!(f.len(), 2);
    assert_eq!(f[1].cost_bytes.unwrap_or(0), 2 * STENCIL_WORD);

    c(
        &mut gl,
        Call::CreateRenderbuffer {
            id: 3,
            width: 64,
            height: 64,
            format: TextureFormat::Depth16,
            samples: 1,
            transient: false,
        },
    );
    c(
        &mut gl,
        Call::CreateRenderbuffer {
            id: 4,
            width: 64,
            height: 64,
            format: TextureFormat::Stencil8,
            samples: 1,
            transient: false,
        },
    );
    c(&mut gl, Call::FramebufferRenderbuffer { framebuffer: 2, attachment: AttachmentPoint::Depth, renderbuffer: 3 });
    c(&mut gl, Call::FramebufferRenderbuffer { framebuffer: 2, attachment: AttachmentPoint::Stencil, renderbuffer: 4 });
    bind(&mut gl, 2);
    let e = gl.call(Call::Clear { color: true, depth: true, stencil: true }).unwrap_err();
    assert!(e.message.contains("GL_FRAMEBUFFER_UNSUPPORTED"), "{e}");
}

/// Row 12: a query's result is available only once its pass is rendered and the frames in
/// flight have passed; asking earlier flushes and stalls.
#[test]
fn query_results_wait_for_their_pass_and_the_frames_in_flight() {
    for frames_in_flight in [3, 1] {
        let mut gl =
            Context::new(ContextConfig { frames_in_flight: Some(frames_in_flight), ..config(64, 64) }).unwrap();
        geometry(&mut gl, 1, ProgramKind::Solid, &quad(-1.0, -1.0, 0.0, 0.0, 0.0));
        c(&mut gl, Call::CreateQuery { id: 1 });
        clear_all(&mut gl);
        c(&mut gl, Call::BeginQuery { id: 1 });
        draw(&mut gl, 6);
        c(&mut gl, Call::EndQuery);
        assert_eq!(c(&mut gl, Call::QueryAvailable { id: 1 }), Output::Available(false), "its pass is not rendered");
        swap(&mut gl);
        let mut waited = 0;
        while c(&mut gl, Call::QueryAvailable { id: 1 }) == Output::Available(false) {
            swap(&mut gl);
            waited += 1;
        }
        assert_eq!(waited + 1, frames_in_flight, "available {frames_in_flight} frame(s) after its frame");
        assert_eq!(c(&mut gl, Call::QueryResult { id: 1 }), Output::Samples(32 * 32));
        let report = gl.end().unwrap();
        assert!(report.frames.iter().all(|f| f.stalls.is_empty()), "polling never stalls");
    }
    // Asking in the same frame: the pass is flushed and the CPU waits 3 frames.
    let report = flushed(|gl| assert_eq!(c(gl, Call::QueryResult { id: 1 }), Output::Samples(32 * 32)));
    let stall = &report.frames[0].stalls[0];
    assert_eq!((stall.cause, stall.frames), (report::StallCause::QueryResult, 3));
    assert_eq!(report.findings_with("query-stall").count(), 1);
}

/// Frames in flight: a read-back of this frame stalls 3 frames, of one from 2 frames ago 1.
#[test]
fn readback_stalls_by_the_frames_still_in_flight() {
    let mut gl = window();
    framebuffer(&mut gl, 2, 64, 64);
    bind(&mut gl, 2);
    clear_all(&mut gl);
    draw(&mut gl, 6);
    bind(&mut gl, 0);
    swap(&mut gl);
    swap(&mut gl);
    bind(&mut gl, 2);
    let Output::Pixels(pixels) = c(&mut gl, Call::ReadPixels { x: 0, y: 0, width: 64, height: 64 }) else { panic!() };
    // GL's rows run bottom to top: the quad over GL's bottom-left quarter is in the first rows.
    assert_eq!(&pixels[..4], &[255, 0, 0, 255]);
    assert_eq!(&pixels[(63 * 64 + 63) * 4..], &[0, 0, 0, 0]);
    clear_all(&mut gl);
    draw(&mut gl, 6);
    c(&mut gl, Call::ReadPixels { x: 0, y: 0, width: 1, height: 1 });
    let report = gl.end().unwrap();
    assert_eq!(report.frames[2].stalls.iter().map(|s| s.frames).collect::<Vec<_>>(), vec![1, 3]);
    assert!(gl.call(Call::ReadPixels { x: 60, y: 0, width: 8, height: 1 }).is_err(), "outside the framebuffer");
}

/// Seed 000 §23.6: frames in flight follow the device — a tiler holds one more frame (its
/// geometry stage) than an immediate-mode GPU, so the same read-back stalls 3 frames on a
/// tiler and 2 in immediate mode, and an occlusion query is ready a frame sooner there.
#[test]
fn frames_in_flight_follow_the_backend() {
    for (backend, frames) in [(tiler::Backend::Tbr, 3), (tiler::Backend::Tbdr, 3), (tiler::Backend::Imr, 2)] {
        let mut gl = Context::new(ContextConfig { backend, ..config(64, 64) }).unwrap();
        assert_eq!(gl.config().frames_in_flight, Some(frames), "{backend}");
        geometry(&mut gl, 1, ProgramKind::Solid, &quad(-1.0, -1.0, 0.0, 0.0, 0.0));
        c(&mut gl, Call::CreateQuery { id: 1 });
        clear_all(&mut gl);
        c(&mut gl, Call::BeginQuery { id: 1 });
        draw(&mut gl, 6);
        c(&mut gl, Call::EndQuery);
        c(&mut gl, Call::ReadPixels { x: 0, y: 0, width: 1, height: 1 });
        swap(&mut gl);
        let mut waited = 1;
        while c(&mut gl, Call::QueryAvailable { id: 1 }) == Output::Available(false) {
            swap(&mut gl);
            waited += 1;
        }
        let report = gl.end().unwrap();
        assert_eq!(report.frames[0].latency_frames, frames, "{backend}");
        assert_eq!(report.frames[0].stalls.iter().map(|s| s.frames).collect::<Vec<_>>(), vec![frames], "{backend}");
        assert_eq!(waited, frames, "{backend}: the query's result is ready {frames} frames on");
    }
}

/// Multisampled render to texture: the samples are resolved into the texture in the tile and
/// never stored, except when a flush cuts the pass (the rest of it needs them).
#[test]
fn multisampled_render_to_texture_resolves_in_the_tile() {
    let mut gl = window();
    c(
        &mut gl,
        Call::CreateTexture {
            id: 2,
            width: 64,
            height: 64,
            format: TextureFormat::Rgba8,
            data: None,
            transient: false,
        },
    );
    c(
        &mut gl,
        Call::CreateRenderbuffer {
            id: 3,
            width: 64,
            height: 64,
            format: TextureFormat::Depth24Stencil8,
            samples: 4,
            transient: false,
        },
    );
    c(&mut gl, Call::CreateFramebuffer { id: 2 });
    c(
        &mut gl,
        Call::FramebufferTexture { framebuffer: 2, attachment: AttachmentPoint::Color0, texture: 2, samples: 4 },
    );
    c(
        &mut gl,
        Call::FramebufferRenderbuffer { framebuffer: 2, attachment: AttachmentPoint::DepthStencil, renderbuffer: 3 },
    );
    bind(&mut gl, 2);
    clear_all(&mut gl);
    draw(&mut gl, 6);
    let Output::Pixels(pixels) = c(&mut gl, Call::ReadPixels { x: 0, y: 0, width: 1, height: 1 }) else { panic!() };
    assert_eq!(pixels, [255, 0, 0, 255], "read_pixels reads the resolved texture");
    draw(&mut gl, 6);
    c(&mut gl, Call::Invalidate { attachments: vec![AttachmentPoint::DepthStencil] });
    bind(&mut gl, 0);
    let image = gl.device().read_rgba8(gl.texture_image(2).unwrap()).unwrap();
    let report = gl.end().unwrap();
    let p = passes(&report);
    assert_eq!(p.len(), 2);
    let resolve = |p: &PassRecord| p.cost.ledger.get(Category::Resolve);
    assert_eq!(op(p[0], Slot::Color(0)), (Clear, StoreKind::Store), "a flush keeps the samples");
    assert_eq!(op(p[1], Slot::Color(0)), (Load, StoreKind::DontCare), "then they are discarded");
    assert_eq!(store(p[0]), 4 * COLOR + 4 * (DEPTH + STENCIL));
    assert_eq!(store(p[1]), 0);
    assert_eq!((resolve(p[0]), resolve(p[1])), (COLOR, COLOR));
    assert_eq!(p[1].attachment(Slot::Color(0)).unwrap().resolve_bytes, COLOR);
    assert_eq!(pixel(&image, 64, 5, 60), [255, 0, 0, 255]);
    assert_eq!(report.findings_with("msaa-stored").count(), 0);
    assert_eq!(report.findings_with("flush-mid-pass").count(), 1);
}

/// A multisampled window resolves into the presented image.
#[test]
fn a_multisampled_window_resolves_before_presenting() {
    let mut gl = Context::new(ContextConfig { samples: 4, ..config(64, 64) }).unwrap();
    geometry(&mut gl, 1, ProgramKind::Solid, &[[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [-1.0, 1.0, 0.0]]);
    clear_all(&mut gl);
    draw(&mut gl, 3);
    swap(&mut gl);
    let image = gl.surface_rgba8();
    let report = gl.end().unwrap();
    let p = passes(&report)[0];
    assert_eq!(op(p, Slot::Color(0)), (Clear, StoreKind::DontCare));
    assert_eq!(p.cost.ledger.get(Category::Resolve), COLOR);
    assert_eq!(store(p), 0, "no sample leaves the tile");
    // Inside white, outside black, and the diagonal edge antialiased.
    assert_eq!(pixel(&image, 64, 0, 63), [255, 255, 255, 255]);
    assert_eq!(pixel(&image, 64, 63, 0), [0, 0, 0, 0]);
    assert!(image.chunks(4).any(|p| p[0] > 0 && p[0] < 255), "some pixels are partly covered");
    assert!(report.findings.is_empty(), "{:#?}", report.findings);
}

/// 16 samples: a multisampled window resolves in the tile, whose 32×32 tiles shrink to 16×16
/// to hold 16 samples of colour and D24S8 (16 × 8 B × 16 × 16 = 32 KiB of tile memory).
#[test]
fn a_sixteen_sample_window_resolves_in_a_shrunk_tile() {
    let run = |samples| {
        let mut gl = Context::new(ContextConfig { samples, ..config(64, 64) }).unwrap();
        geometry(&mut gl, 1, ProgramKind::Solid, &[[-1.0, -1.0, 0.0], [1.0, -0.6, 0.0], [-0.3, 1.0, 0.0]]);
        clear_all(&mut gl);
        draw(&mut gl, 3);
        swap(&mut gl);
        let image = gl.surface_rgba8();
        (image, gl.end().unwrap())
    };
    let (image, report) = run(16);
    let p = passes(&report)[0];
    assert_eq!(p.attachment(Slot::Color(0)).unwrap().samples, 16);
    assert_eq!(op(p, Slot::Color(0)), (Clear, StoreKind::DontCare));
    assert_eq!(p.cost.ledger.get(Category::Resolve), COLOR);
    assert_eq!(store(p), 0, "no sample leaves the tile");
    assert_eq!((p.cost.tile_width, p.cost.tile_height), (16, 16));
    // 16 samples give the slanted edges more shades of grey than 4 do.
    let shades = |image: &[u8]| {
        image.chunks(4).map(|p| p[0]).filter(|&r| r > 0 && r < 255).collect::<std::collections::BTreeSet<_>>().len()
    };
    let (four, _) = run(4);
    assert!(shades(&image) > shades(&four), "{} shades at 16×, {} at 4×", shades(&image), shades(&four));
    assert!(report.findings.is_empty(), "{:#?}", report.findings);
}

/// 16-sample renderbuffers stored at the end of their pass cost every sample: colour
/// 64 × 64 × 16 × 4 B = 262,144 B and packed D24S8 one 4-byte word per sample, 262,144 B.
#[test]
fn sixteen_sample_renderbuffers_store_every_sample() {
    let mut gl = window();
    for (id, format) in [(1, TextureFormat::Rgba8), (2, TextureFormat::Depth24Stencil8)] {
        c(&mut gl, Call::CreateRenderbuffer { id, width: 64, height: 64, format, samples: 16, transient: false });
    }
    c(&mut gl, Call::CreateFramebuffer { id: 1 });
    c(&mut gl, Call::FramebufferRenderbuffer { framebuffer: 1, attachment: AttachmentPoint::Color0, renderbuffer: 1 });
    c(
        &mut gl,
        Call::FramebufferRenderbuffer { framebuffer: 1, attachment: AttachmentPoint::DepthStencil, renderbuffer: 2 },
    );
    bind(&mut gl, 1);
    clear_all(&mut gl);
    draw(&mut gl, 6);
    bind(&mut gl, 0);
    let report = gl.end().unwrap();
    let p = passes(&report)[0];
    assert_eq!(p.framebuffer, 1);
    assert_eq!(op(p, Slot::Color(0)), (Clear, StoreKind::Store));
    assert_eq!(p.attachment(Slot::Color(0)).unwrap().samples, 16);
    assert_eq!(store(p), 262_144 + 262_144);
    assert_eq!(load(p), 0);
}

/// Seed 001 on a preserved window: the frame clears and redraws only a scissored region. The
/// pass covers only the box (colour loaded and stored there alone), and the advice keeps
/// the scissor or uses a tiled region — a full clear would erase the rest of the window.
#[test]
fn a_scissored_redraw_of_a_preserved_window_covers_only_the_box() {
    let mut gl = Context::new_recording(config(64, 64)).unwrap();
    geometry(&mut gl, 1, ProgramKind::Solid, &quad(-1.0, -1.0, 0.0, 0.0, 0.0));
    set_color(&mut gl, [1.0, 0.0, 0.0, 1.0]);
    c(&mut gl, Call::SwapBehavior { behavior: SwapBehavior::Preserved });
    clear_all(&mut gl);
    draw(&mut gl, 6);
    swap(&mut gl);
    let before = gl.surface_rgba8();
    // GL's bottom-left 16×16 pixels: tiler rows 48..64.
    c(&mut gl, Call::Scissor { x: 0, y: 0, width: 16, height: 16 });
    c(&mut gl, Call::Enable { cap: Capability::ScissorTest });
    c(&mut gl, Call::ClearColor { rgba: [0.0, 1.0, 0.0, 1.0] });
    clear_all(&mut gl);
    draw(&mut gl, 6);
    swap(&mut gl);
    let after = gl.surface_rgba8();
    let report = gl.end().unwrap();
    let p = &report.frames[1].passes[0];
    assert_eq!(p.render_area, Some(tiler::Rect::new(0, 48, 16, 16)));
    assert_eq!(load(p), 16 * 16 * 4, "only the box's colour is loaded");
    assert_eq!(store(p), 16 * 16 * 4, "and stored");
    // Outside the box the window kept the first frame's picture.
    for (i, (a, b)) in before.chunks(4).zip(after.chunks(4)).enumerate() {
        let (x, y) = (i % 64, i / 64);
        if x >= 16 || y < 48 {
            assert_eq!(a, b, "({x}, {y})");
        }
    }
    let f: Vec<_> = report.findings_with("partial-clear").collect();
    assert_eq!(f.len(), 1);
    assert!(f[0].advice.contains("the window is preserved"), "{}", f[0].advice);
    assert!(f[0].advice.starts_with("to redraw only the 16×16 region at (0, 0)"), "{}", f[0].advice);
    // `--what-if` does not clear without the scissor: that would erase the rest of the window.
    let frames = gl
        .recorded_frames()
        .unwrap()
        .iter()
        .map(|calls| tiler_gl::trace::TraceFrame { repeat: 1, calls: calls.clone() });
    let trace = Trace { description: None, config: gl.config().clone(), frames: frames.collect() };
    let mut fixer = tiler_gl::advisor::what_if::Fixer::new(&trace).unwrap();
    let why = fixer.add(f[0], &report).unwrap_err();
    assert!(why.contains("smaller than the framebuffer"), "{why}");
}
