//! `render` for shafts scenes: load (built-in name or TOML file), render through the
//! units, write the PNG, print counters, elaboration and the predicted time.

use super::frame::{render_frame, FrameResult};
use super::host::prepare_scene;
use super::prepare::DEFAULT_EXPOSURE;
use super::throughput::{predict, split_objects_shafts, GpuModel, Prediction};
use crate::reference::raymarch::{raymarch_image, to_levels};
pub use crate::report::image_out::levels_png;
use crate::scene::format::Scene;
use std::path::Path;
use std::time::Instant;

pub use crate::scene::load::load_scene;

/// Render a frame and time the simulation.
pub fn render_scene(scene: &Scene) -> Result<(FrameResult, Prediction, f64), String> {
    let t0 = Instant::now();
    let (p, _) = prepare_scene(scene, DEFAULT_EXPOSURE).map_err(|e| e.to_string())?;
    let r = render_frame(&p).map_err(|e| e.to_string())?;
    let wall = t0.elapsed().as_secs_f64();
    let pred = predict(&GpuModel::geforce2_gts(), &r.passes);
    Ok((r, pred, wall))
}

/// Write the ray-marched reference (f64, `samples` per ray) as a PNG; returns its
/// levels and the wall time.
pub fn reference_image(scene: &Scene, samples: u32) -> Result<(Vec<[f64; 3]>, f64), String> {
    let t0 = Instant::now();
    let geom = super::host::scene_geometry(scene).map_err(|e| e.to_string())?;
    let img = raymarch_image(scene, &geom, samples);
    let levels = img
        .iter()
        .map(|p| to_levels(*p, DEFAULT_EXPOSURE))
        .collect();
    Ok((levels, t0.elapsed().as_secs_f64()))
}

pub fn render_cli(
    scene_name: &str,
    out: &Path,
    json: bool,
    reference: Option<&Path>,
) -> Result<(), String> {
    let scene = load_scene(scene_name)?;
    let (r, pred, wall) = render_scene(&scene)?;
    r.fb.save_png(out)
        .map_err(|e| format!("out: {}: {e}", out.display()))?;
    if let Some(path) = reference {
        let (levels, secs) = reference_image(&scene, 180)?;
        levels_png(&levels, scene.image.width, scene.image.height, path)?;
        let hw = r.levels();
        let n = (levels.len() * 3) as f64;
        let (mut sum, mut sq) = (0.0, 0.0);
        for (a, b) in hw.iter().zip(&levels) {
            for c in 0..3 {
                sum += (a[c] - b[c]).abs();
                sq += (a[c] - b[c]).powi(2);
            }
        }
        eprintln!(
            "reference {} (ray-marched, 180 samples, {secs:.2} s): mean |hw - ref| {:.3} levels, RMS {:.3} levels ({:.2} %)",
            path.display(),
            sum / n,
            (sq / n).sqrt(),
            (sq / n).sqrt() / 2.56
        );
    }
    if json {
        let v = serde_json::json!({
            "scene": scene.name,
            "counters": r.counters,
            "elaboration": r.elaboration,
            "predicted_seconds": pred.seconds,
            "predicted_by_pass": pred.by_kind,
            "predicted_seconds_geforce256": predict(&GpuModel::geforce256(), &r.passes).seconds,
            "wall_seconds": wall,
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
        );
        return Ok(());
    }
    println!(
        "{} ({}x{}, n = {}, m = {}): wrote {} in {wall:.2} s of simulation",
        scene.name,
        scene.image.width,
        scene.image.height,
        scene.shafts.planes,
        scene.shafts.subplanes,
        out.display()
    );
    print!("{}", crate::report::table::counters_table(&r.counters));
    println!("\nelaboration:");
    print!(
        "{}",
        crate::report::table::elaboration_table(&r.elaboration)
    );
    let (objects, shafts) = split_objects_shafts(&pred);
    println!(
        "\npredicted GeForce2 GTS time: {:.4} s (objects {:.4} s, shafts {:.4} s; {} passes, {} memory-bound)",
        pred.seconds, objects, shafts, pred.passes, pred.memory_bound_passes
    );
    println!(
        "predicted GeForce 256 (DDR) time: {:.4} s",
        predict(&GpuModel::geforce256(), &r.passes).seconds
    );
    Ok(())
}
