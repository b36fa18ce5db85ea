//! f64 twin of `reflection_vector`: n̂ = n/|n|, v̂ = e/|e|, r = 2(n̂·v̂)n̂ − v̂, t = r·λ
//! and the texel-space coordinate (t + 1)/2 · s per axis (texels, unrounded).
//!
//! Zero vectors (the unit's rule, and the envmap renderer's f64 path): n = 0 → n̂ := v̂
//! (so r = v̂); e = 0 → v̂ := n̂ (r = n̂); both zero → r = 0, the map's centre.
//! Finite inputs never give a NaN: each vector is scaled by its largest |component|
//! before the length is taken, so no square overflows or underflows to zero.

/// x/|x|, or None for the zero vector (finite components assumed; a non-finite
/// component is treated as zero so that no NaN can come out).
pub fn normalise(x: [f64; 3]) -> Option<[f64; 3]> {
    let x = x.map(|c| if c.is_finite() { c } else { 0.0 });
    let m = x.iter().fold(0.0f64, |a, &c| a.max(c.abs()));
    if m == 0.0 {
        return None;
    }
    let y = x.map(|c| c / m); // max |y_i| = 1: the squared length lies in [1, 3]
    let l = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2]).sqrt();
    Some(y.map(|c| c / l))
}

/// The unit normal and view vector after the zero-vector rule.
pub fn unit_vectors(n: [f64; 3], e: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    match (normalise(n), normalise(e)) {
        (Some(a), Some(b)) => (a, b),
        (None, Some(b)) => (b, b),
        (Some(a), None) => (a, a),
        (None, None) => ([0.0; 3], [0.0; 3]),
    }
}

/// r = 2(n̂·v̂)n̂ − v̂ (unit length unless both vectors are zero, then 0).
pub fn reflect(n: [f64; 3], e: [f64; 3]) -> [f64; 3] {
    let (nh, vh) = unit_vectors(n, e);
    let d = nh[0] * vh[0] + nh[1] * vh[1] + nh[2] * vh[2];
    [0, 1, 2].map(|k| 2.0 * d * nh[k] - vh[k])
}

/// The 3D texel-space coordinate (t + 1)/2 · s with t = r·λ (λ clamped to [0, 1], a
/// NaN λ reads as 0), in texels, for a map of side `side`.
pub fn reflection_coord(n: [f64; 3], e: [f64; 3], lambda: f64, side: f64) -> [f64; 3] {
    let lambda = if lambda.is_nan() {
        0.0
    } else {
        lambda.clamp(0.0, 1.0)
    };
    let r = reflect(n, e);
    r.map(|rk| (rk * lambda + 1.0) * 0.5 * side)
}

/// The twin on raw input codes (`frac_bits` fraction bits, exact for codes of ≤ 53
/// bits) and a u1.`lambda_bits` λ code.
pub fn reflection_coord_codes(
    n: [i64; 3],
    e: [i64; 3],
    frac_bits: u32,
    lambda: u32,
    lambda_bits: u32,
    side: f64,
) -> [f64; 3] {
    let k = (-(frac_bits as f64)).exp2();
    let l = lambda as f64 * (-(lambda_bits as f64)).exp2();
    reflection_coord(n.map(|x| x as f64 * k), e.map(|x| x as f64 * k), l, side)
}
