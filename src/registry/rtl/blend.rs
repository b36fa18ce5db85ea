//! blend's vectors: the pixel (src and dst RGBA) is the input word; the blend state
//! (equation, factors, constant colour, rounding) is the Verilog module's parameters.
//! The default set is the classic alpha blend (SRC_ALPHA, ONE_MINUS_SRC_ALPHA, ADD) at
//! 8 bits; the narrow one a 2-bit REVERSE_SUBTRACT with SRC_ALPHA_SATURATE and
//! ONE_MINUS_CONSTANT_COLOR, exhaustive (16-bit input word). tests/rtl_blend.rs sweeps
//! every equation and factor through [`vectors_of`].

use super::{collect, RtlConfig, VectorSet};
use rtl_model::units::blend::{BlendConfig, BlendEquation, BlendFactor, BlendIn, BlendRounding};

/// The Verilog parameters of a blend state.
fn params(cfg: &BlendConfig) -> Vec<(&'static str, u64)> {
    vec![
        ("BITS", cfg.bits as u64),
        ("EQUATION", cfg.equation.code() as u64),
        ("SRC_FACTOR", cfg.src_factor.code() as u64),
        ("DST_FACTOR", cfg.dst_factor.code() as u64),
        ("CONST_R", cfg.constant[0] as u64),
        ("CONST_G", cfg.constant[1] as u64),
        ("CONST_B", cfg.constant[2] as u64),
        ("CONST_A", cfg.constant[3] as u64),
        (
            "ROUNDING",
            match cfg.rounding {
                BlendRounding::Once => 0,
                BlendRounding::PerTerm => 1,
            },
        ),
    ]
}

/// Vectors of the blend in state `cfg` (exhaustive when 8·bits ≤ 20).
pub fn vectors_of(
    cfg: BlendConfig,
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    let u = cfg.build().map_err(|e| e.to_string())?;
    let make = |v: &[u64]| BlendIn {
        src: std::array::from_fn(|c| v[c] as u32),
        dst: std::array::from_fn(|c| v[4 + c] as u32),
    };
    Ok(collect(
        &u,
        (),
        config,
        BlendIn::default(),
        make,
        params(&cfg),
        count,
        seed,
    ))
}

pub(super) fn blend_vectors(
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    let cfg = match config {
        RtlConfig::Default => BlendConfig {
            src_factor: BlendFactor::SrcAlpha,
            dst_factor: BlendFactor::OneMinusSrcAlpha,
            ..BlendConfig::default()
        },
        RtlConfig::Narrow => BlendConfig {
            bits: 2,
            equation: BlendEquation::ReverseSubtract,
            src_factor: BlendFactor::SrcAlphaSaturate,
            dst_factor: BlendFactor::OneMinusConstantColor,
            constant: [1, 2, 3, 0],
            rounding: BlendRounding::Once,
            ..BlendConfig::default()
        },
    };
    vectors_of(cfg, config, count, seed)
}
