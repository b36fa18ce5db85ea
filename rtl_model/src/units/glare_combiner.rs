//! glare_combiner — stub, being written.
