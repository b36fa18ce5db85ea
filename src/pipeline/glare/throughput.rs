//! The glare renderer's throughput model: pixels per clock per pipe, parallel pipes,
//! clock → pixels/s, and the gates and RAM bits of the configuration (Matsuda and
//! Ikedo's renderer fills 1.2 × 10⁹ pixels/s with a ~80 k-gate modulator).
//!
//! Every pipe holds a polygon interpolator, a bloom/flare modulator, a halo modulator
//! and a combiner, each II = 1: one pixel per clock per pipe. The polygon-variable
//! generator and the Gaussian noise generator work per primitive and are shared.
//! A frame's time: per primitive the set-up latency, the walk (its pixels spread
//! over the pipes) and the pipeline's drain, plus the host's RAM-table writes (four
//! words per clock: the shape RAM's four banks, or the falloff/ring RAMs, in parallel).

use super::frame::{GlareFrame, PrimStat};
use rtl_model::UnitSummary;
use serde::Serialize;

/// One row of `throughput.csv`.
#[derive(Clone, Debug, Serialize)]
pub struct ThroughputRow {
    pub config: String,
    pub clock_mhz: f64,
    pub pipes: u32,
    pub pixels_per_second: f64,
    pub gates_nand2: f64,
    pub ram_bits: u64,
}

/// Gates and RAM bits of `pipes` pipes of `per_pipe` units plus the `shared` ones.
pub fn config_cost(per_pipe: &[UnitSummary], shared: &[UnitSummary], pipes: u32) -> (f64, u64) {
    let g = per_pipe.iter().map(|u| u.gates_nand2).sum::<f64>() * pipes as f64
        + shared.iter().map(|u| u.gates_nand2).sum::<f64>();
    let r = per_pipe.iter().map(|u| u.ram_bits).sum::<u64>() * pipes as u64
        + shared.iter().map(|u| u.ram_bits).sum::<u64>();
    (g, r)
}

/// Peak fill rate: one pixel per clock per pipe.
pub fn peak_pixels_per_second(clock_mhz: f64, pipes: u32) -> f64 {
    clock_mhz * 1e6 * pipes as f64
}

/// Clocks of one primitive on `pipes` pipes: set-up, the walk, the drain.
pub fn prim_cycles(p: &PrimStat, pipes: u32, setup: u64, drain: u64) -> u64 {
    if p.walked == 0 {
        return setup;
    }
    setup + p.walked.div_ceil(pipes as u64) + drain
}

/// A frame's predicted time on the configured glare hardware.
#[derive(Clone, Debug, Serialize)]
pub struct GlarePrediction {
    pub clock_mhz: f64,
    pub pipes: u32,
    pub walk_cycles: u64,
    pub table_cycles: u64,
    pub cycles: u64,
    pub seconds: f64,
    pub fragments: u64,
    pub walked: u64,
    /// Covered fragments per second of the predicted time.
    pub fragments_per_second: f64,
}

/// Predict a frame's time from its primitives.
pub fn predict(
    f: &GlareFrame,
    clock_mhz: f64,
    pipes: u32,
    setup: u64,
    drain: u64,
) -> GlarePrediction {
    let walk_cycles: u64 = f
        .prims
        .iter()
        .map(|p| prim_cycles(p, pipes, setup, drain))
        .sum();
    let table_cycles: u64 = f.prims.iter().map(|p| p.table_words.div_ceil(4)).sum();
    let cycles = walk_cycles + table_cycles;
    let seconds = cycles as f64 / (clock_mhz * 1e6);
    let fragments = f.prims.iter().map(|p| p.fragments).sum();
    GlarePrediction {
        clock_mhz,
        pipes,
        walk_cycles,
        table_cycles,
        cycles,
        seconds,
        fragments,
        walked: f.prims.iter().map(|p| p.walked).sum(),
        fragments_per_second: if seconds > 0.0 {
            fragments as f64 / seconds
        } else {
            0.0
        },
    }
}
