//! The `[environment]` section of a scene (Okumura's multi-scale environment
//! map): which environment (a built-in map or a Radiance `.hdr` file), how its voxel
//! map is built (side s, prefilter), and the thesis object drawn with it (sphere or
//! teapot, smoothness λ, lookup path, background). The scene's `camera` and `image`
//! apply. Rendered by `pipeline::envmap::scene_render`; documented in docs/envmap.md.
//!
//! ```toml
//! [environment]
//! map = "venice_sunset"            # a built-in map (pattern, venice_sunset, st_fagans_interior)
//! # hdr = "my_map.hdr"               # or a Radiance file of your own, relative to this file
//! #                                  # (the built-in maps ship as src/scene/data/envmaps/*.hdr)
//! side = 128
//! object = "teapot"
//! lambda = "nonuniform"                 # or a number in [0, 1]
//! prefilter = { type = "accelerated", threshold = 0.001 }   # or "exact"; default "auto"
//! ```
//!
//! A relative `hdr` path is resolved against the scene file's directory when the file
//! is loaded ([`super::format::Scene::from_file`]), against the working directory for
//! a scene parsed from text; the path as written is what the scene serialises.

use std::path::{Path, PathBuf};

use rtl_model::error::{check_range, ConfigError};
use serde::de::{self, Deserializer, Visitor};
use serde::{Deserialize, Serialize, Serializer};

use super::envmap::{EnvMap, BUILTIN_NAMES};
use super::fields;
use super::format::Camera;

/// Default voxel map side s (the thesis': 128³).
pub const DEFAULT_SIDE: u32 = 128;
/// Smallest and largest voxel map side. The largest is the largest power of two whose
/// cube fits the 3D texture sampler's texel RAM address (`rtl_model`'s
/// `texture_sampler::MAX_TEXELS` = 2^24 texels, a 24-bit address): 256
/// ([`super::limits::ENV_MAX_SIDE`]). A 512³ map (2^27 texels, 512 MiB at 4 bytes per
/// texel) is beyond both that address and the 64–128 MB boards of the GeForce3 class,
/// so it is refused before any work (docs/envmap.md, "Map side").
pub const MIN_SIDE: u32 = super::bounds::ENV_MIN_SIDE;
pub const MAX_SIDE: u32 = super::limits::ENV_MAX_SIDE;
/// The thesis' accelerated-prefilter threshold th (Table 5, the figures).
pub const THESIS_THRESHOLD: f64 = 0.001;
/// The accelerated prefilter builds a 4-level pyramid of the map: its width and height
/// must halve three times.
pub const PYRAMID_DIVISOR: usize = 8;
/// Largest exposure (the auto exposure's own cap).
pub const MAX_EXPOSURE: f64 = super::bounds::ENV_MAX_EXPOSURE;

/// `[environment]`: an environment map and the thesis object drawn with it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnvironmentSection {
    /// A built-in map ([`BUILTIN_NAMES`]); exactly one of `map` and `hdr`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub map: Option<String>,
    /// A Radiance `.hdr` file (equirectangular; see `scene::envmap`'s conventions).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hdr: Option<HdrPath>,
    /// Radiance × exposure → levels (255 = full scale); none = the map's auto exposure
    /// ([`EnvMap::auto_exposure`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exposure: Option<f64>,
    /// The rule that picks the exposure when `exposure` is not given
    /// (docs/assumptions.md): the model's solid-angle 99th percentile by default.
    #[serde(default, skip_serializing_if = "ExposureRule::is_default")]
    pub exposure_rule: ExposureRule,
    /// The texel weights of eq. (9): by solid angle (the model's) or the literal
    /// uniform sum (docs/assumptions.md).
    #[serde(default, skip_serializing_if = "EnvWeighting::is_default")]
    pub weighting: EnvWeighting,
    /// Which pyramid level's geodesic dome the accelerated prefilter filters each voxel
    /// on (docs/assumptions.md, envmap.dome_pick); only with an accelerated prefilter.
    #[serde(default, skip_serializing_if = "EnvDomePick::is_default")]
    pub dome_pick: EnvDomePick,
    /// Voxel map side s: a power of two in [`MIN_SIDE`] ..= [`MAX_SIDE`].
    #[serde(default = "default_side")]
    pub side: u32,
    /// The object drawn (at its thesis place: the origin); none = no object.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub object: Option<EnvObject>,
    /// The object's smoothness λ per vertex.
    #[serde(default)]
    pub lambda: EnvLambda,
    /// Which texture the object's lookups use.
    #[serde(default)]
    pub lookup: EnvLookup,
    /// What is behind the object.
    #[serde(default)]
    pub background: EnvBackground,
    /// Scene objects that reflect the environment (mirror-like: a chrome ball), drawn
    /// by the frame's object pass through the environment-map units.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub reflectors: Vec<Reflector>,
    /// How the voxel map is prefiltered (last: a TOML sub-table).
    #[serde(default)]
    pub prefilter: Prefilter,
}

/// How the exposure of an environment map is chosen when the scene gives none: the
/// level 255 stands for a reference radiance, exposure = 1 / reference. The thesis'
/// inputs are 8-bit images and it states no rule.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ExposureRule {
    /// The 99th percentile, weighted by solid angle, of each texel's largest channel
    /// ([`EnvMap::auto_exposure`]; the model's choice).
    #[default]
    P99SolidAngle,
    /// The 99th percentile over texels counted equally (the poles' many small texels
    /// weigh as much as the equator's).
    P99Texels,
    /// The largest channel of the brightest texel: nothing clips.
    Max,
}

impl ExposureRule {
    fn is_default(&self) -> bool {
        *self == ExposureRule::default()
    }
}

/// The weights w of eq. (9) over the input texels ω.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EnvWeighting {
    /// w ∝ ΔΩ(ω)·(t̂·ω)^Λ: each texel weighs its solid angle (the model's choice: an
    /// equirectangular map's polar texels are small).
    #[default]
    SolidAngle,
    /// w ∝ (t̂·ω)^Λ: eq. (9) as written, every texel alike.
    Uniform,
}

impl EnvWeighting {
    fn is_default(&self) -> bool {
        *self == EnvWeighting::default()
    }
}

/// The dome (pyramid level) a voxel's lobe is filtered on in the accelerated build
/// (the thesis §3.4.1: rough voxels use the reduced images; it states no rule).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EnvDomePick {
    /// The coarsest dome whose vertex spacing is ≤ ½ × the lobe's half-weight angle
    /// acos(2^(−1/Λ)) (the model's choice: the lobe well sampled).
    #[default]
    HalfWeight,
    /// The coarsest dome whose spacing is ≤ the voxel spacing ψ_voxel of eq. (12) at
    /// the voxel's |t| (the thesis read literally: a voxel is computed at the
    /// resolution it is stored at).
    VoxelSpacing,
}

impl EnvDomePick {
    fn is_default(&self) -> bool {
        *self == EnvDomePick::default()
    }
}

impl EnvironmentSection {
    /// The exposure the section's map is read at: `exposure` if given, else the one
    /// `exposure_rule` picks for `env`.
    pub fn exposure_for(&self, env: &EnvMap) -> f64 {
        match self.exposure {
            Some(e) => e,
            None => match self.exposure_rule {
                ExposureRule::P99SolidAngle => env.auto_exposure(),
                ExposureRule::P99Texels => env.percentile_exposure(false),
                ExposureRule::Max => env.max_exposure(),
            },
        }
    }
}

/// `environment.reflectors[i]`: a scene object that reflects the environment.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Reflector {
    /// Index into `objects`.
    pub object: usize,
    /// Smoothness λ ∈ [0, 1] (the thesis' λ: 1 = the sharpest lobe the map holds).
    pub lambda: f64,
    /// Fraction of the environment's radiance reflected, in [0, 1].
    pub reflectance: f64,
}

fn default_side() -> u32 {
    DEFAULT_SIDE
}

impl Default for EnvironmentSection {
    /// The pattern at the thesis' settings, no object.
    fn default() -> Self {
        EnvironmentSection {
            map: Some(BUILTIN_NAMES[0].to_string()),
            hdr: None,
            exposure: None,
            exposure_rule: ExposureRule::default(),
            weighting: EnvWeighting::default(),
            dome_pick: EnvDomePick::default(),
            side: DEFAULT_SIDE,
            object: None,
            lambda: EnvLambda::default(),
            lookup: EnvLookup::default(),
            background: EnvBackground::default(),
            reflectors: Vec::new(),
            prefilter: Prefilter::default(),
        }
    }
}

/// A path to a Radiance file: as written in the scene (what is serialised) and the
/// file it names (resolved at load).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct HdrPath {
    written: String,
    resolved: PathBuf,
}

impl HdrPath {
    /// A path taken as written (relative to the working directory).
    pub fn new(written: &str) -> Self {
        HdrPath {
            written: written.to_string(),
            resolved: PathBuf::from(written),
        }
    }

    /// The path as the scene states it.
    pub fn written(&self) -> &str {
        &self.written
    }

    /// The file to read.
    pub fn file(&self) -> &Path {
        &self.resolved
    }

    /// Resolve a relative written path against `dir` (the scene file's directory).
    pub fn resolve_against(&mut self, dir: &Path) {
        let written = Path::new(&self.written);
        self.resolved = if written.is_relative() && !self.written.trim().is_empty() {
            dir.join(written)
        } else {
            written.to_path_buf()
        };
    }
}

impl Serialize for HdrPath {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.written)
    }
}

impl<'de> Deserialize<'de> for HdrPath {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        Ok(HdrPath::new(&String::deserialize(d)?))
    }
}

/// The thesis' objects, each at its thesis place and size.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EnvObject {
    /// Radius 1 at the origin, a 48 × 24 UV sphere.
    Sphere,
    /// The Utah teapot, scale 0.3, its bounding box centred on the origin.
    Teapot,
}

impl EnvObject {
    pub fn name(self) -> &'static str {
        match self {
            EnvObject::Sphere => "sphere",
            EnvObject::Teapot => "teapot",
        }
    }
}

/// The smoothness λ: the same number in [0, 1] at every vertex, or `"nonuniform"`
/// (the thesis' settings: around the view axis on the sphere, with height on the
/// teapot).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EnvLambda {
    Uniform(f64),
    NonUniform,
}

impl Default for EnvLambda {
    /// λ = 1: the sharpest reflection (a chrome object).
    fn default() -> Self {
        EnvLambda::Uniform(1.0)
    }
}

const NONUNIFORM: &str = "nonuniform";

impl Serialize for EnvLambda {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            EnvLambda::Uniform(l) => s.serialize_f64(*l),
            EnvLambda::NonUniform => s.serialize_str(NONUNIFORM),
        }
    }
}

impl<'de> Deserialize<'de> for EnvLambda {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct LambdaVisitor;
        impl Visitor<'_> for LambdaVisitor {
            type Value = EnvLambda;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                write!(f, "a number in [0, 1] or \"{NONUNIFORM}\"")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<EnvLambda, E> {
                Ok(EnvLambda::Uniform(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<EnvLambda, E> {
                Ok(EnvLambda::Uniform(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<EnvLambda, E> {
                Ok(EnvLambda::Uniform(v as f64))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<EnvLambda, E> {
                if v == NONUNIFORM {
                    Ok(EnvLambda::NonUniform)
                } else {
                    Err(E::invalid_value(de::Unexpected::Str(v), &self))
                }
            }
        }
        d.deserialize_any(LambdaVisitor)
    }
}

/// The lookup path of the object's pixels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EnvLookup {
    /// Always the 3D voxel map (the thesis' method).
    #[default]
    Voxel3d,
    /// Elaborated: a 2D cube-map slice for a uniform λ, the 3D map otherwise.
    Auto,
}

/// What is behind the object.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EnvBackground {
    /// The environment in the pixel's view direction.
    #[default]
    Environment,
    Black,
}

/// How the voxel map is prefiltered.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum Prefilter {
    /// The thesis' accelerated build (pyramid, domes, weight table pruned at
    /// `threshold` ∈ [0, 1)).
    Accelerated {
        #[serde(default = "default_threshold")]
        threshold: f64,
    },
    /// Every voxel summed over every texel (slow: seconds to minutes at s = 128).
    Exact,
    /// The default: the faster build at the map's side ([`Prefilter::resolve`]): the
    /// accelerated one at th = [`THESIS_THRESHOLD`] up to [`AUTO_ACCELERATED_MAX_SIDE`],
    /// the exact one above, where every lobe is narrower than a texel of the input and
    /// the exact sum visits fewer samples than the dome that must resolve those lobes
    /// (docs/envmap.md, "Map side").
    #[default]
    Auto,
}

/// The largest side at which [`Prefilter::Auto`] picks the accelerated build.
pub const AUTO_ACCELERATED_MAX_SIDE: u32 = 128;

impl Prefilter {
    /// The build this prefilter means at side `side`: [`Prefilter::Auto`] resolved,
    /// the others as they are.
    pub fn resolve(self, side: u32) -> Prefilter {
        match self {
            Prefilter::Auto if side <= AUTO_ACCELERATED_MAX_SIDE => Prefilter::Accelerated {
                threshold: THESIS_THRESHOLD,
            },
            Prefilter::Auto => Prefilter::Exact,
            other => other,
        }
    }
}

fn default_threshold() -> f64 {
    THESIS_THRESHOLD
}

/// The camera of the thesis' renders: at (0, 1, 3.9) looking at the origin, y up, 36°
/// vertical field of view, near 1, far 10.
pub fn thesis_camera() -> Camera {
    Camera {
        eye: [0.0, 1.0, 3.9],
        look_at: [0.0, 0.0, 0.0],
        up: [0.0, 1.0, 0.0],
        fovy_deg: 36.0,
        near: 1.0,
        far: 10.0,
    }
}

impl EnvironmentSection {
    /// Check every field; errors name `environment.<field>`. Reads and decodes an `hdr`
    /// file (so a missing, unreadable or invalid one is refused before any work).
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.validate_fields()?;
        self.load().map(|_| ())
    }

    /// Every check that reads no file, in this order (the first error is the one
    /// reported): the map's source, the exposure, the side, the object's λ, the
    /// prefilter, the reflectors.
    fn validate_fields(&self) -> Result<(), ConfigError> {
        let f = |e: ConfigError| e.within("environment");
        self.validate_source().map_err(f)?;
        self.validate_exposure().map_err(f)?;
        self.validate_side().map_err(f)?;
        if let EnvLambda::Uniform(l) = self.lambda {
            fields::ENV_LAMBDA.real("lambda", l).map_err(f)?;
        }
        self.validate_prefilter().map_err(f)?;
        self.validate_reflectors().map_err(f)
    }

    /// Exactly one of `map` (a known built-in) and `hdr` (a non-empty path).
    fn validate_source(&self) -> Result<(), ConfigError> {
        match (&self.map, &self.hdr) {
            (Some(_), Some(_)) => Err(ConfigError::invalid(
                "hdr",
                "give either `map` (a built-in map) or `hdr` (a file), not both",
            )),
            (None, None) => Err(ConfigError::invalid(
                "map",
                &format!(
                    "give a built-in map ({}) or an `hdr` file",
                    BUILTIN_NAMES.join(", ")
                ),
            )),
            (Some(m), None) if !BUILTIN_NAMES.contains(&m.as_str()) => Err(ConfigError::invalid(
                "map",
                &format!(
                    "unknown built-in map `{m}` (known: {})",
                    BUILTIN_NAMES.join(", ")
                ),
            )),
            (None, Some(h)) if h.written().trim().is_empty() => {
                Err(ConfigError::invalid("hdr", "the path is empty"))
            }
            _ => Ok(()),
        }
    }

    /// A given `exposure` in its range, and then no `exposure_rule` (the rule picks
    /// the exposure only when none is given).
    fn validate_exposure(&self) -> Result<(), ConfigError> {
        if let Some(e) = self.exposure {
            fields::ENV_EXPOSURE.real("exposure", e)?;
            if !self.exposure_rule.is_default() {
                return Err(ConfigError::invalid(
                    "exposure_rule",
                    "applies only when no `exposure` is given (remove one of the two)",
                ));
            }
        }
        Ok(())
    }

    /// The voxel map's side: in the field table's range, a power of two, and within
    /// the limits of the units it sizes.
    fn validate_side(&self) -> Result<(), ConfigError> {
        // The range from the field table; the power of two below, with its reason.
        let (lo, hi) = fields::ENV_SIDE.bounds().unwrap_or((0.0, 0.0));
        check_range("side", self.side.into(), lo as u64, hi as u64)?;
        if !self.side.is_power_of_two() {
            return Err(ConfigError::invalid(
                "side",
                &format!(
                    "{} is not a power of two (the reflection unit's texel coordinates need one)",
                    self.side
                ),
            ));
        }
        super::limits::check_env_side(self.side)
    }

    /// The accelerated prefilter's threshold in range, and `dome_pick` only where the
    /// side resolves to the accelerated prefilter.
    fn validate_prefilter(&self) -> Result<(), ConfigError> {
        if let Prefilter::Accelerated { threshold } = self.prefilter {
            fields::PREFILTER_THRESHOLD.real("prefilter.threshold", threshold)?;
        }
        if !self.dome_pick.is_default()
            && !matches!(
                self.prefilter.resolve(self.side),
                Prefilter::Accelerated { .. }
            )
        {
            return Err(ConfigError::invalid(
                "dome_pick",
                &format!(
                    "picks the dome of the accelerated prefilter; side {} uses the exact one (set prefilter = {{ type = \"accelerated\" }} or remove dome_pick)",
                    self.side
                ),
            ));
        }
        Ok(())
    }

    /// Each reflector's λ and reflectance in range (errors name `reflectors[i]`), and
    /// reflectors only without the thesis object.
    fn validate_reflectors(&self) -> Result<(), ConfigError> {
        for (i, r) in self.reflectors.iter().enumerate() {
            let g = |e: ConfigError| e.within(&format!("reflectors[{i}]"));
            fields::REFLECTOR_LAMBDA
                .real("lambda", r.lambda)
                .map_err(g)?;
            fields::REFLECTOR_REFLECTANCE
                .real("reflectance", r.reflectance)
                .map_err(g)?;
        }
        if self.object.is_some() && !self.reflectors.is_empty() {
            return Err(ConfigError::invalid(
                "reflectors",
                "a scene draws either the thesis object (`object`) or scene objects that reflect (`reflectors`), not both",
            ));
        }
        Ok(())
    }

    /// The environment map: the built-in one, or the `hdr` file read and decoded (at
    /// most `envmap::MAX_HDR_BYTES`; regular files only). Errors name
    /// `environment.map` / `environment.hdr`, including a map the accelerated
    /// prefilter cannot take (a side not divisible by [`PYRAMID_DIVISOR`]).
    pub fn load(&self) -> Result<EnvMap, ConfigError> {
        self.validate_fields()?;
        let (field, env) = match (&self.map, &self.hdr) {
            (Some(m), _) => ("environment.map", EnvMap::builtin(m)),
            (None, Some(h)) => ("environment.hdr", EnvMap::load_hdr(h.file())),
            (None, None) => {
                return Err(ConfigError::invalid(
                    "environment.map",
                    "give a built-in map or an `hdr` file",
                ))
            }
        };
        let env = env.map_err(|e| match e {
            ConfigError::Invalid { reason, .. } => ConfigError::invalid(field, &reason),
            other => ConfigError::invalid(field, &other.to_string()),
        })?;
        let (w, h) = (env.width(), env.height());
        if matches!(
            self.prefilter.resolve(self.side),
            Prefilter::Accelerated { .. }
        ) && (w % PYRAMID_DIVISOR != 0 || h % PYRAMID_DIVISOR != 0)
        {
            return Err(ConfigError::invalid(
                field,
                &format!(
                    "the map is {w} × {h}; the accelerated prefilter's pyramid needs both \
                     divisible by {PYRAMID_DIVISOR} (or use prefilter = {{ type = \"exact\" }})"
                ),
            ));
        }
        Ok(env)
    }
}
