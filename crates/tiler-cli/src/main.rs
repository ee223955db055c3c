//! `tiler`: render scenes on a software tile-based GPU and see what each frame costs.

mod analyze;
mod bench;
mod compare;
mod diff;
mod files;
mod frame;
mod render;
mod report_args;
mod scene_args;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// A tile-based deferred GPU in software: renders scenes the way mobile GPUs do and counts
/// every byte that crosses to external memory, so you can see what a frame costs on a tiler
/// versus an immediate-mode GPU.
#[derive(Parser)]
#[command(name = "tiler", version, about, long_about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a glTF file (or the built-in scene) to a PNG and print its cost on each backend,
    /// side by side.
    Render(render::RenderArgs),
    /// Time the benchmark scenes of SCENES.md (clear, glTF models, overdraw, tris).
    Bench(bench::BenchArgs),
    /// Render the same frame on several device presets and compare what it costs on each.
    Compare(compare::CompareArgs),
    /// Replay a GL trace: its inferred render passes, what they cost, and advice.
    Analyze(analyze::AnalyzeArgs),
    /// Compare two PNGs with the reference tolerance (99% of pixels within 8/255 per channel).
    Diff(diff::DiffArgs),
}

fn main() -> ExitCode {
    restore_sigpipe();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => render::run(&args),
        Command::Bench(args) => bench::run(&args),
        Command::Compare(args) => compare::run(&args),
        Command::Analyze(args) => analyze::run(&args),
        Command::Diff(args) => diff::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("tiler: error: {error:#}");
            ExitCode::FAILURE
        }
    }
}

/// Printing into a closed pipe (`tiler analyze t.json | head -1`) ends the program quietly, by
/// SIGPIPE, as it ends `cat` or `grep`: Rust ignores the signal at start-up, which turns every
/// later `print!` into a panic instead.
#[cfg(unix)]
fn restore_sigpipe() {
    // SAFETY: called first thing in `main`, before any other thread exists; SIG_DFL is a valid
    // disposition for SIGPIPE and no handler of ours is replaced.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

#[cfg(not(unix))]
fn restore_sigpipe() {}
