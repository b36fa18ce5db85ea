//! texture_sampler — 1D / 2D / 3D texture lookup with nearest or (bi/tri)linear
//! filtering, clamp-to-edge or repeat addressing per axis, texels held in a packed
//! `bitvec` RAM at their configured width.
//!
//! Conventions (OpenGL 1.x / 1.2 for 3D, as on GeForce2 / GeForce3):
//! * The input is a **texel-space** coordinate per axis: the rasteriser has already
//!   multiplied the normalised (s, t, r) by the texture size. It is a signed fixed-point
//!   word s(I).F — I = `coord_int_bits` integer bits including the sign (default 16,
//!   i.e. −32768 ..< 32768 texels: eight repeats of the largest 4096 texture either way),
//!   F = `coord_frac_bits` sub-texel bits (default 8). Words are masked to their I + F
//!   wires (sign-extended); a word that did not fit counts one `overflows` per axis.
//! * Nearest: i = floor(u).  Linear: p = u − ½, i0 = floor(p), a = p − i0, i1 = i0 + 1,
//!   out = Σ (corner weights) · texel.
//! * Address modes: clamp to edge (i → clamp(i, 0, size − 1)) or repeat
//!   (i → i mod size; a mask for power-of-two sizes, a remainder otherwise).
//!
//! Datapath widths (tb = `texel_bits`, wb = `weight_bits`, W = 2^wb, d = `dims`,
//! F = `coord_frac_bits`, I = `coord_int_bits`):
//! * p = u − ½ in s(I+1).Fp with Fp = max(F, 1) (exact: the ½ needs one extra
//!   fraction bit only when F = 0); i0 = p >> Fp is s(I+1); the fraction a is u(Fp).
//! * If Fp ≤ wb the fraction is used exactly (shifted up); otherwise it is reduced to
//!   wb bits by `weight_rounding` (round to nearest, ties up, by default; or truncate):
//!   fx ∈ [0, W] (rounding can reach W), so each per-axis weight W − fx, fx is u(wb+1).
//!   At the defaults (F = wb = 8) the weights are exact.
//! * Product weights Π_axes w: u(wb+1)^d → u(d·wb + 1) (they sum to exactly W^d).
//! * texel × weight: u(tb) × u(d·wb+1) → u(tb + d·wb + 1), but every product and the
//!   whole sum are ≤ (2^tb − 1)·W^d < 2^(tb + d·wb), so the accumulator is
//!   u(tb + d·wb) (≤ 64 bits at the widest config: 16 + 3·16).
//! * One rounding at the end, half up: out = (Σ + W^d/2) >> (d·wb), u(tb). It never
//!   exceeds 2^tb − 1, so no saturation is possible.
//!
//! Where GL leaves the filter's arithmetic to the implementation, `filter_rounding`
//! names the choice: the datapath above (`ProductWeights`, default) or Mesa llvmpipe's
//! `SuccessiveLerps` — s, then t, then r, each lerp v0 + ((w·(v1 − v0) + W/2) >> wb)
//! rounded back to u(tb) — which with `WeightRounding::RoundHalfEven` (llvmpipe's
//! half-to-even coordinate rounding) is bit-exact against llvmpipe at 8 bits
//! ([`TextureSamplerConfig::mesa_llvmpipe`]; tests/texture_sampler_mesa.rs).
//!
//! Timing: nearest = address (1) + RAM read (1), II 1. Linear = address and axis
//! weights (1) + II RAM-read clocks (the 2^d corners in batches of `texels_per_clock`
//! ports, lane weights formed alongside) + texel × weight multiply (1) + adder tree,
//! accumulate and round (1); II = ceil(2^d / texels_per_clock). Every sample counts
//! its texel reads and bytes with `memory::texel_fetch` (no texture cache modelled).

use crate::cost::{prim, Cells, Cost};
use crate::counters::Counters;
use crate::error::{check_finite, check_range, ConfigError};
use crate::fixed_point::{Format, Fx, Overflow, Quant};
use crate::memory::texel_fetch;
use crate::unit::{Signal, Timing, Unit, Width};
use crate::unorm::{check_bits, max_code};
use bitvec::prelude::*;
use serde::{Deserialize, Serialize};

/// Largest size of one axis.
pub const MAX_SIZE: u32 = 4096;
/// Largest texel count (product of the sizes): 2^24.
pub const MAX_TEXELS: u64 = 1 << 24;
/// Largest number of sub-texel fraction bits of the coordinate.
pub const MAX_COORD_FRAC_BITS: u32 = 16;
/// Widest coordinate word (integer + fraction bits): it travels in an `i32`.
pub const MAX_COORD_WIDTH: u32 = 32;
/// Widest filter weight.
pub const MAX_WEIGHT_BITS: u32 = 16;
/// Most RAM read ports (texels fetched per clock).
pub const MAX_TEXELS_PER_CLOCK: u32 = 8;
/// Most channels (RGBA).
pub const MAX_CHANNELS: u32 = 4;

/// Texture filter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Filter {
    /// GL_NEAREST: the texel containing the coordinate (1 texel).
    Nearest,
    /// GL_LINEAR: linear (1D), bilinear (2D) or trilinear (3D, 8 texels) filtering.
    Linear,
}

/// Address (wrap) mode of one axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AddressMode {
    /// GL_CLAMP_TO_EDGE: clamp(i, 0, size − 1).
    Clamp,
    /// GL_REPEAT: i mod size (floored).
    Wrap,
}

/// How the sub-texel fraction is reduced to `weight_bits`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WeightRounding {
    /// Round to nearest, ties up: error ≤ 2^−(wb+1) per axis; fx may reach W.
    Round,
    /// Drop the low bits: error ≤ 2^−wb − 2^−F per axis; no incrementer.
    Truncate,
    /// Round to nearest, ties to even (the parity of the rounded texel coordinate's
    /// last weight bit): llvmpipe's tie rule, which rounds u·2^wb to an integer with
    /// the FPU's round-half-even before it splits off the fraction. Error as `Round`.
    RoundHalfEven,
}

/// How the corner texels are filtered into one code (linear filtering only).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum FilterRounding {
    /// Multiply the axis weights out (Π w, exact), sum the 2^d texel × weight
    /// products exactly and round once, half up (default; the GeForce-style datapath).
    #[default]
    ProductWeights,
    /// Lerp one axis at a time, each lerp rounded back to `texel_bits`:
    /// lerp(w; v0, v1) = v0 + ((w·(v1 − v0) + W/2) >> wb) (arithmetic shift, so ties
    /// go up), s first, then t, then r — 2^d − 1 lerps. What Mesa's llvmpipe does on
    /// 8-bit textures (gallivm `lp_build_lerp` with pre-scaled 8-bit weights in the
    /// AoS sampler).
    SuccessiveLerps,
}

/// The configuration as a user writes it (unvalidated; [`TextureSampler::new`]
/// validates it). Field names are those of the errors: `texture_sampler.<field>`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct TextureSamplerConfig {
    /// 1, 2 or 3.
    pub dims: u32,
    /// [width, height, depth], each 1 ..= 4096, product ≤ 2^24; unused axes must be 1.
    pub size: [u32; 3],
    /// 1 ..= 4 (1 = luminance, the shafts pipeline's g, F and h textures).
    pub channels: u32,
    /// Unorm texel width, 1 ..= 16 (GeForce: 8).
    pub texel_bits: u32,
    /// Integer bits of the coordinate word including its sign, with
    /// 2^(coord_int_bits − 1) ≥ the largest used size and
    /// coord_int_bits + coord_frac_bits ≤ 32 (default 16).
    pub coord_int_bits: u32,
    /// Sub-texel fraction bits of the coordinate, 0 ..= 16 (default 8).
    pub coord_frac_bits: u32,
    /// Filter weight bits, 1 ..= 16 (default 8).
    pub weight_bits: u32,
    /// Fraction → weight reduction (default round to nearest).
    pub weight_rounding: WeightRounding,
    /// How linear filtering combines its corners (default: product weights, one
    /// rounding). `SuccessiveLerps` with `RoundHalfEven` weights is llvmpipe's.
    #[serde(default)]
    pub filter_rounding: FilterRounding,
    pub filter: Filter,
    /// Per axis (s, t, r); unused axes are ignored.
    pub address: [AddressMode; 3],
    /// RAM read ports, 1 ..= 8 (default 4: a bilinear sample per clock).
    pub texels_per_clock: u32,
}

impl Default for TextureSamplerConfig {
    fn default() -> Self {
        Self::geforce()
    }
}

impl TextureSamplerConfig {
    /// GeForce2-era defaults: a 256 × 256 luminance texture, 8-bit texels, 8 sub-texel
    /// coordinate bits, 8-bit weights, bilinear, clamp to edge, 4 texels per clock.
    pub fn geforce() -> Self {
        TextureSamplerConfig {
            dims: 2,
            size: [256, 256, 1],
            channels: 1,
            texel_bits: 8,
            coord_int_bits: 16,
            coord_frac_bits: 8,
            weight_bits: 8,
            weight_rounding: WeightRounding::Round,
            filter_rounding: FilterRounding::ProductWeights,
            filter: Filter::Linear,
            address: [AddressMode::Clamp; 3],
            texels_per_clock: 4,
        }
    }

    /// GeForce defaults for a 1D texture of `width` texels (e.g. the shafts' F(α)).
    pub fn geforce_1d(width: u32) -> Self {
        TextureSamplerConfig {
            dims: 1,
            size: [width, 1, 1],
            ..Self::geforce()
        }
    }

    /// GeForce defaults for a 2D texture (e.g. the shafts' h(s, t)).
    pub fn geforce_2d(width: u32, height: u32) -> Self {
        TextureSamplerConfig {
            dims: 2,
            size: [width, height, 1],
            ..Self::geforce()
        }
    }

    /// GeForce3 defaults for a 3D texture (the multi-scale environment map): trilinear
    /// over 8 texels with 4 ports, so II = 2.
    pub fn geforce_3d(width: u32, height: u32, depth: u32) -> Self {
        TextureSamplerConfig {
            dims: 3,
            size: [width, height, depth],
            ..Self::geforce()
        }
    }

    /// The same texture filtered as Mesa's llvmpipe does (bit-exact against it at
    /// 8-bit texels, 8-bit weights: tests/texture_sampler_mesa.rs): successive lerps
    /// and the half-to-even coordinate tie rule. Other fields are kept.
    pub fn mesa_llvmpipe(self) -> Self {
        TextureSamplerConfig {
            weight_rounding: WeightRounding::RoundHalfEven,
            filter_rounding: FilterRounding::SuccessiveLerps,
            ..self
        }
    }

    /// Check every field; the error names the first field at fault.
    pub fn validate(&self) -> Result<(), ConfigError> {
        check_range("texture_sampler.dims", self.dims as u64, 1, 3)?;
        let d = self.dims as usize;
        for (k, &s) in self.size.iter().enumerate() {
            if k < d {
                check_range("texture_sampler.size", s as u64, 1, MAX_SIZE as u64)?;
            } else if s != 1 {
                return Err(ConfigError::invalid(
                    "texture_sampler.size",
                    &format!("axis {k} is unused at dims = {d} and must be 1, not {s}"),
                ));
            }
        }
        let texels: u64 = self.size.iter().map(|&s| s as u64).product();
        check_range("texture_sampler.size", texels, 1, MAX_TEXELS)?;
        check_range(
            "texture_sampler.channels",
            self.channels as u64,
            1,
            MAX_CHANNELS as u64,
        )?;
        check_bits("texture_sampler.texel_bits", self.texel_bits)?;
        check_range(
            "texture_sampler.coord_frac_bits",
            self.coord_frac_bits as u64,
            0,
            MAX_COORD_FRAC_BITS as u64,
        )?;
        check_range(
            "texture_sampler.coord_int_bits",
            self.coord_int_bits as u64,
            1,
            (MAX_COORD_WIDTH - self.coord_frac_bits) as u64,
        )?;
        let largest = self.size[..d].iter().copied().max().unwrap_or(1) as u64;
        if (1u64 << (self.coord_int_bits - 1)) < largest {
            return Err(ConfigError::invalid(
                "texture_sampler.coord_int_bits",
                &format!(
                    "{} signed integer bits reach only {} texels, the texture has {largest}",
                    self.coord_int_bits,
                    1u64 << (self.coord_int_bits - 1)
                ),
            ));
        }
        check_range(
            "texture_sampler.weight_bits",
            self.weight_bits as u64,
            1,
            MAX_WEIGHT_BITS as u64,
        )?;
        check_range(
            "texture_sampler.texels_per_clock",
            self.texels_per_clock as u64,
            1,
            MAX_TEXELS_PER_CLOCK as u64,
        )?;
        Ok(())
    }

    /// Texels the texture holds (w · h · d).
    pub fn texel_count(&self) -> u64 {
        self.size.iter().map(|&s| s as u64).product()
    }

    /// Texel RAM bits: w · h · d · channels · texel_bits.
    pub fn ram_bits(&self) -> u64 {
        self.texel_count() * self.channels as u64 * self.texel_bits as u64
    }

    /// Texels one sample reads: 1 (nearest) or 2^dims (linear).
    pub fn texels_per_sample(&self) -> u32 {
        match self.filter {
            Filter::Nearest => 1,
            Filter::Linear => 1 << self.dims.clamp(1, 3),
        }
    }

    /// Quantise a normalised coordinate `s` of `axis` (0 = s, 1 = t, 2 = r) to the
    /// texel-space coordinate word, as the rasteriser hands it over:
    /// round-to-nearest (ties up) of s · `size[axis]` into s(I).F, saturating (counted in
    /// `ctr.saturations`) beyond the word. NaN or ±∞ is an error naming
    /// `texture_sampler.coord`; so is an invalid config or axis.
    pub fn texel_coord_from_normalized(
        &self,
        s: f64,
        axis: usize,
        ctr: &mut Counters,
    ) -> Result<i32, ConfigError> {
        self.validate()?;
        if axis >= self.dims as usize {
            return Err(ConfigError::out_of_range(
                "texture_sampler.coord",
                axis as f64,
                0.0,
                (self.dims - 1) as f64,
            ));
        }
        texel_coord_from_normalized(
            s,
            self.size[axis],
            self.coord_int_bits,
            self.coord_frac_bits,
            ctr,
        )
    }

    /// [`Self::texel_coord_from_normalized`] for every used axis (unused axes get 0).
    pub fn input_from_normalized(
        &self,
        stq: [f64; 3],
        ctr: &mut Counters,
    ) -> Result<TextureSamplerIn, ConfigError> {
        let mut coord = [0i32; 3];
        for (k, c) in coord
            .iter_mut()
            .enumerate()
            .take(self.dims.clamp(1, 3) as usize)
        {
            *c = self.texel_coord_from_normalized(stq[k], k, ctr)?;
        }
        Ok(TextureSamplerIn { coord })
    }
}

fn rename(e: ConfigError, field: &str) -> ConfigError {
    match e {
        ConfigError::OutOfRange {
            value, min, max, ..
        } => ConfigError::out_of_range(field, value, min, max),
        ConfigError::NotFinite { value, .. } => ConfigError::not_finite(field, value),
        ConfigError::Invalid { reason, .. } => ConfigError::invalid(field, &reason),
    }
}

/// Host helper: the texel-space coordinate word for normalised `s` on an axis of
/// `size` texels, in s(`coord_int_bits`).(`coord_frac_bits`): round to nearest (ties
/// up) of s · size, saturating beyond the word (counted). NaN/±∞ → error naming
/// `texture_sampler.coord`; widths out of range → errors naming their fields.
pub fn texel_coord_from_normalized(
    s: f64,
    size: u32,
    coord_int_bits: u32,
    coord_frac_bits: u32,
    ctr: &mut Counters,
) -> Result<i32, ConfigError> {
    let s = check_finite("texture_sampler.coord", s)?;
    check_range("texture_sampler.size", size as u64, 1, MAX_SIZE as u64)?;
    check_range(
        "texture_sampler.coord_frac_bits",
        coord_frac_bits as u64,
        0,
        MAX_COORD_FRAC_BITS as u64,
    )?;
    check_range(
        "texture_sampler.coord_int_bits",
        coord_int_bits as u64,
        1,
        (MAX_COORD_WIDTH - coord_frac_bits) as u64,
    )?;
    let fmt = Format::new(coord_int_bits, coord_frac_bits, true)
        .map_err(|e| rename(e, "texture_sampler.coord_int_bits"))?;
    // |s| beyond 2^40 saturates anyway; keep s · size finite.
    let u = s.clamp(-(2f64.powi(40)), 2f64.powi(40)) * size as f64;
    let fx = Fx::from_f64(
        u,
        fmt,
        Quant::Rnd,
        Overflow::Sat,
        "texture_sampler.coord",
        ctr,
    )?;
    Ok(fx.raw as i32) // s(I).F with I + F ≤ 32 fits an i32
}

/// One sample request: texel-space coordinates (s, t, r) as s(I).F words; unused
/// axes are ignored.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct TextureSamplerIn {
    pub coord: [i32; 3],
}

/// The sampler: validated config plus its texel RAM.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TextureSampler {
    cfg: TextureSamplerConfig,
    /// Texel RAM, packed: texel (x, y, z) channel c at bit
    /// (((z·h + y)·w + x)·channels + c)·texel_bits, LSB first.
    ram: BitVec<u64, Lsb0>,
    /// Address bits of each axis: ceil(log2(size)).
    axis_bits: [u32; 3],
    /// The same texels one word each, for the lane kernels' gathers
    /// ([`LaneFilter`]): kept for a one-channel 1D or 2D texture of at most
    /// [`UNPACKED_MAX_TEXELS`] texels, empty otherwise. A copy of `ram` made at each
    /// load, so the two never differ.
    unpacked: Vec<u32>,
}

/// The largest texture (texels) whose codes are also kept one per word for the lane
/// kernels: 16 MiB of words.
const UNPACKED_MAX_TEXELS: u64 = 1 << 22;

/// One lerp of [`FilterRounding::SuccessiveLerps`]: v0 + ((w·(v1 − v0) + W/2) >> wb)
/// with W = 2^wb, w ∈ [0, W], codes u(tb). v1 − v0 is s(tb+1), the product
/// s(tb+wb+2); the arithmetic shift floors, so an exact half rounds up. The result
/// lies between v0 and v1: u(tb), no saturation possible.
#[inline]
pub fn lerp_round(w: i64, v0: i64, v1: i64, wb: u32) -> i64 {
    v0 + ((w * (v1 - v0) + (1i64 << (wb - 1))) >> wb)
}

/// The texels one lookup reads, in the kernel's order, with their filter weights:
/// nearest reads 1 (weight 1); linear reads 2^dims corners, corner c taking axis k's
/// upper texel when bit k of c is set (s fastest), each with its product weight
/// Π_k w_k, u(d·wb + 1), summing to W^d. A texel is its RAM index x + w·(y + h·z)
/// after the address mode (a clamped or wrapped corner may repeat another).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Corners {
    /// Texels read: 1, 2, 4 or 8.
    pub len: u32,
    /// Texel indices, the first `len` used.
    pub texel: [u32; 8],
    /// Product weights (nearest: 1), the first `len` used.
    pub weight: [u64; 8],
}

impl Corners {
    /// The texel indices read, in order.
    pub fn texels(&self) -> &[u32] {
        &self.texel[..self.len as usize]
    }
}

fn ceil_log2(n: u64) -> u32 {
    if n <= 1 {
        0
    } else {
        64 - (n - 1).leading_zeros()
    }
}

const OUT_NAMES: [&str; 4] = ["ch0", "ch1", "ch2", "ch3"];
const IN_NAMES: [&str; 3] = ["coord_s", "coord_t", "coord_r"];

impl TextureSampler {
    /// Validate `cfg` and load `texels`: w·h·d·channels codes, texel (x, y, z)
    /// channel c at index ((z·h + y)·w + x)·channels + c. A wrong count or a code
    /// ≥ 2^texel_bits is an error naming `texture_sampler.texels`.
    pub fn new(cfg: TextureSamplerConfig, texels: &[u32]) -> Result<Self, ConfigError> {
        cfg.validate()?;
        let mut axis_bits = [0u32; 3];
        for (b, &s) in axis_bits.iter_mut().zip(cfg.size.iter()) {
            *b = ceil_log2(s as u64);
        }
        let mut t = TextureSampler {
            ram: BitVec::new(),
            cfg,
            axis_bits,
            unpacked: Vec::new(),
        };
        t.load(texels)?;
        Ok(t)
    }

    /// GeForce defaults ([`TextureSamplerConfig::geforce`], 256 × 256 luminance).
    pub fn geforce(texels: &[u32]) -> Result<Self, ConfigError> {
        Self::new(TextureSamplerConfig::geforce(), texels)
    }

    /// Replace the whole texture (a texture upload or a copy-to-texture). On error the
    /// RAM is left as it was.
    pub fn load(&mut self, texels: &[u32]) -> Result<(), ConfigError> {
        let n = self.cfg.texel_count() * self.cfg.channels as u64;
        if texels.len() as u64 != n {
            return Err(ConfigError::invalid(
                "texture_sampler.texels",
                &format!("expected {n} codes (w·h·d·channels), got {}", texels.len()),
            ));
        }
        let max = max_code(self.cfg.texel_bits);
        // The largest code first (a loop with no early exit, in vector registers), the
        // first one too wide looked for only when there is one.
        let widest = texels.iter().fold(0, |m, &v| m.max(v));
        if widest > max {
            let (i, v) = (texels.iter().copied().enumerate())
                .find(|&(_, v)| v > max)
                .unwrap_or((0, widest));
            return Err(ConfigError::invalid(
                "texture_sampler.texels",
                &format!(
                    "code {v} at index {i} does not fit {} bits",
                    self.cfg.texel_bits
                ),
            ));
        }
        // Packed LSB first into whole words (what a `store_le` per texel writes into a
        // `BitVec<u64, Lsb0>`, a word at a time; a texel straddles at most two words).
        let tb = self.cfg.texel_bits as usize;
        let total = texels.len() * tb;
        let words = if 64 % tb == 0 {
            // Whole texels per word (1, 2, 4, 8 or 16 bits): each word from its own
            // texels, the last one's missing texels 0.
            let per = 64 / tb;
            texels
                .chunks(per)
                .map(|c| {
                    c.iter()
                        .enumerate()
                        .fold(0u64, |w, (j, &v)| w | (v as u64) << (j * tb))
                })
                .collect()
        } else {
            let mut words = vec![0u64; total.div_ceil(64)];
            for (i, &v) in texels.iter().enumerate() {
                let (w, off) = ((i * tb) / 64, (i * tb) % 64);
                words[w] |= (v as u64) << off;
                if off + tb > 64 {
                    words[w + 1] |= (v as u64) >> (64 - off);
                }
            }
            words
        };
        let mut ram = BitVec::<u64, Lsb0>::from_vec(words);
        ram.truncate(total);
        self.ram = ram;
        self.unpacked.clear();
        if self.cfg.channels == 1
            && self.cfg.dims <= 2
            && self.cfg.texel_count() <= UNPACKED_MAX_TEXELS
        {
            self.unpacked.extend_from_slice(texels);
        }
        Ok(())
    }

    pub fn config(&self) -> &TextureSamplerConfig {
        &self.cfg
    }
    pub fn dims(&self) -> u32 {
        self.cfg.dims
    }
    pub fn size(&self) -> [u32; 3] {
        self.cfg.size
    }
    pub fn channels(&self) -> u32 {
        self.cfg.channels
    }
    pub fn texel_bits(&self) -> u32 {
        self.cfg.texel_bits
    }
    pub fn coord_int_bits(&self) -> u32 {
        self.cfg.coord_int_bits
    }
    pub fn coord_frac_bits(&self) -> u32 {
        self.cfg.coord_frac_bits
    }
    /// The coordinate word format s(I).F.
    pub fn coord_format(&self) -> Format {
        Format {
            int_bits: self.cfg.coord_int_bits,
            frac_bits: self.cfg.coord_frac_bits,
            signed: true,
        }
    }
    /// Coordinate word width I + F.
    pub fn coord_bits(&self) -> u32 {
        self.cfg.coord_int_bits + self.cfg.coord_frac_bits
    }
    pub fn weight_bits(&self) -> u32 {
        self.cfg.weight_bits
    }
    pub fn weight_rounding(&self) -> WeightRounding {
        self.cfg.weight_rounding
    }
    pub fn filter(&self) -> Filter {
        self.cfg.filter
    }
    pub fn address(&self) -> [AddressMode; 3] {
        self.cfg.address
    }
    pub fn texels_per_clock(&self) -> u32 {
        self.cfg.texels_per_clock
    }
    /// Texel RAM bits actually held (the bit vector's length).
    pub fn ram_bits(&self) -> u64 {
        self.ram.len() as u64
    }
    /// The packed texel RAM.
    pub fn ram(&self) -> &BitSlice<u64, Lsb0> {
        &self.ram
    }

    /// Read one stored code (coordinates wrapped into range; no counters).
    pub fn texel(&self, x: u32, y: u32, z: u32, c: u32) -> u32 {
        let [w, h, d] = self.cfg.size;
        let a = ((z % d) as u64 * h as u64 + (y % h) as u64) * w as u64 + (x % w) as u64;
        self.read(a, c % self.cfg.channels)
    }

    /// Width of the texel RAM address: ceil(log2(w·h·d)).
    pub fn addr_bits(&self) -> u32 {
        ceil_log2(self.cfg.texel_count())
    }

    /// Width of a product weight: d·wb + 1 (it can equal W^d).
    fn pw_bits(&self) -> u32 {
        self.cfg.dims * self.cfg.weight_bits + 1
    }

    /// Width of the accumulator: tb + d·wb.
    fn acc_bits(&self) -> u32 {
        self.cfg.texel_bits + self.cfg.dims * self.cfg.weight_bits
    }

    /// Filter lanes (texel × weight multipliers per channel): one per port used.
    fn lanes(&self) -> u32 {
        self.cfg.texels_per_clock.min(self.cfg.texels_per_sample())
    }

    #[inline(always)]
    fn read(&self, texel_addr: u64, c: u32) -> u32 {
        let tb = self.cfg.texel_bits as usize;
        let bit = (texel_addr as usize * self.cfg.channels as usize + c as usize) * tb;
        let words = self.ram.as_raw_slice();
        if 64 % tb == 0 {
            // A width that divides 64 never straddles two words.
            ((words[bit / 64] >> (bit % 64)) & (u64::MAX >> (64 - tb))) as u32
        } else {
            crate::packed_rom::read_field(words, bit, tb as u32) as u32
        }
    }

    /// The coordinate wires: the low I + F bits of the word, sign-extended.
    /// Returns the value and whether the word did not fit (it wrapped).
    #[inline]
    pub fn coord_wire(&self, word: i32) -> (i64, bool) {
        let w = self.coord_bits(); // 1 ..= 32
        let sh = 64 - w;
        let v = ((word as i64) << sh) >> sh; // s(I).F
        (v, v != word as i64)
    }

    /// Address mode of one axis on an s(I+1) integer index → u(axis_bits).
    #[inline]
    fn address_axis(&self, k: usize, i: i64) -> u64 {
        let size = self.cfg.size[k] as i64;
        match self.cfg.address[k] {
            AddressMode::Clamp => i.clamp(0, size - 1) as u64,
            // Power-of-two sizes: the low axis_bits bits (a mask); otherwise a remainder.
            AddressMode::Wrap => i.rem_euclid(size) as u64,
        }
    }

    #[inline]
    fn texel_addr(&self, idx: [u64; 3]) -> u64 {
        let [w, h, _] = self.cfg.size;
        // z·(w·h) + y·w + x: u(addr_bits) (concatenation for power-of-two sizes).
        (idx[2] * h as u64 + idx[1]) * w as u64 + idx[0]
    }

    /// Bilinear set-up of one axis from its s(I).F coordinate: the two texel indices
    /// (address mode applied) and their weights (u(wb+1) each, summing to W = 2^wb).
    #[inline(always)]
    fn linear_axis(&self, k: usize, c: i64) -> ([u64; 2], [u64; 2]) {
        let f = self.cfg.coord_frac_bits;
        let wb = self.cfg.weight_bits;
        let big_w = 1u64 << wb;
        // p = u − ½ with Fp = max(F, 1) fraction bits (F = 0 needs one more bit for
        // the ½): s(I).F → s(I+1).Fp, exact.
        let fp = f.max(1);
        let p = (c << (fp - f)) - (1i64 << (fp - 1));
        let i0 = p >> fp; // floor(p): s(I+1)
        let fr = (p - (i0 << fp)) as u64; // the fraction a: u(Fp)
        let fx = if fp <= wb {
            fr << (wb - fp) // exact: u(Fp) → u(wb)
        } else {
            let s = fp - wb;
            match self.cfg.weight_rounding {
                // u(Fp) + half → u(Fp+1) >> s → u(wb+1), fx ∈ [0, W]
                WeightRounding::Round => (fr + (1 << (s - 1))) >> s,
                // u(Fp) >> s → u(wb), fx ∈ [0, W − 1]
                WeightRounding::Truncate => fr >> s,
                // u(Fp) >> s → u(wb), + 1 above half or at half with an odd
                // quotient → u(wb+1), fx ∈ [0, W]
                WeightRounding::RoundHalfEven => {
                    let q = fr >> s;
                    let rem = fr & ((1 << s) - 1);
                    let half = 1 << (s - 1);
                    q + u64::from(rem > half || (rem == half && q & 1 == 1))
                }
            }
        };
        (
            [self.address_axis(k, i0), self.address_axis(k, i0 + 1)],
            [big_w - fx, fx],
        )
    }

    /// The corners of one lookup at the coordinate wires `c` (s(I).F per used axis):
    /// the address arithmetic the kernel runs ([`Self::address_axis`] on floor(u) for
    /// nearest, [`Self::linear_axis`] per axis for linear), shared by the kernel and
    /// by [`Self::footprint`].
    #[inline(always)]
    // Per-axis loops index several parallel per-axis arrays, as the hardware does.
    #[allow(clippy::needless_range_loop)]
    fn corners_at(&self, c: &[i64; 3]) -> Corners {
        let d = self.cfg.dims as usize;
        let f = self.cfg.coord_frac_bits;
        let mut out = Corners::default();
        match self.cfg.filter {
            Filter::Nearest => {
                let mut idx = [0u64; 3];
                for k in 0..d {
                    // floor(u): s(I).F >> F → s(I)
                    idx[k] = self.address_axis(k, c[k] >> f);
                }
                out.len = 1;
                out.texel[0] = self.texel_addr(idx) as u32;
                out.weight[0] = 1;
            }
            Filter::Linear => {
                let big_w = 1u64 << self.cfg.weight_bits; // W = 2^wb
                let mut i01 = [[0u64; 2]; 3];
                let mut w01 = [[big_w, 0u64]; 3];
                for k in 0..d {
                    (i01[k], w01[k]) = self.linear_axis(k, c[k]);
                }
                out.len = 1 << d;
                for corner in 0..(1usize << d) {
                    let mut idx = [0u64; 3];
                    let mut pw = 1u64;
                    for k in 0..d {
                        let b = (corner >> k) & 1;
                        idx[k] = i01[k][b];
                        pw *= w01[k][b]; // u(wb+1)^d → u(d·wb+1), ≤ W^d
                    }
                    // u(addr_bits) ≤ 24 bits: fits a u32.
                    out.texel[corner] = self.texel_addr(idx) as u32;
                    out.weight[corner] = pw;
                }
            }
        }
        out
    }

    /// The coordinate wires of an input word (no counters: the kernel counts a
    /// wrapped word when it samples).
    #[inline(always)]
    fn wires(&self, input: &TextureSamplerIn) -> [i64; 3] {
        let mut c = [0i64; 3];
        for (k, ck) in c.iter_mut().enumerate().take(self.cfg.dims as usize) {
            *ck = self.coord_wire(input.coord[k]).0;
        }
        c
    }

    /// The texels one lookup of `input` reads and their weights, in the kernel's
    /// order (a pure function: no counters, no RAM read).
    pub fn corners(&self, input: &TextureSamplerIn) -> Corners {
        self.corners_at(&self.wires(input))
    }

    /// The texel indices (x + w·(y + h·z), after wrap or clamp) one lookup of `input`
    /// fetches, in the kernel's order, appended to `out`: 1 (nearest) or 2, 4, 8
    /// (linear in 1, 2, 3 dimensions). Over a span their count is the kernel's
    /// `table_reads`.
    pub fn footprint(&self, input: &TextureSamplerIn, out: &mut Vec<u32>) {
        out.extend_from_slice(self.corners(input).texels());
    }

    /// [`Self::footprint`] of the lane form's inputs ([`Self::sample_lanes_keep`]):
    /// lookup i at `s[i]` (and `t[i]` for 2D and 3D, `r[i]` for 3D; lanes of unused
    /// axes are not read and may be empty), the lookups' texels appended in lane order.
    pub fn footprint_lanes(&self, s: &[i32], t: &[i32], r: &[i32], out: &mut Vec<u32>) {
        let d = self.cfg.dims as usize;
        out.reserve(s.len() * self.cfg.texels_per_sample() as usize);
        for (i, &si) in s.iter().enumerate() {
            let input = TextureSamplerIn {
                coord: [
                    si,
                    if d >= 2 { t[i] } else { 0 },
                    if d >= 3 { r[i] } else { 0 },
                ],
            };
            self.footprint(&input, out);
        }
    }

    /// `sample` over a chunk of one-channel 1D or 2D coordinates with the texel
    /// fetches counted once per chunk; false (nothing done) for other configs.
    /// Only the inputs `keep` selects (by index) are sampled; the others give
    /// `[0; 4]` but are counted as sampled (their fetches and wrapped coordinate
    /// wires), so the counters are those of all the inputs.
    #[inline(always)]
    fn sample_batch_1ch(
        &self,
        inputs: &[TextureSamplerIn],
        keep: impl Fn(usize) -> bool,
        out: &mut Vec<[u32; 4]>,
        ctr: &mut Counters,
    ) -> bool {
        let d = self.cfg.dims as usize;
        if self.cfg.channels != 1 || d > 2 {
            return false;
        }
        let f = self.cfg.coord_frac_bits;
        let w = self.cfg.size[0] as u64;
        let mut overflows = 0u64;
        let mut wire = |word: i32| {
            let (v, wrapped) = self.coord_wire(word);
            overflows += u64::from(wrapped);
            v
        };
        match self.cfg.filter {
            Filter::Nearest => out.extend(inputs.iter().enumerate().map(|(k, x)| {
                if !keep(k) {
                    wire(x.coord[0]);
                    if d == 2 {
                        wire(x.coord[1]);
                    }
                    return [0; 4];
                }
                let ix = self.address_axis(0, wire(x.coord[0]) >> f);
                let iy = if d == 2 {
                    self.address_axis(1, wire(x.coord[1]) >> f)
                } else {
                    0
                };
                [self.read(iy * w + ix, 0), 0, 0, 0]
            })),
            Filter::Linear => {
                let shift = d as u32 * self.cfg.weight_bits; // 1 ..= 32
                let half = 1u64 << (shift - 1);
                out.extend(inputs.iter().enumerate().map(|(k, x)| {
                    if !keep(k) {
                        wire(x.coord[0]);
                        if d == 2 {
                            wire(x.coord[1]);
                        }
                        return [0; 4];
                    }
                    let (ix, wx) = self.linear_axis(0, wire(x.coord[0]));
                    let acc = if d == 1 {
                        self.read(ix[0], 0) as u64 * wx[0] + self.read(ix[1], 0) as u64 * wx[1]
                    } else {
                        let (iy, wy) = self.linear_axis(1, wire(x.coord[1]));
                        let (r0, r1) = (iy[0] * w, iy[1] * w);
                        // u(tb) × u(2wb+1), four terms < 2^(tb+2wb)
                        self.read(r0 + ix[0], 0) as u64 * (wx[0] * wy[0])
                            + self.read(r0 + ix[1], 0) as u64 * (wx[1] * wy[0])
                            + self.read(r1 + ix[0], 0) as u64 * (wx[0] * wy[1])
                            + self.read(r1 + ix[1], 0) as u64 * (wx[1] * wy[1])
                    };
                    [((acc + half) >> shift) as u32, 0, 0, 0]
                }));
            }
        }
        self.count_samples(inputs.len() as u64, ctr);
        ctr.overflows += overflows;
        true
    }

    /// The counters of `n` samples none of whose coordinate wires wraps, filtered or
    /// not: what the kernel counts on them (each sample's texel fetches).
    pub fn count_samples(&self, n: u64, ctr: &mut Counters) {
        texel_fetch(
            ctr,
            n * self.cfg.texels_per_sample() as u64,
            self.cfg.texel_bits * self.cfg.channels,
        );
    }

    /// [`Unit::kernel_batch`] where the caller discards some outputs: the outputs of
    /// the inputs with `keep[i]` are the kernel's; the others are unspecified (`[0;
    /// 4]` where the batch kernel skips their filtering, the kernel's otherwise). The
    /// counters are always those of the kernel on every input (a skipped sample still
    /// counts its fetches and wrapped coordinate wires). `keep` is as long as `inputs`.
    pub fn kernel_batch_keep(
        &self,
        inputs: &[TextureSamplerIn],
        keep: &[bool],
        out: &mut Vec<[u32; 4]>,
        ctr: &mut Counters,
    ) {
        assert_eq!(
            keep.len(),
            inputs.len(),
            "texture_sampler: one keep flag per input"
        );
        if self.cfg.filter_rounding == FilterRounding::SuccessiveLerps
            || !self.sample_batch_1ch(inputs, |k| keep[k], out, ctr)
        {
            out.extend(inputs.iter().map(|x| self.sample(x, ctr)));
        }
    }

    /// The batch kernel's lane form for a one-channel 1D or 2D texture: input i is
    /// the coordinate word `s[i]` (and `t[i]` for 2D; `t` is not read for 1D). Each
    /// input with `keep(i)` gets its channel-0 code in `out[i]`; the other `out`
    /// entries are left as they are. The counters are those of
    /// [`Unit::kernel_batch`] on every input (fetches and wrapped coordinate wires
    /// counted in one pass over the lanes, the filter run on the kept ones only).
    /// False with nothing done where the batch kernel goes word by word (other
    /// configs, successive lerps) or the lanes' lengths differ.
    pub fn sample_lanes_keep(
        &self,
        s: &[i32],
        t: &[i32],
        keep: impl Fn(usize) -> bool,
        out: &mut [u32],
        ctr: &mut Counters,
    ) -> bool {
        let d = self.cfg.dims as usize;
        let n = s.len();
        if self.cfg.channels != 1
            || d > 2
            || self.cfg.filter_rounding == FilterRounding::SuccessiveLerps
            || out.len() != n
            || (d == 2 && t.len() != n)
        {
            return false;
        }
        // The wrapped wires of every input: a branch-free count over the lanes.
        let sh = 64 - self.coord_bits();
        let wraps = |c: &[i32]| -> u64 {
            c.iter()
                .map(|&w| u64::from((((w as i64) << sh) >> sh) != w as i64))
                .sum()
        };
        let mut overflows = wraps(s);
        if d == 2 {
            overflows += wraps(t);
        }
        if let Some(lanes) = LaneFilter::of(self) {
            lanes.run(&self.unpacked, s, t, keep, out);
        } else {
            self.sample_lanes_packed(s, t, keep, out);
        }
        self.count_samples(n as u64, ctr);
        ctr.overflows += overflows;
        true
    }

    /// [`Self::sample_lanes_keep`]'s filter on the packed RAM, a lane at a time: the
    /// form for the configurations [`LaneFilter`] does not take.
    fn sample_lanes_packed(
        &self,
        s: &[i32],
        t: &[i32],
        keep: impl Fn(usize) -> bool,
        out: &mut [u32],
    ) {
        let d = self.cfg.dims as usize;
        let f = self.cfg.coord_frac_bits;
        let w = self.cfg.size[0] as u64;
        let wire = |word: i32| self.coord_wire(word).0;
        match self.cfg.filter {
            Filter::Nearest => {
                for (i, o) in out.iter_mut().enumerate() {
                    if keep(i) {
                        let ix = self.address_axis(0, wire(s[i]) >> f);
                        let iy = if d == 2 {
                            self.address_axis(1, wire(t[i]) >> f)
                        } else {
                            0
                        };
                        *o = self.read(iy * w + ix, 0);
                    }
                }
            }
            Filter::Linear => {
                let shift = d as u32 * self.cfg.weight_bits; // 1 ..= 32
                let half = 1u64 << (shift - 1);
                for (i, o) in out.iter_mut().enumerate() {
                    if !keep(i) {
                        continue;
                    }
                    let (ix, wx) = self.linear_axis(0, wire(s[i]));
                    let acc = if d == 1 {
                        self.read(ix[0], 0) as u64 * wx[0] + self.read(ix[1], 0) as u64 * wx[1]
                    } else {
                        let (iy, wy) = self.linear_axis(1, wire(t[i]));
                        let (r0, r1) = (iy[0] * w, iy[1] * w);
                        // u(tb) × u(2wb+1), four terms < 2^(tb+2wb)
                        self.read(r0 + ix[0], 0) as u64 * (wx[0] * wy[0])
                            + self.read(r0 + ix[1], 0) as u64 * (wx[1] * wy[0])
                            + self.read(r1 + ix[0], 0) as u64 * (wx[0] * wy[1])
                            + self.read(r1 + ix[1], 0) as u64 * (wx[1] * wy[1])
                    };
                    *o = ((acc + half) >> shift) as u32;
                }
            }
        }
    }

    /// The datapath on one coordinate: the filtered codes (unused channels 0).
    // Per-axis loops index several parallel per-axis arrays, as the hardware does.
    #[allow(clippy::needless_range_loop)]
    pub fn sample(&self, input: &TextureSamplerIn, ctr: &mut Counters) -> [u32; 4] {
        let d = self.cfg.dims as usize;
        let ch = self.cfg.channels;
        let mut c = [0i64; 3];
        for k in 0..d {
            let (v, wrapped) = self.coord_wire(input.coord[k]);
            ctr.overflows += u64::from(wrapped);
            c[k] = v; // s(I).F
        }
        texel_fetch(
            ctr,
            self.cfg.texels_per_sample() as u64,
            self.cfg.texel_bits * ch,
        );
        let mut out = [0u32; 4];
        match self.cfg.filter {
            Filter::Nearest => {
                let a = self.corners_at(&c).texel[0] as u64;
                for (cc, o) in out.iter_mut().enumerate().take(ch as usize) {
                    *o = self.read(a, cc as u32);
                }
            }
            Filter::Linear if self.cfg.filter_rounding == FilterRounding::SuccessiveLerps => {
                self.successive_lerps(&c, &mut out);
            }
            Filter::Linear => {
                let wb = self.cfg.weight_bits;
                let corners = self.corners_at(&c);
                let mut acc = [0u64; 4]; // u(tb + d·wb) each
                for (&a, &pw) in corners.texels().iter().zip(&corners.weight) {
                    let a = a as u64;
                    for (cc, acc_c) in acc.iter_mut().enumerate().take(ch as usize) {
                        // u(tb) × u(d·wb+1); the sum stays ≤ (2^tb − 1)·W^d < 2^(tb+d·wb)
                        *acc_c += self.read(a, cc as u32) as u64 * pw;
                    }
                }
                let shift = d as u32 * wb; // 1 ..= 48
                let half = 1u64 << (shift - 1);
                for (o, &a) in out.iter_mut().zip(acc.iter()).take(ch as usize) {
                    // round half up: (u(tb+d·wb) + W^d/2) >> d·wb → u(tb), ≤ 2^tb − 1
                    *o = ((a + half) >> shift) as u32;
                }
            }
        }
        out
    }

    /// Linear filtering by [`FilterRounding::SuccessiveLerps`]: per channel the 2^d
    /// corner codes are lerped along s (pairwise), then t, then r; every lerp rounds
    /// back to u(tb), so a later lerp sees the earlier one's rounded code.
    // Per-axis loops index several parallel per-axis arrays, as the hardware does.
    #[allow(clippy::needless_range_loop)]
    fn successive_lerps(&self, c: &[i64; 3], out: &mut [u32; 4]) {
        let d = self.cfg.dims as usize;
        let wb = self.cfg.weight_bits;
        let mut fx = [0i64; 3];
        for k in 0..d {
            let (_, w) = self.linear_axis(k, c[k]);
            fx[k] = w[1] as i64; // the upper corner's weight: u(wb+1), ≤ W
        }
        // The corner texels the product-weight datapath reads, in its order.
        let at = self.corners_at(c);
        let corners = 1usize << d;
        for (cc, o) in out.iter_mut().enumerate().take(self.cfg.channels as usize) {
            let mut v = [0i64; 8]; // u(tb) codes; corner bit k selects axis k's texel
            for (vc, &a) in v.iter_mut().zip(at.texels()) {
                *vc = self.read(a as u64, cc as u32) as i64;
            }
            // Axis k pairs corners 2j and 2j + 1 (they differ in axis k only).
            let mut len = corners;
            for &w in fx.iter().take(d) {
                len /= 2;
                for j in 0..len {
                    v[j] = lerp_round(w, v[2 * j], v[2 * j + 1], wb);
                }
            }
            *o = v[0] as u32;
        }
    }

    /// Gate-cost parts of one axis's address / weight logic.
    fn axis_cost(&self, k: usize, mut cost: Cost) -> Cost {
        let i = self.cfg.coord_int_bits;
        let f = self.cfg.coord_frac_bits;
        let wb = self.cfg.weight_bits;
        let ab = self.axis_bits[k];
        let size = self.cfg.size[k];
        let axis = ["s", "t", "r"][k];
        let linear = self.cfg.filter == Filter::Linear;
        let nidx = if linear { 2 } else { 1 };
        if linear {
            // p = u − ½: a constant subtract over the integer bits and the top fraction bit.
            cost = cost.part(&format!("{axis}: p = u − ½"), prim::adder(i + 1));
            // The fraction of p has max(F, 1) significant bits; only more than wb need rounding.
            if f.max(1) > wb && self.cfg.weight_rounding != WeightRounding::Truncate {
                cost = cost.part(
                    &format!("{axis}: weight round (incrementer)"),
                    prim::half_adder() * (wb + 1) as f64,
                );
            }
            cost = cost
                .part(&format!("{axis}: W − fx"), prim::subtractor(wb + 1))
                .part(
                    &format!("{axis}: i1 = i0 + 1"),
                    prim::half_adder() * (i + 1) as f64,
                );
        }
        let per_index: Cells = match self.cfg.address[k] {
            // i < 0 is the sign bit; i > size − 1 a comparator; a 3:1 select.
            AddressMode::Clamp => prim::comparator(i + 1) + prim::mux_k(ab, 3),
            AddressMode::Wrap if size.is_power_of_two() => Cells::default(), // a mask
            // Floored remainder by a constant: restoring rows for the quotient bits.
            AddressMode::Wrap => prim::divider(i + 1, (i + 1).saturating_sub(ab) + 1),
        };
        cost.part(
            &format!("{axis}: address mode ×{nidx}"),
            per_index * nidx as f64,
        )
    }
}

/// The lane kernels' form of a one-channel 1D or 2D texture
/// ([`TextureSampler::sample_lanes_keep`]): the same integers as the kernel, in 32-bit
/// lanes over the unpacked texels, every lane computed without a branch (the
/// compiler's vector gathers) and the kept ones stored. Built by [`Self::of`] where
/// every value fits: coordinate words of at most 30 bits (the ½-shifted p in s(32)),
/// the accumulator tb + d·wb ≤ 31 bits, each used axis clamped or wrapped on a
/// power-of-two size, product weights, and a weight rounding that is exact or a
/// shift (`round` or `truncate` when Fp > wb).
#[derive(Clone, Copy, Debug)]
struct LaneFilter {
    dims: usize,
    linear: bool,
    /// 32 − (I + F): a word's low I + F bits sign-extended by a left then an
    /// arithmetic right shift.
    wire_shift: u32,
    /// F, the coordinate's fraction bits (nearest: floor(u) = c >> F).
    frac: u32,
    /// Linear: p = (c << up) − half_p, with Fp = `fp` fraction bits; fr = p & fmask.
    up: u32,
    fp: u32,
    half_p: i32,
    fmask: i32,
    /// The weight: ((fr << w_up) + w_round) >> w_down, u(wb+1); the other W − fx.
    w_up: u32,
    w_round: i32,
    w_down: u32,
    big_w: i32,
    /// Per axis, the address mode: (i & and_mask) clamped to 0 ..= hi (clamp: all
    /// ones; wrap on a power of two: size − 1, after which the clamp does nothing).
    and_mask: [i32; 2],
    hi: [i32; 2],
    width: i32,
    /// The accumulator's rounding: (acc + half) >> shift, shift = d·wb (linear).
    shift: u32,
    half: u32,
}

impl LaneFilter {
    fn of(t: &TextureSampler) -> Option<LaneFilter> {
        let c = &t.cfg;
        let d = c.dims as usize;
        if t.unpacked.is_empty()
            || d > 2
            || c.filter_rounding != FilterRounding::ProductWeights
            || c.coord_int_bits + c.coord_frac_bits > 30
            || c.texel_bits + c.dims * c.weight_bits > 31
        {
            return None;
        }
        let (mut and_mask, mut hi) = ([-1i32; 2], [0i32; 2]);
        for k in 0..d {
            let size = c.size[k];
            hi[k] = size as i32 - 1;
            match c.address[k] {
                AddressMode::Clamp => {}
                AddressMode::Wrap if size.is_power_of_two() => and_mask[k] = size as i32 - 1,
                AddressMode::Wrap => return None,
            }
        }
        let (f, wb) = (c.coord_frac_bits, c.weight_bits);
        let fp = f.max(1);
        let (w_up, w_round, w_down) = if fp <= wb {
            (wb - fp, 0, 0)
        } else {
            let s = fp - wb;
            match c.weight_rounding {
                WeightRounding::Round => (0, 1i32 << (s - 1), s),
                WeightRounding::Truncate => (0, 0, s),
                WeightRounding::RoundHalfEven => return None,
            }
        };
        let shift = c.dims * wb;
        Some(LaneFilter {
            dims: d,
            linear: c.filter == Filter::Linear,
            wire_shift: 32 - (c.coord_int_bits + c.coord_frac_bits),
            frac: f,
            up: fp - f,
            fp,
            half_p: 1 << (fp - 1),
            fmask: (1 << fp) - 1,
            w_up,
            w_round,
            w_down,
            big_w: 1 << wb,
            and_mask,
            hi,
            width: c.size[0] as i32,
            shift,
            half: 1 << (shift - 1),
        })
    }

    /// Lane i's code into `out[i]` where `keep(i)`, from the coordinate words `s[i]`
    /// (and `t[i]` in 2D) and the unpacked texels `tex`.
    fn run(
        &self,
        tex: &[u32],
        s: &[i32],
        t: &[i32],
        keep: impl Fn(usize) -> bool,
        out: &mut [u32],
    ) {
        // A block's codes, every lane's, before the kept ones are stored.
        const BLOCK: usize = 64;
        let mut codes = [0u32; BLOCK];
        let mut i = 0;
        while i < out.len() {
            let m = (out.len() - i).min(BLOCK);
            // A block with no lane kept stores nothing: not filtered (the filter has
            // no state and no counters here; the caller counts every lane).
            if !(i..i + m).any(&keep) {
                i += m;
                continue;
            }
            let (sb, cb) = (&s[i..i + m], &mut codes[..m]);
            match (self.dims, self.linear) {
                (1, true) => self.linear_1d(tex, sb, cb),
                (_, true) => self.linear_2d(tex, sb, &t[i..i + m], cb),
                (1, false) => self.nearest(tex, sb, sb, cb),
                (_, false) => self.nearest(tex, sb, &t[i..i + m], cb),
            }
            for (j, (o, &v)) in out[i..i + m].iter_mut().zip(cb.iter()).enumerate() {
                if keep(i + j) {
                    *o = v;
                }
            }
            i += m;
        }
    }

    /// A coordinate word's wires: its low I + F bits, sign-extended (s(I).F).
    #[inline(always)]
    fn wire(&self, word: i32) -> i32 {
        (word << self.wire_shift) >> self.wire_shift
    }

    /// Axis k's address mode on an integer texel index.
    #[inline(always)]
    fn axis(&self, k: usize, i: i32) -> i32 {
        (i & self.and_mask[k]).clamp(0, self.hi[k])
    }

    /// Axis k's bilinear set-up: the two texel indices and the upper one's weight.
    #[inline(always)]
    fn linear_axis(&self, k: usize, word: i32) -> (i32, i32, i32) {
        let p = (self.wire(word) << self.up) - self.half_p; // s(I+1).Fp
        let i0 = p >> self.fp;
        let fx = (((p & self.fmask) << self.w_up) + self.w_round) >> self.w_down;
        (self.axis(k, i0), self.axis(k, i0 + 1), fx)
    }

    /// The texel at address `a`, read without a bounds check (which would keep the
    /// loops from becoming vector gathers).
    #[inline(always)]
    fn at(tex: &[u32], a: i32) -> u32 {
        debug_assert!((0..tex.len() as i64).contains(&(a as i64)));
        // SAFETY: every address the kernels form is in range. Each axis index is
        // clamped to 0 ..= size − 1 by `axis` (size ≥ 1); a 1D lookup reads x ≤ w − 1
        // (nearest's row is 0), a 2D one y·w + x ≤ (h − 1)·w + w − 1 = w·h − 1; and
        // `tex` holds every texel, w·h·d ≥ w·h words (`TextureSampler::load`).
        unsafe { *tex.get_unchecked(a as usize) }
    }

    fn linear_1d(&self, tex: &[u32], s: &[i32], codes: &mut [u32]) {
        for (c, &sw) in codes.iter_mut().zip(s) {
            let (x0, x1, fx) = self.linear_axis(0, sw);
            let acc = Self::at(tex, x0) * (self.big_w - fx) as u32 + Self::at(tex, x1) * fx as u32;
            *c = (acc + self.half) >> self.shift;
        }
    }

    fn linear_2d(&self, tex: &[u32], s: &[i32], t: &[i32], codes: &mut [u32]) {
        for ((c, &sw), &tw) in codes.iter_mut().zip(s).zip(t) {
            let (x0, x1, fx) = self.linear_axis(0, sw);
            let (y0, y1, fy) = self.linear_axis(1, tw);
            let (gx, gy) = (self.big_w - fx, self.big_w - fy);
            let (r0, r1) = (y0 * self.width, y1 * self.width);
            // u(tb) × u(2wb+1), four terms < 2^(tb+2wb) ≤ 2^31
            let acc = Self::at(tex, r0 + x0) * (gx * gy) as u32
                + Self::at(tex, r0 + x1) * (fx * gy) as u32
                + Self::at(tex, r1 + x0) * (gx * fy) as u32
                + Self::at(tex, r1 + x1) * (fx * fy) as u32;
            *c = (acc + self.half) >> self.shift;
        }
    }

    /// Nearest: floor(u) per axis (in 1D `t` is `s` and row 0 is read).
    fn nearest(&self, tex: &[u32], s: &[i32], t: &[i32], codes: &mut [u32]) {
        let row = i32::from(self.dims == 2) * self.width;
        for ((c, &sw), &tw) in codes.iter_mut().zip(s).zip(t) {
            let x = self.axis(0, self.wire(sw) >> self.frac);
            let y = self.axis(1, self.wire(tw) >> self.frac);
            *c = Self::at(tex, y * row + x);
        }
    }
}

impl Unit for TextureSampler {
    type In = TextureSamplerIn;
    type Out = [u32; 4];
    type State = ();

    fn name(&self) -> &'static str {
        "texture_sampler"
    }

    fn kernel(&self, _: &mut (), input: &TextureSamplerIn, ctr: &mut Counters) -> [u32; 4] {
        self.sample(input, ctr)
    }

    /// One-channel 1D and 2D textures (the shafts' F, h, light map and J) through
    /// `TextureSampler::sample_batch_1ch`; anything else word by word.
    fn kernel_batch(
        &self,
        st: &mut (),
        inputs: &[TextureSamplerIn],
        out: &mut Vec<[u32; 4]>,
        ctr: &mut Counters,
    ) {
        // The batch kernel is the product-weight datapath; successive lerps go word
        // by word.
        if self.cfg.filter_rounding == FilterRounding::SuccessiveLerps
            || !self.sample_batch_1ch(inputs, |_| true, out, ctr)
        {
            out.extend(inputs.iter().map(|x| self.kernel(st, x, ctr)));
        }
    }

    fn timing(&self) -> Timing {
        let n = self.cfg.texels_per_sample();
        let ii = n.div_ceil(self.cfg.texels_per_clock); // ports are the bottleneck
        let latency = match self.cfg.filter {
            // address (1) + RAM read into the output register (1)
            Filter::Nearest => 2,
            // address + weights (1), RAM reads (II clocks, one port batch each),
            // texel × weight multipliers (1), adder tree / accumulate + round (1)
            Filter::Linear if self.cfg.filter_rounding == FilterRounding::ProductWeights => 3 + ii,
            // address + weights (1), RAM reads (II), one clock per lerp level (d)
            Filter::Linear => 1 + ii + self.cfg.dims,
        };
        Timing { latency, ii }
    }

    fn cost(&self) -> Cost {
        let d = self.cfg.dims;
        let ch = self.cfg.channels;
        let tb = self.cfg.texel_bits;
        let wb = self.cfg.weight_bits;
        let n = self.cfg.texels_per_sample();
        let ii = self.timing().ii;
        let ab = self.addr_bits();
        let mut cost = Cost::default().part(
            "coordinate input registers",
            prim::register(d * self.coord_bits()),
        );
        for k in 0..d as usize {
            cost = self.axis_cost(k, cost);
        }
        // Texel address a = (z·h + y)·w + x. A power-of-two factor makes its product a
        // shift and the following "+ index" a concatenation (the index is below the
        // factor), so each factor is costed on its own: ·w when w is not a power of two
        // (rows, 2D and 3D), z·h when h is not (planes, 3D only). Each is a constant
        // multiplier, costed as a full one (an upper estimate), plus one adder per
        // texel. (A cube map's F × 6F texture has w = F a power of two: its address is
        // a concatenation, free, although 6F rows are not a power of two.)
        let [w, h, _] = self.cfg.size;
        let nidx = if self.cfg.filter == Filter::Linear {
            2.0
        } else {
            1.0
        };
        let mut base_adders = 0;
        if d == 3 && !h.is_power_of_two() {
            cost = cost.part(
                "address: plane base z·h",
                prim::multiplier(self.axis_bits[2], ceil_log2(h as u64 + 1)) * nidx,
            );
            base_adders += 1;
        }
        if d >= 2 && !w.is_power_of_two() {
            // The row number: y (2D), or z·h + y < d·h (3D).
            let rows = if d == 3 {
                h as u64 * self.cfg.size[2] as u64
            } else {
                h as u64
            };
            let row_bits = ceil_log2(rows).max(1);
            cost = cost.part(
                "address: row base ·w",
                prim::multiplier(row_bits, ceil_log2(w as u64 + 1)) * nidx,
            );
            base_adders += 1;
        }
        if base_adders > 0 {
            cost = cost.part(
                "address: base + index adders",
                prim::adder(ab) * (n * base_adders) as f64,
            );
        }
        cost = cost.part("texel address registers", prim::register(n * ab.max(1)));
        let lanes = self.lanes();
        if ii > 1 {
            cost = cost.part(
                "port address select",
                prim::mux_k(ab.max(1), ii) * lanes as f64,
            );
        }
        match self.cfg.filter {
            Filter::Nearest => cost
                .part("RAM output / output register", prim::register(ch * tb))
                .with_ram_bits(self.ram_bits()),
            Filter::Linear if self.cfg.filter_rounding == FilterRounding::SuccessiveLerps => {
                // Per channel 2^d − 1 lerps, each v1 − v0 (tb+1), w × Δ
                // ((wb+1) × (tb+1)), + W/2 and >> wb (an incrementer on the kept
                // bits), + v0 (tb), and a tb-bit register after each level.
                let lerps = ((1u32 << d) - 1) * ch;
                let lerp = prim::subtractor(tb + 1)
                    + prim::multiplier(wb + 1, tb + 1)
                    + prim::half_adder() * (tb + 2) as f64
                    + prim::adder(tb)
                    + prim::register(tb);
                cost.part("axis weight registers", prim::register(d * (wb + 1)))
                    .part(
                        "corner texel registers",
                        prim::register((n * ch * tb).max(1)),
                    )
                    .part(
                        "successive lerps (2^d − 1 per channel)",
                        lerp * lerps as f64,
                    )
                    .with_ram_bits(self.ram_bits())
            }
            Filter::Linear => {
                let pw = self.pw_bits();
                let acc = self.acc_bits();
                cost = cost.part("axis weight registers", prim::register(2 * d * (wb + 1)));
                // The 2^d corners go through in II batches of `lanes`; each lane forms its
                // corner's product weight in the clock its texels are read:
                // axis-weight select (II > 1), x·y: u(wb+1)² → u(2wb+1), xy·z → u(3wb+1).
                if ii > 1 {
                    cost = cost.part(
                        "lane axis-weight select",
                        prim::mux_k(wb + 1, ii) * (lanes * d) as f64,
                    );
                }
                if d >= 2 {
                    cost = cost.part(
                        "lane weight products (x·y)",
                        prim::multiplier(wb + 1, wb + 1) * lanes as f64,
                    );
                }
                if d == 3 {
                    cost = cost.part(
                        "lane weight products (xy·z)",
                        prim::multiplier(2 * wb + 1, wb + 1) * lanes as f64,
                    );
                }
                cost = cost.part("lane weight registers", prim::register(lanes * pw));
                cost = cost
                    .part("texel registers", prim::register(lanes * ch * tb))
                    .part(
                        "texel × weight multipliers",
                        prim::multiplier(tb, pw) * (lanes * ch) as f64,
                    )
                    .part("product registers", prim::register(lanes * ch * acc))
                    .part("adder tree", prim::adder(acc) * ((lanes - 1) * ch) as f64);
                if ii > 1 {
                    cost = cost
                        .part("accumulator adders", prim::adder(acc) * ch as f64)
                        .part("accumulator registers", prim::register(ch * acc));
                }
                cost.part(
                    "round half up (incrementer)",
                    prim::half_adder() * ((tb + 1) * ch) as f64,
                )
                .part("output register", prim::register(ch * tb))
                .with_ram_bits(self.ram_bits())
            }
        }
    }

    fn widths(&self) -> Vec<Width> {
        let mut v = vec![
            Width {
                name: "texel_bits",
                bits: self.cfg.texel_bits,
            },
            Width {
                name: "coord_int_bits",
                bits: self.cfg.coord_int_bits,
            },
            Width {
                name: "coord_frac_bits",
                bits: self.cfg.coord_frac_bits,
            },
            Width {
                name: "weight_bits",
                bits: self.cfg.weight_bits,
            },
            Width {
                name: "texel_word",
                bits: self.cfg.texel_bits * self.cfg.channels,
            },
            Width {
                name: "texel_addr",
                bits: self.addr_bits(),
            },
        ];
        if self.cfg.filter == Filter::Linear
            && self.cfg.filter_rounding == FilterRounding::SuccessiveLerps
        {
            v.push(Width {
                name: "lerp_product",
                bits: self.cfg.texel_bits + self.cfg.weight_bits + 2,
            });
        } else if self.cfg.filter == Filter::Linear {
            v.push(Width {
                name: "product_weight",
                bits: self.pw_bits(),
            });
            v.push(Width {
                name: "accumulator",
                bits: self.acc_bits(),
            });
        }
        v
    }

    fn in_signals(&self, input: &TextureSamplerIn) -> Vec<Signal> {
        let w = self.coord_bits();
        let mask = if w >= 64 { u64::MAX } else { (1u64 << w) - 1 };
        (0..self.cfg.dims as usize)
            .map(|k| Signal::new(IN_NAMES[k], w, input.coord[k] as i64 as u64 & mask))
            .collect()
    }

    fn out_signals(&self, out: &[u32; 4]) -> Vec<Signal> {
        (0..self.cfg.channels as usize)
            .map(|c| Signal::new(OUT_NAMES[c], self.cfg.texel_bits, out[c] as u64))
            .collect()
    }
}
