//! The environment-map prefilter's set-up: the geodesic dome of the thesis's finest
//! frequency (n = 72, 51 842 vertices), which a test once bounded by wall time.

use criterion::{criterion_group, criterion_main, Criterion};
use glare_pipeline::reference::envmap_prefilter::Dome;
use std::hint::black_box;

fn dome(c: &mut Criterion) {
    c.bench_function("dome n=72", |b| {
        b.iter(|| Dome::new(black_box(72)).unwrap())
    });
}

criterion_group!(benches, dome);
criterion_main!(benches);
