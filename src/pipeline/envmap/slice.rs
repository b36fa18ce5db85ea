//! The 2D-slice elaboration (issue 5): a scene whose roughness is uniform needs only one
//! sphere of the voxel map, so it is rendered with a 2D texture and the 2D (bilinear)
//! `texture_sampler` instead of the 3D (trilinear) one.
//!
//! # Why a slice is enough
//!
//! With a uniform smoothness λ every lookup t = r·λ (r a unit reflection vector) lies
//! on the sphere |t| = λ, so the 3D map is only ever read on that sphere.
//!
//! # The choice: resample the voxel map at radius λ (not re-prefilter the environment)
//!
//! The slice is an equirectangular W × H map (the project's convention:
//! `src/scene/envmap.rs`; texel (i, j) at φ = 2π(i + ½)/W, θ = π(j + ½)/H,
//! d = (sin θ sin φ, cos θ, −sin θ cos φ)). Texel (i, j) holds the voxel map's
//! trilinear value at t = λ·d (f64 on the voxel codes, rounded to a code of the map's
//! width). We resample the map rather than prefilter the environment again at
//! Λ = g(λ), for three reasons:
//! - it works for any map, exact or accelerated;
//! - it costs W·H trilinear reads instead of W·H prefilters at Λ up to 45 000;
//! - the 2D render then differs from the 3D render only by the resampling, which the
//!   tests bound. Re-prefiltering would change the error against the truth as well.
//!
//! By default W = 4s and H = 2s ([`default_slice_size`]). At λ = 1 the equator of the
//! sphere crosses π·s voxels (402 at s = 128), so the slice has about 1.3 texels per
//! voxel along the equator, and more towards the poles and at smaller λ.
//!
//! # What is f64 (a gap, like the reflection)
//!
//! The slice address (φ/2π, θ/π) of r is computed on the host in f64
//! ([`slice_coord`]). GeForce3 has no latitude–longitude addressing: it would use a
//! cube map (six 2D faces, the same bilinear sampler). The sampler, the texel RAM and
//! the coordinate hand-over are the units', as on the 3D path.

use rtl_model::units::texture_sampler::{AddressMode, TextureSampler, TextureSamplerConfig};
use rtl_model::{ConfigError, UnitSummary};
use serde::Serialize;

use super::voxmap::VoxelMap;
use crate::pipeline::shafts::frame::Elaborated;
use crate::scene::envmap::dir_to_uv;
use crate::scene::math::Vec3;

/// The sampler's largest side (texture_sampler's MAX_SIZE).
const MAX_SLICE_SIDE: u32 = 4096;

/// An equirectangular W × H RGB slice of unorm codes (row-major, row 0 at +y).
#[derive(Clone, Debug, PartialEq)]
pub struct Slice {
    width: u32,
    height: u32,
    bits: u32,
    lambda: f64,
    data: Vec<[u32; 3]>,
}

impl Slice {
    pub fn width(&self) -> u32 {
        self.width
    }
    pub fn height(&self) -> u32 {
        self.height
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
    /// Bytes as stored (3 channels × ⌈bits/8⌉ per texel), as [`VoxelMap::bytes`].
    pub fn bytes(&self) -> u64 {
        self.width as u64 * self.height as u64 * 3 * (self.bits as u64).div_ceil(8)
    }
}

/// W = 4s, H = 2s, capped at 4096 × 2048.
pub fn default_slice_size(s: u32) -> (u32, u32) {
    let w = (4 * s).clamp(2, MAX_SLICE_SIDE);
    (w, (w / 2).max(1))
}

/// Resample `map` on the sphere |t| = `lambda` into a `width` × `height` slice (see the
/// module notes). Errors: "envmap_slice.lambda" (not finite or outside [0, 1]),
/// "envmap_slice.size" (a side outside 1 ..= 4096).
pub fn slice_from_map(
    map: &VoxelMap,
    lambda: f64,
    width: u32,
    height: u32,
) -> Result<Slice, ConfigError> {
    let lambda = rtl_model::error::check_finite("envmap_slice.lambda", lambda)?;
    if !(0.0..=1.0).contains(&lambda) {
        return Err(ConfigError::out_of_range(
            "envmap_slice.lambda",
            lambda,
            0.0,
            1.0,
        ));
    }
    for side in [width, height] {
        rtl_model::error::check_range("envmap_slice.size", side.into(), 1, MAX_SLICE_SIDE.into())?;
    }
    let s = map.side();
    let sf = s as f64;
    let max_code = map.max_code() as f64;
    let mut data = Vec::with_capacity(width as usize * height as usize);
    for j in 0..height {
        let theta = std::f64::consts::PI * (j as f64 + 0.5) / height as f64;
        for i in 0..width {
            let phi = std::f64::consts::TAU * (i as f64 + 0.5) / width as f64;
            let d = [
                theta.sin() * phi.sin(),
                theta.cos(),
                -theta.sin() * phi.cos(),
            ];
            // Voxel-index coordinate of t = λ·d: p = (t + 1)/2 · s − ½ (centres at
            // integers), clamped to the edge voxels (the 3D sampler's clamp to edge).
            let mut i0 = [0u32; 3];
            let mut i1 = [0u32; 3];
            let mut fr = [0f64; 3];
            for k in 0..3 {
                let p = ((lambda * d[k] + 1.0) * 0.5 * sf - 0.5).clamp(0.0, sf - 1.0);
                let f0 = p.floor();
                i0[k] = f0 as u32;
                i1[k] = (i0[k] + 1).min(s - 1);
                fr[k] = p - f0;
            }
            let mut acc = [0f64; 3];
            for corner in 0..8u32 {
                let mut w = 1.0;
                let mut idx = [0u32; 3];
                for k in 0..3 {
                    let b = (corner >> k) & 1 == 1;
                    idx[k] = if b { i1[k] } else { i0[k] };
                    w *= if b { fr[k] } else { 1.0 - fr[k] };
                }
                let v = map.get(idx[0], idx[1], idx[2]);
                for c in 0..3 {
                    acc[c] += w * v[c] as f64;
                }
            }
            data.push(acc.map(|a| a.round().clamp(0.0, max_code) as u32));
        }
    }
    Ok(Slice {
        width,
        height,
        bits: map.bits(),
        lambda,
        data,
    })
}

/// The normalised slice coordinate (φ/2π, θ/π) of direction `r` (host f64: the
/// documented gap). A zero or non-finite `r` gives (0, 0).
pub fn slice_coord(r: Vec3) -> [f64; 3] {
    let (u, v) = dir_to_uv(r);
    [u, v, 0.0]
}

/// The 2D sampler holding `slice`: GeForce defaults (8-bit weights, 8 sub-texel bits,
/// bilinear over 4 texels), 3 channels of the slice's width, wrap in φ, clamp in θ.
pub fn sampler_2d(slice: &Slice) -> Result<TextureSampler, ConfigError> {
    let texels: Vec<u32> = slice.data.iter().flatten().copied().collect();
    TextureSampler::new(
        TextureSamplerConfig {
            channels: 3,
            texel_bits: slice.bits,
            address: [AddressMode::Wrap, AddressMode::Clamp, AddressMode::Clamp],
            ..TextureSamplerConfig::geforce_2d(slice.width, slice.height)
        },
        &texels,
    )
    .map_err(|e| e.within("envmap_slice"))
}

/// The 3D sampler holding `map` (the renderer's: GeForce3 defaults, trilinear over 8
/// texels, clamp to edge).
pub fn sampler_3d(map: &VoxelMap) -> Result<TextureSampler, ConfigError> {
    let s = map.side();
    let texels: Vec<u32> = map.data().iter().flatten().copied().collect();
    TextureSampler::new(
        TextureSamplerConfig {
            channels: 3,
            texel_bits: map.bits(),
            ..TextureSamplerConfig::geforce_3d(s, s, s)
        },
        &texels,
    )
    .map_err(|e| e.within("envmap_render"))
}

/// Which lookup path a render elaborated, and what the other would have cost.
#[derive(Clone, Debug, Serialize)]
pub struct Elaboration {
    /// True: the 2D slice path (uniform λ); false: the 3D map.
    pub slice_2d: bool,
    /// The samplers, elaborated or left out (print with
    /// `crate::report::table::elaboration_table`).
    pub units: Vec<Elaborated>,
    /// Texture bytes the elaborated path holds (slice or voxel map).
    pub texture_bytes: u64,
    /// Texture bytes saved against the 3D map (0 on the 3D path).
    pub texture_bytes_saved: u64,
    /// Sampler gates (NAND2 eq.) saved against the 3D sampler (may be negative: the
    /// texel RAM is not in the gate count, and the 2D sampler addresses by wrap).
    pub gates_saved: f64,
    /// Bytes of the roughness texture (per-pixel λ, `render::LambdaSource::Texture`;
    /// its sampler is then listed in `units`); 0 with per-vertex λ.
    pub roughness_texture_bytes: u64,
}

/// Equal when the same units were elaborated or left out for the same reasons, with
/// the same gates and bytes (`Elaborated` itself has no `PartialEq`).
impl PartialEq for Elaboration {
    fn eq(&self, o: &Self) -> bool {
        let key = |e: &Elaborated| {
            (
                e.name.clone(),
                e.left_out.clone(),
                e.gates_saved,
                e.cycles_saved,
                e.summary.as_ref().map(|s| (s.gates_nand2, s.ram_bits)),
            )
        };
        self.slice_2d == o.slice_2d
            && self.texture_bytes == o.texture_bytes
            && self.texture_bytes_saved == o.texture_bytes_saved
            && self.gates_saved == o.gates_saved
            && self.roughness_texture_bytes == o.roughness_texture_bytes
            && self.units.iter().map(key).eq(o.units.iter().map(key))
    }
}

/// The elaboration report of a render: `two_d` is the 2D sampler and its slice when
/// the slice path was taken; `three_d` the 3D sampler (elaborated, or built only to
/// count what was left out). `fragments` is the number of lookups; the left-out unit's
/// `cycles_saved` is `fragments` × (its II − the 2D sampler's II).
pub fn elaboration(
    two_d: Option<(&TextureSampler, &Slice)>,
    three_d: &TextureSampler,
    map: &VoxelMap,
    fragments: u64,
) -> Elaboration {
    let s3 = UnitSummary::of(three_d);
    match two_d {
        Some((s2d, slice)) => {
            let s2 = UnitSummary::of(s2d);
            let gates_saved = s3.gates_nand2 - s2.gates_nand2;
            // The 2D sampler serves the same lookups; what is saved is the 3D one's
            // extra initiation interval (8 texels over 4 ports: II 2 against 1).
            let cycles_saved = fragments * u64::from(s3.ii.saturating_sub(s2.ii));
            Elaboration {
                slice_2d: true,
                units: vec![
                    Elaborated {
                        name: "texture_sampler (2D slice)".into(),
                        summary: Some(s2),
                        left_out: None,
                        gates_saved: 0.0,
                        cycles_saved: 0,
                    },
                    Elaborated {
                        name: "texture_sampler (3D map)".into(),
                        summary: None,
                        left_out: Some(format!(
                            "uniform λ = {}: every lookup is on |t| = λ, no 3D texture unit",
                            slice.lambda
                        )),
                        gates_saved: s3.gates_nand2,
                        cycles_saved,
                    },
                ],
                texture_bytes: slice.bytes(),
                texture_bytes_saved: map.bytes().saturating_sub(slice.bytes()),
                gates_saved,
                roughness_texture_bytes: 0,
            }
        }
        None => Elaboration {
            slice_2d: false,
            units: vec![Elaborated {
                name: "texture_sampler (3D map)".into(),
                summary: Some(s3),
                left_out: None,
                gates_saved: 0.0,
                cycles_saved: 0,
            }],
            texture_bytes: map.bytes(),
            texture_bytes_saved: 0,
            gates_saved: 0.0,
            roughness_texture_bytes: 0,
        },
    }
}
