//! The glare renderer (Matsuda and Ikedo): host set-up, the units' frame, throughput,
//! reproductions and sweeps.

pub mod asic_preset;
pub mod attribute;
pub mod background;
pub mod cli;
pub mod clocked;
pub mod condition;
pub mod fluctuation;
pub mod frame;
pub mod gauss_seeds;
pub mod host;
pub mod primitives;
pub mod reproduce;
pub mod sweep;
pub mod tables;
pub mod throughput;
