//! halo_modulator — the halo luminance modulation circuit (Fig. 3 of M. Matsuda and
//! T. Ikedo, "A Realtime Renderer for Glare Effect Based upon Empirical Approach"): the same
//! SHAPE RAM as the bloom/flare modulator, then THREE ring RAMs (one falloff profile
//! per colour channel R, G, B — the halo ring radius scales with wavelength, the
//! paper's eq. (5)), each times its channel gain.
//!
//! The datapath, formats and widths are in [`crate::units::luminance_ram`]:
//! u, v s2.F → clamp to [−1, 1] and split into index u(k+1) / weight u(wb) → 4 shape
//! samples u(sb) → row lerps u(sb+wb) → column lerp u(sb+2wb) → round → d u(sb) →
//! replicate to u(m+wb): index u(m) / weight u(wb) → per channel c: 2 ring samples
//! u(fb) → lerp u(fb+wb) → round → p_c u(fb) → u1.R, R = fb+gi → × gain_c u(gi).(gf)
//! → round → u(gi+1) → saturate → lum_c u(out_bits).
//! Latency 6, II 1.

use crate::cost::Cost;
use crate::counters::Counters;
use crate::error::ConfigError;
use crate::unit::{Signal, Timing, Unit, Width};
use crate::units::bloom_flare_modulator::{lum_in_signals, lum_out_signals, lum_width_list};
use crate::units::luminance_ram::LumWidths;
pub use crate::units::luminance_ram::Radial;
pub use crate::units::luminance_ram::{LumIn, LumOut};
use serde::{Deserialize, Serialize};

const NAME: &str = "halo_modulator";

/// Config (all widths runtime; the same fields as the bloom/flare modulator).
/// Defaults: F 14, k 7, sb 16, m 8, fb 16, wb 8,
/// gain u12.4, out 12 bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct HaloModulatorConfig {
    /// F: fraction bits of the s2.F coordinates u, v, 2 ..= 16 (default 14).
    pub coord_frac_bits: u32,
    /// k: the shape RAM has 2ᵏ cells per side, (2ᵏ+1)² samples; 1 ..= 10 (default 7).
    pub shape_log2: u32,
    /// Shape entry and distance d width, unorm bits, 1 ..= 16 (default 16).
    pub shape_bits: u32,
    /// m: each of the three ring RAMs has 2ᵐ cells, 2ᵐ+1 samples; 1 ..= 12 (default 8).
    pub falloff_log2: u32,
    /// Ring entry and profile p_c width, unorm bits, 1 ..= 20 (default 16).
    pub falloff_bits: u32,
    /// Interpolation weight width of the shape and ring RAMs, 1 ..= 12 (default 8).
    pub weight_bits: u32,
    /// Integer bits of each channel gain, 0 ..= 16 (default 12).
    pub gain_int_bits: u32,
    /// Fraction bits of each channel gain, 0 ..= 16 (default 4); gain_int_bits +
    /// gain_frac_bits must be ≥ 1 (the error names `gain_frac_bits`).
    pub gain_frac_bits: u32,
    /// Luminance output width (framebuffer codes), 1 ..= 16 (default 12).
    pub out_bits: u32,
    /// Radial correction (default off); see [`Radial`].
    #[serde(default)]
    pub radial: Radial,
}

impl Default for HaloModulatorConfig {
    fn default() -> Self {
        Self::from_widths(LumWidths::default())
    }
}

impl HaloModulatorConfig {
    /// The shared-datapath widths.
    pub fn widths(&self) -> LumWidths {
        LumWidths {
            coord_frac_bits: self.coord_frac_bits,
            shape_log2: self.shape_log2,
            shape_bits: self.shape_bits,
            falloff_log2: self.falloff_log2,
            falloff_bits: self.falloff_bits,
            weight_bits: self.weight_bits,
            gain_int_bits: self.gain_int_bits,
            gain_frac_bits: self.gain_frac_bits,
            out_bits: self.out_bits,
            radial: self.radial,
        }
    }

    /// The config with the given shared-datapath widths (the inverse of `widths`).
    pub fn from_widths(w: LumWidths) -> Self {
        HaloModulatorConfig {
            coord_frac_bits: w.coord_frac_bits,
            shape_log2: w.shape_log2,
            shape_bits: w.shape_bits,
            falloff_log2: w.falloff_log2,
            falloff_bits: w.falloff_bits,
            weight_bits: w.weight_bits,
            gain_int_bits: w.gain_int_bits,
            gain_frac_bits: w.gain_frac_bits,
            out_bits: w.out_bits,
            radial: w.radial,
        }
    }

    /// Validate and load the tables: `shape` has (2ᵏ+1)² entries (row-major, v index
    /// major), each ring profile 2ᵐ+1 (R, G, B), all in [0, 1]. Errors name
    /// `halo_modulator.<field>`, `halo_modulator.shape[<i>]` or
    /// `halo_modulator.rings[<c>][<i>]`.
    pub fn build(&self, shape: &[f64], rings: [&[f64]; 3]) -> Result<HaloModulator, ConfigError> {
        let w = self.widths();
        w.validate(NAME)?;
        let shape = w.quantise_shape(&format!("{NAME}.shape"), shape)?;
        let mut out: [Vec<u32>; 3] = Default::default();
        for (c, r) in rings.iter().enumerate() {
            out[c] = LumWidths::quantise_table(
                &format!("{NAME}.rings[{c}]"),
                r,
                w.falloff_len(),
                w.falloff_bits,
            )?;
        }
        Ok(HaloModulator {
            w,
            shape,
            rings: out,
            kappa: 0,
        })
    }
}

/// The validated modulator with its loaded shape RAM and three ring RAMs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct HaloModulator {
    w: LumWidths,
    shape: Vec<u32>,
    /// κ register, u(ki).(kf) (radial mode; 0 after build).
    kappa: u32,
    rings: [Vec<u32>; 3],
}

impl HaloModulator {
    /// GeForce-era defaults with the given tables.
    pub fn geforce(shape: &[f64], rings: [&[f64]; 3]) -> Result<Self, ConfigError> {
        HaloModulatorConfig::default().build(shape, rings)
    }

    /// The config the modulator was built from.
    pub fn config(&self) -> HaloModulatorConfig {
        HaloModulatorConfig::from_widths(self.w)
    }

    /// The shared-datapath widths of the modulator.
    pub fn lum_widths(&self) -> LumWidths {
        self.w
    }

    /// Shape RAM entries: (2ᵏ+1)².
    pub fn shape_len(&self) -> usize {
        self.w.shape_len()
    }

    /// Entries of each ring RAM: 2ᵐ+1.
    pub fn falloff_len(&self) -> usize {
        self.w.falloff_len()
    }

    /// Loaded shape RAM codes (unorm `shape_bits`).
    pub fn shape_codes(&self) -> &[u32] {
        &self.shape
    }

    /// Loaded ring RAM codes of channel c (unorm `falloff_bits`).
    pub fn ring_codes(&self, c: usize) -> &[u32] {
        &self.rings[c]
    }

    /// Entries written per primitive to load the tables: (2ᵏ+1)² + 3·(2ᵐ+1).
    pub fn table_words(&self) -> u64 {
        self.w.table_words(3)
    }

    /// RAM bits: (2ᵏ+1)²·sb + 3·(2ᵐ+1)·fb.
    pub fn ram_bits(&self) -> u64 {
        self.w.ram_bits(3)
    }

    /// Quantise an RGB gain (luminance in framebuffer codes at p = 1); errors name
    /// `halo_modulator.gain[c]`.
    pub fn gain_from_f64(&self, g: [f64; 3]) -> Result<[u32; 3], ConfigError> {
        self.w.gain_from_f64(NAME, g)
    }

    /// Quantise a primitive-frame position to s2.F (saturating to [−2, 2); NaN/∞ →
    /// error naming `halo_modulator.coord`).
    pub fn coord_from_f64(&self, u: f64) -> Result<i32, ConfigError> {
        self.w.coord_from_f64(NAME, u)
    }

    /// Load the κ register (radial mode; round to nearest u(ki).(kf)). NaN, ∞,
    /// negative or above the largest code is an error naming `<unit>.kappa`.
    pub fn with_kappa(mut self, kappa: f64) -> Result<Self, ConfigError> {
        self.kappa = self.w.kappa_from_f64(NAME, kappa)?;
        Ok(self)
    }

    /// The κ register code, u(ki).(kf).
    pub fn kappa_code(&self) -> u32 {
        self.kappa
    }

    /// The combinational datapath on one pixel.
    #[inline]
    pub fn apply(&self, input: &LumIn, ctr: &mut Counters) -> LumOut {
        let d = if self.w.radial.on {
            self.w
                .radial_lookup(&self.shape, self.kappa, input.u, input.v, ctr)
        } else {
            self.w.shape_lookup(&self.shape, input.u, input.v, ctr)
        };
        let mut lum = [0u32; 3];
        for (c, l) in lum.iter_mut().enumerate() {
            let p = self.w.falloff_lookup(&self.rings[c], d, ctr);
            *l = self.w.gain_mul(p, input.gain[c], ctr);
        }
        LumOut { d, lum }
    }
}

impl Unit for HaloModulator {
    type In = LumIn;
    type Out = LumOut;
    type State = ();

    fn name(&self) -> &'static str {
        NAME
    }

    fn kernel(&self, _: &mut (), input: &LumIn, ctr: &mut Counters) -> LumOut {
        self.apply(input, ctr)
    }

    fn timing(&self) -> Timing {
        Timing {
            latency: self.w.latency(),
            ii: 1,
        }
    }

    fn cost(&self) -> Cost {
        self.w.cost(3).with_ram_bits(self.w.ram_bits(3))
    }

    fn widths(&self) -> Vec<Width> {
        lum_width_list(&self.w)
    }

    fn in_signals(&self, i: &LumIn) -> Vec<Signal> {
        lum_in_signals(&self.w, i)
    }

    fn out_signals(&self, o: &LumOut) -> Vec<Signal> {
        lum_out_signals(&self.w, o)
    }
}
