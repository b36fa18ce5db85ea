//! additive_blend against its f64 twin: exhaustive where a channel's input space is
//! ≤ 2²⁰, property tests (≥ 1 000 cases) at 8→8, 8→16, 8→10, 8→12 and a narrow 3→2,
//! weighted and unweighted, plus random configs; thousands of blended planes.
//!
//! Error bound, in framebuffer LSBs (f = fb_bits, s = src_bits, k = weight_bits,
//! M_x = 2ˣ − 1). The twin's value is min(d + c, M_f) with the ideal contribution
//! c = s/M_s · w/M_w · M_f (w/M_w = 1 unweighted); the unit's is min(d + q, M_f).
//! min(·, M_f) is 1-Lipschitz and the add is exact, so |unit − twin| ≤ |q − c|:
//!
//! * alignment a = align(s): e_align = 0 if f is a multiple of s (replication is then
//!   exactly s·M_f/M_s), < 1 if f > s (replication = ⌊2ᶠ·s/M_s⌋ for s < M_s, so
//!   a − s·M_f/M_s = s/M_s − frac(2ᶠ·s/M_s) ∈ (−1, 1); exact at s = M_s), ≤ ½ if
//!   f < s (round to nearest);
//! * weight rounding q = round(a·w/M_w): e_round = ½ (k ≥ 2; ties cannot occur since
//!   M_w is odd) or 0 (k = 1: w ∈ {0, 1}, exact); unweighted 0;
//! * |q − c| ≤ |q − a·w/M_w| + (w/M_w)·|a − s·M_f/M_s| ≤ e_round + (w/M_w)·e_align.
//!
//! Saturation is exact on both sides (both clamp at M_f). Over k planes of equal
//! contribution the same Lipschitz argument gives |unit − twin| ≤ k·(e_round + (w/M_w)·e_align).
//! The only slack in the assertions is 1e-9 LSB for the f64 twin's own rounding.

mod common;

use glare_pipeline::reference::additive_blend::{
    accumulate_planes, additive_blend, additive_blend_codes, contribution_codes, unorm_value,
};
use proptest::prelude::*;
use rtl_model::memory::bytes_for_bits;
use rtl_model::units::additive_blend::{
    round_div_mersenne, AdditiveBlend, AdditiveBlendConfig, AdditiveBlendIn,
};
use rtl_model::unorm::{max_code, narrow};
use rtl_model::{Counters, Unit, UnitSummary};

const SLACK: f64 = 1e-9;

fn blend(src_bits: u32, fb_bits: u32, weighted: bool, weight_bits: u32) -> AdditiveBlend {
    AdditiveBlend::new(src_bits, fb_bits, 4, weighted, weight_bits).unwrap()
}

/// Alignment error bound in fb LSBs (see the file header).
fn e_align(b: &AdditiveBlend) -> f64 {
    let (s, f) = (b.src_bits(), b.fb_bits());
    if f % s == 0 {
        0.0
    } else if f > s {
        1.0
    } else {
        0.5
    }
}

/// Weight rounding error bound in fb LSBs.
fn e_round(b: &AdditiveBlend) -> f64 {
    if b.weighted() && b.weight_bits() >= 2 {
        0.5
    } else {
        0.0
    }
}

/// The per-add bound e_round + (w/M_w)·e_align, fb LSBs.
fn bound(b: &AdditiveBlend, w: u32) -> f64 {
    let wfrac = if b.weighted() {
        unorm_value(w & b.weight_max(), b.weight_bits())
    } else {
        1.0
    };
    e_round(b) + wfrac * e_align(b)
}

fn twin_weight(b: &AdditiveBlend, w: u32) -> Option<(u32, u32)> {
    b.weighted()
        .then_some((w & b.weight_max(), b.weight_bits()))
}

/// Check one channel against the twin (and the contribution alone against the ideal).
fn check(b: &AdditiveBlend, src: u32, dst: u32, w: u32) {
    let (got, sat, _) = b.blend_channel(src, dst, w);
    let q = b.contribution(src, w);
    let tw = twin_weight(b, w);
    let want = additive_blend_codes(src, dst, b.src_bits(), b.fb_bits(), tw);
    let ideal_c = contribution_codes(src, b.src_bits(), b.fb_bits(), tw);
    let lim = bound(b, w) + SLACK;
    let cfg = b.config();
    assert!(
        (got as f64 - want).abs() <= lim,
        "{cfg:?}: src {src} dst {dst} w {w} → {got}, twin {want}, bound {lim}"
    );
    assert!(
        (q as f64 - ideal_c).abs() <= lim,
        "{cfg:?}: contribution of src {src} w {w} = {q}, ideal {ideal_c}, bound {lim}"
    );
    // Exact integer semantics: min(d + q, M_f), clamp flagged iff d + q > M_f.
    let d = dst & b.fb_max();
    assert_eq!(got, (d + q).min(b.fb_max()));
    assert_eq!(sat, d + q > b.fb_max());
}

#[test]
fn default_is_min_s_plus_d_for_all_65536_pairs() {
    let b = AdditiveBlend::geforce();
    for s in 0..=255u32 {
        for d in 0..=255u32 {
            let (got, sat, under) = b.blend_channel(s, d, 0);
            assert_eq!(got, (s + d).min(255), "{s}+{d}");
            assert_eq!(sat, s + d > 255);
            assert!(!under);
        }
    }
}

#[test]
fn within_bound_exhaustively_where_space_is_at_most_2_pow_20() {
    // (src, fb, weighted, weight_bits): every (src, dst[, w]) combination.
    let full = [
        (8, 8, false, 8),  // 2^16
        (8, 10, false, 8), // 2^18
        (8, 12, false, 8), // 2^20
        (3, 2, false, 8),  // 2^5
        (3, 2, true, 8),   // 2^13
        (4, 4, true, 4),   // 2^12
        (5, 7, true, 8),   // 2^20
        (6, 3, true, 11),  // 2^20
        (2, 16, true, 2),  // 2^20
        (16, 4, false, 8), // 2^20
        (3, 12, true, 5),  // 2^20
    ];
    for (s, f, wtd, k) in full {
        let b = blend(s, f, wtd, k);
        let ws = if wtd { max_code(k) } else { 0 };
        for src in 0..=max_code(s) {
            for dst in 0..=max_code(f) {
                for w in 0..=ws {
                    check(&b, src, dst, w);
                }
            }
        }
    }
    // Larger spaces: every (src, w), dst at the interesting points.
    for (s, f, wtd, k) in [
        (8, 8, true, 8),
        (8, 16, false, 8),
        (8, 16, true, 8),
        (8, 10, true, 8),
    ] {
        let b = blend(s, f, wtd, k);
        let m = b.fb_max();
        let ws = if wtd { max_code(k) } else { 0 };
        for src in 0..=max_code(s) {
            for w in 0..=ws {
                for dst in [0, 1, m / 2, m - 300.min(m), m - 1, m] {
                    check(&b, src, dst, w);
                }
            }
        }
    }
}

#[test]
fn alignment_within_bound_for_every_width_pair_and_code() {
    for s in 1..=16u32 {
        for f in 1..=16u32 {
            let b = blend(s, f, false, 8);
            let lim = e_align(&b) + SLACK;
            for src in 0..=max_code(s) {
                let q = b.contribution(src, 0) as f64;
                let ideal = contribution_codes(src, s, f, None);
                assert!(
                    (q - ideal).abs() <= lim,
                    "{s}→{f}: {src} → {q}, ideal {ideal}"
                );
                if f > s && f % s != 0 {
                    assert!((q - ideal).abs() < 1.0, "replication error must be < 1 LSB");
                }
            }
            assert_eq!(b.contribution(max_code(s), 0), max_code(f), "1.0 stays 1.0");
            assert_eq!(b.contribution(0, 0), 0);
        }
    }
}

#[test]
fn weighted_at_full_weight_equals_unweighted_for_every_width_and_code() {
    for s in 1..=16u32 {
        for f in 1..=16u32 {
            let plain = blend(s, f, false, 8);
            for k in [1u32, 2, 8, 16] {
                let wtd = blend(s, f, true, k);
                let wmax = max_code(k);
                for src in 0..=max_code(s) {
                    assert_eq!(
                        wtd.contribution(src, wmax),
                        plain.contribution(src, 0),
                        "{s}→{f}, k {k}: src {src}"
                    );
                }
                let m = max_code(f);
                for (src, dst) in [(0, 0), (max_code(s), m), (1, m), (max_code(s) / 2, m / 2)] {
                    assert_eq!(
                        wtd.blend_channel(src, dst, wmax),
                        plain.blend_channel(src, dst, 0)
                    );
                }
            }
        }
    }
}

#[test]
fn round_div_mersenne_is_round_to_nearest() {
    let exact = |x: u64, k: u32| {
        let m = max_code(k) as u64;
        (2 * x + m) / (2 * m)
    };
    for k in 1..=16u32 {
        for q in 1..=16u32 {
            let top = max_code(q) as u64 * max_code(k) as u64;
            if q + k <= 16 {
                for x in 0..=top {
                    assert_eq!(
                        round_div_mersenne(x, k, q),
                        exact(x, k),
                        "k {k} q {q} x {x}"
                    );
                }
            } else {
                // Ends, and every rounding boundary near multiples of M_k at both ends.
                let m = max_code(k) as u64;
                let mut xs: Vec<u64> = (0..2000u64.min(top + 1)).collect();
                xs.extend(top.saturating_sub(2000)..=top);
                for n in (0..2000u64).chain(top / m - 2000.min(top / m)..=top / m) {
                    for d in [0, m / 2, m / 2 + 1, m.saturating_sub(1)] {
                        xs.push((n * m + d).min(top));
                    }
                }
                for x in xs {
                    assert_eq!(
                        round_div_mersenne(x, k, q),
                        exact(x, k),
                        "k {k} q {q} x {x}"
                    );
                }
            }
        }
    }
}

#[test]
fn narrow_equals_the_costed_shift_add_form() {
    // The cost of narrowing is priced as (v·M_f) then the J = 1 round_div_mersenne
    // series; prove that is the function unorm::narrow computes.
    for s in 2..=16u32 {
        for f in 1..s {
            for v in 0..=max_code(s) {
                let via = round_div_mersenne(v as u64 * max_code(f) as u64, s, f) as u32;
                assert_eq!(via, narrow(v, s, f), "{s}→{f}: {v}");
            }
        }
    }
}

/// Blend `planes` equal fragments into a pixel that starts at 0, one kernel call each.
fn run_planes(b: &AdditiveBlend, src: u32, w: u32, planes: u64) -> ([u32; 4], Counters) {
    let mut ctr = Counters::default();
    let mut dst = [0u32; 4];
    for _ in 0..planes {
        let input = AdditiveBlendIn {
            src: [src; 4],
            dst,
            weight: w,
        };
        dst = b.kernel(&mut (), &input, &mut ctr);
    }
    (dst, ctr)
}

#[test]
fn thousands_of_planes_saturate_and_count_exactly() {
    let mut wctr = Counters::default();
    let w6 = blend(8, 8, true, 8)
        .quantise_weight(1.0 / 6.0, &mut wctr)
        .unwrap();
    assert_eq!(w6, 42, "round-half-even of 255/6 = 42.5");
    assert_eq!(wctr, Counters::default());
    // (src, fb, weighted, weight_bits, src code, weight code)
    let cases = [
        (8, 8, false, 8, 1, 0),    // 255 adds fit, 4 745 clamp
        (8, 8, false, 8, 5, 0),    // 51·5 = 255 exactly: the 51st add does not clamp
        (8, 16, false, 8, 3, 0),   // 771·85 = 65 535 exactly
        (8, 12, false, 8, 1, 0),   // q = 16 (replication 0x010 + 0x001>>4)
        (8, 10, false, 8, 200, 0), // q = 803
        (3, 2, false, 8, 1, 0),    // q = round(3/7) = 0: every plane underflows
        (3, 2, false, 8, 2, 0),    // q = round(6/7) = 1
        (8, 8, true, 8, 200, w6),  // q = round(200·42/255) = 33
        (8, 8, true, 8, 1, w6),    // q = round(42/255) = 0: lost in 8 bits
        (8, 16, true, 8, 1, w6),   // q = round(257·42/255) = 42: kept in 16 bits
        (8, 16, true, 16, 255, 1), // q = round(65535/65535) = 1
    ];
    let planes = 5000u64;
    for (s, f, wtd, k, src, w) in cases {
        let b = blend(s, f, wtd, k);
        let m = b.fb_max() as u64;
        let q = b.contribution(src, w) as u64;
        let (out, ctr) = run_planes(&b, src, w, planes);
        // Integers: min(k·q, M) and the number of adds i with i·q > M.
        let want = (planes * q).min(m) as u32;
        // (q = 0 never clamps: no add exceeds M.)
        let clamps = m.checked_div(q).map_or(0, |fit| planes - planes.min(fit));
        assert_eq!(out, [want; 4], "{:?} src {src} w {w}", b.config());
        assert_eq!(ctr.saturations, 4 * clamps, "{:?}", b.config());
        let nonzero = src != 0 && (!wtd || w != 0);
        let underflows = if q == 0 && nonzero { 4 * planes } else { 0 };
        assert_eq!(ctr.underflows, underflows);
        let px = bytes_for_bits(b.pixel_bits());
        assert_eq!(
            (ctr.mem_read_bytes, ctr.mem_write_bytes),
            (planes * px, planes * px)
        );
        // The twin, given the contribution the unit adds, predicts both exactly
        // (codes are integers, exact in f64).
        let (tv, tclamps) = accumulate_planes(0.0, q as f64, planes, m as f64);
        assert_eq!((tv, tclamps), (want as f64, clamps), "{:?}", b.config());
        // Against the ideal contribution: |unit − twin| ≤ planes · per-add bound.
        let ideal = contribution_codes(src, s, f, twin_weight(&b, w));
        let (iv, _) = accumulate_planes(0.0, ideal, planes, m as f64);
        let lim = planes as f64 * bound(&b, w) + SLACK * planes as f64;
        assert!(
            (want as f64 - iv).abs() <= lim,
            "{:?}: {want} vs {iv}",
            b.config()
        );
    }
}

#[test]
fn twin_on_values_agrees_with_codes_and_never_nans() {
    assert_eq!(additive_blend(0.75, 0.5, 1.0), 1.0);
    assert_eq!(additive_blend(0.25, 0.5, 0.5), 0.5);
    for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -1.0, 2.0] {
        assert!(!additive_blend(x, x, x).is_nan());
        let (v, c) = accumulate_planes(x, x, 10, x);
        assert!(!v.is_nan());
        let _ = c;
    }
    let v = additive_blend(unorm_value(100, 8), unorm_value(50, 8), 1.0) * 255.0;
    assert!((v - additive_blend_codes(50, 100, 8, 8, None)).abs() < 1e-9);
}

#[test]
fn multiplier_is_costed_only_when_weighted() {
    let plain = AdditiveBlend::geforce();
    let wtd = AdditiveBlendConfig {
        weighted: true,
        ..Default::default()
    }
    .build()
    .unwrap();
    let has_mul = |b: &AdditiveBlend| {
        b.cost()
            .breakdown
            .iter()
            .any(|(n, _)| n.contains("multiplier"))
    };
    assert!(!has_mul(&plain));
    assert!(has_mul(&wtd));
    assert!(wtd.cost().gates_nand2() > plain.cost().gates_nand2());
    assert_eq!(plain.cost().ram_bits, 0);
}

/// Datasheet numbers: `cargo test --test additive_blend -- --nocapture datasheet`.
#[test]
fn datasheet_numbers() {
    let cfgs = [
        (
            "geforce (8→8 RGBA, unweighted)",
            AdditiveBlendConfig::default(),
        ),
        (
            "weighted, k = 8",
            AdditiveBlendConfig {
                weighted: true,
                ..Default::default()
            },
        ),
        (
            "8→16 RGBA, unweighted",
            AdditiveBlendConfig {
                fb_bits: 16,
                ..Default::default()
            },
        ),
        (
            "8→16 RGBA, weighted k = 8",
            AdditiveBlendConfig {
                fb_bits: 16,
                weighted: true,
                ..Default::default()
            },
        ),
        (
            "narrow 3→2 RGBA, unweighted",
            AdditiveBlendConfig {
                src_bits: 3,
                fb_bits: 2,
                ..Default::default()
            },
        ),
    ];
    for (name, c) in cfgs {
        let b = c.build().unwrap();
        let u = UnitSummary::of(&b);
        println!(
            "additive_blend [{name}]: latency {} II {} gates {:.1} NAND2, RAM {} bits",
            u.latency, u.ii, u.gates_nand2, u.ram_bits
        );
        for (part, g) in &u.breakdown {
            println!("    {part}: {g:.1}");
        }
    }
}

fn config_field() -> impl Strategy<Value = u32> {
    prop_oneof![1u32..=16, Just(0u32), 17u32..100, any::<u32>()]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    #[test]
    fn within_bound_at_named_configs(
        cfg in prop::sample::select(vec![(8u32, 8u32), (8, 16), (8, 10), (8, 12), (3, 2)]),
        weighted in any::<bool>(),
        k in prop::sample::select(vec![8u32, 1, 5, 16]),
        src in any::<u32>(), dst in any::<u32>(), w in any::<u32>(),
    ) {
        let b = blend(cfg.0, cfg.1, weighted, k);
        check(&b, src & max_code(cfg.0), dst & max_code(cfg.1), w & max_code(k));
    }

    #[test]
    fn within_bound_at_random_configs(
        s in 1u32..=16, f in 1u32..=16, k in 1u32..=16, weighted in any::<bool>(),
        src in any::<u32>(), dst in any::<u32>(), w in any::<u32>(),
    ) {
        let b = blend(s, f, weighted, k);
        check(&b, src & max_code(s), dst & max_code(f), w & max_code(k));
    }

    #[test]
    fn round_div_mersenne_random(k in 1u32..=16, q in 1u32..=16, x in any::<u64>()) {
        let m = max_code(k) as u64;
        let x = x % (max_code(q) as u64 * m + 1);
        prop_assert_eq!(round_div_mersenne(x, k, q), (2 * x + m) / (2 * m));
    }

    #[test]
    fn raw_words_never_panic_and_stay_in_range(
        s in 1u32..=16, f in 1u32..=16, ch in 1u32..=4, k in 1u32..=16, weighted in any::<bool>(),
        src in any::<[u32; 4]>(), dst in any::<[u32; 4]>(), weight in any::<u32>(),
    ) {
        let b = AdditiveBlend::new(s, f, ch, weighted, k).unwrap();
        let mut ctr = Counters::default();
        let out = b.kernel(&mut (), &AdditiveBlendIn { src, dst, weight }, &mut ctr);
        for (c, &o) in out.iter().enumerate() {
            if c < ch as usize {
                prop_assert!(o <= b.fb_max());
                prop_assert_eq!(o, b.blend_channel(src[c], dst[c], weight).0);
            } else {
                prop_assert_eq!(o, 0);
            }
        }
        prop_assert!(ctr.saturations <= ch as u64);
        prop_assert_eq!(ctr.mem_read_bytes, bytes_for_bits(ch * f));
        prop_assert_eq!(ctr.mem_write_bytes, bytes_for_bits(ch * f));
        // Signals are masked to their widths.
        for sig in b.in_signals(&AdditiveBlendIn { src, dst, weight }).iter().chain(b.out_signals(&out).iter()) {
            prop_assert!(sig.value < (1u64 << sig.width));
        }
    }

    #[test]
    fn tick_and_span_drivers_agree(
        s in 1u32..=16, f in 1u32..=16, ch in 1u32..=4, k in 1u32..=16, weighted in any::<bool>(),
        words in prop::collection::vec((any::<[u32; 4]>(), any::<[u32; 4]>(), any::<u32>()), 0..40),
    ) {
        let b = AdditiveBlend::new(s, f, ch, weighted, k).unwrap();
        let inputs: Vec<AdditiveBlendIn> = words
            .iter()
            .map(|&(src, dst, weight)| AdditiveBlendIn {
                src: src.map(|x| x & max_code(s)),
                dst: dst.map(|x| x & max_code(f)),
                weight: weight & max_code(k),
            })
            .collect();
        common::assert_drivers_agree(&b, (), &inputs);
    }

    #[test]
    fn random_configs_never_panic_and_errors_name_the_field(
        src_bits in config_field(), fb_bits in config_field(),
        channels in prop_oneof![1u32..=4, Just(0u32), 5u32..10, any::<u32>()],
        weighted in any::<bool>(), weight_bits in config_field(),
    ) {
        let c = AdditiveBlendConfig { src_bits, fb_bits, channels, weighted, weight_bits };
        let ok_bits = |x: u32| (1..=16).contains(&x);
        let bad: Vec<&str> = [
            ("additive_blend.src_bits", ok_bits(src_bits)),
            ("additive_blend.fb_bits", ok_bits(fb_bits)),
            ("additive_blend.channels", (1..=4).contains(&channels)),
            ("additive_blend.weight_bits", ok_bits(weight_bits)),
        ]
        .iter()
        .filter(|(_, ok)| !ok)
        .map(|(n, _)| *n)
        .collect();
        match c.build() {
            Ok(b) => {
                prop_assert!(bad.is_empty());
                prop_assert_eq!(b.config(), c);
            }
            Err(e) => {
                prop_assert!(e.field().starts_with("additive_blend."));
                prop_assert!(bad.contains(&e.field()), "{} not in {:?}", e.field(), bad);
            }
        }
    }

    #[test]
    fn weight_quantiser_rounds_and_refuses_non_finite(
        k in 1u32..=16,
        x in prop_oneof![
            0.0f64..=1.0,
            any::<f64>(),
            Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY),
        ],
    ) {
        let b = blend(8, 8, true, k);
        let mut ctr = Counters::default();
        match b.quantise_weight(x, &mut ctr) {
            Ok(code) => {
                prop_assert!(x.is_finite());
                prop_assert!(code <= b.weight_max());
                let m = b.weight_max() as f64;
                let want = (x.clamp(0.0, 1.0) * m).clamp(0.0, m);
                prop_assert!((code as f64 - want).abs() <= 0.5 + 1e-9, "{} → {} want {}", x, code, want);
                if (0.0..=1.0).contains(&x) {
                    prop_assert_eq!(ctr.saturations, 0);
                } else if !(-1.0..=2.0).contains(&x) {
                    prop_assert_eq!(ctr.saturations, 1);
                }
            }
            Err(e) => {
                prop_assert!(!x.is_finite());
                prop_assert_eq!(e.field(), "additive_blend.weight");
            }
        }
    }
}

#[test]
fn bounds_are_nearly_attained() {
    // The derived bounds are not loose: the worst observed error comes close to them.
    for (s, f, wtd, k) in [
        (8, 10, false, 8),
        (8, 12, false, 8),
        (3, 2, false, 8),
        (8, 8, true, 8),
        (3, 2, true, 8),
        (5, 7, true, 8),
    ] {
        let b = blend(s, f, wtd, k);
        let ws = if wtd { max_code(k) } else { 0 };
        let mut worst = 0.0f64;
        let mut worst_ratio = 0.0f64;
        for src in 0..=max_code(s) {
            for w in 0..=ws {
                let q = b.contribution(src, w) as f64;
                let e = (q - contribution_codes(src, s, f, twin_weight(&b, w))).abs();
                worst = worst.max(e);
                worst_ratio = worst_ratio.max(e / bound(&b, w).max(1e-300));
            }
        }
        println!(
            "{s}→{f} weighted {wtd} k {k}: worst {worst:.4} LSB, worst/bound {worst_ratio:.4}"
        );
        assert!(worst_ratio <= 1.0 + 1e-9);
        assert!(
            worst_ratio > 0.7,
            "bound for {s}→{f} looks loose: {worst_ratio}"
        );
    }
}

#[test]
fn geforce_equals_the_default_config() {
    assert_eq!(
        AdditiveBlend::geforce(),
        AdditiveBlendConfig::default().build().unwrap()
    );
    assert_eq!(
        AdditiveBlend::geforce().timing(),
        rtl_model::Timing { latency: 3, ii: 1 }
    );
}

/// The batch path (its contribution table) against the span driver on every source,
/// destination and weight of 4-bit words, weighted and not, narrowing and widening
/// (2¹² inputs each: exhaustive), at several chunk sizes.
#[test]
fn batch_path_agrees_exhaustively_at_4_bits() {
    let inputs: Vec<AdditiveBlendIn> = (0..1u32 << 12)
        .map(|i| AdditiveBlendIn {
            src: [i & 15, (i >> 4) & 15, 15 - (i & 15), 0],
            dst: [(i >> 4) & 15, i & 15, 0, 15],
            weight: i >> 8,
        })
        .collect();
    for (src, fb) in [(4u32, 4u32), (4, 3), (3, 4)] {
        for weighted in [false, true] {
            let b = AdditiveBlend::new(src, fb, 4, weighted, 4).unwrap();
            let mut c = Counters::default();
            let span = rtl_model::driver::run_span(&b, &mut (), &inputs, &mut c);
            common::assert_batch_agrees(&b, &(), &inputs, &span, &(), &c);
        }
    }
}

/// `blend_lanes` (the J buffer's single-channel lane form) against the span driver on
/// the inputs it stands for, `[src, 0, 0, 0]` over `[dst, 0, 0, 0]` at one weight:
/// channel 0's outputs, and the counters once the span's timing is added.
fn lanes_agree_with_span(b: &AdditiveBlend, src: &[u32], dst: &[u32], weight: u32) {
    let inputs: Vec<AdditiveBlendIn> = src
        .iter()
        .zip(dst)
        .map(|(&s, &d)| AdditiveBlendIn {
            src: [s, 0, 0, 0],
            dst: [d, 0, 0, 0],
            weight,
        })
        .collect();
    let mut c_span = Counters::default();
    let out = rtl_model::driver::run_span(b, &mut (), &inputs, &mut c_span);
    let mut lanes = dst.to_vec();
    let mut c = Counters::default();
    b.blend_lanes(src, &mut lanes, weight, &mut c);
    let mut tally = rtl_model::driver::SpanTally::new();
    tally.add(src.len());
    tally.close(b.timing(), &mut c);
    let ch0: Vec<u32> = out.iter().map(|o| o[0]).collect();
    assert_eq!(
        lanes, ch0,
        "blend_lanes outputs differ from the span driver's"
    );
    assert_eq!(
        c, c_span,
        "blend_lanes counters differ from the span driver's"
    );
}

/// Exhaustive at 4-bit words: every source, destination and weight, weighted and not,
/// narrowing, equal and widening, 1 and 4 channels.
#[test]
fn lane_form_agrees_with_the_span_driver_exhaustively_at_4_bits() {
    let src: Vec<u32> = (0..256u32).map(|i| i & 15).collect();
    let dst: Vec<u32> = (0..256u32).map(|i| i >> 4).collect();
    for (s, f) in [(4u32, 4u32), (4, 3), (3, 4)] {
        for ch in [1u32, 4] {
            for weighted in [false, true] {
                let b = AdditiveBlend::new(s, f, ch, weighted, 4).unwrap();
                for w in 0..16 {
                    lanes_agree_with_span(&b, &src, &dst, w);
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]
    /// Random configs (sources past the table's width too), words and weights.
    #[test]
    fn lane_form_agrees_with_the_span_driver(
        s in 1u32..=16, f in 1u32..=16, ch in 1u32..=4, k in 1u32..=16, weighted in any::<bool>(),
        weight in any::<u32>(),
        words in prop::collection::vec((any::<u32>(), any::<u32>()), 0..60),
    ) {
        let b = AdditiveBlend::new(s, f, ch, weighted, k).unwrap();
        let src: Vec<u32> = words.iter().map(|w| w.0 & max_code(s)).collect();
        let dst: Vec<u32> = words.iter().map(|w| w.1 & max_code(f)).collect();
        lanes_agree_with_span(&b, &src, &dst, weight & max_code(k));
    }
}

/// `blend_pixels` (the framebuffer's unweighted lane form) against the span driver on
/// the inputs it stands for, `src[i]` over `dst[i]` at weight 0: the outputs, and the
/// counters once the span's timing is added; a weighted blend or a source wider than
/// the table is refused with nothing done.
fn pixels_agree_with_span(b: &AdditiveBlend, src: &[[u32; 4]], dst: &[[u32; 4]]) {
    let mut out = vec![[9u32; 4]; src.len()];
    let mut c = Counters::default();
    let done = b.blend_pixels(|i| src[i], |i| dst[i], &mut out, &mut c);
    if b.weighted() || b.src_bits() > rtl_model::units::additive_blend::CONTRIBUTION_LUT_BITS {
        assert!(!done, "blend_pixels ran on a config it does not serve");
        assert!(out.iter().all(|o| *o == [9; 4]));
        assert_eq!(c, Counters::default());
        return;
    }
    assert!(done, "blend_pixels refused an unweighted config");
    let inputs: Vec<AdditiveBlendIn> = src
        .iter()
        .zip(dst)
        .map(|(&s, &d)| AdditiveBlendIn {
            src: s,
            dst: d,
            weight: 0,
        })
        .collect();
    let mut c_span = Counters::default();
    let want = rtl_model::driver::run_span(b, &mut (), &inputs, &mut c_span);
    let mut tally = rtl_model::driver::SpanTally::new();
    tally.add(src.len());
    tally.close(b.timing(), &mut c);
    assert_eq!(
        out, want,
        "blend_pixels outputs differ from the span driver's"
    );
    assert_eq!(
        c, c_span,
        "blend_pixels counters differ from the span driver's"
    );
}

/// Exhaustive at 4-bit words: every source and destination code on every channel
/// (2⁸ pairs, rotated across the channels), narrowing, equal and widening, 1 to 4
/// channels; weighted configs refused.
#[test]
fn pixel_form_agrees_with_the_span_driver_exhaustively_at_4_bits() {
    let src: Vec<[u32; 4]> = (0..256u32)
        .map(|i| [i & 15, i >> 4, 15 - (i & 15), (i * 7) & 15])
        .collect();
    let dst: Vec<[u32; 4]> = (0..256u32)
        .map(|i| [i >> 4, i & 15, (i * 3) & 15, 15 - (i >> 4)])
        .collect();
    for (s, f) in [(4u32, 4u32), (4, 3), (3, 4)] {
        for ch in 1..=4 {
            for weighted in [false, true] {
                let b = AdditiveBlend::new(s, f, ch, weighted, 4).unwrap();
                pixels_agree_with_span(&b, &src, &dst);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]
    /// Random configs (sources past the table's width too) and raw words (bits above
    /// the wires included).
    #[test]
    fn pixel_form_agrees_with_the_span_driver(
        s in 1u32..=16, f in 1u32..=16, ch in 1u32..=4, k in 1u32..=16, weighted in any::<bool>(),
        words in prop::collection::vec((any::<[u32; 4]>(), any::<[u32; 4]>()), 0..60),
    ) {
        let b = AdditiveBlend::new(s, f, ch, weighted, k).unwrap();
        let src: Vec<[u32; 4]> = words.iter().map(|w| w.0).collect();
        let dst: Vec<[u32; 4]> = words.iter().map(|w| w.1).collect();
        pixels_agree_with_span(&b, &src, &dst);
    }
}
