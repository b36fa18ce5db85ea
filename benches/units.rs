//! Simulated pixels (kernel calls) per second of each unit through the span driver and
//! the tick driver (criterion reports elements/s), and the whole test-scene frame.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glare_pipeline::pipeline::test_scene;
use glare_pipeline::registry;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::driver::{run_span, run_tick};
use rtl_model::units::blend::{Blend, BlendIn};
use rtl_model::units::chaos_map::ChaosMap;
use rtl_model::units::cube_map_address::{CubeMapAddress, CubeMapAddressIn};
use rtl_model::units::gaussian_noise::{GaussState, GaussianNoise};
use rtl_model::units::glare_combiner::{CombineIn, GlareCombiner};
use rtl_model::units::glare_condition::{ConditionIn, GlareCondition, Material};
use rtl_model::units::luminance_ram::LumIn;
use rtl_model::units::modulate::{Modulate, ModulateIn};
use rtl_model::units::polygon_interpolator::PolygonInterpolator;
use rtl_model::units::polygon_variable_generator::{PolygonVariableGenerator, PrimKind, PvgIn};
use rtl_model::units::projective_texcoord::{ProjectiveIn, ProjectiveTexcoord};
use rtl_model::units::reflection_vector::{ReflectionVector, ReflectionVectorIn};
use rtl_model::units::shadow_compare::{ShadowCompare, ShadowIn};
use rtl_model::units::texture_sampler::{TextureSampler, TextureSamplerConfig, TextureSamplerIn};
use rtl_model::{Counters, Unit};
use std::hint::black_box;

const N: usize = 4096;

fn bench_unit<U: Unit>(c: &mut Criterion, u: &U, state: U::State, inputs: &[U::In]) {
    let mut g = c.benchmark_group(u.name());
    g.throughput(Throughput::Elements(inputs.len() as u64));
    g.bench_function("span", |b| {
        b.iter(|| {
            let mut s = state.clone();
            let mut ctr = Counters::default();
            black_box(run_span(u, &mut s, black_box(inputs), &mut ctr))
        })
    });
    g.bench_function("tick", |b| {
        b.iter(|| {
            let mut s = state.clone();
            let mut ctr = Counters::default();
            black_box(run_tick::<_, Vec<u8>>(u, &mut s, black_box(inputs), &mut ctr, None).unwrap())
        })
    });
    g.finish();
}

fn units(c: &mut Criterion) {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let mut byte = || rng.random_range(0..=255u32);

    let m = Modulate::geforce();
    let inputs: Vec<ModulateIn> = (0..N)
        .map(|_| ModulateIn {
            a: byte(),
            b: byte(),
        })
        .collect();
    bench_unit(c, &m, (), &inputs);

    // The additive datapath the shafts and object passes use (GL_ONE, GL_ONE).
    let blend = Blend::additive(8, 8, false, 8).expect("8-bit additive blend");
    let inputs: Vec<BlendIn> = (0..N)
        .map(|_| BlendIn {
            src: [byte(), byte(), byte(), byte()],
            dst: [byte(), byte(), byte(), byte()],
        })
        .collect();
    bench_unit(c, &blend, (), &inputs);

    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let texels: Vec<u32> = (0..256 * 256).map(|_| rng.random_range(0..=255)).collect();
    let sampler = TextureSampler::new(TextureSamplerConfig::geforce(), &texels).unwrap();
    let inputs: Vec<TextureSamplerIn> = (0..N)
        .map(|_| TextureSamplerIn {
            coord: [
                rng.random_range(0..256 << 8),
                rng.random_range(0..256 << 8),
                0,
            ],
        })
        .collect();
    bench_unit(c, &sampler, (), &inputs);

    let interp = PolygonInterpolator::geforce();
    let mut ctr = Counters::default();
    let v = [(0.5, 0.5), (90.5, 3.0), (7.0, 88.5)]
        .iter()
        .enumerate()
        .map(|(i, &(x, y))| {
            interp
                .vertex_from_f64(i, x, y, &[0.1, 2.0, -3.0, 7.5], &mut ctr)
                .unwrap()
        })
        .collect::<Vec<_>>();
    let setup = interp.setup_triangle(&[v[0], v[1], v[2]], &mut ctr);
    bench_unit(c, &interp, setup.state.clone(), &setup.moves());

    let shadow = ShadowCompare::geforce();
    let inputs: Vec<ShadowIn> = (0..N)
        .map(|k| {
            let (x, y) = (rng.random_range(0..512), rng.random_range(0..512));
            if k % 4 == 0 {
                ShadowIn::Write {
                    x,
                    y,
                    depth: rng.random_range(0..1 << 24),
                }
            } else {
                ShadowIn::Test {
                    x,
                    y,
                    depth: rng.random_range(0..1 << 24),
                }
            }
        })
        .collect();
    bench_unit(c, &shadow, shadow.fresh_state(), &inputs);

    let proj = ProjectiveTexcoord::geforce();
    let inputs: Vec<ProjectiveIn> = (0..N)
        .map(|_| ProjectiveIn {
            s: rng.random_range(0..1 << 18),
            t: rng.random_range(0..1 << 18),
            q: rng.random_range(1 << 16..1 << 19),
        })
        .collect();
    bench_unit(c, &proj, (), &inputs);

    // The envmap's per-pixel reflection: n, e over ±4 units (s16.16), λ over [0, 1].
    let refl = ReflectionVector::geforce3();
    let lim = 4i64 << 16;
    let inputs: Vec<ReflectionVectorIn> = (0..N)
        .map(|_| ReflectionVectorIn {
            n: [(); 3].map(|_| rng.random_range(-lim..=lim)),
            e: [(); 3].map(|_| rng.random_range(-lim..=lim)),
            lambda: rng.random_range(0..=1u32 << 12),
        })
        .collect();
    bench_unit(c, &refl, (), &inputs);

    // The 2D path's cube-map address: the reflection unit's s16.8 words in [0, 128]³.
    let cube = CubeMapAddress::geforce3();
    let inputs: Vec<CubeMapAddressIn> = (0..N)
        .map(|_| CubeMapAddressIn {
            coord: [(); 3].map(|_| rng.random_range(0..=128 << 8)),
        })
        .collect();
    bench_unit(c, &cube, (), &inputs);
}

/// The glare units. Elements are kernel calls: pixels for the modulators, combiner and
/// condition, primitives for the generator, draw requests (two normals each) for the
/// noise generator, map steps (all four patches) for the chaos map.
fn glare_units(c: &mut Criterion) {
    let mut rng = ChaCha8Rng::seed_from_u64(3);

    let pvg = PolygonVariableGenerator::geforce();
    let inputs: Vec<PvgIn> = (0..N)
        .map(|k| PvgIn {
            kind: if k % 2 == 0 {
                PrimKind::Area
            } else {
                PrimKind::Line
            },
            cx: rng.random_range(-4000 << 4..4000 << 4),
            cy: rng.random_range(-4000 << 4..4000 << 4),
            extent: rng.random_range(0..400 << 4),
            half_width: rng.random_range(0..8 << 4),
            angle: rng.random_range(0..1 << 12),
        })
        .collect();
    bench_unit(c, &pvg, (), &inputs);

    // Modulator pixels: (u, v) over ±1.25 in s2.10, gains up to 255 codes (u12.4).
    let lum: Vec<LumIn> = (0..N)
        .map(|_| LumIn {
            u: rng.random_range(-1280..=1280),
            v: rng.random_range(-1280..=1280),
            gain: [0; 3].map(|_| rng.random_range(0..=255 << 4)),
        })
        .collect();
    bench_unit(c, &registry::default_bloom_flare(), (), &lum);
    bench_unit(c, &registry::default_halo(), (), &lum);

    let comb = GlareCombiner::geforce();
    let inputs: Vec<CombineIn> = (0..N)
        .map(|_| CombineIn {
            fb: [0; 3].map(|_| rng.random_range(0..=255)),
            lum: [0; 3].map(|_| rng.random_range(0..=255)),
        })
        .collect();
    bench_unit(c, &comb, (), &inputs);

    let noise = GaussianNoise::geforce();
    bench_unit(c, &noise, GaussState::from_seed(1), &[(); N]);

    let chaos = ChaosMap::geforce();
    bench_unit(c, &chaos, chaos.seeded_state(1), &[(); N]);

    let cond = GlareCondition::geforce();
    let inputs: Vec<ConditionIn> = (0..N)
        .map(|k| {
            let intensity = rng.random_range(0..1 << 16);
            ConditionIn {
                material: if k % 2 == 0 {
                    Material::Metallic
                } else {
                    Material::Water
                },
                intensity,
                specular: rng.random_range(0..=255),
                cos_alpha: rng.random_range(-4096..1 << 14),
                cos_theta: rng.random_range(-(1 << 14)..1 << 14),
                ambient: rng.random_range(0..=intensity / 20),
            }
        })
        .collect();
    bench_unit(c, &cond, (), &inputs);
}

fn frame(c: &mut Criterion) {
    let mut g = c.benchmark_group("test_scene");
    g.sample_size(20);
    g.bench_function("render_320x240", |b| {
        b.iter(|| black_box(test_scene::render().unwrap()))
    });
    g.finish();
}

criterion_group!(benches, units, glare_units, frame);
criterion_main!(benches);
