//! bloom_flare_modulator against its f64 twin under the width-derived bound (see
//! tests/lum_common and docs/units.md § bloom_flare_modulator), for four width
//! configs (defaults, wide, two narrow), random smooth and rough tables, random
//! positions including the clamp region; exhaustive over (u, v) for the narrow
//! configs; drivers agree; config and host-edge errors name the field.

mod common;
mod lum_common;

use glare_pipeline::reference::bloom_flare_modulator::bloom_flare_modulator as twin;
use lum_common::*;
use proptest::prelude::*;
use rtl_model::units::bloom_flare_modulator::{
    BloomFlareModulator, BloomFlareModulatorConfig, LumIn,
};
use rtl_model::units::luminance_ram::{LumWidths, PlainPath};
use rtl_model::{Counters, Unit};

fn build(w: &LumWidths, shape: &[f64], falloff: &[f64]) -> BloomFlareModulator {
    BloomFlareModulatorConfig::from_widths(*w)
        .build(shape, falloff)
        .unwrap()
}

/// Check one pixel against the twin; returns the largest |err|/bound of d and lum.
#[allow(clippy::too_many_arguments)]
fn check(
    m: &BloomFlareModulator,
    shape: &[f64],
    falloff: &[f64],
    e_d: f64,
    e_p: f64,
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
        falloff,
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
        let b = bound_lum(&w, e_p, gain[c]);
        let err = out.lum[c] as f64 - lum[c];
        rl = rl.max(err.abs() / b);
        assert!(
            err.abs() <= b * (1.0 + 1e-9) + 1e-9,
            "{w:?} u {u} v {v} gain {gain:?}: lum[{c}] {} want {} (err {err}, bound {b})",
            out.lum[c],
            lum[c]
        );
    }
    assert_eq!(ctr.table_reads, 6);
    let one = 1i32 << w.coord_frac_bits;
    let clamps = (u.abs() >= one) as u64 + (v.abs() >= one) as u64;
    assert!(ctr.saturations >= clamps && ctr.saturations <= clamps + 3);
    ((dk - d).abs() / e_d, rl)
}

fn run_case(cfg: usize, skind: u32, fkind: u32, seed: u64, npts: usize) {
    let w = configs()[cfg];
    let shape = shape_table(&w, skind, seed);
    let falloff = falloff_table(&w, fkind, seed);
    let m = build(&w, &shape, &falloff);
    let e_d = bound_d(&w, &shape);
    let e_p = bound_p(&w, &falloff, e_d);
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
        let falloff = falloff_table(&w, fkind, 7);
        let m = build(&w, &shape, &falloff);
        let e_d = bound_d(&w, &shape);
        let e_p = bound_p(&w, &falloff, e_d);
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
    let m = build(&w, &vec![0.0; w.shape_len()], &vec![1.0; w.falloff_len()]);
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
    let m = build(&w, &vec![0.0; w.shape_len()], &vec![1.0; w.falloff_len()]);
    let c = m.cost();
    println!(
        "bloom_flare_modulator defaults: latency {} II {} gates {:.0} NAND2, RAM bits {}, table words {}",
        m.timing().latency,
        m.timing().ii,
        c.gates_nand2(),
        c.ram_bits,
        m.table_words()
    );
    for (n, g) in &c.breakdown {
        println!("  {n}: {g:.0}");
    }
    assert_eq!(c.ram_bits, 129 * 129 * 16 + 257 * 16);
    assert_eq!(m.table_words(), 129 * 129 + 257);
}

#[test]
fn wire_masking_matches_the_masked_input() {
    let w = configs()[2];
    let shape = shape_table(&w, 1, 3);
    let falloff = falloff_table(&w, 1, 3);
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

#[test]
fn batch_fast_form_agrees_exhaustively_on_a_narrow_config() {
    // The batch kernel's fast form (PlainPath) is taken by configs 0 and 2 and refused
    // by 1 (its gain product needs more than 64 bits) and 3 (coordinates coarser than
    // the grid), which run the per-word kernel: the proptest below covers all four.
    assert!(PlainPath::new(&configs()[0]).is_some());
    assert!(PlainPath::new(&configs()[1]).is_none());
    assert!(PlainPath::new(&configs()[3]).is_none());
    // Config 2: every (u, v) of the 10-bit wires (2²⁰ words, the clamp region
    // included), with gains sweeping the 4-bit gain code per channel.
    let w = configs()[2];
    assert!(PlainPath::new(&w).is_some());
    for (skind, fkind) in [(1u32, 1u32), (3, 2)] {
        let m = build(
            &w,
            &shape_table(&w, skind, 11),
            &falloff_table(&w, fkind, 11),
        );
        let (lo, hi) = coord_range(&w);
        let g = w.gain_max();
        let inputs: Vec<LumIn> = (lo..=hi)
            .flat_map(|v| {
                (lo..=hi).map(move |u| LumIn {
                    u,
                    v,
                    gain: [u as u32 & g, v as u32 & g, (u ^ v) as u32 & g],
                })
            })
            .collect();
        common::assert_drivers_agree(&m, (), &inputs);
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
        let m = build(&w, &shape_table(&w, seed as u32, seed), &falloff_table(&w, (seed >> 8) as u32, seed));
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
        let cfg = BloomFlareModulatorConfig {
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
            let e = cfg.build(&[0.5], &vec![0.5; w.falloff_len()]).unwrap_err();
            prop_assert_eq!(e.field(), "bloom_flare_modulator.shape");
            if k <= 5 {
                let r = cfg.build(&vec![0.5; w.shape_len()], &vec![0.5; w.falloff_len()]);
                prop_assert!(r.is_ok());
                let e = cfg.build(&vec![0.5; w.shape_len()], &[]).unwrap_err();
                prop_assert_eq!(e.field(), "bloom_flare_modulator.falloff");
            }
        } else {
            let e = cfg.build(&[], &[]).unwrap_err();
            let field = e.field().to_string();
            prop_assert!(
                bad.iter().any(|b| field == format!("bloom_flare_modulator.{b}")),
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
        let cfg = BloomFlareModulatorConfig::from_widths(w);
        let mut shape = vec![0.25; w.shape_len()];
        let i = idx.index(shape.len());
        shape[i] = x;
        let e = cfg.build(&shape, &vec![0.5; w.falloff_len()]).unwrap_err();
        prop_assert_eq!(e.field(), format!("bloom_flare_modulator.shape[{i}]"));
        let mut fo = vec![0.25; w.falloff_len()];
        let j = idx.index(fo.len());
        fo[j] = x;
        let e = cfg.build(&vec![0.5; w.shape_len()], &fo).unwrap_err();
        prop_assert_eq!(e.field(), format!("bloom_flare_modulator.falloff[{j}]"));
        let m = cfg.build(&vec![0.5; w.shape_len()], &vec![0.5; w.falloff_len()]).unwrap();
        let mut gains = [1.0; 3];
        gains[c] = g;
        let e = m.gain_from_f64(gains).unwrap_err();
        prop_assert_eq!(e.field(), format!("bloom_flare_modulator.gain[{c}]"));
        if x.is_nan() || x.is_infinite() {
            let e = m.coord_from_f64(x).unwrap_err();
            prop_assert_eq!(e.field(), "bloom_flare_modulator.coord");
        }
    }

    #[test]
    fn coord_from_f64_rounds_and_saturates(x in -3.0f64..3.0) {
        static M: std::sync::OnceLock<BloomFlareModulator> = std::sync::OnceLock::new();
        let w = LumWidths::default();
        let m = M.get_or_init(|| build(&w, &vec![0.0; w.shape_len()], &vec![1.0; w.falloff_len()]));
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

use glare_pipeline::reference::bloom_flare_modulator::bloom_flare_modulator_radial as twin_r;

fn build_r(w: &LumWidths, e: &[f64], falloff: &[f64], kappa: u32) -> BloomFlareModulator {
    BloomFlareModulatorConfig::from_widths(*w)
        .build(e, falloff)
        .unwrap()
        .with_kappa(w.kappa_value(kappa))
        .unwrap()
}

#[allow(clippy::too_many_arguments)]
fn check_r(
    m: &BloomFlareModulator,
    e: &[f64],
    falloff: &[f64],
    e_d: f64,
    e_p: f64,
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
        falloff,
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
        let b = bound_lum(&w, e_p, gain[c]);
        let err = out.lum[c] as f64 - lum[c];
        rl = rl.max(err.abs() / b);
        assert!(
            err.abs() <= b * (1.0 + 1e-9) + 1e-9,
            "{w:?} κ {kappa} u {u} v {v} gain {gain:?}: lum[{c}] {} want {} (err {err}, bound {b})",
            out.lum[c],
            lum[c]
        );
    }
    assert_eq!(ctr.table_reads, 6);
    let one = 1i32 << w.coord_frac_bits;
    let clamps = (u.abs() >= one) as u64 + (v.abs() >= one) as u64;
    assert!(ctr.saturations >= clamps && ctr.saturations <= clamps + 4);
    assert!(ctr.underflows <= 1);
    ((dk - d).abs() / e_d, rl)
}

fn run_case_r(cfg: usize, ekind: u32, fkind: u32, seed: u64, npts: usize) {
    let w = radial_configs()[cfg];
    let kc = random_kappa(&w, seed);
    let kappa = w.kappa_value(kc);
    let e = radial_table(&w, ekind, seed, kappa);
    let falloff = falloff_table(&w, fkind, seed);
    let m = build_r(&w, &e, &falloff, kc);
    let e_d = bound_d_radial(&w, &e, kappa);
    let e_p = bound_p(&w, &falloff, e_d);
    for (u, v, g) in random_points(&w, seed, npts) {
        check_r(&m, &e, &falloff, e_d, e_p, u, v, g);
    }
}

#[test]
fn radial_exhaustive_positions_for_the_narrow_configs() {
    // Config 2: F = 8 → 2²⁰ positions; config 3: F = 2 → 2⁸.
    for (cfg, ekind, fkind, seed) in [(2usize, 1u32, 1u32, 7u64), (3, 0, 2, 8), (3, 3, 1, 9)] {
        let w = radial_configs()[cfg];
        let kc = w.kappa_max() - (seed % 2) as u32; // large κ: d is not all clamped
        let kappa = w.kappa_value(kc);
        let e = radial_table(&w, ekind, seed, kappa);
        let falloff = falloff_table(&w, fkind, seed);
        let m = build_r(&w, &e, &falloff, kc);
        let e_d = bound_d_radial(&w, &e, kappa);
        let e_p = bound_p(&w, &falloff, e_d);
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
fn radial_cone_is_exact_at_a_shallow_depth() {
    // A point source: sdf_n = κ·|(u, v)|, so e = 0 and the radial mode reproduces the
    // cone to the width terms at k = 2, where the plain bilinear table is far off.
    let mut w = LumWidths {
        shape_log2: 2,
        ..LumWidths::default()
    };
    let kappa = 0.7;
    let plain_tab: Vec<f64> = (0..w.shape_len())
        .map(|i| {
            let s = w.shape_side();
            let c = |i: usize| -1.0 + 2.0 * i as f64 / (s - 1) as f64;
            (kappa * c(i % s).hypot(c(i / s))).min(1.0)
        })
        .collect();
    let fall: Vec<f64> = (0..w.falloff_len())
        .map(|j| j as f64 / (w.falloff_len() - 1) as f64)
        .collect();
    let plain = build(&w, &plain_tab, &fall);
    w.radial.on = true;
    let kc = w.kappa_from_f64("t", kappa).unwrap();
    let rad = build_r(&w, &vec![0.0; w.shape_len()], &fall, kc);
    let kq = w.kappa_value(kc);
    let bound = bound_d_radial(&w, &vec![0.0; w.shape_len()], kq);
    let (mut ep, mut er) = (0f64, 0f64);
    let mut ctr = Counters::default();
    let lsb = ((1u64 << w.shape_bits) - 1) as f64;
    for (u, v, gain) in random_points(&w, 3, 4000) {
        let (uf, vf) = (coord_value(&w, u), coord_value(&w, v));
        let truth = (kq * uf.clamp(-1.0, 1.0).hypot(vf.clamp(-1.0, 1.0))).min(1.0);
        let i = LumIn { u, v, gain };
        ep = ep.max((plain.kernel(&mut (), &i, &mut ctr).d as f64 / lsb - truth).abs());
        er = er.max((rad.kernel(&mut (), &i, &mut ctr).d as f64 / lsb - truth).abs());
    }
    println!("cone at k = 2: plain max |d err| {ep:.2e}, radial {er:.2e} (bound {bound:.2e})");
    assert!(er <= bound && ep > 100.0 * er);
}

#[test]
fn radial_defaults_cost_latency_and_ram_bits() {
    let off = LumWidths::default();
    assert!(!off.radial.on);
    let w = radial_configs()[0];
    let m = build_r(
        &w,
        &vec![0.0; w.shape_len()],
        &vec![1.0; w.falloff_len()],
        0,
    );
    let m0 = build(
        &off,
        &vec![0.0; off.shape_len()],
        &vec![1.0; off.falloff_len()],
    );
    let c = m.cost();
    println!(
        "bloom_flare_modulator radial: latency {} II {} gates {:.0} NAND2 (off {:.0}), RAM bits {}",
        m.timing().latency,
        m.timing().ii,
        c.gates_nand2(),
        m0.cost().gates_nand2(),
        c.ram_bits,
    );
    for (n, g) in &c.breakdown {
        println!("  {n}: {g:.0}");
    }
    assert_eq!(m0.timing().latency, 6);
    assert_eq!(m.timing().latency, 6 + 9);
    assert_eq!(c.ram_bits, m0.cost().ram_bits);
    assert_eq!(m.widths().len(), m0.widths().len() + 4);
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
        run_case_r(cfg, ekind, fkind, seed, 24);
    }

    #[test]
    fn radial_tick_and_span_drivers_agree(
        cfg in 0usize..4,
        seed in any::<u64>(),
        n in 0usize..40,
    ) {
        let w = radial_configs()[cfg];
        let kc = random_kappa(&w, seed);
        let m = build_r(
            &w,
            &radial_table(&w, seed as u32, seed, w.kappa_value(kc)),
            &falloff_table(&w, (seed >> 8) as u32, seed),
            kc,
        );
        let inputs: Vec<LumIn> = random_points(&w, seed, n)
            .into_iter()
            .map(|(u, v, gain)| LumIn { u, v, gain })
            .collect();
        common::assert_drivers_agree(&m, (), &inputs);
    }

    #[test]
    fn radial_configs_and_kappa_errors_name_the_field(
        sb in 1u32..17, rf in 0u32..18, ki in 0u32..10, kf in 0u32..18, ei in 0u32..6,
        kappa in prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(-0.5), Just(1e6), 0.0f64..4.0],
        x in prop_oneof![Just(f64::NAN), Just(-1e3), Just(1e3), Just(f64::NEG_INFINITY)],
        idx in any::<prop::sample::Index>(),
    ) {
        let w = LumWidths {
            shape_log2: 2,
            shape_bits: sb,
            radial: rtl_model::units::luminance_ram::Radial {
                on: true,
                radius_frac_bits: rf,
                kappa_int_bits: ki,
                kappa_frac_bits: kf,
                entry_int_bits: ei,
            },
            ..LumWidths::default()
        };
        let cfg = BloomFlareModulatorConfig::from_widths(w);
        let mut bad = Vec::new();
        if !(2..=16).contains(&rf) { bad.push("radius_frac_bits"); }
        if ki > 8 { bad.push("kappa_int_bits"); }
        if kf > 16 || ki + kf == 0 { bad.push("kappa_frac_bits"); }
        if ei > 4 || ei + 1 > sb { bad.push("entry_int_bits"); }
        let fall = vec![0.5; w.falloff_len()];
        if bad.is_empty() {
            let mut e = vec![0.0; w.shape_len()];
            let i = idx.index(e.len());
            e[i] = x;
            let err = cfg.build(&e, &fall).unwrap_err();
            prop_assert_eq!(err.field(), format!("bloom_flare_modulator.shape[{i}]"));
            let m = cfg.build(&vec![0.0; w.shape_len()], &fall).unwrap();
            let max = w.kappa_value(w.kappa_max());
            match m.with_kappa(kappa) {
                Ok(m) => prop_assert!(kappa >= 0.0 && (w.kappa_value(m.kappa_code()) - kappa).abs()
                    <= 0.5 / 2f64.powi(kf as i32) + 1e-12),
                Err(e) => {
                    prop_assert_eq!(e.field(), "bloom_flare_modulator.kappa");
                    prop_assert!(!kappa.is_finite() || kappa < 0.0 || kappa > max);
                }
            }
        } else {
            let e = cfg.build(&[], &[]).unwrap_err();
            let field = e.field().to_string();
            prop_assert!(
                bad.iter().any(|b| field == format!("bloom_flare_modulator.{b}")),
                "{} not in {:?}", field, bad
            );
        }
    }
}
