//! polygon_interpolator: being written.
