//! BRDF factor textures (pipeline::shading::factor): the SVD and homomorphic
//! factorisations on test materials with known factors, the quantised reconstruction
//! through texture_sampler + modulate against its derived bound, and the stiff cases.

use glare_pipeline::pipeline::shading::factor::homomorphic::{self, HomomorphicParams};
use glare_pipeline::pipeline::shading::factor::svd::{SvdFit, SvdParams};
use glare_pipeline::pipeline::shading::factor::{
    combine, difference_vector, from_half_difference, half_vector, parabolic_coords,
    parabolic_direction, FactorRenderer, FactorTarget, FactorTexture, Factorisation,
};
use glare_pipeline::pipeline::shading::sphere::SphereView;
use glare_pipeline::reference::brdf::Brdf;
use glare_pipeline::scene::math::{v3, Vec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::counters::Counters;
use rtl_model::units::modulate::ModulateChain;

/// A random direction of the open upper hemisphere (z ≥ 0.05).
fn upper(rng: &mut ChaCha8Rng) -> Vec3 {
    loop {
        let v = v3(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(0.05..1.0),
        );
        if v.length() <= 1.0 && v.length() > 0.1 {
            return v.normalized();
        }
    }
}

/// R · cos θ_i = a(h) · b(d): rank 1 in the half/difference parameterisation.
struct SeparableHd;
fn sep_a(h: Vec3) -> f64 {
    0.2 + h.z * h.z + 0.1 * h.x
}
fn sep_b(d: Vec3) -> f64 {
    1.0 + 0.5 * d.x + 0.3 * d.z * d.y
}
impl Brdf for SeparableHd {
    fn name(&self) -> String {
        "separable_hd".into()
    }
    fn eval(&self, wi: Vec3, wo: Vec3) -> f64 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        sep_a(half_vector(wi, wo)) * sep_b(difference_vector(wi, wo)) / wi.z
    }
}

/// R · cos θ_i = p₁(ω_i) p₂(h) p₃(ω_o), each log-linear in its parabolic coordinates
/// (ln p = slope · (s or t)), with an optional zero region of p₁ (ω_i.x < 0).
struct Product3 {
    zero_factor: bool,
}
impl Brdf for Product3 {
    fn name(&self) -> String {
        "product3".into()
    }
    fn eval(&self, wi: Vec3, wo: Vec3) -> f64 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let st = |v: Vec3| {
            let c = parabolic_coords(v);
            (2.0 * c[0] - 1.0, 2.0 * c[1] - 1.0)
        };
        let (si, _) = st(wi);
        let (_, th) = st(half_vector(wi, wo));
        let (so, to) = st(wo);
        let p1 = if self.zero_factor {
            wi.x.max(0.0)
        } else {
            (0.5 * si).exp()
        };
        let p2 = (-0.4 * th).exp();
        let p3 = (0.3 * so - 0.2 * to).exp();
        0.3 * p1 * p2 * p3 / wi.z
    }
}

/// R · cos θ_i = k (n·h)^s: a Blinn–Phong lobe that depends on h only.
struct BlinnLobe;
impl Brdf for BlinnLobe {
    fn name(&self) -> String {
        "blinn_lobe".into()
    }
    fn eval(&self, wi: Vec3, wo: Vec3) -> f64 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        0.9 * half_vector(wi, wo).z.powi(20) / wi.z
    }
}

#[test]
fn parameterisation_round_trips() {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for _ in 0..10_000 {
        let (wi, wo) = (upper(&mut rng), upper(&mut rng));
        let (h, d) = (half_vector(wi, wo), difference_vector(wi, wo));
        assert!((d.length() - 1.0).abs() < 1e-12 && d.z >= -1e-12, "d {d:?}");
        let (wi2, wo2) = from_half_difference(h, d);
        assert!((wi2 - wi).length() < 1e-12 && (wo2 - wo).length() < 1e-12);
        let uv = parabolic_coords(wi);
        let (back, inside) = parabolic_direction(uv);
        assert!(inside && (back - wi).length() < 1e-12);
    }
    // The pole, opposite directions and below the horizon: finite, no panic.
    let z = v3(0.0, 0.0, 1.0);
    assert_eq!(half_vector(z, z), z);
    assert!(difference_vector(v3(1.0, 0.0, 0.0), v3(-1.0, 0.0, 0.0))
        .length()
        .is_finite());
    let c = parabolic_coords(v3(0.0, 0.0, -1.0));
    assert!(c[0].is_finite() && c[1].is_finite());
}

fn small_svd() -> SvdParams {
    SvdParams {
        quadrature: 20,
        ..SvdParams::default()
    }
}

/// A rank-1 separable target is reproduced by the power iteration to f64 precision
/// (before any quantisation): at every pair of inside texel centres G·H = a·b.
#[test]
fn svd_reproduces_rank_one_exactly() {
    let fit = SvdFit::new(&SeparableHd, FactorTarget::BrdfCosine, &small_svd()).unwrap();
    assert!(
        fit.residual_rms <= 1e-12 * fit.target_rms,
        "residual {} of {} after {} iterations",
        fit.residual_rms,
        fit.target_rms,
        fit.iterations
    );
    let n = 16;
    let f = fit.textures(&SeparableHd, n).unwrap();
    let (g, h) = (&f.factors[0], &f.factors[1]);
    let mut worst: f64 = 0.0;
    for i in 0..n * n {
        let (hd, hin) = parabolic_direction(FactorTexture::texel_uv(n, i % n, i / n));
        if !hin {
            continue;
        }
        for j in (0..n * n).step_by(7) {
            let (dd, din) = parabolic_direction(FactorTexture::texel_uv(n, j % n, j / n));
            if din {
                let want = sep_a(hd) * sep_b(dd);
                let got = g.texels[i as usize] * h.texels[j as usize];
                if got == 0.0 {
                    // A texel within a few degrees of the horizon that no valid
                    // quadrature pair reaches keeps 0 (documented in svd.rs).
                    assert!(hd.z < 0.25 || dd.z < 0.25, "zero at h {hd:?}, d {dd:?}");
                    continue;
                }
                worst = worst.max((got - want).abs() / want);
            }
        }
    }
    assert!(worst <= 1e-10, "relative error {worst}");
}

/// The homomorphic fit of a product of three log-linear positive factors recovers it.
/// Tolerance: bilinear filtering of a log-linear factor is exact in log space, so the
/// model errors are (a) exp vs bilinear: the filter interpolates p, the fit its log —
/// at most δ²/8 per factor with δ = the log change across one texel (slope ≤ 1 per
/// unit texture coordinate → δ ≤ 1/N); (b) clamp to edge makes the last half texel flat,
/// off by ≤ δ/2 per factor, and the least-squares compromise spreads it. Pairs whose
/// coordinates are all a texel away from the edges must be within 3·δ/2 in log.
#[test]
fn homomorphic_recovers_a_product() {
    let n = 16;
    let p = HomomorphicParams {
        smoothness: 0.0,
        floor: 1e-9,
        tolerance: 1e-10,
        max_iterations: 2000,
        ..HomomorphicParams::default()
    };
    let b = Product3 { zero_factor: false };
    let (f, rep) = homomorphic::factorise(&b, FactorTarget::BrdfCosine, n, &p, None).unwrap();
    assert_eq!(rep.floored, 0);
    assert!(f
        .factors
        .iter()
        .all(|t| t.texels.iter().all(|v| v.is_finite() && *v > 0.0)));
    let delta = 1.0 / n as f64;
    let bound = 3.0 * delta / 2.0;
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let (mut worst, mut checked): (f64, u32) = (0.0, 0);
    while checked < 5000 {
        let (wi, wo) = (upper(&mut rng), upper(&mut rng));
        let interior = [wi, half_vector(wi, wo), wo].iter().all(|&v| {
            parabolic_coords(v)
                .iter()
                .all(|&c| c >= 1.0 / n as f64 && c <= 1.0 - 1.0 / n as f64)
        });
        if !interior {
            continue;
        }
        checked += 1;
        let want = FactorTarget::BrdfCosine.value(&b, wi, wo);
        worst = worst.max((f.eval(wi, wo) / want).ln().abs());
    }
    assert!(worst <= bound, "max |ln ratio| {worst} > {bound}");
}

/// The 8-bit (b-bit) reconstruction against its f64 twin stays within the bound derived
/// from the widths (FactorRenderer::error_bound_levels: 1 LSB_b per texture sample,
/// ½ LSB_n per widening, constant and modulate, × 2^shift, + ½ level when n > 8), and
/// so against the reference within that bound plus the f64 factorisation's own error.
#[test]
fn quantised_error_within_derived_bound() {
    let view = SphereView {
        size: 40,
        ..SphereView::default()
    };
    let svd = SvdFit::new(&SeparableHd, FactorTarget::BrdfCosine, &small_svd())
        .unwrap()
        .textures(&SeparableHd, 16)
        .unwrap();
    let b = Product3 { zero_factor: false };
    let p = HomomorphicParams {
        max_iterations: 300,
        ..HomomorphicParams::default()
    };
    let (hom, _) = homomorphic::factorise(&b, FactorTarget::BrdfCosine, 16, &p, None).unwrap();
    let reference = |brdf: &dyn Brdf| view.reference_levels(brdf);
    for (fact, refs) in [(&svd, reference(&SeparableHd)), (&hom, reference(&b))] {
        for bits in [4, 5, 8, 12, 16] {
            for irradiance in [1.0, 0.37, 3.0] {
                let v = SphereView { irradiance, ..view };
                let refs = if irradiance == 1.0 {
                    refs.clone()
                } else if fact.factors.len() == 2 {
                    v.reference_levels(&SeparableHd)
                } else {
                    v.reference_levels(&b)
                };
                let r = FactorRenderer::new(fact, bits, irradiance).unwrap();
                let bound = r.error_bound_levels();
                let mut ctr = Counters::default();
                let px = r.render(&v, &mut ctr).unwrap();
                for (i, p) in px.iter().enumerate() {
                    if let Some((hw, fl)) = p {
                        let q = (*hw as f64 - fl).abs();
                        assert!(
                            q <= bound + 1e-9,
                            "{:?} bits {bits} E {irradiance}: pixel {i} |hw − f64| {q} > {bound}",
                            fact.method
                        );
                        let own = (fl - refs[i]).abs();
                        assert!((*hw as f64 - refs[i]).abs() <= bound + own + 1e-9);
                    }
                }
            }
        }
    }
}

/// On a lobe that depends on h only (exactly rank 1), the f64 factors' error on the
/// sphere is the texture sampling alone and falls as the resolution grows (bilinear:
/// second order, so at least halving per doubling).
#[test]
fn error_falls_with_resolution() {
    let view = SphereView {
        size: 64,
        ..SphereView::default()
    };
    let reference = view.reference_levels(&BlinnLobe);
    let fit = SvdFit::new(&BlinnLobe, FactorTarget::BrdfCosine, &small_svd()).unwrap();
    let mut last = f64::INFINITY;
    for n in [8, 16, 32, 64] {
        let f = fit.textures(&BlinnLobe, n).unwrap();
        let r = FactorRenderer::new(&f, 16, 1.0).unwrap();
        let mut ctr = Counters::default();
        let px = r.render(&view, &mut ctr).unwrap();
        let (mut s2, mut k) = (0.0, 0.0);
        for (p, want) in px.iter().zip(&reference) {
            if let Some((_, fl)) = p {
                s2 += (fl - want).powi(2);
                k += 1.0;
            }
        }
        let rms = (s2 / k).sqrt();
        assert!(rms <= last / 2.0, "N = {n}: RMS {rms} vs {last} at N/2");
        last = rms;
    }
}

/// The floor's slack between samples: the active set holds every sample row's fit at or
/// below ln ε, and a pair between samples can exceed it by the filtered variation across
/// one texel (measured 1.024 ε at 16² with the default parameters).
const FLOOR_SLACK: f64 = 1.25;

/// Stiff case: a factor that is zero over half its domain (log 0 in the homomorphic
/// form). Documented behaviour: the floor ε stands in for 0 as a bound, so every texel
/// is finite and > 0, nothing is NaN, and deep inside the zero region (ω_i.x < −0.3,
/// more than a texel from its edge) the f64 reconstruction is ≤ 1.25 ε — its effect on
/// the output, 255·E·1.25 ε = 0.64 level at the default ε — and the quantised output
/// is within the quantisation bound of that.
#[test]
fn zero_factor_is_floored_not_nan() {
    let b = Product3 { zero_factor: true };
    let p = HomomorphicParams::default();
    let (f, rep) = homomorphic::factorise(&b, FactorTarget::BrdfCosine, 16, &p, None).unwrap();
    assert!(rep.floored > 0);
    assert!(f
        .factors
        .iter()
        .all(|t| t.texels.iter().all(|v| v.is_finite() && *v > 0.0)));
    let r = FactorRenderer::new(&f, 8, 1.0).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut ctr = Counters::default();
    let mut checked = 0;
    let mut worst: f64 = 0.0;
    while checked < 2000 {
        let (wi, wo) = (upper(&mut rng), upper(&mut rng));
        if wi.x >= -0.3 {
            continue;
        }
        checked += 1;
        let v = f.eval(wi, wo);
        worst = worst.max(v / p.floor);
        assert!(
            v.is_finite() && v <= FLOOR_SLACK * p.floor,
            "{v} at {wi:?} {wo:?}"
        );
        let hw = r.shade(wi, wo, &mut ctr).unwrap() as f64;
        let fl = r.shade_f64(wi, wo, &mut ctr).unwrap();
        assert!(fl <= 255.0 * FLOOR_SLACK * p.floor);
        assert!(hw <= fl + r.error_bound_levels(), "hw {hw} f64 {fl}");
    }
    assert!(worst > 0.0);
    // The SVD path on the same target: non-negative, finite.
    let s = SvdFit::new(&b, FactorTarget::BrdfCosine, &small_svd())
        .unwrap()
        .textures(&b, 8)
        .unwrap();
    assert!(s
        .factors
        .iter()
        .all(|t| t.texels.iter().all(|v| v.is_finite() && *v >= 0.0)));
}

/// A target that is zero everywhere: no NaN, no panic, a black sphere.
#[test]
fn all_zero_brdf_renders_black() {
    struct Black;
    impl Brdf for Black {
        fn name(&self) -> String {
            "black".into()
        }
        fn eval(&self, _: Vec3, _: Vec3) -> f64 {
            0.0
        }
    }
    let view = SphereView {
        size: 16,
        ..SphereView::default()
    };
    let s = SvdFit::new(&Black, FactorTarget::BrdfCosine, &small_svd())
        .unwrap()
        .textures(&Black, 8)
        .unwrap();
    let (h, _) = homomorphic::factorise(
        &Black,
        FactorTarget::BrdfCosine,
        8,
        &HomomorphicParams::default(),
        None,
    )
    .unwrap();
    for f in [&s, &h] {
        let r = FactorRenderer::new(f, 8, 1.0).unwrap();
        let mut ctr = Counters::default();
        let floor = HomomorphicParams::default().floor;
        for (hw, fl) in r.render(&view, &mut ctr).unwrap().into_iter().flatten() {
            assert!(fl.is_finite() && fl <= 255.0 * floor * 1.0001);
            assert!(hw as f64 <= fl + r.error_bound_levels());
        }
    }
}

/// The combine step: products by `modulate`, then the scale as a saturating shift
/// that counts its clamps.
#[test]
fn combine_scales_and_counts_saturations() {
    let m = ModulateChain::geforce();
    let mut ctr = Counters::default();
    assert_eq!(combine(&[255, 255], 0, &m, &mut ctr), 255);
    assert_eq!(combine(&[128, 255], 1, &m, &mut ctr), 255);
    assert_eq!(ctr.saturations, 1);
    assert_eq!(combine(&[64, 255], 1, &m, &mut ctr), 128);
    assert_eq!(combine(&[10, 255], 60, &m, &mut ctr), 255);
    assert_eq!(combine(&[0, 255], 60, &m, &mut ctr), 0);
    assert_eq!(ctr.saturations, 2);
}

/// Invalid parameters are errors naming the field, never a panic.
#[test]
fn invalid_parameters_name_the_field() {
    let field = |e: rtl_model::error::ConfigError| e.field().to_string();
    let bad = SvdParams {
        quadrature: 2,
        ..SvdParams::default()
    };
    assert_eq!(
        field(SvdFit::new(&BlinnLobe, FactorTarget::BrdfCosine, &bad).unwrap_err()),
        "svd.quadrature"
    );
    let bad = SvdParams {
        ceiling: f64::NAN,
        ..small_svd()
    };
    assert_eq!(
        field(SvdFit::new(&BlinnLobe, FactorTarget::BrdfCosine, &bad).unwrap_err()),
        "svd.ceiling"
    );
    let fit = SvdFit::new(&BlinnLobe, FactorTarget::BrdfCosine, &small_svd()).unwrap();
    assert_eq!(
        field(fit.textures(&BlinnLobe, 0).unwrap_err()),
        "svd.resolution"
    );
    for (p, name) in [
        (
            HomomorphicParams {
                floor: 0.0,
                ..HomomorphicParams::default()
            },
            "homomorphic.floor",
        ),
        (
            HomomorphicParams {
                smoothness: -1.0,
                ..HomomorphicParams::default()
            },
            "homomorphic.smoothness",
        ),
        (
            HomomorphicParams {
                samples_per_texel: 0,
                ..HomomorphicParams::default()
            },
            "homomorphic.samples_per_texel",
        ),
    ] {
        let e = homomorphic::factorise(&BlinnLobe, FactorTarget::BrdfCosine, 8, &p, None);
        assert_eq!(field(e.unwrap_err()), name);
    }
    let f: Factorisation = fit.textures(&BlinnLobe, 8).unwrap();
    assert_eq!(
        field(FactorRenderer::new(&f, 0, 1.0).unwrap_err()),
        "texture_sampler.texel_bits"
    );
    assert_eq!(
        field(FactorRenderer::new(&f, 17, 1.0).unwrap_err()),
        "modulate.bits"
    );
    assert_eq!(
        field(FactorRenderer::new(&f, 8, f64::NAN).unwrap_err()),
        "factor.irradiance"
    );
}

/// The reproduction end to end on a tiny sweep: CSV, plots, spheres and summary written,
/// every row finite, the quantisation inside its bound.
#[test]
fn reproduction_writes_its_files() {
    use glare_pipeline::pipeline::shading::factor::reproduce::{factorization, FactorSweep};
    let cfg = FactorSweep {
        resolutions: vec![32, 64],
        texel_bits: vec![6, 8],
        view: SphereView {
            size: 32,
            ..SphereView::default()
        },
        ceilings: vec![f64::INFINITY, 4.0],
        svd: small_svd(),
        homomorphic: HomomorphicParams {
            max_iterations: 40,
            ..HomomorphicParams::default()
        },
        ..FactorSweep::default()
    };
    let dir = std::env::temp_dir().join(format!("brdf-factor-{}", std::process::id()));
    let summary = factorization(&dir, &BlinnLobe, &cfg).unwrap();
    assert!(summary.iter().any(|l| l.starts_with("svd:")));
    for f in [
        "factorization.csv",
        "factorization_bits_ceiling_inf.png",
        "factorization_resolution_ceiling_4.png",
        "factorization_spheres.png",
        "factorization_summary.txt",
    ] {
        assert!(dir.join(f).exists(), "{f} missing");
    }
    let csv = std::fs::read_to_string(dir.join("factorization.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 2 * 2 * 2 * 2);
    let col = |c: &str| {
        glare_pipeline::report::csv_out::read_csv_column(&dir.join("factorization.csv"), c).unwrap()
    };
    let (q, bound, hw) = (col("quant_max"), col("quant_bound"), col("hw_rms"));
    for ((q, b), h) in q.iter().zip(&bound).zip(&hw) {
        assert!(
            q.is_finite() && h.is_finite() && q <= b,
            "quant {q} bound {b}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `reproduce shading-factorization --resume` (issue 16): a journal cut after the first
/// ceiling (the ∞ one: its floats must survive JSON) resumes to the uninterrupted run's
/// bytes — CSV, plots, spheres, summary and journal. A journal of another sweep is
/// refused.
#[test]
fn reproduction_resumes_from_a_cut_journal_to_the_same_bytes() {
    use glare_pipeline::pipeline::shading::factor::reproduce::{
        factorization_resumable, FactorSweep,
    };
    let cfg = FactorSweep {
        resolutions: vec![16, 32],
        texel_bits: vec![6, 8],
        view: SphereView {
            size: 24,
            ..SphereView::default()
        },
        ceilings: vec![f64::INFINITY, 4.0],
        svd: small_svd(),
        homomorphic: HomomorphicParams {
            max_iterations: 20,
            ..HomomorphicParams::default()
        },
        ..FactorSweep::default()
    };
    let base = std::env::temp_dir().join(format!("brdf-factor-resume-{}", std::process::id()));
    let (whole, cut) = (base.join("whole"), base.join("cut"));
    let a = factorization_resumable(&whole, &BlinnLobe, &cfg, false).unwrap();
    factorization_resumable(&cut, &BlinnLobe, &cfg, false).unwrap();
    let journal = cut.join("shading-factorization.resume.jsonl");
    let text = std::fs::read_to_string(&journal).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 3, "a record and two ceilings");
    std::fs::write(&journal, format!("{}\n", lines[..2].join("\n"))).unwrap();
    for f in std::fs::read_dir(&cut).unwrap() {
        let f = f.unwrap().path();
        if f != journal {
            std::fs::remove_file(f).unwrap();
        }
    }
    let b = factorization_resumable(&cut, &BlinnLobe, &cfg, true).unwrap();
    assert_eq!(a, b);
    let mut names: Vec<_> = std::fs::read_dir(&whole)
        .unwrap()
        .map(|f| f.unwrap().file_name())
        .collect();
    names.sort();
    assert!(names.len() >= 5, "{names:?}");
    for n in &names {
        let (x, y) = (
            std::fs::read(whole.join(n)).unwrap(),
            std::fs::read(cut.join(n)),
        );
        assert_eq!(Some(&x), y.as_ref().ok(), "{n:?} differs after the resume");
    }
    // Another sweep (one more texel width) is refused, naming the setting.
    let other = FactorSweep {
        texel_bits: vec![6, 8, 10],
        ..cfg
    };
    let e = factorization_resumable(&cut, &BlinnLobe, &other, true).unwrap_err();
    assert!(e.contains("sweep"), "{e}");
    let _ = std::fs::remove_dir_all(&base);
}
