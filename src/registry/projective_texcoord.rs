//! `projective_texcoord`: s/q, t/q through a reciprocal ROM and Newton steps.

use super::unit_entry::{seeded, trace_unit, UnitEntry};
use crate::tables::Table;
use rand::Rng;
use rtl_model::units::projective_texcoord::{ProjectiveIn, ProjectiveTexcoord};
use rtl_model::{Counters, UnitSummary};
use std::collections::BTreeMap;
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "projective_texcoord",
    summary: || UnitSummary::of(&ProjectiveTexcoord::geforce()),
    tables,
    trace,
};

/// The reciprocal seed ROM.
fn tables() -> Vec<Table> {
    let proj = ProjectiveTexcoord::geforce();
    let p = proj.rom_params();
    let mut params: BTreeMap<String, String> = p
        .params
        .iter()
        .map(|(k, v)| (k.clone(), v.to_string()))
        .collect();
    params.insert("generator".into(), p.generator.clone());
    vec![Table {
        name: p.name.clone(),
        width: p.width,
        words: proj.rom_words(),
        unit: "projective_texcoord".into(),
        params,
    }]
}

fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let mut rng = seeded(seed);
    let u = ProjectiveTexcoord::geforce();
    let one = 1i64 << 16;
    let inputs: Vec<ProjectiveIn> = (0..pixels)
        .map(|_| ProjectiveIn {
            s: rng.random_range(0..4 * one),
            t: rng.random_range(0..4 * one),
            q: rng.random_range(one..8 * one),
        })
        .collect();
    trace_unit(&u, (), &inputs, w)
}
