//! The elaboration report's row: a unit a frame elaborated, or one it left out and
//! what that saved. Shared by every pipeline (it lives in the report, not inside one
//! pipeline).

use rtl_model::UnitSummary;

/// A unit the frame elaborated, or one it left out.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Elaborated {
    pub name: String,
    pub summary: Option<UnitSummary>,
    /// Why it was left out (None if elaborated).
    pub left_out: Option<String>,
    /// Gates the unit would have cost (for left-out units).
    pub gates_saved: f64,
    /// Cycles it would have run (for left-out units): the fragments it would have seen.
    pub cycles_saved: u64,
}
