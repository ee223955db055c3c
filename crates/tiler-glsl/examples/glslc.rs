//! Compiles and links GLSL ES programs, prints what linking found (or the error), and renders
//! each once as a smoke test: `glslc [--ir] VERTEX FRAGMENT [VERTEX FRAGMENT …]`. With `--ir`
//! it also prints each stage's lowered code, as the executor runs it (after folding, hoisting,
//! fusion and scheduling) and the bank program run once per instance.
//!
//! The render draws a full-screen triangle into a 64×64 target with every attribute set to
//! the vertex's position, `mat4` uniforms the identity, other uniforms zero and no textures,
//! and prints how many pixels the fragment shader wrote (kept, not discarded).

use std::process::ExitCode;
use std::sync::Arc;

use tiler::{
    ColorAttachment, Device, DeviceConfig, Draw, Format, ImageDesc, PipelineDesc, RenderPass, RenderPassDesc,
    VertexFormat, VertexInputState,
};
use tiler_glsl::ir::{BANK, Inst};
use tiler_glsl::{CompiledProgram, Stage, Type};

/// Renders `program` as described in the module docs; returns the pixels written.
fn smoke_render(program: CompiledProgram) -> Result<usize, String> {
    let program = Arc::new(program);
    let mut uniforms = program.new_uniform_values();
    let identity: Vec<f32> = (0..16).map(|i| if i % 5 == 0 { 1.0 } else { 0.0 }).collect();
    for u in program.uniforms() {
        if u.ty == Type::Matrix(4, 4) {
            for k in 0..u.array_size as u32 {
                program.set_uniform(&mut uniforms, u.location + k, &identity).map_err(|e| e.to_string())?;
            }
        }
    }
    let columns = |ty: &Type| if let Type::Matrix(c, _) = ty { *c } else { 1 };
    let locations = program.attributes().iter().map(|a| a.location as usize + columns(&a.ty)).max().unwrap_or(1);
    let formats = vec![VertexFormat::Float32x4; locations];
    let corners = [[-1.0f32, -1.0, 0.5, 1.0], [3.0, -1.0, 0.5, 1.0], [-1.0, 3.0, 0.5, 1.0]];
    let vertices: Vec<[f32; 4]> = corners.iter().flat_map(|c| std::iter::repeat_n(*c, locations)).collect();
    let desc = PipelineDesc::new("glslc", VertexInputState::interleaved(&formats));
    let pipeline = tiler_glsl::pipeline(&program, &uniforms, &[], 64, desc).map_err(|e| e.to_string())?;
    let mut device = Device::new(DeviceConfig::default()).map_err(|e| e.to_string())?;
    let color = device.create_image(ImageDesc::new(64, 64, Format::Rgba8Unorm)).map_err(|e| e.to_string())?;
    let buffer = device.create_buffer_from(&vertices).map_err(|e| e.to_string())?;
    let mut pass = RenderPass::new(RenderPassDesc {
        color: vec![ColorAttachment::clear_store(color, [0.0, 0.0, 0.0, 0.0])],
        depth_stencil: None,
        render_area: None,
    });
    pass.draw(Draw::new(&pipeline, buffer, 0, 3));
    device.submit(&pass).map_err(|e| e.to_string())?;
    let pixels = device.read_rgba8(color).map_err(|e| e.to_string())?;
    Ok(pixels.chunks(4).filter(|p| *p != [0, 0, 0, 0]).count())
}

/// Prints a stage's lowered code, one instruction per line (nested blocks indented).
fn print_ir(stage: Stage, source: &str) {
    fn block(code: &[Inst], depth: usize) {
        for inst in code {
            let pad = "  ".repeat(depth + 1);
            match inst {
                Inst::If(c, then, els) => {
                    println!("{pad}If({c})");
                    block(then, depth + 1);
                    println!("{pad}Else");
                    block(els, depth + 1);
                }
                Inst::Loop { cond_code, cond, body, step, test_first } => {
                    println!("{pad}Loop(cond {cond:?}, test_first {test_first})");
                    block(cond_code, depth + 1);
                    println!("{pad}Body");
                    block(body, depth + 1);
                    println!("{pad}Step");
                    block(step, depth + 1);
                }
                Inst::Call(body) => {
                    println!("{pad}Call");
                    block(body, depth + 1);
                }
                other => println!("{pad}{other:?}"),
            }
        }
    }
    match tiler_glsl::compile::compile(stage, source) {
        Ok(code) => {
            println!("{stage}: {} work registers, bank {:?} (registers from {:#x})", code.work_regs, code.bank, BANK);
            println!(" bank program:");
            block(&code.bank_program, 0);
            println!(" code:");
            block(&code.code, 0);
        }
        Err(e) => println!("{stage}: {e}"),
    }
}

fn main() -> ExitCode {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let ir = args.first().is_some_and(|a| a == "--ir");
    if ir {
        args.remove(0);
    }
    if args.is_empty() || !args.len().is_multiple_of(2) {
        eprintln!("usage: glslc [--ir] VERTEX FRAGMENT [VERTEX FRAGMENT …]");
        return ExitCode::FAILURE;
    }
    let mut failed = 0;
    for pair in args.chunks(2) {
        let read = |path: &str| std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"));
        let result = read(&pair[0]).and_then(|vs| {
            let fs = read(&pair[1])?;
            if ir {
                print_ir(Stage::Vertex, &vs);
                print_ir(Stage::Fragment, &fs);
            }
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
                match smoke_render(p) {
                    Ok(written) => println!("     rendered: {written} of 4096 pixels written"),
                    Err(e) => {
                        failed += 1;
                        println!("FAIL render: {e}");
                    }
                }
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
