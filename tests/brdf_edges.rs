//! Numerical edges of the BRDF references, each found by an independent check (seeded
//! cases against implementations written from the papers, settled by 50-digit
//! evaluation): the value the reference must give at the edge, to the digits the
//! check settled.

use glare_pipeline::pipeline::shading::materials::MaterialBrdf;
use glare_pipeline::reference::brdf::cook_torrance::{
    fresnel_dielectric, fresnel_dielectric_transmittance,
};
use glare_pipeline::reference::brdf::{
    directional_albedo, AlbedoTol, Brdf, CookTorrance, CookTorranceParams, DipoleBrdf,
    DipoleParams, FixedSide, Fresnel, HanrahanKrueger, HanrahanKruegerParams, Masking,
    MicrofacetDistribution, OrenNayar, OrenNayarForm, OrenNayarParams,
};
use glare_pipeline::scene::material::Material;
use glare_pipeline::scene::math::{v3, Vec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn mirrored_azimuth(w: Vec3) -> Vec3 {
    v3(-w.x, -w.y, w.z)
}

fn oren_nayar(rho: f64, sigma: f64) -> OrenNayar {
    OrenNayar::new(OrenNayarParams {
        rho,
        sigma,
        form: OrenNayarForm::Full,
    })
    .unwrap()
}

/// Both directions 2.7·10⁻¹⁴ above the horizon, opposite azimuths: tan β from
/// acos(z) loses all but three digits there (it gave 0.19182059); sin β and cos β from
/// the vector's components keep them. 0.191695669046 is the documented formula
/// evaluated at 50 digits (mpmath) on these inputs; it is also the analytic limit at
/// grazing, (A − 6B/π + 2·0.17 σ²/(σ² + 0.13))/π, which smaller heights approach.
#[test]
fn oren_nayar_keeps_its_digits_at_grazing() {
    let on = oren_nayar(1.0, 0.3);
    let wi = v3(
        -0.011140813150393588,
        0.9999379392154035,
        2.6765904540671205e-14,
    );
    let got = on.eval(wi, mirrored_azimuth(wi));
    let exact = 0.191695669046;
    assert!(
        (got - exact).abs() < 1e-11,
        "Oren–Nayar at grazing: {got:.12}, exact {exact}"
    );
    let s2 = 0.09f64;
    let (a, b) = (1.0 - 0.5 * s2 / (s2 + 0.33), 0.45 * s2 / (s2 + 0.09));
    let limit =
        (a - 6.0 * b / std::f64::consts::PI + 0.34 * s2 / (s2 + 0.13)) / std::f64::consts::PI;
    for z in [1e-9, 1e-12, 1e-15, 1e-100, 1e-300] {
        let w = v3(0.6, 0.8, z);
        let got = on.eval(w, mirrored_azimuth(w));
        assert!(
            (got - limit).abs() < 1e-8,
            "height {z:e}: {got:.12}, limit {limit:.12}"
        );
    }
}

/// The full fit goes below zero near grazing at Δφ = π for σ ≳ 0.8 and ρ ≲ 0.5: the
/// reference keeps the paper's formula (docs/shading.md says where), and the shading
/// path's reference radiance clamps it at 0, as the hardware's unorm factor textures
/// cannot hold a negative value.
#[test]
fn oren_nayar_full_fit_goes_negative_and_the_shading_path_clamps_it() {
    let wi = v3(
        0.6501614546819368,
        -0.7597959389179139,
        0.00046265506985944084,
    );
    let wo = mirrored_azimuth(wi);
    let paper = oren_nayar(0.5, 1.0).eval(wi, wo);
    assert!(
        (paper - -0.0021785).abs() < 5e-8,
        "the paper's full fit: {paper:.8}, expected −0.0021785"
    );
    let material = MaterialBrdf::new(
        &Material::OrenNayar {
            sigma_deg: 1f64.to_degrees(),
        },
        [0.5; 3],
    )
    .unwrap();
    assert_eq!(material.eval(wi, wo), 0.0);
    // Where the fit is positive the shading path gives it unchanged.
    let wo_same = v3(wi.x, wi.y, 0.5).normalized();
    assert_eq!(
        material.eval(wi, wo_same),
        oren_nayar(0.5, 1.0).eval(wi, wo_same)
    );
}

/// At η = 1 there is no interface: F = 0 at every incidence. c² underflows below
/// 1.5·10⁻¹⁵⁴, and reading g² = 0 as total internal reflection gave F = 1.
#[test]
fn fresnel_at_index_one_is_zero_down_to_the_smallest_cosine() {
    for c in [
        1.0,
        0.5,
        1e-100,
        1.4e-154,
        1e-200,
        1e-300,
        f64::MIN_POSITIVE,
    ] {
        assert_eq!(fresnel_dielectric(c, 1.0), 0.0, "F({c:e}, 1)");
        assert_eq!(fresnel_dielectric_transmittance(c, 1.0), 1.0, "T({c:e}, 1)");
    }
    // Total internal reflection is still 1 where it happens (η < 1, sin θ_t > 1).
    assert_eq!(fresnel_dielectric(0.1, 0.8), 1.0);
    assert_eq!(fresnel_dielectric_transmittance(0.1, 0.8), 0.0);
}

/// 1 − F cancels near grazing (F → 1); the transmittance formed directly,
/// ½ (4cg/(c + g)² + 4η²cg/(η²c + g)²), keeps its relative digits: T ≈ 2c·(…) as c → 0.
#[test]
fn fresnel_transmittance_keeps_its_digits_near_grazing() {
    for eta in [1.0, 1.33, 1.5, 3.0] {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for _ in 0..2000 {
            let c: f64 = rng.random_range(1e-3..=1.0);
            let (f, t) = (
                fresnel_dielectric(c, eta),
                fresnel_dielectric_transmittance(c, eta),
            );
            assert!((f + t - 1.0).abs() < 1e-15, "η {eta} c {c}: F {f} + T {t}");
        }
        if eta == 1.0 {
            continue;
        }
        // Halving a tiny cosine halves the transmittance (T is linear in c at 0, η > 1).
        let (t1, t2) = (
            fresnel_dielectric_transmittance(1e-200, eta),
            fresnel_dielectric_transmittance(2e-200, eta),
        );
        assert!(
            t1 > 0.0 && (t2 / t1 - 2.0).abs() < 1e-12,
            "η {eta}: {t1:e} {t2:e}"
        );
    }
}

/// Jensen et al.'s BRDF at η = 1 (α′ = 0.99): F_t = 1 on both sides, so f = R_d/π
/// = 0.2376 at any pair of directions, the incident one 10⁻³⁰⁰ above the horizon too.
#[test]
fn dipole_brdf_at_index_one_does_not_vanish_at_grazing() {
    let brdf = DipoleBrdf::new(DipoleParams {
        sigma_a: 0.01,
        sigma_s_prime: 0.99,
        eta: 1.0,
    })
    .unwrap();
    let wi = v3(0.955336489125606, 0.29552020666133955, 1e-300);
    let wo = v3(0.0, 0.6, 0.8);
    let got = brdf.eval(wi, wo);
    assert!((got - 0.2376).abs() < 5e-5, "dipole BRDF at grazing: {got}");
    assert_eq!(
        got,
        brdf.eval(wo, wo),
        "F_t = 1 at every incidence when η = 1"
    );
}

/// Hanrahan–Krueger is symmetric in (ω_i, ω_o) by construction; evaluated with the
/// transmittances multiplied together before the albedo, it is bitwise so at any albedo.
#[test]
fn hanrahan_krueger_is_bitwise_reciprocal_at_any_albedo() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let dir = |rng: &mut ChaCha8Rng| {
        let z: f64 = rng.random_range(1e-6..1.0);
        let phi: f64 = rng.random_range(0.0..std::f64::consts::TAU);
        let s = (1.0 - z * z).sqrt();
        v3(s * phi.cos(), s * phi.sin(), z)
    };
    for (albedo, depth, g, eta) in [
        (0.7, 1e-6, 0.99, 3.0),
        (0.3, 2.0, -0.5, 1.5),
        (1.0, f64::INFINITY, 0.0, 1.33),
    ] {
        let hk = HanrahanKrueger::new(HanrahanKruegerParams {
            albedo,
            depth,
            g,
            eta,
        })
        .unwrap();
        for _ in 0..20_000 {
            let (a, b) = (dir(&mut rng), dir(&mut rng));
            assert_eq!(
                hk.eval(a, b).to_bits(),
                hk.eval(b, a).to_bits(),
                "albedo {albedo} τ {depth} g {g} η {eta}: {a:?} {b:?}"
            );
        }
    }
}

/// The albedo's stated error bounds its actual error where the V-cavity masking's
/// kinks meet a grazing light: GGX, F = 1, at 89.9°. The values are the normal-axis
/// chart's and a brute-force product rule's (both agree to 10⁻¹⁰, and with the
/// independent check's 50-digit value at α = 1); the mirror chart once gave
/// 0.998799033 ± 1.1·10⁻⁸ at α = 1 (190× its stated error).
#[test]
fn albedo_error_bounds_the_v_cavity_lobe_at_grazing() {
    for (alpha, exact) in [
        (1.0, 0.9987969054),
        (0.6, 0.9992210366),
        (0.3, 0.9993116747),
    ] {
        let lobe = CookTorrance::new(CookTorranceParams {
            distribution: MicrofacetDistribution::Ggx,
            alpha,
            fresnel: Fresnel::One,
            masking: Masking::VCavity,
        })
        .unwrap();
        let t = 89.9f64.to_radians();
        let a = directional_albedo(
            &lobe,
            v3(t.sin(), 0.0, t.cos()),
            FixedSide::Incident,
            AlbedoTol::default(),
        );
        assert!(a.converged, "α {alpha}: not converged");
        assert!(
            (a.value - exact).abs() <= a.error + 1e-10,
            "α {alpha}: {:.10} ± {:.1e}, the value is {exact}",
            a.value,
            a.error
        );
        assert!(a.error < 1e-7, "α {alpha}: stated error {:.1e}", a.error);
    }
}
