//! gaussian_noise — stub, being written.
