//! gaussian_noise against its f64 twin (exact Box–Muller / Irwin–Hall on the same
//! uniform codes), the issue's acceptance test (KS and 3σ/4σ tails at seed 1), the
//! central-limit tail deficit, drivers, config errors, and the datasheet report.

mod common;

use glare_pipeline::reference::gaussian_noise as twin;
use proptest::prelude::*;
use rtl_model::units::gaussian_noise::{
    taus88_step, GaussMode, GaussState, GaussianNoise, GaussianNoiseConfig,
};
use rtl_model::{Counters, Unit};
use std::f64::consts::PI;

/// The project default seed.
const SEED: u64 = 1;

fn cfg(mode: GaussMode, b: u32, t: u32, e: u32, f: u32, o: u32) -> GaussianNoise {
    GaussianNoiseConfig {
        mode,
        uniform_bits: b,
        table_log2: t,
        table_bits: e,
        out_frac_bits: f,
        out_int_bits: o,
    }
    .build()
    .unwrap()
}

/// Width-derived error bound (output LSBs) of one Box–Muller output against the exact
/// value, for the sample with uniform code k1 (derivation in
/// docs/units.md § gaussian_noise). B, T, E, D = E, f from the config; all the
/// terms are in real units until the last line.
///
/// * ln m on [1, 2): entry rounding ½·2^−E, interpolation h²/8·max|ln″| = 2^−2T/8,
///   fraction truncation to T + D bits (slope of the interpolant ≤ 1 + 2^(T−E)) times
///   2^−(T+D), product rounding ½·2^−E → ε_L.
/// * y = e·ln 2 − L: ln 2 held at E + 8 bits (e·½·2^−(E+8) ≤ (B+1)·2^−(E+9)), then
///   rounding to E bits (½·2^−E) → ε_y; w = 2y so ε_w = 2ε_y.
/// * √ on [1, 4), h = 2^−(T−2): ½·2^−E + h²/8·¼ + (½ + 2^(T−2−E))·2^−(T−2+D) + ½·2^−E
///   = ε_S (mantissa units); the radius error is ε_S·2ᵏ ≤ ε_S·√w_c ≤ ε_S(√w + √ε_w),
///   and |√w_c − √w| ≤ min(√ε_w, ε_w/√w) (the √ is not Lipschitz at 0: near u1 → 1
///   the absolute error of y is what matters) → ε_r.
/// * sin on a quarter wave in turns, h = 2^−(T+2): ½·2^−E + (2π)²h²/8
///   + (2π + 2^(T+2−E))·2^−(T+2+D) + ½·2^−E = ε_C.
/// * x = r·cos: |r_c·c_c − r·c| ≤ ε_r(1 + ε_C) + r·ε_C; times 2^f, plus the output
///   rounding ½ LSB. Saturation clamps both sides (the exact value is clamped too).
fn bm_bound_lsb(u: &GaussianNoise, k1: u64) -> f64 {
    let c = u.config();
    let (b, t, e, f) = (
        c.uniform_bits as f64,
        c.table_log2 as f64,
        c.table_bits as f64,
        c.out_frac_bits as f64,
    );
    let d = e;
    let p2 = |x: f64| x.exp2();
    let eps_l = p2(-e) + p2(-2.0 * t) / 8.0 + (1.0 + p2(t - e)) * p2(-(t + d));
    let eps_y = eps_l + (b + 1.0) * p2(-(e + 9.0)) + 0.5 * p2(-e);
    let eps_w = 2.0 * eps_y;
    let h_s = p2(-(t - 2.0));
    let eps_s = p2(-e) + h_s * h_s / 8.0 * 0.25 + (0.5 + p2(t - 2.0 - e)) * p2(-(t - 2.0 + d));
    let (_, r) = twin::box_muller_radius(k1, c.uniform_bits);
    let w = r * r;
    let sqrt_err = if w > 0.0 {
        eps_w.sqrt().min(eps_w / w.sqrt())
    } else {
        eps_w.sqrt()
    };
    let eps_r = sqrt_err + eps_s * (w.sqrt() + eps_w.sqrt());
    let h_c = p2(-(t + 2.0));
    let eps_c = p2(-e)
        + (2.0 * PI).powi(2) * h_c * h_c / 8.0
        + (2.0 * PI + p2(t + 2.0 - e)) * p2(-(t + 2.0 + d));
    (eps_r * (1.0 + eps_c) + r * eps_c) * p2(f) + 0.5
}

fn clamp_exact(u: &GaussianNoise, x: f64) -> f64 {
    let m = u.out_max_code() as f64;
    (x * (u.config().out_frac_bits as f64).exp2()).clamp(-m, m)
}

fn check_bm(u: &GaussianNoise, k1: u64, k2: u64) {
    let mut ctr = Counters::default();
    let (x, y) = u.box_muller_codes(k1, k2, &mut ctr);
    let (ex, ey) = twin::box_muller(k1, k2, u.config().uniform_bits);
    let bound = bm_bound_lsb(u, k1);
    let (ex, ey) = (clamp_exact(u, ex), clamp_exact(u, ey));
    // f64 slack 1e-9 LSB for the twin's own rounding.
    assert!(
        (x as f64 - ex).abs() <= bound + 1e-9 && (y as f64 - ey).abs() <= bound + 1e-9,
        "{:?}: k1 {k1} k2 {k2}: got ({x}, {y}), want ({ex:.3}, {ey:.3}), bound {bound:.3}",
        u.config()
    );
}

/// Configs: default, a wide-table one, a mid one and a narrow one (8-bit uniforms,
/// 16-segment 8-bit tables: errors of several LSB at f = 12) and one with a 1-bit
/// integer part (saturating).
fn bm_configs() -> Vec<GaussianNoise> {
    vec![
        GaussianNoise::geforce(),
        cfg(GaussMode::BoxMuller, 32, 12, 24, 16, 3),
        cfg(GaussMode::BoxMuller, 16, 8, 14, 10, 3),
        cfg(GaussMode::BoxMuller, 8, 4, 8, 12, 3),
        cfg(GaussMode::BoxMuller, 24, 6, 12, 8, 1),
    ]
}

#[test]
fn box_muller_within_bound_exhaustively_at_8_bit_uniforms() {
    // 2⁸ × 2⁸ = 65 536 pairs: the whole input space of the narrow configs.
    for u in [
        cfg(GaussMode::BoxMuller, 8, 4, 8, 12, 3),
        cfg(GaussMode::BoxMuller, 8, 10, 18, 12, 3),
    ] {
        for k1 in 0..256u64 {
            for k2 in 0..256u64 {
                check_bm(&u, k1, k2);
            }
        }
    }
}

#[test]
fn box_muller_extremes_of_u1() {
    // u1 → 0 (largest radius) and u1 → 1 (y rounds to 0: the √ near 0).
    for u in bm_configs() {
        let b = u.config().uniform_bits;
        let max = (1u64 << b) - 1;
        for k1 in [0, 1, 2, 3, max - 3, max - 2, max - 1, max] {
            for k2 in [0, 1, max / 4, max / 2, 3 * max / 4, max] {
                check_bm(&u, k1, k2);
            }
        }
    }
}

#[test]
fn central_limit_is_exact_to_half_an_lsb_exhaustively_over_sums() {
    // The datapath depends on Σk only; sweep every sum reachable at B = 8 (0 ..= 12·255).
    let u = cfg(GaussMode::CentralLimit, 8, 10, 18, 12, 3);
    for s in 0..=12 * 255u64 {
        let mut ks = [0u64; 12];
        let mut rest = s;
        for k in ks.iter_mut() {
            *k = rest.min(255);
            rest -= *k;
        }
        let mut ctr = Counters::default();
        let got = u.central_limit_codes(&ks, &mut ctr) as f64;
        let want = twin::irwin_hall(&ks, 8) * 4096.0;
        assert!((got - want).abs() <= 0.5, "Σk {s}: {got} vs {want}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    #[test]
    fn box_muller_within_derived_bound(
        which in 0usize..5,
        k1 in any::<u64>(),
        k2 in any::<u64>(),
        tiny in any::<bool>(),
    ) {
        let u = &bm_configs()[which];
        let b = u.config().uniform_bits;
        let mask = (1u64 << b) - 1;
        // Half the cases near u1 → 0 (the tails), where ln is steepest.
        let k1 = if tiny { k1 & 0xFF } else { k1 & mask };
        check_bm(u, k1, k2 & mask);
    }

    #[test]
    fn central_limit_within_half_an_lsb(
        b in prop::sample::select(vec![8u32, 16, 24, 32]),
        f in 4u32..=16,
        ks in prop::array::uniform12(any::<u64>()),
    ) {
        let u = cfg(GaussMode::CentralLimit, b, 10, 18, f, 3);
        let mask = (1u64 << b) - 1;
        let ks = ks.map(|k| k & mask);
        let mut ctr = Counters::default();
        let got = u.central_limit_codes(&ks, &mut ctr) as f64;
        let want = twin::irwin_hall(&ks, b) * (f as f64).exp2();
        prop_assert!((got - want).abs() <= 0.5 + 1e-9, "{got} vs {want}");
    }

    #[test]
    fn kernel_uses_the_pure_taus88_words(seed in any::<u64>(), steps in 1usize..20) {
        // The kernel's uniforms are exactly taus88_step on the state words: the twin
        // can be fed the same codes.
        let u = GaussianNoise::geforce();
        let mut s = GaussState::from_seed(seed);
        let (mut a, mut b) = s.words();
        let mut ctr = Counters::default();
        for _ in 0..steps {
            let (ra, rb) = (taus88_step(&mut a), taus88_step(&mut b));
            let o = u.kernel(&mut s, &(), &mut ctr);
            let (x, y) = u.box_muller_codes(u.uniform_code(ra), u.uniform_code(rb), &mut ctr);
            prop_assert_eq!((o.x, o.y), (x, Some(y)));
        }
        prop_assert_eq!(s.words(), (a, b));
    }

    #[test]
    fn tick_and_span_drivers_agree(
        mode in prop::sample::select(vec![GaussMode::BoxMuller, GaussMode::CentralLimit]),
        b in 8u32..=32, t in 4u32..=12, e in 8u32..=24, f in 4u32..=16, o in 1u32..=4,
        seed in any::<u64>(),
        n in 0usize..30,
    ) {
        let u = cfg(mode, b, t, e, f, o);
        common::assert_drivers_agree(&u, GaussState::from_seed(seed), &vec![(); n]);
    }

    #[test]
    fn random_configs_never_panic_and_errors_name_the_field(
        b in 0u32..64, t in 0u32..20, e in 0u32..40, f in 0u32..30, o in 0u32..8,
    ) {
        let c = GaussianNoiseConfig {
            mode: GaussMode::BoxMuller,
            uniform_bits: b,
            table_log2: t,
            table_bits: e,
            out_frac_bits: f,
            out_int_bits: o,
        };
        match c.build() {
            Ok(u) => {
                let mut s = GaussState::from_seed(7);
                let mut ctr = Counters::default();
                let _ = u.kernel(&mut s, &(), &mut ctr);
            }
            Err(err) => {
                let field = err.field().to_string();
                prop_assert!(
                    [
                        "gaussian_noise.uniform_bits",
                        "gaussian_noise.table_log2",
                        "gaussian_noise.table_bits",
                        "gaussian_noise.out_frac_bits",
                        "gaussian_noise.out_int_bits",
                    ]
                    .contains(&field.as_str()),
                    "{}",
                    field
                );
            }
        }
    }
}

#[test]
fn seeds_respect_taus88_minimums() {
    for seed in 0..2000u64 {
        let (a, b) = GaussState::from_seed(seed).words();
        for w in [a, b] {
            assert!(w[0] >= 2 && w[1] >= 8 && w[2] >= 16);
        }
    }
}

fn draw(u: &GaussianNoise, n: usize) -> (Vec<i32>, Counters) {
    let mut s = GaussState::from_seed(SEED);
    let mut ctr = Counters::default();
    let v = u.draw_codes(&mut s, n, &mut ctr);
    (v, ctr)
}

fn lsb(u: &GaussianNoise) -> f64 {
    (-(u.config().out_frac_bits as f64)).exp2()
}

fn acceptance_numbers() -> (twin::KsResult, u64, u64, f64, f64) {
    let u = GaussianNoise::geforce();
    let n = 100_000;
    let (v, _) = draw(&u, n);
    let ks = twin::ks_normal_codes(&v, lsb(&u));
    let (c3, c4) = twin::tail_counts(&v, lsb(&u));
    let e3 = twin::normal_two_sided_tail(3.0) * n as f64;
    let e4 = twin::normal_two_sided_tail(4.0) * n as f64;
    println!(
        "seed {SEED}, N = {n}: KS D = {:.5}, p = {:.4}; |x|>3: {c3} (expected {e3:.2}); |x|>4: {c4} (expected {e4:.2})",
        ks.d, ks.p
    );
    (ks, c3, c4, e3, e4)
}

/// The issue's acceptance test, seed 1, 10⁵ samples of the default config: KS p > 0.01
/// and the 3σ count within 25 % of 269.98. (Measured: D = 0.00193, p = 0.85; 296.)
#[test]
fn issue_acceptance_ks_and_3_sigma_at_seed_1() {
    let (ks, c3, _, e3, _) = acceptance_numbers();
    assert!(ks.p > 0.01, "KS p = {}", ks.p);
    assert!((c3 as f64 - e3).abs() <= 0.25 * e3, "3σ count {c3} vs {e3}");
}

/// The issue's 4σ clause at 10⁵ samples FAILS at seed 1: 9 samples beyond 4σ against
/// 6.33 expected (+42 %; a Poisson(6.33) count is ≥ 9 with probability ≈ 0.20, and
/// lands in 5 ..= 7 only ≈ 45 % of the time). The seed is not changed to make it
/// pass; [`four_sigma_tail_at_two_million_samples`] checks the 4σ tail with enough
/// samples instead. Run with `--ignored` to see it fail.
#[test]
#[ignore = "fails at seed 1 (9 vs 6.33 beyond 4σ: Poisson noise); see four_sigma_tail_at_two_million_samples"]
fn issue_acceptance_4_sigma_at_1e5_seed_1() {
    let (_, _, c4, _, e4) = acceptance_numbers();
    assert!((c4 as f64 - e4).abs() <= 0.25 * e4, "4σ count {c4} vs {e4}");
}

/// The 4σ tail at 2·10⁶ samples (expected 126.6, σ ≈ 11.3): within 25 % (2.8σ).
#[test]
fn four_sigma_tail_at_two_million_samples() {
    let u = GaussianNoise::geforce();
    let n = 2_000_000;
    let (v, ctr) = draw(&u, n);
    let (c3, c4) = twin::tail_counts(&v, lsb(&u));
    let e3 = twin::normal_two_sided_tail(3.0) * n as f64;
    let e4 = twin::normal_two_sided_tail(4.0) * n as f64;
    println!(
        "seed {SEED}, N = {n}: |x|>3: {c3} (expected {e3:.1}); |x|>4: {c4} (expected {e4:.1})"
    );
    assert!((c4 as f64 - e4).abs() <= 0.25 * e4, "4σ count {c4} vs {e4}");
    assert!((c3 as f64 - e3).abs() <= 0.05 * e3, "3σ count {c3} vs {e3}");
    assert_eq!(ctr.saturations, 0);
}

/// Central limit: at 2·10⁶ samples its 4σ count matches the exact Irwin–Hall tail
/// (34.1 expected, σ ≈ 5.8) and is far below
/// the normal 126.6; its 3σ count matches IH (2.014·10⁻³) not N (2.700·10⁻³).
/// (P(IH₁₂ < 2) = (2¹² − 12·1¹²)/12! = 4084/12!, so the two-sided 4σ tail is 1.705·10⁻⁵:
/// 34.10 expected.)
#[test]
fn central_limit_shows_its_tail_deficit() {
    let u = cfg(GaussMode::CentralLimit, 32, 10, 18, 12, 3);
    let n = 2_000_000;
    let (v, _) = draw(&u, n);
    let (c3, c4) = twin::tail_counts(&v, lsb(&u));
    let ih3 = twin::irwin_hall_two_sided_tail(12, 3.0) * n as f64;
    let ih4 = twin::irwin_hall_two_sided_tail(12, 4.0) * n as f64;
    let n4 = twin::normal_two_sided_tail(4.0) * n as f64;
    let n3 = twin::normal_two_sided_tail(3.0) * n as f64;
    println!("CLT N = {n}: |x|>3: {c3} (IH {ih3:.1}, normal {n3:.1}); |x|>4: {c4} (IH {ih4:.1}, normal {n4:.1})");
    assert!(
        (ih4 - 2.0 * 4084.0 / 479_001_600.0 * n as f64).abs() < 1e-9,
        "{ih4}"
    );
    // Poisson(34.2): ±5σ = ±29.
    assert!(
        (c4 as f64 - ih4).abs() <= 5.0 * ih4.sqrt(),
        "{c4} vs IH {ih4}"
    );
    assert!((c4 as f64) < 0.5 * n4);
    assert!(
        (c3 as f64 - ih3).abs() <= 5.0 * ih3.sqrt(),
        "{c3} vs IH {ih3}"
    );
    assert!((c3 as f64) < 0.85 * n3);
    assert!(v.iter().all(|&x| (x as f64 * lsb(&u)).abs() <= 6.0));
}

#[test]
fn erfc_matches_known_values() {
    // Reference values of erfc (Abramowitz & Stegun / high-precision tables).
    for (x, want) in [
        (0.0, 1.0),
        (0.5, 0.479_500_122_186_953_5),
        (1.0, 0.157_299_207_050_285_1),
        (2.0, 0.004_677_734_981_047_266),
        (3.0 / std::f64::consts::SQRT_2, 0.002_699_796_063_260_207),
        (4.0 / std::f64::consts::SQRT_2, 6.334_248_366_623_996e-5),
        (-1.0, 1.842_700_792_949_715),
    ] {
        let got = twin::erfc(x);
        assert!(
            ((got - want) / want).abs() < 1.2e-7,
            "erfc({x}) = {got}, want {want}"
        );
    }
}

/// Datasheet and statistics figures (`cargo test --test gaussian_noise -- --nocapture
/// report` prints them), asserted to be what docs/units.md and docs/glare.md quote.
#[test]
fn report() {
    use common::docs::{assert_quotes, grouped, section};
    let units = section("units.md", "## gaussian_noise");
    let at = "docs/units.md, section gaussian_noise,";
    let glare = section("glare.md", "### Gaussian noise generator");
    for u in [
        GaussianNoise::geforce(),
        cfg(GaussMode::CentralLimit, 32, 10, 18, 12, 3),
    ] {
        let n = 100_000;
        let (v, _) = draw(&u, n);
        let ks = twin::ks_normal_codes(&v, lsb(&u));
        let (c3, c4) = twin::tail_counts(&v, lsb(&u));
        let t = u.timing();
        let c = u.cost();
        let per_clock = u.samples_per_call() as f64 / t.ii as f64;
        println!(
            "{:?}: seed {SEED}, N = {n}: KS D = {:.5} p = {:.4}; |x|>3 {c3} (N(0,1) {:.2}); |x|>4 {c4} (N(0,1) {:.2}); \
             latency {} II {} samples/clock {:.3}; gates {:.0} NAND2; ROM bits {}",
            u.mode(),
            ks.d,
            ks.p,
            twin::normal_two_sided_tail(3.0) * n as f64,
            twin::normal_two_sided_tail(4.0) * n as f64,
            t.latency,
            t.ii,
            per_clock,
            c.gates_nand2(),
            c.ram_bits
        );
        for (part, g) in &c.breakdown {
            println!("    {part}: {g:.0}");
        }
        // The two tables of docs/units.md: timing and cost, statistics at 10⁵.
        let mode = format!("{:?}", u.mode());
        let rate = if per_clock >= 1.0 {
            format!("{per_clock:.0}")
        } else {
            format!("1/{:.0}", 1.0 / per_clock)
        };
        assert_quotes(
            &units,
            &format!(
                "| {mode} | {} | {} | {rate} | {} | {}",
                t.latency,
                t.ii,
                grouped(c.gates_nand2()),
                grouped(c.ram_bits as f64)
            ),
            at,
        );
        let four = if mode == "BoxMuller" {
            format!("**{c4}**")
        } else {
            c4.to_string()
        };
        assert_quotes(
            &units,
            &format!("| {mode} | 10⁵ | {:.5} | {:.3} | {c3} |", ks.d, ks.p),
            at,
        );
        assert_quotes(&units, &format!("| {four} |"), at);
        // docs/glare.md's design table quotes the same run.
        let p_text = if mode == "BoxMuller" {
            format!("**p = {:.2}**", ks.p)
        } else {
            format!("p = {:.2}", ks.p)
        };
        assert_quotes(
            &glare,
            &format!("| {:.5}, {p_text} | {c3} (", ks.d),
            "docs/glare.md's noise design table",
        );
    }
    let u = GaussianNoise::geforce();
    let c = u.cost();
    let kilo = |name: &str| common::docs::kilo(&c.breakdown, name);
    assert_quotes(
        &units,
        &format!(
            "sin/cos interpolators {}, r×cos/r×sin {}, √ interpolator {}, ln interpolator {}",
            kilo("sin, cos interpolators"),
            kilo("r × cos, r × sin"),
            kilo("√ interpolator"),
            kilo("ln interpolator")
        ),
        at,
    );
    let worst = (0..64u64)
        .map(|k| bm_bound_lsb(&u, k))
        .chain([bm_bound_lsb(&u, u32::MAX as u64)])
        .fold(0.0f64, f64::max);
    let (half, tail) = (bm_bound_lsb(&u, 1 << 31), bm_bound_lsb(&u, 0));
    println!(
        "default bound (LSB of 2^-12): worst {worst:.3} (u1 → 1, r → 0: the √ near 0); at u1 = ½ {half:.3}; at u1 = 2^-33 (r = 6.76) {tail:.3}",
    );
    assert_quotes(
        &units,
        &format!(
            "At defaults: {half:.2} LSB at u1 = ½, {tail:.2} LSB at u1 = 2⁻³³ (r = 6.76), up to {worst:.1} LSB"
        ),
        at,
    );
}

// ---- `reproduce glare-gauss-seeds`: the acceptance test at many seeds -------------

use glare_pipeline::pipeline::glare::gauss_seeds;

/// P(5 ≤ X ≤ 7) for X ~ Poisson(m), from the textbook pmf e^(−m) m^k / k!: the
/// module's log-domain pmf and pass probability agree with it, and the pmf sums to 1.
#[test]
fn poisson_pass_probability_matches_the_textbook_sum() {
    let (_, m) = gauss_seeds::expected_counts();
    let direct: f64 = (5..=7u32)
        .map(|k| (-m).exp() * m.powi(k as i32) / (1..=k).product::<u32>() as f64)
        .sum();
    let p = gauss_seeds::poisson_pass_probability(m, 0.25);
    assert!((p - direct).abs() < 1e-12, "{p} vs {direct}");
    // 6.33 · 0.75 = 4.75 and 6.33 · 1.25 = 7.92: the clause accepts 5, 6 and 7.
    assert!((0.40..0.50).contains(&p), "{p}");
    let total: f64 = (0..200).map(|k| gauss_seeds::poisson_pmf(m, k)).sum();
    assert!((total - 1.0).abs() < 1e-12, "{total}");
}

/// The seed sweep's row for seed 1 is the acceptance test's own draw, and its rows and
/// summaries are the same bytes on 1 and 2 threads.
#[test]
fn seed_sweep_reuses_the_acceptance_draw_and_is_thread_count_independent() {
    let (ks, c3, c4, _, _) = acceptance_numbers();
    let r = gauss_seeds::unit_row(SEED);
    assert_eq!((r.count_3sigma, r.count_4sigma), (c3, c4));
    assert_eq!(r.ks_d, ks.d);
    let run = |threads: usize| -> (Vec<u8>, Vec<u8>) {
        let dir =
            std::env::temp_dir().join(format!("gauss_seeds_{threads}_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let sums = pool.install(|| gauss_seeds::gauss_seeds(&dir, 4)).unwrap();
        assert_eq!(sums.len(), 2);
        for s in &sums {
            assert_eq!(s.seeds, 4);
            assert!(s.pass_all <= s.pass_4sigma && s.pass_all <= s.pass_ks);
        }
        let rows = std::fs::read(dir.join("gauss_seeds.csv")).unwrap();
        let summary = std::fs::read(dir.join("gauss_seeds_summary.csv")).unwrap();
        assert!(dir.join("gauss_seeds_4sigma.png").is_file());
        std::fs::remove_dir_all(&dir).unwrap();
        (rows, summary)
    };
    assert_eq!(run(1), run(2));
}

/// The ideal sampler is what the unit is compared with, so it must itself be N(0, 1)
/// at the unit's output LSB: over seeds 1 ..= 3 (3·10⁵ samples) its 3σ count is within
/// 4 Poisson σ of 809.9 and each seed's KS test passes at p > 0.001.
#[test]
fn ideal_sampler_is_normal() {
    let rows: Vec<_> = (1..=3).map(gauss_seeds::ideal_row).collect();
    let c3: u64 = rows.iter().map(|r| r.count_3sigma).sum();
    let e3 = 3.0 * gauss_seeds::expected_counts().0;
    assert!((c3 as f64 - e3).abs() <= 4.0 * e3.sqrt(), "{c3} vs {e3}");
    for r in &rows {
        assert!(r.ks_p > 0.001, "seed {}: p = {}", r.seed, r.ks_p);
    }
}
