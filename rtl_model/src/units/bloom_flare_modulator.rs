//! bloom_flare_modulator — the bloom and flare luminance modulation circuit (Fig. 2 of
//! M. Matsuda and T. Ikedo, "A Realtime Renderer for Glare Effect Based upon Empirical
//! Approach"): (u, v) → SHAPE RAM (bilinear) → d → FALLOFF RAM (linear) → p → × RGB gain.
//!
//! The datapath, formats and widths are in [`crate::units::luminance_ram`]:
//! u, v s2.F → clamp to [−1, 1] and split into index u(k+1) / weight u(wb) → 4 shape
//! samples u(sb) → row lerps u(sb+wb) → column lerp u(sb+2wb) → round → d u(sb) →
//! replicate to u(m+wb): index u(m) / weight u(wb) → 2 falloff samples u(fb) → lerp
//! u(fb+wb) → round → p u(fb) → replicate to u(R), R = fb+gi → × gain u(gi).(gf) →
//! u(gi).(R+gf) → round → u(gi+1) → saturate → lum u(out_bits) ×3.
//! Latency 6, II 1.

use crate::cost::Cost;
use crate::counters::Counters;
use crate::error::ConfigError;
use crate::unit::{Signal, Timing, Unit, Width};
pub use crate::units::luminance_ram::Radial;
use crate::units::luminance_ram::{mask32, LumWidths, PlainPath};
pub use crate::units::luminance_ram::{LumIn, LumOut};
use serde::{Deserialize, Serialize};

const NAME: &str = "bloom_flare_modulator";

/// Config (all widths runtime). Defaults: F 14, k 7, sb 16, m 8, fb 16, wb 8,
/// gain u12.4, out 12 bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct BloomFlareModulatorConfig {
    /// F: fraction bits of the s2.F coordinates u, v, 2 ..= 16 (default 14).
    pub coord_frac_bits: u32,
    /// k: the shape RAM has 2ᵏ cells per side, (2ᵏ+1)² samples; 1 ..= 10 (default 7).
    pub shape_log2: u32,
    /// Shape entry and distance d width, unorm bits, 1 ..= 16 (default 16).
    pub shape_bits: u32,
    /// m: the falloff RAM has 2ᵐ cells, 2ᵐ+1 samples; 1 ..= 12 (default 8).
    pub falloff_log2: u32,
    /// Falloff entry and profile p width, unorm bits, 1 ..= 20 (default 16).
    pub falloff_bits: u32,
    /// Interpolation weight width of both RAMs, 1 ..= 12 (default 8).
    pub weight_bits: u32,
    /// Integer bits of the RGB gain, 0 ..= 16 (default 12).
    pub gain_int_bits: u32,
    /// Fraction bits of the RGB gain, 0 ..= 16 (default 4); gain_int_bits + gain_frac_bits
    /// must be ≥ 1 (the error names `gain_frac_bits`).
    pub gain_frac_bits: u32,
    /// Luminance output width (framebuffer codes), 1 ..= 16 (default 12).
    pub out_bits: u32,
    /// Radial correction (default off); see [`Radial`].
    #[serde(default)]
    pub radial: Radial,
}

impl Default for BloomFlareModulatorConfig {
    fn default() -> Self {
        Self::from_widths(LumWidths::default())
    }
}

impl BloomFlareModulatorConfig {
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
        BloomFlareModulatorConfig {
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
    /// major), `falloff` 2ᵐ+1, all in [0, 1]. Errors name
    /// `bloom_flare_modulator.<field>` or `bloom_flare_modulator.shape[<i>]` /
    /// `.falloff[<i>]`.
    pub fn build(
        &self,
        shape: &[f64],
        falloff: &[f64],
    ) -> Result<BloomFlareModulator, ConfigError> {
        let w = self.widths();
        w.validate(NAME)?;
        let shape = w.quantise_shape(&format!("{NAME}.shape"), shape)?;
        let falloff = LumWidths::quantise_table(
            &format!("{NAME}.falloff"),
            falloff,
            w.falloff_len(),
            w.falloff_bits,
        )?;
        Ok(BloomFlareModulator {
            w,
            shape,
            falloff,
            kappa: 0,
            plain: PlainPath::new(&w),
        })
    }
}

/// The validated modulator with its loaded shape and falloff RAMs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BloomFlareModulator {
    w: LumWidths,
    shape: Vec<u32>,
    /// κ register, u(ki).(kf) (radial mode; 0 after build).
    kappa: u32,
    falloff: Vec<u32>,
    /// The batch kernel's fast form, chosen from the widths at build (None: the
    /// per-word kernel).
    plain: Option<PlainPath>,
}

impl BloomFlareModulator {
    /// GeForce-era defaults with the given tables.
    pub fn geforce(shape: &[f64], falloff: &[f64]) -> Result<Self, ConfigError> {
        BloomFlareModulatorConfig::default().build(shape, falloff)
    }

    /// The config the modulator was built from.
    pub fn config(&self) -> BloomFlareModulatorConfig {
        BloomFlareModulatorConfig::from_widths(self.w)
    }

    /// The shared-datapath widths of the modulator.
    pub fn lum_widths(&self) -> LumWidths {
        self.w
    }

    /// Shape RAM entries: (2ᵏ+1)².
    pub fn shape_len(&self) -> usize {
        self.w.shape_len()
    }

    /// Falloff RAM entries: 2ᵐ+1.
    pub fn falloff_len(&self) -> usize {
        self.w.falloff_len()
    }

    /// Loaded shape RAM codes (unorm `shape_bits`).
    pub fn shape_codes(&self) -> &[u32] {
        &self.shape
    }

    /// Loaded falloff RAM codes (unorm `falloff_bits`).
    pub fn falloff_codes(&self) -> &[u32] {
        &self.falloff
    }

    /// Entries written per primitive to load both tables: (2ᵏ+1)² + 2ᵐ+1.
    pub fn table_words(&self) -> u64 {
        self.w.table_words(1)
    }

    /// RAM bits: (2ᵏ+1)²·sb + (2ᵐ+1)·fb.
    pub fn ram_bits(&self) -> u64 {
        self.w.ram_bits(1)
    }

    /// Quantise an RGB gain (luminance in framebuffer codes at p = 1); errors name
    /// `bloom_flare_modulator.gain[c]`.
    pub fn gain_from_f64(&self, g: [f64; 3]) -> Result<[u32; 3], ConfigError> {
        self.w.gain_from_f64(NAME, g)
    }

    /// Quantise a primitive-frame position to s2.F (saturating to [−2, 2); NaN/∞ →
    /// error naming `bloom_flare_modulator.coord`).
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
        let p = self.w.falloff_lookup(&self.falloff, d, ctr);
        let mut lum = [0u32; 3];
        for (c, l) in lum.iter_mut().enumerate() {
            *l = self.w.gain_mul(p, input.gain[c], ctr);
        }
        LumOut { d, lum }
    }
}

impl Unit for BloomFlareModulator {
    type In = LumIn;
    type Out = LumOut;
    type State = ();

    fn name(&self) -> &'static str {
        NAME
    }

    fn kernel(&self, _: &mut (), input: &LumIn, ctr: &mut Counters) -> LumOut {
        self.apply(input, ctr)
    }

    /// The plain datapath's fast form where the widths allow it ([`PlainPath`]):
    /// counters summed per chunk (6 reads a word: 4 shape banks, 2 falloff banks).
    fn kernel_batch(
        &self,
        _: &mut (),
        inputs: &[LumIn],
        out: &mut Vec<LumOut>,
        ctr: &mut Counters,
    ) {
        let Some(p) = &self.plain else {
            out.extend(inputs.iter().map(|x| self.apply(x, ctr)));
            return;
        };
        let mut sat = 0u64;
        out.extend(inputs.iter().map(|x| {
            let d = p.shape_lookup(&self.shape, x.u, x.v, &mut sat);
            let prep = p.p_operand(p.falloff_lookup(&self.falloff, d));
            let g = x.gain;
            LumOut {
                d,
                lum: [
                    p.gain_mul(prep, g[0], &mut sat),
                    p.gain_mul(prep, g[1], &mut sat),
                    p.gain_mul(prep, g[2], &mut sat),
                ],
            }
        }));
        ctr.table_reads += 6 * inputs.len() as u64;
        ctr.saturations += sat;
    }

    fn timing(&self) -> Timing {
        Timing {
            latency: self.w.latency(),
            ii: 1,
        }
    }

    fn cost(&self) -> Cost {
        self.w.cost(1).with_ram_bits(self.w.ram_bits(1))
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

/// Named widths of the shared datapath (both modulators).
pub(crate) fn lum_width_list(w: &LumWidths) -> Vec<Width> {
    let mut v = vec![
        Width {
            name: "coord_frac_bits",
            bits: w.coord_frac_bits,
        },
        Width {
            name: "shape_log2",
            bits: w.shape_log2,
        },
        Width {
            name: "shape_bits",
            bits: w.shape_bits,
        },
        Width {
            name: "falloff_log2",
            bits: w.falloff_log2,
        },
        Width {
            name: "falloff_bits",
            bits: w.falloff_bits,
        },
        Width {
            name: "weight_bits",
            bits: w.weight_bits,
        },
        Width {
            name: "gain_int_bits",
            bits: w.gain_int_bits,
        },
        Width {
            name: "gain_frac_bits",
            bits: w.gain_frac_bits,
        },
        Width {
            name: "out_bits",
            bits: w.out_bits,
        },
    ];
    if w.radial.on {
        let r = w.radial;
        v.extend([
            Width {
                name: "radius_frac_bits",
                bits: r.radius_frac_bits,
            },
            Width {
                name: "kappa_int_bits",
                bits: r.kappa_int_bits,
            },
            Width {
                name: "kappa_frac_bits",
                bits: r.kappa_frac_bits,
            },
            Width {
                name: "entry_int_bits",
                bits: r.entry_int_bits,
            },
        ]);
    }
    v
}

pub(crate) fn lum_in_signals(w: &LumWidths, i: &LumIn) -> Vec<Signal> {
    let cw = w.coord_frac_bits + 2;
    let gb = w.gain_bits();
    let g = |x: u32| (x & mask32(gb)) as u64;
    vec![
        Signal::new("u", cw, (i.u as u32 & mask32(cw)) as u64),
        Signal::new("v", cw, (i.v as u32 & mask32(cw)) as u64),
        Signal::new("gain_r", gb, g(i.gain[0])),
        Signal::new("gain_g", gb, g(i.gain[1])),
        Signal::new("gain_b", gb, g(i.gain[2])),
    ]
}

pub(crate) fn lum_out_signals(w: &LumWidths, o: &LumOut) -> Vec<Signal> {
    vec![
        Signal::new("d", w.shape_bits, o.d as u64),
        Signal::new("lum_r", w.out_bits, o.lum[0] as u64),
        Signal::new("lum_g", w.out_bits, o.lum[1] as u64),
        Signal::new("lum_b", w.out_bits, o.lum[2] as u64),
    ]
}
