//! The paper's experiments (Dobashi et al., SPEC A): `reproduce shafts-fig4`,
//! `shafts-fig5`, `shafts-vs-raymarch`, `shafts-stage`. Each writes CSV and PNG.

use super::cli::{levels_png, reference_image, render_scene};
use super::frame::FrameResult;
use super::throughput::split_objects_shafts;
use super::throughput::Prediction;
use crate::report::csv_out::write_csv;
use crate::report::metrics::{error_stats, error_stats_at, representative_pixels, rms_percent};
use crate::report::plot::{line_plot, Axis, PlotSpec, Series};
use crate::report::progress::progress_bar;
use crate::scene::builtin::builtin;
use crate::scene::format::Scene;
use serde::Serialize;
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

/// Samples per ray of the unquantised truth (the paper: 200 for Fig. 4, 180 against
/// Nishita's ray tracer).
pub const TRUTH_SAMPLES_FIG4: u32 = 200;
pub const RAYMARCH_SAMPLES: u32 = 180;

#[derive(Serialize)]
pub struct Fig4Row {
    pub planes: u32,
    pub error_levels: f64,
    pub rms_levels: f64,
    pub predicted_hw_seconds: f64,
    pub wall_seconds: f64,
}

#[derive(Serialize)]
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

/// Fig. 4: error and time against the number of sample planes n = 10 … 200, for
/// 8-bit textures and framebuffer (`fig4.csv`) and for 16-bit (`fig4_wide.csv`).
/// The 2 × |planes| frames are independent: they run side by side ([`run_points`]),
/// the rows and files are those of one after the other.
pub fn fig4(out: &Path, planes: &[u32]) -> Result<(), String> {
    let base = scene("fig4")?;
    let (w, h) = (base.image.width, base.image.height);
    let (truth, _) = reference_image(&base, TRUTH_SAMPLES_FIG4)?;
    levels_png(&truth, w, h, &out.join("fig4_truth.png"))?;
    let pixels = txt(representative_pixels(&truth, w, h, 10, base.seed))?;
    let files = [("fig4", 8u32), ("fig4_wide", 16u32)];
    // Point i: file i / |planes|, n = planes[i % |planes|]; the most planes first.
    let np = planes.len();
    let mut order: Vec<usize> = (0..files.len() * np).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(planes[i % np]));
    let bar = progress_bar(order.len() as u64, "fig4");
    let rows = run_points(&order, |i| {
        let ((file, bits), n) = (files[i / np], planes[i % np]);
        let mut s = base.clone();
        s.shafts.planes = n;
        s.shafts.texel_bits = bits;
        s.shafts.fb_bits = bits;
        let (r, pred, wall) = render_scene(&s)?;
        let img = r.levels();
        let row = Fig4Row {
            planes: n,
            error_levels: txt(error_stats_at(&img, &truth, w, &pixels))?.mean_abs,
            rms_levels: txt(error_stats(&img, &truth))?.rms,
            predicted_hw_seconds: pred.seconds,
            wall_seconds: wall,
        };
        if n == 30 {
            r.fb.save_png(&out.join(format!("{file}_n30.png")))
                .map_err(|e| format!("out: {e}"))?;
        }
        bar.inc(1);
        Ok(row)
    })?;
    bar.finish_and_clear();
    for (fi, (file, bits)) in files.iter().enumerate() {
        let rows = &rows[fi * np..(fi + 1) * np];
        write_csv(&out.join(format!("{file}.csv")), rows)?;
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
/// Fig. 6 images at m = 1 and m = 6. The reference frame is rendered once (first, on
/// every thread) and is also the row of its m; the other frames are independent and
/// run side by side ([`run_points`]); the rows are in the order of `subplanes`.
pub fn fig5(out: &Path, subplanes: &[u32]) -> Result<(), String> {
    let base = scene("fig6")?;
    let m_ref = *subplanes.iter().max().ok_or("subplanes: empty list")?;
    let mut s = base.clone();
    s.shafts.subplanes = m_ref;
    let (r_ref, pred_ref, wall_ref) = render_scene(&s)?;
    let reference = r_ref.levels();
    let bar = progress_bar(subplanes.len() as u64, "fig5");
    let row = |m: u32, r: &FrameResult, pred: &Prediction, wall: f64| -> Result<Fig5Row, String> {
        let png = match m {
            1 => Some("fig6a.png"),
            6 => Some("fig6b.png"),
            _ => None,
        };
        if let Some(name) = png {
            r.fb.save_png(&out.join(name))
                .map_err(|e| format!("out: {e}"))?;
        }
        bar.inc(1);
        Ok(Fig5Row {
            subplanes: m,
            rms_levels: txt(error_stats(&r.levels(), &reference))?.rms,
            predicted_hw_seconds: pred.seconds,
            wall_seconds: wall,
        })
    };
    // The most sub-planes first (the longest frames), so the last ones are short.
    let mut order: Vec<usize> = (0..subplanes.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(subplanes[i]));
    let rows = run_points(&order, |i| {
        let m = subplanes[i];
        if m == m_ref {
            return row(m, &r_ref, &pred_ref, wall_ref);
        }
        let mut s = base.clone();
        s.shafts.subplanes = m;
        let (r, pred, wall) = render_scene(&s)?;
        row(m, &r, &pred, wall)
    })?;
    bar.finish_and_clear();
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

/// `f(i)` of every sweep point i of `order` (a permutation of 0 .. order.len(), the
/// order points are started in), results in index order. With more than one rayon
/// thread the points run side by side, one per thread, each on a one-thread pool of
/// its own (a frame's own parallel parts then run in order on that thread): a sweep
/// point's output does not depend on the thread count, so the bytes are those of
/// the points one after the other; only each point's wall time changes meaning (one
/// core's time while the other cores ran other points). The first error in index
/// order is returned (no new point starts after an error).
fn run_points<T: Send>(
    order: &[usize],
    f: impl Fn(usize) -> Result<T, String> + Sync,
) -> Result<Vec<T>, String> {
    let n = order.len();
    let threads = rayon::current_num_threads().min(n);
    if threads <= 1 {
        let mut out: Vec<Option<T>> = (0..n).map(|_| None).collect();
        for &i in order {
            out[i] = Some(f(i)?);
        }
        return out
            .into_iter()
            .enumerate()
            .map(|(i, v)| v.ok_or_else(|| format!("values[{i}]: not run")))
            .collect();
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
                    let Some(&i) = order.get(k) else { break };
                    let r = match &pool {
                        Ok(p) => p.install(|| f(i)),
                        Err(e) => Err(format!("sweep threads: {e}")),
                    };
                    if r.is_err() {
                        failed.store(true, Ordering::Relaxed);
                    }
                    if let Ok(mut slot) = slots[i].lock() {
                        *slot = Some(r);
                    }
                }
            });
        }
    });
    let mut out = Vec::with_capacity(n);
    let mut missing = None;
    for (i, slot) in slots.into_iter().enumerate() {
        match slot.into_inner().ok().flatten() {
            Some(Ok(v)) => out.push(v),
            Some(Err(e)) => return Err(e),
            None => missing = missing.or(Some(i)),
        }
    }
    match missing {
        // A point is left out only after an error, returned above.
        Some(i) => Err(format!("values[{i}]: not run")),
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
