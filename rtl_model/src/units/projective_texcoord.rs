//! projective_texcoord — projective texture coordinates for the light map (I_l in the
//! light-shaft model): u = s/q, v = t/q from the interpolated homogeneous (s, t, q).
//!
//! Datapath (W = in_int_bits + in_frac_bits, F = in_frac_bits, O = out_int_bits +
//! out_frac_bits, I = recip_index_bits, E = recip_entry_bits, N = newton_frac_bits):
//! 1. q ≤ 0 (behind the projector, or on its plane): `behind`, (u, v) = 0, counted in
//!    `underflows`. No division by zero is ever attempted.
//! 2. Leading-zero count of the magnitude Q (u(W−1)): Q = 2ᵖ·m, p = W − 2 − lzc,
//!    m ∈ [1, 2) held exactly as u1.(W−2) by a normalising left shift.
//! 3. Table: the I bits of m below its leading one index a ROM of 2ᴵ entries of E
//!    bits, entry i = round(2^(E+I+1) / (2^(I+1) + 2i + 1)) = round(2ᴱ / c_i) with c_i
//!    = 1 + (i + ½)/2ᴵ the interval's midpoint, clamped to 2ᴱ − 1 (u0.E: 1/m ∈ (½, 1)).
//!    The content is an integer-only function of (I, E) — [`ProjectiveTexcoord::rom_words`].
//! 4. `newton_steps` Newton–Raphson steps r' = r·(2 − m·r), each in u1.N: m truncated
//!    to u1.N; m·r (u1.N × u1.F_r → u2.(N+F_r)); 2 − m·r rounded to u1.N;
//!    r·d (u1.F_r × u1.N → u2.(F_r+N)) rounded to u1.N.
//! 5. u = s·r·2⁻ᵖ: S (s(W)) × r (u1.F_r) → s(W+F_r+1), exact; shifted right by
//!    F_r + p − out_frac_bits rounding to nearest (ties up) into s(out_int).(out_frac),
//!    saturating; each clamped coordinate is counted in `saturations`.
//!    (The input fraction F cancels: s/q = S/Q.)
//!
//! Input words are masked to their W-bit wires (sign-extended from bit W − 1).

use crate::cost::{prim, Cells, Cost};
use crate::counters::Counters;
use crate::error::{check_range, ConfigError};
use crate::fixed_point::{round_shift, round_shift_right_i64, Format, Fx, Overflow, Quant};
use crate::unit::{Signal, Timing, Unit, Width};
use crate::wire::{bits_for, sign_extend as sext};
use bitvec::prelude::*;
use serde::{Deserialize, Serialize};

/// Inputs per block of the batch kernel's lane form.
const LANES: usize = 64;

/// Inputs per block of [`ProjectiveTexcoord::kernel_pair_lanes_in_square`]: the
/// granule of [`ProjLanes::decided`] (the last block may be shorter).
pub const SQUARE_BLOCK: usize = LANES;

/// Entries of the largest ROM (I ≤ 12): the lane form's flat copy of the ROM is this
/// long (zero past 2ᴵ), so its index, masked to it, needs no bounds check and the
/// look-up vectorises as a gather. A real index is always < 2ᴵ: the mask changes
/// nothing.
const ROM_MAX: usize = 1 << 12;

/// The plain config (serde-friendly); [`ProjectiveTexcoordConfig::build`] validates it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ProjectiveTexcoordConfig {
    /// Integer bits of s, t, q including the sign, 1 ..= 24.
    pub in_int_bits: u32,
    /// Fraction bits of s, t, q, 0 ..= 24.
    pub in_frac_bits: u32,
    /// Integer bits of u, v including the sign, 1 ..= 16.
    pub out_int_bits: u32,
    /// Fraction bits of u, v, 0 ..= 16.
    pub out_frac_bits: u32,
    /// ROM index bits I (2ᴵ entries), 1 ..= 12.
    pub recip_index_bits: u32,
    /// ROM entry bits E (u0.E), 1 ..= 24.
    pub recip_entry_bits: u32,
    /// Newton–Raphson steps after the table, 0 ..= 2.
    pub newton_steps: u32,
    /// Fraction bits N of the Newton datapath (u1.N), 1 ..= 40.
    pub newton_frac_bits: u32,
}

impl Default for ProjectiveTexcoordConfig {
    fn default() -> Self {
        ProjectiveTexcoordConfig::geforce()
    }
}

impl ProjectiveTexcoordConfig {
    /// GeForce-era defaults: s, t, q in s16.16 (the interpolator's homogeneous light-
    /// space coordinates: ±32 768 world units at 1/65 536), u, v in s4.12 texture
    /// units (the map is [0, 1); ±8 leaves room for clamp/repeat, 12 fraction bits
    /// address a 4096-texel map, or a 512-texel light map with 3 sub-texel bits),
    /// a 256 × 16-bit reciprocal ROM and one Newton step at 20 fraction bits
    /// (|r·m − 1| ≤ 2⁻⁹ + 2⁻¹⁵ after the table, ≈ 2⁻¹⁷·³ after the step: below the
    /// output's 2⁻¹³ half-LSB for |u| ≤ 8).
    pub fn geforce() -> Self {
        ProjectiveTexcoordConfig {
            in_int_bits: 16,
            in_frac_bits: 16,
            out_int_bits: 4,
            out_frac_bits: 12,
            recip_index_bits: 8,
            recip_entry_bits: 16,
            newton_steps: 1,
            newton_frac_bits: 20,
        }
    }

    /// Validate and build the ROM; the same as [`ProjectiveTexcoord::new`], errors name
    /// `projective_texcoord.<field>`.
    pub fn build(&self) -> Result<ProjectiveTexcoord, ConfigError> {
        ProjectiveTexcoord::new(*self)
    }
}

/// The validated unit: its config and the reciprocal ROM (packed at E bits per entry).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ProjectiveTexcoord {
    cfg: ProjectiveTexcoordConfig,
    rom: BitVec<u64, Lsb0>,
    /// The same ROM one entry a word (E ≤ 24 bits), for the batch kernel's lane form,
    /// zero-filled to [`ROM_MAX`] entries.
    rom_flat: Box<[u32; ROM_MAX]>,
}

/// Homogeneous coordinates from the interpolator: raw s(in_int).(in_frac) codes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct ProjectiveIn {
    /// Homogeneous s, a raw s(in_int_bits).(in_frac_bits) code (masked to its wire).
    pub s: i64,
    /// Homogeneous t, a raw s(in_int_bits).(in_frac_bits) code (masked to its wire).
    pub t: i64,
    /// Homogeneous q, a raw s(in_int_bits).(in_frac_bits) code; q ≤ 0 means behind the
    /// projector.
    pub q: i64,
}

/// Texture coordinates: raw s(out_int).(out_frac) codes; `behind` when q ≤ 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct ProjectiveOut {
    /// u = s/q, a raw s(out_int_bits).(out_frac_bits) code (saturated, counted); 0 when
    /// `behind`.
    pub u: i32,
    /// v = t/q, a raw s(out_int_bits).(out_frac_bits) code (saturated, counted); 0 when
    /// `behind`.
    pub v: i32,
    /// q ≤ 0: the point is behind the projector or on its plane (counted in `underflows`).
    pub behind: bool,
}

/// The projective unit's outputs in lanes ([`ProjectiveTexcoord::kernel_pair_lanes`]):
/// u, v (raw s(out_int).(out_frac) codes, 0 behind the projector) and `behind`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ProjLanes {
    /// u codes, one per word.
    pub u: Vec<i32>,
    /// v codes, one per word.
    pub v: Vec<i32>,
    /// Behind-the-projector flags, one per word.
    pub behind: Vec<bool>,
    /// One flag per block of [`SQUARE_BLOCK`] words, from
    /// [`ProjectiveTexcoord::kernel_pair_lanes_in_square`]: whether it decided the
    /// block (every word behind the projector or outside the square, its codes
    /// replaced by ones of the same classes). Empty from the other forms.
    pub decided: Vec<bool>,
}

impl ProjLanes {
    /// Empty the lanes (their buffers kept).
    pub fn clear(&mut self) {
        self.u.clear();
        self.v.clear();
        self.behind.clear();
        self.decided.clear();
    }

    fn reserve(&mut self, n: usize) {
        self.u.reserve(n);
        self.v.reserve(n);
        self.behind.reserve(n);
    }

    /// Words held.
    pub fn len(&self) -> usize {
        self.u.len()
    }

    /// True when no word is held.
    pub fn is_empty(&self) -> bool {
        self.u.is_empty()
    }
}

/// One block's reciprocal front end ([`ProjectiveTexcoord::front_lanes`]): per lane 1
/// in front of the projector (q > 0) else 0, the exponent p, the normalised
/// mantissa m and its ROM entry.
struct Front {
    live: [i64; LANES],
    p: [i64; LANES],
    m: [i64; LANES],
    r: [i64; LANES],
}

impl Default for Front {
    fn default() -> Self {
        Front {
            live: [0; LANES],
            p: [0; LANES],
            m: [0; LANES],
            r: [0; LANES],
        }
    }
}

impl Front {
    /// A block of `len` lanes counted: a ROM read per lane in front of the projector,
    /// an underflow per lane behind it, and `sat` saturations.
    #[inline(always)]
    fn count(&self, len: usize, sat: i64, ctr: &mut Counters) {
        let lit: i64 = self.live[..len].iter().sum();
        ctr.table_reads += lit as u64;
        ctr.underflows += (len as i64 - lit) as u64;
        ctr.saturations += sat as u64;
    }
}

/// Which blocks of [`ProjectiveTexcoord::kernel_pair_lanes_in_square`] skip the
/// Newton steps and the scaling: those whose every input is behind the projector or
/// certainly outside the unit square with every coordinate's saturation certain.
/// With the reciprocal within 1/16 ([`ProjectiveTexcoord::recip_error_bound`]), a
/// coordinate's code is
/// X·(1 ± 1/16) ± ½ for X = x·2^of/q (x = s, t or r, of its unit's output fraction
/// bits, q > 0), so in integers:
/// - 8x < −q (X < −1/8): the code is below 0;
/// - 8x > 9q (X > 9/8): it is above 1.0;
/// - 8|x|·2^of ≤ 7q·2^(O−1) (|X| ≤ 7/8 of the range): it does not saturate;
/// - 8|x|·2^of ≥ 9q·2^(O−1) (|X| ≥ 9/8 of it): it saturates, to its exact clamp.
#[derive(Clone, Copy, Debug)]
pub struct SquareCut {
    /// Output fraction bits and range exponent O − 1 of the (s, t) unit.
    st: (u32, u32),
    /// The same of the depth (r) unit.
    r: (u32, u32),
}

impl SquareCut {
    /// The cut of a pair that takes the pair form, where both reciprocals are within
    /// 1/16 and the comparisons fit 63 bits (|x| < 2^(W−1), q < 2^(W−1)); the margins
    /// need 1.0 ≥ 16 LSB (of ≥ 4) and the range ≥ 64 LSB (O ≥ 7), and the (s, t)
    /// unit's range must reach 2.0 (O ≥ of + 2), so that its clamps are outside the
    /// square. None elsewhere.
    pub fn of(st: &ProjectiveTexcoord, r: &ProjectiveTexcoord) -> Option<SquareCut> {
        let w = st.in_bits();
        let fits = |u: &ProjectiveTexcoord| {
            let (of, ob) = (u.cfg.out_frac_bits, u.out_bits());
            u.recip_error_bound().is_some()
                && of >= 4
                && ob >= 7
                && w + of + 3 <= 62
                && w + ob + 3 <= 62
        };
        // A clamped u or v must lie outside the square too: the range reaches 2.0.
        let past_one = st.out_bits() > st.cfg.out_frac_bits + 1;
        let ok = st.pair_lanes_apply(r) && fits(st) && fits(r) && past_one;
        let shape = |u: &ProjectiveTexcoord| (u.cfg.out_frac_bits, u.out_bits() - 1);
        ok.then(|| SquareCut {
            st: shape(st),
            r: shape(r),
        })
    }

    /// The cut's four tests of a coordinate whose value lies in [lo, hi], its
    /// magnitude ·2^(of+3) in [least, most], at q in [ql, qh] (0 < ql ≤ qh) on a unit
    /// of range exponent `big` (O − 1), each taken at its worst corner so that it
    /// holds for every value and q in the ranges: [does not saturate, saturates,
    /// below 0, above 1.0] for certain (at most one of the first two).
    #[inline(always)]
    fn tests(
        (least, most): (i64, i64),
        (lo, hi): (i64, i64),
        (ql, qh): (i64, i64),
        big: u32,
    ) -> [bool; 4] {
        [
            most <= (7 * ql) << big,
            least >= (9 * qh) << big,
            8 * hi < -qh,
            8 * lo > 9 * qh,
        ]
    }

    /// One coordinate x at q > 0 of a unit (of, O − 1): (certain, saturates, the code
    /// given: exact if it saturates, else −1 below 0, 1.0 + 1 LSB above 1.0, 0
    /// between), and whether it is certainly outside [0, 1].
    #[inline(always)]
    fn coord(x: i64, q: i64, (of, big): (u32, u32)) -> (bool, bool, i64, bool) {
        let a = x.abs() << (of + 3);
        let [quiet, sat, below, above] = Self::tests((a, a), (x, x), (q, q), big);
        let clamp = if x < 0 {
            -(1i64 << big)
        } else {
            (1i64 << big) - 1
        };
        let code = if sat {
            clamp
        } else if below {
            -1
        } else if above {
            (1i64 << of) + 1
        } else {
            0
        };
        (quiet | sat, sat, code, below | above)
    }

    /// One lane (q its raw word of width `w`): whether it is decided (behind the
    /// projector, or certainly outside the square with every saturation certain),
    /// whether it is in front (q > 0), its codes [u, v, du] (the depth's 0 where it
    /// does not saturate) and the saturations of u and v and of du, the last two
    /// meaningful in front only.
    #[inline(always)]
    fn lane(&self, [s, t, r, q]: [i64; 4], w: u32) -> (bool, bool, [i64; 3], i64, i64) {
        let qj = sext(q, w);
        let live = qj > 0;
        let qq = if live { qj } else { 1 };
        let (cs, sat_s, us, fs) = Self::coord(s, qq, self.st);
        let (ct, sat_t, ut, ft) = Self::coord(t, qq, self.st);
        let (cr, sat_r, ur, _) = Self::coord(r, qq, self.r);
        let decided = !live | (cs & ct & cr & (fs | ft));
        let codes = [us, ut, if sat_r { ur } else { 0 }];
        let sats = i64::from(sat_s) + i64::from(sat_t);
        (decided, live, codes, sats, i64::from(sat_r))
    }

    /// Every input whose codes s, t, r and q (raw words of width `w`) lie in the
    /// ranges `[s, t, r, q]` (least, greatest) decided alike: Some(its class) where
    /// every one is behind the projector, or every one is in front of it, certainly
    /// outside the square by one coordinate for all (s below 0 for all, or above 1.0
    /// for all; or t), and each coordinate's saturation is certain and the same for
    /// all. Each bound of [`SquareCut`]'s per-input tests is taken at the worst
    /// corner of the ranges, so the class holds for each input in them (whatever
    /// their joint values). None elsewhere, and where a range leaves the `w`-bit
    /// words (whose codes are then read sign-extended, not in order).
    pub fn range(&self, [s, t, r, q]: [(i64, i64); 4], w: u32) -> Option<SquareClass> {
        let fits = |(lo, hi): (i64, i64)| lo <= hi && sext(lo, w) == lo && sext(hi, w) == hi;
        if ![s, t, r, q].into_iter().all(fits) {
            return None;
        }
        let (ql, qh) = q;
        if qh <= 0 {
            return Some(SquareClass::BEHIND);
        }
        if ql <= 0 {
            return None;
        }
        // Per coordinate: Some(saturates) where every input's saturation is certain
        // and the same, and whether all are below 0 or all above 1.0.
        let class = |(lo, hi): (i64, i64), (of, big): (u32, u32)| {
            let most = lo.abs().max(hi.abs()) << (of + 3);
            let least = if lo <= 0 && hi >= 0 {
                0
            } else {
                lo.abs().min(hi.abs()) << (of + 3)
            };
            let [quiet, sat, below, above] = Self::tests((least, most), (lo, hi), q, big);
            let sat = if quiet {
                Some(false)
            } else {
                sat.then_some(true)
            };
            (sat, below || above)
        };
        let ((ss, s_out), (st, t_out), (sr, _)) =
            (class(s, self.st), class(t, self.st), class(r, self.r));
        let (ss, st, sr) = (ss?, st?, sr?);
        (s_out || t_out).then_some(SquareClass {
            live: true,
            sats: u64::from(ss) + u64::from(st),
            depth_sats: u64::from(sr),
        })
    }

    /// One block's lanes [s, t, r, q] (the first `len`, q as its raw word of width
    /// `w`): where every lane is decided, its live bits (q > 0) into `live`, the
    /// codes into [u, v, du] (anything behind the projector) and Some((saturations of
    /// u and v, saturations of du)) in front of it; None where some lane is not.
    #[inline(always)]
    fn block(
        &self,
        [s, t, r, q]: [&[i64; LANES]; 4],
        len: usize,
        w: u32,
        live: &mut [i64; LANES],
        [u, v, du]: [&mut [i64; LANES]; 3],
    ) -> Option<(i64, i64)> {
        let at = |j: usize| self.lane([s[j], t[j], r[j], q[j]], w);
        // A block's lanes are neighbours on the screen: one undecided end lane
        // (the common case in a block that is not cut) is enough to give up early.
        if len == 0 || !at(0).0 || !at(len - 1).0 {
            return None;
        }
        let (mut all, mut sat, mut dsat) = (true, 0i64, 0i64);
        for j in 0..len {
            let (decided, l, codes, sats, dsats) = at(j);
            all &= decided;
            let li = i64::from(l);
            live[j] = li;
            [u[j], v[j], du[j]] = codes;
            sat += sats & -li;
            dsat += dsats & -li;
        }
        all.then_some((sat, dsat))
    }
}

/// A class of inputs [`SquareCut::range`] decides alike: in front of the
/// projector or behind it, and in front the saturations each input adds to the
/// (s, t) unit (u and v) and to the depth unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SquareClass {
    /// In front of the projector (q > 0).
    pub live: bool,
    /// Saturations of u and v per input (0 behind the projector).
    pub sats: u64,
    /// Saturations of the depth per input (0 behind the projector).
    pub depth_sats: u64,
}

impl SquareClass {
    /// Every input behind the projector.
    pub const BEHIND: SquareClass = SquareClass {
        live: false,
        sats: 0,
        depth_sats: 0,
    };
}

/// What the integrator needs to write the ROM as a `$readmemh` table.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct RomParams {
    /// Table name, e.g. `projective_texcoord_recip_i8_e16`.
    pub name: String,
    /// Entries (2ᴵ).
    pub depth: u64,
    /// Bits per entry (E).
    pub width: u32,
    /// The generator, in words.
    pub generator: String,
    /// Generator parameters by name.
    pub params: Vec<(String, u64)>,
}

/// ROM entry i for I index bits and E entry bits: round(2^(E+I+1) / (2^(I+1) + 2i + 1))
/// (= round(2ᴱ / (1 + (i + ½)/2ᴵ)), ties up), clamped to 2ᴱ − 1. Integers only
/// (≤ 2³⁸ intermediates), so regeneration is bit-exact.
pub fn recip_rom_entry(i: u64, index_bits: u32, entry_bits: u32) -> u64 {
    let num = 1u64 << (entry_bits + index_bits + 1); // ≤ 2³⁷
    let den = (1u64 << (index_bits + 1)) + 2 * i + 1; // ≤ 2¹⁴
    let r = (2 * num + den) / (2 * den); // round half up
    r.min((1u64 << entry_bits) - 1)
}

impl ProjectiveTexcoord {
    /// Validate a config and build the ROM; errors name `projective_texcoord.<field>`.
    pub fn new(cfg: ProjectiveTexcoordConfig) -> Result<Self, ConfigError> {
        let f = |n: &str| format!("projective_texcoord.{n}");
        check_range(&f("in_int_bits"), cfg.in_int_bits as u64, 1, 24)?;
        check_range(&f("in_frac_bits"), cfg.in_frac_bits as u64, 0, 24)?;
        check_range(&f("out_int_bits"), cfg.out_int_bits as u64, 1, 16)?;
        check_range(&f("out_frac_bits"), cfg.out_frac_bits as u64, 0, 16)?;
        check_range(&f("recip_index_bits"), cfg.recip_index_bits as u64, 1, 12)?;
        check_range(&f("recip_entry_bits"), cfg.recip_entry_bits as u64, 1, 24)?;
        check_range(&f("newton_steps"), cfg.newton_steps as u64, 0, 2)?;
        check_range(&f("newton_frac_bits"), cfg.newton_frac_bits as u64, 1, 40)?;
        let (ib, eb) = (cfg.recip_index_bits, cfg.recip_entry_bits);
        let depth = 1usize << ib;
        let mut rom = bitvec![u64, Lsb0; 0; depth * eb as usize];
        for i in 0..depth {
            let e = eb as usize;
            rom[i * e..(i + 1) * e].store_le::<u64>(recip_rom_entry(i as u64, ib, eb));
        }
        let mut rom_flat = Box::new([0u32; ROM_MAX]);
        for (i, e) in rom_flat.iter_mut().take(depth).enumerate() {
            *e = recip_rom_entry(i as u64, ib, eb) as u32;
        }
        Ok(ProjectiveTexcoord { cfg, rom, rom_flat })
    }

    /// GeForce-era defaults (see [`ProjectiveTexcoordConfig::geforce`]).
    pub fn geforce() -> Self {
        // The defaults are valid by construction.
        match Self::new(ProjectiveTexcoordConfig::geforce()) {
            Ok(u) => u,
            Err(e) => unreachable!("default config invalid: {e}"),
        }
    }

    /// The config the unit was built from.
    pub fn config(&self) -> ProjectiveTexcoordConfig {
        self.cfg
    }

    /// Input format s(in_int).(in_frac).
    pub fn in_format(&self) -> Format {
        Format {
            int_bits: self.cfg.in_int_bits,
            frac_bits: self.cfg.in_frac_bits,
            signed: true,
        }
    }

    /// Output format s(out_int).(out_frac).
    pub fn out_format(&self) -> Format {
        Format {
            int_bits: self.cfg.out_int_bits,
            frac_bits: self.cfg.out_frac_bits,
            signed: true,
        }
    }

    /// Input width W.
    pub fn in_bits(&self) -> u32 {
        self.cfg.in_int_bits + self.cfg.in_frac_bits
    }

    /// Output width O.
    pub fn out_bits(&self) -> u32 {
        self.cfg.out_int_bits + self.cfg.out_frac_bits
    }

    /// Fraction bits of the final reciprocal: N after a Newton step, else E.
    pub fn recip_frac_bits(&self) -> u32 {
        if self.cfg.newton_steps > 0 {
            self.cfg.newton_frac_bits
        } else {
            self.cfg.recip_entry_bits
        }
    }

    /// ROM bits: 2ᴵ · E.
    pub fn rom_bits(&self) -> u64 {
        self.rom.len() as u64
    }

    /// The ROM entries, index order (each < 2ᴱ).
    pub fn rom_words(&self) -> Vec<u64> {
        (0..(1usize << self.cfg.recip_index_bits))
            .map(|i| self.rom_read(i))
            .collect()
    }

    /// Name, depth, width and generator of the ROM.
    pub fn rom_params(&self) -> RomParams {
        let (i, e) = (self.cfg.recip_index_bits, self.cfg.recip_entry_bits);
        RomParams {
            name: format!("projective_texcoord_recip_i{i}_e{e}"),
            depth: 1u64 << i,
            width: e,
            generator: "entry[i] = min(round_half_up(2^(E+I+1) / (2^(I+1) + 2i + 1)), 2^E - 1): \
                        1/m at the midpoint of m in [1 + i/2^I, 1 + (i+1)/2^I), as u0.E"
                .to_string(),
            params: vec![
                ("recip_index_bits".to_string(), i as u64),
                ("recip_entry_bits".to_string(), e as u64),
            ],
        }
    }

    #[inline]
    fn rom_read(&self, i: usize) -> u64 {
        let e = self.cfg.recip_entry_bits as usize;
        crate::packed_rom::read_field(self.rom.as_raw_slice(), i * e, e as u32)
    }

    /// Host helper: quantise f64 (s, t, q) into the input format (round to nearest
    /// even, saturating with `ctr.saturations` counted). NaN/±∞ is an error naming
    /// `projective_texcoord.s`, `.t` or `.q`.
    pub fn quantise_in(
        &self,
        s: f64,
        t: f64,
        q: f64,
        ctr: &mut Counters,
    ) -> Result<ProjectiveIn, ConfigError> {
        let fmt = self.in_format();
        let qz = |x: f64, field: &str, ctr: &mut Counters| {
            Fx::from_f64(x, fmt, Quant::RndConv, Overflow::Sat, field, ctr).map(|v| v.raw as i64)
        };
        Ok(ProjectiveIn {
            s: qz(s, "projective_texcoord.s", ctr)?,
            t: qz(t, "projective_texcoord.t", ctr)?,
            q: qz(q, "projective_texcoord.q", ctr)?,
        })
    }

    /// Host helper: an output code as a real value (texture units).
    pub fn out_value(&self, raw: i32) -> f64 {
        raw as f64 * (-(self.cfg.out_frac_bits as f64)).exp2()
    }

    /// The reciprocal's front end on Q's magnitude (masked to its W−1-bit wire):
    /// (m, p, idx) with Q = 2ᵖ·m, m normalised to u1.fm (fm = W − 2, m ∈ [2^fm,
    /// 2^(fm+1)), ≤ 47 bits) and idx the I bits below its leading one (the ROM
    /// address); None for Q = 0.
    #[inline(always)]
    fn normalise(&self, qmag: u64) -> Option<(u64, u32, usize)> {
        let w = self.in_bits();
        let qmag = qmag & ((1u64 << w.saturating_sub(1)) - 1); // u(W−1) wire
        if qmag == 0 {
            return None;
        }
        let fm = w.saturating_sub(2); // fraction bits of the exact mantissa u1.fm
        let ib = self.cfg.recip_index_bits;
        // Leading-zero count: p = position of the leading one, 0 ..= W − 2.
        let p = 63 - qmag.leading_zeros();
        // Normalise: u(W−1) << (fm − p) → u1.fm.
        let m = qmag << (fm - p);
        // Table index: the I bits below the leading one (zero-filled if fm < I).
        let frac = m & ((1u64 << fm) - 1); // u0.fm
        let idx = if fm >= ib {
            frac >> (fm - ib)
        } else {
            frac << (ib - fm)
        } as usize; // u(I)
        Some((m, p, idx))
    }

    /// The reciprocal datapath for Q > 0 (masked to its W−1-bit magnitude wire):
    /// returns (r, p) with r the raw u1.F_r approximation of 1/m and p the exponent,
    /// Q = 2ᵖ·m. Q = 0 (never reached from the kernel) gives (0, 0) and no ROM read.
    /// Counts the ROM read and any (impossible in range, guarded) Newton clamp.
    pub fn reciprocal(&self, qmag: u64, ctr: &mut Counters) -> (u128, u32) {
        let Some((m, p, idx)) = self.normalise(qmag) else {
            return (0, 0);
        };
        let m = m as u128;
        let fm = self.in_bits().saturating_sub(2);
        ctr.table_reads += 1;
        let mut r = self.rom_read(idx) as u128; // u0.E ⊂ u1.E
        let mut fr = self.cfg.recip_entry_bits;
        let n = self.cfg.newton_frac_bits;
        let r_max = (1u128 << (n + 1)) - 1; // largest u1.N code
        for _ in 0..self.cfg.newton_steps {
            // m truncated to u1.N (exact when fm ≤ N).
            let mn = if fm >= n {
                m >> (fm - n)
            } else {
                m << (n - fm)
            }; // u1.N
            let prod = mn * r; // u1.N × u1.fr → u2.(N+fr), ≤ 82 bits
            let two = 2u128 << (n + fr); // 2 in u2.(N+fr)
                                         // 2 − m·r: s3.(N+fr); in range m·r ∈ (0, 2) so it is positive.
            let d_full = two as i128 - prod as i128;
            // Round to u1.N (ties up); clamp guard (cannot fire in range, counted).
            let d = round_shift(d_full, fr as i32, Quant::Rnd);
            let d = if d < 0 || d > r_max as i128 {
                ctr.saturations += 1;
                d.clamp(0, r_max as i128)
            } else {
                d
            } as u128; // u1.N
            let rd = r * d; // u1.fr × u1.N → u2.(fr+N)
            let r_new = round_shift(rd as i128, fr as i32, Quant::Rnd) as u128; // → u2.N
            r = if r_new > r_max {
                ctr.saturations += 1;
                r_max
            } else {
                r_new
            }; // u1.N
            fr = n;
        }
        (r, p)
    }

    /// A bound ε on the reciprocal's relative error, |1 − m·r| ≤ ε for every q > 0
    /// (m = q·2⁻ᵖ ∈ [1, 2), r the reciprocal as a real), derived from I, E, N and the
    /// Newton steps alone. The ROM entry is 1/c at the midpoint c of its interval,
    /// within 1.5 LSB after rounding and the clamp: ε₀ = 2^−(I+1) + 2^(2−E). A Newton
    /// step in u1.N maps ε to ε² + 2^(3−N) (m truncated to N bits, two roundings to N
    /// bits, all below 2^(2−N) while ε ≤ 1/16). None where some step starts above
    /// 1/16: then the bound, and the argument that no Newton step clamps, do not hold.
    pub fn recip_error_bound(&self) -> Option<f64> {
        let cfg = &self.cfg;
        let mut eps = (-(cfg.recip_index_bits as f64 + 1.0)).exp2()
            + (2.0 - cfg.recip_entry_bits as f64).exp2();
        for _ in 0..cfg.newton_steps {
            if eps > 1.0 / 16.0 {
                return None;
            }
            // With |1 − m·r| ≤ 1/16: d = 2 − m·r ∈ [15/16, 17/16 + 2^−N·2] inside u1.N's
            // range, and r·d < 1.34 < 2: neither clamp can fire.
            eps = eps * eps + (3.0 - cfg.newton_frac_bits as f64).exp2();
        }
        (eps <= 1.0 / 16.0).then_some(eps)
    }

    /// Whether the whole datapath fits 64-bit carriers: the Newton products and
    /// differences (N + F_r + 2 bits, F_r ≤ max(E, N)) and the output product
    /// s(W) × u1.F_r (W + F_r + 1 bits). The batch kernel's specialised form.
    fn fits_64(&self) -> bool {
        let n = self.cfg.newton_frac_bits;
        let fr_max = if self.cfg.newton_steps > 0 {
            self.cfg.recip_entry_bits.max(n)
        } else {
            self.cfg.recip_entry_bits
        };
        n + fr_max + 2 <= 63 && self.in_bits() + self.recip_frac_bits() < 63
    }

    /// [`Self::reciprocal`] in 64-bit carriers, for configs where [`Self::fits_64`]:
    /// the same steps, the same results and counts.
    fn reciprocal_64(&self, qmag: u64, ctr: &mut Counters) -> (u64, u32) {
        let Some((m, p, idx)) = self.normalise(qmag) else {
            return (0, 0);
        };
        let fm = self.in_bits().saturating_sub(2);
        ctr.table_reads += 1;
        let mut r = self.rom_read(idx); // u0.E
        let mut fr = self.cfg.recip_entry_bits;
        let n = self.cfg.newton_frac_bits;
        let r_max = (1u64 << (n + 1)) - 1;
        for _ in 0..self.cfg.newton_steps {
            let mn = if fm >= n {
                m >> (fm - n)
            } else {
                m << (n - fm)
            }; // u1.N
            let prod = mn * r; // u2.(N+fr) ≤ 62 bits
            let d_full = (2i64 << (n + fr)) - prod as i64;
            let d = round_shift_right_i64(d_full, fr, Quant::Rnd);
            let d = if d < 0 || d > r_max as i64 {
                ctr.saturations += 1;
                d.clamp(0, r_max as i64)
            } else {
                d
            } as u64;
            let rd = r * d; // u2.(fr+N) ≤ 62 bits
            let r_new = round_shift_right_i64(rd as i64, fr, Quant::Rnd) as u64;
            r = if r_new > r_max {
                ctr.saturations += 1;
                r_max
            } else {
                r_new
            };
            fr = n;
        }
        (r, p)
    }

    /// Whether the batch kernel's lane form applies: the 64-bit carriers fit
    /// (`Self::fits_64`) and the output shift F_r + p − out_frac is a right shift
    /// for every exponent p ≥ 0 (F_r > out_frac).
    fn lanes_apply(&self) -> bool {
        self.fits_64() && self.recip_frac_bits() > self.cfg.out_frac_bits
    }

    /// Whether every multiplier operand of the lane form fits 32 signed bits: s and t
    /// (W ≤ 32) and the reciprocal (u1.N with N + 1 ≤ 31 after a Newton step; the
    /// ROM's u0.E, E ≤ 24, before). Then each product is the 32 × 32 → 64-bit
    /// multiply of the same integers (one vector instruction where a 64 × 64 one is
    /// several), chosen once per block from the config.
    fn mul_32(&self) -> bool {
        self.in_bits() <= 32 && (self.cfg.newton_steps == 0 || self.cfg.newton_frac_bits <= 30)
    }

    /// The kernel over up to [`LANES`] inputs in structure-of-arrays form, each step
    /// a loop over the lanes with the config's shifts uniform (the compiler vectorises
    /// the Newton steps and the scaling): the same arithmetic as [`Self::kernel`] in
    /// 64-bit carriers (rounding to nearest, ties up, as `(v + half) >> shift`), the
    /// same counts. A lane behind the projector computes on q = 1 and is then
    /// replaced by the behind output; its counts are masked off.
    fn kernel_lanes(
        &self,
        inputs: &[ProjectiveIn],
        out: &mut Vec<ProjectiveOut>,
        ctr: &mut Counters,
    ) {
        let len = inputs.len();
        debug_assert!(len <= LANES);
        let w = self.in_bits();
        let (mut s, mut t, mut q) = ([0i64; LANES], [0i64; LANES], [0i64; LANES]);
        for (j, x) in inputs.iter().enumerate() {
            s[j] = sext(x.s, w);
            t[j] = sext(x.t, w);
            q[j] = x.q;
        }
        let mut f = Front::default();
        self.front_lanes(&q, len, &mut f);
        let (mut u, mut v) = ([0i64; LANES], [0i64; LANES]);
        let sat = self.back_lanes(&f, len, &s, &mut u, Some((&t, &mut v)));
        f.count(len, sat, ctr);
        out.extend((0..len).map(|j| {
            if f.live[j] == 1 {
                ProjectiveOut {
                    u: u[j] as i32,
                    v: v[j] as i32,
                    behind: false,
                }
            } else {
                ProjectiveOut {
                    u: 0,
                    v: 0,
                    behind: true,
                }
            }
        }));
    }

    /// The reciprocal's front end of the first `len` lanes of `q` (masked to its
    /// wire): whether q > 0, and q's exponent, normalised mantissa and ROM entry
    /// (computed on q = 1 behind the projector). Branch-free, so it vectorises
    /// (leading-zero count and shifts; the ROM read apart).
    #[inline(always)]
    fn front_lanes(&self, q: &[i64; LANES], len: usize, f: &mut Front) {
        let w = self.in_bits();
        let fm = w.saturating_sub(2);
        let ib = self.cfg.recip_index_bits;
        let fmask = (1u64 << fm) - 1;
        // The I bits below the leading one: shifted down (fm ≥ I) or up (zero-filled).
        let (down, up) = (fm.saturating_sub(ib), ib.saturating_sub(fm));
        let rom = &*self.rom_flat;
        let lanes = f
            .live
            .iter_mut()
            .zip(f.p.iter_mut())
            .zip(f.m.iter_mut())
            .zip(f.r.iter_mut())
            .zip(&q[..len]);
        for ((((live, p), m), r), &q) in lanes {
            let q = sext(q, w);
            *live = i64::from(q > 0);
            let qq = if q > 0 { q as u64 } else { 1 };
            let pj = 63 - qq.leading_zeros();
            let mj = qq << (fm - pj);
            *m = mj as i64;
            *p = pj as i64;
            *r = (((mj & fmask) >> down) << up) as i64; // the ROM index, read below
        }
        for r in &mut f.r[..len] {
            *r = rom[*r as usize & (ROM_MAX - 1)] as i64;
        }
    }

    /// After [`Self::front_lanes`]: the Newton steps on the front end's ROM entries
    /// and the scaling of the lanes' s (sign-extended) into `u`, and of t into v
    /// where `tv` is given (a unit whose v no one reads skips it; t = 0 would give
    /// v = 0 and no saturation). Clamped; meaningless behind the projector. Returns
    /// the saturations in front of it. In 32-bit multiplies where
    /// [`Self::mul_32`], else in 64-bit ones: the same integers.
    #[inline(always)]
    fn back_lanes(
        &self,
        f: &Front,
        len: usize,
        s: &[i64; LANES],
        u: &mut [i64; LANES],
        tv: Option<(&[i64; LANES], &mut [i64; LANES])>,
    ) -> i64 {
        if self.mul_32() {
            self.back_lanes_with::<true>(f, len, s, u, tv)
        } else {
            self.back_lanes_with::<false>(f, len, s, u, tv)
        }
    }

    /// [`Self::back_lanes`] with its multiplier chosen: `NARROW`, the operands
    /// (known to fit) as 32-bit words.
    #[inline(always)]
    fn back_lanes_with<const NARROW: bool>(
        &self,
        f: &Front,
        len: usize,
        s: &[i64; LANES],
        u: &mut [i64; LANES],
        tv: Option<(&[i64; LANES], &mut [i64; LANES])>,
    ) -> i64 {
        #[inline(always)]
        fn mul<const NARROW: bool>(a: i64, b: i64) -> i64 {
            if NARROW {
                (a as i32 as i64) * (b as i32 as i64)
            } else {
                a * b
            }
        }
        let fm = self.in_bits().saturating_sub(2);
        let n = self.cfg.newton_frac_bits;
        let of = self.cfg.out_frac_bits as i64;
        let r_max = (1i64 << (n + 1)) - 1;
        let mut r = f.r;
        let (live, m, p) = (&f.live[..len], &f.m[..len], &f.p[..len]);
        let r = &mut r[..len];
        let mut sat = 0i64;
        let mut fr = self.cfg.recip_entry_bits;
        for _ in 0..self.cfg.newton_steps {
            let two = 2i64 << (n + fr);
            let half = 1i64 << (fr - 1);
            let (down, up) = (fm.saturating_sub(n), n.saturating_sub(fm));
            for ((rj, &mj), &l) in r.iter_mut().zip(m).zip(live) {
                let mn = (mj >> down) << up; // u1.N
                let d = (two - mul::<NARROW>(mn, *rj) + half) >> fr;
                sat += i64::from(d < 0 || d > r_max) & l;
                let d = d.clamp(0, r_max);
                let rn = (mul::<NARROW>(*rj, d) + half) >> fr;
                sat += i64::from(rn > r_max) & l;
                *rj = rn.min(r_max);
            }
            fr = n;
        }
        let ob = self.out_bits();
        let (lo, hi) = (-(1i64 << (ob - 1)), (1i64 << (ob - 1)) - 1);
        let frl = fr as i64 - of;
        // One coordinate: s·r·2⁻ᵖ rounded (ties up), (clamped, saturated in front).
        let scale = |x: i64, rj: i64, pj: i64, l: i64| {
            let sh = frl + pj; // ≥ 1
            let a = (mul::<NARROW>(x, rj) + (1i64 << (sh - 1))) >> sh;
            (a.clamp(lo, hi), i64::from(a < lo || a > hi) & l)
        };
        let lanes = u.iter_mut().zip(s).zip(&*r).zip(p).zip(live);
        for ((((uj, &sj), &rj), &pj), &l) in lanes {
            let (a, e) = scale(sj, rj, pj, l);
            *uj = a;
            sat += e;
        }
        if let Some((t, v)) = tv {
            let lanes = v.iter_mut().zip(t).zip(&*r).zip(p).zip(live);
            for ((((vj, &tj), &rj), &pj), &l) in lanes {
                let (b, e) = scale(tj, rj, pj, l);
                *vj = b;
                sat += e;
            }
        }
        sat
    }

    /// Whether [`Self::kernel_pair_lanes`] applies to this unit and `other`: both
    /// take the lane form, on inputs of the same width and the same ROM (I, E).
    pub fn pair_lanes_apply(&self, other: &ProjectiveTexcoord) -> bool {
        self.lanes_apply()
            && other.lanes_apply()
            && self.in_bits() == other.in_bits()
            && self.cfg.recip_index_bits == other.cfg.recip_index_bits
            && self.cfg.recip_entry_bits == other.cfg.recip_entry_bits
    }

    /// Two units that divide by the same q, fed from attribute lanes at indices `idx`:
    /// this unit on (s, t, q), `other` on (r, 0, q). Where
    /// [`Self::pair_lanes_apply`], q's leading-zero count, normalisation and ROM read
    /// are done once per input for both (the same ROM, the same wire), then each
    /// unit's Newton steps and scaling on its own config (`other` scales r only: its
    /// v, t·r = 0, is 0 and never saturates). Outputs in lanes: this unit's u, v and
    /// behind appended to `out`, `other`'s u to `other_u` (0 behind the projector).
    /// Each unit's counters are exactly its batch kernel's on its own inputs (`ctr`,
    /// `other_ctr`; both count a ROM read per input in front and an underflow per
    /// input behind, as each unit's front end would).
    /// Returns false with nothing done where the pair form does not apply.
    #[allow(clippy::too_many_arguments)]
    pub fn kernel_pair_lanes(
        &self,
        other: &ProjectiveTexcoord,
        lanes: [&[i64]; 4],
        idx: &[u32],
        out: &mut ProjLanes,
        other_u: &mut Vec<i32>,
        ctr: &mut Counters,
        other_ctr: &mut Counters,
    ) -> bool {
        self.pair_lanes(other, lanes, idx, out, other_u, [ctr, other_ctr], None)
            .is_some()
    }

    /// [`Self::kernel_pair_lanes`] for a caller that reads nothing of a fragment
    /// outside the unit square [0, 1]² in (u, v) but its counters: the same counters,
    /// and the same outputs except in a block of 64 inputs where every input is
    /// behind the projector or certainly outside the square ([`SquareCut`], decided
    /// in integers from s, t, r and q alone). There the Newton steps and the scaling
    /// are skipped, and an input in front of the projector gets codes of the same
    /// classes as the exact ones:
    /// - a coordinate that saturates gets its exact (clamped) code;
    /// - one certainly below 0 gets −1, one certainly above 1.0 gets 1.0 + 1 LSB;
    /// - any other gets 0, and `other`'s depth gets 0 where it does not saturate.
    ///
    /// Each replacement has a magnitude no larger than the exact code's. Which blocks
    /// were skipped goes to `out.decided`, a flag per block of [`SQUARE_BLOCK`]
    /// inputs. Returns how many inputs were in skipped blocks (every one behind the
    /// projector or outside the square), or None with nothing done where the pair
    /// form does not apply.
    #[allow(clippy::too_many_arguments)]
    pub fn kernel_pair_lanes_in_square(
        &self,
        other: &ProjectiveTexcoord,
        lanes: [&[i64]; 4],
        idx: &[u32],
        out: &mut ProjLanes,
        other_u: &mut Vec<i32>,
        ctr: &mut Counters,
        other_ctr: &mut Counters,
    ) -> Option<usize> {
        let cut = SquareCut::of(self, other);
        self.pair_lanes(other, lanes, idx, out, other_u, [ctr, other_ctr], cut)
    }

    /// The counters [`Self::kernel_pair_lanes`] adds for `n` inputs of one class
    /// (this unit's to `ctr`, `other`'s to `other_ctr`), counted without running: a
    /// ROM read per input in front of the projector, an underflow per input behind
    /// it, and in front the class's saturations per input. (Its outputs are not
    /// needed: every input is behind the projector or outside the square.)
    pub fn count_pair_class(
        &self,
        class: SquareClass,
        n: u64,
        ctr: &mut Counters,
        other_ctr: &mut Counters,
    ) {
        let live = if class.live { n } else { 0 };
        for (c, sats) in [(ctr, class.sats), (other_ctr, class.depth_sats)] {
            c.table_reads += live;
            c.underflows += n - live;
            c.saturations += sats * live;
        }
    }

    /// [`Self::kernel_pair_lanes`]'s body; with `cut`, the blocks it decides skipped
    /// (Some(the inputs in them)).
    #[allow(clippy::too_many_arguments)]
    fn pair_lanes(
        &self,
        other: &ProjectiveTexcoord,
        [s, t, r, q]: [&[i64]; 4],
        idx: &[u32],
        out: &mut ProjLanes,
        other_u: &mut Vec<i32>,
        [ctr, other_ctr]: [&mut Counters; 2],
        cut: Option<SquareCut>,
    ) -> Option<usize> {
        if !self.pair_lanes_apply(other) {
            return None;
        }
        let mut skipped = 0;
        let w = self.in_bits();
        out.reserve(idx.len());
        other_u.reserve(idx.len());
        // The four lanes at one length k. Each block's indices are checked against k
        // once; inside the loop an index clamped to k − 1 (a no-op after the check)
        // needs no bounds check, so the gather compiles to vector gathers.
        let k = s.len().min(t.len()).min(r.len()).min(q.len());
        let (s, t, r, q) = (&s[..k], &t[..k], &r[..k], &q[..k]);
        // One block's lanes, reused from block to block (only the first `len` of each
        // are read).
        let (mut sl, mut tl, mut rl, mut ql) =
            ([0i64; LANES], [0i64; LANES], [0i64; LANES], [0i64; LANES]);
        let mut f = Front::default();
        let (mut u, mut v, mut du) = ([0i64; LANES], [0i64; LANES], [0i64; LANES]);
        for block in idx.chunks(LANES) {
            let len = block.len();
            let last = block.iter().copied().max().unwrap_or(0) as usize;
            assert!(
                last < k,
                "kernel_pair_lanes: index {last} past the lanes ({k})"
            );
            let lanes = sl.iter_mut().zip(&mut tl).zip(&mut rl).zip(&mut ql);
            let first = block.first().map_or(0, |&i| i as usize);
            if super::rising_run(block) {
                // A run of consecutive indices (a stretch where every walked pixel is
                // a fragment): slices of the lanes, read without a gather.
                let run = first..first + len;
                let from = s[run.clone()].iter().zip(&t[run.clone()]);
                let from = from.zip(&r[run.clone()]).zip(&q[run]);
                for ((((sj, tj), rj), qj), (((&si, &ti), &ri), &qi)) in lanes.zip(from) {
                    (*sj, *tj, *rj, *qj) = (sext(si, w), sext(ti, w), sext(ri, w), qi);
                }
            } else {
                for ((((sj, tj), rj), qj), &i) in lanes.zip(block) {
                    let i = (i as usize).min(k - 1);
                    (*sj, *tj, *rj, *qj) = (sext(s[i], w), sext(t[i], w), sext(r[i], w), q[i]);
                }
            }
            let cut_sats = cut.and_then(|c| {
                c.block(
                    [&sl, &tl, &rl, &ql],
                    len,
                    w,
                    &mut f.live,
                    [&mut u, &mut v, &mut du],
                )
            });
            if cut.is_some() {
                out.decided.push(cut_sats.is_some());
            }
            let (sat, dsat) = match cut_sats {
                Some(sats) => {
                    skipped += len;
                    sats
                }
                None => {
                    self.front_lanes(&ql, len, &mut f);
                    let sat = self.back_lanes(&f, len, &sl, &mut u, Some((&tl, &mut v)));
                    (sat, other.back_lanes(&f, len, &rl, &mut du, None))
                }
            };
            f.count(len, sat, ctr);
            f.count(len, dsat, other_ctr);
            // 0 behind the projector: the value masked by the lane's live bit.
            let live = &f.live[..len];
            let keep = |(&a, &l): (&i64, &i64)| (a & l.wrapping_neg()) as i32;
            out.u.extend(u[..len].iter().zip(live).map(keep));
            out.v.extend(v[..len].iter().zip(live).map(keep));
            out.behind.extend(live.iter().map(|&l| l == 0));
            other_u.extend(du[..len].iter().zip(live).map(keep));
        }
        Some(skipped)
    }

    /// [`Self::scale`] in a 64-bit carrier when the product is shifted right (the
    /// exact left shift of a small exponent goes through the 128-bit form).
    #[inline]
    fn scale_64(&self, s: i64, r: u64, fr: u32, p: u32, ctr: &mut Counters) -> i32 {
        let shift = fr as i32 + p as i32 - self.cfg.out_frac_bits as i32;
        if shift <= 0 {
            return self.scale(s, r as u128, fr, p, ctr);
        }
        let prod = s * r as i64; // s(W+F_r+1) ≤ 63 bits
        let rounded = round_shift_right_i64(prod, shift as u32, Quant::Rnd);
        let (lo, hi) = (
            -(1i64 << (self.out_bits() - 1)),
            (1i64 << (self.out_bits() - 1)) - 1,
        );
        if rounded < lo || rounded > hi {
            ctr.saturations += 1;
            rounded.clamp(lo, hi) as i32
        } else {
            rounded as i32
        }
    }

    /// One coordinate: S·r·2⁻ᵖ rounded into the output format, saturating.
    #[inline]
    fn scale(&self, s: i64, r: u128, fr: u32, p: u32, ctr: &mut Counters) -> i32 {
        let prod = s as i128 * r as i128; // s(W) × u1.F_r → s(W+F_r+1), ≤ 90 bits
        let shift = fr as i32 + p as i32 - self.cfg.out_frac_bits as i32;
        let rounded = round_shift(prod, shift, Quant::Rnd); // round to nearest, ties up
        let f = self.out_format();
        let (lo, hi) = (f.min_raw(), f.max_raw());
        if rounded < lo || rounded > hi {
            ctr.saturations += 1;
            rounded.clamp(lo, hi) as i32
        } else {
            rounded as i32
        }
    }
}

impl Unit for ProjectiveTexcoord {
    type In = ProjectiveIn;
    type Out = ProjectiveOut;
    type State = ();

    fn name(&self) -> &'static str {
        "projective_texcoord"
    }

    fn kernel(&self, _: &mut (), input: &ProjectiveIn, ctr: &mut Counters) -> ProjectiveOut {
        let w = self.in_bits();
        let (s, t, q) = (sext(input.s, w), sext(input.t, w), sext(input.q, w)); // i64 → s(W)
        if q <= 0 {
            ctr.underflows += 1; // behind the projector: no reciprocal, (u, v) = 0
            return ProjectiveOut {
                u: 0,
                v: 0,
                behind: true,
            };
        }
        let (r, p) = self.reciprocal(q as u64, ctr); // q > 0: magnitude u(W−1)
        let fr = self.recip_frac_bits();
        ProjectiveOut {
            u: self.scale(s, r, fr, p, ctr),
            v: self.scale(t, r, fr, p, ctr),
            behind: false,
        }
    }

    /// The lane form where it applies (`Self::lanes_apply`); else the kernel in
    /// 64-bit carriers where the config fits them (`Self::fits_64`); otherwise the
    /// per-word kernel.
    fn kernel_batch(
        &self,
        st: &mut (),
        inputs: &[ProjectiveIn],
        out: &mut Vec<ProjectiveOut>,
        ctr: &mut Counters,
    ) {
        if self.lanes_apply() {
            out.reserve(inputs.len());
            for block in inputs.chunks(LANES) {
                self.kernel_lanes(block, out, ctr);
            }
            return;
        }
        if !self.fits_64() {
            out.extend(inputs.iter().map(|x| self.kernel(st, x, ctr)));
            return;
        }
        let w = self.in_bits();
        let fr = self.recip_frac_bits();
        out.extend(inputs.iter().map(|input| {
            let (s, t, q) = (sext(input.s, w), sext(input.t, w), sext(input.q, w));
            if q <= 0 {
                ctr.underflows += 1;
                return ProjectiveOut {
                    u: 0,
                    v: 0,
                    behind: true,
                };
            }
            let (r, p) = self.reciprocal_64(q as u64, ctr);
            ProjectiveOut {
                u: self.scale_64(s, r, fr, p, ctr),
                v: self.scale_64(t, r, fr, p, ctr),
                behind: false,
            }
        }));
    }

    fn timing(&self) -> Timing {
        // LZC + normalise | ROM read | 2 per Newton step (m·r, then r·d) |
        // s·r and t·r | round-shift + saturate.
        Timing {
            latency: 4 + 2 * self.cfg.newton_steps,
            ii: 1,
        }
    }

    fn cost(&self) -> Cost {
        let w = self.in_bits();
        let wm = w.saturating_sub(1).max(1); // magnitude bits
        let eb = bits_for(w.saturating_sub(2) as u64); // exponent p bits
        let e = self.cfg.recip_entry_bits;
        let n = self.cfg.newton_frac_bits;
        let o = self.out_bits();
        let steps = self.cfg.newton_steps;
        let carry = 2 * w + eb + 1; // s, t, p, behind travelling down the pipe
        let mut c = Cost::default()
            .part("input registers (s, t, q)", prim::register(3 * w))
            .part(
                "behind detect (q ≤ 0: sign | zero tree)",
                Cells {
                    or2: w as f64,
                    ..Cells::default()
                },
            )
            .part("leading-zero counter", prim::leading_zero_counter(wm))
            .part(
                "normalising shifter",
                prim::shifter(wm, bits_for(wm.saturating_sub(1) as u64)),
            )
            .part(
                "stage-1 registers (m, s, t, p, behind)",
                prim::register(wm + carry),
            )
            .part(
                "ROM output registers (r0, m, s, t, p, behind)",
                prim::register(e + if steps > 0 { n + 1 } else { 0 } + carry),
            );
        let mut fr = e;
        for k in 1..=steps {
            c = c
                .part(
                    &format!("Newton {k}: m·r multiplier"),
                    prim::multiplier(n + 1, fr + 1),
                )
                .part(&format!("Newton {k}: 2 − m·r"), prim::subtractor(n + 2))
                .part(
                    &format!("Newton {k}: registers (d, r, m, carry)"),
                    prim::register((n + 1) + (fr + 1) + (n + 1) + carry),
                )
                .part(
                    &format!("Newton {k}: r·d multiplier"),
                    prim::multiplier(fr + 1, n + 1),
                )
                .part(&format!("Newton {k}: rounder"), prim::adder(n + 1))
                .part(
                    &format!("Newton {k}: registers (r, m, carry)"),
                    prim::register((n + 1) + if k < steps { n + 1 } else { 0 } + carry),
                );
            fr = n;
        }
        let pw = w + fr + 1; // product width
        c.part("s·r, t·r multipliers", prim::multiplier(w, fr + 1) * 2.0)
            .part(
                "product registers (s·r, t·r, p, behind)",
                prim::register(2 * pw + eb + 1),
            )
            .part(
                "output shifters (by F_r + p − out_frac)",
                prim::shifter(pw, eb) * 2.0,
            )
            .part("rounding adders", prim::adder(o + 1) * 2.0)
            .part(
                "saturation (overflow detect + clamp mux)",
                (Cells {
                    or2: pw.saturating_sub(o) as f64,
                    ..Cells::default()
                } + prim::mux(o))
                    * 2.0,
            )
            .part("behind zeroing", prim::mux(o) * 2.0)
            .part("output register (u, v, behind)", prim::register(2 * o + 1))
            .with_ram_bits(self.rom_bits())
    }

    fn widths(&self) -> Vec<Width> {
        vec![
            Width {
                name: "in_bits",
                bits: self.in_bits(),
            },
            Width {
                name: "in_frac_bits",
                bits: self.cfg.in_frac_bits,
            },
            Width {
                name: "out_bits",
                bits: self.out_bits(),
            },
            Width {
                name: "out_frac_bits",
                bits: self.cfg.out_frac_bits,
            },
            Width {
                name: "recip_index_bits",
                bits: self.cfg.recip_index_bits,
            },
            Width {
                name: "recip_entry_bits",
                bits: self.cfg.recip_entry_bits,
            },
            Width {
                name: "newton_frac_bits",
                bits: self.cfg.newton_frac_bits,
            },
        ]
    }

    fn in_signals(&self, i: &ProjectiveIn) -> Vec<Signal> {
        let w = self.in_bits();
        let m = (1u64 << w) - 1;
        vec![
            Signal::new("s", w, i.s as u64 & m),
            Signal::new("t", w, i.t as u64 & m),
            Signal::new("q", w, i.q as u64 & m),
        ]
    }

    fn out_signals(&self, o: &ProjectiveOut) -> Vec<Signal> {
        let w = self.out_bits();
        let m = (1u64 << w) - 1;
        vec![
            Signal::new("u", w, o.u as i64 as u64 & m),
            Signal::new("v", w, o.v as i64 as u64 & m),
            Signal::new("behind", 1, o.behind as u64),
        ]
    }
}
