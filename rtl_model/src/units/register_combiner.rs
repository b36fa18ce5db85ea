//! register_combiner — one GENERAL combiner stage of GL_NV_register_combiners
//! (section 3.8.12.2 of the extension), RGB and alpha portions side by side.
//!
//! Names follow the spec, so the unit can be read against it line by line:
//! registers (Table NV_register_combiners.1) ZERO, CONSTANT_COLOR0/1_NV, FOG,
//! PRIMARY_COLOR_NV, SECONDARY_COLOR_NV, SPARE0/1_NV, TEXTURE0..3_ARB; the input
//! mappings of Table NV_register_combiners.4; the variables A, B, C, D per portion with
//! a component usage (RGB / ALPHA / BLUE); the computations gcc1 … gcc6 (RGB) and
//! gcc1a … gcc4a (alpha); CombinerOutputNV's abOutput / cdOutput / sumOutput, scale,
//! bias, abDotProduct, cdDotProduct and muxSum; out = max(min((gcc + bias)·scale, 1), −1).
//!
//! ## Number format (where the spec leaves it to the implementation)
//! The spec computes on reals in [−1, 1] and says nothing about precision (issue
//! "Should we say anything about the precision …": NO; NV10 uses 9-bit signed fixed
//! point). NV_texture_shader documents that 9-bit type: code c stands for c/255, so
//! 1, 0 and −1 are exact and −256 is −1.0039. Here the width is `internal_bits` = N
//! (9 on GeForce 256/2), S = 2^(N−1) − 1, code c ↔ c/S, register words s(N) (the
//! outputs are clamped to [−S, S]; −S−1 is only seen if an input word carries it).
//!
//! ## Datapath (integers only; W = S·2^G is the working scale, G = `guard_bits`)
//! 0. Load (host edge, [`RegisterCombiner::load_unorm`]): an `input_bits`-bit unorm
//!    code u (U = 2^I − 1) enters a register as round(u·S/U) — exact when N − 1 = I
//!    (GeForce: 8-bit colours in 9-bit registers, c = u).
//! 1. Select: the variable's register component by component usage (ZERO reads 0).
//! 2. Map (Table 4) EXACTLY, in half-LSB units m = 2·S·mapped (s(N+2)): the half bias
//!    −0.5 is S/2 codes, a half-integer because S is odd, so one more fraction bit
//!    holds every mapping of every code without rounding:
//!    UNSIGNED_IDENTITY 2p, UNSIGNED_INVERT 2(S − min(p, S)), EXPAND_NORMAL 2(2p − S),
//!    EXPAND_NEGATE 2(S − 2p), HALF_BIAS_NORMAL 2p − S, HALF_BIAS_NEGATE S − 2p,
//!    SIGNED_IDENTITY 2r, SIGNED_NEGATE −2r, with p = max(0, r).
//! 3. Products m_A·m_B in units 1/(4S²): s(N+2) × s(N+2) → s(2N+2) (|m| ≤ 2^N); a
//!    dot product sums the three lanes' products at full precision → s(2N+3).
//! 4. Product rounding (the spec is silent; chosen: one rounding per product or per
//!    dot product) to the working scale: q = round(p·2^G / (4S)) by `rounding`
//!    (a divide by the constant 4S; ½·2^−G LSB for nearest modes, < 2^−G truncating).
//!    Non-zero products that round to 0 count in `underflows`.
//! 5. gcc5 = q_AB + q_CD (exact), or gcc6 = the mux: SPARE0 alpha of the INPUT
//!    register set ≥ 0.5 → CD, else AB (the spec's corrected sense, August 2000).
//!    With c ↔ c/S and S odd, "≥ 0.5" is exactly c ≥ 2^(N−2): the alpha's top
//!    magnitude bit, as hardware tests it (`mux_select` = Msb). The NV2A tests the
//!    code's LOW bit by default (`mux_select` = Lsb; its combiner control's
//!    MUX_SELECT, nxdk_pgraph_tests Combiner/Mux capture).
//! 6. Scale and bias, then one output rounding: V = (2x − b·W)·k in units 1/(4W)
//!    (b = 1 for BIAS_BY_NEGATIVE_ONE_HALF, k = 2, 4, 8, 1 for NONE, ×2, ×4, ×½;
//!    `bias_constant` = HalfCode makes b = (S + 1)/S: the NV2A subtracts 2^(N−2)
//!    codes, −128/255 at N = 9, as the Combiner/CombinerOps capture shows),
//!    out = round(V / 2^(G+2)) by `rounding` (a shift), clamped to [−S, S]: every
//!    clamp counts in `saturations`, a non-zero V rounded to 0 in `underflows`.
//!    Exact (no rounding) at G = 0 with scale 1, 2 or 4 and no bias.
//! 7. Write: out1/out2/out3 replace the RGB (RGB portion) or alpha (alpha portion)
//!    components of the registers named by abOutput/cdOutput/sumOutput (DISCARD =
//!    `None`); the updated set is the stage's output (the next stage's input).
//!    NV2A only: `ab_blue_to_alpha` / `cd_blue_to_alpha` also write out1's / out2's
//!    blue to the alpha of abOutput's / cdOutput's register (COLOR_OCW bits 19/18).
//!
//! NV2A per-stage constants (`stage_constants`): the stage reads its own
//! CONSTANT_COLOR0/1 instead of the set's; the output set passes the set's on.
//!
//! Config errors (the spec's INVALID_OPERATION / INVALID_VALUE cases) name the field:
//! RGB usage on the alpha portion, BLUE on the RGB portion, FOG with ALPHA usage, a dot
//! product on the alpha portion, the −½ bias with ×4 or ×½, an output to a read-only
//! register, two outputs of one portion to the same register.
//!
//! Timing: latency 3 (select + map | multiply, dot sum | round, sum/mux, scale/bias,
//! clamp, write), II 1.

use crate::cost::{prim, Cells, Cost};
use crate::counters::Counters;
use crate::error::{check_range, ConfigError};
use crate::fixed_point::{round_div, round_shift, Quant};
use crate::unit::{Signal, Timing, Unit, Width};
use crate::wire::sign_extend;
use serde::{Deserialize, Serialize};
use std::borrow::Cow;

/// Table NV_register_combiners.1: 8 + MAX_TEXTURE_UNITS_ARB (4, GeForce3) registers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "SCREAMING_SNAKE_CASE")]
pub enum Register {
    /// ZERO: reads 0, read only.
    Zero,
    /// CONSTANT_COLOR0_NV (ccc0), read only.
    ConstantColor0,
    /// CONSTANT_COLOR1_NV (ccc1), read only.
    ConstantColor1,
    /// FOG: RGB the fog colour, alpha the fog factor (final combiner only); read only.
    Fog,
    /// PRIMARY_COLOR_NV, read/write.
    PrimaryColor,
    /// SECONDARY_COLOR_NV, read/write.
    SecondaryColor,
    /// SPARE0_NV, read/write (its alpha drives the mux).
    Spare0,
    /// SPARE1_NV, read/write.
    Spare1,
    /// TEXTURE0_ARB … TEXTURE3_ARB, read/write.
    Texture0,
    /// TEXTURE1_ARB, read/write.
    Texture1,
    /// TEXTURE2_ARB, read/write.
    Texture2,
    /// TEXTURE3_ARB, read/write.
    Texture3,
}

/// Number of registers in a register set.
pub const REGISTER_COUNT: usize = 12;

impl Register {
    /// Every register in Table 1 order (the order of [`Register::index`]).
    pub const ALL: [Register; REGISTER_COUNT] = [
        Register::Zero,
        Register::ConstantColor0,
        Register::ConstantColor1,
        Register::Fog,
        Register::PrimaryColor,
        Register::SecondaryColor,
        Register::Spare0,
        Register::Spare1,
        Register::Texture0,
        Register::Texture1,
        Register::Texture2,
        Register::Texture3,
    ];

    /// Index into [`RegisterFile::regs`].
    pub fn index(self) -> usize {
        self as usize
    }

    /// Output status "read/write" of Table NV_register_combiners.1.
    pub fn writable(self) -> bool {
        !matches!(
            self,
            Register::Zero | Register::ConstantColor0 | Register::ConstantColor1 | Register::Fog
        )
    }
}

/// Table NV_register_combiners.4: the input range mappings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "SCREAMING_SNAKE_CASE")]
pub enum Mapping {
    /// max(0, e)
    UnsignedIdentity,
    /// 1 − min(max(e, 0), 1)
    UnsignedInvert,
    /// 2·max(0, e) − 1
    ExpandNormal,
    /// −2·max(0, e) + 1
    ExpandNegate,
    /// max(0, e) − 0.5
    HalfBiasNormal,
    /// −max(0, e) + 0.5
    HalfBiasNegate,
    /// e
    SignedIdentity,
    /// −e
    SignedNegate,
}

impl Mapping {
    /// Every mapping in Table 4 order, for sweeps.
    pub const ALL: [Mapping; 8] = [
        Mapping::UnsignedIdentity,
        Mapping::UnsignedInvert,
        Mapping::ExpandNormal,
        Mapping::ExpandNegate,
        Mapping::HalfBiasNormal,
        Mapping::HalfBiasNegate,
        Mapping::SignedIdentity,
        Mapping::SignedNegate,
    ];

    /// The two mappings the final combiner accepts.
    pub fn is_unsigned(self) -> bool {
        matches!(self, Mapping::UnsignedIdentity | Mapping::UnsignedInvert)
    }

    /// The mapping of register code `r` (code c ↔ c/S) in half-LSB units
    /// (2·S·mapped), exact: s(N) in, s(N+2) out.
    #[inline]
    pub fn apply_half_lsb(self, r: i64, s: i64) -> i64 {
        let p = r.max(0); // max(0, e): u(N−1)
        match self {
            Mapping::UnsignedIdentity => 2 * p,
            Mapping::UnsignedInvert => 2 * (s - p.min(s)),
            Mapping::ExpandNormal => 2 * (2 * p - s),
            Mapping::ExpandNegate => 2 * (s - 2 * p),
            Mapping::HalfBiasNormal => 2 * p - s,
            Mapping::HalfBiasNegate => s - 2 * p,
            Mapping::SignedIdentity => 2 * r,
            Mapping::SignedNegate => -2 * r,
        }
    }
}

/// The `<componentUsage>` of CombinerInputNV / FinalCombinerInputNV.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "SCREAMING_SNAKE_CASE")]
pub enum ComponentUsage {
    /// The register's RGB (RGB portion only).
    Rgb,
    /// The register's alpha (replicated across RGB in the RGB portion).
    Alpha,
    /// The register's blue (alpha portion / final G only).
    Blue,
}

/// CombinerOutputNV `<scale>`: NONE, SCALE_BY_TWO_NV, SCALE_BY_FOUR_NV,
/// SCALE_BY_ONE_HALF_NV.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "SCREAMING_SNAKE_CASE")]
pub enum Scale {
    /// NONE: ×1.
    None,
    /// SCALE_BY_TWO_NV: ×2.
    ByTwo,
    /// SCALE_BY_FOUR_NV: ×4.
    ByFour,
    /// SCALE_BY_ONE_HALF_NV: ×½.
    ByOneHalf,
}

impl Scale {
    /// Every scale, NONE first.
    pub const ALL: [Scale; 4] = [Scale::None, Scale::ByTwo, Scale::ByFour, Scale::ByOneHalf];

    /// The scale ×2 (an integer: 2, 4, 8, 1).
    pub fn times_two(self) -> i64 {
        match self {
            Scale::None => 2,
            Scale::ByTwo => 4,
            Scale::ByFour => 8,
            Scale::ByOneHalf => 1,
        }
    }

    /// cscale as a real.
    pub fn value(self) -> f64 {
        self.times_two() as f64 / 2.0
    }
}

/// CombinerOutputNV `<bias>`: NONE or BIAS_BY_NEGATIVE_ONE_HALF_NV.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "SCREAMING_SNAKE_CASE")]
pub enum Bias {
    /// NONE: nothing is added.
    None,
    /// BIAS_BY_NEGATIVE_ONE_HALF_NV: −½ is added before the scale ((S + 1)/2 codes are
    /// subtracted with [`BiasConstant::HalfCode`]); not allowed with ×4 or ×½.
    ByNegativeOneHalf,
}

impl Bias {
    /// cbias as a real (0 or −0.5).
    pub fn value(self) -> f64 {
        match self {
            Bias::None => 0.0,
            Bias::ByNegativeOneHalf => -0.5,
        }
    }
}

/// One variable's CombinerInputNV: `<input>`, `<mapping>`, `<componentUsage>`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct VariableInput {
    /// `<input>`: the register read (ZERO reads 0).
    pub input: Register,
    /// `<mapping>`: how the register's value is mapped before the products (Table 4).
    pub mapping: Mapping,
    /// `<componentUsage>`: RGB or ALPHA on the RGB portion, ALPHA or BLUE on the alpha
    /// portion; FOG with ALPHA usage is refused (its alpha is the final combiner's).
    /// Errors name the variable's `component_usage`.
    pub component_usage: ComponentUsage,
}

impl VariableInput {
    /// The variable `<input>`, `<mapping>`, `<componentUsage>`.
    pub const fn new(input: Register, mapping: Mapping, component_usage: ComponentUsage) -> Self {
        VariableInput {
            input,
            mapping,
            component_usage,
        }
    }
}

/// One portion (RGB or alpha) of a general combiner stage: its four variables
/// (CombinerInputNV) and its output operation (CombinerOutputNV).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct PortionConfig {
    /// Variable A, the first factor of A·B.
    pub a: VariableInput,
    /// Variable B, the second factor of A·B.
    pub b: VariableInput,
    /// Variable C, the first factor of C·D.
    pub c: VariableInput,
    /// Variable D, the second factor of C·D.
    pub d: VariableInput,
    /// `<abOutput>`; `None` = DISCARD_NV.
    pub ab_output: Option<Register>,
    /// `<cdOutput>`; `None` = DISCARD_NV.
    pub cd_output: Option<Register>,
    /// `<sumOutput>`; `None` = DISCARD_NV.
    pub sum_output: Option<Register>,
    /// `<scale>`, applied after the sum (or mux) and the bias.
    pub scale: Scale,
    /// `<bias>`, added before the scale.
    pub bias: Bias,
    /// `<abDotProduct>` (RGB portion only).
    pub ab_dot_product: bool,
    /// `<cdDotProduct>` (RGB portion only).
    pub cd_dot_product: bool,
    /// `<muxSum>`: gcc6/gcc4a (the mux) instead of the sum.
    pub mux_sum: bool,
}

impl PortionConfig {
    /// Table NV_register_combiners.5 (the initial state) for a portion whose natural
    /// component usage is `usage` (RGB or ALPHA): A = PRIMARY_COLOR unsigned identity,
    /// B = ZERO unsigned invert (= 1), C = D = ZERO; the sum A·B + C·D to SPARE0, AB
    /// and CD discarded, no scale or bias.
    pub fn initial(usage: ComponentUsage) -> Self {
        let v = |r, m| VariableInput::new(r, m, usage);
        PortionConfig {
            a: v(Register::PrimaryColor, Mapping::UnsignedIdentity),
            b: v(Register::Zero, Mapping::UnsignedInvert),
            c: v(Register::Zero, Mapping::UnsignedIdentity),
            d: v(Register::Zero, Mapping::UnsignedIdentity),
            ab_output: None,
            cd_output: None,
            sum_output: Some(Register::Spare0),
            scale: Scale::None,
            bias: Bias::None,
            ab_dot_product: false,
            cd_dot_product: false,
            mux_sum: false,
        }
    }

    /// A portion that writes nothing (all three outputs DISCARD_NV).
    pub fn discard(usage: ComponentUsage) -> Self {
        PortionConfig {
            sum_output: None,
            ..Self::initial(usage)
        }
    }

    fn variables(&self) -> [(&'static str, VariableInput); 4] {
        [("a", self.a), ("b", self.b), ("c", self.c), ("d", self.d)]
    }

    /// The spec's errors for this portion, naming `<prefix>.<field>`.
    fn validate(&self, prefix: &str, alpha: bool) -> Result<(), ConfigError> {
        for (name, v) in self.variables() {
            let field = format!("{prefix}.{name}.component_usage");
            match (alpha, v.component_usage) {
                (true, ComponentUsage::Rgb) => {
                    return Err(ConfigError::invalid(
                        &field,
                        "RGB usage on the alpha portion (INVALID_OPERATION)",
                    ))
                }
                (false, ComponentUsage::Blue) => {
                    return Err(ConfigError::invalid(
                        &field,
                        "BLUE usage on the RGB portion (INVALID_OPERATION)",
                    ))
                }
                _ => {}
            }
            if v.input == Register::Fog && v.component_usage == ComponentUsage::Alpha {
                return Err(ConfigError::invalid(
                    &field,
                    "FOG alpha is only available in the final combiner (INVALID_OPERATION)",
                ));
            }
        }
        if alpha && (self.ab_dot_product || self.cd_dot_product) {
            let f = if self.ab_dot_product {
                "ab_dot_product"
            } else {
                "cd_dot_product"
            };
            return Err(ConfigError::invalid(
                &format!("{prefix}.{f}"),
                "dot products are RGB only (INVALID_VALUE)",
            ));
        }
        if self.bias == Bias::ByNegativeOneHalf
            && matches!(self.scale, Scale::ByFour | Scale::ByOneHalf)
        {
            return Err(ConfigError::invalid(
                &format!("{prefix}.bias"),
                "BIAS_BY_NEGATIVE_ONE_HALF with SCALE_BY_FOUR or SCALE_BY_ONE_HALF (INVALID_OPERATION)",
            ));
        }
        let outs = [
            ("ab_output", self.ab_output),
            ("cd_output", self.cd_output),
            ("sum_output", self.sum_output),
        ];
        for (k, (name, out)) in outs.iter().enumerate() {
            let Some(r) = out else { continue };
            if !r.writable() {
                return Err(ConfigError::invalid(
                    &format!("{prefix}.{name}"),
                    "output to a read-only register (INVALID_OPERATION)",
                ));
            }
            if outs[..k].iter().any(|(_, o)| *o == Some(*r)) {
                return Err(ConfigError::invalid(
                    &format!("{prefix}.{name}"),
                    "outputs must name unique registers (INVALID_OPERATION)",
                ));
            }
        }
        Ok(())
    }
}

/// The plain config (serde-friendly); [`RegisterCombinerConfig::build`] validates it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct RegisterCombinerConfig {
    /// N: the signed internal precision (sign + N−1 bits), 3 ..= 24; 9 on GeForce 256/2.
    pub internal_bits: u32,
    /// I: width of the unorm fragment values loaded into the registers, 1 ..= 16.
    pub input_bits: u32,
    /// G: extra fraction bits the products keep until the output rounding, 0 ..= 16.
    pub guard_bits: u32,
    /// Rounding of the products and of the output (any ap_fixed mode).
    pub rounding: Quant,
    /// The RGB portion (default: Table NV_register_combiners.5's initial state).
    pub rgb: PortionConfig,
    /// The alpha portion (default: Table NV_register_combiners.5's initial state).
    pub alpha: PortionConfig,
    /// What BIAS_BY_NEGATIVE_ONE_HALF subtracts ([`BiasConstant`]); `ExactHalf` by
    /// default, `HalfCode` on the NV2A.
    #[serde(default)]
    pub bias_constant: BiasConstant,
    /// Which bit of SPARE0's alpha the mux (gcc6/gcc4a) tests ([`MuxSelect`]); `Msb`
    /// (the spec's ≥ 0.5) by default, `Lsb` on the NV2A unless its combiner control
    /// selects MSB.
    #[serde(default)]
    pub mux_select: MuxSelect,
    /// NV2A: the RGB portion's AB output's blue is also written to the alpha of the
    /// abOutput register (NV097_SET_COMBINER_COLOR_OCW bit 19, AB_BLUE_TO_ALPHA; the
    /// AlphaFromBlue and Independence captures). Not in GL_NV_register_combiners.
    #[serde(default)]
    pub ab_blue_to_alpha: bool,
    /// NV2A: the same for the CD output (COLOR_OCW bit 18, CD_BLUE_TO_ALPHA).
    #[serde(default)]
    pub cd_blue_to_alpha: bool,
    /// NV2A: this stage's own CONSTANT_COLOR0/1 as register codes RGBA (0 ..= S), read
    /// instead of the register set's (NV097_SET_COMBINER_FACTOR0/1 + 4·stage with
    /// SET_COMBINER_CONTROL FACTOR0/1 = EACH_STAGE). `None`: the set's (GL's one pair).
    #[serde(default)]
    pub stage_constants: Option<[[i32; 4]; 2]>,
}

/// The constant BIAS_BY_NEGATIVE_ONE_HALF_NV subtracts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "SCREAMING_SNAKE_CASE")]
pub enum BiasConstant {
    /// Exactly ½ (S/2 codes, a half code: the spec's real −0.5). The model's default.
    #[default]
    ExactHalf,
    /// 2^(N−2) codes = (S + 1)/2, the register's top magnitude bit: −128/255 at N = 9.
    /// The NV2A (nxdk_pgraph_tests Combiner/CombinerOps capture: BIAS of 1.0 gives
    /// 127/255, SHIFT_LEFT_1_BIAS gives 254/255; ExactHalf gives 128 and 255). With
    /// G = 0 and scale 1 or 2 the biased output needs no rounding.
    HalfCode,
}

impl BiasConstant {
    /// The bias in half codes (units 1/(2S)) at S = `s`: S or S + 1.
    #[inline]
    pub fn half_codes(self, s: i64) -> i64 {
        match self {
            BiasConstant::ExactHalf => s,
            BiasConstant::HalfCode => s + 1,
        }
    }
}

/// The SPARE0-alpha test of the mux (gcc6 / gcc4a).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "SCREAMING_SNAKE_CASE")]
pub enum MuxSelect {
    /// SPARE0 alpha ≥ 0.5 ⇔ code ≥ 2^(N−2), its top magnitude bit (the spec;
    /// NV097_SET_COMBINER_CONTROL_MUX_SELECT_MSB on the NV2A).
    #[default]
    Msb,
    /// The code's lowest bit (NV097_SET_COMBINER_CONTROL_MUX_SELECT_LSB, the NV2A's
    /// reset value; Combiner/Mux capture: alpha 0x82 selects AB, 0x81 selects CD).
    Lsb,
}

impl MuxSelect {
    /// Whether the mux picks C·D for SPARE0 alpha code `c` (sign-extended, N bits).
    #[inline]
    pub fn selects_cd(self, c: i64, internal_bits: u32) -> bool {
        match self {
            MuxSelect::Msb => c >= 1i64 << (internal_bits - 2),
            MuxSelect::Lsb => c & 1 == 1,
        }
    }
}

/// What an NV2A texture stage with no texture bound returns: (0, 0, 0, 1) as
/// `bits`-bit unorm RGBA (Combiner/UnboundTexSampler capture: TEXn reads black,
/// its inversion white). A host edge for [`FragmentInputs::texture`].
pub fn unbound_texture(bits: u32) -> [u32; 4] {
    [0, 0, 0, ((1u64 << bits) - 1) as u32]
}

impl Default for RegisterCombinerConfig {
    fn default() -> Self {
        Self::geforce()
    }
}

impl RegisterCombinerConfig {
    /// GeForce 256/2 defaults: 9-bit registers, 8-bit colours, no guard bits, round to
    /// nearest (ties up); both portions in the spec's initial state (Table 5).
    pub fn geforce() -> Self {
        RegisterCombinerConfig {
            internal_bits: 9,
            input_bits: 8,
            guard_bits: 0,
            rounding: Quant::Rnd,
            rgb: PortionConfig::initial(ComponentUsage::Rgb),
            alpha: PortionConfig::initial(ComponentUsage::Alpha),
            bias_constant: BiasConstant::ExactHalf,
            mux_select: MuxSelect::Msb,
            ab_blue_to_alpha: false,
            cd_blue_to_alpha: false,
            stage_constants: None,
        }
    }

    /// Validate and build the unit; the same as [`RegisterCombiner::new`], errors name
    /// `register_combiner.<field>`.
    pub fn build(&self) -> Result<RegisterCombiner, ConfigError> {
        RegisterCombiner::new(*self)
    }
}

/// A combiner register set: per register (Table 1 order, [`Register::index`]) the
/// R, G, B, A components as s(N) codes, code c ↔ c/S. Words are masked to N wires.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct RegisterFile {
    /// R, G, B, A codes of each register, in [`Register::index`] order.
    pub regs: [[i32; 4]; REGISTER_COUNT],
}

impl RegisterFile {
    /// Register `r`'s R, G, B, A codes.
    pub fn get(&self, r: Register) -> [i32; 4] {
        self.regs[r.index()]
    }

    /// Overwrite register `r`'s R, G, B, A codes.
    pub fn set(&mut self, r: Register, v: [i32; 4]) {
        self.regs[r.index()] = v;
    }

    /// The set with CONSTANT_COLOR0/1 replaced by `constants` (the NV2A's per-stage or
    /// final-combiner constants), or the set itself without them.
    pub fn with_constants(&self, constants: Option<[[i32; 4]; 2]>) -> Cow<'_, RegisterFile> {
        match constants {
            Some([c0, c1]) => {
                let mut f = *self;
                f.set(Register::ConstantColor0, c0);
                f.set(Register::ConstantColor1, c1);
                Cow::Owned(f)
            }
            None => Cow::Borrowed(self),
        }
    }
}

/// The fragment values that initialise COMBINER0's register set, as `input_bits`-bit
/// unorm codes, RGBA (Table NV_register_combiners.1's initial values).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct FragmentInputs {
    /// PRIMARY_COLOR_NV, RGBA.
    pub primary_color: [u32; 4],
    /// SECONDARY_COLOR_NV, RGBA.
    pub secondary_color: [u32; 4],
    /// TEXTURE0_ARB … TEXTURE3_ARB, RGBA each.
    pub texture: [[u32; 4]; 4],
    /// CONSTANT_COLOR0_NV, RGBA.
    pub constant_color0: [u32; 4],
    /// CONSTANT_COLOR1_NV, RGBA.
    pub constant_color1: [u32; 4],
    /// RGB the fog colour, alpha the fog factor (1 when fog is off).
    pub fog: [u32; 4],
}

/// The validated unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RegisterCombiner {
    cfg: RegisterCombinerConfig,
}

/// Signal names for traces: `<register>_<component>`, Table 1 order.
const SIGNAL_NAMES: [&str; 4 * REGISTER_COUNT] = [
    "zero_r", "zero_g", "zero_b", "zero_a", "ccc0_r", "ccc0_g", "ccc0_b", "ccc0_a", "ccc1_r",
    "ccc1_g", "ccc1_b", "ccc1_a", "fog_r", "fog_g", "fog_b", "fog_a", "pri_r", "pri_g", "pri_b",
    "pri_a", "sec_r", "sec_g", "sec_b", "sec_a", "spare0_r", "spare0_g", "spare0_b", "spare0_a",
    "spare1_r", "spare1_g", "spare1_b", "spare1_a", "tex0_r", "tex0_g", "tex0_b", "tex0_a",
    "tex1_r", "tex1_g", "tex1_b", "tex1_a", "tex2_r", "tex2_g", "tex2_b", "tex2_a", "tex3_r",
    "tex3_g", "tex3_b", "tex3_a",
];

/// The register set as named N-bit signals (for the VCD traces of both combiner units).
pub fn register_file_signals(file: &RegisterFile, bits: u32) -> Vec<Signal> {
    let m = (1u64 << bits) - 1;
    file.regs
        .iter()
        .flatten()
        .zip(SIGNAL_NAMES)
        .map(|(&v, name)| Signal::new(name, bits, v as i64 as u64 & m))
        .collect()
}

/// Check a signed internal width N (3 ..= 24) under `field`.
pub fn check_internal_bits(field: &str, bits: u32) -> Result<(), ConfigError> {
    check_range(field, bits as u64, 3, 24)
}

/// S = 2^(N−1) − 1: the code of 1.0 in an N-bit register.
#[inline]
pub fn one_code(internal_bits: u32) -> i64 {
    (1i64 << (internal_bits - 1)) - 1
}

/// The register component a variable reads: the register's lane (RGB usage), its
/// alpha (ALPHA) or its blue (BLUE); ZERO reads 0. The word is masked to N wires.
#[inline]
pub fn select_component(
    file: &RegisterFile,
    v: &VariableInput,
    lane: usize,
    internal_bits: u32,
) -> i64 {
    if v.input == Register::Zero {
        return 0;
    }
    let comp = match v.component_usage {
        ComponentUsage::Rgb => lane,
        ComponentUsage::Alpha => 3,
        ComponentUsage::Blue => 2,
    };
    sign_extend(file.regs[v.input.index()][comp] as i64, internal_bits)
}

impl RegisterCombiner {
    /// Validate; errors name `register_combiner.<field>` (`rgb.b.component_usage`, …).
    pub fn new(cfg: RegisterCombinerConfig) -> Result<Self, ConfigError> {
        let f = |n: &str| format!("register_combiner.{n}");
        check_internal_bits(&f("internal_bits"), cfg.internal_bits)?;
        check_range(&f("input_bits"), cfg.input_bits as u64, 1, 16)?;
        check_range(&f("guard_bits"), cfg.guard_bits as u64, 0, 16)?;
        cfg.rgb.validate(&f("rgb"), false)?;
        cfg.alpha.validate(&f("alpha"), true)?;
        for (name, on, dst) in [
            ("ab_blue_to_alpha", cfg.ab_blue_to_alpha, cfg.rgb.ab_output),
            ("cd_blue_to_alpha", cfg.cd_blue_to_alpha, cfg.rgb.cd_output),
        ] {
            let a = &cfg.alpha;
            if on && dst.is_some() && [a.ab_output, a.cd_output, a.sum_output].contains(&dst) {
                return Err(ConfigError::invalid(
                    &f(name),
                    "the alpha portion writes the same register's alpha (which write wins is undocumented)",
                ));
            }
        }
        if let Some(k) = cfg.stage_constants {
            let s = one_code(cfg.internal_bits);
            if k.iter().flatten().any(|&c| !(0..=s).contains(&(c as i64))) {
                return Err(ConfigError::invalid(
                    &f("stage_constants"),
                    &format!("a constant outside the register codes 0 ..= {s}"),
                ));
            }
        }
        Ok(RegisterCombiner { cfg })
    }

    /// GeForce 256/2 defaults ([`RegisterCombinerConfig::geforce`]).
    pub fn geforce() -> Self {
        RegisterCombiner {
            cfg: RegisterCombinerConfig::geforce(),
        }
    }

    /// The config the unit was built from.
    pub fn config(&self) -> RegisterCombinerConfig {
        self.cfg
    }

    /// S: the code of 1.0.
    pub fn one(&self) -> i64 {
        one_code(self.cfg.internal_bits)
    }

    /// Load one unorm code u (`input_bits`, masked to its wires) into the register
    /// format: round(u·S/U) by `rounding` (u(I) × u(N−1) → u(I+N−1), ÷ U). Exact when
    /// N − 1 = I; never saturates (u ≤ U → result ≤ S).
    pub fn load_unorm(&self, u: u32, ctr: &mut Counters) -> i32 {
        let big_u = (1i128 << self.cfg.input_bits) - 1;
        let u = u as i128 & big_u;
        let c = round_div(u * self.one() as i128, big_u, self.cfg.rounding);
        if c == 0 && u != 0 {
            ctr.underflows += 1;
        }
        c as i32
    }

    /// COMBINER0's register set from the fragment (Table 1 initial values): SPARE0's
    /// alpha is texture 0's alpha; the undefined values (SPARE0 RGB, SPARE1) are 0.
    pub fn load_fragment(&self, f: &FragmentInputs, ctr: &mut Counters) -> RegisterFile {
        let mut load = |v: [u32; 4]| v.map(|u| self.load_unorm(u, ctr));
        let mut file = RegisterFile::default();
        file.set(Register::ConstantColor0, load(f.constant_color0));
        file.set(Register::ConstantColor1, load(f.constant_color1));
        file.set(Register::Fog, load(f.fog));
        file.set(Register::PrimaryColor, load(f.primary_color));
        file.set(Register::SecondaryColor, load(f.secondary_color));
        let tex = f.texture.map(&mut load);
        for (k, t) in tex.iter().enumerate() {
            file.regs[Register::Texture0.index() + k] = *t;
        }
        file.set(Register::Spare0, [0, 0, 0, tex[0][3]]);
        file
    }

    /// Step 4: round a product (or dot product) p, in units 1/(4S²), to the working
    /// scale 1/(S·2^G). Counts a non-zero p rounded to 0.
    #[inline]
    fn round_product(&self, p: i128, ctr: &mut Counters) -> i128 {
        let q = round_div(
            p << self.cfg.guard_bits, // s(2N+3) << G
            4 * self.one() as i128,
            self.cfg.rounding,
        ); // → s(N+G+2): |p/(4S)| ≤ 3(S+1)²/S
        if q == 0 && p != 0 {
            ctr.underflows += 1;
        }
        q
    }

    /// Step 6: bias, scale, round to the register format and clamp to [−S, S].
    #[inline]
    fn output(&self, x: i128, portion: &PortionConfig, ctr: &mut Counters) -> i32 {
        let g = self.cfg.guard_bits;
        let s = self.one() as i128;
        let b = if portion.bias == Bias::ByNegativeOneHalf {
            // ½ in units 1/(2W): S·2^G (ExactHalf) or (S + 1)·2^G (HalfCode).
            (self.cfg.bias_constant.half_codes(s as i64) as i128) << g
        } else {
            0
        };
        let v = (2 * x - b) * portion.scale.times_two() as i128; // s(N+G+4) × ≤ 8 → s(N+G+7)
        let r = round_shift(v, (g + 2) as i32, self.cfg.rounding); // → units 1/S
        if r == 0 && v != 0 {
            ctr.underflows += 1;
        }
        if r > s || r < -s {
            ctr.saturations += 1;
        }
        r.clamp(-s, s) as i32
    }

    /// One portion's three outputs (out1, out2, out3) on `lanes` lanes: RGB uses lanes
    /// 0..3, alpha lane 3 (read through the component usage).
    fn portion_outputs(
        &self,
        file: &RegisterFile,
        p: &PortionConfig,
        lanes: std::ops::Range<usize>,
        ctr: &mut Counters,
    ) -> [[i32; 4]; 3] {
        let n = self.cfg.internal_bits;
        let s = self.one();
        // Steps 1–3: mapped variables (s(N+2)) and their lane products (s(2N+2)).
        let mapped = |v: &VariableInput, lane: usize| {
            v.mapping
                .apply_half_lsb(select_component(file, v, lane, n), s) as i128
        };
        let mut ab = [0i128; 4];
        let mut cd = [0i128; 4];
        for lane in lanes.clone() {
            ab[lane] = mapped(&p.a, lane) * mapped(&p.b, lane);
            cd[lane] = mapped(&p.c, lane) * mapped(&p.d, lane);
        }
        // Step 3–4: dot products (sum of the three lanes, s(2N+3)) or lane products,
        // each rounded once.
        let mut q_ab = [0i128; 4];
        let mut q_cd = [0i128; 4];
        let dot = |v: &[i128; 4]| v[0] + v[1] + v[2];
        let q_ab_dot = p.ab_dot_product.then(|| self.round_product(dot(&ab), ctr));
        let q_cd_dot = p.cd_dot_product.then(|| self.round_product(dot(&cd), ctr));
        for lane in lanes.clone() {
            q_ab[lane] = match q_ab_dot {
                Some(q) => q, // gcc2rgb: the dot replicated to R, G, B
                None => self.round_product(ab[lane], ctr),
            };
            q_cd[lane] = match q_cd_dot {
                Some(q) => q,
                None => self.round_product(cd[lane], ctr),
            };
        }
        // Step 5: the mux reads SPARE0 alpha of the input set: ≥ 0.5 ⇔ c ≥ 2^(N−2)
        // (Msb), or its low bit (Lsb).
        let spare0_alpha = sign_extend(file.regs[Register::Spare0.index()][3] as i64, n);
        let mux_cd = self.cfg.mux_select.selects_cd(spare0_alpha, n);
        let mut out = [[0i32; 4]; 3];
        for lane in lanes {
            let sum = if p.mux_sum {
                if mux_cd {
                    q_cd[lane]
                } else {
                    q_ab[lane]
                }
            } else {
                q_ab[lane] + q_cd[lane] // s(N+G+3)
            };
            // The spec clamps each output; a discarded output's clamp is not counted
            // (it is not computed into any register).
            let outs = [p.ab_output, p.cd_output, p.sum_output];
            for (k, x) in [q_ab[lane], q_cd[lane], sum].into_iter().enumerate() {
                if outs[k].is_some() {
                    out[k][lane] = self.output(x, p, ctr);
                }
            }
        }
        out
    }

    /// The whole stage: the updated register set.
    pub fn combine(&self, file: &RegisterFile, ctr: &mut Counters) -> RegisterFile {
        let n = self.cfg.internal_bits;
        let mut next = *file;
        for r in next.regs.iter_mut().flatten() {
            *r = sign_extend(*r as i64, n) as i32; // the N-bit register wires
        }
        // NV2A per-stage constants replace the set's CONSTANT_COLOR0/1 for this stage's
        // reads (the output set passes the input's on).
        let file = &*file.with_constants(self.cfg.stage_constants);
        let rgb = self.portion_outputs(file, &self.cfg.rgb, 0..3, ctr);
        let alpha = self.portion_outputs(file, &self.cfg.alpha, 3..4, ctr);
        // NV2A blue-to-alpha: out1/out2's blue lane also to its register's alpha.
        for (on, dst, vals) in [
            (self.cfg.ab_blue_to_alpha, self.cfg.rgb.ab_output, rgb[0]),
            (self.cfg.cd_blue_to_alpha, self.cfg.rgb.cd_output, rgb[1]),
        ] {
            if let (true, Some(r)) = (on, dst) {
                next.regs[r.index()][3] = vals[2];
            }
        }
        for (p, outs, lanes) in [(&self.cfg.rgb, rgb, 0..3), (&self.cfg.alpha, alpha, 3..4)] {
            for (dst, vals) in [p.ab_output, p.cd_output, p.sum_output].iter().zip(outs) {
                if let Some(r) = dst {
                    for lane in lanes.clone() {
                        next.regs[r.index()][lane] = vals[lane];
                    }
                }
            }
        }
        next
    }
}

impl Unit for RegisterCombiner {
    type In = RegisterFile;
    type Out = RegisterFile;
    type State = ();

    fn name(&self) -> &'static str {
        "register_combiner"
    }

    fn kernel(&self, _: &mut (), input: &RegisterFile, ctr: &mut Counters) -> RegisterFile {
        self.combine(input, ctr)
    }

    fn timing(&self) -> Timing {
        // select + map | multiply, dot sum | round, sum/mux, scale/bias, clamp, write.
        Timing { latency: 3, ii: 1 }
    }

    fn cost(&self) -> Cost {
        let n = self.cfg.internal_bits;
        let g = self.cfg.guard_bits;
        let m = n + 2; // mapped operand s(N+2)
        let pw = 2 * n + 3; // product / dot s(2N+3)
        let qw = n + g + 3; // rounded product and sum
        let file_bits = (REGISTER_COUNT as u32 - 1) * 4 * n; // ZERO is not stored
        let negate = |w: u32| {
            Cells {
                xor2: w as f64,
                ..Cells::default()
            } + prim::half_adder() * w as f64
        };
        // 16 variable lanes: 12 RGB (4 variables × 3) and 4 alpha.
        let lanes = 16.0;
        let mut cost = Cost::default()
            .part("input register set", prim::register(file_bits))
            .part(
                "variable select: register 12:1 × component (16 lanes)",
                (prim::mux_k(n, REGISTER_COUNT as u32) + prim::mux(n)) * lanes,
            )
            .part(
                "input mapping: max(0,·), ×2, ± S, negate, 8:1 (16 lanes)",
                (Cells {
                    and2: n as f64,
                    ..Cells::default()
                } + prim::adder(m)
                    + negate(m)
                    + prim::mux_k(m, 8))
                    * lanes,
            )
            .part(
                "stage registers (mapped variables, register set)",
                prim::register(16 * m + file_bits),
            )
            .part(
                "multipliers s(N+2)×s(N+2) (AB, CD × 4 lanes)",
                prim::multiplier(m, m) * 8.0,
            )
            .part("dot-product adders (2 × 2)", prim::adder(pw) * 4.0)
            .part(
                "stage registers (products, dots, register set)",
                prim::register(8 * pw + 2 * pw + file_bits),
            )
            .part(
                "product rounding ÷4S (shift-add, 8 lanes + 2 dots)",
                prim::adder(pw + g) * 2.0 * 10.0,
            )
            .part("AB + CD adders (4 lanes)", prim::adder(qw) * 4.0)
            .part("mux-sum selects (4 lanes)", prim::mux(qw) * 4.0)
            .part(
                "bias, scale shifter, output rounding (12 outputs)",
                (prim::adder(qw + 1) + prim::shifter(qw + 4, 2) + prim::adder(n + 1)) * 12.0,
            )
            .part(
                "output clamps to [−S, S] (12 outputs)",
                (prim::comparator(n + 1) * 2.0 + prim::mux_k(n, 3)) * 12.0,
            )
            .part(
                "write-back: 8 writable registers × 4 components, 4:1",
                prim::mux_k(n, 4) * 32.0,
            )
            .part("output register set", prim::register(file_bits));
        if self.cfg.stage_constants.is_some() {
            cost = cost.part(
                "per-stage CONSTANT_COLOR0/1 registers (NV2A)",
                prim::register(8 * n),
            );
        }
        if self.cfg.ab_blue_to_alpha || self.cfg.cd_blue_to_alpha {
            cost = cost.part(
                "blue-to-alpha write-back selects (NV2A, 8 alphas)",
                prim::mux(n) * 8.0,
            );
        }
        cost
    }

    fn widths(&self) -> Vec<Width> {
        vec![
            Width {
                name: "internal_bits",
                bits: self.cfg.internal_bits,
            },
            Width {
                name: "input_bits",
                bits: self.cfg.input_bits,
            },
            Width {
                name: "guard_bits",
                bits: self.cfg.guard_bits,
            },
            Width {
                name: "product",
                bits: 2 * self.cfg.internal_bits + 3,
            },
        ]
    }

    fn in_signals(&self, i: &RegisterFile) -> Vec<Signal> {
        register_file_signals(i, self.cfg.internal_bits)
    }

    fn out_signals(&self, o: &RegisterFile) -> Vec<Signal> {
        register_file_signals(o, self.cfg.internal_bits)
    }
}
