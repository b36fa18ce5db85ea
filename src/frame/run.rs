//! Run a frame: the planned passes in order over one frame state, and one time model
//! for the chip (the GPU passes on the configured GPU model, the glare pass on the
//! glare ASIC at its own clock and pipes, summed).

use super::glare_link::{self, Linked};
use super::gpu::Gpu;
use super::objects::{shaded_objects_pass, shading_stats, ShadedObjects};
use super::plan::{plan, Pass, Plan, Step};
use super::timing::{Clock, TimingRequest};
use crate::chip::clock::FrameTiming;
use crate::chip::{pass_seconds, GpuModel, PassStats};
use crate::pipeline::glare::background::from_framebuffer;
use crate::pipeline::glare::cli::render_and_predict_with;
use crate::pipeline::glare::clocked;
use crate::pipeline::glare::frame::GlareFrame;
use crate::pipeline::glare::throughput::GlarePrediction;
use crate::pipeline::shafts::frame::{FrameResult, ShaftsFrame, ShaftsPass};
use crate::report::image_out::Framebuffer;
use crate::scene::format::Scene;
use rtl_model::{ConfigError, Counters};
use serde::Serialize;
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::rc::Rc;
use std::time::Instant;

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
    /// The clocked chip's timing (`render --timing clocked|sampled`), beside the
    /// roofline's `times`; `None` with the default roofline timing.
    pub timing: Option<FrameTiming>,
    /// The frame's recorded work clocked on other chips (`render_swept`), in order.
    pub swept_timings: Vec<FrameTiming>,
}

impl Frame {
    /// Predicted frame time: the sum over passes.
    pub fn predicted_seconds(&self) -> f64 {
        self.times.iter().map(|t| t.seconds).sum()
    }

    /// Every pipeline's elaboration at the scene's widths (shafts, shading, glare),
    /// in that order: the units the frame elaborated and those it left out.
    pub fn elaboration(&self) -> Vec<crate::report::elaboration::Elaborated> {
        [
            self.shafts.as_ref().map(|s| s.elaboration.clone()),
            self.shaded.as_ref().map(|s| s.elaboration.clone()),
            self.linked.as_ref().map(|l| l.shading.elaboration.clone()),
            self.glare.as_ref().map(|(g, _)| g.elaboration.clone()),
        ]
        .into_iter()
        .flatten()
        .flatten()
        .collect()
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
    render_inner(scene, gpu, None, None).map(|(f, _)| f)
}

/// [`render`] timed as `req` asks: on its chip (the scene's GPU by default), and with
/// clocked or sampled timing the shafts passes' recorded work clocked on that chip's
/// clocked configuration `chip` ([`super::timing::chip_config`], resolved before any
/// pass runs) into [`Frame::timing`]. `bar` as [`render_with_progress`]'s `shown`
/// (`None`: no bar).
pub fn render_timed(
    scene: &Scene,
    req: &TimingRequest,
    chip: Option<crate::chip::config::ChipConfig>,
    bar: Option<bool>,
) -> Result<(Frame, (u64, u64)), ConfigError> {
    render_swept(scene, req, chip, Vec::new(), bar)
}

/// [`render_timed`] whose recorded work is also clocked on each of `alternates` (an
/// architecture sweep: one functional frame, every swept chip): their frame timings
/// are [`Frame::swept_timings`], in order.
pub fn render_swept(
    scene: &Scene,
    req: &TimingRequest,
    chip: Option<crate::chip::config::ChipConfig>,
    alternates: Vec<crate::chip::config::ChipConfig>,
    bar: Option<bool>,
) -> Result<(Frame, (u64, u64)), ConfigError> {
    let gpu = req.gpu(scene);
    let clock = match (req.mode.records(), chip) {
        (false, _) => None,
        (true, Some(c)) => Some(
            Clock::new(req.mode, c, gpu.model())
                .with_window(req.window)
                .with_alternates(alternates)
                .with_frame_rows(scene.image.height),
        ),
        (true, None) => {
            return Err(ConfigError::invalid(
                "chip",
                "clocked timing needs the chip's clocked configuration",
            ))
        }
    };
    render_inner(scene, gpu, bar, clock)
}

/// [`render`] with a progress bar on stderr (`report::progress::FrameProgress`, drawn
/// when `shown` and stderr is a terminal outside CI): one step per sample plane of
/// each light and one per other pass ([`progress_steps`]). Returns the frame and the
/// bar's (position, length) at the end, which are equal for a frame that finished.
/// The bar changes no pixel and no counter.
pub fn render_with_progress(
    scene: &Scene,
    shown: bool,
) -> Result<(Frame, (u64, u64)), ConfigError> {
    render_inner(scene, Gpu::for_scene(scene), Some(shown), None)
}

/// The steps of a frame's bar: the sample planes of each planes pass (one step per
/// plane, its sub-planes included), one per other pass.
pub fn progress_steps(scene: &Scene, plan: &Plan) -> u64 {
    let planes = plan
        .prepared
        .as_ref()
        .map_or(scene.shafts.planes, |p| p.scene.shafts.planes);
    plan.passes
        .iter()
        .map(|p| match p.step {
            Step::Shafts(ShaftsPass::Planes { .. }) => u64::from(planes),
            _ => 1,
        })
        .sum()
}

fn render_inner(
    scene: &Scene,
    gpu: Gpu,
    bar: Option<bool>,
    clock: Option<Clock>,
) -> Result<(Frame, (u64, u64)), ConfigError> {
    let t0 = Instant::now();
    let plan = plan(scene)?;
    let progress = bar.map(|shown| {
        crate::report::progress::FrameProgress::install(
            progress_steps(scene, &plan),
            &scene.name,
            shown,
        )
    });
    let mut state = FrameState::new(scene, &plan, gpu)?;
    if let Some(c) = clock {
        state.clock_with(c);
    }
    for pass in &plan.passes {
        state.run(pass)?;
        if !matches!(pass.step, Step::Shafts(ShaftsPass::Planes { .. })) {
            crate::report::progress::frame_step(1);
        }
    }
    state.finish_shafts();
    let at = progress
        .as_ref()
        .map_or((0, 0), |p| (p.position(), p.length()));
    drop(progress);
    let FrameState {
        shafts_done,
        shaded,
        linked,
        glare,
        times,
        clock,
        ..
    } = state;
    let (timing, swept_timings) = match clock {
        Some(c) => {
            let mut c = c.borrow_mut();
            (Some(c.finish()?), c.take_alternates())
        }
        None => (None, Vec::new()),
    };
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
    Ok((
        Frame {
            plan,
            fb,
            shafts: shafts_done,
            shaded,
            linked,
            glare,
            gpu,
            times,
            wall_seconds: t0.elapsed().as_secs_f64(),
            timing,
            swept_timings,
        },
        at,
    ))
}

/// The picture a glare scene's passes draw before its glare (the shafts passes and the
/// object pass), for a glare study that reuses it.
pub fn shafts_backdrop(scene: &Scene) -> Result<Framebuffer, ConfigError> {
    let plan = plan(scene)?;
    let mut state = FrameState::new(scene, &plan, Gpu::for_scene(scene))?;
    for pass in plan.passes.iter().filter(|p| p.step != Step::Glare) {
        state.run(pass)?;
    }
    state.finish_shafts();
    state.shafts_done.map(|r| r.fb).ok_or_else(no_shafts)
}

/// The frame's state between passes.
struct FrameState<'a> {
    scene: &'a Scene,
    plan: &'a Plan,
    gpu: Gpu,
    model: GpuModel,
    /// The shafts passes' state while they run, and their result after.
    shafts: Option<ShaftsFrame<'a>>,
    shafts_done: Option<FrameResult>,
    shaded: Option<ShadedObjects>,
    linked: Option<Linked>,
    glare: Option<(GlareFrame, GlarePrediction)>,
    times: Vec<PassTime>,
    /// The clocked chip's timing as the passes run (clocked or sampled timing).
    clock: Option<Rc<RefCell<Clock>>>,
}

impl<'a> FrameState<'a> {
    /// Clock the passes' recorded work on `c`: the shafts passes record from now on,
    /// and the glare pass when it runs.
    fn clock_with(&mut self, c: Clock) {
        let c = Rc::new(RefCell::new(c));
        if let Some(f) = self.shafts.as_mut() {
            let (bands, passes) = (c.borrow().record_bands(), c.borrow().record_passes());
            f.record_work_sampled(super::timing::sink(&c), bands, passes);
        }
        self.clock = Some(c);
    }

    fn new(scene: &'a Scene, plan: &'a Plan, gpu: Gpu) -> Result<Self, ConfigError> {
        Ok(FrameState {
            scene,
            plan,
            gpu,
            model: gpu.model(),
            shafts: match &plan.prepared {
                Some(p) => Some(ShaftsFrame::new(p, None)?),
                None => None,
            },
            shafts_done: None,
            shaded: None,
            linked: None,
            glare: None,
            times: Vec::new(),
            clock: None,
        })
    }

    /// Run one pass and time it.
    fn run(&mut self, pass: &Pass) -> Result<(), ConfigError> {
        let t = Instant::now();
        match pass.step {
            Step::TestScene | Step::EnvironmentScene => Err(ConfigError::invalid(
                "scene",
                "the foundation test scene and the thesis' environment scenes render through `render` alone (their own frame)",
            )),
            Step::Shafts(sp) => self.shafts_pass(sp, &pass.name, t),
            Step::ShadedObjects => self.object_pass(&pass.name, t),
            Step::ShadedHighlights => self.shaded_highlights(&pass.name, t),
            Step::Glare => self.glare_pass(&pass.name, t),
        }
    }

    /// GPU passes' statistics timed on the frame's GPU.
    fn gpu_time(&mut self, name: &str, stats: &[PassStats], t: Instant) {
        self.times.push(PassTime {
            pass: name.to_string(),
            on: self.gpu.name().to_string(),
            seconds: stats.iter().map(|s| pass_seconds(&self.model, s).0).sum(),
            wall_seconds: t.elapsed().as_secs_f64(),
        });
    }

    fn shafts_pass(&mut self, sp: ShaftsPass, name: &str, t: Instant) -> Result<(), ConfigError> {
        let f = self.shafts.as_mut().ok_or_else(no_shafts)?;
        let before = f.pass_stats().len();
        if let Some(c) = &self.clock {
            c.borrow_mut().begin(name)?;
        }
        f.run(sp)?;
        let stats = f.pass_stats()[before..].to_vec();
        self.gpu_time(name, &stats, t);
        Ok(())
    }

    /// The shading units and environment reflections into the shafts framebuffer.
    fn object_pass(&mut self, name: &str, t: Instant) -> Result<(), ConfigError> {
        let p = self.plan.prepared.as_ref().ok_or_else(no_shafts)?;
        let f = self.shafts.as_mut().ok_or_else(no_shafts)?;
        let hl = self
            .scene
            .glare
            .as_ref()
            .and_then(|g| g.shaded_highlights)
            .map(|h| (h.light, h.intensity, h.radius));
        let refl = super::reflection::reflections(self.scene)?;
        let s = shaded_objects_pass(self.scene, p, f.framebuffer_mut(), hl, &refl)?;
        self.gpu_time(name, &s.stats, t);
        if let Some(c) = &self.clock {
            c.borrow_mut().roofline_only(name, &s.stats)?;
        }
        self.shaded = Some(s);
        Ok(())
    }

    /// A glare scene's objects through the shading units over its own background.
    fn shaded_highlights(&mut self, name: &str, t: Instant) -> Result<(), ConfigError> {
        self.linked = glare_link::prepare(self.scene)?;
        if let Some(l) = &self.linked {
            let light = self
                .scene
                .glare
                .as_ref()
                .and_then(|g| g.shaded_highlights)
                .map_or(0, |h| h.light);
            let stats = [shading_stats(light, l.shading.fragments)];
            self.gpu_time(name, &stats, t);
            if let Some(c) = &self.clock {
                c.borrow_mut().roofline_only(name, &stats)?;
            }
        }
        Ok(())
    }

    /// The glare over the finished picture, with the highlights the shading found.
    fn glare_pass(&mut self, name: &str, t: Instant) -> Result<(), ConfigError> {
        self.finish_shafts();
        let mut gs = match &self.linked {
            Some(l) => l.scene.clone(),
            None => self.scene.clone(),
        };
        if let (Some(s), Some(g)) = (&self.shaded, gs.glare.as_mut()) {
            g.highlights
                .extend(s.highlights.iter().map(|h| h.highlight));
        }
        let hw = gs.glare.as_ref().map(|g| g.hw).unwrap_or_default();
        let base: Option<Vec<[u32; 3]>> = match (&self.shafts_done, &self.linked) {
            (Some(r), _) => Some(from_framebuffer(&r.fb, hw.fb_bits)),
            (None, Some(l)) => Some(l.base.clone()),
            (None, None) => None,
        };
        let record = self.clock.is_some();
        let (mut g, pred, _) = render_and_predict_with(&gs, base.as_deref(), record)?;
        if let (Some(c), Some(work)) = (&self.clock, g.work.take()) {
            // The glare ASIC's pass beside its own formula, then the host's table writes.
            let mut c = c.borrow_mut();
            let chip = c.chip().clone();
            let formula = clocked::formula(&g, &gs, &chip)?;
            c.begin(name)?;
            c.clock_with_formula(work, formula.walk_cycles as f64 / chip.clock_hz)?;
            if let Some(tables) = clocked::tables_pass(&g, &formula, &chip) {
                c.timed(tables)?;
            }
        }
        self.times.push(PassTime {
            pass: name.to_string(),
            on: format!("glare ASIC ({} MHz × {} pipes)", pred.clock_mhz, pred.pipes),
            seconds: pred.seconds,
            wall_seconds: t.elapsed().as_secs_f64(),
        });
        self.glare = Some((g, pred));
        Ok(())
    }

    /// Close the shafts passes' state into their result (once).
    fn finish_shafts(&mut self) {
        if let Some(f) = self.shafts.take() {
            self.shafts_done = Some(f.finish());
        }
    }
}

fn no_shafts() -> ConfigError {
    ConfigError::invalid("scene", "a shafts pass was planned without its set-up")
}
