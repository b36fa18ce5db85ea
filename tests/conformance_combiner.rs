//! The `Combiner` hardware suite (NV2A captures of nxdk_pgraph_tests' combiner tests)
//! against the committed expected values: per image and feature, pixels compared,
//! exact, off by one, worse, for both chips' modes.

use glare_pipeline::conformance::combiner::{self, Modes};
use glare_pipeline::conformance::{store, Case, Chip};
use rtl_model::units::register_combiner::BiasConstant;
use rtl_model::Quant;
use std::collections::BTreeMap;

#[derive(Default, Debug, Clone, Copy)]
struct Tally {
    compared: usize,
    exact: usize,
    off1: usize,
    worse: usize,
}

fn tally(cases: &[Case], exp: &store::Expected) -> BTreeMap<(String, String), Tally> {
    let mut t: BTreeMap<(String, String), Tally> = BTreeMap::new();
    for case in cases {
        let regions = &exp.images[&case.image];
        for r in &case.regions {
            let e = regions
                .iter()
                .find(|e| e.name == r.name)
                .unwrap_or_else(|| panic!("{}: region {} not in the table", case.image, r.name));
            assert_eq!(e.rect, r.rect, "{}/{}", case.image, r.name);
            let s = t
                .entry((case.image.clone(), r.feature.clone()))
                .or_default();
            for (i, px) in e.pixels.iter().enumerate() {
                let p = r.predicted.at(i);
                let d = (0..3)
                    .map(|k| (p[k] as i32 - px[k] as i32).abs())
                    .max()
                    .unwrap();
                s.compared += 1;
                match d {
                    0 => s.exact += 1,
                    1 => s.off1 += 1,
                    _ => s.worse += 1,
                }
            }
        }
    }
    t
}

#[test]
fn nv2a_modes_match_every_patch_and_geforce2_defaults_do_not() {
    let exp = store::load("Combiner").unwrap();
    for chip in [Chip::Nv2a, Chip::GeForce2] {
        let t = tally(&combiner::cases(chip), &exp);
        let mut total = Tally::default();
        for ((img, feat), s) in &t {
            println!(
                "{chip:?} {img:28} {feat:45} compared {:6} exact {:6} off-by-one {:5} worse {:5}",
                s.compared, s.exact, s.off1, s.worse
            );
            total.compared += s.compared;
            total.exact += s.exact;
            total.off1 += s.off1;
            total.worse += s.worse;
        }
        println!("{chip:?} total {total:?}");
        if chip == Chip::Nv2a {
            assert_eq!(total.exact, total.compared, "NV2A modes: {total:?}");
        } else {
            assert!(
                total.exact < total.compared,
                "the GeForce2 defaults differ somewhere"
            );
        }
    }
}

fn sum(t: &BTreeMap<(String, String), Tally>, keep: impl Fn(&str) -> bool) -> Tally {
    let mut s = Tally::default();
    for ((img, _), x) in t {
        if keep(img) {
            s.compared += x.compared;
            s.exact += x.exact;
            s.off1 += x.off1;
            s.worse += x.worse;
        }
    }
    s
}

/// The widths and roundings no document gives (the −½ bias constant, the general
/// combiners' guard bits, the rounding of both combiner units) chosen on one half of
/// the images and checked on the other. The split: the suite's image names sorted,
/// even index calibrates (AlphaFromBlue, CombinerOps, Independence, SpecialInputs),
/// odd index validates (ColorAlphaIndependence, Flags, Mux, UnboundTexSampler).
#[test]
fn calibrated_on_half_the_images_and_validated_on_the_other() {
    let exp = store::load("Combiner").unwrap();
    let mut names: Vec<&String> = exp.images.keys().collect();
    names.sort();
    let calibrate: Vec<String> = names.iter().step_by(2).map(|s| s.to_string()).collect();
    let in_cal = |img: &str| calibrate.iter().any(|c| c == img);
    // Candidates in order of preference on a tie: the units' defaults first.
    let mut best: Option<(Modes, Tally)> = None;
    let mut rows = Vec::new();
    for bias in [BiasConstant::ExactHalf, BiasConstant::HalfCode] {
        for g in [0u32, 1, 2, 3, 4, 8] {
            for q in Quant::ALL {
                let m = Modes {
                    guard_bits: g,
                    rounding: q,
                    bias_constant: Some(bias),
                    ..Modes::of(Chip::Nv2a)
                };
                let t = tally(&combiner::cases_in(m), &exp);
                let cal = sum(&t, in_cal);
                let val = sum(&t, |i| !in_cal(i));
                rows.push((m, cal, val));
                if best.is_none_or(|(_, b)| cal.exact > b.exact) {
                    best = Some((m, cal));
                }
            }
        }
    }
    let exact_all = rows
        .iter()
        .filter(|(_, c, v)| c.exact == c.compared && v.exact == v.compared)
        .count();
    let exact_cal = rows
        .iter()
        .filter(|(_, c, _)| c.exact == c.compared)
        .count();
    println!(
        "{} candidate modes; exact on the calibration half: {exact_cal}; on both: {exact_all}",
        rows.len()
    );
    for (m, c, v) in &rows {
        if c.exact == c.compared || m.guard_bits == 0 && m.rounding == Quant::Rnd {
            println!(
                "  {:?} G {} {:?}: calibrate {c:?} validate {v:?}",
                m.bias_constant.unwrap(),
                m.guard_bits,
                m.rounding
            );
        }
    }
    let (m, cal) = best.unwrap();
    let val = rows.iter().find(|r| r.0 == m).unwrap().2;
    println!("chosen: {m:?}\n  calibration half {cal:?}\n  validation half {val:?}");
    assert_eq!(
        m.bias_constant,
        Some(BiasConstant::HalfCode),
        "the calibration picks the NV2A bias"
    );
    assert_eq!(
        cal.exact, cal.compared,
        "the calibrated modes are exact on their own half"
    );
    assert_eq!(val.exact, val.compared, "and on the other half");
}
