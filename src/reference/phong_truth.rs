//! Phong ground truth (f64) of a glossy reflector in an environment map —
//! eqs. (1)–(5) of Okumura's thesis:
//!
//! L(r, n, Λ) = K_r ∫_Ω f(cos θ, cos φ, Λ) L_i dl,   f = cos^Λ θ if cos θ ≥ 0 and
//! cos φ ≥ 0, else 0 (eqs. 1–2; θ between r and l, φ between n and l), and the
//! simplified form without the cos φ test (eq. 3, f' = cos^Λ θ if cos θ ≥ 0).
//!
//! # Discretisation and normalisation (my reading)
//!
//! The integral is a sum over the environment's texels ω with their solid angles ΔΩ
//! (conventions in [`crate::scene::envmap`]). The thesis' filter (8)(9) is a normalised
//! weighted average, w = (r̂·ω)^Λ / Σ_{ρ: r̂·ρ ≥ 0} (r̂·ρ)^Λ, summed over (roughly
//! equal-area) dome vertices; on an equirectangular map the same average needs the
//! texel solid angles, so here
//!
//! K_r = 1 / Σ_{ρ: r·ρ ≥ 0} ΔΩ_ρ (r·ρ)^Λ      (the discrete form of (Λ + 1)/2π, the
//!                                             energy normalisation of the Phong lobe)
//! L   = K_r · Σ_{ω: r·ω ≥ 0 [and n·ω ≥ 0]} ΔΩ_ω (r·ω)^Λ L(ω).
//!
//! K_r depends on Λ only (never on n): it is the thesis' denominator (9). For the
//! truth **with** the cos φ test the thesis (§4.3) renders "the Phong model" with the Λ
//! matching each λ and blames the errors at the sphere's rim (n ⟂ v) on the dropped
//! cos φ test (Fig. 8); its errors of ≈ 1 level elsewhere say the truth has the same
//! scale as (9). So the truth with the test keeps the denominator of (9) and only masks
//! the numerator: light from below the surface's horizon is lost, not redistributed.
//! Consequences: a constant environment gives the constant back for every Λ without the
//! test (`Visibility::Simplified`), and with the test (`Visibility::CosPhiTest`) exactly
//! where the test removes no kept texel (r = n: the two hemispheres coincide; or a narrow
//! lobe far from n's horizon). At grazing r (r·n → 0) the test removes about half the
//! lobe: the result tends to about half the surroundings' radiance, a defined value.
//! (r·n < 0 cannot come from a reflection r = 2(n·v)n − v with n·v ≥ 0, but it is still
//! defined: often 0.)
//!
//! # Log domain and pruning
//!
//! Weights are computed as exp(Λ·(ln cos θ − ln cos θ_max)) with cos θ_max the largest
//! r·ω over the map, so the nearest texel always has weight exactly 1: no all-zero sum
//! (if every other weight underflows, the nearest texel wins; ties share) and no
//! overflow, for Λ from 0 (0⁰ = 1: the plain solid-angle average over the hemisphere
//! around r, including the cos θ = 0 rim) to 10⁵ and beyond. Texels with
//! Λ·ln(cos θ / cos θ_max) < −[`PRUNE_LOG`] (= −60, relative to the nearest texel) are
//! skipped: each pruned weight is < e⁻⁶⁰ ≈ 8.8·10⁻²⁷ of the nearest one, so with D_p
//! the pruned and D_k the kept mass, |L_pruned − L_full| ≤ L_max · D_p / D_k ≤
//! L_max · 4π e⁻⁶⁰ / ΔΩ_min (ΔΩ_min the smallest texel solid angle; see
//! [`prune_error_bound`]: ≈ 1.2·10⁻¹⁹ · L_max at 512 × 256, 2.3·10⁻²² · L_max at
//! 64 × 32). If no texel has r·ω ≥ 0 (only for degenerate tiny maps) the nearest texel
//! is returned (masked by the cos φ test).
//!
//! Cost: one pass for cos θ_max, one over the kept texels (a `ln` and an `exp` each);
//! ≈ 0.7–0.9 ms per direction at 512 × 256 in the test profile. The renderer (a sphere
//! or the teapot per pixel) comes later; [`PhongTruth::eval_many`] takes (r, n, Λ) arrays.

use rtl_model::error::ConfigError;

use crate::scene::envmap::EnvMap;
use crate::scene::math::Vec3;

/// Log-weight cut-off: texels with Λ·ln(cos θ / cos θ_max) < −PRUNE_LOG are skipped.
pub const PRUNE_LOG: f64 = 60.0;

/// Which form of the Phong integral.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Visibility {
    /// Eq. (3): no cos φ test (what the multi-scale map stores).
    Simplified,
    /// Eqs. (1)–(2): light with n·l < 0 is dropped (the thesis' Phong ground truth).
    CosPhiTest,
}

/// The environment prepared for repeated Phong integrals: texel directions, solid angles
/// and radiance, flattened.
#[derive(Clone, Debug)]
pub struct PhongTruth {
    dirs: Vec<[f64; 3]>,
    solid: Vec<f64>,
    radiance: Vec<[f64; 3]>,
    min_solid: f64,
    max_radiance: f64,
    prune_log: f64,
}

impl PhongTruth {
    /// Prepare `env` (pruning at [`PRUNE_LOG`]).
    pub fn new(env: &EnvMap) -> Self {
        let (w, h) = (env.width(), env.height());
        let mut dirs = Vec::with_capacity(w * h);
        let mut solid = Vec::with_capacity(w * h);
        for j in 0..h {
            let s = env.texel_solid_angle(j);
            for i in 0..w {
                let d = env.texel_dir(i, j);
                dirs.push([d.x, d.y, d.z]);
                solid.push(s);
            }
        }
        let min_solid = solid.iter().copied().fold(f64::INFINITY, f64::min);
        let max_radiance = env
            .texels()
            .iter()
            .flat_map(|t| t.iter().copied())
            .fold(0.0, f64::max);
        PhongTruth {
            dirs,
            solid,
            radiance: env.texels().to_vec(),
            min_solid,
            max_radiance,
            prune_log: PRUNE_LOG,
        }
    }

    /// The same with another cut-off (`f64::INFINITY`: no pruning; for tests). Values
    /// that are NaN or ≤ 0 are refused ("phong_truth.prune_log").
    pub fn with_prune_log(mut self, prune_log: f64) -> Result<Self, ConfigError> {
        if prune_log.is_nan() || prune_log <= 0.0 {
            return Err(ConfigError::out_of_range(
                "phong_truth.prune_log",
                prune_log,
                f64::MIN_POSITIVE,
                f64::INFINITY,
            ));
        }
        self.prune_log = prune_log;
        Ok(self)
    }

    /// The bound on |pruned − unpruned| of any result: L_max · 4π e^(−prune_log) / ΔΩ_min.
    pub fn prune_error_bound(&self) -> f64 {
        prune_error_bound_for(self.prune_log, self.min_solid) * self.max_radiance
    }

    /// The Phong integral for reflection direction `r`, normal `n` (used only with
    /// `CosPhiTest`) and exponent Λ = `lambda` (finite, ≥ 0). `r` and `n` need not be
    /// unit but must be finite and non-zero. Errors name "phong_truth.r",
    /// "phong_truth.n", "phong_truth.lambda". The result is finite and ≥ 0.
    pub fn eval(
        &self,
        r: Vec3,
        n: Vec3,
        lambda: f64,
        vis: Visibility,
    ) -> Result<[f64; 3], ConfigError> {
        let r = unit("phong_truth.r", r)?;
        let n = match vis {
            Visibility::Simplified => [0.0, 1.0, 0.0],
            Visibility::CosPhiTest => unit("phong_truth.n", n)?,
        };
        let lambda = check_lambda("phong_truth.lambda", lambda)?;
        Ok(self.eval_unit(r, n, lambda, vis))
    }

    /// [`PhongTruth::eval`] over arrays of equal length (n is ignored with `Simplified`
    /// but must still have the same length). Errors name the element, e.g.
    /// `"phong_truth.lambda[3]"`; a length mismatch names "phong_truth.n" or
    /// "phong_truth.lambda".
    pub fn eval_many(
        &self,
        r: &[Vec3],
        n: &[Vec3],
        lambda: &[f64],
        vis: Visibility,
    ) -> Result<Vec<[f64; 3]>, ConfigError> {
        for (field, len) in [
            ("phong_truth.n", n.len()),
            ("phong_truth.lambda", lambda.len()),
        ] {
            if len != r.len() {
                return Err(ConfigError::invalid(
                    field,
                    &format!("{len} values for {} reflection vectors", r.len()),
                ));
            }
        }
        r.iter()
            .zip(n)
            .zip(lambda)
            .enumerate()
            .map(|(k, ((&rk, &nk), &lk))| {
                self.eval(rk, nk, lk, vis).map_err(|e| {
                    let field = format!("{}[{k}]", e.field());
                    match e {
                        ConfigError::NotFinite { value, .. } => {
                            ConfigError::not_finite(&field, value)
                        }
                        ConfigError::OutOfRange {
                            value, min, max, ..
                        } => ConfigError::out_of_range(&field, value, min, max),
                        ConfigError::Invalid { reason, .. } => {
                            ConfigError::invalid(&field, &reason)
                        }
                    }
                })
            })
            .collect()
    }

    /// Number of texels that take part for (r, Λ) (r·ω ≥ 0 and not pruned); diagnostic.
    pub fn kept_texels(&self, r: Vec3, lambda: f64) -> Result<usize, ConfigError> {
        let r = unit("phong_truth.r", r)?;
        let lambda = check_lambda("phong_truth.lambda", lambda)?;
        let c_max = self.max_cos(r);
        let c_min = self.cos_cutoff(c_max, lambda);
        Ok(self
            .dirs
            .iter()
            .filter(|d| {
                let c = dot(r, **d);
                c >= 0.0 && c >= c_min
            })
            .count())
    }

    fn max_cos(&self, r: [f64; 3]) -> f64 {
        self.dirs
            .iter()
            .map(|d| dot(r, *d))
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// Texels with cos θ < this are pruned: Λ·ln(c/c_max) < −prune_log ⇔
    /// c < c_max·exp(−prune_log/Λ). Λ = 0 keeps everything (returns −∞).
    fn cos_cutoff(&self, c_max: f64, lambda: f64) -> f64 {
        if lambda == 0.0 || c_max <= 0.0 {
            f64::NEG_INFINITY
        } else {
            c_max * (-self.prune_log / lambda).exp()
        }
    }

    fn eval_unit(&self, r: [f64; 3], n: [f64; 3], lambda: f64, vis: Visibility) -> [f64; 3] {
        let test_phi = vis == Visibility::CosPhiTest;
        let c_max = self.max_cos(r);
        if c_max < 0.0 {
            // No texel in r's hemisphere (degenerate tiny maps): the nearest texel wins.
            let k = self
                .dirs
                .iter()
                .enumerate()
                .max_by(|a, b| dot(r, *a.1).total_cmp(&dot(r, *b.1)))
                .map_or(0, |p| p.0);
            if test_phi && dot(n, self.dirs[k]) < 0.0 {
                return [0.0; 3];
            }
            return self.radiance.get(k).copied().unwrap_or([0.0; 3]);
        }
        let c_min = self.cos_cutoff(c_max, lambda).max(0.0);
        let ln_c_max = c_max.ln();
        let mut den = 0.0;
        let mut num = [0.0; 3];
        for ((d, &s), l) in self.dirs.iter().zip(&self.solid).zip(&self.radiance) {
            let c = dot(r, *d);
            if c < c_min {
                continue;
            }
            // Log weight relative to the nearest texel: 0 for it (and for Λ = 0), ≤ 0
            // otherwise, ≥ −prune_log after the cut-off (c > 0 here unless Λ = 0 or
            // c_max = 0, both caught by the first branch).
            let lw = if lambda == 0.0 || c >= c_max {
                0.0
            } else {
                lambda * (c.ln() - ln_c_max)
            };
            let wt = s * lw.exp();
            den += wt;
            if test_phi && dot(n, *d) < 0.0 {
                continue;
            }
            for ch in 0..3 {
                num[ch] += wt * l[ch];
            }
        }
        // den ≥ ΔΩ of the nearest texel > 0.
        num.map(|x| if den > 0.0 { (x / den).max(0.0) } else { 0.0 })
    }
}

/// One-shot Phong integral (prepares `env` each call; use [`PhongTruth`] for many).
pub fn phong_truth(
    env: &EnvMap,
    r: Vec3,
    n: Vec3,
    lambda: f64,
    vis: Visibility,
) -> Result<[f64; 3], ConfigError> {
    PhongTruth::new(env).eval(r, n, lambda, vis)
}

/// The relative pruning bound 4π e^(−PRUNE_LOG) / ΔΩ_min for `env` (multiply by the
/// map's largest radiance to bound |pruned − unpruned|).
pub fn prune_error_bound(env: &EnvMap) -> f64 {
    let min_solid = (0..env.height())
        .map(|j| env.texel_solid_angle(j))
        .fold(f64::INFINITY, f64::min);
    prune_error_bound_for(PRUNE_LOG, min_solid)
}

fn prune_error_bound_for(prune_log: f64, min_solid: f64) -> f64 {
    4.0 * std::f64::consts::PI * (-prune_log).exp() / min_solid
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn unit(field: &str, v: Vec3) -> Result<[f64; 3], ConfigError> {
    for c in [v.x, v.y, v.z] {
        if !c.is_finite() {
            return Err(ConfigError::not_finite(field, c));
        }
    }
    // Scale by the largest component first so huge or tiny vectors normalise cleanly.
    let m = v.x.abs().max(v.y.abs()).max(v.z.abs());
    if m == 0.0 {
        return Err(ConfigError::invalid(field, "must be a non-zero vector"));
    }
    let s = [v.x / m, v.y / m, v.z / m];
    let len = dot(s, s).sqrt();
    Ok(s.map(|c| c / len))
}

fn check_lambda(field: &str, lambda: f64) -> Result<f64, ConfigError> {
    if !lambda.is_finite() {
        return Err(ConfigError::not_finite(field, lambda));
    }
    if lambda < 0.0 {
        return Err(ConfigError::out_of_range(field, lambda, 0.0, f64::MAX));
    }
    Ok(lambda)
}
