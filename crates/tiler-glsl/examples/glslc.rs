//! Compiles and links GLSL ES programs and prints what linking found, or the error:
//! `glslc VERTEX FRAGMENT [VERTEX FRAGMENT …]`.

use std::process::ExitCode;

use tiler_glsl::CompiledProgram;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.is_empty() || !args.len().is_multiple_of(2) {
        eprintln!("usage: glslc VERTEX FRAGMENT [VERTEX FRAGMENT …]");
        return ExitCode::FAILURE;
    }
    let mut failed = 0;
    for pair in args.chunks(2) {
        let read = |path: &str| std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"));
        let result = read(&pair[0]).and_then(|vs| {
            let fs = read(&pair[1])?;
            CompiledProgram::new(&vs, &fs, &[]).map_err(|e| e.to_string())
        });
        match result {
            Ok(p) => {
                let (vertex_insts, fragment_insts) = p.instruction_counts();
                let attributes: Vec<String> =
                    p.attributes().iter().map(|a| format!("{}@{}", a.name, a.location)).collect();
                let uniforms: Vec<String> = p
                    .uniforms()
                    .iter()
                    .map(|u| format!("{} {}[{}]@{}", u.ty, u.name, u.array_size, u.location))
                    .collect();
                println!(
                    "ok   {}: attributes {}; varyings {} floats; uniforms {}; discards {}; instructions {}+{}",
                    pair[1],
                    attributes.join(" "),
                    p.varying_floats(),
                    uniforms.join(", "),
                    p.fragment_properties().discards,
                    vertex_insts,
                    fragment_insts
                );
            }
            Err(e) => {
                failed += 1;
                println!("FAIL {}: {e}", pair[1]);
            }
        }
    }
    println!("{} of {} programs compiled and linked", args.len() / 2 - failed, args.len() / 2);
    if failed == 0 { ExitCode::SUCCESS } else { ExitCode::FAILURE }
}
