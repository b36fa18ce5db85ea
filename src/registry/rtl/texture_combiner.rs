//! texture_combiner's vectors: the stage's texture-environment state is the Verilog
//! module's parameters (rtl_model/verilog/units/texture_combiner.v), so each
//! configuration is one set of vectors. The Verilog implements the GeforceInteger
//! rounding (every function, source, operand and scale); MesaFloat32's binary32
//! ADD_SIGNED path is not built.

use super::vector_set::{collect, RtlConfig, VectorSet, VerilogParams};
use rtl_model::units::texture_combiner::{
    CombineFunction, CombineSource, CombinerRounding, OperandAlpha, OperandRgb,
    TextureCombinerConfig, TextureCombinerIn,
};

/// The configurations: the GeForce default (MODULATE of TEXTURE, PREVIOUS at 8 bits)
/// and a narrow 4-bit stage with DOT3_RGB at RGB_SCALE 2 and an alpha INTERPOLATE at
/// ALPHA_SCALE 4 with ONE_MINUS operands and SRC_ALPHA into RGB.
pub(super) fn config(config: RtlConfig) -> TextureCombinerConfig {
    match config {
        RtlConfig::Default => TextureCombinerConfig::geforce(),
        RtlConfig::Narrow => TextureCombinerConfig {
            bits: 4,
            combine_rgb: CombineFunction::Dot3Rgb,
            combine_alpha: CombineFunction::Interpolate,
            source_rgb: [
                CombineSource::PrimaryColor,
                CombineSource::Texture,
                CombineSource::Constant,
            ],
            operand_rgb: [
                OperandRgb::OneMinusSrcColor,
                OperandRgb::SrcAlpha,
                OperandRgb::SrcColor,
            ],
            source_alpha: [
                CombineSource::Previous,
                CombineSource::Texture,
                CombineSource::Constant,
            ],
            operand_alpha: [
                OperandAlpha::SrcAlpha,
                OperandAlpha::OneMinusSrcAlpha,
                OperandAlpha::OneMinusSrcAlpha,
            ],
            rgb_scale: 2,
            alpha_scale: 4,
            rounding: CombinerRounding::GeforceInteger,
        },
    }
}

/// The position of `x` in `all` (an enum's code in declaration order).
fn pos<T: PartialEq + Copy>(all: &[T], x: T) -> u64 {
    all.iter().position(|&y| y == x).unwrap_or(0) as u64
}

/// The Verilog parameters of a configuration (enums coded in declaration order,
/// argument i of a packed parameter at bits [2i+1:2i], OP_ALPHA's at bit i).
pub(super) fn params(c: &TextureCombinerConfig) -> Result<VerilogParams, String> {
    if c.rounding != CombinerRounding::GeforceInteger {
        return Err(
            "texture_combiner.rounding: the Verilog implements geforce_integer only".into(),
        );
    }
    let f = |x: CombineFunction| pos(&CombineFunction::ALL, x);
    let pack2 = |codes: [u64; 3]| codes[0] | codes[1] << 2 | codes[2] << 4;
    let src = |s: [CombineSource; 3]| pack2(s.map(|x| pos(&CombineSource::ALL, x)));
    let op_rgb = pack2(c.operand_rgb.map(|x| pos(&OperandRgb::ALL, x)));
    let op_alpha = c
        .operand_alpha
        .iter()
        .enumerate()
        .map(|(i, &o)| u64::from(o == OperandAlpha::OneMinusSrcAlpha) << i)
        .sum();
    Ok(vec![
        ("BITS", c.bits as u64),
        ("COMBINE_RGB", f(c.combine_rgb)),
        ("COMBINE_ALPHA", f(c.combine_alpha)),
        ("SRC_RGB", src(c.source_rgb)),
        ("OP_RGB", op_rgb),
        ("SRC_ALPHA", src(c.source_alpha)),
        ("OP_ALPHA", op_alpha),
        ("RGB_SCALE", c.rgb_scale as u64),
        ("ALPHA_SCALE", c.alpha_scale as u64),
    ])
}

/// The vectors of one texture-environment configuration (the harness's default and
/// narrow ones, or any other: tests/rtl_texture_combiner.rs sweeps the functions).
pub fn vectors_of(
    cfg: TextureCombinerConfig,
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    let u = cfg.build().map_err(|e| e.to_string())?;
    let params = params(&cfg)?;
    let make = |v: &[u64]| {
        let rgba = |k: usize| std::array::from_fn(|c| v[4 * k + c] as u32);
        TextureCombinerIn {
            texture: rgba(0),
            constant: rgba(1),
            primary_color: rgba(2),
            previous: rgba(3),
        }
    };
    Ok(collect(
        &u,
        (),
        config,
        TextureCombinerIn::default(),
        make,
        params,
        count,
        seed,
    ))
}

pub(super) fn texture_combiner_vectors(
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    vectors_of(self::config(config), config, count, seed)
}
