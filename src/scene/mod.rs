//! Scenes: the TOML scene format, its validation, built-in scenes, tessellation,
//! light maps, environment maps and ray–shape geometry (host side, f64).

pub mod bounds;
pub mod builtin;
pub mod builtin_environment;
pub mod builtin_glare;
pub mod builtin_showcase;
pub mod camera;
pub mod clip;
pub mod environment;
pub mod envmap;
pub mod fields;
pub mod fields_reference;
pub mod format;
pub mod geometry;
pub mod glare;
pub mod glare_hw;
pub mod lightmap;
pub mod limits;
pub mod load;
pub mod material;
pub mod math;
pub mod print;
pub mod rounding;
pub mod shading_hw;
pub mod shading_sphere;
pub mod suggest;
pub mod teapot;
pub mod test_scene;
pub mod validate;
