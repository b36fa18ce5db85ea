//! f64 twin of gaussian_noise — stub, being written.
