//! The chip's architecture parameters as `sweep` and `optimize` name them: each a
//! whole number in the unit its name says, read from and written into a
//! [`ChipConfig`]. Changing one never changes a pixel, only the clocked time.

use super::config::ChipConfig;

/// One sweepable architecture parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ChipParam {
    /// Pixel pipes.
    Pipes,
    /// Texture units per pipe.
    Tmus,
    /// Entries of every FIFO between two stages.
    FifoDepth,
    /// Texture cache capacity in KiB (per cache).
    CacheKb,
    /// Texture cache line in bytes.
    CacheLine,
    /// Texture cache ways.
    CacheWays,
    /// Line requests a texture unit may have in flight.
    MissesInFlight,
    /// Memory bandwidth in MB/s (10⁶ bytes per second).
    BandwidthMbs,
    /// Memory latency in core clocks.
    MemLatency,
    /// Requests the memory controller queues.
    MemQueue,
    /// Core clock in MHz (the memory's bytes per second stay as they are).
    ClockMhz,
}

/// Every parameter, in the order `--help` and errors list them.
pub const CHIP_PARAMS: [ChipParam; 11] = [
    ChipParam::Pipes,
    ChipParam::Tmus,
    ChipParam::FifoDepth,
    ChipParam::CacheKb,
    ChipParam::CacheLine,
    ChipParam::CacheWays,
    ChipParam::MissesInFlight,
    ChipParam::BandwidthMbs,
    ChipParam::MemLatency,
    ChipParam::MemQueue,
    ChipParam::ClockMhz,
];

impl ChipParam {
    pub fn name(self) -> &'static str {
        match self {
            ChipParam::Pipes => "pipes",
            ChipParam::Tmus => "tmus",
            ChipParam::FifoDepth => "fifo_depth",
            ChipParam::CacheKb => "cache_kb",
            ChipParam::CacheLine => "cache_line",
            ChipParam::CacheWays => "cache_ways",
            ChipParam::MissesInFlight => "misses_in_flight",
            ChipParam::BandwidthMbs => "bandwidth_mbs",
            ChipParam::MemLatency => "mem_latency",
            ChipParam::MemQueue => "mem_queue",
            ChipParam::ClockMhz => "clock_mhz",
        }
    }

    /// The parameter of a name (`-` accepted for `_`), `None` when it is not a chip
    /// parameter.
    pub fn from_name(name: &str) -> Option<ChipParam> {
        let n = name.replace('-', "_");
        CHIP_PARAMS.into_iter().find(|p| p.name() == n)
    }

    /// Every name, comma-separated (for errors and help).
    pub fn names() -> String {
        CHIP_PARAMS.map(|p| p.name()).join(", ")
    }

    /// This parameter's value in `c`, rounded to the whole unit its name says.
    pub fn get(self, c: &ChipConfig) -> u32 {
        match self {
            ChipParam::Pipes => c.pipes,
            ChipParam::Tmus => c.tmus_per_pipe,
            ChipParam::FifoDepth => c.fifo_depth,
            ChipParam::CacheKb => c.texture_cache.size_bytes / 1024,
            ChipParam::CacheLine => c.texture_cache.line_bytes,
            ChipParam::CacheWays => c.texture_cache.ways,
            ChipParam::MissesInFlight => c.texture_cache.misses_in_flight,
            ChipParam::BandwidthMbs => (c.memory.bytes_per_clock * c.clock_hz / 1e6).round() as u32,
            ChipParam::MemLatency => c.memory.latency_clocks,
            ChipParam::MemQueue => c.memory.queue_depth,
            ChipParam::ClockMhz => (c.clock_hz / 1e6).round() as u32,
        }
    }

    /// Set this parameter to `v` in `c` (the config is validated by the clock, which
    /// names the field of a value it refuses).
    pub fn apply(self, c: &mut ChipConfig, v: u32) {
        match self {
            ChipParam::Pipes => c.pipes = v,
            ChipParam::Tmus => c.tmus_per_pipe = v,
            ChipParam::FifoDepth => c.fifo_depth = v,
            ChipParam::CacheKb => c.texture_cache.size_bytes = v.saturating_mul(1024),
            ChipParam::CacheLine => c.texture_cache.line_bytes = v,
            ChipParam::CacheWays => c.texture_cache.ways = v,
            ChipParam::MissesInFlight => c.texture_cache.misses_in_flight = v,
            ChipParam::BandwidthMbs => c.memory.bytes_per_clock = v as f64 * 1e6 / c.clock_hz,
            ChipParam::MemLatency => c.memory.latency_clocks = v,
            ChipParam::MemQueue => c.memory.queue_depth = v,
            ChipParam::ClockMhz => {
                let bytes_per_second = c.memory.bytes_per_clock * c.clock_hz;
                c.clock_hz = v as f64 * 1e6;
                c.memory.bytes_per_clock = bytes_per_second / c.clock_hz;
            }
        }
    }
}

/// Storage bits the chip's architecture adds to its units' RAM: the texture caches'
/// data (capacity × 8 per cache: one shared, or one per texture unit of every pipe).
/// Tags and FIFO registers are not counted (they are gates, not RAM, and small beside
/// the data).
pub fn texture_cache_bits(c: &ChipConfig) -> u64 {
    let caches = if c.texture_cache.shared {
        1
    } else {
        u64::from(c.pipes) * u64::from(c.tmus_per_pipe)
    };
    caches * u64::from(c.texture_cache.size_bytes) * 8
}
