//! The `Combiner` suite (src/tests/combiner_tests.cpp in nxdk_pgraph_tests): not described yet.

use super::{Case, Chip, Suite};

pub const SUITE: Suite = Suite {
    name: "Combiner",
    source: "src/tests/combiner_tests.cpp",
    cases,
};

/// Every case of the suite, predicted in `chip`'s modes.
pub fn cases(_chip: Chip) -> Vec<Case> {
    Vec::new()
}
