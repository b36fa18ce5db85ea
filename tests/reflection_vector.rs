//! reflection_vector against its f64 twin (n̂, v̂, r = 2(n̂·v̂)n̂ − v̂, t = r·λ,
//! coord = (t + 1)/2 · s), under a bound derived from the configured widths.
//!
//! Bound derivation (also in docs/datasheets/reflection_vector.md). Write A =
//! rsqrt_addr_bits, R = rsqrt_bits, N = newton_frac_bits, B = norm_bits, L =
//! lambda_bits, F = coord_frac_bits, s = 2^side_log2, S = 2^(2k)·m (m ∈ [1, 4)) the
//! squared length of a raw vector (exact), y the unit's 1/√m and e = |y·√m − 1|.
//! * Table: m lies in an interval of relative half-width x < 2^−A around the
//!   interval's midpoint c (parity 0: width 2^−(A−1) from ≥ 1; parity 1: 2^−(A−2) from
//!   ≥ 2), so |√(m/c) − 1| ≤ x/(1 + √(1 − x)); the entry is 1/√c + δ with |δ| ≤
//!   2^−(R+1) (round to nearest) or 2^−R when A ≥ R (then entry 0 rounds up to 2^R and
//!   is clamped), and |δ·√m| ≤ 2|δ|:  e₀ ≤ 2^−A/(1 + √(1 − 2^−A)) + 2·δ_max.
//! * Newton (y' = y(3 − m_N·q)/2, q = y² rounded (|ρ₁| ≤ 2^−(N+1)), m_N = m truncated
//!   (0 ≤ μ < 2^−N), d rounded (|ρ₂| ≤ 2^−(N+1)), y' rounded (|ρ₃| ≤ 2^−(N+1))):
//!   y'√m = (1 + e)(3 − (1 + e)²)/2 + (1 + e)/2·ε + ρ₃√m with
//!   ε = −mρ₁ + μy² + μρ₁ + ρ₂, y² ≤ (1 + e)², m < 4, so
//!   e₁ ≤ e₀²(3/2 + e₀/2) + (1 + e₀)/2·(2^−(N−1) + (1 + e₀)²2^−N + 2^−(2N+1) + 2^−(N+1))
//!   + 2^−N   (valid while d stays positive, e₀ < √3 − 1).
//! * Block normalisation to s(P) mantissas x' = ⌊x/2^sh⌋ (only when P ≤ W can sh > 0):
//!   then |x'| ≥ max|x'_i| ≥ 2^(P−2) and |x' − x/2^sh| < √3, and for any a, b ≠ 0
//!   |a/|a| − b/|b|| ≤ 2|a − b|/|b|, so the mantissa's direction n̂'' is within
//!   η = √3·2^−(P−3) of n̂ (per component and Euclidean); η = 0 when P > W.
//! * n̂_i = x'_i·y·2^−k rounded to B bits: n̂'_i = n̂''_i(1 + e_y) + ρ, |ρ| ≤ h = 2^−(B+1):
//!   |Δn̂_i| ≤ e + η + h, |Δn̂| ≤ a = e + η + √3·h (Euclidean); the same for v̂ (and for
//!   n̂ := v̂ when n = 0); |n̂'_i| ≤ 1 + e + h.
//! * d = n̂'·v̂' rounded to B bits: |Δd| ≤ b = 2a + a² + h (Cauchy–Schwarz, |d| ≤ 1).
//! * r'_i = 2 d' n̂'_i − v̂'_i rounded: Δr_i = 2(Δd·n̂'_i + d·Δn̂_i) − Δv̂_i + ρ, so
//!   |Δr_i| ≤ c_r = 2b(1 + e + h) + 3(e + η + h) + h.
//! * t = r'·λ_q exactly; λ_q from the host helper is within 2^−(L+1) of λ and |r_i| ≤ 1:
//!   |Δt_i| ≤ c_r + 2^−(L+1).
//! * coord = (t + 1)/2·s rounded to nearest in F bits:
//!   |Δcoord| ≤ s/2·(c_r + 2^−(L+1)) + 2^−(F+1) texels. A saturating clamp is
//!   1-Lipschitz, so the unit's word is compared with the twin clamped to the word.
//! * f64 slack (derived, not a fudge): the twin's handful of f64 operations on values
//!   ≤ 2s are within s·2^−48 texels.

mod common;

use glare_pipeline::reference::reflection_vector::{reflect, reflection_coord};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::units::reflection_vector::{
    ReflectionVector, ReflectionVectorConfig, ReflectionVectorIn,
};
use rtl_model::units::texture_sampler::texel_coord_from_normalized;
use rtl_model::{Counters, Unit, UnitSummary};

fn p2(e: i32) -> f64 {
    (e as f64).exp2()
}

#[allow(clippy::too_many_arguments)]
fn cfg(
    lambda: u32,
    a: u32,
    r: u32,
    newton: Option<u32>,
    b: u32,
    mant: u32,
    side: u32,
    coord_int: u32,
    coord_frac: u32,
) -> ReflectionVectorConfig {
    ReflectionVectorConfig {
        in_int_bits: 16,
        in_frac_bits: 16,
        lambda_bits: lambda,
        rsqrt_addr_bits: a,
        rsqrt_bits: r,
        newton: newton.is_some(),
        newton_frac_bits: newton.unwrap_or(18),
        norm_bits: b,
        mant_bits: mant,
        side_log2: side,
        coord_int_bits: coord_int,
        coord_frac_bits: coord_frac,
    }
}

/// (name, config): the default, a wide one, a mid one without Newton, the NARROW one
/// (A = 4, R = 6, B = 8, L = 6, no Newton) and a narrow one with a coarse Newton step
/// and a small map, plus one whose coordinate word is too narrow for the map (saturates).
fn bound_configs() -> Vec<(&'static str, ReflectionVectorConfig)> {
    vec![
        ("default", ReflectionVectorConfig::geforce3()),
        ("wide", cfg(16, 10, 16, Some(28), 22, 27, 9, 16, 12)),
        ("mid, no Newton", cfg(10, 10, 14, None, 12, 17, 7, 16, 8)),
        ("narrow", cfg(6, 4, 6, None, 8, 10, 7, 16, 8)),
        ("narrow + Newton", cfg(8, 3, 5, Some(10), 10, 12, 5, 8, 4)),
        ("saturating word", cfg(12, 8, 11, Some(18), 14, 19, 7, 7, 8)),
    ]
}

/// Derived bound on e = |y·√m − 1|.
fn rsqrt_bound(c: &ReflectionVectorConfig) -> f64 {
    let (a, r, n) = (
        c.rsqrt_addr_bits as i32,
        c.rsqrt_bits as i32,
        c.newton_frac_bits as i32,
    );
    let x = p2(-a);
    let delta = if a >= r { p2(-r) } else { p2(-(r + 1)) };
    let e0 = x / (1.0 + (1.0 - x).sqrt()) + 2.0 * delta;
    if !c.newton {
        return e0;
    }
    let eps = p2(-(n - 1)) + (1.0 + e0).powi(2) * p2(-n) + p2(-(2 * n + 1)) + p2(-(n + 1));
    e0 * e0 * (1.5 + 0.5 * e0) + (1.0 + e0) / 2.0 * eps + p2(-n)
}

/// Derived bound η on the direction error of the block normalisation's truncation
/// (0 when the mantissa holds the whole input word).
fn block_bound(c: &ReflectionVectorConfig) -> f64 {
    if c.mant_bits > c.in_int_bits + c.in_frac_bits {
        0.0
    } else {
        3f64.sqrt() * p2(-(c.mant_bits as i32 - 3))
    }
}

/// Derived per-component bound c_r on |r'_i − r_i|.
fn r_bound(c: &ReflectionVectorConfig) -> f64 {
    let e = rsqrt_bound(c);
    let eta = block_bound(c);
    let h = p2(-(c.norm_bits as i32 + 1));
    let a = e + eta + 3f64.sqrt() * h;
    let b = 2.0 * a + a * a + h;
    2.0 * b * (1.0 + e + h) + 3.0 * (e + eta + h) + h
}

/// Derived bound on |coord − twin| in texels.
fn coord_bound(c: &ReflectionVectorConfig) -> f64 {
    let s = p2(c.side_log2 as i32);
    s / 2.0 * (r_bound(c) + p2(-(c.lambda_bits as i32 + 1))) + p2(-(c.coord_frac_bits as i32 + 1))
}

/// f64 slack of the twin (see the header).
fn slack(c: &ReflectionVectorConfig) -> f64 {
    p2(c.side_log2 as i32) * p2(-48)
}

/// Check one host input (f64 n, e, λ quantised by the unit's helper) against the twin
/// evaluated on the quantised n, e and the f64 λ. Returns worst |err| / bound.
fn check(u: &ReflectionVector, n: [f64; 3], e: [f64; 3], lambda: f64) -> f64 {
    let c = u.config();
    let mut qc = Counters::default();
    let inp = u.quantise_in(n, e, lambda, &mut qc).unwrap();
    let k = p2(-(c.in_frac_bits as i32));
    let (nq, eq) = (inp.n.map(|x| x as f64 * k), inp.e.map(|x| x as f64 * k));
    let s = u.side() as f64;
    let want = reflection_coord(nq, eq, lambda, s);
    let mut ctr = Counters::default();
    let parts = u.parts(&inp, &mut ctr);
    let out = u.kernel(&mut (), &inp, &mut Counters::default());
    assert_eq!(out, parts.out);
    let zeros = u64::from(parts.out.zero_n) + u64::from(parts.out.zero_e);
    assert_eq!(ctr.underflows, zeros);
    assert_eq!(ctr.table_reads, 2 - zeros);
    let bound = coord_bound(&c) + slack(&c);
    let lsb = p2(-(c.coord_frac_bits as i32));
    let ow = c.coord_int_bits + c.coord_frac_bits;
    let (lo, hi) = (-p2(ow as i32 - 1) * lsb, (p2(ow as i32 - 1) - 1.0) * lsb);
    let mut worst = 0.0f64;
    let mut rails = 0;
    #[allow(clippy::needless_range_loop)] // ax indexes four arrays and names the axis
    for ax in 0..3 {
        let got = u.coord_to_f64(out.coord[ax]);
        let err = (got - want[ax].clamp(lo, hi)).abs();
        assert!(
            err <= bound,
            "{c:?}: n {nq:?} e {eq:?} λ {lambda}: axis {ax} got {got}, want {} \
             (err {err:e} > bound {bound:e})",
            want[ax]
        );
        worst = worst.max(err / bound);
        rails += u64::from(got == lo || got == hi);
        // The renderer's f64 path: round((t + 1)/2 · s) into the sampler word; the unit
        // is within the bound + ½ LSB of it.
        let mut rc = Counters::default();
        let t = reflect(nq, eq)[ax] * lambda;
        let word = texel_coord_from_normalized(
            (t + 1.0) * 0.5,
            u.side(),
            c.coord_int_bits,
            c.coord_frac_bits,
            &mut rc,
        )
        .unwrap();
        let d = (out.coord[ax] as f64 - word as f64).abs() * lsb;
        assert!(
            d <= bound + lsb / 2.0,
            "{c:?}: renderer word {word} vs {}",
            out.coord[ax]
        );
    }
    assert!(
        ctr.saturations <= rails,
        "saturations {} > rails {rails}",
        ctr.saturations
    );
    // |r'| ≈ 1 (not both vectors zero): ||r'| − 1| ≤ |Δr| ≤ √3·c_r.
    if !(parts.out.zero_n && parts.out.zero_e) {
        let b = p2(-(c.norm_bits as i32));
        let len = parts
            .r
            .iter()
            .map(|&x| (x as f64 * b).powi(2))
            .sum::<f64>()
            .sqrt();
        let rb = 3f64.sqrt() * r_bound(&c);
        assert!((len - 1.0).abs() <= rb, "{c:?}: |r| = {len} (bound {rb:e})");
    }
    worst
}

/// n, e, λ from uniform numbers: a random direction with magnitude 10^(−3 … 3), e
/// general, grazing (e ⟂ n plus a little n) or back-facing (e·n < 0).
fn sample(
    dn: [f64; 3],
    de: [f64; 3],
    mag: (f64, f64),
    kind: u32,
    graze: f64,
) -> ([f64; 3], [f64; 3]) {
    let unit = |d: [f64; 3]| {
        let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if l < 1e-9 {
            [0.0, 0.0, 1.0]
        } else {
            d.map(|x| x / l)
        }
    };
    let (nh, mut eh) = (unit(dn), unit(de));
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    match kind {
        1 => {
            // Grazing: remove the n component, add graze·n (|graze| ≤ 1e-3).
            let d = dot(nh, eh);
            eh = unit([0, 1, 2].map(|k| eh[k] - d * nh[k] + graze * nh[k]));
        }
        // Back-facing.
        2 if dot(nh, eh) > 0.0 => eh = eh.map(|x| -x),
        _ => {}
    }
    let (mn, me) = (10f64.powf(mag.0), 10f64.powf(mag.1));
    (nh.map(|x| x * mn), eh.map(|x| x * me))
}

#[test]
fn worst_error_per_config_within_the_derived_bound() {
    // A seeded sweep (the proptest below is the ≥ 1000-case check): prints worst/bound.
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for (name, c) in bound_configs() {
        let u = c.build().unwrap();
        let mut worst = 0.0f64;
        for i in 0..40_000u32 {
            let mut v = || [0; 3].map(|_: i32| rng.random_range(-1.0..1.0));
            let (dn, de) = (v(), v());
            let mag = (rng.random_range(-3.0..3.0), rng.random_range(-3.0..3.0));
            let graze = rng.random_range(-1e-3..1e-3);
            let lambda = if i % 7 == 0 {
                1.0
            } else {
                rng.random_range(0.0..=1.0)
            };
            let (n, e) = sample(dn, de, mag, i % 3, graze);
            worst = worst.max(check(&u, n, e, lambda));
        }
        println!(
            "{name:>16}: bound {:.4} texel (c_r {:.3e}, e_rsqrt {:.3e}), worst/bound {worst:.3}",
            coord_bound(&c),
            r_bound(&c),
            rsqrt_bound(&c)
        );
    }
}

#[test]
fn rsqrt_error_within_derived_bound_exhaustively() {
    // Every S in 1 .. 2^20 (m over every table interval at many offsets).
    for (name, c) in bound_configs() {
        let u = c.build().unwrap();
        let b = rsqrt_bound(&c);
        let mut worst = 0.0f64;
        let mut ctr = Counters::default();
        for s in 1u64..(1 << 20) {
            let r = u.rsqrt(s, &mut ctr);
            let m = s as f64 / p2(2 * r.k as i32);
            let e = (r.y as f64 / p2(r.frac as i32) * m.sqrt() - 1.0).abs();
            assert!(e <= b, "{name}: S = {s}: e = {e:e} > {b:e}");
            worst = worst.max(e);
        }
        assert_eq!(ctr.table_reads, (1 << 20) - 1);
        assert_eq!(ctr.saturations, 0);
        println!(
            "{name:>16}: max |y√m − 1| = {worst:.3e}, bound {b:.3e} ({:.3})",
            worst / b
        );
    }
}

#[test]
fn exhaustive_3_bit_vectors_within_bound() {
    // W = 3 (components −4 ..= 3): all 2^18 (n, e) pairs at λ = 1, zero vectors included.
    for c in [
        ReflectionVectorConfig {
            in_int_bits: 3,
            in_frac_bits: 0,
            ..cfg(6, 4, 6, None, 8, 10, 7, 16, 8)
        },
        ReflectionVectorConfig {
            in_int_bits: 2,
            in_frac_bits: 1,
            ..ReflectionVectorConfig::geforce3()
        },
    ] {
        let u = c.build().unwrap();
        let lsb = p2(-(c.in_frac_bits as i32));
        let mut worst = 0.0f64;
        for code in 0u32..(1 << 18) {
            let comp = |j: u32| (((code >> (3 * j)) & 7) as i64 - 4) as f64 * lsb;
            let n = [comp(0), comp(1), comp(2)];
            let e = [comp(3), comp(4), comp(5)];
            worst = worst.max(check(&u, n, e, 1.0));
        }
        println!("exhaustive W = 3 {c:?}: worst/bound {worst:.3}");
    }
}

/// The batch path (the unit's 64-bit form where the config has it, else the general
/// kernel) against the span and tick drivers: exhaustively at W = 3 (all 2^18 (n, e)
/// pairs, zero vectors included, λ cycling through every u1.L wire value of L = 2,
/// clamps included) for a 64-bit-form config and one that falls back (N = 30).
#[test]
fn batch_path_agrees_exhaustively_at_3_bits() {
    for newton_frac_bits in [18, 29, 30] {
        let c = ReflectionVectorConfig {
            in_int_bits: 3,
            in_frac_bits: 0,
            lambda_bits: 2,
            newton_frac_bits,
            ..ReflectionVectorConfig::geforce3()
        };
        let u = c.build().unwrap();
        let inputs: Vec<ReflectionVectorIn> = (0u32..(1 << 18))
            .map(|code| {
                let comp = |j: u32| ((code >> (3 * j)) & 7) as i64 - 4;
                ReflectionVectorIn {
                    n: [comp(0), comp(1), comp(2)],
                    e: [comp(3), comp(4), comp(5)],
                    lambda: code % 8,
                }
            })
            .collect();
        common::assert_drivers_agree(&u, (), &inputs);
    }
}

/// The batch path on the renderer's words: the interpolator's s16.16 n and e codes
/// (unit-ish normals, eye vectors up to 8 long, zero vectors, words that wrap the
/// 32-bit wires) and λ codes around 1, at the GeForce3 config and at the edges of the
/// 64-bit form (N = 29 with and without Newton, P = 32, R = 24, every output shift
/// sign).
#[test]
fn batch_path_agrees_on_render_words() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5eed_0f15);
    let g = ReflectionVectorConfig::geforce3();
    for c in [
        g,
        ReflectionVectorConfig {
            newton_frac_bits: 29,
            rsqrt_bits: 24,
            mant_bits: 32,
            ..g
        },
        ReflectionVectorConfig {
            newton: false,
            rsqrt_bits: 24,
            mant_bits: 32,
            norm_bits: 24,
            lambda_bits: 16,
            ..g
        },
        ReflectionVectorConfig {
            norm_bits: 2,
            lambda_bits: 1,
            side_log2: 12,
            coord_frac_bits: 16,
            ..g
        },
        ReflectionVectorConfig {
            newton_frac_bits: 30,
            ..g
        },
    ] {
        let u = c.build().unwrap();
        let one = 1i64 << 16;
        let inputs: Vec<ReflectionVectorIn> = (0..20_000)
            .map(|i| {
                let mut v = |scale: i64| -> [i64; 3] {
                    match i % 11 {
                        0 => [0; 3],
                        1 => [
                            rng.random::<i64>(),
                            rng.random::<i64>(),
                            rng.random::<i64>(),
                        ],
                        _ => std::array::from_fn(|_| rng.random_range(-scale * one..=scale * one)),
                    }
                };
                let n = v(1);
                let e = v(8);
                ReflectionVectorIn {
                    n,
                    e,
                    lambda: rng.random_range(0..=(1u32 << (c.lambda_bits + 1))),
                }
            })
            .collect();
        common::assert_drivers_agree(&u, (), &inputs);
    }
}

#[test]
fn zero_vectors_follow_the_rule_and_are_counted() {
    let u = ReflectionVector::geforce3();
    let one = 1u32 << 12;
    let e = [0i64, 0, 3 << 16];
    // n = 0 → r = v̂ = +z: coord_z = s = 128 texels (λ = 1), x, y at the centre.
    let mut ctr = Counters::default();
    let o = u.kernel(
        &mut (),
        &ReflectionVectorIn {
            n: [0; 3],
            e,
            lambda: one,
        },
        &mut ctr,
    );
    assert!(o.zero_n && !o.zero_e);
    assert_eq!(ctr.underflows, 1);
    assert_eq!(ctr.table_reads, 1);
    let c = o.coord.map(|x| u.coord_to_f64(x));
    assert!((c[2] - 128.0).abs() <= coord_bound(&u.config()));
    assert!((c[0] - 64.0).abs() <= coord_bound(&u.config()));
    // Both zero → the centre exactly, two underflows, no ROM read.
    let mut ctr = Counters::default();
    let o = u.kernel(
        &mut (),
        &ReflectionVectorIn {
            n: [0; 3],
            e: [0; 3],
            lambda: one,
        },
        &mut ctr,
    );
    assert_eq!(o.coord, [64 << 8; 3]);
    assert_eq!((ctr.underflows, ctr.table_reads), (2, 0));
    // λ above 1 clamps (counted); a λ of 0 gives the centre whatever r is.
    let mut ctr = Counters::default();
    let n = [1 << 16, 0, 0];
    let a = u.kernel(
        &mut (),
        &ReflectionVectorIn {
            n,
            e,
            lambda: one + 5,
        },
        &mut ctr,
    );
    let b = u.kernel(
        &mut (),
        &ReflectionVectorIn { n, e, lambda: one },
        &mut Counters::default(),
    );
    assert_eq!(a, b);
    assert_eq!(ctr.saturations, 1);
    let z = u.kernel(
        &mut (),
        &ReflectionVectorIn { n, e, lambda: 0 },
        &mut Counters::default(),
    );
    assert_eq!(z.coord, [64 << 8; 3]);
}

#[test]
fn saturating_word_counts_its_clamps() {
    // s7.8 cannot hold 64 texels and more: +z reflections at λ = 1 clamp.
    let c = cfg(12, 8, 11, Some(18), 14, 19, 7, 7, 8);
    let u = c.build().unwrap();
    let mut ctr = Counters::default();
    let inp = ReflectionVectorIn {
        n: [0, 0, 1 << 16],
        e: [0, 0, 1 << 16],
        lambda: 1 << 12,
    };
    let o = u.kernel(&mut (), &inp, &mut ctr);
    assert_eq!(o.coord[2], (1 << 14) - 1);
    assert_eq!(ctr.saturations, 3); // x, y at 64 texels too
}

#[test]
fn lambda_from_interpolator_code() {
    let u = ReflectionVector::geforce3();
    let mut ctr = Counters::default();
    assert_eq!(u.lambda_from_code(1 << 16, 16, &mut ctr), 1 << 12);
    assert_eq!(u.lambda_from_code(1 << 15, 16, &mut ctr), 1 << 11);
    assert_eq!(u.lambda_from_code(8, 16, &mut ctr), 1); // 8/65536 = ½ LSB → rounds up
    assert_eq!(ctr.saturations, 0);
    assert_eq!(u.lambda_from_code(-100, 16, &mut ctr), 0);
    assert_eq!(u.lambda_from_code(3 << 16, 16, &mut ctr), 1 << 12);
    assert_eq!(ctr.saturations, 2);
}

#[test]
fn defaults_summary() {
    let u = ReflectionVector::geforce3();
    let s = UnitSummary::of(&u);
    println!(
        "reflection_vector defaults: latency {} II {} gates {:.0} NAND2, ROM bits {}",
        s.latency, s.ii, s.gates_nand2, s.ram_bits
    );
    for (p, g) in &s.breakdown {
        println!("  {p}: {g:.0}");
    }
    let c = u.config();
    println!(
        "bound {:.5} texel ({:.1} LSB of s16.8), c_r {:.3e}, e_rsqrt {:.3e}",
        coord_bound(&c),
        coord_bound(&c) * 256.0,
        r_bound(&c),
        rsqrt_bound(&c)
    );
    assert_eq!((s.latency, s.ii), (12, 1));
    assert_eq!(s.ram_bits, 2 * 256 * 11);
    let no_newton = ReflectionVectorConfig { newton: false, ..c }
        .build()
        .unwrap();
    assert_eq!(no_newton.timing().latency, 9);
}

fn any_dir() -> impl Strategy<Value = [f64; 3]> {
    [-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0]
}

/// A valid config from sane ranges (for the driver test).
fn valid_cfg() -> impl Strategy<Value = ReflectionVectorConfig> {
    (
        (1u32..=16, 0u32..=16),
        1u32..=16,
        (1u32..=12, 2u32..=24),
        (any::<bool>(), 4u32..=30),
        (2u32..=24, 4u32..=32),
        0u32..=12,
        (1u32..=16, 0u32..=16),
    )
        .prop_map(
            |((ii, fi), l, (a, r), (nw, n), (b, mant), side, (ci, cf))| ReflectionVectorConfig {
                in_int_bits: ii,
                in_frac_bits: fi,
                lambda_bits: l,
                rsqrt_addr_bits: a,
                rsqrt_bits: r,
                newton: nw,
                newton_frac_bits: n,
                norm_bits: b,
                mant_bits: mant,
                side_log2: side,
                coord_int_bits: ci,
                coord_frac_bits: cf,
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    #[test]
    fn within_bound_vs_twin(
        ci in 0usize..6,
        dn in any_dir(),
        de in any_dir(),
        mag in (-3.0f64..3.0, -3.0f64..3.0),
        kind in 0u32..3,
        graze in -1e-3f64..1e-3,
        lambda in prop_oneof![Just(1.0f64), Just(0.0f64), 0.0f64..=1.0],
    ) {
        let (_, c) = bound_configs()[ci];
        let u = c.build().unwrap();
        let (n, e) = sample(dn, de, mag, kind, graze);
        check(&u, n, e, lambda);
    }

    #[test]
    fn tick_and_span_drivers_agree(
        c in valid_cfg(),
        words in prop::collection::vec(
            ([any::<i64>(), any::<i64>(), any::<i64>()], [any::<i64>(), any::<i64>(), any::<i64>()], any::<u32>()),
            0..24,
        ),
    ) {
        let u = c.build().unwrap();
        let inputs: Vec<ReflectionVectorIn> = words
            .iter()
            .map(|&(n, e, lambda)| ReflectionVectorIn { n, e, lambda })
            .collect();
        common::assert_drivers_agree(&u, (), &inputs);
    }

    #[test]
    fn random_configs_never_panic_and_errors_name_the_field(
        ii in 0u32..40, fi in 0u32..40, l in 0u32..40, a in 0u32..40, r in 0u32..40,
        nw in any::<bool>(), n in 0u32..40, b in 0u32..40, mant in 0u32..40, side in 0u32..40,
        ci in 0u32..40, cf in 0u32..40,
        n_in in [any::<i64>(), any::<i64>(), any::<i64>()],
        e_in in [any::<i64>(), any::<i64>(), any::<i64>()],
        lam in any::<u32>(),
    ) {
        let c = ReflectionVectorConfig {
            in_int_bits: ii, in_frac_bits: fi, lambda_bits: l, rsqrt_addr_bits: a,
            rsqrt_bits: r, newton: nw, newton_frac_bits: n, norm_bits: b, mant_bits: mant,
            side_log2: side,
            coord_int_bits: ci, coord_frac_bits: cf,
        };
        match c.build() {
            Ok(u) => {
                let mut ctr = Counters::default();
                let inp = ReflectionVectorIn { n: n_in, e: e_in, lambda: lam };
                let _ = u.kernel(&mut (), &inp, &mut ctr);
                let _ = u.cost();
                let _ = u.in_signals(&inp);
            }
            Err(e) => prop_assert!(
                e.field().starts_with("reflection_vector."),
                "field {}",
                e.field()
            ),
        }
    }

    #[test]
    fn non_finite_host_inputs_are_errors_naming_the_field(
        bad in prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY)],
        k in 0usize..3,
        which in 0u32..3,
    ) {
        let u = ReflectionVector::geforce3();
        let mut n = [0.5, 0.25, 1.0];
        let mut e = [1.0, -2.0, 3.0];
        let mut lambda = 0.5;
        let field = match which {
            0 => { n[k] = bad; "reflection_vector.n" }
            1 => { e[k] = bad; "reflection_vector.e" }
            _ => { lambda = bad; "reflection_vector.lambda" }
        };
        let err = u.quantise_in(n, e, lambda, &mut Counters::default()).unwrap_err();
        prop_assert_eq!(err.field(), field);
    }

    #[test]
    fn twin_never_nan(
        n in [any::<f64>(), any::<f64>(), any::<f64>()],
        e in [any::<f64>(), any::<f64>(), any::<f64>()],
        lambda in any::<f64>(),
    ) {
        let n = n.map(|x| if x.is_finite() { x } else { 0.0 });
        let e = e.map(|x| if x.is_finite() { x } else { 1.0 });
        let c = reflection_coord(n, e, lambda, 128.0);
        prop_assert!(c.iter().all(|x| x.is_finite()), "{c:?}");
    }
}
