//! The s³ voxel map of the multi-scale environment map (Okumura's thesis, eqs. 6–9).
//!
//! Voxel (x, y, z), each in 0 .. s, has its centre at
//! t = (2(x + ½)/s − 1, 2(y + ½)/s − 1, 2(z + ½)/s − 1) ∈ (−1, 1)³, in the same world axes
//! as the environment's directions (right-handed, y up). A reflection vector r on a
//! surface of smoothness λ ∈ (0, 1] looks up t = r·λ (eq. 6): the 3D texture coordinate
//! is (t + 1)/2 ∈ [0, 1]³ (s along x, t along y, r along z, as GL's 3D textures).
//! Storage is x fastest, then y, then z. Entries are unorm codes of `bits` per channel
//! (8 by default: the thesis' 256 levels).

use std::sync::{Arc, Mutex, OnceLock};

use rtl_model::units::texture_sampler::TextureSampler;
use rtl_model::ConfigError;

use super::cube_slice::Slice;

/// Largest side accepted: the largest cube the 3D texture sampler can hold (256; the
/// scene's `environment.side` limit is the same constant).
pub const MAX_SIDE: u32 = crate::scene::limits::ENV_MAX_SIDE;

/// Cube-map slices a map keeps (most recently made last; see [`Textures`]).
const SLICES_KEPT: usize = 4;

/// A cube-map slice of a map and the 2D sampler holding it.
pub type SliceTexture = Arc<(TextureSampler, Slice)>;

/// The textures the renderer made from a map, kept with it: a texture is uploaded once
/// per map, not once per frame (the 3D upload packs s³·3 codes into the sampler's bit
/// RAM, ≈ 0.2 s at s = 128, as long as the rest of a 640 × 480 frame; a slice
/// resamples 6F² texels and uploads them). Made on first use; dropped when the map's
/// codes change; a clone of the map starts without them.
#[derive(Debug, Default)]
struct Textures {
    /// The map in the renderer's 3D sampler (`super::slice::sampler_3d`).
    three_d: OnceLock<TextureSampler>,
    /// Cube-map slices by (λ's f64 bits, face side F) (`super::slice::cube_texture`),
    /// at most [`SLICES_KEPT`].
    slices: Mutex<Vec<((u64, u32), SliceTexture)>>,
}

impl Clone for Textures {
    fn clone(&self) -> Self {
        Textures::default()
    }
}

/// An s³ RGB voxel map of unorm codes.
#[derive(Clone, Debug)]
pub struct VoxelMap {
    s: u32,
    bits: u32,
    data: Vec<[u32; 3]>,
    textures: Textures,
}

/// Equal maps hold the same codes (the uploaded textures follow from them).
impl PartialEq for VoxelMap {
    fn eq(&self, o: &Self) -> bool {
        (self.s, self.bits, &self.data) == (o.s, o.bits, &o.data)
    }
}

impl Eq for VoxelMap {}

impl VoxelMap {
    /// An all-zero map; `s` in 1 ..= [`MAX_SIDE`] (`envmap.voxels`), `bits` in 1 ..= 16
    /// (`envmap.voxel_bits`).
    pub fn new(s: u32, bits: u32) -> Result<Self, ConfigError> {
        rtl_model::error::check_range("envmap.voxels", s.into(), 1, MAX_SIDE.into())?;
        rtl_model::error::check_range("envmap.voxel_bits", bits.into(), 1, 16)?;
        Ok(VoxelMap {
            s,
            bits,
            data: vec![[0; 3]; (s as usize).pow(3)],
            textures: Textures::default(),
        })
    }

    pub fn side(&self) -> u32 {
        self.s
    }

    pub fn bits(&self) -> u32 {
        self.bits
    }

    pub fn max_code(&self) -> u32 {
        rtl_model::unorm::max_code(self.bits)
    }

    /// Linear index of voxel (x, y, z).
    pub fn index(&self, x: u32, y: u32, z: u32) -> usize {
        let s = self.s as usize;
        (z as usize * s + y as usize) * s + x as usize
    }

    /// The voxel's centre t.
    pub fn voxel_t(&self, x: u32, y: u32, z: u32) -> [f64; 3] {
        let f = |k: u32| 2.0 * (k as f64 + 0.5) / self.s as f64 - 1.0;
        [f(x), f(y), f(z)]
    }

    pub fn get(&self, x: u32, y: u32, z: u32) -> [u32; 3] {
        self.data[self.index(x, y, z)]
    }

    /// Store a value in levels of the full scale 1.0 (clamped, rounded to a code).
    pub fn set_levels(&mut self, x: u32, y: u32, z: u32, v: [f64; 3]) {
        self.drop_textures();
        let m = self.max_code() as f64;
        let i = self.index(x, y, z);
        self.data[i] = v.map(|c| (c.clamp(0.0, 1.0) * m).round() as u32);
    }

    pub fn data(&self) -> &[[u32; 3]] {
        &self.data
    }

    pub fn data_mut(&mut self) -> &mut [[u32; 3]] {
        self.drop_textures();
        &mut self.data
    }

    /// Bytes of the map as stored (3 channels × ⌈bits/8⌉ per voxel).
    /// Largest |Δ| between neighbouring voxels along any axis, any channel (codes): the
    /// trilinear filter's slope bound, D codes per texel (used by error bounds).
    pub fn max_neighbour_step(&self) -> u32 {
        let s = self.s;
        let mut d = 0;
        for z in 0..s {
            for y in 0..s {
                for x in 0..s {
                    let v = self.get(x, y, z);
                    for (nx, ny, nz) in [(x + 1, y, z), (x, y + 1, z), (x, y, z + 1)] {
                        if nx < s && ny < s && nz < s {
                            let w = self.get(nx, ny, nz);
                            for c in 0..3 {
                                d = d.max(v[c].abs_diff(w[c]));
                            }
                        }
                    }
                }
            }
        }
        d
    }

    /// The codes change: the textures made from them go.
    fn drop_textures(&mut self) {
        self.textures.three_d.take();
        match self.textures.slices.get_mut() {
            Ok(v) => v.clear(),
            Err(p) => p.into_inner().clear(),
        }
    }

    /// The 3D texture made by `upload` (`super::slice`'s, the only caller), kept.
    pub(super) fn texture_3d(
        &self,
        upload: impl FnOnce(&Self) -> Result<TextureSampler, ConfigError>,
    ) -> Result<&TextureSampler, ConfigError> {
        if let Some(t) = self.textures.three_d.get() {
            return Ok(t);
        }
        let t = upload(self)?;
        // Another thread may have uploaded the same texture meanwhile: either is it.
        Ok(self.textures.three_d.get_or_init(|| t))
    }

    /// The cube-map slice `key` = (λ bits, F) made by `make` (`super::slice`'s, the
    /// only caller), kept.
    pub(super) fn texture_slice(
        &self,
        key: (u64, u32),
        make: impl FnOnce(&Self) -> Result<(TextureSampler, Slice), ConfigError>,
    ) -> Result<SliceTexture, ConfigError> {
        let lock = || {
            self.textures
                .slices
                .lock()
                .unwrap_or_else(|p| p.into_inner())
        };
        if let Some((_, t)) = lock().iter().find(|(k, _)| *k == key) {
            return Ok(t.clone());
        }
        // Made outside the lock (it takes a while); a slice made twice is the same.
        let t = Arc::new(make(self)?);
        let mut kept = lock();
        if !kept.iter().any(|(k, _)| *k == key) {
            if kept.len() == SLICES_KEPT {
                kept.remove(0);
            }
            kept.push((key, t.clone()));
        }
        Ok(t)
    }

    pub fn bytes(&self) -> u64 {
        (self.s as u64).pow(3) * 3 * (self.bits as u64).div_ceil(8)
    }
}
