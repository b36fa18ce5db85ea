//! reflection_vector — per-pixel reflection vector, λ scale and 3D texel coordinates:
//! the GeForce3 texture-shader stage (DOT_PRODUCT_REFLECT-style) of the multi-scale
//! environment map. From the polygon interpolator's normal n and eye vector e = eye − p
//! (neither unit length) and the smoothness λ ∈ [0, 1]:
//! n̂ = n/|n|, v̂ = e/|e|, r = 2(n̂·v̂)n̂ − v̂, t = r·λ, coord = (t + 1)/2 · s per axis in
//! the 3D `texture_sampler`'s texel-space words.
//!
//! Datapath (W = in_int_bits + in_frac_bits, A = rsqrt_addr_bits, R = rsqrt_bits,
//! N = newton_frac_bits, B = norm_bits, L = lambda_bits, F = coord_frac_bits,
//! O = coord_int_bits + F, s = 2^side_log2). Integers only; the input fraction bits
//! cancel in the normalisation (n̂ = N/|N| on the raw codes).
//! 0. Block normalisation (P = `mant_bits`): the leading one q of |x₀| | |x₁| | |x₂|
//!    (OR tree + LZC; all-zero is a zero vector) sets one right shift
//!    sh = max(0, q − (P − 2)) for the three components: s(W) >> sh → s(P) mantissas,
//!    truncated (the dropped bits cost a direction error < √3·2^−(P−3); see the
//!    datasheet). The shift cancels in n̂ = x/|x|, so it is not carried.
//! 1. Squared lengths: each mantissa s(P) squared → u(2P−2) (|x'| ≤ 2^(P−1)), the
//!    sum of three → S u(2P) (3·2^(2P−2) < 2^(2P)).
//! 2. Reciprocal square root: p = position of S's leading one (LZC), k = ⌊p/2⌋, so
//!    S = 2^(2k)·m with m ∈ [1, 4) (an even shift). The ROM address is the parity of p
//!    (m ∈ [1, 2) or [2, 4)) above the A − 1 bits below the leading one: 2^A entries of
//!    R bits, entry j = min(round(2^R / √c_j), 2^R − 1) (u0.R), c_j the midpoint of
//!    the entry's m interval (computed from f64 at build time: it is a ROM image).
//!    Optional Newton–Raphson step y' = y·(3 − m·y²)/2 in N fraction bits:
//!    q = y² (u0.R × u0.R → u0.2R, rounded to u1.N); m_N = m truncated to u2.N;
//!    m_N·q (u2.N × u1.N → u3.2N); d = 3 − m_N·q rounded to u2.N; y·d (u0.R × u2.N →
//!    u2.(R+N)), halved and rounded to u1.N.
//! 3. n̂_i = x'_i·y·2^−k: s(P) × u1.Fy → s(P+Fy+1), shifted right by k + Fy − B and
//!    rounded (ties up) into s2.B (Fy = N with Newton, R without). s2.B, not s1.B: an
//!    axis-aligned normal has a component of exactly ±1, which s1.B cannot hold.
//!    Zero vectors: n = 0 → n̂ := v̂ (then r = v̂); e = 0 → v̂ := n̂ (r = n̂); both zero
//!    → n̂ = v̂ = 0, r = 0, t = 0, the map's centre. Each zero vector counts one
//!    `underflows` (the vector has no direction); the renderer's f64 path has the same
//!    rule.
//! 4. d = n̂·v̂: three s2.B × s2.B → s4.2B products, summed → s6.2B, rounded to s3.B.
//!    r_i = 2·d·n̂_i − v̂_i: s3.B × s2.B → s5.2B, doubled → s6.2B, minus v̂_i (aligned)
//!    → s7.2B, rounded into s3.B. t_i = r_i·λ: s3.B × u1.L → s4.(B+L), exact.
//! 5. coord_i = (t_i + 1)·2^(side_log2 − 1) texels: t_i + 1 (s5.(B+L)) shifted right by
//!    B + L + 1 − side_log2 − F (a fixed wiring for a given config) and rounded to
//!    nearest, ties up — the same rounding as `texture_sampler`'s
//!    `input_from_normalized` — into the sampler's s(coord_int).F word, saturating
//!    (counted in `saturations`). Texel centres sit at i + ½ in this word (the sampler's
//!    convention), so coord = (t + 1)/2 · s needs no offset.
//!
//! λ: an unsigned u1.L code (L = `lambda_bits`, default 12) so that λ = 1 is exact
//! (code 2^L); codes above 2^L are clamped to 1.0 (counted in `saturations`).
//!
//! Timing: II 1; latency 9 stages without Newton (block normalise | squares | LZC +
//! normalise | ROM | n̂, v̂ | d | r | t | coord), 12 with (3 more: y², 3 − m·y²,
//! y·d/2).
//! Counters: `table_reads` (one per rsqrt ROM read: 2 per pixel, none for a zero
//! vector), `underflows` (zero vectors), `saturations` (λ clamps, coordinate clamps and
//! guard clamps of internal words that cannot fire on a valid config with a converging
//! rsqrt; see the datasheet).

use crate::cost::{prim, Cells, Cost};
use crate::counters::Counters;
use crate::error::{check_finite, check_range, ConfigError};
use crate::fixed_point::{round_shift, round_shift_right_i64, Format, Fx, Overflow, Quant};
use crate::packed_rom::PackedRom;
use crate::unit::{Signal, Timing, Unit, Width};
use crate::units::texture_sampler::TextureSamplerIn;
use crate::wire::{bits_for, saturate_signed as sat_signed, sign_extend as sext};
use serde::{Deserialize, Serialize};

/// Widest input word W (squares and their sum then fit u64).
pub const MAX_IN_WIDTH: u32 = 32;

/// The plain config (serde-friendly); [`ReflectionVectorConfig::build`] validates it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ReflectionVectorConfig {
    /// Integer bits of n, e including the sign, 1 ..= 24 (W = int + frac ≤ 32).
    pub in_int_bits: u32,
    /// Fraction bits of n, e, 0 ..= 24.
    pub in_frac_bits: u32,
    /// λ fraction bits L of the u1.L λ word, 1 ..= 16.
    pub lambda_bits: u32,
    /// rsqrt ROM address bits A (2^A entries), 1 ..= 12.
    pub rsqrt_addr_bits: u32,
    /// rsqrt ROM entry bits R (u0.R), 2 ..= 24.
    pub rsqrt_bits: u32,
    /// One Newton–Raphson step after the table.
    pub newton: bool,
    /// Fraction bits N of the Newton datapath, 4 ..= 30 (unused without Newton).
    pub newton_frac_bits: u32,
    /// Fraction bits B of n̂, v̂, d and r (s2.B, s3.B), 2 ..= 24.
    pub norm_bits: u32,
    /// Mantissa bits P (signed) each vector is block-normalised to before squaring,
    /// 4 ..= 32 (P ≥ W: no truncation).
    pub mant_bits: u32,
    /// log2 of the map side s (the 3D texture is s × s × s), 0 ..= 12.
    pub side_log2: u32,
    /// Integer bits of the output texel coordinate including the sign, 1 ..= 32 − F.
    pub coord_int_bits: u32,
    /// Sub-texel fraction bits F of the output coordinate, 0 ..= 16.
    pub coord_frac_bits: u32,
}

impl Default for ReflectionVectorConfig {
    fn default() -> Self {
        Self::geforce3()
    }
}

impl ReflectionVectorConfig {
    /// GeForce3 defaults (justified in the datasheet, docs/datasheets/reflection_vector.md):
    /// n, e in s16.16 (the interpolator's output words, fed raw); λ in u1.12; a 256-entry
    /// × 11-bit rsqrt ROM (one per vector) and one Newton step at 18 fraction bits
    /// (|y·√m − 1| ≤ 2^−15.5 < 2^−15, below the half LSB of n̂); n̂, v̂, r with 14
    /// fraction bits; a 128³ map; coordinates in the sampler's s16.8.
    pub fn geforce3() -> Self {
        ReflectionVectorConfig {
            in_int_bits: 16,
            in_frac_bits: 16,
            lambda_bits: 12,
            rsqrt_addr_bits: 8,
            rsqrt_bits: 11,
            newton: true,
            newton_frac_bits: 18,
            norm_bits: 14,
            mant_bits: 19,
            side_log2: 7,
            coord_int_bits: 16,
            coord_frac_bits: 8,
        }
    }

    /// Validate and build the ROM; the same as [`ReflectionVector::new`], errors name
    /// `reflection_vector.<field>`.
    pub fn build(&self) -> Result<ReflectionVector, ConfigError> {
        ReflectionVector::new(*self)
    }
}

/// One pixel: the interpolator's raw s(in_int).(in_frac) codes of n and e (masked and
/// sign-extended to W wires), and λ as a u1.L code (≤ 2^L; larger codes clamp to 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct ReflectionVectorIn {
    /// The normal n (not unit length), raw s(in_int_bits).(in_frac_bits) codes.
    pub n: [i64; 3],
    /// The eye vector e = eye − p (not unit length), raw s(in_int_bits).(in_frac_bits)
    /// codes.
    pub e: [i64; 3],
    /// Smoothness λ, a u1.L code (L = `lambda_bits`): 2^L is 1.0, larger codes clamp to 1.0.
    pub lambda: u32,
}

/// The three texel-space coordinate words (s(coord_int).F) and flags.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct ReflectionVectorOut {
    /// Texel-space coordinates (t + 1)/2 · s per axis, raw s(coord_int_bits).(coord_frac_bits)
    /// codes (saturated, counted).
    pub coord: [i32; 3],
    /// d = n̂·v̂ < 0 (the normal faces away from the eye).
    pub back_facing: bool,
    /// n was the zero vector (n̂ := v̂).
    pub zero_n: bool,
    /// e was the zero vector (v̂ := n̂).
    pub zero_e: bool,
}

impl ReflectionVectorOut {
    /// The sampler's input word (the coordinates are already in its s16.8 format at the
    /// defaults; the config must match the sampler's `coord_int_bits`/`coord_frac_bits`).
    pub fn sampler_in(&self) -> TextureSamplerIn {
        TextureSamplerIn { coord: self.coord }
    }
}

/// The intermediate words of one pixel, for tests and traces (raw codes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct ReflectionParts {
    /// n̂ in s2.B.
    pub n_hat: [i64; 3],
    /// v̂ in s2.B.
    pub v_hat: [i64; 3],
    /// n̂·v̂ in s3.B.
    pub d: i64,
    /// r in s3.B.
    pub r: [i64; 3],
    /// λ in u1.L after the clamp.
    pub lambda: u32,
    /// t = r·λ in s4.(B+L).
    pub t: [i64; 3],
    /// The unit's output for the pixel.
    pub out: ReflectionVectorOut,
}

/// One reciprocal-square-root result: S = 2^(2k)·m, y ≈ 1/√m as u1.`frac` raw.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rsqrt {
    /// 1/√m as a raw fixed-point code with `frac` fraction bits.
    pub y: u64,
    /// Fraction bits of `y`: `rsqrt_bits` (R) without Newton, `newton_frac_bits` (N) with it.
    pub frac: u32,
    /// Half the even exponent of S: S = 2^(2k)·m, m ∈ [1, 4).
    pub k: u32,
}

/// The validated unit: its config and the rsqrt ROM image (one ROM per vector in
/// hardware; the model holds the image once and the cost counts both copies).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ReflectionVector {
    cfg: ReflectionVectorConfig,
    rom: PackedRom,
    /// The batch kernel's specialised form, where the config allows it.
    fast: Option<FastForm>,
}

/// The batch kernel's form of the datapath ([`ReflectionVector::kernel_batch`]): the
/// same words in 64-bit carriers (every shift a fixed wiring of the config, inlined;
/// the ROM read from a decoded copy of the same image). Chosen at construction when
/// every intermediate word fits i64: the widest is the Newton step's 3 − m·y², u3.2N
/// with N ≤ 29 (2N + 4 ≤ 62 bits); without Newton every config fits (n̂ products are
/// s(P+Fy+1) ≤ s63, the rest ≤ s52). Other configs take the general (i128) path.
#[derive(Clone, Debug, PartialEq, Eq)]
struct FastForm {
    /// The rsqrt ROM entries, u0.R each (R ≤ 24), address order.
    rom: Vec<u32>,
}

/// The datapath's front ([`ReflectionVector::front`]): λ in u1.L after the clamp,
/// n̂ and v̂ in s2.B after the zero-vector muxes, and which vector was zero.
struct Front {
    lambda: u32,
    n_hat: [i64; 3],
    v_hat: [i64; 3],
    zero_n: bool,
    zero_e: bool,
}

/// Largest Newton fraction width N the 64-bit form holds (u3.2N ≤ 61 bits + sign).
const FAST_MAX_NEWTON_FRAC: u32 = 29;

/// [`round_shift`] in a 64-bit carrier for a result that fits: a right shift of
/// 1 ..= 63 rounds by `q`, a left shift (`sh` ≤ 0) is exact.
#[inline]
fn shift_i64(x: i64, sh: i32, q: Quant) -> i64 {
    if sh > 0 {
        round_shift_right_i64(x, sh as u32, q)
    } else {
        x << (-sh) as u32
    }
}

/// ROM entry j for A address bits and R entry bits: the parity P = j >> (A − 1) and
/// the index i = j mod 2^(A−1) give the interval midpoint c = 2^P·(1 + (i + ½)/2^(A−1))
/// of m ∈ [1, 4); entry = min(round(2^R/√c), 2^R − 1), u0.R.
pub fn rsqrt_rom_entry(j: u64, addr_bits: u32, entry_bits: u32) -> u64 {
    let a1 = addr_bits - 1;
    let p = (j >> a1) & 1;
    let i = j & ((1u64 << a1) - 1);
    let c = (1.0 + (i as f64 + 0.5) / (a1 as f64).exp2()) * (p as f64 + 1.0);
    let v = ((entry_bits as f64).exp2() / c.sqrt()).round() as u64;
    v.min((1u64 << entry_bits) - 1)
}

impl ReflectionVector {
    /// Validate a config and build the ROM; errors name `reflection_vector.<field>`.
    pub fn new(cfg: ReflectionVectorConfig) -> Result<Self, ConfigError> {
        let f = |n: &str| format!("reflection_vector.{n}");
        check_range(&f("in_int_bits"), cfg.in_int_bits as u64, 1, 24)?;
        check_range(&f("in_frac_bits"), cfg.in_frac_bits as u64, 0, 24)?;
        check_range(
            &f("in_frac_bits"),
            (cfg.in_int_bits + cfg.in_frac_bits) as u64,
            1,
            MAX_IN_WIDTH as u64,
        )?;
        check_range(&f("lambda_bits"), cfg.lambda_bits as u64, 1, 16)?;
        check_range(&f("rsqrt_addr_bits"), cfg.rsqrt_addr_bits as u64, 1, 12)?;
        check_range(&f("rsqrt_bits"), cfg.rsqrt_bits as u64, 2, 24)?;
        check_range(&f("newton_frac_bits"), cfg.newton_frac_bits as u64, 4, 30)?;
        check_range(&f("norm_bits"), cfg.norm_bits as u64, 2, 24)?;
        check_range(&f("mant_bits"), cfg.mant_bits as u64, 4, 32)?;
        check_range(&f("side_log2"), cfg.side_log2 as u64, 0, 12)?;
        check_range(&f("coord_frac_bits"), cfg.coord_frac_bits as u64, 0, 16)?;
        check_range(
            &f("coord_int_bits"),
            cfg.coord_int_bits as u64,
            1,
            (32 - cfg.coord_frac_bits) as u64,
        )?;
        let (a, r) = (cfg.rsqrt_addr_bits, cfg.rsqrt_bits);
        let words: Vec<u64> = (0..1u64 << a).map(|j| rsqrt_rom_entry(j, a, r)).collect();
        let fast = (!cfg.newton || cfg.newton_frac_bits <= FAST_MAX_NEWTON_FRAC).then(|| {
            FastForm {
                rom: words.iter().map(|&w| w as u32).collect(), // u0.R, R ≤ 24
            }
        });
        Ok(ReflectionVector {
            cfg,
            rom: PackedRom::new(r, &words),
            fast,
        })
    }

    /// GeForce3 defaults (see [`ReflectionVectorConfig::geforce3`]).
    pub fn geforce3() -> Self {
        match Self::new(ReflectionVectorConfig::geforce3()) {
            Ok(u) => u,
            Err(e) => unreachable!("default config invalid: {e}"),
        }
    }

    /// Alias of [`Self::geforce3`].
    pub fn geforce() -> Self {
        Self::geforce3()
    }

    /// The config the unit was built from.
    pub fn config(&self) -> ReflectionVectorConfig {
        self.cfg
    }

    /// Input width W.
    pub fn in_bits(&self) -> u32 {
        self.cfg.in_int_bits + self.cfg.in_frac_bits
    }

    /// Input format s(in_int).(in_frac).
    pub fn in_format(&self) -> Format {
        Format {
            int_bits: self.cfg.in_int_bits,
            frac_bits: self.cfg.in_frac_bits,
            signed: true,
        }
    }

    /// Output width O = coord_int + F.
    pub fn out_bits(&self) -> u32 {
        self.cfg.coord_int_bits + self.cfg.coord_frac_bits
    }

    /// Map side s = 2^side_log2.
    pub fn side(&self) -> u32 {
        1 << self.cfg.side_log2
    }

    /// Fraction bits of the final 1/√m: N with Newton, R without.
    pub fn rsqrt_frac_bits(&self) -> u32 {
        if self.cfg.newton {
            self.cfg.newton_frac_bits
        } else {
            self.cfg.rsqrt_bits
        }
    }

    /// ROM bits of the unit: two copies (n and e are normalised in parallel, II 1).
    pub fn rom_bits(&self) -> u64 {
        2 * self.rom.ram_bits()
    }

    /// The ROM entries, address order.
    pub fn rom_words(&self) -> Vec<u64> {
        self.rom.words()
    }

    /// Host helper: quantise f64 n, e (round to nearest, ties up, saturating into
    /// s(in_int).(in_frac), counted) and λ (clamped to [0, 1], counted, rounded to
    /// u1.L). NaN/±∞ is an error naming `reflection_vector.n`, `.e` or `.lambda`.
    pub fn quantise_in(
        &self,
        n: [f64; 3],
        e: [f64; 3],
        lambda: f64,
        ctr: &mut Counters,
    ) -> Result<ReflectionVectorIn, ConfigError> {
        let fmt = self.in_format();
        let q = |x: f64, field: &str, ctr: &mut Counters| {
            Fx::from_f64(x, fmt, Quant::Rnd, Overflow::Sat, field, ctr).map(|v| v.raw as i64)
        };
        let mut out = ReflectionVectorIn::default();
        for k in 0..3 {
            out.n[k] = q(n[k], "reflection_vector.n", ctr)?;
            out.e[k] = q(e[k], "reflection_vector.e", ctr)?;
        }
        let l = check_finite("reflection_vector.lambda", lambda)?;
        let lc = if !(0.0..=1.0).contains(&l) {
            ctr.saturations += 1;
            l.clamp(0.0, 1.0)
        } else {
            l
        };
        let lf = Format::new(1, self.cfg.lambda_bits, false)?;
        // lc ∈ [0, 1] fits u1.L after rounding: no saturation possible here.
        out.lambda = Fx::from_f64(
            lc,
            lf,
            Quant::Rnd,
            Overflow::Sat,
            "reflection_vector.lambda",
            ctr,
        )?
        .raw as u32;
        Ok(out)
    }

    /// Integer helper: a λ code with `frac_bits` fraction bits (e.g. the interpolator's
    /// raw s16.16 λ, frac_bits = 16) → the u1.L λ word: rounded to nearest (ties up),
    /// clamped to [0, 1] (a clamp counts one `saturations`).
    pub fn lambda_from_code(&self, raw: i64, frac_bits: u32, ctr: &mut Counters) -> u32 {
        let l = self.cfg.lambda_bits;
        let v = round_shift(raw as i128, frac_bits as i32 - l as i32, Quant::Rnd);
        let one = 1i128 << l;
        if !(0..=one).contains(&v) {
            ctr.saturations += 1;
        }
        v.clamp(0, one) as u32
    }

    /// An output coordinate word in texels.
    pub fn coord_to_f64(&self, raw: i32) -> f64 {
        raw as f64 * (-(self.cfg.coord_frac_bits as f64)).exp2()
    }

    /// 1/√S for S > 0 (u(2W), larger inputs are masked to their 64-bit wire): the
    /// table read (counted) and the optional Newton step. S = 0 (never reached from the
    /// kernel) gives y = 0 and no read.
    pub fn rsqrt(&self, s: u64, ctr: &mut Counters) -> Rsqrt {
        if s == 0 {
            return Rsqrt {
                y: 0,
                frac: self.rsqrt_frac_bits(),
                k: 0,
            };
        }
        let a1 = self.cfg.rsqrt_addr_bits - 1;
        let p = 63 - s.leading_zeros(); // leading-one position, 0 ..= 2W − 1
        let k = p / 2; // S = 2^(2k)·m, m ∈ [1, 4)
        let par = (p & 1) as u64;
        let below = s & !(1u64 << p); // the bits below the leading one
        let idx = if p >= a1 {
            below >> (p - a1)
        } else {
            below << (a1 - p)
        }; // u(A−1)
        let addr = (par << a1) | idx; // u(A)
        ctr.table_reads += 1;
        let y0 = self.rom.read(addr as usize) as u64; // u0.R
        let r = self.cfg.rsqrt_bits;
        if !self.cfg.newton {
            return Rsqrt { y: y0, frac: r, k };
        }
        let n = self.cfg.newton_frac_bits;
        // m = S / 2^(2k) as u2.(2k), truncated (or zero-extended) to u2.N.
        let m_n = round_shift(s as i128, 2 * k as i32 - n as i32, Quant::Trn); // u2.N
        let q = round_shift((y0 * y0) as i128, 2 * r as i32 - n as i32, Quant::Rnd); // u0.2R → u1.N
        let mq = m_n * q; // u2.N × u1.N → u3.2N
        let three = 3i128 << (2 * n);
        let d = round_shift(three - mq, n as i32, Quant::Rnd); // s4.2N → u2.N
        let d_max = (1i128 << (n + 2)) - 1;
        let d = if !(0..=d_max).contains(&d) {
            ctr.saturations += 1; // guard: cannot fire while |y0·√m − 1| < √3 − 1
            d.clamp(0, d_max)
        } else {
            d
        };
        let yd = y0 as i128 * d; // u0.R × u2.N → u2.(R+N)
        let y1 = round_shift(yd, r as i32 + 1, Quant::Rnd); // ·½ → u1.N (≤ 2^(N+1) − 1)
        let y_max = (1i128 << (n + 1)) - 1;
        let y1 = if y1 > y_max {
            ctr.saturations += 1; // guard: y1 ≤ (1 + e1)/√m < 2
            y_max
        } else {
            y1
        };
        Rsqrt {
            y: y1 as u64,
            frac: n,
            k,
        }
    }

    /// Block normalisation of one vector (raw s(W) codes) to s(P) mantissas: the
    /// leading one q of |x₀| | |x₁| | |x₂| sets a common right shift
    /// sh = max(0, q − (P − 2)), which drops bits (truncation, toward −∞). Returns the
    /// mantissas (the shift cancels in n̂) or None for the zero vector.
    pub fn block_normalise(&self, x: [i64; 3]) -> Option<[i64; 3]> {
        let or = x.iter().fold(0u64, |a, &c| a | c.unsigned_abs()); // u(W)
        if or == 0 {
            return None;
        }
        let q = 63 - or.leading_zeros(); // 0 ..= W − 1
        let sh = q.saturating_sub(self.cfg.mant_bits - 2);
        Some(x.map(|c| c >> sh)) // s(W) >> sh → s(P) (|x'| < 2^(P−1))
    }

    /// Normalise one vector (raw s(W) codes): None for the zero vector, else s2.B
    /// components. Counts the ROM read.
    fn normalise(&self, x: [i64; 3], ctr: &mut Counters) -> Option<[i64; 3]> {
        let x = self.block_normalise(x)?;
        // Squares s(P)² → u(2P−2); their sum u(2P) ≤ 3·2^(2P−2) < 2^64.
        let s: u64 = x.iter().map(|&c| (c as i128 * c as i128) as u64).sum();
        let rs = self.rsqrt(s, ctr);
        let b = self.cfg.norm_bits;
        let shift = rs.k as i32 + rs.frac as i32 - b as i32;
        let mut out = [0i64; 3];
        for (o, &c) in out.iter_mut().zip(&x) {
            let prod = c as i128 * rs.y as i128; // s(P) × u1.Fy → s(P+Fy+1)
            let v = round_shift(prod, shift, Quant::Rnd); // → s2.B
            *o = sat_signed(v, b + 2, ctr) as i64; // guard: |n̂_i| ≤ 1 + e + 2^−(B+1) < 2
        }
        Some(out)
    }

    /// The front of the datapath, both forms: the u1.L λ wire clamped to 1 (counted),
    /// n̂ and v̂ by `normalise` from the s(W) wires, and the zero-vector muxes.
    #[inline]
    fn front(
        &self,
        input: &ReflectionVectorIn,
        ctr: &mut Counters,
        normalise: impl Fn(&Self, [i64; 3], &mut Counters) -> Option<[i64; 3]>,
    ) -> Front {
        let w = self.in_bits();
        let l = self.cfg.lambda_bits;
        let one = 1u32 << l;
        let lam_wire = input.lambda & ((1u32 << (l + 1)) - 1); // u1.L wire
        let lambda = if lam_wire > one {
            ctr.saturations += 1; // λ > 1 clamps to 1
            one
        } else {
            lam_wire
        };
        let nh = normalise(self, input.n.map(|x| sext(x, w)), ctr); // i64 → s(W) wires
        let vh = normalise(self, input.e.map(|x| sext(x, w)), ctr);
        let (zero_n, zero_e) = (nh.is_none(), vh.is_none());
        ctr.underflows += u64::from(zero_n) + u64::from(zero_e);
        // Zero-vector muxes: n̂ := v̂, v̂ := n̂; both zero → 0.
        let (n_hat, v_hat) = match (nh, vh) {
            (Some(a), Some(b)) => (a, b),
            (None, Some(b)) => (b, b),
            (Some(a), None) => (a, a),
            (None, None) => ([0; 3], [0; 3]),
        };
        Front {
            lambda,
            n_hat,
            v_hat,
            zero_n,
            zero_e,
        }
    }

    /// The whole datapath with its intermediate words.
    pub fn parts(&self, input: &ReflectionVectorIn, ctr: &mut Counters) -> ReflectionParts {
        let c = self.cfg;
        let l = c.lambda_bits;
        let fr = self.front(input, ctr, Self::normalise);
        let (lambda, n_hat, v_hat) = (fr.lambda, fr.n_hat, fr.v_hat);
        let (zero_n, zero_e) = (fr.zero_n, fr.zero_e);
        let b = c.norm_bits;
        // d = n̂·v̂: s2.B × s2.B → s4.2B, sum of three → s6.2B, rounded to s3.B.
        let dot: i128 = (0..3).map(|k| n_hat[k] as i128 * v_hat[k] as i128).sum();
        let d = sat_signed(round_shift(dot, b as i32, Quant::Rnd), b + 3, ctr); // s3.B
        let mut r = [0i64; 3];
        let mut t = [0i64; 3];
        let mut coord = [0i32; 3];
        let lf = b + l; // fraction bits of t
        let f = c.coord_frac_bits;
        // coord = (t + 1)·2^(side_log2 − 1)·2^F: shift right by B + L + 1 − side − F.
        let out_shift = lf as i32 + 1 - c.side_log2 as i32 - f as i32;
        let ow = self.out_bits();
        for k in 0..3 {
            // 2·d·n̂_k: s3.B × s2.B → s5.2B, ×2 → s6.2B; − v̂_k·2^B → s7.2B; → s3.B.
            let x = 2 * d * n_hat[k] as i128 - ((v_hat[k] as i128) << b);
            r[k] = sat_signed(round_shift(x, b as i32, Quant::Rnd), b + 3, ctr) as i64;
            // t = r·λ: s3.B × u1.L → s4.(B+L), exact.
            t[k] = r[k] * lambda as i64;
            // t + 1: s5.(B+L); scaled and rounded to nearest (ties up) into s(O−F).F.
            let v = round_shift(t[k] as i128 + (1i128 << lf), out_shift, Quant::Rnd);
            coord[k] = sat_signed(v, ow, ctr) as i32;
        }
        ReflectionParts {
            n_hat,
            v_hat,
            d: d as i64,
            r,
            lambda,
            t,
            out: ReflectionVectorOut {
                coord,
                back_facing: d < 0,
                zero_n,
                zero_e,
            },
        }
    }
}

/// The batch kernel's 64-bit form: [`ReflectionVector::parts`]' words, step for step
/// (see [`FastForm`] for why each fits).
impl ReflectionVector {
    /// [`ReflectionVector::rsqrt`] for S > 0: (y, k), y in u1.Fy.
    #[inline]
    fn rsqrt_fast(&self, rom: &[u32], s: u64, ctr: &mut Counters) -> (i64, u32) {
        let c = &self.cfg;
        let a1 = c.rsqrt_addr_bits - 1;
        let p = 63 - s.leading_zeros();
        let k = p / 2;
        let par = (p & 1) as u64;
        let below = s & !(1u64 << p);
        let idx = if p >= a1 {
            below >> (p - a1)
        } else {
            below << (a1 - p)
        };
        ctr.table_reads += 1;
        let y0 = rom[((par << a1) | idx) as usize] as i64; // u0.R
        if !c.newton {
            return (y0, k);
        }
        let (n, r) = (c.newton_frac_bits, c.rsqrt_bits);
        // S < 2^(2P) ≤ 2^64 but S < 2^(2k+2): m_N = S·2^(N−2k) < 2^(N+2) fits either way.
        let m_n = if 2 * k > n {
            (s >> (2 * k - n)) as i64 // truncation of a non-negative word
        } else {
            (s << (n - 2 * k)) as i64
        }; // u2.N
        let q = shift_i64(y0 * y0, 2 * r as i32 - n as i32, Quant::Rnd); // u1.N
        let d = round_shift_right_i64((3i64 << (2 * n)) - m_n * q, n, Quant::Rnd); // u2.N
        let d_max = (1i64 << (n + 2)) - 1;
        let d = if !(0..=d_max).contains(&d) {
            ctr.saturations += 1;
            d.clamp(0, d_max)
        } else {
            d
        };
        let y1 = round_shift_right_i64(y0 * d, r + 1, Quant::Rnd); // u1.N
        let y_max = (1i64 << (n + 1)) - 1;
        let y1 = if y1 > y_max {
            ctr.saturations += 1;
            y_max
        } else {
            y1
        };
        (y1, k)
    }

    /// [`ReflectionVector::normalise`]: s2.B components, None for the zero vector.
    #[inline]
    fn normalise_fast(&self, rom: &[u32], x: [i64; 3], ctr: &mut Counters) -> Option<[i64; 3]> {
        let x = self.block_normalise(x)?; // s(P)
        let s: u64 = x.iter().map(|&c| (c * c) as u64).sum(); // u(2P)
        let (y, k) = self.rsqrt_fast(rom, s, ctr);
        let b = self.cfg.norm_bits;
        let shift = k as i32 + self.rsqrt_frac_bits() as i32 - b as i32;
        Some(x.map(|c| {
            let v = shift_i64(c * y, shift, Quant::Rnd); // s(P+Fy+1) → s2.B
            sat_signed(v as i128, b + 2, ctr) as i64
        }))
    }

    /// [`ReflectionVector::parts`]' output word.
    #[inline]
    fn out_fast(
        &self,
        rom: &[u32],
        input: &ReflectionVectorIn,
        ctr: &mut Counters,
    ) -> ReflectionVectorOut {
        let c = &self.cfg;
        let l = c.lambda_bits;
        let fr = self.front(input, ctr, |u, x, ctr| u.normalise_fast(rom, x, ctr));
        let (lambda, n_hat, v_hat) = (fr.lambda, fr.n_hat, fr.v_hat);
        let (zero_n, zero_e) = (fr.zero_n, fr.zero_e);
        let b = c.norm_bits;
        let dot: i64 = (0..3).map(|k| n_hat[k] * v_hat[k]).sum(); // s6.2B
        let d = sat_signed(
            round_shift_right_i64(dot, b, Quant::Rnd) as i128,
            b + 3,
            ctr,
        ) as i64; // s3.B
        let lf = b + l;
        let out_shift = lf as i32 + 1 - c.side_log2 as i32 - c.coord_frac_bits as i32;
        let ow = self.out_bits();
        let mut coord = [0i32; 3];
        for k in 0..3 {
            let x = 2 * d * n_hat[k] - (v_hat[k] << b); // s7.2B
            let r = sat_signed(round_shift_right_i64(x, b, Quant::Rnd) as i128, b + 3, ctr) as i64; // s3.B
            let t = r * lambda as i64; // s4.(B+L)
            let v = shift_i64(t + (1i64 << lf), out_shift, Quant::Rnd);
            coord[k] = sat_signed(v as i128, ow, ctr) as i32;
        }
        ReflectionVectorOut {
            coord,
            back_facing: d < 0,
            zero_n,
            zero_e,
        }
    }
}

impl Unit for ReflectionVector {
    type In = ReflectionVectorIn;
    type Out = ReflectionVectorOut;
    type State = ();

    fn name(&self) -> &'static str {
        "reflection_vector"
    }

    fn kernel(
        &self,
        _: &mut (),
        input: &ReflectionVectorIn,
        ctr: &mut Counters,
    ) -> ReflectionVectorOut {
        self.parts(input, ctr).out
    }

    /// The 64-bit form (`FastForm`) where the config has it, its counters summed per
    /// chunk; else the per-word kernel.
    fn kernel_batch(
        &self,
        _: &mut (),
        inputs: &[ReflectionVectorIn],
        out: &mut Vec<ReflectionVectorOut>,
        ctr: &mut Counters,
    ) {
        match &self.fast {
            Some(f) => {
                let mut c = Counters::default();
                out.extend(inputs.iter().map(|x| self.out_fast(&f.rom, x, &mut c)));
                *ctr += c;
            }
            None => out.extend(inputs.iter().map(|x| self.parts(x, ctr).out)),
        }
    }

    fn timing(&self) -> Timing {
        // block normalise | squares | LZC + normalise + address | ROM | [y² | 3 − m·y² | y·d/2] |
        // n̂, v̂ | d | r | t | coord.
        Timing {
            latency: 9 + if self.cfg.newton { 3 } else { 0 },
            ii: 1,
        }
    }

    fn cost(&self) -> Cost {
        let c = self.cfg;
        let w = self.in_bits();
        let (a, r, n, b, l) = (
            c.rsqrt_addr_bits,
            c.rsqrt_bits,
            c.newton_frac_bits,
            c.norm_bits,
            c.lambda_bits,
        );
        let o = self.out_bits();
        let fy = self.rsqrt_frac_bits();
        let pe = c.mant_bits.min(w); // mantissa width after block normalisation
        let kb = bits_for(pe as u64); // k ≤ P − 1
        let sb = 2 * pe; // S width
        let lam = l + 1; // u1.L
                         // Carried down the pipe until the normalisation: mantissas, λ, and per vector k
                         // and the zero flag.
        let carry = 6 * pe + lam + 2 * (kb + 1);
        let mut cost = Cost::default()
            .part("input registers (n, e, λ)", prim::register(6 * w + lam))
            .part("λ clamp (> 1 → 1)", prim::mux(lam) + prim::comparator(lam))
            .part(
                "block normalise: |x_i| (6 × conditional negate)",
                (Cells {
                    xor2: w as f64,
                    ..Cells::default()
                } + prim::half_adder() * w as f64)
                    * 6.0,
            )
            .part(
                "block normalise: OR trees (2, also the zero detect)",
                Cells {
                    or2: 2.0 * 2.0 * w as f64,
                    ..Cells::default()
                },
            )
            .part(
                "block normalise: leading-zero counters (2)",
                prim::leading_zero_counter(w) * 2.0,
            )
            .part(
                "block normalise: shifters (6, W → P)",
                prim::shifter(pe, bits_for(w as u64)) * 6.0,
            )
            .part(
                "stage registers (mantissas, λ, zero flags)",
                prim::register(6 * pe + lam + 2),
            )
            .part("squarers P×P (6)", prim::multiplier(pe, pe) * 6.0)
            .part("square sums (2 × 2 adders)", prim::adder(sb) * 4.0)
            .part(
                "stage registers (S_n, S_e, mantissas, λ, zero flags)",
                prim::register(2 * sb + 6 * pe + lam + 2),
            )
            .part(
                "leading-zero counters (2)",
                prim::leading_zero_counter(sb) * 2.0,
            )
            .part(
                "normalising shifters (2, m to u2.N and the address)",
                prim::shifter(sb, bits_for(sb as u64 - 1)) * 2.0,
            )
            .part(
                "stage-2 registers (address, m_N, carry)",
                prim::register(2 * (a + if c.newton { n + 2 } else { 0 }) + carry),
            )
            .part(
                "ROM output registers (y0, m_N, carry)",
                prim::register(2 * (r + if c.newton { n + 2 } else { 0 }) + carry),
            );
        if c.newton {
            cost = cost
                .part("Newton: y0² (2 squarers R×R)", prim::multiplier(r, r) * 2.0)
                .part("Newton: y0² rounders (2)", prim::adder(n + 1) * 2.0)
                .part(
                    "Newton: registers (q, y0, m_N, carry)",
                    prim::register(2 * ((n + 1) + r + (n + 2)) + carry),
                )
                .part(
                    "Newton: m_N·q multipliers (2)",
                    prim::multiplier(n + 2, n + 1) * 2.0,
                )
                .part(
                    "Newton: 3 − m·q subtract + round (2)",
                    (prim::subtractor(n + 3) + prim::mux(n + 2)) * 2.0,
                )
                .part(
                    "Newton: registers (d, y0, carry)",
                    prim::register(2 * ((n + 2) + r) + carry),
                )
                .part(
                    "Newton: y0·d multipliers (2)",
                    prim::multiplier(r, n + 2) * 2.0,
                )
                .part("Newton: rounders (2)", prim::adder(n + 1) * 2.0)
                .part(
                    "Newton: registers (y1, carry)",
                    prim::register(2 * (n + 1) + carry),
                );
        }
        let pw = pe + fy + 1; // N_i·y product width
        cost.part(
            "normalise: N_i·y multipliers (6)",
            prim::multiplier(pe, fy + 1) * 6.0,
        )
        .part("normalise: shifters by k (6)", prim::shifter(pw, kb) * 6.0)
        .part("normalise: rounders (6)", prim::adder(b + 2) * 6.0)
        .part(
            "zero-vector muxes (n̂ := v̂, v̂ := n̂)",
            prim::mux(3 * (b + 2)) * 2.0,
        )
        .part(
            "stage registers (n̂, v̂, λ, flags)",
            prim::register(6 * (b + 2) + lam + 2),
        )
        .part(
            "d: multipliers (3, s2.B²)",
            prim::multiplier(b + 2, b + 2) * 3.0,
        )
        .part(
            "d: adder tree + rounder",
            prim::adder(2 * b + 6) * 2.0 + prim::adder(b + 3),
        )
        .part(
            "stage registers (d, n̂, v̂, λ, flags)",
            prim::register((b + 3) + 6 * (b + 2) + lam + 2),
        )
        .part(
            "r: 2d·n̂ multipliers (3)",
            prim::multiplier(b + 3, b + 2) * 3.0,
        )
        .part(
            "r: subtract v̂ + round (3)",
            (prim::subtractor(b + 5) + prim::adder(b + 3)) * 3.0,
        )
        .part(
            "stage registers (r, λ, flags)",
            prim::register(3 * (b + 3) + lam + 3),
        )
        .part("t: r·λ multipliers (3)", prim::multiplier(b + 3, lam) * 3.0)
        .part(
            "stage registers (t, flags)",
            prim::register(3 * (b + l + 4) + 3),
        )
        .part(
            "coord: +1 and round (3 adders; the scale is wiring)",
            prim::adder(b + l + 5) * 3.0,
        )
        .part(
            "coord: saturation (overflow detect + clamp mux, 3)",
            (Cells {
                or2: (b + l + 5).saturating_sub(o) as f64,
                ..Cells::default()
            } + prim::mux(o))
                * 3.0,
        )
        .part(
            "output registers (coords, flags)",
            prim::register(3 * o + 3),
        )
        .with_ram_bits(self.rom_bits())
    }

    fn widths(&self) -> Vec<Width> {
        let c = self.cfg;
        vec![
            Width {
                name: "in_bits",
                bits: self.in_bits(),
            },
            Width {
                name: "in_frac_bits",
                bits: c.in_frac_bits,
            },
            Width {
                name: "lambda_bits",
                bits: c.lambda_bits,
            },
            Width {
                name: "rsqrt_addr_bits",
                bits: c.rsqrt_addr_bits,
            },
            Width {
                name: "rsqrt_bits",
                bits: c.rsqrt_bits,
            },
            Width {
                name: "newton_frac_bits",
                bits: if c.newton { c.newton_frac_bits } else { 0 },
            },
            Width {
                name: "norm_bits",
                bits: c.norm_bits,
            },
            Width {
                name: "mant_bits",
                bits: c.mant_bits,
            },
            Width {
                name: "side_log2",
                bits: c.side_log2,
            },
            Width {
                name: "out_bits",
                bits: self.out_bits(),
            },
            Width {
                name: "coord_frac_bits",
                bits: c.coord_frac_bits,
            },
        ]
    }

    fn in_signals(&self, i: &ReflectionVectorIn) -> Vec<Signal> {
        const NAMES: [&str; 6] = ["nx", "ny", "nz", "ex", "ey", "ez"];
        let w = self.in_bits();
        let m = if w >= 64 { u64::MAX } else { (1u64 << w) - 1 };
        let l = self.cfg.lambda_bits + 1;
        let mut v: Vec<Signal> = (0..6)
            .map(|k| {
                let x = if k < 3 { i.n[k] } else { i.e[k - 3] };
                Signal::new(NAMES[k], w, x as u64 & m)
            })
            .collect();
        v.push(Signal::new(
            "lambda",
            l,
            i.lambda as u64 & ((1u64 << l) - 1),
        ));
        v
    }

    fn out_signals(&self, o: &ReflectionVectorOut) -> Vec<Signal> {
        const NAMES: [&str; 3] = ["s", "t", "r"];
        let w = self.out_bits();
        let m = (1u64 << w) - 1;
        let mut v: Vec<Signal> = (0..3)
            .map(|k| Signal::new(NAMES[k], w, o.coord[k] as i64 as u64 & m))
            .collect();
        v.push(Signal::new("back_facing", 1, o.back_facing as u64));
        v.push(Signal::new("zero_n", 1, o.zero_n as u64));
        v.push(Signal::new("zero_e", 1, o.zero_e as u64));
        v
    }
}
