//! additive_blend: being written.
