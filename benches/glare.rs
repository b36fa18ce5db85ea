//! Wall time of the glare renderer: the bit-accurate frame of the `glare-flare` and
//! `leaves` built-ins through the units (`render_glare`), and the f64 reference image
//! of `glare-flare` (`reference_levels`: the analytic formulas per pixel, from the
//! frame's own sources and line draws), so model and reference can be compared.
//! Slow by nature: 10 samples each.

use criterion::{criterion_group, criterion_main, Criterion};
use glare_pipeline::pipeline::glare::cli::reference_levels;
use glare_pipeline::pipeline::glare::frame::render_glare;
use glare_pipeline::scene::builtin::builtin;
use std::hint::black_box;
use std::time::Duration;

fn glare(c: &mut Criterion) {
    for name in ["glare-flare", "leaves"] {
        let scene = builtin(name).expect("built-in scene");
        let frame = render_glare(&scene).expect("frame");
        let mut g = c.benchmark_group(format!(
            "{name}_{}x{}",
            scene.image.width, scene.image.height
        ));
        g.sample_size(10);
        g.measurement_time(Duration::from_secs(10));
        g.bench_function("bit_accurate_frame", |b| {
            b.iter(|| black_box(render_glare(black_box(&scene)).expect("frame")))
        });
        if name == "glare-flare" {
            g.bench_function("f64_reference", |b| {
                b.iter(|| {
                    black_box(reference_levels(black_box(&scene), &frame).expect("reference"))
                })
            });
        }
        g.finish();
    }
}

criterion_group!(benches, glare);
criterion_main!(benches);
