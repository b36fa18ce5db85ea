//! f64 twin of `gaussian_noise`: exact Box–Muller and Irwin–Hall on the same uniform
//! codes the unit draws, plus the statistics its acceptance test needs (a precise
//! erfc, the normal CDF and tails, the Kolmogorov–Smirnov statistic and its asymptotic
//! p-value, the exact Irwin–Hall tail).

use std::f64::consts::PI;

/// u1 = (k1 + ½)/2ᴮ (never 0), u2 = k2/2ᴮ: the uniforms the unit uses.
pub fn uniforms(k1: u64, k2: u64, bits: u32) -> (f64, f64) {
    let s = (-(bits as f64)).exp2();
    ((k1 as f64 + 0.5) * s, k2 as f64 * s)
}

/// Exact Box–Muller: r = √(−2 ln u1), (x, y) = r·(cos 2πu2, sin 2πu2).
pub fn box_muller(k1: u64, k2: u64, bits: u32) -> (f64, f64) {
    let (u1, u2) = uniforms(k1, k2, bits);
    let r = (-2.0 * u1.ln()).max(0.0).sqrt();
    let th = 2.0 * PI * u2;
    (r * th.cos(), r * th.sin())
}

/// −ln u1 and r for the Box–Muller pair (for error budgets).
pub fn box_muller_radius(k1: u64, bits: u32) -> (f64, f64) {
    let u1 = (k1 as f64 + 0.5) * (-(bits as f64)).exp2();
    let y = -u1.ln();
    (y, (2.0 * y).max(0.0).sqrt())
}

/// Exact Irwin–Hall sample: Σ (k_j + ½)/2ᴮ − n/2.
pub fn irwin_hall(ks: &[u64], bits: u32) -> f64 {
    let s = (-(bits as f64)).exp2();
    ks.iter().map(|&k| (k as f64 + 0.5) * s).sum::<f64>() - ks.len() as f64 / 2.0
}

/// erfc(x), Numerical Recipes `erfcc` (Chebyshev fit, |relative error| < 1.2·10⁻⁷
/// everywhere).
pub fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let ans = t
        * (-z * z - 1.265_512_23
            + t * (1.000_023_68
                + t * (0.374_091_96
                    + t * (0.096_784_18
                        + t * (-0.186_288_06
                            + t * (0.278_868_07
                                + t * (-1.135_203_98
                                    + t * (1.488_515_87
                                        + t * (-0.822_152_23 + t * 0.170_872_77)))))))))
            .exp();
    if x >= 0.0 {
        ans
    } else {
        2.0 - ans
    }
}

/// Φ(x), the standard normal CDF.
pub fn normal_cdf(x: f64) -> f64 {
    0.5 * erfc(-x / std::f64::consts::SQRT_2)
}

/// P(|X| > t) for X ~ N(0, 1): 2·Q(t) = erfc(t/√2).
pub fn normal_two_sided_tail(t: f64) -> f64 {
    erfc(t / std::f64::consts::SQRT_2)
}

fn binom(n: u32, k: u32) -> f64 {
    (0..k).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
}

/// Irwin–Hall CDF of the sum of n U(0, 1): F(x) = (1/n!) Σ_{k ≤ x} (−1)ᵏ C(n, k)(x − k)ⁿ.
pub fn irwin_hall_cdf(n: u32, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= n as f64 {
        return 1.0;
    }
    let fact: f64 = (1..=n).map(|i| i as f64).product();
    let mut s = 0.0;
    for k in 0..=(x.floor() as u32) {
        let term = binom(n, k) * (x - k as f64).powi(n as i32);
        s += if k % 2 == 0 { term } else { -term };
    }
    (s / fact).clamp(0.0, 1.0)
}

/// P(|S − n/2| > t) for S the sum of n U(0, 1) (exact; symmetric, so 2·F(n/2 − t)).
pub fn irwin_hall_two_sided_tail(n: u32, t: f64) -> f64 {
    2.0 * irwin_hall_cdf(n, n as f64 / 2.0 - t)
}

/// Kolmogorov distribution's complement Q_KS(λ) = 2 Σ_{j≥1} (−1)^(j−1) e^(−2j²λ²).
pub fn kolmogorov_q(lambda: f64) -> f64 {
    if lambda < 0.2 {
        return 1.0;
    }
    let mut s = 0.0;
    let mut sign = 1.0;
    for j in 1..=100 {
        let term = sign * 2.0 * (-2.0 * (j * j) as f64 * lambda * lambda).exp();
        s += term;
        if term.abs() < 1e-16 {
            break;
        }
        sign = -sign;
    }
    s.clamp(0.0, 1.0)
}

/// Result of a one-sample KS test against N(0, 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KsResult {
    pub n: usize,
    /// sup |F_n − Φ|.
    pub d: f64,
    /// Asymptotic p-value Q_KS((√n + 0.12 + 0.11/√n)·D) (Stephens; Numerical Recipes).
    pub p: f64,
}

/// KS test of output codes (value = code·lsb) against N(0, 1), treating each code as
/// the rounding of a continuous value: P(code ≤ c) = Φ((c + ½)·lsb). D compares the
/// empirical CDF with it just below and at every distinct code.
pub fn ks_normal_codes(codes: &[i32], lsb: f64) -> KsResult {
    let mut v: Vec<i32> = codes.to_vec();
    v.sort_unstable();
    let n = v.len();
    let nf = n as f64;
    let mut d: f64 = 0.0;
    let mut i = 0;
    while i < n {
        let c = v[i];
        let mut j = i;
        while j < n && v[j] == c {
            j += 1;
        }
        let below = normal_cdf((c as f64 - 0.5) * lsb);
        let at = normal_cdf((c as f64 + 0.5) * lsb);
        d = d.max((i as f64 / nf - below).abs());
        d = d.max((j as f64 / nf - at).abs());
        i = j;
    }
    let sq = nf.sqrt();
    KsResult {
        n,
        d,
        p: kolmogorov_q((sq + 0.12 + 0.11 / sq) * d),
    }
}

/// Counts of |x| > 3 and |x| > 4 among codes (value = code·lsb).
pub fn tail_counts(codes: &[i32], lsb: f64) -> (u64, u64) {
    let mut c3 = 0;
    let mut c4 = 0;
    for &c in codes {
        let x = (c as f64 * lsb).abs();
        if x > 3.0 {
            c3 += 1;
        }
        if x > 4.0 {
            c4 += 1;
        }
    }
    (c3, c4)
}
