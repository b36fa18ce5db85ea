//! Two studies behind docs/envmap.md's readings of Table 5:
//!
//! - [`lambda_sweep`] (`reproduce envmap-lambda-sweep`): the pattern's error against
//!   the Phong truth at eight λ from 1 to 0.125, with 8-bit and 16-bit voxels, split
//!   into the part the map can be blamed for (against the truth without the cos φ
//!   test) and the rim part (the cos φ test). It shows which terms do not depend on λ
//!   and hide the λ trend at λ ≥ 0.5 on this smooth environment.
//! - [`roughness`] (`reproduce envmap-roughness`): the thesis' proposed fix, λ per
//!   pixel from a roughness texture against λ per vertex, on the 128³ map.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use super::prefilter::{build_exact_bits, env_to_levels};
use super::render::{
    render_against, render_object_with, LambdaSpec, Object, RenderOptions,
    DEFAULT_LAMBDA_TEXTURE_SIDE,
};
use super::reproduce::{grid, RenderRun};
use super::roughness_comparison::{
    roughness_comparison, roughness_comparison_images, RoughnessRow,
};
use crate::reference::envmap_prefilter::PrefilterParams;

/// The λ of the sweep: Table 5's four and the steps between, down to 0.125.
pub const SWEEP_LAMBDAS: [f64; 8] = [1.0, 0.875, 0.75, 0.625, 0.5, 0.375, 0.25, 0.125];
/// Voxel entry widths compared: the thesis' 8 bits and 16 bits (rounding noise ~0).
pub const SWEEP_BITS: [u32; 2] = [8, 16];

/// One row of `lambda_sweep.csv` (mean |Δ| per channel, 8-bit levels).
#[derive(Clone, Debug, PartialEq)]
pub struct SweepRow {
    pub object: Object,
    pub voxel_bits: u32,
    pub lambda: f64,
    /// Against the truth with the cos φ test (Table 5's).
    pub cos_phi: [f64; 3],
    /// Against the truth without it (eq. 3: the map's own error).
    pub simplified: [f64; 3],
    pub pixels: usize,
    pub back_normal_pixels: usize,
}

impl SweepRow {
    pub const CSV_HEADER: &'static str = "object,voxel_bits,lambda,pixels,cos_phi_mean_r,cos_phi_mean_g,cos_phi_mean_b,simplified_mean_r,simplified_mean_g,simplified_mean_b,rim_term_mean,back_normal_pixels";

    /// Mean over the three channels of the cos φ error minus the simplified one: what
    /// the cos φ test adds (the rim).
    pub fn rim_term(&self) -> f64 {
        (0..3)
            .map(|c| self.cos_phi[c] - self.simplified[c])
            .sum::<f64>()
            / 3.0
    }

    pub fn to_csv(&self) -> String {
        let (c, s) = (self.cos_phi, self.simplified);
        format!(
            "{},{},{},{},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{}",
            self.object.name(),
            self.voxel_bits,
            self.lambda,
            self.pixels,
            c[0],
            c[1],
            c[2],
            s[0],
            s[1],
            s[2],
            self.rim_term(),
            self.back_normal_pixels
        )
    }
}

/// `reproduce envmap-lambda-sweep`: the pattern (512 × 256), exact s³ maps with 8-bit
/// and 16-bit voxels, sphere and teapot at `run.size`² for every λ in
/// [`SWEEP_LAMBDAS`] (uniform). The truth is made once per (object, λ) and shared by
/// both maps. Writes `DIR/lambda_sweep.csv` ([`SweepRow::CSV_HEADER`]). Returns the rows.
pub fn lambda_sweep(out: &Path, run: RenderRun) -> Result<Vec<SweepRow>, String> {
    lambda_sweep_resumable(out, run, false)
}

/// A (object, λ) case's rows as the journal keeps them, one per map: (voxel bits,
/// cos φ mean, simplified mean, pixels, back-normal pixels).
type SweepItem = Vec<(u32, [f64; 3], [f64; 3], usize, usize)>;

/// [`lambda_sweep`], saving each (object, λ) case's rows as it finishes to
/// `DIR/envmap-lambda-sweep.resume.jsonl`; with `resume`, those of an interrupted run
/// of the same sizes are kept and only the others rendered (`report::items`; the maps
/// are built only while a case is left).
pub fn lambda_sweep_resumable(
    out: &Path,
    run: RenderRun,
    resume: bool,
) -> Result<Vec<SweepRow>, String> {
    let e = |x: rtl_model::ConfigError| x.to_string();
    let env = super::reproduce::cli_env("pattern")?;
    let objects = [Object::Sphere, Object::Teapot];
    let journal = crate::report::items::ItemJournal::<SweepItem>::open(
        out,
        "envmap-lambda-sweep",
        &[
            (
                "ENVMAP_PATTERN_SIZE",
                format!("{}x{}", env.width(), env.height()),
            ),
            ("ENVMAP_TABLE3_S", run.s.to_string()),
            ("ENVMAP_IMAGE_SIZE", run.size.to_string()),
        ],
        objects.len() * SWEEP_LAMBDAS.len(),
        resume,
    )?;
    let key = |object: Object, lambda: f64| format!("{}/lambda={lambda}", object.name());
    let left = objects
        .iter()
        .any(|&o| SWEEP_LAMBDAS.iter().any(|&l| !journal.has(&key(o, l))));
    let mut maps = Vec::new();
    if left {
        let levels = env_to_levels(&env, env.auto_exposure()).map_err(e)?;
        let params = PrefilterParams::thesis();
        for bits in SWEEP_BITS {
            let t0 = Instant::now();
            maps.push((
                bits,
                build_exact_bits(&levels, run.s, &params, bits).map_err(e)?,
            ));
            eprintln!(
                "pattern: exact {s}³ map, {bits}-bit voxels, {:.1} s",
                t0.elapsed().as_secs_f64(),
                s = run.s
            );
        }
    }
    let opt = RenderOptions::default();
    let size = (run.size, run.size);
    let mut rows = Vec::new();
    for object in objects {
        for lambda in SWEEP_LAMBDAS {
            let item = journal.item(&key(object, lambda), || {
                let spec = LambdaSpec::Uniform(lambda);
                let first_map = &maps.first().ok_or("internal: no maps")?.1;
                // The first map's render makes the truth; the others reuse it.
                let (_, truth, first) =
                    render_object_with(&env, first_map, object, spec, size, &opt).map_err(e)?;
                let mut item = SweepItem::new();
                for (k, (bits, map)) in maps.iter().enumerate() {
                    let st = if k == 0 {
                        first.clone()
                    } else {
                        render_against(&env, map, object, spec, size, &opt, &truth)
                            .map_err(e)?
                            .1
                    };
                    item.push((
                        *bits,
                        st.cos_phi.mean,
                        st.simplified.mean,
                        st.cos_phi.pixels,
                        st.back_normal_pixels,
                    ));
                }
                Ok(item)
            })?;
            for (bits, cos_phi, simplified, pixels, back_normal_pixels) in item {
                let row = SweepRow {
                    object,
                    voxel_bits: bits,
                    lambda,
                    cos_phi,
                    simplified,
                    pixels,
                    back_normal_pixels,
                };
                eprintln!("{}", row.to_csv());
                rows.push(row);
            }
        }
    }
    journal.finish()?;
    let mut csv = format!("{}\n", SweepRow::CSV_HEADER);
    for r in &rows {
        let _ = writeln!(csv, "{}", r.to_csv());
    }
    crate::report::image_out::write_file(&out.join("lambda_sweep.csv"), csv.as_bytes())?;
    print!("{csv}");
    Ok(rows)
}

/// `reproduce envmap-roughness`: the pattern's exact s³ map (8-bit), sphere and teapot
/// with the thesis' non-uniform λ at `run.size`², λ per vertex against λ from a
/// [`DEFAULT_LAMBDA_TEXTURE_SIDE`]² roughness texture, both against the truth at the
/// intended λ ([`roughness_comparison`]). Writes `DIR/roughness.csv`
/// ([`RoughnessRow::CSV_HEADER`]) and `DIR/roughness_sphere.png` (per vertex, texture,
/// intended truth; then |Δ| × 8 of each against that truth). Returns the rows.
pub fn roughness(out: &Path, run: RenderRun) -> Result<Vec<RoughnessRow>, String> {
    roughness_resumable(out, run, false)
}

/// [`roughness`], saving the sphere's rows (its figure written first) and the
/// teapot's as each finishes to `DIR/envmap-roughness.resume.jsonl`; with `resume`,
/// those of an interrupted run of the same sizes are kept (`report::items`; the map is
/// built only while one is left).
pub fn roughness_resumable(
    out: &Path,
    run: RenderRun,
    resume: bool,
) -> Result<Vec<RoughnessRow>, String> {
    let e = |x: rtl_model::ConfigError| x.to_string();
    let env = super::reproduce::cli_env("pattern")?;
    let journal = crate::report::items::ItemJournal::<Vec<RoughnessRow>>::open(
        out,
        "envmap-roughness",
        &[
            (
                "ENVMAP_PATTERN_SIZE",
                format!("{}x{}", env.width(), env.height()),
            ),
            ("ENVMAP_TABLE3_S", run.s.to_string()),
            ("ENVMAP_IMAGE_SIZE", run.size.to_string()),
        ],
        2,
        resume,
    )?;
    let map = if journal.has_all(["sphere", "teapot"]) {
        None
    } else {
        let levels = env_to_levels(&env, env.auto_exposure()).map_err(e)?;
        Some(build_exact_bits(&levels, run.s, &PrefilterParams::thesis(), 8).map_err(e)?)
    };
    let size = (run.size, run.size);
    let side = DEFAULT_LAMBDA_TEXTURE_SIDE;
    let mut rows = journal.item("sphere", || {
        let map = map.as_ref().ok_or("internal: no map")?;
        // The sphere's renders and truth are kept for the figure (no second render).
        let sphere =
            roughness_comparison_images(&env, map, Object::Sphere, size, side).map_err(e)?;
        let (imgs, truth) = (sphere.images, sphere.truth);
        let d: Vec<_> = imgs.iter().map(|i| i.diff(&truth, 8.0)).collect();
        let blank = truth.diff(&truth, 0.0);
        grid(
            &out.join("roughness_sphere.png"),
            &[
                ("λ per vertex".to_string(), &imgs[0]),
                (format!("λ from a {side}² texture"), &imgs[1]),
                ("truth at the intended λ".to_string(), &truth),
                ("|Δ| × 8, per vertex".to_string(), &d[0]),
                ("|Δ| × 8, texture".to_string(), &d[1]),
                (String::new(), &blank),
            ],
            3,
        )?;
        Ok(sphere.rows)
    })?;
    rows.extend(journal.item("teapot", || {
        let map = map.as_ref().ok_or("internal: no map")?;
        roughness_comparison(&env, map, Object::Teapot, size, side).map_err(e)
    })?);
    journal.finish()?;
    let mut csv = format!("{}\n", RoughnessRow::CSV_HEADER);
    for r in &rows {
        let _ = writeln!(csv, "{}", r.to_csv());
    }
    crate::report::image_out::write_file(&out.join("roughness.csv"), csv.as_bytes())?;
    print!("{csv}");
    Ok(rows)
}
