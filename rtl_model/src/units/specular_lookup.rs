//! specular_lookup — (n·h)^s from a table: the GeForce-era way to get a sharp specular
//! without a per-pixel pow. A ROM (a 1D texture the host writes) of 2^k entries of b
//! bits, indexed by the n-bit dot-product code a DOT3 stage produced, read with
//! nearest or linear interpolation between entries; the output is a b-bit unorm.
//!
//! Table (the host's, written for one exponent s ∈ [1, 10⁴]): N = 2^k − 1 intervals,
//! node j at x_j = j/N, entry T_j = round((j/N)^s · B), B = 2^b − 1 (round half up).
//! Any other contents can be loaded ([`SpecularLookup::load_table`]).
//!
//! Input: the DOT3 result, either an unsigned n-bit unorm x = code/(2^n − 1) (the
//! texture combiner's DOT3_RGB output; default n = 8), or a signed n-bit
//! two's-complement word of the register combiners' internal format,
//! x = code/(2^(n−1) − 1) (9 bits on GeForce 256/2: −256 ..= 255 for [−1, 1]); a
//! negative word (a light behind the surface) reads as 0, counted in `saturations`.
//! Either way the lookup sees an unsigned magnitude code of m bits (m = n, or n − 1
//! when signed), M = 2^m − 1. A word wider than its n wires is masked (sign-extended)
//! and counts one `overflows`.
//!
//! Datapath (k = `table_log2`, b = `entry_bits`, w = `weight_bits`, g = m guard bits):
//! 1. Position p = x·N in table-index units, as u(k).w: P = ⌊(x·C + 2^(g−1)) / 2^g⌋
//!    with the constant C = round(N·2^(w+g)/M) (u(k+w+1)); u(m) × u(k+w+1) →
//!    u(m+k+w+1), rounded to u(k).w. C is exactly 2^(w+g) when m = k (the default):
//!    the multiplier is wiring and P = x·2^w is exact. Otherwise |C − N·2^(w+g)/M| ≤ ½
//!    and x ≤ M < 2^g, so |P/2^w − p| < 2^−w (half from C, half from the rounding)
//!    and P never exceeds N·2^w (the guard clamp below cannot fire; counted if it did).
//! 2. Nearest: i = (P + 2^(w−1)) >> w (u(k)), out = T_i: one ROM read.
//!    Linear: i0 = P >> w, f = P mod 2^w (u(w)), i1 = min(i0 + 1, N) (f = 0 when
//!    i0 = N); two ROM reads (even/odd banks, so one clock); d = T_i1 − T_i0 (s(b+1));
//!    out = T_i0 + ⌊(d·f + 2^(w−1)) / 2^w⌋ (s(b+1) × u(w) → s(b+w+1), floor shift =
//!    round half up) — the texture sampler's 1D lerp, (T0·(W−f) + T1·f + W/2) >> w,
//!    with one multiplier. It lies between T_i0 and T_i1: no saturation possible.
//!    A non-zero interpolant rounded to 0 counts one `underflows`.
//!
//! Timing: II 1; latency 2 nearest (position | ROM read), 4 linear (position | ROM
//! reads | d·f | round, + T_i0).
//! Counters: `table_reads` (1 nearest, 2 linear), `saturations` (negative signed
//! inputs clamped to 0; the position guard), `overflows` (input words that did not fit
//! their wires), `underflows` (non-zero interpolant rounded to 0).

use crate::cost::{prim, Cells, Cost};
use crate::counters::Counters;
use crate::error::{check_finite, check_range, ConfigError};
use crate::packed_rom::PackedRom;
use crate::unit::{Signal, Timing, Unit, Width};
use crate::units::texture_sampler::Filter;
use crate::wire::sign_extend;
use serde::{Deserialize, Serialize};

/// Smallest and largest exponent the host writes tables for.
pub const EXPONENT_RANGE: (f64, f64) = (1.0, 1e4);
/// The exponent of the default table (the registry's ROM image).
pub const DEFAULT_EXPONENT: f64 = 32.0;

/// The plain config (serde-friendly); [`SpecularLookupConfig::build`] validates it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SpecularLookupConfig {
    /// log2 of the entry count k (2^k entries), 1 ..= 12.
    pub table_log2: u32,
    /// Entry (and output) width b, unorm, 1 ..= 16.
    pub entry_bits: u32,
    /// Input word width n: 1 ..= 16 unsigned, 2 ..= 17 signed.
    pub in_bits: u32,
    /// The input is a signed two's-complement word (register-combiner format).
    pub signed_input: bool,
    /// Nearest entry or linear interpolation between entries.
    pub filter: Filter,
    /// Fraction bits w of the table position (the lerp weight), 1 ..= 16.
    pub weight_bits: u32,
    /// The exponent s the table is written for, 1 ..= 10⁴ (finite).
    pub exponent: f64,
}

impl Default for SpecularLookupConfig {
    fn default() -> Self {
        Self::geforce()
    }
}

impl SpecularLookupConfig {
    /// GeForce defaults: a 256 × 8-bit 1D texture indexed by the 8-bit DOT3 code,
    /// linear with 8-bit weights (at n = k the position is the code itself, so the
    /// weight is 0 and linear reads the entry exactly), s = 32.
    pub fn geforce() -> Self {
        SpecularLookupConfig {
            table_log2: 8,
            entry_bits: 8,
            in_bits: 8,
            signed_input: false,
            filter: Filter::Linear,
            weight_bits: 8,
            exponent: DEFAULT_EXPONENT,
        }
    }

    /// The register-combiner variant: a signed 9-bit input word (negative → 0).
    pub fn geforce_signed() -> Self {
        SpecularLookupConfig {
            in_bits: 9,
            signed_input: true,
            ..Self::geforce()
        }
    }

    /// Magnitude bits m of the index code: n, or n − 1 when signed.
    pub fn magnitude_bits(&self) -> u32 {
        self.in_bits - u32::from(self.signed_input)
    }

    /// Validate and load the table for the configured exponent; the same as
    /// [`SpecularLookup::new`], errors name `specular_lookup.<field>`.
    pub fn build(&self) -> Result<SpecularLookup, ConfigError> {
        SpecularLookup::new(*self)
    }
}

/// One pixel: the dot-product word (low `in_bits` wires; signed or unsigned).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct SpecularLookupIn {
    /// The dot-product code: u(n) unorm, or s(n) two's complement when `signed_input`
    /// (negative reads as 0, counted in `saturations`); a word wider than n wires is
    /// masked and counts one `overflows`.
    pub code: i32,
}

/// Table entry j for 2^k entries of b bits at exponent s: round((j/N)^s · (2^b − 1)),
/// N = 2^k − 1 (a ROM image computed in f64 at build time; round half up). A
/// non-finite s reads as 1.
pub fn specular_table_entry(j: u64, table_log2: u32, entry_bits: u32, exponent: f64) -> u64 {
    let n = ((1u64 << table_log2) - 1) as f64;
    let big_b = ((1u64 << entry_bits) - 1) as f64;
    let s = if exponent.is_finite() { exponent } else { 1.0 };
    let x = (j as f64 / n).clamp(0.0, 1.0);
    (x.powf(s) * big_b + 0.5).floor().clamp(0.0, big_b) as u64
}

/// The validated unit: config, the position constant and the table.
#[derive(Clone, Debug, PartialEq)]
pub struct SpecularLookup {
    cfg: SpecularLookupConfig,
    /// C = round(N·2^(w+g)/M), g = m.
    position_scale: u64,
    table: PackedRom,
}

impl SpecularLookup {
    /// Validate and write the table for `cfg.exponent`; errors name
    /// `specular_lookup.<field>`.
    pub fn new(cfg: SpecularLookupConfig) -> Result<Self, ConfigError> {
        let f = |n: &str| format!("specular_lookup.{n}");
        check_range(&f("table_log2"), cfg.table_log2 as u64, 1, 12)?;
        check_range(&f("entry_bits"), cfg.entry_bits as u64, 1, 16)?;
        if cfg.signed_input {
            check_range(&f("in_bits"), cfg.in_bits as u64, 2, 17)?;
        } else {
            check_range(&f("in_bits"), cfg.in_bits as u64, 1, 16)?;
        }
        check_range(&f("weight_bits"), cfg.weight_bits as u64, 1, 16)?;
        let s = check_finite(&f("exponent"), cfg.exponent)?;
        if !(EXPONENT_RANGE.0..=EXPONENT_RANGE.1).contains(&s) {
            return Err(ConfigError::out_of_range(
                &f("exponent"),
                s,
                EXPONENT_RANGE.0,
                EXPONENT_RANGE.1,
            ));
        }
        let (k, b) = (cfg.table_log2, cfg.entry_bits);
        let words: Vec<u64> = (0..1u64 << k)
            .map(|j| specular_table_entry(j, k, b, s))
            .collect();
        let m = cfg.magnitude_bits();
        let big_n = (1u128 << k) - 1;
        let big_m = (1u128 << m) - 1;
        // round(N·2^(w+g)/M), g = m: ≤ 2^12 · 2^32 / 1, exact in u128.
        let num = big_n << (cfg.weight_bits + m);
        let position_scale = ((2 * num + big_m) / (2 * big_m)) as u64;
        Ok(SpecularLookup {
            cfg,
            position_scale,
            table: PackedRom::new(b, &words),
        })
    }

    /// GeForce defaults (see [`SpecularLookupConfig::geforce`]).
    pub fn geforce() -> Self {
        match Self::new(SpecularLookupConfig::geforce()) {
            Ok(u) => u,
            Err(e) => unreachable!("default config invalid: {e}"),
        }
    }

    /// The config the unit was built from.
    pub fn config(&self) -> SpecularLookupConfig {
        self.cfg
    }

    /// Replace the table (the host writing the 1D texture): 2^k codes < 2^b, else an
    /// error naming `specular_lookup.table` (the table is then unchanged).
    pub fn load_table(&mut self, words: &[u64]) -> Result<(), ConfigError> {
        let depth = 1usize << self.cfg.table_log2;
        if words.len() != depth {
            return Err(ConfigError::invalid(
                "specular_lookup.table",
                &format!(
                    "expected {depth} entries (2^table_log2), got {}",
                    words.len()
                ),
            ));
        }
        let max = (1u64 << self.cfg.entry_bits) - 1;
        if let Some((j, v)) = words.iter().enumerate().find(|(_, &v)| v > max) {
            return Err(ConfigError::invalid(
                "specular_lookup.table",
                &format!("entry {j} = {v} does not fit {} bits", self.cfg.entry_bits),
            ));
        }
        self.table = PackedRom::new(self.cfg.entry_bits, words);
        Ok(())
    }

    /// The table entries, address order.
    pub fn table_words(&self) -> Vec<u64> {
        self.table.words()
    }

    /// Table bits 2^k · b.
    pub fn rom_bits(&self) -> u64 {
        self.table.ram_bits()
    }

    /// Entries j > 0 of the written table that are 0 though (j/N)^s > 0: the part of
    /// the table the exponent rounded away (at s = 10⁴, k = b = 8: all but the last).
    pub fn table_underflows(&self) -> u64 {
        self.table
            .words()
            .iter()
            .skip(1)
            .filter(|&&v| v == 0)
            .count() as u64
    }

    /// The position constant C = round(N·2^(w+m)/M).
    pub fn position_scale(&self) -> u64 {
        self.position_scale
    }

    /// True when C is a power of two (m = k): the position is the code, shifted.
    pub fn position_is_exact(&self) -> bool {
        self.cfg.magnitude_bits() == self.cfg.table_log2
    }

    /// The unsigned magnitude code the lookup sees: the word's wires, negative signed
    /// words clamped to 0 (counted), words wider than their wires counted.
    pub fn magnitude(&self, code: i32, ctr: &mut Counters) -> u64 {
        let n = self.cfg.in_bits;
        if self.cfg.signed_input {
            let v = sign_extend(code as i64, n); // s(n)
            ctr.overflows += u64::from(v != code as i64);
            if v < 0 {
                ctr.saturations += 1; // a back-facing dot product reads as 0
                0
            } else {
                v as u64 // u(n−1)
            }
        } else {
            let v = code as i64 & ((1i64 << n) - 1); // u(n)
            ctr.overflows += u64::from(v != code as i64);
            v as u64
        }
    }

    /// Step 1: the table position P = x·N as u(k).w raw (see the module notes).
    pub fn position(&self, x: u64, ctr: &mut Counters) -> u64 {
        let w = self.cfg.weight_bits;
        let g = self.cfg.magnitude_bits();
        // u(m) × u(k+w+1) → u(m+k+w+1) ≤ 2^46; + 2^(g−1), >> g → u(k).w
        let p = (x * self.position_scale + (1u64 << (g - 1))) >> g;
        let top = ((1u64 << self.cfg.table_log2) - 1) << w; // N·2^w
        if p > top {
            ctr.saturations += 1; // guard: cannot fire (|C error|·x < 2^(g−1))
            top
        } else {
            p
        }
    }

    /// The whole datapath on one word.
    pub fn lookup(&self, code: i32, ctr: &mut Counters) -> u32 {
        let w = self.cfg.weight_bits;
        let x = self.magnitude(code, ctr);
        let p = self.position(x, ctr);
        match self.cfg.filter {
            Filter::Nearest => {
                let i = (p + (1u64 << (w - 1))) >> w; // u(k).w + ½ → u(k), ≤ N
                ctr.table_reads += 1;
                self.table.read(i as usize) as u32
            }
            Filter::Linear => {
                let last = (1u64 << self.cfg.table_log2) - 1;
                let i0 = p >> w; // u(k)
                let f = (p & ((1u64 << w) - 1)) as i64; // u(w); 0 when i0 = N
                let i1 = (i0 + 1).min(last);
                ctr.table_reads += 2; // even/odd banks: i0 and i0 + 1 in one clock
                let t0 = self.table.read(i0 as usize); // u(b)
                let t1 = self.table.read(i1 as usize); // u(b)
                let d = t1 - t0; // s(b+1)
                let r = (d * f + (1i64 << (w - 1))) >> w; // s(b+1) × u(w) → s(b+w+1) → s(b+1)
                let out = t0 + r; // between t0 and t1: u(b)
                if out == 0 && (t0 > 0 || (t1 > 0 && f > 0)) {
                    ctr.underflows += 1;
                }
                out as u32
            }
        }
    }
}

impl Unit for SpecularLookup {
    type In = SpecularLookupIn;
    type Out = u32;
    type State = ();

    fn name(&self) -> &'static str {
        "specular_lookup"
    }

    fn kernel(&self, _: &mut (), input: &SpecularLookupIn, ctr: &mut Counters) -> u32 {
        self.lookup(input.code, ctr)
    }

    fn timing(&self) -> Timing {
        // position | ROM read [| d·f | round, + T_i0]
        Timing {
            latency: match self.cfg.filter {
                Filter::Nearest => 2,
                Filter::Linear => 4,
            },
            ii: 1,
        }
    }

    /// Priced as the Verilog (`rtl_model/verilog/units/specular_lookup.v`) is built:
    /// the input word feeds the position logic directly, the first register is the
    /// position's (Timing: position | ROM read…), so there is no input register; the
    /// ROM's synchronous read is the ROM's own output register (nearest has no other).
    /// At m = k the position is x·2^w: its w fraction bits, the lerp weight, are
    /// constant 0, so with the linear filter only T_i0 is live (no weight register,
    /// d = T1 − T0, d·f, rounder or + T0: the output is T_i0 delayed to the latency),
    /// and with the nearest filter the index rounder adds to constant-0 bits. When
    /// m ≠ k, x × C is a constant multiplier ([`prim::constant_multiplier`]).
    fn cost(&self) -> Cost {
        let c = self.cfg;
        let (k, b, w) = (c.table_log2, c.entry_bits, c.weight_bits);
        let m = c.magnitude_bits();
        let exact = self.position_is_exact();
        // Fraction bits of the position that are not constant 0.
        let wf = if exact { 0 } else { w };
        let pw = k + wf; // the position's live bits, u(k).wf
        let mut cost = Cost::default();
        if c.signed_input {
            cost = cost.part(
                "negative → 0 (sign-bit AND gates)",
                Cells {
                    and2: m as f64,
                    ..Cells::default()
                },
            );
        }
        if !exact {
            cost = cost
                .part(
                    "position: x × C (constant, shift-adds over C's signed digits)",
                    prim::constant_multiplier(m, self.position_scale),
                )
                .part(
                    "position: rounder (+ 2^(m−1), incrementer)",
                    prim::half_adder() * (pw + 1) as f64,
                )
                .part(
                    "position: guard clamp (comparator + mux)",
                    prim::comparator(pw + 1) + prim::mux(pw),
                );
        }
        cost = cost.part("position register", prim::register(pw));
        let cost = match c.filter {
            Filter::Nearest => {
                let cost = if exact {
                    cost
                } else {
                    cost.part(
                        "nearest: index rounder (incrementer)",
                        prim::half_adder() * (k + 1) as f64,
                    )
                };
                cost.part(
                    "bank select register, even/odd output mux",
                    prim::register(1) + prim::mux(b),
                )
            }
            Filter::Linear if exact => cost
                .part(
                    "even/odd banks: odd-bank address incrementer, T0 select",
                    prim::half_adder() * k.saturating_sub(1) as f64 + prim::mux(b),
                )
                .part("bank select register", prim::register(1))
                .part("T0 stage register (weight 0)", prim::register(b))
                .part("output register", prim::register(b)),
            Filter::Linear => cost
                .part(
                    "even/odd banks: odd-bank address incrementer, output swap",
                    prim::half_adder() * k.saturating_sub(1) as f64 + prim::mux(b) * 2.0,
                )
                .part(
                    "weight and bank select registers (f, sel)",
                    prim::register(w + 1),
                )
                .part("d = T1 − T0", prim::subtractor(b + 1))
                .part("lerp multiplier d × f", prim::multiplier(b + 1, w))
                .part("stage registers (d·f, T0)", prim::register(b + w + 1 + b))
                .part("rounder + T0", prim::adder(b + w + 1) + prim::adder(b + 1))
                .part("output register", prim::register(b)),
        };
        cost.with_ram_bits(self.rom_bits())
    }

    fn widths(&self) -> Vec<Width> {
        let c = self.cfg;
        vec![
            Width {
                name: "in_bits",
                bits: c.in_bits,
            },
            Width {
                name: "table_log2",
                bits: c.table_log2,
            },
            Width {
                name: "entry_bits",
                bits: c.entry_bits,
            },
            Width {
                name: "weight_bits",
                bits: if c.filter == Filter::Linear {
                    c.weight_bits
                } else {
                    0
                },
            },
        ]
    }

    fn in_signals(&self, i: &SpecularLookupIn) -> Vec<Signal> {
        let n = self.cfg.in_bits;
        vec![Signal::new(
            "dot",
            n,
            i.code as i64 as u64 & ((1u64 << n) - 1),
        )]
    }

    fn out_signals(&self, o: &u32) -> Vec<Signal> {
        vec![Signal::new("spec", self.cfg.entry_bits, *o as u64)]
    }
}
