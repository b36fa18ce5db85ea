//! `render` and `units --scene` through the frame: load, plan, elaborate the chip,
//! run the passes, write the PNG, print the plan, the chip, each pipeline's counters
//! and elaboration, and the predicted time per pass.

use super::chip::{chip_table, elaborate};
use super::plan::{plan, plan_table, test_scene_plan};
use super::run::render_with_progress;
use crate::pipeline::shafts::cli::{load_scene, reference_image};
use crate::report::table::{counters_table, elaboration_table, text_table};
use std::path::Path;

/// `render --scene NAME [--plan]`. Before any work: the output paths are checked
/// (errors name `out` or `reference`), the scene is loaded and validated, and its
/// memory estimate is checked against `max_memory` (bytes; `None` = the default
/// budget, half of `MemAvailable`: `frame::budget`), a shading scene's too
/// (`budget::shading_estimate`: its sphere view).
pub fn render_cli(
    name: &str,
    out: &Path,
    json: bool,
    reference: Option<&Path>,
    plan_only: bool,
    max_memory: Option<u64>,
) -> Result<(), String> {
    use crate::report::image_out::check_png_path;
    if !plan_only {
        check_png_path("out", out)?;
        if let Some(r) = reference {
            check_png_path("reference", r)?;
        }
    }
    if name == "test" {
        if !json {
            print!("pass plan:\n{}", plan_table(&test_scene_plan()));
        }
        if plan_only {
            return Ok(());
        }
        return crate::pipeline::test_scene::render_cli(out, json, reference);
    }
    // A shading scene (`shading-*`, or a file with a `[shading]` table: what
    // `optimize` writes as best.toml for one) renders through the shading sweep's path.
    if let Some(f) = crate::pipeline::shading::scene_file::ShadingFile::resolve(name)? {
        if !plan_only {
            let (budget, from) = super::budget::resolve(max_memory);
            let e = super::budget::shading_estimate(f.image);
            super::budget::check_estimate(e, budget, &from)?;
        }
        return crate::pipeline::shading::scene_file::render_cli(
            &f, out, json, reference, plan_only,
        );
    }
    let scene = load_scene(name)?;
    if !plan_only {
        let (budget, from) = super::budget::resolve(max_memory);
        super::budget::check(&scene, budget, &from)?;
        work_note(&scene);
    }
    let chip = elaborate(&scene);
    if super::plan::environment_scene(&scene) && !plan_only {
        // The thesis' environment scenes keep their own report (map build, truth).
        if !json {
            let p = plan(&scene).map_err(|e| e.to_string())?;
            print!(
                "pass plan:\n{}\nchip:\n{}\n",
                plan_table(&p),
                chip_table(&chip)
            );
        }
        let warnings = super::range::check_environment(&scene);
        super::range::print(&warnings);
        let w = serde_json::to_value(&warnings).map_err(|e| e.to_string())?;
        return crate::pipeline::envmap::scene_render::render_cli(&scene, out, json, reference, w);
    }
    if plan_only {
        let p = plan(&scene).map_err(|e| e.to_string())?;
        if json {
            let v = serde_json::json!({ "scene": scene.name, "plan": p.passes, "chip": chip });
            println!(
                "{}",
                serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
            );
        } else {
            print!(
                "pass plan:\n{}\nchip:\n{}",
                plan_table(&p),
                chip_table(&chip)
            );
        }
        return Ok(());
    }
    let setting = std::env::var("GLARE_PROGRESS").ok();
    let shown = crate::report::progress::frame_bar_wanted(work(&scene), setting.as_deref());
    let (f, _) = render_with_progress(&scene, shown).map_err(|e| e.to_string())?;
    let warnings = super::range::check(&scene, &f);
    f.fb.save_png(out)
        .map_err(|e| format!("out: {}: {e}", out.display()))?;
    let error = match reference {
        Some(path) => Some(super::reproduce::frame_error(&scene, &f, Some(path))?),
        None => None,
    };
    let elaboration: Vec<_> = [
        f.shafts.as_ref().map(|s| s.elaboration.clone()),
        f.shaded.as_ref().map(|s| s.elaboration.clone()),
        f.linked.as_ref().map(|l| l.shading.elaboration.clone()),
        f.glare.as_ref().map(|(g, _)| g.elaboration.clone()),
    ]
    .into_iter()
    .flatten()
    .flatten()
    .collect();
    if json {
        // `counters` is the drawing pipeline's map as before the frame existed (the
        // glare frame's for a glare scene, else the shafts frame's); every pipeline's
        // is under `counters_by_pipeline`.
        let counters = match (&f.glare, &f.shafts) {
            (Some((g, _)), _) => serde_json::to_value(&g.counters),
            (None, Some(s)) => serde_json::to_value(&s.counters),
            (None, None) => Ok(serde_json::Value::Null),
        }
        .map_err(|e| e.to_string())?;
        let v = serde_json::json!({
            "scene": scene.name,
            "plan": f.plan.passes,
            "chip": chip,
            "counters": counters,
            "counters_by_pipeline": f.counters(),
            "elaboration": elaboration,
            "gpu": f.gpu.name(),
            "predicted_by_pass": f.times,
            "predicted_seconds": f.predicted_seconds(),
            "wall_seconds": f.wall_seconds,
            "error_vs_reference": error,
            "warnings": warnings,
        });
        super::range::print(&warnings);
        println!(
            "{}",
            serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
        );
        return Ok(());
    }
    println!(
        "{} ({}x{}): wrote {} in {:.2} s of simulation",
        scene.name,
        scene.image.width,
        scene.image.height,
        out.display(),
        f.wall_seconds
    );
    print!("\npass plan:\n{}", plan_table(&f.plan));
    print!("\nchip:\n{}", chip_table(&chip));
    for (pipeline, c) in f.counters() {
        print!("\n{pipeline} counters:\n{}", counters_table(&c));
    }
    print!(
        "\nelaboration (each pipeline, at the scene's widths):\n{}",
        elaboration_table(&elaboration)
    );
    if let Some(c) = f.shafts.as_ref().and_then(|s| s.clip_stats) {
        println!(
            "\nclipper: {} polygons in, {} out, {} clipped, {} culled, {} vertices generated",
            c.polygons_in,
            c.polygons_out,
            c.polygons_clipped,
            c.polygons_culled,
            c.vertices_generated
        );
    }
    if let Some(l) = &f.linked {
        print!("\n{}", crate::frame::glare_link::summary(l));
    }
    let rows: Vec<Vec<String>> = f
        .times
        .iter()
        .map(|t| {
            vec![
                t.pass.clone(),
                t.on.clone(),
                format!("{:.6}", t.seconds),
                format!("{:.2}", t.wall_seconds),
            ]
        })
        .collect();
    print!(
        "\npredicted time per pass:\n{}",
        text_table(&["pass", "on", "seconds", "simulation_wall_s"], &rows)
    );
    println!("predicted frame time: {:.6} s", f.predicted_seconds());
    if let Some(e) = error {
        print!("\n{}", super::reproduce::error_table(&e));
    }
    super::range::print(&warnings);
    Ok(())
}

/// Fragments above which `render` says up front, on stderr, how much work it is.
pub const LARGE_WORK_FRAGMENTS: f64 = 2e9;

/// A line on stderr before an expensive render: the estimated sample-plane fragments
/// (pixels × planes × (1 + sub-planes) × lights) and memory.
fn work_note(scene: &crate::scene::format::Scene) {
    let fragments = work(scene);
    if fragments > LARGE_WORK_FRAGMENTS {
        eprintln!(
            "note: an expensive scene: about {fragments:.2e} sample-plane fragments and {} of buffers and tables; this may take minutes",
            super::budget::human(super::budget::estimate(scene).total())
        );
    }
}

/// A scene's estimated sample-plane fragments: pixels × planes × (1 + sub-planes) ×
/// lights (what [`work_note`] prints and what decides `render`'s progress bar).
fn work(scene: &crate::scene::format::Scene) -> f64 {
    let px = f64::from(scene.image.width) * f64::from(scene.image.height);
    let s = &scene.shafts;
    let lights = scene.lights.len().max(1) as f64;
    px * f64::from(s.planes) * (1.0 + f64::from(s.subplanes)) * lights
}

/// `units --scene NAME`: the chip the scene elaborates.
pub fn units_scene_cli(name: &str, json: bool) -> Result<(), String> {
    if name == "test" {
        return Err(
            "scene: the foundation test scene has fixed units (`render --scene test --plan`)"
                .into(),
        );
    }
    let scene = load_scene(name)?;
    let chip = elaborate(&scene);
    if json {
        println!(
            "{}",
            serde_json::to_string_pretty(&chip).map_err(|e| e.to_string())?
        );
    } else {
        print!("{}", chip_table(&chip));
    }
    Ok(())
}

/// The ray-marched reference of a shafts scene (re-exported for the reproductions).
pub fn shafts_reference(
    scene: &crate::scene::format::Scene,
    samples: u32,
) -> Result<Vec<[f64; 3]>, String> {
    Ok(reference_image(scene, samples)?.0)
}
