//! The plain-text report of `tiler analyze`: frames, their inferred passes with load and
//! store ops and why, what each moved, and the advisor's findings.

use std::fmt::Write;

use tiler::{Category, Ledger};

use crate::report::{CallRef, EndCause, PassRecord, Report, StartCause};

fn kb(bytes: u64) -> String {
    if bytes == 0 {
        "0".to_string()
    } else if bytes < 10_000 {
        format!("{bytes} B")
    } else if bytes < 10_000_000 {
        format!("{:.1} kB", bytes as f64 / 1e3)
    } else {
        format!("{:.2} MB", bytes as f64 / 1e6)
    }
}

/// The non-zero categories of a ledger, `name bytes, …`.
fn categories(ledger: &Ledger) -> String {
    let parts: Vec<String> = Category::ALL
        .iter()
        .filter(|c| ledger.get(**c) > 0)
        .map(|c| format!("{} {}", c.name().replace('_', " "), kb(ledger.get(*c))))
        .collect();
    if parts.is_empty() { "nothing".to_string() } else { parts.join(", ") }
}

/// Why a pass began, and where: `bound at frame 0, call 12`.
pub fn pass_began(pass: &PassRecord) -> String {
    match pass.start {
        StartCause::Bind => format!("bound at {}", pass.started_at),
        StartCause::NewFrame => format!("new frame at {}", pass.started_at),
        StartCause::AfterFlush { flush } => format!("continues after {} at {}", flush.describe(), pass.started_at),
        StartCause::Tiling => format!("start_tiling at {}", pass.started_at),
        StartCause::Copy => format!("copy at {}", pass.started_at),
        StartCause::BeginPass => format!("begin_pass at {}", pass.started_at),
    }
}

/// Why a pass ended, and where: `swap at frame 0, call 40`.
pub fn pass_ended(pass: &PassRecord) -> String {
    let what = match pass.end {
        EndCause::Bind => "unbound".to_string(),
        EndCause::Swap => "swap".to_string(),
        EndCause::Flush { flush } => format!("FLUSHED by {}", flush.describe()),
        EndCause::EndTiling => "end_tiling".to_string(),
        EndCause::Copy => "copy done".to_string(),
        EndCause::End => "end of trace".to_string(),
        EndCause::EndPass => "end_pass".to_string(),
    };
    format!("{what} at {}", pass.ended_at)
}

/// The whole report as text.
pub fn text_report(report: &Report) -> String {
    let mut out = String::new();
    let c = &report.config;
    // The calls after the last swap make a frame of their own, counted but never presented
    // (`--frames` writes only the presented ones).
    let presented = report.frames.iter().filter(|frame| frame.swapped).count();
    let frames = match report.totals.frames as usize - presented {
        0 => format!("{presented} frame(s)"),
        _ => format!("{} frame(s), {presented} presented", report.totals.frames),
    };
    let _ = writeln!(
        out,
        "{frames}, {} render pass(es); window {}×{} {}, {} backend, {}×{} tiles, {} frame(s) in flight",
        report.totals.passes,
        c.width,
        c.height,
        c.color_format.name(),
        c.backend,
        c.tile_width,
        c.tile_height,
        c.frames_in_flight.unwrap_or(c.backend.frames_in_flight())
    );
    for frame in &report.frames {
        let _ = writeln!(
            out,
            "\nframe {} ({} calls{}): {}",
            frame.index,
            frame.calls,
            if frame.swapped { ", swapped" } else { "" },
            kb(frame.ledger.total())
        );
        for pass in &frame.passes {
            let target = match pass.copy_texture {
                Some(t) => format!("copy into texture {t}"),
                None if pass.framebuffer == 0 => "window".to_string(),
                None => format!("framebuffer {}", pass.framebuffer),
            };
            let area = match pass.render_area {
                Some(r) => format!(", region {}×{} at ({}, {})", r.width, r.height, r.x, r.y),
                None => String::new(),
            };
            let _ = writeln!(
                out,
                "  pass {}: {target} {}×{}×{}{area}, {} draw(s); {} → {}",
                pass.index,
                pass.width,
                pass.height,
                pass.samples,
                pass.draws.len(),
                pass_began(pass),
                pass_ended(pass)
            );
            for a in &pass.attachments {
                let _ = writeln!(
                    out,
                    "      {:<8} {:>9} → {:<9} load {:>8}  store {:>8}   ({}; {})",
                    a.slot.to_string(),
                    format!("{:?}", a.load).to_lowercase(),
                    format!("{:?}", a.store).to_lowercase(),
                    kb(a.load_bytes),
                    kb(a.store_bytes),
                    a.load_reason,
                    a.store_reason
                );
            }
            for (i, sp) in pass.subpasses.iter().enumerate() {
                let into: Vec<_> = pass.dependencies.iter().filter(|d| d.dst == i as u32).collect();
                let mut writes: Vec<String> = sp.color.iter().map(|c| format!("color{c}")).collect();
                if sp.depth_stencil {
                    writes.push("depth-stencil".to_string());
                }
                let reads: Vec<String> = sp
                    .input
                    .iter()
                    .map(|r| match r {
                        tiler::AttachmentRef::Color(c) => format!("color{c}"),
                        tiler::AttachmentRef::DepthStencil => "depth-stencil".to_string(),
                    })
                    .collect();
                let _ = writeln!(
                    out,
                    "      subpass {i}: writes {}, reads {}, {} draw(s){}",
                    if writes.is_empty() { "nothing".to_string() } else { writes.join(", ") },
                    if reads.is_empty() { "no inputs".to_string() } else { reads.join(", ") },
                    pass.draw_subpasses.iter().filter(|s| **s == i as u32).count(),
                    into.iter()
                        .map(|d| format!(
                            "; after subpass {} {}",
                            d.src,
                            if d.by_region { "by region" } else { "NOT by region (split)" }
                        ))
                        .collect::<String>()
                );
            }
            if pass.cost.transient_bytes_saved > 0 {
                let _ = writeln!(
                    out,
                    "      transient attachments: {} of memory not needed (never left the tile)",
                    kb(pass.cost.transient_bytes_saved)
                );
            }
            if pass.cost.counters.subpass_splits > 0 {
                let _ = writeln!(
                    out,
                    "      {} subpass split(s): every attachment stored and reloaded through memory",
                    pass.cost.counters.subpass_splits
                );
            }
            for d in &pass.dropped {
                let _ = writeln!(out, "      {} draw(s) thrown away by the {} at {}", d.draws, d.by, d.call);
            }
            let mut all = pass.cost.ledger;
            all.merge(&pass.extra);
            let counters = &pass.cost.counters;
            let _ = writeln!(
                out,
                "      moved {}: {}; {} primitives, {} fragments shaded, {} tiles, {} incremental render(s)",
                kb(all.total()),
                categories(&all),
                counters.primitives,
                counters.fragments_shaded,
                counters.tiles_processed,
                counters.incremental_renders
            );
        }
        if frame.context_ledger.total() > 0 {
            let _ = writeln!(out, "  outside passes: {}", categories(&frame.context_ledger));
        }
        for s in &frame.stalls {
            let _ = writeln!(
                out,
                "  stall: {:?} at {} waited {} frame(s) for frame {}",
                s.cause, s.call, s.frames, s.waited_for_frame
            );
        }
    }
    let _ = writeln!(out, "\ntotal {}: {}", kb(report.totals.ledger.total()), categories(&report.totals.ledger));
    if report.findings.is_empty() {
        let _ = writeln!(out, "\nno findings");
    } else {
        let _ = writeln!(out, "\n{} finding(s):", report.findings.len());
    }
    for f in &report.findings {
        let (frame, pass) = (f.location.frame.unwrap_or(0), f.location.pass);
        let place = match (pass, f.location.call_at.map(CallRef::from)) {
            (Some(p), Some(c)) => format!("pass {p}, {c}"),
            (None, Some(c)) => c.to_string(),
            (Some(p), None) => format!("frame {frame}, pass {p}"),
            (None, None) => format!("frame {frame}"),
        };
        let mut cost = Vec::new();
        if let Some(bytes) = f.cost_bytes.filter(|n| *n > 0) {
            cost.push(format!("{bytes} bytes"));
        }
        if let Some(fragments) = f.cost_fragments.filter(|n| *n > 0) {
            cost.push(format!("{fragments} fragments"));
        }
        if let Some(frames) = f.cost_stall_frames.filter(|n| *n > 0) {
            cost.push(format!("{frames} frame(s) stalled"));
        }
        let cost = if cost.is_empty() { String::new() } else { format!(" — costs {}", cost.join(", ")) };
        let _ = writeln!(out, "\n  [{:?}] {} at {place}{cost}", f.severity, f.id);
        let _ = writeln!(out, "    {}", f.message);
        let _ = writeln!(out, "    rule ({}): {}", f.rule.section, f.rule.text);
        let _ = writeln!(out, "    instead: {}", f.advice);
    }
    out
}
