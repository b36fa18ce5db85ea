//! The specular exponent by repeated squaring in the register combiners — the
//! GeForce 256/2/3 way to get (n·h)^s without a lookup texture, and the source of the
//! era's well-known banded highlights.
//!
//! Chain (all on the `register_combiner` and `final_combiner` units at one internal
//! width N):
//! - stage 0 (DOT3): TEXTURE0 = n and TEXTURE1 = h as unorm8 vectors (a normal map and
//!   a normalisation cube map), A = TEXTURE0 and B = TEXTURE1 under EXPAND_NORMAL_NV,
//!   AB_DOT_PRODUCT → SPARE0 (RGB): n·h as a signed register code, clamped to [−1, 1];
//! - stages 1 … k: A = B = SPARE0 under UNSIGNED_IDENTITY_NV (so a back-facing
//!   n·h < 0 squares to 0), A·B → SPARE0: after k stages (n·h)^(2^k), each stage
//!   rounded to the register precision;
//! - the final combiner: D = SPARE0 (A = B = C = ZERO), fcoc = SPARE0 as unorm8.
//!
//! A GeForce2 has 2 general combiners and a GeForce3 8, so one pass reaches k = 1 and
//! k = 7 respectively (the dot product takes a stage); the function takes any k and
//! leaves the pass count to the caller.

use rtl_model::chip_preset::ChipPreset;
use rtl_model::error::check_range;
use rtl_model::units::final_combiner::{FinalCombiner, FinalCombinerConfig, FinalVariable};
use rtl_model::units::register_combiner::{
    Bias, ComponentUsage, Mapping, PortionConfig, Register, RegisterCombiner,
    RegisterCombinerConfig, RegisterFile, Scale, VariableInput,
};
use rtl_model::{ConfigError, Counters, Unit};

/// The three configured units of the chain at one internal width.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SquaringChain {
    /// Stage 0: n·h by the expand-normal dot product into SPARE0.
    pub dot_stage: RegisterCombiner,
    /// Stages 1 … k: SPARE0 ← SPARE0 · SPARE0.
    pub square_stage: RegisterCombiner,
    /// SPARE0's red as the unorm8 fragment colour.
    pub final_stage: FinalCombiner,
}

/// An RGB portion writing A·B (or A•B) to SPARE0 and nothing else.
fn ab_to_spare0(a: VariableInput, b: VariableInput, dot: bool) -> PortionConfig {
    let zero = VariableInput::new(
        Register::Zero,
        Mapping::UnsignedIdentity,
        ComponentUsage::Rgb,
    );
    PortionConfig {
        a,
        b,
        c: zero,
        d: zero,
        ab_output: Some(Register::Spare0),
        cd_output: None,
        sum_output: None,
        scale: Scale::None,
        bias: Bias::None,
        ab_dot_product: dot,
        cd_dot_product: false,
        mux_sum: false,
    }
}

impl SquaringChain {
    /// The chain at internal width `internal_bits` (3 ..= 24; 9 on GeForce 256/2),
    /// 8-bit inputs and output, the units' default rounding, the GeForce2's modes.
    /// Errors name `register_combiner.internal_bits` / `final_combiner.internal_bits`.
    pub fn new(internal_bits: u32) -> Result<Self, ConfigError> {
        Self::on_chip(internal_bits, ChipPreset::GeForce2)
    }

    /// [`SquaringChain::new`] with `chip`'s modes of the register and final combiners
    /// (the chip preset: on the NV2A, the bias constant and the mux select). The chain
    /// neither biases nor muxes, so its output is the same on both chips.
    pub fn on_chip(internal_bits: u32, chip: ChipPreset) -> Result<Self, ConfigError> {
        let rgb = |r| VariableInput::new(r, Mapping::ExpandNormal, ComponentUsage::Rgb);
        let spare0 = VariableInput::new(
            Register::Spare0,
            Mapping::UnsignedIdentity,
            ComponentUsage::Rgb,
        );
        let base = chip.register_combiner(RegisterCombinerConfig {
            internal_bits,
            input_bits: 8,
            alpha: PortionConfig::discard(ComponentUsage::Alpha),
            ..RegisterCombinerConfig::geforce()
        });
        let dot_stage = RegisterCombinerConfig {
            rgb: ab_to_spare0(rgb(Register::Texture0), rgb(Register::Texture1), true),
            ..base
        }
        .build()?;
        let square_stage = RegisterCombinerConfig {
            rgb: ab_to_spare0(spare0, spare0, false),
            ..base
        }
        .build()?;
        let zero = FinalVariable::register(Register::Zero, ComponentUsage::Rgb);
        let final_stage = chip
            .final_combiner(FinalCombinerConfig {
                internal_bits,
                out_bits: 8,
                a: zero,
                b: zero,
                c: zero,
                d: FinalVariable::register(Register::Spare0, ComponentUsage::Rgb),
                e: zero,
                f: zero,
                g: FinalVariable::register(Register::Zero, ComponentUsage::Alpha),
                ..FinalCombinerConfig::geforce()
            })
            .build()?;
        Ok(SquaringChain {
            dot_stage,
            square_stage,
            final_stage,
        })
    }

    /// S: the register code of 1.0 at this width.
    pub fn one(&self) -> i32 {
        self.dot_stage.one() as i32
    }

    /// Stage 0: n·h as a register code from two unorm8 vectors (component c stands for
    /// 2c/255 − 1), through the DOT3 stage; clamped to [−S, S].
    pub fn n_dot_h(&self, n: [u8; 3], h: [u8; 3], ctr: &mut Counters) -> i32 {
        let mut file = RegisterFile::default();
        let load = |v: [u8; 3], ctr: &mut Counters| {
            let c = v.map(|x| self.dot_stage.load_unorm(x as u32, ctr));
            [c[0], c[1], c[2], 0]
        };
        file.set(Register::Texture0, load(n, ctr));
        file.set(Register::Texture1, load(h, ctr));
        self.dot_stage
            .kernel(&mut (), &file, ctr)
            .get(Register::Spare0)[0]
    }

    /// Stages 1 … k and the final combiner on an n·h register code (masked to the
    /// register's N wires): (n·h)^(2^k) as unorm8.
    pub fn power_from_code(&self, n_dot_h: i32, k: u32, ctr: &mut Counters) -> u8 {
        let mut file = RegisterFile::default();
        file.set(Register::Spare0, [n_dot_h, n_dot_h, n_dot_h, 0]);
        for _ in 0..k {
            file = self.square_stage.kernel(&mut (), &file, ctr);
        }
        self.final_stage.kernel(&mut (), &file, ctr)[0] as u8
    }

    /// The whole chain: (n·h)^(2^k) as unorm8.
    pub fn specular(&self, n: [u8; 3], h: [u8; 3], k: u32, ctr: &mut Counters) -> u8 {
        let d = self.n_dot_h(n, h, ctr);
        self.power_from_code(d, k, ctr)
    }
}

/// (n·h)^(2^k) by k chained general-combiner squarings at `internal_bits`, from two
/// unorm8 vectors (expand-normal encoding), as unorm8. `k` ≤ 16 (error names
/// `squaring.k`); the width error names the unit's `internal_bits`.
pub fn specular_by_squaring(
    internal_bits: u32,
    n: [u8; 3],
    h: [u8; 3],
    k: u32,
) -> Result<u8, ConfigError> {
    check_range("squaring.k", k as u64, 0, 16)?;
    let chain = SquaringChain::new(internal_bits)?;
    Ok(chain.specular(n, h, k, &mut Counters::default()))
}

/// (c/S)^(2^k) by k chained squarings from an n·h register code c at `internal_bits`,
/// as unorm8 (k ≤ 16, error `squaring.k`).
pub fn power_by_squaring(internal_bits: u32, n_dot_h: i32, k: u32) -> Result<u8, ConfigError> {
    check_range("squaring.k", k as u64, 0, 16)?;
    let chain = SquaringChain::new(internal_bits)?;
    Ok(chain.power_from_code(n_dot_h, k, &mut Counters::default()))
}
