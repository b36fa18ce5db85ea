//! Error against run time for one glare width: render the scene for each value,
//! compare with the f64 reference (the analytic formulas per pixel, the same sources
//! and line draws), write `DIR/sweep_<param>.csv` and `.png`.
//!
//! The reference is the ideal of the formulas, so the error includes the table depth
//! (sampling the profile and the shape), the entry widths, the interpolator's fraction
//! bits and the framebuffer's rounding.

use super::cli::{reference_levels, render_and_predict_over};
use crate::report::image_out::Framebuffer;
use crate::report::metrics::error_stats;
use crate::report::progress::try_map_with_progress;
pub use crate::report::sweep_out::{
    parse_int_values, sweep_table, write_sweep, SweepRow as GlareSweepRow,
};
use crate::scene::format::Scene;
use crate::scene::glare::GlareHw;
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

/// Run the sweep; all scenes are validated first (an invalid value is an error naming
/// the field, e.g. `glare.hw.shape_log2`, before anything runs).
pub fn glare_sweep(
    base: &Scene,
    param: &str,
    values: &[u32],
    out: &Path,
    backdrop: Option<&Framebuffer>,
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
            // A picture drawn by earlier passes of the frame (a shafts background),
            // at this value's framebuffer width.
            let base = backdrop.map(|fb| {
                super::background::from_framebuffer(
                    fb,
                    s.glare.as_ref().map_or(8, |g| g.hw.fb_bits),
                )
            });
            let (f, pred, wall) =
                render_and_predict_over(s, base.as_deref()).map_err(|e| e.to_string())?;
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

pub fn glare_sweep_cli(
    scene: &Scene,
    param: &str,
    values: &str,
    out: &Path,
    backdrop: Option<&Framebuffer>,
) -> Result<(), String> {
    let values = parse_int_values(values)?;
    let (rows, csv, png) = glare_sweep(scene, param, &values, out, backdrop)?;
    println!(
        "sweep {param} on {}: wrote {} and {}",
        scene.name,
        csv.display(),
        png.display()
    );
    print!("{}", sweep_table(param, &rows));
    Ok(())
}
