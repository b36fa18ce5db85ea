//! final_combiner's vectors. The Verilog (rtl_model/verilog/units/final_combiner.v)
//! takes the final-combiner state (variables A .. G, rounding, colour-sum clamp) as
//! parameters: one configuration per set of vectors.

use super::register_combiner::register_file_of;
use super::vector_set::{collect, RtlConfig, VectorSet, VerilogParams};
use rtl_model::fixed_point::Quant;
use rtl_model::units::final_combiner::{FinalCombinerConfig, FinalInput, FinalVariable};
use rtl_model::units::register_combiner::{ComponentUsage, Mapping, Register, RegisterFile};

/// The GeForce default (the fog blend A = fog alpha, B = SPARE0 + SECONDARY, C = fog,
/// G = SPARE0 alpha; N 9, out 8, RND), and a narrow one (N 4, out 3, RND_CONV, colour
/// sum clamped) reading E_TIMES_F, both inverting mappings and BLUE on G, in the NV2A
/// modes (both add-invert flags, the final combiner's own constants read by F).
fn config(config: RtlConfig) -> FinalCombinerConfig {
    match config {
        RtlConfig::Default => FinalCombinerConfig::geforce(),
        RtlConfig::Narrow => {
            use ComponentUsage::{Alpha, Blue, Rgb};
            use Mapping::{UnsignedIdentity as Id, UnsignedInvert as Inv};
            let reg = |r, m, u| FinalVariable::new(FinalInput::Register(r), m, u);
            FinalCombinerConfig {
                internal_bits: 4,
                out_bits: 3,
                rounding: Quant::RndConv,
                color_sum_clamp: true,
                a: reg(Register::Texture0, Inv, Rgb),
                b: FinalVariable::new(FinalInput::ETimesF, Id, Rgb),
                c: FinalVariable::new(FinalInput::Spare0PlusSecondaryColor, Inv, Rgb),
                d: reg(Register::PrimaryColor, Id, Alpha),
                e: reg(Register::Texture1, Id, Rgb),
                f: reg(Register::ConstantColor1, Inv, Alpha),
                g: reg(Register::Texture2, Inv, Blue),
                // The NV2A modes (the default configuration keeps the GeForce's).
                specular_add_invert_r0: true,
                specular_add_invert_v1: true,
                constants: Some([[3, 7, 0, 5], [6, 1, 4, 2]]),
            }
        }
    }
}

fn params(c: &FinalCombinerConfig) -> VerilogParams {
    let mut p = vec![
        ("N", c.internal_bits as u64),
        ("OUT_BITS", c.out_bits as u64),
        ("ROUNDING", super::vector_set::quant_code(c.rounding)),
        ("COLOR_SUM_CLAMP", u64::from(c.color_sum_clamp)),
        ("INVERT_R0", u64::from(c.specular_add_invert_r0)),
        ("INVERT_V1", u64::from(c.specular_add_invert_v1)),
        ("FINAL_CONST", u64::from(c.constants.is_some())),
    ];
    const NAMES: [&str; 8] = [
        "C0_R", "C0_G", "C0_B", "C0_A", "C1_R", "C1_G", "C1_B", "C1_A",
    ];
    let k = c.constants.unwrap_or_default();
    for (name, v) in NAMES.into_iter().zip(k.iter().flatten()) {
        p.push((name, *v as u64));
    }
    let vars: [(&'static str, &'static str, &'static str, FinalVariable); 7] = [
        ("A_IN", "A_MAP", "A_USE", c.a),
        ("B_IN", "B_MAP", "B_USE", c.b),
        ("C_IN", "C_MAP", "C_USE", c.c),
        ("D_IN", "D_MAP", "D_USE", c.d),
        ("E_IN", "E_MAP", "E_USE", c.e),
        ("F_IN", "F_MAP", "F_USE", c.f),
        ("G_IN", "G_MAP", "G_USE", c.g),
    ];
    for (i, m, u, v) in vars {
        let input = match v.input {
            FinalInput::Register(r) => r.index() as u64,
            FinalInput::ETimesF => 12,
            FinalInput::Spare0PlusSecondaryColor => 13,
        };
        let usage = match v.component_usage {
            ComponentUsage::Rgb => 0,
            ComponentUsage::Alpha => 1,
            ComponentUsage::Blue => 2,
        };
        p.push((i, input));
        p.push((m, u64::from(v.mapping == Mapping::UnsignedInvert)));
        p.push((u, usage));
    }
    p
}

pub(super) fn final_combiner_vectors(
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
