//! Shaders, buffers and scenes shared by the integration tests.

use tiler::*;

/// Vertex layout of the test scenes: clip position (4 floats) and colour (4 floats).
pub type Vertex = [f32; 8];

/// Position from attribute 0, colour (attribute 1) to varyings 0..4.
pub struct PassThrough;

impl VertexShader for PassThrough {
    fn shade(&self, input: &VertexInput, out: &mut VertexOutput) {
        out.position = input.attributes[0];
        out.varyings[..4].copy_from_slice(&input.attributes[1].to_array());
    }
}

/// The interpolated colour of varyings 0..4.
pub struct Smooth;

impl FragmentShader for Smooth {
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        frag.set_color(0, frag.smooth_n::<4>(0));
    }
}

/// The provoking vertex's colour.
pub struct FlatColor;

impl FragmentShader for FlatColor {
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        let c = [0, 1, 2, 3].map(|i| F32x8::splat(frag.flat(i)));
        frag.set_color(0, c);
    }
}

/// A constant colour.
pub struct Solid(pub [f32; 4]);

impl FragmentShader for Solid {
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        frag.set_color(0, self.0.map(F32x8::splat));
    }
}

/// Discards fragments whose interpolated alpha is below one half.
pub struct AlphaTest;

impl FragmentShader for AlphaTest {
    fn properties(&self) -> ShaderProperties {
        ShaderProperties { discards: true, ..ShaderProperties::default() }
    }
    #[inline(always)]
    fn shade(&self, frag: &mut Fragments<'_>) {
        let c = frag.smooth_n::<4>(0);
        frag.discard(c[3].lt(F32x8::splat(0.5)));
        frag.set_color(0, c);
    }
}

/// The pipeline description for [`Vertex`] data.
pub fn desc(label: &str) -> PipelineDesc {
    let mut d =
        PipelineDesc::new(label, VertexInputState::interleaved(&[VertexFormat::Float32x4, VertexFormat::Float32x4]));
    d.varyings = vec![Interpolation::Perspective; 4];
    d
}

pub fn pipeline<F: FragmentShader>(fragment: F, desc: PipelineDesc) -> Pipeline {
    Pipeline::new(PassThrough, fragment, desc).expect("valid pipeline")
}

pub fn device(backend: Backend, tile: u32, threads: usize) -> Device {
    Device::new(DeviceConfig { backend, threads, ..DeviceConfig::default() }.with_tile_size(tile)).unwrap()
}

/// A vertex at NDC `(x, y)`, depth `z`, `w = 1`, with a colour.
pub fn v(x: f32, y: f32, z: f32, color: [f32; 4]) -> Vertex {
    [x, y, z, 1.0, color[0], color[1], color[2], color[3]]
}

/// A counter-based generator (PCG hash), deterministic across platforms.
pub struct Rng(pub u32);

impl Rng {
    pub fn next_u32(&mut self) -> u32 {
        self.0 = self.0.wrapping_add(1);
        let state = self.0.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
        let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
        (word >> 22) ^ word
    }

    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * ((self.next_u32() >> 8) as f32 / (1 << 24) as f32)
    }

    pub fn color(&mut self, alpha: f32) -> [f32; 4] {
        [self.range(0.0, 1.0), self.range(0.0, 1.0), self.range(0.0, 1.0), alpha]
    }

    /// A random colour with alpha uniform in `[lo, hi)`.
    pub fn color_alpha(&mut self, lo: f32, hi: f32) -> [f32; 4] {
        let alpha = self.range(lo, hi);
        self.color(alpha)
    }
}

/// A render pass and the images to compare after it.
pub struct TestScene {
    pub passes: Vec<RenderPass>,
    pub images: Vec<ImageId>,
}

/// Renders a scene built on a fresh device and returns the bytes of the images it names,
/// with the last pass's report.
pub fn render_scene(
    build: fn(&mut Device) -> TestScene,
    backend: Backend,
    tile: (u32, u32),
    threads: usize,
    budget: u64,
) -> (Vec<Vec<u8>>, PassReport) {
    render_scene_at(build, backend, tile, threads, budget, None)
}

/// [`render_scene`] with the pixel pipeline compiled for `simd` (`None`: the best level).
pub fn render_scene_at(
    build: fn(&mut Device) -> TestScene,
    backend: Backend,
    tile: (u32, u32),
    threads: usize,
    budget: u64,
    simd: Option<SimdLevel>,
) -> (Vec<Vec<u8>>, PassReport) {
    let config = DeviceConfig {
        backend,
        threads,
        tile_width: tile.0,
        tile_height: tile.1,
        frame_data_budget: budget,
        simd,
        ..DeviceConfig::default()
    };
    let mut device = Device::new(config).unwrap();
    let scene = build(&mut device);
    let mut report = None;
    for pass in &scene.passes {
        report = Some(device.submit(pass).unwrap());
    }
    let images = scene.images.iter().map(|id| device.image_data(*id).unwrap().to_vec()).collect();
    (images, report.unwrap())
}

/// The colour attachment of a single-pass scene: cleared, stored.
pub fn color_pass(color: ImageId, depth: Option<DepthStencilAttachment>) -> RenderPass {
    RenderPass::new(RenderPassDesc {
        color: vec![ColorAttachment::clear_store(color, [0.1, 0.2, 0.3, 1.0])],
        depth_stencil: depth,
        render_area: None,
    })
}
