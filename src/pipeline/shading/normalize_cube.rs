//! The normalisation cube map: GeForce-era per-pixel lighting renormalises an
//! interpolated vector (L, H, N — shortened by the linear interpolation between unit
//! vertex vectors) by looking it up in a cube map whose texels hold the normalised
//! direction of their centre, packed as unorm RGB: code = round((n + 1)/2 · (2^b − 1)).
//!
//! # Through the existing units, no new one
//!
//! The path is the envmap's 2D-slice path (`pipeline::envmap::slice`): the
//! `cube_map_address` unit takes the interpolated vector's three fixed-point words
//! c = (v + 1)/2 · s (its input format: the direction is d = c − s/2, so only the
//! direction matters and any length works) and gives the 2D sampler's word for the
//! F × 6F stacked texture; the 2D `texture_sampler` with 3 channels of b bits reads it
//! (nearest, or bilinear within a face: the address unit clamps each face coordinate to
//! the texel-centre range, so no lookup filters across a face edge, as on GeForce3).
//! Everything fits as is: the address unit's input words are any s(I).F words, its
//! face side any power of two (F ≤ 512 so that 6F ≤ the sampler's 4096 rows), and the
//! sampler holds 3 channels of 1 ..= 16 bits.
//!
//! # What comes out, and the zero vector
//!
//! Three unorm codes; decoded, v' = 2·code/(2^b − 1) − 1. Not exactly unit length:
//! bilinear filtering of unit vectors shortens them (by ≤ the interpolation bound
//! below) and 8-bit texels carry ½ LSB per component. A zero-length vector (c = s/2
//! exactly) has no direction: the address unit flags it, counts one `underflows` and
//! reads face 0 (+x) at its centre — the result is +x (bilinear: the mean of the four
//! centre texels of face 0, about (1, ±1/F, ±1/F) normalised). No panic, no NaN;
//! [`normalize_f64`] gives +x for it too.
//!
//! # Error bound (derived from F, b and the address unit's widths)
//!
//! Let h = 2/F be the texel spacing in the face-plane coordinate u = sc/|ma| ∈ [−1, 1],
//! B = 2^b − 1, δ the address unit's coordinate bound in texels
//! (F/2·E + 2^−(Fo+1), E its reciprocal bound: see `tests/cube_map_address.rs` and
//! [`address_bound_texels`]), n(u, v) = (u, v, 1)/|(u, v, 1)| on a face.
//! * Directions on the face plane at distance 1 from the centre: the angle between two
//!   of them is ≤ their distance in the plane (|p| ≥ 1), so a coordinate error of
//!   Δ texels per axis moves the direction by ≤ √2·Δ·h.
//! * Nearest: the chosen texel's centre is within ½ texel per axis of the unit's
//!   coordinate, which is within δ of the exact one: the texel direction is within
//!   θ_t = √2·(½ + δ)·h; its stored code adds ≤ ½ LSB per component (|q| ≤ √3/B in
//!   value): angle ≤ θ_t + asin(√3/B); per component ≤ ½ + (B/2)·θ_t codes (a chord is
//!   ≤ its angle).
//! * Bilinear: within a face, the interpolant I of the exact texel directions at the
//!   sampled point q differs from n(q) by ≤ h²/8·(max|n_uu| + max|n_vv|) = h²/4
//!   (|n_uu| ≤ 1 on the face, attained at its centre — checked on a grid in the test),
//!   and n(q) from n at the exact point by ≤ √2·Δ·h with Δ = δ inside the face, and
//!   Δ = ½ + δ in the band within ½ + δ texel of a face edge (the texel-centre clamp
//!   moves the sample by up to ½ texel: the seam). Texel codes (convex combination)
//!   and the sampler's output rounding add ≤ ½ + ½ LSB per component, 2√3/B in value:
//!   |e| ≤ V = h²/4 + √2·Δ·h + 2√3/B, angle ≤ asin(min(1, V)); per component
//!   ≤ 1 + (B/2)·(h²/4 + √2·Δ·h) codes.
//!
//! The exact direction compared against is that of the input words (d = c − s/2, exact
//! in f64). Against the vector before it was quantised to words, a very short vector
//! adds its own quantisation: |Δd| ≤ √3/2 · 2^−Fi texels, angle ≤ asin(|Δd|/|d|) — the
//! interpolator's precision, not the cube map's.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::driver::run_span;
use rtl_model::units::cube_map_address::{
    CubeMapAddress, CubeMapAddressConfig, CubeMapAddressIn, CubeMapAddressOut,
};
use rtl_model::units::texture_sampler::{
    Filter, TextureSampler, TextureSamplerConfig, TextureSamplerIn,
};
use rtl_model::{ConfigError, Counters};
use serde::Serialize;

use crate::reference::cube_map_address::{face_st, texel_centre_directions};
use crate::scene::limits::GlRounding;

/// Largest face side: 6F rows must fit the sampler's 4096, F a power of two.
pub const MAX_FACE_SIDE: u32 = 512;

/// The path's configuration; [`NormalizeCubeConfig::build`] validates it (errors name
/// `normalize_cube.<field>`, or `normalize_cube.address.<field>` for the address unit).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct NormalizeCubeConfig {
    /// Face side F, a power of two in 2 ..= 512.
    pub face_side: u32,
    /// Texel bits b per channel, 1 ..= 16.
    pub texel_bits: u32,
    /// Nearest or bilinear (within a face).
    pub filter: Filter,
    /// The address unit (its `face_log2` is set from `face_side`; its output words
    /// are the sampler's coordinate words).
    pub address: CubeMapAddressConfig,
}

impl Default for NormalizeCubeConfig {
    fn default() -> Self {
        Self::geforce()
    }
}

impl NormalizeCubeConfig {
    /// GeForce defaults: 64 × 64 faces of 8-bit RGB, bilinear; the address unit at its
    /// GeForce3 defaults (s16.8 words of a side-128 coordinate cube: c = (v + 1)·64).
    pub fn geforce() -> Self {
        NormalizeCubeConfig {
            face_side: 64,
            texel_bits: 8,
            filter: Filter::Linear,
            address: CubeMapAddressConfig::geforce3(),
        }
    }

    /// The defaults at face side `face` and `bits`-bit texels.
    pub fn with(face: u32, bits: u32, filter: Filter) -> Self {
        NormalizeCubeConfig {
            face_side: face,
            texel_bits: bits,
            filter,
            ..Self::geforce()
        }
    }

    pub fn build(&self) -> Result<NormalizeCube, ConfigError> {
        NormalizeCube::new(*self)
    }
}

/// The units' counters of a batch of lookups.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct NormalizeCubeCounters {
    pub address: Counters,
    pub sampler: Counters,
}

/// The built path: the address unit and the sampler holding the cube map.
#[derive(Clone, Debug)]
pub struct NormalizeCube {
    cfg: NormalizeCubeConfig,
    address: CubeMapAddress,
    sampler: TextureSampler,
}

/// unorm code of a component n ∈ [−1, 1]: round((n + 1)/2 · (2^b − 1)), half up.
fn pack(n: f64, bits: u32) -> u32 {
    let big_b = ((1u64 << bits) - 1) as f64;
    ((n.clamp(-1.0, 1.0) + 1.0) * 0.5 * big_b + 0.5).floor() as u32
}

/// The F × 6F texture, RGB, texel (i, j) of face f at index ((f·F + j)·F + i)·3 + c:
/// the packed normalised direction of the texel centre.
pub fn normalization_texels(face: u32, bits: u32) -> Vec<u32> {
    texel_centre_directions(face)
        .flat_map(|n| n.map(|c| pack(c, bits)))
        .collect()
}

/// The f64 comparison path: exact normalisation of `d`, then unorm rounding. A zero
/// or non-finite `d` gives +x (as the units do for a zero vector).
pub fn normalize_f64(d: [f64; 3], bits: u32) -> [u32; 3] {
    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let n = if l > 0.0 && l.is_finite() {
        d.map(|c| c / l)
    } else {
        [1.0, 0.0, 0.0]
    };
    n.map(|c| pack(c, bits))
}

/// Decode unorm codes to components in [−1, 1]: 2·code/(2^b − 1) − 1.
pub fn decode(codes: [u32; 3], bits: u32) -> [f64; 3] {
    let big_b = ((1u64 << bits) - 1) as f64;
    codes.map(|c| 2.0 * c as f64 / big_b - 1.0)
}

/// Angle (radians) between two vectors; 0 if either is zero.
pub fn angle_between(a: [f64; 3], b: [f64; 3]) -> f64 {
    let dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let cross = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    let c = (cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]).sqrt();
    if c == 0.0 && dot == 0.0 {
        0.0
    } else {
        c.atan2(dot)
    }
}

/// The address unit's bound on |Δs|, |Δt| in texels: F/2·E + 2^−(Fo+1), E the bound
/// on |m·y − 1| of its reciprocal (table, and one Newton step if configured); the
/// derivation is in `tests/cube_map_address.rs` and docs/units.md.
pub fn address_bound_texels(c: &CubeMapAddressConfig) -> f64 {
    let p2 = |e: i32| (e as f64).exp2();
    let dmax = if c.rcp_addr_bits >= c.rcp_bits {
        p2(-(c.rcp_bits as i32))
    } else {
        p2(-(c.rcp_bits as i32) - 1)
    };
    let e0 = p2(-(c.rcp_addr_bits as i32) - 1) + 2.0 * dmax;
    let e = if c.newton {
        let n = p2(-(c.newton_frac_bits as i32));
        e0 * e0 + (1.0 + e0) * 1.5 * n + n
    } else {
        e0
    };
    p2(c.face_log2 as i32) / 2.0 * e + p2(-(c.coord_frac_bits as i32) - 1)
}

/// The derived bounds of one configuration (module notes).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct NormalizeBounds {
    /// Angle (radians) inside a face (bilinear: away from the ½-texel edge band).
    pub angle_interior: f64,
    /// Angle (radians) in the edge band (nearest: everywhere).
    pub angle_edge: f64,
    /// Per-component error in codes inside a face.
    pub component_interior: f64,
    /// Per-component error in codes in the edge band.
    pub component_edge: f64,
    /// Width of the edge band in texels (½ + δ; 0 for nearest).
    pub edge_band_texels: f64,
}

impl NormalizeCube {
    pub fn new(cfg: NormalizeCubeConfig) -> Result<Self, ConfigError> {
        Self::with_rounding(cfg, &GlRounding::default())
    }

    /// The cube with its sampler's filter and weight rounding set by `rounding` (the
    /// shading path's `[rounding]`: GeForce-style by default, Mesa's llvmpipe with
    /// [`GlRounding::mesa_llvmpipe`]).
    pub fn with_rounding(
        cfg: NormalizeCubeConfig,
        rounding: &GlRounding,
    ) -> Result<Self, ConfigError> {
        rtl_model::error::check_range(
            "normalize_cube.face_side",
            cfg.face_side.into(),
            2,
            MAX_FACE_SIDE.into(),
        )?;
        if !cfg.face_side.is_power_of_two() {
            return Err(ConfigError::invalid(
                "normalize_cube.face_side",
                &format!("must be a power of two, not {}", cfg.face_side),
            ));
        }
        rtl_model::error::check_range("normalize_cube.texel_bits", cfg.texel_bits.into(), 1, 16)?;
        let address = CubeMapAddressConfig {
            face_log2: cfg.face_side.trailing_zeros(),
            ..cfg.address
        }
        .build()
        .map_err(|e| e.within("normalize_cube.address"))?;
        let ac = address.config();
        let sampler = TextureSampler::new(
            rounding.sampler(TextureSamplerConfig {
                channels: 3,
                texel_bits: cfg.texel_bits,
                filter: cfg.filter,
                coord_int_bits: ac.coord_int_bits,
                coord_frac_bits: ac.coord_frac_bits,
                ..TextureSamplerConfig::geforce_2d(cfg.face_side, 6 * cfg.face_side)
            }),
            &normalization_texels(cfg.face_side, cfg.texel_bits),
        )
        .map_err(|e| e.within("normalize_cube"))?;
        Ok(NormalizeCube {
            cfg: NormalizeCubeConfig { address: ac, ..cfg },
            address,
            sampler,
        })
    }

    pub fn config(&self) -> NormalizeCubeConfig {
        self.cfg
    }
    pub fn address_unit(&self) -> &CubeMapAddress {
        &self.address
    }
    pub fn sampler(&self) -> &TextureSampler {
        &self.sampler
    }

    /// Texel RAM bits: 6F² · 3 · b.
    pub fn texture_bits(&self) -> u64 {
        self.sampler.ram_bits()
    }

    /// Host helper: the address unit's input words of an f64 vector v (components
    /// of the interpolated vector): c = (v + 1)/2 · s, rounded, saturating (counted).
    /// NaN/±∞ → error naming `normalize_cube.vector`.
    pub fn vector_words(
        &self,
        v: [f64; 3],
        ctr: &mut Counters,
    ) -> Result<CubeMapAddressIn, ConfigError> {
        let s = (self.cfg.address.side_log2 as f64).exp2();
        let mut c = [0.0; 3];
        for (c, &x) in c.iter_mut().zip(&v) {
            *c = (rtl_model::error::check_finite("normalize_cube.vector", x)? + 1.0) * 0.5 * s;
        }
        self.address.quantise_in(c, ctr)
    }

    /// The exact direction the words encode: d = c − s/2 (texels; exact in f64).
    pub fn word_direction(&self, input: &CubeMapAddressIn) -> [f64; 3] {
        let a = self.cfg.address;
        let w = a.in_int_bits + a.in_frac_bits;
        let k = (-(a.in_frac_bits as f64)).exp2();
        let half = (a.side_log2 as f64).exp2() * 0.5;
        input
            .coord
            .map(|x| rtl_model::wire::sign_extend(x as i64, w) as f64 * k - half)
    }

    /// One lookup through the units (their kernels): address, then sample.
    pub fn normalize(&self, input: &CubeMapAddressIn, ctr: &mut NormalizeCubeCounters) -> [u32; 3] {
        let a: CubeMapAddressOut = self.address.address(input, &mut ctr.address);
        let t = self.sampler.sample(&a.sampler_in(), &mut ctr.sampler);
        [t[0], t[1], t[2]]
    }

    /// A batch through the span drivers (cycles and stalls counted per unit).
    pub fn normalize_span(
        &self,
        inputs: &[CubeMapAddressIn],
    ) -> (Vec<[u32; 3]>, NormalizeCubeCounters) {
        let mut ctr = NormalizeCubeCounters::default();
        let addr = run_span(&self.address, &mut (), inputs, &mut ctr.address);
        let words: Vec<TextureSamplerIn> = addr.iter().map(|a| a.sampler_in()).collect();
        let texels = run_span(&self.sampler, &mut (), &words, &mut ctr.sampler);
        (texels.iter().map(|t| [t[0], t[1], t[2]]).collect(), ctr)
    }

    /// The derived bounds (module notes).
    pub fn bounds(&self) -> NormalizeBounds {
        let h = 2.0 / self.cfg.face_side as f64;
        let big_b = ((1u64 << self.cfg.texel_bits) - 1) as f64;
        let delta = address_bound_texels(&self.cfg.address);
        let q = 3f64.sqrt() / big_b;
        let sqrt2 = 2f64.sqrt();
        match self.cfg.filter {
            Filter::Nearest => {
                let t = sqrt2 * (0.5 + delta) * h;
                let angle = t + q.min(1.0).asin();
                let comp = 0.5 + big_b / 2.0 * t;
                NormalizeBounds {
                    angle_interior: angle,
                    angle_edge: angle,
                    component_interior: comp,
                    component_edge: comp,
                    edge_band_texels: 0.0,
                }
            }
            Filter::Linear => {
                let field = |d: f64| h * h / 4.0 + sqrt2 * d * h;
                let angle = |d: f64| (field(d) + 2.0 * q).min(1.0).asin();
                let comp = |d: f64| 1.0 + big_b / 2.0 * field(d);
                NormalizeBounds {
                    angle_interior: angle(delta),
                    angle_edge: angle(0.5 + delta),
                    component_interior: comp(delta),
                    component_edge: comp(0.5 + delta),
                    edge_band_texels: 0.5 + delta,
                }
            }
        }
    }

    /// Whether the exact direction `d` falls in the edge band of its face (within the
    /// band's width of a face edge), where the bilinear bound is the edge one.
    pub fn in_edge_band(&self, d: [f64; 3]) -> bool {
        let f = self.cfg.face_side as f64;
        let band = self.bounds().edge_band_texels;
        let (_, st) = face_st(d, f);
        st.iter().any(|&x| x < band || x > f - band)
    }
}

/// One row of the error table (`reproduce shading-normalize-cube`).
#[derive(Clone, Debug, Serialize)]
pub struct ErrorRow {
    pub face_side: u32,
    pub texel_bits: u32,
    pub filter: &'static str,
    pub samples: usize,
    pub texture_bits: u64,
    pub max_angle_deg: f64,
    pub mean_angle_deg: f64,
    pub max_angle_interior_deg: f64,
    pub bound_angle_interior_deg: f64,
    pub bound_angle_edge_deg: f64,
    pub max_component_codes: f64,
    pub bound_component_edge_codes: f64,
    pub f64_path_max_angle_deg: f64,
    pub max_length_error: f64,
}

/// A random test vector: a uniform direction and a length log-uniform in
/// [2^−12, 1] (interpolated unit vectors shorten; very short ones included).
pub fn random_vector(rng: &mut ChaCha8Rng) -> [f64; 3] {
    loop {
        let d: [f64; 3] = [(); 3].map(|_| rng.random_range(-1.0..1.0));
        let l2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        if l2 > 1e-6 && l2 <= 1.0 {
            let len = (-12.0 * rng.random_range(0.0..1.0f64)).exp2();
            let l = l2.sqrt();
            return d.map(|c| c / l * len);
        }
    }
}

/// Measure one configuration over `samples` seeded random vectors: the looked-up
/// vector against the exact normalisation of the words' direction.
pub fn measure(
    cfg: NormalizeCubeConfig,
    samples: usize,
    seed: u64,
) -> Result<ErrorRow, ConfigError> {
    let cube = cfg.build()?;
    let bits = cfg.texel_bits;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut ctr = Counters::default();
    let mut inputs = Vec::with_capacity(samples);
    while inputs.len() < samples {
        let w = cube.vector_words(random_vector(&mut rng), &mut ctr)?;
        if cube.word_direction(&w) != [0.0; 3] {
            inputs.push(w);
        }
    }
    let (outs, _) = cube.normalize_span(&inputs);
    let b = cube.bounds();
    let (mut max_a, mut sum_a, mut max_in, mut max_c, mut max_f, mut max_len) =
        (0f64, 0f64, 0f64, 0f64, 0f64, 0f64);
    let big_b = ((1u64 << bits) - 1) as f64;
    for (w, o) in inputs.iter().zip(&outs) {
        let d = cube.word_direction(w);
        let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let n = d.map(|c| c / l);
        let v = decode(*o, bits);
        let a = angle_between(v, n);
        max_a = max_a.max(a);
        sum_a += a;
        if !cube.in_edge_band(d) {
            max_in = max_in.max(a);
        }
        for k in 0..3 {
            max_c = max_c.max((o[k] as f64 - (n[k] + 1.0) * 0.5 * big_b).abs());
        }
        max_f = max_f.max(angle_between(decode(normalize_f64(d, bits), bits), n));
        max_len = max_len.max(((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt() - 1.0).abs());
    }
    let deg = f64::to_degrees;
    Ok(ErrorRow {
        face_side: cfg.face_side,
        texel_bits: bits,
        filter: match cfg.filter {
            Filter::Nearest => "nearest",
            Filter::Linear => "bilinear",
        },
        samples,
        texture_bits: cube.texture_bits(),
        max_angle_deg: deg(max_a),
        mean_angle_deg: deg(sum_a / samples.max(1) as f64),
        max_angle_interior_deg: deg(max_in),
        bound_angle_interior_deg: deg(b.angle_interior),
        bound_angle_edge_deg: deg(b.angle_edge),
        max_component_codes: max_c,
        bound_component_edge_codes: b.component_edge,
        f64_path_max_angle_deg: deg(max_f),
        max_length_error: max_len,
    })
}

/// Face sides of the error table.
pub const TABLE_FACE_SIDES: [u32; 5] = [16, 32, 64, 128, 256];

/// `reproduce shading-normalize-cube`: the error table over F = 16 … 256, nearest and
/// bilinear, 8- and 16-bit texels, 20 000 seeded vectors each, as
/// `normalize_cube_error.csv`.
pub fn reproduce(out: &std::path::Path) -> Result<Vec<ErrorRow>, String> {
    let mut rows = Vec::new();
    for bits in [8, 16] {
        for filter in [Filter::Nearest, Filter::Linear] {
            for f in TABLE_FACE_SIDES {
                let row = measure(NormalizeCubeConfig::with(f, bits, filter), 20_000, 13)
                    .map_err(|e| e.to_string())?;
                println!(
                    "F {:>3} b {:>2} {:<8}: max {:.3}° (interior {:.3}°, bounds {:.3}° / {:.3}°), mean {:.3}°, component {:.2} codes (bound {:.2}), f64 path {:.3}°",
                    row.face_side,
                    row.texel_bits,
                    row.filter,
                    row.max_angle_deg,
                    row.max_angle_interior_deg,
                    row.bound_angle_interior_deg,
                    row.bound_angle_edge_deg,
                    row.mean_angle_deg,
                    row.max_component_codes,
                    row.bound_component_edge_codes,
                    row.f64_path_max_angle_deg
                );
                rows.push(row);
            }
        }
    }
    crate::report::csv_out::write_csv(&out.join("normalize_cube_error.csv"), &rows)?;
    Ok(rows)
}
