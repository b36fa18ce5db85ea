//! texture_combiner's Verilog over every COMBINE function, not only the two
//! configurations tests/rtl_cosim.rs runs: for each COMBINE_RGB function (DOT3 ones
//! included), a 3-bit stage with a COMBINE_ALPHA function, sources, operands and
//! scales rotating through their values, under Icarus (one compile per
//! configuration, the state being module parameters), bit- and cycle-exact against
//! the model's vectors. Skips with a printed note without `iverilog`.

mod common;

use common::icarus;
use glare_pipeline::registry::rtl::{texture_combiner_vectors_of, RtlConfig};
use rtl_model::units::texture_combiner::{
    CombineFunction, CombineSource, CombinerRounding, OperandAlpha, OperandRgb,
    TextureCombinerConfig,
};
use std::path::Path;

/// Transactions per configuration (random and corners: the input word is 48 bits).
const COUNT: usize = 20_000;

/// The i-th configuration of the sweep: COMBINE_RGB = ALL[i], the rest rotating.
fn config(i: usize) -> TextureCombinerConfig {
    let src = |k: usize| CombineSource::ALL[k % 4];
    let scale = [1, 2, 4];
    TextureCombinerConfig {
        bits: 3,
        combine_rgb: CombineFunction::ALL[i],
        combine_alpha: CombineFunction::ALPHA[(i + 3) % CombineFunction::ALPHA.len()],
        source_rgb: [src(i), src(i + 1), src(i + 3)],
        operand_rgb: [
            OperandRgb::ALL[i % 4],
            OperandRgb::ALL[(i + 1) % 4],
            OperandRgb::ALL[(i + 2) % 4],
        ],
        source_alpha: [src(i + 2), src(i + 3), src(i)],
        operand_alpha: [
            OperandAlpha::ALL[i % 2],
            OperandAlpha::ALL[(i / 2) % 2],
            OperandAlpha::ALL[(i + 1) % 2],
        ],
        rgb_scale: scale[i % 3],
        alpha_scale: scale[(i + 1) % 3],
        rounding: CombinerRounding::GeforceInteger,
    }
}

#[test]
fn icarus_runs_every_combine_function_bit_and_cycle_exact() {
    if !icarus::have_iverilog() {
        common::tools::skip(
            "iverilog not found; the texture_combiner function sweep did not run \
             (apt-get install iverilog)",
        );
        return;
    }
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("rtl_texture_combiner");
    let mut failed = Vec::new();
    for i in 0..CombineFunction::ALL.len() {
        let cfg = config(i);
        let v = texture_combiner_vectors_of(cfg, RtlConfig::Narrow, COUNT, 7 + i as u64).unwrap();
        assert_eq!(v.stimulus.len(), COUNT);
        let line = icarus::run_set(
            &v,
            &work.join(format!("f{i}")),
            &["units/texture_combiner.v"],
        );
        println!("{:?}/{:?}: {line}", cfg.combine_rgb, cfg.combine_alpha);
        if !line.ends_with(&icarus::clean_tail(COUNT)) {
            failed.push(format!("{cfg:?}: {line}"));
        }
    }
    assert!(failed.is_empty(), "mismatches:\n{}", failed.join("\n"));
}
