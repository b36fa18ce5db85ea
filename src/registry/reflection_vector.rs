//! `reflection_vector`: the environment map's reflected-ray texture coordinates, with
//! an rsqrt ROM for the normalisations.

use super::unit_entry::{seeded, trace_unit, UnitEntry};
use crate::tables::Table;
use rand::Rng;
use rtl_model::units::reflection_vector::{ReflectionVector, ReflectionVectorIn};
use rtl_model::{Counters, UnitSummary};
use std::collections::BTreeMap;
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "reflection_vector",
    summary: || UnitSummary::of(&ReflectionVector::geforce3()),
    tables,
    trace,
};

/// The rsqrt seed ROM (two copies in hardware: n and e in parallel).
fn tables() -> Vec<Table> {
    let refl = ReflectionVector::geforce3();
    let c = refl.config();
    vec![Table {
        name: format!(
            "reflection_vector_rsqrt_{}x{}",
            1u32 << c.rsqrt_addr_bits,
            c.rsqrt_bits
        ),
        width: c.rsqrt_bits,
        words: refl.rom_words(),
        unit: "reflection_vector".into(),
        params: BTreeMap::from([
            ("addr_bits".to_string(), c.rsqrt_addr_bits.to_string()),
            ("entry_bits".to_string(), c.rsqrt_bits.to_string()),
            (
                "generator".to_string(),
                "rsqrt_rom_entry(j): min(round(2^R / sqrt(c)), 2^R - 1), u0.R, c the midpoint of address j's interval of the mantissa m in [1, 4) (top address bit: [1, 2) or [2, 4)); rtl_model/src/units/reflection_vector.rs".to_string(),
            ),
            ("copies".to_string(), "2 (n and e in parallel)".to_string()),
        ]),
    }]
}

fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let mut rng = seeded(seed);
    let u = ReflectionVector::geforce3();
    let c = u.config();
    // n, e over ±4 units (grazing and back-facing included), λ over [0, 1].
    let lim = 4i64 << c.in_frac_bits;
    let inputs: Vec<ReflectionVectorIn> = (0..pixels)
        .map(|_| {
            let n = [(); 3].map(|_| rng.random_range(-lim..=lim));
            let e = [(); 3].map(|_| rng.random_range(-lim..=lim));
            let lambda = rng.random_range(0..=1u32 << c.lambda_bits);
            ReflectionVectorIn { n, e, lambda }
        })
        .collect();
    trace_unit(&u, (), &inputs, w)
}
