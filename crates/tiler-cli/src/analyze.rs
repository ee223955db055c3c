//! `tiler analyze`: replay a GL trace (JSON) or an apitrace capture, print its render passes,
//! cost and the advisor's findings; replay it on one or several device presets (the same
//! report as `tiler render` and `tiler compare`: devices side by side, HTML, heat maps, each
//! finding priced on each device); optionally write the window's last image, (captures) every
//! presented frame, and the driver's detailed record (`--gl-report`).

use std::io::Read;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use tiler::{DevicePreset, FrameCost, Ledger};
use tiler_gl::advisor::what_if;
use tiler_gl::capture::{self, ReplayOptions};
use tiler_gl::report::{FrameRecord, PassRecord};
use tiler_gl::trace::TraceFrame;
use tiler_gl::{ContextConfig, Limits, Report as GlReport, Trace, text_report};
use tiler_report::{AttachmentInfo, Column, FrameSpan, PassInfo, Report, Rgba8Image, SceneInfo};

use crate::files;
use crate::report_args::{self, ReportArgs};

#[derive(Args, Debug)]
pub struct AnalyzeArgs {
    /// The trace: JSON (see crates/tiler-gl/docs/trace-format.md) or an apitrace capture of an
    /// OpenGL ES 2.0 application (told apart by its first bytes).
    pub trace: PathBuf,

    /// Replay on this device preset: a built-in name (tbr, tbdr, tbr-per-tile-vertex, imr,
    /// imr-no-cache) or a preset file (.toml or .json). It replaces the trace's backend, tile
    /// size, frame-data budget and display model. Default: the trace's own configuration.
    #[arg(long, value_name = "NAME|FILE", conflicts_with = "devices")]
    pub device: Option<String>,

    /// Replay on each of these device presets, comma-separated, and show them side by side
    /// (each must present the same pictures; ratios are to the first); every finding is
    /// priced on each device.
    #[arg(long, value_delimiter = ',', value_name = "NAME|FILE,...")]
    pub devices: Vec<String>,

    #[command(flatten)]
    pub report: ReportArgs,

    /// Also write the driver's detailed record of the run as JSON (format tiler-gl-report,
    /// crates/tiler-gl/docs/report-format.md), of the first device.
    #[arg(long, value_name = "OUT.json")]
    pub gl_report: Option<PathBuf>,

    /// Also write the window's image at the end as a PNG.
    #[arg(long, value_name = "OUT.png")]
    pub png: Option<PathBuf>,

    /// Write every presented frame of a capture as DIR/frame-NNNN.png (0-based).
    #[arg(long, value_name = "DIR")]
    pub frames: Option<PathBuf>,

    /// With --frames: also write the picture of the framebuffer bound for drawing after each
    /// of these capture calls (apitrace call numbers, comma-separated) as
    /// DIR/call-NNNNNNNN.png — the window, or a framebuffer object's first colour attachment:
    /// what a render-to-texture pass drew, or a frame of a capture that never calls
    /// eglSwapBuffers. A snapshot in the middle of a render pass renders it there, as a
    /// glReadPixels would, and the report counts it so.
    #[arg(long, value_delimiter = ',', value_name = "CALL,...", requires = "frames")]
    pub snapshot: Vec<u64>,

    /// Prove the advice: apply each finding's fix to the trace (invalidate before the unbind,
    /// clear after the bind, bind each framebuffer once, read back at the end of the pass),
    /// replay it on each device, and report the bytes it saved beside the estimate and
    /// whether the picture is unchanged. For an apitrace capture, the calls it becomes are
    /// edited.
    #[arg(long)]
    pub what_if: bool,
}

/// The most `--snapshot` calls (each writes a PNG).
const MAX_SNAPSHOTS: usize = 10_000;

/// The window's last picture: width, height, RGBA8 rows top first.
type Picture = (u32, u32, Vec<u8>);

/// The context calls a capture became, one list per frame (for `--what-if`).
type RecordedFrames = Vec<Vec<tiler_gl::Call>>;

/// One replay of the trace: on which device, what the driver recorded, the last picture.
struct Replayed {
    preset: DevicePreset,
    report: GlReport,
    /// Read back only when something uses it (`--png`, the shared report, `--devices`,
    /// `--what-if`): a plain analysis of a short capture spent a millisecond on it.
    picture: Option<Picture>,
    /// The configuration it ran with.
    config: ContextConfig,
}

pub fn run(args: &AnalyzeArgs) -> Result<()> {
    // Outputs are checked before any work, against the trace and then against every file it
    // read (side files, glTF files, presets): none may be overwritten.
    let check = |inputs: &[PathBuf]| -> Result<()> {
        args.report.check(inputs)?;
        if let Some(path) = &args.gl_report {
            files::check_output("--gl-report", path, inputs)?;
        }
        if let Some(path) = &args.png {
            files::check_png("--png", path, inputs)?;
        }
        Ok(())
    };
    check(std::slice::from_ref(&args.trace))?;
    let (presets, preset_files) = if !args.devices.is_empty() {
        crate::compare::presets(&args.devices)?
    } else if let Some(name) = &args.device {
        let (preset, file) = files::load_preset(Some(name.trim())).with_context(|| format!("--device {name}"))?;
        (vec![preset], file.into_iter().collect())
    } else {
        (Vec::new(), Vec::new())
    };
    let mut inputs = vec![args.trace.clone()];
    inputs.extend(preset_files);
    check(&inputs)?;
    // The shared report needs the core's whole record of every pass.
    let shared = !presets.is_empty() || !args.report.report.is_empty() || args.report.heatmaps.is_some();
    let devices: Vec<Option<&DevicePreset>> =
        if presets.is_empty() { vec![None] } else { presets.iter().map(Some).collect() };
    let keep_picture = shared || args.png.is_some() || args.what_if || devices.len() > 1;

    let capture = is_capture(&args.trace)?;
    if !capture && args.frames.is_some() {
        bail!("--frames is for apitrace captures; {} is a JSON trace", args.trace.display());
    }
    if args.snapshot.len() > MAX_SNAPSHOTS {
        bail!("--snapshot: {} calls; at most {MAX_SNAPSHOTS}", args.snapshot.len());
    }
    let mut trace = if capture {
        None
    } else {
        let (trace, trace_inputs) = Trace::read_listing_inputs(&args.trace, Limits::default())
            .with_context(|| format!("reading {}", args.trace.display()))?;
        inputs.extend(trace_inputs);
        check(&inputs)?;
        Some(trace)
    };
    let mut replays: Vec<Replayed> = Vec::with_capacity(devices.len());
    let mut recorded_trace: Option<Trace> = None;
    for (i, device) in devices.iter().enumerate() {
        let configure = |config: ContextConfig| -> ContextConfig {
            let config = match device {
                Some(preset) => config.on_device(&preset.device),
                None => config,
            };
            // Every presented frame is checked, not only the last (`--devices`, `--what-if`).
            ContextConfig { keep_pass_reports: shared, digest_presented: devices.len() > 1 || args.what_if, ..config }
        };
        let (report, picture, config) = match &mut trace {
            Some(trace) => replay_trace(trace, configure, &args.trace, keep_picture)?,
            None => {
                let (report, picture, config, recorded) = replay_capture(args, configure, i == 0, keep_picture)?;
                // `--what-if` edits the calls the capture became, recorded on the first replay.
                if let Some(frames) = recorded {
                    let frames = frames.into_iter().map(|calls| TraceFrame { repeat: 1, calls }).collect();
                    recorded_trace = Some(Trace { description: None, config: config.clone(), frames });
                }
                (report, picture, config)
            }
        };
        let preset = match device {
            Some(preset) => (*preset).clone(),
            None => DevicePreset {
                name: config.backend.name().to_string(),
                description: "the trace's own configuration".into(),
                device: config.device_config(),
            },
        };
        if let Some(first) = replays.first()
            && let Some(frame) = different_picture(&first.report, first.picture.as_ref(), &report, picture.as_ref())
        {
            bail!(
                "{}: '{}' presented a different picture from '{}': every device must give the same pictures, bit \
                 for bit; this is a tiler bug, please report it",
                describe_frame(frame, report.frames.len()),
                preset.name,
                first.preset.name
            );
        }
        replays.push(Replayed { preset, report, picture, config });
    }
    if args.what_if {
        let Some(trace) = trace.as_ref().or(recorded_trace.as_ref()) else {
            bail!("--what-if: the calls of {} were not recorded", args.trace.display());
        };
        for replayed in &mut replays {
            what_if(trace, replayed, &args.trace)?;
        }
    }

    let first = &replays[0];
    if let Some(path) = &args.gl_report {
        let json = serde_json::to_string_pretty(&first.report)?;
        tiler_io::write_atomic(path, json.as_bytes()).context("writing --gl-report")?;
    }
    if let Some(path) = &args.png {
        let Some((width, height, rgba)) = &first.picture else { bail!("--png: the last picture was not read back") };
        files::write_png(path, *width, *height, rgba)?;
    }
    if !shared {
        // Files first, so output piped into `head` cannot lose them.
        print!("{}", text_report(&first.report));
        print!("{}", what_if_text(&first.report.findings));
        return Ok(());
    }
    let report = shared_report(&args.trace, &mut replays, args.report.fps)?;
    let lines = args.report.write(&report)?;
    print!("{}", text_report(&replays[0].report));
    if replays.len() > 1 {
        print!("{}", findings_per_device(&report));
    }
    print!("{}", what_if_text(&report.findings));
    report_args::print_table(&report, &lines);
    Ok(())
}

/// Replays a JSON trace with its configuration changed by `configure`.
/// (The trace's own configuration is put back afterwards; its calls are not copied.)
fn replay_trace(
    trace: &mut Trace,
    configure: impl Fn(ContextConfig) -> ContextConfig,
    path: &Path,
    keep_picture: bool,
) -> Result<(GlReport, Option<Picture>, ContextConfig)> {
    let own = trace.config.clone();
    trace.config = configure(own.clone());
    let replayed = trace.replay();
    let config = std::mem::replace(&mut trace.config, own);
    let replay = replayed.with_context(|| format!("replaying {}", path.display()))?;
    let picture = keep_picture.then(|| (config.width, config.height, replay.context.surface_rgba8()));
    Ok((replay.report, picture, config))
}

/// Applies each finding's fix alone to the trace, replays it as `replayed` ran, and records
/// what it saved and whether the pictures stayed the same in the finding.
fn what_if(trace: &Trace, replayed: &mut Replayed, path: &Path) -> Result<()> {
    let Some((_, _, picture)) = &replayed.picture else { bail!("--what-if: the last picture was not read back") };
    let run = what_if::Run { config: &replayed.config, report: &replayed.report, picture };
    let results = what_if::prove(trace, &run, &replayed.preset.name)
        .map_err(anyhow::Error::msg)
        .with_context(|| format!("--what-if on {}", path.display()))?;
    for (finding, result) in replayed.report.findings.iter_mut().zip(results) {
        finding.what_if.push(result);
    }
    Ok(())
}

/// The first frame whose presented picture differs between two runs of the same calls (each
/// frame's digest, recorded with `digest_presented`), or, when every presented frame is the
/// same, the number of frames if the window's picture at the end differs; `None`: the same.
fn different_picture(a: &GlReport, a_end: Option<&Picture>, b: &GlReport, b_end: Option<&Picture>) -> Option<u32> {
    tiler_gl::report::first_different_frame(&a.frames, &b.frames)
        .or_else(|| (a_end != b_end).then_some(a.frames.len().max(b.frames.len()) as u32))
}

/// `frame 3`, or `the window at the end` for the frame after the last.
fn describe_frame(frame: u32, frames: usize) -> String {
    if frame as usize >= frames { "the window at the end".to_string() } else { format!("frame {frame}") }
}

/// Each fix tried: the bytes it saved beside the estimate, and whether the picture held.
fn what_if_text(findings: &[tiler_report::Finding]) -> String {
    let mut out = String::new();
    for finding in findings {
        for w in &finding.what_if {
            if out.is_empty() {
                out.push_str("\nwhat if (each fix applied alone and the frame replayed):\n");
            }
            let line = match (w.measured_bytes, w.same_picture) {
                (Some(measured), Some(same)) => format!(
                    "{}: measured {} B and {} fragments saved, estimated {} B and {}{}; {}",
                    w.fix,
                    w.measured_bytes_before_elimination.unwrap_or(measured),
                    w.measured_fragments.unwrap_or(0),
                    w.estimated_bytes.unwrap_or(0),
                    w.estimated_fragments.unwrap_or(0),
                    match w.measured_bytes_before_elimination {
                        Some(_) => format!(
                            " (the device moved {measured} B fewer: transaction elimination skips the stores of \
                             unchanged tiles)"
                        ),
                        None => String::new(),
                    },
                    match (same, w.different_frame) {
                        (true, _) => "same pictures".to_string(),
                        (false, Some(frame)) => format!("a DIFFERENT picture from frame {frame}"),
                        (false, None) => "a DIFFERENT picture".to_string(),
                    }
                ),
                _ => format!("not tried: {}", w.fix),
            };
            out.push_str(&format!("  {} ({}) on {}: {line}\n", finding.id, finding.location.describe(), w.device));
        }
    }
    out
}

/// Whether the file starts as an apitrace capture does (only a regular file is opened).
fn is_capture(path: &Path) -> Result<bool> {
    let mut file = tiler_io::open_regular(path)?;
    let mut magic = [0u8; 2];
    let n = file.read(&mut magic).with_context(|| format!("reading {}", path.display()))?;
    Ok(capture::is_capture(&magic[..n]))
}

/// Replays a capture with the context's configuration changed by `configure`; writes the
/// presented frames (`--frames`) when `write_frames`.
fn replay_capture(
    args: &AnalyzeArgs,
    configure: impl Fn(ContextConfig) -> ContextConfig,
    write_frames: bool,
    keep_picture: bool,
) -> Result<(GlReport, Option<Picture>, ContextConfig, Option<RecordedFrames>)> {
    let inputs = std::slice::from_ref(&args.trace);
    let frames_dir = args.frames.as_ref().filter(|_| write_frames);
    if let Some(dir) = frames_dir {
        files::check_dir("--frames", dir)?;
        std::fs::create_dir_all(dir).with_context(|| format!("--frames: creating {}", dir.display()))?;
    }
    let mut snapshots_written = Vec::new();
    let mut write_frame = |frame: &capture::PresentedFrame| -> std::result::Result<(), String> {
        let Some(dir) = frames_dir else { return Ok(()) };
        let path = if frame.snapshot {
            snapshots_written.push(frame.call);
            dir.join(format!("call-{:08}.png", frame.call))
        } else {
            dir.join(format!("frame-{:04}.png", frame.index))
        };
        files::check_png("--frames", &path, inputs)
            .and_then(|()| files::write_png(&path, frame.width, frame.height, frame.rgba))
            .map_err(|e| format!("{e:#}"))
    };
    let defaults = ReplayOptions::default();
    // The first replay records the calls for `--what-if`.
    let record = args.what_if && write_frames;
    let snapshots = if write_frames { args.snapshot.clone() } else { Vec::new() };
    let options = ReplayOptions {
        config: configure(defaults.config.clone()),
        record,
        snapshots,
        presented_frames: frames_dir.is_some(),
        ..defaults
    };
    let replay = capture::replay_file(&args.trace, &options, &mut write_frame)
        .with_context(|| format!("replaying {}", args.trace.display()))?;
    if let Some(missed) = options.snapshots.iter().find(|c| !snapshots_written.contains(c)) {
        bail!(
            "--snapshot {missed}: {} has no call {missed} (its calls are numbered 0 to {})",
            args.trace.display(),
            replay.calls.saturating_sub(1)
        );
    }
    let c = replay.context.config().clone();
    let picture = keep_picture.then(|| (c.width, c.height, replay.context.surface_rgba8()));
    let recorded = replay.context.recorded_frames().map(<[Vec<tiler_gl::Call>]>::to_vec);
    Ok((replay.report, picture, c, recorded))
}

/// The report every frame source shares: one column per replay, the passes as the driver
/// inferred them, and each finding priced on each device.
fn shared_report(path: &Path, replays: &mut [Replayed], fps: f64) -> Result<Report> {
    let columns = replays.iter_mut().map(column).collect::<Result<Vec<_>>>()?;
    let first = &replays[0].report;
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let scene = SceneInfo {
        name: name.clone(),
        width: first.config.width,
        height: first.config.height,
        samples: first.config.samples,
        draws: first.totals.counters.draws,
        triangles: first.totals.counters.primitives,
    };
    let findings = if replays.len() == 1 {
        first.findings.clone()
    } else {
        let per_device: Vec<(String, Vec<tiler_report::Finding>)> =
            replays.iter().map(|r| (r.preset.name.clone(), r.report.findings.clone())).collect();
        tiler_report::finding::merge_per_device(&per_device)
    };
    let frames = first.totals.frames;
    let title = format!(
        "{name}: {frames} frame{} on {} device{}",
        if frames == 1 { "" } else { "s" },
        replays.len(),
        if replays.len() == 1 { "" } else { "s" }
    );
    Ok(Report { title, scene, fps, columns, findings, passes: first.passes().map(pass_info).collect() })
}

/// A replay as a report column: every pass of every frame (with the traffic the driver
/// counts for it), and each frame's presenting and driver costs. The core's pass reports move
/// into the column (each is held once).
fn column(replayed: &mut Replayed) -> Result<Column> {
    let mut frame = FrameCost::default();
    let mut frames = Vec::with_capacity(replayed.report.frames.len());
    for record in &mut replayed.report.frames {
        let first_pass = frame.passes.len();
        for pass in &mut record.passes {
            let Some(core) = pass.core.take() else {
                bail!("pass {} has no record of its cost (an internal error)", pass.index);
            };
            let mut core = *core;
            core.ledger.merge(&pass.extra);
            frame.passes.push(core);
        }
        let (present, driver) = split_context_ledger(record);
        frame.present.merge(&present);
        frame.driver.merge(&driver);
        frames.push(FrameSpan { index: record.index as u64, first_pass, passes: record.passes.len(), present, driver });
    }
    let Some((width, height, pixels)) = replayed.picture.clone() else {
        bail!("the report: the last picture was not read back")
    };
    let image = Rgba8Image::new(width, height, pixels).map_err(anyhow::Error::msg)?;
    Ok(Column {
        label: replayed.preset.name.clone(),
        preset: replayed.preset.clone(),
        backend: replayed.report.config.backend,
        frame,
        image,
        frames: if replayed.report.frames.len() > 1 { frames } else { Vec::new() },
    })
}

/// A frame's traffic outside its passes: presenting it (display, composition), and the rest
/// (the driver's copies on write).
fn split_context_ledger(record: &FrameRecord) -> (Ledger, Ledger) {
    let mut present = Ledger::default();
    let mut driver = Ledger::default();
    for (category, bytes) in record.context_ledger.iter() {
        match category {
            tiler::Category::Display | tiler::Category::Composition => present.add(category, bytes),
            _ => driver.add(category, bytes),
        }
    }
    (present, driver)
}

/// A pass as the driver inferred it.
fn pass_info(pass: &PassRecord) -> PassInfo {
    let name = |value: serde_json::Value| value.as_str().unwrap_or_default().to_string();
    PassInfo {
        frame: pass.frame as u64,
        target: match (pass.copy_texture, pass.framebuffer) {
            (Some(texture), _) => format!("texture {texture} (a copy)"),
            (None, 0) => "the window".to_string(),
            (None, fb) => format!("framebuffer {fb}"),
        },
        began: tiler_gl::pass_began(pass),
        ended: tiler_gl::pass_ended(pass),
        attachments: pass
            .attachments
            .iter()
            .map(|a| AttachmentInfo {
                slot: a.slot.to_string(),
                format: a.gl_format.name().to_string(),
                samples: a.samples,
                load: name(serde_json::to_value(a.load).unwrap_or_default()),
                load_reason: a.load_reason.clone(),
                store: name(serde_json::to_value(a.store).unwrap_or_default()),
                store_reason: a.store_reason.clone(),
            })
            .collect(),
    }
}

/// Each finding with what it costs on each device, and where it costs nothing.
fn findings_per_device(report: &Report) -> String {
    if report.findings.is_empty() {
        return String::new();
    }
    let mut out = String::from("\nfindings per device:\n");
    for finding in &report.findings {
        let mut parts: Vec<String> = finding
            .costs
            .iter()
            .map(|c| {
                let mut what = Vec::new();
                if let Some(bytes) = c.cost_bytes {
                    what.push(format!("{bytes} B"));
                }
                if let Some(fragments) = c.cost_fragments {
                    what.push(format!("{fragments} fragments"));
                }
                if let Some(frames) = c.cost_stall_frames {
                    what.push(format!("{frames} frame(s) stalled"));
                }
                format!("{} {}", c.device, what.join(" + "))
            })
            .collect();
        let free: Vec<&str> = report
            .columns
            .iter()
            .map(|c| c.label.as_str())
            .filter(|label| finding.costs.iter().all(|c| c.device != *label))
            .collect();
        if !free.is_empty() {
            parts.push(format!("nothing on {}", free.join(", ")));
        }
        out.push_str(&format!("  {} ({}): {}\n", finding.id, finding.location.describe(), parts.join("; ")));
    }
    out
}
