//! Power spectra — stub, being written.
