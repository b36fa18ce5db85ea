//! The search of `optimize`: from the GeForce defaults, a greedy descent
//! in the style of `fxpopt` and Minibit, with a sound bound that prunes before any
//! simulation.
//!
//! * **Bound.** Before a configuration is simulated, [`super::eval::output_bound`]
//!   gives a guaranteed LOWER bound of its mean, RMS and max error from its
//!   framebuffer width and the reference alone. If that bound already breaks the
//!   budget, no render can meet it: the point is recorded as pruned and never run.
//!   No upper bound (the datasheets' "Error bound") is used to skip a simulation, so
//!   the pruning never drops a point that would have passed.
//! * **Repair.** If the defaults break the budget, the parameter whose one-step
//!   widening removes the most error per cost added is widened (if none removes
//!   any, every parameter is widened one step together; if that does not lower
//!   the error either, `Book::repair_wider`: two-step single widenings, pairs of
//!   them widened together up to their caps, and line searches over each width
//!   whose widening changed the error, down as well as up: the storage-vs-filter
//!   trades), until the budget is met
//!   (at most [`MAX_WIDEN_STEPS`] steps above a default; none left: the search
//!   ends, reporting it).
//! * **Descent.** Each step narrows one parameter by one step (one bit, or half a
//!   table) from the current point. Of the narrowings that meet the budget and save
//!   objective cost, the one with the best saving per error added is taken (error
//!   as the budget's worst ratio value / limit). A narrowing that breaks the budget
//!   (by bound or by simulation), reaches the parameter's lower limit, or saves
//!   nothing — also one step further ([`LOOKAHEAD`] = 2 steps: the error is not
//!   monotone in every width) — backs that parameter off for the rest of the pass;
//!   passes repeat from the point reached until one moves nothing. Then a polish:
//!   one step wider in one parameter traded for up to two steps narrower in
//!   another, the first trade that meets the budget and saves cost taken, and the
//!   passes resume; no trade left: the search has converged. The scores are
//!   lazy (a parameter scored at an earlier point is re-simulated only when it would
//!   be chosen), which keeps the simulations near one per step.
//! * **Order.** The parameters are tried in an order shuffled by `--seed`
//!   (ChaCha8); ties go to the earlier one, so a seed gives one search.

use super::eval::{Evaluator, Metrics, Step, Target, RAM_BIT_NAND2};
use crate::report::metrics::ErrorStats;
use crate::scene::format::Scene;
use rand::seq::SliceRandom;
use rand::SeedableRng;
use std::collections::HashMap;
use std::time::Instant;

/// An error statistic a budget limits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Metric {
    Mean,
    Rms,
    Max,
}

impl Metric {
    pub fn name(self) -> &'static str {
        match self {
            Metric::Mean => "mean",
            Metric::Rms => "rms",
            Metric::Max => "max",
        }
    }
    pub fn of(self, e: &ErrorStats) -> f64 {
        match self {
            Metric::Mean => e.mean_abs,
            Metric::Rms => e.rms,
            Metric::Max => e.max,
        }
    }
}

/// One `--budget`: metric ≤ limit, in 8-bit levels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limit {
    pub metric: Metric,
    pub limit: f64,
}

impl Limit {
    /// `max<=1`, `rms<=0.5`, `mean<=0.3` (spaces allowed); errors name `budget`.
    pub fn parse(text: &str) -> Result<Limit, String> {
        let bad = |why: &str| {
            format!(
                "budget: '{text}' {why} (a budget is METRIC<=LEVELS with METRIC one of \
                 max, rms, mean, e.g. \"max<=1\")"
            )
        };
        let (m, v) = text.split_once("<=").ok_or_else(|| bad("has no '<='"))?;
        let metric = match m.trim().to_ascii_lowercase().as_str() {
            "max" => Metric::Max,
            "rms" => Metric::Rms,
            "mean" => Metric::Mean,
            _ => return Err(bad("names an unknown metric")),
        };
        let limit: f64 = v
            .trim()
            .parse()
            .map_err(|_| bad("has a limit that is not a number"))?;
        if !limit.is_finite() || limit < 0.0 {
            return Err(bad("has a limit that is not a finite number ≥ 0"));
        }
        Ok(Limit { metric, limit })
    }
}

/// Every limit at once.
#[derive(Clone, Debug, PartialEq)]
pub struct Budget(pub Vec<Limit>);

impl Budget {
    pub fn meets(&self, e: &ErrorStats) -> bool {
        self.0.iter().all(|l| l.metric.of(e) <= l.limit)
    }
    /// The worst value / limit over the limits (1 = at the budget).
    pub fn ratio(&self, e: &ErrorStats) -> f64 {
        self.0
            .iter()
            .map(|l| {
                let v = l.metric.of(e);
                if l.limit > 0.0 {
                    v / l.limit
                } else if v > 0.0 {
                    f64::INFINITY
                } else {
                    0.0
                }
            })
            .fold(0.0, f64::max)
    }
    /// The first limit's metric: the error axis of the front and the plot.
    pub fn primary(&self) -> Metric {
        self.0.first().map_or(Metric::Max, |l| l.metric)
    }
    pub fn describe(&self) -> String {
        self.0
            .iter()
            .map(|l| format!("{}<={}", l.metric.name(), l.limit))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// What the search minimises.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Objective {
    Gates,
    Ram,
    /// Gates + RAM bits × [`RAM_BIT_NAND2`].
    Area,
}

impl Objective {
    pub fn parse(text: &str) -> Result<Objective, String> {
        match text.trim() {
            "gates" => Ok(Objective::Gates),
            "ram" => Ok(Objective::Ram),
            "area" => Ok(Objective::Area),
            other => Err(format!(
                "objective: unknown objective '{other}' (known: gates, ram, area)"
            )),
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            Objective::Gates => "gates",
            Objective::Ram => "ram",
            Objective::Area => "area",
        }
    }
    pub fn cost(self, m: &Metrics) -> f64 {
        match self {
            Objective::Gates => m.gates,
            Objective::Ram => m.ram_bits as f64,
            Objective::Area => area(m),
        }
    }
}

/// Gates + RAM bits in NAND2 equivalents.
pub fn area(m: &Metrics) -> f64 {
    m.gates + m.ram_bits as f64 * RAM_BIT_NAND2
}

/// What became of one configuration.
#[derive(Clone, Debug, PartialEq)]
pub enum Status {
    /// Its bound broke the budget: never simulated.
    Pruned(ErrorStats),
    Simulated(Metrics),
}

/// One evaluated configuration (in the order evaluated).
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    pub values: Vec<u32>,
    pub bound: ErrorStats,
    pub status: Status,
    pub on_front: bool,
}

impl Point {
    pub fn metrics(&self) -> Option<&Metrics> {
        match &self.status {
            Status::Simulated(m) => Some(m),
            Status::Pruned(_) => None,
        }
    }
}

/// The limits of one run; `stop` is asked before each simulation (Ctrl-C).
pub struct Limits<'a> {
    pub max_evals: Option<usize>,
    pub seconds: Option<f64>,
    pub stop: &'a dyn Fn() -> bool,
}

/// Why the search ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum End {
    /// No parameter can be narrowed further within the budget.
    Converged,
    MaxEvals,
    Seconds,
    Interrupted,
    /// The defaults break the budget and no widening (up to MAX_WIDEN_STEPS per
    /// parameter) repaired them.
    DefaultsBreakBudget,
}

/// A search's result.
#[derive(Clone, Debug)]
pub struct Outcome {
    pub params: Vec<&'static str>,
    pub points: Vec<Point>,
    /// Index of the defaults and of the best point found (meeting the budget).
    pub defaults: usize,
    pub best: Option<usize>,
    pub simulations: usize,
    pub pruned: usize,
    pub end: End,
}

impl Outcome {
    pub fn best_scene(&self, ev: &Evaluator) -> Option<Result<Scene, String>> {
        self.best.map(|i| {
            ev.kind
                .apply(&ev.base, &self.params, &self.points[i].values)
        })
    }
}

/// The evaluated points and their index, shared by the search and the grid.
pub struct Book<'a> {
    ev: &'a dyn Target,
    params: Vec<&'static str>,
    budget: &'a Budget,
    pub points: Vec<Point>,
    /// values → point index, or None for an invalid configuration.
    index: HashMap<Vec<u32>, Option<usize>>,
    pub simulations: usize,
    pub pruned: usize,
    /// Use the bound (false: the exhaustive grid simulates everything).
    prune: bool,
}

/// What [`Book::visit`] found.
enum Visit {
    Invalid,
    Stopped(End),
    At(usize),
}

/// Where a repair step stopped early: at a point that meets the budget (Ok), or at a
/// limit (Err).
type Stop = Result<usize, End>;

/// A parameter's rank in the repair's step 1: the lowest error ratio of its one- and
/// two-step widenings, the parameter, and whether any widening changed the error
/// (it is sensitive).
type Rank = (f64, usize, bool);

/// What bounds one repair's probes: the defaults `d` (the widenings' caps), the
/// limits and when the search started.
struct Reach<'r> {
    d: &'r [u32],
    limits: &'r Limits<'r>,
    started: Instant,
}

/// What [`Book::probe`] found.
enum Probe {
    Invalid,
    Stopped(End),
    Pruned,
    /// Simulated; meets the budget.
    Meets(usize),
    /// Simulated; breaks the budget at this error ratio.
    At(usize, f64),
}

impl<'a> Book<'a> {
    pub fn new(
        ev: &'a dyn Target,
        params: &[&'static str],
        budget: &'a Budget,
        prune: bool,
    ) -> Self {
        Book {
            ev,
            params: params.to_vec(),
            budget,
            points: Vec::new(),
            index: HashMap::new(),
            simulations: 0,
            pruned: 0,
            prune,
        }
    }

    fn visit(
        &mut self,
        values: &[u32],
        limits: &Limits,
        started: Instant,
        on_point: &mut dyn FnMut(&Book),
    ) -> Result<Visit, String> {
        if let Some(&at) = self.index.get(values) {
            return Ok(at.map_or(Visit::Invalid, Visit::At));
        }
        let Some(bound) = self.ev.bound_at(&self.params, values)? else {
            self.index.insert(values.to_vec(), None);
            return Ok(Visit::Invalid);
        };
        let status = if self.prune && !self.budget.meets(&bound) {
            self.pruned += 1;
            Status::Pruned(bound)
        } else {
            if (limits.stop)() {
                return Ok(Visit::Stopped(End::Interrupted));
            }
            if limits.max_evals.is_some_and(|n| self.simulations >= n) {
                return Ok(Visit::Stopped(End::MaxEvals));
            }
            if limits
                .seconds
                .is_some_and(|t| started.elapsed().as_secs_f64() >= t)
            {
                return Ok(Visit::Stopped(End::Seconds));
            }
            self.simulations += 1;
            let m = self
                .ev
                .evaluate_at(&self.params, values)
                .map_err(|e| format!("{} ({}): {e}", self.describe(values), self.ev.kind_name()))?;
            Status::Simulated(m)
        };
        self.points.push(Point {
            values: values.to_vec(),
            bound,
            status,
            on_front: false,
        });
        let at = self.points.len() - 1;
        self.index.insert(values.to_vec(), Some(at));
        mark_front(&mut self.points, self.budget.primary());
        on_point(self);
        Ok(Visit::At(at))
    }

    /// From `from`, up to [`LOOKAHEAD`] narrowings of parameter `i`: the first point
    /// that meets the budget and costs less than point `x`, with its score (cost
    /// saved per error added); pruned points are stepped over. `Err(end)` when a
    /// limit stopped the search.
    // The search's state, one argument each.
    #[allow(clippy::too_many_arguments)]
    fn first_saving(
        &mut self,
        objective: Objective,
        x: usize,
        from: &[u32],
        i: usize,
        limits: &Limits,
        started: Instant,
        on_point: &mut dyn FnMut(&Book),
    ) -> Result<Result<Option<(usize, f64)>, End>, String> {
        let mut y = from.to_vec();
        for _ in 0..LOOKAHEAD {
            let Some(n) = narrow(self.ev, &self.params, &y, i) else {
                break;
            };
            y = n;
            let j = match self.visit(&y, limits, started, on_point)? {
                Visit::At(j) => j,
                Visit::Invalid => break,
                Visit::Stopped(end) => return Ok(Err(end)),
            };
            let (Some(mx), Some(my)) = (self.points[x].metrics(), self.points[j].metrics()) else {
                continue;
            };
            let saving = objective.cost(mx) - objective.cost(my);
            if self.budget.meets(&my.error) && saving > 0.0 {
                let added = (self.budget.ratio(&my.error) - self.budget.ratio(&mx.error)).max(0.0);
                return Ok(Ok(Some((j, saving / (added + EPS)))));
            }
        }
        Ok(Ok(None))
    }

    /// The repair's last resort at point `x` (it breaks the budget; no single
    /// one-step widening and no joint step lowered its error), in the order tried:
    /// 1. each parameter alone two steps wider (the error is not monotone in every
    ///    width: one bit more can do nothing where two do). A parameter whose one-
    ///    or two-step widening changed the error at all is *sensitive*;
    /// 2. pairs widened together, step by step up to their caps: the two
    ///    parameters whose widenings in 1. left the least error, ties to the earlier
    ///    (two widths that do nothing alone can act together), then every pair of
    ///    sensitive ones, in the order of 1. (two widths that each make it worse
    ///    alone can help together: fig6 at 720x480 needs the texels and the
    ///    framebuffer wider together, and at 9 bits each the two-step widenings
    ///    that left the least error were the framebuffer's and the filter
    ///    weights', not the texels'; the repair before these pairs paired two
    ///    widths whose widenings changed nothing);
    /// 3. from the lowest-error point of 1. and 2. (or `x`), a line search over each
    ///    sensitive parameter in turn, in the order of 1.: its values above the
    ///    current one up to its cap, then below it towards its floor, narrowing
    ///    ending after [`LOOKAHEAD`] steps that do not lower the line's lowest error
    ///    (or at a point pruned by the bound); the next line starts from the lowest
    ///    point of the last. After 2., this explores the storage-vs-filter trades of
    ///    fig6's by-hand repair at full size, which widened texels and framebuffer
    ///    and narrowed the filter weights and coordinate fractions (docs/optimize.md).
    ///
    /// The first point that meets the budget ends it. Returns that point, else the
    /// point of lowest error ratio if it is below `x`'s (None: the repair gives up);
    /// `Err(end)` when a limit stopped it. Widenings stay within
    /// [`MAX_WIDEN_STEPS`] of the defaults `d`.
    fn repair_wider(
        &mut self,
        x: usize,
        d: &[u32],
        limits: &Limits,
        started: Instant,
        on_point: &mut dyn FnMut(&Book),
    ) -> Result<Result<Option<usize>, End>, String> {
        let Some(rx) = self.ratio_of(x) else {
            return Ok(Ok(None));
        };
        let reach = Reach { d, limits, started };
        let from = self.points[x].values.clone();
        // The lowest error ratio seen, and where.
        let mut best: Option<(f64, usize)> = None;
        let rank = match self.rank_two_steps(&reach, &from, rx, &mut best, on_point)? {
            Ok(rank) => rank,
            Err(stop) => return Ok(stop.map(Some)),
        };
        let sens: Vec<usize> = rank.iter().filter(|r| r.2).map(|r| r.1).collect();
        if let Err(stop) = self.widen_pairs(&reach, &from, &rank, &sens, &mut best, on_point)? {
            return Ok(stop.map(Some));
        }
        // 3. Line searches over the sensitive parameters, from the lowest point so far.
        let c = best.filter(|&(r, _)| r < rx).map_or(x, |(_, j)| j);
        if let Err(stop) = self.line_searches(&reach, c, &sens, &mut best, on_point)? {
            return Ok(stop.map(Some));
        }
        Ok(Ok(best.filter(|&(r, _)| r < rx).map(|(_, j)| j)))
    }

    /// The repair's step 1 ([`Book::repair_wider`]): each parameter two steps wider
    /// from `from` (error ratio `rx`), alone. Returns the ranking (lowest error ratio
    /// over the parameter's one- and two-step widenings, the parameter, whether it is
    /// sensitive), sorted by that error, ties to the earlier parameter; or where the
    /// repair stopped.
    fn rank_two_steps(
        &mut self,
        reach: &Reach,
        from: &[u32],
        rx: f64,
        best: &mut Option<(f64, usize)>,
        on_point: &mut dyn FnMut(&Book),
    ) -> Result<Result<Vec<Rank>, Stop>, String> {
        let (d, limits, started) = (reach.d, reach.limits, reach.started);
        let mut rank: Vec<Rank> = Vec::new();
        for i in 0..self.params.len() {
            let Some(one) = widen(self.ev, &self.params, from, d, i) else {
                continue;
            };
            let mut lowest = self
                .index
                .get(&one)
                .copied()
                .flatten()
                .and_then(|j| self.ratio_of(j));
            let mut changed = lowest.is_some_and(|r| r != rx);
            if let Some(two) = widen(self.ev, &self.params, &one, d, i) {
                match self.probe(&two, best, limits, started, on_point)? {
                    Probe::Stopped(end) => return Ok(Err(Err(end))),
                    Probe::Meets(j) => return Ok(Err(Ok(j))),
                    Probe::At(_, r) => {
                        changed |= r != rx;
                        lowest = Some(lowest.map_or(r, |l: f64| l.min(r)));
                    }
                    Probe::Invalid | Probe::Pruned => {}
                }
            }
            if let Some(l) = lowest {
                rank.push((l, i, changed));
            }
        }
        rank.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        Ok(Ok(rank))
    }

    /// The repair's step 2: the pairs (the two best-ranked parameters, then every pair
    /// of sensitive ones `sens`), each widened together from `from` step by step up to
    /// its caps. `Err`: where the repair stopped.
    fn widen_pairs(
        &mut self,
        reach: &Reach,
        from: &[u32],
        rank: &[Rank],
        sens: &[usize],
        best: &mut Option<(f64, usize)>,
        on_point: &mut dyn FnMut(&Book),
    ) -> Result<Result<(), Stop>, String> {
        let (d, limits, started) = (reach.d, reach.limits, reach.started);
        let mut pairs: Vec<(usize, usize)> = Vec::new();
        if let [(_, a, _), (_, b, _), ..] = rank[..] {
            pairs.push((a, b));
        }
        for (k, &a) in sens.iter().enumerate() {
            for &b in &sens[k + 1..] {
                if !pairs.contains(&(a, b)) {
                    pairs.push((a, b));
                }
            }
        }
        for (a, b) in pairs {
            let mut y = from.to_vec();
            while let Some(ya) = widen(self.ev, &self.params, &y, d, a) {
                let Some(yb) = widen(self.ev, &self.params, &ya, d, b) else {
                    break;
                };
                y = yb;
                match self.probe(&y, best, limits, started, on_point)? {
                    Probe::Stopped(end) => return Ok(Err(Err(end))),
                    Probe::Meets(j) => return Ok(Err(Ok(j))),
                    Probe::At(..) => {}
                    Probe::Invalid | Probe::Pruned => break,
                }
            }
        }
        Ok(Ok(()))
    }

    /// The repair's step 3: from point `c`, a line search over each sensitive
    /// parameter of `sens` in turn (wider up to its cap, then narrower, ending
    /// [`LOOKAHEAD`] steps after the line's lowest error); the next line starts from
    /// the lowest point of the last. `Err`: where the repair stopped.
    fn line_searches(
        &mut self,
        reach: &Reach,
        mut c: usize,
        sens: &[usize],
        best: &mut Option<(f64, usize)>,
        on_point: &mut dyn FnMut(&Book),
    ) -> Result<Result<(), Stop>, String> {
        let (d, limits, started) = (reach.d, reach.limits, reach.started);
        for &i in sens {
            let Some(rc) = self.ratio_of(c) else {
                break;
            };
            let cv = self.points[c].values.clone();
            let mut line = (rc, c);
            for wider in [true, false] {
                let mut y = cv.clone();
                let mut misses = 0;
                while misses < LOOKAHEAD {
                    let next = if wider {
                        widen(self.ev, &self.params, &y, d, i)
                    } else {
                        narrow(self.ev, &self.params, &y, i)
                    };
                    let Some(next) = next else {
                        break;
                    };
                    y = next;
                    match self.probe(&y, best, limits, started, on_point)? {
                        Probe::Stopped(end) => return Ok(Err(Err(end))),
                        Probe::Meets(j) => return Ok(Err(Ok(j))),
                        Probe::At(j, r) if r < line.0 => (line, misses) = ((r, j), 0),
                        // Wider runs to the cap (at most MAX_WIDEN_STEPS steps):
                        // the error is not monotone in a width (fig6's texels one
                        // bit wider alone: max 5.72 -> 9.08 at 720x480).
                        Probe::At(..) if wider => {}
                        Probe::At(..) => misses += 1,
                        Probe::Invalid | Probe::Pruned => break,
                    }
                }
            }
            c = line.1;
        }
        Ok(Ok(()))
    }

    /// The error ratio of point `j` (None: pruned).
    fn ratio_of(&self, j: usize) -> Option<f64> {
        self.points[j]
            .metrics()
            .map(|m| self.budget.ratio(&m.error))
    }

    /// Visit `y` for the repair, keeping the lowest error ratio seen in `best`.
    fn probe(
        &mut self,
        y: &[u32],
        best: &mut Option<(f64, usize)>,
        limits: &Limits,
        started: Instant,
        on_point: &mut dyn FnMut(&Book),
    ) -> Result<Probe, String> {
        let j = match self.visit(y, limits, started, on_point)? {
            Visit::At(j) => j,
            Visit::Invalid => return Ok(Probe::Invalid),
            Visit::Stopped(end) => return Ok(Probe::Stopped(end)),
        };
        let Some(m) = self.points[j].metrics() else {
            return Ok(Probe::Pruned);
        };
        if self.budget.meets(&m.error) {
            return Ok(Probe::Meets(j));
        }
        let r = self.budget.ratio(&m.error);
        if best.is_none_or(|(br, _)| r < br) {
            *best = Some((r, j));
        }
        Ok(Probe::At(j, r))
    }

    /// `a=1 b=2` for a point's values.
    pub fn describe(&self, values: &[u32]) -> String {
        describe(&self.params, values)
    }

    /// Lowest objective cost among the simulated points that meet the budget.
    pub fn best(&self, objective: Objective) -> Option<usize> {
        let mut best: Option<(usize, f64, f64)> = None;
        for (i, p) in self.points.iter().enumerate() {
            if let Some(m) = p.metrics() {
                if !self.budget.meets(&m.error) {
                    continue;
                }
                let (c, r) = (objective.cost(m), self.budget.ratio(&m.error));
                if best.is_none_or(|(_, bc, br)| c < bc || (c == bc && r < br)) {
                    best = Some((i, c, r));
                }
            }
        }
        best.map(|b| b.0)
    }
}

/// `a=1 b=2`.
pub fn describe(params: &[&str], values: &[u32]) -> String {
    params
        .iter()
        .zip(values)
        .map(|(p, v)| format!("{p}={v}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// How many steps above its default the repair phase may widen a parameter.
pub const MAX_WIDEN_STEPS: u32 = 4;

/// `values` with parameter `i` widened by one step, or None `MAX_WIDEN_STEPS` above
/// its default `d`.
fn widen(t: &dyn Target, params: &[&str], values: &[u32], d: &[u32], i: usize) -> Option<Vec<u32>> {
    let v = values[i];
    let (n, cap) = match t.step(params[i]) {
        Step::Bit => (v.checked_add(1)?, d[i].saturating_add(MAX_WIDEN_STEPS)),
        Step::Halve => (v.checked_mul(2)?, d[i].saturating_mul(1 << MAX_WIDEN_STEPS)),
    };
    if n > cap {
        return None;
    }
    let mut out = values.to_vec();
    out[i] = n;
    Some(out)
}

/// `values` with parameter `i` widened by one step (no cap: the polish only trades
/// a step back that a narrowing took).
fn widen_any(t: &dyn Target, params: &[&str], values: &[u32], i: usize) -> Option<Vec<u32>> {
    let mut out = values.to_vec();
    out[i] = match t.step(params[i]) {
        Step::Bit => values[i].checked_add(1)?,
        Step::Halve => values[i].checked_mul(2)?,
    };
    Some(out)
}

/// `values` with parameter `i` narrowed by one step, or None at its floor.
fn narrow(t: &dyn Target, params: &[&str], values: &[u32], i: usize) -> Option<Vec<u32>> {
    let v = values[i];
    let n = match t.step(params[i]) {
        Step::Bit => v.checked_sub(1)?,
        Step::Halve if v > 1 => v / 2,
        Step::Halve => return None,
    };
    let mut out = values.to_vec();
    out[i] = n;
    Some(out)
}

/// The defaults' values of `params` in the evaluator's scene.
pub fn defaults(ev: &dyn Target, params: &[&'static str]) -> Result<Vec<u32>, String> {
    params.iter().map(|p| ev.default_value(p)).collect()
}

/// Mark the points on the Pareto front of (gates, RAM bits, `metric` error) among
/// the simulated points: none of them is dominated by another (≤ in all three, < in
/// one).
pub fn mark_front(points: &mut [Point], metric: Metric) {
    let key = |p: &Point| {
        p.metrics()
            .map(|m| (m.gates, m.ram_bits as f64, metric.of(&m.error)))
    };
    let keys: Vec<Option<(f64, f64, f64)>> = points.iter().map(key).collect();
    for i in 0..points.len() {
        points[i].on_front = match keys[i] {
            None => false,
            Some(a) => !keys.iter().flatten().any(|b| dominates(*b, a)),
        };
    }
}

/// b dominates a: no worse in every coordinate, better in one.
pub fn dominates(b: (f64, f64, f64), a: (f64, f64, f64)) -> bool {
    b.0 <= a.0 && b.1 <= a.1 && b.2 <= a.2 && (b.0 < a.0 || b.1 < a.1 || b.2 < a.2)
}

/// The (objective cost, `metric` error) of a simulated point: the plane `pareto.png`
/// draws (error on x, cost on y).
pub fn objective_key(p: &Point, objective: Objective, metric: Metric) -> Option<(f64, f64)> {
    p.metrics()
        .map(|m| (metric.of(&m.error), objective.cost(m)))
}

/// b dominates a in the plane of [`objective_key`]: no worse in both, better in one.
pub fn dominates_2d(b: (f64, f64), a: (f64, f64)) -> bool {
    b.0 <= a.0 && b.1 <= a.1 && (b.0 < a.0 || b.1 < a.1)
}

/// For each point, whether it is on the front of (objective cost, `metric` error)
/// among the simulated points: the front `pareto.png` draws and `pareto.csv`'s
/// `on_objective_front` column. The 3-D front of [`mark_front`] (gates, RAM bits,
/// error) holds every point of this one whose key no other point shares, and
/// more: a point with fewer gates but more RAM bits than another is on the 3-D
/// front whichever objective is chosen.
pub fn objective_front(points: &[Point], objective: Objective, metric: Metric) -> Vec<bool> {
    let keys: Vec<Option<(f64, f64)>> = points
        .iter()
        .map(|p| objective_key(p, objective, metric))
        .collect();
    keys.iter()
        .map(|k| match k {
            None => false,
            Some(a) => !keys.iter().flatten().any(|b| dominates_2d(*b, *a)),
        })
        .collect()
}

/// Narrowings of one parameter tried past a violation before it backs off.
pub const LOOKAHEAD: usize = 2;
/// Lazy priority: unscored parameters first.
const UNSCORED: f64 = f64::INFINITY;
/// Error added below this (in budget ratio) counts as this much: a free saving is
/// taken by its size.
const EPS: f64 = 1e-3;

/// The greedy descent (module notes). `on_point` sees the book after each new point
/// (the CLI saves the CSV and moves the progress bar there).
pub fn search(
    ev: &dyn Target,
    params: &[&'static str],
    budget: &Budget,
    objective: Objective,
    seed: u64,
    limits: &Limits,
    on_point: &mut dyn FnMut(&Book),
) -> Result<Outcome, String> {
    let started = Instant::now();
    let mut book = Book::new(ev, params, budget, true);
    let start = defaults(ev, params)?;
    let finish = |book: Book, defaults: usize, best: Option<usize>, end: End| Outcome {
        params: params.to_vec(),
        points: book.points,
        defaults,
        best,
        simulations: book.simulations,
        pruned: book.pruned,
        end,
    };
    let d = match book.visit(&start, limits, started, on_point)? {
        Visit::At(i) => i,
        Visit::Invalid => return Err("scene: its own widths do not validate".into()),
        Visit::Stopped(end) => return Ok(finish(book, 0, None, end)),
    };
    let run = Descent {
        ev,
        params,
        budget,
        objective,
        limits,
        started,
    };
    let mut x = match run.repair(&mut book, d, &start, on_point)? {
        Repaired::Meets(x) => x,
        Repaired::GaveUp => {
            let best = book.best(objective);
            return Ok(finish(book, d, best, End::DefaultsBreakBudget));
        }
        Repaired::Stopped(end) => return Ok(finish(book, d, None, end)),
    };
    let mut order: Vec<usize> = (0..params.len()).collect();
    order.shuffle(&mut rand_chacha::ChaCha8Rng::seed_from_u64(seed));
    // Passes until one moves nothing: a parameter backed off in one pass is tried
    // again from where the next pass starts.
    let end = loop {
        let at_start = x;
        if let Err(end) = run.narrowing_pass(&mut book, &mut x, &order, on_point)? {
            break end;
        }
        if x != at_start {
            continue;
        }
        match run.polish(&mut book, &mut x, &order, on_point)? {
            Ok(true) => {}
            Ok(false) => break End::Converged,
            Err(end) => break end,
        }
    };
    let best = book.best(objective);
    Ok(finish(book, d, best, end))
}

/// What every step of one [`search`] reads.
struct Descent<'s> {
    ev: &'s dyn Target,
    params: &'s [&'static str],
    budget: &'s Budget,
    objective: Objective,
    limits: &'s Limits<'s>,
    started: Instant,
}

/// How the repair of the defaults ended.
enum Repaired {
    /// At this point, which meets the budget.
    Meets(usize),
    /// Nothing lowered the error further: the defaults break the budget.
    GaveUp,
    /// A limit stopped it.
    Stopped(End),
}

impl Descent<'_> {
    /// Repair: while point `x` (first the defaults `start`'s) breaks the budget, widen
    /// the parameter with the best error removed per cost added (at most
    /// MAX_WIDEN_STEPS above its default); else every parameter together; else the
    /// wider repairs ([`Book::repair_wider`]) before giving up.
    fn repair(
        &self,
        book: &mut Book,
        mut x: usize,
        start: &[u32],
        on_point: &mut dyn FnMut(&Book),
    ) -> Result<Repaired, String> {
        loop {
            let mx = *book.points[x].metrics().ok_or("defaults pruned")?;
            if self.budget.meets(&mx.error) {
                return Ok(Repaired::Meets(x));
            }
            match self.best_widening(book, x, &mx, start, on_point)? {
                Ok(Some(j)) => {
                    x = j;
                    continue;
                }
                Ok(None) => {}
                Err(end) => return Ok(Repaired::Stopped(end)),
            }
            // No single widening helps (the error may need two widths at once, e.g.
            // texels and framebuffer): widen every parameter by one step together.
            match self.joint_widening(book, x, &mx, start, on_point)? {
                Ok(Some(j)) => x = j,
                Ok(None) => {
                    // The joint step did not help either: the wider repairs before giving up.
                    match book.repair_wider(x, start, self.limits, self.started, on_point)? {
                        Ok(Some(j)) => x = j,
                        Ok(None) => return Ok(Repaired::GaveUp),
                        Err(end) => return Ok(Repaired::Stopped(end)),
                    }
                }
                Err(end) => return Ok(Repaired::Stopped(end)),
            }
        }
    }

    /// Of the one-step widenings of point `x` (metrics `mx`), the one removing the most
    /// error ratio per cost added (None: none lowers the error). `Err(end)`: a limit.
    fn best_widening(
        &self,
        book: &mut Book,
        x: usize,
        mx: &Metrics,
        start: &[u32],
        on_point: &mut dyn FnMut(&Book),
    ) -> Result<Result<Option<usize>, End>, String> {
        let (budget, objective) = (self.budget, self.objective);
        let mut pick: Option<(f64, usize)> = None;
        for i in 0..self.params.len() {
            let Some(y) = widen(self.ev, self.params, &book.points[x].values, start, i) else {
                continue;
            };
            let j = match book.visit(&y, self.limits, self.started, on_point)? {
                Visit::At(j) => j,
                Visit::Invalid => continue,
                Visit::Stopped(end) => return Ok(Err(end)),
            };
            let Some(my) = book.points[j].metrics() else {
                continue;
            };
            let gain = budget.ratio(&mx.error) - budget.ratio(&my.error);
            if gain <= 0.0 {
                continue;
            }
            let added = (objective.cost(my) - objective.cost(mx)).max(0.0);
            let s = gain / (added + 1.0);
            if pick.is_none_or(|(b, _)| s > b) {
                pick = Some((s, j));
            }
        }
        Ok(Ok(pick.map(|(_, j)| j)))
    }

    /// Point `x` with every parameter one step wider (those at their caps stay), when
    /// that lowers the error ratio below `mx`'s (else None). `Err(end)`: a limit.
    fn joint_widening(
        &self,
        book: &mut Book,
        x: usize,
        mx: &Metrics,
        start: &[u32],
        on_point: &mut dyn FnMut(&Book),
    ) -> Result<Result<Option<usize>, End>, String> {
        let mut y = book.points[x].values.clone();
        for i in 0..self.params.len() {
            if let Some(n) = widen(self.ev, self.params, &y, start, i) {
                y = n;
            }
        }
        let j = match book.visit(&y, self.limits, self.started, on_point)? {
            Visit::At(j) => Some(j),
            Visit::Invalid => None,
            Visit::Stopped(end) => return Ok(Err(end)),
        };
        Ok(Ok(j.filter(|&j| {
            book.points[j]
                .metrics()
                .is_some_and(|my| self.budget.ratio(&my.error) < self.budget.ratio(&mx.error))
        })))
    }

    /// One pass of narrowings from point `x` (moved as it goes): the active parameter
    /// with the highest (possibly stale) score is narrowed when its saving is at least
    /// every other's score; a parameter with no saving backs off for the rest of the
    /// pass. `Err(end)`: a limit.
    fn narrowing_pass(
        &self,
        book: &mut Book,
        x: &mut usize,
        order: &[usize],
        on_point: &mut dyn FnMut(&Book),
    ) -> Result<Result<(), End>, String> {
        let mut active = order.to_vec();
        let mut score = vec![UNSCORED; self.params.len()];
        // The active parameter with the highest (possibly stale) score.
        while let Some(k) = (0..active.len()).reduce(|a, b| {
            if score[active[b]] > score[active[a]] {
                b
            } else {
                a
            }
        }) {
            let i = active[k];
            // The first of up to LOOKAHEAD narrowings of parameter i that meets the
            // budget and saves cost (error is not monotone in every width: one bit
            // less can break the budget where two bits less does not).
            let from = book.points[*x].values.clone();
            let found = match book.first_saving(
                self.objective,
                *x,
                &from,
                i,
                self.limits,
                self.started,
                on_point,
            )? {
                Ok(f) => f,
                Err(end) => return Ok(Err(end)),
            };
            let Some((j, s)) = found else {
                // Back off: this parameter stays where it is for the rest of the pass.
                active.remove(k);
                continue;
            };
            score[i] = s;
            let others = active
                .iter()
                .filter(|&&o| o != i)
                .map(|&o| score[o])
                .fold(f64::NEG_INFINITY, f64::max);
            if s >= others {
                *x = j;
            }
        }
        Ok(Ok(()))
    }

    /// Polish: trade one step of width in parameter a for up to LOOKAHEAD steps less
    /// in parameter b, taking the first trade that meets the budget and saves cost (a
    /// greedy descent stops in a local minimum such a trade leaves). Returns whether
    /// it moved `x` (false: converged); `Err(end)`: a limit.
    fn polish(
        &self,
        book: &mut Book,
        x: &mut usize,
        order: &[usize],
        on_point: &mut dyn FnMut(&Book),
    ) -> Result<Result<bool, End>, String> {
        for &a in order {
            let Some(up) = widen_any(self.ev, self.params, &book.points[*x].values, a) else {
                continue;
            };
            for &b in order.iter().filter(|&&b| b != a) {
                match book.first_saving(
                    self.objective,
                    *x,
                    &up,
                    b,
                    self.limits,
                    self.started,
                    on_point,
                )? {
                    Ok(Some((j, _))) => {
                        *x = j;
                        return Ok(Ok(true));
                    }
                    Ok(None) => {}
                    Err(end) => return Ok(Err(end)),
                }
            }
        }
        Ok(Ok(false))
    }
}

/// Every value a parameter takes from its default down, one step at a time, while
/// the scene with only that change validates.
pub fn ladder(ev: &dyn Target, params: &[&'static str], i: usize) -> Result<Vec<u32>, String> {
    let mut v = defaults(ev, params)?;
    let mut out = vec![v[i]];
    while let Some(n) = narrow(ev, params, &v, i) {
        if !ev.valid(params, &n) {
            break;
        }
        v = n;
        out.push(v[i]);
    }
    Ok(out)
}

/// The exhaustive grid over every parameter's [`ladder`], each point simulated (no
/// pruning): what the search is measured against. Returns the book.
pub fn grid<'a>(
    ev: &'a dyn Target,
    params: &[&'static str],
    budget: &'a Budget,
) -> Result<Book<'a>, String> {
    let ladders: Vec<Vec<u32>> = (0..params.len())
        .map(|i| ladder(ev, params, i))
        .collect::<Result<_, _>>()?;
    let mut book = Book::new(ev, params, budget, false);
    let never = || false;
    let limits = Limits {
        max_evals: None,
        seconds: None,
        stop: &never,
    };
    let started = Instant::now();
    let mut at = vec![0usize; params.len()];
    loop {
        let values: Vec<u32> = at.iter().zip(&ladders).map(|(&k, l)| l[k]).collect();
        book.visit(&values, &limits, started, &mut |_| {})?;
        // Next index, odometer style.
        let mut d = 0;
        loop {
            if d == at.len() {
                return Ok(book);
            }
            at[d] += 1;
            if at[d] < ladders[d].len() {
                break;
            }
            at[d] = 0;
            d += 1;
        }
    }
}
