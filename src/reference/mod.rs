//! f64 twins of the hardware units (one per unit, named after it) and whole-image
//! references. The reference never imports a unit's kernel; tests are where they meet.

pub mod additive_blend;
pub mod modulate;
pub mod polygon_interpolator;
pub mod projective_texcoord;
pub mod quadrature;
pub mod raymarch;
pub mod shadow_compare;
pub mod shafts_model;
pub mod test_scene;
pub mod texture_sampler;
