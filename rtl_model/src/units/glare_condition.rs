//! glare_condition — decides whether a specular highlight becomes a glare source
//! (M. Matsuda and T. Ikedo, "A Realtime Renderer for Glare Effect Based upon
//! Empirical Approach", Table 2): metallic I_ps = I·I_s·cos²α, water I_ps = I·cos α; glare when
//! I_ps ≥ T·I_a (T = 40 by default: no divider, T·I_a is a shift-add,
//! (I_a<<5)+(I_a<<3)), and for water also total internal reflection
//! 1 − η²(1 − cos²θ) < 0. The highlight value is output saturated at 255.
//!
//! Formats: I, I_a u(ib).(fb) (default u12.4, framebuffer codes); I_s unorm `coef_bits`
//! (default 8); cos α, cos θ s1.(cf) (default s1.14, value code/2^cf ∈ [−1, 1)); η
//! u2.(ef) (default u2.14, η < 4); i_ps out u(out_bits) (default 8).
//!
//! Datapath (widths; W = max(cb, ib+fb+1)):
//! * a = max(cos α, 0): u(cf+1) ≤ 2^cf (cos α < 0 means no highlight, both materials).
//! * metallic factor k = I_s' · a²: I_s replicated to u1.W (+ top bit: 1.0 exact,
//!   |error| ≤ 2^−W), a² u(2cf+1) → k u1.(W+2cf);
//!   water factor k = a · 2^(W+cf) (exact).
//! * I_ps = round(I × k / 2^(W+2cf)): u(ib+fb) × u1.(W+2cf) → u(ib+fb+W+2cf+1) → u(ib).(fb)
//!   (k ≤ 1, so I_ps ≤ I fits the intensity format).
//! * contrast_ok = I_ps ≥ T·I_a: T·I_a by shift-add, u(ib+fb+16).
//! * TIR (water): η² (u(2ef+4)) × (2^(2cf) − cos²θ) (u(2cf+1)) > 2^(2cf+2ef), exact.
//! * i_ps = min(round(I_ps), 2^out_bits − 1) (saturation counted).
//!
//! Latency 3 (squares and I_s·a²; I × k and η²(1 − cos²θ); round, compare, clamp), II 1.

use crate::cost::{prim, Cells, Cost};
use crate::counters::Counters;
use crate::error::{check_finite, check_range, ConfigError};
use crate::unit::{Signal, Timing, Unit, Width};
use crate::units::luminance_ram::{mask32, replicate, sext};
use serde::{Deserialize, Serialize};

const NAME: &str = "glare_condition";

/// Surface material of the highlight.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Material {
    /// A metal: I_ps = I·I_s·cos²α, glare on contrast alone.
    Metallic,
    /// Water: I_ps = I·cos α, glare on contrast and total internal reflection.
    Water,
}

/// Config. `eta` is the host-edge f64 ratio of refraction indices (quantised to
/// u2.`eta_frac_bits`, must lie in [0, 4)).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct GlareConditionConfig {
    /// Integer bits of I and I_a (0 ..= 16, default 12).
    pub int_bits: u32,
    /// Fraction bits of I and I_a (0 ..= 16, default 4; int_bits + frac_bits ≥ 1).
    pub frac_bits: u32,
    /// Width of the specular coefficient I_s, unorm (1 ..= 16, default 8).
    pub coef_bits: u32,
    /// Fraction bits of the s1.cf cosines (1 ..= 16, default 14).
    pub cos_frac_bits: u32,
    /// η, ratio of refraction indices (default 1.333: water → air).
    pub eta: f64,
    /// Fraction bits of η's u2.ef code (1 ..= 16, default 14).
    pub eta_frac_bits: u32,
    /// Contrast threshold T (integer, 0 ..= 65535, default 40).
    pub threshold: u32,
    /// Width of the i_ps output (1 ..= 16, default 8: saturates at 255).
    pub out_bits: u32,
}

impl Default for GlareConditionConfig {
    fn default() -> Self {
        GlareConditionConfig {
            int_bits: 12,
            frac_bits: 4,
            coef_bits: 8,
            cos_frac_bits: 14,
            eta: 1.333,
            eta_frac_bits: 14,
            threshold: 40,
            out_bits: 8,
        }
    }
}

impl GlareConditionConfig {
    /// Validate; errors name `glare_condition.<field>`.
    pub fn build(&self) -> Result<GlareCondition, ConfigError> {
        let f = |n: &str| format!("{NAME}.{n}");
        check_range(&f("int_bits"), self.int_bits as u64, 0, 16)?;
        check_range(&f("frac_bits"), self.frac_bits as u64, 0, 16)?;
        if self.int_bits + self.frac_bits == 0 {
            return Err(ConfigError::invalid(
                &f("frac_bits"),
                "int_bits + frac_bits must be at least 1",
            ));
        }
        check_range(&f("coef_bits"), self.coef_bits as u64, 1, 16)?;
        check_range(&f("cos_frac_bits"), self.cos_frac_bits as u64, 1, 16)?;
        check_range(&f("eta_frac_bits"), self.eta_frac_bits as u64, 1, 16)?;
        check_range(&f("threshold"), self.threshold as u64, 0, 65535)?;
        check_range(&f("out_bits"), self.out_bits as u64, 1, 16)?;
        let eta = check_finite(&f("eta"), self.eta)?;
        let scale = (self.eta_frac_bits as f64).exp2();
        let code = (eta * scale).round();
        let max = ((1u64 << (self.eta_frac_bits + 2)) - 1) as f64;
        if !(0.0..=max).contains(&code) {
            return Err(ConfigError::out_of_range(&f("eta"), eta, 0.0, max / scale));
        }
        Ok(GlareCondition {
            cfg: *self,
            eta_code: code as u32,
        })
    }
}

/// The validated unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GlareCondition {
    cfg: GlareConditionConfig,
    eta_code: u32,
}

/// One highlight.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ConditionIn {
    /// Which formula applies: metallic or water.
    pub material: Material,
    /// I, u(int_bits).(frac_bits).
    pub intensity: u32,
    /// I_s, unorm `coef_bits` (metallic only).
    pub specular: u32,
    /// cos α, s1.(cos_frac_bits).
    pub cos_alpha: i32,
    /// cos θ, s1.(cos_frac_bits): incidence cosine for the TIR test (water only).
    pub cos_theta: i32,
    /// I_a, same format as I.
    pub ambient: u32,
}

/// The decision.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct ConditionOut {
    /// contrast_ok (metallic) or contrast_ok ∧ tir (water).
    pub glare: bool,
    /// Total internal reflection (always false for metallic).
    pub tir: bool,
    /// min(round(I_ps), 2^out_bits − 1) in framebuffer codes.
    pub i_ps: u32,
    /// I_ps ≥ T·I_a.
    pub contrast_ok: bool,
}

impl GlareCondition {
    /// GeForce-era defaults (u12.4 intensities, 8-bit I_s, s1.14 cosines, η = 1.333,
    /// T = 40, 8-bit output).
    pub fn geforce() -> Self {
        GlareConditionConfig::default()
            .build()
            .expect("defaults are valid")
    }

    /// The config the unit was built from (η as given, before quantising).
    pub fn config(&self) -> GlareConditionConfig {
        self.cfg
    }

    /// η as its u2.ef code.
    pub fn eta_code(&self) -> u32 {
        self.eta_code
    }

    /// The quantised η the datapath uses.
    pub fn eta_value(&self) -> f64 {
        self.eta_code as f64 / (self.cfg.eta_frac_bits as f64).exp2()
    }

    fn iw(&self) -> u32 {
        self.cfg.int_bits + self.cfg.frac_bits
    }

    /// Replication width of I_s: W = max(cb, ib+fb+1).
    pub fn spec_rep_bits(&self) -> u32 {
        self.cfg.coef_bits.max(self.iw() + 1)
    }

    /// Quantise an intensity (I or I_a, framebuffer codes) to u(ib).(fb), round to
    /// nearest; NaN/∞, negative or too large is an error naming `field`.
    pub fn intensity_from_f64(&self, x: f64, field: &str) -> Result<u32, ConfigError> {
        let x = check_finite(field, x)?;
        let s = (self.cfg.frac_bits as f64).exp2();
        let code = (x * s).round();
        let max = mask32(self.iw()) as f64;
        if !(0.0..=max).contains(&code) {
            return Err(ConfigError::out_of_range(field, x, 0.0, max / s));
        }
        Ok(code as u32)
    }

    /// Quantise I_s ∈ [0, 1] to a unorm code (error names `glare_condition.specular`).
    pub fn specular_from_f64(&self, x: f64) -> Result<u32, ConfigError> {
        let field = format!("{NAME}.specular");
        let x = check_finite(&field, x)?;
        if !(0.0..=1.0).contains(&x) {
            return Err(ConfigError::out_of_range(&field, x, 0.0, 1.0));
        }
        Ok((x * mask32(self.cfg.coef_bits) as f64).round() as u32)
    }

    /// Quantise a cosine to s1.cf (round to nearest, saturating to [−1, 1 − 2^−cf]:
    /// cos = 1 becomes the largest code); NaN/∞ is an error naming `field`.
    pub fn cos_from_f64(&self, x: f64, field: &str) -> Result<i32, ConfigError> {
        let x = check_finite(field, x)?;
        let one = 1i64 << self.cfg.cos_frac_bits;
        let code = (x * one as f64)
            .round()
            .clamp(-one as f64, (one - 1) as f64);
        Ok(code as i32)
    }

    /// Quantise a whole highlight (fields `glare_condition.intensity`, `.specular`,
    /// `.cos_alpha`, `.cos_theta`, `.ambient`).
    pub fn input_from_f64(
        &self,
        material: Material,
        intensity: f64,
        specular: f64,
        cos_alpha: f64,
        cos_theta: f64,
        ambient: f64,
    ) -> Result<ConditionIn, ConfigError> {
        Ok(ConditionIn {
            material,
            intensity: self.intensity_from_f64(intensity, &format!("{NAME}.intensity"))?,
            specular: self.specular_from_f64(specular)?,
            cos_alpha: self.cos_from_f64(cos_alpha, &format!("{NAME}.cos_alpha"))?,
            cos_theta: self.cos_from_f64(cos_theta, &format!("{NAME}.cos_theta"))?,
            ambient: self.intensity_from_f64(ambient, &format!("{NAME}.ambient"))?,
        })
    }

    /// I_ps as a u(ib).(fb) code (before the output rounding and clamp).
    #[inline]
    pub fn i_ps_code(&self, input: &ConditionIn) -> u64 {
        let cf = self.cfg.cos_frac_bits;
        let cb = self.cfg.coef_bits;
        let w = self.spec_rep_bits();
        let i = (input.intensity & mask32(self.iw())) as u128; // u(ib+fb)
        let a = sext(input.cos_alpha, cf + 1).max(0) as u128; // u(cf+1), ≤ 2^cf − 1
        let k = match input.material {
            Material::Metallic => {
                let s = (input.specular & mask32(cb)) as u64; // u(cb)
                                                              // I_s as u1.W: replicated code + top bit (1.0 exact; |err| ≤ 2^−W).
                let srep = (replicate(s, cb, w) + (s >> (cb - 1))) as u128; // u(W+1)
                let sq = a * a; // u(cf+1)² → u(2cf+2), ≤ 2^(2cf)
                srep * sq // u1.W × u1.(2cf) → u1.(W+2cf) (value ≤ 1)
            }
            Material::Water => a << (w + cf), // u1.cf → u1.(W+2cf), exact
        };
        // u(ib+fb) × u1.(W+2cf) → u(ib+fb+1).(W+2cf); round off W+2cf bits → u(ib).(fb).
        let sh = w + 2 * cf;
        ((i * k + (1u128 << (sh - 1))) >> sh) as u64
    }

    /// TIR test η²(1 − cos²θ) > 1, exact on the codes.
    #[inline]
    pub fn tir(&self, cos_theta: i32) -> bool {
        let cf = self.cfg.cos_frac_bits;
        let ef = self.cfg.eta_frac_bits;
        let ct = sext(cos_theta, cf + 1).unsigned_abs() as u128; // |s1.cf| → u(cf+1)
        let one_minus = (1u128 << (2 * cf)) - ct * ct; // u(2cf+1), ≥ 0 (|ct| ≤ 2^cf)
        let e = self.eta_code as u128; // u2.ef
        let e2 = e * e; // u(2ef+4)
        e2 * one_minus > 1u128 << (2 * cf + 2 * ef) // u(2ef+4) × u(2cf+1) → ≤ 69 bits
    }
}

impl Unit for GlareCondition {
    type In = ConditionIn;
    type Out = ConditionOut;
    type State = ();

    fn name(&self) -> &'static str {
        NAME
    }

    fn kernel(&self, _: &mut (), input: &ConditionIn, ctr: &mut Counters) -> ConditionOut {
        let fb = self.cfg.frac_bits;
        let ips = self.i_ps_code(input); // u(ib).(fb)
        let ia = (input.ambient & mask32(self.iw())) as u64; // u(ib).(fb)
                                                             // T·I_a: constant shift-add (T = 40: (I_a<<5) + (I_a<<3)) → u(ib+fb+16).
        let t_ia = ia * self.cfg.threshold as u64;
        let contrast_ok = ips >= t_ia;
        let tir = match input.material {
            Material::Metallic => false,
            Material::Water => self.tir(input.cos_theta),
        };
        let glare = contrast_ok && (input.material == Material::Metallic || tir);
        // Round to framebuffer codes: u(ib).(fb) → u(ib+1) ...
        let r = if fb == 0 {
            ips
        } else {
            (ips + (1u64 << (fb - 1))) >> fb
        };
        // ... and clamp to u(out_bits).
        let max = mask32(self.cfg.out_bits) as u64;
        let i_ps = if r > max {
            ctr.saturations += 1;
            max
        } else {
            r
        } as u32;
        ConditionOut {
            glare,
            tir,
            i_ps,
            contrast_ok,
        }
    }

    fn timing(&self) -> Timing {
        Timing { latency: 3, ii: 1 }
    }

    fn cost(&self) -> Cost {
        let c = self.cfg;
        let iw = self.iw();
        let cf = c.cos_frac_bits;
        let ef = c.eta_frac_bits;
        let w = self.spec_rep_bits();
        let tb = 32 - c.threshold.leading_zeros(); // bits of T
        let t_adders = c.threshold.count_ones().saturating_sub(1);
        let or = |n: u32| Cells {
            or2: n as f64,
            ..Cells::default()
        };
        Cost::default()
            .part("cos α clamp at 0 (cf+1 AND)", {
                Cells {
                    and2: (cf + 1) as f64,
                    ..Cells::default()
                }
            })
            .part("cos²α multiplier (cf+1)²", prim::multiplier(cf + 1, cf + 1))
            .part(
                "I_s → u1.W (+ top bit incrementer)",
                prim::half_adder() * w as f64,
            )
            .part(
                "I_s × cos²α multiplier (W+1)×(2cf+1)",
                prim::multiplier(w + 1, 2 * cf + 1),
            )
            .part("material select of k", prim::mux(w + 2 * cf + 1))
            .part(
                "I × k multiplier (ib+fb)×(W+2cf+1) + round",
                prim::multiplier(iw, w + 2 * cf + 1) + prim::half_adder() * iw as f64,
            )
            .part(
                "T·I_a shift-add (popcount(T) − 1 adders)",
                prim::adder(iw + tb) * t_adders as f64,
            )
            .part("contrast comparator", prim::comparator(iw + tb))
            .part(
                "|cos θ| and cos²θ multiplier",
                prim::subtractor(cf + 1) + prim::mux(cf + 1) + prim::multiplier(cf + 1, cf + 1),
            )
            .part("1 − cos²θ subtractor", prim::subtractor(2 * cf + 1))
            .part(
                "η² × (1 − cos²θ) multiplier (η² a constant: precomputed register)",
                prim::multiplier(2 * ef + 4, 2 * cf + 1) + prim::register(2 * ef + 4),
            )
            .part("TIR comparator", prim::comparator(2 * ef + 2 * cf + 5))
            .part(
                "output round + clamp",
                prim::half_adder() * c.int_bits as f64 + or(c.int_bits + 1 + c.out_bits),
            )
            .part(
                "pipeline registers",
                prim::register(
                    // stage 1: I, I_a, I_s·cos² / cos, 1 − cos²θ, material
                    2 * iw + (w + 2 * cf + 1) + (2 * cf + 1) + 1
                    // stage 2: I_ps, T·I_a, TIR, material
                    + iw + (iw + tb) + 2
                    // stage 3: outputs
                    + c.out_bits + 3,
                ),
            )
    }

    fn widths(&self) -> Vec<Width> {
        let c = self.cfg;
        vec![
            Width {
                name: "int_bits",
                bits: c.int_bits,
            },
            Width {
                name: "frac_bits",
                bits: c.frac_bits,
            },
            Width {
                name: "coef_bits",
                bits: c.coef_bits,
            },
            Width {
                name: "cos_frac_bits",
                bits: c.cos_frac_bits,
            },
            Width {
                name: "eta_frac_bits",
                bits: c.eta_frac_bits,
            },
            Width {
                name: "out_bits",
                bits: c.out_bits,
            },
        ]
    }

    fn in_signals(&self, i: &ConditionIn) -> Vec<Signal> {
        let iw = self.iw();
        let cw = self.cfg.cos_frac_bits + 1;
        let cb = self.cfg.coef_bits;
        vec![
            Signal::new("water", 1, (i.material == Material::Water) as u64),
            Signal::new("intensity", iw, (i.intensity & mask32(iw)) as u64),
            Signal::new("specular", cb, (i.specular & mask32(cb)) as u64),
            Signal::new("cos_alpha", cw, (i.cos_alpha as u32 & mask32(cw)) as u64),
            Signal::new("cos_theta", cw, (i.cos_theta as u32 & mask32(cw)) as u64),
            Signal::new("ambient", iw, (i.ambient & mask32(iw)) as u64),
        ]
    }

    fn out_signals(&self, o: &ConditionOut) -> Vec<Signal> {
        vec![
            Signal::new("glare", 1, o.glare as u64),
            Signal::new("tir", 1, o.tir as u64),
            Signal::new("i_ps", self.cfg.out_bits, o.i_ps as u64),
            Signal::new("contrast_ok", 1, o.contrast_ok as u64),
        ]
    }
}
