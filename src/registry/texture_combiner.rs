//! `texture_combiner`: one texture environment stage of ARB_texture_env_combine/dot3.

use super::unit_entry::{seeded, trace_unit, UnitEntry};
use rand::Rng;
use rtl_model::units::texture_combiner::{TextureCombiner, TextureCombinerIn};
use rtl_model::{Counters, UnitSummary};
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "texture_combiner",
    summary: || UnitSummary::of(&TextureCombiner::geforce()),
    tables: Vec::new,
    trace,
};

/// GL's initial COMBINE state: MODULATE of TEXTURE and PREVIOUS, 8-bit.
fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let mut rng = seeded(seed);
    let u = TextureCombiner::geforce();
    let mut px = || std::array::from_fn(|_| rng.random_range(0..=255u32));
    let inputs: Vec<TextureCombinerIn> = (0..pixels)
        .map(|_| TextureCombinerIn {
            texture: px(),
            constant: px(),
            primary_color: px(),
            previous: px(),
        })
        .collect();
    trace_unit(&u, (), &inputs, w)
}
