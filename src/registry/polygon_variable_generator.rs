//! `polygon_variable_generator`: a glare primitive's quad from its centre, extent and
//! angle, through a quarter-wave cosine ROM.

use super::unit_entry::{params, rom, seeded, trace_unit, UnitEntry};
use crate::tables::Table;
use rand::Rng;
use rtl_model::units::polygon_variable_generator::{PolygonVariableGenerator, PrimKind, PvgIn};
use rtl_model::{Counters, UnitSummary};
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "polygon_variable_generator",
    summary: || UnitSummary::of(&PolygonVariableGenerator::geforce()),
    tables,
    trace,
};

/// The quarter-wave cosine ROM.
fn tables() -> Vec<Table> {
    let pvg = PolygonVariableGenerator::geforce();
    let c = pvg.config();
    vec![rom(
        format!(
            "polygon_variable_generator_cos_k{}_b{}",
            c.trig_log2, c.trig_bits
        ),
        c.trig_bits,
        pvg.rom_words(),
        "polygon_variable_generator",
        params(&[
            ("trig_log2", c.trig_log2.to_string()),
            ("trig_bits", c.trig_bits.to_string()),
            (
                "generator",
                "entry[j] = round(cos(j/2^k * pi/2) * (2^B - 1)), j = 0 ..= 2^k, unorm B; \
                 sin is read at entry[2^k - j], the quadrant folds signs"
                    .into(),
            ),
        ]),
    )]
}

fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let mut rng = seeded(seed);
    let u = PolygonVariableGenerator::geforce();
    let c = u.config();
    // Centres within ±1/4 of the position range, extents up to 1/16 of it.
    let span = 1i64 << (c.coord_int_bits + c.subpixel_bits - 3);
    let inputs: Vec<PvgIn> = (0..pixels)
        .map(|_| PvgIn {
            kind: if rng.random::<bool>() {
                PrimKind::Line
            } else {
                PrimKind::Area
            },
            cx: rng.random_range(-span..span),
            cy: rng.random_range(-span..span),
            extent: rng.random_range(0..span as u64 / 2),
            half_width: rng.random_range(0..span as u64 / 32),
            angle: rng.random_range(0..1u32 << c.angle_bits),
        })
        .collect();
    trace_unit(&u, (), &inputs, w)
}
