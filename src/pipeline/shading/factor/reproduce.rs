//! `reproduce shading-factorization`: the error of SVD and homomorphic factor textures
//! against factor-texture resolution and texel bits, on the shading test sphere.

use super::homomorphic::{self, HomomorphicParams};
use super::svd::{SvdFit, SvdParams};
use super::{level_stats, FactorMethod, FactorRenderer, FactorTarget, Factorisation};
use crate::pipeline::shading::sphere::SphereView;
use crate::reference::brdf::Brdf;
use crate::report::csv_out::write_csv;
use crate::report::plot::{image_grid, line_plot, Axis, PlotSpec, Series};
use crate::scene::math::Vec3;
use image::RgbaImage;
use rtl_model::counters::Counters;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// STAND-IN MATERIAL, to be replaced by the shared Cook–Torrance reference when the
/// shading branches are merged: a Beckmann microfacet lobe with Schlick's Fresnel and
/// Torrance–Sparrow masking over a Lambert base,
/// R = k_d/π + k_s · D(h) F(ω_i·h) G / (4 cos θ_i cos θ_o).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StandInMicrofacet {
    /// Beckmann RMS slope m (> 0).
    pub roughness: f64,
    pub diffuse: f64,
    pub specular: f64,
    /// Fresnel reflectance at normal incidence.
    pub f0: f64,
}

impl Default for StandInMicrofacet {
    /// A rough metal-like lobe (m = 0.3, F0 = 0.9), no diffuse base (a Lambert term is
    /// not a product of these factors; it would be added by its own combiner stage).
    fn default() -> Self {
        StandInMicrofacet {
            roughness: 0.3,
            diffuse: 0.0,
            specular: 1.0,
            f0: 0.9,
        }
    }
}

impl Brdf for StandInMicrofacet {
    fn name(&self) -> String {
        format!("standin_microfacet_m{}", self.roughness)
    }

    fn eval(&self, wi: Vec3, wo: Vec3) -> f64 {
        let (ci, co) = (wi.z, wo.z);
        if ci <= 0.0 || co <= 0.0 {
            return 0.0;
        }
        let h = (wi + wo).normalized();
        let ch = h.z.clamp(1e-9, 1.0);
        let m2 = self.roughness * self.roughness;
        let tan2 = (1.0 - ch * ch) / (ch * ch);
        let d = (-tan2 / m2).exp() / (std::f64::consts::PI * m2 * ch.powi(4));
        let vh = wi.dot(h).clamp(0.0, 1.0);
        let f = self.f0 + (1.0 - self.f0) * (1.0 - vh).powi(5);
        let g = (2.0 * ch * co / vh.max(1e-9))
            .min(2.0 * ch * ci / vh.max(1e-9))
            .min(1.0);
        self.diffuse / std::f64::consts::PI + self.specular * d * f * g / (4.0 * ci * co)
    }
}

/// What the sweep covers.
#[derive(Clone, Debug, PartialEq)]
pub struct FactorSweep {
    /// Factor-texture resolutions (each texture is N × N).
    pub resolutions: Vec<u32>,
    /// Texel bits b (the combiner is max(8, b) bits wide).
    pub texel_bits: Vec<u32>,
    pub view: SphereView,
    pub target: FactorTarget,
    /// Target ceilings swept (each overrides `svd.ceiling` and `homomorphic.ceiling`).
    pub ceilings: Vec<f64>,
    pub svd: SvdParams,
    pub homomorphic: HomomorphicParams,
}

impl Default for FactorSweep {
    /// 16 … 256 (powers of two), 4 … 16 bits, the default sphere, R · cos θ_i.
    fn default() -> Self {
        FactorSweep {
            resolutions: vec![16, 32, 64, 128, 256],
            texel_bits: (4..=16).collect(),
            view: SphereView::default(),
            target: FactorTarget::BrdfCosine,
            // Absolute values of the target R·cos θ_i. At the default E = 1 they read:
            // ∞, the BRDF as it is; 4 = 4/E, peaks above 4× the output's saturation are
            // cut; 1 = 1/E, everything above what the 8-bit output can show is cut.
            ceilings: vec![f64::INFINITY, 4.0, 1.0],
            svd: SvdParams::default(),
            homomorphic: HomomorphicParams::default(),
        }
    }
}

/// One (method, resolution, bits) point of the sweep; errors in 8-bit levels over the
/// covered sphere pixels.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FactorRow {
    pub brdf: String,
    pub method: String,
    pub target: String,
    /// The target ceiling (values above it fitted as it; inf = none).
    pub ceiling: f64,
    pub resolution: u32,
    pub textures: u32,
    pub texel_bits: u32,
    pub combiner_bits: u32,
    /// Σ size² · b over the factor textures.
    pub table_bits: u64,
    /// The output scale 2^scale_shift.
    pub scale_shift: u32,
    /// The f64 factors (unquantised, same sampling) against the reference: the
    /// factorisation's own error.
    pub f64_mean: f64,
    pub f64_rms: f64,
    pub f64_max: f64,
    /// The 8-bit output of the units against the reference.
    pub hw_mean: f64,
    pub hw_rms: f64,
    pub hw_max: f64,
    /// max |hardware − f64 factors|: the quantisation error alone, and its derived bound.
    pub quant_max: f64,
    pub quant_bound: f64,
    pub saturations: u64,
    pub pixels: u64,
}

/// The sphere as images: reference, f64 factors and hardware levels, and the mask.
struct SphereImages {
    reference: Vec<f64>,
    mask: Vec<bool>,
}

impl SphereImages {
    fn new(view: &SphereView, brdf: &dyn Brdf) -> Self {
        SphereImages {
            reference: view.reference_levels(brdf),
            mask: view.pixels().iter().map(|p| p.is_some()).collect(),
        }
    }
}

/// Render one factorisation at one texel width and score it.
fn score(
    brdf: &dyn Brdf,
    (fact, ceiling): &(Factorisation, f64),
    bits: u32,
    view: &SphereView,
    imgs: &SphereImages,
) -> Result<(FactorRow, Vec<f64>, Vec<f64>), String> {
    let r = FactorRenderer::new(fact, bits, view.irradiance).map_err(|e| e.to_string())?;
    let mut ctr = Counters::default();
    let px = r.render(view, &mut ctr).map_err(|e| e.to_string())?;
    let hw: Vec<f64> = px
        .iter()
        .map(|p| p.map_or(0.0, |(h, _)| h as f64))
        .collect();
    let fl: Vec<f64> = px.iter().map(|p| p.map_or(0.0, |(_, f)| f)).collect();
    let e = |a: &[f64], b: &[f64]| level_stats(a, b, &imgs.mask).map_err(|e| e.to_string());
    let (sf, sh, sq) = (
        e(&fl, &imgs.reference)?,
        e(&hw, &imgs.reference)?,
        e(&hw, &fl)?,
    );
    let row = FactorRow {
        brdf: brdf.name(),
        method: fact.method.name().to_string(),
        target: fact.target.name().to_string(),
        ceiling: *ceiling,
        resolution: fact.factors.first().map_or(0, |f| f.size),
        textures: fact.factors.len() as u32,
        texel_bits: bits,
        combiner_bits: r.combiner_bits(),
        table_bits: r.table_bits(),
        scale_shift: r.shift(),
        f64_mean: sf.mean_abs,
        f64_rms: sf.rms,
        f64_max: sf.max,
        hw_mean: sh.mean_abs,
        hw_rms: sh.rms,
        hw_max: sh.max,
        quant_max: sq.max,
        quant_bound: r.error_bound_levels(),
        saturations: ctr.saturations,
        pixels: imgs.mask.iter().filter(|&&m| m).count() as u64,
    };
    Ok((row, hw, fl))
}

/// The factorisations of the sweep with their ceilings: per ceiling, SVD at every
/// resolution, then homomorphic at every resolution (each warm-started from the last).
pub fn factorisations(
    brdf: &dyn Brdf,
    cfg: &FactorSweep,
) -> Result<Vec<(Factorisation, f64)>, String> {
    let mut out = Vec::new();
    for &ceiling in &cfg.ceilings {
        out.extend(factorisations_at(brdf, cfg, ceiling)?);
    }
    Ok(out)
}

/// The factorisations of one ceiling: SVD at every resolution, then the homomorphic
/// ones (each resolution warm-started from the one before, so a ceiling is one unit
/// of work).
fn factorisations_at(
    brdf: &dyn Brdf,
    cfg: &FactorSweep,
    ceiling: f64,
) -> Result<Vec<(Factorisation, f64)>, String> {
    let mut out = Vec::new();
    let svd = SvdParams { ceiling, ..cfg.svd };
    let fit = SvdFit::new(brdf, cfg.target, &svd).map_err(|e| e.to_string())?;
    for &n in &cfg.resolutions {
        out.push((fit.textures(brdf, n).map_err(|e| e.to_string())?, ceiling));
    }
    let hp = HomomorphicParams {
        ceiling,
        ..cfg.homomorphic
    };
    let mut warm: Option<Factorisation> = None;
    for &n in &cfg.resolutions {
        let (f, _) = homomorphic::factorise(brdf, cfg.target, n, &hp, warm.as_ref())
            .map_err(|e| e.to_string())?;
        warm = Some(f.clone());
        out.push((f, ceiling));
    }
    Ok(out)
}

/// Every (method, resolution, bits) row of the sweep.
pub fn sweep(brdf: &dyn Brdf, cfg: &FactorSweep) -> Result<Vec<FactorRow>, String> {
    let imgs = SphereImages::new(&cfg.view, brdf);
    let mut rows = Vec::new();
    for f in factorisations(brdf, cfg)? {
        for &b in &cfg.texel_bits {
            rows.push(score(brdf, &f, b, &cfg.view, &imgs)?.0);
        }
    }
    Ok(rows)
}

/// The smallest table (then the lowest resolution, then the fewest bits) of `method`
/// whose hardware max error is within `levels`.
pub fn first_within<'a>(rows: &'a [FactorRow], method: &str, levels: f64) -> Option<&'a FactorRow> {
    rows.iter()
        .filter(|r| r.method == method && r.hw_max <= levels)
        .min_by_key(|r| (r.table_bits, r.resolution, r.texel_bits))
}

/// The sentence the reproduction states per method about the 2-level criterion.
pub fn verdict(rows: &[FactorRow], method: &str) -> String {
    const LEVELS: f64 = 2.0;
    if let Some(r) = first_within(rows, method, LEVELS) {
        return format!(
            "{method}: first within {LEVELS} levels max at {0}×{0} texels, {1} bits ({2} table bits, ceiling {5}): max {3:.2}, RMS {4:.3} levels",
            r.resolution, r.texel_bits, r.table_bits, r.hw_max, r.hw_rms, r.ceiling
        );
    }
    let best_f64 = rows
        .iter()
        .filter(|r| r.method == method)
        .min_by(|a, b| a.f64_max.total_cmp(&b.f64_max));
    let best_hw = rows
        .iter()
        .filter(|r| r.method == method)
        .min_by(|a, b| a.hw_max.total_cmp(&b.hw_max));
    match (best_f64, best_hw) {
        (Some(f), Some(h)) if f.f64_max > LEVELS => format!(
            "{method}: never within {LEVELS} levels max: the factorisation itself (f64 factors, no quantisation) is off by {fmax:.2} levels max at best ({fres}×{fres}, ceiling {fc}) — the BRDF is not a product of these factors; the best quantised max is {hmax:.2} ({hres}×{hres}, {hbits} bits, ceiling {hc})",
            fmax = f.f64_max, fres = f.resolution, fc = f.ceiling, hmax = h.hw_max, hres = h.resolution, hbits = h.texel_bits, hc = h.ceiling
        ),
        (Some(f), Some(h)) => format!(
            "{method}: never within {LEVELS} levels max, although the f64 factors are ({fmax:.2} levels max at {fres}×{fres}, ceiling {fc}): quantisation adds the rest — best quantised max {hmax:.2} ({hres}×{hres}, {hbits} bits, ceiling {hc}, output scale 2^{shift})",
            fmax = f.f64_max, fres = f.resolution, fc = f.ceiling, hc = h.ceiling, hmax = h.hw_max, hres = h.resolution, hbits = h.texel_bits, shift = h.scale_shift
        ),
        _ => format!("{method}: no rows"),
    }
}

/// Plot the series that have points (none: no file).
fn plot_nonempty(path: &Path, spec: &PlotSpec, mut series: Vec<Series>) -> Result<(), String> {
    series.retain(|x| !x.points.is_empty());
    if series.is_empty() {
        return Ok(());
    }
    line_plot(path, spec, &series)
}

/// A sphere the image may show: method, ceiling, 8-bit RMS, hardware and f64 levels.
type SphereCandidate = (String, f64, f64, Vec<f64>, Vec<f64>);

/// One ceiling's rows and sphere candidates, the journal's item. Floats are kept as
/// their bit patterns: a ceiling is ∞, which JSON cannot hold, and the bytes must
/// come back exactly.
#[derive(Clone, Default, Serialize, Deserialize)]
struct CeilingItem {
    rows: Vec<RowBits>,
    candidates: Vec<CandidateBits>,
}

#[derive(Clone, Serialize, Deserialize)]
struct CandidateBits(String, u64, u64, Vec<u64>, Vec<u64>);

impl From<SphereCandidate> for CandidateBits {
    fn from((m, c, rms, hw, fl): SphereCandidate) -> Self {
        let bits = |v: Vec<f64>| v.into_iter().map(f64::to_bits).collect();
        CandidateBits(m, c.to_bits(), rms.to_bits(), bits(hw), bits(fl))
    }
}

impl From<CandidateBits> for SphereCandidate {
    fn from(CandidateBits(m, c, rms, hw, fl): CandidateBits) -> Self {
        let f = |v: Vec<u64>| v.into_iter().map(f64::from_bits).collect();
        (m, f64::from_bits(c), f64::from_bits(rms), f(hw), f(fl))
    }
}

/// A [`FactorRow`]: its text and integer fields, then its floats' bit patterns in
/// field order (ceiling, f64 mean/RMS/max, hardware mean/RMS/max, quant max/bound).
#[derive(Clone, Serialize, Deserialize)]
struct RowBits {
    text: [String; 3],
    ints: [u64; 8],
    floats: [u64; 9],
}

impl From<&FactorRow> for RowBits {
    fn from(r: &FactorRow) -> Self {
        RowBits {
            text: [r.brdf.clone(), r.method.clone(), r.target.clone()],
            ints: [
                r.resolution.into(),
                r.textures.into(),
                r.texel_bits.into(),
                r.combiner_bits.into(),
                r.table_bits,
                r.scale_shift.into(),
                r.saturations,
                r.pixels,
            ],
            floats: [
                r.ceiling,
                r.f64_mean,
                r.f64_rms,
                r.f64_max,
                r.hw_mean,
                r.hw_rms,
                r.hw_max,
                r.quant_max,
                r.quant_bound,
            ]
            .map(f64::to_bits),
        }
    }
}

impl From<&RowBits> for FactorRow {
    fn from(b: &RowBits) -> Self {
        let [brdf, method, target] = b.text.clone();
        let [resolution, textures, texel_bits, combiner_bits, table_bits, scale_shift, saturations, pixels] =
            b.ints;
        let [ceiling, f64_mean, f64_rms, f64_max, hw_mean, hw_rms, hw_max, quant_max, quant_bound] =
            b.floats.map(f64::from_bits);
        FactorRow {
            brdf,
            method,
            target,
            ceiling,
            resolution: resolution as u32,
            textures: textures as u32,
            texel_bits: texel_bits as u32,
            combiner_bits: combiner_bits as u32,
            table_bits,
            scale_shift: scale_shift as u32,
            f64_mean,
            f64_rms,
            f64_max,
            hw_mean,
            hw_rms,
            hw_max,
            quant_max,
            quant_bound,
            saturations,
            pixels,
        }
    }
}

fn gray(levels: &[f64], size: u32) -> RgbaImage {
    RgbaImage::from_fn(size, size, |x, y| {
        let v = levels[(y * size + x) as usize].round().clamp(0.0, 255.0) as u8;
        image::Rgba([v, v, v, 255])
    })
}

/// `reproduce shading-factorization` on `brdf`: writes `factorization.csv`, the plots
/// `factorization_bits.png` and `factorization_resolution.png`, the spheres
/// `factorization_spheres.png` (per method: the reference, the 64² × 8-bit
/// reconstruction, and |Δ| × 8 of the f64 factors and of the 8-bit output) and `factorization_summary.txt`; returns the summary lines.
pub fn factorization(
    out: &Path,
    brdf: &dyn Brdf,
    cfg: &FactorSweep,
) -> Result<Vec<String>, String> {
    factorization_resumable(out, brdf, cfg, false)
}

/// [`factorization`], saving each ceiling's rows and sphere candidates as it finishes
/// to `DIR/shading-factorization.resume.jsonl` (`report::items`); with `resume`,
/// those of an interrupted run of the same sweep are kept and only the other
/// ceilings are factorised.
pub fn factorization_resumable(
    out: &Path,
    brdf: &dyn Brdf,
    cfg: &FactorSweep,
    resume: bool,
) -> Result<Vec<String>, String> {
    let imgs = SphereImages::new(&cfg.view, brdf);
    let (rows, candidates) = sweep_ceilings(out, brdf, cfg, resume, &imgs)?;
    write_csv(&out.join("factorization.csv"), &rows)?;
    for &c in &cfg.ceilings {
        plot_bits(out, brdf, cfg, &rows, c)?;
        plot_resolution(out, brdf, &rows, c)?;
    }
    sphere_panels(out, cfg, &imgs, &candidates)?;
    let summary = summary_lines(brdf, cfg, &rows);
    crate::report::atomic::write_bytes(
        &out.join("factorization_summary.txt"),
        (summary.join("\n") + "\n").as_bytes(),
    )
    .map_err(|e| format!("out: {e}"))?;
    Ok(summary)
}

/// The (resolution, texel bits) whose spheres are shown: 64² × 8 bits.
const SHOW: (u32, u32) = (64, 8);

/// Every ceiling's rows and sphere candidates (method, ceiling, 8-bit RMS, hardware
/// image, f64 image at [`SHOW`]), each ceiling journalled as it finishes (kept from an
/// interrupted run with `resume`).
fn sweep_ceilings(
    out: &Path,
    brdf: &dyn Brdf,
    cfg: &FactorSweep,
    resume: bool,
    imgs: &SphereImages,
) -> Result<(Vec<FactorRow>, Vec<SphereCandidate>), String> {
    // The journal's record: everything the rows depend on, by value.
    let settings = [
        ("brdf", brdf.name().to_string()),
        ("sweep", format!("{cfg:?}")),
    ];
    let journal = crate::report::items::ItemJournal::<CeilingItem>::open(
        out,
        "shading-factorization",
        &settings,
        cfg.ceilings.len(),
        resume,
    )?;
    let mut rows = Vec::new();
    let mut candidates: Vec<SphereCandidate> = Vec::new();
    for (k, &ceiling) in cfg.ceilings.iter().enumerate() {
        let item = journal.item(&format!("ceiling{k}"), || {
            let mut item = CeilingItem::default();
            for f in &factorisations_at(brdf, cfg, ceiling)? {
                for &b in &cfg.texel_bits {
                    let (row, hw, fl) = score(brdf, f, b, &cfg.view, imgs)?;
                    if (row.resolution, b) == SHOW {
                        item.candidates
                            .push((row.method.clone(), row.ceiling, row.hw_rms, hw, fl).into());
                    }
                    item.rows.push(RowBits::from(&row));
                }
            }
            Ok(item)
        })?;
        rows.extend(item.rows.iter().map(FactorRow::from));
        candidates.extend(item.candidates.into_iter().map(SphereCandidate::from));
    }
    journal.finish()?;
    Ok((rows, candidates))
}

/// `factorization_bits_ceiling_{c}.png`: the output RMS against texel bits at ceiling
/// `c`, per method and shown resolution (16², 64², 256²).
fn plot_bits(
    out: &Path,
    brdf: &dyn Brdf,
    cfg: &FactorSweep,
    rows: &[FactorRow],
    c: f64,
) -> Result<(), String> {
    let series = |method: &str, n: u32| Series {
        label: format!("{method} {n}²"),
        points: rows
            .iter()
            .filter(|r| r.method == method && r.resolution == n && r.ceiling == c)
            .map(|r| (r.texel_bits as f64, r.hw_rms.max(1e-3)))
            .collect(),
        axis: Axis::Left,
    };
    let mut spec = PlotSpec::new(
        &format!("{}, ceiling {c}: error vs texel bits", brdf.name()),
        "texel bits",
        "RMS error (8-bit levels)",
    );
    spec.log_y = true;
    let shown: Vec<u32> = cfg
        .resolutions
        .iter()
        .copied()
        .filter(|n| [16, 64, 256].contains(n))
        .collect();
    let mut s = Vec::new();
    for m in [FactorMethod::Svd, FactorMethod::Homomorphic] {
        for &n in &shown {
            s.push(series(m.name(), n));
        }
    }
    plot_nonempty(
        &out.join(format!("factorization_bits_ceiling_{c}.png")),
        &spec,
        s,
    )
}

/// `factorization_resolution_ceiling_{c}.png`: the f64 factors' and the 8-bit output's
/// max and RMS errors against the resolution at 8-bit texels, ceiling `c`, per method.
fn plot_resolution(out: &Path, brdf: &dyn Brdf, rows: &[FactorRow], c: f64) -> Result<(), String> {
    let by_res = |method: &str, what: &str| Series {
        label: format!("{method} {what}"),
        points: rows
            .iter()
            .filter(|r| r.method == method && r.texel_bits == 8 && r.ceiling == c)
            .map(|r| {
                let v = match what {
                    "f64 max" => r.f64_max,
                    "8-bit max" => r.hw_max,
                    "f64 RMS" => r.f64_rms,
                    _ => r.hw_rms,
                };
                (r.resolution as f64, v.max(1e-3))
            })
            .collect(),
        axis: Axis::Left,
    };
    let mut spec = PlotSpec::new(
        &format!(
            "{}, ceiling {c}: error vs resolution (8-bit texels)",
            brdf.name()
        ),
        "texture resolution N (N × N texels per factor)",
        "error (8-bit levels)",
    );
    spec.log_x = true;
    spec.log_y = true;
    let mut s = Vec::new();
    for m in [FactorMethod::Svd, FactorMethod::Homomorphic] {
        for what in ["f64 max", "8-bit max", "f64 RMS", "8-bit RMS"] {
            s.push(by_res(m.name(), what));
        }
    }
    plot_nonempty(
        &out.join(format!("factorization_resolution_ceiling_{c}.png")),
        &spec,
        s,
    )
}

/// `factorization_spheres.png`: per method, the ceiling whose 8-bit output is best
/// (lowest RMS) at [`SHOW`]: the reference, the reconstruction, and |Δ| × 8 of the f64
/// factors and of the 8-bit output (nothing written without candidates).
fn sphere_panels(
    out: &Path,
    cfg: &FactorSweep,
    imgs: &SphereImages,
    candidates: &[SphereCandidate],
) -> Result<(), String> {
    let size = cfg.view.size;
    let diff8 = |a: &[f64]| -> Vec<f64> {
        a.iter()
            .zip(&imgs.reference)
            .map(|(h, r)| (h - r).abs() * 8.0)
            .collect()
    };
    let mut panels: Vec<(String, RgbaImage)> = Vec::new();
    let mut spheres: Vec<&SphereCandidate> = Vec::new();
    for m in [FactorMethod::Svd, FactorMethod::Homomorphic] {
        if let Some(c) = candidates
            .iter()
            .filter(|c| c.0 == m.name())
            .min_by(|a, b| a.2.total_cmp(&b.2))
        {
            spheres.push(c);
        }
    }
    for (m, ceiling, _, hw, fl) in spheres {
        let m = format!("{m} (ceiling {ceiling})");
        panels.push(("f64 reference".to_string(), gray(&imgs.reference, size)));
        panels.push((format!("{m} {}² × {} bits", SHOW.0, SHOW.1), gray(hw, size)));
        panels.push((format!("{m} f64 factors |Δ| × 8"), gray(&diff8(fl), size)));
        panels.push((
            format!("{m} {} bits |Δ| × 8", SHOW.1),
            gray(&diff8(hw), size),
        ));
    }
    let refs: Vec<(&str, &RgbaImage)> = panels.iter().map(|(c, i)| (c.as_str(), i)).collect();
    if !refs.is_empty() {
        image_grid(&out.join("factorization_spheres.png"), &refs, 4)?;
    }
    Ok(())
}

/// The summary's lines: the sweep's header, then per method its verdict, its lowest
/// output RMS and its smallest table within 2 levels mean.
fn summary_lines(brdf: &dyn Brdf, cfg: &FactorSweep, rows: &[FactorRow]) -> Vec<String> {
    let mut summary = vec![format!(
        "{} ({}; E = {}; {} covered pixels)",
        brdf.name(),
        cfg.target.name(),
        cfg.view.irradiance,
        rows.first().map_or(0, |r| r.pixels)
    )];
    for m in [FactorMethod::Svd, FactorMethod::Homomorphic] {
        summary.push(verdict(rows, m.name()));
        let mine = || rows.iter().filter(|r| r.method == m.name());
        if let Some(r) = mine().min_by(|a, b| a.hw_rms.total_cmp(&b.hw_rms)) {
            summary.push(format!(
                "{}: lowest output RMS {:.2} levels (mean {:.2}, max {:.1}) at {}×{}, {} bits, ceiling {} — f64 factors there: RMS {:.2}",
                m.name(), r.hw_rms, r.hw_mean, r.hw_max, r.resolution, r.resolution, r.texel_bits, r.ceiling, r.f64_rms
            ));
        }
        if let Some(r) = mine()
            .filter(|r| r.hw_mean <= 2.0)
            .min_by_key(|r| (r.table_bits, r.resolution, r.texel_bits))
        {
            summary.push(format!(
                "{}: smallest table within 2 levels mean: {}×{}, {} bits ({} bits, ceiling {}): mean {:.2}, RMS {:.2}",
                m.name(), r.resolution, r.resolution, r.texel_bits, r.table_bits, r.ceiling, r.hw_mean, r.hw_rms
            ));
        }
    }
    summary
}
