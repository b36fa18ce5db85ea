//! `sweep --scene <environment scene> --param side`: error against run time and memory
//! for the voxel map's side s (docs/sweep.md, "Environment-map scenes").
//!
//! For each side the scene's `environment.side` is set and the scene re-validated
//! (a side beyond `scene::environment::MAX_SIDE` is an error naming
//! `environment.side` before anything runs), then the scene is rendered as `render
//! --scene … --reference` does ([`render_scene`] with the Phong truth): the map is
//! built with the scene's prefilter ([`super::scene_render::build_map`]: the default
//! picks the exact build above [`crate::scene::environment::AUTO_ACCELERATED_MAX_SIDE`]) and the
//! frame drawn through the units. A row holds:
//!
//! * `mean_abs_levels`, `rms_levels`, `max_levels`: the render against the Phong truth
//!   with the cos φ test (the thesis' Table 5 metric), 8-bit levels, over the object's
//!   pixels and the three channels;
//! * `predicted_hw_seconds`: the GeForce3 frame-time model of the frame;
//! * `wall_seconds`: the map build plus the render (truth included);
//! * `gates_nand2`: the elaborated units' gates;
//! * `ram_bits`: the memory of the map: the voxel codes (s³ × 3 × 8 bits), the
//!   texture the elaborated path holds.
//!
//! The CSV, plot, resume and shards are those of the glare and shading sweeps
//! (`report::sweep_out`).

use super::scene_render::{render_scene, SceneFrame};
use crate::report::progress::try_map_with_progress;
use crate::report::resume::Journal;
use crate::report::shard::{Shard, SweepId};
use crate::report::sweep_out::{parse_int_values, run_sweep, sweep_table, SweepRow};
use crate::scene::format::Scene;
use std::path::Path;

/// The parameters an environment-map sweep can change.
pub const ENVMAP_PARAMS: &[&str] = &["side"];

/// The scene of each value, validated: an unknown parameter names `param`, a bad side
/// names `environment.side` (and the value), before anything runs.
pub fn envmap_scenes(base: &Scene, param: &str, values: &[u32]) -> Result<Vec<Scene>, String> {
    if !ENVMAP_PARAMS.contains(&param) {
        return Err(format!(
            "param: unknown environment-map parameter '{param}' (known: {})",
            ENVMAP_PARAMS.join(", ")
        ));
    }
    let mut scenes = Vec::with_capacity(values.len());
    for &v in values {
        let mut s = base.clone();
        let env = s
            .environment
            .as_mut()
            .ok_or("scene: it has no [environment] section to sweep")?;
        env.side = v;
        s.validate()
            .map_err(|e| format!("{e} (sweep value side = {v})"))?;
        scenes.push(s);
    }
    Ok(scenes)
}

/// One row: render `s` with its truth (module notes).
pub fn envmap_row(s: &Scene, param: &str) -> Result<SweepRow, String> {
    let f = render_scene(s, true).map_err(|e| e.to_string())?;
    envmap_row_of(&f, param)
}

/// The row of a render made with its truth (by [`render_scene`] or
/// [`super::scene_render::render_scene_against`]).
pub fn envmap_row_of(f: &SceneFrame, param: &str) -> Result<SweepRow, String> {
    let t = f
        .truth
        .as_ref()
        .ok_or("internal: the render made no truth")?;
    let st = &t.cos_phi;
    let mean = st.mean.iter().sum::<f64>() / 3.0;
    let rms = ((0..3)
        .map(|c| st.mean[c] * st.mean[c] + st.var[c])
        .sum::<f64>()
        / 3.0)
        .sqrt();
    let max = st.max.iter().copied().fold(0.0, f64::max);
    eprintln!(
        "side {}: {} prefilter, {} empty voxels, map {:.1} s, render {:.1} s, {:.1} MB",
        f.map.side,
        f.map.prefilter,
        f.map.empty_voxels.unwrap_or(0),
        f.map.build_seconds,
        f.render_seconds,
        f.map.map_bytes as f64 / 1e6
    );
    Ok(SweepRow {
        param: param.into(),
        value: f.map.side,
        mean_abs_levels: mean,
        rms_levels: rms,
        max_levels: max,
        predicted_hw_seconds: f.prediction.seconds,
        wall_seconds: f.map.build_seconds + f.render_seconds,
        gates_nand2: f
            .frame
            .elaboration
            .units
            .iter()
            .filter_map(|u| u.summary.as_ref())
            .map(|u| u.gates_nand2)
            .sum(),
        ram_bits: f.map.map_bytes * 8,
    })
}

fn envmap_rows(
    base: &Scene,
    param: &str,
    values: &[u32],
    only: Option<Shard>,
    journal: &mut Journal<SweepRow>,
) -> Result<(), String> {
    let scenes = envmap_scenes(base, param, values)?;
    let todo = journal.pending(&scenes, only);
    try_map_with_progress(&todo, &format!("sweep {param}"), |&(i, s)| {
        let row = envmap_row(s, param)?;
        journal.record(i, row)
    })?;
    Ok(())
}

fn title(base: &Scene, param: &str) -> String {
    format!("{}: error and run time against {param}", base.short_name())
}

fn sweep_id(
    scene: &Scene,
    scene_arg: &str,
    param: &str,
    values: &[u32],
) -> Result<SweepId, String> {
    SweepId::of_scene(
        "envmap",
        scene,
        (scene.image.width, scene.image.height),
        scene_arg,
        param,
        values,
        title(scene, param),
    )
}

/// The CLI: the whole sweep into `out/sweep_<param>.csv` and `.png` (or with `shard`
/// only its share, for `sweep merge`), continuing with `resume`.
pub fn envmap_sweep_cli(
    scene: &Scene,
    scene_arg: &str,
    param: &str,
    values: &str,
    out: &Path,
    shard: Option<Shard>,
    resume: bool,
) -> Result<(), String> {
    let values = parse_int_values(values)?;
    // Every value is checked before a journal removes an old CSV.
    envmap_scenes(scene, param, &values)?;
    let id = sweep_id(scene, scene_arg, param, &values)?;
    let Some((rows, csv, png)) = run_sweep(out, &id, shard, resume, |only, journal| {
        envmap_rows(scene, param, &values, only, journal)
    })?
    else {
        return Ok(());
    };
    println!(
        "sweep {param} on {}: wrote {} and {}",
        scene.name,
        csv.display(),
        png.display()
    );
    print!("{}", sweep_table(param, &rows));
    Ok(())
}
