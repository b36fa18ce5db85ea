//! The multi-scale environment map (Okumura's thesis): the voxel map, its prefilter
//! (exact and accelerated), the renderer, its studies and the `[environment]` scene
//! renderer: see docs/envmap.md.

pub mod attribute;
pub mod cube_slice;
pub mod dump;
pub mod image;
pub mod interpolator;
pub mod objects;
pub mod prefilter;
pub mod quick_map;
pub mod render;
pub mod reproduce;
pub mod roughness;
pub mod roughness_comparison;
pub mod scene_render;
pub mod slice;
pub mod studies;
pub mod sweep;
pub mod table5;
pub mod timing;
mod truth;
pub mod voxmap;
mod walk;
