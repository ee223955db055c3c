//! `tiler analyze`: replay a GL trace (JSON) or an apitrace capture, print its render passes,
//! cost and the advisor's findings; optionally write the JSON report, the window's last image,
//! and (captures) every presented frame.

use std::io::Read;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use tiler_gl::capture::{self, ReplayOptions};
use tiler_gl::{Report, Trace, text_report};

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

pub fn run(args: &AnalyzeArgs) -> Result<()> {
    let (report, last) = if is_capture(&args.trace)? {
        analyze_capture(args)?
    } else {
        if args.frames.is_some() {
            bail!("--frames is for apitrace captures; {} is a JSON trace", args.trace.display());
        }
        let trace = Trace::read(&args.trace).with_context(|| format!("reading {}", args.trace.display()))?;
        let replay = trace.replay().with_context(|| format!("replaying {}", args.trace.display()))?;
        let c = &trace.config;
        let last = (c.width, c.height, replay.context.surface_rgba8());
        (replay.report, last)
    };
    print!("{}", text_report(&report));
    if let Some(path) = &args.report {
        let json = serde_json::to_string_pretty(&report)?;
        std::fs::write(path, json).with_context(|| format!("writing {}", path.display()))?;
    }
    if let Some(path) = &args.png {
        let (width, height, rgba) = last;
        crate::render::write_png(path, width, height, &rgba)?;
    }
    Ok(())
}

/// Whether the file starts as an apitrace capture does.
fn is_capture(path: &Path) -> Result<bool> {
    let mut magic = [0u8; 2];
    let mut file = std::fs::File::open(path).with_context(|| format!("opening {}", path.display()))?;
    let n = file.read(&mut magic).with_context(|| format!("reading {}", path.display()))?;
    Ok(capture::is_capture(&magic[..n]))
}

/// The window's last picture: width, height, RGBA8 rows top first.
type Picture = (u32, u32, Vec<u8>);

fn analyze_capture(args: &AnalyzeArgs) -> Result<(Report, Picture)> {
    if let Some(dir) = &args.frames {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let mut write_frame = |frame: &capture::PresentedFrame| -> std::result::Result<(), String> {
        let Some(dir) = &args.frames else { return Ok(()) };
        let path = dir.join(format!("frame-{:04}.png", frame.index));
        crate::render::write_png(&path, frame.width, frame.height, frame.rgba).map_err(|e| format!("{e:#}"))
    };
    let replay = capture::replay_file(&args.trace, &ReplayOptions::default(), &mut write_frame)
        .with_context(|| format!("replaying {}", args.trace.display()))?;
    let c = replay.context.config();
    let last = (c.width, c.height, replay.context.surface_rgba8());
    Ok((replay.report, last))
}
