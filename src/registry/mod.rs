//! Every hardware unit by name, in its GeForce-era default configuration: its
//! summary (widths, latency, II, gates, RAM bits), the tables it holds, and a VCD
//! trace of a few random pixels through the tick driver.
//!
//! One table, [`UNITS`], lists the units; everything else here (`UNIT_NAMES`,
//! `summaries`, `tables`, `trace`, the datasheet's generated figures) is derived from
//! it. Each unit's entry lives in `registry/<unit>.rs`, named like the unit's other
//! files (`rtl_model/src/units/<unit>.rs`, `src/reference/<unit>.rs`,
//! `tests/<unit>.rs`), so a newcomer finds all of them by the unit's name.
//! `datasheet` writes the registry's figures into docs/units.md.

pub mod datasheet;
pub mod rtl;

mod blend;
mod bloom_flare_modulator;
mod chaos_map;
mod clipper;
mod cube_map_address;
mod final_combiner;
mod gaussian_noise;
mod glare_combiner;
mod glare_condition;
mod halo_modulator;
mod luminance_ram;
mod modulate;
mod modulate_chain;
mod polygon_interpolator;
mod polygon_variable_generator;
mod projective_texcoord;
mod reflection_vector;
mod register_combiner;
mod shadow_compare;
mod specular_lookup;
mod texture_combiner;
mod texture_sampler;
mod unit_entry;
mod vertex_lighting;

pub use bloom_flare_modulator::default_bloom_flare;
pub use halo_modulator::default_halo;
pub use unit_entry::UnitEntry;

use crate::tables::Table;
use rtl_model::{Counters, UnitSummary};
use std::io::Write;

/// Every unit, in datasheet order (the order of `units`, `units --json` and
/// docs/units.md). Adding a unit: one line here, one `mod` line above, and its
/// `registry/<unit>.rs` (docs/ARCHITECTURE.md § Adding a unit).
pub const UNITS: &[UnitEntry] = &[
    modulate::ENTRY,
    modulate_chain::ENTRY,
    blend::ENTRY,
    texture_sampler::ENTRY,
    clipper::ENTRY,
    polygon_interpolator::ENTRY,
    shadow_compare::ENTRY,
    projective_texcoord::ENTRY,
    polygon_variable_generator::ENTRY,
    bloom_flare_modulator::ENTRY,
    halo_modulator::ENTRY,
    glare_combiner::ENTRY,
    gaussian_noise::ENTRY,
    chaos_map::ENTRY,
    glare_condition::ENTRY,
    reflection_vector::ENTRY,
    cube_map_address::ENTRY,
    specular_lookup::ENTRY,
    register_combiner::ENTRY,
    final_combiner::ENTRY,
    texture_combiner::ENTRY,
    vertex_lighting::ENTRY,
];

const NAMES: [&str; UNITS.len()] = {
    let mut names = [""; UNITS.len()];
    let mut i = 0;
    while i < UNITS.len() {
        names[i] = UNITS[i].name;
        i += 1;
    }
    names
};

/// Names of all units, in datasheet order.
pub const UNIT_NAMES: &[&str] = &NAMES;

/// The registry entry of the named unit.
pub fn entry(name: &str) -> Option<&'static UnitEntry> {
    UNITS.iter().find(|e| e.name == name)
}

/// Summaries of every unit at its defaults.
pub fn summaries() -> Vec<UnitSummary> {
    UNITS.iter().map(|e| (e.summary)()).collect()
}

/// The order of tables/manifest.json, pinned as it was written before the registry
/// became one table (it differs from datasheet order); a unit not listed here follows
/// in registry order. Dropping the pin would reorder manifest.json once (the `.hex`
/// files would not change).
const MANIFEST_ORDER: &[&str] = &[
    "projective_texcoord",
    "texture_sampler",
    "polygon_variable_generator",
    "bloom_flare_modulator",
    "halo_modulator",
    "gaussian_noise",
    "chaos_map",
    "reflection_vector",
    "vertex_lighting",
    "cube_map_address",
    "specular_lookup",
];

/// Every RAM/ROM image the default units hold, and the textures of the built-in scene.
pub fn tables() -> Vec<Table> {
    let mut entries: Vec<&UnitEntry> = UNITS.iter().collect();
    // Stable: unlisted units keep registry order after the listed ones.
    entries.sort_by_key(|e| {
        MANIFEST_ORDER
            .iter()
            .position(|&n| n == e.name)
            .unwrap_or(MANIFEST_ORDER.len())
    });
    entries.iter().flat_map(|e| (e.tables)()).collect()
}

/// Trace `pixels` random inputs (seeded) through the named unit's tick driver as VCD.
pub fn trace(name: &str, pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let e = entry(name).ok_or_else(|| {
        format!(
            "unit: unknown unit '{name}' (known: {})",
            UNIT_NAMES.join(", ")
        )
    })?;
    (e.trace)(pixels, seed, w)
}
