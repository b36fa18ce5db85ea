//! f64 twin of `projective_texcoord`: u = s/q, v = t/q, and `behind` when q ≤ 0
//! (then u = v = 0, as the hardware outputs).

/// The ideal projective coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projected {
    pub u: f64,
    pub v: f64,
    pub behind: bool,
}

/// (s/q, t/q); q ≤ 0 (or NaN) is behind the projector and gives (0, 0). A NaN s or t
/// gives 0 for that coordinate (never a NaN output); a huge quotient may be ±∞.
pub fn project(s: f64, t: f64, q: f64) -> Projected {
    if q.is_nan() || q <= 0.0 {
        return Projected {
            u: 0.0,
            v: 0.0,
            behind: true,
        };
    }
    let div = |x: f64| {
        let r = x / q;
        if r.is_nan() {
            0.0
        } else {
            r
        }
    };
    Projected {
        u: div(s),
        v: div(t),
        behind: false,
    }
}

/// The twin on raw input codes of a format with `frac_bits` fraction bits (exact
/// conversion for codes of ≤ 53 bits).
pub fn project_codes(s: i64, t: i64, q: i64, frac_bits: u32) -> Projected {
    let k = (-(frac_bits as f64)).exp2();
    project(s as f64 * k, t as f64 * k, q as f64 * k)
}
