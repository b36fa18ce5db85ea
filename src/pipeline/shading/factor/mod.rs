//! BRDF factor textures: a host step factorises a BRDF into a few 2D textures, and the
//! multi-texture units rebuild it per pixel as their product (Kautz and McCool 1999; McCool, Ang and Ahmad 2001).
//!
//! Two factorisations, both of the same target value `v(ω_i, ω_o)` ([`FactorTarget`]):
//! * **Separable / SVD** (Kautz and McCool 1999, [`svd`]): v ≈ G(h) · H(d), with h the
//!   half-angle vector and d the difference vector (Rusinkiewicz 1998): the leading term
//!   of the SVD of the matrix `M[h][d]`, found by power iteration (alternating least
//!   squares) with the below-horizon entries weighted 0.
//! * **Homomorphic** (McCool, Ang and Ahmad 2001, [`homomorphic`]):
//!   log v ≈ log p₁(ω_i) + log p₂(h) + log p₃(ω_o), a sparse linear least-squares
//!   problem in log space, so the factors are positive by construction; log 0 is
//!   clamped at a floor ε.
//!
//! Every factor texture is indexed by the **parabolic map** of its direction (x, y, z)
//! in the upper hemisphere: (s, t) = (x, y) / (1 + z) in the unit disc, texture
//! coordinates ((s + 1)/2, (t + 1)/2) ∈ [0, 1]². Texels outside the disc hold the value
//! at the nearest horizon direction, so bilinear filtering at the rim stays smooth.
//!
//! Reconstruction ([`FactorRenderer`]): each factor is quantised to a b-bit texture with
//! its maximum at the top code; the product of the maxima and the irradiance E is split
//! into a power of two 2^K (the combiner's output scale, a saturating left shift) and a
//! mantissa in (½, 1] (a constant colour). Per pixel the host computes every texture
//! coordinate from (ω_i, ω_o) — on a GeForce3 they come per vertex from the vertex
//! program and are interpolated, so per pixel is the upper bound of the quality — the
//! `texture_sampler` units filter bilinearly, the `modulate` unit multiplies, the scale
//! shift saturates (counted), and the result is an 8-bit level 255 · v · E.

pub mod homomorphic;
pub mod reproduce;
pub mod svd;

use super::sphere::SphereView;
use crate::reference::brdf::Brdf;
use crate::report::metrics::{error_stats_masked, ErrorStats};
use crate::scene::limits::GlRounding;
use crate::scene::math::{v3, Vec3};
use rtl_model::counters::Counters;
use rtl_model::error::ConfigError;
use rtl_model::units::modulate::ModulateChain;
use rtl_model::units::texture_sampler::{TextureSampler, TextureSamplerConfig, TextureSamplerIn};

/// What the factors approximate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FactorTarget {
    /// R(ω_i, ω_o) · cos θ_i (the default): the cosine lives in the factors, the
    /// constant colour is the irradiance alone, and the least-squares fit weighs errors
    /// as they appear in the image. A light below the horizon is masked to 0 by the
    /// self-shadowing flag (N·L > 0, a per-vertex bit in hardware).
    BrdfCosine,
    /// R(ω_i, ω_o) alone; cos θ_i · E is the modulated constant colour (the per-vertex
    /// diffuse colour of GL lighting, here per pixel).
    Brdf,
}

impl FactorTarget {
    /// The value to factorise at (ω_i, ω_o): finite and ≥ 0 (a NaN, ∞ or negative
    /// BRDF value counts as 0, so a broken model cannot poison the fit).
    pub fn value(self, brdf: &dyn Brdf, wi: Vec3, wo: Vec3) -> f64 {
        let r = brdf.eval(wi, wo);
        let v = match self {
            FactorTarget::BrdfCosine => r * wi.z.max(0.0),
            FactorTarget::Brdf => r,
        };
        if v.is_finite() && v > 0.0 {
            v
        } else {
            0.0
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            FactorTarget::BrdfCosine => "brdf_cosine",
            FactorTarget::Brdf => "brdf",
        }
    }
}

/// The direction a factor texture is indexed by.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Projection {
    /// ω_i.
    Incident,
    /// ω_o.
    Outgoing,
    /// h = (ω_i + ω_o) / |ω_i + ω_o|.
    Half,
    /// d: ω_i in the frame where h is the pole (Rusinkiewicz's difference vector).
    Difference,
}

impl Projection {
    /// The projected direction of a pair.
    pub fn direction(self, wi: Vec3, wo: Vec3) -> Vec3 {
        match self {
            Projection::Incident => wi,
            Projection::Outgoing => wo,
            Projection::Half => half_vector(wi, wo),
            Projection::Difference => difference_vector(wi, wo),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Projection::Incident => "incident",
            Projection::Outgoing => "outgoing",
            Projection::Half => "half",
            Projection::Difference => "difference",
        }
    }
}

/// h = normalize(ω_i + ω_o); the normal (+z) when ω_i = −ω_o.
pub fn half_vector(wi: Vec3, wo: Vec3) -> Vec3 {
    let s = wi + wo;
    if s.length() < 1e-12 {
        v3(0.0, 0.0, 1.0)
    } else {
        s.normalized()
    }
}

/// cos φ_h, sin φ_h of h (φ_h = 0 at the pole, where the azimuth is undefined).
fn azimuth(h: Vec3) -> (f64, f64) {
    let r = (h.x * h.x + h.y * h.y).sqrt();
    if r < 1e-12 {
        (1.0, 0.0)
    } else {
        (h.x / r, h.y / r)
    }
}

/// Rusinkiewicz's difference vector: ω_i rotated by −φ_h about n, then by −θ_h about
/// the bitangent, so h itself would land on +z. d·z = ω_i·h ≥ 0 whenever h is defined.
pub fn difference_vector(wi: Vec3, wo: Vec3) -> Vec3 {
    let h = half_vector(wi, wo);
    let (cp, sp) = azimuth(h);
    let (ct, st) = (h.z.clamp(-1.0, 1.0), (1.0 - h.z * h.z).max(0.0).sqrt());
    let x1 = cp * wi.x + sp * wi.y;
    let y1 = -sp * wi.x + cp * wi.y;
    v3(ct * x1 - st * wi.z, y1, st * x1 + ct * wi.z)
}

/// The pair (ω_i, ω_o) of a half vector h and difference vector d (both unit): the
/// inverse of [`half_vector`] and [`difference_vector`].
pub fn from_half_difference(h: Vec3, d: Vec3) -> (Vec3, Vec3) {
    let (cp, sp) = azimuth(h);
    let (ct, st) = (h.z.clamp(-1.0, 1.0), (1.0 - h.z * h.z).max(0.0).sqrt());
    // Rotate d by +θ_h about the bitangent, then by +φ_h about n.
    let x1 = ct * d.x + st * d.z;
    let z1 = -st * d.x + ct * d.z;
    let wi = v3(cp * x1 - sp * d.y, sp * x1 + cp * d.y, z1);
    let wo = h * (2.0 * wi.dot(h)) - wi;
    (wi, wo)
}

/// Parabolic map of a direction to texture coordinates in [0, 1]²: (s, t) = (x, y) /
/// (1 + z), then ((s + 1)/2, (t + 1)/2). A direction below the horizon is taken at the
/// horizon (its (x, y) normalised), so the map never divides by ~0.
pub fn parabolic_coords(v: Vec3) -> [f64; 2] {
    let (s, t) = if v.z >= 0.0 {
        (v.x / (1.0 + v.z), v.y / (1.0 + v.z))
    } else {
        let r = (v.x * v.x + v.y * v.y).sqrt();
        if r < 1e-12 {
            (1.0, 0.0)
        } else {
            (v.x / r, v.y / r)
        }
    };
    [(s + 1.0) * 0.5, (t + 1.0) * 0.5]
}

/// The direction at texture coordinates `uv` (inverse parabolic map); outside the disc
/// the nearest horizon direction. Also returns whether `uv` lies inside the disc.
pub fn parabolic_direction(uv: [f64; 2]) -> (Vec3, bool) {
    let (mut s, mut t) = (uv[0] * 2.0 - 1.0, uv[1] * 2.0 - 1.0);
    let r2 = s * s + t * t;
    let inside = r2 <= 1.0;
    if !inside {
        let r = r2.sqrt();
        s /= r;
        t /= r;
    }
    let r2 = s * s + t * t;
    (v3(2.0 * s, 2.0 * t, 1.0 - r2) * (1.0 / (1.0 + r2)), inside)
}

/// A factor as an f64 texture: `size` × `size` texels, texel (x, y) at `y · size + x`,
/// x along the first texture coordinate.
#[derive(Clone, Debug, PartialEq)]
pub struct FactorTexture {
    pub projection: Projection,
    pub size: u32,
    pub texels: Vec<f64>,
}

impl FactorTexture {
    /// The texture coordinates of texel (x, y)'s centre.
    pub fn texel_uv(size: u32, x: u32, y: u32) -> [f64; 2] {
        let n = size as f64;
        [(x as f64 + 0.5) / n, (y as f64 + 0.5) / n]
    }

    /// Bilinear filtering at texel-space coordinates (u·size, v·size), clamp to edge,
    /// with the sampler's convention (p = u − ½, i0 = floor p).
    pub fn bilinear_texel_space(&self, u: f64, v: f64) -> f64 {
        let n = self.size as i64;
        let (px, py) = (u - 0.5, v - 0.5);
        let (fx, fy) = (px.floor(), py.floor());
        let (ax, ay) = (px - fx, py - fy);
        let c = |i: f64| (i as i64).clamp(0, n - 1) as usize;
        let (x0, x1, y0, y1) = (c(fx), c(fx + 1.0), c(fy), c(fy + 1.0));
        let t = |x: usize, y: usize| self.texels[y * n as usize + x];
        (1.0 - ay) * ((1.0 - ax) * t(x0, y0) + ax * t(x1, y0))
            + ay * ((1.0 - ax) * t(x0, y1) + ax * t(x1, y1))
    }

    /// Bilinear filtering at normalised texture coordinates.
    pub fn bilinear(&self, uv: [f64; 2]) -> f64 {
        let n = self.size as f64;
        self.bilinear_texel_space(uv[0] * n, uv[1] * n)
    }

    /// The largest texel (0 for an empty or all-zero texture).
    pub fn max(&self) -> f64 {
        self.texels.iter().copied().fold(0.0, f64::max)
    }
}

/// Which factorisation made a [`Factorisation`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FactorMethod {
    Svd,
    Homomorphic,
}

impl FactorMethod {
    pub fn name(self) -> &'static str {
        match self {
            FactorMethod::Svd => "svd",
            FactorMethod::Homomorphic => "homomorphic",
        }
    }
}

/// A BRDF as a product of f64 factor textures: v(ω_i, ω_o) ≈ Π_j F_j(π_j(ω_i, ω_o)).
#[derive(Clone, Debug, PartialEq)]
pub struct Factorisation {
    pub method: FactorMethod,
    pub target: FactorTarget,
    pub factors: Vec<FactorTexture>,
}

impl Factorisation {
    /// The f64 reconstruction of the target value: the product of the bilinearly
    /// filtered factors at exact coordinates.
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> f64 {
        self.factors
            .iter()
            .map(|f| f.bilinear(parabolic_coords(f.projection.direction(wi, wo))))
            .product()
    }

    /// Total texel count (all factors).
    pub fn texel_count(&self) -> u64 {
        self.factors
            .iter()
            .map(|f| f.size as u64 * f.size as u64)
            .sum()
    }
}

/// The constant that turns the product of normalised factors back into the 8-bit
/// level: T = E · Π max_j = 2^shift · mantissa, shift = max(0, ceil log2 T), so
/// mantissa ∈ (0, 1] (in (½, 1] whenever T > 1).
pub fn split_scale(total: f64) -> (u32, f64) {
    if !(total.is_finite() && total > 0.0) {
        return (0, 0.0);
    }
    let shift = total.log2().ceil().max(0.0) as u32;
    let mantissa = total / 2f64.powi(shift as i32);
    // log2 rounding can leave the mantissa a hair above 1.
    if mantissa > 1.0 {
        (shift + 1, mantissa * 0.5)
    } else {
        (shift, mantissa)
    }
}

/// Round a non-negative value in [0, 1] to an n-bit unorm code (saturating at the top).
fn unorm_code(x: f64, bits: u32) -> u32 {
    let max = ((1u64 << bits) - 1) as f64;
    (x.clamp(0.0, 1.0) * max).round() as u32
}

/// An n-bit code widened (or kept) to m ≥ n bits: round(c · (2^m − 1)/(2^n − 1)), the
/// exact unorm conversion (it equals bit replication when n divides m).
pub fn widen_code(code: u32, from_bits: u32, to_bits: u32) -> u32 {
    if from_bits == to_bits {
        return code;
    }
    let (a, b) = ((1u64 << from_bits) - 1, (1u64 << to_bits) - 1);
    // u(n) · u(m) → u(n+m) ≤ 32 bits; + a for round half up over 2a.
    ((2 * code as u64 * b + a) / (2 * a)) as u32
}

/// The combine step, isolated so a `texture_combiner` chain can replace it: the
/// operands (texture samples and the constant colour, all `chain.modulate().bits()`
/// wide) are multiplied left to right by the modulate chain (per-stage rounding: the
/// `modulate` unit at every stage; fused: Mesa's llvmpipe, one rounding at the end;
/// an empty list is 0), then the output scale 2^shift is a
/// left shift saturating at the top code (each clamp counts one `saturations`).
/// GL's combiner scale offers ×1, ×2, ×4 per stage, so a shift > 2 stands for the
/// scales of several stages.
pub fn combine(operands: &[u32], shift: u32, chain: &ModulateChain, ctr: &mut Counters) -> u32 {
    let bits = chain.modulate().bits();
    let max = (1u64 << bits) - 1;
    // Π operands through the chain: u(n) × … × u(n) → u(n) (rounded per stage, or once).
    let acc = if operands.is_empty() {
        0
    } else {
        chain.apply(operands) as u64
    };
    // u(n) << shift → u(n + shift), shift ≤ 63 − n keeps it in a u64.
    let shifted = if shift as u64 >= 64 - bits as u64 {
        if acc == 0 {
            0
        } else {
            u64::MAX
        }
    } else {
        acc << shift
    };
    if shifted > max {
        ctr.saturations += 1;
        max as u32
    } else {
        shifted as u32
    }
}

/// A factor sampler's coordinate words for the pair (ω_i, ω_o): the projected
/// direction's parabolic coordinates, quantised by the sampler's own input rule.
fn sampler_input(
    p: Projection,
    s: &TextureSampler,
    wi: Vec3,
    wo: Vec3,
    ctr: &mut Counters,
) -> Result<TextureSamplerIn, ConfigError> {
    let uv = parabolic_coords(p.direction(wi, wo));
    s.config().input_from_normalized([uv[0], uv[1], 0.0], ctr)
}

/// The value of a 2D sampler's coordinate words, in texels.
fn texel_coords(s: &TextureSampler, input: &TextureSamplerIn) -> [f64; 2] {
    let scale = (1u64 << s.coord_frac_bits()) as f64;
    [input.coord[0] as f64 / scale, input.coord[1] as f64 / scale]
}

/// A factor quantised to a b-bit texture: code = round(texel / max · (2^b − 1)).
#[derive(Clone, Debug, PartialEq)]
pub struct QuantisedFactor {
    pub projection: Projection,
    pub size: u32,
    pub texel_bits: u32,
    /// The f64 value of the top code (the factor's largest texel, 0 if all zero).
    pub max: f64,
    pub codes: Vec<u32>,
}

impl QuantisedFactor {
    pub fn new(f: &FactorTexture, texel_bits: u32) -> Self {
        let max = f.max();
        let codes = f
            .texels
            .iter()
            .map(|&t| {
                if max > 0.0 {
                    unorm_code(t / max, texel_bits)
                } else {
                    0
                }
            })
            .collect();
        QuantisedFactor {
            projection: f.projection,
            size: f.size,
            texel_bits,
            max,
            codes,
        }
    }

    /// Table bits: size² · b.
    pub fn bits(&self) -> u64 {
        self.size as u64 * self.size as u64 * self.texel_bits as u64
    }
}

/// The per-pixel reconstruction of a factorisation by the multi-texture units, beside
/// its f64 twin (the same textures unquantised, sampled at the same coordinates).
#[derive(Clone, Debug)]
pub struct FactorRenderer {
    method: FactorMethod,
    target: FactorTarget,
    /// One sampler per factor, with the factor's f64 texels normalised to max 1.
    samplers: Vec<(Projection, TextureSampler, FactorTexture)>,
    /// Each factor's scale: the f64 value of its top code.
    scales: Vec<f64>,
    /// The factors × constant colour chain: `modulate`'s stages, rounded per stage
    /// (default) or fused (Mesa's llvmpipe).
    chain: ModulateChain,
    texel_bits: u32,
    /// The combiner width n = max(8, texel_bits).
    combiner_bits: u32,
    /// The output scale 2^shift.
    shift: u32,
    /// E · Π max_j / 2^shift ∈ [0, 1]: the constant colour.
    mantissa: f64,
}

impl FactorRenderer {
    /// Quantise every factor of `fact` to `texel_bits` (1 ..= 16) and set up the
    /// samplers (GeForce defaults: bilinear, clamp, 8 sub-texel bits, 8-bit weights) and
    /// a `modulate` of n = max(8, texel_bits) bits for irradiance `irradiance`.
    pub fn new(
        fact: &Factorisation,
        texel_bits: u32,
        irradiance: f64,
    ) -> Result<Self, ConfigError> {
        Self::with_rounding(fact, texel_bits, irradiance, GlRounding::default())
    }

    /// [`Self::new`] with a choice of chain rounding (the modulate chain) and filter
    /// and weight rounding (the factor samplers): the scene's `[rounding]`.
    pub fn with_rounding(
        fact: &Factorisation,
        texel_bits: u32,
        irradiance: f64,
        rounding: GlRounding,
    ) -> Result<Self, ConfigError> {
        let combiner_bits = texel_bits.max(8);
        let chain = rounding.chain(combiner_bits)?;
        let mut total = if irradiance.is_finite() {
            irradiance.max(0.0)
        } else {
            return Err(ConfigError::not_finite("factor.irradiance", irradiance));
        };
        let mut samplers = Vec::new();
        let mut scales = Vec::new();
        for f in &fact.factors {
            let q = QuantisedFactor::new(f, texel_bits);
            total *= q.max;
            scales.push(q.max);
            let cfg = rounding.sampler(TextureSamplerConfig {
                texel_bits,
                ..TextureSamplerConfig::geforce_2d(f.size, f.size)
            });
            let sampler = TextureSampler::new(cfg, &q.codes)?;
            let normalised = FactorTexture {
                projection: f.projection,
                size: f.size,
                texels: f
                    .texels
                    .iter()
                    .map(|&t| {
                        if q.max > 0.0 {
                            (t / q.max).clamp(0.0, 1.0)
                        } else {
                            0.0
                        }
                    })
                    .collect(),
            };
            samplers.push((f.projection, sampler, normalised));
        }
        let (shift, mantissa) = split_scale(total);
        Ok(FactorRenderer {
            method: fact.method,
            target: fact.target,
            samplers,
            scales,
            chain,
            texel_bits,
            combiner_bits,
            shift,
            mantissa,
        })
    }

    /// Which factorisation made the textures.
    pub fn method(&self) -> FactorMethod {
        self.method
    }
    /// The output scale is 2^shift.
    pub fn shift(&self) -> u32 {
        self.shift
    }
    /// The constant colour's value before quantisation: E · Π scales / 2^shift.
    pub fn mantissa(&self) -> f64 {
        self.mantissa
    }
    /// Per factor, the f64 value its top code stands for.
    pub fn scales(&self) -> &[f64] {
        &self.scales
    }
    pub fn combiner_bits(&self) -> u32 {
        self.combiner_bits
    }
    pub fn texel_bits(&self) -> u32 {
        self.texel_bits
    }
    /// The units this reconstruction elaborates: one sampler per factor texture,
    /// then the modulate chain that multiplies them (with the constant colour).
    pub fn summaries(&self) -> Vec<rtl_model::UnitSummary> {
        let mut v: Vec<rtl_model::UnitSummary> = self
            .samplers
            .iter()
            .map(|(_, s, _)| rtl_model::UnitSummary::of(s))
            .collect();
        v.push(rtl_model::UnitSummary::of(&self.chain));
        v
    }

    /// Each factor texture as its sampler holds it: (side, codes row by row).
    pub fn texture_codes(&self) -> Vec<(u32, Vec<u32>)> {
        self.samplers
            .iter()
            .map(|(_, s, _)| {
                let [w, h, _] = s.size();
                let codes = (0..h)
                    .flat_map(|y| (0..w).map(move |x| (x, y)))
                    .map(|(x, y)| s.texel(x, y, 0, 0))
                    .collect();
                (w, codes)
            })
            .collect()
    }

    /// What one pixel hands the units: each factor sampler's coordinate (texels, the
    /// value of its coordinate words) and the constant colour's u(n) code.
    pub fn pixel_operands(&self, wi: Vec3, wo: Vec3) -> Result<(Vec<[f64; 2]>, u32), ConfigError> {
        let mut ctr = Counters::default();
        let mut coords = Vec::with_capacity(self.samplers.len());
        for (p, s, _) in &self.samplers {
            coords.push(texel_coords(s, &sampler_input(*p, s, wi, wo, &mut ctr)?));
        }
        Ok((
            coords,
            unorm_code(self.constant(wi, wo), self.combiner_bits),
        ))
    }

    /// Total texture bits.
    pub fn table_bits(&self) -> u64 {
        self.samplers.iter().map(|(_, s, _)| s.ram_bits()).sum()
    }

    /// The constant colour in [0, 1]: the mantissa, times cos θ_i for
    /// [`FactorTarget::Brdf`]; 0 when the light is below the horizon (self-shadowing)
    /// or the viewer is.
    fn constant(&self, wi: Vec3, wo: Vec3) -> f64 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        match self.target {
            FactorTarget::BrdfCosine => self.mantissa,
            FactorTarget::Brdf => self.mantissa * wi.z.min(1.0),
        }
    }

    /// One pixel through the units: an 8-bit level.
    pub fn shade(&self, wi: Vec3, wo: Vec3, ctr: &mut Counters) -> Result<u32, ConfigError> {
        let n = self.combiner_bits;
        let mut ops = Vec::with_capacity(self.samplers.len() + 1);
        for (p, s, _) in &self.samplers {
            let input = sampler_input(*p, s, wi, wo, ctr)?;
            let texel = s.sample(&input, ctr)[0]; // u(b)
            ops.push(widen_code(texel, self.texel_bits, n)); // u(b) → u(n)
        }
        ops.push(unorm_code(self.constant(wi, wo), n));
        let y = combine(&ops, self.shift, &self.chain, ctr) as u64; // u(n)
                                                                    // u(n) → 8-bit level, rounded: (y · 255 · 2 + max) / (2 · max).
        let max = (1u64 << n) - 1;
        Ok(((y * 255 * 2 + max) / (2 * max)) as u32)
    }

    /// The f64 twin of [`Self::shade`]: the unquantised normalised factors, filtered
    /// at the same texel-space coordinate words, multiplied in f64, clamped to 255.
    pub fn shade_f64(&self, wi: Vec3, wo: Vec3, ctr: &mut Counters) -> Result<f64, ConfigError> {
        let mut prod = self.constant(wi, wo);
        for (p, s, f) in &self.samplers {
            let [u, v] = texel_coords(s, &sampler_input(*p, s, wi, wo, ctr)?);
            prod *= f.bilinear_texel_space(u, v);
        }
        Ok((prod * 2f64.powi(self.shift as i32) * 255.0).clamp(0.0, 255.0))
    }

    /// The derived bound on |shade − shade_f64| in 8-bit levels (the quantisation
    /// error alone; the factorisation's own error is shade_f64 − reference):
    /// in units of the combiner's full scale, every texture sample is off by at most
    /// 1/(2^b − 1) (½ LSB texel rounding, filtered by weights that sum to 1, plus ½ LSB
    /// of the sampler's output rounding) plus ½ LSB_n when it is widened to n bits;
    /// the constant colour by ½ LSB_n; each of the m modulates rounds by ½ LSB_n; a
    /// product of values in [0, 1] moves by at most the sum of its operands' errors.
    /// The saturating shift multiplies by 2^shift (a clamp never grows an error), and
    /// the final n → 8-bit rounding adds ½ level when n > 8.
    pub fn error_bound_levels(&self) -> f64 {
        let (b, n) = (self.texel_bits, self.combiner_bits);
        let lsb_b = 1.0 / ((1u64 << b) - 1) as f64;
        let half_n = 0.5 / ((1u64 << n) - 1) as f64;
        let widen = if b < n { half_n } else { 0.0 };
        let textures = self.samplers.len() as f64;
        let modulates = textures; // textures + constant operands, one product fewer
        let full_scale = textures * (lsb_b + widen) + half_n + modulates * half_n;
        255.0 * 2f64.powi(self.shift as i32) * full_scale + if n > 8 { 0.5 } else { 0.0 }
    }

    /// Render the sphere: per pixel (hardware level, f64 twin level), None outside it.
    pub fn render(
        &self,
        view: &SphereView,
        ctr: &mut Counters,
    ) -> Result<Vec<Option<(u32, f64)>>, ConfigError> {
        view.pixels()
            .iter()
            .map(|p| match p {
                None => Ok(None),
                Some(p) => Ok(Some((
                    self.shade(p.wi, p.wo, ctr)?,
                    self.shade_f64(p.wi, p.wo, ctr)?,
                ))),
            })
            .collect()
    }
}

/// Mean, RMS and max |a − b| over the pixels where `mask` is true (gray images in
/// levels; the shared metric, each value counted as its three equal channels).
pub fn level_stats(a: &[f64], b: &[f64], mask: &[bool]) -> Result<ErrorStats, ConfigError> {
    let rgb = |v: &[f64]| v.iter().map(|&x| [x; 3]).collect::<Vec<_>>();
    error_stats_masked(&rgb(a), &rgb(b), mask)
}
