//! modulate_chain — a chain of GL_MODULATE stages on n-bit unorms: out = Π operands,
//! left to right (GL multitexture: primary colour × texture 0 × texture 1, each texture
//! unit MODULATE of TEXTURE and PREVIOUS).
//!
//! Where the value between two stages is rounded GL leaves to the implementation;
//! [`ChainRounding`] names the two choices. `per_stage` (default) is k − 1 `modulate`
//! datapaths in a row, each rounding to u(n) — a GeForce register holds an 8-bit value
//! between texture stages. `fused` is Mesa's software GL (llvmpipe and softpipe): the
//! operands become binary32, the stages multiply in binary32, and one float → unorm
//! conversion ends the chain; bit-exact against OSMesa at 8 bits
//! (tests/modulate_mesa.rs). Widths: operands u(n), n = `bits` 1 ..= 16; per stage
//! u(n) × u(n) → u(2n) → u(n); fused: u(n) → binary32 (24-bit significand), binary32 ×
//! binary32 → binary32, binary32 → u(n). No saturation, overflow or underflow is
//! possible (every product of values in [0, 1] stays in [0, 1]; a binary32 value below
//! 2⁻⁹⁷ is flushed to 0, the code it converts to anyway).
//!
//! The f64 twin is `reference::modulate_chain` (the real product); the datasheet is
//! docs/units.md `## modulate_chain`; tests: tests/modulate_chain.rs (bounds, drivers),
//! tests/modulate.rs (the chain against `modulate`), tests/modulate_mesa.rs (OSMesa).

use crate::cost::{prim, Cost};
use crate::counters::Counters;
use crate::error::{check_range, ConfigError};
use crate::unit::{Signal, Timing, Unit, Width};
use crate::units::modulate::{Modulate, ModulateMode};
use crate::units::texture_combiner::binary32;
use crate::unorm::max_code;
use serde::{Deserialize, Serialize};

/// Most operand ports (a GeForce3 has 4 texture units; 8 leaves room).
pub const MAX_OPERANDS: usize = 8;
/// Operand ports by default: primary colour × texture 0 × texture 1.
pub const DEFAULT_OPERANDS: u32 = 3;

/// One input word: the operands (the first `operands` are read).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct ModulateChainIn {
    /// The operands, u(n) codes, multiplied left to right; only the first `operands`
    /// are read.
    pub ops: [u32; MAX_OPERANDS],
}

const OP_NAMES: [&str; MAX_OPERANDS] = ["op0", "op1", "op2", "op3", "op4", "op5", "op6", "op7"];

/// How a [`ModulateChain`] carries its value from one stage to the next.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum ChainRounding {
    /// Every stage is the `modulate` datapath: its u(n) result feeds the next stage
    /// (default; an 8-bit register between texture stages, as on a GeForce).
    #[default]
    PerStage,
    /// Mesa 22.3's evaluation (llvmpipe and softpipe): each operand becomes the
    /// binary32 fl(c · fl(1/N)), the stages multiply in binary32 left to right
    /// (round to nearest even), and one conversion to u(n) ends the chain: the low n
    /// mantissa bits of fl(fl(v · (1 − 2⁻ⁿ)) + 2²³⁻ⁿ). Within 10⁻⁴ LSB of the exact
    /// product the float error decides the code, so an exact-integer single rounding
    /// would not be Mesa's. Only `ModulateMode::Exact` can be fused. At n ≠ 8 this is
    /// the same rule with n-bit unorms, an extrapolation (only 8 bits is checked).
    Fused,
}

impl ChainRounding {
    /// Both choices, the default (`PerStage`) first, for sweeps.
    pub const ALL: [ChainRounding; 2] = [ChainRounding::PerStage, ChainRounding::Fused];
}

/// A chain of MODULATE stages on n-bit unorms: out = Π operands, left to right.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ModulateChain {
    modulate: Modulate,
    rounding: ChainRounding,
    /// Operand ports: k operands, k − 1 stages.
    operands: u32,
}

impl ModulateChain {
    /// `bits` in 1 ..= 16 (error names `modulate.bits`); `Fused` only with
    /// `ModulateMode::Exact` (error names `modulate.chain_rounding`). The unit has
    /// [`DEFAULT_OPERANDS`] operand ports ([`Self::with_operands`] to change);
    /// [`Self::apply`] takes any number.
    pub fn new(
        bits: u32,
        mode: ModulateMode,
        rounding: ChainRounding,
    ) -> Result<Self, ConfigError> {
        let modulate = Modulate::new(bits, mode)?;
        if rounding == ChainRounding::Fused && mode != ModulateMode::Exact {
            return Err(ConfigError::invalid(
                "modulate.chain_rounding",
                &format!(
                    "fused rounding is Mesa's float datapath; it has no {mode:?} mode (use exact)"
                ),
            ));
        }
        Ok(ModulateChain {
            modulate,
            rounding,
            operands: DEFAULT_OPERANDS,
        })
    }

    /// The same chain with `k` operand ports, 1 ..= [`MAX_OPERANDS`] (error names
    /// `modulate_chain.operands`).
    pub fn with_operands(self, k: u32) -> Result<Self, ConfigError> {
        check_range("modulate_chain.operands", k as u64, 1, MAX_OPERANDS as u64)?;
        Ok(ModulateChain {
            operands: k,
            ..self
        })
    }

    /// Operand ports of the unit (the kernel's chain length).
    pub fn operands(&self) -> u32 {
        self.operands
    }

    /// The GeForce default: 8-bit exact stages, per-stage rounding.
    pub fn geforce() -> Self {
        ModulateChain {
            modulate: Modulate::geforce(),
            rounding: ChainRounding::PerStage,
            operands: DEFAULT_OPERANDS,
        }
    }

    /// The `modulate` datapath of each stage (its width n and rounding mode).
    pub fn modulate(&self) -> &Modulate {
        &self.modulate
    }

    /// Where the value between two stages is rounded: per stage or once at the end.
    pub fn rounding(&self) -> ChainRounding {
        self.rounding
    }

    /// Π operands (each masked to n wires) through the chain; an empty chain is the
    /// top code (1.0), a one-operand chain the operand.
    pub fn apply(&self, operands: &[u32]) -> u32 {
        let n = self.modulate.bits();
        let max = max_code(n);
        let Some((&first, rest)) = operands.split_first() else {
            return max;
        };
        match self.rounding {
            ChainRounding::PerStage => rest
                .iter()
                .fold(first & max, |acc, &op| self.modulate.apply(acc, op)), // u(n) per stage
            ChainRounding::Fused => {
                if rest.is_empty() {
                    return first & max;
                }
                // binary32 throughout: a product of values in [0, 1] stays in [0, 1].
                // A value below 2⁻⁹⁷ converts to 0 whatever follows (every factor is
                // ≤ 1), so it is flushed there, keeping binary32 clear of subnormals.
                let v = rest
                    .iter()
                    .fold(binary32::from_unorm(first & max, n), |acc, &op| {
                        if acc >> 23 < 30 {
                            0
                        } else {
                            binary32::mul(acc, binary32::from_unorm(op & max, n))
                        }
                    });
                binary32::to_unorm(v, n)
            }
        }
    }
}

impl Unit for ModulateChain {
    type In = ModulateChainIn;
    type Out = u32;
    type State = ();

    fn name(&self) -> &'static str {
        "modulate_chain"
    }

    fn kernel(&self, _: &mut (), input: &ModulateChainIn, _ctr: &mut Counters) -> u32 {
        // Nothing to count: products of values ≤ 1 cannot leave u(n) (module notes).
        self.apply(&input.ops[..self.operands as usize])
    }

    fn timing(&self) -> Timing {
        let stages = self.operands.saturating_sub(1);
        match self.rounding {
            // k − 1 `modulate` datapaths (2 clocks each: multiplier, rounding adders).
            ChainRounding::PerStage => Timing {
                latency: (2 * stages).max(1),
                ii: 1,
            },
            // 1 clock u(n) → binary32, 2 per binary32 multiply (significand product;
            // normalise and round), 2 for the conversion (scale, add the magic bias).
            ChainRounding::Fused => Timing {
                latency: if stages == 0 { 1 } else { 3 + 2 * stages },
                ii: 1,
            },
        }
    }

    fn cost(&self) -> Cost {
        let n = self.modulate.bits();
        let k = self.operands;
        let stages = k.saturating_sub(1);
        let base = Cost::default()
            .part("operand registers", prim::register(k * n))
            .part("output register", prim::register(n));
        if stages == 0 {
            return base;
        }
        match self.rounding {
            ChainRounding::PerStage => {
                // Each stage is one `modulate` unit (its registers included).
                let m = self.modulate.cost().cells;
                base.part("modulate stages (k − 1)", m * stages as f64)
            }
            ChainRounding::Fused => {
                // u(n) → binary32: c · fl(1/N), a 24 × n significand product, rounded;
                // binary32 multiply: 24 × 24 significand product, 8-bit exponent adder,
                // normalise (1-bit shift) and round to nearest even (24-bit adder);
                // to u(n): a 24 × 24 product by (1 − 2⁻ⁿ) and the magic-number adder.
                let to_float = prim::multiplier(24, n) + prim::adder(24) + prim::register(32);
                let fmul = prim::multiplier(24, 24)
                    + prim::adder(8)
                    + prim::mux(24)
                    + prim::adder(24)
                    + prim::register(2 * 32);
                let to_unorm = prim::multiplier(24, 24) + prim::adder(24) + prim::register(32);
                base.part("u(n) → binary32 (k)", to_float * k as f64)
                    .part("binary32 multipliers (k − 1)", fmul * stages as f64)
                    .part("binary32 → u(n)", to_unorm)
            }
        }
    }

    fn widths(&self) -> Vec<Width> {
        vec![
            Width {
                name: "bits",
                bits: self.modulate.bits(),
            },
            Width {
                name: "operands",
                bits: self.operands,
            },
        ]
    }

    fn in_signals(&self, i: &ModulateChainIn) -> Vec<Signal> {
        let n = self.modulate.bits();
        (0..self.operands as usize)
            .map(|j| Signal::new(OP_NAMES[j], n, i.ops[j] as u64))
            .collect()
    }

    fn out_signals(&self, o: &u32) -> Vec<Signal> {
        vec![Signal::new("y", self.modulate.bits(), *o as u64)]
    }
}
