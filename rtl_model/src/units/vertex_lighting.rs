//! vertex_lighting — OpenGL 1.x fixed-function lighting per vertex (GL 1.x spec
//! §2.13.1), GeForce 256 T&L style, in a configurable float format
//! ([`FloatFormat`]: E exponent bits, M mantissa bits; GeForce 256 = IEEE single 8/23).
//!
//! Loaded state (the host writes it like registers, see [`LightingSetup`]): the
//! material (emission e_m, ambient a_m, diffuse d_m with alpha, specular s_m,
//! shininess s_rm), the scene ambient a_s and up to 8 lights (position P_pli with w,
//! ambient/diffuse/specular colours, spot direction/exponent/cutoff, constant/linear/
//! quadratic attenuation). One input word = one vertex: eye-space position P and
//! normal n as format words. Output: RGBA unorms of `color_bits` for the interpolator.
//!
//! colour = e_m + a_m·a_s + Σ_i att_i·spot_i·(a_m·a_i + max(N·L_i, 0)·d_m·d_i
//!          + f_i·max(N·h_i, 0)^s_rm·s_m·s_i), f_i = 0 if N·L_i ≤ 0 else 1,
//! clamped to [0, 1] (each clamp counted), alpha = d_m's alpha.
//! * N = n·rsq(n·n) with GL_NORMALIZE (`normalize`), else n as given. A zero-length
//!   normal: rsq(0) saturates to max finite (counted) and N = 0·max = 0, so the vertex
//!   gets e_m + a_m·a_s + Σ att·spot·a_m·a_i (no diffuse, no specular), never NaN.
//! * Local light (w ≠ 0, position xyz/w at load): VP = P_pli − P, d² = VP·VP,
//!   r = rsq(d²), L = VP·r, d = d²·r, att = rcp(k_c + k_l·d + k_q·d²). A light at the
//!   vertex (d² = 0) gives L = 0, d = 0. Directional light (w = 0): L = the direction
//!   normalised at load, att = 1 (GL: attenuation only for local lights).
//!   k_c = k_l = k_q = 0 is allowed: rcp(0) saturates (counted) to max finite.
//! * Spot (cutoff ≠ 180°): c = −L·ŝ (ŝ normalised at load); spot = 0 if c < cos(cutoff)
//!   (cos computed at load), else pow(c, spot exponent); cutoff = 180° → spot = 1.
//! * h = normalize(L + V), V = normalize(−P) for a local viewer (P = 0 → V = 0) or
//!   (0, 0, 1) for an infinite viewer; spec = pow(max(N·h, 0), s_rm) only when N·L > 0.
//! * Products a_m·a_i, d_m·d_i, s_m·s_i and e_m + a_m·a_s are formed at load (the
//!   driver's precomputation, f64 then one rounding to the format).
//!
//! * NV2A modes (config): `normalize_directional` off keeps a directional light's
//!   vector as the host wrote it (N·L scales with its length, h = normalize(L + V) of
//!   that vector); `light_control` gives the two-colour output and its switches
//!   (lighting off passes the vertex colours through, specular enable, separate
//!   specular, secondary alpha from the vertex), see [`LightControl`]. The defaults keep
//!   GL's single colour; with `light_control` the diffuse and specular sums are kept
//!   apart (3 more multiplies per light, 3 more adds per vertex). `specular_curve`
//!   replaces pow(N·h, s) by the NV2A's curve of its SET_SPECULAR_PARAMS registers,
//!   (x + k0)·rcp(k1·x + k2), see [`SpecularCurve`] (per light 1 more multiply, 2 more
//!   adds, one RCP instead of LOG + EXP).
//!
//! The datapath's operation order, each op rounded once (dot3(a, b) =
//! (a₀b₀ + a₁b₁) + a₂b₂): see [`VertexLighting::light`]; tests/vertex_lighting.rs
//! derives its error bound from exactly this order.
//!
//! Allowed ranges: shininess and spot exponent 0 ..= 10⁴ (GL limits both to 128; the
//! model accepts more for sweeps), cutoff 0 ..= 90 or 180, attenuation ≥ 0, colours
//! ≥ 0 and finite (negative "dark lights" are not modelled), at most 8 lights.
//!
//! Timing (derivation in docs/units.md): FP_MULTIPLIERS = 6 multipliers, FP_ADDERS = 4
//! adders and one special-function unit (RSQ, RCP, LOG, EXP), each issuing one op a
//! clock, pipelined; every enabled light takes the worst case's issues whatever its
//! kind (a fixed schedule): per light 36 multiplies, 28 adds (incl. the spot compare)
//! and 7 specials (RSQ d², RCP attenuation, LOG + EXP spot, RSQ H, LOG + EXP
//! specular); GL_NORMALIZE and a local viewer 6 multiplies, 2 adds, 1 special each.
//! II = max(1, ⌈muls/6⌉, ⌈adds/4⌉, specials). One light with GL_NORMALIZE and an
//! infinite viewer: max(7, 8, 8) = 8 clocks, 120 MHz / 8 = 15 M vertices/s, GeForce
//! 256's quoted T&L rate (the calibration; 6 and 4 are the fewest lanes that meet it).
//! Latency = II + 6 (multiply 2, add 2, clamp/convert 1, output register 1).

use crate::cost::{prim, Cells, Cost};
use crate::counters::Counters;
use crate::error::{check_finite, check_range, ConfigError};
use crate::float_format::{FloatFormat, Fp};
pub use crate::lighting_state::{Light, LightingSetup, Material};
use crate::unit::{Signal, Timing, Unit, Width};
use crate::wire::bits_for;
use serde::{Deserialize, Serialize};

/// Most lights GL 1.x guarantees (GL_MAX_LIGHTS ≥ 8).
pub const MAX_LIGHTS: usize = 8;
/// Largest shininess / spot exponent the model accepts (GL: 128).
pub const MAX_EXPONENT: f64 = 1.0e4;
/// FP multiplier and adder lanes (the fewest that meet the 8-clock calibration).
pub const FP_MULTIPLIERS: u32 = 6;
/// FP adder lanes, each issuing one add a clock (with [`FP_MULTIPLIERS`], the fewest
/// that meet the 8-clock calibration).
pub const FP_ADDERS: u32 = 4;
/// Issues per light on the schedule's worst case (local light, spot, specular):
/// multiplies 9 (local: d², L, d, k_l·d, k_q·d²) + 4 (spot dot3, s·log) + 3 (N·L) +
/// 10 (H·H, h, N·h, s·log) + 1 (att·spot) + 9 (3 channels × 3) = 36; adds 7 + 3 + 2 +
/// 7 + 9 = 28; specials 7 (RSQ d², RCP att, LOG + EXP spot, RSQ H, LOG + EXP spec).
pub const ISSUES_PER_LIGHT: Issues = Issues {
    muls: 36,
    adds: 28,
    specials: 7,
};
/// GL_NORMALIZE or a local viewer: dot3, RSQ, 3 multiplies.
pub const ISSUES_PER_NORMALISE: Issues = Issues {
    muls: 6,
    adds: 2,
    specials: 1,
};

/// Operation issues per vertex on each resource.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Issues {
    /// Multiplies.
    pub muls: u32,
    /// Adds (including the spot compare).
    pub adds: u32,
    /// Special-function operations (RSQ, RCP, LOG, EXP).
    pub specials: u32,
}

/// The unit's widths and switches.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct VertexLightingConfig {
    /// The arithmetic's float format.
    pub format: FloatFormat,
    /// Output unorm width per channel, 1 ..= 16.
    pub color_bits: u32,
    /// GL_NORMALIZE: normalise n in the datapath.
    pub normalize: bool,
    /// GL_LIGHT_MODEL_LOCAL_VIEWER: V = normalize(−P) instead of (0, 0, 1).
    pub local_viewer: bool,
    /// Normalise a directional light's vector at load (GL: the driver does). Off, the
    /// register holds the vector as the host wrote it, as the NV2A's
    /// NV097_SET_LIGHT_INFINITE_DIRECTION does: N·L then scales with its length (the
    /// Specular captures of nxdk_pgraph_tests show it). Default on.
    #[serde(default = "yes")]
    pub normalize_directional: bool,
    /// The NV2A's two-colour output and its light-control switches ([`LightControl`]).
    /// None (the default): GL's single colour, specular summed into it, as before.
    #[serde(default)]
    pub light_control: Option<LightControl>,
    /// The specular curve: GL's pow(N·h, shininess) (the default) or the NV2A's
    /// rational curve of its SET_SPECULAR_PARAMS registers ([`SpecularCurve`]).
    #[serde(default)]
    pub specular_curve: SpecularCurve,
}

/// How the unit turns N·h into the specular factor.
///
/// The NV2A (NV20 T&L) has no pow for the specular term: the host writes six
/// coefficients (NV097_SET_SPECULAR_PARAMS, IEEE single words), which the XDK's Direct3D
/// driver derives from the material's power (the derivation, reverse-engineered from a
/// retail XBE, is in the public xgu library, github.com/dracc/xgu, `xgux.h`; the xemu
/// emulator inverts it to a power, `hw/xbox/nv2a/pgraph/pgraph.c`). For the first
/// triplet (k0, k1, k2) the driver keeps k2 = 1 + k0 − k1, so that the curve
/// f(x) = (x + k0)/(k1·x + k2) is 1 at x = 1; f vanishes at x = −k0 and its denominator
/// at x = −k2/k1 (> 1). That f is the chip's curve is read from the CC0 captures of
/// nxdk_pgraph_tests' Specular suite: `NonUnitNormal` (power 125: k0 = −0.972162,
/// −k2/k1 = 1.00868) lights no pixel with normals of length 0.972 and lights the
/// centre at 0.973, goes dark again between 1.008 and 1.009 — the zeros of the
/// numerator and of the denominator; and the ControlFlags quads ("Pow 16") come out
/// exactly with it (docs/conformance.md). The second triplet (the driver's curve for
/// half the power) is not used by this model: nothing in the captures modelled so far
/// depends on it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum SpecularCurve {
    /// GL: max(N·h, 0)^shininess (the material's shininess).
    #[default]
    Power,
    /// The NV2A: f = (x + k0)·rcp(k1·x + k2) with x = max(N·h, 0), 0 unless both the
    /// numerator and the denominator are positive (an x past the denominator's zero
    /// gives 0, as the captures show). `params` are the six SET_SPECULAR_PARAMS words
    /// as the host wrote them (IEEE single bits); k0..k2 = params[0..3] are loaded into
    /// the format (one rounding each), the shininess is not used.
    Nv2aParams {
        /// The six SET_SPECULAR_PARAMS words, IEEE single bit patterns (k0, k1, k2 of
        /// the first triplet, then the unused second triplet).
        params: [u32; 6],
    },
}

impl SpecularCurve {
    /// The NV2A curve from the host's six floats (rounded to IEEE single, as the host
    /// pushes them).
    pub fn nv2a(params: [f32; 6]) -> Self {
        SpecularCurve::Nv2aParams {
            params: params.map(f32::to_bits),
        }
    }

    /// (k0, k1, k2) as f64 (the first triplet), or None for `Power`.
    pub fn coefficients(&self) -> Option<[f64; 3]> {
        match self {
            SpecularCurve::Power => None,
            SpecularCurve::Nv2aParams { params } => {
                Some([0, 1, 2].map(|k| f32::from_bits(params[k]) as f64))
            }
        }
    }
}

fn yes() -> bool {
    true
}

/// The NV2A's lighting switches, as its registers name them (nv_regs.h of pbkit;
/// behaviour read from the CC0 Specular captures of github.com/abaire/
/// nxdk_pgraph_tests_golden_results, the ControlFlags tests): the unit then outputs a
/// primary (diffuse) and a secondary (specular) colour per vertex.
/// * `lighting` false (SET_LIGHTING_ENABLE = 0): primary = the vertex's diffuse colour,
///   secondary RGB = the vertex's specular colour (passed through).
/// * lighting on: the specular sum Σ k·spec·s goes to the secondary colour only when
///   `specular_enable` and `separate_specular` are both set; otherwise it is added to
///   the primary and the secondary RGB is the vertex's specular colour (passed through).
///   Primary alpha = the material's diffuse alpha.
/// * `specular_enable` false (SET_SPECULAR_ENABLE = 0): secondary = (0, 0, 0, 1).
/// * else the secondary alpha is the vertex's specular alpha with
///   `specular_alpha_from_vertex` (SET_LIGHT_CONTROL ALPHA_FROM_MATERIAL_SPECULAR), 1
///   without.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct LightControl {
    /// SET_LIGHTING_ENABLE: light the vertex (true) or pass its colours through (false).
    pub lighting: bool,
    /// SET_SPECULAR_ENABLE: compute the specular term; off, the secondary colour is
    /// (0, 0, 0, 1).
    pub specular_enable: bool,
    /// Send the specular sum to the secondary colour (with `specular_enable`) instead of
    /// adding it to the primary.
    pub separate_specular: bool,
    /// SET_LIGHT_CONTROL ALPHA_FROM_MATERIAL_SPECULAR: the secondary alpha is the vertex's
    /// specular alpha; off, 1.
    pub specular_alpha_from_vertex: bool,
}

impl Default for LightControl {
    fn default() -> Self {
        LightControl {
            lighting: true,
            specular_enable: true,
            separate_specular: true,
            specular_alpha_from_vertex: true,
        }
    }
}

impl Default for VertexLightingConfig {
    fn default() -> Self {
        Self::geforce()
    }
}

impl VertexLightingConfig {
    /// GeForce 256: IEEE single (nearest-even, subnormals flushed), 8-bit colours,
    /// GL_NORMALIZE on, infinite viewer (GL's default).
    pub fn geforce() -> Self {
        VertexLightingConfig {
            format: FloatFormat::IEEE_SINGLE,
            color_bits: 8,
            normalize: true,
            local_viewer: false,
            normalize_directional: true,
            light_control: None,
            specular_curve: SpecularCurve::Power,
        }
    }

    /// The same with another exponent/mantissa width.
    pub fn with_format(self, exp_bits: u32, mant_bits: u32) -> Self {
        VertexLightingConfig {
            format: FloatFormat {
                exp_bits,
                mant_bits,
                ..self.format
            },
            ..self
        }
    }
}

/// One vertex: eye-space position and normal as format words; with
/// [`LightControl`], also its diffuse and specular colours (RGBA unorms of
/// `color_bits`, what the passthroughs forward; ignored without it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct VertexLightingIn {
    /// Eye-space position P (x, y, z), words of `format`.
    pub position: [Fp; 3],
    /// Eye-space normal N (x, y, z), words of `format`; normalised in the datapath when
    /// `normalize` is set.
    pub normal: [Fp; 3],
    /// The vertex's diffuse colour, RGBA unorms of `color_bits` (read only with
    /// [`LightControl`]).
    pub diffuse: [u32; 4],
    /// The vertex's specular colour, RGBA unorms of `color_bits` (read only with
    /// [`LightControl`]).
    pub specular: [u32; 4],
}

/// The lit colour: RGBA unorms of `color_bits`; with [`LightControl`], `rgba` is the
/// primary colour and `secondary` the specular one (all zero without it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct VertexLightingOut {
    /// The lit colour (the primary colour with [`LightControl`]), RGBA unorms of
    /// `color_bits`.
    pub rgba: [u32; 4],
    /// The secondary (specular) colour with [`LightControl`], RGBA unorms of `color_bits`;
    /// all zero without it.
    pub secondary: [u32; 4],
}

/// A spot light's loaded registers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SpotRegs {
    /// ŝ, unit.
    pub direction: [Fp; 3],
    /// cos of GL_SPOT_CUTOFF: the spot factor is 0 where −L·ŝ is below it.
    pub cos_cutoff: Fp,
    /// GL_SPOT_EXPONENT.
    pub exponent: Fp,
}

/// One light's loaded registers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LightRegs {
    /// Local: position xyz/w; directional: unit direction toward the light.
    pub local: bool,
    /// xyz/w of a local light, or the direction toward a directional light (unit unless
    /// `normalize_directional` is off).
    pub vector: [Fp; 3],
    /// Attenuation coefficients (constant, linear, quadratic); used for local lights.
    pub attenuation: [Fp; 3],
    /// The spot registers; `None` when the cutoff is 180 (no spot).
    pub spot: Option<SpotRegs>,
    /// a_m·a_i, d_m·d_i, s_m·s_i.
    pub ambient: [Fp; 3],
    /// Diffuse product d_m·d_i, RGB.
    pub diffuse: [Fp; 3],
    /// Specular product s_m·s_i, RGB.
    pub specular: [Fp; 3],
}

/// The validated unit with its loaded lighting state.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VertexLighting {
    cfg: VertexLightingConfig,
    lights: Vec<LightRegs>,
    /// e_m + a_m·a_s.
    base: [Fp; 3],
    shininess: Fp,
    /// k0, k1, k2 of [`SpecularCurve::Nv2aParams`] (None: pow).
    curve: Option<[Fp; 3]>,
    alpha: u32,
    load_counters: Counters,
}

fn check_colour(field: &str, c: &[f64]) -> Result<(), ConfigError> {
    for &v in c {
        let v = check_finite(field, v)?;
        if v < 0.0 {
            return Err(ConfigError::out_of_range(field, v, 0.0, f64::MAX));
        }
    }
    Ok(())
}

fn unit3(field: &str, v: [f64; 3]) -> Result<[f64; 3], ConfigError> {
    for &c in &v {
        check_finite(field, c)?;
    }
    let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if len == 0.0 || !len.is_finite() {
        return Err(ConfigError::invalid(
            field,
            "must be a non-zero finite vector",
        ));
    }
    Ok(v.map(|c| c / len))
}

impl VertexLighting {
    /// Validate the config and load the lighting state (host edge: f64 → format, one
    /// rounding per register). Errors name `vertex_lighting.<field>`.
    pub fn new(cfg: VertexLightingConfig, setup: &LightingSetup) -> Result<Self, ConfigError> {
        let f = |n: &str| format!("vertex_lighting.{n}");
        cfg.format.validate(&f("format"))?;
        check_range(&f("color_bits"), cfg.color_bits as u64, 1, 16)?;
        check_range(
            &f("lights"),
            setup.lights.len() as u64,
            0,
            MAX_LIGHTS as u64,
        )?;
        let fmt = cfg.format;
        let mut ctr = Counters::default();
        let m = &setup.material;
        check_colour(&f("material.emission"), &m.emission)?;
        check_colour(&f("material.ambient"), &m.ambient)?;
        check_colour(&f("material.diffuse"), &m.diffuse)?;
        check_colour(&f("material.specular"), &m.specular)?;
        check_colour(&f("scene_ambient"), &setup.scene_ambient)?;
        let shin = check_finite(&f("material.shininess"), m.shininess)?;
        if !(0.0..=MAX_EXPONENT).contains(&shin) {
            return Err(ConfigError::out_of_range(
                &f("material.shininess"),
                shin,
                0.0,
                MAX_EXPONENT,
            ));
        }
        let word = |field: &str, v: f64, ctr: &mut Counters| fmt.from_f64(field, v, ctr);
        let mut base = [Fp(0); 3];
        for (c, b) in base.iter_mut().enumerate() {
            *b = word(
                &f("material.emission"),
                m.emission[c] + m.ambient[c] * setup.scene_ambient[c],
                &mut ctr,
            )?;
        }
        let shininess = word(&f("material.shininess"), shin, &mut ctr)?;
        let curve = match cfg.specular_curve.coefficients() {
            None => None,
            Some(k) => {
                let mut w = [Fp(0); 3];
                for (i, c) in k.iter().enumerate() {
                    let v = check_finite(&f("specular_curve.params"), *c)?;
                    w[i] = word(&f("specular_curve.params"), v, &mut ctr)?;
                }
                Some(w)
            }
        };
        let alpha = fmt.to_unorm(
            word(&f("material.diffuse"), m.diffuse[3], &mut ctr)?,
            cfg.color_bits,
            &mut ctr,
        );
        let mut lights = Vec::with_capacity(setup.lights.len());
        for (i, l) in setup.lights.iter().enumerate() {
            let lf = |n: &str| f(&format!("lights[{i}].{n}"));
            check_colour(&lf("ambient"), &l.ambient)?;
            check_colour(&lf("diffuse"), &l.diffuse)?;
            check_colour(&lf("specular"), &l.specular)?;
            check_colour(&lf("attenuation"), &l.attenuation)?;
            for &p in &l.position {
                check_finite(&lf("position"), p)?;
            }
            let w = l.position[3];
            let local = w != 0.0;
            let v = if local {
                [0, 1, 2].map(|k| l.position[k] / w)
            } else if !cfg.normalize_directional {
                unit3(
                    &lf("position"),
                    [l.position[0], l.position[1], l.position[2]],
                )?;
                [l.position[0], l.position[1], l.position[2]]
            } else {
                unit3(
                    &lf("position"),
                    [l.position[0], l.position[1], l.position[2]],
                )?
            };
            let mut vector = [Fp(0); 3];
            for k in 0..3 {
                vector[k] = word(&lf("position"), v[k], &mut ctr)?;
            }
            let cutoff = check_finite(&lf("spot_cutoff"), l.spot_cutoff)?;
            if cutoff != 180.0 && !(0.0..=90.0).contains(&cutoff) {
                return Err(ConfigError::invalid(
                    &lf("spot_cutoff"),
                    &format!("{cutoff} must be in 0 ..= 90 or 180"),
                ));
            }
            let sexp = check_finite(&lf("spot_exponent"), l.spot_exponent)?;
            if !(0.0..=MAX_EXPONENT).contains(&sexp) {
                return Err(ConfigError::out_of_range(
                    &lf("spot_exponent"),
                    sexp,
                    0.0,
                    MAX_EXPONENT,
                ));
            }
            let spot = if cutoff == 180.0 {
                None
            } else {
                let s = unit3(&lf("spot_direction"), l.spot_direction)?;
                let mut direction = [Fp(0); 3];
                for k in 0..3 {
                    direction[k] = word(&lf("spot_direction"), s[k], &mut ctr)?;
                }
                Some(SpotRegs {
                    direction,
                    cos_cutoff: word(&lf("spot_cutoff"), cutoff.to_radians().cos(), &mut ctr)?,
                    exponent: word(&lf("spot_exponent"), sexp, &mut ctr)?,
                })
            };
            let mut regs = LightRegs {
                local,
                vector,
                attenuation: [Fp(0); 3],
                spot,
                ambient: [Fp(0); 3],
                diffuse: [Fp(0); 3],
                specular: [Fp(0); 3],
            };
            for c in 0..3 {
                regs.attenuation[c] = word(&lf("attenuation"), l.attenuation[c], &mut ctr)?;
                regs.ambient[c] = word(&lf("ambient"), m.ambient[c] * l.ambient[c], &mut ctr)?;
                regs.diffuse[c] = word(&lf("diffuse"), m.diffuse[c] * l.diffuse[c], &mut ctr)?;
                regs.specular[c] = word(&lf("specular"), m.specular[c] * l.specular[c], &mut ctr)?;
            }
            lights.push(regs);
        }
        Ok(VertexLighting {
            cfg,
            lights,
            base,
            shininess,
            curve,
            alpha,
            load_counters: ctr,
        })
    }

    /// GeForce 256 defaults ([`VertexLightingConfig::geforce`]) with GL's default
    /// state (GL_LIGHT0 on, default material).
    pub fn geforce() -> Self {
        match Self::new(VertexLightingConfig::geforce(), &LightingSetup::default()) {
            Ok(u) => u,
            Err(e) => unreachable!("default config invalid: {e}"),
        }
    }

    /// The config the unit was built from.
    pub fn config(&self) -> VertexLightingConfig {
        self.cfg
    }

    /// The float format of the arithmetic (exponent and mantissa widths, rounding,
    /// subnormals).
    pub fn format(&self) -> FloatFormat {
        self.cfg.format
    }

    /// Enabled lights.
    pub fn light_count(&self) -> usize {
        self.lights.len()
    }

    /// The loaded light registers (what the host wrote, rounded to the format): the
    /// RTL's state (`registry::rtl` passes them to the Verilog as parameters).
    pub fn light_registers(&self) -> &[LightRegs] {
        &self.lights
    }

    /// The loaded e_m + a_m·a_s, shininess and alpha unorm (see [`Self::light_registers`]).
    pub fn material_registers(&self) -> ([Fp; 3], Fp, u32) {
        (self.base, self.shininess, self.alpha)
    }

    /// Saturations/underflows of the load (host values rounded into registers).
    pub fn load_counters(&self) -> Counters {
        self.load_counters
    }

    /// Host helper: a vertex from f64 eye-space position and normal (one rounding per
    /// component, saturating, counted). NaN/±∞ is an error naming
    /// `vertex_lighting.position` / `vertex_lighting.normal`.
    pub fn vertex_from_f64(
        &self,
        position: [f64; 3],
        normal: [f64; 3],
        ctr: &mut Counters,
    ) -> Result<VertexLightingIn, ConfigError> {
        let fmt = self.cfg.format;
        let mut v = VertexLightingIn::default();
        for k in 0..3 {
            v.position[k] = fmt.from_f64("vertex_lighting.position", position[k], ctr)?;
            v.normal[k] = fmt.from_f64("vertex_lighting.normal", normal[k], ctr)?;
        }
        Ok(v)
    }

    /// (a₀b₀ + a₁b₁) + a₂b₂: 3 multiplies, 2 adds.
    fn dot3(&self, a: &[Fp; 3], b: &[Fp; 3], ctr: &mut Counters) -> Fp {
        let f = &self.cfg.format;
        let t0 = f.mul(a[0], b[0], ctr);
        let t1 = f.mul(a[1], b[1], ctr);
        let s = f.add(t0, t1, ctr);
        let t2 = f.mul(a[2], b[2], ctr);
        f.add(s, t2, ctr)
    }

    /// v·rsq(v·v) (rsq(0) saturates: a zero vector stays zero).
    fn normalise(&self, v: &[Fp; 3], ctr: &mut Counters) -> [Fp; 3] {
        let f = &self.cfg.format;
        let r = f.rsq(self.dot3(v, v, ctr), ctr);
        v.map(|c| f.mul(c, r, ctr))
    }

    /// The datapath on one vertex.
    pub fn light(&self, input: &VertexLightingIn, ctr: &mut Counters) -> VertexLightingOut {
        match self.cfg.light_control {
            None => self.light_gl(input, ctr),
            Some(lc) => self.light_nv2a(&lc, input, ctr),
        }
    }

    /// The NV2A's two-colour path ([`LightControl`]): the diffuse sum
    /// e_m + a_m·a_s + Σ k·(a + nl·d) and the specular sum Σ k·(spec·s) are kept apart
    /// (each op rounded once, [`Self::light_terms`]' order), then routed by the switches;
    /// a specular sum that goes to the primary is added to it before the conversion.
    fn light_nv2a(
        &self,
        lc: &LightControl,
        input: &VertexLightingIn,
        ctr: &mut Counters,
    ) -> VertexLightingOut {
        let f = &self.cfg.format;
        let bits = self.cfg.color_bits;
        let max = ((1u64 << bits) - 1) as u32;
        let vs = input.specular.map(|c| c.min(max));
        let mut secondary = [vs[0], vs[1], vs[2], max];
        let rgba = if !lc.lighting {
            input.diffuse.map(|c| c.min(max))
        } else {
            let mut dacc = self.base;
            let mut sacc = [Fp(0); 3];
            self.accumulate(input, ctr, |c, k, t_diffuse, t_spec, ctr| {
                dacc[c] = f.add(dacc[c], f.mul(k, t_diffuse, ctr), ctr);
                sacc[c] = f.add(sacc[c], f.mul(k, t_spec, ctr), ctr);
            });
            let split = lc.specular_enable && lc.separate_specular;
            if split {
                for c in 0..3 {
                    secondary[c] = f.to_unorm(sacc[c], bits, ctr);
                }
            } else {
                for c in 0..3 {
                    dacc[c] = f.add(dacc[c], sacc[c], ctr);
                }
            }
            [
                f.to_unorm(dacc[0], bits, ctr),
                f.to_unorm(dacc[1], bits, ctr),
                f.to_unorm(dacc[2], bits, ctr),
                self.alpha,
            ]
        };
        if !lc.specular_enable {
            secondary = [0, 0, 0, max];
        } else if lc.specular_alpha_from_vertex {
            secondary[3] = vs[3];
        }
        VertexLightingOut { rgba, secondary }
    }

    /// GL's single colour (the default path).
    fn light_gl(&self, input: &VertexLightingIn, ctr: &mut Counters) -> VertexLightingOut {
        let f = &self.cfg.format;
        let mut acc = self.base;
        self.accumulate(input, ctr, |c, k, t_diffuse, t_spec, ctr| {
            let t = f.add(t_diffuse, t_spec, ctr);
            acc[c] = f.add(acc[c], f.mul(k, t, ctr), ctr);
        });
        let bits = self.cfg.color_bits;
        VertexLightingOut {
            rgba: [
                f.to_unorm(acc[0], bits, ctr),
                f.to_unorm(acc[1], bits, ctr),
                f.to_unorm(acc[2], bits, ctr),
                self.alpha,
            ],
            secondary: [0; 4],
        }
    }

    /// Every light's terms at the vertex: `sum(c, k, a + nl·d, spec·s, ctr)` per light
    /// and channel, k = att·spot (the callback forms the sums).
    fn accumulate(
        &self,
        input: &VertexLightingIn,
        ctr: &mut Counters,
        mut sum: impl FnMut(usize, Fp, Fp, Fp, &mut Counters),
    ) {
        let f = &self.cfg.format;
        let p = &input.position;
        let n = if self.cfg.normalize {
            self.normalise(&input.normal, ctr)
        } else {
            input.normal
        };
        let v = if self.cfg.local_viewer {
            self.normalise(&p.map(|c| f.neg(c)), ctr)
        } else {
            [Fp(0), Fp(0), f.one()]
        };
        for l in &self.lights {
            let (lv, att) = if l.local {
                let vp = [0, 1, 2].map(|k| f.sub(l.vector[k], p[k], ctr));
                let d2 = self.dot3(&vp, &vp, ctr);
                let r = f.rsq(d2, ctr);
                let lv = vp.map(|c| f.mul(c, r, ctr));
                let d = f.mul(d2, r, ctr);
                let [kc, kl, kq] = l.attenuation;
                let den = f.add(kc, f.mul(kl, d, ctr), ctr);
                let den = f.add(den, f.mul(kq, d2, ctr), ctr);
                (lv, f.rcp(den, ctr))
            } else {
                (l.vector, f.one())
            };
            let spot = match &l.spot {
                None => f.one(),
                Some(s) => {
                    let c = f.neg(self.dot3(&lv, &s.direction, ctr));
                    if f.lt(c, s.cos_cutoff) {
                        Fp(0)
                    } else {
                        f.pow(c, s.exponent, ctr)
                    }
                }
            };
            let nl_raw = self.dot3(&n, &lv, ctr);
            let nl = f.max0(nl_raw);
            let spec = if f.lt(Fp(0), nl_raw) {
                let hv = [0, 1, 2].map(|k| f.add(lv[k], v[k], ctr));
                let h = self.normalise(&hv, ctr);
                let nh = f.max0(self.dot3(&n, &h, ctr));
                self.specular_factor(nh, ctr)
            } else {
                Fp(0)
            };
            let k = f.mul(att, spot, ctr);
            for c in 0..3 {
                let t = f.add(l.ambient[c], f.mul(nl, l.diffuse[c], ctr), ctr);
                let ts = f.mul(spec, l.specular[c], ctr);
                sum(c, k, t, ts, ctr);
            }
        }
    }

    /// The specular factor of x = max(N·h, 0): pow(x, shininess), or the NV2A's
    /// (x + k0)·rcp(k1·x + k2), 0 unless numerator and denominator are positive.
    fn specular_factor(&self, nh: Fp, ctr: &mut Counters) -> Fp {
        let f = &self.cfg.format;
        match self.curve {
            None => f.pow(nh, self.shininess, ctr),
            Some([k0, k1, k2]) => {
                let num = f.add(nh, k0, ctr);
                let den = f.add(f.mul(k1, nh, ctr), k2, ctr);
                if f.lt(Fp(0), num) && f.lt(Fp(0), den) {
                    f.mul(num, f.rcp(den, ctr), ctr)
                } else {
                    Fp(0)
                }
            }
        }
    }

    /// The loaded k0, k1, k2 of the NV2A specular curve (None: pow).
    pub fn curve_registers(&self) -> Option<[Fp; 3]> {
        self.curve
    }

    /// Issues per vertex on each resource (see the module docs).
    pub fn issues(&self) -> Issues {
        let n = self.lights.len() as u32;
        let k = u32::from(self.cfg.normalize) + u32::from(self.cfg.local_viewer);
        // Two colours: k·(spec·s) is its own multiply per light and channel (3), and the
        // specular sum joins the primary with 3 adds when it is not separate.
        let (lc_muls, lc_adds) = match self.cfg.light_control {
            None => (0, 0),
            Some(_) => (3 * n, 3),
        };
        // The NV2A curve per light: k1·x and num·rcp (2 multiplies) instead of s·log
        // (1), two adds, one RCP instead of LOG + EXP.
        let (c_muls, c_adds, c_specials) = match self.curve {
            None => (0, 0, 0),
            Some(_) => (n, 2 * n, n),
        };
        Issues {
            muls: ISSUES_PER_LIGHT.muls * n + ISSUES_PER_NORMALISE.muls * k + lc_muls + c_muls,
            adds: ISSUES_PER_LIGHT.adds * n + ISSUES_PER_NORMALISE.adds * k + lc_adds + c_adds,
            specials: ISSUES_PER_LIGHT.specials * n + ISSUES_PER_NORMALISE.specials * k
                - c_specials,
        }
    }
}

impl Unit for VertexLighting {
    type In = VertexLightingIn;
    type Out = VertexLightingOut;
    type State = ();

    fn name(&self) -> &'static str {
        "vertex_lighting"
    }

    fn kernel(
        &self,
        _: &mut (),
        input: &VertexLightingIn,
        ctr: &mut Counters,
    ) -> VertexLightingOut {
        self.light(input, ctr)
    }

    fn timing(&self) -> Timing {
        let i = self.issues();
        let ii = i
            .muls
            .div_ceil(FP_MULTIPLIERS)
            .max(i.adds.div_ceil(FP_ADDERS))
            .max(i.specials)
            .max(1);
        Timing {
            latency: ii + 6,
            ii,
        }
    }

    fn cost(&self) -> Cost {
        let fmt = self.cfg.format;
        let (e, m) = (fmt.exp_bits, fmt.mant_bits);
        let w = fmt.width();
        let k = fmt.pow_frac_bits();
        let sig = m + 1;
        let guard = m + 4; // significand + guard/round/sticky in the adder
        let stages = bits_for(guard as u64);
        let rsq_quotient_bits = 2 * m + 9 + m % 2;
        let rsq_root_bits = rsq_quotient_bits.div_ceil(2);
        // One FP multiplier: significand multiplier, exponent adder (+ bias correction),
        // 1-bit normalise, rounding incrementer.
        let fmul = prim::multiplier(sig, sig)
            + prim::adder(e + 1) * 2.0
            + prim::mux(sig)
            + prim::adder(sig);
        // One FP adder: the operands ordered by magnitude (exponent and significand
        // compared as one (E + M)-bit word), exponent subtract, operand swap, alignment
        // shifter with the sticky OR of the bits it shifts out (a thermometer mask of
        // the shift, an AND and an OR per guard bit), significand add/subtract, LZC,
        // normalising shifter, rounding incrementer.
        let sticky = Cells {
            and2: guard as f64,
            or2: (2 * guard - 1) as f64,
            ..Cells::default()
        };
        let fadd = prim::comparator(w - 1)
            + prim::subtractor(e + 1)
            + sticky
            + prim::mux(w) * 2.0
            + prim::shifter(guard, stages)
            + prim::adder(guard + 1)
            + prim::leading_zero_counter(guard + 1)
            + prim::shifter(guard + 1, stages)
            + prim::adder(sig)
            + prim::adder(e + 1);
        // Register file: per light 19 words (vector 3, attenuation 3, spot 5, the three
        // colour products 9 — minus one spare), base 3, shininess 1; vertex temporaries 24.
        let regfile_words = 19 * MAX_LIGHTS as u32 + 4 + 24;
        let cb = self.cfg.color_bits;
        // One unorm converter: significand × (2^n − 1), round.
        let unorm = prim::multiplier(sig, cb) + prim::adder(sig + cb);
        let light_control = match self.cfg.light_control {
            None => Cells::default(),
            // Vertex colours in (8 words), the specular accumulators (3 words), the
            // secondary's converters (the separate specular sum is converted in the same
            // clock as the primary: 3 more, as vertex_lighting.v has them), its output
            // registers and the routing: a 2:1 mux per primary channel (lit / vertex
            // diffuse, 4 channels) and a 3:1 per secondary one.
            Some(_) => {
                prim::register(8 * cb)
                    + prim::register(3 * w)
                    + unorm * 3.0
                    + prim::register(4 * cb)
                    + prim::mux(4 * cb)
                    + prim::mux(4 * cb) * 2.0
            }
        };
        // The NV2A curve's three coefficient registers (the adds, multiplies and RCP run
        // on the shared lanes; the LOG/EXP stay for the spot exponent).
        let curve = match self.curve {
            None => Cells::default(),
            Some(_) => prim::register(3 * w),
        };
        Cost::default()
            .part("input registers (P, n)", prim::register(6 * w))
            .part("NV2A specular curve coefficients (k0, k1, k2)", curve)
            .part(
                "light control (vertex colours, specular sum, secondary colour and its conversion, routing)",
                light_control,
            )
            .part("FP multipliers (6)", fmul * FP_MULTIPLIERS as f64)
            .part("FP adders (4)", fadd * FP_ADDERS as f64)
            .part(
                "RCP: digit-recurrence divider (M + 4 quotient bits, remainder → sticky)",
                prim::divider(sig + 1, guard),
            )
            .part(
                // The kernel's ⌊√⌊2^(3M+8+M mod 2)/sig⌋⌋ (float_format.rs `rsq`): a
                // division with 2M + 9 + M mod 2 quotient bits, then a root of half as
                // many bits, each step an (RB + 2)-bit compare and subtract.
                "RSQ: restoring divide (2M + 9 + M mod 2 quotient bits), then square root",
                prim::divider(sig + 2, rsq_quotient_bits)
                    + prim::divider(rsq_root_bits + 2, rsq_root_bits),
            )
            .part(
                // A squarer is about half a multiplier (its partial products are
                // symmetric), but the prim set has no squarer: priced as a multiplier
                // (docs/units.md, vertex_lighting's synthesis notes).
                "LOG: K squaring stages u1.K (unrolled, pipelined)",
                prim::multiplier(k + 1, k + 1) * k as f64 + prim::mux(k + 1) * k as f64,
            )
            .part(
                // Each stage multiplies by its own ROM constant (fixed at design
                // time): shift-adds over the constant's signed digits.
                "EXP: K conditional multiplies by the ROM constants",
                fmt.exp2_rom()
                    .iter()
                    .map(|&c| prim::constant_multiplier(k + 1, c) + prim::mux(k + 1))
                    .fold(Cells::default(), |acc, x| acc + x),
            )
            .part(
                "special-function pipeline registers",
                prim::register((k + 1) * (2 * k + 2)),
            )
            .part(
                "compare/max/clamp (3 comparators)",
                prim::comparator(w) * 3.0,
            )
            .part(
                "unorm conversion (3 × significand × (2^n − 1), round)",
                unorm * 3.0,
            )
            .part(
                "register file (lights, material, temporaries)",
                prim::register(regfile_words * w),
            )
            .part(
                "output registers (RGBA)",
                prim::register(4 * self.cfg.color_bits),
            )
            .with_ram_bits(fmt.exp2_rom_bits())
    }

    fn widths(&self) -> Vec<Width> {
        let fmt = self.cfg.format;
        vec![
            Width {
                name: "exp_bits",
                bits: fmt.exp_bits,
            },
            Width {
                name: "mant_bits",
                bits: fmt.mant_bits,
            },
            Width {
                name: "word_bits",
                bits: fmt.width(),
            },
            Width {
                name: "pow_frac_bits",
                bits: fmt.pow_frac_bits(),
            },
            Width {
                name: "color_bits",
                bits: self.cfg.color_bits,
            },
        ]
    }

    fn in_signals(&self, i: &VertexLightingIn) -> Vec<Signal> {
        const NAMES: [&str; 6] = ["px", "py", "pz", "nx", "ny", "nz"];
        let w = self.cfg.format.width();
        let mut sigs: Vec<Signal> = i
            .position
            .iter()
            .chain(i.normal.iter())
            .zip(NAMES)
            .map(|(v, name)| Signal::new(name, w, v.0))
            .collect();
        if self.cfg.light_control.is_some() {
            const COLOURS: [&str; 8] = ["dr", "dg", "db", "da", "sr", "sg", "sb", "sa"];
            let b = self.cfg.color_bits;
            sigs.extend(
                i.diffuse
                    .iter()
                    .chain(i.specular.iter())
                    .zip(COLOURS)
                    .map(|(&v, name)| Signal::new(name, b, v as u64)),
            );
        }
        sigs
    }

    fn out_signals(&self, o: &VertexLightingOut) -> Vec<Signal> {
        const NAMES: [&str; 4] = ["r", "g", "b", "a"];
        const SECONDARY: [&str; 4] = ["r2", "g2", "b2", "a2"];
        let b = self.cfg.color_bits;
        let secondary = if self.cfg.light_control.is_some() {
            &o.secondary[..]
        } else {
            &[]
        };
        o.rgba
            .iter()
            .zip(NAMES)
            .chain(secondary.iter().zip(SECONDARY))
            .map(|(&v, name)| Signal::new(name, b, v as u64))
            .collect()
    }
}
