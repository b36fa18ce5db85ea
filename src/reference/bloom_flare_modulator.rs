//! f64 twin of bloom_flare_modulator — stub, being written.
