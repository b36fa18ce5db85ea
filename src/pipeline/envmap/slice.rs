//! The 2D-slice elaboration: a scene whose roughness is uniform needs only one
//! sphere of the voxel map, so it is rendered with a 2D texture — a CUBE MAP, as
//! GeForce3 addressed environment maps — and the 2D (bilinear) `texture_sampler`
//! instead of the 3D (trilinear) one.
//!
//! # Why a slice is enough
//!
//! With a uniform smoothness λ every lookup t = r·λ (r a unit reflection vector) lies
//! on the sphere |t| = λ, so the 3D map is only ever read on that sphere.
//!
//! # The cube map: six F × F faces, resampled from the voxel map at radius λ
//!
//! The faces follow OpenGL's cube-map table (faces +x, −x, +y, −y, +z, −z;
//! `reference::cube_map_address`). Face texel (i, j) has the direction
//! d = face_direction(face, (i + ½)/F, (j + ½)/F) and holds the voxel map's trilinear
//! value at t = λ·d/|d| (f64 on the voxel codes, rounded to a code of the map's width:
//! the build-time texture, host work). We resample the map rather than prefilter the
//! environment again at Λ = g(λ), for three reasons:
//! - it works for any map, exact or accelerated;
//! - it costs 6F² trilinear reads instead of 6F² prefilters at Λ up to 45 000;
//! - the 2D render then differs from the 3D render only by the resampling, which the
//!   tests bound. Re-prefiltering would change the error against the truth as well.
//!
//! The six faces are stored as ONE F × 6F texture (face f in rows f·F ..< (f+1)·F) in
//! one 2D sampler, so its texel RAM (6F²·3·bits) is counted once and honestly. The
//! `cube_map_address` unit clamps each face coordinate to the texel-centre range
//! [½, F − ½], which with bilinear filtering is clamp-to-edge on the face: a lookup
//! never filters across a face edge. GeForce3 did not filter across cube faces either;
//! the seams (a texel-wide discontinuity of the filtered value at a face edge) are the
//! known cube-map artefact, and are in the 2D-vs-3D difference the tests bound.
//!
//! # The face side F
//!
//! By default F is the smallest power of two ≥ 4s/π ([`default_face_side`]): the
//! cube map's coarsest texel density, F/2 texels per radian at a face centre, is then
//! ≥ the former equirectangular 4s × 2s slice's density 4s/2π = 0.64·s texels per
//! radian (its equator; it was finer towards the poles). For s = 2^k that is F = 2s
//! (256 at s = 128: F/2 = 128 texels per radian against 81.5; 2.0 texels per voxel on
//! the λ = 1 shell, whose radius is s/2 voxels, against 1.27), capped at 512 (6F ≤ the
//! sampler's 4096 rows).
//!
//! # Addressing: the units, not the host
//!
//! The `reflection_vector` unit's s16.8 texel words c = (t + 1)/2 · s go into the
//! `cube_map_address` unit (d = c − s/2: face, (sc/|ma| + 1)/2 · F and the stacked
//! word), whose output is the 2D sampler's input word ([`cube_unit`]; the renderer
//! checks that the 2D sampler reads that word format). With
//! `Reflection::HostF64` the renderer keeps an f64 comparison path: the f64 r through
//! the twin's face selection ([`host_cube_coord`]).

use rayon::prelude::*;
use rtl_model::units::cube_map_address::{CubeMapAddress, CubeMapAddressConfig};
use rtl_model::units::texture_sampler::{TextureSampler, TextureSamplerConfig};
use rtl_model::{ConfigError, UnitSummary};
use serde::Serialize;

pub use super::cube_slice::Slice;
use super::voxmap::{SliceTexture, VoxelMap};
use crate::reference::cube_map_address::{face_st, stacked_st, texel_centre_directions};
use crate::report::elaboration::Elaborated;
use crate::scene::math::Vec3;

/// Largest face side: 6F rows must fit the sampler's 4096, and F is a power of two.
pub const MAX_FACE_SIDE: u32 = 512;

/// F = the smallest power of two ≥ 4s/π (2s for s = 2^k), within 2 ..= 512.
pub fn default_face_side(s: u32) -> u32 {
    let min = (4.0 * s as f64 / std::f64::consts::PI).ceil() as u32;
    min.max(2).next_power_of_two().min(MAX_FACE_SIDE)
}

/// Resample `map` on the sphere |t| = `lambda` into a cube map of face side `face`
/// (see the module notes). Errors: "envmap_slice.lambda" (not finite or outside
/// [0, 1]), "envmap_slice.size" (F not a power of two in 2 ..= 512).
pub fn slice_from_map(map: &VoxelMap, lambda: f64, face: u32) -> Result<Slice, ConfigError> {
    let lambda = rtl_model::error::check_finite("envmap_slice.lambda", lambda)?;
    if !(0.0..=1.0).contains(&lambda) {
        return Err(ConfigError::out_of_range(
            "envmap_slice.lambda",
            lambda,
            0.0,
            1.0,
        ));
    }
    rtl_model::error::check_range("envmap_slice.size", face.into(), 2, MAX_FACE_SIDE.into())?;
    if !face.is_power_of_two() {
        return Err(ConfigError::invalid(
            "envmap_slice.size",
            &format!("the cube-map face side must be a power of two, not {face}"),
        ));
    }
    let s = map.side();
    let sf = s as f64;
    let max_code = map.max_code() as f64;
    // Texels are independent: in parallel (rayon), each texel's sum in a fixed order,
    // collected in texel order (same bytes on any thread count).
    let dirs: Vec<[f64; 3]> = texel_centre_directions(face).collect();
    let data = dirs
        .par_iter()
        .map(|d| resample(map, lambda, sf, max_code, d))
        .collect();
    Ok(Slice {
        face,
        bits: map.bits(),
        lambda,
        data,
    })
}

/// The map's trilinear value at t = λ·d (f64 on the codes), rounded to a code.
fn resample(map: &VoxelMap, lambda: f64, sf: f64, max_code: f64, d: &[f64; 3]) -> [u32; 3] {
    let s = map.side();
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
    acc.map(|a| a.round().clamp(0.0, max_code) as u32)
}

/// The HostF64 comparison path: the normalised coordinate of the stacked texture
/// (s/F, t/(6F)) of direction `r` by the twin's exact face selection (clamped to the
/// face's texel centres). A zero or non-finite `r` gives face 0's centre.
pub fn host_cube_coord(r: Vec3, face: u32) -> [f64; 3] {
    let ff = face as f64;
    let (f, st) = face_st([r.x, r.y, r.z], ff);
    let stk = stacked_st(f, st, ff);
    [stk[0] / ff, stk[1] / (6.0 * ff), 0.0]
}

/// The 2D sampler holding `slice`: GeForce defaults (8-bit weights, 8 sub-texel bits,
/// bilinear over 4 texels), 3 channels of the slice's width, the F × 6F stacked
/// texture, clamp to edge (the face clamp is the `cube_map_address` unit's).
pub fn sampler_2d(slice: &Slice) -> Result<TextureSampler, ConfigError> {
    let texels: Vec<u32> = slice.data.iter().flatten().copied().collect();
    TextureSampler::new(
        TextureSamplerConfig {
            channels: 3,
            texel_bits: slice.bits,
            ..TextureSamplerConfig::geforce_2d(slice.width(), slice.height())
        },
        &texels,
    )
    .map_err(|e| e.within("envmap_slice"))
}

/// The `cube_map_address` unit of a map of side `s` (a power of two; otherwise the
/// next one up, for the cost only — the unit path needs a power of two anyway) for
/// faces of side `face` (a power of two): its input words are the `reflection_vector`
/// unit's, which the renderer builds in the 3D sampler's coordinate format `words`, and
/// its output words are the 2D sampler's, the same GeForce s16.8 format; the
/// reciprocal at the GeForce3 defaults.
pub fn cube_unit(
    words: &TextureSamplerConfig,
    s: u32,
    face: u32,
) -> Result<CubeMapAddress, ConfigError> {
    CubeMapAddressConfig {
        in_int_bits: words.coord_int_bits,
        in_frac_bits: words.coord_frac_bits,
        side_log2: s.max(1).next_power_of_two().trailing_zeros(),
        face_log2: face.max(2).next_power_of_two().trailing_zeros(),
        coord_int_bits: words.coord_int_bits,
        coord_frac_bits: words.coord_frac_bits,
        ..CubeMapAddressConfig::geforce3()
    }
    .build()
    .map_err(|e| e.within("envmap_slice"))
}

/// The 3D sampler holding `map` (the renderer's: GeForce3 defaults, trilinear over 8
/// texels, clamp to edge): uploaded on the map's first render and kept with the map
/// (`VoxelMap::texture`), as a texture is uploaded once, not per frame.
pub fn sampler_3d(map: &VoxelMap) -> Result<&TextureSampler, ConfigError> {
    map.texture_3d(upload_3d)
}

/// The cube map of `map` at radius `lambda` with face side `face`
/// ([`slice_from_map`]) in its 2D sampler ([`sampler_2d`]): made on the first render
/// that needs it and kept with the map, as a texture is (errors as theirs).
pub fn cube_texture(map: &VoxelMap, lambda: f64, face: u32) -> Result<SliceTexture, ConfigError> {
    map.texture_slice((lambda.to_bits(), face), |m| {
        let sl = slice_from_map(m, lambda, face)?;
        Ok((sampler_2d(&sl)?, sl))
    })
}

/// The upload behind [`sampler_3d`].
fn upload_3d(map: &VoxelMap) -> Result<TextureSampler, ConfigError> {
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
    /// True: the 2D cube-map path (uniform λ); false: the 3D map.
    pub slice_2d: bool,
    /// The samplers and the cube-map address unit, elaborated or left out (print with
    /// `crate::report::table::elaboration_table`).
    pub units: Vec<Elaborated>,
    /// Texture bytes the elaborated path holds (cube map or voxel map).
    pub texture_bytes: u64,
    /// Texture bytes saved against the 3D map (0 on the 3D path, and 0 when the cube
    /// map is the larger, as at s ≤ 16 with F = 2s).
    pub texture_bytes_saved: u64,
    /// Gates (NAND2 eq.) saved against the 3D path: the 3D sampler's minus the 2D
    /// sampler's and the `cube_map_address` unit's (may be negative: the texel RAM is
    /// not in the gate count).
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

/// The elaboration report of a render: `two_d` is the 2D sampler and its cube map when
/// the 2D path was taken; `three_d` the 3D sampler (elaborated, or built only to count
/// what was left out); `cube` the `cube_map_address` unit (elaborated on the 2D path,
/// left out on the 3D path; on the 2D path with `cube_used` false — the
/// `Reflection::HostF64` comparison path — it is listed as replaced by host f64, but
/// its gates still count against the saving: a hardware 2D path needs it).
/// `fragments` is the number of lookups; the left-out 3D sampler's `cycles_saved` is
/// `fragments` × (its II − the 2D sampler's II).
pub fn elaboration(
    two_d: Option<(&TextureSampler, &Slice)>,
    three_d: &TextureSampler,
    cube: &CubeMapAddress,
    cube_used: bool,
    map: &VoxelMap,
    fragments: u64,
) -> Elaboration {
    let s3 = UnitSummary::of(three_d);
    let sc = UnitSummary::of(cube);
    match two_d {
        Some((s2d, slice)) => {
            let s2 = UnitSummary::of(s2d);
            let gates_saved = s3.gates_nand2 - s2.gates_nand2 - sc.gates_nand2;
            // The 2D sampler serves the same lookups; what is saved is the 3D one's
            // extra initiation interval (8 texels over 4 ports: II 2 against 1).
            let cycles_saved = fragments * u64::from(s3.ii.saturating_sub(s2.ii));
            let cube_row = if cube_used {
                Elaborated {
                    name: "cube_map_address".into(),
                    summary: Some(sc),
                    left_out: None,
                    gates_saved: 0.0,
                    cycles_saved: 0,
                }
            } else {
                Elaborated {
                    name: "cube_map_address".into(),
                    summary: None,
                    left_out: Some(
                        "Reflection::HostF64: the host addresses the cube map in f64 \
                         (comparison path; its gates still count against the saving)"
                            .into(),
                    ),
                    gates_saved: sc.gates_nand2,
                    cycles_saved: 0,
                }
            };
            Elaboration {
                slice_2d: true,
                units: vec![
                    Elaborated {
                        name: "texture_sampler (2D cube map)".into(),
                        summary: Some(s2),
                        left_out: None,
                        gates_saved: 0.0,
                        cycles_saved: 0,
                    },
                    cube_row,
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
            units: vec![
                Elaborated {
                    name: "texture_sampler (3D map)".into(),
                    summary: Some(s3),
                    left_out: None,
                    gates_saved: 0.0,
                    cycles_saved: 0,
                },
                Elaborated {
                    name: "cube_map_address".into(),
                    summary: None,
                    left_out: Some("3D map: addressed by (t + 1)/2 · s, no cube map".into()),
                    gates_saved: sc.gates_nand2,
                    cycles_saved: 0,
                },
            ],
            texture_bytes: map.bytes(),
            texture_bytes_saved: 0,
            gates_saved: 0.0,
            roughness_texture_bytes: 0,
        },
    }
}
