//! Triangles for every shape: the Utah teapot from Newell's Bézier patches (embedded,
//! `data/teapot.bpt`), UV spheres, rectangles and boxes. The hardware pipeline draws
//! these with the polygon interpolator and the shadow-map pass rasterises them.
//!
//! Every triangle is wound counter-clockwise seen from the side its normals point to
//! (outside for closed shapes, the `normal` side for a plane), and every normal is unit
//! length and finite.

use rtl_model::error::{check_range, ConfigError};

use super::format::Shape;
use super::math::{v3, Vec3};
use super::validate::validate_shape;

/// Newell's teapot: 32 bicubic Bézier patches, Z up (turned Y up on parsing).
const TEAPOT_BPT: &str = include_str!("data/teapot.bpt");

/// UV-sphere resolution used by [`shape_triangles`]: segments around the axis and
/// rings from pole to pole (960 triangles).
pub const SPHERE_SEGMENTS: u32 = 32;
pub const SPHERE_RINGS: u32 = 16;

/// A triangle with per-vertex unit normals.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    pub p: [Vec3; 3],
    pub n: [Vec3; 3],
}

/// A bicubic Bézier patch: `patch[row][col]`, row = u, col = v.
pub type Patch = [[Vec3; 4]; 4];

/// The teapot's 32 patches, Y up: the data's (x, y, z) becomes (x, z, −y) (a proper
/// rotation, so orientation is kept). The teapot then stands on y = 0 with
/// x ∈ [−3, 3.434] (handle to spout tip), y ∈ [0, 3.15], z ∈ [−2, 2].
pub fn teapot_patches() -> Result<Vec<Patch>, ConfigError> {
    parse_bpt(TEAPOT_BPT)
}

/// Parse `.bpt` text: the patch count, then per patch a line "3 3" (degrees) and 16
/// lines "x y z". Errors name `teapot.bpt line N`.
pub fn parse_bpt(text: &str) -> Result<Vec<Patch>, ConfigError> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty());
    let err = |n: usize, why: &str| ConfigError::invalid(&format!("teapot.bpt line {n}"), why);
    let last_line = text.lines().count().max(1);
    let (n0, first) = lines
        .next()
        .ok_or_else(|| err(1, "empty file: expected the patch count"))?;
    let count: usize = first
        .parse()
        .map_err(|_| err(n0, &format!("expected the patch count, found `{first}`")))?;
    if count == 0 || count > 10_000 {
        return Err(err(
            n0,
            &format!("patch count {count} out of range 1 ..= 10000"),
        ));
    }
    let mut patches = Vec::with_capacity(count);
    for pi in 0..count {
        let (n, degrees) = lines.next().ok_or_else(|| {
            err(
                last_line,
                &format!("file ends before patch {pi} of {count}"),
            )
        })?;
        let d: Vec<&str> = degrees.split_whitespace().collect();
        if d != ["3", "3"] {
            return Err(err(
                n,
                &format!("expected the degrees `3 3` of patch {pi}, found `{degrees}`"),
            ));
        }
        let mut patch = [[Vec3::default(); 4]; 4];
        for k in 0..16 {
            let (n, l) = lines.next().ok_or_else(|| {
                err(
                    last_line,
                    &format!("file ends inside patch {pi} (control point {k} of 16)"),
                )
            })?;
            let xs: Vec<f64> = l
                .split_whitespace()
                .map(|w| w.parse::<f64>())
                .collect::<Result<_, _>>()
                .map_err(|_| err(n, &format!("expected three numbers `x y z`, found `{l}`")))?;
            if xs.len() != 3 || xs.iter().any(|x| !x.is_finite() || x.abs() > 1e6) {
                return Err(err(
                    n,
                    &format!("expected three finite numbers `x y z` (|x| ≤ 1e6), found `{l}`"),
                ));
            }
            patch[k / 4][k % 4] = v3(xs[0], xs[2], -xs[1]);
        }
        patches.push(patch);
    }
    if let Some((n, l)) = lines.next() {
        return Err(err(
            n,
            &format!("unexpected content after {count} patches: `{l}`"),
        ));
    }
    Ok(patches)
}

/// Cubic Bernstein weights and their derivatives at t.
fn bernstein(t: f64) -> ([f64; 4], [f64; 4]) {
    let s = 1.0 - t;
    (
        [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t],
        [
            -3.0 * s * s,
            3.0 * s * s - 6.0 * t * s,
            6.0 * t * s - 3.0 * t * t,
            3.0 * t * t,
        ],
    )
}

/// Point and partial derivatives ∂/∂u, ∂/∂v of a patch at (u, v).
fn eval(patch: &Patch, u: f64, v: f64) -> (Vec3, Vec3, Vec3) {
    let (bu, du) = bernstein(u);
    let (bv, dv) = bernstein(v);
    let mut p = Vec3::default();
    let mut pu = Vec3::default();
    let mut pv = Vec3::default();
    for r in 0..4 {
        for c in 0..4 {
            let q = patch[r][c];
            p = p + q * (bu[r] * bv[c]);
            pu = pu + q * (du[r] * bv[c]);
            pv = pv + q * (bu[r] * dv[c]);
        }
    }
    (p, pu, pv)
}

/// Below this length (data units²) the cross product of the partial derivatives is
/// taken as degenerate (a pole of the lid or the bottom, where a whole control row
/// collapses to one point and ∂/∂v vanishes).
const DEGENERATE: f64 = 1e-9;

/// Point and unit outward normal of a patch at (u, v). The outward normal of
/// Newell's data is ∂P/∂v × ∂P/∂u. Where that vanishes (the poles) the normal is taken
/// at a parameter nudged towards the patch centre by 10⁻⁴, 10⁻³, 10⁻² in turn — the
/// limit normal at a pole, to within an angle of the order of the nudge. If every
/// nudge fails (not the case for the teapot data) the normal points from the patch's
/// centre of control points to P, or is +y; it is never NaN.
pub fn patch_point_normal(patch: &Patch, u: f64, v: f64) -> (Vec3, Vec3) {
    let (p, pu, pv) = eval(patch, u, v);
    let n = pv.cross(pu);
    if n.length() > DEGENERATE {
        return (p, n.normalized());
    }
    for d in [1e-4, 1e-3, 1e-2] {
        let (_, pu, pv) = eval(patch, u + (0.5 - u) * d, v + (0.5 - v) * d);
        let n = pv.cross(pu);
        if n.length() > DEGENERATE {
            return (p, n.normalized());
        }
    }
    let centre = patch
        .iter()
        .flatten()
        .fold(Vec3::default(), |a, &q| a + q * (1.0 / 16.0));
    let n = (p - centre).normalized();
    (
        p,
        if n.length() > 0.5 {
            n
        } else {
            v3(0.0, 1.0, 0.0)
        },
    )
}

/// Rotation about +y by `deg` (right-handed: +x turns towards −z).
fn rotate_y(p: Vec3, deg: f64) -> Vec3 {
    let (s, c) = deg.to_radians().sin_cos();
    v3(c * p.x + s * p.z, p.y, -s * p.x + c * p.z)
}

fn vec(a: &[f64; 3]) -> Vec3 {
    v3(a[0], a[1], a[2])
}

/// Is the triangle too small to draw (area below 10⁻¹² of its longest edge squared,
/// i.e. a sliver or a collapsed triangle at a pole)?
fn degenerate(p: &[Vec3; 3]) -> bool {
    let e = [p[1] - p[0], p[2] - p[1], p[0] - p[2]];
    let longest = e.iter().map(|x| x.dot(*x)).fold(0.0, f64::max);
    let twice_area = e[0].cross(p[2] - p[0]).length();
    // NaN (never produced from validated input) counts as degenerate too.
    twice_area.is_nan() || twice_area <= 1e-12 * longest
}

/// The teapot scaled by `scale`, rotated about y by `rotate_y_deg`, moved to
/// `position` (its base centre). Each patch is cut into `subdivisions`² quads, two
/// triangles each; collapsed triangles at the lid and bottom poles are dropped, so the
/// count is 32·2·s² − 8·s (8 patches have one pole edge of s quads); at s = 1 the 4
/// triangles of the two spout-tip patches (four collinear corners) go too.
///
/// Errors name `shape.position[k]`, `shape.scale`, `shape.rotate_y_deg`,
/// `shape.subdivisions` (ranges of `validate_shape`).
pub fn tessellate_teapot(
    position: [f64; 3],
    scale: f64,
    rotate_y_deg: f64,
    subdivisions: u32,
) -> Result<Vec<Triangle>, ConfigError> {
    validate_shape(&Shape::Teapot {
        position,
        scale,
        rotate_y_deg,
        subdivisions,
    })?;
    let patches = teapot_patches()?;
    let s = subdivisions as usize;
    let pos = vec(&position);
    let mut out = Vec::with_capacity(patches.len() * 2 * s * s);
    let mut grid = vec![(Vec3::default(), Vec3::default()); (s + 1) * (s + 1)];
    for patch in &patches {
        for i in 0..=s {
            for j in 0..=s {
                let (p, n) = patch_point_normal(patch, i as f64 / s as f64, j as f64 / s as f64);
                grid[i * (s + 1) + j] = (
                    rotate_y(p * scale, rotate_y_deg) + pos,
                    rotate_y(n, rotate_y_deg).normalized(),
                );
            }
        }
        let at = |i: usize, j: usize| grid[i * (s + 1) + j];
        for i in 0..s {
            for j in 0..s {
                // Corners a = (u, v), b = (u, v + dv), c = (u + du, v + dv),
                // d = (u + du, v); (b − a) × (c − a) ∝ ∂v × ∂u, the outward normal.
                let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
                for [x, y, z] in [[a, b, c], [a, c, d]] {
                    let t = Triangle {
                        p: [x.0, y.0, z.0],
                        n: [x.1, y.1, z.1],
                    };
                    if !degenerate(&t.p) {
                        out.push(t);
                    }
                }
            }
        }
    }
    Ok(out)
}

/// A UV sphere: `segments` around the y axis (≥ 3), `rings` from pole to pole (≥ 2),
/// 2·segments·(rings − 1) triangles; normals are the exact radial directions.
/// Errors name `shape.center[k]`, `shape.radius`, `segments`, `rings`.
pub fn sphere_triangles(
    center: [f64; 3],
    radius: f64,
    segments: u32,
    rings: u32,
) -> Result<Vec<Triangle>, ConfigError> {
    validate_shape(&Shape::Sphere { center, radius })?;
    check_range("segments", segments.into(), 3, 4096)?;
    check_range("rings", rings.into(), 2, 4096)?;
    let c = vec(&center);
    let dir = |ring: u32, seg: u32| {
        let theta = std::f64::consts::PI * ring as f64 / rings as f64; // from +y
        let phi = std::f64::consts::TAU * (seg % segments) as f64 / segments as f64;
        let (st, ct) = theta.sin_cos();
        let (sp, cp) = phi.sin_cos();
        // Right-handed: increasing phi turns +z towards +x (seen from +y, ccw).
        v3(st * sp, ct, st * cp)
    };
    let vert = |ring: u32, seg: u32| {
        let n = dir(ring, seg);
        (c + n * radius, n)
    };
    let mut out = Vec::with_capacity(2 * (segments * (rings - 1)) as usize);
    let mut push = |a: (Vec3, Vec3), b: (Vec3, Vec3), d: (Vec3, Vec3)| {
        out.push(Triangle {
            p: [a.0, b.0, d.0],
            n: [a.1, b.1, d.1],
        })
    };
    for ring in 0..rings {
        for seg in 0..segments {
            // Quad between rings `ring` (upper) and `ring + 1` (lower), segments seg,
            // seg + 1. Seen from outside, going down then around is counter-clockwise.
            let a = vert(ring, seg);
            let b = vert(ring + 1, seg);
            let c2 = vert(ring + 1, seg + 1);
            let d = vert(ring, seg + 1);
            if ring == 0 {
                // North cap: a and d are the pole.
                let pole = (c + v3(0.0, radius, 0.0), v3(0.0, 1.0, 0.0));
                push(pole, b, c2);
            } else if ring == rings - 1 {
                // South cap: b and c are the pole.
                let pole = (c + v3(0.0, -radius, 0.0), v3(0.0, -1.0, 0.0));
                push(a, pole, d);
            } else {
                push(a, b, c2);
                push(a, c2, d);
            }
        }
    }
    Ok(out)
}

/// Triangles of any shape: a sphere as a [`SPHERE_SEGMENTS`] × [`SPHERE_RINGS`] UV
/// sphere (960 triangles), a plane as 2 triangles (normal side counter-clockwise), a
/// box as 12 triangles with face normals, a teapot by [`tessellate_teapot`].
/// Errors name `shape.<field>` as [`validate_shape`] does.
pub fn shape_triangles(shape: &Shape) -> Result<Vec<Triangle>, ConfigError> {
    validate_shape(shape)?;
    match shape {
        Shape::Sphere { center, radius } => {
            sphere_triangles(*center, *radius, SPHERE_SEGMENTS, SPHERE_RINGS)
        }
        Shape::Plane {
            center,
            normal,
            tangent,
            half_size,
        } => {
            let n = vec(normal).normalized();
            let t0 = vec(tangent);
            // The first in-plane axis: the tangent made perpendicular to the normal.
            let t = (t0 - n * t0.dot(n)).normalized();
            let b = n.cross(t);
            let c = vec(center);
            let (hx, hy) = (half_size[0], half_size[1]);
            // t, b, n right-handed: (−t−b) → (t−b) → (t+b) → (−t+b) is ccw seen from n.
            let q = [
                c - t * hx - b * hy,
                c + t * hx - b * hy,
                c + t * hx + b * hy,
                c - t * hx + b * hy,
            ];
            Ok(vec![
                Triangle {
                    p: [q[0], q[1], q[2]],
                    n: [n; 3],
                },
                Triangle {
                    p: [q[0], q[2], q[3]],
                    n: [n; 3],
                },
            ])
        }
        Shape::Box { min, max } => {
            let (lo, hi) = (vec(min), vec(max));
            let corner = |x: bool, y: bool, z: bool| {
                v3(
                    if x { hi.x } else { lo.x },
                    if y { hi.y } else { lo.y },
                    if z { hi.z } else { lo.z },
                )
            };
            let mut out = Vec::with_capacity(12);
            // For each axis k and side, the face's four corners counter-clockwise seen
            // from outside: (u, v, n) right-handed axes with n the outward normal.
            for k in 0..3 {
                for high in [false, true] {
                    let mut n = [0.0; 3];
                    n[k] = if high { 1.0 } else { -1.0 };
                    let n = vec(&n);
                    // The two other axes, in cyclic order so that u × v = +axis k.
                    let (ku, kv) = ((k + 1) % 3, (k + 2) % 3);
                    let c = |a: bool, b: bool| {
                        let mut s = [false; 3];
                        s[k] = high;
                        s[ku] = a;
                        s[kv] = b;
                        corner(s[0], s[1], s[2])
                    };
                    let mut q = [
                        c(false, false),
                        c(true, false),
                        c(true, true),
                        c(false, true),
                    ];
                    if !high {
                        q.reverse();
                    }
                    out.push(Triangle {
                        p: [q[0], q[1], q[2]],
                        n: [n; 3],
                    });
                    out.push(Triangle {
                        p: [q[0], q[2], q[3]],
                        n: [n; 3],
                    });
                }
            }
            Ok(out)
        }
        Shape::Teapot {
            position,
            scale,
            rotate_y_deg,
            subdivisions,
        } => tessellate_teapot(*position, *scale, *rotate_y_deg, *subdivisions),
    }
}
