//! Error and cost of the modulate alternates against the exact GL rounding.

use rtl_model::units::modulate::{Modulate, ModulateMode};
use rtl_model::Unit;
use serde::Serialize;

/// One alternate's error over all operand pairs of an n-bit modulate.
#[derive(Clone, Debug, Serialize)]
pub struct AlternateRow {
    pub mode: ModulateMode,
    pub bits: u32,
    /// Max |alt − round(a·b/(2ⁿ−1))| in LSBs over all pairs.
    pub max_err: u32,
    /// Mean |alt − round(a·b/(2ⁿ−1))| in LSBs over all pairs.
    pub mean_err: f64,
    /// Mean signed error (bias) in LSBs.
    pub mean_bias: f64,
    /// Pairs that differ from the exact rounding.
    pub pairs_differing: u64,
    pub gates_nand2: f64,
}

/// Every mode against the exact mode, exhaustively over all (2ⁿ)² pairs (n ≤ 12).
pub fn modulate_alternates(bits: u32) -> Vec<AlternateRow> {
    let exact = Modulate::new(bits, ModulateMode::Exact).expect("valid width");
    let max = (1u32 << bits) - 1;
    let pairs = (max as u64 + 1).pow(2);
    ModulateMode::ALL
        .iter()
        .map(|&mode| {
            let m = Modulate::new(bits, mode).expect("valid width");
            let (mut max_err, mut sum, mut bias, mut diff) = (0u32, 0u64, 0i64, 0u64);
            for a in 0..=max {
                for b in 0..=max {
                    let d = m.apply(a, b) as i64 - exact.apply(a, b) as i64;
                    max_err = max_err.max(d.unsigned_abs() as u32);
                    sum += d.unsigned_abs();
                    bias += d;
                    diff += u64::from(d != 0);
                }
            }
            AlternateRow {
                mode,
                bits,
                max_err,
                mean_err: sum as f64 / pairs as f64,
                mean_bias: bias as f64 / pairs as f64,
                pairs_differing: diff,
                gates_nand2: m.cost().gates_nand2(),
            }
        })
        .collect()
}
