//! Texture sampling of one 4×2 group (`Texture::sample`), bilinear and trilinear, at every SIMD
//! level this processor runs, through the texture cache model: the kernel that dominates textured scenes (SCENES.md §4.2 samples every
//! texture trilinear). `cargo bench -p tiler --bench texture`.
//!
//! Each iteration samples a row of 64 groups marching across a 512×512 RGBA8 texture, one
//! group (8 pixels) per 4 pixels of screen, so that the cache model sees the reuse between
//! neighbouring groups that a rasterizer gives it.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use tiler::__bench::TextureCache;
use tiler::simd::{LANE_DX, LANE_DY, SimdLevel, SimdSupport};
use tiler::{ColorSpace, F32x8, LaneMask, MipChain, Sampler, Texture};

const SIZE: u32 = 512;
const GROUPS: usize = 64;

/// A texture of pseudo-random texels (an LCG; the values do not matter, only that they vary).
fn texture(color_space: ColorSpace) -> Texture {
    let mut state = 1u32;
    let rgba: Vec<u8> = (0..SIZE * SIZE * 4)
        .map(|_| {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 24) as u8
        })
        .collect();
    Texture::from_rgba8(SIZE, SIZE, &rgba, color_space, MipChain::Box).unwrap()
}

/// The coordinates of a row of groups whose pixels step `texels_per_pixel` texels of level 0
/// in u (and a little in v, as a slanted surface would).
fn groups(texels_per_pixel: f32) -> Vec<(F32x8, F32x8)> {
    let step = texels_per_pixel / SIZE as f32;
    (0..GROUPS)
        .map(|g| {
            let x = |i: usize| (g * 4) as f32 + LANE_DX[i] as f32;
            let y = |i: usize| 37.0 + LANE_DY[i] as f32;
            let u = F32x8::from_fn(|i| 0.1 + x(i) * step + y(i) * step * 0.25);
            let v = F32x8::from_fn(|i| 0.2 + y(i) * step + x(i) * step * 0.125);
            (u, v)
        })
        .collect()
}

fn sample(c: &mut Criterion) {
    let mut group = c.benchmark_group("texture_sample_4x2");
    group.throughput(Throughput::Elements(GROUPS as u64));
    let cases = [
        // Level 0 alone, magnified a little: one bilinear footprint per pixel.
        ("bilinear", Sampler::BILINEAR_CLAMP, 0.75, ColorSpace::Linear),
        // λ ≈ 0.9: two levels blended, the helmet scene's common case.
        ("trilinear", Sampler::TRILINEAR_REPEAT, 1.8, ColorSpace::Linear),
        ("trilinear_srgb", Sampler::TRILINEAR_REPEAT, 1.8, ColorSpace::Srgb),
    ];
    let levels = [SimdLevel::Baseline, SimdLevel::Avx2].into_iter().filter_map(SimdSupport::detect);
    for simd in levels {
        for (name, sampler, texels_per_pixel, color_space) in cases {
            let texture = texture(color_space);
            let groups = groups(texels_per_pixel);
            let mut cache = TextureCache::default();
            group.bench_function(format!("{name}/{}", simd.level()), |b| {
                b.iter(|| {
                    let mut sum = F32x8::ZERO;
                    for &(u, v) in &groups {
                        let rgba = texture.sample(simd, &sampler, u, v, LaneMask::ALL, &mut cache);
                        sum += rgba[0] + rgba[3];
                    }
                    sum
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, sample);
criterion_main!(benches);
