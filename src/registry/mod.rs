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
mod vertex_lighting;

pub use bloom_flare_modulator::default_bloom_flare;
pub use halo_modulator::default_halo;

use crate::tables::Table;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rtl_model::driver::run_tick;
use rtl_model::trace::VcdTrace;
use rtl_model::{Counters, Unit, UnitSummary};
use std::collections::BTreeMap;
use std::io::Write;

/// One hardware unit as the registry knows it.
pub struct UnitEntry {
    /// The unit's name: `Unit::name()` of its instance, the stem of its files and the
    /// heading of its section in docs/units.md.
    pub name: &'static str,
    /// The summary of its default (GeForce-era) instance.
    pub summary: fn() -> UnitSummary,
    /// Every RAM/ROM image its default instance holds that does not change from
    /// primitive to primitive (none: `Vec::new`).
    pub tables: fn() -> Vec<Table>,
    /// `pixels` seeded random inputs through its tick driver, written as VCD.
    pub trace: fn(pixels: usize, seed: u64, out: &mut dyn Write) -> Result<Counters, String>,
}

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

/// The generator every trace draws its random inputs from.
fn seeded(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// A table's parameters from `(key, value)` pairs.
fn params(kv: &[(&str, String)]) -> BTreeMap<String, String> {
    kv.iter().map(|(k, v)| (k.to_string(), v.clone())).collect()
}

/// A unit's generated ROM images as tables, each named with its generator formula
/// and the table's index bits T and entry bits E.
fn generated_roms(
    images: Vec<(String, u32, Vec<u64>)>,
    unit: &str,
    table_log2: u32,
    table_bits: u32,
    generators: &[&str],
) -> Vec<Table> {
    images
        .into_iter()
        .zip(generators)
        .map(|((name, width, words), g)| {
            rom(
                name,
                width,
                words,
                unit,
                params(&[
                    ("table_log2", table_log2.to_string()),
                    ("table_bits", table_bits.to_string()),
                    ("generator", g.to_string()),
                ]),
            )
        })
        .collect()
}

/// A ROM image held by `unit`; its file stem is `name` with dots as underscores.
fn rom(
    name: String,
    width: u32,
    words: Vec<u64>,
    unit: &str,
    params: BTreeMap<String, String>,
) -> Table {
    Table {
        name: name.replace('.', "_"),
        width,
        words,
        unit: unit.into(),
        params,
    }
}

/// Clock `inputs` through `u`'s tick driver from `state`, writing every register as VCD.
fn trace_unit<U: Unit>(
    u: &U,
    mut state: U::State,
    inputs: &[U::In],
    w: &mut dyn Write,
) -> Result<Counters, String> {
    let first = inputs.first().ok_or("pixels: must be at least 1")?;
    let mut probe_state = state.clone();
    let mut scratch = Counters::default();
    let out0 = u.kernel(&mut probe_state, first, &mut scratch);
    let io = |e: std::io::Error| format!("trace: {e}");
    let mut tr = VcdTrace::new(
        w,
        u.name(),
        u.timing().latency,
        &u.in_signals(first),
        &u.out_signals(&out0),
    )
    .map_err(io)?;
    let mut ctr = Counters::default();
    run_tick(u, &mut state, inputs, &mut ctr, Some(&mut tr)).map_err(io)?;
    tr.finish().map_err(io)?;
    Ok(ctr)
}
