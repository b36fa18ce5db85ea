//! Error metrics between two images, in 8-bit levels.
//!
//! Images are row-major `[r, g, b]` pixels, top row first, with channel values in
//! 8-bit levels (0 ..= 255 for an 8-bit framebuffer; the f64 references may exceed
//! that range and are compared as they are). Statistics run over every channel of
//! every pixel considered, so `n` counts channel values (3 per pixel).
//!
//! No NaN ever comes out: a non-finite input value is an error naming the image, the
//! pixel and the channel (`a[12][1]`); no pixel considered gives all-zero statistics
//! with `n = 0`; huge differences give large or infinite statistics (sums are scaled by
//! the maximum when they could overflow), never NaN. Mismatched lengths, pixels outside
//! the image and a zero width are `ConfigError`s naming the argument.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::error::ConfigError;

/// Error statistics over `n` channel values, in 8-bit levels.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ErrorStats {
    /// Mean of |a − b|.
    pub mean_abs: f64,
    /// sqrt(mean of (a − b)²).
    pub rms: f64,
    /// Largest |a − b|.
    pub max: f64,
    /// Number of channel values compared (3 per pixel).
    pub n: u64,
}

impl ErrorStats {
    /// No values compared.
    pub const EMPTY: ErrorStats = ErrorStats {
        mean_abs: 0.0,
        rms: 0.0,
        max: 0.0,
        n: 0,
    };
}

/// RMS as a percentage of the 8-bit range (255 levels = 100 %), the unit of the paper's
/// "RMS 2.6 %" comparison with the ray marcher.
pub fn rms_percent(stats: &ErrorStats) -> f64 {
    stats.rms / 255.0 * 100.0
}

/// Largest |difference| below which the plain sums cannot overflow (squares ≤ 1e200,
/// times at most 2⁶⁴ values).
const PLAIN_SUM_LIMIT: f64 = 1e100;

fn check_lengths(a: &[[f64; 3]], b: &[[f64; 3]]) -> Result<(), ConfigError> {
    if a.len() != b.len() {
        return Err(ConfigError::invalid(
            "b",
            &format!(
                "has {} pixels but a has {} (the images must be the same size)",
                b.len(),
                a.len()
            ),
        ));
    }
    Ok(())
}

fn finite(name: &str, i: usize, p: &[f64; 3]) -> Result<(), ConfigError> {
    for (c, &v) in p.iter().enumerate() {
        if !v.is_finite() {
            return Err(ConfigError::not_finite(&format!("{name}[{i}][{c}]"), v));
        }
    }
    Ok(())
}

/// Statistics over the pixels with the given indices (in order; repeats count again).
fn stats_over(
    a: &[[f64; 3]],
    b: &[[f64; 3]],
    idx: impl Iterator<Item = usize> + Clone,
) -> Result<ErrorStats, ConfigError> {
    let mut n = 0u64;
    let mut max = 0.0f64;
    let mut sum = 0.0f64;
    let mut sum2 = 0.0f64;
    for i in idx.clone() {
        finite("a", i, &a[i])?;
        finite("b", i, &b[i])?;
        for c in 0..3 {
            let d = (a[i][c] - b[i][c]).abs();
            max = max.max(d);
            sum += d;
            sum2 += d * d;
            n += 1;
        }
    }
    if n == 0 {
        return Ok(ErrorStats::EMPTY);
    }
    let nf = n as f64;
    if max <= PLAIN_SUM_LIMIT {
        return Ok(ErrorStats {
            mean_abs: sum / nf,
            rms: (sum2 / nf).sqrt(),
            max,
            n,
        });
    }
    if max.is_infinite() {
        // A difference overflowed (inputs beyond ±9e307): say so with +∞, not NaN.
        return Ok(ErrorStats {
            mean_abs: f64::INFINITY,
            rms: f64::INFINITY,
            max,
            n,
        });
    }
    // Scaled by the maximum so that no sum overflows.
    let (mut s1, mut s2) = (0.0f64, 0.0f64);
    for i in idx {
        for c in 0..3 {
            let q = (a[i][c] - b[i][c]).abs() / max;
            s1 += q;
            s2 += q * q;
        }
    }
    Ok(ErrorStats {
        mean_abs: max * (s1 / nf),
        rms: max * (s2 / nf).sqrt(),
        max,
        n,
    })
}

/// Statistics over all channels of all pixels.
pub fn error_stats(a: &[[f64; 3]], b: &[[f64; 3]]) -> Result<ErrorStats, ConfigError> {
    check_lengths(a, b)?;
    stats_over(a, b, 0..a.len())
}

/// Statistics over the pixels where `mask` is true (all three channels of each).
pub fn error_stats_masked(
    a: &[[f64; 3]],
    b: &[[f64; 3]],
    mask: &[bool],
) -> Result<ErrorStats, ConfigError> {
    check_lengths(a, b)?;
    if mask.len() != a.len() {
        return Err(ConfigError::invalid(
            "mask",
            &format!(
                "has {} entries but the images have {} pixels",
                mask.len(),
                a.len()
            ),
        ));
    }
    stats_over(
        a,
        b,
        mask.iter().enumerate().filter(|(_, &m)| m).map(|(i, _)| i),
    )
}

fn check_width(len: usize, width: u32) -> Result<u32, ConfigError> {
    if width == 0 {
        return Err(ConfigError::invalid("width", "must be at least 1"));
    }
    if len / width as usize * width as usize != len {
        return Err(ConfigError::invalid(
            "width",
            &format!("{width} does not divide the {len} pixels of the image"),
        ));
    }
    Ok((len / width as usize) as u32)
}

/// Statistics over the listed pixels `(x, y)` only — the paper's Fig. 4 metric is the
/// mean |Δ| over 10 representative pixels (see [`representative_pixels`]). A pixel
/// listed twice counts twice.
pub fn error_stats_at(
    a: &[[f64; 3]],
    b: &[[f64; 3]],
    width: u32,
    pixels: &[(u32, u32)],
) -> Result<ErrorStats, ConfigError> {
    check_lengths(a, b)?;
    let height = check_width(a.len(), width)?;
    for (k, &(x, y)) in pixels.iter().enumerate() {
        if x >= width || y >= height {
            return Err(ConfigError::invalid(
                &format!("pixels[{k}]"),
                &format!("({x}, {y}) is outside the {width}×{height} image"),
            ));
        }
    }
    stats_over(
        a,
        b,
        pixels
            .iter()
            .map(|&(x, y)| y as usize * width as usize + x as usize),
    )
}

/// A pixel is lit when its largest channel reaches at least this many 8-bit levels …
pub const LIT_MIN_LEVEL: f64 = 1.0;
/// … and at least this fraction of the brightest pixel's largest channel.
pub const LIT_FRACTION_OF_PEAK: f64 = 0.02;

/// The lit region of `reference`: one flag per pixel (rule in [`representative_pixels`]).
pub fn lit_mask(reference: &[[f64; 3]]) -> Result<Vec<bool>, ConfigError> {
    let mut peak = 0.0f64;
    for (i, p) in reference.iter().enumerate() {
        finite("reference", i, p)?;
        peak = peak.max(p[0].max(p[1]).max(p[2]));
    }
    let threshold = LIT_MIN_LEVEL.max(LIT_FRACTION_OF_PEAK * peak);
    Ok(reference
        .iter()
        .map(|p| p[0].max(p[1]).max(p[2]) >= threshold)
        .collect())
}

/// Choose `count` pixels spread over the lit region of `reference`, deterministically
/// for a `seed`.
///
/// Rule:
/// 1. A pixel is *lit* when its largest channel is ≥ max([`LIT_MIN_LEVEL`],
///    [`LIT_FRACTION_OF_PEAK`] × the image's largest channel value) — the scattered
///    light is non-negligible there.
/// 2. The L lit pixels, in raster order (row by row from the top), are cut into `count`
///    strata of consecutive lit pixels, stratum k = [⌊k·L/count⌋, ⌊(k+1)·L/count⌋), so
///    each stratum holds an equal share (±1) of the lit area.
/// 3. One pixel is drawn uniformly from each stratum, in stratum order, with
///    `ChaCha8Rng::seed_from_u64(seed)`.
///
/// The result is in raster order and has `min(count, L)` distinct pixels (every lit
/// pixel when L ≤ count). Errors: a length that is not `width · height`, a non-finite
/// value, or no lit pixel at all (a metric over nothing would read as zero error).
pub fn representative_pixels(
    reference: &[[f64; 3]],
    width: u32,
    height: u32,
    count: usize,
    seed: u64,
) -> Result<Vec<(u32, u32)>, ConfigError> {
    if reference.len() as u64 != width as u64 * height as u64 {
        return Err(ConfigError::invalid(
            "reference",
            &format!(
                "has {} pixels but width × height = {width} × {height} = {}",
                reference.len(),
                width as u64 * height as u64
            ),
        ));
    }
    let lit: Vec<usize> = lit_mask(reference)?
        .iter()
        .enumerate()
        .filter(|(_, &l)| l)
        .map(|(i, _)| i)
        .collect();
    if lit.is_empty() {
        return Err(ConfigError::invalid(
            "reference",
            &format!(
                "no pixel reaches the lit threshold (largest channel ≥ {LIT_MIN_LEVEL} levels \
                 and ≥ {LIT_FRACTION_OF_PEAK} × peak)"
            ),
        ));
    }
    let xy = |i: usize| ((i % width as usize) as u32, (i / width as usize) as u32);
    let l = lit.len();
    if l <= count {
        return Ok(lit.into_iter().map(xy).collect());
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    Ok((0..count)
        .map(|k| {
            let cut = |k: usize| (k as u128 * l as u128 / count as u128) as usize;
            let (lo, hi) = (cut(k), cut(k + 1));
            xy(lit[rng.random_range(lo..hi)])
        })
        .collect())
}
