//! final_combiner — the FINAL combiner stage of GL_NV_register_combiners (section
//! 3.8.12.3): the register set after the last general combiner in, the fragment's
//! colour fcoc out as `out_bits`-bit unorm RGBA.
//!
//!   fcoc = [ min(A·B + (1 − A)·C + D, 1) per R, G, B ;  G ]
//!
//! with the variables A … G chosen by FinalCombinerInputNV (`<input>`, `<mapping>`,
//! `<componentUsage>`): A … F are RGB vectors (usage RGB or ALPHA), G a scalar (ALPHA or
//! BLUE). Two pseudo-registers besides Table 1's: E_TIMES_F_NV (the product E·F of the
//! mapped E and F) and SPARE0_PLUS_SECONDARY_COLOR_NV (SPARE0 and SECONDARY_COLOR each
//! under UNSIGNED_IDENTITY, summed, clamped to [0, 1] when COLOR_SUM_CLAMP_NV is set);
//! their alpha is 0. Mappings: UNSIGNED_IDENTITY_NV and UNSIGNED_INVERT_NV only.
//!
//! ## Datapath (integers only; S = 2^(N−1) − 1 as in `register_combiner`, U = 2^O − 1)
//! 1. Select + map (exact, units 1/S): max(0, e) or S − min(max(e, 0), S). The
//!    identity keeps SPARE0 + SECONDARY up to 2S (u(N+1)); every other value ≤ S.
//! 2. E·F: u(N−1) × u(N−1) → u(2N−2), rounded once to the register scale by
//!    `rounding` (the spec does not say; chosen: the pseudo-register has the register
//!    precision), ≤ S. Non-zero products rounded to 0 count in `underflows`.
//!    SPARE0 + SECONDARY: u(N) sum; with the clamp, a sum above S counts in
//!    `saturations`.
//! 3. x = A·B + (S − A)·C + S·D in units 1/S² (the lerp at full precision, chosen so
//!    that the output is rounded once): u(2N+1) ≤ 4S² (the spec's "[0, 4]" range).
//! 4. min(x, S²) (a clamp counted in `saturations` when x > S²), then
//!    out = round(x·U / S²) by `rounding` → u(O). Alpha: round(G·U / S).
//!
//! NV2A modes (defaults off, the GeForce behaviour): `specular_add_invert_r0` /
//! `specular_add_invert_v1` put SPARE0 / SECONDARY_COLOR under UNSIGNED_INVERT in the
//! pseudo-register's sum (S − min(max(e, 0), S), exact); `constants` gives the final
//! combiner its own CONSTANT_COLOR0/1. COLOR_SUM_CLAMP_NV is the NV2A's
//! SPECULAR_CLAMP (the Combiner/Flags capture: 0.5·(1 + 1) gives 254 unclamped, 127
//! clamped).
//!
//! The GeForce 256 bug above 2 (spec, NVIDIA Implementation Details) is not modelled:
//! GeForce2 GTS and later compute the full range.
//!
//! Timing: latency 3 (select, map, E·F | the lerp products | sum, clamp, round), II 1.

use crate::cost::{prim, Cells, Cost};
use crate::counters::Counters;
use crate::error::{check_range, ConfigError};
use crate::fixed_point::{round_div, Quant};
use crate::unit::{Signal, Timing, Unit, Width};
use crate::units::register_combiner::{
    check_internal_bits, one_code, register_file_signals, select_component, ComponentUsage,
    Mapping, Register, RegisterFile, VariableInput, REGISTER_COUNT,
};
use serde::{Deserialize, Serialize};

/// FinalCombinerInputNV <input>: a register of Table 1 or one of the two
/// pseudo-registers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "SCREAMING_SNAKE_CASE")]
pub enum FinalInput {
    /// A register of the register set (Table 1 of the extension), read as it stands.
    Register(Register),
    /// E_TIMES_F_NV
    ETimesF,
    /// SPARE0_PLUS_SECONDARY_COLOR_NV
    Spare0PlusSecondaryColor,
}

/// One final-combiner variable: `<input>`, `<mapping>`, `<componentUsage>`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct FinalVariable {
    /// `<input>`: the register or pseudo-register read.
    pub input: FinalInput,
    /// `<mapping>`: UNSIGNED_IDENTITY_NV or UNSIGNED_INVERT_NV only (others are refused
    /// by [`FinalCombiner::new`], naming `<variable>.mapping`).
    pub mapping: Mapping,
    /// `<componentUsage>`: RGB or ALPHA for A … F; ALPHA or BLUE for G (others are refused,
    /// naming `<variable>.component_usage`).
    pub component_usage: ComponentUsage,
}

impl FinalVariable {
    /// The variable `<input>`, `<mapping>`, `<componentUsage>`.
    pub const fn new(input: FinalInput, mapping: Mapping, component_usage: ComponentUsage) -> Self {
        FinalVariable {
            input,
            mapping,
            component_usage,
        }
    }

    /// A register under UNSIGNED_IDENTITY with the given usage.
    pub const fn register(r: Register, component_usage: ComponentUsage) -> Self {
        Self::new(
            FinalInput::Register(r),
            Mapping::UnsignedIdentity,
            component_usage,
        )
    }
}

/// The plain config; [`FinalCombinerConfig::build`] validates it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct FinalCombinerConfig {
    /// N: the register width (the general combiners' `internal_bits`), 3 ..= 24.
    pub internal_bits: u32,
    /// O: the unorm output width, 1 ..= 16 (8: the GeForce framebuffer).
    pub out_bits: u32,
    /// Rounding of E·F and of the output.
    pub rounding: Quant,
    /// COLOR_SUM_CLAMP_NV (csc).
    pub color_sum_clamp: bool,
    /// Variable A, the lerp's weight: A·B + (1 − A)·C (default FOG alpha).
    pub a: FinalVariable,
    /// Variable B, weighted by A (default SPARE0_PLUS_SECONDARY_COLOR_NV).
    pub b: FinalVariable,
    /// Variable C, weighted by 1 − A (default FOG RGB).
    pub c: FinalVariable,
    /// Variable D, added after the lerp (default ZERO).
    pub d: FinalVariable,
    /// Variable E, the first factor of the E_TIMES_F_NV pseudo-register (default ZERO).
    pub e: FinalVariable,
    /// Variable F, the second factor of E_TIMES_F_NV (default ZERO).
    pub f: FinalVariable,
    /// Variable G, the output alpha, a scalar (ALPHA or BLUE usage; default SPARE0 alpha).
    pub g: FinalVariable,
    /// NV2A: SPARE0 enters SPARE0_PLUS_SECONDARY_COLOR under UNSIGNED_INVERT (1 − R0)
    /// instead of UNSIGNED_IDENTITY (NV097_SET_COMBINER_SPECULAR_FOG_CW1 bit 5,
    /// SPECULAR_ADD_INVERT_R0; the Combiner/Flags and SpecialInputs captures).
    #[serde(default)]
    pub specular_add_invert_r0: bool,
    /// NV2A: the same for SECONDARY_COLOR (1 − V1; SPECULAR_ADD_INVERT_V1).
    #[serde(default)]
    pub specular_add_invert_v1: bool,
    /// NV2A: the final combiner's own CONSTANT_COLOR0/1 as register codes RGBA
    /// (0 ..= S), read instead of the register set's (NV097_SET_SPECULAR_FOG_FACTOR
    /// 0/1). `None`: the set's (GL's one pair).
    #[serde(default)]
    pub constants: Option<[[i32; 4]; 2]>,
}

impl Default for FinalCombinerConfig {
    fn default() -> Self {
        Self::geforce()
    }
}

impl FinalCombinerConfig {
    /// GeForce 256/2: 9-bit registers, 8-bit output, round to nearest (ties up), the
    /// colour sum clamp off, and the spec's initial state (Table NV_register_combiners.6,
    /// OpenGL's colour sum and fog): A = FOG alpha, B = SPARE0 + SECONDARY, C = FOG RGB,
    /// D = E = F = ZERO, G = SPARE0 alpha.
    pub fn geforce() -> Self {
        use ComponentUsage::{Alpha, Rgb};
        let reg = FinalVariable::register;
        FinalCombinerConfig {
            internal_bits: 9,
            out_bits: 8,
            rounding: Quant::Rnd,
            color_sum_clamp: false,
            a: reg(Register::Fog, Alpha),
            b: FinalVariable::new(
                FinalInput::Spare0PlusSecondaryColor,
                Mapping::UnsignedIdentity,
                Rgb,
            ),
            c: reg(Register::Fog, Rgb),
            d: reg(Register::Zero, Rgb),
            e: reg(Register::Zero, Rgb),
            f: reg(Register::Zero, Rgb),
            g: reg(Register::Spare0, Alpha),
            specular_add_invert_r0: false,
            specular_add_invert_v1: false,
            constants: None,
        }
    }

    /// Validate and build the unit; the same as [`FinalCombiner::new`], errors name
    /// `final_combiner.<field>`.
    pub fn build(&self) -> Result<FinalCombiner, ConfigError> {
        FinalCombiner::new(*self)
    }

    fn variables(&self) -> [(&'static str, FinalVariable); 7] {
        [
            ("a", self.a),
            ("b", self.b),
            ("c", self.c),
            ("d", self.d),
            ("e", self.e),
            ("f", self.f),
            ("g", self.g),
        ]
    }
}

/// The validated unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FinalCombiner {
    cfg: FinalCombinerConfig,
}

/// The final combiner's output: fcoc as u(O) RGBA.
pub type FinalCombinerOut = [u32; 4];

impl FinalCombiner {
    /// Validate; errors name `final_combiner.<field>` (`b.mapping`, `g.component_usage`, …).
    pub fn new(cfg: FinalCombinerConfig) -> Result<Self, ConfigError> {
        let f = |n: &str| format!("final_combiner.{n}");
        check_internal_bits(&f("internal_bits"), cfg.internal_bits)?;
        check_range(&f("out_bits"), cfg.out_bits as u64, 1, 16)?;
        for (name, v) in cfg.variables() {
            let is_g = name == "g";
            if !v.mapping.is_unsigned() {
                return Err(ConfigError::invalid(
                    &f(&format!("{name}.mapping")),
                    "the final combiner accepts UNSIGNED_IDENTITY_NV or UNSIGNED_INVERT_NV only",
                ));
            }
            let usage_field = f(&format!("{name}.component_usage"));
            match (is_g, v.component_usage) {
                (false, ComponentUsage::Blue) => {
                    return Err(ConfigError::invalid(
                        &usage_field,
                        "BLUE usage is for variable G only (INVALID_OPERATION)",
                    ))
                }
                (true, ComponentUsage::Rgb) => {
                    return Err(ConfigError::invalid(
                        &usage_field,
                        "RGB usage on variable G (INVALID_OPERATION)",
                    ))
                }
                _ => {}
            }
            if let FinalInput::Register(_) = v.input {
                continue;
            }
            let input_field = f(&format!("{name}.input"));
            if matches!(name, "e" | "f" | "g") {
                return Err(ConfigError::invalid(
                    &input_field,
                    "E_TIMES_F / SPARE0_PLUS_SECONDARY_COLOR on E, F or G (INVALID_OPERATION)",
                ));
            }
            if name == "a" && v.input == FinalInput::Spare0PlusSecondaryColor {
                return Err(ConfigError::invalid(
                    &input_field,
                    "SPARE0_PLUS_SECONDARY_COLOR on A (INVALID_OPERATION)",
                ));
            }
            if v.component_usage != ComponentUsage::Rgb {
                return Err(ConfigError::invalid(
                    &usage_field,
                    "a pseudo-register takes RGB usage only (INVALID_OPERATION)",
                ));
            }
        }
        if let Some(k) = cfg.constants {
            let s = one_code(cfg.internal_bits);
            if k.iter().flatten().any(|&c| !(0..=s).contains(&(c as i64))) {
                return Err(ConfigError::invalid(
                    &f("constants"),
                    &format!("a constant outside the register codes 0 ..= {s}"),
                ));
            }
        }
        Ok(FinalCombiner { cfg })
    }

    /// GeForce 256/2 defaults ([`FinalCombinerConfig::geforce`]).
    pub fn geforce() -> Self {
        FinalCombiner {
            cfg: FinalCombinerConfig::geforce(),
        }
    }

    /// The config the unit was built from.
    pub fn config(&self) -> FinalCombinerConfig {
        self.cfg
    }

    /// S: the register code of 1.0.
    pub fn one(&self) -> i64 {
        one_code(self.cfg.internal_bits)
    }

    /// U: the output code of 1.0.
    pub fn out_max(&self) -> u32 {
        ((1u64 << self.cfg.out_bits) - 1) as u32
    }

    /// Step 1 on a register variable: the register component, mapped (units 1/S).
    fn mapped_register(&self, file: &RegisterFile, v: &VariableInput, lane: usize) -> i128 {
        let s = self.one();
        // Unsigned mappings are exact in whole codes: apply_half_lsb gives 2·value.
        (v.mapping
            .apply_half_lsb(select_component(file, v, lane, self.cfg.internal_bits), s)
            / 2) as i128
    }

    /// One variable on one lane (0..3 RGB, 3 for G), given the pseudo-registers' values.
    fn variable(
        &self,
        file: &RegisterFile,
        v: &FinalVariable,
        lane: usize,
        specials: &Specials,
    ) -> i128 {
        let s = self.one() as i128;
        let unsigned_map = |x: i128| match v.mapping {
            Mapping::UnsignedInvert => s - x.clamp(0, s),
            _ => x.max(0),
        };
        match v.input {
            FinalInput::Register(r) => self.mapped_register(
                file,
                &VariableInput::new(r, v.mapping, v.component_usage),
                lane,
            ),
            FinalInput::ETimesF => unsigned_map(specials.e_times_f[lane.min(2)]),
            FinalInput::Spare0PlusSecondaryColor => {
                unsigned_map(specials.spare0_plus_secondary[lane.min(2)])
            }
        }
    }

    /// The whole stage on one register set.
    pub fn combine(&self, file: &RegisterFile, ctr: &mut Counters) -> FinalCombinerOut {
        let c = self.cfg;
        let s = self.one() as i128;
        // NV2A: the final combiner's own constants replace the set's.
        let file = &*file.with_constants(c.constants);
        // Step 2: the pseudo-registers (E, F are registers: validated).
        let mut specials = Specials::default();
        let uses = |x: FinalInput| [c.a, c.b, c.c, c.d].iter().any(|v| v.input == x);
        for lane in 0..3 {
            if uses(FinalInput::ETimesF) {
                let e = self.variable(file, &c.e, lane, &specials);
                let f = self.variable(file, &c.f, lane, &specials);
                let p = e * f; // u(N−1) × u(N−1) → u(2N−2)
                let q = round_div(p, s, c.rounding); // → u(N−1), ≤ S
                if q == 0 && p != 0 {
                    ctr.underflows += 1;
                }
                specials.e_times_f[lane] = q;
            }
            if uses(FinalInput::Spare0PlusSecondaryColor) {
                // UNSIGNED_IDENTITY, or UNSIGNED_INVERT under the NV2A's add-invert flags.
                let term = |r, invert: bool| {
                    let m = if invert {
                        Mapping::UnsignedInvert
                    } else {
                        Mapping::UnsignedIdentity
                    };
                    self.mapped_register(file, &VariableInput::new(r, m, ComponentUsage::Rgb), lane)
                };
                let mut sum = term(Register::Spare0, c.specular_add_invert_r0)
                    + term(Register::SecondaryColor, c.specular_add_invert_v1); // u(N)
                if c.color_sum_clamp && sum > s {
                    ctr.saturations += 1;
                    sum = s;
                }
                specials.spare0_plus_secondary[lane] = sum;
            }
        }
        let mut out = [0u32; 4];
        for (lane, o) in out.iter_mut().enumerate().take(3) {
            let var = |v: &FinalVariable| self.variable(file, v, lane, &specials);
            let (a, b, cc, d) = (var(&c.a), var(&c.b), var(&c.c), var(&c.d));
            // Step 3: A·B + (S − A)·C + S·D, units 1/S²: u(2N+1).
            let mut x = a * b + (s - a) * cc + s * d;
            // Step 4: min(·, 1), then to u(O).
            if x > s * s {
                ctr.saturations += 1;
                x = s * s;
            }
            *o = self.output_code(x, s * s, ctr);
        }
        let g = self.variable(file, &c.g, 3, &specials);
        out[3] = self.output_code(g, s, ctr);
        out
    }

    /// round(x·U / den) by `rounding`, x ∈ [0, den]: u(2N+1) × u(O) → ÷ den → u(O).
    fn output_code(&self, x: i128, den: i128, ctr: &mut Counters) -> u32 {
        let y = round_div(x * self.out_max() as i128, den, self.cfg.rounding);
        if y == 0 && x != 0 {
            ctr.underflows += 1;
        }
        y as u32
    }
}

/// The pseudo-registers' RGB values (units 1/S) for one register set.
#[derive(Clone, Copy, Debug, Default)]
struct Specials {
    e_times_f: [i128; 3],
    spare0_plus_secondary: [i128; 3],
}

impl Unit for FinalCombiner {
    type In = RegisterFile;
    type Out = FinalCombinerOut;
    type State = ();

    fn name(&self) -> &'static str {
        "final_combiner"
    }

    fn kernel(&self, _: &mut (), input: &RegisterFile, ctr: &mut Counters) -> FinalCombinerOut {
        self.combine(input, ctr)
    }

    fn timing(&self) -> Timing {
        // select, map, E·F | A·B, (1 − A)·C | sum, clamp, round to u(O).
        Timing { latency: 3, ii: 1 }
    }

    fn cost(&self) -> Cost {
        let n = self.cfg.internal_bits;
        let o = self.cfg.out_bits;
        let v = n - 1; // an unsigned mapped value u(N−1)
        let xw = 2 * n + 1;
        let file_bits = (REGISTER_COUNT as u32 - 1) * 4 * n;
        let lanes = 6.0 * 3.0 + 1.0; // A … F × RGB, G
        let mut cost = Cost::default()
            .part("input register set", prim::register(file_bits))
            .part(
                "variable select: 14 inputs × component (19 lanes)",
                (prim::mux_k(n, REGISTER_COUNT as u32 + 2) + prim::mux(n)) * lanes,
            )
            .part(
                "unsigned mappings: max(0,·), S − min(·, S) (19 lanes)",
                (Cells {
                    and2: n as f64,
                    ..Cells::default()
                } + prim::subtractor(n)
                    + prim::mux(n))
                    * lanes,
            )
            .part(
                "SPARE0 + SECONDARY adders and the csc clamp (3)",
                (prim::adder(n) + prim::comparator(n) + prim::mux(n)) * 3.0,
            )
            .part(
                "E·F multipliers and rounding ÷S (3)",
                (prim::multiplier(v, v) + prim::adder(2 * v) * 2.0) * 3.0,
            )
            .part(
                "stage registers (variables)",
                prim::register(lanes as u32 * (n + 1)),
            )
            .part(
                "lerp multipliers A·B, (S − A)·C and S·D (3 lanes)",
                (prim::multiplier(v, n) * 2.0 + prim::subtractor(v) + prim::adder(2 * n)) * 3.0,
            )
            .part(
                "stage registers (lerp terms)",
                prim::register(3 * 3 * xw + v),
            )
            .part(
                "sum, clamp to 1, ×U ÷S² rounding (3 lanes + G)",
                (prim::adder(xw) * 2.0 + prim::comparator(xw) + prim::adder(xw + o) * 3.0) * 4.0,
            )
            .part("output register", prim::register(4 * o));
        if self.cfg.specular_add_invert_r0 || self.cfg.specular_add_invert_v1 {
            cost = cost.part(
                "add-invert subtractors S − x (NV2A, 2 × 3)",
                (prim::subtractor(n) + prim::mux(n)) * 6.0,
            );
        }
        if self.cfg.constants.is_some() {
            cost = cost.part(
                "final CONSTANT_COLOR0/1 registers (NV2A)",
                prim::register(8 * n),
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
                name: "out_bits",
                bits: self.cfg.out_bits,
            },
            Width {
                name: "lerp",
                bits: 2 * self.cfg.internal_bits + 1,
            },
        ]
    }

    fn in_signals(&self, i: &RegisterFile) -> Vec<Signal> {
        register_file_signals(i, self.cfg.internal_bits)
    }

    fn out_signals(&self, o: &FinalCombinerOut) -> Vec<Signal> {
        let w = self.cfg.out_bits;
        ["r", "g", "b", "a"]
            .iter()
            .zip(o)
            .map(|(n, &v)| Signal::new(n, w, v as u64))
            .collect()
    }
}
