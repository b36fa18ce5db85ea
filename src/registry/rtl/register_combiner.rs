//! register_combiner's vectors. The Verilog (rtl_model/verilog/units/
//! register_combiner.v) takes the general-combiner state (both portions' variables,
//! outputs, scale, bias, dot products, mux; N, G, rounding) as parameters: one
//! configuration per set of vectors. The input and output words are the register set.

use super::vector_set::{collect, RtlConfig, VectorSet, VerilogParams};
use rtl_model::fixed_point::Quant;
use rtl_model::units::register_combiner::{
    Bias, BiasConstant, ComponentUsage, Mapping, MuxSelect, PortionConfig, Register,
    RegisterCombinerConfig, RegisterFile, Scale, VariableInput, REGISTER_COUNT,
};

/// The GeForce default (Table 5's initial state: A·B with B = 1 to SPARE0, N 9, G 0,
/// RND) and a narrow one (N 4, G 2, RND_CONV) with an RGB dot product, every
/// mapping, the −½ bias with ×2, and the alpha portion's mux at ×½, in the NV2A modes
/// (the half-code bias, the LSB mux, both blue-to-alpha writes, per-stage constants).
fn config(config: RtlConfig) -> RegisterCombinerConfig {
    match config {
        RtlConfig::Default => RegisterCombinerConfig::geforce(),
        RtlConfig::Narrow => {
            use ComponentUsage::{Alpha, Blue, Rgb};
            use Mapping::*;
            let v = VariableInput::new;
            RegisterCombinerConfig {
                internal_bits: 4,
                input_bits: 3,
                guard_bits: 2,
                rounding: Quant::RndConv,
                rgb: PortionConfig {
                    a: v(Register::Texture0, ExpandNormal, Rgb),
                    b: v(Register::Texture1, ExpandNegate, Rgb),
                    c: v(Register::PrimaryColor, HalfBiasNegate, Alpha),
                    d: v(Register::Spare1, SignedNegate, Rgb),
                    ab_output: Some(Register::Spare1),
                    cd_output: Some(Register::Texture0),
                    sum_output: Some(Register::Spare0),
                    scale: Scale::ByTwo,
                    bias: Bias::ByNegativeOneHalf,
                    ab_dot_product: true,
                    cd_dot_product: false,
                    mux_sum: false,
                },
                alpha: PortionConfig {
                    a: v(Register::Texture2, SignedIdentity, Blue),
                    b: v(Register::ConstantColor0, UnsignedInvert, Alpha),
                    c: v(Register::SecondaryColor, HalfBiasNormal, Alpha),
                    d: v(Register::Fog, UnsignedIdentity, Blue),
                    ab_output: Some(Register::Texture3),
                    cd_output: Some(Register::PrimaryColor),
                    sum_output: Some(Register::Spare0),
                    scale: Scale::ByOneHalf,
                    bias: Bias::None,
                    ab_dot_product: false,
                    cd_dot_product: false,
                    mux_sum: true,
                },
                // The NV2A modes (the default configuration keeps the GeForce's).
                bias_constant: BiasConstant::HalfCode,
                mux_select: MuxSelect::Lsb,
                ab_blue_to_alpha: true,
                cd_blue_to_alpha: true,
                stage_constants: Some([[7, 0, 5, 3], [1, 6, 2, 4]]),
            }
        }
    }
}

fn portion_params(prefix: &'static str, p: &PortionConfig, out: &mut VerilogParams) {
    // Parameter names are 'static: one table per portion.
    const RGB: [&str; 20] = [
        "RGB_A_IN",
        "RGB_A_MAP",
        "RGB_A_USE",
        "RGB_B_IN",
        "RGB_B_MAP",
        "RGB_B_USE",
        "RGB_C_IN",
        "RGB_C_MAP",
        "RGB_C_USE",
        "RGB_D_IN",
        "RGB_D_MAP",
        "RGB_D_USE",
        "RGB_AB_OUT",
        "RGB_CD_OUT",
        "RGB_SUM_OUT",
        "RGB_SCALE",
        "RGB_BIAS",
        "RGB_AB_DOT",
        "RGB_CD_DOT",
        "RGB_MUX_SUM",
    ];
    const ALPHA: [&str; 20] = [
        "ALPHA_A_IN",
        "ALPHA_A_MAP",
        "ALPHA_A_USE",
        "ALPHA_B_IN",
        "ALPHA_B_MAP",
        "ALPHA_B_USE",
        "ALPHA_C_IN",
        "ALPHA_C_MAP",
        "ALPHA_C_USE",
        "ALPHA_D_IN",
        "ALPHA_D_MAP",
        "ALPHA_D_USE",
        "ALPHA_AB_OUT",
        "ALPHA_CD_OUT",
        "ALPHA_SUM_OUT",
        "ALPHA_SCALE",
        "ALPHA_BIAS",
        "ALPHA_AB_DOT",
        "ALPHA_CD_DOT",
        "ALPHA_MUX_SUM",
    ];
    let names = if prefix == "RGB" { RGB } else { ALPHA };
    let mut vals = Vec::with_capacity(20);
    for v in [p.a, p.b, p.c, p.d] {
        vals.push(v.input.index() as u64);
        vals.push(
            Mapping::ALL
                .iter()
                .position(|&m| m == v.mapping)
                .unwrap_or(0) as u64,
        );
        vals.push(match v.component_usage {
            ComponentUsage::Rgb => 0,
            ComponentUsage::Alpha => 1,
            ComponentUsage::Blue => 2,
        });
    }
    for o in [p.ab_output, p.cd_output, p.sum_output] {
        vals.push(o.map_or(15, |r| r.index() as u64));
    }
    vals.push(Scale::ALL.iter().position(|&s| s == p.scale).unwrap_or(0) as u64);
    vals.push(u64::from(p.bias == Bias::ByNegativeOneHalf));
    vals.push(u64::from(p.ab_dot_product));
    vals.push(u64::from(p.cd_dot_product));
    vals.push(u64::from(p.mux_sum));
    out.extend(names.into_iter().zip(vals));
}

fn params(c: &RegisterCombinerConfig) -> VerilogParams {
    let mut p = vec![
        ("N", c.internal_bits as u64),
        ("G", c.guard_bits as u64),
        ("ROUNDING", super::vector_set::quant_code(c.rounding)),
    ];
    portion_params("RGB", &c.rgb, &mut p);
    portion_params("ALPHA", &c.alpha, &mut p);
    p.push((
        "BIAS_HALF_CODE",
        u64::from(c.bias_constant == BiasConstant::HalfCode),
    ));
    p.push(("MUX_LSB", u64::from(c.mux_select == MuxSelect::Lsb)));
    p.push(("AB_BLUE_TO_ALPHA", u64::from(c.ab_blue_to_alpha)));
    p.push(("CD_BLUE_TO_ALPHA", u64::from(c.cd_blue_to_alpha)));
    p.push(("STAGE_CONST", u64::from(c.stage_constants.is_some())));
    const NAMES: [&str; 8] = [
        "C0_R", "C0_G", "C0_B", "C0_A", "C1_R", "C1_G", "C1_B", "C1_A",
    ];
    let k = c.stage_constants.unwrap_or_default();
    for (name, v) in NAMES.into_iter().zip(k.iter().flatten()) {
        p.push((name, *v as u64));
    }
    p
}

/// The register file of an input word's fields (register i, channel c at 4·i + c):
/// the combiners' input word is their register file.
pub(super) fn register_file_of(v: &[u64]) -> RegisterFile {
    let mut f = RegisterFile::default();
    for (i, reg) in f.regs.iter_mut().enumerate().take(REGISTER_COUNT) {
        for (c, x) in reg.iter_mut().enumerate() {
            *x = v[4 * i + c] as i32;
        }
    }
    f
}

pub(super) fn register_combiner_vectors(
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    let cfg = self::config(config);
    let u = cfg.build().map_err(|e| e.to_string())?;
    Ok(collect(
        &u,
        (),
        config,
        RegisterFile::default(),
        register_file_of,
        params(&cfg),
        count,
        seed,
    ))
}
