//! Kajiya–Kay hair/fur (Kajiya and Kay 1989) with the fibre along the tangent (+x).
//! Angles are measured against the fibre: θ_i between t and ω_i, θ_o between −t and
//! ω_o, so the mirror cone of a cylinder is θ_i = θ_o, as the seed's eq. (6) has it:
//!
//!   R = k_d sin θ_i + k_s max(0, cos(θ_i − θ_o))^n,
//!   cos(θ_i − θ_o) = sin θ_i sin θ_o − (t·ω_i)(t·ω_o),  sin θ = √(ω_y² + ω_z²).
//!
//! As every model here, `eval` is the factor the renderer multiplies by L_i cos θ_i
//! (the surface normal +z: fur on a surface is self-shadowed below the horizon, where R
//! is 0).
//!
//! What "reciprocal" means for it: the specular term is symmetric in (ω_i, ω_o)
//! exactly (the same two products), so `eval` is reciprocal when k_d = 0; the diffuse
//! term k_d sin θ_i depends on the light alone, so with k_d > 0 `eval` is not, and
//! [`Brdf::is_reciprocal`] says so. In a fibre's own convention (Marschner et al. 2003:
//! L_o = ∫ S L_i cos θ'_i dω_i with θ'_i the inclination from the normal plane, so the
//! cosine is sin θ_i) the roles swap: S = k_d + k_s cos^n(θ_i − θ_o)/sin θ_i
//! ([`KajiyaKay::fibre_function`]) has a reciprocal diffuse part and a non-reciprocal
//! specular part. The model is not energy-normalised (k_s cos^n is the classic Phong-like
//! lobe).

use super::model::{above_horizon, check_range, Brdf, BrdfParamError, Lobe, COS_FLOOR};
use crate::scene::math::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KajiyaKayParams {
    /// Diffuse coefficient k_d ∈ [0, 1e6].
    pub k_d: f64,
    /// Specular coefficient k_s ∈ [0, 1e6].
    pub k_s: f64,
    /// Exponent n ∈ [0, 1e6].
    pub exponent: f64,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KajiyaKay {
    pub params: KajiyaKayParams,
}

fn sin_to_tangent(w: Vec3) -> f64 {
    (w.y * w.y + w.z * w.z).sqrt()
}

impl KajiyaKay {
    pub fn new(params: KajiyaKayParams) -> Result<Self, BrdfParamError> {
        const M: &str = "kajiya_kay";
        check_range(M, "k_d", params.k_d, 0.0, 1e6, "k_d must be in [0, 1e6]")?;
        check_range(M, "k_s", params.k_s, 0.0, 1e6, "k_s must be in [0, 1e6]")?;
        check_range(
            M,
            "exponent",
            params.exponent,
            0.0,
            1e6,
            "the exponent must be in [0, 1e6]",
        )?;
        Ok(KajiyaKay { params })
    }

    /// cos(θ_i − θ_o) clamped at 0, raised to n: the specular cone.
    fn specular(&self, wi: Vec3, wo: Vec3) -> f64 {
        let c = sin_to_tangent(wi) * sin_to_tangent(wo) - wi.x * wo.x;
        self.params.k_s * c.clamp(0.0, 1.0).powf(self.params.exponent)
    }

    /// S = R / sin θ_i, the fibre convention's scattering function (the cosine being
    /// sin θ_i; floored at [`COS_FLOOR`]); 0 below the horizon.
    pub fn fibre_function(&self, wi: Vec3, wo: Vec3) -> f64 {
        let Some((wi, wo)) = above_horizon(wi, wo) else {
            return 0.0;
        };
        self.params.k_d + self.specular(wi, wo) / sin_to_tangent(wi).max(COS_FLOOR)
    }
}

impl Brdf for KajiyaKay {
    fn name(&self) -> String {
        "kajiya_kay".into()
    }
    fn eval(&self, wi: Vec3, wo: Vec3) -> f64 {
        let Some((wi, wo)) = above_horizon(wi, wo) else {
            return 0.0;
        };
        self.params.k_d * sin_to_tangent(wi) + self.specular(wi, wo)
    }
    fn is_reciprocal(&self) -> bool {
        self.params.k_d == 0.0
    }
    fn lobe(&self) -> Lobe {
        Lobe::TangentCone {
            width: (1.0 / (self.params.exponent + 1.0)).sqrt(),
        }
    }
}
