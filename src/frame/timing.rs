//! How a frame's time is found: the roofline formula over each pass's counters (the
//! default, `crate::chip::roofline`), or the clocked chip over what each pass did
//! (`--timing clocked`: every recorded pass clocked in full; `--timing sampled`: a
//! deterministic sample of the passes of each kind and of their screen bands (rows of
//! tiles) clocked and scaled, with its error, [`super::strata`]).
//!
//! With clocked or sampled timing the shafts passes, and a glare scene's glare pass,
//! record their work ([`crate::chip::work::PassWork`]) as they run; each pass's record
//! is handed, as
//! soon as the pass finishes, to the clock's thread, which clocks it while the frame
//! draws the next passes and then drops it, so a frame holds a few passes' records at
//! most ([`Clock`]). Passes that record nothing (the shading units' object pass, a glare
//! scene's shaded highlights) keep their roofline time and are listed as such.

use super::gpu::Gpu;
use super::plan::{Plan, Step};
use super::strata::{Strata, Stratum};
use crate::chip::clock::{clock_pass, FrameTiming, NamedPassTiming, PassTiming, RooflineOnlyPass};
use crate::chip::config::ChipConfig;
use crate::chip::work::{PassSample, PassWork, SampleBands};
use crate::chip::{pass_seconds, GpuModel, PassStats};
use crate::pipeline::shafts::frame::WorkSink;
use rtl_model::ConfigError;
use std::cell::RefCell;
use std::rc::Rc;

/// How the frame's time is found (`render --timing`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum TimingMode {
    /// max(fill, memory) + set-up per pass, with an assumed texture-cache hit rate.
    #[default]
    Roofline,
    /// Every pass's recorded work clocked through the chip's stages, caches and
    /// memory controller.
    Clocked,
    /// A deterministic sample of each pass's screen bands (rows of tiles) clocked
    /// exactly and scaled,
    /// with its estimated error.
    Sampled,
}

impl TimingMode {
    pub fn name(self) -> &'static str {
        match self {
            TimingMode::Roofline => "roofline",
            TimingMode::Clocked => "clocked",
            TimingMode::Sampled => "sampled",
        }
    }

    /// Whether the passes record their work for the clocked chip.
    pub fn records(self) -> bool {
        self != TimingMode::Roofline
    }
}

/// The chip a frame is timed on (`render --chip`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ChipName {
    /// GeForce 256 (DDR): 120 MHz, 4 pipes × 1 texture unit.
    #[value(name = "geforce256")]
    GeForce256,
    /// GeForce2 GTS: 200 MHz, 4 pipes × 2 texture units (the shafts paper's card).
    #[value(name = "geforce2-gts")]
    GeForce2Gts,
    /// GeForce3: 200 MHz, 4 pipes × 2 texture units, 4 textures per pass, 3D textures.
    #[value(name = "geforce3")]
    GeForce3,
    /// The glare ASIC (times a glare scene's glare pass).
    #[value(name = "glare-asic")]
    GlareAsic,
}

/// Every chip name, in the order `--chip` lists them.
pub const CHIP_NAMES: [&str; 4] = ["geforce256", "geforce2-gts", "geforce3", "glare-asic"];

impl ChipName {
    pub fn name(self) -> &'static str {
        match self {
            ChipName::GeForce256 => CHIP_NAMES[0],
            ChipName::GeForce2Gts => CHIP_NAMES[1],
            ChipName::GeForce3 => CHIP_NAMES[2],
            ChipName::GlareAsic => CHIP_NAMES[3],
        }
    }

    /// The GPU this chip is for a frame's GPU passes (`None`: the glare ASIC, which
    /// runs no GPU pass).
    pub fn gpu(self) -> Option<Gpu> {
        match self {
            ChipName::GeForce256 => Some(Gpu::GeForce256),
            ChipName::GeForce2Gts => Some(Gpu::GeForce2Gts),
            ChipName::GeForce3 => Some(Gpu::GeForce3),
            ChipName::GlareAsic => None,
        }
    }

    /// The chip name of a GPU.
    pub fn of_gpu(g: Gpu) -> ChipName {
        match g {
            Gpu::GeForce256 => ChipName::GeForce256,
            Gpu::GeForce2Gts => ChipName::GeForce2Gts,
            Gpu::GeForce3 => ChipName::GeForce3,
        }
    }
}

/// What `render` was asked for: the timing mode and the chip (`None`: the scene's
/// GPU, [`Gpu::for_scene`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TimingRequest {
    pub mode: TimingMode,
    pub chip: Option<ChipName>,
    /// The clocks of the frame (from its start) whose chip-level signals are traced
    /// for the VCD, START..END (`render --vcd-window`); `None`: none traced.
    pub window: Option<(u64, u64)>,
}

impl TimingRequest {
    /// The GPU the frame's GPU passes run on.
    pub fn gpu(&self, scene: &crate::scene::format::Scene) -> Gpu {
        self.chip
            .and_then(ChipName::gpu)
            .unwrap_or_else(|| Gpu::for_scene(scene))
    }
}

/// Refuse, before any pass runs, a request the frame cannot honour: `--chip
/// glare-asic` for a frame without a glare pass, and clocked or sampled timing of a
/// frame with a pass that cannot be clocked yet (the glare pass). The error names the
/// flag and what is supported.
pub fn check(req: &TimingRequest, plan: &Plan) -> Result<(), String> {
    let has_glare = plan.passes.iter().any(|p| p.step == Step::Glare);
    if req.chip == Some(ChipName::GlareAsic) && !has_glare {
        return Err(format!(
            "--chip glare-asic: this scene has no glare pass; its GPU passes run on {}",
            CHIP_NAMES[..3].join(", ")
        ));
    }
    if !req.mode.records() {
        return Ok(());
    }
    let glare_only = glare_only(plan);
    if let (true, Some(c)) = (glare_only, req.chip) {
        if c != ChipName::GlareAsic {
            return Err(format!(
                "--chip {}: a glare scene's pass runs on the glare ASIC; clocked and sampled \
                 timing clock it there (--chip glare-asic, the default)",
                c.name()
            ));
        }
    }
    for p in &plan.passes {
        match p.step {
            Step::Shafts(_) | Step::ShadedObjects | Step::ShadedHighlights => {}
            // A glare scene's one pass, on the glare ASIC.
            Step::Glare if glare_only => {}
            Step::Glare => {
                return Err(format!(
                    "--timing {}: the glare pass ({}) runs on the glare ASIC, a chip of its own \
                     beside this frame's GPU passes, and one clocked timing times one chip; \
                     clocked and sampled timing support the shafts scenes (fig4, fig6, stage and \
                     scene files without glare) and the glare scenes (glare-point, glare-flare, \
                     leaves, …); use --timing roofline (`reproduce glare-asic-throughput` \
                     clocks street-light's glare pass alone)",
                    req.mode.name(),
                    p.name
                ))
            }
            Step::TestScene | Step::EnvironmentScene => {
                return Err(unsupported_family(req.mode, "this scene"))
            }
        }
    }
    Ok(())
}

/// Whether the frame is a glare scene's one pass (clocked on the glare ASIC).
pub fn glare_only(plan: &Plan) -> bool {
    !plan.passes.is_empty() && plan.passes.iter().all(|p| p.step == Step::Glare)
}

/// The chip a frame's clocked or sampled timing runs on, resolved before any pass: a
/// glare scene's, the glare ASIC at the scene's `[glare.hw]`; else `--chip`'s preset or
/// the scene's GPU's.
pub fn frame_chip(
    req: &TimingRequest,
    scene: &crate::scene::format::Scene,
    plan: &Plan,
) -> Result<ChipConfig, String> {
    if glare_only(plan) {
        return crate::pipeline::glare::clocked::glare_chip(scene)
            .map_err(|e| format!("--timing {}: {e}", req.mode.name()));
    }
    chip_config(req.chip.unwrap_or(ChipName::of_gpu(req.gpu(scene))))
}

/// The refusal of clocked or sampled timing for a scene family without recorded work
/// (the foundation test scene, the environment-map scenes, the shading scenes).
pub fn unsupported_family(mode: TimingMode, family: &str) -> String {
    format!(
        "--timing {}: {family} has no recorded pass work to clock; clocked and sampled timing \
         support the shafts scenes (fig4, fig6, stage and scene files without glare) and \
         the glare scenes (glare-point, glare-flare, leaves, …); use --timing roofline",
        mode.name()
    )
}

/// The clocked chip's configuration for `chip`, resolved before any pass runs.
pub fn chip_config(chip: ChipName) -> Result<ChipConfig, String> {
    let c = match chip {
        // The glare ASIC at the default glare widths (a glare scene's own are
        // `pipeline::glare::clocked::glare_chip`).
        ChipName::GlareAsic => crate::pipeline::glare::asic_preset::glare_asic(),
        _ => ChipConfig::preset(chip.name()),
    };
    c.map_err(|e| format!("--chip {}: {e}", chip.name()))
}

/// Every how many screen bands (full-width 8-row tile rows) sampled timing clocks one.
pub const SAMPLE_EVERY: u32 = 8;

/// Of each kind's passes, sampled timing records and clocks the first two and then one
/// in this many ([`PassSample`]) when it samples the frame's bands.
pub const SAMPLE_PASS_EVERY: u32 = 8;

/// The screen bands the sampled mode records and clocks on a frame of `rows` pixel
/// rows: one band in [`SAMPLE_EVERY`], or fewer when the frame has too few bands for
/// every group to get one ([`crate::chip::clock::SAMPLE_GROUPS`]; one in 1: the frame
/// is clocked in full).
pub fn sample_bands(rows: u32) -> SampleBands {
    let band_rows = crate::chip::clock::SAMPLE_BAND_ROWS;
    let bands = rows.div_ceil(band_rows);
    let groups = crate::chip::clock::SAMPLE_GROUPS as u32;
    SampleBands {
        band_rows,
        block_cols: crate::chip::clock::SAMPLE_BLOCK_COLS,
        every: (bands / groups).clamp(1, SAMPLE_EVERY),
    }
}

/// One sampled pass: its timing and the relative standard error of its cycles. The
/// sampled bands' timeline (the groups clocked back to back) is stretched over the
/// pass's scaled cycles, so the frame's timeline reads the same in both modes.
fn clock_sampled(
    chip: &ChipConfig,
    work: &PassWork,
    bands: SampleBands,
) -> Result<(PassTiming, f64), ConfigError> {
    // A full record (the glare pass records every fragment) is cut to the sample.
    let cut;
    let work = if work.sample.is_some() || bands.every <= 1 {
        work
    } else {
        cut = work.sampled(bands);
        &cut
    };
    let (mut t, e) = crate::chip::clock::clock_pass_sampled(chip, work, bands.every)?;
    t.timeline.stretch(t.cycles);
    Ok((t, e))
}

/// One chip's timing of the frame as it is built, pass by pass.
struct ChipTimer {
    chip: ChipConfig,
    timing: FrameTiming,
    /// Sampled mode: the passes by kind, the clocked ones and those scaled from them.
    strata: Strata,
}

impl ChipTimer {
    fn new(mode: TimingMode, chip: ChipConfig) -> Self {
        let timing = FrameTiming {
            mode: mode.name().to_string(),
            chip: chip.name.clone(),
            clock_hz: chip.clock_hz,
            ..FrameTiming::default()
        };
        ChipTimer {
            chip,
            timing,
            strata: Strata::default(),
        }
    }

    /// Time one pass on this chip: clocked (in full, its clocks in `window` traced),
    /// sampled (its bands), or, in sampled mode for a pass that was not recorded, kept
    /// to be scaled from its kind's clocked passes at [`ChipTimer::finish`].
    fn take(
        &mut self,
        work: &PassWork,
        pass: NamedPassTiming,
        (mode, bands): (TimingMode, SampleBands),
        window: Option<&std::ops::Range<u64>>,
    ) -> Result<(), ConfigError> {
        let index = self.timing.passes.len();
        let stratum = work.stats.as_ref().map(Stratum::of);
        let timing = match (mode, work.unrecorded) {
            (TimingMode::Sampled, true) => {
                let Some(kind) = stratum else {
                    return Err(ConfigError::invalid(
                        "timing",
                        "internal: a pass without its record or its counters",
                    ));
                };
                self.strata
                    .unrecorded(kind, index, pass.roofline_seconds)
                    .map_err(|e| ConfigError::invalid("timing", &e))?;
                PassTiming::default()
            }
            (_, true) => {
                return Err(ConfigError::invalid(
                    "timing",
                    "internal: a pass without its record outside the sampled mode",
                ))
            }
            (TimingMode::Sampled, false) => {
                let (t, e) = clock_sampled(&self.chip, work, bands)?;
                // A pass without stats has no kind: its own stratum of one.
                let kind = stratum.unwrap_or(Stratum::Alone(index));
                self.strata
                    .recorded(kind, index, t.cycles, pass.roofline_seconds, e);
                t
            }
            _ => {
                // The frame's window in this pass's own clocks (a pass starts where the
                // one before it ended).
                let start = self.timing.cycles_total();
                let window = window.and_then(|w| crate::report::chip_timing::pass_window(w, start));
                clock_pass(&self.chip, work, window)?
            }
        };
        self.timing.passes.push(NamedPassTiming { timing, ..pass });
        Ok(())
    }

    /// The chip's frame timing. In sampled mode the passes that were not recorded get
    /// their estimate ([`Strata::finish`]), and the frame's relative error combines
    /// the kinds' (independent samples: the root of the summed variances in cycles²,
    /// over the frame's cycles); `every` is the sample's (bands, passes).
    fn finish(&mut self, mode: TimingMode, every: (u32, u32)) -> FrameTiming {
        if mode == TimingMode::Sampled {
            let var = std::mem::take(&mut self.strata).finish(&mut self.timing.passes);
            let total = self.timing.cycles_total();
            self.timing.sampling_error = (total > 0).then(|| var.sqrt() / total as f64);
            self.timing.sample_band_every = Some(every.0.max(1));
            self.timing.sample_pass_every = Some(every.1.max(1));
        }
        std::mem::take(&mut self.timing)
    }
}

/// The frame's clocked timing as it is built, pass by pass (on the clock's own thread:
/// [`Clock`]).
struct ClockState {
    mode: TimingMode,
    model: GpuModel,
    /// The frame pass whose work arrives next.
    pass: String,
    /// The frame's chip.
    main: ChipTimer,
    /// The frame's clocks traced for the VCD (START..END from the frame's start).
    window: Option<std::ops::Range<u64>>,
    /// The sampled mode's screen bands ([`sample_bands`] of the frame's rows).
    bands: SampleBands,
    /// Other chips each pass's record is also timed on, in the same mode (an
    /// architecture sweep: one functional frame, its records timed on every swept
    /// chip).
    alternates: Vec<ChipTimer>,
}

impl ClockState {
    fn new(mode: TimingMode, chip: ChipConfig, model: GpuModel) -> Self {
        ClockState {
            mode,
            model,
            pass: String::new(),
            main: ChipTimer::new(mode, chip),
            window: None,
            alternates: Vec::new(),
            bands: sample_bands(0),
        }
    }

    /// Also time every pass on each of `chips` (in the frame's mode, without a
    /// window).
    fn with_alternates(mut self, chips: Vec<ChipConfig>) -> Self {
        let mode = self.mode;
        self.alternates = chips.into_iter().map(|c| ChipTimer::new(mode, c)).collect();
        self
    }

    /// The alternate chips' frame timings, in the order they were given.
    fn take_alternates(&mut self) -> Vec<FrameTiming> {
        let (mode, every) = (self.mode, self.sample_every());
        std::mem::take(&mut self.alternates)
            .iter_mut()
            .map(|a| a.finish(mode, every))
            .collect()
    }

    /// Trace the chip-level signals over `window` (clocks from the frame's start).
    fn with_window(mut self, window: Option<(u64, u64)>) -> Self {
        self.window = window.map(|(a, b)| a..b);
        self
    }

    /// The bands the passes record the fragments of: the sample in sampled mode
    /// (every chip, the frame's and the alternates, clocks the same sample), else
    /// `None` (every fragment).
    fn record_bands(&self) -> Option<SampleBands> {
        let sampled = self.mode == TimingMode::Sampled && self.bands.every > 1;
        sampled.then_some(self.bands)
    }

    /// Which passes of each kind record their work: in sampled mode, when it records
    /// sampled bands ([`ClockState::record_bands`]), the first two and one in
    /// [`SAMPLE_PASS_EVERY`]; else every pass.
    fn record_passes(&self) -> PassSample {
        match self.record_bands() {
            Some(_) => PassSample {
                every: SAMPLE_PASS_EVERY,
            },
            None => PassSample::ALL,
        }
    }

    /// The sample's rates (one band in .0, of each kind one pass in .1 after two).
    fn sample_every(&self) -> (u32, u32) {
        (self.bands.every, self.record_passes().every)
    }

    /// The frame's height in pixels, which sets the sampled mode's bands.
    fn with_frame_rows(mut self, rows: u32) -> Self {
        self.bands = sample_bands(rows);
        self
    }

    /// Time one pass's record (or, in sampled mode, its counters alone) on the frame's
    /// chip and, side by side, on each alternate (each on its own chip: the same
    /// timings on any thread count).
    fn clock(&mut self, work: PassWork, formula: Option<f64>) -> Result<(), ConfigError> {
        let roofline_seconds = formula.unwrap_or_else(|| {
            work.stats
                .as_ref()
                .map_or(0.0, |s| pass_seconds(&self.model, s).0)
        });
        let pass = NamedPassTiming {
            pass: self.pass.clone(),
            roofline_seconds,
            ..NamedPassTiming::default()
        };
        let how = (self.mode, self.bands);
        use rayon::prelude::*;
        let alternates: Vec<Result<(), ConfigError>> = self
            .alternates
            .par_iter_mut()
            .map(|a| a.take(&work, pass.clone(), how, None))
            .collect();
        alternates
            .into_iter()
            .collect::<Result<(), ConfigError>>()?;
        self.main.take(&work, pass, how, self.window.as_ref())
    }

    /// A pass timed without the clock: appended on every chip as it is.
    fn timed(&mut self, pass: NamedPassTiming) {
        for a in &mut self.alternates {
            a.timing.passes.push(pass.clone());
        }
        self.main.timing.passes.push(pass);
    }

    /// Passes that recorded nothing: their roofline time, listed as such.
    fn roofline_only(&mut self, pass: &str, stats: &[PassStats]) {
        for s in stats {
            self.main.timing.roofline_only.push(RooflineOnlyPass {
                pass: pass.to_string(),
                kind: crate::chip::kind_name(s.kind).to_string(),
                seconds: pass_seconds(&self.model, s).0,
                why: "roofline (no recorded work)".to_string(),
            });
        }
    }

    /// The frame's timing on its chip ([`ChipTimer::finish`]).
    fn finish(&mut self) -> FrameTiming {
        let (mode, every) = (self.mode, self.sample_every());
        self.main.finish(mode, every)
    }
}

/// What the frame tells its clock, in the frame's order.
enum ClockMessage {
    /// The frame pass whose records follow.
    Begin(String),
    /// One pass's record (boxed: the message moves a pointer, not the record's
    /// vectors' headers), with the seconds of its own throughput formula when the GPU
    /// roofline does not time it (the glare ASIC's pass).
    Work(Box<PassWork>, Option<f64>),
    /// A pass timed without the clock (the glare ASIC's host table writes).
    Timed(Box<NamedPassTiming>),
    /// A pass that recorded nothing, with its counters (roofline time).
    RooflineOnly(String, Vec<PassStats>),
}

/// The messages the frame may send ahead of the clock's thread. With none, the frame
/// waits for every record to be clocked before it hands the next over, and the two
/// threads take turns; a few let the frame draw on while a slow record is clocked
/// (`render --scene fig6 --timing sampled`, wall, median of 3 on 2 cores: 2.67 s with
/// none, 2.34 s with 4, 2.30 s with 32).
const CLOCK_QUEUE: usize = 4;

/// The clock's thread: it takes the frame's messages in order and returns its state
/// when the frame drops the sender, or the first error.
type ClockWorker = (
    std::sync::mpsc::SyncSender<ClockMessage>,
    std::thread::JoinHandle<Result<ClockState, ConfigError>>,
);

/// The frame's clocked timing. The passes' records are clocked on a thread of the
/// clock's own while the frame draws its next pass (the functional frame leaves the
/// second core partly idle), strictly in the frame's order, so the timings are those of
/// clocking each record as it arrives, on any thread count. A frame holds at most
/// 6 records at once: the one being clocked, up to 4 waiting, and the
/// one being drawn.
pub struct Clock {
    /// The state before the first message (configured by the `with_` methods) and after
    /// [`Clock::finish`].
    state: Option<ClockState>,
    worker: Option<ClockWorker>,
    /// The worker's error, once it stopped on one.
    failed: Option<ConfigError>,
    /// The frame's chip (its state's copy moves to the worker with the state).
    chip: ChipConfig,
}

impl Clock {
    pub fn new(mode: TimingMode, chip: ChipConfig, model: GpuModel) -> Self {
        Clock {
            state: Some(ClockState::new(mode, chip.clone(), model)),
            worker: None,
            failed: None,
            chip,
        }
    }

    /// The chip the frame is timed on.
    pub fn chip(&self) -> &ChipConfig {
        &self.chip
    }

    /// Apply `f` to the state while it is still being configured.
    fn configure(mut self, f: impl FnOnce(ClockState) -> ClockState) -> Self {
        self.state = self.state.take().map(f);
        self
    }

    /// Also time every pass on each of `chips` (in the frame's mode, without a
    /// window); their frame timings come out of [`Clock::take_alternates`].
    pub fn with_alternates(self, chips: Vec<ChipConfig>) -> Self {
        self.configure(|s| s.with_alternates(chips))
    }

    /// Trace the chip-level signals over `window` (clocks from the frame's start).
    pub fn with_window(self, window: Option<(u64, u64)>) -> Self {
        self.configure(|s| s.with_window(window))
    }

    /// The frame's height in pixels, which sets the sampled mode's bands.
    pub fn with_frame_rows(self, rows: u32) -> Self {
        self.configure(|s| s.with_frame_rows(rows))
    }

    /// The bands the passes record the fragments of: the sample in sampled mode, else
    /// `None` (every fragment). Asked before the first pass.
    pub fn record_bands(&self) -> Option<SampleBands> {
        self.state.as_ref().and_then(ClockState::record_bands)
    }

    /// Which passes of each kind record their work ([`PassSample`]; every pass unless
    /// the sampled mode samples the frame). Asked before the first pass.
    pub fn record_passes(&self) -> PassSample {
        self.state
            .as_ref()
            .map_or(PassSample::ALL, ClockState::record_passes)
    }

    /// Hand `m` to the clock's thread (started on the first message). A thread that
    /// stopped on an error returns it here.
    fn send(&mut self, m: ClockMessage) -> Result<(), ConfigError> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        if self.worker.is_none() {
            let Some(mut state) = self.state.take() else {
                return Err(ConfigError::invalid(
                    "timing",
                    "internal: the clock has finished",
                ));
            };
            let (tx, rx) = std::sync::mpsc::sync_channel::<ClockMessage>(CLOCK_QUEUE);
            let handle = std::thread::spawn(move || {
                for m in rx {
                    match m {
                        ClockMessage::Begin(pass) => state.pass = pass,
                        ClockMessage::Work(w, formula) => state.clock(*w, formula)?,
                        ClockMessage::Timed(p) => state.timed(*p),
                        ClockMessage::RooflineOnly(pass, stats) => {
                            state.roofline_only(&pass, &stats)
                        }
                    }
                }
                Ok(state)
            });
            self.worker = Some((tx, handle));
        }
        let sent = self.worker.as_ref().map(|(tx, _)| tx.send(m));
        match sent {
            Some(Ok(())) => Ok(()),
            // The thread ended: it stopped on an error, which the join returns.
            _ => self.join(),
        }
    }

    /// Wait for the clock's thread to clock everything sent; its state comes back.
    fn join(&mut self) -> Result<(), ConfigError> {
        if let Some((tx, handle)) = self.worker.take() {
            drop(tx);
            match handle.join() {
                Ok(Ok(state)) => self.state = Some(state),
                Ok(Err(e)) => self.failed = Some(e),
                Err(panic) => std::panic::resume_unwind(panic),
            }
        }
        match &self.failed {
            Some(e) => Err(e.clone()),
            None => Ok(()),
        }
    }

    /// The frame pass whose records follow.
    pub fn begin(&mut self, pass: &str) -> Result<(), ConfigError> {
        self.send(ClockMessage::Begin(pass.to_string()))
    }

    /// Clock one pass's record (on the clock's thread; an error surfaces at the next
    /// message or at [`Clock::finish`]).
    pub fn clock(&mut self, work: PassWork) -> Result<(), ConfigError> {
        self.send(ClockMessage::Work(Box::new(work), None))
    }

    /// [`Clock::clock`] for a pass the GPU roofline does not time: `formula_seconds`,
    /// its own throughput formula's, stands beside its clocked time.
    pub fn clock_with_formula(
        &mut self,
        work: PassWork,
        formula_seconds: f64,
    ) -> Result<(), ConfigError> {
        self.send(ClockMessage::Work(Box::new(work), Some(formula_seconds)))
    }

    /// A pass timed without the clock, appended in the frame's order.
    pub fn timed(&mut self, pass: NamedPassTiming) -> Result<(), ConfigError> {
        self.send(ClockMessage::Timed(Box::new(pass)))
    }

    /// Passes that recorded nothing: their roofline time, listed as such.
    pub fn roofline_only(&mut self, pass: &str, stats: &[PassStats]) -> Result<(), ConfigError> {
        self.send(ClockMessage::RooflineOnly(pass.to_string(), stats.to_vec()))
    }

    /// The frame's timing, once every record sent is clocked. In sampled mode its
    /// relative error combines the passes' (independent samples: the root of the
    /// summed squared errors in cycles, over the frame's cycles).
    pub fn finish(&mut self) -> Result<FrameTiming, ConfigError> {
        self.join()?;
        self.state
            .as_mut()
            .map(ClockState::finish)
            .ok_or_else(|| ConfigError::invalid("timing", "internal: the clock has no state"))
    }

    /// The alternate chips' frame timings, in the order they were given (after
    /// [`Clock::finish`]).
    pub fn take_alternates(&mut self) -> Vec<FrameTiming> {
        self.state
            .as_mut()
            .map(ClockState::take_alternates)
            .unwrap_or_default()
    }
}

/// A sink for the shafts frame that clocks each pass's record as it arrives.
pub fn sink(clock: &Rc<RefCell<Clock>>) -> WorkSink {
    let c = Rc::clone(clock);
    Box::new(move |w| c.borrow_mut().clock(w))
}
