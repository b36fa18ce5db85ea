//! f64 reflection models of the shading seed (SPEC D), in pbrt-v4's shape: one small
//! type per model, `eval(ω_i, ω_o)` in a local shading frame, no hidden state.
//!
//! Local frame: the normal is +z, the tangent (the anisotropy or hair direction) is +x,
//! the bitangent +y. ω_i points from the surface toward the light, ω_o toward the
//! viewer; both are unit vectors. `eval` returns the BRDF value R(ω_i, ω_o) in sr⁻¹
//! (the radiance leaving along ω_o is ∫ R · L_i · cos θ_i dω_i), 0 below the horizon
//! unless the model says otherwise, never NaN.

use crate::scene::math::Vec3;

/// A reflection model in the local shading frame (n = +z, t = +x).
pub trait Brdf: Send + Sync {
    /// A short name for tables and file names (`cook_torrance_beckmann`, …).
    fn name(&self) -> String;
    /// R(ω_i, ω_o), sr⁻¹; ω_i toward the light, ω_o toward the viewer, both unit.
    fn eval(&self, wi: Vec3, wo: Vec3) -> f64;
}

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
                crate::scene::math::v3(1.0, 0.0, 0.0)
            } else {
                crate::scene::math::v3(0.0, 1.0, 0.0)
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
        crate::scene::math::v3(w.dot(self.t), w.dot(self.b), w.dot(self.n))
    }

    /// R(ω_i, ω_o) for world-space directions.
    pub fn eval_world(&self, brdf: &dyn Brdf, wi: Vec3, wo: Vec3) -> f64 {
        brdf.eval(self.to_local(wi), self.to_local(wo))
    }
}
