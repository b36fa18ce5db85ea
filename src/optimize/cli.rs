//! `optimize`: every argument checked before any work, the search run with a
//! progress bar, `pareto.csv` rewritten atomically after every point (so Ctrl-C
//! leaves a valid file of what was evaluated), then `pareto.png`, `best.toml` and the
//! verification of the best point by a fresh render of `best.toml`.
//!
//! The doc comments of the argument struct are the command's `--help` text, where
//! `<model>` is a literal placeholder a user reads, not HTML.
#![allow(rustdoc::invalid_html_tags)]

use super::eval::{Kind, Reference};
use super::search::{
    area, describe, objective_front, objective_key, search, Budget, End, Limit, Limits, Metric,
    Objective, Outcome, Point, Status,
};
use crate::report::csv_out::write_csv;
use crate::report::plot::{points_plot, Axis, PlotSpec, Series};
use crate::scene::format::Scene;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The command line's options, as given (checked by [`check`]).
#[derive(Clone, Debug, clap::Args)]
pub struct OptimizeArgs {
    /// A shafts scene (fig4, fig6, stage), a glare scene (glare-point,
    /// glare-elliptic, …), an environment-map scene (env-pattern-sphere, …), a shading
    /// scene (shading-<model>, shading-specular, shading-vertex) or a TOML file of
    /// these (a shading scene file: a `[shading_sphere]` section or its `[shading]`
    /// alias). The scenes `render --scene` takes.
    #[arg(long)]
    pub scene: String,
    /// METRIC<=LEVELS with METRIC max, rms or mean (8-bit levels), e.g. "max<=1";
    /// repeat for several limits. At least one. For a search of the chip's
    /// architecture, one time budget: seconds<=S (the clocked frame time).
    #[arg(long)]
    pub budget: Vec<String>,
    /// What to minimise: gates, ram (RAM bits) or area (gates + 1.5 × RAM bits).
    #[arg(long, default_value = "gates")]
    pub objective: String,
    /// The parameters to search (comma list of `sweep`'s names for the scene);
    /// default: the scene's pipeline's storage and filter bit widths (shafts: not the
    /// interpolator's or the reciprocal's, which `--params` can name; docs/optimize.md).
    /// Or the clocked chip's parameters (pipes, tmus, fifo_depth, cache_kb,
    /// cache_line, cache_ways, misses_in_flight, mem_queue) for a search of its
    /// architecture within a time budget (fig4, fig6, stage).
    #[arg(long)]
    pub params: Option<String>,
    /// Output directory.
    #[arg(long, default_value = "out/optimize")]
    pub out: PathBuf,
    /// Override the scene's image size, WIDTHxHEIGHT (e.g. 96x64; square for a
    /// shading scene's sphere view). `--size` is an older name for it.
    #[arg(long, alias = "size", value_name = "WxH")]
    pub image: Option<String>,
    /// Stop after this many simulations (pruned points do not count).
    #[arg(long)]
    pub max_evals: Option<usize>,
    /// Stop starting simulations after this many seconds.
    #[arg(long, allow_negative_numbers = true)]
    pub seconds: Option<f64>,
    /// Seed of the parameter order (ties go to the earlier parameter).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Shafts scenes: the error is against `wide` (the same frame with every bit
    /// width wide, default) or `truth` (the ray-marched f64 reference).
    #[arg(long, default_value = "wide")]
    pub reference: String,
    /// A search of the chip's architecture: each candidate chip's frame time clocked
    /// (every fragment, the default) or sampled (the passes and screen bands `render
    /// --timing sampled` clocks, the rest scaled: faster, within its stated error).
    #[arg(long, value_enum, value_name = "MODE")]
    pub timing: Option<crate::frame::timing::TimingMode>,
}

/// The options checked, with the scene loaded.
pub struct Plan {
    pub scene: Scene,
    pub scene_arg: String,
    pub budget: Budget,
    pub objective: Objective,
    pub params: Vec<&'static str>,
    pub out: PathBuf,
    pub max_evals: Option<usize>,
    pub seconds: Option<f64>,
    pub seed: u64,
    pub reference: Reference,
}

/// Every argument checked, in the order given, each error naming its argument; no
/// rendering, no file written.
pub fn check(a: &OptimizeArgs) -> Result<Plan, String> {
    check_on(a, crate::scene::load::load_frame_scene(&a.scene)?)
}

/// [`check`] of the scene `a.scene` loaded to (a scene of lights and objects).
pub fn check_on(a: &OptimizeArgs, mut scene: Scene) -> Result<Plan, String> {
    crate::scene::load::apply_image_checked(&mut scene, a.image.as_deref())?;
    if a.budget.is_empty() {
        return Err("budget: at least one --budget is needed, e.g. --budget \"max<=1\"".into());
    }
    if let Some(b) = a
        .budget
        .iter()
        .find(|b| b.trim_start().starts_with("seconds"))
    {
        return Err(format!(
            "budget: '{b}' is a time budget, which bounds an architecture search (--params \
             naming the clocked chip's parameters: {}), not a search of bit widths",
            crate::chip::params::ChipParam::names()
        ));
    }
    let budget = Budget(
        a.budget
            .iter()
            .map(|b| Limit::parse(b))
            .collect::<Result<_, _>>()?,
    );
    let objective = Objective::parse(&a.objective)?;
    let kind = Kind::of(&scene);
    let params = match &a.params {
        Some(list) => kind.parse_params_for(&scene, list)?,
        None => kind.default_params_for(&scene),
    };
    if a.max_evals == Some(0) {
        return Err("max-evals: must be at least 1".into());
    }
    if let Some(t) = a.seconds {
        if !(t.is_finite() && t > 0.0) {
            return Err(format!("seconds: {t} is not a positive number of seconds"));
        }
    }
    let reference = Reference::parse(&a.reference)?;
    crate::report::outputs::check_dir_out("out", &a.out)?;
    Ok(Plan {
        scene,
        scene_arg: a.scene.clone(),
        budget,
        objective,
        params,
        out: a.out.clone(),
        max_evals: a.max_evals,
        seconds: a.seconds,
        seed: a.seed,
        reference,
    })
}

/// One row of `pareto.csv`.
#[derive(Clone, Debug, Serialize)]
pub struct ParetoRow {
    pub index: usize,
    /// `param=value` for every searched parameter.
    pub config: String,
    /// `simulated`, or `pruned` (its bound broke the budget; never simulated).
    pub evaluation: &'static str,
    pub gates_nand2: Option<f64>,
    pub ram_bits: Option<u64>,
    pub area_nand2: Option<f64>,
    pub mean_levels: Option<f64>,
    pub rms_levels: Option<f64>,
    pub max_levels: Option<f64>,
    /// The sound lower bound from the output width (module `eval`).
    pub bound_mean_levels: f64,
    pub bound_rms_levels: f64,
    pub bound_max_levels: f64,
    pub predicted_hw_seconds: Option<f64>,
    pub wall_seconds: Option<f64>,
    pub meets_budget: bool,
    /// On the front of (gates, RAM bits, error of the first budget's metric).
    pub on_front: bool,
    /// On the front of (the objective's cost, that error): the one `pareto.png` draws.
    pub on_objective_front: bool,
    pub is_default: bool,
    pub is_best: bool,
}

/// The CSV rows of `points` (`defaults`, `best`: indices).
pub fn rows(
    params: &[&str],
    points: &[Point],
    budget: &Budget,
    objective: Objective,
    defaults: Option<usize>,
    best: Option<usize>,
) -> Vec<ParetoRow> {
    let on = objective_front(points, objective, budget.primary());
    points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let m = p.metrics();
            ParetoRow {
                index: i,
                config: describe(params, &p.values),
                evaluation: match p.status {
                    Status::Simulated(_) => "simulated",
                    Status::Pruned(_) => "pruned",
                },
                gates_nand2: m.map(|m| m.gates),
                ram_bits: m.map(|m| m.ram_bits),
                area_nand2: m.map(area),
                mean_levels: m.map(|m| m.error.mean_abs),
                rms_levels: m.map(|m| m.error.rms),
                max_levels: m.map(|m| m.error.max),
                bound_mean_levels: p.bound.mean_abs,
                bound_rms_levels: p.bound.rms,
                bound_max_levels: p.bound.max,
                predicted_hw_seconds: m.map(|m| m.predicted_seconds),
                wall_seconds: m.map(|m| m.wall_seconds),
                meets_budget: m.is_some_and(|m| budget.meets(&m.error)),
                on_front: p.on_front,
                on_objective_front: on[i],
                is_default: defaults == Some(i),
                is_best: best == Some(i),
            }
        })
        .collect()
}

/// The error axis of `pareto.png` runs to at most this many times the budget's
/// first limit (or the start's or the best point's error, if larger): one point far
/// off (fig6's 8-bit interpolator accumulators wrap to 252 levels) would squeeze
/// the points near the budget into a sliver.
pub const PLOT_CLIP_LIMITS: f64 = 5.0;

/// The error beyond which `pareto.png` leaves points off, None: no clip (no
/// positive limit, or no point beyond it). `xs`: every simulated point's error;
/// `keep`: errors that must stay in view (the start, the best).
pub fn plot_clip(xs: &[f64], budget: &Budget, keep: &[f64]) -> Option<f64> {
    let limit = budget.0.first().map(|l| l.limit).filter(|&l| l > 0.0)?;
    let clip = keep
        .iter()
        .copied()
        .fold(PLOT_CLIP_LIMITS * limit, f64::max);
    xs.iter().any(|&x| x > clip).then_some(clip)
}

/// What `pareto.png` calls the search's start point: the GeForce defaults for a
/// built-in scene, the file's widths for a scene file (`--scene FILE`).
pub fn start_label(scene_arg: &str) -> String {
    let path = Path::new(scene_arg);
    if !crate::scene::load::builtin_names().contains(&scene_arg) && path.is_file() {
        let name = path
            .file_name()
            .map_or(scene_arg.into(), |n| n.to_string_lossy());
        format!("start: the widths of {name}")
    } else {
        "start: GeForce defaults".into()
    }
}

/// `pareto.png`: the objective's cost against the budget's first error metric;
/// every simulated point, the front in that plane ([`objective_front`], joined), the
/// start point (labelled `start`) and the best point as separate series; points
/// beyond [`plot_clip`] left off, the x axis's label saying how many and how far.
pub fn plot(
    path: &Path,
    title: &str,
    o: &Outcome,
    budget: &Budget,
    objective: Objective,
    start: &str,
) -> Result<(), String> {
    let metric = budget.primary();
    let keep: Vec<f64> = [Some(o.defaults), o.best]
        .into_iter()
        .flatten()
        .filter_map(|i| objective_key(&o.points[i], objective, metric))
        .map(|k| k.0)
        .collect();
    let xs: Vec<f64> = o
        .points
        .iter()
        .filter_map(|p| objective_key(p, objective, metric))
        .map(|k| k.0)
        .collect();
    let clip = plot_clip(&xs, budget, &keep);
    let xy =
        |p: &Point| objective_key(p, objective, metric).filter(|k| clip.is_none_or(|c| k.0 <= c));
    let all: Vec<(f64, f64)> = o.points.iter().filter_map(xy).collect();
    if all.is_empty() {
        return Ok(());
    }
    let on = objective_front(&o.points, objective, metric);
    let mut front: Vec<(f64, f64)> = o
        .points
        .iter()
        .zip(&on)
        .filter(|(_, &f)| f)
        .filter_map(|(p, _)| xy(p))
        .collect();
    // Along the front: error up, cost down.
    front.sort_by(|a, b| a.0.total_cmp(&b.0).then(b.1.total_cmp(&a.1)));
    front.dedup();
    let one = |i: Option<usize>| i.and_then(|i| xy(&o.points[i])).into_iter().collect();
    let (cost, unit) = match objective {
        Objective::Gates => ("gates", "gates (NAND2)"),
        Objective::Ram => ("RAM bits", "RAM bits"),
        Objective::Area => ("area", "area (NAND2: gates + 1.5 x RAM bits)"),
    };
    let series = vec![
        (
            Series {
                label: "evaluated (simulated)".into(),
                points: all,
                axis: Axis::Left,
            },
            false,
        ),
        (
            Series {
                label: format!(
                    "Pareto front of ({cost}, {} error): no point has less of both",
                    metric.name()
                ),
                points: front,
                axis: Axis::Left,
            },
            true,
        ),
        (
            Series {
                label: start.into(),
                points: one(Some(o.defaults)),
                axis: Axis::Left,
            },
            false,
        ),
        (
            Series {
                label: "best within budget".into(),
                points: one(o.best),
                axis: Axis::Left,
            },
            false,
        ),
    ];
    let (series, joined): (Vec<Series>, Vec<bool>) = series
        .into_iter()
        .filter(|(s, _)| !s.points.is_empty())
        .unzip();
    let x_label = x_axis_label(metric, clip, &xs);
    let mut spec = PlotSpec::new(title, &x_label, unit);
    spec.width = 900;
    spec.height = 600;
    points_plot(path, &spec, &series, &joined)
}

/// `pareto.png`'s x-axis label: the metric, and with the axis cut at `clip` how many of
/// the errors `xs` lie beyond it and the largest.
fn x_axis_label(metric: Metric, clip: Option<f64>, xs: &[f64]) -> String {
    let mut x_label = format!("{} error (8-bit levels)", metric.name());
    if let Some(c) = clip {
        let off: Vec<f64> = xs.iter().copied().filter(|&x| x > c).collect();
        let far = off.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        x_label.push_str(&format!(
            "; axis cut at {c:.2}: {} point{} beyond it left off (up to {far:.1})",
            off.len(),
            if off.len() == 1 { "" } else { "s" }
        ));
    }
    x_label
}

/// `best.toml`: the whole scene (its `[shafts]` or `[glare.hw]` widths the best
/// point's), as `render --scene best.toml` reads it.
pub fn best_toml(scene: &Scene, header: &str) -> Result<String, String> {
    let body =
        toml::to_string_pretty(scene).map_err(|e| format!("best.toml: cannot write TOML: {e}"))?;
    Ok(format!("{header}\n{body}"))
}

/// One search as both drivers run it (`optimize_cli` for a `Scene`,
/// `shading::optimize_shading_cli` for a shading scene): a progress bar with the best
/// cost so far, `pareto.csv` rewritten after every point, the final CSV, exit 130 on
/// Ctrl-C with the CSV whole, `pareto.png`, and the summary lines.
pub struct SearchRun<'a> {
    /// The scene as the command line named it.
    pub label: &'a str,
    /// pareto.png's title.
    pub title: &'a str,
    pub params: &'a [&'static str],
    pub budget: &'a Budget,
    pub objective: Objective,
    pub max_evals: Option<usize>,
    pub seconds: Option<f64>,
    pub seed: u64,
    pub out: &'a Path,
    pub started: std::time::Instant,
}

impl SearchRun<'_> {
    fn csv(&self) -> PathBuf {
        self.out.join("pareto.csv")
    }

    /// Search `target`; the outcome with its files written (an interrupted run exits).
    pub fn run(&self, target: &dyn super::eval::Target) -> Result<Outcome, String> {
        let csv = self.csv();
        crate::report::interrupt::arm();
        let bar =
            crate::report::progress::progress_bar(self.max_evals.unwrap_or(0) as u64, "optimize");
        let stop = || crate::report::interrupt::requested().is_some();
        let limits = Limits {
            max_evals: self.max_evals,
            seconds: self.seconds,
            stop: &stop,
        };
        let mut saved: Result<(), String> = Ok(());
        let mut on_point = |book: &super::search::Book| {
            let best = book.best(self.objective);
            let r = rows(
                self.params,
                &book.points,
                self.budget,
                self.objective,
                Some(0),
                best,
            );
            match write_csv(&csv, &r) {
                // What a second signal prints (`report::interrupt`).
                Ok(()) => crate::report::interrupt::saved(format!(
                    "optimize: interrupted after {} simulations; {} holds every point evaluated",
                    book.simulations,
                    csv.display()
                )),
                Err(e) => saved = Err(e),
            }
            if self.max_evals.is_none() {
                bar.set_length(book.simulations as u64 + 1);
            }
            bar.set_position(book.simulations as u64);
            let cost = best
                .and_then(|i| book.points[i].metrics())
                .map(|m| self.objective.cost(m));
            bar.set_message(match cost {
                Some(c) => format!("best {} {c:.0}", self.objective.name()),
                None => "no point within budget yet".into(),
            });
        };
        let o = search(
            target,
            self.params,
            self.budget,
            self.objective,
            self.seed,
            &limits,
            &mut on_point,
        );
        bar.finish_and_clear();
        saved?;
        let o = o?;
        let r = rows(
            self.params,
            &o.points,
            self.budget,
            self.objective,
            Some(o.defaults),
            o.best,
        );
        write_csv(&csv, &r)?;
        if o.end == End::Interrupted {
            if let Some(sig) = crate::report::interrupt::requested() {
                let line = format!(
                    "optimize: interrupted after {} simulations; {} holds every point evaluated",
                    o.simulations,
                    csv.display()
                );
                crate::report::interrupt::exit_with(sig, Some(&line));
            }
        }
        plot(
            &self.out.join("pareto.png"),
            self.title,
            &o,
            self.budget,
            self.objective,
            &start_label(self.label),
        )?;
        self.print_summary(&o);
        Ok(o)
    }

    /// The search's summary line and the defaults' line.
    fn print_summary(&self, o: &Outcome) {
        println!(
            "optimize {}: {} simulations, {} pruned by the bound, ended: {:?}, {:.1} s",
            self.label,
            o.simulations,
            o.pruned,
            o.end,
            self.started.elapsed().as_secs_f64()
        );
        if let Some(d) = o.points[o.defaults].metrics() {
            println!(
                "  defaults: {} gates {:.0} RAM bits {} max {:.3} rms {:.3} mean {:.3}",
                describe(&o.params, &o.points[o.defaults].values),
                d.gates,
                d.ram_bits,
                d.error.max,
                d.error.rms,
                d.error.mean_abs
            );
        }
    }

    /// The best point's line after its fresh render (`m`, of the written `best`
    /// file), the files written; an error when that render breaks the budget.
    pub fn verified(
        &self,
        o: &Outcome,
        best: usize,
        best_file: &Path,
        m: &super::eval::Metrics,
    ) -> Result<(), String> {
        let meets = self.budget.meets(&m.error);
        println!(
            "  best:     {} gates {:.0} RAM bits {} max {:.3} rms {:.3} mean {:.3} \
             (verified by a fresh render of {}: {})",
            describe(&o.params, &o.points[best].values),
            m.gates,
            m.ram_bits,
            m.error.max,
            m.error.rms,
            m.error.mean_abs,
            best_file.display(),
            if meets {
                "meets the budget"
            } else {
                "BREAKS the budget"
            }
        );
        println!("  wrote {}, pareto.png, best.toml", self.csv().display());
        if !meets {
            return Err(format!(
                "budget: the fresh render of {} breaks it",
                best_file.display()
            ));
        }
        Ok(())
    }

    /// The error when no configuration evaluated meets the budget.
    pub fn no_best(&self, o: &Outcome) -> String {
        format!(
            "budget: no configuration evaluated meets {} ({}); {} holds what was evaluated",
            self.budget.describe(),
            if o.end == End::DefaultsBreakBudget {
                format!(
                    "neither the defaults nor any widening the repair tried, up to {} steps",
                    super::search::MAX_WIDEN_STEPS
                )
            } else {
                "the search stopped first".to_string()
            },
            self.csv().display()
        )
    }
}
