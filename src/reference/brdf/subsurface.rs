//! The two subsurface models Shinya's survey describes, as references.
//!
//! **Dipole diffusion** (Jensen, Marschner, Levoy and Hanrahan 2001), [`Dipole`]: a
//! semi-infinite medium of absorption σ_a, reduced scattering σ'_s and relative index η.
//! With σ'_t = σ_a + σ'_s, reduced albedo α' = σ'_s/σ'_t, σ_tr = √(3 σ_a σ'_t),
//! z_r = 1/σ'_t, z_v = z_r (1 + 4A/3), A = (1 + F_dr)/(1 − F_dr) and the diffuse
//! Fresnel reflectance fit F_dr = −1.440/η² + 0.710/η + 0.668 + 0.0636 η (fitted for
//! η ≈ 1…2; at η = 1 it gives +1.6·10⁻³, A = 1.0032):
//!
//!   R_d(r) = α'/(4π) [z_r (1 + σ_tr d_r) e^{−σ_tr d_r}/d_r³ + z_v (1 + σ_tr d_v) e^{−σ_tr d_v}/d_v³],
//!   d_r = √(r² + z_r²), d_v = √(r² + z_v²),
//!
//! whose integral 2π ∫₀^∞ R_d(r) r dr = (α'/2)(e^{−σ_tr z_r} + e^{−σ_tr z_v}) (each term
//! is z (1 + σd) e^{−σd}/d² dd = −z d(e^{−σd}/d)) is the closed form
//! R_d = (α'/2)(1 + e^{−(4/3) A √(3(1 − α'))}) e^{−√(3(1 − α'))}.
//! [`DipoleBrdf`] is the paper's BRDF approximation f = F_t(ω_i) R_d F_t(ω_o)/π,
//! F_t = 1 − F_dielectric(η): reciprocal, albedo F_t(ω_i) R_d (1 − F̄) ≤ 1.
//!
//! **Plane-parallel single scattering** (Hanrahan and Krueger 1993),
//! [`HanrahanKrueger`]: a layer of single-scattering albedo a = σ_s/σ_t, optical depth
//! τ_d (∞ allowed), Henyey–Greenstein phase g and index η under a smooth boundary. The
//! light refracts in (transmittance T_i = 1 − F(cos θ_i)), scatters once at angle ψ and
//! refracts out (T_o):
//!
//!   f = a T_i T_o p(cos ψ) (1 − e^{−τ_d (1/μ_i + 1/μ_o)}) / (η² (μ_i + μ_o)),
//!
//! μ the refracted cosines √(1 − sin²θ/η²) and
//! cos ψ = −((ω_i,x ω_o,x + ω_i,y ω_o,y)/η² + μ_i μ_o) the cosine between the refracted propagation directions. The 1/η² is the
//! radiance change on leaving the denser medium (with the solid-angle compression on
//! entering, it keeps the flux: ∫ f cos θ_o dω_o is the scattered fraction, ≤ 1).
//! Symmetric in (ω_i, ω_o) by construction.

use super::cook_torrance::fresnel_dielectric_transmittance;
use super::henyey_greenstein::HenyeyGreenstein;
use super::model::{above_horizon, check_range, Brdf, BrdfParamError, COS_FLOOR};
use crate::scene::math::Vec3;
use std::f64::consts::{FRAC_1_PI, PI};

/// Dipole parameters (lengths in any unit; σ in its inverse).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DipoleParams {
    /// Absorption coefficient σ_a ≥ 0.
    pub sigma_a: f64,
    /// Reduced scattering coefficient σ'_s = (1 − g) σ_s ≥ 0; σ_a + σ'_s > 0.
    pub sigma_s_prime: f64,
    /// Relative index η ∈ [1, 3].
    pub eta: f64,
}

/// The dipole diffusion profile.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dipole {
    pub params: DipoleParams,
}

/// The constants of the profile derived from the parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DipoleTerms {
    pub sigma_t_prime: f64,
    pub alpha_prime: f64,
    pub sigma_tr: f64,
    pub a: f64,
    pub z_r: f64,
    pub z_v: f64,
}

/// The diffuse Fresnel reflectance fit F_dr(η).
pub fn diffuse_fresnel_reflectance(eta: f64) -> f64 {
    -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta
}

impl Dipole {
    pub fn new(params: DipoleParams) -> Result<Self, BrdfParamError> {
        const M: &str = "dipole";
        check_range(
            M,
            "sigma_a",
            params.sigma_a,
            0.0,
            1e12,
            "σ_a must be in [0, 1e12]",
        )?;
        check_range(
            M,
            "sigma_s_prime",
            params.sigma_s_prime,
            0.0,
            1e12,
            "σ'_s must be in [0, 1e12]",
        )?;
        check_range(
            M,
            "sigma_s_prime",
            params.sigma_a + params.sigma_s_prime,
            1e-12,
            2e12,
            "σ_a + σ'_s must be > 0 (at least 1e-12)",
        )?;
        check_range(M, "eta", params.eta, 1.0, 3.0, "η must be in [1, 3]")?;
        Ok(Dipole { params })
    }

    /// From the reduced albedo α' ∈ [0, 1] and σ'_t > 0.
    pub fn from_albedo(
        alpha_prime: f64,
        sigma_t_prime: f64,
        eta: f64,
    ) -> Result<Self, BrdfParamError> {
        check_range(
            "dipole",
            "alpha_prime",
            alpha_prime,
            0.0,
            1.0,
            "α' must be in [0, 1]",
        )?;
        check_range(
            "dipole",
            "sigma_t_prime",
            sigma_t_prime,
            1e-12,
            1e12,
            "σ'_t must be in [1e-12, 1e12]",
        )?;
        Self::new(DipoleParams {
            sigma_a: (1.0 - alpha_prime) * sigma_t_prime,
            sigma_s_prime: alpha_prime * sigma_t_prime,
            eta,
        })
    }

    pub fn terms(&self) -> DipoleTerms {
        let p = &self.params;
        let sigma_t_prime = p.sigma_a + p.sigma_s_prime;
        let f_dr = diffuse_fresnel_reflectance(p.eta);
        let a = (1.0 + f_dr) / (1.0 - f_dr);
        let z_r = 1.0 / sigma_t_prime;
        DipoleTerms {
            sigma_t_prime,
            alpha_prime: p.sigma_s_prime / sigma_t_prime,
            sigma_tr: (3.0 * p.sigma_a * sigma_t_prime).sqrt(),
            a,
            z_r,
            z_v: z_r * (1.0 + 4.0 * a / 3.0),
        }
    }

    /// R_d(r): the diffuse reflectance per unit area at distance r ≥ 0 from the entry
    /// point, per unit incident flux (|r| is used; NaN gives 0).
    pub fn profile(&self, r: f64) -> f64 {
        if r.is_nan() {
            return 0.0;
        }
        let t = self.terms();
        let r2 = r * r;
        let pole = |z: f64| {
            let d = (r2 + z * z).sqrt();
            if !d.is_finite() {
                return 0.0;
            }
            z * (1.0 + t.sigma_tr * d) * (-t.sigma_tr * d).exp() / (d * d * d)
        };
        t.alpha_prime / (4.0 * PI) * (pole(t.z_r) + pole(t.z_v))
    }

    /// The closed-form total diffuse reflectance
    /// (α'/2)(1 + e^{−(4/3)A√(3(1−α'))}) e^{−√(3(1−α'))}.
    pub fn total_reflectance(&self) -> f64 {
        let t = self.terms();
        let s = (3.0 * (1.0 - t.alpha_prime)).sqrt();
        0.5 * t.alpha_prime * (1.0 + (-(4.0 / 3.0) * t.a * s).exp()) * (-s).exp()
    }
}

/// Jensen et al.'s BRDF approximation of the dipole: F_t(ω_i) R_d F_t(ω_o)/π.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DipoleBrdf {
    pub dipole: Dipole,
}

impl DipoleBrdf {
    pub fn new(params: DipoleParams) -> Result<Self, BrdfParamError> {
        Ok(DipoleBrdf {
            dipole: Dipole::new(params)?,
        })
    }
}

impl Brdf for DipoleBrdf {
    fn name(&self) -> String {
        "dipole_brdf".into()
    }
    fn eval(&self, wi: Vec3, wo: Vec3) -> f64 {
        let Some((wi, wo)) = above_horizon(wi, wo) else {
            return 0.0;
        };
        let eta = self.dipole.params.eta;
        let ti = fresnel_dielectric_transmittance(wi.z.min(1.0), eta);
        let to = fresnel_dielectric_transmittance(wo.z.min(1.0), eta);
        ti * to * self.dipole.total_reflectance() * FRAC_1_PI
    }
    fn energy_normalised(&self) -> bool {
        true
    }
}

/// Hanrahan–Krueger layer parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HanrahanKruegerParams {
    /// Single-scattering albedo σ_s/σ_t ∈ [0, 1].
    pub albedo: f64,
    /// Optical depth τ_d = σ_t · thickness, in [0, ∞] (∞: semi-infinite).
    pub depth: f64,
    /// Henyey–Greenstein asymmetry g ∈ (−1, 1).
    pub g: f64,
    /// Relative index η ∈ [1, 3].
    pub eta: f64,
}

/// The first-order (single-scattering) Hanrahan–Krueger BRDF of a layer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HanrahanKrueger {
    pub params: HanrahanKruegerParams,
    phase: HenyeyGreenstein,
}

impl HanrahanKrueger {
    pub fn new(params: HanrahanKruegerParams) -> Result<Self, BrdfParamError> {
        const M: &str = "hanrahan_krueger";
        check_range(
            M,
            "albedo",
            params.albedo,
            0.0,
            1.0,
            "the albedo must be in [0, 1]",
        )?;
        if params.depth.is_nan() || params.depth < 0.0 {
            return Err(BrdfParamError {
                model: M,
                param: "depth",
                value: format!("{}", params.depth),
                requirement: "the optical depth must be in [0, ∞]",
            });
        }
        check_range(M, "eta", params.eta, 1.0, 3.0, "η must be in [1, 3]")?;
        let phase =
            HenyeyGreenstein::new(params.g).map_err(|e| BrdfParamError { model: M, ..e })?;
        Ok(HanrahanKrueger { params, phase })
    }
}

impl Brdf for HanrahanKrueger {
    fn name(&self) -> String {
        "hanrahan_krueger".into()
    }
    fn eval(&self, wi: Vec3, wo: Vec3) -> f64 {
        let Some((wi, wo)) = above_horizon(wi, wo) else {
            return 0.0;
        };
        let p = &self.params;
        let inv_eta2 = 1.0 / (p.eta * p.eta);
        // μ² = 1 − sin²θ/η² = ((η² − 1) + cos²θ)/η² (no cancellation), floored so the
        // path 1/μ_i + 1/μ_o stays finite when cos θ² underflows.
        let refracted_cos = |w: Vec3| {
            (((p.eta * p.eta - 1.0) + w.z * w.z) * inv_eta2)
                .sqrt()
                .max(COS_FLOOR)
        };
        let (mu_i, mu_o) = (refracted_cos(wi), refracted_cos(wo));
        let cos_psi = -((wi.x * wo.x + wi.y * wo.y) * inv_eta2 + mu_i * mu_o);
        let t_i = fresnel_dielectric_transmittance(wi.z.min(1.0), p.eta);
        let t_o = fresnel_dielectric_transmittance(wo.z.min(1.0), p.eta);
        // 1 − e^{−τ(1/μ_i + 1/μ_o)}; μ > 0 above the horizon (μ ≥ √(1 − 1/η²) or = cos θ).
        let path = 1.0 / mu_i + 1.0 / mu_o;
        let absorbed = if p.depth.is_infinite() {
            1.0
        } else {
            -(-p.depth * path).exp_m1()
        };
        // The symmetric factors are multiplied together first (t_i·t_o), so swapping ω_i
        // and ω_o gives the same bits at any albedo.
        p.albedo * (t_i * t_o) * self.phase.phase(cos_psi) * absorbed * inv_eta2 / (mu_i + mu_o)
    }
    fn energy_normalised(&self) -> bool {
        true
    }
}
