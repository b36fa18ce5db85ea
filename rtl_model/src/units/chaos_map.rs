//! chaos_map — the 1/f fluctuation of sunlight through leaves (M. Matsuda and T. Ikedo,
//! "A Realtime Renderer for Glare Effect Based upon Empirical Approach", eqs. (9)–(11)):
//! the intermittent map
//!   S_{k+1} = S_k + u·S_k^z         for 0 ≤ S_k ≤ a,
//!   S_{k+1} = (S_k − a)/(1 − a)     for a < S_k ≤ 1,      u = (1 − a)/a^z, 1 < z < 2,
//! run on n patches with independent states; output I_p = I·(1/n)·Σ S_i.
//!
//! Datapath (F = `state_bits`, T = `table_log2`, E = `table_bits`, D = E interpolation
//! fraction bits, Z = `z_frac_bits`, O = `out_bits`, Fr = F + 4):
//! * State S: u0.F (0 ≤ S ≤ 1 − 2⁻ᶠ; 1.0 itself is not representable). a is held as
//!   A = round(a·2ᶠ) clamped to [1, 2ᶠ − 2] (so the left branch can always move);
//!   z as u1.Z, round(z·2ᶻ) clamped to [2ᶻ + 1, 2ᶻ⁺¹ − 1].
//! * Left branch (S ≤ A): u·S^z = 2^−v′ with v′ = z·(−log2 S) − log2 u.
//!   1. Leading-zero count: S = 2⁻ᵖ·m, p ∈ [1, F] (u6), m ∈ [1, 2) exact; the mantissa
//!      fraction aligned to T + D bits (exact when it is shorter, else truncated).
//!   2. log2 m from a ROM of 2ᵀ + 1 entries round(log2(1 + i/2ᵀ)·2ᴱ) (u1.E), linearly
//!      interpolated (s(E+2) × u(D) → s(E+D+2), rounded half up): L in u1.E.
//!   3. Δ = p·2ᴱ − L = −log2 S in u6.E (> 0); V = Z_q·Δ − LU in s8.(E+Z): u1.Z × u6.E →
//!      u7.(E+Z), minus the constant LU = round(log2 u · 2^(E+Z)) (log2 u is folded into
//!      the exponent: an adder instead of a multiplier by u, whose range is huge when
//!      a → 0). V < 0 (possible only by rounding at S ≈ a) is clamped to 0.
//!   4. n = ⌊V⌋ (integer part), φ = frac V aligned to T + D bits (truncated); 2^−φ from a
//!      ROM of 2ᵀ + 1 entries round(2^(−i/2ᵀ)·2ᴱ) (u1.E), interpolated: X ∈ [½, 1].
//!   5. inc = round(X·2^(F−E−n)) in u0.F (a right shift by E + n − F, rounded half up);
//!      inc = 0 for S > 0 is an **underflow** (counted).
//!   6. Escape: `None` adds inc (the naive design: S = 0 is a fixed point, and any S whose
//!      increment rounds to 0 sticks); `MinStep` adds max(inc, 1 LSB). The sum saturates
//!      at 2ᶠ − 1 (counted).
//! * Right branch (S > A): S′ = ⌊(S − A)·R_q⌋ with R_q = ⌊2^(F+Fr)/(2ᶠ − A)⌋ / 2^Fr ≤
//!   1/(1 − a_q) (a reciprocal fixed at configuration: no divider). u0.F × u(I_R).Fr →
//!   ⌊·⌋ to u0.F; the true product is < 2^(F+Fr) ≤ 2¹⁰⁰. Because R_q(1 − a_q) ≤ 1 the
//!   result is < S: the right branch never repeats a state, and S = 1 − 2⁻ᶠ moves off.
//! * Output: ΣS_i (u(F+6)) × K, K = round(I·2^(O+14)/n) (u(O+14)) → rounded half up to
//!   u0.O, saturating at 2ᴼ − 1 (counted): I_p = code·2⁻ᴼ.
//!
//! One shared datapath steps the n patches one after another (7 pipeline stages per
//! patch; the n patch states are the unit's state). One kernel call = one map step of
//! all n patches and one output word: II = max(n, 7) (a patch's next state must be
//! written back before it is read again), latency n + 7.

use crate::cost::{prim, Cells, Cost};
use crate::counters::Counters;
use crate::error::{check_finite, check_range, ConfigError};
use crate::fixed_point::{round_shift, Quant};
use crate::packed_rom::PackedRom;
use crate::unit::{Signal, Timing, Unit, Width};
use serde::{Deserialize, Serialize};

/// What keeps the map off its fixed point at 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Escape {
    /// The naive design: S + round(u·S^z). Sticks at 0 (and wherever the increment
    /// underflows).
    None,
    /// S + max(round(u·S^z), 1 LSB): one comparator and one mux.
    MinStep,
}

/// The plain config (serde-friendly); [`ChaosMapConfig::build`] validates it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ChaosMapConfig {
    /// Break point a, in (0, 1) exclusive.
    pub a: f64,
    /// Exponent z, in (1, 2) exclusive.
    pub z: f64,
    /// Intensity I of the source, in [0, 1].
    pub intensity: f64,
    /// Patches n, 1 ..= 64.
    pub patches: u32,
    /// State fraction bits F, 8 ..= 48.
    pub state_bits: u32,
    /// log2 of the ROM segment count T, 4 ..= 12.
    pub table_log2: u32,
    /// ROM entry fraction bits E (= interpolation fraction D), 8 ..= 28.
    pub table_bits: u32,
    /// Fraction bits Z of z, 4 ..= 24.
    pub z_frac_bits: u32,
    /// Output bits O (u0.O), 4 ..= 16.
    pub out_bits: u32,
    /// What keeps the map off its fixed point at 0 (default `min_step`).
    pub escape: Escape,
}

impl Default for ChaosMapConfig {
    fn default() -> Self {
        ChaosMapConfig::geforce()
    }
}

impl ChaosMapConfig {
    /// Defaults: a = 0.8, z = 1.95 (theoretical spectrum f^−β, β = (2z − 3)/(z − 1) =
    /// 0.947; chosen for a clean two-decade slope at 10⁶ steps: fitted −0.83 … −0.90
    /// over seeds 1–4, where a = 0.5, z = 1.9 gave −0.50 … −0.65), I = 1, 4 patches, S in u0.32, 1024-segment ROMs of 24-bit entries, z at
    /// 16 fraction bits, 16-bit output, MinStep escape.
    pub fn geforce() -> Self {
        ChaosMapConfig {
            a: 0.8,
            z: 1.95,
            intensity: 1.0,
            patches: 4,
            state_bits: 32,
            table_log2: 10,
            table_bits: 24,
            z_frac_bits: 16,
            out_bits: 16,
            escape: Escape::MinStep,
        }
    }

    /// Validate and build the unit; the same as [`ChaosMap::new`], errors name
    /// `chaos_map.<field>`.
    pub fn build(&self) -> Result<ChaosMap, ConfigError> {
        ChaosMap::new(*self)
    }
}

/// The validated unit: config, quantised constants and the two ROMs.
#[derive(Clone, Debug, PartialEq)]
pub struct ChaosMap {
    cfg: ChaosMapConfig,
    /// a as u0.F.
    a_q: u64,
    /// z as u1.Z.
    z_q: u64,
    /// round(log2 u · 2^(E+Z)), u = (1 − a_q)/a_q^z.
    log2u_q: i64,
    /// ⌊2^(F+Fr)/(2ᶠ − A)⌋.
    recip: u128,
    /// round(I·2^(O+14)/n).
    k_out: u64,
    log2_rom: PackedRom,
    exp2_rom: PackedRom,
}

/// The n patch states, raw u0.F codes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ChaosState {
    /// One state per patch (`patches` of them), each a u0.F code (F = `state_bits`).
    pub s: Vec<u64>,
}

/// Extra fraction bits of the reciprocal 1/(1 − a) beyond F.
pub const RECIP_EXTRA_BITS: u32 = 4;
/// Extra fraction bits of the output gain K beyond O.
pub const GAIN_EXTRA_BITS: u32 = 14;
/// Pipeline stages a patch spends in the datapath.
pub const PATCH_STAGES: u32 = 7;

fn splitmix64(x: &mut u64) -> u64 {
    *x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *x;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

fn field(n: &str) -> String {
    format!("chaos_map.{n}")
}

fn check_open(name: &str, v: f64, lo: f64, hi: f64) -> Result<f64, ConfigError> {
    let v = check_finite(&field(name), v)?;
    if v <= lo || v >= hi {
        return Err(ConfigError::out_of_range(&field(name), v, lo, hi));
    }
    Ok(v)
}

impl ChaosMap {
    /// Validate a config, quantise a, z, I and build the ROMs; errors name
    /// `chaos_map.<field>` (NaN/±∞ in a, z or intensity included).
    pub fn new(cfg: ChaosMapConfig) -> Result<Self, ConfigError> {
        check_range(&field("patches"), cfg.patches as u64, 1, 64)?;
        check_range(&field("state_bits"), cfg.state_bits as u64, 8, 48)?;
        check_range(&field("table_log2"), cfg.table_log2 as u64, 4, 12)?;
        check_range(&field("table_bits"), cfg.table_bits as u64, 8, 28)?;
        check_range(&field("z_frac_bits"), cfg.z_frac_bits as u64, 4, 24)?;
        check_range(&field("out_bits"), cfg.out_bits as u64, 4, 16)?;
        let a = check_open("a", cfg.a, 0.0, 1.0)?;
        let z = check_open("z", cfg.z, 1.0, 2.0)?;
        let i = check_finite(&field("intensity"), cfg.intensity)?;
        if !(0.0..=1.0).contains(&i) {
            return Err(ConfigError::out_of_range(&field("intensity"), i, 0.0, 1.0));
        }
        let (f, t, e, zf, o) = (
            cfg.state_bits,
            cfg.table_log2,
            cfg.table_bits,
            cfg.z_frac_bits,
            cfg.out_bits,
        );
        let one = 1u64 << f;
        let a_q = ((a * one as f64).round() as u64).clamp(1, one - 2);
        let z_q = ((z * (zf as f64).exp2()).round() as u64).clamp((1 << zf) + 1, (2 << zf) - 1);
        let aqf = a_q as f64 / one as f64;
        // log2 u with the configured (unquantised) z: the twin's u.
        let log2u = (1.0 - aqf).log2() - z * aqf.log2();
        let log2u_q = (log2u * ((e + zf) as f64).exp2()).round() as i64;
        let fr = f + RECIP_EXTRA_BITS;
        let recip = (1u128 << (f + fr)) / (one - a_q) as u128;
        let k_out = (i * ((o + GAIN_EXTRA_BITS) as f64).exp2() / cfg.patches as f64).round() as u64;
        let n = 1u64 << t;
        let scale = (e as f64).exp2();
        let l2: Vec<u64> = (0..=n)
            .map(|j| ((1.0 + j as f64 / n as f64).log2() * scale).round() as u64)
            .collect();
        let x2: Vec<u64> = (0..=n)
            .map(|j| ((-(j as f64) / n as f64).exp2() * scale).round() as u64)
            .collect();
        Ok(ChaosMap {
            cfg,
            a_q,
            z_q,
            log2u_q,
            recip,
            k_out,
            log2_rom: PackedRom::new(e + 1, &l2),
            exp2_rom: PackedRom::new(e + 1, &x2),
        })
    }

    /// Defaults (see [`ChaosMapConfig::geforce`]).
    pub fn geforce() -> Self {
        match Self::new(ChaosMapConfig::geforce()) {
            Ok(u) => u,
            Err(e) => unreachable!("default config invalid: {e}"),
        }
    }

    /// The config the unit was built from (a, z and I as given, before quantising).
    pub fn config(&self) -> ChaosMapConfig {
        self.cfg
    }

    /// a as held (u0.F code).
    pub fn a_code(&self) -> u64 {
        self.a_q
    }

    /// a as held, as a real (for the twin).
    pub fn a_quantised(&self) -> f64 {
        self.a_q as f64 / (self.cfg.state_bits as f64).exp2()
    }

    /// z as held (u1.Z), as a real.
    pub fn z_quantised(&self) -> f64 {
        self.z_q as f64 / (self.cfg.z_frac_bits as f64).exp2()
    }

    /// Largest state code, 2ᶠ − 1.
    pub fn state_max(&self) -> u64 {
        (1u64 << self.cfg.state_bits) - 1
    }

    /// The output gain K = round(I·2^(O+14)/n) as a real: I/n as held.
    pub fn gain_quantised(&self) -> f64 {
        self.k_out as f64 / ((self.cfg.out_bits + GAIN_EXTRA_BITS) as f64).exp2()
    }

    /// ROM images (log2, exp2): (name, entry width, words).
    pub fn rom_images(&self) -> Vec<(String, u32, Vec<u64>)> {
        let (t, e) = (self.cfg.table_log2, self.cfg.table_bits);
        vec![
            (
                format!("chaos_map.log2_t{t}_e{e}"),
                e + 1,
                self.log2_rom.words(),
            ),
            (
                format!("chaos_map.exp2_t{t}_e{e}"),
                e + 1,
                self.exp2_rom.words(),
            ),
        ]
    }

    /// Patch states from a seed: patch i = top F bits of SplitMix64 word i.
    pub fn seeded_state(&self, seed: u64) -> ChaosState {
        let mut x = seed;
        ChaosState {
            s: (0..self.cfg.patches)
                .map(|_| splitmix64(&mut x) >> (64 - self.cfg.state_bits))
                .collect(),
        }
    }

    #[inline]
    fn interp(&self, rom: &PackedRom, i: usize, t: i64, ctr: &mut Counters) -> i64 {
        let d = self.cfg.table_bits as i32;
        let a = rom.read(i); // u1.E
        let b = rom.read(i + 1);
        ctr.table_reads += 2;
        // s(E+2) × u(D) → s(E+D+2), rounded half up to the entry LSB.
        a + round_shift(((b - a) * t) as i128, d, Quant::Rnd) as i64
    }

    /// The increment round(u·S^z) in u0.F for a state code 0 < s ≤ 2ᶠ − 1 (before the
    /// escape); 0 for s = 0.
    pub fn increment(&self, s: u64, ctr: &mut Counters) -> u64 {
        let (f, t, e, zf) = (
            self.cfg.state_bits,
            self.cfg.table_log2,
            self.cfg.table_bits,
            self.cfg.z_frac_bits,
        );
        let d = e;
        let s = s & self.state_max();
        if s == 0 {
            return 0;
        }
        // 1. S = 2⁻ᵖ·m: bit length bl, p = F − bl + 1 ∈ [1, F].
        let bl = 64 - s.leading_zeros();
        let p = (f + 1 - bl) as i64;
        let mf = s - (1u64 << (bl - 1)); // bl − 1 fraction bits of m
        let td = t + d;
        let fr = if bl - 1 <= td {
            mf << (td - (bl - 1))
        } else {
            mf >> ((bl - 1) - td)
        }; // u(T+D)
        let dmask = (1i64 << d) - 1;
        // 2. L = log2 m, u1.E.
        let l = self.interp(&self.log2_rom, (fr >> d) as usize, fr as i64 & dmask, ctr);
        // 3. Δ = −log2 S (u6.E); V = z·Δ − log2 u: u1.Z × u6.E → u7.(E+Z), − s8.(E+Z).
        let delta = (p << e) - l;
        let v = (self.z_q as i128 * delta as i128 - self.log2u_q as i128).max(0);
        // 4. n = ⌊V⌋, φ = frac V aligned to T + D bits.
        let ez = e + zf;
        let n = (v >> ez) as i64;
        let phi = (v & ((1i128 << ez) - 1)) as u64;
        let ph = if ez <= td {
            phi << (td - ez)
        } else {
            phi >> (ez - td)
        };
        let x = self.interp(&self.exp2_rom, (ph >> d) as usize, ph as i64 & dmask, ctr); // u1.E
                                                                                         // 5. inc = round(X·2^(F−E−n)), u0.F.
        let sh = (e as i64 + n - f as i64).min(200) as i32;
        round_shift(x as i128, sh, Quant::Rnd) as u64
    }

    /// One map step of one patch state (raw u0.F code, masked).
    pub fn step(&self, s: u64, ctr: &mut Counters) -> u64 {
        let max = self.state_max();
        let s = s & max;
        if s <= self.a_q {
            let inc = self.increment(s, ctr);
            if s > 0 && inc == 0 {
                ctr.underflows += 1;
            }
            let inc = match self.cfg.escape {
                Escape::None => inc,
                Escape::MinStep => inc.max(1),
            };
            let next = s as u128 + inc as u128; // u0.F + u1.F → u1.F
            if next > max as u128 {
                ctr.saturations += 1;
                max
            } else {
                next as u64
            }
        } else {
            let fr = self.cfg.state_bits + RECIP_EXTRA_BITS;
            // u0.F × u(I_R).Fr → floor to u0.F; < S always (R_q(1 − a_q) ≤ 1).
            (((s - self.a_q) as u128 * self.recip) >> fr) as u64
        }
    }

    /// The output word for the given patch states: round(ΣS·K) to u0.O, saturating.
    pub fn output(&self, s: &[u64], ctr: &mut Counters) -> u32 {
        let (f, o) = (self.cfg.state_bits, self.cfg.out_bits);
        let sum: u128 = s.iter().map(|&x| (x & self.state_max()) as u128).sum(); // u(F+6)
        let prod = sum * self.k_out as u128; // u(F+6) × u(O+14) → u(F+O+20)
        let out = round_shift(prod as i128, (f + GAIN_EXTRA_BITS) as i32, Quant::Rnd) as u64;
        let max = (1u64 << o) - 1;
        if out > max {
            ctr.saturations += 1;
            max as u32
        } else {
            out as u32
        }
    }

    /// Run `steps` kernel steps from `state` (span driver, counters added); returns the
    /// output words. The pipeline's entry point.
    pub fn run_trace(&self, state: &mut ChaosState, steps: usize, ctr: &mut Counters) -> Vec<u32> {
        crate::driver::run_span(self, state, &vec![(); steps], ctr)
    }

    /// Steps of the longest laminar phase: from S = 0 until S > a (the left branch is
    /// monotone in S up to table rounding, so no start in [0, a] takes longer), capped
    /// at `cap`. `None` if it never leaves within `cap` (the naive design at S = 0).
    pub fn laminar_steps_from_zero(&self, cap: u64) -> Option<u64> {
        let mut s = 0u64;
        let mut ctr = Counters::default();
        for k in 1..=cap {
            s = self.step(s, &mut ctr);
            if s > self.a_q {
                return Some(k);
            }
        }
        None
    }
}

impl Unit for ChaosMap {
    /// A step request.
    type In = ();
    type Out = u32;
    type State = ChaosState;

    fn name(&self) -> &'static str {
        "chaos_map"
    }

    fn kernel(&self, state: &mut ChaosState, _: &(), ctr: &mut Counters) -> u32 {
        // A state vector of the wrong length is resized (missing patches start at 0).
        state.s.resize(self.cfg.patches as usize, 0);
        for s in state.s.iter_mut() {
            *s = self.step(*s, ctr);
        }
        self.output(&state.s, ctr)
    }

    fn timing(&self) -> Timing {
        let n = self.cfg.patches;
        Timing {
            latency: n + PATCH_STAGES,
            ii: n.max(PATCH_STAGES),
        }
    }

    /// Priced as rtl_model/verilog/units/chaos_map.v is built. a, z, log2 u and I/n are
    /// constants of the configuration (the Verilog's parameters `A`, `ZQ`, `LU_*`,
    /// `K_OUT`; `recip` is computed from `A` when the unit is built), so z × Δ,
    /// (S − a) × 1/(1 − a) and ΣS × I/n are constant multipliers
    /// ([`prim::constant_multiplier`]: shift-adds over the constant's signed digits;
    /// I/n = 2^−2 at the default is wiring), not general array multipliers. The
    /// interpolators multiply two data words and stay general. Registers are the
    /// Verilog's: the patch states (with their write port), the 7-stage datapath's
    /// stage registers, the ROM address registers, the request counter and valid chain.
    fn cost(&self) -> Cost {
        let c = &self.cfg;
        let (f, t, e, zf, o, n) = (
            c.state_bits,
            c.table_log2,
            c.table_bits,
            c.z_frac_bits,
            c.out_bits,
            c.patches,
        );
        let d = e;
        // The Verilog's patch index and request counter (`IW`), p = F + 1 − bl (7 bits).
        let (iw, pw) = (7, 7);
        let stages = |w: u32| 32 - w.leading_zeros();
        let interp = prim::subtractor(e + 2) + prim::multiplier(e + 2, d) + prim::adder(e + 2);
        let rom_bits = self.log2_rom.ram_bits() + self.exp2_rom.ram_bits();
        let mut cost = Cost::default()
            .part("patch state registers", prim::register(n * f))
            .part("patch state write port (load enables)", prim::mux(n * f))
            .part("patch select", prim::mux_k(f, n))
            .part("lzc of S", prim::leading_zero_counter(f))
            .part("mantissa normaliser", prim::shifter(t + d, stages(f)))
            .part(
                "ROM addresses i, i + 1 (log2, exp2)",
                prim::half_adder() * (2 * t) as f64,
            )
            .part("log2 interpolator", interp)
            .part("p·2^E − L", prim::subtractor(e + 6))
            .part(
                "z × Δ (z constant)",
                prim::constant_multiplier(e + 6, self.z_q),
            )
            .part("− log2 u", prim::subtractor(e + zf + 8))
            .part(
                "V < 0 → 0",
                Cells {
                    and2: (e + zf + 9) as f64,
                    ..Cells::default()
                },
            )
            .part("exp2 interpolator", interp)
            .part("2^−n shifter", prim::shifter(f + 1, stages(f + e)))
            .part("round inc", prim::adder(f))
            .part("branch compare S ≤ a", prim::comparator(f))
            .part("S + inc, saturate", prim::saturating_adder(f + 1))
            .part("S − a", prim::subtractor(f))
            .part(
                "(S − a) × 1/(1 − a) (constant)",
                prim::constant_multiplier_u128(f, self.recip),
            )
            .part("branch mux", prim::mux(f))
            .part(
                "patch accumulator",
                prim::adder(f + 6) + prim::register(f + 6),
            )
            .part("× I/n (constant), round, saturate", {
                prim::constant_multiplier(f + 6, self.k_out)
                    + prim::adder(o + 1)
                    + prim::comparator(o + 1)
                    + prim::mux(o)
            })
            .part(
                "stage registers (S ×5, p ×2, t ×4, index ×6, n ×3, X, S′)",
                prim::register(5 * f + 2 * pw + 4 * d + 6 * iw + 3 * 9 + (e + 2) + f),
            )
            .part(
                "ROM address registers (2 × log2, 2 × exp2)",
                prim::register(2 * (2 * t + 1)),
            )
            .part(
                "request counter and valid chain",
                prim::register(iw + 1 + 6 + 2),
            )
            .part("output register", prim::register(o));
        if c.escape == Escape::MinStep {
            // inc == 0 (an OR tree) forces bit 0: max(inc, 1) = inc | (inc == 0).
            cost = cost.part(
                "min step: inc | (inc == 0)",
                Cells {
                    or2: f as f64,
                    ..Cells::default()
                },
            );
        }
        cost.with_ram_bits(rom_bits)
    }

    fn widths(&self) -> Vec<Width> {
        let c = &self.cfg;
        vec![
            Width {
                name: "state_bits",
                bits: c.state_bits,
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
                name: "z_frac_bits",
                bits: c.z_frac_bits,
            },
            Width {
                name: "out_bits",
                bits: c.out_bits,
            },
        ]
    }

    fn in_signals(&self, _: &()) -> Vec<Signal> {
        vec![Signal::new("step", 1, 1)]
    }

    fn out_signals(&self, o: &u32) -> Vec<Signal> {
        vec![Signal::new("ip", self.cfg.out_bits, *o as u64)]
    }
}
