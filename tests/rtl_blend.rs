//! blend's Verilog over every equation and every factor, not only the two
//! configurations tests/rtl_cosim.rs runs: each equation in both roundings with the
//! factors rotating, then each factor as source and as destination factor, 3-bit
//! channels with a non-trivial constant colour, under Icarus (one compile per state,
//! the state being module parameters), bit- and cycle-exact against the model's
//! vectors; and the additive datapath's sets. Skips with a printed note without
//! `iverilog`.

mod common;

use common::icarus;
use glare_pipeline::registry::rtl::{blend_vectors_of, RtlConfig};
use rtl_model::units::blend::{BlendConfig, BlendEquation, BlendFactor, BlendRounding};
use std::path::Path;

/// Transactions per state (random and corners: the input word is 24 bits).
const COUNT: usize = 4_000;

/// Every state of the sweep.
fn states() -> Vec<BlendConfig> {
    let f = |i: usize| BlendFactor::ALL[i % BlendFactor::ALL.len()];
    let base = BlendConfig {
        bits: 3,
        constant: [2, 5, 7, 3],
        ..BlendConfig::default()
    };
    let mut v = Vec::new();
    for (i, &equation) in BlendEquation::ALL.iter().enumerate() {
        for rounding in [BlendRounding::Once, BlendRounding::PerTerm] {
            v.push(BlendConfig {
                equation,
                src_factor: f(2 * i + 4),
                dst_factor: f(3 * i + 5),
                rounding,
                ..base
            });
        }
    }
    for (i, &factor) in BlendFactor::ALL.iter().enumerate() {
        let eq = [
            BlendEquation::Add,
            BlendEquation::Subtract,
            BlendEquation::ReverseSubtract,
        ];
        v.push(BlendConfig {
            equation: eq[i % 3],
            src_factor: factor,
            dst_factor: f(i + 7),
            ..base
        });
        v.push(BlendConfig {
            equation: eq[(i + 1) % 3],
            src_factor: f(i + 3),
            dst_factor: factor,
            ..base
        });
    }
    v
}

#[test]
fn icarus_runs_every_equation_and_factor_bit_and_cycle_exact() {
    if !icarus::have_iverilog() {
        common::tools::skip(
            "iverilog not found; the blend state sweep did not run (apt-get install iverilog)",
        );
        return;
    }
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("rtl_blend");
    let mut failed = Vec::new();
    let all = states();
    assert_eq!(all.len(), 7 * 2 + 15 * 2);
    for (i, cfg) in all.iter().enumerate() {
        let v = blend_vectors_of(*cfg, RtlConfig::Narrow, COUNT, 11 + i as u64).unwrap();
        assert_eq!(v.stimulus.len(), COUNT);
        let line = icarus::run_set(&v, &work.join(format!("s{i}")), &["units/blend.v"]);
        if !line.ends_with(&icarus::clean_tail(COUNT)) {
            failed.push(format!("{cfg:?}: {line}"));
        }
    }
    assert!(failed.is_empty(), "mismatches:\n{}", failed.join("\n"));
}

/// The 8-bit default state, seeded random pixels: the hardware's width under Icarus.
#[test]
fn icarus_runs_the_8_bit_alpha_blend_bit_and_cycle_exact() {
    if !icarus::have_iverilog() {
        common::tools::skip(
            "iverilog not found; the 8-bit blend did not run (apt-get install iverilog)",
        );
        return;
    }
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("rtl_blend_8");
    for (i, equation) in BlendEquation::ALL.into_iter().enumerate() {
        let cfg = BlendConfig {
            equation,
            src_factor: BlendFactor::SrcAlpha,
            dst_factor: BlendFactor::OneMinusSrcAlpha,
            constant: [0x55; 4],
            ..BlendConfig::default()
        };
        let v = blend_vectors_of(cfg, RtlConfig::Default, COUNT, 3).unwrap();
        let line = icarus::run_set(&v, &work.join(format!("e{i}")), &["units/blend.v"]);
        assert!(
            line.ends_with(&icarus::clean_tail(COUNT)),
            "{equation:?}: {line}"
        );
    }
}

/// The additive datapath (`DATAPATH = 1`, the pipelines' blends): every set of
/// `blend_mode_sets` — 8-bit GL_ONE and weighted, and the narrow widening and
/// narrowing ones, exhaustive — under Icarus, bit- and cycle-exact (latency 3).
#[test]
fn icarus_runs_the_additive_datapath_bit_and_cycle_exact() {
    if !icarus::have_iverilog() {
        common::tools::skip(
            "iverilog not found; the additive blend did not run (apt-get install iverilog)",
        );
        return;
    }
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("rtl_blend_additive");
    let sets = glare_pipeline::registry::rtl::blend_mode_sets(COUNT, 5).unwrap();
    assert_eq!(sets.len(), 6);
    for v in &sets {
        let n = v.stimulus.len();
        let line = icarus::run_set(v, &work.join(v.tag()), &["units/blend.v"]);
        assert!(
            line.ends_with(&icarus::clean_tail(n)),
            "{}: {line}",
            v.tag()
        );
    }
}
