//! Environment maps — stub, being written (issue 5).
