//! `final_combiner`: the final combiner stage of NV_register_combiners.

use super::register_combiner::random_register_files;
use super::unit_entry::{seeded, trace_unit, UnitEntry};
use rtl_model::units::final_combiner::FinalCombiner;
use rtl_model::{Counters, UnitSummary};
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "final_combiner",
    summary: || UnitSummary::of(&FinalCombiner::geforce()),
    tables: Vec::new,
    trace,
};

fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let inputs = random_register_files(&mut seeded(seed), pixels);
    trace_unit(&FinalCombiner::geforce(), (), &inputs, w)
}
