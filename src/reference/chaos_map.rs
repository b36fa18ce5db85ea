//! f64 twin of chaos_map — stub, being written.
