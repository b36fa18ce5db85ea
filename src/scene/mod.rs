//! Scenes: host-side geometry and (later) the TOML scene format and elaboration.

pub mod builtin;
pub mod format;
pub mod math;
pub mod teapot;
pub mod validate;
