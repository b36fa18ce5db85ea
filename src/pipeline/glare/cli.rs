//! `render` for glare scenes: the frame through the units, its PNG, counters,
//! elaboration, predicted time, and optionally the f64 reference and the error.

use super::frame::{generator, glare_of, interpolator, render_glare_over, GlareFrame};
use super::throughput::{predict, GlarePrediction};
use crate::reference::glare_model::reference_image;
use crate::scene::format::Scene;
use rtl_model::{ConfigError, Unit};
use std::path::Path;
use std::time::Instant;

/// Set-up clocks per primitive (generator latency + interpolator set-up) and the
/// pipeline's drain (modulator + combiner latency) at the scene's widths.
pub fn setup_and_drain(f: &GlareFrame, coord_frac_bits: u32) -> Result<(u64, u64), ConfigError> {
    let ip = interpolator(coord_frac_bits)?;
    let setup = generator()?.timing().latency as u64 + ip.setup_cycles() as u64;
    let drain = f
        .units
        .iter()
        .filter(|u| u.name.ends_with("modulator") || u.name == "glare_combiner")
        .map(|u| u.latency as u64)
        .max()
        .unwrap_or(0)
        + 1;
    Ok((setup, drain))
}

/// Render and predict; returns the frame, the prediction and the wall time.
pub fn render_and_predict(
    scene: &Scene,
) -> Result<(GlareFrame, GlarePrediction, f64), ConfigError> {
    render_and_predict_over(scene, None)
}

/// [`render_and_predict`] over a background already drawn for this scene.
pub fn render_and_predict_over(
    scene: &Scene,
    base: Option<&[[u32; 3]]>,
) -> Result<(GlareFrame, GlarePrediction, f64), ConfigError> {
    let t0 = Instant::now();
    let f = render_glare_over(scene, base)?;
    let wall = t0.elapsed().as_secs_f64();
    let g = glare_of(scene)?;
    let (setup, drain) = setup_and_drain(&f, g.hw.coord_frac_bits)?;
    let p = predict(&f, g.hw.clock_mhz, g.hw.pipes, setup, drain);
    Ok((f, p, wall))
}

/// The f64 reference image in levels: the frame's own background and sources (with
/// the hardware's line draws and chaos values), the analytic formulas per pixel.
pub fn reference_levels(scene: &Scene, f: &GlareFrame) -> Result<Vec<[f64; 3]>, ConfigError> {
    let g = glare_of(scene)?;
    let max = rtl_model::unorm::max_code(g.hw.fb_bits) as f64;
    let base: Vec<[f64; 3]> = f.base.iter().map(|p| p.map(|v| v as f64)).collect();
    let img = reference_image(
        scene.image.width,
        scene.image.height,
        &base,
        &f.sources,
        &f.lines,
        &g.determinants,
        &g.model,
        max,
    );
    Ok(img.iter().map(|p| p.map(|v| v * 255.0 / max)).collect())
}

pub fn render_cli(
    scene: &Scene,
    out: &Path,
    json: bool,
    reference: Option<&Path>,
) -> Result<(), String> {
    render_cli_over(scene, None, out, json, reference)
}

/// [`render_cli`] over a background already drawn for this scene (fb codes, RGB).
pub fn render_cli_over(
    scene: &Scene,
    base: Option<&[[u32; 3]]>,
    out: &Path,
    json: bool,
    reference: Option<&Path>,
) -> Result<(), String> {
    let (f, pred, wall) = render_and_predict_over(scene, base).map_err(|e| e.to_string())?;
    f.fb.save_png(out)
        .map_err(|e| format!("out: {}: {e}", out.display()))?;
    let err = match reference {
        Some(path) => {
            let lv = reference_levels(scene, &f).map_err(|e| e.to_string())?;
            crate::report::image_out::levels_png(&lv, scene.image.width, scene.image.height, path)?;
            let st =
                crate::report::metrics::error_stats(&f.levels(), &lv).map_err(|e| e.to_string())?;
            Some(st)
        }
        None => None,
    };
    if json {
        let v = serde_json::json!({
            "scene": scene.name,
            "counters": f.counters,
            "elaboration": f.elaboration,
            "primitives": f.prims.len(),
            "prediction": pred,
            "wall_seconds": wall,
            "error_vs_reference": err,
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
        );
        return Ok(());
    }
    println!(
        "{} ({}x{}): wrote {} in {wall:.2} s of simulation; {} primitives ({} bloom, {} halo, {} flare lines)",
        scene.name,
        scene.image.width,
        scene.image.height,
        out.display(),
        f.prims.len(),
        f.prims.iter().filter(|p| p.kind == "bloom").count(),
        f.prims.iter().filter(|p| p.kind == "halo").count(),
        f.prims.iter().filter(|p| p.kind == "flare").count(),
    );
    print!("{}", crate::report::table::counters_table(&f.counters));
    println!("\nelaboration:");
    print!(
        "{}",
        crate::report::table::elaboration_table(&f.elaboration)
    );
    println!(
        "\npredicted glare time at {} MHz × {} pipes: {:.6} s ({} clocks: {} walking, {} table writes; {} fragments of {} walked pixels, {:.3e} fragments/s)",
        pred.clock_mhz, pred.pipes, pred.seconds, pred.cycles, pred.walk_cycles, pred.table_cycles, pred.fragments, pred.walked, pred.fragments_per_second
    );
    if let Some(st) = err {
        println!(
            "error against the f64 reference ({}): mean |Δ| {:.3}, RMS {:.3}, max {:.1} levels",
            reference.map_or(String::new(), |p| p.display().to_string()),
            st.mean_abs,
            st.rms,
            st.max
        );
    }
    Ok(())
}
