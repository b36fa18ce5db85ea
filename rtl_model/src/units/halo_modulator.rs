//! halo_modulator — stub, being written.
