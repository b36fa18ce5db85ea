//! `glare_condition`: whether a specular highlight becomes a glare source (Matsuda and Ikedo, Table 2).

use super::unit_entry::{seeded, trace_unit, UnitEntry};
use rand::Rng;
use rtl_model::units::glare_condition::{ConditionIn, GlareCondition, Material};
use rtl_model::{Counters, UnitSummary};
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "glare_condition",
    summary: || UnitSummary::of(&GlareCondition::geforce()),
    tables: Vec::new,
    trace,
};

fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let mut rng = seeded(seed);
    let u = GlareCondition::geforce();
    let c = u.config();
    let iw = c.int_bits + c.frac_bits;
    let one = 1i32 << c.cos_frac_bits;
    let inputs: Vec<ConditionIn> = (0..pixels)
        .map(|_| {
            let intensity = rng.random_range(0..1u32 << iw);
            ConditionIn {
                material: if rng.random::<bool>() {
                    Material::Water
                } else {
                    Material::Metallic
                },
                intensity,
                specular: rng.random_range(0..1u32 << c.coef_bits),
                cos_alpha: rng.random_range(-one / 4..one),
                cos_theta: rng.random_range(-one..one),
                // Around the contrast threshold: I_a ≈ I/T.
                ambient: rng.random_range(0..=intensity / c.threshold.max(1) * 2),
            }
        })
        .collect();
    trace_unit(&u, (), &inputs, w)
}
