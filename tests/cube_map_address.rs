//! cube_map_address against its f64 twin (the exact OpenGL cube-map mapping of the
//! direction d = c − s/2), under a bound derived from the configured widths.
//!
//! Bound derivation (also in docs/units.md, `## cube_map_address`). A = rcp_addr_bits,
//! R = rcp_bits, N = newton_frac_bits, F = 2^face_log2, Fo = coord_frac_bits; the
//! input words are the same integers for unit and twin, so D = 2c − s·2^Fi, the
//! major-axis comparisons, the face and sc, tc are EXACT (the face must match).
//! |ma| = 2^p·m, m ∈ [1, 2); y ≈ 1/m; E bounds |m·y − 1|.
//! * Table: m lies in address j's interval [c − h, c + h), h = 2^−(A+1), c its
//!   midpoint (exact also when p < A: the address is then m's exact bits); the entry
//!   is 1/c + δ, |δ| ≤ δ_max = 2^−(R+1) (round to nearest), or 2^−R when A ≥ R (an
//!   entry whose 2^R/c rounds to 2^R is clamped to 2^R − 1, one LSB below 2^R/c at
//!   most). m·y − 1 = (m − c)/c + m·δ, m < 2, c > 1: E₀ = 2^−(A+1) + 2·δ_max.
//! * Newton (m_N = m − μ, 0 ≤ μ < 2^−N; q = m_N·y₀ + ρ₁; y₁ = y₀(2 − q) + ρ₂;
//!   |ρ| ≤ 2^−(N+1); y₀ < 1, m < 2):
//!   m·y₁ − 1 = −e₀² + (1 + e₀)(μ·y₀ − ρ₁) + m·ρ₂, so
//!   E₁ = E₀² + (1 + E₀)·1.5·2^−N + 2^−N   (d = 2 − q stays in (0, 2) while E₀ < 1).
//! * sc·y·2^−p = (sc/|ma|)·(m·y): |Δ(sc/|ma|)| ≤ |sc/|ma||·E ≤ E.
//! * (q + 1)·2^G (G = face_log2 − 1 + Fo) is rounded once to nearest (the + 2^G is
//!   exact): |Δs|, |Δt| ≤ F/2·E + 2^−(Fo+1) texels.
//! * Saturation into the word and the texel-centre clamp are 1-Lipschitz, the stacked
//!   offset face·F exact, so the stacked word obeys the same bound against the twin's
//!   stacked value (the twin is clamped to the word's range too).
//! * f64 slack (derived, not a fudge): the twin's few f64 operations on values
//!   ≤ 2^33 texels, ≤ 8 roundings of relative 2^−53 on |values| ≤ 6F + 2^Io.

mod common;

use glare_pipeline::reference::cube_map_address::{
    cube_address_codes, face_direction, face_st, stacked_st,
};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::units::cube_map_address::{CubeMapAddress, CubeMapAddressConfig, CubeMapAddressIn};
use rtl_model::{Counters, Unit, UnitSummary};

fn p2(e: i32) -> f64 {
    (e as f64).exp2()
}

#[allow(clippy::too_many_arguments)]
fn cfg(
    in_int: u32,
    in_frac: u32,
    side: u32,
    a: u32,
    r: u32,
    newton: Option<u32>,
    face: u32,
    out_int: u32,
    out_frac: u32,
) -> CubeMapAddressConfig {
    CubeMapAddressConfig {
        in_int_bits: in_int,
        in_frac_bits: in_frac,
        side_log2: side,
        rcp_addr_bits: a,
        rcp_bits: r,
        newton: newton.is_some(),
        newton_frac_bits: newton.unwrap_or(16),
        face_log2: face,
        coord_int_bits: out_int,
        coord_frac_bits: out_frac,
    }
}

/// The configurations the bound is checked at (≥ 3, one narrow).
fn bound_configs() -> Vec<(&'static str, CubeMapAddressConfig)> {
    vec![
        ("default", CubeMapAddressConfig::geforce3()),
        ("wide", cfg(16, 12, 9, 10, 16, Some(28), 10, 16, 12)),
        ("mid, no Newton", cfg(16, 8, 7, 8, 10, None, 8, 16, 8)),
        ("NARROW", cfg(8, 2, 4, 2, 3, None, 4, 8, 2)),
        ("narrow + Newton", cfg(10, 4, 5, 3, 4, Some(8), 5, 10, 4)),
        ("saturating word", cfg(16, 8, 7, 6, 8, Some(16), 8, 10, 8)),
    ]
}

/// E: the bound on |m·y − 1|.
fn rcp_bound(c: &CubeMapAddressConfig) -> f64 {
    let dmax = if c.rcp_addr_bits >= c.rcp_bits {
        p2(-(c.rcp_bits as i32))
    } else {
        p2(-(c.rcp_bits as i32) - 1)
    };
    let e0 = p2(-(c.rcp_addr_bits as i32) - 1) + 2.0 * dmax;
    if c.newton {
        let n = p2(-(c.newton_frac_bits as i32));
        e0 * e0 + (1.0 + e0) * 1.5 * n + n
    } else {
        e0
    }
}

/// The bound on |Δs|, |Δt| in texels.
fn coord_bound(c: &CubeMapAddressConfig) -> f64 {
    let f = p2(c.face_log2 as i32);
    f / 2.0 * rcp_bound(c) + p2(-(c.coord_frac_bits as i32) - 1) + slack(c)
}

fn slack(c: &CubeMapAddressConfig) -> f64 {
    8.0 * (6.0 * p2(c.face_log2 as i32) + p2(c.coord_int_bits as i32)) * p2(-53)
}

/// Check one input word; returns the largest |Δ| / bound.
fn check(u: &CubeMapAddress, coord: [i32; 3]) -> f64 {
    let c = u.config();
    let mut ctr = Counters::default();
    let out = u.kernel(&mut (), &CubeMapAddressIn { coord }, &mut ctr);
    // The twin sees the same wires (sign-extended to the input width).
    let w = u.in_bits();
    let wires = coord.map(|x| ((x as i64) << (64 - w)) >> (64 - w));
    let (face, st, stk) = cube_address_codes(wires, c.in_frac_bits, c.side_log2, c.face_log2);
    assert_eq!(out.face, face, "face, input {coord:?}");
    let scale = p2(c.coord_frac_bits as i32);
    let max = (p2(u.out_bits() as i32 - 1) - 1.0) / scale;
    let min = -p2(u.out_bits() as i32 - 1) / scale;
    let bound = coord_bound(&c);
    let mut worst: f64 = 0.0;
    for (got, want) in [
        (out.st[0], st[0]),
        (out.st[1], st[1]),
        (out.coord[0], stk[0]),
        (out.coord[1], stk[1]),
    ] {
        let d = (got as f64 / scale - want.clamp(min, max)).abs();
        assert!(
            d <= bound,
            "|Δ| {d} > bound {bound} (input {coord:?}, out {out:?}, twin {st:?} {stk:?})"
        );
        worst = worst.max(d / bound);
    }
    assert_eq!(out.coord[2], 0);
    assert_eq!(
        out.zero,
        wires.map(|x| 2 * x) == [1i64 << (c.side_log2 + c.in_frac_bits); 3]
    );
    worst
}

/// A random input word: anywhere in the word, near the centre, or on a sphere around
/// it (the reflection unit's output for a unit r and some λ).
fn sample(u: &CubeMapAddress, rng: &mut ChaCha8Rng) -> [i32; 3] {
    let c = u.config();
    let w = u.in_bits();
    let lim = (1i64 << (w - 1)) - 1;
    let centre = (1i64 << (c.side_log2 + c.in_frac_bits)) / 2;
    match rng.random_range(0..3) {
        0 => [(); 3].map(|_| rng.random_range(-lim - 1..=lim) as i32),
        1 => [(); 3].map(|_| (centre + rng.random_range(-8..=8)).clamp(-lim - 1, lim) as i32),
        _ => {
            let d: [f64; 3] = [(); 3].map(|_| rng.random_range(-1.0..1.0));
            let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt().max(1e-9);
            let rad = rng.random_range(0.0..1.0) * centre as f64;
            d.map(|x| {
                (centre as f64 + x / l * rad)
                    .round()
                    .clamp(-(lim as f64) - 1.0, lim as f64) as i32
            })
        }
    }
}

#[test]
fn bound_holds_on_seeded_samples_and_prints_the_ratio() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for (name, c) in bound_configs() {
        let u = c.build().unwrap();
        let mut worst: f64 = 0.0;
        for _ in 0..20_000 {
            let x = sample(&u, &mut rng);
            worst = worst.max(check(&u, x));
        }
        println!(
            "{name}: E {:.3e}, bound {:.4} texel, worst/bound {worst:.2}",
            rcp_bound(&c),
            coord_bound(&c)
        );
    }
}

/// Exhaustive over every input of a 6-bit-word config (2^18 triples), narrow and with
/// Newton.
#[test]
fn exhaustive_on_6_bit_words() {
    for c in [
        cfg(4, 2, 3, 2, 3, None, 3, 8, 2),
        cfg(4, 2, 3, 3, 5, Some(8), 4, 8, 3),
    ] {
        let u = c.build().unwrap();
        let mut worst: f64 = 0.0;
        for x in -32..32 {
            for y in -32..32 {
                for z in -32..32 {
                    worst = worst.max(check(&u, [x, y, z]));
                }
            }
        }
        println!("exhaustive {c:?}: worst/bound {worst:.2}");
    }
}

/// The reciprocal alone, exhaustively over |ma| < 2^16: |m·y − 1| ≤ E.
#[test]
fn reciprocal_within_its_bound_exhaustively() {
    for (name, c) in bound_configs() {
        let u = c.build().unwrap();
        let e = rcp_bound(&c);
        let mut worst: f64 = 0.0;
        for ma in 1u64..1 << 16 {
            let r = u.rcp(ma, &mut Counters::default());
            let m = ma as f64 / p2(r.p as i32);
            let err = (m * r.y as f64 / p2(r.frac as i32) - 1.0).abs();
            assert!(err <= e, "{name}: ma {ma}: {err} > {e}");
            worst = worst.max(err / e);
        }
        println!("{name}: reciprocal worst/bound {worst:.2}");
    }
}

/// The OpenGL table: face centres, orientation of sc and tc on each face, ties, zero.
#[test]
fn opengl_faces_orientation_ties_and_zero() {
    let u = CubeMapAddress::geforce3();
    let c = u.config();
    let s = 1i32 << (c.side_log2 + c.in_frac_bits); // map side in input LSBs
    let fo = 1i32 << c.coord_frac_bits;
    let f = u.face_side() as i32 * fo;
    let word = |d: [i32; 3]| CubeMapAddressIn {
        coord: d.map(|x| s / 2 + x),
    };
    let run = |d: [i32; 3]| u.kernel(&mut (), &word(d), &mut Counters::default());
    // Major axis ±x, ±y, ±z at the face centre.
    for (k, d) in [
        [64, 0, 0],
        [-64, 0, 0],
        [0, 64, 0],
        [0, -64, 0],
        [0, 0, 64],
        [0, 0, -64],
    ]
    .into_iter()
    .enumerate()
    {
        let o = run(d);
        assert_eq!(o.face as usize, k);
        assert_eq!(o.st, [f / 2, f / 2]);
        assert_eq!(o.coord[1], f / 2 + k as i32 * f);
    }
    // Table 3.23 offsets: d = major 64 plus 32 on each minor axis in turn; the
    // expected (sc, tc) signs: sc/|ma| = ±½ → s = F/4 or 3F/4.
    let q = |v: i32| f / 2 + v * f / 4; // (v/2 + 1)/2 · F
    let cases: [([i32; 3], [i32; 2]); 12] = [
        ([64, 0, 32], [q(-1), q(0)]),  // +x: sc = −z
        ([64, 32, 0], [q(0), q(-1)]),  // +x: tc = −y
        ([-64, 0, 32], [q(1), q(0)]),  // −x: sc = +z
        ([-64, 32, 0], [q(0), q(-1)]), // −x: tc = −y
        ([32, 64, 0], [q(1), q(0)]),   // +y: sc = +x
        ([0, 64, 32], [q(0), q(1)]),   // +y: tc = +z
        ([32, -64, 0], [q(1), q(0)]),  // −y: sc = +x
        ([0, -64, 32], [q(0), q(-1)]), // −y: tc = −z
        ([32, 0, 64], [q(1), q(0)]),   // +z: sc = +x
        ([0, 32, 64], [q(0), q(-1)]),  // +z: tc = −y
        ([32, 0, -64], [q(-1), q(0)]), // −z: sc = −x
        ([0, 32, -64], [q(0), q(-1)]), // −z: tc = −y
    ];
    // Within the derived bound (the reciprocal is approximate; the signs differ by F/2).
    let tol = (coord_bound(&c) * fo as f64).ceil() as i32;
    let near = |a: [i32; 2], b: [i32; 2]| (a[0] - b[0]).abs() <= tol && (a[1] - b[1]).abs() <= tol;
    for (d, st) in cases {
        let got = run(d).st;
        assert!(near(got, st), "d {d:?}: {got:?} vs {st:?}");
    }
    // Ties: x over y and z, y over z.
    assert_eq!(run([40, 40, 40]).face, 0);
    assert_eq!(run([-40, 40, -40]).face, 1);
    assert_eq!(run([10, -40, 40]).face, 3);
    assert_eq!(run([10, 20, -30]).face, 5);
    // Zero: face 0 at the centre, counted.
    let mut ctr = Counters::default();
    let o = u.kernel(&mut (), &word([0, 0, 0]), &mut ctr);
    assert!(o.zero);
    assert_eq!(
        (o.face, o.st, o.coord),
        (0, [f / 2, f / 2], [f / 2, f / 2, 0])
    );
    assert_eq!((ctr.underflows, ctr.table_reads), (1, 0));
    // A corner direction clamps to the texel-centre range: ½ texel from each edge.
    let o = run([64, 64, -64]); // x wins the tie; sc = −z → +1, tc = −y → −1
    assert!(near(o.st, [f, 0]), "{:?}", o.st);
    assert_eq!(o.coord[..2], [f - fo / 2, fo / 2]);
}

/// The twin's inverse: the direction of a face point maps back to it.
#[test]
fn twin_face_direction_round_trips() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for _ in 0..10_000 {
        let face = rng.random_range(0..6u8);
        let (s, t) = (
            rng.random_range(0.001..0.999),
            rng.random_range(0.001..0.999),
        );
        let d = face_direction(face, s, t);
        let (f, st) = face_st(d, 1.0);
        assert_eq!(f, face);
        assert!((st[0] - s).abs() < 1e-12 && (st[1] - t).abs() < 1e-12);
        let stk = stacked_st(f, [st[0] * 64.0, st[1] * 64.0], 64.0);
        assert!(stk[1] >= face as f64 * 64.0 && stk[1] < (face as f64 + 1.0) * 64.0);
    }
}

#[test]
fn defaults_summary() {
    let u = CubeMapAddress::geforce3();
    let s = UnitSummary::of(&u);
    let c = u.config();
    println!(
        "cube_map_address defaults: latency {}, II {}, {:.0} NAND2, {} ROM bits; bound {:.4} texel (E {:.3e})",
        s.latency,
        s.ii,
        s.gates_nand2,
        s.ram_bits,
        coord_bound(&c),
        rcp_bound(&c)
    );
    for (p, g) in &s.breakdown {
        println!("  {p}: {g:.0}");
    }
    // The reciprocal choice: table + Newton against a bigger table alone.
    for alt in [
        c,
        CubeMapAddressConfig { newton: false, ..c },
        CubeMapAddressConfig {
            newton: false,
            rcp_addr_bits: 12,
            rcp_bits: 13,
            ..c
        },
        CubeMapAddressConfig {
            rcp_addr_bits: 8,
            rcp_bits: 10,
            newton: false,
            ..c
        },
    ] {
        let a = UnitSummary::of(&alt.build().unwrap());
        println!(
            "  A {} R {} Newton {}: {:.0} NAND2, {} ROM bits, latency {}, bound {:.4} texel",
            alt.rcp_addr_bits,
            alt.rcp_bits,
            alt.newton,
            a.gates_nand2,
            a.ram_bits,
            a.latency,
            coord_bound(&alt)
        );
    }
    assert_eq!((s.latency, s.ii), (10, 1));
    assert_eq!(s.ram_bits, 64 * 8);
    let no_newton = CubeMapAddressConfig { newton: false, ..c }.build().unwrap();
    assert_eq!(no_newton.timing().latency, 7);
}

/// A valid config from sane ranges (for the driver test).
fn valid_cfg() -> impl Strategy<Value = CubeMapAddressConfig> {
    (
        (1u32..=16, 0u32..=16),
        0u32..=12,
        (1u32..=12, 2u32..=24),
        (any::<bool>(), 4u32..=30),
        1u32..=12,
        (2u32..=16, 1u32..=16),
    )
        .prop_map(
            |((ii, fi), side, (a, r), (nw, n), face, (ci, cf))| CubeMapAddressConfig {
                in_int_bits: ii,
                in_frac_bits: fi,
                side_log2: side,
                rcp_addr_bits: a,
                rcp_bits: r,
                newton: nw,
                newton_frac_bits: n,
                face_log2: face,
                coord_int_bits: ci,
                coord_frac_bits: cf,
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    #[test]
    fn within_bound_vs_twin(ci in 0usize..6, seed in any::<u64>()) {
        let (_, c) = bound_configs()[ci];
        let u = c.build().unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let x = sample(&u, &mut rng);
        check(&u, x);
    }

    #[test]
    fn tick_and_span_drivers_agree(
        c in valid_cfg(),
        words in prop::collection::vec([any::<i32>(), any::<i32>(), any::<i32>()], 0..24),
    ) {
        let u = c.build().unwrap();
        let inputs: Vec<CubeMapAddressIn> =
            words.iter().map(|&coord| CubeMapAddressIn { coord }).collect();
        common::assert_drivers_agree(&u, (), &inputs);
    }

    #[test]
    fn random_configs_never_panic_and_errors_name_the_field(
        ii in 0u32..40, fi in 0u32..40, side in 0u32..40, a in 0u32..40, r in 0u32..40,
        nw in any::<bool>(), n in 0u32..40, face in 0u32..40, ci in 0u32..40, cf in 0u32..40,
        coord in [any::<i32>(), any::<i32>(), any::<i32>()],
    ) {
        let c = CubeMapAddressConfig {
            in_int_bits: ii, in_frac_bits: fi, side_log2: side, rcp_addr_bits: a,
            rcp_bits: r, newton: nw, newton_frac_bits: n, face_log2: face,
            coord_int_bits: ci, coord_frac_bits: cf,
        };
        match c.build() {
            Ok(u) => {
                let mut ctr = Counters::default();
                let inp = CubeMapAddressIn { coord };
                let o = u.kernel(&mut (), &inp, &mut ctr);
                prop_assert!(o.face < 6);
                let _ = u.cost();
                let _ = u.in_signals(&inp);
                let _ = u.out_signals(&o);
            }
            Err(e) => prop_assert!(
                e.field().starts_with("cube_map_address."),
                "field {}",
                e.field()
            ),
        }
    }

    #[test]
    fn non_finite_host_inputs_are_errors_naming_the_field(
        bad in prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY)],
        k in 0usize..3,
    ) {
        let u = CubeMapAddress::geforce3();
        let mut c = [64.0, 70.5, 12.0];
        c[k] = bad;
        let err = u.quantise_in(c, &mut Counters::default()).unwrap_err();
        prop_assert_eq!(err.field(), "cube_map_address.coord");
    }

    #[test]
    fn twin_never_nan(d in [any::<f64>(), any::<f64>(), any::<f64>()], fs in 1.0f64..4096.0) {
        let (f, st) = face_st(d, fs);
        prop_assert!(f < 6);
        prop_assert!(st.iter().all(|x| x.is_finite()), "{st:?}");
        let s = stacked_st(f, st, fs);
        prop_assert!(s.iter().all(|x| x.is_finite()));
    }
}
