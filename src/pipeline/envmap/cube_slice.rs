//! A cube-map slice of the voxel map: six F × F faces stacked as one texture. Its own
//! file because both the slice elaboration (`slice.rs`, which makes slices) and the
//! voxel map (`voxmap.rs`, which caches them) hold it.

/// A cube map of six F × F RGB faces of unorm codes, stacked as one F × 6F texture
/// (row-major, width F; face f in rows f·F ..< (f+1)·F).
#[derive(Clone, Debug, PartialEq)]
pub struct Slice {
    pub(super) face: u32,
    pub(super) bits: u32,
    pub(super) lambda: f64,
    pub(super) data: Vec<[u32; 3]>,
}

impl Slice {
    /// Face side F.
    pub fn face_side(&self) -> u32 {
        self.face
    }
    /// Width of the stacked texture (F).
    pub fn width(&self) -> u32 {
        self.face
    }
    /// Height of the stacked texture (6F).
    pub fn height(&self) -> u32 {
        6 * self.face
    }
    pub fn bits(&self) -> u32 {
        self.bits
    }
    pub fn lambda(&self) -> f64 {
        self.lambda
    }
    pub fn data(&self) -> &[[u32; 3]] {
        &self.data
    }
    /// Bytes as stored (6F² texels × 3 channels × ⌈bits/8⌉), as [`super::voxmap::VoxelMap::bytes`].
    pub fn bytes(&self) -> u64 {
        6 * (self.face as u64).pow(2) * 3 * (self.bits as u64).div_ceil(8)
    }
}
