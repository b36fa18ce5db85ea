//! The g = F(α)·h(s, t) tables (Dobashi et al. eq. (6)) as unorm texels: F a 1D texture over
//! α ∈ [0°, 180°], h a 2D texture over s ∈ [0, s_max], t ∈ [0, t_max].
//!
//! Normalisation: F is stored as F/F_max (F_max = 10K at α = 0). h is singular as
//! s → 0 (1/s²), so it is stored as min(h/h_ref, 1) with h_ref = h(s_near, 0), where
//! s_near is the smallest light distance the sample planes reach (at least one
//! texel); texels that clamp are counted (`h_clamped`). The scales F_max and h_ref go
//! into each plane's vertex colour.

use crate::reference::shafts_model::{h, phase_f};
use crate::scene::format::{Medium, ShaftsConfig};
use rtl_model::unorm::max_code;

/// Round-half-even of f·(2ⁿ − 1), clamped to [0, 2ⁿ − 1] (float → unorm as GL does).
pub fn unorm_from_unit(f: f64, bits: u32) -> u32 {
    let max = max_code(bits) as f64;
    let v = (f.clamp(0.0, 1.0) * max).round_ties_even();
    v as u32
}

/// The two tables and their scales.
#[derive(Clone, Debug, PartialEq)]
pub struct GTables {
    pub f_texels: Vec<u32>,
    pub h_texels: Vec<u32>,
    /// F value that texel code max stands for.
    pub f_max: f64,
    /// h value that texel code max stands for.
    pub h_ref: f64,
    pub s_max: f64,
    pub t_max: f64,
    /// h texels that clamped at h_ref (the 1/s² singularity near the light).
    pub h_clamped: u64,
}

/// Build the tables for `medium` over [0, s_max] × [0, t_max]. h_ref is h(s_near, 0),
/// lowered if needed to `h_ceiling`, the h at which one plane at F = F_max adds full
/// scale (so that the per-plane vertex colour never clamps; h beyond it clamps).
pub fn build(
    medium: &Medium,
    cfg: &ShaftsConfig,
    s_max: f64,
    t_max: f64,
    s_near: f64,
    alpha_min: f64,
    h_ceiling: f64,
) -> GTables {
    let bits = cfg.texel_bits;
    let nf = cfg.f_texels as usize;
    // Full scale of F: its largest value in the lit volume (F is stored clamped).
    let f_max = phase_f(alpha_min, medium.k);
    let f_texels = (0..nf)
        .map(|i| {
            let alpha = (i as f64 + 0.5) / nf as f64 * std::f64::consts::PI;
            let f = phase_f(alpha, medium.k);
            if f_max > 0.0 {
                unorm_from_unit(f / f_max, bits)
            } else {
                0
            }
        })
        .collect();
    let [hw, hh] = cfg.h_texels.map(|v| v as usize);
    let s_texel = s_max / hw as f64;
    let s_near = s_near.max(0.5 * s_texel).max(1e-9);
    let h_ref = h(s_near, 0.0, medium.rho, medium.kappa).min(h_ceiling);
    let mut h_clamped = 0u64;
    let mut h_texels = Vec::with_capacity(hw * hh);
    for j in 0..hh {
        let t = (j as f64 + 0.5) / hh as f64 * t_max;
        for i in 0..hw {
            let s = (i as f64 + 0.5) / hw as f64 * s_max;
            let v = if h_ref > 0.0 {
                h(s, t, medium.rho, medium.kappa) / h_ref
            } else {
                0.0
            };
            if v > 1.0 {
                h_clamped += 1;
            }
            h_texels.push(unorm_from_unit(v, bits));
        }
    }
    GTables {
        f_texels,
        h_texels,
        f_max,
        h_ref,
        s_max,
        t_max,
        h_clamped,
    }
}
