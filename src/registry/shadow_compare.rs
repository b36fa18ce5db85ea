//! `shadow_compare`: the shadow map's depth RAM, written and tested.

use super::unit_entry::{seeded, trace_unit, UnitEntry};
use rand::Rng;
use rtl_model::units::shadow_compare::{ShadowCompare, ShadowIn};
use rtl_model::{Counters, UnitSummary};
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "shadow_compare",
    summary: || UnitSummary::of(&ShadowCompare::geforce()),
    tables: Vec::new,
    trace,
};

/// Writes and tests alternating over a 4 × 4 corner of the map.
fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let mut rng = seeded(seed);
    let u = ShadowCompare::geforce();
    let far = (1u32 << u.depth_bits()) - 1;
    let inputs: Vec<ShadowIn> = (0..pixels)
        .map(|k| {
            let (x, y) = (rng.random_range(0..4), rng.random_range(0..4));
            if k % 2 == 0 {
                ShadowIn::Write {
                    x,
                    y,
                    depth: rng.random_range(0..=far),
                }
            } else {
                ShadowIn::Test {
                    x,
                    y,
                    depth: rng.random_range(0..=far as u64),
                }
            }
        })
        .collect();
    trace_unit(&u, u.fresh_state(), &inputs, w)
}
