//! Wall time of the clocked chip on a synthetic pass the size of a Fig. 6(b) sample
//! plane: a 720 × 480 full-screen plane (345 600 fragments), three textures — a 1D
//! F table (256 texels, 2 texels per lookup) and two 2D textures (256 × 256 and
//! 720 × 480 → 512 × 512 screen-mapped, 4 texels per bilinear lookup) — with depth
//! read and colour read-modify-write, on the GeForce2 GTS preset (two hardware
//! passes). Reports ns per fragment of `clock_pass` and of `clock_pass_sampled`
//! (one 32 × 32 tile in 8). `cargo bench --bench chip_clock`.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glare_pipeline::chip::clock::{clock_pass, clock_pass_sampled};
use glare_pipeline::chip::config::ChipConfig;
use glare_pipeline::chip::work::{PassWork, RopWork, TextureWork};
use std::hint::black_box;
use std::time::Duration;

fn fig6b_plane() -> PassWork {
    let (w, h) = (720u32, 480u32);
    let textures = vec![
        TextureWork {
            name: "F".into(),
            size: [256, 1, 1],
            texel_bytes: 1,
            texels_per_lookup: 2,
        },
        TextureWork {
            name: "h".into(),
            size: [256, 256, 1],
            texel_bytes: 1,
            texels_per_lookup: 4,
        },
        TextureWork {
            name: "J".into(),
            size: [512, 512, 1],
            texel_bytes: 1,
            texels_per_lookup: 4,
        },
    ];
    let mut frag_xy = Vec::with_capacity((w * h) as usize);
    let mut texels = Vec::with_capacity((w * h * 10) as usize);
    for y in 0..h {
        for x in 0..w {
            frag_xy.push([x as u16, y as u16]);
            // F: a slowly varying 1D index (the angle along the plane).
            let a = ((x + y) * 255 / (w + h)).min(254);
            texels.extend([a, a + 1]);
            // h: the plane's 2D texture at about 0.36 texels per pixel.
            let (s, t) = ((x * 256 / w).min(254), (y * 256 / h).min(254));
            texels.extend([
                s + 256 * t,
                s + 1 + 256 * t,
                s + 256 * (t + 1),
                s + 1 + 256 * (t + 1),
            ]);
            // J: screen-mapped, about one texel per pixel.
            let (s, t) = ((x * 512 / w).min(510), (y * 512 / h).min(510));
            texels.extend([
                s + 512 * t,
                s + 1 + 512 * t,
                s + 512 * (t + 1),
                s + 1 + 512 * (t + 1),
            ]);
        }
    }
    PassWork {
        stats: None,
        width: w,
        height: h,
        textures,
        prim_first_fragment: vec![0, (w * h / 2)],
        prim_walked: vec![w * h / 2 + w, w * h / 2 + w],
        prim_depth_killed: Vec::new(),
        frag_xy,
        texels,
        rop: RopWork {
            depth_read_bytes: 4,
            depth_write_bytes: 0,
            colour_read_bytes: 4,
            colour_write_bytes: 4,
        },
        copy_read_bytes: 0,
        copy_write_bytes: 0,
        sample: None,
        unrecorded: false,
    }
}

fn chip_clock(c: &mut Criterion) {
    let chip = ChipConfig::geforce2_gts();
    let work = fig6b_plane();
    let t = clock_pass(&chip, &work, None).expect("clocked");
    let (s, rse) = clock_pass_sampled(&chip, &work, 8).expect("sampled");
    eprintln!(
        "fig6b plane: clocked {} cycles ({}; texture cache hit {:.3}), sampled {} cycles (rse {:.4})",
        t.cycles,
        t.bottleneck,
        t.cache_hit_rate().unwrap_or(f64::NAN),
        s.cycles,
        rse
    );
    let mut g = c.benchmark_group("chip_clock_fig6b_plane");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(10));
    g.throughput(Throughput::Elements(work.fragments() as u64));
    g.bench_function("clock_pass", |b| {
        b.iter(|| black_box(clock_pass(&chip, black_box(&work), None).expect("clocked")))
    });
    g.bench_function("clock_pass_sampled_8", |b| {
        b.iter(|| black_box(clock_pass_sampled(&chip, black_box(&work), 8).expect("sampled")))
    });
    g.finish();
}

criterion_group!(benches, chip_clock);
criterion_main!(benches);
