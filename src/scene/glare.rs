//! The glare section of a scene (Matsuda and Ikedo's glare renderer): light sources as the glare renderer sees
//! them, the determinants of Table 1, specular highlights for the glare conditions of
//! Table 2, the empirical forms the paper leaves open, and the hardware widths.
//!
//! Units: intensities and the ambient level are in framebuffer codes (255 = full
//! scale of the 8-bit framebuffer, so a source of 2000 is ~8× saturation); angles in
//! degrees; positions in world units, projected through the scene's camera.

use serde::{Deserialize, Serialize};

/// `[glare]`: present when the scene has glare.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GlareSection {
    /// What the glare is drawn over.
    #[serde(default)]
    pub background: Background,
    #[serde(default)]
    pub determinants: Determinants,
    #[serde(default)]
    pub sources: Vec<GlareSource>,
    #[serde(default)]
    pub highlights: Vec<Highlight>,
    /// Highlights found by the shading units on the scene's objects (objects with a
    /// specular material), tested by the glare conditions like written ones; none =
    /// only the written `highlights` (every scene before shading existed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shaded_highlights: Option<ShadedHighlights>,
    #[serde(default)]
    pub model: GlareModel,
    #[serde(default)]
    pub hw: GlareHw,
    /// Frame number t of the 1/f fluctuation (eq. 10): the chaos map runs t steps.
    #[serde(default)]
    pub frame: u32,
}

/// The picture the glare is added to.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum Background {
    /// All zero.
    #[default]
    Black,
    /// The scene's lights and objects through the light-shafts pipeline (Dobashi et al.).
    Shafts,
    /// A vertical gradient (linear RGB in [0, 1], top to bottom): a night sky.
    Sky { top: [f64; 3], bottom: [f64; 3] },
    /// A leaf canopy against the sky: dark leaves (`leaves` discs, seeded) with the
    /// sky showing through the gaps (Fig. 8).
    Canopy {
        leaves: u32,
        sky: [f64; 3],
        leaf: [f64; 3],
    },
}

/// Table 1's global determinants.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Determinants {
    /// Ambient luminance E₁ in framebuffer codes (≥ 0): bloom −, flare −; also the
    /// I_a of the glare conditions and B_l of eq. (6).
    pub ambient: f64,
    /// Age A_f in years (0 ..= 120): bloom + (Vos' age factor 1 + (A_f/62.5)⁴).
    pub age: f64,
    /// Mist M_f (≥ 0, 0 = clear; M_g of eq. 6): bloom +, flare −.
    pub mist: f64,
    /// Near-sighted glasses G: bloom −, flare +.
    pub glasses: bool,
    /// Wavelengths (nm) that the R, G and B channels stand for; the halo radius scales
    /// as λ/568 (eq. 5), so red rings lie outside blue ones.
    pub wavelengths_nm: [f64; 3],
}

impl Default for Determinants {
    fn default() -> Self {
        Determinants {
            ambient: 4.0,
            age: 30.0,
            mist: 0.0,
            glasses: false,
            wavelengths_nm: [650.0, 550.0, 450.0],
        }
    }
}

/// A light source as the glare renderer sees it (Table 1, rows 1–3).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GlareSource {
    pub kind: SourceKind,
    /// P₀, the centre.
    pub position: [f64; 3],
    /// Circle: radius. Cylindrical / elliptic: semi-major axis a. World units.
    #[serde(default)]
    pub a: f64,
    /// Cylindrical / elliptic: semi-minor axis b (the cylinder's radius).
    #[serde(default)]
    pub b: f64,
    /// Semi-minor direction N (cylindrical, elliptic).
    #[serde(default = "default_n")]
    pub n: [f64; 3],
    /// Polygon: P₁ … P_n (world; with `position` as P₀ they span the polygon).
    #[serde(default)]
    pub vertices: Vec<[f64; 3]>,
    /// I in framebuffer codes.
    pub intensity: f64,
    /// Area size in [0, 1]: the effective intensity is area size × I.
    #[serde(default = "default_one")]
    pub area_size: f64,
    /// Directivity D (the way the source faces); none = radiates equally every way.
    #[serde(default)]
    pub directivity: Option<[f64; 3]>,
    /// Colour of the source's light, linear RGB in [0, 1].
    #[serde(default = "default_white")]
    pub color: [f64; 3],
    /// Which glare components this source shows.
    #[serde(default = "default_true")]
    pub bloom: bool,
    #[serde(default = "default_true")]
    pub halo: bool,
    #[serde(default = "default_true")]
    pub flare: bool,
    /// Sunlight through leaves (eqs. 9–11): split into patches with independent
    /// 1/f chaos states.
    #[serde(default)]
    pub fluctuation: Option<Fluctuation>,
}

fn default_n() -> [f64; 3] {
    [0.0, 1.0, 0.0]
}
fn default_one() -> f64 {
    1.0
}
fn default_white() -> [f64; 3] {
    [1.0, 1.0, 1.0]
}
fn default_true() -> bool {
    true
}

/// Source types of Table 1 row 2.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SourceKind {
    /// A point: bloom after Vos, eq. (1).
    Point,
    /// A disc facing the viewer, radius `a`: eq. (3).
    Circle,
    /// A tube of half-length a and radius b along D × N: eq. (4).
    Cylindrical,
    /// An ellipse with semi-axes a, b in the plane facing D: eq. (4).
    Elliptic,
    /// A polygon P₀ … P_n: eq. (4) with the distance to the polygon.
    Polygon,
}

/// The 1/f fluctuation of eqs. (9)–(11).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Fluctuation {
    /// n patches (1 ..= 64), each a circle source with its own chaos state.
    pub patches: u32,
    /// The patches are scattered (seeded) within this radius of P₀, world units.
    pub spread: f64,
    /// Radius of each patch, world units.
    pub patch_radius: f64,
}

/// A specular highlight the shader found, tested by the glare conditions (Table 2).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Highlight {
    pub material: HighlightMaterial,
    /// The surface point and its normal.
    pub position: [f64; 3],
    pub normal: [f64; 3],
    /// The light's position and intensity I (framebuffer codes).
    pub light: [f64; 3],
    pub intensity: f64,
    /// I_s, the specular coefficient in [0, 1] (metallic).
    #[serde(default = "default_one")]
    pub specular: f64,
    /// η, the ratio of refractive indices (water), > 0.
    #[serde(default = "default_eta")]
    pub eta: f64,
    /// Radius of the highlight's source disc if it becomes a glare source, world units.
    #[serde(default = "default_highlight_radius")]
    pub radius: f64,
}

/// `[glare.shaded_highlights]`: which light's highlights the shading pass looks for.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShadedHighlights {
    /// The scene light (index into `lights`) whose highlights are sought.
    pub light: usize,
    /// I of Table 2 for that light, in framebuffer codes.
    pub intensity: f64,
    /// Radius of the glare source disc a highlight becomes, world units.
    #[serde(default = "default_highlight_radius")]
    pub radius: f64,
}

fn default_eta() -> f64 {
    1.33
}
fn default_highlight_radius() -> f64 {
    0.02
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HighlightMaterial {
    Metallic,
    Water,
}

/// The empirical constants and the forms R1 the paper leaves open (docs/glare.md).
/// R1 is a product of powers, monotone by construction: an argument that raises the
/// output (+ in Table 1) enters as x^e, one that lowers it as (1 + x)^−e, every
/// exponent e ≥ 0.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GlareModel {
    /// Point source, eq. (1): A/(θ + θ₀)^m with A = `point_a`·k·I.
    pub point_a: f64,
    /// k of the point source's A = k·I·(bloom factors)·`point_a`.
    pub point_k: f64,
    pub point_theta0_deg: f64,
    pub point_m: f64,
    /// Extended sources, eqs. (3)/(4): A·exp(−(θ/w)ⁿ) + B/(θ + θ₁)^m, θ from the rim.
    pub bloom_n: f64,
    pub bloom_m: f64,
    /// w, the angular scale of exp(−(θ/w)ⁿ): the model's 0.3°; eqs. (3)/(4) write
    /// exp(−θ³) with none, i.e. 1° read literally (docs/assumptions.md). Also
    /// accepted as `bloom_angle_scale_deg`.
    #[serde(alias = "bloom_angle_scale_deg")]
    pub bloom_w_deg: f64,
    pub bloom_theta1_deg: f64,
    /// B = `bloom_k`·I·(age factor)·(1 + M_f)^e_mist / (1 + E₁)^e_ambient, × `glasses_bloom`
    /// with glasses; the point source's A uses the same factors.
    pub bloom_k: f64,
    pub glasses_bloom: f64,
    /// Halo, eq. (5): C·exp(−(θ − θ₁·λ/568)²/α²), C = `halo_k`·I (or 10·E₁, see
    /// `halo_amplitude`).
    pub halo_k: f64,
    /// θ₁ as the model reads "ring diameter 3°": half of it (see `halo_radius`).
    pub halo_radius_deg: f64,
    pub halo_alpha_deg: f64,
    /// Which reading gives the halo's amplitude C (docs/assumptions.md).
    pub halo_amplitude: HaloAmplitude,
    /// Which reading gives the halo's ring radius θ₁ (docs/assumptions.md).
    pub halo_radius: HaloRadius,
    /// How far out the bloom profiles are drawn (docs/assumptions.md).
    pub bloom_range: BloomRange,
    /// How a water highlight's `eta` is read by the glare condition (Table 2).
    pub water_eta: WaterEta,
    /// Flare lines, eq. (6).
    pub flare_num_k: f64,
    pub flare_len_k_deg: f64,
    pub flare_width_k_deg: f64,
    pub flare_intensity_k: f64,
    /// Angular spread (radians) of a circle source's lines: ang = 1 of eq. (6).
    pub flare_spread_rad: f64,
    /// Most flare lines per source (the noise generator's budget).
    pub flare_max_lines: u32,
    /// Exponents of R1 (all ≥ 0).
    pub e_intensity: f64,
    pub e_glasses: f64,
    pub e_size: f64,
    pub e_ambient: f64,
    pub e_mist: f64,
    pub e_directivity: f64,
    pub e_shape: f64,
    /// Reference size S_ref (degrees) in (1 + S/S_ref).
    pub size_ref_deg: f64,
    /// Glasses factor g on the flare when G is on (≥ 1).
    pub glasses_flare: f64,
    /// Contrast threshold of Table 2.
    pub contrast: f64,
    /// The chaos map of eq. (9): a and z; patches step once per frame.
    pub chaos_a: f64,
    pub chaos_z: f64,
}

impl Default for GlareModel {
    fn default() -> Self {
        GlareModel {
            point_a: 29.0,
            point_k: 0.03,
            point_theta0_deg: 0.13,
            point_m: 2.8,
            bloom_n: 3.0,
            bloom_m: 2.0,
            bloom_w_deg: 0.3,
            bloom_theta1_deg: 0.5,
            bloom_k: 1.0,
            glasses_bloom: 0.8,
            halo_k: 0.05,
            halo_radius_deg: 1.5,
            halo_alpha_deg: 0.225,
            halo_amplitude: HaloAmplitude::Intensity,
            halo_radius: HaloRadius::DiameterHalf,
            bloom_range: BloomRange::Cutoff,
            water_eta: WaterEta::MediaOverAir,
            flare_num_k: 1.2,
            flare_len_k_deg: 0.3,
            flare_width_k_deg: 0.004,
            flare_intensity_k: 0.05,
            flare_spread_rad: 1.0,
            flare_max_lines: 64,
            e_intensity: 0.5,
            e_glasses: 1.0,
            e_size: 1.0,
            e_ambient: 0.5,
            e_mist: 1.0,
            e_directivity: 2.0,
            e_shape: 0.5,
            size_ref_deg: 2.0,
            glasses_flare: 1.5,
            contrast: 40.0,
            chaos_a: 0.8,
            chaos_z: 1.95,
        }
    }
}

/// The halo's amplitude C in eq. (2)/(5). The paper: "A is about ten times the
/// ambient light"; the model: proportional to the source.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HaloAmplitude {
    /// C = `halo_k` · I_e (the model's choice: a brighter source, a brighter ring).
    #[default]
    Intensity,
    /// C = 10 · E₁ (the paper's sentence read literally; no dependence on the source).
    AmbientX10,
}

/// The halo's ring radius θ₁ (at 568 nm).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HaloRadius {
    /// θ₁ = `halo_radius_deg` (1.5°: half of the "diameter 3°" ring).
    #[default]
    DiameterHalf,
    /// θ₁ = 2 · `halo_radius_deg` (3°): Spencer et al.'s formula, from which the paper
    /// takes α, puts the ring at radius 3° · λ/568 nm.
    Spencer,
}

/// How far out the bloom profiles (eqs. (1), (3), (4)) are drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum BloomRange {
    /// Out to where the profile falls below half a level (the model's choice; about
    /// 14° for the built-in sources).
    #[default]
    #[serde(rename = "cutoff_14")]
    Cutoff,
    /// Zero beyond θ = 8°: eq. (1) is stated for θ < 8° only.
    #[serde(rename = "eq1_8deg")]
    Eq1EightDeg,
}

impl BloomRange {
    /// The largest θ (degrees) at which bloom is drawn.
    pub fn limit_deg(self) -> f64 {
        match self {
            BloomRange::Cutoff => f64::INFINITY,
            BloomRange::Eq1EightDeg => 8.0,
        }
    }
}

/// How a water highlight's η (`highlights[i].eta`, 1.33 by default) enters Table 2's
/// total-internal-reflection test 1 − η²(1 − cos²θ) < 0.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WaterEta {
    /// η as written (n_water / n_air = 1.33): the only reading under which water
    /// can make glare (the model's choice).
    #[default]
    MediaOverAir,
    /// η = 1 / `eta` (Table 2's "1/media" read literally: 0.75 for water; the TIR
    /// test never passes, so water never makes glare).
    AirOverMedia,
}

impl GlareModel {
    /// The halo ring's radius θ₁ at 568 nm (degrees) under [`GlareModel::halo_radius`].
    pub fn halo_ring_radius_deg(&self) -> f64 {
        match self.halo_radius {
            HaloRadius::DiameterHalf => self.halo_radius_deg,
            HaloRadius::Spencer => 2.0 * self.halo_radius_deg,
        }
    }

    /// The halo amplitude C for a source of effective intensity `ie` and ambient E₁.
    pub fn halo_amplitude_for(&self, ie: f64, ambient: f64) -> f64 {
        match self.halo_amplitude {
            HaloAmplitude::Intensity => self.halo_k * ie,
            HaloAmplitude::AmbientX10 => 10.0 * ambient,
        }
    }

    /// The η the glare condition uses for a water highlight written with `eta`.
    pub fn water_eta_for(&self, eta: f64) -> f64 {
        match self.water_eta {
            WaterEta::MediaOverAir => eta,
            WaterEta::AirOverMedia => 1.0 / eta,
        }
    }
}

pub use super::glare_hw::GlareHw;

// ---------------------------------------------------------------------------------
// Validation: every error names its field (`glare.sources[1].a`).

use super::fields;
use super::fields::{direction, point};
use rtl_model::ConfigError;

pub use super::bounds::GLARE_INTENSITY_MAX;

impl GlareSection {
    /// Check every field; errors name `glare.<field>`.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.validate_inner().map_err(|e| e.within("glare"))
    }

    fn validate_inner(&self) -> Result<(), ConfigError> {
        match &self.background {
            Background::Black | Background::Shafts => {}
            Background::Sky { top, bottom } => {
                for k in 0..3 {
                    fields::GLARE_BACKGROUND_TOP.real(&format!("background.top[{k}]"), top[k])?;
                    fields::GLARE_BACKGROUND_BOTTOM
                        .real(&format!("background.bottom[{k}]"), bottom[k])?;
                }
            }
            Background::Canopy { leaves, sky, leaf } => {
                fields::GLARE_BACKGROUND_LEAVES.int("background.leaves", (*leaves).into())?;
                for k in 0..3 {
                    fields::GLARE_BACKGROUND_SKY.real(&format!("background.sky[{k}]"), sky[k])?;
                    fields::GLARE_BACKGROUND_LEAF
                        .real(&format!("background.leaf[{k}]"), leaf[k])?;
                }
            }
        }
        let d = &self.determinants;
        fields::GLARE_AMBIENT.real("determinants.ambient", d.ambient)?;
        fields::GLARE_AGE.real("determinants.age", d.age)?;
        fields::GLARE_MIST.real("determinants.mist", d.mist)?;
        for k in 0..3 {
            fields::GLARE_WAVELENGTHS.real(
                &format!("determinants.wavelengths_nm[{k}]"),
                d.wavelengths_nm[k],
            )?;
        }
        for (i, s) in self.sources.iter().enumerate() {
            validate_source(s).map_err(|e| e.within(&format!("sources[{i}]")))?;
        }
        for (i, h) in self.highlights.iter().enumerate() {
            validate_highlight(h).map_err(|e| e.within(&format!("highlights[{i}]")))?;
            if h.material == HighlightMaterial::Water {
                // The η the condition unit will hold under `model.water_eta`.
                check_eta(self.model.water_eta_for(h.eta))
                    .map_err(|e| e.within(&format!("highlights[{i}]")))?;
            }
        }
        if let Some(sh) = &self.shaded_highlights {
            fields::SHADED_INTENSITY.real("shaded_highlights.intensity", sh.intensity)?;
            fields::SHADED_RADIUS.real("shaded_highlights.radius", sh.radius)?;
        }
        validate_model(&self.model).map_err(|e| e.within("model"))?;
        let hw = &self.hw;
        // The widths go into the units' configs: checked by building those
        // (their own ranges, errors mapped onto `hw.<field>`).
        super::glare_hw::check_glare(hw)?;
        fields::HW_CLOCK_MHZ.real("hw.clock_mhz", hw.clock_mhz)?;
        fields::HW_PIPES.int("hw.pipes", hw.pipes.into())?;
        fields::GLARE_FRAME.int("frame", self.frame.into())
    }
}

fn validate_source(s: &GlareSource) -> Result<(), ConfigError> {
    point("position", &s.position)?;
    fields::SOURCE_INTENSITY.real("intensity", s.intensity)?;
    fields::SOURCE_AREA_SIZE.real("area_size", s.area_size)?;
    for k in 0..3 {
        fields::SOURCE_COLOR.real(&format!("color[{k}]"), s.color[k])?;
    }
    if let Some(dv) = &s.directivity {
        direction("directivity", dv)?;
    }
    // a, b and n are checked whatever the kind: a kind that ignores them must not
    // carry a NaN or an out-of-range value through the scene (it would not survive a
    // write and read back: NaN ≠ NaN).
    fields::SOURCE_A.real("a", s.a)?;
    fields::SOURCE_B.real("b", s.b)?;
    point("n", &s.n)?;
    match s.kind {
        SourceKind::Point | SourceKind::Circle => {}
        SourceKind::Cylindrical | SourceKind::Elliptic => {
            if s.b > s.a {
                return Err(ConfigError::invalid(
                    "b",
                    &format!(
                        "the semi-minor axis b = {} exceeds the semi-major axis a = {}",
                        s.b, s.a
                    ),
                ));
            }
            direction("n", &s.n)?;
        }
        SourceKind::Polygon => {
            if s.vertices.len() < 2 || s.vertices.len() > 64 {
                return Err(ConfigError::invalid(
                    "vertices",
                    &format!(
                        "a polygon needs 2 ..= 64 vertices besides position, got {}",
                        s.vertices.len()
                    ),
                ));
            }
            for (k, v) in s.vertices.iter().enumerate() {
                point(&format!("vertices[{k}]"), v)?;
            }
        }
    }
    if let Some(f) = &s.fluctuation {
        fields::FLUCTUATION_PATCHES.int("fluctuation.patches", f.patches.into())?;
        fields::FLUCTUATION_SPREAD.real("fluctuation.spread", f.spread)?;
        fields::FLUCTUATION_PATCH_RADIUS.real("fluctuation.patch_radius", f.patch_radius)?;
    }
    Ok(())
}

fn validate_highlight(h: &Highlight) -> Result<(), ConfigError> {
    point("position", &h.position)?;
    direction("normal", &h.normal)?;
    point("light", &h.light)?;
    fields::HIGHLIGHT_INTENSITY.real("intensity", h.intensity)?;
    fields::HIGHLIGHT_SPECULAR.real("specular", h.specular)?;
    fields::HIGHLIGHT_ETA.real("eta", h.eta)?;
    check_eta(h.eta)?;
    fields::HIGHLIGHT_RADIUS.real("radius", h.radius)
}

/// The glare-condition unit holds η in a fixed-point format: its own constructor
/// says what fits (one source of limits), refused here under the scene's name.
fn check_eta(eta: f64) -> Result<(), ConfigError> {
    rtl_model::units::glare_condition::GlareConditionConfig {
        eta,
        ..Default::default()
    }
    .build()
    .map_err(|e| match e {
        ConfigError::OutOfRange {
            value, min, max, ..
        } => ConfigError::out_of_range("eta", value, min, max),
        other => ConfigError::invalid("eta", &other.to_string()),
    })?;
    Ok(())
}

fn validate_model(m: &GlareModel) -> Result<(), ConfigError> {
    fields::POINT_A.real("point_a", m.point_a)?;
    fields::POINT_K.real("point_k", m.point_k)?;
    fields::POINT_THETA0_DEG.real("point_theta0_deg", m.point_theta0_deg)?;
    fields::POINT_M.real("point_m", m.point_m)?;
    fields::BLOOM_N.real("bloom_n", m.bloom_n)?;
    fields::BLOOM_M.real("bloom_m", m.bloom_m)?;
    fields::BLOOM_W_DEG.real("bloom_w_deg", m.bloom_w_deg)?;
    fields::BLOOM_THETA1_DEG.real("bloom_theta1_deg", m.bloom_theta1_deg)?;
    fields::BLOOM_K.real("bloom_k", m.bloom_k)?;
    fields::GLASSES_BLOOM.real("glasses_bloom", m.glasses_bloom)?;
    fields::HALO_K.real("halo_k", m.halo_k)?;
    fields::HALO_RADIUS_DEG.real("halo_radius_deg", m.halo_radius_deg)?;
    fields::HALO_ALPHA_DEG.real("halo_alpha_deg", m.halo_alpha_deg)?;
    fields::FLARE_NUM_K.real("flare_num_k", m.flare_num_k)?;
    fields::FLARE_LEN_K_DEG.real("flare_len_k_deg", m.flare_len_k_deg)?;
    fields::FLARE_WIDTH_K_DEG.real("flare_width_k_deg", m.flare_width_k_deg)?;
    fields::FLARE_INTENSITY_K.real("flare_intensity_k", m.flare_intensity_k)?;
    fields::FLARE_SPREAD_RAD.real("flare_spread_rad", m.flare_spread_rad)?;
    fields::FLARE_MAX_LINES.int("flare_max_lines", m.flare_max_lines.into())?;
    for (f, e) in [
        (fields::E_INTENSITY, m.e_intensity),
        (fields::E_GLASSES, m.e_glasses),
        (fields::E_SIZE, m.e_size),
        (fields::E_AMBIENT, m.e_ambient),
        (fields::E_MIST, m.e_mist),
        (fields::E_DIRECTIVITY, m.e_directivity),
        (fields::E_SHAPE, m.e_shape),
    ] {
        // Monotone as Table 1 says: the sign of each argument's effect is fixed by
        // where the form puts it; a negative exponent would flip it.
        let name = f.path.rsplit('.').next().unwrap_or(f.path);
        f.real(name, e)?;
    }
    fields::SIZE_REF_DEG.real("size_ref_deg", m.size_ref_deg)?;
    fields::GLASSES_FLARE.real("glasses_flare", m.glasses_flare)?;
    fields::CONTRAST.real("contrast", m.contrast)?;
    fields::CHAOS_A.real("chaos_a", m.chaos_a)?;
    fields::CHAOS_Z.real("chaos_z", m.chaos_z)
}
