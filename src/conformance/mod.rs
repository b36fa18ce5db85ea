//! `conformance`: the model against captures of real GeForce3-class silicon.
//!
//! The captures are the CC0 framebuffer PNGs of an original Xbox (NV2A: NV20 register
//! combiners, GeForce3-era blend, shadow compare and T&L) running the test programs of
//! github.com/abaire/nxdk_pgraph_tests (MIT), stored in
//! github.com/abaire/nxdk_pgraph_tests_golden_results. Each hardware test is described
//! here as data — where each patch lies in the 640 × 480 capture and what the model's
//! units predict inside it — written from reading the test's source (no code of it is
//! copied). `conformance extract` reads a checkout of the captures and keeps, per
//! region, the hardware's pixels run-length encoded ([`store`]) in `tables/conformance/`;
//! `conformance run` compares the predictions with those, or with the full images.

pub mod blend;
mod case;
pub mod cli;
pub mod combiner;
pub mod run;
pub mod shadow;
pub mod specular;
pub mod store;

pub use case::{Case, Chip, Prediction, Rect, Region, Suite};

/// Every suite, in the order reports list them.
pub fn suites() -> [&'static Suite; 4] {
    [
        &combiner::SUITE,
        &blend::SUITE,
        &shadow::SUITE,
        &specular::SUITE,
    ]
}
