//! glare_condition against its f64 twin (SPEC B, Table 2).
//!
//! Bound, derived from the widths (docs/units.md § glare_condition): I_ps as a
//! u(ib).(fb) code has error E (in 2^−fb units)
//!   metallic: E = ½ (I_s replicated to u1.W, W = max(cb, ib+fb+1): I·cos²α·2^−W
//!             < 2^(ib+fb−W) ≤ ½) + ½ (rounding) = 1
//!   water:    E = ½ (rounding only; I·cos α is exact before it)
//! The output i_ps = min(round(I_ps), 2^out − 1) is within ½·[fb > 0] + E·2^−fb of
//! min(I_ps, 2^out − 1) (min is 1-Lipschitz). T·I_a is exact, so contrast_ok (and so
//! glare) equals the twin's except when |I_ps − T·I_a| ≤ E·2^−fb (the band).
//! TIR is an exact integer comparison; the twin's f64 margin may only be wrong within
//! f64 rounding (|margin| ≤ 2^−46), where it is not compared.
//! Four width configs (defaults, wide, two narrow), exhaustive for the narrow ones.

mod common;

use glare_pipeline::reference::glare_condition::{glare_condition as twin, Material as TM};
use proptest::prelude::*;
use rtl_model::units::glare_condition::{
    ConditionIn, GlareCondition, GlareConditionConfig, Material,
};
use rtl_model::{Counters, Unit};

fn configs() -> Vec<GlareConditionConfig> {
    let d = GlareConditionConfig::default();
    vec![
        d,
        GlareConditionConfig {
            int_bits: 16,
            frac_bits: 16,
            coef_bits: 16,
            cos_frac_bits: 16,
            eta: 1.5,
            eta_frac_bits: 16,
            threshold: 40,
            out_bits: 16,
        },
        GlareConditionConfig {
            int_bits: 3,
            frac_bits: 1,
            coef_bits: 2,
            cos_frac_bits: 2,
            eta: 1.25,
            eta_frac_bits: 2,
            threshold: 3,
            out_bits: 2,
        },
        GlareConditionConfig {
            int_bits: 5,
            frac_bits: 0,
            coef_bits: 3,
            cos_frac_bits: 3,
            eta: 2.5,
            eta_frac_bits: 3,
            threshold: 5,
            out_bits: 3,
        },
    ]
}

/// I_ps code error bound E in 2^−fb units.
fn e_ips(m: Material) -> f64 {
    match m {
        Material::Metallic => 1.0,
        Material::Water => 0.5,
    }
}

fn check(u: &GlareCondition, x: &ConditionIn) {
    let c = u.config();
    let iw = c.int_bits + c.frac_bits;
    let lsb = (-(c.frac_bits as f64)).exp2();
    let cos = |v: i32| {
        let w = c.cos_frac_bits + 1;
        (((v as i64) << (64 - w)) >> (64 - w)) as f64 / (c.cos_frac_bits as f64).exp2()
    };
    let mask = |b: u32| (1u64 << b) - 1;
    let i = (x.intensity as u64 & mask(iw)) as f64 * lsb;
    let ia = (x.ambient as u64 & mask(iw)) as f64 * lsb;
    let is = (x.specular as u64 & mask(c.coef_bits)) as f64 / mask(c.coef_bits) as f64;
    let out_max = mask(c.out_bits) as f64;
    let mat = match x.material {
        Material::Metallic => TM::Metallic,
        Material::Water => TM::Water,
    };
    let t = twin(
        mat,
        i,
        is,
        cos(x.cos_alpha),
        cos(x.cos_theta),
        ia,
        u.eta_value(),
        c.threshold as f64,
        out_max,
    );
    let mut ctr = Counters::default();
    let o = u.kernel(&mut (), x, &mut ctr);
    let e = e_ips(x.material) * lsb;
    let half = if c.frac_bits > 0 { 0.5 } else { 0.0 };
    let bound = half + e;
    let err = o.i_ps as f64 - t.i_ps;
    assert!(
        err.abs() <= bound + 1e-9,
        "{c:?} {x:?}: i_ps {} want {} (bound {bound})",
        o.i_ps,
        t.i_ps
    );
    // A saturation is counted exactly when round(I_ps) > out_max.
    assert!(ctr.saturations <= 1);
    if ctr.saturations == 1 {
        assert_eq!(o.i_ps as f64, out_max);
    }
    if t.i_ps_raw > out_max + bound + 1e-9 {
        assert_eq!(ctr.saturations, 1, "{x:?}");
    }
    if t.i_ps_raw < out_max - bound {
        assert_eq!(ctr.saturations, 0, "{x:?}");
    }
    let in_band = (t.i_ps_raw - c.threshold as f64 * ia).abs() <= e + 1e-12;
    if !in_band {
        assert_eq!(o.contrast_ok, t.contrast_ok, "{c:?} {x:?}: contrast {t:?}");
    }
    match x.material {
        Material::Metallic => assert!(!o.tir),
        Material::Water => {
            if t.tir_margin.abs() > 2f64.powi(-46) {
                assert_eq!(o.tir, t.tir, "{c:?} {x:?}: tir {t:?}");
            }
        }
    }
    assert_eq!(
        o.glare,
        o.contrast_ok && (x.material == Material::Metallic || o.tir)
    );
    if !in_band && t.tir_margin.abs() > 2f64.powi(-46) {
        assert_eq!(o.glare, t.glare, "{c:?} {x:?}: glare {t:?}");
    }
}

#[test]
fn exhaustive_narrow_configs() {
    for ci in [2usize, 3] {
        for eta in [0.75, 1.0, 1.333, 2.5, 3.75] {
            let u = GlareConditionConfig {
                eta,
                ..configs()[ci]
            }
            .build()
            .unwrap();
            let c = u.config();
            let iw = c.int_bits + c.frac_bits;
            let half = 1i32 << c.cos_frac_bits;
            for i in 0..(1u32 << iw) {
                for ia in 0..(1u32 << iw) {
                    for ca in -half..half {
                        for s in 0..(1u32 << c.coef_bits) {
                            check(
                                &u,
                                &ConditionIn {
                                    material: Material::Metallic,
                                    intensity: i,
                                    specular: s,
                                    cos_alpha: ca,
                                    cos_theta: 0,
                                    ambient: ia,
                                },
                            );
                        }
                        for ct in -half..half {
                            check(
                                &u,
                                &ConditionIn {
                                    material: Material::Water,
                                    intensity: i,
                                    specular: 0,
                                    cos_alpha: ca,
                                    cos_theta: ct,
                                    ambient: ia,
                                },
                            );
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn table2_examples_at_defaults() {
    let u = GlareCondition::geforce();
    let q = |m, i, s, ca, ct, ia| u.input_from_f64(m, i, s, ca, ct, ia).unwrap();
    let mut c = Counters::default();
    // Bright metallic highlight against a dim ambient: glare, saturated at 255.
    let o = u.kernel(
        &mut (),
        &q(Material::Metallic, 3000.0, 1.0, 0.99, 0.0, 10.0),
        &mut c,
    );
    assert!(o.glare && o.contrast_ok && !o.tir);
    assert_eq!(o.i_ps, 255);
    assert_eq!(c.saturations, 1);
    // The same against a bright ambient: contrast < 40, no glare.
    let o = u.kernel(
        &mut (),
        &q(Material::Metallic, 3000.0, 1.0, 0.99, 0.0, 100.0),
        &mut c,
    );
    assert!(!o.glare && !o.contrast_ok);
    // Water at grazing incidence (cos θ = 0.3, η = 1.333): TIR, glare.
    let o = u.kernel(
        &mut (),
        &q(Material::Water, 2000.0, 0.0, 0.9, 0.3, 10.0),
        &mut c,
    );
    assert!(o.tir && o.glare);
    // Water at normal incidence: no TIR, no glare although the contrast is there.
    let o = u.kernel(
        &mut (),
        &q(Material::Water, 2000.0, 0.0, 0.9, 0.95, 10.0),
        &mut c,
    );
    assert!(!o.tir && o.contrast_ok && !o.glare);
    // cos α < 0: no highlight.
    let o = u.kernel(
        &mut (),
        &q(Material::Water, 2000.0, 0.0, -0.5, 0.3, 0.0),
        &mut c,
    );
    assert_eq!(o.i_ps, 0);
    println!(
        "glare_condition defaults: latency {} II {} gates {:.0} NAND2, RAM bits {}",
        u.timing().latency,
        u.timing().ii,
        u.cost().gates_nand2(),
        u.cost().ram_bits
    );
    for (n, g) in &u.cost().breakdown {
        println!("  {n}: {g:.0}");
    }
}

fn arb_input(ci: usize) -> impl Strategy<Value = (f64, ConditionIn)> {
    let c = configs()[ci];
    let iw = c.int_bits + c.frac_bits;
    let imax = (1u64 << iw) - 1;
    let half = 1i64 << c.cos_frac_bits;
    (
        -1.0f64..4.0,
        any::<bool>(),
        0..=imax,
        any::<u32>(),
        -half..half,
        -half..half,
        0..=imax,
        any::<bool>(),
        -2i64..=2,
    )
        .prop_map(move |(eta, water, i, s, ca, ct, ia, near, dia)| {
            let material = if water {
                Material::Water
            } else {
                Material::Metallic
            };
            let s = s & ((1u32 << c.coef_bits) - 1);
            // Near the threshold: I_a ≈ I_ps / T (± 2 codes).
            let ia = if near && c.threshold > 0 {
                let a = (ca.max(0) as f64) / half as f64;
                let is = s as f64 / ((1u64 << c.coef_bits) - 1) as f64;
                let ips = match material {
                    Material::Metallic => i as f64 * is * a * a,
                    Material::Water => i as f64 * a,
                };
                ((ips / c.threshold as f64).round() as i64 + dia).clamp(0, imax as i64) as u64
            } else {
                ia
            };
            (
                eta,
                ConditionIn {
                    material,
                    intensity: i as u32,
                    specular: s,
                    cos_alpha: ca as i32,
                    cos_theta: ct as i32,
                    ambient: ia as u32,
                },
            )
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    #[test]
    fn within_bound_defaults(x in arb_input(0)) {
        let u = GlareConditionConfig { eta: x.0.abs().min(3.9), ..configs()[0] }.build().unwrap();
        check(&u, &x.1);
    }

    #[test]
    fn within_bound_wide(x in arb_input(1)) {
        let u = GlareConditionConfig { eta: x.0.abs().min(3.9), ..configs()[1] }.build().unwrap();
        check(&u, &x.1);
    }

    #[test]
    fn within_bound_narrow(x in arb_input(2)) {
        let u = GlareConditionConfig { eta: x.0.abs().min(3.5), ..configs()[2] }.build().unwrap();
        check(&u, &x.1);
    }

    #[test]
    fn wire_masking_and_drivers_agree(ci in 0usize..4, xs in prop::collection::vec(arb_input(0), 0..30)) {
        let u = configs()[ci].build().unwrap();
        let inputs: Vec<ConditionIn> = xs.into_iter().map(|(_, x)| x).collect();
        common::assert_drivers_agree(&u, (), &inputs);
        // Junk above the wire widths is ignored (inputs above are default-width codes).
        let c = u.config();
        let iw = c.int_bits + c.frac_bits;
        let mut ctr = Counters::default();
        for x in &inputs {
            let masked = ConditionIn {
                intensity: (x.intensity as u64 & ((1u64 << iw) - 1)) as u32,
                ambient: (x.ambient as u64 & ((1u64 << iw) - 1)) as u32,
                specular: x.specular & ((1u32 << c.coef_bits) - 1),
                cos_alpha: ((x.cos_alpha << (31 - c.cos_frac_bits)) >> (31 - c.cos_frac_bits)),
                cos_theta: ((x.cos_theta << (31 - c.cos_frac_bits)) >> (31 - c.cos_frac_bits)),
                ..*x
            };
            prop_assert_eq!(u.kernel(&mut (), x, &mut ctr), u.kernel(&mut (), &masked, &mut ctr));
        }
    }

    #[test]
    fn random_configs_never_panic_and_errors_name_the_field(
        ib in 0u32..20, fb in 0u32..20, cb in 0u32..20, cf in 0u32..20, ef in 0u32..20,
        t in prop_oneof![0u32..100, any::<u32>()], ob in 0u32..20,
        eta in prop_oneof![-1.0f64..5.0, Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY)],
    ) {
        let cfg = GlareConditionConfig {
            int_bits: ib, frac_bits: fb, coef_bits: cb, cos_frac_bits: cf, eta,
            eta_frac_bits: ef, threshold: t, out_bits: ob,
        };
        let mut bad = Vec::new();
        if ib > 16 { bad.push("int_bits"); }
        if fb > 16 || ib + fb == 0 { bad.push("frac_bits"); }
        if !(1..=16).contains(&cb) { bad.push("coef_bits"); }
        if !(1..=16).contains(&cf) { bad.push("cos_frac_bits"); }
        if !(1..=16).contains(&ef) { bad.push("eta_frac_bits"); }
        if t > 65535 { bad.push("threshold"); }
        if !(1..=16).contains(&ob) { bad.push("out_bits"); }
        let eta_ok = eta.is_finite() && (1..=16).contains(&ef)
            && eta * (ef as f64).exp2() > -0.5 && (eta * (ef as f64).exp2()).round() < (1u64 << (ef + 2)) as f64;
        if !eta_ok { bad.push("eta"); }
        match cfg.build() {
            Ok(_) => prop_assert!(bad.is_empty(), "accepted {:?}", bad),
            Err(e) => {
                let f = e.field().to_string();
                prop_assert!(bad.iter().any(|b| f == format!("glare_condition.{b}")), "{} not in {:?}", f, bad);
            }
        }
    }

    #[test]
    fn host_edge_nan_names_the_field(which in 0usize..5, x in prop_oneof![Just(f64::NAN), Just(f64::INFINITY)]) {
        let u = GlareCondition::geforce();
        let mut v = [100.0, 0.5, 0.5, 0.5, 1.0];
        v[which] = x;
        let e = u.input_from_f64(Material::Water, v[0], v[1], v[2], v[3], v[4]).unwrap_err();
        let names = ["intensity", "specular", "cos_alpha", "cos_theta", "ambient"];
        prop_assert_eq!(e.field(), format!("glare_condition.{}", names[which]));
    }
}
