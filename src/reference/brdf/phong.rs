//! Phong and Blinn–Phong specular lobes in three forms.
//!
//! * [`PhongForm::GlRadiance`]: the term as the fixed-function GL lighting equation
//!   writes it, L_o = k_s · cos^n · L_i with no cos θ_i factor; as a BRDF that is
//!   R = k_s cos^n / cos θ_i (cos θ_i floored at [`COS_FLOOR`]). Not reciprocal, and its
//!   albedo grows like 1/cos θ_i toward grazing light: the seed's "Phong violates
//!   reciprocity".
//! * [`PhongForm::Classic`]: R = k_s cos^n (Lewis 1994's reading of the same term as a
//!   BRDF). Reciprocal; not normalised (albedo 2π k_s/(n+2) at normal incidence for
//!   Phong, so > 1 for small n and k_s near 1).
//! * [`PhongForm::Normalised`]: R = k_s · N(n) · cos^n with N chosen so the albedo at
//!   normal incidence is exactly k_s:
//!   - Phong (cos α, α between ω_i and the mirror of ω_o): N = (n + 2)/(2π), since
//!     ∫ cos^n α cos θ dω = 2π/(n + 2) when the lobe is centred on the normal;
//!   - Blinn–Phong (cos θ_h, the half vector's polar angle): the exact normal-incidence
//!     constant N = (n + 2)(n + 4) / (8π (2^{−n/2} + n)) (from
//!     2π ∫₀^{π/2} cos^n(θ/2) cos θ sin θ dθ = 8π (n + 2^{−n/2}) / ((n + 2)(n + 4))),
//!     not the common approximation (n + 8)/(8π), which exceeds it (by 2.4 % at n = 1).
//!
//!   Whether the albedo stays ≤ k_s away from normal incidence is measured, not
//!   assumed (`reproduce shading-brdf-properties`, docs/shading.md).
//!
//! cos is clamped at 0 and 0^0 = 1, so n = 0 is the constant lobe.

use super::model::{
    above_horizon, check_range, cos_mirror, half_vector, Brdf, BrdfParamError, Lobe, COS_FLOOR,
};
use crate::scene::math::Vec3;
use std::f64::consts::PI;

/// Which form of the lobe (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PhongForm {
    GlRadiance,
    Classic,
    Normalised,
}

impl PhongForm {
    /// Every form but GL's (which divides by cos θ_i alone) is symmetric.
    pub fn is_reciprocal(self) -> bool {
        self != PhongForm::GlRadiance
    }
    pub fn is_normalised(self) -> bool {
        self == PhongForm::Normalised
    }
    fn tag(self) -> &'static str {
        match self {
            PhongForm::GlRadiance => "gl",
            PhongForm::Classic => "classic",
            PhongForm::Normalised => "normalised",
        }
    }
}

/// Parameters shared by [`Phong`] and [`BlinnPhong`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhongParams {
    /// Specular coefficient k_s ≥ 0 (≤ 1 for the normalised form: its normal-incidence
    /// albedo).
    pub k_s: f64,
    /// Exponent n ∈ [0, 1e6].
    pub exponent: f64,
    pub form: PhongForm,
}

/// Largest exponent accepted (the tests go to 1e4).
pub const MAX_EXPONENT: f64 = 1e6;

fn validate(model: &'static str, p: &PhongParams) -> Result<(), BrdfParamError> {
    let k_max = if p.form == PhongForm::Normalised {
        1.0
    } else {
        1e6
    };
    check_range(
        model,
        "k_s",
        p.k_s,
        0.0,
        k_max,
        "k_s must be ≥ 0 (and ≤ 1 in the normalised form, ≤ 1e6 otherwise)",
    )?;
    check_range(
        model,
        "exponent",
        p.exponent,
        0.0,
        MAX_EXPONENT,
        "the exponent must be in [0, 1e6]",
    )
}

/// k_s · max(c, 0)^n with the form's normalisation `norm` and, for the GL form, the
/// division by cos θ_i.
fn lobe_value(p: &PhongParams, norm: f64, cos_lobe: f64, cos_i: f64) -> f64 {
    let c = cos_lobe.clamp(0.0, 1.0).powf(p.exponent);
    match p.form {
        PhongForm::GlRadiance => p.k_s * c / cos_i.max(COS_FLOOR),
        PhongForm::Classic => p.k_s * c,
        PhongForm::Normalised => p.k_s * norm * c,
    }
}

fn lobe_width(exponent: f64) -> f64 {
    (1.0 / (exponent + 1.0)).sqrt()
}

/// Phong: the lobe is cos α, α the angle between ω_i and the mirror of ω_o.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Phong {
    pub params: PhongParams,
}

impl Phong {
    pub fn new(params: PhongParams) -> Result<Self, BrdfParamError> {
        validate("phong", &params)?;
        Ok(Phong { params })
    }
    /// (n + 2)/(2π).
    pub fn normalisation(exponent: f64) -> f64 {
        (exponent + 2.0) / (2.0 * PI)
    }
}

impl Brdf for Phong {
    fn name(&self) -> String {
        format!("phong_{}", self.params.form.tag())
    }
    fn eval(&self, wi: Vec3, wo: Vec3) -> f64 {
        let Some((wi, wo)) = above_horizon(wi, wo) else {
            return 0.0;
        };
        let norm = Self::normalisation(self.params.exponent);
        lobe_value(&self.params, norm, cos_mirror(wi, wo), wi.z)
    }
    fn is_reciprocal(&self) -> bool {
        self.params.form.is_reciprocal()
    }
    fn energy_normalised(&self) -> bool {
        self.params.form.is_normalised()
    }
    fn lobe(&self) -> Lobe {
        Lobe::Mirror {
            width: lobe_width(self.params.exponent),
        }
    }
}

/// Blinn–Phong: the lobe is cos θ_h = n · h, h the unit half vector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlinnPhong {
    pub params: PhongParams,
}

impl BlinnPhong {
    pub fn new(params: PhongParams) -> Result<Self, BrdfParamError> {
        validate("blinn_phong", &params)?;
        Ok(BlinnPhong { params })
    }
    /// (n + 2)(n + 4) / (8π (2^{−n/2} + n)): exact albedo 1 at normal incidence.
    pub fn normalisation(exponent: f64) -> f64 {
        let n = exponent;
        (n + 2.0) * (n + 4.0) / (8.0 * PI * ((-0.5 * n).exp2() + n))
    }
}

impl Brdf for BlinnPhong {
    fn name(&self) -> String {
        format!("blinn_phong_{}", self.params.form.tag())
    }
    fn eval(&self, wi: Vec3, wo: Vec3) -> f64 {
        let Some((wi, wo)) = above_horizon(wi, wo) else {
            return 0.0;
        };
        let norm = Self::normalisation(self.params.exponent);
        lobe_value(&self.params, norm, half_vector(wi, wo).z, wi.z)
    }
    fn is_reciprocal(&self) -> bool {
        self.params.form.is_reciprocal()
    }
    fn energy_normalised(&self) -> bool {
        self.params.form.is_normalised()
    }
    fn lobe(&self) -> Lobe {
        Lobe::HalfVector {
            width: lobe_width(self.params.exponent),
            anisotropic: false,
        }
    }
}
