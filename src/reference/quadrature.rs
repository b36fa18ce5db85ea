//! Adaptive quadrature of the single-scattering integral I_s for one pixel: the
//! accurate reference against which the ray-marcher (and the hardware) is measured.
//!
//! Per light, the integrand f(t) = H · I_l · F(α) · h(max(s, s_min), t) on [0, T]
//! ([`crate::reference::raymarch::scatter_integrand`]) is split at breakpoints and
//! integrated by globally adaptive Gauss–Kronrod G7/K15 (QUADPACK QAG: the interval
//! with the largest error estimate is bisected until the summed estimate is below
//! max(abs, rel · |I|), the depth limit or the evaluation budget).
//!
//! Breakpoints:
//! * the ray's entry into and exit from the spot's cone (roots of the cone quadric);
//! * the point of closest approach to the light t*, and t* ± w · 10^k (k = 0, 1, …)
//!   with w = max(d⊥, s_min), d⊥ the light's distance from the ray line: 1/s² is a
//!   Lorentzian of width d⊥ there, stiff when the light is close to the ray; if
//!   d⊥ < s_min also t* ± √(s_min² − d⊥²), where the clamp starts;
//! * jumps of the integrand — shadow boundaries (H), the cone edge and the light map's
//!   own edges (polka-dot rims) — found by probing a discrete state at `probes` points
//!   (half uniform in t, half uniform in the angle seen from the light, t = t* + w tan φ,
//!   since shadow and map edges are evenly spread in that angle) and bisecting between
//!   probes whose states differ down to 1e-13 · T. A feature thinner than the probe
//!   spacing can be missed by the probes; the adaptive bisection then still converges
//!   on it, only more slowly.
//!
//! The clamp: the true integral through a light lying on the ray diverges like
//! ∫ dt/s²; with s replaced by max(s, s_min) it is finite, about ρ·(F(0) + F(π)) · 2/s_min
//! (for κ = 0: ρK(22/s_min − 10/t* − 1/(T − t*)) exactly; see the tests).

// `!(x > 0.0)` is deliberate throughout: it is true for NaN, which must take the safe
// branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use crate::reference::raymarch::{primary, scatter_integrand, LightEval};
use crate::reference::shafts_model::{mul_no_nan, S_MIN};
use crate::scene::format::{LightKind, Medium, Scene};
use crate::scene::geometry::{Ray, SceneGeometry};
use crate::scene::lightmap::map_r2;

/// Tolerances and limits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadTol {
    /// Relative tolerance on each light's integral.
    pub rel: f64,
    /// Absolute tolerance on each light's (scalar, colour-less) integral.
    pub abs: f64,
    /// Maximum bisection depth below an initial (breakpoint) interval.
    pub max_depth: u32,
    /// Evaluation budget per light (integrand evaluations and state probes).
    pub max_evaluations: u64,
    /// The clamp of s in h (world units).
    pub s_min: f64,
    /// State probes per light for the discontinuity search (≥ 2).
    pub probes: u32,
    /// Check every interval against its two halves: the initial intervals are split
    /// once before any is accepted, and each half's error is at least half of
    /// |K15(whole) − K15(left) − K15(right)|. GK's own estimate compares K15 with G7 on
    /// the same interval; at a kink inside it both rules can be off by nearly the same
    /// amount, and the estimate then understates the error by orders of magnitude (the
    /// albedo of a V-cavity lobe at grazing, whose masking term has kinks, was stated
    /// to 1.1·10⁻⁸ while 2.1·10⁻⁶ off). The halves see the kink at other relative
    /// positions, so the two estimates do not fail together.
    pub halving_check: bool,
}

impl Default for QuadTol {
    fn default() -> Self {
        QuadTol {
            rel: 1e-9,
            abs: 1e-14,
            max_depth: 60,
            max_evaluations: 1_000_000,
            s_min: S_MIN,
            probes: 256,
            halving_check: false,
        }
    }
}

impl QuadTol {
    /// The default with a relative tolerance.
    pub fn rel(rel: f64) -> Self {
        QuadTol {
            rel,
            ..Self::default()
        }
    }
}

/// The result for one pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadResult {
    /// I_v = I_o · exp(−ρκT) + I_s, linear RGB (comparable with `raymarch_pixel`).
    pub value: [f64; 3],
    /// I_s alone.
    pub scattered: [f64; 3],
    /// I_o · exp(−ρκT) alone (exact; no quadrature involved).
    pub surface: [f64; 3],
    /// Estimated absolute error of I_s per channel.
    pub error_estimate: [f64; 3],
    /// Integrand evaluations (each with a shadow ray where the light emits) plus state
    /// probes, over all lights.
    pub evaluations: u64,
    /// Every light met its tolerance (false: depth limit or budget reached).
    pub converged: bool,
    /// The integration interval [0, T].
    pub t_end: f64,
}

/// The scalar integral of one light: (value, error estimate, evaluations, converged).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightIntegral {
    pub value: f64,
    pub error: f64,
    pub evaluations: u64,
    pub converged: bool,
}

/// Adaptive quadrature of pixel (px, py); see the module doc.
pub fn quadrature_pixel(
    scene: &Scene,
    geom: &SceneGeometry,
    px: u32,
    py: u32,
    tol: &QuadTol,
) -> QuadResult {
    let lights = LightEval::all(scene, geom);
    let pr = primary(scene, geom, &lights, px as f64, py as f64);
    let mut scattered = [0.0; 3];
    let mut err = [0.0; 3];
    let mut evaluations = 0;
    let mut converged = true;
    if pr.t_end > 0.0 {
        for le in &lights {
            let li = integrate_light(le, &scene.medium, geom, &pr.ray, pr.t_end, tol);
            evaluations += li.evaluations;
            converged &= li.converged;
            for c in 0..3 {
                scattered[c] += mul_no_nan(li.value, le.light.color[c]);
                err[c] += mul_no_nan(li.error, le.light.color[c].abs());
            }
        }
    }
    QuadResult {
        value: std::array::from_fn(|c| pr.surface[c] + scattered[c]),
        scattered,
        surface: pr.surface,
        error_estimate: err,
        evaluations,
        converged,
        t_end: pr.t_end,
    }
}

// QUADPACK qk15 nodes and weights.
const XGK: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
const WGK: [f64; 8] = [
    0.022_935_322_010_529_22,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_2,
    0.140_653_259_715_525_9,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_727_8,
];
const WG: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// G7/K15 on [a, b]: (K15 value, QUADPACK error estimate).
fn gk15(f: &mut dyn FnMut(f64) -> f64, a: f64, b: f64) -> (f64, f64) {
    let c = 0.5 * (a + b);
    let hl = 0.5 * (b - a);
    let fc = f(c);
    let mut resk = fc * WGK[7];
    let mut resg = fc * WG[3];
    let mut resabs = resk.abs();
    let mut fv1 = [0.0; 7];
    let mut fv2 = [0.0; 7];
    for j in 0..7 {
        let dx = hl * XGK[j];
        let (f1, f2) = (f(c - dx), f(c + dx));
        fv1[j] = f1;
        fv2[j] = f2;
        resk += WGK[j] * (f1 + f2);
        resabs += WGK[j] * (f1.abs() + f2.abs());
        if j % 2 == 1 {
            resg += WG[j / 2] * (f1 + f2);
        }
    }
    let reskh = resk * 0.5;
    let mut resasc = WGK[7] * (fc - reskh).abs();
    for j in 0..7 {
        resasc += WGK[j] * ((fv1[j] - reskh).abs() + (fv2[j] - reskh).abs());
    }
    let result = resk * hl;
    let resabs = resabs * hl.abs();
    let resasc = resasc * hl.abs();
    let mut err = ((resk - resg) * hl).abs();
    if resasc != 0.0 && err != 0.0 {
        err = resasc * (200.0 * err / resasc).powf(1.5).min(1.0);
    }
    let uflow = f64::MIN_POSITIVE / (50.0 * f64::EPSILON);
    if resabs > uflow {
        err = err.max(50.0 * f64::EPSILON * resabs);
    }
    if err.is_nan() {
        err = f64::INFINITY;
    }
    (result, err)
}

#[derive(Clone, Copy, Debug)]
struct Piece {
    a: f64,
    b: f64,
    value: f64,
    err: f64,
    depth: u32,
}

impl PartialEq for Piece {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl Eq for Piece {}
impl PartialOrd for Piece {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Piece {
    /// Largest error first; ties by position (deterministic).
    fn cmp(&self, o: &Self) -> Ordering {
        self.err
            .total_cmp(&o.err)
            .then_with(|| o.a.total_cmp(&self.a))
    }
}

/// Globally adaptive GK15 of `f` over the consecutive intervals given by sorted
/// `breaks` (first = a, last = b): (value, summed error estimate, converged). Also
/// the BRDF albedo quadrature's 1-D rule.
pub(crate) fn adaptive(
    f: &mut dyn FnMut(f64) -> f64,
    breaks: &[f64],
    tol: &QuadTol,
    evals: &mut u64,
) -> (f64, f64, bool) {
    let mut heap = BinaryHeap::new();
    let mut done: Vec<Piece> = Vec::new();
    let (mut total, mut total_err) = (0.0, 0.0);
    for w in breaks.windows(2) {
        let (a, b) = (w[0], w[1]);
        if !(b > a) {
            continue;
        }
        let (value, err) = gk15(f, a, b);
        *evals += 15;
        let m = 0.5 * (a + b);
        if tol.halving_check && m > a && m < b {
            let (v1, e1) = gk15(f, a, m);
            let (v2, e2) = gk15(f, m, b);
            *evals += 30;
            let half_gap = 0.5 * (value - v1 - v2).abs();
            for (a, b, value, err) in [(a, m, v1, e1.max(half_gap)), (m, b, v2, e2.max(half_gap))] {
                total += value;
                total_err += err;
                heap.push(Piece {
                    a,
                    b,
                    value,
                    err,
                    depth: 1,
                });
            }
            continue;
        }
        total += value;
        total_err += err;
        heap.push(Piece {
            a,
            b,
            value,
            err,
            depth: 0,
        });
    }
    let mut converged = true;
    loop {
        if total_err <= tol.abs.max(tol.rel * total.abs()) {
            break;
        }
        let Some(p) = heap.pop() else {
            break;
        };
        let m = 0.5 * (p.a + p.b);
        if p.depth >= tol.max_depth || *evals + 30 > tol.max_evaluations || !(m > p.a && m < p.b) {
            // Cannot refine this one; keep it and try the next largest.
            converged = false;
            done.push(p);
            continue;
        }
        let (v1, mut e1) = gk15(f, p.a, m);
        let (v2, mut e2) = gk15(f, m, p.b);
        *evals += 30;
        if tol.halving_check {
            let half_gap = 0.5 * (p.value - v1 - v2).abs();
            e1 = e1.max(half_gap);
            e2 = e2.max(half_gap);
        }
        total += v1 + v2 - p.value;
        total_err += e1 + e2 - p.err;
        for (a, b, value, err) in [(p.a, m, v1, e1), (m, p.b, v2, e2)] {
            heap.push(Piece {
                a,
                b,
                value,
                err,
                depth: p.depth + 1,
            });
        }
    }
    // Exact final sums in a fixed order.
    let mut all: Vec<Piece> = heap.into_vec();
    all.extend(done);
    all.sort_by(|x, y| x.a.total_cmp(&y.a));
    let value: f64 = all.iter().map(|p| p.value).sum();
    let err: f64 = all.iter().map(|p| p.err).sum();
    let converged = converged && err <= tol.abs.max(tol.rel * value.abs()) * (1.0 + 1e-9);
    (value, err, converged)
}

/// Where the ray (unit `dir`) crosses the spot's cone surface, in (0, T).
fn cone_crossings(le: &LightEval<'_>, ray: &Ray, t_end: f64) -> Vec<f64> {
    let fr = &le.frame;
    if fr.kind != LightKind::Spot || !(fr.tan_cutoff > 0.0) {
        return Vec::new();
    }
    let c2 = 1.0 / (1.0 + fr.tan_cutoff * fr.tan_cutoff); // cos² c
    let w0 = ray.origin - fr.position;
    let (wf, df) = (w0.dot(fr.forward), ray.dir.dot(fr.forward));
    let dd = ray.dir.dot(ray.dir);
    let a = df * df - c2 * dd;
    let b = 2.0 * (wf * df - c2 * w0.dot(ray.dir));
    let c = wf * wf - c2 * w0.dot(w0);
    let mut roots = Vec::new();
    if a.abs() > 1e-14 * (df * df + c2 * dd) {
        let disc = b * b - 4.0 * a * c;
        if disc >= 0.0 {
            let q = -0.5 * (b + b.signum() * disc.sqrt());
            if q != 0.0 {
                roots.push(q / a);
                roots.push(c / q);
            }
        }
    } else if b != 0.0 {
        roots.push(-c / b);
    }
    roots
        .into_iter()
        .filter(|t| t.is_finite() && *t > 0.0 && *t < t_end)
        .collect()
}

/// Integrate one light along `ray` over [0, t_end].
pub fn integrate_light(
    le: &LightEval<'_>,
    medium: &Medium,
    geom: &SceneGeometry,
    ray: &Ray,
    t_end: f64,
    tol: &QuadTol,
) -> LightIntegral {
    let mut evals: u64 = 0;
    if !(t_end > 0.0) || !t_end.is_finite() {
        return LightIntegral {
            value: 0.0,
            error: 0.0,
            evaluations: 0,
            converged: true,
        };
    }
    let s_min = tol.s_min.max(0.0);
    let lp = le.frame.position;
    let w0 = lp - ray.origin;
    let t_star_line = w0.dot(ray.dir);
    let d_perp = (w0 - ray.dir * t_star_line).length();
    let near = Nearest {
        t_star_line,
        d_perp,
        width: d_perp.max(s_min).max(1e-12 * t_end),
    };
    let mut breaks = vec![0.0, t_end];
    breaks.extend(cone_crossings(le, ray, t_end));
    breaks.extend(nearest_breaks(&near, t_end, s_min));
    breaks.extend(state_breaks(le, geom, ray, t_end, &near, tol, &mut evals));
    let clean = clean_breaks(breaks, t_end);

    let mut f = |t: f64| scatter_integrand(le, medium, geom, ray, t, s_min);
    let (value, error, converged) = adaptive(&mut f, &clean, tol, &mut evals);
    LightIntegral {
        value,
        error,
        evaluations: evals,
        converged,
    }
}

/// Where the ray passes the light: the parameter of its closest approach on the
/// infinite line, the distance there, and the width the breakpoints crowd to
/// (the distance, at least s_min and 1e-12 · T).
struct Nearest {
    t_star_line: f64,
    d_perp: f64,
    width: f64,
}

/// Breakpoints at the closest approach (clamped into [0, T]), at width · 10^k either
/// side of it, and where the distance to the light is s_min (the clamp's kink).
fn nearest_breaks(near: &Nearest, t_end: f64, s_min: f64) -> Vec<f64> {
    let (t_star_line, d_perp, width) = (near.t_star_line, near.d_perp, near.width);
    let mut breaks = Vec::new();
    let t_star = t_star_line.clamp(0.0, t_end);
    breaks.push(t_star);
    for side in [-1.0, 1.0] {
        let mut k = width;
        while k < t_end {
            breaks.push(t_star_line + side * k);
            k *= 10.0;
        }
        if d_perp < s_min {
            breaks.push(t_star_line + side * (s_min * s_min - d_perp * d_perp).sqrt());
        }
    }
    breaks
}

/// Breakpoints where the discrete state (in the cone, the map's label, lit) changes:
/// probes uniform in t and uniform in the angle seen from the light, each change
/// bisected down to 1e-13 · T. The state evaluations are counted in `evals`.
fn state_breaks(
    le: &LightEval<'_>,
    geom: &SceneGeometry,
    ray: &Ray,
    t_end: f64,
    near: &Nearest,
    tol: &QuadTol,
    evals: &mut u64,
) -> Vec<f64> {
    let (t_star_line, width) = (near.t_star_line, near.width);
    let lp = le.frame.position;
    // Discrete state: (in cone, map label, H where the light emits).
    let fr = le.frame;
    let state = |t: f64, evals: &mut u64| -> (bool, u64, bool) {
        *evals += 1;
        let p = ray.at(t);
        let (in_cone, label) = match fr.kind {
            LightKind::Point => (true, 0),
            LightKind::Spot => match fr.map_coords(p) {
                Some((u, v)) if map_r2(u, v) <= 1.0 => (true, le.map.discontinuity_label(u, v)),
                _ => (false, 0),
            },
        };
        let emits = in_cone && le.weight(p) > 0.0;
        let lit = !emits || !geom.occluded(p, lp);
        (in_cone, label, lit)
    };
    let n = tol.probes.max(2) as usize;
    let mut probes: Vec<f64> = (0..=n / 2)
        .map(|k| t_end * k as f64 / (n / 2) as f64)
        .collect();
    let (phi0, phi1) = (
        ((0.0 - t_star_line) / width).atan(),
        ((t_end - t_star_line) / width).atan(),
    );
    let na = n - n / 2;
    for k in 0..na {
        let phi = phi0 + (phi1 - phi0) * (k as f64 + 0.5) / na as f64;
        probes.push((t_star_line + width * phi.tan()).clamp(0.0, t_end));
    }
    probes.sort_by(f64::total_cmp);
    probes.dedup();
    let states: Vec<_> = probes.iter().map(|&t| state(t, evals)).collect();
    let resolution = 1e-13 * t_end;
    let mut breaks = Vec::new();
    for k in 1..probes.len() {
        if states[k] == states[k - 1] {
            continue;
        }
        let (mut a, mut b) = (probes[k - 1], probes[k]);
        let sa = states[k - 1];
        while b - a > resolution {
            let m = 0.5 * (a + b);
            if !(m > a && m < b) {
                break;
            }
            if state(m, evals) == sa {
                a = m;
            } else {
                b = m;
            }
        }
        breaks.push(0.5 * (a + b));
    }
    breaks
}

/// The breakpoints inside [0, T], sorted, those within 1e-14 · T of the previous one
/// dropped, the last one T and the first 0.
fn clean_breaks(mut breaks: Vec<f64>, t_end: f64) -> Vec<f64> {
    breaks.retain(|t| t.is_finite() && *t >= 0.0 && *t <= t_end);
    breaks.sort_by(f64::total_cmp);
    let min_gap = 1e-14 * t_end;
    let mut clean: Vec<f64> = Vec::with_capacity(breaks.len());
    for t in breaks {
        match clean.last() {
            Some(&l) if t - l <= min_gap => {}
            _ => clean.push(t),
        }
    }
    if let Some(l) = clean.last_mut() {
        *l = t_end;
    }
    if clean.first() != Some(&0.0) {
        clean.insert(0, 0.0);
    }
    clean
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gk15_exact_for_polynomials_and_adaptive_for_sqrt() {
        let mut f = |x: f64| x.powi(10);
        let (v, _) = gk15(&mut f, 0.0, 1.0);
        assert!((v - 1.0 / 11.0).abs() < 1e-15);
        let mut g = |x: f64| x.sqrt();
        let mut e = 0;
        let tol = QuadTol::rel(1e-12);
        let (v, err, ok) = adaptive(&mut g, &[0.0, 1.0], &tol, &mut e);
        assert!(ok, "err {err}");
        assert!((v - 2.0 / 3.0).abs() < 1e-11);
        // A jump at an irrational point: bisection localises it.
        let mut h = |x: f64| {
            if x < std::f64::consts::FRAC_1_SQRT_2 {
                1.0
            } else {
                0.0
            }
        };
        let (v, _, _) = adaptive(&mut h, &[0.0, 1.0], &QuadTol::rel(1e-10), &mut e);
        assert!((v - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-9);
    }
}
