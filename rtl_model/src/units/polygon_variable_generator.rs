//! polygon_variable_generator — stub, being written.
