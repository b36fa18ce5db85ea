//! The system around the hardware: f64 references, scenes, pipelines, reports, CLI.

pub mod chip;
pub mod cli;
pub mod conformance;
pub mod frame;
pub mod pipeline;
pub mod reference;
pub mod registry;
pub mod report;
pub mod scene;
pub mod tables;
