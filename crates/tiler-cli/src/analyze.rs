//! `tiler analyze`: replay a GL trace, print its render passes, cost and the advisor's
//! findings; optionally write the JSON report and the window's last image.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use tiler_gl::{Trace, text_report};

#[derive(Args, Debug)]
pub struct AnalyzeArgs {
    /// The trace (JSON, see crates/tiler-gl/docs/trace-format.md).
    pub trace: PathBuf,

    /// Also write the report as JSON (see crates/tiler-gl/docs/report-format.md).
    #[arg(long, value_name = "OUT.json")]
    pub report: Option<PathBuf>,

    /// Also write the window's image at the end as a PNG.
    #[arg(long, value_name = "OUT.png")]
    pub png: Option<PathBuf>,
}

pub fn run(args: &AnalyzeArgs) -> Result<()> {
    let trace = Trace::read(&args.trace).with_context(|| format!("reading {}", args.trace.display()))?;
    let replay = trace.replay().with_context(|| format!("replaying {}", args.trace.display()))?;
    print!("{}", text_report(&replay.report));
    if let Some(path) = &args.report {
        let json = serde_json::to_string_pretty(&replay.report)?;
        std::fs::write(path, json).with_context(|| format!("writing {}", path.display()))?;
    }
    if let Some(path) = &args.png {
        let c = trace.config;
        crate::render::write_png(path, c.width, c.height, &replay.context.surface_rgba8())?;
    }
    Ok(())
}
