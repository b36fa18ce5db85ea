//! The `modulate_chain` unit (rtl_model/src/units/modulate_chain.rs): its kernel within
//! the bound derived from its widths against the f64 twin (`reference::modulate_chain`),
//! exhaustively where the input space is small and by proptest elsewhere; the tick, span
//! and batch drivers agree; its config errors name the field. The chain's arithmetic
//! against `modulate` stage by stage is tests/modulate.rs; against OSMesa,
//! tests/modulate_mesa.rs.

mod common;

use common::{assert_drivers_agree, cases};
use glare_pipeline::reference::modulate_chain::modulate_chain_codes;
use proptest::prelude::*;
use rtl_model::units::modulate::ModulateMode;
use rtl_model::units::modulate_chain::{
    ChainRounding, ModulateChain, ModulateChainIn, DEFAULT_OPERANDS, MAX_OPERANDS,
};
use rtl_model::Unit;

/// The bound of docs/units.md `## modulate_chain`, in output LSBs, for k operands at
/// n bits: per stage (k − 1)/2; fused ½ + (3k + 1)·2⁻²⁴·(2ⁿ − 1).
fn bound(r: ChainRounding, k: u32, bits: u32) -> f64 {
    let max = ((1u64 << bits) - 1) as f64;
    match r {
        ChainRounding::PerStage => 0.5 * k.saturating_sub(1) as f64,
        ChainRounding::Fused => 0.5 + (3 * k + 1) as f64 * (-24f64).exp2() * max,
    }
}

fn unit(bits: u32, r: ChainRounding, k: u32) -> ModulateChain {
    ModulateChain::new(bits, ModulateMode::Exact, r)
        .unwrap()
        .with_operands(k)
        .unwrap()
}

fn word(ops: &[u32]) -> ModulateChainIn {
    let mut w = ModulateChainIn::default();
    w.ops[..ops.len()].copy_from_slice(ops);
    w
}

/// Every input of a narrow chain (n = 3, k = 3: 512 words) through all drivers, each
/// output within its bound.
#[test]
fn exhaustive_at_3_bits_three_operands() {
    for r in ChainRounding::ALL {
        let u = unit(3, r, 3);
        let inputs: Vec<ModulateChainIn> = (0..512u32)
            .map(|i| word(&[i & 7, (i >> 3) & 7, i >> 6]))
            .collect();
        let outs = assert_drivers_agree(&u, (), &inputs);
        for (i, o) in inputs.iter().zip(outs) {
            let want = modulate_chain_codes(&i.ops[..3], 3);
            assert!(
                (o as f64 - want).abs() <= bound(r, 3, 3) + 1e-9,
                "{r:?}: {:?} → {o}, want {want}",
                &i.ops[..3]
            );
        }
    }
}

#[test]
fn geforce_default_is_three_8_bit_per_stage_operands() {
    let u = ModulateChain::geforce();
    assert_eq!(u.name(), "modulate_chain");
    assert_eq!(u.operands(), DEFAULT_OPERANDS);
    assert_eq!(u.rounding(), ChainRounding::PerStage);
    assert_eq!(u.modulate().bits(), 8);
    // Two `modulate` stages of 2 clocks; fused adds the float conversions.
    assert_eq!(u.timing().latency, 4);
    let fused = unit(8, ChainRounding::Fused, 3);
    assert_eq!(fused.timing().latency, 7);
    // The binary32 datapath costs more gates than two 8-bit modulates.
    assert!(fused.cost().gates_nand2() > u.cost().gates_nand2());
    assert!(u.cost().gates_nand2() > 0.0);
}

#[test]
fn operand_count_out_of_range_names_the_field() {
    for k in [0, MAX_OPERANDS as u32 + 1] {
        let e = ModulateChain::geforce().with_operands(k).unwrap_err();
        assert_eq!(e.field(), "modulate_chain.operands", "{e}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), ..ProptestConfig::default() })]

    /// Random chains of 1 ..= 8 operands at 1 ..= 16 bits, a short span through every
    /// driver, each output within the width-derived bound.
    #[test]
    fn drivers_agree_and_stay_within_bound(
        bits in 1u32..=16,
        k in 1u32..=MAX_OPERANDS as u32,
        fused in any::<bool>(),
        raw in prop::collection::vec(prop::array::uniform8(any::<u32>()), 1..8),
    ) {
        let r = if fused { ChainRounding::Fused } else { ChainRounding::PerStage };
        let u = unit(bits, r, k);
        let max = (1u32 << bits) - 1;
        let inputs: Vec<ModulateChainIn> = raw
            .iter()
            .map(|ops| ModulateChainIn { ops: ops.map(|o| o & max) })
            .collect();
        let outs = assert_drivers_agree(&u, (), &inputs);
        for (i, o) in inputs.iter().zip(outs) {
            let ops = &i.ops[..k as usize];
            let want = modulate_chain_codes(ops, bits);
            let b = bound(r, k, bits);
            prop_assert!((o as f64 - want).abs() <= b + 1e-9, "{ops:?} → {o}, want {want}");
        }
    }
}
