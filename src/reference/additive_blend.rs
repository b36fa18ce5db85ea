//! f64 twin of additive_blend: being written.
