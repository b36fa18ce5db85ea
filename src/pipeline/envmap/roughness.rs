//! Per-pixel roughness from a texture
//! ([`RenderOptions::lambda_source`](super::render::RenderOptions::lambda_source)): the
//! thesis' proposed fix for the per-vertex λ's smear and the intended-λ truth's errors;
//! the comparison of the two λ sources is [`super::roughness_comparison`]'s. The render
//! itself is [`super::render`]'s, which uses this file (and this file not it).
//!
//! - **Texture coordinates: object-linear texgen** ([`object_texgen`], host f64 per
//!   vertex like the rest of the vertex stage; GeForce's fixed-function T&L has it).
//!   (u, v) = the vertex position projected on two axes, mapped to [0, 1] over the
//!   object's bounding rectangle in that plane. The sphere uses the camera's right and
//!   up axes (its λ is an angle around the view axis). The teapot uses world x and y:
//!   its λ is a function of world height, and p.y is NOT a function of (p·right, p·up)
//!   (the camera looks down by 14.4°: p.y = 0.969 p·up − 0.248 p·forward, and the
//!   teapot is ±0.6 deep), whereas it is exactly v with the x–y planes. With these
//!   choices λ(u, v) ([`lambda_of_uv`]) equals the per-vertex λ at every vertex, so the
//!   two sources render the same λ function and differ only in how it reaches the
//!   pixel.
//! - **(u, v) are attributes 8 and 9 of the one polygon_interpolator**, which is then
//!   configured for [`RENDER_ATTRS_TEXTURE`] = 10 attributes (n, e, λ, z, u, v) instead
//!   of [`RENDER_ATTRS`] = 8 ([`super::interpolator`]), as GeForce3's single
//!   interpolator carries many more channels. Every attribute channel is independent in the unit, so the first 8
//!   come out bit for bit as with 8 attributes. The elaboration report lists what
//!   the 2 channels cost ([`TEXCOORD_CHANNELS`], [`texcoord_channels_cost`]: the
//!   10-attribute unit's gates minus the 8-attribute unit's). PerVertex keeps 8
//!   attributes (byte-identical images, same counters); with the intended truth its
//!   (u, v) come from a measurement-only walk of the 10-attribute configuration (not
//!   counted or elaborated; the same walk, checked fragment for fragment, error
//!   "envmap_render.texcoord"), so both sources see the same (u, v) codes.
//! - **The texture**: side × side, 8-bit, 1 channel, texel (i, j) = round(255 ·
//!   λ((i + ½)/side, (j + ½)/side)) ([`roughness_texels`]); sampled per visible pixel
//!   at its interpolated (u, v) (handed over by `input_from_normalized`, as the 3D
//!   path) by a 2D bilinear `texture_sampler` (GeForce defaults, clamp to edge:
//!   [`roughness_sampler`]); λ = code / 255, then t = r·λ as before. Counted as
//!   "texture_sampler (roughness)" (and the (u, v) events in "polygon_interpolator");
//!   the sampler and the 2 channels are in the elaboration report. With a texture the
//!   3D map is always used (no 2D slice). The existing truths then use the texture's
//!   λ (the λ the render used).
//! - **The intended-λ truth**
//!   ([`RenderOptions::intended_truth`](super::render::RenderOptions::intended_truth),
//!   [`Truth::intended`](super::truth::Truth::intended)):
//!   the per-vertex path's truths use the interpolated λ, so they cannot see the
//!   smear. At each pixel, λ_exact = [`lambda_of_uv`] in f64 at the pixel's
//!   interpolated (u, v) (the same codes in both modes), Λ = g(λ_exact·|r|), eq. (3)
//!   (no cos φ test: what the map stores, so the cos φ error common to both sources
//!   stays out). [`IntendedErrors`] gives the errors over the object and over the seam
//!   band (pixels within [`SEAM_RADIUS`] of a jump of λ_exact by > [`SEAM_JUMP`]), the
//!   map's own error there (against the truth at the λ used), and |λ used − λ_exact|.
//!   [`roughness_comparison`](super::roughness_comparison::roughness_comparison)
//!   makes the rows; docs/envmap.md has the numbers.

use rtl_model::error::{check_range, ConfigError};
use rtl_model::units::texture_sampler::{AddressMode, TextureSampler, TextureSamplerConfig};

use super::image::ErrorStats;
#[cfg(doc)]
use super::interpolator::{
    texcoord_channels_cost, RENDER_ATTRS, RENDER_ATTRS_TEXTURE, TEXCOORD_CHANNELS,
};
#[cfg(doc)]
use super::objects::object_geometry;
use super::objects::{teapot_position, LambdaSpec, Object, TEAPOT_HEIGHT, TEAPOT_SCALE, TEAPOT_X};
use crate::scene::camera::CameraView;
use crate::scene::math::{v3, Vec3};

/// Where the per-pixel smoothness λ comes from (module notes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum LambdaSource {
    /// λ per vertex, interpolated by the polygon interpolator (the thesis' GeForce3
    /// path, Fig. 17(b)); the default, and today's images byte for byte.
    #[default]
    PerVertex,
    /// λ per pixel from a `side` × `side`, 8-bit, 1-channel roughness texture (texel
    /// (i, j) = round(255 · λ(u_i, v_j))) at the pixel's interpolated texture
    /// coordinate (u, v) from an object-linear texgen ([`object_texgen`]), sampled by
    /// a 2D bilinear `texture_sampler` (clamp to edge): λ = code / 255. `side` 1 ..=
    /// [`MAX_LAMBDA_TEXTURE_SIDE`] (errors name "envmap_render.lambda_texture"). The
    /// lookups then always use the 3D map (no 2D slice: λ is no longer uniform per
    /// draw call).
    Texture { side: u32 },
}

impl LambdaSource {
    /// `"per_vertex"` or `"texture_<side>"`.
    pub fn label(&self) -> String {
        match self {
            LambdaSource::PerVertex => "per_vertex".to_string(),
            LambdaSource::Texture { side } => format!("texture_{side}"),
        }
    }

    pub(super) fn validate(&self) -> Result<(), ConfigError> {
        if let LambdaSource::Texture { side } = *self {
            check_range(
                "envmap_render.lambda_texture",
                side.into(),
                1,
                MAX_LAMBDA_TEXTURE_SIDE.into(),
            )?;
        }
        Ok(())
    }
}

/// Largest side of the roughness texture (the sampler's largest axis).
pub const MAX_LAMBDA_TEXTURE_SIDE: u32 = 4096;
/// The roughness texture side
/// [`roughness_comparison`](super::roughness_comparison::roughness_comparison) uses:
/// 256 × 256 × 8 bits, a GeForce-era L8 texture (512 kbit).
pub const DEFAULT_LAMBDA_TEXTURE_SIDE: u32 = 256;
/// The seam band of [`IntendedErrors::seam`]: object pixels within this many pixels
/// (Chebyshev) of a pixel whose intended λ differs from a 4-neighbour's by more than
/// [`SEAM_JUMP`].
pub const SEAM_RADIUS: u32 = 2;
pub const SEAM_JUMP: f64 = 0.5;

/// Errors against the intended-λ truth ([`Truth::intended`](super::truth::Truth::intended)).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct IntendedErrors {
    /// Over all object pixels.
    pub all: ErrorStats,
    /// Over the seam band: object pixels within [`SEAM_RADIUS`] pixels of a jump of
    /// the intended λ by more than [`SEAM_JUMP`] between 4-neighbours (the sphere's 6
    /// o'clock seam of the non-uniform λ; empty, all zero, where λ has no jump).
    pub seam: ErrorStats,
    /// The map's own error over the seam band: against the eq. (3) truth with the λ the
    /// render USED ([`Truth::simplified`](super::truth::Truth::simplified)), the floor
    /// the λ source cannot remove (there λ → 0 reads the coarse centre of the map;
    /// [`super::render`] module notes).
    pub seam_own: ErrorStats,
    /// |λ used − λ intended| over all object pixels and over the seam band.
    pub lambda_all: LambdaErrors,
    pub lambda_seam: LambdaErrors,
}

/// Mean and largest |λ used − λ intended| over a set of pixels.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct LambdaErrors {
    pub pixels: usize,
    pub mean: f64,
    pub max: f64,
}

/// The object-linear texgen of the roughness texture's coordinate (u, v) (GL's
/// OBJECT_LINEAR texgen, which GeForce's fixed-function T&L has): u = (p − o)·a_s / l_s,
/// v = (p − o)·a_t / l_t, so the object's bounding rectangle in the (a_s, a_t) plane
/// maps to [0, 1]² (module notes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TexGen {
    /// The point mapped to (0, 0).
    pub origin: Vec3,
    /// Unit axes of u and v.
    pub s_axis: Vec3,
    pub t_axis: Vec3,
    /// Lengths mapped to 1.
    pub s_len: f64,
    pub t_len: f64,
}

impl TexGen {
    /// A texgen whose (u, v) are never read (arbitrary triangles with per-vertex λ:
    /// the 8-attribute interpolator drops them): every point maps to (0, 0).
    pub fn unused() -> TexGen {
        TexGen {
            origin: v3(0.0, 0.0, 0.0),
            s_axis: v3(0.0, 0.0, 0.0),
            t_axis: v3(0.0, 0.0, 0.0),
            s_len: 1.0,
            t_len: 1.0,
        }
    }

    /// (u, v) of the point `p` (host f64, per vertex).
    pub fn uv(&self, p: Vec3) -> (f64, f64) {
        let d = p - self.origin;
        (
            d.dot(self.s_axis) / self.s_len,
            d.dot(self.t_axis) / self.t_len,
        )
    }
}

/// The texgen of `object` seen by `cam`: the sphere's planes are the camera's right
/// and up axes over its bounding square [−1, 1]² (its λ is an angle around the view
/// axis); the teapot's are world x and y over its bounding rectangle (its λ is a
/// function of world height, which is NOT a function of (p·right, p·up): the camera
/// looks down by 14.4°).
pub fn object_texgen(object: Object, cam: &CameraView) -> TexGen {
    match object {
        Object::Sphere => TexGen {
            origin: (cam.right + cam.up) * -1.0,
            s_axis: cam.right,
            t_axis: cam.up,
            s_len: 2.0,
            t_len: 2.0,
        },
        Object::Teapot => {
            let pos = teapot_position();
            TexGen {
                origin: v3(pos[0] + TEAPOT_X.0 * TEAPOT_SCALE, pos[1], pos[2]),
                s_axis: v3(1.0, 0.0, 0.0),
                t_axis: v3(0.0, 1.0, 0.0),
                s_len: (TEAPOT_X.1 - TEAPOT_X.0) * TEAPOT_SCALE,
                t_len: TEAPOT_HEIGHT * TEAPOT_SCALE,
            }
        }
    }
}

/// λ as a function of the texgen coordinate (u, v) of [`object_texgen`]: the roughness
/// texture's content and the intended per-pixel λ. At a vertex it equals the vertex λ
/// of [`object_geometry`] (up to f64 rounding): the sphere's angle of
/// (2u − 1, 2v − 1) = (p·right, p·up) from 6 o'clock, the teapot's 0.2 + 0.7 v with
/// v = the relative height. Uniform λ gives λ. Never NaN (finite inputs; NaN ones give
/// the 6 o'clock value 0 for the sphere and 0.2 for the teapot).
pub fn lambda_of_uv(object: Object, lambda: LambdaSpec, u: f64, v: f64) -> f64 {
    let u = if u.is_finite() { u } else { 0.5 };
    let v = if v.is_finite() { v } else { 0.0 };
    match lambda {
        LambdaSpec::Uniform(l) => l,
        LambdaSpec::NonUniform => match object {
            Object::Sphere => {
                let (xr, yu) = (2.0 * u - 1.0, 2.0 * v - 1.0);
                let a = (-xr).atan2(-yu).rem_euclid(std::f64::consts::TAU);
                (a / std::f64::consts::TAU).clamp(0.0, 1.0)
            }
            Object::Teapot => 0.2 + 0.7 * v.clamp(0.0, 1.0),
        },
    }
}

/// The roughness texture's texels (row-major, row j at v = (j + ½)/side): round(255 ·
/// [`lambda_of_uv`]) at the texel centres. Errors: "envmap_render.lambda_texture" (side
/// outside 1 ..= 4096), "envmap_render.lambda".
pub fn roughness_texels(
    object: Object,
    lambda: LambdaSpec,
    side: u32,
) -> Result<Vec<u32>, ConfigError> {
    lambda.validate()?;
    LambdaSource::Texture { side }.validate()?;
    let n = side as f64;
    let mut t = Vec::with_capacity(side as usize * side as usize);
    for j in 0..side {
        let v = (j as f64 + 0.5) / n;
        for i in 0..side {
            let u = (i as f64 + 0.5) / n;
            let l = lambda_of_uv(object, lambda, u, v);
            t.push((255.0 * l).round().clamp(0.0, 255.0) as u32);
        }
    }
    Ok(t)
}

/// The roughness sampler: GeForce 2D defaults (bilinear, 8-bit texels and weights, 8
/// sub-texel bits, clamp to edge), 1 channel, holding [`roughness_texels`].
pub fn roughness_sampler(
    object: Object,
    lambda: LambdaSpec,
    side: u32,
) -> Result<TextureSampler, ConfigError> {
    let texels = roughness_texels(object, lambda, side)?;
    TextureSampler::new(
        TextureSamplerConfig {
            channels: 1,
            texel_bits: ROUGHNESS_BITS,
            address: [AddressMode::Clamp; 3],
            ..TextureSamplerConfig::geforce_2d(side, side)
        },
        &texels,
    )
    .map_err(|e| e.within("envmap_render.lambda_texture"))
}

/// Bits of a roughness texel (λ = code / 255).
pub(super) const ROUGHNESS_BITS: u32 = 8;
