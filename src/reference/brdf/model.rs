//! What every model of this directory is and shares: the [`Brdf`] trait and its
//! [`Lobe`] hint, the local [`ShadingFrame`], parameter checks naming the parameter
//! ([`BrdfParamError`]) and the small vector helpers the models evaluate with. The
//! models import this file; it imports none of them.

use crate::scene::math::{v3, Vec3};

/// A reflection model in the local shading frame (n = +z, t = +x).
pub trait Brdf: Send + Sync {
    /// A short name for tables and file names (`cook_torrance_beckmann`, …).
    fn name(&self) -> String;
    /// R(ω_i, ω_o), sr⁻¹; ω_i toward the light, ω_o toward the viewer, both unit.
    fn eval(&self, wi: Vec3, wo: Vec3) -> f64;
    /// Whether the model is meant to satisfy R(ω_i, ω_o) = R(ω_o, ω_i) (the tests hold
    /// every model claiming it to 1e-12 · max(1, R)).
    fn is_reciprocal(&self) -> bool {
        true
    }
    /// Whether the model is meant to conserve energy, ∫ R cos θ_o dω_o ≤ 1 at every
    /// incidence (the tests hold every model claiming it to 1 + the quadrature error).
    fn energy_normalised(&self) -> bool {
        false
    }
    /// Where R(ω_fixed, ·) concentrates, for the albedo quadrature.
    fn lobe(&self) -> Lobe {
        Lobe::Diffuse
    }
}

/// The shape of a model's mass over the hemisphere of the free direction, with the
/// angular width (radians) of its narrowest feature: the albedo quadrature integrates
/// in a chart centred on it and places breakpoints down to a tenth of the width.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Lobe {
    /// Broad over the hemisphere (Lambert, Oren–Nayar).
    Diffuse,
    /// Around the mirror direction of the fixed one (Phong).
    Mirror { width: f64 },
    /// A function of the half vector (Blinn–Phong, microfacets, Ward), `width` its
    /// width in h; an anisotropic one (elongated along the tangent) is integrated over
    /// the half vector, an isotropic one about the mirror direction.
    HalfVector { width: f64, anisotropic: bool },
    /// On the cone about the tangent (+x) mirroring the fixed direction (Kajiya–Kay).
    TangentCone { width: f64 },
}

/// A parameter outside a model's domain: which model, which parameter, what it was and
/// what it must be.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{model}.{param} = {value}: {requirement}")]
pub struct BrdfParamError {
    pub model: &'static str,
    pub param: &'static str,
    pub value: String,
    pub requirement: &'static str,
}

/// `Ok` if `value` is finite and in [lo, hi], else the error naming `model.param`.
pub(crate) fn check_range(
    model: &'static str,
    param: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    requirement: &'static str,
) -> Result<(), BrdfParamError> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(BrdfParamError {
            model,
            param,
            value: format!("{value}"),
            requirement,
        })
    }
}

/// Both directions renormalised if both are finite, non-zero and strictly above the
/// horizon; `None` (the caller returns R = 0) otherwise.
pub(crate) fn above_horizon(wi: Vec3, wo: Vec3) -> Option<(Vec3, Vec3)> {
    let unit = |w: Vec3| {
        let l = w.length();
        if l.is_finite() && l > 0.0 {
            let u = w * (1.0 / l);
            (u.z > 0.0).then_some(u)
        } else {
            None
        }
    };
    Some((unit(wi)?, unit(wo)?))
}

/// The mirror image of `w` about the normal +z.
pub(crate) fn mirror(w: Vec3) -> Vec3 {
    v3(-w.x, -w.y, w.z)
}

/// cos of the angle between ω_i and the mirror of ω_o, written so that swapping the
/// arguments gives the identical float (the same three products, summed in order).
pub(crate) fn cos_mirror(wi: Vec3, wo: Vec3) -> f64 {
    wi.z * wo.z - wi.x * wo.x - wi.y * wo.y
}

/// The unit half vector of two upper-hemisphere directions (ω_i + ω_o is commutative in
/// floats, so the half vector is exactly symmetric).
pub(crate) fn half_vector(wi: Vec3, wo: Vec3) -> Vec3 {
    (wi + wo).normalized()
}

/// The smallest cosine (or product of cosines) a model divides by: keeps 1/cos and
/// 1/√(cos·cos) finite for directions a hair above the horizon, with room for the
/// largest numerators (the Beckmann peak 1/(π α²) ≈ 3e13 at α = 1e-7), so no model
/// here returns more than ~1e294.
pub const COS_FLOOR: f64 = 1e-280;

/// The local frame of a surface point: unit normal `n`, unit tangent `t` orthogonal
/// to it, and `b = n × t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadingFrame {
    pub n: Vec3,
    pub t: Vec3,
    pub b: Vec3,
}

impl ShadingFrame {
    /// From a normal and a tangent hint (Gram–Schmidt); a hint parallel to `n` (or
    /// zero) falls back to a fixed perpendicular, so the frame is always orthonormal.
    pub fn new(n: Vec3, tangent_hint: Vec3) -> Self {
        let n = n.normalized();
        let mut t = tangent_hint - n * tangent_hint.dot(n);
        if t.length() < 1e-9 {
            let a = if n.x.abs() < 0.9 {
                v3(1.0, 0.0, 0.0)
            } else {
                v3(0.0, 1.0, 0.0)
            };
            t = a - n * a.dot(n);
        }
        let t = t.normalized();
        ShadingFrame {
            n,
            t,
            b: n.cross(t),
        }
    }

    /// A world vector in local coordinates (x along t, y along b, z along n).
    pub fn to_local(&self, w: Vec3) -> Vec3 {
        v3(w.dot(self.t), w.dot(self.b), w.dot(self.n))
    }

    /// R(ω_i, ω_o) for world-space directions.
    pub fn eval_world(&self, brdf: &dyn Brdf, wi: Vec3, wo: Vec3) -> f64 {
        brdf.eval(self.to_local(wi), self.to_local(wo))
    }
}
