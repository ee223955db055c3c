//! Prints a capture one call a line: `cargo run -p tiler-apitrace --example dump -- FILE`.
//!
//! - default: like `apitrace dump -v` (number, name, arguments, return value, `// fake`);
//! - `--typed`: each call as this crate decodes it (`number command`);
//! - `--time`: reads each file given, raw and typed, and prints only how long that took
//!   (the fastest of several runs).

use std::io::Write;
use std::process::ExitCode;
use std::time::Instant;

use tiler_apitrace::{GlesReader, TraceReader};

fn main() -> ExitCode {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let time = args.iter().any(|a| a == "--time");
    let typed = args.iter().any(|a| a == "--typed");
    args.retain(|a| a != "--time" && a != "--typed");
    if args.is_empty() {
        eprintln!("usage: dump [--typed | --time] FILE...");
        return ExitCode::FAILURE;
    }
    for path in &args {
        let result = if time {
            time_file(path)
        } else if typed {
            dump_typed(path)
        } else {
            dump_file(path)
        };
        if let Err(e) = result {
            eprintln!("{path}: {e}");
            return ExitCode::FAILURE;
        }
    }
    ExitCode::SUCCESS
}

fn dump_file(path: &str) -> Result<(), Box<dyn std::error::Error>> {
    let reader = TraceReader::open(path)?;
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    for (name, value) in &reader.header().properties {
        writeln!(out, "// {name} = {value:?}")?;
    }
    for call in reader {
        writeln!(out, "{}", call?)?;
    }
    Ok(())
}

fn dump_typed(path: &str) -> Result<(), Box<dyn std::error::Error>> {
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    for call in GlesReader::open(path)? {
        let call = call?;
        let fake = if call.fake { " // fake" } else { "" };
        writeln!(out, "{} {:?}{fake}", call.number, call.command)?;
    }
    Ok(())
}

/// Runs of each timing; the fastest is printed (the machine is shared).
const RUNS: usize = 7;

fn time_file(path: &str) -> Result<(), Box<dyn std::error::Error>> {
    let mut wire = f64::INFINITY;
    let mut typed = f64::INFINITY;
    let mut calls = 0u64;
    let mut bytes = 0;
    for _ in 0..RUNS {
        let start = Instant::now();
        let mut reader = TraceReader::open(path)?;
        calls = 0;
        for call in &mut reader {
            call?;
            calls += 1;
        }
        wire = wire.min(start.elapsed().as_secs_f64());
        bytes = reader.offset();
        let start = Instant::now();
        for call in GlesReader::open(path)? {
            call?;
        }
        typed = typed.min(start.elapsed().as_secs_f64());
    }
    println!(
        "{path}: {calls} calls, {bytes} uncompressed bytes; wire {:.2} ms, typed {:.2} ms \
         (fastest of {RUNS})",
        wire * 1e3,
        typed * 1e3
    );
    Ok(())
}
