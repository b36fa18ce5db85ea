//! The unit contract: config (the implementing struct, validated on construction),
//! kernel, timing and cost, kept apart.

use crate::cost::Cost;
use crate::counters::Counters;
use serde::Serialize;
use std::fmt::Debug;

/// Pipeline timing of a unit under its current config.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Timing {
    /// Clocks from accepting an input to presenting its output (≥ 1: outputs are registered).
    pub latency: u32,
    /// Initiation interval: clocks between accepted inputs (≥ 1).
    pub ii: u32,
}

impl Timing {
    /// Clocks to stream `n` inputs through, from the clock accepting the first input
    /// through the clock presenting the last output: (n − 1)·II + latency + 1.
    /// The tick driver proves this.
    pub fn span_cycles(&self, n: u64) -> u64 {
        if n == 0 {
            0
        } else {
            (n - 1) * self.ii as u64 + self.latency as u64 + 1
        }
    }

    /// Cycles inputs wait because II > 1: (n − 1)·(II − 1).
    pub fn span_stalls(&self, n: u64) -> u64 {
        n.saturating_sub(1) * (self.ii as u64 - 1)
    }
}

/// A named bit field of an input or output word, for VCD traces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Signal {
    /// Signal name as it appears in the VCD (e.g. `a`, `out`).
    pub name: &'static str,
    /// Width of the field in bits (the VCD variable's width).
    pub width: u32,
    /// The field's value, in the low `width` bits.
    pub value: u64,
}

impl Signal {
    /// A signal `name` of `width` bits carrying `value`.
    pub fn new(name: &'static str, width: u32, value: u64) -> Self {
        Signal { name, width, value }
    }
}

/// A named width of a unit's config (for `units` tables and sweeps).
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Width {
    /// Config field the width comes from (e.g. `bits`, `texel_bits`).
    pub name: &'static str,
    /// Width in bits.
    pub bits: u32,
}

/// A hardware block. The implementing struct is the validated config (and any RAM
/// the unit holds); `kernel` is a pure function of config, input word and state.
pub trait Unit {
    /// One input word (one pixel / fragment / step).
    type In: Clone + Debug;
    /// One output word.
    type Out: Clone + Debug + PartialEq;
    /// State carried from one input to the next (accumulators); `()` if none.
    type State: Clone + Debug + PartialEq;

    /// The unit's name, as in `rtl_model/src/units/<name>.rs`.
    fn name(&self) -> &'static str;

    /// The datapath on raw integers. Counts table reads, memory bytes, saturations,
    /// overflows and underflows into `ctr`; the drivers count cycles and pixels.
    fn kernel(&self, state: &mut Self::State, input: &Self::In, ctr: &mut Counters) -> Self::Out;

    /// The batch kernel: `kernel` over a chunk of inputs, outputs appended to `out` in
    /// order. It must leave the same outputs, state and counters as calling `kernel` on
    /// each input in turn (the span driver is its reference; `tests/common` checks all
    /// three drivers for every unit). A unit overrides it with a faster form of the
    /// same arithmetic (a form picked from the config at construction, a loop the
    /// compiler vectorises, counters summed per chunk); the default is the per-word
    /// kernel.
    fn kernel_batch(
        &self,
        state: &mut Self::State,
        inputs: &[Self::In],
        out: &mut Vec<Self::Out>,
        ctr: &mut Counters,
    ) {
        out.extend(inputs.iter().map(|x| self.kernel(state, x, ctr)));
    }

    /// Latency and initiation interval under the current config.
    fn timing(&self) -> Timing;

    /// Gate cost (NAND2 equivalents, with a breakdown) and RAM/ROM bits under the current
    /// config.
    fn cost(&self) -> Cost;

    /// The configured widths, by name.
    fn widths(&self) -> Vec<Width>;

    /// Input word as named fields (for traces).
    fn in_signals(&self, input: &Self::In) -> Vec<Signal>;

    /// Output word as named fields (for traces).
    fn out_signals(&self, out: &Self::Out) -> Vec<Signal>;
}

/// Summary of a unit for tables and `units --json`.
#[derive(Clone, Debug, Serialize)]
pub struct UnitSummary {
    /// The unit's name, as in `rtl_model/src/units/<name>.rs`.
    pub name: &'static str,
    /// Clocks from an input accepted to its output presented.
    pub latency: u32,
    /// Initiation interval: clocks between accepted inputs.
    pub ii: u32,
    /// Logic and register area in NAND2 equivalents.
    pub gates_nand2: f64,
    /// RAM/ROM bits the unit holds, apart from the gates.
    pub ram_bits: u64,
    /// The configured widths, by name.
    pub widths: Vec<Width>,
    /// Named parts and their NAND2 equivalents.
    pub breakdown: Vec<(String, f64)>,
}

impl UnitSummary {
    /// The summary of unit `u` under its current config.
    pub fn of<U: Unit>(u: &U) -> Self {
        let t = u.timing();
        let c = u.cost();
        UnitSummary {
            name: u.name(),
            latency: t.latency,
            ii: t.ii,
            gates_nand2: c.gates_nand2(),
            ram_bits: c.ram_bits,
            widths: u.widths(),
            breakdown: c.breakdown,
        }
    }
}
