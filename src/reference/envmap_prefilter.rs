//! Multi-scale environment map prefilter (f64) — stub, being written (issue 5).
