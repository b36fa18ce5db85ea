//! Per-unit event counters. Cycle counts come from the unit's timing, never from wall time.

use serde::Serialize;
use std::ops::AddAssign;

/// Everything a unit counts. A wrap is never silent: `overflows` counts wraps,
/// `saturations` counts clamps, `underflows` counts non-zero values rounded to zero.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Counters {
    /// Clock cycles from the first input to the last output leaving the unit.
    pub cycles: u64,
    /// Input words (pixels, fragments, vertices or steps) the unit accepted.
    pub pixels_in: u64,
    /// Output words the unit presented.
    pub pixels_out: u64,
    /// Cycles an input waited because the unit was not ready (initiation interval > 1).
    pub stalls: u64,
    /// Reads of the unit's RAM/ROM tables (texels, table entries).
    pub table_reads: u64,
    /// Bytes read from external memory (texels, framebuffer).
    pub mem_read_bytes: u64,
    /// Bytes written to external memory (framebuffer).
    pub mem_write_bytes: u64,
    /// Values clamped to their format's range (SAT, SAT_SYM, SAT_ZERO and unorm clamps).
    pub saturations: u64,
    /// Values that did not fit and wrapped (WRAP): a wrap is never silent.
    pub overflows: u64,
    /// Non-zero values that rounding turned into zero.
    pub underflows: u64,
}

impl AddAssign for Counters {
    fn add_assign(&mut self, o: Counters) {
        self.cycles += o.cycles;
        self.pixels_in += o.pixels_in;
        self.pixels_out += o.pixels_out;
        self.stalls += o.stalls;
        self.table_reads += o.table_reads;
        self.mem_read_bytes += o.mem_read_bytes;
        self.mem_write_bytes += o.mem_write_bytes;
        self.saturations += o.saturations;
        self.overflows += o.overflows;
        self.underflows += o.underflows;
    }
}

impl Counters {
    /// Named fields in a fixed order (for tables and CSV).
    pub fn fields(&self) -> [(&'static str, u64); 10] {
        [
            ("cycles", self.cycles),
            ("pixels_in", self.pixels_in),
            ("pixels_out", self.pixels_out),
            ("stalls", self.stalls),
            ("table_reads", self.table_reads),
            ("mem_read_bytes", self.mem_read_bytes),
            ("mem_write_bytes", self.mem_write_bytes),
            ("saturations", self.saturations),
            ("overflows", self.overflows),
            ("underflows", self.underflows),
        ]
    }
}
