//! luminance_ram — the datapath both glare luminance modulators share (not a unit).
//!
//! A SHAPE RAM turns the primitive-frame position (u, v) into a distance d by bilinear
//! interpolation of a (2ᵏ+1)² sample grid over [−1, 1]², a FALLOFF RAM turns d into a
//! profile value p by linear interpolation of 2ᵐ+1 samples over [0, 1], and a gain
//! multiplier turns p into framebuffer luminance. `bloom_flare_modulator` uses one
//! falloff RAM, `halo_modulator` three (one ring per colour channel).
//!
//! Number formats (all runtime):
//! * u, v: s2.F two's complement (F = `coord_frac_bits`), value code / 2^F ∈ [−2, 2).
//! * shape entries and d: unorm of `shape_bits` (sb): code / (2^sb − 1).
//! * falloff entries and p: unorm of `falloff_bits` (fb): code / (2^fb − 1).
//! * gain: u(gi).(gf) (`gain_int_bits`, `gain_frac_bits`): code / 2^gf, luminance in
//!   framebuffer codes at p = 1.
//! * luminance out: unsigned `out_bits`, saturating.
//!
//! Unorm → binary-fraction conversions (d into the falloff address, p into the gain
//! multiplier) are done by BIT REPLICATION (free wiring): replicating an n-bit unorm
//! code c to W bits gives floor-ish(c/(2ⁿ−1)·2^W), error in [0, 2^−W] of full scale.

use crate::cost::{prim, Cells, Cost};
use crate::counters::Counters;
use crate::error::{check_finite, check_range, ConfigError};
use serde::{Deserialize, Serialize};

/// The widths of the shared modulator datapath (the fields of both modulator configs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct LumWidths {
    /// F of the s2.F coordinates u, v (2 ..= 16, default 14).
    pub coord_frac_bits: u32,
    /// k: the shape RAM has 2ᵏ cells per side, (2ᵏ+1)² samples (1 ..= 10, default 7).
    pub shape_log2: u32,
    /// Shape entry / d width, unorm (1 ..= 16, default 16).
    pub shape_bits: u32,
    /// m: the falloff RAM has 2ᵐ cells, 2ᵐ+1 samples (1 ..= 12, default 8).
    pub falloff_log2: u32,
    /// Falloff entry / p width, unorm (1 ..= 20, default 16).
    pub falloff_bits: u32,
    /// Interpolation weight width, both RAMs (1 ..= 12, default 8).
    pub weight_bits: u32,
    /// Gain integer bits (0 ..= 16, default 12).
    pub gain_int_bits: u32,
    /// Gain fraction bits (0 ..= 16, default 4); gain_int_bits + gain_frac_bits ≥ 1.
    pub gain_frac_bits: u32,
    /// Luminance output width (1 ..= 16, default 12).
    pub out_bits: u32,
    /// Radial-correction mode and its widths (default off: the plain datapath).
    #[serde(default)]
    pub radial: Radial,
}

/// Radial correction (docs/glare.md "Shape depth and radial correction"): the shape
/// RAM holds SIGNED entries e = sdf_n − κ·|(u, v)| (format s(ei).(sb−1−ei), two's
/// complement in the sb-bit entry), the datapath adds κ·|(u, v)| back with |(u, v)|
/// computed arithmetically (two squarers, an adder and a restoring digit-recurrence
/// square root) and clamps: d = clamp(e_interp + κ·|(u, v)|, 0, 1). κ is a
/// per-primitive register u(ki).(kf). A cone (point, circle) gives a constant e, so
/// the bilinear interpolation is exact at any depth.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Radial {
    /// The mode (default false).
    pub on: bool,
    /// rf: fraction bits of the square root |(u, v)| ∈ [0, √2] (2 ..= 16, default 16);
    /// rf + 1 digit rows.
    pub radius_frac_bits: u32,
    /// ki: κ integer bits (0 ..= 8, default 4).
    pub kappa_int_bits: u32,
    /// kf: κ fraction bits (0 ..= 16, default 12); ki + kf ≥ 1.
    pub kappa_frac_bits: u32,
    /// ei: integer bits of the signed shape entries, range [−2^ei, 2^ei)
    /// (0 ..= 4, ≤ sb − 1, default 1).
    pub entry_int_bits: u32,
}

impl Default for Radial {
    fn default() -> Self {
        Radial {
            on: false,
            radius_frac_bits: 16,
            kappa_int_bits: 4,
            kappa_frac_bits: 12,
            entry_int_bits: 1,
        }
    }
}

impl Default for LumWidths {
    fn default() -> Self {
        LumWidths {
            coord_frac_bits: 14,
            shape_log2: 7,
            shape_bits: 16,
            falloff_log2: 8,
            falloff_bits: 16,
            weight_bits: 8,
            gain_int_bits: 12,
            gain_frac_bits: 4,
            out_bits: 12,
            radial: Radial::default(),
        }
    }
}

impl LumWidths {
    /// Check every field; errors name `<unit>.<field>`.
    pub fn validate(&self, unit: &str) -> Result<(), ConfigError> {
        let f = |n: &str| format!("{unit}.{n}");
        check_range(&f("coord_frac_bits"), self.coord_frac_bits as u64, 2, 16)?;
        check_range(&f("shape_log2"), self.shape_log2 as u64, 1, 10)?;
        check_range(&f("shape_bits"), self.shape_bits as u64, 1, 16)?;
        check_range(&f("falloff_log2"), self.falloff_log2 as u64, 1, 12)?;
        check_range(&f("falloff_bits"), self.falloff_bits as u64, 1, 20)?;
        check_range(&f("weight_bits"), self.weight_bits as u64, 1, 12)?;
        check_range(&f("gain_int_bits"), self.gain_int_bits as u64, 0, 16)?;
        check_range(&f("gain_frac_bits"), self.gain_frac_bits as u64, 0, 16)?;
        if self.gain_int_bits + self.gain_frac_bits == 0 {
            return Err(ConfigError::invalid(
                &f("gain_frac_bits"),
                "gain_int_bits + gain_frac_bits must be at least 1",
            ));
        }
        check_range(&f("out_bits"), self.out_bits as u64, 1, 16)?;
        // The radial widths are checked only when the mode is on (off, they are unused).
        let r = &self.radial;
        if !r.on {
            return Ok(());
        }
        check_range(&f("radius_frac_bits"), r.radius_frac_bits as u64, 2, 16)?;
        check_range(&f("kappa_int_bits"), r.kappa_int_bits as u64, 0, 8)?;
        check_range(&f("kappa_frac_bits"), r.kappa_frac_bits as u64, 0, 16)?;
        if r.kappa_int_bits + r.kappa_frac_bits == 0 {
            return Err(ConfigError::invalid(
                &f("kappa_frac_bits"),
                "kappa_int_bits + kappa_frac_bits must be at least 1",
            ));
        }
        check_range(
            &f("entry_int_bits"),
            r.entry_int_bits as u64,
            0,
            4.min(self.shape_bits.saturating_sub(1)) as u64,
        )?;
        Ok(())
    }

    /// fe: fraction bits of the signed radial shape entries, sb − 1 − ei.
    pub fn entry_frac_bits(&self) -> u32 {
        self.shape_bits
            .saturating_sub(1)
            .saturating_sub(self.radial.entry_int_bits)
    }

    /// Largest κ code (ki + kf bits).
    pub fn kappa_max(&self) -> u32 {
        mask32(self.radial.kappa_int_bits + self.radial.kappa_frac_bits)
    }

    /// κ value of a code: code / 2^kf.
    pub fn kappa_value(&self, code: u32) -> f64 {
        (code & self.kappa_max()) as f64 / (self.radial.kappa_frac_bits as f64).exp2()
    }

    /// Quantise κ (round to nearest); NaN, ∞, negative or above the largest code is an
    /// error naming `<unit>.kappa`.
    pub fn kappa_from_f64(&self, unit: &str, k: f64) -> Result<u32, ConfigError> {
        let field = format!("{unit}.kappa");
        let x = check_finite(&field, k)?;
        let sc = (self.radial.kappa_frac_bits as f64).exp2();
        let code = (x * sc).round();
        let max = self.kappa_max() as f64;
        if !(0.0..=max).contains(&code) {
            return Err(ConfigError::out_of_range(&field, x, 0.0, max / sc));
        }
        Ok(code as u32)
    }

    /// Range of the signed radial entries: [−2^ei, 2^ei − 2^−fe].
    pub fn entry_range(&self) -> (f64, f64) {
        let ei = (self.radial.entry_int_bits as f64).exp2();
        (-ei, ei - (-(self.entry_frac_bits() as f64)).exp2())
    }

    /// Pipeline latency: [`LumWidths::LATENCY`] plain; with radial correction the
    /// distance leaves stage S + 3 instead of 3, S = ⌈(rf + 1)/2⌉ square-root stages
    /// (two digit rows a stage): squares | S × sqrt | κ multiply | add, clamp, convert.
    pub fn latency(&self) -> u32 {
        if self.radial.on {
            Self::LATENCY + self.sqrt_stages()
        } else {
            Self::LATENCY
        }
    }

    /// S = ⌈(rf + 1)/2⌉: square-root pipeline stages (two digit rows each).
    pub fn sqrt_stages(&self) -> u32 {
        (self.radial.radius_frac_bits + 2) / 2
    }

    /// Samples per side of the shape grid: 2ᵏ + 1.
    pub fn shape_side(&self) -> usize {
        (1usize << self.shape_log2) + 1
    }

    /// Shape RAM entries: (2ᵏ + 1)².
    pub fn shape_len(&self) -> usize {
        self.shape_side() * self.shape_side()
    }

    /// Falloff RAM entries: 2ᵐ + 1.
    pub fn falloff_len(&self) -> usize {
        (1usize << self.falloff_log2) + 1
    }

    /// Gain word width gi + gf.
    pub fn gain_bits(&self) -> u32 {
        self.gain_int_bits + self.gain_frac_bits
    }

    /// Largest gain code.
    pub fn gain_max(&self) -> u32 {
        mask32(self.gain_bits())
    }

    /// Width R that p is replicated to before the gain multiply: fb + gi, so the
    /// unorm → binary error (|·| ≤ 2^−R of full scale) times the gain (< 2^gi) stays
    /// ≤ 2^−fb output LSB. The multiplier operand is u1.R (R+1 bits: 1.0 exact).
    pub fn p_rep_bits(&self) -> u32 {
        self.falloff_bits + self.gain_int_bits
    }

    /// Quantise a gain triple (round to nearest); NaN, ∞, negative or above the largest
    /// code is an error naming `<unit>.gain[c]`.
    pub fn gain_from_f64(&self, unit: &str, g: [f64; 3]) -> Result<[u32; 3], ConfigError> {
        let mut out = [0u32; 3];
        let max = self.gain_max() as f64;
        for c in 0..3 {
            let field = format!("{unit}.gain[{c}]");
            let x = check_finite(&field, g[c])?;
            let code = (x * (self.gain_frac_bits as f64).exp2()).round();
            if !(0.0..=max).contains(&code) {
                return Err(ConfigError::out_of_range(
                    &field,
                    x,
                    0.0,
                    max / (self.gain_frac_bits as f64).exp2(),
                ));
            }
            out[c] = code as u32;
        }
        Ok(out)
    }

    /// Quantise a position to s2.F (round to nearest). Values outside [−2, 2) saturate
    /// to the range ends (harmless: |u| ≥ 1 clamps to the table edge anyway); NaN/∞ is
    /// an error naming `<unit>.coord`.
    pub fn coord_from_f64(&self, unit: &str, u: f64) -> Result<i32, ConfigError> {
        let x = check_finite(&format!("{unit}.coord"), u)?;
        let f = self.coord_frac_bits;
        let lo = -(1i64 << (f + 1));
        let hi = (1i64 << (f + 1)) - 1;
        let code = (x * (f as f64).exp2()).round().clamp(lo as f64, hi as f64);
        Ok(code as i32)
    }

    /// Clamp a coordinate to the grid and split it into (index, weight):
    /// returns (i, w, clamped) with i ∈ [0, 2ᵏ], w ∈ [0, 2^wb), w = 0 at i = 2ᵏ.
    #[inline]
    fn address(&self, u: i32) -> (usize, u32, bool) {
        let f = self.coord_frac_bits;
        let k = self.shape_log2;
        let wb = self.weight_bits;
        let u = sext(u, f + 2); // wire: s2.F
        let one = 1i64 << f;
        let clamped = u <= -one || u >= one;
        // a = u + 1 in units of 2^−F, clamped to [0, 2]: u(2).F → F+2 bits.
        let a = (u + one).clamp(0, 2 * one) as u64;
        // Position in cells = a / 2^s with s = F + 1 − k fraction bits.
        let s = f as i32 + 1 - k as i32;
        let (i, w) = if s <= 0 {
            ((a << (-s) as u32) as usize, 0u32) // a shift: no fraction left
        } else {
            let s = s as u32;
            let i = (a >> s) as usize;
            let frac = a & ((1u64 << s) - 1); // s bits
            let w = if s >= wb {
                frac >> (s - wb) // truncate to wb bits
            } else {
                frac << (wb - s)
            };
            (i, w as u32)
        };
        (i, w, clamped)
    }

    /// Bilinear interpolation of the 4 neighbouring samples of (u, v) before rounding:
    /// returns t = interpolated entry · 2^(2wb). Entries are unorm u(sb) codes, or with
    /// `signed` two's complement s(sb) codes (radial mode). Counts 4 table reads and a
    /// saturation per clamped axis (|u| ≥ 1 or |v| ≥ 1).
    #[inline]
    fn bilinear(&self, shape: &[u32], u: i32, v: i32, signed: bool, ctr: &mut Counters) -> i64 {
        let side = self.shape_side();
        let last = side - 1;
        let wb = self.weight_bits;
        let sb = self.shape_bits;
        let (i, wx, cu) = self.address(u);
        let (j, wy, cv) = self.address(v);
        ctr.saturations += cu as u64 + cv as u64;
        let i1 = (i + 1).min(last); // at i = 2ᵏ the weight is 0
        let j1 = (j + 1).min(last);
        // Four banks (even/odd in each axis) read in parallel.
        ctr.table_reads += 4;
        let rd = |x: u32| {
            if signed {
                sext(x as i32, sb) // wire: s(sb)
            } else {
                (x & mask32(sb)) as i64 // wire: u(sb)
            }
        };
        let s00 = rd(shape[j * side + i]);
        let s10 = rd(shape[j * side + i1]);
        let s01 = rd(shape[j1 * side + i]);
        let s11 = rd(shape[j1 * side + i1]);
        let (wx, wy) = (wx as i64, wy as i64);
        // Row lerps: s·2^wb + (s' − s)·wx: u(sb)·2^wb + s(sb+1) × u(wb) → u(sb+wb)
        // (signed entries: s(sb+wb)).
        let r0 = (s00 << wb) + (s10 - s00) * wx;
        let r1 = (s01 << wb) + (s11 - s01) * wx;
        // Column lerp: r0·2^wb + (r1 − r0)·wy: s(sb+wb+1) × u(wb) → u(sb+2wb)
        // (signed: s(sb+2wb)).
        (r0 << wb) + (r1 - r0) * wy
    }

    /// Shape lookup: bilinear interpolation of the 4 neighbouring samples of (u, v),
    /// rounded to a `shape_bits` d code. Counts 4 table reads and a saturation when
    /// |u| ≥ 1 or |v| ≥ 1 (one per clamped axis).
    pub fn shape_lookup(&self, shape: &[u32], u: i32, v: i32, ctr: &mut Counters) -> u32 {
        let wb = self.weight_bits;
        let t = self.bilinear(shape, u, v, false, ctr);
        // Round to sb bits: + half, >> 2wb → u(sb) (a convex combination: ≤ max code).
        ((t + (1i64 << (2 * wb - 1))) >> (2 * wb)) as u32
    }

    /// |(u, v)| of the clamped coordinates as u1.rf, rounded down (exact floor):
    /// q = u² + v² (u(2F+2), ≤ 2^(2F+1)), aligned to 2rf fraction bits, then a
    /// restoring square root of rf + 1 digit rows.
    pub fn radius(&self, u: i32, v: i32) -> u64 {
        let f = self.coord_frac_bits;
        let rf = self.radial.radius_frac_bits;
        let one = 1i64 << f;
        let uc = sext(u, f + 2).clamp(-one, one); // s1.F, |uc| ≤ 2^F: u(F+1) magnitude
        let vc = sext(v, f + 2).clamp(-one, one);
        // Two squarers u(F+1)² → u(2F+1) and an adder → u(2F+2).
        let q = (uc * uc + vc * vc) as u64;
        // Align to 2·rf fraction bits (wiring; the dropped bits cannot change the
        // floor of the root): u(2rf+2).
        let q = if rf >= f {
            q << (2 * (rf - f))
        } else {
            q >> (2 * (f - rf))
        };
        isqrt(q, rf + 1) // u1.rf
    }

    /// Radial-mode distance: d = clamp(e_interp + κ·|(u, v)|, 0, 1) as a unorm
    /// `shape_bits` code (rounded to nearest). `kappa` is the u(ki).(kf) register.
    /// Counts the shape reads and clamps of [`LumWidths::shape_lookup`], a saturation
    /// when the sum exceeds 1 and an underflow when it is below 0.
    pub fn radial_lookup(
        &self,
        shape: &[u32],
        kappa: u32,
        u: i32,
        v: i32,
        ctr: &mut Counters,
    ) -> u32 {
        let wb = self.weight_bits;
        let sb = self.shape_bits;
        let fe = self.entry_frac_bits();
        let rf = self.radial.radius_frac_bits;
        let kf = self.radial.kappa_frac_bits;
        // e_interp = t / 2^(fe+2wb): s(sb+2wb).
        let t = self.bilinear(shape, u, v, true, ctr);
        // κ·r: u(ki).(kf) × u1.rf → u(ki+1).(kf+rf).
        let kappa = (kappa & self.kappa_max()) as i64;
        let kr = kappa * self.radius(u, v) as i64;
        // Align both to W = max(fe+2wb, kf+rf) fraction bits (≤ 39) and add:
        // s(ei+1).(W) + u(ki+1).(W) → s(max(ei, ki)+3).(W) (≤ 51 bits).
        let w = (fe + 2 * wb).max(kf + rf);
        let x = (t << (w - fe - 2 * wb)) + (kr << (w - kf - rf));
        // Clamp to [0, 1] = [0, 2^W] (counted) → u1.(W).
        let top = 1i64 << w;
        let x = if x < 0 {
            ctr.underflows += 1;
            0
        } else if x > top {
            ctr.saturations += 1;
            top
        } else {
            x
        };
        // To a unorm code: round(x·(2^sb − 1)/2^W) = (x·2^sb − x + 2^(W−1)) >> W:
        // u(W+sb+1) subtract, round → u(sb) (x = 2^W gives exactly 2^sb − 1).
        (((x << sb) - x + (1i64 << (w - 1))) >> w) as u32
    }

    /// Falloff lookup: linear interpolation at the d code (replicated to m + wb bits:
    /// top m bits index, low wb bits weight), rounded to a `falloff_bits` p code.
    /// Counts 2 table reads (two banks).
    pub fn falloff_lookup(&self, falloff: &[u32], d: u32, ctr: &mut Counters) -> u32 {
        let m = self.falloff_log2;
        let wb = self.weight_bits;
        let d = d & mask32(self.shape_bits); // wire: u(sb)
        let addr = replicate(d as u64, self.shape_bits, m + wb); // u(m + wb)
        let j = (addr >> wb) as usize; // ≤ 2ᵐ − 1
        let w = (addr & ((1u64 << wb) - 1)) as i64; // u(wb)
        ctr.table_reads += 2;
        let f0 = falloff[j] as i64;
        let f1 = falloff[j + 1] as i64;
        // f0·2^wb + (f1 − f0)·w: s(fb+1) × u(wb) → u(fb+wb); round to u(fb).
        let t = (f0 << wb) + (f1 - f0) * w;
        ((t + (1i64 << (wb - 1))) >> wb) as u32
    }

    /// Gain multiply: lum = round(p · gain), saturating at 2^out_bits − 1 (counted).
    pub fn gain_mul(&self, p: u32, gain: u32, ctr: &mut Counters) -> u32 {
        let r = self.p_rep_bits();
        let gf = self.gain_frac_bits;
        let p = p & mask32(self.falloff_bits); // wire: u(fb)
        let g = (gain & self.gain_max()) as u128; // wire: u(gi).(gf)
                                                  // p as a binary fraction u1.R: the replicated code plus the code's top bit, so
                                                  // p = max gives exactly 1.0 (error |·| ≤ 2^−R of full scale either way).
                                                  // u(R) + u1 → u(R+1).
        let prep = replicate(p as u64, self.falloff_bits, r) as u128
            + (p >> (self.falloff_bits - 1)) as u128;
        // u1.R × u(gi).(gf) → u(gi+1).(R+gf) (≤ 69 bits); round off R + gf bits.
        let prod = prep * g;
        let sh = r + gf;
        let lum = (prod + (1u128 << (sh - 1))) >> sh; // u(gi+1)
        let max = mask32(self.out_bits) as u128;
        if lum > max {
            ctr.saturations += 1;
            max as u32
        } else {
            lum as u32
        }
    }

    /// Quantise an f64 table (entries in [0, 1], round to nearest) to unorm codes of
    /// `bits`. A wrong length names `<field>`; a bad entry names `<field>[<index>]`.
    pub fn quantise_table(
        field: &str,
        vals: &[f64],
        len: usize,
        bits: u32,
    ) -> Result<Vec<u32>, ConfigError> {
        if vals.len() != len {
            return Err(ConfigError::invalid(
                field,
                &format!("table has {} entries, the config needs {len}", vals.len()),
            ));
        }
        let max = mask32(bits) as f64;
        // NaN and ∞ fail the range test too: the first entry out of range is named
        // (formatted only for an error: a table load writes up to 2^20 entries), then
        // every entry is rounded in a plain loop.
        if let Some(i) = vals.iter().position(|x| !(0.0..=1.0).contains(x)) {
            let f = format!("{field}[{i}]");
            let x = check_finite(&f, vals[i])?;
            return Err(ConfigError::out_of_range(&f, x, 0.0, 1.0));
        }
        Ok(vals.iter().map(|&x| (x * max).round() as u32).collect())
    }

    /// Quantise the shape table for this config: unorm codes in [0, 1] (plain), or in
    /// radial mode signed s(ei).(fe) codes (round to nearest, stored as sb-bit two's
    /// complement) of entries in [−2^ei, 2^ei − 2^−fe]. A wrong length names
    /// `<field>`; a bad entry names `<field>[<index>]`.
    pub fn quantise_shape(&self, field: &str, vals: &[f64]) -> Result<Vec<u32>, ConfigError> {
        if !self.radial.on {
            return Self::quantise_table(field, vals, self.shape_len(), self.shape_bits);
        }
        if vals.len() != self.shape_len() {
            return Err(ConfigError::invalid(
                field,
                &format!(
                    "table has {} entries, the config needs {}",
                    vals.len(),
                    self.shape_len()
                ),
            ));
        }
        let (lo, hi) = self.entry_range();
        let sc = (self.entry_frac_bits() as f64).exp2();
        let m = mask32(self.shape_bits);
        if let Some(i) = vals.iter().position(|x| !(lo..=hi).contains(x)) {
            let f = format!("{field}[{i}]");
            let x = check_finite(&f, vals[i])?;
            return Err(ConfigError::out_of_range(&f, x, lo, hi));
        }
        Ok(vals
            .iter()
            .map(|&x| ((x * sc).round() as i64 as u32) & m)
            .collect())
    }

    /// Cost of the shared datapath with `rings` falloff RAMs (1: bloom/flare, 3: halo).
    /// Includes pipeline registers; RAM bits are added by [`LumWidths::ram_bits`].
    pub fn cost(&self, rings: u32) -> Cost {
        let f = self.coord_frac_bits;
        let k = self.shape_log2;
        let sb = self.shape_bits;
        let m = self.falloff_log2;
        let fb = self.falloff_bits;
        let wb = self.weight_bits;
        let gb = self.gain_bits();
        let ob = self.out_bits;
        let r = self.p_rep_bits();
        let n = rings as f64;
        let addr_bits = k + 1 + wb; // index u(k+1) and weight u(wb) per axis
        Cost::default()
            // Stage 1: address + shape RAM read.
            .part(
                "coordinate offset u+1, v+1 (2 × (F+2)-bit adders)",
                prim::adder(f + 2) * 2.0,
            )
            .part(
                "edge clamp (2 × compare + mux)",
                (prim::comparator(f + 2) * 2.0 + prim::mux(addr_bits)) * 2.0,
            )
            .part(
                "shape bank addresses i+1, j+1 (incrementers + end clamp)",
                (prim::half_adder() * k as f64 + prim::mux(k + 1)) * 2.0,
            )
            .part(
                "4-bank shape read crossbar (x and y swap)",
                prim::mux(sb) * 8.0,
            )
            // Stage 2–3: bilinear.
            .part(
                "bilinear row lerps (2 × sub, (sb+1)×wb mul, add)",
                (prim::subtractor(sb + 1) + prim::multiplier(sb + 1, wb) + prim::adder(sb + wb))
                    * 2.0,
            )
            .part(
                "bilinear column lerp (sub, (sb+wb+1)×wb mul, add, round)",
                prim::subtractor(sb + wb + 1)
                    + prim::multiplier(sb + wb + 1, wb)
                    + prim::adder(sb + 2 * wb)
                    + prim::half_adder() * sb as f64,
            )
            // Stage 4–5: falloff read + lerp, per ring.
            .part(
                "falloff bank address j+1 and 2-bank swap, per ring",
                (prim::half_adder() * m as f64 + prim::mux(fb) * 2.0) * n,
            )
            .part(
                "falloff lerp (sub, (fb+1)×wb mul, add, round), per ring",
                (prim::subtractor(fb + 1)
                    + prim::multiplier(fb + 1, wb)
                    + prim::adder(fb + wb)
                    + prim::half_adder() * fb as f64)
                    * n,
            )
            // Stage 6: gain multiply + round + saturate, per channel.
            .part(
                "gain multipliers 3 × ((R+1) × (gi+gf)), R = fb+gi",
                prim::multiplier(r + 1, gb) * 3.0,
            )
            .part(
                "p → u1.R incrementer (+ top bit, so p = 1.0 is exact)",
                prim::half_adder() * r as f64,
            )
            .part(
                "gain rounding 3 × (gi+1)-bit incrementer",
                prim::half_adder() * (3 * (self.gain_int_bits + 1)) as f64,
            )
            .part(
                "output saturation 3 × (overflow OR + clamp)",
                (Cells {
                    or2: (self.gain_int_bits + 1).saturating_sub(ob) as f64,
                    ..Cells::default()
                } + Cells {
                    or2: ob as f64,
                    ..Cells::default()
                }) * 3.0,
            )
            .part("pipeline registers", self.registers(rings))
            .merge_radial(self)
    }

    /// The radial-correction parts (empty when off), with their registers.
    fn radial_cost(&self) -> Vec<(&'static str, Cells)> {
        if !self.radial.on {
            return Vec::new();
        }
        let f = self.coord_frac_bits;
        let sb = self.shape_bits;
        let wb = self.weight_bits;
        let r = self.radial;
        let (rf, kb) = (r.radius_frac_bits, r.kappa_int_bits + r.kappa_frac_bits);
        let fe = self.entry_frac_bits();
        let w = (fe + 2 * wb).max(r.kappa_frac_bits + rf);
        let sum = w + r.entry_int_bits.max(r.kappa_int_bits) + 3;
        let st = self.sqrt_stages();
        let mut sqrt = Cells::default();
        for j in 1..=rf + 1 {
            sqrt = sqrt + prim::subtractor(j + 2) + prim::mux(j + 1);
        }
        // Registers: the gain triple and the waiting e for S more stages; q; the
        // square-root stages (remainder, root, radicand bits still to come); κ·r.
        let regs = 3 * self.gain_bits() * st
            + (sb + 2 * wb) * st
            + (2 * f + 2)
            + st * ((rf + 3) + (rf + 1) + (2 * rf + 2))
            + (kb + rf + 1)
            + kb; // the κ register itself
        vec![
            (
                "radial: |u|, |v| (2 × (F+2)-bit negate + select)",
                (prim::subtractor(f + 2) + prim::mux(f + 1)) * 2.0,
            ),
            (
                "radial: squarers 2 × (F+1)×(F+1) and u²+v² (2F+2)-bit adder",
                prim::multiplier(f + 1, f + 1) * 2.0 + prim::adder(2 * f + 2),
            ),
            (
                "radial: square root, rf+1 restoring rows ((j+2)-bit subtract + (j+1)-bit select)",
                sqrt,
            ),
            (
                "radial: κ multiplier (rf+1) × (ki+kf)",
                prim::multiplier(rf + 1, kb),
            ),
            ("radial: e + κ·r adder", prim::adder(sum)),
            (
                "radial: clamp to [0, 1] (sign/overflow OR + select)",
                Cells {
                    or2: (sum - w) as f64,
                    ..Cells::default()
                } + prim::mux(w + 1),
            ),
            (
                "radial: to unorm x·2^sb − x and round",
                prim::subtractor(w + sb + 1),
            ),
            (
                "radial: pipeline registers (S more stages, κ)",
                prim::register(regs),
            ),
        ]
    }

    fn registers(&self, rings: u32) -> Cells {
        let sb = self.shape_bits;
        let fb = self.falloff_bits;
        let wb = self.weight_bits;
        let gb = self.gain_bits();
        let n = rings;
        // The gain triple travels with the pixel through stages 1–5.
        let gain = 5 * 3 * gb;
        let s1 = 4 * sb + 2 * wb; // four samples + weights
        let s2 = 2 * (sb + wb) + wb; // two row values + wy
        let s3 = sb; // d
        let s4 = n * (2 * fb) + wb + sb; // falloff pairs + weight + d
        let s5 = n * fb + sb; // p code(s) + d
        let s6 = 3 * self.out_bits + sb; // output
        prim::register(gain + s1 + s2 + s3 + s4 + s5 + s6)
    }

    /// RAM bits: (2ᵏ+1)²·sb + rings·(2ᵐ+1)·fb.
    pub fn ram_bits(&self, rings: u32) -> u64 {
        self.shape_len() as u64 * self.shape_bits as u64
            + rings as u64 * self.falloff_len() as u64 * self.falloff_bits as u64
    }

    /// Entries written per primitive to load the tables.
    pub fn table_words(&self, rings: u32) -> u64 {
        self.shape_len() as u64 + rings as u64 * self.falloff_len() as u64
    }

    /// Pipeline latency of the modulators: address+shape read, bilinear x, bilinear
    /// y + round, falloff read, lerp + round, gain multiply + saturate.
    pub const LATENCY: u32 = 6;
}

/// The plain datapath (radial correction off) with its shifts and masks worked out
/// from the widths once, at construction: the batch kernels' fast form of
/// [`LumWidths::shape_lookup`], [`LumWidths::falloff_lookup`] and
/// [`LumWidths::gain_mul`], the same arithmetic bit for bit, on 64-bit words and
/// without the per-word width branches and replication loops. It applies when
/// * the cell position keeps a fraction: s = F + 1 − k ≥ 1;
/// * both replications need at most two copies: m + wb ≤ 2·sb, R = fb + gi ≤ 2·fb;
/// * the gain product and its rounding fit 64 bits: (R + 1) + (gi + gf) < 64.
///
/// Elsewhere [`PlainPath::new`] gives None and the modulators run the per-word kernel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PlainPath {
    /// 64 − (F + 2): the sign-extension shift of the s2.F wire.
    coord_sh: u32,
    /// 2^F, the coordinate 1.0.
    one: i64,
    /// s = F + 1 − k fraction bits of the cell position (≥ 1) and their mask.
    s: u32,
    frac_mask: u64,
    /// The wb-bit weight from the s-bit fraction: >> (s − wb) or << (wb − s).
    w_rsh: u32,
    w_lsh: u32,
    wb: u32,
    side: usize,
    last: usize,
    sb: u32,
    sb_mask: u32,
    /// m + wb: the falloff address the d code is replicated to.
    addr_bits: u32,
    wb_mask: u64,
    fb: u32,
    fb_mask: u32,
    /// R = fb + gi and the rounding shift R + gf.
    r: u32,
    gain_sh: u32,
    gain_mask: u32,
    out_max: u64,
}

impl PlainPath {
    /// The fast form for these widths, or None where it does not apply (radial mode,
    /// or a width combination outside the conditions above).
    pub fn new(w: &LumWidths) -> Option<Self> {
        let f = w.coord_frac_bits;
        let s = (f + 1).checked_sub(w.shape_log2).filter(|&s| s >= 1)?;
        let wb = w.weight_bits;
        let (sb, fb) = (w.shape_bits, w.falloff_bits);
        let addr_bits = w.falloff_log2 + wb;
        let r = w.p_rep_bits();
        let fits =
            !w.radial.on && addr_bits <= 2 * sb && r <= 2 * fb && (r + 1) + w.gain_bits() < 64;
        fits.then(|| PlainPath {
            coord_sh: 64 - (f + 2),
            one: 1i64 << f,
            s,
            frac_mask: (1u64 << s) - 1,
            w_rsh: s.saturating_sub(wb),
            w_lsh: wb.saturating_sub(s),
            wb,
            side: w.shape_side(),
            last: w.shape_side() - 1,
            sb,
            sb_mask: mask32(sb),
            addr_bits,
            wb_mask: (1u64 << wb) - 1,
            fb,
            fb_mask: mask32(fb),
            r,
            gain_sh: r + w.gain_frac_bits,
            gain_mask: w.gain_max(),
            out_max: mask32(w.out_bits) as u64,
        })
    }

    /// [`replicate`] for at most two copies (to ≤ 2·from): the code, then its top
    /// to − from bits.
    #[inline(always)]
    fn rep2(c: u64, from: u32, to: u32) -> u64 {
        if to <= from {
            c >> (from - to)
        } else {
            (c << (to - from)) | (c >> (2 * from - to))
        }
    }

    /// [`LumWidths::address`]: (index, weight u(wb), 1 if the axis clamped).
    #[inline(always)]
    fn address(&self, u: i32) -> (usize, i64, u64) {
        let u = ((u as i64) << self.coord_sh) >> self.coord_sh; // wire: s2.F
        let clamped = (u <= -self.one) | (u >= self.one);
        let a = (u + self.one).clamp(0, 2 * self.one) as u64; // u(2).F
        let i = (a >> self.s) as usize;
        let w = ((a & self.frac_mask) >> self.w_rsh) << self.w_lsh;
        (i, w as i64, clamped as u64)
    }

    /// [`LumWidths::shape_lookup`]; adds the clamped axes to `sat` (the 4 reads are
    /// the caller's to count).
    #[inline(always)]
    pub fn shape_lookup(&self, shape: &[u32], u: i32, v: i32, sat: &mut u64) -> u32 {
        let (i, wx, cu) = self.address(u);
        let (j, wy, cv) = self.address(v);
        *sat += cu + cv;
        let i1 = (i + 1).min(self.last);
        let j1 = (j + 1).min(self.last);
        let rd = |k: usize| (shape[k] & self.sb_mask) as i64; // wire: u(sb)
        let (r0, r1) = (j * self.side, j1 * self.side);
        let (s00, s10, s01, s11) = (rd(r0 + i), rd(r0 + i1), rd(r1 + i), rd(r1 + i1));
        let wb = self.wb;
        // Row lerps u(sb+wb), column lerp u(sb+2wb), round to u(sb).
        let a = (s00 << wb) + (s10 - s00) * wx;
        let b = (s01 << wb) + (s11 - s01) * wx;
        let t = (a << wb) + (b - a) * wy;
        ((t + (1i64 << (2 * wb - 1))) >> (2 * wb)) as u32
    }

    /// [`LumWidths::falloff_lookup`] (the 2 reads are the caller's to count).
    #[inline(always)]
    pub fn falloff_lookup(&self, falloff: &[u32], d: u32) -> u32 {
        let d = (d & self.sb_mask) as u64; // wire: u(sb)
        let addr = Self::rep2(d, self.sb, self.addr_bits); // u(m + wb)
        let j = (addr >> self.wb) as usize;
        let w = (addr & self.wb_mask) as i64;
        let (f0, f1) = (falloff[j] as i64, falloff[j + 1] as i64);
        let t = (f0 << self.wb) + (f1 - f0) * w; // u(fb+wb)
        ((t + (1i64 << (self.wb - 1))) >> self.wb) as u32
    }

    /// p as the gain multiplier's u1.R operand (replicated code plus its top bit).
    #[inline(always)]
    pub fn p_operand(&self, p: u32) -> u64 {
        let p = p & self.fb_mask; // wire: u(fb)
        Self::rep2(p as u64, self.fb, self.r) + (p >> (self.fb - 1)) as u64
    }

    /// [`LumWidths::gain_mul`] on the u1.R operand; a saturation adds 1 to `sat`.
    #[inline(always)]
    pub fn gain_mul(&self, prep: u64, gain: u32, sat: &mut u64) -> u32 {
        // u1.R × u(gi).(gf) → u(gi+1).(R+gf) < 2^63; round off R + gf bits.
        let prod = prep * (gain & self.gain_mask) as u64;
        let lum = (prod + (1u64 << (self.gain_sh - 1))) >> self.gain_sh;
        let over = lum > self.out_max;
        *sat += over as u64;
        lum.min(self.out_max) as u32
    }
}

trait MergeRadial {
    fn merge_radial(self, w: &LumWidths) -> Self;
}

impl MergeRadial for Cost {
    fn merge_radial(self, w: &LumWidths) -> Self {
        w.radial_cost()
            .into_iter()
            .fold(self, |c, (name, cells)| c.part(name, cells))
    }
}

/// All-ones of `bits` (0 ..= 32).
#[inline]
pub fn mask32(bits: u32) -> u32 {
    if bits >= 32 {
        u32::MAX
    } else {
        (1u32 << bits) - 1
    }
}

/// ⌊√q⌋ by the restoring digit recurrence, `digits` result bits (q < 4^digits): one
/// row per result bit, each a trial subtract of (4R + next two radicand bits) −
/// (4Q + 1) and a select — the hardware's rows, bit for bit.
#[inline]
pub fn isqrt(q: u64, digits: u32) -> u64 {
    let mut rem = 0u64; // partial remainder: ≤ 2Q, digits + 1 bits
    let mut root = 0u64;
    for i in (0..digits).rev() {
        let pair = (q >> (2 * i)) & 3;
        rem = (rem << 2) | pair;
        let trial = (root << 2) | 1;
        root <<= 1;
        if rem >= trial {
            rem -= trial;
            root |= 1;
        }
    }
    root
}

/// Sign-extend the low `w` bits of `x` (1 ≤ w ≤ 32).
#[inline]
pub fn sext(x: i32, w: u32) -> i64 {
    let sh = 64 - w;
    ((x as i64) << sh) >> sh
}

/// Replicate an n-bit unorm code to `to` bits (wiring only): the first `to` bits of
/// the repeating binary expansion of c / (2ⁿ − 1). Error in [0, 2^−to] of full scale.
#[inline]
pub fn replicate(c: u64, from: u32, to: u32) -> u64 {
    let c = c & ((1u64 << from) - 1);
    let mut out = 0u64;
    let mut filled = 0u32;
    while filled < to {
        let take = from.min(to - filled);
        out = (out << take) | (c >> (from - take));
        filled += take;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn isqrt_is_the_floor_of_the_root() {
        for q in 0..70_000u64 {
            let r = isqrt(q, 9);
            assert!(r * r <= q && (r + 1) * (r + 1) > q, "{q}");
        }
        for q in [(1u64 << 34) - 1, 1u64 << 33, 12_345_678_901] {
            let r = isqrt(q, 17);
            assert!(r * r <= q && (r + 1) * (r + 1) > q, "{q}");
        }
    }

    #[test]
    fn replication_error_is_within_one_lsb_of_the_target() {
        for from in 1..=8u32 {
            for to in 1..=20u32 {
                for c in 0..(1u64 << from) {
                    let x = c as f64 / ((1u64 << from) - 1) as f64;
                    let r = replicate(c, from, to) as f64 / (to as f64).exp2();
                    let e = x - r;
                    assert!(
                        e >= -1e-12 && e <= (-(to as f64)).exp2() + 1e-12,
                        "{c} {from} {to}"
                    );
                }
            }
        }
    }
}

/// One pixel into a modulator: its position in the primitive frame (s2.F codes) and
/// the primitive's RGB gain (u(gi).(gf) codes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct LumIn {
    /// Horizontal position in the primitive frame, an s2.F code (F = `coord_frac_bits`);
    /// clamped to [−1, 1].
    pub u: i32,
    /// Vertical position in the primitive frame, an s2.F code; clamped to [−1, 1].
    pub v: i32,
    /// The primitive's RGB gain, u(gi).(gf) codes (gain_int_bits, gain_frac_bits).
    pub gain: [u32; 3],
}

/// One pixel out of a modulator: the shape distance d (unorm `shape_bits` code) and
/// the RGB luminance in framebuffer codes (`out_bits`, saturated).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct LumOut {
    /// The interpolated shape distance d, a unorm code of `shape_bits` bits.
    pub d: u32,
    /// RGB luminance in framebuffer codes of `out_bits` bits, saturated.
    pub lum: [u32; 3],
}
