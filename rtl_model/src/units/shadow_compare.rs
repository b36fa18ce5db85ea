//! shadow_compare: being written.
