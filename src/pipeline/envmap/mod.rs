//! The multi-scale environment map (SPEC C, issue 5): the voxel map, its prefilter
//! (exact and accelerated), the renderer and its studies: see docs/envmap.md.

pub mod prefilter;
pub mod render;
pub mod reproduce;
pub mod slice;
pub mod studies;
pub mod timing;
pub mod voxmap;
