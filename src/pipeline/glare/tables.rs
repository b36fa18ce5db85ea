//! What the host writes into the modulators' RAMs for one primitive: the shape RAM's
//! distance samples over the primitive's normalised frame and the falloff (or ring)
//! RAM's profile samples, with the quad's size from the profile's cut-off.

use crate::reference::glare_model::{bloom_at, halo, Bloom, Shape2D, SourceGlare};
use crate::reference::luminance_ram::falloff;
use crate::scene::glare::{Determinants, GlareModel};
use rtl_model::units::luminance_ram::LumWidths;

/// Below this many codes a profile is cut off (half an 8-bit LSB).
pub const CUTOFF_CODES: f64 = 0.5;

/// An area primitive (bloom or halo) around a source: the screen-aligned square of
/// half-side `half_px` around `center`, whose frame is turned by `phi`; distances are
/// normalised by `d_max_px` (the falloff RAM spans d ∈ [0, d_max_px]).
#[derive(Clone, Debug, PartialEq)]
pub struct AreaPrim {
    pub center: [f64; 2],
    pub half_px: f64,
    pub phi: f64,
    pub d_max_px: f64,
}

/// (2^k + 1)² samples of min(1, distance/d_max) of `shape` over the area's frame,
/// row-major by v: sample (i, j) sits at u = −1 + i·2^(1−k), v = −1 + j·2^(1−k).
pub fn shape_samples(shape: &Shape2D, a: &AreaPrim, k: u32) -> Vec<f64> {
    let n = (1usize << k) + 1;
    let step = 2.0 / (n - 1) as f64;
    let (c, s) = (a.phi.cos(), a.phi.sin());
    let sample = |i: usize, j: usize| {
        let (u, v) = (-1.0 + i as f64 * step, -1.0 + j as f64 * step);
        let (dx, dy) = (a.half_px * (u * c - v * s), a.half_px * (u * s + v * c));
        (shape.distance(dx, dy) / a.d_max_px).clamp(0.0, 1.0)
    };
    // The grid is dyadic, so sample n²−1−idx sits at exactly (−u, −v) and its
    // (dx, dy) is exactly (−dx, −dy) (IEEE products and differences are odd). A
    // point-symmetric outline (its distance reads |u|, |v| or u², v² of the rotated
    // offset) gives it the same value: the second half is the first's mirror, and the
    // ellipse's 20 Newton steps per sample run half as often. A polygon is computed
    // in full.
    let symmetric = matches!(
        shape,
        Shape2D::Point | Shape2D::Circle { .. } | Shape2D::Ellipse { .. } | Shape2D::Capsule { .. }
    );
    let len = n * n;
    let first = if symmetric { len.div_ceil(2) } else { len };
    let mut out: Vec<f64> = Vec::with_capacity(len);
    // Row by row (idx = j·n + i) without a division per sample.
    'rows: for j in 0..n {
        for i in 0..n {
            if out.len() == first {
                break 'rows;
            }
            out.push(sample(i, j));
        }
    }
    for idx in first..len {
        out.push(out[len - 1 - idx]);
    }
    out
}

/// Radial correction: the κ the host loads for an area primitive, half_px / d_max
/// (the frame's unit in d units), rounded to the register's u(ki).(kf) and saturated
/// at its largest code (any κ reconstructs the samples exactly; a saturated one just
/// corrects less).
pub fn radial_kappa(a: &AreaPrim, w: &LumWidths) -> f64 {
    let sc = (w.radial.kappa_frac_bits as f64).exp2();
    let k = a.half_px / a.d_max_px;
    let code = if k.is_finite() {
        (k * sc).round().clamp(0.0, w.kappa_max() as f64)
    } else {
        w.kappa_max() as f64
    };
    w.kappa_value(code as u32)
}

/// Radial correction, the host's choice per primitive: the signed samples and κ among
/// the candidates κ_full·{0, ½, ¾, 1} (κ_full = [`radial_kappa`]) whose bilinear
/// reconstruction gives the smallest largest profile error |P(d̃) − P(d)| at the probe
/// points (every cell centre and edge midpoint; d = clamp(sdf/d_max, 0, 1) exact, d̃
/// the reconstruction, P each of `profiles` — the falloff or ring RAM samples —
/// interpolated linearly; ties go to the larger κ). κ = 0 is a plain signed-distance
/// table (no kink at the outline); κ_full takes the cone of a source smaller than a
/// cell out of the interpolation but puts a kink at the centre.
pub fn radial_tables(
    shape: &Shape2D,
    a: &AreaPrim,
    w: &LumWidths,
    profiles: &[&[f64]],
) -> (Vec<f64>, f64) {
    let k = w.shape_log2;
    let n = 1usize << k;
    let side = n + 1;
    let half = 1.0 / n as f64; // half a cell in frame units
    let (c, s) = (a.phi.cos(), a.phi.sin());
    let sdf = |u: f64, v: f64| {
        let (dx, dy) = (a.half_px * (u * c - v * s), a.half_px * (u * s + v * c));
        shape.signed_distance(dx, dy) / a.d_max_px
    };
    let at = |i: usize| -1.0 + 2.0 * i as f64 / n as f64;
    // Exact values at the samples and the probes (computed once for all candidates).
    let mut grid = Vec::with_capacity(side * side);
    for j in 0..side {
        for i in 0..side {
            grid.push(sdf(at(i), at(j)));
        }
    }
    // Probes: (u, v, exact, the samples they interpolate).
    let mut probes: Vec<(f64, f64, f64, [usize; 4])> = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (u, v) = (at(i), at(j));
            let id = |di: usize, dj: usize| (j + dj) * side + i + di;
            for (pu, pv, q) in [
                (u + half, v + half, [id(0, 0), id(1, 0), id(0, 1), id(1, 1)]),
                (u + half, v, [id(0, 0), id(1, 0), id(0, 0), id(1, 0)]),
                (u, v + half, [id(0, 0), id(0, 1), id(0, 0), id(0, 1)]),
            ] {
                let ex = sdf(pu, pv);
                if ex.is_finite() && ex < 1.0 {
                    probes.push((pu, pv, ex.max(0.0), q));
                }
            }
        }
    }
    let (lo, hi) = w.entry_range();
    let full = radial_kappa(a, w);
    let kf = (w.radial.kappa_frac_bits as f64).exp2();
    let mut best: Option<(f64, Vec<f64>, f64)> = None;
    for f in [1.0, 0.75, 0.5, 0.0] {
        let kappa = (full * f * kf).round() / kf;
        let e: Vec<f64> = (0..side * side)
            .map(|idx| {
                let r = at(idx % side).hypot(at(idx / side));
                let x = grid[idx] - kappa * r;
                if x.is_finite() {
                    x.clamp(lo, hi)
                } else {
                    0.0
                }
            })
            .collect();
        let err = probes
            .iter()
            .map(|&(u, v, ex, q)| {
                let ei = 0.25 * (e[q[0]] + e[q[1]] + e[q[2]] + e[q[3]]);
                let d = (ei + kappa * u.hypot(v)).clamp(0.0, 1.0);
                profiles
                    .iter()
                    .map(|p| {
                        // 2^m + 1 samples: the falloff RAM's exact twin.
                        let m = (p.len() - 1).trailing_zeros();
                        (falloff(p, m, d) - falloff(p, m, ex)).abs()
                    })
                    .fold(0.0, f64::max)
            })
            .fold(0.0, f64::max);
        if best.as_ref().is_none_or(|b| err < b.0) {
            best = Some((err, e, kappa));
        }
    }
    let (_, e, kappa) = best.expect("four candidates");
    (e, kappa)
}

/// 2^m + 1 samples of `f(θ)/gain` (clipped to [0, 1]) at θ = j/2^m · `theta_max`.
pub fn profile_samples(f: impl Fn(f64) -> f64, theta_max: f64, gain: f64, m: u32) -> Vec<f64> {
    let n = 1usize << m;
    (0..=n)
        .map(|j| {
            let v = f(j as f64 / n as f64 * theta_max) / gain;
            if v.is_finite() {
                v.clamp(0.0, 1.0)
            } else {
                1.0
            }
        })
        .collect()
}

/// The smallest θ ≥ 0 (degrees, up to `limit`) where the decreasing `f` falls below
/// `level`: doubling then bisection.
pub fn cutoff(f: impl Fn(f64) -> f64, level: f64, limit: f64) -> f64 {
    if f(0.0) < level {
        return 0.0;
    }
    let mut hi = 0.01f64.min(limit);
    while f(hi) >= level && hi < limit {
        hi = (hi * 2.0).min(limit);
    }
    if f(hi) >= level {
        return limit;
    }
    let mut lo = 0.0;
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if f(mid) >= level {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// The frame angle of a source's tables: its outline's own axis.
pub fn frame_angle(shape: &Shape2D) -> f64 {
    match shape {
        Shape2D::Ellipse { phi, .. } | Shape2D::Capsule { phi, .. } => *phi,
        _ => 0.0,
    }
}

/// The bloom primitive of a source: the quad, and the profile over θ from the rim
/// (from the centre for a point) with its cut-off `theta_max` (degrees).
pub fn bloom_prim(s: &SourceGlare, b: &Bloom, p: &GlareModel, limit_px: f64) -> (AreaPrim, f64) {
    let cmax = s.color.iter().cloned().fold(0.0, f64::max).max(1e-12);
    let limit = limit_px / s.px_per_deg;
    let theta_max =
        cutoff(|t| bloom_at(b, t, p) * cmax, CUTOFF_CODES, limit).max(1.0 / s.px_per_deg);
    let d_max_px = theta_max * s.px_per_deg;
    (
        AreaPrim {
            center: s.center,
            half_px: s.shape.extent() + d_max_px + 1.0,
            phi: frame_angle(&s.shape),
            d_max_px,
        },
        theta_max,
    )
}

/// The halo primitive: out to the largest ring radius plus 4α (exp(−16) beyond).
pub fn halo_prim(s: &SourceGlare, det: &Determinants, p: &GlareModel) -> (AreaPrim, f64) {
    let lmax = det.wavelengths_nm.iter().cloned().fold(0.0, f64::max);
    let theta_max =
        (p.halo_ring_radius_deg() * lmax / 568.0 + 4.0 * p.halo_alpha_deg).max(1.0 / s.px_per_deg);
    let d_max_px = theta_max * s.px_per_deg;
    (
        AreaPrim {
            center: s.center,
            half_px: s.shape.extent() + d_max_px + 1.0,
            phi: frame_angle(&s.shape),
            d_max_px,
        },
        theta_max,
    )
}

/// Ring samples of channel c (peak 1 at the ring).
pub fn ring_samples(c_lambda: f64, theta_max: f64, p: &GlareModel, m: u32) -> Vec<f64> {
    profile_samples(|t| halo(t, 1.0, c_lambda, p), theta_max, 1.0, m)
}

/// The flare lines' shared shape: in a line's frame (u along from −1 at the source to
/// +1 at the tip, v across), d = min(1, √(((u + 1)/2)² + v²)).
pub fn line_shape_samples(k: u32) -> Vec<f64> {
    let n = (1usize << k) + 1;
    let step = 2.0 / (n - 1) as f64;
    let mut out = Vec::with_capacity(n * n);
    for j in 0..n {
        let v = -1.0 + j as f64 * step;
        for i in 0..n {
            let s = (-1.0 + i as f64 * step + 1.0) / 2.0;
            out.push((s * s + v * v).sqrt().min(1.0));
        }
    }
    out
}

/// The lines' shared falloff: (1 − d)².
pub fn line_falloff_samples(m: u32) -> Vec<f64> {
    profile_samples(|d| (1.0 - d).max(0.0).powi(2), 1.0, 1.0, m)
}
