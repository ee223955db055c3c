//! `tiler analyze`: replay a GL trace (JSON) or an apitrace capture, print its render passes,
//! cost and the advisor's findings; optionally write the JSON report, the window's last image,
//! and (captures) every presented frame.

use std::io::Read;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use tiler_gl::capture::{self, ReplayOptions};
use tiler_gl::{Limits, Report, Trace, text_report};

use crate::files;

#[derive(Args, Debug)]
pub struct AnalyzeArgs {
    /// The trace: JSON (see crates/tiler-gl/docs/trace-format.md) or an apitrace capture of an
    /// OpenGL ES 2.0 application (told apart by its first bytes).
    pub trace: PathBuf,

    /// Also write the report as JSON (see crates/tiler-gl/docs/report-format.md).
    #[arg(long, value_name = "OUT.json")]
    pub report: Option<PathBuf>,

    /// Also write the window's image at the end as a PNG.
    #[arg(long, value_name = "OUT.png")]
    pub png: Option<PathBuf>,

    /// Write every presented frame of a capture as DIR/frame-NNNN.png (0-based).
    #[arg(long, value_name = "DIR")]
    pub frames: Option<PathBuf>,
}

/// The window's last picture: width, height, RGBA8 rows top first.
type Picture = (u32, u32, Vec<u8>);

pub fn run(args: &AnalyzeArgs) -> Result<()> {
    // Outputs are checked before any work, against the trace and then against every file it
    // read (side files, glTF files): none may be overwritten.
    let check = |inputs: &[PathBuf]| -> Result<()> {
        if let Some(path) = &args.report {
            files::check_output("--report", path, inputs)?;
        }
        if let Some(path) = &args.png {
            files::check_png("--png", path, inputs)?;
        }
        Ok(())
    };
    check(std::slice::from_ref(&args.trace))?;
    let (report, last) = if is_capture(&args.trace)? {
        analyze_capture(args)?
    } else {
        if args.frames.is_some() {
            bail!("--frames is for apitrace captures; {} is a JSON trace", args.trace.display());
        }
        let (trace, inputs) = Trace::read_listing_inputs(&args.trace, Limits::default())
            .with_context(|| format!("reading {}", args.trace.display()))?;
        check(&inputs)?;
        let replay = trace.replay().with_context(|| format!("replaying {}", args.trace.display()))?;
        let c = &trace.config;
        let last = (c.width, c.height, replay.context.surface_rgba8());
        (replay.report, last)
    };
    if let Some(path) = &args.report {
        let json = serde_json::to_string_pretty(&report)?;
        tiler_io::write_atomic(path, json.as_bytes()).context("writing the report")?;
    }
    if let Some(path) = &args.png {
        let (width, height, rgba) = last;
        files::write_png(path, width, height, &rgba)?;
    }
    // Files first, so output piped into `head` cannot lose them.
    print!("{}", text_report(&report));
    Ok(())
}

/// Whether the file starts as an apitrace capture does (only a regular file is opened).
fn is_capture(path: &Path) -> Result<bool> {
    let mut file = tiler_io::open_regular(path)?;
    let mut magic = [0u8; 2];
    let n = file.read(&mut magic).with_context(|| format!("reading {}", path.display()))?;
    Ok(capture::is_capture(&magic[..n]))
}

fn analyze_capture(args: &AnalyzeArgs) -> Result<(Report, Picture)> {
    let inputs = std::slice::from_ref(&args.trace);
    if let Some(dir) = &args.frames {
        files::check_dir("--frames", dir)?;
        std::fs::create_dir_all(dir).with_context(|| format!("--frames: creating {}", dir.display()))?;
    }
    let mut write_frame = |frame: &capture::PresentedFrame| -> std::result::Result<(), String> {
        let Some(dir) = &args.frames else { return Ok(()) };
        let path = dir.join(format!("frame-{:04}.png", frame.index));
        files::check_png("--frames", &path, inputs)
            .and_then(|()| files::write_png(&path, frame.width, frame.height, frame.rgba))
            .map_err(|e| format!("{e:#}"))
    };
    let replay = capture::replay_file(&args.trace, &ReplayOptions::default(), &mut write_frame)
        .with_context(|| format!("replaying {}", args.trace.display()))?;
    let c = replay.context.config();
    let last = (c.width, c.height, replay.context.surface_rgba8());
    Ok((replay.report, last))
}
