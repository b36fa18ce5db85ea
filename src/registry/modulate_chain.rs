//! `modulate_chain`: primary colour × texture 0 × texture 1 in GL_MODULATE, 8-bit.

use super::unit_entry::{seeded, trace_unit, UnitEntry};
use rand::Rng;
use rtl_model::units::modulate_chain::{ModulateChain, ModulateChainIn, MAX_OPERANDS};
use rtl_model::{Counters, UnitSummary};
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "modulate_chain",
    summary: || UnitSummary::of(&ModulateChain::geforce()),
    tables: Vec::new,
    trace,
};

fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let mut rng = seeded(seed);
    let u = ModulateChain::geforce();
    let inputs: Vec<ModulateChainIn> = (0..pixels)
        .map(|_| {
            let mut ops = [0u32; MAX_OPERANDS];
            for o in &mut ops {
                *o = rng.random_range(0..=255);
            }
            ModulateChainIn { ops }
        })
        .collect();
    trace_unit(&u, (), &inputs, w)
}
