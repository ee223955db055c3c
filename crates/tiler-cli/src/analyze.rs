//! `tiler analyze`: replay a GL trace, print its render passes, cost and the advisor's
//! findings; optionally write the JSON report and the window's last image.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use tiler_gl::{Limits, Trace, text_report};

use crate::files;

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
    let (trace, inputs) = Trace::read_listing_inputs(&args.trace, Limits::default())
        .with_context(|| format!("reading {}", args.trace.display()))?;
    check(&inputs)?;
    let replay = trace.replay().with_context(|| format!("replaying {}", args.trace.display()))?;
    if let Some(path) = &args.report {
        let json = serde_json::to_string_pretty(&replay.report)?;
        tiler_io::write_atomic(path, json.as_bytes()).context("writing the report")?;
    }
    if let Some(path) = &args.png {
        let c = trace.config;
        files::write_png(path, c.width, c.height, &replay.context.surface_rgba8())?;
    }
    // Files first, so output piped into `head` cannot lose them.
    print!("{}", text_report(&replay.report));
    Ok(())
}
