//! blend — the GL / NV2A framebuffer blend on one RGBA pixel of n-bit unorm channels:
//! dst' = eq(src·f_s, dst·f_d) per channel, with the 15 GL blend factors, the blend
//! constant colour and the 7 equations of the NV2A's `SET_BLEND_EQUATION`.
//!
//! Sources: the factors and the ADD / SUBTRACT / REVERSE_SUBTRACT / MIN / MAX equations
//! are OpenGL 1.4 § 4.1.7 (with GL_ARB_imaging's constant colour and
//! GL_EXT_blend_minmax: MIN and MAX ignore the factors). The NV2A's two signed
//! equations are not in any public document; their meaning here was read from the
//! hardware captures of nxdk_pgraph_tests' `Blend_tests` (github.com/abaire/
//! nxdk_pgraph_tests_golden_results, 448 ADD_SIGNED / REVERSE_SUBTRACT_SIGNED images):
//! the **source** is read as a two's-complement signed n-bit value, the destination
//! as unsigned, both factors are ignored, and the result saturates to 0 ..= 2ⁿ − 1:
//! ADD_SIGNED = clamp(dst + sx(src)), REVERSE_SUBTRACT_SIGNED = clamp(dst − sx(src)).
//!
//! Widths (n = `bits`, M = 2ⁿ − 1): every channel and factor u(n) (M stands for 1.0);
//! each product s·f_s, d·f_d u(2n); their sum or difference s(2n+2);
//! [`BlendRounding::Once`] (the default, the hardware's: one round-to-nearest of
//! (s·f_s ± d·f_d)/M matches every compared pixel of the NV2A captures) divides the
//! signed sum's magnitude by M (in hardware the shift-add series of
//! [`round_div_mersenne`]; M is odd: no
//! ties) → s(n+2), then clamps to u(n). [`BlendRounding::PerTerm`]
//! rounds each product to u(n) first (a `modulate` per term, then a saturating add:
//! two roundings, off by one on a tenth to a quarter of the pixels of ADD images) and
//! is kept as the cheaper alternative. MIN / MAX compare the raw u(n) operands; the
//! signed equations add an s(n) source to a u(n) destination → s(n+2).
//!
//! Source width (s = `src_bits`, default `bits`): the fragment colour u(s) is aligned
//! to n bits before anything else, widened by bit replication when n ≥ s (wiring
//! only, as GPUs expand colours; error < 1 LSB) or narrowed by round-to-nearest when
//! n < s (`unorm::narrow`; error ≤ ½ LSB).
//!
//! Constant width (k = `constant_bits`, default `bits`): the constant colour is u(k)
//! (2ᵏ − 1 stands for 1.0), so a CONSTANT_* factor's term is round(x·c / (2ᵏ − 1)),
//! the shift-add series [`round_div_mersenne`]; k ≠ n needs per_term rounding.
//!
//! Datapath ([`BlendDatapath`], "elaborate only what a scene needs"):
//! `programmable` (the default) builds every factor and equation behind select words,
//! as the NV2A has them; `additive` builds only ADD with destination factor ONE and
//! source factor ONE or CONSTANT_ALPHA — the saturating add of the shafts and object
//! passes: dst' = min(dst + q, 2ⁿ − 1) with q = align(src) (ONE) or
//! q = round(align(src)·c_A / (2ᵏ − 1)) (CONSTANT_ALPHA: a unorm weight, e.g. 1/m of
//! m sub-sample planes). With the destination factor ONE the destination term is
//! exact, so once and per_term round alike there. Its latency is 3 (stage 1 reads the
//! framebuffer while the source is aligned and weighted; stage 2 adds and saturates;
//! stage 3 writes back) and its cost has no factor muxes, equations or clamp below 0.
//!
//! Channel 3 is alpha: the alpha channel's SRC_COLOR factor is the source alpha,
//! DST_COLOR the destination alpha, and SRC_ALPHA_SATURATE is 1 (GL's table).
//!
//! Counters per kernel call (one pixel): `saturations` +1 per channel whose rounded
//! result left 0 ..= M and was clamped (a SUBTRACT below 0 is counted too);
//! `underflows` +1 per term lost to rounding: per_term (and the additive datapath),
//! each weighted term whose operand and factor are non-zero but which rounds to 0
//! (for the additive datapath: a non-zero source, and weight, adding nothing — the
//! plane is lost); once, each channel whose exact (s·f_s ± d·f_d)/M is non-zero but
//! rounds to 0; in every equation, a non-zero source that alignment narrowed to 0
//! (once per channel). One framebuffer read-modify-write of 4·n bits
//! (`memory::framebuffer_rmw`).
//!
//! Pipeline (latency 4, II 1): stage 1 reads the framebuffer and selects the factors;
//! stage 2 multiplies; stage 3 adds (or subtracts, compares) and divides by M;
//! stage 4 clamps and writes back. The read-modify-write hazard of two fragments to
//! one pixel in flight belongs to the pipeline that owns the framebuffer.

use crate::cost::{prim, Cost};
use crate::counters::Counters;
use crate::error::ConfigError;
use crate::memory::{framebuffer_rmw, framebuffer_rmws};
use crate::unit::{Signal, Timing, Unit, Width};
use crate::unorm::{check_bits, max_code, narrow, widen};
use serde::{Deserialize, Serialize};

/// Channels of a pixel (RGBA; index 3 is alpha).
pub const CHANNELS: usize = 4;
const ALPHA: usize = 3;

const SRC_NAMES: [&str; 4] = ["src_r", "src_g", "src_b", "src_a"];
const DST_NAMES: [&str; 4] = ["dst_r", "dst_g", "dst_b", "dst_a"];
const OUT_NAMES: [&str; 4] = ["y_r", "y_g", "y_b", "y_a"];

/// A blend factor (GL's names; NV097_SET_BLEND_FUNC_SFACTOR / DFACTOR).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BlendFactor {
    /// 0: the term vanishes.
    Zero,
    /// 1 (the all-ones code M): the term passes unweighted, exactly.
    One,
    /// The source colour, per channel (R_s, G_s, B_s, A_s) / M.
    SrcColor,
    /// 1 − the source colour, per channel: (M − c_s) / M.
    OneMinusSrcColor,
    /// The source alpha A_s / M on every channel.
    SrcAlpha,
    /// 1 − the source alpha, (M − A_s) / M, on every channel.
    OneMinusSrcAlpha,
    /// The destination alpha A_d / M on every channel.
    DstAlpha,
    /// 1 − the destination alpha, (M − A_d) / M, on every channel.
    OneMinusDstAlpha,
    /// The destination colour, per channel (R_d, G_d, B_d, A_d) / M.
    DstColor,
    /// 1 − the destination colour, per channel: (M − c_d) / M.
    OneMinusDstColor,
    /// min(A_s, 1 − A_d) for colour, 1 for alpha.
    SrcAlphaSaturate,
    /// The constant colour, per channel c / (2ᵏ − 1) (k = `constant_bits`).
    ConstantColor,
    /// 1 − the constant colour, per channel.
    OneMinusConstantColor,
    /// The constant alpha A_c / (2ᵏ − 1) on every channel.
    ConstantAlpha,
    /// 1 − the constant alpha on every channel.
    OneMinusConstantAlpha,
}

impl BlendFactor {
    /// Every factor, in the order of its 4-bit select code ([`BlendFactor::code`]).
    pub const ALL: [BlendFactor; 15] = [
        BlendFactor::Zero,
        BlendFactor::One,
        BlendFactor::SrcColor,
        BlendFactor::OneMinusSrcColor,
        BlendFactor::SrcAlpha,
        BlendFactor::OneMinusSrcAlpha,
        BlendFactor::DstAlpha,
        BlendFactor::OneMinusDstAlpha,
        BlendFactor::DstColor,
        BlendFactor::OneMinusDstColor,
        BlendFactor::SrcAlphaSaturate,
        BlendFactor::ConstantColor,
        BlendFactor::OneMinusConstantColor,
        BlendFactor::ConstantAlpha,
        BlendFactor::OneMinusConstantAlpha,
    ];

    /// Index into [`BlendFactor::ALL`] (the 4-bit select word of the factor mux).
    pub fn code(self) -> u32 {
        BlendFactor::ALL
            .iter()
            .position(|&f| f == self)
            .expect("every factor is listed") as u32
    }
}

/// A blend equation (NV097_SET_BLEND_EQUATION).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BlendEquation {
    /// s·f_s + d·f_d.
    Add,
    /// s·f_s − d·f_d.
    Subtract,
    /// d·f_d − s·f_s.
    ReverseSubtract,
    /// min(s, d); factors ignored.
    Min,
    /// max(s, d); factors ignored.
    Max,
    /// NV2A: d + sx(s), the source read as two's complement; factors ignored.
    AddSigned,
    /// NV2A: d − sx(s), the source read as two's complement; factors ignored.
    ReverseSubtractSigned,
}

impl BlendEquation {
    /// Every equation, in the order of its 3-bit select code ([`BlendEquation::code`]).
    pub const ALL: [BlendEquation; 7] = [
        BlendEquation::Add,
        BlendEquation::Subtract,
        BlendEquation::ReverseSubtract,
        BlendEquation::Min,
        BlendEquation::Max,
        BlendEquation::AddSigned,
        BlendEquation::ReverseSubtractSigned,
    ];

    /// Index into [`BlendEquation::ALL`] (the 3-bit select word).
    pub fn code(self) -> u32 {
        BlendEquation::ALL
            .iter()
            .position(|&e| e == self)
            .expect("every equation is listed") as u32
    }

    /// Whether the equation multiplies by the factors.
    pub fn uses_factors(self) -> bool {
        matches!(
            self,
            BlendEquation::Add | BlendEquation::Subtract | BlendEquation::ReverseSubtract
        )
    }
}

/// Where the weighted terms are brought back to n bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BlendRounding {
    /// One round-to-nearest of (s·f_s ± d·f_d) / M (the hardware's).
    Once,
    /// round(s·f_s / M) ± round(d·f_d / M): a modulate per term, then the add.
    PerTerm,
}

/// Which datapath is built (and costed).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BlendDatapath {
    /// Every factor and equation behind select words: the NV2A's programmable blend.
    Programmable,
    /// Only ADD with destination factor ONE and source factor ONE or CONSTANT_ALPHA:
    /// align, optional weight (multiply and round), saturating add.
    Additive,
}

/// The configuration as a scene (or a test description) gives it; [`BlendConfig::build`]
/// checks it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct BlendConfig {
    /// Channel width (unorm) of source, destination, constant and factors, 1 ..= 16.
    /// Default 8 (the NV2A's A8R8G8B8 surfaces).
    pub bits: u32,
    /// The blend equation (default `add`).
    pub equation: BlendEquation,
    /// The factor f_s that weighs the source (default `one`).
    pub src_factor: BlendFactor,
    /// The factor f_d that weighs the destination (default `zero`).
    pub dst_factor: BlendFactor,
    /// The blend constant colour, RGBA codes of `bits` bits (NV097_SET_BLEND_COLOR).
    pub constant: [u32; 4],
    /// Where the terms are rounded back to `bits` (default `once`, the hardware's).
    pub rounding: BlendRounding,
    /// Width of the incoming fragment colour (unorm), 1 ..= 16; absent = `bits`.
    /// Aligned to `bits` first: bit replication when widening, round-to-nearest when
    /// narrowing.
    pub src_bits: Option<u32>,
    /// Width of the constant colour (the CONSTANT_* factors), 1 ..= 16; absent =
    /// `bits`. Other than `bits` only with `rounding = per_term`.
    pub constant_bits: Option<u32>,
    /// What is built: every factor and equation, or the additive path only.
    pub datapath: BlendDatapath,
}

impl Default for BlendConfig {
    /// GL's initial state: ADD, ONE, ZERO (the blend writes the source), constant 0.
    fn default() -> Self {
        BlendConfig {
            bits: 8,
            equation: BlendEquation::Add,
            src_factor: BlendFactor::One,
            dst_factor: BlendFactor::Zero,
            constant: [0; 4],
            rounding: BlendRounding::Once,
            src_bits: None,
            constant_bits: None,
            datapath: BlendDatapath::Programmable,
        }
    }
}

impl BlendConfig {
    /// Validate; errors name `blend.<field>`.
    pub fn build(&self) -> Result<Blend, ConfigError> {
        check_bits("blend.bits", self.bits)?;
        if let Some(s) = self.src_bits {
            check_bits("blend.src_bits", s)?;
        }
        let k = self.constant_bits.unwrap_or(self.bits);
        if let Some(k) = self.constant_bits {
            check_bits("blend.constant_bits", k)?;
            if k != self.bits && self.rounding == BlendRounding::Once {
                return Err(ConfigError::invalid(
                    "blend.constant_bits",
                    &format!(
                        "{k} differs from blend.bits = {} only with rounding = per_term \
                         (one rounding divides the sum by one full scale)",
                        self.bits
                    ),
                ));
            }
        }
        let max = max_code(k);
        for (c, &v) in self.constant.iter().enumerate() {
            if v > max {
                return Err(ConfigError::out_of_range(
                    [
                        "blend.constant[0]",
                        "blend.constant[1]",
                        "blend.constant[2]",
                        "blend.constant[3]",
                    ][c],
                    v as f64,
                    0.0,
                    max as f64,
                ));
            }
        }
        if self.datapath == BlendDatapath::Additive
            && (self.equation != BlendEquation::Add
                || self.dst_factor != BlendFactor::One
                || !matches!(
                    self.src_factor,
                    BlendFactor::One | BlendFactor::ConstantAlpha
                ))
        {
            return Err(ConfigError::invalid(
                "blend.datapath",
                &format!(
                    "additive builds only equation add with dst_factor one and src_factor \
                     one or constant_alpha (got {:?}, {:?}, {:?}); use programmable",
                    self.equation, self.src_factor, self.dst_factor
                ),
            ));
        }
        Ok(Blend { cfg: *self })
    }
}

/// The validated unit config.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Blend {
    cfg: BlendConfig,
}

/// One pixel: the incoming fragment's RGBA and the framebuffer's current RGBA (codes
/// of `bits` bits; every word is masked to its wire width).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct BlendIn {
    /// The incoming fragment colour, RGBA codes of `src_bits` bits.
    pub src: [u32; 4],
    /// The framebuffer's current colour, RGBA codes of `bits` bits.
    pub dst: [u32; 4],
}

/// The new framebuffer RGBA.
pub type BlendOut = [u32; 4];

/// round(x / (2ᵏ − 1)) for x ≤ (2^q − 1)(2ᵏ − 1), integers only, as the hardware does
/// it without a divider. With t = x + 2ᵏ⁻¹ and J = ⌈q / k⌉:
///
///   round(x / (2ᵏ−1)) = ⌊ t · Σ_{j=0..J} 2^{jk} / 2^{(J+1)k} ⌋.
///
/// Proof: 2ᵏ − 1 is odd, so x/(2ᵏ−1) is never a half-integer and round = ⌊y / M⌋ with
/// y = t − 1 and M = 2ᵏ − 1. Write y = nM + r (0 ≤ r < M). Since Σ 2^{jk} =
/// (2^{(J+1)k} − 1)/M, the right side is ⌊(y+1)/M − (y+1)/(M·2^{(J+1)k})⌋ =
/// ⌊n + (r+1)/M − ε⌋ with 0 < ε ≤ (r+1)/M because y + 1 = t < 2^{q+k} ≤ 2^{(J+1)k};
/// so it equals n. The sum is J shift-adds of t (for k = 8 = q it is Blinn's
/// (t + (t >> 8)) >> 8). Widths: t u(q+k); Σ u(q + k + Jk + 1) ≤ u(2q + 2k) ≤ u(64).
///
/// `k` and `q` are clamped to 1 ..= 16; outside the precondition the result is the
/// same formula (no panic), no longer the rounded quotient.
pub fn round_div_mersenne(x: u64, k: u32, q: u32) -> u64 {
    let k = k.clamp(1, 16);
    let q = q.clamp(1, 16);
    let terms = q.div_ceil(k) + 1; // J + 1 shifted copies
    if q + k * terms < 64 && x >> (q + k) == 0 {
        // The same sum in a 64-bit carrier: its u(q + k + Jk + 1) fits.
        let t = x + (1u64 << (k - 1));
        let acc: u64 = (0..terms).map(|j| t << (j * k)).sum();
        return acc >> (terms * k);
    }
    let t = x as u128 + (1u128 << (k - 1)); // u(q+k) + 2ᵏ⁻¹ → u(q+k) within the precondition
    let mut acc: u128 = 0;
    for j in 0..terms {
        acc += t << (j * k); // running sum grows to u(q + k + Jk + 1)
    }
    u64::try_from(acc >> (terms * k)).unwrap_or(u64::MAX) // top bits: u(q)
}

/// Widest source whose contributions the additive batch paths tabulate (2^10 entries).
pub const CONTRIBUTION_LUT_BITS: u32 = 10;

/// A masked source code's index in the contribution table: the code itself (a source
/// of at most [`CONTRIBUTION_LUT_BITS`] bits, masked to them), masked again so the
/// compiler sees it in range and the table loops need no bounds check.
#[inline(always)]
fn lut_index(masked_src: u32) -> usize {
    masked_src as usize & ((1 << CONTRIBUTION_LUT_BITS) - 1)
}

/// Lanes [`Blend::blend_lanes_at`] checks at once for a run of neighbouring words.
const BLEND_LANES: usize = 16;

/// Fragments ahead of the one blended whose framebuffer pixel is asked for.
const PREFETCH_AHEAD: usize = 96;

/// A hint that `words[i]` is about to be read and written (nothing when `i` is past
/// the words, or off x86-64).
#[inline(always)]
fn prefetch_write<T>(words: &[T], i: usize) {
    #[cfg(target_arch = "x86_64")]
    if let Some(w) = words.get(i) {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        // SAFETY: a prefetch reads nothing and cannot fault; the address is an element's.
        unsafe { _mm_prefetch::<_MM_HINT_T0>((w as *const T).cast()) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (words, i);
}

/// Whether `f` reads the constant colour (a u(constant_bits) factor).
fn is_constant(f: BlendFactor) -> bool {
    matches!(
        f,
        BlendFactor::ConstantColor
            | BlendFactor::OneMinusConstantColor
            | BlendFactor::ConstantAlpha
            | BlendFactor::OneMinusConstantAlpha
    )
}

/// round(t / m) for a signed t, m odd (no ties): (2|t| + m) / 2m with t's sign.
#[inline]
fn round_signed(t: i64, m: u64) -> i64 {
    let q = ((2 * t.unsigned_abs() + m) / (2 * m)) as i64;
    if t < 0 {
        -q
    } else {
        q
    }
}

impl Blend {
    /// GeForce / NV2A default: 8 bits, GL's initial state (ADD, ONE, ZERO), one rounding.
    pub fn geforce() -> Self {
        Blend {
            cfg: BlendConfig::default(),
        }
    }

    /// The 8-bit hardware blend with the given state (constant colour 0).
    pub fn with(equation: BlendEquation, src_factor: BlendFactor, dst_factor: BlendFactor) -> Self {
        Blend {
            cfg: BlendConfig {
                equation,
                src_factor,
                dst_factor,
                ..BlendConfig::default()
            },
        }
    }

    /// The additive datapath: a u(`src_bits`) source added into a u(`fb_bits`)
    /// framebuffer with saturation, GL_ONE (unweighted) or weighted by the constant
    /// alpha, a unorm of `weight_bits` (CONSTANT_ALPHA; set it per draw with
    /// [`Blend::with_weight`]). Per-term rounding. Errors name `blend.<field>`.
    pub fn additive(
        src_bits: u32,
        fb_bits: u32,
        weighted: bool,
        weight_bits: u32,
    ) -> Result<Self, ConfigError> {
        BlendConfig {
            bits: fb_bits,
            equation: BlendEquation::Add,
            src_factor: if weighted {
                BlendFactor::ConstantAlpha
            } else {
                BlendFactor::One
            },
            dst_factor: BlendFactor::One,
            constant: [0; 4],
            rounding: BlendRounding::PerTerm,
            src_bits: Some(src_bits),
            constant_bits: Some(weight_bits),
            datapath: BlendDatapath::Additive,
        }
        .build()
    }

    /// The same blend with the constant colour `c` (each word masked to
    /// `constant_bits`): NV097_SET_BLEND_COLOR between draws.
    pub fn with_constant(&self, c: [u32; 4]) -> Self {
        let m = self.constant_max();
        let mut cfg = self.cfg;
        cfg.constant = c.map(|v| v & m);
        Blend { cfg }
    }

    /// The same blend with the constant alpha (the additive datapath's weight) `w`,
    /// masked to `constant_bits`.
    pub fn with_weight(&self, w: u32) -> Self {
        let mut c = self.cfg.constant;
        c[ALPHA] = w;
        self.with_constant(c)
    }

    /// The config the unit was built from (with its current constant colour).
    pub fn config(&self) -> BlendConfig {
        self.cfg
    }

    /// Framebuffer (and factor) channel width n.
    pub fn bits(&self) -> u32 {
        self.cfg.bits
    }

    /// Source width s (`bits` unless configured).
    pub fn src_bits(&self) -> u32 {
        self.cfg.src_bits.unwrap_or(self.cfg.bits)
    }

    /// Constant colour width k (`bits` unless configured).
    pub fn constant_bits(&self) -> u32 {
        self.cfg.constant_bits.unwrap_or(self.cfg.bits)
    }

    /// Which datapath is built: every factor and equation, or the additive path only.
    pub fn datapath(&self) -> BlendDatapath {
        self.cfg.datapath
    }

    /// Whether the additive datapath multiplies by a weight (CONSTANT_ALPHA).
    pub fn weighted(&self) -> bool {
        self.cfg.datapath == BlendDatapath::Additive
            && self.cfg.src_factor == BlendFactor::ConstantAlpha
    }

    /// All-ones code (1.0).
    pub fn max(&self) -> u32 {
        max_code(self.cfg.bits)
    }

    /// All-ones constant code (1.0 of a CONSTANT_* factor).
    pub fn constant_max(&self) -> u32 {
        max_code(self.constant_bits())
    }

    /// Bits of one framebuffer pixel, as read and written (4 channels).
    pub fn pixel_bits(&self) -> u32 {
        CHANNELS as u32 * self.cfg.bits
    }

    /// The source aligned to the framebuffer width: replication when widening,
    /// round-to-nearest when narrowing. u(src_bits) → u(bits).
    #[inline]
    pub fn align(&self, src: u32) -> u32 {
        let (s, n) = (self.src_bits(), self.cfg.bits);
        let v = src & max_code(s);
        if n >= s {
            widen(v, s, n) // wiring only
        } else {
            // (v·(2ⁿ−1) + 2ˢ⁻¹) / (2ˢ−1): u(s) × u(n) → u(s+n), then the constant divide.
            narrow(v, s, n)
        }
    }

    /// The additive datapath's contribution of a source code: align(src), weighted
    /// round(align(src)·c_A / (2ᵏ − 1)). u(bits).
    #[inline]
    pub fn contribution(&self, src: u32) -> u32 {
        let a = self.align(src); // u(n)
        if !self.weighted() {
            return a;
        }
        let k = self.constant_bits();
        let w = self.cfg.constant[ALPHA]; // u(k)
        let p = a as u64 * w as u64; // u(n) × u(k) → u(n+k)
        round_div_mersenne(p, k, self.cfg.bits) as u32 // u(n+k) → u(n), ≤ a
    }

    /// The additive datapath on one channel: (new dst, clamped?, contribution lost?).
    #[inline]
    pub fn add_channel(&self, src: u32, dst: u32) -> (u32, bool, bool) {
        let max = self.max();
        let q = self.contribution(src); // u(n)
        let sum = (dst & max) + q; // u(n) + u(n) → u(n+1)
        let on = (src & max_code(self.src_bits())) != 0
            && (!self.weighted() || self.cfg.constant[ALPHA] != 0);
        (sum.min(max), sum > max, on && q == 0) // → u(n)
    }

    /// The factor `f` for channel `c` of this pixel (operands aligned and masked):
    /// u(bits), or u(constant_bits) for the CONSTANT_* factors.
    #[inline]
    pub fn factor(&self, f: BlendFactor, c: usize, s: &[u32; 4], d: &[u32; 4]) -> u32 {
        let m = self.max();
        let km = self.constant_max();
        let k = &self.cfg.constant;
        match f {
            BlendFactor::Zero => 0,
            BlendFactor::One => m,
            BlendFactor::SrcColor => s[c],
            BlendFactor::OneMinusSrcColor => m - s[c],
            BlendFactor::SrcAlpha => s[ALPHA],
            BlendFactor::OneMinusSrcAlpha => m - s[ALPHA],
            BlendFactor::DstAlpha => d[ALPHA],
            BlendFactor::OneMinusDstAlpha => m - d[ALPHA],
            BlendFactor::DstColor => d[c],
            BlendFactor::OneMinusDstColor => m - d[c],
            BlendFactor::SrcAlphaSaturate if c == ALPHA => m,
            BlendFactor::SrcAlphaSaturate => s[ALPHA].min(m - d[ALPHA]),
            BlendFactor::ConstantColor => k[c],
            BlendFactor::OneMinusConstantColor => km - k[c],
            BlendFactor::ConstantAlpha => k[ALPHA],
            BlendFactor::OneMinusConstantAlpha => km - k[ALPHA],
        }
    }

    /// The full scale of factor `f` (the code standing for 1.0): 2ᵏ − 1 for the
    /// CONSTANT_* factors, 2ⁿ − 1 for the others.
    fn factor_scale(&self, f: BlendFactor) -> u64 {
        if is_constant(f) {
            self.constant_max() as u64
        } else {
            self.max() as u64
        }
    }

    /// Channel `c` before the clamp, s(n+2) (operands aligned and masked to n bits),
    /// and its terms lost to rounding (see the module's counters).
    #[inline]
    fn unclamped_counted(&self, c: usize, s: &[u32; 4], d: &[u32; 4]) -> (i64, u32) {
        let n = self.cfg.bits;
        let (sc, dc) = (s[c] as i64, d[c] as i64);
        let eq = self.cfg.equation;
        match eq {
            BlendEquation::Min => (sc.min(dc), 0),
            BlendEquation::Max => (sc.max(dc), 0),
            BlendEquation::AddSigned | BlendEquation::ReverseSubtractSigned => {
                // sx(s): u(n) read as s(n).
                let sx = if sc >> (n - 1) != 0 {
                    sc - (1i64 << n)
                } else {
                    sc
                };
                if eq == BlendEquation::AddSigned {
                    (dc + sx, 0) // u(n) + s(n) → s(n+2)
                } else {
                    (dc - sx, 0)
                }
            }
            BlendEquation::Add | BlendEquation::Subtract | BlendEquation::ReverseSubtract => {
                let (sf, df) = (self.cfg.src_factor, self.cfg.dst_factor);
                let fs = self.factor(sf, c, s, d) as i64;
                let fd = self.factor(df, c, s, d) as i64;
                let (ps, pd) = (sc * fs, dc * fd); // u(n) × u(n|k) → u(2n|n+k) each
                let sign = match eq {
                    BlendEquation::Add => (1, 1),
                    BlendEquation::Subtract => (1, -1),
                    _ => (-1, 1),
                };
                match self.cfg.rounding {
                    // u(2n) ± u(2n) → s(2n+2), ÷ M → s(n+2)
                    BlendRounding::Once => {
                        let t = sign.0 * ps + sign.1 * pd;
                        let v = round_signed(t, self.max() as u64);
                        (v, u32::from(t != 0 && v == 0))
                    }
                    // each term ÷ its factor's full scale → u(n), then ± → s(n+2)
                    BlendRounding::PerTerm => {
                        let ts = round_signed(ps, self.factor_scale(sf));
                        let td = round_signed(pd, self.factor_scale(df));
                        let lost = u32::from(ps != 0 && ts == 0) + u32::from(pd != 0 && td == 0);
                        (sign.0 * ts + sign.1 * td, lost)
                    }
                }
            }
        }
    }

    /// One pixel: (new RGBA, channels clamped).
    #[inline]
    pub fn blend_pixel(&self, src: &[u32; 4], dst: &[u32; 4]) -> ([u32; 4], u32) {
        let (out, sat, _) = self.blend_pixel_counted(src, dst);
        (out, sat)
    }

    /// One pixel: (new RGBA, channels clamped, terms lost to rounding).
    #[inline]
    pub fn blend_pixel_counted(&self, src: &[u32; 4], dst: &[u32; 4]) -> ([u32; 4], u32, u32) {
        let m = self.max();
        let mut out = [0u32; 4];
        let (mut sat, mut under) = (0, 0);
        if self.cfg.datapath == BlendDatapath::Additive {
            for (c, o) in out.iter_mut().enumerate() {
                let (v, s, u) = self.add_channel(src[c], dst[c]);
                *o = v;
                sat += u32::from(s);
                under += u32::from(u);
            }
            return (out, sat, under);
        }
        let raw = src.map(|v| v & max_code(self.src_bits()));
        let s = raw.map(|v| self.align(v));
        let d = dst.map(|v| v & m);
        for (c, o) in out.iter_mut().enumerate() {
            let (v, lost) = self.unclamped_counted(c, &s, &d);
            // A non-zero source that alignment narrowed to 0 is lost in any equation.
            let aligned_away = raw[c] != 0 && s[c] == 0;
            under += if aligned_away { lost.max(1) } else { lost };
            let clamped = v.clamp(0, m as i64);
            sat += u32::from(clamped != v);
            *o = clamped as u32; // → u(n)
        }
        (out, sat, under)
    }

    /// The additive datapath's contribution of every source code, for the batch paths
    /// (None when not additive or the source is wider than [`CONTRIBUTION_LUT_BITS`]).
    fn contribution_table(&self) -> Option<[u32; 1 << CONTRIBUTION_LUT_BITS]> {
        if self.cfg.datapath != BlendDatapath::Additive || self.src_bits() > CONTRIBUTION_LUT_BITS {
            return None;
        }
        let mut lut = [0u32; 1 << CONTRIBUTION_LUT_BITS];
        for (s, q) in lut.iter_mut().enumerate().take(1 << self.src_bits()) {
            *q = self.contribution(s as u32);
        }
        Some(lut)
    }

    /// The additive batch kernel on lanes, in place, in the J buffer's form: lane i is
    /// the input `BlendIn { src: [src[i], 0, 0, 0], dst: [d, 0, 0, 0] }` with d the
    /// word `dst[at[i] − offset]` as the earlier lanes left it; its channel-0 result is
    /// written back there (the other channels', all min(contribution(0), max), are
    /// dropped: a read-modify-write per lane). Where no two lanes share a word this is
    /// the batch kernel on those inputs with `dst` as it was, and the counters are the
    /// ones it counts. Additive datapath only; panics otherwise, or if `src` and `at`
    /// differ in length or a word lies outside `dst` (wiring errors of the caller).
    pub fn blend_lanes_at(
        &self,
        src: &[u32],
        at: (&[u32], usize),
        dst: &mut [u32],
        ctr: &mut Counters,
    ) {
        self.lanes_at().blend(src, at, dst, ctr);
    }

    /// [`Self::blend_lanes_at`] prepared once (its contribution table built) for a
    /// caller that blends many lane slices with this unit. Panics unless the datapath
    /// is additive.
    pub fn lanes_at(&self) -> LanesAt<'_> {
        assert_eq!(
            self.cfg.datapath,
            BlendDatapath::Additive,
            "blend_lanes_at: additive datapath only"
        );
        LanesAt {
            unit: self,
            lut: self.contribution_table(),
        }
    }

    /// What [`Self::blend_lanes_at`] counts for `n` lanes whose source is 0, counted
    /// without blending them: a read-modify-write of a word each, and nothing else.
    /// The contribution of source 0 is 0 (align and weight map 0 to 0), so a word
    /// at most the full-scale code (as every blend leaves it) is written back as it
    /// was, and no sum saturates or loses a non-zero source. A caller may leave such
    /// lanes out of `blend_lanes_at` and count them here: the same words, the same
    /// counters.
    pub fn count_zero_lanes(&self, n: u64, ctr: &mut Counters) {
        framebuffer_rmws(ctr, n, self.pixel_bits());
    }

    /// The additive batch kernel on unweighted pixels, in place (the framebuffer's
    /// form, one contribution table built once, no input words): lane i (of `n`) is
    /// fragment `frag(i)` =
    /// (pixel index p, source RGBA) blended over `pixels[p]` as the earlier lanes left
    /// it, the result written back there (a read-modify-write per fragment, as a ROP
    /// does). Where no two lanes share a pixel, this is the batch kernel on the inputs
    /// `BlendIn { src, dst: pixels[p] }` with `pixels` as they were, and the counters
    /// are the ones it counts. False (nothing done) unless the datapath is additive
    /// and unweighted with a source of at most [`CONTRIBUTION_LUT_BITS`] bits. Panics if p is past `pixels` (a wiring error of the caller).
    pub fn blend_pixels_in_place(
        &self,
        n: usize,
        frag: impl Fn(usize) -> (usize, [u32; 4]),
        pixels: &mut [[u32; 4]],
        ctr: &mut Counters,
    ) -> bool {
        if self.weighted() {
            return false;
        }
        let Some(lut) = self.contribution_table() else {
            return false;
        };
        let (max, src_mask) = (self.max(), max_code(self.src_bits()));
        // Per channel: saturations and underflows, summed after the loop.
        let (mut sat, mut under) = ([0u64; 4], [0u64; 4]);
        for i in 0..n {
            // The pixel a few fragments on asked for now: the loop's time is the
            // framebuffer's reads (a pass's pixels rarely sit in cache), so each read is
            // started ahead of its fragment. A hint only: nothing is read or changed.
            if i + PREFETCH_AHEAD < n {
                prefetch_write(pixels, frag(i + PREFETCH_AHEAD).0);
            }
            let (p, s) = frag(i);
            let d = &mut pixels[p];
            for c in 0..4 {
                let sm = s[c] & src_mask;
                let q = lut[lut_index(sm)]; // u(n)
                let sum = (d[c] & max) + q; // u(n+1)
                d[c] = sum.min(max);
                sat[c] += u64::from(sum > max);
                under[c] += u64::from(sm != 0 && q == 0);
            }
        }
        framebuffer_rmws(ctr, n as u64, self.pixel_bits());
        ctr.saturations += sat.iter().sum::<u64>();
        ctr.underflows += under.iter().sum::<u64>();
        true
    }

    /// The additive datapath's cost (the parts a fixed saturating add needs).
    fn additive_cost(&self) -> Cost {
        let (s, f, k) = (self.src_bits(), self.cfg.bits, self.constant_bits());
        let ch = CHANNELS as u32;
        let chf = ch as f64;
        let wbits = if self.weighted() { k } else { 0 };
        let mut c = Cost::default()
            .part(
                "input registers (src, weight)",
                prim::register(ch * s + wbits),
            )
            .part(
                "stage 1 registers (contribution, fb read data)",
                prim::register(2 * ch * f),
            )
            .part("stage 2 register (saturated sum)", prim::register(ch * f))
            .part("stage 3 register (write data)", prim::register(ch * f));
        if f < s {
            c = c.part(
                "align: narrow to fb_bits (round to nearest)",
                narrow_cost(s, f) * chf,
            );
        }
        // f ≥ s: bit replication is wiring, no gates.
        if self.weighted() {
            let j = f.div_ceil(k); // shift-add terms beyond the first
            c = c
                .part("weight multiplier fb×weight", prim::multiplier(f, k) * chf)
                .part(
                    "weight rounding: + 2^(k-1)",
                    prim::half_adder() * ((f + 1) as f64 * chf),
                )
                .part(
                    "weight rounding: ÷(2^k−1) shift-add series",
                    prim::adder(f + k) * (j as f64 * chf),
                );
        }
        c.part("saturating adder fb_bits", prim::saturating_adder(f) * chf)
    }

    /// The programmable datapath's cost: every factor and equation.
    fn programmable_cost(&self) -> Cost {
        let n = self.cfg.bits;
        let (s, k) = (self.src_bits(), self.constant_bits());
        let ch = CHANNELS as f64;
        let mut c = Cost::default()
            .part("input registers (src)", prim::register(4 * s))
            .part(
                "stage 1 registers (src, dst, two factors)",
                prim::register(16 * n),
            )
            .part("stage 2 registers (two products)", prim::register(8 * n))
            .part(
                "stage 3 register (unclamped sum)",
                prim::register(4 * (n + 2)),
            )
            .part("stage 4 register (write data)", prim::register(4 * n))
            .part("constant colour register", prim::register(4 * k));
        if n < s {
            c = c.part(
                "align: narrow to bits (round to nearest)",
                narrow_cost(s, n) * ch,
            );
        }
        c = c
            .part(
                "factor muxes (15 inputs, two per channel)",
                prim::mux_k(n.max(k), 15) * (2.0 * ch),
            )
            .part("one-minus inverters", prim::mux(n.max(k)) * (2.0 * ch))
            .part("src_alpha_saturate min", prim::comparator(n) + prim::mux(n))
            .part(
                "multipliers n×n",
                prim::multiplier(n, n.max(k)) * (2.0 * ch),
            )
            .part("min/max comparator", prim::comparator(n) * ch)
            .part("signed add (sx(src) ± dst)", prim::adder(n + 1) * ch)
            .part("clamp to 0 ..= M", prim::mux(n) * (2.0 * ch));
        let j = (n + 1).div_ceil(n) as f64; // shift-add terms beyond the first
        match self.cfg.rounding {
            BlendRounding::Once => {
                c = c
                    .part("add/subtract products", prim::adder(2 * n + 1) * ch)
                    .part("magnitude (negate)", prim::subtractor(2 * n + 2) * ch)
                    .part("÷M shift-add series", prim::adder(2 * n + 2) * (j * ch))
            }
            BlendRounding::PerTerm => {
                let w = 2 * n.max(k) + 1;
                c = c
                    .part(
                        "÷M shift-add series, per term",
                        prim::adder(w) * (2.0 * j * ch),
                    )
                    .part("add/subtract terms", prim::adder(n + 1) * ch)
            }
        }
        c
    }
}

/// [`Blend::blend_lanes_at`] with its contribution table built once
/// ([`Blend::lanes_at`]).
pub struct LanesAt<'a> {
    unit: &'a Blend,
    /// The contribution of every source code, where the datapath has a table.
    lut: Option<[u32; 1 << CONTRIBUTION_LUT_BITS]>,
}

impl LanesAt<'_> {
    /// [`Blend::blend_lanes_at`]: the same words and counters.
    pub fn blend(
        &self,
        src: &[u32],
        (at, offset): (&[u32], usize),
        dst: &mut [u32],
        ctr: &mut Counters,
    ) {
        assert_eq!(
            src.len(),
            at.len(),
            "blend_lanes_at: src and at lanes differ"
        );
        let unit = self.unit;
        let n = src.len() as u64;
        let (max, src_mask) = (unit.max(), max_code(unit.src_bits()));
        let weight_on = !unit.weighted() || unit.cfg.constant[ALPHA] != 0;
        // One loop per contribution form (the table or the datapath), inlined.
        #[inline(always)]
        fn lanes(
            (src, at, offset): (&[u32], &[u32], usize),
            dst: &mut [u32],
            (src_mask, max): (u32, u32),
            contribution: impl Fn(u32) -> u32,
        ) -> (u64, u64) {
            // One lane: its word read, blended and written back; (saturated, lost).
            let blend = |d: &mut u32, s: u32| {
                let sm = s & src_mask;
                let q = contribution(sm);
                let sum = (*d & max) + q; // u(n) + u(n) → u(n+1)
                *d = sum.min(max);
                (u32::from(sum > max), u32::from(sm != 0 && q == 0))
            };
            // A run's words blended in order: (saturated, lost) counts.
            #[inline(always)]
            fn blend_run<'a>(
                words: impl Iterator<Item = &'a mut u32>,
                src: &[u32],
                blend: &impl Fn(&mut u32, u32) -> (u32, u32),
            ) -> (u32, u32) {
                words.zip(src).fold((0, 0), |(s, u), (d, &x)| {
                    let (a, b) = blend(d, x);
                    (s + a, u + b)
                })
            }
            let (mut sat, mut under) = (0u64, 0u64);
            for (at, src) in at.chunks(BLEND_LANES).zip(src.chunks(BLEND_LANES)) {
                let first = at.first().map_or(0, |&a| a as usize);
                let rising = super::rising_run(at);
                // A row walked leftward (checked only when the run does not rise).
                let falling = !rising && super::falling_run(at);
                let (mut s_block, mut u_block) = (0u32, 0u32);
                if rising || falling {
                    // A run of neighbouring words (a stretch of a row where every walked
                    // pixel is a fragment): one slice, no two lanes on one word, so the
                    // lanes run as vectors (reversed for a leftward run).
                    let lo = if rising { first } else { first + 1 - at.len() } - offset;
                    let words = &mut dst[lo..lo + at.len()];
                    (s_block, u_block) = if rising {
                        blend_run(words.iter_mut(), src, &blend)
                    } else {
                        blend_run(words.iter_mut().rev(), src, &blend)
                    };
                } else {
                    for (&a, &s) in at.iter().zip(src) {
                        let (a, b) = blend(&mut dst[a as usize - offset], s);
                        s_block += a;
                        u_block += b;
                    }
                }
                sat += u64::from(s_block);
                under += u64::from(u_block);
            }
            (sat, under)
        }
        let io = (src, at, offset);
        let (sat, mut under) = match &self.lut {
            Some(lut) => lanes(io, dst, (src_mask, max), |sm| lut[lut_index(sm)]),
            None => lanes(io, dst, (src_mask, max), |sm| unit.contribution(sm)),
        };
        if !weight_on {
            under = 0;
        }
        // Channels 1 ..= 3 carry source and destination 0: the contribution of source 0
        // is 0 (align and weight map 0 to 0), so their sums are 0 and count nothing.
        framebuffer_rmws(ctr, n, unit.pixel_bits());
        ctr.saturations += sat;
        ctr.underflows += under;
    }
}

/// Narrowing u(s) → u(f) by round-to-nearest: v·(2ᶠ−1) = (v << f) − v; + 2ˢ⁻¹ on the
/// upper f+1 bits; (t + (t >> s)) >> s (the J = 1 series). One channel.
fn narrow_cost(s: u32, f: u32) -> crate::cost::Cells {
    prim::subtractor(s + f) + prim::half_adder() * (f + 1) as f64 + prim::adder(s + f)
}

impl Unit for Blend {
    type In = BlendIn;
    type Out = BlendOut;
    type State = ();

    fn name(&self) -> &'static str {
        "blend"
    }

    fn kernel(&self, _: &mut (), input: &BlendIn, ctr: &mut Counters) -> [u32; 4] {
        framebuffer_rmw(ctr, self.pixel_bits());
        let (out, sat, under) = self.blend_pixel_counted(&input.src, &input.dst);
        ctr.saturations += sat as u64;
        ctr.underflows += under as u64;
        out
    }

    /// The kernel with the framebuffer traffic and counters summed per chunk; the
    /// additive datapath looks its contribution up in a table of every source code
    /// (for sources of at most [`CONTRIBUTION_LUT_BITS`] bits), built once per chunk.
    fn kernel_batch(
        &self,
        _: &mut (),
        inputs: &[BlendIn],
        out: &mut Vec<[u32; 4]>,
        ctr: &mut Counters,
    ) {
        let (mut sat, mut under) = (0u64, 0u64);
        if let Some(lut) = self.contribution_table() {
            let (max, src_mask) = (self.max(), max_code(self.src_bits()));
            let weight_on = !self.weighted() || self.cfg.constant[ALPHA] != 0;
            out.extend(inputs.iter().map(|x| {
                let mut o = [0u32; 4];
                for (c, oc) in o.iter_mut().enumerate() {
                    let sm = x.src[c] & src_mask;
                    let q = lut[lut_index(sm)]; // u(n)
                    let sum = (x.dst[c] & max) + q; // u(n+1)
                    *oc = sum.min(max);
                    sat += u64::from(sum > max);
                    under += u64::from(sm != 0 && weight_on && q == 0);
                }
                o
            }));
        } else {
            out.extend(inputs.iter().map(|x| {
                let (o, s, u) = self.blend_pixel_counted(&x.src, &x.dst);
                sat += s as u64;
                under += u as u64;
                o
            }));
        }
        framebuffer_rmws(ctr, inputs.len() as u64, self.pixel_bits());
        ctr.saturations += sat;
        ctr.underflows += under;
    }

    fn timing(&self) -> Timing {
        match self.cfg.datapath {
            // 1: framebuffer read (source aligned / weighted meanwhile); 2: add and
            // saturate; 3: write back.
            BlendDatapath::Additive => Timing { latency: 3, ii: 1 },
            // 1: framebuffer read, factor select; 2: multiply; 3: add and ÷M;
            // 4: clamp, write.
            BlendDatapath::Programmable => Timing { latency: 4, ii: 1 },
        }
    }

    fn cost(&self) -> Cost {
        match self.cfg.datapath {
            BlendDatapath::Additive => self.additive_cost(),
            BlendDatapath::Programmable => self.programmable_cost(),
        }
    }

    fn widths(&self) -> Vec<Width> {
        let w = |name, bits| Width { name, bits };
        let (n, s, k) = (self.cfg.bits, self.src_bits(), self.constant_bits());
        let mut v = match self.cfg.datapath {
            BlendDatapath::Additive => vec![
                w("src_bits", s),
                w("fb_bits", n),
                w("pixel_bits", self.pixel_bits()),
            ],
            BlendDatapath::Programmable => {
                let mut v = vec![w("bits", n), w("pixel_bits", self.pixel_bits())];
                if s != n {
                    v.push(w("src_bits", s));
                }
                v
            }
        };
        if self.weighted() {
            v.push(w("weight_bits", k));
        } else if self.cfg.datapath == BlendDatapath::Programmable && k != n {
            v.push(w("constant_bits", k));
        }
        v
    }

    fn in_signals(&self, i: &BlendIn) -> Vec<Signal> {
        let (n, m) = (self.cfg.bits, self.max());
        let (s, sm) = (self.src_bits(), max_code(self.src_bits()));
        let mut v = Vec::with_capacity(8);
        for (name, &x) in SRC_NAMES.iter().zip(&i.src) {
            v.push(Signal::new(name, s, (x & sm) as u64));
        }
        for (name, &d) in DST_NAMES.iter().zip(&i.dst) {
            v.push(Signal::new(name, n, (d & m) as u64));
        }
        v
    }

    fn out_signals(&self, o: &[u32; 4]) -> Vec<Signal> {
        let (n, m) = (self.cfg.bits, self.max());
        OUT_NAMES
            .iter()
            .zip(o)
            .map(|(name, &y)| Signal::new(name, n, (y & m) as u64))
            .collect()
    }
}
