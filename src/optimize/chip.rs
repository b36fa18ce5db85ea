//! `optimize` over the clocked chip's architecture (`--params` naming the chip's
//! parameters: `cache_kb`, `fifo_depth`, `pipes`, …) within a time budget
//! (`--budget "seconds<=0.17"`): the cheapest chip found whose clocked frame time
//! meets the budget. The pixels do not depend on the architecture, so each round
//! draws the frame once and clocks its recorded work on every chip the round tries
//! (the current one and one step down and up each parameter's ladder).
//!
//! The search is a greedy descent: while the current chip misses the budget, take the
//! step up that buys the most time per unit of cost; once it meets it, take the step
//! down that saves the most cost and still meets it; stop when no step is left. Cost
//! only falls once the budget is met and the budget is never left again, so it ends.
//!
//! What a chip costs (docs/optimize.md "The chip's architecture"): gates are the
//! frame's elaborated units, one set per pipe, with `tmus` texture units per pipe each
//! as large as the largest texture sampler the frame elaborated; RAM bits are what the
//! architecture adds: the texture caches' data, the FIFOs' entries and the memory
//! controller's request queue.

use super::cli::OptimizeArgs;
use super::eval::RAM_BIT_NAND2;
use super::search::Objective;
use crate::chip::clock::{fifo_names, FrameTiming};
use crate::chip::config::ChipConfig;
use crate::chip::params::{texture_cache_bits, ChipParam};
use crate::frame::gpu::Gpu;
use crate::frame::run::render_swept;
use crate::frame::timing::{check, ChipName, TimingMode, TimingRequest};
use crate::report::atomic::write_bytes;
use crate::report::csv_out::write_csv;
use crate::report::elaboration::Elaborated;
use crate::report::plot::{points_plot, Axis, PlotSpec, Series};
use crate::scene::format::Scene;
use serde::Serialize;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Bits of one FIFO entry: a 2×2 quad of fragments, each with its pixel (2 × 16), depth
/// (24), colour (4 × 8), two texture coordinates (2 × 2 × 16) and a coverage bit,
/// rounded up to 160 (assumed: the FIFOs carry what the stages hand on).
pub const FIFO_ENTRY_BITS: u64 = 4 * 160;

/// Bits of one memory request the controller queues: a 32-bit address, a 16-bit
/// length, the client (2) and the issuing unit's tag (14) (assumed).
pub const MEMORY_REQUEST_BITS: u64 = 64;

/// Does the comma list `--params` name any of the chip's parameters?
pub fn names_chip_params(list: &str) -> bool {
    list.split(',')
        .any(|n| ChipParam::from_name(n.trim()).is_some())
}

/// The parameters an architecture search may change: those that change the chip's
/// area. The memory's bandwidth and latency and the clock are the board's and the
/// process's, not the chip's area: `sweep` them.
fn searchable(p: ChipParam) -> bool {
    !matches!(
        p,
        ChipParam::BandwidthMbs | ChipParam::MemLatency | ChipParam::ClockMhz
    )
}

/// The values a parameter steps through (each checked against the chip by
/// `steps`): powers of two, the texture units one by one, the cache 0 (none) to 256
/// KiB.
pub fn ladder(p: ChipParam) -> Vec<u32> {
    let pow2 = |lo: u32, hi: u32| -> Vec<u32> {
        (0..32)
            .map(|k| 1u32 << k)
            .filter(|v| (lo..=hi).contains(v))
            .collect()
    };
    match p {
        ChipParam::Pipes => pow2(1, 16),
        ChipParam::Tmus => (1..=4).collect(),
        ChipParam::FifoDepth => pow2(1, 1024),
        ChipParam::CacheKb => std::iter::once(0).chain(pow2(1, 256)).collect(),
        ChipParam::CacheLine => pow2(8, 256),
        ChipParam::CacheWays => pow2(1, 16),
        ChipParam::MissesInFlight | ChipParam::MemQueue => pow2(1, 256),
        ChipParam::BandwidthMbs | ChipParam::MemLatency | ChipParam::ClockMhz => Vec::new(),
    }
}

/// The checked search.
pub struct ChipPlan {
    pub scene_arg: String,
    pub scene: Scene,
    pub params: Vec<ChipParam>,
    /// The time budget: the clocked frame's seconds at most this.
    pub limit_seconds: f64,
    pub objective: Objective,
    pub out: PathBuf,
    /// The scene's chip (the search starts from it).
    pub base: ChipConfig,
    /// At most this many chips clocked.
    pub max_evals: Option<usize>,
    /// No round started after this many seconds.
    pub seconds: Option<f64>,
    /// How each candidate chip times the frame: clocked or sampled.
    pub mode: TimingMode,
}

/// `seconds<=S` (spaces allowed): the time budget's limit; errors name `budget`.
pub fn parse_time_budget(text: &str) -> Result<f64, String> {
    let bad = |why: &str| {
        format!(
            "budget: '{text}' {why} (an architecture search takes one time budget, \
             seconds<=S: the clocked frame time in seconds, e.g. \"seconds<=0.17\")"
        )
    };
    let (m, v) = text.split_once("<=").ok_or_else(|| bad("has no '<='"))?;
    if !m.trim().eq_ignore_ascii_case("seconds") {
        return Err(bad(
            "is not a time budget: the chip's architecture changes no pixel, so it has no \
             error to limit",
        ));
    }
    let s: f64 = v
        .trim()
        .parse()
        .map_err(|_| bad("has a limit that is not a number"))?;
    if !(s.is_finite() && s > 0.0) {
        return Err(bad("has a limit that is not a positive number of seconds"));
    }
    Ok(s)
}

/// Every argument checked before any work, each error naming its argument (the
/// scene loaded from `a.scene`: a scene of lights and objects).
pub fn check_chip(a: &OptimizeArgs) -> Result<ChipPlan, String> {
    check_chip_on(a, crate::scene::load::load_frame_scene(&a.scene)?)
}

/// [`check_chip`] of the scene `a.scene` loaded to.
pub fn check_chip_on(a: &OptimizeArgs, mut scene: Scene) -> Result<ChipPlan, String> {
    crate::scene::load::apply_image_checked(&mut scene, a.image.as_deref())?;
    let list = a.params.as_deref().unwrap_or_default();
    let mut params = Vec::new();
    for name in list.split(',').map(str::trim) {
        let p = ChipParam::from_name(name).ok_or_else(|| {
            format!(
                "params: '{name}' is not one of the chip's parameters, and an architecture \
                 search cannot also search bit widths (the architecture changes no pixel; \
                 run optimize once for the widths); the chip's: {}",
                searchable_names()
            )
        })?;
        if !searchable(p) {
            return Err(format!(
                "params: {} is the board's or the process's, not the chip's area, so it has \
                 no cost to save; sweep it instead (`sweep --param {}`); the chip's: {}",
                p.name(),
                p.name(),
                searchable_names()
            ));
        }
        if params.contains(&p) {
            return Err(format!("params: {} is named twice", p.name()));
        }
        params.push(p);
    }
    let limit_seconds = match a.budget.as_slice() {
        [one] => parse_time_budget(one)?,
        [] => return Err("budget: an architecture search needs --budget \"seconds<=S\"".into()),
        _ => return Err("budget: an architecture search takes one time budget, seconds<=S".into()),
    };
    let objective = Objective::parse(&a.objective)?;
    if a.reference != "wide" {
        return Err(format!(
            "reference: '{}' chooses the error's reference, and an architecture search has \
             no error (it changes no pixel)",
            a.reference
        ));
    }
    if a.max_evals == Some(0) {
        return Err("max-evals: must be at least 1".into());
    }
    if let Some(t) = a.seconds {
        if !(t.is_finite() && t > 0.0) {
            return Err(format!("seconds: {t} is not a positive number of seconds"));
        }
    }
    let mode = a.timing.unwrap_or(TimingMode::Clocked);
    if !mode.records() {
        return Err(format!(
            "--timing {}: an architecture search clocks every candidate chip: clocked or \
             sampled",
            mode.name()
        ));
    }
    let plan = crate::frame::plan::plan(&scene).map_err(|e| e.to_string())?;
    check(&timed(mode), &plan).map_err(|e| format!("params: {e}"))?;
    if crate::frame::timing::glare_only(&plan) {
        return Err(
            "params: a glare scene's pass runs on the glare ASIC, whose variants `reproduce \
             glare-asic-throughput` clocks; an architecture search takes a scene whose passes \
             run on the GPU (fig4, fig6, stage, shafts scene files)"
                .into(),
        );
    }
    let base = ChipConfig::preset(ChipName::of_gpu(Gpu::for_scene(&scene)).name())
        .map_err(|e| e.to_string())?;
    crate::report::outputs::check_dir_out("out", &a.out)?;
    // The seed orders the parameters (ties go to the earlier one).
    let k = params.len().max(1);
    params.rotate_left((a.seed % k as u64) as usize);
    Ok(ChipPlan {
        scene_arg: a.scene.clone(),
        scene,
        params,
        limit_seconds,
        objective,
        out: a.out.clone(),
        base,
        max_evals: a.max_evals,
        seconds: a.seconds,
        mode,
    })
}

fn searchable_names() -> String {
    crate::chip::params::CHIP_PARAMS
        .into_iter()
        .filter(|&p| searchable(p))
        .map(|p| p.name())
        .collect::<Vec<_>>()
        .join(", ")
}

fn timed(mode: TimingMode) -> TimingRequest {
    TimingRequest {
        mode,
        chip: None,
        window: None,
    }
}

/// The gates of one pixel pipe as the frame elaborated it: every unit but the texture
/// samplers, and the largest texture sampler (one texture unit).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PipeGates {
    pub other: f64,
    pub texture_unit: f64,
}

impl PipeGates {
    pub fn of(elaborated: &[Elaborated]) -> PipeGates {
        let mut g = PipeGates {
            other: 0.0,
            texture_unit: 0.0,
        };
        for e in elaborated {
            let Some(s) = &e.summary else { continue };
            if e.name.starts_with("texture_sampler") {
                g.texture_unit = g.texture_unit.max(s.gates_nand2);
            } else {
                g.other += s.gates_nand2;
            }
        }
        g
    }
}

/// A chip's cost: (gates, RAM bits) (module notes).
pub fn chip_cost(c: &ChipConfig, g: PipeGates) -> (f64, u64) {
    let gates = f64::from(c.pipes) * (g.other + f64::from(c.tmus_per_pipe) * g.texture_unit);
    let fifo_bits = fifo_names(c).len() as u64 * u64::from(c.fifo_depth) * FIFO_ENTRY_BITS;
    let queue_bits = u64::from(c.memory.queue_depth) * MEMORY_REQUEST_BITS;
    (gates, texture_cache_bits(c) + fifo_bits + queue_bits)
}

/// One chip clocked.
#[derive(Clone, Debug)]
pub struct ChipPoint {
    pub values: Vec<u32>,
    pub chip: ChipConfig,
    pub seconds: f64,
    pub cycles: u64,
    pub gates: f64,
    pub ram_bits: u64,
    /// The search round that clocked it (0: the start).
    pub round: usize,
    /// With sampled timing: the frame cycles' relative standard error.
    pub sampling_error: Option<f64>,
}

impl ChipPoint {
    /// Gates + RAM bits in NAND2 equivalents (the `area` objective).
    pub fn area(&self) -> f64 {
        self.gates + self.ram_bits as f64 * RAM_BIT_NAND2
    }
    pub fn cost(&self, o: Objective) -> f64 {
        match o {
            Objective::Gates => self.gates,
            Objective::Ram => self.ram_bits as f64,
            Objective::Area => self.area(),
        }
    }
    pub fn meets(&self, limit: f64) -> bool {
        self.seconds <= limit
    }
}

/// Why the search ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ChipEnd {
    /// No step left that helps.
    Converged,
    /// `--max-evals` chips were clocked.
    MaxEvals,
    /// `--seconds` passed.
    Seconds,
}

/// The search's record.
pub struct ChipOutcome {
    pub points: Vec<ChipPoint>,
    /// The cheapest point that meets the budget.
    pub best: Option<usize>,
    pub end: ChipEnd,
    pub rounds: usize,
}

/// `plan.base` with `values` of `plan.params`, if the chip accepts it.
fn chip_at(plan: &ChipPlan, values: &[u32]) -> Option<ChipConfig> {
    let mut c = plan.base.clone();
    for (p, &v) in plan.params.iter().zip(values) {
        p.apply(&mut c, v);
    }
    c.validate().is_ok().then_some(c)
}

/// The chips one step down and one step up each parameter's ladder from `values` (a
/// value off the ladder steps to its nearest rung), that the chip accepts: (parameter
/// index, goes up, values, chip).
fn steps(plan: &ChipPlan, values: &[u32]) -> Vec<(usize, bool, Vec<u32>, ChipConfig)> {
    let mut out = Vec::new();
    for (i, &p) in plan.params.iter().enumerate() {
        let l = ladder(p);
        let down = l.iter().rev().find(|&&v| v < values[i]);
        let up = l.iter().find(|&&v| v > values[i]);
        for (goes_up, v) in [(false, down), (true, up)] {
            let Some(&v) = v else { continue };
            let mut vs = values.to_vec();
            vs[i] = v;
            if let Some(c) = chip_at(plan, &vs) {
                out.push((i, goes_up, vs, c));
            }
        }
    }
    out
}

/// Draw the frame once and clock it on every chip of `chips` (in the search's mode);
/// their frame timings (in order) and the pipe's gates.
fn clock_round(
    plan: &ChipPlan,
    chips: &[ChipConfig],
) -> Result<(Vec<FrameTiming>, PipeGates), String> {
    clock_round_in(plan, chips, plan.mode)
}

/// [`clock_round`] with timing `mode`.
fn clock_round_in(
    plan: &ChipPlan,
    chips: &[ChipConfig],
    mode: TimingMode,
) -> Result<(Vec<FrameTiming>, PipeGates), String> {
    let (first, rest) = chips
        .split_first()
        .expect("a round clocks at least one chip");
    let (mut frame, _) = render_swept(
        &plan.scene,
        &timed(mode),
        Some(first.clone()),
        rest.to_vec(),
        None,
    )
    .map_err(|e| e.to_string())?;
    let gates = PipeGates::of(&frame.elaboration());
    let mut timings = vec![frame.timing.take().expect("a clocked frame has its timing")];
    timings.append(&mut frame.swept_timings);
    Ok((timings, gates))
}

/// The search (module notes); `pareto.csv` rewritten after every round.
pub fn search_chip(plan: &ChipPlan, started: Instant) -> Result<ChipOutcome, String> {
    let start: Vec<u32> = plan.params.iter().map(|p| p.get(&plan.base)).collect();
    let mut points: Vec<ChipPoint> = Vec::new();
    let mut seen: HashMap<Vec<u32>, usize> = HashMap::new();
    let mut current = start.clone();
    let mut round = 0;
    let end = loop {
        let mut todo: Vec<(Vec<u32>, ChipConfig)> = Vec::new();
        if !seen.contains_key(&current) {
            todo.push((current.clone(), plan.base_at(&current)?));
        }
        for (_, _, vs, c) in steps(plan, &current) {
            if !seen.contains_key(&vs) {
                todo.push((vs, c));
            }
        }
        if let Some(max) = plan.max_evals {
            if points.len() >= max {
                break ChipEnd::MaxEvals;
            }
            todo.truncate(max - points.len());
        }
        if plan
            .seconds
            .is_some_and(|s| started.elapsed().as_secs_f64() >= s)
        {
            break ChipEnd::Seconds;
        }
        if !todo.is_empty() {
            let chips: Vec<ChipConfig> = todo.iter().map(|t| t.1.clone()).collect();
            let (timings, gates) = clock_round(plan, &chips)?;
            for ((vs, chip), ft) in todo.into_iter().zip(timings) {
                let (g, ram) = chip_cost(&chip, gates);
                seen.insert(vs.clone(), points.len());
                points.push(ChipPoint {
                    values: vs,
                    seconds: ft.clocked_seconds(),
                    cycles: ft.cycles_total(),
                    chip,
                    gates: g,
                    ram_bits: ram,
                    round,
                    sampling_error: ft.sampling_error,
                });
            }
            write_csv(&plan.out.join("pareto.csv"), &rows(plan, &points, None))?;
        }
        round += 1;
        match next_step(plan, &points, &seen, &current) {
            Some(next) => current = next,
            // Steps left unclocked: the evaluation limit cut the round.
            None if steps(plan, &current)
                .iter()
                .any(|s| !seen.contains_key(&s.2)) =>
            {
                break ChipEnd::MaxEvals
            }
            None => break ChipEnd::Converged,
        }
    };
    let best = best_point(plan, &points);
    Ok(ChipOutcome {
        points,
        best,
        end,
        rounds: round,
    })
}

impl ChipPlan {
    fn base_at(&self, values: &[u32]) -> Result<ChipConfig, String> {
        chip_at(self, values).ok_or_else(|| {
            format!(
                "params: the chip refuses {}",
                describe_values(&self.params, values)
            )
        })
    }
}

/// The greedy step from `current` (module notes), among its clocked neighbours.
fn next_step(
    plan: &ChipPlan,
    points: &[ChipPoint],
    seen: &HashMap<Vec<u32>, usize>,
    current: &[u32],
) -> Option<Vec<u32>> {
    let here = &points[*seen.get(current)?];
    let o = plan.objective;
    let near: Vec<&ChipPoint> = steps(plan, current)
        .into_iter()
        .filter_map(|(_, _, vs, _)| seen.get(&vs).map(|&i| &points[i]))
        .collect();
    let pick = if here.meets(plan.limit_seconds) {
        // The largest saving that still meets the budget.
        near.into_iter()
            .filter(|p| p.meets(plan.limit_seconds) && p.cost(o) < here.cost(o))
            .min_by(|a, b| a.cost(o).total_cmp(&b.cost(o)))
    } else {
        // The most time bought per unit of cost (a free step first).
        let gain = |p: &ChipPoint| {
            let dt = here.seconds - p.seconds;
            let dc = (p.cost(o) - here.cost(o)).max(0.0);
            // Only faster steps are ranked (dt > 0): a free one first.
            if dc == 0.0 {
                f64::INFINITY
            } else {
                dt / dc
            }
        };
        near.into_iter()
            .filter(|p| p.seconds < here.seconds)
            .max_by(|a, b| gain(a).total_cmp(&gain(b)))
    };
    pick.map(|p| p.values.clone())
}

/// The cheapest point that meets the budget (ties: the earlier).
fn best_point(plan: &ChipPlan, points: &[ChipPoint]) -> Option<usize> {
    let o = plan.objective;
    points
        .iter()
        .enumerate()
        .filter(|(_, p)| p.meets(plan.limit_seconds))
        .min_by(|a, b| a.1.cost(o).total_cmp(&b.1.cost(o)).then(a.0.cmp(&b.0)))
        .map(|(i, _)| i)
}

fn describe_values(params: &[ChipParam], values: &[u32]) -> String {
    params
        .iter()
        .zip(values)
        .map(|(p, v)| format!("{}={v}", p.name()))
        .collect::<Vec<_>>()
        .join(" ")
}

/// One row of an architecture search's `pareto.csv`.
#[derive(Clone, Debug, Serialize)]
pub struct ChipParetoRow {
    pub index: usize,
    pub round: usize,
    /// `param=value` for every searched parameter.
    pub config: String,
    pub clocked_seconds: f64,
    pub cycles: u64,
    pub gates_nand2: f64,
    pub ram_bits: u64,
    pub area_nand2: f64,
    /// The texture caches' share of `ram_bits`.
    pub cache_bits: u64,
    pub meets_budget: bool,
    pub is_start: bool,
    pub is_best: bool,
    /// With sampled timing: the frame cycles' relative standard error; empty when
    /// every fragment was clocked.
    pub sampling_error: Option<f64>,
}

fn rows(plan: &ChipPlan, points: &[ChipPoint], best: Option<usize>) -> Vec<ChipParetoRow> {
    points
        .iter()
        .enumerate()
        .map(|(i, p)| ChipParetoRow {
            index: i,
            round: p.round,
            config: describe_values(&plan.params, &p.values),
            clocked_seconds: p.seconds,
            cycles: p.cycles,
            gates_nand2: p.gates.round(),
            ram_bits: p.ram_bits,
            area_nand2: p.area().round(),
            cache_bits: texture_cache_bits(&p.chip),
            meets_budget: p.meets(plan.limit_seconds),
            is_start: i == 0,
            is_best: best == Some(i),
            sampling_error: p.sampling_error,
        })
        .collect()
}

/// `pareto.png`: every chip clocked, its objective against its clocked time, the
/// budget as a vertical line, the start and the best marked.
fn plot(plan: &ChipPlan, o: &ChipOutcome, path: &Path) -> Result<(), String> {
    let obj = plan.objective;
    let mut spec = PlotSpec::new(
        &format!(
            "optimize {} ({}x{}): {} within seconds<={}",
            plan.scene.short_name(),
            plan.scene.image.width,
            plan.scene.image.height,
            obj.name(),
            plan.limit_seconds
        ),
        "clocked frame time (s)",
        match obj {
            Objective::Gates => "the chip's gates (NAND2 equivalents)",
            Objective::Ram => "RAM bits the architecture adds",
            Objective::Area => "the chip's area (NAND2 equivalents)",
        },
    );
    spec.log_y = o.points.iter().all(|p| p.cost(obj) > 0.0);
    let pt = |p: &ChipPoint| (p.seconds, p.cost(obj));
    let (lo, hi) = o
        .points
        .iter()
        .map(|p| p.cost(obj))
        .fold((f64::INFINITY, 0.0f64), |(a, b), c| (a.min(c), b.max(c)));
    let mut series = vec![Series {
        label: "chips clocked".into(),
        points: o.points.iter().map(pt).collect(),
        axis: Axis::Left,
    }];
    series.push(Series {
        label: "start".into(),
        points: o.points.first().map(pt).into_iter().collect(),
        axis: Axis::Left,
    });
    if let Some(b) = o.best {
        series.push(Series {
            label: "best".into(),
            points: vec![pt(&o.points[b])],
            axis: Axis::Left,
        });
    }
    series.push(Series {
        label: "budget".into(),
        points: vec![(plan.limit_seconds, lo), (plan.limit_seconds, hi)],
        axis: Axis::Left,
    });
    let joined = vec![false; series.len() - 1]
        .into_iter()
        .chain([true])
        .collect::<Vec<_>>();
    points_plot(path, &spec, &series, &joined)
}

/// `optimize --params <the chip's parameters> --budget "seconds<=S"`: every argument
/// checked first; the search; `pareto.csv`, `pareto.png` and `best_chip.toml` (the best
/// chip's every field); the best chip verified by a fresh render in the search's mode
/// (and, after a sampled search, clocked in full against the budget).
pub fn optimize_chip_cli(a: &OptimizeArgs) -> Result<(), String> {
    optimize_chip_on(a, crate::scene::load::load_frame_scene(&a.scene)?)
}

/// [`optimize_chip_cli`] of the scene `a.scene` loaded to.
pub fn optimize_chip_on(a: &OptimizeArgs, scene: Scene) -> Result<(), String> {
    let plan = check_chip_on(a, scene)?;
    std::fs::create_dir_all(&plan.out).map_err(|e| format!("out: {}: {e}", plan.out.display()))?;
    eprintln!(
        "optimize {} ({}x{}, the {} chip's architecture): budget seconds<={}; objective {}; params {}",
        plan.scene_arg,
        plan.scene.image.width,
        plan.scene.image.height,
        plan.base.name,
        plan.limit_seconds,
        plan.objective.name(),
        plan.params.iter().map(|p| p.name()).collect::<Vec<_>>().join(",")
    );
    let t0 = Instant::now();
    let o = search_chip(&plan, t0)?;
    write_csv(
        &plan.out.join("pareto.csv"),
        &rows(&plan, &o.points, o.best),
    )?;
    plot(&plan, &o, &plan.out.join("pareto.png"))?;
    report(&plan, &o, t0)
}

/// A sampled search's best chip clocked in full (every fragment): its frame time
/// printed beside the sample's, and whether it meets the budget (a sampled time within
/// its error of the limit may not). Returns the line for `best_chip.toml`'s header and
/// the frame time when it is over the budget.
fn full_clock_check(plan: &ChipPlan, best: &ChipPoint) -> Result<(String, Option<f64>), String> {
    let (full, _) = clock_round_in(plan, std::slice::from_ref(&best.chip), TimingMode::Clocked)?;
    let seconds = full[0].clocked_seconds();
    let off = (seconds - best.seconds) / best.seconds;
    let within = seconds <= plan.limit_seconds;
    let verdict = if within {
        "within the budget".to_string()
    } else {
        format!("OVER the budget seconds<={}", plan.limit_seconds)
    };
    println!(
        "  best clocked in full: {seconds:.6} s ({} cycles, {:+.2} % from the sample's; \
         stated ± {}): {verdict}{}",
        full[0].cycles_total(),
        100.0 * off,
        best.sampling_error
            .map_or("n/a".to_string(), |e| format!("{:.2} %", 100.0 * e)),
        if within {
            ""
        } else {
            " (search with --timing clocked near the limit)"
        }
    );
    let header = format!(
        "# clocked in full: {seconds:.6} s ({} cycles): {verdict}\n",
        full[0].cycles_total()
    );
    Ok((header, (!within).then_some(seconds)))
}

/// Print the outcome, write `best_chip.toml` and verify it: a fresh frame in the
/// search's mode, and after a sampled search the best chip clocked in full, whose time
/// goes into the file's header. An error (the files kept) when the fresh frame's cycles
/// differ or the full clock is over the budget.
pub fn report(plan: &ChipPlan, o: &ChipOutcome, t0: Instant) -> Result<(), String> {
    let line = |p: &ChipPoint| {
        format!(
            "{}: {:.6} s ({} cycles), gates {:.0}, RAM bits {}, {} {:.0}",
            describe_values(&plan.params, &p.values),
            p.seconds,
            p.cycles,
            p.gates,
            p.ram_bits,
            plan.objective.name(),
            p.cost(plan.objective)
        )
    };
    println!(
        "optimize {}: {} chips clocked in {} rounds, {:.1} s ({})",
        plan.scene_arg,
        o.points.len(),
        o.rounds,
        t0.elapsed().as_secs_f64(),
        match o.end {
            ChipEnd::Converged => "no step left",
            ChipEnd::MaxEvals => "stopped at --max-evals",
            ChipEnd::Seconds => "stopped at --seconds",
        }
    );
    println!("  start: {}", line(&o.points[0]));
    let csv = plan.out.join("pareto.csv");
    let Some(b) = o.best else {
        return Err(format!(
            "budget: no chip clocked meets seconds<={} (the fastest: {:.6} s); {} holds what \
             was clocked",
            plan.limit_seconds,
            o.points
                .iter()
                .map(|p| p.seconds)
                .fold(f64::INFINITY, f64::min),
            csv.display()
        ));
    };
    let best = &o.points[b];
    let toml_path = plan.out.join("best_chip.toml");
    let body = toml::to_string(&best.chip).map_err(|e| format!("best_chip.toml: {e}"))?;
    // Verification: the best chip clocked on a fresh frame of its own (and, after a
    // sampled search, in full).
    let (again, _) = clock_round(plan, std::slice::from_ref(&best.chip))?;
    let cycles = again[0].cycles_total();
    println!(
        "  best:  {} (verified by a fresh {} frame: {} cycles, {})",
        line(best),
        plan.mode.name(),
        cycles,
        if cycles == best.cycles {
            "the same"
        } else {
            "DIFFERENT"
        }
    );
    let (full_line, over) = if plan.mode == TimingMode::Sampled {
        full_clock_check(plan, best)?
    } else {
        (String::new(), None)
    };
    let header =
        format!(
        "# optimize --scene {} --params {} --budget \"seconds<={}\" --objective {} ({}x{}): {}\n",
        plan.scene_arg,
        plan.params.iter().map(|p| p.name()).collect::<Vec<_>>().join(","),
        plan.limit_seconds,
        plan.objective.name(),
        plan.scene.image.width,
        plan.scene.image.height,
        describe_values(&plan.params, &best.values)
    );
    write_bytes(&toml_path, (header + &full_line + &body).as_bytes())?;
    println!(
        "  wrote {}, pareto.png, {}",
        csv.display(),
        toml_path.display()
    );
    if cycles != best.cycles {
        return Err(format!(
            "the best chip's fresh clocked frame took {cycles} cycles, not the search's {}",
            best.cycles
        ));
    }
    if let Some(seconds) = over {
        return Err(format!(
            "budget: the sampled search's best chip takes {seconds:.6} s clocked in full, over \
             seconds<={} (its sampled time {:.6} s); {} and {} are written; search with \
             --timing clocked near the limit",
            plan.limit_seconds,
            best.seconds,
            csv.display(),
            toml_path.display()
        ));
    }
    Ok(())
}
