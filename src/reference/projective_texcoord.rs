//! f64 twin of projective_texcoord: being written.
