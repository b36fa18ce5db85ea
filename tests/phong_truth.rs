//! The Phong ground truth (src/reference/phong_truth.rs): normalisation, the Λ limits,
//! stiff cases (Λ from 0 to 10⁵ and beyond, a sun at 10⁵ × the mean, grazing r) and the
//! pruning bound. Maps are 64 × 32 except where a real 512 × 256 input is the point.

use glare_pipeline::reference::phong_truth::{
    phong_truth, prune_error_bound, PhongTruth, Visibility, PRUNE_LOG,
};
use glare_pipeline::scene::envmap::EnvMap;
use glare_pipeline::scene::math::{v3, Vec3};

const W: usize = 64;
const H: usize = 32;
const LAMBDAS: [f64; 12] = [
    0.0, 1e-9, 1e-3, 0.5, 1.0, 10.0, 100.0, 1e3, 1e4, 45_000.0, 1e5, 1e12,
];

/// `n` well-spread unit directions (a Fibonacci spiral), plus the six axes.
fn directions(n: usize) -> Vec<Vec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let mut v: Vec<Vec3> = (0..n)
        .map(|k| {
            let y = 1.0 - 2.0 * (k as f64 + 0.5) / n as f64;
            let r = (1.0 - y * y).sqrt();
            let a = golden * k as f64;
            v3(r * a.cos(), y, r * a.sin())
        })
        .collect();
    for d in [
        v3(1.0, 0.0, 0.0),
        v3(-1.0, 0.0, 0.0),
        v3(0.0, 1.0, 0.0),
        v3(0.0, -1.0, 0.0),
        v3(0.0, 0.0, 1.0),
        v3(0.0, 0.0, -1.0),
    ] {
        v.push(d);
    }
    v
}

/// A unit vector at angle `a` from unit `r` (in some plane containing r).
fn tilted(r: Vec3, a: f64) -> Vec3 {
    let helper = if r.y.abs() < 0.9 {
        v3(0.0, 1.0, 0.0)
    } else {
        v3(1.0, 0.0, 0.0)
    };
    let p = helper.cross(r).normalized();
    (r * a.cos() + p * a.sin()).normalized()
}

fn finite_nonneg(x: [f64; 3]) -> bool {
    x.iter().all(|c| c.is_finite() && *c >= 0.0)
}

fn assert_close3(got: [f64; 3], want: [f64; 3], rel: f64, what: &str) {
    for c in 0..3 {
        let tol = rel * want[c].abs().max(1e-300);
        assert!(
            (got[c] - want[c]).abs() <= tol,
            "{what}: channel {c}: {} vs {} (rel tol {rel})",
            got[c],
            want[c]
        );
    }
}

#[test]
fn constant_environment_gives_the_constant() {
    let k = [0.3, 1.0, 7.0];
    let env = EnvMap::constant(W, H, k).unwrap();
    let truth = PhongTruth::new(&env);
    for r in directions(40) {
        for &lambda in &LAMBDAS {
            // Without the cos φ test: always (the weights are normalised).
            let a = truth.eval(r, r, lambda, Visibility::Simplified).unwrap();
            assert_close3(a, k, 1e-12, &format!("simplified r={r:?} Λ={lambda}"));
            // With the test and n = r: the two hemispheres coincide, nothing is removed.
            let b = truth.eval(r, r, lambda, Visibility::CosPhiTest).unwrap();
            assert_close3(b, k, 1e-12, &format!("cos φ, n = r, r={r:?} Λ={lambda}"));
        }
        // With the test and n 60° away from r: the kept lobe (ψ ≤ acos e^(−60/Λ) ≈ 0.11
        // rad at Λ = 10⁴, plus less than a texel) stays 30° inside n's hemisphere, so
        // nothing is removed for Λ ≥ 10⁴.
        let n = tilted(r, 60f64.to_radians());
        for lambda in [1e4, 45_000.0, 1e5, 1e12] {
            let b = truth.eval(r, n, lambda, Visibility::CosPhiTest).unwrap();
            assert_close3(b, k, 1e-12, &format!("cos φ, 60°, r={r:?} Λ={lambda}"));
        }
        // For a wide lobe the test removes light: below the constant, never above.
        let b = truth.eval(r, n, 1.0, Visibility::CosPhiTest).unwrap();
        for c in 0..3 {
            assert!(b[c] < k[c] && b[c] > 0.5 * k[c], "{b:?}");
        }
    }
}

#[test]
fn lambda_zero_is_the_hemisphere_average() {
    let env = EnvMap::pattern(W, H);
    let truth = PhongTruth::new(&env);
    for r in directions(30) {
        let mut sum = [0.0; 3];
        let mut wsum = 0.0;
        for j in 0..H {
            for i in 0..W {
                if env.texel_dir(i, j).dot(r) >= 0.0 {
                    let s = env.texel_solid_angle(j);
                    let t = env.texel(i, j);
                    for c in 0..3 {
                        sum[c] += s * t[c];
                    }
                    wsum += s;
                }
            }
        }
        let want = sum.map(|x| x / wsum);
        let got = truth.eval(r, r, 0.0, Visibility::Simplified).unwrap();
        assert_close3(got, want, 1e-12, &format!("Λ = 0, r={r:?}"));
        // Λ → 0 is continuous (only texels exactly on the rim differ).
        let tiny = truth.eval(r, r, 1e-9, Visibility::Simplified).unwrap();
        assert_close3(tiny, want, 1e-6, &format!("Λ = 1e-9, r={r:?}"));
    }
}

#[test]
fn huge_lambda_gives_the_environment_in_direction_r() {
    let env = EnvMap::pattern(W, H);
    let truth = PhongTruth::new(&env);
    // At texel centres where sin θ ≥ 1/2: that texel (its nearest neighbours are
    // ≥ 2π/64 · ½ ≈ 0.049 rad away: weight ≤ e^(−Λ(1 − cos 0.049)) ≈ e^(−120)). Nearer
    // the poles the row's texels crowd together and share the lobe (next loop).
    for j in 5..H - 5 {
        for i in (0..W).step_by(5) {
            let got = truth
                .eval(
                    env.texel_dir(i, j),
                    v3(0.0, 1.0, 0.0),
                    1e5,
                    Visibility::Simplified,
                )
                .unwrap();
            assert_close3(got, env.texel(i, j), 1e-9, &format!("texel ({i},{j})"));
        }
    }
    // Anywhere: inside the spread (channel min/max) of the texels near the closest one.
    for r in directions(300) {
        let got = truth.eval(r, r, 1e5, Visibility::Simplified).unwrap();
        let mut best = f64::NEG_INFINITY;
        for j in 0..H {
            for i in 0..W {
                best = best.max(env.texel_dir(i, j).dot(r));
            }
        }
        let psi_max = best.clamp(-1.0, 1.0).acos();
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for j in 0..H {
            for i in 0..W {
                let psi = env.texel_dir(i, j).dot(r).clamp(-1.0, 1.0).acos();
                if psi <= psi_max + 0.05 {
                    let t = env.texel(i, j);
                    for c in 0..3 {
                        lo[c] = lo[c].min(t[c]);
                        hi[c] = hi[c].max(t[c]);
                    }
                }
            }
        }
        for c in 0..3 {
            assert!(
                got[c] >= lo[c] - 1e-12 && got[c] <= hi[c] + 1e-12,
                "r={r:?}: {got:?} outside {lo:?}..{hi:?}"
            );
        }
    }
}

#[test]
fn extreme_lambdas_and_a_sun_stay_finite() {
    // The pattern at half value with a sun at 10⁵ × the mean in one texel.
    let mut texels = EnvMap::pattern(W, H).into_texels();
    for t in texels.iter_mut() {
        *t = t.map(|c| 0.5 * c);
    }
    let base = EnvMap::new(W, H, texels.clone()).unwrap();
    let mean = base.mean();
    let sun_k = 9 * W + 17;
    texels[sun_k] = mean.map(|m| 1e5 * m);
    let env = EnvMap::new(W, H, texels).unwrap();
    let truth = PhongTruth::new(&env);
    let sun = env.texel_dir(17, 9);
    let mut rs = directions(60);
    rs.push(sun);
    rs.push(tilted(sun, 0.01));
    rs.push(tilted(sun, 0.2));
    let extra = [1e-300, 1e300, f64::MAX];
    for r in rs {
        for &lambda in LAMBDAS.iter().chain(&extra) {
            for vis in [Visibility::Simplified, Visibility::CosPhiTest] {
                for n in [r, tilted(r, 1.2), tilted(r, std::f64::consts::FRAC_PI_2)] {
                    let x = truth.eval(r, n, lambda, vis).unwrap();
                    assert!(
                        finite_nonneg(x),
                        "r={r:?} n={n:?} Λ={lambda} {vis:?}: {x:?}"
                    );
                }
            }
        }
    }
    // Looking at the sun with a sharp lobe gives the sun; a broad lobe its average share.
    let at_sun = truth.eval(sun, sun, 1e5, Visibility::Simplified).unwrap();
    assert_close3(at_sun, env.texels()[sun_k], 1e-9, "sun at Λ = 1e5");
    // At Λ = 1 the normaliser is ≈ ∫ cos = π, so the sun adds ≈ ΔΩ_sun · L_sun / π on
    // top of the (≤ 0.5) pattern.
    let broad = truth.eval(sun, sun, 1.0, Visibility::Simplified).unwrap();
    let share = env.texel_solid_angle(9) * env.texels()[sun_k][0] / std::f64::consts::PI;
    assert!(
        broad[0] > 0.9 * share && broad[0] < 1.1 * share + 0.5,
        "{broad:?} {share}"
    );
}

#[test]
fn grazing_reflection_with_the_cos_phi_test_is_defined() {
    let k = [2.0, 1.0, 0.5];
    let env = EnvMap::constant(W, H, k).unwrap();
    let truth = PhongTruth::new(&env);
    for r in directions(20) {
        // r·n = 0: the test cuts the lobe through its axis, about half is kept while the
        // lobe spans several texels (Λ ≤ 10 on 64 × 32; sharper lobes cover one or two
        // texels and the kept share is whatever side they fall on: 0 ..= 1).
        let n = tilted(r, std::f64::consts::FRAC_PI_2);
        for lambda in [0.0, 1.0, 10.0] {
            let x = truth.eval(r, n, lambda, Visibility::CosPhiTest).unwrap();
            let frac = x[0] / k[0];
            assert!(finite_nonneg(x), "{x:?}");
            assert!((frac - 0.5).abs() < 0.15, "r={r:?} Λ={lambda}: kept {frac}");
            assert_close3(x.map(|c| c / frac), k, 1e-12, "colour kept");
        }
        for lambda in [100.0, 1e3, 1e4, 1e5, 1e12] {
            let x = truth.eval(r, n, lambda, Visibility::CosPhiTest).unwrap();
            assert!(finite_nonneg(x) && x[0] <= k[0] * (1.0 + 1e-12), "{x:?}");
        }
        // Just past grazing (r·n = −10⁻³, not a real reflection) and n = −r: still defined.
        let n2 = tilted(r, std::f64::consts::FRAC_PI_2 + 1e-3);
        for lambda in [0.0, 1.0, 1e3, 1e5] {
            let x = truth.eval(r, n2, lambda, Visibility::CosPhiTest).unwrap();
            assert!(finite_nonneg(x) && x[0] <= k[0] * (1.0 + 1e-12), "{x:?}");
            let y = truth
                .eval(r, r * -1.0, lambda, Visibility::CosPhiTest)
                .unwrap();
            assert!(finite_nonneg(y) && y[0] <= 1e-9, "n = −r: {y:?}");
        }
    }
}

#[test]
fn pruning_error_is_within_its_bound() {
    let small = EnvMap::pattern(W, H);
    let big = EnvMap::pattern(512, 256);
    let (b_small, b_big) = (prune_error_bound(&small), prune_error_bound(&big));
    println!(
        "prune at Λ·ln(cos/cos_max) < −{PRUNE_LOG}: relative bound 4π e^-60/ΔΩ_min = \
         {b_small:.3e} (64×32), {b_big:.3e} (512×256)"
    );
    assert!(b_small < 1e-21 && b_big < 1e-18);
    // Against no pruning, on a map with a sun (where pruning matters most).
    let mut texels = small.into_texels();
    texels[5 * W + 3] = [1e5; 3];
    let env = EnvMap::new(W, H, texels).unwrap();
    let pruned = PhongTruth::new(&env);
    let full = PhongTruth::new(&env).with_prune_log(f64::INFINITY).unwrap();
    let bound = pruned.prune_error_bound();
    let mut worst = 0.0f64;
    for r in directions(60) {
        for &lambda in &LAMBDAS {
            for vis in [Visibility::Simplified, Visibility::CosPhiTest] {
                let n = tilted(r, 0.7);
                let a = pruned.eval(r, n, lambda, vis).unwrap();
                let b = full.eval(r, n, lambda, vis).unwrap();
                for c in 0..3 {
                    // Both sums also carry float rounding (~1e-15 relative).
                    let d = (a[c] - b[c]).abs();
                    worst = worst.max(d);
                    assert!(d <= bound + 1e-13 * b[c].abs(), "r={r:?} Λ={lambda}: {d}");
                }
            }
        }
        // Fewer texels take part as Λ grows.
        let counts: Vec<usize> = [0.0, 10.0, 1e3, 1e5]
            .iter()
            .map(|&l| pruned.kept_texels(r, l).unwrap())
            .collect();
        assert!(counts.windows(2).all(|w| w[0] >= w[1]), "{counts:?}");
        assert!(counts[3] >= 1);
    }
    println!("worst |pruned − unpruned| {worst:.3e} (bound {bound:.3e})");
    for bad in [0.0, -1.0, f64::NAN] {
        let e = PhongTruth::new(&env).with_prune_log(bad).unwrap_err();
        assert_eq!(e.field(), "phong_truth.prune_log");
    }
}

#[test]
fn bad_inputs_give_errors_naming_the_field() {
    let env = EnvMap::pattern(16, 8);
    let t = PhongTruth::new(&env);
    let r = v3(0.0, 0.0, 1.0);
    let s = Visibility::Simplified;
    let c = Visibility::CosPhiTest;
    let field =
        |res: Result<[f64; 3], rtl_model::error::ConfigError>| res.unwrap_err().field().to_string();
    assert_eq!(
        field(t.eval(v3(f64::NAN, 0.0, 1.0), r, 1.0, s)),
        "phong_truth.r"
    );
    assert_eq!(field(t.eval(v3(0.0, 0.0, 0.0), r, 1.0, s)), "phong_truth.r");
    assert_eq!(
        field(t.eval(r, v3(0.0, f64::INFINITY, 0.0), 1.0, c)),
        "phong_truth.n"
    );
    assert_eq!(field(t.eval(r, v3(0.0, 0.0, 0.0), 1.0, c)), "phong_truth.n");
    for bad in [f64::NAN, f64::INFINITY, -1.0, -1e-300] {
        assert_eq!(field(t.eval(r, r, bad, s)), "phong_truth.lambda");
    }
    // n is not used without the test.
    assert!(t.eval(r, v3(0.0, 0.0, 0.0), 1.0, s).is_ok());
    // Huge and tiny vectors normalise.
    let a = t.eval(v3(0.0, 0.0, 1e300), r, 10.0, s).unwrap();
    let b = t.eval(v3(0.0, 0.0, 1e-300), r, 10.0, s).unwrap();
    assert_eq!(a, b);
    // Arrays: the same values as one by one; errors name the element.
    let rs = directions(10);
    let ns: Vec<Vec3> = rs.iter().map(|&r| tilted(r, 0.3)).collect();
    let ls: Vec<f64> = (0..rs.len()).map(|k| 10f64.powi(k as i32 % 6)).collect();
    let many = t.eval_many(&rs, &ns, &ls, c).unwrap();
    for k in 0..rs.len() {
        assert_eq!(many[k], t.eval(rs[k], ns[k], ls[k], c).unwrap());
    }
    let mut bad = ls.clone();
    bad[3] = f64::NAN;
    assert_eq!(
        t.eval_many(&rs, &ns, &bad, c).unwrap_err().field(),
        "phong_truth.lambda[3]"
    );
    assert_eq!(
        t.eval_many(&rs, &ns[1..], &ls, c).unwrap_err().field(),
        "phong_truth.n"
    );
    assert_eq!(
        t.eval_many(&rs, &ns, &ls[1..], c).unwrap_err().field(),
        "phong_truth.lambda"
    );
    // Degenerate 1 × 1 map: r's hemisphere may hold no texel centre: nearest texel wins.
    let one = EnvMap::constant(1, 1, [3.0; 3]).unwrap();
    for r in directions(10) {
        let x = phong_truth(&one, r, r, 1e5, s).unwrap();
        assert_eq!(x, [3.0; 3]);
    }
}

#[test]
fn real_hdr_at_full_size() {
    // One 512 × 256 input to see the cost and the sun: a few directions only.
    let env = EnvMap::venice_sunset().unwrap();
    let t = PhongTruth::new(&env);
    let start = std::time::Instant::now();
    let mut count = 0;
    for r in directions(6) {
        for lambda in [0.0, 1.0, 100.0, 45_000.0, 1e5] {
            for vis in [Visibility::Simplified, Visibility::CosPhiTest] {
                let x = t.eval(r, tilted(r, 1.0), lambda, vis).unwrap();
                assert!(finite_nonneg(x), "{x:?}");
                count += 1;
            }
        }
    }
    let per = start.elapsed().as_secs_f64() / count as f64;
    println!(
        "512×256 Phong truth: {:.2} ms per direction ({count} directions)",
        per * 1e3
    );
}
