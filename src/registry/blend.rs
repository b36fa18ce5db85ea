//! `blend`: the GL / NV2A framebuffer blend (15 factors, 7 equations, one rounding).

use super::unit_entry::{seeded, trace_unit, UnitEntry};
use rand::Rng;
use rtl_model::units::blend::{Blend, BlendEquation, BlendFactor, BlendIn};
use rtl_model::{Counters, UnitSummary};
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "blend",
    summary: || UnitSummary::of(&Blend::geforce()),
    tables: Vec::new,
    trace,
};

fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let mut rng = seeded(seed);
    // The classic alpha blend (GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA), ADD.
    let u = Blend::with(
        BlendEquation::Add,
        BlendFactor::SrcAlpha,
        BlendFactor::OneMinusSrcAlpha,
    );
    let mut px = || std::array::from_fn(|_| rng.random_range(0..=255u32));
    let inputs: Vec<BlendIn> = (0..pixels)
        .map(|_| BlendIn {
            src: px(),
            dst: px(),
        })
        .collect();
    trace_unit(&u, (), &inputs, w)
}
