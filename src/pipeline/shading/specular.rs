//! `reproduce shading-specular`: the specular exponent (n·h)^s on the test sphere,
//! formed three ways against the f64 value 255·(n̂·ĥ)^s:
//!
//! - **squaring** in the register combiners (s = 2^k): n and h from an 8-bit
//!   normalisation cube map (what a register combiner can read), n·h by the first
//!   general combiner's dot product, then k squarings, each rounded to the combiners'
//!   internal precision (9 bits on a GeForce 256/2) — the era's banded highlight;
//! - **lookup after an 8-bit DOT3**: the same 8-bit vectors, GL's DOT3_RGB rounded to
//!   8 bits, then the specular lookup table — which shows where the banding comes from:
//!   an 8-bit n·h, not the squaring (at 9 bits the chained squaring costs almost
//!   nothing over one rounding: see `docs/units.md#register_combiner`);
//! - **lookup at texture-shader precision**: n and h from a 16-bit normalisation cube,
//!   the dot product at 16 bits (GeForce3's texture shader computes the dot product
//!   that addresses the next texture at far more than 8 bits: DOT_PRODUCT_TEXTURE_1D_NV),
//!   and the lookup indexed by the 16-bit n·h with linear interpolation.
//!
//! Banding, in numbers: the distinct output levels inside the highlight beside the
//! reference's, and the largest jump between horizontally adjacent pixels beside the
//! reference's own largest jump (a band edge is a jump the smooth highlight lacks).

use super::normalize_cube::{NormalizeCube, NormalizeCubeConfig, NormalizeCubeCounters};
use super::path::combiner_stage;
use super::sphere::{SphereView, VIEW};
use super::squaring::SquaringChain;
use crate::report::image_out::grey_image;
use crate::report::metrics::error_stats_masked;
use crate::report::plot::{image_grid, line_plot, Axis, PlotSpec, Series};
use image::RgbaImage;
use rtl_model::units::specular_lookup::SpecularLookupConfig;
use rtl_model::units::texture_combiner::{CombineFunction, TextureCombinerIn};
use rtl_model::units::texture_sampler::Filter;
use rtl_model::{ConfigError, Counters};
use serde::Serialize;
use std::collections::BTreeSet;
use std::path::Path;

/// Per covered pixel: n̂ and ĥ as the cube map returns them (unorm codes at its texel
/// width) and the f64 reference n̂·ĥ (clamped at 0).
pub type SphereVectors = Vec<Option<([u32; 3], [u32; 3], f64)>>;

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

/// The 8-bit cube the register combiners read (GeForce defaults: 64² faces).
pub fn cube_8bit() -> Result<NormalizeCube, ConfigError> {
    NormalizeCubeConfig::geforce().build()
}

/// The 16-bit cube of the texture-shader path (256² faces, bilinear).
pub fn cube_16bit() -> Result<NormalizeCube, ConfigError> {
    NormalizeCubeConfig::with(256, 16, Filter::Linear).build()
}

/// n̂ and (l + v)/2 normalised through `cube`, per pixel of the view.
pub fn sphere_vectors(
    view: &SphereView,
    cube: &NormalizeCube,
) -> Result<SphereVectors, ConfigError> {
    let mut ctr = NormalizeCubeCounters::default();
    let mut look = |v: crate::scene::math::Vec3| -> Result<[u32; 3], ConfigError> {
        let w = cube.vector_words([v.x, v.y, v.z], &mut ctr.address)?;
        Ok(cube.normalize(&w, &mut ctr))
    };
    let h = (view.light + VIEW) * 0.5;
    view.pixels()
        .iter()
        .map(|p| match p {
            None => Ok(None),
            Some(p) => {
                let nh = p.frame.n.dot(h.normalized()).max(0.0);
                Ok(Some((look(p.frame.n)?, look(h)?, nh)))
            }
        })
        .collect()
}

/// (n·h)^s: DOT3_RGB at the vectors' width `bits`, then the specular lookup indexed
/// by that width (the lookup's table size and entry width from `lookup`).
pub fn lookup_levels(
    vectors: &SphereVectors,
    bits: u32,
    exponent: f64,
    lookup: SpecularLookupConfig,
    ctr: &mut Counters,
) -> Result<Vec<f64>, ConfigError> {
    let dot3 = combiner_stage(bits, CombineFunction::Dot3Rgb, 1)?;
    let lut = SpecularLookupConfig {
        exponent,
        in_bits: bits,
        ..lookup
    }
    .build()?;
    let one = (1u32 << bits) - 1;
    let out_max = ((1u64 << lookup.entry_bits) - 1) as f64;
    Ok(vectors
        .iter()
        .map(|v| match v {
            None => 0.0,
            Some((n, h, _)) => {
                let input = TextureCombinerIn {
                    texture: [n[0], n[1], n[2], one],
                    previous: [h[0], h[1], h[2], one],
                    ..TextureCombinerIn::default()
                };
                let nh = dot3.combine(&input, ctr)[0];
                lut.lookup(nh as i32, ctr) as f64 * 255.0 / out_max
            }
        })
        .collect())
}

/// (n·h)^(2^k) by k squarings in the register combiners at `internal_bits`, from
/// 8-bit vectors.
pub fn squaring_levels(
    vectors: &SphereVectors,
    k: u32,
    internal_bits: u32,
    ctr: &mut Counters,
) -> Result<Vec<f64>, ConfigError> {
    let chain = SquaringChain::new(internal_bits)?;
    Ok(squaring_levels_on(vectors, k, &chain, ctr))
}

/// [`squaring_levels`] through a given chain (its width and chip modes).
pub fn squaring_levels_on(
    vectors: &SphereVectors,
    k: u32,
    chain: &SquaringChain,
    ctr: &mut Counters,
) -> Vec<f64> {
    let u8v = |a: &[u32; 3]| a.map(|c| c.min(255) as u8);
    vectors
        .iter()
        .map(|v| {
            v.as_ref().map_or(0.0, |(n, h, _)| {
                chain.specular(u8v(n), u8v(h), k, ctr) as f64
            })
        })
        .collect()
}

/// The reference 255·(n̂·ĥ)^s.
pub fn reference_levels(vectors: &SphereVectors, exponent: f64) -> Vec<f64> {
    vectors
        .iter()
        .map(|v| {
            v.as_ref()
                .map_or(0.0, |(_, _, nh)| 255.0 * nh.powf(exponent))
        })
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

/// Squaring at these internal widths (9 = GeForce 256/2).
pub const SQUARING_BITS: [u32; 3] = [9, 12, 16];

/// Path labels, in the CSV and the images.
pub const LOOKUP_8: &str = "lookup after 8-bit DOT3";
pub const LOOKUP_16: &str = "lookup at 16-bit texture-shader precision";

/// Every path at s = 2^k: (label, levels).
pub fn paths_at(
    k: u32,
    v8: &SphereVectors,
    v16: &SphereVectors,
    ctr: &mut Counters,
) -> Result<Vec<(String, Vec<f64>)>, ConfigError> {
    let s = (1u32 << k) as f64;
    let lut = SpecularLookupConfig::geforce();
    let mut out = Vec::new();
    for bits in SQUARING_BITS {
        out.push((
            format!("squaring {bits}-bit"),
            squaring_levels(v8, k, bits, ctr)?,
        ));
    }
    out.push((LOOKUP_8.to_string(), lookup_levels(v8, 8, s, lut, ctr)?));
    out.push((LOOKUP_16.to_string(), lookup_levels(v16, 16, s, lut, ctr)?));
    Ok(out)
}

/// Run s = 8 … 128 (k = 3 ..= 7) on the default 256² sphere; write
/// `shading_specular.csv`, `shading_specular.png` (s = 32 and 128: f64, squaring at
/// 9 bits, the 16-bit lookup, and both differences ×8) and
/// `shading_specular_profile.png` (the row through the highlight at s = 32).
pub fn shading_specular(out: &Path) -> Result<Vec<SpecularRow>, String> {
    let e = |e: ConfigError| e.to_string();
    let view = SphereView::default();
    let v8 = sphere_vectors(&view, &cube_8bit().map_err(e)?).map_err(e)?;
    let v16 = sphere_vectors(&view, &cube_16bit().map_err(e)?).map_err(e)?;
    let mask: Vec<bool> = v8.iter().map(|v| v.is_some()).collect();
    std::fs::create_dir_all(out).map_err(|e| format!("out: {}: {e}", out.display()))?;
    let mut rows = Vec::new();
    let mut panels: Vec<(String, RgbaImage)> = Vec::new();
    let mut profile = Vec::new();
    let mut ctr = Counters::default();
    for k in 3..=7u32 {
        let s = 1u32 << k;
        let reference = reference_levels(&v8, s as f64);
        let paths = paths_at(k, &v8, &v16, &mut ctr).map_err(e)?;
        for (label, levels) in &paths {
            rows.push(score(label, s, levels, &reference, &mask, view.size).map_err(e)?);
        }
        let get = |label: &str| &paths.iter().find(|(l, _)| l == label).expect("path").1;
        let (sq9, lut16) = (get("squaring 9-bit"), get(LOOKUP_16));
        if k == 5 || k == 7 {
            let diff = |a: &[f64]| -> Vec<f64> {
                a.iter()
                    .zip(&reference)
                    .map(|(h, f)| (h - f).abs() * 8.0)
                    .collect()
            };
            panels.push((format!("s = {s}: f64"), grey_image(&reference, view.size)));
            panels.push((
                format!("s = {s}: squaring 9-bit"),
                grey_image(sq9, view.size),
            ));
            panels.push((
                format!("s = {s}: lookup 16-bit"),
                grey_image(lut16, view.size),
            ));
            panels.push((
                format!("s = {s}: squaring |Δ|×8"),
                grey_image(&diff(sq9), view.size),
            ));
            panels.push((
                format!("s = {s}: lookup |Δ|×8"),
                grey_image(&diff(lut16), view.size),
            ));
        }
        if k == 5 {
            profile = vec![
                ("f64".to_string(), reference.clone()),
                ("squaring 9-bit".to_string(), sq9.clone()),
                (LOOKUP_8.to_string(), get(LOOKUP_8).clone()),
                (LOOKUP_16.to_string(), lut16.clone()),
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
            label: label.clone(),
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

/// The rows as a terminal table.
pub fn table(rows: &[SpecularRow]) -> String {
    let body: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            vec![
                r.exponent.to_string(),
                r.path.clone(),
                format!("{:.2}", r.mean_abs),
                format!("{:.2}", r.rms),
                format!("{:.0}", r.max),
                format!("{} / {}", r.distinct_levels, r.reference_levels),
                format!("{:.0} / {:.1}", r.max_step, r.reference_max_step),
            ]
        })
        .collect();
    crate::report::table::text_table(
        &[
            "s",
            "path",
            "mean |Δ|",
            "RMS",
            "max",
            "levels (vs f64)",
            "max step (vs f64)",
        ],
        &body,
    )
}
