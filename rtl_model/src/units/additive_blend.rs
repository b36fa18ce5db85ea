//! additive_blend — the framebuffer blend in (GL_ONE, GL_ONE) with saturation:
//! dst' = min(dst + src', 2ᶠ − 1) per channel of an f-bit framebuffer, one pixel
//! (`channels` channels) per kernel call.
//!
//! Widths (s = `src_bits`, f = `fb_bits`, k = `weight_bits`):
//! * src u(s) is aligned to the framebuffer width: widened by bit replication when
//!   f ≥ s (wiring only, as GPUs expand colours; error < 1 f-LSB), narrowed by
//!   round-to-nearest when f < s (`unorm::narrow`; error ≤ ½ f-LSB) → a u(f).
//! * `weighted` (off by default): the aligned source is scaled by a unorm weight w u(k)
//!   (w = 2ᵏ − 1 stands for 1.0): a·w u(f+k), rounded to nearest at f bits,
//!   q = round(a·w / (2ᵏ − 1)) u(f) (ties cannot occur: 2ᵏ − 1 is odd). The constant
//!   divide is the shift-add series [`round_div_mersenne`]. At w = 2ᵏ − 1, q = a exactly,
//!   so the weighted path reduces to the GL_ONE path.
//! * dst u(f) + q u(f) → u(f+1); a carry past 2ᶠ − 1 clamps to 2ᶠ − 1 (counted).
//!
//! Counters per kernel call (one pixel): `saturations` +1 per channel that clamps;
//! `underflows` +1 per channel whose source (and weight) is non-zero but whose
//! contribution q rounds to 0 (the plane is lost); one framebuffer read-modify-write
//! of `channels · fb_bits` bits (`memory::framebuffer_rmw`, bytes rounded up).
//!
//! Pipeline (latency 3, II 1): stage 1 reads the framebuffer while the source is
//! aligned (and weighted); stage 2 adds and saturates; stage 3 writes back.
//! The read-modify-write hazard of two fragments to the same pixel in flight is not
//! modelled here (the unit has no state; the pipeline owns the framebuffer).

use crate::cost::{prim, Cost};
use crate::counters::Counters;
use crate::error::{check_finite, check_range, ConfigError};
use crate::fixed_point::{Format, Fx, Overflow, Quant};
use crate::memory::{bytes_for_bits, framebuffer_rmw};
use crate::unit::{Signal, Timing, Unit, Width};
use crate::unorm::{check_bits, max_code, narrow, widen};
use serde::{Deserialize, Serialize};

/// Most channels a pixel carries (RGBA).
pub const MAX_CHANNELS: u32 = 4;

/// Channel names for traces, in order.
const SRC_NAMES: [&str; 4] = ["src_r", "src_g", "src_b", "src_a"];
const DST_NAMES: [&str; 4] = ["dst_r", "dst_g", "dst_b", "dst_a"];
const OUT_NAMES: [&str; 4] = ["y_r", "y_g", "y_b", "y_a"];

/// The configuration as a scene file gives it; [`AdditiveBlendConfig::build`] checks it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct AdditiveBlendConfig {
    /// Width of the incoming fragment colour (unorm), 1 ..= 16. Default 8.
    pub src_bits: u32,
    /// Framebuffer channel width (unorm), 1 ..= 16 (8, 10, 12, 16 are the usual). Default 8.
    pub fb_bits: u32,
    /// Channels per pixel, 1 ..= 4 (4 = RGBA). Default 4.
    pub channels: u32,
    /// Scale the source by a unorm weight before the add (weighted accumulation,
    /// e.g. averaging sub-sample planes). Default false (plain GL_ONE, GL_ONE).
    pub weighted: bool,
    /// Width of the weight word, 1 ..= 16 (checked even when `weighted` is off). Default 8.
    pub weight_bits: u32,
}

impl Default for AdditiveBlendConfig {
    fn default() -> Self {
        AdditiveBlendConfig {
            src_bits: 8,
            fb_bits: 8,
            channels: 4,
            weighted: false,
            weight_bits: 8,
        }
    }
}

impl AdditiveBlendConfig {
    /// Validate; errors name `additive_blend.<field>`.
    pub fn build(&self) -> Result<AdditiveBlend, ConfigError> {
        check_bits("additive_blend.src_bits", self.src_bits)?;
        check_bits("additive_blend.fb_bits", self.fb_bits)?;
        check_range(
            "additive_blend.channels",
            self.channels as u64,
            1,
            MAX_CHANNELS as u64,
        )?;
        check_bits("additive_blend.weight_bits", self.weight_bits)?;
        Ok(AdditiveBlend {
            src_bits: self.src_bits,
            fb_bits: self.fb_bits,
            channels: self.channels,
            weighted: self.weighted,
            weight_bits: self.weight_bits,
        })
    }
}

/// The validated unit config.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct AdditiveBlend {
    src_bits: u32,
    fb_bits: u32,
    channels: u32,
    weighted: bool,
    weight_bits: u32,
}

/// One pixel: incoming fragment colour, the framebuffer's current value and the
/// weight (ignored unless `weighted`). Only the first `channels` entries are used;
/// every word is masked to its wire width.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct AdditiveBlendIn {
    pub src: [u32; 4],
    pub dst: [u32; 4],
    pub weight: u32,
}

/// The new framebuffer value per channel (channels ≥ `channels` are 0).
pub type AdditiveBlendOut = [u32; 4];

pub use super::blend::round_div_mersenne;

impl AdditiveBlend {
    /// Build from the individual fields (see [`AdditiveBlendConfig`]).
    pub fn new(
        src_bits: u32,
        fb_bits: u32,
        channels: u32,
        weighted: bool,
        weight_bits: u32,
    ) -> Result<Self, ConfigError> {
        AdditiveBlendConfig {
            src_bits,
            fb_bits,
            channels,
            weighted,
            weight_bits,
        }
        .build()
    }

    /// GeForce default: 8-bit fragment colour into an 8-bit RGBA framebuffer, GL_ONE,
    /// GL_ONE (unweighted; weight width 8 for when weighting is switched on).
    pub fn geforce() -> Self {
        // The values of AdditiveBlendConfig::default(), all in range.
        AdditiveBlend {
            src_bits: 8,
            fb_bits: 8,
            channels: 4,
            weighted: false,
            weight_bits: 8,
        }
    }

    pub fn config(&self) -> AdditiveBlendConfig {
        AdditiveBlendConfig {
            src_bits: self.src_bits,
            fb_bits: self.fb_bits,
            channels: self.channels,
            weighted: self.weighted,
            weight_bits: self.weight_bits,
        }
    }

    pub fn src_bits(&self) -> u32 {
        self.src_bits
    }

    pub fn fb_bits(&self) -> u32 {
        self.fb_bits
    }

    pub fn channels(&self) -> u32 {
        self.channels
    }

    pub fn weighted(&self) -> bool {
        self.weighted
    }

    pub fn weight_bits(&self) -> u32 {
        self.weight_bits
    }

    /// All-ones framebuffer code (stands for 1.0).
    pub fn fb_max(&self) -> u32 {
        max_code(self.fb_bits)
    }

    /// All-ones weight code (stands for 1.0).
    pub fn weight_max(&self) -> u32 {
        max_code(self.weight_bits)
    }

    /// Bits of one framebuffer pixel (channels · fb_bits), as read and written.
    pub fn pixel_bits(&self) -> u32 {
        self.channels * self.fb_bits
    }

    /// Quantise a host-side weight (e.g. 1/m for m sub-sample planes) to the weight
    /// word: round-half-even of w·(2ᵏ − 1), clamped to 0 ..= 2ᵏ − 1 (a clamp is counted
    /// in `ctr.saturations`). NaN or ±∞ gives an error naming `additive_blend.weight`.
    pub fn quantise_weight(&self, w: f64, ctr: &mut Counters) -> Result<u32, ConfigError> {
        const FIELD: &str = "additive_blend.weight";
        let w = check_finite(FIELD, w)?;
        // Anything outside [−1, 2] saturates just the same; keep the carrier small.
        let w = w.clamp(-1.0, 2.0);
        let k = self.weight_bits;
        let fmt = Format::uint(k).map_err(|e| e.within("additive_blend"))?;
        let exact = Fx::exact_from_f64(w, FIELD)?; // dyadic rational, ≤ 2 + 120 frac bits
        let scale = Fx::from_raw(max_code(k) as i128, fmt); // 2ᵏ − 1, u(k)
        let code = exact
            .mul(scale) // exact product
            .assign(fmt, Quant::RndConv, Overflow::Sat, ctr); // → u(k), ties to even
        Ok(code.raw as u32)
    }

    /// The source aligned to the framebuffer width: replication when widening,
    /// round-to-nearest when narrowing. u(src_bits) → u(fb_bits).
    #[inline]
    pub fn align(&self, src: u32) -> u32 {
        let s = src & max_code(self.src_bits);
        if self.fb_bits >= self.src_bits {
            widen(s, self.src_bits, self.fb_bits) // wiring only
        } else {
            // (s·(2ᶠ−1) + 2ˢ⁻¹) / (2ˢ−1): u(s) × u(f) → u(s+f), then the constant divide.
            narrow(s, self.src_bits, self.fb_bits)
        }
    }

    /// What the unit adds to the framebuffer for this source and weight, in fb codes:
    /// align(src), and when weighted round(align(src)·w / (2ᵏ − 1)). u(fb_bits).
    #[inline]
    pub fn contribution(&self, src: u32, weight: u32) -> u32 {
        let a = self.align(src); // u(f)
        if !self.weighted {
            return a;
        }
        let k = self.weight_bits;
        let w = weight & max_code(k); // u(k)
        let p = a as u64 * w as u64; // u(f) × u(k) → u(f+k)
        round_div_mersenne(p, k, self.fb_bits) as u32 // u(f+k) → u(f), ≤ a
    }

    /// One channel: (new dst, clamped?, contribution underflowed to 0?).
    #[inline]
    pub fn blend_channel(&self, src: u32, dst: u32, weight: u32) -> (u32, bool, bool) {
        let max = self.fb_max();
        let q = self.contribution(src, weight); // u(f)
        let d = dst & max; // u(f)
        let sum = d + q; // u(f) + u(f) → u(f+1)
        let saturated = sum > max;
        let nonzero_in = (src & max_code(self.src_bits)) != 0
            && (!self.weighted || (weight & self.weight_max()) != 0);
        let underflow = nonzero_in && q == 0;
        (sum.min(max), saturated, underflow) // → u(f)
    }
}

impl AdditiveBlend {
    /// The batch kernel on lanes (structure of arrays), in the J buffer's form: lane i
    /// is the input `AdditiveBlendIn { src: [src[i], 0, 0, 0], dst: [dst[i], 0, 0, 0],
    /// weight }` (one weight for every lane); its channel-0 result is written back into
    /// `dst[i]` (the other channels', all min(contribution(0, w), max), are dropped) and
    /// the counters are those [`Unit::kernel_batch`] counts on these inputs. The
    /// contribution comes from the same table as the batch kernel's.
    pub fn blend_lanes(&self, src: &[u32], dst: &mut [u32], weight: u32, ctr: &mut Counters) {
        assert_eq!(
            src.len(),
            dst.len(),
            "blend_lanes: src and dst lanes differ"
        );
        let n = src.len() as u64;
        let (max, src_mask) = (self.fb_max(), max_code(self.src_bits));
        let w = if self.weighted {
            weight & self.weight_max()
        } else {
            0
        };
        let weight_on = !self.weighted || w != 0;
        let (mut sat, mut under) = (0u64, 0u64);
        if self.src_bits <= CONTRIBUTION_LUT_BITS {
            let mut lut = [0u32; 1 << CONTRIBUTION_LUT_BITS];
            for (s, q) in lut.iter_mut().enumerate().take(1 << self.src_bits) {
                *q = self.contribution(s as u32, w);
            }
            for (d, &s) in dst.iter_mut().zip(src) {
                let sm = s & src_mask;
                let q = lut[sm as usize];
                let sum = (*d & max) + q;
                sat += u64::from(sum > max);
                under += u64::from(sm != 0 && q == 0);
                *d = sum.min(max);
            }
        } else {
            for (d, &s) in dst.iter_mut().zip(src) {
                let sm = s & src_mask;
                let q = self.contribution(sm, w);
                let sum = (*d & max) + q;
                sat += u64::from(sum > max);
                under += u64::from(sm != 0 && q == 0);
                *d = sum.min(max);
            }
        }
        if !weight_on {
            under = 0;
        }
        // Channels 1 .. channels − 1: source and destination 0 (never an underflow).
        let q0 = self.contribution(0, w);
        sat += u64::from(q0 > max) * n * (self.channels as u64 - 1);
        let bytes = bytes_for_bits(self.pixel_bits()) * n;
        ctr.mem_read_bytes += bytes;
        ctr.mem_write_bytes += bytes;
        ctr.saturations += sat;
        ctr.underflows += under;
    }

    /// The batch kernel on unweighted pixels in lanes (the framebuffer's form): lane i
    /// is the input `AdditiveBlendIn { src: src(i), dst: dst(i), weight: 0 }`, its
    /// output written to `out[i]`, the counters those [`Unit::kernel_batch`] counts on
    /// these inputs. Chosen from the config: an unweighted blend has one contribution
    /// table, built once, and no input words are made. False (nothing done) when
    /// weighted or the source is wider than [`CONTRIBUTION_LUT_BITS`].
    pub fn blend_pixels(
        &self,
        src: impl Fn(usize) -> [u32; 4],
        dst: impl Fn(usize) -> [u32; 4],
        out: &mut [[u32; 4]],
        ctr: &mut Counters,
    ) -> bool {
        if self.weighted || self.src_bits > CONTRIBUTION_LUT_BITS {
            return false;
        }
        let ch = self.channels as usize;
        let (max, src_mask) = (self.fb_max(), max_code(self.src_bits));
        let mut lut = [0u32; 1 << CONTRIBUTION_LUT_BITS];
        for (s, q) in lut.iter_mut().enumerate().take(1 << self.src_bits) {
            *q = self.contribution(s as u32, 0);
        }
        let (mut sat, mut under) = (0u64, 0u64);
        for (i, o) in out.iter_mut().enumerate() {
            let (s, d) = (src(i), dst(i));
            let mut r = [0u32; 4];
            for (c, rc) in r.iter_mut().enumerate().take(ch) {
                let sm = s[c] & src_mask;
                let q = lut[sm as usize]; // u(f)
                let sum = (d[c] & max) + q; // u(f+1)
                *rc = sum.min(max);
                sat += u64::from(sum > max);
                under += u64::from(sm != 0 && q == 0);
            }
            *o = r;
        }
        let bytes = bytes_for_bits(self.pixel_bits()) * out.len() as u64;
        ctr.mem_read_bytes += bytes;
        ctr.mem_write_bytes += bytes;
        ctr.saturations += sat;
        ctr.underflows += under;
        true
    }
}

/// Widest source whose contributions the batch kernel tabulates (2^10 entries).
pub const CONTRIBUTION_LUT_BITS: u32 = 10;

impl Unit for AdditiveBlend {
    type In = AdditiveBlendIn;
    type Out = AdditiveBlendOut;
    type State = ();

    fn name(&self) -> &'static str {
        "additive_blend"
    }

    fn kernel(&self, _: &mut (), input: &AdditiveBlendIn, ctr: &mut Counters) -> [u32; 4] {
        // One pixel read and written back: channels · fb_bits bits each way.
        framebuffer_rmw(ctr, self.pixel_bits());
        let mut out = [0u32; 4];
        for (c, o) in out.iter_mut().enumerate().take(self.channels as usize) {
            let (v, sat, under) = self.blend_channel(input.src[c], input.dst[c], input.weight);
            *o = v;
            ctr.saturations += u64::from(sat);
            ctr.underflows += u64::from(under);
        }
        out
    }

    /// The kernel with the config's masks and the framebuffer traffic hoisted out
    /// of the loop (counted once per chunk). For sources of at most
    /// [`CONTRIBUTION_LUT_BITS`] bits the contribution (align, weight, constant
    /// divide) is looked up in a table of every source code at the current weight,
    /// built when the weight changes (a J-buffer span has one weight).
    fn kernel_batch(
        &self,
        _: &mut (),
        inputs: &[AdditiveBlendIn],
        out: &mut Vec<[u32; 4]>,
        ctr: &mut Counters,
    ) {
        let ch = self.channels as usize;
        let (max, src_mask, w_mask) = (self.fb_max(), max_code(self.src_bits), self.weight_max());
        let (mut sat, mut under) = (0u64, 0u64);
        let use_lut = self.src_bits <= CONTRIBUTION_LUT_BITS;
        let mut lut = [0u32; 1 << CONTRIBUTION_LUT_BITS];
        let mut lut_weight: Option<u32> = None;
        out.extend(inputs.iter().map(|x| {
            // The weight as the datapath sees it (ignored when unweighted).
            let w = if self.weighted { x.weight & w_mask } else { 0 };
            if use_lut && lut_weight != Some(w) {
                for (src, q) in lut.iter_mut().enumerate().take(1 << self.src_bits) {
                    *q = self.contribution(src as u32, w);
                }
                lut_weight = Some(w);
            }
            let weight_on = !self.weighted || w != 0;
            let mut o = [0u32; 4];
            for c in 0..ch {
                let q = if use_lut {
                    lut[(x.src[c] & src_mask) as usize]
                } else {
                    self.contribution(x.src[c], x.weight)
                }; // u(f)
                let sum = (x.dst[c] & max) + q; // u(f+1)
                o[c] = sum.min(max);
                sat += u64::from(sum > max);
                under += u64::from((x.src[c] & src_mask) != 0 && weight_on && q == 0);
            }
            o
        }));
        let bytes = bytes_for_bits(self.pixel_bits()) * inputs.len() as u64;
        ctr.mem_read_bytes += bytes;
        ctr.mem_write_bytes += bytes;
        ctr.saturations += sat;
        ctr.underflows += under;
    }

    fn timing(&self) -> Timing {
        // Stage 1: framebuffer read (source aligned / weighted meanwhile);
        // stage 2: add and saturate; stage 3: write back.
        Timing { latency: 3, ii: 1 }
    }

    fn cost(&self) -> Cost {
        let (s, f, k) = (self.src_bits, self.fb_bits, self.weight_bits);
        let ch = self.channels;
        let chf = ch as f64;
        let wbits = if self.weighted { k } else { 0 };
        let mut c = Cost::default()
            .part(
                "input registers (src, weight)",
                prim::register(ch * s + wbits),
            )
            .part(
                "stage 1 registers (contribution, fb read data)",
                prim::register(2 * ch * f),
            )
            .part("stage 2 register (saturated sum)", prim::register(ch * f))
            .part("stage 3 register (write data)", prim::register(ch * f));
        if f < s {
            // narrow: v·(2ᶠ−1) = (v << f) − v; + 2ˢ⁻¹ on the upper f+1 bits;
            // (t + (t >> s)) >> s (the J = 1 series).
            let per =
                prim::subtractor(s + f) + prim::half_adder() * (f + 1) as f64 + prim::adder(s + f);
            c = c.part("align: narrow to fb_bits (round to nearest)", per * chf);
        }
        // f ≥ s: bit replication is wiring, no gates.
        if self.weighted {
            let j = f.div_ceil(k); // shift-add terms beyond the first
            c = c
                .part("weight multiplier fb×weight", prim::multiplier(f, k) * chf)
                .part(
                    "weight rounding: + 2^(k-1)",
                    prim::half_adder() * ((f + 1) as f64 * chf),
                )
                .part(
                    "weight rounding: ÷(2^k−1) shift-add series",
                    prim::adder(f + k) * (j as f64 * chf),
                );
        }
        c.part("saturating adder fb_bits", prim::saturating_adder(f) * chf)
    }

    fn widths(&self) -> Vec<Width> {
        let mut v = vec![
            Width {
                name: "src_bits",
                bits: self.src_bits,
            },
            Width {
                name: "fb_bits",
                bits: self.fb_bits,
            },
            Width {
                name: "pixel_bits",
                bits: self.pixel_bits(),
            },
        ];
        if self.weighted {
            v.push(Width {
                name: "weight_bits",
                bits: self.weight_bits,
            });
        }
        v
    }

    fn in_signals(&self, i: &AdditiveBlendIn) -> Vec<Signal> {
        let n = self.channels as usize;
        let (smax, fmax) = (max_code(self.src_bits), self.fb_max());
        let mut v = Vec::with_capacity(2 * n + 1);
        for (name, &src) in SRC_NAMES.iter().zip(&i.src).take(n) {
            v.push(Signal::new(name, self.src_bits, (src & smax) as u64));
        }
        for (name, &dst) in DST_NAMES.iter().zip(&i.dst).take(n) {
            v.push(Signal::new(name, self.fb_bits, (dst & fmax) as u64));
        }
        if self.weighted {
            let w = i.weight & self.weight_max();
            v.push(Signal::new("w", self.weight_bits, w as u64));
        }
        v
    }

    fn out_signals(&self, o: &[u32; 4]) -> Vec<Signal> {
        (0..self.channels as usize)
            .map(|c| Signal::new(OUT_NAMES[c], self.fb_bits, (o[c] & self.fb_max()) as u64))
            .collect()
    }
}
