//! `register_combiner`: one general combiner stage of NV_register_combiners.

use super::unit_entry::{seeded, trace_unit, UnitEntry};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rtl_model::units::register_combiner::{RegisterCombiner, RegisterFile};
use rtl_model::{Counters, UnitSummary};
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "register_combiner",
    summary: || UnitSummary::of(&RegisterCombiner::geforce()),
    tables: Vec::new,
    trace,
};

/// `pixels` register sets as COMBINER0 sees them: random 8-bit fragment colours
/// loaded into the 9-bit registers, SPARE0/1 anywhere in [−1, 1]. The final combiner
/// reads the same register file.
pub fn random_register_files(rng: &mut ChaCha8Rng, pixels: usize) -> Vec<RegisterFile> {
    let s = RegisterCombiner::geforce().one() as i32;
    (0..pixels)
        .map(|_| {
            let mut f = RegisterFile::default();
            for (k, reg) in f.regs.iter_mut().enumerate().skip(1) {
                let lo = if (6..8).contains(&k) { -s } else { 0 };
                *reg = std::array::from_fn(|_| rng.random_range(lo..=s));
            }
            f
        })
        .collect()
}

fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let inputs = random_register_files(&mut seeded(seed), pixels);
    trace_unit(&RegisterCombiner::geforce(), (), &inputs, w)
}
