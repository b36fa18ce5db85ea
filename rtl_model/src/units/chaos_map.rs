//! chaos_map — stub, being written.
