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
use crate::report::resume::Journal;
use crate::report::shard::{Shard, SweepId};
use crate::report::sweep_out::shard_sweep;
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

/// The value of `param` in `hw` (`radial` as 0 or 1); an unknown name is an error
/// naming `param`.
pub fn get(hw: &GlareHw, param: &str) -> Result<u32, String> {
    Ok(match param {
        "shape_log2" => hw.shape_log2,
        "shape_bits" => hw.shape_bits,
        "falloff_log2" => hw.falloff_log2,
        "falloff_bits" => hw.falloff_bits,
        "weight_bits" => hw.weight_bits,
        "coord_frac_bits" => hw.coord_frac_bits,
        "noise_bits" => hw.noise_bits,
        "fb_bits" => hw.fb_bits,
        "radial" => u32::from(hw.radial),
        _ => {
            return Err(format!(
                "param: unknown glare width '{param}' (known: {})",
                GLARE_PARAMS.join(", ")
            ))
        }
    })
}

/// The scene of each value, validated (an invalid value is an error naming the field,
/// e.g. `glare.hw.shape_log2`, before anything runs).
pub fn glare_scenes(base: &Scene, param: &str, values: &[u32]) -> Result<Vec<Scene>, String> {
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
    Ok(scenes)
}

/// The rows of the values `only` picks (every value without a shard) that `journal`
/// does not hold yet, each recorded in it as it finishes; all scenes are validated
/// first.
pub fn glare_rows(
    base: &Scene,
    param: &str,
    values: &[u32],
    backdrop: Option<&Framebuffer>,
    only: Option<Shard>,
    journal: &mut Journal<GlareSweepRow>,
) -> Result<(), String> {
    let scenes = glare_scenes(base, param, values)?;
    let todo = journal.pending(&scenes, only);
    try_map_with_progress(
        &todo,
        &format!("sweep {param}"),
        |&(i, s)| -> Result<(), String> {
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
            let v = get(&g, param)?;
            journal.record(
                i,
                GlareSweepRow {
                    param: param.into(),
                    value: v,
                    mean_abs_levels: st.mean_abs,
                    rms_levels: st.rms,
                    max_levels: st.max,
                    predicted_hw_seconds: pred.seconds,
                    wall_seconds: wall,
                    gates_nand2: f.units.iter().map(|u| u.gates_nand2).sum(),
                    ram_bits: f.units.iter().map(|u| u.ram_bits).sum(),
                },
            )
        },
    )?;
    Ok(())
}

/// The plot's title: the scene's name up to its first ':'.
fn title(base: &Scene, param: &str) -> String {
    format!("{}: error and run time against {param}", base.short_name())
}

/// Run the sweep and write `out/sweep_<param>.csv` and `.png`; see [`glare_rows`].
/// The CSV is rewritten as each row finishes (`report::resume`).
pub fn glare_sweep(
    base: &Scene,
    param: &str,
    values: &[u32],
    out: &Path,
    backdrop: Option<&Framebuffer>,
) -> Result<(Vec<GlareSweepRow>, PathBuf, PathBuf), String> {
    let id = sweep_id(base, &base.name, param, values)?;
    glare_sweep_resumable(base, &id, param, values, out, backdrop, false)
}

/// [`glare_sweep`] as sweep `id`, continuing (with `resume`) from the rows an earlier
/// run of it left.
fn glare_sweep_resumable(
    base: &Scene,
    id: &SweepId,
    param: &str,
    values: &[u32],
    out: &Path,
    backdrop: Option<&Framebuffer>,
    resume: bool,
) -> Result<(Vec<GlareSweepRow>, PathBuf, PathBuf), String> {
    // Every value is checked before the journal removes an old CSV.
    glare_scenes(base, param, values)?;
    let csv = out.join(format!("sweep_{param}.csv"));
    let mut journal = Journal::plain(&csv, id, resume, |r: &GlareSweepRow| r.value.to_string())?;
    glare_rows(base, param, values, backdrop, None, &mut journal)?;
    let rows: Vec<GlareSweepRow> = journal.into_rows().into_iter().map(|(_, r)| r).collect();
    let (csv, png) = write_sweep(&rows, &title(base, param), param, out)?;
    Ok((rows, csv, png))
}

/// What makes two runs or a glare sweep's shards one sweep: `scene_arg` as given to `--scene`,
/// and the scene itself (after `--image`) by fingerprint, so that shards rendered
/// from two different files of one name are refused.
fn sweep_id(
    scene: &Scene,
    scene_arg: &str,
    param: &str,
    values: &[u32],
) -> Result<SweepId, String> {
    SweepId::of_scene(
        "glare",
        scene,
        (scene.image.width, scene.image.height),
        scene_arg,
        param,
        values,
        title(scene, param),
    )
}

/// The CLI: the whole sweep, or with `shard` only its share, written to the shard
/// file (docs/sweep.md); with `resume`, continuing from the rows an interrupted run
/// of the same sweep left.
// The command line's options, one argument each.
#[allow(clippy::too_many_arguments)]
pub fn glare_sweep_cli(
    scene: &Scene,
    scene_arg: &str,
    param: &str,
    values: &str,
    out: &Path,
    backdrop: Option<&Framebuffer>,
    shard: Option<Shard>,
    resume: bool,
) -> Result<(), String> {
    let values = parse_int_values(values)?;
    let id = sweep_id(scene, scene_arg, param, &values)?;
    if let Some(shard) = shard {
        glare_scenes(scene, param, &values)?;
        let mut journal = Journal::shard(out, &id, shard, resume)?;
        glare_rows(scene, param, &values, backdrop, Some(shard), &mut journal)?;
        return shard_sweep(out, &id, shard, &journal.into_rows());
    }
    let (rows, csv, png) =
        glare_sweep_resumable(scene, &id, param, &values, out, backdrop, resume)?;
    println!(
        "sweep {param} on {}: wrote {} and {}",
        scene.name,
        csv.display(),
        png.display()
    );
    print!("{}", sweep_table(param, &rows));
    Ok(())
}
