//! specular_lookup's vectors (`rtl_model/verilog/units/specular_lookup.v`): the DOT3
//! word → T(x·N/M), nearest or linear, with the table read through two `rtl_rom` ports,
//! its even and odd entries (the banks that let linear read T_i0 and T_i0+1 on one
//! clock). The table is seeded random codes (every entry matters), loaded with
//! `SpecularLookup::load_table` as the host would.
//!
//! Default: the registry's GeForce unit (unsigned 8-bit DOT3 code, 256 × 8-bit table,
//! linear with 8-bit weights; m = k, so the position is the code and the weight is 0):
//! 256 words, exhaustive. Narrow: a signed 10-bit register-combiner word (m = 9), a
//! 32 × 5-bit table, linear with 3-bit weights: the position multiplier by
//! C = round(31·2^12/511) = 248 and its rounding, every weight of the lerp, and the
//! negative words clamped to 0; 1 024 words, exhaustive. Nearest filtering, m < k and
//! other widths run in tests/rtl_specular_lookup.rs (Icarus, [`vectors_of`]).

use super::super::unit_entry::seeded;
use super::vector_set::{collect, RomPort, RtlConfig, VectorSet};
use rand::Rng;
use rtl_model::units::specular_lookup::{SpecularLookupConfig, SpecularLookupIn};
use rtl_model::units::texture_sampler::Filter;

/// The configuration of the harness's default or narrow set.
pub fn config_of(config: RtlConfig) -> SpecularLookupConfig {
    match config {
        RtlConfig::Default => SpecularLookupConfig::geforce(),
        RtlConfig::Narrow => SpecularLookupConfig {
            table_log2: 5,
            entry_bits: 5,
            in_bits: 10,
            signed_input: true,
            filter: Filter::Linear,
            weight_bits: 3,
            exponent: 8.0,
        },
    }
}

/// The vectors of any configuration: `random_table` loads seeded random codes (else
/// the host's table for `cfg.exponent`). Exhaustive when the word has ≤ 2^20 values.
pub fn vectors_of(
    cfg: SpecularLookupConfig,
    random_table: bool,
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    let mut u = cfg.build().map_err(|e| e.to_string())?;
    if random_table {
        let mut rng = seeded(seed ^ 0x5bec_7ab1e);
        let max = (1u64 << cfg.entry_bits) - 1;
        let words: Vec<u64> = (0..1u64 << cfg.table_log2)
            .map(|_| rng.random_range(0..=max))
            .collect();
        u.load_table(&words).map_err(|e| e.to_string())?;
    }
    let n = cfg.in_bits;
    let signed = cfg.signed_input;
    // The wire value as the model's input word (sign-extended when signed).
    let make = move |v: &[u64]| SpecularLookupIn {
        code: if signed {
            ((v[0] << (64 - n)) as i64 >> (64 - n)) as i32
        } else {
            v[0] as i32
        },
    };
    let params = vec![
        ("IN_BITS", n as u64),
        ("SIGNED", u64::from(signed)),
        ("TABLE_LOG2", cfg.table_log2 as u64),
        ("ENTRY_BITS", cfg.entry_bits as u64),
        ("WEIGHT_BITS", cfg.weight_bits as u64),
        ("LINEAR", u64::from(cfg.filter == Filter::Linear)),
        ("POS_SCALE", u.position_scale()),
    ];
    let mut v = collect(
        &u,
        (),
        config,
        SpecularLookupIn::default(),
        make,
        params,
        count,
        seed,
    );
    let words = u.table_words();
    let bank = |parity: usize| -> Vec<u64> {
        words
            .iter()
            .enumerate()
            .filter(|(j, _)| j % 2 == parity)
            .map(|(_, &w)| w)
            .collect()
    };
    v.roms = vec![
        RomPort {
            name: "even",
            ports: 1,
            width: cfg.entry_bits,
            words: bank(0),
        },
        RomPort {
            name: "odd",
            ports: 1,
            width: cfg.entry_bits,
            words: bank(1),
        },
    ];
    Ok(v)
}

pub(super) fn specular_lookup_vectors(
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    vectors_of(config_of(config), true, config, count, seed)
}
