//! The scene format (TOML via serde). Types only here; validation is in
//! `validate.rs`, built-in scenes in `builtin.rs`.
//!
//! Conventions: right-handed world, y up, lengths in world units; colours are linear
//! RGB in [0, 1]; angles in degrees. Every field has a serde default where a sensible
//! one exists, so a scene file states only what it changes.

use rtl_model::chip_preset::ChipPreset;
use serde::{Deserialize, Serialize};

/// A whole scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Free text, shown in reports.
    #[serde(default)]
    pub name: String,
    /// Seed of every random choice made for this scene.
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// Which chip's behaviour the units follow where the GeForce2 and the NV2A differ
    /// (`rtl_model::chip_preset`); left out = the GeForce2, the project's defaults.
    #[serde(default, skip_serializing_if = "ChipPreset::is_default")]
    pub chip: ChipPreset,
    #[serde(default)]
    pub image: ImageSize,
    /// Required in a scene of lights and objects; a shading sphere or the test scene
    /// has none (left out, it reads as [`Camera::unset`]).
    #[serde(default = "Camera::unset", skip_serializing_if = "Camera::is_unset")]
    pub camera: Camera,
    #[serde(default)]
    pub medium: Medium,
    #[serde(default)]
    pub lights: Vec<Light>,
    #[serde(default)]
    pub objects: Vec<Object>,
    #[serde(default)]
    pub shafts: ShaftsConfig,
    /// Glare sources and the glare renderer's settings (Matsuda and Ikedo); none = no glare.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub glare: Option<super::glare::GlareSection>,
    /// An environment map and the thesis object drawn with it (Okumura's thesis); none = no
    /// environment.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub environment: Option<super::environment::EnvironmentSection>,
    /// Where GL leaves rounding to the implementation, the units' choice (chain,
    /// filter, weight); none = the GeForce-style defaults (docs/shading.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rounding: Option<super::rounding::GlRounding>,
    /// The widths of the shading units the object pass runs; none = the GeForce
    /// defaults (`scene::shading_hw`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shading_hw: Option<super::shading_hw::ShadingHw>,
    /// The shading units' sphere (`shading-*`): a scene that holds it is that sphere
    /// and nothing else (`scene::shading_sphere`); none = a scene of lights and objects.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shading_sphere: Option<super::shading_sphere::ShadingSphereSection>,
    /// The foundation test scene (`test`), a fixed scene: the section is empty, its
    /// presence makes the scene that one (`scene::test_scene`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub test_scene: Option<super::test_scene::TestSceneSection>,
}

fn default_seed() -> u64 {
    1
}

pub use super::camera::{Camera, ImageSize};

/// The participating medium, homogeneous: density ρ, extinction κ, phase constant K
/// (F(α) = K·(1 + 9·cos¹⁶(α/2)), Dobashi et al. eq. (4)).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Medium {
    /// ρ ≥ 0.
    pub rho: f64,
    /// κ ≥ 0.
    pub kappa: f64,
    /// K ≥ 0.
    pub k: f64,
}

impl Default for Medium {
    fn default() -> Self {
        Medium {
            rho: 0.05,
            kappa: 1.0,
            k: 1.0,
        }
    }
}

/// A light source.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Light {
    #[serde(default)]
    pub kind: LightKind,
    pub position: [f64; 3],
    /// Spot axis (need not be unit length; must not be zero for a spot).
    #[serde(default = "default_direction")]
    pub direction: [f64; 3],
    /// Spot cone half-angle, degrees, in (0, 90). Ignored for a point light.
    #[serde(default = "default_cutoff")]
    pub cutoff_deg: f64,
    /// Radiant intensity on the axis (≥ 0), times `color`.
    #[serde(default = "default_intensity")]
    pub intensity: f64,
    #[serde(default = "default_white")]
    pub color: [f64; 3],
    /// The spot's distribution across the cone (I_l); `None` = uniform over the cone
    /// (no projective light-map unit is elaborated for it).
    #[serde(default)]
    pub light_map: Option<LightMap>,
}

fn default_direction() -> [f64; 3] {
    [0.0, -1.0, 0.0]
}
fn default_cutoff() -> f64 {
    20.0
}
fn default_intensity() -> f64 {
    1.0
}
fn default_white() -> [f64; 3] {
    [1.0, 1.0, 1.0]
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LightKind {
    #[default]
    Spot,
    Point,
}

/// A light map: the image projected from the light over its cone, value in [0, 1].
/// Map coordinates (u, v) ∈ [0, 1]² span the cone's square; (½, ½) is the axis.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum LightMap {
    /// A smooth spot: 1 on the axis falling to 0 at the cone's edge as
    /// (1 − r²)^`exponent`, r = distance from the axis in units of the cone radius.
    Smooth {
        #[serde(default = "default_exponent")]
        exponent: f64,
    },
    /// Polka dots: a smooth spot multiplied by a `dots` × `dots` grid of discs of
    /// relative radius `radius` (0 < radius ≤ 0.5 of a cell).
    PolkaDots {
        #[serde(default = "default_dots")]
        dots: u32,
        #[serde(default = "default_dot_radius")]
        radius: f64,
    },
    /// An image file (PNG or other formats the `image` crate reads), luminance used.
    Image { path: String },
}

fn default_exponent() -> f64 {
    1.0
}
fn default_dots() -> u32 {
    5
}
fn default_dot_radius() -> f64 {
    0.3
}

/// An object: lit surface (I_o) and, when `occluder`, a shadow caster in the medium.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Object {
    pub shape: Shape,
    /// Diffuse albedo, linear RGB in [0, 1].
    #[serde(default = "default_albedo")]
    pub color: [f64; 3],
    /// Casts shadows (into the shadow map and for the reference's shadow rays).
    #[serde(default = "default_true")]
    pub occluder: bool,
    /// The surface's reflection model; none = Lambert with `color` (every scene
    /// written before materials existed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<super::material::Material>,
}

fn default_albedo() -> [f64; 3] {
    [0.7, 0.7, 0.7]
}
fn default_true() -> bool {
    true
}

/// Geometry.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum Shape {
    Sphere {
        center: [f64; 3],
        radius: f64,
    },
    /// A rectangle: centre, unit-free normal, and half extents along two in-plane axes
    /// (the first is `tangent`, the second normal × tangent).
    Plane {
        center: [f64; 3],
        normal: [f64; 3],
        #[serde(default = "default_tangent")]
        tangent: [f64; 3],
        half_size: [f64; 2],
    },
    /// An axis-aligned box.
    Box {
        min: [f64; 3],
        max: [f64; 3],
    },
    /// The Utah teapot (Newell's 32 Bézier patches, Z up in the data, turned Y up),
    /// scaled, rotated about y (degrees) and moved; `subdivisions` per patch side.
    Teapot {
        position: [f64; 3],
        #[serde(default = "default_one")]
        scale: f64,
        #[serde(default)]
        rotate_y_deg: f64,
        #[serde(default = "default_subdivisions")]
        subdivisions: u32,
    },
}

fn default_tangent() -> [f64; 3] {
    [1.0, 0.0, 0.0]
}
fn default_one() -> f64 {
    1.0
}
fn default_subdivisions() -> u32 {
    8
}

/// How the shafts are drawn in hardware (Dobashi et al.).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ShaftsConfig {
    /// n sample planes, 1 ..= 10 000.
    pub planes: u32,
    /// m sub-sample planes per interval, 1 ..= 256 (1 = no sub-plane path).
    pub subplanes: u32,
    /// Mesh cells per sample plane [columns, rows] (the paper: 15 × 10).
    pub mesh: [u32; 2],
    /// F(α) texture width (1D, α from 0° to 180°).
    pub f_texels: u32,
    /// h(s, t) texture size [s, t].
    pub h_texels: [u32; 2],
    /// Table ranges s ∈ [0, s_max], t ∈ [0, t_max]; 0 = fit to the scene.
    pub s_max: f64,
    pub t_max: f64,
    /// Texel, framebuffer and filter-weight widths (GeForce2: 8).
    pub texel_bits: u32,
    pub fb_bits: u32,
    pub weight_bits: u32,
    /// Sub-texel fraction bits of the interpolated texture coordinates.
    pub coord_frac_bits: u32,
    /// Shadow map resolution (square) and depth bits.
    pub shadow_resolution: u32,
    pub shadow_depth_bits: u32,
    /// What full scale of the F(α) texture stands for (see [`FScale`]).
    pub f_scale: FScale,
    /// Whether h's full scale is capped so one plane cannot exceed full scale (see
    /// [`HCap`], docs/assumptions.md).
    pub h_cap: HCap,
    /// The ray length Δt each sample plane stands for in eq. (5) (see [`PlaneStep`],
    /// docs/assumptions.md).
    #[serde(skip_serializing_if = "PlaneStep::is_default")]
    pub plane_step: PlaneStep,
    /// Side of each spot's light-map texture (a power of two, 2 ..= 4096): the beam's
    /// rim is as sharp as one texel of it.
    pub light_map_texels: u32,
    /// The polygon interpolator's attribute accumulators, s(int).(frac): integer bits
    /// including the sign (GeForce default 20) and fraction bits (24). The
    /// interpolator is most of a shafts chip's gates (8 attributes × 44-bit
    /// accumulators); `optimize` searches these (docs/optimize.md).
    #[serde(skip_serializing_if = "is_default_acc_int")]
    pub acc_int_bits: u32,
    #[serde(skip_serializing_if = "is_default_acc_frac")]
    pub acc_frac_bits: u32,
    /// The projective-texcoord unit's reciprocal: ROM index bits (default 8, 2^8
    /// entries), ROM entry bits (16) and the Newton step's fraction bits (20). The
    /// depth projection shares the ROM (index and entry bits); its own Newton steps
    /// stay at 30 fraction bits.
    #[serde(skip_serializing_if = "is_default_recip_index")]
    pub recip_index_bits: u32,
    #[serde(skip_serializing_if = "is_default_recip_entry")]
    pub recip_entry_bits: u32,
    #[serde(skip_serializing_if = "is_default_newton_frac")]
    pub newton_frac_bits: u32,
}

/// GeForce-era defaults of the unit widths in `[shafts]` (those of
/// `PolygonInterpolatorConfig::default` and `ProjectiveTexcoordConfig::geforce`); a
/// scene that leaves them at these writes none of them, so scene files and dumps made
/// before the fields existed read and print the same.
pub const DEFAULT_ACC_INT_BITS: u32 = 20;
pub const DEFAULT_ACC_FRAC_BITS: u32 = 24;
pub const DEFAULT_RECIP_INDEX_BITS: u32 = 8;
pub const DEFAULT_RECIP_ENTRY_BITS: u32 = 16;
pub const DEFAULT_NEWTON_FRAC_BITS: u32 = 20;

fn is_default_acc_int(v: &u32) -> bool {
    *v == DEFAULT_ACC_INT_BITS
}
fn is_default_acc_frac(v: &u32) -> bool {
    *v == DEFAULT_ACC_FRAC_BITS
}
fn is_default_recip_index(v: &u32) -> bool {
    *v == DEFAULT_RECIP_INDEX_BITS
}
fn is_default_recip_entry(v: &u32) -> bool {
    *v == DEFAULT_RECIP_ENTRY_BITS
}
fn is_default_newton_frac(v: &u32) -> bool {
    *v == DEFAULT_NEWTON_FRAC_BITS
}

/// Full scale of the 8-bit F(α) table.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FScale {
    /// The table's own maximum over α ∈ [0°, 180°], F(0) = 10K — the paper's table,
    /// built without knowing the scene. Seen from the side (α ≈ 90°) F is about a
    /// tenth of full scale: 26 codes.
    #[default]
    Table,
    /// F(α_min), the largest F the scene's lit volume meets (found by the host): the
    /// codes the planes use span the whole 8 bits; F beyond it clamps.
    LitVolume,
}

/// The cap on h_ref, the h value the h texture's full scale stands for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HCap {
    /// h_ref = min(h(s_near, 0), h at which one plane at F's full scale, the brightest
    /// light and the corner ray adds 255 levels): the plane's scale, a vertex colour,
    /// never exceeds 1; h nearer the light clamps in the texture (the model's choice).
    #[default]
    OnePlane,
    /// h_ref = h(s_near, 0), uncapped: h never clamps in the texture, and the plane's
    /// vertex colour saturates instead where it would exceed 1.
    None,
}

/// Δt of eq. (5): the length of a pixel's ray between two sample planes, which the
/// plane's scale (a vertex colour) carries.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PlaneStep {
    /// Δt = Δr·t/r per mesh vertex: the planes are Δr apart in view depth, so an
    /// off-axis ray crosses Δr/cos between them (the model's choice; interpolated).
    #[default]
    AlongRay,
    /// Δt = Δr for every pixel: the planes' spacing, one scale per plane (the paper's
    /// eq. (5) read literally; off-axis rays are under-weighted by cos). The tables and
    /// h's cap are those of `along_ray`, so only Δt changes.
    PlaneSpacing,
}

impl PlaneStep {
    fn is_default(&self) -> bool {
        *self == PlaneStep::default()
    }
}

impl Default for ShaftsConfig {
    fn default() -> Self {
        ShaftsConfig {
            planes: 30,
            subplanes: 6,
            mesh: [15, 10],
            f_texels: 256,
            h_texels: [256, 256],
            s_max: 0.0,
            t_max: 0.0,
            texel_bits: 8,
            fb_bits: 8,
            weight_bits: 8,
            coord_frac_bits: 8,
            shadow_resolution: 512,
            // The paper's GeForce2 has no depth textures: its shadow map is an 8-bit
            // image of light distances ("each map's pixels are stored as 8 bits").
            shadow_depth_bits: 8,
            f_scale: FScale::Table,
            h_cap: HCap::OnePlane,
            plane_step: PlaneStep::AlongRay,
            light_map_texels: 256,
            acc_int_bits: DEFAULT_ACC_INT_BITS,
            acc_frac_bits: DEFAULT_ACC_FRAC_BITS,
            recip_index_bits: DEFAULT_RECIP_INDEX_BITS,
            recip_entry_bits: DEFAULT_RECIP_ENTRY_BITS,
            newton_frac_bits: DEFAULT_NEWTON_FRAC_BITS,
        }
    }
}

/// What a scene is, which decides the command's path: the foundation test scene, a
/// shading units' sphere, or a scene of lights and objects (the frame's passes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SceneKind<'a> {
    Test,
    ShadingSphere(&'a super::shading_sphere::ShadingSphereSection),
    Frame,
}

impl Scene {
    /// A scene of nothing: every field at the value a file that leaves it out gets.
    /// The test scene and the shading spheres are this with their section set.
    pub fn blank() -> Scene {
        Scene {
            name: String::new(),
            seed: default_seed(),
            chip: ChipPreset::default(),
            image: ImageSize::default(),
            camera: Camera::unset(),
            medium: Medium::default(),
            lights: Vec::new(),
            objects: Vec::new(),
            shafts: ShaftsConfig::default(),
            glare: None,
            environment: None,
            rounding: None,
            shading_hw: None,
            shading_sphere: None,
            test_scene: None,
        }
    }

    /// The foundation test scene (`render --scene test`).
    pub fn test_scene() -> Scene {
        Scene {
            test_scene: Some(super::test_scene::TestSceneSection {}),
            ..Scene::blank()
        }
    }

    /// The shading units' sphere of `section`.
    pub fn shading_sphere(section: super::shading_sphere::ShadingSphereSection) -> Scene {
        Scene {
            shading_sphere: Some(section),
            ..Scene::blank()
        }
    }

    /// Which kind of scene this is (its sections say, not its name).
    pub fn kind(&self) -> SceneKind<'_> {
        match (&self.test_scene, &self.shading_sphere) {
            (Some(_), _) => SceneKind::Test,
            (None, Some(s)) => SceneKind::ShadingSphere(s),
            (None, None) => SceneKind::Frame,
        }
    }

    /// The name up to its first ':' (the built-ins' names are "fig6: a description"):
    /// what plot titles show.
    pub fn short_name(&self) -> &str {
        self.name.split(':').next().unwrap_or("")
    }

    /// Whether `objects[i]` is drawn by the frame's object pass (shading units,
    /// environment reflections) rather than as a Lambert object by the shafts passes:
    /// it has a material or reflects the environment.
    pub fn shaded_object(&self, i: usize) -> bool {
        self.objects.get(i).is_some_and(|o| o.material.is_some())
            || self
                .environment
                .as_ref()
                .is_some_and(|e| e.reflectors.iter().any(|r| r.object == i))
    }
}
