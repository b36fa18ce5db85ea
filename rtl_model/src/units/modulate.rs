//! modulate — the multi-texture combiner in GL_MODULATE: out = a · b on n-bit unorms.
//!
//! Widths: operands u(n) (n = `bits`, 8 by default, 1 ..= 16), product u(2n),
//! result u(n). The default rounds exactly, round(a·b / (2ⁿ−1)), with the shift-add
//! divide GL implementations use (Blinn): t = a·b + 2ⁿ⁻¹; out = (t + (t >> n)) >> n.
//! The alternates are real width/gate trade-offs and are kept selectable.
//!
//! A chain of MODULATE stages (GL multitexture: PREVIOUS · TEXTUREk per texture unit,
//! e.g. primary colour × texture 0 × texture 1) is the `modulate_chain` unit
//! ([`ModulateChain`], re-exported here); where the
//! value between two stages is rounded is left to the implementation by GL, and
//! [`ChainRounding`] names the two choices: `per_stage` (default) rounds every stage to
//! u(n) as the `modulate` datapath does — a GeForce register holds an 8-bit value
//! between texture stages; `fused` evaluates the chain as Mesa's software GL does
//! (binary32 products, one float → unorm conversion at the end), bit-exact against
//! llvmpipe and softpipe at 8 bits (tests/modulate_mesa.rs).

use crate::cost::{prim, Cost};
use crate::counters::Counters;
use crate::error::ConfigError;
use crate::unit::{Signal, Timing, Unit, Width};
use crate::unorm::{check_bits, max_code};
use serde::{Deserialize, Serialize};

pub use super::modulate_chain::{ChainRounding, ModulateChain};

/// How the n-bit product is brought back to n bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ModulateMode {
    /// round(a·b / (2ⁿ−1)), exact: (t + (t >> n)) >> n with t = a·b + 2ⁿ⁻¹.
    Exact,
    /// (a·b) >> n: drops the divide, biased low by up to 2 LSB.
    Shift,
    /// a·(b+1) >> n: exact at b = max, error within ±1 LSB.
    PlusOne,
    /// floor(a·b / (2ⁿ−1)): truncating divide, error within [0, 1) LSB.
    TruncDiv,
}

impl ModulateMode {
    /// Every rounding mode, the default (`Exact`) first, for sweeps.
    pub const ALL: [ModulateMode; 4] = [
        ModulateMode::Exact,
        ModulateMode::Shift,
        ModulateMode::PlusOne,
        ModulateMode::TruncDiv,
    ];
}

/// Config: operand width and rounding mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Modulate {
    bits: u32,
    mode: ModulateMode,
}

/// The second operand of [`Modulate::apply_lanes`]: a code per lane, or one code for
/// every lane.
#[derive(Clone, Copy, Debug)]
pub enum Operand<'a> {
    /// Lane i's code: `a`'s lane i takes this slice's lane i.
    Lanes(&'a [u32]),
    /// One code for every lane.
    Constant(u32),
}

/// Two n-bit unorm operands (texture colour and incoming colour).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct ModulateIn {
    /// First operand, a u(n) code (masked to `bits` wires).
    pub a: u32,
    /// Second operand, a u(n) code (masked to `bits` wires).
    pub b: u32,
}

impl Modulate {
    /// `bits` in 1 ..= 16 (error names `modulate.bits`).
    pub fn new(bits: u32, mode: ModulateMode) -> Result<Self, ConfigError> {
        check_bits("modulate.bits", bits)?;
        Ok(Modulate { bits, mode })
    }

    /// GeForce default: 8-bit, exact rounding.
    pub fn geforce() -> Self {
        Modulate {
            bits: 8,
            mode: ModulateMode::Exact,
        }
    }

    /// Operand and result width n in bits, 1 ..= 16 (GeForce: 8).
    pub fn bits(&self) -> u32 {
        self.bits
    }

    /// How the u(2n) product is brought back to n bits.
    pub fn mode(&self) -> ModulateMode {
        self.mode
    }

    /// [`Self::apply`] on lanes: `out` (cleared first) gets `apply(a[i], b(i))` for
    /// every lane of `a`, where `b` is [`Operand::Lanes`] (lane i of a slice as long
    /// as `a`) or [`Operand::Constant`] (one code for every lane). The rounding mode
    /// is chosen once, outside the loop, so the compiler runs the lanes as vectors.
    /// Panics if the operand lanes' lengths differ (a wiring error of the caller).
    pub fn apply_lanes(&self, a: &[u32], b: Operand, out: &mut Vec<u32>) {
        #[inline(always)]
        fn lanes(a: &[u32], b: Operand, out: &mut Vec<u32>, f: impl Fn(u32, u32) -> u32) {
            out.clear();
            match b {
                Operand::Lanes(b) => {
                    assert_eq!(a.len(), b.len(), "modulate: operand lanes differ");
                    out.extend(a.iter().zip(b).map(|(&x, &y)| f(x, y)));
                }
                Operand::Constant(c) => out.extend(a.iter().map(|&x| f(x, c))),
            }
        }
        // One loop per mode, each calling its mode's datapath: no match inside the
        // loop, so the lanes run as vectors.
        let n = self.bits;
        let max = max_code(n);
        // Generic over the datapath (each fn item its own type), so each loop's call
        // is known at compile time.
        #[inline(always)]
        fn with(f: impl Fn(u32, u32, u32) -> u32, n: u32, max: u32) -> impl Fn(u32, u32) -> u32 {
            move |x, y| f(n, x & max, y & max)
        }
        match self.mode {
            ModulateMode::Exact => lanes(a, b, out, with(exact, n, max)),
            ModulateMode::Shift => lanes(a, b, out, with(shift, n, max)),
            ModulateMode::PlusOne => lanes(a, b, out, with(plus_one, n, max)),
            ModulateMode::TruncDiv => lanes(a, b, out, with(trunc_div, n, max)),
        }
    }

    /// The combinational datapath on one pair (operands masked to n wires).
    ///
    /// In 32-bit words: n ≤ 16 (the constructor's bound), so every intermediate fits
    /// (Exact: t ≤ (2ⁿ−1)² + 2ⁿ⁻¹ < 2²ⁿ and t + (t >> n) ≤ 2³² − 2¹⁵ at n = 16;
    /// PlusOne: a·(b+1) ≤ (2ⁿ−1)·2ⁿ; TruncDiv: x + 1 + (x >> n) < 2²ⁿ), and the
    /// lanes run twice as wide as in 64-bit words.
    #[inline(always)]
    pub fn apply(&self, a: u32, b: u32) -> u32 {
        let n = self.bits;
        debug_assert!((1..=16).contains(&n));
        let max = max_code(n);
        let (a, b) = (a & max, b & max);
        match self.mode {
            ModulateMode::Exact => exact(n, a, b),
            ModulateMode::Shift => shift(n, a, b),
            ModulateMode::PlusOne => plus_one(n, a, b),
            ModulateMode::TruncDiv => trunc_div(n, a, b),
        }
    }
}

/// [`ModulateMode::Exact`] on u(n) codes: round(a·b / (2ⁿ−1)).
#[inline(always)]
fn exact(n: u32, a: u32, b: u32) -> u32 {
    let t = a * b + (1 << (n - 1)); // u(n) × u(n) → u(2n), + half → u(2n)
    (t + (t >> n)) >> n // u(2n) + u(n) → u(2n+1), < 2³² (above); >> n → u(n)
}

/// [`ModulateMode::Shift`] on u(n) codes: ⌊a·b / 2ⁿ⌋.
#[inline(always)]
fn shift(n: u32, a: u32, b: u32) -> u32 {
    (a * b) >> n // u(2n) >> n → u(n)
}

/// [`ModulateMode::PlusOne`] on u(n) codes: ⌊a·(b+1) / 2ⁿ⌋.
#[inline(always)]
fn plus_one(n: u32, a: u32, b: u32) -> u32 {
    (a * (b + 1)) >> n // u(n) × u(n+1) → u(2n)
}

/// [`ModulateMode::TruncDiv`] on u(n) codes: ⌊a·b / (2ⁿ−1)⌋, as
/// (x + 1 + (x >> n)) >> n for x = a·b ≤ (2ⁿ−1)².
#[inline(always)]
fn trunc_div(n: u32, a: u32, b: u32) -> u32 {
    let x = a * b; // u(2n)
    (x + 1 + (x >> n)) >> n // < 2²ⁿ (above)
}

impl Unit for Modulate {
    type In = ModulateIn;
    type Out = u32;
    type State = ();

    fn name(&self) -> &'static str {
        "modulate"
    }

    fn kernel(&self, _: &mut (), input: &ModulateIn, _ctr: &mut Counters) -> u32 {
        // No saturation or wrap is possible: a·b ≤ (2ⁿ−1)² keeps every mode within u(n).
        self.apply(input.a, input.b)
    }

    /// The per-word arithmetic inlined into one loop over the chunk (the mode is
    /// loop-invariant, so the compiler hoists its match and the loop vectorises).
    fn kernel_batch(
        &self,
        _: &mut (),
        inputs: &[ModulateIn],
        out: &mut Vec<u32>,
        _: &mut Counters,
    ) {
        out.extend(inputs.iter().map(|i| self.apply(i.a, i.b)));
    }

    fn timing(&self) -> Timing {
        // Stage 1: the n×n multiplier; stage 2: the rounding adders.
        Timing { latency: 2, ii: 1 }
    }

    fn cost(&self) -> Cost {
        let n = self.bits;
        let base = Cost::default()
            .part("operand registers", prim::register(2 * n))
            .part("product register", prim::register(2 * n))
            .part("output register", prim::register(n));
        match self.mode {
            ModulateMode::Exact => base
                .part("multiplier n×n", prim::multiplier(n, n))
                .part("add half (upper n bits)", prim::adder(n))
                .part("add t>>n", prim::adder(2 * n)),
            ModulateMode::Shift => base.part("multiplier n×n", prim::multiplier(n, n)),
            ModulateMode::PlusOne => base
                .part("incrementer b+1", prim::half_adder() * n as f64)
                .part("multiplier n×(n+1)", prim::multiplier(n, n + 1)),
            ModulateMode::TruncDiv => base
                .part("multiplier n×n", prim::multiplier(n, n))
                .part("add 1 + x>>n", prim::adder(2 * n)),
        }
    }

    fn widths(&self) -> Vec<Width> {
        vec![Width {
            name: "bits",
            bits: self.bits,
        }]
    }

    fn in_signals(&self, i: &ModulateIn) -> Vec<Signal> {
        vec![
            Signal::new("a", self.bits, i.a as u64),
            Signal::new("b", self.bits, i.b as u64),
        ]
    }

    fn out_signals(&self, o: &u32) -> Vec<Signal> {
        vec![Signal::new("y", self.bits, *o as u64)]
    }
}
