//! Wall time to simulate the Fig. 6(b) frame bit-accurately (720 × 480, n = 30, m = 6)
//! and to ray-march its 180-sample reference. Slow by nature: 10 samples each.

use criterion::{criterion_group, criterion_main, Criterion};
use glare_pipeline::pipeline::shafts::frame::render_frame;
use glare_pipeline::pipeline::shafts::host::prepare_scene;
use glare_pipeline::pipeline::shafts::prepare::DEFAULT_EXPOSURE;
use glare_pipeline::reference::raymarch::raymarch_image;
use glare_pipeline::scene::builtin::builtin;
use std::hint::black_box;
use std::time::Duration;

fn fig6b(c: &mut Criterion) {
    let scene = builtin("fig6").expect("built-in scene");
    let (p, geom) = prepare_scene(&scene, DEFAULT_EXPOSURE).expect("valid scene");
    let mut g = c.benchmark_group("fig6b_720x480_n30_m6");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(10));
    g.bench_function("bit_accurate_frame", |b| {
        b.iter(|| black_box(render_frame(&p).expect("frame")))
    });
    g.bench_function("raymarch_180_samples", |b| {
        b.iter(|| black_box(raymarch_image(&scene, &geom, 180)))
    });
    g.finish();
}

criterion_group!(benches, fig6b);
criterion_main!(benches);
