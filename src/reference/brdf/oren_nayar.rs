//! Oren–Nayar rough diffuse reflection (Oren and Nayar 1994): V-cavities of Lambertian
//! facets whose slope angle has standard deviation σ (radians). With α = max(θ_i, θ_o),
//! β = min(θ_i, θ_o) and cos Δφ the cosine of the azimuth difference (0 when either
//! direction is the normal, where the azimuth is undefined and every term using it is
//! multiplied by a zero anyway):
//!
//! * [`OrenNayarForm::Full`], the paper's full model, direct term plus the
//!   interreflection term:
//!   R = (ρ/π) [C₁ + cos Δφ C₂ tan β + (1 − |cos Δφ|) C₃ tan((α + β)/2)] plus the
//!   interreflection 0.17 (ρ²/π) σ²/(σ² + 0.13) [1 − cos Δφ (2β/π)²], with
//!   C₁ = 1 − 0.5 σ²/(σ² + 0.33),
//!   C₂ = 0.45 σ²/(σ² + 0.09) sin α (cos Δφ ≥ 0) or 0.45 σ²/(σ² + 0.09) (sin α − (2β/π)³),
//!   C₃ = 0.125 σ²/(σ² + 0.09) (4αβ/π²)².
//! * [`OrenNayarForm::Qualitative`], the paper's simplified model:
//!   R = (ρ/π) [A + B max(0, cos Δφ) sin α tan β], A = 1 − 0.5 σ²/(σ² + 0.33),
//!   B = 0.45 σ²/(σ² + 0.09).
//!
//! Every term is a symmetric function of (θ_i, θ_o) and of cos Δφ, so the model is
//! reciprocal exactly. Neither form is constructed to bound the albedo; it is measured.
//! σ = 0 is Lambert.

use super::model::{above_horizon, check_range, Brdf, BrdfParamError};
use crate::scene::math::Vec3;
use std::f64::consts::{FRAC_1_PI, FRAC_PI_2, PI};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OrenNayarForm {
    Full,
    Qualitative,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrenNayarParams {
    /// Facet albedo ρ ∈ [0, 1].
    pub rho: f64,
    /// Facet slope standard deviation σ, radians, in [0, 1.5].
    pub sigma: f64,
    pub form: OrenNayarForm,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrenNayar {
    pub params: OrenNayarParams,
}

impl OrenNayar {
    pub fn new(params: OrenNayarParams) -> Result<Self, BrdfParamError> {
        check_range(
            "oren_nayar",
            "rho",
            params.rho,
            0.0,
            1.0,
            "ρ must be in [0, 1]",
        )?;
        check_range(
            "oren_nayar",
            "sigma",
            params.sigma,
            0.0,
            1.5,
            "σ must be in [0, 1.5] radians",
        )?;
        Ok(OrenNayar { params })
    }
}

impl Brdf for OrenNayar {
    fn name(&self) -> String {
        match self.params.form {
            OrenNayarForm::Full => "oren_nayar".into(),
            OrenNayarForm::Qualitative => "oren_nayar_qualitative".into(),
        }
    }

    fn eval(&self, wi: Vec3, wo: Vec3) -> f64 {
        let Some((wi, wo)) = above_horizon(wi, wo) else {
            return 0.0;
        };
        let (rho, s2) = (self.params.rho, self.params.sigma * self.params.sigma);
        let pi_ = (wi.x * wi.x + wi.y * wi.y).sqrt();
        let po = (wo.x * wo.x + wo.y * wo.y).sqrt();
        // The angles from the components, not from acos(z): sin θ = |(x, y)|, cos θ = z,
        // and the complement γ = π/2 − θ = atan2(z, |(x, y)|) keeps its relative digits
        // near grazing, where tan β and 1 − (2β/π)³ would otherwise lose them.
        let side = |p: f64, z: f64| (p, z.min(1.0), z.min(1.0).atan2(p));
        // α is the direction nearer the horizon (the smaller cos θ, a tie broken by the
        // larger sin θ), β the other: the same choice either way round, so the model
        // stays exactly reciprocal.
        let ((sin_a, cos_a, gamma_a), (sin_b, cos_b, gamma_b)) = if (wi.z, -pi_) <= (wo.z, -po) {
            (side(pi_, wi.z), side(po, wo.z))
        } else {
            (side(po, wo.z), side(pi_, wi.z))
        };
        let (alpha, beta) = (FRAC_PI_2 - gamma_a, FRAC_PI_2 - gamma_b);
        let tan_beta = sin_b / cos_b;
        let cos_dphi = if pi_ > 0.0 && po > 0.0 {
            ((wi.x * wo.x + wi.y * wo.y) / (pi_ * po)).clamp(-1.0, 1.0)
        } else {
            0.0
        };
        let a = 1.0 - 0.5 * s2 / (s2 + 0.33);
        let b = 0.45 * s2 / (s2 + 0.09);
        match self.params.form {
            OrenNayarForm::Qualitative => {
                rho * FRAC_1_PI * (a + b * cos_dphi.max(0.0) * sin_a * tan_beta)
            }
            OrenNayarForm::Full => {
                // 2β/π = 1 − δ with δ = 2γ_β/π; the cubes and squares of 1 − δ are
                // expanded so that 1 − (1 − δ)ⁿ is formed without cancellation, and
                // 1 − sin α = cos²α/(1 + sin α).
                let delta = 2.0 * gamma_b / PI;
                let c2 = if cos_dphi >= 0.0 {
                    b * sin_a
                } else {
                    let one_minus_sin_a = cos_a * cos_a / (1.0 + sin_a);
                    let one_minus_cube = delta * (3.0 - 3.0 * delta + delta * delta);
                    b * (one_minus_cube - one_minus_sin_a)
                };
                let c3 = 0.125 * s2 / (s2 + 0.09) * (4.0 * alpha * beta / (PI * PI)).powi(2);
                // tan((α + β)/2) = 1/tan((γ_α + γ_β)/2).
                let tan_half_sum = 1.0 / (0.5 * (gamma_a + gamma_b)).tan();
                let direct =
                    a + cos_dphi * c2 * tan_beta + (1.0 - cos_dphi.abs()) * c3 * tan_half_sum;
                // 1 − cos Δφ (2β/π)² = (1 − cos Δφ) + cos Δφ (2δ − δ²).
                let one_minus_square = delta * (2.0 - delta);
                let inter = 0.17 * rho * s2 / (s2 + 0.13)
                    * ((1.0 - cos_dphi) + cos_dphi * one_minus_square);
                rho * FRAC_1_PI * (direct + inter)
            }
        }
    }
}
