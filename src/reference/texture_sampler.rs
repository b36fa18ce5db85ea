//! f64 twin of texture_sampler: being written.
