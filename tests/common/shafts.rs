//! The closed form of the single-scattering integral shared by the shafts tests.

/// ∫ sin^k φ dφ (antiderivative), by the reduction formula.
pub fn int_sin_pow(k: u32, phi: f64) -> f64 {
    match k {
        0 => phi,
        1 => -phi.cos(),
        _ => {
            -phi.sin().powi(k as i32 - 1) * phi.cos() / k as f64
                + (k as f64 - 1.0) / k as f64 * int_sin_pow(k - 2, phi)
        }
    }
}

/// Exact I_s for κ = 0, a point light of unit intensity at distance d from a ray whose
/// closest approach is at t0, over [0, T]: with x = t − t0 = d tan φ, cos α = −sin φ,
/// cos²(α/2) = (1 − sin φ)/2 and dt/s² = dφ/d, so
/// I = (ρK/d) ∫ [1 + 9 ((1 − sin φ)/2)^8] dφ — a polynomial in sin φ.
pub fn closed_form_point(rho: f64, k: f64, d: f64, t0: f64, t_end: f64) -> f64 {
    let binom = [1.0, 8.0, 28.0, 56.0, 70.0, 56.0, 28.0, 8.0, 1.0];
    let anti = |phi: f64| {
        let poly: f64 = (0..=8)
            .map(|j| binom[j] * (-1f64).powi(j as i32) * int_sin_pow(j as u32, phi))
            .sum();
        phi + 9.0 / 256.0 * poly
    };
    let (p0, p1) = ((-t0 / d).atan(), ((t_end - t0) / d).atan());
    rho * k / d * (anti(p1) - anti(p0))
}
