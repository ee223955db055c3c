//! The shader executor against native Rust: `cargo bench -p tiler-glsl --bench executor`.
//!
//! A Blinn-Phong fragment shader (three normalisations, two dots, a `pow`) over a 256×256
//! full-screen triangle rendered through `Device` (TBR, one thread), as GLSL run by the
//! executor and as a native `FragmentShader` doing the same arithmetic (the two images are
//! checked equal before timing). `flat` writes a constant colour: the pipeline's own cost,
//! to subtract from both. Throughput in fragments.

use std::hint::black_box;
use std::sync::Arc;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec4;
use tiler::{
    ColorAttachment, Device, DeviceConfig, Draw, F32x8, Format, FragmentShader, Fragments, ImageDesc, ImageId,
    Interpolation, Pipeline, PipelineDesc, RenderPass, RenderPassDesc, VertexFormat, VertexInput, VertexInputState,
    VertexOutput, VertexShader,
};
use tiler_glsl::CompiledProgram;

const SIZE: u32 = 256;

const VS: &str = "
attribute vec4 position;
varying vec3 normal;
varying vec3 view;
void main() {
    gl_Position = position;
    normal = vec3(position.xy, 1.0);
    view = vec3(-position.yx, 2.0);
}";

// In highp: the native shader below computes what it does, operation for operation (mediump
// rounds every operation to binary16, as llvmpipe does).
const FS: &str = "
precision highp float;
uniform vec3 light_dir;
uniform vec3 light_color;
uniform vec3 base;
varying vec3 normal;
varying vec3 view;
void main() {
    vec3 n = normalize(normal);
    vec3 l = normalize(light_dir);
    vec3 v = normalize(view);
    vec3 h = normalize(l + v);
    float diffuse = max(dot(n, l), 0.0);
    float specular = pow(max(dot(n, h), 0.0), 32.0);
    gl_FragColor = vec4(base * diffuse * light_color + light_color * specular, 1.0);
}";

const LIGHT_DIR: [f32; 3] = [0.3, 0.5, 0.8];
const LIGHT_COLOR: [f32; 3] = [1.0, 0.9, 0.8];
const BASE: [f32; 3] = [0.6, 0.3, 0.2];

struct NativeVs;
impl VertexShader for NativeVs {
    fn shade(&self, input: &VertexInput, out: &mut VertexOutput) {
        let p = input.attributes[0];
        out.position = Vec4::new(p.x, -p.y, (p.z + p.w) * 0.5, p.w);
        out.varyings[..6].copy_from_slice(&[p.x, p.y, 1.0, -p.y, -p.x, 2.0]);
    }
}

type V3 = [F32x8; 3];

/// GLSL's highp `dot` as tiler computes it (llvmpipe's order): summed from the last component.
#[inline(always)]
fn dot(a: V3, b: V3) -> F32x8 {
    a[2] * b[2] + a[1] * b[1] + a[0] * b[0]
}

/// GLSL's highp `normalize` as tiler computes it (llvmpipe's form): `v · (1 / √(v · v))`.
#[inline(always)]
fn normalize(a: V3) -> V3 {
    let inverse = F32x8::ONE / dot(a, a).sqrt();
    a.map(|c| c * inverse)
}

#[inline(always)]
fn max0(x: F32x8) -> F32x8 {
    F32x8::from_array(x.to_array().map(|x| if x < 0.0 { 0.0 } else { x }))
}

struct NativeBlinnPhong;
impl FragmentShader for NativeBlinnPhong {
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        let n = normalize(frag.smooth_n::<3>(0));
        let l = normalize(LIGHT_DIR.map(F32x8::splat));
        let v = normalize(frag.smooth_n::<3>(3));
        let h = normalize([l[0] + v[0], l[1] + v[1], l[2] + v[2]]);
        let diffuse = max0(dot(n, l));
        let specular = F32x8::from_array(max0(dot(n, h)).to_array().map(|x| x.powf(32.0)));
        let color: V3 = std::array::from_fn(|c| {
            F32x8::splat(BASE[c]) * diffuse * F32x8::splat(LIGHT_COLOR[c]) + F32x8::splat(LIGHT_COLOR[c]) * specular
        });
        frag.set_color(0, [color[0], color[1], color[2], F32x8::ONE]);
    }
}

struct Flat;
impl FragmentShader for Flat {
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        frag.set_color(0, [F32x8::splat(0.5), F32x8::ZERO, F32x8::ONE, F32x8::ONE]);
    }
}

fn desc(varyings: usize) -> PipelineDesc {
    PipelineDesc {
        varyings: vec![Interpolation::Perspective; varyings],
        ..PipelineDesc::new("bench", VertexInputState::interleaved(&[VertexFormat::Float32x4]))
    }
}

struct Scene {
    device: Device,
    color: ImageId,
    pass: RenderPass,
}

fn scene(pipeline: &Pipeline) -> Scene {
    let config = DeviceConfig { threads: 1, ..DeviceConfig::default() };
    let mut device = Device::new(config).unwrap();
    let color = device.create_image(ImageDesc::new(SIZE, SIZE, Format::Rgba8Unorm)).unwrap();
    let vertices: [[f32; 4]; 3] = [[-1.0, -1.0, 0.0, 1.0], [3.0, -1.0, 0.0, 1.0], [-1.0, 3.0, 0.0, 1.0]];
    let buffer = device.create_buffer_from(&vertices).unwrap();
    let mut pass = RenderPass::new(RenderPassDesc {
        color: vec![ColorAttachment::clear_store(color, [0.0, 0.0, 0.0, 1.0])],
        depth_stencil: None,
        render_area: None,
    });
    pass.draw(Draw::new(pipeline, buffer, 0, 3));
    Scene { device, color, pass }
}

fn bench(c: &mut Criterion) {
    let program = Arc::new(CompiledProgram::new(VS, FS, &[]).unwrap());
    let mut uniforms = program.new_uniform_values();
    for (name, value) in [("light_dir", LIGHT_DIR), ("light_color", LIGHT_COLOR), ("base", BASE)] {
        program.set_uniform(&mut uniforms, program.uniform_location(name).unwrap(), &value).unwrap();
    }
    let glsl = tiler_glsl::pipeline(&program, &uniforms, &[], SIZE, desc(0)).unwrap();
    let native = Pipeline::new(NativeVs, NativeBlinnPhong, desc(6)).unwrap();
    let flat = Pipeline::new(NativeVs, Flat, desc(6)).unwrap();

    let mut scenes = [("flat", scene(&flat)), ("native", scene(&native)), ("glsl", scene(&glsl))];
    let mut images = Vec::new();
    for (_, s) in &mut scenes {
        s.device.submit(&s.pass).unwrap();
        images.push(s.device.read_rgba8(s.color).unwrap());
    }
    assert_eq!(images[1], images[2], "the GLSL and native shaders must render the same image");

    let mut group = c.benchmark_group("blinn_phong_256x256");
    group.warm_up_time(Duration::from_millis(500));
    group.measurement_time(Duration::from_secs(3));
    group.sample_size(20);
    group.throughput(Throughput::Elements(u64::from(SIZE * SIZE)));
    for (name, s) in &mut scenes {
        group.bench_function(*name, |b| b.iter(|| black_box(s.device.submit(&s.pass).unwrap())));
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
