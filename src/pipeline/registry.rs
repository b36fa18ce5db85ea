//! Every hardware unit by name, in its GeForce-era default configuration: its
//! summary (widths, latency, II, gates, RAM bits), the tables it holds, and a VCD
//! trace of a few random pixels through the tick driver.

use crate::pipeline::test_scene;
use crate::tables::Table;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::driver::run_tick;
use rtl_model::trace::VcdTrace;
use rtl_model::units::additive_blend::{AdditiveBlend, AdditiveBlendIn};
use rtl_model::units::modulate::{Modulate, ModulateIn};
use rtl_model::units::polygon_interpolator::PolygonInterpolator;
use rtl_model::units::projective_texcoord::{ProjectiveIn, ProjectiveTexcoord};
use rtl_model::units::shadow_compare::{ShadowCompare, ShadowIn};
use rtl_model::units::texture_sampler::{TextureSampler, TextureSamplerConfig, TextureSamplerIn};
use rtl_model::{Counters, Unit, UnitSummary};
use std::collections::BTreeMap;
use std::io::Write;

/// Names of all units, in datasheet order.
pub const UNIT_NAMES: &[&str] = &[
    "modulate",
    "additive_blend",
    "texture_sampler",
    "polygon_interpolator",
    "shadow_compare",
    "projective_texcoord",
];

/// The default texture sampler (2D 256 × 256 luminance), holding a zero texture.
fn default_sampler() -> TextureSampler {
    let cfg = TextureSamplerConfig::geforce();
    let texels = vec![0u32; cfg.texel_count() as usize];
    TextureSampler::new(cfg, &texels).expect("the GeForce default sampler config is valid")
}

/// Summaries of every unit at its defaults.
pub fn summaries() -> Vec<UnitSummary> {
    vec![
        UnitSummary::of(&Modulate::geforce()),
        UnitSummary::of(&AdditiveBlend::geforce()),
        UnitSummary::of(&default_sampler()),
        UnitSummary::of(&PolygonInterpolator::geforce()),
        UnitSummary::of(&ShadowCompare::geforce()),
        UnitSummary::of(&ProjectiveTexcoord::geforce()),
    ]
}

/// Every RAM/ROM image the default units hold, and the textures of the built-in scene.
pub fn tables() -> Vec<Table> {
    let mut out = Vec::new();
    let proj = ProjectiveTexcoord::geforce();
    let p = proj.rom_params();
    let mut params: BTreeMap<String, String> = p
        .params
        .iter()
        .map(|(k, v)| (k.clone(), v.to_string()))
        .collect();
    params.insert("generator".into(), p.generator.clone());
    out.push(Table {
        name: p.name.clone(),
        width: p.width,
        words: proj.rom_words(),
        unit: "projective_texcoord".into(),
        params,
    });
    let scene_param = |what: &str| {
        BTreeMap::from([
            (
                "scene".to_string(),
                "built-in test scene (render)".to_string(),
            ),
            ("generator".to_string(), what.to_string()),
        ])
    };
    out.push(Table {
        name: "test_scene_checker_rgba8_64x64".into(),
        width: 8,
        words: test_scene::checker_texels()
            .into_iter()
            .map(u64::from)
            .collect(),
        unit: "texture_sampler".into(),
        params: scene_param(
            "8x8-texel squares (235,228,210) / (70,96,140), alpha 255; texel (x,y) channel c at ((y*64+x)*4+c)",
        ),
    });
    out.push(Table {
        name: "test_scene_lightmap_l8_64x64".into(),
        width: 8,
        words: test_scene::lightmap_texels()
            .into_iter()
            .map(u64::from)
            .collect(),
        unit: "texture_sampler".into(),
        params: scene_param(
            "spot disc: 255 inside r=0.3, linear in r^2 to 0 at r=0.45 (map units)",
        ),
    });
    out
}

/// Trace `pixels` random inputs (seeded) through the named unit's tick driver as VCD.
pub fn trace(name: &str, pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    match name {
        "modulate" => {
            let u = Modulate::geforce();
            let inputs: Vec<ModulateIn> = (0..pixels)
                .map(|_| ModulateIn {
                    a: rng.random_range(0..=255),
                    b: rng.random_range(0..=255),
                })
                .collect();
            trace_unit(&u, (), &inputs, w)
        }
        "additive_blend" => {
            let u = AdditiveBlend::geforce();
            let mut px = || std::array::from_fn(|_| rng.random_range(0..=255u32));
            let inputs: Vec<AdditiveBlendIn> = (0..pixels)
                .map(|_| AdditiveBlendIn {
                    src: px(),
                    dst: px(),
                    weight: 255,
                })
                .collect();
            trace_unit(&u, (), &inputs, w)
        }
        "texture_sampler" => {
            let cfg = TextureSamplerConfig::geforce_2d(16, 16);
            let texels: Vec<u32> = (0..256).map(|_| rng.random_range(0..=255)).collect();
            let u = TextureSampler::new(cfg, &texels).map_err(|e| e.to_string())?;
            let inputs: Vec<TextureSamplerIn> = (0..pixels)
                .map(|_| TextureSamplerIn {
                    coord: [
                        rng.random_range(0..16 << 8),
                        rng.random_range(0..16 << 8),
                        0,
                    ],
                })
                .collect();
            trace_unit(&u, (), &inputs, w)
        }
        "polygon_interpolator" => {
            let u = PolygonInterpolator::geforce();
            let mut ctr = Counters::default();
            let mut vert = |i: usize, x: f64, y: f64| {
                let attrs: Vec<f64> = (0..4).map(|_| rng.random_range(-4.0..4.0)).collect();
                u.vertex_from_f64(i, x, y, &attrs, &mut ctr)
                    .map_err(|e| e.to_string())
            };
            let v = [vert(0, 0.5, 0.5)?, vert(1, 5.5, 1.0)?, vert(2, 1.0, 4.5)?];
            let s = u.setup_triangle(&v, &mut ctr);
            let moves: Vec<_> = s.moves().into_iter().take(pixels).collect();
            trace_unit(&u, s.state.clone(), &moves, w)
        }
        "shadow_compare" => {
            let u = ShadowCompare::geforce();
            let far = (1u32 << u.depth_bits()) - 1;
            let inputs: Vec<ShadowIn> = (0..pixels)
                .map(|k| {
                    let (x, y) = (rng.random_range(0..4), rng.random_range(0..4));
                    if k % 2 == 0 {
                        ShadowIn::Write {
                            x,
                            y,
                            depth: rng.random_range(0..=far),
                        }
                    } else {
                        ShadowIn::Test {
                            x,
                            y,
                            depth: rng.random_range(0..=far as u64),
                        }
                    }
                })
                .collect();
            trace_unit(&u, u.fresh_state(), &inputs, w)
        }
        "projective_texcoord" => {
            let u = ProjectiveTexcoord::geforce();
            let one = 1i64 << 16;
            let inputs: Vec<ProjectiveIn> = (0..pixels)
                .map(|_| ProjectiveIn {
                    s: rng.random_range(0..4 * one),
                    t: rng.random_range(0..4 * one),
                    q: rng.random_range(one..8 * one),
                })
                .collect();
            trace_unit(&u, (), &inputs, w)
        }
        _ => Err(format!(
            "unit: unknown unit '{name}' (known: {})",
            UNIT_NAMES.join(", ")
        )),
    }
}

fn trace_unit<U: Unit>(
    u: &U,
    mut state: U::State,
    inputs: &[U::In],
    w: &mut dyn Write,
) -> Result<Counters, String> {
    let first = inputs.first().ok_or("pixels: must be at least 1")?;
    let mut probe_state = state.clone();
    let mut scratch = Counters::default();
    let out0 = u.kernel(&mut probe_state, first, &mut scratch);
    let io = |e: std::io::Error| format!("trace: {e}");
    let mut tr = VcdTrace::new(
        w,
        u.name(),
        u.timing().latency,
        &u.in_signals(first),
        &u.out_signals(&out0),
    )
    .map_err(io)?;
    let mut ctr = Counters::default();
    run_tick(u, &mut state, inputs, &mut ctr, Some(&mut tr)).map_err(io)?;
    tr.finish().map_err(io)?;
    Ok(ctr)
}
