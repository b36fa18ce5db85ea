//! The glare formulas in f64 (Matsuda and Ikedo): bloom (1), (3), (4), halo (2), (5), flare lines
//! (6) with the R1 forms of docs/glare.md, the determinants' factors, the 2D source
//! shapes on screen and their distance functions, and the reference image.
//!
//! Angles are in degrees; θ is measured on the screen's tangent plane at the source
//! (screen distance in pixels ÷ pixels per degree), which is what the hardware's
//! distance tables hold. For extended sources θ is measured from the source's rim
//! (0 on and inside the outline), so that eqs. (3)/(4) are continuous at θ₀: inside
//! the outline the value is the profile's value at the rim.

use crate::scene::glare::{Determinants, GlareModel};

/// Vos' age factor of disability glare, 1 + (A_f/62.5)⁴ (bloom +).
pub fn age_factor(age: f64) -> f64 {
    1.0 + (age.max(0.0) / 62.5).powi(4)
}

/// The determinants' factor on bloom: age +, mist +, ambient −, glasses −, directivity
/// weak (0.75 + 0.25·c_D).
pub fn bloom_factor(d: &Determinants, m: &GlareModel, c_dir: f64) -> f64 {
    let glasses = if d.glasses { m.glasses_bloom } else { 1.0 };
    age_factor(d.age) * (1.0f64 + d.mist).powf(m.e_mist) / (1.0f64 + d.ambient).powf(m.e_ambient)
        * glasses
        * (0.75 + 0.25 * c_dir.clamp(0.0, 1.0))
}

/// `num / den^m` for num ≥ 0, den > 0, kept finite: den^m is taken no smaller than
/// the least normal f64, 2.2·10⁻³⁰⁸ (at m = 8 it falls below that for den < 10⁻³⁸·⁵
/// and underflows to 0 further down), and the quotient no larger than `f64::MAX`.
/// So 0 at num = 0 (never 0/0 = NaN) and a huge finite value, never +∞, at θ → 0
/// with θ₀ → 0.
fn inverse_power(num: f64, den: f64, m: f64) -> f64 {
    (num / den.powf(m).max(f64::MIN_POSITIVE)).min(f64::MAX)
}

/// A point source's bloom, eq. (1): A/(θ + θ₀)^m, θ from the centre. Finite for
/// every valid argument (θ₀ > 0, m ∈ [0.5, 8], A ≥ 0): see `inverse_power`; at
/// θ = 0 it is A/θ₀^m, e.g. 10⁷²·A for θ₀ = 10⁻⁹°, m = 8, and A/2.2·10⁻³⁰⁸ (at most
/// f64::MAX) for θ₀ so small that θ₀^m is not a normal f64 (θ₀ = 10⁻³⁰⁰, m = 8).
pub fn bloom_point(theta: f64, a: f64, theta0: f64, m: f64) -> f64 {
    inverse_power(a, theta.max(0.0) + theta0, m)
}

/// An extended source's bloom, eqs. (3)/(4), θ from the rim (≥ 0):
/// A·exp(−(θ/w)ⁿ) + B/(θ + θ₁)^m (the second term kept finite as in [`bloom_point`]).
pub fn bloom_extended(theta_rim: f64, a: f64, b: f64, p: &GlareModel) -> f64 {
    let t = theta_rim.max(0.0);
    (a * (-(t / p.bloom_w_deg).powf(p.bloom_n)).exp()
        + inverse_power(b, t + p.bloom_theta1_deg, p.bloom_m))
    .min(f64::MAX)
}

/// Halo ring, eq. (5)'s second term: C·exp(−(θ − θ₁·λ/568)²/α²), θ from the rim.
pub fn halo(theta_rim: f64, c: f64, lambda_nm: f64, p: &GlareModel) -> f64 {
    let r = p.halo_ring_radius_deg() * lambda_nm / 568.0;
    let x = (theta_rim.max(0.0) - r) / p.halo_alpha_deg;
    c * (-x * x).exp()
}

/// A flare line's profile over its own frame: s ∈ [0, 1] along (0 at the source),
/// t ∈ [−1, 1] across (in half-widths): (1 − √(s² + t²))², 0 beyond.
pub fn flare_profile(s: f64, t: f64) -> f64 {
    if s < 0.0 {
        return 0.0;
    }
    let d = (s * s + t * t).sqrt();
    if d >= 1.0 {
        0.0
    } else {
        (1.0 - d) * (1.0 - d)
    }
}

/// A source's outline on the screen, relative to its centre, pixels (y down).
#[derive(Clone, Debug, PartialEq)]
pub enum Shape2D {
    Point,
    Circle {
        r: f64,
    },
    /// Semi-axes a ≥ b along the angle `phi` (radians, from +x towards +y).
    Ellipse {
        a: f64,
        b: f64,
        phi: f64,
    },
    /// A segment of half-length `h` along `phi`, thickened by `r`.
    Capsule {
        h: f64,
        r: f64,
        phi: f64,
    },
    /// A convex polygon (vertices in order).
    Polygon {
        pts: Vec<[f64; 2]>,
    },
}

impl Shape2D {
    /// Distance from (x, y) to the outline, 0 on and inside it.
    pub fn distance(&self, x: f64, y: f64) -> f64 {
        match self {
            Shape2D::Point => (x * x + y * y).sqrt(),
            Shape2D::Circle { r } => ((x * x + y * y).sqrt() - r).max(0.0),
            Shape2D::Ellipse { a, b, phi } => {
                let (c, s) = (phi.cos(), phi.sin());
                ellipse_distance(x * c + y * s, -x * s + y * c, *a, *b)
            }
            Shape2D::Capsule { h, r, phi } => {
                let (c, s) = (phi.cos(), phi.sin());
                let (u, v) = (x * c + y * s, -x * s + y * c);
                let du = (u.abs() - h).max(0.0);
                ((du * du + v * v).sqrt() - r).max(0.0)
            }
            Shape2D::Polygon { pts } => polygon_distance(pts, x, y),
        }
    }

    /// Signed distance from (x, y) to the outline: [`Shape2D::distance`] outside,
    /// minus the distance to the outline inside (a point and degenerate outlines have
    /// no inside: the plain distance).
    pub fn signed_distance(&self, x: f64, y: f64) -> f64 {
        match self {
            Shape2D::Point => (x * x + y * y).sqrt(),
            Shape2D::Circle { r } => (x * x + y * y).sqrt() - r,
            Shape2D::Ellipse { a, b, phi } => {
                let (c, s) = (phi.cos(), phi.sin());
                let (u, v) = (x * c + y * s, -x * s + y * c);
                let d = ellipse_distance(u, v, *a, *b);
                if d > 0.0 || *a <= 0.0 || *b <= 0.0 {
                    d
                } else {
                    -ellipse_inner_distance(u, v, *a, *b)
                }
            }
            Shape2D::Capsule { h, r, phi } => {
                let (c, s) = (phi.cos(), phi.sin());
                let (u, v) = (x * c + y * s, -x * s + y * c);
                let du = (u.abs() - h).max(0.0);
                (du * du + v * v).sqrt() - r
            }
            Shape2D::Polygon { pts } => {
                let d = polygon_distance(pts, x, y);
                if d > 0.0 {
                    d
                } else {
                    -polygon_edge_distance(pts, x, y)
                }
            }
        }
    }

    /// The largest distance of the outline from the centre (0 for a point).
    pub fn extent(&self) -> f64 {
        match self {
            Shape2D::Point => 0.0,
            Shape2D::Circle { r } => *r,
            Shape2D::Ellipse { a, b, .. } => a.max(*b),
            Shape2D::Capsule { h, r, .. } => h + r,
            Shape2D::Polygon { pts } => pts
                .iter()
                .map(|p| (p[0] * p[0] + p[1] * p[1]).sqrt())
                .fold(0.0, f64::max),
        }
    }
}

/// Distance from (x, y) to the ellipse x²/a² + y²/b² = 1 (0 inside), by Newton
/// iterations on the foot point's parameter from a good start (converges in a few
/// steps; 20 are run, enough for f64 on any aspect ratio met here).
pub fn ellipse_distance(x: f64, y: f64, a: f64, b: f64) -> f64 {
    let (px, py) = (x.abs(), y.abs());
    if a <= 0.0 || b <= 0.0 {
        // Degenerate: a segment along x (b = 0) or y (a = 0), or a point.
        let (h, v) = if b <= 0.0 {
            ((px - a.max(0.0)).max(0.0), py)
        } else {
            (px, (py - b).max(0.0))
        };
        return (h * h + v * v).sqrt();
    }
    if (px / a).powi(2) + (py / b).powi(2) <= 1.0 {
        return 0.0;
    }
    // Foot point (a cos t, b sin t), t ∈ [0, π/2]; minimise the squared distance.
    let mut t = (py * a).atan2(px * b);
    for _ in 0..20 {
        let (c, s) = (t.cos(), t.sin());
        let (ex, ey) = (a * c, b * s);
        let (dx, dy) = (-a * s, b * c);
        let (rx, ry) = (ex - px, ey - py);
        let f = rx * dx + ry * dy;
        let df = dx * dx + dy * dy + rx * (-a * c) + ry * (-b * s);
        if df.abs() < 1e-300 {
            break;
        }
        t = (t - f / df).clamp(0.0, std::f64::consts::FRAC_PI_2);
    }
    let (ex, ey) = (a * t.cos(), b * t.sin());
    ((ex - px).powi(2) + (ey - py).powi(2)).sqrt()
}

/// Distance from a point (x, y) inside the ellipse x²/a² + y²/b² ≤ 1 to its outline:
/// the nearest of 256 foot-point parameters over the quarter arc, refined by
/// bisection-safe Newton steps on the squared distance.
pub fn ellipse_inner_distance(x: f64, y: f64, a: f64, b: f64) -> f64 {
    let (px, py) = (x.abs(), y.abs());
    let d2 = |t: f64| (a * t.cos() - px).powi(2) + (b * t.sin() - py).powi(2);
    let n = 256;
    let h = std::f64::consts::FRAC_PI_2 / n as f64;
    let mut best = 0.0;
    for i in 0..=n {
        let t = i as f64 * h;
        if d2(t) < d2(best) {
            best = t;
        }
    }
    // Golden-section refinement in the bracketing cells.
    let (mut lo, mut hi) = (
        (best - h).max(0.0),
        (best + h).min(std::f64::consts::FRAC_PI_2),
    );
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..60 {
        let m1 = hi - g * (hi - lo);
        let m2 = lo + g * (hi - lo);
        if d2(m1) < d2(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    d2(0.5 * (lo + hi)).min(d2(best)).sqrt()
}

/// Distance from (x, y) to the segment p–q (a point when p = q).
fn segment_distance(p: [f64; 2], q: [f64; 2], x: f64, y: f64) -> f64 {
    let (ex, ey) = (q[0] - p[0], q[1] - p[1]);
    let (wx, wy) = (x - p[0], y - p[1]);
    let len2 = ex * ex + ey * ey;
    let t = if len2 > 0.0 {
        ((wx * ex + wy * ey) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (dx, dy) = (wx - t * ex, wy - t * ey);
    (dx * dx + dy * dy).sqrt()
}

/// Distance from (x, y) to the nearest edge of a polygon (its boundary polyline).
pub fn polygon_edge_distance(pts: &[[f64; 2]], x: f64, y: f64) -> f64 {
    let n = pts.len();
    let mut best = f64::INFINITY;
    for i in 0..n {
        best = best.min(segment_distance(pts[i], pts[(i + 1) % n], x, y));
    }
    if best.is_finite() {
        best
    } else {
        (x * x + y * y).sqrt()
    }
}

/// Distance from (x, y) to a convex polygon (0 inside); fewer than 3 points, and a
/// degenerate polygon (all points coincident or collinear: |twice the area| ≤ 10⁻¹²
/// × the longest edge²), count as the polyline they make, so a zero-size polygon is
/// a point and a flat one a segment (without this, every point of the plane passed
/// the inside test of coincident vertices: all edge cross products are 0).
pub fn polygon_distance(pts: &[[f64; 2]], x: f64, y: f64) -> f64 {
    let n = pts.len();
    if n == 0 {
        return (x * x + y * y).sqrt();
    }
    if n == 1 {
        return ((x - pts[0][0]).powi(2) + (y - pts[0][1]).powi(2)).sqrt();
    }
    let mut area2 = 0.0;
    let mut edge2_max: f64 = 0.0;
    for i in 0..n {
        let p = pts[i];
        let q = pts[(i + 1) % n];
        area2 += p[0] * q[1] - q[0] * p[1];
        edge2_max = edge2_max.max((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2));
    }
    let solid = n >= 3 && area2.abs() > 1e-12 * edge2_max;
    let mut best = f64::INFINITY;
    let mut sign_pos = true;
    let mut sign_neg = true;
    for i in 0..n {
        let p = pts[i];
        let q = pts[(i + 1) % n];
        best = best.min(segment_distance(p, q, x, y));
        let cross = (q[0] - p[0]) * (y - p[1]) - (q[1] - p[1]) * (x - p[0]);
        sign_pos &= cross >= 0.0;
        sign_neg &= cross <= 0.0;
    }
    if solid && (sign_pos || sign_neg) {
        0.0
    } else {
        best
    }
}

/// What a source contributes, as the application processor works it out.
#[derive(Clone, Debug, PartialEq)]
pub struct SourceGlare {
    /// Screen centre, pixels (y down).
    pub center: [f64; 2],
    pub shape: Shape2D,
    /// Pixels per degree at the source.
    pub px_per_deg: f64,
    pub color: [f64; 3],
    pub bloom: Option<Bloom>,
    /// C of eq. (5) (codes); None = no halo.
    pub halo: Option<f64>,
    pub flare: Option<FlareParams>,
}

/// Bloom constants of one source.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bloom {
    /// Eq. (1): A/(θ + θ₀)^m, θ from the centre.
    Point { a: f64, theta0: f64, m: f64 },
    /// Eqs. (3)/(4): A inside, A·exp(−(θ/w)ⁿ) + B/(θ + θ₁)^m from the rim.
    Extended { a: f64, b: f64 },
}

/// The R1 outputs of eq. (6) for one source.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlareParams {
    /// Number of lines (split between the two symmetric distributions).
    pub num: u32,
    /// len (degrees): a line's length is |Gauss|·len.
    pub len_deg: f64,
    /// Line width (degrees).
    pub width_deg: f64,
    /// Peak luminance of a line (codes).
    pub intensity: f64,
    /// Spread of the angle (radians): angle = Gauss·spread + R(N) (+ π for the
    /// second distribution).
    pub spread_rad: f64,
    /// R(N), radians on the screen.
    pub base_rad: f64,
}

/// One flare line on the screen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlareLine {
    /// Direction from the source centre, radians (from +x towards +y, y down).
    pub angle: f64,
    pub length_px: f64,
    pub width_px: f64,
    pub intensity: f64,
}

impl FlareParams {
    /// Lines from two standard-normal draws each (length, angle); line k belongs to
    /// distribution k mod 2 (the second is turned by π).
    pub fn lines(&self, draws: &[(f64, f64)], px_per_deg: f64) -> Vec<FlareLine> {
        draws
            .iter()
            .take(self.num as usize)
            .enumerate()
            .map(|(k, &(g_len, g_ang))| FlareLine {
                angle: g_ang * self.spread_rad
                    + self.base_rad
                    + if k % 2 == 1 {
                        std::f64::consts::PI
                    } else {
                        0.0
                    },
                length_px: g_len.abs() * self.len_deg * px_per_deg,
                width_px: self.width_deg * px_per_deg,
                intensity: self.intensity,
            })
            .collect()
    }
}

/// The float reference's own draws for `num` lines: pairs of standard normals from
/// `rand_distr` (ChaCha8 seeded with `seed`), (length, angle) per line.
pub fn float_draws(num: u32, seed: u64) -> Vec<(f64, f64)> {
    use rand::SeedableRng;
    use rand_distr::{Distribution, StandardNormal};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    (0..num)
        .map(|_| {
            let a: f64 = StandardNormal.sample(&mut rng);
            let b: f64 = StandardNormal.sample(&mut rng);
            (a, b)
        })
        .collect()
}

/// The bloom luminance (codes) at `theta` degrees from the rim (extended) or centre;
/// 0 beyond `p.bloom_range`'s limit.
pub fn bloom_at(b: &Bloom, theta: f64, p: &GlareModel) -> f64 {
    if theta > p.bloom_range.limit_deg() {
        return 0.0;
    }
    match *b {
        Bloom::Point { a, theta0, m } => bloom_point(theta, a, theta0, m),
        Bloom::Extended { a, b } => bloom_extended(theta, a, b, p),
    }
}

/// A flare line's luminance (codes, before colour) at a pixel offset (dx, dy) from
/// the source centre.
pub fn flare_line_at(l: &FlareLine, dx: f64, dy: f64) -> f64 {
    if l.length_px <= 0.0 || l.width_px <= 0.0 {
        return 0.0;
    }
    let (c, s) = (l.angle.cos(), l.angle.sin());
    let along = dx * c + dy * s;
    let across = -dx * s + dy * c;
    l.intensity * flare_profile(along / l.length_px, across / (0.5 * l.width_px))
}

/// The reference image: `base` (codes, f64) plus every source's bloom, halo and
/// lines, clamped to `max` (the framebuffer's full scale). `lines[i]` are source i's.
#[allow(clippy::too_many_arguments)]
pub fn reference_image(
    width: u32,
    height: u32,
    base: &[[f64; 3]],
    sources: &[SourceGlare],
    lines: &[Vec<FlareLine>],
    det: &Determinants,
    p: &GlareModel,
    max: f64,
) -> Vec<[f64; 3]> {
    let mut img = base.to_vec();
    for (i, s) in sources.iter().enumerate() {
        for y in 0..height {
            for x in 0..width {
                let (dx, dy) = (x as f64 + 0.5 - s.center[0], y as f64 + 0.5 - s.center[1]);
                let theta = s.shape.distance(dx, dy) / s.px_per_deg;
                let px = &mut img[(y * width + x) as usize];
                if let Some(b) = &s.bloom {
                    let l = bloom_at(b, theta, p);
                    for (v, col) in px.iter_mut().zip(s.color) {
                        *v += l * col;
                    }
                }
                if let Some(cc) = s.halo {
                    for ((v, col), lambda) in px.iter_mut().zip(s.color).zip(det.wavelengths_nm) {
                        *v += halo(theta, cc, lambda, p) * col;
                    }
                }
                if let Some(ls) = lines.get(i) {
                    for l in ls {
                        let f = flare_line_at(l, dx, dy);
                        for (v, col) in px.iter_mut().zip(s.color) {
                            *v += f * col;
                        }
                    }
                }
            }
        }
    }
    for px in &mut img {
        for v in px.iter_mut() {
            *v = v.clamp(0.0, max);
        }
    }
    img
}
