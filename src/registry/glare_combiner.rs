//! `glare_combiner`: the framebuffer plus the glare luminance, saturating.

use super::unit_entry::{seeded, trace_unit, UnitEntry};
use rand::Rng;
use rtl_model::units::glare_combiner::{CombineIn, GlareCombiner};
use rtl_model::{Counters, UnitSummary};
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "glare_combiner",
    summary: || UnitSummary::of(&GlareCombiner::geforce()),
    tables: Vec::new,
    trace,
};

fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let mut rng = seeded(seed);
    let u = GlareCombiner::geforce();
    let c = u.config();
    let (fmax, lmax) = ((1u32 << c.fb_bits) - 1, (1u32 << c.lum_bits) - 1);
    let inputs: Vec<CombineIn> = (0..pixels)
        .map(|_| CombineIn {
            fb: std::array::from_fn(|_| rng.random_range(0..=fmax)),
            // Mostly small luminance, sometimes enough to saturate.
            lum: std::array::from_fn(|_| rng.random_range(0..=lmax) >> 4),
        })
        .collect();
    trace_unit(&u, (), &inputs, w)
}
