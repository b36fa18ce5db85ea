//! Phong ground truth — stub, being written (issue 5).
