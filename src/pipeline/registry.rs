//! Every hardware unit by name, in its GeForce-era default configuration: its
//! summary (widths, latency, II, gates, RAM bits), the tables it holds, and a VCD
//! trace of a few random pixels through the tick driver.

use crate::pipeline::glare::tables::{
    halo_prim, line_falloff_samples, line_shape_samples, ring_samples, shape_samples,
};
use crate::pipeline::test_scene;
use crate::reference::glare_model::{Shape2D, SourceGlare};
use crate::scene::glare::{Determinants, GlareModel};
use crate::tables::Table;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::driver::run_tick;
use rtl_model::trace::VcdTrace;
use rtl_model::units::additive_blend::{AdditiveBlend, AdditiveBlendIn};
use rtl_model::units::bloom_flare_modulator::{BloomFlareModulator, BloomFlareModulatorConfig};
use rtl_model::units::chaos_map::ChaosMap;
use rtl_model::units::cube_map_address::{CubeMapAddress, CubeMapAddressIn};
use rtl_model::units::final_combiner::FinalCombiner;
use rtl_model::units::gaussian_noise::{GaussState, GaussianNoise};
use rtl_model::units::glare_combiner::{CombineIn, GlareCombiner};
use rtl_model::units::glare_condition::{ConditionIn, GlareCondition, Material};
use rtl_model::units::halo_modulator::{HaloModulator, HaloModulatorConfig};
use rtl_model::units::luminance_ram::{LumIn, LumWidths};
use rtl_model::units::modulate::{Modulate, ModulateIn};
use rtl_model::units::polygon_interpolator::PolygonInterpolator;
use rtl_model::units::polygon_variable_generator::{PolygonVariableGenerator, PrimKind, PvgIn};
use rtl_model::units::projective_texcoord::{ProjectiveIn, ProjectiveTexcoord};
use rtl_model::units::reflection_vector::{ReflectionVector, ReflectionVectorIn};
use rtl_model::units::register_combiner::{RegisterCombiner, RegisterFile};
use rtl_model::units::shadow_compare::{ShadowCompare, ShadowIn};
use rtl_model::units::specular_lookup::{SpecularLookup, SpecularLookupIn};
use rtl_model::units::texture_combiner::{TextureCombiner, TextureCombinerIn};
use rtl_model::units::texture_sampler::{TextureSampler, TextureSamplerConfig, TextureSamplerIn};
use rtl_model::units::vertex_lighting::{VertexLighting, VertexLightingConfig, VertexLightingIn};
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
    "polygon_variable_generator",
    "bloom_flare_modulator",
    "halo_modulator",
    "glare_combiner",
    "gaussian_noise",
    "chaos_map",
    "glare_condition",
    "reflection_vector",
    "cube_map_address",
    "specular_lookup",
    "register_combiner",
    "final_combiner",
    "texture_combiner",
    "vertex_lighting",
];

/// The default texture sampler (2D 256 × 256 luminance), holding a zero texture.
fn default_sampler() -> TextureSampler {
    let cfg = TextureSamplerConfig::geforce();
    let texels = vec![0u32; cfg.texel_count() as usize];
    TextureSampler::new(cfg, &texels).expect("the GeForce default sampler config is valid")
}

/// The default bloom/flare modulator (`LumWidths::default()`), holding the tables
/// every flare line shares: the spindle shape and the (1 − d)² falloff. (Bloom tables
/// are per source and loaded by the host with each primitive.)
pub fn default_bloom_flare() -> BloomFlareModulator {
    let w = LumWidths::default();
    BloomFlareModulatorConfig::from_widths(w)
        .build(
            &line_shape_samples(w.shape_log2),
            &line_falloff_samples(w.falloff_log2),
        )
        .expect("the default modulator widths and the flare-line tables are valid")
}

/// Pixels per degree of the representative halo source (a point source; the ring
/// tables do not depend on it, only its shape table's quad margin does).
const HALO_PX_PER_DEG: f64 = 20.0;

/// The representative halo: a point source of the default glare model and
/// determinants (λ = 650, 550, 450 nm). Returns θ_max (degrees) and the shape and
/// R, G, B ring samples the host writes, as the frame computes them.
fn default_halo_tables(w: &LumWidths) -> (f64, Vec<f64>, [Vec<f64>; 3]) {
    let model = GlareModel::default();
    let det = Determinants::default();
    let src = SourceGlare {
        center: [0.0, 0.0],
        shape: Shape2D::Point,
        px_per_deg: HALO_PX_PER_DEG,
        color: [1.0; 3],
        bloom: None,
        halo: Some(1.0),
        flare: None,
    };
    let (a, theta_max) = halo_prim(&src, &det, &model);
    let shape = shape_samples(&src.shape, &a, w.shape_log2);
    let rings = det
        .wavelengths_nm
        .map(|l| ring_samples(l, theta_max, &model, w.falloff_log2));
    (theta_max, shape, rings)
}

/// The default halo modulator holding the representative halo's tables.
pub fn default_halo() -> HaloModulator {
    let w = LumWidths::default();
    let (_, shape, r) = default_halo_tables(&w);
    HaloModulatorConfig::from_widths(w)
        .build(&shape, [&r[0], &r[1], &r[2]])
        .expect("the default modulator widths and the halo tables are valid")
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
        UnitSummary::of(&PolygonVariableGenerator::geforce()),
        UnitSummary::of(&default_bloom_flare()),
        UnitSummary::of(&default_halo()),
        UnitSummary::of(&GlareCombiner::geforce()),
        UnitSummary::of(&GaussianNoise::geforce()),
        UnitSummary::of(&ChaosMap::geforce()),
        UnitSummary::of(&GlareCondition::geforce()),
        UnitSummary::of(&ReflectionVector::geforce3()),
        UnitSummary::of(&CubeMapAddress::geforce3()),
        UnitSummary::of(&SpecularLookup::geforce()),
        UnitSummary::of(&RegisterCombiner::geforce()),
        UnitSummary::of(&FinalCombiner::geforce()),
        UnitSummary::of(&TextureCombiner::geforce()),
        UnitSummary::of(&VertexLighting::geforce()),
    ]
}

fn params(kv: &[(&str, String)]) -> BTreeMap<String, String> {
    kv.iter().map(|(k, v)| (k.to_string(), v.clone())).collect()
}

/// The glare units' ROMs and the modulator RAMs that do not change from primitive to
/// primitive: the flare lines' shared shape and falloff, and the halo rings of the
/// default model. Bloom shape/falloff and halo shape RAMs depend on each source's
/// outline, size and intensity and are written by the host per primitive: not here.
fn glare_tables() -> Vec<Table> {
    let mut out = Vec::new();
    let rom = |name: String, width: u32, words: Vec<u64>, unit: &str, p| Table {
        name: name.replace('.', "_"),
        width,
        words,
        unit: unit.into(),
        params: p,
    };

    // Polygon variable generator: the quarter-wave cosine ROM.
    let pvg = PolygonVariableGenerator::geforce();
    let c = pvg.config();
    out.push(rom(
        format!(
            "polygon_variable_generator_cos_k{}_b{}",
            c.trig_log2, c.trig_bits
        ),
        c.trig_bits,
        pvg.rom_words(),
        "polygon_variable_generator",
        params(&[
            ("trig_log2", c.trig_log2.to_string()),
            ("trig_bits", c.trig_bits.to_string()),
            (
                "generator",
                "entry[j] = round(cos(j/2^k * pi/2) * (2^B - 1)), j = 0 ..= 2^k, unorm B; \
                 sin is read at entry[2^k - j], the quadrant folds signs"
                    .into(),
            ),
        ]),
    ));

    // Bloom/flare modulator: the flare lines' shared tables (loaded once per frame).
    let w = LumWidths::default();
    let bf = default_bloom_flare();
    let shape_params = |extra: &[(&str, String)]| {
        let mut p = params(&[
            ("shape_log2", w.shape_log2.to_string()),
            ("shape_bits", w.shape_bits.to_string()),
        ]);
        p.extend(params(extra));
        p
    };
    let falloff_params = |extra: &[(&str, String)]| {
        let mut p = params(&[
            ("falloff_log2", w.falloff_log2.to_string()),
            ("falloff_bits", w.falloff_bits.to_string()),
        ]);
        p.extend(params(extra));
        p
    };
    out.push(rom(
        format!(
            "bloom_flare_modulator_line_shape_k{}_b{}",
            w.shape_log2, w.shape_bits
        ),
        w.shape_bits,
        bf.shape_codes().iter().map(|&v| u64::from(v)).collect(),
        "bloom_flare_modulator",
        shape_params(&[
            (
                "generator",
                "flare-line spindle: sample (i, j) at u = -1 + i*2^(1-k), v = -1 + j*2^(1-k), \
                 d = min(1, sqrt(((u+1)/2)^2 + v^2)), code = round(d * (2^sb - 1)) at \
                 [j*(2^k+1) + i]"
                    .into(),
            ),
            (
                "loaded",
                "once per frame, shared by every flare line".into(),
            ),
        ]),
    ));
    out.push(rom(
        format!(
            "bloom_flare_modulator_line_falloff_m{}_b{}",
            w.falloff_log2, w.falloff_bits
        ),
        w.falloff_bits,
        bf.falloff_codes().iter().map(|&v| u64::from(v)).collect(),
        "bloom_flare_modulator",
        falloff_params(&[
            (
                "generator",
                "flare-line falloff p(d) = (1 - d)^2 at d = j/2^m, j = 0 ..= 2^m, \
                 code = round(p * (2^fb - 1))"
                    .into(),
            ),
            (
                "loaded",
                "once per frame, shared by every flare line".into(),
            ),
        ]),
    ));

    // Halo modulator: the three ring RAMs of the default model.
    let (theta_max, _, _) = default_halo_tables(&w);
    let halo = default_halo();
    let model = GlareModel::default();
    let det = Determinants::default();
    for (c, ch) in ["r", "g", "b"].iter().enumerate() {
        out.push(rom(
            format!(
                "halo_modulator_ring_{ch}_m{}_b{}",
                w.falloff_log2, w.falloff_bits
            ),
            w.falloff_bits,
            halo.ring_codes(c).iter().map(|&v| u64::from(v)).collect(),
            "halo_modulator",
            falloff_params(&[
                (
                    "generator",
                    "exp(-((theta - theta1*lambda/568)/alpha)^2) at theta = j/2^m * theta_max, \
                     j = 0 ..= 2^m, code = round(v * (2^fb - 1)); theta_max = \
                     theta1*max(lambda)/568 + 4*alpha (degrees)"
                        .into(),
                ),
                ("lambda_nm", det.wavelengths_nm[c].to_string()),
                ("theta1_deg", model.halo_radius_deg.to_string()),
                ("alpha_deg", model.halo_alpha_deg.to_string()),
                ("theta_max_deg", format!("{theta_max:.12}")),
                (
                    "loaded",
                    "by the host with each halo primitive; the same for every source of \
                     a scene with the default model and determinants"
                        .into(),
                ),
            ]),
        ));
    }

    // Gaussian noise: ln, sqrt and sin ROMs of the Box-Muller datapath.
    let gn = GaussianNoise::geforce();
    let gc = gn.config();
    let gens = [
        "entry[i] = round(ln(1 + i/2^T) * 2^E), i = 0 ..= 2^T, u0.E",
        "entry[j] = round(sqrt(i/2^(T-2)) * 2^E), i = 2^(T-2) + j, j = 0 ..= 3*2^(T-2), u2.E",
        "entry[i] = round(sin(pi/2 * i/2^T) * 2^E), i = 0 ..= 2^T, u1.E (quarter wave)",
    ];
    for ((name, width, words), g) in gn.rom_images().into_iter().zip(gens) {
        out.push(rom(
            name,
            width,
            words,
            "gaussian_noise",
            params(&[
                ("table_log2", gc.table_log2.to_string()),
                ("table_bits", gc.table_bits.to_string()),
                ("generator", g.into()),
            ]),
        ));
    }

    // Chaos map: log2 and exp2 ROMs of the left branch.
    let cm = ChaosMap::geforce();
    let cc = cm.config();
    let gens = [
        "entry[i] = round(log2(1 + i/2^T) * 2^E), i = 0 ..= 2^T, u1.E",
        "entry[i] = round(2^(-i/2^T) * 2^E), i = 0 ..= 2^T, u1.E",
    ];
    for ((name, width, words), g) in cm.rom_images().into_iter().zip(gens) {
        out.push(rom(
            name,
            width,
            words,
            "chaos_map",
            params(&[
                ("table_log2", cc.table_log2.to_string()),
                ("table_bits", cc.table_bits.to_string()),
                ("generator", g.into()),
            ]),
        ));
    }
    out
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
    out.extend(glare_tables());
    let refl = ReflectionVector::geforce3();
    let c = refl.config();
    out.push(Table {
        name: format!(
            "reflection_vector_rsqrt_{}x{}",
            1u32 << c.rsqrt_addr_bits,
            c.rsqrt_bits
        ),
        width: c.rsqrt_bits,
        words: refl.rom_words(),
        unit: "reflection_vector".into(),
        params: BTreeMap::from([
            ("addr_bits".to_string(), c.rsqrt_addr_bits.to_string()),
            ("entry_bits".to_string(), c.rsqrt_bits.to_string()),
            (
                "generator".to_string(),
                "rsqrt_rom_entry(j): min(round(2^R / sqrt(c)), 2^R - 1), u0.R, c the midpoint of address j's interval of the mantissa m in [1, 4) (top address bit: [1, 2) or [2, 4)); rtl_model/src/units/reflection_vector.rs".to_string(),
            ),
            ("copies".to_string(), "2 (n and e in parallel)".to_string()),
        ]),
    });
    let vl = VertexLighting::geforce();
    let f = vl.format();
    let k = f.pow_frac_bits();
    out.push(Table {
        name: format!("vertex_lighting_exp2_{k}x{}", k + 1),
        width: k + 1,
        words: f.exp2_rom(),
        unit: "vertex_lighting".into(),
        params: BTreeMap::from([
            ("exp_bits".to_string(), f.exp_bits.to_string()),
            ("mant_bits".to_string(), f.mant_bits.to_string()),
            ("pow_frac_bits".to_string(), k.to_string()),
            (
                "generator".to_string(),
                "entry[k-1] = 2^(2^-k) in u1.K, k = 1 ..= K = M + 4: K integer square roots from 2 at K + 16 bits, rounded to K (the pow unit's exp2 constants); rtl_model/src/float_format.rs".to_string(),
            ),
        ]),
    });
    let cube = CubeMapAddress::geforce3();
    let c = cube.config();
    out.push(Table {
        name: format!(
            "cube_map_address_rcp_{}x{}",
            1u32 << c.rcp_addr_bits,
            c.rcp_bits
        ),
        width: c.rcp_bits,
        words: cube.rom_words(),
        unit: "cube_map_address".into(),
        params: BTreeMap::from([
            ("addr_bits".to_string(), c.rcp_addr_bits.to_string()),
            ("entry_bits".to_string(), c.rcp_bits.to_string()),
            (
                "generator".to_string(),
                "rcp_rom_entry(j): min(round(2^R / c), 2^R - 1), u0.R, c = 1 + (j + 1/2)/2^A the midpoint of address j's interval of the mantissa m in [1, 2) of |ma|; rtl_model/src/units/cube_map_address.rs".to_string(),
            ),
        ]),
    });
    let spec = SpecularLookup::geforce();
    let c = spec.config();
    out.push(Table {
        name: format!(
            "specular_lookup_pow{}_{}x{}",
            c.exponent,
            1u32 << c.table_log2,
            c.entry_bits
        ),
        width: c.entry_bits,
        words: spec.table_words(),
        unit: "specular_lookup".into(),
        params: BTreeMap::from([
            ("table_log2".to_string(), c.table_log2.to_string()),
            ("entry_bits".to_string(), c.entry_bits.to_string()),
            ("exponent".to_string(), c.exponent.to_string()),
            (
                "generator".to_string(),
                "specular_table_entry(j): round((j/N)^s * (2^b - 1)) half up, N = 2^k - 1; the host writes it per exponent (this is the default s); rtl_model/src/units/specular_lookup.rs".to_string(),
            ),
        ]),
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
        "polygon_variable_generator" => {
            let u = PolygonVariableGenerator::geforce();
            let c = u.config();
            // Centres within ±1/4 of the position range, extents up to 1/16 of it.
            let span = 1i64 << (c.coord_int_bits + c.subpixel_bits - 3);
            let inputs: Vec<PvgIn> = (0..pixels)
                .map(|_| PvgIn {
                    kind: if rng.random::<bool>() {
                        PrimKind::Line
                    } else {
                        PrimKind::Area
                    },
                    cx: rng.random_range(-span..span),
                    cy: rng.random_range(-span..span),
                    extent: rng.random_range(0..span as u64 / 2),
                    half_width: rng.random_range(0..span as u64 / 32),
                    angle: rng.random_range(0..1u32 << c.angle_bits),
                })
                .collect();
            trace_unit(&u, (), &inputs, w)
        }
        "bloom_flare_modulator" | "halo_modulator" => {
            let lw = LumWidths::default();
            // (u, v) over ±1.25 (the clamp region included), gains up to 255 codes.
            let one = 1i32 << lw.coord_frac_bits;
            let lim = one + one / 4;
            let gmax = 255u32 << lw.gain_frac_bits;
            let inputs: Vec<LumIn> = (0..pixels)
                .map(|_| LumIn {
                    u: rng.random_range(-lim..=lim),
                    v: rng.random_range(-lim..=lim),
                    gain: std::array::from_fn(|_| rng.random_range(0..=gmax)),
                })
                .collect();
            if name == "halo_modulator" {
                trace_unit(&default_halo(), (), &inputs, w)
            } else {
                trace_unit(&default_bloom_flare(), (), &inputs, w)
            }
        }
        "glare_combiner" => {
            let u = GlareCombiner::geforce();
            let c = u.config();
            let (fmax, lmax) = ((1u32 << c.fb_bits) - 1, (1u32 << c.lum_bits) - 1);
            let inputs: Vec<CombineIn> = (0..pixels)
                .map(|_| CombineIn {
                    fb: std::array::from_fn(|_| rng.random_range(0..=fmax)),
                    // Mostly small luminance, sometimes enough to saturate.
                    lum: std::array::from_fn(|_| rng.random_range(0..=lmax) >> 4),
                })
                .collect();
            trace_unit(&u, (), &inputs, w)
        }
        "gaussian_noise" => {
            let u = GaussianNoise::geforce();
            trace_unit(&u, GaussState::from_seed(seed), &vec![(); pixels], w)
        }
        "chaos_map" => {
            let u = ChaosMap::geforce();
            trace_unit(&u, u.seeded_state(seed), &vec![(); pixels], w)
        }
        "glare_condition" => {
            let u = GlareCondition::geforce();
            let c = u.config();
            let iw = c.int_bits + c.frac_bits;
            let one = 1i32 << c.cos_frac_bits;
            let inputs: Vec<ConditionIn> = (0..pixels)
                .map(|_| {
                    let intensity = rng.random_range(0..1u32 << iw);
                    ConditionIn {
                        material: if rng.random::<bool>() {
                            Material::Water
                        } else {
                            Material::Metallic
                        },
                        intensity,
                        specular: rng.random_range(0..1u32 << c.coef_bits),
                        cos_alpha: rng.random_range(-one / 4..one),
                        cos_theta: rng.random_range(-one..one),
                        // Around the contrast threshold: I_a ≈ I/T.
                        ambient: rng.random_range(0..=intensity / c.threshold.max(1) * 2),
                    }
                })
                .collect();
            trace_unit(&u, (), &inputs, w)
        }
        "reflection_vector" => {
            let u = ReflectionVector::geforce3();
            let c = u.config();
            // n, e over ±4 units (grazing and back-facing included), λ over [0, 1].
            let lim = 4i64 << c.in_frac_bits;
            let inputs: Vec<ReflectionVectorIn> = (0..pixels)
                .map(|_| {
                    let n = [(); 3].map(|_| rng.random_range(-lim..=lim));
                    let e = [(); 3].map(|_| rng.random_range(-lim..=lim));
                    let lambda = rng.random_range(0..=1u32 << c.lambda_bits);
                    ReflectionVectorIn { n, e, lambda }
                })
                .collect();
            trace_unit(&u, (), &inputs, w)
        }
        "cube_map_address" => {
            let u = CubeMapAddress::geforce3();
            let c = u.config();
            // The reflection unit's words: anywhere in the map's cube [0, s]³ (texels,
            // s(16).8), the centre (a zero direction) now and then.
            let s = 1i32 << (c.side_log2 + c.in_frac_bits);
            let inputs: Vec<CubeMapAddressIn> = (0..pixels)
                .map(|k| CubeMapAddressIn {
                    coord: if k % 8 == 7 {
                        [s / 2; 3]
                    } else {
                        [(); 3].map(|_| rng.random_range(0..=s))
                    },
                })
                .collect();
            trace_unit(&u, (), &inputs, w)
        }
        "specular_lookup" => {
            let u = SpecularLookup::geforce();
            // DOT3 codes over the whole range, with the top (the highlight) favoured.
            let inputs: Vec<SpecularLookupIn> = (0..pixels)
                .map(|k| SpecularLookupIn {
                    code: if k % 2 == 0 {
                        rng.random_range(0..=255)
                    } else {
                        rng.random_range(224..=255)
                    },
                })
                .collect();
            trace_unit(&u, (), &inputs, w)
        }
        "texture_combiner" => {
            // GL's initial COMBINE state: MODULATE of TEXTURE and PREVIOUS, 8-bit.
            let u = TextureCombiner::geforce();
            let mut px = || std::array::from_fn(|_| rng.random_range(0..=255u32));
            let inputs: Vec<TextureCombinerIn> = (0..pixels)
                .map(|_| TextureCombinerIn {
                    texture: px(),
                    constant: px(),
                    primary_color: px(),
                    previous: px(),
                })
                .collect();
            trace_unit(&u, (), &inputs, w)
        }
        "register_combiner" | "final_combiner" => {
            // Register sets as COMBINER0 sees them: random 8-bit fragment colours loaded
            // into the 9-bit registers, SPARE0/1 anywhere in [−1, 1].
            let rc = RegisterCombiner::geforce();
            let s = rc.one() as i32;
            let inputs: Vec<RegisterFile> = (0..pixels)
                .map(|_| {
                    let mut f = RegisterFile::default();
                    for (k, reg) in f.regs.iter_mut().enumerate().skip(1) {
                        let lo = if (6..8).contains(&k) { -s } else { 0 };
                        *reg = std::array::from_fn(|_| rng.random_range(lo..=s));
                    }
                    f
                })
                .collect();
            if name == "register_combiner" {
                trace_unit(&rc, (), &inputs, w)
            } else {
                trace_unit(&FinalCombiner::geforce(), (), &inputs, w)
            }
        }
        "vertex_lighting" => {
            // GL's default state (GL_LIGHT0, default material with a specular term),
            // vertices on a sphere of radius 1 at z = −4, normals of varying length
            // (GL_NORMALIZE), now and then a zero-length one.
            let cfg = VertexLightingConfig::geforce();
            let mut setup = rtl_model::units::vertex_lighting::LightingSetup::default();
            setup.material.specular = [0.8; 3];
            setup.material.shininess = 32.0;
            let u = VertexLighting::new(cfg, &setup).map_err(|e| e.to_string())?;
            let mut ctr = Counters::default();
            let inputs: Vec<VertexLightingIn> = (0..pixels)
                .map(|k| {
                    let n: [f64; 3] = [(); 3].map(|_| rng.random_range(-1.0..1.0));
                    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt().max(1e-3);
                    let scale = if k % 8 == 7 {
                        0.0
                    } else {
                        rng.random_range(0.5..2.0)
                    };
                    let p = [0, 1, 2].map(|i| n[i] / len + if i == 2 { -4.0 } else { 0.0 });
                    u.vertex_from_f64(p, n.map(|c| c / len * scale), &mut ctr)
                        .map_err(|e| e.to_string())
                })
                .collect::<Result<_, _>>()?;
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
