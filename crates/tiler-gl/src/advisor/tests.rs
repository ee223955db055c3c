//! The advisor's index against the brute-force scans it replaced, and its work against the
//! length of the run.

use super::{PassIndex, advise_counting};
use crate::report::{PassRecord, Report, StoreKind};
use crate::{Bytes, Call, ComponentType, Context, ContextConfig, FramebufferTarget, Mode, ProgramKind, TextureFormat};

/// A run of `frames` short frames: each draws into a 4× multisampled framebuffer, stores it,
/// and blits it to the window (two passes, an `msaa-stored` and a `store-unread` finding per
/// frame); every fifth frame also draws into the framebuffer again after the blit (a rebind).
fn short_frames(frames: u32) -> Report {
    let mut gl =
        Context::new(ContextConfig { threads: 1, tile_width: 8, tile_height: 8, ..ContextConfig::new(8, 8) }).unwrap();
    let mut call = |call: Call| {
        gl.call(call).unwrap_or_else(|e| panic!("{e}"));
    };
    let triangle: [[f32; 3]; 3] = [[-1.0, -1.0, 0.5], [3.0, -1.0, 0.5], [-1.0, 3.0, 0.5]];
    call(Call::CreateBuffer { id: 1, data: Bytes::from_slice(&triangle) });
    call(Call::CreateProgram { id: 1, program: ProgramKind::Solid.into() });
    call(Call::UseProgram { id: 1 });
    call(Call::VertexAttribPointer {
        index: 0,
        buffer: 1,
        size: 3,
        component: ComponentType::Float,
        normalized: false,
        stride: 0,
        offset: 0,
    });
    call(Call::EnableVertexAttrib { index: 0 });
    call(Call::CreateRenderbuffer {
        id: 1,
        width: 8,
        height: 8,
        format: TextureFormat::Rgba8,
        samples: 4,
        transient: false,
    });
    call(Call::CreateFramebuffer { id: 1 });
    call(Call::FramebufferRenderbuffer { framebuffer: 1, attachment: crate::AttachmentPoint::Color0, renderbuffer: 1 });
    for frame in 0..frames {
        call(Call::BindFramebuffer { target: FramebufferTarget::Framebuffer, framebuffer: 1 });
        call(Call::Clear { color: true, depth: true, stencil: true });
        call(Call::DrawArrays { mode: Mode::Triangles, first: 0, count: 3 });
        call(Call::BindFramebuffer { target: FramebufferTarget::Framebuffer, framebuffer: 0 });
        call(Call::Clear { color: true, depth: true, stencil: true });
        call(Call::BindFramebuffer { target: FramebufferTarget::Read, framebuffer: 1 });
        call(Call::BlitFramebuffer { src: [0, 0, 8, 8], dst: [0, 0, 8, 8], filter: crate::Filter::Nearest });
        if frame % 5 == 4 {
            call(Call::BindFramebuffer { target: FramebufferTarget::Framebuffer, framebuffer: 1 });
            call(Call::DrawArrays { mode: Mode::Triangles, first: 0, count: 3 });
        }
        call(Call::SwapBuffers);
    }
    gl.end().unwrap()
}

/// The index finds what the scans over every earlier and later pass found.
#[test]
fn the_index_finds_what_the_scans_found() {
    let report = short_frames(12);
    let passes: Vec<&PassRecord> = report.passes().collect();
    let index = PassIndex::new(&report.frames);
    let mut rebound = 0;
    for (i, pass) in passes.iter().enumerate() {
        let scanned = passes[..i]
            .iter()
            .rev()
            .find(|p| p.frame == pass.frame && p.framebuffer == pass.framebuffer && p.copy_texture.is_none());
        assert_eq!(index.same_framebuffer_before(i).map(|p| p.index), scanned.map(|p| p.index), "pass {i}");
        rebound += usize::from(scanned.is_some());
        for (k, a) in pass.attachments.iter().enumerate() {
            let mut reads = 0;
            for p in &passes[i + 1..] {
                reads += p.draws.iter().filter(|d| d.sampled == Some(a.image)).map(|d| d.texture_bytes).sum::<u64>();
                if p.attachments.iter().any(|b| b.image == a.image && b.store == StoreKind::Store) {
                    break;
                }
            }
            assert_eq!(index.reads_until_stored_again(i, k), reads, "pass {i}, {}", a.slot);
        }
        assert_eq!(index.numbered(pass.index).map(|p| p.index), Some(pass.index));
    }
    assert!(rebound > 0, "the run rebinds a framebuffer within a frame");
    assert!(report.findings_with("msaa-stored").count() > 0);
    // The window's blit between reads framebuffer 1: the rebinding is needed, and not advised.
    let rebinds: Vec<usize> = (0..passes.len())
        .filter(|&i| passes[i].framebuffer == 1 && index.same_framebuffer_before(i).is_some())
        .collect();
    assert!(!rebinds.is_empty());
    for i in rebinds {
        let why = index.rebind_needed(i).expect("the blit reads what the first binding drew");
        assert!(why.contains("reads"), "{why}");
    }
    assert_eq!(report.findings_with("framebuffer-rebound").count(), 0);
}

/// The advisor's work grows in step with the run: the pass records the rules are handed
/// stay within a few per pass, at 200 frames and at 800. (Comparing each pass with every
/// earlier one, as the first advisor did, hands out about `passes² / 2`: 125,000 records for
/// the 500 passes of 200 frames.)
#[test]
fn the_advisor_is_linear_in_the_run() {
    let work = |frames: u32| {
        let report = short_frames(frames);
        let passes = report.totals.passes as u64;
        let (findings, handed_out) = advise_counting(&report.config, &report.frames);
        assert_eq!(findings.len(), report.findings.len());
        (passes, handed_out)
    };
    let (short_passes, short_work) = work(200);
    let (long_passes, long_work) = work(800);
    assert_eq!(long_passes, 4 * short_passes);
    for (passes, handed_out) in [(short_passes, short_work), (long_passes, long_work)] {
        assert!(handed_out <= 8 * passes, "{handed_out} pass records handed out for {passes} passes");
    }
    assert!(long_work <= 4 * short_work + 64, "4× the run, {long_work} vs {short_work} records");
}
