//! The system around the hardware: f64 references, scenes, pipelines, reports, CLI.

pub mod reference;
