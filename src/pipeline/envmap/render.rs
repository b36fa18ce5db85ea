//! Rendering a sphere or the Utah teapot with the multi-scale environment map (SPEC C,
//! the thesis §3.5 and §4.3, Table 5) through the hardware units, against the Phong
//! ground truth.
//!
//! # The per-pixel path, and what in it is f64
//!
//! 1. **Geometry (host, f64, per vertex — the application / T&L stage).** The object is
//!    tessellated ([`sphere_triangles`], [`tessellate_teapot`]); every vertex is
//!    projected by a pinhole camera ([`CameraView`]) and given 8 attributes: the unit
//!    normal n (3), the eye vector e = eye − p (3, unnormalised), the smoothness λ (1)
//!    and the window depth z ∈ [0, 1] (1); with a roughness texture also (u, v) (2).
//! 2. **polygon_interpolator (unit).** Each triangle is set up and walked by the unit
//!    (`pipeline::raster::draw_triangle`, the shafts pipeline's path): attributes are
//!    quantised into s16.16, interpolated by the unit's fixed-point walker and come out
//!    as s16.16 codes. The interpolation is **affine in screen space** (the unit has no
//!    perspective correction; GeForce3 had it): on these small triangles the difference
//!    is sub-pixel, but it is a difference. λ is per vertex and interpolated, as on the
//!    thesis' GeForce3: where λ changes fast across a triangle (the sphere's 6 o'clock
//!    seam of the non-uniform λ, where it jumps from ≈ 1 back to 0) the reflection is
//!    distorted — the thesis' Fig. 17(b) artefact. [`LambdaSource::Texture`] (the
//!    thesis' proposed fix, issue 5's option) takes λ per pixel from a roughness
//!    texture instead: see "Per-pixel roughness" below.
//!    Triangles seen from their back get their normals flipped (two-sided lighting; the
//!    teapot is an open sheet whose inside shows at the rim and the spout).
//! 3. **Depth test (integer).** The nearest fragment per pixel wins by comparing the
//!    interpolated window-depth codes (an integer compare standing for the depth buffer;
//!    the shafts pipeline's `shadow_compare` z-buffer is not instantiated here). Shading
//!    is then done once per visible pixel (deferred), which gives the same image as
//!    shading every fragment before the test; only the sampler's counters differ.
//! 4. **reflection_vector (unit; [`Reflection::Unit`], the default).** The
//!    interpolator's raw s16.16 codes of n and e go straight in, λ as u1.12 (rounded from
//!    the s16.16 code, or from the roughness texture's 8-bit code). The unit normalises
//!    both vectors (rsqrt ROM + one Newton step), forms r = 2(n̂·v̂)n̂ − v̂ and t = r·λ,
//!    and outputs (t + 1)/2 · s as the 3D sampler's s16.8 texel words. It stands for
//!    GeForce3's texture-shader stage (DOT_PRODUCT_REFLECT-style). Its coordinate error
//!    is ≤ 0.0556 texel at s = 128 (derived, docs/units.md). The map side must be a
//!    power of two.
//! 5. **[`Reflection::HostF64`] (the earlier path, for comparison).** The host
//!    normalises n and e in f64 from the same codes, forms r and t, and
//!    `TextureSamplerConfig::input_from_normalized` rounds (t + 1)/2 · s to the sampler's
//!    s16.8 words (saturating, counted). The truth always uses this f64 r (the ideal
//!    reflection of the interpolated n, e). The 2D-slice path also addresses the slice
//!    by the f64 r (lat-long; a gap).
//! 6. **texture_sampler (unit).** [`TextureSamplerConfig::geforce_3d`] (s × s × s, 3
//!    channels, the map's unorm texels — 8-bit by default — trilinear over 8 texels,
//!    8-bit weights, clamp to edge) samples the [`VoxelMap`]; its output codes are the
//!    framebuffer's (8-bit: a map with other widths is rescaled to 8 bits by rounding).
//! 7. **Background (host, f64, not the object).** Either black or the environment seen
//!    in the pixel's view direction: a bilinear lookup of the environment at the same
//!    exposure, rounded to 8-bit levels (standing for a sky-box / cube-map pass; not
//!    part of the error statistics).
//!
//! # Per-pixel roughness from a texture ([`RenderOptions::lambda_source`])
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
//!   of [`RENDER_ATTRS`] = 8, as GeForce3's single interpolator carries many more
//!   channels. Every attribute channel is independent in the unit, so the first 8
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
//! - **The intended-λ truth** ([`RenderOptions::intended_truth`], [`Truth::intended`]):
//!   the per-vertex path's truths use the interpolated λ, so they cannot see the
//!   smear. At each pixel, λ_exact = [`lambda_of_uv`] in f64 at the pixel's
//!   interpolated (u, v) (the same codes in both modes), Λ = g(λ_exact·|r|), eq. (3)
//!   (no cos φ test: what the map stores, so the cos φ error common to both sources
//!   stays out). [`IntendedErrors`] gives the errors over the object and over the seam
//!   band (pixels within [`SEAM_RADIUS`] of a jump of λ_exact by > [`SEAM_JUMP`]), the
//!   map's own error there (against the truth at the λ used), and |λ used − λ_exact|.
//!   [`roughness_comparison`] makes the rows; docs/envmap.md has the numbers.
//!
//! # Exposure and levels
//!
//! The map holds the thesis' 256-level units: [`quick_map`] prefilters
//! `env.to_level_map(exposure)` (levels 0 ..= 255 as f64) and stores level/255 as unorm
//! codes. `exposure` is [`RenderOptions::exposure`], by default
//! [`EnvMap::auto_exposure`] (1 for the built-in pattern). A map built elsewhere must use
//! the same exposure for the comparison to mean anything.
//!
//! # Ground truth and errors
//!
//! At every object pixel the truth is [`PhongTruth::eval`] on the same level map, with
//! the SAME per-pixel r and n̂ as the rendered pixel (so geometry and interpolation are
//! shared and the difference is the map's: prefilter, voxel resolution s, 8-bit voxels,
//! trilinear filtering, coordinate quantisation — plus, for the cos φ truth, the dropped
//! cos φ test), and Λ = g(|t|) with g of eq. (13) at the map's s and I = 256 — the Λ the
//! map stores at t. Both truths are made: with the cos φ test (eqs. 1–2, the thesis'
//! Phong model; the Table 5 rows use it) and without it (eq. 3). Truth pixels are
//! rounded to 8-bit levels like the rendered image; Δ = rendered − truth per channel,
//! over the object's pixels; the statistics are the mean and (population) variance of
//! |Δ| — the thesis' "誤差の平均 / 誤差の分散" (its means are positive) — plus the signed
//! mean and the largest |Δ|.
//!
//! λ = 0 (the sphere's 6 o'clock vertices) gives t = 0: the map's centre voxel region
//! (the whole-sphere mean) against a truth at Λ = g(0) = 0 (the hemisphere mean around
//! r). Outside the thesis' 0 < λ ≤ 1, defined, and a visible source of error there.
//!
//! # Scene
//!
//! Camera at (0, 1, 3.9) looking at the origin, y up, 36° vertical field of view, near 1,
//! far 10. The sphere: radius 1 at the origin, a 48 × 24 UV sphere. The teapot: scale
//! 0.3, its bounding box centred on the origin, spout towards +x (screen right), 6 × 6
//! quads per patch.
//!
//! # Test/small map builder
//!
//! [`quick_map`] is a SMALL, TEST-ONLY builder (exact prefilter over at most 64 × 32
//! texels, one voxel at a time). The full 128³ builder is `envmap::prefilter`'s.

use std::collections::BTreeMap;
use std::path::Path;

use rtl_model::driver::run_span;
use rtl_model::error::{check_range, ConfigError};
use rtl_model::units::polygon_interpolator::{PolygonInterpolator, PolygonInterpolatorConfig};
use rtl_model::units::reflection_vector::{
    ReflectionVector, ReflectionVectorConfig, ReflectionVectorIn,
};
use rtl_model::units::texture_sampler::{
    AddressMode, TextureSampler, TextureSamplerConfig, TextureSamplerIn,
};
use rtl_model::{Counters, UnitSummary};

use super::slice;
use super::voxmap::VoxelMap;
use crate::pipeline::raster::{draw_triangle, host_attrs, Fragment, HostVertex};
use crate::pipeline::shafts::frame::Elaborated;
use crate::pipeline::shafts::view::CameraView;
use crate::reference::envmap_prefilter::{
    g, prefilter_voxel_exact, Equirect, PrefilterParams, Samples, Weighting, THESIS_LEVELS,
};
use crate::reference::phong_truth::{PhongTruth, Visibility};
use crate::scene::envmap::EnvMap;
use crate::scene::format::{Camera, ImageSize};
use crate::scene::math::{v3, Vec3};
use crate::scene::teapot::{sphere_triangles, tessellate_teapot, Triangle};

/// Fraction bits of the interpolator's attribute outputs (s16.16).
const ATTR_FRAC: u32 = 16;
/// Attributes the render's interpolator carries with per-vertex λ: n (3), e (3), λ, z.
pub const RENDER_ATTRS: u32 = 8;
/// With [`LambdaSource::Texture`]: the same 8 plus the texture coordinate (u, v), in
/// the same interpolator.
pub const RENDER_ATTRS_TEXTURE: u32 = RENDER_ATTRS + 2;

/// The render's polygon interpolator carrying `attrs` attributes (GeForce defaults:
/// s16.16 attributes, s20.24 accumulators; outputs s16.16).
pub fn render_interpolator(attrs: u32) -> Result<PolygonInterpolator, ConfigError> {
    PolygonInterpolatorConfig {
        attrs,
        out_int_bits: 16,
        out_frac_bits: ATTR_FRAC,
        ..PolygonInterpolatorConfig::default()
    }
    .build()
}

/// The elaboration report's row for (u, v) with [`LambdaSource::Texture`]: the
/// interpolator's 2 more attribute channels, summary from [`texcoord_channels_cost`].
pub const TEXCOORD_CHANNELS: &str = "polygon_interpolator +2 attributes (u, v): 10, not 8";

/// What carrying (u, v) costs the render's interpolator: gates, RAM bits and the
/// breakdown are the INCREMENT, the [`RENDER_ATTRS_TEXTURE`]-attribute config's minus
/// the [`RENDER_ATTRS`]-attribute config's (only the parts that grow are kept: two more
/// attribute accumulators, output rounders and output register bits; the sequenced
/// set-up datapath is shared, it takes 3 more clocks per attribute); latency, II and
/// widths are the 10-attribute unit's (the same latency and II as with 8).
pub fn texcoord_channels_cost() -> Result<UnitSummary, ConfigError> {
    let with = UnitSummary::of(&render_interpolator(RENDER_ATTRS_TEXTURE)?);
    let without = UnitSummary::of(&render_interpolator(RENDER_ATTRS)?);
    let breakdown = with
        .breakdown
        .iter()
        .zip(&without.breakdown)
        .map(|((n1, g1), (n0, g0))| {
            let name = if n1 == n0 {
                format!("{n1}: {RENDER_ATTRS_TEXTURE} − {RENDER_ATTRS} attributes")
            } else {
                format!("{n1} − {n0}")
            };
            (name, g1 - g0)
        })
        .filter(|(_, d)| *d != 0.0)
        .collect();
    Ok(UnitSummary {
        gates_nand2: with.gates_nand2 - without.gates_nand2,
        ram_bits: with.ram_bits - without.ram_bits,
        breakdown,
        ..with
    })
}
/// Largest image side.
pub const MAX_IMAGE_SIDE: u32 = 4096;
/// Largest environment (texels) [`quick_map`] prefilters exactly; larger maps are
/// box-filtered down to ≤ 64 × 32 first (solid-angle weighted).
pub const QUICK_MAP_MAX_TEXELS: usize = 64 * 32;
/// Sphere tessellation (segments around y, rings pole to pole).
pub const SPHERE_SEGMENTS: u32 = 48;
pub const SPHERE_RINGS: u32 = 24;
/// Teapot: quads per patch side, scale.
pub const TEAPOT_SUBDIVISIONS: u32 = 6;
pub const TEAPOT_SCALE: f64 = 0.3;
/// Teapot height before scaling (y ∈ [0, 3.15]) and x extent (handle −3 to spout 3.434).
const TEAPOT_HEIGHT: f64 = 3.15;
const TEAPOT_X: (f64, f64) = (-3.0, 3.434);

/// The object drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Object {
    Sphere,
    Teapot,
}

impl Object {
    pub fn name(self) -> &'static str {
        match self {
            Object::Sphere => "sphere",
            Object::Teapot => "teapot",
        }
    }
}

/// The smoothness λ per vertex.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum LambdaSpec {
    /// The same λ ∈ [0, 1] everywhere.
    Uniform(f64),
    /// The thesis' non-uniform λ: the sphere's λ runs 0 → 1 around the view axis (6
    /// o'clock 0, 9 o'clock 0.25, 12 o'clock 0.5, 3 o'clock 0.75, seen from the camera);
    /// the teapot's runs linearly with height from 0.2 (bottom) to 0.9 (top).
    NonUniform,
}

impl LambdaSpec {
    /// "1", "0.5", … or "nonuniform" (for the Table 5 rows).
    pub fn label(&self) -> String {
        match self {
            LambdaSpec::Uniform(l) => format!("{l}"),
            LambdaSpec::NonUniform => "nonuniform".to_string(),
        }
    }

    fn validate(&self) -> Result<(), ConfigError> {
        if let LambdaSpec::Uniform(l) = *self {
            let l = rtl_model::error::check_finite("envmap_render.lambda", l)?;
            if !(0.0..=1.0).contains(&l) {
                return Err(ConfigError::out_of_range(
                    "envmap_render.lambda",
                    l,
                    0.0,
                    1.0,
                ));
            }
        }
        Ok(())
    }
}

/// What is behind the object.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Background {
    /// The environment in the view direction, 8-bit levels (host f64 lookup).
    #[default]
    Environment,
    Black,
}

/// Which texture the object's lookups use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Lookup {
    /// Always the 3D voxel map through the 3D (trilinear) sampler: the thesis' method,
    /// and the default, so Table 5 measures the 3D map.
    #[default]
    Voxel3D,
    /// The elaborated choice: for [`LambdaSpec::Uniform`] a 2D slice of the map at
    /// radius λ through the 2D (bilinear) sampler (`super::slice`); the 3D map for
    /// [`LambdaSpec::NonUniform`].
    Auto,
}

/// Where the per-pixel smoothness λ comes from (module notes, "Per-pixel roughness").
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
    /// "per_vertex" or "texture_<side>".
    pub fn label(&self) -> String {
        match self {
            LambdaSource::PerVertex => "per_vertex".to_string(),
            LambdaSource::Texture { side } => format!("texture_{side}"),
        }
    }

    fn validate(&self) -> Result<(), ConfigError> {
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
/// The roughness texture side [`roughness_comparison`] uses: 256 × 256 × 8 bits, a
/// GeForce-era L8 texture (512 kbit).
pub const DEFAULT_LAMBDA_TEXTURE_SIDE: u32 = 256;
/// The seam band of [`IntendedErrors::seam`]: object pixels within this many pixels
/// (Chebyshev) of a pixel whose intended λ differs from a 4-neighbour's by more than
/// [`SEAM_JUMP`].
pub const SEAM_RADIUS: u32 = 2;
pub const SEAM_JUMP: f64 = 0.5;

/// Options of [`render_object_with`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderOptions {
    /// Exposure of the environment's levels; None: [`EnvMap::auto_exposure`].
    pub exposure: Option<f64>,
    pub background: Background,
    pub lookup: Lookup,
    /// Per-vertex (default) or per-pixel λ from a roughness texture.
    pub lambda_source: LambdaSource,
    /// Also make the intended-λ truth ([`Truth::intended`]) and its errors
    /// ([`RenderStats::intended`]); off by default (it costs a third truth per pixel).
    pub intended_truth: bool,
    /// Who forms r and the 3D texture coordinate of t = r·λ: the `reflection_vector`
    /// unit (default) or host f64 (the earlier path, kept for comparison).
    pub reflection: Reflection,
}

/// Who computes the reflection and the 3D lookup's texel coordinates.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Reflection {
    /// The bit-accurate `reflection_vector` unit (GeForce3's texture-shader stage): the
    /// interpolator's raw n, e codes and λ in u1.12 → s16.8 texel coordinates. Needs a
    /// power-of-two map side (else an error naming "envmap_render.reflection").
    #[default]
    Unit,
    /// Host f64: r = 2(n̂·v̂)n̂ − v̂, t = r·λ, (t + 1)/2 · s rounded by the sampler's
    /// `input_from_normalized`.
    HostF64,
}

/// What one render did, counted (no truth needed): for the frame-time model and the
/// elaboration report.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct FrameInfo {
    pub width: u32,
    pub height: u32,
    /// Triangles set up.
    pub triangles: usize,
    /// Fragments the interpolator produced (every covered pixel of every triangle,
    /// before the depth test).
    pub fragments: u64,
    /// Visible object pixels (after the depth test; each got one texture lookup).
    pub shaded: u64,
    /// Background pixels (the environment pass).
    pub background_pixels: u64,
    /// Texels one lookup reads (8: trilinear 3D; 4: bilinear 2D slice).
    pub texels_per_lookup: u32,
    /// Texels of the roughness texture each shaded pixel reads (4: bilinear, with
    /// [`LambdaSource::Texture`]; 0 per vertex). Not yet in the frame-time model.
    pub roughness_texels_per_lookup: u32,
    /// Which sampler was elaborated, which left out, and the bytes and gates saved.
    pub elaboration: super::slice::Elaboration,
}

/// An 8-bit RGB image with the object's coverage.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    /// Row-major, y down.
    pub pixels: Vec<[u8; 3]>,
    /// True where the object is (the pixels the statistics use).
    pub mask: Vec<bool>,
}

impl Image {
    fn new(width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Image {
            width,
            height,
            pixels: vec![[0; 3]; n],
            mask: vec![false; n],
        }
    }

    pub fn get(&self, x: u32, y: u32) -> [u8; 3] {
        self.pixels[(y * self.width + x) as usize]
    }

    pub fn covered(&self, x: u32, y: u32) -> bool {
        self.mask[(y * self.width + x) as usize]
    }

    /// Object pixels.
    pub fn coverage(&self) -> usize {
        self.mask.iter().filter(|m| **m).count()
    }

    /// Write as an 8-bit RGB PNG (errors name "envmap_render.path").
    pub fn write_png(&self, path: impl AsRef<Path>) -> Result<(), ConfigError> {
        let path = path.as_ref();
        let buf: Vec<u8> = self.pixels.iter().flatten().copied().collect();
        image::save_buffer(
            path,
            &buf,
            self.width,
            self.height,
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| {
            ConfigError::invalid(
                "envmap_render.path",
                &format!("`{}`: cannot write PNG: {e}", path.display()),
            )
        })
    }

    /// |a − b| × `gain` (clamped) on the object pixels of `self`, black elsewhere: a
    /// difference image for looking at.
    pub fn diff(&self, other: &Image, gain: f64) -> Image {
        let mut d = Image::new(self.width, self.height);
        for k in 0..self.pixels.len().min(other.pixels.len()) {
            if self.mask[k] {
                d.mask[k] = true;
                for c in 0..3 {
                    let v = (self.pixels[k][c] as f64 - other.pixels[k][c] as f64).abs() * gain;
                    d.pixels[k][c] = v.clamp(0.0, 255.0).round() as u8;
                }
            }
        }
        d
    }

    /// Images side by side (heights must match; shorter ones are padded black).
    pub fn hstack(images: &[&Image]) -> Image {
        let w: u32 = images.iter().map(|i| i.width).sum();
        let h = images.iter().map(|i| i.height).max().unwrap_or(0);
        let mut out = Image::new(w.max(1), h.max(1));
        let mut x0 = 0;
        for im in images {
            for y in 0..im.height {
                for x in 0..im.width {
                    let k = (y * out.width + x0 + x) as usize;
                    out.pixels[k] = im.get(x, y);
                    out.mask[k] = im.covered(x, y);
                }
            }
            x0 += im.width;
        }
        out
    }
}

/// Error statistics of Δ = rendered − truth over the object's pixels (8-bit levels).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct ErrorStats {
    pub pixels: usize,
    /// Mean of |Δ| per channel.
    pub mean: [f64; 3],
    /// Population variance of |Δ| per channel.
    pub var: [f64; 3],
    /// Mean of Δ (signed) per channel.
    pub mean_signed: [f64; 3],
    /// Largest |Δ| per channel.
    pub max: [f64; 3],
}

impl ErrorStats {
    /// Statistics of `img` − `truth` over `img`'s object pixels (all zero if none).
    pub fn of(img: &Image, truth: &Image) -> ErrorStats {
        Self::of_masked(img, truth, &img.mask)
    }

    /// Statistics of `img` − `truth` over the pixels where `mask` is true (all zero if
    /// none; a short mask leaves the rest out).
    pub fn of_masked(img: &Image, truth: &Image, mask: &[bool]) -> ErrorStats {
        let mut s = ErrorStats::default();
        let mut sum = [0.0; 3];
        let mut sum2 = [0.0; 3];
        let mut sums = [0.0; 3];
        let n = img.pixels.len().min(truth.pixels.len());
        for (k, _) in mask.iter().take(n).enumerate().filter(|(_, m)| **m) {
            s.pixels += 1;
            for c in 0..3 {
                let d = img.pixels[k][c] as f64 - truth.pixels[k][c] as f64;
                sum[c] += d.abs();
                sum2[c] += d * d;
                sums[c] += d;
                s.max[c] = s.max[c].max(d.abs());
            }
        }
        if s.pixels > 0 {
            let n = s.pixels as f64;
            for c in 0..3 {
                s.mean[c] = sum[c] / n;
                s.var[c] = (sum2[c] / n - s.mean[c] * s.mean[c]).max(0.0);
                s.mean_signed[c] = sums[c] / n;
            }
        }
        s
    }

    pub fn is_finite(&self) -> bool {
        self.mean
            .iter()
            .chain(&self.var)
            .chain(&self.mean_signed)
            .chain(&self.max)
            .all(|v| v.is_finite())
    }
}

/// The two ground-truth images.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Truth {
    /// Eqs. (1)–(2): with the cos φ test (the thesis' Phong model).
    pub cos_phi: Image,
    /// Eq. (3): without it (what the map stores).
    pub simplified: Image,
    /// The voxel side s whose g(|t|) gave Λ (the truth depends on it).
    pub side: u32,
    /// With [`RenderOptions::intended_truth`]: eq. (3) (no cos φ test) with the
    /// INTENDED λ, λ(u, v) in f64 at the pixel's interpolated texture coordinate, and
    /// Λ = g(λ·|r|) (module notes, "Per-pixel roughness"). None otherwise.
    pub intended: Option<Image>,
}

/// Errors against the intended-λ truth ([`Truth::intended`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct IntendedErrors {
    /// Over all object pixels.
    pub all: ErrorStats,
    /// Over the seam band: object pixels within [`SEAM_RADIUS`] pixels of a jump of
    /// the intended λ by more than [`SEAM_JUMP`] between 4-neighbours (the sphere's 6
    /// o'clock seam of the non-uniform λ; empty, all zero, where λ has no jump).
    pub seam: ErrorStats,
    /// The map's own error over the seam band: against the eq. (3) truth with the λ the
    /// render USED ([`Truth::simplified`]), the floor the λ source cannot remove (there
    /// λ → 0 reads the coarse centre of the map; module notes).
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

/// Errors against both truths.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderStats {
    pub cos_phi: ErrorStats,
    pub simplified: ErrorStats,
    /// Unit counters ("polygon_interpolator", "texture_sampler (envmap)").
    pub counters: BTreeMap<String, Counters>,
    /// Triangles drawn.
    pub triangles: usize,
    /// Object pixels whose interpolated normal faces away from the eye (n̂·v < 0: at
    /// silhouettes, from interpolating vertex normals); there the cos φ truth loses most
    /// of the lobe and the errors are large (the thesis' rim error, Fig. 8).
    pub back_normal_pixels: usize,
    /// The render's counts and elaboration report.
    pub frame: FrameInfo,
    /// Errors against the intended-λ truth, with [`RenderOptions::intended_truth`].
    pub intended: Option<IntendedErrors>,
}

/// SMALL / TEST map builder: the exact prefilter (eqs. 8–9, Λ = g(|t|) at s and I = 256,
/// solid-angle weighting) of every voxel of an s³ map, over `env`'s levels at
/// [`EnvMap::auto_exposure`], 8-bit voxels. Environments above
/// [`QUICK_MAP_MAX_TEXELS`] are first box-filtered (solid-angle weighted) by the
/// smallest factor that brings them to ≤ 64 × 32 (it must divide both sides, else an
/// error naming "envmap_render.env"). Cost ≈ s³ × texels weight evaluations: s = 16 on
/// 64 × 32 ≈ 8·10⁶. Not the thesis' builder (that is `envmap::prefilter`).
pub fn quick_map(env: &EnvMap, s: u32) -> Result<VoxelMap, ConfigError> {
    quick_map_with(env, s, env.auto_exposure())
}

/// [`quick_map`] at an explicit exposure ("envmap.exposure").
pub fn quick_map_with(env: &EnvMap, s: u32, exposure: f64) -> Result<VoxelMap, ConfigError> {
    let mut map = VoxelMap::new(s, 8)?;
    let small = shrink(env)?;
    let levels = small.to_level_map(exposure)?;
    let eq = Equirect::from_slice(levels.width(), levels.height(), levels.texels())?;
    let samples = Samples::from_equirect(&eq);
    let params = PrefilterParams::new(s as f64, THESIS_LEVELS, Weighting::SolidAngle)?;
    for z in 0..s {
        for y in 0..s {
            for x in 0..s {
                let t = map.voxel_t(x, y, z);
                let v = prefilter_voxel_exact(t, &samples, &params);
                map.set_levels(x, y, z, v.map(|c| c / 255.0));
            }
        }
    }
    Ok(map)
}

fn shrink(env: &EnvMap) -> Result<EnvMap, ConfigError> {
    if env.width() * env.height() <= QUICK_MAP_MAX_TEXELS {
        return Ok(env.clone());
    }
    let f = (1..=env.width())
        .find(|&f| {
            // (no `%` / is_multiple_of: the crate's MSRV is 1.80)
            env.width() / f * f == env.width()
                && env.height() / f * f == env.height()
                && (env.width() / f) * (env.height() / f) <= QUICK_MAP_MAX_TEXELS
        })
        .ok_or_else(|| {
            ConfigError::invalid(
                "envmap_render.env",
                &format!(
                    "{} × {} cannot be box-filtered to ≤ {QUICK_MAP_MAX_TEXELS} texels",
                    env.width(),
                    env.height()
                ),
            )
        })?;
    env.downsample(f)
}

/// The camera of every render (module notes).
pub fn camera() -> Camera {
    Camera {
        eye: [0.0, 1.0, 3.9],
        look_at: [0.0, 0.0, 0.0],
        up: [0.0, 1.0, 0.0],
        fovy_deg: 36.0,
        near: 1.0,
        far: 10.0,
    }
}

/// The object's triangles (world space) and per-vertex λ.
pub fn object_geometry(
    object: Object,
    lambda: LambdaSpec,
    cam: &CameraView,
) -> Result<Vec<(Triangle, [f64; 3])>, ConfigError> {
    lambda.validate()?;
    let (tris, lam): (Vec<Triangle>, Box<dyn Fn(Vec3) -> f64>) = match object {
        Object::Sphere => {
            let tris = sphere_triangles([0.0; 3], 1.0, SPHERE_SEGMENTS, SPHERE_RINGS)?;
            let (right, up) = (cam.right, cam.up);
            let f = move |p: Vec3| {
                // Angle around the view axis from 6 o'clock, through 9 (left), 12, 3.
                let (xr, yu) = (p.dot(right), p.dot(up));
                let a = (-xr).atan2(-yu).rem_euclid(std::f64::consts::TAU);
                (a / std::f64::consts::TAU).clamp(0.0, 1.0)
            };
            (tris, Box::new(f))
        }
        Object::Teapot => {
            let pos = teapot_position();
            let tris = tessellate_teapot(pos, TEAPOT_SCALE, 0.0, TEAPOT_SUBDIVISIONS)?;
            let (y0, h) = (pos[1], TEAPOT_HEIGHT * TEAPOT_SCALE);
            let f = move |p: Vec3| 0.2 + 0.7 * ((p.y - y0) / h).clamp(0.0, 1.0);
            (tris, Box::new(f))
        }
    };
    Ok(tris
        .into_iter()
        .map(|t| {
            let l = match lambda {
                LambdaSpec::Uniform(l) => [l; 3],
                LambdaSpec::NonUniform => [lam(t.p[0]), lam(t.p[1]), lam(t.p[2])],
            };
            (t, l)
        })
        .collect())
}

/// The object-linear texgen of the roughness texture's coordinate (u, v) (GL's
/// OBJECT_LINEAR texgen, which GeForce's fixed-function T&L has): u = (p − o)·a_s / l_s,
/// v = (p − o)·a_t / l_t, so the object's bounding rectangle in the (a_s, a_t) plane
/// maps to [0, 1]² (module notes, "Per-pixel roughness").
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
const ROUGHNESS_BITS: u32 = 8;

fn teapot_position() -> [f64; 3] {
    [
        -0.5 * (TEAPOT_X.0 + TEAPOT_X.1) * TEAPOT_SCALE,
        -0.5 * TEAPOT_HEIGHT * TEAPOT_SCALE,
        0.0,
    ]
}

/// [`render_object_with`] with the default options (auto exposure, environment
/// background).
pub fn render_object(
    env: &EnvMap,
    map: &VoxelMap,
    object: Object,
    lambda: LambdaSpec,
    size: (u32, u32),
) -> Result<(Image, Truth, RenderStats), ConfigError> {
    render_object_with(env, map, object, lambda, size, &RenderOptions::default())
}

/// One visible fragment's interpolated values (f64 from the unit's output codes).
struct Shading {
    n: Vec3,
    r: Vec3,
    /// The λ the render used (interpolated per vertex, or the roughness texture's).
    lambda: f64,
    /// The intended λ: [`lambda_of_uv`] at the interpolated (u, v) (= `lambda` when
    /// (u, v) were not interpolated).
    lambda_intended: f64,
}

/// Render `object` with smoothness `lambda` at `size` = (width, height) through the
/// units with `map`, and the two Phong truths on `env` at the same pixels. Errors:
/// "envmap_render.size", "envmap_render.lambda", "envmap.exposure", unit config errors.
///
/// The truth pixels are independent and are computed in parallel with rayon (each
/// pixel's sum in a fixed order, results collected in pixel order: the same bytes for
/// any thread count).
pub fn render_object_with(
    env: &EnvMap,
    map: &VoxelMap,
    object: Object,
    lambda: LambdaSpec,
    size: (u32, u32),
    opt: &RenderOptions,
) -> Result<(Image, Truth, RenderStats), ConfigError> {
    let r = render_core(env, map, object, lambda, size, opt)?;
    let truth = truth_images(&r, opt.intended_truth)?;
    let stats = r.stats(&truth);
    Ok((r.img, truth, stats))
}

/// As [`render_object_with`], but reusing `truth` from an earlier call with the same
/// environment, exposure, object, λ, size and map side (e.g. the exact map's render
/// when rendering the accelerated map): the truth depends only on the geometry, the
/// interpolated n, r, λ, and g at the map's side, never on the map's voxels. The
/// truth's object mask and map side must equal this render's, else an error naming
/// "envmap_render.truth" (it was made for another scene or side). The exposure and
/// environment are the caller's to keep the same.
pub fn render_against(
    env: &EnvMap,
    map: &VoxelMap,
    object: Object,
    lambda: LambdaSpec,
    size: (u32, u32),
    opt: &RenderOptions,
    truth: &Truth,
) -> Result<(Image, RenderStats), ConfigError> {
    let r = render_core(env, map, object, lambda, size, opt)?;
    if truth.cos_phi.mask != r.img.mask
        || truth.simplified.mask != r.img.mask
        || truth.cos_phi.width != r.img.width
        || truth.cos_phi.height != r.img.height
        || truth.side != r.side
    {
        return Err(ConfigError::invalid(
            "envmap_render.truth",
            "its object pixels or map side differ from this render's (another scene, size, object or s)",
        ));
    }
    let stats = r.stats(truth);
    Ok((r.img, stats))
}

/// Only the rendered image (no truth, no statistics): for looking at.
pub fn render_image(
    env: &EnvMap,
    map: &VoxelMap,
    object: Object,
    lambda: LambdaSpec,
    size: (u32, u32),
    opt: &RenderOptions,
) -> Result<Image, ConfigError> {
    Ok(render_core(env, map, object, lambda, size, opt)?.img)
}

/// The rendered image and its counts (no truth): for timing a frame.
pub fn render_frame(
    env: &EnvMap,
    map: &VoxelMap,
    object: Object,
    lambda: LambdaSpec,
    size: (u32, u32),
    opt: &RenderOptions,
) -> Result<(Image, FrameInfo), ConfigError> {
    let r = render_core(env, map, object, lambda, size, opt)?;
    Ok((r.img, r.frame))
}

/// The rendered image (object and background) and what the truth needs.
struct Rendered {
    img: Image,
    /// Background pixels (also the truths' background).
    background: Vec<(usize, [u8; 3])>,
    shading: Vec<(usize, Shading)>,
    levels_env: EnvMap,
    side: u32,
    counters: BTreeMap<String, Counters>,
    triangles: usize,
    back_normal_pixels: usize,
    frame: FrameInfo,
}

impl Rendered {
    fn stats(&self, truth: &Truth) -> RenderStats {
        RenderStats {
            cos_phi: ErrorStats::of(&self.img, &truth.cos_phi),
            simplified: ErrorStats::of(&self.img, &truth.simplified),
            counters: self.counters.clone(),
            triangles: self.triangles,
            back_normal_pixels: self.back_normal_pixels,
            frame: self.frame.clone(),
            intended: truth.intended.as_ref().map(|t| {
                let band = self.seam_band();
                IntendedErrors {
                    all: ErrorStats::of(&self.img, t),
                    seam: ErrorStats::of_masked(&self.img, t, &band),
                    seam_own: ErrorStats::of_masked(&self.img, &truth.simplified, &band),
                    lambda_all: self.lambda_errors(&self.img.mask),
                    lambda_seam: self.lambda_errors(&band),
                }
            }),
        }
    }

    fn lambda_errors(&self, mask: &[bool]) -> LambdaErrors {
        let mut e = LambdaErrors::default();
        let mut sum = 0.0;
        for (k, sh) in &self.shading {
            if mask.get(*k).copied().unwrap_or(false) {
                let d = (sh.lambda - sh.lambda_intended).abs();
                e.pixels += 1;
                sum += d;
                e.max = e.max.max(d);
            }
        }
        if e.pixels > 0 {
            e.mean = sum / e.pixels as f64;
        }
        e
    }

    /// The seam band of [`IntendedErrors::seam`] from the intended λ per pixel.
    fn seam_band(&self) -> Vec<bool> {
        let (w, h) = (self.img.width as i64, self.img.height as i64);
        let mut lam: Vec<Option<f64>> = vec![None; self.img.pixels.len()];
        for (k, sh) in &self.shading {
            lam[*k] = Some(sh.lambda_intended);
        }
        let mut band = vec![false; lam.len()];
        let r = SEAM_RADIUS as i64;
        for y in 0..h {
            for x in 0..w {
                let Some(l) = lam[(y * w + x) as usize] else {
                    continue;
                };
                let jump = [(1, 0), (0, 1)].iter().any(|&(dx, dy)| {
                    let (nx, ny) = (x + dx, y + dy);
                    nx < w
                        && ny < h
                        && lam[(ny * w + nx) as usize].is_some_and(|m| (m - l).abs() > SEAM_JUMP)
                });
                if !jump {
                    continue;
                }
                for by in (y - r).max(0)..=(y + r + 1).min(h - 1) {
                    for bx in (x - r).max(0)..=(x + r + 1).min(w - 1) {
                        let k = (by * w + bx) as usize;
                        band[k] = lam[k].is_some();
                    }
                }
            }
        }
        band
    }
}

fn render_core(
    env: &EnvMap,
    map: &VoxelMap,
    object: Object,
    lambda: LambdaSpec,
    size: (u32, u32),
    opt: &RenderOptions,
) -> Result<Rendered, ConfigError> {
    let (w, h) = size;
    check_range("envmap_render.size", w.into(), 1, MAX_IMAGE_SIDE.into())?;
    check_range("envmap_render.size", h.into(), 1, MAX_IMAGE_SIDE.into())?;
    lambda.validate()?;
    opt.lambda_source.validate()?;
    let exposure = opt.exposure.unwrap_or_else(|| env.auto_exposure());
    let levels_env = env.to_level_map(exposure)?;
    let cam_cfg = camera();
    let cam = CameraView::new(
        &cam_cfg,
        ImageSize {
            width: w,
            height: h,
        },
    );
    let geo = object_geometry(object, lambda, &cam)?;

    // ---- units
    // ONE interpolator: n, e, λ, z (8 attributes); with a roughness texture also the
    // texture coordinate (u, v) as attributes 8 and 9 (10 attributes).
    let texture_side = match opt.lambda_source {
        LambdaSource::PerVertex => None,
        LambdaSource::Texture { side } => Some(side),
    };
    let want_uv = texture_side.is_some() || opt.intended_truth;
    let interp_uv = render_interpolator(RENDER_ATTRS_TEXTURE)?;
    let interp = match texture_side {
        Some(_) => interp_uv,
        None => render_interpolator(RENDER_ATTRS)?,
    };
    // Per-vertex λ with the intended truth: the render stays at 8 attributes; the
    // truth's (u, v) come from a MEASUREMENT walk of the 10-attribute config (not
    // counted, not elaborated), so both sources see the same (u, v) codes.
    let uv_probe = (texture_side.is_none() && opt.intended_truth).then_some(interp_uv);
    let texgen = object_texgen(object, &cam);
    let rough = match texture_side {
        Some(side) => Some(roughness_sampler(object, lambda, side)?),
        None => None,
    };
    let s = map.side();
    let sampler3 = slice::sampler_3d(map)?;
    let refl_unit = match opt.reflection {
        Reflection::Unit => Some(reflection_unit(&sampler3, s)?),
        Reflection::HostF64 => None,
    };
    let mut c_refl = Counters::default();
    let mut refl_in: Vec<ReflectionVectorIn> = Vec::new();
    // The 2D-slice elaboration: uniform λ (per vertex) reads the map only on |t| = λ.
    let two_d = match (opt.lookup, lambda, opt.lambda_source) {
        (Lookup::Auto, LambdaSpec::Uniform(l), LambdaSource::PerVertex) => {
            let (sw, sh) = slice::default_slice_size(s);
            let sl = slice::slice_from_map(map, l, sw, sh)?;
            let s2 = slice::sampler_2d(&sl)?;
            Some((s2, sl))
        }
        _ => None,
    };
    let sampler: &TextureSampler = two_d.as_ref().map_or(&sampler3, |(s2, _)| s2);

    // ---- raster + depth test
    let mut c_int = Counters::default();
    let n_px = w as usize * h as usize;
    let mut zbuf: Vec<i64> = vec![i64::MAX; n_px];
    let mut frag_at: Vec<Option<(Fragment, [i64; 2])>> = vec![None; n_px];
    let mut triangles = 0;
    let mut fragments = 0u64;
    for (tri, lam) in &geo {
        let mut hv = [HostVertex {
            x: 0.0,
            y: 0.0,
            attrs: host_attrs([]),
        }; 3];
        let mut ok = true;
        // Two-sided lighting (GL's LIGHT_MODEL_TWO_SIDE): a triangle seen from its back
        // (the teapot is an open sheet: the inside of the rim and spout shows) gets its
        // normals flipped. Per primitive, host side (the facing is the sign of the
        // screen-space area the setup computes anyway).
        let face = (tri.p[1] - tri.p[0]).cross(tri.p[2] - tri.p[0]);
        let flip = if face.dot(cam.eye - tri.p[0]) < 0.0 {
            -1.0
        } else {
            1.0
        };
        for k in 0..3 {
            let Some((sx, sy, sz)) = cam.project(tri.p[k]) else {
                ok = false;
                break;
            };
            let n = tri.n[k] * flip;
            let e = cam.eye - tri.p[k];
            let (u, v) = texgen.uv(tri.p[k]);
            // An 8-attribute interpolator reads the first 8 (u, v unused).
            hv[k] = HostVertex {
                x: sx,
                y: sy,
                attrs: host_attrs([n.x, n.y, n.z, e.x, e.y, e.z, lam[k], sz, u, v]),
            };
        }
        if !ok {
            continue;
        }
        triangles += 1;
        let frags = draw_triangle(&interp, &hv, w, h, &mut c_int)?;
        let probe = match &uv_probe {
            Some(p) => {
                let f = draw_triangle(p, &hv, w, h, &mut Counters::default())?;
                if f.len() != frags.len()
                    || f.iter().zip(&frags).any(|(a, b)| (a.x, a.y) != (b.x, b.y))
                {
                    return Err(ConfigError::invalid(
                        "envmap_render.texcoord",
                        "the (u, v) measurement walk covered other pixels than the render",
                    ));
                }
                f
            }
            None => Vec::new(),
        };
        for (i, f) in frags.into_iter().enumerate() {
            fragments += 1;
            let k = (f.y * w + f.x) as usize;
            // Integer depth compare on the s16.16 window-depth code (less wins).
            if f.attrs[7] < zbuf[k] {
                zbuf[k] = f.attrs[7];
                let uv = match (texture_side, probe.get(i)) {
                    (Some(_), _) => [f.attrs[8], f.attrs[9]],
                    (None, Some(g)) => [g.attrs[8], g.attrs[9]],
                    (None, None) => [0; 2],
                };
                frag_at[k] = Some((f, uv));
            }
        }
    }

    // ---- per visible pixel: reflection (f64 gap), λ, coordinate hand-over, sampler.
    let mut img = Image::new(w, h);
    let mut c_tex = Counters::default();
    let mut c_rough = Counters::default();
    let mut shading: Vec<(usize, Shading)> = Vec::new();
    let mut rough_in: Vec<TextureSamplerIn> = Vec::new();
    let mut back_normal_pixels = 0;
    let a = |raw: i64| interp.out_to_f64(raw);
    for (k, f) in frag_at.iter().enumerate() {
        let Some((f, uv)) = f else { continue };
        let n = v3(a(f.attrs[0]), a(f.attrs[1]), a(f.attrs[2])).normalized();
        let v = v3(a(f.attrs[3]), a(f.attrs[4]), a(f.attrs[5])).normalized();
        let lam = a(f.attrs[6]).clamp(0.0, 1.0);
        if n.dot(v) < 0.0 {
            back_normal_pixels += 1;
        }
        // GAP: the reflection and t = r·λ are host f64 (module notes, step 4).
        let (n, r) = reflect(n, v);
        let (u, vv) = (a(uv[0]), a(uv[1]));
        if let Some(rs) = &rough {
            rough_in.push(
                rs.config()
                    .input_from_normalized([u, vv, 0.0], &mut c_rough)?,
            );
        }
        let lambda_intended = if want_uv {
            lambda_of_uv(object, lambda, u, vv)
        } else {
            lam
        };
        shading.push((
            k,
            Shading {
                n,
                r,
                lambda: lam,
                lambda_intended,
            },
        ));
        if let Some(ru) = &refl_unit {
            // The interpolator's raw codes go straight in; λ s16.16 → u1.12.
            refl_in.push(ReflectionVectorIn {
                n: [f.attrs[0], f.attrs[1], f.attrs[2]],
                e: [f.attrs[3], f.attrs[4], f.attrs[5]],
                lambda: ru.lambda_from_code(f.attrs[6], ATTR_FRAC, &mut c_refl),
            });
        }
    }
    // The roughness texture: λ = code / 255 replaces the interpolated λ.
    if let Some(rs) = &rough {
        let codes = run_span(rs, &mut (), &rough_in, &mut c_rough);
        let max = ((1u32 << ROUGHNESS_BITS) - 1) as f64;
        for ((_, sh), c) in shading.iter_mut().zip(&codes) {
            sh.lambda = c[0] as f64 / max;
        }
        if let Some(ru) = &refl_unit {
            // The texture's u0.8 code c → u1.L: round(c · 2^L / 255), a constant
            // multiply (integer, ties up).
            let l = ru.config().lambda_bits;
            let m = (1u64 << ROUGHNESS_BITS) - 1;
            for (ri, c) in refl_in.iter_mut().zip(&codes) {
                ri.lambda = ((2 * (c[0] as u64) * (1u64 << l) + m) / (2 * m)) as u32;
            }
        }
    }
    let inputs: Vec<TextureSamplerIn> = match (&refl_unit, two_d.is_some()) {
        // The unit: raw codes → the 3D sampler's s16.8 texel words.
        (Some(ru), false) => run_span(ru, &mut (), &refl_in, &mut c_refl)
            .iter()
            .map(|o| o.sampler_in())
            .collect(),
        _ => {
            let mut v = Vec::with_capacity(shading.len());
            for (_, sh) in &shading {
                let stq = if two_d.is_some() {
                    // 2D slice: the lookup is on |t| = λ, addressed by r's direction
                    // (host f64, lat-long: a documented gap).
                    slice::slice_coord(sh.r)
                } else {
                    let t = sh.r * sh.lambda;
                    [(t.x + 1.0) * 0.5, (t.y + 1.0) * 0.5, (t.z + 1.0) * 0.5]
                };
                v.push(sampler.config().input_from_normalized(stq, &mut c_tex)?);
            }
            v
        }
    };
    let texel_out = run_span(sampler, &mut (), &inputs, &mut c_tex);
    let max_code = map.max_code();
    let to8 = |c: u32| -> u8 {
        if max_code == 255 {
            c.min(255) as u8
        } else {
            ((c as u64 * 255 + max_code as u64 / 2) / max_code as u64).min(255) as u8
        }
    };
    for ((k, _), out) in shading.iter().zip(&texel_out) {
        img.pixels[*k] = [to8(out[0]), to8(out[1]), to8(out[2])];
        img.mask[*k] = true;
    }

    // ---- background
    let mut background = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let k = (y * w + x) as usize;
            if img.mask[k] {
                continue;
            }
            let bg = match opt.background {
                Background::Black => [0; 3],
                Background::Environment => {
                    let d = cam.ray_dir(x as f64 + 0.5, y as f64 + 0.5);
                    levels_env.lookup(d).map(level8)
                }
            };
            img.pixels[k] = bg;
            background.push((k, bg));
        }
    }

    let shaded = shading.len() as u64;
    let mut elaboration = slice::elaboration(
        two_d.as_ref().map(|(s2, sl)| (s2, sl)),
        &sampler3,
        map,
        shaded,
    );
    let refl_used = refl_unit.as_ref().filter(|_| two_d.is_none());
    if let Some(ru) = refl_used {
        elaboration.units.push(Elaborated {
            name: "reflection_vector".into(),
            summary: Some(UnitSummary::of(ru)),
            left_out: None,
            gates_saved: 0.0,
            cycles_saved: 0,
        });
    }
    if let Some(rs) = &rough {
        elaboration.units.push(Elaborated {
            name: "texture_sampler (roughness)".into(),
            summary: Some(UnitSummary::of(rs)),
            left_out: None,
            gates_saved: 0.0,
            cycles_saved: 0,
        });
        // Not a unit of its own: the interpolator's 2 more attribute channels, costed
        // as the increment over the 8-attribute configuration.
        elaboration.units.push(Elaborated {
            name: TEXCOORD_CHANNELS.into(),
            summary: Some(texcoord_channels_cost()?),
            left_out: None,
            gates_saved: 0.0,
            cycles_saved: 0,
        });
        elaboration.roughness_texture_bytes =
            rs.config().texel_count() * u64::from(ROUGHNESS_BITS.div_ceil(8));
    }
    let frame = FrameInfo {
        width: w,
        height: h,
        triangles,
        fragments,
        shaded,
        background_pixels: background.len() as u64,
        texels_per_lookup: sampler.config().texels_per_sample(),
        roughness_texels_per_lookup: rough
            .as_ref()
            .map_or(0, |rs| rs.config().texels_per_sample()),
        elaboration,
    };
    let mut counters = BTreeMap::new();
    counters.insert("polygon_interpolator".to_string(), c_int);
    counters.insert("texture_sampler (envmap)".to_string(), c_tex);
    if rough.is_some() {
        counters.insert("texture_sampler (roughness)".to_string(), c_rough);
    }
    if refl_used.is_some() {
        counters.insert("reflection_vector".to_string(), c_refl);
    }
    Ok(Rendered {
        img,
        background,
        shading,
        levels_env,
        side: s,
        counters,
        triangles,
        back_normal_pixels,
        frame,
    })
}

/// The `reflection_vector` unit for a map of side `s` (a power of two), its output words
/// in `sampler`'s coordinate format, the rest at the GeForce3 defaults.
fn reflection_unit(sampler: &TextureSampler, s: u32) -> Result<ReflectionVector, ConfigError> {
    if !s.is_power_of_two() {
        return Err(ConfigError::invalid(
            "envmap_render.reflection",
            &format!("the reflection_vector unit needs a power-of-two map side, not {s} (use Reflection::HostF64)"),
        ));
    }
    let sc = sampler.config();
    ReflectionVectorConfig {
        side_log2: s.trailing_zeros(),
        coord_int_bits: sc.coord_int_bits,
        coord_frac_bits: sc.coord_frac_bits,
        ..ReflectionVectorConfig::geforce3()
    }
    .build()
}

/// A level in f64 rounded to an 8-bit level (clamped).
fn level8(x: f64) -> u8 {
    x.clamp(0.0, 255.0).round() as u8
}

/// The two truths at the rendered pixels (parallel over pixels, deterministic), with
/// the render's background.
fn truth_images(r: &Rendered, intended: bool) -> Result<Truth, ConfigError> {
    use rayon::prelude::*;
    let (w, h) = (r.img.width, r.img.height);
    let truth = PhongTruth::new(&r.levels_env);
    let s = r.side as f64;
    type Px = ([u8; 3], [u8; 3], Option<[u8; 3]>);
    let px: Vec<Px> = r
        .shading
        .par_iter()
        .map(|(_, sh)| {
            let big_lambda = g(sh.lambda * sh.r.length(), s, THESIS_LEVELS);
            let tc = truth.eval(sh.r, sh.n, big_lambda, Visibility::CosPhiTest)?;
            let ts = truth.eval(sh.r, sh.n, big_lambda, Visibility::Simplified)?;
            let ti = if intended {
                let big = g(sh.lambda_intended * sh.r.length(), s, THESIS_LEVELS);
                Some(
                    truth
                        .eval(sh.r, sh.n, big, Visibility::Simplified)?
                        .map(level8),
                )
            } else {
                None
            };
            Ok((tc.map(level8), ts.map(level8), ti))
        })
        .collect::<Result<_, ConfigError>>()?;
    let mut truth_c = Image::new(w, h);
    let mut truth_s = Image::new(w, h);
    let mut truth_i = intended.then(|| Image::new(w, h));
    for ((k, _), (c, s, i)) in r.shading.iter().zip(px) {
        truth_c.pixels[*k] = c;
        truth_s.pixels[*k] = s;
        truth_c.mask[*k] = true;
        truth_s.mask[*k] = true;
        if let (Some(ti), Some(i)) = (truth_i.as_mut(), i) {
            ti.pixels[*k] = i;
            ti.mask[*k] = true;
        }
    }
    for &(k, bg) in &r.background {
        truth_c.pixels[k] = bg;
        truth_s.pixels[k] = bg;
        if let Some(ti) = truth_i.as_mut() {
            ti.pixels[k] = bg;
        }
    }
    Ok(Truth {
        cos_phi: truth_c,
        simplified: truth_s,
        side: r.side,
        intended: truth_i,
    })
}

/// r = 2(n̂·v)n̂ − v for unit v (host f64: the documented gap). A zero normal (never
/// from the tessellations) is replaced by v. Returns (n̂, r), r unit.
fn reflect(n: Vec3, v: Vec3) -> (Vec3, Vec3) {
    let n = if n.length() > 0.0 { n } else { v };
    let v = if v.length() > 0.0 { v } else { n };
    let r = (n * (2.0 * n.dot(v)) - v).normalized();
    let r = if r.length() > 0.0 { r } else { n };
    (n, r)
}

/// One row of the thesis' Table 5 (errors against the cos φ truth, 8-bit levels).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Table5Row {
    pub object: String,
    pub env: String,
    pub lambda: String,
    pub accelerated: bool,
    pub mean: [f64; 3],
    pub var: [f64; 3],
}

impl Table5Row {
    pub const CSV_HEADER: &'static str =
        "object,env,lambda,accelerated,mean_r,mean_g,mean_b,var_r,var_g,var_b";

    pub fn to_csv(&self) -> String {
        format!(
            "{},{},{},{},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4}",
            self.object,
            self.env,
            self.lambda,
            self.accelerated,
            self.mean[0],
            self.mean[1],
            self.mean[2],
            self.var[0],
            self.var[1],
            self.var[2]
        )
    }
}

/// The λ cases of Table 5: 1, 0.75, 0.5, 0.25, non-uniform.
pub const TABLE5_LAMBDAS: [LambdaSpec; 5] = [
    LambdaSpec::Uniform(1.0),
    LambdaSpec::Uniform(0.75),
    LambdaSpec::Uniform(0.5),
    LambdaSpec::Uniform(0.25),
    LambdaSpec::NonUniform,
];

/// Table 5 rows for `objects` × [`TABLE5_LAMBDAS`] with `map` (the caller says whether
/// it was built accelerated and names the environment), at `size`.
pub fn table5_rows(
    env: &EnvMap,
    env_name: &str,
    map: &VoxelMap,
    accelerated: bool,
    objects: &[Object],
    size: (u32, u32),
) -> Result<Vec<Table5Row>, ConfigError> {
    let mut rows = Vec::new();
    for &object in objects {
        for lambda in TABLE5_LAMBDAS {
            let (_, _, st) = render_object(env, map, object, lambda, size)?;
            rows.push(Table5Row {
                object: object.name().to_string(),
                env: env_name.to_string(),
                lambda: lambda.label(),
                accelerated,
                mean: st.cos_phi.mean,
                var: st.cos_phi.var,
            });
        }
    }
    Ok(rows)
}

/// One row of the roughness comparison: a λ source's errors against the intended-λ
/// truth ([`Truth::intended`], eq. 3, 8-bit levels).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RoughnessRow {
    pub object: String,
    /// [`LambdaSource::label`].
    pub lambda_source: String,
    /// Object pixels.
    pub pixels: usize,
    /// Mean and largest |Δ| per channel over the object.
    pub mean: [f64; 3],
    pub max: [f64; 3],
    /// The same over the seam band ([`IntendedErrors::seam`]; 0 pixels for the teapot).
    pub seam_pixels: usize,
    pub seam_mean: [f64; 3],
    pub seam_max: [f64; 3],
    /// Mean |Δ| over the seam band against the truth with the render's own λ (the
    /// map's floor there, [`IntendedErrors::seam_own`]).
    pub seam_own_mean: [f64; 3],
    /// Mean and largest |λ used − λ intended| over the object and the seam band.
    pub lambda_mean: f64,
    pub lambda_max: f64,
    pub seam_lambda_mean: f64,
    pub seam_lambda_max: f64,
}

impl RoughnessRow {
    pub const CSV_HEADER: &'static str = "object,lambda_source,pixels,mean_r,mean_g,mean_b,max_r,max_g,max_b,seam_pixels,seam_mean_r,seam_mean_g,seam_mean_b,seam_max_r,seam_max_g,seam_max_b,seam_own_mean_r,seam_own_mean_g,seam_own_mean_b,lambda_mean,lambda_max,seam_lambda_mean,seam_lambda_max";

    pub fn to_csv(&self) -> String {
        let f = |v: [f64; 3]| format!("{:.4},{:.4},{:.4}", v[0], v[1], v[2]);
        format!(
            "{},{},{},{},{},{},{},{},{},{:.5},{:.5},{:.5},{:.5}",
            self.object,
            self.lambda_source,
            self.pixels,
            f(self.mean),
            f(self.max),
            self.seam_pixels,
            f(self.seam_mean),
            f(self.seam_max),
            f(self.seam_own_mean),
            self.lambda_mean,
            self.lambda_max,
            self.seam_lambda_mean,
            self.seam_lambda_max
        )
    }

    /// Mean of the three channels' mean |Δ| (over the object, and over the seam band).
    pub fn mean_rgb(&self) -> f64 {
        self.mean.iter().sum::<f64>() / 3.0
    }
    pub fn seam_mean_rgb(&self) -> f64 {
        self.seam_mean.iter().sum::<f64>() / 3.0
    }
    pub fn seam_own_mean_rgb(&self) -> f64 {
        self.seam_own_mean.iter().sum::<f64>() / 3.0
    }
}

/// The thesis' proposed fix measured (issue 5): `object` with the non-uniform λ at
/// `size`, rendered with λ per vertex and with a `side` × `side` roughness texture,
/// each against the intended-λ truth (the same truth image for both: it depends only
/// on the geometry and the interpolated n, r, (u, v)). Rows in that order. Errors as
/// [`render_object_with`] and "envmap_render.lambda_texture".
pub fn roughness_comparison(
    env: &EnvMap,
    map: &VoxelMap,
    object: Object,
    size: (u32, u32),
    side: u32,
) -> Result<Vec<RoughnessRow>, ConfigError> {
    let mut rows = Vec::new();
    for source in [LambdaSource::PerVertex, LambdaSource::Texture { side }] {
        let opt = RenderOptions {
            lambda_source: source,
            intended_truth: true,
            ..RenderOptions::default()
        };
        // Each source gets its own truths: the intended one is the same image for both,
        // but `seam_own` needs the truth with the λ this render used.
        let (_, _, st) = render_object_with(env, map, object, LambdaSpec::NonUniform, size, &opt)?;
        let i = st.intended.unwrap_or_default();
        rows.push(RoughnessRow {
            object: object.name().to_string(),
            lambda_source: source.label(),
            pixels: i.all.pixels,
            mean: i.all.mean,
            max: i.all.max,
            seam_pixels: i.seam.pixels,
            seam_mean: i.seam.mean,
            seam_max: i.seam.max,
            seam_own_mean: i.seam_own.mean,
            lambda_mean: i.lambda_all.mean,
            lambda_max: i.lambda_all.max,
            seam_lambda_mean: i.lambda_seam.mean,
            seam_lambda_max: i.lambda_seam.max,
        });
    }
    Ok(rows)
}
