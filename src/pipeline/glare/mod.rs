//! The glare renderer (SPEC B): host set-up, the units' frame, throughput,
//! reproductions and sweeps.

pub mod host;
pub mod tables;
