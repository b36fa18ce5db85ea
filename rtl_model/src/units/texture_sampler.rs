//! texture_sampler: being written.
