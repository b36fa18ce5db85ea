//! `additive_blend`: the saturating (GL_ONE, GL_ONE) framebuffer blend.

use super::{seeded, trace_unit, UnitEntry};
use rand::Rng;
use rtl_model::units::additive_blend::{AdditiveBlend, AdditiveBlendIn};
use rtl_model::{Counters, UnitSummary};
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "additive_blend",
    summary: || UnitSummary::of(&AdditiveBlend::geforce()),
    tables: Vec::new,
    trace,
};

fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let mut rng = seeded(seed);
    let u = AdditiveBlend::geforce();
    let mut px = || std::array::from_fn(|_| rng.random_range(0..=255u32));
    let inputs: Vec<AdditiveBlendIn> = (0..pixels)
        .map(|_| AdditiveBlendIn {
            src: px(),
            dst: px(),
            weight: 255,
        })
        .collect();
    trace_unit(&u, (), &inputs, w)
}
