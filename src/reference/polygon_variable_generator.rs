//! f64 twin of polygon_variable_generator — stub, being written.
