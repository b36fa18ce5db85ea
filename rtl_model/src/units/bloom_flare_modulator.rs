//! bloom_flare_modulator — stub, being written.
