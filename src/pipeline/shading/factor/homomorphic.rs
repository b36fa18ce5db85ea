//! Homomorphic factorisation (McCool, Ang and Ahmad 2001):
//! v(ω_i, ω_o) ≈ p₁(ω_i) · p₂(h) · p₃(ω_o), fitted in log space, so every factor is
//! exp(something) — positive by construction.
//!
//! The system: one row per sample pair (ω_i, ω_o),
//!   Σ_j Σ_corners w · `x_j[texel]` = ln max(v, ε),
//! with x_j = ln p_j the unknown log texels and w the bilinear weights the sampler will
//! use, plus smoothness rows √λ · (`x[a]` − `x[b]`) = 0 between neighbouring texels of each
//! factor (they settle texels no sample reaches, e.g. outside the parabolic disc).
//! Solved by conjugate gradients on the normal equations (CGLS, matrix-free).
//!
//! **The floor ε** ([`HomomorphicParams::floor`], default 10⁻⁴ in the target's units,
//! sr⁻¹): a zero (or tiny) target value is fitted as ln ε, not ln 0. Where the target
//! is zero the reconstruction therefore approaches ε, which costs 255 · E · ε levels in
//! the image (0.026 at E = 1) — invisible at 8 bits. A smaller ε makes the log system
//! stiffer around the zero region's border (a jump of ln(v/ε) the bilinear factors
//! cannot follow) without a visible gain.
//!
//! Samples: half are (ω_i, ω_o) drawn uniformly in both parabolic discs, half are
//! (h, d) drawn uniformly in theirs (so the h texture is covered up to its rim); pairs
//! with either direction at or below the horizon are dropped (never seen by a surface).

use super::{
    from_half_difference, parabolic_coords, parabolic_direction, FactorMethod, FactorTarget,
    FactorTexture, Factorisation, Projection,
};
use crate::reference::brdf::Brdf;
use crate::scene::math::Vec3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use rtl_model::error::{check_range, ConfigError};

/// The three projections, in texture order.
pub const PROJECTIONS: [Projection; 3] =
    [Projection::Incident, Projection::Half, Projection::Outgoing];

/// Parameters of the log-space fit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HomomorphicParams {
    /// ε: target values below it are fitted as ln ε (finite, > 0; default 10⁻⁴).
    pub floor: f64,
    /// Sample pairs per texel of one factor, ≥ 1 (default 8).
    pub samples_per_texel: u32,
    /// At least this many sample pairs (default 32 768).
    pub min_samples: u32,
    /// λ of the smoothness rows (finite, ≥ 0; default 1).
    pub smoothness: f64,
    /// Most CGLS iterations, ≥ 1 (default 600).
    pub max_iterations: u32,
    /// Stop when ‖Aᵀr‖ falls below this fraction of its start (default 1e-7).
    pub tolerance: f64,
    /// Target values above this are fitted as this (> 0, may be ∞; default 1): see
    /// [`super::svd::SvdParams::ceiling`].
    pub ceiling: f64,
    /// Seed of the sample pairs.
    pub seed: u64,
}

impl Default for HomomorphicParams {
    fn default() -> Self {
        HomomorphicParams {
            floor: 2e-3,
            samples_per_texel: 8,
            min_samples: 32_768,
            smoothness: 1.0,
            max_iterations: 600,
            tolerance: 1e-7,
            ceiling: f64::INFINITY,
            seed: 0x5EED_FAC7,
        }
    }
}

impl HomomorphicParams {
    pub fn validate(&self) -> Result<(), ConfigError> {
        if !(self.floor.is_finite() && self.floor > 0.0) {
            return Err(ConfigError::invalid(
                "homomorphic.floor",
                &format!("{} is not a finite value > 0", self.floor),
            ));
        }
        if self.ceiling.is_nan() || self.ceiling <= 0.0 {
            return Err(ConfigError::invalid(
                "homomorphic.ceiling",
                &format!("{} is not a value > 0", self.ceiling),
            ));
        }
        check_range(
            "homomorphic.samples_per_texel",
            self.samples_per_texel as u64,
            1,
            1 << 16,
        )?;
        check_range(
            "homomorphic.max_iterations",
            self.max_iterations as u64,
            1,
            u32::MAX as u64,
        )?;
        if !(self.smoothness.is_finite() && self.smoothness >= 0.0) {
            return Err(ConfigError::invalid(
                "homomorphic.smoothness",
                &format!("{} is not a finite value ≥ 0", self.smoothness),
            ));
        }
        if !(self.tolerance.is_finite() && self.tolerance >= 0.0) {
            return Err(ConfigError::invalid(
                "homomorphic.tolerance",
                &format!("{} is not a finite value ≥ 0", self.tolerance),
            ));
        }
        Ok(())
    }
}

/// What the fit did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HomomorphicReport {
    pub samples: usize,
    /// Samples whose target was below the floor (fitted as ln ε).
    pub floored: usize,
    /// Of those, the ones the final fit overshoots (the others are predicted ≤ ln ε).
    pub floored_fitted: usize,
    pub iterations: u32,
    /// RMS of the data rows' residual in log space (natural log).
    pub residual_rms_log: f64,
}

/// One data row: 12 (index, weight) pairs and the right-hand side.
#[derive(Clone, Copy, Debug)]
struct Row {
    idx: [u32; 12],
    w: [f32; 12],
    y: f64,
}

impl Row {
    /// The row's prediction Σ w · x[idx] (the fitted log value).
    fn predict(&self, x: &[f64]) -> f64 {
        self.idx
            .iter()
            .zip(&self.w)
            .map(|(&i, &w)| w as f64 * x[i as usize])
            .sum()
    }
}

/// The bilinear corners of texture coordinates `uv` on an n × n texture (the sampler's
/// convention: p = u·n − ½, clamp to edge): 4 (texel index, weight) pairs.
fn corners(uv: [f64; 2], n: u32) -> [(u32, f64); 4] {
    let (px, py) = (uv[0] * n as f64 - 0.5, uv[1] * n as f64 - 0.5);
    let (fx, fy) = (px.floor(), py.floor());
    let (ax, ay) = (px - fx, py - fy);
    let c = |i: f64| (i as i64).clamp(0, n as i64 - 1) as u32;
    let (x0, x1, y0, y1) = (c(fx), c(fx + 1.0), c(fy), c(fy + 1.0));
    [
        (y0 * n + x0, (1.0 - ax) * (1.0 - ay)),
        (y0 * n + x1, ax * (1.0 - ay)),
        (y1 * n + x0, (1.0 - ax) * ay),
        (y1 * n + x1, ax * ay),
    ]
}

/// A uniform point of the parabolic disc, as a direction.
fn disc_direction(rng: &mut ChaCha8Rng) -> Vec3 {
    loop {
        let uv = [rng.random::<f64>(), rng.random::<f64>()];
        let (d, inside) = parabolic_direction(uv);
        if inside {
            return d;
        }
    }
}

struct System {
    rows: Vec<Row>,
    /// Rows in the fit: a floored row whose prediction is already ≤ ln ε is dropped
    /// (the floor is a bound, not a value to match).
    active: Vec<bool>,
    n: u32,
    /// √λ.
    smooth: f64,
}

impl System {
    fn unknowns(&self) -> usize {
        3 * (self.n * self.n) as usize
    }

    /// Smoothness row pairs (a, b) of one texture (offset added by the caller).
    fn neighbours(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        let n = self.n as usize;
        (0..n * n).flat_map(move |i| {
            let (x, y) = (i % n, i / n);
            let right = (x + 1 < n).then_some((i, i + 1));
            let down = (y + 1 < n).then_some((i, i + n));
            right.into_iter().chain(down)
        })
    }

    /// A x: data rows, then smoothness rows.
    fn apply(&self, x: &[f64]) -> Vec<f64> {
        let mut out: Vec<f64> = self
            .rows
            .par_iter()
            .zip(&self.active)
            .map(|(r, &on)| if on { r.predict(x) } else { 0.0 })
            .collect();
        if self.smooth > 0.0 {
            let t = (self.n * self.n) as usize;
            for k in 0..3 {
                out.extend(
                    self.neighbours()
                        .map(|(a, b)| self.smooth * (x[k * t + a] - x[k * t + b])),
                );
            }
        }
        out
    }

    /// Aᵀ r.
    fn apply_t(&self, r: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.unknowns()];
        for ((row, &rv), _) in self
            .rows
            .iter()
            .zip(r)
            .zip(&self.active)
            .filter(|(_, &on)| on)
        {
            for (&i, &w) in row.idx.iter().zip(&row.w) {
                out[i as usize] += w as f64 * rv;
            }
        }
        if self.smooth > 0.0 {
            let t = (self.n * self.n) as usize;
            let mut k_rows = r[self.rows.len()..].iter();
            for k in 0..3 {
                for (a, b) in self.neighbours() {
                    let rv = self.smooth * k_rows.next().copied().unwrap_or(0.0);
                    out[k * t + a] += rv;
                    out[k * t + b] -= rv;
                }
            }
        }
        out
    }

    fn rhs(&self) -> Vec<f64> {
        let mut b: Vec<f64> = self
            .rows
            .iter()
            .zip(&self.active)
            .map(|(r, &on)| if on { r.y } else { 0.0 })
            .collect();
        if self.smooth > 0.0 {
            let count = 3 * self.neighbours().count();
            b.extend(std::iter::repeat_n(0.0, count));
        }
        b
    }
}

/// Passes of the floor's active set.
const FLOOR_PASSES: u32 = 6;

/// CGLS from `x`: returns the iterations run and the final residual b − A x.
fn cgls(sys: &System, x: &mut [f64], params: &HomomorphicParams) -> (u32, Vec<f64>) {
    let b = sys.rhs();
    let ax = sys.apply(x);
    let mut r: Vec<f64> = b.iter().zip(&ax).map(|(b, a)| b - a).collect();
    let mut s = sys.apply_t(&r);
    let mut p = s.clone();
    let mut gamma = dot(&s, &s);
    let gamma0 = gamma;
    let mut iterations = 0;
    for it in 1..=params.max_iterations {
        if gamma <= (params.tolerance * params.tolerance) * gamma0 || gamma == 0.0 {
            break;
        }
        iterations = it;
        let q = sys.apply(&p);
        let qq = dot(&q, &q);
        if qq <= 0.0 || !qq.is_finite() {
            break;
        }
        let alpha = gamma / qq;
        x.iter_mut().zip(&p).for_each(|(x, p)| *x += alpha * p);
        r.iter_mut().zip(&q).for_each(|(r, q)| *r -= alpha * q);
        s = sys.apply_t(&r);
        let g_new = dot(&s, &s);
        let beta = g_new / gamma;
        p.iter_mut().zip(&s).for_each(|(p, s)| *p = s + beta * *p);
        gamma = g_new;
    }
    (iterations, r)
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Fit p₁(ω_i) p₂(h) p₃(ω_o) at `resolution` × `resolution` (1 ..= 1024) texels each.
/// `warm`, if given, starts CGLS from its factors (e.g. the previous resolution's fit,
/// resampled bilinearly). Never panics; a target that is zero everywhere gives factors
/// whose product is ε.
pub fn factorise(
    brdf: &dyn Brdf,
    target: FactorTarget,
    resolution: u32,
    params: &HomomorphicParams,
    warm: Option<&Factorisation>,
) -> Result<(Factorisation, HomomorphicReport), ConfigError> {
    params.validate()?;
    check_range("homomorphic.resolution", resolution as u64, 1, 1024)?;
    let n = resolution;
    let texels = (n * n) as usize;
    let samples = (params.samples_per_texel as usize * texels).max(params.min_samples as usize);
    let pairs = sample_pairs(params.seed, samples);
    let ln_floor = params.floor.ln();
    let rows = log_rows(brdf, target, params, &pairs, n);
    let floored = rows.iter().filter(|r| r.y == ln_floor).count();
    let active = vec![true; rows.len()];
    let mut sys = System {
        active,
        rows,
        n,
        smooth: params.smoothness.sqrt(),
    };
    let mut x = start_logs(&sys, warm, params);
    let (iterations, r) = solve_with_floor(&mut sys, &mut x, params, ln_floor);
    let data = sys.rows.len();
    let fitted = sys.active.iter().filter(|&&on| on).count();
    let residual_rms_log =
        (r[..data].iter().map(|v| v * v).sum::<f64>() / fitted.max(1) as f64).sqrt();
    // exp, kept finite: ln of the largest f64 is ≈ 709.
    let factors = PROJECTIONS
        .iter()
        .enumerate()
        .map(|(k, &projection)| FactorTexture {
            projection,
            size: n,
            texels: x[k * texels..(k + 1) * texels]
                .iter()
                .map(|v| v.clamp(-700.0, 700.0).exp())
                .collect(),
        })
        .collect();
    Ok((
        Factorisation {
            method: FactorMethod::Homomorphic,
            target,
            factors,
        },
        HomomorphicReport {
            samples: data,
            floored,
            floored_fitted: sys
                .rows
                .iter()
                .zip(&sys.active)
                .filter(|(r, &on)| on && r.y == ln_floor)
                .count(),
            iterations,
            residual_rms_log,
        },
    ))
}

/// `samples` (ω_i, ω_o) pairs above the surface from the seeded generator: even ones
/// two disc directions, odd ones a half and a difference vector (the specular peak
/// sampled densely).
fn sample_pairs(seed: u64, samples: usize) -> Vec<(Vec3, Vec3)> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut pairs = Vec::with_capacity(samples);
    while pairs.len() < samples {
        let (wi, wo) = if pairs.len() % 2 == 0 {
            (disc_direction(&mut rng), disc_direction(&mut rng))
        } else {
            from_half_difference(disc_direction(&mut rng), disc_direction(&mut rng))
        };
        if wi.z > 0.0 && wo.z > 0.0 {
            pairs.push((wi, wo));
        }
    }
    pairs
}

/// One least-squares row per pair: the log target (clamped to the ceiling, ln ε at or
/// below the floor) against the bilinear weights (f32) of the three factors' 4 texels
/// each at `n` × `n`.
fn log_rows(
    brdf: &dyn Brdf,
    target: FactorTarget,
    params: &HomomorphicParams,
    pairs: &[(Vec3, Vec3)],
    n: u32,
) -> Vec<Row> {
    let ln_floor = params.floor.ln();
    pairs
        .par_iter()
        .map(|&(wi, wo)| {
            let v = target.value(brdf, wi, wo).min(params.ceiling);
            let mut idx = [0u32; 12];
            let mut w = [0f32; 12];
            for (k, p) in PROJECTIONS.iter().enumerate() {
                let cs = corners(parabolic_coords(p.direction(wi, wo)), n);
                for (c, (i, wt)) in cs.iter().enumerate() {
                    idx[4 * k + c] = k as u32 * n * n + i;
                    w[4 * k + c] = *wt as f32;
                }
            }
            Row {
                idx,
                w,
                y: if v > params.floor { v.ln() } else { ln_floor },
            }
        })
        .collect()
}

/// Start: the warm factors' logs at this resolution's texel centres, else the mean
/// log target split evenly over the three factors.
fn start_logs(sys: &System, warm: Option<&Factorisation>, params: &HomomorphicParams) -> Vec<f64> {
    let n = sys.n;
    let texels = (n * n) as usize;
    match warm {
        Some(wf) if wf.factors.len() == 3 => {
            let mut x = Vec::with_capacity(sys.unknowns());
            for f in &wf.factors {
                for i in 0..texels as u32 {
                    let v = f.bilinear(FactorTexture::texel_uv(n, i % n, i / n));
                    x.push(v.max(params.floor).ln());
                }
            }
            x
        }
        _ => {
            let mean = sys.rows.iter().map(|r| r.y).sum::<f64>() / sys.rows.len().max(1) as f64;
            vec![mean / 3.0; sys.unknowns()]
        }
    }
}

/// Active set on the floor: a floored row is a bound (fit ≤ ln ε), not a value to
/// match. Solve, then keep only the floored rows the fit overshoots, and re-solve
/// until the set stops changing (at most FLOOR_PASSES solves). Returns the CGLS
/// iterations and the residual of the final set (rows switched off count 0).
fn solve_with_floor(
    sys: &mut System,
    x: &mut [f64],
    params: &HomomorphicParams,
    ln_floor: f64,
) -> (u32, Vec<f64>) {
    let mut iterations = 0;
    let mut r = Vec::new();
    for _pass in 0..FLOOR_PASSES {
        let (it, res) = cgls(sys, x, params);
        iterations += it;
        r = res;
        let mut changed = false;
        for (row, on) in sys.rows.iter().zip(sys.active.iter_mut()) {
            let want = row.y != ln_floor || row.predict(x) > ln_floor;
            changed |= want != *on;
            *on = want;
        }
        if !changed {
            break;
        }
    }
    for (rv, &on) in r.iter_mut().zip(&sys.active) {
        if !on {
            *rv = 0.0;
        }
    }
    (iterations, r)
}
