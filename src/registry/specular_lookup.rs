//! `specular_lookup`: a DOT3 code raised to the specular exponent through a table.

use super::unit_entry::{seeded, trace_unit, UnitEntry};
use crate::tables::Table;
use rand::Rng;
use rtl_model::units::specular_lookup::{SpecularLookup, SpecularLookupIn};
use rtl_model::{Counters, UnitSummary};
use std::collections::BTreeMap;
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "specular_lookup",
    summary: || UnitSummary::of(&SpecularLookup::geforce()),
    tables,
    trace,
};

/// The power table at the default exponent (the host writes one per exponent).
fn tables() -> Vec<Table> {
    let spec = SpecularLookup::geforce();
    let c = spec.config();
    vec![Table {
        name: format!(
            "specular_lookup_pow{}_{}x{}",
            c.exponent,
            1u32 << c.table_log2,
            c.entry_bits
        ),
        width: c.entry_bits,
        words: spec.table_words(),
        unit: "specular_lookup".into(),
        params: BTreeMap::from([
            ("table_log2".to_string(), c.table_log2.to_string()),
            ("entry_bits".to_string(), c.entry_bits.to_string()),
            ("exponent".to_string(), c.exponent.to_string()),
            (
                "generator".to_string(),
                "specular_table_entry(j): round((j/N)^s * (2^b - 1)) half up, N = 2^k - 1; the host writes it per exponent (this is the default s); rtl_model/src/units/specular_lookup.rs".to_string(),
            ),
        ]),
    }]
}

fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let mut rng = seeded(seed);
    let u = SpecularLookup::geforce();
    // DOT3 codes over the whole range, with the top (the highlight) favoured.
    let inputs: Vec<SpecularLookupIn> = (0..pixels)
        .map(|k| SpecularLookupIn {
            code: if k % 2 == 0 {
                rng.random_range(0..=255)
            } else {
                rng.random_range(224..=255)
            },
        })
        .collect();
    trace_unit(&u, (), &inputs, w)
}
