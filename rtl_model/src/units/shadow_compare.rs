//! shadow_compare — the shadow-map unit (H in the light-shaft model): a depth RAM of
//! `width × height` words of `depth_bits`, written in the depth pass (z-buffer LESS:
//! keep the minimum) and read and compared per fragment in the lookup pass
//! (GL_ARB_shadow, compare LEQUAL by default): lit ⇔ frag_depth − bias ≤ stored_depth.
//!
//! Modes (config fields whose defaults are the GeForce2 behaviour above):
//! * `compare`: the eight functions of GL_ARB_shadow / GL_EXT_shadow_funcs and of the
//!   NV2A's `NV097_SET_SHADOW_COMPARE_FUNC` (NEVER, LESS, EQUAL, LEQUAL, GREATER,
//!   NOTEQUAL, GEQUAL, ALWAYS): lit ⇔ (frag − bias) OP stored. The function's 3-bit
//!   code (GL's low three bits: NEVER 0 … ALWAYS 7) is a truth table indexed by the
//!   comparator's outcome (bit 0: less, bit 1: equal, bit 2: greater), so the eight
//!   functions cost one 3:1 mux behind the one comparator.
//! * `texel`: how a depth-pass `Write` word is read as a depth. `Unorm` (default): the
//!   word's low n bits. `Z16`: a 16-bit depth texel (n must be 16). `Z24S8`: a 32-bit
//!   texel holding the depth in its high 24 bits and stencil in the low 8 (n must be
//!   24), depth = word >> 8. The NV2A's `DEPTH_Y16_FIXED` and `DEPTH_X8_Y24_FIXED`
//!   texture formats, as measured on the captures of nxdk_pgraph_tests'
//!   texture_shadow_comparator raw-value tests (github.com/abaire/nxdk_pgraph_tests,
//!   MIT; captures github.com/abaire/nxdk_pgraph_tests_golden_results, CC0): the
//!   compare is an integer compare at the texel's precision.
//!
//! Widths (n = `depth_bits`, k = `frag_frac_bits`):
//! * stored depth: u(n) unorm, code d stands for d / (2ⁿ − 1); a cleared texel holds
//!   2ⁿ − 1 (= 1.0, the far plane).
//! * fragment depth: u(n).k — n integer bits counted in depth LSBs plus k extra
//!   fraction bits from the interpolator, code f stands for f / (2ᵏ·(2ⁿ − 1)).
//! * bias: u(n) integer depth LSBs (unsigned: a bias pushes the fragment toward the
//!   light, never away).
//! * coordinates x, y: s16 wires (an `i32` input is clamped to s16, which keeps any
//!   out-of-map coordinate out of the map since the map is at most 4096 wide).
//! * address y·w + x: u(⌈log₂ h⌉) × u(⌈log₂(w+1)⌉) + u(⌈log₂ w⌉) → u(⌈log₂(w·h)⌉) ≤ u24.
//! * compare: f − bias·2ᵏ is s(n+k+1); stored·2ᵏ is u(n+k); one (n+k+1)-bit comparator.
//!
//! Conventions: a lookup outside the map compares against the far plane (the map's
//! border, as GL_CLAMP_TO_BORDER with border depth 1.0) with the fragment depth
//! clamped to the far plane (GL clamps r to [0, 1]): under LEQUAL it is always *lit*.
//! A depth-pass write outside the map
//! is dropped; both are counted in `saturations` (a coordinate clamped to the border).
//! `Clear` is a one-clock flash clear of the RAM to the far plane (real parts use a
//! fast-clear tag per block; a design that clears by writes would spend
//! [`ShadowCompare::clear_cycles_by_writes`] clocks instead).
//! The RAM is internal (`ram_bits` in the cost); every RAM read (a test, or the read
//! half of a depth-pass read-modify-write) is counted in `table_reads`.

use crate::cost::{prim, Cells, Cost};
use crate::counters::Counters;
use crate::error::{check_finite, check_range, ConfigError};
use crate::fixed_point::{Format, Fx, Overflow, Quant};
use crate::unit::{Signal, Timing, Unit, Width};
use crate::wire::bits_for;
use bitvec::prelude::*;
use serde::{Deserialize, Serialize};

/// Largest map side.
pub const MAX_MAP_SIDE: u32 = 4096;
/// Widest stored depth.
pub const MAX_DEPTH_BITS: u32 = 32;
/// Most extra fraction bits of the fragment depth.
pub const MAX_FRAG_FRAC_BITS: u32 = 8;
/// Width of the signed x and y coordinate wires.
pub const COORD_BITS: u32 = 16;

/// The plain config (serde-friendly); [`ShadowCompareConfig::build`] validates it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ShadowCompareConfig {
    /// Map width in texels, 1 ..= 4096.
    pub width: u32,
    /// Map height in texels, 1 ..= 4096.
    pub height: u32,
    /// Stored depth width n, 1 ..= 32 (GeForce: 24).
    pub depth_bits: u32,
    /// Depth bias in LSBs of the stored depth, 0 ..= 2ⁿ − 1 (unsigned).
    pub bias: u32,
    /// Extra fraction bits k of the incoming fragment depth, 0 ..= 8.
    pub frag_frac_bits: u32,
    /// The depth compare function (GeForce2 default: LEQUAL).
    #[serde(default, skip_serializing_if = "CompareFunc::is_default")]
    pub compare: CompareFunc,
    /// How a depth-pass write word is read as a depth (default: its low n bits).
    #[serde(default, skip_serializing_if = "DepthTexel::is_default")]
    pub texel: DepthTexel,
}

/// A depth compare function: lit ⇔ (frag − bias) OP stored.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CompareFunc {
    /// Code 0: never lit.
    Never,
    /// Code 1: lit when frag − bias < stored.
    Less,
    /// Code 2: lit when frag − bias = stored.
    Equal,
    /// Code 3 (the default): lit when frag − bias ≤ stored.
    #[default]
    Lequal,
    /// Code 4: lit when frag − bias > stored.
    Greater,
    /// Code 5: lit when frag − bias ≠ stored.
    Notequal,
    /// Code 6: lit when frag − bias ≥ stored.
    Gequal,
    /// Code 7: always lit.
    Always,
}

impl CompareFunc {
    /// All eight, in code order.
    pub const ALL: [CompareFunc; 8] = [
        CompareFunc::Never,
        CompareFunc::Less,
        CompareFunc::Equal,
        CompareFunc::Lequal,
        CompareFunc::Greater,
        CompareFunc::Notequal,
        CompareFunc::Gequal,
        CompareFunc::Always,
    ];

    /// The 3-bit code: GL's `GL_NEVER` … `GL_ALWAYS` minus 0x200, and the NV2A's
    /// `NV097_SET_SHADOW_COMPARE_FUNC` value. Bit 0: lit when less, bit 1: when equal,
    /// bit 2: when greater.
    pub const fn code(self) -> u32 {
        self as u32
    }

    /// The function of a 3-bit code (None above 7).
    pub fn from_code(code: u32) -> Option<CompareFunc> {
        CompareFunc::ALL.get(code as usize).copied()
    }

    /// GL's name of the function ("LEQUAL").
    pub const fn name(self) -> &'static str {
        match self {
            CompareFunc::Never => "NEVER",
            CompareFunc::Less => "LESS",
            CompareFunc::Equal => "EQUAL",
            CompareFunc::Lequal => "LEQUAL",
            CompareFunc::Greater => "GREATER",
            CompareFunc::Notequal => "NOTEQUAL",
            CompareFunc::Gequal => "GEQUAL",
            CompareFunc::Always => "ALWAYS",
        }
    }

    /// a OP b: the code's bit at the comparator's outcome (0 less, 1 equal, 2 greater).
    #[inline(always)]
    pub fn eval(self, a: i64, b: i64) -> bool {
        let outcome = 2 * u32::from(a > b) + u32::from(a == b);
        (self.code() >> outcome) & 1 == 1
    }

    /// Whether, at one fragment depth, the stored words that light it are a run at
    /// either end of their range (or all, or none): its outcome then changes at most
    /// once as the stored word grows (greater, equal, then less), so two stored words
    /// with one outcome give it to every word between them. All but EQUAL and
    /// NOTEQUAL.
    pub const fn is_monotone(self) -> bool {
        let (lt, eq, gt) = (self.code() & 1, (self.code() >> 1) & 1, self.code() >> 2);
        !(lt == gt && eq != lt)
    }

    /// True for LEQUAL, the default (left out when a config is written).
    pub fn is_default(&self) -> bool {
        *self == CompareFunc::default()
    }
}

/// How a depth-pass write word is read as a depth (see the module notes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DepthTexel {
    /// The word's low n bits.
    #[default]
    Unorm,
    /// A 16-bit depth texel (`depth_bits` 16).
    Z16,
    /// A 32-bit texel, depth in the high 24 bits, stencil in the low 8 (`depth_bits` 24).
    Z24S8,
}

impl DepthTexel {
    /// Bits of the texel word: n (`Unorm`), 16 or 32.
    pub fn word_bits(self, depth_bits: u32) -> u32 {
        match self {
            DepthTexel::Unorm => depth_bits,
            DepthTexel::Z16 => 16,
            DepthTexel::Z24S8 => 32,
        }
    }

    /// Right shift from the texel word to the depth: 8 for `Z24S8`, else 0.
    pub fn shift(self) -> u32 {
        match self {
            DepthTexel::Z24S8 => 8,
            _ => 0,
        }
    }

    /// The depth width the format requires (None: any).
    pub fn required_depth_bits(self) -> Option<u32> {
        match self {
            DepthTexel::Unorm => None,
            DepthTexel::Z16 => Some(16),
            DepthTexel::Z24S8 => Some(24),
        }
    }

    /// True for `Unorm`, the default (left out when a config is written).
    pub fn is_default(&self) -> bool {
        *self == DepthTexel::default()
    }
}

impl Default for ShadowCompareConfig {
    fn default() -> Self {
        ShadowCompareConfig::geforce()
    }
}

impl ShadowCompareConfig {
    /// GeForce-era defaults: a 512 × 512 map of 24-bit depths (the depth buffer's
    /// width), a bias of 2 LSB, fragment depth at the stored width (k = 0).
    pub fn geforce() -> Self {
        ShadowCompareConfig {
            width: 512,
            height: 512,
            depth_bits: 24,
            bias: 2,
            frag_frac_bits: 0,
            compare: CompareFunc::Lequal,
            texel: DepthTexel::Unorm,
        }
    }

    /// Validate; the same as [`ShadowCompare::new`], errors name `shadow_compare.<field>`.
    pub fn build(&self) -> Result<ShadowCompare, ConfigError> {
        ShadowCompare::new(*self)
    }
}

/// The validated unit config (the depth RAM lives in [`ShadowState`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct ShadowCompare {
    cfg: ShadowCompareConfig,
}

/// One input word.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShadowIn {
    /// Flash-clear the map to the far plane (2ⁿ − 1).
    Clear,
    /// Depth pass: store `depth` (u(n), masked to n bits) at (x, y) if it is less than
    /// the stored depth.
    Write {
        /// Texel column (clamped to the s16 wire; outside the map the write is dropped).
        x: i32,
        /// Texel row (clamped to the s16 wire; outside the map the write is dropped).
        y: i32,
        /// The texel word written, read as a depth by `texel` (u(n) for `unorm`).
        depth: u32,
    },
    /// Lookup pass: compare a fragment depth (u(n).k raw, masked to n + k bits)
    /// against the stored depth at (x, y).
    Test {
        /// Texel column (clamped to the s16 wire; outside the map: the far plane).
        x: i32,
        /// Texel row (clamped to the s16 wire; outside the map: the far plane).
        y: i32,
        /// The fragment depth, a raw u(n).k code (n = `depth_bits`, k =
        /// `frag_frac_bits`).
        depth: u64,
    },
}

/// One output word.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct ShadowOut {
    /// Test: the fragment is lit (frag − bias ≤ stored, or out of map). False otherwise.
    pub lit: bool,
    /// The stored depth at (x, y) after the operation (Test: the word compared
    /// against; Write: the new minimum; Clear or out of map: 2ⁿ − 1, the far plane).
    pub stored: u32,
    /// Write: the depth passed the LESS test and was stored. False otherwise.
    pub written: bool,
}

/// The depth RAM, `width · height · depth_bits` bits, word (x, y) at bit
/// `(y·width + x)·depth_bits`, little-endian within the word.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ShadowState {
    /// The packed depth words, `width · height · depth_bits` bits.
    pub ram: BitVec<u64, Lsb0>,
}

impl ShadowCompare {
    /// Validate a config; errors name `shadow_compare.<field>`.
    pub fn new(cfg: ShadowCompareConfig) -> Result<Self, ConfigError> {
        check_range(
            "shadow_compare.width",
            cfg.width as u64,
            1,
            MAX_MAP_SIDE as u64,
        )?;
        check_range(
            "shadow_compare.height",
            cfg.height as u64,
            1,
            MAX_MAP_SIDE as u64,
        )?;
        check_range(
            "shadow_compare.depth_bits",
            cfg.depth_bits as u64,
            1,
            MAX_DEPTH_BITS as u64,
        )?;
        check_range(
            "shadow_compare.bias",
            cfg.bias as u64,
            0,
            max_code(cfg.depth_bits) as u64,
        )?;
        check_range(
            "shadow_compare.frag_frac_bits",
            cfg.frag_frac_bits as u64,
            0,
            MAX_FRAG_FRAC_BITS as u64,
        )?;
        if let Some(n) = cfg.texel.required_depth_bits() {
            if cfg.depth_bits != n {
                return Err(ConfigError::invalid(
                    "shadow_compare.texel",
                    &format!(
                        "{:?} texels hold {n}-bit depths, but depth_bits is {}",
                        cfg.texel, cfg.depth_bits
                    ),
                ));
            }
        }
        Ok(ShadowCompare { cfg })
    }

    /// GeForce-era defaults (see [`ShadowCompareConfig::geforce`]).
    pub fn geforce() -> Self {
        ShadowCompare {
            cfg: ShadowCompareConfig::geforce(),
        }
    }

    /// The config the unit was built from.
    pub fn config(&self) -> ShadowCompareConfig {
        self.cfg
    }
    /// Map width in texels, 1 ..= 4096.
    pub fn width(&self) -> u32 {
        self.cfg.width
    }
    /// Map height in texels, 1 ..= 4096.
    pub fn height(&self) -> u32 {
        self.cfg.height
    }
    /// Stored depth width n in bits, 1 ..= 32 (GeForce: 24).
    pub fn depth_bits(&self) -> u32 {
        self.cfg.depth_bits
    }
    /// Depth bias in LSBs of the stored depth, 0 ..= 2ⁿ − 1.
    pub fn bias(&self) -> u32 {
        self.cfg.bias
    }
    /// Extra fraction bits k of the incoming fragment depth, 0 ..= 8.
    pub fn frag_frac_bits(&self) -> u32 {
        self.cfg.frag_frac_bits
    }
    /// The depth compare function (default LEQUAL).
    pub fn compare(&self) -> CompareFunc {
        self.cfg.compare
    }
    /// How a depth-pass write word is read as a depth.
    pub fn texel(&self) -> DepthTexel {
        self.cfg.texel
    }

    /// Width of the input depth wire: the fragment depth (n + k) or a texel word,
    /// whichever is wider.
    pub fn in_depth_bits(&self) -> u32 {
        self.frag_bits()
            .max(self.cfg.texel.word_bits(self.cfg.depth_bits))
    }

    /// The depth a depth-pass write word stands for, per `texel`: u(n).
    #[inline]
    pub fn texel_depth(&self, word: u32) -> u32 {
        (word >> self.cfg.texel.shift()) & self.far() // u32 → u(n) wire
    }

    /// The outcome of a lookup outside the map: the fragment depth clamped to the
    /// far plane, less the bias, against the far plane.
    #[inline]
    fn border_lit(&self, f: u64) -> bool {
        let k = self.cfg.frag_frac_bits;
        let far_k = (self.far() as i64) << k; // u(n+k)
        let fb = (f as i64).min(far_k) - ((self.cfg.bias as i64) << k);
        self.cfg.compare.eval(fb, far_k)
    }

    /// The far-plane code 2ⁿ − 1 (a cleared texel).
    pub fn far(&self) -> u32 {
        max_code(self.cfg.depth_bits)
    }

    /// Width of the fragment-depth wire, n + k.
    pub fn frag_bits(&self) -> u32 {
        self.cfg.depth_bits + self.cfg.frag_frac_bits
    }

    /// Bits of the depth RAM: w · h · n.
    pub fn ram_bits(&self) -> u64 {
        self.cfg.width as u64 * self.cfg.height as u64 * self.cfg.depth_bits as u64
    }

    /// Width of the RAM address y·w + x.
    pub fn addr_bits(&self) -> u32 {
        bits_for(self.cfg.width as u64 * self.cfg.height as u64 - 1)
    }

    /// Clocks a clear would take if done by one write per texel at II 1 (not modelled:
    /// `Clear` is a flash clear; a pipeline may charge this instead).
    pub fn clear_cycles_by_writes(&self) -> u64 {
        self.cfg.width as u64 * self.cfg.height as u64
    }

    /// A cleared depth RAM (every texel at the far plane).
    pub fn fresh_state(&self) -> ShadowState {
        ShadowState {
            ram: bitvec![u64, Lsb0; 1; self.ram_bits() as usize],
        }
    }

    /// Host helper: a stored depth z ∈ [0, 1] as a u(n) unorm word,
    /// round(z·(2ⁿ − 1)) (round to nearest, ties up). z outside [0, 1] is clamped and
    /// counted in `ctr.saturations`; NaN/±∞ is an error naming `shadow_compare.depth`.
    pub fn depth_word(&self, z: f64, ctr: &mut Counters) -> Result<u32, ConfigError> {
        let z = clamp_unit(check_finite("shadow_compare.depth", z)?, ctr);
        let fmt = Format::uint(self.cfg.depth_bits)?;
        let x = z * self.far() as f64; // depth in LSBs
        let v = Fx::from_f64(
            x,
            fmt,
            Quant::Rnd,
            Overflow::Sat,
            "shadow_compare.depth",
            ctr,
        )?;
        Ok(v.raw as u32)
    }

    /// Host helper: a fragment depth z ∈ [0, 1] as a u(n).k word,
    /// round(z·(2ⁿ − 1)·2ᵏ). Clamping and errors as [`Self::depth_word`], the field
    /// being `shadow_compare.frag_depth`.
    pub fn frag_word(&self, z: f64, ctr: &mut Counters) -> Result<u64, ConfigError> {
        let z = clamp_unit(check_finite("shadow_compare.frag_depth", z)?, ctr);
        let fmt = Format::new(self.cfg.depth_bits, self.cfg.frag_frac_bits, false)?;
        let x = z * self.far() as f64; // depth in LSBs, k fraction bits kept below
        let v = Fx::from_f64(
            x,
            fmt,
            Quant::Rnd,
            Overflow::Sat,
            "shadow_compare.frag_depth",
            ctr,
        )?;
        Ok(v.raw as u64)
    }

    /// Host helper: a bias given in depth units (b ∈ [0, 1]) as integer LSBs of an
    /// n-bit depth, round(b·(2ⁿ − 1)). Errors name `shadow_compare.bias` (NaN, ±∞,
    /// negative or > 1) or `shadow_compare.depth_bits`.
    pub fn bias_lsb_from_f64(depth_bits: u32, b: f64) -> Result<u32, ConfigError> {
        check_range(
            "shadow_compare.depth_bits",
            depth_bits as u64,
            1,
            MAX_DEPTH_BITS as u64,
        )?;
        let b = check_finite("shadow_compare.bias", b)?;
        if !(0.0..=1.0).contains(&b) {
            return Err(ConfigError::out_of_range(
                "shadow_compare.bias",
                b,
                0.0,
                1.0,
            ));
        }
        let fmt = Format::uint(depth_bits)?;
        let x = b * max_code(depth_bits) as f64;
        let mut ctr = Counters::default();
        let v = Fx::from_f64(
            x,
            fmt,
            Quant::Rnd,
            Overflow::Sat,
            "shadow_compare.bias",
            &mut ctr,
        )?;
        Ok(v.raw as u32)
    }

    /// RAM address of (x, y), or None outside the map. Coordinates are first clamped
    /// to their s16 wires (which keeps out-of-map coordinates out of the map).
    #[inline]
    pub fn address(&self, x: i32, y: i32) -> Option<usize> {
        // i32 → s16 clamps an out-of-map coordinate to one still out of the map (a
        // side is at most MAX_MAP_SIDE ≤ 2¹⁵), so the map test on the clamped wires
        // is the test on the words: one unsigned compare per axis (a negative word
        // is ≥ 2³¹ as u32).
        const { assert!(MAX_MAP_SIDE <= 1 << (COORD_BITS - 1)) };
        if x as u32 >= self.cfg.width || y as u32 >= self.cfg.height {
            return None;
        }
        // u12 × u13 → u25 (≤ 2²⁴ − 1 for a 4096² map), + u12 → addr_bits.
        Some(y as usize * self.cfg.width as usize + x as usize)
    }

    /// A depth test (`ShadowIn::Test`) against a RAM of this config's size: the
    /// kernel's Test arm, which reads the state and never writes it.
    #[inline]
    fn test(&self, st: &ShadowState, x: i32, y: i32, depth: u64, ctr: &mut Counters) -> ShadowOut {
        self.test_read(x, y, depth, |a| self.read(st, a), ctr)
    }

    /// The test with the stored word at an address from `read` (the packed RAM, or
    /// its words unpacked by [`Self::words`]).
    #[inline(always)]
    fn test_read(
        &self,
        x: i32,
        y: i32,
        depth: u64,
        read: impl Fn(usize) -> u32,
        ctr: &mut Counters,
    ) -> ShadowOut {
        let k = self.cfg.frag_frac_bits;
        let fmask = (1u64 << self.frag_bits()) - 1;
        let f = depth & fmask; // u64 → u(n).k wire, ≤ 40 bits
        let Some(addr) = self.address(x, y) else {
            ctr.saturations += 1; // border lookup: against the far plane
            return ShadowOut {
                lit: self.border_lit(f),
                stored: self.far(),
                written: false,
            };
        };
        ctr.table_reads += 1;
        let s = read(addr); // u(n)
                            // frag − bias·2ᵏ: u(n+k) − u(n+k) → s(n+k+1)
        let fb = f as i64 - ((self.cfg.bias as i64) << k);
        // stored·2ᵏ: u(n) → u(n+k); the compare function on s(n+k+1)
        let lit = self.cfg.compare.eval(fb, (s as i64) << k);
        ShadowOut {
            lit,
            stored: s,
            written: false,
        }
    }

    /// The kernel over a chunk of depth tests against a shared, read-only RAM (threads
    /// test one map at once; a test never writes it). The same outputs and counters as
    /// the kernel; inputs other than `Test`, or a state of another config's size,
    /// return false with nothing done (the caller takes the per-word kernel).
    pub fn test_batch(
        &self,
        st: &ShadowState,
        inputs: &[ShadowIn],
        out: &mut Vec<ShadowOut>,
        ctr: &mut Counters,
    ) -> bool {
        if st.ram.len() as u64 != self.ram_bits()
            || !inputs.iter().all(|i| matches!(i, ShadowIn::Test { .. }))
        {
            return false;
        }
        out.extend(inputs.iter().map(|i| match *i {
            ShadowIn::Test { x, y, depth } => self.test(st, x, y, depth, ctr),
            _ => unreachable!("checked above: tests only"),
        }));
        true
    }

    /// Depth tests against a shared, read-only RAM, kept as indices: for each
    /// `(i, x, y, depth)` of `cands` the test `ShadowIn::Test { x, y, depth }`, and
    /// `i` pushed onto `lit` when it is lit. The outputs' `lit` bits and
    /// the counters of [`Self::test_batch`] on those tests, without building the
    /// input and output words. Returns the number of tests, or None (nothing done)
    /// for a state of another config's size.
    #[inline]
    pub fn test_filter(
        &self,
        st: &ShadowState,
        cands: impl Iterator<Item = (u32, i32, i32, u64)>,
        lit: &mut Vec<u32>,
        ctr: &mut Counters,
    ) -> Option<usize> {
        if st.ram.len() as u64 != self.ram_bits() {
            return None;
        }
        let mut c = Counters::default();
        let mut n = 0;
        for (i, x, y, depth) in cands {
            n += 1;
            if self.test(st, x, y, depth, &mut c).lit {
                lit.push(i);
            }
        }
        *ctr += c;
        Some(n)
    }

    /// The RAM's words in address order (y·width + x), unpacked from a state of this
    /// config's size (else None): what [`Self::test_filter_words`] reads.
    pub fn words(&self, st: &ShadowState) -> Option<Vec<u32>> {
        if st.ram.len() as u64 != self.ram_bits() {
            return None;
        }
        let n = self.cfg.width as usize * self.cfg.height as usize;
        Some((0..n).map(|a| self.read(st, a)).collect())
    }

    /// [`Self::test_filter`] against the words of a read-only RAM unpacked by
    /// [`Self::words`] (a word per address instead of a packed field): the same
    /// kept indices and counters. None (nothing done) when `words` is not one word
    /// per address of this config.
    #[inline]
    pub fn test_filter_words(
        &self,
        words: &[u32],
        cands: impl Iterator<Item = (u32, i32, i32, u64)>,
        lit: &mut Vec<u32>,
        ctr: &mut Counters,
    ) -> Option<usize> {
        if words.len() != self.cfg.width as usize * self.cfg.height as usize {
            return None;
        }
        let mut c = Counters::default();
        let mut n = 0;
        for (i, x, y, depth) in cands {
            n += 1;
            if self.test_read(x, y, depth, |a| words[a], &mut c).lit {
                lit.push(i);
            }
        }
        *ctr += c;
        Some(n)
    }

    /// [`Self::test_filter_words`] over lanes `0..len`, lane i a candidate when
    /// `cand(i).0`, tested at (x, y, depth) = `cand(i).1 ..`: the same kept indices
    /// (ascending), counters and count, each lane tested without a branch (a lane
    /// that is no candidate, or off the map, reads word 0 and is masked off), so a
    /// chunk of walked pixels is filtered in one pass.
    pub fn test_filter_lanes(
        &self,
        words: &[u32],
        len: usize,
        cand: impl Fn(usize) -> (bool, i32, i32, u64),
        lit: &mut Vec<u32>,
        ctr: &mut Counters,
    ) -> Option<usize> {
        let (w, h) = (self.cfg.width, self.cfg.height);
        if words.len() != w as usize * h as usize || len > u32::MAX as usize {
            return None;
        }
        let base = lit.len();
        lit.resize(base + len, 0);
        let dst = &mut lit[base..];
        let (mut kept, mut n, mut reads) = (0usize, 0usize, 0usize);
        for i in 0..len {
            let (is_cand, x, y, depth) = cand(i);
            let (in_map, l) = self.lane_test(words, x, y, depth);
            dst[kept] = i as u32;
            kept += usize::from(is_cand & l);
            n += usize::from(is_cand);
            reads += usize::from(is_cand & in_map);
        }
        lit.truncate(base + kept);
        self.count_tests(reads, n - reads, ctr);
        Some(n)
    }

    /// `lane_test` at one fragment depth word `depth` for every lane, in a `vw` × `vh`
    /// viewport: its left side computed once.
    fn flat_test(&self, depth: u64, (vw, vh): (u32, u32)) -> FlatTest {
        let k = self.cfg.frag_frac_bits;
        let fmask = (1u64 << self.frag_bits()) - 1;
        FlatTest {
            fb: (depth & fmask) as i64 - ((self.cfg.bias as i64) << k),
            k,
            border: self.border_lit(depth & fmask),
            compare: self.cfg.compare,
            viewport: (vw as i64, vh as i64),
            map: (self.cfg.width as i64, self.cfg.height as i64),
        }
    }

    /// The least and the greatest word of each row of the unpacked `words`
    /// ([`Self::words`]): the rows [`Self::test_filter_flat_rows`] may decide at once.
    pub fn row_ranges(&self, words: &[u32]) -> Vec<(u32, u32)> {
        let row = (self.cfg.width as usize).max(1);
        let range = |r: &[u32]| {
            let lo = r.iter().fold(u32::MAX, |m, &w| m.min(w));
            (lo, r.iter().fold(0, |m, &w| m.max(w)))
        };
        words.chunks(row).map(range).collect()
    }

    /// [`Self::test_filter_flat`], with the lanes decided at once where every lane is
    /// covered, inside the viewport and on the map, and every row they lie on gives
    /// every word it holds one outcome at `depth`, the same for all the rows (`rows`:
    /// [`Self::row_ranges`] of `words`; a row holds one word, or the function
    /// [`CompareFunc::is_monotone`] gives its least and greatest words one outcome):
    /// then each lane is a candidate read on the map, and all are kept or none is.
    /// The same kept indices, counters and count either way.
    pub fn test_filter_flat_rows(
        &self,
        (words, rows): (&[u32], &[(u32, u32)]),
        lanes: (&[i64], &[i64], &[bool]),
        viewport: (u32, u32),
        depth: u64,
        lit: &mut Vec<u32>,
        ctr: &mut Counters,
    ) -> Option<usize> {
        let h = self.cfg.height as usize;
        if rows.len() == h && words.len() == self.cfg.width as usize * h {
            if let Some(all) = self.flat_rows_outcome(rows, lanes, viewport, depth) {
                let n = lanes.0.len();
                if all {
                    lit.extend(0..n as u32);
                }
                self.count_tests(n, 0, ctr);
                return Some(n);
            }
        }
        self.test_filter_flat(words, lanes, viewport, depth, lit, ctr)
    }

    /// [`Self::test_filter_flat_rows`]'s decision: Some(the outcome every lane gets)
    /// where the lanes (at least one, of one length) are covered, in the viewport
    /// and on the map, on rows whose every word has that outcome.
    fn flat_rows_outcome(
        &self,
        rows: &[(u32, u32)],
        (x, y, inside): (&[i64], &[i64], &[bool]),
        viewport: (u32, u32),
        depth: u64,
    ) -> Option<bool> {
        let n = x.len();
        if n == 0 || y.len() != n || inside.len() != n {
            return None;
        }
        let test = self.flat_test(depth, viewport);
        let monotone = self.cfg.compare.is_monotone();
        // A row's one outcome: its word's where it holds one word, else its least and
        // greatest words' where they agree and the function is monotone.
        let row_outcome = |&(lo, hi): &(u32, u32)| {
            let (a, b) = (test.on_map(lo), test.on_map(hi));
            (a == b && (lo == hi || monotone)).then_some(a)
        };
        // The first and the last lane's rows first: where either has no one outcome
        // (or is off the map), nothing is scanned.
        let uniform =
            |y: i64| usize::try_from(y).is_ok_and(|r| rows.get(r).and_then(row_outcome).is_some());
        // (Every lane covered: a fold without an early exit runs as vectors.)
        let covered = inside.iter().fold(true, |all, &c| all & c);
        if !uniform(y[0]) || !uniform(y[n - 1]) || !covered {
            return None;
        }
        let ((x0, x1), (y0, y1)) = (lane_bounds(x), lane_bounds(y));
        let ((vw, vh), (mw, mh)) = (test.viewport, test.map);
        if x0 < 0 || y0 < 0 || x1 >= vw.min(mw) || y1 >= vh.min(mh) {
            return None;
        }
        let mut outcome = None;
        for row in &rows[y0 as usize..=y1 as usize] {
            let lit = row_outcome(row)?;
            if outcome.is_some_and(|o| o != lit) {
                return None;
            }
            outcome = Some(lit);
        }
        outcome
    }

    /// [`Self::test_filter_lanes`] where every lane tests the one depth word `depth`
    /// (a plane parallel to the screen) and lane i is a candidate when `inside[i]` and
    /// `(x[i], y[i])` lies in the `vw` × `vh` viewport, tested at `(x[i], y[i])`: the same
    /// kept indices, counters and count. The lanes are read straight from the slices
    /// and the biased fragment depth is computed once, so the loop holds no closure
    /// state. None (nothing done) when `words` is not one word per address or the
    /// lanes' lengths differ.
    pub fn test_filter_flat(
        &self,
        words: &[u32],
        (x, y, inside): (&[i64], &[i64], &[bool]),
        (vw, vh): (u32, u32),
        depth: u64,
        lit: &mut Vec<u32>,
        ctr: &mut Counters,
    ) -> Option<usize> {
        let (w, h) = (self.cfg.width, self.cfg.height);
        let len = x.len();
        if words.len() != w as usize * h as usize
            || y.len() != len
            || inside.len() != len
            || len > u32::MAX as usize
        {
            return None;
        }
        let test = self.flat_test(depth, (vw, vh));
        let base = lit.len();
        lit.resize(base + len, 0);
        let dst = &mut lit[base..];
        #[cfg(any(avx512_lanes, avx2_lanes))]
        let lanes = FlatLanes {
            words,
            x,
            y,
            inside,
        };
        // Whole groups of 8 lanes in vector registers where the CPU has them, the rest
        // one lane at a time: the same kept indices and counts either way.
        #[cfg(avx512_lanes)]
        // SAFETY: compiled only where the build has these features (`avx512_lanes`,
        // rtl_model/build.rs).
        let (done, mut t) = unsafe { flat_groups_avx512(&lanes, &test, dst) };
        #[cfg(avx2_lanes)]
        // SAFETY: compiled only where the build has AVX2 (`avx2_lanes`, rtl_model/build.rs).
        let (done, mut t) = unsafe { flat_groups_avx2(&lanes, &test, dst) };
        #[cfg(not(any(avx512_lanes, avx2_lanes)))]
        let (done, mut t) = (0, FlatTally::default());
        for i in done..len {
            let (cand, in_map, l) = test.lane(words, x[i], y[i], inside[i]);
            dst[t.kept] = i as u32;
            t.add(
                usize::from(cand & l),
                usize::from(cand),
                usize::from(in_map),
            );
        }
        let FlatTally { kept, n, reads } = t;
        lit.truncate(base + kept);
        self.count_tests(reads, n - reads, ctr);
        Some(n)
    }

    /// Depth tests of lanes against a read-only RAM's words unpacked by
    /// [`Self::words`], lane i the test `ShadowIn::Test` at (x, y, depth) =
    /// `(x[i], y[i], depth[i])`: its output's `lit` bit pushed onto `lit` (in lane
    /// order), the counters those of [`Self::test_batch`] on those tests, without the
    /// input and output words and without a branch (a lane off the map reads word 0
    /// and takes the border's outcome), so the compiler runs the lanes as vectors.
    /// None (nothing done) when `words` is not one word per address or the lanes'
    /// lengths differ.
    pub fn test_lit_lanes(
        &self,
        words: &[u32],
        (x, y, depth): (&[i32], &[i32], &[u64]),
        lit: &mut Vec<bool>,
        ctr: &mut Counters,
    ) -> Option<usize> {
        let (w, h) = (self.cfg.width, self.cfg.height);
        let len = x.len();
        if words.len() != w as usize * h as usize || y.len() != len || depth.len() != len {
            return None;
        }
        let k = self.cfg.frag_frac_bits;
        let fmask = (1u64 << self.frag_bits()) - 1;
        let bias = (self.cfg.bias as i64) << k;
        let far = (self.far() as i64) << k; // u(n+k)
        let compare = self.cfg.compare;
        let base = lit.len();
        lit.resize(base + len, false);
        let mut reads = 0usize;
        for (((l, &xi), &yi), &d) in lit[base..].iter_mut().zip(x).zip(y).zip(depth) {
            // `address`'s test: one unsigned compare per axis.
            let in_map = ((xi as u32) < w) & ((yi as u32) < h);
            let a = if in_map {
                yi as usize * w as usize + xi as usize
            } else {
                0
            };
            // SAFETY: on the map a = y·w + x ≤ (h − 1)·w + w − 1 < w·h = words.len()
            // (checked above); off it a = 0 < words.len() (w, h ≥ 1, `new`).
            let word = unsafe { *words.get_unchecked(a) };
            let f = (d & fmask) as i64;
            let on_map = compare.eval(f - bias, (word as i64) << k);
            // `border_lit`: the cleared texel's far depth.
            let border = compare.eval(f.min(far) - bias, far);
            *l = if in_map { on_map } else { border };
            reads += usize::from(in_map);
        }
        self.count_tests(reads, len - reads, ctr);
        Some(len)
    }

    /// The counters of `on_map` tests at a texel on the map and `off_map` off it (a
    /// border lookup), whatever their depths: what the kernel counts on them.
    pub fn count_tests(&self, on_map: usize, off_map: usize, ctr: &mut Counters) {
        ctr.table_reads += on_map as u64;
        ctr.saturations += off_map as u64;
    }

    /// One test of the lane forms on unpacked words (one word per address, checked
    /// by the caller), without a branch: (inside the map, lit). A lane off the map
    /// reads word 0, masked off: a border lookup, lit by convention.
    #[inline(always)]
    fn lane_test(&self, words: &[u32], x: i32, y: i32, depth: u64) -> (bool, bool) {
        let (w, h) = (self.cfg.width, self.cfg.height);
        let k = self.cfg.frag_frac_bits;
        let fmask = (1u64 << self.frag_bits()) - 1;
        let bias = (self.cfg.bias as i64) << k;
        // `address`'s test: one unsigned compare per axis.
        let in_map = (x as u32) < w && (y as u32) < h;
        let a = if in_map {
            y as usize * w as usize + x as usize
        } else {
            0
        };
        let f = depth & fmask;
        let fb = f as i64 - bias;
        let l = if in_map {
            self.cfg.compare.eval(fb, (words[a] as i64) << k)
        } else {
            self.border_lit(f)
        };
        (in_map, l)
    }

    #[inline]
    fn read(&self, st: &ShadowState, addr: usize) -> u32 {
        let n = self.cfg.depth_bits as usize;
        crate::packed_rom::read_field(st.ram.as_raw_slice(), addr * n, n as u32) as u32
    }

    #[inline]
    fn write(&self, st: &mut ShadowState, addr: usize, d: u32) {
        let n = self.cfg.depth_bits as usize;
        st.ram[addr * n..(addr + 1) * n].store_le::<u32>(d);
    }
}

/// [`ShadowCompare::test_filter_flat`]'s test of one lane, its constants computed
/// once: the biased fragment depth `fb` (s(n+k+1)), the frac bits k of the word's
/// left shift, the border's outcome, the function, the viewport's and the map's size.
struct FlatTest {
    fb: i64,
    k: u32,
    border: bool,
    compare: CompareFunc,
    viewport: (i64, i64),
    map: (i64, i64),
}

impl FlatTest {
    /// Lane (x, y, inside): whether it is a candidate (covered, 0 ≤ x < vw,
    /// 0 ≤ y < vh: `lane_test`'s wires hold it), whether it reads the map, and the
    /// test's outcome (the border's off the map).
    #[inline(always)]
    fn lane(&self, words: &[u32], x: i64, y: i64, inside: bool) -> (bool, bool, bool) {
        let ((vw, vh), (mw, mh)) = (self.viewport, self.map);
        let cand = inside & (x >= 0) & (y >= 0) & (x < vw) & (y < vh);
        let in_map = cand & (x < mw) & (y < mh);
        // Off the map word 0 is read and masked off: no branch.
        let a = if in_map { (y * mw + x) as usize } else { 0 };
        let on_map = self.on_map(words[a]);
        (cand, in_map, (!in_map & self.border) | (in_map & on_map))
    }

    /// The test's outcome at an address on the map that holds `word`.
    #[inline(always)]
    fn on_map(&self, word: u32) -> bool {
        self.compare.eval(self.fb, (word as i64) << self.k)
    }
}

/// The least and the greatest of `v` (i64::MAX and i64::MIN when empty): two
/// reductions the compiler runs as vectors.
fn lane_bounds(v: &[i64]) -> (i64, i64) {
    let lo = v.iter().fold(i64::MAX, |m, &c| m.min(c));
    let hi = v.iter().fold(i64::MIN, |m, &c| m.max(c));
    (lo, hi)
}

/// Counts of [`ShadowCompare::test_filter_flat`]'s lanes: kept, candidates, map reads.
#[derive(Default)]
struct FlatTally {
    kept: usize,
    n: usize,
    reads: usize,
}

impl FlatTally {
    #[inline(always)]
    fn add(&mut self, kept: usize, n: usize, reads: usize) {
        self.kept += kept;
        self.n += n;
        self.reads += reads;
    }
}

/// [`ShadowCompare::test_filter_flat`]'s inputs as its vector forms take them: the
/// map's words (one per address) and the lanes' x, y and coverage.
#[cfg(any(avx512_lanes, avx2_lanes))]
#[derive(Clone, Copy)]
struct FlatLanes<'a> {
    words: &'a [u32],
    x: &'a [i64],
    y: &'a [i64],
    inside: &'a [bool],
}

#[cfg(any(avx512_lanes, avx2_lanes))]
impl FlatLanes<'_> {
    /// Whole groups of 8 lanes that lie in every lane slice and in `dst` (none
    /// without words to read).
    fn groups(&self, dst: &[u32]) -> usize {
        if self.words.is_empty() {
            return 0;
        }
        self.x
            .len()
            .min(self.y.len())
            .min(self.inside.len())
            .min(dst.len())
            / 8
    }
}

/// [`ShadowCompare::test_filter_flat`]'s lanes in whole groups of 8, in AVX-512
/// registers: each group's candidates, map reads and outcomes as 8-bit masks, the
/// words read as a block along a walk row or gathered under the map mask, the kept
/// indices packed into `dst` at the running count. Returns the lanes done (a multiple
/// of 8) and their tally. Without `avx512_lanes` it is not built (AVX2 builds take
/// `flat_groups_avx2`; others take every lane one at a time).
#[cfg(avx512_lanes)]
#[target_feature(enable = "avx512f,avx512bw,avx512vl")]
fn flat_groups_avx512(lanes: &FlatLanes, t: &FlatTest, dst: &mut [u32]) -> (usize, FlatTally) {
    use std::arch::x86_64::*;
    let FlatLanes {
        words,
        x,
        y,
        inside,
    } = *lanes;
    let groups = lanes.groups(dst);
    let mut tally = FlatTally::default();
    let ((vw, vh), (mw, mh)) = (t.viewport, t.map);
    let (zero, fb) = (_mm512_setzero_si512(), _mm512_set1_epi64(t.fb));
    let (vw, vh) = (_mm512_set1_epi64(vw), _mm512_set1_epi64(vh));
    let (mwv, mhv) = (_mm512_set1_epi64(mw), _mm512_set1_epi64(mh));
    let shift = _mm512_set1_epi64(t.k as i64);
    let border: u8 = if t.border { 0xff } else { 0 };
    // The function's code as three lane masks: bit 0 keeps "less", 1 "equal",
    // 2 "greater".
    let code = t.compare.code();
    let [on_lt, on_eq, on_gt] = [0, 1, 2].map(|b| 0u8.wrapping_sub((code >> b & 1) as u8));
    let lane_index = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    let lane_offset = _mm512_setr_epi64(0, 1, 2, 3, 4, 5, 6, 7);
    let lane_back = _mm512_setr_epi64(0, -1, -2, -3, -4, -5, -6, -7);
    let lane_reverse = _mm256_setr_epi32(7, 6, 5, 4, 3, 2, 1, 0);
    for g in 0..groups {
        let o = g * 8;
        // SAFETY: lanes o .. o + 8 lie in x, y, inside and dst (o + 8 ≤ 8 · groups,
        // each at least that long); bool is one byte, 0 or 1.
        let (xv, yv, ins) = unsafe {
            (
                _mm512_loadu_si512(x.as_ptr().add(o).cast()),
                _mm512_loadu_si512(y.as_ptr().add(o).cast()),
                _mm_loadl_epi64(inside.as_ptr().add(o).cast()),
            )
        };
        let covered = _mm_cmpneq_epi8_mask(ins, _mm_setzero_si128()) as u8;
        let cand = covered
            & _mm512_cmpge_epi64_mask(xv, zero)
            & _mm512_cmpge_epi64_mask(yv, zero)
            & _mm512_cmplt_epi64_mask(xv, vw)
            & _mm512_cmplt_epi64_mask(yv, vh);
        let in_map = cand & _mm512_cmplt_epi64_mask(xv, mwv) & _mm512_cmplt_epi64_mask(yv, mhv);
        // y · w + x on the low 32 bits of each lane: exact where the map is read
        // (0 ≤ x < w, 0 ≤ y < h), the only lanes loaded. Eight lanes of one row of
        // the walk (x₀ … x₀ ± 7, one y: the walk goes back and forth), all on the map,
        // are eight words in a row: one load (reversed for a leftward row). Others are
        // gathered (slow on some CPUs), under the map mask.
        let addr = _mm512_add_epi64(_mm512_mul_epi32(yv, mwv), xv);
        let x0 = _mm512_set1_epi64(_mm_cvtsi128_si64(_mm512_castsi512_si128(xv)));
        let y0 = _mm512_set1_epi64(_mm_cvtsi128_si64(_mm512_castsi512_si128(yv)));
        let dx = _mm512_sub_epi64(xv, x0);
        let one_row = in_map == 0xff && _mm512_cmpeq_epi64_mask(yv, y0) == 0xff;
        let a0 = _mm_cvtsi128_si64(_mm512_castsi512_si128(addr)) as usize;
        let gathered = if one_row && _mm512_cmpeq_epi64_mask(dx, lane_offset) == 0xff {
            // SAFETY: every lane is on the map, so a0 + 7 (the last lane's address)
            // < w · h = words.len().
            unsafe { _mm256_loadu_si256(words.as_ptr().add(a0).cast()) }
        } else if one_row && _mm512_cmpeq_epi64_mask(dx, lane_back) == 0xff {
            // SAFETY: every lane is on the map, so a0 − 7 (the last lane's address)
            // ≥ 0 and a0 < words.len().
            let ahead = unsafe { _mm256_loadu_si256(words.as_ptr().add(a0 - 7).cast()) };
            _mm256_permutexvar_epi32(lane_reverse, ahead)
        } else {
            // SAFETY: a lane in the map mask has 0 ≤ addr < w · h = words.len(); the
            // others are not loaded.
            unsafe {
                _mm512_mask_i64gather_epi32::<4>(
                    _mm256_setzero_si256(),
                    in_map,
                    addr,
                    words.as_ptr().cast(),
                )
            }
        };
        let word = _mm512_sllv_epi64(_mm512_cvtepu32_epi64(gathered), shift);
        let (gt, eq) = (
            _mm512_cmpgt_epi64_mask(fb, word),
            _mm512_cmpeq_epi64_mask(fb, word),
        );
        let outcome = (on_lt & !(gt | eq)) | (on_eq & eq) | (on_gt & gt);
        let keep = cand & ((!in_map & border) | (in_map & outcome));
        let index = _mm256_add_epi32(lane_index, _mm256_set1_epi32(o as i32));
        // The kept indices packed in a register and stored whole (a compressing store
        // to memory is slow on some CPUs): the words past the kept ones are written
        // over by the next group or cut off by the caller.
        // SAFETY: kept ≤ o, so the 8 words from dst[kept] lie within dst[.. o + 8].
        unsafe {
            _mm256_storeu_si256(
                dst.as_mut_ptr().add(tally.kept).cast(),
                _mm256_maskz_compress_epi32(keep, index),
            )
        };
        tally.add(
            keep.count_ones() as usize,
            cand.count_ones() as usize,
            in_map.count_ones() as usize,
        );
    }
    (groups * 8, tally)
}

/// Byte mask m's set bits' positions, lowest first, as the nibbles of one word (lane
/// position p in bits 4p .. 4p + 4; the rest 0): [`flat_groups_avx2`]'s packing of
/// the kept lanes, without a compress instruction.
#[cfg(avx2_lanes)]
const PACKED_LANES: [u32; 256] = {
    let mut table = [0u32; 256];
    let mut m = 0;
    while m < 256 {
        let (mut word, mut n, mut bit) = (0u32, 0, 0);
        while bit < 8 {
            if m >> bit & 1 == 1 {
                word |= bit << (4 * n);
                n += 1;
            }
            bit += 1;
        }
        table[m as usize] = word;
        m += 1;
    }
    table
};

/// [`ShadowCompare::test_filter_flat`]'s lanes in whole groups of 8 with AVX2 (two
/// registers of four 64-bit lanes per coordinate): each group's candidates, map reads
/// and outcomes as 8-bit masks, the words read as one block along a walk row (eight
/// lanes of one row, all on the map, read eight words in a row) or else one lane at a
/// time under the map mask, the kept indices packed through [`PACKED_LANES`] into
/// `dst` at the running count. Returns the lanes done (a multiple of 8) and their
/// tally: the same as [`FlatTest::lane`] one lane at a time.
#[cfg(avx2_lanes)]
#[target_feature(enable = "avx2")]
fn flat_groups_avx2(lanes: &FlatLanes, t: &FlatTest, dst: &mut [u32]) -> (usize, FlatTally) {
    use std::arch::x86_64::*;
    let (words, x, y) = (lanes.words, lanes.x, lanes.y);
    let ((vw, vh), (mw, mh)) = (t.viewport, t.map);
    let below = _mm256_set1_epi64x(-1);
    let (vwv, vhv) = (_mm256_set1_epi64x(vw), _mm256_set1_epi64x(vh));
    let (mwv, mhv) = (_mm256_set1_epi64x(mw), _mm256_set1_epi64x(mh));
    let fb = _mm256_set1_epi64x(t.fb);
    let shift = _mm_cvtsi64_si128(t.k as i64);
    let border: u32 = if t.border { 0xff } else { 0 };
    // The function's code as three lane masks: bit 0 keeps "less", 1 "equal",
    // 2 "greater".
    let code = t.compare.code();
    let [on_lt, on_eq, on_gt] = [0, 1, 2].map(|b| 0u32.wrapping_sub(code >> b & 1) & 0xff);
    let (ahead_lo, ahead_hi) = (
        _mm256_setr_epi64x(0, 1, 2, 3),
        _mm256_setr_epi64x(4, 5, 6, 7),
    );
    let (back_lo, back_hi) = (
        _mm256_setr_epi64x(0, -1, -2, -3),
        _mm256_setr_epi64x(-4, -5, -6, -7),
    );
    let lane_reverse = _mm256_setr_epi32(7, 6, 5, 4, 3, 2, 1, 0);
    let nibble_shift = _mm256_setr_epi32(0, 4, 8, 12, 16, 20, 24, 28);
    let bits = |v: __m256i| _mm256_movemask_pd(_mm256_castsi256_pd(v)) as u32;
    let all = |v: __m256i| _mm256_movemask_epi8(v) == -1;
    let (groups, mut tally) = (lanes.groups(dst), FlatTally::default());
    for g in 0..groups {
        let o = g * 8;
        // SAFETY: lanes o .. o + 8 lie in x, y, inside and dst (o + 8 ≤ 8 · groups,
        // each at least that long); bool is one byte, 0 or 1.
        let (x_lo, x_hi, y_lo, y_hi, ins) = unsafe {
            (
                _mm256_loadu_si256(x.as_ptr().add(o).cast()),
                _mm256_loadu_si256(x.as_ptr().add(o + 4).cast()),
                _mm256_loadu_si256(y.as_ptr().add(o).cast()),
                _mm256_loadu_si256(y.as_ptr().add(o + 4).cast()),
                _mm_loadl_epi64(lanes.inside.as_ptr().add(o).cast()),
            )
        };
        let covered = _mm_movemask_epi8(_mm_cmpgt_epi8(ins, _mm_setzero_si128())) as u32 & 0xff;
        let half = |xv: __m256i, yv: __m256i| {
            let on_screen = _mm256_and_si256(
                _mm256_and_si256(_mm256_cmpgt_epi64(xv, below), _mm256_cmpgt_epi64(yv, below)),
                _mm256_and_si256(_mm256_cmpgt_epi64(vwv, xv), _mm256_cmpgt_epi64(vhv, yv)),
            );
            let on_map = _mm256_and_si256(_mm256_cmpgt_epi64(mwv, xv), _mm256_cmpgt_epi64(mhv, yv));
            (bits(on_screen), bits(_mm256_and_si256(on_screen, on_map)))
        };
        let ((c_lo, m_lo), (c_hi, m_hi)) = (half(x_lo, y_lo), half(x_hi, y_hi));
        let cand = covered & (c_lo | c_hi << 4);
        let in_map = cand & (m_lo | m_hi << 4);
        let (x0, y0) = (_mm256_set1_epi64x(x[o]), _mm256_set1_epi64x(y[o]));
        let one_row = in_map == 0xff
            && all(_mm256_cmpeq_epi64(y_lo, y0))
            && all(_mm256_cmpeq_epi64(y_hi, y0));
        let (dx_lo, dx_hi) = (_mm256_sub_epi64(x_lo, x0), _mm256_sub_epi64(x_hi, x0));
        let along = |lo: __m256i, hi: __m256i| {
            all(_mm256_cmpeq_epi64(dx_lo, lo)) && all(_mm256_cmpeq_epi64(dx_hi, hi))
        };
        // Computed for a row on the map alone, where 0 ≤ x < w and 0 ≤ y < h:
        // y · w + x < w · h = words.len() (elsewhere the lanes may be any s64).
        let a0 = if one_row {
            (y[o] * mw + x[o]) as usize
        } else {
            0
        };
        let read = if one_row && along(ahead_lo, ahead_hi) {
            // SAFETY: every lane is on the map, so a0 + 7 (the last lane's address)
            // < words.len().
            unsafe { _mm256_loadu_si256(words.as_ptr().add(a0).cast()) }
        } else if one_row && along(back_lo, back_hi) {
            // SAFETY: every lane is on the map, so a0 − 7 (the last lane's address)
            // ≥ 0 and a0 < words.len().
            let ahead = unsafe { _mm256_loadu_si256(words.as_ptr().add(a0 - 7).cast()) };
            _mm256_permutevar8x32_epi32(ahead, lane_reverse)
        } else {
            let mut w8 = [0u32; 8];
            for (l, w) in w8.iter_mut().enumerate() {
                if in_map >> l & 1 == 1 {
                    *w = words[(y[o + l] * mw + x[o + l]) as usize];
                }
            }
            // SAFETY: w8 is 8 words.
            unsafe { _mm256_loadu_si256(w8.as_ptr().cast()) }
        };
        let word_lo = _mm256_sll_epi64(_mm256_cvtepu32_epi64(_mm256_castsi256_si128(read)), shift);
        let word_hi = _mm256_sll_epi64(
            _mm256_cvtepu32_epi64(_mm256_extracti128_si256::<1>(read)),
            shift,
        );
        let gt = bits(_mm256_cmpgt_epi64(fb, word_lo)) | bits(_mm256_cmpgt_epi64(fb, word_hi)) << 4;
        let eq = bits(_mm256_cmpeq_epi64(fb, word_lo)) | bits(_mm256_cmpeq_epi64(fb, word_hi)) << 4;
        let outcome = (on_lt & !(gt | eq)) | (on_eq & eq) | (on_gt & gt);
        let keep = cand & ((!in_map & border) | (in_map & outcome));
        let packed = _mm256_srlv_epi32(
            _mm256_set1_epi32(PACKED_LANES[keep as usize] as i32),
            nibble_shift,
        );
        let index = _mm256_add_epi32(
            _mm256_and_si256(packed, _mm256_set1_epi32(0xf)),
            _mm256_set1_epi32(o as i32),
        );
        // The kept indices stored whole: the words past the kept ones are written over
        // by the next group or cut off by the caller.
        // SAFETY: kept ≤ o, so the 8 words from dst[kept] lie within dst[.. o + 8].
        unsafe { _mm256_storeu_si256(dst.as_mut_ptr().add(tally.kept).cast(), index) };
        tally.add(
            keep.count_ones() as usize,
            cand.count_ones() as usize,
            in_map.count_ones() as usize,
        );
    }
    (groups * 8, tally)
}

fn max_code(bits: u32) -> u32 {
    if bits >= 32 {
        u32::MAX
    } else {
        (1u32 << bits) - 1
    }
}

fn clamp_unit(z: f64, ctr: &mut Counters) -> f64 {
    if (0.0..=1.0).contains(&z) {
        z
    } else {
        ctr.saturations += 1;
        z.clamp(0.0, 1.0)
    }
}

impl Unit for ShadowCompare {
    type In = ShadowIn;
    type Out = ShadowOut;
    type State = ShadowState;

    fn name(&self) -> &'static str {
        "shadow_compare"
    }

    fn kernel(&self, st: &mut ShadowState, input: &ShadowIn, ctr: &mut Counters) -> ShadowOut {
        // The RAM is part of the unit: a state of another config's size is replaced by
        // a cleared RAM of this one (never an out-of-bounds read).
        if st.ram.len() as u64 != self.ram_bits() {
            *st = self.fresh_state();
        }
        let far = self.far();
        match *input {
            ShadowIn::Clear => {
                st.ram.fill(true); // every word = 2ⁿ − 1
                ShadowOut {
                    lit: false,
                    stored: far,
                    written: false,
                }
            }
            ShadowIn::Write { x, y, depth } => {
                let Some(addr) = self.address(x, y) else {
                    ctr.saturations += 1; // clipped to the border: dropped
                    return ShadowOut {
                        lit: false,
                        stored: far,
                        written: false,
                    };
                };
                let d = self.texel_depth(depth); // texel word → u(n) wire
                ctr.table_reads += 1; // read half of the read-modify-write
                let old = self.read(st, addr); // u(n)
                let written = d < old; // n-bit comparator (z-buffer LESS)
                if written {
                    self.write(st, addr, d);
                }
                ShadowOut {
                    lit: false,
                    stored: d.min(old),
                    written,
                }
            }
            ShadowIn::Test { x, y, depth } => self.test(st, x, y, depth, ctr),
        }
    }

    /// Chunks of tests run through [`ShadowCompare::test_batch`]; anything else (a
    /// write, a clear, a state to be replaced) word by word.
    fn kernel_batch(
        &self,
        st: &mut ShadowState,
        inputs: &[ShadowIn],
        out: &mut Vec<ShadowOut>,
        ctr: &mut Counters,
    ) {
        if !self.test_batch(st, inputs, out, ctr) {
            out.extend(inputs.iter().map(|x| self.kernel(st, x, ctr)));
        }
    }

    fn timing(&self) -> Timing {
        // Stage 1: address y·w + x and the RAM read; stage 2: bias subtract and compare
        // (writes: the LESS compare and the write-back). A Test or Write right behind a
        // Write to the same texel gets the new word through a forwarding mux.
        Timing { latency: 2, ii: 1 }
    }

    fn cost(&self) -> Cost {
        let n = self.cfg.depth_bits;
        let k = self.cfg.frag_frac_bits;
        let a = self.addr_bits();
        let yb = bits_for(self.cfg.height as u64 - 1);
        let wb = bits_for(self.cfg.width as u64);
        let xb = bits_for(self.cfg.width as u64 - 1);
        // No input register: as in the Verilog (rtl_model/verilog/units/shadow_compare.v),
        // the two clocks of `timing()` are the stage-1 registers (beside the RAM read)
        // and the output register; the inputs feed the map test and the address
        // directly.
        let c = Cost::default().part(
            "out-of-map checks (x ≥ w, y ≥ h, signs)",
            prim::comparator(COORD_BITS) * 2.0
                + Cells {
                    or2: 3.0,
                    ..Cells::default()
                },
        );
        // y·w + x: wires when w is a power of two ({y, x} concatenated); otherwise a
        // general y × w multiplier and an adder (an upper estimate: a synthesised
        // constant w would reduce it to shift-adds).
        let c = if self.cfg.width.is_power_of_two() {
            c.part("address {y, x} (w a power of two: wires)", Cells::default())
        } else {
            c.part("address multiplier y·w", prim::multiplier(yb, wb))
                .part("address adder + x", prim::adder(a.max(xb)))
        };
        let c = c.part(
            "stage-1 registers (address, depth word, op, in-map)",
            prim::register(a + self.in_depth_bits() + 3),
        );
        // LEQUAL is the one comparator's output; any other function adds an equality
        // compare, the 3:1 truth-table mux of the function's code, and the border's
        // fragment clamp (an AND of the integer bits, an OR of the fraction bits).
        let c = if self.cfg.compare == CompareFunc::Lequal {
            c
        } else {
            c.part(
                "compare function (equality, truth-table mux, border clamp)",
                prim::comparator(n + k + 1) + prim::mux_k(1, 3) + prim::mux(n + k),
            )
        };
        c.part(
            "bias subtractor frag − bias·2^k",
            prim::subtractor(n + k + 1),
        )
        .part(
            "depth comparator (LEQUAL test / LESS write)",
            prim::comparator(n + k + 1),
        )
        .part("compare operand mux (test / write)", prim::mux(n + k + 1))
        .part(
            "write forwarding (address match + bypass mux)",
            prim::comparator(a) + prim::mux(n),
        )
        .part(
            "write forwarding registers (clear, write enable, address, word)",
            prim::register(2 + a + n),
        )
        .part(
            "output register (lit, written, stored)",
            prim::register(n + 2),
        )
        .with_ram_bits(self.ram_bits())
    }

    fn widths(&self) -> Vec<Width> {
        vec![
            Width {
                name: "depth_bits",
                bits: self.cfg.depth_bits,
            },
            Width {
                name: "frag_frac_bits",
                bits: self.cfg.frag_frac_bits,
            },
            Width {
                name: "frag_bits",
                bits: self.frag_bits(),
            },
            Width {
                name: "addr_bits",
                bits: self.addr_bits(),
            },
            Width {
                name: "coord_bits",
                bits: COORD_BITS,
            },
        ]
    }

    fn in_signals(&self, i: &ShadowIn) -> Vec<Signal> {
        let m16 = (1u64 << COORD_BITS) - 1;
        let lim = 1i32 << (COORD_BITS - 1);
        let wire = |v: i32| v.clamp(-lim, lim - 1) as i64 as u64 & m16; // i32 → s16
        let (op, x, y, d) = match *i {
            ShadowIn::Clear => (0u64, 0i32, 0i32, 0u64),
            ShadowIn::Write { x, y, depth } => {
                let tb = self.cfg.texel.word_bits(self.cfg.depth_bits);
                (1, x, y, depth as u64 & ((1u64 << tb) - 1))
            }
            ShadowIn::Test { x, y, depth } => (2, x, y, depth & ((1u64 << self.frag_bits()) - 1)),
        };
        vec![
            Signal::new("op", 2, op),
            Signal::new("x", COORD_BITS, wire(x)),
            Signal::new("y", COORD_BITS, wire(y)),
            Signal::new("depth", self.in_depth_bits(), d),
        ]
    }

    fn out_signals(&self, o: &ShadowOut) -> Vec<Signal> {
        vec![
            Signal::new("lit", 1, o.lit as u64),
            Signal::new("written", 1, o.written as u64),
            Signal::new("stored", self.cfg.depth_bits, o.stored as u64),
        ]
    }
}
