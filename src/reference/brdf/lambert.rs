//! Lambert: R = ρ/π, the constant BRDF. Reciprocal trivially; directional albedo ρ at
//! every incidence (exactly, since ∫ cos θ dω = π), so energy-conserving for ρ ≤ 1.

use super::model::{above_horizon, check_range, Brdf, BrdfParamError};
use crate::scene::math::Vec3;

/// The Lambertian reflector of albedo `rho`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lambert {
    /// Directional albedo ρ ∈ [0, 1].
    pub rho: f64,
}

impl Lambert {
    pub fn new(rho: f64) -> Result<Self, BrdfParamError> {
        check_range(
            "lambert",
            "rho",
            rho,
            0.0,
            1.0,
            "the albedo must be in [0, 1]",
        )?;
        Ok(Lambert { rho })
    }
}

impl Brdf for Lambert {
    fn name(&self) -> String {
        "lambert".into()
    }
    fn eval(&self, wi: Vec3, wo: Vec3) -> f64 {
        match above_horizon(wi, wo) {
            Some(_) => self.rho * std::f64::consts::FRAC_1_PI,
            None => 0.0,
        }
    }
    fn energy_normalised(&self) -> bool {
        true
    }
}
