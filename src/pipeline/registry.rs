//! Every hardware unit by name, in its GeForce-era default configuration: its
//! summary (widths, latency, II, gates, RAM bits), the tables it holds, and a VCD
//! trace of a few random pixels through the tick driver.

use crate::tables::Table;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::driver::run_tick;
use rtl_model::trace::VcdTrace;
use rtl_model::units::modulate::{Modulate, ModulateIn};
use rtl_model::{Counters, Unit, UnitSummary};
use std::io::Write;

/// Names of all units, in datasheet order.
pub const UNIT_NAMES: &[&str] = &["modulate"];

/// Summaries of every unit at its defaults.
pub fn summaries() -> Vec<UnitSummary> {
    vec![UnitSummary::of(&Modulate::geforce())]
}

/// Every RAM/ROM image the default units hold.
pub fn tables() -> Vec<Table> {
    Vec::new()
}

/// Trace `pixels` random inputs (seeded) through the named unit's tick driver as VCD.
pub fn trace(name: &str, pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    match name {
        "modulate" => {
            let u = Modulate::geforce();
            let inputs: Vec<ModulateIn> = (0..pixels)
                .map(|_| ModulateIn {
                    a: rng.random_range(0..=255),
                    b: rng.random_range(0..=255),
                })
                .collect();
            trace_unit(&u, (), &inputs, w)
        }
        _ => Err(format!(
            "unit: unknown unit '{name}' (known: {})",
            UNIT_NAMES.join(", ")
        )),
    }
}

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
