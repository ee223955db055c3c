//! The built-in scene at 1280×720 on each backend: the baseline every later change is measured
//! against (`cargo bench -p tiler-scene`).

use criterion::{Criterion, criterion_group, criterion_main};
use tiler::{Backend, Device, DeviceConfig};

fn builtin_scene(c: &mut Criterion) {
    let mut group = c.benchmark_group("builtin_scene_1280x720");
    group.sample_size(20);
    for backend in Backend::ALL {
        let mut device = Device::new(DeviceConfig { backend, ..DeviceConfig::default() }).unwrap();
        let scene = tiler_scene::builtin::build(&mut device, 1280, 720, 1).unwrap();
        group.bench_function(backend.name(), |b| b.iter(|| scene.render(&mut device, backend).unwrap()));
    }
    group.finish();
}

criterion_group!(benches, builtin_scene);
criterion_main!(benches);
