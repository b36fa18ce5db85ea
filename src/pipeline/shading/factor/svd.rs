//! The separable approximation of Kautz and McCool (1999): v(ω_i, ω_o) ≈ G(h) · H(d),
//! the leading term σ₁ u₁ v₁ᵀ of the SVD of the matrix `M[h][d]` = v(ω_i(h, d), ω_o(h, d)).
//!
//! How it is computed (our own code, no linear-algebra dependency):
//! * M is sampled on a quadrature grid: the centres of a Q × Q grid over each
//!   parabolic disc (h rows, d columns; only centres inside the disc).
//! * Entries whose (ω_i, ω_o) has either direction at or below the horizon are never
//!   seen by a surface and are weighted 0 (missing data), so the fit does not bend the
//!   factors towards those zeros. With every weight 1 the iteration below is exactly the
//!   power iteration on M Mᵀ, i.e. the leading singular pair; with the mask it is the
//!   weighted rank-1 least-squares fit (alternating least squares):
//!   G_h = Σ_d w M H / Σ_d w H², H_d = Σ_h w M G / Σ_h w G².
//!   From a positive start on a non-negative M both factors stay ≥ 0.
//! * The texels of a resolution N are the same least-squares step evaluated at each
//!   texel centre against the converged other factor on the quadrature grid, so the
//!   textures at every resolution sample one pair of continuous factor functions.

use super::{
    from_half_difference, parabolic_direction, FactorMethod, FactorTarget, FactorTexture,
    Factorisation, Projection,
};
use crate::reference::brdf::Brdf;
use crate::scene::math::Vec3;
use rayon::prelude::*;
use rtl_model::error::{check_range, ConfigError};

/// Parameters of the separable fit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SvdParams {
    /// Quadrature grid per axis of each disc, 4 ..= 128 (default 48: ≈ 1 800 directions
    /// per disc, a 3.3-million-entry matrix).
    pub quadrature: u32,
    /// Most power iterations, ≥ 1 (default 500).
    pub max_iterations: u32,
    /// Stop when no entry of the max-normalised G moves by more than this (default 1e-13).
    pub tolerance: f64,
    /// Target values above this are fitted as this (> 0, may be ∞; default 1): with
    /// [`FactorTarget::BrdfCosine`] at irradiance E, 1/E is the value the 8-bit output
    /// saturates at, so a peak above it (a grazing-view spike of a microfacet lobe) need
    /// not inflate the textures' range and the output scale.
    pub ceiling: f64,
}

impl Default for SvdParams {
    fn default() -> Self {
        SvdParams {
            quadrature: 48,
            max_iterations: 500,
            tolerance: 1e-13,
            ceiling: f64::INFINITY,
        }
    }
}

/// The converged rank-1 fit on the quadrature grid.
#[derive(Clone, Debug)]
pub struct SvdFit {
    pub target: FactorTarget,
    pub ceiling: f64,
    /// Quadrature half vectors and difference vectors.
    h_dirs: Vec<Vec3>,
    d_dirs: Vec<Vec3>,
    /// G on `h_dirs` (max 1) and H on `d_dirs`.
    pub g: Vec<f64>,
    pub h: Vec<f64>,
    /// Power iterations run.
    pub iterations: u32,
    /// √(Σ w (M − G H)² / Σ w): the fit's RMS residual on the quadrature grid.
    pub residual_rms: f64,
    /// √(Σ w M² / Σ w): the RMS of the target, for scale.
    pub target_rms: f64,
}

/// The directions at the centres of a q × q grid that lie inside the parabolic disc.
fn disc_directions(q: u32) -> Vec<Vec3> {
    let mut out = Vec::new();
    for y in 0..q {
        for x in 0..q {
            let (d, inside) = parabolic_direction(FactorTexture::texel_uv(q, x, y));
            if inside {
                out.push(d);
            }
        }
    }
    out
}

/// The matrix entry at (h, d), or None when ω_i or ω_o is at or below the horizon.
fn entry(brdf: &dyn Brdf, target: Target, h: Vec3, d: Vec3) -> Option<f64> {
    let (wi, wo) = from_half_difference(h, d);
    (wi.z > 0.0 && wo.z > 0.0).then(|| target.0.value(brdf, wi, wo).min(target.1))
}

/// The target and its ceiling.
type Target = (FactorTarget, f64);

/// One least-squares step: Σ w M(row, c) f_c / Σ w f_c² over the columns `cols`
/// (`row_is_h` says whether the fixed direction is h or d). 0 if nothing is valid.
fn ls_step(
    brdf: &dyn Brdf,
    target: Target,
    fixed: Vec3,
    row_is_h: bool,
    cols: &[Vec3],
    f: &[f64],
) -> f64 {
    weighted_ratio(cols.iter().zip(f).filter_map(|(&c, &fc)| {
        let e = if row_is_h {
            entry(brdf, target, fixed, c)
        } else {
            entry(brdf, target, c, fixed)
        };
        e.map(|m| (m, fc))
    }))
}

/// The least-squares scale of one factor entry: Σ m f / Σ f² over the valid
/// (m, f) pairs, clamped ≥ 0; 0 when nothing is valid.
fn weighted_ratio(pairs: impl Iterator<Item = (f64, f64)>) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for (m, f) in pairs {
        num += m * f;
        den += f * f;
    }
    if den > 0.0 {
        (num / den).max(0.0)
    } else {
        0.0
    }
}

/// The fit's parameters, checked before any work (errors name `svd.<field>`).
fn check_params(params: &SvdParams) -> Result<(), ConfigError> {
    check_range("svd.quadrature", params.quadrature as u64, 4, 128)?;
    check_range(
        "svd.max_iterations",
        params.max_iterations as u64,
        1,
        u32::MAX as u64,
    )?;
    if params.ceiling.is_nan() || params.ceiling <= 0.0 {
        return Err(ConfigError::invalid(
            "svd.ceiling",
            &format!("{} is not a value > 0", params.ceiling),
        ));
    }
    if !(params.tolerance.is_finite() && params.tolerance >= 0.0) {
        return Err(ConfigError::invalid(
            "svd.tolerance",
            &format!("{} is not a finite value ≥ 0", params.tolerance),
        ));
    }
    Ok(())
}

/// The power iteration on the row-major `nh` × `nd` matrix `m` (entries < 0 have weight
/// 0): alternately H from G and G from H (G normalised to max 1), until G moves by at
/// most the tolerance or the iterations run out. Returns (G, H, iterations run).
fn power_iteration(
    m: &[f64],
    nh: usize,
    nd: usize,
    params: &SvdParams,
) -> (Vec<f64>, Vec<f64>, u32) {
    let mut g = vec![1.0; nh];
    let mut hf = vec![1.0; nd];
    let mut iterations = 0;
    for it in 1..=params.max_iterations {
        iterations = it;
        // H_d = Σ_h w M G / Σ_h w G²
        let mut num = vec![0.0; nd];
        let mut den = vec![0.0; nd];
        for (row, &gi) in m.chunks_exact(nd).zip(&g) {
            for ((&mv, n), dd) in row.iter().zip(num.iter_mut()).zip(den.iter_mut()) {
                if mv >= 0.0 {
                    *n += mv * gi;
                    *dd += gi * gi;
                }
            }
        }
        for ((x, n), dd) in hf.iter_mut().zip(&num).zip(&den) {
            *x = if *dd > 0.0 { (n / dd).max(0.0) } else { 0.0 };
        }
        // G_h = Σ_d w M H / Σ_d w H², then normalised to max 1.
        let new_g: Vec<f64> = m
            .par_chunks_exact(nd)
            .map(|row| {
                weighted_ratio(
                    row.iter()
                        .zip(&hf)
                        .filter(|(&mv, _)| mv >= 0.0)
                        .map(|(&mv, &x)| (mv, x)),
                )
            })
            .collect();
        let gmax = new_g.iter().copied().fold(0.0, f64::max);
        if gmax <= 0.0 {
            // An all-zero target: the zero factors are exact.
            g = new_g;
            hf.iter_mut().for_each(|x| *x = 0.0);
            break;
        }
        let new_g: Vec<f64> = new_g.iter().map(|x| x / gmax).collect();
        let change = new_g
            .iter()
            .zip(&g)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        g = new_g;
        for x in hf.iter_mut() {
            *x *= gmax;
        }
        if change <= params.tolerance {
            break;
        }
    }
    (g, hf, iterations)
}

/// Over the weighted entries of `m` (row-major, `nd` columns; < 0: weight 0): the
/// squared residual Σ (M − G H)², the squared target Σ M² and the count.
fn residual_sums(m: &[f64], nd: usize, g: &[f64], hf: &[f64]) -> (f64, f64, f64) {
    let (mut r2, mut t2, mut w) = (0.0, 0.0, 0.0);
    for (row, &gi) in m.chunks_exact(nd).zip(g) {
        for (&mv, &x) in row.iter().zip(hf) {
            if mv >= 0.0 {
                r2 += (mv - gi * x).powi(2);
                t2 += mv * mv;
                w += 1.0;
            }
        }
    }
    (r2, t2, w)
}

impl SvdFit {
    /// Sample M and run the power iteration. Errors name `svd.<field>`.
    pub fn new(
        brdf: &dyn Brdf,
        target: FactorTarget,
        params: &SvdParams,
    ) -> Result<Self, ConfigError> {
        check_params(params)?;
        let target_c = (target, params.ceiling);
        let h_dirs = disc_directions(params.quadrature);
        let d_dirs = disc_directions(params.quadrature);
        let nd = d_dirs.len();
        // Row-major M, −1 marks a weight-0 entry.
        let m: Vec<f64> = h_dirs
            .par_iter()
            .flat_map_iter(|&h| {
                d_dirs
                    .iter()
                    .map(move |&d| entry(brdf, target_c, h, d).unwrap_or(-1.0))
            })
            .collect();
        let (g, hf, iterations) = power_iteration(&m, h_dirs.len(), nd, params);
        let (r2, t2, w) = residual_sums(&m, nd, &g, &hf);
        let w = f64::max(w, 1.0);
        Ok(SvdFit {
            target,
            ceiling: params.ceiling,
            h_dirs,
            d_dirs,
            g,
            h: hf,
            iterations,
            residual_rms: (r2 / w).sqrt(),
            target_rms: (t2 / w).sqrt(),
        })
    }

    /// The two factor textures at `resolution` × `resolution` (1 ..= 4096): each texel
    /// the least-squares step at its centre direction (outside the disc: the direction
    /// at radius 1 − 1/(2·resolution), just inside the horizon, so a rim texel still
    /// sees valid pairs). A texel so close to the horizon that none of its pairs with
    /// the quadrature directions is above the horizon on both sides keeps 0 (in the tests
    /// only within a few degrees of the horizon, at Q = 20).
    pub fn textures(&self, brdf: &dyn Brdf, resolution: u32) -> Result<Factorisation, ConfigError> {
        check_range("svd.resolution", resolution as u64, 1, 4096)?;
        let n = resolution;
        let rim = 1.0 - 0.5 / n as f64;
        let dirs: Vec<Vec3> = (0..n * n)
            .map(|i| {
                let uv = FactorTexture::texel_uv(n, i % n, i / n);
                let (s, t) = (uv[0] * 2.0 - 1.0, uv[1] * 2.0 - 1.0);
                let r = (s * s + t * t).sqrt();
                let k = if r > rim { rim / r } else { 1.0 };
                parabolic_direction([(s * k + 1.0) * 0.5, (t * k + 1.0) * 0.5]).0
            })
            .collect();
        let target = (self.target, self.ceiling);
        let g_tex: Vec<f64> = dirs
            .par_iter()
            .map(|&h| ls_step(brdf, target, h, true, &self.d_dirs, &self.h))
            .collect();
        let h_tex: Vec<f64> = dirs
            .par_iter()
            .map(|&d| ls_step(brdf, target, d, false, &self.h_dirs, &self.g))
            .collect();
        Ok(Factorisation {
            method: FactorMethod::Svd,
            target: self.target,
            factors: vec![
                FactorTexture {
                    projection: Projection::Half,
                    size: n,
                    texels: g_tex,
                },
                FactorTexture {
                    projection: Projection::Difference,
                    size: n,
                    texels: h_tex,
                },
            ],
        })
    }
}

/// Fit and build the textures in one call.
pub fn factorise(
    brdf: &dyn Brdf,
    target: FactorTarget,
    resolution: u32,
    params: &SvdParams,
) -> Result<Factorisation, ConfigError> {
    SvdFit::new(brdf, target, params)?.textures(brdf, resolution)
}
