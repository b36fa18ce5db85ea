//! One file per hardware unit. Each has an f64 twin in the main crate's
//! `src/reference/`, a property test in `tests/` and a datasheet in `docs/units.md`.

pub mod additive_blend;
pub mod modulate;
pub mod polygon_interpolator;
pub mod projective_texcoord;
pub mod shadow_compare;
pub mod texture_sampler;
