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
//! [`round_div_mersenne`](super::additive_blend::round_div_mersenne); M is odd: no
//! ties) → s(n+2), then clamps to u(n). [`BlendRounding::PerTerm`]
//! rounds each product to u(n) first (a `modulate` per term, then a saturating add:
//! two roundings, off by one on a tenth to a quarter of the pixels of ADD images) and
//! is kept as the cheaper alternative. MIN / MAX compare the raw u(n) operands; the
//! signed equations add an s(n) source to a u(n) destination → s(n+2).
//!
//! Channel 3 is alpha: the alpha channel's SRC_COLOR factor is the source alpha,
//! DST_COLOR the destination alpha, and SRC_ALPHA_SATURATE is 1 (GL's table).
//!
//! Counters per kernel call (one pixel): `saturations` +1 per channel whose rounded
//! result left 0 ..= M and was clamped (a SUBTRACT below 0 is counted too); one
//! framebuffer read-modify-write of 4·n bits (`memory::framebuffer_rmw`).
//!
//! Pipeline (latency 4, II 1): stage 1 reads the framebuffer and selects the factors;
//! stage 2 multiplies; stage 3 adds (or subtracts, compares) and divides by M;
//! stage 4 clamps and writes back. The read-modify-write hazard of two fragments to
//! one pixel in flight belongs to the pipeline that owns the framebuffer.

use crate::cost::{prim, Cost};
use crate::counters::Counters;
use crate::error::ConfigError;
use crate::memory::{bytes_for_bits, framebuffer_rmw};
use crate::unit::{Signal, Timing, Unit, Width};
use crate::unorm::{check_bits, max_code};
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
    Zero,
    One,
    SrcColor,
    OneMinusSrcColor,
    SrcAlpha,
    OneMinusSrcAlpha,
    DstAlpha,
    OneMinusDstAlpha,
    DstColor,
    OneMinusDstColor,
    /// min(A_s, 1 − A_d) for colour, 1 for alpha.
    SrcAlphaSaturate,
    ConstantColor,
    OneMinusConstantColor,
    ConstantAlpha,
    OneMinusConstantAlpha,
}

impl BlendFactor {
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

/// The configuration as a scene (or a test description) gives it; [`BlendConfig::build`]
/// checks it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct BlendConfig {
    /// Channel width (unorm) of source, destination, constant and factors, 1 ..= 16.
    /// Default 8 (the NV2A's A8R8G8B8 surfaces).
    pub bits: u32,
    pub equation: BlendEquation,
    pub src_factor: BlendFactor,
    pub dst_factor: BlendFactor,
    /// The blend constant colour, RGBA codes of `bits` bits (NV097_SET_BLEND_COLOR).
    pub constant: [u32; 4],
    pub rounding: BlendRounding,
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
        }
    }
}

impl BlendConfig {
    /// Validate; errors name `blend.<field>`.
    pub fn build(&self) -> Result<Blend, ConfigError> {
        check_bits("blend.bits", self.bits)?;
        let max = max_code(self.bits);
        for (c, &k) in self.constant.iter().enumerate() {
            if k > max {
                return Err(ConfigError::out_of_range(
                    [
                        "blend.constant[0]",
                        "blend.constant[1]",
                        "blend.constant[2]",
                        "blend.constant[3]",
                    ][c],
                    k as f64,
                    0.0,
                    max as f64,
                ));
            }
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
    pub src: [u32; 4],
    pub dst: [u32; 4],
}

/// The new framebuffer RGBA.
pub type BlendOut = [u32; 4];

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

    pub fn config(&self) -> BlendConfig {
        self.cfg
    }

    pub fn bits(&self) -> u32 {
        self.cfg.bits
    }

    /// All-ones code (1.0).
    pub fn max(&self) -> u32 {
        max_code(self.cfg.bits)
    }

    /// Bits of one framebuffer pixel, as read and written (4 channels).
    pub fn pixel_bits(&self) -> u32 {
        CHANNELS as u32 * self.cfg.bits
    }

    /// The factor `f` for channel `c` of this pixel, u(n) (operands already masked).
    #[inline]
    pub fn factor(&self, f: BlendFactor, c: usize, s: &[u32; 4], d: &[u32; 4]) -> u32 {
        let m = self.max();
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
            BlendFactor::OneMinusConstantColor => m - k[c],
            BlendFactor::ConstantAlpha => k[ALPHA],
            BlendFactor::OneMinusConstantAlpha => m - k[ALPHA],
        }
    }

    /// round(t / M) for a signed t with |t| ≤ 2M² (M odd: no ties), s(n+2).
    #[inline]
    fn round_signed(&self, t: i64) -> i64 {
        // (2|t| + M) / 2M: the shift-add series in hardware (see `cost`), a constant
        // divide here. u(2n+1) → u(n+1).
        let m = self.max() as u64;
        let q = ((2 * t.unsigned_abs() + m) / (2 * m)) as i64;
        if t < 0 {
            -q
        } else {
            q
        }
    }

    /// Channel `c` before the clamp, s(n+2) (operands masked to n bits).
    #[inline]
    pub fn unclamped(&self, c: usize, s: &[u32; 4], d: &[u32; 4]) -> i64 {
        let n = self.cfg.bits;
        let (sc, dc) = (s[c] as i64, d[c] as i64);
        let eq = self.cfg.equation;
        match eq {
            BlendEquation::Min => sc.min(dc),
            BlendEquation::Max => sc.max(dc),
            BlendEquation::AddSigned | BlendEquation::ReverseSubtractSigned => {
                // sx(s): u(n) read as s(n).
                let sx = if sc >> (n - 1) != 0 {
                    sc - (1i64 << n)
                } else {
                    sc
                };
                if eq == BlendEquation::AddSigned {
                    dc + sx // u(n) + s(n) → s(n+2)
                } else {
                    dc - sx
                }
            }
            BlendEquation::Add | BlendEquation::Subtract | BlendEquation::ReverseSubtract => {
                let fs = self.factor(self.cfg.src_factor, c, s, d) as i64;
                let fd = self.factor(self.cfg.dst_factor, c, s, d) as i64;
                let (ps, pd) = (sc * fs, dc * fd); // u(n) × u(n) → u(2n) each
                let sign = match eq {
                    BlendEquation::Add => (1, 1),
                    BlendEquation::Subtract => (1, -1),
                    _ => (-1, 1),
                };
                match self.cfg.rounding {
                    // u(2n) ± u(2n) → s(2n+2), ÷ M → s(n+2)
                    BlendRounding::Once => self.round_signed(sign.0 * ps + sign.1 * pd),
                    // each u(2n) ÷ M → u(n), then ± → s(n+2)
                    BlendRounding::PerTerm => {
                        sign.0 * self.round_signed(ps) + sign.1 * self.round_signed(pd)
                    }
                }
            }
        }
    }

    /// One pixel: (new RGBA, channels clamped).
    #[inline]
    pub fn blend_pixel(&self, src: &[u32; 4], dst: &[u32; 4]) -> ([u32; 4], u32) {
        let m = self.max();
        let s = src.map(|v| v & m);
        let d = dst.map(|v| v & m);
        let mut out = [0u32; 4];
        let mut sat = 0;
        for (c, o) in out.iter_mut().enumerate() {
            let v = self.unclamped(c, &s, &d);
            let clamped = v.clamp(0, m as i64);
            sat += u32::from(clamped != v);
            *o = clamped as u32; // → u(n)
        }
        (out, sat)
    }
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
        let (out, sat) = self.blend_pixel(&input.src, &input.dst);
        ctr.saturations += sat as u64;
        out
    }

    /// The kernel with the framebuffer traffic and saturations summed per chunk.
    fn kernel_batch(
        &self,
        _: &mut (),
        inputs: &[BlendIn],
        out: &mut Vec<[u32; 4]>,
        ctr: &mut Counters,
    ) {
        let mut sat = 0u64;
        out.extend(inputs.iter().map(|x| {
            let (o, s) = self.blend_pixel(&x.src, &x.dst);
            sat += s as u64;
            o
        }));
        let bytes = bytes_for_bits(self.pixel_bits()) * inputs.len() as u64;
        ctr.mem_read_bytes += bytes;
        ctr.mem_write_bytes += bytes;
        ctr.saturations += sat;
    }

    fn timing(&self) -> Timing {
        // 1: framebuffer read, factor select; 2: multiply; 3: add and ÷M; 4: clamp, write.
        Timing { latency: 4, ii: 1 }
    }

    fn cost(&self) -> Cost {
        let n = self.cfg.bits;
        let ch = CHANNELS as f64;
        let mut c = Cost::default()
            .part("input registers (src)", prim::register(4 * n))
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
            .part("constant colour register", prim::register(4 * n))
            .part(
                "factor muxes (15 inputs, two per channel)",
                prim::mux_k(n, 15) * (2.0 * ch),
            )
            .part("one-minus inverters", prim::mux(n) * (2.0 * ch))
            .part("src_alpha_saturate min", prim::comparator(n) + prim::mux(n))
            .part("multipliers n×n", prim::multiplier(n, n) * (2.0 * ch))
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
                c = c
                    .part(
                        "÷M shift-add series, per term",
                        prim::adder(2 * n + 1) * (2.0 * j * ch),
                    )
                    .part("add/subtract terms", prim::adder(n + 1) * ch)
            }
        }
        c
    }

    fn widths(&self) -> Vec<Width> {
        vec![
            Width {
                name: "bits",
                bits: self.cfg.bits,
            },
            Width {
                name: "pixel_bits",
                bits: self.pixel_bits(),
            },
        ]
    }

    fn in_signals(&self, i: &BlendIn) -> Vec<Signal> {
        let (n, m) = (self.cfg.bits, self.max());
        let mut v = Vec::with_capacity(8);
        for (name, &s) in SRC_NAMES.iter().zip(&i.src) {
            v.push(Signal::new(name, n, (s & m) as u64));
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
