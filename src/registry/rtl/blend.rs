//! blend's vectors: the pixel (src and dst RGBA) is the input word; the blend state
//! (equation, factors, constant colour, rounding) is the Verilog module's parameters.
//! The default set is the classic alpha blend (SRC_ALPHA, ONE_MINUS_SRC_ALPHA, ADD) at
//! 8 bits; the narrow one a 2-bit REVERSE_SUBTRACT with SRC_ALPHA_SATURATE and
//! ONE_MINUS_CONSTANT_COLOR, exhaustive (16-bit input word). tests/rtl_blend.rs sweeps
//! every equation and factor through [`vectors_of`]. [`blend_mode_sets`] adds the
//! additive datapath (the pipelines' blends): unweighted and weighted, widening and
//! narrowing the source.

use super::vector_set::{collect, RtlConfig, VectorSet};
use rtl_model::units::blend::{
    Blend, BlendConfig, BlendDatapath, BlendEquation, BlendFactor, BlendIn, BlendRounding,
};

/// The Verilog parameters of a blend state.
fn params(u: &Blend) -> Vec<(&'static str, u64)> {
    let cfg = u.config();
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
        (
            "DATAPATH",
            match cfg.datapath {
                BlendDatapath::Programmable => 0,
                BlendDatapath::Additive => 1,
            },
        ),
        ("SRC_BITS", u.src_bits() as u64),
        ("CONST_BITS", u.constant_bits() as u64),
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
    if u.datapath() == BlendDatapath::Programmable && u.constant_bits() != u.bits() {
        return Err(
            "blend.constant_bits: the programmable Verilog holds the constant at \
                    blend.bits"
                .into(),
        );
    }
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
        params(&u),
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

/// The additive datapath's sets, each tagged `blend_<config>_<mode>`: the pipelines'
/// 8-bit GL_ONE blend and the J buffer's 8-bit weighted one (random and corners), and
/// narrow ones, exhaustive (16-bit input words): a 1-bit source widened into 3 bits and
/// a 3-bit source narrowed into 1 bit, each unweighted and weighted (a 2-bit, a 3-bit
/// weight).
pub fn blend_mode_sets(count: usize, seed: u64) -> Result<Vec<VectorSet>, String> {
    let additive = |s, f, weighted, k, w: u32| -> Result<BlendConfig, String> {
        let u = Blend::additive(s, f, weighted, k).map_err(|e| e.to_string())?;
        Ok(u.with_weight(w).config())
    };
    let modes = [
        ("additive", RtlConfig::Default, additive(8, 8, false, 8, 0)?),
        (
            "additive_weighted",
            RtlConfig::Default,
            additive(8, 8, true, 8, 0x55)?,
        ),
        ("additive", RtlConfig::Narrow, additive(1, 3, false, 8, 0)?),
        (
            "additive_widen_weighted",
            RtlConfig::Narrow,
            additive(1, 3, true, 2, 2)?,
        ),
        (
            "additive_narrow",
            RtlConfig::Narrow,
            additive(3, 1, false, 8, 0)?,
        ),
        (
            "additive_narrow_weighted",
            RtlConfig::Narrow,
            additive(3, 1, true, 3, 5)?,
        ),
    ];
    modes
        .into_iter()
        .map(|(name, config, cfg)| {
            let mut v = vectors_of(cfg, config, count, seed)?;
            v.variant = Some(name.to_string());
            Ok(v)
        })
        .collect()
}
