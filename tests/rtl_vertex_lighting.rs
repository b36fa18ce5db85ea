//! vertex_lighting's Verilog in the NV2A modes, not only the two GL configurations
//! tests/rtl_cosim.rs runs: the directional light's vector normalised at load or as
//! written (`normalize_directional`), and the two-colour light control
//! (`light_control`) with every set of its four switches (lighting, specular enable,
//! separate specular, specular alpha from the vertex), under Verilator and Icarus
//! (one build each, every mode a block of `cosim_top`), bit- and cycle-exact against
//! the model's vectors (`registry::rtl::vertex_lighting_mode_sets`: 34 narrow sets
//! with a directional light of length ≈ 1.19, 16 at the default's widths with its
//! local spot light), and the NV2A specular curve (`specular_curve`: 6 sets, the
//! "Pow 16" and power-125 SET_SPECULAR_PARAMS words, with GL's colour and with light
//! control). A simulator that is not installed is skipped with a SKIP note
//! (under `.ci/run`, which sets `GLARE_REQUIRE_TOOLS`, it fails instead).

mod common;

use common::cosim::{self, Sim};
use common::icarus::clean_tail;
use glare_pipeline::registry::rtl::{light_controls, vertex_lighting_mode_sets, VectorSet};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// Vertices per mode (seeded; the input word is 66 to 320 bits).
const COUNT: usize = 2_000;
const SEED: u64 = 20;

fn work_dir() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("rtl_vertex_lighting")
}

/// The mode sets, written once for both simulators, and their Verilog blocks.
fn shared() -> &'static (Vec<VectorSet>, Vec<PathBuf>) {
    static SETS: OnceLock<(Vec<VectorSet>, Vec<PathBuf>)> = OnceLock::new();
    SETS.get_or_init(|| {
        let sets = vertex_lighting_mode_sets(COUNT, SEED).unwrap();
        let blocks = cosim::write_sets(&sets, &work_dir().join("sets"));
        (sets, blocks)
    })
}

fn by_tag<'a>(sets: &'a [VectorSet], tag: &str) -> &'a VectorSet {
    sets.iter()
        .find(|v| v.tag() == tag)
        .unwrap_or_else(|| panic!("no set {tag}"))
}

/// The named field of a packed hex word (`fields` in order, the first in the top bits).
fn field(word: &str, fields: &[glare_pipeline::registry::rtl::Field], name: &str) -> u64 {
    let total: u32 = fields.iter().map(|f| f.width).sum();
    let bits: Vec<bool> = word
        .chars()
        .flat_map(|c| {
            let d = c.to_digit(16).unwrap();
            (0..4).rev().map(move |k| d >> k & 1 == 1)
        })
        .collect();
    let mut at = bits.len() - total as usize;
    for f in fields {
        if f.name == name {
            return bits[at..at + f.width as usize]
                .iter()
                .fold(0, |a, &b| a << 1 | u64::from(b));
        }
        at += f.width as usize;
    }
    panic!("no field {name}")
}

/// The sets are the modes the task names, and their vertices tell the modes apart.
#[test]
fn mode_sets_cover_every_switch_set_and_tell_the_modes_apart() {
    let sets = &shared().0;
    assert_eq!(sets.len(), 2 * 17 + 16 + 6);
    // The testbench reads the tag into 64 characters.
    for v in sets {
        assert!(v.tag().len() <= 64, "{}", v.tag());
    }
    let mut tags: Vec<String> = sets.iter().map(VectorSet::tag).collect();
    tags.sort();
    tags.dedup();
    assert_eq!(tags.len(), sets.len(), "tags are unique");
    let name = |lc: &rtl_model::units::vertex_lighting::LightControl| {
        format!(
            "lit{}_spec{}_sep{}_valpha{}",
            u8::from(lc.lighting),
            u8::from(lc.specular_enable),
            u8::from(lc.separate_specular),
            u8::from(lc.specular_alpha_from_vertex)
        )
    };
    for lc in light_controls() {
        let n = name(&lc);
        let d = by_tag(sets, &format!("vertex_lighting_default_{n}"));
        let n0 = by_tag(sets, &format!("vertex_lighting_narrow_nd0_{n}"));
        let n1 = by_tag(sets, &format!("vertex_lighting_narrow_nd1_{n}"));
        for v in [d, n0, n1] {
            assert_eq!(v.stimulus.len(), COUNT);
            assert!(v.params.contains(&("LIGHT_CONTROL", 1)), "{}", v.tag());
            // The vertex colours' edge values occur (0 and max of every field).
            for f in ["dr", "da", "sg", "sa"] {
                let w = v.in_fields.iter().find(|x| x.name == f).unwrap().width;
                let vals: Vec<u64> = v
                    .stimulus
                    .iter()
                    .map(|s| field(s, &v.in_fields, f))
                    .collect();
                assert!(vals.contains(&0) && vals.contains(&((1 << w) - 1)), "{f}");
            }
        }
        // nd0 and nd1: the same vertices (but those the shaper puts at the light's
        // register), the light's registers differ (written or normalised), and with
        // lighting on the colours show it.
        let same: Vec<usize> = (0..COUNT)
            .filter(|&k| n0.stimulus[k] == n1.stimulus[k])
            .collect();
        assert!(
            same.len() > COUNT * 3 / 4,
            "{n}: {} shared vertices",
            same.len()
        );
        let differ = same
            .iter()
            .filter(|&&k| n0.expected[k] != n1.expected[k])
            .count();
        assert_eq!(lc.lighting, differ > 0, "{n}: {differ} vertices differ");
        let light = |v: &VectorSet| {
            v.params
                .iter()
                .filter(|(k, _)| k.starts_with("LIGHT_"))
                .cloned()
                .collect::<Vec<_>>()
        };
        assert_ne!(light(n0), light(n1));
        if lc.lighting && lc.specular_enable && lc.separate_specular {
            // The lit specular sum as the secondary colour: highlights and none.
            for v in [d, n0, n1] {
                let r2: Vec<u64> = v
                    .expected
                    .iter()
                    .map(|s| field(s, &v.out_fields, "r2"))
                    .collect();
                assert!(r2.contains(&0), "{}", v.tag());
                assert!(
                    r2.iter().filter(|&&x| x > 0).count() > COUNT / 20,
                    "{}",
                    v.tag()
                );
                // Its channels differ (a coloured light): a channel swap shows.
                let g2_differs = v
                    .expected
                    .iter()
                    .any(|s| field(s, &v.out_fields, "g2") != field(s, &v.out_fields, "r2"));
                assert!(g2_differs, "{}", v.tag());
            }
        }
    }
    for nd in [0, 1] {
        let gl = by_tag(sets, &format!("vertex_lighting_narrow_nd{nd}_gl"));
        assert!(gl.params.contains(&("LIGHT_CONTROL", 0)));
        assert_eq!(gl.out_fields.len(), 4, "GL's single colour");
    }
}

/// The curve sets carry the curve's parameters, their colours differ from pow's on the
/// same vertices, the power-125 set's x = N·h runs past both of its zeros, and at the
/// narrow "Pow 16" set's switches the curve's two adds set II (9, pow's 8).
#[test]
fn curve_sets_differ_from_pow_and_reach_both_zeros() {
    use rtl_model::units::vertex_lighting::{
        LightControl, LightingSetup, SpecularCurve, VertexLighting, VertexLightingConfig,
    };
    use rtl_model::{FloatFormat, Fp, Unit};
    let sets = &shared().0;
    let curves: Vec<&VectorSet> = sets.iter().filter(|v| v.tag().contains("_curve")).collect();
    assert_eq!(curves.len(), 6);
    for v in &curves {
        assert!(v.params.contains(&("SPECULAR_CURVE", 1)), "{}", v.tag());
        for k in ["CURVE_K0", "CURVE_K1", "CURVE_K2"] {
            assert!(v.params.iter().any(|(n, w)| *n == k && *w != 0), "{k}");
        }
    }
    for v in sets.iter().filter(|v| !v.tag().contains("_curve")) {
        assert!(!v
            .params
            .iter()
            .any(|(n, _)| n.starts_with("SPECULAR_CURVE")));
    }
    // Curve against pow at the same configuration and switches (same vertices).
    for (curve, pow) in [
        ("narrow_nd1_curve125_gl", "narrow_nd1_gl"),
        (
            "narrow_nd1_curve125_lit1_spec1_sep1_valpha1",
            "narrow_nd1_lit1_spec1_sep1_valpha1",
        ),
        (
            "default_curve16_lit1_spec1_sep1_valpha1",
            "default_lit1_spec1_sep1_valpha1",
        ),
        (
            "default_curve125_lit1_spec1_sep0_valpha1",
            "default_lit1_spec1_sep0_valpha1",
        ),
    ] {
        let c = by_tag(sets, &format!("vertex_lighting_{curve}"));
        let p = by_tag(sets, &format!("vertex_lighting_{pow}"));
        assert_eq!(c.stimulus, p.stimulus, "{curve}");
        let differ = (0..COUNT)
            .filter(|&k| c.expected[k] != p.expected[k])
            .count();
        assert!(
            differ > COUNT / 50,
            "{curve}: {differ} vertices differ from pow"
        );
    }
    // x = N·h (f64 from the words) over the narrow power-125 set's lit vertices: below
    // the numerator's zero 0.972, between, and past the denominator's 1.00868.
    let v = by_tag(sets, "vertex_lighting_narrow_nd1_curve125_gl");
    let mut fmt = FloatFormat::IEEE_SINGLE;
    fmt.exp_bits = 4;
    fmt.mant_bits = 6;
    let param = |n: &str| v.params.iter().find(|(k, _)| *k == n).unwrap().1;
    let word = |s: &str, n: &str| fmt.to_f64(Fp(field(s, &v.in_fields, n)));
    let l = ["LIGHT_X", "LIGHT_Y", "LIGHT_Z"].map(|n| fmt.to_f64(Fp(param(n))));
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let unit = |a: [f64; 3]| {
        let r = dot(a, a).sqrt();
        a.map(|c| if r > 0.0 { c / r } else { 0.0 })
    };
    let mut ranges = [0usize; 3];
    for s in &v.stimulus {
        let p = ["px", "py", "pz"].map(|n| word(s, n));
        let n = ["nx", "ny", "nz"].map(|n| word(s, n));
        if dot(n, l) <= 0.0 {
            continue;
        }
        let vv = unit(p.map(|c| -c)); // the narrow configuration's local viewer
        let x = dot(n, unit([l[0] + vv[0], l[1] + vv[1], l[2] + vv[2]]));
        if x < 0.96 {
            ranges[0] += 1;
        } else if (0.98..1.0).contains(&x) {
            ranges[1] += 1;
        } else if x > 1.02 {
            ranges[2] += 1;
        }
    }
    println!("power 125, narrow: x < 0.96, 0.98 ..< 1, > 1.02: {ranges:?}");
    assert!(ranges.iter().all(|&n| n > 0), "{ranges:?}");
    // II: the narrow "Pow 16" set (no normalise, an infinite viewer, light control).
    let iv = by_tag(
        sets,
        "vertex_lighting_narrow_nd1_iv_curve16_lit1_spec1_sep1_valpha0",
    );
    let mut cfg = VertexLightingConfig::geforce().with_format(4, 6);
    cfg.normalize = false;
    cfg.local_viewer = false;
    cfg.light_control = Some(LightControl::default());
    let setup = LightingSetup::default();
    let pow_ii = VertexLighting::new(cfg, &setup).unwrap().timing().ii;
    cfg.specular_curve = SpecularCurve::nv2a([-0.8, -2.8, 3.0, 0.0, 0.0, 0.0]);
    let curve_ii = VertexLighting::new(cfg, &setup).unwrap().timing().ii;
    assert_eq!((pow_ii, curve_ii, iv.ii), (8, 9, 9));
}

fn check(sim: Sim) {
    if !sim.installed() {
        common::tools::skip(&format!(
            "{} not found; vertex_lighting's NV2A modes did not run under it ({})",
            sim.name(),
            sim.install_line()
        ));
        return;
    }
    let (sets, blocks) = shared();
    let run = cosim::build(
        sim,
        &work_dir().join(sim.name()),
        &["units/vertex_lighting.v"],
        blocks,
    );
    let lines = cosim::run_sets(&run, sets, &work_dir().join("sets"));
    let mut failed = Vec::new();
    for (v, line) in sets.iter().zip(&lines) {
        println!("{} {line}", sim.name());
        if !line.ends_with(&clean_tail(v.stimulus.len())) {
            failed.push(format!("{}: {line}", v.tag()));
        }
    }
    assert!(
        failed.is_empty(),
        "{} mismatches:\n{}",
        sim.name(),
        failed.join("\n")
    );
}

#[test]
fn verilator_runs_every_nv2a_mode_bit_and_cycle_exact() {
    check(Sim::Verilator);
}

#[test]
fn icarus_runs_every_nv2a_mode_bit_and_cycle_exact() {
    check(Sim::Icarus);
}
