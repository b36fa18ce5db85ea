//! gaussian_noise — the N(0, 1) source for the flare lines (M. Matsuda and T. Ikedo,
//! "A Realtime Renderer for Glare Effect Based upon Empirical Approach", eq. (6):
//! length = Gauss(num)·len, angle = Gauss(num)·ang + R(N)).
//!
//! Uniform source: two combined Tausworthe generators **taus88** (L'Ecuyer 1996: three
//! LFSRs, shifts/masks/XORs only, period ≈ 2⁸⁸), A and B, seeded differently; their
//! 3 × 32 state bits each are held in a `bitvec` [`BitArray`]. Every clock each
//! generator steps once and gives one 32-bit word; the top B = `uniform_bits` bits
//! are the uniform codes k1 (from A) and k2 (from B), k ∈ [0, 2ᴮ).
//!
//! **Box–Muller** (default; II = 1, **two normals per clock**, x and y):
//! u1 = (k1 + ½)/2ᴮ ∈ (0, 1) (never 0, so −ln u1 is finite: at most (B+1)·ln 2),
//! u2 = k2/2ᴮ, r = √(−2 ln u1), (x, y) = r·(cos 2πu2, sin 2πu2). Widths
//! (T = `table_log2`, E = `table_bits`, D = E interpolation-fraction bits,
//! f = `out_frac_bits`, O = `out_int_bits`):
//! 1. U1 = 2·k1 + 1, u(B+1), odd. Leading-zero count: U1 = 2ᵖ·m, p ∈ [0, B], m ∈ [1, 2)
//!    exact. −ln u1 = e·ln 2 − ln m with e = B + 1 − p ∈ [1, B+1] (u6).
//! 2. ln m: the mantissa fraction aligned to T + D bits (exact when p ≤ T + D, else
//!    truncated); its top T bits index a ROM of 2ᵀ + 1 entries round(ln(1 + i/2ᵀ)·2ᴱ)
//!    (u0.E); linear interpolation with the low D bits: a + round((b − a)·t / 2ᴰ)
//!    (s(E+2) × u(D) → s(E+D+2)), result L in u0.E.
//! 3. Y = round((e·LN2 − L·2⁸) / 2⁸), LN2 = round(ln 2·2^(E+8)) (u6 × u(E+8) →
//!    u(E+14)); Y = −ln u1 in u5.E, clamped at ≥ 0. w = 2y = Y·2^−(E−1) (u6.(E−1)).
//! 4. √w: Y = 0 → r = 0 (an underflow, counted). Else normalise by an even shift,
//!    w = m′·4ᵏ, m′ ∈ [1, 4), k ∈ [−⌈E/2⌉, 2]; m′ aligned to (T − 2) + D fraction bits
//!    (truncated); its integer part and top T − 2 fraction bits index a ROM of
//!    ¾·2ᵀ + 1 entries round(√(i/2^(T−2))·2ᴱ), i = 2^(T−2) ..= 2ᵀ (u2.E), interpolated
//!    as above: S ≈ √m′ (u2.E), r = S·2ᵏ.
//! 5. cos/sin 2πu2: the top 2 bits of k2 are the quadrant; the B − 2 bits below (the
//!    phase φ in the quadrant) are aligned to T + D bits (truncated), P, and its
//!    complement 2^(T+D) − P. A quarter-wave ROM of 2ᵀ + 1 entries
//!    round(sin(π/2·i/2ᵀ)·2ᴱ) (u1.E), read at P (sin φ) and at the complement
//!    (cos φ), both interpolated; the quadrant swaps and negates them.
//! 6. x = ±round(S·C·2^(k+f−2E)) (u2.E × u1.E → u3.2E, shifted and rounded half up on
//!    the magnitude), saturated symmetrically to ±(2^(O+f) − 1) in s(O+1).f, each clamp
//!    counted in `saturations`. Output words: x, y in s(O+1).f (default s3.12 in the
//!    sign + magnitude notation, a 16-bit word).
//!
//! **Central limit** (the alternative the datasheet compares against): the sum of 12
//! uniforms (k_j + ½)/2ᴮ minus 6 (Irwin–Hall), from the same two generators: six
//! clocks per sample (II = 6, **one normal per 6 clocks**): code =
//! round((Σk_j + 6 − 6·2ᴮ)·2^(f−B)), exact but for the last rounding (½ LSB). Its
//! tails end at ±6 and are thin at 4σ.
//!
//! Timing: Box–Muller latency 9 (generator register, lzc/normalise, ln ROM,
//! ln interpolate, e·ln 2 − L, √ normalise, √ ROM, √ interpolate, r·cos/r·sin and
//! round), II 1. Central limit: latency 7 (six accumulate clocks + round), II 6.

use crate::cost::{prim, Cells, Cost};
use crate::counters::Counters;
use crate::error::{check_range, ConfigError};
use crate::fixed_point::{round_shift, Quant};
use crate::packed_rom::PackedRom;
use crate::unit::{Signal, Timing, Unit, Width};
use bitvec::prelude::*;
use serde::{Deserialize, Serialize};

/// Which Gaussian datapath.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GaussMode {
    /// Box–Muller with ln / √ / sin ROMs: two normals per clock.
    BoxMuller,
    /// Sum of 12 uniforms minus 6 (Irwin–Hall): one sample per 6 clocks.
    CentralLimit,
}

/// The plain config (serde-friendly); [`GaussianNoiseConfig::build`] validates it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct GaussianNoiseConfig {
    /// The datapath: Box–Muller (the default) or the central-limit sum.
    pub mode: GaussMode,
    /// Bits B of each uniform (top bits of the taus88 word), 8 ..= 32.
    pub uniform_bits: u32,
    /// log2 of the ROM segment count T (ln, sin: 2ᵀ + 1 entries), 4 ..= 12.
    pub table_log2: u32,
    /// ROM entry fraction bits E (also the interpolation fraction D), 8 ..= 24.
    pub table_bits: u32,
    /// Output fraction bits f, 4 ..= 16.
    pub out_frac_bits: u32,
    /// Output integer (magnitude) bits O, excluding the sign, 1 ..= 4.
    pub out_int_bits: u32,
}

impl Default for GaussianNoiseConfig {
    fn default() -> Self {
        GaussianNoiseConfig::geforce()
    }
}

impl GaussianNoiseConfig {
    /// Defaults: Box–Muller, 32-bit uniforms (|x| ≤ √(2·33·ln 2) = 6.76), 1024-segment
    /// ROMs of 18-bit entries, output s3.12 (16-bit words).
    pub fn geforce() -> Self {
        GaussianNoiseConfig {
            mode: GaussMode::BoxMuller,
            uniform_bits: 32,
            table_log2: 10,
            table_bits: 18,
            out_frac_bits: 12,
            out_int_bits: 3,
        }
    }

    /// Validate and build the unit; the same as [`GaussianNoise::new`], errors name
    /// `gaussian_noise.<field>`.
    pub fn build(&self) -> Result<GaussianNoise, ConfigError> {
        GaussianNoise::new(*self)
    }
}

/// The validated unit: config and its three ROMs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GaussianNoise {
    cfg: GaussianNoiseConfig,
    ln_rom: PackedRom,
    sqrt_rom: PackedRom,
    sin_rom: PackedRom,
    /// round(ln 2 · 2^(E+8)).
    ln2: i64,
}

/// One taus88 state: s1, s2, s3 (96 bits).
pub type Taus88Bits = BitArray<[u32; 3], Lsb0>;

/// Generator state: the two taus88 instances A and B (192 state bits).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GaussState {
    /// Generator A, the source of the uniform codes k1.
    pub a: Taus88Bits,
    /// Generator B, the source of the uniform codes k2.
    pub b: Taus88Bits,
}

/// Output word: raw s(O+1).f codes. Box–Muller gives x and y every clock; the
/// central-limit mode gives x only (`y = None`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct GaussOut {
    /// The first normal sample, a raw s(O+1).f code (O = `out_int_bits`, f =
    /// `out_frac_bits`).
    pub x: i32,
    /// The second normal sample of a Box–Muller step (same format); `None` in the
    /// central-limit mode.
    pub y: Option<i32>,
}

/// taus88 minimum seeds: s1 > 1, s2 > 7, s3 > 15 (else a component LFSR is stuck at 0).
pub const TAUS88_MIN: [u32; 3] = [2, 8, 16];

/// One taus88 step (L'Ecuyer 1996, "Maximally equidistributed combined Tausworthe
/// generators", Fig. 1): returns s1 ^ s2 ^ s3 after stepping. Shifts, masks, XORs.
#[inline]
pub fn taus88_step(s: &mut [u32; 3]) -> u32 {
    let b = ((s[0] << 13) ^ s[0]) >> 19;
    s[0] = ((s[0] & 0xFFFF_FFFE) << 12) ^ b;
    let b = ((s[1] << 2) ^ s[1]) >> 25;
    s[1] = ((s[1] & 0xFFFF_FFF8) << 4) ^ b;
    let b = ((s[2] << 3) ^ s[2]) >> 11;
    s[2] = ((s[2] & 0xFFFF_FFF0) << 17) ^ b;
    s[0] ^ s[1] ^ s[2]
}

fn splitmix64(x: &mut u64) -> u64 {
    *x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *x;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

fn taus_bits(w: [u32; 3]) -> Taus88Bits {
    let mut b = Taus88Bits::ZERO;
    for (i, v) in w.iter().enumerate() {
        b[i * 32..(i + 1) * 32].store_le::<u32>(*v);
    }
    b
}

fn taus_words(b: &Taus88Bits) -> [u32; 3] {
    [
        b[0..32].load_le::<u32>(),
        b[32..64].load_le::<u32>(),
        b[64..96].load_le::<u32>(),
    ]
}

impl GaussState {
    /// Seed both generators from a u64: six words of SplitMix64 (Steele et al. 2014)
    /// from `seed`, A = words 0..3, B = words 3..6; a word below its taus88 minimum
    /// ([`TAUS88_MIN`]: 2, 8, 16) has the minimum added, so every component is valid.
    /// The project default seed is 1.
    pub fn from_seed(seed: u64) -> Self {
        let mut x = seed;
        let mut w = [0u32; 6];
        for (i, v) in w.iter_mut().enumerate() {
            let r = splitmix64(&mut x) as u32;
            let min = TAUS88_MIN[i % 3];
            *v = if r < min { r + min } else { r };
        }
        GaussState {
            a: taus_bits([w[0], w[1], w[2]]),
            b: taus_bits([w[3], w[4], w[5]]),
        }
    }

    /// The state words (A, B).
    pub fn words(&self) -> ([u32; 3], [u32; 3]) {
        (taus_words(&self.a), taus_words(&self.b))
    }

    /// Step both generators once: the raw 32-bit words of A and B (one clock).
    #[inline]
    pub fn next_raw(&mut self) -> (u32, u32) {
        let (mut a, mut b) = self.words();
        let ra = taus88_step(&mut a);
        let rb = taus88_step(&mut b);
        self.a = taus_bits(a);
        self.b = taus_bits(b);
        (ra, rb)
    }
}

/// Bits of the ln-table index alignment etc. never exceed these.
pub const MAX_UNIFORM_BITS: u32 = 32;

impl GaussianNoise {
    /// Validate a config and build the ROMs; errors name `gaussian_noise.<field>`.
    pub fn new(cfg: GaussianNoiseConfig) -> Result<Self, ConfigError> {
        let f = |n: &str| format!("gaussian_noise.{n}");
        check_range(&f("uniform_bits"), cfg.uniform_bits as u64, 8, 32)?;
        check_range(&f("table_log2"), cfg.table_log2 as u64, 4, 12)?;
        check_range(&f("table_bits"), cfg.table_bits as u64, 8, 24)?;
        check_range(&f("out_frac_bits"), cfg.out_frac_bits as u64, 4, 16)?;
        check_range(&f("out_int_bits"), cfg.out_int_bits as u64, 1, 4)?;
        let (t, e) = (cfg.table_log2, cfg.table_bits);
        let n = 1u64 << t;
        let scale = (e as f64).exp2();
        // Table contents are computed once at configuration (host side, f64), then
        // frozen as integers; the kernel only reads them.
        let ln: Vec<u64> = (0..=n)
            .map(|i| ((1.0 + i as f64 / n as f64).ln() * scale).round() as u64)
            .collect();
        let q = n / 4;
        let sq: Vec<u64> = (q..=n)
            .map(|i| ((i as f64 / q as f64).sqrt() * scale).round() as u64)
            .collect();
        let sn: Vec<u64> = (0..=n)
            .map(|i| {
                ((std::f64::consts::FRAC_PI_2 * i as f64 / n as f64).sin() * scale).round() as u64
            })
            .collect();
        let ln2 = (std::f64::consts::LN_2 * ((e + 8) as f64).exp2()).round() as i64;
        Ok(GaussianNoise {
            cfg,
            ln_rom: PackedRom::new(e, &ln),
            sqrt_rom: PackedRom::new(e + 2, &sq),
            sin_rom: PackedRom::new(e + 1, &sn),
            ln2,
        })
    }

    /// Defaults (see [`GaussianNoiseConfig::geforce`]).
    pub fn geforce() -> Self {
        match Self::new(GaussianNoiseConfig::geforce()) {
            Ok(u) => u,
            Err(e) => unreachable!("default config invalid: {e}"),
        }
    }

    /// The config the unit was built from.
    pub fn config(&self) -> GaussianNoiseConfig {
        self.cfg
    }

    /// Which datapath is built: Box–Muller or the central-limit sum.
    pub fn mode(&self) -> GaussMode {
        self.cfg.mode
    }

    /// Output width: sign + O + f bits.
    pub fn out_bits(&self) -> u32 {
        1 + self.cfg.out_int_bits + self.cfg.out_frac_bits
    }

    /// Largest output magnitude code, 2^(O+f) − 1.
    pub fn out_max_code(&self) -> i32 {
        (1i32 << (self.cfg.out_int_bits + self.cfg.out_frac_bits)) - 1
    }

    /// Normals per kernel call (2 for Box–Muller, 1 for central limit).
    pub fn samples_per_call(&self) -> u32 {
        match self.cfg.mode {
            GaussMode::BoxMuller => 2,
            GaussMode::CentralLimit => 1,
        }
    }

    /// Uniform code k = top B bits of a raw taus88 word.
    #[inline]
    pub fn uniform_code(&self, raw: u32) -> u64 {
        (raw >> (32 - self.cfg.uniform_bits)) as u64
    }

    /// ROM contents (ln, √, sin), entry order, for `$readmemh` images:
    /// (name, entry width, words).
    pub fn rom_images(&self) -> Vec<(String, u32, Vec<u64>)> {
        let (t, e) = (self.cfg.table_log2, self.cfg.table_bits);
        vec![
            (
                format!("gaussian_noise.ln_t{t}_e{e}"),
                e,
                self.ln_rom.words(),
            ),
            (
                format!("gaussian_noise.sqrt_t{t}_e{e}"),
                e + 2,
                self.sqrt_rom.words(),
            ),
            (
                format!("gaussian_noise.sin_t{t}_e{e}"),
                e + 1,
                self.sin_rom.words(),
            ),
        ]
    }

    /// ROM bits of the Box–Muller datapath (0 for central limit).
    pub fn rom_bits(&self) -> u64 {
        match self.cfg.mode {
            GaussMode::BoxMuller => {
                self.ln_rom.ram_bits() + self.sqrt_rom.ram_bits() + self.sin_rom.ram_bits()
            }
            GaussMode::CentralLimit => 0,
        }
    }

    /// Linear interpolation between entries i and i + 1 of a ROM: a + round((b − a)·t/2ᴰ).
    /// Two ROM reads (counted).
    #[inline]
    fn interp(&self, rom: &PackedRom, i: usize, t: i64, ctr: &mut Counters) -> i64 {
        let d = self.cfg.table_bits as i32; // D = E
        let a = rom.read(i); // u(≤E+2)
        let b = rom.read(i + 1);
        ctr.table_reads += 2;
        // s(E+3) × u(D) → s(E+D+3), rounded half up back to the entry's LSB.
        a + round_shift(((b - a) * t) as i128, d, Quant::Rnd) as i64
    }

    /// The Box–Muller datapath on one pair of uniform codes (k1, k2 < 2ᴮ; masked).
    /// Returns the raw output codes (x, y) in s(O+1).f.
    pub fn box_muller_codes(&self, k1: u64, k2: u64, ctr: &mut Counters) -> (i32, i32) {
        let bb = self.cfg.uniform_bits;
        let t = self.cfg.table_log2;
        let e = self.cfg.table_bits;
        let d = e; // interpolation fraction bits D
        let mask_b = (1u64 << bb) - 1;
        let (k1, k2) = (k1 & mask_b, k2 & mask_b);
        let dmask = (1i64 << d) - 1;

        // 1. U1 = 2·k1 + 1: u(B+1), never 0.
        let u1 = 2 * k1 + 1;
        let p = 63 - u1.leading_zeros(); // floor(log2 U1) ∈ [0, B]
        let ee = (bb + 1 - p) as i64; // e ∈ [1, B+1]: u6
        let mf = u1 - (1u64 << p); // mantissa fraction, p bits
                                   // 2. Align to T + D bits (≤ 48): exact when p ≤ T + D, else truncated.
        let td = t + d;
        let fr = if p <= td {
            mf << (td - p)
        } else {
            mf >> (p - td)
        };
        let l = self.interp(&self.ln_rom, (fr >> d) as usize, fr as i64 & dmask, ctr); // u0.E
                                                                                       // 3. Y = round((e·LN2 − L·2⁸)/2⁸): u6 × u(E+8) → u(E+14); Y in u5.E, ≥ 0.
        let y8 = ee * self.ln2 - (l << 8);
        let y = (round_shift(y8 as i128, 8, Quant::Rnd) as i64).max(0);

        // 5. Quadrant and phase of k2 (computed beside the ln/√ path in hardware).
        let quad = (k2 >> (bb - 2)) & 3;
        let ph = k2 & ((1u64 << (bb - 2)) - 1); // B − 2 bits
        let pb = bb - 2;
        let pp = if pb <= td {
            ph << (td - pb)
        } else {
            ph >> (pb - td)
        }; // u(T+D)
        let pc = (1u64 << td) - pp; // complement: (0, 2^(T+D)]
        let s_phi = self.interp(&self.sin_rom, (pp >> d) as usize, pp as i64 & dmask, ctr); // u1.E
        let c_phi = self.interp(&self.sin_rom, (pc >> d) as usize, pc as i64 & dmask, ctr);
        let (cos_v, sin_v) = match quad {
            0 => (c_phi, s_phi),
            1 => (-s_phi, c_phi),
            2 => (-c_phi, -s_phi),
            _ => (s_phi, -c_phi),
        };

        if y == 0 {
            // −ln u1 rounded to 0: r = 0.
            ctr.underflows += 1;
            return (0, 0);
        }
        // 4. w = Y·2^−(E−1); top bit of Y at position bl − 1: w ∈ [2^q, 2^(q+1)), q = bl − E.
        let bl = 64 - (y as u64).leading_zeros() as i32;
        let q = bl - e as i32;
        let k = q.div_euclid(2); // w = m′·4ᵏ, m′ ∈ [1, 4)
                                 // M = m′·2^(T−2+D): shift Y (frac E−1) by (T − 2 + D) − (E − 1) − 2k.
        let sh = (t as i32 - 2 + d as i32) - (e as i32 - 1) - 2 * k;
        let m = if sh >= 0 {
            (y as u64) << sh
        } else {
            (y as u64) >> (-sh)
        }; // u2.(T−2+D)
        let idx = (m >> d) as usize - (1usize << (t - 2));
        let s = self.interp(&self.sqrt_rom, idx, m as i64 & dmask, ctr); // u2.E

        // 6. x = S·C·2^(k+f−2E): u2.E × u1.E → u3.2E.
        let f = self.cfg.out_frac_bits as i32;
        let shift = 2 * e as i32 - f - k;
        let maxc = self.out_max_code() as i64;
        let mut out = |c: i64| -> i32 {
            let mag = round_shift((s * c.abs()) as i128, shift, Quant::Rnd) as i64;
            let mag = if mag > maxc {
                ctr.saturations += 1;
                maxc
            } else {
                mag
            };
            (if c < 0 { -mag } else { mag }) as i32
        };
        (out(cos_v), out(sin_v))
    }

    /// The central-limit datapath on 12 uniform codes (each masked to B bits).
    pub fn central_limit_codes(&self, ks: &[u64; 12], ctr: &mut Counters) -> i32 {
        let bb = self.cfg.uniform_bits;
        let mask_b = (1u64 << bb) - 1;
        let sum: u64 = ks.iter().map(|k| k & mask_b).sum(); // u(B+4)
                                                            // Σ(k + ½)/2ᴮ − 6 = (Σk + 6 − 6·2ᴮ)/2ᴮ: s(B+4).
        let v = sum as i64 + 6 - 6 * (1i64 << bb);
        let f = self.cfg.out_frac_bits as i32;
        let mag = round_shift(v.unsigned_abs() as i128, bb as i32 - f, Quant::Rnd) as i64;
        let maxc = self.out_max_code() as i64;
        let mag = if mag > maxc {
            ctr.saturations += 1;
            maxc
        } else {
            mag
        };
        (if v < 0 { -mag } else { mag }) as i32
    }

    /// Convenience: `n` normals (flattened x, y, x, y, … for Box–Muller) from `state`,
    /// as raw codes; counters as the kernel counts them (no cycle accounting).
    pub fn draw_codes(&self, state: &mut GaussState, n: usize, ctr: &mut Counters) -> Vec<i32> {
        let mut v = Vec::with_capacity(n + 1);
        while v.len() < n {
            let o = self.kernel(state, &(), ctr);
            v.push(o.x);
            if let Some(y) = o.y {
                v.push(y);
            }
        }
        v.truncate(n);
        v
    }

    /// taus88 cost: 96 state flip-flops, and the XORs of its three components
    /// (13 + 1, 7 + 0, 21 + 0 for the feedback words b and their merge into the
    /// shifted state; see [`taus88_step`]) and 64 for s1 ^ s2 ^ s3.
    fn taus88_cells() -> Cells {
        prim::register(96)
            + Cells {
                xor2: 14.0 + 7.0 + 21.0 + 64.0,
                ..Cells::default()
            }
    }

    /// Linear interpolator: subtract, multiply by the D-bit fraction, add.
    fn interp_cells(entry: u32, d: u32) -> Cells {
        prim::subtractor(entry + 1) + prim::multiplier(entry + 1, d) + prim::adder(entry + 1)
    }
}

impl Unit for GaussianNoise {
    /// A draw request (one kernel call per accepted request).
    type In = ();
    type Out = GaussOut;
    type State = GaussState;

    fn name(&self) -> &'static str {
        "gaussian_noise"
    }

    fn kernel(&self, state: &mut GaussState, _: &(), ctr: &mut Counters) -> GaussOut {
        match self.cfg.mode {
            GaussMode::BoxMuller => {
                let (ra, rb) = state.next_raw();
                let (x, y) =
                    self.box_muller_codes(self.uniform_code(ra), self.uniform_code(rb), ctr);
                GaussOut { x, y: Some(y) }
            }
            GaussMode::CentralLimit => {
                let mut ks = [0u64; 12];
                for j in 0..6 {
                    let (ra, rb) = state.next_raw();
                    ks[2 * j] = self.uniform_code(ra);
                    ks[2 * j + 1] = self.uniform_code(rb);
                }
                GaussOut {
                    x: self.central_limit_codes(&ks, ctr),
                    y: None,
                }
            }
        }
    }

    fn timing(&self) -> Timing {
        match self.cfg.mode {
            GaussMode::BoxMuller => Timing { latency: 9, ii: 1 },
            GaussMode::CentralLimit => Timing { latency: 7, ii: 6 },
        }
    }

    fn cost(&self) -> Cost {
        let c = &self.cfg;
        let (bb, t, e) = (c.uniform_bits, c.table_log2, c.table_bits);
        let d = e;
        let ob = self.out_bits();
        let gens = Cost::default()
            .part("taus88 A", Self::taus88_cells())
            .part("taus88 B", Self::taus88_cells());
        match c.mode {
            GaussMode::BoxMuller => {
                let stages = |n: u32| 32 - n.leading_zeros(); // shifter stages for n bit positions
                gens.part("uniform registers", prim::register(2 * bb))
                    .part("lzc of U1", prim::leading_zero_counter(bb + 1))
                    .part("mantissa normaliser", prim::shifter(t + d, stages(bb + 1)))
                    .part("ln interpolator", Self::interp_cells(e, d))
                    // LN2 is a constant (the Verilog's parameter): shift-adds over its
                    // signed digits, not a general 6 × (E + 8) array.
                    .part(
                        "e × ln2 (constant)",
                        prim::constant_multiplier(6, self.ln2 as u64),
                    )
                    .part("e·ln2 − L, round", prim::subtractor(e + 14))
                    .part("y registers", prim::register(3 * (e + 6)))
                    .part("lzc of Y", prim::leading_zero_counter(e + 5))
                    .part("√ normaliser", prim::shifter(t + d, stages(e + 6)))
                    .part("√ interpolator", Self::interp_cells(e + 2, d))
                    .part("phase complement", prim::subtractor(t + d + 1))
                    .part("phase aligner", prim::shifter(t + d, 1))
                    .part("sin, cos interpolators", Self::interp_cells(e + 1, d) * 2.0)
                    .part("quadrant swap and negate", prim::mux(2 * (e + 2)) * 2.0)
                    .part("trig registers", prim::register(4 * (e + 2)))
                    .part("r × cos, r × sin", prim::multiplier(e + 2, e + 1) * 2.0)
                    .part(
                        "scale shifters",
                        prim::shifter(2 * e + 3, stages(e / 2 + 4)) * 2.0,
                    )
                    .part("round and saturate", {
                        (prim::adder(ob) + prim::comparator(ob) + prim::mux(ob)) * 2.0
                    })
                    .part("sign apply", prim::subtractor(ob) * 2.0)
                    .part("pipeline registers", prim::register(6 * (e + 8)))
                    .part("output registers", prim::register(2 * ob))
                    .with_ram_bits(self.rom_bits())
            }
            GaussMode::CentralLimit => gens
                .part("adder of two uniforms", prim::adder(bb))
                .part("accumulator", prim::adder(bb + 4) + prim::register(bb + 4))
                .part("clock counter (mod 6)", prim::adder(3) + prim::register(3))
                .part("offset, round, saturate", {
                    prim::adder(bb + 4) + prim::comparator(ob) + prim::mux(ob)
                })
                .part("sign apply", prim::subtractor(ob))
                .part("output register", prim::register(ob)),
        }
    }

    fn widths(&self) -> Vec<Width> {
        let c = &self.cfg;
        vec![
            Width {
                name: "uniform_bits",
                bits: c.uniform_bits,
            },
            Width {
                name: "table_log2",
                bits: c.table_log2,
            },
            Width {
                name: "table_bits",
                bits: c.table_bits,
            },
            Width {
                name: "out_frac_bits",
                bits: c.out_frac_bits,
            },
            Width {
                name: "out_int_bits",
                bits: c.out_int_bits,
            },
        ]
    }

    fn in_signals(&self, _: &()) -> Vec<Signal> {
        vec![Signal::new("req", 1, 1)]
    }

    fn out_signals(&self, o: &GaussOut) -> Vec<Signal> {
        let w = self.out_bits();
        let m = (1u64 << w) - 1;
        vec![
            Signal::new("x", w, o.x as i64 as u64 & m),
            Signal::new("y", w, o.y.unwrap_or(0) as i64 as u64 & m),
        ]
    }
}
