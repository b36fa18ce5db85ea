//! `bloom_flare_modulator`: a bloom or flare-line primitive's luminance from its shape
//! and falloff RAMs.

use super::luminance_ram::{falloff_params, random_inputs, shape_params};
use super::unit_entry::{rom, seeded, trace_unit, UnitEntry};
use crate::pipeline::glare::tables::{line_falloff_samples, line_shape_samples};
use crate::tables::Table;
use rtl_model::units::bloom_flare_modulator::{BloomFlareModulator, BloomFlareModulatorConfig};
use rtl_model::units::luminance_ram::LumWidths;
use rtl_model::{Counters, UnitSummary};
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "bloom_flare_modulator",
    summary: || UnitSummary::of(&default_bloom_flare()),
    tables,
    trace,
};

/// The default bloom/flare modulator (`LumWidths::default()`), holding the tables
/// every flare line shares: the spindle shape and the (1 − d)² falloff. (Bloom tables
/// are per source and loaded by the host with each primitive.)
pub fn default_bloom_flare() -> BloomFlareModulator {
    let w = LumWidths::default();
    BloomFlareModulatorConfig::from_widths(w)
        .build(
            &line_shape_samples(w.shape_log2),
            &line_falloff_samples(w.falloff_log2),
        )
        .expect("the default modulator widths and the flare-line tables are valid")
}

/// The flare lines' shared shape and falloff (loaded once per frame). Bloom shape and
/// falloff RAMs depend on each source's outline, size and intensity and are written by
/// the host per primitive: not here.
fn tables() -> Vec<Table> {
    let w = LumWidths::default();
    let bf = default_bloom_flare();
    vec![
        rom(
            format!(
                "bloom_flare_modulator_line_shape_k{}_b{}",
                w.shape_log2, w.shape_bits
            ),
            w.shape_bits,
            bf.shape_codes().iter().map(|&v| u64::from(v)).collect(),
            "bloom_flare_modulator",
            shape_params(
                &w,
                &[
                    (
                        "generator",
                        "flare-line spindle: sample (i, j) at u = -1 + i*2^(1-k), v = -1 + j*2^(1-k), \
                         d = min(1, sqrt(((u+1)/2)^2 + v^2)), code = round(d * (2^sb - 1)) at \
                         [j*(2^k+1) + i]"
                            .into(),
                    ),
                    (
                        "loaded",
                        "once per frame, shared by every flare line".into(),
                    ),
                ],
            ),
        ),
        rom(
            format!(
                "bloom_flare_modulator_line_falloff_m{}_b{}",
                w.falloff_log2, w.falloff_bits
            ),
            w.falloff_bits,
            bf.falloff_codes().iter().map(|&v| u64::from(v)).collect(),
            "bloom_flare_modulator",
            falloff_params(
                &w,
                &[
                    (
                        "generator",
                        "flare-line falloff p(d) = (1 - d)^2 at d = j/2^m, j = 0 ..= 2^m, \
                         code = round(p * (2^fb - 1))"
                            .into(),
                    ),
                    (
                        "loaded",
                        "once per frame, shared by every flare line".into(),
                    ),
                ],
            ),
        ),
    ]
}

fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let inputs = random_inputs(&mut seeded(seed), pixels);
    trace_unit(&default_bloom_flare(), (), &inputs, w)
}
