//! halo_modulator against its f64 twin under the width-derived bound (the bloom/flare
//! bound per channel with that channel's ring profile; see tests/lum_common and
//! docs/units.md § halo_modulator), for four width configs (defaults, wide, two
//! narrow), random smooth and rough shapes and three independent random rings, random
//! positions including the clamp region; exhaustive over (u, v) for the narrow
//! configs; drivers agree; config and host-edge errors name the field.

mod common;
mod lum_common;

use glare_pipeline::reference::halo_modulator::halo_modulator as twin;
use lum_common::*;
use proptest::prelude::*;
use rtl_model::units::halo_modulator::{HaloModulator, HaloModulatorConfig, LumIn};
use rtl_model::units::luminance_ram::LumWidths;
use rtl_model::{Counters, Unit};

type Rings = [Vec<f64>; 3];

fn r3(r: &Rings) -> [&[f64]; 3] {
    [&r[0], &r[1], &r[2]]
}

fn build(w: &LumWidths, shape: &[f64], rings: &Rings) -> HaloModulator {
    HaloModulatorConfig::from_widths(*w)
        .build(shape, r3(rings))
        .unwrap()
}

/// Three independent random rings (kinds k, k+1, k+3, seeds differ).
fn rings(w: &LumWidths, kind: u32, seed: u64) -> Rings {
    [
        falloff_table(w, kind, seed),
        falloff_table(w, kind + 1, seed.wrapping_add(1)),
        falloff_table(w, kind + 3, seed.wrapping_add(2)),
    ]
}

fn flat(w: &LumWidths, x: f64) -> Rings {
    [
        vec![x; w.falloff_len()],
        vec![x; w.falloff_len()],
        vec![x; w.falloff_len()],
    ]
}

/// Check one pixel against the twin; returns the largest |err|/bound of d and lum.
#[allow(clippy::too_many_arguments)]
fn check(
    m: &HaloModulator,
    shape: &[f64],
    falloff: &Rings,
    e_d: f64,
    e_p: [f64; 3],
    u: i32,
    v: i32,
    gain: [u32; 3],
) -> (f64, f64) {
    let w = m.lum_widths();
    let mut ctr = Counters::default();
    let out = m.kernel(&mut (), &LumIn { u, v, gain }, &mut ctr);
    let g = gain.map(|c| gain_value(&w, c));
    let (d, lum) = twin(
        shape,
        w.shape_log2,
        r3(falloff),
        w.falloff_log2,
        coord_value(&w, u),
        coord_value(&w, v),
        g,
        out_max(&w),
    );
    let dk = out.d as f64 / ((1u64 << w.shape_bits) - 1) as f64;
    assert!(
        (dk - d).abs() <= e_d * (1.0 + 1e-9) + 1e-12,
        "{w:?} u {u} v {v}: d {dk} want {d} (bound {e_d})"
    );
    let mut rl = 0f64;
    for c in 0..3 {
        let b = bound_lum(&w, e_p[c], gain[c]);
        let err = out.lum[c] as f64 - lum[c];
        rl = rl.max(err.abs() / b);
        assert!(
            err.abs() <= b * (1.0 + 1e-9) + 1e-9,
            "{w:?} u {u} v {v} gain {gain:?}: lum[{c}] {} want {} (err {err}, bound {b})",
            out.lum[c],
            lum[c]
        );
    }
    assert_eq!(ctr.table_reads, 10);
    let one = 1i32 << w.coord_frac_bits;
    let clamps = (u.abs() >= one) as u64 + (v.abs() >= one) as u64;
    assert!(ctr.saturations >= clamps && ctr.saturations <= clamps + 3);
    ((dk - d).abs() / e_d, rl)
}

fn run_case(cfg: usize, skind: u32, fkind: u32, seed: u64, npts: usize) {
    let w = configs()[cfg];
    let shape = shape_table(&w, skind, seed);
    let falloff = rings(&w, fkind, seed);
    let m = build(&w, &shape, &falloff);
    let e_d = bound_d(&w, &shape);
    let e_p = [0, 1, 2].map(|c| bound_p(&w, &falloff[c], e_d));
    for (u, v, g) in random_points(&w, seed, npts) {
        check(&m, &shape, &falloff, e_d, e_p, u, v, g);
    }
}

#[test]
fn exhaustive_positions_for_the_narrow_configs() {
    // Config 2: F = 8 → 10-bit u and v, 2²⁰ positions; config 3: F = 2 → 2⁸.
    for (cfg, skind, fkind) in [(2usize, 1u32, 1u32), (3, 0, 2), (3, 3, 1)] {
        let w = configs()[cfg];
        let shape = shape_table(&w, skind, 7);
        let falloff = rings(&w, fkind, 7);
        let m = build(&w, &shape, &falloff);
        let e_d = bound_d(&w, &shape);
        let e_p = [0, 1, 2].map(|c| bound_p(&w, &falloff[c], e_d));
        let (lo, hi) = coord_range(&w);
        let g = [w.gain_max(), w.gain_max() / 2, 1];
        let (mut rd, mut rl) = (0f64, 0f64);
        for v in lo..=hi {
            for u in lo..=hi {
                let (a, b) = check(&m, &shape, &falloff, e_d, e_p, u, v, g);
                rd = rd.max(a);
                rl = rl.max(b);
            }
        }
        println!("config {cfg}: worst |err|/bound: d {rd:.3}, lum {rl:.3}");
    }
}

#[test]
fn flat_tables_give_exact_gain() {
    // d = 0 everywhere, p = 1 everywhere → lum = gain rounded (and saturated).
    let w = LumWidths::default();
    let m = build(&w, &vec![0.0; w.shape_len()], &flat(&w, 1.0));
    let mut ctr = Counters::default();
    let g = m.gain_from_f64([100.0, 4095.0, 0.5]).unwrap();
    let o = m.kernel(
        &mut (),
        &LumIn {
            u: 3,
            v: -700,
            gain: g,
        },
        &mut ctr,
    );
    assert_eq!(o.d, 0);
    assert_eq!(o.lum, [100, 4095, 1]);
    let g = m.gain_from_f64([4095.9375, 0.0, 0.0]).unwrap();
    let o = m.kernel(
        &mut (),
        &LumIn {
            u: 0,
            v: 0,
            gain: g,
        },
        &mut ctr,
    );
    assert_eq!(o.lum, [4095, 0, 0]);
    assert_eq!(ctr.saturations, 1);
}

#[test]
fn defaults_cost_and_ram_bits() {
    let w = LumWidths::default();
    let m = build(&w, &vec![0.0; w.shape_len()], &flat(&w, 1.0));
    let c = m.cost();
    println!(
        "halo_modulator defaults: latency {} II {} gates {:.0} NAND2, RAM bits {}, table words {}",
        m.timing().latency,
        m.timing().ii,
        c.gates_nand2(),
        c.ram_bits,
        m.table_words()
    );
    for (n, g) in &c.breakdown {
        println!("  {n}: {g:.0}");
    }
    assert_eq!(c.ram_bits, 129 * 129 * 16 + 3 * 257 * 16);
    assert_eq!(m.table_words(), 129 * 129 + 3 * 257);
}

#[test]
fn wire_masking_matches_the_masked_input() {
    let w = configs()[2];
    let shape = shape_table(&w, 1, 3);
    let falloff = rings(&w, 1, 3);
    let m = build(&w, &shape, &falloff);
    let mut c = Counters::default();
    for (u, v, g) in random_points(&w, 11, 200) {
        let a = m.kernel(&mut (), &LumIn { u, v, gain: g }, &mut c);
        let junk = LumIn {
            u: u ^ (0x5a5a_5a5a << (w.coord_frac_bits + 2)),
            v: v ^ (-1i32 << (w.coord_frac_bits + 2)),
            gain: g.map(|x| x | (0xffff_ffff << w.gain_bits())),
        };
        assert_eq!(m.kernel(&mut (), &junk, &mut c), a);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    #[test]
    fn within_bound_random_tables_and_positions(
        cfg in 0usize..4,
        skind in 0u32..4,
        fkind in 0u32..4,
        seed in any::<u64>(),
    ) {
        run_case(cfg, skind, fkind, seed, 24);
    }

    #[test]
    fn tick_and_span_drivers_agree(
        cfg in 0usize..4,
        seed in any::<u64>(),
        n in 0usize..40,
    ) {
        let w = configs()[cfg];
        let m = build(&w, &shape_table(&w, seed as u32, seed), &rings(&w, (seed >> 8) as u32 % 4, seed));
        let inputs: Vec<LumIn> = random_points(&w, seed, n)
            .into_iter()
            .map(|(u, v, gain)| LumIn { u, v, gain })
            .collect();
        common::assert_drivers_agree(&m, (), &inputs);
    }

    #[test]
    fn random_configs_never_panic_and_errors_name_the_field(
        f in 0u32..20, k in 0u32..13, sb in 0u32..18, m in 0u32..14, fb in 0u32..22,
        wb in 0u32..14, gi in 0u32..18, gf in 0u32..18, ob in 0u32..18,
    ) {
        let cfg = HaloModulatorConfig {
            coord_frac_bits: f, shape_log2: k, shape_bits: sb, falloff_log2: m,
            falloff_bits: fb, weight_bits: wb, gain_int_bits: gi, gain_frac_bits: gf,
            out_bits: ob, radial: Default::default(),
        };
        let mut bad = Vec::new();
        if !(2..=16).contains(&f) { bad.push("coord_frac_bits"); }
        if !(1..=10).contains(&k) { bad.push("shape_log2"); }
        if !(1..=16).contains(&sb) { bad.push("shape_bits"); }
        if !(1..=12).contains(&m) { bad.push("falloff_log2"); }
        if !(1..=20).contains(&fb) { bad.push("falloff_bits"); }
        if !(1..=12).contains(&wb) { bad.push("weight_bits"); }
        if gi > 16 { bad.push("gain_int_bits"); }
        if gf > 16 || gi + gf == 0 { bad.push("gain_frac_bits"); }
        if !(1..=16).contains(&ob) { bad.push("out_bits"); }
        if bad.is_empty() {
            let w = cfg.widths();
            // Wrong table lengths name the table.
            let fl = flat(&w, 0.5);
            let e = cfg.build(&[0.5], r3(&fl)).unwrap_err();
            prop_assert_eq!(e.field(), "halo_modulator.shape");
            if k <= 5 {
                let sh = vec![0.5; w.shape_len()];
                prop_assert!(cfg.build(&sh, r3(&fl)).is_ok());
                let e = cfg.build(&sh, [&fl[0], &fl[1], &[]]).unwrap_err();
                prop_assert_eq!(e.field(), "halo_modulator.rings[2]");
            }
        } else {
            let e = cfg.build(&[], [&[], &[], &[]]).unwrap_err();
            let field = e.field().to_string();
            prop_assert!(
                bad.iter().any(|b| field == format!("halo_modulator.{b}")),
                "{} not in {:?}", field, bad
            );
        }
    }

    #[test]
    fn bad_table_entries_and_gains_name_the_field(
        idx in any::<prop::sample::Index>(),
        x in prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(-1e-3), Just(1.0001), Just(f64::NEG_INFINITY)],
        c in 0usize..3,
        g in prop_oneof![Just(f64::NAN), Just(-0.5), Just(1e9), Just(f64::INFINITY)],
    ) {
        let w = configs()[2];
        let cfg = HaloModulatorConfig::from_widths(w);
        let mut shape = vec![0.25; w.shape_len()];
        let i = idx.index(shape.len());
        shape[i] = x;
        let fl = flat(&w, 0.5);
        let e = cfg.build(&shape, r3(&fl)).unwrap_err();
        prop_assert_eq!(e.field(), format!("halo_modulator.shape[{i}]"));
        let mut fo = flat(&w, 0.25);
        let j = idx.index(w.falloff_len());
        fo[c][j] = x;
        let sh = vec![0.5; w.shape_len()];
        let e = cfg.build(&sh, r3(&fo)).unwrap_err();
        prop_assert_eq!(e.field(), format!("halo_modulator.rings[{c}][{j}]"));
        let m = cfg.build(&sh, r3(&fl)).unwrap();
        let mut gains = [1.0; 3];
        gains[c] = g;
        let e = m.gain_from_f64(gains).unwrap_err();
        prop_assert_eq!(e.field(), format!("halo_modulator.gain[{c}]"));
        if x.is_nan() || x.is_infinite() {
            let e = m.coord_from_f64(x).unwrap_err();
            prop_assert_eq!(e.field(), "halo_modulator.coord");
        }
    }

    #[test]
    fn coord_from_f64_rounds_and_saturates(x in -3.0f64..3.0) {
        static M: std::sync::OnceLock<HaloModulator> = std::sync::OnceLock::new();
        let w = LumWidths::default();
        let m = M.get_or_init(|| build(&w, &vec![0.0; w.shape_len()], &flat(&w, 1.0)));
        let c = m.coord_from_f64(x).unwrap();
        let (lo, hi) = coord_range(&w);
        prop_assert!(c >= lo && c <= hi);
        if x > -2.0 && x < 1.999 {
            prop_assert!((coord_value(&w, c) - x).abs() <= 0.5 / 1024.0 + 1e-12);
        }
    }
}

// ---------------------------------------------------------------------------------
// Radial correction (LumWidths::radial.on): signed e tables, κ register, the bound
// `bound_d_radial` (tests/lum_common) derived from the widths, four configs.

use glare_pipeline::reference::halo_modulator::halo_modulator_radial as twin_r;

fn build_r(w: &LumWidths, e: &[f64], rings: &Rings, kappa: u32) -> HaloModulator {
    HaloModulatorConfig::from_widths(*w)
        .build(e, r3(rings))
        .unwrap()
        .with_kappa(w.kappa_value(kappa))
        .unwrap()
}

#[allow(clippy::too_many_arguments)]
fn check_r(
    m: &HaloModulator,
    e: &[f64],
    falloff: &Rings,
    e_d: f64,
    e_p: [f64; 3],
    u: i32,
    v: i32,
    gain: [u32; 3],
) -> (f64, f64) {
    let w = m.lum_widths();
    let kappa = w.kappa_value(m.kappa_code());
    let mut ctr = Counters::default();
    let out = m.kernel(&mut (), &LumIn { u, v, gain }, &mut ctr);
    let g = gain.map(|c| gain_value(&w, c));
    let (d, lum) = twin_r(
        e,
        w.shape_log2,
        kappa,
        r3(falloff),
        w.falloff_log2,
        coord_value(&w, u),
        coord_value(&w, v),
        g,
        out_max(&w),
    );
    let dk = out.d as f64 / ((1u64 << w.shape_bits) - 1) as f64;
    assert!(
        (dk - d).abs() <= e_d * (1.0 + 1e-9) + 1e-12,
        "{w:?} κ {kappa} u {u} v {v}: d {dk} want {d} (bound {e_d})"
    );
    let mut rl = 0f64;
    for c in 0..3 {
        let b = bound_lum(&w, e_p[c], gain[c]);
        let err = out.lum[c] as f64 - lum[c];
        rl = rl.max(err.abs() / b);
        assert!(
            err.abs() <= b * (1.0 + 1e-9) + 1e-9,
            "{w:?} κ {kappa} u {u} v {v} gain {gain:?}: lum[{c}] {} want {} (err {err}, bound {b})",
            out.lum[c],
            lum[c]
        );
    }
    assert_eq!(ctr.table_reads, 10);
    let one = 1i32 << w.coord_frac_bits;
    let clamps = (u.abs() >= one) as u64 + (v.abs() >= one) as u64;
    assert!(ctr.saturations >= clamps && ctr.saturations <= clamps + 4);
    assert!(ctr.underflows <= 1);
    ((dk - d).abs() / e_d, rl)
}

fn setup_r(
    cfg: usize,
    ekind: u32,
    fkind: u32,
    seed: u64,
) -> (HaloModulator, Vec<f64>, Rings, f64, [f64; 3]) {
    let w = radial_configs()[cfg];
    let kc = random_kappa(&w, seed);
    let kappa = w.kappa_value(kc);
    let e = radial_table(&w, ekind, seed, kappa);
    let falloff = rings(&w, fkind, seed);
    let m = build_r(&w, &e, &falloff, kc);
    let e_d = bound_d_radial(&w, &e, kappa);
    let e_p = [0, 1, 2].map(|c| bound_p(&w, &falloff[c], e_d));
    (m, e, falloff, e_d, e_p)
}

#[test]
fn radial_exhaustive_positions_for_the_narrow_configs() {
    for (cfg, ekind, fkind, seed) in [(2usize, 0u32, 3u32, 17u64), (3, 1, 0, 18)] {
        let (m, e, falloff, e_d, e_p) = setup_r(cfg, ekind, fkind, seed);
        let w = m.lum_widths();
        let (lo, hi) = coord_range(&w);
        let g = [w.gain_max(), w.gain_max() / 2, 1];
        let (mut rd, mut rl) = (0f64, 0f64);
        for v in lo..=hi {
            for u in lo..=hi {
                let (a, b) = check_r(&m, &e, &falloff, e_d, e_p, u, v, g);
                rd = rd.max(a);
                rl = rl.max(b);
            }
        }
        println!("radial config {cfg}: worst |err|/bound: d {rd:.3}, lum {rl:.3}");
    }
}

#[test]
fn radial_defaults_cost_and_latency() {
    let w = radial_configs()[0];
    let m = build_r(&w, &vec![0.0; w.shape_len()], &flat(&w, 1.0), 0);
    let c = m.cost();
    println!(
        "halo_modulator radial: latency {} II {} gates {:.0} NAND2, RAM bits {}",
        m.timing().latency,
        m.timing().ii,
        c.gates_nand2(),
        c.ram_bits,
    );
    assert_eq!(m.timing().latency, 15);
    assert_eq!(c.ram_bits, 129 * 129 * 16 + 3 * 257 * 16);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    #[test]
    fn radial_within_bound_random_tables_and_positions(
        cfg in 0usize..4,
        ekind in 0u32..4,
        fkind in 0u32..4,
        seed in any::<u64>(),
    ) {
        let (m, e, falloff, e_d, e_p) = setup_r(cfg, ekind, fkind, seed);
        for (u, v, g) in random_points(&m.lum_widths(), seed, 24) {
            check_r(&m, &e, &falloff, e_d, e_p, u, v, g);
        }
    }

    #[test]
    fn radial_tick_and_span_drivers_agree(
        cfg in 0usize..4,
        seed in any::<u64>(),
        n in 0usize..40,
    ) {
        let (m, ..) = setup_r(cfg, seed as u32, (seed >> 8) as u32, seed);
        let inputs: Vec<LumIn> = random_points(&m.lum_widths(), seed, n)
            .into_iter()
            .map(|(u, v, gain)| LumIn { u, v, gain })
            .collect();
        common::assert_drivers_agree(&m, (), &inputs);
    }

    #[test]
    fn radial_kappa_errors_name_the_field(
        kappa in prop_oneof![Just(f64::NAN), Just(f64::NEG_INFINITY), Just(-1.0), Just(1e6)],
    ) {
        let w = radial_configs()[2];
        let m = build_r(&w, &vec![0.0; w.shape_len()], &flat(&w, 0.5), 0);
        let e = m.with_kappa(kappa).unwrap_err();
        prop_assert_eq!(e.field(), "halo_modulator.kappa");
    }
}
