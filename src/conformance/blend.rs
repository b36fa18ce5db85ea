//! The `Blend_tests` suite (src/tests/blend_tests.cpp in nxdk_pgraph_tests): not described yet.

use super::{Case, Chip, Suite};

pub const SUITE: Suite = Suite {
    name: "Blend_tests",
    source: "src/tests/blend_tests.cpp",
    cases,
};

/// Every case of the suite, predicted in `chip`'s modes.
pub fn cases(_chip: Chip) -> Vec<Case> {
    Vec::new()
}
