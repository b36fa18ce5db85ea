//! modulate against its f64 twin: exhaustive where the input space is ≤ 2²⁰,
//! property tests (≥ 1 000 cases) at 8, 12 and 16 bits and a narrow 3-bit config.

mod common;

use glare_pipeline::reference::modulate::{modulate_chain_codes, modulate_codes};
use proptest::prelude::*;
use rtl_model::units::modulate::{
    ChainRounding, Modulate, ModulateChain, ModulateIn, ModulateMode, Operand,
};

/// Width-derived error bound, in output LSBs, of each mode against a·b/(2ⁿ−1)
/// (derivations in docs/units.md#modulate). Returned as (low, high): err ∈ [low, high].
fn bound(mode: ModulateMode, bits: u32) -> (f64, f64) {
    let max = ((1u64 << bits) - 1) as f64;
    let two_n = (1u64 << bits) as f64;
    match mode {
        ModulateMode::Exact => (-0.5, 0.5),
        // a·b/(2ⁿ−1) − a·b/2ⁿ ≤ (2ⁿ−1)/2ⁿ, plus < 1 from the floor.
        ModulateMode::Shift => (-(max / two_n) - 1.0, 0.0),
        // a(b+1)/2ⁿ − ab/(2ⁿ−1) = a(2ⁿ−1−b)/(2ⁿ(2ⁿ−1)) ∈ [0, 1), then a floor.
        ModulateMode::PlusOne => (-1.0, max / two_n),
        ModulateMode::TruncDiv => (-1.0, 0.0),
    }
}

fn check(m: &Modulate, a: u32, b: u32) {
    let got = m.apply(a, b) as f64;
    let want = modulate_codes(a, b, m.bits());
    let err = got - want;
    let (lo, hi) = bound(m.mode(), m.bits());
    // Strict inequalities where the derivation gives them, with f64 slack of 1e-9.
    assert!(
        err >= lo - 1e-9 && err <= hi + 1e-9,
        "{:?} {} bits: {a}·{b} → {got}, want {want} (err {err}, bound [{lo}, {hi}])",
        m.mode(),
        m.bits()
    );
}

#[test]
fn default_equals_round_ab_over_255_for_all_65536_pairs() {
    let m = Modulate::geforce();
    for a in 0..=255u32 {
        for b in 0..=255u32 {
            // Integer round-half-up of a·b/255 (a tie cannot occur: 255 is odd).
            let want = (2 * a * b + 255) / 510;
            assert_eq!(m.apply(a, b), want, "{a}·{b}");
        }
    }
}

#[test]
fn exact_mode_is_exact_exhaustively_up_to_10_bits() {
    for bits in 1..=10u32 {
        let m = Modulate::new(bits, ModulateMode::Exact).unwrap();
        let max = (1u32 << bits) - 1;
        for a in 0..=max {
            for b in 0..=max {
                let want = ((2 * a as u64 * b as u64 + max as u64) / (2 * max as u64)) as u32;
                assert_eq!(m.apply(a, b), want, "{bits} bits: {a}·{b}");
            }
        }
    }
}

/// Each mode's definition in 64-bit integers at the widest operands, where the
/// datapath's 32-bit intermediates come closest to overflowing (t + (t >> n) up to
/// 2³² − 2¹⁵ at 16 bits): every pair of corner and near-corner codes at 13 ..= 16 bits.
#[test]
fn every_mode_matches_its_definition_at_the_widest_codes() {
    for bits in 13..=16u32 {
        let max = (1u64 << bits) - 1;
        let two_n = 1u64 << bits;
        let codes = [0, 1, 2, max / 2, max / 2 + 1, max - 2, max - 1, max];
        for mode in ModulateMode::ALL {
            let m = Modulate::new(bits, mode).unwrap();
            for &a in &codes {
                for &b in &codes {
                    let want = match mode {
                        ModulateMode::Exact => (2 * a * b + max) / (2 * max),
                        ModulateMode::Shift => a * b / two_n,
                        ModulateMode::PlusOne => a * (b + 1) / two_n,
                        ModulateMode::TruncDiv => a * b / max,
                    };
                    assert_eq!(
                        m.apply(a as u32, b as u32) as u64,
                        want,
                        "{mode:?} {bits} bits: {a}·{b}"
                    );
                }
            }
        }
    }
}

#[test]
fn every_mode_within_bound_exhaustively_at_8_and_3_bits() {
    for bits in [3u32, 8] {
        for mode in ModulateMode::ALL {
            let m = Modulate::new(bits, mode).unwrap();
            let max = (1u32 << bits) - 1;
            for a in 0..=max {
                for b in 0..=max {
                    check(&m, a, b);
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    #[test]
    fn within_bound_at_8_12_16_and_narrow_3_bits(
        bits in prop::sample::select(vec![3u32, 8, 12, 16]),
        mode in prop::sample::select(ModulateMode::ALL.to_vec()),
        a in any::<u32>(),
        b in any::<u32>(),
    ) {
        let m = Modulate::new(bits, mode).unwrap();
        let max = (1u32 << bits) - 1;
        check(&m, a & max, b & max);
    }

    #[test]
    fn tick_and_span_drivers_agree(
        bits in 1u32..=16,
        mode in prop::sample::select(ModulateMode::ALL.to_vec()),
        pairs in prop::collection::vec((any::<u32>(), any::<u32>()), 0..40),
    ) {
        let m = Modulate::new(bits, mode).unwrap();
        let inputs: Vec<ModulateIn> = pairs.iter().map(|&(a, b)| ModulateIn { a: a & ((1 << bits) - 1), b: b & ((1 << bits) - 1) }).collect();
        common::assert_drivers_agree(&m, (), &inputs);
    }

    #[test]
    fn out_of_range_width_is_an_error_naming_the_field(bits in prop_oneof![Just(0u32), 17u32..1000]) {
        let e = Modulate::new(bits, ModulateMode::Exact).unwrap_err();
        prop_assert_eq!(e.field(), "modulate.bits");
    }
}

/// The batch path against the span driver on every operand pair of the 8-bit and the
/// 4-bit unit, in every mode (65 536 and 256 pairs: exhaustive), at several chunk sizes.
#[test]
fn batch_path_agrees_exhaustively_at_8_and_4_bits() {
    for bits in [8u32, 4] {
        let n = 1u32 << bits;
        let inputs: Vec<ModulateIn> = (0..n * n)
            .map(|i| ModulateIn { a: i / n, b: i % n })
            .collect();
        for mode in ModulateMode::ALL {
            let m = Modulate::new(bits, mode).unwrap();
            let mut c = rtl_model::Counters::default();
            let span = rtl_model::driver::run_span(&m, &mut (), &inputs, &mut c);
            common::assert_batch_agrees(&m, &(), &inputs, &span, &(), &c);
        }
    }
}

/// The lane form (`apply_lanes`) against `apply` on every operand pair of the 8-bit
/// and the 4-bit unit, in every mode (exhaustive), with lanes and with a constant
/// second operand; and unmasked words (any u32) as `apply` masks them.
#[test]
fn lane_form_agrees_exhaustively_at_8_and_4_bits() {
    for bits in [8u32, 4] {
        let n = 1u32 << bits;
        // Every pair, plus words past the n wires (masked by both forms).
        let a: Vec<u32> = (0..n * n)
            .map(|i| i / n)
            .chain([u32::MAX, n, 3 * n + 1])
            .collect();
        let b: Vec<u32> = (0..n * n)
            .map(|i| i % n)
            .chain([7, u32::MAX, n + 2])
            .collect();
        for mode in ModulateMode::ALL {
            let m = Modulate::new(bits, mode).unwrap();
            let mut out = vec![12345];
            m.apply_lanes(&a, Operand::Lanes(&b), &mut out);
            let want: Vec<u32> = a.iter().zip(&b).map(|(&x, &y)| m.apply(x, y)).collect();
            assert_eq!(out, want, "{bits} bits, {mode:?}, lanes");
            for c in [0, 1, n / 2, n - 1, n + 5] {
                m.apply_lanes(&a, Operand::Constant(c), &mut out);
                let want: Vec<u32> = a.iter().map(|&x| m.apply(x, c)).collect();
                assert_eq!(out, want, "{bits} bits, {mode:?}, constant {c}");
            }
        }
    }
}

// ---- the chain (ModulateChain) ----

/// Width-derived bound, in output LSBs, of a k-operand chain against the exact
/// product (docs/units.md#modulate):
/// * `per_stage`: stage j rounds acc·op/N to ½ LSB, and an error e in acc becomes
///   e·op/N ≤ e in the next product, so k − 1 stages err by ≤ (k − 1)/2;
/// * `fused`: Mesa's binary32 — 2 roundings per operand (fl(1/N), c · it), k − 1
///   products, 2 in the unorm conversion, each ≤ 2⁻²⁴ relative on a value ≤ 1, i.e.
///   ≤ (3k + 1) · 2⁻²⁴ · N LSB before the final round to nearest (½).
fn chain_bound(rounding: ChainRounding, k: usize, bits: u32) -> f64 {
    let max = ((1u64 << bits) - 1) as f64;
    match rounding {
        ChainRounding::PerStage => 0.5 * k.saturating_sub(1) as f64,
        ChainRounding::Fused => 0.5 + (3 * k + 1) as f64 * (-24f64).exp2() * max,
    }
}

fn check_chain(c: &ModulateChain, ops: &[u32]) {
    let bits = c.modulate().bits();
    let got = c.apply(ops) as f64;
    let want = modulate_chain_codes(ops, bits);
    let b = chain_bound(c.rounding(), ops.len(), bits);
    assert!(
        (got - want).abs() <= b + 1e-9,
        "{:?} {bits} bits: {ops:?} → {got}, want {want} (bound {b})",
        c.rounding()
    );
}

#[test]
fn chain_per_stage_is_modulate_stage_by_stage_and_both_within_bound_at_8_bits() {
    // Every (a, b) with the third operand on a stride: per_stage is exactly two
    // `modulate` applications; both roundings are within their bounds.
    let m = Modulate::geforce();
    let per = ModulateChain::geforce();
    let fused = ModulateChain::new(8, ModulateMode::Exact, ChainRounding::Fused).unwrap();
    for a in 0..=255u32 {
        for b in 0..=255u32 {
            for c in (0..=255u32).step_by(17) {
                assert_eq!(per.apply(&[a, b, c]), m.apply(m.apply(a, b), c));
                check_chain(&per, &[a, b, c]);
                check_chain(&fused, &[a, b, c]);
            }
        }
    }
    assert_eq!(per.apply(&[]), 255);
    assert_eq!(fused.apply(&[77]), 77);
}

#[test]
fn chain_fused_needs_the_exact_mode_and_names_the_field() {
    for mode in [
        ModulateMode::Shift,
        ModulateMode::PlusOne,
        ModulateMode::TruncDiv,
    ] {
        let e = ModulateChain::new(8, mode, ChainRounding::Fused).unwrap_err();
        assert_eq!(e.field(), "modulate.chain_rounding", "{e}");
        assert!(ModulateChain::new(8, mode, ChainRounding::PerStage).is_ok());
    }
    let e = ModulateChain::new(0, ModulateMode::Exact, ChainRounding::Fused).unwrap_err();
    assert_eq!(e.field(), "modulate.bits", "{e}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    /// Chains of 1 ..= 8 operands at 1 ..= 16 bits, both roundings, within the bound.
    #[test]
    fn chain_within_derived_bound(
        bits in 1u32..=16,
        rounding in prop::sample::select(ChainRounding::ALL.to_vec()),
        ops in prop::collection::vec(any::<u32>(), 1..=8),
    ) {
        let c = ModulateChain::new(bits, ModulateMode::Exact, rounding).unwrap();
        let max = (1u32 << bits) - 1;
        let ops: Vec<u32> = ops.iter().map(|&o| o & max).collect();
        check_chain(&c, &ops);
    }
}
