//! Error against run time for one glare width: render the scene for each value,
//! compare with the f64 reference (the analytic formulas per pixel, the same sources
//! and line draws), write `DIR/sweep_<param>.csv` and `.png`.
//!
//! The reference is the ideal of the formulas, so the error includes the table depth
//! (sampling the profile and the shape), the entry widths, the interpolator's fraction
//! bits and the framebuffer's rounding.

use super::cli::{reference_levels, render_and_predict};
use crate::report::csv_out::write_csv;
use crate::report::metrics::error_stats;
use crate::report::plot::{line_plot, Axis, PlotSpec, Series};
use crate::report::progress::try_map_with_progress;
use crate::report::table::text_table;
use crate::scene::format::Scene;
use crate::scene::glare::GlareHw;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The glare widths a sweep can change (fields of `[glare.hw]`).
pub const GLARE_PARAMS: &[&str] = &[
    "shape_log2",
    "shape_bits",
    "falloff_log2",
    "falloff_bits",
    "weight_bits",
    "coord_frac_bits",
    "noise_bits",
    "fb_bits",
    "radial",
];

/// Set `param` of `hw` to `v`; an unknown name is an error naming `param`.
pub fn apply(hw: &mut GlareHw, param: &str, v: u32) -> Result<(), String> {
    let f = match param {
        "shape_log2" => &mut hw.shape_log2,
        "shape_bits" => &mut hw.shape_bits,
        "falloff_log2" => &mut hw.falloff_log2,
        "falloff_bits" => &mut hw.falloff_bits,
        "weight_bits" => &mut hw.weight_bits,
        "coord_frac_bits" => &mut hw.coord_frac_bits,
        "noise_bits" => &mut hw.noise_bits,
        "fb_bits" => &mut hw.fb_bits,
        "radial" => {
            // 0 = off, any other value = on.
            hw.radial = v != 0;
            return Ok(());
        }
        _ => {
            return Err(format!(
                "param: unknown glare width '{param}' (known: {})",
                GLARE_PARAMS.join(", ")
            ))
        }
    };
    *f = v;
    Ok(())
}

/// `10,20,30` or ranges `4..10:2` (inclusive), non-negative integers; errors name
/// `values`.
pub fn parse_int_values(text: &str) -> Result<Vec<u32>, String> {
    let mut out = Vec::new();
    for item in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let bad = || format!("values: '{item}' is not an integer or a range start..end:step");
        if let Some((a, rest)) = item.split_once("..") {
            let (b, step) = rest.split_once(':').unwrap_or((rest, "1"));
            let (a, b, step): (u32, u32, u32) = (
                a.trim().parse().map_err(|_| bad())?,
                b.trim().parse().map_err(|_| bad())?,
                step.trim().parse().map_err(|_| bad())?,
            );
            if step == 0 || b < a {
                return Err(bad());
            }
            out.extend((a..=b).step_by(step as usize));
        } else {
            out.push(item.parse().map_err(|_| bad())?);
        }
    }
    if out.is_empty() {
        return Err("values: no values given".into());
    }
    if out.len() > 1000 {
        return Err(format!("values: {} values (at most 1000)", out.len()));
    }
    Ok(out)
}

/// One row of `sweep_<param>.csv`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GlareSweepRow {
    pub param: String,
    pub value: u32,
    pub mean_abs_levels: f64,
    pub rms_levels: f64,
    pub max_levels: f64,
    pub predicted_hw_seconds: f64,
    pub wall_seconds: f64,
    pub gates_nand2: f64,
    pub ram_bits: u64,
}

/// Run the sweep; all scenes are validated first (an invalid value is an error naming
/// the field, e.g. `glare.hw.shape_log2`, before anything runs).
pub fn glare_sweep(
    base: &Scene,
    param: &str,
    values: &[u32],
    out: &Path,
) -> Result<(Vec<GlareSweepRow>, PathBuf, PathBuf), String> {
    let mut scenes = Vec::new();
    for &v in values {
        let mut s = base.clone();
        let g = s
            .glare
            .as_mut()
            .ok_or("scene: it has no [glare] section to sweep")?;
        apply(&mut g.hw, param, v)?;
        s.validate().map_err(|e| format!("{e} (value {v})"))?;
        scenes.push(s);
    }
    let rows = try_map_with_progress(
        &scenes,
        &format!("sweep {param}"),
        |s| -> Result<GlareSweepRow, String> {
            let (f, pred, wall) = render_and_predict(s).map_err(|e| e.to_string())?;
            let lv = reference_levels(s, &f).map_err(|e| e.to_string())?;
            let st = error_stats(&f.levels(), &lv).map_err(|e| e.to_string())?;
            let g = s.glare.as_ref().map(|g| g.hw).unwrap_or_default();
            let mut v = 0;
            for (name, x) in [
                ("shape_log2", g.shape_log2),
                ("shape_bits", g.shape_bits),
                ("falloff_log2", g.falloff_log2),
                ("falloff_bits", g.falloff_bits),
                ("weight_bits", g.weight_bits),
                ("coord_frac_bits", g.coord_frac_bits),
                ("noise_bits", g.noise_bits),
                ("fb_bits", g.fb_bits),
                ("radial", u32::from(g.radial)),
            ] {
                if name == param {
                    v = x;
                }
            }
            Ok(GlareSweepRow {
                param: param.into(),
                value: v,
                mean_abs_levels: st.mean_abs,
                rms_levels: st.rms,
                max_levels: st.max,
                predicted_hw_seconds: pred.seconds,
                wall_seconds: wall,
                gates_nand2: f.units.iter().map(|u| u.gates_nand2).sum(),
                ram_bits: f.units.iter().map(|u| u.ram_bits).sum(),
            })
        },
    )?;
    let title = format!(
        "{}: error and run time against {param}",
        base.name.split(':').next().unwrap_or("")
    );
    let (csv, png) = write_sweep(&rows, &title, param, out)?;
    Ok((rows, csv, png))
}

/// Write `DIR/sweep_<param>.csv` (the rows) and `DIR/sweep_<param>.png` (mean and RMS
/// error on the left axis, the wall time on the right, against the value); every
/// sweep with this row shape (glare, shading) writes its outputs here.
pub fn write_sweep(
    rows: &[GlareSweepRow],
    title: &str,
    param: &str,
    out: &Path,
) -> Result<(PathBuf, PathBuf), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("out: {}: {e}", out.display()))?;
    let csv = out.join(format!("sweep_{param}.csv"));
    let png = out.join(format!("sweep_{param}.png"));
    write_csv(&csv, rows)?;
    let mut spec = PlotSpec::new(title, param, "error against the f64 reference (levels)");
    spec.y_right_label = Some("wall time of the simulation (s)".into());
    let pts = |f: &dyn Fn(&GlareSweepRow) -> f64| {
        rows.iter()
            .map(|r| (r.value as f64, f(r)))
            .collect::<Vec<_>>()
    };
    line_plot(
        &png,
        &spec,
        &[
            Series {
                label: "mean |Δ|".into(),
                points: pts(&|r| r.mean_abs_levels),
                axis: Axis::Left,
            },
            Series {
                label: "RMS".into(),
                points: pts(&|r| r.rms_levels),
                axis: Axis::Left,
            },
            Series {
                label: "wall time".into(),
                points: pts(&|r| r.wall_seconds),
                axis: Axis::Right,
            },
        ],
    )?;
    Ok((csv, png))
}

pub fn glare_sweep_cli(scene: &Scene, param: &str, values: &str, out: &Path) -> Result<(), String> {
    let values = parse_int_values(values)?;
    let (rows, csv, png) = glare_sweep(scene, param, &values, out)?;
    println!(
        "sweep {param} on {}: wrote {} and {}",
        scene.name,
        csv.display(),
        png.display()
    );
    print!("{}", sweep_table(param, &rows));
    Ok(())
}

/// The rows as a terminal table, headed by the param's name.
pub fn sweep_table(param: &str, rows: &[GlareSweepRow]) -> String {
    let table: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            vec![
                r.value.to_string(),
                format!("{:.3}", r.mean_abs_levels),
                format!("{:.3}", r.rms_levels),
                format!("{:.1}", r.max_levels),
                format!("{:.6}", r.predicted_hw_seconds),
                format!("{:.3}", r.wall_seconds),
                format!("{:.0}", r.gates_nand2),
                r.ram_bits.to_string(),
            ]
        })
        .collect();
    text_table(
        &[
            param,
            "mean_abs",
            "rms",
            "max",
            "predicted_hw_s",
            "wall_s",
            "gates_nand2",
            "ram_bits",
        ],
        &table,
    )
}
