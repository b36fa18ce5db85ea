//! Directional albedo ρ(ω) = ∫ R(ω, ω') cos θ' dω' (or with the arguments swapped) by
//! nested globally adaptive Gauss–Kronrod G7/K15 ([`crate::reference::quadrature`]'s
//! rule), with an error stated from a convergence check.
//!
//! The sphere of the free direction is charted around where the model's mass is
//! ([`Brdf::lobe`]):
//! * `Diffuse`, `Mirror` and isotropic `HalfVector`: polar angle θ' about an axis (+z
//!   for diffuse models, the mirror of the fixed direction for lobes, where isotropic
//!   microfacet lobes peak too) outside, azimuth φ' inside, over the above-horizon arc
//!   of each cone, φ' ∈ [−φ_m, φ_m], cos φ_m = −cot θ' cot θ_axis in closed form, so
//!   the horizon is never a discontinuity inside an interval; the outer integrand's
//!   kink where the arc starts to be cut (θ' = π/2 − θ_axis) is a breakpoint;
//! * anisotropic `HalfVector` (Ward with α_x ≠ α_y): the half vector h in polar
//!   coordinates about +z, the free direction its reflection 2(ω·h)h − ω with the
//!   Jacobian 4 (ω·h); the reflection is above the horizon iff
//!   cos(φ − φ_f) > −cot θ_f cot 2θ, again a closed-form arc, and the azimuth
//!   breakpoints sit at multiples of π/2 and crowd toward 0 and π, where an
//!   x-elongated lobe lies. (The mirror chart cannot follow a 100:1 lobe; this chart
//!   follows it exactly but is the less reliable of the two at extreme grazing: for
//!   an isotropic Cook–Torrance lobe at θ = 89.9° it disagreed with the mirror and the
//!   normal-axis charts, which agree with each other, by 3e-6 while both passes agreed to 1e-8,
//!   so it is used only where the mirror chart cannot be.)
//! * `TangentCone`: polar angle about the tangent +x (the Kajiya–Kay cone is a line
//!   θ' = const there), the horizon being φ' ∈ (0, π) exactly.
//!
//! The polar breakpoints run geometrically (×10) from a tenth of the lobe's width up,
//! so the adaptive rule sees a lobe of any width (exponent 10⁴, roughness 1e-7), and
//! toward the horizon from a tenth of cos θ_fixed (grazing incidence puts the features
//! there). A feature narrower than every breakpoint scale can still be missed by both
//! passes alike; the tests cross-check the charts against each other and against
//! closed forms for that reason.
//!
//! Every interval's error is also checked against its two halves
//! ([`QuadTol::halving_check`]): a kink of a masking term inside an interval can make
//! K15 and G7 agree while both are off (the V-cavity lobe at 89.9° was stated to
//! 1.1·10⁻⁸ while 2.1·10⁻⁶ off), and the halves see the kink elsewhere.
//!
//! The stated error: the integral is computed twice, at tolerance 100 τ and at τ, and
//! the error is |A_τ − A_{100τ}| + the GK estimate of A_τ — the change under a
//! hundredfold tightening plus what the finer rule still claims. Since A_{100τ} is
//! accurate to about 100 τ, this overstates the error of A_τ, which is what a bound
//! wants.

// `!(x > 0.0)` is deliberate: it is true for NaN, which must take the safe branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::model::{mirror, Brdf, Lobe};
use crate::reference::quadrature::{adaptive, QuadTol};
use crate::scene::math::{v3, Vec3};
use std::f64::consts::{FRAC_PI_2, PI};

/// Which argument of R is held fixed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FixedSide {
    /// ρ(ω_i) = ∫ R(ω_i, ω_o) cos θ_o dω_o: energy conservation for light from ω_i.
    Incident,
    /// ρ(ω_o) = ∫ R(ω_i, ω_o) cos θ_i dω_i.
    Outgoing,
}

/// Tolerances of the finer of the two passes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AlbedoTol {
    /// Relative tolerance τ of the outer integral (the inner ones get τ/10).
    pub rel: f64,
    /// Absolute tolerance of the outer integral (the inner ones get a tenth).
    pub abs: f64,
    /// Outer (polar) integrand evaluations allowed per pass.
    pub max_outer: u64,
    /// BRDF evaluations allowed per inner (azimuth) integral.
    pub max_inner: u64,
}

impl Default for AlbedoTol {
    fn default() -> Self {
        AlbedoTol {
            rel: 1e-8,
            abs: 1e-11,
            max_outer: 6_000,
            max_inner: 12_000,
        }
    }
}

/// An albedo with its stated error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Albedo {
    /// A_τ.
    pub value: f64,
    /// |A_τ − A_{100τ}| + the GK estimate of A_τ.
    pub error: f64,
    /// A_{100τ}.
    pub coarse: f64,
    /// BRDF evaluations of both passes.
    pub evaluations: u64,
    /// Both passes met their tolerance within the budgets.
    pub converged: bool,
}

/// ρ of `brdf` with `fixed` (renormalised) held on `side`. A fixed direction on or
/// below the horizon (or zero) has albedo 0 exactly.
pub fn directional_albedo(brdf: &dyn Brdf, fixed: Vec3, side: FixedSide, tol: AlbedoTol) -> Albedo {
    let fixed = fixed.normalized();
    if !(fixed.z > 0.0) {
        return Albedo {
            value: 0.0,
            error: 0.0,
            coarse: 0.0,
            evaluations: 0,
            converged: true,
        };
    }
    let coarse_tol = AlbedoTol {
        rel: tol.rel * 100.0,
        abs: tol.abs * 100.0,
        ..tol
    };
    let (coarse, _, ev_c, ok_c) = integrate(brdf, fixed, side, &coarse_tol);
    let (value, est, ev_f, ok_f) = integrate(brdf, fixed, side, &tol);
    Albedo {
        value,
        error: (value - coarse).abs() + est,
        coarse,
        evaluations: ev_c + ev_f,
        converged: ok_c && ok_f,
    }
}

/// ∫ f over the consecutive intervals of sorted `breaks` by adaptive GK15:
/// (value, error estimate, evaluations, converged).
pub fn integrate_1d(
    f: &mut dyn FnMut(f64) -> f64,
    breaks: &[f64],
    rel: f64,
    abs: f64,
    max_evaluations: u64,
) -> (f64, f64, u64, bool) {
    let tol = QuadTol {
        rel,
        abs,
        max_depth: 60,
        max_evaluations,
        halving_check: true,
        ..QuadTol::default()
    };
    let mut evals = 0;
    let (v, e, ok) = adaptive(f, breaks, &tol, &mut evals);
    (v, e, evals, ok)
}

/// Sorted, deduplicated breakpoints inside [lo, hi] (ends included).
fn breaks_in(lo: f64, hi: f64, points: impl IntoIterator<Item = f64>) -> Vec<f64> {
    let mut b: Vec<f64> = points
        .into_iter()
        .filter(|&x| x > lo && x < hi)
        .chain([lo, hi])
        .collect();
    b.sort_by(f64::total_cmp);
    b.dedup_by(|a, b| (*a - *b).abs() <= 1e-15 * (1.0 + b.abs()));
    b
}

/// width/10 · 10^k, k = 0, 1, …, below `limit`.
fn geometric(width: f64, limit: f64) -> Vec<f64> {
    let mut v = Vec::new();
    let mut x = (width / 10.0).max(1e-9);
    while x < limit {
        v.push(x);
        x *= 10.0;
    }
    v
}

/// The half-width φ_m of the arc {φ : a + b cos φ > 0}, b ≥ 0: π (the whole circle),
/// 0 (none) or acos(−a/b). b ≈ 0 (the cone degenerates to a point or the fixed
/// direction is the normal) is all or nothing by the sign of a.
fn arc_half_width(a: f64, b: f64) -> f64 {
    if b <= 1e-300 {
        return if a > 0.0 { PI } else { 0.0 };
    }
    let q = -a / b;
    if q <= -1.0 {
        PI
    } else if q >= 1.0 {
        0.0
    } else {
        q.acos()
    }
}

/// One pass: (value, GK estimate, BRDF evaluations, converged).
fn integrate(
    brdf: &dyn Brdf,
    fixed: Vec3,
    side: FixedSide,
    tol: &AlbedoTol,
) -> (f64, f64, u64, bool) {
    let mut evaluations = 0u64;
    let inner_ok = std::cell::Cell::new(true);
    let weighted = |w: Vec3| -> f64 {
        evaluations += 1;
        if !(w.z > 0.0) {
            return 0.0;
        }
        let r = match side {
            FixedSide::Incident => brdf.eval(fixed, w),
            FixedSide::Outgoing => brdf.eval(w, fixed),
        };
        r * w.z
    };
    let (inner_rel, inner_abs) = (tol.rel / 10.0, tol.abs / 10.0);
    let inner = |g: &mut dyn FnMut(f64) -> f64, breaks: &[f64]| -> f64 {
        let (v, _, _, conv) = integrate_1d(g, breaks, inner_rel, inner_abs, tol.max_inner);
        if !conv {
            inner_ok.set(false);
        }
        v
    };
    let (outer_breaks, mut outer) = match brdf.lobe() {
        Lobe::Diffuse
        | Lobe::Mirror { .. }
        | Lobe::HalfVector {
            anisotropic: false, ..
        } => about_axis(brdf.lobe(), fixed, weighted, inner),
        Lobe::HalfVector {
            width,
            anisotropic: true,
        } => anisotropic_half_vector(width, fixed, weighted, inner),
        Lobe::TangentCone { width } => tangent_cone(width, fixed, weighted, inner),
    };
    let (value, est, _, outer_ok) =
        integrate_1d(&mut *outer, &outer_breaks, tol.rel, tol.abs, tol.max_outer);
    drop(outer);
    (value, est, evaluations, outer_ok && inner_ok.get())
}

/// The outer integral of one pass: its θ breakpoints and the integrand of θ (the
/// inner φ integral times sin θ).
type Outer<'a> = (Vec<f64>, Box<dyn FnMut(f64) -> f64 + 'a>);

/// The outer integral of a diffuse, mirror or isotropic half-vector lobe: polar angle θ
/// about the lobe's axis (the normal, or the mirror direction of `fixed`), azimuth φ
/// inside; `weighted` is R · cos θ of a direction (0 below the horizon), `inner` the
/// inner integral over φ.
fn about_axis<'a>(
    lobe: Lobe,
    fixed: Vec3,
    mut weighted: impl FnMut(Vec3) -> f64 + 'a,
    inner: impl Fn(&mut dyn FnMut(f64) -> f64, &[f64]) -> f64 + 'a,
) -> Outer<'a> {
    // Microfacet lobes peak at the mirror direction too (h = n there); in ω the
    // lobe is about twice as wide as in h.
    let (axis, width, half_vector) = match lobe {
        Lobe::Mirror { width } => (mirror(fixed), Some(width), false),
        Lobe::HalfVector { width, .. } => (mirror(fixed), Some(2.0 * width), true),
        _ => (v3(0.0, 0.0, 1.0), None, false),
    };
    let c_a = axis.z.min(1.0);
    let s_a = (axis.x * axis.x + axis.y * axis.y).sqrt();
    // u: perpendicular to the axis, toward +z (u_z = sin θ_axis); v = axis × u.
    let u = if s_a > 1e-12 {
        v3(-axis.x * c_a / s_a, -axis.y * c_a / s_a, s_a)
    } else {
        v3(1.0, 0.0, 0.0)
    };
    let v = axis.cross(u);
    let theta_axis = c_a.acos();
    let theta_max = (FRAC_PI_2 + theta_axis).min(PI);
    let mut pts = vec![FRAC_PI_2, FRAC_PI_2 - theta_axis];
    if let Some(w) = width {
        pts.extend(geometric(w, theta_max));
    }
    // Grazing incidence puts features within ~cos θ_fixed of the horizon.
    for d in geometric(fixed.z, 1.0) {
        pts.extend([FRAC_PI_2 - d, theta_max - d]);
    }
    let breaks = breaks_in(0.0, theta_max, pts);
    // A half-vector lobe is squeezed in ω: moving h by δ within the plane of
    // incidence moves the reflection by 2δ (cos θ_f ĥ_f + sin θ_f ẑ), across
    // it by only 2δ cos θ_f (ĥ_f the fixed direction's horizontal unit
    // vector). Near grazing that is a thin sliver along e = cos θ_f ĥ_f +
    // sin θ_f ẑ: azimuth breakpoints crowd toward e's direction, both ways.
    let mut phi_pts = Vec::new();
    if half_vector && s_a > 1e-12 {
        let e = v3(c_a * fixed.x / s_a, c_a * fixed.y / s_a, s_a);
        let phi_e = e.dot(v).atan2(e.dot(u));
        for centre in [phi_e - PI, phi_e, phi_e + PI] {
            phi_pts.push(centre);
            for d in [1e-4, 1e-3, 1e-2, 1e-1] {
                phi_pts.extend([centre - d, centre + d]);
            }
        }
    }
    let f = move |t: f64| -> f64 {
        let (st, ct) = t.sin_cos();
        // Above the horizon: ct c_a + st s_a cos φ > 0.
        let phi_max = arc_half_width(ct * c_a, st * s_a);
        if phi_max == 0.0 {
            return 0.0;
        }
        let mut g = |p: f64| {
            let (sp, cp) = p.sin_cos();
            weighted(axis * ct + (u * cp + v * sp) * st)
        };
        let b = breaks_in(
            -phi_max,
            phi_max,
            [-0.5 * phi_max, 0.0, 0.5 * phi_max]
                .into_iter()
                .chain(phi_pts.iter().copied()),
        );
        st * inner(&mut g, &b)
    };
    (breaks, Box::new(f))
}

/// The outer integral of an anisotropic half-vector lobe: the half vector h's polar
/// angle θ outside, its azimuth φ inside (Jacobian 4 (ω·h)); as [`about_axis`].
fn anisotropic_half_vector<'a>(
    width: f64,
    fixed: Vec3,
    mut weighted: impl FnMut(Vec3) -> f64 + 'a,
    inner: impl Fn(&mut dyn FnMut(f64) -> f64, &[f64]) -> f64 + 'a,
) -> Outer<'a> {
    // h at polar angle θ, azimuth φ; the reflection 2(ω·h)h − ω is above the
    // horizon iff cos(φ − φ_fixed) > q = −cos θ_f cos 2θ / (sin θ_f sin 2θ):
    // the arc is closed-form here too.
    let (c_f, s_f) = (
        fixed.z.min(1.0),
        (fixed.x * fixed.x + fixed.y * fixed.y).sqrt(),
    );
    let phi_f = fixed.y.atan2(fixed.x);
    // The arc is cut from θ = π/4 − θ_f/2 (q = −1) and gone at π/4 + θ_f/2
    // (q = 1): the outer integrand has √-type kinks there; breakpoints at
    // them and crowding toward them.
    let theta_f = c_f.acos();
    let (cut, gone) = (0.25 * PI - 0.5 * theta_f, 0.25 * PI + 0.5 * theta_f);
    let mut pts = geometric(width, FRAC_PI_2);
    pts.extend([cut, gone]);
    for d in geometric(c_f.min(width), 1.0) {
        pts.extend([d, FRAC_PI_2 - d, cut - d, cut + d, gone - d, gone + d]);
    }
    let breaks = breaks_in(0.0, gone.min(FRAC_PI_2), pts);
    // The lobe is a function of h's own azimuth (x, y axes): breakpoints at
    // multiples of π/2, crowding toward 0 and π where an x-elongated lobe is.
    let mut phi_pts = Vec::new();
    for k in -4..=4 {
        let centre = k as f64 * FRAC_PI_2;
        phi_pts.push(centre);
        if k % 2 == 0 {
            for d in [1e-4, 1e-3, 1e-2, 1e-1] {
                phi_pts.extend([centre - d, centre + d]);
            }
        }
    }
    let f = move |t: f64| -> f64 {
        let (st, ct) = t.sin_cos();
        let (s2t, c2t) = (2.0 * st * ct, ct * ct - st * st);
        let phi_max = arc_half_width(c_f * c2t, s_f * s2t);
        if phi_max == 0.0 {
            return 0.0;
        }
        let mut g = |p: f64| {
            let (sp, cp) = p.sin_cos();
            let h = v3(st * cp, st * sp, ct);
            let d = fixed.dot(h);
            if !(d > 0.0) {
                return 0.0;
            }
            4.0 * d * weighted(h * (2.0 * d) - fixed)
        };
        let b = breaks_in(
            phi_f - phi_max,
            phi_f + phi_max,
            [phi_f - 0.5 * phi_max, phi_f, phi_f + 0.5 * phi_max]
                .into_iter()
                .chain(phi_pts.iter().copied()),
        );
        st * inner(&mut g, &b)
    };
    (breaks, Box::new(f))
}

/// The outer integral of a tangent-cone lobe (about the x axis, the fibre's tangent):
/// the angle θ from the tangent outside, the azimuth φ around it inside; as
/// [`about_axis`].
fn tangent_cone<'a>(
    width: f64,
    fixed: Vec3,
    mut weighted: impl FnMut(Vec3) -> f64 + 'a,
    inner: impl Fn(&mut dyn FnMut(f64) -> f64, &[f64]) -> f64 + 'a,
) -> Outer<'a> {
    let peak = (-fixed.x).clamp(-1.0, 1.0).acos();
    let mut pts = vec![peak];
    for d in geometric(width, PI) {
        pts.extend([peak - d, peak + d]);
    }
    let breaks = breaks_in(0.0, PI, pts);
    let f = move |t: f64| -> f64 {
        let (st, ct) = t.sin_cos();
        let mut g = |p: f64| {
            let (sp, cp) = p.sin_cos();
            weighted(v3(ct, st * cp, st * sp))
        };
        st * inner(&mut g, &[0.0, FRAC_PI_2, PI])
    };
    (breaks, Box::new(f))
}
