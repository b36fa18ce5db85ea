//! TEMPORARY stand-in until the reference helper's version lands (same API).

/// F(α) = K(1 + 9 cos¹⁶(α/2)).
pub fn phase_f(alpha_rad: f64, k: f64) -> f64 {
    k * (1.0 + 9.0 * (alpha_rad / 2.0).cos().powi(16))
}

/// h(s, t) = ρ exp(−ρκ(s + t)) / s².
pub fn h(s: f64, t: f64, rho: f64, kappa: f64) -> f64 {
    if s <= 0.0 {
        return if rho > 0.0 { f64::MAX } else { 0.0 };
    }
    rho * (-rho * kappa * (s + t)).exp() / (s * s)
}
