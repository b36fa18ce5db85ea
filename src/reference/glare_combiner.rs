//! f64 twin of glare_combiner — stub, being written.
