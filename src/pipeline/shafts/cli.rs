//! The shafts pipeline run on its own (for the reproductions, sweeps and tests): a
//! frame and its GeForce2 GTS prediction, and the ray-marched reference. `render`
//! goes through the frame (`crate::frame`).

use super::frame::{render_frame, FrameResult};
use super::host::prepare_scene;
use super::prepare::DEFAULT_EXPOSURE;
use crate::chip::{predict, GpuModel, Prediction};
use crate::reference::raymarch::{raymarch_image, to_levels};
pub use crate::report::image_out::levels_png;
use crate::scene::format::Scene;
use std::time::Instant;

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
