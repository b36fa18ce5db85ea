//! texture_combiner — one texture-environment stage in COMBINE mode
//! (GL_ARB_texture_env_combine, GL_ARB_texture_env_dot3; core in OpenGL 1.3, §3.8.13).
//!
//! The stage sees four RGBA sources (TEXTURE, CONSTANT, PRIMARY_COLOR, PREVIOUS) on its
//! input word; the config picks Arg0..Arg2 for RGB (`SOURCEi_RGB`, `OPERANDi_RGB`) and for
//! alpha (`SOURCEi_ALPHA`, `OPERANDi_ALPHA`), the functions `COMBINE_RGB` and
//! `COMBINE_ALPHA`, and `RGB_SCALE` / `ALPHA_SCALE` ∈ {1, 2, 4}. The functions, with
//! every value in [0, 1] and the result clamped to [0, 1] after the scale:
//!
//! | COMBINE_RGB / COMBINE_ALPHA | result                                            |
//! |-----------------------------|---------------------------------------------------|
//! | REPLACE                     | Arg0                                              |
//! | MODULATE                    | Arg0 · Arg1                                       |
//! | ADD                         | Arg0 + Arg1                                       |
//! | ADD_SIGNED                  | Arg0 + Arg1 − 0.5                                 |
//! | INTERPOLATE                 | Arg0 · Arg2 + Arg1 · (1 − Arg2)                   |
//! | SUBTRACT                    | Arg0 − Arg1                                       |
//! | DOT3_RGB (RGB only)         | 4·((Arg0r−0.5)(Arg1r−0.5) + (Arg0g−0.5)(Arg1g−0.5) + (Arg0b−0.5)(Arg1b−0.5)) into r, g, b |
//! | DOT3_RGBA (RGB only)        | the same scalar into r, g, b and a; COMBINE_ALPHA is ignored |
//!
//! OPERANDi_RGB is SRC_COLOR (c), ONE_MINUS_SRC_COLOR (1 − c), SRC_ALPHA (a) or
//! ONE_MINUS_SRC_ALPHA (1 − a); OPERANDi_ALPHA is SRC_ALPHA or ONE_MINUS_SRC_ALPHA.
//! DOT3_RGBA's alpha is scaled by ALPHA_SCALE (as Mesa does; the spec only says the
//! dot "is placed into" alpha).
//!
//! Widths (n = `bits`, 8 by default, 1 ..= 16; N = 2ⁿ − 1 stands for 1.0): every source
//! u(n); 1 − c is N − c (the bitwise NOT); each function's exact value in output codes is
//! X / D with an integer X and a divisor D ∈ {1, 2, N} (see [`TextureCombiner::exact`]):
//! REPLACE, ADD, SUBTRACT D = 1; ADD_SIGNED D = 2 (X = s·(2(a0 + a1) − N), s(n+5));
//! MODULATE, INTERPOLATE D = N (X ≤ 4N², u(2n+2)); DOT3 D = N with
//! X = s·Σ(2a0 − N)(2a1 − N) (each factor s(n+1), X s(2n+6)). X < 0 clamps to 0 and
//! X > N·D to N (both counted in `saturations`); then one rounding per stage:
//!
//! - [`CombinerRounding::GeforceInteger`] (default): round half up, once. D = N by the
//!   shift-add t = X + 2ⁿ⁻¹, (t + (t >> n)) >> n (exact for 0 ≤ X ≤ N²; a tie cannot
//!   occur since N is odd); D = 2 by (X + 1) >> 1 — ADD_SIGNED at scale 1 is the only
//!   function whose exact value is always a tie (a0 + a1 − N/2), and it gives
//!   a0 + a1 − (N − 1)/2 (−127 at 8 bits).
//! - [`CombinerRounding::MesaFloat32`]: what Mesa 22.3 (llvmpipe and softpipe, OSMesa)
//!   computes. Mesa evaluates the stage in IEEE binary32 and converts to unorm with
//!   round-to-nearest-even; away from ties its float error (≤ 10⁻³ LSB at 8 bits) never
//!   moves the nearest code, so every function but ADD_SIGNED at scale 1 is the same
//!   integer result as the default. ADD_SIGNED at scale 1 is all ties, and Mesa's
//!   float rounding decides them: the unit evaluates Mesa's binary32 expression with an
//!   integer soft-float ([`binary32`]): Argᵢ' = fl(cᵢ · fl(1/N)),
//!   v = fl(fl(Arg0' − 0.5) + Arg1'), where ONE_MINUS on Arg0 is folded to
//!   fl(0.5 − Arg0') and ONE_MINUS on Arg1 is fl(1 − Arg1'), then the unorm conversion
//!   fl(fl(v · (1 − 2⁻ⁿ)) + 2²³⁻ⁿ)'s low n mantissa bits. (Found by measurement against
//!   OSMesa; tests/texture_combiner_mesa.rs holds it to 3.9·10⁷ 8-bit channel results,
//!   every ADD_SIGNED pair under every operand mapping among them.) At other widths the
//!   mode is the same rule with n-bit unorms, an extrapolation: only 8 bits is checked.

use crate::cost::{prim, Cells, Cost};
use crate::counters::Counters;
use crate::error::ConfigError;
use crate::unit::{Signal, Timing, Unit, Width};
use crate::unorm::{check_bits, max_code};
use serde::{Deserialize, Serialize};

/// COMBINE_RGB / COMBINE_ALPHA. The DOT3 functions are valid for RGB only.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CombineFunction {
    /// Arg0.
    Replace,
    /// Arg0 · Arg1.
    Modulate,
    /// Arg0 + Arg1 (the scaled result clamps to 1, counted in `saturations`).
    Add,
    /// Arg0 + Arg1 − 0.5, clamped to [0, 1]; at scale 1 every exact result is a tie,
    /// which the `rounding` mode breaks.
    AddSigned,
    /// Arg0 · Arg2 + Arg1 · (1 − Arg2): a lerp weighted by Arg2.
    Interpolate,
    /// Arg0 − Arg1 (a negative result clamps to 0, counted in `saturations`).
    Subtract,
    /// 4·Σ (Arg0 − 0.5)(Arg1 − 0.5) over r, g, b, the scalar written to r, g, b (RGB only).
    Dot3Rgb,
    /// The same scalar into r, g, b and a; COMBINE_ALPHA is ignored (RGB only).
    Dot3Rgba,
}

impl CombineFunction {
    /// Every function, in GL's order; the DOT3 ones last.
    pub const ALL: [CombineFunction; 8] = [
        CombineFunction::Replace,
        CombineFunction::Modulate,
        CombineFunction::Add,
        CombineFunction::AddSigned,
        CombineFunction::Interpolate,
        CombineFunction::Subtract,
        CombineFunction::Dot3Rgb,
        CombineFunction::Dot3Rgba,
    ];

    /// The functions COMBINE_ALPHA accepts (all but the DOT3 ones, the last two).
    pub const ALPHA: &'static [CombineFunction] = (&Self::ALL as &[CombineFunction]).split_at(6).0;

    /// True for DOT3_RGB and DOT3_RGBA (the RGB-only functions).
    pub fn is_dot3(self) -> bool {
        matches!(self, CombineFunction::Dot3Rgb | CombineFunction::Dot3Rgba)
    }
}

/// SOURCEi_RGB / SOURCEi_ALPHA: which of the input word's four colours an argument reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CombineSource {
    /// TEXTURE: the stage's texel.
    Texture,
    /// CONSTANT: the texture environment colour.
    Constant,
    /// PRIMARY_COLOR: the fragment's interpolated primary colour.
    PrimaryColor,
    /// PREVIOUS: the previous stage's result (the primary colour at stage 0).
    Previous,
}

impl CombineSource {
    /// Every source, in GL's order.
    pub const ALL: [CombineSource; 4] = [
        CombineSource::Texture,
        CombineSource::Constant,
        CombineSource::PrimaryColor,
        CombineSource::Previous,
    ];
}

/// OPERANDi_RGB: the colour or the alpha of the source, optionally 1 − it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum OperandRgb {
    /// c: the source's colour channel.
    SrcColor,
    /// 1 − c (N − c, the bitwise NOT).
    OneMinusSrcColor,
    /// a: the source's alpha, on every colour channel.
    SrcAlpha,
    /// 1 − a on every colour channel.
    OneMinusSrcAlpha,
}

impl OperandRgb {
    /// Every RGB operand, in GL's order.
    pub const ALL: [OperandRgb; 4] = [
        OperandRgb::SrcColor,
        OperandRgb::OneMinusSrcColor,
        OperandRgb::SrcAlpha,
        OperandRgb::OneMinusSrcAlpha,
    ];

    fn reads_alpha(self) -> bool {
        matches!(self, OperandRgb::SrcAlpha | OperandRgb::OneMinusSrcAlpha)
    }

    fn inverts(self) -> bool {
        matches!(
            self,
            OperandRgb::OneMinusSrcColor | OperandRgb::OneMinusSrcAlpha
        )
    }
}

/// OPERANDi_ALPHA: the source's alpha or 1 − it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum OperandAlpha {
    /// a: the source's alpha.
    SrcAlpha,
    /// 1 − a (N − a, the bitwise NOT).
    OneMinusSrcAlpha,
}

impl OperandAlpha {
    /// Both alpha operands.
    pub const ALL: [OperandAlpha; 2] = [OperandAlpha::SrcAlpha, OperandAlpha::OneMinusSrcAlpha];
}

/// Where GL leaves the rounding to the implementation (see the module doc).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CombinerRounding {
    /// One round-half-up per stage on the exact integer X / D (GeForce-style 8-bit).
    GeforceInteger,
    /// Mesa's binary32 evaluation: round to nearest, ADD_SIGNED's ties as Mesa's floats
    /// break them.
    MesaFloat32,
}

impl CombinerRounding {
    /// Both rounding modes, the default first.
    pub const ALL: [CombinerRounding; 2] = [
        CombinerRounding::GeforceInteger,
        CombinerRounding::MesaFloat32,
    ];
}

/// The stage's texture-environment state (GL names in the field docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct TextureCombinerConfig {
    /// Unorm width of every source and of the result (1 ..= 16).
    pub bits: u32,
    /// COMBINE_RGB.
    pub combine_rgb: CombineFunction,
    /// COMBINE_ALPHA (not a DOT3 function; ignored under DOT3_RGBA).
    pub combine_alpha: CombineFunction,
    /// SOURCE0_RGB .. SOURCE2_RGB.
    pub source_rgb: [CombineSource; 3],
    /// OPERAND0_RGB .. OPERAND2_RGB.
    pub operand_rgb: [OperandRgb; 3],
    /// SOURCE0_ALPHA .. SOURCE2_ALPHA.
    pub source_alpha: [CombineSource; 3],
    /// OPERAND0_ALPHA .. OPERAND2_ALPHA.
    pub operand_alpha: [OperandAlpha; 3],
    /// RGB_SCALE: 1, 2 or 4.
    pub rgb_scale: u32,
    /// ALPHA_SCALE: 1, 2 or 4.
    pub alpha_scale: u32,
    /// How the stage rounds (default `geforce_integer`).
    pub rounding: CombinerRounding,
}

impl TextureCombinerConfig {
    /// GL's initial COMBINE state on an 8-bit GeForce: MODULATE of
    /// (TEXTURE, PREVIOUS, CONSTANT) with SRC_COLOR / SRC_ALPHA, scales 1, integer
    /// rounding.
    pub fn geforce() -> Self {
        TextureCombinerConfig {
            bits: 8,
            combine_rgb: CombineFunction::Modulate,
            combine_alpha: CombineFunction::Modulate,
            source_rgb: [
                CombineSource::Texture,
                CombineSource::Previous,
                CombineSource::Constant,
            ],
            operand_rgb: [
                OperandRgb::SrcColor,
                OperandRgb::SrcColor,
                OperandRgb::SrcAlpha,
            ],
            source_alpha: [
                CombineSource::Texture,
                CombineSource::Previous,
                CombineSource::Constant,
            ],
            operand_alpha: [OperandAlpha::SrcAlpha; 3],
            rgb_scale: 1,
            alpha_scale: 1,
            rounding: CombinerRounding::GeforceInteger,
        }
    }

    /// The same functions with every argument SRC_COLOR / SRC_ALPHA of Arg0 =
    /// TEXTURE, Arg1 = CONSTANT, Arg2 = PRIMARY_COLOR (what the tests sweep).
    pub fn with_functions(
        bits: u32,
        rgb: CombineFunction,
        alpha: CombineFunction,
        rounding: CombinerRounding,
    ) -> Self {
        let order = [
            CombineSource::Texture,
            CombineSource::Constant,
            CombineSource::PrimaryColor,
        ];
        TextureCombinerConfig {
            bits,
            combine_rgb: rgb,
            combine_alpha: alpha,
            source_rgb: order,
            operand_rgb: [OperandRgb::SrcColor; 3],
            source_alpha: order,
            operand_alpha: [OperandAlpha::SrcAlpha; 3],
            rgb_scale: 1,
            alpha_scale: 1,
            rounding,
        }
    }

    /// Validate (errors name `texture_combiner.<field>`).
    pub fn build(self) -> Result<TextureCombiner, ConfigError> {
        check_bits("texture_combiner.bits", self.bits)?;
        if self.combine_alpha.is_dot3() {
            return Err(ConfigError::invalid(
                "texture_combiner.combine_alpha",
                "DOT3_RGB and DOT3_RGBA are RGB functions only",
            ));
        }
        for (field, s) in [
            ("texture_combiner.rgb_scale", self.rgb_scale),
            ("texture_combiner.alpha_scale", self.alpha_scale),
        ] {
            if !matches!(s, 1 | 2 | 4) {
                return Err(ConfigError::invalid(
                    field,
                    &format!("{s} is not a GL scale (1, 2 or 4)"),
                ));
            }
        }
        Ok(TextureCombiner { cfg: self })
    }
}

/// One fragment: the four RGBA sources the stage can read, each channel u(n).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct TextureCombinerIn {
    /// TEXTURE: the stage's texel, RGBA.
    pub texture: [u32; 4],
    /// CONSTANT: the texture environment colour, RGBA.
    pub constant: [u32; 4],
    /// PRIMARY_COLOR: the fragment's primary colour, RGBA.
    pub primary_color: [u32; 4],
    /// PREVIOUS: the previous stage's result, RGBA.
    pub previous: [u32; 4],
}

impl TextureCombinerIn {
    fn source(&self, s: CombineSource) -> [u32; 4] {
        match s {
            CombineSource::Texture => self.texture,
            CombineSource::Constant => self.constant,
            CombineSource::PrimaryColor => self.primary_color,
            CombineSource::Previous => self.previous,
        }
    }
}

/// One argument as the datapath sees it: the selected source code and whether the
/// operand mapping inverts it (ONE_MINUS_*). Its value is N − code when inverted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CombineArg {
    /// The selected source channel, a u(n) code.
    pub code: u32,
    /// ONE_MINUS_*: the operand is N − code.
    pub invert: bool,
}

impl CombineArg {
    /// The mapped operand, u(n): code or N − code (the bitwise NOT).
    #[inline]
    pub fn value(self, max: u32) -> u32 {
        if self.invert {
            max - self.code
        } else {
            self.code
        }
    }
}

/// The validated stage.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TextureCombiner {
    cfg: TextureCombinerConfig,
}

impl TextureCombiner {
    /// Validate; the same as [`TextureCombinerConfig::build`], errors name
    /// `texture_combiner.<field>`.
    pub fn new(cfg: TextureCombinerConfig) -> Result<Self, ConfigError> {
        cfg.build()
    }

    /// GL's initial COMBINE state on an 8-bit GeForce (see
    /// [`TextureCombinerConfig::geforce`]).
    pub fn geforce() -> Self {
        TextureCombiner {
            cfg: TextureCombinerConfig::geforce(),
        }
    }

    /// The stage's texture-environment state.
    pub fn config(&self) -> &TextureCombinerConfig {
        &self.cfg
    }

    fn max(&self) -> u32 {
        max_code(self.cfg.bits)
    }

    /// Arg0..Arg2 of RGB channel `ch` (0 ..= 2) after SOURCEi_RGB and OPERANDi_RGB.
    pub fn rgb_args(&self, input: &TextureCombinerIn, ch: usize) -> [CombineArg; 3] {
        let m = self.max();
        std::array::from_fn(|i| {
            let op = self.cfg.operand_rgb[i];
            let src = input.source(self.cfg.source_rgb[i]);
            CombineArg {
                code: src[if op.reads_alpha() { 3 } else { ch }] & m,
                invert: op.inverts(),
            }
        })
    }

    /// Arg0..Arg2 of alpha after SOURCEi_ALPHA and OPERANDi_ALPHA.
    pub fn alpha_args(&self, input: &TextureCombinerIn) -> [CombineArg; 3] {
        let m = self.max();
        std::array::from_fn(|i| CombineArg {
            code: input.source(self.cfg.source_alpha[i])[3] & m,
            invert: self.cfg.operand_alpha[i] == OperandAlpha::OneMinusSrcAlpha,
        })
    }

    /// The exact value of a (non-DOT3) function on one channel, in output codes, as
    /// (X, D): value = X / D before the clamp. `scale` ∈ {1, 2, 4}.
    pub fn exact(&self, f: CombineFunction, args: &[CombineArg; 3], scale: u32) -> (i64, i64) {
        let n = self.max() as i64;
        let [a0, a1, a2] = args.map(|a| a.value(self.max()) as i64);
        let s = scale as i64;
        match f {
            CombineFunction::Replace => (s * a0, 1), // u(n) << 2 → u(n+2)
            CombineFunction::Add => (s * (a0 + a1), 1), // u(n+1) << 2 → u(n+3)
            CombineFunction::Subtract => (s * (a0 - a1), 1), // s(n+1) << 2 → s(n+3)
            // 2(a0 + a1) − N: s(n+3), odd; scaled s(n+5).
            CombineFunction::AddSigned => (s * (2 * (a0 + a1) - n), 2),
            CombineFunction::Modulate => (s * a0 * a1, n), // u(n) × u(n) → u(2n), << 2
            // a0·a2 + a1·(N − a2) ≤ N²: u(2n), << 2 → u(2n+2).
            CombineFunction::Interpolate => (s * (a0 * a2 + a1 * (n - a2)), n),
            CombineFunction::Dot3Rgb | CombineFunction::Dot3Rgba => {
                unreachable!("DOT3 is a three-channel function: see dot3_exact")
            }
        }
    }

    /// DOT3's exact scalar in output codes as (X, N): X = s·Σ(2a0 − N)(2a1 − N)
    /// (each factor s(n+1), each product s(2n+2), the sum s(2n+4), scaled s(2n+6)),
    /// since 4(a0/N − ½)(a1/N − ½)·N = (2a0 − N)(2a1 − N)/N.
    pub fn dot3_exact(&self, args: &[[CombineArg; 3]; 3], scale: u32) -> (i64, i64) {
        let m = self.max();
        let n = m as i64;
        let sum: i64 = args
            .iter()
            .map(|a| (2 * a[0].value(m) as i64 - n) * (2 * a[1].value(m) as i64 - n))
            .sum();
        (scale as i64 * sum, n)
    }

    /// Clamp X / D (D ∈ {1, 2, N}) to [0, N], counting a clamp, and round once, half
    /// up: the stage's single rounding.
    pub fn clamp_round(&self, (x, d): (i64, i64), ctr: &mut Counters) -> u32 {
        let bits = self.cfg.bits;
        let m = self.max() as i64;
        if x < 0 {
            ctr.saturations += 1;
            return 0;
        }
        if x > m * d {
            ctr.saturations += 1;
            return m as u32;
        }
        match d {
            1 => x as u32,
            2 => ((x + 1) >> 1) as u32, // half up: X odd only for ADD_SIGNED at scale 1
            _ => {
                // round(X / N) for 0 ≤ X ≤ N²: t = X + 2ⁿ⁻¹ (u(2n)+1 bit);
                // (t + (t >> n)) >> n (u(2n+1) >> n → u(n)).
                let t = x + (1 << (bits - 1));
                ((t + (t >> bits)) >> bits) as u32
            }
        }
    }

    /// One channel of a non-DOT3 function, rounded per the config.
    fn channel(
        &self,
        f: CombineFunction,
        args: &[CombineArg; 3],
        scale: u32,
        ctr: &mut Counters,
    ) -> u32 {
        let exact = self.exact(f, args, scale);
        if f == CombineFunction::AddSigned
            && scale == 1
            && self.cfg.rounding == CombinerRounding::MesaFloat32
        {
            // Count the clamp on the exact value; Mesa's float decides the code.
            let m = self.max() as i64;
            if exact.0 < 0 || exact.0 > 2 * m {
                ctr.saturations += 1;
            }
            return binary32::mesa_add_signed(args[0], args[1], self.cfg.bits);
        }
        self.clamp_round(exact, ctr)
    }

    /// The stage on one fragment: RGBA out, each u(n).
    pub fn combine(&self, input: &TextureCombinerIn, ctr: &mut Counters) -> [u32; 4] {
        let c = &self.cfg;
        let rgb_args: [[CombineArg; 3]; 3] = std::array::from_fn(|ch| self.rgb_args(input, ch));
        let mut out = [0u32; 4];
        if c.combine_rgb.is_dot3() {
            let x = self.dot3_exact(&rgb_args, c.rgb_scale);
            let v = self.clamp_round(x, ctr);
            out[..3].fill(v);
        } else {
            for ch in 0..3 {
                out[ch] = self.channel(c.combine_rgb, &rgb_args[ch], c.rgb_scale, ctr);
            }
        }
        out[3] = if c.combine_rgb == CombineFunction::Dot3Rgba {
            let x = self.dot3_exact(&rgb_args, c.alpha_scale);
            self.clamp_round(x, ctr)
        } else {
            self.channel(c.combine_alpha, &self.alpha_args(input), c.alpha_scale, ctr)
        };
        out
    }
}

/// IEEE-754 binary32 arithmetic on bit patterns, integers only, round to nearest even:
/// the float datapath Mesa's ADD_SIGNED runs on. Only zero and normal numbers occur
/// (every value is 0 or of magnitude ≥ 2⁻⁴⁰), so there are no subnormals, infinities
/// or NaNs to handle.
pub mod binary32 {
    use super::CombineArg;
    use crate::unorm::max_code;

    /// 1.0 as a binary32 bit pattern.
    pub const ONE: u32 = 0x3f80_0000;
    /// 0.5 as a binary32 bit pattern.
    pub const HALF: u32 = 0x3f00_0000;

    /// (negative, significand with its hidden bit (u24), exponent of its LSB):
    /// value = ±sig · 2^exp.
    fn decode(x: u32) -> (bool, u64, i32) {
        let biased = ((x >> 23) & 0xff) as i32;
        let frac = (x & 0x7f_ffff) as u64;
        let sig = if biased == 0 { 0 } else { frac | 0x80_0000 };
        (x >> 31 == 1, sig, biased - 150)
    }

    /// The binary32 nearest (ties to even) to ±mag · 2^exp.
    pub fn round(negative: bool, mag: u128, exp: i32) -> u32 {
        if mag == 0 {
            return 0;
        }
        let len = 128 - mag.leading_zeros() as i32;
        let (mut q, mut e) = if len > 24 {
            let sh = (len - 24) as u32;
            let q = (mag >> sh) as u64;
            let rem = mag & ((1u128 << sh) - 1);
            let half = 1u128 << (sh - 1);
            let up = rem > half || (rem == half && q & 1 == 1);
            (q + up as u64, exp + sh as i32)
        } else {
            ((mag as u64) << (24 - len), exp - (24 - len))
        };
        if q == 1 << 24 {
            q >>= 1;
            e += 1;
        }
        let biased = e + 150;
        debug_assert!((1..255).contains(&biased), "binary32 out of normal range");
        ((negative as u32) << 31) | ((biased as u32) << 23) | (q as u32 & 0x7f_ffff)
    }

    /// fl(a · b).
    pub fn mul(a: u32, b: u32) -> u32 {
        let (na, sa, ea) = decode(a);
        let (nb, sb, eb) = decode(b);
        round(na != nb, (sa * sb) as u128, ea + eb) // u24 × u24 → u48
    }

    /// fl(a + b).
    pub fn add(a: u32, b: u32) -> u32 {
        let (na, sa, ea) = decode(a);
        let (nb, sb, eb) = decode(b);
        if sa == 0 {
            return b;
        }
        if sb == 0 {
            return a;
        }
        // Align to the smaller exponent; beyond 100 bits apart the smaller addend is
        // far below half an ulp of the larger and cannot change the rounding.
        let e0 = ea.min(eb).max(ea.max(eb) - 100);
        let signed = |neg: bool, s: u64, e: i32| -> i128 {
            let v = if e >= e0 { (s as i128) << (e - e0) } else { 0 };
            if neg {
                -v
            } else {
                v
            }
        };
        let sum = signed(na, sa, ea) + signed(nb, sb, eb); // ≤ 125 bits
        round(sum < 0, sum.unsigned_abs(), e0)
    }

    /// fl(a − b).
    pub fn sub(a: u32, b: u32) -> u32 {
        add(a, b ^ 0x8000_0000)
    }

    /// fl(1 / (2ⁿ − 1)): the constant unorm → float conversion multiplies by.
    pub fn reciprocal_of_max(bits: u32) -> u32 {
        let m = max_code(bits) as u128;
        let q = (1u128 << 80) / m;
        // Sticky bit: the remainder 2⁸⁰ − q·N is non-zero.
        let sticky = ((1u128 << 80) != q * m) as u128;
        round(false, (q << 1) | sticky, -81) // the sticky bit keeps ties honest
    }

    /// fl(c · fl(1/N)): an n-bit unorm code as Mesa's texture fetch makes it a float.
    pub fn from_unorm(code: u32, bits: u32) -> u32 {
        mul(round(false, code as u128, 0), reciprocal_of_max(bits))
    }

    /// Mesa's float → unorm conversion: 0 for v ≤ 0, N for v ≥ 1, else the low n
    /// mantissa bits of fl(fl(v · (1 − 2⁻ⁿ)) + 2²³⁻ⁿ) (round to nearest even of v·N).
    pub fn to_unorm(v: u32, bits: u32) -> u32 {
        let m = max_code(bits);
        if v >> 31 == 1 || v == 0 {
            return 0;
        }
        if v >= ONE {
            return m;
        }
        let k = round(false, m as u128, -(bits as i32)); // N / 2ⁿ, exact in 24 bits
        let y = mul(v, k);
        let z = add(y, round(false, 1, 23 - bits as i32));
        z & m
    }

    /// ADD_SIGNED at scale 1 as Mesa evaluates it: fl(fl(Arg0' − 0.5) + Arg1'), with
    /// ONE_MINUS on Arg0 folded to fl(0.5 − Arg0') and on Arg1 as fl(1 − Arg1').
    pub fn mesa_add_signed(a0: CombineArg, a1: CombineArg, bits: u32) -> u32 {
        let f0 = from_unorm(a0.code, bits);
        let f1 = from_unorm(a1.code, bits);
        let biased0 = if a0.invert {
            sub(HALF, f0)
        } else {
            sub(f0, HALF)
        };
        let arg1 = if a1.invert { sub(ONE, f1) } else { f1 };
        to_unorm(add(biased0, arg1), bits)
    }
}

const CHANNEL_NAMES: [[&str; 4]; 4] = [
    ["texture_r", "texture_g", "texture_b", "texture_a"],
    ["constant_r", "constant_g", "constant_b", "constant_a"],
    ["primary_r", "primary_g", "primary_b", "primary_a"],
    ["previous_r", "previous_g", "previous_b", "previous_a"],
];

impl Unit for TextureCombiner {
    type In = TextureCombinerIn;
    type Out = [u32; 4];
    type State = ();

    fn name(&self) -> &'static str {
        "texture_combiner"
    }

    fn kernel(&self, _: &mut (), input: &TextureCombinerIn, ctr: &mut Counters) -> [u32; 4] {
        self.combine(input, ctr)
    }

    fn timing(&self) -> Timing {
        // Stage 1: source/operand muxes and the multipliers; stage 2: the sums, scale,
        // clamp and rounding adders. The binary32 path of the Mesa mode (two float adds
        // and the conversion's multiply-add after the operand multiply) takes a third.
        let latency = match self.cfg.rounding {
            CombinerRounding::GeforceInteger => 2,
            CombinerRounding::MesaFloat32 => 3,
        };
        Timing { latency, ii: 1 }
    }

    fn cost(&self) -> Cost {
        let n = self.cfg.bits;
        let not_n = Cells {
            not: n as f64,
            ..Cells::default()
        };
        // Per channel (4): three arguments, each a 4:1 source mux, a 2:1 invert
        // select over N − c (a NOT); RGB arguments also a 2:1 colour/alpha select.
        let arg_select = prim::mux_k(n, 4) + not_n + prim::mux(n);
        let mut cost = Cost::default()
            .part("input registers (4 sources × RGBA)", prim::register(16 * n))
            .part(
                "argument source muxes and ONE_MINUS (12 args)",
                arg_select * 12.0,
            )
            .part("SRC_ALPHA selects (9 RGB args)", prim::mux(n) * 9.0)
            // a0·a1 (MODULATE) or a0·a2 (INTERPOLATE) or the expanded DOT3 product
            // (2a0 − N)(2a1 − N): one (n+1)×(n+1) multiplier; a1·(N − a2) a second n×n.
            .part(
                "multipliers (n+1)×(n+1) and n×n, ×4",
                (prim::multiplier(n + 1, n + 1) + prim::multiplier(n, n)) * 4.0,
            )
            .part(
                // 2c − N = 2(c − 2ⁿ⁻¹) + 1: c with its top bit inverted, read as signed,
                // with a constant 1 below it.
                "DOT3 expand 2c − N (6 args, top-bit NOT)",
                Cells {
                    not: 6.0,
                    ..Cells::default()
                },
            )
            .part(
                "product registers (2 × (2n+3) bits, ×4)",
                prim::register(2 * (2 * n + 3)) * 4.0,
            )
            .part(
                "sum adder (2n+3) and ADD/SUBTRACT adder (n+2), ×4",
                (prim::adder(2 * n + 3) + prim::adder(n + 2)) * 4.0,
            )
            .part(
                "DOT3 three-term sum (2 adders of 2n+4)",
                prim::adder(2 * n + 4) * 2.0,
            )
            .part(
                "function select 4:1 (2n+6 bits), ×4",
                prim::mux_k(2 * n + 6, 4) * 4.0,
            )
            .part(
                "scale ×1/×2/×4 shifter, ×4",
                prim::shifter(2 * n + 6, 2) * 4.0,
            )
            .part(
                "clamp comparators (< 0, > N·D), ×4",
                prim::comparator(2 * n + 6) * 4.0,
            )
            .part(
                "rounding adders t = X + 2ⁿ⁻¹, t + (t >> n), ×4",
                (prim::adder(2 * n + 1) + prim::adder(2 * n + 1)) * 4.0,
            )
            .part("clamp muxes, ×4", prim::mux(n) * 8.0)
            .part("output register", prim::register(4 * n));
        if self.cfg.rounding == CombinerRounding::MesaFloat32 {
            // The binary32 ADD_SIGNED path, per channel: two code × fl(1/N) multipliers
            // (24 × n), two float adders (align shifter, 26-bit adder, leading-zero
            // count, normalise shifter), the conversion's 24 × 24 multiply and add.
            let fadd =
                prim::shifter(26, 5) * 2.0 + prim::adder(26) + prim::leading_zero_counter(26);
            let path = prim::multiplier(24, n) * 2.0
                + fadd * 3.0
                + prim::multiplier(24, 24)
                + prim::register(3 * 32);
            cost = cost.part("binary32 ADD_SIGNED path, ×4", path * 4.0);
        }
        cost
    }

    fn widths(&self) -> Vec<Width> {
        vec![
            Width {
                name: "bits",
                bits: self.cfg.bits,
            },
            Width {
                name: "product",
                bits: 2 * self.cfg.bits + 2,
            },
            Width {
                name: "dot3_sum",
                bits: 2 * self.cfg.bits + 6,
            },
        ]
    }

    fn in_signals(&self, i: &TextureCombinerIn) -> Vec<Signal> {
        let srcs = [i.texture, i.constant, i.primary_color, i.previous];
        let mut v = Vec::with_capacity(16);
        for (names, src) in CHANNEL_NAMES.iter().zip(srcs) {
            for (name, c) in names.iter().zip(src) {
                v.push(Signal::new(name, self.cfg.bits, c as u64));
            }
        }
        v
    }

    fn out_signals(&self, o: &[u32; 4]) -> Vec<Signal> {
        ["r", "g", "b", "a"]
            .iter()
            .zip(o)
            .map(|(name, &c)| Signal::new(name, self.cfg.bits, c as u64))
            .collect()
    }
}
