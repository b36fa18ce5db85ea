//! n-bit unsigned normalised (unorm) integer helpers: code c stands for c / (2ⁿ − 1).

use crate::error::{check_range, ConfigError};

/// Widest unorm the units accept (16-bit framebuffers and texels).
pub const MAX_UNORM_BITS: u32 = 16;

/// All-ones code of an n-bit unorm (stands for 1.0).
pub fn max_code(bits: u32) -> u32 {
    debug_assert!((1..=32).contains(&bits));
    if bits >= 32 {
        u32::MAX
    } else {
        (1u32 << bits) - 1
    }
}

/// Check a unorm width config field (1 ..= 16).
pub fn check_bits(field: &str, bits: u32) -> Result<(), ConfigError> {
    check_range(field, bits as u64, 1, MAX_UNORM_BITS as u64)
}

/// Widen an n-bit unorm to m ≥ n bits by bit replication, as GPUs expand texels and
/// colours (exact for 1.0 and 0.0; error < 1 LSB of the wider format).
pub fn widen(v: u32, from: u32, to: u32) -> u32 {
    debug_assert!(to >= from);
    let mut out = 0u32;
    let mut filled = 0u32;
    while filled < to {
        let take = from.min(to - filled);
        let chunk = v >> (from - take);
        out = (out << take) | chunk;
        filled += take;
    }
    out
}

/// Narrow an n-bit unorm to m ≤ n bits rounding to nearest: round(v·(2ᵐ−1)/(2ⁿ−1)).
/// Integer-exact (u64 intermediates: 16 + 16 bits).
pub fn narrow(v: u32, from: u32, to: u32) -> u32 {
    debug_assert!(to <= from);
    let num = v as u64 * max_code(to) as u64; // u(from) × u(to) → u(from + to)
    let den = max_code(from) as u64;
    ((2 * num + den) / (2 * den)) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn widen_keeps_ends_and_is_close() {
        for from in 1..=8u32 {
            for to in from..=16u32 {
                assert_eq!(widen(0, from, to), 0);
                assert_eq!(widen(max_code(from), from, to), max_code(to));
                for v in 0..=max_code(from) {
                    let exact = v as f64 * max_code(to) as f64 / max_code(from) as f64;
                    assert!((widen(v, from, to) as f64 - exact).abs() < 1.0);
                }
            }
        }
    }

    #[test]
    fn narrow_rounds_to_nearest() {
        for v in 0..=1023u32 {
            let exact = v as f64 * 255.0 / 1023.0;
            assert!((narrow(v, 10, 8) as f64 - exact).abs() <= 0.5);
        }
    }
}
