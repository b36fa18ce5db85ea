//! f64 twin of `polygon_interpolator`: plane-equation (barycentric) evaluation of each
//! attribute at the pixel centre (x + ½, y + ½), and the coverage test with the
//! top-left fill rule, from vertex positions in pixels (y down) and attribute values.
//!
//! Fed the same quantised vertex data as the unit, the only differences left are the
//! unit's gradient/start rounding, its accumulation and its output rounding. With
//! positions on a 2^-s grid (s ≤ 8) and |coordinates| ≤ 2^13 px every edge function below
//! is computed exactly in f64 (≤ 46 significant bits), so coverage is exact.
//!
//! Degenerate (zero-area) primitives cover nothing; their attribute value is defined
//! as the first vertex's (never NaN).

/// A point in pixels.
pub type P = [f64; 2];

/// Edge function of a→b at p: positive on the interior side of a positively wound
/// polygon (doubled signed area of a, b, p; y down).
pub fn edge(a: P, b: P, p: P) -> f64 {
    (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
}

/// Doubled signed area of v0 v1 v2 (> 0: positive winding).
pub fn area2(v: [P; 3]) -> f64 {
    edge(v[0], v[1], v[2])
}

/// Top-left rule for an edge a→b of a positively wound polygon: a top edge is horizontal
/// with the interior below it, a left edge has the interior to its right.
pub fn is_top_left(a: P, b: P) -> bool {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    (dy == 0.0 && dx > 0.0) || dy < 0.0
}

/// The centre of pixel (x, y).
pub fn centre(x: i64, y: i64) -> P {
    [x as f64 + 0.5, y as f64 + 0.5]
}

/// Does the convex polygon `poly` (any winding, ≥ 3 vertices) cover point p under the
/// top-left rule? A zero-area polygon covers nothing.
pub fn polygon_covers(poly: &[P], p: P) -> bool {
    if poly.len() < 3 {
        return false;
    }
    let a = area2([poly[0], poly[1], poly[2]]);
    if a == 0.0 {
        return false;
    }
    let n = poly.len();
    (0..n).all(|i| {
        let (mut s, mut t) = (poly[i], poly[(i + 1) % n]);
        if a < 0.0 {
            // Walk the polygon backwards so that the interior is on the positive side.
            std::mem::swap(&mut s, &mut t);
        }
        let e = edge(s, t, p);
        e > 0.0 || (e == 0.0 && is_top_left(s, t))
    })
}

/// Does triangle v cover the centre of pixel (x, y)?
pub fn triangle_covers(v: [P; 3], x: i64, y: i64) -> bool {
    polygon_covers(&v, centre(x, y))
}

/// The implied 4th vertex of the parallelogram v0 v1 v2 v3: v0 + v2 − v1.
pub fn parallelogram_v3(v: [P; 3]) -> P {
    [v[0][0] + v[2][0] - v[1][0], v[0][1] + v[2][1] - v[1][1]]
}

/// Does the parallelogram v0 v1 v2 (v0 + v2 − v1) cover the centre of pixel (x, y)?
pub fn parallelogram_covers(v: [P; 3], x: i64, y: i64) -> bool {
    polygon_covers(&[v[0], v[1], v[2], parallelogram_v3(v)], centre(x, y))
}

/// Which triangle of a GL quad's split — 0: (v0 v1 v2), 1: (v0 v2 v3) — covers the
/// centre of pixel (x, y), if any (the first if, impossibly for a convex quad, both).
pub fn quad_covers(v: [P; 4], x: i64, y: i64) -> Option<usize> {
    if triangle_covers([v[0], v[1], v[2]], x, y) {
        Some(0)
    } else if triangle_covers([v[0], v[2], v[3]], x, y) {
        Some(1)
    } else {
        None
    }
}

/// The attribute plane through (v_i, a_i) evaluated at p by barycentric weights
/// w_i = E_i(p) / area. Zero area → `a[0]`.
pub fn plane_at(v: [P; 3], a: [f64; 3], p: P) -> f64 {
    let ar = area2(v);
    if ar == 0.0 {
        return a[0];
    }
    let w0 = edge(v[1], v[2], p) / ar;
    let w1 = edge(v[2], v[0], p) / ar;
    let w2 = edge(v[0], v[1], p) / ar;
    w0 * a[0] + w1 * a[1] + w2 * a[2]
}

/// The attribute of triangle v at the centre of pixel (x, y).
pub fn triangle_value(v: [P; 3], a: [f64; 3], x: i64, y: i64) -> f64 {
    plane_at(v, a, centre(x, y))
}

/// The attribute of a GL quad at pixel (x, y): the plane of the triangle of the split
/// that covers it (triangle 0's plane where neither does).
pub fn quad_value(v: [P; 4], a: [f64; 4], x: i64, y: i64) -> f64 {
    match quad_covers(v, x, y) {
        Some(1) => triangle_value([v[0], v[2], v[3]], [a[0], a[2], a[3]], x, y),
        _ => triangle_value([v[0], v[1], v[2]], [a[0], a[1], a[2]], x, y),
    }
}

/// The attribute of an affine parallelogram v0 v1 v2 (plane through those three).
pub fn parallelogram_value(v: [P; 3], a: [f64; 3], x: i64, y: i64) -> f64 {
    triangle_value(v, a, x, y)
}

/// The NV2A's barycentric attribute of triangle v at p (the unit's `barycentric`
/// mode): the weights of v0 and v2, λ0 = E(v1, v2, p)/area and λ2 = E(v0, v1, p)/area,
/// quantised down to multiples of 2^−w — `strict`: an exact multiple takes the step
/// below — then A = a1 + q0·(a0 − a1) + q2·(a2 − a1). The quantisation is done exactly:
/// positions on the 2^−`subpixel_bits` grid (pixel centres on the half grid) make every
/// edge function an integer, so q = ⌊(2^w·E − t)/area⌋ in integers; the rest is f64.
/// Zero area → `a[1]`.
pub fn barycentric_value(
    v: [P; 3],
    a: [f64; 3],
    p: P,
    subpixel_bits: u32,
    weight_bits: u32,
    strict: bool,
) -> f64 {
    // To integers on the half-sub-pixel grid (exact: the grid is 2^−(s+1)).
    let g = (1u64 << (subpixel_bits + 1)) as f64;
    let i = |q: P| [(q[0] * g) as i128, (q[1] * g) as i128];
    let e = |a: [i128; 2], b: [i128; 2], c: [i128; 2]| {
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    };
    let (v0, v1, v2, pi) = (i(v[0]), i(v[1]), i(v[2]), i(p));
    let ar = e(v0, v1, v2);
    if ar == 0 {
        return a[1];
    }
    let t = i128::from(strict);
    let q = |num: i128| {
        // The weight's sign follows the winding: divide by |area| with E signed alike.
        let (num, den) = if ar > 0 { (num, ar) } else { (-num, -ar) };
        (((num << weight_bits) - t).div_euclid(den)).clamp(0, 1i128 << weight_bits) as f64
    };
    let scale = (1u64 << weight_bits) as f64;
    let (q0, q2) = (q(e(v1, v2, pi)), q(e(v0, v1, pi)));
    a[1] + (q0 * (a[0] - a[1]) + q2 * (a[2] - a[1])) / scale
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_reproduces_vertices_and_is_affine() {
        let v = [[0.0, 0.0], [4.0, 0.0], [0.0, 2.0]];
        let a = [1.0, 5.0, -3.0];
        for (i, p) in v.iter().enumerate() {
            assert!((plane_at(v, a, *p) - a[i]).abs() < 1e-12);
        }
        assert!((plane_at(v, a, [2.0, 1.0]) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn shared_edge_is_covered_once() {
        // Unit square as two triangles: pixel centres exactly on the diagonal.
        let q = [[0.5, 0.5], [4.5, 0.5], [4.5, 4.5], [0.5, 4.5]];
        for y in -1..6 {
            for x in -1..6 {
                let a = triangle_covers([q[0], q[1], q[2]], x, y);
                let b = triangle_covers([q[0], q[2], q[3]], x, y);
                assert!(!(a && b), "{x},{y}");
            }
        }
    }

    #[test]
    fn barycentric_value_is_the_plane_on_exact_weights() {
        // Weights that are multiples of 2^−8 at the centre: the plane's value.
        let v = [[0.0, 0.0], [4.0, 0.0], [4.0, 4.0]];
        let a = [0.0, 64.0, 192.0];
        let p = [3.5, 0.5];
        let plane = plane_at(v, a, p);
        assert_eq!(barycentric_value(v, a, p, 4, 8, false), plane);
        // Strict: both exact weights take the step below (1/256 each).
        let s = barycentric_value(v, a, p, 4, 8, true);
        assert_eq!(s, 64.0 + (31.0 * -64.0 + 31.0 * 128.0) / 256.0);
        assert!(s != plane);
    }

    #[test]
    fn degenerate_covers_nothing_and_is_finite() {
        let v = [[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]];
        assert!(!triangle_covers(v, 0, 0));
        assert_eq!(triangle_value(v, [1.0, 2.0, 3.0], 0, 0), 1.0);
    }
}
