//! f64 reflection models of Shinya's survey, in pbrt-v4's shape: one small
//! type per model, `eval(ω_i, ω_o)` in a local shading frame, no hidden state.
//!
//! Local frame: the normal is +z, the tangent (the anisotropy or hair direction) is +x,
//! the bitangent +y. ω_i points from the surface toward the light, ω_o toward the
//! viewer; both are unit vectors. `eval` returns the BRDF value R(ω_i, ω_o) in sr⁻¹
//! (the radiance leaving along ω_o is ∫ R · L_i · cos θ_i dω_i), 0 below the horizon
//! unless the model says otherwise, never NaN.
//!
//! Conventions shared by every model here:
//! * a direction on or below the horizon (cos θ ≤ 0, including cos θ exactly 0), a
//!   zero vector or a non-finite one gives R = 0; other inputs are renormalised, so a
//!   slightly non-unit vector is harmless;
//! * `eval` is written symmetrically in (ω_i, ω_o) wherever the model is reciprocal
//!   (the half vector from ω_i + ω_o, products in a fixed order), so the reciprocity
//!   residual of those models is at rounding level or exactly 0;
//! * constructors validate every parameter and name it on error
//!   (`cook_torrance.alpha = 0: …`).
//!
//! [`albedo`] integrates the directional albedo with a stated error; the models'
//! [`Brdf::lobe`] hint tells it where the mass is.

pub mod albedo;
pub mod cook_torrance;
pub mod henyey_greenstein;
pub mod kajiya_kay;
pub mod lambert;
pub mod oren_nayar;
pub mod phong;
pub mod subsurface;
pub mod ward;

pub use albedo::{directional_albedo, Albedo, AlbedoTol, FixedSide};
pub use cook_torrance::{
    CookTorrance, CookTorranceParams, Fresnel, Masking, MicrofacetDistribution,
};
pub use henyey_greenstein::HenyeyGreenstein;
pub use kajiya_kay::{KajiyaKay, KajiyaKayParams};
pub use lambert::Lambert;
pub use oren_nayar::{OrenNayar, OrenNayarForm, OrenNayarParams};
pub use phong::{BlinnPhong, Phong, PhongForm, PhongParams};
pub use subsurface::{Dipole, DipoleBrdf, DipoleParams, HanrahanKrueger, HanrahanKruegerParams};
pub use ward::{Ward, WardForm, WardParams};
mod model;

pub use model::{Brdf, BrdfParamError, Lobe, ShadingFrame, COS_FLOOR};
