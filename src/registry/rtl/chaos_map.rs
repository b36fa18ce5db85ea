//! chaos_map's vectors: `count` step requests from the reset state
//! `ChaosMap::seeded_state(SEED)` (the Verilog computes the same SplitMix64 states from
//! its `SEED` parameter). The log2 and exp2 ROMs are read ports; a, z, log2 u and the
//! output gain are parameters, as the model quantises them.

use super::stream::request_stream;
use super::vector_set::{RomPort, RtlConfig, VectorSet};
use rtl_model::units::chaos_map::{ChaosMapConfig, Escape, GAIN_EXTRA_BITS};

/// The configuration built at `config`: the GeForce default (4 patches, u0.32,
/// MinStep), or narrow (2 patches, u0.8, T 4, E 8, Z 4, O 4) with the naive escape,
/// so the sticking states (S = 0, an increment that rounds to 0) are exercised.
pub fn config_of(config: RtlConfig) -> ChaosMapConfig {
    match config {
        RtlConfig::Default => ChaosMapConfig::geforce(),
        RtlConfig::Narrow => ChaosMapConfig {
            patches: 2,
            state_bits: 8,
            table_log2: 4,
            table_bits: 8,
            z_frac_bits: 4,
            out_bits: 4,
            escape: Escape::None,
            ..ChaosMapConfig::geforce()
        },
    }
}

pub(super) fn chaos_map_vectors(
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    let cfg = config_of(config);
    let u = cfg.build().map_err(|e| e.to_string())?;
    // The reset seed is a Verilog parameter: keep it below 2^31.
    let state_seed = seed & 0x7fff_ffff;
    let (f, e, zf, o) = (
        cfg.state_bits,
        cfg.table_bits,
        cfg.z_frac_bits,
        cfg.out_bits,
    );
    // The model's constants, by the same expressions (chaos_map.rs, ChaosMap::new).
    let a_q = u.a_code();
    let aqf = a_q as f64 / (f as f64).exp2();
    let log2u = (1.0 - aqf).log2() - cfg.z * aqf.log2();
    let lu = (log2u * ((e + zf) as f64).exp2()).round() as i64;
    let z_q = (u.z_quantised() * (zf as f64).exp2()) as u64;
    let k_out = (u.gain_quantised() * ((o + GAIN_EXTRA_BITS) as f64).exp2()) as u64;
    let params = vec![
        ("PATCHES", cfg.patches as u64),
        ("STATE_BITS", f as u64),
        ("TABLE_LOG2", cfg.table_log2 as u64),
        ("TABLE_BITS", e as u64),
        ("Z_FRAC_BITS", zf as u64),
        ("OUT_BITS", o as u64),
        ("A", a_q),
        ("ZQ", z_q),
        ("LU_MAG", lu.unsigned_abs()),
        ("LU_NEG", u64::from(lu < 0)),
        ("K_OUT", k_out),
        ("ESCAPE", u64::from(cfg.escape == Escape::MinStep)),
        ("SEED", state_seed),
    ];
    let mut v = request_stream(&u, u.seeded_state(state_seed), config, params, count);
    for ((_, _, words), port) in u.rom_images().into_iter().zip(["log2", "exp2"]) {
        v.roms.push(RomPort {
            name: port,
            ports: 2,
            width: e + 1,
            words,
        });
    }
    Ok(v)
}
