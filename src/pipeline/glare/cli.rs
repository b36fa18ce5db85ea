//! The glare pass run on its own (for the reproductions, sweeps and tests): the pass
//! and its prediction on the glare ASIC, and the f64 reference. `render` goes through
//! the frame (`crate::frame`).

use super::frame::{generator, interpolator, render_glare_with, GlareFrame};
use super::host::glare_of;
use super::throughput::{predict, GlarePrediction};
use crate::reference::glare_model::reference_image;
use crate::scene::format::Scene;
use rtl_model::{ConfigError, Unit};
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
    render_and_predict_with(scene, base, false)
}

/// [`render_and_predict_over`], with `record` also recording the pass's work for the
/// clocked chip ([`GlareFrame::work`]; `super::clocked::frame_timing` clocks it).
pub fn render_and_predict_with(
    scene: &Scene,
    base: Option<&[[u32; 3]]>,
    record: bool,
) -> Result<(GlareFrame, GlarePrediction, f64), ConfigError> {
    let t0 = Instant::now();
    let f = render_glare_with(scene, base, record)?;
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
