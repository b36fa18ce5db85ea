//! The Phong ground truth of a render (Okumura's thesis, eqs. 1–3) at the rendered pixels, and
//! the errors against the intended-λ truth. See [`super::render`]'s module notes
//! ("Ground truth and errors") and [`super::roughness`] (the intended λ, the seam band).

use rtl_model::error::ConfigError;

use super::image::{ErrorStats, Image};
use super::roughness::{IntendedErrors, LambdaErrors, SEAM_JUMP, SEAM_RADIUS};
use crate::reference::envmap_prefilter::{g, THESIS_LEVELS};
use crate::reference::phong_truth::{PhongTruth, Visibility};
use crate::scene::envmap::EnvMap;
use crate::scene::math::Vec3;

/// The two ground-truth images.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Truth {
    /// Eqs. (1)–(2): with the cos φ test (the thesis' Phong model).
    pub cos_phi: Image,
    /// Eq. (3): without it (what the map stores).
    pub simplified: Image,
    /// The voxel side s whose g(|t|) gave Λ (the truth depends on it).
    pub side: u32,
    /// With [`super::render::RenderOptions::intended_truth`]: eq. (3) (no cos φ test) with the
    /// INTENDED λ, λ(u, v) in f64 at the pixel's interpolated texture coordinate, and
    /// Λ = g(λ·|r|) ([`super::roughness`] module notes). None otherwise.
    pub intended: Option<Image>,
}

/// One visible fragment's interpolated values (f64 from the unit's output codes).
pub(super) struct Shading {
    pub n: Vec3,
    pub r: Vec3,
    /// The λ the render used (interpolated per vertex, or the roughness texture's).
    pub lambda: f64,
    /// The intended λ: [`super::roughness::lambda_of_uv`] at the interpolated (u, v) (= `lambda` when
    /// (u, v) were not interpolated).
    pub lambda_intended: f64,
}

/// A level in f64 rounded to an 8-bit level (clamped).
pub(super) fn level8(x: f64) -> u8 {
    x.clamp(0.0, 255.0).round() as u8
}

/// The two truths at the rendered pixels (parallel over pixels, deterministic), with
/// the render's background.
pub(super) fn truth_images(
    shading: &[(usize, Shading)],
    background: &[(usize, [u8; 3])],
    levels_env: &EnvMap,
    side: u32,
    (w, h): (u32, u32),
    intended: bool,
) -> Result<Truth, ConfigError> {
    use rayon::prelude::*;
    let truth = PhongTruth::new(levels_env);
    let s = side as f64;
    type Px = ([u8; 3], [u8; 3], Option<[u8; 3]>);
    let px: Vec<Px> = shading
        .par_iter()
        .map(|(_, sh)| {
            let big_lambda = g(sh.lambda * sh.r.length(), s, THESIS_LEVELS);
            let tc = truth.eval(sh.r, sh.n, big_lambda, Visibility::CosPhiTest)?;
            let ts = truth.eval(sh.r, sh.n, big_lambda, Visibility::Simplified)?;
            let ti = if intended {
                let big = g(sh.lambda_intended * sh.r.length(), s, THESIS_LEVELS);
                Some(
                    truth
                        .eval(sh.r, sh.n, big, Visibility::Simplified)?
                        .map(level8),
                )
            } else {
                None
            };
            Ok((tc.map(level8), ts.map(level8), ti))
        })
        .collect::<Result<_, ConfigError>>()?;
    let mut truth_c = Image::new(w, h);
    let mut truth_s = Image::new(w, h);
    let mut truth_i = intended.then(|| Image::new(w, h));
    for ((k, _), (c, s, i)) in shading.iter().zip(px) {
        truth_c.pixels[*k] = c;
        truth_s.pixels[*k] = s;
        truth_c.mask[*k] = true;
        truth_s.mask[*k] = true;
        if let (Some(ti), Some(i)) = (truth_i.as_mut(), i) {
            ti.pixels[*k] = i;
            ti.mask[*k] = true;
        }
    }
    for &(k, bg) in background {
        truth_c.pixels[k] = bg;
        truth_s.pixels[k] = bg;
        if let Some(ti) = truth_i.as_mut() {
            ti.pixels[k] = bg;
        }
    }
    Ok(Truth {
        cos_phi: truth_c,
        simplified: truth_s,
        side,
        intended: truth_i,
    })
}

/// The errors against the intended-λ truth `intended`: over all object pixels and over
/// the seam band, the latter also against the render's own truth `simplified`, and the
/// λ errors.
pub(super) fn intended_errors(
    img: &Image,
    shading: &[(usize, Shading)],
    intended: &Image,
    simplified: &Image,
) -> IntendedErrors {
    let band = seam_band(img, shading);
    IntendedErrors {
        all: ErrorStats::of(img, intended),
        seam: ErrorStats::of_masked(img, intended, &band),
        seam_own: ErrorStats::of_masked(img, simplified, &band),
        lambda_all: lambda_errors(shading, &img.mask),
        lambda_seam: lambda_errors(shading, &band),
    }
}

/// |λ used − λ intended| over the pixels in `mask`.
fn lambda_errors(shading: &[(usize, Shading)], mask: &[bool]) -> LambdaErrors {
    let mut e = LambdaErrors::default();
    let mut sum = 0.0;
    for (k, sh) in shading {
        if mask.get(*k).copied().unwrap_or(false) {
            let d = (sh.lambda - sh.lambda_intended).abs();
            e.pixels += 1;
            sum += d;
            e.max = e.max.max(d);
        }
    }
    if e.pixels > 0 {
        e.mean = sum / e.pixels as f64;
    }
    e
}

/// The seam band of [`IntendedErrors::seam`] from the intended λ per pixel.
fn seam_band(img: &Image, shading: &[(usize, Shading)]) -> Vec<bool> {
    let (w, h) = (img.width as i64, img.height as i64);
    let mut lam: Vec<Option<f64>> = vec![None; img.pixels.len()];
    for (k, sh) in shading {
        lam[*k] = Some(sh.lambda_intended);
    }
    let mut band = vec![false; lam.len()];
    let r = SEAM_RADIUS as i64;
    for y in 0..h {
        for x in 0..w {
            let Some(l) = lam[(y * w + x) as usize] else {
                continue;
            };
            let jump = [(1, 0), (0, 1)].iter().any(|&(dx, dy)| {
                let (nx, ny) = (x + dx, y + dy);
                nx < w
                    && ny < h
                    && lam[(ny * w + nx) as usize].is_some_and(|m| (m - l).abs() > SEAM_JUMP)
            });
            if !jump {
                continue;
            }
            for by in (y - r).max(0)..=(y + r + 1).min(h - 1) {
                for bx in (x - r).max(0)..=(x + r + 1).min(w - 1) {
                    let k = (by * w + bx) as usize;
                    band[k] = lam[k].is_some();
                }
            }
        }
    }
    band
}
