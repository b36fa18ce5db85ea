//! The shading pipeline (the models of Shinya's survey): BRDFs rendered by the GeForce-era shading units —
//! vertex lighting, texture and register combiners, specular lookup, normalisation
//! cube map and BRDF factor textures — beside their f64 references.

pub mod attribute;
pub mod attributed_sweep;
pub mod brdf_properties;
pub mod brdfs;
pub mod factor;
pub mod materials;
pub mod normalize_cube;
pub mod path;
pub mod scene_file;
pub mod scene_pass;
pub mod specular;
pub mod sphere;
pub mod squaring;
pub mod sweep;
pub mod vertex_float;
