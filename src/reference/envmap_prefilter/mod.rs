//! Multi-scale environment map prefilter — f64 building blocks (Okumura's
//! thesis, eqs. (8)–(14)): the roughness map g(|t|), geodesic domes, the
//! environment pyramid, log-domain normalised Phong weights, the exact prefilter of
//! one voxel and the weight-table entry selection. The voxel-map and table builds
//! come later.
//!
//! Direction conventions: see the `equirect` module (φ = 0 along −z, increasing towards +x;
//! θ from +y; d = (sin θ sin φ, cos θ, −sin θ cos φ); right-handed, y up).
//!
//! # Reading of the thesis' equations
//!
//! **(13)** Λ = g(|t|) = −log I / log cos(arctan(2/(|t|·s))). With x = 2/(|t|·s),
//! cos(arctan x) = 1/√(1 + x²), so g = 2 ln I / ln(1 + x²) — evaluated that way
//! (`ln_1p`), which is exact where the literal form loses everything to rounding
//! (at |t| = 1, s = 128, cos ψ = 1 − 1.2·10⁻⁴). The log base cancels.
//! At |t| = 1, s = 128, I = 256: Λ = 45 431.64 (the SPEC's "~45 000"). Large |t|·s:
//! Λ ≈ ln I·(|t|s)²/2, monotone increasing, so |t| > 1 (the cube's corners reach √3)
//! just gives larger Λ (g(√3) ≈ 1.36·10⁵). |t| → 0: x → ∞, Λ → 0, but only like
//! ln I / ln(2/(|t|s)) (slowly: Λ(1/s) = 6.9). g(0) is defined as 0 (the limit);
//! NaN |t| → 0, negative |t| uses |t|, I ≤ 1 → 0 (nothing representable), s ≤ 0 →
//! 0; the result is always finite (capped at f64::MAX) and ≥ 0.
//!
//! **(8)(9)** F(t) = Σ_{ω: 0 ≤ t·ω} Ω(ω)·w(t, ω),
//! w(t, ω) = (t·ω)^Λ / Σ_{ρ: 0 ≤ t·ρ} (t·ρ)^Λ. In the thesis Ω is *the input
//! environment map* ("入力となる単位球面上に定義された環境マップを Ω") and Ω(ω) its
//! value at pixel ω — the radiance L(ω), not a solid angle; likewise Ω(ω_ij) in (14).
//! Read literally, (9) weights every pixel equally (no solid angle anywhere), which
//! is a quadrature of ∫cos^Λ ψ L dω / ∫cos^Λ ψ dω only when the samples have equal
//! solid angles — the thesis' reason for resampling onto geodesic domes ("環境マップの
//! 形式による解像度の偏りが無くなる"). So two weightings are offered:
//! * [`Weighting::SolidAngle`] (default): w = ΔΩ(ω)·(t̂·ω)^Λ / Σ_ρ ΔΩ(ρ)·(t̂·ρ)^Λ,
//!   F = Σ w·L — the solid-angle quadrature of the normalised Phong lobe (the sample
//!   solid angle ΔΩ is inside the normalisation, so Σ w = 1). This is the one that is
//!   right on an equirectangular map, and on a dome it differs from the literal form
//!   only by the dome's small solid-angle non-uniformity.
//! * [`Weighting::Uniform`]: the literal (9), ΔΩ ≡ 1.
//!
//! (t·ω)^Λ = |t|^Λ (t̂·ω)^Λ and |t|^Λ cancels, so t̂ is used for t ≠ 0. Weights are
//! computed in the log domain: with m = max over the hemisphere of ln(t̂·ω),
//! u = ΔΩ·exp(Λ·(ln(t̂·ω) − m)) (the maximum term is exactly ΔΩ·1, so the sum is never
//! zero and nothing overflows for any Λ ∈ [0, ∞]); Λ·0 is taken as 0 (Λ = ∞ keeps only
//! the nearest samples), t̂·ω = 0 contributes 0^Λ = 0 for Λ > 0 and 0⁰ = 1 for Λ = 0.
//!
//! **t = 0** (the centre voxel; λ = 0, outside the thesis' 0 < λ ≤ 1): read (8)(9)
//! with t itself, every ω satisfies 0 ≤ t·ω and (t·ω)^g(0) = 0⁰ = 1, so F(0) is the
//! plain (ΔΩ-weighted) mean over the *whole sphere*. That is what is implemented.
//! Note the limit t → 0 along a direction t̂ is instead the hemisphere mean around t̂
//! (Λ → 0): F is discontinuous at the centre, as the thesis' formula is.
//!
//! **(14) and th**: the table keeps the entries with cos^Λ ψ > th, cos^Λ ψ = (t̂·ω)^Λ
//! the *un-normalised* lobe (peak 1 at ψ = 0), and stores the full-hemisphere
//! normalised weights w of (9) — not renormalised over the kept set, so
//! F(t_i) = Σ_j L(ω_ij)·w_ij loses the pruned weight (for a narrow lobe, ≈ th of
//! it: the mass of a 2-D Gaussian below th × its peak is th; measured 0.097 at
//! Λ = 1000, th = 0.1 on the n = 72 dome). The thesis does not say which; its Table 3
//! errors grow linearly in th (per channel 1.9 / 3.8 / 19 / 38 levels at th = 0.005 /
//! 0.01 / 0.05 / 0.1, pattern map), which fits lost weight better than a renormalised
//! truncation — but 38 levels at th = 0.1 is more than 0.1 × 255, so lost weight
//! alone does not explain the size: an open doubt. [`WeightEntries::kept_weight`] gives the
//! kept sum so a caller can renormalise if wanted.

// `!(x > 0.0)` is deliberate: it is true for NaN, which must take the safe branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod dome;
mod equirect;

pub use dome::{
    dome_vertex_count, spherical_triangle_area, Dome, MAX_DOME_FREQUENCY, THESIS_DOME_FREQUENCIES,
};
pub use equirect::{
    angles_to_direction, build_pyramid, direction_to_angles, texel_direction, texel_solid_angle,
    Equirect,
};

use rtl_model::error::ConfigError;

/// Intensity levels I of the thesis (8-bit voxels).
pub const THESIS_LEVELS: f64 = 256.0;
/// Voxel resolution s of the thesis (128³).
pub const THESIS_VOXEL_RES: f64 = 128.0;
/// Pyramid levels of the thesis (512×256 → 64×32).
pub const THESIS_PYRAMID_LEVELS: usize = 4;

/// Λ = g(|t|) of eq. (13) for voxel resolution `s` and `levels` intensity levels
/// (see the module notes for the limits). Always finite and ≥ 0.
pub fn g(t_len: f64, s: f64, levels: f64) -> f64 {
    // `!(x > 0)` also catches NaN.
    if !(levels > 1.0) || !(s > 0.0) || t_len.is_nan() {
        return 0.0;
    }
    let ts = t_len.abs() * s;
    if !(ts > 0.0) {
        return 0.0;
    }
    let ln_i = levels.ln();
    let x = 2.0 / ts; // tan ψ_voxel
    let lambda = if x < 1e-100 {
        // ln(1 + x²) ≈ x²: avoid the underflow of x² to 0.
        ln_i * 0.5 * ts * ts
    } else {
        2.0 * ln_i / (x * x).ln_1p()
    };
    if lambda.is_nan() {
        0.0
    } else {
        lambda.min(f64::MAX)
    }
}

/// How each sample's solid angle enters the weights (module notes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Weighting {
    /// w ∝ ΔΩ(ω)·(t̂·ω)^Λ: the solid-angle quadrature (default).
    #[default]
    SolidAngle,
    /// w ∝ (t̂·ω)^Λ: the literal eq. (9), every sample counts the same.
    Uniform,
}

/// Parameters of the prefilter: voxel resolution s, intensity levels I (for g),
/// the weighting.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PrefilterParams {
    s: f64,
    levels: f64,
    weighting: Weighting,
}

impl PrefilterParams {
    /// s ∈ [1, 4096] (`envmap_prefilter.s`), levels ∈ [2, 2³²]
    /// (`envmap_prefilter.levels`), finite.
    pub fn new(s: f64, levels: f64, weighting: Weighting) -> Result<Self, ConfigError> {
        let s = rtl_model::error::check_finite("envmap_prefilter.s", s)?;
        if !(1.0..=4096.0).contains(&s) {
            return Err(ConfigError::out_of_range(
                "envmap_prefilter.s",
                s,
                1.0,
                4096.0,
            ));
        }
        let levels = rtl_model::error::check_finite("envmap_prefilter.levels", levels)?;
        if !(2.0..=4_294_967_296.0).contains(&levels) {
            return Err(ConfigError::out_of_range(
                "envmap_prefilter.levels",
                levels,
                2.0,
                4_294_967_296.0,
            ));
        }
        Ok(PrefilterParams {
            s,
            levels,
            weighting,
        })
    }
    /// The thesis: s = 128, I = 256, solid-angle weighting.
    pub fn thesis() -> Self {
        PrefilterParams {
            s: THESIS_VOXEL_RES,
            levels: THESIS_LEVELS,
            weighting: Weighting::SolidAngle,
        }
    }
    pub fn s(&self) -> f64 {
        self.s
    }
    pub fn levels(&self) -> f64 {
        self.levels
    }
    pub fn weighting(&self) -> Weighting {
        self.weighting
    }
    /// Λ = g(|t|) for these parameters.
    pub fn lambda(&self, t: [f64; 3]) -> f64 {
        g(norm(t), self.s, self.levels)
    }
}

/// Samples on the sphere: unit directions, their solid angles, their radiance.
#[derive(Clone, Debug, PartialEq)]
pub struct Samples {
    pub dirs: Vec<[f64; 3]>,
    pub solid_angles: Vec<f64>,
    pub radiance: Vec<[f64; 3]>,
}

impl Samples {
    /// Every texel of `map` (centre direction, texel solid angle, value).
    pub fn from_equirect(map: &Equirect) -> Self {
        let (w, h) = (map.width(), map.height());
        let mut dirs = Vec::with_capacity(w * h);
        let mut solid_angles = Vec::with_capacity(w * h);
        for j in 0..h {
            let a = texel_solid_angle(j, w, h);
            for i in 0..w {
                dirs.push(texel_direction(i, j, w, h));
                solid_angles.push(a);
            }
        }
        Samples {
            dirs,
            solid_angles,
            radiance: map.texels().to_vec(),
        }
    }
    /// The dome's vertices with `map` resampled onto them (bilinear).
    pub fn from_dome(dome: &Dome, map: &Equirect) -> Self {
        Samples {
            dirs: dome.dirs().to_vec(),
            solid_angles: dome.solid_angles().to_vec(),
            radiance: dome.resample(map),
        }
    }
}

/// Normalised weights w(t, ω) of eq. (9) over `dirs` (0 outside the hemisphere
/// t̂·ω ≥ 0), computed in the log domain; Σ w = 1 whenever some sample has positive
/// weight (else all 0). `lambda` NaN or < 0 is taken as 0. t = 0 (or non-finite t):
/// the whole-sphere weights (module notes). `solid_angles` shorter than `dirs`
/// counts missing entries as 0.
pub fn normalised_weights(
    t: [f64; 3],
    lambda: f64,
    dirs: &[[f64; 3]],
    solid_angles: &[f64],
    weighting: Weighting,
) -> Vec<f64> {
    let lobe = Lobe::new(t, lambda, dirs);
    let area = |k: usize| match weighting {
        Weighting::SolidAngle => solid_angles.get(k).copied().unwrap_or(0.0).max(0.0),
        Weighting::Uniform => 1.0,
    };
    let mut w: Vec<f64> = dirs
        .iter()
        .enumerate()
        .map(|(k, &d)| area(k) * lobe.relative(d))
        .collect();
    let sum: f64 = w.iter().sum();
    if sum > 0.0 && sum.is_finite() {
        let inv = 1.0 / sum;
        w.iter_mut().for_each(|x| *x *= inv);
    } else {
        w.iter_mut().for_each(|x| *x = 0.0);
    }
    w
}

/// F(t) of eqs. (8)(9) at an explicit Λ over `samples`: Σ w·L. Never NaN for finite
/// radiance; 0 if no sample has positive weight.
pub fn prefilter_samples(
    t: [f64; 3],
    lambda: f64,
    samples: &Samples,
    weighting: Weighting,
) -> [f64; 3] {
    let w = normalised_weights(t, lambda, &samples.dirs, &samples.solid_angles, weighting);
    let mut out = [0.0; 3];
    for (wk, l) in w.iter().zip(&samples.radiance) {
        if *wk > 0.0 {
            for c in 0..3 {
                out[c] += wk * l[c];
            }
        }
    }
    out
}

/// The exact prefilter of ONE voxel t (eqs. (8)(9), Λ = g(|t|)) over an environment's
/// texels (`texels` = [`Samples::from_equirect`] of the full-resolution map).
pub fn prefilter_voxel_exact(t: [f64; 3], texels: &Samples, params: &PrefilterParams) -> [f64; 3] {
    prefilter_samples(t, params.lambda(t), texels, params.weighting)
}

/// The same over a dome level: `radiance` = [`Dome::resample`] of a pyramid level.
pub fn prefilter_voxel_dome(
    t: [f64; 3],
    dome: &Dome,
    radiance: &[[f64; 3]],
    params: &PrefilterParams,
) -> [f64; 3] {
    let w = normalised_weights(
        t,
        params.lambda(t),
        dome.dirs(),
        dome.solid_angles(),
        params.weighting,
    );
    let mut out = [0.0; 3];
    for (wk, l) in w.iter().zip(radiance) {
        if *wk > 0.0 {
            for c in 0..3 {
                out[c] += wk * l[c];
            }
        }
    }
    out
}

/// One voxel's weight-table entries (Table 1): the samples with cos^Λ ψ > th.
#[derive(Clone, Debug, PartialEq)]
pub struct WeightEntries {
    /// (sample index, w) with w the full-hemisphere normalised weight of (9).
    pub entries: Vec<(u32, f64)>,
    /// Samples in the hemisphere t̂·ω ≥ 0 (all of them at t = 0).
    pub hemisphere: usize,
    /// Σ w over the kept entries (1 − the pruned weight).
    pub kept_weight: f64,
}

impl WeightEntries {
    pub fn len(&self) -> usize {
        self.entries.len()
    }
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
    /// Eq. (14): F = Σ_j L(ω_j)·w_j (indices out of range are skipped).
    pub fn apply(&self, radiance: &[[f64; 3]]) -> [f64; 3] {
        let mut out = [0.0; 3];
        for &(k, w) in &self.entries {
            if let Some(l) = radiance.get(k as usize) {
                for c in 0..3 {
                    out[c] += w * l[c];
                }
            }
        }
        out
    }
}

/// Weight-table entry selection for voxel t at explicit Λ: keep ω with
/// cos^Λ ψ = (t̂·ω)^Λ > th (un-normalised lobe; 0⁰ = 1; at t = 0 every sample has
/// lobe 1). The weights are NOT renormalised over the kept set (module notes).
pub fn select_weight_entries(
    t: [f64; 3],
    lambda: f64,
    dirs: &[[f64; 3]],
    solid_angles: &[f64],
    weighting: Weighting,
    th: f64,
) -> WeightEntries {
    let w = normalised_weights(t, lambda, dirs, solid_angles, weighting);
    let lobe = Lobe::new(t, lambda, dirs);
    let mut entries = Vec::new();
    let mut hemisphere = 0;
    let mut kept_weight = 0.0;
    for (k, &d) in dirs.iter().enumerate() {
        let Some(v) = lobe.absolute(d) else { continue };
        hemisphere += 1;
        if v > th {
            entries.push((k as u32, w[k]));
            kept_weight += w[k];
        }
    }
    WeightEntries {
        entries,
        hemisphere,
        kept_weight,
    }
}

/// The Phong lobe around t̂ with the log-domain normaliser.
struct Lobe {
    /// None: t = 0 (whole sphere, every lobe value 1).
    t_hat: Option<[f64; 3]>,
    lambda: f64,
    /// max ln(t̂·ω) over samples with t̂·ω > 0; None if there is none.
    ln_max: Option<f64>,
}

impl Lobe {
    fn new(t: [f64; 3], lambda: f64, dirs: &[[f64; 3]]) -> Self {
        let lambda = if lambda.is_nan() {
            0.0
        } else {
            lambda.max(0.0)
        };
        let len = norm(t);
        if !(len > 0.0 && len.is_finite()) {
            return Lobe {
                t_hat: None,
                lambda,
                ln_max: None,
            };
        }
        let t_hat = [t[0] / len, t[1] / len, t[2] / len];
        let c_max = dirs
            .iter()
            .map(|&d| dot(t_hat, d))
            .filter(|c| *c > 0.0)
            .fold(0.0f64, f64::max);
        Lobe {
            t_hat: Some(t_hat),
            lambda,
            ln_max: (c_max > 0.0).then(|| c_max.ln()),
        }
    }

    /// exp(Λ(ln c − m)) ∈ [0, 1] for sample d (0 outside the hemisphere). If no
    /// sample has c > 0 the c = 0 samples count 1 (0⁰, as for Λ = 0).
    fn relative(&self, d: [f64; 3]) -> f64 {
        let Some(t_hat) = self.t_hat else { return 1.0 };
        let c = dot(t_hat, d);
        if !(c >= 0.0) {
            return 0.0;
        }
        let Some(m) = self.ln_max else { return 1.0 };
        if self.lambda == 0.0 {
            return 1.0;
        }
        if c == 0.0 {
            return 0.0;
        }
        let diff = c.ln() - m;
        if diff >= 0.0 {
            1.0
        } else {
            (self.lambda * diff).exp()
        }
    }

    /// cos^Λ ψ = c^Λ (peak 1) for d in the hemisphere, None outside it.
    fn absolute(&self, d: [f64; 3]) -> Option<f64> {
        let Some(t_hat) = self.t_hat else {
            return Some(1.0);
        };
        let c = dot(t_hat, d);
        if !(c >= 0.0) {
            return None;
        }
        Some(if self.lambda == 0.0 || c >= 1.0 {
            1.0
        } else if c == 0.0 {
            0.0
        } else {
            (self.lambda * c.ln()).exp()
        })
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}
