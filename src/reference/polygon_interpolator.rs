//! f64 twin of polygon_interpolator: being written.
