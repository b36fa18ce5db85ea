//! The clocked chip: a pass's recorded work ([`PassWork`]) run clock by clock through
//! the stages joined by bounded FIFOs with valid/ready back-pressure, the texture
//! caches and the memory controller. Time only: the pixels are the functional model's.

use super::config::ChipConfig;
use super::work::PassWork;
use rtl_model::ConfigError;
use serde::Serialize;
use std::collections::BTreeMap;

/// One stage's clocks over a pass: busy (did work), stalled (had work, blocked by a
/// full FIFO downstream or by memory), starved (empty upstream). busy + stalled +
/// starved = the pass's cycles.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct StageClocks {
    pub name: String,
    pub busy: u64,
    pub stalled: u64,
    pub starved: u64,
}

/// A FIFO's deepest occupancy over a pass.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct FifoHighWater {
    pub name: String,
    pub depth: u32,
    pub high_water: u32,
}

/// Utilisation over time: per stage, the busy fraction of each bucket of
/// `bucket_clocks` clocks (the last bucket may be shorter).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Timeline {
    pub bucket_clocks: u64,
    pub stages: Vec<String>,
    /// `busy[s][b]`: stage s's busy fraction in bucket b, 0 ..= 1.
    pub busy: Vec<Vec<f32>>,
}

/// The chip-level signals over a window of clocks, for a VCD: each signal's value at
/// the window's start and every change after it.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct WindowTrace {
    pub start_clock: u64,
    pub end_clock: u64,
    /// (name, width in bits): "<fifo>.valid", "<fifo>.ready", "<fifo>.level", …
    pub signals: Vec<(String, u32)>,
    /// (clock, signal index, value), in clock order.
    pub changes: Vec<(u64, u32, u64)>,
}

/// A pass clocked on a chip.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct PassTiming {
    /// Clocks from the pass's first primitive to its last write (over all its hardware
    /// passes, with the pass overhead).
    pub cycles: u64,
    /// Hardware passes the pass took (⌈textures / textures per pass⌉).
    pub hardware_passes: u32,
    pub stages: Vec<StageClocks>,
    pub fifos: Vec<FifoHighWater>,
    pub cache_hits: u64,
    pub cache_misses: u64,
    /// Bytes moved by each memory client: "texture", "depth", "colour", "copy".
    pub bytes_by_client: BTreeMap<String, u64>,
    /// The stage or memory client that bounds the pass.
    pub bottleneck: String,
    pub timeline: Timeline,
    /// Present when a window was asked for and overlaps the pass.
    pub window: Option<WindowTrace>,
}

impl PassTiming {
    /// Hits ÷ lookups, `None` when the pass looked nothing up.
    pub fn cache_hit_rate(&self) -> Option<f64> {
        let n = self.cache_hits + self.cache_misses;
        (n > 0).then(|| self.cache_hits as f64 / n as f64)
    }
}

/// One pass of a frame, clocked, beside its roofline prediction.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct NamedPassTiming {
    /// The frame's pass name (as `render --plan` lists it).
    pub pass: String,
    pub timing: PassTiming,
    /// The roofline's seconds for the same pass (the cross-check).
    pub roofline_seconds: f64,
}

/// A frame's clocked timing.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct FrameTiming {
    /// "clocked" or "sampled".
    pub mode: String,
    /// The chip preset's name.
    pub chip: String,
    pub clock_hz: f64,
    pub passes: Vec<NamedPassTiming>,
    /// In sampled mode: the estimated relative error of the frame's cycles (one
    /// standard error over the sampled tiles), else `None`.
    pub sampling_error: Option<f64>,
    /// Passes of the frame that recorded no work (not clocked: not in `passes`,
    /// not in `cycles_total`), with their roofline time.
    pub roofline_only: Vec<RooflineOnlyPass>,
}

/// A pass of a clocked frame that recorded no work, timed by the roofline alone.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct RooflineOnlyPass {
    /// The frame's pass name.
    pub pass: String,
    /// Its kind (`crate::chip::kind_name`).
    pub kind: String,
    /// The roofline's seconds.
    pub seconds: f64,
    /// Why it is not clocked ("roofline (no recorded work)").
    pub why: String,
}

impl FrameTiming {
    /// Clocks over every pass.
    pub fn cycles_total(&self) -> u64 {
        self.passes.iter().map(|p| p.timing.cycles).sum()
    }

    /// The frame's clocked seconds at the chip's clock.
    pub fn clocked_seconds(&self) -> f64 {
        self.cycles_total() as f64 / self.clock_hz
    }
}

/// Clock one pass's work on a chip. `window` (clocks relative to the pass's start)
/// asks for the chip-level signals over that range.
pub fn clock_pass(
    chip: &ChipConfig,
    work: &PassWork,
    window: Option<std::ops::Range<u64>>,
) -> Result<PassTiming, ConfigError> {
    let _ = (chip, work, window);
    Err(ConfigError::invalid(
        "timing",
        "the clocked chip is being built; use --timing roofline",
    ))
}
