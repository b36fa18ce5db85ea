//! Run a frame: the planned passes in order over one frame state, and one time model
//! for the chip (the GPU passes on the configured GPU model, the glare pass on the
//! glare ASIC at its own clock and pipes, summed).

use super::glare_link::{self, Linked};
use super::objects::{shaded_objects_pass, ShadedObjects};
use super::plan::{plan, Plan, Step};
use crate::pipeline::glare::background::from_framebuffer;
use crate::pipeline::glare::cli::render_and_predict_over;
use crate::pipeline::glare::frame::GlareFrame;
use crate::pipeline::glare::throughput::GlarePrediction;
use crate::pipeline::shafts::frame::{FrameResult, ShaftsFrame};
use crate::pipeline::time_model::{pass_seconds, GpuModel, PassStats};
use crate::report::image_out::Framebuffer;
use crate::scene::format::Scene;
use rtl_model::{ConfigError, Counters};
use serde::Serialize;
use std::collections::BTreeMap;
use std::time::Instant;

/// Which GPU runs the frame's GPU passes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Gpu {
    GeForce2Gts,
    GeForce3,
}

impl Gpu {
    /// GeForce3 when the scene needs its 3D textures (an environment map), else the
    /// GeForce2 GTS the shafts paper measured on.
    pub fn for_scene(scene: &Scene) -> Gpu {
        if scene.environment.is_some() {
            Gpu::GeForce3
        } else {
            Gpu::GeForce2Gts
        }
    }

    pub fn model(self) -> GpuModel {
        match self {
            Gpu::GeForce2Gts => GpuModel::geforce2_gts(),
            Gpu::GeForce3 => GpuModel::geforce3(),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Gpu::GeForce2Gts => "GeForce2 GTS",
            Gpu::GeForce3 => "GeForce3",
        }
    }
}

/// One pass's predicted time.
#[derive(Clone, Debug, Serialize)]
pub struct PassTime {
    pub pass: String,
    /// "GeForce2 GTS", "GeForce3" or "glare ASIC (f MHz × p pipes)".
    pub on: String,
    pub seconds: f64,
    /// Wall time the simulation of this pass took.
    pub wall_seconds: f64,
}

/// A rendered frame.
pub struct Frame {
    pub plan: Plan,
    /// The final picture.
    pub fb: Framebuffer,
    pub shafts: Option<FrameResult>,
    pub shaded: Option<ShadedObjects>,
    pub linked: Option<Linked>,
    pub glare: Option<(GlareFrame, GlarePrediction)>,
    pub gpu: Gpu,
    pub times: Vec<PassTime>,
    pub wall_seconds: f64,
}

impl Frame {
    /// Predicted frame time: the sum over passes.
    pub fn predicted_seconds(&self) -> f64 {
        self.times.iter().map(|t| t.seconds).sum()
    }

    /// The counters of every pipeline, each under its pipeline's name.
    pub fn counters(&self) -> BTreeMap<String, BTreeMap<String, Counters>> {
        let mut out = BTreeMap::new();
        if let Some(s) = &self.shafts {
            out.insert("shafts".to_string(), s.counters.clone());
        }
        if let Some(s) = &self.shaded {
            out.insert("shading".to_string(), s.counters.clone());
        }
        if let Some(l) = &self.linked {
            out.insert("shading".to_string(), l.shading.counters.clone());
        }
        if let Some((g, _)) = &self.glare {
            out.insert("glare".to_string(), g.counters.clone());
        }
        out
    }
}

/// Render a scene through its planned passes.
pub fn render(scene: &Scene) -> Result<Frame, ConfigError> {
    render_on(scene, Gpu::for_scene(scene))
}

/// [`render`] with the GPU passes timed on `gpu`.
pub fn render_on(scene: &Scene, gpu: Gpu) -> Result<Frame, ConfigError> {
    let t0 = Instant::now();
    let plan = plan(scene)?;
    let model = gpu.model();
    let mut times = Vec::new();
    let mut shafts = match &plan.prepared {
        Some(p) => Some(ShaftsFrame::new(p, None)?),
        None => None,
    };
    let mut shafts_done: Option<FrameResult> = None;
    let mut shaded: Option<ShadedObjects> = None;
    let mut linked: Option<Linked> = None;
    let mut glare = None;
    let gpu_time = |name: &str, stats: &[PassStats], t: Instant| PassTime {
        pass: name.to_string(),
        on: gpu.name().to_string(),
        seconds: stats.iter().map(|s| pass_seconds(&model, s).0).sum(),
        wall_seconds: t.elapsed().as_secs_f64(),
    };
    for pass in &plan.passes {
        let t = Instant::now();
        match pass.step {
            Step::TestScene | Step::EnvironmentScene => {
                return Err(ConfigError::invalid(
                    "scene",
                    "the foundation test scene and the thesis' environment scenes render through `render` alone (their own frame)",
                ))
            }
            Step::Shafts(sp) => {
                let f = shafts.as_mut().ok_or_else(no_shafts)?;
                let before = f.pass_stats().len();
                f.run(sp)?;
                times.push(gpu_time(&pass.name, &f.pass_stats()[before..], t));
            }
            Step::ShadedObjects => {
                let f = shafts.as_mut().ok_or_else(no_shafts)?;
                let p = plan.prepared.as_ref().ok_or_else(no_shafts)?;
                let hl = scene
                    .glare
                    .as_ref()
                    .and_then(|g| g.shaded_highlights)
                    .map(|h| (h.light, h.intensity, h.radius));
                let refl = super::reflection::reflections(scene)?;
                let s = shaded_objects_pass(scene, p, f.framebuffer_mut(), hl, &refl)?;
                times.push(gpu_time(&pass.name, &s.stats, t));
                shaded = Some(s);
            }
            Step::ShadedHighlights => {
                linked = glare_link::prepare(scene)?;
            }
            Step::Glare => {
                if let Some(f) = shafts.take() {
                    shafts_done = Some(f.finish());
                }
                let mut gs = match &linked {
                    Some(l) => l.scene.clone(),
                    None => scene.clone(),
                };
                if let (Some(s), Some(g)) = (&shaded, gs.glare.as_mut()) {
                    g.highlights
                        .extend(s.highlights.iter().map(|h| h.highlight));
                }
                let hw = gs.glare.as_ref().map(|g| g.hw).unwrap_or_default();
                let base: Option<Vec<[u32; 3]>> = match (&shafts_done, &linked) {
                    (Some(r), _) => Some(from_framebuffer(&r.fb, hw.fb_bits)),
                    (None, Some(l)) => Some(l.base.clone()),
                    (None, None) => None,
                };
                let (g, pred, _) = render_and_predict_over(&gs, base.as_deref())?;
                times.push(PassTime {
                    pass: pass.name.clone(),
                    on: format!("glare ASIC ({} MHz × {} pipes)", pred.clock_mhz, pred.pipes),
                    seconds: pred.seconds,
                    wall_seconds: t.elapsed().as_secs_f64(),
                });
                glare = Some((g, pred));
            }
        }
    }
    if let Some(f) = shafts.take() {
        shafts_done = Some(f.finish());
    }
    let fb = match (&glare, &shafts_done) {
        (Some((g, _)), _) => g.fb.clone(),
        (None, Some(r)) => r.fb.clone(),
        (None, None) => {
            return Err(ConfigError::invalid(
                "scene",
                "nothing to draw: no objects, no lights in a medium and no glare",
            ))
        }
    };
    Ok(Frame {
        plan,
        fb,
        shafts: shafts_done,
        shaded,
        linked,
        glare,
        gpu,
        times,
        wall_seconds: t0.elapsed().as_secs_f64(),
    })
}

fn no_shafts() -> ConfigError {
    ConfigError::invalid("scene", "a shafts pass was planned without its set-up")
}

/// The picture a glare scene's shafts passes draw (its glare left to the glare pass):
/// the shafts passes of its plan, run alone.
pub fn shafts_backdrop(scene: &Scene) -> Result<Framebuffer, ConfigError> {
    let plan = plan(scene)?;
    let p = plan.prepared.as_ref().ok_or_else(no_shafts)?;
    let mut f = ShaftsFrame::new(p, None)?;
    for pass in &plan.passes {
        match pass.step {
            Step::Shafts(sp) => f.run(sp)?,
            Step::ShadedObjects => {
                let refl = super::reflection::reflections(scene)?;
                shaded_objects_pass(scene, p, f.framebuffer_mut(), None, &refl)?;
            }
            _ => {}
        }
    }
    Ok(f.finish().fb)
}
