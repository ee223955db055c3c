//! The options every command that produces a report shares: the frame rate of the
//! per-second figures, report files (HTML or JSON by extension) and heat-map PNGs.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use tiler_report::Report;

#[derive(Args, Debug)]
pub struct ReportArgs {
    /// Frames per second for the per-second figures: bandwidth (MB/s) and power (mW).
    #[arg(long, default_value_t = 60.0, value_parser = parse_fps)]
    pub fps: f64,

    /// Write a report: PATH.html (one self-contained page: picture, charts, heat maps) or
    /// PATH.json (schema tiler-report/1, docs/report-schema.md). May be given more than once.
    #[arg(long, value_name = "PATH")]
    pub report: Vec<PathBuf>,

    /// Write the per-tile heat maps and the overdraw maps as PNGs into DIR (created if
    /// missing).
    #[arg(long, value_name = "DIR")]
    pub heatmaps: Option<PathBuf>,
}

/// A report file's format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Html,
    Json,
}

fn format_of(path: &Path) -> Result<Format> {
    match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
        Some("html" | "htm") => Ok(Format::Html),
        Some("json") => Ok(Format::Json),
        _ => bail!("--report {}: the name must end in .html or .json (the format follows it)", path.display()),
    }
}

/// Parses a frame rate: a finite number above zero.
fn parse_fps(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(fps) if fps.is_finite() && fps > 0.0 && fps <= 1e6 => Ok(fps),
        _ => Err(format!("'{s}' is not a frame rate (a number of frames per second above 0, e.g. 60)")),
    }
}

impl ReportArgs {
    /// Checks the report paths before any rendering: a known format, a place to write that
    /// is none of `inputs`; and that `--heatmaps` names a folder, not a file.
    ///
    /// # Errors
    /// An unknown extension, a missing directory, a directory or input named as a report, or
    /// a file named as the heat-map folder, naming the path.
    pub fn check(&self, inputs: &[PathBuf]) -> Result<()> {
        for path in &self.report {
            format_of(path)?;
            crate::files::check_output("--report", path, inputs)?;
        }
        if let Some(dir) = &self.heatmaps {
            crate::files::check_dir("--heatmaps", dir)?;
        }
        Ok(())
    }

    /// Whether heat maps are wanted, so the device must record an overdraw map.
    pub fn wants_maps(&self) -> bool {
        !self.report.is_empty() || self.heatmaps.is_some()
    }

    /// Writes the reports and heat maps asked for, then prints the table and where the files
    /// went. Files come first, so output piped into `head` cannot lose them; printing to a
    /// closed pipe is not an error.
    ///
    /// # Errors
    /// A file or directory that cannot be written, naming it.
    pub fn write_and_print(&self, report: &Report) -> Result<()> {
        let lines = self.write(report)?;
        print_table(report, &lines);
        Ok(())
    }

    /// Writes the reports and heat maps asked for (each file whole or not at all); returns
    /// a line per file written, saying where it went.
    ///
    /// # Errors
    /// A file or directory that cannot be written, naming it.
    pub fn write(&self, report: &Report) -> Result<Vec<String>> {
        let mut lines = Vec::new();
        for path in &self.report {
            let text = match format_of(path)? {
                Format::Html => tiler_report::to_html(report),
                Format::Json => tiler_report::to_json(report),
            };
            tiler_io::write_atomic(path, text.as_bytes()).context("writing the report")?;
            lines.push(format!("report → {}", path.display()));
        }
        if let Some(dir) = &self.heatmaps {
            let written = tiler_report::write_heatmaps(report, dir).context("writing the heat maps")?;
            lines.push(format!("{} heat maps → {}", written.len(), dir.display()));
        }
        Ok(lines)
    }
}

/// Prints the side-by-side table and `lines` (where files went); a closed pipe is not an error.
pub fn print_table(report: &Report, lines: &[String]) {
    let mut out = std::io::stdout().lock();
    let _ = write!(out, "\n{}", tiler_report::text_table(report));
    for line in lines {
        let _ = writeln!(out, "{line}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn report_formats_follow_the_extension() {
        assert_eq!(format_of(Path::new("out.HTML")).unwrap(), Format::Html);
        assert_eq!(format_of(Path::new("a/b.json")).unwrap(), Format::Json);
        let e = format_of(Path::new("out.txt")).unwrap_err().to_string();
        assert!(e.contains("out.txt") && e.contains(".html or .json"), "{e}");
        assert!(parse_fps("60").is_ok() && parse_fps("0").is_err() && parse_fps("nan").is_err());
    }
}
