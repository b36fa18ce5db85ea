//! The paper's experiments (Dobashi et al.): `reproduce shafts-fig4`,
//! `shafts-fig5`, `shafts-vs-raymarch`, `shafts-stage`. Each writes CSV and PNG.

use super::cli::{levels_png, reference_image, render_scene};
use super::frame::FrameResult;
use crate::chip::split_objects_shafts;
use crate::chip::Prediction;
use crate::report::csv_out::write_csv;
use crate::report::metrics::{error_stats, error_stats_at, representative_pixels, rms_percent};
use crate::report::plot::{line_plot, Axis, PlotSpec, Series};
use crate::report::progress::progress_bar;
use crate::report::resume::Journal;
use crate::report::shard::SweepId;
use crate::scene::builtin::builtin;
use crate::scene::format::Scene;
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

/// Samples per ray of the unquantised truth (the paper: 200 for Fig. 4, 180 against
/// Nishita's ray tracer).
pub const TRUTH_SAMPLES_FIG4: u32 = 200;
pub const RAYMARCH_SAMPLES: u32 = 180;

#[derive(Serialize, Deserialize)]
pub struct Fig4Row {
    pub planes: u32,
    pub error_levels: f64,
    pub rms_levels: f64,
    pub predicted_hw_seconds: f64,
    pub wall_seconds: f64,
}

#[derive(Serialize, Deserialize)]
pub struct Fig5Row {
    pub subplanes: u32,
    pub rms_levels: f64,
    pub predicted_hw_seconds: f64,
    pub wall_seconds: f64,
}

#[derive(Serialize)]
pub struct VsRaymarchRow {
    pub rms_percent: f64,
    pub hw_wall_seconds: f64,
    pub ref_wall_seconds: f64,
    pub predicted_hw_seconds: f64,
}

#[derive(Serialize)]
pub struct StageRow {
    pub lights: usize,
    pub predicted_hw_seconds: f64,
    pub predicted_objects_seconds: f64,
    pub predicted_shafts_seconds: f64,
    pub wall_seconds: f64,
}

/// A metric's error as text (it names the argument at fault).
fn txt<T>(r: Result<T, rtl_model::error::ConfigError>) -> Result<T, String> {
    r.map_err(|e| e.to_string())
}

fn scene(name: &str) -> Result<Scene, String> {
    builtin(name).map_err(|e| e.to_string())
}

/// What makes two runs of a reproduction one (`--resume`): the figure, its CSV, the
/// values, the widths, the truth's samples and the binary's version (in the record).
fn reproduction_id(figure: &str, file: &str, param: &str, values: &[u32], bits: u32) -> SweepId {
    let mut settings = std::collections::BTreeMap::new();
    settings.insert("bits".to_string(), bits.to_string());
    if figure == "shafts-fig4" {
        settings.insert("truth_samples".to_string(), TRUTH_SAMPLES_FIG4.to_string());
    }
    SweepId {
        kind: format!("reproduce {figure}"),
        scene: file.to_string(),
        param: param.to_string(),
        values: values.iter().map(u32::to_string).collect(),
        settings,
        title: format!("{figure} {file}.csv"),
    }
}

/// Fig. 4: error and time against the number of sample planes n = 10 … 200, for
/// 8-bit textures and framebuffer (`fig4.csv`) and for 16-bit (`fig4_wide.csv`).
/// Each CSV is rewritten as each row finishes; with `resume`, the rows an interrupted
/// run left are kept and only the others rendered (`report::resume`). The frames are
/// independent and run side by side (`run_points`) in row order, so the rows on file
/// stay a prefix of each CSV (what `--resume` reads back).
pub fn fig4(out: &Path, planes: &[u32], resume: bool) -> Result<(), String> {
    let base = scene("fig4")?;
    let (w, h) = (base.image.width, base.image.height);
    let files = [("fig4", 8u32), ("fig4_wide", 16u32)];
    let mut journals = Vec::new();
    for (file, bits) in files {
        let id = reproduction_id("shafts-fig4", file, "planes", planes, bits);
        let csv = out.join(format!("{file}.csv"));
        journals.push(Journal::plain(&csv, &id, resume, |r: &Fig4Row| {
            r.planes.to_string()
        })?);
    }
    // Point i: file i / |planes|, n = planes[i % |planes|].
    let np = planes.len();
    let todo: Vec<usize> = (0..files.len() * np)
        .filter(|&i| !journals[i / np].is_done(i % np))
        .collect();
    for j in &journals {
        let left = (0..np).filter(|&i| !j.is_done(i)).count();
        if let Some(note) = j.resume_note(left) {
            eprintln!("{note}");
        }
    }
    // The truth is needed while a row is left, and for its own image.
    let truth_png = out.join("fig4_truth.png");
    if !todo.is_empty() || !truth_png.exists() {
        let (truth, _) = reference_image(&base, TRUTH_SAMPLES_FIG4)?;
        levels_png(&truth, w, h, &truth_png)?;
        let pixels = txt(representative_pixels(&truth, w, h, 10, base.seed))?;
        let journals_lock: Vec<Mutex<&mut Journal<Fig4Row>>> =
            journals.iter_mut().map(Mutex::new).collect();
        let bar = progress_bar(todo.len() as u64, "fig4");
        run_points(&todo, |i| {
            let ((file, bits), n) = (files[i / np], planes[i % np]);
            let mut s = base.clone();
            s.shafts.planes = n;
            s.shafts.texel_bits = bits;
            s.shafts.fb_bits = bits;
            let (r, pred, wall) = render_scene(&s)?;
            let img = r.levels();
            // The image first: a row on file means its image is written too.
            if n == 30 {
                r.fb.save_png(&out.join(format!("{file}_n30.png")))
                    .map_err(|e| format!("out: {e}"))?;
            }
            let row = Fig4Row {
                planes: n,
                error_levels: txt(error_stats_at(&img, &truth, w, &pixels))?.mean_abs,
                rms_levels: txt(error_stats(&img, &truth))?.rms,
                predicted_hw_seconds: pred.seconds,
                wall_seconds: wall,
            };
            journals_lock[i / np]
                .lock()
                .map_err(|_| "fig4: a sweep thread failed".to_string())?
                .record(i % np, row)?;
            bar.inc(1);
            Ok(())
        })?;
        bar.finish_and_clear();
    }
    for ((file, bits), journal) in files.into_iter().zip(journals) {
        let rows: Vec<Fig4Row> = journal.into_rows().into_iter().map(|(_, r)| r).collect();
        write_csv(&out.join(format!("{file}.csv")), &rows)?;
        plot_error_time(
            &out.join(format!("{file}.png")),
            &format!("Fig. 4: error and time vs sample planes ({bits}-bit texels and framebuffer)"),
            "sample planes n",
            rows.iter()
                .map(|r| (r.planes as f64, r.error_levels))
                .collect(),
            rows.iter()
                .map(|r| (r.planes as f64, r.predicted_hw_seconds))
                .collect(),
            "mean |error| at 10 pixels (levels)",
        )?;
    }
    Ok(())
}

/// Fig. 5: RMS against the m = 25 image for m = 1 … 25 sub-planes (n = 30), and the
/// Fig. 6 images at m = 1 and m = 6. `fig5.csv` is rewritten as each row finishes;
/// with `resume`, the rows an interrupted run left are kept (`report::resume`). The
/// reference frame is rendered once (first, on every thread) and is also the row of
/// its m; the other frames are independent and run side by side (`run_points`) in
/// row order, so the rows on file stay a prefix of the CSV.
pub fn fig5(out: &Path, subplanes: &[u32], resume: bool) -> Result<(), String> {
    let base = scene("fig6")?;
    let m_ref = *subplanes.iter().max().ok_or("subplanes: empty list")?;
    let id = reproduction_id("shafts-fig5", "fig5", "subplanes", subplanes, 8);
    let mut journal = Journal::plain(&out.join("fig5.csv"), &id, resume, |r: &Fig5Row| {
        r.subplanes.to_string()
    })?;
    let todo: Vec<usize> = (0..subplanes.len())
        .filter(|&i| !journal.is_done(i))
        .collect();
    if let Some(note) = journal.resume_note(todo.len()) {
        eprintln!("{note}");
    }
    if !todo.is_empty() {
        let mut s = base.clone();
        s.shafts.subplanes = m_ref;
        let (r_ref, pred_ref, wall_ref) = render_scene(&s)?;
        let reference = r_ref.levels();
        let bar = progress_bar(todo.len() as u64, "fig5");
        let journal_lock = Mutex::new(&mut journal);
        let row = |i: usize, r: &FrameResult, pred: &Prediction, wall: f64| {
            let m = subplanes[i];
            // The image first: a row on file means its image is written too.
            let png = match m {
                1 => Some("fig6a.png"),
                6 => Some("fig6b.png"),
                _ => None,
            };
            if let Some(name) = png {
                r.fb.save_png(&out.join(name))
                    .map_err(|e| format!("out: {e}"))?;
            }
            let row = Fig5Row {
                subplanes: m,
                rms_levels: txt(error_stats(&r.levels(), &reference))?.rms,
                predicted_hw_seconds: pred.seconds,
                wall_seconds: wall,
            };
            journal_lock
                .lock()
                .map_err(|_| "fig5: a sweep thread failed".to_string())?
                .record(i, row)?;
            bar.inc(1);
            Ok(())
        };
        run_points(&todo, |i| {
            let m = subplanes[i];
            if m == m_ref {
                return row(i, &r_ref, &pred_ref, wall_ref);
            }
            let mut s = base.clone();
            s.shafts.subplanes = m;
            let (r, pred, wall) = render_scene(&s)?;
            row(i, &r, &pred, wall)
        })?;
        bar.finish_and_clear();
    }
    let rows: Vec<Fig5Row> = journal.into_rows().into_iter().map(|(_, r)| r).collect();
    write_csv(&out.join("fig5.csv"), &rows)?;
    plot_error_time(
        &out.join("fig5.png"),
        "Fig. 5: RMS against m = 25 and time vs sub-sample planes (n = 30)",
        "sub-sample planes m",
        rows.iter()
            .map(|r| (r.subplanes as f64, r.rms_levels))
            .collect(),
        rows.iter()
            .map(|r| (r.subplanes as f64, r.predicted_hw_seconds))
            .collect(),
        "RMS (levels)",
    )
}

/// `f(p)` of every sweep point p of `points` (in the order they are started), the
/// results in the same order. With more than one rayon thread the points run side by
/// side, one per thread, each on a one-thread pool of its own (a frame's own parallel
/// parts then run in order on that thread): a sweep point's output does not depend on
/// the thread count, so the bytes are those of the points one after the other; only
/// each point's wall time changes meaning (one core's time while the other cores ran
/// other points). The first error in `points` order is returned (no new point starts
/// after an error).
fn run_points<T: Send>(
    points: &[usize],
    f: impl Fn(usize) -> Result<T, String> + Sync,
) -> Result<Vec<T>, String> {
    let n = points.len();
    let threads = rayon::current_num_threads().min(n);
    if threads <= 1 {
        return points.iter().map(|&p| f(p)).collect();
    }
    let next = AtomicUsize::new(0);
    let failed = AtomicBool::new(false);
    let slots: Vec<Mutex<Option<Result<T, String>>>> = (0..n).map(|_| Mutex::new(None)).collect();
    std::thread::scope(|sc| {
        for _ in 0..threads {
            sc.spawn(|| {
                let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build();
                while !failed.load(Ordering::Relaxed) {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    let Some(&p) = points.get(k) else { break };
                    let r = match &pool {
                        Ok(pool) => pool.install(|| f(p)),
                        Err(e) => Err(format!("sweep threads: {e}")),
                    };
                    if r.is_err() {
                        failed.store(true, Ordering::Relaxed);
                    }
                    if let Ok(mut slot) = slots[k].lock() {
                        *slot = Some(r);
                    }
                }
            });
        }
    });
    let mut out = Vec::with_capacity(n);
    let mut missing = None;
    for (k, slot) in slots.into_iter().enumerate() {
        match slot.into_inner().ok().flatten() {
            Some(Ok(v)) => out.push(v),
            Some(Err(e)) => return Err(e),
            None => missing = missing.or(Some(points[k])),
        }
    }
    match missing {
        // A point is left out only after an error, returned above.
        Some(p) => Err(format!("sweep point {p}: not run")),
        None => Ok(out),
    }
}

/// The n = 30, m = 6 frame against a 180-sample ray-marched reference.
pub fn vs_raymarch(out: &Path) -> Result<(), String> {
    let s = scene("fig6")?;
    let (r, pred, hw_wall) = render_scene(&s)?;
    let (reference, ref_wall) = reference_image(&s, RAYMARCH_SAMPLES)?;
    r.fb.save_png(&out.join("vs_raymarch_hw.png"))
        .map_err(|e| format!("out: {e}"))?;
    levels_png(
        &reference,
        s.image.width,
        s.image.height,
        &out.join("vs_raymarch_ref.png"),
    )?;
    let st = txt(error_stats(&r.levels(), &reference))?;
    write_csv(
        &out.join("vs_raymarch.csv"),
        &[VsRaymarchRow {
            rms_percent: rms_percent(&st),
            hw_wall_seconds: hw_wall,
            ref_wall_seconds: ref_wall,
            predicted_hw_seconds: pred.seconds,
        }],
    )
}

/// Fig. 7: the stage under five spotlights.
pub fn stage(out: &Path) -> Result<(), String> {
    let s = scene("stage")?;
    let (r, pred, wall) = render_scene(&s)?;
    r.fb.save_png(&out.join("stage.png"))
        .map_err(|e| format!("out: {e}"))?;
    let (objects, shafts) = split_objects_shafts(&pred);
    write_csv(
        &out.join("stage.csv"),
        &[StageRow {
            lights: s.lights.len(),
            predicted_hw_seconds: pred.seconds,
            predicted_objects_seconds: objects,
            predicted_shafts_seconds: shafts,
            wall_seconds: wall,
        }],
    )
}

fn plot_error_time(
    path: &Path,
    title: &str,
    x_label: &str,
    error: Vec<(f64, f64)>,
    time: Vec<(f64, f64)>,
    error_label: &str,
) -> Result<(), String> {
    line_plot(
        path,
        &PlotSpec {
            title: title.to_string(),
            x_label: x_label.to_string(),
            y_left_label: error_label.to_string(),
            y_right_label: Some("predicted GeForce2 GTS time (s)".to_string()),
            log_x: false,
            log_y: false,
            width: 900,
            height: 560,
        },
        &[
            Series {
                label: "error".to_string(),
                points: error,
                axis: Axis::Left,
            },
            Series {
                label: "predicted time".to_string(),
                points: time,
                axis: Axis::Right,
            },
        ],
    )
}
