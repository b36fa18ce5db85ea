//! What the program builder and the C source writer share: the pass list's entries,
//! the per-light data and the layouts of the vertex files.

use crate::pipeline::shafts::frame::ShaftsPass;

/// One pass of the plan: exported (the shafts pass) or not, with why.
#[derive(Clone, Debug)]
pub enum Export {
    Shafts(ShaftsPass),
    NotExported { pass: String, why: String },
}

/// What the generated program's passes read, per light.
pub struct LightData {
    pub has_map: bool,
    pub color: [u32; 3],
}

/// Floats per object vertex: x, y, z (window), r, g, b (vertex colour), s, t, r, q.
pub const OBJ_FLOATS: usize = 10;
/// Floats per plane mesh vertex: x, y, F coordinate (texels), h s and t (texels),
/// plane scale S, s, t, r, q.
pub const PLANE_FLOATS: usize = 10;
/// Floats per sub-plane corner: x, y, s, t, r, q.
pub const SUB_FLOATS: usize = 6;

/// Sub-plane j's 8-bit weight of m: ⌊(j+1)·255/m⌋ − ⌊j·255/m⌋ (they sum to 255).
pub fn subplane_weight(j: u64, m: u64) -> u32 {
    (((j + 1) * 255 / m) - (j * 255 / m)) as u32
}
