//! f64 twin of glare_condition — stub, being written.
