//! `reproduce shading-specular`: the specular exponent (n·h)^s two ways on the test
//! sphere — by repeated squaring in the register combiners (s = 2^k, the GeForce
//! 256/2/3 trick, each squaring rounded to the combiners' internal precision: 9 bits
//! on a GeForce 256/2) and by the specular lookup table after a DOT3 — against the
//! f64 value 255·(n̂·ĥ)^s. Both paths read the same normalisation-cube vectors, so
//! what differs is only how the power is formed.
//!
//! Banding, in numbers: the number of distinct output levels inside the highlight,
//! and the largest jump between horizontally adjacent pixels beside the reference's
//! own largest jump (a band edge is a jump the smooth highlight does not have).

use super::normalize_cube::{NormalizeCube, NormalizeCubeConfig, NormalizeCubeCounters};
use super::sphere::{SphereView, VIEW};
use super::squaring::SquaringChain;
use super::brdfs::grey_image;
use crate::report::metrics::error_stats_masked;
use crate::report::plot::{image_grid, line_plot, Axis, PlotSpec, Series};
use image::RgbaImage;
use rtl_model::units::specular_lookup::{SpecularLookup, SpecularLookupConfig};
use rtl_model::units::texture_combiner::{
    CombineFunction, CombineSource, TextureCombinerConfig, TextureCombinerIn,
};
use rtl_model::{ConfigError, Counters};
use serde::Serialize;
use std::collections::BTreeSet;
use std::path::Path;

/// One path at one exponent.
#[derive(Clone, Debug, Serialize)]
pub struct SpecularRow {
    pub path: String,
    pub exponent: u32,
    pub mean_abs: f64,
    pub rms: f64,
    pub max: f64,
    /// Distinct output levels among pixels where the reference is ≥ 1 level.
    pub distinct_levels: usize,
    /// The same count for the reference rounded to levels.
    pub reference_levels: usize,
    /// Largest |Δ| between horizontally adjacent covered pixels, output and reference.
    pub max_step: f64,
    pub reference_max_step: f64,
}

/// The per-pixel normalised N and H (unorm8 RGB, expand-normal encoding) of the view,
/// through the normalisation cube; None outside the sphere. Also the f64 reference
/// n̂·ĥ (clamped at 0).
pub fn sphere_vectors(
    view: &SphereView,
    cube: &NormalizeCube,
) -> Result<Vec<Option<([u8; 3], [u8; 3], f64)>>, ConfigError> {
    let mut ctr = NormalizeCubeCounters::default();
    let mut look = |v: crate::scene::math::Vec3| -> Result<[u8; 3], ConfigError> {
        let w = cube.vector_words([v.x, v.y, v.z], &mut ctr.address)?;
        Ok(cube.normalize(&w, &mut ctr).map(|c| c as u8))
    };
    view.pixels()
        .iter()
        .map(|p| match p {
            None => Ok(None),
            Some(p) => {
                let h = (view.light + VIEW) * 0.5;
                let nh = p.frame.n.dot(h.normalized()).max(0.0);
                Ok(Some((look(p.frame.n)?, look(h)?, nh)))
            }
        })
        .collect()
}

/// (n·h)^s by DOT3 (texture_combiner) and the specular lookup (s any exponent).
pub fn lookup_levels(
    vectors: &[Option<([u8; 3], [u8; 3], f64)>],
    exponent: f64,
    lookup: SpecularLookupConfig,
    ctr: &mut Counters,
) -> Result<Vec<f64>, ConfigError> {
    let dot3 = TextureCombinerConfig {
        combine_rgb: CombineFunction::Dot3Rgb,
        combine_alpha: CombineFunction::Replace,
        source_rgb: [
            CombineSource::Texture,
            CombineSource::Previous,
            CombineSource::Constant,
        ],
        ..TextureCombinerConfig::geforce()
    }
    .build()?;
    let lut: SpecularLookup = SpecularLookupConfig { exponent, ..lookup }.build()?;
    Ok(vectors
        .iter()
        .map(|v| match v {
            None => 0.0,
            Some((n, h, _)) => {
                let rgba = |a: &[u8; 3]| [a[0] as u32, a[1] as u32, a[2] as u32, 255];
                let input = TextureCombinerIn {
                    texture: rgba(n),
                    previous: rgba(h),
                    ..TextureCombinerIn::default()
                };
                let nh = dot3.combine(&input, ctr)[0];
                lut.lookup(nh as i32, ctr) as f64
            }
        })
        .collect())
}

/// (n·h)^(2^k) by k squarings in the register combiners at `internal_bits`.
pub fn squaring_levels(
    vectors: &[Option<([u8; 3], [u8; 3], f64)>],
    k: u32,
    internal_bits: u32,
    ctr: &mut Counters,
) -> Result<Vec<f64>, ConfigError> {
    let chain = SquaringChain::new(internal_bits)?;
    Ok(vectors
        .iter()
        .map(|v| v.map_or(0.0, |(n, h, _)| chain.specular(n, h, k, ctr) as f64))
        .collect())
}

/// The reference 255·(n̂·ĥ)^s.
pub fn reference_levels(vectors: &[Option<([u8; 3], [u8; 3], f64)>], exponent: f64) -> Vec<f64> {
    vectors
        .iter()
        .map(|v| v.map_or(0.0, |(_, _, nh)| 255.0 * nh.powf(exponent)))
        .collect()
}

fn max_step(levels: &[f64], mask: &[bool], size: u32) -> f64 {
    let s = size as usize;
    let mut m: f64 = 0.0;
    for y in 0..s {
        for x in 0..s - 1 {
            let (i, j) = (y * s + x, y * s + x + 1);
            if mask[i] && mask[j] {
                m = m.max((levels[i] - levels[j]).abs());
            }
        }
    }
    m
}

/// Score one path's image against the reference.
pub fn score(
    path: &str,
    exponent: u32,
    hw: &[f64],
    reference: &[f64],
    mask: &[bool],
    size: u32,
) -> Result<SpecularRow, ConfigError> {
    let rgb = |v: &[f64]| v.iter().map(|&x| [x; 3]).collect::<Vec<_>>();
    let st = error_stats_masked(&rgb(hw), &rgb(reference), mask)?;
    let lit: Vec<usize> = (0..hw.len())
        .filter(|&i| mask[i] && reference[i] >= 1.0)
        .collect();
    let distinct = |v: &[f64]| {
        lit.iter()
            .map(|&i| v[i].round() as i64)
            .collect::<BTreeSet<_>>()
            .len()
    };
    let rounded: Vec<f64> = reference.iter().map(|v| v.round()).collect();
    Ok(SpecularRow {
        path: path.to_string(),
        exponent,
        mean_abs: st.mean_abs,
        rms: st.rms,
        max: st.max,
        distinct_levels: distinct(hw),
        reference_levels: distinct(&rounded),
        max_step: max_step(hw, mask, size),
        reference_max_step: max_step(reference, mask, size),
    })
}

/// Squaring at these internal widths (9 = GeForce 256/2) beside the lookup.
pub const SQUARING_BITS: [u32; 3] = [9, 12, 16];

/// Run k = 3 ..= 7 (s = 8 … 128) on the default sphere; write
/// `shading_specular.csv`, `shading_specular.png` (s = 32 and 128: f64, squaring at
/// 9 bits, lookup, and both differences ×8) and `shading_specular_profile.png` (the
/// row through the highlight at s = 32).
pub fn shading_specular(out: &Path) -> Result<Vec<SpecularRow>, String> {
    let view = SphereView::default();
    let cube = NormalizeCubeConfig::geforce()
        .build()
        .map_err(|e| e.to_string())?;
    let vectors = sphere_vectors(&view, &cube).map_err(|e| e.to_string())?;
    let mask: Vec<bool> = vectors.iter().map(|v| v.is_some()).collect();
    std::fs::create_dir_all(out).map_err(|e| format!("out: {}: {e}", out.display()))?;
    let mut rows = Vec::new();
    let mut panels: Vec<(String, RgbaImage)> = Vec::new();
    let mut profile = Vec::new();
    let mut ctr = Counters::default();
    for k in 3..=7u32 {
        let s = 1u32 << k;
        let reference = reference_levels(&vectors, s as f64);
        let lookup = lookup_levels(&vectors, s as f64, SpecularLookupConfig::geforce(), &mut ctr)
            .map_err(|e| e.to_string())?;
        rows.push(score("lookup 256×8b", s, &lookup, &reference, &mask, view.size).map_err(|e| e.to_string())?);
        let mut sq9 = Vec::new();
        for bits in SQUARING_BITS {
            let sq = squaring_levels(&vectors, k, bits, &mut ctr).map_err(|e| e.to_string())?;
            rows.push(
                score(&format!("squaring {bits}-bit"), s, &sq, &reference, &mask, view.size)
                    .map_err(|e| e.to_string())?,
            );
            if bits == SQUARING_BITS[0] {
                sq9 = sq;
            }
        }
        if k == 5 || k == 7 {
            let diff = |a: &[f64]| -> Vec<f64> {
                a.iter().zip(&reference).map(|(h, f)| (h - f).abs() * 8.0).collect()
            };
            panels.push((format!("s = {s}: f64"), grey_image(&reference, view.size)));
            panels.push((format!("s = {s}: squaring 9-bit"), grey_image(&sq9, view.size)));
            panels.push((format!("s = {s}: lookup"), grey_image(&lookup, view.size)));
            panels.push((format!("s = {s}: squaring |Δ|×8"), grey_image(&diff(&sq9), view.size)));
            panels.push((format!("s = {s}: lookup |Δ|×8"), grey_image(&diff(&lookup), view.size)));
        }
        if k == 5 {
            profile = vec![
                ("f64", reference.clone()),
                ("squaring 9-bit", sq9.clone()),
                ("lookup", lookup.clone()),
            ];
        }
    }
    crate::report::csv_out::write_csv(&out.join("shading_specular.csv"), &rows)?;
    let refs: Vec<(&str, &RgbaImage)> = panels.iter().map(|(c, i)| (c.as_str(), i)).collect();
    image_grid(&out.join("shading_specular.png"), &refs, 5)?;
    // The row through the highlight's peak.
    let size = view.size as usize;
    let peak = profile[0]
        .1
        .iter()
        .enumerate()
        .fold((0, f64::MIN), |m, (i, &v)| if v > m.1 { (i, v) } else { m })
        .0;
    let y = peak / size;
    let series: Vec<Series> = profile
        .iter()
        .map(|(label, v)| Series {
            label: label.to_string(),
            points: (0..size).map(|x| (x as f64, v[y * size + x])).collect(),
            axis: Axis::Left,
        })
        .collect();
    line_plot(
        &out.join("shading_specular_profile.png"),
        &PlotSpec::new(
            &format!("(n·h)^32 along row {y} through the highlight"),
            "x (pixels)",
            "level",
        ),
        &series,
    )?;
    Ok(rows)
}
