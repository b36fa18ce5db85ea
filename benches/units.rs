//! Simulated pixels per second of each unit through the span driver (and the tick
//! driver for comparison). Throughput is reported by criterion as elements/s.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::driver::{run_span, run_tick};
use rtl_model::units::modulate::{Modulate, ModulateIn};
use rtl_model::Counters;
use std::hint::black_box;

const N: usize = 4096;

fn modulate(c: &mut Criterion) {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let u = Modulate::geforce();
    let inputs: Vec<ModulateIn> = (0..N)
        .map(|_| ModulateIn {
            a: rng.random_range(0..=255),
            b: rng.random_range(0..=255),
        })
        .collect();
    let mut g = c.benchmark_group("modulate");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("span", |b| {
        b.iter(|| {
            let mut ctr = Counters::default();
            black_box(run_span(&u, &mut (), black_box(&inputs), &mut ctr))
        })
    });
    g.bench_function("tick", |b| {
        b.iter(|| {
            let mut ctr = Counters::default();
            black_box(
                run_tick::<_, Vec<u8>>(&u, &mut (), black_box(&inputs), &mut ctr, None).unwrap(),
            )
        })
    });
    g.finish();
}

criterion_group!(benches, modulate);
criterion_main!(benches);
