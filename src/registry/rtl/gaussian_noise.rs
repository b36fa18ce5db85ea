//! gaussian_noise's vectors: `count` draw requests from the reset state
//! `GaussState::from_seed(SEED)` (the Verilog computes the same SplitMix64 seeding
//! from its `SEED` parameter), Box–Muller mode only (the Verilog does not implement
//! the central-limit mode). The ln, √ and sin ROMs are read ports.

use super::stream::request_stream;
use super::vector_set::{RomPort, RtlConfig, VectorSet};
use rtl_model::units::gaussian_noise::{GaussMode, GaussState, GaussianNoiseConfig};

/// The configuration built at `config`: the GeForce default (B 32, T 10, E 18,
/// s3.12), or narrow (B 8, T 4, E 8, s1.4).
pub fn config_of(config: RtlConfig) -> GaussianNoiseConfig {
    match config {
        RtlConfig::Default => GaussianNoiseConfig::geforce(),
        RtlConfig::Narrow => GaussianNoiseConfig {
            mode: GaussMode::BoxMuller,
            uniform_bits: 8,
            table_log2: 4,
            table_bits: 8,
            out_frac_bits: 4,
            out_int_bits: 1,
        },
    }
}

pub(super) fn gaussian_noise_vectors(
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    let cfg = config_of(config);
    let u = cfg.build().map_err(|e| e.to_string())?;
    // The reset seed is a Verilog parameter: keep it below 2^31 (an unsized literal).
    let state_seed = seed & 0x7fff_ffff;
    let e = cfg.table_bits;
    // The model's ln 2 code, round(ln 2 · 2^(E+8)) (the same expression).
    let ln2 = (std::f64::consts::LN_2 * ((e + 8) as f64).exp2()).round() as u64;
    let params = vec![
        ("UNIFORM_BITS", cfg.uniform_bits as u64),
        ("TABLE_LOG2", cfg.table_log2 as u64),
        ("TABLE_BITS", e as u64),
        ("OUT_FRAC_BITS", cfg.out_frac_bits as u64),
        ("OUT_INT_BITS", cfg.out_int_bits as u64),
        ("LN2", ln2),
        ("SEED", state_seed),
    ];
    let mut v = request_stream(&u, GaussState::from_seed(state_seed), config, params, count);
    let images = u.rom_images();
    for ((name, ports), (_, width, words)) in
        [("ln", 2), ("sqrt", 2), ("sin", 4)].into_iter().zip(images)
    {
        v.roms.push(RomPort {
            name,
            ports,
            width,
            words,
        });
    }
    Ok(v)
}
