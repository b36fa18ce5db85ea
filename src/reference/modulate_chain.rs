//! f64 twin of `modulate_chain`: the real product of the operands, whatever the
//! chain's rounding (the hardware's bound against it is derived in docs/units.md,
//! `## modulate_chain`).

/// A chain of MODULATE stages: the real product of its values (1 for none).
pub fn modulate_chain(values: &[f64]) -> f64 {
    values.iter().product()
}

/// The exact product of n-bit unorm codes, in output LSBs: Π (cₖ / (2ⁿ−1)) · (2ⁿ−1).
pub fn modulate_chain_codes(codes: &[u32], bits: u32) -> f64 {
    let max = ((1u64 << bits) - 1) as f64;
    let values: Vec<f64> = codes.iter().map(|&c| c as f64 / max).collect();
    modulate_chain(&values) * max
}
