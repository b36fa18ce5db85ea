//! The clocked chip's outputs. A minimal placeholder of `print_table` and `json` so
//! `render --timing clocked` reports through them; the full outputs (per-stage
//! utilisation, cache hit rate, bandwidth by client, timeline, VCD) replace it.

use crate::chip::clock::FrameTiming;
use serde_json::Value;

/// One line per clocked pass: cycles, seconds at the chip's clock and the roofline's.
pub fn print_table(ft: &FrameTiming) -> String {
    let mut s = format!(
        "clocked timing ({}, {}, {:.0} MHz):\n",
        ft.mode,
        ft.chip,
        ft.clock_hz / 1e6
    );
    for p in &ft.passes {
        s += &format!(
            "  {}: {} cycles, {:.6} s clocked, {:.6} s roofline\n",
            p.pass,
            p.timing.cycles,
            p.timing.cycles as f64 / ft.clock_hz,
            p.roofline_seconds
        );
    }
    s += &format!(
        "  frame: {} cycles, {:.6} s clocked\n",
        ft.cycles_total(),
        ft.clocked_seconds()
    );
    s
}

/// The frame's clocked timing as JSON.
pub fn json(ft: &FrameTiming) -> Value {
    serde_json::to_value(ft).unwrap_or(Value::Null)
}
