//! `modulate`: GL_MODULATE on 8-bit unorm values.

use super::unit_entry::{seeded, trace_unit, UnitEntry};
use rand::Rng;
use rtl_model::units::modulate::{Modulate, ModulateIn};
use rtl_model::{Counters, UnitSummary};
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "modulate",
    summary: || UnitSummary::of(&Modulate::geforce()),
    tables: Vec::new,
    trace,
};

fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let mut rng = seeded(seed);
    let u = Modulate::geforce();
    let inputs: Vec<ModulateIn> = (0..pixels)
        .map(|_| ModulateIn {
            a: rng.random_range(0..=255),
            b: rng.random_range(0..=255),
        })
        .collect();
    trace_unit(&u, (), &inputs, w)
}
