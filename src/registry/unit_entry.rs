//! What each unit's registry file gives the registry ([`UnitEntry`]) and the helpers
//! those files build it with (seeded inputs, ROM tables, a VCD trace). The unit files
//! and the registry's table (`mod.rs`) import this file; it imports none of them.

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

/// The generator every trace draws its random inputs from.
pub(super) fn seeded(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// A table's parameters from `(key, value)` pairs.
pub(super) fn params(kv: &[(&str, String)]) -> BTreeMap<String, String> {
    kv.iter().map(|(k, v)| (k.to_string(), v.clone())).collect()
}

/// A unit's generated ROM images as tables, each named with its generator formula
/// and the table's index bits T and entry bits E.
pub(super) fn generated_roms(
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
pub(super) fn rom(
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
pub(super) fn trace_unit<U: Unit>(
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
