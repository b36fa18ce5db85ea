//! f64 twin of `chaos_map`: the intermittent map of Matsuda and Ikedo (9)–(11) and the patch
//! average I_p = I·(1/n)·Σ S_i. Never NaN: S = 0 gives 0^z = 0; a, z are taken as
//! given (the caller keeps 0 < a < 1, 1 < z < 2).

/// u = (1 − a)/a^z, so that the left branch maps a to 1.
pub fn chaos_u(a: f64, z: f64) -> f64 {
    (1.0 - a) / a.powf(z)
}

/// The map as the hardware approximates it: for s ≤ a, s + max(u·s^z, min_step);
/// for s > a, (s − a)/(1 − a); the result clamped to [0, s_max]. The paper's map is
/// `chaos_step(s, a, z, 0.0, 1.0)`; the MinStep design uses min_step = 2⁻ᶠ and
/// s_max = 1 − 2⁻ᶠ.
pub fn chaos_step(s: f64, a: f64, z: f64, min_step: f64, s_max: f64) -> f64 {
    let next = if s <= a {
        let inc = if s > 0.0 {
            chaos_u(a, z) * s.powf(z)
        } else {
            0.0
        };
        s + inc.max(min_step)
    } else {
        (s - a) / (1.0 - a)
    };
    next.clamp(0.0, s_max)
}

/// The increment u·s^z alone (0 at s = 0).
pub fn chaos_increment(s: f64, a: f64, z: f64) -> f64 {
    if s > 0.0 {
        chaos_u(a, z) * s.powf(z)
    } else {
        0.0
    }
}

/// I_p = I·(1/n)·Σ S_i.
pub fn patch_intensity(states: &[f64], intensity: f64) -> f64 {
    if states.is_empty() {
        return 0.0;
    }
    intensity * states.iter().sum::<f64>() / states.len() as f64
}

/// Theoretical spectral exponent β of S(f) ∝ f^−β for the intermittent map
/// x + u·x^z (Manneville 1980; Schuster, "Deterministic Chaos"): β = (2z − 3)/(z − 1)
/// for 3/2 < z < 2, 0 (flat) for z ≤ 3/2.
pub fn spectral_exponent(z: f64) -> f64 {
    if z <= 1.5 {
        0.0
    } else {
        (2.0 * z - 3.0) / (z - 1.0)
    }
}
