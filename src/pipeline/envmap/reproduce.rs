//! `reproduce envmap-table3`, `envmap-table5`, `envmap-images`.
//!
//! **Table 5 and the figures** ([`table5`], [`images`]; the thesis §4.3): renders of
//! the sphere and the teapot through the units with the 128³ maps built here
//! ([`build_exact`], [`build_accelerated`] at th = 0.001) from the environment at its
//! auto exposure — the renderer's default exposure, so the map and the Phong truth see
//! the same 256-level input. See the functions for the files written.
//!
//! **Table 3**: the thesis' Table 3 (voxel error of the accelerated build
//! against the exact one, per threshold th) and Table 4's table sizes and times.
//!
//! For env ∈ {pattern (512 × 256, exposure 1 = its auto exposure), st_fagans_interior
//! (auto exposure)}: the exact map at side s (timed), then for each th in [`THESIS_TH`]
//! the accelerated map and its error against the exact one. Writes
//! `DIR/table3.csv` (`env,th,mean_r,mean_g,mean_b,var_r,var_g,var_b,build_seconds,
//! table_mbytes`: mean |Δ| and variance of Δ in levels over all s³ voxels),
//! `DIR/table3_extra.csv` (entries, empty voxels, and the same errors with each
//! voxel's kept weights renormalised) and `DIR/prefilter_times.csv`.
//! The CLI uses s = 128 (the thesis); the environment variable `ENVMAP_TABLE3_S`
//! overrides it (up to `scene::environment::MAX_SIDE`, 256), and `ENVMAP_TABLE3_TH`
//! (a comma list) runs only those thresholds.
//!
//! Measured (release, 2 cores shared, s = 128; mean |Δ| (r, g, b) in levels, build s,
//! table MB at 8 bytes per entry):
//!
//! | th | pattern | st_fagans_interior | MB | empty voxels |
//! |---|---|---|---|---|
//! | 0.001 | 0.25 0.27 0.27 | 0.85 0.83 0.79 | 118.7 | 0 |
//! | 0.005 | 1.31 1.33 1.33 | 0.96 0.90 0.83 | 91.0 | 744 |
//! | 0.01 | 2.85 2.85 2.85 | 1.22 1.07 0.91 | 79.1 | 3 696 |
//! | 0.05 | 15.4 15.4 15.4 | 3.58 2.82 1.88 | 51.5 | 50 088 |
//! | 0.1 | 30.7 30.7 30.7 | 6.57 5.07 3.19 | 39.6 | 138 216 |
//! | 0.25 | 70.7 70.7 70.7 | 14.5 11.2 6.85 | 23.6 | 486 048 |
//! | 0.5 | 120 120 120 | 24.4 18.8 11.4 | 11.9 | 1 061 280 |
//!
//! Exact 128³: 7.7 s (pattern), 14.7 s (st_fagans); accelerated 4–9 s per th (the
//! whole build: pyramid, domes, table, filter). The thesis: 73 h exact, 21 h table,
//! 459 → 32.7 MB; its errors fall again at th = 0.25, 0.5 (54 → 34 levels), ours keep
//! growing (empty voxels give F = 0 here; the thesis does not say what it stored).

use super::prefilter::{
    build_accelerated, build_accelerated_both, build_exact, env_to_levels, prune_bound, voxel_error,
};
use super::render::{
    render_against, render_frame, render_image, render_object_with, upload_textures, Image,
    LambdaSpec, Lookup, Object, RenderOptions,
};
use super::table5::{Table5Row, TABLE5_LAMBDAS};
use super::timing::{predict_frame, TimingRow};
use super::voxmap::VoxelMap;
use crate::chip::GpuModel;
use crate::reference::envmap_prefilter::PrefilterParams;
use crate::scene::envmap::EnvMap;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

/// The thesis' thresholds (Table 3).
pub const THESIS_TH: [f64; 7] = [0.001, 0.005, 0.01, 0.05, 0.1, 0.25, 0.5];

/// A built-in environment as the CLI's reproductions load it: the pattern at
/// `ENVMAP_PATTERN_SIZE` (`WIDTHxHEIGHT`, e.g. `1024x512`, each side 2 ..= 4096) if set,
/// else at the thesis' 512 × 256; the photos as embedded. The size is the input's
/// resolution knob (docs/envmap.md, Table 5: the pattern's error against λ·s).
pub fn cli_env(name: &str) -> Result<EnvMap, String> {
    let e = |x: rtl_model::ConfigError| x.to_string();
    match (name, std::env::var("ENVMAP_PATTERN_SIZE")) {
        ("pattern", Ok(v)) => {
            let (w, h) = parse_size(&v).ok_or_else(|| {
                format!(
                    "ENVMAP_PATTERN_SIZE: '{v}' is not WIDTHxHEIGHT with each side in 2 ..= 4096"
                )
            })?;
            Ok(EnvMap::pattern(w, h))
        }
        _ => EnvMap::builtin(name).map_err(e),
    }
}

fn parse_size(v: &str) -> Option<(usize, usize)> {
    let (w, h) = v.trim().split_once(['x', 'X'])?;
    let (w, h) = (
        w.trim().parse::<usize>().ok()?,
        h.trim().parse::<usize>().ok()?,
    );
    ((2..=4096).contains(&w) && (2..=4096).contains(&h)).then_some((w, h))
}

/// The side used by the CLI: `ENVMAP_TABLE3_S` if set, else 128. The side must be
/// what a scene's `environment.side` may be (a power of two in
/// `MIN_SIDE ..= MAX_SIDE`: the reflection_vector unit needs a power of two), checked
/// here before any build, not after the prefilter has run.
pub fn cli_side() -> Result<u32, String> {
    use crate::scene::environment::{MAX_SIDE, MIN_SIDE};
    match std::env::var("ENVMAP_TABLE3_S") {
        Ok(v) => match v.trim().parse::<u32>() {
            Ok(s) if (MIN_SIDE..=MAX_SIDE).contains(&s) && s.is_power_of_two() => Ok(s),
            Ok(s) if s > MAX_SIDE => Err(format!(
                "ENVMAP_TABLE3_S: {s} is beyond the largest supported side {MAX_SIDE} ({MAX_SIDE}³ is the largest cube the 3D texture sampler's 2^24-texel address holds; docs/envmap.md, \"Map side\")"
            )),
            _ => Err(format!(
                "ENVMAP_TABLE3_S: '{v}' is not a power of two in {MIN_SIDE} ..= {MAX_SIDE} (the reflection_vector unit needs a power-of-two side)"
            )),
        },
        Err(_) => Ok(128),
    }
}

/// The thresholds of a Table 3 run: `ENVMAP_TABLE3_TH` (a comma list, each in
/// [0, 1)) if set, else [`THESIS_TH`] — one th keeps a run at s = 256 to minutes.
/// Checked before any build.
pub fn cli_thresholds() -> Result<Vec<f64>, String> {
    let Ok(v) = std::env::var("ENVMAP_TABLE3_TH") else {
        return Ok(THESIS_TH.to_vec());
    };
    v.split(',')
        .map(|x| match x.trim().parse::<f64>() {
            Ok(th) if (0.0..1.0).contains(&th) => Ok(th),
            _ => Err(format!(
                "ENVMAP_TABLE3_TH: '{v}' is not a comma list of thresholds in [0, 1)"
            )),
        })
        .collect()
}

/// Run Table 3 at voxel side `s` into `out` (see the module doc).
pub fn table3(out: &Path, s: u32) -> Result<(), String> {
    table3_at(out, s, &THESIS_TH, false)
}

/// What the rows of an environment-map reproduction depend on besides its own sizes:
/// the pattern's resolution (`ENVMAP_PATTERN_SIZE` as resolved), for its journal
/// (`report::items`).
fn journal_settings(
    more: &[(&'static str, String)],
) -> Result<Vec<(&'static str, String)>, String> {
    let p = cli_env("pattern")?;
    let mut v = vec![(
        "ENVMAP_PATTERN_SIZE",
        format!("{}x{}", p.width(), p.height()),
    )];
    v.extend_from_slice(more);
    Ok(v)
}

/// [`table3`] at the thresholds `ths`. Each environment's exact build (its
/// `prefilter_times.csv` line) and each (environment, th) row is saved as it finishes
/// to `DIR/envmap-table3.resume.jsonl`; with `resume`, those of an interrupted run of
/// the same side, thresholds and pattern are kept and only the others built
/// (`report::items`; an environment whose rows are all saved is not built at all).
pub fn table3_at(out: &Path, s: u32, ths: &[f64], resume: bool) -> Result<(), String> {
    let e = |x: rtl_model::ConfigError| x.to_string();
    let params = PrefilterParams::thesis();
    let mut t3 =
        String::from("env,th,mean_r,mean_g,mean_b,var_r,var_g,var_b,build_seconds,table_mbytes\n");
    let mut extra = String::from(
        "env,th,entries,entries_per_voxel,empty_voxels,renorm_mean_r,renorm_mean_g,renorm_mean_b,renorm_var_r,renorm_var_g,renorm_var_b\n",
    );
    let mut times = String::from("env,s,exact_seconds,exposure,prune_bound,threads\n");
    let names = ["pattern", "st_fagans_interior"];
    let list = ths.iter().map(|th| th.to_string()).collect::<Vec<_>>();
    let journal = crate::report::items::ItemJournal::<Vec<String>>::open(
        out,
        "envmap-table3",
        &journal_settings(&[
            ("ENVMAP_TABLE3_S", s.to_string()),
            ("ENVMAP_TABLE3_TH", list.join(",")),
        ])?,
        names.len() * (1 + ths.len()),
        resume,
    )?;
    for name in names {
        let exact_key = format!("{name}/exact");
        let keys: Vec<String> = ths.iter().map(|th| format!("{name}/th={th}")).collect();
        // The exact map, built only while a row of this environment is left.
        let mut built = None;
        if !journal.has(&exact_key) || !journal.has_all(keys.iter().map(String::as_str)) {
            let env = cli_env(name)?;
            let exposure = env.auto_exposure();
            let levels = env_to_levels(&env, exposure).map_err(e)?;
            let t0 = Instant::now();
            let exact = build_exact(&levels, s, &params).map_err(e)?;
            let exact_s = t0.elapsed().as_secs_f64();
            eprintln!("{name}: exact {s}³ in {exact_s:.1} s");
            journal.item(&exact_key, || {
                Ok(vec![format!(
                    "{name},{s},{exact_s:.3},{exposure:.6e},{:.3e},{}",
                    prune_bound(&levels, params.weighting()),
                    rayon::current_num_threads()
                )])
            })?;
            built = Some((levels, exact));
        }
        let line = journal.item(&exact_key, || Err("internal: no exact build".into()))?;
        let _ = writeln!(times, "{}", line[0]);
        for (&th, key) in ths.iter().zip(&keys) {
            let lines = journal.item(key, || {
                let (levels, exact) = built.as_ref().ok_or("internal: no exact map")?;
                let (acc, ren, st) = build_accelerated_both(levels, s, &params, th).map_err(e)?;
                let (mean, var) = voxel_error(&acc, exact).ok_or("internal: side mismatch")?;
                let (rmean, rvar) = voxel_error(&ren, exact).ok_or("internal: side mismatch")?;
                eprintln!(
                    "{name} th={th}: mean |Δ| {:.3} {:.3} {:.3}, {:.1} s, {:.1} MB, {} empty",
                    mean[0],
                    mean[1],
                    mean[2],
                    st.build_seconds,
                    st.mbytes(),
                    st.empty_voxels
                );
                Ok(vec![
                    format!(
                        "{name},{th},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.3},{:.2}",
                        mean[0],
                        mean[1],
                        mean[2],
                        var[0],
                        var[1],
                        var[2],
                        st.build_seconds,
                        st.mbytes()
                    ),
                    format!(
                        "{name},{th},{},{:.2},{},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4}",
                        st.entries,
                        st.entries as f64 / (s as f64).powi(3),
                        st.empty_voxels,
                        rmean[0],
                        rmean[1],
                        rmean[2],
                        rvar[0],
                        rvar[1],
                        rvar[2]
                    ),
                ])
            })?;
            let _ = writeln!(t3, "{}", lines[0]);
            let _ = writeln!(extra, "{}", lines[1]);
        }
    }
    journal.finish()?;
    crate::report::image_out::write_file(&out.join("table3.csv"), t3.as_bytes())?;
    crate::report::image_out::write_file(&out.join("table3_extra.csv"), extra.as_bytes())?;
    crate::report::image_out::write_file(&out.join("prefilter_times.csv"), times.as_bytes())?;
    print!("{t3}");
    Ok(())
}

// ---------------------------------------------------------------------------------
// Table 5, Figs. 14–17, 20, 21: renders against the Phong truth.

/// The accelerated map's threshold for Table 5 and the figures (the thesis' choice).
pub const TABLE5_TH: f64 = crate::scene::environment::THESIS_THRESHOLD;
/// Gain of the difference images (|Δ| × 8: 32 levels → white).
pub const DIFF_GAIN: f64 = 8.0;
/// The environments of Table 5 and the figures: the thesis' Fig. 13(a) and a photo
/// (standing for Fig. 13(b)).
pub const TABLE5_ENVS: [&str; 2] = ["pattern", "st_fagans_interior"];

/// Sizes of a Table 5 / images run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RenderRun {
    /// Voxel side s (the thesis: 128).
    pub s: u32,
    /// Image width and height (square).
    pub size: u32,
}

/// `reproduce --image NxN`: the image side for this process, set once before any
/// [`RenderRun::cli`]; it wins over `$ENVMAP_IMAGE_SIZE`.
static IMAGE_SIDE: std::sync::OnceLock<u32> = std::sync::OnceLock::new();

/// The reproductions whose image size `--image` (or `$ENVMAP_IMAGE_SIZE`) sets.
pub const IMAGE_REPRODUCTIONS: &[&str] = &[
    "envmap-table5",
    "envmap-images",
    "envmap-lambda-sweep",
    "envmap-roughness",
];

/// `reproduce --image`: a square size, 8 ..= 1024 on a side (errors name `--image`),
/// used by every later [`RenderRun::cli`] of this process instead of
/// `$ENVMAP_IMAGE_SIZE`.
pub fn set_image_side(text: &str) -> Result<u32, String> {
    let side = crate::report::image_arg::parse_image(text).and_then(|(w, h)| {
        if w != h {
            return Err(format!(
                "--image: {w}x{h} is not square; these reproductions render square images (e.g. {w}x{w})"
            ));
        }
        if !(8..=1024).contains(&w) {
            return Err(format!("--image: {w}x{h}: each side must be in 8 ..= 1024"));
        }
        Ok(w)
    })?;
    let _ = IMAGE_SIDE.set(side);
    Ok(side)
}

impl RenderRun {
    /// The CLI's: s = 128 (or `ENVMAP_TABLE3_S`), 256 × 256 (or `reproduce --image`,
    /// else `ENVMAP_IMAGE_SIZE`, 8 ..= 1024).
    pub fn cli() -> Result<Self, String> {
        if let Some(&size) = IMAGE_SIDE.get() {
            return Ok(RenderRun {
                s: cli_side()?,
                size,
            });
        }
        let size = match std::env::var("ENVMAP_IMAGE_SIZE") {
            Ok(v) => match v.trim().parse::<u32>() {
                Ok(n) if (8..=1024).contains(&n) => n,
                _ => return Err(format!("ENVMAP_IMAGE_SIZE: '{v}' is not in 8 ..= 1024")),
            },
            Err(_) => 256,
        };
        Ok(RenderRun {
            s: cli_side()?,
            size,
        })
    }
}

fn rgba(img: &Image) -> image::RgbaImage {
    let mut out = image::RgbaImage::new(img.width, img.height);
    for (x, y, p) in out.enumerate_pixels_mut() {
        let c = img.get(x, y);
        *p = image::Rgba([c[0], c[1], c[2], 255]);
    }
    out
}

pub(crate) fn grid(path: &Path, panels: &[(String, &Image)], columns: usize) -> Result<(), String> {
    let imgs: Vec<(String, image::RgbaImage)> =
        panels.iter().map(|(c, i)| (c.clone(), rgba(i))).collect();
    let refs: Vec<(&str, &image::RgbaImage)> = imgs.iter().map(|(c, i)| (c.as_str(), i)).collect();
    crate::report::plot::image_grid(path, &refs, columns)
}

/// The exact and accelerated (th = [`TABLE5_TH`]) maps of `env` at its auto exposure
/// (the renderer's default exposure: the same levels as the truth), with build times.
fn both_maps(env: &EnvMap, s: u32) -> Result<(VoxelMap, VoxelMap, f64, f64), String> {
    let e = |x: rtl_model::ConfigError| x.to_string();
    let params = PrefilterParams::thesis();
    let levels = env_to_levels(env, env.auto_exposure()).map_err(e)?;
    let t0 = Instant::now();
    let exact = build_exact(&levels, s, &params).map_err(e)?;
    let t_exact = t0.elapsed().as_secs_f64();
    let (acc, st) = build_accelerated(&levels, s, &params, TABLE5_TH).map_err(e)?;
    Ok((exact, acc, t_exact, st.build_seconds))
}

/// `reproduce envmap-table5`: for env ∈ [`TABLE5_ENVS`], object ∈ {sphere, teapot}, λ ∈
/// [`TABLE5_LAMBDAS`], the render with the exact and the accelerated (th = 0.001) map
/// against the Phong truth with the cos φ test (mean |Δ| and variance of |Δ| over the
/// object's pixels, 8-bit levels). The truth is computed once per (env, object, λ) and
/// shared by both maps. Writes `DIR/table5.csv` (`object,env,lambda,accelerated,
/// mean_r,mean_g,mean_b,var_r,var_g,var_b`), `DIR/table5_extra.csv` (the same against
/// the truth without the cos φ test, the signed mean, the largest |Δ| and the pixel
/// counts), `DIR/table5_times.csv`, and the difference figures `DIR/fig20.png`
/// (pattern, sphere, λ = 0.5) and `DIR/fig21.png` (photo, teapot, non-uniform λ):
/// (a) truth, (b) exact, (c) |a − b| × 8, (d) accelerated, (e) |a − d| × 8.
/// Returns the rows.
pub fn table5(out: &Path, run: RenderRun) -> Result<Vec<Table5Row>, String> {
    table5_resumable(out, run, false)
}

/// [`table5`], saving each (env, object, λ) case (its two rows, their extra lines and
/// its figure, written first) and each environment's times line as it finishes to
/// `DIR/envmap-table5.resume.jsonl`; with `resume`, those of an interrupted run of the
/// same sizes are kept and only the others rendered (`report::items`; an environment
/// whose times line is saved is not built again).
pub fn table5_resumable(
    out: &Path,
    run: RenderRun,
    resume: bool,
) -> Result<Vec<Table5Row>, String> {
    let size = (run.size, run.size);
    let mut rows = Vec::new();
    let mut extra = String::from(
        "object,env,lambda,accelerated,pixels,simplified_mean_r,simplified_mean_g,simplified_mean_b,signed_mean_r,signed_mean_g,signed_mean_b,max_r,max_g,max_b,back_normal_pixels\n",
    );
    let mut times = String::from(
        "env,env_width,env_height,s,size,exact_build_seconds,accelerated_build_seconds,truth_and_render_seconds\n",
    );
    let opt = RenderOptions::default();
    let journal = crate::report::items::ItemJournal::<(Vec<Table5Row>, Vec<String>)>::open(
        out,
        "envmap-table5",
        &journal_settings(&[
            ("ENVMAP_TABLE3_S", run.s.to_string()),
            ("ENVMAP_IMAGE_SIZE", run.size.to_string()),
        ])?,
        TABLE5_ENVS.len() * (1 + 2 * TABLE5_LAMBDAS.len()),
        resume,
    )?;
    for name in TABLE5_ENVS {
        let times_key = format!("{name}/times");
        // The maps, built only while this environment has work left.
        let mut maps = None;
        if !journal.has(&times_key) {
            let env = cli_env(name)?;
            let (exact, acc, t_exact, t_acc) = both_maps(&env, run.s)?;
            eprintln!(
                "{name}: maps {s}³ exact {t_exact:.1} s, accelerated {t_acc:.1} s",
                s = run.s
            );
            maps = Some((env, exact, acc, t_exact, t_acc));
        }
        let t0 = Instant::now();
        for object in [Object::Sphere, Object::Teapot] {
            for lambda in TABLE5_LAMBDAS {
                let key = format!("{name}/{}/lambda={}", object.name(), lambda.label());
                let (case_rows, case_extra) = journal.item(&key, || {
                    let maps = maps.as_ref().ok_or("internal: no maps")?;
                    table5_case(out, name, maps, (object, lambda), size, &opt)
                })?;
                rows.extend(case_rows);
                for l in case_extra {
                    let _ = writeln!(extra, "{l}");
                }
            }
        }
        let (_, line) = journal.item(&times_key, || {
            let (env, _, _, t_exact, t_acc) = maps.as_ref().ok_or("internal: no maps")?;
            Ok((
                Vec::new(),
                vec![format!(
                    "{name},{},{},{},{},{t_exact:.3},{t_acc:.3},{:.3}",
                    env.width(),
                    env.height(),
                    run.s,
                    run.size,
                    t0.elapsed().as_secs_f64()
                )],
            ))
        })?;
        let _ = writeln!(times, "{}", line[0]);
    }
    journal.finish()?;
    let mut csv = format!("{}\n", Table5Row::CSV_HEADER);
    for r in &rows {
        let _ = writeln!(csv, "{}", r.to_csv());
    }
    crate::report::image_out::write_file(&out.join("table5.csv"), csv.as_bytes())?;
    crate::report::image_out::write_file(&out.join("table5_extra.csv"), extra.as_bytes())?;
    crate::report::image_out::write_file(&out.join("table5_times.csv"), times.as_bytes())?;
    print!("{csv}");
    Ok(rows)
}

/// An environment's maps for Table 5: the environment, the exact and the accelerated
/// map, and their build times (s).
type Table5Maps = (EnvMap, VoxelMap, VoxelMap, f64, f64);

/// One Table 5 case: `object` at `lambda` under environment `name`, rendered with the
/// exact and the accelerated map against one truth. Returns its two rows (exact,
/// accelerated) and their `table5_extra.csv` lines; writes its figure (Fig. 20 or 21)
/// when it is that case.
fn table5_case(
    out: &Path,
    name: &str,
    (env, exact, acc, _, _): &Table5Maps,
    (object, lambda): (Object, LambdaSpec),
    size: (u32, u32),
    opt: &RenderOptions,
) -> Result<(Vec<Table5Row>, Vec<String>), String> {
    let e = |x: rtl_model::ConfigError| x.to_string();
    let mut rows = Vec::new();
    let mut extra = Vec::new();
    let t1 = Instant::now();
    let (img_e, truth, st_e) =
        render_object_with(env, exact, object, lambda, size, opt).map_err(e)?;
    let (img_a, st_a) = render_against(env, acc, object, lambda, size, opt, &truth).map_err(e)?;
    eprintln!(
        "{name} {} λ={}: {} px, mean |Δ| exact {:.2} {:.2} {:.2}, accelerated {:.2} {:.2} {:.2} ({:.1} s)",
        object.name(),
        lambda.label(),
        st_e.cos_phi.pixels,
        st_e.cos_phi.mean[0],
        st_e.cos_phi.mean[1],
        st_e.cos_phi.mean[2],
        st_a.cos_phi.mean[0],
        st_a.cos_phi.mean[1],
        st_a.cos_phi.mean[2],
        t1.elapsed().as_secs_f64()
    );
    for (accelerated, st) in [(false, &st_e), (true, &st_a)] {
        rows.push(Table5Row {
            object: object.name().to_string(),
            env: name.to_string(),
            lambda: lambda.label(),
            accelerated,
            mean: st.cos_phi.mean,
            var: st.cos_phi.var,
        });
        let (m, sm, mx) = (st.simplified.mean, st.cos_phi.mean_signed, st.cos_phi.max);
        extra.push(format!(
            "{},{name},{},{accelerated},{},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{},{},{},{}",
            object.name(),
            lambda.label(),
            st.cos_phi.pixels,
            m[0],
            m[1],
            m[2],
            sm[0],
            sm[1],
            sm[2],
            mx[0],
            mx[1],
            mx[2],
            st.back_normal_pixels
        ));
    }
    let fig = match (name, object, lambda) {
        ("pattern", Object::Sphere, LambdaSpec::Uniform(0.5)) => Some("fig20.png"),
        ("st_fagans_interior", Object::Teapot, LambdaSpec::NonUniform) => Some("fig21.png"),
        _ => None,
    };
    if let Some(file) = fig {
        let g = format!("×{DIFF_GAIN}");
        let d_e = img_e.diff(&truth.cos_phi, DIFF_GAIN);
        let d_a = img_a.diff(&truth.cos_phi, DIFF_GAIN);
        grid(
            &out.join(file),
            &[
                ("(a) Phong truth".to_string(), &truth.cos_phi),
                ("(b) exact map".to_string(), &img_e),
                (format!("(c) |a − b| {g}"), &d_e),
                (format!("(d) accelerated, th = {TABLE5_TH}"), &img_a),
                (format!("(e) |a − d| {g}"), &d_a),
            ],
            5,
        )?;
    }
    Ok((rows, extra))
}

/// `reproduce envmap-images`: the Figs. 14–17 analogues with the accelerated map (th =
/// [`TABLE5_TH`], the thesis' method): per env ∈ [`TABLE5_ENVS`], sphere and teapot at
/// uniform λ = 1, 0.5, 0.25 (`DIR/fig14_pattern.png`, `DIR/fig16_st_fagans_interior.png`:
/// rows sphere, teapot) and non-uniform λ (`DIR/fig15_pattern.png`,
/// `DIR/fig17_st_fagans_interior.png`: sphere, teapot, and their Phong truths).
/// Returns the files written.
pub fn images(out: &Path, run: RenderRun) -> Result<Vec<std::path::PathBuf>, String> {
    images_resumable(out, run, false)
}

/// [`images`], noting each environment's two figures in
/// `DIR/envmap-images.resume.jsonl` once both are written; with `resume`, the figures
/// of an interrupted run of the same sizes are kept and only the other environment is
/// rendered (`report::items`).
pub fn images_resumable(
    out: &Path,
    run: RenderRun,
    resume: bool,
) -> Result<Vec<std::path::PathBuf>, String> {
    let e = |x: rtl_model::ConfigError| x.to_string();
    let size = (run.size, run.size);
    let opt = RenderOptions::default();
    let mut files = Vec::new();
    let envs = [
        ("pattern", "fig14", "fig15"),
        ("st_fagans_interior", "fig16", "fig17"),
    ];
    let journal = crate::report::items::ItemJournal::<Vec<String>>::open(
        out,
        "envmap-images",
        &journal_settings(&[
            ("ENVMAP_TABLE3_S", run.s.to_string()),
            ("ENVMAP_IMAGE_SIZE", run.size.to_string()),
        ])?,
        envs.len(),
        resume,
    )?;
    for (name, uni, non) in envs {
        let written = journal.item(name, || {
            let env = cli_env(name)?;
            let params = PrefilterParams::thesis();
            let levels = env_to_levels(&env, env.auto_exposure()).map_err(e)?;
            let (acc, st) = build_accelerated(&levels, run.s, &params, TABLE5_TH).map_err(e)?;
            eprintln!(
                "{name}: accelerated {}³ map in {:.1} s",
                run.s, st.build_seconds
            );
            let mut panels: Vec<(String, Image)> = Vec::new();
            for object in [Object::Sphere, Object::Teapot] {
                for l in [1.0, 0.5, 0.25] {
                    let img = render_image(&env, &acc, object, LambdaSpec::Uniform(l), size, &opt)
                        .map_err(e)?;
                    panels.push((format!("{}, λ = {l}", object.name()), img));
                }
            }
            let refs: Vec<(String, &Image)> = panels.iter().map(|(c, i)| (c.clone(), i)).collect();
            let f_uni = format!("{uni}_{name}.png");
            grid(&out.join(&f_uni), &refs, 3)?;
            let mut panels: Vec<(String, Image)> = Vec::new();
            let mut truths: Vec<(String, Image)> = Vec::new();
            for object in [Object::Sphere, Object::Teapot] {
                let (img, truth, _) =
                    render_object_with(&env, &acc, object, LambdaSpec::NonUniform, size, &opt)
                        .map_err(e)?;
                panels.push((format!("{}, non-uniform λ", object.name()), img));
                truths.push((format!("{}, Phong truth", object.name()), truth.cos_phi));
            }
            panels.extend(truths);
            let refs: Vec<(String, &Image)> = panels.iter().map(|(c, i)| (c.clone(), i)).collect();
            let f_non = format!("{non}_{name}.png");
            grid(&out.join(&f_non), &refs, 2)?;
            Ok(vec![f_uni, f_non])
        })?;
        files.extend(written.iter().map(|f| out.join(f)));
    }
    journal.finish()?;
    for f in &files {
        println!("{}", f.display());
    }
    Ok(files)
}

// ---------------------------------------------------------------------------------
// Frame timing (the thesis' Table 6) and the 2D-slice elaboration.

/// The frame size of `reproduce envmap-timing` (the thesis' 640 × 480).
pub const TIMING_SIZE: (u32, u32) = (640, 480);
/// The uniform λ of the 2D-slice rows.
pub const TIMING_SLICE_LAMBDA: f64 = 0.5;

/// `reproduce envmap-timing`: the accelerated (th = [`TABLE5_TH`]) map of side `s` of
/// the pattern environment; sphere and teapot at 640 × 480 with the non-uniform λ (the
/// 3D path: rows `sphere`, `teapot`) and with uniform λ = 0.5 through the 2D slice
/// (`Lookup::Auto`: rows `sphere_slice2d`, `teapot_slice2d`). No truth is computed.
/// `wall_seconds` is the bit-accurate model's render time on this machine (one run,
/// geometry to image, with the map's textures resident as the prediction assumes: they
/// are uploaded first by [`upload_textures`] and that time is printed apart, on
/// stderr); `predicted_seconds_geforce3` is [`predict_frame`] on
/// [`GpuModel::geforce3`]. Writes `DIR/timing.csv`
/// (`object,width,height,fragments,wall_seconds,predicted_seconds_geforce3`) and
/// `DIR/elaboration.txt` (the samplers elaborated and left out, texture bytes).
pub fn timing(out: &Path, s: u32) -> Result<Vec<TimingRow>, String> {
    timing_resumable(out, s, false)
}

/// [`timing`], saving each frame's row and elaboration text as it finishes to
/// `DIR/envmap-timing.resume.jsonl`; with `resume`, those of an interrupted run of the
/// same side are kept and only the other frames rendered (`report::items`; the map is
/// built only while a frame is left).
pub fn timing_resumable(out: &Path, s: u32, resume: bool) -> Result<Vec<TimingRow>, String> {
    let e = |x: rtl_model::ConfigError| x.to_string();
    let env = cli_env("pattern")?;
    let cases = [
        ("", LambdaSpec::NonUniform, Lookup::Voxel3D),
        (
            "_slice2d",
            LambdaSpec::Uniform(TIMING_SLICE_LAMBDA),
            Lookup::Auto,
        ),
    ];
    let objects = [Object::Sphere, Object::Teapot];
    let journal = crate::report::items::ItemJournal::<(TimingRow, String)>::open(
        out,
        "envmap-timing",
        &journal_settings(&[("ENVMAP_TABLE3_S", s.to_string())])?,
        cases.len() * objects.len(),
        resume,
    )?;
    let key = |suffix: &str, object: Object| format!("{}{suffix}", object.name());
    let mut map = None;
    if !cases
        .iter()
        .all(|c| objects.iter().all(|&o| journal.has(&key(c.0, o))))
    {
        let params = PrefilterParams::thesis();
        let levels = env_to_levels(&env, env.auto_exposure()).map_err(e)?;
        let (m, st) = build_accelerated(&levels, s, &params, TABLE5_TH).map_err(e)?;
        eprintln!(
            "pattern: accelerated {s}³ map (th = {TABLE5_TH}) in {:.1} s",
            st.build_seconds
        );
        map = Some(m);
    }
    let gpu = GpuModel::geforce3();
    let mut rows = Vec::new();
    let mut elab = String::new();
    for (suffix, lambda, lookup) in cases {
        for object in objects {
            let (row, text) = journal.item(&key(suffix, object), || {
            let map = map.as_ref().ok_or("internal: no map")?;
            let opt = RenderOptions {
                lookup,
                ..RenderOptions::default()
            };
            // The textures first (kept with the map: the 3D map once, the cube map once
            // per λ), timed apart: the frame below is the render with them resident.
            let t_up = Instant::now();
            upload_textures(map, lambda, &opt).map_err(e)?;
            let up = t_up.elapsed().as_secs_f64();
            let t0 = Instant::now();
            let (_, f) = render_frame(&env, map, object, lambda, TIMING_SIZE, &opt).map_err(e)?;
            let wall = t0.elapsed().as_secs_f64();
            let p = predict_frame(&gpu, &f);
            let name = format!("{}{suffix}", object.name());
            eprintln!(
                "{name}: {} fragments, {} shaded, {} triangles; textures {up:.3} s; wall {wall:.3} s; GeForce3 {:.3} ms (object pass {} bound; {:.2} MB moved)",
                f.fragments,
                f.shaded,
                f.triangles,
                p.seconds * 1e3,
                if p.object_memory_bound() { "memory" } else { "fill" },
                p.bytes / 1e6
            );
            let el = &f.elaboration;
            let text = format!(
                "{name} (λ = {}): texture {} bytes, saved {} bytes, gates saved (3D sampler − 2D sampler − cube_map_address) {:.0}\n{}",
                lambda.label(),
                el.texture_bytes,
                el.texture_bytes_saved,
                el.gates_saved,
                crate::report::table::elaboration_table(&el.units)
            );
            Ok((
                TimingRow {
                    object: name,
                    width: TIMING_SIZE.0,
                    height: TIMING_SIZE.1,
                    fragments: f.fragments,
                    wall_seconds: wall,
                    predicted_seconds_geforce3: p.seconds,
                },
                text,
            ))
            })?;
            let _ = writeln!(elab, "{text}");
            rows.push(row);
        }
    }
    journal.finish()?;
    let mut csv = format!("{}\n", TimingRow::CSV_HEADER);
    for r in &rows {
        let _ = writeln!(csv, "{}", r.to_csv());
    }
    crate::report::image_out::write_file(&out.join("timing.csv"), csv.as_bytes())?;
    crate::report::image_out::write_file(&out.join("elaboration.txt"), elab.as_bytes())?;
    print!("{csv}");
    print!("{elab}");
    Ok(rows)
}
