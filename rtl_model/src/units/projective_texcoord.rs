//! projective_texcoord: being written.
