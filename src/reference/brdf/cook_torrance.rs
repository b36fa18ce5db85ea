//! Cook–Torrance microfacet reflection: R = D(h) · F(ω·h) · G(ω_i, ω_o) / (4 cos θ_i cos θ_o).
//!
//! * D, the normal distribution, normalised so ∫ D(h) (n·h) dω_h = 1:
//!   Beckmann D = exp(−tan²θ_h/α²) / (π α² cos⁴θ_h) (α the RMS slope m), evaluated in
//!   logs so it stays finite as α → 0 (the peak 1/(π α²) is 3e13 at the smallest α
//!   accepted, 1e-7); GGX (Trowbridge–Reitz) D = α² / (π ((1 − cos²θ_h) + α² cos²θ_h)²),
//!   with 1 − cos²θ_h taken from the half vector's x, y (no cancellation at the peak).
//! * F: exact unpolarised Fresnel for a dielectric of index η (total internal
//!   reflection gives 1 when η < 1) or a conductor of complex index η + ik, or
//!   Schlick's F₀ + (1 − F₀)(1 − cos)^5, or 1 (a perfect mirror facet).
//! * G: Torrance–Sparrow V-cavity min(1, 2 (n·h)(n·ω_o)/(ω·h), 2 (n·h)(n·ω_i)/(ω·h)),
//!   or (GGX only) the separable Smith G₁(ω_i) G₁(ω_o),
//!   G₁ = 2 cos θ / (cos θ + √(cos²θ + α² sin²θ)), or none (G = 1, which diverges at
//!   grazing like 1/cos; the denominator is floored at [`COS_FLOOR`]).
//!
//! ω·h is taken as the mean of ω_i·h and ω_o·h (equal in exact arithmetic), so every
//! factor is symmetric in the floats and the reciprocity residual is exactly 0.
//! With G a V-cavity or Smith masking and F ≤ 1 the albedo is ≤ 1 (single scattering
//! only loses energy); the tests measure it.

// `!(x > 0.0)` is deliberate: it is true for NaN, which must take the safe branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::model::{
    above_horizon, check_range, half_vector, Brdf, BrdfParamError, Lobe, COS_FLOOR,
};
use crate::scene::math::Vec3;
use std::f64::consts::PI;

/// The normal distribution D.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MicrofacetDistribution {
    Beckmann,
    Ggx,
}

/// The Fresnel factor F(cos θ_d), θ_d the angle between ω_i (or ω_o) and h.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fresnel {
    /// F = 1.
    One,
    /// Schlick's approximation with normal-incidence reflectance `f0` ∈ [0, 1].
    Schlick { f0: f64 },
    /// Exact, real index `eta` ∈ (0, 100] (relative to the outside medium).
    Dielectric { eta: f64 },
    /// Exact, complex index `eta` + i `k` (metals), eta ∈ (0, 100], k ∈ [0, 100].
    Conductor { eta: f64, k: f64 },
}

impl Fresnel {
    /// Schlick with F₀ from a complex index: ((η − 1)² + k²) / ((η + 1)² + k²).
    pub fn schlick_from_ior(eta: f64, k: f64) -> Fresnel {
        Fresnel::Schlick {
            f0: ((eta - 1.0).powi(2) + k * k) / ((eta + 1.0).powi(2) + k * k),
        }
    }

    /// F at cos θ_d; cos ≤ 0 (not reached from `eval`) gives the grazing limit 1.
    pub fn eval(&self, cos_d: f64) -> f64 {
        if !(cos_d > 0.0) {
            return 1.0;
        }
        let c = cos_d.min(1.0);
        match *self {
            Fresnel::One => 1.0,
            Fresnel::Schlick { f0 } => f0 + (1.0 - f0) * (1.0 - c).powi(5),
            Fresnel::Dielectric { eta } => fresnel_dielectric(c, eta),
            Fresnel::Conductor { eta, k } => fresnel_conductor(c, eta, k),
        }
    }

    fn tag(&self) -> &'static str {
        match self {
            Fresnel::One => "f1",
            Fresnel::Schlick { .. } => "schlick",
            Fresnel::Dielectric { .. } => "dielectric",
            Fresnel::Conductor { .. } => "conductor",
        }
    }

    fn validate(&self) -> Result<(), BrdfParamError> {
        const M: &str = "cook_torrance";
        match *self {
            Fresnel::One => Ok(()),
            Fresnel::Schlick { f0 } => {
                check_range(M, "fresnel.f0", f0, 0.0, 1.0, "F0 must be in [0, 1]")
            }
            Fresnel::Dielectric { eta } => check_range(
                M,
                "fresnel.eta",
                eta,
                f64::MIN_POSITIVE,
                100.0,
                "the index must be in (0, 100]",
            ),
            Fresnel::Conductor { eta, k } => {
                check_range(
                    M,
                    "fresnel.eta",
                    eta,
                    f64::MIN_POSITIVE,
                    100.0,
                    "the index must be in (0, 100]",
                )?;
                check_range(M, "fresnel.k", k, 0.0, 100.0, "k must be in [0, 100]")
            }
        }
    }
}

/// Unpolarised Fresnel reflectance of a dielectric (Cook and Torrance's form):
/// g = √(η² − 1 + c²), F = ½ ((g − c)/(g + c))² (1 + ((c(g + c) − 1)/(c(g − c) + 1))²);
/// no real g is total internal reflection (F = 1). `c` ∈ (0, 1].
pub fn fresnel_dielectric(c: f64, eta: f64) -> f64 {
    let Some(g) = fresnel_g(c, eta) else {
        return 1.0;
    };
    let a = (g - c) / (g + c);
    let b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
    (0.5 * a * a * (1.0 + b * b)).min(1.0)
}

/// 1 − [`fresnel_dielectric`], formed directly as ½ (T_s + T_p) with
/// T_s = 4cg/(c + g)² and T_p = 4η²cg/(η²c + g)² (each a product of two ratios in
/// [0, 1]): near grazing F → 1 and 1 − F would keep only the digits F lost.
pub fn fresnel_dielectric_transmittance(c: f64, eta: f64) -> f64 {
    let Some(g) = fresnel_g(c, eta) else {
        return 0.0;
    };
    let e2c = eta * eta * c;
    let t_s = (c / (c + g)) * (g / (c + g));
    let t_p = (e2c / (e2c + g)) * (g / (e2c + g));
    (2.0 * (t_s + t_p)).clamp(0.0, 1.0)
}

/// g = √(η² − 1 + c²) without cancellation or underflow: hypot(√(η² − 1), c) for
/// η ≥ 1 (at η = 1, g = c exactly, however small c is: c² would underflow below
/// 1.5·10⁻¹⁵⁴ and read as total internal reflection); √((c − s)(c + s)) with
/// s = √(1 − η²) for η < 1, None (total internal reflection) when c ≤ s.
fn fresnel_g(c: f64, eta: f64) -> Option<f64> {
    if eta >= 1.0 {
        Some(((eta - 1.0) * (eta + 1.0)).sqrt().hypot(c))
    } else {
        let s = ((1.0 - eta) * (1.0 + eta)).sqrt();
        (c > s).then(|| ((c - s) * (c + s)).sqrt())
    }
}

/// Unpolarised Fresnel reflectance of a conductor of index η + ik from the complex
/// amplitudes r_∥ = (η c − cos_t)/(η c + cos_t), r_⊥ = (c − η cos_t)/(c + η cos_t),
/// cos_t = √(1 − (1 − c²)/η²). `c` ∈ (0, 1]; k = 0 agrees with [`fresnel_dielectric`].
pub fn fresnel_conductor(c: f64, eta: f64, k: f64) -> f64 {
    let n = Complex { re: eta, im: k };
    let sin2_t = Complex::real(1.0 - c * c) / (n * n);
    let cos_t = (Complex::real(1.0) - sin2_t).sqrt();
    let nc = n * Complex::real(c);
    let r_par = (nc - cos_t) / (nc + cos_t);
    let n_cos_t = n * cos_t;
    let r_perp = (Complex::real(c) - n_cos_t) / (Complex::real(c) + n_cos_t);
    let f = 0.5 * (r_par.norm2() + r_perp.norm2());
    if f.is_finite() {
        f.min(1.0)
    } else {
        1.0
    }
}

#[derive(Clone, Copy, Debug)]
struct Complex {
    re: f64,
    im: f64,
}

impl Complex {
    fn real(re: f64) -> Self {
        Complex { re, im: 0.0 }
    }
    fn norm2(self) -> f64 {
        self.re * self.re + self.im * self.im
    }
    /// The principal square root (non-negative real part).
    fn sqrt(self) -> Self {
        let r = self.norm2().sqrt();
        let re = (0.5 * (r + self.re)).max(0.0).sqrt();
        let im = (0.5 * (r - self.re)).max(0.0).sqrt();
        Complex {
            re,
            im: if self.im < 0.0 { -im } else { im },
        }
    }
}

impl std::ops::Add for Complex {
    type Output = Complex;
    fn add(self, o: Complex) -> Complex {
        Complex {
            re: self.re + o.re,
            im: self.im + o.im,
        }
    }
}
impl std::ops::Sub for Complex {
    type Output = Complex;
    fn sub(self, o: Complex) -> Complex {
        Complex {
            re: self.re - o.re,
            im: self.im - o.im,
        }
    }
}
impl std::ops::Mul for Complex {
    type Output = Complex;
    fn mul(self, o: Complex) -> Complex {
        Complex {
            re: self.re * o.re - self.im * o.im,
            im: self.re * o.im + self.im * o.re,
        }
    }
}
impl std::ops::Div for Complex {
    type Output = Complex;
    fn div(self, o: Complex) -> Complex {
        let d = o.norm2();
        Complex {
            re: (self.re * o.re + self.im * o.im) / d,
            im: (self.im * o.re - self.re * o.im) / d,
        }
    }
}

/// The masking–shadowing term G.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Masking {
    /// G = 1 (not energy-conserving at grazing).
    None,
    /// Torrance–Sparrow V-cavity.
    VCavity,
    /// Separable Smith for GGX (rejected with Beckmann).
    SmithGgx,
}

/// Cook–Torrance parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CookTorranceParams {
    pub distribution: MicrofacetDistribution,
    /// Roughness: Beckmann's RMS slope m, or GGX's α; in [1e-7, 4].
    pub alpha: f64,
    pub fresnel: Fresnel,
    pub masking: Masking,
}

/// Smallest roughness accepted: D's peak 1/(π α²) ≈ 3e13 is still far from overflow and
/// the albedo quadrature still resolves the lobe.
pub const MIN_ALPHA: f64 = 1e-7;

/// The Cook–Torrance BRDF.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CookTorrance {
    pub params: CookTorranceParams,
}

impl CookTorrance {
    pub fn new(params: CookTorranceParams) -> Result<Self, BrdfParamError> {
        check_range(
            "cook_torrance",
            "alpha",
            params.alpha,
            MIN_ALPHA,
            4.0,
            "the roughness must be in [1e-7, 4]",
        )?;
        params.fresnel.validate()?;
        if params.masking == Masking::SmithGgx && params.distribution != MicrofacetDistribution::Ggx
        {
            return Err(BrdfParamError {
                model: "cook_torrance",
                param: "masking",
                value: "SmithGgx".into(),
                requirement: "Smith masking is implemented for the GGX distribution only",
            });
        }
        Ok(CookTorrance { params })
    }

    /// D(h) for a unit half vector (0 for h_z ≤ 0).
    pub fn distribution(&self, h: Vec3) -> f64 {
        let c = h.z;
        if !(c > 0.0) {
            return 0.0;
        }
        let s2 = h.x * h.x + h.y * h.y;
        let a = self.params.alpha;
        match self.params.distribution {
            MicrofacetDistribution::Beckmann => {
                // ln D = −tan²θ/α² − ln π − 2 ln α − 4 ln cos θ: no 0/0 or overflow.
                let tan2_over_a2 = s2 / (c * c * a * a);
                (-tan2_over_a2 - PI.ln() - 2.0 * a.ln() - 4.0 * c.ln()).exp()
            }
            MicrofacetDistribution::Ggx => {
                let d = s2 + a * a * c * c;
                a * a / (PI * d * d)
            }
        }
    }

    fn smith_g1(&self, w: Vec3) -> f64 {
        let a = self.params.alpha;
        let s2 = w.x * w.x + w.y * w.y;
        2.0 * w.z / (w.z + (w.z * w.z + a * a * s2).sqrt())
    }
}

impl Brdf for CookTorrance {
    fn name(&self) -> String {
        let d = match self.params.distribution {
            MicrofacetDistribution::Beckmann => "beckmann",
            MicrofacetDistribution::Ggx => "ggx",
        };
        let g = match self.params.masking {
            Masking::None => "nomask",
            Masking::VCavity => "vcavity",
            Masking::SmithGgx => "smith",
        };
        format!("cook_torrance_{d}_{}_{g}", self.params.fresnel.tag())
    }

    fn eval(&self, wi: Vec3, wo: Vec3) -> f64 {
        let Some((wi, wo)) = above_horizon(wi, wo) else {
            return 0.0;
        };
        let h = half_vector(wi, wo);
        let d = self.distribution(h);
        if d == 0.0 {
            return 0.0;
        }
        let cos_d = 0.5 * (wi.dot(h) + wo.dot(h));
        let f = self.params.fresnel.eval(cos_d);
        let g = match self.params.masking {
            Masking::None => 1.0,
            Masking::VCavity => {
                // min is commutative for non-NaN operands: symmetric in (ω_i, ω_o).
                let k = 2.0 * h.z / cos_d;
                1f64.min(k * wo.z).min(k * wi.z)
            }
            Masking::SmithGgx => self.smith_g1(wi) * self.smith_g1(wo),
        };
        d * f * g / (4.0 * (wi.z * wo.z).max(COS_FLOOR))
    }

    fn energy_normalised(&self) -> bool {
        self.params.masking != Masking::None
    }

    fn lobe(&self) -> Lobe {
        Lobe::HalfVector {
            width: self.params.alpha,
            anisotropic: false,
        }
    }
}
