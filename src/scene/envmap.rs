//! Environment maps (host side, f64): the input of the multi-scale environment map
//! (Okumura's thesis) and of its Phong ground truth.
//!
//! # Conventions (shared with `reference::envmap_prefilter`)
//!
//! Right-handed, y up. An environment map is **equirectangular**, `width` W texels in
//! longitude φ by `height` H texels in polar angle θ, stored row-major (`texels[j·W + i]`):
//!
//! - θ runs from 0 (+y, the top edge of row 0) to π (−y, the bottom edge of row H−1);
//!   texel (i, j) has its centre at θ = π(j + ½)/H.
//! - φ runs from 0 along **−z** increasing towards **+x** (so φ = π/2 is +x, φ = π is +z,
//!   φ = 3π/2 is −x); texel (i, j) has its centre at φ = 2π(i + ½)/W. Column 0's left edge
//!   is φ = 0. An HDR file's pixel (column i, row j) is texel (i, j): the file's left edge
//!   looks along −z and its horizontal centre along +z.
//! - direction d(θ, φ) = (sin θ sin φ, cos θ, −sin θ cos φ).
//! - u = φ/2π ∈ [0, 1), v = θ/π ∈ [0, 1]; texel centres are at u = (i + ½)/W, v = (j + ½)/H.
//! - texel solid angle ΔΩ_j = (2π/W)·(cos θ_top − cos θ_bottom), θ_top = πj/H,
//!   θ_bottom = π(j+1)/H; the sum over all texels telescopes to 4π exactly.
//!
//! Texel values are **linear radiance** (any positive scale), finite, in
//! [0, [`MAX_RADIANCE`]]. The 256-level input the thesis assumes is
//! [`EnvMap::to_levels`]: round(255 · clamp(L · exposure, 0, 1)).
//!
//! # Exposure choice
//!
//! [`EnvMap::auto_exposure`] maps the **99th percentile, by solid angle, of the texels'
//! max(R, G, B)** to level 255: exposure = 1 / P99. The thesis' inputs are 8-bit images
//! as shot or drawn (its pattern is at full value everywhere); this choice clips only the
//! brightest 1 % of the sphere (a sun, lamps), keeps the rest of the range, and gives the
//! built-in pattern exposure 1 exactly (every texel of it has max channel 1). A
//! mean-luminance rule (mean → 0.18·255) was rejected: a sun at 10⁵ × the mean drags the
//! mean up and darkens everything else to a few levels.
//!
//! # Built-in maps
//!
//! [`EnvMap::pattern`] is the thesis' Fig. 13(a) synthetic colour chart (the default).
//! [`EnvMap::venice_sunset`] and [`EnvMap::st_fagans_interior`] are Poly Haven CC0 maps,
//! 512 × 256, embedded from `src/scene/data/envmaps/` (see the README there).

use std::io::{BufReader, Read};
use std::path::Path;

use image::codecs::hdr::HdrDecoder;
use image::{DynamicImage, ImageDecoder, ImageFormat, Rgb};
use rtl_model::error::ConfigError;

use crate::scene::math::{v3, Vec3};

const PI: f64 = std::f64::consts::PI;
const TAU: f64 = std::f64::consts::TAU;

/// Largest accepted texel value (sums of 10⁶ texels × 4π stay far from overflow).
pub const MAX_RADIANCE: f64 = 1e100;
/// Largest accepted width; the largest height is half of it.
pub const MAX_WIDTH: usize = 16384;
pub const MAX_HEIGHT: usize = 8192;
/// Largest Radiance file read: a [`MAX_WIDTH`] × [`MAX_HEIGHT`] map uncompressed (4
/// bytes per RGBE texel) plus 1 MiB of header.
pub const MAX_HDR_BYTES: u64 = (MAX_WIDTH * MAX_HEIGHT * 4) as u64 + (1 << 20);
/// Size of the built-in maps (the thesis' 512 × 256).
pub const DEFAULT_WIDTH: usize = 512;
pub const DEFAULT_HEIGHT: usize = 256;

const VENICE_SUNSET_HDR: &[u8] = include_bytes!("data/envmaps/venice_sunset_512.hdr");
const ST_FAGANS_INTERIOR_HDR: &[u8] = include_bytes!("data/envmaps/st_fagans_interior_512.hdr");

/// Names accepted by [`EnvMap::builtin`]; the first is the default.
pub const BUILTIN_NAMES: [&str; 3] = ["pattern", "venice_sunset", "st_fagans_interior"];

/// The unit direction for polar angle θ (from +y) and longitude φ (from −z towards +x).
pub fn dir_from_angles(theta: f64, phi: f64) -> Vec3 {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    v3(st * sp, ct, -st * cp)
}

/// The unit direction of map coordinates (u, v) ∈ [0, 1) × [0, 1].
pub fn uv_to_dir(u: f64, v: f64) -> Vec3 {
    dir_from_angles(PI * v, TAU * u)
}

/// Map coordinates (u, v) of a direction (need not be unit): u = φ/2π ∈ [0, 1),
/// v = θ/π ∈ [0, 1]. The zero vector and non-finite vectors give (0, 0) (the +y pole);
/// exactly at the poles (x = z = 0) u is 0.
pub fn dir_to_uv(d: Vec3) -> (f64, f64) {
    let len = d.length();
    if !(len.is_finite() && len > 0.0) {
        return (0.0, 0.0);
    }
    let y = (d.y / len).clamp(-1.0, 1.0);
    let theta = y.acos();
    if d.x == 0.0 && d.z == 0.0 {
        return (0.0, if d.y > 0.0 { 0.0 } else { 1.0 });
    }
    let mut phi = d.x.atan2(-d.z);
    if phi < 0.0 {
        phi += TAU;
    }
    let mut u = phi / TAU;
    if u >= 1.0 {
        u -= 1.0;
    }
    (u.clamp(0.0, 1.0), (theta / PI).clamp(0.0, 1.0))
}

/// The unit direction of texel (i, j)'s centre in a `width` × `height` map.
pub fn texel_dir(i: usize, j: usize, width: usize, height: usize) -> Vec3 {
    let w = width.max(1) as f64;
    let h = height.max(1) as f64;
    dir_from_angles(PI * (j as f64 + 0.5) / h, TAU * (i as f64 + 0.5) / w)
}

/// The solid angle of any texel of row j in a `width` × `height` map:
/// (2π/W)·(cos(πj/H) − cos(π(j+1)/H)).
pub fn texel_solid_angle(j: usize, width: usize, height: usize) -> f64 {
    let w = width.max(1) as f64;
    let h = height.max(1) as f64;
    let top = (PI * j as f64 / h).cos();
    let bottom = (PI * (j as f64 + 1.0) / h).cos();
    (TAU / w) * (top - bottom)
}

/// HSV → RGB: h in turns (wraps), s, v in [0, 1].
pub fn hsv_to_rgb(h: f64, s: f64, v: f64) -> [f64; 3] {
    let h6 = h.rem_euclid(1.0) * 6.0;
    let sector = (h6.floor() as i64).rem_euclid(6);
    let f = h6 - h6.floor();
    let p = v * (1.0 - s);
    let q = v * (1.0 - s * f);
    let t = v * (1.0 - s * (1.0 - f));
    match sector {
        0 => [v, t, p],
        1 => [q, v, p],
        2 => [p, v, t],
        3 => [p, q, v],
        4 => [t, p, v],
        _ => [v, p, q],
    }
}

/// An equirectangular environment map of linear radiance (see the module conventions).
/// The fields are private: a value always has `texels.len() == width · height` and every
/// texel finite and in [0, MAX_RADIANCE].
#[derive(Clone, Debug, PartialEq)]
pub struct EnvMap {
    width: usize,
    height: usize,
    texels: Vec<[f64; 3]>,
}

impl EnvMap {
    /// A map from row-major texels. Errors: width/height out of 1..=MAX
    /// ("envmap.width"/"envmap.height"), wrong texel count ("envmap.texels"), a NaN/∞
    /// (`"envmap.texels[k]"`, not finite) or a value outside `[0, MAX_RADIANCE]` (out of range).
    pub fn new(width: usize, height: usize, texels: Vec<[f64; 3]>) -> Result<Self, ConfigError> {
        check_size(width, height)?;
        if texels.len() != width * height {
            return Err(ConfigError::invalid(
                "envmap.texels",
                &format!(
                    "{} texels given for a {width} × {height} map (need {})",
                    texels.len(),
                    width * height
                ),
            ));
        }
        for (k, t) in texels.iter().enumerate() {
            for &c in t {
                if !c.is_finite() {
                    return Err(ConfigError::not_finite(&format!("envmap.texels[{k}]"), c));
                }
                if !(0.0..=MAX_RADIANCE).contains(&c) {
                    return Err(ConfigError::out_of_range(
                        &format!("envmap.texels[{k}]"),
                        c,
                        0.0,
                        MAX_RADIANCE,
                    ));
                }
            }
        }
        Ok(EnvMap {
            width,
            height,
            texels,
        })
    }

    /// A constant map (every texel `value`).
    pub fn constant(width: usize, height: usize, value: [f64; 3]) -> Result<Self, ConfigError> {
        check_size(width, height)?;
        EnvMap::new(width, height, vec![value; width * height])
    }

    /// A map whose texel (i, j) is `f(direction of its centre)`.
    pub fn from_fn(
        width: usize,
        height: usize,
        f: impl Fn(Vec3) -> [f64; 3],
    ) -> Result<Self, ConfigError> {
        check_size(width, height)?;
        let mut texels = Vec::with_capacity(width * height);
        for j in 0..height {
            for i in 0..width {
                texels.push(f(texel_dir(i, j, width, height)));
            }
        }
        EnvMap::new(width, height, texels)
    }

    /// The thesis' Fig. 13(a) synthetic colour pattern ("hue varies horizontally,
    /// saturation vertically"): texel (i, j) = HSV(h = (i + ½)/W turns, s = 1 − j/(H−1),
    /// v = 1) → RGB, i.e. a hue × saturation chart: the hue wheel red → yellow → green →
    /// cyan → blue → magenta left to right, fully saturated in row 0 (top, +y) fading
    /// linearly to white in row H−1 (bottom, −y); H = 1 gives one saturated row. Values
    /// are in [0, 1] and meant for exposure 1 (then the levels are the chart's 8-bit
    /// values). Sizes are clamped into 1..=MAX.
    pub fn pattern(width: usize, height: usize) -> EnvMap {
        let w = width.clamp(1, MAX_WIDTH);
        let h = height.clamp(1, MAX_HEIGHT);
        let mut texels = Vec::with_capacity(w * h);
        for j in 0..h {
            let s = if h > 1 {
                1.0 - j as f64 / (h - 1) as f64
            } else {
                1.0
            };
            for i in 0..w {
                let hue = (i as f64 + 0.5) / w as f64;
                texels.push(hsv_to_rgb(hue, s, 1.0));
            }
        }
        EnvMap {
            width: w,
            height: h,
            texels,
        }
    }

    /// Venice sunset (Poly Haven, CC0), 512 × 256, embedded: outdoor with a visible sun.
    pub fn venice_sunset() -> Result<EnvMap, ConfigError> {
        EnvMap::from_hdr_bytes(VENICE_SUNSET_HDR, "builtin venice_sunset")
    }

    /// St Fagans interior (Poly Haven, CC0), 512 × 256, embedded: an interior like the
    /// thesis' photo (Fig. 13(b)).
    pub fn st_fagans_interior() -> Result<EnvMap, ConfigError> {
        EnvMap::from_hdr_bytes(ST_FAGANS_INTERIOR_HDR, "builtin st_fagans_interior")
    }

    /// A built-in map by name (see [`BUILTIN_NAMES`]); the pattern is 512 × 256.
    pub fn builtin(name: &str) -> Result<EnvMap, ConfigError> {
        match name {
            "pattern" => Ok(EnvMap::pattern(DEFAULT_WIDTH, DEFAULT_HEIGHT)),
            "venice_sunset" => EnvMap::venice_sunset(),
            "st_fagans_interior" => EnvMap::st_fagans_interior(),
            _ => Err(ConfigError::invalid(
                "envmap.name",
                &format!(
                    "unknown built-in environment `{name}` (known: {})",
                    BUILTIN_NAMES.join(", ")
                ),
            )),
        }
    }

    /// Load an equirectangular Radiance `.hdr` (RGBE) file. Every error has field
    /// "envmap.path" and names the path: missing/unreadable file, not a regular file (a
    /// device or a pipe could be endless), larger than [`MAX_HDR_BYTES`], not an HDR, a
    /// bad size, or a texel that is NaN/∞/negative (refused, not clamped). At most
    /// [`MAX_HDR_BYTES`] are read whatever the file does while it is read.
    pub fn load_hdr(path: impl AsRef<Path>) -> Result<EnvMap, ConfigError> {
        let path = path.as_ref();
        let shown = path.display().to_string();
        let file = std::fs::File::open(path).map_err(|e| path_error(&shown, "cannot open", &e))?;
        let meta = file
            .metadata()
            .map_err(|e| path_error(&shown, "cannot read its metadata", &e))?;
        if !meta.is_file() {
            return Err(ConfigError::invalid(
                "envmap.path",
                &format!("`{shown}`: not a regular file"),
            ));
        }
        if meta.len() > MAX_HDR_BYTES {
            return Err(ConfigError::invalid(
                "envmap.path",
                &format!(
                    "`{shown}`: {} bytes, more than the {MAX_HDR_BYTES} a {MAX_WIDTH} × {MAX_HEIGHT} map needs",
                    meta.len()
                ),
            ));
        }
        let capped = BufReader::new(file.take(MAX_HDR_BYTES));
        // A file that ends early fails inside the decoder as an I/O "failed to fill
        // whole buffer"; say what it means.
        let not_hdr = |e: image::ImageError| match &e {
            image::ImageError::IoError(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
                path_error(
                    &shown,
                    "truncated HDR file",
                    &"the file ends before all the pixels its header promises",
                )
            }
            _ => path_error(&shown, "cannot decode as Radiance HDR", &e),
        };
        let decoder = HdrDecoder::new(capped).map_err(not_hdr)?;
        // The header's size, before the decoder allocates the image for it.
        let (w, h) = decoder.dimensions();
        check_size(w as usize, h as usize).map_err(|e| path_error(&shown, "bad size", &e))?;
        let img = DynamicImage::from_decoder(decoder).map_err(not_hdr)?;
        EnvMap::from_rgb32f(img.into_rgb32f(), &shown)
    }

    /// Decode an in-memory Radiance `.hdr`; `name` is what errors call it.
    pub fn from_hdr_bytes(bytes: &[u8], name: &str) -> Result<EnvMap, ConfigError> {
        let img = image::load_from_memory_with_format(bytes, ImageFormat::Hdr)
            .map_err(|e| path_error(name, "cannot decode as Radiance HDR", &e))?;
        EnvMap::from_rgb32f(img.into_rgb32f(), name)
    }

    fn from_rgb32f(img: image::Rgb32FImage, name: &str) -> Result<EnvMap, ConfigError> {
        let (w, h) = (img.width() as usize, img.height() as usize);
        let texels = img
            .pixels()
            .map(|p| [p.0[0] as f64, p.0[1] as f64, p.0[2] as f64])
            .collect();
        EnvMap::new(w, h, texels).map_err(|e| {
            ConfigError::invalid("envmap.path", &format!("`{name}`: bad content: {e}"))
        })
    }

    /// Write the map as a Radiance `.hdr` (RGBE, RLE) through image's encoder; values are
    /// rounded to f32 (and RGBE's ~1 % mantissa). Errors have field "envmap.path".
    pub fn write_hdr(&self, path: impl AsRef<Path>) -> Result<(), ConfigError> {
        let path = path.as_ref();
        let shown = path.display().to_string();
        let pixels: Vec<Rgb<f32>> = self
            .texels
            .iter()
            .map(|t| Rgb(t.map(|c| c.min(f32::MAX as f64) as f32)))
            .collect();
        // Into an existing directory only (as `File::create`), atomically
        // (`report::atomic`): the old file or the whole new one.
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            if !dir.is_dir() {
                return Err(path_error(&shown, "cannot create", &"no such directory"));
            }
        }
        crate::report::atomic::write_with(path, |w| {
            image::codecs::hdr::HdrEncoder::new(w)
                .encode(&pixels, self.width, self.height)
                .map_err(std::io::Error::other)
        })
        .map_err(|e| path_error(&shown, "cannot write HDR", &e))
    }

    pub fn width(&self) -> usize {
        self.width
    }
    pub fn height(&self) -> usize {
        self.height
    }
    /// Row-major texels, `texels()[j · width + i]`.
    pub fn texels(&self) -> &[[f64; 3]] {
        &self.texels
    }
    pub fn into_texels(self) -> Vec<[f64; 3]> {
        self.texels
    }
    /// Texel (i, j); i wraps modulo W, j is clamped to the last row.
    pub fn texel(&self, i: usize, j: usize) -> [f64; 3] {
        let i = i % self.width;
        let j = j.min(self.height - 1);
        self.texels[j * self.width + i]
    }
    /// The direction of texel (i, j)'s centre.
    pub fn texel_dir(&self, i: usize, j: usize) -> Vec3 {
        texel_dir(i, j, self.width, self.height)
    }
    /// The solid angle of a texel of row j.
    pub fn texel_solid_angle(&self, j: usize) -> f64 {
        texel_solid_angle(j, self.width, self.height)
    }

    /// Bilinear lookup in direction `d` (need not be unit): between texel centres,
    /// wrapping in φ, clamped in θ at the poles (above the first / below the last row's
    /// centres the row's values are used). Zero/non-finite `d` looks up (0, 0).
    pub fn lookup(&self, d: Vec3) -> [f64; 3] {
        let (u, v) = dir_to_uv(d);
        self.lookup_uv(u, v)
    }

    /// Bilinear lookup at map coordinates (u, v); u wraps, v clamps. Non-finite → 0.
    pub fn lookup_uv(&self, u: f64, v: f64) -> [f64; 3] {
        let u = if u.is_finite() { u } else { 0.0 };
        let v = if v.is_finite() { v } else { 0.0 };
        let (w, h) = (self.width as f64, self.height as f64);
        let x = u.rem_euclid(1.0) * w - 0.5;
        let y = (v * h - 0.5).clamp(0.0, h - 1.0);
        let x0 = x.floor();
        let fx = x - x0;
        let i0 = (x0 as i64).rem_euclid(self.width as i64) as usize;
        let i1 = (i0 + 1) % self.width;
        let y0 = y.floor();
        let fy = y - y0;
        let j0 = (y0 as usize).min(self.height - 1);
        let j1 = (j0 + 1).min(self.height - 1);
        let t00 = self.texel(i0, j0);
        let t10 = self.texel(i1, j0);
        let t01 = self.texel(i0, j1);
        let t11 = self.texel(i1, j1);
        let mut out = [0.0; 3];
        for c in 0..3 {
            let top = t00[c] + (t10[c] - t00[c]) * fx;
            let bottom = t01[c] + (t11[c] - t01[c]) * fx;
            out[c] = top + (bottom - top) * fy;
        }
        out
    }

    /// Box-filter by `factor` in both axes, each output texel the **solid-angle-weighted**
    /// mean of its factor × factor block (so ∫ L dΩ is preserved exactly, up to
    /// rounding). `factor` must be ≥ 1 and divide both width and height
    /// ("envmap.downsample_factor").
    pub fn downsample(&self, factor: usize) -> Result<EnvMap, ConfigError> {
        let field = "envmap.downsample_factor";
        if factor == 0
            || self.width / factor * factor != self.width
            || self.height / factor * factor != self.height
        {
            return Err(ConfigError::invalid(
                field,
                &format!(
                    "{factor} must be ≥ 1 and divide both {} and {}",
                    self.width, self.height
                ),
            ));
        }
        if factor == 1 {
            return Ok(self.clone());
        }
        let (w2, h2) = (self.width / factor, self.height / factor);
        let mut texels = Vec::with_capacity(w2 * h2);
        for j2 in 0..h2 {
            for i2 in 0..w2 {
                let mut sum = [0.0; 3];
                let mut wsum = 0.0;
                for j in j2 * factor..(j2 + 1) * factor {
                    let wt = self.texel_solid_angle(j);
                    for i in i2 * factor..(i2 + 1) * factor {
                        let t = self.texels[j * self.width + i];
                        for c in 0..3 {
                            sum[c] += wt * t[c];
                        }
                        wsum += wt;
                    }
                }
                texels.push(sum.map(|s| if wsum > 0.0 { s / wsum } else { 0.0 }));
            }
        }
        EnvMap::new(w2, h2, texels)
    }

    /// ∫ L dΩ / 4π per channel (the solid-angle-weighted mean).
    pub fn mean(&self) -> [f64; 3] {
        let mut sum = [0.0; 3];
        for j in 0..self.height {
            let wt = self.texel_solid_angle(j);
            for t in &self.texels[j * self.width..(j + 1) * self.width] {
                for c in 0..3 {
                    sum[c] += wt * t[c];
                }
            }
        }
        sum.map(|s| s / (4.0 * PI))
    }

    /// The exposure that maps the solid-angle-weighted 99th percentile of max(R, G, B)
    /// to level 255 (see the module doc): 1/P99; if P99 is 0, 1/max; an all-black map
    /// gives 1. Always finite and > 0 (capped at 1e300).
    pub fn auto_exposure(&self) -> f64 {
        let mut v: Vec<(f64, f64)> = Vec::with_capacity(self.texels.len());
        for j in 0..self.height {
            let wt = self.texel_solid_angle(j);
            for t in &self.texels[j * self.width..(j + 1) * self.width] {
                v.push((t[0].max(t[1]).max(t[2]), wt));
            }
        }
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        let total: f64 = v.iter().map(|p| p.1).sum();
        let mut acc = 0.0;
        let mut p99 = v.last().map_or(0.0, |p| p.0);
        for &(val, wt) in &v {
            acc += wt;
            if acc >= 0.99 * total {
                p99 = val;
                break;
            }
        }
        let max = v.last().map_or(0.0, |p| p.0);
        let reference = if p99 > 0.0 { p99 } else { max };
        if reference > 0.0 {
            (1.0 / reference).min(1e300)
        } else {
            1.0
        }
    }

    /// 1 / the 99th percentile of the texels' max(R, G, B) (`weighted`: by solid
    /// angle, as [`EnvMap::auto_exposure`]; else every texel counts once), 1 / the
    /// largest if the percentile is 0, 1 for a black map; at most 10³⁰⁰.
    pub fn percentile_exposure(&self, weighted: bool) -> f64 {
        if weighted {
            return self.auto_exposure();
        }
        let mut v: Vec<f64> = self
            .texels
            .iter()
            .map(|t| t[0].max(t[1]).max(t[2]))
            .collect();
        v.sort_by(|a, b| a.total_cmp(b));
        let max = v.last().copied().unwrap_or(0.0);
        // The smallest value with at least 99 % of the texels at or below it.
        let k = ((0.99 * v.len() as f64).ceil() as usize).clamp(1, v.len().max(1)) - 1;
        let p99 = v.get(k).copied().unwrap_or(0.0);
        let reference = if p99 > 0.0 { p99 } else { max };
        if reference > 0.0 {
            (1.0 / reference).min(1e300)
        } else {
            1.0
        }
    }

    /// 1 / the largest channel of the brightest texel (nothing clips); 1 for a black
    /// map; at most 10³⁰⁰.
    pub fn max_exposure(&self) -> f64 {
        let max = self
            .texels
            .iter()
            .map(|t| t[0].max(t[1]).max(t[2]))
            .fold(0.0, f64::max);
        if max > 0.0 {
            (1.0 / max).min(1e300)
        } else {
            1.0
        }
    }

    /// The 256-level input the thesis assumes: round(255 · clamp(L · exposure, 0, 1)) per
    /// channel, row-major. `exposure` must be finite and > 0 ("envmap.exposure").
    pub fn to_levels(&self, exposure: f64) -> Result<Vec<[u8; 3]>, ConfigError> {
        check_exposure(exposure)?;
        Ok(self
            .texels
            .iter()
            .map(|t| t.map(|c| level(c, exposure)))
            .collect())
    }

    /// [`EnvMap::to_levels`] as a map whose texels are the levels as f64 (0.0 ..= 255.0),
    /// for prefilters that work in the thesis' 256-level units.
    pub fn to_level_map(&self, exposure: f64) -> Result<EnvMap, ConfigError> {
        let levels = self.to_levels(exposure)?;
        Ok(EnvMap {
            width: self.width,
            height: self.height,
            texels: levels.iter().map(|t| t.map(f64::from)).collect(),
        })
    }
}

fn level(c: f64, exposure: f64) -> u8 {
    // c ∈ [0, 1e100] and exposure finite > 0: c·exposure is ≥ 0, maybe +∞ (clamped).
    ((c * exposure).clamp(0.0, 1.0) * 255.0).round() as u8
}

fn check_exposure(exposure: f64) -> Result<(), ConfigError> {
    if !exposure.is_finite() {
        return Err(ConfigError::not_finite("envmap.exposure", exposure));
    }
    if exposure <= 0.0 {
        return Err(ConfigError::out_of_range(
            "envmap.exposure",
            exposure,
            f64::MIN_POSITIVE,
            f64::MAX,
        ));
    }
    Ok(())
}

fn check_size(width: usize, height: usize) -> Result<(), ConfigError> {
    rtl_model::error::check_range("envmap.width", width as u64, 1, MAX_WIDTH as u64)?;
    rtl_model::error::check_range("envmap.height", height as u64, 1, MAX_HEIGHT as u64)
}

fn path_error(path: &str, what: &str, e: &dyn std::fmt::Display) -> ConfigError {
    ConfigError::invalid("envmap.path", &format!("`{path}`: {what}: {e}"))
}
