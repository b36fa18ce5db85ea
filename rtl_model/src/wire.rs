//! Wire-level helpers the units share: sign extension of a narrow two's-complement
//! wire, the width a value needs, and a counted signed saturation.

use crate::counters::Counters;

/// Sign-extend the low `w` bits of `x` (a `w`-bit two's-complement wire, 1 ≤ w ≤ 64).
#[inline]
pub fn sign_extend(x: i64, w: u32) -> i64 {
    let sh = 64 - w;
    (x << sh) >> sh
}

/// Bits an unsigned value needs (at least 1): ⌊log2 v⌋ + 1.
#[inline]
pub fn bits_for(v: u64) -> u32 {
    (64 - v.leading_zeros()).max(1)
}

/// Clamp `x` into the signed range of `width` bits (1 ≤ width ≤ 127), counting a clamp
/// in `ctr.saturations`.
#[inline]
pub fn saturate_signed(x: i128, width: u32, ctr: &mut Counters) -> i128 {
    let hi = (1i128 << (width - 1)) - 1;
    let lo = -(1i128 << (width - 1));
    if x > hi || x < lo {
        ctr.saturations += 1;
        x.clamp(lo, hi)
    } else {
        x
    }
}
