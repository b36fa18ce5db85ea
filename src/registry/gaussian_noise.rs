//! `gaussian_noise`: Box-Muller Gaussian samples through ln, sqrt and sin ROMs.

use super::unit_entry::{generated_roms, trace_unit, UnitEntry};
use crate::tables::Table;
use rtl_model::units::gaussian_noise::{GaussState, GaussianNoise};
use rtl_model::{Counters, UnitSummary};
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "gaussian_noise",
    summary: || UnitSummary::of(&GaussianNoise::geforce()),
    tables,
    trace,
};

/// The ln, sqrt and sin ROMs of the Box-Muller datapath.
fn tables() -> Vec<Table> {
    let gn = GaussianNoise::geforce();
    let gc = gn.config();
    let gens = [
        "entry[i] = round(ln(1 + i/2^T) * 2^E), i = 0 ..= 2^T, u0.E",
        "entry[j] = round(sqrt(i/2^(T-2)) * 2^E), i = 2^(T-2) + j, j = 0 ..= 3*2^(T-2), u2.E",
        "entry[i] = round(sin(pi/2 * i/2^T) * 2^E), i = 0 ..= 2^T, u1.E (quarter wave)",
    ];
    generated_roms(
        gn.rom_images(),
        "gaussian_noise",
        gc.table_log2,
        gc.table_bits,
        &gens,
    )
}

/// The unit draws its own uniforms: the seed is its LFSR state, no inputs.
fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let u = GaussianNoise::geforce();
    trace_unit(&u, GaussState::from_seed(seed), &vec![(); pixels], w)
}
