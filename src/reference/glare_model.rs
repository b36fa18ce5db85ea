//! f64 model of the glare formulas — stub, being written.
