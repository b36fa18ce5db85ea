//! specular_lookup's Verilog beyond the two configurations tests/rtl_cosim.rs runs
//! (the GeForce default, where m = k makes every lerp weight 0, and a signed linear
//! narrow one): nearest filtering with m > k, m < k and m = k, linear with m < k,
//! a one-bit magnitude, a two-entry table and the widest words (n = 17 signed,
//! k = 12, b = 16, w = 16), each exhaustive over its input word, under Icarus (one
//! compile per configuration: the filter and widths are module parameters), bit- and
//! cycle-exact against the model's vectors. Skips with a printed note without
//! `iverilog`.

mod common;

use common::icarus;
use glare_pipeline::registry::rtl::{self, specular_lookup_vectors_of, RtlConfig};
use rtl_model::units::specular_lookup::SpecularLookupConfig;
use rtl_model::units::texture_sampler::Filter;
use rtl_model::UnitSummary;
use std::path::Path;

/// (in_bits, signed, table_log2, entry_bits, weight_bits, filter, random table).
type Case = (u32, bool, u32, u32, u32, Filter, bool);

const CASES: &[Case] = &[
    // nearest, m = 6 > k = 4
    (6, false, 4, 4, 2, Filter::Nearest, true),
    // nearest, signed, m = 3 < k = 5 (C = 142)
    (4, true, 5, 6, 2, Filter::Nearest, true),
    // nearest at the GeForce signed widths (m = k = 8), the host's s = 32 table
    (9, true, 8, 8, 8, Filter::Nearest, false),
    // linear, m = 3 < k = 6: every position has a fraction
    (3, false, 6, 7, 5, Filter::Linear, true),
    // linear, a two-entry table (one word per bank), 1-bit weights
    (4, false, 1, 3, 1, Filter::Linear, true),
    // nearest, signed 2-bit word: a 1-bit magnitude (g = 1), 1-bit weights
    (2, true, 2, 3, 1, Filter::Nearest, true),
    // the widest: signed 17-bit word (2^17 words), 4096 × 16-bit table, 16-bit weights
    (17, true, 12, 16, 16, Filter::Linear, true),
];

/// The harness's narrow configuration (src/registry/rtl/specular_lookup.rs).
const HARNESS_NARROW: SpecularLookupConfig = SpecularLookupConfig {
    table_log2: 5,
    entry_bits: 5,
    in_bits: 10,
    signed_input: true,
    filter: Filter::Linear,
    weight_bits: 3,
    exponent: 8.0,
};

#[test]
fn icarus_runs_nearest_and_other_widths_bit_and_cycle_exact() {
    if !icarus::have_iverilog() {
        common::tools::skip(
            "iverilog not found; the specular_lookup configurations did not run \
             (apt-get install iverilog)",
        );
        return;
    }
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("rtl_specular_lookup");
    // The model's cost of the harness's two sets too, by part (docs/units.md's hand
    // synthesis beside Yosys).
    for (c, cfg) in [
        (RtlConfig::Default, SpecularLookupConfig::geforce()),
        (RtlConfig::Narrow, HARNESS_NARROW),
    ] {
        let v = rtl::vectors("specular_lookup", c, 1, 1).unwrap();
        let s = UnitSummary::of(&cfg.build().unwrap());
        assert_eq!(s.gates_nand2, v.gates_model, "{c:?}");
        println!("{}: {:.0} NAND2 model", v.tag(), v.gates_model);
        for (part, g) in &s.breakdown {
            println!("  {part}: {g:.0}");
        }
    }
    let mut failed = Vec::new();
    for (i, &(n, signed, k, b, w, filter, random)) in CASES.iter().enumerate() {
        let cfg = SpecularLookupConfig {
            table_log2: k,
            entry_bits: b,
            in_bits: n,
            signed_input: signed,
            filter,
            weight_bits: w,
            exponent: 32.0,
        };
        let v =
            specular_lookup_vectors_of(cfg, random, RtlConfig::Narrow, 1, 11 + i as u64).unwrap();
        assert!(v.exhaustive, "{cfg:?}");
        assert_eq!(v.stimulus.len(), 1 << n, "{cfg:?}");
        let line = icarus::run_set(
            &v,
            &work.join(format!("c{i}")),
            &["tb/rtl_rom.v", "units/specular_lookup.v"],
        );
        // The model's cost at this configuration, for a hand synthesis (docs/units.md).
        println!("{cfg:?} ({:.0} NAND2 model): {line}", v.gates_model);
        if !line.ends_with(&icarus::clean_tail(v.stimulus.len())) {
            failed.push(format!("{cfg:?}: {line}"));
        }
    }
    assert!(failed.is_empty(), "{failed:#?}");
}
