//! The scene format's fields, one table: every section and field of a scene file by
//! its TOML path (`lights[].position`, `shafts.planes`), with its type, unit, allowed
//! range, default, where the range comes from, and what it means.
//!
//! This table is the one source of truth for the format's reference:
//! - docs/scenes.md is generated from it
//!   ([`reference_markdown`](super::fields_reference::reference_markdown),
//!   `glare-pipeline scene --reference docs/scenes.md`); a test fails when the
//!   committed file differs;
//! - validation (`validate.rs`, `glare.rs`, `environment.rs`, `material.rs`) takes the
//!   ranges it checks from the entries here ([`Field::real`], [`Field::int`]), so the
//!   documented range and the checked one cannot drift;
//! - `scene NAME` writes its comments from it ([`section_comment`], [`unit_comment`]);
//! - tests/scene.rs serialises every built-in and a maximal scene per variant, collects
//!   every key path and asserts the set equals this table's, and deserialises a scene
//!   with each entry set (each choice of a choice field) to prove every entry is a
//!   real key of the serde format.
//!
//! Ranges that a unit's own constructor decides (bit widths, table sizes) are not
//! copied here: their entry says [`Range::Unit`] and names the unit whose limit
//! applies; validation builds that unit (`limits.rs`).

use rtl_model::error::{check_finite, check_range, ConfigError};

use super::bounds::{self as V, interval};
use super::math::{v3, Vec3};

/// A field's TOML type.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Ty {
    /// A table (`[camera]`, or an inline table).
    Table,
    /// A table with a tag key choosing its variant (`type` or `model`).
    Tagged,
    /// An array of tables (`[[lights]]`).
    Tables,
    Real,
    Int,
    Bool,
    Str,
    /// A fixed-length array of reals (`[x, y, z]`).
    Reals(usize),
    /// A fixed-length array of integers.
    Ints(usize),
    /// An array of `[x, y, z]` points.
    Points,
    /// One of the listed strings.
    Choice(&'static [&'static str]),
    /// A real, or one of the listed strings.
    RealOr(&'static [&'static str]),
}

impl Ty {
    /// As the reference shows it.
    pub fn text(&self) -> String {
        let q = |v: &[&str]| {
            v.iter()
                .map(|s| format!("`\"{s}\"`"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        match self {
            Ty::Table => "table".into(),
            Ty::Tagged => "table (tagged)".into(),
            Ty::Tables => "array of tables".into(),
            Ty::Real => "real".into(),
            Ty::Int => "integer".into(),
            Ty::Bool => "boolean".into(),
            Ty::Str => "string".into(),
            Ty::Reals(n) => format!("[real; {n}]"),
            Ty::Ints(n) => format!("[integer; {n}]"),
            Ty::Points => "array of [real; 3]".into(),
            Ty::Choice(v) => format!("one of {}", q(v)),
            Ty::RealOr(v) => format!("real or {}", q(v)),
        }
    }

    /// Whether the field is a table (a section) rather than a value.
    pub fn is_section(&self) -> bool {
        matches!(self, Ty::Table | Ty::Tagged | Ty::Tables)
    }
}

/// The values a field accepts (each element of an array field).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Range {
    /// No numeric range (a section, a string, a boolean, a choice).
    None,
    /// Any finite real.
    Finite,
    /// A finite real in an interval, each end open or closed.
    Real {
        lo: f64,
        lo_closed: bool,
        hi: f64,
        hi_closed: bool,
    },
    /// An integer in `lo ..= hi`.
    Int { lo: u64, hi: u64 },
    /// A power of two in `lo ..= hi`.
    Pow2 { lo: u64, hi: u64 },
    /// Decided by a unit's own constructor (the limit column names it), or a rule
    /// relating fields, in words.
    Unit(&'static str),
}

/// lo ≤ x ≤ hi.
pub const fn closed_range(lo: f64, hi: f64) -> Range {
    Range::Real {
        lo,
        lo_closed: true,
        hi,
        hi_closed: true,
    }
}
/// lo < x ≤ hi.
pub const fn open_closed(lo: f64, hi: f64) -> Range {
    Range::Real {
        lo,
        lo_closed: false,
        hi,
        hi_closed: true,
    }
}
/// lo < x < hi.
pub const fn open_range(lo: f64, hi: f64) -> Range {
    Range::Real {
        lo,
        lo_closed: false,
        hi,
        hi_closed: false,
    }
}
/// lo ≤ x < hi.
pub const fn closed_open(lo: f64, hi: f64) -> Range {
    Range::Real {
        lo,
        lo_closed: true,
        hi,
        hi_closed: false,
    }
}
/// lo ..= hi, integers.
pub const fn ints(lo: u64, hi: u64) -> Range {
    Range::Int { lo, hi }
}

/// Format a bound: integers plainly, large numbers as 1e6.
fn num(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e5 {
        format!("{x:.0}")
    } else if x.abs() >= 1e5 {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

impl Range {
    /// Check a real against this range (see [`Field::real`]).
    pub fn real(&self, name: &str, x: f64) -> Result<(), ConfigError> {
        match *self {
            Range::Real {
                lo,
                lo_closed,
                hi,
                hi_closed,
            } => interval(name, x, lo, lo_closed, hi, hi_closed),
            _ => check_finite(name, x).map(|_| ()),
        }
    }

    /// As the reference shows it.
    pub fn text(&self) -> String {
        match self {
            Range::None => String::new(),
            Range::Finite => "finite".into(),
            Range::Real {
                lo,
                lo_closed,
                hi,
                hi_closed,
            } => format!(
                "{} {} x {} {}",
                num(*lo),
                if *lo_closed { "≤" } else { "<" },
                if *hi_closed { "≤" } else { "<" },
                num(*hi)
            ),
            Range::Int { lo, hi } => format!("{lo} ..= {hi}"),
            Range::Pow2 { lo, hi } => format!("power of two, {lo} ..= {hi}"),
            Range::Unit(s) => s.to_string(),
        }
    }
}

/// One field (or section) of the scene format.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Field {
    /// TOML path: `camera.eye`, `lights[].light_map.exponent`.
    pub path: &'static str,
    pub ty: Ty,
    /// Unit of the value ("" for none).
    pub unit: &'static str,
    /// The allowed values (each element of an array).
    pub range: Range,
    /// The default as TOML text; "required" when it must be given, "none" when
    /// leaving it out means the feature is off.
    pub default: &'static str,
    /// Where the range comes from.
    pub limit: &'static str,
    /// The variant the field belongs to (`type = "sphere"`), "" for every variant.
    pub when: &'static str,
    /// What it is.
    pub doc: &'static str,
}

impl Field {
    /// Check a real against this field's range; the error names `name` (the path as
    /// the caller writes it, with indices). A field whose range is not a real
    /// interval only needs to be finite.
    pub fn real(&self, name: &str, x: f64) -> Result<(), ConfigError> {
        self.range.real(name, x)
    }

    /// [`Field::real`] for every element of an array.
    pub fn reals(&self, name: &str, xs: &[f64]) -> Result<(), ConfigError> {
        for (k, &x) in xs.iter().enumerate() {
            self.real(&format!("{name}[{k}]"), x)?;
        }
        Ok(())
    }

    /// Check an integer against this field's range; the error names `name`.
    pub fn int(&self, name: &str, x: u64) -> Result<(), ConfigError> {
        match self.range {
            Range::Int { lo, hi } => check_range(name, x, lo, hi),
            Range::Pow2 { lo, hi } => {
                check_range(name, x, lo, hi)?;
                if x.is_power_of_two() {
                    Ok(())
                } else {
                    Err(ConfigError::invalid(
                        name,
                        &format!("{x} is not a power of two"),
                    ))
                }
            }
            _ => Ok(()),
        }
    }

    /// Within a closed interval (for callers that need the bounds).
    pub fn bounds(&self) -> Option<(f64, f64)> {
        match self.range {
            Range::Real { lo, hi, .. } => Some((lo, hi)),
            Range::Int { lo, hi } | Range::Pow2 { lo, hi } => Some((lo as f64, hi as f64)),
            _ => None,
        }
    }
}

// ---------------------------------------------------------------------------------
// Limit sources, named once.

const WORLD: &str =
    "WORLD_MAX = 10⁶ world units: keeps s², far·near and |P − eye|² finite and precise in f64";
const DIRECTION: &str =
    "WORLD_MAX per component; length ≥ MIN_LENGTH = 10⁻⁹ (a shorter vector cannot be normalised)";
const COLOUR: &str = "linear RGB: 1 is full scale";
const CODES: &str = "GLARE_INTENSITY_MAX = 10⁹ framebuffer codes (10⁶ is a documented stiff case)";
const MODEL: &str = "the form's stated domain (docs/glare.md)";
const EXPONENT: &str =
    "R1 is monotone only with exponents ≥ 0 (Table 1's signs); 8 bounds the stiffness";
const SAMPLER: &str = "texture_sampler: MAX_SIZE = 4096 texels per axis; 2 (a lerp needs two ends)";
const NONE: &str = "";
const BRDF: &str = "the reflection model's own domain (src/reference/brdf)";

const IMAGE_MAX_U: u64 = V::IMAGE_MAX as u64;
const TEX_MAX: u64 = rtl_model::units::texture_sampler::MAX_SIZE as u64;
const ENV_MIN_SIDE: u64 = V::ENV_MIN_SIDE as u64;
const ENV_MAX_SIDE: u64 = V::ENV_MAX_SIDE as u64;
const WMAX: f64 = V::WORLD_MAX;
/// A position or direction component: within ±WORLD_MAX.
pub const POS: Range = closed_range(-WMAX, WMAX);

/// A position: each component finite and within ±`WORLD_MAX` (errors name
/// `field[k]`).
pub(crate) fn point(field: &str, p: &[f64; 3]) -> Result<Vec3, ConfigError> {
    for (k, &x) in p.iter().enumerate() {
        POS.real(&format!("{field}[{k}]"), x)?;
    }
    Ok(v3(p[0], p[1], p[2]))
}

/// A direction: a valid point with length ≥ `MIN_LENGTH` (a zero vector names
/// `field`).
pub(crate) fn direction(field: &str, d: &[f64; 3]) -> Result<Vec3, ConfigError> {
    use super::bounds::MIN_LENGTH;
    let v = point(field, d)?;
    if v.length() < MIN_LENGTH {
        return Err(ConfigError::invalid(
            field,
            &format!(
                "is (almost) the zero vector (length < {MIN_LENGTH:e}); a direction is needed"
            ),
        ));
    }
    Ok(v)
}

macro_rules! fields {
    ($( $name:ident = $path:literal, $ty:expr, $unit:literal, $range:expr, $default:literal,
        $limit:expr, $when:literal, $doc:literal; )*) => {
        $(
            #[doc = $doc]
            pub const $name: Field = Field {
                path: $path,
                ty: $ty,
                unit: $unit,
                range: $range,
                default: $default,
                limit: $limit,
                when: $when,
                doc: $doc,
            };
        )*
        /// Every section and field of the scene format, in the order of the reference.
        pub const FIELDS: &[Field] = &[$($name),*];
    };
}

const LIGHT_KINDS: &[&str] = &["spot", "point"];
const LIGHT_MAPS: &[&str] = &["smooth", "polka_dots", "image"];
const SHAPES: &[&str] = &["sphere", "plane", "box", "teapot"];
const MODELS: &[&str] = &[
    "lambert",
    "phong",
    "blinn_phong",
    "cook_torrance",
    "ward",
    "oren_nayar",
    "kajiya_kay",
];
const BACKGROUNDS: &[&str] = &["black", "shafts", "sky", "canopy"];
const SOURCE_KINDS: &[&str] = &["point", "circle", "cylindrical", "elliptic", "polygon"];

fields! {
    // ---- top level
    NAME = "name", Ty::Str, "", Range::None, "\"\"", NONE, "",
        "Free text shown in reports; the built-ins write \"short name: description\".";
    SEED = "seed", Ty::Int, "", Range::None, "1", NONE, "",
        "Seed of every random choice made for the scene (noise, leaves, patches).";
    CHIP = "chip", Ty::Choice(&rtl_model::chip_preset::ChipPreset::NAMES), "", Range::None, "\"geforce2\"", NONE, "",
        "Which chip's behaviour the units follow where the GeForce2 (NV15, the project's defaults) and the original Xbox's NV2A (GeForce3-class, the chip of the hardware captures, docs/conformance.md) differ. No unit a frame scene elaborates differs between the two (shadow_compare's compare function and texel format are the scene's state on both), so a frame renders the same under either. The shading spheres take it as `shading_sphere.chip`, where the squaring path's register combiners and the vertex lighting follow it (docs/shading.md).";

    // ---- [image]
    IMAGE = "image", Ty::Table, "", Range::None, "{ width = 720, height = 480 }", NONE, "",
        "Output size in pixels (the paper's 720 × 480 when left out; both fields when given).";
    IMAGE_WIDTH = "image.width", Ty::Int, "pixels", ints(1, IMAGE_MAX_U), "required",
        "shadow_compare MAX_MAP_SIDE (the camera depth buffer) and the polygon_interpolator coordinate format (13 integer bits: vertices up to 4095.94)", "",
        "Image width.";
    IMAGE_HEIGHT = "image.height", Ty::Int, "pixels", ints(1, IMAGE_MAX_U), "required",
        "as image.width", "",
        "Image height.";

    // ---- [camera]
    CAMERA = "camera", Ty::Table, "", Range::None, "required", NONE, "",
        "A pinhole camera (right-handed world, y up). Required in a scene of lights and objects; a `[shading_sphere]` or `[test_scene]` scene has none.";
    CAMERA_EYE = "camera.eye", Ty::Reals(3), "world units", POS, "required", WORLD, "",
        "Where the camera is.";
    CAMERA_LOOK_AT = "camera.look_at", Ty::Reals(3), "world units", POS, "required", WORLD, "",
        "The point looked at; must differ from eye.";
    CAMERA_UP = "camera.up", Ty::Reals(3), "", POS, "[0.0, 1.0, 0.0]", DIRECTION, "",
        "Up direction; non-zero and not parallel to look_at − eye (sine of the angle ≥ 10⁻⁶).";
    CAMERA_FOVY_DEG = "camera.fovy_deg", Ty::Real, "degrees", open_range(0.0, 180.0), "45.0",
        "a perspective projection's field of view", "",
        "Vertical field of view.";
    CAMERA_NEAR = "camera.near", Ty::Real, "world units", open_closed(0.0, WMAX), "0.1", WORLD, "",
        "Near clip distance.";
    CAMERA_FAR = "camera.far", Ty::Real, "world units", Range::Unit("camera.near < x ≤ 1e6"), "100.0",
        WORLD, "",
        "Far clip distance; must exceed near.";

    // ---- [medium]
    MEDIUM = "medium", Ty::Table, "", Range::None, "{ rho = 0.05, kappa = 1.0, k = 1.0 }", NONE, "",
        "The participating medium, homogeneous: density ρ, extinction κ, phase constant K with F(α) = K·(1 + 9·cos¹⁶(α/2)) (Dobashi et al., eq. 4).";
    MEDIUM_RHO = "medium.rho", Ty::Real, "per world unit", closed_range(0.0, V::MEDIUM_MAX), "required",
        "MEDIUM_MAX = 10⁶ (ρκ = 10³ is a documented stiff case; exp underflows to 0, never NaN)", "",
        "Density ρ; attenuation is exp(−ρκ·length).";
    MEDIUM_KAPPA = "medium.kappa", Ty::Real, "", closed_range(0.0, V::MEDIUM_MAX), "required", "as medium.rho", "",
        "Extinction coefficient κ.";
    MEDIUM_K = "medium.k", Ty::Real, "", closed_range(0.0, V::MEDIUM_MAX), "required", "as medium.rho", "",
        "Phase-function constant K.";

    // ---- [[lights]]
    LIGHTS = "lights", Ty::Tables, "", Range::None, "[]", NONE, "",
        "Light sources of the shafts pipeline (and the shading units' lights).";
    LIGHT_KIND = "lights[].kind", Ty::Choice(LIGHT_KINDS), "", Range::None, "\"spot\"", NONE, "",
        "A spot (a cone, with a shadow map and optionally a light map) or a point light.";
    LIGHT_POSITION = "lights[].position", Ty::Reals(3), "world units", POS, "required", WORLD, "",
        "Where the light is.";
    LIGHT_DIRECTION = "lights[].direction", Ty::Reals(3), "", POS, "[0.0, -1.0, 0.0]", DIRECTION, "",
        "Spot axis (any non-zero length); a point light's shadow map looks along it too.";
    LIGHT_CUTOFF_DEG = "lights[].cutoff_deg", Ty::Real, "degrees", open_range(0.0, 90.0), "20.0",
        "a cone's half-angle (a spot's frustum)", "kind = \"spot\"",
        "Cone half-angle (ignored by a point light, which only needs it finite).";
    LIGHT_INTENSITY = "lights[].intensity", Ty::Real, "full scale × world unit²", closed_range(0.0, V::INTENSITY_MAX), "1.0",
        "INTENSITY_MAX = 10⁹", "",
        "Radiant intensity on the axis, times color; 1.0 lights a white surface at distance 1 to full scale.";
    LIGHT_COLOR = "lights[].color", Ty::Reals(3), "", closed_range(0.0, V::LIGHT_COLOR_MAX), "[1.0, 1.0, 1.0]",
        "LIGHT_COLOR_MAX = 10³", "",
        "Colour of the light, linear RGB.";
    LIGHT_MAP = "lights[].light_map", Ty::Tagged, "", Range::None, "none", NONE, "kind = \"spot\"",
        "The spot's distribution across its cone, tagged by `type`; none = uniform (no projective light-map unit is elaborated).";
    LIGHT_MAP_TYPE = "lights[].light_map.type", Ty::Choice(LIGHT_MAPS), "", Range::None, "required", NONE, "",
        "smooth: (1 − r²)^exponent; polka_dots: a smooth spot times a grid of discs; image: a picture file's luminance.";
    LIGHT_MAP_EXPONENT = "lights[].light_map.exponent", Ty::Real, "", closed_range(0.0, 64.0), "1.0",
        "64: beyond it the spot is narrower than a texel of the default map", "type = \"smooth\"",
        "Falloff exponent of the smooth spot.";
    LIGHT_MAP_DOTS = "lights[].light_map.dots", Ty::Int, "", ints(1, 64), "5",
        "64: a dot narrower than a texel of the default 256² map is lost", "type = \"polka_dots\"",
        "Dots per side of the grid.";
    LIGHT_MAP_RADIUS = "lights[].light_map.radius", Ty::Real, "cells", open_closed(0.0, 0.5), "0.3",
        "a disc within its cell", "type = \"polka_dots\"",
        "Dot radius relative to a grid cell.";
    LIGHT_MAP_PATH = "lights[].light_map.path", Ty::Str, "", Range::Unit("an existing image file (PNG, HDR), ≤ 64 MiB"), "required",
        "LIGHT_MAP_FILE_MAX_BYTES", "type = \"image\"",
        "Image file, relative to the scene file's directory; its luminance is the map.";

    // ---- [[objects]]
    OBJECTS = "objects", Ty::Tables, "", Range::None, "[]", NONE, "",
        "Lit surfaces; occluders also cast shadows into the medium.";
    OBJECT_SHAPE = "objects[].shape", Ty::Tagged, "", Range::None, "required", NONE, "",
        "Geometry, tagged by `type`.";
    SHAPE_TYPE = "objects[].shape.type", Ty::Choice(SHAPES), "", Range::None, "required", NONE, "",
        "sphere, plane (a rectangle), box (axis-aligned) or teapot (Newell's 32 Bézier patches).";
    SHAPE_CENTER = "objects[].shape.center", Ty::Reals(3), "world units", POS, "required", WORLD,
        "type = \"sphere\" or \"plane\"",
        "Centre of the sphere or rectangle.";
    SHAPE_RADIUS = "objects[].shape.radius", Ty::Real, "world units", open_closed(0.0, WMAX), "required", WORLD,
        "type = \"sphere\"",
        "Sphere radius.";
    SHAPE_NORMAL = "objects[].shape.normal", Ty::Reals(3), "", POS, "required", DIRECTION, "type = \"plane\"",
        "Rectangle normal (any non-zero length).";
    SHAPE_TANGENT = "objects[].shape.tangent", Ty::Reals(3), "", POS, "[1.0, 0.0, 0.0]", DIRECTION,
        "type = \"plane\"",
        "First in-plane axis; must not be parallel to the normal (the second is normal × tangent).";
    SHAPE_HALF_SIZE = "objects[].shape.half_size", Ty::Reals(2), "world units", open_closed(0.0, WMAX), "required",
        WORLD, "type = \"plane\"",
        "Half extents along tangent and normal × tangent.";
    SHAPE_MIN = "objects[].shape.min", Ty::Reals(3), "world units", POS, "required", WORLD, "type = \"box\"",
        "Lowest corner.";
    SHAPE_MAX = "objects[].shape.max", Ty::Reals(3), "world units", POS, "required", WORLD, "type = \"box\"",
        "Highest corner; each component must exceed min's.";
    SHAPE_POSITION = "objects[].shape.position", Ty::Reals(3), "world units", POS, "required", WORLD,
        "type = \"teapot\"",
        "Where the teapot stands.";
    SHAPE_SCALE = "objects[].shape.scale", Ty::Real, "", open_closed(0.0, V::TEAPOT_SCALE_MAX), "1.0",
        "TEAPOT_SCALE_MAX = 10⁵ (the data spans ~6.4 units: the result stays within WORLD_MAX)", "type = \"teapot\"",
        "Scale of the teapot data.";
    SHAPE_ROTATE_Y_DEG = "objects[].shape.rotate_y_deg", Ty::Real, "degrees", Range::Finite, "0.0", NONE,
        "type = \"teapot\"",
        "Rotation about the y axis.";
    SHAPE_SUBDIVISIONS = "objects[].shape.subdivisions", Ty::Int, "", ints(1, 64), "8",
        "64² quads per patch: 262 144 triangles", "type = \"teapot\"",
        "Tessellation: quads per patch side.";
    OBJECT_COLOR = "objects[].color", Ty::Reals(3), "", closed_range(0.0, 1.0), "[0.7, 0.7, 0.7]", COLOUR, "",
        "Diffuse albedo.";
    OBJECT_OCCLUDER = "objects[].occluder", Ty::Bool, "", Range::None, "true", NONE, "",
        "Casts shadows (into the shadow map and for the reference's shadow rays).";
    MATERIAL = "objects[].material", Ty::Tagged, "", Range::None, "none", NONE, "",
        "Reflection model, tagged by `model`; none = Lambert with color. An object with a material is drawn by the shading units.";
    MATERIAL_MODEL = "objects[].material.model", Ty::Choice(MODELS), "", Range::None, "required", NONE, "",
        "The reflection model (docs/shading.md).";
    MATERIAL_KS = "objects[].material.ks", Ty::Real, "", closed_range(0.0, 1.0), "required", BRDF,
        "model = \"phong\", \"blinn_phong\" or \"kajiya_kay\"",
        "Specular coefficient k_s.";
    MATERIAL_EXPONENT = "objects[].material.exponent", Ty::Real, "", closed_range(0.0, V::EXPONENT_MAX), "required",
        "EXPONENT_MAX = 10⁵: beyond it cos^n underflows for every angle a texel resolves",
        "model = \"phong\", \"blinn_phong\" or \"kajiya_kay\"",
        "Specular exponent n.";
    MATERIAL_NORMALIZED = "objects[].material.normalized", Ty::Bool, "", Range::None, "false", NONE,
        "model = \"phong\" or \"blinn_phong\"",
        "Scale the lobe by (n + 2)/2π.";
    MATERIAL_DISTRIBUTION = "objects[].material.distribution", Ty::Choice(&["beckmann", "ggx"]), "", Range::None,
        "\"beckmann\"", NONE, "model = \"cook_torrance\"",
        "Microfacet normal distribution.";
    MATERIAL_ROUGHNESS = "objects[].material.roughness", Ty::Real, "", open_closed(0.0, 1.0), "required", BRDF,
        "model = \"cook_torrance\"",
        "Beckmann m or GGX α.";
    MATERIAL_IOR = "objects[].material.ior", Ty::Real, "", open_closed(0.0, 100.0), "required", BRDF,
        "model = \"cook_torrance\"",
        "Real part of the index of refraction.";
    MATERIAL_EXTINCTION = "objects[].material.extinction", Ty::Real, "", closed_range(0.0, 100.0), "0.0", BRDF,
        "model = \"cook_torrance\"",
        "Imaginary part of the index of refraction (0 = dielectric, > 0 = metal).";
    MATERIAL_FRESNEL = "objects[].material.fresnel", Ty::Choice(&["exact", "schlick"]), "", Range::None,
        "\"exact\"", NONE, "model = \"cook_torrance\"",
        "The exact Fresnel equations or Schlick's approximation.";
    MATERIAL_RHO_S = "objects[].material.rho_s", Ty::Real, "", closed_range(0.0, 1.0), "required", BRDF,
        "model = \"ward\"",
        "Ward's specular reflectance ρ_s.";
    MATERIAL_ALPHA_X = "objects[].material.alpha_x", Ty::Real, "", open_closed(0.0, 1.0), "required", BRDF,
        "model = \"ward\"",
        "Roughness along the tangent.";
    MATERIAL_ALPHA_Y = "objects[].material.alpha_y", Ty::Real, "", open_closed(0.0, 1.0), "required", BRDF,
        "model = \"ward\"",
        "Roughness across the tangent.";
    MATERIAL_SIGMA_DEG = "objects[].material.sigma_deg", Ty::Real, "degrees", closed_range(0.0, 85.0), "required",
        "the reference takes σ ≤ 1.5 rad (85.9°)", "model = \"oren_nayar\"",
        "Oren–Nayar roughness σ.";

    // ---- [shafts]
    SHAFTS = "shafts", Ty::Table, "", Range::None, "", NONE, "",
        "How the light shafts are drawn in hardware (Dobashi et al.): sample planes, tables and widths.";
    SHAFTS_PLANES = "shafts.planes", Ty::Int, "", ints(1, 10_000), "30",
        "10 000: the documented stiff case of thousands of blended planes", "",
        "n, sample planes.";
    SHAFTS_SUBPLANES = "shafts.subplanes", Ty::Int, "", ints(1, 256), "6",
        "256: the J blend weights 1/m in 8 bits", "",
        "m, sub-sample planes per interval (1 = no sub-plane path).";
    SHAFTS_MESH = "shafts.mesh", Ty::Ints(2), "cells", ints(1, 256), "[15, 10]",
        "256 per side", "",
        "Mesh cells per sample plane, [columns, rows] (the paper: 15 × 10).";
    SHAFTS_F_TEXELS = "shafts.f_texels", Ty::Int, "texels", ints(2, TEX_MAX), "256", SAMPLER, "",
        "Width of the 1D F(α) texture (α from 0° to 180°).";
    SHAFTS_H_TEXELS = "shafts.h_texels", Ty::Ints(2), "texels", ints(2, TEX_MAX), "[256, 256]",
        "texture_sampler: MAX_SIZE per axis and MAX_TEXELS = 2²⁴ in all", "",
        "Size [s, t] of the h(s, t) texture.";
    SHAFTS_S_MAX = "shafts.s_max", Ty::Real, "world units", closed_range(0.0, WMAX), "0.0", WORLD, "",
        "Range of the h table's s axis; 0 = fit to the scene.";
    SHAFTS_T_MAX = "shafts.t_max", Ty::Real, "world units", closed_range(0.0, WMAX), "0.0", WORLD, "",
        "Range of the h table's t axis; 0 = fit to the scene.";
    SHAFTS_TEXEL_BITS = "shafts.texel_bits", Ty::Int, "bits", Range::Unit("1 ..= 16"), "8",
        "texture_sampler texel_bits, modulate bits, blend src_bits", "",
        "Texel width of the F, h and light-map textures (GeForce2: 8).";
    SHAFTS_FB_BITS = "shafts.fb_bits", Ty::Int, "bits", Range::Unit("blend's bits range"), "8",
        "blend bits", "",
        "Framebuffer bits per channel.";
    SHAFTS_WEIGHT_BITS = "shafts.weight_bits", Ty::Int, "bits", Range::Unit("texture_sampler's weight_bits range"), "8",
        "texture_sampler weight_bits, blend constant_bits", "",
        "Filter and blend weight width.";
    SHAFTS_COORD_FRAC_BITS = "shafts.coord_frac_bits", Ty::Int, "bits",
        Range::Unit("texture_sampler's coord_frac_bits range"), "8", "texture_sampler coord_frac_bits", "",
        "Sub-texel fraction bits of the interpolated texture coordinates.";
    SHAFTS_SHADOW_RESOLUTION = "shafts.shadow_resolution", Ty::Int, "texels",
        Range::Unit("1 ..= shadow_compare MAX_MAP_SIDE"), "512", "shadow_compare width and height", "",
        "Side of each light's square shadow map.";
    SHAFTS_SHADOW_DEPTH_BITS = "shafts.shadow_depth_bits", Ty::Int, "bits",
        Range::Unit("shadow_compare's depth_bits range"), "8", "shadow_compare depth_bits", "",
        "Shadow-map depth bits (the paper's GeForce2 stores 8-bit light distances).";
    SHAFTS_F_SCALE = "shafts.f_scale", Ty::Choice(&["table", "lit_volume"]), "", Range::None, "\"table\"", NONE, "",
        "What full scale of the F(α) texture stands for: the table's own maximum F(0) = 10K, or the largest F the lit volume meets.";
    SHAFTS_H_CAP = "shafts.h_cap", Ty::Choice(&["one_plane", "none"]), "", Range::None, "\"one_plane\"", NONE, "",
        "Whether h's full scale is capped so that one plane cannot exceed full scale (docs/assumptions.md).";
    SHAFTS_PLANE_STEP = "shafts.plane_step", Ty::Choice(&["along_ray", "plane_spacing"]), "", Range::None,
        "\"along_ray\"", NONE, "",
        "The ray length Δt each sample plane stands for in eq. (5) (docs/assumptions.md).";
    SHAFTS_LIGHT_MAP_TEXELS = "shafts.light_map_texels", Ty::Int, "texels", Range::Pow2 { lo: 2, hi: TEX_MAX },
        "256", SAMPLER, "",
        "Side of each spot's light-map texture; the beam's rim is as sharp as one texel.";
    SHAFTS_ACC_INT_BITS = "shafts.acc_int_bits", Ty::Int, "bits", Range::Unit("polygon_interpolator's acc_int_bits range"),
        "20", "polygon_interpolator coordinate format (acc_int_bits)", "",
        "Integer bits (with sign) of the polygon interpolator's attribute accumulators.";
    SHAFTS_ACC_FRAC_BITS = "shafts.acc_frac_bits", Ty::Int, "bits", Range::Unit("polygon_interpolator's acc_frac_bits range"),
        "24", "polygon_interpolator coordinate format (acc_frac_bits)", "",
        "Fraction bits of the interpolator's accumulators.";
    SHAFTS_RECIP_INDEX_BITS = "shafts.recip_index_bits", Ty::Int, "bits",
        Range::Unit("projective_texcoord's recip_index_bits range"), "8", "projective_texcoord recip_index_bits", "",
        "Reciprocal ROM index bits of the projective-texcoord unit (2^bits entries; the depth projection shares it).";
    SHAFTS_RECIP_ENTRY_BITS = "shafts.recip_entry_bits", Ty::Int, "bits",
        Range::Unit("projective_texcoord's recip_entry_bits range"), "16", "projective_texcoord recip_entry_bits", "",
        "Reciprocal ROM entry bits.";
    SHAFTS_NEWTON_FRAC_BITS = "shafts.newton_frac_bits", Ty::Int, "bits",
        Range::Unit("projective_texcoord's newton_frac_bits range"), "20", "projective_texcoord newton_frac_bits", "",
        "Fraction bits of the reciprocal's Newton step.";

    // ---- [glare]
    GLARE = "glare", Ty::Table, "", Range::None, "none", NONE, "",
        "Glare sources and the glare renderer's settings (Matsuda and Ikedo); none = no glare. Intensities are framebuffer codes (255 = full scale).";
    GLARE_BACKGROUND = "glare.background", Ty::Tagged, "", Range::None, "{ type = \"black\" }", NONE, "",
        "What the glare is drawn over, tagged by `type`.";
    GLARE_BACKGROUND_TYPE = "glare.background.type", Ty::Choice(BACKGROUNDS), "", Range::None, "required", NONE, "",
        "black; shafts (the scene's lights and objects through the shafts pipeline); sky (a vertical gradient); canopy (leaves against the sky).";
    GLARE_BACKGROUND_TOP = "glare.background.top", Ty::Reals(3), "", closed_range(0.0, 1.0), "required", COLOUR,
        "type = \"sky\"", "Colour at the top of the image.";
    GLARE_BACKGROUND_BOTTOM = "glare.background.bottom", Ty::Reals(3), "", closed_range(0.0, 1.0), "required", COLOUR,
        "type = \"sky\"", "Colour at the bottom of the image.";
    GLARE_BACKGROUND_LEAVES = "glare.background.leaves", Ty::Int, "", ints(0, 10_000), "required",
        "10 000 discs", "type = \"canopy\"", "Number of leaf discs (seeded).";
    GLARE_BACKGROUND_SKY = "glare.background.sky", Ty::Reals(3), "", closed_range(0.0, 1.0), "required", COLOUR,
        "type = \"canopy\"", "Sky colour between the leaves.";
    GLARE_BACKGROUND_LEAF = "glare.background.leaf", Ty::Reals(3), "", closed_range(0.0, 1.0), "required", COLOUR,
        "type = \"canopy\"", "Leaf colour.";
    GLARE_DETERMINANTS = "glare.determinants", Ty::Table, "", Range::None, "", NONE, "",
        "Table 1's global determinants.";
    GLARE_AMBIENT = "glare.determinants.ambient", Ty::Real, "codes", closed_range(0.0, 1e6), "4.0", MODEL, "",
        "Ambient luminance E₁: bloom −, flare −; also I_a of the glare conditions.";
    GLARE_AGE = "glare.determinants.age", Ty::Real, "years", closed_range(0.0, 120.0), "30.0",
        "a human age (Vos' age factor 1 + (A/62.5)⁴)", "", "Age of the viewer: bloom +.";
    GLARE_MIST = "glare.determinants.mist", Ty::Real, "", closed_range(0.0, 1e3), "0.0", MODEL, "",
        "Mist M_f (0 = clear): bloom +, flare −.";
    GLARE_GLASSES = "glare.determinants.glasses", Ty::Bool, "", Range::None, "false", NONE, "",
        "Near-sighted glasses: bloom −, flare +.";
    GLARE_WAVELENGTHS = "glare.determinants.wavelengths_nm", Ty::Reals(3), "nm", closed_range(300.0, 900.0),
        "[650.0, 550.0, 450.0]", "visible light and near UV/IR", "",
        "Wavelengths the R, G, B channels stand for; the halo radius scales as λ/568.";
    GLARE_SOURCES = "glare.sources", Ty::Tables, "", Range::None, "[]", NONE, "",
        "Light sources as the glare renderer sees them (Table 1, rows 1–3).";
    SOURCE_KIND = "glare.sources[].kind", Ty::Choice(SOURCE_KINDS), "", Range::None, "required", NONE, "",
        "point (eq. 1), circle (a disc facing the viewer, eq. 3), cylindrical, elliptic, polygon (eq. 4).";
    SOURCE_POSITION = "glare.sources[].position", Ty::Reals(3), "world units", POS, "required", WORLD, "",
        "P₀, the centre (projected through the scene's camera).";
    SOURCE_A = "glare.sources[].a", Ty::Real, "world units", closed_range(0.0, 1e6), "0.0", WORLD,
        "kind = \"circle\", \"cylindrical\" or \"elliptic\"",
        "Circle: radius; cylindrical / elliptic: semi-major axis.";
    SOURCE_B = "glare.sources[].b", Ty::Real, "world units", closed_range(0.0, 1e6), "0.0", WORLD,
        "kind = \"cylindrical\" or \"elliptic\"",
        "Semi-minor axis (the cylinder's radius); must not exceed a.";
    SOURCE_N = "glare.sources[].n", Ty::Reals(3), "", POS, "[0.0, 1.0, 0.0]", DIRECTION,
        "kind = \"cylindrical\" or \"elliptic\"", "Semi-minor direction N.";
    SOURCE_VERTICES = "glare.sources[].vertices", Ty::Points, "world units", POS, "[]",
        "2 ..= 64 vertices besides position", "kind = \"polygon\"",
        "P₁ … P_n; with position as P₀ they span the polygon.";
    SOURCE_INTENSITY = "glare.sources[].intensity", Ty::Real, "codes", closed_range(0.0, V::GLARE_INTENSITY_MAX), "required", CODES, "",
        "I; 2000 is about 8× saturation.";
    SOURCE_AREA_SIZE = "glare.sources[].area_size", Ty::Real, "", closed_range(0.0, 1.0), "1.0", MODEL, "",
        "The effective intensity is area_size × I.";
    SOURCE_DIRECTIVITY = "glare.sources[].directivity", Ty::Reals(3), "", POS, "none", DIRECTION, "",
        "Directivity D, the way the source faces; none = radiates equally every way.";
    SOURCE_COLOR = "glare.sources[].color", Ty::Reals(3), "", closed_range(0.0, 1.0), "[1.0, 1.0, 1.0]", COLOUR, "",
        "Colour of the source's light.";
    SOURCE_BLOOM = "glare.sources[].bloom", Ty::Bool, "", Range::None, "true", NONE, "",
        "Show bloom.";
    SOURCE_HALO = "glare.sources[].halo", Ty::Bool, "", Range::None, "true", NONE, "",
        "Show the halo.";
    SOURCE_FLARE = "glare.sources[].flare", Ty::Bool, "", Range::None, "true", NONE, "",
        "Show flare lines.";
    SOURCE_FLUCTUATION = "glare.sources[].fluctuation", Ty::Table, "", Range::None, "none", NONE, "",
        "Sunlight through leaves (eqs. 9–11): the source split into patches with independent 1/f chaos states.";
    FLUCTUATION_PATCHES = "glare.sources[].fluctuation.patches", Ty::Int, "", ints(1, 64), "required",
        "64 chaos states", "", "Number of patches (circle sources).";
    FLUCTUATION_SPREAD = "glare.sources[].fluctuation.spread", Ty::Real, "world units", closed_range(0.0, 1e6),
        "required", WORLD, "", "Patches are scattered (seeded) within this radius of P₀.";
    FLUCTUATION_PATCH_RADIUS = "glare.sources[].fluctuation.patch_radius", Ty::Real, "world units",
        closed_range(0.0, 1e6), "required", WORLD, "", "Radius of each patch.";
    GLARE_HIGHLIGHTS = "glare.highlights", Ty::Tables, "", Range::None, "[]", NONE, "",
        "Specular highlights tested by the glare conditions (Table 2); one that passes becomes a circle source.";
    HIGHLIGHT_MATERIAL = "glare.highlights[].material", Ty::Choice(&["metallic", "water"]), "", Range::None,
        "required", NONE, "", "Which glare condition of Table 2 applies.";
    HIGHLIGHT_POSITION = "glare.highlights[].position", Ty::Reals(3), "world units", POS, "required", WORLD, "",
        "The surface point.";
    HIGHLIGHT_NORMAL = "glare.highlights[].normal", Ty::Reals(3), "", POS, "required", DIRECTION, "",
        "The surface normal.";
    HIGHLIGHT_LIGHT = "glare.highlights[].light", Ty::Reals(3), "world units", POS, "required", WORLD, "",
        "The light's position.";
    HIGHLIGHT_INTENSITY = "glare.highlights[].intensity", Ty::Real, "codes", closed_range(0.0, V::GLARE_INTENSITY_MAX), "required",
        CODES, "", "The light's intensity I.";
    HIGHLIGHT_SPECULAR = "glare.highlights[].specular", Ty::Real, "", closed_range(0.0, 1.0), "1.0", MODEL,
        "material = \"metallic\"", "I_s, the specular coefficient.";
    HIGHLIGHT_ETA = "glare.highlights[].eta", Ty::Real, "", open_closed(0.0, 10.0), "1.33",
        "and the glare_condition unit's η format (its constructor)", "material = \"water\"",
        "η, the ratio of refractive indices (read as model.water_eta says).";
    HIGHLIGHT_RADIUS = "glare.highlights[].radius", Ty::Real, "world units", closed_range(0.0, 1e6), "0.02", WORLD,
        "", "Radius of the source disc the highlight becomes.";
    SHADED_HIGHLIGHTS = "glare.shaded_highlights", Ty::Table, "", Range::None, "none", NONE, "",
        "Highlights found by the shading units on objects with a specular material; none = only the written highlights.";
    SHADED_LIGHT = "glare.shaded_highlights.light", Ty::Int, "", Range::Unit("an index into lights"), "required",
        "the scene's light count", "", "The scene light whose highlights are sought.";
    SHADED_INTENSITY = "glare.shaded_highlights.intensity", Ty::Real, "codes", closed_range(0.0, V::GLARE_INTENSITY_MAX), "required",
        CODES, "", "I of Table 2 for that light.";
    SHADED_RADIUS = "glare.shaded_highlights.radius", Ty::Real, "world units", closed_range(0.0, 1e6), "0.02", WORLD,
        "", "Radius of the glare source disc a highlight becomes.";
    GLARE_MODEL = "glare.model", Ty::Table, "", Range::None, "", NONE, "",
        "The empirical constants and the forms the paper leaves open (docs/glare.md, docs/assumptions.md).";
    POINT_A = "glare.model.point_a", Ty::Real, "", closed_range(0.0, 1e6), "29.0", MODEL, "",
        "Point source, eq. (1): A/(θ + θ₀)^m with A = point_a·k·I.";
    POINT_K = "glare.model.point_k", Ty::Real, "", closed_range(0.0, 1e6), "0.03", MODEL, "",
        "k of the point source's A.";
    POINT_THETA0_DEG = "glare.model.point_theta0_deg", Ty::Real, "degrees", open_closed(0.0, 90.0), "0.13", MODEL, "",
        "θ₀ of eq. (1).";
    POINT_M = "glare.model.point_m", Ty::Real, "", closed_range(0.5, 8.0), "2.8", MODEL, "",
        "m of eq. (1).";
    BLOOM_N = "glare.model.bloom_n", Ty::Real, "", closed_range(0.5, 10.0), "3.0", MODEL, "",
        "Extended sources, eqs. (3)/(4): the n of A·exp(−(θ/w)ⁿ).";
    BLOOM_M = "glare.model.bloom_m", Ty::Real, "", closed_range(0.5, 8.0), "2.0", MODEL, "",
        "The m of B/(θ + θ₁)^m.";
    BLOOM_W_DEG = "glare.model.bloom_w_deg", Ty::Real, "degrees", open_closed(0.0, 90.0), "0.3", MODEL, "",
        "w, the angular scale of exp(−(θ/w)ⁿ) (the paper writes none: 1° read literally). Also accepted as bloom_angle_scale_deg.";
    BLOOM_THETA1_DEG = "glare.model.bloom_theta1_deg", Ty::Real, "degrees", open_closed(0.0, 90.0), "0.5", MODEL, "",
        "θ₁ of B/(θ + θ₁)^m.";
    BLOOM_K = "glare.model.bloom_k", Ty::Real, "", closed_range(0.0, 1e6), "1.0", MODEL, "",
        "B = bloom_k·I·(age factor)·(mist and ambient factors).";
    GLASSES_BLOOM = "glare.model.glasses_bloom", Ty::Real, "", closed_range(0.0, 1.0), "0.8", MODEL, "",
        "Factor on bloom with glasses.";
    HALO_K = "glare.model.halo_k", Ty::Real, "", closed_range(0.0, 1e6), "0.05", MODEL, "",
        "Halo, eq. (5): C = halo_k·I (see halo_amplitude).";
    HALO_RADIUS_DEG = "glare.model.halo_radius_deg", Ty::Real, "degrees", closed_range(0.0, 90.0), "1.5", MODEL, "",
        "θ₁, the ring radius at 568 nm (half the \"diameter 3°\"; see halo_radius).";
    HALO_ALPHA_DEG = "glare.model.halo_alpha_deg", Ty::Real, "degrees", open_closed(0.0, 90.0), "0.225", MODEL, "",
        "α, the ring's width.";
    HALO_AMPLITUDE = "glare.model.halo_amplitude", Ty::Choice(&["intensity", "ambient_x10"]), "", Range::None,
        "\"intensity\"", NONE, "",
        "C = halo_k·I (the model's choice) or C = 10·E₁ (the paper's sentence read literally).";
    HALO_RADIUS = "glare.model.halo_radius", Ty::Choice(&["diameter_half", "spencer"]), "", Range::None,
        "\"diameter_half\"", NONE, "",
        "θ₁ = halo_radius_deg, or 2·halo_radius_deg (Spencer et al. 1995).";
    BLOOM_RANGE = "glare.model.bloom_range", Ty::Choice(&["cutoff_14", "eq1_8deg"]), "", Range::None,
        "\"cutoff_14\"", NONE, "",
        "Bloom drawn out to where it falls below half a level, or zero beyond 8° (eq. 1's stated range).";
    WATER_ETA = "glare.model.water_eta", Ty::Choice(&["media_over_air", "air_over_media"]), "", Range::None,
        "\"media_over_air\"", NONE, "",
        "How a water highlight's eta enters Table 2's total-internal-reflection test.";
    FLARE_NUM_K = "glare.model.flare_num_k", Ty::Real, "", closed_range(0.0, 1e6), "1.2", MODEL, "",
        "Flare lines, eq. (6): number factor.";
    FLARE_LEN_K_DEG = "glare.model.flare_len_k_deg", Ty::Real, "degrees", closed_range(0.0, 1e3), "0.3", MODEL, "",
        "Length factor.";
    FLARE_WIDTH_K_DEG = "glare.model.flare_width_k_deg", Ty::Real, "degrees", closed_range(0.0, 1e3), "0.004",
        MODEL, "", "Width factor.";
    FLARE_INTENSITY_K = "glare.model.flare_intensity_k", Ty::Real, "", closed_range(0.0, 1e6), "0.05", MODEL, "",
        "Intensity factor.";
    FLARE_SPREAD_RAD = "glare.model.flare_spread_rad", Ty::Real, "radians", closed_range(0.0, 10.0), "1.0", MODEL, "",
        "Angular spread of a circle source's lines (ang = 1 of eq. 6).";
    FLARE_MAX_LINES = "glare.model.flare_max_lines", Ty::Int, "", ints(0, 1024), "64",
        "the noise generator's budget", "", "Most flare lines per source.";
    E_INTENSITY = "glare.model.e_intensity", Ty::Real, "", closed_range(0.0, 8.0), "0.5", EXPONENT, "",
        "Exponent of R1 on the intensity.";
    E_GLASSES = "glare.model.e_glasses", Ty::Real, "", closed_range(0.0, 8.0), "1.0", EXPONENT, "",
        "Exponent of R1 on the glasses.";
    E_SIZE = "glare.model.e_size", Ty::Real, "", closed_range(0.0, 8.0), "1.0", EXPONENT, "",
        "Exponent of R1 on the source size.";
    E_AMBIENT = "glare.model.e_ambient", Ty::Real, "", closed_range(0.0, 8.0), "0.5", EXPONENT, "",
        "Exponent of R1 on the ambient level.";
    E_MIST = "glare.model.e_mist", Ty::Real, "", closed_range(0.0, 8.0), "1.0", EXPONENT, "",
        "Exponent of R1 on the mist.";
    E_DIRECTIVITY = "glare.model.e_directivity", Ty::Real, "", closed_range(0.0, 8.0), "2.0", EXPONENT, "",
        "Exponent of R1 on the directivity.";
    E_SHAPE = "glare.model.e_shape", Ty::Real, "", closed_range(0.0, 8.0), "0.5", EXPONENT, "",
        "Exponent of R1 on the shape.";
    SIZE_REF_DEG = "glare.model.size_ref_deg", Ty::Real, "degrees", open_closed(0.0, 90.0), "2.0", MODEL, "",
        "S_ref in (1 + S/S_ref).";
    GLASSES_FLARE = "glare.model.glasses_flare", Ty::Real, "", closed_range(1.0, 100.0), "1.5", MODEL, "",
        "Factor g on the flare with glasses (≥ 1).";
    CONTRAST = "glare.model.contrast", Ty::Real, "", open_closed(0.0, 1e6), "40.0", MODEL, "",
        "Contrast threshold of Table 2.";
    CHAOS_A = "glare.model.chaos_a", Ty::Real, "", open_range(0.0, 1.0), "0.8", "the chaos map of eq. (9)", "",
        "a of the chaos map.";
    CHAOS_Z = "glare.model.chaos_z", Ty::Real, "", open_range(1.0, 2.0), "1.95", "the chaos map of eq. (9)", "",
        "z of the chaos map.";
    GLARE_HW = "glare.hw", Ty::Table, "", Range::None, "", NONE, "",
        "The glare hardware's widths (what a sweep changes).";
    HW_SHAPE_LOG2 = "glare.hw.shape_log2", Ty::Int, "log2 cells", Range::Unit("luminance_ram's shape_log2 range"), "7",
        "luminance_ram shape_log2", "", "Shape RAM: 2^k cells per side.";
    HW_SHAPE_BITS = "glare.hw.shape_bits", Ty::Int, "bits", Range::Unit("luminance_ram's shape_bits range"), "16",
        "luminance_ram shape_bits", "", "Shape RAM entry width.";
    HW_FALLOFF_LOG2 = "glare.hw.falloff_log2", Ty::Int, "log2 cells", Range::Unit("luminance_ram's falloff_log2 range"),
        "8", "luminance_ram falloff_log2", "", "Falloff RAM: 2^m cells.";
    HW_FALLOFF_BITS = "glare.hw.falloff_bits", Ty::Int, "bits", Range::Unit("luminance_ram's falloff_bits range"), "16",
        "luminance_ram falloff_bits", "", "Falloff RAM entry width.";
    HW_WEIGHT_BITS = "glare.hw.weight_bits", Ty::Int, "bits", Range::Unit("luminance_ram's weight_bits range"), "8",
        "luminance_ram weight_bits", "", "Interpolation weight bits in both RAMs.";
    HW_COORD_FRAC_BITS = "glare.hw.coord_frac_bits", Ty::Int, "bits",
        Range::Unit("luminance_ram's coord_frac_bits range"), "14", "luminance_ram coord_frac_bits", "",
        "Fraction bits of the interpolated (u, v).";
    HW_NOISE_BITS = "glare.hw.noise_bits", Ty::Int, "bits", Range::Unit("gaussian_noise's uniform_bits range"), "32",
        "gaussian_noise uniform_bits", "", "Uniform bits of the Gaussian noise generator.";
    HW_FB_BITS = "glare.hw.fb_bits", Ty::Int, "bits", Range::Unit("glare_combiner's fb_bits range"), "8",
        "glare_combiner fb_bits", "", "Framebuffer bits per channel.";
    HW_CLOCK_MHZ = "glare.hw.clock_mhz", Ty::Real, "MHz", open_closed(0.0, 1e5), "300.0", "a clock", "",
        "Clock of the throughput model.";
    HW_PIPES = "glare.hw.pipes", Ty::Int, "", ints(1, 256), "4", "parallel pixel pipes", "",
        "Parallel pixel pipes of the throughput model.";
    HW_RADIAL = "glare.hw.radial", Ty::Bool, "", Range::None, "false", NONE, "",
        "Radial correction in the luminance modulators' shape RAM.";
    GLARE_FRAME = "glare.frame", Ty::Int, "frames", ints(0, 10_000_000), "0", "10⁷ chaos-map steps", "",
        "Frame number t of the 1/f fluctuation (the chaos map runs t steps).";

    // ---- [environment]
    ENVIRONMENT = "environment", Ty::Table, "", Range::None, "none", NONE, "",
        "An environment map and the object drawn with it (Okumura's multi-scale environment map, docs/envmap.md); none = no environment.";
    ENV_MAP = "environment.map", Ty::Choice(&super::envmap::BUILTIN_NAMES), "", Range::None, "none", NONE, "",
        "A built-in map; exactly one of map and hdr.";
    ENV_HDR = "environment.hdr", Ty::Str, "", Range::Unit("a Radiance .hdr file, equirectangular"), "none",
        "envmap MAX_HDR_BYTES", "",
        "A Radiance file, relative to the scene file's directory.";
    ENV_EXPOSURE = "environment.exposure", Ty::Real, "levels per radiance unit", open_closed(0.0, V::ENV_MAX_EXPOSURE), "none",
        "MAX_EXPOSURE (the auto exposure's own cap)", "",
        "Radiance × exposure → levels (255 = full scale); none = chosen by exposure_rule.";
    ENV_EXPOSURE_RULE = "environment.exposure_rule", Ty::Choice(&["p99_solid_angle", "p99_texels", "max"]), "",
        Range::None, "\"p99_solid_angle\"", NONE, "",
        "How the exposure is picked when none is given (docs/assumptions.md).";
    ENV_WEIGHTING = "environment.weighting", Ty::Choice(&["solid_angle", "uniform"]), "", Range::None,
        "\"solid_angle\"", NONE, "", "Texel weights of eq. (9): by solid angle, or the literal uniform sum.";
    ENV_DOME_PICK = "environment.dome_pick", Ty::Choice(&["half_weight", "voxel_spacing"]), "", Range::None,
        "\"half_weight\"", NONE, "",
        "Which pyramid level's dome the accelerated prefilter uses (only with an accelerated prefilter).";
    ENV_SIDE = "environment.side", Ty::Int, "voxels", Range::Pow2 { lo: ENV_MIN_SIDE, hi: ENV_MAX_SIDE }, "128",
        "texture_sampler MAX_TEXELS = 2²⁴ (the 3D map's texel address: side³ ≤ 2²⁴)", "",
        "Side s of the s³ voxel map.";
    ENV_OBJECT = "environment.object", Ty::Choice(&["sphere", "teapot"]), "", Range::None, "none", NONE, "",
        "The thesis object drawn at the origin; none = no object.";
    ENV_LAMBDA = "environment.lambda", Ty::RealOr(&["nonuniform"]), "", closed_range(0.0, 1.0), "1.0", MODEL, "",
        "Smoothness λ of the object (1 = the sharpest lobe), or the thesis' nonuniform settings.";
    ENV_LOOKUP = "environment.lookup", Ty::Choice(&["voxel3d", "auto"]), "", Range::None, "\"voxel3d\"", NONE, "",
        "Always the 3D voxel map, or a 2D slice where λ is uniform.";
    ENV_BACKGROUND = "environment.background", Ty::Choice(&["environment", "black"]), "", Range::None,
        "\"environment\"", NONE, "", "What is behind the object.";
    ENV_REFLECTORS = "environment.reflectors", Ty::Tables, "", Range::None, "[]", NONE, "",
        "Scene objects that reflect the environment (not with object).";
    REFLECTOR_OBJECT = "environment.reflectors[].object", Ty::Int, "", Range::Unit("an index into objects (not a teapot)"),
        "required", "the scene's object count", "", "The reflecting object.";
    REFLECTOR_LAMBDA = "environment.reflectors[].lambda", Ty::Real, "", closed_range(0.0, 1.0), "required", MODEL, "",
        "Smoothness λ.";
    REFLECTOR_REFLECTANCE = "environment.reflectors[].reflectance", Ty::Real, "", closed_range(0.0, 1.0), "required",
        MODEL, "", "Fraction of the environment's radiance reflected.";
    ENV_PREFILTER = "environment.prefilter", Ty::Tagged, "", Range::None, "{ type = \"auto\" }", NONE, "",
        "How the voxel map is prefiltered, tagged by `type`.";
    PREFILTER_TYPE = "environment.prefilter.type", Ty::Choice(&["accelerated", "exact", "auto"]), "", Range::None,
        "required", NONE, "",
        "accelerated (the thesis' pyramid and domes), exact (every texel; slow), auto (accelerated up to side 128, exact above).";
    PREFILTER_THRESHOLD = "environment.prefilter.threshold", Ty::Real, "", closed_open(0.0, 1.0), "0.001", MODEL,
        "type = \"accelerated\"", "Weight-table pruning threshold th.";

    // ---- [shading_hw]
    SHADING_HW = "shading_hw", Ty::Table, "", Range::None, "none", NONE, "",
        "The widths of the shading units the frame's object pass runs; none = the GeForce defaults (docs/shading.md). `sweep`, `attribute` and `optimize` set them on a frame scene.";
    SHADING_HW_CUBE_FACE = "shading_hw.cube_face", Ty::Int, "texels", Range::Pow2 { lo: 2, hi: 512 }, "64",
        "normalisation cube: 6F rows fit texture_sampler's 4096", "",
        "The normalisation cube map's face side F.";
    SHADING_HW_LOOKUP_LOG2 = "shading_hw.lookup_log2", Ty::Int, "log2 entries", ints(1, 12), "8",
        "specular_lookup: 1 ..= 12", "", "log2 of the specular lookup's entries (Phong, Blinn–Phong).";
    SHADING_HW_FACTOR_SIZE = "shading_hw.factor_size", Ty::Int, "texels", ints(1, 4096), "64", SAMPLER, "",
        "The BRDF factor textures' side (factored materials).";
    SHADING_HW_FACTOR_BITS = "shading_hw.factor_bits", Ty::Int, "bits", ints(1, 16), "8",
        "texture_sampler: texel bits 1 ..= 16", "", "The factor textures' texel bits.";

    // ---- [rounding]
    ROUNDING = "rounding", Ty::Table, "", Range::None, "none", NONE, "",
        "Where GL leaves rounding to the implementation, the units' choice; none = the GeForce-style defaults (docs/shading.md).";
    ROUNDING_CHAIN = "rounding.chain", Ty::Choice(&["per_stage", "fused"]), "", Range::None, "\"per_stage\"", NONE, "",
        "A chain of MODULATE stages: an 8-bit register between stages, or rounded once.";
    ROUNDING_FILTER = "rounding.filter", Ty::Choice(&["product_weights", "successive_lerps"]), "", Range::None,
        "\"product_weights\"", NONE, "", "Bilinear filtering: weights multiplied out, or three lerps.";
    ROUNDING_WEIGHT = "rounding.weight", Ty::Choice(&["round", "round_half_even", "truncate"]), "", Range::None,
        "\"round\"", NONE, "", "Sub-texel fraction → filter weight.";

    // ---- [shading_sphere]
    SHADING_SPHERE = "shading_sphere", Ty::Table, "", Range::None, "none", NONE, "",
        "The shading units' sphere: a built-in shading scene (`shading-<model>`, `shading-specular`, `shading-vertex`) at a chosen size, chip and widths, rendered through the shading path against its f64 reference (docs/shading.md). A scene that holds it is that sphere and nothing else: no camera, image, medium, lights, objects, shafts, glare, environment, rounding or shading_hw (validation refuses the mix, naming the field). A file whose top-level table is `[shading]` with the same keys reads as this section (errors then name `shading.*`); `scene shading-NAME` prints that form and `optimize` writes it as best.toml.";
    SHADING_SPHERE_SCENE = "shading_sphere.scene", Ty::Str, "", Range::None, "required", NONE, "",
        "The built-in shading scene: `shading-lambert`, `shading-oren_nayar`, `shading-phong`, `shading-blinn_phong`, `shading-cook_torrance_metal`, `shading-cook_torrance_dielectric`, `shading-cook_torrance_backlit`, `shading-ward`, `shading-kajiya_kay`, `shading-specular` or `shading-vertex`.";
    SHADING_SPHERE_IMAGE = "shading_sphere.image", Ty::Int, "pixels", ints(2, 4096), "256",
        "texture_sampler MAX_SIZE (4096); 2 (a sphere needs a rim)", "not shading-vertex",
        "The sphere view's side (the view is square); `shading-vertex` lights sphere vertices and has no image.";
    SHADING_SPHERE_CHIP = "shading_sphere.chip", Ty::Choice(&rtl_model::chip_preset::ChipPreset::NAMES), "", Range::None, "\"geforce2\"", NONE, "",
        "The chip preset whose modes the path's units follow: the squaring path's register combiners (`shading-specular`) and the vertex lighting (`shading-vertex`) differ between the GeForce2 and the NV2A (docs/conformance.md).";
    SHADING_SPHERE_HW = "shading_sphere.hw", Ty::Table, "", Range::None, "none", NONE, "",
        "The widths of the scene's path by `sweep`'s names; a width not given keeps its GeForce default, a width the scene's path does not have is refused naming it.";
    SHADING_SPHERE_HW_COMBINER_BITS = "shading_sphere.hw.combiner_bits", Ty::Int, "bits", Range::Unit("register_combiner internal width"), "9",
        "register_combiner", "shading-specular (its squaring path, alone)", "The register combiners' internal width of the squaring path.";
    SHADING_SPHERE_HW_CUBE_FACE = "shading_sphere.hw.cube_face", Ty::Int, "texels", Range::Unit("normalisation cube face side"), "64",
        "texture_sampler (6F rows of the cube)", "not shading-vertex", "The normalisation cube map's face side (256 on `shading-specular`'s lookup path).";
    SHADING_SPHERE_HW_CUBE_BITS = "shading_sphere.hw.cube_bits", Ty::Int, "bits", Range::Unit("texture_sampler texel bits"), "16",
        "texture_sampler", "shading-specular", "The cube's texel bits on `shading-specular`'s lookup path (the DOT3's and the lookup index's width).";
    SHADING_SPHERE_HW_LOOKUP_LOG2 = "shading_sphere.hw.lookup_log2", Ty::Int, "log2 entries", Range::Unit("specular_lookup entries"), "8",
        "specular_lookup", "Phong, Blinn–Phong, shading-specular", "log2 of the specular lookup's entries.";
    SHADING_SPHERE_HW_LOOKUP_BITS = "shading_sphere.hw.lookup_bits", Ty::Int, "bits", Range::Unit("specular_lookup entry bits"), "8",
        "specular_lookup", "shading-specular", "The specular lookup's entry bits.";
    SHADING_SPHERE_HW_FACTOR_SIZE = "shading_sphere.hw.factor_size", Ty::Int, "texels", Range::Unit("factor texture side"), "64",
        "texture_sampler", "the factored models", "The BRDF factor textures' side.";
    SHADING_SPHERE_HW_FACTOR_BITS = "shading_sphere.hw.factor_bits", Ty::Int, "bits", Range::Unit("factor texel bits"), "8",
        "texture_sampler", "the factored models", "The factor textures' texel bits.";
    SHADING_SPHERE_HW_VERTEX_MANTISSA = "shading_sphere.hw.vertex_mantissa", Ty::Int, "bits", Range::Unit("vertex_lighting float format"), "23",
        "vertex_lighting", "shading-vertex", "The vertex lighting's float mantissa bits.";
    SHADING_SPHERE_HW_VERTEX_EXPONENT = "shading_sphere.hw.vertex_exponent", Ty::Int, "bits", Range::Unit("vertex_lighting float format"), "8",
        "vertex_lighting", "shading-vertex", "The vertex lighting's float exponent bits.";

    // ---- [test_scene]
    TEST_SCENE = "test_scene", Ty::Table, "", Range::None, "none", NONE, "",
        "The foundation test scene (`render --scene test`): a fixed 320 × 240 scene of a checkered floor, a spot with a light map and a shadow map, and a window-frame occluder. The table is empty (the scene has no fields); a scene that holds it is that scene and nothing else.";
}

/// The entry of a TOML path (`lights[].position`), if any.
pub fn field(path: &str) -> Option<&'static Field> {
    FIELDS.iter().find(|f| f.path == path)
}

/// A concrete path (`lights[2].light_map.type`) with its indices removed
/// (`lights[].light_map.type`).
pub fn generic_path(path: &str) -> String {
    let mut out = String::with_capacity(path.len());
    let mut skip = false;
    for c in path.chars() {
        match c {
            '[' => {
                out.push('[');
                skip = true;
            }
            ']' => {
                out.push(']');
                skip = false;
            }
            _ if skip => {}
            _ => out.push(c),
        }
    }
    out
}

/// The valid keys directly under a section path (`camera` → eye, look_at, …), for
/// suggestions.
pub fn keys_under(section: &str) -> Vec<&'static str> {
    let g = generic_path(section);
    FIELDS
        .iter()
        .filter_map(|f| {
            let rest = if g.is_empty() {
                Some(f.path)
            } else {
                f.path
                    .strip_prefix(g.as_str())
                    .and_then(|r| r.strip_prefix('.').or_else(|| r.strip_prefix("[].")))
            }?;
            (!rest.contains('.')).then_some(rest)
        })
        .collect()
}

/// The one-line comment `scene NAME` writes above a section header: the first
/// sentence of its description (a period after "al" or "eq" does not end one).
pub fn section_comment(path: &str) -> Option<String> {
    let f = field(&generic_path(path))?;
    Some(first_sentence(f.doc))
}

fn first_sentence(doc: &str) -> String {
    let mut from = 0;
    while let Some(i) = doc[from..].find(". ") {
        let end = from + i;
        let word = doc[..end].rsplit([' ', '(']).next().unwrap_or("");
        if !matches!(word, "al" | "eq" | "e.g" | "i.e") {
            return doc[..=end].to_string();
        }
        from = end + 2;
    }
    let d = doc.trim_end_matches('.');
    format!("{d}.")
}

/// The unit `scene NAME` writes after a field's value, if it has one.
pub fn unit_comment(path: &str) -> Option<&'static str> {
    let f = field(&generic_path(path))?;
    (!f.unit.is_empty()).then_some(f.unit)
}
