//! Prints a capture one call a line, like `apitrace dump -v`: `cargo run -p tiler-apitrace
//! --example dump -- FILE`. With `--time`, reads each file given and prints only how long it
//! took and what it held.

use std::process::ExitCode;
use std::time::Instant;

use tiler_apitrace::TraceReader;

fn main() -> ExitCode {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let time = args.iter().any(|a| a == "--time");
    args.retain(|a| a != "--time");
    if args.is_empty() {
        eprintln!("usage: dump [--time] FILE...");
        return ExitCode::FAILURE;
    }
    for path in &args {
        if let Err(e) = if time { time_file(path) } else { dump_file(path) } {
            eprintln!("{path}: {e}");
            return ExitCode::FAILURE;
        }
    }
    ExitCode::SUCCESS
}

fn dump_file(path: &str) -> Result<(), Box<dyn std::error::Error>> {
    use std::io::Write;
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

fn time_file(path: &str) -> Result<(), Box<dyn std::error::Error>> {
    let start = Instant::now();
    let mut calls = 0u64;
    let mut reader = TraceReader::open(path)?;
    for call in &mut reader {
        call?;
        calls += 1;
    }
    let wire = start.elapsed();
    println!("{path}: {calls} calls, {} stream bytes, read in {:.2} ms", reader.offset(), wire.as_secs_f64() * 1e3);
    Ok(())
}
