//! Scenes: the TOML scene format, its validation, built-in scenes, tessellation and
//! host-side geometry.

pub mod builtin;
pub mod format;
pub mod math;
pub mod teapot;
pub mod validate;
