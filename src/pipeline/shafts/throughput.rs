//! The shafts pipeline's throughput model: the shared GPU time model
//! (`pipeline::time_model`, docs/throughput.md), re-exported under its old path.

pub use crate::pipeline::time_model::*;
