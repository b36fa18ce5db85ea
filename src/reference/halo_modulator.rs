//! f64 twin of halo_modulator — stub, being written.
