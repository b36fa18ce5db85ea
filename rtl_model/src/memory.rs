//! External memory traffic: bytes per access at a word's real width, and the
//! bandwidth model that turns bytes into clocks.

use crate::counters::Counters;
use crate::error::{check_finite, ConfigError};

/// Bytes one access of a `bits`-wide word moves (memory is byte-addressed).
pub fn bytes_for_bits(bits: u32) -> u64 {
    (bits as u64).div_ceil(8)
}

/// Count a framebuffer read-modify-write of one pixel of `pixel_bits` (read + write).
pub fn framebuffer_rmw(ctr: &mut Counters, pixel_bits: u32) {
    framebuffer_rmws(ctr, 1, pixel_bits);
}

/// Count `n` framebuffer read-modify-writes of pixels of `pixel_bits` each.
pub fn framebuffer_rmws(ctr: &mut Counters, n: u64, pixel_bits: u32) {
    let b = bytes_for_bits(pixel_bits) * n;
    ctr.mem_read_bytes += b;
    ctr.mem_write_bytes += b;
}

/// Count `texels` texel fetches of `texel_bits` each (no texture cache is modelled:
/// every fetch is a memory read; a cache would divide this, see docs/throughput.md).
pub fn texel_fetch(ctr: &mut Counters, texels: u64, texel_bits: u32) {
    ctr.table_reads += texels;
    ctr.mem_read_bytes += texels * bytes_for_bits(texel_bits);
}

/// A memory interface of a given bandwidth at a given core clock.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MemoryModel {
    /// Sustained bytes per second (GeForce2 GTS: about 5.3e9).
    pub bytes_per_second: f64,
    /// Core clock in Hz (GeForce2 GTS: 200e6).
    pub clock_hz: f64,
}

impl MemoryModel {
    /// A memory interface of `bytes_per_second` at a core clock of `clock_hz`. Both must be
    /// finite and > 0; otherwise the error names `memory.bytes_per_second` or
    /// `memory.clock_hz`.
    pub fn new(bytes_per_second: f64, clock_hz: f64) -> Result<Self, ConfigError> {
        for (f, v) in [
            ("memory.bytes_per_second", bytes_per_second),
            ("memory.clock_hz", clock_hz),
        ] {
            check_finite(f, v)?;
            if v <= 0.0 {
                return Err(ConfigError::out_of_range(f, v, f64::MIN_POSITIVE, f64::MAX));
            }
        }
        Ok(MemoryModel {
            bytes_per_second,
            clock_hz,
        })
    }

    /// GeForce2 GTS defaults: 5.3 GB/s at a 200 MHz core clock.
    pub fn geforce2_gts() -> Self {
        MemoryModel {
            bytes_per_second: 5.3e9,
            clock_hz: 200e6,
        }
    }

    /// Core clocks the memory needs to move the counted bytes.
    pub fn cycles_for(&self, ctr: &Counters) -> u64 {
        let bytes = (ctr.mem_read_bytes + ctr.mem_write_bytes) as f64;
        (bytes * self.clock_hz / self.bytes_per_second).ceil() as u64
    }

    /// Seconds for a pass bounded by either compute cycles or memory traffic.
    pub fn seconds(&self, compute_cycles: u64, ctr: &Counters) -> f64 {
        compute_cycles.max(self.cycles_for(ctr)) as f64 / self.clock_hz
    }
}
