//! Say when the hardware is out of its range: after a frame, the rules below read the
//! units' counters (and, where no counter can see the loss, the scene's geometry) and
//! warn when a unit saturated, overflowed or underflowed for more than a small share of
//! its fragments, or a table's range was clamped — naming the unit, the event, the
//! share, the scene field that drove it there and the nearest value that would fit.
//!
//! A counter rule is one row of `RULES`: the pipeline and unit instance, the event,
//! its denominator (fragments, or fragments × 3 channels), the threshold, and the scene
//! fields that can drive it (in the order they are tried). The driving field is found by
//! a sensitivity check: the frame is rendered reduced (at most [`REDUCED_WIDTH`] pixels
//! wide) with each candidate moved to an ordinary value, and the first candidate whose
//! move brings the share under the threshold is named; the nearest value that fits is
//! then bisected between the scene's value and that ordinary value on the reduced frame
//! (rounded to three significant digits towards the ordinary side). The host rules
//! (depth-buffer resolution, h-table range) are analytic. docs/frame.md lists the rules
//! and why the counters it leaves alone are ordinary.

use super::run::{render, Frame};
use crate::pipeline::shafts::host::scene_geometry;
use crate::pipeline::shafts::prepare::{for_each_lit_point, in_cone, lit_ranges};
use crate::scene::camera::vec3;
use crate::scene::format::{LightKind, Scene};
use crate::scene::geometry::Ray;
use rtl_model::Counters;
use serde::Serialize;

/// One warning: which unit ran out of its range, how often, and why.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RangeWarning {
    /// "shafts", "glare" or "envmap".
    pub pipeline: String,
    /// The unit instance as the counters name it.
    pub unit: String,
    /// "saturations", "overflows", "underflows", "depth resolution" or "table range".
    pub event: String,
    /// Share of the rule's denominator (fragments, fragments × channels, sample planes
    /// or lit samples) the event hit, in [0, ∞) (a fragment may saturate on several
    /// planes).
    pub share: f64,
    /// What the share is a share of.
    pub of: String,
    /// The scene field that drove the unit there (its path as the scene file spells it).
    pub field: String,
    /// The field's value in the scene.
    pub value: String,
    /// The nearest value of `field` that brings the share under the threshold, where
    /// one was found.
    pub nearest: Option<String>,
    /// The rule's threshold.
    pub threshold: f64,
}

impl std::fmt::Display for RangeWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "warning: {} unit `{}` out of range: {} on {:.1} % of {} (threshold {:.1} %), driven by {} = {}",
            self.pipeline,
            self.unit,
            self.event,
            self.share * 100.0,
            self.of,
            self.threshold * 100.0,
            self.field,
            self.value
        )?;
        match &self.nearest {
            Some(n) => write!(f, "; nearest value that fits: {} = {n}", self.field),
            None => write!(f, "; no value of it found that fits"),
        }
    }
}

/// Frames wider than this are reduced to it (same aspect) for the sensitivity check.
pub const REDUCED_WIDTH: u32 = 64;

/// Bisection steps for the nearest value.
const BISECT_STEPS: u32 = 10;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Event {
    Saturations,
    Overflows,
    Underflows,
}

impl Event {
    fn name(self) -> &'static str {
        match self {
            Event::Saturations => "saturations",
            Event::Overflows => "overflows",
            Event::Underflows => "underflows",
        }
    }

    fn count(self, c: &Counters) -> u64 {
        match self {
            Event::Saturations => c.saturations,
            Event::Overflows => c.overflows,
            Event::Underflows => c.underflows,
        }
    }
}

/// Which scene fields can drive a rule's unit out of range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Drivers {
    /// The shafts frame: a user-set h-table range shorter than the lit volume's, the
    /// camera's eye inside a light's cone, a spot's wide cutoff, a light's intensity
    /// (tried in that order).
    Shafts,
    /// The glare sources' intensities.
    GlareSources,
}

/// One counter rule.
struct Rule {
    pipeline: &'static str,
    /// The unit instance's counter name; a trailing `*` matches any suffix.
    unit: &'static str,
    event: Event,
    /// Denominator: pixels_in × 3 (an event per colour channel) or pixels_in.
    per_channel: bool,
    threshold: f64,
    drivers: Drivers,
}

/// The counter rules. What is absent is ordinary (docs/frame.md § Out of range): the
/// shadow compare's saturations (border lookups outside the shadow map, lit by
/// convention), the projective unit's saturations (coordinates clamped to the light
/// map's edge, outside the cone) and underflows (q ≤ 0: behind the projector, which a
/// spot with a cutoff under 90° does not light; the unit returns "unlit", which is the
/// right answer), the J buffer's underflows (sub-plane averages below
/// one level), and the glare interpolator's overflows (its accumulators WRAP, modular,
/// so pixels whose true value fits come out right).
const RULES: &[Rule] = &[
    Rule {
        pipeline: "shafts",
        unit: "additive_blend",
        event: Event::Saturations,
        per_channel: true,
        threshold: 0.01,
        drivers: Drivers::Shafts,
    },
    Rule {
        pipeline: "shafts",
        unit: "additive_blend (J buffer)",
        event: Event::Saturations,
        per_channel: true,
        threshold: 0.01,
        drivers: Drivers::Shafts,
    },
    Rule {
        pipeline: "shafts",
        unit: "projective_texcoord (depth)",
        event: Event::Saturations,
        per_channel: false,
        threshold: 0.05,
        drivers: Drivers::Shafts,
    },
    Rule {
        pipeline: "shafts",
        unit: "modulate",
        event: Event::Saturations,
        per_channel: true,
        threshold: 0.01,
        drivers: Drivers::Shafts,
    },
    Rule {
        pipeline: "shafts",
        unit: "texture_sampler*",
        event: Event::Saturations,
        per_channel: false,
        threshold: 0.01,
        drivers: Drivers::Shafts,
    },
    Rule {
        pipeline: "shafts",
        unit: "texture_sampler*",
        event: Event::Overflows,
        per_channel: false,
        threshold: 0.01,
        drivers: Drivers::Shafts,
    },
    Rule {
        pipeline: "shafts",
        unit: "polygon_interpolator",
        event: Event::Saturations,
        per_channel: false,
        threshold: 0.01,
        drivers: Drivers::Shafts,
    },
    Rule {
        pipeline: "shafts",
        unit: "polygon_interpolator",
        event: Event::Underflows,
        per_channel: false,
        threshold: 0.001,
        drivers: Drivers::Shafts,
    },
    Rule {
        pipeline: "glare",
        unit: "bloom_flare_modulator",
        event: Event::Saturations,
        per_channel: false,
        threshold: 0.01,
        drivers: Drivers::GlareSources,
    },
    Rule {
        pipeline: "glare",
        unit: "halo_modulator",
        event: Event::Saturations,
        per_channel: false,
        threshold: 0.01,
        drivers: Drivers::GlareSources,
    },
    Rule {
        pipeline: "glare",
        unit: "glare_combiner",
        event: Event::Saturations,
        per_channel: true,
        threshold: 0.25,
        drivers: Drivers::GlareSources,
    },
];

impl Rule {
    fn matches(&self, pipeline: &str, unit: &str) -> bool {
        pipeline == self.pipeline
            && match self.unit.strip_suffix('*') {
                Some(prefix) => unit.starts_with(prefix),
                None => unit == self.unit,
            }
    }

    fn share(&self, c: &Counters) -> Option<f64> {
        let den = c.pixels_in * if self.per_channel { 3 } else { 1 };
        (den > 0).then(|| self.event.count(c) as f64 / den as f64)
    }

    fn of(&self) -> &'static str {
        if self.per_channel {
            "fragments × channels"
        } else {
            "fragments"
        }
    }
}

/// Sets a candidate's parameter in a scene.
type Setter = Box<dyn Fn(&mut Scene, f64)>;

/// A scene field the sensitivity check can move: a scalar parameter `x`, the scene's
/// value `value`, an `ordinary` value at which the unit is expected in range.
struct Candidate {
    field: String,
    value: f64,
    ordinary: f64,
    /// Bisect in log space (a positive scale factor) rather than linearly.
    log: bool,
    set: Setter,
    show: Box<dyn Fn(f64) -> String>,
}

/// Every warning for a rendered frame of `scene`.
pub fn check(scene: &Scene, frame: &Frame) -> Vec<RangeWarning> {
    check_counted(scene, frame).0
}

/// [`check`], with the number of reduced frames the sensitivity check rendered (at
/// most a fixed number per warning, whatever the scene's number of sources).
pub fn check_counted(scene: &Scene, frame: &Frame) -> (Vec<RangeWarning>, usize) {
    let mut out = host_rules(scene, frame);
    out.extend(check_environment(scene));
    let counters = frame.counters();
    let mut probe = Probe::new(scene);
    for rule in RULES {
        let Some(units) = counters.get(rule.pipeline) else {
            continue;
        };
        for (unit, c) in units {
            if !rule.matches(rule.pipeline, unit) {
                continue;
            }
            let Some(share) = rule.share(c) else { continue };
            if share <= rule.threshold {
                continue;
            }
            let (field, value, nearest) = probe.drive(rule, unit);
            out.push(RangeWarning {
                pipeline: rule.pipeline.to_string(),
                unit: unit.clone(),
                event: rule.event.name().to_string(),
                share,
                of: rule.of().to_string(),
                field,
                value,
                nearest,
                threshold: rule.threshold,
            });
        }
    }
    (out, probe.renders.get())
}

/// Print the warnings to stderr, one a line.
pub fn print(warnings: &[RangeWarning]) {
    for w in warnings {
        eprintln!("{w}");
    }
}

/// The scene at most [`REDUCED_WIDTH`] pixels wide (same aspect).
pub fn reduced(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    if s.image.width > REDUCED_WIDTH {
        let h = (s.image.height as f64 * REDUCED_WIDTH as f64 / s.image.width as f64).round();
        s.image.width = REDUCED_WIDTH;
        s.image.height = (h as u32).max(8);
    }
    s
}

/// Renders of the reduced scene with one field moved, for the sensitivity check.
struct Probe {
    base: Scene,
    /// Reduced frames rendered so far.
    renders: std::cell::Cell<usize>,
}

impl Probe {
    fn new(scene: &Scene) -> Self {
        Probe {
            base: reduced(scene),
            renders: std::cell::Cell::new(0),
        }
    }

    /// The rule's share for `unit` on the reduced scene with `c` set to `x` (None when
    /// the render fails: the value is not one the scene accepts).
    fn share_at(&self, rule: &Rule, unit: &str, c: &Candidate, x: f64) -> Option<f64> {
        let mut s = self.base.clone();
        (c.set)(&mut s, x);
        s.validate().ok()?;
        self.renders.set(self.renders.get() + 1);
        let f = render(&s).ok()?;
        let counters = f.counters();
        let share = counters
            .get(rule.pipeline)
            .and_then(|m| m.get(unit))
            .and_then(|c| rule.share(c))
            .unwrap_or(0.0);
        Some(share)
    }

    /// The driving field, its value and the nearest value that fits.
    fn drive(&mut self, rule: &Rule, unit: &str) -> (String, String, Option<String>) {
        let cands = candidates(&self.base, rule.drivers, rule.event == Event::Underflows);
        let fits = |x: Option<f64>| x.is_some_and(|s| s <= rule.threshold);
        for c in &cands {
            if !fits(self.share_at(rule, unit, c, c.ordinary)) {
                continue;
            }
            // Bisect between the value (out of range) and the ordinary value (fits).
            let (mut lo, mut hi) = (c.value, c.ordinary);
            let mid = |a: f64, b: f64| {
                if c.log {
                    (a.ln() * 0.5 + b.ln() * 0.5).exp()
                } else {
                    0.5 * (a + b)
                }
            };
            for _ in 0..BISECT_STEPS {
                let m = mid(lo, hi);
                if fits(self.share_at(rule, unit, c, m)) {
                    hi = m;
                } else {
                    lo = m;
                }
            }
            // Three significant digits, stepped towards the ordinary side until it fits
            // (the share need not be monotonic in the field).
            let dir = c.ordinary - c.value;
            let mut nearest = snap(hi, dir);
            for _ in 0..50 {
                if fits(self.share_at(rule, unit, c, nearest)) {
                    break;
                }
                nearest += snap_step(nearest).copysign(dir);
            }
            return (c.field.clone(), (c.show)(c.value), Some((c.show)(nearest)));
        }
        // No single field silences it: name the first candidate without a nearest value.
        match cands.first() {
            Some(c) => (c.field.clone(), (c.show)(c.value), None),
            None => ("scene".to_string(), "-".to_string(), None),
        }
    }
}

/// The step of the third significant digit of `x`.
fn snap_step(x: f64) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return 1e-3;
    }
    10f64.powf(x.abs().log10().floor() - 2.0)
}

/// `x` rounded to three significant digits in the direction `toward` (its sign).
fn snap(x: f64, toward: f64) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let step = snap_step(x);
    let q = x / step;
    let q = if toward > 0.0 { q.ceil() } else { q.floor() };
    q * step
}

/// A number as the scene file would spell it (three significant digits at most past
/// the point).
fn show_num(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let mag = x.abs().log10().floor();
    if !(-4.0..7.0).contains(&mag) {
        return format!("{x:e}");
    }
    let decimals = (2.0 - mag).max(0.0) as usize;
    let s = format!("{x:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

fn show_vec(v: [f64; 3]) -> String {
    let c = |x: f64| {
        let s = format!("{x:.4}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        if s == "-0" {
            "0".to_string()
        } else {
            s.to_string()
        }
    };
    format!("[{}, {}, {}]", c(v[0]), c(v[1]), c(v[2]))
}

/// The candidates for a rule's drivers, in the order they are tried (`up`: an
/// underflow, which a larger intensity cures; else a smaller one).
fn candidates(scene: &Scene, drivers: Drivers, up: bool) -> Vec<Candidate> {
    let mut out = Vec::new();
    match drivers {
        Drivers::Shafts => {
            table_candidates(scene, &mut out);
            light_candidates(scene, &mut out);
        }
        Drivers::GlareSources => glare_candidates(scene, up, &mut out),
    }
    out
}

/// Glare sources tried one by one: every source of a frame of at most this many, else
/// this many of the brightest. Each costs a reduced frame, so a frame of thousands of
/// sources is not probed once per source.
const GLARE_SINGLE_CANDIDATES: usize = 4;

/// The glare units' candidates: single sources' intensities (in index order; the
/// brightest first when there are more than [`GLARE_SINGLE_CANDIDATES`]), then, with
/// several sources, every source's intensity scaled by one factor (what silences a
/// combiner saturated by many sources together, which no single one drives).
fn glare_candidates(scene: &Scene, up: bool, out: &mut Vec<Candidate>) {
    let Some(g) = &scene.glare else {
        return;
    };
    let ordinary = if up { 1e4 } else { 1e-4 };
    let mut lit: Vec<usize> = (0..g.sources.len())
        .filter(|&i| g.sources[i].intensity > 0.0)
        .collect();
    let several = lit.len() > 1;
    if lit.len() > GLARE_SINGLE_CANDIDATES {
        // Brightest first (a stable sort: equal ones in index order).
        lit.sort_by(|&a, &b| g.sources[b].intensity.total_cmp(&g.sources[a].intensity));
        lit.truncate(GLARE_SINGLE_CANDIDATES);
    }
    for i in lit {
        let v = g.sources[i].intensity;
        out.push(Candidate {
            field: format!("glare.sources[{i}].intensity"),
            value: v,
            ordinary: v * ordinary,
            log: true,
            set: Box::new(move |sc, x| {
                if let Some(g) = sc.glare.as_mut() {
                    g.sources[i].intensity = x;
                }
            }),
            show: Box::new(show_num),
        });
    }
    if several {
        let n = g.sources.len();
        out.push(Candidate {
            field: "glare.sources[*].intensity".to_string(),
            value: 1.0,
            ordinary,
            log: true,
            set: Box::new(|sc, x| {
                if let Some(g) = sc.glare.as_mut() {
                    for s in &mut g.sources {
                        s.intensity *= x;
                    }
                }
            }),
            show: Box::new(move |x| format!("×{} (all {n} sources scaled together)", show_num(x))),
        });
    }
}

/// A spot's cutoff is a candidate above this; it is moved to [`ORDINARY_CUTOFF_DEG`]
/// (the paper's Fig. 6 spot).
const WIDE_CUTOFF_DEG: f64 = 30.0;
const ORDINARY_CUTOFF_DEG: f64 = 25.0;

fn light_candidates(scene: &Scene, out: &mut Vec<Candidate>) {
    let cam = &scene.camera;
    let eye = vec3(cam.eye);
    let forward = (vec3(cam.look_at) - eye).normalized();
    // The eye inside a light's cone, nearer the light than the look-at point is: move
    // it back along the view axis (by up to the eye–look-at distance).
    for l in &scene.lights {
        let d = (eye - vec3(l.position)).length();
        let reach = (vec3(cam.look_at) - vec3(l.position)).length();
        if in_cone(l, eye) && d < reach {
            let e0 = cam.eye;
            let span = (vec3(cam.look_at) - eye).length().max(1.0);
            let at = move |k: f64| {
                let e = vec3(e0) - forward * k;
                [e.x, e.y, e.z]
            };
            out.push(Candidate {
                field: "camera.eye".to_string(),
                value: 0.0,
                ordinary: span,
                log: false,
                set: Box::new(move |sc, k| sc.camera.eye = at(k)),
                show: Box::new(move |k| show_vec(at(k))),
            });
            break;
        }
    }
    for (i, l) in scene.lights.iter().enumerate() {
        if l.kind == LightKind::Spot && l.cutoff_deg > WIDE_CUTOFF_DEG {
            out.push(Candidate {
                field: format!("lights[{i}].cutoff_deg"),
                value: l.cutoff_deg,
                ordinary: ORDINARY_CUTOFF_DEG,
                log: false,
                set: Box::new(move |sc, x| sc.lights[i].cutoff_deg = x),
                show: Box::new(show_num),
            });
        }
    }
    // A light's intensity, down then up: too bright saturates, and in a frame with
    // several lights one far brighter than the rest sets the scale the others' colours
    // underflow in.
    for (i, l) in scene.lights.iter().enumerate() {
        if l.intensity > 0.0 {
            for scale in [1e-4, 1e4] {
                out.push(Candidate {
                    field: format!("lights[{i}].intensity"),
                    value: l.intensity,
                    ordinary: l.intensity * scale,
                    log: true,
                    set: Box::new(move |sc, x| sc.lights[i].intensity = x),
                    show: Box::new(show_num),
                });
            }
        }
    }
}

fn table_candidates(scene: &Scene, out: &mut Vec<Candidate>) {
    if scene.shafts.s_max > 0.0 {
        if let Some(auto) = auto_ranges(scene) {
            if auto.0 > scene.shafts.s_max {
                out.push(Candidate {
                    field: "shafts.s_max".to_string(),
                    value: scene.shafts.s_max,
                    ordinary: auto.0,
                    log: true,
                    set: Box::new(|sc, x| sc.shafts.s_max = x),
                    show: Box::new(show_num),
                });
            }
        }
    }
}

/// The h table's ranges the host would choose (`s_max = t_max = 0`).
fn auto_ranges(scene: &Scene) -> Option<(f64, f64)> {
    let geom = scene_geometry(scene).ok()?;
    let first_hit = |o, d| {
        geom.first_hit(&Ray { origin: o, dir: d }, f64::INFINITY)
            .map(|(_, h)| h.t)
    };
    let lit = lit_ranges(scene, &first_hit);
    Some((lit.s_max, lit.t_max))
}

/// Bits of the shafts frame's depth buffer (its one definition, beside the frame).
pub const DEPTH_BUFFER_BITS: u32 = crate::pipeline::shafts::frame::ZBUF_BITS;

/// A sample plane's depth test resolves it when the depth buffer's step at its depth
/// is at most this share of the plane spacing.
pub const DEPTH_STEP_SHARE: f64 = 0.25;

/// A user-set h-table range warns when more than this share of the lit samples lie
/// past it.
pub const TABLE_RANGE_SHARE: f64 = 0.01;

/// The view-depth step of one depth-buffer word at view depth `r` (GL's window depth
/// 0.5 + 0.5·z_ndc; dz_w/dr = f·n / ((f − n)·r²)).
pub fn depth_step(near: f64, far: f64, r: f64) -> f64 {
    (far - near) * r * r / (far * near) / f64::from(1u32 << DEPTH_BUFFER_BITS)
}

/// The analytic rules no counter sees.
fn host_rules(scene: &Scene, frame: &Frame) -> Vec<RangeWarning> {
    let mut out = Vec::new();
    let Some(p) = &frame.plan.prepared else {
        return out;
    };
    if frame.shafts.is_none() || scene.lights.is_empty() {
        return out;
    }
    let (near, far) = (scene.camera.near, scene.camera.far);
    // Depth resolution at the sample planes: the planes' depth test against the objects
    // needs the depth buffer to tell depths a fraction of a plane spacing apart.
    let (r0, r1) = p.plane_range;
    let n = scene.shafts.planes.max(1);
    let dr = (r1 - r0) / n as f64;
    if dr > 0.0 {
        let limit = dr * DEPTH_STEP_SHARE;
        let bad = (0..n)
            .filter(|&i| depth_step(near, far, r0 + (i as f64 + 0.5) * dr) > limit)
            .count();
        if bad > 0 {
            // step(r1) ≤ limit ⇔ 1/n ≤ limit·2^B/r1² + 1/f.
            let r = r1.max(near);
            let q = limit * f64::from(1u32 << DEPTH_BUFFER_BITS) / (r * r);
            let nearest = snap(1.0 / (q + 1.0 / far), 1.0);
            out.push(RangeWarning {
                pipeline: "shafts".into(),
                unit: "shadow_compare (depth buffer)".into(),
                event: "depth resolution".into(),
                share: bad as f64 / n as f64,
                of: format!(
                    "sample planes (a depth-buffer step over {DEPTH_STEP_SHARE} of the plane spacing {})",
                    show_num(dr)
                ),
                field: "camera.near".into(),
                value: show_num(near),
                nearest: Some(show_num(nearest)),
                threshold: 0.0,
            });
        }
    }
    // The h table's user-set ranges against the lit samples' light and eye distances.
    if scene.shafts.s_max > 0.0 || scene.shafts.t_max > 0.0 {
        if let Some((s_auto, t_auto)) = auto_ranges(scene) {
            let samples = lit_samples(scene);
            for (field, set, auto, k) in [
                ("shafts.s_max", scene.shafts.s_max, s_auto, 0usize),
                ("shafts.t_max", scene.shafts.t_max, t_auto, 1),
            ] {
                if set <= 0.0 || samples.is_empty() {
                    continue;
                }
                let past = samples
                    .iter()
                    .filter(|st| if k == 0 { st.0 > set } else { st.1 > set })
                    .count();
                let share = past as f64 / samples.len() as f64;
                if share > TABLE_RANGE_SHARE {
                    out.push(RangeWarning {
                        pipeline: "shafts".into(),
                        unit: "texture_sampler (h)".into(),
                        event: "table range".into(),
                        share,
                        of: "lit samples (coordinates clamped to the table's edge)".into(),
                        field: field.into(),
                        value: show_num(set),
                        nearest: Some(show_num(snap(auto, 1.0))),
                        threshold: TABLE_RANGE_SHARE,
                    });
                }
            }
        }
    }
    out
}

/// An environment map's texels clamped at full scale (radiance × exposure > 1) on more
/// than this share of the sphere (solid-angle weighted) warn; the auto exposure clamps
/// 1 % by construction (`EnvMap::auto_exposure`), night-street's chosen exposure 0.5
/// of the Venice map 4.5 %.
pub const ENV_CLAMP_SHARE: f64 = 0.10;

/// Non-zero texels rounded to level 0 on more than this share of the sphere warn.
pub const ENV_UNDERFLOW_SHARE: f64 = 0.25;

/// The environment map's texels at the scene's exposure: the share clamped at full
/// scale and the share of non-zero texels rounded to zero, with the nearest exposure
/// that keeps each under its threshold (analytic: a weighted quantile).
pub fn check_environment(scene: &Scene) -> Vec<RangeWarning> {
    let mut out = Vec::new();
    let Some(section) = &scene.environment else {
        return out;
    };
    let Ok(env) = section.load() else {
        return out;
    };
    let exposure = section.exposure_for(&env);
    let (w, h) = (env.width(), env.height());
    let mut v: Vec<(f64, f64)> = Vec::with_capacity(w * h);
    for j in 0..h {
        let wt = env.texel_solid_angle(j);
        for t in &env.texels()[j * w..(j + 1) * w] {
            v.push((t[0].max(t[1]).max(t[2]), wt));
        }
    }
    v.sort_by(|a, b| a.0.total_cmp(&b.0));
    let total: f64 = v.iter().map(|p| p.1).sum();
    if total <= 0.0 {
        return out;
    }
    // The radiance at cumulative weight share q (from the dark end).
    let quantile = |q: f64, from: usize| {
        let sub: f64 = v[from..].iter().map(|p| p.1).sum();
        let mut acc = 0.0;
        for p in &v[from..] {
            acc += p.1;
            if acc >= q * sub {
                return p.0;
            }
        }
        v.last().map_or(0.0, |p| p.0)
    };
    let field = "environment.exposure";
    let value = match section.exposure {
        Some(e) => show_num(e),
        None => format!("auto ({})", show_num(exposure)),
    };
    let clamped: f64 = v
        .iter()
        .filter(|p| p.0 * exposure > 1.0)
        .map(|p| p.1)
        .sum::<f64>()
        / total;
    if clamped > ENV_CLAMP_SHARE {
        let r = quantile(1.0 - ENV_CLAMP_SHARE, 0);
        out.push(RangeWarning {
            pipeline: "envmap".into(),
            unit: "texture_sampler (environment)".into(),
            event: "table range".into(),
            share: clamped,
            of: "the sphere's solid angle (texels clamped at full scale)".into(),
            field: field.into(),
            value: value.clone(),
            nearest: (r > 0.0).then(|| show_num(snap(1.0 / r, -1.0))),
            threshold: ENV_CLAMP_SHARE,
        });
    }
    let first_lit = v.iter().position(|p| p.0 > 0.0).unwrap_or(v.len());
    let lit: f64 = v[first_lit..].iter().map(|p| p.1).sum();
    if lit > 0.0 {
        let zero = 0.5 / 255.0;
        let under: f64 = v[first_lit..]
            .iter()
            .filter(|p| p.0 * exposure < zero)
            .map(|p| p.1)
            .sum::<f64>()
            / lit;
        if under > ENV_UNDERFLOW_SHARE {
            let r = quantile(ENV_UNDERFLOW_SHARE, first_lit);
            out.push(RangeWarning {
                pipeline: "envmap".into(),
                unit: "texture_sampler (environment)".into(),
                event: "underflows".into(),
                share: under,
                of: "the lit sphere's solid angle (non-zero texels rounded to level 0)".into(),
                field: field.into(),
                value,
                nearest: (r > 0.0).then(|| show_num(snap(zero / r, 1.0))),
                threshold: ENV_UNDERFLOW_SHARE,
            });
        }
    }
    out
}

/// (light distance s, eye distance t) of points in the lit volume in front of the
/// first surface, on a 24 × 16 grid of rays (cell centres) × 64 depths.
fn lit_samples(scene: &Scene) -> Vec<(f64, f64)> {
    let Ok(geom) = scene_geometry(scene) else {
        return Vec::new();
    };
    let cam = crate::scene::camera::CameraView::new(&scene.camera, scene.image);
    let (gx, gy, gz) = (24usize, 16usize, 64usize);
    let centres = (0..gy).flat_map(|iy| {
        (0..gx).map(move |ix| ((ix as f64 + 0.5) / gx as f64, (iy as f64 + 0.5) / gy as f64))
    });
    let first_hit = |origin, dir| {
        geom.first_hit(&Ray { origin, dir }, f64::INFINITY)
            .map(|(_, h)| h.t)
    };
    let mut out = Vec::new();
    for_each_lit_point(scene, &cam, centres, gz, &first_hit, |q| {
        out.push((q.s, q.t))
    });
    out
}

/// One distinct warning of a run of several frames (a sweep, a reproduction), with
/// every point where it fired.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PointWarning {
    /// The warning at the first point where it fired.
    pub warning: RangeWarning,
    /// The labels of the points where it fired (`planes = 20`), in order.
    pub points: Vec<String>,
}

impl std::fmt::Display for PointWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} [at {}", self.warning, self.points[0])?;
        if self.points.len() > 1 {
            write!(
                f,
                " and {} more point(s): {}",
                self.points.len() - 1,
                self.points[1..].join(", ")
            )?;
        }
        write!(f, "]")
    }
}

/// The warnings of the points of a sweep or reproduction (label, scene), once per
/// distinct warning (pipeline, unit, event, field), each naming the points where it
/// fired. Each point is checked on its frame reduced to [`REDUCED_WIDTH`] pixels wide
/// (as the sensitivity check renders it: a sweep does not keep its frames), an
/// environment scene by [`check_environment`]; a point whose frame does not render
/// here is skipped (the run itself reported it).
pub fn check_points(points: &[(String, Scene)]) -> Vec<PointWarning> {
    let mut out: Vec<PointWarning> = Vec::new();
    for (label, scene) in points {
        // A run stopped (SIGINT, SIGTERM) once its rows are saved ends here.
        crate::report::interrupt::exit_if_requested();
        let warnings = if super::plan::environment_scene(scene) {
            check_environment(scene)
        } else {
            let s = reduced(scene);
            match render(&s) {
                Ok(f) => check(&s, &f),
                Err(_) => continue,
            }
        };
        for w in warnings {
            let same = |p: &&mut PointWarning| {
                let o = &p.warning;
                (
                    o.pipeline.as_str(),
                    o.unit.as_str(),
                    o.event.as_str(),
                    o.field.as_str(),
                ) == (
                    w.pipeline.as_str(),
                    w.unit.as_str(),
                    w.event.as_str(),
                    w.field.as_str(),
                )
            };
            match out.iter_mut().find(same) {
                Some(p) => {
                    if !p.points.contains(label) {
                        p.points.push(label.clone());
                    }
                }
                None => out.push(PointWarning {
                    warning: w,
                    points: vec![label.clone()],
                }),
            }
        }
    }
    out
}

/// Print [`check_points`]' warnings to stderr, one a line.
pub fn print_points(warnings: &[PointWarning]) {
    for w in warnings {
        eprintln!("{w}");
    }
}
