//! The glare section of a scene (SPEC B): light sources as the glare renderer sees
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
    /// The scene's lights and objects through the light-shafts pipeline (SPEC A).
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
    pub point_theta0_deg: f64,
    pub point_m: f64,
    /// Extended sources, eqs. (3)/(4): A·exp(−(θ/w)ⁿ) + B/(θ + θ₁)^m, θ from the rim.
    pub bloom_n: f64,
    pub bloom_m: f64,
    pub bloom_w_deg: f64,
    pub bloom_theta1_deg: f64,
    /// B = `bloom_k`·I·(age factor)·(1 + M_f)^e_mist / (1 + E₁)^e_ambient, × `glasses_bloom`
    /// with glasses; the point source's A uses the same factors.
    pub bloom_k: f64,
    pub glasses_bloom: f64,
    /// Halo, eq. (5): C·exp(−(θ − θ₁·λ/568)²/α²), C = `halo_k`·I.
    pub halo_k: f64,
    pub halo_radius_deg: f64,
    pub halo_alpha_deg: f64,
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
            point_theta0_deg: 0.13,
            point_m: 2.8,
            bloom_n: 3.0,
            bloom_m: 2.0,
            bloom_w_deg: 1.0,
            bloom_theta1_deg: 0.5,
            bloom_k: 0.3,
            glasses_bloom: 0.8,
            halo_k: 0.05,
            halo_radius_deg: 1.5,
            halo_alpha_deg: 0.225,
            flare_num_k: 1.2,
            flare_len_k_deg: 0.12,
            flare_width_k_deg: 0.012,
            flare_intensity_k: 0.03,
            flare_spread_rad: 1.0,
            flare_max_lines: 64,
            e_intensity: 0.5,
            e_glasses: 1.0,
            e_size: 1.0,
            e_ambient: 0.5,
            e_mist: 1.0,
            e_directivity: 2.0,
            e_shape: 1.0,
            size_ref_deg: 2.0,
            glasses_flare: 1.5,
            contrast: 40.0,
            chaos_a: 0.7,
            chaos_z: 1.9,
        }
    }
}

/// The glare hardware's widths (a sweep changes them).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GlareHw {
    /// Shape RAM: 2^k cells per side; entry width.
    pub shape_log2: u32,
    pub shape_bits: u32,
    /// Falloff RAM: 2^m cells; entry width.
    pub falloff_log2: u32,
    pub falloff_bits: u32,
    /// Interpolation weight bits in both RAMs.
    pub weight_bits: u32,
    /// Fraction bits of the interpolated (u, v) (the interpolator's output).
    pub coord_frac_bits: u32,
    /// Gaussian noise generator: uniform bits used.
    pub noise_bits: u32,
    /// Framebuffer bits per channel.
    pub fb_bits: u32,
    /// Clock (MHz) and parallel pixel pipes, for the throughput model.
    pub clock_mhz: f64,
    pub pipes: u32,
}

impl Default for GlareHw {
    fn default() -> Self {
        GlareHw {
            shape_log2: 7,
            shape_bits: 10,
            falloff_log2: 8,
            falloff_bits: 16,
            weight_bits: 8,
            coord_frac_bits: 10,
            noise_bits: 32,
            fb_bits: 8,
            clock_mhz: 300.0,
            pipes: 4,
        }
    }
}
