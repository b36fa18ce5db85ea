//! The single-scattering model of the light shafts (Dobashi et al.), in f64:
//!
//! * I_v = I_o · exp(−ρκT) + I_s                                  (1)
//! * I_s = ∫₀ᵀ H(t) · I_l(t) · g(α, s, t) dt                        (2)
//! * g(α, s, t) = F(α) · h(s, t)                                   (3)(6)
//! * F(α) = K · (1 + 9 cos¹⁶(α/2))                                 (4)
//! * h(s, t) = ρ · exp(−ρκ(s + t)) / s²                            (6)
//!
//! α is the scattering angle at P, 0 for pure forward scattering:
//! cos α = dot(norm(light − P), norm(P − eye)).
//!
//! Never NaN for finite, non-negative ρ, κ, K, s, t:
//! * s → 0: h → +∞ (h(0, t) = +∞ exactly when ρ·exp(−ρκt) > 0, and 0 when it is 0 —
//!   e.g. ρ = 0 or the exponential underflowed — never 0/0). The integral (2) through a
//!   point light lying on the ray diverges like 1/s, so the references integrate
//!   [`h_clamped`] with s replaced by max(s, s_min) ([`S_MIN`] by default).
//! * F · h with F = 0 (K = 0) and h = ∞ is 0, not NaN ([`g`]).
//! * ρκ = 0: no attenuation; ρκ huge: the exponentials underflow to exactly 0.
//! * α comes from acos of a cosine clamped to [−1, 1]; a zero-length direction (P at
//!   the eye or at the light) gives cos α = 0, i.e. α = 90°.

use crate::scene::format::Medium;
pub(crate) use crate::scene::math::mul_no_nan;
use crate::scene::math::Vec3;

/// The references' default clamp of the light distance in h (world units): the
/// integrand uses max(s, S_MIN). Only matters within S_MIN of a light; chosen far
/// below any texel of the hardware's h table (see [`h_table_s_min`]).
pub const S_MIN: f64 = 1e-6;

/// F(α) = K · (1 + 9 cos¹⁶(α/2)), α in radians (any finite α; the formula is even and
/// 2π-periodic in α/2 → the 16th power makes it well defined everywhere).
/// F(0) = 10K, F(π) = K.
pub fn phase_f(alpha_rad: f64, k: f64) -> f64 {
    let c = (0.5 * alpha_rad).cos();
    k * (1.0 + 9.0 * c.powi(16))
}

/// cos α at P for a light at `light` seen from `eye`: dot(norm(light − P), norm(P − eye)),
/// clamped to [−1, 1]; 0 when P coincides with the light or the eye.
pub fn cos_alpha(light: Vec3, p: Vec3, eye: Vec3) -> f64 {
    let c = (light - p).normalized().dot((p - eye).normalized());
    if c.is_nan() {
        0.0
    } else {
        c.clamp(-1.0, 1.0)
    }
}

/// The scattering angle α ∈ [0, π] in radians (acos of [`cos_alpha`]).
pub fn alpha(light: Vec3, p: Vec3, eye: Vec3) -> f64 {
    cos_alpha(light, p, eye).acos()
}

/// h(s, t) = ρ · exp(−ρκ(s + t)) / s². At s = 0 the result is +∞ if the numerator is
/// positive and 0 if it is 0 (ρ = 0 or underflow); never NaN for finite s, t ≥ 0 and
/// ρ, κ ≥ 0. Negative s is taken as |s|.
pub fn h(s: f64, t: f64, rho: f64, kappa: f64) -> f64 {
    let s = s.abs();
    let num = rho * (-(rho * kappa) * (s + t)).exp();
    if num == 0.0 {
        return 0.0;
    }
    let s2 = s * s;
    if s2 == 0.0 {
        f64::INFINITY
    } else {
        num / s2
    }
}

/// h with the light distance clamped from below: h(max(|s|, s_min), t) (the clamp
/// applies to the attenuation too, as in a table). Finite for s_min > 0.
///
/// The hardware's h table (a 2D texture over s ∈ [0, s_max], t ∈ [0, t_max], texels
/// sampled at their centres) cannot represent s below its first texel centre: for
/// s < s_min = [`h_table_s_min`] it returns the first column, i.e. this clamped value
/// (before its 8-bit quantisation, which further saturates the largest values at the
/// table's normalisation). Use that s_min to compare a reference with the hardware.
pub fn h_clamped(s: f64, t: f64, rho: f64, kappa: f64, s_min: f64) -> f64 {
    h(s.abs().max(s_min), t, rho, kappa)
}

/// The smallest s the hardware's h table represents: its first texel centre,
/// s_max / (2 · texels). 0 when `texels` is 0.
pub fn h_table_s_min(s_max: f64, texels: u32) -> f64 {
    if texels == 0 {
        0.0
    } else {
        s_max / (2.0 * texels as f64)
    }
}

/// g(α, s, t) = F(α) · h(s, t) for a medium (ρ, κ, K). 0 when either factor is 0
/// (so K = 0 at s = 0 gives 0, not NaN); +∞ at s = 0 otherwise.
pub fn g(alpha_rad: f64, s: f64, t: f64, medium: &Medium) -> f64 {
    mul_no_nan(
        phase_f(alpha_rad, medium.k),
        h(s, t, medium.rho, medium.kappa),
    )
}

/// g with the clamped h ([`h_clamped`]).
pub fn g_clamped(alpha_rad: f64, s: f64, t: f64, medium: &Medium, s_min: f64) -> f64 {
    mul_no_nan(
        phase_f(alpha_rad, medium.k),
        h_clamped(s, t, medium.rho, medium.kappa, s_min),
    )
}

/// exp(−ρκT), the attenuation of the object's radiance over the eye distance T.
pub fn attenuation(t_total: f64, medium: &Medium) -> f64 {
    let x = medium.rho * medium.kappa * t_total;
    if x.is_nan() {
        // 0 · ∞: no medium along an infinite path attenuates nothing.
        1.0
    } else {
        (-x).exp()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::math::v3;
    use std::f64::consts::PI;

    #[test]
    fn phase_end_points() {
        assert_eq!(phase_f(0.0, 2.0), 20.0);
        assert!((phase_f(PI, 2.0) - 2.0).abs() < 1e-15);
        // cos¹⁶(45°) = 2⁻⁸.
        assert!((phase_f(PI / 2.0, 1.0) - (1.0 + 9.0 / 256.0)).abs() < 1e-15);
    }

    #[test]
    fn h_singular_never_nan() {
        assert_eq!(h(0.0, 1.0, 0.5, 1.0), f64::INFINITY);
        assert_eq!(h(0.0, 1.0, 0.0, 1.0), 0.0);
        assert_eq!(h(0.0, 1e6, 1.0, 1e3), 0.0);
        assert_eq!(h_clamped(0.0, 0.0, 1.0, 0.0, 0.5), 4.0);
        let m = Medium {
            rho: 1.0,
            kappa: 0.0,
            k: 0.0,
        };
        assert_eq!(g(0.0, 0.0, 0.0, &m), 0.0);
        assert_eq!(attenuation(f64::INFINITY, &Medium { rho: 0.0, ..m }), 1.0);
    }

    #[test]
    fn alpha_forward_and_degenerate() {
        let eye = v3(0.0, 0.0, 0.0);
        let light = v3(0.0, 0.0, -10.0);
        assert_eq!(alpha(light, v3(0.0, 0.0, -5.0), eye), 0.0);
        assert!((alpha(light, v3(0.0, 0.0, -15.0), eye) - PI).abs() < 1e-15);
        assert_eq!(cos_alpha(light, light, eye), 0.0);
        assert_eq!(cos_alpha(light, eye, eye), 0.0);
    }
}
