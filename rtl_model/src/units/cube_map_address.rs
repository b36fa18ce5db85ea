//! cube_map_address — cube-map face selection and face texel coordinates (GeForce3's
//! cube-map addressing, ARB_texture_cube_map / OpenGL Table 3.23) for the envmap's
//! 2D-slice path: the `reflection_vector` unit's three texel-space words
//! c_i = (t_i + 1)/2 · s (t = r·λ) in, one face of a cube map and its 2D texel
//! coordinates (the 2D `texture_sampler`'s s(I).F words) out.
//!
//! The direction is d_i = c_i − s/2 (a cube map needs only the direction, so λ
//! cancels). Major axis = the largest |d_i|; face, sc, tc from the OpenGL table
//! (face index 0 ..= 5 = +x, −x, +y, −y, +z, −z):
//!
//! | major | face | sc | tc |
//! |---|---|---|---|
//! | +x | 0 | −d_z | −d_y |
//! | −x | 1 | +d_z | −d_y |
//! | +y | 2 | +d_x | +d_z |
//! | −y | 3 | +d_x | −d_z |
//! | +z | 4 | +d_x | −d_y |
//! | −z | 5 | −d_x | −d_y |
//!
//! and (s, t) = ((sc/|ma| + 1)/2, (tc/|ma| + 1)/2) · F texels on a face of side
//! F = 2^face_log2. Ties (the spec leaves them to the implementation; the rule must be
//! deterministic): x wins if |d_x| ≥ |d_y| and |d_x| ≥ |d_z|, else y if |d_y| ≥ |d_z|,
//! else z. d = 0 (λ = 0 or a degenerate r): face 0 (+x) at the face centre (F/2, F/2),
//! counted in `underflows`, flagged `zero`.
//!
//! Datapath (Wi = in_int_bits + in_frac_bits = the reflection unit's output word,
//! Fi = in_frac_bits, A = rcp_addr_bits, R = rcp_bits, N = newton_frac_bits,
//! Fo = coord_frac_bits, Io = coord_int_bits, G = face_log2 − 1 + Fo). Integers only.
//! 1. D_i = 2·c_i − s·2^Fi (= 2·d_i in units of 2^−Fi texels; the factor 2 keeps
//!    s/2 exact for s = 1): s(Wi) → s(Wi+2). |D_i| → u(Wi+1).
//! 2. Major axis: 3 magnitude comparators (|D_x| ≥ |D_y|, |D_x| ≥ |D_z|,
//!    |D_y| ≥ |D_z|), the tie rule above; face = 2·axis + sign; sc, tc, |ma| by 3:1
//!    muxes and conditional negations (s(Wi+2), u(Wi+1)).
//! 3. Reciprocal of |ma|: p = position of the leading one (LZC), |ma| = 2^p·m,
//!    m ∈ [1, 2). ROM address = the A bits below the leading one (zero-filled when
//!    p < A); 2^A entries of R bits, entry j = min(round(2^R / c_j), 2^R − 1) (u0.R),
//!    c_j = 1 + (j + ½)/2^A the midpoint of the entry's m interval (a ROM image
//!    computed from f64 at build time). Optional Newton step y' = y·(2 − m·y) in N
//!    fraction bits: m_N = m truncated to u1.N; q = m_N·y (u1.N × u0.R → u1.(N+R),
//!    rounded to u1.N); d = 2 − q (u1.N); y' = y·d (u0.R × u1.N → u1.(R+N), rounded to
//!    u1.N). Fy = N with Newton, R without.
//! 4. sc·y, tc·y: s(Wi+2) × u1.Fy → s(Wi+Fy+3); shifted right by p + Fy − G and
//!    rounded to nearest (ties up, the sampler helper's rounding) → (sc/|ma|)·2^G;
//!    then 2^G is added (the "+ 1", a constant at a fixed position) → s·2^Fo texels, saturated into
//!    the s(Io).Fo word (counted): the face coordinates `st`.
//! 5. The stacked word for one F × 6F texture (faces stacked in t, face f in rows
//!    f·F ..< (f+1)·F): each face coordinate is clamped to the texel-centre range
//!    [½, F − ½]·2^Fo — with bilinear filtering this IS clamp-to-edge on the face (the
//!    same texels and weights), so one 2D sampler never filters across a face edge, as
//!    GeForce3 did not — and t gets face·F·2^Fo added (a concatenation: t < F·2^Fo),
//!    saturated into the word (counted; never at a valid sampler config).
//!
//! Timing: II 1; latency 7 without Newton (D and |D| | compare + select | LZC +
//! normalise | ROM | sc·y, tc·y | shift, round, + 1 | clamp, stack, output), 10 with
//! (m·y | 2 − q | y·d after the ROM).
//! Counters: `table_reads` (one ROM read per non-zero direction), `underflows` (zero
//! directions), `saturations` (output-word clamps of `st` and of the stacked word,
//! and guard clamps inside the Newton step that cannot fire on a valid config).

use crate::cost::{prim, Cells, Cost};
use crate::counters::Counters;
use crate::error::{check_finite, check_range, ConfigError};
use crate::fixed_point::{round_shift, Quant};
use crate::packed_rom::PackedRom;
use crate::unit::{Signal, Timing, Unit, Width};
use crate::units::texture_sampler::TextureSamplerIn;
use crate::wire::{bits_for, saturate_signed as sat_signed, sign_extend as sext};
use serde::{Deserialize, Serialize};

/// The plain config (serde-friendly); [`CubeMapAddressConfig::build`] validates it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct CubeMapAddressConfig {
    /// Integer bits (with sign) of the input words (the reflection unit's
    /// `coord_int_bits`), 1 ..= 24, in_int + in_frac ≤ 32.
    pub in_int_bits: u32,
    /// Fraction bits of the input words (the reflection unit's `coord_frac_bits`),
    /// 0 ..= 16.
    pub in_frac_bits: u32,
    /// log2 of the 3D map side s the input words refer to (centre s/2), 0 ..= 12.
    pub side_log2: u32,
    /// Reciprocal ROM address bits A (2^A entries), 1 ..= 12.
    pub rcp_addr_bits: u32,
    /// Reciprocal ROM entry bits R (u0.R), 2 ..= 24.
    pub rcp_bits: u32,
    /// One Newton–Raphson step after the table.
    pub newton: bool,
    /// Fraction bits N of the Newton datapath, 4 ..= 30 (unused without Newton).
    pub newton_frac_bits: u32,
    /// log2 of the face side F, 1 ..= 12.
    pub face_log2: u32,
    /// Integer bits (with sign) of the output words, 2 ..= 32 − coord_frac_bits.
    pub coord_int_bits: u32,
    /// Sub-texel fraction bits of the output words, 1 ..= 16 (≥ 1: the texel-centre
    /// clamp needs ½ texel).
    pub coord_frac_bits: u32,
}

impl Default for CubeMapAddressConfig {
    fn default() -> Self {
        Self::geforce3()
    }
}

impl CubeMapAddressConfig {
    /// GeForce3-era defaults (datasheet in docs/units.md): the reflection unit's s16.8
    /// words of a 128³ map in; a 64 × 8-bit reciprocal ROM and one Newton step at 16
    /// fraction bits; faces of 256 × 256 (F = 2s); the 2D sampler's s16.8 words out.
    pub fn geforce3() -> Self {
        CubeMapAddressConfig {
            in_int_bits: 16,
            in_frac_bits: 8,
            side_log2: 7,
            rcp_addr_bits: 6,
            rcp_bits: 8,
            newton: true,
            newton_frac_bits: 16,
            face_log2: 8,
            coord_int_bits: 16,
            coord_frac_bits: 8,
        }
    }

    /// Validate and build the unit; the same as [`CubeMapAddress::new`], errors name
    /// `cube_map_address.<field>`.
    pub fn build(&self) -> Result<CubeMapAddress, ConfigError> {
        CubeMapAddress::new(*self)
    }
}

/// One pixel: the reflection unit's three s(in_int).(in_frac) texel-space words
/// (masked and sign-extended to their wires).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct CubeMapAddressIn {
    /// The direction (x, y, z) in texel space of a map of side s (centre s/2), raw
    /// s(in_int_bits).(in_frac_bits) codes.
    pub coord: [i32; 3],
}

/// The face, its texel coordinates and the stacked sampler word.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct CubeMapAddressOut {
    /// 0 ..= 5: +x, −x, +y, −y, +z, −z.
    pub face: u8,
    /// (s, t) on the face in texels, s(Io).Fo words (not clamped to the face).
    pub st: [i32; 2],
    /// The 2D sampler's word for the F × 6F stacked texture: (s, t + face·F), each
    /// face coordinate clamped to the texel-centre range [½, F − ½]; `coord[2]` = 0.
    pub coord: [i32; 3],
    /// The direction was zero (face 0, centre).
    pub zero: bool,
}

impl CubeMapAddressOut {
    /// The 2D sampler's input word (stacked layout; the sampler must be
    /// `geforce_2d(F, 6F)` with this unit's coordinate format, clamp to edge).
    pub fn sampler_in(&self) -> TextureSamplerIn {
        TextureSamplerIn { coord: self.coord }
    }
}

/// One reciprocal result: |ma| = 2^p·m, y ≈ 1/m as u1.`frac` raw.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rcp {
    /// 1/m as a raw fixed-point code with `frac` fraction bits: u0.R from the ROM, u1.N
    /// after the Newton step.
    pub y: u64,
    /// Fraction bits of `y`: `rcp_bits` (R) without Newton, `newton_frac_bits` (N) with it.
    pub frac: u32,
    /// Exponent p of the major axis: |ma| = 2^p·m, m ∈ [1, 2) (a leading-zero count).
    pub p: u32,
}

/// The validated unit: its config and the reciprocal ROM image.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CubeMapAddress {
    cfg: CubeMapAddressConfig,
    rom: PackedRom,
}

/// ROM entry j for A address bits and R entry bits: c = 1 + (j + ½)/2^A, the
/// midpoint of address j's interval of m ∈ [1, 2); entry = min(round(2^R/c), 2^R − 1),
/// u0.R. The same reciprocal table as `projective_texcoord`'s, so it is that unit's
/// integer-only generator (bit-exact; it equals the f64 form over every A ≤ 12, R ≤ 24).
pub fn rcp_rom_entry(j: u64, addr_bits: u32, entry_bits: u32) -> u64 {
    crate::units::projective_texcoord::recip_rom_entry(j, addr_bits, entry_bits)
}

impl CubeMapAddress {
    /// Validate a config and build the ROM; errors name `cube_map_address.<field>`.
    pub fn new(cfg: CubeMapAddressConfig) -> Result<Self, ConfigError> {
        let f = |n: &str| format!("cube_map_address.{n}");
        check_range(&f("in_int_bits"), cfg.in_int_bits as u64, 1, 24)?;
        check_range(&f("in_frac_bits"), cfg.in_frac_bits as u64, 0, 16)?;
        check_range(
            &f("in_frac_bits"),
            (cfg.in_int_bits + cfg.in_frac_bits) as u64,
            1,
            32,
        )?;
        check_range(&f("side_log2"), cfg.side_log2 as u64, 0, 12)?;
        check_range(&f("rcp_addr_bits"), cfg.rcp_addr_bits as u64, 1, 12)?;
        check_range(&f("rcp_bits"), cfg.rcp_bits as u64, 2, 24)?;
        check_range(&f("newton_frac_bits"), cfg.newton_frac_bits as u64, 4, 30)?;
        check_range(&f("face_log2"), cfg.face_log2 as u64, 1, 12)?;
        check_range(&f("coord_frac_bits"), cfg.coord_frac_bits as u64, 1, 16)?;
        check_range(
            &f("coord_int_bits"),
            cfg.coord_int_bits as u64,
            2,
            (32 - cfg.coord_frac_bits) as u64,
        )?;
        let (a, r) = (cfg.rcp_addr_bits, cfg.rcp_bits);
        let words: Vec<u64> = (0..1u64 << a).map(|j| rcp_rom_entry(j, a, r)).collect();
        Ok(CubeMapAddress {
            cfg,
            rom: PackedRom::new(r, &words),
        })
    }

    /// GeForce3 defaults (see [`CubeMapAddressConfig::geforce3`]).
    pub fn geforce3() -> Self {
        match Self::new(CubeMapAddressConfig::geforce3()) {
            Ok(u) => u,
            Err(e) => unreachable!("default config invalid: {e}"),
        }
    }

    /// Alias of [`Self::geforce3`].
    pub fn geforce() -> Self {
        Self::geforce3()
    }

    /// The config the unit was built from.
    pub fn config(&self) -> CubeMapAddressConfig {
        self.cfg
    }

    /// Input word width Wi.
    pub fn in_bits(&self) -> u32 {
        self.cfg.in_int_bits + self.cfg.in_frac_bits
    }

    /// Output word width Io + Fo.
    pub fn out_bits(&self) -> u32 {
        self.cfg.coord_int_bits + self.cfg.coord_frac_bits
    }

    /// Face side F = 2^face_log2.
    pub fn face_side(&self) -> u32 {
        1 << self.cfg.face_log2
    }

    /// Fraction bits of the final 1/m: N with Newton, R without.
    pub fn rcp_frac_bits(&self) -> u32 {
        if self.cfg.newton {
            self.cfg.newton_frac_bits
        } else {
            self.cfg.rcp_bits
        }
    }

    /// ROM bits (one reciprocal ROM).
    pub fn rom_bits(&self) -> u64 {
        self.rom.ram_bits()
    }

    /// The ROM entries, address order.
    pub fn rom_words(&self) -> Vec<u64> {
        self.rom.words()
    }

    /// Output raw code → texels.
    pub fn coord_to_f64(&self, raw: i32) -> f64 {
        raw as f64 * (-(self.cfg.coord_frac_bits as f64)).exp2()
    }

    /// Host helper: quantise f64 texel-space coordinates (the reflection unit's
    /// meaning: c = (t + 1)/2 · s texels) to input words: round to nearest (ties up),
    /// saturating (counted). NaN/±∞ is an error naming `cube_map_address.coord`.
    pub fn quantise_in(
        &self,
        c: [f64; 3],
        ctr: &mut Counters,
    ) -> Result<CubeMapAddressIn, ConfigError> {
        let w = self.in_bits();
        let hi = (1i128 << (w - 1)) - 1;
        let lo = -(1i128 << (w - 1));
        let scale = (self.cfg.in_frac_bits as f64).exp2();
        let mut out = CubeMapAddressIn::default();
        for (o, &x) in out.coord.iter_mut().zip(&c) {
            let x = check_finite("cube_map_address.coord", x)?;
            let v = (x * scale + 0.5).floor().clamp(-1e30, 1e30) as i128;
            let v = if v > hi || v < lo {
                ctr.saturations += 1;
                v.clamp(lo, hi)
            } else {
                v
            };
            *o = v as i32;
        }
        Ok(out)
    }

    /// 1/m of |ma| (> 0): ROM (+ Newton). Counts the ROM read.
    pub fn rcp(&self, ma: u64, ctr: &mut Counters) -> Rcp {
        let a = self.cfg.rcp_addr_bits;
        let r = self.cfg.rcp_bits;
        let ma = ma.max(1);
        let p = 63 - ma.leading_zeros(); // LZC: |ma| = 2^p·m
        let frac = ma & ((1u64 << p) - 1); // the p bits below the leading one: m − 1 in u0.p
                                           // The A bits below the leading one (zero-filled when p < A).
        let addr = round_shift(frac as i128, p as i32 - a as i32, Quant::Trn) as u64;
        ctr.table_reads += 1;
        let y0 = self.rom.read(addr as usize) as u64; // u0.R
        if !self.cfg.newton {
            return Rcp { y: y0, frac: r, p };
        }
        let n = self.cfg.newton_frac_bits;
        // m_N = m truncated to u1.N: (2^p + frac) as u1.p → u1.N.
        let m_n = round_shift(ma as i128, p as i32 - n as i32, Quant::Trn); // u1.N
        let q = round_shift(m_n * y0 as i128, r as i32, Quant::Rnd); // u1.N × u0.R → u1.(N+R) → u1.N
        let two = 2i128 << n;
        let d = two - q; // u1.N (q ∈ (0, 2) on a converging table)
        let d_max = (2i128 << n) - 1;
        let d = if !(0..=d_max).contains(&d) {
            ctr.saturations += 1; // guard: cannot fire while |m·y0 − 1| < 1
            d.clamp(0, d_max)
        } else {
            d
        };
        let y1 = round_shift(y0 as i128 * d, r as i32, Quant::Rnd); // u0.R × u1.N → u1.(R+N) → u1.N
        let y_max = (2i128 << n) - 1;
        let y1 = if y1 > y_max {
            ctr.saturations += 1; // guard: y1 ≤ (1 + e1)/m < 2
            y_max
        } else {
            y1
        };
        Rcp {
            y: y1 as u64,
            frac: n,
            p,
        }
    }

    /// The whole datapath on one pixel.
    pub fn address(&self, input: &CubeMapAddressIn, ctr: &mut Counters) -> CubeMapAddressOut {
        let c = self.cfg;
        let wi = self.in_bits();
        let fi = c.in_frac_bits;
        // 1. D_i = 2·c_i − s·2^Fi: s(Wi) → s(Wi+2).
        let half_s2 = 1i64 << (c.side_log2 + fi); // s·2^Fi
        let dv = input.coord.map(|x| 2 * sext(x as i64, wi) - half_s2); // s(Wi+2)
        let mag = dv.map(|x| x.unsigned_abs()); // u(Wi+1)
        let fo = c.coord_frac_bits;
        let g = c.face_log2 - 1 + fo; // (s/F)·2^Fo·… position of the "+ 1": F/2·2^Fo = 2^G
        let ow = self.out_bits();
        let f_raw = 1i128 << (c.face_log2 + fo); // F·2^Fo
        let lo = 1i128 << (fo - 1); // ½ texel
        let hi = f_raw - lo; // F − ½ texels
        if mag == [0; 3] {
            ctr.underflows += 1;
            let centre = sat_signed(1i128 << g, ow, ctr) as i32;
            let t_st = sat_signed((1i128 << g).clamp(lo, hi), ow, ctr) as i32;
            return CubeMapAddressOut {
                face: 0,
                st: [centre, centre],
                coord: [t_st, t_st, 0],
                zero: true,
            };
        }
        // 2. Major axis (tie rule: x, then y, then z), face, sc, tc.
        let axis = if mag[0] >= mag[1] && mag[0] >= mag[2] {
            0
        } else if mag[1] >= mag[2] {
            1
        } else {
            2
        };
        let neg = dv[axis] < 0;
        let face = (2 * axis + usize::from(neg)) as u8;
        let [x, y, z] = dv;
        let (sc, tc) = match face {
            0 => (-z, -y),
            1 => (z, -y),
            2 => (x, z),
            3 => (x, -z),
            4 => (x, -y),
            _ => (-x, -y),
        }; // s(Wi+2) each
           // 3. 1/|ma|.
        let rc = self.rcp(mag[axis], ctr);
        // 4. sc·y: s(Wi+2) × u1.Fy → s(Wi+Fy+3); >> (p + Fy − G), rounded; + 2^G.
        let shift = rc.p as i32 + rc.frac as i32 - g as i32;
        let face_coord = |v: i64| -> i128 {
            round_shift(v as i128 * rc.y as i128, shift, Quant::Rnd) + (1i128 << g)
        };
        let u = [face_coord(sc), face_coord(tc)];
        let st = [
            sat_signed(u[0], ow, ctr) as i32,
            sat_signed(u[1], ow, ctr) as i32,
        ];
        // 5. Clamp to the texel-centre range (= clamp to edge), stack the faces in t.
        let s_c = u[0].clamp(lo, hi);
        let t_c = u[1].clamp(lo, hi) + face as i128 * f_raw;
        CubeMapAddressOut {
            face,
            st,
            coord: [
                sat_signed(s_c, ow, ctr) as i32,
                sat_signed(t_c, ow, ctr) as i32,
                0,
            ],
            zero: false,
        }
    }
}

impl Unit for CubeMapAddress {
    type In = CubeMapAddressIn;
    type Out = CubeMapAddressOut;
    type State = ();

    fn name(&self) -> &'static str {
        "cube_map_address"
    }

    fn kernel(
        &self,
        _: &mut (),
        input: &CubeMapAddressIn,
        ctr: &mut Counters,
    ) -> CubeMapAddressOut {
        self.address(input, ctr)
    }

    fn timing(&self) -> Timing {
        // D, |D| | compare + select | LZC + normalise | ROM | [m·y | 2 − q | y·d] |
        // sc·y, tc·y | shift, round, + 1 | clamp, stack, output.
        Timing {
            latency: 7 + if self.cfg.newton { 3 } else { 0 },
            ii: 1,
        }
    }

    fn cost(&self) -> Cost {
        let c = self.cfg;
        let wi = self.in_bits();
        let (a, r, n) = (c.rcp_addr_bits, c.rcp_bits, c.newton_frac_bits);
        let dw = wi + 2; // D: s(Wi+2)
        let mw = wi + 1; // |D|: u(Wi+1)
        let pb = bits_for(mw as u64 - 1); // p ≤ Wi
        let fy = self.rcp_frac_bits();
        let ow = self.out_bits();
        let fo = c.coord_frac_bits;
        let pw = dw + fy + 1; // sc·y product width
                              // Carried down the pipe after the select: sc, tc, face (3), zero flag.
        let carry = 2 * dw + 4;
        let mut cost = Cost::default()
            .part("input registers (3 words)", prim::register(3 * wi))
            .part(
                "D = 2c − s·2^Fi (3 constant subtracts)",
                prim::adder(dw) * 3.0,
            )
            .part(
                "|D| (3 conditional negates)",
                (Cells {
                    xor2: mw as f64,
                    ..Cells::default()
                } + prim::half_adder() * mw as f64)
                    * 3.0,
            )
            .part("stage registers (D, |D|)", prim::register(3 * dw + 3 * mw))
            .part(
                "major axis: 3 magnitude comparators",
                prim::comparator(mw) * 3.0,
            )
            .part(
                "zero detect (OR tree)",
                Cells {
                    or2: (3 * mw) as f64,
                    ..Cells::default()
                },
            )
            .part(
                "select |ma| (3:1), sc, tc (3:1 each)",
                prim::mux_k(mw, 3) + prim::mux_k(dw, 3) * 2.0,
            )
            .part(
                "sc, tc conditional negates (2)",
                (Cells {
                    xor2: dw as f64,
                    ..Cells::default()
                } + prim::half_adder() * dw as f64)
                    * 2.0,
            )
            .part(
                "stage registers (|ma|, sc, tc, face, zero)",
                prim::register(mw + carry),
            )
            .part(
                "leading-zero counter (|ma|)",
                prim::leading_zero_counter(mw),
            )
            .part("normalising shifter (address, m_N)", prim::shifter(mw, pb))
            .part(
                "stage registers (address, m_N, p, carry)",
                prim::register(a + if c.newton { n + 1 } else { 0 } + pb + carry),
            )
            .part(
                "ROM output registers (y0, m_N, p, carry)",
                prim::register(r + if c.newton { n + 1 } else { 0 } + pb + carry),
            );
        if c.newton {
            cost = cost
                .part("Newton: m_N·y0 multiplier", prim::multiplier(n + 1, r))
                .part("Newton: q rounder", prim::adder(n + 1))
                .part(
                    "Newton: registers (q, y0, p, carry)",
                    prim::register((n + 1) + r + pb + carry),
                )
                .part("Newton: d = 2 − q", prim::subtractor(n + 2))
                .part(
                    "Newton: registers (d, y0, p, carry)",
                    prim::register((n + 1) + r + pb + carry),
                )
                .part("Newton: y0·d multiplier", prim::multiplier(r, n + 1))
                .part("Newton: y' rounder", prim::adder(n + 1))
                .part(
                    "Newton: registers (y', p, carry)",
                    prim::register((n + 1) + pb + carry),
                );
        }
        cost.part(
            "sc·y, tc·y multipliers (2)",
            prim::multiplier(dw, fy + 1) * 2.0,
        )
        .part(
            "stage registers (products, p, face, zero)",
            prim::register(2 * pw + pb + 4),
        )
        .part(
            "shifters by p (2)",
            prim::shifter(pw, bits_for((wi + fy + 1) as u64)) * 2.0,
        )
        .part("rounders + the \"+ 1\" (2)", prim::adder(ow + 1) * 2.0)
        .part("zero-direction centre muxes (2)", prim::mux(ow) * 2.0)
        .part(
            "stage registers (s, t, face)",
            prim::register(2 * (ow + 1) + 4),
        )
        .part(
            "texel-centre clamps (2 × 2 comparators + 3:1 mux)",
            (prim::comparator(ow + 1) * 2.0 + prim::mux_k(ow, 3)) * 2.0,
        )
        .part(
            "output saturation (overflow detect + clamp mux, 4)",
            (Cells {
                or2: 2.0,
                ..Cells::default()
            } + prim::mux(ow))
                * 4.0,
        )
        .part(
            "stack: face·F into t (concatenation above the face bits)",
            Cells {
                or2: 3.0,
                ..Cells::default()
            } + prim::adder(ow.saturating_sub(c.face_log2 + fo)),
        )
        .part(
            "output registers (st, stacked s, t, face, zero)",
            prim::register(4 * ow + 4),
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
                name: "side_log2",
                bits: c.side_log2,
            },
            Width {
                name: "rcp_addr_bits",
                bits: c.rcp_addr_bits,
            },
            Width {
                name: "rcp_bits",
                bits: c.rcp_bits,
            },
            Width {
                name: "newton_frac_bits",
                bits: if c.newton { c.newton_frac_bits } else { 0 },
            },
            Width {
                name: "face_log2",
                bits: c.face_log2,
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

    fn in_signals(&self, i: &CubeMapAddressIn) -> Vec<Signal> {
        const NAMES: [&str; 3] = ["cs", "ct", "cr"];
        let w = self.in_bits();
        let m = (1u64 << w) - 1;
        (0..3)
            .map(|k| Signal::new(NAMES[k], w, i.coord[k] as i64 as u64 & m))
            .collect()
    }

    fn out_signals(&self, o: &CubeMapAddressOut) -> Vec<Signal> {
        let w = self.out_bits();
        let m = (1u64 << w) - 1;
        vec![
            Signal::new("face", 3, o.face as u64),
            Signal::new("face_s", w, o.st[0] as i64 as u64 & m),
            Signal::new("face_t", w, o.st[1] as i64 as u64 & m),
            Signal::new("s", w, o.coord[0] as i64 as u64 & m),
            Signal::new("t", w, o.coord[1] as i64 as u64 & m),
            Signal::new("zero", 1, o.zero as u64),
        ]
    }
}
