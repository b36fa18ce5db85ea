//! f64 twin of `modulate`: the real product of two unorm values.

/// a · b on values in [0, 1].
pub fn modulate(a: f64, b: f64) -> f64 {
    a * b
}

/// The exact product of two n-bit unorm codes, in output LSBs: a·b / (2ⁿ−1).
pub fn modulate_codes(a: u32, b: u32, bits: u32) -> f64 {
    let max = ((1u64 << bits) - 1) as f64;
    modulate(a as f64 / max, b as f64 / max) * max
}

// The chain's twin lives with its unit's name (`reference::modulate_chain`).
pub use super::modulate_chain::{modulate_chain, modulate_chain_codes};
