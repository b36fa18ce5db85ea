//! Scenes: host-side geometry and (later) the TOML scene format and elaboration.

pub mod format;
pub mod geometry;
pub mod lightmap;
pub mod math;
