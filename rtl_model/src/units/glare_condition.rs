//! glare_condition — stub, being written.
