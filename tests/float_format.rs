//! rtl_model::float_format against exactly rounded f64 results and Rust's f32.
//!
//! Reference derivation. For a format with p = M + 1 significand bits, M ≤ 24:
//! * the product of two format values has ≤ 2p ≤ 50 significant bits and an exponent
//!   inside f64's range, so the f64 product is EXACT; rounding it once to the format
//!   (`round_to_format`, below, with f64 scaling by powers of two only) is the exactly
//!   rounded product;
//! * the f64 sum of two format values is rounded once to 53 bits, then to p bits: a
//!   double rounding, which is innocuous when 53 ≥ 2p + 2 (Figueroa's theorem for +, −,
//!   ×, ÷, √), i.e. M ≤ 24; so `round_to_format(a + b)` is the exactly rounded sum;
//! * 1/x likewise (÷ is covered by the same theorem);
//! * 1/√x is two f64 operations, so it is checked against the exact value within half
//!   a format ulp (+ 2^−50 relative for f64's own error) instead of bit for bit.
//!
//! At 8/23 with subnormals kept, add and mul must equal Rust's f32 (IEEE single,
//! nearest-even) bit for bit whenever f32's result is finite (the format saturates
//! where IEEE goes to ∞).

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::float_format::{FloatFormat, Fp, Rounding, Subnormals};
use rtl_model::Counters;

fn fmt(e: u32, m: u32, r: Rounding, s: Subnormals) -> FloatFormat {
    FloatFormat::new(e, m)
        .unwrap()
        .with_rounding(r)
        .with_subnormals(s)
}

/// The format value nearest to x under the format's rounding (f64 arithmetic on
/// powers of two only, so exact), saturating at the largest finite value.
fn round_to_format(x: f64, f: &FloatFormat) -> f64 {
    if x == 0.0 {
        return x;
    }
    if x.is_infinite() {
        return f.to_f64(f.max_finite(x < 0.0)); // beyond f64 is beyond the format too
    }
    let m = f.mant_bits as i32;
    let e = x.abs().log2().floor() as i32;
    // log2 may misjudge by one near a power of two: fix e so that 2^e ≤ |x| < 2^(e+1).
    let e = if 2f64.powi(e) > x.abs() {
        e - 1
    } else if 2f64.powi(e + 1) <= x.abs() {
        e + 1
    } else {
        e
    };
    let q_exp = match f.subnormals {
        Subnormals::Keep => e.max(f.emin()) - m,
        Subnormals::Flush => e - m,
    };
    let y = ldexp(x, -q_exp);
    let y = match f.rounding {
        Rounding::NearestEven => y.round_ties_even(),
        Rounding::Truncate => y.trunc(),
    };
    let r = ldexp(y, q_exp);
    let max = f.to_f64(f.max_finite(false));
    if r.abs() > max {
        return max.copysign(x);
    }
    if f.subnormals == Subnormals::Flush && r.abs() < 2f64.powi(f.emin()) {
        return 0.0f64.copysign(x);
    }
    r
}

/// x + y rounded once to the format. Nearest-even: the double rounding through f64 is
/// innocuous (M ≤ 24). Truncate: f64's nearest sum s plus its exact error e (TwoSum);
/// truncating s is right unless s is itself a format value and e points toward zero,
/// when the exact sum lies just inside it: one format step toward zero.
fn exact_sum_rounded(x: f64, y: f64, f: &FloatFormat) -> f64 {
    let s = x + y;
    let r = round_to_format(s, f);
    if f.rounding == Rounding::NearestEven {
        return r;
    }
    let bb = s - x;
    let e = (x - (s - bb)) + (y - bb);
    if r == s && e != 0.0 && (e < 0.0) != (s < 0.0) && s != 0.0 {
        round_to_format(s * (1.0 - 2f64.powi(-40)), f)
    } else if s == 0.0 && e != 0.0 {
        round_to_format(e, f)
    } else {
        r
    }
}

/// x·2^k exactly (in two steps, so 2^k itself need not be an f64).
fn ldexp(x: f64, k: i32) -> f64 {
    let h = k / 2;
    x * 2f64.powi(h) * 2f64.powi(k - h)
}

fn all_words(f: &FloatFormat) -> Vec<Fp> {
    (0..1u64 << f.width()).map(Fp).collect()
}

fn same(a: f64, b: f64) -> bool {
    a == b && (a != 0.0 || a.is_sign_negative() == b.is_sign_negative())
}

/// Exhaustive over every pair of e4m3 words (65 536), every rounding/subnormal mode.
#[test]
fn e4m3_add_mul_exhaustive() {
    for r in [Rounding::NearestEven, Rounding::Truncate] {
        for s in [Subnormals::Keep, Subnormals::Flush] {
            let f = fmt(4, 3, r, s);
            let words = all_words(&f);
            let mut ctr = Counters::default();
            for &a in &words {
                for &b in &words {
                    let (x, y) = (f.to_f64(a), f.to_f64(b));
                    if f.fields(a).1 == 15 || f.fields(b).1 == 15 {
                        continue; // the reserved exponent is never produced
                    }
                    let sum = f.to_f64(f.add(a, b, &mut ctr));
                    let want = round_to_format(x + y, &f);
                    assert!(
                        same(sum, want) || (sum == 0.0 && want == 0.0 && x + y == 0.0),
                        "{r:?} {s:?}: {x} + {y} = {sum}, want {want}"
                    );
                    let prod = f.to_f64(f.mul(a, b, &mut ctr));
                    let want = round_to_format(x * y, &f);
                    assert!(
                        same(prod, want),
                        "{r:?} {s:?}: {x} × {y} = {prod}, want {want}"
                    );
                }
            }
        }
    }
}

/// Every positive e4m3 / e5m2 value: rcp bit-exact against f64, rsq within ½ ulp.
#[test]
fn tiny_rcp_rsq_exhaustive() {
    for (e, m) in [(4, 3), (5, 2), (3, 6)] {
        for s in [Subnormals::Keep, Subnormals::Flush] {
            let f = fmt(e, m, Rounding::NearestEven, s);
            let mut ctr = Counters::default();
            for a in all_words(&f) {
                let x = f.to_f64(a);
                if x <= 0.0 || f.fields(a).1 == (1 << e) - 1 {
                    continue;
                }
                let got = f.to_f64(f.rcp(a, &mut ctr));
                assert_eq!(got, round_to_format(1.0 / x, &f), "e{e}m{m} 1/{x}");
                check_rsq(&f, a, &mut ctr);
            }
        }
    }
}

fn ulp_at(v: f64, f: &FloatFormat) -> f64 {
    let e = v.abs().log2().floor() as i32;
    2f64.powi(e.max(f.emin()) - f.mant_bits as i32)
}

fn check_rsq(f: &FloatFormat, a: Fp, ctr: &mut Counters) {
    let x = f.to_f64(a);
    let got = f.to_f64(f.rsq(a, ctr));
    let exact = 1.0 / x.sqrt();
    let max = f.to_f64(f.max_finite(false));
    if exact > max {
        assert_eq!(got, max);
        return;
    }
    // One rounding: ½ ulp to nearest, < 1 ulp truncating.
    let step = match f.rounding {
        Rounding::NearestEven => 0.5,
        Rounding::Truncate => 1.0,
    };
    let half = step * ulp_at(exact, f) * (1.0 + 2f64.powi(-40));
    assert!(
        (got - exact).abs() <= half + exact * 2f64.powi(-50),
        "rsq({x}) = {got}, exact {exact}"
    );
}

/// A random word: mostly ordinary values, sometimes zeros, subnormals, the extremes
/// and values near 1 (so sums cancel).
fn random_word(f: &FloatFormat, rng: &mut ChaCha8Rng) -> Fp {
    let top = (1u32 << f.exp_bits) - 2; // largest ordinary exponent field
    let mant = rng.random_range(0..1u64 << f.mant_bits);
    let neg = rng.random::<bool>();
    let e = match rng.random_range(0..10) {
        0 => 0,                                                // zero / subnormal
        1 => top,                                              // largest binade
        2 => 1,                                                // smallest normal binade
        3..=5 => f.bias() as u32 + rng.random_range(0..3) - 1, // near 1
        _ => rng.random_range(1..=top),
    };
    let mant = if rng.random_range(0..20) == 0 {
        0
    } else {
        mant
    };
    f.pack(neg, e, mant)
}

/// IEEE single: bit for bit with f32 add and mul (10⁶ pairs each), subnormals kept.
#[test]
fn single_matches_f32() {
    let f = fmt(8, 23, Rounding::NearestEven, Subnormals::Keep);
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    let mut ctr = Counters::default();
    let (mut adds, mut muls) = (0u64, 0u64);
    for _ in 0..1_300_000 {
        let (a, b) = (random_word(&f, &mut rng), random_word(&f, &mut rng));
        let (x, y) = (f32::from_bits(a.0 as u32), f32::from_bits(b.0 as u32));
        for (sym, want, got, count) in [
            ("+", x + y, f.add(a, b, &mut ctr), &mut adds),
            ("×", x * y, f.mul(a, b, &mut ctr), &mut muls),
        ] {
            if want.is_finite() {
                let got = got.0 as u32;
                assert_eq!(
                    got,
                    want.to_bits(),
                    "{x:e} {sym} {y:e}: {:e} vs {want:e}",
                    f32::from_bits(got)
                );
                *count += 1;
            }
        }
    }
    assert!(
        adds >= 1_000_000 && muls >= 1_000_000,
        "{adds} adds, {muls} muls"
    );
}

/// Random pairs in e8m23 (truncate and flush), e5m10 and e6m17 against exactly
/// rounded f64, with rcp and rsq.
#[test]
fn random_formats_match_f64() {
    let formats = [
        fmt(8, 23, Rounding::NearestEven, Subnormals::Flush),
        fmt(8, 23, Rounding::Truncate, Subnormals::Keep),
        fmt(5, 10, Rounding::NearestEven, Subnormals::Keep),
        fmt(6, 17, Rounding::Truncate, Subnormals::Flush),
        fmt(11, 24, Rounding::NearestEven, Subnormals::Keep),
    ];
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for f in formats {
        let mut ctr = Counters::default();
        for _ in 0..100_000 {
            let (a, b) = (random_word(&f, &mut rng), random_word(&f, &mut rng));
            let (x, y) = (f.to_f64(a), f.to_f64(b));
            let sum = f.to_f64(f.add(a, b, &mut ctr));
            let want = exact_sum_rounded(x, y, &f);
            assert!(
                same(sum, want) || (sum == 0.0 && want == 0.0),
                "{f:?}: {x:e} + {y:e} = {sum:e}, want {want:e}"
            );
            let prod = f.to_f64(f.mul(a, b, &mut ctr));
            assert!(
                same(prod, round_to_format(x * y, &f)),
                "{f:?}: {x:e} × {y:e}"
            );
            if x > 0.0 {
                let r = f.to_f64(f.rcp(a, &mut ctr));
                assert_eq!(r, round_to_format(1.0 / x, &f), "{f:?}: 1/{x:e}");
                check_rsq(&f, a, &mut ctr);
            }
        }
    }
}

/// Saturation and underflow are counted; from_f64 refuses NaN/∞ naming the field.
#[test]
fn counters_and_host_edge() {
    let f = FloatFormat::new(5, 10).unwrap();
    let mut ctr = Counters::default();
    let big = f.from_f64("x", 60000.0, &mut ctr).unwrap();
    let _ = f.mul(big, big, &mut ctr);
    assert_eq!(ctr.saturations, 1);
    let tiny = f.from_f64("x", 1e-4, &mut ctr).unwrap();
    let z = f.mul(tiny, tiny, &mut ctr);
    assert!(f.is_zero(z));
    assert_eq!(ctr.underflows, 1);
    let e = f.from_f64("vertex_lighting.shininess", f64::NAN, &mut ctr);
    assert_eq!(e.unwrap_err().field(), "vertex_lighting.shininess");
    assert!(f.from_f64("x", f64::INFINITY, &mut ctr).is_err());
    assert_eq!(
        FloatFormat::new(1, 10).unwrap_err().field(),
        "float_format.exp_bits"
    );
    assert_eq!(
        FloatFormat::new(8, 40).unwrap_err().field(),
        "float_format.mant_bits"
    );
    // 0 → rcp/rsq saturate (counted), no NaN anywhere.
    let mut c2 = Counters::default();
    assert_eq!(f.rcp(f.zero(), &mut c2), f.max_finite(false));
    assert_eq!(f.rsq(f.zero(), &mut c2), f.max_finite(false));
    assert_eq!(c2.saturations, 2);
}

/// pow against f64 within the derived bound (module docs): t = s·log2 x is off by at
/// most s·ε_L + 3u|t| (+ a u² term), exp2 by η_exp, the result by one rounding u.
#[test]
fn pow_within_derived_bound() {
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    for f in [
        FloatFormat::new(8, 23).unwrap(),
        FloatFormat::new(5, 10).unwrap(),
        FloatFormat::new(5, 7).unwrap(),
        FloatFormat::new(8, 4).unwrap(),
    ] {
        let u = 2f64.powi(f.unit_roundoff_log2());
        let mut ctr = Counters::default();
        for _ in 0..20_000 {
            let x = rng.random_range(0.0..1.0f64).powi(rng.random_range(1..4));
            let s = match rng.random_range(0..3) {
                0 => rng.random_range(0.0..2.0),
                1 => rng.random_range(0.0..128.0),
                _ => rng.random_range(0.0..1.0e4f64),
            };
            let xf = f.from_f64("x", x, &mut ctr).unwrap();
            let sf = f.from_f64("s", s, &mut ctr).unwrap();
            let (xv, sv) = (f.to_f64(xf), f.to_f64(sf));
            let got = f.to_f64(f.pow(xf, sf, &mut ctr));
            let want = if sv == 0.0 {
                1.0
            } else if xv == 0.0 {
                0.0
            } else {
                xv.powf(sv)
            };
            let t = if want == 0.0 {
                0.0
            } else {
                (sv * xv.log2()).abs()
            };
            let dt = sv * f.log2_abs_error() + (3.0 * u + 3.0 * u * u) * t;
            let rel = (1.0 + (dt * std::f64::consts::LN_2).exp_m1())
                * (1.0 + f.exp2_rel_error())
                * (1.0 + u)
                - 1.0;
            // Below the format's range the result may flush: allow the smallest normal.
            let floor = 2f64.powi(f.emin());
            assert!(
                (got - want).abs() <= rel * want + floor,
                "{f:?}: {xv}^{sv} = {got}, want {want} (rel bound {rel})"
            );
        }
    }
}
