//! The Henyey–Greenstein phase function
//!
//!   p(cos θ) = (1/4π) (1 − g²) / (1 + g² − 2g cos θ)^{3/2},
//!
//! θ the scattering angle between the propagation directions before and after the
//! event (cos θ = 1 is straight on; g > 0 scatters forward). Shinya's survey writes
//! the exponent as 2/3, a typo: only 3/2 integrates to 1 over the sphere. Its
//! "+2g s·s'" has s pointing back toward the light, the same function.
//!
//! Normalised, ∫ p dω = 1, with mean cosine ∫ p cos θ dω = g (tested to 1e-6 over
//! g ∈ [−0.99, 0.99] and beyond). Stiffness as g → ±1: the denominator is evaluated
//! as (1 − |g|)² + 2|g|(1 ∓ cos θ), a sum of non-negative terms, so there is no
//! cancellation and no division by 0 for |g| < 1; the peak (1 + |g|)/(4π (1 − |g|)²)
//! is finite (≈ 1.6e29 at 1 − |g| = 1e-15). |g| = 1 itself is a Dirac delta, not a
//! function: the constructor rejects it (and |g| > 1, which is not a phase function).

use super::model::{check_range, BrdfParamError};
use std::f64::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HenyeyGreenstein {
    /// Asymmetry g ∈ (−1, 1): the mean cosine.
    pub g: f64,
}

impl HenyeyGreenstein {
    pub fn new(g: f64) -> Result<Self, BrdfParamError> {
        let below_one = 1.0 - f64::EPSILON / 2.0;
        check_range(
            "henyey_greenstein",
            "g",
            g,
            -below_one,
            below_one,
            "g must be in the open interval (−1, 1); ±1 is a delta",
        )?;
        Ok(HenyeyGreenstein { g })
    }

    /// p(cos θ), sr⁻¹; cos θ is clamped to [−1, 1] (NaN gives 0).
    pub fn phase(&self, cos_theta: f64) -> f64 {
        if cos_theta.is_nan() {
            return 0.0;
        }
        let c = cos_theta.clamp(-1.0, 1.0);
        let g = self.g;
        let a = g.abs();
        // 1 + g² − 2g c = (1 − |g|)² + 2|g| (1 − sign(g) c): no cancellation.
        let one_minus_sc = if g >= 0.0 { 1.0 - c } else { 1.0 + c };
        let d = (1.0 - a) * (1.0 - a) + 2.0 * a * one_minus_sc;
        (1.0 - a) * (1.0 + a) / (4.0 * PI * d * d.sqrt())
    }

    /// The mean cosine, g.
    pub fn mean_cosine(&self) -> f64 {
        self.g
    }
}
