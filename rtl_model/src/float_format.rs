//! A runtime-configurable binary floating-point format and its arithmetic on raw
//! integer fields (no f64 inside any operation; f64 only at the host edge:
//! [`FloatFormat::from_f64`], [`FloatFormat::to_f64`]).
//!
//! Encoding (IEEE-754 layout, sign bit implied): a word of 1 + E + M bits,
//! `sign | biased exponent (E bits) | mantissa (M bits)`, bias = 2^(E−1) − 1.
//! Exponent field 0 is zero or a subnormal; the all-ones exponent field is RESERVED
//! (no ∞/NaN are ever produced, so the largest finite value is the IEEE one,
//! (2 − 2^−M)·2^bias). E = 8, M = 23 is IEEE single (GeForce 256's T&L word) and then
//! add/mul agree bit for bit with Rust's `f32` whenever f32's result is finite (tested).
//!
//! Every operation is computed exactly (wide integers) and rounded once:
//! * rounding: to nearest, ties to even ([`Rounding::NearestEven`], default), or
//!   toward zero ([`Rounding::Truncate`]); one rounding's relative error is at most
//!   u = 2^−(M+1) (nearest) or 2^−M (truncate) for a normal result;
//! * subnormals: flushed to zero ([`Subnormals::Flush`], default — the cheaper
//!   hardware and what the era's T&L engines did: subnormal operands read as zero,
//!   a result below the smallest normal after rounding becomes ±0) or kept
//!   ([`Subnormals::Keep`], gradual underflow as IEEE);
//! * a result beyond the largest finite value saturates to ±max finite (counted in
//!   `saturations`); a non-zero result that becomes zero (flushed or rounded) is
//!   counted in `underflows`.
//!
//! Operations: [`FloatFormat::add`], [`FloatFormat::sub`], [`FloatFormat::mul`] (no
//! fused multiply-add: a·b + c rounds twice), compare ([`FloatFormat::lt`],
//! [`FloatFormat::le`]), [`FloatFormat::max0`], [`FloatFormat::rcp`] and
//! [`FloatFormat::rsq`] (exactly rounded, one rounding: the model of a digit-recurrence
//! divide / square-root unit carrying a remainder), and [`FloatFormat::pow`] for the
//! specular and spot exponents, computed as the era's LIT did, log2 → mul → exp2:
//! * log2(x), x = 2^e·y, y ∈ [1, 2): e exact plus K = M + 4 fraction bits of log2(y)
//!   by repeated squaring (y ← y², bit = y ≥ 2, y ← y/2), y held in u1.K and truncated
//!   once per step. The computed value never exceeds log2(x) and falls short by at most
//!   ε_L = 2^−K + 2^−K/(ln 2·(1 − 2^−K)) (the bits beyond K, plus Σ 2^−k·|log2(1 − τ_k)|
//!   with τ_k ≤ 2^−K the truncation of step k). Rounded to the format (u).
//! * t = s·log2(x) in the format (u).
//! * 2^t: t = n + f, n = ⌊t⌋, f ∈ [0, 1) truncated to K bits (relative error of 2^f
//!   within [−ln 2·2^−K, 0]); 2^f = Π 2^(2^−k) over the set bits of f, from a ROM of
//!   K constants in u1.K (entry error ≤ 2^−(K+1)(1 + 2^−14), built by integer square
//!   roots from 2), each product truncated to u1.K (relative error ≤ 2^−K). Then 2^n
//!   scales the exponent and the result is rounded to the format (u).
//!   So 2^t' = 2^t·(1 + η), |η| ≤ η_exp = (1 + 2^−(K+1)(1 + 2^−14))^K·(1 + 2^−K)^K·
//!   2^(2^−K) − 1 (see [`FloatFormat::exp2_rel_error`]).
//!   pow(x, 0) = 1 (also for x = 0, as C's pow); pow(x ≤ 0, s > 0) = 0.
//!
//! Widths: M ≤ 39 so that the exactly rounded RSQ fits 128-bit integers
//! (⌊√(2^(2P)/m)⌋ with 2P ≥ 3M + 8 bits); E ≤ 11 so every value is an f64.

use crate::counters::Counters;
use crate::error::{check_finite, check_range, ConfigError};
use serde::{Deserialize, Serialize};

/// How a result is brought to M mantissa bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Rounding {
    /// Round to nearest, ties to even (IEEE default).
    #[default]
    NearestEven,
    /// Round toward zero (drop the bits): cheaper, biased, u = 2^−M.
    Truncate,
}

/// Results (and operands) below the smallest normal magnitude.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Subnormals {
    /// Flush to ±0 (operands and results), counted in `underflows`.
    #[default]
    Flush,
    /// Gradual underflow (IEEE subnormals).
    Keep,
}

/// A binary float format: E exponent bits, M mantissa bits, sign implied.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct FloatFormat {
    /// Exponent field width E, 2 ..= 11.
    pub exp_bits: u32,
    /// Stored mantissa width M (the leading 1 is implied), 1 ..= 39.
    pub mant_bits: u32,
    /// How a result is rounded to M mantissa bits (default: nearest-even).
    pub rounding: Rounding,
    /// Whether values below the smallest normal are flushed to zero (the default) or kept
    /// as subnormals.
    pub subnormals: Subnormals,
}

/// One value: the raw word `sign | exponent | mantissa` (low 1 + E + M bits).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct Fp(pub u64);

/// An unpacked finite non-zero value: (−1)^neg · sig · 2^lsb, sig normalised to
/// [2^M, 2^(M+1)).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Parts {
    neg: bool,
    lsb: i32,
    sig: u64,
}

/// Largest exponent the internal pow datapath handles without saturating n.
const POW_N_LIMIT: i128 = 1 << 14;

/// The exp2 ROM for K fraction bits (built once per K): 2^(2^−k), k = 1 ..= K, in
/// u1.K, by integer square roots from 2 at K + 16 bits (each ⌊√⌋ errs < 1 LSB there,
/// halved by the next root), rounded to K bits.
fn exp2_rom_of(k: u32) -> &'static [u64] {
    static ROMS: std::sync::OnceLock<Vec<Vec<u64>>> = std::sync::OnceLock::new();
    let roms = ROMS.get_or_init(|| {
        (0..=43u32)
            .map(|k| {
                let wide = k + 16; // ≤ 59: the square of a u1.wide word fits u128
                let mut c = 2u128 << wide; // 2 in u1.wide
                (1..=k)
                    .map(|_| {
                        c = (c << wide).isqrt(); // √c in u1.wide
                        ((c + (1 << 15)) >> 16) as u64
                    })
                    .collect()
            })
            .collect()
    });
    &roms[k as usize]
}

impl FloatFormat {
    /// IEEE single as on GeForce 256's T&L (8/23), nearest-even, subnormals flushed.
    pub const IEEE_SINGLE: FloatFormat = FloatFormat {
        exp_bits: 8,
        mant_bits: 23,
        rounding: Rounding::NearestEven,
        subnormals: Subnormals::Flush,
    };

    /// Validate E and M (errors name `<prefix>.exp_bits` / `<prefix>.mant_bits`);
    /// nearest-even rounding, subnormals flushed.
    pub fn new(exp_bits: u32, mant_bits: u32) -> Result<Self, ConfigError> {
        let f = FloatFormat {
            exp_bits,
            mant_bits,
            rounding: Rounding::default(),
            subnormals: Subnormals::default(),
        };
        f.validate("float_format")?;
        Ok(f)
    }

    /// The same widths with another rounding mode.
    pub fn with_rounding(self, rounding: Rounding) -> Self {
        FloatFormat { rounding, ..self }
    }

    /// The same widths with subnormals flushed or kept.
    pub fn with_subnormals(self, subnormals: Subnormals) -> Self {
        FloatFormat { subnormals, ..self }
    }

    /// Check the widths; errors name `<prefix>.exp_bits` / `<prefix>.mant_bits`.
    pub fn validate(&self, prefix: &str) -> Result<(), ConfigError> {
        check_range(&format!("{prefix}.exp_bits"), self.exp_bits as u64, 2, 11)?;
        check_range(&format!("{prefix}.mant_bits"), self.mant_bits as u64, 1, 39)
    }

    /// Word width 1 + E + M.
    pub fn width(&self) -> u32 {
        1 + self.exp_bits + self.mant_bits
    }

    /// Exponent bias, 2^(E−1) − 1 (127 for E = 8).
    pub fn bias(&self) -> i32 {
        (1 << (self.exp_bits - 1)) - 1
    }

    /// Unbiased exponent of the smallest normal, 1 − bias.
    pub fn emin(&self) -> i32 {
        1 - self.bias()
    }

    /// Unbiased exponent of the largest finite value (the all-ones field is reserved).
    pub fn emax(&self) -> i32 {
        self.bias()
    }

    /// Unit roundoff: the largest relative error of one rounding to a normal value,
    /// 2^−(M+1) (nearest) or 2^−M (truncate), as an exponent.
    pub fn unit_roundoff_log2(&self) -> i32 {
        match self.rounding {
            Rounding::NearestEven => -(self.mant_bits as i32) - 1,
            Rounding::Truncate => -(self.mant_bits as i32),
        }
    }

    /// Working fraction bits K of pow's log2 and exp2 (M + 4).
    pub fn pow_frac_bits(&self) -> u32 {
        self.mant_bits + 4
    }

    fn sign_bit(&self) -> u64 {
        1u64 << (self.exp_bits + self.mant_bits)
    }

    fn mant_mask(&self) -> u64 {
        (1u64 << self.mant_bits) - 1
    }

    /// The word for +0 (all bits clear).
    pub fn zero(&self) -> Fp {
        Fp(0)
    }

    /// The word for 1.0 (biased exponent = bias, mantissa 0).
    pub fn one(&self) -> Fp {
        Fp((self.bias() as u64) << self.mant_bits)
    }

    /// ±(2 − 2^−M)·2^emax.
    pub fn max_finite(&self, neg: bool) -> Fp {
        let e = ((1u64 << self.exp_bits) - 2) << self.mant_bits;
        Fp(e | self.mant_mask() | if neg { self.sign_bit() } else { 0 })
    }

    /// True when the sign bit of `x` is set (including −0).
    pub fn is_neg(&self, x: Fp) -> bool {
        x.0 & self.sign_bit() != 0
    }

    /// `x` with its sign bit flipped (exact; −0 for +0).
    pub fn neg(&self, x: Fp) -> Fp {
        Fp(x.0 ^ self.sign_bit())
    }

    /// `x` with its sign bit cleared (exact).
    pub fn abs(&self, x: Fp) -> Fp {
        Fp(x.0 & !self.sign_bit())
    }

    /// True for ±0 (and for subnormals when they are flushed).
    pub fn is_zero(&self, x: Fp) -> bool {
        self.unpack(x).is_none()
    }

    /// Fields: (sign, biased exponent, mantissa).
    pub fn fields(&self, x: Fp) -> (bool, u32, u64) {
        let e = ((x.0 >> self.mant_bits) & ((1u64 << self.exp_bits) - 1)) as u32;
        (self.is_neg(x), e, x.0 & self.mant_mask())
    }

    /// Pack fields (masked to their widths).
    pub fn pack(&self, neg: bool, biased_exp: u32, mant: u64) -> Fp {
        let e = (biased_exp as u64 & ((1u64 << self.exp_bits) - 1)) << self.mant_bits;
        Fp(e | (mant & self.mant_mask()) | if neg { self.sign_bit() } else { 0 })
    }

    /// None for zero (and flushed subnormals). The reserved all-ones exponent (never
    /// produced here) reads as the largest finite exponent.
    fn unpack(&self, x: Fp) -> Option<Parts> {
        let (neg, e, mant) = self.fields(x);
        let m = self.mant_bits;
        if e == 0 {
            if mant == 0 || self.subnormals == Subnormals::Flush {
                return None;
            }
            // Subnormal: mant·2^(emin − M), normalised (exact).
            let shift = mant.leading_zeros() - (63 - m);
            return Some(Parts {
                neg,
                lsb: self.emin() - m as i32 - shift as i32,
                sig: mant << shift,
            });
        }
        let e = e.min((1 << self.exp_bits) - 2) as i32;
        Some(Parts {
            neg,
            lsb: e - self.bias() - m as i32,
            sig: (1u64 << m) | mant,
        })
    }

    /// Round (−1)^neg · (sig + frac)·2^lsb, 0 ≤ frac < 1 and frac > 0 iff `sticky`, to
    /// the format: the one rounding of every operation. Counts saturations/underflows.
    fn round_pack(&self, neg: bool, lsb: i32, sig: u128, sticky: bool, ctr: &mut Counters) -> Fp {
        let sign = if neg { self.sign_bit() } else { 0 };
        if sig == 0 {
            if sticky {
                ctr.underflows += 1;
            }
            return Fp(sign);
        }
        let m = self.mant_bits as i32;
        let top = 127 - sig.leading_zeros() as i32; // value in [2^(top+lsb), 2^(top+lsb+1))
        let mut e = top + lsb;
        // The exponent of the result's LSB: M below the leading one, or the subnormal
        // grid's 2^(emin − M) when kept.
        let keep_sub = self.subnormals == Subnormals::Keep;
        let target = if keep_sub && e < self.emin() {
            self.emin() - m
        } else {
            e - m
        };
        let shift = target - lsb; // > 0: drop bits
        let (mut q, inexact) = if shift <= 0 {
            (sig << (-shift) as u32, sticky)
        } else if shift >= 128 {
            (0u128, true)
        } else {
            let q = sig >> shift as u32;
            let rest = sig & ((1u128 << shift as u32) - 1);
            let half = 1u128 << (shift - 1) as u32;
            let up = match self.rounding {
                Rounding::Truncate => false,
                Rounding::NearestEven => rest > half || (rest == half && (sticky || q & 1 == 1)),
            };
            (q + up as u128, rest != 0 || sticky)
        };
        if q == 0 {
            ctr.underflows += u64::from(inexact);
            return Fp(sign);
        }
        // Carry out of the rounding: renormalise.
        if q >> (m + 1) != 0 {
            q >>= 1;
            e += 1;
        } else if keep_sub && e < self.emin() {
            // Subnormal grid: the exponent is emin's, q < 2^M unless it rounded up.
            e = if q >> m != 0 {
                self.emin()
            } else {
                self.emin() - 1
            };
        }
        if e > self.emax() {
            ctr.saturations += 1;
            return self.max_finite(neg);
        }
        if e < self.emin() {
            if !keep_sub {
                ctr.underflows += 1;
                return Fp(sign);
            }
            return Fp(sign | q as u64); // subnormal: exponent field 0
        }
        let biased = (e + self.bias()) as u64;
        Fp(sign | biased << self.mant_bits | (q as u64 & self.mant_mask()))
    }

    /// Host edge: the nearest format value (this format's rounding); beyond the range
    /// saturates (counted). NaN/±∞ is an error naming `field`.
    pub fn from_f64(&self, field: &str, x: f64, ctr: &mut Counters) -> Result<Fp, ConfigError> {
        let x = check_finite(field, x)?;
        let bits = x.to_bits();
        let neg = bits >> 63 != 0;
        let e = ((bits >> 52) & 0x7ff) as i32;
        let frac = bits & ((1u64 << 52) - 1);
        if e == 0 && frac == 0 {
            return Ok(Fp(if neg { self.sign_bit() } else { 0 }));
        }
        let (sig, lsb) = if e == 0 {
            (frac, -1074)
        } else {
            (frac | 1 << 52, e - 1075)
        };
        Ok(self.round_pack(neg, lsb, sig as u128, false, ctr))
    }

    /// Host edge: the exact f64 value of a format word.
    pub fn to_f64(&self, x: Fp) -> f64 {
        match self.unpack(x) {
            None => {
                if self.is_neg(x) {
                    -0.0
                } else {
                    0.0
                }
            }
            Some(p) => {
                let v = p.sig as f64 * (p.lsb as f64).exp2();
                if p.neg {
                    -v
                } else {
                    v
                }
            }
        }
    }

    /// a + b, rounded once.
    pub fn add(&self, a: Fp, b: Fp, ctr: &mut Counters) -> Fp {
        let (pa, pb) = match (self.unpack(a), self.unpack(b)) {
            (None, None) => {
                // ±0 + ±0: −0 only if both are −0.
                return Fp(if self.is_neg(a) && self.is_neg(b) {
                    self.sign_bit()
                } else {
                    0
                });
            }
            (None, Some(_)) => return self.canonical(b),
            (Some(_), None) => return self.canonical(a),
            (Some(x), Some(y)) => (x, y),
        };
        // Order by magnitude: |big| ≥ |small| (same sig width, so (lsb, sig) orders).
        let (big, small) = if (pa.lsb, pa.sig) >= (pb.lsb, pb.sig) {
            (pa, pb)
        } else {
            (pb, pa)
        };
        let m = self.mant_bits;
        // Big operand at bits 125 − M ..= 125 of a u128; the small one aligned below it,
        // the bits shifted out kept as a sticky bit. ≥ 73 bits below the big operand's
        // LSB keep the rounding exact after any cancellation.
        let s0 = 125 - m;
        let a_w = (big.sig as u128) << s0; // u(M+1) << s0 → < 2^126
        let d = (big.lsb - small.lsb) as u32;
        let b_full = (small.sig as u128) << s0;
        let (b_w, sticky) = if d >= 128 {
            (0u128, true)
        } else {
            (b_full >> d, b_full & ((1u128 << d) - 1) != 0)
        };
        let lsb = big.lsb - s0 as i32;
        if big.neg == small.neg {
            self.round_pack(big.neg, lsb, a_w + b_w, sticky, ctr) // < 2^127
        } else {
            // a − (b + frac), frac ∈ (0, 1) when sticky: (a − b − 1) + (1 − frac).
            let diff = a_w - b_w - u128::from(sticky);
            if diff == 0 && !sticky {
                return Fp(0); // exact cancellation: +0
            }
            self.round_pack(big.neg, lsb, diff, sticky, ctr)
        }
    }

    /// A non-zero value as it reads (subnormals flushed when they are).
    fn canonical(&self, x: Fp) -> Fp {
        match self.unpack(x) {
            None => Fp(x.0 & self.sign_bit()),
            Some(_) => x,
        }
    }

    /// a − b, rounded once.
    pub fn sub(&self, a: Fp, b: Fp, ctr: &mut Counters) -> Fp {
        self.add(a, self.neg(b), ctr)
    }

    /// a · b, rounded once.
    pub fn mul(&self, a: Fp, b: Fp, ctr: &mut Counters) -> Fp {
        let neg = self.is_neg(a) != self.is_neg(b);
        match (self.unpack(a), self.unpack(b)) {
            (Some(x), Some(y)) => {
                // u(M+1) × u(M+1) → u(2M+2) ≤ 80 bits.
                let p = x.sig as u128 * y.sig as u128;
                self.round_pack(neg, x.lsb + y.lsb, p, false, ctr)
            }
            _ => Fp(if neg { self.sign_bit() } else { 0 }),
        }
    }

    /// Signed comparison key: orders format words as their values (±0 equal).
    fn key(&self, x: Fp) -> i128 {
        match self.unpack(x) {
            None => 0,
            Some(_) => {
                let mag = (x.0 & !self.sign_bit()) as i128;
                if self.is_neg(x) {
                    -mag
                } else {
                    mag
                }
            }
        }
    }

    /// a < b (a comparator on sign-magnitude words).
    pub fn lt(&self, a: Fp, b: Fp) -> bool {
        self.key(a) < self.key(b)
    }

    /// a ≤ b.
    pub fn le(&self, a: Fp, b: Fp) -> bool {
        self.key(a) <= self.key(b)
    }

    /// max(x, 0): a sign test and a mux (−0 and negatives → +0).
    pub fn max0(&self, x: Fp) -> Fp {
        if self.key(x) > 0 {
            x
        } else {
            Fp(0)
        }
    }

    /// min(max(x, 0), 1).
    pub fn clamp01(&self, x: Fp) -> Fp {
        let one = self.one();
        if self.key(x) > self.key(one) {
            one
        } else {
            self.max0(x)
        }
    }

    /// 1/x exactly rounded. x = ±0 saturates to ±max finite (counted).
    pub fn rcp(&self, x: Fp, ctr: &mut Counters) -> Fp {
        let neg = self.is_neg(x);
        let Some(p) = self.unpack(x) else {
            ctr.saturations += 1;
            return self.max_finite(neg);
        };
        let m = self.mant_bits;
        // ⌊2^K / sig⌋ with K = 2M + 4: ≥ M + 3 quotient bits, the remainder → sticky.
        let k = 2 * m + 4;
        let num = 1u128 << k; // ≤ 2^82
        let q = num / p.sig as u128;
        let sticky = !num.is_multiple_of(p.sig as u128);
        self.round_pack(neg, -(k as i32) - p.lsb, q, sticky, ctr)
    }

    /// 1/√|x| exactly rounded (the sign is ignored, as the vertex engines' RSQ).
    /// x = 0 saturates to +max finite (counted).
    pub fn rsq(&self, x: Fp, ctr: &mut Counters) -> Fp {
        let Some(p) = self.unpack(x) else {
            ctr.saturations += 1;
            return self.max_finite(false);
        };
        let m = self.mant_bits;
        // |x| = sig·2^lsb with lsb made even: 1/√|x| = 2^(−lsb/2) / √sig.
        let (sig, lsb) = if p.lsb % 2 != 0 {
            ((p.sig as u128) << 1, p.lsb - 1) // u(M+2)
        } else {
            (p.sig as u128, p.lsb)
        };
        // ⌊2^P/√sig⌋ = ⌊√⌊2^(2P)/sig⌋⌋, 2P = 3M + 8 (even, ≤ 125): ≥ M + 3 result bits.
        let two_p = 3 * m + 8 + (m % 2);
        let num = 1u128 << two_p;
        let quo = num / sig;
        let r = quo.isqrt();
        // Exact iff r² = 2^(2P)/sig exactly.
        let sticky = !(num.is_multiple_of(sig) && r * r == quo);
        self.round_pack(false, -(two_p as i32 / 2) - lsb / 2, r, sticky, ctr)
    }

    /// The pow ROM: 2^(2^−k) in u1.K for k = 1 ..= K (index k − 1), by K integer
    /// square roots from 2 at K + 16 bits, rounded to K (entry error ≤ 2^−(K+1)(1 + 2^−14)).
    pub fn exp2_rom(&self) -> Vec<u64> {
        exp2_rom_of(self.pow_frac_bits()).to_vec()
    }

    /// ROM bits of the pow unit: K entries of K + 1 bits.
    pub fn exp2_rom_bits(&self) -> u64 {
        let k = self.pow_frac_bits() as u64;
        k * (k + 1)
    }

    /// Bound on |log2 computed − log2 x| (the computed value is never above), ε_L.
    pub fn log2_abs_error(&self) -> f64 {
        let k = -(self.pow_frac_bits() as f64);
        k.exp2() + k.exp2() / (std::f64::consts::LN_2 * (1.0 - k.exp2()))
    }

    /// Bound η_exp on the relative error of exp2's fixed-point product (before the
    /// final rounding to the format).
    pub fn exp2_rel_error(&self) -> f64 {
        let k = self.pow_frac_bits() as i32;
        let e = (-(k as f64)).exp2();
        let rom = (1.0 + 0.5 * e * (1.0 + 2f64.powi(-14))).powi(k);
        let trunc = (1.0 + e).powi(k);
        rom * trunc * e.exp2() - 1.0
    }

    /// log2(x) for x > 0 in fixed point: (e·2^K + F) with F the K fraction bits of
    /// log2(y), x = 2^e·y; returns (value, K). Truncated: never above log2 x.
    fn log2_fixed(&self, p: Parts) -> (i128, u32) {
        let m = self.mant_bits;
        let k = self.pow_frac_bits();
        let e = p.lsb as i128 + m as i128; // x = 2^e · sig/2^M
        let mut y = (p.sig as u128) << (k - m); // u1.K, in [2^K, 2^(K+1))
        let mut f: i128 = 0;
        for _ in 0..k {
            let z = y * y; // u2.2K: < 2^(2K+2) ≤ 2^88
            f <<= 1;
            if z >> (2 * k + 1) != 0 {
                f |= 1;
                y = z >> (k + 1); // y²/2, truncated to u1.K
            } else {
                y = z >> k; // y², truncated to u1.K
            }
        }
        ((e << k) + f, k)
    }

    /// x^s by log2 → mul → exp2 (see the module docs). pow(x, 0) = 1; pow(x ≤ 0, s) = 0.
    pub fn pow(&self, x: Fp, s: Fp, ctr: &mut Counters) -> Fp {
        if self.is_zero(s) {
            return self.one();
        }
        if self.key(x) <= 0 {
            return Fp(0);
        }
        let Some(px) = self.unpack(x) else {
            return Fp(0);
        };
        let (l_fix, k) = self.log2_fixed(px);
        let l = self.round_pack(l_fix < 0, -(k as i32), l_fix.unsigned_abs(), false, ctr);
        let t = self.mul(s, l, ctr);
        self.exp2(t, ctr)
    }

    /// 2^t (see the module docs). Counts one ROM read per set fraction bit.
    pub fn exp2(&self, t: Fp, ctr: &mut Counters) -> Fp {
        let Some(pt) = self.unpack(t) else {
            return self.one();
        };
        let k = self.pow_frac_bits();
        // t·2^K floored (toward −∞): t = sig·2^lsb.
        let sh = pt.lsb + k as i32;
        let limit = POW_N_LIMIT << k;
        let mag: i128 = if sh >= 0 {
            if sh >= 40 {
                limit
            } else {
                ((pt.sig as i128) << sh).min(limit)
            }
        } else if -sh >= 100 {
            0
        } else {
            pt.sig as i128 >> (-sh) as u32
        };
        let inexact =
            sh < 0 && (-sh >= 100 || (pt.sig as i128) & ((1i128 << (-sh) as u32) - 1) != 0);
        let t_fix: i128 = if pt.neg {
            -(mag + i128::from(inexact)) // floor of a negative value
        } else {
            mag
        };
        let n = t_fix >> k; // ⌊t⌋
        let f = (t_fix & ((1i128 << k) - 1)) as u64; // K fraction bits
        if n > self.emax() as i128 + 1 {
            ctr.saturations += 1;
            return self.max_finite(false);
        }
        if n < (self.emin() - self.mant_bits as i32 - 2) as i128 {
            ctr.underflows += 1;
            return Fp(0);
        }
        let rom = exp2_rom_of(k);
        let mut prod: u128 = 1u128 << k; // 1.0 in u1.K
        for bit in 1..=k {
            if f >> (k - bit) & 1 == 1 {
                ctr.table_reads += 1;
                // u1.K × u1.K → u2.2K, truncated to u1.K (the product stays < 2).
                prod = (prod * rom[(bit - 1) as usize] as u128) >> k;
            }
        }
        self.round_pack(false, n as i32 - k as i32, prod, false, ctr)
    }

    /// x clamped to [0, 1] as an n-bit unorm, round(x·(2^n − 1)) to nearest (ties up),
    /// exactly. Counts a clamp in `saturations`.
    pub fn to_unorm(&self, x: Fp, bits: u32, ctr: &mut Counters) -> u32 {
        let maxc = (1u64 << bits) - 1;
        let Some(p) = self.unpack(x) else {
            return 0;
        };
        if p.neg {
            ctr.saturations += 1;
            return 0;
        }
        if self.key(x) >= self.key(self.one()) {
            if self.key(x) > self.key(self.one()) {
                ctr.saturations += 1;
            }
            return maxc as u32;
        }
        // sig·2^lsb·(2^n − 1) + ½, floored: u(M+1) × u(n) → u(M+n+1), lsb < 0 here.
        let prod = p.sig as u128 * maxc as u128;
        let sh = -p.lsb;
        if sh >= 120 {
            return 0;
        }
        let code = (prod + (1u128 << (sh - 1))) >> sh;
        if code == 0 {
            ctr.underflows += 1;
        }
        code as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c() -> Counters {
        Counters::default()
    }

    #[test]
    fn one_and_max_finite() {
        let f = FloatFormat::new(8, 23).unwrap();
        assert_eq!(f.to_f64(f.one()), 1.0);
        assert_eq!(f.to_f64(f.max_finite(false)), f32::MAX as f64);
        let h = FloatFormat::new(5, 10).unwrap();
        assert_eq!(h.to_f64(h.max_finite(true)), -65504.0);
    }

    #[test]
    fn rom_matches_f64() {
        let f = FloatFormat::new(8, 23).unwrap();
        let k = f.pow_frac_bits() as i32;
        for (i, &w) in f.exp2_rom().iter().enumerate() {
            let want = (2f64.powf(2f64.powi(-(i as i32) - 1)) * 2f64.powi(k)).round();
            assert!((w as f64 - want).abs() <= 1.0, "{i}: {w} vs {want}");
        }
    }

    #[test]
    fn pow_is_close() {
        let f = FloatFormat::new(8, 23).unwrap();
        let mut ctr = c();
        for &(x, s) in &[
            (0.5, 2.0),
            (0.9, 128.0),
            (0.999, 10000.0),
            (0.3, 0.5),
            (1.0, 7.0),
        ] {
            let xf = f.from_f64("x", x, &mut ctr).unwrap();
            let sf = f.from_f64("s", s, &mut ctr).unwrap();
            let got = f.to_f64(f.pow(xf, sf, &mut ctr));
            let (xv, sv) = (f.to_f64(xf), f.to_f64(sf));
            let want = xv.powf(sv);
            // Derived: t = s·log2 x off by s·ε_L + 3u·|t| (log rounded, s·L rounded),
            // then exp2's η and the final rounding u.
            let u = 2f64.powi(f.unit_roundoff_log2());
            let dt = sv * f.log2_abs_error() + 3.5 * u * (sv * xv.log2()).abs();
            let rel = (dt * std::f64::consts::LN_2).exp_m1() + f.exp2_rel_error() + 1.01 * u;
            assert!((got - want).abs() <= rel * want, "{x}^{s}: {got} vs {want}");
        }
    }
}
