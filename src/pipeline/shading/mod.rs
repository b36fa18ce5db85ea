//! The shading pipeline (SPEC D): BRDFs rendered by the GeForce-era shading units —
//! vertex lighting, texture and register combiners, specular lookup, normalisation
//! cube map and BRDF factor textures — beside their f64 references.

pub mod sphere;
pub mod vertex_float;
