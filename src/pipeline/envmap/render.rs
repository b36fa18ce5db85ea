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
//!    and the window depth z ∈ [0, 1] (1).
//! 2. **polygon_interpolator (unit).** Each triangle is set up and walked by the unit
//!    (`pipeline::raster::draw_triangle`, the shafts pipeline's path): attributes are
//!    quantised into s16.16, interpolated by the unit's fixed-point walker and come out
//!    as s16.16 codes. The interpolation is **affine in screen space** (the unit has no
//!    perspective correction; GeForce3 had it): on these small triangles the difference
//!    is sub-pixel, but it is a difference. λ is per vertex and interpolated, as on the
//!    thesis' GeForce3: where λ changes fast across a triangle (the sphere's 6 o'clock
//!    seam of the non-uniform λ, where it jumps from ≈ 1 back to 0) the reflection is
//!    distorted — the thesis' Fig. 17(b) artefact. A per-pixel λ from a roughness
//!    texture (the thesis' own future work, issue 5's option) would remove it: not done.
//!    Triangles seen from their back get their normals flipped (two-sided lighting; the
//!    teapot is an open sheet whose inside shows at the rim and the spout).
//! 3. **Depth test (integer).** The nearest fragment per pixel wins by comparing the
//!    interpolated window-depth codes (an integer compare standing for the depth buffer;
//!    the shafts pipeline's `shadow_compare` z-buffer is not instantiated here). Shading
//!    is then done once per visible pixel (deferred), which gives the same image as
//!    shading every fragment before the test; only the sampler's counters differ.
//! 4. **Reflection and t = r·λ — f64, a DOCUMENTED GAP.** There is no reflection unit in
//!    the model. At each pixel, from the interpolator's output codes (converted to f64
//!    exactly), the host normalises n and e, forms v = ê, r = 2(n̂·v)n̂ − v, t = r·λ and
//!    the normalised 3D texture coordinate (t + 1)/2. This stands for the GeForce3
//!    texture shader (DOT_PRODUCT_REFLECT-style per-pixel reflection, or the thesis'
//!    per-vertex reflection-map texgen plus a λ texture matrix). Everything else per
//!    pixel is the units'.
//! 5. **Coordinate hand-over (fixed point).** (t + 1)/2 · s is rounded to the sampler's
//!    s16.8 texel-space words by `TextureSamplerConfig::input_from_normalized` (the
//!    rasteriser's hand-over; saturating, counted).
//! 6. **texture_sampler (unit).** [`TextureSamplerConfig::geforce_3d`] (s × s × s, 3
//!    channels, the map's unorm texels — 8-bit by default — trilinear over 8 texels,
//!    8-bit weights, clamp to edge) samples the [`VoxelMap`]; its output codes are the
//!    framebuffer's (8-bit: a map with other widths is rescaled to 8 bits by rounding).
//! 7. **Background (host, f64, not the object).** Either black or the environment seen
//!    in the pixel's view direction: a bilinear lookup of the environment at the same
//!    exposure, rounded to 8-bit levels (standing for a sky-box / cube-map pass; not
//!    part of the error statistics).
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
use rtl_model::units::polygon_interpolator::PolygonInterpolatorConfig;
use rtl_model::units::texture_sampler::{TextureSampler, TextureSamplerIn};
use rtl_model::Counters;

use super::slice;
use super::voxmap::VoxelMap;
use crate::pipeline::raster::{draw_triangle, Fragment, HostVertex};
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

/// Options of [`render_object_with`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderOptions {
    /// Exposure of the environment's levels; None: [`EnvMap::auto_exposure`].
    pub exposure: Option<f64>,
    pub background: Background,
    pub lookup: Lookup,
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
        let mut s = ErrorStats::default();
        let mut sum = [0.0; 3];
        let mut sum2 = [0.0; 3];
        let mut sums = [0.0; 3];
        for k in 0..img.pixels.len().min(truth.pixels.len()) {
            if !img.mask[k] {
                continue;
            }
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
            let pos = [
                -0.5 * (TEAPOT_X.0 + TEAPOT_X.1) * TEAPOT_SCALE,
                -0.5 * TEAPOT_HEIGHT * TEAPOT_SCALE,
                0.0,
            ];
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
    lambda: f64,
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
    let truth = truth_images(&r)?;
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
        }
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
    let interp = PolygonInterpolatorConfig {
        attrs: 8,
        out_int_bits: 16,
        out_frac_bits: ATTR_FRAC,
        ..PolygonInterpolatorConfig::default()
    }
    .build()?;
    let s = map.side();
    let sampler3 = slice::sampler_3d(map)?;
    // The 2D-slice elaboration: uniform λ reads the map only on |t| = λ.
    let two_d = match (opt.lookup, lambda) {
        (Lookup::Auto, LambdaSpec::Uniform(l)) => {
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
    let mut frag_at: Vec<Option<Fragment>> = vec![None; n_px];
    let mut triangles = 0;
    let mut fragments = 0u64;
    for (tri, lam) in &geo {
        let mut hv = [HostVertex {
            x: 0.0,
            y: 0.0,
            attrs: [0.0; 8],
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
            hv[k] = HostVertex {
                x: sx,
                y: sy,
                attrs: [n.x, n.y, n.z, e.x, e.y, e.z, lam[k], sz],
            };
        }
        if !ok {
            continue;
        }
        triangles += 1;
        for f in draw_triangle(&interp, &hv, w, h, &mut c_int)? {
            fragments += 1;
            let k = (f.y * w + f.x) as usize;
            // Integer depth compare on the s16.16 window-depth code (less wins).
            if f.attrs[7] < zbuf[k] {
                zbuf[k] = f.attrs[7];
                frag_at[k] = Some(f);
            }
        }
    }

    // ---- per visible pixel: reflection (f64 gap), coordinate hand-over, sampler.
    let mut img = Image::new(w, h);
    let mut c_tex = Counters::default();
    let mut inputs: Vec<TextureSamplerIn> = Vec::new();
    let mut shading: Vec<(usize, Shading)> = Vec::new();
    let mut back_normal_pixels = 0;
    let a = |raw: i64| interp.out_to_f64(raw);
    for (k, f) in frag_at.iter().enumerate() {
        let Some(f) = f else { continue };
        let n = v3(a(f.attrs[0]), a(f.attrs[1]), a(f.attrs[2])).normalized();
        let v = v3(a(f.attrs[3]), a(f.attrs[4]), a(f.attrs[5])).normalized();
        let lam = a(f.attrs[6]).clamp(0.0, 1.0);
        if n.dot(v) < 0.0 {
            back_normal_pixels += 1;
        }
        // GAP: the reflection and t = r·λ are host f64 (module notes, step 4).
        let (n, r) = reflect(n, v);
        let stq = if two_d.is_some() {
            // 2D slice: the lookup is on |t| = λ, addressed by r's direction.
            slice::slice_coord(r)
        } else {
            let t = r * lam;
            [(t.x + 1.0) * 0.5, (t.y + 1.0) * 0.5, (t.z + 1.0) * 0.5]
        };
        inputs.push(sampler.config().input_from_normalized(stq, &mut c_tex)?);
        shading.push((k, Shading { n, r, lambda: lam }));
    }
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
    let frame = FrameInfo {
        width: w,
        height: h,
        triangles,
        fragments,
        shaded,
        background_pixels: background.len() as u64,
        texels_per_lookup: sampler.config().texels_per_sample(),
        elaboration: slice::elaboration(
            two_d.as_ref().map(|(s2, sl)| (s2, sl)),
            &sampler3,
            map,
            shaded,
        ),
    };
    let mut counters = BTreeMap::new();
    counters.insert("polygon_interpolator".to_string(), c_int);
    counters.insert("texture_sampler (envmap)".to_string(), c_tex);
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

/// A level in f64 rounded to an 8-bit level (clamped).
fn level8(x: f64) -> u8 {
    x.clamp(0.0, 255.0).round() as u8
}

/// The two truths at the rendered pixels (parallel over pixels, deterministic), with
/// the render's background.
fn truth_images(r: &Rendered) -> Result<Truth, ConfigError> {
    use rayon::prelude::*;
    let (w, h) = (r.img.width, r.img.height);
    let truth = PhongTruth::new(&r.levels_env);
    let s = r.side as f64;
    let px: Vec<([u8; 3], [u8; 3])> = r
        .shading
        .par_iter()
        .map(|(_, sh)| {
            let big_lambda = g(sh.lambda * sh.r.length(), s, THESIS_LEVELS);
            let tc = truth.eval(sh.r, sh.n, big_lambda, Visibility::CosPhiTest)?;
            let ts = truth.eval(sh.r, sh.n, big_lambda, Visibility::Simplified)?;
            Ok((tc.map(level8), ts.map(level8)))
        })
        .collect::<Result<_, ConfigError>>()?;
    let mut truth_c = Image::new(w, h);
    let mut truth_s = Image::new(w, h);
    for ((k, _), (c, s)) in r.shading.iter().zip(px) {
        truth_c.pixels[*k] = c;
        truth_s.pixels[*k] = s;
        truth_c.mask[*k] = true;
        truth_s.mask[*k] = true;
    }
    for &(k, bg) in &r.background {
        truth_c.pixels[k] = bg;
        truth_s.pixels[k] = bg;
    }
    Ok(Truth {
        cos_phi: truth_c,
        simplified: truth_s,
        side: r.side,
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
