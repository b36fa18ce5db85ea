//! f64 twin of shadow_compare: being written.
