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
    keep_freed_memory();
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

/// Large blocks (images, textures, frame data, vertex batches: hundreds of kilobytes to
/// megabytes, allocated and freed pass after pass) come from the heap and stay there when
/// freed, instead of glibc's default of a fresh `mmap` for each (zeroed pages, a page fault a
/// page on first touch) and a `munmap` when freed. Measured on the shared glmark2 captures
/// (`perf stat`, docs/benchmarking.md): a quarter fewer page faults and 3–10% less CPU time
/// on the small ones. The process's peak memory is the same: only what was freed is kept.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn keep_freed_memory() {
    // glibc caps the threshold at half its largest heap, 32 MiB on 64-bit: larger blocks still
    // get their own mapping.
    const MMAP_THRESHOLD: libc::c_int = 32 << 20;
    // SAFETY: `mallopt` only sets the allocator's parameters (it takes the allocator's lock);
    // both are valid options with values in their ranges, and a refusal (0) leaves glibc's
    // defaults, which are correct, only slower.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, MMAP_THRESHOLD);
        libc::mallopt(libc::M_TRIM_THRESHOLD, libc::c_int::MAX);
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn keep_freed_memory() {}
