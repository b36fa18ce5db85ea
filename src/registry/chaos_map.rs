//! `chaos_map`: the intermittent map of the 1/f fluctuation, through log2 and exp2 ROMs.

use super::unit_entry::{generated_roms, trace_unit, UnitEntry};
use crate::tables::Table;
use rtl_model::units::chaos_map::ChaosMap;
use rtl_model::{Counters, UnitSummary};
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "chaos_map",
    summary: || UnitSummary::of(&ChaosMap::geforce()),
    tables,
    trace,
};

/// The log2 and exp2 ROMs of the left branch.
fn tables() -> Vec<Table> {
    let cm = ChaosMap::geforce();
    let cc = cm.config();
    let gens = [
        "entry[i] = round(log2(1 + i/2^T) * 2^E), i = 0 ..= 2^T, u1.E",
        "entry[i] = round(2^(-i/2^T) * 2^E), i = 0 ..= 2^T, u1.E",
    ];
    generated_roms(
        cm.rom_images(),
        "chaos_map",
        cc.table_log2,
        cc.table_bits,
        &gens,
    )
}

/// The map iterates its own state from the seed: no inputs.
fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let u = ChaosMap::geforce();
    trace_unit(&u, u.seeded_state(seed), &vec![(); pixels], w)
}
