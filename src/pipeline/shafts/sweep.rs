//! `sweep`: error against run time for one `shafts` parameter (DESIGN §4).
//!
//! Each value is applied to the scene's `shafts` config, the scene is re-validated
//! (all values before anything is rendered or written), then every value is rendered
//! through the bit-accurate units and compared with the scene's f64 ray-marched
//! reference, computed once per sweep (it does not depend on the `shafts` config).
//!
//! Per value: `error_levels` = mean |Δ| over the 10 representative pixels of the
//! reference (as `reproduce shafts-fig4`), `rms_levels` = RMS over the whole image,
//! `predicted_hw_seconds` from the GeForce2 GTS throughput model, `wall_seconds` of the
//! simulation (preparation + frame), and `gates_nand2` = the sum of the gates of the
//! units the frame elaborated (units left out do not count).
//!
//! Output: `DIR/sweep_<param>.csv` and `DIR/sweep_<param>.png`. The CSV is rewritten
//! (atomically) as each row finishes, beside the record `DIR/sweep_<param>.resume.json`
//! of which sweep it is: a run that fails or is stopped keeps its rows, and `--resume`
//! continues from them (`report::resume`).

use super::cli::{reference_image, render_scene};
use super::frame::FrameResult;
use crate::report::csv_out::write_csv;
use crate::report::metrics::{error_stats, error_stats_at, representative_pixels};
use crate::report::plot::{line_plot, Axis, PlotSpec, Series};
use crate::report::progress::progress_bar;
use crate::report::resume::Journal;
use crate::report::shard::{fingerprint, finish_shard, Shard, ShardSet, SweepId};
use crate::report::table::text_table;
use crate::scene::format::{Scene, ShaftsConfig};
use serde::{Deserialize, Serialize};
use std::fmt;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Most values one sweep may have (after ranges are expanded).
pub const MAX_VALUES: usize = 1000;
/// Largest `--truth-samples`.
pub const MAX_TRUTH_SAMPLES: u32 = 100_000;
/// Default `--truth-samples` (the paper's Fig. 4 truth).
pub const DEFAULT_TRUTH_SAMPLES: u32 = 200;
/// Representative pixels of `error_levels`.
pub const REPRESENTATIVE_PIXELS: usize = 10;

/// A sweepable `shafts` field.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Param {
    Planes,
    Subplanes,
    TexelBits,
    FbBits,
    WeightBits,
    CoordFracBits,
    Mesh,
    ShadowResolution,
    ShadowDepthBits,
    FTexels,
    HTexels,
    LightMapTexels,
    AccIntBits,
    AccFracBits,
    RecipIndexBits,
    RecipEntryBits,
    NewtonFracBits,
}

impl Param {
    pub const ALL: [Param; 17] = [
        Param::Planes,
        Param::Subplanes,
        Param::TexelBits,
        Param::FbBits,
        Param::WeightBits,
        Param::CoordFracBits,
        Param::Mesh,
        Param::ShadowResolution,
        Param::ShadowDepthBits,
        Param::FTexels,
        Param::HTexels,
        Param::LightMapTexels,
        Param::AccIntBits,
        Param::AccFracBits,
        Param::RecipIndexBits,
        Param::RecipEntryBits,
        Param::NewtonFracBits,
    ];

    /// The name on the command line and in the CSV (= the `shafts` field name).
    pub fn name(self) -> &'static str {
        match self {
            Param::Planes => "planes",
            Param::Subplanes => "subplanes",
            Param::TexelBits => "texel_bits",
            Param::FbBits => "fb_bits",
            Param::WeightBits => "weight_bits",
            Param::CoordFracBits => "coord_frac_bits",
            Param::Mesh => "mesh",
            Param::ShadowResolution => "shadow_resolution",
            Param::ShadowDepthBits => "shadow_depth_bits",
            Param::FTexels => "f_texels",
            Param::HTexels => "h_texels",
            Param::LightMapTexels => "light_map_texels",
            Param::AccIntBits => "acc_int_bits",
            Param::AccFracBits => "acc_frac_bits",
            Param::RecipIndexBits => "recip_index_bits",
            Param::RecipEntryBits => "recip_entry_bits",
            Param::NewtonFracBits => "newton_frac_bits",
        }
    }

    /// By name (`-` accepted for `_`); an unknown name is an error naming `param` and
    /// listing the known ones.
    pub fn from_name(name: &str) -> Result<Param, String> {
        let norm = name.trim().replace('-', "_");
        Param::ALL
            .into_iter()
            .find(|p| p.name() == norm)
            .ok_or_else(|| {
                format!(
                    "param: unknown parameter '{name}' (known: {})",
                    Param::ALL.map(Param::name).join(", ")
                )
            })
    }

    /// Takes `AxB` values (mesh columns × rows, h texture s × t) rather than numbers.
    pub fn is_pair(self) -> bool {
        matches!(self, Param::Mesh | Param::HTexels)
    }

    /// The value set into `cfg` (no validation here: see [`sweep`]). A value of the
    /// wrong shape (a pair for a numeric param or the reverse) is an error naming
    /// `values`.
    pub fn apply(self, cfg: &mut ShaftsConfig, v: Value) -> Result<(), String> {
        let wrong = || {
            Err(format!(
                "values: '{v}' does not fit {} (it takes {})",
                self.name(),
                self.value_help()
            ))
        };
        match v {
            Value::Pair(a, b) => match self {
                Param::Mesh => cfg.mesh = [a, b],
                Param::HTexels => cfg.h_texels = [a, b],
                _ => return wrong(),
            },
            Value::One(x) => match self {
                Param::Planes => cfg.planes = x,
                Param::Subplanes => cfg.subplanes = x,
                Param::TexelBits => cfg.texel_bits = x,
                Param::FbBits => cfg.fb_bits = x,
                Param::WeightBits => cfg.weight_bits = x,
                Param::CoordFracBits => cfg.coord_frac_bits = x,
                Param::ShadowResolution => cfg.shadow_resolution = x,
                Param::ShadowDepthBits => cfg.shadow_depth_bits = x,
                Param::FTexels => cfg.f_texels = x,
                Param::LightMapTexels => cfg.light_map_texels = x,
                Param::AccIntBits => cfg.acc_int_bits = x,
                Param::AccFracBits => cfg.acc_frac_bits = x,
                Param::RecipIndexBits => cfg.recip_index_bits = x,
                Param::RecipEntryBits => cfg.recip_entry_bits = x,
                Param::NewtonFracBits => cfg.newton_frac_bits = x,
                Param::Mesh | Param::HTexels => return wrong(),
            },
        }
        Ok(())
    }

    /// This param's value in `cfg` (a pair's first number).
    pub fn get(self, cfg: &ShaftsConfig) -> u32 {
        match self {
            Param::Planes => cfg.planes,
            Param::Subplanes => cfg.subplanes,
            Param::TexelBits => cfg.texel_bits,
            Param::FbBits => cfg.fb_bits,
            Param::WeightBits => cfg.weight_bits,
            Param::CoordFracBits => cfg.coord_frac_bits,
            Param::ShadowResolution => cfg.shadow_resolution,
            Param::ShadowDepthBits => cfg.shadow_depth_bits,
            Param::FTexels => cfg.f_texels,
            Param::LightMapTexels => cfg.light_map_texels,
            Param::AccIntBits => cfg.acc_int_bits,
            Param::AccFracBits => cfg.acc_frac_bits,
            Param::RecipIndexBits => cfg.recip_index_bits,
            Param::RecipEntryBits => cfg.recip_entry_bits,
            Param::NewtonFracBits => cfg.newton_frac_bits,
            Param::Mesh => cfg.mesh[0],
            Param::HTexels => cfg.h_texels[0],
        }
    }

    fn value_help(self) -> &'static str {
        if self.is_pair() {
            "values like 15x10,30x20"
        } else {
            "whole numbers, e.g. 10,20,30, or ranges start..end:step, e.g. 10..200:10"
        }
    }
}

/// One swept value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Value {
    One(u32),
    /// `AxB`.
    Pair(u32, u32),
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::One(x) => write!(f, "{x}"),
            Value::Pair(a, b) => write!(f, "{a}x{b}"),
        }
    }
}

fn parse_u32(item: &str, what: &str) -> Result<u32, String> {
    let t = item.trim();
    t.parse::<u32>().map_err(|_| {
        format!("'{t}' is not a number ({what} must be a whole number in 0 ..= 4294967295)")
    })
}

/// `AxB` (also `AXB`), each side a whole number.
fn parse_pair(item: &str) -> Result<(u32, u32), String> {
    let t = item.trim();
    let (a, b) = t
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{t}' is not of the form AxB (e.g. 15x10)"))?;
    Ok((parse_u32(a, "each side")?, parse_u32(b, "each side")?))
}

/// The `--values` list: comma-separated items, each a value (`10`, or `15x10` for
/// mesh / h_texels) or, for numeric params, an inclusive range `start..end:step`
/// (`start..end` steps by 1). Errors name `values[k]`, the k-th comma item (from 0),
/// or `values` for the whole list; at most [`MAX_VALUES`] values in all. Ranges are
/// not checked against the field's limits here: [`sweep`] validates each value.
pub fn parse_values(param: Param, text: &str) -> Result<Vec<Value>, String> {
    if text.trim().is_empty() {
        return Err(format!(
            "values: empty list ({} takes {})",
            param.name(),
            param.value_help()
        ));
    }
    let mut out = Vec::new();
    for (k, item) in text.split(',').enumerate() {
        let at = |m: String| format!("values[{k}]: {m}");
        let item = item.trim();
        if item.is_empty() {
            return Err(at(format!(
                "empty item ({} takes {})",
                param.name(),
                param.value_help()
            )));
        }
        if let Some((start, rest)) = item.split_once("..") {
            if param.is_pair() {
                return Err(at(format!(
                    "'{item}': a range needs a numeric parameter ({} takes {})",
                    param.name(),
                    param.value_help()
                )));
            }
            let (end, step) = match rest.split_once(':') {
                Some((e, s)) => (e, parse_u32(s, "the step").map_err(at)?),
                None => (rest, 1),
            };
            let start = parse_u32(start, "the start").map_err(at)?;
            let end = parse_u32(end, "the end").map_err(at)?;
            if step == 0 {
                return Err(at(format!("'{item}': the step must be at least 1")));
            }
            if end < start {
                return Err(at(format!(
                    "'{item}': the end {end} is below the start {start}"
                )));
            }
            let count = ((end - start) / step) as usize + 1;
            if out.len() + count > MAX_VALUES {
                return Err(at(format!(
                    "'{item}' gives {count} values; a sweep has at most {MAX_VALUES}"
                )));
            }
            out.extend((0..count as u32).map(|i| Value::One(start + i * step)));
        } else {
            let v = if param.is_pair() {
                let (a, b) = parse_pair(item).map_err(at)?;
                Value::Pair(a, b)
            } else {
                Value::One(parse_u32(item, param.name()).map_err(at)?)
            };
            if out.len() + 1 > MAX_VALUES {
                return Err(format!("values: more than {MAX_VALUES} values"));
            }
            out.push(v);
        }
    }
    Ok(out)
}

/// `--image WxH`; a malformed size is an error naming `image` (the range is checked
/// by the scene's validation, as `image.width` / `image.height`).
pub fn parse_image(text: &str) -> Result<(u32, u32), String> {
    crate::report::image_arg::parse_image(text)
}

/// One row of `sweep_<param>.csv` (read back from shard files by `sweep merge`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepRow {
    pub param: String,
    pub value: String,
    pub error_levels: f64,
    pub rms_levels: f64,
    pub predicted_hw_seconds: f64,
    pub wall_seconds: f64,
    pub gates_nand2: f64,
}

/// What a sweep produced.
#[derive(Clone, Debug)]
pub struct SweepOutput {
    pub rows: Vec<SweepRow>,
    pub csv: PathBuf,
    pub png: PathBuf,
    /// Wall time of the ray-marched reference.
    pub truth_seconds: f64,
}

/// Gates of the units the frame elaborated (left-out units do not count).
pub fn elaborated_gates(r: &FrameResult) -> f64 {
    r.elaboration
        .iter()
        .filter_map(|e| e.summary.as_ref())
        .map(|s| s.gates_nand2)
        .sum()
}

/// The scenes of a sweep: `base` with each value applied, all validated. The first
/// invalid value is an error naming the field (`shafts.texel_bits: …`) and the value.
pub fn sweep_scenes(base: &Scene, param: Param, values: &[Value]) -> Result<Vec<Scene>, String> {
    base.validate().map_err(|e| e.to_string())?;
    if values.is_empty() {
        return Err("values: empty list".into());
    }
    if values.len() > MAX_VALUES {
        return Err(format!(
            "values: {} values; a sweep has at most {MAX_VALUES}",
            values.len()
        ));
    }
    values
        .iter()
        .map(|&v| {
            let mut s = base.clone();
            param.apply(&mut s.shafts, v)?;
            s.validate()
                .map_err(|e| format!("{e} (sweep value {} = {v})", param.name()))?;
            Ok(s)
        })
        .collect()
}

/// Run the sweep on `base` (a validated scene; its image size is used as it is) and
/// write `out/sweep_<param>.csv` and `.png` (each atomically). Every value is
/// validated before anything is rendered or written; the CSV is rewritten as each
/// row finishes, so a render that fails (or a run that is stopped) leaves the rows
/// done so far, and `sweep_cli` with `resume` continues from them.
pub fn sweep(
    base: &Scene,
    param: Param,
    values: &[Value],
    truth_samples: u32,
    out: &Path,
) -> Result<SweepOutput, String> {
    let id = sweep_id(base, &base.name, param, values, truth_samples)?;
    sweep_resumable(base, &id, param, values, truth_samples, out, false)
}

/// [`sweep`] as one sweep `id`, continuing (with `resume`) from the rows of an earlier
/// run of the same sweep (`report::resume`).
pub fn sweep_resumable(
    base: &Scene,
    id: &SweepId,
    param: Param,
    values: &[Value],
    truth_samples: u32,
    out: &Path,
    resume: bool,
) -> Result<SweepOutput, String> {
    let csv = out.join(format!("sweep_{}.csv", param.name()));
    let png = out.join(format!("sweep_{}.png", param.name()));
    // Every value is checked before the journal removes an old CSV.
    check_sweep(base, param, values, truth_samples)?;
    let mut journal = Journal::plain(&csv, id, resume, |r: &SweepRow| r.value.clone())?;
    let truth_seconds = match sweep_rows(base, param, values, truth_samples, None, &mut journal) {
        Ok(t) => t,
        Err(e) => {
            let n = journal.into_rows().len();
            let saved = if n == 0 {
                String::new()
            } else {
                format!(
                    "; the {n} rows done are in {} (`--resume` continues from them)",
                    csv.display()
                )
            };
            return Err(format!("{e}{saved}"));
        }
    };
    let rows: Vec<SweepRow> = journal.into_rows().into_iter().map(|(_, r)| r).collect();
    write_outputs(&csv, &png, &plot_title(base, param), param, values, &rows)?;
    Ok(SweepOutput {
        rows,
        csv,
        png,
        truth_seconds,
    })
}

/// What makes two runs (or two shards) one sweep: the scene as named on the command
/// line and by fingerprint (two files of one name on two machines are two sweeps),
/// the param, every value, the image size and the truth's samples.
fn sweep_id(
    scene: &Scene,
    scene_name: &str,
    param: Param,
    values: &[Value],
    truth_samples: u32,
) -> Result<SweepId, String> {
    Ok(SweepId {
        kind: "shafts".into(),
        scene: scene_name.into(),
        param: param.name().into(),
        values: values.iter().map(Value::to_string).collect(),
        settings: [
            (
                "image".to_string(),
                format!("{}x{}", scene.image.width, scene.image.height),
            ),
            ("truth_samples".to_string(), truth_samples.to_string()),
            ("scene_fingerprint".to_string(), fingerprint(scene)?),
        ]
        .into(),
        title: plot_title(scene, param),
    })
}

/// The CSV and the plot, each atomically: what a sweep and a merge of its shards
/// write alike.
fn write_outputs(
    csv: &Path,
    png: &Path,
    title: &str,
    param: Param,
    values: &[Value],
    rows: &[SweepRow],
) -> Result<(), String> {
    write_csv(csv, rows)?;
    plot(png, title, param, values, rows)
}

/// Everything a sweep checks before it writes or renders: the truth's samples, and
/// every value's scene ([`sweep_scenes`]), which it returns.
fn check_sweep(
    base: &Scene,
    param: Param,
    values: &[Value],
    truth_samples: u32,
) -> Result<Vec<Scene>, String> {
    if !(1..=MAX_TRUTH_SAMPLES).contains(&truth_samples) {
        return Err(format!(
            "truth_samples: {truth_samples} is out of range (allowed 1 ..= {MAX_TRUTH_SAMPLES})"
        ));
    }
    sweep_scenes(base, param, values)
}

/// Render the values `only` picks (every value without a shard) that `journal` does
/// not hold yet, recording each row in it as it finishes; returns the wall time of
/// the reference (0 when no value is left: it is not computed). Every value is
/// validated first, so a bad sweep renders nothing; a render that fails is an error
/// naming the value, `journal` holding the rows before it.
pub fn sweep_rows(
    base: &Scene,
    param: Param,
    values: &[Value],
    truth_samples: u32,
    only: Option<Shard>,
    journal: &mut Journal<SweepRow>,
) -> Result<f64, String> {
    let scenes = check_sweep(base, param, values, truth_samples)?;
    let todo = journal.pending(&scenes, only);
    if todo.is_empty() {
        return Ok(0.0);
    }
    let (w, h) = (base.image.width, base.image.height);
    let (truth, truth_seconds) = reference_image(base, truth_samples)?;
    let pixels = representative_pixels(&truth, w, h, REPRESENTATIVE_PIXELS, base.seed)
        .map_err(|e| format!("truth (the {w}x{h} ray-marched reference): {e}"))?;
    let bar = progress_bar(todo.len() as u64, &format!("sweep {}", param.name()));
    for (k, s) in todo {
        let v = values[k];
        match render_row(s, param, v, &truth, w, &pixels) {
            Ok(r) => journal.record(k, r)?,
            Err(e) => {
                bar.abandon();
                return Err(format!(
                    "{} = {v} (value {k} of the sweep): {e}",
                    param.name()
                ));
            }
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    Ok(truth_seconds)
}

fn render_row(
    s: &Scene,
    param: Param,
    v: Value,
    truth: &[[f64; 3]],
    w: u32,
    pixels: &[(u32, u32)],
) -> Result<SweepRow, String> {
    let (r, pred, wall) = render_scene(s)?;
    let img = r.levels();
    let at = error_stats_at(&img, truth, w, pixels).map_err(|e| e.to_string())?;
    let all = error_stats(&img, truth).map_err(|e| e.to_string())?;
    Ok(SweepRow {
        param: param.name().to_string(),
        value: v.to_string(),
        error_levels: at.mean_abs,
        rms_levels: all.rms,
        predicted_hw_seconds: pred.seconds,
        wall_seconds: wall,
        gates_nand2: elaborated_gates(&r),
    })
}

/// "sweep planes on fig4 (360x240)": the scene's name up to its first ':' (at most
/// 40 characters).
fn plot_title(scene: &Scene, param: Param) -> String {
    let name: String = scene
        .name
        .split(':')
        .next()
        .unwrap_or("")
        .trim()
        .chars()
        .take(40)
        .collect();
    let on = if name.is_empty() {
        String::new()
    } else {
        format!(" on {name}")
    };
    format!(
        "sweep {}{on} ({}x{}): error and predicted time",
        param.name(),
        scene.image.width,
        scene.image.height
    )
}

/// Errors on the left axis, predicted time on the right; x = the value for numeric
/// params (points sorted by x), the value's index for pairs (the label lists them).
fn plot(
    path: &Path,
    title: &str,
    param: Param,
    values: &[Value],
    rows: &[SweepRow],
) -> Result<(), String> {
    let xs: Vec<f64> = values
        .iter()
        .enumerate()
        .map(|(i, v)| match v {
            Value::One(x) => *x as f64,
            Value::Pair(..) => i as f64,
        })
        .collect();
    let x_label = if param.is_pair() {
        let mut shown: Vec<String> = values
            .iter()
            .take(6)
            .enumerate()
            .map(|(i, v)| format!("{i} = {v}"))
            .collect();
        if values.len() > 6 {
            shown.push("…".into());
        }
        format!(
            "{}: index of the value ({})",
            param.name(),
            shown.join(", ")
        )
    } else {
        param.name().to_string()
    };
    // Numeric values are drawn in increasing x (the CSV keeps the order given).
    let mut order: Vec<usize> = (0..rows.len().min(xs.len())).collect();
    order.sort_by(|&a, &b| xs[a].total_cmp(&xs[b]));
    let series = |label: &str, axis: Axis, f: fn(&SweepRow) -> f64| Series {
        label: label.to_string(),
        points: order.iter().map(|&i| (xs[i], f(&rows[i]))).collect(),
        axis,
    };
    line_plot(
        path,
        &PlotSpec {
            title: title.to_string(),
            x_label,
            y_left_label: "error (8-bit levels)".to_string(),
            y_right_label: Some("predicted GeForce2 GTS time (s)".to_string()),
            log_x: false,
            log_y: false,
            width: 900,
            height: 560,
        },
        &[
            series("mean |error| at 10 pixels", Axis::Left, |r| r.error_levels),
            series("RMS error, whole image", Axis::Left, |r| r.rms_levels),
            series("predicted time", Axis::Right, |r| r.predicted_hw_seconds),
        ],
    )
}

/// The `sweep` command on a shafts scene (`scene`, loaded from `scene_name`): apply `--image`,
/// parse and validate every value, sweep (with `shard`, only its share, written to
/// the shard file: docs/sweep.md), print a table. With `resume`, continue from the
/// rows an interrupted run of the same sweep left (`report::resume`).
// The command line's options, one argument each.
#[allow(clippy::too_many_arguments)]
pub fn sweep_cli(
    mut scene: Scene,
    scene_name: &str,
    param: &str,
    values: &str,
    out: &Path,
    truth_samples: u32,
    image: Option<&str>,
    shard: Option<Shard>,
    resume: bool,
) -> Result<(), String> {
    let param = Param::from_name(param)?;
    let values = parse_values(param, values)?;
    crate::scene::load::apply_image(&mut scene, image)?;
    let id = sweep_id(&scene, scene_name, param, &values, truth_samples)?;
    if let Some(shard) = shard {
        check_sweep(&scene, param, &values, truth_samples)?;
        let mut journal = Journal::shard(out, &id, shard, resume)?;
        sweep_rows(
            &scene,
            param,
            &values,
            truth_samples,
            Some(shard),
            &mut journal,
        )?;
        let done = journal.into_rows();
        println!("{}", finish_shard(out, &id, shard, &done)?);
        let rows: Vec<SweepRow> = done.into_iter().map(|(_, r)| r).collect();
        print!("{}", table(param, &rows));
        return Ok(());
    }
    let t0 = Instant::now();
    let res = sweep_resumable(&scene, &id, param, &values, truth_samples, out, resume)?;
    println!(
        "sweep {} on {} ({}x{}, truth {} samples per ray in {:.2} s): wrote {} and {} in {:.1} s",
        param.name(),
        scene_name,
        scene.image.width,
        scene.image.height,
        truth_samples,
        res.truth_seconds,
        res.csv.display(),
        res.png.display(),
        t0.elapsed().as_secs_f64()
    );
    print!("{}", table(param, &res.rows));
    Ok(())
}

/// `sweep merge` of a shafts sweep: the shards' rows written as [`sweep`] writes
/// them (CSV, plot, table on stdout).
pub fn merge_cli(set: &ShardSet, out: &Path) -> Result<(), String> {
    // The header was written by a shafts sweep; if it still does not read as one
    // (edited by hand, another version), the error names the file.
    let in_file = |e: String| format!("{}: {e}", set.files[0].display());
    let param = Param::from_name(&set.id.param).map_err(in_file)?;
    let values = parse_values(param, &set.id.values.join(",")).map_err(in_file)?;
    let rows: Vec<SweepRow> = set.rows()?;
    let csv = out.join(format!("sweep_{}.csv", param.name()));
    let png = out.join(format!("sweep_{}.png", param.name()));
    write_outputs(&csv, &png, &set.id.title, param, &values, &rows)?;
    println!("{}", set.merged(&csv, &png));
    print!("{}", table(param, &rows));
    Ok(())
}

/// The rows as the terminal table, headed by the param's name; the columns are named
/// as in the CSV (`error_levels` is the mean |Δ| in 8-bit levels).
fn table(param: Param, rows: &[SweepRow]) -> String {
    let table: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            vec![
                r.value.clone(),
                format!("{:.3}", r.error_levels),
                format!("{:.3}", r.rms_levels),
                format!("{:.6}", r.predicted_hw_seconds),
                format!("{:.3}", r.wall_seconds),
                format!("{:.0}", r.gates_nand2),
            ]
        })
        .collect();
    text_table(
        &[
            param.name(),
            "error_levels",
            "rms_levels",
            "predicted_hw_seconds",
            "wall_seconds",
            "gates_nand2",
        ],
        &table,
    )
}
