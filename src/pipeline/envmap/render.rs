//! Rendering a sphere or the Utah teapot with the multi-scale environment map (Okumura's
//! thesis §3.5 and §4.3, Table 5) through the hardware units, against the Phong
//! ground truth.
//!
//! # The per-pixel path, and what in it is f64
//!
//! 1. **Geometry (host, f64, per vertex — the application / T&L stage).** The object is
//!    tessellated ([`crate::scene::teapot::sphere_triangles`],
//!    [`crate::scene::teapot::tessellate_teapot`]; `super::objects`); every vertex is
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
//!    thesis' proposed fix) takes λ per pixel from a roughness
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
//!    reflection of the interpolated n, e). On the 2D path (below) HostF64 addresses the
//!    cube map by the f64 r through the `cube_map_address` twin (a comparison path,
//!    labelled so in the elaboration).
//!
//!    **The 2D path ([`Lookup::Auto`] with a uniform λ): cube_map_address (unit).**
//!    The reflection unit's s16.8 words go into the `cube_map_address` unit (direction
//!    d = c − s/2, OpenGL face selection, (sc/|ma| + 1)/2 · F by a reciprocal ROM and
//!    one Newton step; error ≤ 0.0244 texel at F = 256, docs/units.md), whose stacked
//!    F × 6F word is the 2D sampler's input ([`super::slice`]). No host f64 on the
//!    lookup path any more.
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
//! Texgen, the roughness texture and sampler, the intended-λ truth and its seam band:
//! see [`super::roughness`]'s module notes.
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
//! At every object pixel the truth is [`crate::reference::phong_truth::PhongTruth::eval`] on the same level map, with
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
//! [`render_geometry`] draws any triangles with per-vertex λ seen from any camera at any
//! size through the same steps (the thesis objects and camera through it give the
//! same bytes as [`render_frame`]); `super::scene_render` draws a scene's
//! `[environment]` object with it.
//!
//! # Test/small map builder
//!
//! [`quick_map`] is a SMALL, TEST-ONLY map builder: see [`super::quick_map`].

use std::collections::BTreeMap;

use rayon::prelude::*;
use rtl_model::driver::{add_span_counters, run_span};
use rtl_model::error::{check_range, ConfigError};
use rtl_model::units::cube_map_address::{CubeMapAddress, CubeMapAddressIn, CubeMapAddressOut};
use rtl_model::units::polygon_interpolator::PolygonInterpolator;
use rtl_model::units::reflection_vector::{
    ReflectionVector, ReflectionVectorConfig, ReflectionVectorIn, ReflectionVectorOut,
};
#[cfg(doc)]
use rtl_model::units::texture_sampler::TextureSamplerConfig;
use rtl_model::units::texture_sampler::{TextureSampler, TextureSamplerIn};
use rtl_model::{Counters, Unit, UnitSummary};

pub use super::image::{ErrorStats, Image};
use super::interpolator::ATTR_FRAC;
pub use super::interpolator::{
    render_interpolator, texcoord_channels_cost, RENDER_ATTRS, RENDER_ATTRS_TEXTURE,
    TEXCOORD_CHANNELS,
};
pub use super::objects::{
    camera, object_geometry, LambdaSpec, Object, SPHERE_RINGS, SPHERE_SEGMENTS, TEAPOT_SCALE,
    TEAPOT_SUBDIVISIONS,
};
pub use super::quick_map::{quick_map, quick_map_with, QUICK_MAP_MAX_TEXELS};
use super::roughness::ROUGHNESS_BITS;
pub use super::roughness::{
    lambda_of_uv, object_texgen, roughness_sampler, roughness_texels, IntendedErrors, LambdaErrors,
    LambdaSource, TexGen, DEFAULT_LAMBDA_TEXTURE_SIDE, MAX_LAMBDA_TEXTURE_SIDE, SEAM_JUMP,
    SEAM_RADIUS,
};
use super::slice;
pub use super::truth::Truth;
use super::truth::{intended_errors, level8, truth_images, Shading};
use super::voxmap::{SliceTexture, VoxelMap};
use super::walk::Frag;
use crate::report::elaboration::Elaborated;
use crate::scene::camera::CameraView;
use crate::scene::envmap::EnvMap;
use crate::scene::format::{Camera, ImageSize};
use crate::scene::math::{v3, Vec3};
use crate::scene::teapot::Triangle;

/// Largest image side.
pub const MAX_IMAGE_SIDE: u32 = 4096;
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
    /// radius λ — a cube map of six F × F faces — through the `cube_map_address` unit
    /// and the 2D (bilinear) sampler (`super::slice`); the 3D map for
    /// [`LambdaSpec::NonUniform`].
    Auto,
}

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
    /// Texels one lookup reads (8: trilinear 3D; 4: bilinear 2D cube map).
    pub texels_per_lookup: u32,
    /// Texels of the roughness texture each shaded pixel reads (4: bilinear, with
    /// [`LambdaSource::Texture`]; 0 per vertex). Not yet in the frame-time model.
    pub roughness_texels_per_lookup: u32,
    /// Which sampler was elaborated, which left out, and the bytes and gates saved.
    pub elaboration: super::slice::Elaboration,
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
    let r = render_core(env, map, object, lambda, size, opt, true)?;
    with_truth(r, opt)
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
    let r = render_core(env, map, object, lambda, size, opt, true)?;
    against(r, truth)
}

/// The errors of `r` against `truth`, made by an earlier render of the same pixels:
/// its object mask, size and map side checked against `r`'s ("envmap_render.truth").
fn against(r: Rendered, truth: &Truth) -> Result<(Image, RenderStats), ConfigError> {
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
    Ok(render_core(env, map, object, lambda, size, opt, false)?.img)
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
    let r = render_core(env, map, object, lambda, size, opt, false)?;
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
            intended: truth
                .intended
                .as_ref()
                .map(|t| intended_errors(&self.img, &self.shading, t, &truth.simplified)),
        }
    }
}

/// Render arbitrary triangles with per-vertex λ (world space, each λ in [0, 1]) seen
/// from `camera` at `size` = (width, height) through the same units and steps as
/// [`render_frame`] (module notes): the image with its coverage mask, the frame's
/// counts and elaboration, and the unit counters. The 2D-slice lookup
/// ([`Lookup::Auto`]) is elaborated when every vertex has the same λ. Per-vertex λ only:
/// a roughness texture and the intended-λ truth need a thesis object (errors naming
/// "envmap_render.lambda_source" / "envmap_render.intended_truth"). Other errors:
/// "envmap_render.size", "envmap_render.lambda", the camera's fields (`camera.…`),
/// "envmap.exposure", unit config errors.
///
/// With [`object_geometry`] of a thesis object and [`camera`] it gives
/// [`render_frame`]'s image and frame (tests/envmap_scene.rs).
pub fn render_geometry(
    env: &EnvMap,
    map: &VoxelMap,
    tris: &[(Triangle, [f64; 3])],
    camera: &Camera,
    size: (u32, u32),
    opt: &RenderOptions,
) -> Result<(Image, FrameInfo, BTreeMap<String, Counters>), ConfigError> {
    let r = render_tris(env, map, &drawn(tris, camera)?, size, opt, false)?;
    Ok((r.img, r.frame, r.counters))
}

/// [`render_geometry`] and the two Phong truths at the same pixels (as
/// [`render_object_with`] makes them): the image, the truths and the errors against them.
pub fn render_geometry_with_truth(
    env: &EnvMap,
    map: &VoxelMap,
    tris: &[(Triangle, [f64; 3])],
    camera: &Camera,
    size: (u32, u32),
    opt: &RenderOptions,
) -> Result<(Image, Truth, RenderStats), ConfigError> {
    let r = render_tris(env, map, &drawn(tris, camera)?, size, opt, true)?;
    with_truth(r, opt)
}

/// As [`render_geometry_with_truth`], but reusing `truth` from an earlier call with
/// the same environment, exposure, triangles, camera, size and map side (as
/// [`render_against`] for the thesis objects): the truth depends on the map's side s
/// (Λ = g(λ·|r|, s, I)), never on its voxels. Its object mask, size and side are
/// checked against this render's ("envmap_render.truth").
pub fn render_geometry_against(
    env: &EnvMap,
    map: &VoxelMap,
    tris: &[(Triangle, [f64; 3])],
    camera: &Camera,
    size: (u32, u32),
    opt: &RenderOptions,
    truth: &Truth,
) -> Result<(Image, RenderStats), ConfigError> {
    let r = render_tris(env, map, &drawn(tris, camera)?, size, opt, true)?;
    against(r, truth)
}

/// The render's image, its two truths and the errors against them.
fn with_truth(
    r: Rendered,
    opt: &RenderOptions,
) -> Result<(Image, Truth, RenderStats), ConfigError> {
    let truth = truth_images(
        &r.shading,
        &r.background,
        &r.levels_env,
        r.side,
        (r.img.width, r.img.height),
        opt.intended_truth,
    )?;
    let stats = r.stats(&truth);
    Ok((r.img, truth, stats))
}

/// What a render draws: triangles with per-vertex λ seen from a camera, and for a
/// thesis object what the roughness texture and the intended-λ truth need.
struct Drawn<'a> {
    tris: &'a [(Triangle, [f64; 3])],
    camera: &'a Camera,
    /// λ when every vertex has the same one: the 2D-slice elaboration's condition.
    uniform: Option<f64>,
    /// The thesis object and its λ (texgen, roughness texture, intended λ).
    object: Option<(Object, LambdaSpec)>,
}

/// Arbitrary triangles: their λ checked, the camera checked, uniform λ found.
fn drawn<'a>(
    tris: &'a [(Triangle, [f64; 3])],
    camera: &'a Camera,
) -> Result<Drawn<'a>, ConfigError> {
    crate::scene::validate::validate_camera(camera)?;
    for (_, lam) in tris {
        for &l in lam {
            LambdaSpec::Uniform(l).validate()?;
        }
    }
    let first = tris.first().map(|(_, lam)| lam[0]);
    let uniform = first.filter(|&l| tris.iter().all(|(_, lam)| lam.iter().all(|&x| x == l)));
    Ok(Drawn {
        tris,
        camera,
        uniform,
        object: None,
    })
}

fn render_core(
    env: &EnvMap,
    map: &VoxelMap,
    object: Object,
    lambda: LambdaSpec,
    size: (u32, u32),
    opt: &RenderOptions,
    truth: bool,
) -> Result<Rendered, ConfigError> {
    let (w, h) = size;
    check_range("envmap_render.size", w.into(), 1, MAX_IMAGE_SIDE.into())?;
    check_range("envmap_render.size", h.into(), 1, MAX_IMAGE_SIDE.into())?;
    lambda.validate()?;
    opt.lambda_source.validate()?;
    let cam_cfg = camera();
    let cam = CameraView::new(
        &cam_cfg,
        ImageSize {
            width: w,
            height: h,
        },
    );
    let tris = object_geometry(object, lambda, &cam)?;
    let drawn = Drawn {
        tris: &tris,
        camera: &cam_cfg,
        uniform: lambda.uniform(),
        object: Some((object, lambda)),
    };
    render_tris(env, map, &drawn, size, opt, truth)
}

/// The render of `drawn` (module notes, steps 1–7). `truth`: also keep what the truth
/// and the statistics read (the f64 n̂, r, λ per object pixel and the background
/// list); without it the f64 shading is skipped where the lookup does not need it
/// (the same image and counters).
fn render_tris(
    env: &EnvMap,
    map: &VoxelMap,
    drawn: &Drawn<'_>,
    size: (u32, u32),
    opt: &RenderOptions,
    truth: bool,
) -> Result<Rendered, ConfigError> {
    let (w, h) = size;
    check_drawn(drawn, size, opt)?;
    let exposure = opt.exposure.unwrap_or_else(|| env.auto_exposure());
    let levels_env = env.to_level_map(exposure)?;
    let cam = CameraView::new(
        drawn.camera,
        ImageSize {
            width: w,
            height: h,
        },
    );
    let units = RenderUnits::new(map, drawn, opt, &cam)?;

    // ---- raster + depth test (walk.rs)
    let walked = super::walk::walk(
        drawn.tris,
        &super::walk::WalkSetup {
            cam: &cam,
            texgen: &units.texgen,
            interp: &units.interp,
            uv_probe: units.uv_probe.as_ref(),
            uv_from_render: units.texture_side.is_some(),
            w,
            h,
        },
    )?;
    let (visible, triangles, fragments, c_int) = (
        walked.visible,
        walked.triangles,
        walked.fragments,
        walked.counters,
    );

    // ---- per visible pixel, host f64 (only where needed), then the roughness texture
    let mut c_rough = Counters::default();
    let mut host = units.host_shading(drawn, &visible, truth, &mut c_rough)?;
    let rough_lambda = units.roughness_lambda(&host.rough_in, &mut host.shading, &mut c_rough);

    // ---- the lookup chain into the object's pixels
    let mut img = Image::new(w, h);
    let [c_refl, c_cube, c_tex] = units.lookups(
        map,
        &host.shading,
        rough_lambda.as_deref(),
        &visible,
        &mut img,
    )?;

    // ---- background
    fill_background(&mut img, opt, &cam, &levels_env);
    let background_pixels = img.mask.iter().filter(|&&m| !m).count() as u64;
    // The truths' background: the same pixels, listed.
    let background = if truth {
        background_list(&img)
    } else {
        Vec::new()
    };

    let shaded = visible.len() as u64;
    let frame = FrameInfo {
        width: w,
        height: h,
        triangles,
        fragments,
        shaded,
        background_pixels,
        texels_per_lookup: units.sampler().config().texels_per_sample(),
        roughness_texels_per_lookup: units
            .rough
            .as_ref()
            .map_or(0, |rs| rs.config().texels_per_sample()),
        elaboration: units.elaboration(map, shaded)?,
    };
    Ok(Rendered {
        img,
        background,
        shading: host.shading,
        levels_env,
        side: units.s,
        counters: units.counters(c_int, [c_refl, c_cube, c_tex], c_rough),
        triangles,
        back_normal_pixels: host.back_normal_pixels,
        frame,
    })
}

/// The render's own checks, before any work: the image size, the λ source, and what
/// only a thesis object has (texgen, intended λ).
fn check_drawn(
    drawn: &Drawn<'_>,
    size: (u32, u32),
    opt: &RenderOptions,
) -> Result<(), ConfigError> {
    let (w, h) = size;
    check_range("envmap_render.size", w.into(), 1, MAX_IMAGE_SIDE.into())?;
    check_range("envmap_render.size", h.into(), 1, MAX_IMAGE_SIDE.into())?;
    opt.lambda_source.validate()?;
    if drawn.object.is_none() {
        if opt.lambda_source != LambdaSource::PerVertex {
            return Err(ConfigError::invalid(
                "envmap_render.lambda_source",
                "a roughness texture needs a thesis object's texgen; arbitrary triangles take λ per vertex",
            ));
        }
        if opt.intended_truth {
            return Err(ConfigError::invalid(
                "envmap_render.intended_truth",
                "the intended λ is defined on the thesis objects only",
            ));
        }
    }
    Ok(())
}

/// The units one render instantiates (module notes, steps 2–6), and the choices that
/// pick them.
struct RenderUnits<'m> {
    /// The roughness texture's side, with [`LambdaSource::Texture`].
    texture_side: Option<u32>,
    /// The truth or the texture reads (u, v).
    want_uv: bool,
    /// ONE interpolator: n, e, λ, z (8 attributes); with a roughness texture also the
    /// texture coordinate (u, v) as attributes 8 and 9 (10 attributes).
    interp: PolygonInterpolator,
    /// Per-vertex λ with the intended truth: the render stays at 8 attributes; the
    /// truth's (u, v) come from a MEASUREMENT walk of the 10-attribute config (not
    /// counted, not elaborated), so both sources see the same (u, v) codes.
    uv_probe: Option<PolygonInterpolator>,
    texgen: TexGen,
    /// The roughness texture's sampler.
    rough: Option<TextureSampler>,
    /// The map's side s.
    s: u32,
    sampler3: &'m TextureSampler,
    refl_unit: Option<ReflectionVector>,
    /// Cube-map face side F.
    face: u32,
    /// The 2D-slice elaboration's cube map and 2D sampler (None: the 3D path).
    two_d: Option<SliceTexture>,
    cube: CubeMapAddress,
}

impl<'m> RenderUnits<'m> {
    fn new(
        map: &'m VoxelMap,
        drawn: &Drawn<'_>,
        opt: &RenderOptions,
        cam: &CameraView,
    ) -> Result<Self, ConfigError> {
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
        let uv_probe = (texture_side.is_none() && opt.intended_truth).then_some(interp_uv);
        // Without a thesis object (u, v) are never read (8 attributes, no probe).
        let texgen = match drawn.object {
            Some((object, _)) => object_texgen(object, cam),
            None => TexGen::unused(),
        };
        let rough = match (texture_side, drawn.object) {
            (Some(side), Some((object, lambda))) => Some(roughness_sampler(object, lambda, side)?),
            _ => None,
        };
        let s = map.side();
        let sampler3 = slice::sampler_3d(map)?;
        let refl_unit = match opt.reflection {
            Reflection::Unit => Some(reflection_unit(sampler3, s)?),
            Reflection::HostF64 => None,
        };
        // The 2D-slice elaboration: uniform λ (per vertex) reads the map only on |t| = λ:
        // a cube map of six F × F faces through the 2D sampler, addressed by the
        // cube_map_address unit from the reflection unit's words.
        let face = slice::default_face_side(s);
        let two_d = cube_map(map, opt, drawn.uniform)?;
        let cube = slice::cube_unit(sampler3.config(), s, face)?;
        let units = RenderUnits {
            texture_side,
            want_uv,
            interp,
            uv_probe,
            texgen,
            rough,
            s,
            sampler3,
            refl_unit,
            face,
            two_d,
            cube,
        };
        let (sc, cc) = (units.sampler().config(), units.cube.config());
        if (sc.coord_int_bits, sc.coord_frac_bits) != (cc.coord_int_bits, cc.coord_frac_bits) {
            return Err(ConfigError::invalid(
                "envmap_slice.sampler",
                "the 2D sampler does not read the cube_map_address unit's word format",
            ));
        }
        Ok(units)
    }

    /// The render's unit counters by name: the interpolator's `c_int`, the lookup
    /// chain's `[reflection_vector, cube_map_address, sampler]` and the roughness
    /// texture's `c_rough`, each unit's only where it ran.
    fn counters(
        &self,
        c_int: Counters,
        [c_refl, c_cube, c_tex]: [Counters; 3],
        c_rough: Counters,
    ) -> BTreeMap<String, Counters> {
        let mut counters = BTreeMap::new();
        counters.insert("polygon_interpolator".to_string(), c_int);
        counters.insert("texture_sampler (envmap)".to_string(), c_tex);
        if self.rough.is_some() {
            counters.insert("texture_sampler (roughness)".to_string(), c_rough);
        }
        if self.refl_unit.is_some() {
            counters.insert("reflection_vector".to_string(), c_refl);
        }
        if self.cube_used() {
            counters.insert("cube_map_address".to_string(), c_cube);
        }
        counters
    }

    /// The sampler the object's lookups read: the 2D one on the 2D path, else the 3D.
    fn sampler(&self) -> &TextureSampler {
        self.two_d.as_deref().map_or(self.sampler3, |(s2, _)| s2)
    }

    /// The 2D path's `cube_map_address` unit runs (it needs the reflection unit's words).
    fn cube_used(&self) -> bool {
        self.two_d.is_some() && self.refl_unit.is_some()
    }

    /// Per visible pixel, host f64 (only where needed: the truth, the HostF64 path or the
    /// roughness texture): n̂, the f64 r, λ, and the roughness texture's inputs (counted
    /// in `c_rough`).
    fn host_shading(
        &self,
        drawn: &Drawn<'_>,
        visible: &[Frag],
        truth: bool,
        c_rough: &mut Counters,
    ) -> Result<HostShading, ConfigError> {
        let mut shading: Vec<(usize, Shading)> = Vec::new();
        let mut rough_in: Vec<TextureSamplerIn> = Vec::new();
        let mut back_normal_pixels = 0;
        let a = |raw: i64| self.interp.out_to_f64(raw);
        if truth || self.refl_unit.is_none() || self.rough.is_some() {
            for f in visible {
                let n = v3(a(f.attrs[0]), a(f.attrs[1]), a(f.attrs[2])).normalized();
                let v = v3(a(f.attrs[3]), a(f.attrs[4]), a(f.attrs[5])).normalized();
                let lam = a(f.attrs[6]).clamp(0.0, 1.0);
                if n.dot(v) < 0.0 {
                    back_normal_pixels += 1;
                }
                // The ideal f64 reflection of the interpolated n, e: the truth uses it, and
                // the HostF64 paths (3D and 2D) address with it (module notes, steps 4–5).
                let (n, r) = reflect(n, v);
                let (u, vv) = (a(f.uv[0]), a(f.uv[1]));
                if let Some(rs) = &self.rough {
                    rough_in.push(rs.config().input_from_normalized([u, vv, 0.0], c_rough)?);
                }
                let lambda_intended = match (self.want_uv, drawn.object) {
                    (true, Some((object, lambda))) => lambda_of_uv(object, lambda, u, vv),
                    _ => lam,
                };
                shading.push((
                    f.k as usize,
                    Shading {
                        n,
                        r,
                        lambda: lam,
                        lambda_intended,
                    },
                ));
            }
        }
        Ok(HostShading {
            shading,
            rough_in,
            back_normal_pixels,
        })
    }

    /// The roughness texture: λ = code / 255 replaces the interpolated λ in `shading`;
    /// for the reflection unit as u1.L (returned).
    fn roughness_lambda(
        &self,
        rough_in: &[TextureSamplerIn],
        shading: &mut [(usize, Shading)],
        c_rough: &mut Counters,
    ) -> Option<Vec<u32>> {
        let rs = self.rough.as_ref()?;
        let codes = run_span(rs, &mut (), rough_in, c_rough);
        let max = ((1u32 << ROUGHNESS_BITS) - 1) as f64;
        for ((_, sh), c) in shading.iter_mut().zip(&codes) {
            sh.lambda = c[0] as f64 / max;
        }
        let ru = self.refl_unit.as_ref()?;
        // The texture's u0.8 code c → u1.L: round(c · 2^L / 255), a constant
        // multiply (integer, ties up).
        let l = ru.config().lambda_bits;
        let m = (1u64 << ROUGHNESS_BITS) - 1;
        Some(
            codes
                .iter()
                .map(|c| ((2 * (c[0] as u64) * (1u64 << l) + m) / (2 * m)) as u32)
                .collect(),
        )
    }

    /// The lookup chain, chunk by chunk (module notes, steps 4–6): reflection unit
    /// (→ cube_map_address on the 2D path) → sampler, on the units' batch path; the
    /// visible pixels' texels into `img` (masked). Returns the counters of the
    /// reflection unit, `cube_map_address` and the sampler.
    fn lookups(
        &self,
        map: &VoxelMap,
        shading: &[(usize, Shading)],
        rough_lambda: Option<&[u32]>,
        visible: &[Frag],
        img: &mut Image,
    ) -> Result<[Counters; 3], ConfigError> {
        let mut c_refl = Counters::default();
        let mut c_tex = Counters::default();
        let sampler = self.sampler();
        let max_code = map.max_code();
        let units = Lookups {
            refl: self.refl_unit.as_ref(),
            cube: self.two_d.as_ref().map(|_| &self.cube),
            sampler,
            shading,
            rough_lambda,
            face: self.face,
        };
        let mut texel8 = vec![[0u8; 3]; visible.len()];
        let parts: Vec<Result<[Counters; 3], ConfigError>> = texel8
            .par_chunks_mut(LOOKUP_CHUNK)
            .zip(visible.par_chunks(LOOKUP_CHUNK))
            .enumerate()
            .map_init(LookupBufs::default, |b, (i, (px, frags))| {
                units.chunk(b, i * LOOKUP_CHUNK, frags, px, max_code)
            })
            .collect();
        // Counters summed in chunk order; each unit's timing once for its whole span (the
        // frame's visible pixels), as one `run_span` adds it.
        let mut c_cube = Counters::default();
        for p in parts {
            let [r, c, t] = p?;
            c_refl += r;
            c_cube += c;
            c_tex += t;
        }
        let n_vis = visible.len() as u64;
        if let Some(ru) = &self.refl_unit {
            add_span_counters(ru.timing(), n_vis, &mut c_refl);
            if self.two_d.is_some() {
                add_span_counters(self.cube.timing(), n_vis, &mut c_cube);
            }
        }
        add_span_counters(sampler.timing(), n_vis, &mut c_tex);
        for (f, p) in visible.iter().zip(&texel8) {
            img.pixels[f.k as usize] = *p;
            img.mask[f.k as usize] = true;
        }
        Ok([c_refl, c_cube, c_tex])
    }

    /// What the render elaborated: the samplers and `cube_map_address` (the slice's
    /// report), the reflection unit, and the roughness texture with the interpolator's
    /// 2 texture-coordinate channels.
    fn elaboration(&self, map: &VoxelMap, shaded: u64) -> Result<slice::Elaboration, ConfigError> {
        let mut elaboration = slice::elaboration(
            self.two_d.as_deref().map(|(s2, sl)| (s2, sl)),
            self.sampler3,
            &self.cube,
            self.cube_used(),
            map,
            shaded,
        );
        if let Some(ru) = &self.refl_unit {
            elaboration.units.push(Elaborated {
                name: "reflection_vector".into(),
                summary: Some(UnitSummary::of(ru)),
                left_out: None,
                gates_saved: 0.0,
                cycles_saved: 0,
            });
        }
        if let Some(rs) = &self.rough {
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
        Ok(elaboration)
    }
}

/// The host f64 shading of the visible pixels ([`RenderUnits::host_shading`]).
struct HostShading {
    shading: Vec<(usize, Shading)>,
    /// The roughness texture's input words, one per visible pixel (with a texture).
    rough_in: Vec<TextureSamplerIn>,
    back_normal_pixels: usize,
}

/// The background pixels (those the object left unmasked) with their colours, listed.
fn background_list(img: &Image) -> Vec<(usize, [u8; 3])> {
    (0..img.pixels.len())
        .filter(|&k| !img.mask[k])
        .map(|k| (k, img.pixels[k]))
        .collect()
}

/// The background (module notes, step 7) into every pixel the object left unmasked:
/// rows in parallel (each pixel on its own).
fn fill_background(img: &mut Image, opt: &RenderOptions, cam: &CameraView, levels_env: &EnvMap) {
    let w = img.width;
    let bg_of = |x: u32, y: u32| match opt.background {
        Background::Black => [0; 3],
        Background::Environment => {
            let d = cam.ray_dir(x as f64 + 0.5, y as f64 + 0.5);
            levels_env.lookup(d).map(level8)
        }
    };
    img.pixels
        .par_chunks_mut(w as usize)
        .zip(img.mask.par_chunks(w as usize))
        .enumerate()
        .for_each(|(y, (row, mask))| {
            for (x, (p, &m)) in row.iter_mut().zip(mask).enumerate() {
                if !m {
                    *p = bg_of(x as u32, y as u32);
                }
            }
        });
}

/// Visible pixels per lookup task: each task runs its pixels through the chain's units
/// with its own buffers ([`LookupBufs`], reused by the tasks of one rayon worker).
const LOOKUP_CHUNK: usize = 1024;

/// The lookup chain of a render (module notes, steps 4–6) and what its HostF64 path
/// reads.
struct Lookups<'a> {
    refl: Option<&'a ReflectionVector>,
    /// The 2D path's `cube_map_address` unit (its stacked cube map is `sampler`'s);
    /// None on the 3D path.
    cube: Option<&'a CubeMapAddress>,
    sampler: &'a TextureSampler,
    /// The f64 shading of every visible pixel, in the same order (read by the HostF64
    /// path only; empty otherwise).
    shading: &'a [(usize, Shading)],
    /// λ per visible pixel from the roughness texture, u1.L (replaces the interpolated
    /// λ at the reflection unit's input).
    rough_lambda: Option<&'a [u32]>,
    /// Cube-map face side F.
    face: u32,
}

/// One task's word buffers, reused from chunk to chunk (no allocation per pixel).
#[derive(Default)]
struct LookupBufs {
    refl_in: Vec<ReflectionVectorIn>,
    refl_out: Vec<ReflectionVectorOut>,
    words: Vec<CubeMapAddressIn>,
    cube_out: Vec<CubeMapAddressOut>,
    tex_in: Vec<TextureSamplerIn>,
    tex_out: Vec<[u32; 4]>,
}

impl Lookups<'_> {
    /// The visible pixels `frags` (the first is visible pixel number `base`) through
    /// the chain into their 8-bit texels `px`. Returns the counters of the reflection
    /// unit, `cube_map_address` and the sampler, without the timing counters (the
    /// caller adds each unit's once for the whole frame).
    fn chunk(
        &self,
        b: &mut LookupBufs,
        base: usize,
        frags: &[Frag],
        px: &mut [[u8; 3]],
        max_code: u32,
    ) -> Result<[Counters; 3], ConfigError> {
        let (mut c_refl, mut c_cube, mut c_tex) = Default::default();
        b.tex_in.clear();
        match self.refl {
            Some(ru) => {
                // The interpolator's raw codes go straight in; λ s16.16 → u1.12 (counted
                // even where the roughness texture's λ replaces it).
                b.refl_in.clear();
                for (i, f) in frags.iter().enumerate() {
                    let lambda = ru.lambda_from_code(f.attrs[6], ATTR_FRAC, &mut c_refl);
                    b.refl_in.push(ReflectionVectorIn {
                        n: [f.attrs[0], f.attrs[1], f.attrs[2]],
                        e: [f.attrs[3], f.attrs[4], f.attrs[5]],
                        lambda: self.rough_lambda.map_or(lambda, |l| l[base + i]),
                    });
                }
                b.refl_out.clear();
                ru.kernel_batch(&mut (), &b.refl_in, &mut b.refl_out, &mut c_refl);
                match self.cube {
                    // The 2D path: the reflection unit's words → cube_map_address → the
                    // stacked cube map's s16.8 words.
                    Some(cube) => {
                        b.words.clear();
                        b.words.extend(
                            b.refl_out
                                .iter()
                                .map(|o| CubeMapAddressIn { coord: o.coord }),
                        );
                        b.cube_out.clear();
                        cube.kernel_batch(&mut (), &b.words, &mut b.cube_out, &mut c_cube);
                        b.tex_in.extend(b.cube_out.iter().map(|o| o.sampler_in()));
                    }
                    // The 3D path: the unit's words are the 3D sampler's s16.8 words.
                    None => b.tex_in.extend(b.refl_out.iter().map(|o| o.sampler_in())),
                }
            }
            None => {
                for (_, sh) in &self.shading[base..base + frags.len()] {
                    let stq = if self.cube.is_some() {
                        // HostF64 comparison path (2D): the f64 r's face and coordinates
                        // by the cube_map_address twin, not the unit.
                        slice::host_cube_coord(sh.r, self.face)
                    } else {
                        let t = sh.r * sh.lambda;
                        [(t.x + 1.0) * 0.5, (t.y + 1.0) * 0.5, (t.z + 1.0) * 0.5]
                    };
                    b.tex_in.push(
                        self.sampler
                            .config()
                            .input_from_normalized(stq, &mut c_tex)?,
                    );
                }
            }
        }
        b.tex_out.clear();
        self.sampler
            .kernel_batch(&mut (), &b.tex_in, &mut b.tex_out, &mut c_tex);
        // The map's codes → 8-bit framebuffer codes (rounded when the map is not 8-bit).
        let to8 = |c: u32| -> u8 {
            if max_code == 255 {
                c.min(255) as u8
            } else {
                ((c as u64 * 255 + max_code as u64 / 2) / max_code as u64).min(255) as u8
            }
        };
        for (p, o) in px.iter_mut().zip(&b.tex_out) {
            *p = [to8(o[0]), to8(o[1]), to8(o[2])];
        }
        Ok([c_refl, c_cube, c_tex])
    }
}

/// The 2D-slice elaboration's cube map and 2D sampler, when the render takes that path
/// ([`Lookup::Auto`] with `uniform` λ per vertex): kept with the map
/// ([`slice::cube_texture`]).
fn cube_map(
    map: &VoxelMap,
    opt: &RenderOptions,
    uniform: Option<f64>,
) -> Result<Option<SliceTexture>, ConfigError> {
    match (opt.lookup, uniform, opt.lambda_source) {
        (Lookup::Auto, Some(l), LambdaSource::PerVertex) => Ok(Some(slice::cube_texture(
            map,
            l,
            slice::default_face_side(map.side()),
        )?)),
        _ => Ok(None),
    }
}

/// Upload the textures a render of the thesis object with `lambda` and `opt` reads
/// (the 3D map, and on the 2D path its cube map at λ) before the first frame: they
/// are kept with `map`, so a frame timed after this does not include them (as
/// [`super::timing::predict_frame`] does not). Errors as the render's.
pub fn upload_textures(
    map: &VoxelMap,
    lambda: LambdaSpec,
    opt: &RenderOptions,
) -> Result<(), ConfigError> {
    lambda.validate()?;
    slice::sampler_3d(map)?;
    cube_map(map, opt, lambda.uniform())?;
    Ok(())
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

/// r = 2(n̂·v)n̂ − v for unit v (host f64: the documented gap). A zero normal (never
/// from the tessellations) is replaced by v. Returns (n̂, r), r unit.
fn reflect(n: Vec3, v: Vec3) -> (Vec3, Vec3) {
    let n = if n.length() > 0.0 { n } else { v };
    let v = if v.length() > 0.0 { v } else { n };
    let r = (n * (2.0 * n.dot(v)) - v).normalized();
    let r = if r.length() > 0.0 { r } else { n };
    (n, r)
}
