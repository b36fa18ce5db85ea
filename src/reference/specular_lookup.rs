//! f64 twin of `specular_lookup`: the specular power x^s of the dot product, and the
//! exact interpolant of a table (the same table read at the exact position, with
//! exact weights and no output rounding).
//!
//! x is the DOT3 code's value: code/(2^n − 1) unsigned, code/(2^(n−1) − 1) signed
//! (negative → 0). The table has 2^k nodes at j/N, N = 2^k − 1; the exact position of
//! x is p = x·N (index units). Nothing here panics or returns NaN: a non-finite x or s
//! reads as 0 or 1.

/// x^s on x clamped to [0, 1] (NaN → 0); a non-finite s reads as 1, a negative one
/// as 0 (the unit's range is [1, 10⁴]; this keeps the result in [0, 1]).
pub fn specular(x: f64, s: f64) -> f64 {
    let x = if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) };
    let s = if s.is_finite() { s.max(0.0) } else { 1.0 };
    x.powf(s)
}

/// The value x ∈ [0, 1] of an input word's wires (the low `in_bits` bits; signed:
/// two's complement, negative → 0).
pub fn input_value(code: i64, in_bits: u32, signed: bool) -> f64 {
    if signed {
        let sh = 64 - in_bits;
        let v = (code << sh) >> sh;
        v.max(0) as f64 / ((1u64 << (in_bits - 1)) - 1) as f64
    } else {
        (code & ((1i64 << in_bits) - 1)) as f64 / ((1u64 << in_bits) - 1) as f64
    }
}

/// The exact (unrounded) table in output LSBs: B·(j/N)^s, j = 0 ..< 2^k.
pub fn exact_table(table_log2: u32, entry_bits: u32, s: f64) -> Vec<f64> {
    let n = ((1u64 << table_log2) - 1) as f64;
    let big_b = ((1u64 << entry_bits) - 1) as f64;
    (0..1u64 << table_log2)
        .map(|j| specular(j as f64 / n, s) * big_b)
        .collect()
}

/// The exact interpolant of `table` (values at nodes 0 ..< len) at position `p` (index
/// units, clamped to [0, len − 1]): nearest = the node round(p) (half up), linear =
/// the straight line between the nodes either side. An empty table reads 0.
pub fn table_interpolant(table: &[f64], p: f64, linear: bool) -> f64 {
    let Some(last) = table.len().checked_sub(1) else {
        return 0.0;
    };
    let p = if p.is_nan() {
        0.0
    } else {
        p.clamp(0.0, last as f64)
    };
    if !linear {
        return table[((p + 0.5).floor() as usize).min(last)];
    }
    let i0 = (p.floor() as usize).min(last);
    let i1 = (i0 + 1).min(last);
    let f = p - i0 as f64;
    table[i0] + (table[i1] - table[i0]) * f
}

/// The ideal output in output LSBs: (2^b − 1)·x^s.
pub fn specular_codes(x: f64, entry_bits: u32, s: f64) -> f64 {
    specular(x, s) * ((1u64 << entry_bits) - 1) as f64
}
